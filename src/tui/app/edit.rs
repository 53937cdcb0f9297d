//! What the user edits: the scene, the PRB matrix and each panel's state (bottom's state per
//! widget: [`BeamState`], [`LoadsState`], [`MatrixState`], [`MechState`]), and the text box
//! of the field being edited. Every edit either takes a valid new scene or matrix, or changes
//! nothing and says why (`Err`); sending the job an edit calls for is the app's (its job
//! client), and so is showing the message.

use std::path::PathBuf;

use crate::beam::Effects;
use crate::io::ModelFile;
use crate::mech::MechCase;
use crate::prb::published::NAMES as PUBLISHED;
use crate::prb::{Column, PrbMatrix};
use crate::scene::{EffectsChoice, Scene};
use crate::study::CaseForm;

use super::super::panel::Panel;
use super::super::state::beam::{toggled_effect, BeamField, BeamState};
use super::super::state::checked;
use super::super::state::loads::{self, held_forces, Hold, LoadsState};
use super::super::state::matrix::MatrixState;
use super::super::state::mech::{self as mech_state, MechField, MechState};
use super::super::state::text::TextBox;
use super::super::worker::TruthView;
use super::data;

/// What a text box is editing.
#[derive(Debug, Clone, PartialEq)]
pub enum EditTarget {
    /// A field of the beam panel.
    Beam(BeamField),
    /// A cell of the load table.
    Load {
        /// The path.
        row: usize,
        /// The column, an index into [`LOAD_COLUMNS`](super::super::state::loads::LOAD_COLUMNS).
        col: usize,
    },
    /// A cell of the matrix.
    Cell {
        /// The segment.
        row: usize,
        /// The column.
        col: Column,
    },
    /// A row of the mechanism panel.
    Mech(MechField),
}

/// The scene, the model and the panels' states.
#[derive(Debug)]
pub struct Editing {
    /// The scene being edited.
    pub scene: Scene,
    /// Where it was read from or last saved to.
    pub scene_path: Option<PathBuf>,
    /// Whether the UI has saved the scene at `scene_path` itself (then saving there again
    /// is just saving); a file opened as written by hand is asked about first, as saving
    /// rewrites it in prbfit's layout without its comments.
    pub saved_here: bool,
    /// The scene changed since it was last saved.
    pub scene_dirty: bool,
    /// The PRB matrix being edited.
    pub matrix: PrbMatrix,
    /// The matrix changed since it was last exported or saved.
    pub model_dirty: bool,
    /// The matrix came from the scene's `[prb] matrix`: the first job judges it as saved.
    pub model_from_scene: bool,
    /// The panel that takes the keys.
    pub focus: Panel,
    /// The beam panel's cursor.
    pub beam_state: BeamState,
    /// The load panel's cursor.
    pub loads_state: LoadsState,
    /// The matrix panel's cursor and display mode.
    pub matrix_state: MatrixState,
    /// A mechanism scene's panel cursor and what its charts show.
    pub mech_state: MechState,
    /// The field being edited and its text.
    pub editing: Option<(EditTarget, TextBox)>,
    /// Which published model `m` loads next.
    next_published: usize,
}

/// The model a scene without its own starts from: Su's 3R (or an L-R-R-R matrix).
fn start_matrix() -> PrbMatrix {
    #[allow(clippy::expect_used)]
    ModelFile::load("su-3r").map(|m| m.prb).unwrap_or_else(|_| {
        // "L-R-R-R" is a constant the topology parser accepts (a test builds every topology
        // of the ladder), so this cannot fail.
        PrbMatrix::from_topology("L-R-R-R").expect("valid topology")
    })
}

