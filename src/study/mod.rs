//! One problem (DESIGN §7): a scene's truth and everything the front ends ask of it.
//!
//! A [`Study`] holds a scene (its `auto` effects decided) and its truth, whichever kind:
//! - a cantilever's beam solved along its load paths (the beam's fast shooting path),
//! - a mechanism's beam mechanism solved along its drives (§8),
//! - or measured rows, a cantilever's tips or a mechanism's stage (§9).
//!
//! Every kind is held in one form: the scene as a [`Mechanism`] (a cantilever is the
//! one-flexure mechanism of §8, [`truth::one_flexure`]) and, per path, the truth's cases in
//! §8's stage form. On that the study offers what every front end (the CLI, the UI's worker,
//! the Python module) asks, each answer one serialisable report: judge a matrix
//! ([`Study::judge`], one [`Figures`] type whose reaction figures are absent when nothing is
//! prescribed), fit ([`Study::fit`]), select ([`Study::select`]), calibrate
//! ([`calibrate::calibrate`]), decide effects ([`effects::resolve_effects`]) and export
//! ([`Study::export`]), and find each path's stroke limit ([`Study::stroke_limits`]). The layers above never ask which kind of scene they hold; the one
//! place that does is here, where a cantilever keeps its fast paths: the beam's shooting
//! along a load path for the truth, and the chain's own statics for a PRB model (the
//! figures of DESIGN §8's one-flexure mechanism are the cantilever's, which
//! `tests/study.rs` checks on several scenes).
//!
//! # Adding a kind of truth or a per-case output
//! A new kind of truth is a new way to fill [`Study`]'s `truth` cases (and, if it has a
//! faster solver, a new arm in `judge` and in `fit::target`); a new per-case output is a
//! field of [`crate::mech::MechCase`] or of [`JudgedCase`], filled where the cases are made.

pub mod calibrate;
pub mod dynamics;
pub mod effects;
pub mod export;
mod fit;
pub mod modes;
pub mod select;
pub mod stroke;
pub mod tradeoff;
pub mod truth;

use std::cell::{Cell, RefCell};
use std::ops::ControlFlow;
use std::time::Instant;

use crate::beam::{BeamSolver, Resolution, SolveError};
use crate::cancel::CancelToken;
use crate::eval::{Baseline, BaselineError, CaseError, EvalError};
use crate::fidelity::Fidelity;
use crate::mech::{exact, measured, prb, MechCase, MechError};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::{Drive, Mechanism, Scene};

pub use crate::mech::figures::{CompareError, Figures, JudgedCase, Judgement, UnfollowedPath};
pub use effects::{resolve_effects, EffectsDecision, EffectsError};
pub use fit::FitError;
pub use stroke::StrokeLimit;

/// The PRB mechanism's Newton tolerance in every judgement and fit (a cantilever's chain has
/// its own); the truth's own is the study's resolution. 1e-8 is far below any model error.
pub const PRB_TOL: f64 = 1e-8;

/// How finely a study's truth is solved and sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// Every case of the scene, the beam at this resolution (`eval`, `solve`).
    Every(Resolution),
    /// A fit preset's resolution and sampling of the paths (`fit`, `select`, `export`):
    /// a path's steps halved at draft, doubled at precise; measured rows are what they are.
    Fidelity(Fidelity),
}

impl Sampling {
    /// The beam's resolution.
    pub fn resolution(self) -> Resolution {
        match self {
            Sampling::Every(r) => r,
            Sampling::Fidelity(f) => f.resolution(),
        }
    }

    /// A path of `steps` cases as sampled.
    fn steps(self, steps: u32) -> u32 {
        match self {
            Sampling::Every(_) => steps,
            Sampling::Fidelity(f) => f.steps(steps),
        }
    }
}

/// How a study's cases read in reports: a cantilever's as tips under loads (DESIGN §4,
/// `load`, `a`, `b`, `phi`), a mechanism's as stage motions and loads (§8, `stage`,
/// `stage_load`, per flexure `tip` and `wrench`). The same cases, two ways of writing them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseForm {
    /// A plain cantilever: the stage is its tip.
    Tip,
    /// A mechanism scene.
    Stage,
}

