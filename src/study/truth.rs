//! A scene's truth, in the one form every operation reads: per path (a cantilever's load
//! path, a mechanism's drive, a measured path), the cases in §8's stage form
//! ([`MechCase`]: stage pose and load in flexure 1's units, and each flexure's tip and
//! wrench).
//!
//! A plain cantilever is the one-flexure mechanism of DESIGN §8 ([`one_flexure`]): one
//! clamped flexure from the origin along +x, its stage point at the unloaded tip, every
//! coordinate loaded, one drive per load path. Its stage motion is the tip's displacement
//! `(a - 1, b, phi)` and its stage load is the tip load. Its truth is still solved by the
//! beam's fast shooting path along each load path (or read from its measured tips), and
//! its PRB models still by the chain's own statics; [`tip_case`] puts their answers in the
//! stage form.

use crate::beam::{BeamSolution, Load, Stress, TipPose};
use crate::eval::Baseline;
use crate::mech::{FlexureCase, MechCase};
use crate::scene::{Attach, Coordinate, Drive, Flexure, Mechanism, Scene};
use crate::si::load_si;

/// The cantilever of `scene` as the one-flexure mechanism of DESIGN §8: one clamped flexure
/// (the scene's beam) from the origin along +x, the stage point at its unloaded tip, and
/// one drive per load path with every coordinate loaded by the path's end load in SI (a
/// data scene's paths through their measured loads).
pub fn one_flexure(scene: &Scene) -> Mechanism {
    let beam = scene.beam;
    let drives = match &scene.truth {
        Some(truth) if !truth.paths.is_empty() => truth
            .paths
            .iter()
            .map(|p| {
                let rows: Vec<[f64; 3]> = p.rows.iter().map(|r| load_si(&beam, &r.load)).collect();
                let end = rows.last().copied().unwrap_or([0.0; 3]);
                Drive {
                    coordinates: end.map(Coordinate::Loaded),
                    steps: u32::try_from(rows.len()).unwrap_or(u32::MAX),
                    rows,
                }
            })
            .collect(),
        _ => scene
            .loads
            .iter()
            .map(|p| Drive::proportional(load_si(&beam, &p.end).map(Coordinate::Loaded), p.steps))
            .collect(),
    };
    Mechanism {
        flexures: vec![Flexure {
            root: [0.0, 0.0],
            angle: 0.0,
            attach: Attach::Clamped,
            beam,
        }],
        stage_point: [beam.length, 0.0],
        drives,
    }
}

/// A cantilever's case in the stage form: the tip `tip` under `load`, at `fraction` of its
/// path, with its largest fibre stress when known.
pub fn tip_case(
    fraction: f64,
    load: Load,
    tip: TipPose,
    iterations: u32,
    stress: Option<Stress>,
) -> MechCase {
    MechCase {
        fraction,
        stage: [tip.a - 1.0, tip.b, tip.phi],
        stage_load: [load.alpha_x, load.alpha_y, load.beta],
        flexures: vec![FlexureCase {
            tip,
            wrench: load,
            load_stable: true,
            stress,
        }],
        iterations,
        joints: Vec::new(),
        state: None,
    }
}

/// The cases of a cantilever's baseline (the beam's solutions, or its measured tips), path
/// by path, in the stage form.
pub fn baseline_cases(baseline: &Baseline) -> Vec<Vec<MechCase>> {
    let mut out = Vec::with_capacity(baseline.paths.len());
    let mut start = 0;
    for path in &baseline.paths {
        let end = (start + path.steps as usize).min(baseline.solutions.len());
        let solutions: &[BeamSolution] = &baseline.solutions[start..end];
        start = end;
        let n = solutions.len().max(1) as f64;
        out.push(
            solutions
                .iter()
                .enumerate()
                .map(|(k, s)| tip_case((k + 1) as f64 / n, s.load, s.tip, s.iterations, s.stress))
                .collect(),
        );
    }
    out
}
