//! The PRB matrix panel: one row per segment (gamma, k_theta, k_ex, mu), nondimensional or in
//! SI for the scene's beam (mu in kg when the beam has a density); cells are free (fitted) or
//! fixed. A three-column matrix shows each mu as its gamma; editing or fixing a mu writes
//! every mu out.

use crate::prb::{Column, PrbMatrix, PrbRow};
use crate::scene::BeamSpec;
use crate::si::column_factor;

use super::super::units::{format_quantity, parse_over, parse_quantity, trim_number, Quantity};
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
            let si = v * column_factor(beam, col);
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
    pub fn parse_cell(
        &self,
        beam: &BeamSpec,
        col: Column,
        present: f64,
        text: &str,
    ) -> Result<f64, String> {
        Ok(match text.trim().to_ascii_lowercase().as_str() {
            "inf" => f64::INFINITY,
            _ if self.si => {
                let q = if col == Column::Gamma {
                    Quantity::Length
                } else {
                    Quantity::Plain
                };
                let factor = column_factor(beam, col);
                // A bare length meant in the shown mm is refused, not taken as metres.
                parse_over(text, q, present * factor).map_err(|e| format!("{col}: {e}"))? / factor
            }
            _ => parse_quantity(text, Quantity::Plain).map_err(|e| format!("{col}: {e}"))?,
        })
    }

    /// `matrix` with the cell at (`row`, `col`) set from `text`. Typing a gamma keeps the
    /// gammas summing to 1 ([`PrbMatrix::with_gamma`]). A value ending in `!`, as a matrix
    /// is written in a scene file, also fixes the cell (`f` fixes or frees it too).
    pub fn edited(
        &self,
        matrix: &PrbMatrix,
        beam: &BeamSpec,
        row: usize,
        col: Column,
        text: &str,
    ) -> Result<PrbMatrix, String> {
        let (text, fix) = match text.trim().strip_suffix('!') {
            Some(value) => (value, true),
            None => (text, false),
        };
        let present = matrix.rows().get(row).map_or(0.0, |r| r.get(col));
        let v = self.parse_cell(beam, col, present, text)?;
        let mut edited = if col == Column::Gamma && matrix.len() > 1 {
            matrix.with_gamma(row, v).map_err(|e| e.to_string())?
        } else {
            matrix.with_cell(row, col, v).map_err(|e| e.to_string())?
        };
        if fix {
            edited.set_free(row, col, false);
        }
        Ok(edited)
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
                mu: r.mu.map(|mu| mu / 2.0),
                ..PrbRow::new(half, k, f64::INFINITY)
            },
        );
        if let Some(mu) = r.mu {
            new_rows[i].mu = Some(mu / 2.0);
        }
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
        if let (Some(mu), Some(gone)) = (rows[neighbour].mu, gone.mu) {
            rows[neighbour].mu = Some(mu + gone);
        }
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
