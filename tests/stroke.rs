//! Stroke limits (DESIGN §11): the fraction of each path where the largest fibre stress
//! first reaches the allowable stress, found by root-finding along the path.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::path::Path;

use common::{assert_input_error, prbfit, Scratch};
use prbfit::beam::{BeamSolver, Resolution};
use prbfit::fit::{CancelToken, Fidelity};
use prbfit::mech::exact;
use prbfit::scene::{DrivePath, Scene};
use prbfit::study::{Sampling, Study};

fn scene(name: &str, allowable: &str) -> Scene {
    let p = format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(Path::new(&p)).unwrap();
    let text = text.replacen(
        "[beam]",
        &format!("[beam]\nallowable_stress = {allowable}"),
        1,
    );
    Scene::from_toml_str(&text, name).unwrap()
}

fn study(scene: &Scene) -> Study {
    Study::new(scene, Sampling::Every(Resolution::default())).unwrap()
}

/// The default scene (L/t0 = 100, E = 200 GPa). Its pure-moment path (beta to 2) has
/// `sigma = beta E t0 / (2 L)`, linear in the load: 2 GPa at its end, so an allowable of
/// 1.3 GPa is reached at 0.65 exactly. Every other limit is checked by solving the beam
/// there: the stress equals the allowable, and one part in 1e6 of the path either side is
/// below and above it (the stress is good to ~1e-9 relative, its slope ~1 per path).
#[test]
fn cantilever_limits_are_where_the_stress_reaches_the_allowable() {
    let allowable = 1.3e9;
    let scene = scene("default.toml", "1.3e9");
    let study = study(&scene);
    let limits = study
        .stroke_limits()
        .expect("the scene has an allowable stress");
    assert_eq!(limits.len(), scene.loads.len());
    let moment = limits[2].fraction.expect("the moment path reaches 1.3 GPa");
    println!(
        "pure moment: limit {moment:.9} (exact 0.65), {} shots",
        limits[2].shots
    );
    assert!((moment - 0.65).abs() < 1e-9, "{moment}");
    let baseline = study.baseline().unwrap();
    let solver = BeamSolver::new(baseline.model, Resolution::default()).unwrap();
    let stress = |path: usize, lambda: f64| {
        let end = scene.loads[path].end;
        let s = solver.solve(end.scaled(lambda)).unwrap().stress.unwrap();
        s.max * scene.beam.youngs_modulus
    };
    for l in &limits {
        println!("path {}: {:?} in {} shots", l.path, l.fraction, l.shots);
        assert!(l.shots <= 20, "path {}: {} shots", l.path, l.shots);
        let f = l
            .fraction
            .expect("every path of the default scene passes 1.3 GPa");
        assert!(f > 0.0 && f <= 1.0);
        let at = stress(l.path - 1, f);
        assert!((at / allowable - 1.0).abs() < 1e-6, "path {}: {at}", l.path);
        assert!(stress(l.path - 1, f - 1e-6) < allowable, "path {}", l.path);
        assert!(stress(l.path - 1, (f + 1e-6).min(1.0)) >= allowable * (1.0 - 1e-9));
        assert_eq!(l.flexure, Some(1));
    }
}

/// An allowable above every case's stress: no limit (null), and no solve spent.
#[test]
fn a_path_that_never_reaches_the_allowable_has_no_limit() {
    let study = study(&scene("default.toml", "1e12"));
    for l in study.stroke_limits().unwrap() {
        assert_eq!((l.fraction, l.shots), (None, 0));
    }
    let none = study_without_allowable();
    assert!(none.stroke_limits().is_none());
}

fn study_without_allowable() -> Study {
    let p = format!("{}/assets/scenes/default.toml", env!("CARGO_MANIFEST_DIR"));
    study(&Scene::from_file(Path::new(&p)).unwrap())
}

