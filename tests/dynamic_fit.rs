//! The dynamic fit (issue 25.3, DESIGN §10): `[fit] modes = N` frees the mus and matches the
//! first N natural frequencies beside the statics. On the built-in scene (with steel's
//! density) the fitted 3R's first three frequencies against the beam's, against Su's 3R with
//! uniform mass (`mu = gamma`), and how much its statics moved; the figures are printed
//! (`cargo test --test dynamic_fit -- --nocapture`).
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use prbfit::fit::{CancelToken, Fidelity, FitOptions};
use prbfit::prb::{published, PrbMatrix};
use prbfit::scene::{Scene, DEFAULT_SCENE_TOML};
use prbfit::study::{Sampling, Study};

/// The built-in scene with steel's density and `[fit]` extra lines.
fn scene(fit: &str) -> Scene {
    let text = DEFAULT_SCENE_TOML
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        )
        .replacen(
            "angle_weight = 1.0",
            &format!("angle_weight = 1.0\n{fit}"),
            1,
        );
    Scene::from_toml_str(&text, "dynamic.toml").unwrap()
}

fn fit(study: &Study, start: &PrbMatrix) -> prbfit::fit::FitReport {
    let options = FitOptions {
        fidelity: Fidelity::Normal,
        angle_weight: study.scene().fit.angle_weight,
        seed: 1,
    };
    study
        .fit(start, &options, &mut |_| {}, &CancelToken::new())
        .unwrap()
}

fn su() -> PrbMatrix {
    published::all()
        .into_iter()
        .find(|m| m.prb.topology() == "L-R-R-R" && m.name.contains("su"))
        .unwrap()
        .prb
}

