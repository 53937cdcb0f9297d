//! The PRB matrix `Omega` (DESIGN §3, §10): one row per rigid segment, root first, columns
//! `[gamma, k_theta, k_ex, mu]`.
//!
//! - `gamma`: the segment's nominal length as a fraction of L (the gammas sum to 1);
//! - `k_theta`: torsion spring at the segment's root end, `K_theta = k_theta E I0 / L`, or
//!   `inf` for no joint there;
//! - `k_ex`: extension spring along the segment, `K_ex = k_ex E A0 / L`, or `inf` for a fixed
//!   length;
//! - `mu`: the segment's mass as a fraction of the beam's `rho A0 L` (DESIGN §10), its centre
//!   of mass at the segment's middle. The column is optional: a matrix written with three
//!   columns has `mu_i = gamma_i` (the beam's mass where its length is) and keeps it through
//!   every gamma edit and fit, so every three-column file and command keeps its meaning.
//!   Either every row gives a mu or none does; given mus are finite, `>= 0` and sum to 1.
//!
//! The matrix's text form, its TOML/JSON form and topology names are in `notation.rs`.

use std::fmt;

use crate::text::bounded;

/// How far the gammas' sum may stray from 1 (round-off in a typed matrix, not rounding of
/// published values, which must be converted explicitly).
pub const GAMMA_SUM_TOL: f64 = 1e-9;

/// The stiffest finite spring a matrix may hold, in units of `E I0 / L` (`E A0 / L`). A
/// spring this stiff moves its joint by 1e-12 of the load: it is rigid, and `inf` says so
/// exactly, where a spring of 1e308 would only make the statics ill-conditioned (and, before
/// this limit, was reported as a buckling point).
pub const MAX_SPRING: f64 = 1e12;

/// The most segments a PRB matrix may have. A PRB model is a few rigid links (the published
/// ones have two to four segments, the selection ladder at most five); the fit's parameters
/// grow with every segment (a 16-segment 15R fits in about 1.6 s, release build), so a matrix
/// of hundreds would fit for minutes: refused at once instead.
pub const MAX_SEGMENTS: usize = 32;

/// How far the mus' sum may stray from 1 (as [`GAMMA_SUM_TOL`]).
pub const MU_SUM_TOL: f64 = GAMMA_SUM_TOL;

/// The four columns of a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Column {
    /// `gamma`: the segment's nominal length as a fraction of L.
    Gamma,
    /// `k_theta`: the torsion spring at the segment's root end, in units of `E I0 / L`.
    KTheta,
    /// `k_ex`: the extension spring along the segment, in units of `E A0 / L`.
    KEx,
    /// `mu`: the segment's mass as a fraction of the beam's `rho A0 L` (DESIGN §10).
    Mu,
}

impl Column {
    /// The four columns in matrix order: gamma, k_theta, k_ex, mu.
    pub const ALL: [Column; 4] = [Column::Gamma, Column::KTheta, Column::KEx, Column::Mu];

    /// The statics' three columns (a three-column matrix's): gamma, k_theta, k_ex.
    pub const STATICS: [Column; 3] = [Column::Gamma, Column::KTheta, Column::KEx];

    /// The column's 0-based position in a row (gamma 0, k_theta 1, k_ex 2, mu 3), also the
    /// index into [`PrbRow::free`].
    pub fn index(self) -> usize {
        match self {
            Column::Gamma => 0,
            Column::KTheta => 1,
            Column::KEx => 2,
            Column::Mu => 3,
        }
    }

    /// The column's name as the text form, files and messages spell it (`gamma`,
    /// `k_theta`, `k_ex`, `mu`).
    pub fn name(self) -> &'static str {
        match self {
            Column::Gamma => "gamma",
            Column::KTheta => "k_theta",
            Column::KEx => "k_ex",
            Column::Mu => "mu",
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
    /// The segment's mass as a fraction of the beam's `rho A0 L`; `None` (a three-column
    /// matrix): `gamma`, whatever the gamma becomes ([`PrbRow::mass`]).
    pub mu: Option<f64>,
    /// Per cell (gamma, k_theta, k_ex, mu): may the fit change it? `inf` cells never are.
    pub free: [bool; 4],
}

impl PrbRow {
    /// A row of the statics' three columns, every cell free, its mass where its length is.
    pub fn new(gamma: f64, k_theta: f64, k_ex: f64) -> PrbRow {
        PrbRow {
            gamma,
            k_theta,
            k_ex,
            mu: None,
            free: [true; 4],
        }
    }

    /// The value in `column` (gamma as a fraction of L, k_theta in `E I0 / L`, k_ex in
    /// `E A0 / L`, mu as a fraction of `rho A0 L`: [`PrbRow::mass`]).
    pub fn get(&self, column: Column) -> f64 {
        match column {
            Column::Gamma => self.gamma,
            Column::KTheta => self.k_theta,
            Column::KEx => self.k_ex,
            Column::Mu => self.mass(),
        }
    }

