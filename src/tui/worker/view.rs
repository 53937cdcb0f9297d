//! What the charts draw, one type each for every kind of scene: the truth a job's models
//! were judged on ([`TruthView`]) and a model judged on it ([`ModelView`]).
//!
//! Both are the study's one form (DESIGN §7): per path (a cantilever's load path, a
//! mechanism's drive, a measured path) the cases in §8's stage form, the model's as the
//! study judges them ([`Study::judge`]: [`JudgedCase`], truth and model side by side with
//! their errors). Beside it each holds what is drawn of every case, a [`Pose`]: a cantilever
//! is the one-flexure mechanism, so its beam's centre line is a pose of one flexure (from
//! the beam's own solutions, its fast path) and its PRB chain is posed like a mechanism's
//! ([`pose::chains`]). A data scene's truth is its measured cases, with the scene's beam
//! (or beam mechanism) beside them ([`MeasuredView`], built in `worker/truth.rs`).

use crate::mech::figures::{has_reactions, Figures, Frequencies, JudgedCase, UnfollowedPath};
use crate::mech::pose::{self, Pose};
use crate::mech::MechCase;
use crate::prb::PrbMatrix;
use crate::scene::Mechanism;
use crate::study::dynamics::ModeShapePair;
use crate::study::stroke::StrokeLimit;
use crate::study::{CaseForm, EffectsDecision, Study};

/// The truth over a job's paths, as the charts draw it.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthView {
    /// How the cases read: a cantilever's tips, or a mechanism's stage.
    pub form: CaseForm,
    /// The scene as a mechanism (a cantilever's is its one-flexure mechanism), its effects
    /// decided and its paths as sampled (a data scene's are its measured paths).
    pub mechanism: Mechanism,
    /// How the scene's `auto` effects were decided, when they were (a mechanism's flexures
    /// that set their own keep them).
    pub decision: Option<EffectsDecision>,
    /// Per path, the truth's cases: the beam's (or beam mechanism's), or the measured ones.
    pub cases: Vec<Vec<MechCase>>,
    /// Per path, per case, the beam as drawn: the truth's own, or on a data scene the beam
    /// beside the data (no case where it cannot follow the measured paths).
    pub poses: Vec<Vec<Pose>>,
    /// The unloaded scene as drawn.
    pub unloaded: Pose,
    /// A data scene's file and the beam beside the data; `None` when the truth is the beam.
    pub measured: Option<MeasuredView>,
    /// Each path's stroke limit (DESIGN §11), when a flexure has an allowable stress (none
    /// on measured data, which has no stress).
    pub stroke_limits: Option<Vec<StrokeLimit>>,
    /// How long the truth's solves took.
    pub seconds: f64,
}

impl TruthView {
    /// Cases over every path.
    pub fn case_count(&self) -> usize {
        self.cases.iter().map(Vec::len).sum()
    }

    /// Path `path`'s (from 0) stroke limit, a fraction of the path, if it has one.
    pub fn stroke_limit(&self, path: usize) -> Option<f64> {
        self.stroke_limits.as_ref()?.get(path)?.fraction
    }

    /// The largest fibre stress of case `case` of path `path` (both from 0) over its
    /// flexures, where a solved truth gives it: `(flexure from 0, Pa, s / L)`.
    pub fn case_stress(&self, path: usize, case: usize) -> Option<(usize, f64, f64)> {
        let c = self.cases.get(path)?.get(case)?;
        c.flexures
            .iter()
            .zip(&self.mechanism.flexures)
            .enumerate()
            .filter_map(|(i, (f, m))| f.stress.map(|s| (i, s.max * m.beam.youngs_modulus, s.at)))
            .fold(None, |best: Option<(usize, f64, f64)>, x| match best {
                Some(b) if b.1 >= x.1 => Some(b),
                _ => Some(x),
            })
    }

    /// Whether some path prescribes a stage coordinate (its figures then have reaction
    /// errors).
    pub fn prescribes(&self) -> bool {
        has_reactions(&self.mechanism.drives)
    }

