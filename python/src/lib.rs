//! `prbfit` in Python (DESIGN §12): the library's scenes, matrices and command reports over
//! PyO3. Every command is the library's own report ([`prbfit::report`]), so a result's
//! `to_dict()` is the CLI's `--json` object; long calls run on a worker thread with the GIL
//! released, and Ctrl-C cancels them through the library's cancel token.

mod convert;
mod errors;
mod matrix;
mod results;
mod run;
mod scene;

use pyo3::prelude::*;

/// The native half of the `prbfit` package; `prbfit/__init__.py` re-exports it.
#[pymodule]
fn _prbfit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<matrix::Matrix>()?;
    results::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_panic_in_worker, m)?)?;
    Ok(())
}

/// For the tests: a panic on a command's worker thread, which must come out as `SolveError`
/// and never as a Rust panic.
#[pyfunction]
fn _panic_in_worker(py: Python<'_>) -> PyResult<()> {
    run::run(py, None, |_| -> prbfit::report::Result<()> {
        panic!("a deliberate panic (the module's test)")
    })
}
