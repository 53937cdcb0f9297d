//! Known answers for the beam mechanism's modes (DESIGN §8, §10).
//!
//! The flexures have `L = 1 m` and `E I0 = 1 N m^2` (width 1 m, thickness 0.01 m,
//! `E = 12e6 Pa`), the inextensible elastica, so the nondimensional `Omega` reads directly.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use prbfit::beam::modes::ModeSettings;
use prbfit::beam::{Effects, Resolution};
use prbfit::fit::CancelToken;
use prbfit::mech::modes::{drive_modes, held_by, mech_modes, MechMass};
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};

fn beam() -> BeamSpec {
    BeamSpec {
        length: 1.0,
        width: 1.0,
        thickness: 0.01,
        youngs_modulus: 12e6,
        poisson_ratio: 0.3,
        shear_coefficient: None,
        density: None,
        allowable_stress: None,
        effects: EffectsChoice::Fixed(Effects::NONE),
    }
}

/// The parallel-guiding stage: clamped flexures at `(0, +-0.3)` along +x, `P = (1, 0)`,
/// a force `fy` on the stage.
fn parallel_stage(fy: f64, steps: u32) -> Mechanism {
    let flexure = |y: f64| Flexure {
        root: [0.0, y],
        angle: 0.0,
        attach: Attach::Clamped,
        beam: beam(),
    };
    Mechanism {
        flexures: vec![flexure(0.3), flexure(-0.3)],
        stage_point: [1.0, 0.0],
        drives: vec![Drive::proportional(
            [
                Coordinate::Loaded(0.0),
                Coordinate::Loaded(fy),
                Coordinate::Loaded(0.0),
            ],
            steps,
        )],
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn a_heavy_stage_on_two_flexures_rings_at_the_massless_flexure_limit() {
    let mech = parallel_stage(0.0, 1);
    let settings = ModeSettings::frequencies(3);
    // The stage 1e8 times a flexure's mass: the flexures' own inertia shifts omega^2 by
    // 26/35 of it (Rayleigh), a relative 4e-9.
    let heavy = 1e8;
    let mass = MechMass::uniform(2, heavy, heavy * 0.1);
    let modes = mech_modes(&mech, &mass, [false; 3], None, &settings).unwrap();
    let limit = (24.0 / heavy).sqrt();
    assert!(
        rel(modes.omega[0], limit) < 1e-7,
        "{} vs {limit}",
        modes.omega[0]
    );
    // A lighter stage: Rayleigh's quotient with the static (fixed-guided) shape, each
    // flexure adding 13/35 of its mass, bounds omega from above, and its error is second
    // order in the flexures' share of the moving mass: about 3e-3 at a stage of the
    // flexures' own mass, below 1e-4 at ten times it.
    for (stage, close) in [(10.0, 2e-4), (1.0, 5e-3)] {
        let mass = MechMass::uniform(2, stage, 0.1);
        let modes = mech_modes(&mech, &mass, [false; 3], None, &settings).unwrap();
        let rayleigh = (24.0 / (stage + 2.0 * 13.0 / 35.0)).sqrt();
        assert!(modes.omega[0] <= rayleigh * (1.0 + 1e-12));
        assert!(
            rel(modes.omega[0], rayleigh) < close,
            "{stage}: {} vs {rayleigh}",
            modes.omega[0]
        );
    }
}

#[test]
fn a_held_stage_leaves_two_clamped_clamped_flexures() {
    // Every stage coordinate held: each flexure is clamped at both ends, whose first
    // frequency is b^2 with cos b cosh b = 1, b = 4.730040744862704; two flexures, a pair.
    let mech = parallel_stage(0.0, 1);
    let mass = MechMass::uniform(2, 3.0, 0.5);
    let modes = mech_modes(&mech, &mass, [true; 3], None, &ModeSettings::frequencies(3)).unwrap();
    let b: f64 = 4.730040744862704;
    for w in &modes.omega[..2] {
        assert!(rel(*w, b * b) < 1e-6, "{w}");
    }
    // The next is the clamped-clamped second mode, b = 7.853204624095838.
    let b2: f64 = 7.853204624095838;
    assert!(rel(modes.omega[2], b2 * b2) < 1e-6, "{}", modes.omega[2]);
}

#[test]
fn the_drive_holds_its_prescribed_coordinates() {
    let mut mech = parallel_stage(0.0, 1);
    mech.drives[0].coordinates[1] = Coordinate::Prescribed(0.0);
    assert_eq!(held_by(&mech.drives[0]), [false, true, false]);
}

#[test]
fn every_case_of_a_drive_has_its_modes() {
    // A sideways force: the stage moves, the flexures carry tension and compression.
    let mech = parallel_stage(3.0, 3);
    let mass = MechMass::uniform(2, 2.0, 0.2);
    let cases = drive_modes(
        &mech,
        &mass,
        Resolution::with_tol(1e-10),
        &ModeSettings::default(),
    )
    .unwrap();
    assert_eq!(cases[0].len(), 3);
    let unloaded = mech_modes(&mech, &mass, [false; 3], None, &ModeSettings::default()).unwrap();
    for case in &cases[0] {
        assert!(case.omega[0] > 0.0);
        assert!(rel(case.omega[0], unloaded.omega[0]) < 0.2);
        let shape = &case.shapes[0];
        assert_eq!(shape.flexures.len(), 2);
        let largest = shape
            .flexures
            .iter()
            .flatten()
            .fold(0.0f64, |a, p| a.max(p.dx.hypot(p.dy)));
        assert!((largest - 1.0).abs() < 1e-12);
    }
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(12))]

        /// Omega (flexure 1's) depends on the mechanism's shape only: the whole mechanism
        /// scaled by `k`, of another material, with the stage's mass scaled as `rho k^3`
        /// and its inertia as `rho k^5`, rings at the same Omega.
        #[test]
        fn frequencies_are_invariant_to_the_si_scale(
            log_k in -3.0..3.0f64, e_ratio in 0.01..100.0f64, rho_ratio in 0.1..10.0f64,
            stage in 0.0..5.0f64, inertia in 0.0..0.5f64, gap in 0.1..0.8f64,
        ) {
            let k = 10f64.powf(log_k);
            let build = |scale: f64, e: f64| {
                let mut mech = parallel_stage(0.0, 1);
                for f in &mut mech.flexures {
                    f.root = [f.root[0] * scale, f.root[1].signum() * gap * scale];
                    f.beam.length *= scale;
                    f.beam.width *= scale;
                    f.beam.thickness *= scale;
                    f.beam.youngs_modulus = e;
                }
                mech.stage_point = [mech.stage_point[0] * scale, 0.0];
                mech
            };
            let (a, b) = (build(1.0, 12e6), build(k, 12e6 * e_ratio));
            let (rho_a, rho_b) = (1000.0, 1000.0 * rho_ratio);
            // The flexure's mass rho w t L and the stage's in proportion to it.
            let mass = |m: &Mechanism, rho: f64| {
                let beam = m.flexures[0].beam;
                let line = rho * beam.area() * beam.length;
                MechMass::from_si(m, rho, stage * line, inertia * line * beam.length.powi(2))
                    .unwrap()
            };
            let settings = ModeSettings::frequencies(3);
            let wa = mech_modes(&a, &mass(&a, rho_a), [false; 3], None, &settings).unwrap();
            let wb = mech_modes(&b, &mass(&b, rho_b), [false; 3], None, &settings).unwrap();
            for (x, y) in wa.omega.iter().zip(&wb.omega) {
                prop_assert!(rel(*x, *y) < 1e-8, "{x} vs {y}");
            }
        }
    }
}

