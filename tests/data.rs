//! Data scenes (DESIGN §9): measured load cases and tips as the truth.
//!
//! - Round trip: data written from prbfit's own beam and read back as the truth gives the
//!   beam scene's figures and fit. The data are the beam's tips printed with 17 significant
//!   digits, so the figures agree to the beam solver's own tolerance (tips good to 1e-8 at
//!   the default `tol = 1e-9`, `Resolution::claimed_tip_error`).
//! - Noise: data with 0.1% L Gaussian noise are fitted without chasing the noise.
//! - Calibration recovers the E and the thickness the data were made with.
//! - Every malformed file is exit status 2 naming file:line:column.
//! - A beam edit (the UI) converts SI rows again: rebased rows are the rows read with the
//!   edited beam.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{assert_input_error, json, prbfit, succeeded, Gauss, Scratch};
use prbfit::beam::{BeamSolver, Load, Resolution};
use prbfit::scene::Scene;

/// The built-in scene's beam and targets, with `[truth] data = "{csv}"` in place of its loads
/// and `E = {e}` as the nominal modulus.
fn data_scene(csv: &str, e: f64, thickness: f64) -> String {
    format!(
        r#"name = "measured flexure"
[beam]
length = 0.05
width = 0.01
thickness = {thickness:?}
youngs_modulus = {e:?}
poisson_ratio = 0.3
effects = "none"

[truth]
data = "{csv}"
"#
    )
}

/// The same beam as a beam scene with the built-in scene's four load paths.
fn beam_scene() -> String {
    let builtin = Scene::builtin();
    let mut s = builtin.clone();
    s.beam.effects = prbfit::scene::EffectsChoice::Fixed(prbfit::beam::Effects::NONE);
    s.name = "beam flexure".into();
    s.to_toml()
}

/// The beam's tips over the built-in scene's cases for a beam of modulus `e` and thickness
/// `t` (effects off), as CSV rows: SI (`fx, fy, mz, x, y, theta`) or nondimensional, with
/// `noise(path, row, component)` added to the tip (units of L and radians).
fn beam_csv(e: f64, t: f64, si: bool, noise: &mut dyn FnMut() -> f64) -> String {
    let builtin = Scene::builtin();
    let mut beam = builtin.beam;
    beam.youngs_modulus = e;
    beam.thickness = t;
    beam.effects = prbfit::scene::EffectsChoice::Fixed(prbfit::beam::Effects::NONE);
    let solver = BeamSolver::new(beam.model(), Resolution::default()).unwrap();
    let ei = e * beam.second_moment();
    let (l, force, moment) = (beam.length, ei / beam.length.powi(2), ei / beam.length);
    let mut out = if si {
        String::from("path,fx,fy,mz,x,y,theta\n")
    } else {
        String::from("path,alpha_x,alpha_y,beta,a,b,phi\n")
    };
    for (i, path) in builtin.loads.iter().enumerate() {
        for sol in solver.solve_path(path.end, path.steps).unwrap() {
            let (ld, tip) = (sol.load, sol.tip);
            let (a, b, phi) = (tip.a + noise(), tip.b + noise(), tip.phi + noise());
            if si {
                out.push_str(&format!(
                    "{},{:?},{:?},{:?},{:?},{:?},{:?}\n",
                    i + 1,
                    ld.alpha_x * force,
                    ld.alpha_y * force,
                    ld.beta * moment,
                    a * l,
                    b * l,
                    phi
                ));
            } else {
                out.push_str(&format!(
                    "{},{:?},{:?},{:?},{:?},{:?},{:?}\n",
                    i + 1,
                    ld.alpha_x,
                    ld.alpha_y,
                    ld.beta,
                    a,
                    b,
                    phi
                ));
            }
        }
    }
    out
}

fn no_noise() -> f64 {
    0.0
}

/// The figures of `prbfit eval --json` as (rms pos, max pos, rms ang, max ang, J).
fn figures(v: &serde_json::Value) -> [f64; 5] {
    [
        "rms_pos_err",
        "max_pos_err",
        "rms_ang_err",
        "max_ang_err",
        "objective",
    ]
    .map(|k| v[k].as_f64().unwrap())
}

