//! The baseline beam: a planar geometrically exact (Reissner) cantilever with switchable
//! shear, extension and Poisson effects — the "modified Timoshenko" beam of the paper's §2
//! (DESIGN §2). Everything in prbfit is judged against it.
//!
//! # Method
//! The tip load keeps its direction, so the boundary-value problem reduces to one unknown,
//! the root moment `M(0)`, and one condition, `M(L) = beta` (see the `shoot` module for
//! why). It is solved by shooting with Newton's method, the slope coming from the
//! variational equations integrated alongside the beam. Every load is reached by continuation from the unloaded
//! beam: the load is scaled by `lambda` from 0 to 1 in steps that halve whenever Newton
//! fails, lands on an unstable equilibrium, or jumps too far, so the solution stays on the
//! branch the physical beam reaches.
//!
//! A converged equilibrium is accepted only if it is stable: the response `(dpsi, dM)(s)` to a
//! change of the root moment must keep `dM(s)/dM(0) > 0` along the whole beam (the Morse
//! index theorem; see `chain_stability`), in particular `dM(L)/dM(0) > 0`. That slope is 1 for
//! the unloaded beam and crosses zero exactly where a neighbouring equilibrium appears (a
//! buckling bifurcation or limit point). An exactly axial compression above Euler's load
//! therefore fails with [`SolveError::Unstable`] rather than reporting the straight, unstable
//! shape as an answer, however far above; tilting the load by any amount picks a buckling
//! direction and the solver follows it.
//!
//! # Huge loads
//! Under a force `alpha` perturbations grow like `exp(sqrt(alpha) s)`, and a huge force (1e4,
//! 1e6, 1e8) pulls the beam straight along itself except for boundary layers of length
//! `1 / sqrt(alpha)`. Three things keep such loads cheap:
//! - multiple shooting with about `sqrt(alpha) / 3` segments (up to 4096), so each shot
//!   amplifies errors by about `e^3`, with the banded Newton system solved in linear time;
//! - a first continuation step sized by linear theory, and steps that then double as far as
//!   the tip's motion allows: the shape settles within the first `1e2 / alpha` of the path
//!   and the steps grow geometrically after it, so their number grows like `log(alpha)`
//!   (21 at `alpha_y = 1e6`, 27 at 1e8);
//! - Newton that gives up once its residual stops halving (past a limit point there is no
//!   root to find), so failed steps cost a few shots.
//!
//! The time of a shot still grows like `sqrt(alpha)` (the integrator must resolve the
//! boundary layer), so every load case runs under an [`EffortBudget`]: a solve answers, or
//! fails with a typed reason, within about a second or two of CPU whatever the load. A
//! [`CancelToken`] passed to [`BeamSolver::solve_path_cancellable`] stops a solve within a
//! few dozen integration steps (well under a millisecond).
//!
//! # Accuracy
//! [`Resolution::tol`] is the local error tolerance of the integrator, and through it the
//! Newton stopping test. The tip error this buys is measured by `cargo bench --bench beam`
//! and claimed by [`Resolution::claimed_tip_error`]; a property test holds the solver to it.
//! Huge forces keep that promise: `tests/beam_budget.rs` checks them against closed forms up
//! to `alpha = 1e6`, and the bench lists the error up to 1e8.

mod band;
mod model;
pub mod plate;
pub mod root;
mod shoot;

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::text::bounded;

use crate::cancel::CancelToken;
use band::Band;
pub use model::{cowper_kappa, BeamModel, Effects, ModelError, MAX_SLENDERNESS};
use shoot::{shoot, Meter, Samples, Segment, Shot, ShotFailure, ShotSettings, TipForce};

/// A tip load in the paper's nondimensional form: `alpha_x = Fx L^2 / (E I0)`,
/// `alpha_y = Fy L^2 / (E I0)`, `beta = Mz L / (E I0)`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Load {
    /// Tip force along the clamp's axis (x), `Fx L^2 / (E I0)`; negative compresses the
    /// unloaded beam.
    pub alpha_x: f64,
    /// Tip force across the clamp's axis (y), `Fy L^2 / (E I0)`.
    pub alpha_y: f64,
    /// Tip moment, `Mz L / (E I0)`, counter-clockwise positive; `2 pi` curls the elastica
    /// into a full circle.
    pub beta: f64,
}

impl Load {
    /// The load `(alpha_x, alpha_y, beta)`; the forces keep this direction while the beam
    /// deflects (they are not follower loads).
    pub const fn new(alpha_x: f64, alpha_y: f64, beta: f64) -> Load {
        Load {
            alpha_x,
            alpha_y,
            beta,
        }
    }

    /// The load scaled by `lambda` (a point on a proportional load path).
    pub fn scaled(&self, lambda: f64) -> Load {
        Load::new(
            lambda * self.alpha_x,
            lambda * self.alpha_y,
            lambda * self.beta,
        )
    }

    /// `|alpha_x| + |alpha_y| + |beta|`, the size of the load.
    pub fn magnitude(&self) -> f64 {
        self.alpha_x.abs() + self.alpha_y.abs() + self.beta.abs()
    }

    /// Whether all three components are finite (neither infinite nor NaN); the solver
    /// refuses any other load with [`SolveError::NonFiniteLoad`].
    pub fn is_finite(&self) -> bool {
        self.alpha_x.is_finite() && self.alpha_y.is_finite() && self.beta.is_finite()
    }

    /// Parses `AX,AY,BETA`.
    pub fn parse(text: &str) -> Result<Load, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(format!(
                "expected three numbers AX,AY,BETA, got {} in `{text}`",
                parts.len()
            ));
        }
        let mut v = [0.0; 3];
        for (slot, part) in v.iter_mut().zip(&parts) {
            let x: f64 = part
                .parse()
                .map_err(|_| format!("`{part}` is not a number (in `{text}`)"))?;
            if !x.is_finite() {
                return Err(format!("`{part}` is not a finite number (in `{text}`)"));
            }
            *slot = x;
        }
        Ok(Load::new(v[0], v[1], v[2]))
    }
}

impl fmt::Display for Load {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "alpha_x = {}, alpha_y = {}, beta = {}",
            bounded(self.alpha_x),
            bounded(self.alpha_y),
            bounded(self.beta)
        )
    }
}

