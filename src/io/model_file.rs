//! PRB model files: a matrix plus what it is and where it came from. The published models
//! (Howell 1R, Su 3R, Chen 3R, [`crate::prb::published`]) are compiled in, so `--model su-3r`
//! works from any directory; any other name is read as a file (TOML, or JSON when it ends in
//! `.json`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::eval::ErrorFigures;
use crate::mech::figures::MechFigures;
use crate::prb::{published, PrbMatrix};
use crate::scene::{Mechanism, Scene, SceneError};
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
    /// `w` in J.
    pub angle_weight: f64,
    /// The five figures on the scene.
    #[serde(flatten)]
    pub figures: ErrorFigures,
    /// Mechanism scenes (DESIGN §8): the reaction figures, `J`'s force weight and the model
    /// in SI for every flexure; absent for a cantilever fit.
    #[serde(default, flatten, skip_serializing_if = "Option::is_none")]
    pub mechanism: Option<MechRecord>,
    /// The prbfit that made the file.
    pub prbfit_version: String,
    /// UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub created: String,
}

/// What a fit on a mechanism scene adds to its [`FitRecord`]. The record's own figures are
/// then the stage's (units of flexure 1's `L`), and its `objective` is §8's `J`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MechRecord {
    /// `w_f` in `J`.
    pub force_weight: f64,
    /// RMS of the reaction error, a fraction of each prescribed coordinate's largest reaction.
    pub rms_force_err: f64,
    /// Largest reaction error.
    pub max_force_err: f64,
    /// Largest flexure tip position error, units of that flexure's `L`.
    pub max_tip_err: f64,
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

    /// A fitted (or hand-made) model of `scene`'s beam, with provenance.
    pub fn fitted(
        matrix: &PrbMatrix,
        scene: &Scene,
        fidelity: &str,
        figures: &ErrorFigures,
    ) -> ModelFile {
        ModelFile {
            name: format!("fitted-{}", matrix.topology().to_lowercase()),
            title: Some(format!("{} fitted to {}", matrix.topology(), scene.name)),
            topology: Some(matrix.topology()),
            source: Some(format!(
                "prbfit {}, fidelity {fidelity}",
                env!("CARGO_PKG_VERSION")
            )),
            conversion: None,
            prb: matrix.clone(),
            fit: Some(FitRecord {
                scene: scene.name.clone(),
                fidelity: fidelity.to_string(),
                angle_weight: scene.fit.angle_weight,
                figures: *figures,
                mechanism: None,
                prbfit_version: env!("CARGO_PKG_VERSION").to_string(),
                created: super::files::utc_timestamp(),
            }),
            si: Some(si_model(matrix, &scene.beam)),
            load_range: Some(load_range(&scene.beam, &scene.loads)),
        }
    }

    /// A model fitted on `mechanism` (the mechanism of `scene`), with provenance: the stage
    /// figures and the reaction figures of DESIGN §8, and the model in SI for every flexure
    /// (`si` is flexure 1's, which sets the mechanism's units). A mechanism has drives, not a
    /// cantilever's load range, so `load_range` is absent.
    pub fn fitted_mechanism(
        matrix: &PrbMatrix,
        scene: &Scene,
        mechanism: &Mechanism,
        fidelity: &str,
        figures: &MechFigures,
    ) -> ModelFile {
        let flexure_si: Vec<SiModel> = mechanism
            .flexures
            .iter()
            .map(|f| si_model(matrix, &f.beam))
            .collect();
        // The stage's five figures of §4 (`objective` is §8's `J`, the reaction term included).
        let stage = ErrorFigures {
            rms_pos_err: figures.rms_pos_err,
            max_pos_err: figures.max_pos_err,
            rms_ang_err: figures.rms_ang_err,
            max_ang_err: figures.max_ang_err,
            objective: figures.objective,
        };
        let mut file = ModelFile::fitted(matrix, scene, fidelity, &stage);
        file.title = Some(format!(
            "{} fitted to the mechanism {}",
            matrix.topology(),
            scene.name
        ));
        file.si = flexure_si.first().cloned();
        file.load_range = None;
        if let Some(fit) = file.fit.as_mut() {
            fit.mechanism = Some(MechRecord {
                force_weight: scene.fit.force_weight,
                rms_force_err: figures.rms_force_err,
                max_force_err: figures.max_force_err,
                max_tip_err: figures.max_tip_err,
                flexure_si,
            });
        }
        file
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

    #[test]
    fn fit_records_flatten_the_figures() {
        let scene = Scene::builtin();
        let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
        let figures = ErrorFigures {
            rms_pos_err: 1.0,
            max_pos_err: 2.0,
            rms_ang_err: 3.0,
            max_ang_err: 4.0,
            objective: 5.0,
        };
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
        let figures = MechFigures {
            rms_pos_err: 1.0,
            max_pos_err: 2.0,
            rms_ang_err: 3.0,
            max_ang_err: 4.0,
            objective: 5.0,
            rms_force_err: 6.0,
            max_force_err: 7.0,
            max_tip_err: 8.0,
        };
        let file = ModelFile::fitted_mechanism(&m, &scene, &mechanism, "normal", &figures);
        let record = file.fit.as_ref().unwrap().mechanism.as_ref().unwrap();
        assert_eq!(record.flexure_si.len(), mechanism.flexures.len());
        assert_eq!(file.si.as_ref(), record.flexure_si.first());
        assert!(file.load_range.is_none());
        let text = file.to_toml().unwrap();
        assert!(text.contains("max_force_err = 7.0"), "{text}");
        assert_eq!(ModelFile::from_toml_str(&text, "t").unwrap(), file);
        let back: ModelFile = serde_json::from_str(&file.to_json().unwrap()).unwrap();
        assert_eq!(back, file);
    }

    #[test]
    fn unknown_names_say_what_exists() {
        let err = ModelFile::load("nosuch-9r").unwrap_err().to_string();
        assert!(err.contains("howell-1r, su-3r, chen-3r"), "{err}");
    }
}
