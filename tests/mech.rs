//! Known answers for flexure mechanisms (DESIGN §8), exact beam and PRB.
//!
//! The beams here have `L = 1 m` and `E I0 = 1 N m^2` (width 1 m, thickness 0.01 m,
//! `E = 12e6 Pa`), so SI values are the nondimensional ones and every number below reads
//! directly as units of `L` and `alpha = F L^2 / (E I0)`. The exact beam is the inextensible
//! elastica (no effects), the setting of the classical closed forms.
//!
//! Tolerances: the mechanism Newton stops at `tol = 1e-10` on the tip residuals and the beams
//! are solved at the same `tol`, whose tips are good to `10 tol = 1e-9`
//! (`Resolution::claimed_tip_error`); comparisons against a separately solved reference
//! beam therefore hold to `1e-8` with a margin of ten for the reported force's own error
//! (a force error `e` moves a tip by about `e / 3`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution};
use prbfit::mech::{exact, prb, MechCase, MechError};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};
use proptest::prelude::*;

const TOL: f64 = 1e-10;

/// `L = 1`, `E I0 = 1`, the elastica.
fn beam() -> BeamSpec {
    BeamSpec {
        length: 1.0,
        width: 1.0,
        thickness: 0.01,
        youngs_modulus: 12e6,
        poisson_ratio: 0.3,
        shear_coefficient: None,
        effects: EffectsChoice::Fixed(Effects::NONE),
    }
}

fn flexure(root: [f64; 2], attach: Attach) -> Flexure {
    Flexure {
        root,
        angle: 0.0,
        attach,
        beam: beam(),
    }
}

fn mechanism(
    flexures: Vec<Flexure>,
    stage_point: [f64; 2],
    drive: [Coordinate; 3],
    steps: u32,
) -> Mechanism {
    Mechanism {
        flexures,
        stage_point,
        drives: vec![Drive {
            coordinates: drive,
            steps,
        }],
    }
}

fn exact_cases(m: &Mechanism) -> Result<Vec<MechCase>, MechError> {
    Ok(exact::solve(m, Resolution::with_tol(TOL))?.remove(0))
}

fn elastica() -> BeamSolver {
    BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(TOL)).unwrap()
}

use Coordinate::{Loaded, Prescribed};

/// The fixed-guided segment: one clamped flexure, its tip moved sideways by `dy` with the
/// stage kept from turning and free to slide along the flexure (`dx` loaded with 0).
///
/// The known answer: with no axial force and equal, opposite end rotations (both zero), the
/// moment `M(s) = beta + alpha (a - x(s))` vanishes where `x = a / 2`, and by symmetry at the
/// middle `s = L / 2`: the beam is two cantilevers of length `L / 2` meeting at that
/// inflection point, each under the transverse force `F` alone. A half beam's own load is
/// `alpha_half = F (L/2)^2 / (E I) = alpha / 4`; its tip is `(a_c, b_c)(alpha / 4)` in units
/// of `L / 2`; two of them, point-symmetric, give `delta / L = b_c(alpha / 4)` and
/// `a / L = a_c(alpha / 4)`, and the tip moment is `beta = -alpha a / 2` (`M(L/2) = 0`).
/// For small motion `b_c(x) = x / 3`, so `delta = alpha / 12`: the stiffness `12 E I / L^3`.
fn fixed_guided(dy: f64, steps: u32) -> Mechanism {
    mechanism(
        vec![flexure([0.0, 0.0], Attach::Clamped)],
        [1.0, 0.0],
        [Loaded(0.0), Prescribed(dy), Prescribed(0.0)],
        steps,
    )
}

#[test]
fn fixed_guided_is_two_half_cantilevers() {
    let cases = exact_cases(&fixed_guided(0.6, 6)).unwrap();
    let half = elastica();
    assert_eq!(cases.len(), 6);
    for c in &cases {
        let f = c.flexures[0];
        let alpha = f.wrench.alpha_y;
        let reference = half.solve(Load::new(0.0, alpha / 4.0, 0.0)).unwrap().tip;
        assert!(
            (reference.b - c.stage[1]).abs() < 1e-8,
            "{c:?} vs {reference:?}"
        );
        assert!((reference.b - f.tip.b).abs() < 1e-8);
        assert!(
            (reference.a - f.tip.a).abs() < 1e-8,
            "{c:?} vs {reference:?}"
        );
        assert!(
            (f.wrench.beta + alpha * f.tip.a / 2.0).abs() < 1e-8,
            "{c:?}"
        );
        assert!(f.wrench.alpha_x.abs() < 1e-8);
        assert!(f.tip.phi.abs() < 1e-9);
        // The stage follows the tip, and the drive supplies the flexure's force.
        assert!((c.stage[0] - (f.tip.a - 1.0)).abs() < 1e-9);
        assert!((c.stage_load[1] - alpha).abs() < 1e-12);
        assert_eq!(c.stage_load[0], 0.0);
    }
}

