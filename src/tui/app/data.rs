//! A data scene in the UI (DESIGN §9): its loads are its file's rows, shown read-only (the
//! load panel's cursor moves over the rows, and the shape chart follows the path of the
//! row it is on); a beam edit converts SI rows again with the new nominal beam, as reading
//! the file with that beam would. A mechanism data scene's drives are its file's measured
//! paths, read-only the same way (its flexures, stage and beam stay editable: the rows are
//! SI, so an edit changes nothing physical in them).

use super::*;

impl App {
    /// Whether the scene's truth is measured data (DESIGN §9).
    pub fn is_data(&self) -> bool {
        self.scene.truth.is_some()
    }

    /// The rows the load panel lists: a data scene's rows, else its load paths.
    pub fn load_rows(&self) -> usize {
        match &self.scene.truth {
            Some(t) => t.row_count(),
            None => self.scene.loads.len(),
        }
    }

    /// A data scene's path (0-based) holding row `row` (0-based over all paths).
    pub(super) fn path_of_row(&self, row: usize) -> usize {
        let Some(t) = &self.scene.truth else {
            return row;
        };
        let mut start = 0;
        for (i, p) in t.paths.iter().enumerate() {
            start += p.rows.len();
            if row < start {
                return i;
            }
        }
        t.paths.len().saturating_sub(1)
    }

    /// `[` and `]` on a data scene: the cursor to the first row of the previous or next path,
    /// wrapping around.
    pub(super) fn cycle_data_path(&mut self, delta: i32) {
        let Some(t) = &self.scene.truth else {
            return;
        };
        let n = t.paths.len().max(1) as i64;
        let path = (self.path_of_row(self.loads_state.row) as i64 + delta as i64).rem_euclid(n);
        self.loads_state.row = t.paths[..path as usize].iter().map(|p| p.rows.len()).sum();
    }

    /// An edit of a data scene's loads (a cell, a row added or deleted) is refused, saying
    /// where the loads come from; nothing changes.
    pub(super) fn refuse_load_edit(&mut self) {
        let file = self.scene.truth.as_ref().map_or("", |t| t.file.as_str());
        self.set_error(format!(
            "read-only: a data scene's loads are the rows of {file} (DESIGN §9); edit the file \
             and open the scene again"
        ));
    }

    /// Whether the scene is a mechanism whose truth is measured data: its drives are the
    /// file's paths.
    pub fn is_mech_data(&self) -> bool {
        self.is_mechanism() && self.is_data()
    }

    /// An edit of a mechanism data scene's drives (a coordinate, its steps, `p` on one, a
    /// drive added or deleted) is refused, saying where the drives come from; nothing
    /// changes.
    pub(super) fn refuse_drive_edit(&mut self) {
        self.set_error(drives_read_only(
            self.scene.truth.as_ref().map_or("", |t| t.file.as_str()),
        ));
    }

    /// `H` on a data scene: the rows' units decide what a beam edit keeps.
    pub(super) fn data_hold_message(&mut self) {
        let Some(t) = &self.scene.truth else {
            return;
        };
        self.set_info(match t.units {
            Units::Si => {
                "hold: a data scene keeps its rows' N, N m and m; a beam edit converts them \
                 again (the alphas follow the beam)"
            }
            Units::Nondimensional => {
                "hold: a data scene keeps its rows' alpha, beta, a, b (nondimensional in the \
                 file): a beam edit leaves them"
            }
        });
    }

    /// `scene`, a beam edit of the current one, with its data converted again with the
    /// edited beam and its load paths following the rows: the scene's own edit,
    /// [`Scene::rebased`].
    pub(super) fn rebase_data(&self, scene: Scene) -> Result<Scene, String> {
        scene.rebased(&self.scene.beam)
    }
}

/// Why a mechanism data scene's drives cannot be edited.
pub(super) fn drives_read_only(file: &str) -> String {
    format!(
        "read-only: a mechanism data scene's drives are the rows of {file} (DESIGN §9); edit \
         the file and open the scene again"
    )
}
