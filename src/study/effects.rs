//! Modelling only what a scene requires (the paper's "simple procedure that leads the user to
//! the most effective PRB model for each situation", made automatic and measured):
//! [`decide_effects`] keeps those of shear, extension, Poisson and plane strain that change
//! the truth by more than [`AUTO_FRACTION`] of the scene's accuracy targets, on every kind of
//! scene: a cantilever's tip (plane strain judged once [`plate_criterion`] has said how near
//! the plate the section is), a mechanism's stage motion and reactions.

use std::rc::Rc;

use serde::Serialize;

use crate::beam::plate::{case_fraction, ends_fraction};
use crate::beam::{BeamSolution, Effects, Resolution};
use crate::cancel::CancelToken;
use crate::eval::{Baseline, BaselineError};
use crate::mech::{exact, MechCase, MechError};
use crate::scene::{Accuracy, BeamSpec, Drive, EffectsChoice, LoadPath, Mechanism, Scene};

use crate::mech::figures::{compare, has_reactions, CompareError};

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
    /// take their ends' fraction (the guided flexure's when clamped to the stage).
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

/// Decides the effects of `scene` whatever its own choice says: a cantilever's from its beam
/// under its load paths (`decide_beam_effects`), a mechanism's for every flexure whose
/// effects are `auto` from the beam mechanism along its drives
/// (`decide_mechanism_effects`). Stops soon after `cancel` is set (the UI's worker cancels
/// it when a newer edit arrives).
pub fn decide_effects(
    scene: &Scene,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<EffectsDecision, EffectsError> {
    match &scene.mechanism {
        Some(mechanism) => decide_mechanism_effects(mechanism, &scene.accuracy, resolution, cancel),
        None => Ok(decide_beam_effects(
            &scene.beam,
            &scene.loads,
            &scene.accuracy,
            resolution,
            cancel,
        )?),
    }
}

/// The most cases per load path on which each effect of a beam is judged (see
/// `decide_beam_effects`).
pub const DECIDE_STEPS: u32 = 8;

/// The effects of a beam under the given loads and targets.
///
/// Every effect is judged against the full model (all on): drop it (dropping extension drops
/// Poisson too), solve every case, and keep the effect if the tip moves by more than
/// [`AUTO_FRACTION`] of the target. Then all dropped effects are dropped together and checked
/// once more; should the combination exceed the fraction, the most influential dropped
/// effect is taken back until it does not.
///
/// On a scene whose paths have more than [`DECIDE_STEPS`] cases, each effect is judged on a
/// sample of every path: its cases at the fractions `k / d` of the path's end, `d` the
/// largest divisor of the path's steps not above [`DECIDE_STEPS`] (so the sample's cases are
/// the path's own, its end among them). The decision is then checked on every case: the
/// model with the decided effects is solved on all of them and must stay within
/// [`AUTO_FRACTION`] of the full model, and that figure is the one reported as
/// `dropped_together_fraction`; should it not, the decision is made again on every case. A
/// kept effect stays kept on every case (its change there is at least its change on the
/// sample, its cases among them); each effect's own figure is its change on the sample, a
/// lower bound of its change on every case, equal to it wherever the change is largest at
/// a sampled case (the path's end, for an effect that grows with the load). The plate
/// criterion is computed on every case, as before. So the decision is the full procedure's
/// unless one dropped effect alone moves the tip by more than the threshold between the
/// sampled cases while all the dropped ones together do not; and what it claims, that the
/// decided model is within the threshold of the full one, is checked on every case. Each
/// set of effects is solved on the sample at a few of its cases' cost, so the decision costs
/// about three solves of the scene (narrow beam, full model, decided model) instead of six.
fn decide_beam_effects(
    beam: &BeamSpec,
    loads: &[LoadPath],
    accuracy: &Accuracy,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<EffectsDecision, BaselineError> {
    let sample: Vec<LoadPath> = loads
        .iter()
        .map(|p| LoadPath {
            end: p.end,
            steps: sample_steps(p.steps),
        })
        .collect();
    let change = |memo: &mut Memo<Rc<Vec<BeamSolution>>, _>, e: Effects| {
        let (reference, with) = memo.pair(full_effects(), e)?;
        let (pos, ang) = tip_change(reference, with);
        Ok::<_, BaselineError>(Change {
            pos,
            ang,
            force: None,
        })
    };
    let mut every = Memo::new(solve_beam(beam, loads, resolution, cancel));
    // The plate criterion on the narrow beam with every refinement, on every case.
    let plate = plate_criterion(beam, every.get(Effects::ALL)?);
    let full = full_effects();
    let mut sampled = (sample.as_slice() != loads)
        .then(|| Memo::new(solve_beam(beam, &sample, resolution, cancel)));
    let mut decision = decide_on_sample(
        accuracy,
        full,
        sampled.as_mut().map(|s| move |e: Effects| change(s, e)),
        |e| change(&mut every, e),
    )?;
    decision.plate = Some(plate);
    Ok(decision)
}

/// Solves `beam` under `loads` with the effects asked for (a [`Memo`]'s solve). Once the
/// narrow beam with every refinement ([`Effects::ALL`]) is solved, the model with every
/// refinement and plane strain takes its cases' plate fractions from those cases instead of
/// solving them again (the same cases, bit for bit: [`BeamSolver::solve_path_on_narrow`]).
///
/// [`BeamSolver::solve_path_on_narrow`]: crate::beam::BeamSolver::solve_path_on_narrow
fn solve_beam<'a>(
    beam: &'a BeamSpec,
    loads: &'a [LoadPath],
    resolution: Resolution,
    cancel: &'a CancelToken,
) -> impl FnMut(Effects) -> Result<Rc<Vec<BeamSolution>>, BaselineError> + 'a {
    let mut narrow: Option<Rc<Vec<BeamSolution>>> = None;
    move |e| {
        let mut b = *beam;
        b.effects = EffectsChoice::Fixed(e);
        // The decision compares tips; only the plate criterion reads shapes, those of the
        // narrow beam with every refinement.
        let shapes = e == Effects::ALL;
        let on_narrow = narrow
            .as_deref()
            .filter(|_| e.plane_strain && e.with_plane_strain(false) == Effects::ALL)
            .map(|n| n.as_slice());
        let cases = Rc::new(
            Baseline::solve_keeping(
                b.model(),
                loads,
                resolution,
                cancel,
                &mut |_, _| {},
                shapes,
                on_narrow,
            )?
            .solutions,
        );
        if e == Effects::ALL {
            narrow = Some(Rc::clone(&cases));
        }
        Ok(cases)
    }
}

