//! A mechanism's shape chart (DESIGN §8): one case of the shown drive, every flexure as the
//! exact beam and as the PRB chain over it, the couplers and the stage (its point `P` joined
//! to where the flexures meet it), over the unloaded mechanism in grey, at equal aspect. On a
//! mechanism data scene (DESIGN §9) the beam is the beam mechanism along the measured drives
//! (none when it cannot follow them) and the measured stage point is marked
//! ([`MEASURED_MARKER`]), with a legend naming the three on the bottom border.

use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line as CanvasLine};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};
use ratatui::Frame;

use crate::mech::pose::Pose;

use super::super::app::{Activity, App};
use super::super::worker::{MechBaselineView, MechModelView};
use super::shapes::MEASURED_MARKER;
use super::{equal_aspect_bounds, sanitize_terminal, Palette, MEASURED_COLOR};

/// What the mechanism shape chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The shown drive (from 0) and how many there are.
    pub drive: usize,
    /// How many drives the mechanism has.
    pub drives: usize,
    /// The shown case of the drive (from 0), when there are results.
    pub case: Option<usize>,
    /// The exact mechanism.
    pub exact: Option<&'a MechBaselineView>,
    /// The model judged on it.
    pub model: Option<&'a MechModelView>,
    /// Why there is no result, when the job failed.
    pub failure: Option<&'a str>,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The mechanism shape chart of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        let drive = app.shown_drive();
        View {
            drive,
            drives: app.scene.mechanism.as_ref().map_or(0, |m| m.drives.len()),
            case: app.mech_state.shown_case(app.shown_drive_cases()),
            exact: app.mech_exact.as_deref(),
            model: app.mech_model.as_ref(),
            failure: match &app.activity {
                Activity::Failed(m) => Some(m),
                _ => None,
            },
            pal: Palette { mono: app.mono },
        }
    }
}

/// Points of a pose, for the chart's bounds.
fn points(pose: &Pose, out: &mut Vec<(f64, f64)>) {
    let all = pose
        .flexures
        .iter()
        .flatten()
        .chain(pose.couplers.iter().flatten())
        .chain(&pose.stage)
        .chain(std::iter::once(&pose.stage_point))
        .chain(&pose.roots);
    out.extend(all.map(|p| (p[0], p[1])));
}

/// Draws a pose's lines in `color`: flexures, couplers, the stage.
fn lines(ctx: &mut Context, pose: &Pose, color: Color) {
    let mut seg = |a: &[f64; 2], b: &[f64; 2]| {
        ctx.draw(&CanvasLine::new(a[0], a[1], b[0], b[1], color));
    };
    for line in &pose.flexures {
        for w in line.windows(2) {
            seg(&w[0], &w[1]);
        }
    }
    for [a, b] in &pose.couplers {
        seg(a, b);
    }
    for s in &pose.stage {
        seg(&pose.stage_point, s);
    }
}

