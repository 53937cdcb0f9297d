//! `prbfit solve` end to end: the real binary, its JSON, its errors and exit statuses.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{assert_input_error, json, prbfit, Scratch};

/// A scene file in a scratch directory that lives as long as the returned guard.
fn scene_file(text: &str) -> (Scratch, String) {
    let dir = Scratch::new("scene");
    let p = dir.write("scene.toml", text);
    (dir, p)
}

#[test]
fn one_load_as_json_matches_the_elliptic_table() {
    let out = prbfit(&["solve", "--load", "0,2,0", "--effects", "none", "--json"]);
    let v = json(&out);
    assert!((v["a"].as_f64().unwrap() - 0.839358).abs() < 1e-6);
    assert!((v["b"].as_f64().unwrap() - 0.493457).abs() < 1e-6);
    assert!((v["phi"].as_f64().unwrap() - 0.781750).abs() < 1e-6);
}

#[test]
fn negative_loads_and_shape_output() {
    let out = prbfit(&["solve", "--load", "-1,-2,-0.5", "--json", "--shape"]);
    let v = json(&out);
    let shape = v["shape"].as_array().unwrap();
    assert_eq!(shape.len(), 41);
    let last = &shape[40];
    assert!((last["x"].as_f64().unwrap() - v["a"].as_f64().unwrap()).abs() < 1e-6);
    assert!(v["b"].as_f64().unwrap() < 0.0);
}

#[test]
fn whole_scene_solves_every_case() {
    // The elastica (the built-in 10 mm wide strip keeps plane strain with `auto`).
    let v = json(&prbfit(&["solve", "--effects", "none", "--json"]));
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 20, "the built-in scene has 4 paths of 5 steps");
    assert!(v["seconds"].as_f64().unwrap() > 0.0);
    // The first path is a transverse force; its last case is alpha_y = 5 (the elastica's
    // 0.612372, printed to 6 digits).
    let c = &cases[4];
    assert_eq!(c["load"]["alpha_y"].as_f64(), Some(5.0));
    assert!((c["a"].as_f64().unwrap() - 0.612372).abs() < 1e-6);
}

#[test]
fn flag_overrides_reach_the_solver() {
    // Shear only, slenderness 2: linear Timoshenko at a small load.
    let v = json(&prbfit(&[
        "solve",
        "--load",
        "0,1e-4,0",
        "--effects",
        "shear",
        "--slenderness",
        "2",
        "--nu",
        "0.3",
        "--json",
    ]));
    let kappa = 10.0 * 1.3 / (12.0 + 3.3);
    let c_s = 1.0 / (12.0 * 4.0) * 2.0 * 1.3 / kappa;
    let expected = 1e-4 / 3.0 + 1e-4 * c_s;
    assert!(((v["b"].as_f64().unwrap() - expected) / expected).abs() < 1e-6);
}

#[test]
fn bad_flags_exit_2_naming_the_flag() {
    assert_input_error(
        &prbfit(&["solve", "--load", "1,2"]),
        &["--load", "three numbers"],
    );
    assert_input_error(&prbfit(&["solve", "--load", "1,x,2"]), &["--load", "`x`"]);
    assert_input_error(
        &prbfit(&["solve", "--load", "1,nan,2"]),
        &["--load", "finite"],
    );
    assert_input_error(&prbfit(&["solve", "--nu", "0.7"]), &["--nu", "0.7"]);
    assert_input_error(
        &prbfit(&["solve", "--slenderness", "-3"]),
        &["--slenderness"],
    );
    assert_input_error(&prbfit(&["solve", "--kappa", "0"]), &["--kappa"]);
    assert_input_error(
        &prbfit(&["solve", "--effects", "twist"]),
        &["--effects", "twist"],
    );
    assert_input_error(
        &prbfit(&["solve", "--effects", "poisson"]),
        &["--effects", "extension"],
    );
    assert_input_error(&prbfit(&["solve", "--tol", "0"]), &["--tol"]);
    assert_input_error(&prbfit(&["solve", "--bogus"]), &["--bogus"]);
    assert_input_error(
        &prbfit(&["solve", "--scene", "/no/such/file.toml"]),
        &["/no/such/file.toml"],
    );
}

