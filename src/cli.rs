//! The command line (DESIGN §6). Input errors exit with status 2 and one line on stderr that
//! names the file, line or flag; a computation that fails (a load past a critical point, say)
//! exits with status 1; results go to stdout, as text or, with `--json`, one JSON object.

use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use serde_json::json;

use prbfit::beam::{BeamModel, BeamSolution, BeamSolver, Effects, Load, ModelError, Resolution};
use prbfit::eval::{evaluate, Baseline, CaseError};
use prbfit::export::{export, ExportError, ExportFormat, ExportInput};
use prbfit::files::{write_atomic, WriteError};
use prbfit::fit::{fit, CancelToken, Fidelity, FitError, FitOptions};
use prbfit::prb::{PrbMatrix, PrbSolver};
use prbfit::scene::{ModelFile, ModelFormat, Scene, SceneError};
use prbfit::select::{resolve_effects, select, EffectsDecision};

#[derive(Parser)]
#[command(
    name = "prbfit",
    version,
    about = "Finds the best pseudo-rigid-body (PRB) model of a compliant cantilever beam",
    long_about = None
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Solve the large-deflection baseline beam: one load, or every load case of the scene.
    Solve(SolveArgs),
    /// Judge PRB models against the beam: one load, or every load case of the scene.
    Eval(EvalArgs),
    /// Fit the free cells of a PRB matrix to the beam over the scene's loads.
    Fit(FitArgs),
    /// Fit the topology ladder and pick the simplest model that meets the scene's targets.
    Select(SelectArgs),
    /// Measure the speed/accuracy trade along each knob.
    Tradeoff(TradeoffArgs),
    /// Write a model for other tools: prbfit's model file, MuJoCo, URDF, SDF or CSV.
    Export(ExportArgs),
    /// Open the terminal UI (the default with no command) on a scene file or the built-in one.
    Tui {
        /// Scene file (TOML); default: the built-in scene.
        scene: Option<PathBuf>,
    },
}

/// Options every subcommand shares.
#[derive(Args)]
struct Common {
    /// Scene file (TOML, DESIGN §5); default: the built-in scene.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Print one JSON object on stdout instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct SolveArgs {
    #[command(flatten)]
    common: Common,
    /// One tip load, nondimensional: alpha_x, alpha_y, beta.
    #[arg(long, value_name = "AX,AY,BETA", value_parser = Load::parse, allow_hyphen_values = true)]
    load: Option<Load>,
    /// Beam effects: a comma-separated list of shear, extension, poisson; or none; or all.
    #[arg(long, value_name = "LIST|none")]
    effects: Option<String>,
    /// Slenderness L/t0 (overrides the scene's beam).
    #[arg(long, value_name = "L_OVER_T", allow_negative_numbers = true)]
    slenderness: Option<f64>,
    /// Poisson's ratio (overrides the scene's beam).
    #[arg(long, value_name = "NU", allow_negative_numbers = true)]
    nu: Option<f64>,
    /// Shear coefficient kappa (default: Cowper's rectangle value for nu).
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    kappa: Option<f64>,
    /// Integrator tolerance: the speed/accuracy knob (tip error about 10x this or better).
    #[arg(long, value_name = "TOL", allow_negative_numbers = true, default_value_t = Resolution::default().tol)]
    tol: f64,
    /// Include the deformed shape (points along the beam) in the JSON output.
    #[arg(long)]
    shape: bool,
}

#[derive(Args)]
struct EvalArgs {
    #[command(flatten)]
    common: Common,
    /// A PRB matrix in text form, e.g. "0.15,inf,inf; 0.85,2.2525,inf" (repeatable).
    #[arg(long, value_name = "MATRIX")]
    prb: Vec<String>,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file (repeatable).
    #[arg(long, value_name = "NAME_OR_FILE")]
    model: Vec<String>,
    /// Judge one tip load instead of the scene's cases.
    #[arg(long, value_name = "AX,AY,BETA", value_parser = Load::parse, allow_hyphen_values = true)]
    load: Option<Load>,
    /// Baseline integrator tolerance.
    #[arg(long, value_name = "TOL", allow_negative_numbers = true, default_value_t = Resolution::default().tol)]
    tol: f64,
}

