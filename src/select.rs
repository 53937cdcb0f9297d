//! Modelling only what a scene requires (the paper's "simple procedure that leads the user to
//! the most effective PRB model for each situation", made automatic and measured):
//!
//! - [`decide_effects`]: which of shear, extension and Poisson change the beam's tip by more
//!   than [`AUTO_FRACTION`] of the scene's accuracy targets; only those are kept. Plane
//!   strain (the wide section's limit) is judged the same way once [`plate_criterion`] has
//!   said the section is nearer the plate than the narrow beam.
//! - [`select`]: fits a ladder of topologies in order of complexity, judges the published
//!   models as they are, and picks the simplest model that meets the targets.

use std::time::Instant;

use serde::Serialize;

use crate::beam::plate::{case_fraction, ends_fraction};
use crate::beam::{BeamSolution, Effects, Resolution};
use crate::eval::{evaluate, Baseline, BaselineError, ErrorFigures};
use crate::fit::mech::{fit_mechanism, MechFitError, MECH_TOL};
use crate::fit::{fit, CancelToken, Fidelity, FitError, FitOptions};
use crate::mech::figures::{compare, CompareError, MechFigures};
use crate::mech::{exact, prb, MechCase, MechError};
use crate::prb::published;
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, BeamSpec, EffectsChoice, LoadPath, Mechanism, Scene};

/// An effect is kept when dropping it moves the tip by more than this fraction of the
/// scene's accuracy target (position or angle, whichever is nearer its target).
pub const AUTO_FRACTION: f64 = 0.1;

/// What dropping one effect does to the tip.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectImpact {
    /// The effect dropped: `shear`, `extension` (which drops Poisson too), `poisson`, or
    /// `plane_strain` (the plate stiffening of the section's width).
    pub effect: &'static str,
    /// Largest tip position change over the scene's cases, units of L.
    pub pos_change: f64,
    /// Largest tip angle change, radians.
    pub ang_change: f64,
    /// Mechanism scenes: the largest change of a prescribed coordinate's reaction, as a
    /// fraction of its largest reaction (DESIGN §8's `e_force`); none on a cantilever.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_change: Option<f64>,
    /// The largest of the changes as a fraction of its target.
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
    /// What dropping each effect alone does, in the order shear, extension, poisson,
    /// plane_strain.
    pub impacts: Vec<EffectImpact>,
    /// Where the section lies between the narrow beam and the plate (the plate fraction the
    /// plane-strain effect uses, case by case); `None` on mechanism scenes, whose flexures
    /// take their ends' fraction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plate: Option<PlateCriterion>,
    /// The tip change of dropping every dropped effect together (checked, not assumed), as a
    /// fraction of the target.
    pub dropped_together_fraction: f64,
    /// The fraction of the target above which an effect is kept ([`AUTO_FRACTION`]).
    pub threshold: f64,
}

/// Where a scene's section lies between the narrow beam (plane stress) and the plate (plane
/// strain), by the criterion of [`crate::beam::plate`]: per load case the plate fraction
/// combines the ends' ([`ends_fraction`]) and the anticlastic one (Searle's parameter
/// `b^2 / (R t)` at each point of the beam, Ashwell's solution, averaged along the beam with
/// the weight `M(s)^2` of the bending compliance; [`case_fraction`]); the scene's is their
/// mean over the cases, and the section is *wide* when that is at least 1/2. The plane-strain
/// effect stiffens each case by its own fraction, `E / (1 - nu^2 phi)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateCriterion {
    /// `w0 / t0`.
    pub width_over_thickness: f64,
    /// `w0 / L`.
    pub width_over_length: f64,
    /// The ends' plate fraction.
    pub ends_fraction: f64,
    /// Searle's parameter `w0^2 / (R t0)` at the scene's largest curvature.
    pub largest_searle: f64,
    /// The mean plate fraction over the cases (0: beam, 1: plate).
    pub plate_fraction: f64,
    /// `plate_fraction >= 1/2`.
    pub wide: bool,
}

