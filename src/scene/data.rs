//! Measured data as the truth (DESIGN §9): a CSV of load cases and measured tips, read,
//! checked and converted to the nondimensional form the rest of prbfit works in.
//!
//! The file has a header row and one row per load case, in path order (each path grows from
//! near the unloaded state; the PRB model follows its rows in order). Columns:
//!
//! - `path` (optional, an integer): groups rows into paths, each path's rows together;
//!   absent, the file is one path;
//! - loads: `fx, fy, mz` (N, N m) or `alpha_x, alpha_y, beta` (nondimensional);
//! - the measured tip: `x, y` (m, from the clamp, the unloaded beam along +x) and `theta`
//!   (rad), or `a, b, phi` (units of L, rad).
//!
//! SI and nondimensional columns may not be mixed; the scene's `[beam]` (its nominal `L`,
//! `E`, `I0`) converts SI to nondimensional. Blank lines and lines starting with `#` are
//! skipped. Every problem is an error naming `file:line:column` and the column's name: a
//! missing or unknown or repeated column, a field that is not a number (or is NaN or
//! infinite), a row with too few or too many fields, a path that shrinks (its load
//! magnitude must grow from row to row) or that comes back after another path, a file
//! with no rows.

use serde::Serialize;

use crate::beam::{Load, TipPose};

use super::{BeamSpec, SceneError};

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

/// A data scene's truth: the file as the scene names it, its content hash, its units and its
/// paths.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DataTruth {
    /// The file as the scene's `[truth] data` writes it (relative to the scene file).
    pub file: String,
    /// SHA-256 of the file's bytes, lowercase hex (empty until the file is read).
    pub sha256: String,
    /// The file's unit system: SI rows were converted with the scene's nominal beam
    /// (nondimensional until the file is read: no rows, nothing converted).
    pub units: Units,
    /// The measured paths (empty until the file is read, and for a mechanism).
    pub paths: Vec<MeasuredPath>,
    /// A mechanism scene's measured drive paths (DESIGN §9 with §8), SI (`None` for a
    /// cantilever, and until the file is read).
    pub stage: Option<StageData>,
}

impl DataTruth {
    /// Rows in all.
    pub fn row_count(&self) -> usize {
        self.paths.iter().map(|p| p.rows.len()).sum::<usize>()
            + self
                .stage
                .as_ref()
                .map_or(0, |s| s.paths.iter().map(|p| p.rows.len()).sum())
    }

    /// Every path's loads, in order.
    pub fn loads(&self) -> Vec<Vec<Load>> {
        self.paths
            .iter()
            .map(|p| p.rows.iter().map(|r| r.load).collect())
            .collect()
    }

    /// The same data with `to` as the nominal beam in place of `from`, the beam its rows were
    /// converted with: what reading the file again with `to` gives. SI rows keep their
    /// newtons and metres, so their nondimensional loads and tips follow the beam (`alpha`
    /// with `L^2 / (E I0)`, `beta` with `L / (E I0)`, the tip with `1 / L`; the angle stays);
    /// nondimensional rows are the same on any beam.
    ///
    /// # Errors
    /// A path that no longer grows from row to row on `to` (the load magnitude sums force
    /// and moment terms, which scale differently): the file would not open with that beam.
    pub fn rebased(&self, from: &BeamSpec, to: &BeamSpec) -> Result<DataTruth, String> {
        let mut out = self.clone();
        if self.units == Units::Nondimensional {
            return Ok(out);
        }
        let (f0, m0, l0) = nominal_scales(from);
        let (f1, m1, l1) = nominal_scales(to);
        let (force, moment, length) = (f1 / f0, m1 / m0, l1 / l0);
        for path in &mut out.paths {
            for row in &mut path.rows {
                row.load = Load {
                    alpha_x: row.load.alpha_x * force,
                    alpha_y: row.load.alpha_y * force,
                    beta: row.load.beta * moment,
                };
                row.tip = TipPose {
                    a: row.tip.a * length,
                    b: row.tip.b * length,
                    phi: row.tip.phi,
                };
            }
            for pair in path.rows.windows(2) {
                if pair[1].load.magnitude() <= pair[0].load.magnitude() {
                    return Err(format!(
                        "with this beam, path {} of {} shrinks at line {} (its nondimensional \
                         load magnitude is not above line {}'s): the file would not open with it",
                        path.id, self.file, pair[1].line, pair[0].line
                    ));
                }
            }
        }
        Ok(out)
    }
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
fn nominal_scales(beam: &BeamSpec) -> (f64, f64, f64) {
    let ei = beam.youngs_modulus * beam.second_moment();
    let l = beam.length;
    (l * l / ei, l / ei, 1.0 / l)
}

/// What a column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Column {
    Path,
    /// Load component 0..3, in its units.
    Load(usize, Units),
    /// Tip component 0..3 (x or a, y or b, theta or phi), in its units.
    Tip(usize, Units),
}

