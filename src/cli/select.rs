//! `prbfit select`: the topology ladder fitted, the published models judged, the simplest model
//! that meets the scene's targets chosen. On a mechanism scene (DESIGN §8) the ladder is
//! fitted on the mechanism and judged by its figures, the reaction error among the targets.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::beam::Resolution;
use prbfit::eval::ErrorFigures;
use prbfit::fit::mech::MechFitError;
use prbfit::fit::CancelToken;
use prbfit::mech::figures::MechFigures;
use prbfit::scene::{Accuracy, Mechanism, Scene};
use prbfit::select::{
    select, select_mechanism, EffectsDecision, Judged, Rung, Selection, Unfollowed,
};

use super::args::SelectArgs;
use super::output::{emit, num, safe, DecisionLine, Progress, TruthInfo, TruthLine};
use super::{load_scene, resolve_scene};

/// The figures' own columns in the text table.
trait Columns: Judged {
    /// The header of the figures' columns.
    fn header() -> String;
    /// The row's cells.
    fn cells(&self) -> String;
    /// The targets line.
    fn targets(accuracy: &Accuracy) -> String;
}

impl Columns for ErrorFigures {
    fn header() -> String {
        format!("{:>11} {:>10} {:>10}", "J", "max pos", "max ang")
    }
    fn cells(&self) -> String {
        format!(
            "{:>11.4e} {:>10.3e} {:>10.3e}",
            self.objective, self.max_pos_err, self.max_ang_err
        )
    }
    fn targets(a: &Accuracy) -> String {
        format!(
            "targets: max position error {} L, max angle error {} rad",
            num(a.max_pos_err),
            num(a.max_ang_err)
        )
    }
}

impl Columns for MechFigures {
    fn header() -> String {
        format!(
            "{:>11} {:>10} {:>10} {:>10}",
            "J", "max pos", "max ang", "max force"
        )
    }
    fn cells(&self) -> String {
        format!(
            "{:>11.4e} {:>10.3e} {:>10.3e} {:>10.3e}",
            self.objective, self.max_pos_err, self.max_ang_err, self.max_force_err
        )
    }
    fn targets(a: &Accuracy) -> String {
        format!(
            "targets: max stage position error {} L, max stage angle error {} rad, max reaction \
             error {} of the largest",
            num(a.max_pos_err),
            num(a.max_ang_err),
            num(a.max_force_err)
        )
    }
}

/// The table and the choice.
#[derive(Debug, Serialize)]
pub struct SelectOutput<F: Judged = ErrorFigures> {
    rows: Vec<Rung<F>>,
    chosen: Option<Rung<F>>,
    closest: Option<Rung<F>>,
    unfollowed: Vec<Unfollowed>,
    fidelity: prbfit::fidelity::Fidelity,
    scene: String,
    targets: Accuracy,
    effects_decision: Option<EffectsDecision>,
    /// A data scene's truth, and the beam's own error against it.
    #[serde(skip_serializing_if = "Option::is_none")]
    truth: Option<TruthInfo>,
    seconds: f64,
    #[serde(skip)]
    cases: usize,
    #[serde(skip)]
    chosen_index: Option<usize>,
    #[serde(skip)]
    what: &'static str,
}

impl<F: Judged> SelectOutput<F> {
    fn new(
        selection: Selection<F>,
        scene: &Scene,
        effects_decision: Option<EffectsDecision>,
        cases: usize,
        seconds: f64,
    ) -> SelectOutput<F> {
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
            truth: TruthInfo::of(scene),
            seconds,
            cases,
            what: if scene.mechanism.is_some() {
                "mechanism cases"
            } else {
                "load cases"
            },
        }
    }
}

impl<F: Columns> fmt::Display for SelectOutput<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {} ({} {}, {} fidelity)",
            safe(&self.scene),
            self.cases,
            self.what,
            self.fidelity
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        write!(f, "{}", TruthLine(&self.truth))?;
        writeln!(f, "{}", F::targets(&self.targets))?;
        writeln!(
            f,
            "{:<12} {:<11} {:>3} {} {:>11} {:>9}  targets",
            "model",
            "topology",
            "dof",
            F::header(),
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
                r.figures.cells(),
                r.eval_seconds_per_case * 1e6,
                r.fit_seconds * 1e3,
                if r.meets_targets { "met" } else { "not met" },
                mark
            )?;
        }
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

/// Runs `prbfit select`.
pub fn run(args: SelectArgs) -> Result<()> {
    let scene = load_scene(&args.common)?;
    let t0 = Instant::now();
    let (scene, decision) = resolve_scene(&scene)?;
    if let Some(mechanism) = &scene.mechanism {
        return run_mechanism(&args, &scene, mechanism, decision, t0);
    }
    let baseline = args.fidelity.baseline(&scene).context("baseline beam")?;
    let mut progress = Progress::new("selecting");
    let mut done = 0;
    let selection = select(
        &scene,
        &baseline,
        args.fidelity,
        &CancelToken::new(),
        &mut |row| {
            done += 1;
            progress.update(|| format!("{done} models judged, last {}", row.name));
        },
    )?;
    progress.finish();
    let out = SelectOutput::new(
        selection,
        &scene,
        decision,
        baseline.case_count(),
        t0.elapsed().as_secs_f64(),
    );
    emit(&out, args.common.json)
}

/// `prbfit select` on a mechanism scene: the exact mechanism is solved once (at the default
/// resolution, as `fit` does; a data scene's truth is its data), then the ladder is fitted on
/// it.
fn run_mechanism(
    args: &SelectArgs,
    scene: &Scene,
    mechanism: &Mechanism,
    decision: Option<EffectsDecision>,
    t0: Instant,
) -> Result<()> {
    let exact = super::mech::truth(scene, mechanism, Resolution::default())?;
    let mut progress = Progress::new("selecting");
    let mut done = 0;
    let selection = select_mechanism(
        scene,
        mechanism,
        &exact,
        args.fidelity,
        &CancelToken::new(),
        &mut |row| {
            done += 1;
            progress.update(|| format!("{done} models judged, last {}", row.name));
        },
    )
    .map_err(|e: MechFitError| anyhow::Error::new(e))?;
    progress.finish();
    let out = SelectOutput::new(
        selection,
        scene,
        decision,
        exact.iter().map(Vec::len).sum(),
        t0.elapsed().as_secs_f64(),
    );
    emit(&out, args.common.json)
}
