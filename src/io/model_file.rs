//! PRB model files: a matrix plus what it is and where it came from. The published models
//! (Howell 1R, Su 3R, Chen 3R, [`crate::prb::published`]) are compiled in, so `--model su-3r`
//! works from any directory; any other name is read as a file (TOML, or JSON when it ends in
//! `.json`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::mech::figures::Figures;
use crate::prb::{published, PrbMatrix};
use crate::scene::{rules, BeamSpec, RuleError, Scene, SceneError};
use crate::si::{load_range, si_model, LoadRange, SiModel};

/// A PRB model file. Unknown keys are allowed (richer exports carry more), but what is
/// here is checked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    /// Short name (`su-3r`, `fitted-l-r-r-r`).
    pub name: String,
    /// Human name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    /// Topology name; checked against the matrix when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub topology: Option<String>,
    /// Where the model comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// How published values were converted to the matrix convention.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conversion: Option<String>,
    /// The matrix.
    pub prb: PrbMatrix,
    /// How a fitted model was made, and how well it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitRecord>,
    /// The model in SI units for the scene's beam (exports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub si: Option<SiModel>,
    /// The scene's load range (exports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_range: Option<LoadRange>,
}

/// Provenance and error figures of a fitted model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitRecord {
    /// The scene's name.
    pub scene: String,
    /// The fidelity preset.
    pub fidelity: String,
    /// Why the fit stopped before it finished (`cancelled`: Ctrl-C), if it did: the matrix
    /// and figures are then the best found so far, not a finished fit's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_early: Option<String>,
    /// `w` in J.
    pub angle_weight: f64,
    /// The figures on the scene: §4's five, with a mechanism's reaction figures where some
    /// coordinate is prescribed and its flexure tip error where the truth has flexure tips.
    #[serde(flatten)]
    pub figures: Figures,
    /// Data scenes (DESIGN §9): the data the model was fitted to (its figures are against
    /// the data); absent when the truth was the beam.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<TruthRecord>,
    /// Mechanism scenes (DESIGN §8): `J`'s force weight and the model in SI for every
    /// flexure; absent for a cantilever fit.
    #[serde(default, flatten, skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<MechRecord>,
    /// The prbfit that made the file.
    pub prbfit_version: String,
    /// UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub created: String,
}

/// The measured data a model was fitted to or judged on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TruthRecord {
    /// The data file as the scene names it.
    pub data: String,
    /// SHA-256 of the file's bytes, lowercase hex.
    pub sha256: String,
    /// Rows (load cases) in the file.
    pub rows: usize,
}

/// What a fit on a mechanism scene adds to its [`FitRecord`]. The record's own figures are
/// then the stage's (units of flexure 1's `L`), and its `objective` is §8's `J`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MechRecord {
    /// `w_f` in `J`.
    pub force_weight: f64,
    /// The matrix in SI for each flexure in order (its own `L` and `E I0`).
    pub flexure_si: Vec<SiModel>,
}

impl ModelFile {
    /// The model as TOML.
    pub fn to_toml(&self) -> Result<String, ModelFileError> {
        toml::to_string(self).map_err(|e| ModelFileError(e.to_string()))
    }

    /// The model as pretty JSON, ending in a newline. Infinite springs are written as the
    /// string `"inf"` (the matrix's own encoding), so nothing becomes `null`.
    pub fn to_json(&self) -> Result<String, ModelFileError> {
        let mut s =
            serde_json::to_string_pretty(self).map_err(|e| ModelFileError(e.to_string()))?;
        s.push('\n');
        Ok(s)
    }

    /// A published model by name, or a file.
    pub fn load(name_or_file: &str) -> Result<ModelFile, SceneError> {
        if let Some(p) = published::by_name(name_or_file) {
            return Ok(ModelFile::from(p));
        }
        let path = Path::new(name_or_file);
        let text = super::files::read_input(path).map_err(|e| SceneError {
            origin: name_or_file.to_string(),
            line: None,
            key: None,
            message: format!(
                "not a published model ({}) and not a readable model file: {}",
                published::NAMES.join(", "),
                e.reason()
            ),
        })?;
        if path.extension().is_some_and(|e| e == "json") {
            let model: ModelFile = serde_json::from_str(&text).map_err(|e| SceneError {
                origin: name_or_file.to_string(),
                line: Some(e.line()),
                key: None,
                message: e.to_string(),
            })?;
            model.check(name_or_file)?;
            Ok(model)
        } else {
            ModelFile::from_toml_str(&text, name_or_file)
        }
    }

