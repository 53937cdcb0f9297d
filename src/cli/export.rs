//! `prbfit export`: a model written for another tool, by
//! [`prbfit::study::Study::export`]. On a mechanism scene (DESIGN §8) the whole PRB mechanism
//! is written (MuJoCo MJCF) or the model file; other formats are refused as bad input (exit
//! status 2) naming the ones that work.

use std::fmt;

use anyhow::Result;
use serde::Serialize;

use prbfit::export::ExportError;
use prbfit::format::Format;
use prbfit::io::files::{check_target, write_atomic};
use prbfit::io::ModelFile;
use prbfit::prb::PrbMatrix;
use prbfit::scene::Scene;
use prbfit::study::Sampling;

use super::args::ExportArgs;
use super::output::{emit, safe};
use super::{bad, load_scene, parse_matrix, scene_model, study};

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

/// Runs `prbfit export`.
pub fn run(args: ExportArgs) -> Result<()> {
    let format = match args.format {
        Some(f) => f,
        None => Format::from_path(&args.output).ok_or_else(|| {
            bad(format!(
                "-o {}: give --format, or a file name ending in one of {}",
                args.output.display(),
                Format::extensions_help()
            ))
        })?,
    };
    // Refuse before spending the time on a baseline: an existing file without --force, a
    // device, a dangling link.
    check_target(&args.output, args.force)?;
    let scene = load_scene(&args.common)?;
    let (name, matrix) = model(&args, &scene)?;
    let study = study(&scene, Sampling::Fidelity(args.fidelity))?;
    let text = study
        .export(&name, &matrix, format, args.density)
        .map_err(input_error)?;
    write_atomic(&args.output, text.as_bytes(), args.force)?;
    let out = ExportOutput {
        output: args.output.display().to_string(),
        format,
        prb: matrix.to_text(),
        bytes: text.len(),
    };
    emit(&out, args.common.json)
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
fn input_error(e: ExportError) -> anyhow::Error {
    match e {
        ExportError::Density(_) => bad(format!("--density: {e}")),
        ExportError::MechanismFormat { .. } => bad(format!("--format: {e}")),
        other => anyhow::Error::new(other),
    }
}
