//! `prbfit eval`: PRB models judged against the scene's truth (the beam, the beam mechanism,
//! or measured data), at one load or over the scene. Every model is judged on one study
//! ([`crate::study::Study::judge`]); the report reads as the scene's cases do (DESIGN §4's
//! tips, §8's stage).
//!
//! A model that cannot follow some load paths or drives to their end is judged over the
//! cases it followed (DESIGN §6): its row lists `unfollowed: [{path, fraction, reason}]`, the
//! text a line naming each, and it does not meet the targets. A model that follows no case
//! at all (a 1R asked to keep its tip angle) is a row saying why; with every model failing
//! there is nothing to report and the status is 1.

use std::fmt;
use std::time::Instant;

use serde::Serialize;

use crate::beam::{Load, Resolution, TipPose};
use crate::io::ModelFile;
use crate::mech::figures::{Figures, JudgedCase, UnfollowedPath};
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, Mechanism, Scene, COORDINATE_KEYS};
use crate::si::MechUnits;
use crate::study::{CaseForm, EffectsDecision, Sampling};

mod at_load;
mod stress;

use at_load::at_load;
pub use at_load::{AtLoad, AtLoadReport};

pub use stress::StressFigures;
use stress::StressLines;

use super::stage::{count, drive_line, tidy, units_line, DriveInfo, LOAD_NAMES};
use super::{
    frequency_lines, met, num, parse_matrix, safe, scene_model, study, Control, DecisionLine,
    ReportError, Result, TruthInfo, TruthLine,
};

/// `eval`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct EvalArgs {
    /// PRB matrices in text form (`--prb`, repeatable).
    pub prb: Vec<String>,
    /// Published model names or model files (`--model`, repeatable). With neither: the
    /// scene's `[prb] matrix`.
    pub model: Vec<String>,
    /// One tip load instead of the scene's cases (`--load`).
    pub load: Option<Load>,
    /// Baseline integrator tolerance (`--tol`).
    pub tol: f64,
}

impl Default for EvalArgs {
    fn default() -> EvalArgs {
        EvalArgs {
            prb: Vec::new(),
            model: Vec::new(),
            load: None,
            tol: Resolution::default().tol,
        }
    }
}

/// What `eval` reports: the models at one load, or over the scene.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum EvalOutput {
    /// `--load`.
    AtLoad(Box<AtLoadReport>),
    /// Over the scene's cases.
    Scene(Box<EvalReport>),
}

impl fmt::Display for EvalOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvalOutput::AtLoad(r) => r.fmt(f),
            EvalOutput::Scene(r) => r.fmt(f),
        }
    }
}

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

/// One case of a cantilever's evaluation: the PRB tip, the beam tip, the errors.
#[derive(Debug, Serialize)]
pub struct TipRow {
    load: Load,
    #[serde(flatten)]
    prb: TipPose,
    beam: TipPose,
    pos_err: f64,
    ang_err: f64,
    /// The PRB model's stress estimate, Pa (DESIGN §11).
    #[serde(skip_serializing_if = "Option::is_none")]
    max_stress: Option<f64>,
    /// The beam's largest fibre stress, Pa (none on measured data).
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_max_stress: Option<f64>,
}

/// A mechanism case's stage as judged: pose and load, as §8 writes them.
#[derive(Debug, Serialize)]
pub struct StageOnly {
    stage: [f64; 3],
    stage_load: [f64; 3],
    /// Per flexure, the largest fibre stress, Pa (null on measured data).
    max_stress: Vec<Option<f64>>,
}

/// One case of a mechanism's evaluation: the PRB stage, the truth's stage, the errors.
#[derive(Debug, Serialize)]
pub struct StageRow {
    /// From 1.
    drive: usize,
    fraction: f64,
    /// The PRB mechanism's stage pose.
    stage: [f64; 3],
    /// The PRB mechanism's stage load (given or reaction).
    stage_load: [f64; 3],
    /// The truth's stage.
    beam: StageOnly,
    pos_err: f64,
    ang_err: f64,
    force_err: f64,
    /// The largest flexure tip position error, units of that flexure's `L`.
    tip_err: f64,
    /// Per flexure, the PRB model's stress estimate, Pa (DESIGN §11).
    max_stress: Vec<Option<f64>>,
}

/// One case, in the form of the scene's cases.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum CaseRow {
    /// A cantilever's.
    Tip(TipRow),
    /// A mechanism's.
    Stage(StageRow),
}