    /// Parses a model file's TOML; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<ModelFile, SceneError> {
        let model: ModelFile = toml::from_str(text).map_err(|e| SceneError {
            origin: origin.to_string(),
            line: e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1),
            key: None,
            message: e.message().trim().to_string(),
        })?;
        model.check(origin)?;
        Ok(model)
    }

    fn check(&self, origin: &str) -> Result<(), SceneError> {
        self.check_records().map_err(|e| SceneError {
            origin: origin.to_string(),
            line: None,
            key: Some(e.key),
            message: e.message,
        })?;
        if let Some(topology) = &self.topology {
            let actual = self.prb.topology();
            if *topology != actual {
                return Err(SceneError {
                    origin: origin.to_string(),
                    line: None,
                    key: Some("topology".into()),
                    message: format!("says {topology} but the matrix is {actual}"),
                });
            }
        }
        Ok(())
    }

    /// The file's own account of itself (`[fit]`, `[si]`, `[load_range]`): nothing computes
    /// with it, but a NaN or a negative length there is a corrupt or hand-broken file, and is
    /// refused like one in the matrix.
    fn check_records(&self) -> Result<(), RuleError> {
        if let Some(fit) = &self.fit {
            check_fit(fit).map_err(|e| e.under("fit"))?;
        }
        if let Some(si) = &self.si {
            check_si(si).map_err(|e| e.under("si"))?;
        }
        if let Some(r) = &self.load_range {
            for (key, pair) in [
                ("alpha_x", r.alpha_x),
                ("alpha_y", r.alpha_y),
                ("beta", r.beta),
                ("fx", r.fx),
                ("fy", r.fy),
                ("mz", r.mz),
            ] {
                for v in pair {
                    rules::finite(v).map_err(|m| RuleError::new(key, m).under("load_range"))?;
                }
            }
        }
        Ok(())
    }

    /// A fitted (or hand-made) model of `scene` judged by `figures`, with provenance. On a
    /// mechanism scene (DESIGN §8) the record adds `J`'s force weight and the model in SI for
    /// every flexure (`si` is flexure 1's, which sets the mechanism's units); a mechanism has
    /// drives, not a cantilever's load range, so `load_range` is absent. With the scene's
    /// `[beam] density` every segment's SI entry carries its mass and inertia, and `si` the
    /// scene's `[tip]` body (`tip`) or `[stage]` (`stage`) when it gives one.
    pub fn fitted(
        matrix: &PrbMatrix,
        scene: &Scene,
        fidelity: &str,
        figures: &Figures,
    ) -> ModelFile {
        // One density for every flexure: the scene's `[beam] density`.
        let with_density = |b: &BeamSpec| BeamSpec {
            density: scene.beam.density,
            ..*b
        };
        let body = (!scene.body.is_none()).then_some(scene.body);
        let mechanism = scene.mechanism.as_ref().map(|m| MechRecord {
            force_weight: scene.fit.force_weight,
            flexure_si: m
                .flexures
                .iter()
                .map(|f| si_model(matrix, &with_density(&f.beam)))
                .collect(),
        });
        // The scene's name as every export writes it: control characters replaced (a model
        // file is printed and pasted as often as it is parsed).
        let scene_name = crate::text::sanitize_terminal(&scene.name).into_owned();
        let title = match &mechanism {
            Some(_) => format!("{} fitted to the mechanism {scene_name}", matrix.topology(),),
            None => format!("{} fitted to {scene_name}", matrix.topology()),
        };
        ModelFile {
            name: format!("fitted-{}", matrix.topology().to_lowercase()),
            title: Some(title),
            topology: Some(matrix.topology()),
            source: Some(format!(
                "prbfit {}, fidelity {fidelity}",
                env!("CARGO_PKG_VERSION")
            )),
            conversion: None,
            prb: matrix.clone(),
            si: match &mechanism {
                Some(m) => m
                    .flexure_si
                    .first()
                    .cloned()
                    .map(|si| SiModel { stage: body, ..si }),
                None => Some(SiModel {
                    tip: body,
                    ..si_model(matrix, &scene.beam)
                }),
            },
            load_range: mechanism
                .is_none()
                .then(|| load_range(&scene.beam, &scene.loads)),
            fit: Some(FitRecord {
                scene: scene_name,
                fidelity: fidelity.to_string(),
                stopped_early: None,
                angle_weight: scene.fit.angle_weight,
                figures: *figures,
                truth: scene.truth.as_ref().map(|t| TruthRecord {
                    data: t.file.clone(),
                    sha256: t.sha256.clone(),
                    rows: t.row_count(),
                }),
                mechanism,
                prbfit_version: env!("CARGO_PKG_VERSION").to_string(),
                created: super::files::utc_timestamp(),
            }),
        }
    }
}