#[test]
fn fixed_guided_small_motion_stiffness_is_12() {
    let dy = 1e-4;
    let c = &exact_cases(&fixed_guided(dy, 1)).unwrap()[0];
    // The nonlinear correction is O(dy^2) = 1e-8; the tolerance on the tip, 1e-10 over
    // dy = 1e-4, is 1e-6 of the stiffness.
    let k = c.stage_load[1] / dy;
    assert!((k - 12.0).abs() < 1e-4, "stiffness {k}");
}

/// The displacement-driven cantilever: the tip moved sideways, free to slide and turn. Its
/// reaction, applied as a load, must put the tip back where the drive put it.
#[test]
fn driven_cantilever_inverts_the_loaded_one() {
    let m = mechanism(
        vec![flexure([0.0, 0.0], Attach::Clamped)],
        [1.0, 0.0],
        [Loaded(0.0), Prescribed(0.4), Loaded(0.0)],
        4,
    );
    let cases = exact_cases(&m).unwrap();
    let solver = elastica();
    for c in &cases {
        let w = c.flexures[0].wrench;
        assert!(w.alpha_x.abs() < 1e-8 && w.beta.abs() < 1e-8, "{w:?}");
        let tip = solver
            .solve(Load::new(0.0, c.stage_load[1], 0.0))
            .unwrap()
            .tip;
        assert!((tip.b - c.stage[1]).abs() < 1e-8, "{tip:?} vs {c:?}");
        assert!((tip.phi - c.stage[2]).abs() < 1e-8);
    }
}

/// The parallel-guiding stage: two identical clamped flexures at `(0, +-W)`, a force on the
/// stage centre `(L, 0)`. For small motion the stage barely turns (its rotation is resisted
/// by the flexures' axial stiffness) and each flexure is a fixed-guided segment carrying
/// half the force: `uy = (Ay / 2) / 12 = Ay / 24`.
fn parallel_stage(ay: f64, steps: u32) -> Mechanism {
    let w = 0.3;
    mechanism(
        vec![
            flexure([0.0, w], Attach::Clamped),
            flexure([0.0, -w], Attach::Clamped),
        ],
        [1.0, 0.0],
        [Loaded(0.0), Loaded(ay), Loaded(0.0)],
        steps,
    )
}

#[test]
fn parallel_stage_small_motion() {
    let ay = 1e-3;
    let c = &exact_cases(&parallel_stage(ay, 1)).unwrap()[0];
    // Nonlinear terms are O(ay^2) relative; the tip tolerance 1e-10 is 2.4e-6 of uy.
    let uy = c.stage[1];
    assert!((uy / (ay / 24.0) - 1.0).abs() < 1e-4, "uy = {uy}");
    assert!(c.stage[2].abs() < 1e-6);
}

/// A tip pinned onto a guide through its unloaded tip and pushed along the inextensible
/// flexure's axis can only move by buckling: not even a first-order motion exists.
#[test]
fn pinned_tip_pushed_along_its_axis_is_immobile() {
    let m = mechanism(
        vec![flexure([0.0, 0.0], Attach::Pinned)],
        [1.0, 0.0],
        [Prescribed(-0.1), Prescribed(0.0), Prescribed(0.0)],
        4,
    );
    let e = exact_cases(&m).unwrap_err();
    assert!(matches!(e, MechError::Immobile { drive: 1, .. }), "{e}");
}

fn howell_1r() -> PrbMatrix {
    PrbMatrix::parse("0.15,inf,inf; 0.85,2.2525,inf").unwrap()
}

#[test]
fn one_r_cannot_be_fixed_guided() {
    let e = prb::solve(&fixed_guided(0.2, 2), &howell_1r(), TOL).unwrap_err();
    assert!(matches!(e, MechError::Immobile { .. }), "{e}");
}