/// The tip pose: position in units of L, cross-section angle in radians.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TipPose {
    /// Tip position along the clamp's axis, `x(L) / L` (1 for the unloaded beam).
    pub a: f64,
    /// Tip position across the clamp's axis, `y(L) / L`.
    pub b: f64,
    /// Tip cross-section angle `psi(L)`, radians, counter-clockwise positive: the
    /// orientation of a rigid body bolted to the tip. With shear on it differs from the
    /// slope of the centre line by the shear angle `atan(gamma / (1 + eps))`.
    pub phi: f64,
}

impl TipPose {
    /// The pose of the unloaded beam.
    pub const STRAIGHT: TipPose = TipPose {
        a: 1.0,
        b: 0.0,
        phi: 0.0,
    };

    /// Largest component difference (units of L and radians).
    pub fn max_diff(&self, other: &TipPose) -> f64 {
        (self.a - other.a)
            .abs()
            .max((self.b - other.b).abs())
            .max((self.phi - other.phi).abs())
    }
}

/// A point of the deformed centre line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShapePoint {
    /// Material coordinate, units of L.
    pub s: f64,
    /// Position along the clamp's axis, units of L.
    pub x: f64,
    /// Position across the clamp's axis, units of L.
    pub y: f64,
    /// Cross-section angle, radians.
    pub psi: f64,
}

/// The solver's resolution: the speed/accuracy knob.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Resolution {
    /// Local error tolerance of the integrator (units of L and radians).
    pub tol: f64,
    /// Points of the deformed shape returned with each solution (root and tip included).
    pub shape_points: usize,
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            tol: 1e-9,
            shape_points: 41,
        }
    }
}

impl Resolution {
    /// A resolution with the given tolerance and the default shape sampling.
    pub fn with_tol(tol: f64) -> Resolution {
        Resolution {
            tol,
            ..Resolution::default()
        }
    }

    /// The tip error (units of L, radians) this resolution promises, for loads within the
    /// solver's range. Calibrated by `cargo bench --bench beam` and enforced by
    /// `tests/beam_properties.rs`.
    pub fn claimed_tip_error(&self) -> f64 {
        10.0 * self.tol
    }

    fn validate(&self) -> Result<(), SolveError> {
        if !(self.tol.is_finite() && self.tol >= 1e-14 && self.tol <= 1e-2) {
            return Err(SolveError::BadResolution(format!(
                "tolerance must be in [1e-14, 1e-2], got {}",
                bounded(self.tol)
            )));
        }
        if self.shape_points < 2 || self.shape_points > 100_000 {
            return Err(SolveError::BadResolution(format!(
                "shape points must be in [2, 100000], got {}",
                self.shape_points
            )));
        }
        Ok(())
    }
}

/// How much work the solver may spend on one load case (one [`BeamSolver::solve`], or one
/// case of a path, counted from the previous case) before it gives up with
/// [`SolveError::EffortExceeded`]. Every count includes the attempts that failed.
///
/// The default bounds one case to roughly a second of CPU in a release build, whatever
/// the load (the integration steps dominate; one costs well under a microsecond); loads in
/// the solver's range use a small fraction of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct EffortBudget {
    /// Continuation steps tried (accepted or rejected).
    pub continuation_steps: u32,
    /// Newton shots (each integrates the whole beam once).
    pub shots: u32,
    /// Integration steps tried, over all shots; with the Poisson effect on each counts
    /// twice, as its material law makes a step cost about that much more.
    pub rk_steps: u64,
}

impl Default for EffortBudget {
    fn default() -> Self {
        EffortBudget {
            continuation_steps: 400,
            shots: 4_000,
            rk_steps: 4_000_000,
        }
    }
}

/// The work spent on one load case so far.
#[derive(Debug, Clone, Copy, Default)]
struct Work {
    steps: u32,
    shots: u32,
}

/// How a solve ended. A solve that did not converge is an `Err`, so this records how well
/// the accepted equilibrium is pinned down.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Convergence {
    /// `|M(L) - beta|` at the last shot, before the final linear correction.
    pub residual: f64,
    /// The last Newton update of the root moment.
    pub last_update: f64,
    /// `dM(L)/dM(0)`: positive for a stable equilibrium, zero at a buckling point. It grows
    /// like `exp(sqrt(alpha))` under a force and saturates at `f64::MAX` (from about
    /// `alpha = 5e5`).
    pub stability: f64,
}

/// One equilibrium of the beam.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BeamSolution {
    /// The load this equilibrium carries.
    pub load: Load,
    /// The tip pose under it.
    pub tip: TipPose,
    /// Bending moment at the clamp, units of `E I0 / L`.
    pub root_moment: f64,
    /// The deformed centre line at uniform `s`.
    pub shape: Vec<ShapePoint>,
    /// Newton iterations (shots) spent on this load, continuation sub-steps included.
    pub iterations: u32,
    /// Continuation steps taken to reach this load from the previous one.
    pub continuation_steps: u32,
    /// Integration steps of the final shot.
    pub rk_steps: u32,
    /// How well the equilibrium is pinned down, and how stable it is.
    pub convergence: Convergence,
}

