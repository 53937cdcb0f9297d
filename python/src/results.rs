//! The results: one class per command, each holding the report the CLI prints. `to_dict()`
//! is the `--json` object, `str()` the text; every top-level key of the dict is also an
//! attribute (the figures: `r.objective`, `r.max_pos_err`, ...), and the arrays are numpy.

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use serde_json::Value;

use prbfit::prb::PrbMatrix;

use crate::convert::{array, num, to_py, triple};
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

    /// The result's class and what identifies it: the scene, the model, `J`, the verdict,
    /// the cases (the default named only the class and an address).
    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let class = slf.get_type().name()?.to_string();
        let v = &slf.get().value;
        let mut parts = Vec::new();
        if let Some(s) = v.get("scene").and_then(Value::as_str) {
            parts.push(format!("scene {s:?}"));
        }
        if let Some(t) = v.get("topology").and_then(Value::as_str) {
            parts.push(t.to_string());
        }
        if let Some(j) = v.get("objective").and_then(Value::as_f64) {
            parts.push(format!("J {j:.4e}"));
        }
        if let Some(m) = v.get("meets_targets").and_then(Value::as_bool) {
            parts.push(
                if m {
                    "meets its targets"
                } else {
                    "misses its targets"
                }
                .to_string(),
            );
        }
        let cases = v
            .get("cases")
            .and_then(|c| c.as_u64().or_else(|| c.as_array().map(|a| a.len() as u64)));
        if let Some(n) = cases {
            parts.push(format!("{n} cases"));
        }
        Ok(match parts.is_empty() {
            true => format!("<prbfit.{class}>"),
            false => format!("<prbfit.{class} {}>", parts.join(", ")),
        })
    }

    /// The class's names and the report's keys, each an attribute (tab completion finds
    /// the figures).
    fn __dir__(slf: &Bound<'_, Self>) -> PyResult<Vec<String>> {
        let mut names: Vec<String> = slf.get_type().dir()?.extract()?;
        names.extend(slf.get().keys());
        names.sort();
        names.dedup();
        Ok(names)
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
        array(py, &rows)
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
            Some(r) if !r.is_empty() => array(py, &r),
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
            array(py, &rows)
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
        .map(|m| array(py, &case_rows(m, beam)))
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
    /// The FEA tips `(n, 3)` per case; a mechanism's: the FEA's stage `[dx, dy, dphi]` per
    /// case (units of flexure 1's L, rad).
    #[getter]
    fn tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        fea_rows(py, &slf.as_super().value, "fea")
    }

    /// The beam's tips `(n, 3)` beside them; a mechanism's report gives the beam
    /// mechanism's differences instead (`pos_diff`, `ang_diff`, `force_diff` per case in
    /// `to_dict()`): `(0, 3)`.
    #[getter]
    fn beam_tips<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        fea_rows(py, &slf.as_super().value, "beam")
    }
}

/// The `[a, b, phi]` at `key` of each case; a mechanism's cases (a `stage` of their own):
/// the FEA's stage for `fea`, none for `beam`.
fn fea_rows<'py>(py: Python<'py>, v: &Value, key: &str) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<[f64; 3]> = v
        .get("cases")
        .and_then(Value::as_array)
        .map(|cases| {
            cases
                .iter()
                .filter_map(|c| match (c.get("stage"), key) {
                    (Some(s), "fea") => Some(triple(Some(s))),
                    (Some(_), _) => None,
                    (None, _) => {
                        let t = c.get(key).unwrap_or(&Value::Null);
                        Some([num(t, "a"), num(t, "b"), num(t, "phi")])
                    }
                })
                .collect()
        })
        .unwrap_or_default();
    array(py, &rows)
}

/// `Scene.modes()`: natural frequencies of the truth and of each model about the same
/// equilibria.
#[pyclass(module = "prbfit", extends = Report, frozen)]
pub struct Modes;

/// The equilibria of a modes report: its `cases`, or the report itself (one).
fn equilibria(v: &Value) -> (Vec<&Value>, bool) {
    match v.get("cases").and_then(Value::as_array) {
        Some(cases) => (cases.iter().collect(), false),
        None => (vec![v], true),
    }
}