#[test]
fn fitted_3r_rings_like_the_beam_where_su_does_not() {
    let dynamic = Study::new(&scene("modes = 3"), Sampling::Fidelity(Fidelity::Normal)).unwrap();
    let statics = Study::new(&scene(""), Sampling::Fidelity(Fidelity::Normal)).unwrap();
    let truth = dynamic.truth_modes().unwrap();
    // The slender steel leaf (L/t = 100) rings near Euler-Bernoulli's cantilever (3.516015,
    // 22.034492, 61.697214) scaled as one: the auto effects stiffen the wide strip (0.76 %
    // on every frequency here), the shear and rotary inertia move the ratios by order
    // (t/L)^2 = 1e-4 only.
    for (w, want) in truth.omega.iter().zip([3.516015, 22.034492, 61.697214]) {
        assert!((w / want - 1.0).abs() < 1e-2, "{:?}", truth.omega);
        let ratio = (w / truth.omega[0]) / (want / 3.516015);
        assert!((ratio - 1.0).abs() < 2e-3, "{:?}", truth.omega);
    }

    // Su's 3R with uniform mass, judged on the dynamic scene.
    let su = su();
    let su_judged = dynamic.judge(&su).unwrap();
    let su_f = su_judged.frequencies.clone().unwrap();
    // The statics-only fit and the dynamic one, from the topology's default start.
    let start = PrbMatrix::from_topology("3R").unwrap();
    let plain = fit(&statics, &start);
    let fitted = fit(&dynamic, &start);
    let f = dynamic.frequencies(&fitted.matrix).unwrap();
    let plain_f = dynamic.frequencies(&plain.matrix).unwrap();
    // The statics' J of each (the dynamic figures' J less its frequency term).
    let w = dynamic.scene().fit.frequency_weight;
    let statics_j = fitted.figures.objective - w * f.mean_square();
    let hz = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:9.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let pct = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{:+7.3}%", 100.0 * x))
            .collect::<Vec<_>>()
            .join(" ")
    };
    eprintln!("first three frequencies (Hz) of the built-in scene, steel 7850 kg/m^3:");
    eprintln!("  beam                     {}", hz(&f.beam_hz));
    eprintln!(
        "  su-3r (uniform mass)     {}   {}",
        hz(&su_f.model_hz),
        pct(&su_f.freq_err)
    );
    eprintln!(
        "  3R fitted, statics only  {}   {}",
        hz(&plain_f.model_hz),
        pct(&plain_f.freq_err)
    );
    eprintln!(
        "  3R fitted, modes = 3     {}   {}",
        hz(&f.model_hz),
        pct(&f.freq_err)
    );
    eprintln!("  fitted matrix (modes = 3): {}", fitted.matrix.to_text());
    eprintln!(
        "  statics: J {:.3e} -> {:.3e}, max_pos_err {:.4} -> {:.4}, max_ang_err {:.4} -> {:.4}",
        plain.figures.objective,
        statics_j,
        plain.figures.max_pos_err,
        fitted.figures.max_pos_err,
        plain.figures.max_ang_err,
        fitted.figures.max_ang_err
    );
    eprintln!(
        "  fit time: statics {:.2} s, modes = 3 {:.2} s",
        plain.seconds, fitted.seconds
    );

    // The dynamic fit frees the mus (written out, summing to 1) and matches the three
    // frequencies far better than Su's uniform mass does, and within the scene's 1 %
    // target, while its statics barely move (no 3R meets this scene's 1 % position target:
    // the statics-only fit reaches 1.9 %).
    assert!(fitted.matrix.has_mu());
    let sum: f64 = fitted.matrix.rows().iter().map(|r| r.mass()).sum();
    assert!((sum - 1.0).abs() < 1e-12);
    let max_err = f.max_err();
    assert_eq!(fitted.figures.max_freq_err, Some(max_err));
    assert!(
        max_err < 0.5 * su_f.max_err(),
        "{max_err} vs Su {}",
        su_f.max_err()
    );
    assert!(
        max_err <= dynamic.scene().accuracy.max_freq_err,
        "{max_err}"
    );
    // Asking for frequencies costs the statics (the springs move too: DESIGN §10, a 3R
    // cannot match three frequencies by its masses alone): the statics' J can only rise
    // above the statics-only optimum (to the fit's tolerance), and here by a few percent
    // (measured 2.6 %; 10 % allowed), the largest errors likewise.
    let plain_j = plain.figures.objective;
    assert!(
        statics_j >= plain_j * (1.0 - 1e-3),
        "{statics_j} vs {plain_j}"
    );
    assert!(statics_j <= 1.1 * plain_j, "{statics_j} vs {plain_j}");
    assert!(fitted.figures.max_pos_err <= 1.1 * plain.figures.max_pos_err);
    assert!(fitted.figures.max_ang_err <= 1.1 * plain.figures.max_ang_err);
    // The statics-only fit never frees the mus: it keeps the three-column meaning.
    assert!(!plain.matrix.has_mu());
    assert_eq!(plain.figures.max_freq_err, None);
}

