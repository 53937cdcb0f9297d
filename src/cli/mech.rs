//! `prbfit solve` and `prbfit eval` on a mechanism scene (DESIGN §8).
//!
//! `solve` follows every drive path of the exact mechanism (a §2 beam per flexure) and
//! reports each case as §8 writes it: `stage` `[dx, dy, dphi]` and `stage_load`
//! `[alpha_x, alpha_y, beta]` in flexure 1's units, and per flexure its `tip` `[a, b, phi]`
//! and `wrench` `[alpha_x, alpha_y, beta]` in its own frame and units. The text form adds
//! millimetres (or metres), degrees, newtons and newton metres through flexure 1's `L` and
//! `E I0`, and marks which loads are reactions (prescribed coordinates).
//!
//! `eval` solves the exact mechanism once and the PRB mechanism once per model, and judges
//! each model by the seven figures of [`prbfit::mech::figures`].
//!
//! Failures: a mechanism that cannot follow a drive path (a critical point, no equilibrium,
//! a motion nothing can make) is a failed computation, exit status 1, as for a beam past a
//! critical point, with one line naming the drive and how far along it the path got; no
//! cases are printed. In `eval`, a model whose PRB mechanism cannot follow (a 1R model asked
//! to keep its tip angle) is a row saying so, `meets_targets` false; with every model failing
//! there is nothing to report and the status is 1.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::beam::{BeamSolver, Resolution};
use prbfit::mech::figures::{compare, MechCaseError, MechFigures};
use prbfit::mech::{exact, measured, prb, MechCase};
use prbfit::scene::{Accuracy, Drive, Mechanism, Scene, COORDINATE_KEYS};
use prbfit::select::EffectsDecision;
use prbfit::si::MechUnits;

use prbfit::fidelity::Fidelity;
use prbfit::fit::mech::{fit_mechanism, MechFitError};
use prbfit::fit::{CancelToken, FitError, FitOptions, StopReason};
use prbfit::format::Format;
use prbfit::io::files::write_atomic;
use prbfit::io::model_file::ModelFile;
use prbfit::prb::PrbMatrix;

use super::args::{EvalArgs, FitArgs, SolveArgs};
use super::bad;
use super::eval::{named_models, OneOrMany};
use super::output::{emit, met, num, safe, DecisionLine, Progress, TruthInfo, TruthLine};

/// Names of the stage coordinates' loads in the text tables, with their SI unit.
const LOAD_NAMES: [&str; 3] = ["Fx N", "Fy N", "Mz N m"];

/// Flexure 1's scale, for the text form: lengths and loads in SI.
/// The line that says which units flexure 1 sets.
fn units_line(units: &MechUnits) -> String {
    format!(
        "flexure 1 sets the units: L = {} {}; alpha = 1 is E I0/L^2 = {} N, beta = 1 is \
         E I0/L = {} N m\n",
        num(units.length * units.per_metre),
        units.distance,
        num(units.force),
        num(units.moment)
    )
}

/// `n` things, plural when not one.
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

/// `x` for a column printed with `decimals` digits: a value that rounds to zero there (a
/// reaction zero in exact arithmetic, met to the solver's tolerance) prints as `0`, not
/// `-0.0000`.
fn tidy(x: f64, decimals: i32) -> f64 {
    if x.abs() < 0.5 * 10f64.powi(-decimals) {
        0.0
    } else {
        x
    }
}

/// A drive path as the reports describe it.
#[derive(Debug, Clone, Serialize)]
pub struct DriveInfo {
    /// From 1.
    drive: usize,
    /// Per stage coordinate `[x, y, phi]`: prescribed (the output is the reaction) or loaded.
    prescribed: [bool; 3],
    /// Cases along the path.
    steps: u32,
}

impl DriveInfo {
    fn all(mechanism: &Mechanism) -> Vec<DriveInfo> {
        mechanism
            .drives
            .iter()
            .enumerate()
            .map(|(i, d)| DriveInfo {
                drive: i + 1,
                prescribed: d.coordinates.map(|c| c.is_prescribed()),
                steps: d.steps,
            })
            .collect()
    }
}

