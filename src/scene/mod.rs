//! Scenes: what the user is designing for — the beam, the load paths or the mechanism and its
//! drives, the measured data when there are some, the accuracy needed (DESIGN §5, §8, §9) —
//! and the rules that say what a valid scene is.
//!
//! Each scene type checks its own rules with a `validate` method ([`BeamSpec::validate`],
//! [`LoadPath::validate`], [`Flexure::validate`], [`Drive::validate`],
//! [`Mechanism::validate`], [`Accuracy::validate`], [`FitSettings::validate`], and the whole
//! [`Scene::validate`]), built from the value rules of [`rules`]. A broken rule is a
//! [`RuleError`] naming its key (`flexures[2].thickness`). The TOML reader
//! ([`Scene::from_toml_str`]) and every editor (the UI's edits) apply these same methods: the
//! reader places the error at its key's line (`file:line: key: message`), an editor shows it
//! as `key: message`. Edits that carry a change along ([`Mechanism::with_stage_point`],
//! [`Mechanism::rebased`], [`Scene::rebased`]) leave the checking to their caller.
//!
//! Files, each using only those before it: `error.rs` and `rules.rs`; `beam.rs`
//! ([`BeamSpec`]), `load.rs` ([`LoadPath`]), `settings.rs` ([`Accuracy`], [`FitSettings`]),
//! `drive.rs` ([`Drive`], [`DrivePath`]), `mechanism.rs` ([`Flexure`], [`Mechanism`]);
//! [`data`] (measured data files); this file ([`Scene`] and its rules); `reader/` (TOML to a
//! scene) and `writer.rs` (a scene to TOML).

pub mod data;
pub mod rules;

mod beam;
mod drive;
mod error;
mod load;
mod mechanism;
mod reader;
mod settings;
mod writer;

pub use beam::{BeamSpec, EffectsChoice};
pub use drive::{Coordinate, Drive, DrivePath, COORDINATE_KEYS};
pub use error::{RuleError, SceneError};
pub use load::LoadPath;
pub use mechanism::{Attach, Flexure, Mechanism, MAX_SPAN};
pub use rules::{MAX_CASES, MAX_MODULUS, MAX_NONDIMENSIONAL, MAX_STEPS};
pub use settings::{Accuracy, Body, FitSettings};

use serde::{Deserialize, Serialize};

use crate::beam::Load;
use crate::prb::PrbMatrix;

/// The scene compiled into the binary: what `prbfit` runs on with no `--scene`.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../assets/scenes/default.toml");
/// The name under which the built-in scene reports errors.
pub const DEFAULT_SCENE_NAME: &str = "<built-in scene>";

/// A scene: valid when [`Scene::validate`] says so, as every scene read from a file is and
/// every edit the UI takes.
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
    /// The rigid body at the end of the flexures (DESIGN §10): a cantilever's `[tip]` body, a
    /// mechanism's `[stage]` mass and inertia.
    #[serde(default)]
    pub body: Body,
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