/// The parallel stage: each flexure a fixed-guided segment, root moment `F L / 2` per
/// flexure in small motion (600 MPa at drive 1's end). At each drive's limit the beam
/// mechanism solved there has its worst flexure at the allowable.
#[test]
fn mechanism_limits_are_where_a_flexure_reaches_the_allowable() {
    let allowable = 4e8;
    let scene = scene("parallel-stage.toml", "4e8");
    let study = study(&scene);
    let limits = study.stroke_limits().unwrap();
    let mechanism = study.mechanism();
    let solver = exact::solver(mechanism, study.resolution()).unwrap();
    let worst = |drive: usize, lambda: f64| {
        let path = mechanism.drive_path(&mechanism.drives[drive]);
        let to = DrivePath::proportional(path.at(lambda), 1);
        let case = solver.solve_path(&to, drive + 1).unwrap().pop().unwrap();
        case.flexures
            .iter()
            .zip(&mechanism.flexures)
            .map(|(c, f)| c.stress.unwrap().max * f.beam.youngs_modulus)
            .fold(0.0, f64::max)
    };
    assert_eq!(limits.len(), 2);
    for l in &limits {
        let f = l.fraction.expect("both drives pass 400 MPa");
        println!(
            "drive {}: limit {f:.9} in {} shots, flexure {:?}",
            l.path, l.shots, l.flexure
        );
        assert!(l.shots <= 20);
        let at = worst(l.path - 1, f);
        assert!(
            (at / allowable - 1.0).abs() < 1e-6,
            "drive {}: {at}",
            l.path
        );
        assert!(worst(l.path - 1, f - 1e-6) < allowable);
    }
    // Drive 1 in small motion: 600 MPa at its end, linear, so near 2/3.
    let f = limits[0].fraction.unwrap();
    assert!((f - 2.0 / 3.0).abs() < 0.02, "{f}");
}

/// A per-flexure allowable overrides the scene's: a weaker lower flexure sets the limit.
#[test]
fn a_flexure_allowable_overrides_the_beam() {
    let mut scene = scene("parallel-stage.toml", "1e12");
    let m = scene.mechanism.as_mut().unwrap();
    m.flexures[1].beam.allowable_stress = Some(4e8);
    scene.validate().unwrap();
    let limits = study(&scene).stroke_limits().unwrap();
    assert_eq!(limits[0].flexure, Some(2));
    assert!(limits[0].fraction.is_some());
    // The written scene keeps the override and reads back the same.
    let back = Scene::from_toml_str(&scene.to_toml(), "written").unwrap();
    assert_eq!(
        back.mechanism.unwrap().flexures[1].beam.allowable_stress,
        Some(4e8)
    );
}