impl ModelFile {
    /// This fitted model's record marked as stopped before its fit finished (`why`:
    /// `cancelled`), in its title and its fit record, so that nothing reading the file takes
    /// the best matrix so far for a finished fit.
    pub fn stopped_early(mut self, why: &str) -> ModelFile {
        if let Some(fit) = &mut self.fit {
            fit.stopped_early = Some(why.to_string());
        }
        if let Some(title) = &mut self.title {
            title.push_str(&format!(" (stopped early: {why}; the best so far)"));
        }
        self
    }
}

impl From<published::PublishedModel> for ModelFile {
    fn from(p: published::PublishedModel) -> ModelFile {
        ModelFile {
            name: p.name,
            title: Some(p.title),
            topology: Some(p.topology),
            source: Some(p.source),
            conversion: Some(p.conversion),
            prb: p.prb,
            fit: None,
            si: None,
            load_range: None,
        }
    }
}

/// A model that could not be turned into text (a value the format cannot hold).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the model cannot be written: {0}")]
pub struct ModelFileError(pub String);

/// A fit record's weights and figures: finite and `>= 0`.
fn check_fit(fit: &FitRecord) -> Result<(), RuleError> {
    let f = &fit.figures;
    let mut numbers = vec![
        ("angle_weight", fit.angle_weight),
        ("rms_pos_err", f.rms_pos_err),
        ("max_pos_err", f.max_pos_err),
        ("rms_ang_err", f.rms_ang_err),
        ("max_ang_err", f.max_ang_err),
        ("objective", f.objective),
    ];
    for (key, v) in [
        ("rms_force_err", f.rms_force_err),
        ("max_force_err", f.max_force_err),
        ("max_tip_err", f.max_tip_err),
    ] {
        numbers.extend(v.map(|v| (key, v)));
    }
    if let Some(m) = &fit.mechanism {
        numbers.push(("force_weight", m.force_weight));
    }
    for (key, v) in numbers {
        rules::non_negative(v).map_err(|m| RuleError::new(key, m))?;
    }
    if let Some(m) = &fit.mechanism {
        for (i, si) in m.flexure_si.iter().enumerate() {
            check_si(si).map_err(|e| e.under(&format!("flexure_si[{}]", i + 1)))?;
        }
    }
    Ok(())
}

