//! The PRB model's own stress estimate (DESIGN §11): its largest joint or root moment's
//! fibre stress, known answers, and `prbfit eval` showing it beside the beam's.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{json, prbfit};

use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution};
use prbfit::prb::{PrbMatrix, PrbSolver};

/// A beam of slenderness 100 with every effect but plane strain (Poisson's shrink on).
fn model() -> BeamModel {
    BeamModel::new(100.0, 0.3, None, Effects::ALL).unwrap()
}

/// The PRB model's estimate under `load`, and the beam's largest stress.
fn both(matrix: &str, load: Load) -> (f64, f64, f64, f64) {
    let model = model();
    let m = PrbMatrix::parse(matrix).unwrap();
    let solver = PrbSolver::new(&m, model.axial_compliance());
    let prb = solver.solve(load).unwrap();
    let p = solver.max_stress(&model, load, &prb.q).unwrap();
    let beam = BeamSolver::new(model, Resolution::default())
        .unwrap()
        .solve(load)
        .unwrap()
        .stress
        .unwrap();
    (p.max, p.at, beam.max, beam.at)
}

/// 1R under a pure moment: the joint carries the applied moment, as every section of the
/// beam does, so both are `beta E t0 / (2 L)` (no axial force, so no shrink), the root
/// first. Exact: the statics are the same sums, good to rounding.
#[test]
fn a_pure_moment_is_the_joint_moment() {
    for beta in [0.1, 0.5, 1.5] {
        let (p, at, b, _) = both("0.15,inf,inf; 0.85,2.25,inf", Load::new(0.0, 0.0, beta));
        let exact = beta / (2.0 * 100.0);
        assert!((p / exact - 1.0).abs() < 1e-12, "{p} vs {exact}");
        assert!((b / exact - 1.0).abs() < 1e-9, "{b} vs {exact}");
        assert_eq!(at, 0.0);
    }
}

/// A small transverse force: the root moment is `alpha_y a_tip = alpha_y (1 - O(alpha^2))`,
/// the beam's `F L` likewise, so the estimate is the beam's to `O(alpha^2)`: at `alpha_y =
/// 1e-4`, 1e-7 relative covers it (the tip's shortening ~ alpha^2 / 10 and the axial term's
/// `c_e |N| ~ alpha^2` part).
#[test]
fn a_small_force_gives_the_root_moment_f_l() {
    let alpha = 1e-4;
    let (p, at, b, bat) = both("0.15,inf,inf; 0.85,2.25,inf", Load::new(0.0, alpha, 0.0));
    let exact = alpha / (2.0 * 100.0);
    assert!((p / exact - 1.0).abs() < 1e-7, "{p} vs {exact}");
    assert!((b / exact - 1.0).abs() < 1e-7, "{b} vs {exact}");
    assert_eq!((at, bat), (0.0, 0.0));
}

/// Tension: no moment, every link carries `N`, so the estimate is the beam's `N / A` with
/// the same Poisson shrink (one material law), to rounding.
#[test]
fn tension_is_n_over_a_with_the_shrink() {
    let n = 50.0;
    let (p, _, b, _) = both("0.15,inf,inf; 0.85,2.25,inf", Load::new(n, 0.0, 0.0));
    let shrunk = model().fibre_stress(n, 0.0).unwrap();
    assert!((p / shrunk - 1.0).abs() < 1e-12, "{p} vs {shrunk}");
    assert!((b / shrunk - 1.0).abs() < 1e-9, "{b} vs {shrunk}");
    // The shrink is there: more than the unshrunk N / A.
    assert!(shrunk > model().axial_compliance() * n);
}

/// `eval --load`: the 1R's estimate beside the beam's under a pure moment on the built-in
/// scene (`L / t0 = 100`, `E = 200 GPa`, `beta = 0.5`: 500 MPa each, error 0).
#[test]
fn eval_at_a_load_shows_both_stresses() {
    let v = json(&prbfit(&[
        "eval",
        "--model",
        "howell-1r",
        "--load",
        "0,0,0.5",
        "--json",
    ]));
    let p = v["max_stress"].as_f64().unwrap();
    let b = v["beam_max_stress"].as_f64().unwrap();
    assert!((p / 5e8 - 1.0).abs() < 1e-12, "{p}");
    assert!((b / 5e8 - 1.0).abs() < 1e-9, "{b}");
    assert!(v["stress_err"].as_f64().unwrap().abs() < 1e-9);
    let out = prbfit(&["eval", "--model", "howell-1r", "--load", "0,0,0.5"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("howell-1r stress: PRB 500.0 MPa at s/L 0.000, beam 500.0 MPa"),
        "{text}"
    );
}

/// `eval` over a scene: per flexure, the largest estimate and the beam's, and the error,
/// checked against the cases' own stresses; on a mechanism one per flexure; on measured
/// data none (the data has no stress), and the text says so.
#[test]
fn eval_over_scenes_shows_the_estimate_per_flexure() {
    let scene = |name: &str| format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let v = json(&prbfit(&["eval", "--model", "chen-3r", "--json"]));
    let s = v["stress"].as_array().unwrap();
    assert_eq!(s.len(), 1);
    let cases = v["cases"].as_array().unwrap();
    let largest = |key: &str| {
        cases
            .iter()
            .map(|c| c[key].as_f64().unwrap())
            .fold(0.0, f64::max)
    };
    assert_eq!(s[0]["prb_max_stress"].as_f64(), Some(largest("max_stress")));
    assert_eq!(
        s[0]["beam_max_stress"].as_f64(),
        Some(largest("beam_max_stress"))
    );
    let err = cases
        .iter()
        .map(|c| (c["max_stress"].as_f64().unwrap() - c["beam_max_stress"].as_f64().unwrap()).abs())
        .fold(0.0, f64::max)
        / largest("beam_max_stress");
    assert!((s[0]["max_stress_err"].as_f64().unwrap() - err).abs() < 1e-12);
    // A fitted 3R carries the beam's moments to a few per cent.
    assert!(err < 0.1, "{err}");

    let v = json(&prbfit(&[
        "eval",
        "--scene",
        &scene("parallel-stage.toml"),
        "--model",
        "chen-3r",
        "--json",
    ]));
    let s = v["stress"].as_array().unwrap();
    assert_eq!(s.len(), 2);
    for (i, f) in s.iter().enumerate() {
        assert_eq!(f["flexure"].as_u64(), Some(i as u64 + 1));
        assert!(f["max_stress_err"].as_f64().unwrap() < 0.1, "{f}");
    }
    let last = v["cases"].as_array().unwrap().last().unwrap().clone();
    assert_eq!(last["max_stress"].as_array().unwrap().len(), 2);
    assert_eq!(last["beam"]["max_stress"].as_array().unwrap().len(), 2);

    let data = scene("slider-crank-rig.toml");
    let v = json(&prbfit(&[
        "eval", "--scene", &data, "--model", "chen-3r", "--json",
    ]));
    assert!(v.get("stress").is_none());
    assert!(v["cases"][0]["beam"]["max_stress"][0].is_null());
    let out = prbfit(&["eval", "--scene", &data, "--model", "chen-3r"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("stress: not judged (the data has no stress"),
        "{text}"
    );
}
