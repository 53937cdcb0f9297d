//! Drawing: one file per panel, each with one `draw(frame, area, &View)` that renders from a
//! small view, a plain snapshot built from the [`App`] (oxker's `FrameData`), so every panel
//! can be snapshot-tested on its own. The charts have one renderer each for every kind of
//! scene, drawing the worker's one truth view and one model view; where the kinds read
//! differently (a cantilever's tips, a mechanism's stage: [`CaseForm`]) the view says how.
//!
//! Layout: a title line; the beam, load and matrix panels on the left; on the right the
//! deformed shapes ([`shapes`]: beam and PRB linkage, equal aspect) over the error charts
//! ([`errors`]); a status line with the fit's figures against the scene's targets, a message
//! line; a key-hint line. Below [`MIN_WIDTH`] x [`MIN_HEIGHT`] only a "too small" note is
//! drawn.
//!
//! A mechanism scene (DESIGN §8) has the mechanism panel in place of the load paths, and on
//! the right its shapes over its force–stroke chart ([`strokes`]) and its error chart. A data
//! scene (DESIGN §9) has its file's rows in place of the load paths ([`rows`]), the measured
//! points as markers over the shapes, the errors against the data marked at every row with
//! the beam's own beside them, and a status line naming the data; a mechanism data scene
//! marks the measured reactions or motions on its force–stroke chart too.
//!
//! Text that came from outside (a scene's name, file paths, error messages) is drawn through
//! [`sanitize_terminal`](crate::text::sanitize_terminal), so a file cannot send escape
//! sequences to the terminal. `parts.rs` holds what every panel draws with.

pub mod beam;
pub mod errors;
pub mod loads;
pub mod matrix;
pub mod mech;
pub mod overlays;
mod parts;
pub mod rows;
pub mod select;
pub mod shapes;
pub mod status;
pub mod strokes;

use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::Frame;

use crate::study::CaseForm;

use super::app::App;
use super::state::beam::BeamField;

pub use parts::{
    equal_aspect_bounds, Palette, MEASURED_COLOR, MEASURED_MARKER, MIN_HEIGHT, MIN_WIDTH,
};

/// Whether a terminal of `width` x `height` is below the UI's minimum (only the "too small"
/// note is drawn).
pub fn too_small(width: u16, height: u16) -> bool {
    width < MIN_WIDTH || height < MIN_HEIGHT
}

/// Draws the whole screen.
pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    if too_small(area.width, area.height) {
        // The question asked (quit with unsaved work, overwrite) stays visible.
        let question = app
            .prompt
            .as_ref()
            .filter(|(k, _)| k.is_question())
            .map(|(k, _)| k.question());
        overlays::draw_too_small(frame, area, question);
        return;
    }
    let status_view = status::View::new(app);
    let rows = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Length(1),
            Constraint::Min(10),
            Constraint::Length(status::height(&status_view, area.width)),
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
    overlays::draw(frame, area, &overlays::View::new(app));
}

fn draw_left(frame: &mut Frame, area: Rect, app: &App) {
    // The matrix first (all its rows if it can), then at least four lines of loads; the beam
    // panel takes the rest and scrolls to its selected field when short.
    let mechanism = app.edit.is_mechanism();
    let matrix_height =
        (app.edit.matrix.len() as u16 + 3).clamp(4, area.height.saturating_sub(9).max(4));
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
    } else if app.edit.is_data() {
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
    shapes::draw(frame, parts[0], &shapes::View::new(app));
    match app.edit.case_form() {
        // A cantilever: its tip's position and angle errors.
        CaseForm::Tip => {
            let position = Some(errors::ErrorKind::Position);
            errors::draw(frame, charts[0], &errors::View::new(app, position));
            let angle = Some(errors::ErrorKind::Angle);
            errors::draw(frame, charts[1], &errors::View::new(app, angle));
        }
        // A mechanism: its force–stroke chart and its main error.
        CaseForm::Stage => {
            strokes::draw(frame, charts[0], &strokes::View::new(app));
            errors::draw(frame, charts[1], &errors::View::new(app, None));
        }
    }
}
