//! Mechanism scenes (DESIGN §8): one or more flexures between the ground and one rigid stage,
//! each stage coordinate prescribed (displacement control) or loaded, flexure tips clamped,
//! pinned or joined to the stage by a rigid coupler.
//!
//! Everything here is SI, as the scene file gives it; [`Mechanism::nondimensional`] converts
//! with flexure 1's `L` and `E I0` (the scale the mechanism's errors and loads are reported
//! in, DESIGN §8), so the solvers work in the same units as the single beam.

use std::ops::Range;

use serde::{Deserialize, Serialize};
use toml::Spanned;

use super::{rules, BeamSpec, SceneError, Validator};

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
}

/// A stage coordinate along a drive path: prescribed (a displacement or rotation the drive
/// imposes; the output is the reaction) or loaded (a force or moment; the output is where the
/// stage goes). A coordinate with neither is loaded with zero.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Coordinate {
    /// End value of the displacement (m) or rotation (rad).
    Prescribed(f64),
    /// End value of the force (N) or moment (N m).
    Loaded(f64),
}

impl Coordinate {
    /// Whether the drive imposes this coordinate.
    pub fn is_prescribed(&self) -> bool {
        matches!(self, Coordinate::Prescribed(_))
    }

    /// The end value, whichever kind.
    pub fn value(&self) -> f64 {
        match self {
            Coordinate::Prescribed(v) | Coordinate::Loaded(v) => *v,
        }
    }
}

/// One drive path: every stage coordinate `[x, y, phi]` varied proportionally from the
/// unloaded state, evaluated at `k / steps`; or, a measured path (DESIGN §9), through its
/// rows' values in order, evaluated at each row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Drive {
    /// `x`, `y` (m or N) and `phi` (rad or N m) of the stage point: the end values (a
    /// measured path's last row).
    pub coordinates: [Coordinate; 3],
    /// Cases along the path (a measured path's row count).
    pub steps: u32,
    /// A measured path's rows (SI, each coordinate of the kind `coordinates` gives, in the
    /// data file's order): the path runs straight from the unloaded state to the first row
    /// and from each row to the next, and its cases are the rows. Empty: the proportional
    /// path.
    #[serde(default, skip)]
    pub rows: Vec<[f64; 3]>,
}

impl Drive {
    /// A proportional drive path to `coordinates` in `steps` steps.
    pub fn proportional(coordinates: [Coordinate; 3], steps: u32) -> Drive {
        Drive {
            coordinates,
            steps,
            rows: Vec::new(),
        }
    }
}

/// A drive path as the solvers follow it, nondimensional (see [`Mechanism::nondimensional`]):
/// the stage coordinates' kinds and their values along the path's parameter `lambda` in
/// `[0, 1]`, with the path's cases at `k / steps`.
#[derive(Debug, Clone, PartialEq)]
pub struct DrivePath {
    /// The end values (`lambda = 1`), of the coordinates' kinds.
    pub end: [Coordinate; 3],
    /// Cases along the path.
    pub steps: u32,
    /// A measured path's rows (empty: proportional): row `k` (from 1) is at
    /// `lambda = k / steps`, the values linear in `lambda` between rows and from the
    /// unloaded state to row 1.
    pub rows: Vec<[f64; 3]>,
}

impl DrivePath {
    /// A proportional path to `end` in `steps` steps.
    pub fn proportional(end: [Coordinate; 3], steps: u32) -> DrivePath {
        DrivePath {
            end,
            steps: steps.max(1),
            rows: Vec::new(),
        }
    }

    /// The path's first `k` cases as a path of their own (`k` from 1 to `steps`): the same
    /// cases, at fractions `k / steps` of this one's parameter scaled by `steps / k`.
    pub fn first(&self, k: u32) -> DrivePath {
        let k = k.clamp(1, self.steps.max(1));
        if self.rows.is_empty() {
            let part = f64::from(k) / f64::from(self.steps.max(1));
            return DrivePath {
                end: self.end.map(|c| match c {
                    Coordinate::Prescribed(v) => Coordinate::Prescribed(v * part),
                    Coordinate::Loaded(v) => Coordinate::Loaded(v * part),
                }),
                steps: k,
                rows: Vec::new(),
            };
        }
        let rows: Vec<[f64; 3]> = self.rows.iter().take(k as usize).copied().collect();
        let last = rows.last().copied().unwrap_or([0.0; 3]);
        DrivePath {
            end: std::array::from_fn(|c| match self.end[c] {
                Coordinate::Prescribed(_) => Coordinate::Prescribed(last[c]),
                Coordinate::Loaded(_) => Coordinate::Loaded(last[c]),
            }),
            steps: k,
            rows,
        }
    }

