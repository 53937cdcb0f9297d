//! How well a PRB model follows the truth (DESIGN §4, §8): per-case errors and the error
//! figures of every kind of scene.
//!
//! # Method
//! Truth and model are followed along the same paths (a cantilever's load paths, a
//! mechanism's drives, or measured rows), so their cases pair one to one. For each pair:
//! - `pos_err`: the distance between the two stage points over the *loaded* position
//!   coordinates only, `hypot` of the `dx` and `dy` errors of those of `dx`, `dy` that are
//!   loaded (units of flexure 1's `L`); 0 when both are prescribed, since a prescribed
//!   coordinate is where the drive puts it in both. A cantilever is the one-flexure
//!   mechanism whose stage is its tip, every coordinate loaded: this is §4's tip error.
//! - `ang_err`: `dphi_model - dphi_truth` (radians) when `dphi` is loaded, else 0.
//! - `force_err`: for each *prescribed* coordinate `c`, `|R_model,c - R_truth,c| / S_c`, with
//!   `R` the drive's reaction (`stage_load[c]`) and `S_c` the largest `|R_truth,c|` over every
//!   case of every drive that prescribes `c`; the case's value is the root of the sum of
//!   their squares over its prescribed coordinates (0 when it has none), as `pos_err` is of
//!   the position errors, so that `J` is a plain sum of squares the fit can minimise. `S_c`
//!   is floored at `1e-3` times the largest `S` of any prescribed coordinate, so that a
//!   coordinate that carries (almost) no reaction, such as the guide of a fixed-guided
//!   segment with no axial force, is judged against the mechanism's main reaction instead
//!   of being divided by nearly zero; and at `1e-12`, so that a drive no part of which pushes
//!   back gives a finite figure.
//!
//! The figures ([`Figures`]) are those of DESIGN §4, `J = mean(e_pos^2 + w e_ang^2 +
//! w_f e_force^2)`, plus the reaction error's RMS and maximum when some coordinate is
//! prescribed, and the largest flexure tip error when the truth has flexures inside a
//! stage (a mechanism scene's beam mechanism): one type for every scene, whose absent
//! figures are absent, not zero.

use serde::{Deserialize, Serialize};

use crate::mech::MechCase;
use crate::scene::{Accuracy, Drive};

/// The floor of a coordinate's reaction scale, relative to the largest one (see the module
/// docs).
const RELATIVE_SCALE_FLOOR: f64 = 1e-3;
/// The absolute floor of a reaction scale, nondimensional.
const ABSOLUTE_SCALE_FLOOR: f64 = 1e-12;

/// The error figures of a model on a scene (DESIGN §4 and §8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    /// RMS of `e_pos`, units of (flexure 1's) `L`.
    pub rms_pos_err: f64,
    /// Largest `e_pos`, units of (flexure 1's) `L`.
    pub max_pos_err: f64,
    /// RMS of `e_ang`, radians.
    pub rms_ang_err: f64,
    /// Largest `|e_ang|`, radians.
    pub max_ang_err: f64,
    /// `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`.
    pub objective: f64,
    /// RMS of `e_force`, a fraction of each coordinate's largest reaction; absent when no
    /// coordinate is prescribed (a cantilever, a loaded stage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_force_err: Option<f64>,
    /// Largest `e_force`; absent when no coordinate is prescribed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_force_err: Option<f64>,
    /// Largest flexure tip position error over every flexure and case, units of that
    /// flexure's own `L`: how far a PRB flexure's tip is from the beam's even where the
    /// stage figures cannot see it (a fully prescribed stage). Reported, not in `J`; absent
    /// where the stage is all there is to see (a cantilever, whose stage is its tip) or the
    /// truth has no flexure tips (measured data).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_tip_err: Option<f64>,
    /// Largest relative error `|Omega_PRB,i / Omega_beam,i - 1|` of the first `[fit] modes`
    /// natural frequencies about the unloaded equilibrium (DESIGN §10; infinite when the
    /// model has fewer or is unstable there); absent when the scene asks for none. `J`
    /// then includes `w_omega mean_i (Omega_PRB,i / Omega_beam,i - 1)^2`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "infinite_as_text"
    )]
    pub max_freq_err: Option<f64>,
}

