//! The PRB matrix `Omega` (DESIGN §3): one row per rigid segment, root first, columns
//! `[gamma, k_theta, k_ex]`.
//!
//! - `gamma`: the segment's nominal length as a fraction of L (the gammas sum to 1);
//! - `k_theta`: torsion spring at the segment's root end, `K_theta = k_theta E I0 / L`, or
//!   `inf` for no joint there;
//! - `k_ex`: extension spring along the segment, `K_ex = k_ex E A0 / L`, or `inf` for a fixed
//!   length.
//!
//! Text form: rows separated by `;`, entries by `,`, `inf` for infinity, and a trailing `!`
//! on a cell that the fit must leave alone (`0.1!,inf,inf; 0.9,2.25,inf`). `inf` cells are
//! the topology and never fitted. Floats print in Rust's shortest round-trip form, so text,
//! TOML and JSON all round-trip exactly.
//!
//! Topology names list the segments from the root: `L` rigid, `R` torsion spring, `P`
//! extension spring, `RP` both, joined by `-` (Su's 3R is `L-R-R-R`, Howell's 1R `L-R`).

use std::fmt;
use std::str::FromStr;

use serde::de::{self, Deserializer};
use serde::ser::Serializer;
use serde::{Deserialize, Serialize};

use crate::text::bounded;

/// How far the gammas' sum may stray from 1 (round-off in a typed matrix, not rounding of
/// published values, which must be converted explicitly).
pub const GAMMA_SUM_TOL: f64 = 1e-9;

/// The stiffest finite spring a matrix may hold, in units of `E I0 / L` (`E A0 / L`). A
/// spring this stiff moves its joint by 1e-12 of the load: it is rigid, and `inf` says so
/// exactly, where a spring of 1e308 would only make the statics ill-conditioned (and, before
/// this limit, was reported as a buckling point).
pub const MAX_SPRING: f64 = 1e12;

/// The three columns of a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Column {
    /// `gamma`: the segment's nominal length as a fraction of L.
    Gamma,
    /// `k_theta`: the torsion spring at the segment's root end, in units of `E I0 / L`.
    KTheta,
    /// `k_ex`: the extension spring along the segment, in units of `E A0 / L`.
    KEx,
}

impl Column {
    /// The three columns in matrix order: gamma, k_theta, k_ex.
    pub const ALL: [Column; 3] = [Column::Gamma, Column::KTheta, Column::KEx];

    /// The column's 0-based position in a row (gamma 0, k_theta 1, k_ex 2), also the index
    /// into [`PrbRow::free`].
    pub fn index(self) -> usize {
        match self {
            Column::Gamma => 0,
            Column::KTheta => 1,
            Column::KEx => 2,
        }
    }

    /// The column's name as the text form, files and messages spell it (`gamma`,
    /// `k_theta`, `k_ex`).
    pub fn name(self) -> &'static str {
        match self {
            Column::Gamma => "gamma",
            Column::KTheta => "k_theta",
            Column::KEx => "k_ex",
        }
    }
}

impl fmt::Display for Column {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One segment of the chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrbRow {
    /// Nominal length of the segment as a fraction of L (> 0; the gammas of a matrix sum
    /// to 1).
    pub gamma: f64,
    /// Torsion spring at the segment's root end, in units of `E I0 / L` (> 0), or `inf` for
    /// no joint there.
    pub k_theta: f64,
    /// Extension spring along the segment, in units of `E A0 / L` (> 0), or `inf` for a fixed
    /// length.
    pub k_ex: f64,
    /// Per cell (gamma, k_theta, k_ex): may the fit change it? `inf` cells never are.
    pub free: [bool; 3],
}

impl PrbRow {
    /// The value in `column` (gamma as a fraction of L, k_theta in `E I0 / L`, k_ex in
    /// `E A0 / L`).
    pub fn get(&self, column: Column) -> f64 {
        match column {
            Column::Gamma => self.gamma,
            Column::KTheta => self.k_theta,
            Column::KEx => self.k_ex,
        }
    }

