//! `prbfit export`: a model written for another tool, by
//! [`crate::study::Study::export`]. On a mechanism scene (DESIGN §8) the whole PRB mechanism
//! is written (MuJoCo MJCF) or the model file; other formats are refused as bad input (exit
//! status 2) naming the ones that work.

use std::fmt;

use std::path::PathBuf;

use serde::Serialize;

use crate::export::ExportError;
use crate::fidelity::Fidelity;
use crate::format::Format;
use crate::io::files::{check_target, write_atomic};
use crate::io::ModelFile;
use crate::prb::PrbMatrix;
use crate::scene::Scene;
use crate::study::Sampling;

use super::{parse_matrix, safe, scene_model, study, Control, ReportError, Result};

/// `export`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct ExportArgs {
    /// A PRB matrix in text form (`--prb`).
    pub prb: Option<String>,
    /// A published model or a model file (`--model`); it and `prb` are exclusive. With
    /// neither: the scene's `[prb] matrix`.
    pub model: Option<String>,
    /// The format; default: from the output file's extension.
    pub format: Option<Format>,
    /// The file to write (`-o`).
    pub output: PathBuf,
    /// Overwrite the file if it exists.
    pub force: bool,
    /// Density for the masses, kg/m^3; `None`: the scene's `[beam] density`, else
    /// [`DEFAULT_DENSITY`].
    pub density: Option<f64>,
    /// Fidelity of the baseline the figures and the CSV come from.
    pub fidelity: Fidelity,
}

impl ExportArgs {
    /// The arguments that write `output` with the defaults of the CLI's flags.
    pub fn new(output: PathBuf) -> ExportArgs {
        ExportArgs {
            prb: None,
            model: None,
            format: None,
            output,
            force: false,
            density: None,
            fidelity: Fidelity::Normal,
        }
    }
}

pub use crate::study::export::DEFAULT_DENSITY;

/// What was written.
#[derive(Debug, Serialize)]
pub struct ExportOutput {
    output: String,
    format: Format,
    prb: String,
    bytes: usize,
}

impl fmt::Display for ExportOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "wrote {} ({} bytes)", safe(&self.output), self.bytes)
    }
}

/// The format `args` write, and the output checked (an existing file without `force`, a
/// device, a dangling link are refused): what `export` refuses before it loads a scene.
pub fn target(args: &ExportArgs) -> Result<Format> {
    let format = match args.format {
        Some(f) => f,
        None => Format::from_path(&args.output).ok_or_else(|| {
            ReportError::input(format!(
                "-o {}: give --format, or a file name ending in one of {}",
                args.output.display(),
                Format::extensions_help()
            ))
        })?,
    };
    // Refuse before spending the time on a baseline: an existing file without --force, a
    // device, a dangling link.
    check_target(&args.output, args.force)?;
    Ok(format)
}

/// `prbfit export` on `scene`: writes the file and says what it wrote.
pub fn export(scene: &Scene, args: &ExportArgs, ctl: &mut Control<'_>) -> Result<ExportOutput> {
    let format = target(args)?;
    let (name, matrix) = model(args, scene)?;
    let study = study(scene, Sampling::Fidelity(args.fidelity), ctl)?;
    let text = study
        .export(&name, &matrix, format, args.density)
        .map_err(input_error)?;
    // Cancelled while the model was judged (a mechanism's judge has no token to stop it):
    // nothing is written.
    if ctl.cancel.is_cancelled() {
        return Err(ReportError::solve("cancelled: nothing was written"));
    }
    write_atomic(&args.output, text.as_bytes(), args.force)?;
    let out = ExportOutput {
        output: args.output.display().to_string(),
        format,
        prb: matrix.to_text(),
        bytes: text.len(),
    };
    Ok(out)
}

/// The model to export and its name: --model, --prb, or the scene's own.
fn model(args: &ExportArgs, scene: &Scene) -> Result<(String, PrbMatrix)> {
    Ok(match (&args.model, &args.prb) {
        (Some(m), _) => {
            let file = ModelFile::load(m)?;
            (file.name, file.prb)
        }
        (None, Some(text)) => {
            let m = parse_matrix("--prb", text)?;
            (m.topology().to_lowercase(), m)
        }
        (None, None) => scene_model(scene)?,
    })
}

/// Errors the user can fix by changing a flag are bad input (exit status 2).
fn input_error(e: ExportError) -> ReportError {
    match e {
        ExportError::Density(_) => ReportError::input(format!("--density: {e}")),
        ExportError::MechanismFormat { .. } => ReportError::input(format!("--format: {e}")),
        other => ReportError::failed(&other),
    }
}