/// The numbers at `key` of `v` (an absent key: none).
fn numbers(v: Option<&Value>, key: &str) -> Vec<f64> {
    v.and_then(|v| v.get(key))
        .and_then(Value::as_array)
        .map(|a| a.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect())
        .unwrap_or_default()
}

/// Frequencies per equilibrium as one array: `(count,)` for one equilibrium, `(n, count)`
/// for every case; `NaN` where there is no frequency (a model with fewer, or none there).
fn frequency_array(py: Python<'_>, v: &Value, pick: impl Fn(&Value) -> Vec<f64>) -> Py<PyAny> {
    let (cases, one) = equilibria(v);
    let width = cases
        .iter()
        .map(|c| numbers(c.get("beam"), "omega").len())
        .max()
        .unwrap_or(0);
    let rows: Vec<Vec<f64>> = cases
        .iter()
        .map(|c| {
            let mut r = pick(c);
            r.resize(width, f64::NAN);
            r
        })
        .collect();
    if one {
        let row = rows.into_iter().next().unwrap_or_default();
        PyArray1::from_vec(py, row).into_any().unbind()
    } else {
        let n = rows.len();
        let flat: Vec<f64> = rows.into_iter().flatten().collect();
        let a = PyArray1::from_vec(py, flat);
        match a.reshape([n, width]) {
            Ok(a) => a.into_any().unbind(),
            Err(_) => py.None(),
        }
    }
}

/// One array per model (in the order of `models`) of its `key` per equilibrium.
fn per_model_frequencies(py: Python<'_>, v: &Value, key: &str) -> Vec<Py<PyAny>> {
    let (cases, _) = equilibria(v);
    let models = cases
        .first()
        .and_then(|c| c.get("models"))
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    (0..models)
        .map(|i| {
            frequency_array(py, v, |c| {
                numbers(c.get("models").and_then(|m| m.get(i)), key)
            })
        })
        .collect()
}

#[pymethods]
impl Modes {
    /// The truth's `Omega` (flexure 1's nondimensional frequencies): `(count,)`, or
    /// `(n, count)` with `cases=True`.
    #[getter]
    fn beam_omega(slf: PyRef<'_, Self>, py: Python<'_>) -> Py<PyAny> {
        frequency_array(py, &slf.as_super().value, |c| {
            numbers(c.get("beam"), "omega")
        })
    }

    /// The truth's frequencies in Hz, shaped as `beam_omega`.
    #[getter]
    fn beam_hz(slf: PyRef<'_, Self>, py: Python<'_>) -> Py<PyAny> {
        frequency_array(py, &slf.as_super().value, |c| numbers(c.get("beam"), "hz"))
    }

    /// Each model's `Omega`, one array per model shaped as `beam_omega`; `NaN` where the
    /// model has no such frequency (a 1R has one; a model that failed there has none).
    #[getter]
    fn omega(slf: PyRef<'_, Self>, py: Python<'_>) -> Vec<Py<PyAny>> {
        per_model_frequencies(py, &slf.as_super().value, "omega")
    }

    /// Each model's frequencies in Hz, as `omega`.
    #[getter]
    fn hz(slf: PyRef<'_, Self>, py: Python<'_>) -> Vec<Py<PyAny>> {
        per_model_frequencies(py, &slf.as_super().value, "hz")
    }

    /// Each model's `Omega_PRB / Omega_beam - 1` per frequency, as `omega`.
    #[getter]
    fn freq_err(slf: PyRef<'_, Self>, py: Python<'_>) -> Vec<Py<PyAny>> {
        per_model_frequencies(py, &slf.as_super().value, "freq_err")
    }

    /// The equilibria's tip (stage) loads `(n, 3)`, flexure 1's `[alpha_x, alpha_y, beta]`
    /// (one row without `cases=True`).
    #[getter]
    fn loads<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let (cases, _) = equilibria(&slf.as_super().value);
        let rows: Vec<[f64; 3]> = cases.iter().map(|c| triple(c.get("load"))).collect();
        array(py, &rows)
    }
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
    m.add_class::<Modes>()?;
    Ok(())
}