/// Why a cantilever scene with no load paths is refused.
const NO_LOADS: &str = "the scene has no load paths: add at least one [[loads]] table";

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

    /// Every load case of every path, in order.
    pub fn cases(&self) -> Vec<Load> {
        self.loads.iter().flat_map(|p| p.cases()).collect()
    }

    /// Checks the scene by the rules a scene file obeys; the error names the key
    /// (`beam.thickness`, `loads[2].steps`, `flexures[1].link_to`) and has no line (see
    /// [`Scene::check_rules`] for the rule error itself).
    pub fn validate(&self) -> Result<(), SceneError> {
        self.check_rules().map_err(|e| e.in_scene(&self.name))
    }

    /// The scene's rules, in the order a file is read: the beam's (under `beam`); a
    /// mechanism's (no `[[loads]]` beside it, [`Mechanism::validate`]; on a data scene
    /// [`Mechanism::validate_measured`], its drives being the file's rows); a data file's
    /// name (`truth.data`); a cantilever's load paths (at least one, each by
    /// [`LoadPath::validate`] under `loads[i]` unless they are a data file's rows, at most
    /// [`MAX_CASES`] cases); the targets (under `accuracy`) and weights (under `fit`; `modes` needs `[beam]
    /// density`); the body (under `tip` or `stage`, [`Scene::body_table`]); the model (`prb.matrix`).
    pub fn check_rules(&self) -> Result<(), RuleError> {
        self.beam.validate().map_err(|e| e.under("beam"))?;
        if let Some(m) = &self.mechanism {
            if !self.loads.is_empty() {
                return Err(RuleError::new(
                    "loads",
                    "a mechanism scene (with [[flexures]]) is driven by [[drives]], not \
                     [[loads]]",
                ));
            }
            match self.truth {
                Some(_) => m.validate_measured()?,
                None => m.validate()?,
            }
        }
        if let Some(t) = &self.truth {
            if t.file.trim().is_empty() {
                return Err(RuleError::new("truth.data", "an empty file name"));
            }
        }
        if self.loads.is_empty() && self.mechanism.is_none() && self.truth.is_none() {
            return Err(RuleError::new("loads", NO_LOADS));
        }
        // A data scene's paths are its file's rows, which its reader checks (a path may be one
        // row at rest, which a [[loads]] table may not).
        for (i, p) in self
            .loads
            .iter()
            .enumerate()
            .filter(|_| self.truth.is_none())
        {
            p.validate()
                .map_err(|e| e.under(&format!("loads[{}]", i + 1)))?;
        }
        rules::case_count(self.loads.iter().map(|p| p.steps), "paths")
            .map_err(|m| RuleError::new("loads", m))?;
        // A data file's rows within reach once nondimensional, as its reader checks them:
        // SI rows are rebased when the beam is edited (the Python module's `set_beam`), and
        // a softer beam can push them past it.
        if let Some(t) = &self.truth {
            for row in t.paths.iter().flat_map(|p| &p.rows) {
                let values = [
                    ("alpha_x", row.load.alpha_x),
                    ("alpha_y", row.load.alpha_y),
                    ("beta", row.load.beta),
                    ("a", row.tip.a),
                    ("b", row.tip.b),
                    ("phi", row.tip.phi),
                ];
                for (name, v) in values {
                    rules::reachable(v, v).map_err(|m| {
                        RuleError::new(
                            "truth.data",
                            format!(
                                "{}:{}: {name} = {m} (the rows are converted with the scene's \
                                 beam)",
                                t.file, row.line
                            ),
                        )
                    })?;
                }
            }
        }
        self.accuracy.validate().map_err(|e| e.under("accuracy"))?;
        self.fit.validate().map_err(|e| e.under("fit"))?;
        if self.fit.modes > 0 && self.beam.density.is_none() {
            return Err(RuleError::new(
                "fit.modes",
                "a dynamic fit needs the beam's density: add `density = ...` (kg/m^3) under \
                 [beam]",
            ));
        }
        self.body
            .validate()
            .map_err(|e| e.under(self.body_table()))?;
        if let Some(m) = &self.prb {
            m.validate()
                .map_err(|e| RuleError::new("prb.matrix", e.to_string()))?;
        }
        Ok(())
    }

    /// The table that holds [`Scene::body`]: `stage` in a mechanism scene, `tip` otherwise.
    pub fn body_table(&self) -> &'static str {
        if self.mechanism.is_some() {
            "stage"
        } else {
            "tip"
        }
    }

    /// The scene after an edit of its beam from `from`: what follows the beam follows it. A
    /// mechanism's flexures and stage point ([`Mechanism::rebased`]); a cantilever data
    /// scene's rows, converted again with the new beam ([`data::DataTruth::rebased`], which
    /// refuses a beam on which a path no longer grows), and its load paths with them. The
    /// caller checks the result ([`Scene::validate`]).
    pub fn rebased(mut self, from: &BeamSpec) -> Result<Scene, String> {
        if self.beam == *from {
            return Ok(self);
        }
        if let Some(m) = &self.mechanism {
            self.mechanism = Some(m.rebased(from, &self.beam));
        } else if let Some(t) = &self.truth {
            let t = t.rebased(from, &self.beam)?;
            self.set_measured(t.paths, t.units, t.sha256);
        }
        Ok(self)
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
        assert_eq!(scene.validate(), Ok(()));
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
        let mut s = good.clone();
        s.loads[1].steps = 0;
        assert_eq!(
            s.validate().unwrap_err().key.as_deref(),
            Some("loads[2].steps")
        );
        let mut s = good.clone();
        s.body.mass = -1.0;
        assert_eq!(s.validate().unwrap_err().key.as_deref(), Some("tip.mass"));
        let mut s = good.clone();
        s.beam.density = Some(f64::NAN);
        assert_eq!(
            s.validate().unwrap_err().key.as_deref(),
            Some("beam.density")
        );
        let mut s = good;
        s.loads.clear();
        assert_eq!(s.validate().unwrap_err().message, NO_LOADS);
    }
}
