//! The load-path panel: one row per path (its end load and step count); the selected row is
//! also the path the shape chart draws.
//!
//! Loads are nondimensional in the scene (`alpha = F L^2 / (E I0)`, `beta = M L / (E I0)`,
//! DESIGN §1), so a beam edit holding alpha changes the force: a blade 4x thicker takes 64x
//! the force for the same alpha. The panel shows them in SI too (N, N m, for the beam as it
//! is now), and [`Hold`] says which stays when the beam changes: with `Force`, a beam edit
//! rescales the alphas so that Fx, Fy and Mz stay ([`held_forces`]).

use crate::beam::Load;
use crate::scene::{rules, BeamSpec, LoadPath, Scene};
use crate::si::load_factors;

use super::super::units::{parse_quantity, trim_number, Quantity};
use super::step;

/// The load table's columns.
pub const LOAD_COLUMNS: [&str; 4] = ["alpha_x", "alpha_y", "beta", "steps"];
/// The load table's columns in SI.
pub const LOAD_COLUMNS_SI: [&str; 4] = ["Fx N", "Fy N", "Mz N m", "steps"];

/// What stays when the beam changes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Hold {
    /// The nondimensional loads (the scene file's numbers): the forces follow the beam.
    #[default]
    Alpha,
    /// The forces and moments in N and N m: the alphas follow the beam.
    Force,
}

impl std::fmt::Display for Hold {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Hold::Alpha => "alpha",
            Hold::Force => "force",
        })
    }
}

/// The load panel's cursor and what a beam edit holds.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LoadsState {
    /// The selected path (and the one the shape chart shows).
    pub row: usize,
    /// The selected column, an index into [`LOAD_COLUMNS`].
    pub col: usize,
    /// What a beam edit keeps.
    pub hold: Hold,
}

/// The loads of `old`'s beam with the same forces (N) and moments (N m) on `new`'s beam:
/// every alpha times `(E I0 / L^2)_old / (E I0 / L^2)_new`, every beta likewise with
/// `E I0 / L`.
pub fn held_forces(loads: &[LoadPath], old: &BeamSpec, new: &BeamSpec) -> Vec<LoadPath> {
    let (f0, m0) = load_factors(old);
    let (f1, m1) = load_factors(new);
    loads
        .iter()
        .map(|p| LoadPath {
            end: Load::new(
                p.end.alpha_x * f0 / f1,
                p.end.alpha_y * f0 / f1,
                p.end.beta * m0 / m1,
            ),
            ..*p
        })
        .collect()
}

/// A load in SI for `beam`, as the panel writes it: `Fx 0 N  Fy 2.083 N  Mz 0 N m`.
pub fn si_text(path: &LoadPath, beam: &BeamSpec) -> String {
    let (f, m) = load_factors(beam);
    format!(
        "Fx {} N  Fy {} N  Mz {} N m",
        trim_number(path.end.alpha_x * f, 4),
        trim_number(path.end.alpha_y * f, 4),
        trim_number(path.end.beta * m, 4)
    )
}

/// The nondimensional load of the same end load, as the panel writes it.
pub fn alpha_text(path: &LoadPath) -> String {
    format!(
        "alpha_x {}  alpha_y {}  beta {}",
        trim_number(path.end.alpha_x, 4),
        trim_number(path.end.alpha_y, 4),
        trim_number(path.end.beta, 4)
    )
}

/// The SI value of one nondimensional unit of a load column for `beam` (1 for `steps`).
fn column_factor(beam: &BeamSpec, col: usize) -> f64 {
    let (f, m) = load_factors(beam);
    match col {
        0 | 1 => f,
        2 => m,
        _ => 1.0,
    }
}

impl LoadsState {
    /// Moves the cursor; `paths` is how many rows there are.
    pub fn move_by(&mut self, dx: i32, dy: i32, paths: usize) {
        self.row = step(self.row, dy, paths);
        self.col = step(self.col, dx, LOAD_COLUMNS.len());
    }

    /// `[` and `]`: the previous or next path, wrapping around.
    pub fn cycle_path(&mut self, delta: i32, paths: usize) {
        let n = paths.max(1) as i64;
        self.row = (self.row as i64 + delta as i64).rem_euclid(n) as usize;
    }

