//! `prbfit plot`: the UI's charts as an SVG or PNG figure, for papers and design reviews.
//! A mechanism scene (DESIGN §8) gets its force–stroke chart ([`prbfit::plot::mech`]): the
//! kinds `force`, `motion` and `all` apply there, `shapes` and `errors` to cantilevers.

use std::fmt;

use anyhow::{Context, Result};
use clap::ArgMatches;
use serde::Serialize;

use prbfit::beam::{BeamSolver, Resolution};
use prbfit::io::files::{check_target, write_atomic};
use prbfit::io::ModelFile;
use prbfit::plot::{
    mech, render, ChartKind, Figure, ImageFormat, Output, PlotError, PlotModel, Unfollowed,
    MODEL_RGB,
};
use prbfit::scene::data::DataTruth;
use prbfit::scene::{Scene, COORDINATE_KEYS};
use prbfit::study::{CaseForm, Sampling, Study};

use super::args::PlotArgs;
use prbfit::report::safe;

use super::output::emit;
use super::{bad, load_scene, parse_matrix, scene_model, study};

/// A model drawn.
#[derive(Debug, Serialize)]
struct ModelEntry {
    name: String,
    prb: String,
}

/// One panel of a mechanism's force–stroke chart.
#[derive(Debug, Serialize)]
struct PanelEntry {
    /// The drive path, from 1.
    drive: usize,
    /// The stage coordinate: `dx`, `dy` or `dphi`.
    coordinate: &'static str,
    /// `reaction` (a prescribed coordinate) or `motion` (a loaded one).
    output: &'static str,
    x_label: String,
    y_label: String,
}