/// Why the beam could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// A component of the requested load is infinite or NaN.
    #[error("load is not finite: {0}")]
    NonFiniteLoad(Load),
    /// [`BeamSolver::new`] was given a tolerance outside `[1e-14, 1e-2]` or a shape sampling
    /// outside `[2, 100000]` points; the text says which.
    #[error("bad resolution: {0}")]
    BadResolution(String),
    /// Continuation could not make progress: its step fell below the smallest allowed
    /// while Newton kept failing (stagnation, a singular Jacobian, a shot that overflowed
    /// or whose step size collapsed) or kept jumping to another branch, with no sign of a
    /// critical point.
    #[error(
        "no equilibrium found for {load}: stuck at {} of the load path ({reason})",
        Fraction(*fraction)
    )]
    NoConvergence {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction `lambda` of `load` reached, i.e. the last accepted equilibrium.
        fraction: f64,
        /// What the last failed attempt ran into.
        reason: String,
    },
    /// The equilibrium followed from zero stops being stable: `dM(s)/dM(0)` reaches zero
    /// somewhere along the beam (a buckling bifurcation, e.g. axial compression past Euler's
    /// load), or continuation is stuck where that slope has collapsed (a snap-through limit
    /// point).
    #[error(
        "the equilibrium path for {load} reaches a critical point at {} of the load \
         (dM(L)/dM(0) -> 0): a snap-through limit point, past which the beam jumps to another \
         shape, or a buckling bifurcation, past which the shape is not unique (for an exactly \
         axial compression, tilt the load slightly to choose the buckling direction)",
        Fraction(*fraction)
    )]
    Unstable {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last stable equilibrium before the critical point.
        fraction: f64,
    },
    /// The constitutive law has no state for the axial force met on the path: with
    /// Poisson's effect a tension past the peak of `eps (1 - nu eps)^2 = N / (E A0)` (the
    /// section necks), or a compression that shortens the centre line to nothing
    /// (`1 + eps <= 0`).
    #[error(
        "the material law fails for {load} at {} of the load path: {reason}",
        Fraction(*fraction)
    )]
    MaterialLimit {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
        /// The axial force and which limit it passed.
        reason: String,
    },
    /// The solve was still following the load path when its [`EffortBudget`] ran out.
    #[error(
        "gave up on {load} at {} of the load path: the effort budget ran out ({steps} \
         continuation steps, {shots} Newton shots, {rk_steps} integration steps for one load \
         case) before the path reached its end; to proceed, solve a smaller load (this \
         fraction of it was reached), loosen the tolerance, or raise the solver's effort \
         budget",
        Fraction(*fraction)
    )]
    EffortExceeded {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
        /// Continuation steps tried on this load case.
        steps: u32,
        /// Newton shots tried on this load case.
        shots: u32,
        /// Integration steps tried on this load case.
        rk_steps: u64,
    },
    /// The caller's [`CancelToken`] was cancelled.
    #[error("solve of {load} cancelled at {} of the load path", Fraction(*fraction))]
    Cancelled {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
    },
}

/// A fraction of a load path, printed with four decimals, or four significant digits when it
/// is below a thousandth (a huge load's critical point can sit at 2.467e-4 of it).
struct Fraction(f64);

impl fmt::Display for Fraction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0 == 0.0 || self.0.abs() >= 1e-3 {
            write!(f, "{:.4}", self.0)
        } else {
            write!(f, "{:.3e}", self.0)
        }
    }
}

/// The accepted state at one point of a load path: `(psi, M)` at the start of every
/// shooting segment.
#[derive(Debug, Clone)]
struct PathPoint {
    lambda: f64,
    nodes: Vec<[f64; 2]>,
    tip: TipPose,
    /// `dM(L)/dM(0)` here.
    stability: f64,
    /// The same, scale-free (see [`Chain::direction`]).
    direction: f64,
}

/// The last two accepted points of a load path (one at its start), all the predictor needs.
/// It always holds a point, the unloaded beam to begin with.
#[derive(Debug, Clone)]
struct History {
    before: Option<PathPoint>,
    last: PathPoint,
}

impl History {
    /// The unloaded beam, shot in `segments` segments: where every path starts.
    fn unloaded(segments: usize) -> History {
        History {
            before: None,
            last: PathPoint {
                lambda: 0.0,
                nodes: vec![[0.0, 0.0]; segments],
                tip: TipPose::STRAIGHT,
                stability: 1.0,
                // (dpsi, dM)(L) = (L, 1) for the unloaded beam.
                direction: std::f64::consts::FRAC_1_SQRT_2,
            },
        }
    }

    /// Accepts `point`, forgetting the oldest one kept.
    fn push(&mut self, point: PathPoint) {
        self.before = Some(std::mem::replace(&mut self.last, point));
    }

    /// The points kept, oldest first.
    fn iter(&self) -> impl Iterator<Item = &PathPoint> {
        self.before.iter().chain(std::iter::once(&self.last))
    }
}

/// The outcome of one Newton solve at a fixed load.
struct NewtonResult {
    nodes: Vec<[f64; 2]>,
    shape: Vec<ShapePoint>,
    tip: TipPose,
    shots: u32,
    rk_steps: u32,
    convergence: Convergence,
    /// The stability of the shape (see [`chain_stability`]).
    chain: Chain,
}

enum NewtonFailure {
    Shot(ShotFailure),
    Diverged(String),
    /// The case's budget of Newton shots ran out.
    OutOfShots,
}

/// One load case in progress: its budget, the work spent on it, and the caller's cancel flag
/// (inside `meter`, which also counts the integration steps).
struct CaseContext<'a> {
    budget: EffortBudget,
    work: Work,
    meter: Meter<'a>,
}

impl<'a> CaseContext<'a> {
    fn new(budget: EffortBudget, model: &BeamModel, cancel: &'a CancelToken) -> CaseContext<'a> {
        CaseContext {
            budget,
            work: Work::default(),
            meter: Meter {
                tries: 0,
                cost: 0,
                // Poisson's law solves an equation for the strain at every evaluation.
                weight: if model.effects.poisson { 2 } else { 1 },
                limit: budget.rk_steps,
                cancel,
            },
        }
    }

    fn exceeded(&self, load: Load, fraction: f64) -> SolveError {
        SolveError::EffortExceeded {
            load,
            fraction,
            steps: self.work.steps,
            shots: self.work.shots,
            rk_steps: self.meter.tries,
        }
    }
}

/// The solver: a validated beam, a resolution, and the most work it may spend on a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSolver {
    /// The beam: slenderness, Poisson's ratio, shear coefficient and effects.
    pub model: BeamModel,
    /// Integrator tolerance and shape sampling.
    pub resolution: Resolution,
    /// The most work one load case may take; [`BeamSolver::new`] sets the default.
    pub budget: EffortBudget,
}

