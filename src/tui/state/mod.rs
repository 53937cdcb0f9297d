//! The state of each panel, on its own: its cursor and how it turns typed text into a new
//! value (bottom's per-widget state). A panel never touches another panel's state; the
//! [`App`](super::app::App) holds what they share (scene, matrix, jobs, messages) and
//! dispatches keys to the focused one.
//!
//! - [`beam`]: the beam's fields and the scene's targets;
//! - [`loads`]: the load-path table;
//! - [`matrix`]: the PRB matrix table (nondimensional or SI), gamma rebalancing;
//! - [`mech`]: a mechanism scene's flexures, stage and drives, in place of the load paths
//!   (`mech_text.rs`: how its values are shown and typed);
//! - [`select`]: the model-selection view;
//! - [`text`]: the text box of the editors and prompts (cursor, readline keys).

pub mod beam;
pub mod loads;
pub mod matrix;
pub mod mech;
mod mech_text;
pub mod select;
pub mod text;

/// The panels that take the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Panel {
    /// The beam and the scene's targets.
    Beam,
    /// The load paths.
    Loads,
    /// The PRB matrix.
    Matrix,
    /// A mechanism scene's flexures, stage and drives (in place of the load paths).
    Mechanism,
}

impl Panel {
    /// The panel in the middle of the left column: the load paths, or on a mechanism scene
    /// the mechanism.
    pub fn middle(mechanism: bool) -> Panel {
        if mechanism {
            Panel::Mechanism
        } else {
            Panel::Loads
        }
    }

    /// The panel Tab moves to (on a mechanism scene when `mechanism`).
    pub fn next(self, mechanism: bool) -> Panel {
        match self {
            Panel::Beam => Panel::middle(mechanism),
            Panel::Loads | Panel::Mechanism => Panel::Matrix,
            Panel::Matrix => Panel::Beam,
        }
    }

    /// The panel Shift-Tab moves to (on a mechanism scene when `mechanism`).
    pub fn prev(self, mechanism: bool) -> Panel {
        match self {
            Panel::Beam => Panel::Matrix,
            Panel::Loads | Panel::Mechanism => Panel::Beam,
            Panel::Matrix => Panel::middle(mechanism),
        }
    }

    /// The panel to focus on a scene of the other kind: the middle panel changes with it.
    pub fn on_scene(self, mechanism: bool) -> Panel {
        match self {
            Panel::Loads | Panel::Mechanism => Panel::middle(mechanism),
            p => p,
        }
    }
}

/// Moves a cursor `v` by `d` inside `0..n` (clamped; 0 when empty).
pub fn step(v: usize, d: i32, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (v as i64 + d as i64).clamp(0, n as i64 - 1) as usize
    }
}
