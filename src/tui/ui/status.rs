//! The one-line bars: the title (scene, fidelity, live refit), the status lines (J and the
//! maximum errors against the targets with what the worker is doing, always shown; on a data
//! scene the data file with its hash and the beam theory's own figures against the data (a
//! mechanism's: the beam mechanism along the measured drives); with `[beam] density` the
//! first natural frequencies of the beam and the model in Hz, with PASS/FAIL against
//! `max_freq_err` on those the fit matches;
//! under them the last message on a line of its own, so no message ever hides J or
//! PASS/FAIL) and the key hints, read from the keymap.

use std::borrow::Cow;

use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use crate::fit::Fidelity;
use crate::mech::figures::{Figures, Frequencies, UnfollowedPath};
use crate::scene::{Accuracy, Mechanism};

use crate::text::sanitize_terminal;

use super::super::app::{Activity, App, Tone};
use super::super::keymap;
use super::super::units::trim_number;
use super::super::worker::ModelView;
use super::parts::{wrap_words, Palette, MEASURED_COLOR};

/// What the title line draws.
#[derive(Debug, Clone)]
pub struct TitleView<'a> {
    /// The scene's name (from its file: sanitized when drawn).
    pub name: &'a str,
    /// Something is unsaved: the scene or the model worked on (what q and o ask about).
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
            name: &app.edit.scene.name,
            // The scene's or the model's: what q and o ask about.
            dirty: app.unsaved(),
            fidelity: app.jobs.fidelity,
            live: app.jobs.live,
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

/// A model's figures as the status line shows them: `J`, and of the reaction, position and
/// angle errors those the scene's paths have.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FigureLine {
    /// The figures.
    pub figures: Figures,
    /// Which errors the paths have: force, position, angle ([`errors_shown`]).
    pub shown: [bool; 3],
    /// When the model could not follow every path: the figures are over the cases it
    /// followed.
    pub partial: Option<Partial>,
}

/// A model that stopped on some paths (DESIGN §6): how many, and the first one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Partial {
    /// How many paths it did not follow to their end.
    pub paths: usize,
    /// Of how many.
    pub of: usize,
    /// The first such path (from 1).
    pub path: usize,
    /// The fraction of it the model reached.
    pub fraction: f64,
}

impl Partial {
    /// The model's stops, `None` when it followed every path.
    pub fn of(unfollowed: &[UnfollowedPath], of: usize) -> Option<Partial> {
        unfollowed.first().map(|u| Partial {
            paths: unfollowed.len(),
            of,
            path: u.path,
            fraction: u.fraction,
        })
    }
}

/// Which errors a scene's paths have: force (some path prescribes a stage coordinate),
/// position (some path loads `x` or `y`), angle (some path loads `phi`). A cantilever's
/// one-flexure mechanism loads every coordinate: position and angle.
pub fn errors_shown(m: &Mechanism) -> [bool; 3] {
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

/// A data scene's line (DESIGN §9): the data file, its hash, and the scene's beam (or beam
/// mechanism) against the data.
#[derive(Debug, Clone)]
pub struct DataLine<'a> {
    /// The data file as the scene names it (sanitized when drawn).
    pub file: &'a str,
    /// The first characters of its SHA-256.
    pub sha256: &'a str,
    /// The beam's figures against the data, or why it has none; `None` until the worker
    /// has solved it.
    pub beam: Option<Result<FigureLine, Cow<'a, str>>>,
}

/// How many hex digits of a data file's SHA-256 the status line shows.
pub const HASH_PREFIX: usize = 8;

/// What the status line draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The last message (file paths and errors inside are sanitized when drawn).
    pub message: Option<(&'a str, Tone)>,
    /// The shown model's figures.
    pub figures: Option<FigureLine>,
    /// The model compared against: its name and figures on the same truth.
    pub compare: Option<(&'a str, FigureLine)>,
    /// A data scene's file and the beam against it.
    pub data: Option<DataLine<'a>>,
    /// The shown model's natural frequencies against the truth's (with `[beam] density`).
    pub modes: Option<&'a Frequencies>,
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
        let scene = &app.edit.scene;
        let truth = app.shown.truth();
        let shown = truth.map_or([false, true, true], |t| errors_shown(&t.mechanism));
        let line = |figures: Figures| FigureLine {
            figures,
            shown,
            partial: None,
        };
        let model_line = |m: &ModelView| FigureLine {
            partial: Partial::of(&m.unfollowed, m.cases.len()),
            ..line(m.figures)
        };
        let (w, w_f) = (scene.fit.angle_weight, scene.fit.force_weight);
        // The beam's cases beside the data are kept; judging them is arithmetic.
        let beam = truth
            .and_then(|t| t.beam_against_data(w, w_f))
            .map(|r| r.map(line).map_err(Cow::Borrowed));
        let data = scene.truth.as_ref().map(|t| DataLine {
            file: &t.file,
            sha256: t.sha256.get(..HASH_PREFIX).unwrap_or(&t.sha256),
            beam,
        });
        View {
            message: app.message.as_ref().map(|(m, t)| (m.as_str(), *t)),
            figures: app.shown.model().map(model_line),
            compare: app.shown.shown_compare().map(|(n, v)| (n, model_line(v))),
            data,
            modes: app.shown.model().and_then(|m| m.frequencies.as_ref()),
            accuracy: scene.accuracy,
            activity: &app.jobs.activity,
            pal: Palette { mono: app.mono },
        }
    }
}

