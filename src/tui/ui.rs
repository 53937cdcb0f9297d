//! Drawing: one function per panel, each rendering from the [`App`] snapshot only.
//!
//! Layout: a title line; the beam, load and matrix panels on the left; on the right the
//! deformed shapes (beam and PRB linkage, equal aspect) over the tip-error charts; a status
//! line with the fit's figures against the scene's targets; a key-hint line. Below
//! [`MIN_WIDTH`] x [`MIN_HEIGHT`] only a "too small" note is drawn.

use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine};
use ratatui::widgets::{
    Axis, Block, Borders, Cell, Chart, Clear, Dataset, GraphType, Paragraph, Row, Table,
    TableState, Wrap,
};
use ratatui::Frame;

use crate::prb::Column;

use super::app::{Activity, App, BeamField, EditTarget, Panel, Tone, LOAD_COLUMNS};
use super::units::trim_number;

pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 20;

/// Colours, or none at all under NO_COLOR.
struct Palette {
    mono: bool,
}

impl Palette {
    fn fg(&self, c: Color) -> Style {
        if self.mono {
            Style::default()
        } else {
            Style::default().fg(c)
        }
    }
    fn color(&self, c: Color) -> Color {
        if self.mono {
            Color::Reset
        } else {
            c
        }
    }
    fn focus(&self, focused: bool) -> Style {
        if focused {
            self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
        } else {
            Style::default()
        }
    }
    fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    fn pass(&self, ok: bool) -> Style {
        self.fg(if ok { Color::Green } else { Color::Red })
            .add_modifier(Modifier::BOLD)
    }
}

/// Path colours for the error charts.
const PATH_COLORS: [Color; 6] = [
    Color::Yellow,
    Color::Cyan,
    Color::Magenta,
    Color::Green,
    Color::Blue,
    Color::Red,
];

pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let note = Paragraph::new(format!(
            "Terminal too small: {}x{}. prbfit needs at least {MIN_WIDTH}x{MIN_HEIGHT}. \
             Enlarge the window, or press q to quit.",
            area.width, area.height
        ))
        .wrap(Wrap { trim: true });
        frame.render_widget(note, area);
        return;
    }
    let pal = Palette { mono: app.mono };
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(1),
            Constraint::Min(10),
            Constraint::Length(1),
            Constraint::Length(1),
        ])
        .split(area);
    draw_title(frame, rows[0], app, &pal);
    let left_width = if area.width >= 110 { 46 } else { 38 };
    let cols = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Length(left_width), Constraint::Min(20)])
        .split(rows[1]);
    draw_left(frame, cols[0], app, &pal);
    draw_right(frame, cols[1], app, &pal);
    draw_status(frame, rows[2], app, &pal);
    draw_hints(frame, rows[3], app, &pal);
    if app.select_view.is_some() {
        draw_select(frame, rows[1], app, &pal);
    }
    if app.help {
        draw_help(frame, area, &pal);
    }
    if let Some((kind, tb)) = &app.prompt {
        draw_prompt(frame, area, kind.question(), &tb.text, &pal);
    }
}

fn draw_title(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let mut spans = vec![
        Span::styled(" prbfit ", pal.fg(Color::Black).bg(pal.color(Color::Cyan))),
        Span::raw(" "),
        Span::styled(
            app.scene.name.clone(),
            Style::default().add_modifier(Modifier::BOLD),
        ),
    ];
    if app.scene_dirty {
        spans.push(Span::raw(" [modified]"));
    }
    spans.push(Span::raw(format!(
        "  fidelity {}  live refit {}",
        app.fidelity,
        if app.live { "on" } else { "paused" }
    )));
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

fn panel_block<'a>(title: &'a str, focused: bool, pal: &Palette) -> Block<'a> {
    Block::default()
        .borders(Borders::ALL)
        .border_style(pal.focus(focused))
        .title(Span::styled(title, pal.focus(focused)))
}

fn draw_left(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    // The matrix first (all its rows if it can), then at least four lines of loads; the beam
    // panel takes the rest and scrolls to its selected field when short.
    let matrix_height =
        (app.matrix.len() as u16 + 3).clamp(4, area.height.saturating_sub(9).max(4));
    let beam_height =
        (BeamField::ALL.len() as u16 + 2).min(area.height.saturating_sub(matrix_height + 4).max(3));
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(beam_height),
            Constraint::Min(4),
            Constraint::Length(matrix_height),
        ])
        .split(area);
    draw_beam(frame, parts[0], app, pal);
    draw_loads(frame, parts[1], app, pal);
    draw_matrix(frame, parts[2], app, pal);
}

