//! The fit's objective (DESIGN §4, §8) as least squares: `J = |r|^2` with the residuals of a
//! [`Target`] (three per load case), each capped at [`PENALTY`] so a trial model
//! that misses a case (it buckles or snaps where the beam does not) costs a large but finite
//! amount — never NaN, never infinity (argmin's solvers hang on the one and fail on the other).

use std::cell::RefCell;
use std::ops::ControlFlow;

use nalgebra::{DMatrix, DVector};

use crate::cancel::CancelToken;
use crate::eval::Baseline;
use crate::prb::{
    Linearised, PrbMatrix, PrbRow, PrbSolver, SolverLimits, WarmStart, CELLS_PER_ROW,
};

use super::{lm, Parameterisation};

/// A residual of unit weight given to each component of a case the PRB model cannot reach,
/// and the cap on every residual of unit weight: a weighted component's is `PENALTY
/// sqrt(weight)`, so that the cap bounds the same error whatever the weight (an error of
/// `sqrt(n)` L or rad over `n` cases, useless in any model). With unit weights a missed case
/// adds 3 to `J`: far above any usable model (J below 1e-2), yet finite. (A cap that did not
/// grow with the weight flattened every residual of a heavily weighted component, and the
/// polish, seeing no slope, wandered: `angle_weight = 1e6` ended at 1600 times its start.)
pub const PENALTY: f64 = 1.0;

/// Trial models give up on a load path once continuation needs steps below this fraction of
/// it: failing trials stay cheap, and a model this close to failing is useless anyway.
const FIT_MIN_STEP: f64 = 1e-3;

/// Newton iterations a trial model may spend per load case of a path (a healthy model needs
/// about three): beyond, it counts as failing that path, so struggling trials stay cheap.
const FIT_NEWTON_PER_CASE: u32 = 20;

/// Newton iterations per continuation attempt for trial models (quadratic convergence from
/// a secant predictor needs about five).
const FIT_NEWTON_LIMIT: u32 = 12;

/// The limits of trial models, checked when the crate compiles.
const TRIAL_LIMITS: SolverLimits =
    SolverLimits::new(FIT_NEWTON_LIMIT, FIT_NEWTON_PER_CASE, FIT_MIN_STEP);

/// What a fit matches: the residuals of a trial matrix against a truth, a fixed number of
/// them, each capped at [`PENALTY`] (a case the model cannot reach costs [`PENALTY`] per
/// residual), whose sum of squares is the scene's `J`.
pub trait Target {
    /// How many residuals [`Target::residuals`] appends.
    fn len(&self) -> usize;
    /// Whether there are none.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Appends the residuals of `matrix` to `out` (cleared), in a fixed order.
    fn residuals(&self, matrix: &PrbMatrix, out: &mut Vec<f64>) {
        self.residuals_with_cells(matrix, out, None);
    }
    /// As [`Target::residuals`]; with `cells`, also the residuals' exact derivatives with
    /// respect to the matrix's statics cells there (cleared; one row per residual of
    /// [`CELLS_PER_ROW`] columns per matrix row: gamma, k_theta, k_ex; row-major), and
    /// true. False, with `cells` left empty, for a target without them: the polish then
    /// takes differences of the residuals. A capped residual (a missed case, or one past
    /// [`PENALTY`]) has derivative 0, as the cap makes it.
    fn residuals_with_cells(
        &self,
        matrix: &PrbMatrix,
        out: &mut Vec<f64>,
        cells: Option<&mut Vec<f64>>,
    ) -> bool;
    /// Fills `out` (cleared) with the residuals of a model that reaches no case: each its
    /// cap, the weighted [`PENALTY`].
    fn missed_all(&self, out: &mut Vec<f64>);
    /// The `J` at which a target's errors are `fraction` of its accuracy targets: the polish
    /// stops once `J` is this low, where what it could still gain is that small a part of
    /// what the user asked for. 0 (the default): the polish stops on its tolerances alone.
    fn objective_floor(&self, fraction: f64) -> f64 {
        let _ = fraction;
        0.0
    }
    /// Whether the residuals depend on the mus (a dynamic fit, DESIGN §10): the search then
    /// frees them ([`super::Parameterisation::with_masses`]). False (the default): the
    /// statics, which do not see them.
    fn masses(&self) -> bool {
        false
    }
}