#[derive(Args)]
struct FitArgs {
    #[command(flatten)]
    common: Common,
    /// Topology to fit, from the root: L, R, P, RP joined by - (e.g. L-R-R-R).
    #[arg(
        long,
        value_name = "TOPO",
        conflicts_with = "prb",
        required_unless_present = "prb"
    )]
    topology: Option<String>,
    /// Matrix to start from; cells ending in ! stay fixed.
    #[arg(long, value_name = "MATRIX")]
    prb: Option<String>,
    /// draft, normal or precise.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    fidelity: Fidelity,
    /// Seed of the random starts: the same seed gives the same fit.
    #[arg(long, value_name = "N", default_value_t = 1)]
    seed: u64,
    /// Save the fitted model (.toml or .json).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
    /// Overwrite the output file if it exists.
    #[arg(long)]
    force: bool,
}

#[derive(Args)]
struct SelectArgs {
    #[command(flatten)]
    common: Common,
    /// draft, normal or precise.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    fidelity: Fidelity,
}

#[derive(Args)]
struct TradeoffArgs {
    #[command(flatten)]
    common: Common,
    /// The topology the sampling and fidelity knobs fit.
    #[arg(long, value_name = "TOPO", default_value = "L-R-R-R")]
    topology: String,
}

#[derive(Args)]
#[command(group = clap::ArgGroup::new("which").required(true).args(["prb", "model"]))]
struct ExportArgs {
    #[command(flatten)]
    common: Common,
    /// A PRB matrix in text form.
    #[arg(long, value_name = "MATRIX")]
    prb: Option<String>,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file.
    #[arg(long, value_name = "NAME_OR_FILE")]
    model: Option<String>,
    /// toml, json, mjcf, urdf, sdf or csv.
    #[arg(long, value_name = "F", value_parser = ExportFormat::from_str)]
    format: ExportFormat,
    /// The file to write.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: PathBuf,
    /// Overwrite the file if it exists.
    #[arg(long)]
    force: bool,
    /// Density for the masses, kg/m^3 (only dynamics depend on it).
    #[arg(
        long,
        value_name = "KG_M3",
        default_value_t = 1000.0,
        allow_negative_numbers = true
    )]
    density: f64,
    /// Fidelity of the baseline the figures and the CSV come from.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    fidelity: Fidelity,
}

/// An error in what the user gave us: exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct BadInput(String);

fn bad(message: impl Into<String>) -> anyhow::Error {
    BadInput(message.into()).into()
}

pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // clap's message is several lines; the contract is one line naming the flag: the
            // message up to the usage, joined.
            let text = e.to_string();
            let joined = text
                .lines()
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with("tip:"))
                .collect::<Vec<_>>()
                .join(" ");
            let first = if joined.is_empty() {
                "invalid arguments"
            } else {
                joined.as_str()
            };
            let first = first.trim_start_matches("error: ");
            eprintln!("prbfit: {first} (see prbfit --help)");
            return ExitCode::from(2);
        }
    };
    let outcome = match cli.command {
        Some(Command::Solve(args)) => solve(args),
        Some(Command::Eval(args)) => eval(args),
        Some(Command::Fit(args)) => fit_command(args),
        Some(Command::Select(args)) => select_command(args),
        Some(Command::Tradeoff(args)) => tradeoff_command(args),
        Some(Command::Export(args)) => export_command(args),
        Some(Command::Tui { scene }) => tui(scene),
        None => tui(None),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let input = e.downcast_ref::<BadInput>().is_some()
                || e.downcast_ref::<SceneError>().is_some()
                || e.downcast_ref::<WriteError>().is_some();
            eprintln!("prbfit: {}", one_line(&e));
            ExitCode::from(if input { 2 } else { 1 })
        }
    }
}

/// The error and its causes on one line.
fn one_line(e: &anyhow::Error) -> String {
    let parts: Vec<String> = e
        .chain()
        .map(|c| c.to_string().replace('\n', " "))
        .collect();
    parts.join(": ")
}

fn load_scene(common: &Common) -> Result<Scene> {
    match &common.scene {
        None => Ok(Scene::builtin()),
        Some(path) => Ok(Scene::from_file(path)?),
    }
}

/// The scene with `effects = "auto"` decided, and the decision.
fn resolved_scene(common: &Common) -> Result<(Scene, Option<EffectsDecision>)> {
    let scene = load_scene(common)?;
    resolve_effects(&scene, Resolution::default()).context("deciding the beam effects")
}

