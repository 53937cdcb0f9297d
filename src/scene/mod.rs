//! Scenes: what the user is designing for — the beam, the load paths, the accuracy needed
//! (DESIGN §5). A scene is read from TOML, validated with errors that name the file, line and
//! key, and converted from SI to the nondimensional core.
//!
//! `effects = "auto"` is decided from the beam, the loads and the targets by
//! [`crate::select::decide_effects`]; code that has not decided it (a scene just read)
//! treats it as every effect on, the safe superset.

pub mod data;
mod mechanism;

pub use mechanism::{Attach, Coordinate, Drive, DrivePath, Flexure, Mechanism, COORDINATE_KEYS};

use std::fmt;
use std::ops::Range;

use serde::{Deserialize, Serialize};
use toml::Spanned;

use crate::beam::{cowper_kappa, BeamModel, Effects, Load};
use crate::prb::PrbMatrix;

/// The scene compiled into the binary: what `prbfit` runs on with no `--scene`.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../assets/scenes/default.toml");
/// The name under which the built-in scene reports errors.
pub const DEFAULT_SCENE_NAME: &str = "<built-in scene>";

/// A load path: the end load, reached proportionally from zero and evaluated at
/// `k / steps`, `k = 1..=steps`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LoadPath {
    /// The end load, nondimensional.
    pub end: Load,
    /// Cases along the path (1 to [`MAX_STEPS`]).
    pub steps: u32,
}

impl LoadPath {
    /// The load cases along the path.
    pub fn cases(&self) -> impl Iterator<Item = Load> + '_ {
        (1..=self.steps).map(move |k| self.end.scaled(k as f64 / self.steps as f64))
    }
}

/// Which beam effects the scene asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EffectsChoice {
    /// Decide from the beam and loads (for now: all effects on).
    Auto,
    /// Exactly these effects.
    Fixed(Effects),
}

impl EffectsChoice {
    /// The effects the baseline uses.
    pub fn resolve(&self) -> Effects {
        match self {
            EffectsChoice::Auto => Effects::ALL,
            EffectsChoice::Fixed(e) => *e,
        }
    }
}

impl fmt::Display for EffectsChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EffectsChoice::Auto => write!(f, "auto"),
            EffectsChoice::Fixed(e) => write!(f, "{e}"),
        }
    }
}

/// The beam in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BeamSpec {
    /// m
    pub length: f64,
    /// m
    pub width: f64,
    /// m
    pub thickness: f64,
    /// Pa
    pub youngs_modulus: f64,
    /// `nu`, in `[0, 0.5)`.
    pub poisson_ratio: f64,
    /// `None`: Cowper's rectangle value.
    pub shear_coefficient: Option<f64>,
    /// Which effects of DESIGN §2 the beam models.
    pub effects: EffectsChoice,
}

impl BeamSpec {
    /// `L / t0`.
    pub fn slenderness(&self) -> f64 {
        self.length / self.thickness
    }

    /// `kappa` in use: the given one or Cowper's.
    pub fn kappa(&self) -> f64 {
        self.shear_coefficient
            .unwrap_or_else(|| cowper_kappa(self.poisson_ratio))
    }

    /// `A0 = w0 t0`.
    pub fn area(&self) -> f64 {
        self.width * self.thickness
    }

    /// `I0 = w0 t0^3 / 12`.
    pub fn second_moment(&self) -> f64 {
        self.width * self.thickness.powi(3) / 12.0
    }

    /// The nondimensional beam the solver works on.
    ///
    /// # Panics
    /// On a beam that breaks the scene's rules: every scene is validated where it is made (a
    /// file by its reader, an edit by [`Scene::validate`]), so that is a bug, never input.
    #[allow(clippy::expect_used)]
    pub fn model(&self) -> BeamModel {
        BeamModel::new(
            self.slenderness(),
            self.poisson_ratio,
            self.shear_coefficient,
            self.effects.resolve(),
        )
        .expect("a validated scene describes a valid beam")
        .with_width_ratio(self.width / self.thickness)
    }
}

/// What "good enough" means for a scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Units of L.
    pub max_pos_err: f64,
    /// Radians.
    pub max_ang_err: f64,
    /// Mechanism scenes: the largest reaction error of a prescribed stage coordinate, as a
    /// fraction of that coordinate's largest reaction over the scene (DESIGN §8).
    #[serde(default = "default_force_err")]
    pub max_force_err: f64,
}

fn default_force_err() -> f64 {
    0.05
}

