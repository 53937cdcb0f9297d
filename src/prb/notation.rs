//! The PRB matrix's notations (DESIGN §3): its text form, its TOML/JSON form and topology
//! names.
//!
//! Text form: rows separated by `;`, entries by `,`, `inf` for infinity, and a trailing `!`
//! on a cell that the fit must leave alone (`0.1!,inf,inf; 0.9,2.25,inf`). Each row has three
//! entries (`gamma, k_theta, k_ex`, its mass where its length is) or four (`..., mu`),
//! every row alike; a three-column matrix prints as three columns. `inf` cells are
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

use super::matrix::{Column, MatrixError, PrbMatrix, PrbRow};

impl PrbMatrix {
    /// The topology name (`L-R-R-R`).
    pub fn topology(&self) -> String {
        self.rows
            .iter()
            .map(|r| r.kind())
            .collect::<Vec<_>>()
            .join("-")
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
            .map(|(k, &gamma)| {
                PrbRow::new(
                    gamma,
                    if k.contains('R') { n_r } else { f64::INFINITY },
                    if k.contains('P') {
                        1.0 / gamma
                    } else {
                        f64::INFINITY
                    },
                )
            })
            .collect();
        PrbMatrix::new(rows)
    }

    /// The text form (with `!` on fixed finite cells; the mu column only when the matrix
    /// gives its mus).
    pub fn to_text(&self) -> String {
        let columns: &[Column] = if self.has_mu() {
            &Column::ALL
        } else {
            &Column::STATICS
        };
        self.rows
            .iter()
            .map(|r| {
                columns
                    .iter()
                    .map(|&c| {
                        let v = r.get(c);
                        if v == f64::INFINITY {
                            "inf".to_string()
                        } else if r.free[c.index()] {
                            cell_text(v)
                        } else {
                            format!("{}!", cell_text(v))
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
            if !(3..=4).contains(&cells.len()) {
                return Err(MatrixError::RowLength {
                    row,
                    got: if trimmed.is_empty() { 0 } else { cells.len() },
                });
            }
            let mut values = [0.0; 4];
            let mut free = [true; 4];
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
                mu: (cells.len() == 4).then_some(values[3]),
                free,
            });
        }
        PrbMatrix::new(rows)
    }
}

/// A finite cell as the text form writes it: its shortest form that reads back to the same
/// number, plainly in the range of springs and fractions (`3.51`, `0.125`), in scientific
/// notation beyond it (`1e-300`, which plainly is 302 characters).
fn cell_text(v: f64) -> String {
    if v == 0.0 || (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A finite number or `inf` (any case, optionally `+inf`/`infinity`); NaN is not a number
/// here, nor is a number too large for a double (`1e400`): a rigid segment or a locked joint
/// is written `inf`, never reached by overflow.
fn parse_entry(text: &str) -> Option<f64> {
    let lower = text.to_ascii_lowercase();
    if matches!(lower.as_str(), "inf" | "+inf" | "infinity" | "+infinity") {
        return Some(f64::INFINITY);
    }
    if lower.contains("inf") || lower.contains("nan") {
        return None;
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
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

/// Serialised as a table of rows, each `{gamma, k_theta, k_ex, mu, fixed}` with infinity as
/// the string `"inf"` (JSON has no infinity), `mu` only when the matrix gives its mus, and
/// `fixed` listing the pinned columns. The same encoding serves TOML and JSON and
/// round-trips exactly.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RowRepr {
    gamma: f64,
    k_theta: Entry,
    k_ex: Entry,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mu: Option<f64>,
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
            Entry::Word(w) => {
                parse_entry(w).ok_or_else(|| format!("`{w}` is neither a finite number nor inf"))
            }
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
                mu: r.mu,
                fixed: Column::ALL
                    .iter()
                    .filter(|c| {
                        !r.free[c.index()]
                            && r.get(**c).is_finite()
                            && (**c != Column::Mu || r.mu.is_some())
                    })
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
            let mut free = [true; 4];
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
                mu: r.mu,
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
    use super::*;

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

    #[test]
    fn su_text_parses_and_prints() {
        let text = "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf";
        let m = PrbMatrix::parse(text).unwrap();
        assert_eq!(m.topology(), "L-R-R-R");
        assert_eq!(m.to_text(), text);
        assert_eq!(m.revolute_count(), 3);
    }

    /// A number too large for a double is refused, not read as `inf` (a rigid segment):
    /// in the text form and in a model file's string cells alike.
    #[test]
    fn an_overflowing_number_is_not_inf() {
        let err = PrbMatrix::parse("0.25,inf,inf; 0.25,1e400,inf; 0.5,2,inf").unwrap_err();
        assert_eq!(
            err.to_string(),
            "row 2, column k_theta: `1e400` is neither a finite number nor inf"
        );
        assert!(PrbMatrix::parse("0.25,inf,inf; 0.25,-1e999,inf; 0.5,2,inf").is_err());
        let json = r#"[{"gamma":0.5,"k_theta":"inf","k_ex":"inf"},
                       {"gamma":0.5,"k_theta":"1e400","k_ex":"inf"}]"#;
        let err = serde_json::from_str::<PrbMatrix>(json)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("row 2: `1e400` is neither a finite number nor inf"),
            "{err}"
        );
        // Extreme cells print bounded and read back to the same bits.
        let tiny = PrbMatrix::parse("0.1,inf,inf; 0.9,1e-300,inf").unwrap();
        assert_eq!(tiny.to_text(), "0.1,inf,inf; 0.9,1e-300,inf");
        let big = PrbMatrix::parse("0.1,inf,inf; 0.9,1.2345e11!,inf").unwrap();
        assert_eq!(big.to_text(), "0.1,inf,inf; 0.9,123450000000!,inf");
        assert_eq!(PrbMatrix::parse(&big.to_text()).unwrap(), big);
        // `inf` itself, written any way the text form allows, stays infinite.
        let m = PrbMatrix::parse("0.25,+Infinity,inf; 0.75,2,INF").unwrap();
        assert_eq!(m.rows()[0].k_theta, f64::INFINITY);
        assert_eq!(m.rows()[1].k_ex, f64::INFINITY);
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
    fn mu_column_round_trips_in_text_and_json() {
        let text = "0.1,inf,inf,0.2!; 0.35,3.51,inf,0.3; 0.4,2.99,inf,0.4; 0.15,2.58,inf,0.1";
        let m = PrbMatrix::parse(text).unwrap();
        assert!(m.has_mu() && !m.rows()[0].is_free(Column::Mu));
        assert_eq!(m.to_text(), text);
        let json = serde_json::to_string(&m).unwrap();
        assert!(
            json.contains("\"mu\":0.2") && json.contains("\"fixed\":[\"mu\"]"),
            "{json}"
        );
        assert_eq!(serde_json::from_str::<PrbMatrix>(&json).unwrap(), m);
        // Three columns stay three: no mu in text or JSON.
        let su =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
        assert!(!serde_json::to_string(&su).unwrap().contains("mu"));
        assert_eq!(su.to_text().matches(',').count(), 8);
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
