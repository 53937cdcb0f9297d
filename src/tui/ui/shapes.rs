//! The shape chart, for every kind of scene: the truth's beam and the PRB model over it, as
//! the worker posed them (each flexure's centre line, the couplers, the stage), at equal
//! aspect; the clamps, and on measured data the measured points as markers
//! ([`MEASURED_MARKER`]) over everything.
//!
//! How much it shows follows how the scene's cases read ([`CaseForm`]):
//! - a cantilever (its tip is its stage): every case of the shown load path at once, the
//!   family of deflected shapes, from a wall at the clamp;
//! - a mechanism: one case of the shown drive (`<` `>`), over the unloaded mechanism in
//!   grey, with a bar across each flexure's clamp and its stage point `P` marked.
//!
//! With `M` it shows the first mode shapes instead (DESIGN §10), the beam's and the PRB
//! model's over each other about the unloaded equilibrium, each mode in its colour: a
//! cantilever's as its transverse motion along the unloaded beam (the tip's 1), a
//! mechanism's as the mechanism displaced by its motion (the same [`MODE_SCALE`] for beam and
//! PRB) over the unloaded mechanism in grey. On a data scene they are the nominal beam's.
//! The shown case's largest fibre stress (DESIGN §11) is on the bottom border (a
//! cantilever's shown case is its path's end, the outermost shape; a mechanism's names its
//! most stressed flexure), with `past limit` when the case lies past its path's stroke limit,
//! and a red `*` on that flexure's centre line where the stress peaks.
//!
//! On a data scene (DESIGN §9) the beam is the scene's beam (or beam mechanism) beside the
//! data (none where it cannot follow them), and a legend on the bottom border names the
//! three.

use std::ops::Range;

use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line as CanvasLine};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};
use ratatui::Frame;

use crate::mech::modes::MechModeShape;
use crate::mech::pose::{self, Pose};
use crate::scene::Mechanism;
use crate::study::dynamics::ModeShapePair;
use crate::study::CaseForm;
use crate::text::sanitize_terminal;

use super::super::app::{Activity, App, MODE_SCALE};
use super::super::units::trim_number;
use super::super::worker::{ModelView, TruthView};
use super::parts::{equal_aspect_bounds, Palette, MEASURED_COLOR, MEASURED_MARKER};

/// What the shape chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// How the scene's cases read: how much the chart shows (module docs).
    pub form: CaseForm,
    /// The shown path (from 0).
    pub path: usize,
    /// How many paths the scene has.
    pub paths: usize,
    /// The shown cases of the path: all of a cantilever's, a mechanism's shown one (none
    /// before there are results).
    pub cases: Range<usize>,
    /// How many cases the shown path has.
    pub path_cases: usize,
    /// The truth the model was judged on.
    pub truth: Option<&'a TruthView>,
    /// The model judged on it.
    pub model: Option<&'a ModelView>,
    /// Why there is no result, when the job failed.
    pub failure: Option<&'a str>,
    /// The mode shapes instead (`M`): the model's, empty when it has none.
    pub modes: Option<&'a [ModeShapePair]>,
    /// The shown case's largest fibre stress (DESIGN §11; a cantilever's shown case is its
    /// path's last, the outermost shape): `(flexure from 0, Pa, s / L)`, and whether the
    /// case is past its path's stroke limit. `None` on measured data (no stress).
    pub stress: Option<((usize, f64, f64), bool)>,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The shape chart of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        let form = app.edit.case_form();
        let path_cases = app.shown_cases();
        let cases = match form {
            CaseForm::Tip => 0..path_cases,
            CaseForm::Stage => match app.edit.mech_state.shown_case(path_cases) {
                Some(c) => c..c + 1,
                None => 0..0,
            },
        };
        let path = app.edit.shown_path();
        let stress = app.shown.truth().and_then(|t| {
            let case = cases.end.checked_sub(1)?;
            let s = t.case_stress(path, case)?;
            let fraction = t.cases.get(path)?.get(case)?.fraction;
            Some((s, t.stroke_limit(path).is_some_and(|l| fraction > l)))
        });
        View {
            form,
            path,
            stress,
            paths: app.edit.path_count(),
            cases,
            path_cases,
            truth: app.shown.truth(),
            model: app.shown.model(),
            failure: match &app.jobs.activity {
                Activity::Failed(m) => Some(m),
                _ => None,
            },
            modes: app
                .show_modes
                .then(|| app.shown.model().map_or(&[][..], |m| &m.mode_shapes[..])),
            pal: Palette { mono: app.mono },
        }
    }
}

/// The shown `cases` of path `path` of `per_path` (none where it has none).
fn of_path<'p, T>(per_path: &'p [Vec<T>], path: usize, cases: &Range<usize>) -> &'p [T] {
    // A model that stopped on this path (DESIGN §6) has only its first cases.
    per_path.get(path).map_or(&[], |p| {
        &p[cases.start.min(p.len())..cases.end.min(p.len())]
    })
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