/// The compliant slider-crank with Howell's 1R model against the rigid-body slider-crank.
///
/// The 1R chain is a rigid crank of length `r = 0.85` turning about `O = (0.15, 0)` against a
/// torsion spring `k = 2.2525` (`E I0 / L`). A rigid coupler of length `c` joins the crank's
/// end `A = O + r (cos t, sin t)` to the slider `S = S0 + (0, s)`,
/// `S0 = (1 + c cos 45deg, -c sin 45deg)`, driven along y. Closure `|S - A| = c` with
/// `D = S - O` reads `|D|^2 - 2 r (Dx cos t + Dy sin t) + r^2 = c^2`, so
/// `t = atan2(Dy, Dx) + acos((|D|^2 + r^2 - c^2) / (2 r |D|))` (the branch through `t = 0` at
/// `s = 0`, where `atan2(Dy, Dx) < 0`). The guide's normal force does no work along the
/// drive, so virtual work gives the drive force `F_y ds = k t dt`: `alpha_y = k t dt/ds`.
#[test]
fn one_r_slider_crank_matches_the_rigid_body_model() {
    let c_len = 0.5;
    let (s45, c45) = std::f64::consts::FRAC_PI_4.sin_cos();
    let s0 = [1.0 + c_len * c45, -c_len * s45];
    let stroke = 0.3;
    let m = mechanism(
        vec![flexure([0.0, 0.0], Attach::Link { to: s0 })],
        s0,
        [Prescribed(0.0), Prescribed(stroke), Prescribed(0.0)],
        6,
    );
    let (r, k, o) = (0.85, 2.2525, [0.15, 0.0]);
    let crank = |s: f64| {
        let d = [s0[0] - o[0], s0[1] + s - o[1]];
        let dn = d[0].hypot(d[1]);
        d[1].atan2(d[0]) + ((dn * dn + r * r - c_len * c_len) / (2.0 * r * dn)).acos()
    };
    assert!(crank(0.0).abs() < 1e-12);
    let cases = prb::solve(&m, &howell_1r(), 1e-12).unwrap().remove(0);
    for c in &cases {
        let s = c.stage[1];
        let t = crank(s);
        let h = 1e-5;
        let dt = (crank(s + h) - crank(s - h)) / (2.0 * h);
        let tip = c.flexures[0].tip;
        assert!((tip.phi - t).abs() < 1e-10, "{tip:?} vs {t}");
        assert!((tip.a - (o[0] + r * t.cos())).abs() < 1e-10);
        assert!((tip.b - (o[1] + r * t.sin())).abs() < 1e-10);
        // The central difference is good to h^2 t''' ~ 1e-10.
        let force = k * t * dt;
        assert!(
            (c.stage_load[1] - force).abs() < 1e-7 * (1.0 + force.abs()),
            "{} vs {force}",
            c.stage_load[1]
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Every flexure's reported wrench, solved as a plain cantilever from rest, gives back its
    /// reported tip: the mechanism's flexures are the single beam. Only for loads that keep
    /// every flexure's axial compression below the cantilever's buckling load `pi^2 / 4`:
    /// past it a flexure's wrench has other equilibria, and the cantilever loaded from rest
    /// takes one of those or meets a limit point (`FlexureCase::load_stable` says when the
    /// flexure is even stable under its wrench as a dead load; the shrunk cases
    /// `ay = 4.12` and `ay = 6.6, ax = 1.1` in the regression file were such).
    #[test]
    fn reported_wrenches_reproduce_the_tips(ay in -2.0..2.0f64, ax in -1.0..1.0f64, mz in -0.3..0.3f64) {
        let mut m = parallel_stage(ay, 2);
        m.drives[0].coordinates = [Loaded(ax), Loaded(ay), Loaded(mz)];
        let cases = exact_cases(&m).unwrap();
        let solver = elastica();
        prop_assert!(cases.iter().all(|c| c.flexures.iter().all(|f| f.load_stable)));
        for c in &cases {
            for f in &c.flexures {
                let tip = solver.solve(f.wrench).unwrap().tip;
                prop_assert!(tip.max_diff(&f.tip) < 1e-8, "{tip:?} vs {f:?}");
            }
        }
    }
}

/// A clamped-clamped flexure pushed along its axis (extension on, `L / t0 = 100`): it
/// shortens by `alpha c_e` (`c_e = 1 / (12 (L/t0)^2)`) until the Euler load of the
/// clamped-clamped column, `alpha = 4 pi^2`, at `dx = -4 pi^2 c_e = -3.29e-4`, where the
/// straight shape bifurcates. The solver must stop there, not carry on along the straight,
/// unstable branch.
#[test]
fn clamped_flexure_pushed_past_euler_reports_the_bifurcation() {
    let mut f = flexure([0.0, 0.0], Attach::Clamped);
    f.beam.effects = EffectsChoice::Fixed(Effects {
        shear: false,
        extension: true,
        poisson: false,
    });
    let m = mechanism(
        vec![f],
        [1.0, 0.0],
        [Prescribed(-6e-4), Prescribed(0.0), Prescribed(0.0)],
        12,
    );
    let e = exact_cases(&m).unwrap_err();
    let critical = 4.0 * std::f64::consts::PI.powi(2) / (12.0 * 100.0 * 100.0) / 6e-4;
    match e {
        MechError::Critical { drive: 1, fraction } => {
            assert!(
                fraction < critical && fraction >= critical - 1.0 / 12.0 - 1e-12,
                "stopped at {fraction}, critical at {critical}"
            );
        }
        other => panic!("{other}"),
    }
}

/// The compliant slider-crank with the exact beam: the coupler is a two-force member, so
/// the flexure's tip force points along it, and the drive force balances it.
#[test]
fn exact_slider_crank_pushes_along_the_coupler() {
    let c_len = 0.5;
    let (s45, c45) = std::f64::consts::FRAC_PI_4.sin_cos();
    let s0 = [1.0 + c_len * c45, -c_len * s45];
    let m = mechanism(
        vec![flexure([0.0, 0.0], Attach::Link { to: s0 })],
        s0,
        [Prescribed(0.0), Prescribed(0.3), Prescribed(0.0)],
        5,
    );
    let cases = exact_cases(&m).unwrap();
    for c in &cases {
        let f = c.flexures[0];
        let slider = [s0[0] + c.stage[0], s0[1] + c.stage[1]];
        let along = [slider[0] - f.tip.a, slider[1] - f.tip.b];
        assert!((along[0].hypot(along[1]) - c_len).abs() < 1e-9);
        let w = f.wrench;
        assert!((w.alpha_x * along[1] - w.alpha_y * along[0]).abs() < 1e-9);
        // The pin's zero tip moment is one of Newton's equations, met to its tol (1e-10).
        assert!(w.beta.abs() < 1e-9, "tip moment {}", w.beta);
        assert!((c.stage_load[1] - w.alpha_y).abs() < 1e-12);
        assert!(c.stage_load[1] > 0.0);
    }
}

/// Flexures of other sizes and directions, each in its own frame and units: flexure 1 as in
/// the parallel stage, flexure 2 twice as long, with twice the stiffness `E`, reaching back
/// from the right (`root = (3, -W)`, `angle = 180 deg`). To first order the stage does not
/// turn (the inextensible flexures hold it) and each flexure is a fixed-guided segment of
/// stiffness `12 E I / L^3`: 12 and `12 * 2 / 8 = 3`, so `uy = Ay / 15`. Flexure 2's own
/// wrench is in its own units: its transverse force, `Ay * 3 / 15` in flexure 1's units, is
/// `-Ay * 3 / 15 * L2^2 / (E I2 / E I1) = -Ay * 0.4` in its own frame, which points the
/// other way.
#[test]
fn flexures_of_other_sizes_and_directions() {
    let ay = 1e-3;
    let w = 0.3;
    let mut f2 = flexure([3.0, -w], Attach::Clamped);
    f2.angle = std::f64::consts::PI;
    f2.beam.length = 2.0;
    f2.beam.youngs_modulus *= 2.0;
    let m = mechanism(
        vec![flexure([0.0, w], Attach::Clamped), f2],
        [1.0, 0.0],
        [Loaded(0.0), Loaded(ay), Loaded(0.0)],
        1,
    );
    let c = &exact_cases(&m).unwrap()[0];
    assert!((c.stage[1] / (ay / 15.0) - 1.0).abs() < 1e-4, "{c:?}");
    let w2 = c.flexures[1].wrench;
    assert!((w2.alpha_y / (-ay * 0.4) - 1.0).abs() < 1e-4, "{w2:?}");
    // Its tip, in its own units, moved down (its +y is global -y) by uy / L2.
    assert!((c.flexures[1].tip.b / (-c.stage[1] / 2.0) - 1.0).abs() < 1e-6);
}

/// The fixed-guided segment with every effect on (shear, extension, Poisson; `L / t0 = 10`,
/// a stubby flexure where they matter): the point symmetry about the middle holds for the
/// Reissner beam too (no axial force, so the axial and shear strains follow the same
/// antisymmetric pattern), so each half is a cantilever of its own slenderness `5` under
/// `alpha / 4`.
#[test]
fn fixed_guided_with_every_effect_is_two_half_cantilevers() {
    let mut f = flexure([0.0, 0.0], Attach::Clamped);
    f.beam.thickness = 0.1;
    f.beam.youngs_modulus = 12e3; // E I0 = 1 again
    f.beam.effects = EffectsChoice::Fixed(Effects::ALL);
    let m = mechanism(
        vec![f],
        [1.0, 0.0],
        [Loaded(0.0), Prescribed(0.4), Prescribed(0.0)],
        4,
    );
    let cases = exact_cases(&m).unwrap();
    let half = BeamSolver::new(
        BeamModel::new(5.0, 0.3, None, Effects::ALL).unwrap(),
        Resolution::with_tol(TOL),
    )
    .unwrap();
    for c in &cases {
        let f = c.flexures[0];
        let alpha = f.wrench.alpha_y;
        let reference = half.solve(Load::new(0.0, alpha / 4.0, 0.0)).unwrap().tip;
        assert!(
            (reference.b - f.tip.b).abs() < 1e-8,
            "{c:?} vs {reference:?}"
        );
        assert!(
            (reference.a - f.tip.a).abs() < 1e-8,
            "{c:?} vs {reference:?}"
        );
        assert!(
            (f.wrench.beta + alpha * f.tip.a / 2.0).abs() < 1e-8,
            "{c:?}"
        );
    }
}

/// A scene file in SI (DESIGN §8's slider-crank: `L = 50 mm` steel, coupler `c = 25 mm` at
/// 45 degrees, stroke 10 mm) gives the same nondimensional answers as the same mechanism
/// drawn at `L = 1`, `E I0 = 1`: the solver sees only flexure 1's units.
#[test]
fn si_scene_solves_in_flexure_one_units() {
    let (s45, c45) = std::f64::consts::FRAC_PI_4.sin_cos();
    let (l, c_len) = (0.05, 0.025);
    let slider = [l + c_len * c45, -c_len * s45];
    let text = format!(
        "name = \"slider-crank\"\n[beam]\nlength = {l}\nwidth = 0.01\nthickness = 0.0005\n\
         youngs_modulus = 200e9\npoisson_ratio = 0.3\neffects = \"none\"\n[[flexures]]\n\
         root = [0.0, 0.0]\nangle_deg = 0.0\nattach = \"link\"\n[stage]\n\
         point = [{:?}, {:?}]\n[[drives]]\ndx = 0.0\ndy = 0.01\ndphi = 0.0\nsteps = 4\n",
        slider[0], slider[1]
    );
    let scene = prbfit::scene::Scene::from_toml_str(&text, "sc.toml").unwrap();
    let si = exact_cases(scene.mechanism.as_ref().unwrap()).unwrap();
    let s0 = [slider[0] / l, slider[1] / l];
    let unit = mechanism(
        vec![flexure([0.0, 0.0], Attach::Link { to: s0 })],
        s0,
        [Prescribed(0.0), Prescribed(0.01 / l), Prescribed(0.0)],
        4,
    );
    let unit = exact_cases(&unit).unwrap();
    for (a, b) in si.iter().zip(&unit) {
        for k in 0..3 {
            assert!((a.stage[k] - b.stage[k]).abs() < 1e-9, "{a:?} vs {b:?}");
            assert!(
                (a.stage_load[k] - b.stage_load[k]).abs() < 1e-7,
                "{a:?} vs {b:?}"
            );
        }
        assert!(a.flexures[0].tip.max_diff(&b.flexures[0].tip) < 1e-9);
    }
    // A 10 mm stroke of a 50 mm crank is 0.2 L: the drive force is of order 1.
    assert!((si[3].stage[1] - 0.2).abs() < 1e-12);
    assert!(si[3].stage_load[1] > 0.1, "{:?}", si[3]);
}
