//! Stages on three or more parallel clamped flexures (issue 24): with the flexures able to
//! stretch they are determinate however stiff the stretch is next to the bending, and their
//! small motion is linear frame theory's; with no stretch they are statically indeterminate
//! along their axes, and the error says so and names the cure.
//!
//! Units: every flexure has `L = 1` and `E I = 1`, so SI values are the nondimensional ones
//! (`alpha = F L^2 / (E I)`, `beta = M L / (E I)`).
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use prbfit::beam::{Effects, Resolution};
use prbfit::mech::{exact, prb, MechCase, MechError};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};
use proptest::prelude::*;

const NU: f64 = 0.3;
/// The flexures' tip tolerance (units of `L`).
const TOL: f64 = 1e-10;

/// Length 1, `E I = 1`, slenderness `L / t`.
fn beam(slenderness: f64, effects: Effects) -> BeamSpec {
    let t = 1.0 / slenderness;
    BeamSpec {
        length: 1.0,
        width: 1.0,
        thickness: t,
        youngs_modulus: 12.0 / t.powi(3),
        poisson_ratio: NU,
        shear_coefficient: None,
        effects: EffectsChoice::Fixed(effects),
        density: None,
        allowable_stress: None,
    }
}

/// Shear and stretch: what a real stage's flexures do (Poisson's section shrinkage is
/// second order at the small loads compared here).
const STRETCHY: Effects = Effects {
    shear: true,
    extension: true,
    ..Effects::NONE
};

/// Clamped flexures along +x from roots `(0, y)`, the stage point `p`, one drive of `steps`
/// loading the stage with `load` (nondimensional).
fn stage(
    ys: &[f64],
    slenderness: f64,
    effects: Effects,
    p: [f64; 2],
    load: [f64; 3],
    steps: u32,
) -> Mechanism {
    Mechanism {
        flexures: ys
            .iter()
            .map(|&y| Flexure {
                root: [0.0, y],
                angle: 0.0,
                attach: Attach::Clamped,
                beam: beam(slenderness, effects),
            })
            .collect(),
        stage_point: p,
        drives: vec![Drive::proportional(load.map(Coordinate::Loaded), steps)],
    }
}

/// Linear frame theory, written independently of prbfit: the stage displacement
/// `[ux, uy, theta]` of `P` under `load`, each flexure a clamped-clamped Timoshenko frame
/// element (axial `E A / L`; bending with `Phi = 12 E I / (kappa G A L^2)`) whose far end is
/// welded to the rigid stage.
fn linear_frame(ys: &[f64], slenderness: f64, p: [f64; 2], load: [f64; 3]) -> [f64; 3] {
    let t = 1.0 / slenderness;
    let (ei, ea) = (1.0, 12.0 / (t * t));
    // Cowper's rectangle, and G = E / (2 (1 + nu)).
    let kappa = 10.0 * (1.0 + NU) / (12.0 + 11.0 * NU);
    let kga = kappa * ea / (2.0 * (1.0 + NU));
    let phi = 12.0 * ei / kga;
    // The tip's stiffness with the root clamped: force and moment at the tip per tip
    // displacement (u, v) and rotation (r).
    let tip = [
        [ea, 0.0, 0.0],
        [0.0, 12.0 * ei / (1.0 + phi), -6.0 * ei / (1.0 + phi)],
        [0.0, -6.0 * ei / (1.0 + phi), (4.0 + phi) * ei / (1.0 + phi)],
    ];
    let mut k = [[0.0; 3]; 3];
    for &y in ys {
        // The tip (1, y) moves with the stage: u = ux - theta ry, v = uy + theta rx.
        let (rx, ry) = (1.0 - p[0], y - p[1]);
        let t = [[1.0, 0.0, -ry], [0.0, 1.0, rx], [0.0, 0.0, 1.0]];
        for (i, ti) in (0..3).map(|i| (i, t.map(|row| row[i]))) {
            for j in 0..3 {
                k[i][j] += (0..3)
                    .map(|a| (0..3).map(|b| ti[a] * tip[a][b] * t[b][j]).sum::<f64>())
                    .sum::<f64>();
            }
        }
    }
    solve3(k, load)
}

/// Cramer's rule on a 3 by 3 system.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        (0..3).for_each(|r| m[r][c] = b[r]);
        *xc = det(m) / d;
    }
    x
}

fn solved(m: &Mechanism) -> Result<MechCase, MechError> {
    Ok(exact::solve(m, Resolution::with_tol(TOL))?
        .remove(0)
        .remove(0))
}

/// `n` flexures evenly spread over `[-0.3, 0.3] L`.
fn even(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| -0.3 + 0.6 * i as f64 / (n - 1) as f64)
        .collect()
}

/// How far the beam mechanism's stage motion is from linear frame theory's, relative to the
/// largest of the motion's three parts.
fn gap(case: &MechCase, linear: [f64; 3]) -> f64 {
    let big = linear.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    (0..3).fold(0.0_f64, |m, i| m.max((case.stage[i] - linear[i]).abs())) / big
}

/// The stage motion's nonlinear part is at most `O(alpha)` of it (the axial force's
/// stiffening of the bending, `alpha_x / 10` or so; the bending's shortening is second order):
/// at a load of `LOAD` its relative size is below `LOAD`, and the flexures' tip tolerance
/// adds `TOL` over the motion (1e-5 here). Measured: 4e-10 to 1.1e-9.
const LOAD: f64 = 1e-5;
const LINEAR: f64 = 2e-5;

