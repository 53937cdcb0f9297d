//! Measured data as the truth of a mechanism scene (DESIGN §9 with §8; issue 14): the data
//! file's inputs are the `[[drives]]` names, its measurements the `stage_*` columns.
//!
//! - Round trip: data written from prbfit's own beam mechanism, read back as the truth, gives
//!   the beam scene's figures and fit (to the solvers' tolerances), on a loaded stage, a
//!   driven one (reactions) and a mixed one.
//! - Rows in order: a path whose drive turns is followed row by row.
//! - Noise: 0.1% L of noise on the stage is fitted without chasing it.
//! - Calibration recovers the modulus the data were made with.
//! - Every bad file is exit 2 naming file:line:column; the commands that cannot use the data
//!   (solve, tradeoff, the UI) say so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{assert_input_error, json, prbfit, succeeded, Gauss, Scratch, MECH_FIGURES};
use prbfit::scene::{Coordinate, Drive, Scene};

/// The repository's example scene `name`.
fn asset(name: &str) -> String {
    format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The text of the example scene `name` with its `[[drives]]` replaced by `[truth] data =
/// "<csv>"` (the examples give their drives last before `[accuracy]`).
fn data_scene_text(name: &str, csv: &str) -> String {
    let text = std::fs::read_to_string(asset(name)).unwrap();
    let (start, end) = (
        text.find("[[drives]]").unwrap(),
        text.find("[accuracy]").unwrap(),
    );
    format!(
        "{}[truth]\ndata = \"{csv}\"\n\n{}",
        &text[..start],
        &text[end..]
    )
}

/// The data a rig would measure on the example scene `name`, made by prbfit's own beam
/// mechanism (`prbfit solve --json`): SI, one path per drive, the drive's inputs under their
/// `[[drives]]` names and the stage's outputs (the loaded coordinates' motion, the
/// prescribed ones' reactions) as `stage_*`, plus `noise(c)` added to coordinate `c`'s
/// output in nondimensional units (L, radians, or `alpha`/`beta`).
fn beam_mechanism_csv(name: &str, noise: &mut dyn FnMut(usize) -> f64) -> String {
    let scene = Scene::from_file(std::path::Path::new(&asset(name))).unwrap();
    let m = scene.mechanism.as_ref().unwrap();
    let (l, ei) = m.scale();
    let solved = json(&prbfit(&["solve", "--scene", &asset(name), "--json"]));
    let kinds = m.drives[0].coordinates.map(|c| c.is_prescribed());
    for d in &m.drives {
        assert_eq!(d.coordinates.map(|c| c.is_prescribed()), kinds);
    }
    let names = [
        ["dx", "fx", "stage_dx", "stage_fx"],
        ["dy", "fy", "stage_dy", "stage_fy"],
        ["dphi", "mz", "stage_dphi", "stage_mz"],
    ];
    let mut head = vec!["path"];
    for c in 0..3 {
        head.push(names[c][if kinds[c] { 0 } else { 1 }]);
    }
    for c in 0..3 {
        head.push(names[c][if kinds[c] { 3 } else { 2 }]);
    }
    let pose_si = [l, l, 1.0];
    let load_si = [ei / (l * l), ei / (l * l), ei / l];
    let mut out = head.join(",") + "\n";
    for case in solved["cases"].as_array().unwrap() {
        let v = |key: &str, c: usize| case[key][c].as_f64().unwrap();
        let mut row = vec![case["drive"].to_string()];
        for c in 0..3 {
            row.push(if kinds[c] {
                format!("{:?}", v("stage", c) * pose_si[c])
            } else {
                format!("{:?}", v("stage_load", c) * load_si[c])
            });
        }
        for c in 0..3 {
            row.push(if kinds[c] {
                format!("{:?}", (v("stage_load", c) + noise(c)) * load_si[c])
            } else {
                format!("{:?}", (v("stage", c) + noise(c)) * pose_si[c])
            });
        }
        out.push_str(&(row.join(",") + "\n"));
    }
    out
}

fn no_noise(_: usize) -> f64 {
    0.0
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing from {v}"))
}

/// Round trip on three mechanisms: the parallel stage (every coordinate loaded: the stage's
/// motion measured), the slider-crank (every coordinate prescribed: the reactions measured)
/// and the fixed-guided segment (mixed). The data are the beam mechanism's own cases at
/// full precision, so the data scene's truth is the beam scene's to rounding; what differs
/// is how the PRB mechanism gets there (through the rows instead of proportionally), each
/// point converged to its Newton tolerance 1e-8 (`MECH_TOL`), so every figure agrees to
/// about 1e-8 and `J = mean(e^2)` to `O(1e-8 sqrt(J))`. The beam mechanism judged against the
/// data is its own path again (through the rows, at the default tolerance 1e-9 per tip):
/// within 1e-7 on every figure.
#[test]
fn data_from_the_beam_mechanism_gives_its_figures_and_fit() {
    let dir = Scratch::new("mech-data-round");
    for name in [
        "parallel-stage.toml",
        "slider-crank.toml",
        "fixed-guided.toml",
    ] {
        let csv = format!("{}.csv", name.trim_end_matches(".toml"));
        dir.write(&csv, &beam_mechanism_csv(name, &mut no_noise));
        let data = dir.write(name, &data_scene_text(name, &csv));
        let eval = |scene: &str| {
            json(&prbfit(&[
                "eval", "--scene", scene, "--model", "su-3r", "--json",
            ]))
        };
        let (on_data, on_beam) = (eval(&data), eval(&asset(name)));
        for key in MECH_FIGURES {
            // The reaction figures exist where some coordinate is prescribed, for both.
            assert_eq!(
                on_data.get(key).is_some(),
                on_beam.get(key).is_some(),
                "{key}"
            );
            if on_beam.get(key).is_none() {
                continue;
            }
            let (d, b) = (f(&on_data, key), f(&on_beam, key));
            let tol = if key == "objective" {
                1e-7 * b.sqrt() + 1e-14
            } else {
                1e-7
            };
            assert!((d - b).abs() <= tol, "{name} {key}: data {d} vs beam {b}");
        }
        assert_eq!(
            on_data["cases"].as_array().unwrap().len(),
            on_beam["cases"].as_array().unwrap().len()
        );
        let truth = &on_data["truth"];
        assert_eq!(truth["data"], csv.as_str(), "{name}: {truth}");
        for key in MECH_FIGURES.iter().filter(|k| on_beam.get(**k).is_some()) {
            let v = f(&truth["beam_vs_data"], key);
            assert!(
                v <= 1e-7,
                "{name}: the beam against its own data {key} = {v}"
            );
        }
        // The fit: the same model, as far as J can tell.
        let fit = |scene: &str| {
            json(&prbfit(&[
                "fit",
                "--scene",
                scene,
                "--topology",
                "2R",
                "--json",
            ]))
        };
        let (fd, fb) = (fit(&data), fit(&asset(name)));
        let (jd, jb) = (f(&fd, "objective"), f(&fb, "objective"));
        eprintln!(
            "{name}: su-3r J {} / {}; 2R fit J {jd:.6e} / {jb:.6e}",
            f(&on_data, "objective"),
            f(&on_beam, "objective")
        );
        assert!(
            (jd - jb).abs() <= 1e-7 * jb.sqrt() + 1e-14,
            "{name}: fitted J {jd} on data vs {jb} on the beam"
        );
        assert_eq!(fd["meets_targets"], fb["meets_targets"], "{name}");
    }
}

/// A measured path need not be proportional: rows that pull along the flexures first and
/// then push sideways on top are followed in order, each case at its own row's load. For
/// these moderate loads the stage is path independent (conservative loads, no bifurcation),
/// so the PRB mechanism's stage at each row is its proportional solution to that row's load,
/// and the beam mechanism's last row its proportional solution to the end load, each to the
/// Newton tolerances (1e-8 PRB, 1e-9 per beam tip): within 1e-7 L.
#[test]
fn a_turning_drive_is_followed_row_by_row() {
    use prbfit::beam::Resolution;
    use prbfit::mech::{exact, prb};
    use Coordinate::Loaded;
    let dir = Scratch::new("mech-data-turn");
    let scene = Scene::from_file(std::path::Path::new(&asset("parallel-stage.toml"))).unwrap();
    let base = scene.mechanism.clone().unwrap();
    let rows = [
        [5.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 10.0, 0.0],
        [10.0, 20.0, 0.0],
    ];
    let mut turning = base.clone();
    turning.drives = vec![Drive {
        coordinates: [Loaded(10.0), Loaded(20.0), Loaded(0.0)],
        steps: 4,
        rows: rows.to_vec(),
    }];
    let measured = exact::solve(&turning, Resolution::default()).unwrap();
    let (l, _) = base.scale();
    let mut csv = String::from("fx,fy,stage_dx,stage_dy,stage_dphi\n");
    for (r, c) in rows.iter().zip(&measured[0]) {
        csv.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?}\n",
            r[0],
            r[1],
            c.stage[0] * l,
            c.stage[1] * l,
            c.stage[2]
        ));
    }
    // The beam mechanism through the rows ends where the proportional path ends.
    let mut straight = base.clone();
    straight.drives = vec![Drive::proportional(turning.drives[0].coordinates, 8)];
    let end = exact::solve(&straight, Resolution::default()).unwrap()[0][7].clone();
    let last = &measured[0][3];
    for c in 0..3 {
        assert!(
            (last.stage[c] - end.stage[c]).abs() < 1e-7,
            "{:?} vs {:?}",
            last.stage,
            end.stage
        );
    }
    dir.write("turn.csv", &csv);
    let data = dir.write(
        "turn.toml",
        &data_scene_text("parallel-stage.toml", "turn.csv"),
    );
    let v = json(&prbfit(&[
        "eval", "--scene", &data, "--model", "su-3r", "--json",
    ]));
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 4);
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    for (case, r) in cases.iter().zip(rows) {
        let mut alone = base.clone();
        alone.drives = vec![Drive::proportional(
            [Loaded(r[0]), Loaded(r[1]), Loaded(r[2])],
            8,
        )];
        let want = prb::solve(&alone, &su, 1e-10).unwrap()[0][7].clone();
        for c in 0..3 {
            let got = case["stage"][c].as_f64().unwrap();
            assert!(
                (got - want.stage[c]).abs() < 1e-7,
                "row {r:?}: {case} vs {:?}",
                want.stage
            );
        }
        // The case is at the row's own load.
        let (_, ei) = base.scale();
        let alpha = r[1] * l * l / ei;
        assert!((case["stage_load"][1].as_f64().unwrap() - alpha).abs() < 1e-12);
    }
}

