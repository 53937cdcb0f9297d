//! The extremes the baseline beam must survive (issue: baseline beam). Each solution is
//! checked against the beam equations through its shape, independently of the solver.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::f64::consts::PI;

use common::equilibrium_defect;
use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution, SolveError};

/// Fine resolution for checking shapes by finite differences. Two errors enter the check:
/// the fourth-order difference's truncation h^4/30 |f^(5)| with h = 2.5e-3 (401 samples),
/// about 1e-8 relative at the steepest case (alpha = 100, curvature 15 at the root); and the
/// shape's dense output, a quintic Hermite interpolant inside each integration step, whose
/// slope error O(h_step^5 |f^(6)|) reaches about 2e-7 relative there. A bound of 1e-6 sits
/// above both; a shape off the equilibrium by a visible amount fails it by orders.
fn fine(model: BeamModel) -> BeamSolver {
    BeamSolver::new(
        model,
        Resolution {
            tol: 1e-12,
            shape_points: 401,
        },
    )
    .unwrap()
}

fn check(model: BeamModel, load: Load, defect_bound: f64) -> prbfit::beam::BeamSolution {
    let sol = fine(model)
        .solve(load)
        .unwrap_or_else(|e| panic!("{load}: {e}"));
    let defect = equilibrium_defect(&model, &sol);
    println!(
        "{load}: tip {:?}, defect {defect:.2e}, iterations {}",
        sol.tip, sol.iterations
    );
    assert!(defect < defect_bound, "{load}: defect {defect:.3e}");
    assert!(sol.convergence.stability > 0.0);
    sol
}

#[test]
fn huge_transverse_force_alpha_100() {
    for effects in [Effects::NONE, Effects::ALL] {
        let model = BeamModel::new(100.0, 0.3, None, effects).unwrap();
        let sol = check(model, Load::new(0.0, 100.0, 0.0), 1e-6);
        // The beam hangs almost along the force: tip angle close to pi/2, a small.
        assert!(sol.tip.phi > 1.5 && sol.tip.phi < PI / 2.0);
        assert!(sol.tip.a < 0.2 && sol.tip.b > 0.85);
    }
}

#[test]
fn full_loop_both_ways() {
    for beta in [2.0 * PI, -2.0 * PI] {
        let sol = check(BeamModel::elastica(), Load::new(0.0, 0.0, beta), 1e-6);
        assert!(
            sol.tip.a.abs() < 1e-9 && sol.tip.b.abs() < 1e-9,
            "tip back at the root"
        );
        assert!((sol.tip.phi - beta).abs() < 1e-9);
    }
}

/// A load at 135 degrees from the beam axis (pushing back towards the clamp) with
/// alpha = 10 buckles the beam and swings the tip past the vertical.
#[test]
fn post_buckling_load_at_135_degrees() {
    let c = 10.0 * (3.0 * PI / 4.0).cos();
    let s = 10.0 * (3.0 * PI / 4.0).sin();
    for effects in [Effects::NONE, Effects::ALL] {
        let model = BeamModel::new(50.0, 0.3, None, effects).unwrap();
        let sol = check(model, Load::new(c, s, 0.0), 1e-6);
        assert!(
            sol.tip.phi > PI / 2.0,
            "tip angle {} not past vertical",
            sol.tip.phi
        );
        assert!(sol.tip.a < 0.0, "tip behind the clamp");
    }
}

/// Axial compression just below Euler's load pi^2/4 leaves the beam straight; above it,
/// exactly along the axis, there is no unique answer and the solver says so.
#[test]
fn axial_compression_and_euler_load() {
    let solver = fine(BeamModel::elastica());
    let below = solver
        .solve(Load::new(-0.95 * PI * PI / 4.0, 0.0, 0.0))
        .unwrap();
    assert!(below.tip.b.abs() < 1e-12 && (below.tip.a - 1.0).abs() < 1e-12);
    match solver.solve(Load::new(-3.0, 0.0, 0.0)) {
        Err(SolveError::Unstable { fraction, .. }) => {
            // The critical point is Euler's load: lambda * 3 = pi^2 / 4.
            assert!(
                (fraction * 3.0 - PI * PI / 4.0).abs() < 1e-3,
                "at {fraction}"
            );
        }
        other => panic!("expected an instability error, got {other:?}"),
    }
    // A slight tilt picks the buckling direction and the post-buckled shape follows.
    let tilted = check(BeamModel::elastica(), Load::new(-3.0, 0.01, 0.0), 1e-6);
    assert!(tilted.tip.b > 0.3, "buckled sideways: b = {}", tilted.tip.b);
}

