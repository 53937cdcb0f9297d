//! The model-selection view: the topology ladder's table (rows as they are fitted, the
//! chosen or closest marked) over the speed/accuracy trade-off chart. On a mechanism scene
//! the table has the reaction error beside the stage's position and angle errors
//! ([`columns`]), and the models that cannot follow the mechanism are listed under it.

use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::Span;
use ratatui::widgets::{
    Axis, Block, Borders, Cell, Chart, Clear, Dataset, GraphType, Paragraph, Row, Table, TableState,
};
use ratatui::Frame;

use crate::mech::figures::Figures;
use crate::scene::Accuracy;

use crate::study::CaseForm;
use crate::text::sanitize_terminal;

use super::super::app::App;
use super::super::state::select::SelectState;
use super::super::units::trim_number;
use super::parts::{Palette, PATH_COLORS};

/// The figure columns of a selection table, after `model`, `topology` and `dof`: their
/// headers and widths; a mechanism's have the reaction error beside the stage's.
pub fn columns(mechanism: bool) -> (&'static [&'static str], &'static [u16]) {
    if mechanism {
        (&["J", "max force", "max pos", "max ang"], &[10, 10, 8, 9])
    } else {
        (&["J", "max pos", "max ang"], &[10, 8, 9])
    }
}

/// The widths of the table's model and topology columns, its degrees of freedom, its timings
/// (us/case, fit ms), and the room its verdict wants (`not met <- closest`).
const NAMES: [u16; 2] = [11, 11];
const DOF: [u16; 1] = [4];
const TIMINGS: [u16; 2] = [8, 7];
const VERDICT: u16 = 18;

/// A row's cells under [`columns`].
pub fn cells_of(figures: &Figures, mechanism: bool) -> Vec<String> {
    let mut out = vec![format!("{:.3e}", figures.objective)];
    if mechanism {
        out.push(format!("{}%", trim_number(figures.max_force() * 100.0, 3)));
    }
    out.push(format!("{}%", trim_number(figures.max_pos_err * 100.0, 3)));
    out.push(format!(
        "{}deg",
        trim_number(figures.max_ang_err.to_degrees(), 3)
    ));
    out
}

/// What the selection view draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The rows, the choice, the trade-off and the cursor.
    pub state: &'a SelectState,
    /// The scene is a mechanism (its selection lists the models that cannot follow it, not
    /// the trade-off).
    pub mechanism: bool,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// The scene's truth is measured data (no trade-off to measure).
    pub data: bool,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The selection view of `app`, when open.
    pub fn new(app: &'a App) -> Option<View<'a>> {
        Some(View {
            state: app.shown.select.as_ref()?,
            mechanism: app.edit.case_form() == CaseForm::Stage,
            accuracy: app.edit.scene.accuracy,
            data: app.edit.is_data(),
            pal: Palette { mono: app.mono },
        })
    }
}