#[test]
fn three_five_and_eight_stretchy_flexures_are_linear_frames_at_small_load() {
    for n in [3, 5, 8] {
        for slenderness in [10.0, 100.0, 1000.0] {
            let ys = even(n);
            let p = [1.0, 0.05];
            let load = [0.4 * LOAD, LOAD, -0.2 * LOAD];
            let case = solved(&stage(&ys, slenderness, STRETCHY, p, load, 1))
                .unwrap_or_else(|e| panic!("{n} flexures at L/t = {slenderness}: {e}"));
            let linear = linear_frame(&ys, slenderness, p, load);
            let g = gap(&case, linear);
            println!("{n} flexures, L/t = {slenderness}: gap {g:.1e}");
            assert!(
                g < LINEAR,
                "{n} flexures, L/t {slenderness}: {case:?} vs {linear:?}"
            );
        }
    }
}

/// The same stages followed to a large sideways load: the path is followed to its end.
#[test]
fn five_stretchy_flexures_follow_a_large_sideways_load() {
    for slenderness in [10.0, 1000.0] {
        let m = stage(
            &even(5),
            slenderness,
            STRETCHY,
            [1.0, 0.0],
            [0.0, 20.0, 0.0],
            8,
        );
        let cases = exact::solve(&m, Resolution::with_tol(1e-9))
            .unwrap()
            .remove(0);
        assert_eq!(cases.len(), 8);
        // Five fixed-guided segments share 20: each carries 4, a guided deflection of
        // about 4 / 12 = 0.33 L less the stiffening.
        let uy = cases[7].stage[1];
        assert!(uy > 0.1 && uy < 0.34, "L/t {slenderness}: uy = {uy}");
    }
}

/// With no stretch, three parallel clamped flexures can carry forces along their axes that
/// balance on the stage with nothing moving: the error names the indeterminacy, the
/// flexures, and the cure.
#[test]
fn inextensible_parallel_flexures_are_named_indeterminate() {
    let m = stage(
        &even(3),
        100.0,
        Effects::NONE,
        [1.0, 0.0],
        [0.0, 1.0, 0.0],
        2,
    );
    let e = solved(&m).unwrap_err();
    assert!(
        matches!(&e, MechError::Indeterminate { drive: 1, flexures } if flexures == &[1, 2, 3]),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(text.contains("statically indeterminate"), "{text}");
    assert!(text.contains("`extension`"), "{text}");
    // Two inextensible flexures are determinate (the parallel-guiding stage).
    assert!(solved(&stage(
        &even(2),
        100.0,
        Effects::NONE,
        [1.0, 0.0],
        [0.0, 1.0, 0.0],
        2
    ))
    .is_ok());
}

/// A PRB model with rigid links along the axis is as indeterminate on three flexures.
#[test]
fn rigid_axial_prb_models_on_three_flexures_are_indeterminate() {
    let m = stage(&even(3), 100.0, STRETCHY, [1.0, 0.0], [0.0, 1.0, 0.0], 2);
    let su = PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
    let e = prb::solve(&m, &su, TOL).unwrap_err();
    assert!(matches!(&e, MechError::Indeterminate { .. }), "{e:?}");
    // So is a chain with a prismatic joint but one revolute joint: the cure named is the
    // chain it lacks, not the joint it has.
    let rp = PrbMatrix::parse("0.2,inf,inf; 0.8,2.5,2000").unwrap();
    let e = prb::solve(&m, &rp, TOL).unwrap_err();
    assert!(matches!(&e, MechError::Indeterminate { .. }), "{e:?}");
    let text = e.to_string();
    assert!(
        text.contains("two revolute joints at least, and a prismatic one for three or more"),
        "{text}"
    );
    // Such a chain solves: a fitted shape of L-RP-RP-RP.
    let rp3 = PrbMatrix::parse("0.1,inf,inf; 0.35,3.5,2000; 0.4,3.0,2000; 0.15,2.6,2000").unwrap();
    assert!(prb::solve(&m, &rp3, TOL).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Stiff but legitimate: 3 to 6 stretchy flexures at any slenderness from 10 to 1000, at
    /// any spacing, with the stage point anywhere near the tips and a small load in any
    /// direction, solve and move as linear frame theory says.
    #[test]
    fn stretchy_parallel_stages_solve_at_any_stiffness(
        n in 3usize..=6,
        log_slenderness in 1.0f64..3.0,
        gaps in proptest::collection::vec(0.05f64..0.5, 5),
        p in (0.5f64..1.5, -0.5f64..0.5),
        dir in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
    ) {
        let slenderness = 10f64.powf(log_slenderness);
        let mut ys = vec![0.0];
        for g in &gaps[..n - 1] {
            ys.push(ys[ys.len() - 1] + g);
        }
        let norm = (dir.0 * dir.0 + dir.1 * dir.1 + dir.2 * dir.2).sqrt().max(1e-3);
        let load = [dir.0, dir.1, dir.2].map(|d| LOAD * d / norm);
        let m = stage(&ys, slenderness, STRETCHY, [p.0, p.1], load, 1);
        let case = solved(&m).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let linear = linear_frame(&ys, slenderness, [p.0, p.1], load);
        prop_assert!(gap(&case, linear) < LINEAR, "{:?} vs {:?}", case.stage, linear);
    }
}