/// Continuation never takes a step that turns the tip by more than this (radians) ...
const MAX_TIP_TURN: f64 = 1.0;
/// ... or moves it by more than this (units of L), so it cannot hop to another branch.
const MAX_TIP_MOVE: f64 = 0.6;
/// ... or, once extension has stretched the beam past 2.4 L, by more than this fraction of
/// the tip's distance from the root: a pull of 1e6 on a stubby beam stretches it 800-fold,
/// and an absolute limit would take thousands of steps along a straight line.
const STRETCHED_MOVE: f64 = 0.25;
/// Newton's correction of the predicted tip may always be this large (units of L, radians).
const MIN_CORRECTION: f64 = 0.15;
/// A continuation stuck where `dM(L)/dM(0)` has fallen below this fraction of its largest
/// value on the path has reached a critical point.
const NEAR_CRITICAL: f64 = 0.01;
/// The same for the slope's direction ([`Chain::direction`]), which falls like the slope near a
/// limit point but is bounded by 1, so a huge load's fold shows in it only close by.
const NEAR_CRITICAL_DIRECTION: f64 = 0.1;
/// The smallest continuation step before the solver gives up, for loads up to 100; a huge
/// load, whose shape changes and critical points sit within the path's first millionths,
/// gets a proportionally finer one, so that those are located as precisely.
const MIN_STEP: f64 = 1e-7;
const MAX_NEWTON: u32 = 30;
/// Newton gives up when its residual has not halved in this many shots.
const STAGNATION_SHOTS: u32 = 8;
/// Shooting segments are short enough that perturbations grow by at most about
/// `exp(SEGMENT_GROWTH)` across one (they grow like `exp(sqrt(|alpha|) s)`).
const SEGMENT_GROWTH: f64 = 3.0;
/// Enough segments for `sqrt(alpha)` up to about 12000 (`alpha` ~ 1.5e8). The banded Newton
/// system makes a segment cost little more than the integration steps it holds.
const MAX_SEGMENTS: usize = 4096;
/// Shape points of the narrow-beam solutions that give a wide section's cases their plate
/// fractions (the moment is averaged along the beam over them).
const PLATE_SHAPE_POINTS: usize = 41;

impl BeamSolver {
    /// A solver for `model` at `resolution`, with the default [`EffortBudget`]; fails with
    /// [`SolveError::BadResolution`] if the resolution is out of range.
    pub fn new(model: BeamModel, resolution: Resolution) -> Result<BeamSolver, SolveError> {
        resolution.validate()?;
        Ok(BeamSolver {
            model,
            resolution,
            budget: EffortBudget::default(),
        })
    }

    /// The same solver with another effort budget.
    pub fn with_budget(self, budget: EffortBudget) -> BeamSolver {
        BeamSolver { budget, ..self }
    }

    /// Solves one load by continuation from the unloaded beam.
    pub fn solve(&self, load: Load) -> Result<BeamSolution, SolveError> {
        self.solve_cancellable(load, &CancelToken::new())
    }

    /// As [`BeamSolver::solve`], stopping with [`SolveError::Cancelled`] soon after `cancel`
    /// is cancelled.
    pub fn solve_cancellable(
        &self,
        load: Load,
        cancel: &CancelToken,
    ) -> Result<BeamSolution, SolveError> {
        if let Some(narrow) = self.plate_refined() {
            let (_, last) = narrow.follow_path(load, 1, cancel)?;
            return self.with_case_plate(&last).solve_cancellable(load, cancel);
        }
        let (_, last) = self.follow_path(load, 1, cancel)?;
        Ok(last)
    }

    /// With plane strain on a section of known width, the narrow-beam solver whose solutions
    /// give each case its plate fraction ([`plate::case_fraction`]); `None` otherwise.
    fn plate_refined(&self) -> Option<BeamSolver> {
        let m = &self.model;
        if !m.effects.plane_strain || m.width_ratio().is_none() {
            return None;
        }
        let narrow = m.narrow();
        Some(BeamSolver {
            model: narrow,
            resolution: Resolution {
                shape_points: self.resolution.shape_points.max(PLATE_SHAPE_POINTS),
                ..self.resolution
            },
            budget: self.budget,
        })
    }

    /// This solver with the plate fraction of the case whose narrow-beam solution is
    /// `narrow`, and no width (so that it solves with that fraction as it is).
    fn with_case_plate(&self, narrow: &BeamSolution) -> BeamSolver {
        let m = &self.model;
        let width_ratio = m.width_ratio().unwrap_or(f64::INFINITY);
        let (phi, _) = plate::case_fraction(width_ratio, m.slenderness, m.nu, narrow);
        let mut model = m.with_plate_fraction(phi);
        model.forget_width();
        BeamSolver { model, ..*self }
    }

    /// Solves the proportional path to `end`, returning the cases at `k / steps`,
    /// `k = 1..=steps` (DESIGN §5). Each case warm-starts from the previous ones.
    pub fn solve_path(&self, end: Load, steps: u32) -> Result<Vec<BeamSolution>, SolveError> {
        self.solve_path_cancellable(end, steps, &CancelToken::new())
    }

    /// As [`BeamSolver::solve_path`], stopping with [`SolveError::Cancelled`] soon after
    /// `cancel` is cancelled: the flag is read before every continuation step and every few
    /// dozen integration steps, i.e. every few microseconds of work.
    pub fn solve_path_cancellable(
        &self,
        end: Load,
        steps: u32,
        cancel: &CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        if let Some(narrow) = self.plate_refined() {
            // Each case at its own plate fraction, solved from the unloaded beam along the
            // same ray (so on the branch the path follows).
            let (mut cases, last) = narrow.follow_path(end, steps, cancel)?;
            cases.push(last);
            return cases
                .iter()
                .map(|c| self.with_case_plate(c).solve_cancellable(c.load, cancel))
                .collect();
        }
        let (mut out, last) = self.follow_path(end, steps, cancel)?;
        out.push(last);
        Ok(out)
    }

    /// The work of [`BeamSolver::solve_path_cancellable`]: the cases before the last, and the
    /// last (at `end` itself) apart, so that a single solve gets its case without a search.
    fn follow_path(
        &self,
        end: Load,
        steps: u32,
        cancel: &CancelToken,
    ) -> Result<(Vec<BeamSolution>, BeamSolution), SolveError> {
        if !end.is_finite() {
            return Err(SolveError::NonFiniteLoad(end));
        }
        let steps = steps.max(1);
        let segments = segment_count(&self.model, end);
        let mut history = History::unloaded(segments);
        let mut earlier = Vec::with_capacity(steps as usize);
        let mut dlam = first_step(&self.model, end, 1.0 / steps as f64);
        let min_step = MIN_STEP * (100.0 / end.magnitude()).min(1.0);
        let mut k = 1;
        loop {
            let target = k as f64 / steps as f64;
            let mut case = CaseContext::new(self.budget, &self.model, cancel);
            let (solution, next_dlam) =
                self.advance(end, &mut history, target, (dlam, min_step), &mut case)?;
            dlam = next_dlam;
            if k == steps {
                return Ok((earlier, solution));
            }
            earlier.push(solution);
            k += 1;
        }
    }

