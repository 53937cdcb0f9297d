//! A cantilever scene's load paths (DESIGN §5): proportional paths from zero to an end load,
//! nondimensional, and the rules a path obeys ([`LoadPath::validate`]).

use serde::{Deserialize, Serialize};

use crate::beam::Load;

use super::error::RuleError;
use super::rules;

/// A load path: the end load, reached proportionally from zero and evaluated at
/// `k / steps`, `k = 1..=steps`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// The end load, nondimensional.
    pub end: Load,
    /// Cases along the path (1 to [`MAX_STEPS`](super::MAX_STEPS)).
    pub steps: u32,
}

impl LoadPath {
    /// The load cases along the path.
    pub fn cases(&self) -> impl Iterator<Item = Load> + '_ {
        (1..=self.steps).map(move |k| self.end.scaled(k as f64 / self.steps as f64))
    }

    /// Checks the path's rules: finite components (`alpha_x`, `alpha_y`, `beta`) of at most
    /// [`MAX_NONDIMENSIONAL`](super::MAX_NONDIMENSIONAL), an end
    /// load that is not zero (the path as a whole), `steps` from 1 to
    /// [`MAX_STEPS`](super::MAX_STEPS). A scene puts the keys under `loads[i]`.
    pub fn validate(&self) -> Result<(), RuleError> {
        let check = |key: &str, r: Result<(), String>| r.map_err(|m| RuleError::new(key, m));
        let e = self.end;
        check("alpha_x", rules::reachable(e.alpha_x, e.alpha_x))?;
        check("alpha_y", rules::reachable(e.alpha_y, e.alpha_y))?;
        check("beta", rules::reachable(e.beta, e.beta))?;
        rules::nonzero(&self.end).map_err(RuleError::whole)?;
        rules::steps(i64::from(self.steps)).map_err(|m| RuleError::new("steps", m))?;
        Ok(())
    }
}
