//! The app's job client (gitui's newest-job queue, seen from the UI): how finely jobs run
//! and whether edits refit, the jobs it has sent and the one that counts, the debounce of
//! edits, and where the worker is with the newest job ([`Activity`]). It makes jobs from what
//! it is given; it knows nothing of the panels or of what is shown.

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::cancel::CancelToken;
use crate::fit::{Fidelity, StopReason};
use crate::prb::PrbMatrix;
use crate::scene::Scene;

use super::super::worker::{FitStatus, Job, JobKind};

/// Edits closer together than this are sent as one job.
pub const DEBOUNCE: Duration = Duration::from_millis(30);

/// Where the worker is with the latest job.
#[derive(Debug, Clone, PartialEq)]
pub enum Activity {
    /// Nothing asked.
    Idle,
    /// Sent, nothing back yet.
    Waiting,
    /// Fitting, this far.
    Fitting(FitStatus),
    /// Finished.
    Done {
        /// How long the job took.
        seconds: f64,
        /// Why the fit stopped (none for a judge job).
        stop: Option<StopReason>,
        /// Fit iterations.
        iterations: u32,
        /// Objective evaluations.
        evaluations: u64,
    },
    /// Failed, saying why.
    Failed(String),
    /// The fit was cancelled.
    Cancelled,
}

/// A job waiting out the debounce.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pending {
    /// When the change behind it was accepted.
    at: Instant,
    /// Fit (else judge).
    fit: bool,
    /// The user asked for it (an edit), not the program (start-up, open).
    by_user: bool,
}

/// The jobs sent to the worker and where it is with them.
#[derive(Debug)]
pub struct JobClient {
    /// How finely jobs solve and fit.
    pub fidelity: Fidelity,
    /// Every edit refits (else it is only judged).
    pub live: bool,
    /// The newest job sent and its cancel token.
    pub current: Option<(u64, CancelToken)>,
    /// Where the worker is.
    pub activity: Activity,
    /// When the edit behind the newest job was accepted (for timing the UI's response).
    pub edit_accepted_at: Option<Instant>,
    counter: u64,
    /// An accepted edit waiting out the debounce.
    pending: Option<Pending>,
    /// The newest job was asked for by the user (an edit, `r`), so the model it fits is the
    /// user's work.
    by_user: bool,
}

impl Default for JobClient {
    fn default() -> JobClient {
        JobClient {
            fidelity: Fidelity::Normal,
            live: true,
            current: None,
            activity: Activity::Idle,
            edit_accepted_at: None,
            counter: 0,
            pending: None,
            by_user: false,
        }
    }
}

impl JobClient {
    /// A new job of `kind` on `scene` and `matrix` (and the `compare` model), numbered after
    /// every job before it.
    pub fn job(
        &mut self,
        kind: JobKind,
        scene: &Scene,
        matrix: &PrbMatrix,
        compare: Option<&PrbMatrix>,
    ) -> Job {
        self.counter += 1;
        Job {
            id: self.counter,
            scene: Arc::new(scene.clone()),
            matrix: matrix.clone(),
            compare: compare.cloned(),
            fidelity: self.fidelity,
            kind,
            cancel: CancelToken::new(),
        }
    }

    /// `job` becomes the newest: the one before is cancelled, the debounce ends, and
    /// `by_user` says whether the user asked for it.
    pub fn send(&mut self, job: &Job, by_user: bool) {
        self.cancel();
        self.current = Some((job.id, job.cancel.clone()));
        self.activity = Activity::Waiting;
        self.edit_accepted_at = self.pending.map(|p| p.at);
        self.pending = None;
        self.by_user = by_user;
    }

    /// Cancels the newest job (its messages still come, and are taken, until it stops).
    pub fn cancel(&self) {
        if let Some((_, token)) = &self.current {
            token.cancel();
        }
    }

    /// Whether `id` is the newest job.
    pub fn is_current(&self, id: u64) -> bool {
        self.current.as_ref().is_some_and(|(c, _)| *c == id)
    }

    /// The newest job's id (0 before any).
    pub fn current_id(&self) -> u64 {
        self.current.as_ref().map_or(0, |(id, _)| *id)
    }

    /// Whether the newest job was asked for by the user.
    pub fn by_user(&self) -> bool {
        self.by_user
    }

    /// Whether the worker is on the newest job (nothing back yet, or fitting).
    pub fn busy(&self) -> bool {
        matches!(self.activity, Activity::Waiting | Activity::Fitting(_))
    }

    /// An edit was accepted: (re)start the debounce; the job fits when live refit is on.
    pub fn changed(&mut self, now: Instant) {
        self.pending = Some(Pending {
            at: now,
            fit: self.live,
            by_user: true,
        });
    }

    /// The program (not the user) wants the model judged (or, with `fit`, fitted) again:
    /// after an open, or back from the selection view.
    pub fn refresh(&mut self, now: Instant, fit: bool) {
        self.pending = Some(Pending {
            at: now,
            fit,
            by_user: false,
        });
    }

    /// The change waiting is judged, not fitted, even with live refit on.
    pub fn judge_only(&mut self) {
        if let Some(p) = &mut self.pending {
            p.fit = false;
        }
    }

    /// Drops the change waiting.
    pub fn drop_pending(&mut self) {
        self.pending = None;
    }

    /// Whether a debounced job is waiting.
    pub fn has_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// The debounced job due at `now`: its kind and whether the user asked for it.
    pub fn due(&self, now: Instant) -> Option<(JobKind, bool)> {
        let p = self
            .pending
            .filter(|p| now.duration_since(p.at) >= DEBOUNCE)?;
        Some((kind(p.fit), p.by_user))
    }
}

/// A fit or, without `fit`, a judge.
pub fn kind(fit: bool) -> JobKind {
    if fit {
        JobKind::Fit
    } else {
        JobKind::Judge
    }
}
