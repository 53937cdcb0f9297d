//! `prbfit solve`: the baseline beam's tip under one load, or over every case of the scene.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::beam::{BeamModel, BeamSolution, BeamSolver, Effects, Load, ModelError, Resolution};
use prbfit::beam::{ShapePoint, TipPose};
use prbfit::scene::Scene;
use prbfit::select::EffectsDecision;

use super::args::SolveArgs;
use super::output::{num, safe, DecisionLine, Progress};
use super::{bad, load_scene, resolve_scene};

/// The beam as solved, for the reports.
#[derive(Debug, Serialize)]
pub struct BeamInfo {
    slenderness: f64,
    nu: f64,
    kappa: f64,
    effects: Vec<&'static str>,
    #[serde(skip)]
    display_effects: Effects,
}

impl From<&BeamModel> for BeamInfo {
    fn from(m: &BeamModel) -> BeamInfo {
        BeamInfo {
            slenderness: m.slenderness,
            nu: m.nu,
            kappa: m.kappa,
            effects: m.effects.names(),
            display_effects: m.effects,
        }
    }
}

impl fmt::Display for BeamInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "beam: L/t0 = {}, nu = {}, kappa = {:.4}, effects: {}",
            num(self.slenderness),
            num(self.nu),
            self.kappa,
            self.display_effects
        )
    }
}

/// `solve --load`: one tip.
#[derive(Debug, Serialize)]
pub struct OneLoad {
    load: Load,
    a: f64,
    b: f64,
    phi: f64,
    root_moment: f64,
    iterations: u32,
    continuation_steps: u32,
    stability: f64,
    beam: BeamInfo,
    effects_decision: Option<EffectsDecision>,
    tol: f64,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    shape: Option<Vec<ShapePoint>>,
}

impl fmt::Display for OneLoad {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", DecisionLine(&self.effects_decision), self.beam)?;
        writeln!(f, "load: {}", self.load)?;
        writeln!(
            f,
            "tip:  a = {:.9}  b = {:.9}  phi = {:.9} rad ({:.4} deg)",
            self.a,
            self.b,
            self.phi,
            self.phi.to_degrees()
        )?;
        writeln!(
            f,
            "root moment {:.6} E I0/L; {} Newton shots over {} continuation steps; {:.3} ms",
            self.root_moment,
            self.iterations,
            self.continuation_steps,
            self.seconds * 1e3
        )
    }
}

/// One case of `solve` over the scene.
#[derive(Debug, Serialize)]
pub struct Case {
    load: Load,
    #[serde(flatten)]
    tip: TipPose,
    iterations: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    shape: Option<Vec<ShapePoint>>,
}

/// `solve` over the scene's cases.
#[derive(Debug, Serialize)]
pub struct SceneCases {
    scene: String,
    beam: BeamInfo,
    effects_decision: Option<EffectsDecision>,
    tol: f64,
    cases: Vec<Case>,
    seconds: f64,
}

impl fmt::Display for SceneCases {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene: {}", safe(&self.scene))?;
        write!(f, "{}{}", DecisionLine(&self.effects_decision), self.beam)?;
        writeln!(
            f,
            "{:>9} {:>9} {:>9} | {:>12} {:>12} {:>12} | {:>5}",
            "alpha_x", "alpha_y", "beta", "a", "b", "phi", "shots"
        )?;
        for c in &self.cases {
            writeln!(
                f,
                "{:>9.4} {:>9.4} {:>9.4} | {:>12.8} {:>12.8} {:>12.8} | {:>5}",
                c.load.alpha_x,
                c.load.alpha_y,
                c.load.beta,
                c.tip.a,
                c.tip.b,
                c.tip.phi,
                c.iterations
            )?;
        }
        writeln!(
            f,
            "{} cases in {:.3} ms",
            self.cases.len(),
            self.seconds * 1e3
        )
    }
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
    BeamModel::new(slenderness, nu, kappa, effects)
        .map_err(|e| {
            let flag = match e {
                ModelError::Slenderness(_) => "--slenderness",
                ModelError::PoissonRatio(_) => "--nu",
                ModelError::ShearCoefficient(_) => "--kappa",
                ModelError::UnknownEffect(_) | ModelError::PoissonWithoutExtension => "--effects",
            };
            bad(format!("{flag}: {e}"))
        })
        // The section's width in thicknesses stays the scene's (plane strain's plate fraction).
        .map(|m| m.with_width_ratio(scene.beam.width / scene.beam.thickness))
}

/// Runs `prbfit solve`.
pub fn run(args: SolveArgs) -> Result<()> {
    let scene = load_scene(&args.common)?;
    super::refuse_data(
        &scene,
        "solve",
        "solves the beam along [[loads]], and a data scene's loads are its rows",
    )?;
    if scene.mechanism.is_some() {
        let (scene, decision) = resolve_scene(&scene)?;
        if let Some(mechanism) = &scene.mechanism {
            return super::mech::solve(&scene, mechanism, decision, &args);
        }
    }
    let (scene, decision) = if args.effects.is_some() {
        (scene, None)
    } else {
        resolve_scene(&scene)?
    };
    let model = beam_model(&scene, &args)?;
    let solver = BeamSolver::new(model, Resolution::with_tol(args.tol))
        .map_err(|e| bad(format!("--tol {}: {e}", num(args.tol))))?;
    let json = args.common.json;
    let shape = |s: &BeamSolution| args.shape.then(|| s.shape.clone());
    if let Some(load) = args.load {
        let t0 = Instant::now();
        let sol = solver.solve(load).context("solve failed")?;
        let report = OneLoad {
            load,
            a: sol.tip.a,
            b: sol.tip.b,
            phi: sol.tip.phi,
            root_moment: sol.root_moment,
            iterations: sol.iterations,
            continuation_steps: sol.continuation_steps,
            stability: sol.convergence.stability,
            beam: BeamInfo::from(&model),
            effects_decision: decision,
            tol: args.tol,
            seconds: t0.elapsed().as_secs_f64(),
            shape: shape(&sol),
        };
        return super::output::emit(&report, json);
    }
    let t0 = Instant::now();
    let mut cases = Vec::new();
    let mut progress = Progress::new("solving");
    let n_paths = scene.loads.len();
    for (i, path) in scene.loads.iter().enumerate() {
        progress.update(|| {
            format!(
                "load path {}/{n_paths}, {} cases so far",
                i + 1,
                cases.len()
            )
        });
        let sols = solver
            .solve_path(path.end, path.steps)
            .with_context(|| format!("load path {} of the scene", i + 1))?;
        cases.extend(sols.iter().map(|s| Case {
            load: s.load,
            tip: s.tip,
            iterations: s.iterations,
            shape: shape(s),
        }));
    }
    progress.finish();
    let report = SceneCases {
        scene: scene.name,
        beam: BeamInfo::from(&model),
        effects_decision: decision,
        tol: args.tol,
        cases,
        seconds: t0.elapsed().as_secs_f64(),
    };
    super::output::emit(&report, json)
}