/// A short bar across each flexure's clamp of the unloaded `rest`, scaled to the chart's
/// bounds.
fn clamp_bars(rest: &Pose, xb: [f64; 2], yb: [f64; 2]) -> Vec<[f64; 4]> {
    let bar = 0.04 * (xb[1] - xb[0]).max(yb[1] - yb[0]);
    rest.flexures
        .iter()
        .filter_map(|line| {
            let (r, t) = (line.first()?, line.last()?);
            let len = (t[0] - r[0]).hypot(t[1] - r[1]).max(1e-12);
            let (nx, ny) = (-(t[1] - r[1]) / len * bar, (t[0] - r[0]) / len * bar);
            Some([r[0] - nx, r[1] - ny, r[0] + nx, r[1] + ny])
        })
        .collect()
}

/// The chart's frame: its title, and on measured data the legend on the bottom border (so
/// that a narrow chart keeps it whole).
fn block<'a>(view: &View, measured: Option<bool>) -> Block<'a> {
    let n = view.path + 1;
    let title = match (view.form, measured) {
        (CaseForm::Tip, None) => format!(
            " Deformed shapes, load path {n} of {}  ([ ] to switch)  beam ─ PRB ─o ",
            view.paths
        ),
        (CaseForm::Tip, Some(_)) => {
            format!(" Deformed shapes, data path {n} of {} ([ ]) ", view.paths)
        }
        (CaseForm::Stage, _) => {
            let case = if view.cases.is_empty() {
                "no case".to_string()
            } else {
                format!("case {}/{}", view.cases.start + 1, view.path_cases)
            };
            let legend = if measured.is_some() {
                ""
            } else {
                "beam ─ PRB ─o  "
            };
            format!(
                " Mechanism  drive {n}/{}  {case}  {legend}[ ] < > ",
                view.paths.max(1)
            )
        }
    };
    let block = Block::default().borders(Borders::ALL).title(title);
    let Some(beam) = measured else {
        let Some(((flexure, pa, at), past)) = view.stress else {
            return block;
        };
        // A cantilever's shown case is its path's end; a mechanism's names its flexure.
        let which = match view.form {
            CaseForm::Tip => " (end)".to_string(),
            CaseForm::Stage => format!(", flexure {}", flexure + 1),
        };
        let mut text = vec![
            Span::raw(format!(
                " σmax {} MPa{which} at s/L {} ",
                trim_number(pa / 1e6, 4),
                trim_number(at, 3)
            )),
            Span::styled("*", view.pal.fg(Color::Red)),
        ];
        if past {
            text.push(Span::styled(" past limit", view.pal.fg(Color::Red)));
        }
        text.push(Span::raw(" "));
        return block.title_bottom(Line::from(text));
    };
    let pal = view.pal;
    let what = match view.form {
        CaseForm::Tip => " measured ",
        CaseForm::Stage => " measured P ",
    };
    let mut legend = vec![
        Span::raw(what),
        Span::styled(MEASURED_MARKER, pal.fg(MEASURED_COLOR)),
    ];
    if beam {
        legend.push(Span::raw("  beam "));
        legend.push(Span::styled("─", pal.fg(Color::Gray)));
    }
    legend.push(Span::raw("  PRB "));
    legend.push(Span::styled("─o", pal.fg(Color::Yellow)));
    legend.push(Span::raw(" "));
    block.title_bottom(Line::from(legend))
}

/// The mode shapes' colours, first mode first.
const MODE_COLORS: [Color; 3] = [Color::Yellow, Color::Cyan, Color::Magenta];

/// Draws the mode shapes (`M`): per mode, in its colour (yellow, cyan, magenta), the
/// beam's shape as lines and the PRB model's through its joints (`o`); the title gives each
/// mode's frequencies, beam/PRB in Hz. A cantilever's are its transverse motion along the
/// unloaded beam, each scaled so the tip moves by 1; a mechanism's are drawn displaced
/// about its unloaded equilibrium (grey), both by the same [`MODE_SCALE`].
fn draw_modes(frame: &mut Frame, area: Rect, view: &View, modes: &[ModeShapePair]) {
    let mechanism = view
        .truth
        .filter(|_| view.form == CaseForm::Stage)
        .map(|t| &t.mechanism);
    let mut title = match mechanism {
        Some(_) => " Mode shapes: beam ─ PRB ─o ".to_string(),
        None => " Modes (tip 1): beam ─ PRB ─o ".to_string(),
    };
    if modes.first().is_some_and(|m| m.nominal) {
        title.push_str(" nominal beam ");
    }
    for m in modes {
        title.push_str(&format!(
            " {}/{}",
            trim_number(m.beam_hz, 4),
            trim_number(m.model_hz, 4)
        ));
    }
    if !modes.is_empty() {
        title.push_str(" Hz ");
    }
    let block = Block::default().borders(Borders::ALL).title(title);
    if modes.is_empty() {
        frame.render_widget(
            Paragraph::new(
                "no mode shapes: they need [beam] density in the scene and a judged PRB model \
                 that rings about the unloaded equilibrium (M: back to the deformed shapes)",
            )
            .wrap(Wrap { trim: true })
            .block(block),
            area,
        );
        return;
    }
    match mechanism {
        Some(mechanism) => draw_mech_modes(frame, area, block, mechanism, modes, view.pal),
        None => draw_tip_modes(frame, area, block, modes, view.pal),
    }
}

