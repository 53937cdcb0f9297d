//! The baseline beam: a planar geometrically exact (Reissner) cantilever with switchable
//! shear, extension and Poisson effects — the "modified Timoshenko" beam of the paper's §2
//! (DESIGN §2). Everything in prbfit is judged against it.
//!
//! # Method
//! The tip load keeps its direction, so the boundary-value problem reduces to one unknown,
//! the root moment `M(0)`, and one condition, `M(L) = beta` (see the `shoot` module for
//! why). It is solved by shooting with Newton's method, the slope coming from the
//! variational equations integrated alongside the beam. Every load is reached by continuation
//! from the unloaded beam (the crate's one driver, [`crate::continuation`]): the load is
//! scaled by `lambda` from 0 to 1 in steps that halve whenever Newton fails, lands on an
//! unstable equilibrium, or jumps too far, so the solution stays on the branch the physical
//! beam reaches.
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
//! [`CancelToken`](crate::cancel::CancelToken) passed to
//! [`BeamSolver::solve_path_cancellable`] stops a solve within a few dozen integration steps
//! (well under a millisecond).
//!
//! # Finely sampled paths
//! A path of many cases (a designer's 1000-case sweep) costs one shot a case: the predictor
//! is the parabola through the last three accepted points (error `O(dlambda^3)`; the secant
//! where the parabola bends sharply away from it, near a fold), and Newton accepts its first
//! shot's update when the error that update leaves, by the contraction constant measured on
//! the path's earlier cases (times a safety factor of 10), is a tenth of the tolerance. The
//! last update is carried to the tip and to the sampled shape linearly (the shots carry the
//! shape's sensitivities), so no shot is spent only to sample the converged shape. The
//! right-hand side's `sin` and `cos` are inline kernels (`trig.rs`). Measured with
//! `benches/scipy/` (1000 elastica cases: 2 shots a case before, 1 after).
//!
//! # Accuracy
//! [`Resolution::tol`] is the local error tolerance of the integrator, and through it the
//! Newton stopping test. The tip error this buys is measured by `cargo bench --bench beam`
//! and claimed by [`Resolution::claimed_tip_error`]; a property test holds the solver to it.
//! Huge forces keep that promise: `tests/beam_budget.rs` checks them against closed forms up
//! to `alpha = 1e6`, and the bench lists the error up to 1e8.
//!
//! # Files
//! - `load.rs`: the load, the tip pose, the shape's points;
//! - `solver.rs`: [`BeamSolver`], its [`Resolution`] and [`EffortBudget`];
//! - `solve.rs`: solving a load or a load path, with the plate correction case by case;
//! - `solution.rs`: what a solve returns ([`BeamSolution`], [`SolveError`]);
//! - `trig.rs`: `sin` and `cos` of the section angle for the right-hand side;
//! - `path.rs`: the beam as a problem of the continuation driver (predictor, branch and
//!   stability tests, step caps, per-case report) and its first step;
//! - `newton.rs`: multiple-shooting Newton at a fixed load (and how many segments a load
//!   needs) and the Morse-index stability;
//! - `shoot.rs`: what every shot shares (state, right-hand side, settings, samples, meter);
//!   `shot.rs` picks a model's integrator: `dopri.rs` (Dormand-Prince, one shot or two side by
//!   side) or `taylor/` (Taylor series, the plain-bending beam); `band.rs`: the banded linear
//!   solve;
//! - `model.rs`, [`plate`]: the beam's constitutive law and the plate correction;
//! - `stress.rs`: the largest fibre stress along the beam ([`Stress`], DESIGN §11);
//! - [`root`]: the shot from the clamp with the root moment given (for mechanisms).

mod band;
mod dopri;
mod load;
mod model;
pub mod modes;
mod newton;
mod path;
pub mod plate;
pub mod root;
mod shoot;
mod shot;
mod solution;
mod solve;
mod solver;
mod stress;
mod taylor;

pub use load::{Load, ShapePoint, TipPose};
pub use model::{cowper_kappa, BeamModel, Effects, ModelError, MAX_KAPPA, MAX_SLENDERNESS};
pub use solution::{BeamSolution, Convergence, SolveError};
pub use solver::{BeamSolver, EffortBudget, Resolution};
pub use stress::Stress;
pub(crate) use stress::StressScratch;
