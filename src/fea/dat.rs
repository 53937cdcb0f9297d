//! Reading CalculiX's `.dat` output: the tip's displacement and rotation at the end of each
//! step.
//!
//! The deck asks for `*NODE PRINT` of the reference node (`U`: the tip's displacement) and of
//! the rigid body's rotation node (`U`: its rotation vector, whose z component is the planar
//! tip rotation; it is not wrapped at pi, measured through a full loop). CalculiX prints a
//! block per increment, headed
//!
//! ```text
//!  displacements (vx,vy,vz) for set NREF and time  0.1000000E+01
//! ```
//!
//! with the *total* time, and every step lasts 1, so step `k` ends at time `k`. A step whose
//! end is missing did not converge.

use super::deck::{REF_SET, ROT_SET};

/// What the end of one step left: the tip's displacement `(ux, uy)` (m) and rotation (rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepEnd {
    /// Displacement of the tip's reference point, m.
    pub ux: f64,
    /// m
    pub uy: f64,
    /// Rotation of the tip section about z, rad.
    pub theta: f64,
}

/// A `.dat` file that does not say what a finished run says.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DatError {
    /// A line of a displacement block that is not `node ux uy uz`.
    #[error("line {line}: expected `node ux uy uz` in a displacement block, got `{text}`")]
    BadRow {
        /// 1-based line of the `.dat` file.
        line: usize,
        /// The line (shortened).
        text: String,
    },
    /// A block header whose time is not a number.
    #[error("line {line}: the block header has no time: `{text}`")]
    BadHeader {
        /// 1-based line.
        line: usize,
        /// The line (shortened).
        text: String,
    },
    /// The output stops before the end of step `step` (1-based).
    #[error("no result for the end of step {step} (of {steps}): the analysis stopped before it")]
    MissingStep {
        /// The first step without a result.
        step: usize,
        /// Steps asked for.
        steps: usize,
    },
}

/// One printed block: what it prints (`U` or `RF`), its set, total time and the first
/// node's three values.
struct Block {
    /// Displacements (`true`) or forces.
    displacement: bool,
    set: String,
    time: f64,
    u: Option<[f64; 3]>,
}

fn shorten(s: &str) -> String {
    s.chars().take(80).collect()
}

fn blocks(text: &str) -> Result<Vec<Block>, DatError> {
    const HEAD: &str = "displacements (vx,vy,vz) for set ";
    const FORCES: &str = "forces (fx,fy,fz) for set ";
    let mut out: Vec<Block> = Vec::new();
    let mut in_block = false;
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        let header = line
            .strip_prefix(HEAD)
            .map(|r| (true, r))
            .or_else(|| line.strip_prefix(FORCES).map(|r| (false, r)));
        if let Some((displacement, rest)) = header {
            let bad = || DatError::BadHeader {
                line: n + 1,
                text: shorten(line),
            };
            let (set, time) = rest.split_once(" and time").ok_or_else(bad)?;
            let time: f64 = time.trim().parse().map_err(|_| bad())?;
            if !time.is_finite() {
                return Err(bad());
            }
            out.push(Block {
                displacement,
                set: set.trim().to_string(),
                time,
                u: None,
            });
            in_block = true;
            continue;
        }
        // Any other header (a block this parser does not read) ends the displacement block.
        if line.chars().next().is_some_and(|c| c.is_ascii_alphabetic()) {
            in_block = false;
            continue;
        }
        if !in_block {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let parsed: Option<[f64; 3]> = (fields.len() == 4 && fields[0].parse::<u64>().is_ok())
            .then(|| {
                let v: Vec<f64> = fields[1..].iter().filter_map(|f| f.parse().ok()).collect();
                (v.len() == 3 && v.iter().all(|x| x.is_finite())).then(|| [v[0], v[1], v[2]])
            })
            .flatten();
        let Some(u) = parsed else {
            return Err(DatError::BadRow {
                line: n + 1,
                text: shorten(line),
            });
        };
        if let Some(b) = out.last_mut() {
            b.u.get_or_insert(u);
        }
    }
    Ok(out)
}

/// The values printed for `set` at total time `time` (the last such block): displacements
/// or forces.
fn value_at(blocks: &[Block], displacement: bool, set: &str, time: f64) -> Option<[f64; 3]> {
    blocks
        .iter()
        .rev()
        .find(|b| {
            b.displacement == displacement
                && b.set.eq_ignore_ascii_case(set)
                && (b.time - time).abs() <= 1e-6 * time
        })
        .and_then(|b| b.u)
}