/// Why a study's truth could not be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StudyError {
    /// The `auto` effects could not be decided.
    #[error("deciding the beam effects: {0}")]
    Effects(#[from] EffectsError),
    /// The cantilever's beam cannot follow a load path.
    #[error("baseline beam: {0}")]
    Beam(#[from] BaselineError),
    /// The beam mechanism cannot follow a drive.
    #[error("the exact (beam) mechanism: {0}")]
    Mechanism(#[from] MechError),
    /// Cancelled before the truth was complete.
    #[error("cancelled")]
    Cancelled,
    /// The truth's natural frequencies could not be had (DESIGN §10).
    #[error("the truth's natural frequencies: {0}")]
    Modes(#[from] crate::beam::modes::ModesError),
}

/// Why a model could not be judged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum JudgeError {
    /// The PRB cantilever cannot follow a load path.
    #[error(transparent)]
    Cantilever(#[from] EvalError),
    /// The PRB mechanism cannot follow a drive.
    #[error(transparent)]
    Mechanism(#[from] MechError),
    /// The model's cases do not pair with the truth's (a bug if ever seen).
    #[error(transparent)]
    Compare(#[from] CompareError),
}

/// A scene's truth and the scene it belongs to (module docs).
#[derive(Debug, Clone)]
pub struct Study {
    scene: Scene,
    decision: Option<EffectsDecision>,
    mechanism: Mechanism,
    truth: Vec<Vec<MechCase>>,
    /// A cantilever's fast path: its beam solutions (or measured tips) along its load paths.
    beam: Option<Baseline>,
    sampling: Sampling,
    /// The resolution the truth was solved at.
    resolution: Resolution,
    seconds: f64,
    /// The truth's natural frequencies (with `[beam] density`).
    modes: Option<dynamics::TruthModes>,
}

impl Study {
    /// The study of `scene`: its `auto` effects decided (at the default resolution), its
    /// truth solved as `sampling` says.
    pub fn new(scene: &Scene, sampling: Sampling) -> Result<Study, StudyError> {
        Study::solve(scene, sampling, &CancelToken::new(), &mut |_, _, _| {})
    }

    /// As [`Study::new`], stopping with [`StudyError::Cancelled`] soon after `cancel` is
    /// set, and telling `on_path(paths_done, paths, cases_done)` after each path.
    pub fn solve(
        scene: &Scene,
        sampling: Sampling,
        cancel: &CancelToken,
        on_path: &mut dyn FnMut(usize, usize, usize),
    ) -> Result<Study, StudyError> {
        let (resolved, decision) =
            resolve_effects(scene, Resolution::default(), cancel).map_err(|e| {
                if cancel.is_cancelled() {
                    StudyError::Cancelled
                } else {
                    e.into()
                }
            })?;
        Study::decided(resolved, decision, sampling, cancel, on_path)
    }

    /// The study of `scene` taken as given: an `auto` beam is modelled with every effect (as
    /// `BeamSpec::model` takes it), for callers that decide the effects themselves or not at
    /// all.
    pub fn as_given(scene: &Scene, sampling: Sampling) -> Result<Study, StudyError> {
        Study::decided(
            scene.clone(),
            None,
            sampling,
            &CancelToken::new(),
            &mut |_, _, _| {},
        )
    }

    /// The study of a scene whose effects are already decided (`decision` says how, if they
    /// were `auto`).
    pub fn decided(
        scene: Scene,
        decision: Option<EffectsDecision>,
        sampling: Sampling,
        cancel: &CancelToken,
        on_path: &mut dyn FnMut(usize, usize, usize),
    ) -> Result<Study, StudyError> {
        let t0 = Instant::now();
        let resolution = sampling.resolution();
        let mut truth_resolution = resolution;
        let (mechanism, beam, truth) = match &scene.mechanism {
            None => {
                let baseline = match &scene.truth {
                    // Measured data is what it is: no resolution or sampling to choose.
                    Some(data) => Baseline::from_data(scene.beam.model(), data),
                    None => {
                        let paths: Vec<_> = scene
                            .loads
                            .iter()
                            .map(|p| crate::scene::LoadPath {
                                end: p.end,
                                steps: sampling.steps(p.steps),
                            })
                            .collect();
                        let n = paths.len();
                        Baseline::solve(
                            scene.beam.model(),
                            &paths,
                            resolution,
                            cancel,
                            &mut |done, cases| on_path(done, n, cases),
                        )
                        .map_err(|e| cancelled_or(cancel, e))?
                    }
                };
                let mut mechanism = truth::one_flexure(&scene);
                for (d, p) in mechanism.drives.iter_mut().zip(&baseline.paths) {
                    d.steps = p.steps;
                }
                let cases = truth::baseline_cases(&baseline);
                (mechanism, Some(baseline), cases)
            }
            Some(m) => {
                // A mechanism's reactions are its flexures' stiffness times their tips'
                // motion: a truth solved at a preset's coarse tolerance leaves its error in
                // them (at draft's 1e-6, a 1e-3 part of the largest reaction on the
                // slider-crank, more than the fit can then resolve). So a mechanism's truth is
                // solved at the preset's tolerance or the default, whichever is finer.
                let resolution = match sampling {
                    Sampling::Fidelity(_) => {
                        Resolution::with_tol(resolution.tol.min(Resolution::default().tol))
                    }
                    Sampling::Every(r) => r,
                };
                truth_resolution = resolution;
                let mut mechanism = m.clone();
                let cases = if scene.truth.is_some() {
                    measured::truth(&scene, &mechanism, resolution)?
                } else {
                    for d in mechanism.drives.iter_mut().filter(|d| d.rows.is_empty()) {
                        d.steps = sampling.steps(d.steps);
                    }
                    let solver = exact::solver(&mechanism, resolution)?.with_cancel(cancel);
                    let n = mechanism.drives.len();
                    let mut cases = Vec::with_capacity(n);
                    for (i, d) in mechanism.drives.iter().enumerate() {
                        if cancel.is_cancelled() {
                            return Err(StudyError::Cancelled);
                        }
                        cases.push(solver.solve_path(&mechanism.drive_path(d), i + 1).map_err(
                            |e| match e {
                                MechError::Cancelled => StudyError::Cancelled,
                                e => e.into(),
                            },
                        )?);
                        let done = cases.iter().map(Vec::len).sum();
                        on_path(i + 1, n, done);
                    }
                    cases
                };
                (mechanism, None, cases)
            }
        };
        let modes = dynamics::TruthModes::of(&scene, &mechanism).transpose()?;
        Ok(Study {
            modes,
            scene,
            decision,
            mechanism,
            truth,
            beam,
            sampling,
            resolution: truth_resolution,
            seconds: t0.elapsed().as_secs_f64(),
        })
    }

    /// How the study's cases read in reports.
    pub fn case_form(&self) -> CaseForm {
        if self.scene.mechanism.is_some() {
            CaseForm::Stage
        } else {
            CaseForm::Tip
        }
    }

    /// The scene, its effects decided.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// How `auto` effects were decided, when they were.
    pub fn decision(&self) -> Option<&EffectsDecision> {
        self.decision.as_ref()
    }

    /// The scene as a mechanism (a cantilever's is its one-flexure mechanism), its drives
    /// as sampled.
    pub fn mechanism(&self) -> &Mechanism {
        &self.mechanism
    }

    /// The paths (load paths or drives) as sampled.
    pub fn drives(&self) -> &[Drive] {
        &self.mechanism.drives
    }

    /// The truth's cases, path by path, in §8's stage form.
    pub fn truth(&self) -> &[Vec<MechCase>] {
        &self.truth
    }

    /// A cantilever's beam solutions (or measured tips), for what only a beam has: its
    /// deformed shapes. `None` on a mechanism scene.
    pub fn baseline(&self) -> Option<&Baseline> {
        self.beam.as_ref()
    }

    /// Cases in all.
    pub fn case_count(&self) -> usize {
        self.truth.iter().map(Vec::len).sum()
    }

    /// Whether the truth is measured data.
    pub fn is_measured(&self) -> bool {
        self.scene.truth.is_some()
    }

    /// How the truth was solved.
    pub fn sampling(&self) -> Sampling {
        self.sampling
    }

    /// The resolution the truth was solved at (a mechanism's: the sampling's, or the
    /// default when that is finer).
    pub fn resolution(&self) -> Resolution {
        self.resolution
    }

    /// Wall-clock time of the truth's solves.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The weights of `J`: `w` (angle) and `w_f` (force).
    pub fn weights(&self) -> (f64, f64) {
        (self.scene.fit.angle_weight, self.scene.fit.force_weight)
    }

    /// Judges `matrix` (in place of every flexure) against the truth, with the scene's
    /// weights; a model that cannot follow every case is an error (the fit, the selection
    /// and the exports judge whole models).
    pub fn judge(&self, matrix: &PrbMatrix) -> Result<Judgement, JudgeError> {
        self.judge_weighted(matrix, self.scene.fit.angle_weight)
    }

    /// [`Study::judge`] with `w = angle_weight` in `J`.
    pub fn judge_weighted(
        &self,
        matrix: &PrbMatrix,
        angle_weight: f64,
    ) -> Result<Judgement, JudgeError> {
        self.judge_with(matrix, angle_weight, false)
    }

    /// Judges `matrix` over the cases it can follow (DESIGN §6, `eval`): a path it cannot
    /// follow to its end is listed in [`Judgement::unfollowed`] with how far it got and why,
    /// and the figures are over the cases it followed. An error only when it follows no case
    /// at all. Its model cases carry the PRB model's own stress estimate (DESIGN §11,
    /// [`crate::prb::PrbSolver::max_stress`]), which [`Study::judge`] leaves out.
    pub fn judge_followed(&self, matrix: &PrbMatrix) -> Result<Judgement, JudgeError> {
        self.judge_with(matrix, self.scene.fit.angle_weight, true)
    }

    fn judge_with(
        &self,
        matrix: &PrbMatrix,
        angle_weight: f64,
        partial: bool,
    ) -> Result<Judgement, JudgeError> {
        let force_weight = self.scene.fit.force_weight;
        let judgement = match &self.beam {
            Some(baseline) => {
                let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
                let cases = RefCell::new(Vec::with_capacity(self.case_count()));
                let unfollowed = RefCell::new(Vec::new());
                let first_error = RefCell::new(None);
                // The truth's path and case of the next beam solution visited.
                let at = Cell::new((0usize, 0usize));
                let outcome = baseline.follow(
                    &solver,
                    |b, prb| {
                        let (mut path, mut k) = at.get();
                        while k >= self.truth.get(path).map_or(usize::MAX, Vec::len) {
                            path += 1;
                            k = 0;
                        }
                        let e = CaseError::new(prb.load, b.tip, prb.tip);
                        let truth = self.truth[path][k].clone();
                        // The model's own stress estimate, for eval (DESIGN §11).
                        let stress = partial
                            .then(|| solver.max_stress(&baseline.model, prb.load, prb.q))
                            .flatten();
                        let mut model = truth::tip_case(
                            truth.fraction,
                            prb.load,
                            prb.tip,
                            prb.iterations,
                            stress,
                        );
                        model.joints = vec![prb.q.to_vec()];
                        cases.borrow_mut().push(JudgedCase {
                            path: path + 1,
                            fraction: truth.fraction,
                            truth,
                            model,
                            pos_err: e.pos_err,
                            ang_err: e.ang_err,
                            force_err: 0.0,
                            tip_err: 0.0,
                        });
                        at.set((path, k + 1));
                    },
                    |missed, e| {
                        if !partial {
                            return ControlFlow::Break(());
                        }
                        let path = self.truth.get(e.path - 1).map_or(&[][..], Vec::as_slice);
                        let reached = path.len().saturating_sub(missed.len());
                        unfollowed.borrow_mut().push(UnfollowedPath {
                            path: e.path,
                            fraction: reached.checked_sub(1).map_or(0.0, |k| path[k].fraction),
                            reason: e.source.to_string(),
                        });
                        first_error.borrow_mut().get_or_insert_with(|| e.clone());
                        // The next case visited is the next path's first.
                        at.set((e.path, 0));
                        ControlFlow::Continue(())
                    },
                );
                outcome?;
                let cases = cases.into_inner();
                if let (true, Some(e)) = (cases.is_empty(), first_error.into_inner()) {
                    // No case followed: nothing to judge.
                    return Err(e.into());
                }
                Judgement {
                    figures: Figures::from_cases(&cases, angle_weight, force_weight, false, false),
                    reaction_scale: [None; 3],
                    cases,
                    unfollowed: unfollowed.into_inner(),
                    frequencies: None,
                }
            }
            None if partial => {
                let followed =
                    prb::follow(&self.mechanism, matrix, self.prb_tol(), &CancelToken::new());
                let mut judged = crate::mech::figures::compare_followed(
                    &self.mechanism.drives,
                    &followed.drives,
                    &self.truth,
                    angle_weight,
                    force_weight,
                )?;
                let mut first_error = None;
                for (i, failure) in followed.failures.into_iter().enumerate() {
                    if let Some(e) = failure {
                        judged.unfollowed.push(UnfollowedPath {
                            path: i + 1,
                            fraction: followed.drives[i].last().map_or(0.0, |c| c.fraction),
                            reason: e.to_string(),
                        });
                        first_error.get_or_insert(e);
                    }
                }
                if let (true, Some(e)) = (judged.cases.is_empty(), first_error) {
                    // Nothing followed: nothing to judge; the first stop is the answer.
                    return Err(e.into());
                }
                judged
            }
            None => {
                let model = prb::solve(&self.mechanism, matrix, self.prb_tol())?;
                crate::mech::figures::compare(
                    &self.mechanism.drives,
                    &model,
                    &self.truth,
                    angle_weight,
                    force_weight,
                )?
            }
        };
        Ok(self.with_frequencies(judgement, matrix))
    }

    /// `judgement` with `matrix`'s frequencies against the truth's (DESIGN §10): with
    /// `[fit] modes = N`, `max_freq_err` over the first N and
    /// `w_omega mean_i (Omega_PRB,i / Omega_beam,i - 1)^2` added to `J`.
    fn with_frequencies(&self, mut judgement: Judgement, matrix: &PrbMatrix) -> Judgement {
        let Some(f) = self.frequencies(matrix) else {
            return judgement;
        };
        if f.judged > 0 {
            judgement.figures.max_freq_err = Some(f.max_err());
            judgement.figures.objective += self.scene.fit.frequency_weight * f.mean_square();
        }
        judgement.frequencies = Some(f);
        judgement
    }

    /// The PRB mechanism's tolerance: [`PRB_TOL`], or the truth's own when finer.
    fn prb_tol(&self) -> f64 {
        self.resolution.tol.min(PRB_TOL)
    }

    /// The scene's own beam (or beam mechanism) judged against its measured data (DESIGN
    /// §9: how far the ideal beam is from the specimen), at the default resolution; `None`
    /// when the truth is not data.
    pub fn beam_against_data(&self) -> Option<Result<Figures, String>> {
        self.scene.truth.as_ref()?;
        let resolution = Resolution::default();
        Some(match &self.scene.mechanism {
            Some(m) => measured::beam_against_data(&self.scene, m, resolution)
                .map_err(|e| e.to_string())
                .and_then(|e| e.map(|e| e.figures).ok_or_else(|| "no data".to_string())),
            None => crate::eval::beam_against_data(&self.scene, resolution)
                .map_err(|e| e.to_string())
                .and_then(|e| e.map(|e| e.figures).ok_or_else(|| "no data".to_string())),
        })
    }

    /// Checks that `resolution` can solve every flexure (a bad tolerance is bad input).
    pub fn check_resolution(scene: &Scene, resolution: Resolution) -> Result<(), SolveError> {
        let beams: Vec<_> = match &scene.mechanism {
            Some(m) => m.flexures.iter().map(|f| f.beam).collect(),
            None => vec![scene.beam],
        };
        for b in beams {
            BeamSolver::new(b.model(), resolution)?;
        }
        Ok(())
    }
}

/// A baseline error, or [`StudyError::Cancelled`] when `cancel` stopped it.
fn cancelled_or(cancel: &CancelToken, e: BaselineError) -> StudyError {
    if cancel.is_cancelled() {
        StudyError::Cancelled
    } else {
        StudyError::Beam(e)
    }
}