impl CaseRow {
    /// The case `c` as `form` reads it; `youngs`: each flexure's Young's modulus (its
    /// stress unit).
    fn new(c: &JudgedCase, form: CaseForm, youngs: &[f64]) -> CaseRow {
        let pa = |case: &crate::mech::MechCase| -> Vec<Option<f64>> {
            case.flexures
                .iter()
                .zip(youngs)
                .map(|(f, e)| f.stress.map(|s| s.max * e))
                .collect()
        };
        match (form, c.model.flexures.first(), c.truth.flexures.first()) {
            (CaseForm::Tip, Some(prb), Some(beam)) => CaseRow::Tip(TipRow {
                load: prb.wrench,
                prb: prb.tip,
                beam: beam.tip,
                pos_err: c.pos_err,
                ang_err: c.ang_err,
                max_stress: pa(&c.model).first().copied().flatten(),
                beam_max_stress: pa(&c.truth).first().copied().flatten(),
            }),
            _ => CaseRow::Stage(StageRow {
                drive: c.path,
                fraction: c.fraction,
                stage: c.model.stage,
                stage_load: c.model.stage_load,
                beam: StageOnly {
                    stage: c.truth.stage,
                    stage_load: c.truth.stage_load,
                    max_stress: pa(&c.truth),
                },
                pos_err: c.pos_err,
                ang_err: c.ang_err,
                force_err: c.force_err,
                tip_err: c.tip_err,
                max_stress: pa(&c.model),
            }),
        }
    }

    fn stage(&self) -> Option<&StageRow> {
        match self {
            CaseRow::Stage(s) => Some(s),
            CaseRow::Tip(_) => None,
        }
    }
}

/// One model over the scene.
#[derive(Debug, Serialize)]
pub struct ModelRow {
    model: String,
    prb: String,
    topology: String,
    /// The figures; absent when the model cannot follow the scene.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    figures: Option<Figures>,
    meets_targets: bool,
    /// Why the PRB model could not be solved, when it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    failure: Option<String>,
    /// The paths it could not follow to their end; its figures are over the cases it
    /// followed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    unfollowed: Vec<UnfollowedPath>,
    /// Per flexure, the PRB model's stress estimate beside the truth's (DESIGN §11); absent
    /// on measured data, which has no stress.
    #[serde(skip_serializing_if = "Option::is_none")]
    stress: Option<Vec<StressFigures>>,
    seconds: f64,
    cases: Vec<CaseRow>,
}

impl ModelRow {
    /// Its stress lines (one per flexure, named on a mechanism).
    fn stress_lines(&self, mechanism: bool) -> StressLines<'_> {
        StressLines {
            model: &self.model,
            figures: self.stress.as_deref(),
            mechanism,
        }
    }

    /// One line per path the model could not follow to its end.
    fn unfollowed_lines(&self, f: &mut fmt::Formatter<'_>, path: &str) -> fmt::Result {
        for u in &self.unfollowed {
            writeln!(
                f,
                "{}: {path} {} not followed past {:.4} of it: {}",
                safe(&self.model),
                u.path,
                u.fraction,
                safe(&u.reason)
            )?;
        }
        Ok(())
    }
}

/// `eval` over the scene.
#[derive(Debug, Serialize)]
pub struct EvalReport {
    #[serde(flatten)]
    models: OneOrMany<ModelRow>,
    scene: String,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth (DESIGN §9): the file, and the beam (mechanism) against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    baseline_seconds: f64,
    /// A mechanism's drives.
    #[serde(skip_serializing_if = "Option::is_none")]
    drives: Option<Vec<DriveInfo>>,
    /// A mechanism's reaction scale `S_c` of each stage coordinate (nondimensional); 0 where
    /// no drive prescribes the coordinate.
    #[serde(skip_serializing_if = "Option::is_none")]
    reaction_scale: Option<[f64; 3]>,
    #[serde(skip)]
    form: CaseForm,
    #[serde(skip)]
    cases: usize,
    #[serde(skip)]
    accuracy: Accuracy,
    #[serde(skip)]
    angle_weight: f64,
    #[serde(skip)]
    force_weight: f64,
    #[serde(skip)]
    mechanism: Mechanism,
    /// The natural frequencies the scene judges (`[fit] modes`).
    #[serde(skip)]
    modes: u32,
}

impl fmt::Display for EvalReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.form {
            CaseForm::Tip => self.fmt_tip(f),
            CaseForm::Stage => self.fmt_stage(f),
        }
    }
}

impl EvalReport {
    /// The frequency target's lines for every model judged, when the scene judges them.
    fn frequency_lines(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        frequency_lines(
            f,
            self.modes,
            self.accuracy.max_freq_err,
            self.models
                .rows()
                .iter()
                .filter_map(|r| r.figures.as_ref().map(|m| (r.model.as_str(), m))),
        )
    }