/// The text of a field, or its editor (with a cursor) when being edited.
fn shown(app: &App, target: &EditTarget, text: String) -> (String, bool) {
    match &app.editing {
        Some((t, tb)) if t == target => (format!("{}_", tb.text), true),
        _ => (text, false),
    }
}

fn draw_beam(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let focused = app.focus == Panel::Beam;
    let b = &app.scene.beam;
    let title = format!(
        " Beam and targets  L/t0 = {} ",
        trim_number(b.slenderness(), 4)
    );
    let block = panel_block(&title, focused, pal);
    let rows: Vec<Row> = BeamField::ALL
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let (text, editing) = shown(app, &EditTarget::Beam(f), app.beam_text(f));
            let style = if editing || (focused && app.beam_row == i) {
                pal.selected()
            } else {
                Style::default()
            };
            Row::new(vec![
                Cell::from(f.label()),
                Cell::from(Span::styled(text, style)),
            ])
        })
        .collect();
    let table = Table::new(rows, [Constraint::Length(11), Constraint::Min(10)])
        .column_spacing(0)
        .block(block);
    let mut state = TableState::default().with_selected(Some(app.beam_row));
    frame.render_stateful_widget(table, area, &mut state);
}

fn draw_loads(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let focused = app.focus == Panel::Loads;
    let block = panel_block(" Load paths ", focused, pal);
    let header = Row::new(
        std::iter::once(Cell::from("#"))
            .chain(LOAD_COLUMNS.iter().map(|c| Cell::from(*c)))
            .collect::<Vec<_>>(),
    )
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = (0..app.scene.loads.len())
        .map(|r| {
            let mut cells = vec![Cell::from(Span::styled(
                format!("{}", r + 1),
                pal.fg(PATH_COLORS[r % PATH_COLORS.len()]),
            ))];
            for c in 0..LOAD_COLUMNS.len() {
                let (text, editing) = shown(
                    app,
                    &EditTarget::Load { row: r, col: c },
                    app.load_text(r, c),
                );
                let style = if editing || (focused && app.load_row == r && app.load_col == c) {
                    pal.selected()
                } else {
                    Style::default()
                };
                cells.push(Cell::from(Span::styled(text, style)));
            }
            Row::new(cells)
        })
        .collect();
    let table = Table::new(
        rows,
        [
            Constraint::Length(2),
            Constraint::Length(9),
            Constraint::Length(9),
            Constraint::Length(8),
            Constraint::Length(5),
        ],
    )
    .header(header)
    .block(block)
    .row_highlight_style(if focused {
        Style::default()
    } else {
        Style::default().add_modifier(Modifier::BOLD)
    });
    let mut state = TableState::default().with_selected(Some(app.load_row));
    frame.render_stateful_widget(table, area, &mut state);
}

fn draw_matrix(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let focused = app.focus == Panel::Matrix;
    let title = format!(" PRB matrix  {}  (! fixed) ", app.matrix.topology());
    let block = panel_block(&title, focused, pal);
    let header = if app.si {
        Row::new(vec!["#", "length", "N m/rad", "N/m"])
    } else {
        Row::new(vec!["#", "gamma", "k_theta", "k_ex"])
    }
    .style(Style::default().add_modifier(Modifier::BOLD));
    let rows: Vec<Row> = app
        .matrix
        .rows()
        .iter()
        .enumerate()
        .map(|(r, row)| {
            let mut cells = vec![Cell::from(format!("{}", r + 1))];
            for (ci, col) in Column::ALL.iter().enumerate() {
                let value = row.get(*col);
                let mut text = app.cell_text(r, *col);
                let fixed = value.is_finite() && !row.free[col.index()];
                if fixed {
                    text.push('!');
                }
                let (text, editing) = shown(app, &EditTarget::Cell { row: r, col: *col }, text);
                let mut style = if value == f64::INFINITY {
                    pal.fg(Color::DarkGray)
                } else if fixed {
                    pal.fg(Color::Yellow)
                } else {
                    pal.fg(Color::Green)
                };
                if editing || (focused && app.matrix_row == r && app.matrix_col == ci) {
                    style = pal.selected();
                }
                cells.push(Cell::from(Span::styled(text, style)));
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
        ],
    )
    .header(header)
    .block(block);
    let mut state = TableState::default().with_selected(Some(app.matrix_row));
    frame.render_stateful_widget(table, area, &mut state);
}

fn draw_right(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Percentage(58), Constraint::Percentage(42)])
        .split(area);
    draw_shapes(frame, parts[0], app, pal);
    let charts = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Percentage(50), Constraint::Percentage(50)])
        .split(parts[1]);
    draw_error_chart(frame, charts[0], app, pal, ErrorKind::Position);
    draw_error_chart(frame, charts[1], app, pal, ErrorKind::Angle);
}

