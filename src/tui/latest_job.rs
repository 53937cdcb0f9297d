//! A newest-job queue between the UI and its worker thread.
//!
//! Shaped like gitui's `AsyncSingleJob`: only the newest job matters. Submitting a job
//! replaces the one waiting (which never runs) and cancels the one running, so a burst of
//! edits costs one solve, not one per keystroke. The worker [`LatestJob::take`]s the newest
//! job; a job taken is current until a newer one is submitted, after which
//! [`LatestJob::is_stale`] tells the worker its results are no longer wanted.
//!
//! Side effects the user asked for (an export) must neither be replaced nor cancelled by a
//! newer edit: they go into a second lane, [`LatestJob::submit_kept`], a first-in first-out
//! queue whose jobs all run, before the newest job.

use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};

use crate::cancel::CancelToken;

/// A job that carries its own cancel token.
pub trait Cancellable {
    /// The token the job's computation checks.
    fn cancel_token(&self) -> &CancelToken;
}

/// The queue; clones share it (one for the UI, one for the worker).
#[derive(Debug)]
pub struct LatestJob<J> {
    shared: Arc<Shared<J>>,
}

impl<J> Clone for LatestJob<J> {
    fn clone(&self) -> Self {
        LatestJob {
            shared: self.shared.clone(),
        }
    }
}

#[derive(Debug)]
struct Shared<J> {
    state: Mutex<State<J>>,
    ready: Condvar,
}

#[derive(Debug)]
struct State<J> {
    /// The newest job not yet taken, with its sequence number.
    waiting: Option<(u64, J)>,
    /// The token of the newest-lane job being worked on.
    running: Option<CancelToken>,
    /// Jobs that all run, in order.
    kept: VecDeque<J>,
    /// The sequence number of the newest job submitted.
    newest: u64,
    closed: bool,
}

/// A job taken off the queue.
#[derive(Debug)]
pub struct Taken<J> {
    /// The job.
    pub job: J,
    /// Its sequence number in the newest-job lane; `None` for a kept job (never stale).
    seq: Option<u64>,
}

impl<J> Taken<J> {
    /// Whether the job came from the kept lane (its result is always wanted).
    pub fn is_kept(&self) -> bool {
        self.seq.is_none()
    }
}

impl<J: Cancellable> Default for LatestJob<J> {
    fn default() -> Self {
        LatestJob::new()
    }
}