/// Solves `mechanism` along `drives` with the effects asked for in every flexure whose
/// effects are `auto` (a [`Memo`]'s solve).
fn solve_mechanism<'a>(
    mechanism: &'a Mechanism,
    drives: &'a [Drive],
    resolution: Resolution,
    cancel: &'a CancelToken,
) -> impl FnMut(Effects) -> Result<Vec<Vec<MechCase>>, EffectsError> + 'a {
    move |e| {
        let mut m = mechanism.clone();
        m.drives = drives.to_vec();
        for f in &mut m.flexures {
            if f.beam.effects == EffectsChoice::Auto {
                f.beam.effects = EffectsChoice::Fixed(e);
            }
        }
        exact::solver(&m, resolution)
            .and_then(|s| s.with_cancel(cancel).solve_all(&m))
            .map_err(|source| EffectsError::Mechanism { effects: e, source })
    }
}

/// A path's steps on the sample that decides the effects: the largest divisor of `steps` not
/// above [`DECIDE_STEPS`], so the sample's cases are the path's own, its end among them.
fn sample_steps(steps: u32) -> u32 {
    (1..=steps.min(DECIDE_STEPS))
        .rev()
        .find(|d| steps.is_multiple_of(*d))
        .unwrap_or(steps)
}

/// [`decide`] on the sample's changes `sample` (when the scene has more cases than its
/// sample), checked on every case (`every`): the decided model must stay within
/// [`AUTO_FRACTION`] of the full one there, which is the figure reported; else (and without a
/// sample) the decision is made on every case.
fn decide_on_sample<E, S, A>(
    accuracy: &Accuracy,
    full: Effects,
    sample: Option<S>,
    mut every: A,
) -> Result<EffectsDecision, E>
where
    S: FnMut(Effects) -> Result<Change, E>,
    A: FnMut(Effects) -> Result<Change, E>,
{
    if let Some(sample) = sample {
        let mut decision = decide(accuracy, full, sample)?;
        let together = every(decision.effects)?.fraction(accuracy);
        if together <= AUTO_FRACTION {
            decision.dropped_together_fraction = together;
            return Ok(decision);
        }
    }
    decide(accuracy, full, every)
}

/// The full model a decision is judged against: every effect, plane strain too.
fn full_effects() -> Effects {
    Effects::ALL.with_plane_strain(true)
}