/// Equal-aspect bounds for a braille canvas of `area` (2 x 4 dots per cell) holding `pts`.
pub fn equal_aspect_bounds(pts: &[(f64, f64)], area: Rect) -> ([f64; 2], [f64; 2]) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, 1.0_f64, -0.1_f64, 0.1_f64);
    for &(x, y) in pts.iter().filter(|p| p.0.is_finite() && p.1.is_finite()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let pad = 0.05 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    // World units per dot, made equal along both axes.
    let dots_x = (area.width.saturating_sub(2).max(1) as f64) * 2.0;
    let dots_y = (area.height.saturating_sub(2).max(1) as f64) * 4.0;
    let per_dot = ((x1 - x0) / dots_x).max((y1 - y0) / dots_y);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hx, hy) = (per_dot * dots_x / 2.0, per_dot * dots_y / 2.0);
    ([cx - hx, cx + hx], [cy - hy, cy + hy])
}

fn draw_shapes(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let path = app.shown_path();
    let title = format!(
        " Deformed shapes, load path {} of {}  ([ ] to switch)  beam ─ PRB ─o ",
        path + 1,
        app.scene.loads.len()
    );
    let block = Block::default().borders(Borders::ALL).title(title);
    let cases = app.shown_cases();
    let (Some(baseline), true) = (&app.baseline, !cases.is_empty()) else {
        let msg = match &app.activity {
            Activity::Failed(m) => format!("no result: {m}"),
            _ => "solving the beam...".to_string(),
        };
        frame.render_widget(
            Paragraph::new(msg).wrap(Wrap { trim: true }).block(block),
            area,
        );
        return;
    };
    let mut all: Vec<(f64, f64)> = Vec::new();
    for c in cases.clone() {
        all.extend(&baseline.shapes[c]);
        if let Some(model) = &app.model {
            if let Some(l) = model.linkages.get(c) {
                all.extend(l);
            }
        }
    }
    all.push((0.0, 0.0));
    let (xb, yb) = equal_aspect_bounds(&all, area);
    let beam_color = pal.color(Color::Gray);
    let prb_color = pal.color(Color::Yellow);
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(|ctx| {
            // The clamp.
            ctx.draw(&CanvasLine::new(
                0.0,
                yb[0] * 0.3,
                0.0,
                yb[1] * 0.3,
                beam_color,
            ));
            for c in cases.clone() {
                for w in baseline.shapes[c].windows(2) {
                    ctx.draw(&CanvasLine::new(w[0].0, w[0].1, w[1].0, w[1].1, beam_color));
                }
            }
            ctx.layer();
            if let Some(model) = &app.model {
                for c in cases.clone() {
                    let Some(link) = model.linkages.get(c) else {
                        continue;
                    };
                    for w in link.windows(2) {
                        ctx.draw(&CanvasLine::new(w[0].0, w[0].1, w[1].0, w[1].1, prb_color));
                    }
                }
                ctx.layer();
                for c in cases.clone() {
                    let Some(link) = model.linkages.get(c) else {
                        continue;
                    };
                    for p in link.iter().skip(1) {
                        ctx.print(p.0, p.1, Span::styled("o", Style::default().fg(prb_color)));
                    }
                }
            }
        });
    frame.render_widget(canvas, area);
}

#[derive(Clone, Copy, PartialEq)]
enum ErrorKind {
    Position,
    Angle,
}

/// Axis bounds from data, with zero included and a little headroom.
fn bounds(values: impl Iterator<Item = f64>) -> [f64; 2] {
    let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi - lo < 1e-12 {
        hi = lo + 1.0;
    }
    let pad = 0.08 * (hi - lo);
    [if lo < 0.0 { lo - pad } else { lo }, hi + pad]
}