/// Noise of 0.1% L on the parallel stage's measured `dx` and `dy` (and 1e-3 rad on `dphi`):
/// a 3R fitted to the noisy data, judged against the noiseless beam mechanism. 16 cases give
/// 48 residuals for 7 free cells, which absorb about `7/48` of the noise's variance: the
/// residual against the noisy data is about `sqrt(J_clean_pos^2 + 2e-6 (1 - 7/48))` L rms,
/// and the fitted model moves from the noiseless fit's by about `1e-3 sqrt(7/48) = 3.8e-4` L
/// rms at most; a model that chased the noise would sit about `1.4e-3` L from the truth.
#[test]
fn noisy_stage_data_are_fitted_without_chasing_the_noise() {
    let dir = Scratch::new("mech-data-noise");
    let mut g = Gauss(0x9e37_79b9_7f4a_7c15);
    dir.write(
        "noisy.csv",
        &beam_mechanism_csv("parallel-stage.toml", &mut |_| g.next(1e-3)),
    );
    let noisy = dir.write(
        "noisy.toml",
        &data_scene_text("parallel-stage.toml", "noisy.csv"),
    );
    let beam = asset("parallel-stage.toml");
    // 3 stage coordinates of 16 cases: 48 residuals.
    common::fit_does_not_chase_the_noise(&noisy, &beam, 48.0);
}

