//! The exact mechanism: every flexure is the §2 beam (DESIGN §8) with its tip force and its
//! *root* moment as unknowns, shot from the clamp ([`BeamSolver::shoot_root`]): one
//! integration per flexure per Newton iteration, whose variational equations give the tip's
//! exact compliance (`d(a, b, phi, beta) / d(alpha_x, alpha_y, m0)`), and no Newton iteration
//! inside the flexure. The map from the root to the tip is an initial-value problem, so it
//! has no folds: a flexure held by the stage past its own load-controlled buckling load is
//! solved like any other. Newton's check of an iterate it expects to have converged shoots
//! without the variational equations ([`BeamSolver::shoot_root_tip`]) and samples the shape
//! there, for the case's stress; so does its first evaluation at a case, the continuation's
//! prediction, which on a drive of many cases is most often the solution (it then takes its
//! Jacobian from an earlier case, while its change extrapolated from the last two factored
//! stays small: `path.rs`, `Chord`). The flexures are shot two at a time, side by side, where
//! both take the Dormand-Prince integrator ([`crate::beam::root::shoot_root_pair`]; a plain
//! elastica's Taylor shot, and an odd flexure out, are shot alone): the same numbers as one
//! by one, in less time.
//!
//! Accuracy: Newton stops at the solver's `tol` on every compatibility residual; the shot
//! integrates to the beam's `tol`, so a flexure's tip is good to the beam's
//! `Resolution::claimed_tip_error` and its reported wrench `(alpha_x, alpha_y, beta)` is the
//! one that shape balances (`beta` is the shot's own tip moment).
//!
//! Range: one shot spans the flexure, and perturbations grow like `exp(sqrt(|alpha|))` along
//! it, so flexure forces past a few hundred (a stage load of hundreds of `E I / L^2`) lose
//! digits; the continuation then stops with [`MechError::NoEquilibrium`] rather than report
//! them.

use crate::beam::root::{shoot_root_pair, shoot_root_tip_pair, RootShot};
use crate::beam::{BeamSolver, Load, Resolution, ShapePoint, Stress, StressScratch, TipPose};
use crate::scene::Mechanism;

use super::geometry::Geometry;
use super::solve::{shape_storage, FlexEval, FlexureModel, Kind, MechSolver};
use super::{MechCase, MechError, TipFailure};

thread_local! {
    /// The stress search's storage, kept from case to case ([`BeamFlexure::stress`]).
    static STRESS_SCRATCH: std::cell::RefCell<StressScratch> =
        std::cell::RefCell::new(StressScratch::default());
}

/// Where `dM(L)/dM(0)` sits in a flexure's Jacobian (row `tip_moment`, column `m0`).
const STABILITY: usize = 3 * 3 + 2;

/// One flexure as the exact beam.
#[derive(Debug, Clone, Copy)]
pub struct BeamFlexure {
    /// Its solver (its own slenderness, effects and resolution).
    pub solver: BeamSolver,
}

impl FlexureModel for BeamFlexure {
    fn internal(&self) -> usize {
        0
    }

    fn eval(&self, w: [f64; 3], _z: &[f64]) -> Result<FlexEval, TipFailure> {
        // Newton's iterates with a Jacobian after the first are seldom its solution (that is
        // checked by values, below), so they do not sample the centre line.
        self.full(w, false)
    }

    fn predicted(&self) -> bool {
        true
    }

    fn eval_shaped(&self, w: [f64; 3], _z: &[f64]) -> Result<FlexEval, TipFailure> {
        self.full(w, true)
    }

    fn eval_values(&self, w: [f64; 3], _z: &[f64]) -> Result<FlexEval, TipFailure> {
        // The shot samples its centre line: a check that converges is the solved shape,
        // whose stress the case reports (`stress`), for a few interpolations per step
        // instead of another shot.
        let mut shape = shape_storage();
        let tip = self
            .solver
            .shoot_root_tip(w[0], w[1], w[2], Some(&mut shape))?;
        Ok(values_eval(tip, shape))
    }

