//! A mechanism's drive paths (DESIGN §8): each stage coordinate prescribed (a displacement
//! or rotation the drive imposes) or loaded (a force or moment), varied proportionally from
//! the unloaded state or, on a data scene (DESIGN §9), through a measured path's rows; the
//! rules a drive obeys ([`Drive::validate`]); and the nondimensional [`DrivePath`] the
//! solvers follow.

use serde::{Deserialize, Serialize};

use super::error::RuleError;
use super::rules;

/// The names of the stage coordinates as the scene file writes them: displacement, load.
pub const COORDINATE_KEYS: [(&str, &str); 3] = [("dx", "fx"), ("dy", "fy"), ("dphi", "mz")];

/// A stage coordinate along a drive path: prescribed (a displacement or rotation the drive
/// imposes; the output is the reaction) or loaded (a force or moment; the output is where the
/// stage goes). A coordinate with neither is loaded with zero.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Coordinate {
    /// End value of the displacement (m) or rotation (rad).
    Prescribed(f64),
    /// End value of the force (N) or moment (N m).
    Loaded(f64),
}

impl Coordinate {
    /// Whether the drive imposes this coordinate.
    pub fn is_prescribed(&self) -> bool {
        matches!(self, Coordinate::Prescribed(_))
    }

    /// The end value, whichever kind.
    pub fn value(&self) -> f64 {
        match self {
            Coordinate::Prescribed(v) | Coordinate::Loaded(v) => *v,
        }
    }
}

/// One drive path: every stage coordinate `[x, y, phi]` varied proportionally from the
/// unloaded state, evaluated at `k / steps`; or, a measured path (DESIGN §9), through its
/// rows' values in order, evaluated at each row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Drive {
    /// `x`, `y` (m or N) and `phi` (rad or N m) of the stage point: the end values (a
    /// measured path's last row).
    pub coordinates: [Coordinate; 3],
    /// Cases along the path (a measured path's row count).
    pub steps: u32,
    /// A measured path's rows (SI, each coordinate of the kind `coordinates` gives, in the
    /// data file's order): the path runs straight from the unloaded state to the first row
    /// and from each row to the next, and its cases are the rows. Empty: the proportional
    /// path.
    #[serde(default, skip)]
    pub rows: Vec<[f64; 3]>,
}

impl Drive {
    /// A proportional drive path to `coordinates` in `steps` steps.
    pub fn proportional(coordinates: [Coordinate; 3], steps: u32) -> Drive {
        Drive {
            coordinates,
            steps,
            rows: Vec::new(),
        }
    }

    /// Checks a proportional drive's rules: finite end values (keyed as the file writes
    /// the coordinate: `dx` when prescribed, `fx` when loaded), a path that goes somewhere
    /// (the drive as a whole), `steps` from 1 to [`MAX_STEPS`](super::MAX_STEPS). A
    /// measured path (rows from a data file) is its file's, which that file's reader checks.
    /// A scene puts the keys under `drives[i]`.
    pub fn validate(&self) -> Result<(), RuleError> {
        if !self.rows.is_empty() {
            return Ok(());
        }
        for (c, (dk, lk)) in self.coordinates.iter().zip(COORDINATE_KEYS) {
            let key = if c.is_prescribed() { dk } else { lk };
            rules::finite(c.value()).map_err(|m| RuleError::new(key, m))?;
        }
        if self.coordinates.iter().all(|c| c.value() == 0.0) {
            return Err(RuleError::whole(
                "the drive path goes nowhere: give a non-zero dx/fx, dy/fy or dphi/mz",
            ));
        }
        rules::steps(i64::from(self.steps)).map_err(|m| RuleError::new("steps", m))?;
        Ok(())
    }
}

/// A drive path as the solvers follow it, nondimensional (see [`Mechanism::nondimensional`](super::Mechanism::nondimensional)):
/// the stage coordinates' kinds and their values along the path's parameter `lambda` in
/// `[0, 1]`, with the path's cases at `k / steps`.
#[derive(Debug, Clone, PartialEq)]
pub struct DrivePath {
    /// The end values (`lambda = 1`), of the coordinates' kinds.
    pub end: [Coordinate; 3],
    /// Cases along the path.
    pub steps: u32,
    /// A measured path's rows (empty: proportional): row `k` (from 1) is at
    /// `lambda = k / steps`, the values linear in `lambda` between rows and from the
    /// unloaded state to row 1.
    pub rows: Vec<[f64; 3]>,
}