/// The single beam's target (DESIGN §4): three residuals per load case,
/// `(da, db, sqrt(w) dphi) / sqrt(n)`.
pub struct CantileverTarget<'a> {
    baseline: &'a Baseline,
    angle_scale: f64,
    case_scale: f64,
    /// `J` of errors exactly at the accuracy targets (0: no floor).
    target_objective: f64,
    /// The last trial model's equilibria, the next one's warm start.
    warm: RefCell<Warm>,
    /// The sensitivities' storage, kept from one evaluation to the next (a trial model of
    /// the same topology reuses it, so an evaluation allocates none).
    scratch: std::cell::Cell<Option<(Linearised, Vec<f64>)>>,
}

/// A trial model near the last one (every finite cell within this relative change) starts
/// each case from the last one's equilibrium of it: a polish's steps are this small but its
/// first few, and a swarm's particles are further apart.
const WARM_CHANGE: f64 = 0.25;

/// The last trial model a target solved, and its equilibria path by path, to warm-start the
/// next one.
#[derive(Debug, Default)]
struct Warm {
    rows: Vec<PrbRow>,
    starts: Vec<WarmStart>,
}

impl Warm {
    /// Whether `matrix` is near enough the last model for its warm start; `matrix` is the
    /// last model from now on.
    fn next(&mut self, matrix: &PrbMatrix) -> bool {
        let rows = matrix.rows();
        let close = |a: f64, b: f64| {
            a == b || (a.is_finite() && b.is_finite() && (a - b).abs() <= WARM_CHANGE * b.abs())
        };
        let near = rows.len() == self.rows.len()
            && rows.iter().zip(&self.rows).all(|(a, b)| {
                close(a.gamma, b.gamma) && close(a.k_theta, b.k_theta) && close(a.k_ex, b.k_ex)
            });
        self.rows.clear();
        self.rows.extend_from_slice(rows);
        near
    }
}

impl<'a> CantileverTarget<'a> {
    /// The target of `baseline` with `J`'s angle weight.
    pub fn new(baseline: &'a Baseline, angle_weight: f64) -> CantileverTarget<'a> {
        CantileverTarget {
            baseline,
            angle_scale: angle_weight.sqrt(),
            case_scale: 1.0 / (baseline.case_count().max(1) as f64).sqrt(),
            target_objective: 0.0,
            warm: RefCell::default(),
            scratch: std::cell::Cell::new(None),
        }
    }

    /// The target whose polish may stop once `J` is a `fraction^2` part of
    /// `target_objective`, the `J` of errors exactly at the scene's accuracy targets
    /// ([`Target::objective_floor`]).
    pub fn with_target_objective(mut self, target_objective: f64) -> CantileverTarget<'a> {
        self.target_objective = target_objective;
        self
    }
}

impl CantileverTarget<'_> {
    /// The caps of a case's three residuals (position, position, angle).
    fn caps(&self) -> [f64; 3] {
        [PENALTY, PENALTY, PENALTY * self.angle_scale]
    }
}