/// Draws the mechanism shape chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let case_text = match view.case {
        Some(c) => {
            let cases = view
                .exact
                .and_then(|e| e.cases.get(view.drive))
                .map_or(0, Vec::len);
            format!("case {}/{cases}", c + 1)
        }
        None => "no case".into(),
    };
    let measured = view.exact.and_then(|e| e.measured.as_ref());
    // On data the legend is on the bottom border, naming the data's marker too.
    let legend = if measured.is_some() {
        ""
    } else {
        "beam ─ PRB ─o  "
    };
    let title = format!(
        " Mechanism  drive {}/{}  {case_text}  {legend}[ ] < > ",
        view.drive + 1,
        view.drives.max(1),
    );
    let mut block = Block::default().borders(Borders::ALL).title(title);
    if let Some(m) = measured {
        let pal = view.pal;
        let mut legend = vec![
            Span::raw(" measured P "),
            Span::styled(MEASURED_MARKER, pal.fg(MEASURED_COLOR)),
        ];
        if m.beam.is_ok() {
            legend.push(Span::raw("  beam "));
            legend.push(Span::styled("─", pal.fg(Color::Gray)));
        }
        legend.push(Span::raw("  PRB "));
        legend.push(Span::styled("─o", pal.fg(Color::Yellow)));
        legend.push(Span::raw(" "));
        block = block.title_bottom(Line::from(legend));
    }
    let shown = view.exact.zip(view.case).and_then(|(e, c)| {
        let beam = e.poses.get(view.drive).and_then(|d| d.get(c));
        let chain = view
            .model
            .and_then(|m| m.poses.get(view.drive))
            .and_then(|d| d.get(c));
        // The measured stage point: P moved by the measured (dx, dy), units of L.
        let data_point = e
            .measured
            .as_ref()
            .and(e.cases.get(view.drive))
            .and_then(|d| d.get(c))
            .map(|c| {
                let p = e.unloaded.stage_point;
                [p[0] + c.stage[0], p[1] + c.stage[1]]
            })
            .filter(|p| p[0].is_finite() && p[1].is_finite());
        (beam.is_some() || data_point.is_some()).then_some((e, beam, chain, data_point))
    });
    let Some((exact, beam, chain, data_point)) = shown else {
        let msg = match view.failure {
            Some(m) => format!("no result: {}", sanitize_terminal(m)),
            None => "solving the mechanism...".to_string(),
        };
        frame.render_widget(
            Paragraph::new(msg).wrap(Wrap { trim: true }).block(block),
            area,
        );
        return;
    };
    let mut all = Vec::new();
    points(&exact.unloaded, &mut all);
    if let Some(b) = beam {
        points(b, &mut all);
    }
    if let Some(c) = chain {
        points(c, &mut all);
    }
    all.extend(data_point.map(|p| (p[0], p[1])));
    let (xb, yb) = equal_aspect_bounds(&all, area);
    let rest_color = view.pal.color(Color::DarkGray);
    let beam_color = view.pal.color(Color::Gray);
    let prb_color = view.pal.color(Color::Yellow);
    let point_color = view.pal.color(Color::Cyan);
    let data_color = view.pal.color(MEASURED_COLOR);
    // The clamps: a short bar across each flexure's root.
    let bar = 0.04 * (xb[1] - xb[0]).max(yb[1] - yb[0]);
    let clamps: Vec<[f64; 4]> = exact
        .unloaded
        .flexures
        .iter()
        .filter_map(|line| {
            let (r, t) = (line.first()?, line.last()?);
            let len = (t[0] - r[0]).hypot(t[1] - r[1]).max(1e-12);
            let (nx, ny) = (-(t[1] - r[1]) / len * bar, (t[0] - r[0]) / len * bar);
            Some([r[0] - nx, r[1] - ny, r[0] + nx, r[1] + ny])
        })
        .collect();
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(|ctx| {
            lines(ctx, &exact.unloaded, rest_color);
            for c in &clamps {
                ctx.draw(&CanvasLine::new(c[0], c[1], c[2], c[3], beam_color));
            }
            ctx.layer();
            if let Some(beam) = beam {
                lines(ctx, beam, beam_color);
            }
            ctx.layer();
            if let Some(chain) = chain {
                lines(ctx, chain, prb_color);
                ctx.layer();
                for line in &chain.flexures {
                    for p in line.iter().skip(1) {
                        ctx.print(
                            p[0],
                            p[1],
                            Span::styled("o", Style::default().fg(prb_color)),
                        );
                    }
                }
            }
            if let Some(p) = beam.or(chain).map(|b| b.stage_point) {
                ctx.print(
                    p[0],
                    p[1],
                    Span::styled("P", Style::default().fg(point_color)),
                );
            }
            // The measured stage point last: over everything.
            if let Some(p) = data_point {
                ctx.print(
                    p[0],
                    p[1],
                    Span::styled(MEASURED_MARKER, Style::default().fg(data_color)),
                );
            }
        });
    frame.render_widget(canvas, area);
}
