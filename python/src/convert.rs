//! JSON values to Python objects (the reports' `to_dict()`), and arguments from Python with
//! errors that name them.

use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::IntoPyObjectExt;
use serde_json::Value;

use crate::errors;

/// `v` as Python objects: objects as dicts (in the report's key order), arrays as lists,
/// integers as ints, other numbers as floats, `null` as `None`.
pub fn to_py(py: Python<'_>, v: &Value) -> PyResult<Py<PyAny>> {
    Ok(match v {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_py_any(py)?,
        Value::Number(n) => {
            if let Some(i) = n.as_u64() {
                i.into_py_any(py)?
            } else if let Some(i) = n.as_i64() {
                i.into_py_any(py)?
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_py_any(py)?
            }
        }
        Value::String(s) => s.into_py_any(py)?,
        Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(to_py(py, x)?)?;
            }
            list.into_any().unbind()
        }
        Value::Object(o) => {
            let dict = PyDict::new(py);
            for (k, x) in o {
                dict.set_item(k, to_py(py, x)?)?;
            }
            dict.into_any().unbind()
        }
    })
}

/// The number at `key` of `v` (NaN when absent: a report's arrays are built from keys its
/// type always has).
pub fn num(v: &Value, key: &str) -> f64 {
    v.get(key).and_then(Value::as_f64).unwrap_or(f64::NAN)
}

/// The numbers of a JSON array (`[a, b, phi]`).
pub fn triple(v: Option<&Value>) -> [f64; 3] {
    let at = |i: usize| {
        v.and_then(|a| a.get(i))
            .and_then(Value::as_f64)
            .unwrap_or(f64::NAN)
    };
    [at(0), at(1), at(2)]
}

/// Rows of three as an `(n, 3)` array.
pub fn array3<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let array = PyArray2::<f64>::zeros(py, [rows.len(), 3], false);
    // SAFETY: the array was just created here, C-contiguous, and no other reference to its
    // data exists yet (it has not been handed to Python).
    if let Ok(data) = unsafe { array.as_slice_mut() } {
        for (cell, x) in data.iter_mut().zip(rows.iter().flatten()) {
            *cell = *x;
        }
    }
    array
}

/// A finite number for `argument`, or bad input naming it.
pub fn finite(argument: &str, x: f64) -> PyResult<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(errors::input(
            argument,
            format!("{x} is not a finite number"),
        ))
    }
}

/// Extracts `T` from `value` for `argument`: a wrong type is bad input naming it.
pub fn extract<'py, T>(argument: &str, value: &Bound<'py, PyAny>, what: &str) -> PyResult<T>
where
    T: FromPyObjectOwned<'py>,
{
    value.extract::<T>().map_err(|_| {
        let ty = value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into());
        errors::input(argument, format!("expected {what}, got {ty}"))
    })
}

use pyo3::conversion::FromPyObjectOwned;
