//! The deformed shapes of the shown load path: the beam's centre lines and the PRB linkage
//! over them, at equal aspect. On a data scene (DESIGN §9) the measured tips are markers
//! over them ([`MEASURED_MARKER`]), and the beam is the scene's beam solved at the measured
//! loads (none when it cannot reach them); a legend on the bottom border names the three.

use std::ops::Range;

use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};
use ratatui::Frame;

use super::super::app::{Activity, App};
use super::super::worker::{BaselineView, ModelView};
use super::{equal_aspect_bounds, sanitize_terminal, Palette, MEASURED_COLOR};

/// The mark of a measured tip.
pub const MEASURED_MARKER: &str = "×";

/// What the shape chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The shown path (0-based) and how many there are.
    pub path: usize,
    /// How many load paths the scene has.
    pub paths: usize,
    /// The baseline and the model judged on it, when there are results.
    pub baseline: Option<&'a BaselineView>,
    /// The model judged on the baseline.
    pub model: Option<&'a ModelView>,
    /// The shown path's cases (indices into the baseline).
    pub cases: Range<usize>,
    /// Why there is no result, when the job failed.
    pub failure: Option<&'a str>,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The shape chart of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        View {
            path: app.shown_path(),
            paths: app.scene.loads.len(),
            baseline: app.baseline.as_deref(),
            model: app.model.as_ref(),
            cases: app.shown_cases(),
            failure: match &app.activity {
                Activity::Failed(m) => Some(m),
                _ => None,
            },
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the shape chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let measured = view.baseline.and_then(|b| b.measured.as_ref());
    let beam_color = view.pal.color(Color::Gray);
    let prb_color = view.pal.color(Color::Yellow);
    let data_color = view.pal.color(MEASURED_COLOR);
    let block = match measured {
        None => Block::default().borders(Borders::ALL).title(format!(
            " Deformed shapes, load path {} of {}  ([ ] to switch)  beam ─ PRB ─o ",
            view.path + 1,
            view.paths
        )),
        // The legend on a border of its own, so that a narrow chart keeps it whole.
        Some(m) => {
            let mut legend = vec![
                Span::raw(" measured "),
                Span::styled(MEASURED_MARKER, Style::default().fg(data_color)),
            ];
            if m.beam.is_ok() {
                legend.push(Span::raw("  beam "));
                legend.push(Span::styled("─", Style::default().fg(beam_color)));
            }
            legend.push(Span::raw("  PRB "));
            legend.push(Span::styled("─o", Style::default().fg(prb_color)));
            legend.push(Span::raw(" "));
            Block::default()
                .borders(Borders::ALL)
                .title(format!(
                    " Deformed shapes, data path {} of {} ([ ]) ",
                    view.path + 1,
                    view.paths
                ))
                .title_bottom(Line::from(legend))
        }
    };
    let cases = view.cases.clone();
    let (Some(baseline), true) = (view.baseline, !cases.is_empty()) else {
        let msg = match view.failure {
            Some(m) => format!("no result: {}", sanitize_terminal(m)),
            None => "solving the beam...".to_string(),
        };
        frame.render_widget(
            Paragraph::new(msg).wrap(Wrap { trim: true }).block(block),
            area,
        );
        return;
    };
    // The beam's shapes: the baseline's, or beside measured data the beam at its loads.
    let beam_shapes: &[Vec<(f64, f64)>] = match measured.map(|m| &m.beam) {
        Some(Ok(beside)) => &beside.shapes,
        Some(Err(_)) => &[],
        None => &baseline.shapes,
    };
    let tips: Vec<(f64, f64)> = measured
        .map(|m| {
            cases
                .clone()
                .filter_map(|c| m.tips.get(c))
                .map(|t| (t.a, t.b))
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect()
        })
        .unwrap_or_default();
    let mut all: Vec<(f64, f64)> = tips.clone();
    for c in cases.clone() {
        if let Some(shape) = beam_shapes.get(c) {
            all.extend(shape);
        }
        if let Some(l) = view.model.and_then(|m| m.linkages.get(c)) {
            all.extend(l);
        }
    }
    all.push((0.0, 0.0));
    let (xb, yb) = equal_aspect_bounds(&all, area);
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
                let Some(shape) = beam_shapes.get(c) else {
                    continue;
                };
                for w in shape.windows(2) {
                    ctx.draw(&CanvasLine::new(w[0].0, w[0].1, w[1].0, w[1].1, beam_color));
                }
            }
            ctx.layer();
            if let Some(model) = view.model {
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
            // The measured tips last: over everything, the PRB tip's `o` included.
            for &(x, y) in &tips {
                ctx.print(
                    x,
                    y,
                    Span::styled(MEASURED_MARKER, Style::default().fg(data_color)),
                );
            }
        });
    frame.render_widget(canvas, area);
}