impl Editing {
    /// Editing `scene`, starting from its own model (`[prb] matrix`) if it has one, else
    /// from Su's 3R model (or an L-R-R-R matrix). The model lives in [`Editing::matrix`];
    /// the scene's copy goes back in when it is saved ([`Editing::scene_to_save`]).
    pub fn new(mut scene: Scene, scene_path: Option<PathBuf>) -> Editing {
        let from_scene = scene.prb.take();
        let model_from_scene = from_scene.is_some();
        let matrix = from_scene.unwrap_or_else(start_matrix);
        Editing {
            scene,
            scene_path,
            scene_dirty: false,
            saved_here: false,
            matrix,
            model_dirty: false,
            model_from_scene,
            focus: Panel::Matrix,
            beam_state: BeamState::default(),
            loads_state: LoadsState::default(),
            matrix_state: MatrixState::default(),
            mech_state: MechState::default(),
            editing: None,
            next_published: 0,
        }
    }

    /// Whether the scene is a mechanism (DESIGN §8).
    pub fn is_mechanism(&self) -> bool {
        self.scene.mechanism.is_some()
    }

    /// How the scene's cases read (DESIGN §7): a cantilever's as tips under loads, a
    /// mechanism's as stage motions and loads.
    pub fn case_form(&self) -> CaseForm {
        if self.is_mechanism() {
            CaseForm::Stage
        } else {
            CaseForm::Tip
        }
    }

    /// Whether the scene's truth is measured data (DESIGN §9).
    pub fn is_data(&self) -> bool {
        data::is_data(&self.scene)
    }

    /// Whether the scene is a mechanism whose truth is measured data: its drives are the
    /// file's paths.
    pub fn is_mech_data(&self) -> bool {
        self.is_mechanism() && self.is_data()
    }

    /// The rows the load panel lists: a data scene's rows, else its load paths.
    pub fn load_rows(&self) -> usize {
        data::load_rows(&self.scene)
    }

    /// How many paths the charts can show: a mechanism's drives, else the load paths.
    pub fn path_count(&self) -> usize {
        match &self.scene.mechanism {
            Some(m) => m.drives.len(),
            None => self.scene.loads.len(),
        }
    }

    /// The path the charts show: a mechanism's shown drive, a data scene's path of the row
    /// the load panel's cursor is on, else the load panel's selected path.
    pub fn shown_path(&self) -> usize {
        if self.is_mechanism() {
            self.mech_state.shown_drive(self.path_count())
        } else if self.is_data() {
            data::path_of_row(&self.scene, self.loads_state.row)
        } else {
            self.loads_state.shown_path(self.scene.loads.len())
        }
    }

    /// `[` and `]`: the charts show the previous or next path, wrapping around.
    pub fn cycle_path(&mut self, delta: i32) {
        let paths = self.path_count();
        if self.is_mechanism() {
            self.mech_state.cycle_drive(delta, paths);
        } else if self.is_data() {
            self.loads_state.row = data::cycled_path_row(&self.scene, self.loads_state.row, delta);
        } else {
            self.loads_state.cycle_path(delta, paths);
        }
    }

    /// The beam the SI view (`u`) shows the matrix and the loads for, when it is on.
    pub fn si_beam(&self) -> Option<&crate::scene::BeamSpec> {
        self.matrix_state.si.then_some(&self.scene.beam)
    }

    /// The text of a matrix cell as the matrix panel shows it.
    pub fn cell_text(&self, row: usize, col: Column) -> String {
        self.matrix_state
            .cell_text(&self.matrix, &self.scene.beam, row, col)
    }

    /// The mechanism panel's selected row.
    pub fn mech_field(&self) -> Option<MechField> {
        self.mech_state.field(self.scene.mechanism.as_ref()?)
    }

    /// The scene as a file stores it: the model being worked on goes in as `[prb] matrix`.
    pub fn scene_to_save(&self) -> Scene {
        let mut scene = self.scene.clone();
        scene.prb = Some(self.matrix.clone());
        scene
    }

    /// The scene was written to `path`: nothing is unsaved any more.
    pub fn saved(&mut self, path: PathBuf) {
        self.scene_path = Some(path);
        self.saved_here = true;
        self.scene_dirty = false;
        self.model_dirty = false;
    }