/// Bad allowable stresses: exit 2 naming the key, in `[beam]` and in a flexure's table.
#[test]
fn bad_allowable_stresses_are_refused_naming_the_key() {
    let dir = Scratch::new("allowable");
    let base = std::fs::read_to_string(format!(
        "{}/assets/scenes/default.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    for bad in ["-1e9", "0.0", "nan", "inf"] {
        let text = base.replacen("[beam]", &format!("[beam]\nallowable_stress = {bad}"), 1);
        let p = dir.write("bad.toml", &text);
        assert_input_error(
            &prbfit(&["solve", "--scene", &p]),
            &["beam.allowable_stress", "must be a finite number > 0"],
        );
    }
    let stage = std::fs::read_to_string(format!(
        "{}/assets/scenes/parallel-stage.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    for bad in ["-5.0", "0.0", "nan", "inf"] {
        let text = stage.replacen(
            "attach = \"clamped\"",
            &format!("attach = \"clamped\"\nallowable_stress = {bad}"),
            1,
        );
        let p = dir.write("bad-flexure.toml", &text);
        // Every command reads the scene through the same rules.
        for cmd in ["solve", "eval", "select"] {
            assert_input_error(
                &prbfit(&[cmd, "--scene", &p]),
                &[
                    "flexures[1].allowable_stress",
                    "must be a finite number > 0",
                ],
            );
        }
    }
}

/// `solve --json` lists the stroke limits in order, marks the cases past them, and gives
/// every case its stress in Pa; the text names the limits.
#[test]
fn solve_lists_stroke_limits_and_marks_the_cases_past_them() {
    let dir = Scratch::new("stroke-cli");
    let p = format!("{}/assets/scenes/default.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(p).unwrap();
    let scene = dir.write(
        "s.toml",
        &text.replacen("[beam]", "[beam]\nallowable_stress = 1.3e9", 1),
    );
    let v = common::json(&prbfit(&["solve", "--scene", &scene, "--json"]));
    let limits = v["stroke_limits"].as_array().unwrap();
    assert_eq!(limits.len(), 4);
    assert!((limits[2].as_f64().unwrap() - 0.65).abs() < 1e-9);
    assert_eq!(v["allowable_stress"].as_f64(), Some(1.3e9));
    for c in v["cases"].as_array().unwrap() {
        let stress = c["max_stress"].as_f64().unwrap();
        let past = c["past_stroke_limit"].as_bool().unwrap();
        // Stress grows along every path of this scene, so past the limit is above it.
        assert_eq!(past, stress > 1.3e9, "{c}");
    }
    let out = prbfit(&["solve", "--scene", &scene]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("stroke limits (allowable stress 1300.0000 MPa): load path 1 at"));
    assert!(text.contains("load path 3 at 0.650000"));
    assert!(text.contains("past the stroke limit"));
    // Without an allowable: stresses, but no limits.
    let v = common::json(&prbfit(&["solve", "--json"]));
    assert!(v["stroke_limits"].is_null());
    assert!(v["cases"][0]["max_stress"].as_f64().unwrap() > 0.0);
}

/// `Study::within_stroke` (`select --within-stroke`): each path ends at its limit, sampled
/// as fully as the whole path, so its last case's stress is the allowable (to the limit's
/// 1e-6 of the path times the stress's slope, ~1 per path: 1e-5 relative is ample).
#[test]
fn within_stroke_ends_each_path_at_its_limit() {
    let scene = scene("default.toml", "1.3e9");
    let full = study(&scene);
    let (within, limits) = full.within_stroke(&CancelToken::new()).unwrap().unwrap();
    assert_eq!(within.case_count(), full.case_count());
    for ((path, short), l) in scene.loads.iter().zip(&within.scene().loads).zip(&limits) {
        let f = l.fraction.unwrap();
        assert_eq!(short.end, path.end.scaled(f));
    }
    for (kept, l) in within.truth().iter().zip(&limits) {
        let (r, _) = within.stress_ratio(kept.last().unwrap()).unwrap();
        assert!((r - 1.0).abs() < 1e-5, "path {}: ratio {r}", l.path);
    }
    // The shorter study fits and selects as the whole one does.
    let selection = within
        .select(Fidelity::Draft, &CancelToken::new(), &mut |_| {})
        .unwrap();
    assert!(!selection.rows.is_empty());
    // No allowable: nothing to judge within.
    let none = study_without_allowable();
    assert!(none.within_stroke(&CancelToken::new()).unwrap().is_none());
}

/// A mechanism's drives end at their limits: the parallel stage's last case of each drive
/// has its worst flexure at the allowable (as above, 1e-5 relative).
#[test]
fn within_stroke_shortens_a_mechanisms_drives() {
    let scene = scene("parallel-stage.toml", "4e8");
    let full = study(&scene);
    let (within, limits) = full.within_stroke(&CancelToken::new()).unwrap().unwrap();
    assert_eq!(within.case_count(), full.case_count());
    for (kept, l) in within.truth().iter().zip(&limits) {
        assert!(l.fraction.is_some());
        let (r, _) = within.stress_ratio(kept.last().unwrap()).unwrap();
        assert!((r - 1.0).abs() < 1e-5, "drive {}: ratio {r}", l.path);
        // Before it, below the allowable.
        let (r, _) = within.stress_ratio(&kept[kept.len() - 2]).unwrap();
        assert!(r < 1.0);
    }
}

/// `select --within-stroke` says which part of each path it judged (text and JSON), and
/// refuses a scene with no allowable stress (exit 2, naming the flag).
#[test]
fn select_within_stroke_judges_up_to_the_limits() {
    let dir = Scratch::new("select-within");
    let p = format!("{}/assets/scenes/default.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(p).unwrap();
    let scene = dir.write(
        "s.toml",
        &text.replacen("[beam]", "[beam]\nallowable_stress = 1.3e9", 1),
    );
    let args = [
        "select",
        "--scene",
        &scene,
        "--fidelity",
        "draft",
        "--within-stroke",
    ];
    let out = prbfit(&args);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("judged within the stroke limits: path 1 to 0."),
        "{text}"
    );
    assert!(text.contains("path 3 to 0.650000"), "{text}");
    let v = common::json(&prbfit(&[&args[..], &["--json"]].concat()));
    let limits = v["within_stroke"].as_array().unwrap();
    assert_eq!(limits.len(), 4);
    assert!((limits[2].as_f64().unwrap() - 0.65).abs() < 1e-9);
    assert!(!v["rows"].as_array().unwrap().is_empty());
    // Without the flag the JSON has no such field.
    let v = common::json(&prbfit(&[&args[..5], &["--json"]].concat()));
    assert!(v.get("within_stroke").is_none());
    assert_input_error(
        &prbfit(&["select", "--fidelity", "draft", "--within-stroke"]),
        &["--within-stroke", "no allowable_stress"],
    );
    // A path that never reaches the allowable is judged whole: `null` in the JSON's list
    // (it was refused as a non-finite number once).
    let p = format!(
        "{}/assets/scenes/steel-flexure.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(p).unwrap();
    let scene = dir.write(
        "steel.toml",
        &text.replacen("[beam]", "[beam]\nallowable_stress = 1e9", 1),
    );
    let v = common::json(&prbfit(&[
        "select",
        "--scene",
        &scene,
        "--fidelity",
        "draft",
        "--within-stroke",
        "--json",
    ]));
    let limits = v["within_stroke"].as_array().unwrap();
    assert!(limits.iter().any(|l| l.is_null()), "{limits:?}");
    assert!(limits.iter().any(|l| l.is_f64()), "{limits:?}");
}
