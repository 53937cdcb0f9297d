//! Mechanism scenes (DESIGN §8): one or more flexures between the ground and one rigid stage,
//! each stage coordinate prescribed (displacement control) or loaded, flexure tips clamped,
//! pinned or joined to the stage by a rigid coupler; the rules a flexure and a mechanism
//! obey ([`Flexure::validate`], [`Mechanism::validate`]) and the edits that carry what a
//! designer expects along ([`Mechanism::with_stage_point`], [`Mechanism::rebased`]).
//!
//! Everything here is SI, as the scene file gives it; [`Mechanism::nondimensional`] converts
//! with flexure 1's `L` and `E I0` (the scale the mechanism's errors and loads are reported
//! in, DESIGN §8), so the solvers work in the same units as the single beam. The drive paths
//! are in [`super::drive`].

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use super::beam::BeamSpec;
use super::drive::{Coordinate, Drive, DrivePath, COORDINATE_KEYS};
use super::error::RuleError;
use super::rules;

/// How a flexure's tip is joined to the stage.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Attach {
    /// Bolted: the tip turns with the stage (3 compatibility equations).
    Clamped,
    /// A frictionless pin at the unloaded tip: the tip moment is zero (2 equations).
    Pinned,
    /// A rigid coupler pinned at both ends, from the tip to `to` on the stage (m): the tip
    /// force acts along the coupler and the tip moment is zero.
    Link {
        /// The coupler's stage end, m, in the unloaded pose.
        to: [f64; 2],
    },
}

/// One flexure: a §2 beam clamped to the ground at `root`, pointing along `angle` unloaded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Flexure {
    /// The clamp, m.
    pub root: [f64; 2],
    /// Direction of the unloaded flexure, radians from +x.
    pub angle: f64,
    /// How its tip meets the stage.
    pub attach: Attach,
    /// Its beam: the scene's `[beam]` with this flexure's overrides.
    pub beam: BeamSpec,
}

impl Flexure {
    /// The unloaded tip, m.
    pub fn tip(&self) -> [f64; 2] {
        let (s, c) = self.angle.sin_cos();
        [
            self.root[0] + self.beam.length * c,
            self.root[1] + self.beam.length * s,
        ]
    }

    /// Its beam model in the mechanism: the beam's ([`BeamSpec::model`]), whose plane-strain
    /// plate fraction is the guided flexure's when the tip is clamped to the stage (held flat
    /// at both ends, [`crate::beam::plate::guided_ends_fraction`]) and the cantilever's ends'
    /// when it is pinned or coupled (the tip free to turn, its moment zero: the bending
    /// peaks at the clamp alone, as a cantilever's under a tip force).
    pub fn model(&self) -> crate::beam::BeamModel {
        let model = self.beam.model();
        match self.attach {
            Attach::Clamped => model.with_guided_width_ratio(self.beam.width / self.beam.thickness),
            Attach::Pinned | Attach::Link { .. } => model,
        }
    }

    /// Checks the flexure's rules: a finite `root`, `angle_deg` within a turn, its beam's rules
    /// ([`BeamSpec::validate`]: its overrides are keys of the flexure's own table) and a
    /// finite coupler end (`link_to`). A scene puts the keys under `flexures[i]`.
    pub fn validate(&self) -> Result<(), RuleError> {
        rules::point(self.root).map_err(|m| RuleError::new("root", m))?;
        rules::direction(self.angle).map_err(|m| RuleError::new("angle_deg", m))?;
        self.beam.validate()?;
        if let Attach::Link { to } = self.attach {
            rules::point(to).map_err(|m| RuleError::new("link_to", m))?;
        }
        Ok(())
    }
}

/// A mechanism, SI: valid when [`Mechanism::validate`] says so, as every mechanism a scene
/// file gives and every edit the UI takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mechanism {
    /// In order; flexure 1 sets the scale.
    pub flexures: Vec<Flexure>,
    /// The stage's reference point P, m: where loads act and motion is measured.
    pub stage_point: [f64; 2],
    /// The drive paths.
    pub drives: Vec<Drive>,
}

impl Mechanism {
    /// The scale of the mechanism: flexure 1's `(L, E I0)`.
    pub fn scale(&self) -> (f64, f64) {
        let b = self.flexures.first().map(|f| f.beam);
        b.map_or((1.0, 1.0), |b| {
            (b.length, b.youngs_modulus * b.second_moment())
        })
    }

