//! A mechanism's force–stroke chart (DESIGN §8), as `prbfit plot --kind all` draws it
//! ([`stroke_panels`]): for the shown drive, one panel at a time — the reaction of a
//! prescribed stage coordinate against the drive's stroke, or (for a loaded coordinate) the
//! stage's motion against the load; the beam in grey, the model in yellow, the compared
//! model as grey dots, the shown case marked.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::widgets::{Axis, Block, Borders, Chart, Dataset, GraphType, Paragraph};
use ratatui::Frame;

use crate::mech::MechCase;
use crate::plot::errors::bounds;
use crate::plot::mech::{stroke_panels, Output, StrokePanel};
use crate::plot::ChartKind;
use crate::scene::COORDINATE_KEYS;

use super::super::app::App;
use super::super::units::trim_number;
use super::Palette;

/// What the force–stroke chart draws.
#[derive(Debug, Clone)]
pub struct View {
    /// The shown drive's panels: beam, then the model's curve, then the compared model's.
    pub panels: Vec<StrokePanel>,
    /// The panel shown (an index into `panels`, wrapping).
    pub shown: usize,
    /// The shown case of the drive (from 0).
    pub case: Option<usize>,
    /// A compared model is drawn (the panels' second model curve).
    pub comparing: bool,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The force–stroke chart of `app`.
    pub fn new(app: &App) -> View {
        let drive = app.shown_drive();
        let compare = app.shown_mech_compare().map(|(_, v)| v);
        let panels = match &app.mech_exact {
            Some(exact) => {
                let none: Vec<Vec<MechCase>> = Vec::new();
                let model = app.mech_model.as_ref().map_or(&none, |m| &m.cases);
                let mut models: Vec<&[Vec<MechCase>]> = vec![model];
                if let Some(c) = compare {
                    models.push(&c.cases);
                }
                let mut panels: Vec<StrokePanel> =
                    stroke_panels(&exact.mechanism, &exact.cases, &models, ChartKind::All)
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
            shown: app.mech_state.chart,
            case: app.mech_state.shown_case(app.shown_drive_cases()),
            comparing: compare.is_some(),
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
    let block = Block::default()
        .borders(Borders::ALL)
        .title(format!(" {}{more} ", title(p)));
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
    // The shown case: curves start at rest, so case k is point k + 1.
    let marker: Vec<(f64, f64)> = view
        .case
        .and_then(|k| beam.get(k + 1))
        .copied()
        .into_iter()
        .collect();
    let all = || beam.iter().chain(&model).chain(&compared);
    let xb = bounds(all().map(|q| q.0));
    let yb = bounds(all().map(|q| q.1));
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
            .data(&beam),
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(pal.fg(Color::Yellow))
            .data(&model),
    ];
    datasets.push(
        Dataset::default()
            .marker(Marker::Dot)
            .graph_type(GraphType::Scatter)
            .style(pal.fg(Color::Cyan))
            .data(&marker),
    );
    let chart = Chart::new(datasets)
        .block(block)
        .x_axis(
            Axis::default()
                .title(x_unit)
                .bounds(xb)
                .labels([trim_number(xb[0], 3), trim_number(xb[1], 3)]),
        )
        .y_axis(
            Axis::default()
                .title(y_unit)
                .bounds(yb)
                .labels([trim_number(yb[0], 3), trim_number(yb[1], 3)]),
        )
        .hidden_legend_constraints((Constraint::Ratio(0, 1), Constraint::Ratio(0, 1)));
    frame.render_widget(chart, area);
}