/// `max_freq_err` in files: a number, or the text `"inf"` for a model with fewer frequencies
/// than the scene judges (JSON has no infinity, and serde_json would write `null`); read back
/// from either.
pub(crate) mod infinite_as_text {
    use serde::de::Error;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(x) if *x == f64::INFINITY => s.serialize_some("inf"),
            Some(x) => s.serialize_some(x),
            None => s.serialize_none(),
        }
    }

    /// A plain number the same way (a ratio to a target that is infinite with it).
    pub fn number<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if *x == f64::INFINITY {
            s.serialize_str("inf")
        } else {
            s.serialize_f64(*x)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Value {
            Number(f64),
            Text(String),
        }
        match Option::<Value>::deserialize(d)? {
            None => Ok(None),
            Some(Value::Number(x)) => Ok(Some(x)),
            Some(Value::Text(t)) if t == "inf" => Ok(Some(f64::INFINITY)),
            Some(Value::Text(t)) => Err(D::Error::custom(format!(
                "max_freq_err: expected a number or \"inf\", got {t:?}"
            ))),
        }
    }
}

impl Figures {
    /// The figures over `cases`, with `w = angle_weight` and `w_f = force_weight` in `J`;
    /// `reactions`: some coordinate is prescribed; `tips`: the flexure tip error is judged.
    pub fn from_cases(
        cases: &[JudgedCase],
        angle_weight: f64,
        force_weight: f64,
        reactions: bool,
        tips: bool,
    ) -> Figures {
        Figures::from_errors(
            cases
                .iter()
                .map(|c| [c.pos_err, c.ang_err, c.force_err, c.tip_err]),
            (angle_weight, force_weight),
            reactions,
            tips,
        )
    }

    /// The figures over per-case errors `[pos_err, ang_err, force_err, tip_err]`, with the
    /// weights `(w, w_f)` of `J`.
    pub fn from_errors(
        cases: impl IntoIterator<Item = [f64; 4]>,
        (angle_weight, force_weight): (f64, f64),
        reactions: bool,
        tips: bool,
    ) -> Figures {
        let mut count = 0usize;
        let (mut sp, mut sa, mut sf) = (0.0, 0.0, 0.0);
        let (mut mp, mut ma, mut mf, mut mt) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
        for [pos, ang, force, tip] in cases {
            count += 1;
            mt = mt.max(tip);
            sp += pos * pos;
            sa += ang * ang;
            sf += force * force;
            mp = mp.max(pos);
            ma = ma.max(ang.abs());
            mf = mf.max(force);
        }
        let n = count.max(1) as f64;
        Figures {
            rms_pos_err: (sp / n).sqrt(),
            max_pos_err: mp,
            rms_ang_err: (sa / n).sqrt(),
            max_ang_err: ma,
            objective: (sp + angle_weight * sa + force_weight * sf) / n,
            rms_force_err: reactions.then(|| (sf / n).sqrt()),
            max_force_err: reactions.then_some(mf),
            max_tip_err: tips.then_some(mt),
            max_freq_err: None,
        }
    }

    /// The reaction error's largest value, 0 when nothing is prescribed.
    pub fn max_force(&self) -> f64 {
        self.max_force_err.unwrap_or(0.0)
    }

    /// Whether the figures meet a scene's targets (position, angle and, where there are
    /// reactions, reaction; where frequencies are judged, `max_freq_err`).
    pub fn meets(&self, accuracy: &Accuracy) -> bool {
        self.max_pos_err <= accuracy.max_pos_err
            && self.max_ang_err <= accuracy.max_ang_err
            && self.max_force() <= accuracy.max_force_err
            && self.max_freq() <= accuracy.max_freq_err
    }

    /// The frequency error's largest value, 0 when no frequency is judged.
    pub fn max_freq(&self) -> f64 {
        self.max_freq_err.unwrap_or(0.0)
    }