fn draw_error_chart(frame: &mut Frame, area: Rect, app: &App, pal: &Palette, kind: ErrorKind) {
    let (title, unit) = match kind {
        ErrorKind::Position => (" Tip position error ", "%L"),
        ErrorKind::Angle => (" Tip angle error ", "deg"),
    };
    let block = Block::default().borders(Borders::ALL).title(title);
    let (Some(model), Some(baseline)) = (&app.model, &app.baseline) else {
        frame.render_widget(Paragraph::new("").block(block), area);
        return;
    };
    // One series per load path: error against the fraction of the path's end load.
    let mut series: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut k = 0;
    for p in &baseline.paths {
        let mut pts = Vec::with_capacity(p.steps as usize + 1);
        pts.push((0.0, 0.0));
        for s in 1..=p.steps {
            if let Some(case) = model.cases.get(k) {
                let v = match kind {
                    ErrorKind::Position => case.pos_err * 100.0,
                    ErrorKind::Angle => case.ang_err.to_degrees(),
                };
                if v.is_finite() {
                    pts.push((s as f64 / p.steps as f64, v));
                }
            }
            k += 1;
        }
        series.push(pts);
    }
    let yb = bounds(series.iter().flatten().map(|p| p.1));
    let target = match kind {
        ErrorKind::Position => app.scene.accuracy.max_pos_err * 100.0,
        ErrorKind::Angle => app.scene.accuracy.max_ang_err.to_degrees(),
    };
    let target_line = [(0.0, target), (1.0, target)];
    let neg_target = [(0.0, -target), (1.0, -target)];
    let mut datasets: Vec<Dataset> = series
        .iter()
        .enumerate()
        .map(|(i, pts)| {
            Dataset::default()
                .name(format!("{}", i + 1))
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(pal.fg(PATH_COLORS[i % PATH_COLORS.len()]))
                .data(pts)
        })
        .collect();
    // The scene's target, where it falls inside the plotted range.
    if target <= yb[1] {
        datasets.push(
            Dataset::default()
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(pal.fg(Color::Red))
                .data(&target_line),
        );
    }
    if kind == ErrorKind::Angle && -target >= yb[0] {
        datasets.push(
            Dataset::default()
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(pal.fg(Color::Red))
                .data(&neg_target),
        );
    }
    let chart = Chart::new(datasets)
        .block(block)
        .x_axis(
            Axis::default()
                .title("load")
                .bounds([0.0, 1.0])
                .labels(["0", "1"]),
        )
        .y_axis(
            Axis::default()
                .title(unit)
                .bounds(yb)
                .labels([trim_number(yb[0], 2), trim_number(yb[1], 2)]),
        )
        .hidden_legend_constraints((Constraint::Ratio(0, 1), Constraint::Ratio(0, 1)));
    frame.render_widget(chart, area);
}

