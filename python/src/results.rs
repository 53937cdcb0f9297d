//! The results: one class per command, each holding the report the CLI prints. `to_dict()`
//! is the `--json` object, `str()` the text; every top-level key of the dict is also an
//! attribute (the figures: `r.objective`, `r.max_pos_err`, ...), and the arrays are numpy.

use numpy::PyArray2;
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use serde_json::Value;

use prbfit::prb::PrbMatrix;

use crate::convert::{array3, num, to_py, triple};
use crate::matrix::Matrix;

/// What every result has: the report as JSON and as text.
#[pyclass(module = "prbfit", subclass, frozen)]
pub struct Report {
    pub value: Value,
    pub text: String,
}

impl Report {
    /// The rows of one model (`eval`): the report itself, or each of `models`.
    fn model_rows(&self) -> Vec<&Value> {
        match self.value.get("models").and_then(Value::as_array) {
            Some(rows) => rows.iter().collect(),
            None => vec![&self.value],
        }
    }
}

#[pymethods]
impl Report {
    /// The CLI's `--json` object for the same command, as dicts, lists and numbers.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_py(py, &self.value)
    }

    /// The top-level keys of the report, each also an attribute.
    fn keys(&self) -> Vec<String> {
        self.value
            .as_object()
            .map(|o| o.keys().cloned().collect())
            .unwrap_or_default()
    }

    /// A top-level key of the report.
    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        match self.value.get(name) {
            Some(v) => to_py(py, v),
            None => Err(PyAttributeError::new_err(format!(
                "this result has no `{name}` (its keys: {})",
                self.keys().join(", ")
            ))),
        }
    }

    /// The CLI's text.
    fn __str__(&self) -> String {
        self.text.clone()
    }
}

/// `Scene.solve()`: the baseline beam's tips (or a mechanism's stage) over the scene's cases
/// or at one load.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Solution;

#[pymethods]
impl Solution {
    /// Tips `(n, 3)`: `[a, b, phi]` per case (one row for a single load). A mechanism's:
    /// flexure 1's tip in its own frame per case (see `stages` for the stage).
    #[getter]
    fn tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v = &slf.as_super().value;
        let rows: Vec<[f64; 3]> = match v.get("cases").and_then(Value::as_array) {
            None => vec![[num(v, "a"), num(v, "b"), num(v, "phi")]],
            Some(cases) => cases
                .iter()
                .map(|c| match c.get("flexures") {
                    Some(f) => triple(f.get(0).and_then(|f| f.get("tip"))),
                    None => [num(c, "a"), num(c, "b"), num(c, "phi")],
                })
                .collect(),
        };
        array3(py, &rows)
    }

    /// A mechanism's stage `(n, 3)`: `[dx, dy, dphi]` per case (units of flexure 1's L, rad);
    /// a cantilever's: its tips.
    #[getter]
    fn stages<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v = &slf.as_super().value;
        let rows: Option<Vec<[f64; 3]>> = v.get("cases").and_then(Value::as_array).map(|cases| {
            cases
                .iter()
                .filter(|c| c.get("stage").is_some())
                .map(|c| triple(c.get("stage")))
                .collect()
        });
        match rows {
            Some(r) if !r.is_empty() => array3(py, &r),
            _ => Solution::tips(slf, py),
        }
    }

    /// Deformed shapes (`shape=True`): one `(m, 3)` array `[x, y, psi]` per case (units of
    /// L, rad); empty without `shape=True`.
    #[getter]
    fn shapes<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Vec<Bound<'py, PyArray2<f64>>> {
        let v = &slf.as_super().value;
        let shape = |s: &Value| {
            let rows: Vec<[f64; 3]> = s
                .as_array()
                .map(|pts| {
                    pts.iter()
                        .map(|p| [num(p, "x"), num(p, "y"), num(p, "psi")])
                        .collect()
                })
                .unwrap_or_default();
            array3(py, &rows)
        };
        match v.get("cases").and_then(Value::as_array) {
            Some(cases) => cases
                .iter()
                .filter_map(|c| c.get("shape"))
                .map(shape)
                .collect(),
            None => v.get("shape").map(shape).into_iter().collect(),
        }
    }
}

/// `Scene.eval()`: models judged against the scene's truth.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Evaluation;

