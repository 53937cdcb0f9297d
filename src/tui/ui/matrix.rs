//! The PRB matrix panel: gamma, k_theta, k_ex, mu per segment (or their SI values); free cells
//! green, fixed ones yellow and marked `!`, `inf` grey.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::{Cell, Row, Table, TableState};
use ratatui::Frame;

use crate::prb::Column;

use super::super::app::{App, EditTarget, Panel};
use super::parts::{field_text, panel_block, Palette};

/// How a cell looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellKind {
    /// Fitted.
    Free,
    /// Kept as typed.
    Fixed,
    /// No spring (topology, not a parameter).
    Infinite,
}

/// What the matrix panel draws.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The panel has the focus.
    pub focused: bool,
    /// The matrix's topology, for the title.
    pub topology: String,
    /// SI column headers.
    pub si: bool,
    /// The mu column in kg (SI view of a beam with a density).
    pub mass_si: bool,
    /// Per segment, per column: text (or editor), kind, being edited.
    pub cells: Vec<Vec<(String, CellKind, bool)>>,
    /// The selected segment.
    pub row: usize,
    /// The selected column.
    pub col: usize,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The matrix panel of `app`.
    pub fn new(app: &App) -> View {
        let cells = app
            .edit
            .matrix
            .rows()
            .iter()
            .enumerate()
            .map(|(r, row)| {
                Column::ALL
                    .iter()
                    .map(|&col| {
                        let value = row.get(col);
                        let mut text = app.edit.cell_text(r, col);
                        let kind = if value == f64::INFINITY {
                            CellKind::Infinite
                        } else if !row.free[col.index()] {
                            text.push('!');
                            CellKind::Fixed
                        } else {
                            CellKind::Free
                        };
                        let (text, editing) =
                            field_text(app, &EditTarget::Cell { row: r, col }, text);
                        (text, kind, editing)
                    })
                    .collect()
            })
            .collect();
        View {
            focused: app.edit.focus == Panel::Matrix,
            topology: app.edit.matrix.topology(),
            si: app.edit.matrix_state.si,
            mass_si: app.edit.matrix_state.si && app.edit.scene.beam.density.is_some(),
            cells,
            row: app.edit.matrix_state.row,
            col: app.edit.matrix_state.col,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the matrix panel.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let title = format!(" PRB matrix  {}  (! fixed) ", view.topology);
    let block = panel_block(title, view.focused, pal);
    let mass = if view.mass_si { "kg" } else { "mu" };
    let header = if view.si {
        Row::new(vec!["#", "length", "N m/rad", "N/m", mass])
    } else {
        Row::new(vec!["#", "gamma", "k_theta", "k_ex", mass])
    }
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = view
        .cells
        .iter()
        .enumerate()
        .map(|(r, row)| {
            let mut cells = vec![Cell::from(format!("{}", r + 1))];
            for (ci, (text, kind, editing)) in row.iter().enumerate() {
                let mut style = match kind {
                    CellKind::Infinite => pal.fg(Color::DarkGray),
                    CellKind::Fixed => pal.fg(Color::Yellow),
                    CellKind::Free => pal.fg(Color::Green),
                };
                if *editing || (view.focused && view.row == r && view.col == ci) {
                    style = pal.selected();
                }
                cells.push(Cell::from(Span::styled(text.clone(), style)));
            }
            Row::new(cells)
        })
        .collect();
    let table = Table::new(
        rows,
        [
            Constraint::Length(2),
            Constraint::Length(11),
            Constraint::Length(10),
            Constraint::Length(10),
            Constraint::Length(9),
        ],
    )
    .header(header)
    .block(block);
    let mut state = TableState::default().with_selected(Some(view.row));
    frame.render_stateful_widget(table, area, &mut state);
}
