//! The error chart, for every kind of scene: one error of the model against the truth, in
//! % or degrees, against the fraction of each path (a load path's end load, a drive's
//! stroke, a measured path's rows), one line per path from rest, with the scene's target as
//! a red line (both signs for the signed angle error); the model compared against (`C`) as
//! grey dots under them.
//!
//! Each path's stroke limit (DESIGN §11), when the scene has an allowable stress, is a dotted
//! vertical line in the path's colour.
//!
//! A cantilever has two: its tip's position (%L) and angle (deg) errors. A mechanism has
//! its main one: the reaction error (% of each prescribed coordinate's largest reaction)
//! when a drive prescribes a stage coordinate, else the stage position error (% of flexure
//! 1's `L`). On a data scene (DESIGN §9) the errors are against the measured cases: the
//! model's error is marked at every measured row, and the scene's beam (or beam mechanism)
//! against the data is a grey line per path, named with the model's on the bottom border.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph};
use ratatui::Frame;

use crate::mech::figures::JudgedCase;
use crate::plot::errors::bounds;
use crate::scene::Accuracy;
use crate::study::CaseForm;

use super::super::app::App;
use super::super::units::trim_number;
use super::super::worker::{ModelView, TruthView};
use super::parts::{Palette, PATH_COLORS};

/// Which error a chart shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Position error (a cantilever's tip, a mechanism's stage), in % of L.
    Position,
    /// Angle error, in degrees (signed).
    Angle,
    /// Reaction error of the prescribed coordinates, in % of each one's largest reaction.
    Force,
}

impl ErrorKind {
    /// A case's error of this kind, in the chart's unit.
    fn of(self, c: &JudgedCase) -> f64 {
        match self {
            ErrorKind::Position => c.pos_err * 100.0,
            ErrorKind::Angle => c.ang_err.to_degrees(),
            ErrorKind::Force => c.force_err * 100.0,
        }
    }

    /// The chart's title, unit and the scene's target in that unit.
    fn labels(self, form: CaseForm, acc: &Accuracy) -> (&'static str, &'static str, f64) {
        let tip = form == CaseForm::Tip;
        match self {
            ErrorKind::Position if tip => (" Tip position error ", "%L", acc.max_pos_err * 100.0),
            ErrorKind::Position => (" Stage position error ", "%L", acc.max_pos_err * 100.0),
            ErrorKind::Angle if tip => (" Tip angle error ", "deg", acc.max_ang_err.to_degrees()),
            ErrorKind::Angle => (" Stage angle error ", "deg", acc.max_ang_err.to_degrees()),
            ErrorKind::Force => (" Reaction error ", "% of max", acc.max_force_err * 100.0),
        }
    }
}

/// A truth's main error: the reaction error when a path prescribes a stage coordinate, else
/// the position error.
pub fn main_kind(truth: &TruthView) -> ErrorKind {
    if truth.prescribes() {
        ErrorKind::Force
    } else {
        ErrorKind::Position
    }
}

/// What an error chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// How the scene's cases read (a cantilever's tips, a mechanism's stage).
    pub form: CaseForm,
    /// Which error; `None`: the truth's main one ([`main_kind`]), once there is a truth.
    pub kind: Option<ErrorKind>,
    /// The truth the model was judged on.
    pub truth: Option<&'a TruthView>,
    /// The model's errors.
    pub model: Option<&'a ModelView>,
    /// The compared model's errors, on the same truth.
    pub compare: Option<&'a ModelView>,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The `kind` error chart of `app` (`None`: its truth's main error).
    pub fn new(app: &'a App, kind: Option<ErrorKind>) -> View<'a> {
        View {
            form: app.edit.case_form(),
            kind,
            truth: app.shown.truth(),
            model: app.shown.model(),
            compare: app.shown.shown_compare().map(|(_, v)| v),
            accuracy: app.edit.scene.accuracy,
            pal: Palette { mono: app.mono },
        }
    }
}

/// One series per path: the `kind` error of each judged case against the path's fraction,
/// from rest.
fn series(cases: &[Vec<JudgedCase>], kind: ErrorKind) -> Vec<Vec<(f64, f64)>> {
    cases
        .iter()
        .map(|path| {
            std::iter::once((0.0, 0.0))
                .chain(
                    path.iter()
                        .map(|c| (c.fraction, kind.of(c)))
                        .filter(|p| p.0.is_finite() && p.1.is_finite()),
                )
                .collect()
        })
        .collect()
}