    /// Continues from the last point of `history` to `target`, sub-stepping as needed.
    fn advance(
        &self,
        end: Load,
        history: &mut History,
        target: f64,
        (mut dlam, min_step): (f64, f64),
        case: &mut CaseContext<'_>,
    ) -> Result<(BeamSolution, f64), SolveError> {
        let mut shots = 0u32;
        let mut sub_steps = 0u32;
        let mut peak_stability = history.iter().map(|p| p.stability).fold(1.0, f64::max);
        let mut peak_direction = history.iter().map(|p| p.direction).fold(0.0, f64::max);
        loop {
            let prev = &history.last;
            let (prev_lambda, prev_tip) = (prev.lambda, prev.tip);
            let (prev_stability, prev_direction) = (prev.stability, prev.direction);
            if case.meter.cancel.is_cancelled() {
                return Err(SolveError::Cancelled {
                    load: end,
                    fraction: prev_lambda,
                });
            }
            if case.work.steps >= case.budget.continuation_steps {
                return Err(case.exceeded(end, prev_lambda));
            }
            case.work.steps += 1;
            let lambda = (prev_lambda + dlam).min(target);
            let (guess, predicted_tip) = predict(end, history, lambda);
            let load = end.scaled(lambda);
            let failure = match self.newton(load, guess, case) {
                Ok(result) => {
                    shots += result.shots;
                    let turn = (result.tip.phi - prev_tip.phi).abs();
                    let move_limit =
                        MAX_TIP_MOVE.max(STRETCHED_MOVE * prev_tip.a.hypot(prev_tip.b));
                    let moved = (result.tip.a - prev_tip.a).hypot(result.tip.b - prev_tip.b);
                    // Newton may correct the predictor, but not by much more than the step
                    // itself: a big correction means it found another branch.
                    let correction = result.tip.max_diff(&predicted_tip);
                    let allowed = MIN_CORRECTION + 0.5 * predicted_tip.max_diff(&prev_tip);
                    if result.convergence.stability <= 0.0 || result.chain.focal_point {
                        SolveError::Unstable {
                            load: end,
                            fraction: prev_lambda,
                        }
                    } else if turn > MAX_TIP_TURN || moved > move_limit || correction > allowed {
                        SolveError::NoConvergence {
                            load: end,
                            fraction: prev_lambda,
                            reason: "continuation step too large".into(),
                        }
                    } else {
                        sub_steps += 1;
                        history.push(PathPoint {
                            lambda,
                            nodes: result.nodes.clone(),
                            tip: result.tip,
                            stability: result.convergence.stability,
                            direction: result.chain.direction,
                        });
                        peak_stability = peak_stability.max(result.convergence.stability);
                        peak_direction = peak_direction.max(result.chain.direction);
                        // Double the step, but not past what this step's tip motion says
                        // would break a limit: the tip moves about in proportion to the
                        // step, and a rejected step costs a whole Newton solve. (A huge pull
                        // with extension on stretches the beam by 0.5 L per step; doubling
                        // blindly had every second step rejected.)
                        let taken = lambda - prev_lambda;
                        let mut next = 2.0 * dlam;
                        if turn > 0.0 {
                            next = next.min(0.9 * MAX_TIP_TURN / turn * taken);
                        }
                        if moved > 0.0 {
                            next = next.min(0.9 * move_limit / moved * taken);
                        }
                        // The step just accepted kept within the limits, so the next is at
                        // least 0.9 of it: the step size cannot collapse here.
                        dlam = next.min(1.0);
                        if lambda >= target {
                            // Newton's last update reached the tip linearly but not the
                            // shape sampled on its last shot: one more shot from the updated
                            // nodes samples the shape of the solution returned.
                            let tip_tol = self.resolution.tol * load.magnitude().min(1.0);
                            let result = if result.convergence.last_update > tip_tol {
                                match self.newton(load, result.nodes.clone(), case) {
                                    Ok(again) => {
                                        shots += again.shots;
                                        again
                                    }
                                    Err(_) => result,
                                }
                            } else {
                                result
                            };
                            let solution = BeamSolution {
                                load,
                                tip: result.tip,
                                root_moment: result.nodes[0][1],
                                shape: result.shape,
                                iterations: shots,
                                continuation_steps: sub_steps,
                                rk_steps: result.rk_steps,
                                convergence: result.convergence,
                            };
                            return Ok((solution, dlam));
                        }
                        continue;
                    }
                }
                Err(NewtonFailure::Shot(ShotFailure::Material(limit))) => {
                    SolveError::MaterialLimit {
                        load: end,
                        fraction: prev_lambda,
                        reason: limit.to_string(),
                    }
                }
                Err(NewtonFailure::Shot(ShotFailure::StepBudget)) => SolveError::NoConvergence {
                    load: end,
                    fraction: prev_lambda,
                    reason: "the integrator's step size collapsed".into(),
                },
                Err(NewtonFailure::Shot(ShotFailure::NonFinite)) => SolveError::NoConvergence {
                    load: end,
                    fraction: prev_lambda,
                    reason: "a shot overflowed".into(),
                },
                Err(NewtonFailure::Shot(ShotFailure::Cancelled)) => {
                    return Err(SolveError::Cancelled {
                        load: end,
                        fraction: prev_lambda,
                    })
                }
                Err(NewtonFailure::Shot(ShotFailure::OutOfEffort) | NewtonFailure::OutOfShots) => {
                    return Err(case.exceeded(end, prev_lambda))
                }
                Err(NewtonFailure::Diverged(reason)) => SolveError::NoConvergence {
                    load: end,
                    fraction: prev_lambda,
                    reason,
                },
            };
            // Halve the step actually tried: one clipped at the target would otherwise be
            // retried unchanged until the halving reached below the distance to it.
            dlam = 0.5 * (lambda - prev_lambda);
            // The smallest step is also relative to the load reached, so that a limit point
            // far along a huge load's path costs no more halvings than one at an ordinary load.
            if dlam < min_step.max(MIN_STEP * prev_lambda) {
                // Stuck where the stability slope has collapsed: a limit point, past which
                // the equilibrium followed from zero no longer exists (the beam snaps). Under
                // a huge force the slope carries a factor exp(sqrt(alpha)) that grows along
                // the path and hides its collapse; its direction does not.
                if prev_stability < NEAR_CRITICAL * peak_stability
                    || prev_direction < NEAR_CRITICAL_DIRECTION * peak_direction
                {
                    return Err(SolveError::Unstable {
                        load: end,
                        fraction: prev_lambda,
                    });
                }
                return Err(failure);
            }
        }
    }