impl Default for Accuracy {
    fn default() -> Self {
        Accuracy {
            max_pos_err: 0.01,
            max_ang_err: 0.02,
            max_force_err: default_force_err(),
        }
    }
}

/// Settings of the fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitSettings {
    /// `w` in `J = mean(e_pos^2 + w e_ang^2)`.
    pub angle_weight: f64,
    /// Mechanism scenes: `w_f` in `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`.
    #[serde(default = "default_force_weight")]
    pub force_weight: f64,
}

fn default_force_weight() -> f64 {
    1.0
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            angle_weight: 1.0,
            force_weight: default_force_weight(),
        }
    }
}

/// A validated scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// What the user calls it.
    pub name: String,
    /// The beam, SI.
    pub beam: BeamSpec,
    /// The load paths, each from zero.
    pub loads: Vec<LoadPath>,
    /// The targets.
    pub accuracy: Accuracy,
    /// The fit's settings.
    pub fit: FitSettings,
    /// The model being worked on (`[prb] matrix`, fixed cells marked `!`), if the scene
    /// names one: `eval`, `fit` and `export` use it when no model is given, and the UI
    /// saves and opens it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prb: Option<PrbMatrix>,
    /// A mechanism scene (DESIGN §8): flexures, stage and drive paths; `loads` is then empty.
    /// `None`: the plain cantilever of §5.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<Mechanism>,
    /// A data scene (DESIGN §9): measured load cases and tips are the truth in place of the
    /// beam (`[truth] data = "file.csv"`); `loads` then holds one path per measured path
    /// (to its last row, one case per row) for what counts cases. Read by
    /// [`Scene::from_file`]; a scene parsed from text has the file's name but no rows yet.
    #[serde(skip)]
    pub truth: Option<data::DataTruth>,
}

impl Scene {
    /// Gives a data scene its measured paths (read by the IO layer, in `units`) and `sha256`,
    /// the file's content hash; `loads` becomes one path per measured path, to its last row,
    /// one case per row.
    pub fn set_measured(
        &mut self,
        paths: Vec<data::MeasuredPath>,
        units: data::Units,
        sha256: String,
    ) {
        self.loads = paths
            .iter()
            .filter_map(|p| {
                p.rows.last().map(|last| LoadPath {
                    end: last.load,
                    steps: u32::try_from(p.rows.len()).unwrap_or(u32::MAX),
                })
            })
            .collect();
        if let Some(t) = self.truth.as_mut() {
            t.paths = paths;
            t.units = units;
            t.sha256 = sha256;
        }
    }

    /// Gives a mechanism data scene its measured drive paths (read by the IO layer) and
    /// `sha256`, the file's content hash: the mechanism's drives become one path per measured
    /// path, through its rows (DESIGN §9), its cases the rows.
    pub fn set_measured_stage(&mut self, stage: data::StageData, sha256: String) {
        if let Some(m) = self.mechanism.as_mut() {
            m.drives = stage
                .paths
                .iter()
                .filter_map(|p| {
                    let last = p.rows.last()?;
                    let kind = |c: usize, v: f64| {
                        if stage.prescribed[c] {
                            Coordinate::Prescribed(v)
                        } else {
                            Coordinate::Loaded(v)
                        }
                    };
                    Some(Drive {
                        coordinates: std::array::from_fn(|c| kind(c, last.drive[c])),
                        steps: u32::try_from(p.rows.len()).unwrap_or(u32::MAX),
                        rows: p.rows.iter().map(|r| r.drive).collect(),
                    })
                })
                .collect();
        }
        if let Some(t) = self.truth.as_mut() {
            t.paths = Vec::new();
            t.units = data::Units::Si;
            t.stage = Some(stage);
            t.sha256 = sha256;
        }
    }

    /// The built-in scene.
    #[allow(clippy::expect_used)] // a compiled-in constant, checked by a test
    pub fn builtin() -> Scene {
        Scene::from_toml_str(DEFAULT_SCENE_TOML, DEFAULT_SCENE_NAME)
            .expect("the built-in scene is valid (checked by a test)")
    }