/// The plate criterion of `beam` under the cases `solutions` (solved as a narrow beam).
pub fn plate_criterion(beam: &BeamSpec, solutions: &[BeamSolution]) -> PlateCriterion {
    let (w_t, w_l) = (beam.width / beam.thickness, beam.width / beam.length);
    let ends = ends_fraction(w_l, w_t);
    let mut largest_searle = 0.0_f64;
    let mut sum = 0.0;
    for s in solutions {
        let (fraction, searle) = case_fraction(w_t, beam.slenderness(), beam.poisson_ratio, s);
        largest_searle = largest_searle.max(searle);
        sum += fraction;
    }
    let plate_fraction = if solutions.is_empty() {
        ends
    } else {
        sum / solutions.len() as f64
    };
    PlateCriterion {
        width_over_thickness: w_t,
        width_over_length: w_l,
        ends_fraction: ends,
        largest_searle,
        plate_fraction,
        wide: plate_fraction >= 0.5,
    }
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
    let solve = |solved: &mut Vec<(Effects, Vec<BeamSolution>)>,
                 e: Effects|
     -> Result<usize, BaselineError> {
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
    // The plate criterion on the narrow beam with every refinement.
    let narrow = solve(&mut solved, Effects::ALL)?;
    let plate = plate_criterion(beam, &solved[narrow].1);
    let full = Effects::ALL.with_plane_strain(true);
    let mut decision = decide(
        accuracy,
        full,
        |effects: Effects| -> Result<Change, BaselineError> {
            let reference = solve(&mut solved, full)?;
            let this = solve(&mut solved, effects)?;
            let (pos, ang) = tip_change(&solved[reference].1, &solved[this].1);
            Ok(Change {
                pos,
                ang,
                force: None,
            })
        },
    )?;
    decision.plate = Some(plate);
    Ok(decision)
}

/// What dropping effects changes: the largest position (units of L) and angle changes, and
/// on a mechanism the largest reaction change (a fraction of each coordinate's largest).
struct Change {
    pos: f64,
    ang: f64,
    force: Option<f64>,
}

impl Change {
    /// The largest change as a fraction of its target.
    fn fraction(&self, accuracy: &Accuracy) -> f64 {
        let force = self.force.map_or(0.0, |f| f / accuracy.max_force_err);
        fraction((self.pos, self.ang), accuracy).max(force)
    }
}

/// The decision procedure of [`decide_effects`], for any truth: `moves(e)` is what modelling
/// with the effects `e` instead of `full` changes. `full` has every refinement on, plane
/// strain (the plate stiffening of the section's width) included.
fn decide<E>(
    accuracy: &Accuracy,
    full: Effects,
    mut moves: impl FnMut(Effects) -> Result<Change, E>,
) -> Result<EffectsDecision, E> {
    let mut impacts = Vec::new();
    for effect in ["shear", "extension", "poisson", "plane_strain"] {
        let mut e = full;
        match effect {
            "shear" => e.shear = false,
            "extension" => {
                e.extension = false;
                e.poisson = false;
            }
            "poisson" => e.poisson = false,
            _ => e.plane_strain = false,
        }
        let moved = moves(e)?;
        let frac = moved.fraction(accuracy);
        impacts.push(EffectImpact {
            effect,
            pos_change: moved.pos,
            ang_change: moved.ang,
            force_change: moved.force,
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
            plane_strain: impacts[3].kept,
        };
        let together = moves(effects)?.fraction(accuracy);
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
                    plate: None,
                    dropped_together_fraction: together,
                    threshold: AUTO_FRACTION,
                })
            }
        }
    }
}

/// Decides the effects of a mechanism's flexures from the mechanism itself: as
/// [`decide_effects`], with the exact mechanism (DESIGN §8) as the truth, every flexure whose
/// effects are `auto` modelled alike, and the change judged where the designer looks: the
/// stage's motion in its loaded coordinates and the reactions of its prescribed ones.
pub fn decide_mechanism_effects(
    mechanism: &Mechanism,
    accuracy: &Accuracy,
    resolution: Resolution,
) -> Result<EffectsDecision, EffectsError> {
    let with = |e: Effects| {
        let mut m = mechanism.clone();
        for f in &mut m.flexures {
            if f.beam.effects == EffectsChoice::Auto {
                f.beam.effects = EffectsChoice::Fixed(e);
            }
        }
        m
    };
    let mut solved: Vec<(Effects, Vec<Vec<MechCase>>)> = Vec::new();
    // A flexure's plate stiffening in a mechanism is its ends' (`BeamModel::with_width_ratio`):
    // the anticlastic part is load dependent, and the mechanism solver does not follow each
    // flexure's own load path case by case.
    let full = Effects::ALL.with_plane_strain(true);
    decide(
        accuracy,
        full,
        |effects: Effects| -> Result<Change, EffectsError> {
            let mut solve = |e: Effects| -> Result<usize, EffectsError> {
                if let Some(i) = solved.iter().position(|(k, _)| *k == e) {
                    return Ok(i);
                }
                let cases = exact::solve(&with(e), resolution)
                    .map_err(|source| EffectsError::Mechanism { effects: e, source })?;
                solved.push((e, cases));
                Ok(solved.len() - 1)
            };
            let all = solve(full)?;
            let this = solve(effects)?;
            let change =
                compare(&mechanism.drives, &solved[this].1, &solved[all].1, 1.0, 1.0)?.figures;
            let prescribed = mechanism
                .drives
                .iter()
                .any(|d| d.coordinates.iter().any(|c| c.is_prescribed()));
            Ok(Change {
                pos: change.max_pos_err,
                ang: change.max_ang_err,
                force: prescribed.then_some(change.max_force_err),
            })
        },
    )
}

