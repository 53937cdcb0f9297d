//! Flexure mechanisms (DESIGN §8): flexures between the ground and one rigid stage, the stage
//! driven (prescribed coordinates) or loaded, solved with the exact beam ([`exact`]) or with a
//! PRB model in place of every flexure ([`prb`]).
//!
//! # Method
//! Both solvers share one formulation ([`solve`]). Every flexure is a cantilever in its own
//! frame ([`geometry`]) whose state is given by three wrench parameters, in its own units,
//! and (a PRB chain) its joint coordinates:
//! - the exact beam ([`exact`]): its tip force `(alpha_x, alpha_y)` and its *root* moment;
//!   the tip follows by one integration from the clamp (an initial-value problem, no folds),
//!   whose variational equations give the tip's exact compliance;
//! - a PRB chain ([`prb`]): its tip force and tip moment, and its joint angles and
//!   extensions `q`, with the joints' equilibrium `K q = J(q)^T w` as extra equations and
//!   the statics' analytic tangent.
//!
//! A coupler (`link`) takes its tension `t` and direction `psi` (global frame, flexure 1's
//! units) in place of the force, so the tip force lies along it. The equations are, per
//! flexure: clamped, the tip pose `(a, b, phi)` is where the stage puts the tip; pinned,
//! `(a, b)` and a zero tip moment; coupled, the tip sits at the coupler's stage end minus
//! `length (cos psi, sin psi)` and the tip moment is zero. The stage's loaded coordinates are
//! the remaining unknowns, balanced by the stage's equilibrium: the load applied at `P`
//! equals the sum of the flexures' tip forces and their moments about `P` (the tip wrench
//! acts on the flexure; its reaction on the stage). For a prescribed coordinate the same sum
//! is the reaction the drive supplies.
//!
//! Newton's method solves the system with its analytic Jacobian: the flexures' blocks from
//! their models, chained with the rigid stage's and the couplers' geometry (checked against
//! differences in `system.rs`'s tests). One iteration costs one integration of each beam, or
//! one linearisation of each chain. The drive path is followed by continuation (the crate's
//! one driver, [`crate::continuation`]; the mechanism's side of it in `path.rs`): the drive's
//! end values are scaled by `lambda`, cases at `k / steps`, sub-steps that halve on failure,
//! each started, for the beam's flexures, from the cubic through the last four accepted
//! points where they are equally spaced (those taken as predicted moved by Newton's step from
//! their own Jacobian), and from the secant elsewhere and for PRB chains, whose evaluations
//! cost little. On a drive of
//! many cases that prediction is the solution to a small fraction of the tolerance, and a
//! case costs one evaluation (`path.rs`).
//!
//! # Honesty
//! - The sign of the Jacobian's determinant is watched along the path: it changes sign only
//!   through a singular Jacobian, i.e. a limit point (snap-through) or a bifurcation of the
//!   mechanism, and the solver stops there with [`MechError::Critical`] rather than follow
//!   the unstable branch or jump. Continuation that stalls next to a nearly singular
//!   Jacobian (a fold it cannot pass at a fixed drive fraction) is reported the same way.
//!   The flexures' own unknowns are root (beam) or joint (chain) quantities, never a given
//!   tip load, so a flexure held by the stage past its own load-controlled buckling load (a
//!   parallel stage's compressed flexure) is regular and changes no sign.
//! - A Jacobian that is singular in the unloaded pose means the drive asks for a motion no
//!   flexure can make to first order (a tip pinned onto a guide through its unloaded tip and
//!   pushed along the inextensible flexure's axis; a 1R model asked to keep its tip angle
//!   while moving sideways; a stage coordinate nothing holds): [`MechError::Immobile`]; or
//!   that the flexures can carry a self-stress, forces balancing each other on the stage
//!   with nothing moving, so the load's division among them is undetermined (three or more
//!   parallel clamped flexures that cannot stretch): [`MechError::Indeterminate`], told apart
//!   by the singular Jacobian's null vector (forces only, or a motion). Stiff but legitimate
//!   stages (the same flexures with their stretch on, at any slenderness) are regular: the
//!   singularity test is a pivot at rounding, not a small one (see `path.rs`).
//!
//! # Accuracy
//! Newton stops when every tip compatibility residual is below the solver's tolerance `tol`
//! (units of each flexure's `L`, radians) and the moment and stage balance rows below
//! `tol (1 + |load|)`. A beam's tip is then as accurate as its shot (the beam's
//! `Resolution::claimed_tip_error`, `10 tol` of the beam; a PRB chain is exact), and the
//! reported wrench reproduces the reported tip by construction: it is the wrench the shape
//! balances (`FlexureCase::load_stable` says whether loading from rest reaches it).

pub mod exact;
pub mod figures;
pub mod geometry;
pub mod measured;
pub mod modes;
mod path;
pub mod pose;
pub mod prb;
pub mod prb_modes;
pub mod sensitivity;
pub mod solve;
mod system;

use serde::Serialize;

use crate::beam::{Load, SolveError, Stress, TipPose};
use crate::prb::PrbError;

/// One flexure in one case of a mechanism.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlexureCase {
    /// Its tip `[a, b, phi]` in its own frame and units.
    pub tip: TipPose,
    /// The wrench on its tip, in its own frame and units (`solve --load` of it gives `tip`
    /// when `load_stable`).
    pub wrench: Load,
    /// Whether the flexure would be stable under its wrench as a *given* (dead) load. A
    /// flexure held by the stage can be stable where the loaded cantilever is not (a
    /// parallel stage's compressed flexure past the cantilever's buckling load
    /// `pi^2 / 4`); its wrench then has other equilibria, and `solve --load`, which follows
    /// the load from zero, finds one of those or none. Past that buckling load even a stable
    /// flexure may sit on a branch that loading from rest does not reach.
    pub load_stable: bool,
    /// Its largest fibre stress and where it is (DESIGN §11): the beam's along its shape, a
    /// PRB model's from its largest joint or root moment; `None` where unknown (a measured
    /// tip has no shape).
    pub stress: Option<Stress>,
}