fn column_of(name: &str) -> Option<Column> {
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

/// A field as an error message quotes it: terminal-safe, at most 40 characters.
fn shown(field: &str) -> String {
    let safe = crate::text::sanitize_terminal(field);
    if safe.chars().count() > 40 {
        format!("{}...", safe.chars().take(40).collect::<String>())
    } else {
        safe.into_owned()
    }
}

/// A field of a line with its 1-based character column.
fn fields(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, c) in line.char_indices() {
        if c == ',' {
            out.push((start, &line[start..i]));
            start = i + 1;
        }
    }
    out.push((start, &line[start..]));
    out.into_iter()
        .map(|(at, f)| {
            let lead = f.len() - f.trim_start().len();
            (line[..at + lead].chars().count() + 1, f.trim())
        })
        .collect()
}

/// The file being read, for errors that name `file:line:column`.
struct Csv<'a> {
    origin: &'a str,
}

/// A data row's parsed fields: its path number and, per column, its value (`NaN` in the
/// path column's slot).
struct Fields {
    id: i64,
    values: Vec<f64>,
}

impl<'a> Csv<'a> {
    fn fail(&self, line: usize, column: usize, key: Option<&str>, message: String) -> SceneError {
        SceneError {
            origin: format!("{}:{line}:{column}", self.origin),
            line: None,
            key: key.map(str::to_string),
            message,
        }
    }

