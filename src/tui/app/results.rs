//! What the worker sends back, taken into the app: models shown with the truth they were
//! judged on (one result slot, whatever the scene), fit reports, compared models, exports,
//! selection rows, failures.

use crate::fit::{FitReport, StopReason};

use super::super::worker::WorkerMsg;
use super::{Activity, App};

impl App {
    /// A message from the worker; stale ones (not the newest job's) are dropped, except an
    /// export's and a compared model's. A model is always shown with the truth it was judged
    /// on, which comes with it. Returns whether the message was taken.
    pub fn on_worker(&mut self, msg: WorkerMsg) -> bool {
        match msg {
            // Kept like an export, and shown only while it is the compared matrix and the
            // truth is the shown one (see Shown::shown_compare).
            WorkerMsg::Compared { truth, model, .. } => self.shown.take_compared(truth, *model),
            WorkerMsg::Exported { path, result, .. } => {
                match result {
                    Ok(()) => {
                        self.edit.model_dirty = false;
                        self.set_info(format!("exported {}", path.display()));
                    }
                    Err(e) => self.set_error(format!("not exported: {e}")),
                }
                true
            }
            msg if !self.jobs.is_current(msg.id()) => false,
            WorkerMsg::Progress {
                truth,
                model,
                status,
                compare,
                ..
            } => {
                self.shown.take(truth, *model, compare.map(|c| *c));
                self.jobs.activity = Activity::Fitting(status);
                self.clear_worker_error();
                true
            }
            WorkerMsg::Done {
                truth,
                model,
                report,
                seconds,
                compare,
                ..
            } => {
                let stop = model.unfollowed.first().map(|u| {
                    let paths = model.unfollowed.len();
                    format!(
                        "the model stops on {paths} path{} (path {} at {:.3} of it: {}); its \
                         figures are over the cases it followed",
                        if paths == 1 { "" } else { "s" },
                        u.path,
                        u.fraction,
                        u.reason
                    )
                });
                self.shown.take(truth, *model, compare.map(|c| *c));
                self.finished(report.as_deref(), seconds);
                self.shown.report = report.map(|r| *r);
                self.clear_worker_error();
                if let Some(stop) = stop {
                    self.set_error(stop);
                    self.message_from_worker = true;
                }
                true
            }
            WorkerMsg::Failed { message, .. } => {
                // The figures and charts shown were judged on the scene and matrix before
                // this job's edit: shown beside its failure, they would pass for its own.
                self.shown.clear_result();
                self.shown.report = None;
                self.set_error(message.clone());
                self.message_from_worker = true;
                self.jobs.activity = Activity::Failed(message);
                self.shown.selection_stopped();
                true
            }
            WorkerMsg::Fitting { status, .. } => {
                self.jobs.activity = Activity::Fitting(status);
                true
            }
            WorkerMsg::SelectRow { id, row } => {
                self.shown.take_row(id, *row);
                // That row's fit is over: "working" until the next one reports (the published
                // rows and the trade-off have no fit to show).
                self.jobs.activity = Activity::Waiting;
                true
            }
            WorkerMsg::SelectDone {
                id,
                selection,
                knobs,
            } => {
                self.shown.take_selection(id, *selection, knobs);
                self.jobs.activity = Activity::Idle;
                true
            }
        }
    }

    /// A job finished: a fit's matrix replaces the free cells; the activity says how it
    /// ended (its stop reason, iterations and evaluations; none for a judge job).
    fn finished(&mut self, fit: Option<&FitReport>, seconds: f64) {
        let Some(r) = fit else {
            self.jobs.activity = Activity::Done {
                seconds,
                stop: None,
                iterations: 0,
                evaluations: 0,
            };
            return;
        };
        // The fitted values replace the free cells (not an edit: no refit). They are the
        // user's work when the user asked for this fit (`r`, or the live refit of an edit);
        // the fit the program started (start-up, open) changes nothing the user would lose.
        if r.matrix != self.edit.matrix {
            self.edit.matrix = r.matrix.clone();
            self.edit.model_dirty |= self.jobs.by_user();
        }
        self.jobs.activity = if r.stop == StopReason::Cancelled {
            Activity::Cancelled
        } else {
            Activity::Done {
                seconds,
                stop: Some(r.stop),
                iterations: r.iterations,
                evaluations: r.evaluations,
            }
        };
    }

    /// A good result answers the failure before it.
    fn clear_worker_error(&mut self) {
        if self.message_from_worker {
            self.clear_message();
        }
    }
}
