//! The load-path panel: one row per path (its end load and step count); the selected row is
//! also the path the shape chart draws.

use crate::scene::{LoadPath, Scene, MAX_STEPS};

use super::super::units::{parse_quantity, trim_number, Quantity};
use super::step;

/// The load table's columns.
pub const LOAD_COLUMNS: [&str; 4] = ["alpha_x", "alpha_y", "beta", "steps"];

/// The load panel's cursor.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LoadsState {
    /// The selected path (and the one the shape chart shows).
    pub row: usize,
    /// The selected column, an index into [`LOAD_COLUMNS`].
    pub col: usize,
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

/// The text of a cell.
pub fn load_text(path: &LoadPath, col: usize) -> String {
    match col {
        0 => trim_number(path.end.alpha_x, 6),
        1 => trim_number(path.end.alpha_y, 6),
        2 => trim_number(path.end.beta, 6),
        _ => path.steps.to_string(),
    }
}

/// `path` with column `col` set from `text`; an error (and nothing changed) if invalid.
pub fn edited(path: &LoadPath, col: usize, text: &str) -> Result<LoadPath, String> {
    let mut path = *path;
    if col == 3 {
        let steps: i64 = text
            .trim()
            .parse()
            .map_err(|_| format!("steps: `{}` is not a whole number", text.trim()))?;
        if !(1..=MAX_STEPS).contains(&steps) {
            return Err(format!("steps must be 1 to {MAX_STEPS}"));
        }
        path.steps = steps as u32;
    } else {
        let v = parse_quantity(text, Quantity::Plain)
            .map_err(|e| format!("{}: {e}", LOAD_COLUMNS[col.min(2)]))?;
        match col {
            0 => path.end.alpha_x = v,
            1 => path.end.alpha_y = v,
            _ => path.end.beta = v,
        }
        if path.end.magnitude() == 0.0 {
            return Err("a load path cannot be all zero".into());
        }
    }
    Ok(path)
}
