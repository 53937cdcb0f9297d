//! The one-line bars: the title (scene, fidelity, live refit), the status lines (J and the
//! maximum errors against the targets with what the worker is doing, always shown; on a data
//! scene the data file with its hash and the beam theory's own figures against the data (a
//! mechanism's: the beam mechanism along the measured drives);
//! under them the last message on a line of its own, so no message ever hides J or
//! PASS/FAIL) and the key hints, read from the keymap.

use std::borrow::Cow;

use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use crate::fit::Fidelity;
use crate::mech::figures::Figures as ModelFigures;
use crate::scene::{Accuracy, Mechanism};

use super::super::app::{Activity, App, Tone};
use super::super::keymap;
use super::super::units::trim_number;
use super::{sanitize_terminal, Palette, MEASURED_COLOR};

/// What the title line draws.
#[derive(Debug, Clone)]
pub struct TitleView<'a> {
    /// The scene's name (from its file: sanitized when drawn).
    pub name: &'a str,
    /// The scene has unsaved changes.
    pub dirty: bool,
    /// The fidelity.
    pub fidelity: Fidelity,
    /// Live refit is on.
    pub live: bool,
    /// Colours.
    pub pal: Palette,
}

impl<'a> TitleView<'a> {
    /// The title line of `app`.
    pub fn new(app: &'a App) -> TitleView<'a> {
        TitleView {
            name: &app.scene.name,
            dirty: app.scene_dirty,
            fidelity: app.fidelity,
            live: app.live,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the title line.
pub fn draw_title(frame: &mut Frame, area: Rect, view: &TitleView) {
    let pal = view.pal;
    let mut spans = vec![
        Span::styled(" prbfit ", pal.fg(Color::Black).bg(pal.color(Color::Cyan))),
        Span::raw(" "),
        Span::styled(
            sanitize_terminal(view.name).into_owned(),
            Style::default().add_modifier(Modifier::BOLD),
        ),
    ];
    if view.dirty {
        spans.push(Span::raw(" [modified]"));
    }
    spans.push(Span::raw(format!(
        "  fidelity {}  live refit {}",
        view.fidelity,
        if view.live { "on" } else { "paused" }
    )));
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

/// A model's figures as the status line shows them.
#[derive(Debug, Clone, Copy)]
pub enum Figures<'a> {
    /// A cantilever's: J, tip position and angle errors.
    Beam(&'a ModelFigures),
    /// A mechanism's (DESIGN §8): J, and of the reaction, stage position and stage angle
    /// errors those the drives have (`shown`: force, position, angle).
    Mech(&'a ModelFigures, [bool; 3]),
}

/// Which of a mechanism's errors exist: force (some drive prescribes a coordinate),
/// position (some drive loads `x` or `y`), angle (some drive loads `phi`).
pub fn mech_errors_shown(m: &Mechanism) -> [bool; 3] {
    let any = |f: &dyn Fn(usize, bool) -> bool| {
        m.drives
            .iter()
            .any(|d| (0..3).any(|c| f(c, d.coordinates[c].is_prescribed())))
    };
    [
        any(&|_, prescribed| prescribed),
        any(&|c, prescribed| c < 2 && !prescribed),
        any(&|c, prescribed| c == 2 && !prescribed),
    ]
}

/// A data scene's line (DESIGN §9): the data file, its hash, and the scene's beam against
/// the data.
#[derive(Debug, Clone)]
pub struct DataLine<'a> {
    /// The data file as the scene names it (sanitized when drawn).
    pub file: &'a str,
    /// The first characters of its SHA-256.
    pub sha256: &'a str,
    /// The beam theory's figures against the data, or why it has none; `None` until the
    /// worker has solved it.
    pub beam: Option<Result<BesideFigures, Cow<'a, str>>>,
}

/// The beam theory's figures against measured data: a cantilever's beam, or a mechanism's
/// exact beam mechanism along the measured drives (with the errors its drives have, as
/// [`Figures::Mech`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BesideFigures {
    /// The scene's beam at the measured loads.
    Beam(ModelFigures),
    /// The beam mechanism along the measured drives.
    Mech(ModelFigures, [bool; 3]),
}

impl BesideFigures {
    fn figures(&self) -> Figures<'_> {
        match self {
            BesideFigures::Beam(f) => Figures::Beam(f),
            BesideFigures::Mech(f, shown) => Figures::Mech(f, *shown),
        }
    }
}

/// How many hex digits of a data file's SHA-256 the status line shows.
pub const HASH_PREFIX: usize = 8;

/// What the status line draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The last message (file paths and errors inside are sanitized when drawn).
    pub message: Option<(&'a str, Tone)>,
    /// The shown model's figures.
    pub figures: Option<Figures<'a>>,
    /// The model compared against: its name and figures on the same baseline.
    pub compare: Option<(&'a str, Figures<'a>)>,
    /// A data scene's file and the beam against it.
    pub data: Option<DataLine<'a>>,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// What the worker is doing.
    pub activity: &'a Activity,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The status line of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        let (figures, compare) = match &app.scene.mechanism {
            Some(m) => {
                let shown = mech_errors_shown(m);
                (
                    app.mech_model
                        .as_ref()
                        .map(|v| Figures::Mech(&v.figures, shown)),
                    app.shown_mech_compare()
                        .map(|(n, v)| (n, Figures::Mech(&v.figures, shown))),
                )
            }
            None => (
                app.model.as_ref().map(|m| Figures::Beam(&m.figures)),
                app.shown_compare()
                    .map(|(n, v)| (n, Figures::Beam(&v.figures))),
            ),
        };
        let (w, w_f) = (app.scene.fit.angle_weight, app.scene.fit.force_weight);
        let beam = match &app.scene.mechanism {
            // The beam mechanism's cases are kept; judging them is arithmetic.
            Some(m) => app
                .mech_exact
                .as_ref()
                .and_then(|v| v.beam_against_data(w, w_f))
                .map(|r| {
                    r.map(|e| BesideFigures::Mech(e.figures, mech_errors_shown(m)))
                        .map_err(Cow::Owned)
                }),
            None => app
                .baseline
                .as_ref()
                .and_then(|b| b.measured.as_ref())
                .map(|m| match &m.beam {
                    Ok(b) => Ok(BesideFigures::Beam(b.figures(w))),
                    Err(why) => Err(Cow::Borrowed(why.as_str())),
                }),
        };
        let data = app.scene.truth.as_ref().map(|t| DataLine {
            file: &t.file,
            sha256: t.sha256.get(..HASH_PREFIX).unwrap_or(&t.sha256),
            beam,
        });
        View {
            message: app.message.as_ref().map(|(m, t)| (m.as_str(), *t)),
            figures,
            compare,
            data,
            accuracy: app.scene.accuracy,
            activity: &app.activity,
            pal: Palette { mono: app.mono },
        }
    }
}

/// How many lines [`draw`] takes: the figures, the compared model's (when comparing), the
/// data's (on a data scene), the message.
pub fn height(view: &View) -> u16 {
    2 + u16::from(view.compare.is_some()) + u16::from(view.data.is_some())
}

/// `J | pos ..% PASS<.. | ang ..deg PASS<.. | ` for figures `f` against `acc`; a
/// mechanism's reaction error first, `force ..% FAIL<..`, and only the errors its drives
/// have.
fn figure_spans(f: Figures, acc: &Accuracy, pal: Palette) -> Vec<Span<'static>> {
    let verdict = |ok: bool| Span::styled(if ok { "PASS" } else { "FAIL" }, pal.pass(ok));
    let (objective, pos, ang, force, shown) = match f {
        Figures::Beam(f) => (
            f.objective,
            f.max_pos_err,
            f.max_ang_err,
            0.0,
            [false, true, true],
        ),
        Figures::Mech(f, shown) => (
            f.objective,
            f.max_pos_err,
            f.max_ang_err,
            f.max_force(),
            shown,
        ),
    };
    let mut spans = vec![Span::raw(format!(" J {objective:.3e} | "))];
    let mut figure = |name: &str, value: String, ok: bool, target: String| {
        spans.push(Span::raw(format!("{name} {value} ")));
        spans.push(verdict(ok));
        spans.push(Span::raw(format!("<{target} | ")));
    };
    if shown[0] {
        figure(
            "force",
            format!("{}%", trim_number(force * 100.0, 3)),
            force <= acc.max_force_err,
            trim_number(acc.max_force_err * 100.0, 3),
        );
    }
    if shown[1] {
        figure(
            "pos",
            format!("{}%L", trim_number(pos * 100.0, 3)),
            pos <= acc.max_pos_err,
            trim_number(acc.max_pos_err * 100.0, 3),
        );
    }
    if shown[2] {
        figure(
            "ang",
            format!("{}deg", trim_number(ang.to_degrees(), 3)),
            ang <= acc.max_ang_err,
            trim_number(acc.max_ang_err.to_degrees(), 3),
        );
    }
    spans
}