/// Draws the selection view: the ladder table over the trade-off chart (on a mechanism
/// scene, over the models that cannot follow it).
pub fn draw(frame: &mut Frame, area: Rect, v: &View<'_>) {
    let (view, pal) = (v.state, v.pal);
    let mechanism = v.mechanism;
    frame.render_widget(Clear, area);
    let state = if view.running {
        if view.rows.is_empty() {
            "fitting the ladder..."
        } else if v.data {
            "fitting the ladder on the data..."
        } else if mechanism {
            "fitting the ladder on the mechanism..."
        } else {
            "fitting / measuring the trade-off..."
        }
    } else if view.stopped {
        "stopped: the rows fitted before it, nothing chosen"
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
    let (headers, column_widths) = columns(mechanism);
    // Where the table is narrower than its columns, the timings go first, then the degrees
    // of freedom, so the figures, the topologies and the verdict keep their width (squeezed,
    // J lost its exponent and the 3R, 4R and 5R all read "L-R-").
    // The room a set of columns takes: each width and the space after it.
    let span = |widths: &[u16]| -> u16 { widths.iter().map(|w| w + 1).sum() };
    let room = area.width.saturating_sub(2);
    let kept = span(&NAMES) + span(column_widths) + VERDICT;
    let dof = room >= kept + span(&DOF);
    let timings = room >= kept + span(&DOF) + span(&TIMINGS);
    let header_cells: Vec<&str> = ["model", "topology"]
        .into_iter()
        .chain(dof.then_some("dof"))
        .chain(headers.iter().copied())
        .chain(if timings {
            vec!["us/case", "fit ms"]
        } else {
            vec![]
        })
        .chain(["targets"])
        .collect();
    let header = Row::new(header_cells).style(Style::default().add_modifier(Modifier::BOLD));
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
            let mut cells = vec![
                Cell::from(sanitize_terminal(&r.name).into_owned()),
                Cell::from(r.topology.clone()),
            ];
            if dof {
                cells.push(Cell::from(r.dof.to_string()));
            }
            cells.extend(cells_of(&r.figures, mechanism).into_iter().map(Cell::from));
            if timings {
                cells.extend([
                    Cell::from(format!("{:.2}", r.eval_seconds_per_case * 1e6)),
                    Cell::from(format!("{:.0}", r.fit_seconds * 1e3)),
                ]);
            }
            cells.push(Cell::from(Span::styled(
                format!("{verdict}{mark}"),
                pal.pass(r.meets_targets),
            )));
            Row::new(cells).style(style)
        })
        .collect();
    let widths: Vec<Constraint> = NAMES
        .iter()
        .chain(if dof { &DOF[..] } else { &[][..] })
        .chain(column_widths)
        .chain(if timings { &TIMINGS[..] } else { &[][..] })
        .map(|&w| Constraint::Length(w))
        .chain(std::iter::once(Constraint::Min(8)))
        .collect();
    let table = Table::new(rows, widths).header(header).block(
        Block::default()
            .borders(Borders::ALL)
            .border_style(pal.fg(Color::Cyan))
            .title(title),
    );
    let mut tstate = TableState::default().with_selected(Some(view.selected));
    frame.render_stateful_widget(table, parts[0], &mut tstate);
    if mechanism {
        draw_unfollowed(frame, parts[1], view, v.data);
        return;
    }

    // The trade-off: log10 time against log10 error, one line per knob.
    let block = Block::default().borders(Borders::ALL).title(format!(
        " Speed/accuracy trade-off: log10 seconds (x) against log10 error (y); targets {}% L, {} deg ",
        trim_number(acc.max_pos_err * 100.0, 3),
        trim_number(acc.max_ang_err.to_degrees(), 3)
    ));
    if view.knobs.is_empty() {
        let msg = if v.data {
            "none on measured data: the trade-off measures the beam's resolution and the load \
             sampling, which data does not have"
        } else if view.running {
            "measuring..."
        } else {
            "no trade-off measured"
        };
        frame.render_widget(
            Paragraph::new(msg)
                .wrap(ratatui::widgets::Wrap { trim: true })
                .block(block),
            parts[1],
        );
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

/// A mechanism selection's lower part: the models that cannot follow the mechanism and why
/// (the trade-off is measured on cantilever scenes only, and none on measured data).
fn draw_unfollowed(frame: &mut Frame, area: Rect, view: &SelectState, data: bool) {
    let block = Block::default()
        .borders(Borders::ALL)
        .title(" Models that cannot follow the mechanism ");
    let text = if view.unfollowed.is_empty() {
        if view.running {
            "fitting...".to_string()
        } else if data {
            "none: every model tried follows the measured drives (none on measured data: the \
             speed/accuracy trade-off measures the beam's resolution and the load sampling, \
             which data does not have)"
                .to_string()
        } else {
            "none: every model tried follows the mechanism (the speed/accuracy trade-off is \
             measured on cantilever scenes)"
                .to_string()
        }
    } else {
        view.unfollowed
            .iter()
            .map(|u| {
                format!(
                    "{}: {}",
                    sanitize_terminal(&u.name),
                    sanitize_terminal(&u.reason)
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    frame.render_widget(
        Paragraph::new(text)
            .wrap(ratatui::widgets::Wrap { trim: true })
            .block(block),
        area,
    );
}