    /// The text of a cantilever's evaluation.
    fn fmt_tip(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {} ({} load cases)",
            safe(&self.scene),
            self.cases
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
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
            match (&r.figures, &r.failure) {
                (Some(m), _) => writeln!(
                    f,
                    "{:<12} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>11.4e}  {}",
                    safe(&r.model),
                    m.rms_pos_err,
                    m.max_pos_err,
                    m.rms_ang_err,
                    m.max_ang_err,
                    m.objective,
                    met(r.meets_targets)
                )?,
                (None, failure) => writeln!(
                    f,
                    "{:<12} cannot follow the scene: {}",
                    safe(&r.model),
                    safe(failure.as_deref().unwrap_or("no solution"))
                )?,
            }
        }
        self.frequency_lines(f)?;
        for r in self.models.rows() {
            r.unfollowed_lines(f, "load path")?;
        }
        self.stress_lines(f, false)?;
        writeln!(f, "baseline: {:.3} ms", self.baseline_seconds * 1e3)
    }

    /// Every model's stress lines, or why there are none (measured data has no stress).
    fn stress_lines(&self, f: &mut fmt::Formatter<'_>, mechanism: bool) -> fmt::Result {
        if self.truth.is_some() {
            return writeln!(
                f,
                "stress: not judged (the data has no stress; the PRB models' estimates are in \
                 the JSON cases)"
            );
        }
        for r in self.models.rows() {
            write!(f, "{}", r.stress_lines(mechanism))?;
        }
        Ok(())
    }

    /// Per drive, the table of what the drive produces: the loaded coordinates' motion and
    /// the prescribed ones' reactions, beam against PRB.
    fn case_table(&self, f: &mut fmt::Formatter<'_>, row: &ModelRow) -> fmt::Result {
        let drives = self.drives.as_deref().unwrap_or_default();
        let units = MechUnits::new(&self.mechanism);
        let (dist, factor) = (units.distance, units.per_metre);
        let truth = if self.truth.is_some() { "data" } else { "beam" };
        for (info, drive) in drives.iter().zip(&self.mechanism.drives) {
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
            for c in row
                .cases
                .iter()
                .filter_map(CaseRow::stage)
                .filter(|c| c.drive == info.drive)
            {
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

    /// The text of a mechanism scene's evaluation.
    fn fmt_stage(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let cases = self.mechanism.case_count();
        writeln!(
            f,
            "scene: {} (mechanism: {}, {}, {})",
            safe(&self.scene),
            count(self.mechanism.flexures.len(), "flexure"),
            count(self.mechanism.drives.len(), "drive path"),
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
                    m.rms_force_err.unwrap_or(0.0),
                    m.max_force(),
                    m.objective,
                    m.max_tip_err
                        .map_or_else(|| "-".to_string(), |t| format!("{t:.2e}")),
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
        self.frequency_lines(f)?;
        for r in self.models.rows() {
            r.unfollowed_lines(f, "drive")?;
        }
        self.stress_lines(f, true)?;
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

/// `prbfit eval` on `scene`.
pub fn eval(scene: &Scene, args: &EvalArgs, ctl: &mut Control<'_>) -> Result<EvalOutput> {
    if let Some(load) = args.load {
        return at_load(args, scene, load, ctl).map(|r| EvalOutput::AtLoad(Box::new(r)));
    }
    let resolution = super::resolution(scene, args.tol)?;
    let models = named_models(args, scene)?;
    let study = study(scene, Sampling::Every(resolution), ctl)?;
    let form = study.case_form();
    let scene = study.scene();
    let accuracy = scene.accuracy;
    let youngs: Vec<f64> = study
        .mechanism()
        .flexures
        .iter()
        .map(|f| f.beam.youngs_modulus)
        .collect();
    let mut rows = Vec::new();
    let mut scale = None;
    for (name, matrix) in models {
        let t0 = Instant::now();
        let mut row = ModelRow {
            model: name,
            prb: matrix.to_text(),
            topology: matrix.topology(),
            figures: None,
            meets_targets: false,
            failure: None,
            unfollowed: Vec::new(),
            stress: None,
            seconds: 0.0,
            cases: Vec::new(),
        };
        match study.judge_followed(&matrix) {
            Ok(e) => {
                scale = Some(e.reaction_scale.map(|s| s.unwrap_or(0.0)));
                // A model that stops short does not meet the targets, whatever its figures
                // over the cases it reached.
                row.meets_targets = e.figures.meets(&accuracy) && e.unfollowed.is_empty();
                row.unfollowed = e.unfollowed;
                row.figures = Some(e.figures);
                row.stress = stress::figures(&e.cases, &youngs);
                row.cases = e
                    .cases
                    .iter()
                    .map(|c| CaseRow::new(c, form, &youngs))
                    .collect();
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
        return Err(ReportError::solve(format!(
            "no model given can follow the {} of \"{}\": {}",
            match form {
                CaseForm::Tip => "loads",
                CaseForm::Stage => "mechanism",
            },
            safe(&scene.name),
            reasons.join("; ")
        )));
    }
    let mechanism = form == CaseForm::Stage;
    let report = EvalReport {
        truth: TruthInfo::of(&study),
        models: OneOrMany::new(rows),
        scene: scene.name.clone(),
        effects_decision: study.decision().cloned(),
        baseline_seconds: study.seconds(),
        drives: mechanism.then(|| DriveInfo::all(study.mechanism())),
        reaction_scale: scale.filter(|_| mechanism),
        form,
        cases: study.case_count(),
        accuracy,
        angle_weight: scene.fit.angle_weight,
        force_weight: scene.fit.force_weight,
        mechanism: study.mechanism().clone(),
        modes: scene.fit.modes,
    };
    Ok(EvalOutput::Scene(Box::new(report)))
}