    /// Overwrites the value in `column`, unchecked: the owning [`PrbMatrix`] validates.
    pub fn set(&mut self, column: Column, value: f64) {
        match column {
            Column::Gamma => self.gamma = value,
            Column::KTheta => self.k_theta = value,
            Column::KEx => self.k_ex = value,
        }
    }

    /// A torsion spring at this segment's root end.
    pub fn has_revolute(&self) -> bool {
        self.k_theta.is_finite()
    }

    /// An extension spring along this segment.
    pub fn has_prismatic(&self) -> bool {
        self.k_ex.is_finite()
    }

    /// Whether the fit may change this cell (finite and marked free).
    pub fn is_free(&self, column: Column) -> bool {
        self.free[column.index()] && self.get(column).is_finite()
    }

    /// The row's topology letter(s): `L`, `R`, `P` or `RP`.
    pub fn kind(&self) -> &'static str {
        match (self.has_revolute(), self.has_prismatic()) {
            (false, false) => "L",
            (true, false) => "R",
            (false, true) => "P",
            (true, true) => "RP",
        }
    }
}

/// A PRB matrix. Construct with [`PrbMatrix::new`] (validates) or parse the text form.
#[derive(Debug, Clone, PartialEq)]
pub struct PrbMatrix {
    rows: Vec<PrbRow>,
}

/// What is wrong with a matrix; rows and columns are 1-based, as a user counts them.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MatrixError {
    /// The matrix has no rows (an empty list or empty text).
    #[error("the matrix has no rows")]
    Empty,
    /// A row of the text form does not have exactly three entries.
    #[error("row {row}: expected 3 entries (gamma, k_theta, k_ex), got {got}")]
    RowLength {
        /// 1-based row of the text.
        row: usize,
        /// How many entries the row had (0 for an empty row).
        got: usize,
    },
    /// An entry of the text form is neither a number nor `inf`.
    #[error("row {row}, column {column}: `{text}` is not a number or inf")]
    NotANumber {
        /// 1-based row of the text.
        row: usize,
        /// The column of the bad entry.
        column: Column,
        /// The entry as typed (with its `!`, if any).
        text: String,
    },
    /// A segment length is not a finite number > 0.
    #[error(
        "row {row}, column gamma: the segment length must be a finite number > 0, got {}",
        bounded(*value)
    )]
    Gamma {
        /// 1-based row.
        row: usize,
        /// The rejected gamma (fraction of L).
        value: f64,
    },
    /// A spring constant is neither > 0 nor `inf` (zero, negative, NaN or `-inf`).
    #[error(
        "row {row}, column {column}: a spring constant must be > 0 and at most {MAX_SPRING:e} \
         (stiffer is rigid: write inf for no joint), got {}",
        bounded(*value)
    )]
    Spring {
        /// 1-based row.
        row: usize,
        /// [`Column::KTheta`] or [`Column::KEx`].
        column: Column,
        /// The rejected constant (`E I0 / L` or `E A0 / L`).
        value: f64,
    },
    /// The gammas do not sum to 1 within [`GAMMA_SUM_TOL`].
    #[error("the gammas must sum to 1, they sum to {sum} (off by {:.3e})", sum - 1.0)]
    GammaSum {
        /// The sum of the gammas found.
        sum: f64,
    },
    /// Every `k_theta` and `k_ex` is `inf`: the chain is one rigid body and cannot deflect.
    #[error("the matrix has no joint: give at least one finite k_theta or k_ex")]
    NoJoint,
    /// A topology name has a segment other than `L`, `R`, `P` or `RP`; holds that segment.
    #[error("unknown topology segment `{0}` (expected L, R, P or RP, joined by -)")]
    Topology(String),
    /// An edit names a row past the end of the matrix.
    #[error("row {row}: no such row (the matrix has {rows})")]
    NoRow {
        /// 1-based row asked for.
        row: usize,
        /// How many rows the matrix has.
        rows: usize,
    },
    /// A gamma edit on a one-segment matrix: there is no other segment to rebalance against.
    #[error("a single segment's gamma is always 1")]
    SingleSegmentGamma,
    /// A gamma edit, with the donor segment taking the difference, gives an invalid matrix
    /// (the donor's length would be <= 0, say).
    #[error("{source} (segment {donor} would get the rest)")]
    Rebalance {
        /// 1-based: the segment that would have taken the difference.
        donor: usize,
        /// What the rebalanced matrix broke.
        #[source]
        source: Box<MatrixError>,
    },
}