/// The tip at the end of each of `steps` steps, from the text of a `.dat` file.
pub fn step_ends(text: &str, steps: usize) -> Result<Vec<StepEnd>, DatError> {
    let blocks = blocks(text)?;
    let at = |set: &str, time: f64| value_at(&blocks, true, set, time);
    (1..=steps)
        .map(|k| {
            let time = k as f64;
            match (at(REF_SET, time), at(ROT_SET, time)) {
                (Some(u), Some(r)) => Ok(StepEnd {
                    ux: u[0],
                    uy: u[1],
                    theta: r[2],
                }),
                _ => Err(DatError::MissingStep { step: k, steps }),
            }
        })
        .collect()
}

/// What the end of one step of a mechanism left at the stage: its reference node's and
/// rotation node's displacements and reactions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageEnd {
    /// `[ux, uy, rotation]` of the stage point, m and rad.
    pub pose: [f64; 3],
    /// `[Fx, Fy, Mz]` printed as reactions at the stage point (N, N m): the load the
    /// boundary conditions put on the stage where a coordinate is prescribed, the applied
    /// load where it is loaded.
    pub reaction: [f64; 3],
}

/// The stage at the end of each of `steps` steps, from the text of a `.dat` file that
/// prints `U` and `RF` of the sets `reference` (the stage point) and `rotation` (its
/// rotation node).
pub fn stage_ends(
    text: &str,
    steps: usize,
    reference: &str,
    rotation: &str,
) -> Result<Vec<StageEnd>, DatError> {
    let blocks = blocks(text)?;
    (1..=steps)
        .map(|k| {
            let time = k as f64;
            let u = value_at(&blocks, true, reference, time);
            let r = value_at(&blocks, true, rotation, time);
            let fu = value_at(&blocks, false, reference, time);
            let fr = value_at(&blocks, false, rotation, time);
            match (u, r, fu, fr) {
                (Some(u), Some(r), Some(fu), Some(fr)) => Ok(StageEnd {
                    pose: [u[0], u[1], r[2]],
                    reaction: [fu[0], fu[1], fr[2]],
                }),
                _ => Err(DatError::MissingStep { step: k, steps }),
            }
        })
        .collect()
}

/// How many steps of `steps` have a complete result for `set`'s displacement: the steps
/// that converged before an analysis stopped.
pub fn finished_steps(text: &str, steps: usize, set: &str) -> usize {
    let Ok(blocks) = blocks(text) else {
        return 0;
    };
    (1..=steps)
        .take_while(|&k| value_at(&blocks, true, set, k as f64).is_some())
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_STEPS: &str = "
 displacements (vx,vy,vz) for set NREF and time  0.5000000E+00

        57 -1.000000E-06  2.000000E-04  0.000000E+00

 displacements (vx,vy,vz) for set NROT and time  0.5000000E+00

        58  0.000000E+00  0.000000E+00  1.000000E-02

 displacements (vx,vy,vz) for set NREF and time  0.1000000E+01

        57 -4.000000E-06  4.000000E-04  0.000000E+00

 displacements (vx,vy,vz) for set NROT and time  0.1000000E+01

        58  0.000000E+00  0.000000E+00  2.000000E-02

 displacements (vx,vy,vz) for set NREF and time  0.2000000E+01

        57 -1.600000E-05  8.000000E-04  0.000000E+00

 displacements (vx,vy,vz) for set NROT and time  0.2000000E+01

        58  0.000000E+00  0.000000E+00  4.000000E-02
";

    #[test]
    fn the_end_of_each_step_is_read() {
        let ends = step_ends(TWO_STEPS, 2).unwrap();
        assert_eq!(ends.len(), 2);
        assert_eq!(ends[0].uy, 4e-4);
        assert_eq!(ends[0].theta, 2e-2);
        assert_eq!(ends[1].ux, -1.6e-5);
        assert_eq!(ends[1].theta, 4e-2);
    }

    #[test]
    fn a_missing_step_is_an_error() {
        assert_eq!(
            step_ends(TWO_STEPS, 3),
            Err(DatError::MissingStep { step: 3, steps: 3 })
        );
        assert_eq!(
            step_ends("", 1),
            Err(DatError::MissingStep { step: 1, steps: 1 })
        );
    }

    #[test]
    fn malformed_output_names_its_line() {
        let bad = TWO_STEPS.replace("4.000000E-04", "4.0000x0E-04");
        match step_ends(&bad, 2) {
            Err(DatError::BadRow { line, text }) => {
                assert_eq!(line, 12);
                assert!(text.contains("4.0000x0E-04"), "{text}");
            }
            other => panic!("{other:?}"),
        }
        let bad = TWO_STEPS.replace("time  0.1000000E+01", "time  soon");
        assert!(matches!(
            step_ends(&bad, 2),
            Err(DatError::BadHeader { line: 10, .. })
        ));
        let nan = TWO_STEPS.replace("2.000000E-02", "NaN");
        assert!(matches!(step_ends(&nan, 2), Err(DatError::BadRow { .. })));
    }
}