    /// On a data scene, the beam's figures against the data as the reports' "beam vs data"
    /// has them (the data in the truth slot, the beam in the model's), with the weights `w`
    /// and `w_f` (taken when drawn: an edit of a weight needs no new solve); or why it has
    /// none. `None` when the truth is the beam.
    pub fn beam_against_data(
        &self,
        angle_weight: f64,
        force_weight: f64,
    ) -> Option<Result<Figures, &str>> {
        let m = self.measured.as_ref()?;
        Some(match &m.beam {
            // Measured data has no flexure tips: the stage is what was measured.
            Ok(cases) => Ok(Figures::from_errors(
                cases
                    .iter()
                    .flatten()
                    .map(|c| [c.pos_err, c.ang_err, c.force_err, c.tip_err]),
                (angle_weight, force_weight),
                self.prescribes(),
                false,
            )),
            Err(why) => Err(why.as_str()),
        })
    }
}

/// A data scene's truth as the charts and the status line show it (DESIGN §9).
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredView {
    /// The data file as the scene names it (sanitized when drawn).
    pub file: String,
    /// SHA-256 of its bytes, lowercase hex.
    pub sha256: String,
    /// Per path, the scene's beam (a cantilever's beam at every measured load, a
    /// mechanism's beam mechanism along the measured drives) judged against the measured
    /// cases, as the reports' "beam vs data" judges it; or why it cannot follow them (no
    /// failure of the job: the data are the truth, the beam is only beside them).
    pub beam: Result<Vec<Vec<JudgedCase>>, String>,
}

/// A PRB model judged on the truth: what the charts and the status line show.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelView {
    /// The matrix judged (in every flexure).
    pub matrix: PrbMatrix,
    /// Its figures (DESIGN §4 and §8).
    pub figures: Figures,
    /// Per path, per case: the model's case against the truth's, with its errors.
    pub cases: Vec<Vec<JudgedCase>>,
    /// Per path, per case, the PRB model as drawn.
    pub poses: Vec<Vec<Pose>>,
    /// The paths the model could not follow to their end (DESIGN §6): its cases there stop
    /// where it stopped, and the figures are over the cases it followed.
    pub unfollowed: Vec<UnfollowedPath>,
    /// Its natural frequencies against the truth's (DESIGN §10), when the scene gives
    /// `[beam] density`.
    pub frequencies: Option<Frequencies>,
    /// The first mode shapes about the unloaded equilibrium, the beam's (beam mechanism's)
    /// and the model's (with a density), for a cantilever or a mechanism alike.
    pub mode_shapes: Vec<ModeShapePair>,
}

impl ModelView {
    /// Cases over every path.
    pub fn case_count(&self) -> usize {
        self.cases.iter().map(Vec::len).sum()
    }

    /// Per path, the model's cases.
    pub fn model_cases(&self) -> Vec<Vec<MechCase>> {
        model_cases(&self.cases)
    }
}

/// Per path, the model side of judged cases.
pub fn model_cases(cases: &[Vec<JudgedCase>]) -> Vec<Vec<MechCase>> {
    cases
        .iter()
        .map(|p| p.iter().map(|c| c.model.clone()).collect())
        .collect()
}

/// Judged cases (path by path, each naming its path from 1) grouped per path, `paths` of
/// them.
pub fn per_path(cases: Vec<JudgedCase>, paths: usize) -> Vec<Vec<JudgedCase>> {
    let mut out: Vec<Vec<JudgedCase>> = vec![Vec::new(); paths];
    for c in cases {
        if let Some(p) = out.get_mut(c.path.wrapping_sub(1)) {
            p.push(c);
        }
    }
    out
}

/// `matrix` judged on `study`'s truth as `eval` judges it ([`Study::judge_followed`], the
/// scene's weights: the cases it can follow, the paths it cannot listed), with its poses. An
/// error only when it follows no case at all.
pub fn model_view(study: &Study, matrix: &PrbMatrix) -> Result<ModelView, String> {
    let judged = study
        .judge_followed(matrix)
        .map_err(|e| format!("the PRB model ({}) cannot follow: {e}", matrix.topology()))?;
    if judged.cases.len() > study.case_count() {
        return Err(format!(
            "internal error: {} PRB cases for {} cases of the truth",
            judged.cases.len(),
            study.case_count()
        ));
    }
    let cases = per_path(judged.cases, study.truth().len());
    let poses = pose::chains(study.mechanism(), matrix, &model_cases(&cases));
    Ok(ModelView {
        matrix: matrix.clone(),
        figures: judged.figures,
        cases,
        poses,
        unfollowed: judged.unfollowed,
        frequencies: judged.frequencies,
        mode_shapes: study.mode_shapes(matrix),
    })
}
