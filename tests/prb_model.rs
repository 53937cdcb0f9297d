//! PRB matrix and statics: closed forms, the analytic Jacobian, round trips, bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use prbfit::beam::{Load, TipPose};
use prbfit::prb::{
    Column, MatrixError, PrbCase, PrbError, PrbMatrix, PrbRow, PrbSolver, TipBody, WarmStart,
};
use proptest::prelude::*;

/// A random valid matrix: 1 to 5 rows, any mix of L, R, P, RP (at least one joint).
fn matrix() -> impl Strategy<Value = PrbMatrix> {
    proptest::collection::vec((0.05..1.0f64, 0..4u8, 0.5..20.0f64, 0.5..20.0f64), 1..=5)
        .prop_filter_map("needs a joint", |rows| {
            let total: f64 = rows.iter().map(|r| r.0).sum();
            let mut out: Vec<PrbRow> = rows
                .iter()
                .map(|&(g, kind, kt, ke)| PrbRow {
                    gamma: g / total,
                    k_theta: if kind & 1 == 1 { kt } else { f64::INFINITY },
                    k_ex: if kind & 2 == 2 { ke } else { f64::INFINITY },
                    mu: None,
                    free: [kind != 0, true, kt > 10.0, true],
                })
                .collect();
            // Exact unit sum despite round-off in the normalisation.
            let head: f64 = out[..out.len() - 1].iter().map(|r| r.gamma).sum();
            let last = out.len() - 1;
            out[last].gamma = 1.0 - head;
            PrbMatrix::new(out).ok()
        })
}

fn revolute_only() -> impl Strategy<Value = PrbMatrix> {
    matrix()
        .prop_map(|m| {
            let rows = m
                .rows()
                .iter()
                .map(|r| PrbRow {
                    k_ex: f64::INFINITY,
                    ..*r
                })
                .collect::<Vec<_>>();
            rows
        })
        .prop_filter_map("needs a revolute joint", |rows| PrbMatrix::new(rows).ok())
}