    /// The worst ratio of a figure to its target (1 = on target).
    pub fn target_ratio(&self, accuracy: &Accuracy) -> f64 {
        (self.max_pos_err / accuracy.max_pos_err)
            .max(self.max_ang_err / accuracy.max_ang_err)
            .max(self.max_force() / accuracy.max_force_err)
            .max(self.max_freq() / accuracy.max_freq_err)
    }
}

/// One pair of cases compared: the truth's and the model's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JudgedCase {
    /// Which load path or drive (from 1).
    pub path: usize,
    /// The path's fraction `k / steps` (a measured path's `k / rows`).
    pub fraction: f64,
    /// The truth's case (the beam, the beam mechanism, or a measured row).
    pub truth: MechCase,
    /// The model's case.
    pub model: MechCase,
    /// Stage position error over the loaded position coordinates, units of flexure 1's `L`.
    pub pos_err: f64,
    /// Stage angle error `dphi_model - dphi_truth` if `dphi` is loaded, else 0; radians.
    pub ang_err: f64,
    /// Reaction error over the prescribed coordinates, each as a fraction of that
    /// coordinate's reaction scale, combined as the root of the sum of squares (0 when none
    /// is prescribed).
    pub force_err: f64,
    /// The largest flexure tip position error of the case, units of that flexure's `L` (0
    /// when the truth has no flexure tips).
    pub tip_err: f64,
}

/// A model judged against a truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Judgement {
    /// The figures over every case.
    pub figures: Figures,
    /// The reaction scale `S_c` of each stage coordinate `[x, y, phi]` (nondimensional,
    /// flexure 1's units); `None` for a coordinate no drive prescribes.
    pub reaction_scale: [Option<f64>; 3],
    /// Per case, path by path: the followed ones.
    pub cases: Vec<JudgedCase>,
    /// The paths the model could not follow to their end (DESIGN §6: the figures are over
    /// the cases it followed); empty when it followed every case.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unfollowed: Vec<UnfollowedPath>,
    /// The model's natural frequencies against the truth's (DESIGN §10), when the scene
    /// gives `[beam] density`; filled by the study.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequencies: Option<Frequencies>,
}

/// A model's natural frequencies against the truth's (DESIGN §10), about the unloaded
/// equilibrium, in flexure 1's `Omega = omega sqrt(rho A0 L^4 / (E I0))` and in Hz.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frequencies {
    /// The truth's `Omega`, lowest first.
    pub beam: Vec<f64>,
    /// The model's, as many (fewer when the model has fewer moving joints).
    pub model: Vec<f64>,
    /// The truth's in Hz.
    pub beam_hz: Vec<f64>,
    /// The model's in Hz.
    pub model_hz: Vec<f64>,
    /// `Omega_model / Omega_beam - 1` per frequency the model has.
    pub freq_err: Vec<f64>,
    /// How many of them the scene's fit matches and targets (`[fit] modes`).
    pub judged: usize,
    /// The truth is measured data, which has no dynamics: the beam's frequencies are the
    /// nominal beam's.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub nominal: bool,
}

impl Frequencies {
    /// The largest `|freq_err|` over the judged frequencies (infinite when the model has
    /// fewer).
    pub fn max_err(&self) -> f64 {
        (0..self.judged)
            .map(|i| self.freq_err.get(i).map_or(f64::INFINITY, |e| e.abs()))
            .fold(0.0, f64::max)
    }

    /// `mean_i (Omega_PRB,i / Omega_beam,i - 1)^2` over the judged frequencies (a missing
    /// one counts as an error of 1).
    pub fn mean_square(&self) -> f64 {
        if self.judged == 0 {
            return 0.0;
        }
        (0..self.judged)
            .map(|i| self.freq_err.get(i).map_or(1.0, |e| e * e))
            .sum::<f64>()
            / self.judged as f64
    }
}

/// A load path or drive a model could not follow to its end.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnfollowedPath {
    /// Which path (from 1).
    pub path: usize,
    /// The fraction of the path it reached (its last followed case's; 0 when none).
    pub fraction: f64,
    /// Why it stopped.
    pub reason: String,
}