/// How many lines [`draw`] takes: the figures, the compared model's (when comparing), the
/// data's (on a data scene), the frequencies (with a density), the message.
pub fn height(view: &View, width: u16) -> u16 {
    figure_lines(view) + message_lines(view, width)
}

/// The lines above the message: the figures and the activity, and the compared model's, the
/// data's and the frequencies' lines when shown.
fn figure_lines(view: &View) -> u16 {
    1 + u16::from(view.compare.is_some())
        + u16::from(view.data.is_some())
        + u16::from(view.modes.is_some())
}

/// The message wrapped to `width` (its end, usually the part saying why, is not cut at the
/// terminal's edge), at most [`MAX_MESSAGE_LINES`] lines.
fn message_text(view: &View, width: u16) -> Vec<String> {
    let Some((m, _)) = view.message else {
        return Vec::new();
    };
    let mut lines = wrap_words(&sanitize_terminal(m), usize::from(width.max(2)) - 1);
    lines.truncate(MAX_MESSAGE_LINES);
    lines
}

/// The message's lines at `width`; one (kept blank) without one.
fn message_lines(view: &View, width: u16) -> u16 {
    u16::try_from(message_text(view, width).len().max(1)).unwrap_or(1)
}

/// At most this many lines of message.
const MAX_MESSAGE_LINES: usize = 3;

/// `value` and `target` at `sig` significant digits, or more where the two would read the
/// same although they differ (`ang 1.15deg FAIL<1.15` for 1.1459 against 1.1459156): digits
/// are added until they read apart, up to ten.
fn against(value: f64, target: f64, sig: usize) -> (String, String) {
    let mut digits = sig;
    loop {
        let (v, t) = (trim_number(value, digits), trim_number(target, digits));
        if v != t || value == target || digits >= 10 {
            return (v, t);
        }
        digits += 1;
    }
}

/// `J | pos ..% PASS<.. | ang ..deg PASS<.. | ` for figures `f` against `acc`; a
/// mechanism's reaction error first, `force ..% FAIL<..`, and only the errors its drives
/// have.
fn figure_spans(f: FigureLine, acc: &Accuracy, pal: Palette) -> Vec<Span<'static>> {
    let verdict = |ok: bool| Span::styled(if ok { "PASS" } else { "FAIL" }, pal.pass(ok));
    let (shown, partial, f) = (f.shown, f.partial, f.figures);
    let (objective, pos, ang, force) = (f.objective, f.max_pos_err, f.max_ang_err, f.max_force());
    let mut spans = vec![Span::raw(format!(" J {objective:.3e} | "))];
    // Each figure against its target at three significant digits, or as many more as it
    // takes for the two not to read the same.
    let mut figure = |name: &str, value: f64, target: f64, scale: f64, unit: &str| {
        let (v, t) = against(value * scale, target * scale, 3);
        spans.push(Span::raw(format!("{name} {v}{unit} ")));
        spans.push(verdict(value <= target));
        spans.push(Span::raw(format!("<{t} | ")));
    };
    if shown[0] {
        figure("force", force, acc.max_force_err, 100.0, "%");
    }
    if shown[1] {
        figure("pos", pos, acc.max_pos_err, 100.0, "%L");
    }
    if shown[2] {
        figure(
            "ang",
            ang,
            acc.max_ang_err,
            180.0 / std::f64::consts::PI,
            "deg",
        );
    }
    if let Some(e) = f.max_freq_err {
        figure("freq", e, acc.max_freq_err, 100.0, "%");
    }
    if let Some(p) = partial {
        // The figures above are over the followed cases only: never a pass for the model.
        let more = if p.paths > 1 {
            format!(" (+{} more)", p.paths - 1)
        } else {
            String::new()
        };
        spans.push(Span::styled(
            format!(
                "PARTIAL {}/{} paths: path {} stops at {:.3}{more}",
                p.of - p.paths,
                p.of,
                p.path,
                p.fraction
            ),
            pal.pass(false),
        ));
        spans.push(Span::raw(" | "));
    }
    spans
}

