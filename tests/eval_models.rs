//! Judging PRB models against the beam: a closed-form case, the published models on the
//! built-in and example scenes, and `prbfit eval` end to end.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{prbfit, succeeded};

use prbfit::beam::{BeamModel, Effects, Load, Resolution};
use prbfit::eval::{evaluate, Baseline};
use prbfit::io::ModelFile;
use prbfit::prb::PrbMatrix;
use prbfit::scene::{LoadPath, Scene};

/// One revolute joint at the clamp with k = 1, under a pure moment: the link turns by beta,
/// so its tip is (cos beta, sin beta); the beam is the arc (sin beta / beta,
/// (1 - cos beta) / beta). Both tip angles are beta.
#[test]
fn errors_of_a_single_link_under_pure_moment() {
    let m = PrbMatrix::parse("1,1,inf").unwrap();
    let paths = [LoadPath {
        end: Load::new(0.0, 0.0, 1.5),
        steps: 3,
    }];
    let baseline =
        Baseline::for_model(BeamModel::elastica(), &paths, Resolution::with_tol(1e-11)).unwrap();
    let e = evaluate(&m, &baseline, 2.0).unwrap();
    let mut sum_sq = 0.0;
    for (k, case) in e.cases.iter().enumerate() {
        let beta = 0.5 * (k + 1) as f64;
        let (pa, pb) = (beta.cos(), beta.sin());
        let (ba, bb) = (beta.sin() / beta, (1.0 - beta.cos()) / beta);
        let expected = (pa - ba).hypot(pb - bb);
        assert!(
            (case.pos_err - expected).abs() < 1e-9,
            "{} vs {expected}",
            case.pos_err
        );
        assert!(case.ang_err.abs() < 1e-9);
        sum_sq += expected * expected;
    }
    let f = e.figures;
    assert!((f.rms_pos_err - (sum_sq / 3.0).sqrt()).abs() < 1e-9);
    assert!(
        (f.objective - sum_sq / 3.0).abs() < 1e-9,
        "angle error is zero, so J = mean e_pos^2"
    );
    assert!(f.max_pos_err >= f.rms_pos_err);
}

/// The angle weight enters J as DESIGN §4 says.
#[test]
fn angle_weight_scales_the_angle_term() {
    let scene = Scene::builtin();
    let baseline = Baseline::compute(&scene, Resolution::default()).unwrap();
    let su = ModelFile::load("su-3r").unwrap().prb;
    let f1 = evaluate(&su, &baseline, 1.0).unwrap().figures;
    let f3 = evaluate(&su, &baseline, 3.0).unwrap().figures;
    let pos_term = f1.rms_pos_err.powi(2);
    let ang_term = f1.rms_ang_err.powi(2);
    assert!((f1.objective - (pos_term + ang_term)).abs() < 1e-15);
    assert!((f3.objective - (pos_term + 3.0 * ang_term)).abs() < 1e-15);
}

/// The published models' figures on the built-in scene (printed: `cargo test --test
/// eval_models -- --nocapture`). Every figure is finite and the 3R models, built for force
/// and moment loads, beat the 1R, which is built for forces alone and cannot turn its tip
/// like the beam under a moment.
#[test]
fn published_models_on_the_builtin_scene() {
    let scene = Scene::builtin();
    let baseline = Baseline::compute(&scene, Resolution::default()).unwrap();
    let mut j = Vec::new();
    println!(
        "{:<10} {:>10} {:>10} {:>10} {:>10} {:>11}",
        "model", "rms pos", "max pos", "rms ang", "max ang", "J"
    );
    for model in prbfit::prb::published::all() {
        let f = evaluate(&model.prb, &baseline, scene.fit.angle_weight)
            .unwrap()
            .figures;
        println!(
            "{:<10} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>11.4e}",
            model.name, f.rms_pos_err, f.max_pos_err, f.rms_ang_err, f.max_ang_err, f.objective
        );
        for v in [
            f.rms_pos_err,
            f.max_pos_err,
            f.rms_ang_err,
            f.max_ang_err,
            f.objective,
        ] {
            assert!(v.is_finite() && v >= 0.0);
        }
        j.push((model.name, f.objective));
    }
    assert!(j[1].1 < j[0].1 && j[2].1 < j[0].1, "{j:?}");
}