#[test]
fn data_from_the_beam_gives_the_beam_scenes_figures_and_fit() {
    let dir = Scratch::new("data-round-trip");
    let beam = dir.write("beam.toml", &beam_scene());
    let reference = json(&prbfit(&[
        "eval", "--scene", &beam, "--model", "su-3r", "--json",
    ]));
    for si in [false, true] {
        dir.write("own.csv", &beam_csv(200e9, 0.0005, si, &mut no_noise));
        let scene = dir.write("own.toml", &data_scene("own.csv", 200e9, 0.0005));
        let v = json(&prbfit(&[
            "eval", "--scene", &scene, "--model", "su-3r", "--json",
        ]));
        assert_eq!(v["truth"]["rows"], 20, "{v}");
        // The beam's own error against data made from it: the solver's tolerance.
        assert!(v["truth"]["beam_vs_data"]["max_pos_err"].as_f64().unwrap() < 1e-8);
        for (a, b) in figures(&v).iter().zip(figures(&reference)) {
            assert!(
                (a - b).abs() <= 1e-8 * (1.0 + b.abs()),
                "si {si}: {a} vs {b}"
            );
        }
    }
    // The same fit: a 2R fitted to the data and to the beam, judged on the beam scene.
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
    let (on_data, on_beam) = (fit(&dir.file("own.toml")), fit(&beam));
    let (jd, jb) = (
        on_data["objective"].as_f64().unwrap(),
        on_beam["objective"].as_f64().unwrap(),
    );
    // The fit's normal baseline and the data differ by the beam's tolerance (1e-8 on tips),
    // which moves J = mean(e^2) by O(1e-8 sqrt(J)).
    assert!((jd - jb).abs() <= 1e-7 * jb.sqrt(), "{jd} vs {jb}");
}

/// Noise of 0.1% L on every tip coordinate (and 1e-3 rad on the angle): a 3R fitted to the
/// noisy data is judged against the noiseless beam. Seven free cells fitted to 60 residuals
/// average the noise down by about `sqrt(7/60)`, so the fitted model's error against the
/// truth grows by about `1e-3 sqrt(7/60) = 3.4e-4` L rms over the noiseless fit's, well under
/// the noise itself; a model that chased the noise would sit about `1e-3` L from the truth.
#[test]
fn noisy_data_fit_without_chasing_the_noise() {
    let dir = Scratch::new("data-noise");
    let mut g = Gauss(0x9e37_79b9_7f4a_7c15);
    dir.write(
        "noisy.csv",
        &beam_csv(200e9, 0.0005, false, &mut || g.next(1e-3)),
    );
    let noisy = dir.write("noisy.toml", &data_scene("noisy.csv", 200e9, 0.0005));
    let beam = dir.write("beam.toml", &beam_scene());
    // 3 tip coordinates of 20 cases: 60 residuals.
    common::fit_does_not_chase_the_noise(&noisy, &beam, 60.0);
}

/// `calibrate` recovers the modulus and the thickness the data were made with from a
/// nominal beam 10% and 4% off (to the golden-section search's 1e-9 in the logarithm, well
/// inside 1e-6), and its residual is the solver's tolerance.
#[test]
fn calibration_recovers_the_beam_the_data_came_from() {
    let dir = Scratch::new("data-calibrate");
    dir.write("si.csv", &beam_csv(200e9, 0.0005, true, &mut no_noise));
    let off_e = dir.write("e.toml", &data_scene("si.csv", 180e9, 0.0005));
    let v = json(&prbfit(&["calibrate", "--scene", &off_e, "--json"]));
    let e = v["value"].as_f64().unwrap();
    assert!((e / 200e9 - 1.0).abs() < 1e-6, "{v}");
    assert!(v["figures"]["max_pos_err"].as_f64().unwrap() < 1e-7, "{v}");
    assert!(
        v["nominal_figures"]["max_pos_err"].as_f64().unwrap() > 1e-2,
        "{v}"
    );
    let off_t = dir.write("t.toml", &data_scene("si.csv", 200e9, 0.00052));
    let v = json(&prbfit(&[
        "calibrate",
        "--scene",
        &off_t,
        "--param",
        "thickness",
        "--json",
    ]));
    let t = v["value"].as_f64().unwrap();
    assert!((t / 0.0005 - 1.0).abs() < 1e-6, "{v}");
    assert_input_error(
        &prbfit(&["calibrate", "--scene", &off_t, "--param", "width"]),
        &["--param", "youngs_modulus"],
    );
    assert_input_error(&prbfit(&["calibrate"]), &["no measured data"]);
}