    /// The coordinates at `lambda` (clamped to `[0, 1]`).
    pub fn at(&self, lambda: f64) -> [Coordinate; 3] {
        let lambda = lambda.clamp(0.0, 1.0);
        let values: [f64; 3] = if self.rows.is_empty() {
            self.end.map(|c| lambda * c.value())
        } else {
            let n = self.rows.len();
            let s = lambda * n as f64;
            // Row `k` sits at `s = k`; `s` in `[k - 1, k]` is between row `k - 1` (the
            // unloaded state for k = 1) and row `k`. Snap within rounding of a row onto it.
            let k = (s - 1e-9).ceil().clamp(1.0, n as f64) as usize;
            let t = (s - (k - 1) as f64).clamp(0.0, 1.0);
            let to = self.rows[k - 1];
            let from = if k >= 2 { self.rows[k - 2] } else { [0.0; 3] };
            if (t - 1.0).abs() <= 1e-9 {
                to
            } else {
                std::array::from_fn(|c| from[c] + t * (to[c] - from[c]))
            }
        };
        std::array::from_fn(|c| match self.end[c] {
            Coordinate::Prescribed(_) => Coordinate::Prescribed(values[c]),
            Coordinate::Loaded(_) => Coordinate::Loaded(values[c]),
        })
    }
}

/// A validated mechanism, SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mechanism {
    /// In order; flexure 1 sets the scale.
    pub flexures: Vec<Flexure>,
    /// The stage's reference point P, m: where loads act and motion is measured.
    pub stage_point: [f64; 2],
    /// The drive paths.
    pub drives: Vec<Drive>,
}

