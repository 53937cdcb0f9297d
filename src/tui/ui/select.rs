//! The model-selection view: the topology ladder's table (rows as they are fitted, the
//! chosen or closest marked) over the speed/accuracy trade-off chart.

use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::Span;
use ratatui::widgets::{
    Axis, Block, Borders, Cell, Chart, Clear, Dataset, GraphType, Paragraph, Row, Table, TableState,
};
use ratatui::Frame;

use crate::scene::Accuracy;

use super::super::app::App;
use super::super::state::select::SelectState;
use super::super::units::trim_number;
use super::{sanitize_terminal, Palette, PATH_COLORS};

/// What the selection view draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The rows, the choice, the trade-off and the cursor.
    pub state: &'a SelectState,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The selection view of `app`, when open.
    pub fn new(app: &'a App) -> Option<View<'a>> {
        Some(View {
            state: app.select.as_ref()?,
            accuracy: app.scene.accuracy,
            pal: Palette { mono: app.mono },
        })
    }
}

/// Draws the selection view: the ladder table over the trade-off chart.
pub fn draw(frame: &mut Frame, area: Rect, v: &View) {
    let (view, pal) = (v.state, v.pal);
    frame.render_widget(Clear, area);
    let state = if view.running {
        if view.rows.is_empty() {
            "fitting the ladder..."
        } else {
            "fitting / measuring the trade-off..."
        }
    } else {
        "done"
    };
    let title = format!(
        " Model selection ({state})  Enter loads the model · arrows move · c cancels · Esc closes "
    );
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length((view.rows.len() as u16 + 4).min(area.height / 2 + 2)),
            Constraint::Min(5),
        ])
        .split(area);
    let acc = &v.accuracy;
    let header = Row::new(vec![
        "model", "topology", "dof", "J", "max pos", "max ang", "us/case", "fit ms", "targets",
    ])
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = view
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let verdict = if r.meets_targets { "met" } else { "not met" };
            let mark = if Some(i) == view.chosen {
                " <- chosen"
            } else if view.chosen.is_none() && Some(i) == view.closest {
                " <- closest"
            } else {
                ""
            };
            let style = if i == view.selected {
                pal.selected()
            } else {
                Style::default()
            };
            Row::new(vec![
                Cell::from(sanitize_terminal(&r.name).into_owned()),
                Cell::from(r.topology.clone()),
                Cell::from(r.dof.to_string()),
                Cell::from(format!("{:.3e}", r.figures.objective)),
                Cell::from(format!(
                    "{}%",
                    trim_number(r.figures.max_pos_err * 100.0, 3)
                )),
                Cell::from(format!(
                    "{}deg",
                    trim_number(r.figures.max_ang_err.to_degrees(), 3)
                )),
                Cell::from(format!("{:.2}", r.eval_seconds_per_case * 1e6)),
                Cell::from(format!("{:.0}", r.fit_seconds * 1e3)),
                Cell::from(Span::styled(
                    format!("{verdict}{mark}"),
                    pal.pass(r.meets_targets),
                )),
            ])
            .style(style)
        })
        .collect();
    let table = Table::new(
        rows,
        [
            Constraint::Length(11),
            Constraint::Length(11),
            Constraint::Length(4),
            Constraint::Length(10),
            Constraint::Length(8),
            Constraint::Length(9),
            Constraint::Length(8),
            Constraint::Length(7),
            Constraint::Min(8),
        ],
    )
    .header(header)
    .block(
        Block::default()
            .borders(Borders::ALL)
            .border_style(pal.fg(Color::Cyan))
            .title(title),
    );
    let mut tstate = TableState::default().with_selected(Some(view.selected));
    frame.render_stateful_widget(table, parts[0], &mut tstate);

    // The trade-off: log10 time against log10 error, one line per knob.
    let block = Block::default().borders(Borders::ALL).title(format!(
        " Speed/accuracy trade-off: log10 seconds (x) against log10 error (y); targets {}% L, {} deg ",
        trim_number(acc.max_pos_err * 100.0, 3),
        trim_number(acc.max_ang_err.to_degrees(), 3)
    ));
    if view.knobs.is_empty() {
        let msg = if view.running {
            "measuring..."
        } else {
            "no trade-off measured"
        };
        frame.render_widget(Paragraph::new(msg).block(block), parts[1]);
        return;
    }
    let series: Vec<Vec<(f64, f64)>> = view
        .knobs
        .iter()
        .map(|k| {
            k.rows
                .iter()
                .filter(|r| r.seconds > 0.0 && r.error > 0.0 && r.error.is_finite())
                .map(|r| (r.seconds.log10(), r.error.log10()))
                .collect()
        })
        .collect();
    let xs = series.iter().flatten().map(|p| p.0);
    let ys = series.iter().flatten().map(|p| p.1);
    let span = |v: Vec<f64>| {
        let lo = v.iter().cloned().fold(f64::MAX, f64::min);
        let hi = v.iter().cloned().fold(f64::MIN, f64::max);
        if lo > hi {
            [0.0, 1.0]
        } else {
            [lo.floor(), hi.ceil().max(lo.floor() + 1.0)]
        }
    };
    let (xb, yb) = (span(xs.collect()), span(ys.collect()));
    let datasets: Vec<Dataset> = view
        .knobs
        .iter()
        .zip(&series)
        .enumerate()
        .map(|(i, (k, pts))| {
            Dataset::default()
                .name(k.knob)
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(pal.fg(PATH_COLORS[i % PATH_COLORS.len()]))
                .data(pts)
        })
        .collect();
    let chart = Chart::new(datasets)
        .block(block)
        .x_axis(
            Axis::default()
                .bounds(xb)
                .labels([format!("1e{}", xb[0]), format!("1e{}", xb[1])]),
        )
        .y_axis(
            Axis::default()
                .bounds(yb)
                .labels([format!("1e{}", yb[0]), format!("1e{}", yb[1])]),
        )
        .hidden_legend_constraints((Constraint::Ratio(1, 2), Constraint::Ratio(1, 2)));
    frame.render_widget(chart, parts[1]);
}