/// A fitted model file records the data it was fitted to: its name and its SHA-256.
#[test]
fn model_files_name_the_data_and_its_hash() {
    use sha2::Digest;
    let dir = Scratch::new("data-provenance");
    let csv = beam_csv(200e9, 0.0005, false, &mut no_noise);
    dir.write("own.csv", &csv);
    let scene = dir.write("own.toml", &data_scene("own.csv", 200e9, 0.0005));
    let model = dir.file("m.toml");
    succeeded(&prbfit(&[
        "fit",
        "--scene",
        &scene,
        "--topology",
        "1R",
        "-o",
        &model,
    ]));
    let m: toml::Value = toml::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let hash: String = sha2::Sha256::digest(csv.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    assert_eq!(m["fit"]["truth"]["data"].as_str(), Some("own.csv"));
    assert_eq!(m["fit"]["truth"]["sha256"].as_str(), Some(hash.as_str()));
    assert_eq!(m["fit"]["truth"]["rows"].as_integer(), Some(20));
    // select works on the data too, and names it.
    let v = json(&prbfit(&[
        "select",
        "--scene",
        &scene,
        "--fidelity",
        "draft",
        "--json",
    ]));
    assert_eq!(v["truth"]["sha256"].as_str(), Some(hash.as_str()));
    assert!(!v["rows"].as_array().unwrap().is_empty());
    // Commands with nothing to say about data say so.
    for cmd in ["solve", "tradeoff"] {
        assert_input_error(&prbfit(&[cmd, "--scene", &scene]), &["data scene", cmd]);
    }
    assert_input_error(
        &prbfit(&[
            "eval", "--scene", &scene, "--model", "su-3r", "--load", "0,1,0",
        ]),
        &["--load", "own.csv"],
    );
}

/// `n` rows of path `path` whose load grows from the unloaded state (tips made up: only the
/// reader sees them).
fn growing_rows(path: usize, n: usize) -> String {
    (1..=n)
        .map(|k| format!("{path},0,{},0,0.9,0.3,0.4\n", k as f64 * 1e-3))
        .collect()
}

/// Every malformed data file: exit status 2, naming the file, the line and the column.
#[test]
fn bad_data_files_name_file_line_and_column() {
    let dir = Scratch::new("data-bad");
    let scene = dir.write("s.toml", &data_scene("d.csv", 200e9, 0.0005));
    let head = "path,alpha_x,alpha_y,beta,a,b,phi\n";
    let good = "1,0,1,0,0.94,0.30,0.46\n";
    let cases: &[common::BadFile] = &[
        ("empty", String::new(), &["d.csv:1:1", "empty"]),
        (
            "header only",
            head.to_string(),
            &["d.csv:1:1", "no data rows"],
        ),
        (
            "missing column",
            "alpha_x,alpha_y,beta,a,b\n0,1,0,0.9,0.3\n".into(),
            &["d.csv:1:1", "missing column `phi`"],
        ),
        (
            "unknown column",
            "path,alpha_x,alpha_y,beta,a,b,phi,fz\n".into(),
            &["d.csv:1:35", "fz", "unknown column"],
        ),
        (
            "mixed units",
            "path,fx,fy,mz,a,b,phi\n1,0,1,0,0.9,0.3,0.4\n".into(),
            &["d.csv:1:", "mixed units"],
        ),
        (
            "not a number",
            format!("{head}{good}1,0,2,0,0.8,zero,0.78\n"),
            &["d.csv:3:13", "b", "not a number"],
        ),
        (
            "NaN",
            format!("{head}1,0,NaN,0,0.9,0.3,0.4\n"),
            &["d.csv:2:5", "alpha_y", "not a finite number"],
        ),
        (
            "too few fields",
            format!("{head}1,0,1,0,0.9,0.3\n"),
            &["d.csv:2:", "6 fields", "7 columns"],
        ),
        (
            "shrinking path",
            format!("{head}{good}1,0,0.5,0,0.98,0.15,0.24\n"),
            &["d.csv:3:1", "path 1 shrinks", "line 2"],
        ),
        (
            "path comes back",
            format!("{head}{good}2,0,0,1,0.9,0.3,1.0\n1,0,2,0,0.8,0.5,0.78\n"),
            &["d.csv:4:1", "path 1 comes back"],
        ),
        (
            "bad path number",
            format!("{head}one,0,1,0,0.9,0.3,0.4\n"),
            &["d.csv:2:1", "not a path number"],
        ),
        // Finite but far past any beam's reach (a unit slip, a corrupt file): refused at the
        // field, before it overflows what is derived from it.
        (
            "an enormous load",
            format!("{head}{good}1,0,1e308,0,0.8,0.5,0.78\n"),
            &["d.csv:3:5", "alpha_y", "1e308 is beyond the 1e9"],
        ),
        (
            "an enormous angle",
            format!("{head}1,0,1,0,0.9,0.3,1e300\n"),
            &["d.csv:2:17", "phi", "1e300 is beyond the 1e9"],
        ),
        // The scene's limits (docs/cli.md, "Limits") hold for rows too, refused at the row
        // that passes them: 10000 steps a path, 100000 cases in all.
        (
            "a path of 10001 rows",
            format!("{head}{}", growing_rows(1, 10_001)),
            &["d.csv:10002:1", "path 1", "10000 steps"],
        ),
        (
            "100001 rows",
            format!(
                "{head}{}",
                (1..=11).map(|p| growing_rows(p, 9_091)).collect::<String>()
            ),
            &["d.csv:100002:1", "100000 load cases"],
        ),
        // The same limit over paths of one row each (the reader once searched its paths
        // for every row: seconds, where this is refused at once).
        (
            "100001 one-row paths",
            format!(
                "{head}{}",
                (1..=100_001)
                    .map(|p| growing_rows(p, 1))
                    .collect::<String>()
            ),
            &["d.csv:100002:1", "100000 load cases"],
        ),
    ];
    common::assert_bad_data_files(&dir, &scene, cases);
}

/// The loads of measured data need not be proportional: a path whose rows turn (a force,
/// then a moment added on top) is followed row by row, and the PRB model's tips at the rows
/// are its solutions at the rows' own loads (checked against single solves from rest,
/// which reach the same branch for these moderate loads).
#[test]
fn a_turning_path_is_followed_row_by_row() {
    let dir = Scratch::new("data-turn");
    let rows = [
        (0.0, 1.0, 0.0),
        (0.0, 2.0, 0.0),
        (0.0, 2.0, 0.5),
        (0.0, 2.0, 1.0),
    ];
    let mut csv = String::from("alpha_x,alpha_y,beta,a,b,phi\n");
    let solver = BeamSolver::new(Scene::builtin().beam.model(), Resolution::default()).unwrap();
    for (ax, ay, b) in rows {
        let tip = solver.solve(Load::new(ax, ay, b)).unwrap().tip;
        csv.push_str(&format!(
            "{ax},{ay},{b},{:?},{:?},{:?}\n",
            tip.a, tip.b, tip.phi
        ));
    }
    dir.write("turn.csv", &csv);
    let scene = dir.write("turn.toml", &data_scene("turn.csv", 200e9, 0.0005));
    let v = json(&prbfit(&[
        "eval", "--scene", &scene, "--model", "su-3r", "--json",
    ]));
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 4);
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let prb = prbfit::prb::PrbSolver::new(&su, 0.0);
    for (c, (ax, ay, b)) in cases.iter().zip(rows) {
        let alone = prb.solve(Load::new(ax, ay, b)).unwrap().tip;
        let a = c["a"].as_f64().unwrap();
        assert!((a - alone.a).abs() < 1e-8, "{c} vs {alone:?}");
    }
}

