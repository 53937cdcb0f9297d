//! `prbfit select`: the topology ladder fitted, the published models judged, the simplest model
//! that meets the scene's targets chosen. On a mechanism scene (DESIGN §8) the ladder is
//! fitted on the mechanism and judged by its figures, the reaction error among the targets.

use std::fmt;
use std::time::Instant;

use serde::Serialize;

use crate::fidelity::Fidelity;
use crate::mech::figures::Figures;
use crate::scene::{Accuracy, Scene};
use crate::study::select::{Rung, Selection, Unfollowed};
use crate::study::{CaseForm, EffectsDecision, Sampling};

use super::{
    frequency_lines, num, safe, study, Control, DecisionLine, Progress, ReportError, Result,
    TruthInfo, TruthLine,
};

/// `select`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct SelectArgs {
    /// The fits' preset and the baseline's sampling.
    pub fidelity: Fidelity,
    /// Judge only the cases up to each path's stroke limit (`--within-stroke`, DESIGN §11).
    pub within_stroke: bool,
}

impl Default for SelectArgs {
    fn default() -> SelectArgs {
        SelectArgs {
            fidelity: Fidelity::Normal,
            within_stroke: false,
        }
    }
}

/// The figures' own columns in the text table: the header, a row's cells, the targets line;
/// a mechanism's have the reaction error beside the stage's position and angle errors.
fn header(form: CaseForm) -> String {
    match form {
        CaseForm::Tip => format!("{:>11} {:>10} {:>10}", "J", "max pos", "max ang"),
        CaseForm::Stage => format!(
            "{:>11} {:>10} {:>10} {:>10}",
            "J", "max pos", "max ang", "max force"
        ),
    }
}

fn cells(f: &Figures, form: CaseForm) -> String {
    match form {
        CaseForm::Tip => format!(
            "{:>11.4e} {:>10.3e} {:>10.3e}",
            f.objective, f.max_pos_err, f.max_ang_err
        ),
        CaseForm::Stage => format!(
            "{:>11.4e} {:>10.3e} {:>10.3e} {:>10.3e}",
            f.objective,
            f.max_pos_err,
            f.max_ang_err,
            f.max_force()
        ),
    }
}

fn targets(a: &Accuracy, form: CaseForm) -> String {
    match form {
        CaseForm::Tip => format!(
            "targets: max position error {} L, max angle error {} rad",
            num(a.max_pos_err),
            num(a.max_ang_err)
        ),
        CaseForm::Stage => format!(
            "targets: max stage position error {} L, max stage angle error {} rad, max reaction \
             error {} of the largest",
            num(a.max_pos_err),
            num(a.max_ang_err),
            num(a.max_force_err)
        ),
    }
}

/// The table and the choice.
#[derive(Debug, Serialize)]
pub struct SelectOutput {
    rows: Vec<Rung>,
    chosen: Option<Rung>,
    closest: Option<Rung>,
    unfollowed: Vec<Unfollowed>,
    fidelity: Fidelity,
    scene: String,
    targets: Accuracy,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth, and the beam's own error against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    /// With `--within-stroke`: each path's stroke limit (null: none within it), the cases
    /// judged being those up to it.
    #[serde(skip_serializing_if = "Option::is_none")]
    within_stroke: Option<Vec<Option<f64>>>,
    seconds: f64,
    #[serde(skip)]
    cases: usize,
    #[serde(skip)]
    chosen_index: Option<usize>,
    #[serde(skip)]
    form: CaseForm,
    /// The natural frequencies the scene judges (`[fit] modes`).
    #[serde(skip)]
    modes: u32,
}

impl SelectOutput {
    fn new(
        selection: Selection,
        scene: &Scene,
        form: CaseForm,
        effects_decision: Option<EffectsDecision>,
        (truth, cases, seconds): (Option<TruthInfo>, usize, f64),
    ) -> SelectOutput {
        let row = |i: Option<usize>| i.and_then(|i| selection.rows.get(i).cloned());
        SelectOutput {
            chosen: row(selection.chosen),
            closest: row(Some(selection.closest)),
            chosen_index: selection.chosen,
            rows: selection.rows,
            unfollowed: selection.unfollowed,
            fidelity: selection.fidelity,
            scene: scene.name.clone(),
            targets: scene.accuracy,
            effects_decision,
            truth,
            within_stroke: None,
            seconds,
            cases,
            form,
            modes: scene.fit.modes,
        }
    }
}

