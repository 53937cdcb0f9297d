//! Known answers for the truth's modes (DESIGN §10): each frequency equation is solved here
//! by scanning for sign changes and bisecting, independently of the Ritz method in
//! `prbfit::beam::modes`.
//!
//! Tolerances: the claim is 1e-6 relative on the first three frequencies. The method
//! converges exponentially in its degree (1e-9 at the default degree on every case here,
//! measured by raising the degree) and the equilibrium is resampled to 1e-10, so the tests
//! hold the claim itself, 1e-6, except where they say otherwise.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use nalgebra::{Matrix4, SymmetricEigen};
use prbfit::beam::modes::{
    beam_modes, generalized_lowest, path_modes, unloaded_modes, FlexureModel, FrequencyScale,
    ModeSettings, TipBody,
};
use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, SolveError};
use prbfit::fit::CancelToken;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The first `count` roots of `f` on `(lo, hi)`: sign changes on a fine grid, bisected.
fn roots(f: impl Fn(f64) -> f64, lo: f64, hi: f64, count: usize) -> Vec<f64> {
    let steps = 4000;
    let h = (hi - lo) / steps as f64;
    let mut out = Vec::new();
    let mut a = lo;
    let mut fa = f(a);
    for k in 1..=steps {
        let b = lo + h * k as f64;
        let fb = f(b);
        if fa == 0.0 || fa.signum() != fb.signum() {
            let (mut x0, mut x1, mut f0) = (a, b, fa);
            for _ in 0..200 {
                let m = 0.5 * (x0 + x1);
                let fm = f(m);
                if fm.signum() == f0.signum() {
                    x0 = m;
                    f0 = fm;
                } else {
                    x1 = m;
                }
            }
            out.push(0.5 * (x0 + x1));
            if out.len() == count {
                return out;
            }
        }
        a = b;
        fa = fb;
    }
    panic!("only {} roots found below {hi}", out.len());
}

/// The Euler-Bernoulli beam-column's frequency determinant: a clamped beam (`L = E I =
/// rho A = 1`) under an axial dead tension `p` (negative: compression), with a tip body of
/// mass `mu` and rotary inertia `j`. `v'''' - p v'' - W^2 v = 0`, with
/// `v = A cosh(a s) + B sinh(a s) + C cos(b s) + D sin(b s)`, `a^2 - b^2 = p`,
/// `a^2 b^2 = W^2`; `v(0) = v'(0) = 0`; at the tip `v'' = j W^2 v'` and
/// `-v''' + p v' = mu W^2 v`.
fn beam_column(w: f64, p: f64, mu: f64, j: f64) -> f64 {
    let root = (p * p + 4.0 * w * w).sqrt();
    let a = ((p + root) / 2.0).sqrt();
    let b = ((-p + root) / 2.0).sqrt();
    // C = -A, D = -(a / b) B: columns for A and B of v, v', v'', v''' at s = 1.
    let (ch, sh, c, s) = (a.cosh(), a.sinh(), b.cos(), b.sin());
    let col_a = [
        ch - c,
        a * sh + b * s,
        a * a * ch + b * b * c,
        a.powi(3) * sh - b.powi(3) * s,
    ];
    let r = a / b;
    let col_b = [
        sh - r * s,
        a * ch - r * b * c,
        a * a * sh + r * b * b * s,
        a.powi(3) * ch + r * b.powi(3) * c,
    ];
    let row = |v: &[f64; 4]| {
        (
            v[2] - j * w * w * v[1],
            -v[3] + p * v[1] - mu * w * w * v[0],
        )
    };
    let (a1, a2) = row(&col_a);
    let (b1, b2) = row(&col_b);
    (a1 * b2 - a2 * b1) / (1.0 + a.cosh().powi(2))
}

fn settings() -> ModeSettings {
    ModeSettings::frequencies(3)
}

fn elastica() -> BeamModel {
    BeamModel::elastica()
}

#[test]
fn the_uniform_cantilever_rings_at_the_classic_frequencies() {
    let exact = roots(|w| beam_column(w, 0.0, 0.0, 0.0), 1.0, 70.0, 3);
    // The published six digits.
    for (w, published) in exact.iter().zip([3.516015, 22.034492, 61.697214]) {
        assert!((w - published).abs() < 1e-6, "{w} vs {published}");
    }
    let modes = unloaded_modes(&elastica(), TipBody::NONE, &settings()).unwrap();
    for (w, e) in modes.omega.iter().zip(&exact) {
        assert!(rel(*w, *e) < 1e-8, "{w} vs {e}: {:e}", rel(*w, *e));
    }
}