/// A cantilever's mode (its one-flexure mechanism's) as its transverse motion `(x, dy)`
/// along the unloaded beam, the tip's 1.
fn transverse(shape: &MechModeShape) -> Vec<[f64; 2]> {
    let line = shape.flexures.first().map_or(&[][..], |l| &l[..]);
    let tip = line.last().map_or(1.0, |p| p.dy);
    let scale = if tip == 0.0 { 1.0 } else { 1.0 / tip };
    line.iter().map(|p| [p.x, scale * p.dy]).collect()
}

/// A cantilever's mode shapes ([`draw_modes`]).
fn draw_tip_modes(
    frame: &mut Frame,
    area: Rect,
    block: Block,
    modes: &[ModeShapePair],
    pal: Palette,
) {
    let lines: Vec<[Vec<[f64; 2]>; 2]> = modes
        .iter()
        .map(|m| [transverse(&m.beam), transverse(&m.model)])
        .collect();
    let (lo, hi) = lines
        .iter()
        .flatten()
        .flatten()
        .fold((0.0_f64, 0.0_f64), |(lo, hi), p| {
            (lo.min(p[1]), hi.max(p[1]))
        });
    let pad = 0.08 * (hi - lo).max(1e-9);
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([-0.02, 1.02])
        .y_bounds([lo - pad, hi + pad])
        .paint(|ctx| {
            ctx.draw(&CanvasLine::new(
                0.0,
                0.0,
                1.0,
                0.0,
                pal.color(Color::DarkGray),
            ));
            for marked in [false, true] {
                for ([beam, model], color) in lines.iter().zip(MODE_COLORS) {
                    let line = if marked { model } else { beam };
                    let color = pal.color(color);
                    for w in line.windows(2) {
                        ctx.draw(&CanvasLine::new(w[0][0], w[0][1], w[1][0], w[1][1], color));
                    }
                }
                ctx.layer();
            }
            for ([_, model], color) in lines.iter().zip(MODE_COLORS) {
                for p in model.iter().skip(1) {
                    ctx.print(p[0], p[1], Span::styled("o", pal.fg(color)));
                }
            }
        });
    frame.render_widget(canvas, area);
}

/// A mechanism's mode shapes ([`draw_modes`]).
fn draw_mech_modes(
    frame: &mut Frame,
    area: Rect,
    block: Block,
    mechanism: &Mechanism,
    modes: &[ModeShapePair],
    pal: Palette,
) {
    let Some(first) = modes.first() else {
        return;
    };
    let rest = pose::mode(mechanism, [0.0; 3], &first.beam, 0.0);
    let mut all = Vec::new();
    points(&rest, &mut all);
    let (x0, x1, y0, y1) = all.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(x0, x1, y0, y1), p| (x0.min(p.0), x1.max(p.0), y0.min(p.1), y1.max(p.1)),
    );
    let size = (x1 - x0).max(y1 - y0);
    let scale = MODE_SCALE
        * if size.is_finite() && size > 0.0 {
            size
        } else {
            1.0
        };
    let poses: Vec<[Pose; 2]> = modes
        .iter()
        .map(|m| {
            [
                pose::mode(mechanism, [0.0; 3], &m.beam, scale),
                pose::mode(mechanism, [0.0; 3], &m.model, scale),
            ]
        })
        .collect();
    for pose in poses.iter().flatten() {
        points(pose, &mut all);
    }
    let (xb, yb) = equal_aspect_bounds(&all, area);
    let clamps = clamp_bars(&rest, xb, yb);
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(|ctx| {
            lines(ctx, &rest, pal.color(Color::DarkGray));
            for c in &clamps {
                let color = pal.color(Color::Gray);
                ctx.draw(&CanvasLine::new(c[0], c[1], c[2], c[3], color));
            }
            ctx.layer();
            for side in 0..2 {
                for (pair, color) in poses.iter().zip(MODE_COLORS) {
                    lines(ctx, &pair[side], pal.color(color));
                }
                ctx.layer();
            }
            for ([_, model], color) in poses.iter().zip(MODE_COLORS) {
                for p in model.flexures.iter().flat_map(|l| l.iter().skip(1)) {
                    ctx.print(p[0], p[1], Span::styled("o", pal.fg(color)));
                }
            }
            let p = rest.stage_point;
            ctx.print(p[0], p[1], Span::styled("P", pal.fg(Color::Cyan)));
        });
    frame.render_widget(canvas, area);
}

