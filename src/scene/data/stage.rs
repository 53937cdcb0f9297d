//! A mechanism's data file (DESIGN §9 with §8): the drive's inputs named as the `[[drives]]`
//! keys (`dx`/`fx`, `dy`/`fy`, `dphi`/`mz`), the measured stage pose and loads as `stage_*`,
//! SI; which coordinates the drive prescribes is the file's, and a measured column that
//! repeats an input must agree with it.

use serde::Serialize;

use super::super::drive::Coordinate;
use super::super::error::SceneError;
use super::super::mechanism::Mechanism;
use super::csv::{Csv, RowPaths};
use super::tip::column_of;

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
/// [`parse_csv`](super::parse_csv), naming `file:line:column`.
pub fn parse_stage_csv(
    text: &str,
    origin: &str,
    mechanism: &Mechanism,
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
    let disp = mechanism.factors([Coordinate::Prescribed(0.0); 3]);
    let load = mechanism.factors([Coordinate::Loaded(0.0); 3]);
    let factor = |c: usize, is_pose: bool| if is_pose { disp[c] } else { load[c] };
    let magnitude = |r: &MeasuredStageRow| {
        (0..3)
            .map(|c| r.drive[c] * factor(c, prescribed[c]))
            .fold(0.0_f64, f64::hypot)
    };

    let path_column = position(StageColumn::Path);
    let mut paths: RowPaths<MeasuredStageRow> = RowPaths::default();
    for (line_no, line) in rows {
        let (f, at) = csv.row(line_no, line, &names, path_column)?;
        let mut input = [0.0; 3];
        // Per coordinate, the measured pose and load columns: (value, column, index).
        let mut measured: [[Option<(f64, usize, usize)>; 2]; 3] = [[None; 2]; 3];
        for (k, (c, v)) in columns.iter().zip(&f.values).enumerate() {
            // Every value within reach once nondimensional (kept in SI here).
            let checked = |i: usize, pose: bool| {
                csv.scaled(line_no, at[k], names[k], *v, factor(i, pose))
                    .map(|_| *v)
            };
            match *c {
                StageColumn::Input(i, _) => input[i] = checked(i, prescribed[i])?,
                StageColumn::Measured(i, pose) => {
                    measured[i][usize::from(!pose)] = Some((checked(i, pose)?, at[k], k));
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
    csv.nonempty(header_line, &paths.paths)?;
    // The reactions are the truth's forces: every one of them 0 says the drive held its
    // coordinates without any force, which no flexure allows (a rig that did not record
    // them).
    // Judged against them, a model's every relative force error would be its reaction over
    // the scale's floor, 1e11 and more (J 3.6e23 on the slider-crank), not a figure.
    let reactions: Vec<usize> = (0..3).filter(|&c| prescribed[c]).collect();
    let all_zero = paths
        .paths
        .iter()
        .flat_map(|p| &p.1)
        .all(|r| reactions.iter().all(|&c| r.stage_load[c] == 0.0));
    if !reactions.is_empty() && all_zero {
        let columns: Vec<&str> = reactions.iter().map(|&c| STAGE_NAMES[c][3]).collect();
        return Err(csv.fail(
            header_line,
            1,
            None,
            format!(
                "every measured reaction of the prescribed coordinates ({}) is 0: no flexure \
                 lets a drive hold them without force, and a model's force errors \
                 relative to 0 are no figure; give the reactions the rig measured",
                columns.join(", ")
            ),
        ));
    }
    Ok(StageData {
        prescribed,
        paths: paths
            .paths
            .into_iter()
            .map(|(id, rows)| MeasuredStagePath { id, rows })
            .collect(),
    })
}