#[test]
fn a_tip_body_lowers_the_frequencies_as_its_frequency_equation_says() {
    for (mu, j) in [(0.5, 0.0), (2.0, 0.0), (1.0, 0.05), (0.0, 0.2)] {
        let exact = roots(|w| beam_column(w, 0.0, mu, j), 0.3, 80.0, 3);
        let tip = TipBody::new(mu, j).unwrap();
        let modes = unloaded_modes(&elastica(), tip, &settings()).unwrap();
        for (w, e) in modes.omega.iter().zip(&exact) {
            assert!(rel(*w, *e) < 1e-6, "mu {mu} j {j}: {w} vs {e}");
        }
    }
}

#[test]
fn axial_tension_and_compression_follow_the_beam_column_equation() {
    for p in [10.0, 2.0, -1.0, -2.2, -2.45] {
        let exact = roots(|w| beam_column(w, p, 0.0, 0.0), 0.05, 80.0, 3);
        let modes = beam_modes(
            &elastica(),
            TipBody::NONE,
            Load::new(p, 0.0, 0.0),
            0.0,
            &settings(),
        )
        .unwrap();
        for (w, e) in modes.omega.iter().zip(&exact) {
            assert!(rel(*w, *e) < 1e-6, "p {p}: {w} vs {e}");
        }
    }
    // With a tip mass too.
    let exact = roots(|w| beam_column(w, -1.5, 0.7, 0.01), 0.05, 80.0, 3);
    let tip = TipBody::new(0.7, 0.01).unwrap();
    let modes = beam_modes(
        &elastica(),
        tip,
        Load::new(-1.5, 0.0, 0.0),
        0.0,
        &settings(),
    )
    .unwrap();
    for (w, e) in modes.omega.iter().zip(&exact) {
        assert!(rel(*w, *e) < 1e-6, "{w} vs {e}");
    }
}

/// Timoshenko's clamped-free beam (`E I = rho A = 1`, shear stiffness `k G A = 1 / c_s`,
/// rotary inertia `rho I = r`): the state `(v, theta, theta', gamma)` obeys
/// `v' = theta + gamma`, `theta'' = -(gamma / c_s + r W^2 theta)`,
/// `gamma' = -c_s W^2 v`; from `v = theta = 0` at the clamp, the free tip needs
/// `theta' = gamma = 0`: the determinant of the transfer matrix's lower right block.
fn timoshenko(w: f64, c_s: f64, r: f64) -> f64 {
    let w2 = w * w;
    #[rustfmt::skip]
    let a = Matrix4::new(
        0.0, 1.0, 0.0, 1.0,
        0.0, 0.0, 1.0, 0.0,
        0.0, -r * w2, 0.0, -1.0 / c_s,
        -c_s * w2, 0.0, 0.0, 0.0,
    );
    let t = a.exp();
    t[(2, 2)] * t[(3, 3)] - t[(2, 3)] * t[(3, 2)]
}

#[test]
fn a_stubby_beam_rings_as_timoshenkos_beam() {
    for slenderness in [3.0, 6.0, 20.0] {
        let model = BeamModel::new(
            slenderness,
            0.3,
            None,
            Effects {
                shear: true,
                ..Effects::NONE
            },
        )
        .unwrap();
        let (c_s, r) = (model.shear_compliance(), model.axial_compliance());
        let exact = roots(|w| timoshenko(w, c_s, r), 0.5, 70.0, 3);
        let modes = unloaded_modes(&model, TipBody::NONE, &settings()).unwrap();
        for (w, e) in modes.omega.iter().zip(&exact) {
            assert!(rel(*w, *e) < 1e-6, "L/t {slenderness}: {w} vs {e}");
        }
        // Shear and rotary inertia lower every frequency below Euler-Bernoulli's.
        let eb = unloaded_modes(&elastica(), TipBody::NONE, &settings()).unwrap();
        assert!(modes.omega[0] < eb.omega[0]);
    }
}