/// The shipped example (issue 14 item 6): a wide steel strip whose 3D FEA (by `prbfit fea
/// --section solid`) no uniform beam matches. A 3R fitted to the FEA data meets the scene's
/// targets against that data; the 3R fitted to the uniform beam misses them by several
/// times, and the calibrated modulus lies between the narrow beam's and the plate's.
#[test]
fn the_wide_strip_is_fitted_to_its_fea_not_to_the_beam() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let data = format!("{dir}/wide-strip-fea.toml");
    let beam = format!("{dir}/wide-strip.toml");
    let fit = |scene: &str| {
        json(&prbfit(&[
            "fit",
            "--scene",
            scene,
            "--topology",
            "3R",
            "--json",
        ]))["prb"]
            .as_str()
            .unwrap()
            .to_string()
    };
    let (on_data, on_beam) = (fit(&data), fit(&beam));
    let judged = |m: &str| json(&prbfit(&["eval", "--scene", &data, "--prb", m, "--json"]));
    let (d, b) = (judged(&on_data), judged(&on_beam));
    assert_eq!(d["meets_targets"], true, "{d}");
    assert_eq!(b["meets_targets"], false, "{b}");
    assert!(b["max_pos_err"].as_f64().unwrap() > 3.0 * d["max_pos_err"].as_f64().unwrap());
    let c = json(&prbfit(&["calibrate", "--scene", &data, "--json"]));
    let ratio = c["ratio"].as_f64().unwrap();
    // Between the narrow beam (1) and the plate (1 / (1 - 0.3^2) = 1.099).
    assert!(ratio > 1.01 && ratio < 1.099, "{c}");
}