    /// The header (its line and fields) and the data lines (numbered from 1), skipping
    /// blank and `#` lines; an empty file is an error naming `known`, the columns.
    #[allow(clippy::type_complexity)]
    fn split<'t>(
        &self,
        text: &'t str,
        known: &str,
    ) -> Result<(usize, Vec<(usize, &'t str)>, Vec<(usize, &'t str)>), SceneError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let Some((header_line, header)) = lines.next() else {
            return Err(self.fail(
                1,
                1,
                None,
                format!("the file is empty: it needs a header row and one row per case ({known})"),
            ));
        };
        Ok((header_line, fields(header), lines.collect()))
    }

    /// The header's columns by `lookup` (an error message for a name it does not know), each
    /// at most once, with their names as written.
    fn columns<'h, C: PartialEq + Copy>(
        &self,
        header_line: usize,
        header: &[(usize, &'h str)],
        lookup: impl Fn(&str) -> Result<C, String>,
    ) -> Result<(Vec<C>, Vec<&'h str>), SceneError> {
        let mut columns: Vec<C> = Vec::with_capacity(header.len());
        let mut names = Vec::with_capacity(header.len());
        for &(col, name) in header {
            let c = lookup(&name.to_ascii_lowercase())
                .map_err(|why| self.fail(header_line, col, Some(name), why))?;
            if columns.contains(&c) {
                return Err(self.fail(header_line, col, Some(name), "a column given twice".into()));
            }
            columns.push(c);
            names.push(name);
        }
        Ok((columns, names))
    }

    /// One data line's fields: as many as the header's `names`, the `path` column (at
    /// `path_column`) an integer, every other a finite number.
    fn row(
        &self,
        line_no: usize,
        line: &str,
        names: &[&str],
        path_column: Option<usize>,
    ) -> Result<(Fields, Vec<usize>), SceneError> {
        let f = fields(line);
        if f.len() != names.len() {
            return Err(self.fail(
                line_no,
                f.last().map_or(1, |x| x.0),
                None,
                format!(
                    "{} fields where the header has {} columns",
                    f.len(),
                    names.len()
                ),
            ));
        }
        let mut out = Fields {
            id: 1,
            values: Vec::with_capacity(f.len()),
        };
        for (k, &(col, field)) in f.iter().enumerate() {
            let name = names[k];
            if Some(k) == path_column {
                out.id = field.parse::<i64>().map_err(|_| {
                    self.fail(
                        line_no,
                        col,
                        Some(name),
                        format!("not a path number: \"{}\"", shown(field)),
                    )
                })?;
                out.values.push(f64::NAN);
                continue;
            }
            let v: f64 = field.parse().map_err(|_| {
                self.fail(
                    line_no,
                    col,
                    Some(name),
                    format!("not a number: \"{}\"", shown(field)),
                )
            })?;
            if !v.is_finite() {
                return Err(self.fail(
                    line_no,
                    col,
                    Some(name),
                    format!("{field} is not a finite number"),
                ));
            }
            out.values.push(v);
        }
        Ok((out, f.iter().map(|x| x.0).collect()))
    }

    /// Adds `row` (from line `line_no`, on path `id`) to `paths`: a path's rows together and
    /// in order, each path growing (`magnitude`, named `what` in the error) from the unloaded
    /// state; the rows' lines by `line_of`.
    #[allow(clippy::too_many_arguments)]
    fn push<R>(
        &self,
        paths: &mut Vec<(i64, Vec<R>)>,
        id: i64,
        row: R,
        line_no: usize,
        what: &str,
        magnitude: impl Fn(&R) -> f64,
        line_of: impl Fn(&R) -> usize,
    ) -> Result<(), SceneError> {
        if paths.last().is_none_or(|p| p.0 != id) {
            if let Some(earlier) = paths.iter().find(|p| p.0 == id) {
                return Err(self.fail(
                    line_no,
                    1,
                    Some("path"),
                    format!(
                        "path {id} comes back after path {} (its rows began at line {}): a \
                         path's rows must be together, in order",
                        paths.last().map_or(0, |p| p.0),
                        earlier.1.first().map_or(0, &line_of)
                    ),
                ));
            }
            paths.push((id, Vec::new()));
        }
        // `paths` has a last element: pushed just above when this row starts a path.
        if let Some(path) = paths.last_mut() {
            if let Some(prev) = path.1.last() {
                let (before, now) = (magnitude(prev), magnitude(&row));
                if now <= before {
                    return Err(self.fail(
                        line_no,
                        1,
                        None,
                        format!(
                            "path {id} shrinks: its {what} {} is not above the previous row's {} \
                             (line {}); a path's rows must grow from the unloaded state",
                            crate::text::bounded(now),
                            crate::text::bounded(before),
                            line_of(prev)
                        ),
                    ));
                }
            }
            path.1.push(row);
        }
        Ok(())
    }

    /// The end of a file: an error when it had no data rows.
    fn nonempty<R>(&self, header_line: usize, paths: &[(i64, Vec<R>)]) -> Result<(), SceneError> {
        if paths.is_empty() {
            return Err(self.fail(
                header_line,
                1,
                None,
                "no data rows after the header: an empty path".into(),
            ));
        }
        Ok(())
    }
}

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
    let mut paths: Vec<(i64, Vec<MeasuredRow>)> = Vec::new();
    for (line_no, line) in rows {
        let (f, _) = csv.row(line_no, line, &names, path_column)?;
        let mut load = [0.0; 3];
        let mut tip = [0.0; 3];
        for (c, v) in columns.iter().zip(&f.values) {
            match *c {
                Column::Load(i, _) => load[i] = v * if i == 2 { moment } else { force },
                Column::Tip(i, _) => tip[i] = if i == 2 { *v } else { v * length },
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
    csv.nonempty(header_line, &paths)?;
    let units = if si { Units::Si } else { Units::Nondimensional };
    Ok((
        paths
            .into_iter()
            .map(|(id, rows)| MeasuredPath { id, rows })
            .collect(),
        units,
    ))
}

/// One measured case of a mechanism (DESIGN §9 with §8): the drive's inputs and the stage's
/// pose and load, SI (m, rad, N, N m), every coordinate known: a prescribed coordinate's
/// pose is its input and its load the measured reaction, a loaded coordinate's load is its
/// input (0 when the file has no column for it) and its pose the measured motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasuredStageRow {
    /// The file's 1-based line.
    pub line: usize,
    /// The drive's inputs `[x, y, phi]`, each of its coordinate's kind (m or N, rad or N m).
    pub drive: [f64; 3],
    /// The stage pose `[dx, dy, dphi]` of the stage point, m and rad.
    pub stage: [f64; 3],
    /// The load on the stage at its point `[fx, fy, mz]`, N and N m: given, or the drive's
    /// reaction.
    pub stage_load: [f64; 3],
}

/// One measured drive path of a mechanism: its rows in order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredStagePath {
    /// The `path` column's value (1 when the file has no such column).
    pub id: i64,
    /// The rows, in the file's order.
    pub rows: Vec<MeasuredStageRow>,
}

