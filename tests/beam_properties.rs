//! Properties of the baseline beam that hold for every load, checked over generated inputs.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use prbfit::beam::{BeamModel, BeamSolution, BeamSolver, Effects, Load, Resolution, SolveError};
use proptest::prelude::*;

fn effects() -> impl Strategy<Value = Effects> {
    prop_oneof![
        Just(Effects::NONE),
        Just(Effects::parse_list("shear").unwrap()),
        Just(Effects::parse_list("extension").unwrap()),
        Just(Effects::ALL),
    ]
}

/// Loads inside the solver's everyday range (transverse and axial forces, moments, mixed).
fn load() -> impl Strategy<Value = Load> {
    (-8.0..8.0f64, -8.0..8.0f64, -4.0..4.0f64)
        .prop_map(|(ax, ay, beta)| Load::new(ax, ay, beta))
        // An exactly axial compression past Euler's load has no unique answer.
        .prop_filter("not a pure axial compression", |l| {
            l.alpha_y.abs() + l.beta.abs() > 0.05
        })
}

/// Solves, treating a reported critical point (snap-through or bifurcation, which some
/// force-and-moment combinations in the range reach) as "no case here". Any other failure is
/// a test failure.
fn solve_or_critical(solver: &BeamSolver, load: Load) -> Option<BeamSolution> {
    match solver.solve(load) {
        Ok(sol) => Some(sol),
        Err(SolveError::Unstable { .. }) => None,
        Err(e) => panic!("{load}: {e}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Negating alpha_y and beta mirrors the beam in the x axis: a stays, b and phi flip.
    #[test]
    fn mirror_symmetry(load in load(), effects in effects(), slenderness in 3.0..200.0f64,
                       nu in 0.0..0.49f64) {
        let model = BeamModel::new(slenderness, nu, None, effects).unwrap();
        let solver = BeamSolver::new(model, Resolution::with_tol(1e-10)).unwrap();
        let mirrored = Load::new(load.alpha_x, -load.alpha_y, -load.beta);
        let (Ok(p), Ok(q)) = (solver.solve(load), solver.solve(mirrored)) else {
            // Both must fail alike (a material limit is symmetric too).
            prop_assert_eq!(solver.solve(load).is_ok(), solver.solve(mirrored).is_ok());
            return Ok(());
        };
        // Both are solved to the claimed error independently; their mismatch is at most twice.
        let claim = 2.0 * solver.resolution.claimed_tip_error();
        prop_assert!((p.tip.a - q.tip.a).abs() <= claim, "a {} vs {}", p.tip.a, q.tip.a);
        prop_assert!((p.tip.b + q.tip.b).abs() <= claim, "b {} vs {}", p.tip.b, q.tip.b);
        prop_assert!((p.tip.phi + q.tip.phi).abs() <= claim, "phi {} vs {}", p.tip.phi, q.tip.phi);
    }

    /// The resolution keeps its promise: the tip at a tolerance differs from a much finer
    /// solve by less than that tolerance's claimed error.
    #[test]
    fn finer_resolution_moves_the_tip_less_than_claimed(load in load(), effects in effects(),
                                                        exponent in 5..11i32) {
        let model = BeamModel::new(20.0, 0.3, None, effects).unwrap();
        let tol = 10f64.powi(-exponent);
        let coarse = BeamSolver::new(model, Resolution::with_tol(tol)).unwrap();
        let fine = BeamSolver::new(model, Resolution::with_tol(1e-13)).unwrap();
        let Some(b) = solve_or_critical(&fine, load) else { return Ok(()) };
        let a = coarse.solve(load).unwrap();
        let diff = a.tip.max_diff(&b.tip);
        prop_assert!(diff <= coarse.resolution.claimed_tip_error(),
                     "tol {tol:e}: tip moved {diff:e}");
    }

    /// Shear and stretch are O((t/L)^2) effects: the tip with every effect on approaches the
    /// elastica's as the beam gets slender, and 100 times closer for 10 times the slenderness.
    #[test]
    fn shear_and_extension_vanish_for_slender_beams(load in load(), nu in 0.0..0.49f64) {
        let reference = BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-12)).unwrap();
        // Keep away from critical points, where the effects' small shift of the critical
        // load changes the answer discontinuously.
        let Some(elastica) = solve_or_critical(&reference, load.scaled(1.1)).and_then(|_| {
            solve_or_critical(&reference, load)
        }) else { return Ok(()) };
        let gap = |slenderness: f64| {
            let model = BeamModel::new(slenderness, nu, None, Effects::ALL).unwrap();
            let solver = BeamSolver::new(model, Resolution::with_tol(1e-12)).unwrap();
            solver.solve(load).unwrap().tip.max_diff(&elastica.tip)
        };
        let (g30, g300, g3000) = (gap(30.0), gap(300.0), gap(3000.0));
        // At L/t = 3000 the effects are ~1e-7 of the load; the solves are good to ~1e-11.
        prop_assert!(g3000 < 1e-6, "L/t 3000: {g3000:e}");
        // Quadratic decay, with room for the O((t/L)^4) terms at L/t = 30.
        prop_assert!(g300 < g30 / 50.0 + 1e-10, "{g30:e} -> {g300:e}");
        prop_assert!(g3000 < g300 / 50.0 + 1e-10, "{g300:e} -> {g3000:e}");
    }
}
