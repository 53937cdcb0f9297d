//! Modelling only what a scene requires (the paper's "simple procedure that leads the user to
//! the most effective PRB model for each situation", made automatic and measured):
//!
//! - [`decide_effects`]: which of shear, extension and Poisson change the beam's tip by more
//!   than [`AUTO_FRACTION`] of the scene's accuracy targets; only those are kept.
//! - [`select`]: fits a ladder of topologies in order of complexity, judges the published
//!   models as they are, and picks the simplest model that meets the targets.

use std::time::Instant;

use serde::Serialize;

use crate::beam::{BeamSolution, Effects, Resolution};
use crate::eval::{evaluate, Baseline, BaselineError, ErrorFigures};
use crate::fit::{fit, CancelToken, Fidelity, FitError, FitOptions};
use crate::prb::published;
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, BeamSpec, EffectsChoice, LoadPath, Scene};

/// An effect is kept when dropping it moves the tip by more than this fraction of the
/// scene's accuracy target (position or angle, whichever is nearer its target).
pub const AUTO_FRACTION: f64 = 0.1;

/// What dropping one effect does to the tip.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectImpact {
    /// The effect dropped: `shear`, `extension` (which drops Poisson too) or `poisson`.
    pub effect: &'static str,
    /// Largest tip position change over the scene's cases, units of L.
    pub pos_change: f64,
    /// Largest tip angle change, radians.
    pub ang_change: f64,
    /// The larger of the two changes as a fraction of its target.
    pub fraction_of_target: f64,
    /// Whether the effect stays in the model: its fraction exceeds [`AUTO_FRACTION`], or it
    /// was taken back so the dropped effects together stay under it (extension is also kept
    /// whenever Poisson is).
    pub kept: bool,
}

/// The effects chosen for a scene, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectsDecision {
    /// The effects the scene's beam is modelled with.
    pub effects: Effects,
    /// What dropping each effect alone does, in the order shear, extension, poisson.
    pub impacts: Vec<EffectImpact>,
    /// The tip change of dropping every dropped effect together (checked, not assumed), as a
    /// fraction of the target.
    pub dropped_together_fraction: f64,
    /// The fraction of the target above which an effect is kept ([`AUTO_FRACTION`]).
    pub threshold: f64,
}

/// Largest tip change between two solves of the same cases, as (position, angle).
fn tip_change(a: &[BeamSolution], b: &[BeamSolution]) -> (f64, f64) {
    a.iter().zip(b).fold((0.0_f64, 0.0_f64), |(p, q), (x, y)| {
        (
            p.max((x.tip.a - y.tip.a).hypot(x.tip.b - y.tip.b)),
            q.max((x.tip.phi - y.tip.phi).abs()),
        )
    })
}

fn fraction(change: (f64, f64), accuracy: &Accuracy) -> f64 {
    (change.0 / accuracy.max_pos_err).max(change.1 / accuracy.max_ang_err)
}

/// Decides the effects for a beam under the given loads and targets.
///
/// Every effect is judged against the full model (all on): drop it (dropping extension drops
/// Poisson too), solve every case, and keep the effect if the tip moves by more than
/// [`AUTO_FRACTION`] of the target. Then all dropped effects are dropped together and checked
/// once more; should the combination exceed the fraction, the most influential dropped
/// effect is taken back until it does not.
pub fn decide_effects(
    beam: &BeamSpec,
    loads: &[LoadPath],
    accuracy: &Accuracy,
    resolution: Resolution,
) -> Result<EffectsDecision, BaselineError> {
    decide_effects_cancellable(beam, loads, accuracy, resolution, &CancelToken::new())
}