#[test]
fn a_failed_solve_exits_1_and_says_why() {
    let out = prbfit(&["solve", "--load", "-3,0,0", "--effects", "none"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("critical point"), "{err}");
    assert!(out.stdout.is_empty());
}

const GOOD: &str = r#"
name = "test"
[beam]
length = 0.05
width = 0.01
thickness = 0.0005
youngs_modulus = 200e9
poisson_ratio = 0.3
effects = ["shear"]
[[loads]]
alpha_y = 2.0
steps = 2
"#;

#[test]
fn scene_file_is_read() {
    let (_g, path) = scene_file(GOOD);
    let v = json(&prbfit(&["solve", "--scene", &path, "--json"]));
    assert_eq!(v["cases"].as_array().unwrap().len(), 2);
    assert_eq!(v["beam"]["effects"], serde_json::json!(["shear"]));
    assert_eq!(v["scene"], "test");
}

#[test]
fn bad_scene_files_exit_2_with_file_line_and_key() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "thickness = 0.0005",
            "thickness = -0.0005",
            &[":6:", "beam.thickness", "> 0"],
        ),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.7",
            &[":8:", "beam.poisson_ratio", "0.7"],
        ),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = nan",
            &[":8:", "beam.poisson_ratio", "NaN"],
        ),
        ("thickness = 0.0005", "thicknes = 0.0005", &["thicknes"]),
        (
            "effects = [\"shear\"]",
            "effects = [\"poisson\"]",
            &[":9:", "beam.effects", "extension"],
        ),
        (
            "effects = [\"shear\"]",
            "effects = \"some\"",
            &[":9:", "beam.effects", "some"],
        ),
        ("steps = 2", "steps = 0", &[":12:", "loads[1].steps"]),
        ("steps = 2", "steps = 2.5", &[":12:"]),
        ("alpha_y = 2.0", "alpha_y = 0.0", &["loads[1]", "all zero"]),
        (
            "alpha_y = 2.0",
            "alpha_y = inf",
            &[":11:", "loads[1].alpha_y"],
        ),
        (
            "length = 0.05",
            "length = 0.0001",
            &["beam.thickness", "slenderness"],
        ),
        ("[[loads]]", "[[load]]", &["load"]),
        ("width = 0.01", "width = \"wide\"", &[":5:"]),
        ("name = \"test\"", "name = \"test", &[":2:"]),
    ];
    for (from, to, needles) in cases {
        let text = GOOD.replace(from, to);
        assert_ne!(text, GOOD, "{from} not in the scene");
        let (_g, path) = scene_file(&text);
        let out = prbfit(&["solve", "--scene", &path]);
        let mut all = vec![path.as_str()];
        all.extend_from_slice(needles);
        assert_input_error(&out, &all);
    }
    let (_g, path) = scene_file(&GOOD.replace("[[loads]]\nalpha_y = 2.0\nsteps = 2\n", ""));
    assert_input_error(&prbfit(&["solve", "--scene", &path]), &["no load paths"]);
}

/// A cantilever's `solve` stops when cancelled (the Python module's Ctrl-C, the CLI's): the
/// path it is on ends at its next check and the result is an error, where every path used to
/// be solved to its end whatever the token said (a 70000-case scene with shapes ran on for
/// seconds after Python's Ctrl-C).
#[test]
fn a_cancelled_cantilever_solve_stops_on_its_path() {
    use prbfit::fit::CancelToken;
    use prbfit::report::{solve::SolveArgs, Control, Progress};
    use prbfit::scene::Scene;

    let scene = Scene::builtin();
    assert!(scene.loads.len() >= 3);
    let run = |cancel_on: usize| {
        let cancel = CancelToken::new();
        let on_path = cancel.clone();
        let mut progress = |p: &Progress<'_>| {
            if let Progress::Solving { path, .. } = p {
                if *path == cancel_on {
                    on_path.cancel();
                }
            }
        };
        let mut ctl = Control {
            cancel,
            progress: &mut progress,
        };
        prbfit::report::solve::solve(&scene, &SolveArgs::default(), &mut ctl)
    };
    assert!(run(0).is_ok());
    assert!(run(2).is_err(), "a cancelled solve reported every path");
}