fn draw_status(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    if let Some((m, tone)) = &app.message {
        if *tone == Tone::Error {
            let line = Line::from(Span::styled(format!(" {m}"), pal.fg(Color::Red)));
            frame.render_widget(Paragraph::new(line), area);
            return;
        }
    }
    let mut spans = Vec::new();
    match &app.model {
        Some(model) => {
            let f = &model.figures;
            let acc = &app.scene.accuracy;
            let pos_ok = f.max_pos_err <= acc.max_pos_err;
            let ang_ok = f.max_ang_err <= acc.max_ang_err;
            spans.push(Span::raw(format!(" J {:.3e} | pos ", f.objective)));
            spans.push(Span::raw(format!(
                "{}%L ",
                trim_number(f.max_pos_err * 100.0, 3)
            )));
            spans.push(Span::styled(
                if pos_ok { "PASS" } else { "FAIL" },
                pal.pass(pos_ok),
            ));
            spans.push(Span::raw(format!(
                "<{} | ang {}deg ",
                trim_number(acc.max_pos_err * 100.0, 3),
                trim_number(f.max_ang_err.to_degrees(), 3)
            )));
            spans.push(Span::styled(
                if ang_ok { "PASS" } else { "FAIL" },
                pal.pass(ang_ok),
            ));
            spans.push(Span::raw(format!(
                "<{} | ",
                trim_number(acc.max_ang_err.to_degrees(), 3)
            )));
        }
        None => spans.push(Span::raw(" no model judged yet  ")),
    }
    let activity = match &app.activity {
        Activity::Idle => "idle".to_string(),
        Activity::Waiting => "working...".to_string(),
        Activity::Fitting(s) => format!("fitting it {} · {:.0} ms", s.iteration, s.seconds * 1e3),
        Activity::Done {
            seconds,
            stop,
            iterations,
            ..
        } => match stop {
            Some(stop) => format!("{stop} · it {iterations} · {:.0} ms", seconds * 1e3),
            None => format!("judged · {:.0} ms", seconds * 1e3),
        },
        Activity::Failed(_) => "failed".to_string(),
        Activity::Cancelled => "fit cancelled".to_string(),
    };
    spans.push(Span::styled(activity, pal.fg(Color::Cyan)));
    if let Some((m, Tone::Info)) = &app.message {
        spans.push(Span::raw(format!("  | {m}")));
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

fn draw_hints(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let text = if app.editing.is_some() {
        " type a value (0.5 mm, 200 GPa, inf) · Enter accept · Esc cancel"
    } else if app.prompt.is_some() {
        " type · Enter accept · Esc cancel"
    } else {
        match app.focus {
            Panel::Matrix => {
                " ? keys · q quit · Tab panel · Enter edit · f free/fixed · a/d row · t topology · m model · u SI · r fit · c cancel · space live · v fidelity · e export"
            }
            Panel::Loads => {
                " ? keys · q quit · Tab panel · Enter edit · a/d path · [ ] shown path · r fit · c cancel · space live · v fidelity · s save · o open"
            }
            Panel::Beam => {
                " ? keys · q quit · Tab panel · Enter edit (0.5 mm, 200 GPa) · 1/2/3 shear/extension/poisson · r fit · c cancel · space live · v fidelity"
            }
        }
    };
    frame.render_widget(
        Paragraph::new(Span::styled(text, pal.fg(Color::DarkGray))),
        area,
    );
}

/// Every key, for the help overlay (and the README).
pub const HELP: &[(&str, &str)] = &[
    ("Tab / Shift-Tab", "next / previous panel"),
    ("arrows, h j k l", "move inside a panel"),
    (
        "Enter",
        "edit the selected field or cell; Enter accepts, Esc cancels",
    ),
    ("f", "matrix: toggle the cell free (fitted) / fixed (!)"),
    (
        "1 / 2 / 3",
        "beam: switch shear / extension / poisson on or off",
    ),
    ("a / d", "add / delete a matrix row or a load path"),
    (
        "t",
        "matrix from a topology name (L-R-R-R) or a published model",
    ),
    ("m", "cycle the published models: Howell 1R, Su 3R, Chen 3R"),
    (
        "[ / ]",
        "show the previous / next load path in the shape chart",
    ),
    ("r", "fit now"),
    (
        "S",
        "selection: fit the topology ladder, pick the simplest model meeting the targets",
    ),
    ("c, Esc", "cancel the running fit"),
    ("space", "pause / resume live refit after every edit"),
    ("v", "cycle fidelity: draft, normal, precise"),
    ("s / o", "save / open a scene file"),
    (
        "e",
        "export: .toml .json (model file) .xml/.mjcf .urdf .sdf .csv",
    ),
    ("?, F1", "this help (any key closes it)"),
    ("q, Ctrl-C", "quit (asks first if something is unsaved)"),
];

fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let w = width.min(area.width);
    let h = height.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

fn draw_help(frame: &mut Frame, area: Rect, pal: &Palette) {
    let rect = centered(area, 92, HELP.len() as u16 + 2);
    frame.render_widget(Clear, rect);
    let lines: Vec<Line> = HELP
        .iter()
        .map(|(k, v)| {
            Line::from(vec![
                Span::styled(format!(" {k:<16}"), pal.fg(Color::Cyan)),
                Span::raw(*v),
            ])
        })
        .collect();
    let block = Block::default().borders(Borders::ALL).title(" Keys ");
    frame.render_widget(
        Paragraph::new(lines)
            .block(block)
            .wrap(Wrap { trim: false }),
        rect,
    );
}

fn draw_prompt(frame: &mut Frame, area: Rect, question: &str, text: &str, pal: &Palette) {
    let rect = centered(area, 70, 3);
    frame.render_widget(Clear, rect);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(pal.fg(Color::Cyan))
        .title(format!(" {question} "));
    frame.render_widget(Paragraph::new(format!("{text}_")).block(block), rect);
}

/// The selection view: the ladder table over the trade-off chart.
fn draw_select(frame: &mut Frame, area: Rect, app: &App, pal: &Palette) {
    let Some(view) = &app.select_view else { return };
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
    let acc = &app.scene.accuracy;
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
                Cell::from(r.name.clone()),
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
