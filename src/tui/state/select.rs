//! The model-selection view: the ladder's table (rows arrive as they are fitted), its choice
//! and the trade-off measurements, with a cursor over the rows. On a mechanism scene the
//! models that cannot follow the mechanism are listed instead of the trade-off.

use crate::study::select::{Rung, Selection, Unfollowed};
use crate::study::tradeoff::Knob;

use super::step;

/// The selection view's state.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectState {
    /// The selection job whose rows these are.
    pub job: u64,
    /// The rows so far.
    pub rows: Vec<Rung>,
    /// The simplest row meeting the targets, once known.
    pub chosen: Option<usize>,
    /// The row closest to the targets, once known.
    pub closest: Option<usize>,
    /// The trade-off measurements.
    pub knobs: Vec<Knob>,
    /// The cursor.
    pub selected: usize,
    /// The job still runs.
    pub running: bool,
    /// The job ended before its selection was made (cancelled, or failed): the rows are
    /// those fitted by then, and nothing is chosen.
    pub stopped: bool,
    /// The models tried that cannot follow the scene, once known.
    pub unfollowed: Vec<Unfollowed>,
}

impl SelectState {
    /// An empty view for selection job `job`, running.
    pub fn new(job: u64) -> SelectState {
        SelectState {
            job,
            rows: Vec::new(),
            chosen: None,
            closest: None,
            knobs: Vec::new(),
            selected: 0,
            running: true,
            stopped: false,
            unfollowed: Vec::new(),
        }
    }

    /// Moves the cursor `dy` rows.
    pub fn move_by(&mut self, dy: i32) {
        self.selected = step(self.selected, dy, self.rows.len());
    }

    /// A row of job `job` arrived; rows of another job are dropped.
    pub fn on_row(&mut self, job: u64, row: Rung) -> bool {
        if job != self.job {
            return false;
        }
        self.rows.push(row);
        true
    }

    /// The whole selection of job `job` arrived; the cursor goes to its choice.
    pub fn on_done(&mut self, job: u64, selection: Selection, knobs: Vec<Knob>) -> bool {
        if job != self.job {
            return false;
        }
        self.unfollowed = selection.unfollowed;
        self.rows = selection.rows;
        self.chosen = selection.chosen;
        self.closest = Some(selection.closest);
        self.knobs = knobs;
        self.selected = selection.chosen.unwrap_or(selection.closest);
        self.running = false;
        true
    }

    /// The row under the cursor.
    pub fn selected_row(&self) -> Option<&Rung> {
        self.rows.get(self.selected)
    }
}
