//! Every key the UI takes, in one table that the key handling, the help overlay (`?`) and
//! the hint line all read, so they cannot drift apart (gitui's `key_list.rs` with the
//! `CommandInfo` of each tab). The guide's key table (docs/ui.md) is this table, checked by a
//! test.
//!
//! Text entry (a field's editor, a prompt) has its own rows, scope [`Scope::TEXT`]: the
//! readline keys; any other character is typed (the first one over a pre-filled value
//! replaces it).

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::panel::Panel;

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Show the help overlay.
    Help,
    /// Quit (asking first when something is unsaved).
    Quit,
    /// Focus the next panel.
    NextPanel,
    /// Focus the previous panel.
    PrevPanel,
    /// Cursor up.
    Up,
    /// Cursor down.
    Down,
    /// Cursor left.
    Left,
    /// Cursor right.
    Right,
    /// Edit the selected field or cell.
    Edit,
    /// Toggle the selected matrix cell free / fixed.
    ToggleFree,
    /// Switch shear on or off.
    ToggleShear,
    /// Switch extension on or off.
    ToggleExtension,
    /// Switch Poisson on or off.
    TogglePoisson,
    /// Switch plane strain (the plate stiffening of wide sections) on or off.
    TogglePlaneStrain,
    /// Add a matrix row or a load path.
    AddRow,
    /// Delete a matrix row or a load path.
    DeleteRow,
    /// Show the previous load path.
    PrevPath,
    /// Show the next load path.
    NextPath,
    /// Mechanism: a drive coordinate prescribed or loaded, or the next attachment.
    ToggleKind,
    /// Mechanism: the shape chart's previous case.
    PrevCase,
    /// Mechanism: the shape chart's next case.
    NextCase,
    /// Mechanism: the force-stroke chart's next panel.
    NextChart,
    /// Ask for a topology or model name.
    Topology,
    /// Load the next published model.
    NextPublished,
    /// Compare with the next model: none, the published ones, the selection's.
    CycleCompare,
    /// Switch the matrix and the loads between nondimensional and SI.
    ToggleSi,
    /// Switch what a beam edit holds: alpha or the force.
    ToggleHold,
    /// Fit now.
    Fit,
    /// Cancel the running fit.
    Cancel,
    /// Open the model selection.
    Selection,
    /// Toggle the shape chart between the deformed shapes and the mode shapes.
    ModeShapes,
    /// Selection view: load the selected row's model.
    SelectLoad,
    /// Selection view: stop the running selection.
    SelectStop,
    /// Selection view: close it.
    SelectClose,
    /// Pause or resume live refit.
    ToggleLive,
    /// Cycle the fidelity.
    CycleFidelity,
    /// Save the scene.
    Save,
    /// Open a scene.
    Open,
    /// Export the model.
    Export,
    /// Text: accept.
    TextAccept,
    /// Text: cancel.
    TextCancel,
    /// Text: cursor left.
    TextLeft,
    /// Text: cursor right.
    TextRight,
    /// Text: cursor to the start.
    TextStart,
    /// Text: cursor to the end.
    TextEnd,
    /// Text: delete before the cursor.
    TextBackspace,
    /// Text: delete at the cursor.
    TextDelete,
    /// Text: delete from the start to the cursor.
    TextClearStart,
    /// Text: delete from the cursor to the end.
    TextClearEnd,
    /// Text: delete the word before the cursor.
    TextDeleteWord,
}

/// A key, with or without Ctrl. A key without Ctrl matches whatever the modifiers (Shift
/// comes with capitals), as the UI always did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    /// The key.
    pub code: KeyCode,
    /// Ctrl must be held.
    pub ctrl: bool,
}

impl Key {
    /// Whether `event` is this key.
    pub fn matches(&self, event: &KeyEvent) -> bool {
        event.code == self.code && (!self.ctrl || event.modifiers.contains(KeyModifiers::CONTROL))
    }
}

/// Where keys are read: a bit per panel and one for the selection view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Scope(u8);