/// Why two sets of cases cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompareError {
    /// The solutions do not have one path per drive.
    #[error("{what} has {got} drive paths, the mechanism {expected}: the cases do not pair up")]
    Drives {
        /// Which solution ("the PRB mechanism", "the exact mechanism").
        what: &'static str,
        /// Its path count.
        got: usize,
        /// The mechanism's drive count.
        expected: usize,
    },
    /// A drive's paths have different lengths or fractions.
    #[error(
        "drive {drive}: the PRB mechanism has {prb} cases, the exact one {exact}, or their \
         fractions differ: the cases do not pair up"
    )]
    Cases {
        /// Which drive path (from 1).
        drive: usize,
        /// Case count of the PRB path.
        prb: usize,
        /// Case count of the exact path.
        exact: usize,
    },
}

/// The reaction scale `S_c` of each coordinate: the largest `|R_truth,c|` over the drives
/// that prescribe `c`, floored (module docs). `None` where no drive prescribes `c`.
pub fn reaction_scales(drives: &[Drive], truth: &[Vec<MechCase>]) -> [Option<f64>; 3] {
    let mut scale = [None::<f64>; 3];
    for (drive, cases) in drives.iter().zip(truth) {
        for (c, coordinate) in drive.coordinates.iter().enumerate() {
            if !coordinate.is_prescribed() {
                continue;
            }
            let largest = cases
                .iter()
                .map(|case| case.stage_load[c].abs())
                .fold(scale[c].unwrap_or(0.0), f64::max);
            scale[c] = Some(largest);
        }
    }
    let biggest = scale.iter().flatten().fold(0.0_f64, |m, s| m.max(*s));
    let floor = (RELATIVE_SCALE_FLOOR * biggest).max(ABSOLUTE_SCALE_FLOOR);
    scale.map(|s| s.map(|s| s.max(floor)))
}

/// Whether some drive prescribes some coordinate: the figures then have reaction errors.
pub fn has_reactions(drives: &[Drive]) -> bool {
    drives
        .iter()
        .any(|d| d.coordinates.iter().any(|c| c.is_prescribed()))
}

/// Compares the model's cases with the truth's along `drives` (the mechanism's drive paths,
/// which say which coordinates are prescribed), with `w = angle_weight` and
/// `w_f = force_weight` in `J`. The flexure tip error is judged when the truth has flexure
/// tips.
///
/// # Errors
/// [`CompareError`] when the two solutions do not have the same drives, case counts and
/// fractions.
pub fn compare(
    drives: &[Drive],
    model: &[Vec<MechCase>],
    truth: &[Vec<MechCase>],
    angle_weight: f64,
    force_weight: f64,
) -> Result<Judgement, CompareError> {
    check_pairs(drives, model, truth)?;
    Ok(compare_scaled(
        drives,
        model,
        truth,
        reaction_scales(drives, truth),
        (angle_weight, force_weight),
    ))
}

/// That `model` and `truth` have one path per drive and their cases pair one to one (same
/// counts, same fractions).
fn check_pairs(
    drives: &[Drive],
    model: &[Vec<MechCase>],
    truth: &[Vec<MechCase>],
) -> Result<(), CompareError> {
    for (what, got) in [
        ("the PRB mechanism", model.len()),
        ("the exact mechanism", truth.len()),
    ] {
        if got != drives.len() {
            return Err(CompareError::Drives {
                what,
                got,
                expected: drives.len(),
            });
        }
    }
    for (i, (p, e)) in model.iter().zip(truth).enumerate() {
        let fractions_differ = p
            .iter()
            .zip(e)
            .any(|(p, e)| (p.fraction - e.fraction).abs() > 1e-12);
        if p.len() != e.len() || fractions_differ {
            return Err(CompareError::Cases {
                drive: i + 1,
                prb: p.len(),
                exact: e.len(),
            });
        }
    }
    Ok(())
}

