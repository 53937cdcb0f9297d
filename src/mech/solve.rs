//! The mechanism solver for any flexure model (the exact beam or a PRB chain): the flexure
//! models' interface, the solver and its limits. See the parent module for the formulation;
//! the equations and their Jacobian are in `system.rs`; the drive paths it follows
//! ([`MechSolver::solve_path`]: Newton, continuation, critical-point tests) and the cases it
//! reports are in `path.rs`.

use crate::beam::{ShapePoint, Stress, TipPose};
use crate::cancel::CancelToken;

use super::geometry::Geometry;
use super::TipFailure;

/// A flexure whose state is given by three wrench parameters and, for a PRB chain, its
/// joint coordinates: the exact beam (root shot) or a PRB chain (joint coordinates and tip
/// wrench, the chain's equilibrium as extra equations).
pub trait FlexureModel {
    /// How many unknowns besides the three wrench parameters (the chain's joint
    /// coordinates; none for the beam), and as many equations.
    fn internal(&self) -> usize;
    /// The flexure at `(alpha_x, alpha_y, w)` (its own frame and units; `w` is the root
    /// moment of a beam, the tip moment of a chain) and internal unknowns `z`.
    fn eval(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure>;
    /// [`FlexureModel::eval`] where the Jacobian is not needed: the same outputs and
    /// residuals (to the model's integration tolerance), with `jacobian` left empty where
    /// leaving it out saves work (the beam's shot without its variational equations). Newton
    /// checks a last iterate this way. The default is the full evaluation.
    fn eval_values(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        self.eval(w, z)
    }
    /// [`FlexureModel::eval`] that also samples the flexure's shape where the model has
    /// one ([`FlexEval::shape`]): Newton's first evaluation at a case, which is the solution
    /// when the continuation's prediction already meets the tolerance. The default is the
    /// full evaluation.
    fn eval_shaped(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        self.eval(w, z)
    }
    /// Whether an evaluation costs enough (the beam's shots) that the drive's path should
    /// predict each case closely enough to stop at its first evaluation: continuation's
    /// cubic predictor through Newton-refined points, and a prediction whose residual is
    /// within `AS_PREDICTED` (1e-11) taken as the case (`path.rs`). False (the default,
    /// a PRB chain's analytic linearisation): the secant, and Newton's step and check.
    fn predicted(&self) -> bool {
        false
    }
    /// The evaluation of kind `kind`.
    fn eval_as(&self, w: [f64; 3], z: &[f64], kind: Kind) -> Result<FlexEval, TipFailure> {
        match kind {
            Kind::Full => self.eval(w, z),
            Kind::Shaped => self.eval_shaped(w, z),
            Kind::Values => self.eval_values(w, z),
        }
    }
    /// Every flexure of `models` at its `(w, z)` in `at`, in order, evaluated as `kind`
    /// says, up to the first that fails (the caller stops there; a model that evaluates
    /// several at once may return the rest of its batch too). The default evaluates them one
    /// by one; the exact beam shoots two side by side, with the same results.
    fn eval_all(
        models: &[Self],
        at: &[([f64; 3], &[f64])],
        kind: Kind,
    ) -> Vec<Result<FlexEval, TipFailure>>
    where
        Self: Sized,
    {
        let mut out = Vec::with_capacity(models.len());
        for (m, &(w, z)) in models.iter().zip(at) {
            let eval = m.eval_as(w, z, kind);
            let failed = eval.is_err();
            out.push(eval);
            if failed {
                break;
            }
        }
        out
    }
    /// Whether the flexure is stable under its tip wrench as a *given* (dead) load.
    fn load_stable(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> bool;
    /// The continuous quantity whose sign [`FlexureModel::load_stable`] reads, where the
    /// model has one (the beam's `dM(L)/dM(0)`), from an evaluation with its Jacobian: a
    /// drive may then carry the flexure's stability from one case to the next while this
    /// quantity's change, extrapolated from the last two evaluations along the drive, stays
    /// well within itself (`path.rs`, `Chord`). `None` (the default): every case's stability
    /// is its own evaluation's.
    fn stability_indicator(&self, eval: &FlexEval) -> Option<f64> {
        let _ = eval;
        None
    }
    /// Its largest fibre stress in the state `eval` at `(w, z)` (DESIGN §11), `None` where
    /// the model cannot tell.
    fn stress(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> Option<Stress> {
        let _ = (eval, w, z);
        None
    }
    /// For a model made of a PRB matrix's cells: the derivatives of its outputs `(a, b,
    /// phi, tip_moment, internal...)` with respect to those cells at fixed unknowns `(w,
    /// z)`, in `out` (cleared): `4 + k` rows of [`crate::prb::CELLS_PER_ROW`] columns per
    /// matrix row, row-major, and true. False (the default) for a model without cells (the
    /// beam).
    fn cell_derivatives(&self, w: [f64; 3], z: &[f64], out: &mut Vec<f64>) -> bool {
        let _ = (w, z, out);
        false
    }
}

/// What an evaluation of the flexures computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Outputs and Jacobian ([`FlexureModel::eval`]).
    Full,
    /// Outputs, Jacobian and shape ([`FlexureModel::eval_shaped`]).
    Shaped,
    /// Outputs alone where that is cheaper ([`FlexureModel::eval_values`]).
    Values,
}

/// A flexure model evaluated at its unknowns.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexEval {
    /// Its tip (own frame and units).
    pub tip: TipPose,
    /// The moment on its tip (own units).
    pub tip_moment: f64,
    /// The internal equations' residuals.
    pub internal: Vec<f64>,
    /// `d(a, b, phi, tip_moment, internal...) / d(alpha_x, alpha_y, w, z...)`, row-major,
    /// `4 + k` rows of `3 + k` (`k` = [`FlexureModel::internal`]); empty from an
    /// [`FlexureModel::eval_values`] that left it out. At a solved point it is the
    /// evaluation's own or, where Newton checked its last iterate by values alone, the one
    /// at the iterate before (within Newton's last, converged step of it), or, where a beam
    /// mechanism's drive took the case by values alone, an earlier case's (`path.rs`,
    /// `Chord`).
    pub jacobian: Vec<f64>,
    /// The centre line this evaluation shot (own frame and units), where the model samples
    /// one: the exact beam's [`FlexureModel::eval_values`] (Newton's check, which is the
    /// solution when it converges) and [`FlexureModel::eval_shaped`] (Newton's first
    /// evaluation at a case); empty otherwise.
    pub shape: Vec<ShapePoint>,
}

impl Drop for FlexEval {
    /// The shape's storage goes back to a per-thread pool, for the next evaluation's.
    fn drop(&mut self) {
        if self.shape.capacity() > 0 {
            let mut shape = std::mem::take(&mut self.shape);
            shape.clear();
            SHAPES.with_borrow_mut(|pool| {
                if pool.len() < SHAPE_POOL {
                    pool.push(shape);
                }
            });
        }
    }
}

/// The most shapes' storage kept for reuse per thread: a path's evaluations drop theirs as
/// fast as they make them, so a few suffice.
const SHAPE_POOL: usize = 16;

thread_local! {
    /// Storage of dropped evaluations' shapes. A shape (41 points by default, 1.3 KB) is too
    /// big for the allocator's per-thread caches, and each fresh one made it tidy its free
    /// lists first (`malloc_consolidate`: 1.5 % of the parallel stage's solve, in a profile).
    static SHAPES: std::cell::RefCell<Vec<Vec<ShapePoint>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Empty storage for an evaluation's shape: a dropped evaluation's (emptied) where there
/// is one.
pub(crate) fn shape_storage() -> Vec<ShapePoint> {
    SHAPES.with_borrow_mut(Vec::pop).unwrap_or_default()
}

/// The solver of one mechanism with one model per flexure.
#[derive(Debug, Clone)]
pub struct MechSolver<M> {
    pub(super) geometry: Geometry,
    pub(super) models: Vec<M>,
    pub(super) tol: f64,
    /// Where each flexure's unknowns start in the unknown vector.
    pub(super) offsets: Vec<usize>,
    /// Flexure unknowns in all (the stage's loaded coordinates follow).
    pub(super) flexure_unknowns: usize,
    /// Newton iterations at one point before the step is halved.
    pub(super) max_newton: u32,
    /// The smallest continuation step (a fraction of the drive) before giving up.
    pub(super) min_step: f64,
    /// Stops a drive path between its cases ([`MechError::Cancelled`]) once set.
    pub(super) cancel: Option<CancelToken>,
}

/// Newton iterations at one point of the path before the step is halved.
const MAX_NEWTON: u32 = 25;
/// The smallest continuation step before giving up.
const MIN_STEP: f64 = 1e-6;
/// Newton iterations per point for a fit's trial models: a healthy model needs three or
/// four from the secant predictor; one that needs more is about to fail anyway.
const TRIAL_NEWTON: u32 = 12;
/// The smallest continuation step of a fit's trial models: they give up on a drive once
/// they need steps below this fraction of it, so failing trials stay cheap (the
/// cantilever's trials stop at the same fraction).
const TRIAL_MIN_STEP: f64 = 1e-3;

impl<M: FlexureModel> MechSolver<M> {
    /// A solver for `geometry` with one model per flexure; Newton stops at `tol` (units of
    /// each flexure's `L`, radians; loads relative to `1 + |load|`).
    pub fn new(geometry: Geometry, models: Vec<M>, tol: f64) -> MechSolver<M> {
        let mut at = 0;
        let offsets = models
            .iter()
            .map(|m| {
                let o = at;
                at += 3 + m.internal();
                o
            })
            .collect();
        MechSolver {
            geometry,
            models,
            tol,
            offsets,
            flexure_unknowns: at,
            max_newton: MAX_NEWTON,
            min_step: MIN_STEP,
            cancel: None,
        }
    }

    /// The solver whose drive paths stop with [`super::MechError::Cancelled`] soon after `cancel`
    /// is set (checked between the continuation's steps: a case or two of work).
    pub fn with_cancel(mut self, cancel: &CancelToken) -> MechSolver<M> {
        self.cancel = Some(cancel.clone());
        self
    }

    /// The same solver with a fit's trial limits: fewer Newton iterations per point and a
    /// larger smallest step, so a trial model that struggles fails fast (a fit's model that
    /// needs more is useless anyway; the fitted model is judged without these limits).
    pub fn for_trials(mut self) -> MechSolver<M> {
        self.max_newton = TRIAL_NEWTON;
        self.min_step = TRIAL_MIN_STEP;
        self
    }

    /// The geometry solved.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
}
