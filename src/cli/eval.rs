//! `prbfit eval`: PRB models judged against the beam, at one load or over the scene.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::beam::{BeamSolver, Load, Resolution, TipPose};
use prbfit::cancel::CancelToken;
use prbfit::eval::{evaluate, Baseline, CaseError, ErrorFigures};
use prbfit::io::ModelFile;
use prbfit::prb::{PrbMatrix, PrbSolver};
use prbfit::scene::{Accuracy, Scene};
use prbfit::select::EffectsDecision;

use super::args::EvalArgs;
use super::output::{emit, met, num, safe, DecisionLine, Progress};
use super::{bad, load_scene, parse_matrix, resolve_scene, scene_model};

/// One model's row, or several under `models` (DESIGN §6).
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum OneOrMany<T> {
    /// A single model: its fields at the top level.
    One(T),
    /// Several models.
    Many {
        /// In the order given.
        models: Vec<T>,
    },
}

impl<T> OneOrMany<T> {
    pub(super) fn new(mut rows: Vec<T>) -> OneOrMany<T> {
        if rows.len() == 1 {
            if let Some(one) = rows.pop() {
                return OneOrMany::One(one);
            }
        }
        OneOrMany::Many { models: rows }
    }

    pub(super) fn rows(&self) -> &[T] {
        match self {
            OneOrMany::One(t) => std::slice::from_ref(t),
            OneOrMany::Many { models } => models,
        }
    }
}

/// A model at one load.
#[derive(Debug, Serialize)]
pub struct AtLoad {
    model: String,
    prb: String,
    load: Load,
    #[serde(flatten)]
    tip: TipPose,
    pos_err: f64,
    ang_err: f64,
    beam: TipPose,
}

/// `eval --load`.
#[derive(Debug, Serialize)]
#[serde(transparent)]
pub struct AtLoadReport(OneOrMany<AtLoad>);

impl fmt::Display for AtLoadReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows = self.0.rows();
        let Some(first) = rows.first() else {
            return Ok(());
        };
        writeln!(f, "load: {}", first.load)?;
        writeln!(
            f,
            "{:<12} {:>11} {:>11} {:>11} | {:>10} {:>10}",
            "model", "a", "b", "phi", "pos_err", "ang_err"
        )?;
        let beam = first.beam;
        writeln!(
            f,
            "{:<12} {:>11.7} {:>11.7} {:>11.7} |",
            "beam", beam.a, beam.b, beam.phi
        )?;
        for r in rows {
            writeln!(
                f,
                "{:<12} {:>11.7} {:>11.7} {:>11.7} | {:>10.3e} {:>10.3e}",
                safe(&r.model),
                r.tip.a,
                r.tip.b,
                r.tip.phi,
                r.pos_err,
                r.ang_err
            )?;
        }
        Ok(())
    }
}

/// One case of a scene evaluation: the PRB tip, the beam tip, the errors.
#[derive(Debug, Serialize)]
pub struct CaseRow {
    load: Load,
    #[serde(flatten)]
    prb: TipPose,
    beam: TipPose,
    pos_err: f64,
    ang_err: f64,
}

impl From<&CaseError> for CaseRow {
    fn from(c: &CaseError) -> CaseRow {
        CaseRow {
            load: c.load,
            prb: c.prb,
            beam: c.beam,
            pos_err: c.pos_err,
            ang_err: c.ang_err,
        }
    }
}

/// One model over the scene.
#[derive(Debug, Serialize)]
pub struct ModelRow {
    model: String,
    prb: String,
    topology: String,
    #[serde(flatten)]
    figures: ErrorFigures,
    meets_targets: bool,
    seconds: f64,
    cases: Vec<CaseRow>,
}

/// `eval` over the scene.
#[derive(Debug, Serialize)]
pub struct SceneReport {
    #[serde(flatten)]
    models: OneOrMany<ModelRow>,
    scene: String,
    effects_decision: Option<EffectsDecision>,
    baseline_seconds: f64,
    #[serde(skip)]
    cases: usize,
    #[serde(skip)]
    accuracy: Accuracy,
    #[serde(skip)]
    angle_weight: f64,
}