    /// A drive's end values nondimensional: displacements in units of flexure 1's `L`,
    /// rotations in radians, forces as `alpha = F L^2 / (E I0)`, moments as
    /// `beta = M L / (E I0)` (flexure 1's `L`, `E I0`).
    pub fn nondimensional(&self, drive: &Drive) -> [Coordinate; 3] {
        let factors = self.factors(drive.coordinates);
        std::array::from_fn(|c| match drive.coordinates[c] {
            Coordinate::Prescribed(v) => Coordinate::Prescribed(v * factors[c]),
            Coordinate::Loaded(v) => Coordinate::Loaded(v * factors[c]),
        })
    }

    /// What one SI unit of each coordinate, of the kinds of `kinds`, is nondimensional
    /// (flexure 1's `L`, `E I0`): `1 / L` for a displacement, 1 for a rotation,
    /// `L^2 / (E I0)` for a force, `L / (E I0)` for a moment.
    pub fn factors(&self, kinds: [Coordinate; 3]) -> [f64; 3] {
        let (l, ei) = self.scale();
        let scale = [(1.0 / l, l * l / ei), (1.0 / l, l * l / ei), (1.0, l / ei)];
        std::array::from_fn(|c| {
            if kinds[c].is_prescribed() {
                scale[c].0
            } else {
                scale[c].1
            }
        })
    }

    /// A drive path as the solvers follow it, nondimensional: proportional, or through a
    /// measured path's rows.
    pub fn drive_path(&self, drive: &Drive) -> DrivePath {
        let factors = self.factors(drive.coordinates);
        DrivePath {
            end: self.nondimensional(drive),
            steps: drive.steps.max(1),
            rows: drive
                .rows
                .iter()
                .map(|r| std::array::from_fn(|c| r[c] * factors[c]))
                .collect(),
        }
    }

    /// Load cases in all.
    pub fn case_count(&self) -> u64 {
        self.drives.iter().map(|d| u64::from(d.steps)).sum()
    }

    /// Checks the mechanism's rules, keyed as a scene file writes them: each flexure's
    /// ([`Flexure::validate`], under `flexures[i]`), a finite `stage.point`, no coupler of
    /// zero length (its stage end on its flexure's unloaded tip: `flexures[i].link_to`), no
    /// two flexures from one root along one line (`flexures[i]`), each drive's
    /// ([`Drive::validate`], under `drives[i]`), at least one drive and at most
    /// [`MAX_CASES`](super::MAX_CASES) cases over them (`drives`).
    pub fn validate(&self) -> Result<(), RuleError> {
        self.validate_measured()?;
        if self.drives.is_empty() {
            return Err(RuleError::new(
                "drives",
                "a mechanism scene needs at least one [[drives]] table (the drive path: \
                 dx/fx, dy/fy, dphi/mz, steps)",
            ));
        }
        rules::case_count(self.drives.iter().map(|d| d.steps), "drive paths")
            .map_err(|m| RuleError::new("drives", m))
    }

    /// The rules of a mechanism whose drive paths are a data file's rows (DESIGN §9), which
    /// that file's reader checks: [`Mechanism::validate`] but for the number of drives and
    /// cases (a scene read from text has no rows yet).
    pub fn validate_measured(&self) -> Result<(), RuleError> {
        for (i, f) in self.flexures.iter().enumerate() {
            f.validate().map_err(|e| e.under(&flexure_key(i)))?;
        }
        rules::point(self.stage_point).map_err(|m| RuleError::new("stage.point", m))?;
        self.within_reach()?;
        let scale = self.flexures.first().map_or(1.0, |f| f.beam.length);
        // A zero-length coupler is no coupler.
        for (i, f) in self.flexures.iter().enumerate() {
            if let Attach::Link { to } = f.attach {
                if dist(f.tip(), to) <= COINCIDENT * scale {
                    return Err(RuleError::new(
                        format!("{}.link_to", flexure_key(i)),
                        format!(
                            "the coupler would have zero length: its stage end {to:?} is the \
                             flexure's unloaded tip; use attach = \"pinned\" for a pin there"
                        ),
                    ));
                }
            }
        }
        // Two flexures on the same line from the same root overlap: one beam, counted twice.
        for (i, a) in self.flexures.iter().enumerate() {
            for (j, b) in self.flexures.iter().enumerate().take(i) {
                let same_root = dist(a.root, b.root) <= COINCIDENT * scale;
                let same_dir = (a.angle - b.angle)
                    .rem_euclid(TAU)
                    .min((b.angle - a.angle).rem_euclid(TAU))
                    < 1e-9;
                if same_root && same_dir {
                    return Err(RuleError::new(
                        flexure_key(i),
                        format!(
                            "starts where flexure {} starts and points the same way: the two \
                             would overlap",
                            j + 1
                        ),
                    ));
                }
            }
        }
        for (i, d) in self.drives.iter().enumerate() {
            let under = |e: RuleError| e.under(&format!("drives[{}]", i + 1));
            d.validate().map_err(under)?;
            if d.rows.is_empty() {
                let scaled = self.nondimensional(d);
                for ((c, n), (dk, lk)) in d.coordinates.iter().zip(scaled).zip(COORDINATE_KEYS) {
                    let key = if c.is_prescribed() { dk } else { lk };
                    rules::reachable(c.value(), n.value())
                        .map_err(|m| under(RuleError::new(key, m)))?;
                }
            }
        }
        Ok(())
    }

