//! One shot: the integrator a segment of the beam needs. The plain-bending beam (no shear,
//! no extension, no Poisson) is integrated by Taylor series ([`super::taylor`]), several times
//! faster at the same tolerance; any other by the Dormand-Prince pair of [`super::shoot`],
//! which also holds what both share (the state layout, the settings, the samples, the meter).

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
    if super::taylor::applies(model) {
        super::taylor::integrate::<N>(model, force, segment, settings, shape, meter)
    } else {
        super::dopri::integrate::<N>(model, force, segment, settings, shape, meter)
    }
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
/// ([`super::dopri::integrate_pair`]); a Taylor-series beam is shot on its own.
pub(crate) fn root_shot_pair<const N: usize>(
    shots: [(&BeamModel, TipForce, f64, ShotSettings, Option<Samples<'_>>); 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    let [(ma, fa, m0a, sa, sha), (mb, fb, m0b, sb, shb)] = shots;
    let [meter_a, meter_b] = meters;
    if super::taylor::applies(ma) || super::taylor::applies(mb) {
        return [
            root_shot::<N>(ma, fa, m0a, sa, sha, meter_a),
            root_shot::<N>(mb, fb, m0b, sb, shb, meter_b),
        ];
    }
    let spec = |model, force, moment, settings, shape| ShotSpec {
        model,
        force,
        segment: Segment::from_clamp(moment),
        settings,
        shape,
    };
    super::dopri::integrate_pair::<N>(
        [spec(ma, fa, m0a, sa, sha), spec(mb, fb, m0b, sb, shb)],
        [meter_a, meter_b],
    )
}
