//! `prbfit.Matrix`: a PRB matrix (DESIGN §3), parsed from its text form, built from a
//! topology name, or given as rows `[gamma, k_theta, k_ex]` or `[gamma, k_theta, k_ex, mu]`
//! (a list or a numpy array, `inf` where there is no joint); its numpy form and its topology.

use numpy::{PyArray2, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;

use prbfit::prb::{PrbMatrix, PrbRow};

use crate::convert::array;
use crate::errors;

/// A PRB matrix: one row `[gamma, k_theta, k_ex, mu]` per segment from the root (`mu`
/// optional: without it each segment's mass is where its length is); `inf` for no
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
            // A published model's name where a matrix is wanted: say so, and where it goes.
            if let Some(p) = prbfit::prb::published::by_name(text.trim()) {
                return Err(errors::input(
                    argument,
                    format!(
                        "\"{text}\" is a published model's name, not a matrix: give its matrix \
                         (\"{}\"), or name it where a model is asked for (eval, modes, export)",
                        p.prb.to_text()
                    ),
                ));
            }
            return PrbMatrix::parse(&text)
                .map_err(|e| errors::input(argument, format!("\"{text}\": {e}")));
        }
        rows_matrix(argument, value, None)
    }
}

/// A float32 value as the float64 of its shortest decimal (the digits that read back as the
/// same float32): `inf` and NaN stay what they are.
fn single_as_typed(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

/// A 2-D array's rows, each entry through `value`.
fn array_rows<T: Copy>(
    view: numpy::ndarray::ArrayView2<'_, T>,
    value: impl Fn(T) -> f64,
) -> Vec<Vec<f64>> {
    view.rows()
        .into_iter()
        .map(|row| row.iter().map(|&x| value(x)).collect())
        .collect()
}

/// Rows (a numpy array or a list of lists) as a matrix; `fixed` marks the cells that stay.
/// A numpy array must be `(N, 3)` or `(N, 4)`; each row of a list has 3 or 4 entries (mixed
/// widths are the matrix's own error: every row gives a mu or none does).
fn rows_matrix(
    argument: &str,
    value: &Bound<'_, PyAny>,
    fixed: Option<Vec<Vec<bool>>>,
) -> PyResult<PrbMatrix> {
    let rows: Vec<Vec<f64>> = if let Ok(a) = value.cast::<PyUntypedArray>() {
        crate::convert::real_dtype(argument, value)?;
        let shape = a.shape().to_vec();
        if shape.len() != 2 || !(shape[1] == 3 || shape[1] == 4) {
            let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
            return Err(errors::input(
                argument,
                format!(
                    "expected an array of shape (N, 3) [gamma, k_theta, k_ex] or (N, 4) \
                     [gamma, k_theta, k_ex, mu], got shape ({})",
                    dims.join(", ")
                ),
            ));
        }
        if let Ok(single) = value.extract::<PyReadonlyArray2<'_, f32>>() {
            // A float32 entry is read as the decimal it prints as (numpy's repr): 0.1 is
            // 0.1, not 0.10000000149011612, so gammas that sum to 1 as typed still do.
            array_rows(single.as_array(), single_as_typed)
        } else {
            let floats = a
                .call_method1("astype", ("float64",))
                .map_err(|_| errors::input(argument, "expected an array of numbers"))?;
            let a: PyReadonlyArray2<'_, f64> = floats
                .extract()
                .map_err(|_| errors::input(argument, "expected an array of numbers"))?;
            array_rows(a.as_array(), |x| x)
        }
    } else {
        value.extract::<Vec<Vec<f64>>>().map_err(|_| {
            errors::input(
                argument,
                "expected a Matrix, its text form, or rows [gamma, k_theta, k_ex] or \
                 [gamma, k_theta, k_ex, mu] of numbers",
            )
        })?
    };
    if let Some(f) = &fixed {
        let widths: Vec<usize> = rows.iter().map(Vec::len).collect();
        check_fixed(f, &widths)?;
    }
    let mut out = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let (gamma, k_theta, k_ex, mu) = match r[..] {
            [g, k, e] => (g, k, e, None),
            [g, k, e, m] => (g, k, e, Some(m)),
            _ => {
                return Err(errors::input(
                    argument,
                    format!(
                        "row {}: expected 3 entries (gamma, k_theta, k_ex) or 4 (gamma, \
                         k_theta, k_ex, mu), got {}",
                        i + 1,
                        r.len()
                    ),
                ))
            }
        };
        for (name, x) in [
            ("gamma", gamma),
            ("k_theta", k_theta),
            ("k_ex", k_ex),
            ("mu", mu.unwrap_or(0.0)),
        ] {
            if x.is_nan() {
                return Err(errors::input(
                    argument,
                    format!("row {}, {name}: NaN is not a number", i + 1),
                ));
            }
        }
        let mut free = [true; 4];
        if let Some(f) = fixed.as_ref().and_then(|f| f.get(i)) {
            for (cell, fixed) in free.iter_mut().zip(f) {
                *cell = !fixed;
            }
        }
        out.push(PrbRow {
            gamma,
            k_theta,
            k_ex,
            mu,
            free,
        });
    }
    PrbMatrix::new(out).map_err(|e| errors::input(argument, e))
}