/// One line naming what a drive prescribes and what it loads, in SI.
fn drive_line(drive: usize, d: &Drive, units: &MechUnits) -> String {
    let (dist, factor) = (units.distance, units.per_metre);
    let mut prescribed = Vec::new();
    let mut loaded = Vec::new();
    for (c, (coordinate, (disp, load))) in d.coordinates.iter().zip(COORDINATE_KEYS).enumerate() {
        let v = coordinate.value();
        if coordinate.is_prescribed() {
            prescribed.push(if c == 2 {
                format!("{disp} -> {} deg", num(v.to_degrees()))
            } else {
                format!("{disp} -> {} {dist}", num(v * factor))
            });
        } else {
            let unit = if c == 2 { "N m" } else { "N" };
            loaded.push(format!("{load} -> {} {unit}", num(v)));
        }
    }
    let list = |v: Vec<String>| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    let steps = if d.rows.is_empty() {
        format!("{} steps", d.steps)
    } else {
        format!("{} measured rows to", d.rows.len())
    };
    format!(
        "drive {drive}, {steps}: prescribed {}; loaded {} (* = a reaction the drive supplies)",
        list(prescribed),
        list(loaded)
    )
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
}

/// One case of `solve` on a mechanism.
#[derive(Debug, Serialize)]
pub struct CaseRow {
    /// From 1.
    drive: usize,
    fraction: f64,
    stage: [f64; 3],
    stage_load: [f64; 3],
    flexures: Vec<FlexureRow>,
    iterations: u32,
}

impl CaseRow {
    fn new(drive: usize, c: &MechCase) -> CaseRow {
        CaseRow {
            drive,
            fraction: c.fraction,
            stage: c.stage,
            stage_load: c.stage_load,
            flexures: c
                .flexures
                .iter()
                .map(|f| FlexureRow {
                    tip: [f.tip.a, f.tip.b, f.tip.phi],
                    wrench: [f.wrench.alpha_x, f.wrench.alpha_y, f.wrench.beta],
                    load_stable: f.load_stable,
                })
                .collect(),
            iterations: c.iterations,
        }
    }
}

/// `solve` on a mechanism scene.
#[derive(Debug, Serialize)]
pub struct SolveReport {
    scene: String,
    flexure_count: usize,
    drives: Vec<DriveInfo>,
    tol: f64,
    cases: Vec<CaseRow>,
    seconds: f64,
    effects_decision: Option<EffectsDecision>,
    #[serde(skip)]
    mechanism: Mechanism,
}

impl fmt::Display for SolveReport {
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
                "{:>6} | {:>9} {:>9} {:>9} | {:>9} {:>9} | {:>9} {:>9} {:>9} | {:>11} {:>11} {:>11}",
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
            )?;
            for c in self.cases.iter().filter(|c| c.drive == info.drive) {
                let (s, l) = (c.stage, c.stage_load);
                writeln!(
                    f,
                    "{:>6.3} | {:>9.5} {:>9.5} {:>9.4} | {:>9.4} {:>9.4} | {:>9.4} {:>9.4} {:>9.4} | {:>11.5} {:>11.5} {:>11.6}",
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
                )?;
            }
        }
        writeln!(
            f,
            "{} cases in {:.3} ms",
            self.cases.len(),
            self.seconds * 1e3
        )
    }
}

/// A flag of the single beam given with a mechanism scene: bad input naming the flag.
fn refuse_flag(flag: &str, scene: &Scene, why: &str) -> anyhow::Error {
    bad(format!(
        "{flag}: \"{}\" is a mechanism scene, and {why}",
        safe(&scene.name)
    ))
}

/// The loads of a mechanism are its drives.
const LOADS_ARE_DRIVES: &str = "a mechanism's loads are its [[drives]] (edit them in the scene)";