impl fmt::Display for SceneReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {} ({} load cases)",
            safe(&self.scene),
            self.cases
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        writeln!(
            f,
            "targets: max position error {} L, max angle error {} rad; angle weight {}",
            num(self.accuracy.max_pos_err),
            num(self.accuracy.max_ang_err),
            num(self.angle_weight)
        )?;
        writeln!(
            f,
            "{:<12} {:>10} {:>10} {:>10} {:>10} {:>11}  targets",
            "model", "rms pos", "max pos", "rms ang", "max ang", "J"
        )?;
        for r in self.models.rows() {
            let m = &r.figures;
            writeln!(
                f,
                "{:<12} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>11.4e}  {}",
                safe(&r.model),
                m.rms_pos_err,
                m.max_pos_err,
                m.rms_ang_err,
                m.max_ang_err,
                m.objective,
                met(r.meets_targets)
            )?;
        }
        writeln!(f, "baseline: {:.3} ms", self.baseline_seconds * 1e3)
    }
}

/// The models named on the command line, in order: `--model`s then `--prb`s; with none, the
/// scene's `[prb] matrix`.
pub(super) fn named_models(args: &EvalArgs, scene: &Scene) -> Result<Vec<(String, PrbMatrix)>> {
    let mut out = Vec::new();
    for name in &args.model {
        let m = ModelFile::load(name)?;
        out.push((m.name.clone(), m.prb));
    }
    for text in &args.prb {
        let m = parse_matrix("--prb", text)?;
        out.push((m.topology(), m));
    }
    if out.is_empty() {
        out.push(scene_model(scene)?);
    }
    Ok(out)
}

/// Runs `prbfit eval`.
pub fn run(args: EvalArgs) -> Result<()> {
    let scene = load_scene(&args.common)?;
    if scene.mechanism.is_some() {
        let (scene, decision) = resolve_scene(&scene)?;
        if let Some(mechanism) = &scene.mechanism {
            return super::mech::eval(&scene, mechanism, decision, &args);
        }
    }
    let (scene, decision) = resolve_scene(&scene)?;
    let models = named_models(&args, &scene)?;
    let resolution = Resolution::with_tol(args.tol);
    let json = args.common.json;
    let weight = scene.fit.angle_weight;
    let beam = scene.beam.model();

    if let Some(load) = args.load {
        let solver = BeamSolver::new(beam, resolution)
            .map_err(|e| bad(format!("--tol {}: {e}", num(args.tol))))?;
        let sol = solver.solve(load).context("baseline beam")?;
        let mut rows = Vec::new();
        for (name, m) in models {
            let prb = PrbSolver::new(&m, beam.axial_compliance())
                .solve(load)
                .with_context(|| format!("model {name}"))?;
            let case = CaseError::new(load, sol.tip, prb.tip);
            rows.push(AtLoad {
                model: name,
                prb: m.to_text(),
                load,
                tip: case.prb,
                pos_err: case.pos_err,
                ang_err: case.ang_err,
                beam: case.beam,
            });
        }
        return emit(&AtLoadReport(OneOrMany::new(rows)), json);
    }

    // One baseline for every model.
    let mut progress = Progress::new("solving the beam");
    let n_paths = scene.loads.len();
    let baseline = Baseline::solve(
        scene.beam.model(),
        &scene.loads,
        resolution,
        &CancelToken::new(),
        &mut |done, cases| {
            progress.update(|| format!("load path {done}/{n_paths}, {cases} cases"));
        },
    )
    .context("baseline beam")?;
    progress.finish();
    let mut rows = Vec::new();
    for (name, m) in models {
        let t0 = Instant::now();
        let e = evaluate(&m, &baseline, weight).with_context(|| format!("model {name}"))?;
        rows.push(ModelRow {
            model: name,
            prb: m.to_text(),
            topology: m.topology(),
            figures: e.figures,
            meets_targets: e.figures.meets(&scene.accuracy),
            seconds: t0.elapsed().as_secs_f64(),
            cases: e.cases.iter().map(CaseRow::from).collect(),
        });
    }
    let report = SceneReport {
        models: OneOrMany::new(rows),
        scene: scene.name.clone(),
        effects_decision: decision,
        baseline_seconds: baseline.seconds,
        cases: baseline.case_count(),
        accuracy: scene.accuracy,
        angle_weight: weight,
    };
    emit(&report, json)
}