/// One case of a drive path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechCase {
    /// The drive path's fraction `k / steps`.
    pub fraction: f64,
    /// Stage pose `[dx, dy, dphi]` of `P` (units of flexure 1's `L`; radians).
    pub stage: [f64; 3],
    /// Load on the stage at `P` `[alpha_x, alpha_y, beta]` (flexure 1's units): the given
    /// load for loaded coordinates, the drive's reaction for prescribed ones.
    pub stage_load: [f64; 3],
    /// Per flexure, in order.
    pub flexures: Vec<FlexureCase>,
    /// Newton iterations spent on this case, sub-steps included.
    pub iterations: u32,
    /// Per flexure, its model's internal unknowns: a PRB chain's joint coordinates `q`
    /// (angles, extensions, root first), from which its shape is drawn; empty for the beam,
    /// whose shape follows from its tip wrench.
    #[serde(skip)]
    pub joints: Vec<Vec<f64>>,
    /// The mechanism solver's state at this case (its unknowns and the drive's coordinates
    /// there), from which the case is linearised (its natural frequencies, DESIGN §10);
    /// `None` for a case that no mechanism solver made (a cantilever's, measured data).
    #[serde(skip)]
    pub state: Option<SolvedState>,
}

/// A mechanism solver's state at one case: what [`prb_modes`] linearises.
#[derive(Debug, Clone, PartialEq)]
pub struct SolvedState {
    /// The unknowns (every flexure's wrench parameters and internal unknowns, then the
    /// stage's loaded coordinates).
    pub unknowns: Vec<f64>,
    /// The drive's coordinates at the case.
    pub at: [crate::scene::Coordinate; 3],
}

/// Why a flexure's tip could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TipFailure {
    /// The beam solver's reason.
    #[error(transparent)]
    Beam(#[from] SolveError),
    /// The PRB solver's reason.
    #[error(transparent)]
    Prb(#[from] PrbError),
}

/// "1, 2 and 3": flexure numbers in a sentence.
fn list_flexures(flexures: &[usize]) -> String {
    let names: Vec<String> = flexures.iter().map(usize::to_string).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// Why a mechanism's drive path could not be followed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechError {
    /// Nothing can move the stage the way the drive asks, even a little.
    #[error(
        "the mechanism cannot follow drive {drive} even to first order: its equations are \
         singular in the unloaded pose ({detail}). An inextensible flexure pinned onto a guide \
         through its own tip and pushed along its axis can only move by buckling, a 1R model \
         cannot keep its tip angle while its tip moves, and a stage coordinate nothing holds \
         is undetermined"
    )]
    Immobile {
        /// Which drive path (from 1).
        drive: usize,
        /// The Jacobian's smallest pivot relative to its largest.
        detail: String,
    },
    /// The unloaded stage is statically indeterminate: some flexures can carry forces that
    /// balance each other on the stage without moving anything (a self-stress), so how the
    /// load divides among them is undetermined. Three or more clamped flexures in parallel
    /// do this along their axes when nothing lets them stretch.
    #[error(
        "the mechanism cannot follow drive {drive}: the unloaded stage is statically \
         indeterminate: flexures {} can carry forces that balance each other on the stage \
         without moving it, so how a load divides among them is undetermined (three or more \
         clamped flexures in parallel do this along their axes when none can stretch). Give \
         them axial compliance: the `extension` effect in `[beam] effects` (or the flexures' \
         own tables) for the beam; for a PRB model, chains whose tips can move every way the \
         clamp holds them: two revolute joints at least, and a prismatic one for three or more \
         flexures in parallel (L-R-RP, L-RP-RP-RP)",
        list_flexures(flexures)
    )]
    Indeterminate {
        /// Which drive path (from 1).
        drive: usize,
        /// The flexures (from 1) that carry the self-stress.
        flexures: Vec<usize>,
    },
    /// The mechanism's equilibrium path reaches a limit point or a bifurcation.
    #[error(
        "drive {drive} reaches a critical point at {fraction:.4} of its path (the equilibrium \
         equations turn singular): a snap-through limit point or a buckling bifurcation of the \
         mechanism, past which the path followed from rest ends or is not unique"
    )]
    Critical {
        /// Which drive path (from 1).
        drive: usize,
        /// The last fraction of the path where a regular equilibrium was accepted.
        fraction: f64,
    },
    /// Continuation stalled.
    #[error(
        "no equilibrium of the mechanism found on drive {drive} past {fraction:.4} of its path \
         ({reason})"
    )]
    NoEquilibrium {
        /// Which drive path (from 1).
        drive: usize,
        /// The last fraction of the path where an equilibrium was accepted.
        fraction: f64,
        /// What stopped it.
        reason: String,
    },
    /// The solver's cancel token ([`solve::MechSolver::with_cancel`]) stopped a drive path.
    #[error("cancelled")]
    Cancelled,
    /// A flexure could not be solved at all (its model or resolution is unusable).
    #[error("flexure {flexure}: {source}")]
    Flexure {
        /// Which flexure (from 1).
        flexure: usize,
        /// The tip solver's reason.
        source: TipFailure,
    },
}