/// Force and moment together bend the beam into an S: the curvature changes sign inside.
#[test]
fn combined_load_makes_an_s() {
    for effects in [Effects::NONE, Effects::ALL] {
        let model = BeamModel::new(30.0, 0.3, None, effects).unwrap();
        let sol = check(model, Load::new(0.0, 6.0, -3.0), 1e-6);
        let psi: Vec<f64> = sol.shape.iter().map(|p| p.psi).collect();
        let peak = psi.iter().cloned().fold(f64::MIN, f64::max);
        assert!(peak > psi[psi.len() - 1] + 0.05, "psi rises then falls");
        assert!(
            sol.root_moment > 0.0,
            "root moment and tip moment have opposite signs"
        );
    }
}

/// Force up, moment down: the beam first curls down, then the growing force flips it. The
/// equilibrium reached from zero ends at a limit point (the beam snaps through); the solver
/// reports it and its neighbourhood shows the stability slope collapsing.
#[test]
fn snap_through_is_reported() {
    let solver = fine(BeamModel::elastica());
    let end = Load::new(0.0, 4.855, -3.685);
    let fraction = match solver.solve(end) {
        Err(SolveError::Unstable { fraction, .. }) => fraction,
        other => panic!("expected a critical point, got {other:?}"),
    };
    assert!(fraction > 0.70 && fraction < 0.72, "at {fraction}");
    // Near a fold the slope vanishes like the square root of the distance to it.
    let stability = |f: f64| {
        solver
            .solve(end.scaled(fraction * f))
            .unwrap()
            .convergence
            .stability
    };
    let (early, near, nearer) = (stability(0.5), stability(0.999), stability(0.9999));
    assert!(near < 0.05 * early, "{near} vs {early}");
    let ratio = near / nearer;
    assert!(ratio > 2.0 && ratio < 4.5, "sqrt(10) expected, got {ratio}");
    let before = solver.solve(end.scaled(fraction * 0.9999)).unwrap();
    assert!(equilibrium_defect(&BeamModel::elastica(), &before) < 1e-6);
}

#[test]
fn nearly_incompressible_rubber() {
    let model = BeamModel::new(4.0, 0.499, None, Effects::ALL).unwrap();
    for load in [
        Load::new(0.0, 5.0, 0.0),
        Load::new(3.0, 3.0, 1.0),
        Load::new(-3.0, 2.0, 0.0),
        Load::new(0.0, 0.0, 2.0 * PI),
    ] {
        check(model, load, 1e-6);
    }
}

#[test]
fn slenderness_from_1_to_10000() {
    for slenderness in [1.0, 2.0, 10.0, 1e3, 1e4] {
        let model = BeamModel::new(slenderness, 0.3, None, Effects::ALL).unwrap();
        for load in [Load::new(0.0, 2.0, 0.0), Load::new(1.0, 1.0, 1.0)] {
            check(model, load, 1e-6);
        }
    }
}

/// Stubby rubber under a big pull necks in the Poisson law: a typed error, never a number.
/// `eps (1 - nu eps)^2` peaks at 4 / (27 nu); with c_e = 1/12 that is a pull of 3.63.
#[test]
fn material_limit_is_an_error() {
    let nu = 0.49;
    let peak = 4.0 / (27.0 * nu) * 12.0;
    let stretch_only = Effects::parse_list("extension,poisson").unwrap();
    let model = BeamModel::new(1.0, nu, None, stretch_only).unwrap();
    let err = fine(model).solve(Load::new(10.0, 0.0, 0.0)).unwrap_err();
    match &err {
        SolveError::MaterialLimit { fraction, .. } => {
            assert!(
                (fraction * 10.0 - peak).abs() < 1e-3 * peak,
                "at {fraction}"
            )
        }
        other => panic!("expected a material limit, got {other}"),
    }
    assert!(err.to_string().contains("necks"), "{err}");
    // With shear on as well, the softening section loses stability before it necks: the
    // shear strain's slope grows without bound as eps nears 1 / (3 nu).
    let model = BeamModel::new(1.0, nu, None, Effects::ALL).unwrap();
    match fine(model).solve(Load::new(10.0, 0.0, 0.0)) {
        Err(SolveError::Unstable { fraction, .. }) => assert!(fraction * 10.0 < peak),
        other => panic!("expected an instability, got {other:?}"),
    }
}

#[test]
fn non_finite_loads_are_rejected() {
    let solver = fine(BeamModel::elastica());
    assert!(matches!(
        solver.solve(Load::new(f64::NAN, 1.0, 0.0)),
        Err(SolveError::NonFiniteLoad(_))
    ));
    assert!(solver.solve(Load::new(0.0, f64::INFINITY, 0.0)).is_err());
}