/// A model in SI: sizes within a scene's ([`rules::size`]), the modulus finite and `> 0`, each
/// segment's length and given springs too, its mass and inertia and the bodies' finite and
/// `>= 0`.
fn check_si(si: &SiModel) -> Result<(), RuleError> {
    for (key, v) in [
        ("beam_length", si.beam_length),
        ("width", si.width),
        ("thickness", si.thickness),
    ] {
        rules::size(v).map_err(|m| RuleError::new(key, m))?;
    }
    rules::positive(si.youngs_modulus).map_err(|m| RuleError::new("youngs_modulus", m))?;
    for (i, seg) in si.segments.iter().enumerate() {
        let at = |e: RuleError| e.under(&format!("segments[{}]", i + 1));
        rules::positive(seg.length).map_err(|m| at(RuleError::new("length", m)))?;
        for (key, v) in [("k_theta", seg.k_theta), ("k_ex", seg.k_ex)] {
            if let Some(v) = v {
                rules::positive(v).map_err(|m| at(RuleError::new(key, m)))?;
            }
        }
        for (key, v) in [("mass", seg.mass), ("inertia", seg.inertia)] {
            if let Some(v) = v {
                rules::non_negative(v).map_err(|m| at(RuleError::new(key, m)))?;
            }
        }
    }
    for (key, body) in [("tip", si.tip), ("stage", si.stage)] {
        if let Some(b) = body {
            b.validate().map_err(|e| e.under(key))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn published_names_load_with_their_provenance() {
        for name in published::NAMES {
            let m = ModelFile::load(name).unwrap();
            assert_eq!(m.name, name);
            assert_eq!(Some(m.prb), published::by_name(name).map(|p| p.prb));
            assert!(m.source.is_some() && m.conversion.is_some());
        }
    }

    /// Distinct figures, each told apart in the file.
    fn figures() -> Figures {
        Figures {
            rms_pos_err: 1.0,
            max_pos_err: 2.0,
            rms_ang_err: 3.0,
            max_ang_err: 4.0,
            objective: 5.0,
            rms_force_err: None,
            max_force_err: None,
            max_tip_err: None,
            max_freq_err: None,
        }
    }

    #[test]
    fn fit_records_flatten_the_figures() {
        let scene = Scene::builtin();
        let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
        let figures = figures();
        let file = ModelFile::fitted(&m, &scene, "normal", &figures);
        let text = file.to_toml().unwrap();
        assert!(text.contains("max_ang_err = 4.0"), "{text}");
        let back = ModelFile::from_toml_str(&text, "t").unwrap();
        assert_eq!(back, file);
        let json = file.to_json().unwrap();
        let back: ModelFile = serde_json::from_str(&json).unwrap();
        assert_eq!(back, file);
    }

    /// A mechanism fit's record carries the reaction figures and every flexure's SI model,
    /// and reads back (TOML and JSON) as written.
    #[test]
    fn mechanism_fit_records_round_trip() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/scenes/parallel-stage.toml"
        );
        let scene = Scene::from_file(Path::new(path)).unwrap();
        let mechanism = scene.mechanism.clone().unwrap();
        let m = PrbMatrix::parse("0.1,inf,inf; 0.8,3,inf; 0.1,3,inf").unwrap();
        let figures = Figures {
            rms_pos_err: 1.0,
            max_pos_err: 2.0,
            rms_ang_err: 3.0,
            max_ang_err: 4.0,
            objective: 5.0,
            rms_force_err: Some(6.0),
            max_force_err: Some(7.0),
            max_tip_err: Some(8.0),
            max_freq_err: None,
        };
        let file = ModelFile::fitted(&m, &scene, "normal", &figures);
        let record = file.fit.as_ref().unwrap().mechanism.as_ref().unwrap();
        assert_eq!(record.flexure_si.len(), mechanism.flexures.len());
        assert_eq!(
            file.si.as_ref().map(|s| &s.segments),
            record.flexure_si.first().map(|s| &s.segments)
        );
        assert!(file.load_range.is_none());
        let text = file.to_toml().unwrap();
        assert!(text.contains("max_force_err = 7.0"), "{text}");
        assert_eq!(ModelFile::from_toml_str(&text, "t").unwrap(), file);
        let back: ModelFile = serde_json::from_str(&file.to_json().unwrap()).unwrap();
        assert_eq!(back, file);
    }

    /// The records a file carries about itself are checked like its matrix: a NaN figure, a
    /// negative SI length, a non-finite load range are refused by key (they were accepted).
    #[test]
    fn broken_records_are_refused_by_key() {
        let scene = Scene::builtin();
        let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
        let good = ModelFile::fitted(&m, &scene, "normal", &figures());
        let text = good.to_toml().unwrap();
        assert_eq!(ModelFile::from_toml_str(&text, "m.toml").unwrap(), good);
        let objective = format!(
            "objective = {:?}",
            good.fit.as_ref().unwrap().figures.objective
        );
        assert!(text.contains(&objective), "{text}");
        let beam_length = format!("beam_length = {:?}", scene.beam.length);
        assert!(text.contains(&beam_length), "{text}");
        for (broken, key, words) in [
            (
                text.replacen(&objective, "objective = nan", 1),
                "fit.objective",
                "finite number >= 0, got NaN",
            ),
            (
                text.replacen(&beam_length, "beam_length = -1.0", 1),
                "si.beam_length",
                "finite number > 0, got -1",
            ),
            (
                text.replacen("alpha_y = [0.0, ", "alpha_y = [inf, ", 1),
                "load_range.alpha_y",
                "finite number, got inf",
            ),
        ] {
            let err = ModelFile::from_toml_str(&broken, "m.toml").unwrap_err();
            assert_eq!(err.key.as_deref(), Some(key), "{err}");
            assert!(err.to_string().contains(words), "{err}");
        }
    }

    #[test]
    fn unknown_names_say_what_exists() {
        let err = ModelFile::load("nosuch-9r").unwrap_err().to_string();
        assert!(err.contains("howell-1r, su-3r, chen-3r"), "{err}");
    }

    /// With `[beam] density` every segment's SI entry carries `mu_i rho A0 L` and the rod's
    /// inertia about its centre, and `si` the tip body; without a density (and body) none of
    /// these keys is written; both read back as written.
    #[test]
    fn model_files_carry_the_masses_in_si_with_a_density() {
        let figures = figures();
        let m = PrbMatrix::parse("0.15,inf,inf,0.25; 0.5,2.2,inf,0.45; 0.35,3,40,0.3").unwrap();
        let mut scene = Scene::builtin();
        scene.beam.density = Some(7850.0);
        scene.body = crate::scene::Body {
            mass: 0.002,
            inertia: 1e-8,
        };
        let file = ModelFile::fitted(&m, &scene, "normal", &figures);
        let b = &scene.beam;
        let rho_a_l = 7850.0 * b.width * b.thickness * b.length;
        let si = file.si.as_ref().unwrap();
        for ((seg, mu), gamma) in si
            .segments
            .iter()
            .zip([0.25, 0.45, 0.3])
            .zip([0.15, 0.5, 0.35])
        {
            let mass = mu * rho_a_l;
            let inertia = mass * (gamma * b.length).powi(2) / 12.0;
            // Products of the same few numbers in another order: a few ulp.
            assert!((seg.mass.unwrap() / mass - 1.0).abs() < 1e-14, "{seg:?}");
            assert!(
                (seg.inertia.unwrap() / inertia - 1.0).abs() < 1e-14,
                "{seg:?}"
            );
        }
        assert_eq!(si.tip, Some(scene.body));
        assert_eq!(si.stage, None);
        let text = file.to_toml().unwrap();
        assert!(
            text.contains("mass = ") && text.contains("[si.tip]"),
            "{text}"
        );
        assert_eq!(ModelFile::from_toml_str(&text, "t").unwrap(), file);
        let back: ModelFile = serde_json::from_str(&file.to_json().unwrap()).unwrap();
        assert_eq!(back, file);

        let plain = ModelFile::fitted(&m, &Scene::builtin(), "normal", &figures);
        let si = plain.si.as_ref().unwrap();
        assert!(si
            .segments
            .iter()
            .all(|s| s.mass.is_none() && s.inertia.is_none()));
        assert!(si.tip.is_none() && si.stage.is_none());
        let text = plain.to_toml().unwrap();
        assert!(
            !text.contains("mass") && !text.contains("inertia"),
            "{text}"
        );
    }

    /// A model file written before the masses (no `mass`, `inertia`, `tip` under `si`) loads,
    /// its SI segments without masses.
    #[test]
    fn an_old_model_file_without_masses_still_loads() {
        let old = r#"name = "fitted-l-r"
title = "L-R fitted to prbfit example"
topology = "L-R"

[[prb]]
gamma = 0.15
k_theta = "inf"
k_ex = "inf"

[[prb]]
gamma = 0.85
k_theta = 2.2525
k_ex = "inf"

[si]
beam_length = 0.1
width = 0.01
thickness = 0.001
youngs_modulus = 200000000000.0

[[si.segments]]
length = 0.015

[[si.segments]]
length = 0.085
k_theta = 37.541666666666664
"#;
        let file = ModelFile::from_toml_str(old, "old.toml").unwrap();
        let si = file.si.unwrap();
        assert_eq!(si.segments.len(), 2);
        assert_eq!(si.segments[1].k_theta, Some(37.541666666666664));
        assert!(si
            .segments
            .iter()
            .all(|s| s.mass.is_none() && s.inertia.is_none()));
        assert!(si.tip.is_none() && si.stage.is_none());
    }
}