impl fmt::Display for SelectOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {} ({} {}, {} fidelity)",
            safe(&self.scene),
            self.cases,
            match self.form {
                CaseForm::Tip => "load cases",
                CaseForm::Stage => "mechanism cases",
            },
            self.fidelity
        )?;
        if let Some(limits) = &self.within_stroke {
            let parts: Vec<String> = limits
                .iter()
                .enumerate()
                .map(|(i, l)| match l {
                    Some(x) => format!("path {} to {x:.6}", i + 1),
                    None => format!("path {} whole", i + 1),
                })
                .collect();
            writeln!(f, "judged within the stroke limits: {}", parts.join(", "))?;
        }
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
        writeln!(f, "{}", targets(&self.targets, self.form))?;
        writeln!(
            f,
            "{:<12} {:<11} {:>3} {} {:>11} {:>9}  targets",
            "model",
            "topology",
            "dof",
            header(self.form),
            "us/case",
            "fit ms"
        )?;
        for (i, r) in self.rows.iter().enumerate() {
            let mark = if Some(i) == self.chosen_index {
                " <- chosen"
            } else {
                ""
            };
            writeln!(
                f,
                "{:<12} {:<11} {:>3} {} {:>11.3} {:>9.1}  {}{}",
                r.name,
                r.topology,
                r.dof,
                cells(&r.figures, self.form),
                r.eval_seconds_per_case * 1e6,
                r.fit_seconds * 1e3,
                if r.meets_targets { "met" } else { "not met" },
                mark
            )?;
        }
        frequency_lines(
            f,
            self.modes,
            self.targets.max_freq_err,
            self.rows.iter().map(|r| (r.name.as_str(), &r.figures)),
        )?;
        for u in &self.unfollowed {
            writeln!(
                f,
                "{:<12} cannot follow the scene: {}",
                u.name,
                safe(&u.reason)
            )?;
        }
        match (&self.chosen, &self.closest) {
            (Some(r), _) => writeln!(f, "chosen: {} ({}): {}", r.name, r.topology, r.prb)?,
            (None, Some(r)) => writeln!(
                f,
                "no model meets the targets; closest: {} ({}), its worst error is {:.2}x its target",
                r.name, r.topology, r.target_ratio
            )?,
            (None, None) => writeln!(f, "no model could be fitted")?,
        }
        writeln!(f, "{:.2} s in all", self.seconds)
    }
}

/// `prbfit select` on `scene`.
pub fn select(scene: &Scene, args: &SelectArgs, ctl: &mut Control<'_>) -> Result<SelectOutput> {
    let t0 = Instant::now();
    let study = study(scene, Sampling::Fidelity(args.fidelity), ctl)?;
    let (study, limits) = if args.within_stroke {
        let within = study
            .within_stroke(&ctl.cancel)
            .map_err(|e| ReportError::failed_in("the study within the stroke limits", &e))?;
        let (within, limits) = within.ok_or_else(|| {
            ReportError::input(format!(
                "--within-stroke: \"{}\" gives no allowable_stress ([beam] or a flexure's), \
                 so its paths have no stroke limit",
                safe(&scene.name)
            ))
        })?;
        (within, Some(limits.iter().map(|l| l.fraction).collect()))
    } else {
        (study, None)
    };
    // Rows and fits report through one sink, so they share the progress line.
    let progress = std::cell::RefCell::new(&mut *ctl.progress);
    let done = std::cell::Cell::new(0);
    let selection = study
        .select_with_progress(
            args.fidelity,
            &ctl.cancel,
            &mut |row| {
                done.set(done.get() + 1);
                (progress.borrow_mut())(&Progress::Select {
                    done: done.get(),
                    last: &row.name,
                });
            },
            &mut |topology, fit| {
                (progress.borrow_mut())(&Progress::SelectFit {
                    done: done.get(),
                    topology,
                    fit,
                });
            },
        )
        .map_err(|e| ReportError::failed(&e))?;
    let mut out = SelectOutput::new(
        selection,
        study.scene(),
        study.case_form(),
        study.decision().cloned(),
        (
            TruthInfo::of(&study),
            study.case_count(),
            t0.elapsed().as_secs_f64(),
        ),
    );
    out.within_stroke = limits;
    Ok(out)
}
