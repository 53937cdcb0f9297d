//! The deformed shapes of the shown load path: the beam's centre lines and the PRB linkage
//! over them, at equal aspect.

use std::ops::Range;

use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::Span;
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};
use ratatui::Frame;

use super::super::app::{Activity, App};
use super::super::worker::{BaselineView, ModelView};
use super::{equal_aspect_bounds, sanitize_terminal, Palette};

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
    let title = format!(
        " Deformed shapes, load path {} of {}  ([ ] to switch)  beam ─ PRB ─o ",
        view.path + 1,
        view.paths
    );
    let block = Block::default().borders(Borders::ALL).title(title);
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
    let mut all: Vec<(f64, f64)> = Vec::new();
    for c in cases.clone() {
        all.extend(&baseline.shapes[c]);
        if let Some(l) = view.model.and_then(|m| m.linkages.get(c)) {
            all.extend(l);
        }
    }
    all.push((0.0, 0.0));
    let (xb, yb) = equal_aspect_bounds(&all, area);
    let beam_color = view.pal.color(Color::Gray);
    let prb_color = view.pal.color(Color::Yellow);
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
        });
    frame.render_widget(canvas, area);
}