impl Target for CantileverTarget<'_> {
    fn len(&self) -> usize {
        3 * self.baseline.case_count()
    }

    fn missed_all(&self, out: &mut Vec<f64>) {
        out.clear();
        for _ in 0..self.baseline.case_count() {
            out.extend_from_slice(&self.caps());
        }
    }

    fn objective_floor(&self, fraction: f64) -> f64 {
        fraction * fraction * self.target_objective
    }

    /// With `cells`, each followed case's tip sensitivity, scaled as its residuals are.
    fn residuals_with_cells(
        &self,
        matrix: &PrbMatrix,
        out: &mut Vec<f64>,
        mut cells: Option<&mut Vec<f64>>,
    ) -> bool {
        out.clear();
        let width = CELLS_PER_ROW * matrix.rows().len();
        if let Some(c) = cells.as_deref_mut() {
            c.clear();
        }
        let solver = PrbSolver::new(matrix, self.baseline.model.axial_compliance())
            .with_limits(TRIAL_LIMITS);
        // Storage for the sensitivities, only when they are asked for (the swarm's and the
        // plain evaluations' hot path allocates nothing for them).
        let (mut lin, mut sensitivity) = match cells {
            Some(_) => {
                let (lin, mut sensitivity) = self
                    .scratch
                    .take()
                    .filter(|(lin, _)| solver.fits(lin))
                    .unwrap_or_else(|| (solver.linearised(), Vec::new()));
                sensitivity.clear();
                sensitivity.resize(3 * width, 0.0);
                (Some(lin), sensitivity)
            }
            None => (None, Vec::new()),
        };
        // The residuals stay in case order whichever cases are missed (the polish compares
        // residual vectors component by component), so both closures append to one vector.
        let state = RefCell::new((out, cells));
        let scales = [
            self.case_scale,
            self.case_scale,
            self.angle_scale * self.case_scale,
        ];
        let caps = self.caps();
        let mut warm = self.warm.borrow_mut();
        let near = warm.next(matrix);
        let _ = self.baseline.follow_warm(
            &solver,
            Some((&mut warm.starts, near)),
            |b, sol| {
                let raw = [
                    (sol.tip.a - b.tip.a) * scales[0],
                    (sol.tip.b - b.tip.b) * scales[1],
                    (sol.tip.phi - b.tip.phi) * scales[2],
                ];
                let mut state = state.borrow_mut();
                let (out, cells) = &mut *state;
                let known = lin.as_mut().is_some_and(|lin| {
                    sol.work.is_some_and(|work| {
                        solver.tip_sensitivity_converged(sol.q, work, lin, &mut sensitivity)
                    }) || solver.tip_sensitivity(sol.load, sol.q, lin, &mut sensitivity)
                });
                for (k, &r) in raw.iter().enumerate() {
                    let row = known.then(|| &sensitivity[k * width..(k + 1) * width]);
                    let scale = (scales[k], 1.0);
                    push_residual(out, cells.as_deref_mut(), r, row, scale, caps[k], width);
                }
            },
            |missed, _| {
                // The cases this model cannot reach.
                let mut state = state.borrow_mut();
                let (out, cells) = &mut *state;
                for _ in missed {
                    out.extend_from_slice(&caps);
                }
                if let Some(cells) = cells.as_deref_mut() {
                    cells.extend(std::iter::repeat_n(0.0, 3 * width * missed.len()));
                }
                ControlFlow::Continue(())
            },
        );
        if let Some(lin) = lin {
            self.scratch.set(Some((lin, sensitivity)));
        }
        true
    }
}

/// Appends the residual `r` to `out`, capped at `cap` (its component's weighted
/// [`PENALTY`], so that failing to reach a case is never better than reaching it badly), and,
/// with `cells`, its derivative: the row `derivative` (`width` cells) times `scale` over
/// `over` (the residual's own scaling), or zeros where it is unknown or the residual is capped
/// (flat there), as [`Target::residuals_with_cells`] promises.
pub(crate) fn push_residual(
    out: &mut Vec<f64>,
    cells: Option<&mut Vec<f64>>,
    r: f64,
    derivative: Option<&[f64]>,
    (scale, over): (f64, f64),
    cap: f64,
    width: usize,
) {
    out.push(r.clamp(-cap, cap));
    if let Some(cells) = cells {
        match derivative {
            Some(d) if r.abs() < cap => cells.extend(d.iter().map(|v| v * scale / over)),
            _ => cells.extend(std::iter::repeat_n(0.0, width)),
        }
    }
}

/// `J` and its residuals for parameter vectors, counting evaluations.
pub(super) struct Objective<'a> {
    target: &'a dyn Target,
    param: &'a Parameterisation,
    cancel: &'a CancelToken,
    evaluations: std::cell::Cell<u64>,
    /// Scratch: the residuals' derivatives with respect to the matrix's cells.
    cells: RefCell<Vec<f64>>,
}