/// Slenderness 10: c_e = 1 / 1200.
const C_E: f64 = 1.0 / 1200.0;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The chain's mass matrix (DESIGN §10) is symmetric and positive definite at any
    /// configuration when every segment carries mass (mu = gamma) and the tip a body: every
    /// joint then moves some mass. Checked by Cholesky; and the modes of the unloaded chain
    /// are finite and positive, one per degree of freedom.
    #[test]
    fn mass_matrix_is_symmetric_positive_definite(
        m in matrix(),
        q in proptest::collection::vec(-0.5..0.5f64, 10),
        tip in 0.0..2.0f64,
    ) {
        let s = PrbSolver::new(&m, C_E);
        let n = s.dof_count();
        let body = TipBody { mass: tip, inertia: 0.1 * tip };
        let mass = s.mass_matrix(&q[..n], body);
        for a in 0..n {
            for b in 0..n {
                prop_assert!((mass[a * n + b] - mass[b * n + a]).abs() <= 1e-15 * mass[a * n + a].abs().max(1.0));
            }
        }
        let dense = nalgebra::DMatrix::from_row_slice(n, n, &mass);
        prop_assert!(dense.cholesky().is_some(), "{mass:?}");
        let w = s.modes(Load::new(0.0, 0.0, 0.0), &vec![0.0; n], body).unwrap();
        // One per degree of freedom, except that `linalg::frequencies` leaves out those more
        // than 1000 times the lowest (a soft chain's stiff prismatic joints): what is left out
        // is above every one returned's 1000 times the lowest.
        prop_assert!(!w.is_empty() && w.len() <= n, "{:?}", w);
        prop_assert!(w.iter().all(|w| w.is_finite() && *w > 0.0), "{:?}", w);
        prop_assert!(w.windows(2).all(|p| p[0] <= p[1]), "{:?}", w);
        if w.len() < n {
            prop_assert!(w[w.len() - 1] <= 1000.0 * w[0], "{:?}", w);
        }
    }

    /// Under a pure moment every joint carries beta, so phi = beta sum 1/k_theta: exact for
    /// the circle when the compliances sum to 1, at any beta.
    #[test]
    fn pure_moment_tip_angle_is_exact(m in revolute_only(), beta in -4.0..4.0f64) {
        // Rescale the springs so that sum 1/k_theta = 1.
        let inv: f64 = m.rows().iter().filter(|r| r.has_revolute()).map(|r| 1.0 / r.k_theta).sum();
        let rows: Vec<PrbRow> = m.rows().iter().map(|r| PrbRow { k_theta: r.k_theta * inv, ..*r }).collect();
        let m = PrbMatrix::new(rows).unwrap();
        let sol = PrbSolver::new(&m, C_E).solve(Load::new(0.0, 0.0, beta)).unwrap();
        prop_assert!((sol.tip.phi - beta).abs() < 1e-12, "phi {} vs {beta}", sol.tip.phi);
    }

    /// Small loads: the linear compliance of the chain. Joint i at s_i = sum_{j<i} gamma_j
    /// turns by theta_i = (beta + alpha_y (1 - s_i)) / k_i; the tip rises by
    /// b = sum theta_i (1 - s_i) and turns by sum theta_i; an axial pull stretches each P
    /// segment by c_e alpha_x / k_ex. Nonlinear terms are O(load^2) ~ 1e-12 relative.
    #[test]
    fn small_load_compliance_is_the_closed_form(m in matrix(), ax in -1.0..1.0f64,
                                                ay in -1.0..1.0f64, beta in -1.0..1.0f64) {
        let eps = 1e-6;
        let load = Load::new(ax * eps, ay * eps, beta * eps);
        let sol = PrbSolver::new(&m, C_E).solve(load).unwrap();
        let (mut b, mut phi, mut stretch, mut s) = (0.0, 0.0, 0.0, 0.0);
        for r in m.rows() {
            if r.has_revolute() {
                let theta = (load.beta + load.alpha_y * (1.0 - s)) / r.k_theta;
                b += theta * (1.0 - s);
                phi += theta;
            }
            if r.has_prismatic() {
                stretch += C_E * load.alpha_x / r.k_ex;
            }
            s += r.gamma;
        }
        let scale = eps * 100.0;
        prop_assert!((sol.tip.b - b).abs() < 1e-5 * scale, "b {} vs {b}", sol.tip.b);
        prop_assert!((sol.tip.phi - phi).abs() < 1e-5 * scale, "phi {} vs {phi}", sol.tip.phi);
        prop_assert!((sol.tip.a - 1.0 - stretch).abs() < 1e-5 * scale + 1e-15);
    }

    /// The analytic Jacobian matches central finite differences of the residual.
    #[test]
    fn jacobian_matches_finite_differences(m in matrix(),
                                           q in proptest::collection::vec(-1.0..1.0f64, 10),
                                           ax in -5.0..5.0f64, ay in -5.0..5.0f64, beta in -3.0..3.0f64) {
        let solver = PrbSolver::new(&m, C_E);
        let n = solver.dof_count();
        let q: Vec<f64> = q[..n].iter().map(|v| v * 0.1).collect();
        let load = Load::new(ax, ay, beta);
        let (_, jac) = solver.residual_and_jacobian(load, &q);
        let h = 1e-6;
        for c in 0..n {
            let mut qp = q.clone();
            let mut qm = q.clone();
            qp[c] += h;
            qm[c] -= h;
            let (rp, _) = solver.residual_and_jacobian(load, &qp);
            let (rm, _) = solver.residual_and_jacobian(load, &qm);
            for r in 0..n {
                let fd = (rp[r] - rm[r]) / (2.0 * h);
                let an = jac[r * n + c];
                // Central differences: error h^2 |r'''| ~ 1e-12 * 1e4 (k_ex / c_e) plus
                // round-off |r| eps / h ~ 1e4 * 1e-16 / 1e-6.
                prop_assert!((fd - an).abs() < 1e-5 * (1.0 + an.abs()), "J[{r}][{c}] {an} vs {fd}");
            }
        }
    }

    /// Text, TOML and JSON all give back exactly the same matrix, infinity and flags included.
    #[test]
    fn round_trips_are_exact(m in matrix()) {
        prop_assert_eq!(&PrbMatrix::parse(&m.to_text()).unwrap(), &m);
        let json = serde_json::to_string(&m).unwrap();
        prop_assert_eq!(&serde_json::from_str::<PrbMatrix>(&json).unwrap(), &m);
        #[derive(serde::Serialize, serde::Deserialize)]
        struct Wrapper { prb: PrbMatrix }
        let toml_text = toml::to_string(&Wrapper { prb: m.clone() }).unwrap();
        let back: Wrapper = toml::from_str(&toml_text).unwrap();
        prop_assert_eq!(&back.prb, &m);
    }
}

