//! JSON values to Python objects (the reports' `to_dict()`), and arguments from Python with
//! errors that name them.

use numpy::{PyArray2, PyArrayMethods};
use pyo3::exceptions::PyOverflowError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyTuple};
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

/// Rows of `N` as an `(n, N)` array.
pub fn array<'py, const N: usize>(py: Python<'py>, rows: &[[f64; N]]) -> Bound<'py, PyArray2<f64>> {
    let array = PyArray2::<f64>::zeros(py, [rows.len(), N], false);
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

/// Refuses a numpy array (or scalar) of `value` whose dtype is not a real number's (numpy's
/// kinds `f`, `i`, `u`, or `O` whose items are checked one by one): complex numbers were
/// cut to their real part with no more than a warning, and times and strings read as
/// numbers.
pub fn real_dtype(argument: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
    let Ok(dtype) = value.getattr("dtype") else {
        return Ok(());
    };
    let kind: String = dtype
        .getattr("kind")
        .and_then(|k| k.extract())
        .unwrap_or_default();
    if matches!(kind.as_str(), "f" | "i" | "u" | "O") {
        return Ok(());
    }
    let name = dtype
        .str()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| kind.clone());
    Err(errors::input(
        argument,
        format!("expected real numbers, got dtype {name}"),
    ))
}

/// Extracts `T` from `value` for `argument`: a wrong type is bad input naming it.
pub fn extract<'py, T>(argument: &str, value: &Bound<'py, PyAny>, what: &str) -> PyResult<T>
where
    T: FromPyObjectOwned<'py>,
{
    real_dtype(argument, value)?;
    // The items of a list or a tuple (one level: a complex numpy scalar among numbers).
    let items = value
        .cast::<PyList>()
        .map(|l| l.iter().collect::<Vec<_>>())
        .or_else(|_| value.cast::<PyTuple>().map(|t| t.iter().collect()));
    for item in items.unwrap_or_default() {
        real_dtype(argument, &item)?;
    }
    value.extract::<T>().map_err(|_| {
        errors::input(
            argument,
            format!("expected {what}, got {}", type_name(value)),
        )
    })
}

use pyo3::conversion::FromPyObjectOwned;

/// An int as an error message shows it: a long one by its first 12 digits and its length.
fn shown_int(value: &Bound<'_, PyAny>) -> String {
    let text = value.str().map(|s| s.to_string()).unwrap_or_default();
    if text.chars().count() > 24 {
        format!(
            "{}... ({} digits)",
            text.chars().take(12).collect::<String>(),
            text.len()
        )
    } else {
        text
    }
}

/// A real number for the keyword `argument` (a Python float or int, a numpy number), or none
/// when not given: anything else is bad input naming the argument, where PyO3's own
/// conversion read `True` as 1.0, cut a complex numpy scalar to its real part, and raised an
/// `OverflowError` naming nothing for an int too large for a float.
pub fn real(argument: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let ty = type_name(value);
    // A numpy bool's dtype kind is `b`, which `real_dtype` refuses.
    if value.is_instance_of::<PyBool>() {
        return Err(errors::input(argument, "expected a number, got bool"));
    }
    real_dtype(argument, value)?;
    match value.extract::<f64>() {
        Ok(x) => Ok(Some(x)),
        Err(e) if e.is_instance_of::<PyOverflowError>(value.py()) => Err(errors::input(
            argument,
            format!("{}: too large for a number", shown_int(value)),
        )),
        Err(_) => Err(errors::input(
            argument,
            format!("expected a number, got {ty}"),
        )),
    }
}

/// A whole number for `argument` from `min` to `max`: a Python int (or anything with
/// `__index__`, a numpy integer), or a float with no fractional part (a row of a float
/// array); anything else is bad input naming the argument, where PyO3's own conversion raised
/// an `OverflowError` that named nothing for an int out of its type's range.
pub fn whole<T>(argument: &str, value: &Bound<'_, PyAny>, min: T, max: T) -> PyResult<T>
where
    T: TryFrom<i128> + Into<i128> + Copy + std::fmt::Display,
{
    let ty = type_name(value);
    let out_of_range = || {
        errors::input(
            argument,
            format!(
                "{}: must be a whole number from {min} to {max}",
                shown_int(value)
            ),
        )
    };
    if value.is_instance_of::<PyBool>() {
        return Err(errors::input(argument, "expected a whole number, got bool"));
    }
    let n: i128 = match value.extract::<i128>() {
        Ok(n) => n,
        Err(e) if e.is_instance_of::<PyOverflowError>(value.py()) => return Err(out_of_range()),
        Err(_) => match value.extract::<f64>() {
            // An integral float within i128's range converts exactly.
            Ok(x) if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e38 => x as i128,
            Ok(_) => return Err(out_of_range()),
            Err(_) => {
                return Err(errors::input(
                    argument,
                    format!("expected a whole number, got {ty}"),
                ))
            }
        },
    };
    if n < min.into() || n > max.into() {
        return Err(out_of_range());
    }
    T::try_from(n).map_err(|_| out_of_range())
}

/// The type name of `value`, as an error message shows it.
fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into())
}

/// A `T` for `argument` (`what` names it in the message), or none when not given (`None`):
/// anything else is bad input naming the argument, where PyO3's own conversion raised a
/// `TypeError`.
fn given<'py, T: FromPyObjectOwned<'py>>(
    argument: &str,
    value: Option<&Bound<'py, PyAny>>,
    what: &str,
) -> PyResult<Option<T>> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    value.extract::<T>().map(Some).map_err(|_| {
        errors::input(
            argument,
            format!("expected {what}, got {}", type_name(value)),
        )
    })
}

/// A string for `argument`, or none when not given.
pub fn text(argument: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<String>> {
    given(argument, value, "a string")
}

/// A file path for `argument` (a `str` or an `os.PathLike`), or none when not given.
pub fn path(
    argument: &str,
    value: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<std::path::PathBuf>> {
    given(argument, value, "a path (str or os.PathLike)")
}

/// A flag for `argument` (`True` or `False`, a numpy bool), `default` when not given: an int
/// or anything else is bad input naming the argument.
pub fn flag(argument: &str, value: Option<&Bound<'_, PyAny>>, default: bool) -> PyResult<bool> {
    Ok(given(argument, value, "True or False")?.unwrap_or(default))
}