/// Draws the status lines: the figures and the activity, the compared model's figures (when
/// comparing), then the message (if any).
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let mut spans = match view.figures {
        Some(f) => figure_spans(f, &view.accuracy, pal),
        None if matches!(view.activity, Activity::Failed(_)) => {
            vec![Span::raw(
                " no figures: the last edit's job failed (the message says why)  ",
            )]
        }
        None => vec![Span::raw(" no model judged yet  ")],
    };
    let activity = match view.activity {
        Activity::Idle => "idle".to_string(),
        Activity::Waiting => "working...".to_string(),
        Activity::Fitting(s) => format!(
            "fitting · {} it {} · {} evals · {:.0} ms",
            s.phase,
            s.iteration,
            s.evaluations,
            s.seconds * 1e3
        ),
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
    if let Some(m) = view.modes {
        lines.push(modes_line(m, &view.accuracy, pal));
    }
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Length(figure_lines(view)), Constraint::Min(1)])
        .split(area);
    frame.render_widget(Paragraph::new(lines), parts[0]);
    if let Some((_, tone)) = view.message {
        let style = match tone {
            Tone::Error => pal.fg(Color::Red),
            Tone::Info => Style::default(),
        };
        let message: Vec<Line> = message_text(view, area.width)
            .into_iter()
            .map(|l| Line::from(Span::styled(format!(" {l}"), style)))
            .collect();
        frame.render_widget(Paragraph::new(message), parts[1]);
    }
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
        Some(Ok(f)) => spans.extend(figure_spans(*f, acc, pal)),
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

/// ` modes Hz beam 164.3 1030 2883 · model 164.3 1030 2884 · -0.005% -0.002% +0.006% PASS<1`:
/// the first natural frequencies of the truth and the shown model about the unloaded
/// equilibrium (DESIGN §10), each model frequency's error, and against `max_freq_err` the
/// verdict on those the fit matches (`[fit] modes`; none judged: `not fitted`).
fn modes_line(m: &Frequencies, acc: &Accuracy, pal: Palette) -> Line<'static> {
    let hz = |v: &[f64]| {
        v.iter()
            .map(|x| trim_number(*x, 5))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let label = if m.nominal {
        " modes Hz (nominal beam: the data is not dynamic) beam "
    } else {
        " modes Hz beam "
    };
    let mut spans = vec![Span::raw(format!(
        "{label}{} · model {} ·",
        hz(&m.beam_hz),
        hz(&m.model_hz)
    ))];
    for (i, e) in m.freq_err.iter().enumerate() {
        let sign = if *e > 0.0 { "+" } else { "" };
        let text = format!(" {sign}{}%", trim_number(e * 100.0, 3));
        if i < m.judged {
            spans.push(Span::styled(text, pal.pass(e.abs() <= acc.max_freq_err)));
        } else {
            spans.push(Span::styled(text, pal.fg(Color::DarkGray)));
        }
    }
    if m.judged > 0 {
        let ok = m.max_err() <= acc.max_freq_err;
        spans.push(Span::raw(format!(" · first {} ", m.judged)));
        spans.push(Span::styled(if ok { "PASS" } else { "FAIL" }, pal.pass(ok)));
        spans.push(Span::raw(format!(
            "<{}%",
            trim_number(acc.max_freq_err * 100.0, 3)
        )));
    } else {
        spans.push(Span::styled(
            " · not fitted ([fit] modes = 0)",
            pal.fg(Color::DarkGray),
        ));
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
        let text = if app.edit.editing.is_some() {
            keymap::EDITING_HINT.to_string()
        } else if let Some((kind, _)) = &app.prompt {
            if kind.is_question() {
                keymap::QUESTION_HINT.to_string()
            } else {
                keymap::PROMPT_HINT.to_string()
            }
        } else {
            keymap::hint_line(app.edit.focus, app.edit.is_data())
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

#[cfg(test)]
mod tests {
    use crate::tui::ui::status::against;

    #[test]
    fn a_figure_and_its_target_never_read_the_same_unless_equal() {
        // 1.999e-2 rad against 0.02 rad, in degrees: "1.15" and "1.15" at three digits.
        let deg = 180.0 / std::f64::consts::PI;
        let (v, t) = against(1.999e-2 * deg, 0.02 * deg, 3);
        assert_ne!(v, t);
        assert_eq!((v.as_str(), t.as_str()), ("1.145", "1.146"));
        assert_eq!(against(0.5, 1.0, 3), ("0.5".into(), "1".into()));
        assert_eq!(against(2.0, 2.0, 3), ("2".into(), "2".into()));
    }
}
