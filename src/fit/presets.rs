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

    /// The polish's tolerances and iteration limit.
    pub(crate) fn lm(self) -> LmOptions {
        match self {
            Fidelity::Draft => LmOptions {
                ftol: 1e-5,
                xtol: 1e-6,
                max_iterations: 40,
            },
            Fidelity::Normal => LmOptions {
                ftol: 1e-9,
                xtol: 1e-9,
                max_iterations: 100,
            },
            Fidelity::Precise => LmOptions {
                ftol: 1e-13,
                xtol: 1e-12,
                max_iterations: 400,
            },
        }
    }
}