impl Scope {
    /// The beam panel.
    pub const BEAM: Scope = Scope(1);
    /// The load panel.
    pub const LOADS: Scope = Scope(2);
    /// The matrix panel.
    pub const MATRIX: Scope = Scope(4);
    /// The mechanism panel.
    pub const MECH: Scope = Scope(32);
    /// Any of the panels.
    pub const PANELS: Scope = Scope(1 | 2 | 4 | 32);
    /// The selection view.
    pub const SELECT: Scope = Scope(8);
    /// Text entry: a field's editor or a prompt.
    pub const TEXT: Scope = Scope(16);

    /// Both scopes.
    pub const fn or(self, other: Scope) -> Scope {
        Scope(self.0 | other.0)
    }

    /// Whether `self` includes all of `other`.
    pub fn contains(self, other: Scope) -> bool {
        self.0 & other.0 == other.0
    }

    /// The scope of a panel.
    pub fn of(panel: Panel) -> Scope {
        match panel {
            Panel::Beam => Scope::BEAM,
            Panel::Loads => Scope::LOADS,
            Panel::Matrix => Scope::MATRIX,
            Panel::Mechanism => Scope::MECH,
        }
    }
}

/// One key and its action.
#[derive(Debug, Clone, Copy)]
pub struct Binding {
    /// The key.
    pub key: Key,
    /// What it does.
    pub action: Action,
}

/// A short reminder on the hint line, in the panels of `scope`.
#[derive(Debug, Clone, Copy)]
pub struct Hint {
    /// The text, e.g. `f free/fixed`.
    pub text: &'static str,
    /// The panels whose hint line shows it.
    pub scope: Scope,
    /// It edits the load paths or the drives, which a data scene's rows are (read-only): its
    /// hint line leaves it out.
    pub edits_rows: bool,
}

/// A row of the key table: its keys as written in the help and the guide, what they do,
/// where they apply, the bindings, and the hints.
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// The keys, as written: `Tab / Shift-Tab`.
    pub keys: &'static str,
    /// What they do.
    pub does: &'static str,
    /// Where the bindings apply.
    pub scope: Scope,
    /// Each key and its action.
    pub bindings: &'static [Binding],
    /// The hint-line reminders.
    pub hints: &'static [Hint],
}

const fn ch(c: char, action: Action) -> Binding {
    Binding {
        key: Key {
            code: KeyCode::Char(c),
            ctrl: false,
        },
        action,
    }
}

const fn code(code: KeyCode, action: Action) -> Binding {
    Binding {
        key: Key { code, ctrl: false },
        action,
    }
}

const fn ctrl(c: char, action: Action) -> Binding {
    Binding {
        key: Key {
            code: KeyCode::Char(c),
            ctrl: true,
        },
        action,
    }
}

const fn hint(text: &'static str, scope: Scope) -> Hint {
    Hint {
        text,
        scope,
        edits_rows: false,
    }
}

/// A hint for a key that edits the load paths or drives (not shown on a data scene).
const fn rows_hint(text: &'static str, scope: Scope) -> Hint {
    Hint {
        text,
        scope,
        edits_rows: true,
    }
}

const ALL: Scope = Scope::PANELS;

