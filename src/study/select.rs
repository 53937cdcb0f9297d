//! The topology ladder (the paper's "simple procedure that leads the user to the most
//! effective PRB model for each situation", made automatic and measured): [`Study::select`]
//! fits a ladder of topologies in order of complexity, judges the published models as they
//! are, and picks the simplest model that meets the scene's targets, on every kind of scene.
//! A model that cannot follow the scene (a 1R asked to keep its tip angle, a fit that found
//! nothing that follows) is listed as unfollowed and the ladder goes on.

use std::time::Instant;

use serde::Serialize;

use crate::beam::Effects;
use crate::fit::{CancelToken, Fidelity, FitOptions, FitProgress};
use crate::mech::figures::Figures;
use crate::prb::published;
use crate::prb::PrbMatrix;
use crate::scene::Accuracy;

use super::fit::FitError;
use super::Study;

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
    /// The error figures of the matrix on the selection's truth (DESIGN §4, §8).
    pub figures: Figures,
    /// Whether every error figure is within the scene's target.
    pub meets_targets: bool,
    /// Worst ratio of an error figure to its target (1 = on target); infinite, `"inf"` in
    /// JSON, for a model with fewer frequencies than the scene judges.
    #[serde(serialize_with = "crate::mech::figures::infinite_as_text::number")]
    pub target_ratio: f64,
    /// Time to solve the PRB model for one case, seconds.
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
    /// The models tried that cannot follow the scene, in the order tried.
    pub unfollowed: Vec<Unfollowed>,
}

impl Rung {
    fn new(
        name: String,
        m: PrbMatrix,
        published: bool,
        figures: Figures,
        accuracy: &Accuracy,
        costs: (f64, f64),
    ) -> Rung {
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

impl Selection {
    /// Ranks the rows (simplest first: joint freedoms, then fitted before published, then
    /// `J`) and picks the simplest that meets the targets.
    fn ranked(mut rows: Vec<Rung>, unfollowed: Vec<Unfollowed>, fidelity: Fidelity) -> Self {
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
        Selection {
            rows,
            chosen,
            closest,
            fidelity,
            unfollowed,
        }
    }
}

/// Seconds per case of `run`, which does `cases` cases: repeated until 5 ms have passed.
pub fn per_case(cases: usize, mut run: impl FnMut()) -> f64 {
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

impl Study {
    /// The effects of every flexure together (extension in any flexure brings the ladder's
    /// extension-spring variants).
    pub fn effects(&self) -> Effects {
        self.mechanism()
            .flexures
            .iter()
            .map(|f| f.beam.effects.resolve())
            .fold(Effects::NONE, |a, e| Effects {
                shear: a.shear || e.shear,
                extension: a.extension || e.extension,
                poisson: a.poisson || e.poisson,
                plane_strain: a.plane_strain || e.plane_strain,
            })
    }

    /// The cost of one PRB case of `matrix`: judging it on the truth, repeated until 5 ms
    /// have passed, divided by the cases.
    pub fn eval_cost(&self, matrix: &PrbMatrix) -> f64 {
        per_case(self.case_count(), || {
            let _ = self.judge(matrix);
        })
    }

    /// Fits the ladder and judges the published models on the truth (one matrix for every
    /// flexure of a mechanism), against the scene's targets; `on_row` sees each row as it is
    /// done. A topology or published model that cannot follow the scene is listed in
    /// [`Selection::unfollowed`]. Cancelled, it returns what it has.
    ///
    /// # Errors
    /// A fit that cannot start (a bad weight).
    pub fn select(
        &self,
        fidelity: Fidelity,
        cancel: &CancelToken,
        on_row: &mut dyn FnMut(&Rung),
    ) -> Result<Selection, FitError> {
        self.select_with_progress(fidelity, cancel, on_row, &mut |_, _| {})
    }

    /// [`Study::select`], with each ladder fit's progress (its topology and the fit's
    /// [`FitProgress`], at the fit's own pace) to `on_fit`: a fit on many cases runs for
    /// minutes between two rows.
    ///
    /// # Errors
    /// As [`Study::select`].
    pub fn select_with_progress(
        &self,
        fidelity: Fidelity,
        cancel: &CancelToken,
        on_row: &mut dyn FnMut(&Rung),
        on_fit: &mut dyn FnMut(&str, &FitProgress),
    ) -> Result<Selection, FitError> {
        let accuracy = self.scene().accuracy;
        let mut rows = Vec::new();
        let mut unfollowed = Vec::new();
        for topology in ladder(self.effects()) {
            if cancel.is_cancelled() {
                break;
            }
            let options = FitOptions {
                fidelity,
                angle_weight: self.scene().fit.angle_weight,
                seed: 1,
            };
            let t0 = Instant::now();
            let mut progress = |p: &FitProgress| on_fit(topology, p);
            let report = match self.fit(&ladder_start(topology), &options, &mut progress, cancel) {
                Ok(report) => report,
                Err(FitError::NoFeasibleModel(e)) => {
                    let what = match self.case_form() {
                        super::CaseForm::Tip => "the loads",
                        super::CaseForm::Stage => "the mechanism",
                    };
                    unfollowed.push(Unfollowed {
                        name: topology.to_string(),
                        reason: format!("no fitted {topology} follows {what}: {e}"),
                    });
                    continue;
                }
                Err(e) => return Err(e),
            };
            let fit_seconds = t0.elapsed().as_secs_f64();
            let cost = self.eval_cost(&report.matrix);
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
            match self.judge(&model.prb) {
                Ok(e) => {
                    let cost = self.eval_cost(&model.prb);
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
