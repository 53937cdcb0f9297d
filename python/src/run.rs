//! Running a command off the GIL: the work goes to a worker thread while the calling thread
//! waits in short slices with the GIL released, taking it back between slices only to check
//! for signals (Ctrl-C cancels the work through the library's cancel token, the one the UI
//! uses) and to call the progress callback. A panic in the work is caught and raised as
//! `SolveError`: none reaches Python.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use prbfit::cancel::CancelToken;
use prbfit::report::{self, Control, Progress};

use crate::errors;

/// How long the calling thread waits, GIL released, between signal checks.
const SLICE: Duration = Duration::from_millis(20);

/// How long the calling thread first polls for the result (yielding its core to the worker)
/// before it sleeps: a short call (one beam solve, tens of microseconds) then returns without
/// the wake-up of a sleeping thread.
const SPIN: Duration = Duration::from_micros(100);

/// The first message: polled for [`SPIN`], then waited for up to [`SLICE`].
fn first_message<T>(rx: &mpsc::Receiver<T>) -> Result<T, RecvTimeoutError> {
    let t0 = std::time::Instant::now();
    while t0.elapsed() < SPIN {
        match rx.try_recv() {
            Ok(m) => return Ok(m),
            Err(mpsc::TryRecvError::Disconnected) => return Err(RecvTimeoutError::Disconnected),
            Err(mpsc::TryRecvError::Empty) => std::thread::yield_now(),
        }
    }
    rx.recv_timeout(SLICE)
}

/// A fit's progress, owned, for the callback.
struct FitSnapshot {
    phase: &'static str,
    iteration: u32,
    evaluations: u64,
    best_objective: f64,
    best: String,
    seconds: f64,
}

enum Message {
    Fit(FitSnapshot),
    Done,
}

/// Runs `work` on a worker thread with the GIL released; `callback` (a fit's progress) is
/// called on this thread with the newest progress as a dict. Ctrl-C or an exception in the
/// callback cancels the work and is raised once the worker has stopped.
pub fn run<T, F>(py: Python<'_>, callback: Option<&Bound<'_, PyAny>>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&mut Control<'_>) -> report::Result<T> + Send,
{
    let cancel = CancelToken::new();
    let (tx, rx) = mpsc::channel::<Message>();
    let wants_progress = callback.is_some();
    std::thread::scope(|s| {
        let worker_cancel = cancel.clone();
        let handle = s.spawn(move || {
            let out = catch_unwind(AssertUnwindSafe(|| {
                let progress_tx = tx.clone();
                let mut progress = |p: &Progress<'_>| {
                    if let (true, Progress::Fit(f)) = (wants_progress, p) {
                        let _ = progress_tx.send(Message::Fit(FitSnapshot {
                            phase: f.phase,
                            iteration: f.iteration,
                            evaluations: f.evaluations,
                            best_objective: f.best_objective,
                            best: f.best.to_text(),
                            seconds: f.seconds,
                        }));
                    }
                };
                let mut ctl = Control {
                    cancel: worker_cancel,
                    progress: &mut progress,
                };
                work(&mut ctl)
            }));
            let _ = tx.send(Message::Done);
            out
        });
        let mut failure: Option<PyErr> = None;
        let mut rx = rx;
        let mut spin = true;
        loop {
            // The receiver goes into the GIL-free wait and back (it is Send, not Sync).
            let (first, back) = py.detach(move || {
                let m = if spin {
                    first_message(&rx)
                } else {
                    rx.recv_timeout(SLICE)
                };
                (m, rx)
            });
            rx = back;
            spin = false;
            // The newest of what has come: the callback sees the latest progress only.
            let mut latest = None;
            let mut done = false;
            let mut next = Some(first);
            while let Some(m) = next.take() {
                match m {
                    Ok(Message::Fit(f)) => latest = Some(f),
                    Ok(Message::Done) | Err(RecvTimeoutError::Disconnected) => done = true,
                    Err(RecvTimeoutError::Timeout) => {}
                }
                if let Ok(m) = rx.try_recv() {
                    next = Some(Ok(m));
                }
            }
            if let (Some(f), Some(cb), None) = (latest, callback, &failure) {
                if let Err(e) = call(py, cb, &f) {
                    cancel.cancel();
                    failure = Some(e);
                }
            }
            if done {
                break;
            }
            if failure.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.cancel();
                    failure = Some(e);
                }
            }
        }
        let joined = py.detach(|| handle.join());
        if let Some(e) = failure {
            return Err(e);
        }
        match joined {
            Ok(Ok(Ok(t))) => Ok(t),
            Ok(Ok(Err(e))) => Err(errors::report_error(e)),
            Ok(Err(panic)) | Err(panic) => Err(errors::SolveError::new_err(format!(
                "internal error (please report it): {}",
                panic_text(&panic)
            ))),
        }
    })
}

/// Calls the progress callback with one dict.
fn call(py: Python<'_>, cb: &Bound<'_, PyAny>, f: &FitSnapshot) -> PyResult<()> {
    let d = PyDict::new(py);
    d.set_item("phase", f.phase)?;
    d.set_item("iteration", f.iteration)?;
    d.set_item("evaluations", f.evaluations)?;
    d.set_item("best_objective", f.best_objective)?;
    d.set_item("best", &f.best)?;
    d.set_item("seconds", f.seconds)?;
    cb.call1((d,))?;
    Ok(())
}

/// A panic's message.
fn panic_text(p: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic".to_string()
    }
}