/// A 1R chain under axial compression buckles at alpha = k / gamma (k theta = P gamma sin
/// theta); the solver stops there and says so.
#[test]
fn one_r_buckles_at_k_over_gamma() {
    let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
    let solver = PrbSolver::new(&m, C_E);
    let critical = 2.2525 / 0.85;
    let below = solver.solve(Load::new(-0.99 * critical, 0.0, 0.0)).unwrap();
    assert!(below.tip.b.abs() < 1e-12 && below.tip.phi.abs() < 1e-12);
    match solver.solve(Load::new(-1.2 * critical, 0.0, 0.0)) {
        Err(prbfit::prb::PrbError::Unstable { fraction, .. }) => {
            assert!((fraction * 1.2 - 1.0).abs() < 1e-4, "at {fraction}")
        }
        other => panic!("expected a critical point, got {other:?}"),
    }
    // Tilted, it buckles sideways and follows the post-buckled branch.
    let tilted = solver.solve(Load::new(-1.2 * critical, 0.01, 0.0)).unwrap();
    assert!(tilted.tip.phi > 0.5, "{:?}", tilted.tip);
}

/// Howell's 1R under a transverse force: k theta = alpha_y (a - x_1) has a one-variable
/// closed form: theta solves k theta = alpha_y gamma cos theta (joint at 0.15, arm 0.85).
#[test]
fn one_r_transverse_force_closed_form() {
    let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
    let solver = PrbSolver::new(&m, C_E);
    for alpha in [0.5, 2.0, 5.0, 10.0] {
        let sol = solver.solve(Load::new(0.0, alpha, 0.0)).unwrap();
        let theta = sol.tip.phi;
        assert!((2.2525 * theta - alpha * 0.85 * theta.cos()).abs() < 1e-12);
        assert!((sol.tip.a - (0.15 + 0.85 * theta.cos())).abs() < 1e-14);
        assert!((sol.tip.b - 0.85 * theta.sin()).abs() < 1e-14);
    }
}

#[test]
fn joint_positions_draw_the_chain() {
    let m = PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
    let solver = PrbSolver::new(&m, C_E);
    let sol = solver.solve(Load::new(0.0, 3.0, 0.0)).unwrap();
    let pts = solver.joint_positions(&sol.q);
    assert_eq!(pts.len(), 5);
    assert_eq!(pts[0], [0.0, 0.0]);
    assert_eq!(pts[1], [0.1, 0.0]);
    assert!((pts[4][0] - sol.tip.a).abs() < 1e-15 && (pts[4][1] - sol.tip.b).abs() < 1e-15);
    // The forward kinematics agree with the equilibrium's tip.
    let tip = solver.tip_pose(&sol.q);
    assert!(tip.max_diff(&sol.tip) < 1e-15);
    let turned = solver.tip_pose(&[0.1, 0.2, 0.3]);
    assert!((turned.phi - 0.6).abs() < 1e-15);
}

#[test]
fn bad_matrices_are_rejected_with_row_and_column() {
    let cases: &[(&str, &str)] = &[
        ("", "row 1: expected 3 entries"),
        (
            "0.5,inf,inf,0.6; 0.5,2,inf,0.6",
            "the mus must sum to 1, they sum to 1.2",
        ),
        (
            "0.5,inf,inf,-0.1; 0.5,2,inf,1.1",
            "row 1, column mu: the segment's mass fraction must be a finite number >= 0, got -0.1",
        ),
        (
            "0.5,inf,inf,0.5; 0.5,2,inf",
            "row 2: every row gives a mu (a fourth entry) or none does",
        ),
        (
            "0.5,inf; 0.5,2,inf",
            "row 1: expected 3 entries (gamma, k_theta, k_ex) or 4 (gamma, k_theta, k_ex, mu), got 2",
        ),
        (
            "0.5,inf,inf; 0.5,two,inf",
            "row 2, column k_theta: `two` is neither a finite number nor inf",
        ),
        (
            "0.5,inf,inf; 0.5,2,nan",
            "row 2, column k_ex: `nan` is neither a finite number nor inf",
        ),
        (
            "-0.5,inf,inf; 1.5,2,inf",
            "row 1, column gamma: the segment length must be",
        ),
        ("0,inf,inf; 1,2,inf", "row 1, column gamma"),
        (
            "0.5,inf,inf; 0.5,0,inf",
            "row 2, column k_theta: a spring constant must be > 0",
        ),
        ("0.5,inf,inf; 0.5,-2,inf", "row 2, column k_theta"),
        ("0.5,inf,-inf; 0.5,2,inf", "row 1, column k_ex"),
        (
            "0.5,inf,inf; 0.6,2,inf",
            "the gammas must sum to 1, they sum to 1.1",
        ),
        (
            "0.125,inf,inf; 0.35,3.25,inf; 0.388,2.84,inf; 0.136,2.95,inf",
            "sum to 0.999",
        ),
        ("0.5,inf,inf; 0.5,inf,inf", "no joint"),
    ];
    for (text, message) in cases {
        let err = PrbMatrix::parse(text).unwrap_err().to_string();
        assert!(
            err.contains(message),
            "`{text}`: got `{err}`, wanted `{message}`"
        );
    }
    // Editing a cell to a bad value fails and leaves the matrix as it was.
    let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.25,inf").unwrap();
    let err = m.with_cell(1, Column::KTheta, f64::NAN).unwrap_err();
    assert!(matches!(err, MatrixError::Spring { row: 2, .. }));
    assert_eq!(m.to_text(), "0.15,inf,inf; 0.85,2.25,inf");
    // JSON with a bad entry names the row.
    let err = serde_json::from_str::<PrbMatrix>(r#"[{"gamma":1.0,"k_theta":"soft","k_ex":"inf"}]"#)
        .unwrap_err()
        .to_string();
    assert!(err.contains("row 1") && err.contains("soft"), "{err}");
}

/// The cases of `solver` along `end` in `steps`, warm-started from `warm` if given, and the
/// equilibria as a warm start for the next model.
fn warm_path(
    solver: &PrbSolver,
    end: Load,
    steps: u32,
    warm: Option<&WarmStart>,
) -> (Result<Vec<(TipPose, u32)>, PrbError>, WarmStart) {
    let mut cases = Vec::new();
    let mut next = WarmStart::default();
    next.clear(solver.dof_count());
    let mut visit = |c: PrbCase<'_>| {
        cases.push((c.tip, c.iterations));
        next.push(&c);
    };
    let outcome = match warm {
        Some(w) => solver.solve_warm_with(end, steps, None, w, &mut visit),
        None => solver.solve_path_with(end, steps, &mut visit),
    };
    (outcome.map(|()| cases), next)
}