/// The key table, in the order of the help and the guide, which is also the hint line's.
pub const KEYMAP: &[Entry] = &[
    Entry {
        keys: "?, F1",
        does: "this help (the arrows and page keys scroll it, any other key closes it)",
        scope: ALL,
        bindings: &[ch('?', Action::Help), code(KeyCode::F(1), Action::Help)],
        hints: &[hint("? keys", ALL)],
    },
    Entry {
        keys: "q, Ctrl-C",
        does: "quit (asks first when something is unsaved)",
        scope: ALL,
        bindings: &[ch('q', Action::Quit), ctrl('c', Action::Quit)],
        hints: &[hint("q quit", ALL)],
    },
    Entry {
        keys: "Tab / Shift-Tab",
        does: "next / previous panel",
        scope: ALL,
        bindings: &[
            code(KeyCode::Tab, Action::NextPanel),
            code(KeyCode::BackTab, Action::PrevPanel),
        ],
        hints: &[hint("Tab panel", ALL)],
    },
    Entry {
        keys: "arrows, h j k l",
        does: "move inside a panel or the selection table",
        scope: ALL.or(Scope::SELECT),
        bindings: &[
            code(KeyCode::Up, Action::Up),
            ch('k', Action::Up),
            code(KeyCode::Down, Action::Down),
            ch('j', Action::Down),
            code(KeyCode::Left, Action::Left),
            ch('h', Action::Left),
            code(KeyCode::Right, Action::Right),
            ch('l', Action::Right),
        ],
        hints: &[],
    },
    Entry {
        keys: "Enter",
        does: "edit the selected field or cell; Enter accepts, Esc cancels",
        scope: ALL,
        bindings: &[code(KeyCode::Enter, Action::Edit)],
        hints: &[
            hint("Enter edit (0.5 mm, 200 GPa)", Scope::BEAM),
            rows_hint("Enter edit", Scope::LOADS),
            hint("Enter edit", Scope::MATRIX.or(Scope::MECH)),
        ],
    },
    Entry {
        keys: "f",
        does: "matrix: toggle a cell free (fitted) / fixed (shown with !)",
        scope: Scope::MATRIX,
        bindings: &[ch('f', Action::ToggleFree)],
        hints: &[hint("f free/fixed", Scope::MATRIX)],
    },
    Entry {
        keys: "1 / 2 / 3 / 4",
        does: "beam: switch shear / extension / poisson / plane strain on or off",
        scope: Scope::BEAM,
        bindings: &[
            ch('1', Action::ToggleShear),
            ch('2', Action::ToggleExtension),
            ch('3', Action::TogglePoisson),
            ch('4', Action::TogglePlaneStrain),
        ],
        hints: &[hint("1-4 shear/ext/poisson/plate", Scope::BEAM)],
    },
    Entry {
        keys: "p",
        does: "mechanism: coordinate prescribed <-> loaded (same end state), attach kind",
        scope: Scope::MECH,
        bindings: &[ch('p', Action::ToggleKind)],
        hints: &[rows_hint("p prescribed/loaded", Scope::MECH)],
    },
    Entry {
        keys: "a / d",
        does: "add / delete a matrix row, a load path or a mechanism's drive",
        scope: Scope::LOADS.or(Scope::MATRIX).or(Scope::MECH),
        bindings: &[ch('a', Action::AddRow), ch('d', Action::DeleteRow)],
        hints: &[
            hint("a/d row", Scope::MATRIX),
            rows_hint("a/d path", Scope::LOADS),
            rows_hint("a/d drive", Scope::MECH),
        ],
    },
    Entry {
        keys: "H",
        does: "loads: a beam edit holds alpha, or the force (N, N m: alphas rescaled)",
        scope: Scope::LOADS,
        bindings: &[ch('H', Action::ToggleHold)],
        hints: &[rows_hint("H hold alpha/force", Scope::LOADS)],
    },
    Entry {
        keys: "[ / ]",
        does: "previous / next load path (a mechanism's drive) in the charts",
        scope: ALL,
        bindings: &[ch('[', Action::PrevPath), ch(']', Action::NextPath)],
        hints: &[
            hint("[ ] shown path", Scope::LOADS),
            hint("[ ] drive", Scope::MECH),
        ],
    },
    Entry {
        keys: "< / >",
        does: "mechanism: previous / next case of the shown drive in the shape chart",
        scope: ALL,
        bindings: &[ch('<', Action::PrevCase), ch('>', Action::NextCase)],
        hints: &[hint("< > case", Scope::MECH)],
    },
    Entry {
        keys: "F",
        does: "mechanism: the force-stroke chart's next reaction (or motion)",
        scope: ALL,
        bindings: &[ch('F', Action::NextChart)],
        hints: &[hint("F force chart", Scope::MECH)],
    },
    Entry {
        keys: "t",
        does: "matrix from a topology (L-R-R-R, 3R) or a published model's name",
        scope: ALL,
        bindings: &[ch('t', Action::Topology)],
        hints: &[hint("t topology", Scope::MATRIX)],
    },
    Entry {
        keys: "m",
        does: "cycle the published models: Howell 1R, Su 3R, Chen 3R (judged, not fitted)",
        scope: ALL,
        bindings: &[ch('m', Action::NextPublished)],
        hints: &[hint("m model", Scope::MATRIX)],
    },
    Entry {
        keys: "C",
        does: "compare with: none, Howell, Su, Chen, the selection's model (charts, status)",
        scope: ALL,
        bindings: &[ch('C', Action::CycleCompare)],
        hints: &[hint("C compare", ALL)],
    },
    Entry {
        keys: "u",
        does: "matrix and loads in SI: lengths, N m/rad, N/m, kg, N, N m (typed values too)",
        scope: ALL,
        bindings: &[ch('u', Action::ToggleSi)],
        hints: &[hint("u SI", Scope::MATRIX.or(Scope::LOADS))],
    },
    Entry {
        keys: "r",
        does: "fit now",
        scope: ALL,
        bindings: &[ch('r', Action::Fit)],
        hints: &[hint("r fit", ALL)],
    },
    Entry {
        keys: "c, Esc",
        does: "cancel the running fit",
        scope: ALL,
        bindings: &[ch('c', Action::Cancel), code(KeyCode::Esc, Action::Cancel)],
        hints: &[hint("c cancel", ALL)],
    },
    Entry {
        keys: "S",
        does: "model selection: the topology ladder's table and the trade-off chart",
        scope: ALL,
        bindings: &[ch('S', Action::Selection)],
        hints: &[],
    },
    Entry {
        keys: "M",
        does: "mode shapes of beam and PRB over each other ([beam] density); again: back",
        scope: ALL,
        bindings: &[ch('M', Action::ModeShapes)],
        hints: &[],
    },
    Entry {
        keys: "Enter (in S)",
        does: "load the selected row's model and close the selection",
        scope: Scope::SELECT,
        bindings: &[code(KeyCode::Enter, Action::SelectLoad)],
        hints: &[],
    },
    Entry {
        keys: "c (in S)",
        does: "stop the running selection",
        scope: Scope::SELECT,
        bindings: &[ch('c', Action::SelectStop)],
        hints: &[],
    },
    Entry {
        keys: "Esc, q (in S)",
        does: "close the selection",
        scope: Scope::SELECT,
        bindings: &[
            code(KeyCode::Esc, Action::SelectClose),
            ch('q', Action::SelectClose),
        ],
        hints: &[],
    },
    Entry {
        keys: "space",
        does: "pause / resume live refit after every edit",
        scope: ALL,
        bindings: &[ch(' ', Action::ToggleLive)],
        hints: &[hint("space live", ALL)],
    },
    Entry {
        keys: "v",
        does: "cycle fidelity: draft, normal, precise",
        scope: ALL,
        bindings: &[ch('v', Action::CycleFidelity)],
        hints: &[hint("v fidelity", ALL)],
    },
    Entry {
        keys: "s / o",
        does: "save / open a scene file",
        scope: ALL,
        bindings: &[ch('s', Action::Save), ch('o', Action::Open)],
        hints: &[hint("s save", Scope::LOADS), hint("o open", Scope::LOADS)],
    },
    Entry {
        keys: "e",
        does: "export the model: .toml .json .xml/.mjcf .urdf .sdf .csv",
        scope: ALL,
        bindings: &[ch('e', Action::Export)],
        hints: &[hint("e export", Scope::MATRIX)],
    },
    Entry {
        keys: "Enter / Esc (typing)",
        does: "accept / cancel; the first character typed replaces the shown value",
        scope: Scope::TEXT,
        bindings: &[
            code(KeyCode::Enter, Action::TextAccept),
            code(KeyCode::Esc, Action::TextCancel),
        ],
        hints: &[],
    },
    Entry {
        keys: "Left / Right (typing)",
        does: "move the cursor (and keep the shown value to edit it)",
        scope: Scope::TEXT,
        bindings: &[
            code(KeyCode::Left, Action::TextLeft),
            code(KeyCode::Right, Action::TextRight),
        ],
        hints: &[],
    },
    Entry {
        keys: "Home, Ctrl-A / End, Ctrl-E",
        does: "cursor to the start / end of the text",
        scope: Scope::TEXT,
        bindings: &[
            code(KeyCode::Home, Action::TextStart),
            ctrl('a', Action::TextStart),
            code(KeyCode::End, Action::TextEnd),
            ctrl('e', Action::TextEnd),
        ],
        hints: &[],
    },
    Entry {
        keys: "Backspace / Delete",
        does: "delete the character before / at the cursor",
        scope: Scope::TEXT,
        bindings: &[
            code(KeyCode::Backspace, Action::TextBackspace),
            code(KeyCode::Delete, Action::TextDelete),
        ],
        hints: &[],
    },
    Entry {
        keys: "Ctrl-U / Ctrl-K",
        does: "delete to the start / end of the text (at the end Ctrl-U clears it)",
        scope: Scope::TEXT,
        bindings: &[
            ctrl('u', Action::TextClearStart),
            ctrl('k', Action::TextClearEnd),
        ],
        hints: &[],
    },
    Entry {
        keys: "Ctrl-W",
        does: "delete the word before the cursor",
        scope: Scope::TEXT,
        bindings: &[ctrl('w', Action::TextDeleteWord)],
        hints: &[],
    },
];

