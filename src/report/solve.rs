//! `prbfit solve`: the truth the models are judged against: the baseline beam's tip under one
//! load or over every case of the scene; on a mechanism scene (DESIGN §8) the beam mechanism
//! along every drive, each case as §8 writes it: `stage` `[dx, dy, dphi]` and `stage_load`
//! `[alpha_x, alpha_y, beta]` in flexure 1's units, and per flexure its `tip` `[a, b, phi]`
//! and `wrench` `[alpha_x, alpha_y, beta]` in its own frame and units. The text form adds
//! millimetres (or metres), degrees, newtons and newton metres through flexure 1's `L` and
//! `E I0`, and marks which loads are reactions (prescribed coordinates).
//!
//! A mechanism that cannot follow a drive path (a critical point, no equilibrium, a motion
//! nothing can make) is a failed computation, exit status 1, as for a beam past a critical
//! point, with one line naming the drive and how far along it the path got.

use std::fmt;
use std::time::Instant;

use serde::Serialize;

use crate::beam::{BeamModel, BeamSolution, BeamSolver, Effects, Load, ModelError, Resolution};
use crate::beam::{ShapePoint, TipPose};
use crate::mech::MechCase;
use crate::scene::{Mechanism, Scene};
use crate::si::MechUnits;
use crate::study::stroke::{self, StrokeLimit};
use crate::study::{EffectsDecision, Sampling};

use super::stage::{
    count, drive_line, refuse_flag, tidy, units_line, DriveInfo, LOADS_ARE_DRIVES, LOAD_NAMES,
};
use super::{
    fixed, mpa, num, resolve_scene, safe, Control, DecisionLine, Progress, ReportError, Result,
};

/// `solve`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct SolveArgs {
    /// One tip load instead of the scene's cases (`--load`).
    pub load: Option<Load>,
    /// Beam effects overriding the scene's, as `--effects` takes them (a list, `none`, `all`).
    pub effects: Option<String>,
    /// Slenderness `L/t0` overriding the scene's beam.
    pub slenderness: Option<f64>,
    /// Poisson's ratio overriding the scene's beam.
    pub nu: Option<f64>,
    /// Shear coefficient (default: Cowper's rectangle value for nu).
    pub kappa: Option<f64>,
    /// Integrator tolerance (`--tol`).
    pub tol: f64,
    /// Include the deformed shapes (`--shape`).
    pub shape: bool,
}

impl Default for SolveArgs {
    fn default() -> SolveArgs {
        SolveArgs {
            load: None,
            effects: None,
            slenderness: None,
            nu: None,
            kappa: None,
            tol: Resolution::default().tol,
            shape: false,
        }
    }
}

/// What `solve` reports: one load, the scene's cases, or a mechanism's.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum SolveReport {
    /// `--load`: one tip.
    One(OneLoad),
    /// A cantilever's cases.
    Scene(SceneCases),
    /// A mechanism's cases.
    Stage(StageCases),
}

impl fmt::Display for SolveReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolveReport::One(r) => r.fmt(f),
            SolveReport::Scene(r) => r.fmt(f),
            SolveReport::Stage(r) => r.fmt(f),
        }
    }
}

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
            // In full (shortest round trip, at most 20 characters in [0, 0.5)): rounded,
            // 0.49999999 printed as 0.5, a ratio the reader refuses.
            self.nu,
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
    /// The largest fibre stress along the beam, Pa (DESIGN §11).
    max_stress: Option<f64>,
    /// Where it is, s/L.
    max_stress_at: Option<f64>,
    /// The scene's `allowable_stress`, Pa.
    #[serde(skip_serializing_if = "Option::is_none")]
    allowable_stress: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    shape: Option<Vec<ShapePoint>>,
}