/// Draws the status lines: the figures and the activity, the compared model's figures (when
/// comparing), then the message (if any).
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let mut spans = match view.figures {
        Some(f) => figure_spans(f, &view.accuracy, pal),
        None => vec![Span::raw(" no model judged yet  ")],
    };
    let activity = match view.activity {
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
    let mut lines = vec![Line::from(spans)];
    if let Some((name, f)) = view.compare {
        let mut spans = figure_spans(f, &view.accuracy, pal);
        spans.push(Span::styled(
            format!("compared with {} (C)", sanitize_terminal(name)),
            pal.fg(Color::DarkGray),
        ));
        lines.push(Line::from(spans));
    }
    if let Some(d) = &view.data {
        lines.push(data_line(d, &view.accuracy, view.activity, pal));
    }
    if let Some((m, tone)) = view.message {
        let style = match tone {
            Tone::Error => pal.fg(Color::Red),
            Tone::Info => Style::default(),
        };
        lines.push(Line::from(Span::styled(
            format!(" {}", sanitize_terminal(m)),
            style,
        )));
    }
    frame.render_widget(Paragraph::new(lines), area);
}

/// ` data FILE sha256 HASH · beam vs data: J .. | pos .. | ang .. |`: which data the
/// scene is judged on, and how far the beam theory (grey in the charts) is from it.
fn data_line(d: &DataLine, acc: &Accuracy, activity: &Activity, pal: Palette) -> Line<'static> {
    let mut spans = vec![Span::styled(
        format!(
            " data {} sha256 {} · beam vs data:",
            sanitize_terminal(d.file),
            d.sha256
        ),
        pal.fg(MEASURED_COLOR),
    )];
    match &d.beam {
        Some(Ok(f)) => spans.extend(figure_spans(f.figures(), acc, pal)),
        Some(Err(why)) => spans.push(Span::styled(
            format!(" none: {}", sanitize_terminal(why)),
            pal.fg(Color::DarkGray),
        )),
        // The worker sends the beam with the job's first result: a job that failed has none.
        None if matches!(activity, Activity::Failed(_)) => spans.push(Span::raw(" no result")),
        None => spans.push(Span::raw(" solving...")),
    }
    Line::from(spans)
}

/// What the hint line draws.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HintsView {
    /// The hints, from the keymap.
    pub text: String,
    /// Colours.
    pub pal: Palette,
}

impl HintsView {
    /// The hint line of `app`: text entry's keys, or the focused panel's hints.
    pub fn new(app: &App) -> HintsView {
        let text = if app.editing.is_some() {
            keymap::EDITING_HINT.to_string()
        } else if let Some((kind, _)) = &app.prompt {
            if kind.is_question() {
                keymap::QUESTION_HINT.to_string()
            } else {
                keymap::PROMPT_HINT.to_string()
            }
        } else {
            keymap::hint_line(app.focus, app.scene.truth.is_some())
        };
        HintsView {
            text,
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the hint line.
pub fn draw_hints(frame: &mut Frame, area: Rect, view: &HintsView) {
    frame.render_widget(
        Paragraph::new(Span::styled(
            view.text.as_str(),
            view.pal.fg(Color::DarkGray),
        )),
        area,
    );
}