impl PrbMatrix {
    /// A validated matrix.
    pub fn new(mut rows: Vec<PrbRow>) -> Result<PrbMatrix, MatrixError> {
        // A flag on an `inf` cell means nothing; keep it canonical (free, so that a cell
        // later given a finite value starts out free) so equal matrices compare equal.
        for r in &mut rows {
            for c in Column::ALL {
                if r.get(c) == f64::INFINITY {
                    r.free[c.index()] = true;
                }
            }
        }
        let m = PrbMatrix { rows };
        m.validate()?;
        Ok(m)
    }

    /// The segments, root first.
    pub fn rows(&self) -> &[PrbRow] {
        &self.rows
    }

    /// Number of segments (rows).
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether there are no segments; never true for a validated matrix.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Checks every rule of DESIGN §3.
    pub fn validate(&self) -> Result<(), MatrixError> {
        if self.rows.is_empty() {
            return Err(MatrixError::Empty);
        }
        for (i, r) in self.rows.iter().enumerate() {
            let row = i + 1;
            if !(r.gamma.is_finite() && r.gamma > 0.0) {
                return Err(MatrixError::Gamma {
                    row,
                    value: r.gamma,
                });
            }
            for column in [Column::KTheta, Column::KEx] {
                let value = r.get(column);
                let ok = value == f64::INFINITY || (value > 0.0 && value <= MAX_SPRING);
                if !ok {
                    return Err(MatrixError::Spring { row, column, value });
                }
            }
        }
        let sum: f64 = self.rows.iter().map(|r| r.gamma).sum();
        if (sum - 1.0).abs() > GAMMA_SUM_TOL {
            return Err(MatrixError::GammaSum { sum });
        }
        if !self
            .rows
            .iter()
            .any(|r| r.has_revolute() || r.has_prismatic())
        {
            return Err(MatrixError::NoJoint);
        }
        Ok(())
    }

    /// Sets one cell and validates; on error the matrix is unchanged.
    pub fn with_cell(
        &self,
        row: usize,
        column: Column,
        value: f64,
    ) -> Result<PrbMatrix, MatrixError> {
        let mut rows = self.rows.clone();
        rows[row].set(column, value);
        PrbMatrix::new(rows)
    }

    /// Sets segment `row`'s gamma (0-based) to `gamma` and keeps the gammas summing to 1: one
    /// other segment, the donor, takes the difference. The donor is a segment whose gamma is
    /// free if there is one (a fixed cell is the user's word), preferring segments after
    /// `row`, then the one furthest towards the tip. On error (the donor would get a length
    /// <= 0, say) the matrix is unchanged and the error names the donor.
    pub fn with_gamma(&self, row: usize, gamma: f64) -> Result<PrbMatrix, MatrixError> {
        let rows = &self.rows;
        if row >= rows.len() {
            return Err(MatrixError::NoRow {
                row: row + 1,
                rows: rows.len(),
            });
        }
        let delta = gamma - rows[row].gamma;
        let donor = (0..rows.len())
            .filter(|&i| i != row)
            .max_by_key(|&i| (rows[i].is_free(Column::Gamma), i > row, i))
            .ok_or(MatrixError::SingleSegmentGamma)?;
        let mut new_rows = rows.clone();
        new_rows[row].gamma = gamma;
        new_rows[donor].gamma -= delta;
        PrbMatrix::new(new_rows).map_err(|e| MatrixError::Rebalance {
            donor: donor + 1,
            source: Box::new(e),
        })
    }

    /// Marks a cell free (the fit may change it) or fixed.
    pub fn set_free(&mut self, row: usize, column: Column, free: bool) {
        self.rows[row].free[column.index()] = free;
    }

