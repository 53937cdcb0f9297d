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
    pub(crate) fn lm(self) -> LmOptions {
        match self {
            Fidelity::Draft => LmOptions {
                ftol: 1e-5,
                xtol: 1e-6,
                max_iterations: 40,
                floor: 0.0,
            },
            Fidelity::Normal => LmOptions {
                ftol: 1e-9,
                xtol: 1e-9,
                max_iterations: 100,
                floor: 0.0,
            },
            Fidelity::Precise => LmOptions {
                ftol: 1e-13,
                xtol: 1e-12,
                max_iterations: 400,
                floor: 0.0,
            },
        }
    }
}
