//! What the worker sends back, taken into the UI's state: models shown with the baseline they
//! were judged on, fit reports, compared models, exports, selection rows, failures.

use std::sync::Arc;

use super::*;

impl App {
    /// A message from the worker; stale ones (not the newest job's) are dropped, except an
    /// export's. A model is always shown with the baseline it was judged on, which comes with
    /// it.
    pub fn on_worker(&mut self, msg: WorkerMsg) -> bool {
        if let WorkerMsg::Compared {
            baseline, model, ..
        } = msg
        {
            // Kept like an export, and shown only while it is the compared matrix and the
            // baseline is the shown one (see shown_compare).
            let wanted = self
                .compare
                .as_ref()
                .is_some_and(|(_, m)| *m == model.matrix);
            if wanted {
                self.compare_view = Some((baseline, *model));
            }
            return wanted;
        }
        if let WorkerMsg::MechCompared { exact, model, .. } = msg {
            let wanted = self
                .compare
                .as_ref()
                .is_some_and(|(_, m)| *m == model.matrix);
            if wanted {
                self.mech_compare = Some((exact, *model));
            }
            return wanted;
        }
        if let WorkerMsg::Exported { path, result, .. } = msg {
            match result {
                Ok(()) => {
                    self.model_dirty = false;
                    self.set_info(format!("exported {}", path.display()));
                }
                Err(e) => self.set_error(format!("not exported: {e}")),
            }
            return true;
        }
        let Some((current, _)) = &self.current_job else {
            return false;
        };
        if msg.id() != *current {
            return false;
        }
        match msg {
            WorkerMsg::Progress {
                baseline,
                model,
                status,
                compare,
                ..
            } => {
                self.take_compare(&baseline, compare);
                self.baseline = Some(baseline);
                self.model = Some(*model);
                self.activity = Activity::Fitting(status);
                self.clear_worker_error();
            }
            WorkerMsg::Done {
                baseline,
                model,
                report,
                seconds,
                compare,
                ..
            } => {
                self.take_compare(&baseline, compare);
                self.finished(
                    report
                        .as_ref()
                        .map(|r| (&r.matrix, r.stop, r.iterations, r.evaluations)),
                    seconds,
                );
                self.report = report.map(|r| *r);
                self.baseline = Some(baseline);
                self.model = Some(*model);
                self.clear_worker_error();
            }
            WorkerMsg::MechProgress {
                exact,
                model,
                status,
                compare,
                ..
            } => {
                if let Some(view) = compare {
                    self.mech_compare = Some((exact.clone(), *view));
                }
                self.mech_exact = Some(exact);
                self.mech_model = Some(*model);
                self.activity = Activity::Fitting(status);
                self.clear_worker_error();
            }
            WorkerMsg::MechDone {
                exact,
                model,
                report,
                seconds,
                compare,
                ..
            } => {
                if let Some(view) = compare {
                    self.mech_compare = Some((exact.clone(), *view));
                }
                self.finished(
                    report
                        .as_ref()
                        .map(|r| (&r.matrix, r.stop, r.iterations, r.evaluations)),
                    seconds,
                );
                self.mech_exact = Some(exact);
                self.mech_model = Some(*model);
                self.clear_worker_error();
            }
            WorkerMsg::Failed { message, .. } => {
                self.set_error(message.clone());
                self.message_from_worker = true;
                self.activity = Activity::Failed(message);
                self.selection_stopped();
            }
            // Taken above, whatever its job.
            WorkerMsg::Exported { .. }
            | WorkerMsg::Compared { .. }
            | WorkerMsg::MechCompared { .. } => {}
            WorkerMsg::SelectRow { id, row } => {
                if let Some(v) = &mut self.select {
                    v.on_row(id, *row);
                }
            }
            WorkerMsg::MechSelectRow { id, row } => {
                if let Some(v) = &mut self.mech_select {
                    v.on_row(id, *row);
                }
            }
            WorkerMsg::MechSelectDone { id, selection } => {
                if let Some(row) = selection
                    .rows
                    .get(selection.chosen.unwrap_or(selection.closest))
                {
                    self.selection_model = Some((format!("{} (S)", row.name), row.prb.clone()));
                }
                if let Some(v) = &mut self.mech_select {
                    v.on_done(id, *selection, Vec::new());
                }
                self.activity = Activity::Idle;
            }
            WorkerMsg::SelectDone {
                id,
                selection,
                knobs,
            } => {
                let pick = selection.chosen.unwrap_or(selection.closest);
                if let Some(row) = selection.rows.get(pick) {
                    self.selection_model = Some((format!("{} (S)", row.name), row.prb.clone()));
                }
                if let Some(v) = &mut self.select {
                    v.on_done(id, *selection, knobs);
                }
                self.activity = Activity::Idle;
            }
        }
        true
    }

    /// A job finished: a fit's matrix (its stop reason, iterations and evaluations) replaces
    /// the free cells; the activity says how it ended.
    fn finished(&mut self, fit: Option<(&PrbMatrix, StopReason, u32, u64)>, seconds: f64) {
        let Some((matrix, stop, iterations, evaluations)) = fit else {
            self.activity = Activity::Done {
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
        if *matrix != self.matrix {
            self.matrix = matrix.clone();
            self.model_dirty |= self.current_job_by_user;
        }
        self.activity = if stop == StopReason::Cancelled {
            Activity::Cancelled
        } else {
            Activity::Done {
                seconds,
                stop: Some(stop),
                iterations,
                evaluations,
            }
        };
    }

    /// The compared model a result brought, judged on `baseline`.
    pub(super) fn take_compare(
        &mut self,
        baseline: &Arc<BaselineView>,
        compare: Option<Box<ModelView>>,
    ) {
        if let Some(view) = compare {
            self.compare_view = Some((baseline.clone(), *view));
        }
    }

    /// A good result answers the failure before it.
    pub(super) fn clear_worker_error(&mut self) {
        if self.message_from_worker {
            self.clear_message();
        }
    }
}
