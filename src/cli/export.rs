//! `prbfit export`: a model written for another tool.

use std::fmt;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::export::{export, ExportError, ExportInput};
use prbfit::format::Format;
use prbfit::io::files::{check_target, write_atomic};
use prbfit::io::ModelFile;

use super::args::ExportArgs;
use super::output::{emit, safe};
use super::{bad, parse_matrix, resolved_scene, scene_model};

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
    let (scene, _) = resolved_scene(&args.common, "export")?;
    let (name, matrix) = match (&args.model, &args.prb) {
        (Some(m), _) => {
            let file = ModelFile::load(m)?;
            (file.name, file.prb)
        }
        (None, Some(text)) => {
            let m = parse_matrix("--prb", text)?;
            (m.topology().to_lowercase(), m)
        }
        (None, None) => scene_model(&scene)?,
    };
    let baseline = args.fidelity.baseline(&scene).context("baseline beam")?;
    let input = ExportInput {
        name,
        matrix: &matrix,
        scene: &scene,
        baseline: &baseline,
        fidelity: args.fidelity.to_string(),
        density: args.density,
    };
    let text = export(&input, format).map_err(|e| match e {
        ExportError::Density(_) => bad(format!("--density: {e}")),
        other => anyhow::Error::new(other),
    })?;
    write_atomic(&args.output, text.as_bytes(), args.force)?;
    let out = ExportOutput {
        output: args.output.display().to_string(),
        format,
        prb: matrix.to_text(),
        bytes: text.len(),
    };
    emit(&out, args.common.json)
}