/// [`compare`] of a model that may have stopped short on some drives (a critical point the
/// truth does not have): each drive's cases as far as the model got, paired with the
/// truth's first ones, each coordinate's reaction scale still the whole truth's, so the
/// figures over the followed cases read as the whole scene's would.
///
/// # Errors
/// [`CompareError`] when the model has cases the truth does not (more of them, other
/// fractions), or another number of drives.
pub fn compare_followed(
    drives: &[Drive],
    model: &[Vec<MechCase>],
    truth: &[Vec<MechCase>],
    angle_weight: f64,
    force_weight: f64,
) -> Result<Judgement, CompareError> {
    let reached: Vec<Vec<MechCase>> = truth
        .iter()
        .zip(model)
        .map(|(t, m)| t[..m.len().min(t.len())].to_vec())
        .collect();
    // The strict checks on what was reached: same drives, same cases, same fractions.
    check_pairs(drives, model, &reached)?;
    Ok(compare_scaled(
        drives,
        model,
        &reached,
        reaction_scales(drives, truth),
        (angle_weight, force_weight),
    ))
}

/// The judgement of pairs of cases that line up, with the reaction scales `reaction_scale`.
fn compare_scaled(
    drives: &[Drive],
    model: &[Vec<MechCase>],
    truth: &[Vec<MechCase>],
    reaction_scale: [Option<f64>; 3],
    (angle_weight, force_weight): (f64, f64),
) -> Judgement {
    let mut cases = Vec::new();
    for (i, ((drive, p_path), e_path)) in drives.iter().zip(model).zip(truth).enumerate() {
        let prescribed = drive.coordinates.map(|c| c.is_prescribed());
        for (p, e) in p_path.iter().zip(e_path) {
            let errors = signed_errors(drive, p, e, &reaction_scale);
            let pick = |c: usize, want: bool| {
                if prescribed[c] == want {
                    errors[c]
                } else {
                    0.0
                }
            };
            let (dx, dy, ang_err) = (pick(0, false), pick(1, false), pick(2, false));
            let force_err = pick(0, true).hypot(pick(1, true)).hypot(pick(2, true));
            cases.push(JudgedCase {
                path: i + 1,
                fraction: e.fraction,
                truth: e.clone(),
                model: p.clone(),
                pos_err: dx.hypot(dy),
                ang_err,
                force_err,
                tip_err: p
                    .flexures
                    .iter()
                    .zip(&e.flexures)
                    .map(|(a, b)| (a.tip.a - b.tip.a).hypot(a.tip.b - b.tip.b))
                    .fold(0.0, f64::max),
            });
        }
    }
    let tips = truth.iter().flatten().any(|c| !c.flexures.is_empty());
    Judgement {
        figures: Figures::from_cases(
            &cases,
            angle_weight,
            force_weight,
            has_reactions(drives),
            tips,
        ),
        reaction_scale,
        cases,
        unfollowed: Vec::new(),
        frequencies: None,
    }
}

/// One signed error per stage coordinate of a case pair: for a loaded coordinate the stage
/// motion's (`model - truth`, units of flexure 1's `L` or radians), for a prescribed one the
/// reaction's as a fraction of the coordinate's reaction scale `scale` (from
/// [`Judgement::reaction_scale`]). `pos_err`, `ang_err` and `force_err` are made of these,
/// and so are the fit's residuals.
pub fn signed_errors(
    drive: &Drive,
    model: &MechCase,
    truth: &MechCase,
    scale: &[Option<f64>; 3],
) -> [f64; 3] {
    std::array::from_fn(|c| {
        if drive.coordinates[c].is_prescribed() {
            (model.stage_load[c] - truth.stage_load[c]) / reaction_divisor(scale, c)
        } else {
            model.stage[c] - truth.stage[c]
        }
    })
}

