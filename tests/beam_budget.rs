//! Loads far beyond the everyday range (issue 11): every solve answers or says why not within
//! a bounded effort, huge forces are answered and right, and a solve can be cancelled.
//!
//! No test here asserts a wall-clock time: `cargo bench --bench beam` reports the times.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{carlson_rd, carlson_rf};
use std::f64::consts::{FRAC_PI_2, PI};
use std::thread;
use std::time::Duration;

use prbfit::beam::{
    BeamModel, BeamSolver, Effects, EffortBudget, Load, Resolution, SolveError, TipPose,
};
use prbfit::cancel::CancelToken;

fn elastica() -> BeamSolver {
    BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-9)).unwrap()
}

/// Bisshopp & Drucker's closed form for a transverse tip force (validation.md),
///
/// ```text
/// sqrt(alpha_y) = K(k) - F(p1, k),   a = sqrt(2 sin phi) / sqrt(alpha_y),
/// b = 1 - 2 (E(k) - E(p1, k)) / sqrt(alpha_y),   k^2 = (1 + sin phi) / 2,
/// sin p1 = 1 / (sqrt(2) k),
/// ```
///
/// written in the complementary parameter `m1 = 1 - k^2 = (1 - sin phi) / 2` so that it stays
/// exact as the tip angle tends to pi/2: at `alpha_y = 1e5`, `m1` is about 1e-274 while
/// `phi` differs from pi/2 by far less than an ulp. With `sin^2 p1 = 1 / (2 k^2)` the
/// second argument of the incomplete integrals is exactly 1/2. Returns `(alpha_y, tip)`.
fn bisshopp_drucker(m1: f64) -> (f64, TipPose) {
    let k2 = 1.0 - m1;
    let complete_f = carlson_rf(0.0, m1, 1.0);
    let complete_e = complete_f - k2 / 3.0 * carlson_rd(0.0, m1, 1.0);
    let s = (0.5 / k2).sqrt();
    let c2 = (1.0 - 2.0 * m1) / (2.0 * k2);
    let f1 = s * carlson_rf(c2, 0.5, 1.0);
    let e1 = f1 - k2 * s * s * s / 3.0 * carlson_rd(c2, 0.5, 1.0);
    let root_alpha = complete_f - f1;
    // 1 - sin phi = 2 m1, i.e. pi/2 - phi = 2 asin(sqrt(m1)).
    let phi = FRAC_PI_2 - 2.0 * m1.sqrt().asin();
    let tip = TipPose {
        a: (2.0 * (1.0 - 2.0 * m1)).sqrt() / root_alpha,
        b: 1.0 - 2.0 * (complete_e - e1) / root_alpha,
        phi,
    };
    (root_alpha * root_alpha, tip)
}

