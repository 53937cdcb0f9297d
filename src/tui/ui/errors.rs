//! The tip error charts: position (%L) or angle (deg) error against the fraction of each
//! path's end load, one line per path, with the scene's target as red lines; the model
//! compared against (`C`) as grey dotted lines under them.
//!
//! On a data scene (DESIGN §9) the errors are against the data: the load fraction is each
//! row's load magnitude over its path's last row's, the PRB's error is marked at every
//! measured row, and the scene's beam against the data is a second, grey line per path
//! (named with the PRB's on the bottom border).

use crate::eval::CaseError;
use crate::plot::errors::bounds;
use ratatui::layout::{Constraint, Rect};
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph};
use ratatui::Frame;

use crate::scene::Accuracy;

use super::super::app::App;
use super::super::units::trim_number;
use super::super::worker::{BaselineView, ModelView};
use super::{Palette, PATH_COLORS};

/// Which error a chart shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Tip position error, in % of L.
    Position,
    /// Tip angle error, in degrees.
    Angle,
}

/// What an error chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// Which error.
    pub kind: ErrorKind,
    /// The baseline the model was judged on.
    pub baseline: Option<&'a BaselineView>,
    /// The model's errors.
    pub model: Option<&'a ModelView>,
    /// The compared model's errors, on the same baseline.
    pub compare: Option<&'a ModelView>,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The `kind` error chart of `app`.
    pub fn new(app: &'a App, kind: ErrorKind) -> View<'a> {
        View {
            kind,
            baseline: app.baseline.as_deref(),
            model: app.model.as_ref(),
            compare: app.shown_compare().map(|(_, v)| v),
            accuracy: app.scene.accuracy,
            pal: Palette { mono: app.mono },
        }
    }
}

/// One series per load path: the error of `cases` (one per baseline case) against the
/// fraction of the path's end load: step `s` of `steps` on the beam, on measured data the
/// row's load magnitude over the path's last row's (the rows need not be evenly spaced).
fn path_series(
    baseline: &BaselineView,
    cases: &[CaseError],
    kind: ErrorKind,
) -> Vec<Vec<(f64, f64)>> {
    let measured = baseline.measured.is_some();
    let mut series = Vec::with_capacity(baseline.paths.len());
    let mut k = 0;
    for p in &baseline.paths {
        let mut pts = Vec::with_capacity(p.steps as usize + 1);
        pts.push((0.0, 0.0));
        let end = p.end.magnitude();
        for s in 1..=p.steps {
            if let Some(case) = cases.get(k) {
                let v = match kind {
                    ErrorKind::Position => case.pos_err * 100.0,
                    ErrorKind::Angle => case.ang_err.to_degrees(),
                };
                let x = if measured {
                    case.load.magnitude() / end
                } else {
                    s as f64 / p.steps as f64
                };
                if v.is_finite() && x.is_finite() {
                    pts.push((x, v));
                }
            }
            k += 1;
        }
        series.push(pts);
    }
    series
}

/// The legend under an error chart on measured data: the PRB's mark (`prb`), and the beam's
/// line when the beam beside the data is drawn.
pub(super) fn data_legend(pal: Palette, prb: &'static str, beam: bool) -> Line<'static> {
    let mut legend = vec![
        Span::raw(" PRB "),
        Span::styled(prb, pal.fg(PATH_COLORS[0])),
    ];
    if beam {
        legend.push(Span::raw(" beam "));
        legend.push(Span::styled("─", pal.fg(Color::Gray)));
    }
    legend.push(Span::raw(" "));
    Line::from(legend)
}

/// An error chart's curves in drawing order: the compared model's (dots, dark grey), the
/// beam's against the data (grey line), then the model's per path (coloured lines, named by
/// path when `named`), so the model being worked on draws over the others.
pub(super) fn layered<'a>(
    pal: Palette,
    compared: &'a [Vec<(f64, f64)>],
    beam: &'a [Vec<(f64, f64)>],
    model: &'a [Vec<(f64, f64)>],
    named: bool,
) -> Vec<Dataset<'a>> {
    let mut datasets: Vec<Dataset> = compared
        .iter()
        .map(|pts| {
            Dataset::default()
                .marker(Marker::Dot)
                .graph_type(GraphType::Scatter)
                .style(pal.fg(Color::DarkGray))
                .data(pts)
        })
        .collect();
    datasets.extend(beam.iter().map(|pts| {
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(pal.fg(Color::Gray))
            .data(pts)
    }));
    datasets.extend(model.iter().enumerate().map(|(i, pts)| {
        let d = Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(pal.fg(PATH_COLORS[i % PATH_COLORS.len()]))
            .data(pts);
        if named {
            d.name(format!("{}", i + 1))
        } else {
            d
        }
    }));
    datasets
}

/// Draws one error chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let (kind, pal) = (view.kind, view.pal);
    let (title, unit) = match kind {
        ErrorKind::Position => (" Tip position error ", "%L"),
        ErrorKind::Angle => (" Tip angle error ", "deg"),
    };
    let measured = view.baseline.and_then(|b| b.measured.as_ref());
    let beam_beside = measured.and_then(|m| m.beam.as_ref().ok());
    let mut block = Block::default().borders(Borders::ALL).title(title);
    if measured.is_some() {
        block = block.title_bottom(data_legend(pal, "•", beam_beside.is_some()));
    }
    let (Some(model), Some(baseline)) = (view.model, view.baseline) else {
        frame.render_widget(Paragraph::new("").block(block), area);
        return;
    };
    let series = path_series(baseline, &model.cases, kind);
    let compared = view
        .compare
        .map(|c| path_series(baseline, &c.cases, kind))
        .unwrap_or_default();
    let beam = beam_beside
        .map(|b| path_series(baseline, &b.cases, kind))
        .unwrap_or_default();
    let yb = bounds(
        series
            .iter()
            .chain(&compared)
            .chain(&beam)
            .flatten()
            .map(|p| p.1),
    );
    let target = match kind {
        ErrorKind::Position => view.accuracy.max_pos_err * 100.0,
        ErrorKind::Angle => view.accuracy.max_ang_err.to_degrees(),
    };
    let target_line = [(0.0, target), (1.0, target)];
    let neg_target = [(0.0, -target), (1.0, -target)];
    // The compared model and the beam against the data under the PRB's lines.
    let mut datasets = layered(pal, &compared, &beam, &series, true);
    // The measured rows: a mark on the PRB's line at each (its unloaded start is no row).
    if measured.is_some() {
        datasets.extend(series.iter().enumerate().map(|(i, pts)| {
            Dataset::default()
                .marker(Marker::Dot)
                .graph_type(GraphType::Scatter)
                .style(pal.fg(PATH_COLORS[i % PATH_COLORS.len()]))
                .data(&pts[1.min(pts.len())..])
        }));
    }
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
    render_chart(frame, area, (datasets, block), "load", unit, yb);
}

/// An error chart (the cantilever's and the mechanism's): `x_title` from 0 to 1 of each
/// path, the error in `unit` within `yb`, no legend (the panel's title names the series).
pub(super) fn render_chart(
    frame: &mut Frame,
    area: Rect,
    (datasets, block): (Vec<Dataset<'_>>, Block<'_>),
    x_title: &str,
    unit: &str,
    yb: [f64; 2],
) {
    let chart = Chart::new(datasets)
        .block(block)
        .x_axis(
            Axis::default()
                .title(x_title)
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