/// The names of the stage coordinates as the scene file writes them: displacement, load.
pub const COORDINATE_KEYS: [(&str, &str); 3] = [("dx", "fx"), ("dy", "fy"), ("dphi", "mz")];

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

    /// Writes the mechanism's tables in the scene file's schema (overrides only where a
    /// flexure's beam differs from the scene's).
    pub(super) fn write_toml(&self, scene_beam: &BeamSpec, drives: bool, out: &mut String) {
        use std::fmt::Write as _;
        for f in &self.flexures {
            let _ = write!(
                out,
                "\n[[flexures]]\nroot = [{:?}, {:?}]\nangle_deg = {:?}\n",
                f.root[0],
                f.root[1],
                f.angle.to_degrees()
            );
            match f.attach {
                Attach::Clamped => out.push_str("attach = \"clamped\"\n"),
                Attach::Pinned => out.push_str("attach = \"pinned\"\n"),
                Attach::Link { to } => {
                    let _ = write!(
                        out,
                        "attach = \"link\"\nlink_to = [{:?}, {:?}]\n",
                        to[0], to[1]
                    );
                }
            }
            let b = &f.beam;
            for (name, mine, scene) in [
                ("length", b.length, scene_beam.length),
                ("width", b.width, scene_beam.width),
                ("thickness", b.thickness, scene_beam.thickness),
                (
                    "youngs_modulus",
                    b.youngs_modulus,
                    scene_beam.youngs_modulus,
                ),
                ("poisson_ratio", b.poisson_ratio, scene_beam.poisson_ratio),
            ] {
                if mine != scene {
                    let _ = writeln!(out, "{name} = {mine:?}");
                }
            }
        }
        let _ = write!(
            out,
            "\n[stage]\npoint = [{:?}, {:?}]\n",
            self.stage_point[0], self.stage_point[1]
        );
        for d in self.drives.iter().filter(|_| drives) {
            out.push_str("\n[[drives]]\n");
            for (c, (dk, lk)) in d.coordinates.iter().zip(COORDINATE_KEYS) {
                let _ = match c {
                    Coordinate::Prescribed(v) => writeln!(out, "{dk} = {v:?}"),
                    Coordinate::Loaded(v) => writeln!(out, "{lk} = {v:?}"),
                };
            }
            let _ = writeln!(out, "steps = {}", d.steps);
        }
    }

    /// Load cases in all.
    pub fn case_count(&self) -> u64 {
        self.drives.iter().map(|d| u64::from(d.steps)).sum()
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFlexure {
    root: Option<Spanned<[f64; 2]>>,
    angle_deg: Option<Spanned<f64>>,
    attach: Option<Spanned<String>>,
    link_to: Option<Spanned<[f64; 2]>>,
    length: Option<Spanned<f64>>,
    width: Option<Spanned<f64>>,
    thickness: Option<Spanned<f64>>,
    youngs_modulus: Option<Spanned<f64>>,
    poisson_ratio: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStage {
    point: Option<Spanned<[f64; 2]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDrive {
    dx: Option<Spanned<f64>>,
    dy: Option<Spanned<f64>>,
    dphi: Option<Spanned<f64>>,
    fx: Option<Spanned<f64>>,
    fy: Option<Spanned<f64>>,
    mz: Option<Spanned<f64>>,
    steps: Option<Spanned<i64>>,
}

/// A flexure's optional override of one beam value: the raw value, its key, where it goes,
/// the rule it obeys.
type Override<'a> = (
    &'a Option<Spanned<f64>>,
    &'static str,
    &'a mut f64,
    fn(f64) -> Result<(), String>,
);

/// Two points closer than this fraction of flexure 1's length are the same point.
const COINCIDENT: f64 = 1e-9;

impl Validator<'_> {
    /// The mechanism of a scene with `[[flexures]]`; `beam` is the scene's `[beam]`.
    pub(super) fn mechanism(
        &self,
        beam: &BeamSpec,
        flexures: &[Spanned<RawFlexure>],
        stage: Option<&Spanned<RawStage>>,
        drives: &[Spanned<RawDrive>],
        data: bool,
    ) -> Result<Mechanism, SceneError> {
        let mut out = Vec::with_capacity(flexures.len());
        for (i, raw) in flexures.iter().enumerate() {
            out.push(self.flexure(beam, raw, i + 1)?);
        }
        let scale = out.first().map_or(1.0, |f| f.beam.length);
        let stage_point = match stage.and_then(|s| s.get_ref().point.as_ref()) {
            Some(p) => self.point(p, "stage.point")?,
            None => out.first().map_or([0.0, 0.0], Flexure::tip),
        };
        // Couplers: a zero-length coupler is no coupler.
        for (i, (f, raw)) in out.iter_mut().zip(flexures).enumerate() {
            let tip = f.tip();
            if let Attach::Link { to } = &mut f.attach {
                if raw.get_ref().link_to.is_none() {
                    *to = stage_point;
                }
                if dist(tip, *to) <= COINCIDENT * scale {
                    let span = raw
                        .get_ref()
                        .link_to
                        .as_ref()
                        .map_or(raw.span(), |s| s.span());
                    return Err(self.error(
                        span,
                        &format!("flexures[{}].link_to", i + 1),
                        format!(
                            "the coupler would have zero length: its stage end {:?} is the \
                             flexure's unloaded tip; use attach = \"pinned\" for a pin there",
                            to
                        ),
                    ));
                }
            }
        }
        // Two flexures on the same line from the same root overlap: one beam, counted twice.
        for i in 0..out.len() {
            for j in 0..i {
                let (a, b) = (&out[i], &out[j]);
                let same_root = dist(a.root, b.root) <= COINCIDENT * scale;
                let same_dir = (a.angle - b.angle)
                    .rem_euclid(std::f64::consts::TAU)
                    .min((b.angle - a.angle).rem_euclid(std::f64::consts::TAU))
                    < 1e-9;
                if same_root && same_dir {
                    return Err(self.error(
                        flexures[i].span(),
                        &format!("flexures[{}]", i + 1),
                        format!(
                            "starts where flexure {} starts and points the same way: the two \
                             would overlap",
                            j + 1
                        ),
                    ));
                }
            }
        }
        if let (true, Some(first)) = (data, drives.first()) {
            return Err(self.error(
                first.span(),
                "drives",
                "a data scene's drive paths are its data file's rows (DESIGN §9: the [[drives]] \
                 names as input columns): remove the [[drives]] tables"
                    .into(),
            ));
        }
        if drives.is_empty() && !data {
            return Err(SceneError {
                origin: self.origin.to_string(),
                line: None,
                key: Some("drives".into()),
                message: "a mechanism scene needs at least one [[drives]] table (the drive \
                          path: dx/fx, dy/fy, dphi/mz, steps)"
                    .into(),
            });
        }
        let mut paths = Vec::with_capacity(drives.len());
        for (i, d) in drives.iter().enumerate() {
            paths.push(self.drive(d, i + 1)?);
        }
        let mechanism = Mechanism {
            flexures: out,
            stage_point,
            drives: paths,
        };
        let n = mechanism.case_count();
        if n > super::MAX_CASES {
            return Err(SceneError {
                origin: self.origin.to_string(),
                line: None,
                key: Some("drives".into()),
                message: format!(
                    "{n} load cases over {} drive paths is more than the {} a scene may have",
                    mechanism.drives.len(),
                    super::MAX_CASES
                ),
            });
        }
        Ok(mechanism)
    }

    fn point(&self, p: &Spanned<[f64; 2]>, key: &str) -> Result<[f64; 2], SceneError> {
        let v = *p.get_ref();
        for c in v {
            rules::finite(c).map_err(|m| self.error(p.span(), key, m))?;
        }
        Ok(v)
    }

    fn flexure(
        &self,
        beam: &BeamSpec,
        spanned: &Spanned<RawFlexure>,
        index: usize,
    ) -> Result<Flexure, SceneError> {
        let key = |field: &str| format!("flexures[{index}].{field}");
        let raw = spanned.get_ref();
        let root = match &raw.root {
            Some(p) => self.point(p, &key("root"))?,
            None => [0.0, 0.0],
        };
        let angle = match &raw.angle_deg {
            Some(a) => self
                .number(a, &key("angle_deg"), rules::finite)?
                .to_radians(),
            None => 0.0,
        };
        let mut b = *beam;
        let fields: [Override<'_>; 5] = [
            (&raw.length, "length", &mut b.length, rules::positive),
            (&raw.width, "width", &mut b.width, rules::positive),
            (
                &raw.thickness,
                "thickness",
                &mut b.thickness,
                rules::positive,
            ),
            (
                &raw.youngs_modulus,
                "youngs_modulus",
                &mut b.youngs_modulus,
                rules::positive,
            ),
            (
                &raw.poisson_ratio,
                "poisson_ratio",
                &mut b.poisson_ratio,
                rules::poisson_ratio,
            ),
        ];
        for (value, field, slot, rule) in fields {
            if let Some(v) = value {
                *slot = self.number(v, &key(field), rule)?;
            }
        }
        rules::slenderness(b.thickness, b.length).map_err(|m| {
            let span = raw
                .thickness
                .as_ref()
                .or(raw.length.as_ref())
                .map_or(spanned.span(), |s| s.span());
            self.error(span, &key("thickness"), m)
        })?;
        let attach = match raw
            .attach
            .as_ref()
            .map(|a| (a.get_ref().as_str(), a.span()))
        {
            None | Some(("clamped", _)) => Attach::Clamped,
            Some(("pinned", _)) => Attach::Pinned,
            // The coupler's stage end defaults to the stage point, filled in by the caller.
            Some(("link", _)) => Attach::Link { to: [0.0, 0.0] },
            Some((other, span)) => {
                return Err(self.error(
                    span,
                    &key("attach"),
                    format!("expected \"clamped\", \"pinned\" or \"link\", got \"{other}\""),
                ))
            }
        };
        if let Some(to) = &raw.link_to {
            let p = self.point(to, &key("link_to"))?;
            match attach {
                Attach::Link { .. } => {
                    return Ok(Flexure {
                        root,
                        angle,
                        attach: Attach::Link { to: p },
                        beam: b,
                    })
                }
                _ => {
                    return Err(self.error(
                        to.span(),
                        &key("link_to"),
                        "a coupler end is only for attach = \"link\"".into(),
                    ))
                }
            }
        }
        Ok(Flexure {
            root,
            angle,
            attach,
            beam: b,
        })
    }

    fn drive(&self, spanned: &Spanned<RawDrive>, index: usize) -> Result<Drive, SceneError> {
        let key = |field: &str| format!("drives[{index}].{field}");
        let r = spanned.get_ref();
        let pairs = [(&r.dx, &r.fx), (&r.dy, &r.fy), (&r.dphi, &r.mz)];
        let mut coordinates = [Coordinate::Loaded(0.0); 3];
        for (slot, ((disp, load), (dk, lk))) in coordinates
            .iter_mut()
            .zip(pairs.into_iter().zip(COORDINATE_KEYS))
        {
            *slot = match (disp, load) {
                (Some(d), Some(l)) => {
                    let span: Range<usize> =
                        d.span().start.min(l.span().start)..d.span().end.max(l.span().end);
                    return Err(self.error(
                        span,
                        &key(dk),
                        format!(
                            "give either a displacement ({dk}) or a load ({lk}) for this \
                             coordinate, not both"
                        ),
                    ));
                }
                (Some(d), None) => {
                    Coordinate::Prescribed(self.number(d, &key(dk), rules::finite)?)
                }
                (None, Some(l)) => Coordinate::Loaded(self.number(l, &key(lk), rules::finite)?),
                (None, None) => Coordinate::Loaded(0.0),
            };
        }
        if coordinates.iter().all(|c| c.value() == 0.0) {
            return Err(self.error(
                spanned.span(),
                &format!("drives[{index}]"),
                "the drive path goes nowhere: give a non-zero dx/fx, dy/fy or dphi/mz".into(),
            ));
        }
        let steps = self.steps(&r.steps, &key("steps"))?;
        Ok(Drive::proportional(coordinates, steps))
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod path_tests {
    use super::*;

    /// A proportional path is the end values times `lambda`; a measured path runs straight
    /// from rest to row 1 and from row to row, each row exactly at `k / n`.
    #[test]
    fn drive_paths_pass_through_their_rows() {
        use Coordinate::{Loaded, Prescribed};
        let end = [Prescribed(0.0), Prescribed(0.4), Loaded(2.0)];
        let p = DrivePath::proportional(end, 4);
        assert_eq!(p.at(0.5), [Prescribed(0.0), Prescribed(0.2), Loaded(1.0)]);
        let rows = DrivePath {
            end,
            steps: 3,
            rows: vec![[0.0, 0.1, 0.0], [0.0, 0.1, 1.0], [0.0, 0.4, 2.0]],
        };
        let value = |l: f64| rows.at(l).map(|c| c.value());
        assert_eq!(value(0.0), [0.0; 3]);
        for (k, r) in rows.rows.iter().enumerate() {
            assert_eq!(value((k + 1) as f64 / 3.0), *r);
        }
        // Halfway from rest to row 1, and from row 1 to row 2.
        let half = value(0.5 / 3.0);
        assert!((half[1] - 0.05).abs() < 1e-15 && half[2] == 0.0);
        let half = value(1.5 / 3.0);
        assert!((half[1] - 0.1).abs() < 1e-15 && (half[2] - 0.5).abs() < 1e-15);
        // Kinds are the end's.
        assert!(rows.at(0.7)[1].is_prescribed() && !rows.at(0.7)[2].is_prescribed());
        // The first cases as a path of their own pass through the same rows.
        let two = rows.first(2);
        assert_eq!(two.steps, 2);
        assert_eq!(two.at(1.0).map(|c| c.value()), rows.rows[1]);
        assert_eq!(two.at(0.5).map(|c| c.value()), rows.rows[0]);
        let half = p.first(2);
        assert_eq!(half.at(1.0), p.at(0.5));
        assert_eq!(half.at(0.5), p.at(0.25));
    }
}
