//! `prbfit fit`: the free cells of a matrix fitted to the scene's truth (the beam over its
//! loads, the beam mechanism along its drives — one matrix for every flexure — or measured
//! data), by [`crate::study::Study::fit`].

use std::fmt;

use std::path::PathBuf;

use serde::Serialize;

use crate::fidelity::Fidelity;
use crate::fit::{FitOptions, SearchError, StopReason};
use crate::format::Format;
use crate::io::files::{check_target, write_atomic};
use crate::io::ModelFile;
use crate::mech::figures::Figures;
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, Scene};
use crate::study::{CaseForm, EffectsDecision, FitError, Sampling};

use super::{
    frequency_lines, met, num, parse_matrix, safe, scene_model, study, Control, DecisionLine,
    Progress, ReportError, Result, TruthInfo, TruthLine,
};

/// `fit`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct FitArgs {
    /// Topology to fit from (`--topology`); it and `prb` are exclusive. With neither: the
    /// scene's `[prb] matrix`.
    pub topology: Option<String>,
    /// Matrix to start from (`--prb`); cells ending in `!` stay fixed.
    pub prb: Option<String>,
    /// The fit's preset.
    pub fidelity: Fidelity,
    /// Seed of the random starts.
    pub seed: u64,
    /// Save the fitted model here (`-o`, .toml or .json).
    pub output: Option<PathBuf>,
    /// Overwrite the output if it exists.
    pub force: bool,
}

impl Default for FitArgs {
    fn default() -> FitArgs {
        FitArgs {
            topology: None,
            prb: None,
            fidelity: Fidelity::Normal,
            seed: 1,
            output: None,
            force: false,
        }
    }
}

/// What `fit` found.
#[derive(Debug, Serialize)]
pub struct FitOutput {
    prb: String,
    topology: String,
    #[serde(flatten)]
    figures: Figures,
    start_objective: f64,
    meets_targets: bool,
    iterations: u32,
    evaluations: u64,
    stop_reason: StopReason,
    fidelity: Fidelity,
    cases: usize,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth, and the beam's own error against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    baseline_seconds: f64,
    seconds: f64,
    /// The model file written (`-o`).
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    #[serde(skip)]
    scene: String,
    #[serde(skip)]
    matrix: PrbMatrix,
    #[serde(skip)]
    accuracy: Accuracy,
    #[serde(skip)]
    form: CaseForm,
    /// The natural frequencies the scene judges (`[fit] modes`).
    #[serde(skip)]
    modes: u32,
}

impl fmt::Display for FitOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.form {
            CaseForm::Tip => self.fmt_tip(f),
            CaseForm::Stage => self.fmt_stage(f),
        }
    }
}

impl FitOutput {
    /// The model file written, and whether it holds a fit stopped before it finished.
    fn saved_line(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.saved, self.stop_reason) {
            (Some(path), StopReason::Cancelled) => writeln!(
                f,
                "saved {} (marked stopped early: the best so far)",
                safe(path)
            ),
            (Some(path), _) => writeln!(f, "saved {}", safe(path)),
            (None, _) => Ok(()),
        }
    }

    /// The fitted model's frequency target line, when the scene judges frequencies.
    fn frequency_line(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        frequency_lines(
            f,
            self.modes,
            self.accuracy.max_freq_err,
            [("fitted", &self.figures)],
        )
    }

    /// The text of a cantilever's fit.
    fn fmt_tip(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = &self.figures;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
        writeln!(
            f,
            "scene: {} ({} load cases at {} fidelity)",
            safe(&self.scene),
            self.cases,
            self.fidelity
        )?;
        writeln!(f, "fitted {}: {}", self.topology, self.matrix)?;
        writeln!(
            f,
            "J = {:.4e} (start {:.4e}); position error rms {:.3e} max {:.3e} L; angle error rms {:.3e} max {:.3e} rad",
            m.objective, self.start_objective, m.rms_pos_err, m.max_pos_err, m.rms_ang_err, m.max_ang_err
        )?;
        writeln!(
            f,
            "targets ({} L, {} rad): {}",
            num(self.accuracy.max_pos_err),
            num(self.accuracy.max_ang_err),
            met(self.meets_targets)
        )?;
        self.frequency_line(f)?;
        writeln!(
            f,
            "{}; {} iterations, {} evaluations, {:.1} ms (baseline {:.1} ms)",
            self.stop_reason,
            self.iterations,
            self.evaluations,
            self.seconds * 1e3,
            self.baseline_seconds * 1e3
        )?;
        self.saved_line(f)?;
        Ok(())
    }

    /// The text of a mechanism scene's fit.
    fn fmt_stage(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
            m.rms_force_err.unwrap_or(0.0),
            m.max_force()
        )?;
        writeln!(
            f,
            "targets ({} L, {} rad, reaction {}): {}",
            num(self.accuracy.max_pos_err),
            num(self.accuracy.max_ang_err),
            num(self.accuracy.max_force_err),
            met(self.meets_targets)
        )?;
        self.frequency_line(f)?;
        self.saved_line(f)?;
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