    /// The topology name (`L-R-R-R`).
    pub fn topology(&self) -> String {
        self.rows
            .iter()
            .map(|r| r.kind())
            .collect::<Vec<_>>()
            .join("-")
    }

    /// Number of revolute joints.
    pub fn revolute_count(&self) -> usize {
        self.rows.iter().filter(|r| r.has_revolute()).count()
    }

    /// Number of prismatic joints.
    pub fn prismatic_count(&self) -> usize {
        self.rows.iter().filter(|r| r.has_prismatic()).count()
    }

    /// A matrix for a topology name with sensible starting values:
    /// - a leading rigid segment gets `gamma = 0.3 / (n + 1)` for `n` later segments (Howell's
    ///   0.15 for one joint, close to Su's 0.10 for three);
    /// - the rest share the length equally, the last at half weight (a tip segment carries
    ///   little moment, as in Su's and Chen's 3R);
    /// - every torsion spring starts at `k_theta = n_R`, so that `sum 1/k_theta = 1` and a
    ///   pure moment is exact from the start;
    /// - every extension spring starts at `k_ex = 1 / gamma`, the axial stiffness of that
    ///   length of beam.
    ///
    /// Designers' shorthand is accepted too: `nR` (`1R` .. `9R`, any case) is a rigid root
    /// segment and `n` revolute ones, `L-R-...-R` (so `1R` is Howell's `L-R`, `3R` Su's
    /// `L-R-R-R`).
    pub fn from_topology(name: &str) -> Result<PrbMatrix, MatrixError> {
        let expanded = expand_shorthand(name.trim());
        let name = expanded.as_deref().unwrap_or(name);
        let kinds: Vec<&str> = name.trim().split('-').map(str::trim).collect();
        for k in &kinds {
            if !matches!(*k, "L" | "R" | "P" | "RP") {
                return Err(MatrixError::Topology(k.to_string()));
            }
        }
        let n = kinds.len();
        let leading_rigid = kinds[0] == "L" && n > 1;
        let mut gammas = vec![0.0; n];
        let start = if leading_rigid {
            gammas[0] = 0.3 / n as f64;
            1
        } else {
            0
        };
        let rest = 1.0 - gammas[0];
        let weights: Vec<f64> = (start..n)
            .map(|i| {
                if i + 1 == n && n - start > 1 {
                    0.5
                } else {
                    1.0
                }
            })
            .collect();
        let total: f64 = weights.iter().sum();
        for (i, w) in (start..n).zip(&weights) {
            gammas[i] = rest * w / total;
        }
        // Make the sum exactly 1 despite round-off.
        let sum_others: f64 = gammas[..n - 1].iter().sum();
        gammas[n - 1] = 1.0 - sum_others;
        let n_r = kinds.iter().filter(|k| k.contains('R')).count().max(1) as f64;
        let rows = kinds
            .iter()
            .zip(&gammas)
            .map(|(k, &gamma)| PrbRow {
                gamma,
                k_theta: if k.contains('R') { n_r } else { f64::INFINITY },
                k_ex: if k.contains('P') {
                    1.0 / gamma
                } else {
                    f64::INFINITY
                },
                free: [true; 3],
            })
            .collect();
        PrbMatrix::new(rows)
    }