/// The closed form at a given load: bisection on `ln m1` (the load grows monotonically as
/// `m1` falls), to round-off.
fn closed_form_transverse(alpha_y: f64) -> TipPose {
    let (mut lo, mut hi) = ((1e-300f64).ln(), 0.5f64.ln());
    assert!(
        bisshopp_drucker(lo.exp()).0 > alpha_y,
        "alpha_y {alpha_y} too big"
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if bisshopp_drucker(mid.exp()).0 > alpha_y {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    bisshopp_drucker(lo.exp()).1
}

/// The elastica's tip under a huge force `F` at angle `theta` (|theta| < pi) and a moment
/// `|beta| < 2 sqrt(F)`: matched boundary layers.
///
/// Measuring angles from the force, `chi = psi - theta`, the elastica is `chi'' = F sin chi`
/// with `chi(0) = -theta` and `chi'(L) = beta`. Away from the ends the beam lies along the
/// force (`chi = 0`, a saddle); the first integral `chi'^2 = 4 F sin^2(chi / 2) + C` has
/// `C = O(exp(-2 sqrt(F)))` because the beam spends a length of order 1 near the saddle. The
/// root layer turns `chi` from `-theta` to 0 and the tip layer from 0 to `chi_L` with
/// `sin(chi_L / 2) = beta / (2 sqrt F)`; integrating `e^{i chi} - 1` over each with
/// `ds = d chi / chi'` gives the tip, in the complex plane,
///
/// ```text
/// z = e^{i theta} (1 + 2/sqrt(F) [(cos(theta/2) - 1) - i sin(theta/2)]
///                    + 2/sqrt(F) [(cos(chi_L/2) - 1) + i sin(chi_L/2)]),
/// phi = theta + chi_L,
/// ```
///
/// up to terms of order `exp(-sqrt(F))`, below 1e-40 for `F >= 1e4`. For a transverse force
/// (theta = pi/2, beta = 0) this is `a = sqrt(2/F)`, `b = 1 - (2 - sqrt 2)/sqrt(F)`, the
/// limit of Bisshopp and Drucker's closed form (checked below).
fn aligned_asymptote(load: Load) -> TipPose {
    let force = load.alpha_x.hypot(load.alpha_y);
    let theta = load.alpha_y.atan2(load.alpha_x);
    let root = force.sqrt();
    let half_tip = (load.beta / (2.0 * root)).asin();
    assert!(theta.abs() < PI && load.beta.abs() < 2.0 * root);
    let d_re = 2.0 / root * ((0.5 * theta).cos() - 1.0 + half_tip.cos() - 1.0);
    let d_im = 2.0 / root * (-(0.5 * theta).sin() + half_tip.sin());
    let (s, c) = theta.sin_cos();
    let (re, im) = (1.0 + d_re, d_im);
    TipPose {
        a: c * re - s * im,
        b: s * re + c * im,
        phi: theta + 2.0 * half_tip,
    }
}

/// The closed form is exact where its parameter is representable, and at alpha_y = 1e4 and
/// 1e5 it already equals its limit, the aligned asymptote, to round-off. So the asymptote is
/// the exact answer to double precision for every larger load, where `m1` underflows.
#[test]
fn closed_form_reaches_its_limit() {
    // The published table's alpha_y = 10 row, through the m1 form of the closed form.
    let tip = closed_form_transverse(10.0);
    assert!((tip.a - 0.445004).abs() < 1e-6, "a {}", tip.a);
    assert!((tip.b - 0.810609).abs() < 1e-6, "b {}", tip.b);
    assert!((tip.phi - 1.430286).abs() < 1e-6, "phi {}", tip.phi);
    for alpha_y in [1e4, 1e5] {
        let exact = closed_form_transverse(alpha_y);
        let limit = aligned_asymptote(Load::new(0.0, alpha_y, 0.0));
        let gap = exact.max_diff(&limit);
        assert!(gap < 1e-14, "alpha_y {alpha_y}: {exact:?} vs {limit:?}");
    }
}

/// Huge transverse forces are answered, and the tip is the closed form's to well within the
/// resolution's claimed error (1e-8 at tol 1e-9; the brief asks for 1e-6). At 1e6 this
/// solve used to run for ever.
#[test]
fn huge_transverse_forces_match_the_closed_form() {
    let solver = elastica();
    for alpha_y in [1e4, 1e5, 1e6] {
        let load = Load::new(0.0, alpha_y, 0.0);
        let sol = solver.solve(load).unwrap_or_else(|e| panic!("{load}: {e}"));
        let expected = if alpha_y <= 1e5 {
            closed_form_transverse(alpha_y)
        } else {
            aligned_asymptote(load)
        };
        let err = sol.tip.max_diff(&expected);
        println!(
            "{load}: tip {:?}, error {err:.2e}, {} continuation steps, {} shots",
            sol.tip, sol.continuation_steps, sol.iterations
        );
        assert!(
            err <= solver.resolution.claimed_tip_error() && err < 1e-6,
            "{load}: tip {:?} vs {expected:?}",
            sol.tip
        );
        assert!(sol.convergence.stability > 0.0);
        // The number of continuation steps grows like the logarithm of the load.
        assert!(
            sol.continuation_steps < 40,
            "{} steps",
            sol.continuation_steps
        );
    }
}

/// Combined huge loads: a force at 45 degrees, a force with a tip moment, and a compression
/// tilted by 1e-4 rad, which buckles the beam early and swings it round to hang along the
/// force (this one used to return the straight beam, unstable 4000 times over).
#[test]
fn huge_combined_loads_match_the_aligned_asymptote() {
    let solver = elastica();
    for load in [
        Load::new(1e6, 1e6, 0.0),
        Load::new(0.0, 1e6, 1e3),
        Load::new(0.0, -1e5, 200.0),
        Load::new(-1e4, 1.0, 0.0),
        Load::new(-1e6, 1e5, 0.0),
    ] {
        let sol = solver.solve(load).unwrap_or_else(|e| panic!("{load}: {e}"));
        let expected = aligned_asymptote(load);
        let err = sol.tip.max_diff(&expected);
        println!("{load}: tip {:?}, error {err:.2e}", sol.tip);
        assert!(
            err <= solver.resolution.claimed_tip_error(),
            "{load}: tip {:?} vs {expected:?}",
            sol.tip
        );
    }
}

/// A huge pull with extension on only stretches the beam: `a = 1 + alpha_x c_e` exactly,
/// for any load (here a strain of 833 at L/t = 10, 8.3 at L/t = 100, 0.083 at L/t = 1000).
/// Shear on as well changes nothing while the straight beam is stable (see the next test).
/// The integrator's error is relative here: `a` is summed over up to 4096 segments.
#[test]
fn huge_tension_stretches_by_n_over_ea() {
    for (effects, slenderness) in [
        ("extension", 10.0),
        ("extension", 100.0),
        ("extension", 1000.0),
        ("shear,extension", 1000.0),
    ] {
        let model = BeamModel::new(
            slenderness,
            0.3,
            None,
            Effects::parse_list(effects).unwrap(),
        )
        .unwrap();
        let solver = BeamSolver::new(model, Resolution::default()).unwrap();
        let alpha_x = 1e6;
        let tip = solver.solve(Load::new(alpha_x, 0.0, 0.0)).unwrap().tip;
        let expected = 1.0 + alpha_x * model.axial_compliance();
        assert!(
            (tip.a - expected).abs() < 1e-11 * expected,
            "{effects}, L/t {slenderness}: a {} vs {expected}",
            tip.a
        );
        assert!(tip.b.abs() < 1e-12 && tip.phi.abs() < 1e-12);
    }
}

/// The Reissner beam with shear has a tension instability: straight under a pull `N`,
/// `dM/ds = n (1 + eps - c_s N) psi` to first order, which turns oscillatory once
/// `c_s N > 1 + eps = 1 + c_e N`, i.e. past `N = 1 / (c_s - c_e)` (58254 at L/t = 100 and
/// nu = 0.3, a strain of 49%); a focal point follows within a relative 1e-4. It is a property
/// of the model's linear shear law at huge strains, and the solver reports it.
#[test]
fn shear_makes_a_huge_pull_unstable() {
    let model = BeamModel::new(
        100.0,
        0.3,
        None,
        Effects::parse_list("shear,extension").unwrap(),
    )
    .unwrap();
    let solver = BeamSolver::new(model, Resolution::default()).unwrap();
    let critical = 1.0 / (model.shear_compliance() - model.axial_compliance());
    match solver.solve(Load::new(1e6, 0.0, 0.0)) {
        Err(SolveError::Unstable { fraction, .. }) => {
            let at = fraction * 1e6;
            assert!(
                (at / critical - 1.0).abs() < 1e-3,
                "at {at}, expected {critical}"
            );
        }
        other => panic!("expected an instability, got {other:?}"),
    }
}

/// Every effect on, a huge transverse force: answered, hanging along the force.
#[test]
fn huge_force_with_every_effect() {
    let model = BeamModel::new(300.0, 0.3, None, Effects::ALL).unwrap();
    let solver = BeamSolver::new(model, Resolution::default()).unwrap();
    let alpha_y = 1e5;
    let sol = solver.solve(Load::new(0.0, alpha_y, 0.0)).unwrap();
    assert!(
        (sol.tip.phi - FRAC_PI_2).abs() < 1e-9,
        "phi {}",
        sol.tip.phi
    );
    // Along the force the beam is stretched by the Poisson law's strain; the root's
    // boundary layer costs about (2 - sqrt 2) / sqrt(alpha) = 0.0019 of that.
    let (eps, _, _) = model.section_strains(alpha_y, 0.0).unwrap();
    let short = 1.0 + eps - sol.tip.b;
    assert!(
        short > 0.0 && short < 0.01,
        "b {} vs 1 + eps = {}",
        sol.tip.b,
        1.0 + eps
    );
    assert!(sol.tip.a > 0.0 && sol.tip.a < 0.01, "a {}", sol.tip.a);
}

/// An axial compression far past Euler's load is a bifurcation the solver reports, at
/// Euler's load, however large the load: one long continuation step used to land where
/// `dM(L)/dM(0) = cos(sqrt(alpha))` was positive again and return the straight, unstable beam.
#[test]
fn huge_axial_compression_is_unstable_at_eulers_load() {
    let solver = elastica();
    for alpha_x in [-30.0, -1e4, -1e6] {
        match solver.solve(Load::new(alpha_x, 0.0, 0.0)) {
            Err(SolveError::Unstable { fraction, .. }) => {
                let critical = -fraction * alpha_x;
                assert!(
                    (critical / (PI * PI / 4.0) - 1.0).abs() < 1e-3,
                    "alpha_x {alpha_x}: critical at {critical}"
                );
            }
            other => panic!("alpha_x {alpha_x}: expected an instability, got {other:?}"),
        }
    }
    // The message names the tiny fraction legibly.
    let err = solver.solve(Load::new(-1e6, 0.0, 0.0)).unwrap_err();
    assert!(err.to_string().contains("2.46"), "{err}");
}

/// A tip moment `beta > 2 sqrt(F)` cannot be carried by the tip's boundary layer
/// (`chi'^2 = 4 F sin^2(chi / 2)` peaks at `4 F`): along the path `lambda beta` outgrows
/// `2 sqrt(lambda F)` at `lambda = 4 F / beta^2`, where the tip snaps into a loop. The solver
/// reports that limit point, where the slope `dM(L)/dM(0)` is still 1e285 at 1e6.
#[test]
fn huge_force_with_too_big_a_tip_moment_snaps() {
    let solver = elastica();
    for load in [Load::new(0.0, 1e4, 300.0), Load::new(0.0, -1e6, -3000.0)] {
        let expected = 4.0 * load.alpha_y.abs() / (load.beta * load.beta);
        match solver.solve(load) {
            Err(SolveError::Unstable { fraction, .. }) => {
                assert!((fraction - expected).abs() < 1e-4, "{load}: at {fraction}")
            }
            other => panic!("{load}: expected a limit point, got {other:?}"),
        }
    }
}

/// A solve that cannot be finished within the budget says so, with the fraction reached,
/// and never spends more than the budget.
#[test]
fn exhausted_budget_is_a_typed_error() {
    let budget = EffortBudget {
        continuation_steps: 5,
        ..EffortBudget::default()
    };
    let solver = elastica().with_budget(budget);
    let load = Load::new(0.0, 1e6, 0.0);
    let err = solver.solve(load).unwrap_err();
    match &err {
        SolveError::EffortExceeded {
            load: l,
            fraction,
            steps,
            shots,
            ..
        } => {
            assert_eq!(*l, load);
            assert!(*fraction > 0.0 && *fraction < 1e-3, "at {fraction}");
            assert_eq!(*steps, 5);
            assert!(*shots >= 5);
        }
        other => panic!("expected EffortExceeded, got {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.contains("of the load path") && text.contains("budget"),
        "{text}"
    );
    // The fraction reached is printed legibly (four significant digits when tiny).
    let SolveError::EffortExceeded { fraction, .. } = err else {
        unreachable!()
    };
    assert!(text.contains(&format!("{fraction:.3e}")), "{text}");

    // A budget of integration steps stops a solve inside a shot.
    let budget = EffortBudget {
        rk_steps: 20_000,
        ..EffortBudget::default()
    };
    match elastica().with_budget(budget).solve(load) {
        Err(SolveError::EffortExceeded { fraction, .. }) => assert!(fraction < 1.0),
        other => panic!("expected EffortExceeded, got {other:?}"),
    }
    // The budget is per load case: a path of several cases may spend it on each.
    let budget = EffortBudget {
        continuation_steps: 30,
        ..EffortBudget::default()
    };
    let path = elastica()
        .with_budget(budget)
        .solve_path(Load::new(0.0, 1e5, 0.0), 4)
        .unwrap();
    assert_eq!(path.len(), 4);
}

/// With the default budget a load beyond reach (alpha_y = 1e9, a boundary layer of 3e-5 L)
/// ends in an error within the budget, instead of running for ever.
#[test]
fn load_beyond_reach_ends_within_the_default_budget() {
    let solver = elastica();
    let budget = solver.budget;
    match solver.solve(Load::new(0.0, 1e9, 0.0)) {
        Err(SolveError::EffortExceeded {
            steps,
            shots,
            rk_steps,
            fraction,
            ..
        }) => {
            assert!(steps <= budget.continuation_steps && shots <= budget.shots);
            assert!(rk_steps <= budget.rk_steps);
            assert!(fraction > 0.0 && fraction < 1.0);
        }
        Err(SolveError::NoConvergence { .. }) => {}
        other => panic!("expected the budget to run out, got {other:?}"),
    }
    // A moment of 1000 coils the beam 160 times: one radian per continuation step is too
    // slow, and the solver says so.
    match solver.solve(Load::new(0.0, 0.0, 1e3)) {
        Err(SolveError::EffortExceeded { fraction, .. }) => assert!(fraction > 0.0),
        other => panic!("expected the budget to run out, got {other:?}"),
    }
}

/// A token cancelled from another thread stops a long path solve.
#[test]
fn cancel_stops_a_long_solve() {
    let solver = elastica();
    let token = CancelToken::new();
    let remote = token.clone();
    let canceller = thread::spawn(move || {
        thread::sleep(Duration::from_millis(5));
        remote.cancel();
    });
    // Dozens of huge-load cases: seconds of work.
    let result = solver.solve_path_cancellable(Load::new(0.0, 1e8, 0.0), 40, &token);
    canceller.join().unwrap();
    match result {
        Err(SolveError::Cancelled { fraction, .. }) => assert!((0.0..1.0).contains(&fraction)),
        other => panic!("expected Cancelled, got {:?}", other.map(|v| v.len())),
    }
    // A token cancelled beforehand stops the solve before any work.
    match solver.solve_cancellable(Load::new(0.0, 3.0, 0.0), &token) {
        Err(SolveError::Cancelled { fraction, .. }) => assert_eq!(fraction, 0.0),
        other => panic!("expected Cancelled, got {other:?}"),
    }
    // A live token changes nothing.
    let live = CancelToken::new();
    let load = Load::new(1.0, 4.0, -2.0);
    assert_eq!(
        solver.solve_cancellable(load, &live).unwrap(),
        solver.solve(load).unwrap()
    );
}
