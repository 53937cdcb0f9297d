//! A mechanism's measured data as its truth (DESIGN §9 with §8): the measured stage poses
//! and loads as the cases the PRB mechanism is judged and fitted against, in the units the
//! solvers report (flexure 1's `L` and `E I0`).
//!
//! Row `k` (from 1) of a path of `n` rows is the case at fraction `k / n`, where the
//! solvers, following the same path through the rows ([`crate::scene::DrivePath`]), report
//! it; so [`super::figures::compare`] pairs them one to one. The measured cases have no
//! flexure tips (a rig measures the stage), so the per-flexure tip error is not judged.

use crate::beam::Resolution;
use crate::scene::data::StageData;
use crate::scene::{Coordinate, Mechanism, Scene};

use super::figures::{compare, CompareError, Judgement};
use super::{exact, MechCase, MechError};

/// The truth a mechanism scene's PRB models are judged and fitted against, one `Vec` of
/// cases per drive path: a data scene's measured cases ([`truth_cases`]), or else the exact
/// (beam) mechanism solved at `resolution`. `mechanism` is the scene's, effects decided.
///
/// # Errors
/// The exact mechanism's, when the truth is the beam.
pub fn truth(
    scene: &Scene,
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<Vec<Vec<MechCase>>, MechError> {
    match &scene.truth {
        // A data scene read from text only has no rows and no drives yet: no cases.
        Some(t) => Ok(t
            .stage
            .as_ref()
            .map(|s| truth_cases(mechanism, s))
            .unwrap_or_default()),
        None => exact::solve(mechanism, resolution),
    }
}

/// Why the beam mechanism could not be judged against the data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BesideError {
    /// The exact mechanism cannot follow the measured drives.
    #[error("the beam mechanism along the measured drives: {0}")]
    Exact(#[from] MechError),
    /// Its cases do not pair with the rows.
    #[error(transparent)]
    Compare(#[from] CompareError),
}

/// The scene's own beam mechanism judged against a mechanism data scene's measurements
/// (DESIGN §9: how far the ideal flexures are from the specimen): the exact mechanism
/// followed through the measured drives, at `resolution`, compared with the measured cases
/// as a PRB mechanism would be (the data in the truth slot, the beam in the model's), with
/// the scene's weights. `None` for a scene without mechanism data.
pub fn beam_against_data(
    scene: &Scene,
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<Option<Judgement>, BesideError> {
    let Some(stage) = scene.truth.as_ref().and_then(|t| t.stage.as_ref()) else {
        return Ok(None);
    };
    let beam = exact::solve(mechanism, resolution)?;
    let data = truth_cases(mechanism, stage);
    Ok(Some(compare(
        &mechanism.drives,
        &beam,
        &data,
        scene.fit.angle_weight,
        scene.fit.force_weight,
    )?))
}

/// The measured cases of `stage`, one `Vec` per path, nondimensional with `mechanism`'s
/// scale (displacements over flexure 1's `L`, forces as `alpha`, moments as `beta`).
pub fn truth_cases(mechanism: &Mechanism, stage: &StageData) -> Vec<Vec<MechCase>> {
    let disp = mechanism.factors([Coordinate::Prescribed(0.0); 3]);
    let load = mechanism.factors([Coordinate::Loaded(0.0); 3]);
    stage
        .paths
        .iter()
        .map(|p| {
            let n = p.rows.len().max(1);
            p.rows
                .iter()
                .enumerate()
                .map(|(k, r)| MechCase {
                    fraction: (k + 1) as f64 / n as f64,
                    stage: std::array::from_fn(|c| r.stage[c] * disp[c]),
                    stage_load: std::array::from_fn(|c| r.stage_load[c] * load[c]),
                    flexures: Vec::new(),
                    iterations: 0,
                    joints: Vec::new(),
                    state: None,
                })
                .collect()
        })
        .collect()
}
