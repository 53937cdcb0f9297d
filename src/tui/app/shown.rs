//! What the app shows of the worker's answers, for every kind of scene: one result slot
//! (the model and the truth it was judged on, [`Judged`]), the last fit's report, the model
//! compared against and its result, and the selection view. The charts draw from here; the
//! panels being edited are in [`Editing`](super::edit::Editing).

use std::sync::Arc;

use crate::beam::Effects;
use crate::fit::FitReport;
use crate::prb::PrbMatrix;
use crate::study::select::{Rung, Selection};
use crate::study::tradeoff::Knob;

use super::super::state::select::SelectState;
use super::super::worker::{ModelView, TruthView};

/// A model and the truth it was judged on: they always travel together.
#[derive(Debug, Clone, PartialEq)]
pub struct Judged {
    /// The truth (beam, beam mechanism or measured data) the model was judged on.
    pub truth: Arc<TruthView>,
    /// The model.
    pub model: ModelView,
}

/// What is shown.
#[derive(Debug, Clone, Default)]
pub struct Shown {
    /// The model shown, with the truth it was judged on.
    pub result: Option<Judged>,
    /// The last fit's report.
    pub report: Option<FitReport>,
    /// The model compared against (`C`): its name and matrix.
    pub compare: Option<(String, PrbMatrix)>,
    /// The compared model as judged, with the truth it was judged on.
    pub compared: Option<Judged>,
    /// The selection view, when open.
    pub select: Option<SelectState>,
    /// The last selection's model (its choice, else the closest row), which `C` offers.
    pub selection_model: Option<(String, PrbMatrix)>,
}

impl Shown {
    /// The truth the shown model was judged on.
    pub fn truth(&self) -> Option<&TruthView> {
        self.result.as_ref().map(|r| &*r.truth)
    }

    /// The shown model.
    pub fn model(&self) -> Option<&ModelView> {
        self.result.as_ref().map(|r| &r.model)
    }

    /// A result to show: the model and the truth it was judged on, and the compared model
    /// judged on the same truth, if it came with it.
    pub fn take(&mut self, truth: Arc<TruthView>, model: ModelView, compare: Option<ModelView>) {
        if let Some(model) = compare {
            self.compared = Some(Judged {
                truth: truth.clone(),
                model,
            });
        }
        self.result = Some(Judged { truth, model });
    }

    /// A compare job's model: kept while it is the compared matrix (and drawn only with the
    /// truth it was judged on, [`Shown::shown_compare`]); whether it was.
    pub fn take_compared(&mut self, truth: Arc<TruthView>, model: ModelView) -> bool {
        let wanted = self
            .compare
            .as_ref()
            .is_some_and(|(_, m)| *m == model.matrix);
        if wanted {
            self.compared = Some(Judged { truth, model });
        }
        wanted
    }

    /// Nothing of the last scene is shown (another scene was opened, or the job answering an
    /// edit failed).
    pub fn clear_result(&mut self) {
        self.result = None;
        self.compared = None;
    }

    /// The compared model to draw: its name and view, when it was judged for the compared
    /// matrix on the truth the shown model was judged on (never another scene's).
    pub fn shown_compare(&self) -> Option<(&str, &ModelView)> {
        let (name, matrix) = self.compare.as_ref()?;
        let compared = self.compared.as_ref()?;
        let shown = &self.result.as_ref()?.truth;
        let same = Arc::ptr_eq(&compared.truth, shown) || *compared.truth == **shown;
        (same && compared.model.matrix == *matrix).then_some((name.as_str(), &compared.model))
    }

    /// What the scene's `auto` effects were decided as, once the worker decided them.
    pub fn decided_effects(&self) -> Option<Effects> {
        Some(self.truth()?.decision.as_ref()?.effects)
    }

    /// Whether the selection view is open.
    pub fn selection_open(&self) -> bool {
        self.select.is_some()
    }

    /// Whether the open selection's job still runs.
    pub fn selection_running(&self) -> bool {
        self.select.as_ref().is_some_and(|v| v.running)
    }

    /// The open selection's job ended before its selection was made (failed, stopped).
    pub fn selection_stopped(&mut self) {
        if let Some(v) = &mut self.select {
            v.stopped |= v.running;
            v.running = false;
        }
    }

    /// The model of the row under the open selection's cursor: its name and matrix.
    pub fn selected_model(&self) -> Option<(String, PrbMatrix)> {
        let row = self.select.as_ref()?.selected_row()?;
        Some((row.name.clone(), row.prb.clone()))
    }

    /// A selection row of job `id`.
    pub fn take_row(&mut self, id: u64, row: Rung) {
        if let Some(v) = &mut self.select {
            v.on_row(id, row);
        }
    }

    /// The whole selection of job `id`: its model (the choice, else the closest row) is
    /// offered to `C`.
    pub fn take_selection(&mut self, id: u64, selection: Selection, knobs: Vec<Knob>) {
        if let Some(row) = selection
            .rows
            .get(selection.chosen.unwrap_or(selection.closest))
        {
            self.selection_model = Some((format!("{} (S)", row.name), row.prb.clone()));
        }
        if let Some(v) = &mut self.select {
            v.on_done(id, selection, knobs);
        }
    }
}