/// A mechanism's measured data: which stage coordinates the file's drive prescribes (a
/// `dx, dy, dphi` input column) and its paths.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StageData {
    /// Per stage coordinate `[x, y, phi]`: prescribed (a displacement input) or loaded.
    pub prescribed: [bool; 3],
    /// The measured paths.
    pub paths: Vec<MeasuredStagePath>,
}

/// A mechanism data file's column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum StageColumn {
    Path,
    /// A drive input of coordinate 0..3: displacement (`true`) or load.
    Input(usize, bool),
    /// A measured value of coordinate 0..3: pose (`true`) or load.
    Measured(usize, bool),
}

fn stage_column_of(name: &str) -> Option<StageColumn> {
    use StageColumn::{Input, Measured};
    Some(match name {
        "path" => StageColumn::Path,
        "dx" => Input(0, true),
        "dy" => Input(1, true),
        "dphi" => Input(2, true),
        "fx" => Input(0, false),
        "fy" => Input(1, false),
        "mz" => Input(2, false),
        "stage_dx" => Measured(0, true),
        "stage_dy" => Measured(1, true),
        "stage_dphi" => Measured(2, true),
        "stage_fx" => Measured(0, false),
        "stage_fy" => Measured(1, false),
        "stage_mz" => Measured(2, false),
        _ => return None,
    })
}

const STAGE_KNOWN: &str = "path, the drive's inputs dx/fx, dy/fy, dphi/mz, and the measured \
                           stage_dx, stage_dy, stage_dphi, stage_fx, stage_fy, stage_mz (SI; \
                           DESIGN §9)";

/// The names of a coordinate's columns: input displacement, input load, measured pose,
/// measured load.
const STAGE_NAMES: [[&str; 4]; 3] = [
    ["dx", "fx", "stage_dx", "stage_fx"],
    ["dy", "fy", "stage_dy", "stage_fy"],
    ["dphi", "mz", "stage_dphi", "stage_mz"],
];

/// How far a redundant measured column (the pose of a prescribed coordinate, the load of a
/// loaded one) may differ from the input it repeats, relative to the larger of the two
/// (nondimensional), before the file contradicts itself: a file written from a drive's own
/// values repeats them to its printing precision, far below this.
const REPEAT_TOLERANCE: f64 = 1e-6;
/// The absolute part of that tolerance, nondimensional (a zero load printed as `1e-12`).
const REPEAT_FLOOR: f64 = 1e-9;