/// Why the effects could not be decided.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EffectsError {
    /// The single beam could not be solved.
    #[error(transparent)]
    Baseline(#[from] BaselineError),
    /// The exact mechanism could not be solved with some set of effects.
    #[error("the exact mechanism with effects [{effects}]: {source}")]
    Mechanism {
        /// The effects it was solved with.
        effects: Effects,
        /// Why it failed.
        source: MechError,
    },
    /// Two solutions of the mechanism did not pair up (a bug if ever seen).
    #[error(transparent)]
    Compare(#[from] CompareError),
}

/// The scene with `effects = "auto"` replaced by the decided effects (and the decision), or
/// the scene as it is. On a mechanism scene the decision is made on the mechanism
/// ([`decide_mechanism_effects`]) for every flexure whose effects are `auto`.
pub fn resolve_effects(
    scene: &Scene,
    resolution: Resolution,
) -> Result<(Scene, Option<EffectsDecision>), EffectsError> {
    if let Some(mechanism) = &scene.mechanism {
        let auto = |b: &BeamSpec| b.effects == EffectsChoice::Auto;
        if !mechanism.flexures.iter().any(|f| auto(&f.beam)) {
            return Ok((scene.clone(), None));
        }
        let decision = decide_mechanism_effects(mechanism, &scene.accuracy, resolution)?;
        let mut resolved = scene.clone();
        let fixed = EffectsChoice::Fixed(decision.effects);
        if let Some(m) = resolved.mechanism.as_mut() {
            for f in m.flexures.iter_mut().filter(|f| auto(&f.beam)) {
                f.beam.effects = fixed;
            }
        }
        if auto(&resolved.beam) {
            resolved.beam.effects = fixed;
        }
        return Ok((resolved, Some(decision)));
    }
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

/// Error figures that a selection judges against a scene's targets: the cantilever's
/// ([`ErrorFigures`], DESIGN §4) or a mechanism's ([`MechFigures`], §8).
pub trait Judged: Clone + Serialize {
    /// `J`.
    fn objective(&self) -> f64;
    /// Whether every figure is within its target.
    fn meets(&self, accuracy: &Accuracy) -> bool;
    /// The worst ratio of a figure to its target (1 = on target).
    fn target_ratio(&self, accuracy: &Accuracy) -> f64;
}

impl Judged for ErrorFigures {
    fn objective(&self) -> f64 {
        self.objective
    }
    fn meets(&self, accuracy: &Accuracy) -> bool {
        ErrorFigures::meets(self, accuracy)
    }
    fn target_ratio(&self, accuracy: &Accuracy) -> f64 {
        (self.max_pos_err / accuracy.max_pos_err).max(self.max_ang_err / accuracy.max_ang_err)
    }
}

impl Judged for MechFigures {
    fn objective(&self) -> f64 {
        self.objective
    }
    fn meets(&self, accuracy: &Accuracy) -> bool {
        MechFigures::meets(self, accuracy)
    }
    fn target_ratio(&self, accuracy: &Accuracy) -> f64 {
        (self.max_pos_err / accuracy.max_pos_err)
            .max(self.max_ang_err / accuracy.max_ang_err)
            .max(self.max_force_err / accuracy.max_force_err)
    }
}

/// One row of the selection table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rung<F = ErrorFigures> {
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
    /// The error figures of the matrix on the selection's truth (DESIGN §4, §8).
    pub figures: F,
    /// Whether every error figure is within the scene's target.
    pub meets_targets: bool,
    /// Worst ratio of an error figure to its target (1 = on target).
    pub target_ratio: f64,
    /// Time to solve the PRB model for one load case (one mechanism case), seconds.
    pub eval_seconds_per_case: f64,
    /// Fit time (0 for a published model), seconds.
    pub fit_seconds: f64,
}

fn as_text<S: serde::Serializer>(m: &PrbMatrix, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&m.to_text())
}