    /// Parses and validates a scene; `origin` names it in errors (a file path).
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError {
            origin: origin.to_string(),
            line: e.span().map(|s| line_of(text, s.start)),
            key: None,
            message: e.message().trim().to_string(),
        })?;
        Validator { text, origin }.scene(raw)
    }

    /// Every load case of every path, in order.
    pub fn cases(&self) -> Vec<Load> {
        self.loads.iter().flat_map(|p| p.cases()).collect()
    }

    /// The scene as TOML, in the schema it was read from.
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        out.push_str(&format!("name = {}\n\n[beam]\n", toml_string(&self.name)));
        let b = &self.beam;
        out.push_str(&format!("length = {:e}\n", b.length));
        out.push_str(&format!("width = {:e}\n", b.width));
        out.push_str(&format!("thickness = {:e}\n", b.thickness));
        out.push_str(&format!("youngs_modulus = {:e}\n", b.youngs_modulus));
        out.push_str(&format!("poisson_ratio = {:?}\n", b.poisson_ratio));
        if let Some(k) = b.shear_coefficient {
            out.push_str(&format!("shear_coefficient = {k:?}\n"));
        }
        match b.effects {
            EffectsChoice::Auto => out.push_str("effects = \"auto\"\n"),
            EffectsChoice::Fixed(e) => {
                let names: Vec<String> = e.names().iter().map(|n| format!("\"{n}\"")).collect();
                out.push_str(&format!("effects = [{}]\n", names.join(", ")));
            }
        }
        if let Some(t) = &self.truth {
            out.push_str(&format!("\n[truth]\ndata = {}\n", toml_string(&t.file)));
        }
        for path in self.loads.iter().filter(|_| self.truth.is_none()) {
            out.push_str(&format!(
                "\n[[loads]]\nalpha_x = {:?}\nalpha_y = {:?}\nbeta = {:?}\nsteps = {}\n",
                path.end.alpha_x, path.end.alpha_y, path.end.beta, path.steps
            ));
        }
        if let Some(m) = &self.mechanism {
            // A data scene's drive paths are its file's rows.
            m.write_toml(&self.beam, self.truth.is_none(), &mut out);
        }
        out.push_str(&format!(
            "\n[accuracy]\nmax_pos_err = {:?}\nmax_ang_err = {:?}\n",
            self.accuracy.max_pos_err, self.accuracy.max_ang_err
        ));
        if self.mechanism.is_some() {
            out.push_str(&format!(
                "max_force_err = {:?}\n",
                self.accuracy.max_force_err
            ));
        }
        out.push_str(&format!(
            "\n[fit]\nangle_weight = {:?}\n",
            self.fit.angle_weight
        ));
        if self.mechanism.is_some() {
            out.push_str(&format!("force_weight = {:?}\n", self.fit.force_weight));
        }
        if let Some(m) = &self.prb {
            out.push_str(&format!(
                "\n[prb]\nmatrix = {}\n",
                toml_string(&m.to_text())
            ));
        }
        out
    }
}

fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A scene that cannot be used, with where and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SceneError {
    /// The file (or `<built-in scene>`).
    pub origin: String,
    /// 1-based line in the file, when the error has one.
    pub line: Option<usize>,
    /// Dotted key, such as `beam.thickness` or `loads[2].steps`.
    pub key: Option<String>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.origin)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if let Some(key) = &self.key {
            write!(f, "{key}: ")?;
        }
        write!(f, "{}", self.message)
    }
}