#[test]
fn the_first_frequency_vanishes_where_the_mechanisms_statics_find_buckling() {
    // The parallel stage pushed along its flexures: each a fixed-guided column, which sways
    // at pi^2 E I / L^2 (effective length L), the pair at 2 pi^2. The statics (exact
    // mechanism) stop at their critical point; the modes' first omega^2 crosses zero there.
    let pushed = |fx: f64, steps: u32| {
        let mut m = parallel_stage(0.0, steps);
        m.drives[0].coordinates[0] = Coordinate::Loaded(fx);
        m
    };
    let euler = 2.0 * std::f64::consts::PI.powi(2);
    let end = -1.3 * euler;
    let statics = match prbfit::mech::exact::solve(&pushed(end, 40), Resolution::with_tol(1e-10)) {
        Err(prbfit::mech::MechError::Critical { fraction, .. }) => -end * fraction,
        other => panic!("expected the statics to stop at buckling, got {other:?}"),
    };
    let mass = MechMass::uniform(2, 1.0, 0.1);
    let settings = ModeSettings::frequencies(1);
    // The first frequency about the pushed equilibrium (its last case).
    let first = |p: f64| {
        let mech = pushed(-p, 1);
        let cases = prbfit::mech::exact::solve(&mech, Resolution::with_tol(1e-10)).unwrap();
        mech_modes(&mech, &mass, [false; 3], cases[0].last(), &settings)
            .unwrap()
            .omega[0]
    };
    // Straight columns: the equilibrium under an axial push is the compressed straight one.
    // Omega_1^2 falls smoothly to zero at buckling: its zero, extrapolated linearly from 99
    // and 99.5 % of the load, is off by the curvature's share, (0.005)^2 relative at most.
    assert!(first(0.5 * euler) > first(0.99 * euler));
    let (a, b) = (first(0.99 * euler).powi(2), first(0.995 * euler).powi(2));
    assert!(b > 0.0 && b < a);
    let crossing = 0.99 * euler + (0.005 * euler) * a / (a - b);
    assert!(rel(crossing, euler) < 2.5e-5, "{crossing} vs {euler}");
    // The statics' critical point: the last accepted fraction, within a step (1/40 of the
    // path) below it, or at it when their step control closes in.
    assert!(
        statics <= crossing * (1.0 + 1e-6) && crossing - statics <= -end / 40.0,
        "statics {statics} vs modes {crossing}"
    );
}