    /// The text form (with `!` on fixed finite cells).
    pub fn to_text(&self) -> String {
        self.rows
            .iter()
            .map(|r| {
                Column::ALL
                    .iter()
                    .map(|&c| {
                        let v = r.get(c);
                        if v == f64::INFINITY {
                            "inf".to_string()
                        } else if r.free[c.index()] {
                            format!("{v}")
                        } else {
                            format!("{v}!")
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// Parses the text form and validates.
    pub fn parse(text: &str) -> Result<PrbMatrix, MatrixError> {
        let mut rows = Vec::new();
        for (i, row_text) in text.split(';').enumerate() {
            let row = i + 1;
            let trimmed = row_text.trim();
            if trimmed.is_empty() && i > 0 && text.trim_end().ends_with(';') {
                continue; // a trailing `;`
            }
            let cells: Vec<&str> = trimmed.split(',').map(str::trim).collect();
            if cells.len() != 3 {
                return Err(MatrixError::RowLength {
                    row,
                    got: if trimmed.is_empty() { 0 } else { cells.len() },
                });
            }
            let mut values = [0.0; 3];
            let mut free = [true; 3];
            for (j, cell) in cells.iter().enumerate() {
                let column = Column::ALL[j];
                let (number, fixed) = match cell.strip_suffix('!') {
                    Some(rest) => (rest.trim(), true),
                    None => (*cell, false),
                };
                let value = parse_entry(number).ok_or_else(|| MatrixError::NotANumber {
                    row,
                    column,
                    text: cell.to_string(),
                })?;
                values[j] = value;
                free[j] = !fixed;
            }
            rows.push(PrbRow {
                gamma: values[0],
                k_theta: values[1],
                k_ex: values[2],
                free,
            });
        }
        PrbMatrix::new(rows)
    }
}

/// A number or `inf` (any case, optionally `+inf`/`infinity`); NaN is not a number here.
fn parse_entry(text: &str) -> Option<f64> {
    let lower = text.to_ascii_lowercase();
    if matches!(lower.as_str(), "inf" | "+inf" | "infinity" | "+infinity") {
        return Some(f64::INFINITY);
    }
    if lower.contains("inf") || lower.contains("nan") {
        return None;
    }
    text.parse::<f64>().ok()
}

impl fmt::Display for PrbMatrix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_text())
    }
}

impl FromStr for PrbMatrix {
    type Err = MatrixError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        PrbMatrix::parse(s)
    }
}

/// Serialised as a table of rows, each `{gamma, k_theta, k_ex, fixed}` with infinity as the
/// string `"inf"` (JSON has no infinity) and `fixed` listing the pinned columns. The same
/// encoding serves TOML and JSON and round-trips exactly.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RowRepr {
    gamma: f64,
    k_theta: Entry,
    k_ex: Entry,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    fixed: Vec<String>,
}

#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum Entry {
    Number(f64),
    Word(String),
}

impl Entry {
    fn from_value(v: f64) -> Entry {
        if v == f64::INFINITY {
            Entry::Word("inf".into())
        } else {
            Entry::Number(v)
        }
    }

    fn value(&self) -> Result<f64, String> {
        match self {
            Entry::Number(v) => Ok(*v),
            Entry::Word(w) => parse_entry(w).ok_or_else(|| format!("`{w}` is not a number or inf")),
        }
    }
}

impl Serialize for PrbMatrix {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let rows: Vec<RowRepr> = self
            .rows
            .iter()
            .map(|r| RowRepr {
                gamma: r.gamma,
                k_theta: Entry::from_value(r.k_theta),
                k_ex: Entry::from_value(r.k_ex),
                fixed: Column::ALL
                    .iter()
                    .filter(|c| !r.free[c.index()] && r.get(**c).is_finite())
                    .map(|c| c.name().to_string())
                    .collect(),
            })
            .collect();
        rows.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for PrbMatrix {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let reprs = Vec::<RowRepr>::deserialize(deserializer)?;
        let mut rows = Vec::with_capacity(reprs.len());
        for (i, r) in reprs.iter().enumerate() {
            let ctx = |e: String| de::Error::custom(format!("row {}: {e}", i + 1));
            let mut free = [true; 3];
            for name in &r.fixed {
                let c = Column::ALL
                    .iter()
                    .find(|c| c.name() == name)
                    .ok_or_else(|| ctx(format!("unknown column `{name}` in fixed")))?;
                free[c.index()] = false;
            }
            rows.push(PrbRow {
                gamma: r.gamma,
                k_theta: r.k_theta.value().map_err(ctx)?,
                k_ex: r.k_ex.value().map_err(ctx)?,
                free,
            });
        }
        PrbMatrix::new(rows).map_err(de::Error::custom)
    }
}

