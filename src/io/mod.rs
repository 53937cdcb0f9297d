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
        Scene::from_toml_str(&text, &origin)
    }
}