/// Every example scene loads, solves and judges every published model.
#[test]
fn example_scenes_are_valid() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::from_file(&path).unwrap();
        if let Some(m) = &scene.mechanism {
            // A mechanism scene (DESIGN §8) has no cantilever cases: its check is that the
            // exact mechanism and Su's 3R in every flexure follow every drive
            // (tests/cli_mech.rs checks each scene's physics).
            let exact = prbfit::mech::exact::solve(m, Resolution::default())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let su = ModelFile::load("su-3r").unwrap().prb;
            let prb = prbfit::mech::prb::solve(m, &su, 1e-9)
                .unwrap_or_else(|e| panic!("su-3r on {}: {e}", path.display()));
            assert_eq!(exact.len(), prb.len());
            count += 1;
            continue;
        }
        let baseline = Baseline::compute(&scene, Resolution::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for model in prbfit::prb::published::all() {
            evaluate(&model.prb, &baseline, 1.0)
                .unwrap_or_else(|e| panic!("{} on {}: {e}", model.name, path.display()));
        }
        count += 1;
    }
    assert!(count >= 3, "default, steel flexure and urethane joint");
}

/// The urethane joint is where shear and stretch matter: the tip with every effect differs
/// from the elastica's by more than the scene's position target.
#[test]
fn urethane_joint_needs_its_effects() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/urethane-joint.toml"
    );
    let scene = Scene::from_file(std::path::Path::new(path)).unwrap();
    assert!((scene.beam.slenderness() - 4.0).abs() < 1e-12);
    let full = Baseline::compute(&scene, Resolution::default()).unwrap();
    let m = scene.beam.model();
    let bare = BeamModel::new(m.slenderness, m.nu, Some(m.kappa), Effects::NONE).unwrap();
    let elastica = Baseline::for_model(bare, &scene.loads, Resolution::default()).unwrap();
    let gap = full
        .solutions
        .iter()
        .zip(&elastica.solutions)
        .map(|(a, b)| (a.tip.a - b.tip.a).hypot(a.tip.b - b.tip.b))
        .fold(0.0, f64::max);
    assert!(gap > scene.accuracy.max_pos_err, "gap {gap}");
}

#[test]
fn cli_eval_reports_the_five_figures() {
    let out = prbfit(&["eval", "--model", "su-3r", "--json"]);
    succeeded(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "rms_pos_err",
        "max_pos_err",
        "rms_ang_err",
        "max_ang_err",
        "objective",
    ] {
        assert!(v[key].as_f64().unwrap() >= 0.0, "{key}");
    }
    assert_eq!(v["cases"].as_array().unwrap().len(), 20);
    assert_eq!(v["topology"], "L-R-R-R");

    let out = prbfit(&[
        "eval",
        "--prb",
        "0.15,inf,inf; 0.85,2.2525,inf",
        "--load",
        "0,2,0",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pos = (v["a"].as_f64().unwrap() - v["beam"]["a"].as_f64().unwrap())
        .hypot(v["b"].as_f64().unwrap() - v["beam"]["b"].as_f64().unwrap());
    assert!((pos - v["pos_err"].as_f64().unwrap()).abs() < 1e-15);

    // Several models share one baseline.
    let out = prbfit(&[
        "eval",
        "--model",
        "howell-1r",
        "--model",
        "chen-3r",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["models"].as_array().unwrap().len(), 2);
}

#[test]
fn cli_eval_rejects_bad_models() {
    for (args, needle) in [
        (vec!["eval", "--prb", "0.5,inf,inf; 0.6,2,inf"], "sum to 1"),
        (
            vec!["eval", "--prb", "0.5,inf,inf; 0.5,-2,inf"],
            "row 2, column k_theta",
        ),
        (vec!["eval", "--model", "nosuch-3r"], "su-3r"),
        (vec!["eval"], "--prb MATRIX or --model"),
    ] {
        let out = prbfit(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1);
    }
}
