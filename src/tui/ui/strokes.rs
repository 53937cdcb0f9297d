//! A mechanism's force–stroke chart (DESIGN §8), as `prbfit plot --kind all` draws it
//! ([`stroke_panels`]): for the shown drive, one panel at a time — the reaction of a
//! prescribed stage coordinate against the drive's stroke, or (for a loaded coordinate) the
//! stage's motion against the load; the beam in grey, the model in yellow, the compared
//! model as grey dots, the shown case marked, and the drive's stroke limit (DESIGN §11) a
//! red dotted line. On a mechanism data scene (DESIGN §9) the
//! truth is the measured cases, drawn as markers ([`MEASURED_MARKER`], as `plot` draws them
//! as crosses), with the beam mechanism along the measured drives in grey beside them and a
//! legend naming the three.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Rect};
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph, Widget};
use ratatui::Frame;

use crate::mech::MechCase;
use crate::plot::errors::bounds;
use crate::plot::mech::stroke_panels;
use crate::plot::ChartKind;
use crate::plot::{Output, StrokePanel};
use crate::scene::COORDINATE_KEYS;

use super::super::app::App;
use super::super::units::trim_number;
use super::super::worker::model_cases;
use super::parts::{Palette, MEASURED_COLOR, MEASURED_MARKER};

