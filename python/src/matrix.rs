//! `prbfit.Matrix`: a PRB matrix (DESIGN §3), parsed from its text form, built from a
//! topology name, or given as rows `[gamma, k_theta, k_ex]` (a list or a numpy array, `inf`
//! where there is no joint); its numpy form and its topology.

use numpy::{PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use prbfit::prb::{PrbMatrix, PrbRow};

use crate::convert::array3;
use crate::errors;

/// A PRB matrix: one row `[gamma, k_theta, k_ex]` per segment from the root; `inf` for no
/// joint. Cells may be fixed (the text form's `!`): a fit keeps them.
#[pyclass(module = "prbfit", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct Matrix {
    pub inner: PrbMatrix,
}

impl Matrix {
    /// The matrix given to `argument`: a `Matrix`, its text form, or rows.
    pub fn from_any(argument: &str, value: &Bound<'_, PyAny>) -> PyResult<PrbMatrix> {
        if let Ok(m) = value.cast::<Matrix>() {
            return Ok(m.get().inner.clone());
        }
        if let Ok(text) = value.extract::<String>() {
            return PrbMatrix::parse(&text)
                .map_err(|e| errors::input(argument, format!("\"{text}\": {e}")));
        }
        rows_matrix(argument, value, None)
    }
}

/// Rows (a numpy array or a list of lists) as a matrix; `fixed` marks the cells that stay.
fn rows_matrix(
    argument: &str,
    value: &Bound<'_, PyAny>,
    fixed: Option<Vec<[bool; 3]>>,
) -> PyResult<PrbMatrix> {
    let rows: Vec<Vec<f64>> = if let Ok(a) = value.extract::<PyReadonlyArray2<'_, f64>>() {
        let shape = a.shape().to_vec();
        let view = a.as_array();
        (0..shape[0])
            .map(|i| (0..shape[1]).map(|j| view[[i, j]]).collect())
            .collect()
    } else {
        value.extract::<Vec<Vec<f64>>>().map_err(|_| {
            errors::input(
                argument,
                "expected a Matrix, its text form, or rows [gamma, k_theta, k_ex] of numbers",
            )
        })?
    };
    if let Some(f) = &fixed {
        if f.len() != rows.len() {
            return Err(errors::input(
                "fixed",
                format!("{} rows for a matrix of {}", f.len(), rows.len()),
            ));
        }
    }
    let mut out = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let [gamma, k_theta, k_ex] = r[..] else {
            return Err(errors::input(
                argument,
                format!(
                    "row {}: expected 3 entries (gamma, k_theta, k_ex), got {}",
                    i + 1,
                    r.len()
                ),
            ));
        };
        for (name, x) in [("gamma", gamma), ("k_theta", k_theta), ("k_ex", k_ex)] {
            if x.is_nan() {
                return Err(errors::input(
                    argument,
                    format!("row {}, {name}: NaN is not a number", i + 1),
                ));
            }
        }
        let free = fixed
            .as_ref()
            .and_then(|f| f.get(i))
            .map_or([true; 3], |f| f.map(|fixed| !fixed));
        out.push(PrbRow {
            gamma,
            k_theta,
            k_ex,
            free,
        });
    }
    PrbMatrix::new(out).map_err(|e| errors::input(argument, e))
}

#[pymethods]
impl Matrix {
    /// A matrix from rows `[gamma, k_theta, k_ex]` (a list of lists or an (N, 3) numpy
    /// array, `inf` for no joint), its text form, or another Matrix; `fixed` (N rows of 3
    /// booleans) marks cells a fit keeps.
    #[new]
    #[pyo3(signature = (rows, fixed = None))]
    fn new(rows: &Bound<'_, PyAny>, fixed: Option<Vec<[bool; 3]>>) -> PyResult<Matrix> {
        let inner = match fixed {
            Some(f) => rows_matrix("rows", rows, Some(f))?,
            None => Matrix::from_any("rows", rows)?,
        };
        Ok(Matrix { inner })
    }

    /// Parses the text form: rows separated by `;`, entries by `,`, `inf` for no joint, a
    /// trailing `!` on a fixed cell.
    #[staticmethod]
    fn parse(text: &str) -> PyResult<Matrix> {
        PrbMatrix::parse(text)
            .map(|inner| Matrix { inner })
            .map_err(|e| errors::input("text", format!("\"{text}\": {e}")))
    }

    /// The starting matrix of a topology (`L-R-R-R`, `1R`..`4R`, segments `L`, `R`, `P`,
    /// `RP`).
    #[staticmethod]
    fn from_topology(name: &str) -> PyResult<Matrix> {
        PrbMatrix::from_topology(name)
            .map(|inner| Matrix { inner })
            .map_err(|e| errors::input("topology", format!("{name}: {e}")))
    }

    /// The (N, 3) numpy array `[gamma, k_theta, k_ex]`, `inf` where there is no joint.
    fn to_numpy<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .rows()
            .iter()
            .map(|r| [r.gamma, r.k_theta, r.k_ex])
            .collect();
        array3(py, &rows)
    }

    /// (N, 3) booleans: the cells a fit keeps (`!` in the text form).
    #[getter]
    fn fixed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<bool>>> {
        let rows: Vec<Vec<bool>> = self
            .inner
            .rows()
            .iter()
            .map(|r| r.free.iter().map(|f| !f).collect())
            .collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| errors::SolveError::new_err(e.to_string()))
    }

    /// The topology name, from the root (`L-R-R-R`).
    #[getter]
    fn topology(&self) -> String {
        self.inner.topology()
    }

    /// The text form, as the CLI and the reports write it.
    #[getter]
    fn text(&self) -> String {
        self.inner.to_text()
    }

    /// Segments (rows).
    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __str__(&self) -> String {
        self.inner.to_text()
    }

    fn __repr__(&self) -> String {
        format!("Matrix.parse(\"{}\")", self.inner.to_text())
    }
}