/// What [`signed_errors`] divides coordinate `c`'s reaction error by: its reaction scale,
/// or the absolute floor where it has none.
pub fn reaction_divisor(scale: &[Option<f64>; 3], c: usize) -> f64 {
    scale[c].unwrap_or(ABSOLUTE_SCALE_FLOOR)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::scene::Coordinate::{Loaded, Prescribed};

    fn case(fraction: f64, stage: [f64; 3], stage_load: [f64; 3]) -> MechCase {
        MechCase {
            fraction,
            stage,
            stage_load,
            flexures: Vec::new(),
            iterations: 0,
            joints: Vec::new(),
            state: None,
        }
    }

    /// dx loaded, dy and dphi prescribed: the fixed-guided segment's drive.
    fn guided(steps: u32) -> Drive {
        Drive::proportional([Loaded(0.0), Prescribed(0.3), Prescribed(0.0)], steps)
    }

    #[test]
    fn hand_computed_fixed_guided_pair() {
        // Two cases. Exact reactions: y 2 and 4 (S_y = 4), phi -0.5 and -1 (S_phi = 1).
        let exact = vec![vec![
            case(0.5, [-0.01, 0.15, 0.0], [0.0, 2.0, -0.5]),
            case(1.0, [-0.04, 0.30, 0.0], [0.0, 4.0, -1.0]),
        ]];
        // PRB: dx off by 0.003 and 0.004; y reactions off by 0.2 and 0.4; phi off by 0.3, 0.
        let prb = vec![vec![
            case(0.5, [-0.013, 0.15, 0.0], [0.0, 2.2, -0.8]),
            case(1.0, [-0.044, 0.30, 0.0], [0.0, 3.6, -1.0]),
        ]];
        let e = compare(&[guided(2)], &prb, &exact, 1.0, 2.0).unwrap();
        assert_eq!(e.reaction_scale, [None, Some(4.0), Some(1.0)]);
        let c = &e.cases;
        assert!((c[0].pos_err - 0.003).abs() < 1e-15);
        assert!((c[1].pos_err - 0.004).abs() < 1e-15);
        assert_eq!(c[0].ang_err, 0.0);
        // Case 1: y 0.2/4 = 0.05, phi 0.3/1 = 0.3 -> hypot = sqrt(0.0925). Case 2: y
        // 0.4/4 = 0.1, phi 0.
        assert!((c[0].force_err - 0.0925_f64.sqrt()).abs() < 1e-12);
        assert!((c[1].force_err - 0.1).abs() < 1e-12);
        let f = e.figures;
        assert!((f.max_pos_err - 0.004).abs() < 1e-15);
        assert!((f.rms_pos_err - (12.5e-6_f64).sqrt()).abs() < 1e-15);
        assert!((f.max_force() - 0.0925_f64.sqrt()).abs() < 1e-12);
        assert!((f.rms_force_err.unwrap() - 0.05125_f64.sqrt()).abs() < 1e-12);
        assert_eq!((f.rms_ang_err, f.max_ang_err), (0.0, 0.0));
        // J = mean(e_pos^2 + 2 e_force^2) = (9e-6 + 0.185 + 16e-6 + 0.02) / 2.
        assert!((f.objective - (25e-6 + 0.205) / 2.0).abs() < 1e-15);
    }

    /// The tip error: per case the largest flexure tip position error, over the cases the
    /// largest; not part of `J`.
    #[test]
    fn tip_error_is_the_worst_flexure_tip() {
        use crate::beam::{Load, TipPose};
        use crate::mech::FlexureCase;
        let with_tips = |mut c: MechCase, tips: &[(f64, f64)]| {
            c.flexures = tips
                .iter()
                .map(|&(a, b)| FlexureCase {
                    tip: TipPose { a, b, phi: 0.0 },
                    wrench: Load {
                        alpha_x: 0.0,
                        alpha_y: 0.0,
                        beta: 0.0,
                    },
                    load_stable: true,
                    stress: None,
                })
                .collect();
            c
        };
        let stage = [-0.01, 0.15, 0.0];
        let load = [0.0, 2.0, -0.5];
        let exact = vec![vec![
            with_tips(case(0.5, stage, load), &[(0.9, 0.1), (0.9, 0.1)]),
            with_tips(case(1.0, stage, load), &[(0.8, 0.2), (0.8, 0.2)]),
        ]];
        // Case 1: flexure 2 off by (0.003, 0.004) = 0.005; case 2: flexure 1 off by 0.002.
        let prb = vec![vec![
            with_tips(case(0.5, stage, load), &[(0.9, 0.1), (0.903, 0.104)]),
            with_tips(case(1.0, stage, load), &[(0.8, 0.202), (0.8, 0.2)]),
        ]];
        let e = compare(&[guided(2)], &prb, &exact, 1.0, 1.0).unwrap();
        assert!((e.cases[0].tip_err - 0.005).abs() < 1e-12);
        assert!((e.cases[1].tip_err - 0.002).abs() < 1e-12);
        assert!((e.figures.max_tip_err.unwrap() - 0.005).abs() < 1e-12);
        assert_eq!(e.figures.objective, 0.0);
    }

    #[test]
    fn loaded_stage_uses_position_and_angle_only() {
        // Every coordinate loaded: the cantilever's figures, no force error.
        let drive = Drive::proportional([Loaded(0.0), Loaded(1.0), Loaded(0.5)], 1);
        let exact = vec![vec![case(1.0, [-0.1, 0.3, 0.4], [0.0, 1.0, 0.5])]];
        let prb = vec![vec![case(1.0, [-0.13, 0.34, 0.38], [0.0, 1.0, 0.5])]];
        let e = compare(&[drive], &prb, &exact, 0.5, 1.0).unwrap();
        assert_eq!(e.reaction_scale, [None, None, None]);
        let c = &e.cases[0];
        assert!((c.pos_err - 0.05).abs() < 1e-12); // a 3-4-5 triangle
        assert!((c.ang_err + 0.02).abs() < 1e-12);
        assert_eq!(c.force_err, 0.0);
        assert!((e.figures.objective - (0.0025 + 0.5 * 0.0004)).abs() < 1e-12);
        // Nothing prescribed: no reaction figures at all, and no flexure tips to judge.
        assert_eq!(e.figures.max_force_err, None);
        assert_eq!(e.figures.rms_force_err, None);
        assert_eq!(e.figures.max_tip_err, None);
    }

    #[test]
    fn a_coordinate_without_reaction_is_judged_against_the_largest() {
        // The guide (x) carries no exact reaction, the drive (y) carries 10: the guide's
        // scale is floored at 1e-3 * 10, so an x reaction error of 0.05 is 5, not 0.05 / 0.
        let drive = Drive::proportional([Prescribed(0.0), Prescribed(0.2), Loaded(0.0)], 1);
        let exact = vec![vec![case(1.0, [0.0, 0.2, 0.1], [0.0, 10.0, 0.0])]];
        let prb = vec![vec![case(1.0, [0.0, 0.2, 0.1], [0.05, 10.0, 0.0])]];
        let e = compare(&[drive], &prb, &exact, 1.0, 1.0).unwrap();
        assert_eq!(e.reaction_scale, [Some(1e-2), Some(10.0), None]);
        assert!((e.cases[0].force_err - 5.0).abs() < 1e-12);
        // Fully prescribed position: no position error even though nothing compares it.
        assert_eq!(e.cases[0].pos_err, 0.0);
        assert!(!e.figures.meets(&Accuracy::default()));
        let loose = Accuracy {
            max_force_err: 5.5,
            ..Accuracy::default()
        };
        assert!(e.figures.meets(&loose));
    }

    #[test]
    fn mismatched_solutions_are_errors() {
        let one = vec![vec![case(1.0, [0.0; 3], [0.0; 3])]];
        let two = vec![vec![
            case(0.5, [0.0; 3], [0.0; 3]),
            case(1.0, [0.0; 3], [0.0; 3]),
        ]];
        assert!(matches!(
            compare(&[guided(1)], &one, &two, 1.0, 1.0),
            Err(CompareError::Cases { drive: 1, .. })
        ));
        assert!(matches!(
            compare(&[guided(1), guided(1)], &one, &one, 1.0, 1.0),
            Err(CompareError::Drives {
                got: 1,
                expected: 2,
                ..
            })
        ));
        let shifted = vec![vec![case(0.9, [0.0; 3], [0.0; 3])]];
        assert!(compare(&[guided(1)], &shifted, &one, 1.0, 1.0).is_err());
    }
}