/// The shipped example of issue 14 item 6: a spring-steel flexure tapered from 0.5 mm at the
/// clamp to 0.25 mm at the tip, whose plane-stress FEA (`prbfit fea --taper 0.5`,
/// `assets/scenes/tapered-flexure-fea.csv`) is the truth. Measured (README, worked example):
/// - no uniform beam matches it: calibrating E leaves max 1.455e-1 L (29 x the 0.005 L
///   target), calibrating the thickness the same; the FEA's own mesh error (about 1e-3 L on
///   40 elements, `tests/fea.rs`) is far too small to explain that, so the test asks for
///   more than 10 x the target;
/// - a 3R fitted to the FEA comes within 1.09 x the position target (5.444e-3 L, angle
///   5.524e-3 rad): it does not meet it, and no 3R fitted by J does (seeds 1, 2, 3, 7 at
///   precise fidelity and another start reach the same J); it is 41 x nearer the FEA than the 3R fitted to the uniform beam
///   (2.212e-1 L), asked here as within 2 x the target and 10 x nearer;
/// - a 4R fitted to the FEA meets the targets (2.898e-3 L, 2.954e-3 rad: 0.58 and 0.30 of
///   them), the 4R fitted to the uniform beam misses them on the FEA by 44 x.
///
/// The FEA's mesh does not decide these: on 80 elements instead of 40 the tips move by at
/// most 2.8e-4 L and 8.1e-4 rad, and the 3R and 4R fitted to that FEA reach 5.456e-3 and
/// 2.904e-3 L.
#[test]
fn the_tapered_flexure_is_fitted_to_its_fea_not_to_a_uniform_beam() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let data = format!("{dir}/tapered-flexure-fea.toml");
    let beam = format!("{dir}/tapered-flexure.toml");
    let target = Scene::from_file(std::path::Path::new(&data))
        .unwrap()
        .accuracy;
    for param in ["youngs_modulus", "thickness"] {
        let c = json(&prbfit(&[
            "calibrate",
            "--scene",
            &data,
            "--param",
            param,
            "--json",
        ]));
        let max_pos = c["figures"]["max_pos_err"].as_f64().unwrap();
        let max_ang = c["figures"]["max_ang_err"].as_f64().unwrap();
        println!("calibrated {param}: max pos {max_pos:.3e} L, max ang {max_ang:.3e} rad");
        assert!(
            max_pos > 10.0 * target.max_pos_err && max_ang > 10.0 * target.max_ang_err,
            "{c}"
        );
    }
    let fit = |scene: &str, topology: &str| {
        json(&prbfit(&[
            "fit",
            "--scene",
            scene,
            "--topology",
            topology,
            "--json",
        ]))["prb"]
            .as_str()
            .unwrap()
            .to_string()
    };
    let judged = |m: &str| json(&prbfit(&["eval", "--scene", &data, "--prb", m, "--json"]));
    let max_pos = |v: &serde_json::Value| v["max_pos_err"].as_f64().unwrap();
    let max_ang = |v: &serde_json::Value| v["max_ang_err"].as_f64().unwrap();
    let mut judged_3r = Vec::new();
    for topology in ["3R", "4R"] {
        let (d, b) = (judged(&fit(&data, topology)), judged(&fit(&beam, topology)));
        println!(
            "{topology} on the FEA: fitted to it {:.3e} L, {:.3e} rad; fitted to the uniform \
             beam {:.3e} L, {:.3e} rad",
            max_pos(&d),
            max_ang(&d),
            max_pos(&b),
            max_ang(&b)
        );
        assert_eq!(b["meets_targets"], false, "{b}");
        assert!(max_pos(&b) > 10.0 * target.max_pos_err, "{b}");
        judged_3r.push((d, b));
    }
    let (d3, b3) = &judged_3r[0];
    assert!(
        max_pos(d3) < 2.0 * target.max_pos_err && max_ang(d3) < 2.0 * target.max_ang_err,
        "{d3}"
    );
    assert!(max_pos(b3) > 10.0 * max_pos(d3), "{d3} {b3}");
    let (d4, _) = &judged_3r[1];
    assert_eq!(d4["meets_targets"], true, "{d4}");
}

