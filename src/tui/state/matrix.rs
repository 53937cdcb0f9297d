//! The PRB matrix panel: one row per segment (gamma, k_theta, k_ex), nondimensional or in SI
//! for the scene's beam; cells are free (fitted) or fixed.

use crate::prb::{Column, PrbMatrix, PrbRow};
use crate::scene::BeamSpec;

use super::super::units::{format_quantity, parse_quantity, trim_number, Quantity};
use super::step;

/// The matrix panel's cursor and display mode.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MatrixState {
    /// The selected segment.
    pub row: usize,
    /// The selected column, an index into [`Column::ALL`].
    pub col: usize,
    /// Show (and take) SI values for the scene's beam.
    pub si: bool,
}

impl Default for MatrixState {
    fn default() -> Self {
        MatrixState {
            row: 1,
            col: 1,
            si: false,
        }
    }
}

impl MatrixState {
    /// The selected column.
    pub fn column(&self) -> Column {
        Column::ALL[self.col.min(Column::ALL.len() - 1)]
    }

    /// Moves the cursor; `rows` is the matrix's length.
    pub fn move_by(&mut self, dx: i32, dy: i32, rows: usize) {
        self.row = step(self.row, dy, rows);
        self.col = step(self.col, dx, Column::ALL.len());
    }

    /// Keeps the cursor inside a matrix of `rows` segments.
    pub fn clamp(&mut self, rows: usize) {
        self.row = self.row.min(rows.saturating_sub(1));
    }

    /// The text of a cell: `inf`, or the value (in SI for `beam` when the SI view is on).
    pub fn cell_text(
        &self,
        matrix: &PrbMatrix,
        beam: &BeamSpec,
        row: usize,
        col: Column,
    ) -> String {
        let v = matrix.rows()[row].get(col);
        if v == f64::INFINITY {
            "inf".into()
        } else if self.si {
            let si = v * si_factor(beam, col);
            match col {
                Column::Gamma => format_quantity(si, Quantity::Length),
                _ => trim_number(si, 5),
            }
        } else {
            trim_number(v, 6)
        }
    }

    /// The nondimensional value typed into a cell (`inf`, a number, or SI input in the SI
    /// view: a length for gamma, N m/rad or N/m for the springs).
    pub fn parse_cell(&self, beam: &BeamSpec, col: Column, text: &str) -> Result<f64, String> {
        Ok(match text.trim().to_ascii_lowercase().as_str() {
            "inf" => f64::INFINITY,
            _ if self.si => {
                let q = if col == Column::Gamma {
                    Quantity::Length
                } else {
                    Quantity::Plain
                };
                parse_quantity(text, q).map_err(|e| format!("{col}: {e}"))? / si_factor(beam, col)
            }
            _ => parse_quantity(text, Quantity::Plain).map_err(|e| format!("{col}: {e}"))?,
        })
    }

    /// `matrix` with the cell at (`row`, `col`) set from `text`. Typing a gamma keeps the
    /// gammas summing to 1 ([`rebalance_gamma`]).
    pub fn edited(
        &self,
        matrix: &PrbMatrix,
        beam: &BeamSpec,
        row: usize,
        col: Column,
        text: &str,
    ) -> Result<PrbMatrix, String> {
        let v = self.parse_cell(beam, col, text)?;
        if col == Column::Gamma && matrix.len() > 1 {
            rebalance_gamma(matrix, row, v)
        } else {
            matrix.with_cell(row, col, v).map_err(|e| e.to_string())
        }
    }

    /// `matrix` with the selected segment split in two halves; the new one gets a joint.
    pub fn split_row(&self, matrix: &PrbMatrix) -> Result<PrbMatrix, String> {
        let rows = matrix.rows();
        let i = self.row.min(rows.len().saturating_sub(1));
        let r = rows[i];
        let half = r.gamma / 2.0;
        let mut new_rows = rows.to_vec();
        new_rows[i].gamma = half;
        let k = if r.has_revolute() {
            r.k_theta
        } else {
            matrix.revolute_count().max(1) as f64
        };
        new_rows.insert(
            i + 1,
            PrbRow {
                gamma: half,
                k_theta: k,
                k_ex: f64::INFINITY,
                free: [true; 3],
            },
        );
        PrbMatrix::new(new_rows).map_err(|e| e.to_string())
    }

    /// `matrix` without the selected segment; its length goes to its neighbour.
    pub fn remove_row(&self, matrix: &PrbMatrix) -> Result<PrbMatrix, String> {
        if matrix.len() <= 1 {
            return Err("a PRB model needs at least one segment".into());
        }
        let mut rows = matrix.rows().to_vec();
        let gone = rows.remove(self.row.min(rows.len() - 1));
        let neighbour = self.row.saturating_sub(1).min(rows.len() - 1);
        rows[neighbour].gamma += gone.gamma;
        PrbMatrix::new(rows).map_err(|e| format!("rejected: {e}"))
    }

    /// `matrix` with the selected cell switched between free and fixed; an `inf` cell is
    /// topology, not a parameter.
    pub fn toggled_free(&self, matrix: &PrbMatrix) -> Result<PrbMatrix, String> {
        let col = self.column();
        let row = self.row.min(matrix.len().saturating_sub(1));
        if matrix.rows()[row].get(col) == f64::INFINITY {
            return Err("an inf cell is topology, not a parameter: type a value first".into());
        }
        let free = matrix.rows()[row].free[col.index()];
        let mut m = matrix.clone();
        m.set_free(row, col, !free);
        Ok(m)
    }
}

/// SI value per nondimensional unit of a column for `beam`: L (m) for gamma, E I0 / L
/// (N m/rad) for k_theta, E A0 / L (N/m) for k_ex.
pub fn si_factor(beam: &BeamSpec, col: Column) -> f64 {
    match col {
        Column::Gamma => beam.length,
        Column::KTheta => beam.youngs_modulus * beam.second_moment() / beam.length,
        Column::KEx => beam.youngs_modulus * beam.area() / beam.length,
    }
}

/// Sets gamma of segment `row` to `v` and keeps the gammas summing to 1 by taking the
/// difference `v - gamma[row]` from one other segment, the donor, chosen as the last segment
/// whose gamma is free and that lies after `row`; else the last free one before it; else
/// the last fixed one after it; else the last fixed one before it. Only gamma of `row` and of
/// the donor change (free flags and springs are kept). The result is validated like any
/// matrix (every gamma in (0, 1], sum 1): a donor that would go to zero or below is an error
/// naming it. A matrix of one segment has no donor (its gamma is always 1).
// TODO(merge): becomes a `PrbMatrix` operation in the core.
pub fn rebalance_gamma(matrix: &PrbMatrix, row: usize, v: f64) -> Result<PrbMatrix, String> {
    let rows = matrix.rows();
    let delta = v - rows[row].gamma;
    let donor = (0..rows.len())
        .filter(|&i| i != row)
        .max_by_key(|&i| (rows[i].is_free(Column::Gamma), i > row, i))
        .ok_or("a single segment's gamma is always 1")?;
    let mut new_rows = rows.to_vec();
    new_rows[row].gamma = v;
    new_rows[donor].gamma -= delta;
    PrbMatrix::new(new_rows).map_err(|e| format!("{e} (segment {} would get the rest)", donor + 1))
}