    /// Newton's method for multiple shooting at a fixed load.
    ///
    /// The unknowns are the root moment and `(psi, M)` at the start of every later segment;
    /// the equations are continuity of `(psi, M)` between segments and `M(L) = beta`. With one
    /// segment this is plain shooting on the root moment. More segments keep each shot's
    /// sensitivity near `exp(SEGMENT_GROWTH)` where a single shot's would be
    /// `exp(sqrt(alpha))` and Newton's basin would shrink to nothing. An update that makes
    /// the (scaled) residual grow is halved.
    fn newton(
        &self,
        load: Load,
        mut nodes: Vec<[f64; 2]>,
        case: &mut CaseContext<'_>,
    ) -> Result<NewtonResult, NewtonFailure> {
        let force = TipForce {
            alpha_x: load.alpha_x,
            alpha_y: load.alpha_y,
        };
        let settings = self.settings(load);
        let magnitude = load.magnitude();
        let moment_weight = 1.0 / (1.0 + magnitude);
        // The tip must be right to the tolerance, relative to the deflection for tiny loads
        // so that a load of 1e-9 still agrees with linear theory to many digits.
        let tip_tol = self.resolution.tol * magnitude.min(1.0);
        let segments = nodes.len();
        let unknowns = 2 * segments - 1;
        let samples = self.resolution.shape_points;
        let mut shape = Vec::with_capacity(samples);
        let mut ends: Vec<[f64; 12]> = vec![[0.0; 12]; segments];
        // Row 2k (psi continuity) reaches from column 2k - 1 to 2k + 1, row 2k + 1 (moment
        // continuity) from 2k - 1 to 2k + 2: two subdiagonals and one superdiagonal.
        let mut jacobian = Band::new(unknowns, 2, 1);
        let mut residual = vec![0.0; unknowns];
        // The last iterate that improved the residual, and the update taken from it.
        let mut base: Option<(Vec<[f64; 2]>, f64, Vec<f64>)> = None;
        let mut last_measure = f64::INFINITY;
        let (mut best_merit, mut best_shot) = (f64::INFINITY, 0);
        nodes[0][0] = 0.0;
        for shot_no in 1..=MAX_NEWTON {
            if case.work.shots >= case.budget.shots {
                return Err(NewtonFailure::OutOfShots);
            }
            case.work.shots += 1;
            // Shoot every segment; the shape is sampled on every iteration, which is far
            // cheaper than one more pass at the end.
            shape.clear();
            let mut origin = (0.0, 0.0);
            let mut rk_steps = 0;
            for (k, node) in nodes.iter().enumerate() {
                let segment = Segment {
                    s_start: k as f64 / segments as f64,
                    s_end: (k + 1) as f64 / segments as f64,
                    psi: node[0],
                    moment: node[1],
                    origin,
                };
                let sampling = Samples {
                    points: &mut shape,
                    count: samples,
                };
                // The first segment starts at the clamp, where psi = 0 is no unknown.
                let meter = &mut case.meter;
                let shot = if k == 0 {
                    shoot::<8>(&self.model, force, segment, settings, Some(sampling), meter)
                } else {
                    shoot::<12>(&self.model, force, segment, settings, Some(sampling), meter)
                };
                let Shot { end, steps } = shot.map_err(NewtonFailure::Shot)?;
                origin = (origin.0 + end[2], origin.1 + end[3]);
                ends[k] = end;
                rk_steps += steps;
            }
            let last = &ends[segments - 1];

            // Residual and Jacobian. Column of psi_k is 2k - 1 (k >= 1), of M_k is 2k.
            jacobian.clear();
            for k in 0..segments {
                let e = &ends[k];
                let (row_psi, row_m) = (2 * k, 2 * k + 1);
                let rows: &[(usize, usize, usize)] = if k + 1 < segments {
                    residual[row_psi] = e[0] - nodes[k + 1][0];
                    residual[row_m] = e[1] - nodes[k + 1][1];
                    jacobian.set(row_psi, 2 * k + 1, -1.0);
                    jacobian.set(row_m, 2 * k + 2, -1.0);
                    &[(row_psi, 8, 4), (row_m, 9, 5)]
                } else {
                    residual[row_psi] = e[1] - load.beta;
                    &[(row_psi, 9, 5)]
                };
                for &(row, d_psi, d_m) in rows {
                    if k > 0 {
                        jacobian.set(row, 2 * k - 1, e[d_psi]);
                    }
                    jacobian.set(row, 2 * k, e[d_m]);
                }
            }
            let merit = residual
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    if i % 2 == 1 || i == unknowns - 1 {
                        r * moment_weight
                    } else {
                        *r
                    }
                })
                .fold(0.0_f64, |acc, r| acc.max(r.abs()));

            // Past a limit point there is no root, only a minimum of the residual, where
            // damped Newton cycles for ever: give up once the residual stops halving, and let
            // the continuation halve its step instead.
            if merit < 0.5 * best_merit {
                best_merit = merit;
                best_shot = shot_no;
            } else if shot_no - best_shot >= STAGNATION_SHOTS {
                return Err(NewtonFailure::Diverged(format!(
                    "Newton stagnated: the residual did not halve in {STAGNATION_SHOTS} shots"
                )));
            }
            if let Some((base_nodes, base_merit, update)) = &base {
                let noise_level = last_measure <= 10.0 * tip_tol;
                if merit > *base_merit && !noise_level {
                    let half: Vec<f64> = update.iter().map(|u| 0.5 * u).collect();
                    nodes = apply(base_nodes, &half);
                    base = Some((base_nodes.clone(), *base_merit, half));
                    last_measure *= 0.5;
                    continue;
                }
            }