/// Reads a mechanism's data file (DESIGN §9 with §8) `text` (from the file `origin`):
/// inputs named as the `[[drives]]` keys, the measured stage pose and loads as `stage_*`,
/// SI, converted for its checks with `mechanism`'s scale (flexure 1's `L`, `E I0`).
///
/// The drive's kinds are the file's: a coordinate with a displacement column (`dx`) is
/// prescribed and its reaction (`stage_fx`) is what was measured; one with a load column or
/// neither (loaded with 0) is loaded and its motion (`stage_dx`) was measured. A measured
/// column that repeats an input (`stage_dx` beside `dx`) must agree with it. Errors as for
/// [`parse_csv`], naming `file:line:column`.
pub fn parse_stage_csv(
    text: &str,
    origin: &str,
    mechanism: &super::Mechanism,
) -> Result<StageData, SceneError> {
    let csv = Csv { origin };
    let (header_line, header, rows) = csv.split(text, STAGE_KNOWN)?;
    let (columns, names) = csv.columns(header_line, &header, |name| {
        stage_column_of(name).ok_or_else(|| {
            if column_of(name).is_some() {
                format!(
                    "a cantilever's column in a mechanism scene's data: its columns are \
                     {STAGE_KNOWN}"
                )
            } else {
                format!("unknown column; a mechanism's data columns are {STAGE_KNOWN}")
            }
        })
    })?;
    let position = |c: StageColumn| columns.iter().position(|x| *x == c);
    let mut prescribed = [false; 3];
    for (c, [dk, lk, pk, fk]) in STAGE_NAMES.iter().enumerate() {
        if let (Some(d), Some(_)) = (
            position(StageColumn::Input(c, true)),
            position(StageColumn::Input(c, false)),
        ) {
            return Err(csv.fail(
                header_line,
                header[d].0,
                Some(dk),
                format!(
                    "give either a displacement ({dk}) or a load ({lk}) for this coordinate, \
                     not both"
                ),
            ));
        }
        prescribed[c] = position(StageColumn::Input(c, true)).is_some();
        let (need, why) = if prescribed[c] {
            (
                *fk,
                format!("{dk} is prescribed, so its reaction {fk} is what was measured"),
            )
        } else {
            (
                *pk,
                format!(
                    "{} is loaded, so the stage's motion is what was measured",
                    if position(StageColumn::Input(c, false)).is_some() {
                        lk.to_string()
                    } else {
                        format!("{lk} (absent: 0)")
                    }
                ),
            )
        };
        if position(StageColumn::Measured(c, !prescribed[c])).is_none() {
            return Err(csv.fail(
                header_line,
                1,
                None,
                format!("missing column `{need}`: {why}"),
            ));
        }
    }
    if !columns.iter().any(|c| matches!(c, StageColumn::Input(..))) {
        return Err(csv.fail(
            header_line,
            1,
            None,
            "no drive input column: give the drive's dx/fx, dy/fy or dphi/mz".into(),
        ));
    }
    // SI to nondimensional, per coordinate: [displacement, load].
    let disp = mechanism.factors([crate::scene::Coordinate::Prescribed(0.0); 3]);
    let load = mechanism.factors([crate::scene::Coordinate::Loaded(0.0); 3]);
    let factor = |c: usize, is_pose: bool| if is_pose { disp[c] } else { load[c] };
    let magnitude = |r: &MeasuredStageRow| {
        (0..3)
            .map(|c| r.drive[c] * factor(c, prescribed[c]))
            .fold(0.0_f64, f64::hypot)
    };

    let path_column = position(StageColumn::Path);
    let mut paths: Vec<(i64, Vec<MeasuredStageRow>)> = Vec::new();
    for (line_no, line) in rows {
        let (f, at) = csv.row(line_no, line, &names, path_column)?;
        let mut input = [0.0; 3];
        // Per coordinate, the measured pose and load columns: (value, column, index).
        let mut measured: [[Option<(f64, usize, usize)>; 2]; 3] = [[None; 2]; 3];
        for (k, (c, v)) in columns.iter().zip(&f.values).enumerate() {
            match *c {
                StageColumn::Input(i, _) => input[i] = *v,
                StageColumn::Measured(i, pose) => {
                    measured[i][usize::from(!pose)] = Some((*v, at[k], k));
                }
                StageColumn::Path => {}
            }
        }
        let mut stage = [0.0; 3];
        let mut stage_load = [0.0; 3];
        for c in 0..3 {
            let p = prescribed[c];
            // The input's slot and the measured slot: pose for a loaded coordinate, load for
            // a prescribed one.
            let (given, out) = if p {
                (&mut stage[c], &mut stage_load[c])
            } else {
                (&mut stage_load[c], &mut stage[c])
            };
            *given = input[c];
            *out = measured[c][usize::from(p)].map_or(0.0, |m| m.0);
            // A measured column that repeats the input must agree with it.
            if let Some((v, col, k)) = measured[c][usize::from(!p)] {
                let s = factor(c, p);
                let (a, b) = (v * s, input[c] * s);
                if (a - b).abs() > REPEAT_TOLERANCE * a.abs().max(b.abs()) + REPEAT_FLOOR {
                    return Err(csv.fail(
                        line_no,
                        col,
                        Some(names[k]),
                        format!(
                            "{} contradicts the input {} = {} on the same row: a measured \
                             column that repeats the drive's input must agree with it",
                            crate::text::bounded(v),
                            STAGE_NAMES[c][usize::from(!p)],
                            crate::text::bounded(input[c])
                        ),
                    ));
                }
            }
        }
        let row = MeasuredStageRow {
            line: line_no,
            drive: input,
            stage,
            stage_load,
        };
        csv.push(
            &mut paths,
            f.id,
            row,
            line_no,
            "drive's magnitude (nondimensional)",
            magnitude,
            |r| r.line,
        )?;
    }
    csv.nonempty(header_line, &paths)?;
    Ok(StageData {
        prescribed,
        paths: paths
            .into_iter()
            .map(|(id, rows)| MeasuredStagePath { id, rows })
            .collect(),
    })
}