    /// The path the shape chart draws.
    pub fn shown_path(&self, paths: usize) -> usize {
        self.row.min(paths.saturating_sub(1))
    }

    /// Inserts a copy of the selected path after it and selects the copy.
    pub fn add(&mut self, scene: &mut Scene) {
        let i = self.shown_path(scene.loads.len());
        if let Some(&copy) = scene.loads.get(i) {
            scene.loads.insert(i + 1, copy);
            self.row = i + 1;
        }
    }

    /// Deletes the selected path; a scene keeps at least one.
    pub fn delete(&mut self, scene: &mut Scene) -> Result<(), String> {
        if scene.loads.len() <= 1 {
            return Err("a scene needs at least one load path".into());
        }
        scene.loads.remove(self.shown_path(scene.loads.len()));
        self.row = self.row.min(scene.loads.len() - 1);
        Ok(())
    }
}

/// The text of a cell: nondimensional, or in SI for `si`'s beam.
pub fn load_text(path: &LoadPath, col: usize, si: Option<&BeamSpec>) -> String {
    let k = si.map_or(1.0, |b| column_factor(b, col));
    let digits = if si.is_some() { 5 } else { 6 };
    match col {
        0 => trim_number(path.end.alpha_x * k, digits),
        1 => trim_number(path.end.alpha_y * k, digits),
        2 => trim_number(path.end.beta * k, digits),
        _ => path.steps.to_string(),
    }
}

/// `path` with column `col` set from `text` (in SI for `si`'s beam when given); an error (and
/// nothing changed) if the text is not a value of the column's kind or the path breaks the
/// scene's rules for a path ([`LoadPath::validate`], the rules the scene file's reader
/// applies; a step count by [`rules::steps`]), said as `key: message` with the path's own
/// keys (`steps: ...`).
pub fn edited(
    path: &LoadPath,
    col: usize,
    text: &str,
    si: Option<&BeamSpec>,
) -> Result<LoadPath, String> {
    let mut path = *path;
    if col == 3 {
        let steps: i64 = text
            .trim()
            .parse()
            .map_err(|_| format!("steps: `{}` is not a whole number", text.trim()))?;
        path.steps = rules::steps(steps).map_err(|m| format!("steps: {m}"))?;
    } else {
        let v = parse_quantity(text, Quantity::Plain)
            .map_err(|e| format!("{}: {e}", LOAD_COLUMNS[col.min(2)]))?
            / si.map_or(1.0, |b| column_factor(b, col));
        match col {
            0 => path.end.alpha_x = v,
            1 => path.end.alpha_y = v,
            _ => path.end.beta = v,
        }
    }
    path.validate().map_err(|e| e.to_string())?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// A load-path edit meets the scene file's rules and says what the reader says of that
    /// file (the path's own key, without the file's line and `loads[3]`): a path edited to
    /// all zero, a step count by the file's step rule.
    #[test]
    fn edits_are_refused_with_the_readers_words() {
        let scene = Scene::builtin();
        // Path 3 is a pure moment: beta to zero leaves nothing.
        let mut bad = scene.clone();
        bad.loads[2].end.beta = 0.0;
        let file = Scene::from_toml_str(&bad.to_toml(), "s.toml").unwrap_err();
        assert!(file.line.is_some(), "{file}");
        assert_eq!(file.key.as_deref(), Some("loads[3]"));
        assert_eq!(edited(&scene.loads[2], 2, "0", None), Err(file.message));
        bad.loads[2].end.beta = 2.0;
        bad.loads[2].steps = 0;
        let file = Scene::from_toml_str(&bad.to_toml(), "s.toml").unwrap_err();
        assert_eq!(file.key.as_deref(), Some("loads[3].steps"));
        let ui = edited(&scene.loads[2], 3, "0", None).unwrap_err();
        assert_eq!(ui, format!("steps: {}", file.message));
        assert_eq!(
            edited(&scene.loads[2], 3, "-3", None).unwrap_err(),
            "steps: must be a whole number from 1 to 10000, got -3"
        );
        assert_eq!(edited(&scene.loads[2], 3, "7", None).unwrap().steps, 7);
    }
}
