//! PRB model files: a matrix plus what it is and where it came from. The published models
//! (Howell 1R, Su 3R, Chen 3R) ship in `assets/models/` and are compiled in, so `--model
//! su-3r` works from any directory; any other name is read as a file (TOML, or JSON when it
//! ends in `.json`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::prb::PrbMatrix;

use super::SceneError;

/// The published models: name and file text.
pub const PUBLISHED: [(&str, &str); 3] = [
    (
        "howell-1r",
        include_str!("../../assets/models/howell-1r.toml"),
    ),
    ("su-3r", include_str!("../../assets/models/su-3r.toml")),
    ("chen-3r", include_str!("../../assets/models/chen-3r.toml")),
];

/// A PRB model file. Unknown keys are allowed (richer exports carry more), but what is
/// here is checked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub topology: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conversion: Option<String>,
    pub prb: PrbMatrix,
    /// How a fitted model was made, and how well it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitRecord>,
    /// The model in SI units for the scene's beam (exports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub si: Option<crate::export::SiModel>,
    /// The scene's load range (exports).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_range: Option<crate::export::LoadRange>,
}

/// Provenance and error figures of a fitted model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitRecord {
    pub scene: String,
    pub fidelity: String,
    pub angle_weight: f64,
    pub rms_pos_err: f64,
    pub max_pos_err: f64,
    pub rms_ang_err: f64,
    pub max_ang_err: f64,
    pub objective: f64,
    pub prbfit_version: String,
    /// UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub created: String,
}

/// The format a model file is written in, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelFormat {
    Toml,
    Json,
}

impl ModelFormat {
    /// `.toml` or `.json`; anything else is an error naming the file.
    pub fn from_path(path: &Path) -> Result<ModelFormat, String> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("toml") => Ok(ModelFormat::Toml),
            Some("json") => Ok(ModelFormat::Json),
            _ => Err(format!(
                "{}: a model file must end in .toml or .json",
                path.display()
            )),
        }
    }
}

impl ModelFile {
    /// The model as text in `format`.
    pub fn to_text(&self, format: ModelFormat) -> String {
        match format {
            ModelFormat::Toml => toml::to_string(self).expect("a model serialises to TOML"),
            ModelFormat::Json => {
                let mut s = serde_json::to_string_pretty(self).expect("a model serialises to JSON");
                s.push('\n');
                s
            }
        }
    }

    /// A published model by name, or a file.
    pub fn load(name_or_file: &str) -> Result<ModelFile, SceneError> {
        if let Some((_, text)) = PUBLISHED.iter().find(|(n, _)| *n == name_or_file) {
            return ModelFile::from_toml_str(text, &format!("<model {name_or_file}>"));
        }
        let path = Path::new(name_or_file);
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            origin: name_or_file.to_string(),
            line: None,
            key: None,
            message: format!(
                "not a published model ({}) and not a readable file: {e}",
                PUBLISHED.map(|p| p.0).join(", ")
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
        scene: &super::Scene,
        fidelity: &str,
        figures: &crate::eval::ErrorFigures,
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
                rms_pos_err: figures.rms_pos_err,
                max_pos_err: figures.max_pos_err,
                rms_ang_err: figures.rms_ang_err,
                max_ang_err: figures.max_ang_err,
                objective: figures.objective,
                prbfit_version: env!("CARGO_PKG_VERSION").to_string(),
                created: crate::files::utc_timestamp(),
            }),
            si: Some(crate::export::si_model(matrix, scene)),
            load_range: Some(crate::export::load_range(scene)),
        }
    }

    /// All published models, parsed.
    pub fn published() -> Vec<ModelFile> {
        PUBLISHED
            .iter()
            .map(|(n, _)| ModelFile::load(n).expect("published models are valid (tested)"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn published_models_load_and_match_design() {
        let texts = [
            ("howell-1r", "0.15,inf,inf; 0.85,2.2525,inf"),
            (
                "su-3r",
                "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf",
            ),
            (
                "chen-3r",
                "0.126,inf,inf; 0.35,3.25,inf; 0.388,2.84,inf; 0.136,2.95,inf",
            ),
        ];
        for (name, text) in texts {
            let m = ModelFile::load(name).unwrap();
            assert_eq!(m.name, name);
            assert_eq!(m.prb, PrbMatrix::parse(text).unwrap());
            assert!(m.source.is_some() && m.conversion.is_some());
        }
    }

    #[test]
    fn unknown_names_say_what_exists() {
        let err = ModelFile::load("nosuch-9r").unwrap_err().to_string();
        assert!(err.contains("howell-1r, su-3r, chen-3r"), "{err}");
    }
}
