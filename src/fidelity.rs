//! Fidelity presets: one knob that trades speed for accuracy across the baseline beam (its
//! integrator tolerance), the load sampling, and the fit's effort. This module holds what the
//! baseline needs (resolution, sampling); the fit's own settings per preset live with the fit
//! (`crate::fit`), so both `eval` and `fit` can use the presets without one reaching into the
//! other.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::beam::Resolution;
use crate::scene::LoadPath;

/// Speed against accuracy, all knobs together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Fidelity {
    /// Coarse baseline, half the load samples, local polish only.
    Draft,
    /// The scene's load samples, a small swarm, a tight polish.
    #[default]
    Normal,
    /// Fine baseline, twice the load samples, a large swarm, the tightest polish.
    Precise,
}

impl Fidelity {
    /// Every preset, fastest first.
    pub const ALL: [Fidelity; 3] = [Fidelity::Draft, Fidelity::Normal, Fidelity::Precise];

    /// Baseline integrator tolerance.
    pub fn resolution(self) -> Resolution {
        Resolution::with_tol(match self {
            Fidelity::Draft => 1e-6,
            Fidelity::Normal => 1e-8,
            Fidelity::Precise => 1e-10,
        })
    }

    /// The load paths as sampled for the fit.
    pub fn sample(self, paths: &[LoadPath]) -> Vec<LoadPath> {
        paths
            .iter()
            .map(|p| LoadPath {
                end: p.end,
                steps: self.steps(p.steps),
            })
            .collect()
    }

    /// A path of `steps` cases as the fit samples it: halved at draft, doubled at precise.
    pub fn steps(self, steps: u32) -> u32 {
        match self {
            Fidelity::Draft => steps.div_ceil(2),
            Fidelity::Normal => steps,
            Fidelity::Precise => steps.saturating_mul(2),
        }
    }

    /// The next preset, cycling (the UI's `v`).
    pub fn next(self) -> Fidelity {
        match self {
            Fidelity::Draft => Fidelity::Normal,
            Fidelity::Normal => Fidelity::Precise,
            Fidelity::Precise => Fidelity::Draft,
        }
    }
}

impl fmt::Display for Fidelity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Fidelity::Draft => "draft",
            Fidelity::Normal => "normal",
            Fidelity::Precise => "precise",
        })
    }
}

impl FromStr for Fidelity {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "draft" => Ok(Fidelity::Draft),
            "normal" => Ok(Fidelity::Normal),
            "precise" => Ok(Fidelity::Precise),
            other => Err(format!(
                "unknown fidelity `{other}` (expected draft, normal or precise)"
            )),
        }
    }
}