/// Issue 14 item 5 on the shipped 3D FEA of the wide strip (10 t wide, 1.5 w long): the
/// narrow beam (plane stress) is too soft and the plate (`E / (1 - nu^2)`) too stiff, by
/// several times the scene's targets; the plane-strain effect with the section's plate
/// fraction (`E / (1 - nu^2 phi)`, `phi` from the ends and each case's curvature) meets them.
/// The rest is the criterion's error (its `phi` within 0.1 of the 3D FEA's, `tests/fea.rs`:
/// 0.9 % in stiffness) and the FEA mesh's.
#[test]
fn plane_strain_with_the_plate_fraction_closes_the_wide_strips_gap() {
    use prbfit::beam::{BeamModel, Effects};
    use prbfit::scene::EffectsChoice;
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/wide-strip-fea.toml"
    );
    let scene = Scene::from_file(std::path::Path::new(path)).unwrap();
    let truth = scene.truth.clone().unwrap();
    let wide = Effects::ALL.with_plane_strain(true);
    let mut spec = scene.beam;
    spec.effects = EffectsChoice::Fixed(wide);
    let interpolated = spec.model();
    let narrow = scene.beam.model();
    // No width: the unboundedly wide section, the plate limit.
    let plate = BeamModel::new(spec.slenderness(), spec.poisson_ratio, None, wide).unwrap();
    assert_eq!(plate.plate_fraction(), 1.0);
    assert!(interpolated.plate_fraction() > 0.3 && interpolated.plate_fraction() < 0.6);
    let against = |model: BeamModel| {
        let solver = BeamSolver::new(model, Resolution::default()).unwrap();
        let (mut pos, mut ang) = (0.0_f64, 0.0_f64);
        for row in truth.paths.iter().flat_map(|p| &p.rows) {
            let tip = solver.solve(row.load).unwrap().tip;
            pos = pos.max((tip.a - row.tip.a).hypot(tip.b - row.tip.b));
            ang = ang.max((tip.phi - row.tip.phi).abs());
        }
        (pos, ang)
    };
    let (n, p, i) = (against(narrow), against(plate), against(interpolated));
    println!("beam against the 3D FEA: max pos (L), max ang (rad)");
    println!("  plane stress        {:.3e} {:.3e}", n.0, n.1);
    println!("  plate E/(1-nu^2)    {:.3e} {:.3e}", p.0, p.1);
    println!("  E/(1-nu^2 phi)      {:.3e} {:.3e}", i.0, i.1);
    let a = scene.accuracy;
    let meets = |(pos, ang): (f64, f64)| pos <= a.max_pos_err && ang <= a.max_ang_err;
    assert!(!meets(n) && !meets(p), "{n:?} {p:?}");
    assert!(meets(i), "{i:?}");
    // Within the criterion's 0.9 % stiffness error of the FEA: at most a fifth of the
    // narrow beam's 4.6-6.5 % gap.
    assert!(i.0 < n.0 / 5.0 && i.0 < p.0 / 3.0, "{i:?} {n:?} {p:?}");
}