/// The parallel stage (assets/scenes/parallel-stage.toml) with `[beam] density` and a stage
/// of `stage_kg` (about 100 times a flexure's 1.96 g when heavy).
fn dense_parallel_stage(stage_kg: f64) -> prbfit::scene::Scene {
    let text = common::dense_parallel_stage(stage_kg, 1e-5);
    prbfit::scene::Scene::from_toml_str(&text, "dense-parallel-stage.toml").unwrap()
}

/// Issue 25.6: a mechanism's mode shapes, the beam mechanism's and the PRB mechanism's,
/// paired lowest first with the frequencies `prbfit modes` reports (the same
/// `Study::modes` at the unloaded equilibrium), and overlaying: the heavy stage's first
/// mode translates it sideways in both, the flexures S-bent between.
#[test]
fn a_mechanisms_mode_shapes_pair_the_beams_and_the_prb_models() {
    use prbfit::study::modes::Equilibria;
    use prbfit::study::{Sampling, Study};
    let study = Study::new(
        &dense_parallel_stage(0.2),
        Sampling::Every(Resolution::with_tol(1e-8)),
    )
    .unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let pairs = study.mode_shapes(&su);
    assert_eq!(pairs.len(), 3, "{pairs:?}");
    let reported = study
        .modes(
            std::slice::from_ref(&su),
            Equilibria::Unloaded,
            3,
            &CancelToken::new(),
        )
        .unwrap();
    let model = reported[0].models[0].as_ref().unwrap();
    for (k, pair) in pairs.iter().enumerate() {
        // The same numbers: the shapes' solve is the frequencies' (with eigenvectors), so
        // they agree to round-off.
        assert!(
            rel(pair.beam_hz, reported[0].beam.hz[k]) < 1e-9,
            "{k}: {pair:?}"
        );
        assert!(rel(pair.model_hz, model.hz[k]) < 1e-9, "{k}: {pair:?}");
        assert!(!pair.nominal);
        assert_eq!(pair.beam.flexures.len(), 2);
        assert_eq!(pair.model.flexures.len(), 2);
        // Su's 3R: its root, 3 joints and tip per flexure.
        assert_eq!(pair.model.flexures[0].len(), 5);
    }
    // The first mode: the stage (100 flexures' mass) moves sideways, not along, each
    // flexure's largest motion at its tip on the stage, so P moves by the normalised 1 in
    // both. The beam's stage turns a little with it (5.5e-4 rad per L: its flexures,
    // extensible here, stretch and shorten under the tips' moments, which Su's axially
    // rigid 3R does not), so the turn is bounded, not zero.
    let (beam, prb) = (&pairs[0].beam, &pairs[0].model);
    for shape in [beam, prb] {
        assert!((shape.stage[1] - 1.0).abs() < 1e-6, "{:?}", shape.stage);
        assert!(shape.stage[0].abs() < 1e-9, "{:?}", shape.stage);
        assert!(shape.stage[2].abs() < 1e-3, "{:?}", shape.stage);
    }
    // The PRB chains' joints lie on the beam's S-shaped motion at the same arc length:
    // within 0.07 of the tip's motion (measured 0.061 at s = 0.85, where the 3R's rigid last
    // segment, kept parallel by the stage, carries the tip's whole motion to its last
    // joint; 0.028 at s = 0.1, its rigid root segment's end).
    for (line, joints) in beam.flexures.iter().zip(&prb.flexures) {
        for p in joints {
            let k = ((p.s * 40.0).round() as usize).min(40);
            let q = line[k];
            assert!((q.s - p.s).abs() < 1e-12, "{} vs {}", q.s, p.s);
            assert!(
                (p.dy - q.dy).abs() < 0.07,
                "s {}: PRB {} beam {}",
                p.s,
                p.dy,
                q.dy
            );
            assert!(
                (p.dx - q.dx).abs() < 1e-3,
                "s {}: PRB {} beam {}",
                p.s,
                p.dx,
                q.dx
            );
        }
    }
}

