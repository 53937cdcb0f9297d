//! What each fidelity preset means for the fit: the swarm's size, the random starts, the
//! Levenberg-Marquardt tolerances. (What it means for the baseline — resolution, sampling —
//! is in [`crate::fidelity`].)

use crate::fidelity::Fidelity;

use super::lm::LmOptions;

impl Fidelity {
    /// `(particles, iterations)` of the swarm, if any.
    pub(crate) fn swarm(self) -> Option<(usize, u64)> {
        match self {
            Fidelity::Draft => None,
            Fidelity::Normal => Some((12, 15)),
            Fidelity::Precise => Some((30, 60)),
        }
    }

    /// Random starting points beside the given matrix and the published ones.
    pub(crate) fn random_starts(self) -> usize {
        match self {
            Fidelity::Draft => 0,
            Fidelity::Normal => 2,
            Fidelity::Precise => 6,
        }
    }

    /// `(iterations, polished)` of the polish's scouting round over `candidates` distinct
    /// starts: every candidate gets `iterations` Levenberg-Marquardt iterations, then only
    /// the best `polished` that have not converged yet are polished to the end.
    ///
    /// At draft, with more than one candidate, three iterations show which basin is best and
    /// one full polish follows it: the 20-case 3R fit took 27 evaluations where twelve
    /// iterations and three polishes took 53, to the same `J` (`cargo bench --bench fit`;
    /// 20 since the polish continues from its scout's last evaluation and damps by
    /// Nielsen's rule, [`super::lm`]).
    /// A lone candidate (a polish alone, as a staged dynamic fit's last stage; a topology with
    /// one start) keeps twelve and the full polish that restarts from them, at every
    /// fidelity: one run of the same budget instead stops far from the optimum on a staged
    /// dynamic fit (the ringing flexure's L-RP-RP-RP with two modes: `J` 6.8e-3 where the
    /// restart reaches 2.7e-7; `tests/dynamic_fit.rs`).
    pub(crate) fn scouting(self, candidates: usize) -> (u32, usize) {
        match self {
            Fidelity::Draft if candidates > 1 => (3, 1),
            _ => (12, 3),
        }
    }

    /// The fraction of the accuracy targets below which the polish's progress no longer counts
    /// ([`super::Target::objective_floor`]): a hundredth at draft, a thousandth at normal;
    /// none at precise, which polishes as far as its tolerances go.
    pub(crate) fn floor_fraction(self) -> f64 {
        match self {
            Fidelity::Draft => 1e-2,
            Fidelity::Normal => 1e-3,
            Fidelity::Precise => 0.0,
        }
    }

    /// The polish's tolerances and iteration limit.
    ///
    /// Draft also stops on the model's word ([`LmOptions::gain_tol`] 1e-3, on the exact
    /// Jacobian): once a step has lowered `J` by less than 0.1 % and the Gauss-Newton model
    /// predicts less than 0.1 % more, where `ftol` alone waits for a second small step and
    /// polishes the last few 1e-4 of `J` that draft's half-sampled truth does not resolve
    /// (its fitted `J` is 0.05-27 % above precise's on the example scenes). Over the 14 example scenes' draft fits of `L-R`,
    /// `L-R-R`, `L-R-R-R` and `L-RP-RP-RP` (53 that run; with the start evaluated once,
    /// [`super::search`]) it took 1340 evaluations where 1482 were taken, each fitted model's
    /// `J` on the normal-fidelity truth within -0.07 % and +0.11 % of before, every
    /// targets-met flag the same. `ftol` at 1e-3 instead took 1225, but stopped the
    /// cross-axis pivot's 2R 17.6 % short, where the model still predicted much to gain.
    pub(crate) fn lm(self) -> LmOptions {
        match self {
            Fidelity::Draft => LmOptions {
                ftol: 1e-5,
                xtol: 1e-6,
                gain_tol: 1e-3,
                max_iterations: 40,
                floor: 0.0,
            },
            Fidelity::Normal => LmOptions {
                ftol: 1e-9,
                xtol: 1e-9,
                gain_tol: 0.0,
                max_iterations: 100,
                floor: 0.0,
            },
            Fidelity::Precise => LmOptions {
                ftol: 1e-13,
                xtol: 1e-12,
                gain_tol: 0.0,
                max_iterations: 400,
                floor: 0.0,
            },
        }
    }
}
