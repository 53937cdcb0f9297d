//! Warm-started beam solves, for solvers that call the beam many times at nearby loads (the
//! mechanism's Newton iteration, `crate::mech::exact`).
//!
//! [`BeamSolver::solve_near`] first runs the shooting Newton iteration at the new load
//! starting from a previous equilibrium's nodes: one to three shots when the loads are close,
//! against a whole continuation from the unloaded beam. The answer is accepted only if it
//! is near the previous tip (within the continuation's step limits, so it cannot have hopped
//! to another branch); otherwise the load is solved by continuation from zero, exactly as
//! [`BeamSolver::solve`] does. Accuracy is the same as `solve`'s: the same Newton iteration
//! and stopping test.
//!
//! The beam's own stability test (`dM(L)/dM(0) > 0`) is for a beam under a *given* load.
//! A beam held by a mechanism is partly displacement-controlled, and may be stable where
//! the load-controlled beam is not, so the warm start reports that slope
//! ([`WarmBeam::stability`]) instead of refusing the equilibrium; the mechanism judges its own
//! stability.

use super::{
    first_step, segment_count, BeamSolver, CaseContext, History, Load, SolveError, TipPose,
    MAX_TIP_MOVE, MAX_TIP_TURN, MIN_STEP,
};
use crate::cancel::CancelToken;

/// A converged beam equilibrium that a nearby load can start from.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmBeam {
    /// The load it balances.
    pub load: Load,
    /// Its tip.
    pub tip: TipPose,
    /// `dM(L)/dM(0)`: positive where the beam under this load alone is stable.
    pub stability: f64,
    /// `(psi, M)` at the start of every shooting segment.
    nodes: Vec<[f64; 2]>,
}

impl WarmBeam {
    /// The unloaded beam.
    pub fn unloaded() -> WarmBeam {
        WarmBeam {
            load: Load::default(),
            tip: TipPose::STRAIGHT,
            stability: 1.0,
            nodes: vec![[0.0, 0.0]],
        }
    }
}

impl WarmBeam {
    /// The nodes for `segments` shooting segments: `(psi, M)` interpolated linearly in `s`
    /// between this state's nodes and its tip (`psi(L) = phi`, `M(L) = beta`). The segment
    /// count grows with the force (see `segment_count`), so a nearby load may need more.
    fn resampled(&self, segments: usize) -> Vec<[f64; 2]> {
        let n = self.nodes.len();
        if n == segments {
            return self.nodes.clone();
        }
        let at = |k: usize| {
            if k < n {
                self.nodes[k]
            } else {
                [self.tip.phi, self.load.beta]
            }
        };
        (0..segments)
            .map(|j| {
                let x = j as f64 / segments as f64 * n as f64;
                let k = (x.floor() as usize).min(n - 1);
                let t = x - k as f64;
                let (p, q) = (at(k), at(k + 1));
                [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
            })
            .collect()
    }
}

impl BeamSolver {
    /// The equilibrium under `load`, started from `from` when given (see the module docs).
    pub fn solve_near(&self, load: Load, from: Option<&WarmBeam>) -> Result<WarmBeam, SolveError> {
        if !load.is_finite() {
            return Err(SolveError::NonFiniteLoad(load));
        }
        if load.magnitude() == 0.0 {
            return Ok(WarmBeam::unloaded());
        }
        let cancel = CancelToken::new();
        let segments = segment_count(&self.model, load);
        if let Some(w) = from {
            let mut case = CaseContext::new(self.budget, &self.model, &cancel);
            if let Ok(r) = self.newton(load, w.resampled(segments), &mut case) {
                let moved = (r.tip.a - w.tip.a).hypot(r.tip.b - w.tip.b);
                let turn = (r.tip.phi - w.tip.phi).abs();
                if moved <= 0.5 * MAX_TIP_MOVE && turn <= 0.5 * MAX_TIP_TURN {
                    return Ok(WarmBeam {
                        load,
                        tip: r.tip,
                        stability: r.convergence.stability,
                        nodes: r.nodes,
                    });
                }
            }
        }
        let mut history = History::unloaded(segments);
        let mut case = CaseContext::new(self.budget, &self.model, &cancel);
        let dlam = first_step(&self.model, load, 1.0);
        let min_step = MIN_STEP * (100.0 / load.magnitude()).min(1.0);
        let (solution, _) = self.advance(load, &mut history, 1.0, (dlam, min_step), &mut case)?;
        let nodes = history.last.nodes;
        Ok(WarmBeam {
            load,
            tip: solution.tip,
            stability: solution.convergence.stability,
            nodes,
        })
    }
}