    /// Overwrites the value in `column` (a mu becomes explicit), unchecked: the owning
    /// [`PrbMatrix`] validates.
    pub fn set(&mut self, column: Column, value: f64) {
        match column {
            Column::Gamma => self.gamma = value,
            Column::KTheta => self.k_theta = value,
            Column::KEx => self.k_ex = value,
            Column::Mu => self.mu = Some(value),
        }
    }

    /// The segment's mass as a fraction of the beam's `rho A0 L`: its mu, or its gamma in a
    /// three-column matrix.
    pub fn mass(&self) -> f64 {
        self.mu.unwrap_or(self.gamma)
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
    pub(super) rows: Vec<PrbRow>,
}

/// A sum as an error quotes it: every digit that tells it from 1 (Rust's shortest form,
/// `0.8999999999999999`) where that is short, bounded (`1e308`, `1e-300`) where it is not.
fn shortest_bounded(sum: f64) -> String {
    if (1e-4..1e6).contains(&sum.abs()) {
        sum.to_string()
    } else {
        bounded(sum)
    }
}

/// What is wrong with a matrix; rows and columns are 1-based, as a user counts them.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MatrixError {
    /// The matrix has no rows (an empty list or empty text).
    #[error("the matrix has no rows")]
    Empty,
    /// More rows than [`MAX_SEGMENTS`].
    #[error("the matrix has {got} segments, more than the {MAX_SEGMENTS} a PRB matrix may have")]
    TooManySegments {
        /// How many rows it has.
        got: usize,
    },
    /// A row of the text form does not have three or four entries.
    #[error("row {row}: expected 3 entries (gamma, k_theta, k_ex) or 4 (gamma, k_theta, k_ex, mu), got {got}")]
    RowLength {
        /// 1-based row of the text.
        row: usize,
        /// How many entries the row had (0 for an empty row).
        got: usize,
    },
    /// An entry of the text form is neither a finite number nor `inf`.
    #[error("row {row}, column {column}: `{text}` is neither a finite number nor inf")]
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
    /// Some rows give a mu and others do not.
    #[error("row {row}: every row gives a mu (a fourth entry) or none does; row 1 has {first} entries, row {row} has {got}")]
    MixedMu {
        /// 1-based: the first row that differs from row 1.
        row: usize,
        /// Entries of row 1.
        first: usize,
        /// Entries of that row.
        got: usize,
    },
    /// A mass fraction is not a finite number >= 0.
    #[error(
        "row {row}, column mu: the segment's mass fraction must be a finite number >= 0, got {}",
        bounded(*value)
    )]
    Mu {
        /// 1-based row.
        row: usize,
        /// The rejected mu (fraction of `rho A0 L`).
        value: f64,
    },
    /// The mus do not sum to 1 within [`MU_SUM_TOL`].
    #[error(
        "the mus must sum to 1, they sum to {} (off by {:.3e})",
        shortest_bounded(*sum),
        sum - 1.0
    )]
    MuSum {
        /// The sum of the mus found.
        sum: f64,
    },
    /// The gammas do not sum to 1 within [`GAMMA_SUM_TOL`].
    #[error(
        "the gammas must sum to 1, they sum to {} (off by {:.3e})",
        shortest_bounded(*sum),
        sum - 1.0
    )]
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
    #[error(
        "segment {donor} takes up the difference (the column sums to 1), and would break its \
         rule: {source}"
    )]
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
            for c in Column::STATICS {
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
        if self.rows.len() > MAX_SEGMENTS {
            return Err(MatrixError::TooManySegments {
                got: self.rows.len(),
            });
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
        let explicit = self.rows[0].mu.is_some();
        for (i, r) in self.rows.iter().enumerate() {
            match r.mu {
                Some(_) if !explicit => {
                    return Err(MatrixError::MixedMu {
                        row: i + 1,
                        first: 3,
                        got: 4,
                    })
                }
                None if explicit => {
                    return Err(MatrixError::MixedMu {
                        row: i + 1,
                        first: 4,
                        got: 3,
                    })
                }
                Some(value) if !(value.is_finite() && value >= 0.0) => {
                    return Err(MatrixError::Mu { row: i + 1, value })
                }
                _ => {}
            }
        }
        if explicit {
            let sum: f64 = self.rows.iter().map(PrbRow::mass).sum();
            if (sum - 1.0).abs() > MU_SUM_TOL {
                return Err(MatrixError::MuSum { sum });
            }
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

    /// Sets one cell and validates; on error the matrix is unchanged. A mu edit is
    /// [`PrbMatrix::with_mu`] (the mus keep summing to 1).
    pub fn with_cell(
        &self,
        row: usize,
        column: Column,
        value: f64,
    ) -> Result<PrbMatrix, MatrixError> {
        if column == Column::Mu {
            return self.with_mu(row, value);
        }
        let mut rows = self.rows.clone();
        rows[row].set(column, value);
        PrbMatrix::new(rows)
    }

    /// Whether the matrix gives its mus (a fourth column); otherwise each mu is its gamma.
    pub fn has_mu(&self) -> bool {
        self.rows.first().is_some_and(|r| r.mu.is_some())
    }

    /// The same matrix with its mus written out (`mu_i = gamma_i` where it had none): what an
    /// edit or a fit of the masses starts from.
    pub fn with_explicit_mu(&self) -> PrbMatrix {
        let mut m = self.clone();
        for r in &mut m.rows {
            r.mu = Some(r.mass());
        }
        m
    }

    /// Sets segment `row`'s mu (0-based) and keeps the mus summing to 1, the way
    /// [`PrbMatrix::with_gamma`] keeps the gammas: one other segment, a free one after `row`
    /// by preference, takes the difference. A three-column matrix gets its mus written out
    /// first. On error the matrix is unchanged and the error names the donor.
    pub fn with_mu(&self, row: usize, mu: f64) -> Result<PrbMatrix, MatrixError> {
        let rows = &self.with_explicit_mu().rows;
        if row >= rows.len() {
            return Err(MatrixError::NoRow {
                row: row + 1,
                rows: rows.len(),
            });
        }
        let mut new_rows = rows.clone();
        new_rows[row].mu = Some(mu);
        if rows.len() == 1 {
            return PrbMatrix::new(new_rows);
        }
        let delta = mu - rows[row].mass();
        let donor = (0..rows.len())
            .filter(|&i| i != row)
            .max_by_key(|&i| (rows[i].is_free(Column::Mu), i > row, i))
            .ok_or(MatrixError::SingleSegmentGamma)?;
        new_rows[donor].mu = Some(rows[donor].mass() - delta);
        PrbMatrix::new(new_rows).map_err(|e| MatrixError::Rebalance {
            donor: donor + 1,
            source: Box::new(e),
        })
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

    /// Marks a cell free (the fit may change it) or fixed; marking a mu of a three-column
    /// matrix writes its mus out first ([`PrbMatrix::with_explicit_mu`]), so the mark shows.
    pub fn set_free(&mut self, row: usize, column: Column, free: bool) {
        if column == Column::Mu && !self.has_mu() {
            *self = self.with_explicit_mu();
        }
        self.rows[row].free[column.index()] = free;
    }

    /// Number of revolute joints.
    pub fn revolute_count(&self) -> usize {
        self.rows.iter().filter(|r| r.has_revolute()).count()
    }

    /// Number of prismatic joints.
    pub fn prismatic_count(&self) -> usize {
        self.rows.iter().filter(|r| r.has_prismatic()).count()
    }
}

#[cfg(test)]
mod tests {
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
        assert!(
            err.starts_with("segment 3 takes up the difference"),
            "{err}"
        );
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
    fn mus_are_gammas_unless_given_and_sum_to_one() {
        let three = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
        assert!(!three.has_mu());
        assert_eq!(three.rows()[1].mass(), 0.85);
        // A gamma edit carries an implicit mu along.
        let moved = three.with_gamma(1, 0.8).unwrap();
        assert_eq!(moved.rows()[1].mass(), 0.8);
        // A mu edit writes every mu out and rebalances one donor.
        let parked = three.with_mu(0, 0.3).unwrap();
        assert!(parked.has_mu());
        let mus: Vec<f64> = parked.rows().iter().map(PrbRow::mass).collect();
        assert!(
            (mus[0] - 0.3).abs() < 1e-15 && (mus[1] - 0.7).abs() < 1e-15,
            "{mus:?}"
        );
        assert_eq!(parked.rows()[1].gamma, 0.85, "gammas stay");
        let e = three.with_mu(0, 1.5).unwrap_err().to_string();
        assert!(
            e.contains("mass fraction must be a finite number >= 0"),
            "{e}"
        );
        assert!(e.starts_with("segment 2 takes up the difference"), "{e}");
        assert!(matches!(
            PrbMatrix::parse("0.15,inf,inf,0.2; 0.85,2.2525,inf,0.7"),
            Err(MatrixError::MuSum { .. })
        ));
        assert!(matches!(
            PrbMatrix::parse("0.15,inf,inf,-0.1; 0.85,2.2525,inf,1.1"),
            Err(MatrixError::Mu { row: 1, .. })
        ));
        assert!(matches!(
            PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf,1"),
            Err(MatrixError::MixedMu { row: 2, .. })
        ));
        assert!(PrbMatrix::parse("0.15,inf,inf,nan; 0.85,2.2525,inf,1").is_err());
    }
}
