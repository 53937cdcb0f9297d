//! How well a PRB mechanism follows the exact one (DESIGN §8): per-case errors and the seven
//! error figures of a mechanism scene.
//!
//! # Method
//! Both mechanisms are solved along the same drive paths, so their cases pair one to one.
//! For each pair, with `exact` the beam mechanism and `prb` the PRB one:
//! - `pos_err`: the distance between the two stage points over the *loaded* position
//!   coordinates only, `hypot` of the `dx` and `dy` errors of those of `dx`, `dy` that are
//!   loaded (units of flexure 1's `L`); 0 when both are prescribed, since a prescribed
//!   coordinate is where the drive puts it in both mechanisms.
//! - `ang_err`: `dphi_prb - dphi_exact` (radians) when `dphi` is loaded, else 0.
//! - `force_err`: for each *prescribed* coordinate `c`, `|R_prb,c - R_exact,c| / S_c`, with
//!   `R` the drive's reaction (`stage_load[c]`) and `S_c` the largest `|R_exact,c|` over every
//!   case of every drive that prescribes `c`; the case's value is the root of the sum of
//!   their squares over its prescribed coordinates (0 when it has none), as `pos_err` is of
//!   the position errors, so that `J` is a plain sum of squares the fit can minimise. `S_c` is floored at `1e-3` times the
//!   largest `S` of any prescribed coordinate, so that a coordinate that carries (almost) no
//!   reaction, such as the guide of a fixed-guided segment with no axial force, is judged
//!   against the mechanism's main reaction instead of being divided by nearly zero; and at
//!   `1e-12`, so that a drive no part of which pushes back gives a finite figure.
//!
//! The figures are those of DESIGN §4 plus the reaction error's RMS and maximum, with
//! `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`.

use serde::Serialize;

use crate::scene::{Accuracy, Drive};

use super::MechCase;

/// The floor of a coordinate's reaction scale, relative to the largest one (see the module
/// docs).
const RELATIVE_SCALE_FLOOR: f64 = 1e-3;
/// The absolute floor of a reaction scale, nondimensional.
const ABSOLUTE_SCALE_FLOOR: f64 = 1e-12;

/// The error figures of a mechanism scene (DESIGN §4 and §8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MechFigures {
    /// RMS of `e_pos`, units of flexure 1's `L`.
    pub rms_pos_err: f64,
    /// Largest `e_pos`, units of flexure 1's `L`.
    pub max_pos_err: f64,
    /// RMS of `e_ang`, radians.
    pub rms_ang_err: f64,
    /// Largest `|e_ang|`, radians.
    pub max_ang_err: f64,
    /// `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`.
    pub objective: f64,
    /// RMS of `e_force`, a fraction of each coordinate's largest reaction.
    pub rms_force_err: f64,
    /// Largest `e_force`.
    pub max_force_err: f64,
    /// Largest flexure tip position error over every flexure and case, units of that
    /// flexure's own `L`: how far a PRB flexure's tip is from the beam's even where the
    /// stage figures cannot see it (a fully prescribed stage). Reported, not in `J`; 0 against
    /// measured data, which has no flexure tips to judge.
    pub max_tip_err: f64,
}

impl MechFigures {
    /// Whether the figures meet a scene's targets (position, angle and reaction).
    pub fn meets(&self, accuracy: &Accuracy) -> bool {
        self.max_pos_err <= accuracy.max_pos_err
            && self.max_ang_err <= accuracy.max_ang_err
            && self.max_force_err <= accuracy.max_force_err
    }
}

/// One pair of cases compared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechCaseError {
    /// Which drive path (from 1).
    pub drive: usize,
    /// The drive path's fraction `k / steps`.
    pub fraction: f64,
    /// The exact mechanism's case.
    pub exact: MechCase,
    /// The PRB mechanism's case.
    pub prb: MechCase,
    /// Stage position error over the loaded position coordinates, units of flexure 1's `L`.
    pub pos_err: f64,
    /// Stage angle error `dphi_prb - dphi_exact` if `dphi` is loaded, else 0; radians.
    pub ang_err: f64,
    /// Reaction error over the prescribed coordinates, each as a fraction of that
    /// coordinate's reaction scale, combined as the root of the sum of squares.
    pub force_err: f64,
    /// The largest flexure tip position error of the case, units of that flexure's `L`.
    pub tip_err: f64,
}