    fn eval_all(
        models: &[Self],
        at: &[([f64; 3], &[f64])],
        kind: Kind,
    ) -> Vec<Result<FlexEval, TipFailure>> {
        // Two by two, side by side (`beam::root::shoot_root_pair`): the same numbers as one
        // by one, in about two thirds of the time. Up to the first pair with a failure.
        let mut out: Vec<Result<FlexEval, TipFailure>> = Vec::with_capacity(models.len());
        for (pair, at) in models.chunks(2).zip(at.chunks(2)) {
            if out.iter().any(Result::is_err) {
                break;
            }
            match (pair, at) {
                ([a, b], [(wa, _), (wb, _)]) => {
                    if kind != Kind::Values {
                        // With the variational equations; the shapes where asked for.
                        let (mut sa, mut sb) = (shape_storage(), shape_storage());
                        let sampled = kind == Kind::Shaped;
                        let [ra, rb] = shoot_root_pair([
                            (&a.solver, *wa, sampled.then_some(&mut sa)),
                            (&b.solver, *wb, sampled.then_some(&mut sb)),
                        ]);
                        out.push(ra.map(|s| full_eval(&s, sa)).map_err(TipFailure::from));
                        out.push(rb.map(|s| full_eval(&s, sb)).map_err(TipFailure::from));
                    } else {
                        let (mut sa, mut sb) = (shape_storage(), shape_storage());
                        let [ra, rb] = shoot_root_tip_pair([
                            (&a.solver, *wa, Some(&mut sa)),
                            (&b.solver, *wb, Some(&mut sb)),
                        ]);
                        out.push(ra.map(|t| values_eval(t, sa)).map_err(TipFailure::from));
                        out.push(rb.map(|t| values_eval(t, sb)).map_err(TipFailure::from));
                    }
                }
                _ => out.extend(
                    pair.iter()
                        .zip(at)
                        .map(|(m, &(w, z))| m.eval_as(w, z, kind)),
                ),
            }
        }
        out
    }

    fn load_stable(&self, eval: &FlexEval, _w: [f64; 3], _z: &[f64]) -> bool {
        // dM(L)/dM(0), the single beam's own test (see `beam::root::RootShot::stability`).
        eval.jacobian[STABILITY] > 0.0
    }

    fn stability_indicator(&self, eval: &FlexEval) -> Option<f64> {
        eval.jacobian.get(STABILITY).copied()
    }

    fn stress(&self, eval: &FlexEval, w: [f64; 3], _z: &[f64]) -> Option<Stress> {
        // The shape `eval`'s own shot sampled (the root wrench `w` it was shot with), or,
        // for a solution Newton evaluated in full (which samples none), the shape of a shot
        // by values at the same wrench: one more shot, at the same tolerance.
        let load = Load::new(w[0], w[1], eval.tip_moment);
        let max_stress = |shape: &[ShapePoint]| {
            STRESS_SCRATCH.with_borrow_mut(|scratch| {
                self.solver.max_stress_with(load, eval.tip, shape, scratch)
            })
        };
        if eval.shape.is_empty() {
            let mut shape = Vec::new();
            self.solver
                .shoot_root_tip(w[0], w[1], w[2], Some(&mut shape))
                .ok()?;
            return max_stress(&shape);
        }
        max_stress(&eval.shape)
    }
}

/// A flexure evaluated in full from its shot, with the centre line it sampled (empty if
/// none).
fn full_eval(shot: &RootShot, shape: Vec<ShapePoint>) -> FlexEval {
    FlexEval {
        tip: shot.tip,
        tip_moment: shot.tip_moment,
        internal: Vec::new(),
        jacobian: shot.jacobian.iter().flatten().copied().collect(),
        shape,
    }
}