#[test]
fn extension_adds_the_axial_modes() {
    // A stubby beam: the first axial mode, (pi / 2) sqrt(E A / (rho A)) in units of the
    // bending scale, i.e. (pi / 2) sqrt(12) L/t0, falls among the bending modes.
    let slenderness = 4.0;
    let model = BeamModel::new(
        slenderness,
        0.3,
        None,
        Effects {
            extension: true,
            ..Effects::NONE
        },
    )
    .unwrap();
    let axial = std::f64::consts::FRAC_PI_2 * 12f64.sqrt() * slenderness;
    let modes = unloaded_modes(&model, TipBody::NONE, &ModeSettings::frequencies(4)).unwrap();
    let bending = unloaded_modes(&elastica(), TipBody::NONE, &settings()).unwrap();
    // The bending modes are Euler-Bernoulli's (shear off), the axial one in between.
    let mut expected = bending.omega.clone();
    expected.push(axial);
    expected.sort_by(f64::total_cmp);
    for (w, e) in modes.omega.iter().zip(&expected) {
        assert!(rel(*w, *e) < 1e-6, "{w} vs {e}");
    }
}

#[test]
fn the_first_frequency_vanishes_where_the_statics_find_buckling() {
    // The statics, pushed past Euler's load, stop at their critical point.
    let solver = BeamSolver::new(elastica(), Default::default()).unwrap();
    let end = -3.0;
    let fraction = match solver.solve(Load::new(end, 0.0, 0.0)) {
        Err(SolveError::Unstable { fraction, .. }) => fraction,
        other => panic!("expected the statics to find buckling, got {other:?}"),
    };
    let statics = -end * fraction;
    // Where the modes' first omega^2 crosses zero, by bisection on the compression.
    let first = |p: f64| {
        beam_modes(
            &elastica(),
            TipBody::NONE,
            Load::new(-p, 0.0, 0.0),
            0.0,
            &settings(),
        )
        .unwrap()
        .omega[0]
    };
    let (mut lo, mut hi) = (2.0, 3.0);
    assert!(first(lo) > 0.0 && first(hi) < 0.0);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if first(m) > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    let euler = std::f64::consts::PI.powi(2) / 4.0;
    assert!(rel(lo, euler) < 1e-8, "{lo} vs {euler}");
    // The statics report the last stable fraction, within about twice their smallest
    // continuation step (1e-7 of the path) below the critical point.
    assert!(
        statics <= lo && lo - statics < 1e-6 * -end,
        "{statics} vs {lo}"
    );
    // And the first frequency falls like the square root of the distance to it.
    let near = first(euler * (1.0 - 1e-4));
    assert!(near > 0.0 && near < 0.1, "{near}");
}

#[test]
fn every_case_of_a_path_has_its_modes_and_a_compression_lowers_them() {
    let solver = BeamSolver::new(elastica(), Default::default()).unwrap();
    let cases = path_modes(
        &solver,
        TipBody::NONE,
        Load::new(-2.0, 0.2, 0.0),
        4,
        &settings(),
    )
    .unwrap();
    // The cases at 1/4 .. 4/4 of the load, each below the unloaded beam and the last.
    assert_eq!(cases.len(), 4);
    let unloaded = unloaded_modes(&elastica(), TipBody::NONE, &settings()).unwrap();
    assert!(cases[0].omega[0] < unloaded.omega[0]);
    for pair in cases.windows(2) {
        assert!(pair[1].omega[0] < pair[0].omega[0]);
    }
}

#[test]
fn a_load_past_buckling_gets_the_statics_message() {
    let solver = BeamSolver::new(elastica(), Default::default()).unwrap();
    let err = path_modes(
        &solver,
        TipBody::NONE,
        Load::new(-3.0, 0.0, 0.0),
        3,
        &settings(),
    )
    .unwrap_err();
    let statics = solver.solve_path(Load::new(-3.0, 0.0, 0.0), 3).unwrap_err();
    assert_eq!(err.to_string(), statics.to_string());
}