            let mut update: Vec<f64> = residual.iter().map(|r| -r).collect();
            debug_assert_eq!(jacobian.size(), unknowns);
            if !jacobian.solve(&mut update) {
                return Err(NewtonFailure::Diverged("singular shooting Jacobian".into()));
            }

            // How far the update moves the tip (by the linearisation) and the nodes.
            let mut delta = TipPose {
                a: 0.0,
                b: 0.0,
                phi: 0.0,
            };
            let mut node_change = 0.0_f64;
            for (k, e) in ends.iter().enumerate() {
                let d_psi = if k > 0 { update[2 * k - 1] } else { 0.0 };
                let d_m = update[2 * k];
                delta.a += e[10] * d_psi + e[6] * d_m;
                delta.b += e[11] * d_psi + e[7] * d_m;
                if k + 1 == segments {
                    delta.phi = e[8] * d_psi + e[4] * d_m;
                }
                node_change = node_change.max(d_psi.abs()).max(d_m.abs() * moment_weight);
            }
            let measure = delta.max_diff(&TipPose::default()).max(node_change);
            if !measure.is_finite() {
                return Err(NewtonFailure::Diverged(
                    "the Newton update is not finite".into(),
                ));
            }
            // Stop when the update moves the tip and nodes by less than the tolerance; or
            // when Newton's quadratic convergence (contraction C = measure / last^2) says the
            // error left after applying this update, C measure^2, is well below it; or when
            // the integrator's noise keeps the updates from shrinking any further.
            // The contraction is only trusted once both updates are small (the asymptotic
            // regime), and never below 1: after a long damped step it would be estimated far
            // too small and accept an update that is not yet converged.
            let contracting = measure < 0.5 * last_measure;
            let contraction = (measure / (last_measure * last_measure)).max(1.0);
            let left_after = measure * measure * contraction;
            let quadratic = contracting
                && last_measure <= 1e-2
                && measure <= 1e-3
                && left_after <= 0.1 * tip_tol;
            let stalled = !contracting && measure <= 100.0 * self.resolution.tol;
            if measure <= tip_tol || quadratic || stalled {
                // Apply the last update linearly: free, and it removes the Newton error.
                let tip = TipPose {
                    a: origin.0 + delta.a,
                    b: origin.1 + delta.b,
                    phi: last[0] + delta.phi,
                };
                let chain = chain_stability(&ends);
                return Ok(NewtonResult {
                    nodes: apply(&nodes, &update),
                    shape,
                    tip,
                    shots: shot_no,
                    rk_steps,
                    convergence: Convergence {
                        residual: merit,
                        last_update: measure,
                        stability: chain.slope,
                    },
                    chain,
                });
            }
            // Damp wild updates: angles beyond a radian or moments beyond what the load can
            // produce mean the linearisation is useless here.
            let biggest = update
                .iter()
                .enumerate()
                .map(|(i, u)| {
                    if i % 2 == 0 {
                        u.abs() / (2.0 * (magnitude + 1.0))
                    } else {
                        u.abs()
                    }
                })
                .fold(0.0_f64, f64::max);
            if biggest > 1.0 {
                update.iter_mut().for_each(|u| *u /= biggest);
            }
            let next = apply(&nodes, &update);
            base = Some((std::mem::replace(&mut nodes, next), merit, update));
            last_measure = measure;
        }
        Err(NewtonFailure::Diverged(format!(
            "Newton did not converge in {MAX_NEWTON} iterations"
        )))
    }

    fn settings(&self, load: Load) -> ShotSettings {
        let magnitude = load.magnitude();
        ShotSettings {
            tol: self.resolution.tol,
            // A slope good to 1e-5 still gains five digits per Newton step.
            variational_tol: (self.resolution.tol * 1e3).clamp(1e-7, 1e-5),
            moment_scale: magnitude,
            h0: 0.1 / (1.0 + magnitude.sqrt()),
            max_steps: 200_000,
        }
    }
}

/// How many shooting segments a load path needs (see [`SEGMENT_GROWTH`]).
///
/// Near a straight stretch under a tension `F` perturbations of `psi` obey
/// `psi'' = (1 + eps) F psi / (E I / E I0)`, so they grow at the rate
/// `sqrt(F (1 + eps) / p^4)` (the stretch lengthens the lever, Poisson's shrink softens the
/// section); under a compression they oscillate at up to `sqrt(F (1 + c_s F))`. The largest
/// force on a proportional path is at its end. Past [`MAX_SEGMENTS`] (`alpha` beyond about
/// 1.5e8) segments amplify more and Newton's basin shrinks; such loads usually end in the
/// effort budget.
fn segment_count(model: &BeamModel, end: Load) -> usize {
    let force = end.alpha_x.hypot(end.alpha_y);
    let tension = match model.axial_strain(force) {
        Ok((eps, _, p)) => (1.0 + eps.max(0.0)) * model.plate_compliance() / p.powi(4),
        // A force the material cannot carry fails on the path anyway.
        Err(_) => 1.0,
    };
    // Under compression the same perturbations oscillate instead, at the rate
    // `sqrt(F (1 + c_s F))`: shear adds `gamma N` to `dM/ds`. Segments must also hold that
    // oscillation to less than half a period (see `chain_stability`).
    let compression = if model.effects.shear {
        1.0 + model.shear_compliance() * force
    } else {
        1.0
    };
    let softening = tension.max(compression);
    let rate = (force * softening).sqrt();
    let wanted = (rate / SEGMENT_GROWTH).ceil();
    if wanted.is_finite() {
        (wanted as usize).clamp(1, MAX_SEGMENTS)
    } else {
        MAX_SEGMENTS
    }
}