/// 1-based line of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: Option<Spanned<String>>,
    beam: Spanned<RawBeam>,
    #[serde(default)]
    loads: Vec<Spanned<RawLoad>>,
    accuracy: Option<Spanned<RawAccuracy>>,
    fit: Option<Spanned<RawFit>>,
    prb: Option<Spanned<RawPrb>>,
    truth: Option<Spanned<RawTruth>>,
    #[serde(default)]
    flexures: Vec<Spanned<mechanism::RawFlexure>>,
    stage: Option<Spanned<mechanism::RawStage>>,
    #[serde(default)]
    drives: Vec<Spanned<mechanism::RawDrive>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTruth {
    data: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPrb {
    matrix: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBeam {
    length: Spanned<f64>,
    width: Spanned<f64>,
    thickness: Spanned<f64>,
    youngs_modulus: Spanned<f64>,
    poisson_ratio: Spanned<f64>,
    shear_coefficient: Option<Spanned<f64>>,
    /// Any TOML value: checked by hand, so a wrong type gets a message that says what is
    /// expected (serde's untagged enums only say "did not match any variant").
    effects: Option<Spanned<toml::Value>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoad {
    alpha_x: Option<Spanned<f64>>,
    alpha_y: Option<Spanned<f64>>,
    beta: Option<Spanned<f64>>,
    steps: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAccuracy {
    max_pos_err: Option<Spanned<f64>>,
    max_ang_err: Option<Spanned<f64>>,
    max_force_err: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFit {
    angle_weight: Option<Spanned<f64>>,
    force_weight: Option<Spanned<f64>>,
}

/// The most load steps one path may ask for.
pub const MAX_STEPS: i64 = 10_000;

/// The most load cases a scene may have over all its paths. A solve costs tens of
/// microseconds per case and a fit evaluates every case hundreds of times, so this is already
/// minutes of fitting; a scene with more is a mistake (a generated file run wild), refused
/// before any work.
pub const MAX_CASES: u64 = 100_000;

/// The rules a scene's values obey. Each is written once and applied twice: by the file
/// reader (errors name the line) and by [`Scene::validate`] (an edited scene, no file).
mod rules {
    use crate::beam::{Load, MAX_SLENDERNESS};
    use crate::text::bounded;

    use super::MAX_STEPS;

    pub fn positive(v: f64) -> Result<(), String> {
        (v.is_finite() && v > 0.0)
            .then_some(())
            .ok_or_else(|| format!("must be a finite number > 0, got {}", bounded(v)))
    }

    pub fn poisson_ratio(v: f64) -> Result<(), String> {
        (v.is_finite() && (0.0..0.5).contains(&v))
            .then_some(())
            .ok_or_else(|| format!("must be in [0, 0.5), got {}", bounded(v)))
    }

    pub fn non_negative(v: f64) -> Result<(), String> {
        (v.is_finite() && v >= 0.0)
            .then_some(())
            .ok_or_else(|| format!("must be a finite number >= 0, got {}", bounded(v)))
    }

    pub fn finite(v: f64) -> Result<(), String> {
        v.is_finite()
            .then_some(())
            .ok_or_else(|| format!("must be a finite number, got {}", bounded(v)))
    }

    /// The thickness against the length: `1 <= L/t0 <= MAX_SLENDERNESS`.
    pub fn slenderness(thickness: f64, length: f64) -> Result<(), String> {
        if thickness > length {
            return Err(format!(
                "a beam must be at least as long as it is thick (slenderness L/t0 >= 1), \
                 got thickness {} > length {}",
                bounded(thickness),
                bounded(length)
            ));
        }
        if length / thickness > MAX_SLENDERNESS {
            return Err(format!(
                "slenderness L/t0 = {:e} is beyond the {MAX_SLENDERNESS:e} prbfit models",
                length / thickness
            ));
        }
        Ok(())
    }

    pub fn steps(v: i64) -> Result<(), String> {
        (1..=MAX_STEPS)
            .contains(&v)
            .then_some(())
            .ok_or_else(|| format!("must be a whole number from 1 to {MAX_STEPS}, got {v}"))
    }

    /// The cases over all paths.
    pub fn case_count(paths: &[super::LoadPath]) -> Result<(), String> {
        let n: u64 = paths.iter().map(|p| u64::from(p.steps)).sum();
        (n <= super::MAX_CASES).then_some(()).ok_or_else(|| {
            format!(
                "{n} load cases over {} paths is more than the {} a scene may have",
                paths.len(),
                super::MAX_CASES
            )
        })
    }

    pub fn nonzero(end: &Load) -> Result<(), String> {
        (end.magnitude() != 0.0)
            .then_some(())
            .ok_or_else(|| "the load path is all zero: give alpha_x, alpha_y or beta".into())
    }
}

impl Scene {
    /// Checks an edited scene against the same rules a scene file obeys; the error names the
    /// key (`beam.thickness`, `loads[2].steps`).
    pub fn validate(&self) -> Result<(), SceneError> {
        let fail = |key: String, message: String| SceneError {
            origin: self.name.clone(),
            line: None,
            key: Some(key),
            message,
        };
        let check = |key: &str, r: Result<(), String>| r.map_err(|m| fail(key.into(), m));
        let b = &self.beam;
        check("beam.length", rules::positive(b.length))?;
        check("beam.width", rules::positive(b.width))?;
        check("beam.thickness", rules::positive(b.thickness))?;
        check("beam.thickness", rules::slenderness(b.thickness, b.length))?;
        check("beam.youngs_modulus", rules::positive(b.youngs_modulus))?;
        check("beam.poisson_ratio", rules::poisson_ratio(b.poisson_ratio))?;
        if let Some(k) = b.shear_coefficient {
            check("beam.shear_coefficient", rules::positive(k))?;
        }
        if let EffectsChoice::Fixed(e) = b.effects {
            e.validate()
                .map_err(|e| fail("beam.effects".into(), e.to_string()))?;
        }
        if self.loads.is_empty() && self.mechanism.is_none() {
            return Err(fail("loads".into(), NO_LOADS.into()));
        }
        // A data scene's paths are its file's rows, which its reader checks (a path may be one
        // row at rest, which a [[loads]] table may not).
        for (i, p) in self
            .loads
            .iter()
            .enumerate()
            .filter(|_| self.truth.is_none())
        {
            let key = |field: &str| format!("loads[{}].{field}", i + 1);
            check(&key("alpha_x"), rules::finite(p.end.alpha_x))?;
            check(&key("alpha_y"), rules::finite(p.end.alpha_y))?;
            check(&key("beta"), rules::finite(p.end.beta))?;
            rules::nonzero(&p.end).map_err(|m| fail(format!("loads[{}]", i + 1), m))?;
            check(&key("steps"), rules::steps(i64::from(p.steps)))?;
        }
        check("loads", rules::case_count(&self.loads))?;
        check(
            "accuracy.max_pos_err",
            rules::positive(self.accuracy.max_pos_err),
        )?;
        check(
            "accuracy.max_ang_err",
            rules::positive(self.accuracy.max_ang_err),
        )?;
        check(
            "accuracy.max_force_err",
            rules::positive(self.accuracy.max_force_err),
        )?;
        check(
            "fit.angle_weight",
            rules::non_negative(self.fit.angle_weight),
        )?;
        check(
            "fit.force_weight",
            rules::non_negative(self.fit.force_weight),
        )
    }
}

const NO_LOADS: &str = "the scene has no load paths: add at least one [[loads]] table";

struct Validator<'a> {
    text: &'a str,
    origin: &'a str,
}

impl Validator<'_> {
    fn error(&self, span: Range<usize>, key: &str, message: String) -> SceneError {
        SceneError {
            origin: self.origin.to_string(),
            line: Some(line_of(self.text, span.start)),
            key: Some(key.to_string()),
            message,
        }
    }

    /// The value, if it obeys `rule`; else the error naming its line and key.
    fn number(
        &self,
        value: &Spanned<f64>,
        key: &str,
        rule: fn(f64) -> Result<(), String>,
    ) -> Result<f64, SceneError> {
        let v = *value.get_ref();
        rule(v).map_err(|m| self.error(value.span(), key, m))?;
        Ok(v)
    }

    fn scene(&self, raw: RawScene) -> Result<Scene, SceneError> {
        let name = raw
            .name
            .map(|n| n.into_inner())
            .unwrap_or_else(|| "unnamed scene".to_string());
        let beam = self.beam(raw.beam.get_ref())?;
        let mechanism = if raw.flexures.is_empty() {
            if let Some(first) = raw
                .drives
                .first()
                .map(|d| d.span())
                .or(raw.stage.as_ref().map(|s| s.span()))
            {
                return Err(self.error(
                    first,
                    "flexures",
                    "[stage] and [[drives]] describe a mechanism: add its [[flexures]] (or \
                     give [[loads]] for a plain cantilever)"
                        .into(),
                ));
            }
            None
        } else {
            if let Some(first) = raw.loads.first() {
                return Err(self.error(
                    first.span(),
                    "loads",
                    "a mechanism scene (with [[flexures]]) is driven by [[drives]], not \
                     [[loads]]"
                        .into(),
                ));
            }
            Some(self.mechanism(
                &beam,
                &raw.flexures,
                raw.stage.as_ref(),
                &raw.drives,
                raw.truth.is_some(),
            )?)
        };
        let truth = match &raw.truth {
            None => None,
            Some(t) => {
                let file = &t.get_ref().data;
                if let Some(first) = raw.loads.first() {
                    return Err(self.error(
                        first.span(),
                        "loads",
                        "a data scene's load cases are its data file's rows: remove the \
                         [[loads]] tables"
                            .into(),
                    ));
                }
                if file.get_ref().trim().is_empty() {
                    return Err(self.error(file.span(), "truth.data", "an empty file name".into()));
                }
                Some(data::DataTruth {
                    file: file.get_ref().clone(),
                    sha256: String::new(),
                    units: data::Units::default(),
                    paths: Vec::new(),
                    stage: None,
                })
            }
        };
        if raw.loads.is_empty() && mechanism.is_none() && truth.is_none() {
            return Err(SceneError {
                origin: self.origin.to_string(),
                line: None,
                key: Some("loads".into()),
                message: NO_LOADS.into(),
            });
        }
        let mut loads = Vec::with_capacity(raw.loads.len());
        for (i, load) in raw.loads.iter().enumerate() {
            loads.push(self.load(load, i + 1)?);
        }
        rules::case_count(&loads).map_err(|message| SceneError {
            origin: self.origin.to_string(),
            line: None,
            key: Some("loads".into()),
            message,
        })?;
        let default = Accuracy::default();
        let acc = raw.accuracy.as_ref().map(|a| a.get_ref());
        let target = |v: Option<&Spanned<f64>>, key: &str, default: f64| match v {
            Some(v) => self.number(v, key, rules::positive),
            None => Ok(default),
        };
        let accuracy = Accuracy {
            max_pos_err: target(
                acc.and_then(|a| a.max_pos_err.as_ref()),
                "accuracy.max_pos_err",
                default.max_pos_err,
            )?,
            max_ang_err: target(
                acc.and_then(|a| a.max_ang_err.as_ref()),
                "accuracy.max_ang_err",
                default.max_ang_err,
            )?,
            max_force_err: target(
                acc.and_then(|a| a.max_force_err.as_ref()),
                "accuracy.max_force_err",
                default.max_force_err,
            )?,
        };
        let fit_raw = raw.fit.as_ref().map(|f| f.get_ref());
        let weight = |v: Option<&Spanned<f64>>, key: &str, default: f64| match v {
            Some(v) => self.number(v, key, rules::non_negative),
            None => Ok(default),
        };
        let defaults = FitSettings::default();
        let fit = FitSettings {
            angle_weight: weight(
                fit_raw.and_then(|f| f.angle_weight.as_ref()),
                "fit.angle_weight",
                defaults.angle_weight,
            )?,
            force_weight: weight(
                fit_raw.and_then(|f| f.force_weight.as_ref()),
                "fit.force_weight",
                defaults.force_weight,
            )?,
        };
        let prb = match &raw.prb {
            None => None,
            Some(p) => {
                let m = &p.get_ref().matrix;
                Some(
                    PrbMatrix::parse(m.get_ref())
                        .map_err(|e| self.error(m.span(), "prb.matrix", e.to_string()))?,
                )
            }
        };
        Ok(Scene {
            name,
            beam,
            loads,
            accuracy,
            fit,
            prb,
            mechanism,
            truth,
        })
    }

    fn beam(&self, raw: &RawBeam) -> Result<BeamSpec, SceneError> {
        let length = self.number(&raw.length, "beam.length", rules::positive)?;
        let width = self.number(&raw.width, "beam.width", rules::positive)?;
        let thickness = self.number(&raw.thickness, "beam.thickness", rules::positive)?;
        rules::slenderness(thickness, length)
            .map_err(|m| self.error(raw.thickness.span(), "beam.thickness", m))?;
        let youngs_modulus =
            self.number(&raw.youngs_modulus, "beam.youngs_modulus", rules::positive)?;
        let poisson_ratio = self.number(
            &raw.poisson_ratio,
            "beam.poisson_ratio",
            rules::poisson_ratio,
        )?;
        let shear_coefficient = match &raw.shear_coefficient {
            Some(k) => Some(self.number(k, "beam.shear_coefficient", rules::positive)?),
            None => None,
        };
        let effects = match &raw.effects {
            None => EffectsChoice::Auto,
            Some(spanned) => self.effects(spanned)?,
        };
        Ok(BeamSpec {
            length,
            width,
            thickness,
            youngs_modulus,
            poisson_ratio,
            shear_coefficient,
            effects,
        })
    }

    fn effects(&self, spanned: &Spanned<toml::Value>) -> Result<EffectsChoice, SceneError> {
        let key = "beam.effects";
        let fail = |message: String| self.error(spanned.span(), key, message);
        let expected = "expected \"auto\", \"none\", \"all\" or a list such as \
                        [\"shear\", \"extension\"] (names: shear, extension, poisson, \
                        plane_strain)";
        match spanned.get_ref() {
            toml::Value::String(w) if w == "auto" => Ok(EffectsChoice::Auto),
            toml::Value::String(w) if w == "none" => Ok(EffectsChoice::Fixed(Effects::NONE)),
            toml::Value::String(w) if w == "all" => Ok(EffectsChoice::Fixed(Effects::ALL)),
            toml::Value::String(w) => Err(fail(format!("{expected}, got \"{w}\""))),
            toml::Value::Array(list) => {
                let mut effects = Effects::NONE;
                for item in list {
                    let name = item.as_str().ok_or_else(|| {
                        fail(format!(
                            "{expected}; the list holds {} `{item}`, not a name",
                            item.type_str()
                        ))
                    })?;
                    effects.set(name).map_err(|e| fail(e.to_string()))?;
                }
                effects.validate().map_err(|e| fail(e.to_string()))?;
                Ok(EffectsChoice::Fixed(effects))
            }
            other => Err(fail(format!(
                "{expected}, got the {} `{other}`",
                other.type_str()
            ))),
        }
    }

    fn load(&self, raw: &Spanned<RawLoad>, index: usize) -> Result<LoadPath, SceneError> {
        let key = |field: &str| format!("loads[{index}].{field}");
        let component = |value: &Option<Spanned<f64>>, field: &str| match value {
            None => Ok(0.0),
            Some(v) => self.number(v, &key(field), rules::finite),
        };
        let r = raw.get_ref();
        let end = Load::new(
            component(&r.alpha_x, "alpha_x")?,
            component(&r.alpha_y, "alpha_y")?,
            component(&r.beta, "beta")?,
        );
        rules::nonzero(&end).map_err(|m| self.error(raw.span(), &format!("loads[{index}]"), m))?;
        let steps = self.steps(&r.steps, &key("steps"))?;
        Ok(LoadPath { end, steps })
    }

    /// A path's `steps` (1 when absent), within [`MAX_STEPS`].
    fn steps(&self, raw: &Option<Spanned<i64>>, key: &str) -> Result<u32, SceneError> {
        match raw {
            None => Ok(1),
            Some(s) => {
                let v = *s.get_ref();
                rules::steps(v).map_err(|m| self.error(s.span(), key, m))?;
                Ok(v as u32)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_scene_is_valid() {
        let scene = Scene::builtin();
        assert!(!scene.loads.is_empty());
        assert!(scene.cases().len() >= 10);
    }

    #[test]
    fn validate_applies_the_file_rules() {
        let good = Scene::builtin();
        assert_eq!(good.validate(), Ok(()));
        let mut s = good.clone();
        s.beam.thickness = -1.0;
        assert_eq!(
            s.validate().unwrap_err().key.as_deref(),
            Some("beam.thickness")
        );
        let mut s = good.clone();
        s.beam.poisson_ratio = 0.5;
        let e = s.validate().unwrap_err();
        assert_eq!(e.key.as_deref(), Some("beam.poisson_ratio"));
        assert!(e.message.contains("[0, 0.5)"), "{e}");
        let mut s = good.clone();
        s.fit.angle_weight = f64::NAN;
        assert_eq!(
            s.validate().unwrap_err().key.as_deref(),
            Some("fit.angle_weight")
        );
        let mut s = good.clone();
        s.beam.thickness = s.beam.length * 2.0;
        assert!(s
            .validate()
            .unwrap_err()
            .message
            .contains("at least as long"));
        let mut s = good;
        s.loads[1].steps = 0;
        assert_eq!(
            s.validate().unwrap_err().key.as_deref(),
            Some("loads[2].steps")
        );
    }

    #[test]
    fn toml_round_trip() {
        let mut scene = Scene::builtin();
        let again = Scene::from_toml_str(&scene.to_toml(), "round trip").unwrap();
        assert_eq!(scene, again);
        // With a model, fixed cells and inf included.
        scene.prb = Some(
            PrbMatrix::parse("0.1!,inf,inf; 0.35,3.51,inf; 0.4,2.99!,inf; 0.15,2.58,1e3").unwrap(),
        );
        let text = scene.to_toml();
        assert!(text.contains("[prb]\nmatrix = \"0.1!,inf,inf;"), "{text}");
        let again = Scene::from_toml_str(&text, "round trip").unwrap();
        assert_eq!(scene, again);
    }

    const SLIDER_CRANK: &str = r#"
name = "slider-crank"
[beam]
length = 0.05
width = 0.01
thickness = 0.0005
youngs_modulus = 200e9
poisson_ratio = 0.3
effects = "none"
[[flexures]]
root = [0.0, 0.0]
angle_deg = 0.0
attach = "link"
[stage]
point = [0.07, -0.02]
[[drives]]
dx = 0.0
dy = 0.01
dphi = 0.0
steps = 10
[accuracy]
max_force_err = 0.03
"#;

    /// A mechanism whose truth is data: no [[drives]] (the rows are the drives), and it saves
    /// as it was read; [[drives]] beside [truth] are refused at their line.
    #[test]
    fn mechanism_data_scenes_read_and_round_trip() {
        let start = SLIDER_CRANK.find("[[drives]]").unwrap();
        let end = SLIDER_CRANK.find("[accuracy]").unwrap();
        let text = format!(
            "{}[truth]\ndata = \"rig.csv\"\n\n{}",
            &SLIDER_CRANK[..start],
            &SLIDER_CRANK[end..]
        );
        let scene = Scene::from_toml_str(&text, "rig.toml").unwrap();
        assert!(scene.mechanism.as_ref().unwrap().drives.is_empty());
        assert_eq!(scene.truth.as_ref().unwrap().file, "rig.csv");
        let saved = scene.to_toml();
        assert!(
            saved.contains("[truth]") && !saved.contains("[[drives]]"),
            "{saved}"
        );
        assert_eq!(Scene::from_toml_str(&saved, "again").unwrap(), scene);
        let both = SLIDER_CRANK.replace("[accuracy]", "[truth]\ndata = \"rig.csv\"\n[accuracy]");
        let e = Scene::from_toml_str(&both, "both.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("drives"), "{e}");
        assert!(e.line.is_some(), "{e}");
    }

    #[test]
    fn mechanism_scenes_read_and_round_trip() {
        let scene = Scene::from_toml_str(SLIDER_CRANK, "sc.toml").unwrap();
        let m = scene.mechanism.as_ref().unwrap();
        assert_eq!(m.flexures.len(), 1);
        assert_eq!(m.flexures[0].attach, Attach::Link { to: [0.07, -0.02] });
        assert_eq!(m.stage_point, [0.07, -0.02]);
        assert_eq!(
            m.drives[0].coordinates,
            [
                Coordinate::Prescribed(0.0),
                Coordinate::Prescribed(0.01),
                Coordinate::Prescribed(0.0)
            ]
        );
        assert!(scene.loads.is_empty());
        assert_eq!(scene.accuracy.max_force_err, 0.03);
        assert_eq!(scene.validate(), Ok(()));
        let again = Scene::from_toml_str(&scene.to_toml(), "again").unwrap();
        assert_eq!(again, scene);
        // dy = 0.01 m is 0.2 L; a drive load of 1 N is alpha = F L^2 / (E I0).
        let nd = m.nondimensional(&m.drives[0]);
        assert!((nd[1].value() - 0.2).abs() < 1e-15);
    }

    #[test]
    fn bad_mechanisms_name_their_line_and_key() {
        let cases = [
            (
                "dy = 0.01",
                "dy = 0.01\nfy = 2.0",
                "drives[1].dy",
                "not both",
            ),
            (
                "attach = \"link\"",
                "attach = \"glued\"",
                "flexures[1].attach",
                "glued",
            ),
            (
                "point = [0.07, -0.02]",
                "point = [0.05, 0.0]",
                "flexures[1].link_to",
                "zero length",
            ),
            ("steps = 10", "steps = 0", "drives[1].steps", "1 to"),
            (
                "attach = \"link\"",
                "attach = \"link\"\n[[flexures]]\nroot = [0.0, 0.0]\nattach = \"clamped\"",
                "flexures[2]",
                "overlap",
            ),
        ];
        for (from, to, key, words) in cases {
            let text = SLIDER_CRANK.replacen(from, to, 1);
            let e = Scene::from_toml_str(&text, "sc.toml").unwrap_err();
            assert_eq!(e.key.as_deref(), Some(key), "{e}");
            assert!(e.line.is_some(), "{e}");
            assert!(e.to_string().contains(words), "{e}");
        }
        // A mechanism with [[loads]], and drives without flexures.
        let both = format!("{SLIDER_CRANK}\n[[loads]]\nalpha_y = 1.0\n");
        let e = Scene::from_toml_str(&both, "sc.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("loads"), "{e}");
        let orphan = format!("{DEFAULT_SCENE_TOML}\n[[drives]]\ndy = 0.01\n");
        let e = Scene::from_toml_str(&orphan, "d.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("flexures"), "{e}");
    }

    #[test]
    fn a_bad_prb_matrix_names_its_line_and_cell() {
        let text = format!(
            "{}\n[prb]\nmatrix = \"0.5,inf,inf; 0.6,2,inf\"\n",
            DEFAULT_SCENE_TOML
        );
        let e = Scene::from_toml_str(&text, "s.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("prb.matrix"));
        assert_eq!(e.line, Some(DEFAULT_SCENE_TOML.lines().count() + 3));
        assert!(e.message.contains("sum to 1"), "{e}");
    }
}
