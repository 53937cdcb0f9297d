//! A data scene's load panel (DESIGN §9), in place of the load paths: its file's rows,
//! read-only, each with its path (in the path's colour) and its load, nondimensional or in SI
//! with `u` (for the nominal beam as it is now); the row under the cursor in the other units
//! on the bottom border. The shape chart shows the path of the selected row.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::{Cell, Row, Table, TableState};
use ratatui::Frame;

use crate::scene::data::MeasuredPath;
use crate::scene::LoadPath;

use super::super::app::{App, Panel};
use super::super::state::loads::{alpha_text, load_text, si_text, LOAD_COLUMNS, LOAD_COLUMNS_SI};
use super::parts::{panel_block, Palette, PATH_COLORS};

/// What the data rows panel draws.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The panel has the focus.
    pub focused: bool,
    /// Per row: its path's place (0-based, for the colour), the path's id, and the load's
    /// three texts.
    pub rows: Vec<(usize, i64, [String; 3])>,
    /// The selected row.
    pub row: usize,
    /// The table is in SI (N, N m).
    pub si: bool,
    /// The selected row: its file line and its load in the units the table is not in.
    pub other_units: String,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The data rows panel of `app` (empty on a scene without data).
    pub fn new(app: &App) -> View {
        let paths: &[MeasuredPath] = app.edit.scene.truth.as_ref().map_or(&[], |t| &t.paths);
        // A row's load as a path of one step, so that the load panel's texts apply.
        let as_path = |load| LoadPath {
            end: load,
            steps: 1,
        };
        let rows: Vec<(usize, i64, [String; 3])> = paths
            .iter()
            .enumerate()
            .flat_map(|(i, p)| p.rows.iter().map(move |r| (i, p.id, r)))
            .map(|(i, id, r)| {
                let path = as_path(r.load);
                let text = |col| load_text(&path, col, app.edit.si_beam());
                (i, id, [text(0), text(1), text(2)])
            })
            .collect();
        let row = app.edit.loads_state.row.min(rows.len().saturating_sub(1));
        let other_units = paths
            .iter()
            .flat_map(|p| &p.rows)
            .nth(row)
            .map(|r| {
                let path = as_path(r.load);
                let load = match app.edit.matrix_state.si {
                    true => alpha_text(&path),
                    false => si_text(&path, &app.edit.scene.beam),
                };
                format!("line {}: {load}", r.line)
            })
            .unwrap_or_default();
        View {
            focused: app.edit.focus == Panel::Loads,
            rows,
            row,
            si: app.edit.matrix_state.si,
            other_units,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the data rows panel.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let block = panel_block(" Data rows (read-only) ", view.focused, pal).title_bottom(
        Span::styled(format!(" {} ", view.other_units), pal.fg(Color::DarkGray)),
    );
    let columns = if view.si {
        LOAD_COLUMNS_SI
    } else {
        LOAD_COLUMNS
    };
    let header = Row::new(
        std::iter::once(Cell::from("path"))
            .chain(columns[..3].iter().map(|c| Cell::from(*c)))
            .collect::<Vec<_>>(),
    )
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = view
        .rows
        .iter()
        .map(|(i, id, load)| {
            let mut cells = vec![Cell::from(Span::styled(
                id.to_string(),
                pal.fg(PATH_COLORS[i % PATH_COLORS.len()]),
            ))];
            cells.extend(load.iter().map(|t| Cell::from(t.clone())));
            Row::new(cells)
        })
        .collect();
    let table = Table::new(
        rows,
        [
            Constraint::Length(4),
            Constraint::Length(9),
            Constraint::Length(9),
            Constraint::Length(9),
        ],
    )
    .header(header)
    .block(block)
    // Read-only: the whole row is the cursor, no cell to edit.
    .row_highlight_style(if view.focused {
        pal.selected()
    } else {
        Style::default().add_modifier(Modifier::BOLD)
    });
    let mut state = TableState::default().with_selected(Some(view.row));
    frame.render_stateful_widget(table, area, &mut state);
}