/// A PRB mechanism judged against the exact one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechEvaluation {
    /// The figures over every case.
    pub figures: MechFigures,
    /// The reaction scale `S_c` of each stage coordinate `[x, y, phi]` (nondimensional,
    /// flexure 1's units); `None` for a coordinate no drive prescribes.
    pub reaction_scale: [Option<f64>; 3],
    /// Per case, drive by drive.
    pub cases: Vec<MechCaseError>,
}

/// Why two sets of mechanism cases cannot be compared.
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

/// The reaction scale `S_c` of each coordinate: the largest `|R_exact,c|` over the drives
/// that prescribe `c`, floored (module docs). `None` where no drive prescribes `c`.
fn reaction_scales(drives: &[Drive], exact: &[Vec<MechCase>]) -> [Option<f64>; 3] {
    let mut scale = [None::<f64>; 3];
    for (drive, cases) in drives.iter().zip(exact) {
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

/// Compares the PRB mechanism's cases with the exact mechanism's along `drives` (the
/// mechanism's drive paths, which say which coordinates are prescribed), with
/// `w = angle_weight` and `w_f = force_weight` in `J`.
///
/// # Errors
/// [`CompareError`] when the two solutions do not have the same drives, case counts and
/// fractions.
pub fn compare(
    drives: &[Drive],
    prb: &[Vec<MechCase>],
    exact: &[Vec<MechCase>],
    angle_weight: f64,
    force_weight: f64,
) -> Result<MechEvaluation, CompareError> {
    for (what, got) in [
        ("the PRB mechanism", prb.len()),
        ("the exact mechanism", exact.len()),
    ] {
        if got != drives.len() {
            return Err(CompareError::Drives {
                what,
                got,
                expected: drives.len(),
            });
        }
    }
    for (i, (p, e)) in prb.iter().zip(exact).enumerate() {
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
    let reaction_scale = reaction_scales(drives, exact);
    let mut cases = Vec::new();
    for (i, ((drive, p_path), e_path)) in drives.iter().zip(prb).zip(exact).enumerate() {
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
            cases.push(MechCaseError {
                drive: i + 1,
                fraction: e.fraction,
                exact: e.clone(),
                prb: p.clone(),
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
    Ok(MechEvaluation {
        figures: figures(&cases, angle_weight, force_weight),
        reaction_scale,
        cases,
    })
}

/// One signed error per stage coordinate of a case pair: for a loaded coordinate the stage
/// motion's (`prb - exact`, units of flexure 1's `L` or radians), for a prescribed one the
/// reaction's as a fraction of the coordinate's reaction scale `scale` (from
/// [`MechEvaluation::reaction_scale`]). `pos_err`, `ang_err` and `force_err` are made of
/// these, and so are the fit's residuals.
pub fn signed_errors(
    drive: &Drive,
    prb: &MechCase,
    exact: &MechCase,
    scale: &[Option<f64>; 3],
) -> [f64; 3] {
    std::array::from_fn(|c| {
        if drive.coordinates[c].is_prescribed() {
            (prb.stage_load[c] - exact.stage_load[c]) / scale[c].unwrap_or(ABSOLUTE_SCALE_FLOOR)
        } else {
            prb.stage[c] - exact.stage[c]
        }
    })
}

/// The seven figures over `cases`.
fn figures(cases: &[MechCaseError], angle_weight: f64, force_weight: f64) -> MechFigures {
    let n = cases.len().max(1) as f64;
    let (mut sp, mut sa, mut sf) = (0.0, 0.0, 0.0);
    let (mut mp, mut ma, mut mf, mut mt) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for c in cases {
        mt = mt.max(c.tip_err);
        sp += c.pos_err * c.pos_err;
        sa += c.ang_err * c.ang_err;
        sf += c.force_err * c.force_err;
        mp = mp.max(c.pos_err);
        ma = ma.max(c.ang_err.abs());
        mf = mf.max(c.force_err);
    }
    MechFigures {
        rms_pos_err: (sp / n).sqrt(),
        max_pos_err: mp,
        rms_ang_err: (sa / n).sqrt(),
        max_ang_err: ma,
        objective: (sp + angle_weight * sa + force_weight * sf) / n,
        rms_force_err: (sf / n).sqrt(),
        max_force_err: mf,
        max_tip_err: mt,
    }
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
        assert!((f.max_force_err - 0.0925_f64.sqrt()).abs() < 1e-12);
        assert!((f.rms_force_err - 0.05125_f64.sqrt()).abs() < 1e-12);
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
        assert!((e.figures.max_tip_err - 0.005).abs() < 1e-12);
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
        assert_eq!(e.figures.max_force_err, 0.0);
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
