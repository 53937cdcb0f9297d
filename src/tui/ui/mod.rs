//! Drawing: one file per panel, each with one `draw(frame, area, &View)` that renders from a
//! small view built from the [`App`] (oxker's `FrameData`), so every panel can be
//! snapshot-tested on its own.
//!
//! Layout: a title line; the beam, load and matrix panels on the left; on the right the
//! deformed shapes (beam and PRB linkage, equal aspect) over the tip-error charts; a status
//! line with the fit's figures against the scene's targets, a message line; a key-hint line. Below
//! [`MIN_WIDTH`] x [`MIN_HEIGHT`] only a "too small" note is drawn.
//!
//! A mechanism scene (DESIGN §8) has the mechanism panel in place of the load paths, and on
//! the right the mechanism's shapes over its force–stroke chart and its error chart. A data
//! scene (DESIGN §9) has its file's rows in place of the load paths, the measured tips as
//! markers over the shapes, the errors against the data with the beam's own beside them,
//! and a status line naming the data; a mechanism data scene marks the measured reactions or
//! motions on its force–stroke chart and the measured stage point on its shape chart, with
//! the beam mechanism along the measured drives beside them.
//!
//! Text that came from outside (a scene's name, file paths, error messages) is drawn through
//! [`sanitize_terminal`], so a file cannot send escape sequences to the terminal.

pub mod beam;
pub mod errors;
pub mod loads;
pub mod matrix;
pub mod mech;
pub mod mech_errors;
pub mod mech_shapes;
pub mod overlays;
pub mod rows;
pub mod select;
pub mod shapes;
pub mod status;
pub mod strokes;

use std::borrow::Cow;

use crate::text::sanitize_terminal;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::{Block, Borders};
use ratatui::Frame;

use super::app::App;
use super::state::beam::BeamField;

/// Narrower than this, only the "too small" note is drawn.
pub const MIN_WIDTH: u16 = 60;
/// Lower than this, only the "too small" note is drawn.
pub const MIN_HEIGHT: u16 = 20;

/// Colours, or none at all under NO_COLOR.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Palette {
    /// No colour at all.
    pub mono: bool,
}

impl Palette {
    fn fg(&self, c: Color) -> Style {
        if self.mono {
            Style::default()
        } else {
            Style::default().fg(c)
        }
    }
    fn color(&self, c: Color) -> Color {
        if self.mono {
            Color::Reset
        } else {
            c
        }
    }
    fn focus(&self, focused: bool) -> Style {
        if focused {
            self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
        } else {
            Style::default()
        }
    }
    fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    fn pass(&self, ok: bool) -> Style {
        self.fg(if ok { Color::Green } else { Color::Red })
            .add_modifier(Modifier::BOLD)
    }
}

/// The colour of measured data (DESIGN §9): the markers, the data line.
pub const MEASURED_COLOR: Color = Color::Magenta;

/// Path colours for the error charts.
const PATH_COLORS: [Color; 6] = [
    Color::Yellow,
    Color::Cyan,
    Color::Magenta,
    Color::Green,
    Color::Blue,
    Color::Red,
];

/// Draws the whole screen.
pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        overlays::draw_too_small(frame, area);
        return;
    }
    let status_view = status::View::new(app);
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(1),
            Constraint::Min(10),
            Constraint::Length(status::height(&status_view)),
            Constraint::Length(1),
        ])
        .split(area);
    status::draw_title(frame, rows[0], &status::TitleView::new(app));
    let left_width = if area.width >= 110 { 46 } else { 38 };
    let cols = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Length(left_width), Constraint::Min(20)])
        .split(rows[1]);
    draw_left(frame, cols[0], app);
    draw_right(frame, cols[1], app);
    status::draw(frame, rows[2], &status_view);
    status::draw_hints(frame, rows[3], &status::HintsView::new(app));
    if let Some(view) = select::View::new(app) {
        select::draw(frame, rows[1], &view);
    }
    if let Some(view) = select::View::mechanism(app) {
        select::draw(frame, rows[1], &view);
    }
    overlays::draw(frame, area, &overlays::View::new(app));
}