    /// Every point of the mechanism (roots, coupler ends, the stage point) within
    /// [`MAX_SPAN`] lengths of its longest flexure from flexure 1's root: a mechanism larger
    /// than that is a unit slip (a point in millimetres among metres), and one at 1e300 m
    /// breaks every moment arm. Keyed as the file writes the point.
    fn within_reach(&self) -> Result<(), RuleError> {
        let Some(first) = self.flexures.first() else {
            return Ok(());
        };
        let longest = self
            .flexures
            .iter()
            .map(|f| f.beam.length)
            .fold(0.0_f64, f64::max);
        let reach = MAX_SPAN * longest;
        let check = |key: String, p: [f64; 2]| {
            let d = dist(p, first.root);
            if d <= reach {
                return Ok(());
            }
            Err(RuleError::new(
                key,
                format!(
                    "{} m from flexure 1's root, beyond the {MAX_SPAN:e} lengths of the longest \
                     flexure ({} m) a mechanism may span: the scene is in metres",
                    crate::text::bounded(d),
                    crate::text::bounded(longest)
                ),
            ))
        };
        for (i, f) in self.flexures.iter().enumerate() {
            check(format!("{}.root", flexure_key(i)), f.root)?;
            if let Attach::Link { to } = f.attach {
                check(format!("{}.link_to", flexure_key(i)), to)?;
            }
        }
        check("stage.point".into(), self.stage_point)
    }

    /// The mechanism with the stage point at `p`; couplers whose stage end sat on the old
    /// stage point stay on it (an edit: the caller validates the result).
    pub fn with_stage_point(&self, p: [f64; 2]) -> Mechanism {
        let mut out = self.clone();
        let old = self.stage_point;
        for f in &mut out.flexures {
            if let Attach::Link { to } = &mut f.attach {
                if *to == old {
                    *to = p;
                }
            }
        }
        out.stage_point = p;
        out
    }

    /// The mechanism after the scene's beam went from `old` to `new`: every flexure value
    /// that was the scene's (not overridden) follows it, the shear coefficient and the
    /// effects always do (a flexure cannot override them); the stage point follows flexure
    /// 1's unloaded tip when it sat on it, and couplers ending on the stage point follow that
    /// (an edit: the caller validates the result).
    pub fn rebased(&self, old: &BeamSpec, new: &BeamSpec) -> Mechanism {
        let tip_before = self.flexures.first().map(Flexure::tip);
        let mut out = self.clone();
        for f in &mut out.flexures {
            let b = &mut f.beam;
            for (mine, was, now) in [
                (&mut b.length, old.length, new.length),
                (&mut b.width, old.width, new.width),
                (&mut b.thickness, old.thickness, new.thickness),
                (
                    &mut b.youngs_modulus,
                    old.youngs_modulus,
                    new.youngs_modulus,
                ),
                (&mut b.poisson_ratio, old.poisson_ratio, new.poisson_ratio),
            ] {
                if *mine == was {
                    *mine = now;
                }
            }
            b.shear_coefficient = new.shear_coefficient;
            b.effects = new.effects;
            if b.allowable_stress == old.allowable_stress {
                b.allowable_stress = new.allowable_stress;
            }
        }
        match (tip_before, out.flexures.first().map(Flexure::tip)) {
            (Some(before), Some(after)) if before == self.stage_point && before != after => {
                out.with_stage_point(after)
            }
            _ => out,
        }
    }
}

/// Flexure `i`'s (from 0) table as a key: `flexures[i + 1]`.
/// How many lengths of its longest flexure a mechanism may span ([`Mechanism::validate`]).
pub const MAX_SPAN: f64 = 1e4;

fn flexure_key(i: usize) -> String {
    format!("flexures[{}]", i + 1)
}

/// Two points closer than this fraction of flexure 1's length are the same point.
const COINCIDENT: f64 = 1e-9;

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