/// `calibrate` on a mechanism: data made with E 10% above the scene's recover it to the
/// golden-section search's 1e-9 in the logarithm (1e-6 asserted), with the residual at the
/// solvers' tolerance; the thickness that explains them is about `1.1^(1/3)` thicker (the
/// bending stiffness goes as `E t^3`; shear and stretch, of relative size `(t/L)^2 = 1e-4`
/// here, make the rest), its residual well below the nominal one.
#[test]
fn calibration_recovers_the_flexures_modulus() {
    let dir = Scratch::new("mech-data-calibrate");
    let stiff = std::fs::read_to_string(asset("parallel-stage.toml"))
        .unwrap()
        .replace("youngs_modulus = 200e9", "youngs_modulus = 220e9");
    assert!(stiff.contains("220e9"));
    dir.write("stiff.toml", &stiff);
    // The data of the stiffer mechanism, by prbfit's beam mechanism.
    let text = {
        let scene = Scene::from_file(std::path::Path::new(&dir.file("stiff.toml"))).unwrap();
        let m = scene.mechanism.unwrap();
        let (l, ei) = m.scale();
        let solved = json(&prbfit(&[
            "solve",
            "--scene",
            &dir.file("stiff.toml"),
            "--json",
        ]));
        let mut out = String::from("path,fx,fy,stage_dx,stage_dy,stage_dphi\n");
        for c in solved["cases"].as_array().unwrap() {
            let v = |k: &str, i: usize| c[k][i].as_f64().unwrap();
            out.push_str(&format!(
                "{},{:?},{:?},{:?},{:?},{:?}\n",
                c["drive"],
                v("stage_load", 0) * ei / (l * l),
                v("stage_load", 1) * ei / (l * l),
                v("stage", 0) * l,
                v("stage", 1) * l,
                v("stage", 2)
            ));
        }
        out
    };
    dir.write("stiff.csv", &text);
    let data = dir.write(
        "data.toml",
        &data_scene_text("parallel-stage.toml", "stiff.csv"),
    );
    let e = json(&prbfit(&["calibrate", "--scene", &data, "--json"]));
    assert!((f(&e, "ratio") - 1.1).abs() < 1e-6, "{e}");
    assert!(f(&e["figures"], "max_pos_err") < 1e-7, "{e}");
    assert!(f(&e["nominal_figures"], "max_pos_err") > 1e-3, "{e}");
    let t = json(&prbfit(&[
        "calibrate",
        "--scene",
        &data,
        "--param",
        "thickness",
        "--json",
    ]));
    assert!(
        (f(&t, "ratio") - 1.1_f64.cbrt()).abs() < 1e-3,
        "{t} vs {}",
        1.1_f64.cbrt()
    );
    assert!(
        f(&t["figures"], "objective") < 1e-3 * f(&t["nominal_figures"], "objective"),
        "{t}"
    );
}