/// A cantilever's mode shapes come through the same path (its one-flexure mechanism): the
/// PRB model's frequencies are its chain's (`Study::frequencies`), and a shape drawn by
/// `pose::mode` moves the stage point (the tip) by the scale times its motion.
#[test]
fn a_cantilevers_mode_shapes_are_its_one_flexure_mechanisms() {
    use prbfit::study::{Sampling, Study};
    let text = prbfit::scene::DEFAULT_SCENE_TOML.replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    );
    let scene = prbfit::scene::Scene::from_toml_str(&text, "dense.toml").unwrap();
    let study = Study::new(&scene, Sampling::Every(Resolution::with_tol(1e-8))).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let pairs = study.mode_shapes(&su);
    let chain = study.frequencies(&su).unwrap();
    assert_eq!(pairs.len(), 3);
    for (k, pair) in pairs.iter().enumerate() {
        // The mechanism's pencil and the chain's K q = omega^2 M q: the same eigenvalues,
        // through two eigensolvers (round-off).
        assert!(
            rel(pair.model_hz, chain.model_hz[k]) < 1e-9,
            "{k}: {pair:?}"
        );
        assert!(rel(pair.beam_hz, chain.beam_hz[k]) < 1e-12, "{k}");
        // The tip (the stage) moves across in every mode, the model's with the beam's
        // sign.
        assert!(
            pair.beam.stage[1] * pair.model.stage[1] > 0.0,
            "{k}: {pair:?}"
        );
        let mechanism = study.mechanism();
        let rest = prbfit::mech::pose::mode(mechanism, [0.0; 3], &pair.model, 0.0);
        let moved = prbfit::mech::pose::mode(mechanism, [0.0; 3], &pair.model, 0.1);
        assert_eq!(rest.stage_point, [1.0, 0.0]);
        let dy = moved.stage_point[1] - rest.stage_point[1];
        assert!((dy - 0.1 * pair.model.stage[1]).abs() < 1e-15, "{k}");
        let tip = *moved.flexures[0].last().unwrap();
        assert!(
            (tip[1] - moved.stage_point[1]).abs() < 1e-12,
            "{k}: {tip:?}"
        );
    }
}

/// A data scene's mode shapes are its nominal beam's (the data are not dynamic), through
/// the same path: the wide strip's 3D FEA (a cantilever data scene).
#[test]
fn a_data_scenes_mode_shapes_are_the_nominal_beams() {
    use prbfit::study::modes::Equilibria;
    use prbfit::study::{Sampling, Study};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let text = std::fs::read_to_string(path.join("wide-strip-fea.toml"))
        .unwrap()
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        )
        .replacen(
            "data = \"wide-strip-fea.csv\"",
            &format!("data = {:?}", path.join("wide-strip-fea.csv")),
            1,
        );
    let scene = prbfit::scene::Scene::from_toml_str(&text, "strip.toml").unwrap();
    let study = Study::new(&scene, Sampling::Every(Resolution::with_tol(1e-8))).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let pairs = study.mode_shapes(&su);
    assert_eq!(pairs.len(), 3);
    let reported = study
        .modes(
            std::slice::from_ref(&su),
            Equilibria::Unloaded,
            3,
            &CancelToken::new(),
        )
        .unwrap();
    let model = reported[0].models[0].as_ref().unwrap();
    for (k, pair) in pairs.iter().enumerate() {
        assert!(pair.nominal);
        assert!(rel(pair.beam_hz, reported[0].beam.hz[k]) < 1e-9, "{k}");
        assert!(rel(pair.model_hz, model.hz[k]) < 1e-9, "{k}");
        assert_eq!(pair.beam.flexures.len(), 1);
        assert_eq!(pair.model.flexures.len(), 1);
    }
}

