//! The beam panel: one row per field, the selected one highlighted when focused.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::Style;
use ratatui::text::Span;
use ratatui::widgets::{Cell, Row, Table, TableState};
use ratatui::Frame;

use super::super::app::{App, EditTarget, Panel};
use super::super::state::beam::BeamField;
use super::super::units::trim_number;
use super::parts::{field_text, panel_block, Palette};

/// What the beam panel draws.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The panel has the focus.
    pub focused: bool,
    /// L / t0, for the title.
    pub slenderness: f64,
    /// Per field: its label, its text (or editor), and whether it is being edited.
    pub rows: Vec<(&'static str, String, bool)>,
    /// The selected row.
    pub selected: usize,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The beam panel of `app`.
    pub fn new(app: &App) -> View {
        View {
            focused: app.edit.focus == Panel::Beam,
            slenderness: app.edit.scene.beam.slenderness(),
            rows: BeamField::of(app.edit.is_mechanism())
                .iter()
                .map(|&f| {
                    let text = f.text(&app.edit.scene, app.shown.decided_effects());
                    let (text, editing) = field_text(app, &EditTarget::Beam(f), text);
                    (f.label(), text, editing)
                })
                .collect(),
            selected: app.edit.beam_state.row,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the beam panel.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let title = format!(
        " Beam and targets  L/t0 = {} ",
        trim_number(view.slenderness, 4)
    );
    let block = panel_block(title, view.focused, pal);
    let rows: Vec<Row> = view
        .rows
        .iter()
        .enumerate()
        .map(|(i, (label, text, editing))| {
            let style = if *editing || (view.focused && view.selected == i) {
                pal.selected()
            } else {
                Style::default()
            };
            Row::new(vec![
                Cell::from(*label),
                Cell::from(Span::styled(text.clone(), style)),
            ])
        })
        .collect();
    let table = Table::new(rows, [Constraint::Length(11), Constraint::Min(10)])
        .column_spacing(0)
        .block(block);
    let mut state = TableState::default().with_selected(Some(view.selected));
    frame.render_stateful_widget(table, area, &mut state);
}