/// The legend under an error chart on measured data: the model's marks, and the beam's
/// line when the beam beside the data is drawn.
fn data_legend(pal: Palette, beam: bool) -> Line<'static> {
    let mut legend = vec![
        Span::raw(" PRB "),
        Span::styled("•", pal.fg(PATH_COLORS[0])),
    ];
    if beam {
        legend.push(Span::raw(" beam "));
        legend.push(Span::styled("─", pal.fg(Color::Gray)));
    }
    legend.push(Span::raw(" "));
    Line::from(legend)
}

/// A line of `pts` in `color`.
fn line<'a>(pal: Palette, color: Color, pts: &'a [(f64, f64)]) -> Dataset<'a> {
    Dataset::default()
        .marker(Marker::Braille)
        .graph_type(GraphType::Line)
        .style(pal.fg(color))
        .data(pts)
}

/// Dots at `pts` in `color`.
fn dots<'a>(pal: Palette, color: Color, pts: &'a [(f64, f64)]) -> Dataset<'a> {
    Dataset::default()
        .marker(Marker::Dot)
        .graph_type(GraphType::Scatter)
        .style(pal.fg(color))
        .data(pts)
}

/// Points down a vertical line at `x` across `yb`, for a dotted line.
pub fn vertical(x: f64, yb: [f64; 2]) -> Vec<(f64, f64)> {
    (0..=24)
        .map(|k| (x, yb[0] + (yb[1] - yb[0]) * f64::from(k) / 24.0))
        .collect()
}

/// Draws one error chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let kind = view.kind.or_else(|| view.truth.map(main_kind));
    let measured = view.truth.and_then(|t| t.measured.as_ref());
    let beam_beside = measured.and_then(|m| m.beam.as_ref().ok());
    let labels = kind.map(|k| k.labels(view.form, &view.accuracy));
    let title = labels.map_or(" Errors ", |(title, _, _)| title);
    let mut block = Block::default().borders(Borders::ALL).title(title);
    if measured.is_some() {
        block = block.title_bottom(data_legend(pal, beam_beside.is_some()));
    }
    let (Some(kind), Some((_, unit, target)), Some(model)) = (kind, labels, view.model) else {
        frame.render_widget(Paragraph::new("").block(block), area);
        return;
    };
    let lines = series(&model.cases, kind);
    let compared = view
        .compare
        .map(|c| series(&c.cases, kind))
        .unwrap_or_default();
    let beam = beam_beside.map(|b| series(b, kind)).unwrap_or_default();
    let yb = bounds(
        lines
            .iter()
            .chain(&compared)
            .chain(&beam)
            .flatten()
            .map(|p| p.1),
    );
    let target_line = [(0.0, target), (1.0, target)];
    let neg_target = [(0.0, -target), (1.0, -target)];
    // The compared model (dots, dark grey), the beam against the data (grey lines), then the
    // model's per path, so the model being worked on draws over the others.
    let mut datasets: Vec<Dataset> = compared
        .iter()
        .map(|pts| dots(pal, Color::DarkGray, pts))
        .collect();
    datasets.extend(beam.iter().map(|pts| line(pal, Color::Gray, pts)));
    let color = |i: usize| PATH_COLORS[i % PATH_COLORS.len()];
    datasets.extend(
        lines
            .iter()
            .enumerate()
            .map(|(i, pts)| line(pal, color(i), pts)),
    );
    // The measured rows: a mark on the model's line at each (its start at rest is no row).
    if measured.is_some() {
        datasets.extend(
            lines
                .iter()
                .enumerate()
                .map(|(i, pts)| dots(pal, color(i), &pts[1.min(pts.len())..])),
        );
    }
    // Each path's stroke limit (DESIGN §11): a dotted vertical line in the path's colour.
    let limits: Vec<(usize, Vec<(f64, f64)>)> = view
        .truth
        .and_then(|t| t.stroke_limits.as_ref())
        .map(|ls| {
            ls.iter()
                .enumerate()
                .filter_map(|(i, l)| Some((i, vertical(l.fraction?, yb))))
                .collect()
        })
        .unwrap_or_default();
    datasets.extend(limits.iter().map(|(i, pts)| dots(pal, color(*i), pts)));
    // The scene's target, where it falls inside the plotted range.
    if target <= yb[1] {
        datasets.push(line(pal, Color::Red, &target_line));
    }
    if kind == ErrorKind::Angle && -target >= yb[0] {
        datasets.push(line(pal, Color::Red, &neg_target));
    }
    let x_title = match view.form {
        CaseForm::Tip => "load",
        CaseForm::Stage => "drive",
    };
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
        // No legend: the title names the error, the colours the paths.
        .hidden_legend_constraints((Constraint::Ratio(0, 1), Constraint::Ratio(0, 1)));
    frame.render_widget(chart, area);
}
