//! One shot: the integrator a segment of the beam needs. The plain-bending beam (no shear,
//! no extension, no Poisson) is integrated by Taylor series ([`super::taylor`]), several times
//! faster at the same tolerance, and so is any beam's state alone. The sensitivities of a
//! beam with the other effects are the Dormand-Prince pair's ([`super::dopri`]; its state is
//! then the series', see [`series_state`]). [`super::shoot`] holds what both share (the
//! state layout, the settings, the samples, the meter).

use super::dopri::ShotSpec;
use super::model::BeamModel;
use super::shoot::{Meter, Samples, Segment, Shot, ShotFailure, ShotSettings, State, TipForce};

/// One segment's integration by the integrator its model needs.
fn integrate<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    if !super::taylor::applies::<N>(model) {
        let shot = super::dopri::integrate::<N>(model, force, segment, settings, shape, meter);
        return series_state(model, force, segment, settings, meter, shot);
    }
    super::taylor::integrate::<N>(model, force, segment, settings, shape, meter)
}

/// Integrates one segment. Position states start at zero (they are increments), the
/// sensitivities at the identity. Every attempted step is charged to `meter`.
pub(crate) fn shoot<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<Shot, ShotFailure> {
    let (u, steps) = integrate::<N>(model, force, segment, settings, shape, meter)?;
    let mut end = [0.0; 12];
    end[..N.min(12)].copy_from_slice(&u[..N.min(12)]);
    Ok(Shot { end, steps })
}

/// The whole beam shot from its clamp under the tip force `force` and the root moment
/// `moment`: an initial-value problem, no Newton iteration. `N = 16` also gives the
/// derivatives of the tip state with respect to `moment`, `alpha_x` and `alpha_y`; `N = 4`
/// the tip state alone.
pub(crate) fn root_shot<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    moment: f64,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    integrate::<N>(
        model,
        force,
        Segment::from_clamp(moment),
        settings,
        shape,
        meter,
    )
}

/// Two beams shot from their clamps, each as [`root_shot`] would shoot it alone (the same
/// steps and numbers), integrated side by side where both take the Dormand-Prince pair
/// ([`super::dopri::integrate_pair`]) or both the Taylor series
/// ([`super::taylor::integrate_pair`]); one of each are shot one after the other.
pub(crate) fn root_shot_pair<const N: usize>(
    shots: [(&BeamModel, TipForce, f64, ShotSettings, Option<Samples<'_>>); 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    let [(ma, fa, m0a, sa, sha), (mb, fb, m0b, sb, shb)] = shots;
    let [meter_a, meter_b] = meters;
    match (
        super::taylor::applies::<N>(ma),
        super::taylor::applies::<N>(mb),
    ) {
        (true, true) => {
            let (ga, gb) = (Segment::from_clamp(m0a), Segment::from_clamp(m0b));
            return super::taylor::integrate_pair::<N>(
                [(ma, fa, ga, sa, sha), (mb, fb, gb, sb, shb)],
                [meter_a, meter_b],
            );
        }
        (false, false) => {}
        _ => {
            return [
                root_shot::<N>(ma, fa, m0a, sa, sha, meter_a),
                root_shot::<N>(mb, fb, m0b, sb, shb, meter_b),
            ]
        }
    }
    let spec = |model, force, moment, settings, shape| ShotSpec {
        model,
        force,
        segment: Segment::from_clamp(moment),
        settings,
        shape,
    };
    let [a, b] = super::dopri::integrate_pair::<N>(
        [spec(ma, fa, m0a, sa, sha), spec(mb, fb, m0b, sb, shb)],
        [&mut *meter_a, &mut *meter_b],
    );
    [
        series_state(ma, fa, Segment::from_clamp(m0a), sa, meter_a, a),
        series_state(mb, fb, Segment::from_clamp(m0b), sb, meter_b, b),
    ]
}

/// A shot of a beam with the other effects and its sensitivities (`N > 4`, by the
/// Runge-Kutta pair), its state replaced by the series' ([`super::taylor`]): every shot of
/// such a beam, with or without sensitivities, then ends where the state's series puts it,
/// so that a Newton iterate checked by values alone is checked against the equations its
/// Jacobian's residual solved. (The two integrators agree to their tolerance; a mechanism's
/// path accepts a prediction only well within it.) The samples are the pair's.
fn series_state<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    meter: &mut Meter<'_>,
    shot: Result<(State<N>, u32), ShotFailure>,
) -> Result<(State<N>, u32), ShotFailure> {
    let (mut u, steps) = shot?;
    if N > 4 && !model.is_plain() {
        let (v, _) = integrate::<4>(model, force, segment, settings, None, meter)?;
        u[..4].copy_from_slice(&v);
    }
    Ok((u, steps))
}
