//! Measured data in the worker (DESIGN §9). A data scene's baseline is its rows
//! ([`Baseline::from_data`](crate::eval::Baseline::from_data): the measured tips, no shapes);
//! beside it the charts draw the scene's own beam solved at every measured load, each by
//! continuation from the unloaded beam as `eval::beam_against_data` solves it for the reports,
//! so the UI's "beam vs data" is the CLI's. Solved here, off the UI thread, with the baseline
//! and cached with it.

use crate::beam::{BeamSolver, Resolution, SolveError, TipPose};
use crate::cancel::CancelToken;
use crate::eval::{tip_figures, CaseError};
use crate::mech::figures::Figures;
use crate::scene::data::DataTruth;
use crate::scene::BeamSpec;

/// A data scene's truth as the charts and the status lines show it.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredView {
    /// The data file as the scene names it (sanitized when drawn).
    pub file: String,
    /// SHA-256 of its bytes, lowercase hex.
    pub sha256: String,
    /// Per case (row, path by path, as the baseline's cases), the measured tip.
    pub tips: Vec<TipPose>,
    /// The scene's beam at the measured loads, or why it cannot reach them.
    pub beam: Result<BeamBeside, String>,
}

/// The beam theory beside measured data: the scene's beam (its effects decided) solved at
/// every measured load.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamBeside {
    /// Per case, the beam's deformed centre line (units of L).
    pub shapes: Vec<Vec<(f64, f64)>>,
    /// Per case, the beam's tip against the measured one, as `eval::beam_against_data`
    /// gives them: the data in the `beam` slot, the beam theory in the `prb` slot.
    pub cases: Vec<CaseError>,
}

impl BeamBeside {
    /// The beam's figures against the data, with `w = angle_weight` in `J` (taken when
    /// drawn, so an edit of the weight needs no new solve).
    pub fn figures(&self, angle_weight: f64) -> Figures {
        tip_figures(&self.cases, angle_weight)
    }
}

/// Why [`measured_view`] has no answer: the job was cancelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cancelled;

/// The charts' view of `truth`, with `beam` (effects decided) solved at every measured load
/// at `resolution`. A beam that cannot reach a row is no failure of the job (the data are
/// the truth; the beam is only shown beside them): the view says why instead.
///
/// # Errors
/// [`Cancelled`] soon after `cancel` is set (the beam checks it every continuation step).
pub fn measured_view(
    truth: &DataTruth,
    beam: &BeamSpec,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<MeasuredView, Cancelled> {
    Ok(MeasuredView {
        file: truth.file.clone(),
        sha256: truth.sha256.clone(),
        tips: truth
            .paths
            .iter()
            .flat_map(|p| &p.rows)
            .map(|r| r.tip)
            .collect(),
        beam: beam_beside(truth, beam, resolution, cancel)?,
    })
}

fn beam_beside(
    truth: &DataTruth,
    beam: &BeamSpec,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<Result<BeamBeside, String>, Cancelled> {
    let solver = match BeamSolver::new(beam.model(), resolution) {
        Ok(s) => s,
        Err(e) => return Ok(Err(format!("the beam cannot be solved: {e}"))),
    };
    let mut shapes = Vec::with_capacity(truth.row_count());
    let mut cases = Vec::with_capacity(truth.row_count());
    for row in truth.paths.iter().flat_map(|p| &p.rows) {
        match solver.solve_cancellable(row.load, cancel) {
            Ok(solved) => {
                shapes.push(solved.shape.iter().map(|p| (p.x, p.y)).collect());
                cases.push(CaseError::new(row.load, row.tip, solved.tip));
            }
            Err(SolveError::Cancelled { .. }) => return Err(Cancelled),
            Err(e) => {
                return Ok(Err(format!(
                    "the beam cannot reach line {} of {}: {e}",
                    row.line, truth.file
                )))
            }
        }
    }
    Ok(Ok(BeamBeside { shapes, cases }))
}