/// `matrix` with every finite spring scaled by `factor`.
fn springs_scaled(matrix: &PrbMatrix, factor: f64) -> PrbMatrix {
    let rows = matrix
        .rows()
        .iter()
        .map(|r| PrbRow {
            k_theta: r.k_theta * factor,
            k_ex: r.k_ex * factor,
            ..*r
        })
        .collect();
    PrbMatrix::new(rows).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// A path warm-started from a neighbouring model's equilibria (its springs 0.8 to 1.25
    /// times) reports the equilibria the plain path does, to Newton's tolerance (1e-13 on
    /// the joints; 1e-10 on the tips leaves room for the early stop's estimate), and fails
    /// where the plain path fails: the warm start changes the cost, not the answer.
    #[test]
    fn a_warm_start_changes_the_cost_not_the_equilibria(
        m in matrix(),
        factor in 0.8..1.25f64,
        ax in -12.0..12.0f64,
        ay in -12.0..12.0f64,
        beta in -4.0..4.0f64,
        steps in 1..6u32,
    ) {
        let end = Load::new(ax, ay, beta);
        let near = springs_scaled(&m, factor);
        let (_, warm) = warm_path(&PrbSolver::new(&m, C_E), end, steps, None);
        let solver = PrbSolver::new(&near, C_E);
        let (plain, _) = warm_path(&solver, end, steps, None);
        let (warmed, _) = warm_path(&solver, end, steps, Some(&warm));
        match (plain, warmed) {
            (Ok(p), Ok(w)) => {
                prop_assert_eq!(p.len(), w.len());
                for ((pt, _), (wt, _)) in p.iter().zip(&w) {
                    prop_assert!(pt.max_diff(wt) < 1e-10, "{:?} against {:?}", wt, pt);
                }
            }
            (Err(_), Err(_)) => {}
            (p, w) => prop_assert!(false, "plain {:?}, warm {:?}", p.err(), w.err()),
        }
    }
}

/// Su's 3R along a combined load, warm-started from the model with 1 % stiffer springs (a
/// late polish step): every case reached, in fewer Newton iterations than from rest (the
/// hint's first update is the parameter change's first-order effect).
#[test]
fn a_warm_start_saves_newton_iterations() {
    let su = PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
    let end = Load::new(-1.0, 3.0, 1.0);
    let (_, warm) = warm_path(
        &PrbSolver::new(&springs_scaled(&su, 1.01), C_E),
        end,
        5,
        None,
    );
    let solver = PrbSolver::new(&su, C_E);
    let (plain, _) = warm_path(&solver, end, 5, None);
    let (warmed, _) = warm_path(&solver, end, 5, Some(&warm));
    let total = |cases: &[(TipPose, u32)]| cases.iter().map(|c| c.1).sum::<u32>();
    let (plain, warmed) = (plain.unwrap(), warmed.unwrap());
    assert!(
        total(&warmed) < total(&plain),
        "warm {} against plain {} iterations",
        total(&warmed),
        total(&plain)
    );
}

