//! The one-line prompts (save, open, export, topology, density) and the y/n questions
//! (quit, open over unsaved work, overwrite): their keys and what Enter does.

use std::path::PathBuf;
use std::time::Instant;

use ratatui::crossterm::event::{KeyCode, KeyEvent};

use super::super::keymap::Action;
use super::super::units::trim_number;
use super::dialog::{parse_density, text_action, TextKey};
use super::{App, Command, PromptKind};

impl App {
    /// Closes the open prompt unanswered, with what waited on it (a write, an export path).
    pub(super) fn drop_prompt(&mut self) {
        self.prompt = None;
        self.overwrite = None;
        self.export_path = None;
    }

    /// Keys while a prompt is open (`ctrl_c`: the key is Ctrl-C).
    pub(super) fn prompt_key(&mut self, key: KeyEvent, ctrl_c: bool, now: Instant) -> Vec<Command> {
        let Some((kind, tb)) = &mut self.prompt else {
            return Vec::new();
        };
        let kind = *kind;
        if kind.is_question() {
            let yes = matches!(key.code, KeyCode::Char('y') | KeyCode::Char('Y'));
            self.prompt = None;
            let write = self.overwrite.take();
            match (kind, yes) {
                (PromptKind::ConfirmQuit, true) => self.quit = true,
                (PromptKind::ConfirmOpen, true) => {
                    self.open_prompt(PromptKind::OpenScene, String::new())
                }
                (PromptKind::ConfirmOverwrite, true) => {
                    return match write {
                        Some(Command::SaveScene { path, .. }) => vec![Command::SaveScene {
                            path,
                            overwrite: true,
                        }],
                        Some(Command::Export { path, .. }) => vec![Command::Export {
                            path,
                            overwrite: true,
                        }],
                        _ => Vec::new(),
                    };
                }
                (PromptKind::ConfirmOverwrite, false) => self.set_info("not written"),
                _ => {}
            }
            return Vec::new();
        }
        if ctrl_c {
            self.prompt = None;
            self.export_path = None;
            return Vec::new();
        }
        match text_action(&key) {
            TextKey::Action(Action::TextCancel) => self.drop_prompt(),
            TextKey::Action(Action::TextAccept) => {
                let text = tb.text.trim().to_string();
                self.prompt = None;
                if text.is_empty() {
                    // Nothing typed is a cancel, said as one (it left a blank line).
                    let what = match kind {
                        PromptKind::SaveScene => Some("not saved: no file given"),
                        PromptKind::OpenScene => Some("not opened: no file given"),
                        PromptKind::ExportModel | PromptKind::ExportMechanism => {
                            Some("not exported: no file given")
                        }
                        PromptKind::ExportDensity => {
                            self.export_path = None;
                            Some("not exported: no density given")
                        }
                        _ => None,
                    };
                    if let Some(what) = what {
                        self.set_info(what);
                    }
                    return Vec::new();
                }
                self.clear_message();
                return match kind {
                    PromptKind::SaveScene => vec![Command::SaveScene {
                        path: PathBuf::from(text),
                        overwrite: false,
                    }],
                    PromptKind::OpenScene => vec![Command::OpenScene(PathBuf::from(text))],
                    // Exported by the worker from its baseline: no solve on this thread. The
                    // formats with masses ask for the links' density first, unless the scene
                    // gives it (`[beam] density`).
                    PromptKind::ExportModel | PromptKind::ExportMechanism => {
                        let path = PathBuf::from(text);
                        if self.export_asks_density(&path) {
                            self.export_path = Some(path);
                            let density = trim_number(self.export_density, 6);
                            self.open_prompt(PromptKind::ExportDensity, density);
                            Vec::new()
                        } else {
                            vec![Command::Export {
                                path,
                                overwrite: false,
                            }]
                        }
                    }
                    PromptKind::ExportDensity => match parse_density(&text) {
                        Ok(density) => {
                            self.export_density = density;
                            match self.export_path.take() {
                                Some(path) => vec![Command::Export {
                                    path,
                                    overwrite: false,
                                }],
                                None => Vec::new(),
                            }
                        }
                        Err(e) => {
                            self.export_path = None;
                            self.set_error(format!("not exported: {e}"));
                            Vec::new()
                        }
                    },
                    PromptKind::Topology => {
                        self.load_named_matrix(&text, now);
                        Vec::new()
                    }
                    // Answered above, before any text is typed.
                    PromptKind::ConfirmQuit
                    | PromptKind::ConfirmOpen
                    | PromptKind::ConfirmOverwrite => Vec::new(),
                };
            }
            TextKey::Action(a) => {
                tb.apply(a);
            }
            TextKey::Char(c) => tb.insert(c),
            TextKey::None => {}
        }
        Vec::new()
    }
}
