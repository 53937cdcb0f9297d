//! What the UI asks of the worker ([`Job`]) and what the worker sends back ([`WorkerMsg`]):
//! one set of messages for every kind of scene, each naming its job, and each result with
//! the truth view it was judged on.

use std::path::PathBuf;
use std::sync::Arc;

use crate::cancel::CancelToken;
use crate::fit::{Fidelity, FitReport};
use crate::prb::PrbMatrix;
use crate::scene::Scene;
use crate::study::select::{Rung, Selection};
use crate::study::tradeoff::Knob;

use super::super::latest_job::Cancellable;
use super::view::{ModelView, TruthView};

/// What a job does.
#[derive(Debug, Clone, PartialEq)]
pub enum JobKind {
    /// Write the matrix to a file, in the format its extension names.
    Export {
        /// The file.
        path: PathBuf,
        /// The links' density (kg/m^3) for their masses: the scene's, else the one typed for
        /// a robot format (MJCF, URDF, SDF); none for a model file or CSV of a scene without
        /// one (no masses, as the CLI writes it).
        density: Option<f64>,
        /// Replace the file if it exists (the user said so).
        overwrite: bool,
    },
    /// Judge the matrix.
    Judge,
    /// Judge, then fit its free cells.
    Fit,
    /// Fit the topology ladder, judge the published models, measure the trade-off.
    Select,
    /// Judge the matrix as the model the user compares against (a kept job: it neither
    /// cancels nor is cancelled by the fit of the model being worked on).
    Compare,
}

/// One request: the scene as it was when the job was made, and the matrix.
#[derive(Debug, Clone)]
pub struct Job {
    /// Numbers jobs in the order the UI made them; every message names its job.
    pub id: u64,
    /// The scene (beam, loads or mechanism, targets, weights, data) the job works on.
    pub scene: Arc<Scene>,
    /// The PRB matrix to judge, fit or export.
    pub matrix: PrbMatrix,
    /// The model to compare against: a judge or fit job judges it too, on the same truth,
    /// and its messages carry it.
    pub compare: Option<PrbMatrix>,
    /// How finely the truth is solved and the fit sampled.
    pub fidelity: Fidelity,
    /// What to do.
    pub kind: JobKind,
    /// Stops the job; cancelled when a newer job is submitted (except for exports).
    pub cancel: CancelToken,
}

impl Cancellable for Job {
    fn cancel_token(&self) -> &CancelToken {
        &self.cancel
    }
}

/// How far a fit has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitStatus {
    /// The search's phase (`start`, `swarm`, `polish`): its iterations count from 0 again
    /// in each.
    pub phase: &'static str,
    /// Optimiser iterations so far.
    pub iteration: u32,
    /// Objective evaluations so far.
    pub evaluations: u64,
    /// Time since the job started.
    pub seconds: f64,
}

/// Messages to the UI.
#[derive(Debug, Clone)]
pub enum WorkerMsg {
    /// The job's starting matrix judged (before any fitting), or the best matrix so far.
    Progress {
        /// The job.
        id: u64,
        /// The truth the model was judged on.
        truth: Arc<TruthView>,
        /// The model.
        model: Box<ModelView>,
        /// How far the fit has got.
        status: FitStatus,
        /// The job's compare model, judged on the same truth.
        compare: Option<Box<ModelView>>,
    },
    /// The job's final model.
    Done {
        /// The job.
        id: u64,
        /// The truth the model was judged on.
        truth: Arc<TruthView>,
        /// The model.
        model: Box<ModelView>,
        /// The fit's report (none for a judge job).
        report: Option<Box<FitReport>>,
        /// Time the job took.
        seconds: f64,
        /// The job's compare model, judged on the same truth.
        compare: Option<Box<ModelView>>,
    },
    /// A compare job's model, judged.
    Compared {
        /// The job.
        id: u64,
        /// The truth it was judged on.
        truth: Arc<TruthView>,
        /// The model.
        model: Box<ModelView>,
    },
    /// The job failed, saying why.
    Failed {
        /// The job.
        id: u64,
        /// Why, for the user.
        message: String,
    },
    /// A fit under way with no new model to show: a selection's ladder fit (between two
    /// rows, which a fit on many cases may keep apart for minutes), or a fit searching on
    /// without a better model (its heartbeat, [`crate::fit::HEARTBEAT`]).
    Fitting {
        /// The job.
        id: u64,
        /// How far that fit has got (its time since the job started).
        status: FitStatus,
    },
    /// One row of a selection, as soon as it is fitted.
    SelectRow {
        /// The job.
        id: u64,
        /// The row.
        row: Box<Rung>,
    },
    /// The whole selection and the trade-off measurements (none where the trade-off has
    /// nothing to measure: a mechanism, measured data).
    SelectDone {
        /// The job.
        id: u64,
        /// The ladder, its choice and the models that cannot follow the scene.
        selection: Box<Selection>,
        /// The trade-off measurements.
        knobs: Vec<Knob>,
    },
    /// An export finished (or failed, saying why). Never stale: the user asked for it.
    Exported {
        /// The job.
        id: u64,
        /// The file.
        path: PathBuf,
        /// Written, or why not.
        result: Result<(), String>,
    },
}

impl WorkerMsg {
    /// The job the message belongs to.
    pub fn id(&self) -> u64 {
        match self {
            WorkerMsg::Progress { id, .. }
            | WorkerMsg::Done { id, .. }
            | WorkerMsg::Compared { id, .. }
            | WorkerMsg::Failed { id, .. }
            | WorkerMsg::Fitting { id, .. }
            | WorkerMsg::SelectRow { id, .. }
            | WorkerMsg::SelectDone { id, .. }
            | WorkerMsg::Exported { id, .. } => *id,
        }
    }
}