/// What a mechanism scene's models are judged and fitted against: the measured cases of a
/// data scene (DESIGN §9), else the exact (beam) mechanism at `resolution`.
pub fn truth(
    scene: &Scene,
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<Vec<Vec<MechCase>>> {
    measured::truth(scene, mechanism, resolution).with_context(|| {
        format!(
            "mechanism scene \"{}\", the exact (beam) mechanism",
            safe(&scene.name)
        )
    })
}

/// The beam resolution the cantilever commands use for `tol`, checked on flexure 1's beam so
/// that a bad `--tol` is bad input naming the flag.
fn resolution(mechanism: &Mechanism, tol: f64) -> Result<Resolution> {
    let resolution = Resolution::with_tol(tol);
    for fl in &mechanism.flexures {
        BeamSolver::new(fl.beam.model(), resolution)
            .map_err(|e| bad(format!("--tol {}: {e}", num(tol))))?;
    }
    Ok(resolution)
}

/// Runs `prbfit solve` on a mechanism scene.
pub fn solve(
    scene: &Scene,
    mechanism: &Mechanism,
    decision: Option<EffectsDecision>,
    args: &SolveArgs,
) -> Result<()> {
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
    let resolution = resolution(mechanism, args.tol)?;
    let t0 = Instant::now();
    let mut progress = Progress::new("solving the mechanism");
    progress.update(|| format!("{} drive paths", mechanism.drives.len()));
    let paths = exact::solve(mechanism, resolution)
        .with_context(|| format!("mechanism scene \"{}\"", safe(&scene.name)))?;
    progress.finish();
    let cases = paths
        .iter()
        .enumerate()
        .flat_map(|(i, path)| path.iter().map(move |c| CaseRow::new(i + 1, c)))
        .collect();
    let report = SolveReport {
        effects_decision: decision,
        scene: scene.name.clone(),
        flexure_count: mechanism.flexures.len(),
        drives: DriveInfo::all(mechanism),
        tol: args.tol,
        cases,
        seconds: t0.elapsed().as_secs_f64(),
        mechanism: mechanism.clone(),
    };
    emit(&report, args.common.json)
}

/// A mechanism case's stage as judged: pose and load, as §8 writes them.
#[derive(Debug, Serialize)]
pub struct StageRow {
    stage: [f64; 3],
    stage_load: [f64; 3],
}

/// One case of `eval` on a mechanism: the PRB stage, the beam stage, the errors.
#[derive(Debug, Serialize)]
pub struct EvalCaseRow {
    /// From 1.
    drive: usize,
    fraction: f64,
    /// The PRB mechanism's stage pose.
    stage: [f64; 3],
    /// The PRB mechanism's stage load (given or reaction).
    stage_load: [f64; 3],
    /// The exact (beam) mechanism's stage.
    beam: StageRow,
    pos_err: f64,
    ang_err: f64,
    force_err: f64,
    /// The largest flexure tip position error, units of that flexure's `L`.
    tip_err: f64,
}

impl From<&MechCaseError> for EvalCaseRow {
    fn from(c: &MechCaseError) -> EvalCaseRow {
        EvalCaseRow {
            drive: c.drive,
            fraction: c.fraction,
            stage: c.prb.stage,
            stage_load: c.prb.stage_load,
            beam: StageRow {
                stage: c.exact.stage,
                stage_load: c.exact.stage_load,
            },
            pos_err: c.pos_err,
            ang_err: c.ang_err,
            force_err: c.force_err,
            tip_err: c.tip_err,
        }
    }
}

/// One model over the mechanism scene.
#[derive(Debug, Serialize)]
pub struct ModelRow {
    model: String,
    prb: String,
    topology: String,
    /// The seven figures; absent when the model cannot follow the mechanism.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    figures: Option<MechFigures>,
    meets_targets: bool,
    /// Why the PRB mechanism could not be solved, when it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    failure: Option<String>,
    seconds: f64,
    cases: Vec<EvalCaseRow>,
}

/// `eval` on a mechanism scene.
#[derive(Debug, Serialize)]
pub struct EvalReport {
    #[serde(flatten)]
    models: OneOrMany<ModelRow>,
    scene: String,
    drives: Vec<DriveInfo>,
    /// The reaction scale `S_c` of each stage coordinate (nondimensional); 0 where no drive
    /// prescribes the coordinate.
    reaction_scale: [f64; 3],
    baseline_seconds: f64,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth (DESIGN §9): the file, and the beam mechanism against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    #[serde(skip)]
    accuracy: Accuracy,
    #[serde(skip)]
    angle_weight: f64,
    #[serde(skip)]
    force_weight: f64,
    #[serde(skip)]
    mechanism: Mechanism,
}

impl EvalReport {
    /// Per drive, the table of what the drive produces: the loaded coordinates' motion and
    /// the prescribed ones' reactions, beam against PRB.
    fn case_table(&self, f: &mut fmt::Formatter<'_>, row: &ModelRow) -> fmt::Result {
        let units = MechUnits::new(&self.mechanism);
        let (dist, factor) = (units.distance, units.per_metre);
        let truth = if self.truth.is_some() { "data" } else { "beam" };
        for (info, drive) in self.drives.iter().zip(&self.mechanism.drives) {
            writeln!(f)?;
            writeln!(
                f,
                "{}: {}",
                safe(&row.model),
                drive_line(info.drive, drive, &units)
            )?;
            // The columns: the drive's own prescribed motions (the abscissa), then per
            // coordinate the output, beam and PRB.
            let mut head = format!("{:>6}", "frac");
            for (c, (disp, _)) in COORDINATE_KEYS.iter().enumerate() {
                if info.prescribed[c] && drive.coordinates[c].value() != 0.0 {
                    let unit = if c == 2 { "deg" } else { dist };
                    head.push_str(&format!(" {:>10}", format!("{disp} {unit}")));
                }
            }
            head.push_str(" |");
            for (c, (disp, _)) in COORDINATE_KEYS.iter().enumerate() {
                let name = if info.prescribed[c] {
                    format!("{}*", LOAD_NAMES[c])
                } else if c == 2 {
                    format!("{disp} deg")
                } else {
                    format!("{disp} {dist}")
                };
                head.push_str(&format!(" {:>11} {:>11}", format!("{truth} {name}"), "PRB"));
            }
            head.push_str(&format!(
                " | {:>9} {:>9} {:>9}",
                "pos_err", "ang_err", "force_err"
            ));
            writeln!(f, "{head}")?;
            // An output in SI: the reaction (N, N m) or the motion (mm or m, degrees).
            let output = |c: usize, stage: &[f64; 3], load: &[f64; 3]| {
                let v = if info.prescribed[c] {
                    load[c] * units.load(c)
                } else if c == 2 {
                    stage[c].to_degrees()
                } else {
                    stage[c] * units.length * factor
                };
                tidy(v, 5)
            };
            for c in row.cases.iter().filter(|c| c.drive == info.drive) {
                let mut line = format!("{:>6.3}", c.fraction);
                for k in 0..3 {
                    if info.prescribed[k] && drive.coordinates[k].value() != 0.0 {
                        let v = if k == 2 {
                            c.beam.stage[k].to_degrees()
                        } else {
                            c.beam.stage[k] * units.length * factor
                        };
                        line.push_str(&format!(" {v:>10.4}"));
                    }
                }
                line.push_str(" |");
                for k in 0..3 {
                    line.push_str(&format!(
                        " {:>11.5} {:>11.5}",
                        output(k, &c.beam.stage, &c.beam.stage_load),
                        output(k, &c.stage, &c.stage_load)
                    ));
                }
                line.push_str(&format!(
                    " | {:>9.2e} {:>9.2e} {:>9.2e}",
                    c.pos_err, c.ang_err, c.force_err
                ));
                writeln!(f, "{line}")?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for EvalReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cases = self.mechanism.case_count();
        writeln!(
            f,
            "scene: {} (mechanism: {}, {}, {})",
            safe(&self.scene),
            count(self.mechanism.flexures.len(), "flexure"),
            count(self.drives.len(), "drive path"),
            count(usize::try_from(cases).unwrap_or(usize::MAX), "case")
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
        write!(f, "{}", units_line(&MechUnits::new(&self.mechanism)))?;
        writeln!(
            f,
            "targets: max position error {} L, max angle error {} rad, max reaction error {} \
             (of each prescribed coordinate's largest reaction); weights: angle {}, force {}",
            num(self.accuracy.max_pos_err),
            num(self.accuracy.max_ang_err),
            num(self.accuracy.max_force_err),
            num(self.angle_weight),
            num(self.force_weight)
        )?;
        for row in self.models.rows().iter().filter(|r| r.failure.is_none()) {
            self.case_table(f, row)?;
        }
        writeln!(f)?;
        let w = self
            .models
            .rows()
            .iter()
            .map(|r| safe(&r.model).chars().count())
            .fold(12, usize::max);
        let per_case = 1e6 / (self.mechanism.case_count().max(1) as f64);
        writeln!(
            f,
            "{:<w$} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>8}  targets",
            "model",
            "rms pos",
            "max pos",
            "rms ang",
            "max ang",
            "rms force",
            "max force",
            "J",
            "max tip",
            "us/case"
        )?;
        for r in self.models.rows() {
            match (&r.figures, &r.failure) {
                (Some(m), _) => writeln!(
                    f,
                    "{:<w$} {:>9.2e} {:>9.2e} {:>9.2e} {:>9.2e} {:>9.2e} {:>9.2e} {:>10.3e} {:>9} {:>8.1}  {}",
                    safe(&r.model),
                    m.rms_pos_err,
                    m.max_pos_err,
                    m.rms_ang_err,
                    m.max_ang_err,
                    m.rms_force_err,
                    m.max_force_err,
                    m.objective,
                    if self.truth.is_some() {
                        "-".to_string()
                    } else {
                        format!("{:.2e}", m.max_tip_err)
                    },
                    r.seconds * per_case,
                    met(r.meets_targets)
                )?,
                (None, failure) => writeln!(
                    f,
                    "{:<w$} cannot follow the mechanism: {}",
                    safe(&r.model),
                    failure.as_deref().unwrap_or("no solution")
                )?,
            }
        }
        if self.truth.is_some() {
            // A rig measures the stage, not the flexures' tips.
            writeln!(
                f,
                "(max tip: not judged on measured data, which has no flexure tips)"
            )
        } else {
            writeln!(
                f,
                "baseline (exact mechanism): {:.3} ms",
                self.baseline_seconds * 1e3
            )
        }
    }
}

/// Runs `prbfit eval` on a mechanism scene.
pub fn eval(
    scene: &Scene,
    mechanism: &Mechanism,
    decision: Option<EffectsDecision>,
    args: &EvalArgs,
) -> Result<()> {
    if args.load.is_some() {
        return Err(refuse_flag("--load", scene, LOADS_ARE_DRIVES));
    }
    let models = named_models(args, scene)?;
    let resolution = resolution(mechanism, args.tol)?;
    let (angle_weight, force_weight) = (scene.fit.angle_weight, scene.fit.force_weight);

    let t0 = Instant::now();
    let mut progress = Progress::new("solving the exact mechanism");
    progress.update(|| format!("{} drive paths", mechanism.drives.len()));
    let exact = truth(scene, mechanism, resolution)?;
    progress.finish();
    let baseline_seconds = t0.elapsed().as_secs_f64();

    let mut rows = Vec::new();
    let mut scale = [0.0; 3];
    for (name, matrix) in models {
        let t0 = Instant::now();
        let mut row = ModelRow {
            model: name.clone(),
            prb: matrix.to_text(),
            topology: matrix.topology(),
            figures: None,
            meets_targets: false,
            failure: None,
            seconds: 0.0,
            cases: Vec::new(),
        };
        match prb::solve(mechanism, &matrix, args.tol) {
            Ok(paths) => {
                let e = compare(
                    &mechanism.drives,
                    &paths,
                    &exact,
                    angle_weight,
                    force_weight,
                )
                .with_context(|| format!("model {name}"))?;
                scale = e.reaction_scale.map(|s| s.unwrap_or(0.0));
                row.meets_targets = e.figures.meets(&scene.accuracy);
                row.figures = Some(e.figures);
                row.cases = e.cases.iter().map(EvalCaseRow::from).collect();
            }
            Err(e) => row.failure = Some(e.to_string()),
        }
        row.seconds = t0.elapsed().as_secs_f64();
        rows.push(row);
    }
    if rows.iter().all(|r| r.failure.is_some()) {
        let reasons: Vec<String> = rows
            .iter()
            .filter_map(|r| {
                r.failure
                    .as_ref()
                    .map(|why| format!("model {}: {why}", safe(&r.model)))
            })
            .collect();
        anyhow::bail!(
            "no model given can follow the mechanism of \"{}\": {}",
            safe(&scene.name),
            reasons.join("; ")
        );
    }
    let report = EvalReport {
        truth: TruthInfo::of(scene),
        effects_decision: decision,
        models: OneOrMany::new(rows),
        scene: scene.name.clone(),
        drives: DriveInfo::all(mechanism),
        reaction_scale: scale,
        baseline_seconds,
        accuracy: scene.accuracy,
        angle_weight,
        force_weight,
        mechanism: mechanism.clone(),
    };
    emit(&report, args.common.json)
}

/// What `prbfit fit` found on a mechanism scene.
#[derive(Debug, Serialize)]
pub struct MechFitOutput {
    prb: String,
    topology: String,
    #[serde(flatten)]
    figures: MechFigures,
    start_objective: f64,
    meets_targets: bool,
    iterations: u32,
    evaluations: u64,
    stop_reason: StopReason,
    fidelity: Fidelity,
    cases: usize,
    baseline_seconds: f64,
    seconds: f64,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth (DESIGN §9): the file, and the beam mechanism against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    /// The model file written (`-o`).
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    #[serde(skip)]
    scene: String,
    #[serde(skip)]
    matrix: PrbMatrix,
    #[serde(skip)]
    accuracy: Accuracy,
}

impl fmt::Display for MechFitOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = &self.figures;
        writeln!(
            f,
            "scene: {} (mechanism, {} cases at {} fidelity)",
            safe(&self.scene),
            self.cases,
            self.fidelity
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
        writeln!(f, "fitted {}: {}", self.topology, self.matrix)?;
        writeln!(
            f,
            "J = {:.4e} (start {:.4e}); position error max {:.3e} L; angle error max {:.3e} rad; \
             reaction error rms {:.3e} max {:.3e}",
            m.objective,
            self.start_objective,
            m.max_pos_err,
            m.max_ang_err,
            m.rms_force_err,
            m.max_force_err
        )?;
        writeln!(
            f,
            "targets ({} L, {} rad, reaction {}): {}",
            num(self.accuracy.max_pos_err),
            num(self.accuracy.max_ang_err),
            num(self.accuracy.max_force_err),
            met(self.meets_targets)
        )?;
        if let Some(path) = &self.saved {
            writeln!(f, "saved {}", safe(path))?;
        }
        let truth = if self.truth.is_some() {
            "against the measured data".to_string()
        } else {
            format!("exact mechanism {:.1} ms", self.baseline_seconds * 1e3)
        };
        writeln!(
            f,
            "{}; {} iterations, {} evaluations, {:.1} ms ({truth})",
            self.stop_reason,
            self.iterations,
            self.evaluations,
            self.seconds * 1e3,
        )
    }
}

/// Runs `prbfit fit` on a mechanism scene: one matrix for every flexure, fitted to the exact
/// mechanism along the scene's drives (DESIGN §8's `J`).
pub fn fit(
    scene: &Scene,
    mechanism: &Mechanism,
    decision: Option<EffectsDecision>,
    args: &FitArgs,
) -> Result<()> {
    let format = super::fit::model_file_target(args)?;
    let start = super::fit::start_matrix(args, scene)?;
    let resolution = resolution(mechanism, Resolution::default().tol)?;
    let t0 = Instant::now();
    let exact = truth(scene, mechanism, resolution)?;
    let baseline_seconds = t0.elapsed().as_secs_f64();
    let options = FitOptions {
        fidelity: args.fidelity,
        angle_weight: scene.fit.angle_weight,
        seed: args.seed,
    };
    let mut progress = Progress::new("fitting");
    let report = fit_mechanism(
        mechanism,
        &exact,
        &start,
        &options,
        scene.fit.force_weight,
        &scene.accuracy,
        &mut |p| super::fit::show(&mut progress, p),
        &CancelToken::new(),
    )
    .map_err(|e| match e {
        MechFitError::Fit(FitError::Param(p)) => bad(format!("--prb: {p}")),
        other => anyhow::Error::new(other),
    })?;
    progress.finish();
    if let (Some(path), Some(format)) = (&args.output, format) {
        let model = ModelFile::fitted_mechanism(
            &report.matrix,
            scene,
            mechanism,
            &args.fidelity.to_string(),
            &report.figures,
        );
        let text = match format {
            Format::Json => model.to_json()?,
            _ => model.to_toml()?,
        };
        write_atomic(path, text.as_bytes(), args.force)?;
    }
    let output = MechFitOutput {
        truth: TruthInfo::of(scene),
        saved: args.output.as_ref().map(|p| p.display().to_string()),
        effects_decision: decision,
        prb: report.matrix.to_text(),
        topology: report.matrix.topology(),
        figures: report.figures,
        start_objective: report.start_objective,
        meets_targets: report.figures.meets(&scene.accuracy),
        iterations: report.iterations,
        evaluations: report.evaluations,
        stop_reason: report.stop,
        fidelity: report.fidelity,
        cases: exact.iter().map(Vec::len).sum(),
        baseline_seconds,
        seconds: t0.elapsed().as_secs_f64(),
        scene: scene.name.clone(),
        matrix: report.matrix,
        accuracy: scene.accuracy,
    };
    emit(&output, args.common.json)
}
