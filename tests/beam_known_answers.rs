//! Known answers for the baseline beam (shared/reference/validation.md and closed forms).

use std::f64::consts::PI;

use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution};

fn elastica(tol: f64) -> BeamSolver {
    BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(tol)).unwrap()
}

/// Bisshopp & Drucker's table (validation.md), given to 6 decimals: rounding alone is 5e-7.
#[test]
fn elliptic_table_transverse_force() {
    let table = [
        (0.5, 0.984081, 0.162144, 0.244534),
        (1.0, 0.943567, 0.301721, 0.461352),
        (2.0, 0.839358, 0.493457, 0.781750),
        (3.0, 0.745580, 0.603253, 0.986017),
        (5.0, 0.612372, 0.713792, 1.215368),
        (10.0, 0.445004, 0.810609, 1.430286),
    ];
    let solver = elastica(1e-10);
    for (alpha_y, a, b, phi) in table {
        let tip = solver.solve(Load::new(0.0, alpha_y, 0.0)).unwrap().tip;
        assert!(
            (tip.a - a).abs() < 1e-6,
            "alpha_y {alpha_y}: a {} vs {a}",
            tip.a
        );
        assert!(
            (tip.b - b).abs() < 1e-6,
            "alpha_y {alpha_y}: b {} vs {b}",
            tip.b
        );
        assert!(
            (tip.phi - phi).abs() < 1e-6,
            "alpha_y {alpha_y}: phi {} vs {phi}",
            tip.phi
        );
    }
}

/// A pure tip moment bends the inextensible beam into a circular arc, for any beta up to a
/// full loop (and shear does nothing: Q = 0 when alpha = 0).
#[test]
fn circle_under_pure_moment() {
    let solver = elastica(1e-10);
    for beta in [-2.0 * PI, -4.0, -1.0, 1e-3, 0.5, 2.0, PI, 5.0, 2.0 * PI] {
        let sol = solver.solve(Load::new(0.0, 0.0, beta)).unwrap();
        let (a, b) = (beta.sin() / beta, (1.0 - beta.cos()) / beta);
        assert!((sol.tip.a - a).abs() < 1e-6, "beta {beta}: a {}", sol.tip.a);
        assert!((sol.tip.b - b).abs() < 1e-6, "beta {beta}: b {}", sol.tip.b);
        assert!(
            (sol.tip.phi - beta).abs() < 1e-6,
            "beta {beta}: phi {}",
            sol.tip.phi
        );
        // Every shape point lies on the circle of radius 1/beta centred at (0, 1/beta).
        let r = 1.0 / beta;
        for p in &sol.shape {
            let d = (p.x.powi(2) + (p.y - r).powi(2)).sqrt();
            assert!(
                (d - r.abs()).abs() < 1e-6,
                "beta {beta}: point off the circle"
            );
        }
    }
}

/// Linear Timoshenko: deflection F L^3/(3EI) + F L/(kappa G A0), section rotation F L^2/(2EI).
/// At alpha = 1e-4 the geometric nonlinearity is O(alpha^3) relative ~ 1e-9.
#[test]
fn linear_timoshenko_limit_with_shear() {
    for slenderness in [1.0, 3.0, 10.0, 100.0] {
        let model = BeamModel::new(
            slenderness,
            0.3,
            None,
            Effects::parse_list("shear").unwrap(),
        )
        .unwrap();
        let solver = BeamSolver::new(model, Resolution::with_tol(1e-11)).unwrap();
        let f = 1e-4;
        let tip = solver.solve(Load::new(0.0, f, 0.0)).unwrap().tip;
        let expected_b = f / 3.0 + f * model.shear_compliance();
        assert!(
            ((tip.b - expected_b) / expected_b).abs() < 1e-6,
            "L/t {slenderness}: b {} vs {expected_b}",
            tip.b
        );
        assert!(((tip.phi - f / 2.0) / (f / 2.0)).abs() < 1e-6);
    }
}

/// Loads of 1e-9 agree with linear theory to many digits (no drowning in round-off).
#[test]
fn tiny_loads_match_linear_theory() {
    let model = BeamModel::new(20.0, 0.3, None, Effects::ALL).unwrap();
    let solver = BeamSolver::new(model, Resolution::default()).unwrap();
    let f = 1e-9;
    let tip = solver.solve(Load::new(0.0, f, 0.0)).unwrap().tip;
    let expected_b = f / 3.0 + f * model.shear_compliance();
    assert!(
        ((tip.b - expected_b) / expected_b).abs() < 1e-8,
        "b {}",
        tip.b
    );
    assert!(
        ((tip.phi - f / 2.0) / (f / 2.0)).abs() < 1e-8,
        "phi {}",
        tip.phi
    );
    let m = 1e-9;
    let tip = solver.solve(Load::new(0.0, 0.0, m)).unwrap().tip;
    assert!(((tip.phi - m) / m).abs() < 1e-8);
    assert!(((tip.b - m / 2.0) / (m / 2.0)).abs() < 1e-8);
    let t = 1e-9;
    let tip = solver.solve(Load::new(t, 0.0, 0.0)).unwrap().tip;
    let stretch = tip.a - 1.0;
    // Extension with Poisson: eps (1 - nu eps)^2 = c_e t, i.e. eps = c_e t to O(t^2).
    let expected = t * model.axial_compliance();
    // The stretch (2e-13) is read off a = 1 + stretch, which double precision holds only to
    // its last bits: allow four ulps of 1.
    assert!(
        (stretch - expected).abs() < 4.0 * f64::EPSILON,
        "stretch {stretch}"
    );
}

/// Pure tension with extension on (Poisson off): a = 1 + Fx / (E A0), exactly, any load.
#[test]
fn pure_tension_stretches_by_n_over_ea() {
    for slenderness in [2.0, 10.0] {
        let model = BeamModel::new(
            slenderness,
            0.3,
            None,
            Effects::parse_list("extension").unwrap(),
        )
        .unwrap();
        let solver = BeamSolver::new(model, Resolution::default()).unwrap();
        for alpha_x in [0.5, 5.0, 50.0] {
            let tip = solver.solve(Load::new(alpha_x, 0.0, 0.0)).unwrap().tip;
            let expected = 1.0 + alpha_x * model.axial_compliance();
            assert!(
                (tip.a - expected).abs() < 1e-12,
                "a {} vs {expected}",
                tip.a
            );
            assert!(tip.b.abs() < 1e-12 && tip.phi.abs() < 1e-12);
        }
    }
}

/// With Poisson on, pure tension solves eps (1 - nu eps)^2 = N / (E A0).
#[test]
fn pure_tension_with_poisson() {
    let nu = 0.49;
    let model = BeamModel::new(3.0, nu, None, Effects::ALL).unwrap();
    let solver = BeamSolver::new(model, Resolution::default()).unwrap();
    let alpha_x = 20.0;
    let tip = solver.solve(Load::new(alpha_x, 0.0, 0.0)).unwrap().tip;
    let eps = tip.a - 1.0;
    let lhs = eps * (1.0 - nu * eps).powi(2);
    assert!(
        (lhs - alpha_x * model.axial_compliance()).abs() < 1e-12,
        "eps {eps}"
    );
}
