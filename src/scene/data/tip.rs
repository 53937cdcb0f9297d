//! A cantilever's data file (DESIGN §9): load columns `fx, fy, mz` (N, N m) or
//! `alpha_x, alpha_y, beta`, the measured tip `x, y, theta` (m, rad) or `a, b, phi` (units of
//! L, rad), one unit system throughout, converted to nondimensional with the scene's nominal
//! beam; a path's load magnitude grows from row to row.

use serde::Serialize;

use crate::beam::{Load, TipPose};

use super::super::beam::BeamSpec;
use super::super::error::SceneError;
use super::csv::{Csv, RowPaths};

/// One measured load case.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasuredRow {
    /// The file's 1-based line.
    pub line: usize,
    /// The load, nondimensional (the scene's nominal beam).
    pub load: Load,
    /// The measured tip, nondimensional (units of the nominal `L`, radians).
    pub tip: TipPose,
}

/// One measured path: its rows in order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredPath {
    /// The `path` column's value (1 when the file has no such column).
    pub id: i64,
    /// The rows, in the file's order.
    pub rows: Vec<MeasuredRow>,
}

/// The unit system of a data file's load and tip columns.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// `fx, fy, mz` (N, N m), `x, y` (m) and `theta`: converted with the scene's nominal beam.
    Si,
    /// `alpha_x, alpha_y, beta`, `a, b` (units of L) and `phi`: the same on any beam.
    #[default]
    Nondimensional,
}

/// What one newton, one newton metre and one metre are, nondimensional, on `beam`:
/// `L^2 / (E I0)`, `L / (E I0)` and `1 / L` (DESIGN §1).
pub(super) fn nominal_scales(beam: &BeamSpec) -> (f64, f64, f64) {
    let ei = beam.youngs_modulus * beam.second_moment();
    let l = beam.length;
    (l * l / ei, l / ei, 1.0 / l)
}

/// What a column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Column {
    Path,
    /// Load component 0..3, in its units.
    Load(usize, Units),
    /// Tip component 0..3 (x or a, y or b, theta or phi), in its units.
    Tip(usize, Units),
}

pub(super) fn column_of(name: &str) -> Option<Column> {
    use Units::{Nondimensional as N, Si};
    Some(match name {
        "path" => Column::Path,
        "fx" => Column::Load(0, Si),
        "fy" => Column::Load(1, Si),
        "mz" => Column::Load(2, Si),
        "alpha_x" => Column::Load(0, N),
        "alpha_y" => Column::Load(1, N),
        "beta" => Column::Load(2, N),
        "x" => Column::Tip(0, Si),
        "y" => Column::Tip(1, Si),
        "theta" => Column::Tip(2, Si),
        "a" => Column::Tip(0, N),
        "b" => Column::Tip(1, N),
        "phi" => Column::Tip(2, N),
        _ => return None,
    })
}

const KNOWN: &str = "path, fx, fy, mz, alpha_x, alpha_y, beta, x, y, theta, a, b, phi (DESIGN §9)";

/// Reads the CSV `text` (from the file `origin`) with `beam` as the nominal beam: its paths,
/// and the unit system its columns are in.
pub fn parse_csv(
    text: &str,
    origin: &str,
    beam: &BeamSpec,
) -> Result<(Vec<MeasuredPath>, Units), SceneError> {
    let csv = Csv { origin };
    let (header_line, header, rows) = csv.split(text, KNOWN)?;
    let (columns, names) = csv.columns(header_line, &header, |name| {
        column_of(name).ok_or_else(|| format!("unknown column; the columns are {KNOWN}"))
    })?;
    // One unit system for loads and tips, every component present.
    let units: Vec<(usize, Units)> = columns
        .iter()
        .enumerate()
        .filter_map(|(i, c)| match c {
            Column::Load(_, u) | Column::Tip(_, u) => Some((i, *u)),
            Column::Path => None,
        })
        .collect();
    if let (Some(&(_, first)), Some(&(i, _))) =
        (units.first(), units.iter().find(|(_, u)| *u != units[0].1))
    {
        let (si, nd) = if first == Units::Si {
            (names[units[0].0], names[i])
        } else {
            (names[i], names[units[0].0])
        };
        return Err(csv.fail(
            header_line,
            header[i].0,
            Some(names[i]),
            format!(
                "mixed units: `{si}` is SI and `{nd}` nondimensional; use fx, fy, mz, x, y, \
                 theta or alpha_x, alpha_y, beta, a, b, phi throughout"
            ),
        ));
    }
    let si = units.first().is_none_or(|(_, u)| *u == Units::Si);
    let wanted: [(&str, Column); 6] = if si {
        [
            ("fx", Column::Load(0, Units::Si)),
            ("fy", Column::Load(1, Units::Si)),
            ("mz", Column::Load(2, Units::Si)),
            ("x", Column::Tip(0, Units::Si)),
            ("y", Column::Tip(1, Units::Si)),
            ("theta", Column::Tip(2, Units::Si)),
        ]
    } else {
        [
            ("alpha_x", Column::Load(0, Units::Nondimensional)),
            ("alpha_y", Column::Load(1, Units::Nondimensional)),
            ("beta", Column::Load(2, Units::Nondimensional)),
            ("a", Column::Tip(0, Units::Nondimensional)),
            ("b", Column::Tip(1, Units::Nondimensional)),
            ("phi", Column::Tip(2, Units::Nondimensional)),
        ]
    };
    if let Some((name, _)) = wanted.iter().find(|(_, c)| !columns.contains(c)) {
        return Err(csv.fail(
            header_line,
            1,
            None,
            format!(
                "missing column `{name}`: a data file needs every load and tip column of one \
                 unit system ({})",
                wanted.map(|w| w.0).join(", ")
            ),
        ));
    }
    // Nominal scales: SI to nondimensional.
    let (force, moment, length) = if si {
        nominal_scales(beam)
    } else {
        (1.0, 1.0, 1.0)
    };
    let path_column = columns.iter().position(|c| *c == Column::Path);
    let mut paths: RowPaths<MeasuredRow> = RowPaths::default();
    for (line_no, line) in rows {
        let (f, at) = csv.row(line_no, line, &names, path_column)?;
        let mut load = [0.0; 3];
        let mut tip = [0.0; 3];
        for (k, (c, &v)) in columns.iter().zip(&f.values).enumerate() {
            let scaled = |factor| csv.scaled(line_no, at[k], names[k], v, factor);
            match *c {
                Column::Load(i, _) => load[i] = scaled(if i == 2 { moment } else { force })?,
                Column::Tip(i, _) => tip[i] = scaled(if i == 2 { 1.0 } else { length })?,
                Column::Path => {}
            }
        }
        let row = MeasuredRow {
            line: line_no,
            load: Load {
                alpha_x: load[0],
                alpha_y: load[1],
                beta: load[2],
            },
            tip: TipPose {
                a: tip[0],
                b: tip[1],
                phi: tip[2],
            },
        };
        csv.push(
            &mut paths,
            f.id,
            row,
            line_no,
            "load magnitude",
            |r| r.load.magnitude(),
            |r| r.line,
        )?;
    }
    csv.nonempty(header_line, &paths.paths)?;
    let units = if si { Units::Si } else { Units::Nondimensional };
    Ok((
        paths
            .paths
            .into_iter()
            .map(|(id, rows)| MeasuredPath { id, rows })
            .collect(),
        units,
    ))
}
