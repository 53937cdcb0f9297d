//! Measured data as the truth (DESIGN §9): a CSV of load cases and measured tips, read,
//! checked and converted to the nondimensional form the rest of prbfit works in.
//!
//! The file has a header row and one row per load case, in path order (each path grows from
//! near the unloaded state; the PRB model follows its rows in order). Columns:
//!
//! - `path` (optional, an integer): groups rows into paths, each path's rows together;
//!   absent, the file is one path;
//! - loads: `fx, fy, mz` (N, N m) or `alpha_x, alpha_y, beta` (nondimensional);
//! - the measured tip: `x, y` (m, from the clamp, the unloaded beam along +x) and `theta`
//!   (rad), or `a, b, phi` (units of L, rad).
//!
//! SI and nondimensional columns may not be mixed; the scene's `[beam]` (its nominal `L`,
//! `E`, `I0`) converts SI to nondimensional. Blank lines and lines starting with `#` are
//! skipped. Every problem is an error naming `file:line:column` and the column's name: a
//! missing or unknown or repeated column, a field that is not a number (or is NaN or
//! infinite), a row with too few or too many fields, a path that shrinks (its load
//! magnitude must grow from row to row) or that comes back after another path, a file
//! with no rows.
//!
//! A mechanism's file (DESIGN §9 with §8) names its columns after the `[[drives]]` keys and
//! the measured stage (`stage_dx`, ..., `stage_mz`), SI: see [`parse_stage_csv`].
//!
//! This file holds the scene's [`DataTruth`] and how it follows a beam edit
//! ([`DataTruth::rebased`]); `tip.rs` reads a cantilever's file ([`parse_csv`]), `stage.rs` a
//! mechanism's ([`parse_stage_csv`]), and `csv.rs` what both share (header, fields, paths).

mod csv;
mod stage;
mod tip;

pub use stage::{parse_stage_csv, MeasuredStagePath, MeasuredStageRow, StageData};
pub use tip::{parse_csv, MeasuredPath, MeasuredRow, Units};

use serde::Serialize;

use crate::beam::{Load, TipPose};

use super::beam::BeamSpec;
use tip::nominal_scales;

/// A data scene's truth: the file as the scene names it, its content hash, its units and its
/// paths.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DataTruth {
    /// The file as the scene's `[truth] data` writes it (relative to the scene file).
    pub file: String,
    /// SHA-256 of the file's bytes, lowercase hex (empty until the file is read).
    pub sha256: String,
    /// The file's unit system: SI rows were converted with the scene's nominal beam
    /// (nondimensional until the file is read: no rows, nothing converted).
    pub units: Units,
    /// The measured paths (empty until the file is read, and for a mechanism).
    pub paths: Vec<MeasuredPath>,
    /// A mechanism scene's measured drive paths (DESIGN §9 with §8), SI (`None` for a
    /// cantilever, and until the file is read).
    pub stage: Option<StageData>,
}

impl DataTruth {
    /// Rows in all.
    pub fn row_count(&self) -> usize {
        self.paths.iter().map(|p| p.rows.len()).sum::<usize>()
            + self
                .stage
                .as_ref()
                .map_or(0, |s| s.paths.iter().map(|p| p.rows.len()).sum())
    }

    /// Every path's loads, in order.
    pub fn loads(&self) -> Vec<Vec<Load>> {
        self.paths
            .iter()
            .map(|p| p.rows.iter().map(|r| r.load).collect())
            .collect()
    }

    /// The same data with `to` as the nominal beam in place of `from`, the beam its rows were
    /// converted with: what reading the file again with `to` gives. SI rows keep their
    /// newtons and metres, so their nondimensional loads and tips follow the beam (`alpha`
    /// with `L^2 / (E I0)`, `beta` with `L / (E I0)`, the tip with `1 / L`; the angle stays);
    /// nondimensional rows are the same on any beam.
    ///
    /// # Errors
    /// A path that no longer grows from row to row on `to` (the load magnitude sums force
    /// and moment terms, which scale differently): the file would not open with that beam.
    pub fn rebased(&self, from: &BeamSpec, to: &BeamSpec) -> Result<DataTruth, String> {
        let mut out = self.clone();
        if self.units == Units::Nondimensional {
            return Ok(out);
        }
        let (f0, m0, l0) = nominal_scales(from);
        let (f1, m1, l1) = nominal_scales(to);
        let (force, moment, length) = (f1 / f0, m1 / m0, l1 / l0);
        for path in &mut out.paths {
            for row in &mut path.rows {
                row.load = Load {
                    alpha_x: row.load.alpha_x * force,
                    alpha_y: row.load.alpha_y * force,
                    beta: row.load.beta * moment,
                };
                row.tip = TipPose {
                    a: row.tip.a * length,
                    b: row.tip.b * length,
                    phi: row.tip.phi,
                };
            }
            for pair in path.rows.windows(2) {
                if pair[1].load.magnitude() <= pair[0].load.magnitude() {
                    return Err(format!(
                        "with this beam, path {} of {} shrinks at line {} (its nondimensional \
                         load magnitude is not above line {}'s): the file would not open with it",
                        path.id, self.file, pair[1].line, pair[0].line
                    ));
                }
            }
        }
        Ok(out)
    }
}
