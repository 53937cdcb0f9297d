//! `prbfit select`: the topology ladder fitted, the published models judged, the simplest model
//! that meets the scene's targets chosen.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use prbfit::fit::CancelToken;
use prbfit::scene::Accuracy;
use prbfit::select::{select, EffectsDecision, Rung, Selection};

use super::args::SelectArgs;
use super::output::{emit, num, safe, DecisionLine, Progress};
use super::resolved_scene;

/// The table and the choice.
#[derive(Debug, Serialize)]
pub struct SelectOutput {
    rows: Vec<Rung>,
    chosen: Option<Rung>,
    closest: Option<Rung>,
    fidelity: prbfit::fidelity::Fidelity,
    scene: String,
    targets: Accuracy,
    effects_decision: Option<EffectsDecision>,
    seconds: f64,
    #[serde(skip)]
    cases: usize,
    #[serde(skip)]
    chosen_index: Option<usize>,
}

impl SelectOutput {
    fn new(
        selection: Selection,
        scene: String,
        targets: Accuracy,
        effects_decision: Option<EffectsDecision>,
        cases: usize,
        seconds: f64,
    ) -> SelectOutput {
        let row = |i: Option<usize>| i.and_then(|i| selection.rows.get(i).cloned());
        SelectOutput {
            chosen: row(selection.chosen),
            closest: row(Some(selection.closest)),
            chosen_index: selection.chosen,
            rows: selection.rows,
            fidelity: selection.fidelity,
            scene,
            targets,
            effects_decision,
            seconds,
            cases,
        }
    }
}

impl fmt::Display for SelectOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {} ({} load cases, {} fidelity)",
            safe(&self.scene),
            self.cases,
            self.fidelity
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        writeln!(
            f,
            "targets: max position error {} L, max angle error {} rad",
            num(self.targets.max_pos_err),
            num(self.targets.max_ang_err)
        )?;
        writeln!(
            f,
            "{:<12} {:<11} {:>3} {:>11} {:>10} {:>10} {:>11} {:>9}  targets",
            "model", "topology", "dof", "J", "max pos", "max ang", "us/case", "fit ms"
        )?;
        for (i, r) in self.rows.iter().enumerate() {
            let mark = if Some(i) == self.chosen_index {
                " <- chosen"
            } else {
                ""
            };
            writeln!(
                f,
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
    let (scene, decision) = resolved_scene(&args.common, "select")?;
    let t0 = Instant::now();
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
        scene.name,
        scene.accuracy,
        decision,
        baseline.case_count(),
        t0.elapsed().as_secs_f64(),
    );
    emit(&out, args.common.json)
}