/// A model that could not be judged: its PRB model cannot follow the scene (a 1R asked to
/// keep its tip angle, a fit that found nothing that follows).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unfollowed {
    /// The topology, or the published model's name.
    pub name: String,
    /// Why, in a sentence.
    pub reason: String,
}

/// The table and the choice.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Selection<F = ErrorFigures> {
    /// Every row judged, simplest first: joint freedoms, then fitted before published, then
    /// `J`.
    pub rows: Vec<Rung<F>>,
    /// Index of the simplest row that meets the targets.
    pub chosen: Option<usize>,
    /// Index of the row nearest the targets (by `target_ratio`).
    pub closest: usize,
    /// The fit preset the ladder was fitted at.
    pub fidelity: Fidelity,
    /// The models tried that cannot follow the scene, in the order tried.
    pub unfollowed: Vec<Unfollowed>,
}

/// A mechanism scene's selection (DESIGN §8's figures, `max_force_err` among the targets).
pub type MechSelection = Selection<MechFigures>;

/// A row of a mechanism scene's selection.
pub type MechRung = Rung<MechFigures>;

impl<F: Judged> Rung<F> {
    fn new(
        name: String,
        m: PrbMatrix,
        published: bool,
        figures: F,
        accuracy: &Accuracy,
        costs: (f64, f64),
    ) -> Rung<F> {
        Rung {
            name,
            topology: m.topology(),
            published,
            dof: joint_dof(&m),
            meets_targets: figures.meets(accuracy),
            target_ratio: figures.target_ratio(accuracy),
            figures,
            eval_seconds_per_case: costs.0,
            fit_seconds: costs.1,
            prb: m,
        }
    }
}

impl<F: Judged> Selection<F> {
    /// Ranks the rows (simplest first: joint freedoms, then fitted before published, then
    /// `J`) and picks the simplest that meets the targets.
    fn ranked(mut rows: Vec<Rung<F>>, unfollowed: Vec<Unfollowed>, fidelity: Fidelity) -> Self {
        rows.sort_by(|a, b| {
            (a.dof, a.published)
                .cmp(&(b.dof, b.published))
                .then(a.figures.objective().total_cmp(&b.figures.objective()))
        });
        let chosen = rows.iter().position(|r| r.meets_targets);
        let closest = rows
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.target_ratio.total_cmp(&b.1.target_ratio))
            .map(|(i, _)| i)
            .unwrap_or(0);
        Selection {
            rows,
            chosen,
            closest,
            fidelity,
            unfollowed,
        }
    }
}

/// The cost of one PRB load case: judging the matrix on the baseline, repeated until 5 ms
/// have passed, divided by the cases.
pub fn eval_cost(m: &PrbMatrix, baseline: &Baseline, weight: f64) -> f64 {
    per_case(baseline.case_count(), || {
        let _ = evaluate(m, baseline, weight);
    })
}

/// Seconds per case of `run`, which does `cases` cases: repeated until 5 ms have passed.
fn per_case(cases: usize, mut run: impl FnMut()) -> f64 {
    let t0 = Instant::now();
    let mut n = 0u32;
    while n < 3 || t0.elapsed().as_secs_f64() < 0.005 {
        run();
        n += 1;
    }
    t0.elapsed().as_secs_f64() / n as f64 / cases.max(1) as f64
}

/// The start of a ladder rung.
fn ladder_start(topology: &str) -> PrbMatrix {
    // `ladder` lists only fixed names made of `L`, `R` and `RP` segments, which
    // `from_topology` always accepts (`ladder_topologies_are_valid` checks every one).
    #[allow(clippy::expect_used)]
    PrbMatrix::from_topology(topology).expect("ladder topologies are valid")
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
    let mut rows = Vec::new();
    let mut unfollowed = Vec::new();
    for topology in ladder(baseline.model.effects) {
        if cancel.is_cancelled() {
            break;
        }
        let options = FitOptions {
            fidelity,
            angle_weight: weight,
            seed: 1,
        };
        let t0 = Instant::now();
        let report = fit(
            baseline,
            &ladder_start(topology),
            &options,
            &mut |_| {},
            cancel,
        )?;
        let fit_seconds = t0.elapsed().as_secs_f64();
        let cost = eval_cost(&report.matrix, baseline, weight);
        let row = Rung::new(
            topology.to_string(),
            report.matrix,
            false,
            report.figures,
            &accuracy,
            (cost, fit_seconds),
        );
        on_row(&row);
        rows.push(row);
    }
    for model in published::all() {
        match evaluate(&model.prb, baseline, weight) {
            Ok(e) => {
                let cost = eval_cost(&model.prb, baseline, weight);
                let row = Rung::new(
                    model.name,
                    model.prb,
                    true,
                    e.figures,
                    &accuracy,
                    (cost, 0.0),
                );
                on_row(&row);
                rows.push(row);
            }
            Err(e) => unfollowed.push(Unfollowed {
                name: model.name,
                reason: e.to_string(),
            }),
        }
    }
    Ok(Selection::ranked(rows, unfollowed, fidelity))
}