/// What the force–stroke chart draws.
#[derive(Debug, Clone)]
pub struct View {
    /// The shown drive's panels: the truth (the beam, or the measured cases), then the
    /// model's curve, then the compared model's, then the beam mechanism beside the data.
    pub panels: Vec<StrokePanel>,
    /// The panel shown (an index into `panels`, wrapping).
    pub shown: usize,
    /// The shown case of the drive (from 0).
    pub case: Option<usize>,
    /// The shown drive's stroke limit (DESIGN §11), a fraction of the drive.
    pub limit: Option<f64>,
    /// A compared model is drawn (the panels' second model curve).
    pub comparing: bool,
    /// The truth is measured data: drawn as markers, not a curve.
    pub measured: bool,
    /// Beside measured data, the beam mechanism's curve: an index into each panel's
    /// `models`.
    pub beside: Option<usize>,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The force–stroke chart of `app`.
    pub fn new(app: &App) -> View {
        let drive = app.edit.shown_path();
        let compare = app.shown.shown_compare().map(|(_, v)| v);
        let truth = app.shown.truth();
        let measured = truth.and_then(|t| t.measured.as_ref());
        let beam_beside = measured.and_then(|m| m.beam.as_ref().ok());
        let beside = beam_beside.map(|_| 1 + usize::from(compare.is_some()));
        let panels = match truth {
            Some(truth) => {
                let mut models = vec![app.shown.model().map_or_else(Vec::new, |m| m.model_cases())];
                models.extend(compare.map(|c| c.model_cases()));
                models.extend(beam_beside.map(|b| model_cases(b)));
                let models: Vec<&[Vec<MechCase>]> = models.iter().map(Vec::as_slice).collect();
                let mut panels: Vec<StrokePanel> =
                    stroke_panels(&truth.mechanism, &truth.cases, &models, ChartKind::All)
                        .into_iter()
                        .filter(|p| p.drive == drive + 1)
                        .collect();
                // The drive's own reaction first: the force along its stroke.
                panels.sort_by_key(|p| !is_along_stroke(p));
                panels
            }
            None => Vec::new(),
        };
        View {
            panels,
            shown: app.edit.mech_state.chart,
            case: app.edit.mech_state.shown_case(app.shown_cases()),
            limit: truth.and_then(|t| t.stroke_limit(drive)),
            comparing: compare.is_some(),
            measured: measured.is_some(),
            beside,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Whether a panel's output is along the drive's input: the reaction of the stroke's own
/// coordinate, or the motion of the load's.
fn is_along_stroke(p: &StrokePanel) -> bool {
    let (disp, load) = COORDINATE_KEYS[p.coordinate.min(2)];
    let input = match p.output {
        Output::Reaction => format!("stroke {disp} "),
        Output::Motion => {
            let mut name = load.to_string();
            name.replace_range(..1, &load[..1].to_uppercase());
            format!("load {name} ")
        }
    };
    p.x_label.starts_with(&input)
}

/// `label` without its unit, and the unit: `reaction Fy (N)` is (`reaction Fy`, `N`).
fn split_unit(label: &str) -> (&str, &str) {
    match label.rsplit_once(" (") {
        Some((name, unit)) => (name, unit.trim_end_matches(')')),
        None => (label, ""),
    }
}

/// A panel's title, short enough for a small chart: `Fy reaction vs dy`, `dx motion vs Fx`.
fn title(p: &StrokePanel) -> String {
    let (disp, load) = COORDINATE_KEYS[p.coordinate.min(2)];
    let what = match p.output {
        Output::Reaction => {
            let mut name = load.to_string();
            name.replace_range(..1, &load[..1].to_uppercase());
            format!("{name} reaction")
        }
        Output::Motion => format!("{disp} motion"),
    };
    let (against, _) = split_unit(&p.x_label);
    let against = against
        .strip_prefix("stroke ")
        .or_else(|| against.strip_prefix("load "))
        .unwrap_or("fraction");
    format!("{what} vs {against}")
}

/// Draws the force–stroke chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let n = view.panels.len();
    let Some(p) = view.panels.get(view.shown % n.max(1)) else {
        let block = Block::default()
            .borders(Borders::ALL)
            .title(" Force-stroke ");
        frame.render_widget(Paragraph::new("").block(block), area);
        return;
    };
    let (_, y_unit) = split_unit(&p.y_label);
    let (_, x_unit) = split_unit(&p.x_label);
    let more = if n > 1 {
        format!(" {}/{n} F", view.shown % n + 1)
    } else {
        String::new()
    };
    let mut block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {}{more} ", title(p)));
    if view.measured {
        // The legend on a border of its own, as the cantilever's data charts have it.
        let mut legend = vec![
            Span::raw(" measured "),
            Span::styled(MEASURED_MARKER, pal.fg(MEASURED_COLOR)),
        ];
        if view.beside.is_some() {
            legend.push(Span::raw("  beam "));
            legend.push(Span::styled("─", pal.fg(Color::Gray)));
        }
        legend.push(Span::raw("  PRB "));
        legend.push(Span::styled("─", pal.fg(Color::Yellow)));
        legend.push(Span::raw(" "));
        block = block.title_bottom(Line::from(legend));
    }
    let pts = |curve: &[[f64; 2]]| -> Vec<(f64, f64)> {
        curve
            .iter()
            .filter(|q| q[0].is_finite() && q[1].is_finite())
            .map(|q| (q[0], q[1]))
            .collect()
    };
    let beam = pts(&p.beam);
    let model = p.models.first().map(|c| pts(c)).unwrap_or_default();
    let compared = if view.comparing {
        p.models.get(1).map(|c| pts(c)).unwrap_or_default()
    } else {
        Vec::new()
    };
    let beside = view
        .beside
        .and_then(|i| p.models.get(i))
        .map(|c| pts(c))
        .unwrap_or_default();
    // The shown case: curves start at rest, so case k is point k + 1.
    let marker: Vec<(f64, f64)> = view
        .case
        .and_then(|k| beam.get(k + 1))
        .copied()
        .into_iter()
        .collect();
    // Measured data: a marker per row but the shown case's (the rest point is no row).
    let rows: Vec<(f64, f64)> = if view.measured {
        beam.iter()
            .enumerate()
            .skip(1)
            .filter(|(i, _)| view.case.map(|k| k + 1) != Some(*i))
            .map(|(_, q)| *q)
            .collect()
    } else {
        Vec::new()
    };
    let all = || beam.iter().chain(&model).chain(&compared).chain(&beside);
    let xb = bounds(all().map(|q| q.0));
    let yb = bounds(all().map(|q| q.1));
    // The truth's curve: the beam's, or beside measured data the beam mechanism's.
    let grey = if view.measured { &beside } else { &beam };
    let mut datasets = vec![
        Dataset::default()
            .marker(Marker::Dot)
            .graph_type(GraphType::Scatter)
            .style(pal.fg(Color::DarkGray))
            .data(&compared),
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(pal.fg(Color::Gray))
            .data(grey),
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(pal.fg(Color::Yellow))
            .data(&model),
    ];
    // The stroke limit: a red dotted line where the drive's input reaches that fraction of
    // its end (the input is proportional along a drive from rest).
    let limit: Vec<(f64, f64)> = view
        .limit
        .zip(beam.last())
        .map(|(l, end)| super::errors::vertical(l * end.0, yb))
        .unwrap_or_default();
    datasets.push(
        Dataset::default()
            .marker(Marker::Dot)
            .graph_type(GraphType::Scatter)
            .style(pal.fg(Color::Red))
            .data(&limit),
    );
    datasets.push(
        Dataset::default()
            .marker(Marker::Dot)
            .graph_type(GraphType::Scatter)
            .style(pal.fg(Color::Cyan))
            .data(&marker),
    );
    let axes = Axes {
        block: &block,
        x: (x_unit, xb),
        y: (y_unit, yb),
    };
    frame.render_widget(axes.chart(datasets), area);
    if !rows.is_empty() {
        // A chart's points are one-symbol markers: the rows are drawn alone on a scratch
        // chart of the same axes, and where its markers fall the screen gets the data's.
        let mut scratch = Buffer::empty(area);
        let rows_only = Dataset::default()
            .marker(Marker::Dot)
            .graph_type(GraphType::Scatter)
            .data(&rows);
        axes.chart(vec![rows_only]).render(area, &mut scratch);
        let style = pal.fg(MEASURED_COLOR);
        mark_points(frame.buffer_mut(), &scratch, area, style);
    }
}

/// A panel's frame and axes, for the chart and for its scratch copy.
struct Axes<'a> {
    block: &'a Block<'a>,
    /// The unit and the bounds of each axis.
    x: (&'a str, [f64; 2]),
    y: (&'a str, [f64; 2]),
}

impl<'a> Axes<'a> {
    fn chart(&self, datasets: Vec<Dataset<'a>>) -> Chart<'a> {
        let axis = |(unit, b): (&'a str, [f64; 2])| {
            Axis::default()
                .title(unit)
                .bounds(b)
                .labels([trim_number(b[0], 3), trim_number(b[1], 3)])
        };
        Chart::new(datasets)
            .block(self.block.clone())
            .x_axis(axis(self.x))
            .y_axis(axis(self.y))
            .hidden_legend_constraints((Constraint::Ratio(0, 1), Constraint::Ratio(0, 1)))
    }
}

/// Puts the measured marker, in `style`, on every cell of `area` where `scratch` (a chart
/// holding only the measured rows, as dots) has a dot.
fn mark_points(buf: &mut Buffer, scratch: &Buffer, area: Rect, style: Style) {
    let dot = ratatui::symbols::DOT;
    for y in area.top()..area.bottom() {
        for x in area.left()..area.right() {
            let hit = scratch.cell((x, y)).is_some_and(|c| c.symbol() == dot);
            if let (true, Some(cell)) = (hit, buf.cell_mut((x, y))) {
                cell.set_symbol(MEASURED_MARKER).set_style(style);
            }
        }
    }
}