/// A warm start does not carry a model past its buckling load: the 1R pushed along its
/// axis to 1.25 times `k / gamma` (critical at 0.8 of the path, between the cases at 4/6
/// and 5/6), warm-started from a model 30 % stiffer (which stays straight there), still
/// meets its critical point where it does from rest, to within the path's smallest step
/// (1e-7). Each hint past it is a straight chain whose stiffness is not positive definite,
/// so it is forgotten.
#[test]
fn a_warm_start_does_not_pass_a_critical_point() {
    let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
    let critical = 2.2525 / 0.85;
    let end = Load::new(-1.25 * critical, 0.0, 0.0);
    let (stiffer, warm) = warm_path(&PrbSolver::new(&springs_scaled(&m, 1.3), C_E), end, 6, None);
    assert_eq!(stiffer.unwrap().len(), 6);
    let solver = PrbSolver::new(&m, C_E);
    let fraction = |r: Result<Vec<(TipPose, u32)>, PrbError>| match r {
        Err(PrbError::Unstable { fraction, .. }) => fraction,
        other => panic!("expected a critical point, got {other:?}"),
    };
    let plain = fraction(warm_path(&solver, end, 6, None).0);
    let warmed = fraction(warm_path(&solver, end, 6, Some(&warm)).0);
    for at in [plain, warmed] {
        assert!(
            (at - 0.8).abs() < 2e-7,
            "plain at {plain}, warm at {warmed}"
        );
    }
}

/// Measured rows (a specimen's polyline of loads) warm-started from a neighbouring model's
/// equilibria at the same rows: the same tips as the rows followed from rest, to 1e-10.
#[test]
fn a_warm_start_on_measured_rows_keeps_the_equilibria() {
    let su = PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
    let rows = [
        Load::new(0.0, 1.0, 0.0),
        Load::new(-0.5, 2.5, 0.3),
        Load::new(-1.0, 3.0, 1.0),
        Load::new(-1.5, 2.0, 1.5),
    ];
    let solve = |solver: &PrbSolver, warm: Option<&WarmStart>| {
        let mut tips = Vec::new();
        let mut next = WarmStart::default();
        next.clear(solver.dof_count());
        let mut visit = |c: PrbCase<'_>| {
            tips.push(c.tip);
            next.push(&c);
        };
        match warm {
            Some(w) => solver.solve_warm_with(rows[3], 4, Some(&rows), w, &mut visit),
            None => solver.solve_rows_with(&rows, &mut visit),
        }
        .unwrap();
        (tips, next)
    };
    let (_, warm) = solve(&PrbSolver::new(&springs_scaled(&su, 1.05), C_E), None);
    let solver = PrbSolver::new(&su, C_E);
    let (plain, _) = solve(&solver, None);
    let (warmed, _) = solve(&solver, Some(&warm));
    assert_eq!(plain.len(), 4);
    for (p, w) in plain.iter().zip(&warmed) {
        assert!(p.max_diff(w) < 1e-10, "{w:?} against {p:?}");
    }
}

/// A hint from another branch is forgotten even when it is an equilibrium of the model: the
/// 1R tilted past its buckling load follows the branch bent one way from rest; a warm start
/// holding the mirror branch (bent the other way, an equilibrium of the same chain under the
/// mirrored tilt) lands far from the followed step, and the path reports the plain
/// equilibria.
#[test]
fn a_hint_on_another_branch_is_forgotten() {
    let m = PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap();
    let solver = PrbSolver::new(&m, C_E);
    let critical = 2.2525 / 0.85;
    let end = Load::new(-1.5 * critical, 0.01, 0.0);
    let (plain, _) = warm_path(&solver, end, 4, None);
    let mirrored = Load::new(-1.5 * critical, -0.01, 0.0);
    let (_, warm) = warm_path(&solver, mirrored, 4, None);
    let (warmed, _) = warm_path(&solver, end, 4, Some(&warm));
    let (plain, warmed) = (plain.unwrap(), warmed.unwrap());
    assert!(plain.last().unwrap().0.phi > 0.5, "{plain:?}");
    for ((p, _), (w, _)) in plain.iter().zip(&warmed) {
        assert!(p.max_diff(w) < 1e-10, "{w:?} against {p:?}");
    }
}
