//! The state of each panel, on its own: its cursor and how it turns typed text into a new
//! value (bottom's per-widget state). A panel never touches another panel's state; the app's
//! [`Editing`](super::app::Editing) holds them with what they edit (the scene, the matrix),
//! and the app dispatches keys to the focused one.
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

pub use super::panel::Panel;

use crate::scene::Scene;

/// Checks an edited scene, of any kind, by the rules its file obeys
/// ([`Scene::check_rules`], the reader's rules), as a panel shows a broken one:
/// `key: message`.
pub fn checked(scene: &Scene) -> Result<(), String> {
    scene.check_rules().map_err(|e| e.to_string())
}

/// Moves a cursor `v` by `d` inside `0..n` (clamped; 0 when empty).
pub fn step(v: usize, d: i32, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (v as i64 + d as i64).clamp(0, n as i64 - 1) as usize
    }
}
