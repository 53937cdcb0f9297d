//! The background worker: truth solves, evaluations, fits, selections and exports, off the
//! UI thread, for every kind of scene through the one study layer (DESIGN §7).
//!
//! The UI hands jobs to a [`LatestJob`] queue: the worker always takes the newest one (older
//! ones waiting are dropped unstarted, the running one is cancelled), and every message
//! carries its job's id so the UI can drop what a stale job still sends. Exports are side
//! effects the user asked for: they go through the queue's kept lane, are never cancelled by a
//! newer job and their result is always delivered.
//!
//! Results carry what they were computed from: every `Progress` and `Done` holds the
//! [`TruthView`] its model (and the model compared against, if any) was judged on, as does
//! a compare job's `Compared`, so no order of messages can pair a model with another scene's
//! truth, or with none. The study of the last scene is cached and solved again only when the
//! scene (beam, loads or mechanism, targets, weights, data) or the fidelity changes.
//!
//! A failure in a job (a load the beam cannot reach, even a panic) becomes a `Failed`
//! message; the worker then waits for the next job.
//!
//! - `job.rs`: the jobs and the messages;
//! - `view.rs`: the truth and model views the charts draw, one type each for every scene;
//! - `truth.rs`: a study's truth view (the shapes only one kind has, the beam beside data);
//! - `run.rs`: one job on its (cached) study;
//! - this file: the thread, its queue and its loop.

mod job;
mod run;
mod truth;
mod view;

pub use job::{FitStatus, Job, JobKind, WorkerMsg};
pub use run::{study_of, write_error};
pub use truth::truth_view;
pub use view::{model_cases, model_view, MeasuredView, ModelView, TruthView};

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::latest_job::{LatestJob, Taken};

/// The thread's name, which the panic hook uses to tell worker panics from UI panics.
pub const WORKER_THREAD: &str = "prbfit-worker";

/// How long quitting waits for the worker to notice its job was cancelled before leaving the
/// thread behind (the process is about to end).
pub const SHUTDOWN_DEADLINE: Duration = Duration::from_millis(200);

/// The worker thread, its job queue and its messages.
pub struct Worker {
    queue: LatestJob<Job>,
    /// What the worker sends back.
    pub messages: Receiver<WorkerMsg>,
    handle: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the worker thread.
    pub fn spawn() -> std::io::Result<Worker> {
        let queue = LatestJob::new();
        let (msg_tx, msg_rx) = channel::<WorkerMsg>();
        let jobs = queue.clone();
        let handle = std::thread::Builder::new()
            .name(WORKER_THREAD.into())
            .spawn(move || worker_loop(&jobs, &msg_tx))?;
        Ok(Worker {
            queue,
            messages: msg_rx,
            handle: Some(handle),
        })
    }

    /// Queues a job. An export or a compare is kept until done; any other job replaces the
    /// one waiting and cancels the one running.
    pub fn submit(&self, job: Job) {
        if matches!(job.kind, JobKind::Export { .. } | JobKind::Compare) {
            self.queue.submit_kept(job);
        } else {
            self.queue.submit(job);
        }
    }

    /// Stops the worker: cancels its job and waits up to `deadline` for the thread to end;
    /// past that the thread is left to finish on its own. Returns whether it ended.
    pub fn shutdown(mut self, deadline: Duration) -> bool {
        self.stop(deadline)
    }

    fn stop(&mut self, deadline: Duration) -> bool {
        self.queue.close();
        let Some(handle) = self.handle.take() else {
            return true;
        };
        join_within(handle, deadline).is_some()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.stop(SHUTDOWN_DEADLINE);
    }
}

/// Joins `handle` if its thread ends within `deadline`; otherwise detaches it and returns
/// `None`.
pub fn join_within<T>(handle: JoinHandle<T>, deadline: Duration) -> Option<std::thread::Result<T>> {
    let t0 = Instant::now();
    while !handle.is_finished() {
        if t0.elapsed() >= deadline {
            return None;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Some(handle.join())
}

fn worker_loop(jobs: &LatestJob<Job>, out: &Sender<WorkerMsg>) {
    let mut cache = None;
    while let Some(taken) = jobs.take() {
        if taken.job.cancel.is_cancelled() {
            continue;
        }
        let id = taken.job.id;
        let send = |msg: WorkerMsg| deliver(jobs, &taken, out, msg);
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            run::run_job(&taken.job, &mut cache, &send)
        }));
        let failure = match outcome {
            Ok(Ok(())) => None,
            Ok(Err(message)) => Some(message),
            Err(panic) => {
                cache = None;
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                Some(format!("internal error in the worker: {what}"))
            }
        };
        // A cancelled job's failure (its solve stopped on the token) is no news: a newer job
        // or the user's cancel already speaks for it.
        if let Some(message) = failure.filter(|_| !taken.job.cancel.is_cancelled()) {
            if out.send(WorkerMsg::Failed { id, message }).is_err() {
                return;
            }
        }
    }
}

/// Sends a job's message, unless a newer job was submitted since (the UI would drop it; an
/// export is never stale).
fn deliver(jobs: &LatestJob<Job>, taken: &Taken<Job>, out: &Sender<WorkerMsg>, msg: WorkerMsg) {
    if !jobs.is_stale(taken) {
        // The UI has gone: nothing left to do.
        let _ = out.send(msg);
    }
}
