//! The load-path panel: a table of the paths' end loads and step counts (nondimensional, or
//! in SI with `u`), what a beam edit holds in the title, and the selected path in the other
//! units on the bottom border; with an allowable stress, each path's stroke limit (DESIGN
//! §11) in a `limit` column.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::{Cell, Row, Table, TableState};
use ratatui::Frame;

use super::super::app::{App, EditTarget, Panel};
use super::super::state::loads::{
    alpha_text, load_text, si_text, Hold, LOAD_COLUMNS, LOAD_COLUMNS_SI,
};
use super::super::units::trim_number;
use super::parts::{field_text, panel_block, Palette, PATH_COLORS};

/// What the load panel draws.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// The panel has the focus.
    pub focused: bool,
    /// Per path, per column: the text (or editor) and whether it is being edited.
    pub cells: Vec<Vec<(String, bool)>>,
    /// The selected path.
    pub row: usize,
    /// The selected column.
    pub col: usize,
    /// The table is in SI (N, N m).
    pub si: bool,
    /// What a beam edit holds.
    pub hold: Hold,
    /// The selected path in the units the table is not in.
    pub other_units: String,
    /// Each path's stroke limit (DESIGN §11), when the truth shown has them (a column).
    pub limits: Option<Vec<Option<f64>>>,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The load panel of `app`.
    pub fn new(app: &App) -> View {
        View {
            focused: app.edit.focus == Panel::Loads,
            cells: app
                .edit
                .scene
                .loads
                .iter()
                .enumerate()
                .map(|(row, path)| {
                    (0..LOAD_COLUMNS.len())
                        .map(|col| {
                            field_text(
                                app,
                                &EditTarget::Load { row, col },
                                load_text(path, col, app.edit.si_beam()),
                            )
                        })
                        .collect()
                })
                .collect(),
            row: app.edit.loads_state.row,
            col: app.edit.loads_state.col,
            si: app.edit.matrix_state.si,
            hold: app.edit.loads_state.hold,
            other_units: app
                .edit
                .scene
                .loads
                .get(app.edit.shown_path())
                .map(|p| match app.edit.matrix_state.si {
                    true => alpha_text(p),
                    false => si_text(p, &app.edit.scene.beam),
                })
                .unwrap_or_default(),
            limits: app
                .shown
                .truth()
                .and_then(|t| t.stroke_limits.as_ref())
                .map(|l| l.iter().map(|l| l.fraction).collect()),
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the load panel.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let title = format!(" Load paths  hold {} ", view.hold);
    let block = panel_block(title, view.focused, pal).title_bottom(Span::styled(
        format!(" {} ", view.other_units),
        pal.fg(Color::DarkGray),
    ));

    let columns = if view.si {
        LOAD_COLUMNS_SI
    } else {
        LOAD_COLUMNS
    };
    let header = Row::new(
        std::iter::once(Cell::from("#"))
            .chain(columns.iter().map(|c| Cell::from(*c)))
            .chain(view.limits.as_ref().map(|_| Cell::from("limit")))
            .collect::<Vec<_>>(),
    )
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = view
        .cells
        .iter()
        .enumerate()
        .map(|(r, row)| {
            let mut cells = vec![Cell::from(Span::styled(
                format!("{}", r + 1),
                pal.fg(PATH_COLORS[r % PATH_COLORS.len()]),
            ))];
            for (c, (text, editing)) in row.iter().enumerate() {
                let style = if *editing || (view.focused && view.row == r && view.col == c) {
                    pal.selected()
                } else {
                    Style::default()
                };
                cells.push(Cell::from(Span::styled(text.clone(), style)));
            }
            // The stroke limit (DESIGN §11): the fraction of the path where the stress
            // reaches the allowable, `-` where it does not.
            if let Some(limits) = &view.limits {
                let text = match limits.get(r).copied().flatten() {
                    Some(l) => trim_number(l, 4),
                    None => "-".to_string(),
                };
                cells.push(Cell::from(Span::styled(text, pal.fg(Color::Red))));
            }
            Row::new(cells)
        })
        .collect();
    let mut widths = vec![
        Constraint::Length(2),
        Constraint::Length(9),
        Constraint::Length(9),
        Constraint::Length(8),
        Constraint::Length(5),
    ];
    if view.limits.is_some() {
        widths.push(Constraint::Length(6));
    }
    let table = Table::new(rows, widths)
        .header(header)
        .block(block)
        .row_highlight_style(if view.focused {
            Style::default()
        } else {
            Style::default().add_modifier(Modifier::BOLD)
        });
    let mut state = TableState::default().with_selected(Some(view.row));
    frame.render_stateful_widget(table, area, &mut state);
}
