//! Known answers for the beam's largest fibre stress (DESIGN §11):
//! `sigma / E = c_e |N| / p^2 + |M| / (2 (L/t0) p^3)`.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use prbfit::beam::{BeamModel, BeamSolution, BeamSolver, Effects, Load, Resolution};

fn solver(model: BeamModel, tol: f64, points: usize) -> BeamSolver {
    BeamSolver::new(
        model,
        Resolution {
            tol,
            shape_points: points,
        },
    )
    .unwrap()
}

fn stress(sol: &BeamSolution) -> (f64, f64) {
    let s = sol.stress.expect("a solved beam has a stress");
    (s.max, s.at)
}

/// A pure moment bends the beam into an arc with `M = beta` everywhere and no axial force:
/// `sigma = beta E t0 / (2 L)` at every section, whatever the effects (N = 0, so no shrink).
#[test]
fn pure_moment_is_beta_e_t0_over_2l_everywhere() {
    for effects in [
        Effects::NONE,
        Effects::ALL,
        Effects::ALL.with_plane_strain(true),
    ] {
        let model = BeamModel::new(50.0, 0.3, None, effects).unwrap();
        for beta in [0.01, 1.0, -3.0, 6.0] {
            let sol = solver(model, 1e-10, 41)
                .solve(Load::new(0.0, 0.0, beta))
                .unwrap();
            let (max, at) = stress(&sol);
            let exact = beta.abs() / (2.0 * 50.0);
            // The moment at each point is the statics of the shape the integrator sampled
            // (positions good to ~1e-9 L), times |load| <= 6: 1e-8 relative is generous.
            let err = (max - exact).abs() / exact;
            println!("pure moment {effects} beta {beta}: sigma/E {max:.9e}, rel. err {err:.1e}");
            assert!(err < 1e-8, "{effects} beta {beta}: {max} vs {exact}");
            assert!((0.0..=1.0).contains(&at));
        }
    }
}

/// A small transverse force `F` makes the root moment `F L` (linear theory; the tip's
/// shortening `a = 1 - alpha^2 / 15 + ...` is the relative error), the largest along the beam,
/// at the clamp: `sigma = F L t0 / (2 I0)`, i.e. `alpha_y / (2 L/t0)` in units of E.
#[test]
fn small_transverse_force_gives_the_root_moment_f_l() {
    for effects in [Effects::NONE, Effects::ALL] {
        let model = BeamModel::new(100.0, 0.3, None, effects).unwrap();
        for alpha_y in [1e-4, -1e-3] {
            let sol = solver(model, 1e-12, 41)
                .solve(Load::new(0.0, alpha_y, 0.0))
                .unwrap();
            let (max, at) = stress(&sol);
            let exact = f64::abs(alpha_y) / 200.0;
            let err = (max - exact).abs() / exact;
            println!("transverse {effects} alpha_y {alpha_y}: rel. err {err:.1e}, at {at}");
            // Linear theory's error is alpha^2 / 15 <= 7e-8; the shear and axial terms of
            // the ALL beam are of order alpha (t0/L)^2 smaller still.
            assert!(err < 2e-7, "{effects} {alpha_y}: {max} vs {exact}");
            assert_eq!(at, 0.0);
        }
    }
}

/// Pure tension: no moment, `sigma = N / A`. Without Poisson `A = A0`, so `sigma / E =
/// c_e alpha_x`; with it the section shrinks to `A0 p^2` and the law `eps p^2 = c_e N`
/// makes `sigma / E = eps`, the strain, exactly (here read from the tip's stretch `a - 1`).
#[test]
fn tension_is_n_over_a() {
    let slender = 20.0;
    let c_e = 1.0 / (12.0 * slender * slender);
    let stretch = BeamModel::new(
        slender,
        0.3,
        None,
        Effects::parse_list("extension").unwrap(),
    )
    .unwrap();
    let alpha_x = 300.0;
    let sol = solver(stretch, 1e-11, 41)
        .solve(Load::new(alpha_x, 0.0, 0.0))
        .unwrap();
    let (max, _) = stress(&sol);
    let err = (max - c_e * alpha_x).abs() / (c_e * alpha_x);
    println!("tension without shrink: rel. err {err:.1e}");
    assert!(err < 1e-12, "{max} vs {}", c_e * alpha_x);

    let shrink = BeamModel::new(slender, 0.45, None, Effects::ALL).unwrap();
    // A large tension (strain ~5 %) so the shrink shows: 1/p^2 ~ 1.05.
    let alpha_x = 0.05 / c_e;
    let sol = solver(shrink, 1e-11, 41)
        .solve(Load::new(alpha_x, 0.0, 0.0))
        .unwrap();
    let (max, _) = stress(&sol);
    let eps = sol.tip.a - 1.0;
    let err = (max - eps).abs() / eps;
    println!("tension with shrink: sigma/E {max:.6e}, eps {eps:.6e}, rel. err {err:.1e}");
    // The tip's stretch is integrated to the tolerance (1e-11 L) over eps ~ 0.05.
    assert!(err < 1e-8, "{max} vs strain {eps}");
    assert!(max > c_e * alpha_x * 1.02, "the shrink raises the stress");
}