/// As [`decide_effects`], stopping soon after `cancel` is set (the UI's worker cancels it
/// when a newer edit arrives).
pub fn decide_effects_cancellable(
    beam: &BeamSpec,
    loads: &[LoadPath],
    accuracy: &Accuracy,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<EffectsDecision, BaselineError> {
    // Each set of effects is solved once, however often the procedure asks for it.
    let mut solved: Vec<(Effects, Vec<BeamSolution>)> = Vec::new();
    let mut tip_moves = |effects: Effects| -> Result<(f64, f64), BaselineError> {
        // The index of `e`'s solutions in `solved`, solving them the first time.
        let mut solve = |e: Effects| -> Result<usize, BaselineError> {
            if let Some(i) = solved.iter().position(|(k, _)| *k == e) {
                return Ok(i);
            }
            let mut b = *beam;
            b.effects = EffectsChoice::Fixed(e);
            solved.push((
                e,
                Baseline::solve(b.model(), loads, resolution, cancel, &mut |_, _| {})?.solutions,
            ));
            Ok(solved.len() - 1)
        };
        let all = solve(Effects::ALL)?;
        let this = solve(effects)?;
        Ok(tip_change(&solved[all].1, &solved[this].1))
    };
    let mut impacts = Vec::new();
    for effect in ["shear", "extension", "poisson"] {
        let mut e = Effects::ALL;
        match effect {
            "shear" => e.shear = false,
            "extension" => {
                e.extension = false;
                e.poisson = false;
            }
            _ => e.poisson = false,
        }
        let moved = tip_moves(e)?;
        let frac = fraction(moved, accuracy);
        impacts.push(EffectImpact {
            effect,
            pos_change: moved.0,
            ang_change: moved.1,
            fraction_of_target: frac,
            kept: frac > AUTO_FRACTION,
        });
    }
    // Poisson acts through extension: keeping Poisson keeps extension.
    if impacts[2].kept {
        impacts[1].kept = true;
    }
    loop {
        let effects = Effects {
            shear: impacts[0].kept,
            extension: impacts[1].kept,
            poisson: impacts[2].kept,
        };
        let together = fraction(tip_moves(effects)?, accuracy);
        // The dropped effect that matters most; none when every effect is kept.
        let most_influential_dropped = impacts
            .iter()
            .enumerate()
            .filter(|(_, i)| !i.kept)
            .max_by(|a, b| a.1.fraction_of_target.total_cmp(&b.1.fraction_of_target))
            .map(|(k, _)| k);
        match most_influential_dropped {
            // Take it back and check the rest together again.
            Some(back) if together > AUTO_FRACTION => {
                impacts[back].kept = true;
                if back == 2 {
                    impacts[1].kept = true;
                }
            }
            // The dropped effects together are below the threshold, or nothing is dropped.
            _ => {
                return Ok(EffectsDecision {
                    effects,
                    impacts,
                    dropped_together_fraction: together,
                    threshold: AUTO_FRACTION,
                })
            }
        }
    }
}

/// The scene with `effects = "auto"` replaced by the decided effects (and the decision), or
/// the scene as it is.
pub fn resolve_effects(
    scene: &Scene,
    resolution: Resolution,
) -> Result<(Scene, Option<EffectsDecision>), BaselineError> {
    if scene.beam.effects != EffectsChoice::Auto {
        return Ok((scene.clone(), None));
    }
    let decision = decide_effects(&scene.beam, &scene.loads, &scene.accuracy, resolution)?;
    let mut resolved = scene.clone();
    resolved.beam.effects = EffectsChoice::Fixed(decision.effects);
    Ok((resolved, Some(decision)))
}

/// The topologies tried, simplest first: revolute chains, and with extension in the scene's
/// effects, their extension-spring variants.
pub fn ladder(effects: Effects) -> Vec<&'static str> {
    let mut out = vec!["L-R", "L-R-R", "L-R-R-R", "L-R-R-R-R"];
    if effects.extension {
        out.extend(["L-RP", "L-R-RP", "L-RP-RP-RP"]);
    }
    out
}

/// Joint degrees of freedom of a matrix: one per revolute and per prismatic joint.
pub fn joint_dof(m: &PrbMatrix) -> usize {
    m.revolute_count() + m.prismatic_count()
}

/// One row of the selection table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rung {
    /// The topology, or the published model's name.
    pub name: String,
    /// The topology name of the matrix (`L-R-R-R`).
    pub topology: String,
    /// A published model judged as it is, rather than a fitted topology.
    pub published: bool,
    /// The PRB matrix judged (fitted or published); serialised in its text form.
    #[serde(serialize_with = "as_text")]
    pub prb: PrbMatrix,
    /// Joint degrees of freedom: revolute plus prismatic joints ([`joint_dof`]).
    pub dof: usize,
    /// The error figures of the matrix on the selection's baseline (DESIGN §4).
    pub figures: ErrorFigures,
    /// Whether the largest position and angle errors are within the scene's targets.
    pub meets_targets: bool,
    /// Worst ratio of an error figure to its target (1 = on target).
    pub target_ratio: f64,
    /// Time to solve the PRB model for one load case, seconds.
    pub eval_seconds_per_case: f64,
    /// Fit time (0 for a published model), seconds.
    pub fit_seconds: f64,
}