/// What was written.
#[derive(Debug, Serialize)]
pub struct PlotOutput {
    output: String,
    format: ImageFormat,
    kind: ChartKind,
    /// The load path whose shapes are drawn (1-based); absent for a mechanism scene, whose
    /// figure draws every drive.
    #[serde(skip_serializing_if = "Option::is_none")]
    path: Option<usize>,
    /// A mechanism scene's panels, in the figure's order (row by row).
    #[serde(skip_serializing_if = "Option::is_none")]
    panels: Option<Vec<PanelEntry>>,
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
        let path = self.path.unwrap_or(1);
        let what = match (&self.panels, self.kind) {
            (Some(panels), _) => {
                let list: Vec<String> = panels
                    .iter()
                    .map(|p| format!("drive {} {}", p.drive, safe(&p.y_label)))
                    .collect();
                format!(
                    "force-stroke chart, {} panel(s): {}",
                    panels.len(),
                    list.join(", ")
                )
            }
            (None, ChartKind::Stress) => {
                "largest fibre stress against the load, every path".to_string()
            }
            (None, ChartKind::Shapes) => format!("deformed shapes of load path {path}"),
            (None, ChartKind::Errors) => "tip errors of every load path".to_string(),
            (None, _) => {
                format!("deformed shapes of load path {path} and tip errors of every load path")
            }
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
            if let Some(reason) = &u.reason {
                writeln!(
                    f,
                    "note: {} reaches only {} of the {} cases of drive {} ({}): {}",
                    safe(&u.model),
                    u.reached,
                    u.steps,
                    u.path,
                    if u.reached == 0 {
                        "not drawn"
                    } else {
                        "drawn up to there"
                    },
                    safe(reason)
                )?;
                continue;
            }
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
    // The models' own names so far: the third `su-3r` is `su-3r #3`.
    let mut names: Vec<String> = Vec::with_capacity(given.len());
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
        let taken = names.iter().filter(|n| **n == name).count();
        names.push(name.clone());
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
    let scene = load_scene(&args.common)?;
    let kind_fits = match scene.mechanism {
        _ if args.kind == ChartKind::Stress => true,
        Some(_) => args.kind.has_force() || args.kind.has_motion(),
        None => args.kind.has_shapes() || args.kind.has_errors(),
    };
    if !kind_fits {
        return Err(bad(PlotError::KindNotForScene {
            kind: args.kind,
            mechanism: scene.mechanism.is_some(),
        }
        .to_string()));
    }
    if args.kind == ChartKind::Stress && scene.truth.is_some() {
        return Err(bad(PlotError::NoStress {
            scene: scene.name.clone(),
        }
        .to_string()));
    }
    if scene.mechanism.is_none() && (args.path == 0 || args.path > scene.loads.len()) {
        return Err(bad(format!(
            "--path {}: the scene has {} load path(s), numbered from 1",
            args.path,
            scene.loads.len()
        )));
    }
    // The truth at the fidelity's resolution; a mechanism's drives drawn case by case as the
    // scene gives them, a cantilever's load paths as the fit samples them.
    let sampling = match scene.mechanism {
        Some(_) => Sampling::Every(args.fidelity.resolution()),
        None => Sampling::Fidelity(args.fidelity),
    };
    let study = study(&scene, sampling)?;
    let scene = study.scene();
    if args.kind == ChartKind::Stress {
        let models = models(&args, matches, scene)?;
        let figure = Figure::stress(&study, &models).map_err(|e| match e {
            PlotError::TooManyModels { .. } => bad(format!("--model/--prb: {e}")),
            PlotError::NoStress { .. } => bad(e.to_string()),
            other => anyhow::Error::new(other),
        })?;
        return write_figure(&args, format, figure, &models, None);
    }
    if study.case_form() == CaseForm::Stage {
        return run_mechanism(&args, matches, &study, format);
    }
    let models = models(&args, matches, scene)?;
    if models.len() > MODEL_RGB.len() {
        return Err(bad(format!(
            "--model/--prb: at most {} models fit in one figure, got {}",
            MODEL_RGB.len(),
            models.len()
        )));
    }
    let baseline = study
        .baseline()
        .context("internal error: a cantilever plot on a mechanism scene")?;
    let mut figure =
        Figure::build(scene, baseline, &models, args.path, args.kind).map_err(|e| match e {
            PlotError::NoSuchPath { .. } => bad(format!("--path {}: {e}", args.path)),
            PlotError::TooManyModels { .. } => bad(format!("--model/--prb: {e}")),
            PlotError::KindNotForScene { .. } => bad(e.to_string()),
            other => anyhow::Error::new(other),
        })?;
    if let (Some(truth), true) = (&scene.truth, args.kind.has_shapes()) {
        figure = figure.with_beam_beside(beam_beside(scene, truth, args.path));
    }
    write_figure(&args, format, figure, &models, Some(args.path))
}

/// The scene's nominal beam at each measured load of data path `path` (1-based), each solved
/// from rest as `eval` judges it against the data: the centre lines drawn beside the measured
/// tips. A row the beam cannot reach has no line (eval reports why).
fn beam_beside(scene: &Scene, truth: &DataTruth, path: usize) -> Vec<Vec<[f64; 2]>> {
    let Ok(solver) = BeamSolver::new(scene.beam.model(), Resolution::default()) else {
        return Vec::new();
    };
    truth
        .paths
        .get(path.saturating_sub(1))
        .map(|p| {
            p.rows
                .iter()
                .filter_map(|r| solver.solve(r.load).ok())
                .map(|s| s.shape.iter().map(|q| [q.x, q.y]).collect())
                .collect()
        })
        .unwrap_or_default()
}

/// Renders `figure`, writes it and reports what was written.
fn write_figure(
    args: &PlotArgs,
    format: ImageFormat,
    figure: Figure,
    models: &[PlotModel],
    path: Option<usize>,
) -> Result<()> {
    let bytes = render(&figure, format)?;
    write_atomic(&args.output, &bytes, args.force)?;
    let (width, height) = figure.size();
    let panels = figure.force_stroke.as_ref().map(|chart| {
        chart
            .panels
            .iter()
            .map(|p| PanelEntry {
                drive: p.drive,
                coordinate: COORDINATE_KEYS[p.coordinate.min(2)].0,
                output: match p.output {
                    Output::Reaction => "reaction",
                    Output::Motion => "motion",
                },
                x_label: p.x_label.clone(),
                y_label: p.y_label.clone(),
            })
            .collect()
    });
    let out = PlotOutput {
        output: args.output.display().to_string(),
        format,
        kind: args.kind,
        path,
        panels,
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

/// `prbfit plot` on a mechanism scene (DESIGN §8): the force–stroke chart of every drive,
/// the study's truth (the exact mechanism, or measured data) and each model's PRB mechanism.
fn run_mechanism(
    args: &PlotArgs,
    matches: Option<&ArgMatches>,
    study: &Study,
    format: ImageFormat,
) -> Result<()> {
    let scene = study.scene();
    let kind_error = |e: PlotError| bad(e.to_string());
    if args.path != 1 {
        return Err(bad(format!(
            "--path {}: \"{}\" is a mechanism scene, and its figure draws every drive path \
             (the shapes of one load path are a cantilever scene's)",
            args.path,
            safe(&scene.name)
        )));
    }
    let models = models(args, matches, scene)?;
    if models.len() > MODEL_RGB.len() {
        return Err(bad(format!(
            "--model/--prb: at most {} models fit in one figure, got {}",
            MODEL_RGB.len(),
            models.len()
        )));
    }
    let figure = mech::figure_from(
        scene,
        study.mechanism(),
        study.truth(),
        &models,
        args.fidelity.resolution().tol,
        args.kind,
    )
    .map_err(|e| match e {
        PlotError::KindNotForScene { .. } | PlotError::NothingToDraw { .. } => kind_error(e),
        PlotError::TooManyModels { .. } => bad(format!("--model/--prb: {e}")),
        other => {
            anyhow::Error::new(other).context(format!("mechanism scene \"{}\"", safe(&scene.name)))
        }
    })?;
    write_figure(args, format, figure, &models, None)
}