/// An interior peak: a compressive force `P` below Euler's load, a transverse force `-f`
/// and a tip moment that opposes it. In linear theory `M'' = -P M`, `M'(0) = f`, so
/// `M = A cos ks + B sin ks` (`k = sqrt P`, `B = f / k`), whose peak `sqrt(A^2 + B^2)` sits
/// at `tan(k s) = B / A`: choosing `A = B / tan(k / 2)` puts it at mid-span, above both
/// ends (`M(0) = M(1) = A`). `sigma = c_e P + |M| / (2 L/t0)` there.
#[test]
fn interior_peak_where_moment_and_force_oppose() {
    let model = BeamModel::elastica();
    let c_e = model.axial_compliance();
    let p = 2.0_f64;
    let k = p.sqrt();
    let f = 1e-4;
    let b = f / k;
    let a = b / (k / 2.0).tan();
    let beta = a * k.cos() + b * k.sin();
    let load = Load::new(-p, -f, beta);
    // Coarse shapes too: the peak is found on the beam, not on the samples.
    for points in [41, 6, 2] {
        let sol = solver(model, 1e-12, points).solve(load).unwrap();
        let (max, at) = stress(&sol);
        let exact = c_e * p + (a * a + b * b).sqrt() / (2.0 * model.slenderness);
        let err = (max - exact).abs() / exact;
        println!("interior peak, {points} points: at {at:.6}, rel. err {err:.1e}");
        // Linear theory leaves relative errors of order psi^2 ~ (1e-4)^2 in the moment;
        // the place is where a flat maximum is, good to the square root of that.
        assert!(err < 1e-7, "{points} points: {max} vs {exact}");
        assert!((at - 0.5).abs() < 1e-4, "{points} points: peak at {at}");
    }
}

/// A large deflection with an interior peak (tip force and an opposing tip moment curling
/// the beam past a quarter turn): the peak found from a 41-point shape matches the largest
/// value on a 20001-point shape computed here from the statics (an independent brute force;
/// its grid misses the peak by `O(h^2)`, h = 5e-5).
#[test]
fn interior_peak_matches_a_brute_force_on_a_fine_shape() {
    let model = BeamModel::elastica();
    let load = Load::new(-1.5, -2.0, 1.5);
    let coarse = solver(model, 1e-11, 41).solve(load).unwrap();
    let fine = solver(model, 1e-11, 20001).solve(load).unwrap();
    let c_e = model.axial_compliance();
    let (mut best, mut best_s) = (0.0_f64, 0.0);
    for q in &fine.shape {
        let m = load.beta + load.alpha_y * (fine.tip.a - q.x) - load.alpha_x * (fine.tip.b - q.y);
        let n = load.alpha_x * q.psi.cos() + load.alpha_y * q.psi.sin();
        let sigma = c_e * n.abs() + m.abs() / (2.0 * model.slenderness);
        if sigma > best {
            (best, best_s) = (sigma, q.s);
        }
    }
    let (max, at) = stress(&coarse);
    let err = (max - best).abs() / best;
    println!("large interior peak: at {at:.6} (brute {best_s:.6}), rel. err {err:.1e}");
    assert!(
        best_s > 0.05 && best_s < 0.95,
        "the test's peak must be inside: {best_s}"
    );
    assert!(err < 1e-8, "{max} vs brute force {best}");
    assert!((at - best_s).abs() < 1e-3, "{at} vs {best_s}");
}

