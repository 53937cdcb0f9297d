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
        density: None,
        effects: EffectsChoice::Fixed(Effects::NONE),
        allowable_stress: None,
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
        drives: vec![Drive::proportional(drive, steps)],
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

/// DESIGN §8's closed form of a fixed-guided case: the flexure is two half-length
/// cantilevers meeting at the inflection point, so its tip is `b_c(alpha / 4)` of the half
/// beam `half` (the flexure's own model) and its tip moment `-alpha a / 2`.
fn assert_two_half_cantilevers(c: &MechCase, half: &BeamSolver) {
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

#[test]
fn fixed_guided_is_two_half_cantilevers() {
    let cases = exact_cases(&fixed_guided(0.6, 6)).unwrap();
    let half = elastica();
    assert_eq!(cases.len(), 6);
    for c in &cases {
        assert_two_half_cantilevers(c, &half);
        let (f, alpha) = (c.flexures[0], c.flexures[0].wrench.alpha_y);
        assert!((c.stage[1] - f.tip.b).abs() < 1e-9);
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

/// A random mechanism of the four kinds this suite knows, with a random drive: the parallel
/// stage loaded, the fixed-guided flexure and the slider-crank driven, and a clamped
/// flexure beside a pinned one (different lengths and directions) loaded.
fn random_mechanism(kind: usize, u: [f64; 3]) -> Mechanism {
    match kind {
        0 => {
            let mut m = parallel_stage(0.0, 2);
            m.drives[0].coordinates = [Loaded(u[0]), Loaded(2.0 * u[1]), Loaded(0.3 * u[2])];
            m
        }
        1 => fixed_guided(0.5 * u[1], 3),
        2 => {
            let (s45, c45) = std::f64::consts::FRAC_PI_4.sin_cos();
            let s0 = [1.0 + 0.5 * c45, -0.5 * s45];
            mechanism(
                vec![flexure([0.0, 0.0], Attach::Link { to: s0 })],
                s0,
                // Down past -0.285 the flexure and the coupler stretch into one straight
                // line to the slider (1 + 0.5 = |slider|): a toggle, reported as critical.
                [Prescribed(0.0), Prescribed(0.25 * u[1]), Prescribed(0.0)],
                3,
            )
        }
        _ => {
            let mut pinned = flexure([0.2, -0.5], Attach::Pinned);
            pinned.angle = 0.6;
            pinned.beam.length = 0.9;
            mechanism(
                vec![flexure([0.0, 0.3], Attach::Clamped), pinned],
                [1.0, 0.0],
                [Loaded(u[0]), Loaded(2.0 * u[1]), Loaded(0.3 * u[2])],
                2,
            )
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Every flexure's reported wrench, solved as a plain cantilever from rest, gives back its
    /// reported tip: the mechanism's flexures are the single beam. This holds where the
    /// flexure is stable under its wrench as a dead load (`FlexureCase::load_stable`); a
    /// flexure held by the stage past its cantilever buckling load (`pi^2 / 4` axial, as the
    /// shrunk case `ay = 1.88, ax = -0.94, mz = 0.30` of the parallel stage has, see
    /// `compressed_flexure_is_not_load_stable`) sits on a branch that loading from rest does
    /// not reach, and is skipped; so is a stable flexure whose wrench compresses it past that
    /// load (`alpha_x < -pi^2 / 4`): loading it from rest along the wrench's ray can meet a
    /// limit point first (found by this test: `(-2.508, 0.755, -0.480)`, where the beam from
    /// rest turns unstable at 0.97 of the ray), so the held branch is not the one reached.
    #[test]
    fn reported_wrenches_reproduce_the_tips(kind in 0..4usize, u0 in -1.0..1.0f64, u1 in -1.0..1.0f64, u2 in -1.0..1.0f64) {
        let m = random_mechanism(kind, [u0, u1, u2]);
        let cases = exact_cases(&m).unwrap();
        let solver = elastica();
        let euler = std::f64::consts::PI.powi(2) / 4.0;
        for c in &cases {
            for f in c.flexures.iter().filter(|f| f.load_stable && f.wrench.alpha_x > -euler) {
                let tip = solver.solve(f.wrench).unwrap().tip;
                prop_assert!(tip.max_diff(&f.tip) < 1e-8, "{tip:?} vs {f:?}");
            }
        }
    }
}

/// The parallel stage's upper flexure at `(Ax, Ay, B) = (-0.94, 1.88, 0.30)` carries an axial
/// compression of 2.59, past the cantilever's buckling load `pi^2 / 4 = 2.47`: held by the
/// stage it is stable, but not under its wrench as a dead load, and the report says so.
#[test]
fn compressed_flexure_is_not_load_stable() {
    let mut m = parallel_stage(0.0, 2);
    m.drives[0].coordinates = [Loaded(-0.941), Loaded(1.878), Loaded(0.299)];
    let last = exact_cases(&m).unwrap().pop().unwrap();
    let upper = last.flexures[0];
    assert!(
        upper.wrench.alpha_x < -std::f64::consts::PI.powi(2) / 4.0,
        "{upper:?}"
    );
    assert!(!upper.load_stable);
    assert!(last.flexures[1].load_stable);
}

/// A clamped-clamped flexure pushed along its axis (extension on, `L / t0 = 100`): it
/// shortens by `alpha c_e` (`c_e = 1 / (12 (L/t0)^2)`) until the Euler load of the
/// clamped-clamped column, where the straight shape bifurcates. For the extensible beam of
/// DESIGN §2 that load solves `(1 - c_e alpha) alpha = 4 pi^2` (the bending equation
/// linearised about the straight shortened column, `psi'' = -(1 + eps) alpha psi` with
/// `eps = -c_e alpha`): `alpha = 39.4914`, 3.3e-4 above `4 pi^2`, at `dx = -c_e alpha =
/// -3.29e-4`. The solver must stop there, not carry on along the straight, unstable branch;
/// it bisects the sign change of its Jacobian's determinant, so it reports the last regular
/// point within about twice its smallest step (1e-6 of the path) before the bifurcation.
#[test]
fn clamped_flexure_pushed_past_euler_reports_the_bifurcation() {
    let mut f = flexure([0.0, 0.0], Attach::Clamped);
    f.beam.effects = EffectsChoice::Fixed(Effects {
        shear: false,
        extension: true,
        poisson: false,
        plane_strain: false,
    });
    let m = mechanism(
        vec![f],
        [1.0, 0.0],
        [Prescribed(-6e-4), Prescribed(0.0), Prescribed(0.0)],
        12,
    );
    let e = exact_cases(&m).unwrap_err();
    let c_e = 1.0 / (12.0 * 100.0 * 100.0);
    let x = 16.0 * std::f64::consts::PI.powi(2) * c_e;
    let alpha = (1.0 - (1.0 - x).sqrt()) / (2.0 * c_e);
    let critical = c_e * alpha / 6e-4;
    match e {
        MechError::Critical { drive: 1, fraction } => {
            assert!(
                fraction < critical && fraction >= critical - 4e-6,
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
        assert_two_half_cantilevers(c, &half);
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

fn su_3r() -> PrbMatrix {
    PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap()
}

/// The design grid of the parallel-guiding stage: `W = 0.3 L`, `Ay` 0..20,
/// `Ax` -10..10, `B` -3..3 (steps 2, 2 and 1: 847 points), loads at the stage centre, each
/// point by continuation from zero in 10 steps. Every point must be solved or stop at a
/// named critical point; nothing may stall. The exact beam solves all 847 (a published
/// shooting solver fails on about 8% of such a grid); Su's 3R meets a limit point of its own
/// at one corner. `cargo bench --bench mech` times the grid.
#[test]
fn parallel_stage_design_grid_is_covered() {
    let matrix = su_3r();
    let mut solved = [0usize; 2];
    let mut critical = Vec::new();
    for iy in 0..=10 {
        for ix in 0..=10 {
            for ib in 0..=6 {
                let load = [-10.0 + 2.0 * ix as f64, 2.0 * iy as f64, -3.0 + ib as f64];
                let mut m = parallel_stage(0.0, 10);
                m.drives[0].coordinates = [Loaded(load[0]), Loaded(load[1]), Loaded(load[2])];
                let results = [
                    exact::solve(&m, Resolution::with_tol(1e-8)),
                    prb::solve(&m, &matrix, 1e-10),
                ];
                for (k, r) in results.into_iter().enumerate() {
                    match r {
                        Ok(cases) => {
                            let last = cases[0].last().unwrap();
                            // The scene's loads pass through SI and back: rounding only.
                            for (a, b) in last.stage_load.iter().zip(load) {
                                assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()));
                            }
                            solved[k] += 1;
                        }
                        Err(MechError::Critical { fraction, .. }) => {
                            critical.push((k, load, fraction))
                        }
                        Err(e) => panic!("{load:?} ({}): {e}", ["beam", "su-3r"][k]),
                    }
                }
            }
        }
    }
    println!(
        "solved: beam {}, su-3r {} of 847; critical: {critical:?}",
        solved[0], solved[1]
    );
    assert_eq!(
        solved[0], 847,
        "the exact stage has no limit point on this grid"
    );
    assert!(solved[1] >= 840);
}

/// The path does not matter away from limit points: the stage loaded to `(Ax, Ay, B)`,
/// then the same stage driven sideways (`dy` prescribed, `Ax` and `B` still applied) to the
/// `dy` it reached, needs exactly `Ay` as the drive's reaction and takes the same pose.
/// Beam and PRB. (Driving *every* coordinate proportionally is another path: it shortens
/// the flexures before they bend, and a stiff flexure buckles on the way, as it should.)
/// Both paths stop at their solver's tol (1e-10 on the tips); a tip error `e` costs a
/// reaction error of about the stage's stiffness (`<= 100`) times `e`.
#[test]
fn loaded_and_driven_back_give_the_same_reaction() {
    let mut loaded = parallel_stage(0.0, 5);
    let load = [1.5, 6.0, -0.8];
    loaded.drives[0].coordinates = [Loaded(load[0]), Loaded(load[1]), Loaded(load[2])];
    let matrix = su_3r();
    type Solve<'a> = Box<dyn Fn(&Mechanism) -> Result<Vec<Vec<MechCase>>, MechError> + 'a>;
    let solvers: [(&str, Solve); 2] = [
        (
            "beam",
            Box::new(|m| exact::solve(m, Resolution::with_tol(TOL))),
        ),
        ("su-3r", Box::new(|m| prb::solve(m, &matrix, TOL))),
    ];
    for (name, solve) in &solvers {
        let end = solve(&loaded).unwrap()[0].last().unwrap().clone();
        let mut driven = loaded.clone();
        driven.drives[0].coordinates = [Loaded(load[0]), Prescribed(end.stage[1]), Loaded(load[2])];
        driven.drives[0].steps = 7;
        let back = solve(&driven).unwrap()[0].last().unwrap().clone();
        for k in 0..3 {
            assert!(
                (back.stage_load[k] - load[k]).abs() < 1e-7,
                "{name}: reaction {:?} vs load {load:?}",
                back.stage_load
            );
            assert!((back.stage[k] - end.stage[k]).abs() < 1e-9, "{name}: pose");
        }
        for (a, b) in back.flexures.iter().zip(&end.flexures) {
            assert!(a.tip.max_diff(&b.tip) < 1e-9, "{name}: {a:?} vs {b:?}");
        }
    }
}

/// A full loop: the tip's angle driven to `2 pi` with its position free and unloaded. The
/// flexure rolls up under a pure moment `beta = phi` (the elastica's curvature is uniform),
/// its tip on the circle `(sin phi / phi, (1 - cos phi) / phi)`, folding back over itself
/// past `phi = pi`. Tolerance: the tip residual 1e-10 and the shot's 1e-9.
#[test]
fn tip_turned_through_a_full_loop() {
    let m = mechanism(
        vec![flexure([0.0, 0.0], Attach::Clamped)],
        [1.0, 0.0],
        [
            Loaded(0.0),
            Loaded(0.0),
            Prescribed(2.0 * std::f64::consts::PI),
        ],
        16,
    );
    let cases = exact_cases(&m).unwrap();
    for c in &cases {
        let phi = c.stage[2];
        assert!((c.stage_load[2] - phi).abs() < 1e-8, "{c:?}");
        let (a, b) = (phi.sin() / phi, (1.0 - phi.cos()) / phi);
        assert!((c.stage[0] - (a - 1.0)).abs() < 1e-8, "{c:?}");
        assert!((c.stage[1] - b).abs() < 1e-8, "{c:?}");
    }
    // And a PRB chain follows too (Su's 3R turns each joint through its share).
    let prb_cases = prb::solve(&m, &su_3r(), TOL).unwrap().remove(0);
    assert!((prb_cases.last().unwrap().stage[2] - 2.0 * std::f64::consts::PI).abs() < 1e-12);
}

/// The fixed-guided flexure driven to `0.9 L` sideways, where it stands nearly across its
/// unloaded direction and the force has grown steeply: still two half cantilevers.
#[test]
fn fixed_guided_to_a_large_stroke() {
    let cases = exact_cases(&fixed_guided(0.9, 9)).unwrap();
    let half = elastica();
    let last = cases.last().unwrap();
    let f = last.flexures[0];
    let reference = half
        .solve(Load::new(0.0, f.wrench.alpha_y / 4.0, 0.0))
        .unwrap()
        .tip;
    assert!(
        (reference.b - 0.9).abs() < 1e-8,
        "{last:?} vs {reference:?}"
    );
    assert!((reference.a - f.tip.a).abs() < 1e-8);
    // The force is monotone along the stroke (no limit point is crossed).
    assert!(cases
        .windows(2)
        .all(|w| w[1].stage_load[1] > w[0].stage_load[1]));
}

/// The parallel stage pushed along its flexures (`Ax < 0`, no other load): the flexures are
/// fixed-guided columns whose sway buckling load is `pi^2 E I / L^2` each, `2 pi^2 = 19.74`
/// for the stage. The straight path must stop at that bifurcation, not run on past it.
#[test]
fn parallel_stage_compressed_to_its_buckling_load() {
    let mut m = parallel_stage(0.0, 25);
    m.drives[0].coordinates = [Loaded(-25.0), Loaded(0.0), Loaded(0.0)];
    let critical = 2.0 * std::f64::consts::PI.powi(2) / 25.0;
    for (name, result) in [
        ("beam", exact::solve(&m, Resolution::with_tol(TOL))),
        ("su-3r", prb::solve(&m, &su_3r(), TOL)),
    ] {
        match result {
            Err(MechError::Critical { fraction, .. }) if name == "beam" => assert!(
                fraction < critical && fraction >= critical - 1.0 / 25.0 - 1e-12,
                "stopped at {fraction}, critical at {critical}"
            ),
            // Su's 3R buckles at its own load (its springs give a column of another
            // stiffness): only that it stops, and before the beam would have.
            Err(MechError::Critical { fraction, .. }) => assert!(fraction < 1.0),
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// Stubby rubber (`L / t0 = 3`, `nu = 0.49999`, every effect) and a hair-thin flexure
/// (`L / t0 = 1e5`, extension on) in a parallel stage, against the linear Timoshenko frame:
/// each flexure a clamped beam element with tip stiffness `12 / (1 + P)`, `-6 / (1 + P)`,
/// `(4 + P) / (1 + P)` (`P = 12 c_s`, `c_s` the shear compliance) and axial stiffness
/// `1 / c_e`, the stage rigid. The stubby stage turns (its flexures' axial stiffness is only
/// 108 times the bending one), the hair's barely (1.2e11 times): `uy -> Ay / 24`. `uy` is
/// odd in `Ay`, so nonlinear terms are O(Ay^2) = 1e-8 relative (Poisson's shrink among
/// them); the tips' tolerance 1e-10 is 2.4e-5 of `uy ~ 4e-6`, the bound used (measured:
/// 3e-10).
#[test]
fn stubby_and_hair_thin_stages_small_motion() {
    for (slenderness, nu, effects) in [
        (3.0, 0.49999, Effects::ALL),
        (
            1e5,
            0.3,
            Effects {
                shear: false,
                extension: true,
                poisson: false,
                plane_strain: false,
            },
        ),
    ] {
        let ay = 1e-4;
        let mut m = parallel_stage(ay, 1);
        for f in &mut m.flexures {
            f.beam.thickness = 1.0 / slenderness;
            f.beam.youngs_modulus = 12.0 * slenderness.powi(3); // E I0 = 1 again
            f.beam.poisson_ratio = nu;
            f.beam.effects = EffectsChoice::Fixed(effects);
        }
        let model = BeamModel::new(slenderness, nu, None, effects).unwrap();
        let p = 12.0 * model.shear_compliance();
        let k_axial = 1.0 / model.axial_compliance();
        let (kvv, kvt, ktt) = (12.0 / (1.0 + p), -6.0 / (1.0 + p), (4.0 + p) / (1.0 + p));
        // Stage stiffness: tips at y = +-W from P; tip (u, v, theta) = (dx - y dphi, dy, dphi).
        let w: f64 = 0.3;
        let mut k = [[0.0; 3]; 3];
        for y in [w, -w] {
            let t = [[1.0, 0.0, -y], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            let ki = [[k_axial, 0.0, 0.0], [0.0, kvv, kvt], [0.0, kvt, ktt]];
            for r in 0..3 {
                for c in 0..3 {
                    for a in 0..3 {
                        for b in 0..3 {
                            k[r][c] += t[a][r] * ki[a][b] * t[b][c];
                        }
                    }
                }
            }
        }
        // Solve K d = (0, ay, 0) by Cramer's rule.
        let det3 = |m: [[f64; 3]; 3]| {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let mut ky = k;
        for row in &mut ky {
            row[1] = 0.0;
        }
        ky[1][1] = ay;
        let expected = det3(ky) / det3(k);
        let c = &exact_cases(&m).unwrap()[0];
        assert!(
            (c.stage[1] / expected - 1.0).abs() < 3e-5,
            "L/t0 = {slenderness}: uy = {} vs {expected}",
            c.stage[1]
        );
        if slenderness > 10.0 {
            assert!((expected / (ay / 24.0) - 1.0).abs() < 1e-6);
        }
    }
}