/// A model fitted to mechanism data records the file and its SHA-256, and so does the
/// selection's run; `select` judges on the data and says so.
#[test]
fn models_fitted_to_mechanism_data_name_the_data() {
    use sha2::Digest;
    let dir = Scratch::new("mech-data-record");
    let csv = beam_mechanism_csv("slider-crank.toml", &mut no_noise);
    dir.write("rig.csv", &csv);
    let data = dir.write("rig.toml", &data_scene_text("slider-crank.toml", "rig.csv"));
    let model = dir.file("m.toml");
    succeeded(&prbfit(&[
        "fit",
        "--scene",
        &data,
        "--topology",
        "2R",
        "-o",
        &model,
    ]));
    let written: toml::Value = toml::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let truth = &written["fit"]["truth"];
    let sha: String = sha2::Sha256::digest(csv.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    assert_eq!(truth["data"].as_str(), Some("rig.csv"));
    assert_eq!(truth["sha256"].as_str(), Some(sha.as_str()));
    assert_eq!(truth["rows"].as_integer(), Some(10));
    // select judges the ladder on the data, and names it.
    let v = json(&prbfit(&[
        "select",
        "--scene",
        &data,
        "--fidelity",
        "draft",
        "--json",
    ]));
    assert_eq!(v["truth"]["sha256"].as_str(), Some(sha.as_str()));
    assert_eq!(v["chosen"]["meets_targets"], true, "{v}");
    // The chosen model's figures are its figures on the data, as eval gives them (select
    // solves the PRB mechanism to Newton's 1e-8, eval to its --tol 1e-9: the reactions, of
    // order 1 over a scale of order 1, agree to about 1e-8).
    let chosen = v["chosen"]["prb"].as_str().unwrap();
    let e = json(&prbfit(&[
        "eval", "--scene", &data, "--prb", chosen, "--json",
    ]));
    let (a, b) = (
        f(&v["chosen"]["figures"], "max_force_err"),
        f(&e, "max_force_err"),
    );
    assert!((a - b).abs() < 1e-7, "select {a} vs eval {b}");
    // The text report names the data and the beam mechanism against it.
    let out = prbfit(&["eval", "--scene", &data, "--model", "su-3r"]);
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("truth: measured data rig.csv (10 rows in 1 path(s)"),
        "{text}"
    );
    assert!(
        text.contains("the scene's beam mechanism against the data"),
        "{text}"
    );
    assert!(text.contains("data Fy N*"), "{text}");
}