/// The stress scales with the load along a path and is never below the root's.
#[test]
fn path_stress_grows_and_bounds_the_root() {
    let model = BeamModel::new(30.0, 0.3, None, Effects::ALL).unwrap();
    let cases = solver(model, 1e-9, 41)
        .solve_path(Load::new(1.0, 4.0, -1.0), 8)
        .unwrap();
    let mut last = 0.0;
    for c in &cases {
        let (max, at) = stress(c);
        let root = model.fibre_stress(c.load.alpha_x, c.root_moment).unwrap();
        assert!(max >= root * (1.0 - 1e-12), "{max} < root {root}");
        assert!(max > last, "stress grows along the path");
        assert!((0.0..=1.0).contains(&at));
        last = max;
    }
}

/// A solver without shapes (what `solve --scene` uses without `--shape`) returns the same
/// tips, stresses and counts, bit for bit, and no shapes: on the elastica (Taylor shots), a
/// shearing beam (Runge-Kutta shots) and a wide plane-strain strip (each case at its plate
/// fraction from the narrow beam's shape, which it still needs).
#[test]
fn a_solver_without_shapes_keeps_every_other_figure() {
    let shear = Effects {
        shear: true,
        ..Effects::NONE
    };
    let strip = BeamModel::new(100.0, 0.3, None, Effects::NONE.with_plane_strain(true))
        .unwrap()
        .with_width_ratio(20.0);
    for model in [
        BeamModel::elastica(),
        BeamModel::new(8.0, 0.3, None, shear).unwrap(),
        strip,
    ] {
        let with = solver(model, 1e-9, 41);
        let without = with.without_shapes();
        for end in [Load::new(0.0, 5.0, 0.0), Load::new(-1.0, 3.0, 1.0)] {
            let a = with.solve_path(end, 25).unwrap();
            let b = without.solve_path(end, 25).unwrap();
            assert_eq!(a.len(), b.len());
            for (a, b) in a.iter().zip(&b) {
                assert_eq!(a.shape.len(), 41);
                assert!(b.shape.is_empty());
                assert_eq!((a.load, a.tip, a.stress), (b.load, b.tip, b.stress));
                assert_eq!((a.iterations, a.rk_steps), (b.iterations, b.rk_steps));
                assert_eq!(a.root_moment, b.root_moment);
            }
        }
    }
}

/// A wide strip's plane-strain path given its narrow beam's cases (the effects decision's
/// `Effects::ALL` solve) is the path solved alone, bit for bit; cases that are not the path's
/// (another path's, or too few) are ignored, not trusted.
#[test]
fn a_plate_path_on_given_narrow_cases_is_the_path_solved_alone() {
    let all = Effects {
        shear: true,
        extension: true,
        poisson: true,
        plane_strain: false,
    };
    let wide = BeamModel::new(20.0, 0.45, None, all.with_plane_strain(true))
        .unwrap()
        .with_width_ratio(20.0);
    let narrow = BeamModel::new(20.0, 0.45, None, all)
        .unwrap()
        .with_width_ratio(20.0);
    let (wide, narrow) = (solver(wide, 1e-9, 41), solver(narrow, 1e-9, 41));
    let cancel = prbfit::cancel::CancelToken::new();
    let end = Load::new(-1.0, 4.0, 1.0);
    let other = Load::new(0.0, 6.0, 0.0);
    let alone = wide.solve_path(end, 12).unwrap();
    let given = narrow.solve_path(end, 12).unwrap();
    let wrong = narrow.solve_path(other, 12).unwrap();
    for (cases, trusted) in [
        (&given[..], true),
        (&wrong[..], false),
        (&given[..6], false),
    ] {
        let on = wide.solve_path_on_narrow(end, 12, cases, &cancel).unwrap();
        assert_eq!(on.len(), alone.len());
        for (a, b) in on.iter().zip(&alone) {
            assert_eq!(
                (a.tip, a.stress, a.iterations),
                (b.tip, b.stress, b.iterations)
            );
        }
        if !trusted {
            continue;
        }
        // And they differ from the narrow beam's own: plane strain is on.
        assert!(on[11].tip.max_diff(&given[11].tip) > 1e-4);
    }
    // The given cases are used, not solved again: other shapes (moments, from the points'
    // positions) give other plate fractions.
    let mut bent = given.clone();
    for case in &mut bent {
        for p in &mut case.shape {
            p.y *= 0.5;
        }
    }
    let on_bent = wide.solve_path_on_narrow(end, 12, &bent, &cancel).unwrap();
    assert!(on_bent[11].tip.max_diff(&alone[11].tip) > 1e-9);
}