/// A stress in Pa as text: MPa, with its place along the flexure.
fn stress_text(pa: Option<f64>, at: Option<f64>) -> String {
    match (pa, at) {
        (Some(pa), Some(at)) => format!("{} MPa at s/L = {at:.4}", mpa(pa, 4)),
        _ => "unknown".to_string(),
    }
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
        write!(
            f,
            "max stress {}",
            stress_text(self.max_stress, self.max_stress_at)
        )?;
        match (self.allowable_stress, self.max_stress) {
            (Some(a), Some(s)) => writeln!(
                f,
                " ({} % of the allowable {} MPa{})",
                fixed(100.0 * s / a, 1),
                mpa(a, 4),
                if s >= a { ": PAST IT" } else { "" }
            )?,
            _ => writeln!(f)?,
        }
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
    /// The largest fibre stress along the beam, Pa.
    max_stress: Option<f64>,
    /// Where it is, s/L.
    max_stress_at: Option<f64>,
    /// Past its path's stroke limit (present when the scene has an allowable stress).
    #[serde(skip_serializing_if = "Option::is_none")]
    past_stroke_limit: Option<bool>,
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
    /// The scene's `allowable_stress`, Pa.
    allowable_stress: Option<f64>,
    /// Per load path in order, the fraction of its end load where the stress first reaches
    /// the allowable (null: not within the path); null without an allowable stress.
    stroke_limits: Option<Vec<Option<f64>>>,
    #[serde(skip)]
    limits: Vec<StrokeLimit>,
    cases: Vec<Case>,
    seconds: f64,
}

impl fmt::Display for SceneCases {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene: {}", safe(&self.scene))?;
        write!(f, "{}{}", DecisionLine(&self.effects_decision), self.beam)?;
        writeln!(
            f,
            "{:>9} {:>9} {:>9} | {:>12} {:>12} {:>12} | {:>10} {:>6} | {:>5}",
            "alpha_x", "alpha_y", "beta", "a", "b", "phi", "stress MPa", "at s/L", "shots"
        )?;
        for c in &self.cases {
            writeln!(
                f,
                "{:>9.4} {:>9.4} {:>9.4} | {:>12.8} {:>12.8} {:>12.8} | {:>10} {:>6} | {:>5}{}",
                c.load.alpha_x,
                c.load.alpha_y,
                c.load.beta,
                c.tip.a,
                c.tip.b,
                c.tip.phi,
                c.max_stress.map_or("-".into(), |s| mpa(s, 3)),
                c.max_stress_at.map_or("-".into(), |s| format!("{s:.3}")),
                c.iterations,
                if c.past_stroke_limit == Some(true) {
                    "  past the stroke limit"
                } else {
                    ""
                }
            )?;
        }
        write!(
            f,
            "{}",
            LimitsLine(self.allowable_stress, &self.limits, "load path")
        )?;
        writeln!(
            f,
            "{} cases in {:.3} ms",
            self.cases.len(),
            self.seconds * 1e3
        )
    }
}

/// One flexure of one case, §8's arrays.
#[derive(Debug, Serialize)]
pub struct FlexureRow {
    /// `[a, b, phi]`, its own frame and units.
    tip: [f64; 3],
    /// `[alpha_x, alpha_y, beta]`, its own frame and units.
    wrench: [f64; 3],
    /// Stable under its wrench as a dead load.
    load_stable: bool,
    /// Its largest fibre stress, Pa.
    max_stress: Option<f64>,
    /// Where it is, s/L along it.
    max_stress_at: Option<f64>,
}

/// One case of `solve` on a mechanism.
#[derive(Debug, Serialize)]
pub struct StageCase {
    /// From 1.
    drive: usize,
    fraction: f64,
    stage: [f64; 3],
    stage_load: [f64; 3],
    flexures: Vec<FlexureRow>,
    iterations: u32,
    /// Past its drive's stroke limit (present when a flexure has an allowable stress).
    #[serde(skip_serializing_if = "Option::is_none")]
    past_stroke_limit: Option<bool>,
}

