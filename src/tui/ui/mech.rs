//! The mechanism panel: a mechanism scene's flexures, stage point and drives, one value per
//! row, in place of the load paths (DESIGN §8). A mechanism data scene's drives are its
//! file's measured paths (each drive's end row and its rows as steps), read-only.
//! With an allowable stress, each drive's stroke limit (DESIGN §11) follows its steps.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::{Color, Style};
use ratatui::text::Span;
use ratatui::widgets::{Cell, Row, Table, TableState};
use ratatui::Frame;

use super::super::app::{App, EditTarget, Panel};
use super::super::state::mech::{fields, MechField};
use super::super::units::trim_number;
use super::parts::{field_text, panel_block, Palette};

/// What the mechanism panel draws.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The panel has the focus.
    pub focused: bool,
    /// The title: how many flexures and drives.
    pub title: String,
    /// The drives are a data file's rows (read-only).
    pub data: bool,
    /// Per row: its group (on the group's first row only), label, text (or editor), and
    /// whether it is being edited.
    pub rows: Vec<(String, &'static str, String, bool)>,
    /// The selected row.
    pub selected: usize,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The mechanism panel of `app` (empty on a cantilever scene).
    pub fn new(app: &App) -> View {
        let mut rows = Vec::new();
        let mut title = " Mechanism ".to_string();
        if let Some(m) = &app.edit.scene.mechanism {
            let plural =
                |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
            title = if app.edit.is_data() {
                // The drives are the data file's paths: shown, not edited.
                format!(
                    " Mechanism  {} · {} (data) ",
                    plural(m.flexures.len(), "flexure"),
                    plural(m.drives.len(), "drive")
                )
            } else {
                format!(
                    " Mechanism  {} · {} ",
                    plural(m.flexures.len(), "flexure"),
                    plural(m.drives.len(), "drive")
                )
            };
            let mut last_group = String::new();
            for f in fields(m) {
                let group = f.group();
                let (text, editing) = field_text(app, &EditTarget::Mech(f), f.text(m));
                let head = if group == last_group {
                    String::new()
                } else {
                    group.clone()
                };
                last_group = group;
                // A drive's stroke limit (DESIGN §11) beside its steps.
                let limit = match f {
                    MechField::Steps(d) if !editing => app
                        .shown
                        .truth()
                        .and_then(|t| t.stroke_limit(d))
                        .map(|l| format!("  limit {}", trim_number(l, 4))),
                    _ => None,
                };
                rows.push((head, f.label(), text + &limit.unwrap_or_default(), editing));
            }
        }
        View {
            focused: app.edit.focus == Panel::Mechanism,
            title,
            data: app.edit.is_data(),
            selected: app.edit.mech_state.row.min(rows.len().saturating_sub(1)),
            rows,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the mechanism panel.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let bottom = if view.data {
        " drives read-only: the data's rows "
    } else {
        " dx dy dphi prescribed · Fx Fy Mz loaded "
    };
    let block = panel_block(view.title.as_str(), view.focused, pal)
        .title_bottom(Span::styled(bottom, pal.fg(Color::DarkGray)));

    let rows: Vec<Row> = view
        .rows
        .iter()
        .enumerate()
        .map(|(i, (group, label, text, editing))| {
            let style = if *editing || (view.focused && view.selected == i) {
                pal.selected()
            } else {
                Style::default()
            };
            Row::new(vec![
                Cell::from(group.clone()),
                Cell::from(*label),
                Cell::from(Span::styled(text.clone(), style)),
            ])
        })
        .collect();
    let table = Table::new(
        rows,
        [
            Constraint::Length(10),
            Constraint::Length(8),
            Constraint::Min(10),
        ],
    )
    .column_spacing(0)
    .block(block);
    let mut state = TableState::default().with_selected(Some(view.selected));
    frame.render_stateful_widget(table, area, &mut state);
}