/// A coupler and a held stage: the slider-crank's drive prescribes all three of the slider's
/// coordinates, so it rings with the slider held, the flexure's tip kept on a circle about
/// the coupler's far end. The shapes pair with the reported frequencies, the stage does not
/// move, and the drawn coupler runs from the flexure's moved tip to its fixed stage end.
#[test]
fn a_coupled_flexure_rings_with_its_slider_held() {
    use prbfit::study::modes::Equilibria;
    use prbfit::study::{Sampling, Study};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let text = std::fs::read_to_string(path.join("slider-crank.toml"))
        .unwrap()
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        );
    let scene = prbfit::scene::Scene::from_toml_str(&text, "crank.toml").unwrap();
    let study = Study::new(&scene, Sampling::Every(Resolution::with_tol(1e-8))).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let pairs = study.mode_shapes(&su);
    // Su's 3R has three joints, the coupler takes one: two modes to pair with the beam's.
    assert_eq!(pairs.len(), 2);
    let reported = study
        .modes(
            std::slice::from_ref(&su),
            Equilibria::Unloaded,
            3,
            &CancelToken::new(),
        )
        .unwrap();
    let model = reported[0].models[0].as_ref().unwrap();
    for (k, pair) in pairs.iter().enumerate() {
        assert!(rel(pair.beam_hz, reported[0].beam.hz[k]) < 1e-9, "{k}");
        assert!(rel(pair.model_hz, model.hz[k]) < 1e-9, "{k}");
        assert_eq!(pair.beam.stage, [0.0; 3]);
        assert_eq!(pair.model.stage, [0.0; 3]);
        for shape in [&pair.beam, &pair.model] {
            let pose = prbfit::mech::pose::mode(study.mechanism(), [0.0; 3], shape, 0.1);
            let rest = prbfit::mech::pose::mode(study.mechanism(), [0.0; 3], shape, 0.0);
            let tip = *pose.flexures[0].last().unwrap();
            assert_eq!(pose.couplers[0][0], tip);
            assert_eq!(pose.couplers[0][1], rest.couplers[0][1]);
        }
    }
}

/// A mechanism's data are not dynamic either: the slider-crank rig's modes are its nominal
/// beam mechanism's, with the slider held as the data's drive holds it (its `dx, dy, dphi`
/// input columns), not free (which would leave the slider's rigid motions at zero
/// frequency); the PRB model's too, and the shapes pair with the reported frequencies.
#[test]
fn a_mechanisms_data_hold_what_their_drive_prescribes() {
    use prbfit::study::modes::Equilibria;
    use prbfit::study::{Sampling, Study};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let text = std::fs::read_to_string(path.join("slider-crank-rig.toml"))
        .unwrap()
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        )
        .replacen(
            "data = \"slider-crank-rig.csv\"",
            &format!("data = {:?}", path.join("slider-crank-rig.csv")),
            1,
        );
    // Read from a file, as `prbfit` reads a scene: that loads the data.
    let file = std::env::temp_dir().join(format!("prbfit-rig-{}.toml", std::process::id()));
    std::fs::write(&file, text).unwrap();
    let rig = prbfit::scene::Scene::from_file(&file).unwrap();
    std::fs::remove_file(&file).unwrap();
    let rig = Study::new(&rig, Sampling::Every(Resolution::with_tol(1e-8))).unwrap();
    assert_eq!(rig.unloaded_held(), [true; 3]);
    // The same mechanism driven by its own [[drives]] (slider-crank.toml).
    let text = std::fs::read_to_string(path.join("slider-crank.toml"))
        .unwrap()
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        );
    let driven = prbfit::scene::Scene::from_toml_str(&text, "crank.toml").unwrap();
    let driven = Study::new(&driven, Sampling::Every(Resolution::with_tol(1e-8))).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let at = Equilibria::Unloaded;
    let a = &rig
        .modes(std::slice::from_ref(&su), at, 3, &CancelToken::new())
        .unwrap()[0];
    let b = &driven
        .modes(std::slice::from_ref(&su), at, 3, &CancelToken::new())
        .unwrap()[0];
    for (x, y) in a.beam.omega.iter().zip(&b.beam.omega) {
        assert!(
            rel(*x, *y) < 1e-12,
            "{:?} vs {:?}",
            a.beam.omega,
            b.beam.omega
        );
    }
    let (ma, mb) = (a.models[0].as_ref().unwrap(), b.models[0].as_ref().unwrap());
    assert_eq!(ma.omega, mb.omega);
    let pairs = rig.mode_shapes(&su);
    assert_eq!(pairs.len(), 2);
    for (k, pair) in pairs.iter().enumerate() {
        assert!(pair.nominal);
        assert!(rel(pair.beam_hz, a.beam.hz[k]) < 1e-9, "{k}");
        assert!(rel(pair.model_hz, ma.hz[k]) < 1e-9, "{k}");
    }
}