#[test]
fn the_mass_matrix_is_symmetric_positive_definite() {
    let loads = [
        Load::new(0.0, 0.0, 0.0),
        Load::new(3.0, -8.0, 1.0),
        Load::new(-1.0, 2.0, -2.0),
    ];
    for effects in [
        Effects::NONE,
        Effects::ALL,
        Effects {
            shear: true,
            ..Effects::NONE
        },
    ] {
        let model = BeamModel::new(20.0, 0.3, None, effects).unwrap();
        let solver = BeamSolver::new(model, Default::default()).unwrap();
        for load in loads {
            let sol = solver.solve(load).unwrap();
            let flexure = FlexureModel::new(&model, load, sol.root_moment, None).unwrap();
            let m = flexure.mass_with_tip(TipBody::new(0.3, 0.01).unwrap());
            let asym = (&m - m.transpose()).abs().max();
            assert!(asym <= 1e-14 * m.abs().max(), "{effects}: {asym:e}");
            let eig = SymmetricEigen::new(m.clone()).eigenvalues;
            assert!(eig.min() > 0.0, "{effects} {load:?}: {}", eig.min());
            // The stiffness is symmetric and, at a stable equilibrium, positive definite.
            let k = flexure.stiffness();
            assert!((k - k.transpose()).abs().max() <= 1e-12 * k.abs().max());
            assert!(k.clone().cholesky().is_some());
        }
    }
}

#[test]
fn frequencies_do_not_depend_on_the_beams_si_scale() {
    // Omega is the same for every beam of the same shape; omega scales as t / L^2
    // sqrt(E / rho). Two beams, 1000 times apart in size and of different materials, with
    // tip bodies in proportion.
    let model = BeamModel::new(50.0, 0.3, None, Effects::ALL).unwrap();
    let (e1, rho1, l1, w1, t1) = (200e9, 7850.0, 0.1, 0.01, 0.002);
    let k = 1e-3;
    let (e2, rho2, l2, w2, t2) = (2e9, 1200.0, l1 * k, w1 * k, t1 * k);
    let tip1 = TipBody::from_si(0.05, 1e-5, rho1, w1, t1, l1).unwrap();
    let m_ratio = rho2 / rho1 * k.powi(3);
    let tip2 = TipBody::from_si(0.05 * m_ratio, 1e-5 * m_ratio * k * k, rho2, w2, t2, l2).unwrap();
    assert!(rel(tip1.mass, tip2.mass) < 1e-12 && rel(tip1.inertia, tip2.inertia) < 1e-12);
    let a = unloaded_modes(&model, tip1, &settings()).unwrap();
    let b = unloaded_modes(&model, tip2, &settings()).unwrap();
    // The same numbers up to the round-off of the SI ratios.
    for (x, y) in a.omega.iter().zip(&b.omega) {
        assert!(rel(*x, *y) < 1e-12);
    }
    let s1 = FrequencyScale::rectangle(e1, rho1, l1, t1).unwrap();
    let s2 = FrequencyScale::rectangle(e2, rho2, l2, t2).unwrap();
    let ratio = (e2 / rho2 / (e1 / rho1)).sqrt() * (t2 / t1) / (l2 / l1).powi(2);
    for (h1, h2) in a.hz(&s1).iter().zip(b.hz(&s2)) {
        assert!(rel(h2 / h1, ratio) < 1e-12);
    }
    // The steel cantilever's first frequency by hand: 3.516 / (2 pi) sqrt(E I / (rho A L^4)).
    let by_hand = a.omega[0] / (2.0 * std::f64::consts::PI)
        * (e1 * w1 * t1.powi(3) / 12.0 / (rho1 * w1 * t1 * l1.powi(4))).sqrt();
    assert!(rel(a.hz(&s1)[0], by_hand) < 1e-12);
}

#[test]
fn mode_shapes_are_normalised_and_the_first_is_the_cantilevers() {
    let modes = unloaded_modes(&elastica(), TipBody::NONE, &ModeSettings::default()).unwrap();
    assert_eq!(modes.shapes.len(), 3);
    // The frequencies alone (no shapes: no eigenvectors computed) are the same numbers.
    let alone = unloaded_modes(&elastica(), TipBody::NONE, &settings()).unwrap();
    assert!(alone.shapes.is_empty());
    for (a, b) in alone.omega.iter().zip(&modes.omega) {
        assert!(rel(*a, *b) < 1e-13, "{a} vs {b}");
    }
    // The first mode of the clamped-free beam: (cosh - cos) - s (sinh - sin), s the ratio
    // (cosh b + cos b) / (sinh b + sin b), normalised at the tip.
    let b = modes.omega[0].sqrt();
    let sigma = (b.cosh() + b.cos()) / (b.sinh() + b.sin());
    let phi = |x: f64| (b * x).cosh() - (b * x).cos() - sigma * ((b * x).sinh() - (b * x).sin());
    let first = &modes.shapes[0];
    for p in &first.points {
        assert!((p.dy - phi(p.s) / phi(1.0)).abs() < 1e-8, "s {}", p.s);
        assert!(p.dx.abs() < 1e-12 && p.y.abs() < 1e-12 && (p.x - p.s).abs() < 1e-12);
    }
    for shape in &modes.shapes {
        let largest = shape
            .points
            .iter()
            .fold(0.0f64, |a, p| a.max(p.dx.hypot(p.dy)));
        assert!((largest - 1.0).abs() < 1e-12);
    }
}