/// `nR` → `L-R-...-R` with `n` revolute segments (1 to 9), else `None`.
fn expand_shorthand(name: &str) -> Option<String> {
    let (count, r) = name.split_at_checked(name.len().checked_sub(1)?)?;
    let n: usize = count.parse().ok()?;
    ((1..=9).contains(&n) && r.eq_ignore_ascii_case("r")).then(|| {
        std::iter::once("L")
            .chain(std::iter::repeat_n("R", n))
            .collect::<Vec<_>>()
            .join("-")
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn shorthand_names_expand_to_topologies() {
        for (short, long) in [
            ("1R", "L-R"),
            ("2r", "L-R-R"),
            ("3R", "L-R-R-R"),
            ("4R", "L-R-R-R-R"),
        ] {
            assert_eq!(
                PrbMatrix::from_topology(short).unwrap(),
                PrbMatrix::from_topology(long).unwrap(),
                "{short}"
            );
        }
        for bad in ["0R", "10R", "3P", "x3R"] {
            assert!(PrbMatrix::from_topology(bad).is_err(), "{bad}");
        }
    }

    use super::*;

    #[test]
    fn with_gamma_rebalances_one_donor_and_keeps_the_sum() {
        // Su's 3R with the tip gamma fixed: row 1 grows, the donor is the last free gamma
        // after it (row 2), not the fixed tip.
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15!,2.58,inf").unwrap();
        let n = m.with_gamma(1, 0.45).unwrap();
        let g: Vec<f64> = n.rows().iter().map(|r| r.gamma).collect();
        assert_eq!(g, vec![0.1, 0.45, 0.4 - (0.45 - 0.35), 0.15]);
        assert!((g.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // Too much: the donor would go negative, the error names it and nothing changes.
        let err = m.with_gamma(1, 0.9).unwrap_err().to_string();
        assert!(err.contains("segment 3 would get the rest"), "{err}");
        assert!(matches!(
            PrbMatrix::parse("1,2,inf").unwrap().with_gamma(0, 0.5),
            Err(MatrixError::SingleSegmentGamma)
        ));
        assert!(matches!(
            m.with_gamma(7, 0.5),
            Err(MatrixError::NoRow { .. })
        ));
    }

    #[test]
    fn su_text_parses_and_prints() {
        let text = "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf";
        let m = PrbMatrix::parse(text).unwrap();
        assert_eq!(m.topology(), "L-R-R-R");
        assert_eq!(m.to_text(), text);
        assert_eq!(m.revolute_count(), 3);
    }

    #[test]
    fn fixed_cells_round_trip_in_text() {
        let m = PrbMatrix::parse("0.15!,inf,inf; 0.85, 2.2525! ,inf").unwrap();
        assert!(!m.rows()[0].is_free(Column::Gamma));
        assert!(!m.rows()[1].is_free(Column::KTheta));
        assert!(m.rows()[1].is_free(Column::Gamma));
        assert!(!m.rows()[1].is_free(Column::KEx), "inf is never free");
        assert_eq!(PrbMatrix::parse(&m.to_text()).unwrap(), m);
    }

    #[test]
    fn topology_names_give_valid_starting_matrices() {
        for name in [
            "L-R",
            "L-R-R",
            "L-R-R-R",
            "L-R-R-R-R",
            "L-RP",
            "L-P",
            "R",
            "R-R",
            "L-R-P",
            "RP-RP",
        ] {
            let m = PrbMatrix::from_topology(name).unwrap();
            assert_eq!(m.topology(), name);
            let inv: f64 = m
                .rows()
                .iter()
                .filter(|r| r.has_revolute())
                .map(|r| 1.0 / r.k_theta)
                .sum();
            if m.revolute_count() > 0 {
                assert!((inv - 1.0).abs() < 1e-12);
            }
        }
        let howell_like = PrbMatrix::from_topology("L-R").unwrap();
        assert!((howell_like.rows()[0].gamma - 0.15).abs() < 1e-15);
        assert!(
            matches!(PrbMatrix::from_topology("L-X"), Err(MatrixError::Topology(w)) if w == "X")
        );
        assert!(matches!(
            PrbMatrix::from_topology("L"),
            Err(MatrixError::NoJoint)
        ));
    }
}