/// The topologies of a mechanism's ladder: [`ladder`] of the effects of all its flexures
/// together (extension in any flexure brings the extension-spring variants).
fn mechanism_ladder(mechanism: &Mechanism) -> Vec<&'static str> {
    let effects = mechanism
        .flexures
        .iter()
        .map(|f| f.beam.effects.resolve())
        .fold(Effects::NONE, |a, e| Effects {
            shear: a.shear || e.shear,
            extension: a.extension || e.extension,
            poisson: a.poisson || e.poisson,
            plane_strain: a.plane_strain || e.plane_strain,
        });
    ladder(effects)
}

/// [`select`] on a mechanism scene (DESIGN §8): the ladder fitted on the mechanism (one
/// matrix for every flexure, [`fit_mechanism`]) and the published models judged on it,
/// against `exact` (the exact mechanism's cases, one path per drive) and the scene's targets,
/// `max_force_err` among them. A topology or published model whose PRB mechanism cannot
/// follow the drives is listed in [`Selection::unfollowed`]. Cancelled, it returns what it
/// has.
pub fn select_mechanism(
    scene: &Scene,
    mechanism: &Mechanism,
    exact: &[Vec<MechCase>],
    fidelity: Fidelity,
    cancel: &CancelToken,
    on_row: &mut dyn FnMut(&MechRung),
) -> Result<MechSelection, MechFitError> {
    let accuracy = scene.accuracy;
    let (weight, force_weight) = (scene.fit.angle_weight, scene.fit.force_weight);
    let cases: usize = exact.iter().map(Vec::len).sum();
    let cost = |m: &PrbMatrix| {
        per_case(cases, || {
            let _ = prb::solve(mechanism, m, MECH_TOL);
        })
    };
    let mut rows = Vec::new();
    let mut unfollowed = Vec::new();
    for topology in mechanism_ladder(mechanism) {
        if cancel.is_cancelled() {
            break;
        }
        let options = FitOptions {
            fidelity,
            angle_weight: weight,
            seed: 1,
        };
        let t0 = Instant::now();
        let fitted = fit_mechanism(
            mechanism,
            exact,
            &ladder_start(topology),
            &options,
            force_weight,
            &accuracy,
            &mut |_| {},
            cancel,
        );
        let report = match fitted {
            Ok(report) => report,
            Err(MechFitError::NoFeasibleModel(e)) => {
                unfollowed.push(Unfollowed {
                    name: topology.to_string(),
                    reason: format!("no fitted {topology} follows the mechanism: {e}"),
                });
                continue;
            }
            Err(e) => return Err(e),
        };
        let fit_seconds = t0.elapsed().as_secs_f64();
        let row = Rung::new(
            topology.to_string(),
            report.matrix.clone(),
            false,
            report.figures,
            &accuracy,
            (cost(&report.matrix), fit_seconds),
        );
        on_row(&row);
        rows.push(row);
    }
    for model in published::all() {
        let judged = prb::solve(mechanism, &model.prb, MECH_TOL)
            .map_err(|e| e.to_string())
            .and_then(|cases| {
                compare(&mechanism.drives, &cases, exact, weight, force_weight)
                    .map_err(|e| e.to_string())
            });
        match judged {
            Ok(e) => {
                let c = cost(&model.prb);
                let row = Rung::new(model.name, model.prb, true, e.figures, &accuracy, (c, 0.0));
                on_row(&row);
                rows.push(row);
            }
            Err(reason) => unfollowed.push(Unfollowed {
                name: model.name,
                reason,
            }),
        }
    }
    Ok(Selection::ranked(rows, unfollowed, fidelity))
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
