//! The IO layer: everything that reads or writes a file. It sits above the numerical core
//! (beam, prb, eval, fit) and below the commands and the UI, so the core never touches the
//! file system and the commands never parse files themselves.
//!
//! - [`files`]: safe writing (atomic, never over a device or through a link into a file),
//! - [`model_file`]: PRB model files (the matrix, its provenance and figures),
//! - scene files: [`Scene::from_file`] reads and validates one.

pub mod files;
pub mod model_file;

use std::path::Path;

use crate::scene::{Scene, SceneError};

pub use model_file::{FitRecord, ModelFile, ModelFileError};

impl Scene {
    /// Reads and validates a scene file (a regular file of at most
    /// [`files::MAX_INPUT_BYTES`]; devices, fifos and directories are refused before reading).
    pub fn from_file(path: &Path) -> Result<Scene, SceneError> {
        let origin = path.display().to_string();
        let text = files::read_input(path).map_err(|e| SceneError {
            origin: origin.clone(),
            line: None,
            key: None,
            message: format!("cannot read the scene file: {}", e.reason()),
        })?;
        let mut scene = Scene::from_toml_str(&text, &origin)?;
        if let Some(truth) = &scene.truth {
            let base = path.parent().unwrap_or(Path::new("."));
            let file = base.join(&truth.file);
            let located = |mut e: SceneError| {
                if e.line.is_none() && e.origin == file.display().to_string() {
                    // A file that cannot be read: the scene's key that names it.
                    e.origin = origin.clone();
                    e.key = Some("truth.data".into());
                }
                e
            };
            if let Some(m) = &scene.mechanism {
                let (stage, sha256) = read_stage_data(&file, m).map_err(located)?;
                scene.set_measured_stage(stage, sha256);
            } else {
                let (paths, units, sha256) = read_data(&file, &scene.beam).map_err(located)?;
                scene.set_measured(paths, units, sha256);
            }
        }
        Ok(scene)
    }
}

/// Reads and checks a data file (DESIGN §9) with `beam` as the nominal beam: its paths, the
/// unit system of its columns and the SHA-256 of its bytes (lowercase hex).
pub fn read_data(
    file: &Path,
    beam: &crate::scene::BeamSpec,
) -> Result<
    (
        Vec<crate::scene::data::MeasuredPath>,
        crate::scene::data::Units,
        String,
    ),
    SceneError,
> {
    let (text, hex) = read_hashed(file)?;
    let (paths, units) = crate::scene::data::parse_csv(&text, &file.display().to_string(), beam)?;
    Ok((paths, units, hex))
}

/// Reads and checks a mechanism's data file (DESIGN §9 with §8), converted for its checks
/// with `mechanism`'s scale: its measured drive paths and the SHA-256 of its bytes.
pub fn read_stage_data(
    file: &Path,
    mechanism: &crate::scene::Mechanism,
) -> Result<(crate::scene::data::StageData, String), SceneError> {
    let (text, hex) = read_hashed(file)?;
    let stage = crate::scene::data::parse_stage_csv(&text, &file.display().to_string(), mechanism)?;
    Ok((stage, hex))
}

/// A data file's text and the SHA-256 of its bytes (lowercase hex).
fn read_hashed(file: &Path) -> Result<(String, String), SceneError> {
    use sha2::Digest;
    let shown = file.display().to_string();
    let text = files::read_input(file).map_err(|e| SceneError {
        origin: shown.clone(),
        line: None,
        key: None,
        message: format!("cannot read the data file {shown}: {}", e.reason()),
    })?;
    let hash = sha2::Sha256::digest(text.as_bytes());
    let hex: String = hash.iter().map(|b| format!("{b:02x}")).collect();
    Ok((text, hex))
}