/// The matrix a fit starts from: `--topology`, `--prb`, or the scene's own model.
pub fn start_matrix(args: &FitArgs, scene: &Scene) -> Result<PrbMatrix> {
    Ok(match (&args.topology, &args.prb) {
        (Some(t), _) => PrbMatrix::from_topology(t)
            .map_err(|e| ReportError::input(format!("--topology {t}: {e}")))?,
        (None, Some(text)) => parse_matrix("--prb", text)?,
        (None, None) => scene_model(scene)?.1,
    })
}

/// The format of the model file `-o` names (checked, and refused if it exists without
/// `--force`, before any time is spent on a fit); none without `-o`.
pub fn model_file_target(args: &FitArgs) -> Result<Option<Format>> {
    let Some(path) = &args.output else {
        return Ok(None);
    };
    let format = Format::from_path(path)
        .filter(|f| f.is_model_file())
        .ok_or_else(|| {
            ReportError::input(format!(
                "{}: a model file must end in .toml or .json",
                path.display()
            ))
        })?;
    check_target(path, args.force)?;
    Ok(Some(format))
}

/// `prbfit fit` on `scene`.
pub fn fit(scene: &Scene, args: &FitArgs, ctl: &mut Control<'_>) -> Result<FitOutput> {
    let start = start_matrix(args, scene)?;
    let format = model_file_target(args)?;
    let t0 = std::time::Instant::now();
    let study = study(scene, Sampling::Fidelity(args.fidelity), ctl)?;
    let scene = study.scene();
    let options = FitOptions {
        fidelity: args.fidelity,
        angle_weight: scene.fit.angle_weight,
        seed: args.seed,
    };
    let progress = &mut *ctl.progress;
    let report = study
        .fit(
            &start,
            &options,
            &mut |p| progress(&Progress::Fit(p)),
            &ctl.cancel,
        )
        .map_err(|e| match e {
            FitError::Search(SearchError::Param(p)) => ReportError::input(format!("--prb: {p}")),
            other => ReportError::failed(&other),
        })?;
    let figures = report.figures;
    if let (Some(path), Some(format)) = (&args.output, format) {
        let model = ModelFile::fitted(&report.matrix, scene, &args.fidelity.to_string(), &figures);
        // Ctrl-C keeps the best so far (the CLI prints it too), marked as such.
        let model = match report.stop {
            StopReason::Cancelled => model.stopped_early("cancelled"),
            _ => model,
        };
        let text = match format {
            Format::Json => model.to_json(),
            _ => model.to_toml(),
        }
        .map_err(|e| ReportError::failed(&e))?;
        write_atomic(path, text.as_bytes(), args.force)?;
    }
    let out = FitOutput {
        prb: report.matrix.to_text(),
        topology: report.matrix.topology(),
        figures,
        start_objective: report.start_objective,
        meets_targets: figures.meets(&scene.accuracy),
        iterations: report.iterations,
        evaluations: report.evaluations,
        stop_reason: report.stop,
        fidelity: args.fidelity,
        cases: study.case_count(),
        effects_decision: study.decision().cloned(),
        truth: TruthInfo::of(&study),
        baseline_seconds: study.seconds(),
        seconds: t0.elapsed().as_secs_f64(),
        saved: args.output.as_ref().map(|p| p.display().to_string()),
        scene: scene.name.clone(),
        matrix: report.matrix,
        accuracy: scene.accuracy,
        modes: scene.fit.modes,
        form: study.case_form(),
    };
    Ok(out)
}
