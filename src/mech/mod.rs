//! Flexure mechanisms (DESIGN §8): flexures between the ground and one rigid stage, the stage
//! driven (prescribed coordinates) or loaded, solved with the exact beam ([`exact`]) or with a
//! PRB model in place of every flexure ([`prb`]).
//!
//! # Method
//! Both solvers share one formulation ([`solve`]). Every flexure is a cantilever in its own
//! frame ([`geometry`]) under an unknown tip wrench, written in its own units:
//! - clamped tip: `(alpha_x, alpha_y, beta)`; compatibility: the tip pose `(a, b, phi)` is
//!   where the stage puts the tip (3 equations);
//! - pinned tip: `(alpha_x, alpha_y)`, `beta = 0`; compatibility of `(a, b)` (2 equations);
//! - coupler (`link`): the coupler's tension `t` and direction `psi` (global frame, flexure 1's
//!   units), so the tip force is `t (cos psi, sin psi)`, `beta = 0`; compatibility: the tip sits
//!   at the coupler's stage end minus `length (cos psi, sin psi)` (2 equations).
//!
//! The stage's loaded coordinates are the remaining unknowns, balanced by the stage's
//! equilibrium: the load applied at `P` equals the sum of the flexures' tip forces and their
//! moments about `P` (the tip wrench acts on the flexure; its reaction on the stage). For a
//! prescribed coordinate the same sum is the reaction the drive supplies.
//!
//! Newton's method solves the system; its Jacobian is by finite differences: each flexure
//! unknown is perturbed by `1e-6 (1 + |x|)` and only that flexure is re-solved (warm-started
//! from its current equilibrium), the stage unknowns need no flexure solve. One Newton
//! iteration therefore costs `1 + n_i` tip solves per flexure (`n_i` its unknowns, 2 or 3).
//! The drive path is followed by continuation: the drive's end values are scaled by
//! `lambda`, cases at `k / steps`, sub-steps that halve on failure, each started from a
//! secant prediction of the last two accepted points.
//!
//! # Honesty
//! - The sign of the Jacobian's determinant is watched along the path: it changes sign only
//!   through a singular Jacobian, i.e. a limit point (snap-through) or a bifurcation of the
//!   mechanism, and the solver stops there with [`MechError::Critical`] rather than follow
//!   the unstable branch or jump.
//! - A Jacobian that is singular in the unloaded pose means the drive asks for a motion no
//!   flexure can make to first order (a tip pinned onto a guide through its unloaded tip and
//!   pushed along the inextensible flexure's axis; a 1R model asked to keep its tip angle
//!   while moving sideways; a stage coordinate nothing holds): [`MechError::Immobile`].
//!
//! # Known limitation: flexures past their own load-controlled limit
//! The unknowns are tip wrenches, so each flexure is solved as a *load-controlled*
//! cantilever. Where that cantilever has a limit point (a parallel stage's compressed
//! flexure under an axial force past the cantilever's buckling load `pi^2 / 4`, with a
//! transverse force), its tip is a folded function of its wrench, the mechanism's Jacobian
//! passes through infinity (the determinant's sign test corrects for that, see
//! [`solve::TipModel::load_stability`]) and Newton may stall near the fold although the
//! mechanism is regular there: the parallel stage with Su's 3R stops with
//! [`MechError::NoEquilibrium`] near `Ay = 3.3`, where the exact one carries on. The cure is
//! to take each flexure's root moment (beam) or joint coordinates (PRB) as its unknowns
//! instead of its tip moment: the map from the root to the tip is an initial-value problem
//! with no folds. That is the next step.
//!
//! # Accuracy
//! Newton stops when every tip compatibility residual is below the solver's tolerance `tol`
//! (units of each flexure's `L`, radians) and the stage balance below `tol (1 + |load|)`.
//! A flexure's tip is then as accurate as its tip solver (the beam's
//! `Resolution::claimed_tip_error`, `10 tol` of the beam; the PRB chain to 1e-13), and the
//! reported wrench reproduces the reported tip by construction: it is the wrench the tip was
//! solved under.

pub mod exact;
pub mod figures;
pub mod geometry;
pub mod prb;
pub mod solve;

use serde::Serialize;

use crate::beam::{Load, SolveError, TipPose};
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
    /// A flexure could not be solved at all (its model or resolution is unusable).
    #[error("flexure {flexure}: {source}")]
    Flexure {
        /// Which flexure (from 1).
        flexure: usize,
        /// The tip solver's reason.
        source: TipFailure,
    },
}