fn draw_left(frame: &mut Frame, area: Rect, app: &App) {
    // The matrix first (all its rows if it can), then at least four lines of loads; the beam
    // panel takes the rest and scrolls to its selected field when short.
    let mechanism = app.is_mechanism();
    let matrix_height =
        (app.matrix.len() as u16 + 3).clamp(4, area.height.saturating_sub(9).max(4));
    let rest = area.height.saturating_sub(matrix_height);
    // A mechanism's panel needs room too: the beam panel takes at most half of what is left.
    let beam_room = if mechanism {
        rest / 2
    } else {
        rest.saturating_sub(4)
    };
    let beam_height = (BeamField::of(mechanism).len() as u16 + 2).min(beam_room.max(3));
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(beam_height),
            Constraint::Min(4),
            Constraint::Length(matrix_height),
        ])
        .split(area);
    beam::draw(frame, parts[0], &beam::View::new(app));
    if mechanism {
        mech::draw(frame, parts[1], &mech::View::new(app));
    } else if app.is_data() {
        rows::draw(frame, parts[1], &rows::View::new(app));
    } else {
        loads::draw(frame, parts[1], &loads::View::new(app));
    }
    matrix::draw(frame, parts[2], &matrix::View::new(app));
}

fn draw_right(frame: &mut Frame, area: Rect, app: &App) {
    let parts = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Percentage(58), Constraint::Percentage(42)])
        .split(area);
    let charts = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Percentage(50), Constraint::Percentage(50)])
        .split(parts[1]);
    if app.is_mechanism() {
        mech_shapes::draw(frame, parts[0], &mech_shapes::View::new(app));
        strokes::draw(frame, charts[0], &strokes::View::new(app));
        mech_errors::draw(frame, charts[1], &mech_errors::View::new(app));
        return;
    }
    shapes::draw(frame, parts[0], &shapes::View::new(app));
    errors::draw(
        frame,
        charts[0],
        &errors::View::new(app, errors::ErrorKind::Position),
    );
    errors::draw(
        frame,
        charts[1],
        &errors::View::new(app, errors::ErrorKind::Angle),
    );
}

/// A panel's bordered block, highlighted when it has the focus.
fn panel_block<'a>(title: impl Into<Cow<'a, str>>, focused: bool, pal: Palette) -> Block<'a> {
    let title: Cow<'a, str> = title.into();
    Block::default()
        .borders(Borders::ALL)
        .border_style(pal.focus(focused))
        .title(Span::styled(title, pal.focus(focused)))
}

/// The text of a field, or its editor (with a cursor) when being edited.
fn shown(app: &App, target: &super::app::EditTarget, text: String) -> (String, bool) {
    match &app.editing {
        Some((t, tb)) if t == target => (tb.with_cursor(), true),
        _ => (text, false),
    }
}

/// A rectangle of at most `width` x `height` in the middle of `area`.
fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let w = width.min(area.width);
    let h = height.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

/// Equal-aspect bounds for a braille canvas of `area` (2 x 4 dots per cell) holding `pts`.
pub fn equal_aspect_bounds(pts: &[(f64, f64)], area: Rect) -> ([f64; 2], [f64; 2]) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, 1.0_f64, -0.1_f64, 0.1_f64);
    for &(x, y) in pts.iter().filter(|p| p.0.is_finite() && p.1.is_finite()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let pad = 0.05 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    // World units per dot, made equal along both axes.
    let dots_x = (area.width.saturating_sub(2).max(1) as f64) * 2.0;
    let dots_y = (area.height.saturating_sub(2).max(1) as f64) * 4.0;
    let per_dot = ((x1 - x0) / dots_x).max((y1 - y0) / dots_y);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hx, hy) = (per_dot * dots_x / 2.0, per_dot * dots_y / 2.0);
    ([cx - hx, cx + hx], [cy - hy, cy + hy])
}