impl StageCase {
    fn new(drive: usize, c: &MechCase, youngs: &[f64], limit: Option<&StrokeLimit>) -> StageCase {
        StageCase {
            drive,
            fraction: c.fraction,
            stage: c.stage,
            stage_load: c.stage_load,
            flexures: c
                .flexures
                .iter()
                .enumerate()
                .map(|(i, f)| FlexureRow {
                    tip: [f.tip.a, f.tip.b, f.tip.phi],
                    wrench: [f.wrench.alpha_x, f.wrench.alpha_y, f.wrench.beta],
                    load_stable: f.load_stable,
                    max_stress: f.stress.zip(youngs.get(i)).map(|(s, e)| s.max * e),
                    max_stress_at: f.stress.map(|s| s.at),
                })
                .collect(),
            iterations: c.iterations,
            past_stroke_limit: limit.map(|l| l.passed_by(c.fraction)),
        }
    }
}

/// `solve` on a mechanism scene: the beam mechanism along every drive.
#[derive(Debug, Serialize)]
pub struct StageCases {
    scene: String,
    flexure_count: usize,
    drives: Vec<DriveInfo>,
    tol: f64,
    /// Per flexure, its `allowable_stress` (Pa), null where none.
    allowable_stress: Vec<Option<f64>>,
    /// Per drive in order, the fraction of its end values where a flexure's stress first
    /// reaches its allowable (null: not within the drive); null without any allowable.
    stroke_limits: Option<Vec<Option<f64>>>,
    #[serde(skip)]
    limits: Vec<StrokeLimit>,
    cases: Vec<StageCase>,
    seconds: f64,
    effects_decision: Option<EffectsDecision>,
    #[serde(skip)]
    mechanism: Mechanism,
}

impl fmt::Display for StageCases {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let units = MechUnits::new(&self.mechanism);
        let (dist, factor) = (units.distance, units.per_metre);
        writeln!(
            f,
            "scene: {} (mechanism: {}, {})",
            safe(&self.scene),
            count(self.flexure_count, "flexure"),
            count(self.drives.len(), "drive path")
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", units_line(&units))?;
        for (info, drive) in self.drives.iter().zip(&self.mechanism.drives) {
            writeln!(f)?;
            writeln!(f, "{}", drive_line(info.drive, drive, &units))?;
            let star = |c: usize| if info.prescribed[c] { "*" } else { " " };
            writeln!(
                f,
                "{:>6} | {:>9} {:>9} {:>9} | {:>9} {:>9} | {:>9} {:>9} {:>9} | {:>11} {:>11} {:>11} | {:>10}",
                "frac",
                "dx/L",
                "dy/L",
                "dphi deg",
                format!("dx {dist}"),
                format!("dy {dist}"),
                format!("alpha_x{}", star(0)),
                format!("alpha_y{}", star(1)),
                format!("beta{}", star(2)),
                format!("{}{}", LOAD_NAMES[0], star(0)),
                format!("{}{}", LOAD_NAMES[1], star(1)),
                format!("{}{}", LOAD_NAMES[2], star(2)),
                "stress MPa",
            )?;
            for c in self.cases.iter().filter(|c| c.drive == info.drive) {
                let (s, l) = (c.stage, c.stage_load);
                writeln!(
                    f,
                    "{:>6.3} | {:>9.5} {:>9.5} {:>9.4} | {:>9.4} {:>9.4} | {:>9.4} {:>9.4} {:>9.4} | {:>11.5} {:>11.5} {:>11.6} | {:>10}{}",
                    c.fraction,
                    s[0],
                    s[1],
                    s[2].to_degrees(),
                    s[0] * units.length * factor,
                    s[1] * units.length * factor,
                    tidy(l[0], 4),
                    tidy(l[1], 4),
                    tidy(l[2], 4),
                    tidy(l[0] * units.load(0), 5),
                    tidy(l[1] * units.load(1), 5),
                    tidy(l[2] * units.load(2), 6),
                    worst_stress(c),
                    if c.past_stroke_limit == Some(true) { "  past the stroke limit" } else { "" }
                )?;
            }
        }
        let allowable = self
            .allowable_stress
            .iter()
            .flatten()
            .copied()
            .reduce(f64::min);
        write!(f, "{}", LimitsLine(allowable, &self.limits, "drive"))?;
        writeln!(
            f,
            "{} cases in {:.3} ms",
            self.cases.len(),
            self.seconds * 1e3
        )
    }
}

