//! The key handling: one key at a time to whatever has it (the prompt, the field being
//! edited, the help, the selection view, else the focused panel), each through the
//! [`keymap`], so the keys, the help and the hint line cannot drift apart.

use std::time::Instant;

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::fit::Fidelity;
use crate::prb::{Column, PrbMatrix};

use super::super::keymap::{self, Action, Scope};
use super::dialog::{text_action, TextKey};
use super::{App, Command, EditTarget, PromptKind};

impl App {
    /// Handles one key; returns the commands it causes.
    pub fn on_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        if key.kind == KeyEventKind::Release {
            return Vec::new();
        }
        let ctrl_c =
            key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL);
        if self.too_small {
            // Only the "too small" note is drawn: no key acts on what cannot be seen, but q
            // and Ctrl-C (the note says so) and the answer to a question the note shows.
            let question = self.prompt.as_ref().is_some_and(|(k, _)| k.is_question());
            let quit = ctrl_c || key.code == KeyCode::Char('q');
            if question {
                return self.prompt_key(key, ctrl_c, now);
            }
            if !quit {
                return Vec::new();
            }
            // A text prompt or field edit open behind the note is dropped (its text was not
            // accepted), then quitting asks as it always does.
            self.drop_prompt();
            self.edit.editing = None;
            self.request_quit();
            return Vec::new();
        }
        if self.prompt.is_some() {
            return self.prompt_key(key, ctrl_c, now);
        }
        if self.edit.editing.is_some() {
            if ctrl_c {
                self.edit.editing = None;
            } else {
                self.edit_key(key, now);
            }
            return Vec::new();
        }
        if self.help {
            // The arrows (and j, k, the page keys) scroll the help; any other key closes it.
            match key.code {
                KeyCode::Down | KeyCode::Char('j') => {
                    self.help_scroll = self.help_scroll.saturating_add(1);
                }
                KeyCode::PageDown | KeyCode::Char(' ') => {
                    self.help_scroll = self.help_scroll.saturating_add(10);
                }
                KeyCode::Up | KeyCode::Char('k') => {
                    self.help_scroll = self.help_scroll.saturating_sub(1);
                }
                KeyCode::PageUp => self.help_scroll = self.help_scroll.saturating_sub(10),
                _ => {
                    self.help = false;
                    self.help_scroll = 0;
                }
            }
            self.help_scroll = self.help_scroll.min(self.help_scroll_max.get());
            return Vec::new();
        }
        if self.shown.selection_open() {
            if ctrl_c {
                self.close_selection();
                self.request_quit();
            } else {
                self.select_key(key, now);
            }
            return Vec::new();
        }
        match keymap::action(&key, Scope::of(self.edit.focus)) {
            Some(action) => {
                // The last message was about the last action.
                self.clear_message();
                self.act(action, now)
            }
            None => Vec::new(),
        }
    }

    /// A gamma or mu typed into `row` is balanced by another segment's (each column sums to
    /// 1): say which took the difference, as the panel shows its cells (SI or not), and that
    /// it was fixed when none was free to.
    fn say_donor(&mut self, before: &PrbMatrix, row: usize, col: Column) {
        let after = &self.edit.matrix;
        let value = |m: &PrbMatrix, i: usize| m.rows().get(i).map(|r| r.get(col));
        let Some(i) = (0..after.len()).find(|&i| i != row && value(before, i) != value(after, i))
        else {
            return;
        };
        let (state, beam) = (&self.edit.matrix_state, &self.edit.scene.beam);
        let was = state.cell_text(before, beam, i, col);
        let now = state.cell_text(after, beam, i, col);
        let fixed = if after.rows()[i].is_free(col) {
            ""
        } else {
            " (fixed: none was free to; f frees one to choose)"
        };
        self.set_info(format!(
            "row {}'s {} took the difference: {was} -> {now}{fixed}",
            i + 1,
            col.name()
        ));
    }

    /// Keys in the text box of the field being edited.
    fn edit_key(&mut self, key: KeyEvent, now: Instant) {
        let Some((_, tb)) = &mut self.edit.editing else {
            return;
        };
        match text_action(&key) {
            TextKey::Action(Action::TextCancel) => self.edit.editing = None,
            TextKey::Action(Action::TextAccept) => {
                if let Some((target, tb)) = self.edit.editing.take() {
                    // A gamma or mu typed is balanced by another row's: keep the matrix before
                    // it, to say which.
                    let balanced = match target {
                        EditTarget::Cell {
                            row,
                            col: col @ (Column::Gamma | Column::Mu),
                        } => Some((self.edit.matrix.clone(), row, col)),
                        _ => None,
                    };
                    match self.edit.apply_edit(&target, &tb.text) {
                        Ok(()) => {
                            self.clear_message();
                            if let Some((before, row, col)) = balanced {
                                self.say_donor(&before, row, col);
                            }
                            self.jobs.changed(now);
                        }
                        Err(e) => self.set_error(format!("rejected: {e} (the old value is kept)")),
                    }
                }
            }
            TextKey::Action(a) => {
                tb.apply(a);
            }
            TextKey::Char(c) => tb.insert(c),
            TextKey::None => {}
        }
    }

    /// Keys while the selection view is open.
    fn select_key(&mut self, key: KeyEvent, now: Instant) {
        match keymap::action(&key, Scope::SELECT) {
            Some(a @ (Action::Up | Action::Down)) => {
                let dy = if a == Action::Up { -1 } else { 1 };
                if let Some(v) = &mut self.shown.select {
                    v.move_by(dy);
                }
            }
            Some(Action::SelectStop) if self.shown.selection_running() => {
                self.jobs.cancel();
                self.shown.selection_stopped();
                self.set_info("selection cancelled");
            }
            Some(Action::SelectLoad) => {
                if let Some((name, m)) = self.shown.selected_model() {
                    self.close_selection();
                    self.set_info(format!("matrix: {name} from the selection (r fits it)"));
                    self.replace_matrix(m, now);
                    // As the table showed it.
                    self.jobs.judge_only();
                }
            }
            Some(Action::SelectClose) => {
                self.close_selection();
                // Back to the matrix being edited: judge or fit it again.
                self.jobs.refresh(now, self.jobs.live);
            }
            _ => {}
        }
    }

    /// Does what a key in the focused panel asked for.
    fn act(&mut self, action: Action, now: Instant) -> Vec<Command> {
        let mut out = Vec::new();
        let mechanism = self.edit.is_mechanism();
        match action {
            Action::Quit => self.request_quit(),
            Action::Help => self.help = true,
            Action::NextPanel => self.edit.focus = self.edit.focus.next(mechanism),
            Action::PrevPanel => self.edit.focus = self.edit.focus.prev(mechanism),
            Action::Up => self.edit.move_cursor(0, -1),
            Action::Down => self.edit.move_cursor(0, 1),
            Action::Left => self.edit.move_cursor(-1, 0),
            Action::Right => self.edit.move_cursor(1, 0),
            Action::Edit => {
                if let Err(e) = self.edit.start_edit() {
                    self.set_error(e);
                }
            }
            Action::Fit => out.push(self.submit(true)),
            Action::Selection => out.push(self.open_selection()),
            Action::Cancel => self.cancel_fit(),
            Action::ToggleLive => {
                self.jobs.live = !self.jobs.live;
                self.set_info(if self.jobs.live {
                    "live refit on: every edit refits"
                } else {
                    "live refit paused: edits are judged, not fitted (r fits)"
                });
            }
            Action::CycleFidelity => {
                self.jobs.fidelity = match self.jobs.fidelity {
                    Fidelity::Draft => Fidelity::Normal,
                    Fidelity::Normal => Fidelity::Precise,
                    Fidelity::Precise => Fidelity::Draft,
                };
                self.set_info(format!("fidelity: {}", self.jobs.fidelity));
                self.jobs.changed(now);
            }
            Action::Save => self.open_prompt(
                PromptKind::SaveScene,
                self.edit
                    .scene_path
                    .as_ref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_else(|| "scene.toml".into()),
            ),
            Action::Open if self.unsaved() => {
                self.open_prompt(PromptKind::ConfirmOpen, String::new())
            }
            Action::Open => self.open_prompt(PromptKind::OpenScene, String::new()),
            Action::Export if mechanism => {
                self.open_prompt(PromptKind::ExportMechanism, "mechanism.xml".into())
            }
            Action::Export => self.open_prompt(PromptKind::ExportModel, "model.toml".into()),
            Action::Topology => self.open_prompt(PromptKind::Topology, self.edit.matrix.topology()),
            Action::NextPublished => {
                let name = self.edit.next_published();
                self.load_named_matrix(name, now);
            }
            Action::CycleCompare => out.extend(self.cycle_compare()),
            Action::ToggleFree => {
                let outcome = self.edit.toggle_free().map(|()| true);
                self.edited(outcome, now);
            }
            Action::ToggleShear => self.toggle_effect('1', now),
            Action::ToggleExtension => self.toggle_effect('2', now),
            Action::TogglePoisson => self.toggle_effect('3', now),
            Action::TogglePlaneStrain => self.toggle_effect('4', now),
            Action::AddRow | Action::DeleteRow => {
                let outcome = self.edit.add_or_delete_row(action == Action::AddRow);
                self.edited(outcome, now);
            }
            Action::ModeShapes => {
                self.show_modes = !self.show_modes;
                let mechanism = self.edit.case_form() == crate::study::CaseForm::Stage;
                self.set_info(match (self.show_modes, mechanism) {
                    (true, false) => {
                        "mode shapes: beam and PRB, unloaded, the tip's motion 1 (M: back)"
                            .to_string()
                    }
                    (true, true) => format!(
                        "mode shapes: beam and PRB displaced about the unloaded mechanism, \
                         the largest motion {} of its size (M: back)",
                        super::MODE_SCALE
                    ),
                    (false, _) => "deformed shapes".to_string(),
                });
            }
            Action::ToggleSi => {
                let si = !self.edit.matrix_state.si;
                self.edit.matrix_state.si = si;
                self.set_info(if si {
                    "SI for this beam: segment lengths, N m/rad, N/m; loads in N, N m"
                } else {
                    "nondimensional: gamma, k_theta (E I0/L), k_ex (E A0/L); alpha, beta"
                });
            }
            Action::ToggleHold => {
                let news = self.edit.toggle_hold();
                self.set_info(news);
            }
            Action::PrevPath => self.edit.cycle_path(-1),
            Action::NextPath => self.edit.cycle_path(1),
            Action::PrevCase | Action::NextCase => {
                let delta = if action == Action::PrevCase { -1 } else { 1 };
                let cases = self.shown_cases();
                self.edit.mech_state.cycle_case(delta, cases);
            }
            Action::NextChart => self.edit.mech_state.chart += 1,
            Action::ToggleKind => {
                let outcome = self.edit.toggle_kind(self.shown.truth());
                self.edited(outcome, now);
            }
            // The selection view's and the text boxes' own keys never reach here.
            Action::SelectLoad
            | Action::SelectStop
            | Action::SelectClose
            | Action::TextAccept
            | Action::TextCancel
            | Action::TextLeft
            | Action::TextRight
            | Action::TextStart
            | Action::TextEnd
            | Action::TextBackspace
            | Action::TextDelete
            | Action::TextClearStart
            | Action::TextClearEnd
            | Action::TextDeleteWord => {}
        }
        out
    }

    /// 1, 2, 3, 4 switch shear, extension, poisson, plane strain.
    fn toggle_effect(&mut self, which: char, now: Instant) {
        match self.edit.toggle_effect(which, self.shown.decided_effects()) {
            Ok(e) => {
                self.set_info(format!("effects: {e}"));
                self.jobs.changed(now);
            }
            Err(err) => self.set_error(format!("rejected: {err}")),
        }
    }
}