/// Draws the shape chart (the mode shapes when `M` asks).
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    if let Some(modes) = view.modes {
        draw_modes(frame, area, view, modes);
        return;
    }
    let measured = view.truth.and_then(|t| t.measured.as_ref());
    let block = block(view, measured.map(|m| m.beam.is_ok()));
    let single = view.form == CaseForm::Stage;
    let path = view.path;
    let cases = view.cases.clone();
    let shown = view.truth.filter(|_| !cases.is_empty()).and_then(|truth| {
        let beams = of_path(&truth.poses, path, &cases);
        let chains = view
            .model
            .map_or(&[][..], |m| of_path(&m.poses, path, &cases));
        // The measured points: the stage point moved by the measured (dx, dy), units of L.
        let p0 = truth.unloaded.stage_point;
        let data: Vec<(f64, f64)> = measured
            .map_or(&[][..], |_| of_path(&truth.cases, path, &cases))
            .iter()
            .map(|c| (p0[0] + c.stage[0], p0[1] + c.stage[1]))
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        (!(beams.is_empty() && data.is_empty())).then_some((truth, beams, chains, data))
    });
    let Some((truth, beams, chains, data)) = shown else {
        let msg = match view.failure {
            Some(m) => format!("no result: {}", sanitize_terminal(m)),
            None if single => "solving the mechanism...".to_string(),
            None => "solving the beam...".to_string(),
        };
        frame.render_widget(
            Paragraph::new(msg).wrap(Wrap { trim: true }).block(block),
            area,
        );
        return;
    };
    let mut all = data.clone();
    points(&truth.unloaded, &mut all);
    for pose in beams.iter().chain(chains) {
        points(pose, &mut all);
    }
    let (xb, yb) = equal_aspect_bounds(&all, area);
    let pal = view.pal;
    let rest_color = pal.color(Color::DarkGray);
    let beam_color = pal.color(Color::Gray);
    let prb_color = pal.color(Color::Yellow);
    let point_color = pal.color(Color::Cyan);
    let data_color = pal.color(MEASURED_COLOR);
    let peak_color = pal.color(Color::Red);
    // The shown case's peak on its flexure's centre line (points at uniform s).
    let peak = view.stress.and_then(|((flexure, _, at), _)| {
        let line = beams.last()?.flexures.get(flexure)?;
        let last = line.len().checked_sub(1)?;
        let k = ((at * last as f64).round() as usize).min(last);
        line.get(k).copied()
    });
    // The clamps: a bar across each flexure's root, a mechanism's short, a cantilever's a
    // wall.
    let clamps: Vec<[f64; 4]> = if single {
        clamp_bars(&truth.unloaded, xb, yb)
    } else {
        vec![[0.0, yb[0] * 0.3, 0.0, yb[1] * 0.3]]
    };
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds(xb)
        .y_bounds(yb)
        .paint(|ctx| {
            // One case shows the mechanism at rest under it, in a layer of its own.
            if single {
                lines(ctx, &truth.unloaded, rest_color);
            }
            for c in &clamps {
                ctx.draw(&CanvasLine::new(c[0], c[1], c[2], c[3], beam_color));
            }
            if single {
                ctx.layer();
            }
            for beam in beams {
                lines(ctx, beam, beam_color);
            }
            ctx.layer();
            for chain in chains {
                lines(ctx, chain, prb_color);
            }
            ctx.layer();
            for p in chains
                .iter()
                .flat_map(|c| &c.flexures)
                .flat_map(|l| l.iter().skip(1))
            {
                ctx.print(
                    p[0],
                    p[1],
                    Span::styled("o", Style::default().fg(prb_color)),
                );
            }
            if single {
                if let Some(p) = beams.first().or(chains.first()).map(|b| b.stage_point) {
                    ctx.print(
                        p[0],
                        p[1],
                        Span::styled("P", Style::default().fg(point_color)),
                    );
                }
            }
            // Where the shown case's stress peaks: a red `*` on its beam.
            if let Some(p) = peak {
                ctx.print(
                    p[0],
                    p[1],
                    Span::styled("*", Style::default().fg(peak_color)),
                );
            }
            // The measured points last: over everything, the PRB's `o` included.
            for &(x, y) in &data {
                let mark = Span::styled(MEASURED_MARKER, Style::default().fg(data_color));
                ctx.print(x, y, mark);
            }
        });
    frame.render_widget(canvas, area);
}