/// Checks `fixed` against a matrix whose rows have `widths` entries: one row of flags per
/// row, one flag per entry.
fn check_fixed(fixed: &[Vec<bool>], widths: &[usize]) -> PyResult<()> {
    if fixed.len() != widths.len() {
        return Err(errors::input(
            "fixed",
            format!("{} rows for a matrix of {}", fixed.len(), widths.len()),
        ));
    }
    for (i, (f, &w)) in fixed.iter().zip(widths).enumerate() {
        if f.len() != w {
            return Err(errors::input(
                "fixed",
                format!("row {}: {} flags for a row of {w} entries", i + 1, f.len()),
            ));
        }
    }
    Ok(())
}

/// `matrix` (a `Matrix` or its text form, already read) with exactly the cells `fixed`
/// marks kept by a fit: its own `!` marks give way to the flags.
fn with_fixed(argument: &str, matrix: PrbMatrix, fixed: &[Vec<bool>]) -> PyResult<PrbMatrix> {
    let widths: Vec<usize> = matrix
        .rows()
        .iter()
        .map(|r| 3 + usize::from(r.mu.is_some()))
        .collect();
    check_fixed(fixed, &widths)?;
    let rows = matrix
        .rows()
        .iter()
        .zip(fixed)
        .map(|(r, f)| {
            let mut r = *r;
            for (cell, &kept) in r.free.iter_mut().zip(f) {
                *cell = !kept;
            }
            r
        })
        .collect();
    PrbMatrix::new(rows).map_err(|e| errors::input(argument, e))
}

#[pymethods]
impl Matrix {
    /// A matrix from rows `[gamma, k_theta, k_ex]` or `[gamma, k_theta, k_ex, mu]` (a list
    /// of lists or an (N, 3) or (N, 4) numpy array, `inf` for no joint), its text form, or
    /// another Matrix; `fixed` (N rows of as many booleans) marks cells a fit keeps (over a
    /// text form's or a Matrix's own marks).
    #[new]
    #[pyo3(signature = (rows, fixed = None))]
    fn new(rows: &Bound<'_, PyAny>, fixed: Option<&Bound<'_, PyAny>>) -> PyResult<Matrix> {
        let fixed =
            match fixed.filter(|f| !f.is_none()) {
                Some(f) => Some(f.extract::<Vec<Vec<bool>>>().map_err(|_| {
                    errors::input("fixed", "expected a list of rows of True or False")
                })?),
                None => None,
            };
        let read = rows.cast::<Matrix>().is_ok() || rows.extract::<String>().is_ok();
        let inner = match fixed {
            Some(f) if read => with_fixed("rows", Matrix::from_any("rows", rows)?, &f)?,
            Some(f) => rows_matrix("rows", rows, Some(f))?,
            None => Matrix::from_any("rows", rows)?,
        };
        Ok(Matrix { inner })
    }

    /// Parses the text form: rows separated by `;`, entries by `,`, `inf` for no joint, a
    /// trailing `!` on a fixed cell.
    #[staticmethod]
    fn parse(text: &Bound<'_, PyAny>) -> PyResult<Matrix> {
        let text = crate::convert::text("text", Some(text))?
            .ok_or_else(|| errors::input("text", "give the matrix's text"))?;
        PrbMatrix::parse(&text)
            .map(|inner| Matrix { inner })
            .map_err(|e| errors::input("text", format!("\"{text}\": {e}")))
    }

    /// The starting matrix of a topology (`L-R-R-R`, `1R`..`4R`, segments `L`, `R`, `P`,
    /// `RP`).
    #[staticmethod]
    fn from_topology(name: &Bound<'_, PyAny>) -> PyResult<Matrix> {
        let name = crate::convert::text("name", Some(name))?
            .ok_or_else(|| errors::input("name", "give a topology"))?;
        PrbMatrix::from_topology(&name)
            .map(|inner| Matrix { inner })
            .map_err(|e| errors::input("topology", format!("{name}: {e}")))
    }

    /// The (N, 4) numpy array `[gamma, k_theta, k_ex, mu]`, `inf` where there is no joint;
    /// a matrix given without mus (three columns) has `mu = gamma` (see `has_mu`).
    fn to_numpy<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rows: Vec<[f64; 4]> = self
            .inner
            .rows()
            .iter()
            .map(|r| [r.gamma, r.k_theta, r.k_ex, r.mass()])
            .collect();
        array(py, &rows)
    }

    /// Whether the matrix gives its mus (a fourth column); without, each segment's mass is
    /// where its length is (`mu = gamma`), through every fit.
    #[getter]
    fn has_mu(&self) -> bool {
        self.inner.has_mu()
    }

    /// (N, 4) booleans, `[gamma, k_theta, k_ex, mu]`: the cells a fit keeps (`!` in the
    /// text form).
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