#[test]
fn bad_input_is_refused() {
    assert!(TipBody::new(-1.0, 0.0).is_err());
    assert!(TipBody::new(0.0, f64::NAN).is_err());
    assert!(TipBody::from_si(1.0, 0.0, 0.0, 0.01, 0.001, 0.1).is_err());
    assert!(FrequencyScale::rectangle(1e9, -1.0, 0.1, 0.001).is_err());
    let none = ModeSettings::frequencies(0);
    assert!(unloaded_modes(&elastica(), TipBody::NONE, &none).is_err());
    assert!(beam_modes(
        &elastica(),
        TipBody::NONE,
        Load::new(f64::NAN, 0.0, 0.0),
        0.0,
        &settings()
    )
    .is_err());
}

#[test]
fn the_block_method_agrees_with_the_dense_eigenproblem() {
    // 3 fields of 30 coefficients: past the size where the block (subspace) iteration
    // takes over. The dense reference: eigenvalues of L^-1 K L^-T with M = L L^T.
    let model = BeamModel::new(8.0, 0.3, None, Effects::ALL).unwrap();
    let load = Load::new(4.0, -6.0, 0.5);
    let solver = BeamSolver::new(model, Default::default()).unwrap();
    let m0 = solver.solve(load).unwrap().root_moment;
    let flexure = FlexureModel::new(&model, load, m0, Some(30)).unwrap();
    assert_eq!(flexure.dofs(), 90);
    let m = flexure.mass_with_tip(TipBody::new(0.2, 0.01).unwrap());
    let (omega_sq, vectors) = generalized_lowest(flexure.stiffness(), &m, 4).unwrap();
    let l = m.clone().cholesky().unwrap().l();
    let x = l.solve_lower_triangular(flexure.stiffness()).unwrap();
    let c = l.solve_lower_triangular(&x.transpose()).unwrap();
    let mut dense: Vec<f64> = SymmetricEigen::new((&c + c.transpose()) * 0.5)
        .eigenvalues
        .iter()
        .copied()
        .collect();
    dense.sort_by(f64::total_cmp);
    for (a, b) in omega_sq.iter().zip(&dense) {
        // The dense route through M loses digits to K's axial and shear stiffness (its
        // largest eigenvalue over the smallest, ~1e5 here, times round-off).
        assert!(rel(*a, *b) < 1e-9, "{a} vs {b}");
    }
    // Unit modal mass, M-orthogonal.
    for (i, u) in vectors.iter().enumerate() {
        for (j, v) in vectors.iter().enumerate() {
            let muv = (u.transpose() * &m * v)[(0, 0)];
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((muv - want).abs() < 1e-9, "{i} {j}: {muv}");
        }
    }
}

#[test]
fn with_shear_off_a_stubby_beam_has_no_rotary_inertia() {
    // L/t0 = 3, inextensible and shear-rigid: the classic Euler-Bernoulli beam, whose
    // frequencies do not depend on the slenderness. Rotary inertia (rho I = r rho A L^2,
    // r = 1 / (12 (L/t0)^2)) would lower Omega_k by about r int phi'^2 / (2 int phi^2)
    // (Rayleigh's quotient with the Euler-Bernoulli mode phi): measured here, so the test
    // shows the 1e-8 agreement could not hold with it.
    let slenderness = 3.0;
    let model = BeamModel::new(slenderness, 0.3, None, Effects::NONE).unwrap();
    let exact = roots(|w| beam_column(w, 0.0, 0.0, 0.0), 1.0, 70.0, 3);
    let modes = unloaded_modes(&model, TipBody::NONE, &settings()).unwrap();
    let r = model.axial_compliance();
    assert!((r - 1.0 / (12.0 * slenderness * slenderness)).abs() < 1e-15);
    for (w, e) in modes.omega.iter().zip(&exact) {
        assert!(rel(*w, *e) < 1e-8, "{w} vs {e}");
        // The shift rotary inertia would make, by Simpson's rule on the mode's shape.
        let b = e.sqrt();
        let sigma = (b.cosh() + b.cos()) / (b.sinh() + b.sin());
        let phi =
            |x: f64| (b * x).cosh() - (b * x).cos() - sigma * ((b * x).sinh() - (b * x).sin());
        let dphi = |x: f64| {
            b * ((b * x).sinh() + (b * x).sin() - sigma * ((b * x).cosh() - (b * x).cos()))
        };
        let n = 2000;
        let simpson = |f: &dyn Fn(f64) -> f64| {
            let h = 1.0 / n as f64;
            (0..=n)
                .map(|i| {
                    let c = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    c * f(i as f64 * h)
                })
                .sum::<f64>()
                * h
                / 3.0
        };
        let shift = r * simpson(&|x| dphi(x).powi(2)) / (2.0 * simpson(&|x| phi(x).powi(2)));
        assert!(shift > 1e-3, "rotary inertia's shift {shift:e}");
    }
}