/// Every bad mechanism data file is exit 2 naming file:line:column and what is wrong; a
/// data scene that also gives [[drives]] is refused at its line; the commands that have
/// nothing to say about mechanism data (solve, tradeoff, the UI) say so.
#[test]
fn bad_mechanism_data_name_file_line_and_column() {
    let dir = Scratch::new("mech-data-bad");
    let scene = dir.write("s.toml", &data_scene_text("slider-crank.toml", "d.csv"));
    let head = "dx,dy,dphi,stage_fx,stage_fy,stage_mz\n";
    let good = "0,0.0015,0,-0.71,0.71,0\n";
    let cases: &[common::BadFile] = &[
        ("empty", String::new(), &["d.csv:1:1", "empty"]),
        ("header only", head.into(), &["d.csv:1:1", "no data rows"]),
        (
            "a prescribed coordinate's reaction missing",
            "dx,dy,dphi,stage_fx,stage_mz\n".into(),
            &["d.csv:1:1", "missing column `stage_fy`", "dy is prescribed"],
        ),
        (
            "a loaded coordinate's motion missing",
            "dx,fy,dphi,stage_fx,stage_mz\n".into(),
            &["d.csv:1:1", "missing column `stage_dy`", "fy is loaded"],
        ),
        (
            "displacement and load of one coordinate",
            "dx,dy,fy,dphi,stage_fx,stage_fy,stage_mz\n".into(),
            &["d.csv:1:4", "either a displacement (dy) or a load (fy)"],
        ),
        (
            "a cantilever's column",
            "dx,dy,dphi,stage_fx,stage_fy,stage_mz,theta\n".into(),
            &["d.csv:1:39", "theta", "a cantilever's column"],
        ),
        (
            "unknown column",
            "dx,dy,dphi,stage_fx,stage_fy,stage_mz,stage_q\n".into(),
            &["d.csv:1:39", "stage_q", "unknown column"],
        ),
        (
            "a column twice",
            "dx,dy,dphi,stage_fx,stage_fy,stage_mz,dx\n".into(),
            &["d.csv:1:39", "given twice"],
        ),
        (
            "not a number",
            format!("{head}{good}0,0.003,0,-1.3,one,0\n"),
            &["d.csv:3:", "stage_fy", "not a number"],
        ),
        (
            "NaN",
            format!("{head}0,NaN,0,-0.71,0.71,0\n"),
            &["d.csv:2:3", "dy", "not a finite number"],
        ),
        (
            "an enormous motion, blamed on its own line",
            format!("{head}{good}0,1e308,0,-1.3,1.3,0\n"),
            &["d.csv:3:3", "dy", "1e308", "is beyond the 1e9"],
        ),
        (
            "too many fields",
            format!("{head}0,0.0015,0,-0.71,0.71,0,7\n"),
            &["d.csv:2:", "7 fields", "6 columns"],
        ),
        (
            "shrinking path",
            format!("{head}{good}0,0.001,0,-0.5,0.5,0\n"),
            &["d.csv:3:1", "path 1 shrinks", "line 2"],
        ),
        (
            "a repeated input that disagrees",
            "dx,dy,dphi,stage_fx,stage_fy,stage_mz,stage_dy\n0,0.0015,0,-0.71,0.71,0,0.002\n"
                .into(),
            &["d.csv:2:", "stage_dy", "contradicts the input dy"],
        ),
        // A rig that recorded no force: every relative force error would be against 0 (a
        // model's J was 3.6e23, exit 0).
        (
            "every reaction 0",
            format!("{head}0,0.0015,0,0,0,0\n0,0.003,0,0,0,0\n"),
            &[
                "d.csv:1:1",
                "every measured reaction of the prescribed coordinates (stage_fx, stage_fy, \
                 stage_mz) is 0: no flexure lets a drive hold them without force, and a \
                 model's force errors relative to 0 are no figure",
            ],
        ),
    ];
    common::assert_bad_data_files(&dir, &scene, cases);
    // A repeated input that agrees is fine.
    dir.write(
        "d.csv",
        "dx,dy,dphi,stage_fx,stage_fy,stage_mz,stage_dy\n0,0.0015,0,-0.71,0.71,0,0.0015\n",
    );
    succeeded(&prbfit(&["eval", "--scene", &scene, "--model", "su-3r"]));
    // [[drives]] beside the data.
    let both = std::fs::read_to_string(asset("slider-crank.toml"))
        .unwrap()
        .replace("[accuracy]", "[truth]\ndata = \"d.csv\"\n\n[accuracy]");
    let both = dir.write("both.toml", &both);
    assert_input_error(
        &prbfit(&["eval", "--scene", &both]),
        &["both.toml", "drives", "remove the [[drives]]"],
    );
    // The commands with nothing to say about the data.
    dir.write("d.csv", &format!("{head}{good}"));
    for args in [
        vec!["solve", "--scene", &scene],
        vec!["tradeoff", "--scene", &scene],
    ] {
        let out = prbfit(&args);
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}

/// The shipped example `slider-crank-rig.toml`: its rows are the beam mechanism at 190 GPa
/// printed to 0.1 mN (forces of 0.68 N and more: at most 7.4e-5 relative per row), so the
/// calibrated modulus is 190 GPa to 1e-4 and the calibrated beam mechanism meets the data to
/// that printing; a 1R fitted to the rows meets the scene's targets.
#[test]
fn the_shipped_rig_data_calibrate_to_their_modulus() {
    let scene = asset("slider-crank-rig.toml");
    let c = json(&prbfit(&["calibrate", "--scene", &scene, "--json"]));
    assert!((f(&c, "value") / 190e9 - 1.0).abs() < 1e-4, "{c}");
    assert!(f(&c["figures"], "max_force_err") < 1e-4, "{c}");
    let fit = json(&prbfit(&[
        "fit",
        "--scene",
        &scene,
        "--topology",
        "1R",
        "--json",
    ]));
    assert_eq!(fit["meets_targets"], true, "{fit}");
    assert_eq!(fit["truth"]["data"], "slider-crank-rig.csv");
}
