//! `prbfit plot`: the UI's charts as an SVG or PNG figure, for papers and design reviews.

use std::fmt;

use anyhow::{Context, Result};
use clap::ArgMatches;
use serde::Serialize;

use prbfit::io::files::{check_target, write_atomic};
use prbfit::io::ModelFile;
use prbfit::plot::{
    render, ChartKind, Figure, ImageFormat, PlotError, PlotModel, Unfollowed, MODEL_RGB,
};
use prbfit::scene::Scene;

use super::args::PlotArgs;
use super::output::{emit, safe};
use super::{bad, parse_matrix, resolved_scene, scene_model};

/// A model drawn.
#[derive(Debug, Serialize)]
struct ModelEntry {
    name: String,
    prb: String,
}

/// What was written.
#[derive(Debug, Serialize)]
pub struct PlotOutput {
    output: String,
    format: ImageFormat,
    kind: ChartKind,
    /// The load path whose shapes are drawn (1-based).
    path: usize,
    /// The model first, then the compared ones.
    models: Vec<ModelEntry>,
    width: u32,
    height: u32,
    bytes: usize,
    /// Load paths a model could not follow to the end (drawn as far as it got).
    unfollowed: Vec<Unfollowed>,
}

impl fmt::Display for PlotOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<String> = self.models.iter().map(|m| safe(&m.name).into()).collect();
        let what = match self.kind {
            ChartKind::Shapes => format!("deformed shapes of load path {}", self.path),
            ChartKind::Errors => "tip errors of every load path".to_string(),
            ChartKind::All => format!(
                "deformed shapes of load path {} and tip errors of every load path",
                self.path
            ),
        };
        let models = match names.split_first() {
            Some((first, [])) => first.clone(),
            Some((first, rest)) => format!("{first} against {}", rest.join(", ")),
            None => String::new(),
        };
        writeln!(
            f,
            "wrote {} ({} x {} {}, {} bytes): {what}; {models}",
            safe(&self.output),
            self.width,
            self.height,
            self.format,
            self.bytes,
        )?;
        for u in &self.unfollowed {
            writeln!(
                f,
                "note: {} reaches only {} of the {} cases of load path {} (drawn up to there)",
                safe(&u.model),
                u.reached,
                u.steps,
                u.path
            )?;
        }
        Ok(())
    }
}

/// One model as given on the command line.
enum Given<'a> {
    Model(&'a str),
    Prb(&'a str),
}

/// The models in the order they were given (--model and --prb interleaved, as the matches'
/// indices say); with none, the scene's own. Repeated names get a number so the legend tells
/// them apart.
fn models(args: &PlotArgs, matches: Option<&ArgMatches>, scene: &Scene) -> Result<Vec<PlotModel>> {
    let index = |id: &str, n: usize| -> Vec<usize> {
        matches
            .and_then(|m| m.indices_of(id))
            .map(|i| i.collect())
            .unwrap_or_else(|| (0..n).collect())
    };
    let mut given: Vec<(usize, Given<'_>)> = Vec::new();
    for (i, m) in index("model", args.model.len())
        .into_iter()
        .zip(&args.model)
    {
        given.push((i, Given::Model(m)));
    }
    let after = args.model.len();
    for (i, p) in index("prb", args.prb.len()).into_iter().zip(&args.prb) {
        // Without matches (never from the command line) the --prbs follow the --models.
        given.push((if matches.is_some() { i } else { after + i }, Given::Prb(p)));
    }
    given.sort_by_key(|(i, _)| *i);

    let mut out: Vec<PlotModel> = Vec::with_capacity(given.len().max(1));
    for (_, g) in given {
        let (name, matrix) = match g {
            Given::Model(m) => {
                let file = ModelFile::load(m)?;
                (file.name, file.prb)
            }
            Given::Prb(text) => {
                let m = parse_matrix("--prb", text)?;
                (m.topology().to_lowercase(), m)
            }
        };
        let taken = out.iter().filter(|o| o.name == name).count();
        let name = if taken > 0 {
            format!("{name} #{}", taken + 1)
        } else {
            name
        };
        out.push(PlotModel { name, matrix });
    }
    if out.is_empty() {
        let (name, matrix) = scene_model(scene)?;
        out.push(PlotModel { name, matrix });
    }
    Ok(out)
}

/// Runs `prbfit plot`; `matches` are the subcommand's, for the order of the models.
pub fn run(args: PlotArgs, matches: Option<&ArgMatches>) -> Result<()> {
    let format = ImageFormat::from_path(&args.output).ok_or_else(|| {
        bad(format!(
            "-o {}: the figure's file name must end in {}",
            args.output.display(),
            ImageFormat::EXTENSIONS
        ))
    })?;
    // Refuse before spending the time on a baseline.
    check_target(&args.output, args.force)?;
    let (scene, _) = resolved_scene(&args.common, "plot")?;
    if args.path == 0 || args.path > scene.loads.len() {
        return Err(bad(format!(
            "--path {}: the scene has {} load path(s), numbered from 1",
            args.path,
            scene.loads.len()
        )));
    }
    let models = models(&args, matches, &scene)?;
    if models.len() > MODEL_RGB.len() {
        return Err(bad(format!(
            "--model/--prb: at most {} models fit in one figure, got {}",
            MODEL_RGB.len(),
            models.len()
        )));
    }
    let baseline = args.fidelity.baseline(&scene).context("baseline beam")?;
    let figure =
        Figure::build(&scene, &baseline, &models, args.path, args.kind).map_err(|e| match e {
            PlotError::NoSuchPath { .. } => bad(format!("--path {}: {e}", args.path)),
            PlotError::TooManyModels { .. } => bad(format!("--model/--prb: {e}")),
            other => anyhow::Error::new(other),
        })?;
    let bytes = render(&figure, format)?;
    write_atomic(&args.output, &bytes, args.force)?;
    let (width, height) = prbfit::plot::canvas_size(args.kind);
    let out = PlotOutput {
        output: args.output.display().to_string(),
        format,
        kind: args.kind,
        path: args.path,
        models: models
            .iter()
            .map(|m| ModelEntry {
                name: m.name.clone(),
                prb: m.matrix.to_text(),
            })
            .collect(),
        width,
        height,
        bytes: bytes.len(),
        unfollowed: figure.unfollowed,
    };
    emit(&out, args.common.json)
}