fn as_text<S: serde::Serializer>(m: &PrbMatrix, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&m.to_text())
}

/// The table and the choice.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Selection {
    /// Every row judged, simplest first: joint freedoms, then fitted before published, then
    /// `J`.
    pub rows: Vec<Rung>,
    /// Index of the simplest row that meets the targets.
    pub chosen: Option<usize>,
    /// Index of the row nearest the targets (by `target_ratio`).
    pub closest: usize,
    /// The fit preset the ladder was fitted at.
    pub fidelity: Fidelity,
}

/// The cost of one PRB load case: judging the matrix on the baseline, repeated until 5 ms
/// have passed, divided by the cases.
pub fn eval_cost(m: &PrbMatrix, baseline: &Baseline, weight: f64) -> f64 {
    let t0 = Instant::now();
    let mut n = 0u32;
    while n < 3 || t0.elapsed().as_secs_f64() < 0.005 {
        let _ = evaluate(m, baseline, weight);
        n += 1;
    }
    t0.elapsed().as_secs_f64() / n as f64 / baseline.case_count().max(1) as f64
}

/// Fits the ladder and judges the published models on `baseline`; `on_row` sees each row as
/// it is done. Cancelled, it returns what it has.
pub fn select(
    scene: &Scene,
    baseline: &Baseline,
    fidelity: Fidelity,
    cancel: &CancelToken,
    on_row: &mut dyn FnMut(&Rung),
) -> Result<Selection, FitError> {
    let accuracy = scene.accuracy;
    let weight = scene.fit.angle_weight;
    let rung = |name: String, m: PrbMatrix, published: bool, figures: ErrorFigures, fit_seconds| {
        let ratio = (figures.max_pos_err / accuracy.max_pos_err)
            .max(figures.max_ang_err / accuracy.max_ang_err);
        Rung {
            name,
            topology: m.topology(),
            published,
            dof: joint_dof(&m),
            figures,
            meets_targets: figures.meets(&accuracy),
            target_ratio: ratio,
            eval_seconds_per_case: eval_cost(&m, baseline, weight),
            fit_seconds,
            prb: m,
        }
    };
    let mut rows = Vec::new();
    for topology in ladder(baseline.model.effects) {
        if cancel.is_cancelled() {
            break;
        }
        // `ladder` lists only fixed names made of `L`, `R` and `RP` segments, which
        // `from_topology` always accepts (`ladder_topologies_are_valid` checks every one).
        #[allow(clippy::expect_used)]
        let start = PrbMatrix::from_topology(topology).expect("ladder topologies are valid");
        let options = FitOptions {
            fidelity,
            angle_weight: weight,
            seed: 1,
        };
        let t0 = Instant::now();
        let report = fit(baseline, &start, &options, &mut |_| {}, cancel)?;
        let row = rung(
            topology.to_string(),
            report.matrix,
            false,
            report.figures,
            t0.elapsed().as_secs_f64(),
        );
        on_row(&row);
        rows.push(row);
    }
    for model in published::all() {
        if let Ok(e) = evaluate(&model.prb, baseline, weight) {
            let row = rung(model.name.clone(), model.prb, true, e.figures, 0.0);
            on_row(&row);
            rows.push(row);
        }
    }
    // Simplest first: joint freedoms, then fitted before published, then J.
    rows.sort_by(|a, b| {
        (a.dof, a.published)
            .cmp(&(b.dof, b.published))
            .then(a.figures.objective.total_cmp(&b.figures.objective))
    });
    let chosen = rows.iter().position(|r| r.meets_targets);
    let closest = rows
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.target_ratio.total_cmp(&b.1.target_ratio))
        .map(|(i, _)| i)
        .unwrap_or(0);
    Ok(Selection {
        rows,
        chosen,
        closest,
        fidelity,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladder_topologies_are_valid() {
        for topology in ladder(Effects::ALL) {
            assert!(
                PrbMatrix::from_topology(topology).is_ok(),
                "{topology} does not parse"
            );
        }
    }
}