/// The slender steel leaf of `assets/scenes/steel-flexure.toml` (40 mm long, 8 mm wide,
/// 0.3 mm thick) by 3D FEA under a transverse force and a tip moment. The fixture was written
/// by `prbfit fea --section solid --mesh 40` (CalculiX 2.20, 81 s) on that beam with the
/// paths `alpha_y = 2` and `beta = 1.5`, two steps each; 2D plane stress on the same mesh is
/// within 7.9e-4 L of the narrow beam. The 3D strip is 2.4-5.5 % stiffer: the narrow beam
/// misses the scene's targets by several times, the beam with the plane-strain effect meets
/// them, which is why `effects = "auto"` keeps plane strain on this scene.
#[test]
fn the_steel_leaf_needs_plane_strain_by_3d_fea() {
    let dir = Scratch::new("steel-leaf-fea");
    std::fs::copy(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/steel-flexure-fea.csv"
        ),
        dir.file("fea.csv"),
    )
    .unwrap();
    let beam_against_fea = |effects: &str| {
        let scene = dir.file("leaf.toml");
        std::fs::write(
            &scene,
            format!(
                "name = \"steel leaf, 3D FEA\"\n[beam]\nlength = 0.04\nwidth = 0.008\n\
                 thickness = 0.0003\nyoungs_modulus = 200e9\npoisson_ratio = 0.29\n\
                 effects = {effects}\n[truth]\ndata = \"fea.csv\"\n[accuracy]\n\
                 max_pos_err = 0.005\nmax_ang_err = 0.01\n"
            ),
        )
        .unwrap();
        let v = json(&prbfit(&[
            "eval",
            "--scene",
            &scene,
            "--model",
            "howell-1r",
            "--json",
        ]));
        let beam = &v["truth"]["beam_vs_data"];
        (
            beam["max_pos_err"].as_f64().unwrap(),
            beam["max_ang_err"].as_f64().unwrap(),
        )
    };
    let narrow = beam_against_fea("[\"shear\", \"extension\", \"poisson\"]");
    let wide = beam_against_fea("[\"shear\", \"extension\", \"poisson\", \"plane_strain\"]");
    println!("narrow beam against the 3D FEA: {narrow:?}; with plane strain: {wide:?}");
    assert!(
        narrow.0 > 5.0 * 0.005 && narrow.1 > 5.0 * 0.01,
        "{narrow:?}"
    );
    // Within the 2D mesh's own 7.9e-4 L plus the criterion's 1 % of stiffness.
    assert!(wide.0 < 0.005 && wide.1 < 0.01, "{wide:?}");
}