/// The first continuation step from the unloaded beam: `wanted`, shortened so that linear
/// theory (tip turn `alpha_y / 2 + beta`, deflection `alpha_y / 3 + beta / 2`, stretch
/// `c_e alpha_x`) keeps it inside the step limits. Linear theory overestimates a large load's
/// deflection, so this never asks too much; without it a huge load would start by halving the
/// whole path down to its first few thousandths, each halving a failed Newton solve far from
/// any equilibrium (99% of the work of an `alpha_y = 1e4` solve).
fn first_step(model: &BeamModel, end: Load, wanted: f64) -> f64 {
    let turn = 0.5 * end.alpha_y.abs() + end.beta.abs();
    let stretch = if model.effects.extension {
        model.axial_compliance() * end.alpha_x.abs()
    } else {
        0.0
    };
    let moved = end.alpha_y.abs() / 3.0 + 0.5 * end.beta.abs() + stretch;
    // A margin below the limits, so that round-off cannot put the step just past one.
    let mut step = wanted;
    if turn * step > 0.9 * MAX_TIP_TURN {
        step = 0.9 * MAX_TIP_TURN / turn;
    }
    if moved * step > 0.9 * MAX_TIP_MOVE {
        step = 0.9 * MAX_TIP_MOVE / moved;
    }
    step
}

/// The response `(dpsi, dM)` of the beam to a change of its root moment, as far as the
/// stability tests need it.
#[derive(Debug, Clone, Copy)]
struct Chain {
    /// `dM(L)/dM(0)`, saturating at `f64::MAX`.
    slope: f64,
    /// `dM(L) / |(dpsi(L), dM(L))|`: the slope's sign without the factor
    /// `exp(sqrt(alpha))` a huge force puts in front of it. Near a limit point it falls like
    /// the slope; far from one it is of order 1 at any load, where the slope can be 1e300.
    direction: f64,
    /// `dM(s)/dM(0)` is already non-positive at the end of an inner segment.
    focal_point: bool,
}

/// `dM(L)/dM(0)` through the chain of segments, and whether `dM(s)/dM(0)` is already
/// non-positive at the end of an inner segment.
///
/// `(dpsi, dM)(s)`, the response to a change of the root moment, is the Jacobi field of the
/// beam's energy with the clamp's `dpsi(0) = 0`; `dM(s) = 0` is the free end's natural
/// boundary condition at `s`. By the Morse index theorem the equilibrium is stable (no
/// neighbouring shape of lower energy) exactly when `dM(s) > 0` on all of `(0, L]`, not only
/// at the tip: under a compression well past Euler's load `dM(L)` returns to positive values
/// (for an axial load it is `cos(sqrt(alpha) s)`), and one long continuation step could land
/// there with no sign change seen at the tip. A segment spans at most about
/// [`SEGMENT_GROWTH`] `< pi` of that oscillation's phase, so no zero can hide inside one.
///
/// At huge loads the product grows like `exp(sqrt(alpha))`, past the range of a double, so
/// it is rescaled as it goes and a stable equilibrium too stiff to represent saturates at
/// `f64::MAX`.
fn chain_stability(ends: &[[f64; 12]]) -> Chain {
    let mut v = [0.0, 1.0];
    let mut log_scale = 0.0;
    let mut focal_point = false;
    for (k, e) in ends.iter().enumerate() {
        v = [e[8] * v[0] + e[4] * v[1], e[9] * v[0] + e[5] * v[1]];
        if k + 1 < ends.len() && v[1] <= 0.0 {
            focal_point = true;
        }
        let big = v[0].abs().max(v[1].abs());
        // Rescaling only past 1e100 leaves every ordinary load's value untouched.
        if big > 1e100 && big.is_finite() {
            v = [v[0] / big, v[1] / big];
            log_scale += big.ln();
        }
    }
    let norm = v[0].hypot(v[1]);
    let direction = if norm > 0.0 { v[1] / norm } else { 0.0 };
    let slope = if log_scale == 0.0 || v[1] == 0.0 {
        v[1]
    } else {
        let magnitude = v[1].abs().ln() + log_scale;
        if magnitude >= f64::MAX.ln() {
            f64::MAX.copysign(v[1])
        } else {
            magnitude.exp().copysign(v[1])
        }
    };
    Chain {
        slope,
        direction,
        focal_point,
    }
}

/// `nodes` moved by a Newton update laid out as the unknowns (`M_0, psi_1, M_1, ...`).
fn apply(nodes: &[[f64; 2]], update: &[f64]) -> Vec<[f64; 2]> {
    nodes
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let d_psi = if k > 0 { update[2 * k - 1] } else { 0.0 };
            [n[0] + d_psi, n[1] + update[2 * k]]
        })
        .collect()
}

/// Predicts the nodes and the tip at `lambda` from the path so far: the linear-theory
/// tangent at the start (`M(s) = beta + alpha_y (1 - s)`, `psi` its integral, the tip
/// moving by the Euler-Bernoulli compliance), then secant extrapolation.
fn predict(end: Load, history: &History, lambda: f64) -> (Vec<[f64; 2]>, TipPose) {
    match history {
        History {
            before: None,
            last: p,
        } => {
            let segments = p.nodes.len();
            let dl = lambda - p.lambda;
            let nodes = (0..segments)
                .map(|k| {
                    let s = k as f64 / segments as f64;
                    let m = end.beta + end.alpha_y * (1.0 - s);
                    let psi = end.beta * s + end.alpha_y * (s - 0.5 * s * s);
                    [p.nodes[k][0] + dl * psi, p.nodes[k][1] + dl * m]
                })
                .collect();
            let tip = TipPose {
                a: p.tip.a,
                b: p.tip.b + dl * (end.alpha_y / 3.0 + end.beta / 2.0),
                phi: p.tip.phi + dl * (end.alpha_y / 2.0 + end.beta),
            };
            (nodes, tip)
        }
        History {
            before: Some(p0),
            last: p1,
        } => {
            let t = (lambda - p1.lambda) / (p1.lambda - p0.lambda);
            let nodes = p1
                .nodes
                .iter()
                .zip(&p0.nodes)
                .map(|(n1, n0)| [n1[0] + t * (n1[0] - n0[0]), n1[1] + t * (n1[1] - n0[1])])
                .collect();
            let tip = TipPose {
                a: p1.tip.a + t * (p1.tip.a - p0.tip.a),
                b: p1.tip.b + t * (p1.tip.b - p0.tip.b),
                phi: p1.tip.phi + t * (p1.tip.phi - p0.tip.phi),
            };
            (nodes, tip)
        }
    }
}