/// A mechanism case's largest flexure stress in MPa, with the flexure when there are several.
fn worst_stress(c: &StageCase) -> String {
    let worst = c
        .flexures
        .iter()
        .enumerate()
        .filter_map(|(i, f)| f.max_stress.map(|s| (i, s)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match worst {
        Some((i, s)) if c.flexures.len() > 1 => format!("{} ({})", mpa(s, 3), i + 1),
        Some((_, s)) => mpa(s, 3),
        None => "-".into(),
    }
}

/// The stroke limits as one line (none without an allowable stress).
struct LimitsLine<'a>(Option<f64>, &'a [StrokeLimit], &'static str);

impl fmt::Display for LimitsLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let LimitsLine(allowable, limits, what) = *self;
        let Some(allowable) = allowable else {
            return Ok(());
        };
        let parts: Vec<String> = limits
            .iter()
            .map(|l| match l.fraction {
                Some(x) => format!("{what} {} at {x:.6}", l.path),
                None => format!("{what} {} none", l.path),
            })
            .collect();
        writeln!(
            f,
            "stroke limits (allowable stress {} MPa): {}",
            mpa(allowable, 4),
            parts.join(", ")
        )
    }
}

/// `prbfit solve` on a mechanism scene: the beam mechanism (DESIGN §8) along every drive.
fn solve_stage(scene: &Scene, args: &SolveArgs, ctl: &mut Control<'_>) -> Result<StageCases> {
    if args.load.is_some() {
        return Err(refuse_flag("--load", scene, LOADS_ARE_DRIVES));
    }
    let beam_flags = [
        ("--effects", args.effects.is_some()),
        ("--slenderness", args.slenderness.is_some()),
        ("--nu", args.nu.is_some()),
        ("--kappa", args.kappa.is_some()),
    ];
    if let Some((flag, _)) = beam_flags.iter().find(|(_, given)| *given) {
        return Err(refuse_flag(
            flag,
            scene,
            "its flexures are the scene's [beam] with each [[flexures]] table's overrides \
             (edit them in the scene)",
        ));
    }
    if args.shape {
        return Err(refuse_flag(
            "--shape",
            scene,
            "the deformed shapes of a mechanism's flexures are not reported yet",
        ));
    }
    let resolution = super::resolution(scene, args.tol)?;
    let t0 = Instant::now();
    let study = super::study(scene, Sampling::Every(resolution), ctl)?;
    let mechanism = study.mechanism();
    let youngs: Vec<f64> = mechanism
        .flexures
        .iter()
        .map(|f| f.beam.youngs_modulus)
        .collect();
    let limits = study.stroke_limits();
    let cases = study
        .truth()
        .iter()
        .enumerate()
        .flat_map(|(i, path)| {
            let limit = limits.as_ref().and_then(|l| l.get(i));
            let youngs = &youngs;
            path.iter()
                .map(move |c| StageCase::new(i + 1, c, youngs, limit))
        })
        .collect();
    let report = StageCases {
        effects_decision: study.decision().cloned(),
        scene: scene.name.clone(),
        flexure_count: mechanism.flexures.len(),
        drives: DriveInfo::all(mechanism),
        tol: args.tol,
        allowable_stress: study.allowable_stresses(),
        stroke_limits: limits
            .as_ref()
            .map(|l| l.iter().map(|l| l.fraction).collect()),
        limits: limits.unwrap_or_default(),
        cases,
        seconds: t0.elapsed().as_secs_f64(),
        mechanism: mechanism.clone(),
    };
    Ok(report)
}

/// The beam of the scene with the command-line overrides applied; errors name the flag.
fn beam_model(scene: &Scene, args: &SolveArgs) -> Result<BeamModel> {
    let base = scene.beam.model();
    let effects = match &args.effects {
        None => base.effects,
        Some(text) => Effects::parse_list(text)
            .map_err(|e| ReportError::input(format!("--effects {text}: {e}")))?,
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
                ModelError::UnknownEffect(_)
                | ModelError::PoissonWithoutExtension
                | ModelError::NoneWithOthers => "--effects",
            };
            ReportError::input(format!("{flag}: {e}"))
        })
        // The section's width in thicknesses stays the scene's (plane strain's plate fraction).
        .map(|m| m.with_width_ratio(scene.beam.width / scene.beam.thickness))
}