    /// The scene was replaced (opened from `path`): nothing is unsaved, the cursors start
    /// again. A scene with its own model (`[prb] matrix`) brings it; returns whether it did.
    /// One without starts from Su's 3R, as `prbfit tui FILE` does: what an opened scene shows
    /// does not depend on the scene open before it (a 1R kept from it cannot follow a parallel
    /// stage; its pinned mass column went with another beam's gammas).
    pub fn open(&mut self, mut scene: Scene, path: PathBuf) -> bool {
        let from_scene = scene.prb.take();
        let brought = from_scene.is_some();
        self.matrix = from_scene.unwrap_or_else(start_matrix);
        self.matrix_state.clamp(self.matrix.len());
        self.scene = scene;
        self.scene_path = Some(path);
        self.saved_here = false;
        self.scene_dirty = false;
        self.model_dirty = false;
        self.loads_state.row = 0;
        self.mech_state = MechState::default();
        self.focus = self.focus.on_scene(self.is_mechanism());
        brought
    }

    /// Enter: opens the focused panel's selected field in a text box; refused (nothing
    /// opens) on what a data scene reads from its file.
    pub fn start_edit(&mut self) -> Result<(), String> {
        let (target, text) = match self.focus {
            Panel::Beam => {
                let f = self.beam_state.field(self.is_mechanism());
                (EditTarget::Beam(f), f.edit_text(&self.scene))
            }
            Panel::Mechanism => {
                let Some((m, f)) = self.scene.mechanism.as_ref().zip(self.mech_field()) else {
                    return Ok(());
                };
                if self.is_mech_data() && f.drive().is_some() {
                    return Err(data::drives_read_only(&self.scene));
                }
                (EditTarget::Mech(f), f.edit_text(m))
            }
            Panel::Loads if self.is_data() => return Err(data::loads_read_only(&self.scene)),
            Panel::Loads => {
                let (row, col) = (self.loads_state.row, self.loads_state.col);
                let text = self
                    .scene
                    .loads
                    .get(row)
                    .map(|p| loads::load_text(p, col, self.si_beam()))
                    .unwrap_or_default();
                (EditTarget::Load { row, col }, text)
            }
            Panel::Matrix => {
                let (row, col) = (self.matrix_state.row, self.matrix_state.column());
                (EditTarget::Cell { row, col }, self.cell_text(row, col))
            }
        };
        self.editing = Some((target, TextBox::new(text)));
        Ok(())
    }

    /// Applies an edit if valid; on error nothing changes.
    pub fn apply_edit(&mut self, target: &EditTarget, text: &str) -> Result<(), String> {
        match target {
            EditTarget::Beam(field) => {
                let mut scene = field.edited(&self.scene, text)?;
                // A data scene's loads are its rows: they follow the beam as its file's
                // units say (take_scene), whatever the hold.
                if self.loads_state.hold == Hold::Force && !self.is_data() {
                    scene.loads = held_forces(&scene.loads, &self.scene.beam, &scene.beam);
                }
                // The slenderness rule is the scene file's thickness key's; a length edit
                // breaks it too, and the message names what was edited.
                self.take_scene(scene).map_err(|e| match field {
                    BeamField::Length => {
                        e.replacen("beam.thickness:", "beam.length (against the thickness):", 1)
                    }
                    _ => e,
                })?;
            }
            EditTarget::Mech(field) if self.is_mech_data() && field.drive().is_some() => {
                return Err(data::drives_read_only(&self.scene));
            }
            EditTarget::Mech(field) => {
                let m = self
                    .scene
                    .mechanism
                    .as_ref()
                    .ok_or("not a mechanism scene")?;
                let mut scene = self.scene.clone();
                scene.mechanism = Some(field.edited(m, text)?);
                self.take_scene(scene)?;
            }
            EditTarget::Load { .. } if self.is_data() => {
                return Err("a data scene's loads are its file's rows (read-only)".into());
            }
            EditTarget::Load { row, col } => {
                let old = self.scene.loads.get(*row).ok_or("no such load path")?;
                let path = loads::edited(old, *col, text, self.si_beam())?;
                if path != *old {
                    self.scene.loads[*row] = path;
                    self.scene_dirty = true;
                }
            }
            EditTarget::Cell { row, col } => {
                let m =
                    self.matrix_state
                        .edited(&self.matrix, &self.scene.beam, *row, *col, text)?;
                if m != self.matrix {
                    self.matrix = m;
                    self.model_dirty = true;
                }
            }
        }
        Ok(())
    }