fn decision_json(decision: &Option<EffectsDecision>) -> serde_json::Value {
    match decision {
        Some(d) => serde_json::to_value(d).expect("finite figures"),
        None => serde_json::Value::Null,
    }
}

/// One line saying what `effects = "auto"` decided.
fn decision_line(decision: &Option<EffectsDecision>) -> Option<String> {
    let d = decision.as_ref()?;
    let part = |kept: bool| {
        d.impacts
            .iter()
            .filter(|i| i.kept == kept)
            .map(|i| {
                format!(
                    "{} ({:.1}% of target)",
                    i.effect,
                    i.fraction_of_target * 100.0
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (kept, dropped) = (part(true), part(false));
    Some(format!(
        "effects auto: kept [{}]; dropped [{}] (together {:.1}% of target; threshold {:.0}%)",
        kept,
        dropped,
        d.dropped_together_fraction * 100.0,
        d.threshold * 100.0
    ))
}

/// The beam of the scene with the command-line overrides applied; errors name the flag.
fn beam_model(scene: &Scene, args: &SolveArgs) -> Result<BeamModel> {
    let base = scene.beam.model();
    let effects = match &args.effects {
        None => base.effects,
        Some(text) => {
            Effects::parse_list(text).map_err(|e| bad(format!("--effects {text}: {e}")))?
        }
    };
    let slenderness = args.slenderness.unwrap_or(base.slenderness);
    let nu = args.nu.unwrap_or(base.nu);
    // A new nu changes Cowper's kappa unless kappa itself was given.
    let kappa = match (args.kappa, args.nu) {
        (Some(k), _) => Some(k),
        (None, Some(_)) => scene.beam.shear_coefficient,
        (None, None) => Some(base.kappa),
    };
    BeamModel::new(slenderness, nu, kappa, effects).map_err(|e| {
        let flag = match e {
            ModelError::Slenderness(_) => "--slenderness",
            ModelError::PoissonRatio(_) => "--nu",
            ModelError::ShearCoefficient(_) => "--kappa",
            ModelError::UnknownEffect(_) | ModelError::PoissonWithoutExtension => "--effects",
        };
        bad(format!("{flag}: {e}"))
    })
}

fn solve(args: SolveArgs) -> Result<()> {
    let (scene, decision) = if args.effects.is_some() {
        (load_scene(&args.common)?, None)
    } else {
        resolved_scene(&args.common)?
    };
    let model = beam_model(&scene, &args)?;
    let resolution = Resolution::with_tol(args.tol);
    let solver =
        BeamSolver::new(model, resolution).map_err(|e| bad(format!("--tol {}: {e}", args.tol)))?;
    let json = args.common.json;
    if let Some(load) = args.load {
        let t0 = Instant::now();
        let sol = solver.solve(load).with_context(|| "solve failed")?;
        let seconds = t0.elapsed().as_secs_f64();
        if json {
            let mut out = json!({
                "load": load,
                "a": sol.tip.a,
                "b": sol.tip.b,
                "phi": sol.tip.phi,
                "root_moment": sol.root_moment,
                "iterations": sol.iterations,
                "continuation_steps": sol.continuation_steps,
                "stability": sol.convergence.stability,
                "beam": beam_json(&model),
                "effects_decision": decision_json(&decision),
                "tol": args.tol,
                "seconds": seconds,
            });
            if args.shape {
                out["shape"] = serde_json::to_value(&sol.shape)?;
            }
            print_json(&out)?;
        } else {
            if let Some(line) = decision_line(&decision) {
                println!("{line}");
            }
            println!("{}", beam_line(&model));
            println!("load: {load}");
            println!(
                "tip:  a = {:.9}  b = {:.9}  phi = {:.9} rad ({:.4} deg)",
                sol.tip.a,
                sol.tip.b,
                sol.tip.phi,
                sol.tip.phi.to_degrees()
            );
            println!(
                "root moment {:.6} E I0/L; {} Newton shots over {} continuation steps; {:.3} ms",
                sol.root_moment,
                sol.iterations,
                sol.continuation_steps,
                seconds * 1e3
            );
        }
        return Ok(());
    }

    let t0 = Instant::now();
    let mut solutions: Vec<BeamSolution> = Vec::new();
    for (i, path) in scene.loads.iter().enumerate() {
        let sols = solver
            .solve_path(path.end, path.steps)
            .with_context(|| format!("load path {} of the scene", i + 1))?;
        solutions.extend(sols);
    }
    let seconds = t0.elapsed().as_secs_f64();
    if json {
        let cases: Vec<_> = solutions
            .iter()
            .map(|s| {
                let mut case = json!({
                    "load": s.load, "a": s.tip.a, "b": s.tip.b, "phi": s.tip.phi,
                    "iterations": s.iterations,
                });
                if args.shape {
                    case["shape"] = serde_json::to_value(&s.shape).expect("finite shape");
                }
                case
            })
            .collect();
        print_json(&json!({
            "scene": scene.name,
            "beam": beam_json(&model),
            "effects_decision": decision_json(&decision),
            "tol": args.tol,
            "cases": cases,
            "seconds": seconds,
        }))?;
    } else {
        println!("scene: {}", scene.name);
        if let Some(line) = decision_line(&decision) {
            println!("{line}");
        }
        println!("{}", beam_line(&model));
        println!(
            "{:>9} {:>9} {:>9} | {:>12} {:>12} {:>12} | {:>5}",
            "alpha_x", "alpha_y", "beta", "a", "b", "phi", "shots"
        );
        for s in &solutions {
            println!(
                "{:>9.4} {:>9.4} {:>9.4} | {:>12.8} {:>12.8} {:>12.8} | {:>5}",
                s.load.alpha_x,
                s.load.alpha_y,
                s.load.beta,
                s.tip.a,
                s.tip.b,
                s.tip.phi,
                s.iterations
            );
        }
        println!("{} cases in {:.3} ms", solutions.len(), seconds * 1e3);
    }
    Ok(())
}

fn beam_json(model: &BeamModel) -> serde_json::Value {
    json!({
        "slenderness": model.slenderness,
        "nu": model.nu,
        "kappa": model.kappa,
        "effects": model.effects.names(),
    })
}

fn beam_line(model: &BeamModel) -> String {
    format!(
        "beam: L/t0 = {}, nu = {}, kappa = {:.4}, effects: {}",
        model.slenderness, model.nu, model.kappa, model.effects
    )
}

/// Only these keys may be `null` by design.
const NULLABLE: [&str; 2] = ["effects_decision", "chosen"];

/// Prints one JSON object; refuses non-finite numbers (which serde_json would write as
/// `null`) rather than print them.
fn print_json(value: &serde_json::Value) -> Result<()> {
    fn finite(v: &serde_json::Value) -> bool {
        match v {
            serde_json::Value::Null => false,
            serde_json::Value::Array(a) => a.iter().all(finite),
            serde_json::Value::Object(o) => o
                .iter()
                .all(|(k, v)| (v.is_null() && NULLABLE.contains(&k.as_str())) || finite(v)),
            _ => true,
        }
    }
    anyhow::ensure!(
        finite(value),
        "internal error: a result is not a finite number"
    );
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// The models named on the command line, in order: `--model`s then `--prb`s.
fn named_models(args: &EvalArgs) -> Result<Vec<(String, PrbMatrix)>> {
    let mut out = Vec::new();
    for name in &args.model {
        let m = ModelFile::load(name)?;
        out.push((m.name.clone(), m.prb));
    }
    for text in &args.prb {
        let m = PrbMatrix::parse(text).map_err(|e| bad(format!("--prb \"{text}\": {e}")))?;
        out.push((m.topology(), m));
    }
    if out.is_empty() {
        return Err(bad("give a model: --prb MATRIX or --model NAME_OR_FILE"));
    }
    Ok(out)
}

fn eval(args: EvalArgs) -> Result<()> {
    let (scene, decision) = resolved_scene(&args.common)?;
    let models = named_models(&args)?;
    let resolution = Resolution::with_tol(args.tol);
    let json = args.common.json;
    let weight = scene.fit.angle_weight;
    let beam = scene.beam.model();

    if let Some(load) = args.load {
        let solver = BeamSolver::new(beam, resolution)
            .map_err(|e| bad(format!("--tol {}: {e}", args.tol)))?;
        let sol = solver.solve(load).context("baseline beam")?;
        let mut rows = Vec::new();
        for (name, m) in &models {
            let prb = PrbSolver::new(m, beam.axial_compliance())
                .solve(load)
                .with_context(|| format!("model {name}"))?;
            let case = CaseError::new(load, sol.tip, prb.tip);
            rows.push((name, m, case));
        }
        if json {
            let objs: Vec<_> = rows
                .iter()
                .map(|(name, m, c)| {
                    json!({
                        "model": name, "prb": m.to_text(), "load": load,
                        "a": c.prb.a, "b": c.prb.b, "phi": c.prb.phi,
                        "pos_err": c.pos_err, "ang_err": c.ang_err,
                        "beam": {"a": c.beam.a, "b": c.beam.b, "phi": c.beam.phi},
                    })
                })
                .collect();
            print_json(&one_or_many(objs))?;
        } else {
            println!("load: {load}");
            println!(
                "{:<12} {:>11} {:>11} {:>11} | {:>10} {:>10}",
                "model", "a", "b", "phi", "pos_err", "ang_err"
            );
            println!(
                "{:<12} {:>11.7} {:>11.7} {:>11.7} |",
                "beam", sol.tip.a, sol.tip.b, sol.tip.phi
            );
            for (name, _, c) in &rows {
                println!(
                    "{:<12} {:>11.7} {:>11.7} {:>11.7} | {:>10.3e} {:>10.3e}",
                    name, c.prb.a, c.prb.b, c.prb.phi, c.pos_err, c.ang_err
                );
            }
        }
        return Ok(());
    }

    // One baseline for every model.
    let baseline = Baseline::compute(&scene, resolution).context("baseline beam")?;
    let mut results = Vec::new();
    for (name, m) in &models {
        let t0 = Instant::now();
        let e = evaluate(m, &baseline, weight).with_context(|| format!("model {name}"))?;
        results.push((name, m, e, t0.elapsed().as_secs_f64()));
    }
    if json {
        let objs: Vec<_> = results
            .iter()
            .map(|(name, m, e, secs)| {
                let f = &e.figures;
                json!({
                    "model": name,
                    "prb": m.to_text(),
                    "topology": m.topology(),
                    "rms_pos_err": f.rms_pos_err,
                    "max_pos_err": f.max_pos_err,
                    "rms_ang_err": f.rms_ang_err,
                    "max_ang_err": f.max_ang_err,
                    "objective": f.objective,
                    "meets_targets": f.meets(&scene.accuracy),
                    "seconds": secs,
                    "cases": e.cases.iter().map(|c| json!({
                        "load": c.load, "a": c.prb.a, "b": c.prb.b, "phi": c.prb.phi,
                        "beam": {"a": c.beam.a, "b": c.beam.b, "phi": c.beam.phi},
                        "pos_err": c.pos_err, "ang_err": c.ang_err,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mut out = one_or_many(objs);
        out["scene"] = json!(scene.name);
        out["effects_decision"] = decision_json(&decision);
        out["baseline_seconds"] = json!(baseline.seconds);
        print_json(&out)?;
    } else {
        println!(
            "scene: {} ({} load cases)",
            scene.name,
            baseline.case_count()
        );
        println!(
            "targets: max position error {} L, max angle error {} rad; angle weight {}",
            scene.accuracy.max_pos_err, scene.accuracy.max_ang_err, weight
        );
        println!(
            "{:<12} {:>10} {:>10} {:>10} {:>10} {:>11}  targets",
            "model", "rms pos", "max pos", "rms ang", "max ang", "J"
        );
        for (name, _, e, _) in &results {
            let f = &e.figures;
            println!(
                "{:<12} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>11.4e}  {}",
                name,
                f.rms_pos_err,
                f.max_pos_err,
                f.rms_ang_err,
                f.max_ang_err,
                f.objective,
                if f.meets(&scene.accuracy) {
                    "met"
                } else {
                    "NOT met"
                }
            );
        }
        println!("baseline: {:.3} ms", baseline.seconds * 1e3);
    }
    Ok(())
}

/// One object as is; several under `models`.
fn one_or_many(mut objs: Vec<serde_json::Value>) -> serde_json::Value {
    if objs.len() == 1 {
        objs.pop().expect("one")
    } else {
        json!({ "models": objs })
    }
}

fn fit_command(args: FitArgs) -> Result<()> {
    let (scene, decision) = resolved_scene(&args.common)?;
    let start = match (&args.topology, &args.prb) {
        (Some(t), _) => {
            PrbMatrix::from_topology(t).map_err(|e| bad(format!("--topology {t}: {e}")))?
        }
        (None, Some(text)) => {
            PrbMatrix::parse(text).map_err(|e| bad(format!("--prb \"{text}\": {e}")))?
        }
        (None, None) => return Err(bad("give --topology TOPO or --prb MATRIX")),
    };
    let format = match &args.output {
        Some(path) => {
            let format = ModelFormat::from_path(path).map_err(bad)?;
            if path.exists() && !args.force {
                // Refuse before spending the time on a fit.
                return Err(WriteError::Exists(path.clone()).into());
            }
            Some(format)
        }
        None => None,
    };
    let t0 = Instant::now();
    let baseline = args.fidelity.baseline(&scene).context("baseline beam")?;
    let options = FitOptions {
        fidelity: args.fidelity,
        angle_weight: scene.fit.angle_weight,
        seed: args.seed,
    };
    let report = fit(
        &baseline,
        &start,
        &options,
        &mut |_| {},
        &CancelToken::new(),
    )
    .map_err(|e| match e {
        FitError::Param(p) => bad(format!("--prb: {p}")),
        other => anyhow::Error::new(other),
    })?;
    let seconds = t0.elapsed().as_secs_f64();
    let f = report.figures;
    if let (Some(path), Some(format)) = (&args.output, format) {
        let model = ModelFile::fitted(&report.matrix, &scene, &args.fidelity.to_string(), &f);
        write_atomic(path, model.to_text(format).as_bytes(), args.force)?;
    }
    if args.common.json {
        print_json(&json!({
            "prb": report.matrix.to_text(),
            "topology": report.matrix.topology(),
            "rms_pos_err": f.rms_pos_err,
            "max_pos_err": f.max_pos_err,
            "rms_ang_err": f.rms_ang_err,
            "max_ang_err": f.max_ang_err,
            "objective": f.objective,
            "start_objective": report.start_objective,
            "meets_targets": f.meets(&scene.accuracy),
            "iterations": report.iterations,
            "evaluations": report.evaluations,
            "stop_reason": report.stop,
            "fidelity": args.fidelity,
            "cases": baseline.case_count(),
            "effects_decision": decision_json(&decision),
            "baseline_seconds": baseline.seconds,
            "seconds": seconds,
        }))?;
    } else {
        if let Some(line) = decision_line(&decision) {
            println!("{line}");
        }
        println!(
            "scene: {} ({} load cases at {} fidelity)",
            scene.name,
            baseline.case_count(),
            args.fidelity
        );
        println!("fitted {}: {}", report.matrix.topology(), report.matrix);
        println!(
            "J = {:.4e} (start {:.4e}); position error rms {:.3e} max {:.3e} L; angle error rms {:.3e} max {:.3e} rad",
            f.objective, report.start_objective, f.rms_pos_err, f.max_pos_err, f.rms_ang_err, f.max_ang_err
        );
        println!(
            "targets ({} L, {} rad): {}",
            scene.accuracy.max_pos_err,
            scene.accuracy.max_ang_err,
            if f.meets(&scene.accuracy) {
                "met"
            } else {
                "NOT met"
            }
        );
        println!(
            "{}; {} iterations, {} evaluations, {:.1} ms (baseline {:.1} ms)",
            report.stop,
            report.iterations,
            report.evaluations,
            seconds * 1e3,
            baseline.seconds * 1e3
        );
        if let Some(path) = &args.output {
            println!("saved {}", path.display());
        }
    }
    Ok(())
}

fn tui(path: Option<PathBuf>) -> Result<()> {
    let scene = match &path {
        Some(p) => Scene::from_file(p)?,
        None => Scene::builtin(),
    };
    prbfit::tui::run(scene, path).map_err(|e| bad(format!("{e:#}")))
}

fn select_command(args: SelectArgs) -> Result<()> {
    let (scene, decision) = resolved_scene(&args.common)?;
    let t0 = Instant::now();
    let baseline = args.fidelity.baseline(&scene).context("baseline beam")?;
    let selection = select(
        &scene,
        &baseline,
        args.fidelity,
        &CancelToken::new(),
        &mut |_| {},
    )?;
    let seconds = t0.elapsed().as_secs_f64();
    if args.common.json {
        let mut v = serde_json::to_value(&selection)?;
        let row = |i: Option<usize>| match i {
            Some(i) => serde_json::to_value(&selection.rows[i]).expect("finite"),
            None => serde_json::Value::Null,
        };
        v["chosen"] = row(selection.chosen);
        v["closest"] = row(Some(selection.closest));
        v["scene"] = json!(scene.name);
        v["targets"] = json!(scene.accuracy);
        v["effects_decision"] = decision_json(&decision);
        v["seconds"] = json!(seconds);
        print_json(&v)?;
        return Ok(());
    }
    println!(
        "scene: {} ({} load cases, {} fidelity)",
        scene.name,
        baseline.case_count(),
        args.fidelity
    );
    if let Some(line) = decision_line(&decision) {
        println!("{line}");
    }
    println!(
        "targets: max position error {} L, max angle error {} rad",
        scene.accuracy.max_pos_err, scene.accuracy.max_ang_err
    );
    println!(
        "{:<12} {:<11} {:>3} {:>11} {:>10} {:>10} {:>11} {:>9}  targets",
        "model", "topology", "dof", "J", "max pos", "max ang", "us/case", "fit ms"
    );
    for (i, r) in selection.rows.iter().enumerate() {
        let mark = if Some(i) == selection.chosen {
            " <- chosen"
        } else {
            ""
        };
        println!(
            "{:<12} {:<11} {:>3} {:>11.4e} {:>10.3e} {:>10.3e} {:>11.3} {:>9.1}  {}{}",
            r.name,
            r.topology,
            r.dof,
            r.figures.objective,
            r.figures.max_pos_err,
            r.figures.max_ang_err,
            r.eval_seconds_per_case * 1e6,
            r.fit_seconds * 1e3,
            if r.meets_targets { "met" } else { "not met" },
            mark
        );
    }
    match selection.chosen {
        Some(i) => {
            let r = &selection.rows[i];
            println!("chosen: {} ({}): {}", r.name, r.topology, r.prb);
        }
        None => {
            let r = &selection.rows[selection.closest];
            println!(
                "no model meets the targets; closest: {} ({}), its worst error is {:.2}x its target",
                r.name, r.topology, r.target_ratio
            );
        }
    }
    println!("{:.2} s in all", seconds);
    Ok(())
}

fn tradeoff_command(args: TradeoffArgs) -> Result<()> {
    let (scene, decision) = resolved_scene(&args.common)?;
    let start = PrbMatrix::from_topology(&args.topology)
        .map_err(|e| bad(format!("--topology {}: {e}", args.topology)))?;
    let knobs = prbfit::tradeoff::measure(&scene, &start, &CancelToken::new())?;
    if args.common.json {
        print_json(&json!({
            "scene": scene.name,
            "topology": args.topology,
            "effects_decision": decision_json(&decision),
            "knobs": knobs,
        }))?;
        return Ok(());
    }
    println!(
        "scene: {}; fitted topology for the fit knobs: {}",
        scene.name, args.topology
    );
    if let Some(line) = decision_line(&decision) {
        println!("{line}");
    }
    for k in &knobs {
        println!("\n{}: time = {}; error = {}", k.knob, k.time_of, k.error_of);
        for r in &k.rows {
            let time = if r.seconds < 1e-3 {
                format!("{:.2} us", r.seconds * 1e6)
            } else {
                format!("{:.1} ms", r.seconds * 1e3)
            };
            println!("  {:<28} {:>12} {:>12.3e}", r.setting, time, r.error);
        }
    }
    Ok(())
}

fn export_command(args: ExportArgs) -> Result<()> {
    if args.output.exists() && !args.force {
        return Err(WriteError::Exists(args.output.clone()).into());
    }
    let (scene, _) = resolved_scene(&args.common)?;
    let (name, matrix) = match (&args.model, &args.prb) {
        (Some(m), _) => {
            let file = ModelFile::load(m)?;
            (file.name, file.prb)
        }
        (None, Some(text)) => {
            let m = PrbMatrix::parse(text).map_err(|e| bad(format!("--prb \"{text}\": {e}")))?;
            (m.topology().to_lowercase(), m)
        }
        (None, None) => return Err(bad("give --prb MATRIX or --model NAME_OR_FILE")),
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
    let text = export(&input, args.format).map_err(|e| match e {
        ExportError::Density(_) => bad(format!("--density: {e}")),
        other => anyhow::Error::new(other),
    })?;
    write_atomic(&args.output, text.as_bytes(), args.force)?;
    if args.common.json {
        print_json(&json!({
            "output": args.output.display().to_string(),
            "format": format!("{:?}", args.format).to_lowercase(),
            "prb": matrix.to_text(),
            "bytes": text.len(),
        }))?;
    } else {
        println!("wrote {} ({} bytes)", args.output.display(), text.len());
    }
    Ok(())
}