/// `prbfit solve` on `scene`.
pub fn solve(scene: &Scene, args: &SolveArgs, ctl: &mut Control<'_>) -> Result<SolveReport> {
    super::refuse_data(
        scene,
        "solve",
        "solves the beam along [[loads]], and a data scene's loads are its rows",
    )?;
    if scene.mechanism.is_some() {
        return solve_stage(scene, args, ctl).map(SolveReport::Stage);
    }
    let (scene, decision) = if args.effects.is_some() {
        (scene.clone(), None)
    } else {
        resolve_scene(scene, &ctl.cancel)?
    };
    let model = beam_model(&scene, args)?;
    let solver = BeamSolver::new(model, Resolution::with_tol(args.tol))
        .map_err(|e| ReportError::input(format!("--tol {}: {e}", num(args.tol))))?;
    // Without --shape nothing reads a case's shape once its stress is found.
    let solver = if args.shape {
        solver
    } else {
        solver.without_shapes()
    };
    let shape = |s: &BeamSolution| args.shape.then(|| s.shape.clone());
    let youngs = scene.beam.youngs_modulus;
    let allowable = scene.beam.allowable_stress;
    // A solution's stress ratio: the cantilever is its flexure 1 (from 0).
    let ratio = |s: &BeamSolution| {
        let a = allowable?;
        s.stress.map(|st| (st.max * youngs / a, 0))
    };
    if let Some(load) = args.load {
        let t0 = Instant::now();
        let sol = solver
            .solve(load)
            .map_err(|e| ReportError::failed_in("solve failed", &e))?;
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
            max_stress: sol.stress.map(|s| s.max * youngs),
            max_stress_at: sol.stress.map(|s| s.at),
            allowable_stress: scene.beam.allowable_stress,
            shape: shape(&sol),
        };
        return Ok(SolveReport::One(report));
    }
    let t0 = Instant::now();
    let mut cases = Vec::new();
    let mut limits = Vec::new();
    let n_paths = scene.loads.len();
    for (i, path) in scene.loads.iter().enumerate() {
        (ctl.progress)(&Progress::Solving {
            path: i + 1,
            paths: n_paths,
            cases: cases.len(),
        });
        let sols = solver
            .solve_path_cancellable(path.end, path.steps, &ctl.cancel)
            .map_err(|e| ReportError::failed_in(format!("load path {} of the scene", i + 1), &e))?;
        let n = sols.len().max(1) as f64;
        let fraction = |k: usize| (k + 1) as f64 / n;
        let limit = allowable.map(|_| {
            stroke::path_limit(
                i + 1,
                sols.iter()
                    .enumerate()
                    .map(|(k, s)| (fraction(k), ratio(s))),
                &|l| {
                    solver
                        .solve(path.end.scaled(l))
                        .ok()
                        .as_ref()
                        .and_then(ratio)
                        .map(|r| r.0)
                },
            )
        });
        cases.extend(sols.iter().enumerate().map(|(k, s)| Case {
            load: s.load,
            tip: s.tip,
            iterations: s.iterations,
            max_stress: s.stress.map(|st| st.max * youngs),
            max_stress_at: s.stress.map(|st| st.at),
            past_stroke_limit: limit.map(|l| l.passed_by(fraction(k))),
            shape: shape(s),
        }));
        limits.extend(limit);
    }
    let report = SceneCases {
        scene: scene.name,
        beam: BeamInfo::from(&model),
        effects_decision: decision,
        tol: args.tol,
        allowable_stress: allowable,
        stroke_limits: allowable.map(|_| limits.iter().map(|l: &StrokeLimit| l.fraction).collect()),
        limits,
        cases,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok(SolveReport::Scene(report))
}