    /// Takes an edited scene, of any kind, if it obeys the scene file's rules
    /// ([`checked`]); the scene's own edit, [`Scene::rebased`], first carries a beam edit to
    /// a mechanism's flexures and a data scene's rows.
    fn take_scene(&mut self, scene: Scene) -> Result<(), String> {
        let scene = scene.rebased(&self.scene.beam)?;
        checked(&scene)?;
        if scene != self.scene {
            self.scene = scene;
            self.scene_dirty = true;
        }
        Ok(())
    }

    /// `p` on the mechanism panel: the selected coordinate prescribed or loaded (keeping the
    /// end state `truth` shows for its drive), or the selected flexure's next attachment that
    /// makes a valid mechanism. `Ok(false)`: nothing to do here.
    pub fn toggle_kind(&mut self, truth: Option<&TruthView>) -> Result<bool, String> {
        let (Some(m), Some(field)) = (self.scene.mechanism.as_ref(), self.mech_field()) else {
            return Ok(false);
        };
        if self.is_mech_data() && field.drive().is_some() {
            return Err(data::drives_read_only(&self.scene));
        }
        // The truth's end state of the drive, when it was solved for this drive.
        let end: Option<&MechCase> = field.drive().and_then(|d| {
            let t = truth?;
            let same = t.mechanism.drives.get(d).map(|x| x.coordinates)
                == m.drives.get(d).map(|x| x.coordinates);
            t.cases.get(d).filter(|_| same)?.last()
        });
        let choices = mech_state::toggled(m, field, end);
        if choices.is_empty() {
            return Err("p: on a drive coordinate (x, y, phi) or a flexure's attach row".into());
        }
        let mut last_error = String::new();
        for choice in choices {
            let mut scene = self.scene.clone();
            scene.mechanism = Some(choice);
            match self.take_scene(scene) {
                Ok(()) => return Ok(true),
                Err(e) => last_error = e,
            }
        }
        Err(format!("rejected: {last_error} (the old value is kept)"))
    }

    /// The model is now `m` (not from any file).
    pub fn replace_matrix(&mut self, m: PrbMatrix) {
        self.matrix = m;
        self.model_dirty = true;
        self.matrix_state.clamp(self.matrix.len());
    }