impl<J: Cancellable> LatestJob<J> {
    /// An empty, open queue.
    pub fn new() -> LatestJob<J> {
        LatestJob {
            shared: Arc::new(Shared {
                state: Mutex::new(State {
                    waiting: None,
                    running: None,
                    kept: VecDeque::new(),
                    newest: 0,
                    closed: false,
                }),
                ready: Condvar::new(),
            }),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State<J>> {
        // The state stays consistent through every operation (no user code runs under the
        // lock), so a panic elsewhere while holding it leaves nothing half-done.
        self.shared
            .state
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }

    /// Makes `job` the newest: the waiting job is dropped (its token cancelled) and the
    /// running one is cancelled.
    pub fn submit(&self, job: J) {
        let mut s = self.lock();
        if s.closed {
            job.cancel_token().cancel();
            return;
        }
        if let Some(t) = &s.running {
            t.cancel();
        }
        s.newest += 1;
        let seq = s.newest;
        if let Some((_, old)) = s.waiting.replace((seq, job)) {
            old.cancel_token().cancel();
        }
        drop(s);
        self.shared.ready.notify_all();
    }

    /// Queues `job` to run after the jobs kept before it, whatever is submitted later.
    pub fn submit_kept(&self, job: J) {
        let mut s = self.lock();
        if s.closed {
            return;
        }
        s.kept.push_back(job);
        drop(s);
        self.shared.ready.notify_all();
    }

    /// Waits for the next job: a kept one first, else the newest. `None` once closed.
    pub fn take(&self) -> Option<Taken<J>> {
        let mut s = self.lock();
        // Whatever ran before has finished: it can no longer be cancelled.
        s.running = None;
        loop {
            if s.closed {
                return None;
            }
            if let Some(job) = s.kept.pop_front() {
                return Some(Taken { job, seq: None });
            }
            if let Some((seq, job)) = s.waiting.take() {
                s.running = Some(job.cancel_token().clone());
                return Some(Taken {
                    job,
                    seq: Some(seq),
                });
            }
            s = self
                .shared
                .ready
                .wait(s)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Whether a newer job was submitted after `taken` (its results are not wanted).
    pub fn is_stale(&self, taken: &Taken<J>) -> bool {
        taken.seq.is_some_and(|seq| seq != self.lock().newest)
    }

    /// Closes the queue: the waiting and running jobs are cancelled, kept jobs not started
    /// are dropped, and [`LatestJob::take`] returns `None` from now on.
    pub fn close(&self) {
        let mut s = self.lock();
        s.closed = true;
        if let Some(t) = s.running.take() {
            t.cancel();
        }
        if let Some((_, job)) = s.waiting.take() {
            job.cancel_token().cancel();
        }
        s.kept.clear();
        drop(s);
        self.shared.ready.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;
    use std::time::Duration;

    #[derive(Debug)]
    struct TestJob {
        n: u32,
        cancel: CancelToken,
    }

    impl Cancellable for TestJob {
        fn cancel_token(&self) -> &CancelToken {
            &self.cancel
        }
    }

    fn job(n: u32) -> TestJob {
        TestJob {
            n,
            cancel: CancelToken::new(),
        }
    }

    /// Three jobs submitted while one runs: only the last of them runs next.
    #[test]
    fn overwrite() {
        let q = LatestJob::new();
        q.submit(job(1));
        let running = q.take().unwrap();
        assert_eq!(running.job.n, 1);
        let (a, b, c) = (job(2), job(3), job(4));
        let (ta, tb) = (a.cancel.clone(), b.cancel.clone());
        q.submit(a);
        q.submit(b);
        q.submit(c);
        assert!(
            ta.is_cancelled() && tb.is_cancelled(),
            "replaced, never run"
        );
        let next = q.take().unwrap();
        assert_eq!(next.job.n, 4);
        assert!(!next.job.cancel.is_cancelled());
        // Nothing else waits: a worker on another thread would block.
        let (tx, rx) = channel();
        let q2 = q.clone();
        let worker = std::thread::spawn(move || {
            while let Some(t) = q2.take() {
                tx.send(t.job.n).unwrap();
            }
        });
        assert!(rx.recv_timeout(Duration::from_millis(50)).is_err());
        q.submit(job(5));
        assert_eq!(rx.recv_timeout(Duration::from_secs(5)).unwrap(), 5);
        q.close();
        worker.join().unwrap();
    }

    /// A newer submit cancels the running job's token; the newer one is not cancelled.
    #[test]
    fn cancel() {
        let q = LatestJob::new();
        q.submit(job(1));
        let running = q.take().unwrap();
        assert!(!running.job.cancel.is_cancelled());
        q.submit(job(2));
        assert!(running.job.cancel.is_cancelled());
        let next = q.take().unwrap();
        assert!(!next.job.cancel.is_cancelled());
        // Closing cancels what runs and ends the worker's loop.
        q.close();
        assert!(next.job.cancel.is_cancelled());
        assert!(q.take().is_none());
    }

    /// A job's results are wanted only until a newer job is submitted.
    #[test]
    fn no_stale_delivery() {
        let q = LatestJob::new();
        q.submit(job(1));
        let first = q.take().unwrap();
        assert!(!q.is_stale(&first));
        q.submit(job(2));
        assert!(q.is_stale(&first));
        let second = q.take().unwrap();
        assert!(!q.is_stale(&second));
    }

    /// Kept jobs are neither replaced nor cancelled by newer submits, run in order, and
    /// before the newest job; their results are never stale.
    #[test]
    fn kept_jobs_all_run() {
        let q = LatestJob::new();
        q.submit(job(1));
        let running = q.take().unwrap();
        q.submit_kept(job(10));
        q.submit_kept(job(11));
        q.submit(job(2));
        q.submit(job(3));
        assert!(running.job.cancel.is_cancelled());
        let a = q.take().unwrap();
        q.submit(job(4));
        assert_eq!(a.job.n, 10);
        assert!(a.is_kept() && !q.is_stale(&a));
        assert!(
            !a.job.cancel.is_cancelled(),
            "a newer submit leaves it alone"
        );
        let b = q.take().unwrap();
        assert_eq!(b.job.n, 11);
        assert_eq!(q.take().unwrap().job.n, 4);
    }
}