/// A data scene whose beam is edited softer keeps its rows within reach or is refused, as
/// its file would be refused with that beam: at 1e-3 Pa the wide strip's FEA loads are 1e14
/// nondimensional (the edit was accepted, and every command failed on it later).
#[test]
fn a_beam_edit_that_puts_the_rows_out_of_reach_is_refused() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/wide-strip-fea.toml");
    let scene = Scene::from_file(&path).unwrap();
    scene.validate().unwrap();
    let mut soft = scene.clone();
    soft.beam.youngs_modulus = 1e-3;
    let soft = soft.rebased(&scene.beam).unwrap();
    let e = soft.validate().unwrap_err();
    assert_eq!(e.key.as_deref(), Some("truth.data"), "{e}");
    assert!(e.message.contains("wide-strip-fea.csv:2:"), "{e}");
    assert!(e.message.contains("beyond the 1e9"), "{e}");
}

/// The UI converts a data scene's rows again when its nominal beam is edited
/// (`DataTruth::rebased`): SI rows rebased from one beam to another are the rows read with
/// the other, to a few ulps (two scale ratios multiplied against one scale); nondimensional
/// rows are the same on any beam; a path that would shrink on the other beam (the load
/// magnitude adds force and moment terms, which scale differently) is refused, as reading
/// the file with that beam refuses it.
#[test]
fn rebased_rows_are_the_rows_read_with_the_other_beam() {
    use prbfit::scene::data::{parse_csv, DataTruth, Units};
    let truth = |csv: &str, beam| {
        let (paths, units) = parse_csv(csv, "t.csv", beam).unwrap();
        DataTruth {
            file: "t.csv".into(),
            sha256: String::new(),
            units,
            paths,
            stage: None,
        }
    };
    let a = Scene::builtin().beam;
    let mut b = a;
    b.youngs_modulus *= 1.3;
    b.length *= 0.8;
    b.thickness *= 1.1;
    let si = "path,fx,fy,mz,x,y,theta\n\
              1,1,2,0.01,0.049,0.004,0.1\n\
              1,2,4,0.02,0.047,0.008,0.2\n\
              2,0,0,0.05,0.048,0.01,0.3\n";
    let on_a = truth(si, &a);
    assert_eq!(on_a.units, Units::Si);
    let rebased = on_a.rebased(&a, &b).unwrap();
    let on_b = truth(si, &b);
    assert_ne!(on_a.paths, on_b.paths, "the beams convert differently");
    let close = |x: f64, y: f64| (x - y).abs() <= 4.0 * f64::EPSILON * x.abs().max(y.abs());
    for (p, q) in rebased.paths.iter().zip(&on_b.paths) {
        assert_eq!((p.id, p.rows.len()), (q.id, q.rows.len()));
        for (r, s) in p.rows.iter().zip(&q.rows) {
            assert_eq!(r.line, s.line);
            for (x, y) in [
                (r.load.alpha_x, s.load.alpha_x),
                (r.load.alpha_y, s.load.alpha_y),
                (r.load.beta, s.load.beta),
                (r.tip.a, s.tip.a),
                (r.tip.b, s.tip.b),
                (r.tip.phi, s.tip.phi),
            ] {
                assert!(close(x, y), "line {}: {x} rebased, {y} read", r.line);
            }
        }
    }

    let nd = "alpha_x,alpha_y,beta,a,b,phi\n0,1,0,0.9,0.3,0.5\n0,2,0,0.8,0.5,0.8\n";
    let on_a = truth(nd, &a);
    assert_eq!(on_a.units, Units::Nondimensional);
    // A spreadsheet's byte-order mark changes nothing (it made `\u{feff}alpha_x` an unknown
    // column).
    assert_eq!(truth(&format!("\u{feff}{nd}"), &a), on_a);
    assert_eq!(on_a.rebased(&a, &b).unwrap(), on_a);

    // Row 2 grows on a long beam (its force counts with L^2, the moment with L) and shrinks
    // on a short one.
    let (mut long, mut short) = (a, a);
    long.length = 0.1;
    short.length = 0.01;
    let mixed = "fx,fy,mz,x,y,theta\n0,0,1,0.09,0.02,0.3\n0,15,0.2,0.08,0.03,0.4\n";
    let on_long = truth(mixed, &long);
    assert!(parse_csv(mixed, "t.csv", &short).is_err());
    let err = on_long.rebased(&long, &short).unwrap_err();
    assert!(err.contains("shrinks at line 3"), "{err}");
}
