//! A data scene in the editor (DESIGN §9): its loads are its file's rows, shown read-only
//! (the load panel's cursor moves over the rows, and the charts follow the path of the row
//! it is on); a beam edit converts SI rows again with the new nominal beam, as reading the
//! file with that beam would ([`Scene::rebased`]). A mechanism data scene's drives are its
//! file's measured paths, read-only the same way (its flexures, stage and beam stay
//! editable: the rows are SI, so an edit changes nothing physical in them). Plain functions
//! of the scene: what [`Editing`](super::edit::Editing) asks of it.

use crate::scene::data::Units;
use crate::scene::Scene;

/// Whether the scene's truth is measured data.
pub fn is_data(scene: &Scene) -> bool {
    scene.truth.is_some()
}

/// The rows the load panel lists: a data scene's rows, else its load paths.
pub fn load_rows(scene: &Scene) -> usize {
    match &scene.truth {
        Some(t) => t.row_count(),
        None => scene.loads.len(),
    }
}

/// A data scene's path (0-based) holding row `row` (0-based over all paths); `row` itself
/// on any other scene.
pub fn path_of_row(scene: &Scene, row: usize) -> usize {
    let Some(t) = &scene.truth else {
        return row;
    };
    let mut start = 0;
    for (i, p) in t.paths.iter().enumerate() {
        start += p.rows.len();
        if row < start {
            return i;
        }
    }
    t.paths.len().saturating_sub(1)
}

/// `[` and `]` on a data scene: the first row of the path `delta` from row `row`'s,
/// wrapping around.
pub fn cycled_path_row(scene: &Scene, row: usize, delta: i32) -> usize {
    let Some(t) = &scene.truth else {
        return row;
    };
    let n = t.paths.len().max(1) as i64;
    let path = (path_of_row(scene, row) as i64 + delta as i64).rem_euclid(n) as usize;
    t.paths[..path].iter().map(|p| p.rows.len()).sum()
}

/// The data file's name ("" when the scene has none).
fn file(scene: &Scene) -> &str {
    scene.truth.as_ref().map_or("", |t| t.file.as_str())
}

/// Why a data scene's loads (a cell, a row added or deleted) cannot be edited.
pub fn loads_read_only(scene: &Scene) -> String {
    format!(
        "read-only: a data scene's loads are the rows of {} (DESIGN §9); edit the file and \
         open the scene again",
        file(scene)
    )
}

/// Why a mechanism data scene's drives (a coordinate, its steps, `p` on one, a drive added
/// or deleted) cannot be edited.
pub fn drives_read_only(scene: &Scene) -> String {
    format!(
        "read-only: a mechanism data scene's drives are the rows of {} (DESIGN §9); edit \
         the file and open the scene again",
        file(scene)
    )
}

/// `H` on a data scene: what a beam edit keeps, as the rows' units decide.
pub fn hold_message(scene: &Scene) -> Option<&'static str> {
    Some(match scene.truth.as_ref()?.units {
        Units::Si => {
            "hold: a data scene keeps its rows' N, N m and m; a beam edit converts them again \
             (the alphas follow the beam)"
        }
        Units::Nondimensional => {
            "hold: a data scene keeps its rows' alpha, beta, a, b (nondimensional in the \
             file): a beam edit leaves them"
        }
    })
}