impl BeamFlexure {
    /// [`FlexureModel::eval`], sampling the centre line where `shaped`.
    fn full(&self, w: [f64; 3], shaped: bool) -> Result<FlexEval, TipFailure> {
        let mut shape = shape_storage();
        let shot =
            self.solver
                .shoot_root_sampled(w[0], w[1], w[2], shaped.then_some(&mut shape))?;
        Ok(full_eval(&shot, shape))
    }
}

/// A flexure evaluated by values from its shot's tip, tip moment and sampled centre line.
fn values_eval((tip, tip_moment): (TipPose, f64), shape: Vec<ShapePoint>) -> FlexEval {
    FlexEval {
        tip,
        tip_moment,
        internal: Vec::new(),
        jacobian: Vec::new(),
        shape,
    }
}

/// The exact mechanism solver of `mechanism`: each flexure its own beam at `resolution`,
/// Newton at the resolution's tol.
pub fn solver(
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<MechSolver<BeamFlexure>, MechError> {
    let mut models = Vec::with_capacity(mechanism.flexures.len());
    for (i, f) in mechanism.flexures.iter().enumerate() {
        let solver = BeamSolver::new(f.model(), resolution).map_err(|e| MechError::Flexure {
            flexure: i + 1,
            source: e.into(),
        })?;
        models.push(BeamFlexure { solver });
    }
    Ok(MechSolver::new(
        Geometry::new(mechanism),
        models,
        resolution.tol,
    ))
}

/// Every drive path of `mechanism`, solved exactly: one `Vec` of cases per drive.
pub fn solve(
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<Vec<Vec<MechCase>>, MechError> {
    solver(mechanism, resolution)?.solve_all(mechanism)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{BeamModel, Effects};

    /// Three flexures evaluated together (a pair side by side, the third alone) are each
    /// what it is evaluated alone, in full, in full with the shape, and by values, bit for
    /// bit.
    #[test]
    fn flexures_evaluated_together_are_each_evaluated_alone() {
        let beam = |slenderness: f64, effects| BeamFlexure {
            solver: BeamSolver::new(
                BeamModel::new(slenderness, 0.3, None, effects).unwrap(),
                Resolution::with_tol(1e-9),
            )
            .unwrap(),
        };
        let models = [
            beam(100.0, Effects::ALL),
            beam(20.0, Effects::ALL),
            beam(50.0, Effects::NONE),
        ];
        let w = [[-0.04, 1.2, 0.6], [0.04, 1.3, 0.62], [0.3, -0.8, -0.4]];
        let at: Vec<([f64; 3], &[f64])> = w.iter().map(|&w| (w, &[][..])).collect();
        for kind in [Kind::Full, Kind::Shaped, Kind::Values] {
            let together = BeamFlexure::eval_all(&models, &at, kind);
            assert_eq!(together.len(), 3);
            for ((m, &(w, z)), t) in models.iter().zip(&at).zip(&together) {
                let alone = m.eval_as(w, z, kind);
                assert_eq!(t.as_ref().unwrap(), &alone.unwrap(), "{kind:?}, at {w:?}");
            }
        }
        // A flexure that fails (its section necks under a pull of 200 E I0 / L^2) fails as
        // it does alone, and the evaluation stops at its pair.
        let rubber = BeamFlexure {
            solver: BeamSolver::new(
                BeamModel::new(4.0, 0.49, None, Effects::ALL).unwrap(),
                Resolution::with_tol(1e-9),
            )
            .unwrap(),
        };
        let models = [models[0], rubber, models[1], models[2]];
        let w = [w[0], [200.0, 0.0, 0.0], w[1], w[2]];
        let at: Vec<([f64; 3], &[f64])> = w.iter().map(|&w| (w, &[][..])).collect();
        for kind in [Kind::Full, Kind::Shaped, Kind::Values] {
            let together = BeamFlexure::eval_all(&models, &at, kind);
            assert_eq!(together.len(), 2, "{kind:?}: up to the failing pair");
            let alone = rubber.eval_as(w[1], &[], kind);
            assert!(alone.is_err());
            assert_eq!(together[1], alone, "{kind:?}");
        }
    }
}