/// The hint line while a field is being edited.
pub const EDITING_HINT: &str =
    " type 0.5 mm, 200 GPa, inf · ←/→ edit · ^U clear · ^W word · Enter ok · Esc cancel";
/// The hint line while a prompt asks for text.
pub const PROMPT_HINT: &str =
    " type (replaces the text) · ←/→ edit · ^U clear · ^W word · Enter ok · Esc cancel";
/// The hint line while a yes/no question waits.
pub const QUESTION_HINT: &str = " y yes · any other key no";

/// What `event` does in `scope` (a panel's, or the selection view's), if anything.
pub fn action(event: &KeyEvent, scope: Scope) -> Option<Action> {
    KEYMAP
        .iter()
        .filter(|e| e.scope.contains(scope))
        .flat_map(|e| e.bindings)
        .find(|b| b.key.matches(event))
        .map(|b| b.action)
}

/// The hint line of `panel`: its hints, in table order; on a data scene (`data`), without
/// the keys that edit its rows (the load paths or drives), which are read-only there.
pub fn hint_line(panel: Panel, data: bool) -> String {
    let scope = Scope::of(panel);
    let hints: Vec<&str> = KEYMAP
        .iter()
        .flat_map(|e| e.hints)
        .filter(|h| h.scope.contains(scope) && !(data && h.edits_rows))
        .map(|h| h.text)
        .collect();
    format!(" {}", hints.join(" · "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a data scene the hint line leaves out the keys that edit its read-only rows (the
    /// load paths, the drives) and keeps the others.
    #[test]
    fn data_scenes_hint_no_row_edits() {
        let loads = hint_line(Panel::Loads, false);
        for h in ["Enter edit", "a/d path", "H hold"] {
            assert!(loads.contains(h), "{loads}");
            assert!(!hint_line(Panel::Loads, true).contains(h));
        }
        let mech = (
            hint_line(Panel::Mechanism, false),
            hint_line(Panel::Mechanism, true),
        );
        for h in ["p prescribed", "a/d drive"] {
            assert!(mech.0.contains(h) && !mech.1.contains(h), "{mech:?}");
        }
        assert!(
            mech.1.contains("Enter edit") && mech.1.contains("< > case"),
            "{mech:?}"
        );
        assert_eq!(
            hint_line(Panel::Matrix, true),
            hint_line(Panel::Matrix, false)
        );
    }

    /// No key means two things in one place.
    #[test]
    fn no_key_is_bound_twice_in_a_scope() {
        for scope in [
            Scope::BEAM,
            Scope::LOADS,
            Scope::MATRIX,
            Scope::MECH,
            Scope::SELECT,
            Scope::TEXT,
        ] {
            let keys: Vec<Key> = KEYMAP
                .iter()
                .filter(|e| e.scope.contains(scope))
                .flat_map(|e| e.bindings.iter().map(|b| b.key))
                .collect();
            for (i, k) in keys.iter().enumerate() {
                assert!(!keys[i + 1..].contains(k), "{k:?} twice in {scope:?}");
            }
        }
    }

    /// Every entry's hints show only where its keys work.
    #[test]
    fn hints_only_where_the_keys_apply() {
        for e in KEYMAP {
            for h in e.hints {
                assert!(e.scope.contains(h.scope), "{}: {}", e.keys, h.text);
            }
        }
    }
}