    /// `m`: the name of the next published model, round and round.
    pub fn next_published(&mut self) -> &'static str {
        let name = PUBLISHED[self.next_published % PUBLISHED.len()];
        self.next_published += 1;
        name
    }

    /// 1, 2, 3, 4 switch shear, extension, poisson, plane strain (from the effects `auto`
    /// was `decided` as); the effects taken.
    pub fn toggle_effect(
        &mut self,
        which: char,
        decided: Option<Effects>,
    ) -> Result<Effects, String> {
        let e = toggled_effect(&self.scene, decided, which);
        let mut scene = self.scene.clone();
        scene.beam.effects = EffectsChoice::Fixed(e);
        self.take_scene(scene)?;
        Ok(e)
    }

    /// `f`: the selected matrix cell fixed or free.
    pub fn toggle_free(&mut self) -> Result<(), String> {
        self.matrix = self.matrix_state.toggled_free(&self.matrix)?;
        self.model_dirty = true;
        Ok(())
    }

    /// `H`: what a beam edit keeps, the alphas or the forces; the news.
    pub fn toggle_hold(&mut self) -> &'static str {
        if let Some(m) = data::hold_message(&self.scene) {
            return m;
        }
        self.loads_state.hold = match self.loads_state.hold {
            Hold::Alpha => Hold::Force,
            Hold::Force => Hold::Alpha,
        };
        match self.loads_state.hold {
            Hold::Alpha => "hold: alpha (a beam edit keeps alpha; the forces follow)",
            Hold::Force => "hold: force (a beam edit keeps Fx, Fy, Mz; the alphas follow)",
        }
    }

    /// `a` (`add`) or `d`: a row added after the selected one or the selected row deleted,
    /// on the focused panel; `Ok(false)`: nothing to do here.
    pub fn add_or_delete_row(&mut self, add: bool) -> Result<bool, String> {
        match self.focus {
            Panel::Loads if self.is_data() => Err(data::loads_read_only(&self.scene)),
            Panel::Loads if add => {
                self.loads_state.add(&mut self.scene);
                self.scene_dirty = true;
                Ok(true)
            }
            Panel::Loads => {
                self.loads_state.delete(&mut self.scene)?;
                self.scene_dirty = true;
                Ok(true)
            }
            Panel::Matrix if add => {
                let m = self
                    .matrix_state
                    .split_row(&self.matrix)
                    .map_err(|e| format!("rejected: {e}"))?;
                self.matrix_state.row += 1;
                self.replace_matrix(m);
                Ok(true)
            }
            Panel::Matrix => {
                let m = self.matrix_state.remove_row(&self.matrix)?;
                self.replace_matrix(m);
                Ok(true)
            }
            Panel::Mechanism => self.edit_drives(add),
            Panel::Beam => Ok(false),
        }
    }

    /// `a` / `d` on the mechanism panel: a copy of the selected drive after it, or the
    /// selected drive deleted (a mechanism keeps at least one); refused on a mechanism data
    /// scene, whose drives are its file's paths.
    fn edit_drives(&mut self, add: bool) -> Result<bool, String> {
        let Some(m) = self.scene.mechanism.as_ref() else {
            return Ok(false);
        };
        if self.is_mech_data() {
            return Err(data::drives_read_only(&self.scene));
        }
        let Some(d) = self.mech_field().and_then(MechField::drive) else {
            return Err("a / d: on a drive's rows (flexures are added in the scene file)".into());
        };
        let mut new = m.clone();
        if add {
            let Some(copy) = m.drives.get(d).cloned() else {
                return Ok(false);
            };
            new.drives.insert(d + 1, copy);
        } else if m.drives.len() > 1 {
            new.drives.remove(d);
        } else {
            return Err("a mechanism needs at least one drive".into());
        }
        let mut scene = self.scene.clone();
        scene.mechanism = Some(new);
        self.take_scene(scene)
            .map_err(|e| format!("rejected: {e}"))?;
        let shown = if add { d + 1 } else { d.saturating_sub(1) };
        self.mech_state.drive = shown;
        self.mech_state.case = None;
        // The cursor to the shown drive's first row.
        if let Some(m) = &self.scene.mechanism {
            self.mech_state.row = mech_state::fields(m)
                .iter()
                .position(|f| f.drive() == Some(shown))
                .unwrap_or(0);
        }
        Ok(true)
    }

    /// The arrows: the focused panel's cursor moves (on the mechanism panel the charts
    /// follow the drive the cursor is on).
    pub fn move_cursor(&mut self, dx: i32, dy: i32) {
        let mechanism = self.is_mechanism();
        match self.focus {
            Panel::Beam => self.beam_state.move_by(dy, mechanism),
            Panel::Loads => self.loads_state.move_by(dx, dy, self.load_rows()),
            Panel::Matrix => self.matrix_state.move_by(dx, dy, self.matrix.len()),
            Panel::Mechanism => {
                let rows = self
                    .scene
                    .mechanism
                    .as_ref()
                    .map_or(0, |m| mech_state::fields(m).len());
                self.mech_state.move_by(dy, rows);
                if let Some(d) = self.mech_field().and_then(MechField::drive) {
                    if d != self.mech_state.drive {
                        self.mech_state.drive = d;
                        self.mech_state.case = None;
                        self.mech_state.chart = 0;
                    }
                }
            }
        }
    }
}