impl<'a> Objective<'a> {
    pub(super) fn new(
        target: &'a dyn Target,
        param: &'a Parameterisation,
        cancel: &'a CancelToken,
    ) -> Objective<'a> {
        Objective {
            target,
            param,
            cancel,
            evaluations: std::cell::Cell::new(0),
            cells: RefCell::new(Vec::new()),
        }
    }

    pub(super) fn evaluations(&self) -> u64 {
        self.evaluations.get()
    }

    /// Fills `out` with the residuals at `p`; false when cancelled.
    pub(super) fn residuals(&self, p: &DVector<f64>, out: &mut Vec<f64>) -> bool {
        match self.param.decode(p) {
            Some(matrix) => self.matrix_residuals(&matrix, out),
            None => {
                if self.cancel.is_cancelled() {
                    return false;
                }
                self.evaluations.set(self.evaluations.get() + 1);
                self.target.missed_all(out);
                true
            }
        }
    }

    /// As [`Objective::residuals`], with `d r / d p` in `jacobian` when the target gives
    /// its cells' derivatives ([`Target::residuals_with_cells`]): `Some(true)` with both
    /// filled, `Some(false)` with the residuals only (the caller differences them), `None`
    /// when cancelled. A parameter vector no matrix decodes from (not finite) is the flat
    /// penalty: `Some(true)` with a zero Jacobian. A target that fits the mus (a dynamic
    /// fit) is differenced: the cells' derivatives are the statics cells' only.
    pub(super) fn residuals_and_jacobian(
        &self,
        p: &DVector<f64>,
        out: &mut Vec<f64>,
        jacobian: &mut DMatrix<f64>,
    ) -> Option<bool> {
        let Some(matrix) = self.param.decode(p) else {
            // A parameter vector past every cell's range: the penalty, flat.
            if !self.residuals(p, out) {
                return None;
            }
            *jacobian = DMatrix::zeros(out.len(), self.param.len());
            return Some(true);
        };
        self.matrix_and_jacobian(&matrix, p, out, jacobian)
    }

    /// The work of [`Objective::residuals_and_jacobian`] on `matrix`, whose derivatives are
    /// chained through the parameterisation at `p`.
    fn matrix_and_jacobian(
        &self,
        matrix: &PrbMatrix,
        p: &DVector<f64>,
        out: &mut Vec<f64>,
        jacobian: &mut DMatrix<f64>,
    ) -> Option<bool> {
        if self.cancel.is_cancelled() {
            return None;
        }
        self.evaluations.set(self.evaluations.get() + 1);
        if self.target.masses() {
            self.target.residuals(matrix, out);
            return Some(false);
        }
        let mut cells = self.cells.borrow_mut();
        if !self
            .target
            .residuals_with_cells(matrix, out, Some(&mut cells))
        {
            return Some(false);
        }
        self.param.chain_rule(p, &cells, out.len(), jacobian);
        Some(true)
    }

    /// The residuals of `matrix` itself and, where the target gives them, their derivatives
    /// with respect to the parameters at `p`, `matrix`'s encoding (as
    /// [`Objective::residuals_and_jacobian`]); `None` when cancelled. This is the start's
    /// evaluation: `J` of the start, and a polish's first evaluation from `p` where `p`
    /// decodes to the start to rounding (the caller checks: the decoding clamps).
    pub(super) fn matrix_evaluation(
        &self,
        matrix: &PrbMatrix,
        p: &DVector<f64>,
    ) -> Option<lm::Evaluated> {
        let mut residuals = Vec::new();
        let mut jacobian = DMatrix::zeros(0, 0);
        let exact = self.matrix_and_jacobian(matrix, p, &mut residuals, &mut jacobian)?;
        Some(lm::Evaluated {
            residuals,
            jacobian,
            exact,
        })
    }

    /// Fills `out` with the residuals of `matrix`; false when cancelled.
    fn matrix_residuals(&self, matrix: &PrbMatrix, out: &mut Vec<f64>) -> bool {
        if self.cancel.is_cancelled() {
            return false;
        }
        self.evaluations.set(self.evaluations.get() + 1);
        self.target.residuals(matrix, out);
        true
    }

    /// `J` of `matrix`, or `None` when cancelled.
    pub(super) fn matrix_value(&self, matrix: &PrbMatrix) -> Option<f64> {
        let mut r = Vec::new();
        self.matrix_residuals(matrix, &mut r)
            .then(|| r.iter().map(|v| v * v).sum())
    }

    /// `J` at `p`, or `None` when cancelled.
    pub(super) fn value(&self, p: &DVector<f64>) -> Option<f64> {
        let mut r = Vec::new();
        self.residuals(p, &mut r)
            .then(|| r.iter().map(|v| v * v).sum())
    }
}