mod properties {
    use super::*;
    use prbfit::scene::{BeamSpec, EffectsChoice};
    use proptest::prelude::*;

    fn effects() -> impl Strategy<Value = Effects> {
        (any::<bool>(), any::<bool>()).prop_map(|(shear, extension)| Effects {
            shear,
            extension,
            ..Effects::NONE
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        /// The mass matrix (distributed mass and a tip body) is symmetric positive definite
        /// about any equilibrium, and the stiffness symmetric, positive definite at a stable
        /// one; the frequencies are then real and positive.
        #[test]
        fn the_mass_matrix_is_spd_about_any_equilibrium(
            slenderness in 3.0..200.0f64, effects in effects(),
            ax in -1.5..20.0f64, ay in -10.0..10.0f64, beta in -2.0..2.0f64,
            mu in 0.0..3.0f64, j in 0.0..0.5f64,
        ) {
            let model = BeamModel::new(slenderness, 0.3, None, effects).unwrap();
            let solver = BeamSolver::new(model, Default::default()).unwrap();
            let load = Load::new(ax, ay, beta);
            let Ok(sol) = solver.solve(load) else {
                // A load the statics refuse (a critical point on the way) has no modes.
                return Ok(());
            };
            let flexure = FlexureModel::new(&model, load, sol.root_moment, None).unwrap();
            let m = flexure.mass_with_tip(TipBody::new(mu, j).unwrap());
            let asym = (&m - m.transpose()).abs().max();
            prop_assert!(asym <= 1e-14 * m.abs().max(), "asymmetry {asym:e}");
            let eig = SymmetricEigen::new(m.clone()).eigenvalues;
            prop_assert!(eig.min() > 0.0, "{}", eig.min());
            let k = flexure.stiffness();
            prop_assert!((k - k.transpose()).abs().max() <= 1e-12 * k.abs().max());
            let modes = solution_modes_of(&model, TipBody::new(mu, j).unwrap(), load, sol.root_moment);
            prop_assert!(modes.iter().all(|w| *w > 0.0), "{modes:?}");
        }

        /// Omega depends on the beam's shape only: a beam scaled by `k` in size, of another
        /// material, with its tip body scaled in proportion (mass as rho k^3, inertia as
        /// rho k^5), has the same Omega, and its Hz scale as `t / L^2 sqrt(E / rho)`.
        #[test]
        fn frequencies_are_invariant_to_the_si_scale(
            log_k in -3.0..3.0f64, e_ratio in 0.01..100.0f64, rho_ratio in 0.1..10.0f64,
            slenderness in 5.0..300.0f64, effects in effects(),
            mu in 0.0..2.0f64, j in 0.0..0.2f64,
        ) {
            let k = 10f64.powf(log_k);
            let spec = |scale: f64, e: f64| BeamSpec {
                length: 0.1 * scale,
                width: 0.02 * scale,
                thickness: 0.1 / slenderness * scale,
                youngs_modulus: e,
                poisson_ratio: 0.3,
                shear_coefficient: None,
                density: None,
                allowable_stress: None,
                effects: EffectsChoice::Fixed(effects),
            };
            let (a, b) = (spec(1.0, 70e9), spec(k, 70e9 * e_ratio));
            let (rho_a, rho_b) = (2700.0, 2700.0 * rho_ratio);
            // The tip body: mu times the beam's mass, j times its mass times L^2.
            let body = |s: &BeamSpec, rho: f64| {
                let m = rho * s.area() * s.length;
                TipBody::from_si(mu * m, j * m * s.length.powi(2), rho, s.width, s.thickness, s.length)
                    .unwrap()
            };
            let (ta, tb) = (body(&a, rho_a), body(&b, rho_b));
            let wa = unloaded_modes(&a.model(), ta, &settings()).unwrap();
            let wb = unloaded_modes(&b.model(), tb, &settings()).unwrap();
            // The same numbers up to the round-off of the SI ratios (L/t0, the body's).
            for (x, y) in wa.omega.iter().zip(&wb.omega) {
                prop_assert!(rel(*x, *y) < 1e-9, "{x} vs {y}");
            }
            let sa = FrequencyScale::rectangle(a.youngs_modulus, rho_a, a.length, a.thickness).unwrap();
            let sb = FrequencyScale::rectangle(b.youngs_modulus, rho_b, b.length, b.thickness).unwrap();
            let ratio = (e_ratio / rho_ratio).sqrt() / k;
            for (ha, hb) in wa.hz(&sa).iter().zip(wb.hz(&sb)) {
                prop_assert!(rel(hb / ha, ratio) < 1e-9);
            }
        }
    }

    fn solution_modes_of(model: &BeamModel, tip: TipBody, load: Load, m0: f64) -> Vec<f64> {
        beam_modes(model, tip, load, m0, &settings()).unwrap().omega
    }
}

/// The scene's modes (`Study::modes`, what `prbfit modes` prints) take a cantilever as the
/// one-flexure mechanism, its tip body the stage's mass and inertia about the tip: the
/// same frequencies as the beam's own modes with the tip body, and for a PRB model the
/// chain's own (`PrbSolver::modes`), at rest and under a load.
#[test]
fn the_scenes_modes_are_the_beams_and_the_chains() {
    use prbfit::prb::{PrbSolver, TipBody as PrbTip};
    use prbfit::scene::Scene;
    use prbfit::study::modes::Equilibria;
    use prbfit::study::{Sampling, Study};
    let scene = Scene::from_toml_str(
        "name = \"c\"\n[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\n\
         youngs_modulus = 200e9\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         effects = [\"shear\", \"extension\", \"poisson\"]\n\
         [tip]\nmass = 0.002\ninertia = 1e-8\n[[loads]]\nalpha_y = 2.0\nsteps = 2\n",
        "test",
    )
    .unwrap();
    let study = Study::new(&scene, Sampling::Every(Default::default())).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let model = scene.beam.model();
    let tip = TipBody::from_si(0.002, 1e-8, 7850.0, 0.01, 0.0005, 0.05).unwrap();
    let chain = PrbSolver::new(&su, model.axial_compliance());
    let prb_tip = PrbTip {
        mass: tip.mass,
        inertia: tip.inertia,
    };
    for (at, load) in [
        (Equilibria::Unloaded, Load::new(0.0, 0.0, 0.0)),
        (
            Equilibria::Load(Load::new(-1.0, 0.5, 0.2)),
            Load::new(-1.0, 0.5, 0.2),
        ),
    ] {
        let found = study
            .modes(std::slice::from_ref(&su), at, 3, &CancelToken::new())
            .unwrap();
        assert_eq!(found.len(), 1);
        let solver = BeamSolver::new(model, Default::default()).unwrap();
        let m0 = solver.solve(load).unwrap().root_moment;
        let beam = beam_modes(&model, tip, load, m0, &settings()).unwrap();
        for (a, b) in found[0].beam.omega.iter().zip(&beam.omega) {
            // Two discretisations of one problem, each good to 1e-9 (the mechanism adds
            // the stage's coordinates and eliminates them exactly).
            assert!(rel(*a, *b) < 1e-8, "{at:?}: {a} vs {b}");
        }
        let q = chain.solve(load).unwrap().q;
        let own = chain.modes(load, &q, prb_tip).unwrap();
        let via = found[0].models[0].as_ref().unwrap();
        for (a, b) in via.omega.iter().zip(&own) {
            // The PRB statics' Newton tolerance (1e-8 and 1e-10) on the equilibrium.
            assert!(rel(*a, *b) < 1e-7, "{at:?}: {a} vs {b}");
        }
        for ((e, p), b) in via
            .freq_err
            .iter()
            .zip(&via.omega)
            .zip(&found[0].beam.omega)
        {
            assert!((e - (p / b - 1.0)).abs() < 1e-12);
        }
    }
}
