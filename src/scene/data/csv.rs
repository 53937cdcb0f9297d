//! The CSV reading both kinds of data file share (DESIGN §9): the header and the data lines
//! (blank and `#` lines skipped), columns looked up by name and given once, a row's fields
//! as numbers, rows gathered into paths that grow from the unloaded state. Every error names
//! `file:line:column`.

use std::collections::HashMap;

use super::super::error::SceneError;
use super::super::rules;

/// Rows gathered into paths as they are read, with what the limits check needs counted as
/// it goes (a file of 100000 one-row paths searched its paths for each row: seconds).
pub(super) struct RowPaths<R> {
    /// The paths in file order: id and rows.
    pub paths: Vec<(i64, Vec<R>)>,
    /// The rows read.
    rows: usize,
    /// Each id's index in `paths`.
    index: HashMap<i64, usize>,
}

impl<R> Default for RowPaths<R> {
    fn default() -> Self {
        RowPaths {
            paths: Vec::new(),
            rows: 0,
            index: HashMap::new(),
        }
    }
}

/// A field as an error message quotes it: terminal-safe, at most 40 characters.
pub(super) fn shown(field: &str) -> String {
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
pub(super) struct Csv<'a> {
    /// The file, as errors name it.
    pub(super) origin: &'a str,
}

/// A data row's parsed fields: its path number and, per column, its value (`NaN` in the
/// path column's slot).
pub(super) struct Fields {
    /// The `path` column's value (1 without one).
    pub(super) id: i64,
    /// Per column, its value.
    pub(super) values: Vec<f64>,
}

impl<'a> Csv<'a> {
    /// The field `v` (at `line`, `column`, of column `name`) made nondimensional by `factor`
    /// (1 for a column already so), within the reach a scene's loads have
    /// ([`rules::reachable`]): a tip a billion lengths away is a file in the wrong units or a
    /// corrupt one, and numbers near `f64::MAX` overflow everything derived from them
    /// (`x = 1e308` ended in "a result is not a finite number", with no line).
    pub(super) fn scaled(
        &self,
        line: usize,
        column: usize,
        name: &str,
        v: f64,
        factor: f64,
    ) -> Result<f64, SceneError> {
        let scaled = v * factor;
        rules::reachable(v, scaled).map_err(|m| self.fail(line, column, Some(name), m))?;
        Ok(scaled)
    }

    pub(super) fn fail(
        &self,
        line: usize,
        column: usize,
        key: Option<&str>,
        message: String,
    ) -> SceneError {
        SceneError {
            origin: format!("{}:{line}:{column}", self.origin),
            line: None,
            key: key.map(str::to_string),
            message,
        }
    }

    /// The header (its line and fields) and the data lines (numbered from 1), skipping a
    /// leading byte-order mark and blank and `#` lines; an empty file is an error naming
    /// `known`, the columns.
    #[allow(clippy::type_complexity)]
    pub(super) fn split<'t>(
        &self,
        text: &'t str,
        known: &str,
    ) -> Result<(usize, Vec<(usize, &'t str)>, Vec<(usize, &'t str)>), SceneError> {
        // The byte-order mark a spreadsheet writes first is no part of the first column's
        // name (its columns count from after it, as an editor shows them).
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
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
    pub(super) fn columns<'h, C: PartialEq + Copy>(
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
    pub(super) fn row(
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
    pub(super) fn push<R>(
        &self,
        gathered: &mut RowPaths<R>,
        id: i64,
        row: R,
        line_no: usize,
        what: &str,
        magnitude: impl Fn(&R) -> f64,
        line_of: impl Fn(&R) -> usize,
    ) -> Result<(), SceneError> {
        // A scene's limits hold for measured rows too, refused at the row that passes them
        // (before anything is solved): a row is a case, a path's rows its steps.
        let paths = &mut gathered.paths;
        if u64::try_from(gathered.rows).unwrap_or(u64::MAX) >= crate::scene::MAX_CASES {
            return Err(self.fail(
                line_no,
                1,
                None,
                format!(
                    "more than the {} load cases (rows) a scene may have",
                    crate::scene::MAX_CASES
                ),
            ));
        }
        if let Some(path) = paths.last().filter(|p| p.0 == id) {
            if i64::try_from(path.1.len()).unwrap_or(i64::MAX) >= crate::scene::MAX_STEPS {
                return Err(self.fail(
                    line_no,
                    1,
                    None,
                    format!(
                        "path {id} has more than the {} steps (rows) a load path may have",
                        crate::scene::MAX_STEPS
                    ),
                ));
            }
        }
        if paths.last().is_none_or(|p| p.0 != id) {
            if let Some(earlier) = gathered.index.get(&id).map(|&i| &paths[i]) {
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
            gathered.index.insert(id, paths.len());
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
            gathered.rows += 1;
        }
        Ok(())
    }

    /// The end of a file: an error when it had no data rows.
    pub(super) fn nonempty<R>(
        &self,
        header_line: usize,
        paths: &[(i64, Vec<R>)],
    ) -> Result<(), SceneError> {
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