/// The `(n, 3)` rows of `key` (a triple or the flattened tip) of each case of a model row.
fn case_rows(row: &Value, beam: bool) -> Vec<[f64; 3]> {
    let tip = |c: &Value| -> [f64; 3] {
        if let Some(s) = c.get("stage").filter(|_| !beam) {
            return triple(Some(s));
        }
        let c = if beam { c.get("beam").unwrap_or(c) } else { c };
        match c.get("stage") {
            Some(s) => triple(Some(s)),
            None => [num(c, "a"), num(c, "b"), num(c, "phi")],
        }
    };
    match row.get("cases").and_then(Value::as_array) {
        Some(cases) => cases.iter().map(tip).collect(),
        None => vec![tip(row)],
    }
}

#[pymethods]
impl Evaluation {
    /// The model's tips `(n, 3)` per case (a mechanism's: its stage); with several models,
    /// one array per model in the order of `models`.
    #[getter]
    fn tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Py<PyAny> {
        per_model(py, slf.as_super(), false)
    }

    /// The truth's tips `(n, 3)` per case beside them (a mechanism's: its stage).
    #[getter]
    fn beam_tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Py<PyAny> {
        per_model(py, slf.as_super(), true)
    }
}

fn per_model(py: Python<'_>, r: &Report, beam: bool) -> Py<PyAny> {
    let rows = r.model_rows();
    let arrays: Vec<_> = rows
        .iter()
        .map(|m| array3(py, &case_rows(m, beam)))
        .collect();
    if r.value.get("models").is_some() {
        pyo3::types::PyList::new(py, arrays)
            .map(|l| l.into_any().unbind())
            .unwrap_or_else(|_| py.None())
    } else {
        arrays
            .into_iter()
            .next()
            .map(|a| a.into_any().unbind())
            .unwrap_or_else(|| py.None())
    }
}

/// `Scene.fit()`: the fitted matrix and its figures.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Fit;

#[pymethods]
impl Fit {
    /// The fitted matrix.
    #[getter]
    fn matrix(slf: PyRef<'_, Self>) -> PyResult<Matrix> {
        matrix_at(&slf.as_super().value, "prb")
    }
}

/// The matrix of the text at `key`.
fn matrix_at(v: &Value, key: &str) -> PyResult<Matrix> {
    let text = v.get(key).and_then(Value::as_str).unwrap_or_default();
    PrbMatrix::parse(text)
        .map(|inner| Matrix { inner })
        .map_err(|e| crate::errors::SolveError::new_err(format!("internal error: {e}")))
}

/// `Scene.select()`: the topology ladder and the chosen model.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Selection;

#[pymethods]
impl Selection {
    /// The chosen model's matrix, or None when no model meets the targets.
    #[getter]
    fn chosen_matrix(slf: PyRef<'_, Self>) -> PyResult<Option<Matrix>> {
        match slf.as_super().value.get("chosen") {
            Some(c) if !c.is_null() => matrix_at(c, "prb").map(Some),
            _ => Ok(None),
        }
    }
}

/// `Scene.calibrate()`: one beam parameter fitted to a data scene's measurements.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Calibration;

/// `Scene.export()`: what was written.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Export;

/// `Scene.fea()`: the CalculiX run and the beam beside it.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Fea;

#[pymethods]
impl Fea {
    /// The FEA tips `(n, 3)` per case.
    #[getter]
    fn tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        fea_rows(py, &slf.as_super().value, "fea")
    }

    /// The beam's tips `(n, 3)` beside them.
    #[getter]
    fn beam_tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        fea_rows(py, &slf.as_super().value, "beam")
    }
}

fn fea_rows<'py>(py: Python<'py>, v: &Value, key: &str) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<[f64; 3]> = v
        .get("cases")
        .and_then(Value::as_array)
        .map(|cases| {
            cases
                .iter()
                .map(|c| {
                    let t = c.get(key).unwrap_or(&Value::Null);
                    [num(t, "a"), num(t, "b"), num(t, "phi")]
                })
                .collect()
        })
        .unwrap_or_default();
    array3(py, &rows)
}

/// Adds the result classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Report>()?;
    m.add_class::<Solution>()?;
    m.add_class::<Evaluation>()?;
    m.add_class::<Fit>()?;
    m.add_class::<Selection>()?;
    m.add_class::<Calibration>()?;
    m.add_class::<Export>()?;
    m.add_class::<Fea>()?;
    Ok(())
}