/// One code path: a mechanism's dynamic fit goes through the same study. The parallel
/// stage (steel's density, a stage of about twice a flexure's mass) fitted with `modes = 1`
/// matches its first frequency within the 1 % target, where Su's 3R with uniform mass
/// misses it; a measured-data scene's frequencies are the nominal beam's, and say so.
#[test]
fn mechanism_and_data_scenes_go_through_the_same_study() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/");
    let text = common::dense_parallel_stage(0.0039, 1e-6).replacen(
        "force_weight = 1.0",
        "force_weight = 1.0\nmodes = 1",
        1,
    );
    let scene = Scene::from_toml_str(&text, "stage.toml").unwrap();
    let study = Study::new(&scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let su = su();
    let su_f = study.frequencies(&su).unwrap();
    let options = FitOptions {
        fidelity: Fidelity::Draft,
        angle_weight: 1.0,
        seed: 1,
    };
    let fitted = study
        .fit(&su, &options, &mut |_| {}, &CancelToken::new())
        .unwrap();
    let f = study.frequencies(&fitted.matrix).unwrap();
    eprintln!(
        "parallel stage, first frequency (Hz): beam {:.3}, su-3r {:.3} ({:+.3} %), fitted {:.3} ({:+.3} %)",
        f.beam_hz[0],
        su_f.model_hz[0],
        100.0 * su_f.freq_err[0],
        f.model_hz[0],
        100.0 * f.freq_err[0]
    );
    assert!(fitted.matrix.has_mu());
    assert!(f.max_err() <= scene.accuracy.max_freq_err, "{f:?}");
    assert!(f.max_err() < su_f.max_err(), "{f:?} vs {su_f:?}");
    assert!(!f.nominal);

    // A data scene (FEA tips of a wide strip) with a density: the nominal beam's modes.
    let text = std::fs::read_to_string(format!("{dir}wide-strip-fea.toml"))
        .unwrap()
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 2700.0",
            1,
        );
    let path = std::env::temp_dir().join(format!("prbfit-dyn-{}.toml", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let csv = std::env::temp_dir().join("wide-strip-fea.csv");
    std::fs::copy(format!("{dir}wide-strip-fea.csv"), &csv).unwrap();
    let scene = Scene::from_file(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let study = Study::new(&scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let truth = study.truth_modes().unwrap();
    assert!(truth.nominal);
    let judged = study.judge(&su).unwrap();
    assert!(judged.frequencies.unwrap().nominal);
}

/// A staged dynamic fit ends on a polish alone from the statics-and-masses optimum: its one
/// candidate keeps the twelve-iteration scout and the full polish that restarts from it. The
/// ringing flexure (every effect, a tip body) fitted with L-RP-RP-RP and `modes = 2` at
/// normal then matches both frequencies to 0.004 % (measured); one run of the same budget
/// stopped "converged" at J 6.8e-3 with an 11 % frequency error. 0.1 % is a tenth of the
/// scene's 1 % target: far from either.
#[test]
fn a_staged_fit_polishes_its_lone_candidate_to_the_frequencies() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/ringing-flexure.toml"
    );
    let text = std::fs::read_to_string(path).unwrap() + "\n[fit]\nmodes = 2\n";
    let scene = Scene::from_toml_str(&text, "ringing.toml").unwrap();
    let study = Study::as_given(&scene, Sampling::Fidelity(Fidelity::Normal)).unwrap();
    let start = PrbMatrix::from_topology("L-RP-RP-RP").unwrap();
    let fitted = fit(&study, &start);
    let f = study.frequencies(&fitted.matrix).unwrap();
    eprintln!(
        "ringing flexure, L-RP-RP-RP, modes = 2: J {:.4e}, frequency errors {:?}",
        fitted.figures.objective, f.freq_err
    );
    assert!(f.max_err() < 1e-3, "{f:?}");
}

/// A heavy frequency weight is obeyed, not flattened: each residual's cap grows with its
/// weight, so the polish still sees the frequencies' slope. With the cap fixed at 1,
/// `frequency_weight = 100` made no progress at all (10 % off) and 1000 ended 26 times above
/// its start (48.6 % off). The ringing flexure with three modes, L-R-R-R at draft: every
/// weight ends below its start and meets the 1 % frequency target.
#[test]
fn heavy_frequency_weights_still_reach_the_frequencies() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/ringing-flexure.toml"
    );
    for w in [1.0, 100.0, 1e3, 1e5] {
        let text = std::fs::read_to_string(path).unwrap()
            + &format!("\n[fit]\nmodes = 3\nfrequency_weight = {w:?}\n");
        let scene = Scene::from_toml_str(&text, "ringing.toml").unwrap();
        let study = Study::as_given(&scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
        let options = FitOptions {
            fidelity: Fidelity::Draft,
            angle_weight: scene.fit.angle_weight,
            seed: 1,
        };
        let start = PrbMatrix::from_topology("L-R-R-R").unwrap();
        let fitted = study
            .fit(&start, &options, &mut |_| {}, &CancelToken::new())
            .unwrap();
        let f = study.frequencies(&fitted.matrix).unwrap();
        eprintln!(
            "frequency_weight {w:e}: J {:.4e} (start {:.4e}), frequency errors {:?}",
            fitted.figures.objective, fitted.start_objective, f.freq_err
        );
        assert!(
            fitted.figures.objective <= fitted.start_objective,
            "w {w}: J {} above its start {}",
            fitted.figures.objective,
            fitted.start_objective
        );
        assert!(f.max_err() < scene.accuracy.max_freq_err, "w {w}: {f:?}");
    }
}
