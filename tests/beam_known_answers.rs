//! Known answers for the baseline beam (shared/reference/validation.md and closed forms).
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{carlson_rd, carlson_rf};
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

/// Incomplete elliptic integrals of the first and second kind, modulus k.
fn elliptic_f_e(phi: f64, k: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let y = 1.0 - k * k * s * s;
    let rf = carlson_rf(c * c, y, 1.0);
    let rd = carlson_rd(c * c, y, 1.0);
    (s * rf, s * rf - k * k * s * s * s * rd / 3.0)
}

/// Bisshopp & Drucker's closed form (validation.md) for the tip angle `phi`: the load that
/// produces it and the tip position.
fn bisshopp_drucker(phi: f64) -> (f64, f64, f64) {
    let k = ((1.0 + phi.sin()) / 2.0).sqrt();
    let p1 = (1.0 / (2.0_f64.sqrt() * k)).asin();
    let (kk, ek) = elliptic_f_e(PI / 2.0, k);
    let (f1, e1) = elliptic_f_e(p1, k);
    let root_alpha = kk - f1;
    let a = (2.0 * phi.sin()).sqrt() / root_alpha;
    let b = 1.0 - 2.0 * (ek - e1) / root_alpha;
    (root_alpha * root_alpha, a, b)
}

/// The closed form reproduces the published table, and the solver matches the closed form
/// to 1e-8 from small to very large deflections (tip angles 0.05 to 1.55 rad, alpha_y up to
/// about 60).
#[test]
fn elliptic_closed_form_transverse_force() {
    // The table's alpha_y = 2 row, through the closed form: tip angle 0.781750.
    let (alpha, a, b) = bisshopp_drucker(0.781750);
    assert!((alpha - 2.0).abs() < 1e-5 && (a - 0.839358).abs() < 1e-6);
    assert!((b - 0.493457).abs() < 1e-6);
    let solver = elastica(1e-11);
    for i in 1..=31 {
        let phi = 0.05 * i as f64;
        let (alpha_y, a, b) = bisshopp_drucker(phi);
        let tip = solver.solve(Load::new(0.0, alpha_y, 0.0)).unwrap().tip;
        assert!((tip.a - a).abs() < 1e-8, "phi {phi}: a {} vs {a}", tip.a);
        assert!((tip.b - b).abs() < 1e-8, "phi {phi}: b {} vs {b}", tip.b);
        assert!(
            (tip.phi - phi).abs() < 1e-8,
            "phi {phi}: {} at alpha_y {alpha_y}",
            tip.phi
        );
    }
}

/// Plane strain (a wide section) is the narrow beam with the plate modulus E / (1 - nu^2) in
/// bending and stretching and the same shear modulus: under a pure moment every curvature is
/// scaled by 1 - nu^2, so the elastica's closed form holds with beta (1 - nu^2); under a
/// small transverse force the bending part of the deflection shrinks by 1 - nu^2 and the
/// shear part does not; a pull stretches 1 - nu^2 as far.
#[test]
fn plane_strain_is_the_plate_modulus() {
    let nu = 0.3;
    let plate = 1.0 - nu * nu;
    let wide = Effects::parse_list("plane_strain").unwrap();
    let solver = BeamSolver::new(
        BeamModel::new(50.0, nu, None, wide).unwrap(),
        Resolution::with_tol(1e-11),
    )
    .unwrap();
    let beta = 2.0;
    let tip = solver.solve(Load::new(0.0, 0.0, beta)).unwrap().tip;
    let turn = beta * plate;
    assert!((tip.phi - turn).abs() < 1e-9, "phi {}", tip.phi);
    assert!((tip.a - turn.sin() / turn).abs() < 1e-9, "a {}", tip.a);
    assert!(
        (tip.b - (1.0 - turn.cos()) / turn).abs() < 1e-9,
        "b {}",
        tip.b
    );

    let all = Effects::parse_list("all,plane_strain").unwrap();
    let model = BeamModel::new(10.0, nu, None, all).unwrap();
    let solver = BeamSolver::new(model, Resolution::with_tol(1e-11)).unwrap();
    let f = 1e-6;
    let tip = solver.solve(Load::new(0.0, f, 0.0)).unwrap().tip;
    let expected_b = plate * f / 3.0 + f * model.shear_compliance();
    assert!(
        ((tip.b - expected_b) / expected_b).abs() < 1e-6,
        "b {} vs {expected_b}",
        tip.b
    );
    let t = 1e-3;
    let tip = solver.solve(Load::new(t, 0.0, 0.0)).unwrap().tip;
    let expected = plate * t * model.axial_compliance();
    assert!(
        ((tip.a - 1.0 - expected) / expected).abs() < 1e-4,
        "stretch {} vs {expected}",
        tip.a - 1.0
    );
    assert!((model.plate_factor() - 1.0 / plate).abs() < 1e-15);
}

/// A finely sampled path takes one Newton shot a case (the quadratic predictor, the first
/// shot accepted by the contraction measured on the path) and carries Newton's last update
/// to the shape linearly: every case's tip and every shape point must still be as accurate
/// as the resolution claims, against the same path solved at tol 1e-12 (whose own error is
/// a thousandth of that claim). Circle arcs (a pure moment) and transverse and pushing forces,
/// with every effect on for one of them.
#[test]
fn one_shot_cases_of_a_fine_path_are_as_accurate_as_claimed() {
    let tol = 1e-9;
    let models = [
        (BeamModel::elastica(), Load::new(0.0, 5.0, 0.0)),
        (BeamModel::elastica(), Load::new(0.0, 0.0, 2.0 * PI)),
        (BeamModel::elastica(), Load::new(-2.1213, 2.1213, 0.0)),
        (
            BeamModel::new(10.0, 0.45, None, Effects::ALL).unwrap(),
            Load::new(-1.0, 3.0, 1.0),
        ),
    ];
    for (model, end) in models {
        let fast = BeamSolver::new(model, Resolution::with_tol(tol)).unwrap();
        let reference = BeamSolver::new(model, Resolution::with_tol(1e-12)).unwrap();
        let claim = fast.resolution.claimed_tip_error();
        let cases = fast.solve_path(end, 400).unwrap();
        let exact = reference.solve_path(end, 400).unwrap();
        let shots: u32 = cases.iter().map(|c| c.iterations).sum();
        // Most cases take one shot (the first few, before a contraction is measured, two).
        assert!(shots < 440, "{end}: {shots} shots for 400 cases");
        for (c, e) in cases.iter().zip(&exact) {
            assert!(
                c.tip.max_diff(&e.tip) <= claim,
                "{end}: tip {:?} vs {:?}",
                c.tip,
                e.tip
            );
            assert_eq!(c.shape.len(), e.shape.len());
            for (p, q) in c.shape.iter().zip(&e.shape) {
                let gap = (p.x - q.x)
                    .abs()
                    .max((p.y - q.y).abs())
                    .max((p.psi - q.psi).abs());
                assert!(gap <= claim, "{end}: shape at s {} off by {gap:e}", p.s);
            }
            // The shape ends at the tip.
            let last = c.shape.last().unwrap();
            let gap = (last.x - c.tip.a).abs().max((last.y - c.tip.b).abs());
            assert!(gap <= claim, "{end}: shape's end {gap:e} from the tip");
        }
    }
}