/// A scene's cases solved with several sets of effects by `solve` (a beam's load paths, a
/// mechanism's drives), each set solved once however often it is asked for.
struct Memo<T, F> {
    solve: F,
    solved: Vec<(Effects, T)>,
}

impl<T, E, F: FnMut(Effects) -> Result<T, E>> Memo<T, F> {
    fn new(solve: F) -> Self {
        Memo {
            solve,
            solved: Vec::new(),
        }
    }

    /// The index in `solved` of the cases solved with `e`.
    fn index(&mut self, e: Effects) -> Result<usize, E> {
        if let Some(i) = self.solved.iter().position(|(k, _)| *k == e) {
            return Ok(i);
        }
        let cases = (self.solve)(e)?;
        self.solved.push((e, cases));
        Ok(self.solved.len() - 1)
    }

    /// The cases solved with `e`.
    fn get(&mut self, e: Effects) -> Result<&T, E> {
        let i = self.index(e)?;
        Ok(&self.solved[i].1)
    }

    /// The cases solved with `reference` and with `effects`.
    fn pair(&mut self, reference: Effects, effects: Effects) -> Result<(&T, &T), E> {
        let (r, e) = (self.index(reference)?, self.index(effects)?);
        Ok((&self.solved[r].1, &self.solved[e].1))
    }
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
/// [`decide_beam_effects`], with the exact mechanism (DESIGN §8) as the truth, every flexure whose
/// effects are `auto` modelled alike, and the change judged where the designer looks: the
/// stage's motion in its loaded coordinates and the reactions of its prescribed ones. The
/// same sample decides: each proportional drive's cases at the fractions `k / d`, `d` the
/// largest divisor of its steps not above [`DECIDE_STEPS`] (a measured drive's rows are all
/// kept: they are the data's own cases), the decision checked on every case.
fn decide_mechanism_effects(
    mechanism: &Mechanism,
    accuracy: &Accuracy,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<EffectsDecision, EffectsError> {
    // A flexure's plate stiffening in a mechanism is its ends' (`Flexure::model`: the guided
    // flexure's when its tip is clamped to the stage, the cantilever's when pinned or
    // coupled): the anticlastic part is load dependent, and the mechanism solver does not
    // follow each flexure's own load path case by case.
    let full = full_effects();
    let sample: Vec<Drive> = mechanism
        .drives
        .iter()
        .map(|d| Drive {
            steps: if d.rows.is_empty() {
                sample_steps(d.steps)
            } else {
                d.steps
            },
            ..d.clone()
        })
        .collect();
    let change = |memo: &mut Memo<Vec<Vec<MechCase>>, _>, drives: &[Drive], e: Effects| {
        let (reference, with) = memo.pair(full, e)?;
        let change = compare(drives, with, reference, 1.0, 1.0)?.figures;
        debug_assert_eq!(change.max_force_err.is_some(), has_reactions(drives));
        Ok::<_, EffectsError>(Change {
            pos: change.max_pos_err,
            ang: change.max_ang_err,
            force: change.max_force_err,
        })
    };
    let drives = &mechanism.drives;
    let mut every = Memo::new(solve_mechanism(mechanism, drives, resolution, cancel));
    let mut sampled = (&sample != drives)
        .then(|| Memo::new(solve_mechanism(mechanism, &sample, resolution, cancel)));
    decide_on_sample(
        accuracy,
        full,
        sampled.as_mut().map(|s| |e: Effects| change(s, &sample, e)),
        |e| change(&mut every, drives, e),
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
/// the scene as it is. On a mechanism scene the decision is made on the mechanism for every
/// flexure whose effects are `auto` (and the scene's `[beam]`, when `auto`, takes it too).
pub fn resolve_effects(
    scene: &Scene,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<(Scene, Option<EffectsDecision>), EffectsError> {
    let auto = |b: &BeamSpec| b.effects == EffectsChoice::Auto;
    let any_auto = match &scene.mechanism {
        Some(m) => m.flexures.iter().any(|f| auto(&f.beam)),
        None => auto(&scene.beam),
    };
    if !any_auto {
        return Ok((scene.clone(), None));
    }
    let decision = decide_effects(scene, resolution, cancel)?;
    let fixed = EffectsChoice::Fixed(decision.effects);
    let mut resolved = scene.clone();
    if let Some(m) = resolved.mechanism.as_mut() {
        for f in m.flexures.iter_mut().filter(|f| auto(&f.beam)) {
            f.beam.effects = fixed;
        }
    }
    if auto(&resolved.beam) {
        resolved.beam.effects = fixed;
    }
    Ok((resolved, Some(decision)))
}