impl DrivePath {
    /// A proportional path to `end` in `steps` steps.
    pub fn proportional(end: [Coordinate; 3], steps: u32) -> DrivePath {
        DrivePath {
            end,
            steps: steps.max(1),
            rows: Vec::new(),
        }
    }

    /// The path's first `k` cases as a path of their own (`k` from 1 to `steps`): the same
    /// cases, at fractions `k / steps` of this one's parameter scaled by `steps / k`.
    pub fn first(&self, k: u32) -> DrivePath {
        let k = k.clamp(1, self.steps.max(1));
        if self.rows.is_empty() {
            let part = f64::from(k) / f64::from(self.steps.max(1));
            return DrivePath {
                end: self.end.map(|c| match c {
                    Coordinate::Prescribed(v) => Coordinate::Prescribed(v * part),
                    Coordinate::Loaded(v) => Coordinate::Loaded(v * part),
                }),
                steps: k,
                rows: Vec::new(),
            };
        }
        let rows: Vec<[f64; 3]> = self.rows.iter().take(k as usize).copied().collect();
        let last = rows.last().copied().unwrap_or([0.0; 3]);
        DrivePath {
            end: std::array::from_fn(|c| match self.end[c] {
                Coordinate::Prescribed(_) => Coordinate::Prescribed(last[c]),
                Coordinate::Loaded(_) => Coordinate::Loaded(last[c]),
            }),
            steps: k,
            rows,
        }
    }

    /// The coordinates at `lambda` (clamped to `[0, 1]`).
    pub fn at(&self, lambda: f64) -> [Coordinate; 3] {
        let lambda = lambda.clamp(0.0, 1.0);
        let values: [f64; 3] = if self.rows.is_empty() {
            self.end.map(|c| lambda * c.value())
        } else {
            let n = self.rows.len();
            let s = lambda * n as f64;
            // Row `k` sits at `s = k`; `s` in `[k - 1, k]` is between row `k - 1` (the
            // unloaded state for k = 1) and row `k`. Snap within rounding of a row onto it.
            let k = (s - 1e-9).ceil().clamp(1.0, n as f64) as usize;
            let t = (s - (k - 1) as f64).clamp(0.0, 1.0);
            let to = self.rows[k - 1];
            let from = if k >= 2 { self.rows[k - 2] } else { [0.0; 3] };
            if (t - 1.0).abs() <= 1e-9 {
                to
            } else {
                std::array::from_fn(|c| from[c] + t * (to[c] - from[c]))
            }
        };
        std::array::from_fn(|c| match self.end[c] {
            Coordinate::Prescribed(_) => Coordinate::Prescribed(values[c]),
            Coordinate::Loaded(_) => Coordinate::Loaded(values[c]),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A proportional path is the end values times `lambda`; a measured path runs straight
    /// from rest to row 1 and from row to row, each row exactly at `k / n`.
    #[test]
    fn drive_paths_pass_through_their_rows() {
        use Coordinate::{Loaded, Prescribed};
        let end = [Prescribed(0.0), Prescribed(0.4), Loaded(2.0)];
        let p = DrivePath::proportional(end, 4);
        assert_eq!(p.at(0.5), [Prescribed(0.0), Prescribed(0.2), Loaded(1.0)]);
        let rows = DrivePath {
            end,
            steps: 3,
            rows: vec![[0.0, 0.1, 0.0], [0.0, 0.1, 1.0], [0.0, 0.4, 2.0]],
        };
        let value = |l: f64| rows.at(l).map(|c| c.value());
        assert_eq!(value(0.0), [0.0; 3]);
        for (k, r) in rows.rows.iter().enumerate() {
            assert_eq!(value((k + 1) as f64 / 3.0), *r);
        }
        // Halfway from rest to row 1, and from row 1 to row 2.
        let half = value(0.5 / 3.0);
        assert!((half[1] - 0.05).abs() < 1e-15 && half[2] == 0.0);
        let half = value(1.5 / 3.0);
        assert!((half[1] - 0.1).abs() < 1e-15 && (half[2] - 0.5).abs() < 1e-15);
        // Kinds are the end's.
        assert!(rows.at(0.7)[1].is_prescribed() && !rows.at(0.7)[2].is_prescribed());
        // The first cases as a path of their own pass through the same rows.
        let two = rows.first(2);
        assert_eq!(two.steps, 2);
        assert_eq!(two.at(1.0).map(|c| c.value()), rows.rows[1]);
        assert_eq!(two.at(0.5).map(|c| c.value()), rows.rows[0]);
        let half = p.first(2);
        assert_eq!(half.at(1.0), p.at(0.5));
        assert_eq!(half.at(0.5), p.at(0.25));
    }
}
