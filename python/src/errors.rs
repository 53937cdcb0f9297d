//! `prbfit.Error` and its two kinds, the CLI's exit statuses: `InputError` (2) and
//! `SolveError` (1), with the CLI's one-line messages.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

use prbfit::report::ReportError;

create_exception!(
    prbfit,
    Error,
    PyException,
    "Anything prbfit refuses or fails at."
);
create_exception!(
    prbfit,
    InputError,
    Error,
    "Bad input: a scene, an argument or a file the user can fix (the CLI's exit status 2)."
);
create_exception!(
    prbfit,
    SolveError,
    Error,
    "The computation failed: a load past a critical point, a model that cannot follow the \
     scene (the CLI's exit status 1)."
);

/// Adds the exceptions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("SolveError", py.get_type::<SolveError>())?;
    Ok(())
}

/// The Python exception of a report's error.
pub fn report_error(e: ReportError) -> PyErr {
    let message = prbfit::report::safe(e.message()).into_owned();
    if e.is_input() {
        InputError::new_err(message)
    } else {
        SolveError::new_err(message)
    }
}

/// Bad input naming `argument`.
pub fn input(argument: &str, message: impl std::fmt::Display) -> PyErr {
    InputError::new_err(format!("{argument}: {message}"))
}
