//! Every export format parses back with the SI values as computed; the own format round-trips
//! exactly; files are never overwritten without --force; a failed write leaves the old file.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{prbfit, succeeded};

use std::path::Path;

use prbfit::io::ModelFile;
use prbfit::prb::PrbMatrix;
use prbfit::scene::Scene;

type Dir = common::Scratch;

/// A model with every kind of row: rigid, R, RP, P.
const MATRIX: &str = "0.1,inf,inf; 0.35,3.5,inf; 0.4,2.9,1.7; 0.15,inf,4.2";

fn export(dir: &Dir, format: &str, name: &str) -> String {
    let path = dir.file(name);
    let out = prbfit(&["export", "--prb", MATRIX, "--format", format, "-o", &path]);
    assert!(
        out.status.success(),
        "{format}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read_to_string(&path).unwrap()
}

/// SI values of the built-in beam: (E I0 / L, E A0 / L, L).
fn units() -> (f64, f64, f64) {
    let b = Scene::builtin().beam;
    let l = b.length;
    (
        b.youngs_modulus * b.second_moment() / l,
        b.youngs_modulus * b.area() / l,
        l,
    )
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs()
}

fn num(s: &str) -> f64 {
    s.trim()
        .parse()
        .unwrap_or_else(|_| panic!("`{s}` is not a number"))
}

#[test]
fn own_format_round_trips_exactly_and_evaluates_the_same() {
    let dir = Dir::new("own");
    let m = PrbMatrix::parse(MATRIX).unwrap();
    let (ei_l, ea_l, l) = units();
    for (format, name) in [("toml", "m.toml"), ("json", "m.json")] {
        export(&dir, format, name);
        let path = dir.file(name);
        let file = ModelFile::load(&path).unwrap();
        assert_eq!(
            file.prb, m,
            "{format}: the matrix, infinity included, exactly"
        );
        assert_eq!(file.topology.as_deref(), Some("L-R-RP-P"));
        let si = file.si.as_ref().unwrap();
        assert!(close(si.segments[1].k_theta.unwrap(), 3.5 * ei_l));
        assert!(close(si.segments[2].k_ex.unwrap(), 1.7 * ea_l));
        assert!(si.segments[0].k_theta.is_none() && si.segments[3].k_theta.is_none());
        assert!(close(si.segments[2].length, 0.4 * l));
        let range = file.load_range.unwrap();
        assert_eq!(range.alpha_y, [0.0, 5.0]);
        assert!(close(range.fy[1], 5.0 * ei_l / l));
        let record = file.fit.as_ref().unwrap();
        assert_eq!(record.prbfit_version, env!("CARGO_PKG_VERSION"));
        assert_eq!(record.fidelity, "normal");
        // prbfit eval reads it back and finds the same figures.
        let out = prbfit(&["eval", "--model", &path, "--json", "--tol", "1e-8"]);
        succeeded(&out);
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["prb"].as_str().unwrap(), m.to_text());
        assert_eq!(v["objective"].as_f64().unwrap(), record.figures.objective);
        // Serialising what was read and reading it again gives the same model.
        let again = ModelFile::from_toml_str(&file.to_toml().unwrap(), "x").unwrap();
        assert_eq!(again, file);
    }
}

#[test]
fn mjcf_has_springs_sites_and_no_gravity() {
    let dir = Dir::new("mjcf");
    let text = export(&dir, "mjcf", "m.xml");
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "mujoco");
    let find = |tag: &'static str| root.descendants().filter(move |n| n.has_tag_name(tag));
    assert_eq!(
        find("compiler").next().unwrap().attribute("angle"),
        Some("radian")
    );
    assert_eq!(
        find("option").next().unwrap().attribute("gravity"),
        Some("0 0 0")
    );
    let (ei_l, ea_l, l) = units();
    let joints: Vec<_> = find("joint").collect();
    let hinges: Vec<_> = joints
        .iter()
        .filter(|j| j.attribute("type") == Some("hinge"))
        .collect();
    let slides: Vec<_> = joints
        .iter()
        .filter(|j| j.attribute("type") == Some("slide"))
        .collect();
    assert_eq!((hinges.len(), slides.len()), (2, 2));
    assert!(close(
        num(hinges[0].attribute("stiffness").unwrap()),
        3.5 * ei_l
    ));
    assert!(close(
        num(hinges[1].attribute("stiffness").unwrap()),
        2.9 * ei_l
    ));
    assert!(close(
        num(slides[0].attribute("stiffness").unwrap()),
        1.7 * ea_l
    ));
    assert!(close(
        num(slides[1].attribute("stiffness").unwrap()),
        4.2 * ea_l
    ));
    assert!(joints.iter().all(|j| j.attribute("springref") == Some("0")));
    assert_eq!(find("body").count(), 4);
    let tip = find("site")
        .find(|s| s.attribute("name") == Some("tip"))
        .expect("a tip site");
    // The bodies' offsets plus the tip site's add up to the beam's length.
    let x = |n: roxmltree::Node| num(n.attribute("pos").unwrap().split(' ').next().unwrap());
    let total: f64 = find("body").map(x).sum::<f64>() + x(tip);
    assert!(close(total, l));
}

#[test]
fn urdf_carries_springs_in_gazebo_elements() {
    let dir = Dir::new("urdf");
    let text = export(&dir, "urdf", "m.urdf");
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "robot");
    assert!(
        text.contains("URDF has no joint springs"),
        "a comment says so"
    );
    let (ei_l, ea_l, _) = units();
    let joints: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("joint"))
        .collect();
    for j in &joints {
        if matches!(j.attribute("type"), Some("revolute" | "prismatic")) {
            assert!(
                j.children().any(|c| c.has_tag_name("limit")),
                "limits on {:?}",
                j.attribute("name")
            );
        }
    }
    let stiffness = |joint: &str| -> f64 {
        let g = root
            .children()
            .find(|n| n.has_tag_name("gazebo") && n.attribute("reference") == Some(joint))
            .unwrap_or_else(|| panic!("gazebo block for {joint}"));
        let reference = g
            .children()
            .find(|c| c.has_tag_name("springReference"))
            .unwrap();
        assert_eq!(reference.text(), Some("0"));
        num(g
            .children()
            .find(|c| c.has_tag_name("springStiffness"))
            .unwrap()
            .text()
            .unwrap())
    };
    assert!(close(stiffness("theta2"), 3.5 * ei_l));
    assert!(close(stiffness("theta3"), 2.9 * ei_l));
    assert!(close(stiffness("delta3"), 1.7 * ea_l));
    assert!(close(stiffness("delta4"), 4.2 * ea_l));
    // Every joint names links that exist.
    let links: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("link"))
        .map(|n| n.attribute("name").unwrap().to_string())
        .collect();
    for j in &joints {
        for end in ["parent", "child"] {
            let name = j
                .children()
                .find(|c| c.has_tag_name(end))
                .unwrap()
                .attribute("link")
                .unwrap();
            assert!(links.iter().any(|l| l == name), "{name}");
        }
    }
}

#[test]
fn sdf_joints_have_spring_dynamics() {
    let dir = Dir::new("sdf");
    let text = export(&dir, "sdf", "m.sdf");
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(
        (root.tag_name().name(), root.attribute("version")),
        ("sdf", Some("1.10"))
    );
    let (ei_l, ea_l, _) = units();
    let spring = |joint: &str| -> (f64, f64) {
        let j = root
            .descendants()
            .find(|n| n.has_tag_name("joint") && n.attribute("name") == Some(joint))
            .unwrap();
        let dynamics = j
            .descendants()
            .find(|n| n.has_tag_name("dynamics"))
            .unwrap();
        let get = |tag: &str| {
            num(dynamics
                .children()
                .find(|c| c.has_tag_name(tag))
                .unwrap()
                .text()
                .unwrap())
        };
        (get("spring_stiffness"), get("spring_reference"))
    };
    assert_eq!(spring("theta2").1, 0.0);
    assert!(close(spring("theta2").0, 3.5 * ei_l));
    assert!(close(spring("theta3").0, 2.9 * ei_l));
    assert!(close(spring("delta3").0, 1.7 * ea_l));
    assert!(close(spring("delta4").0, 4.2 * ea_l));
    assert!(root
        .descendants()
        .any(|n| n.has_tag_name("frame") && n.attribute("name") == Some("tip")));
}

#[test]
fn csv_has_both_tips_and_shapes_for_every_case() {
    let dir = Dir::new("csv");
    let text = export(&dir, "csv", "m.csv");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("case,alpha_x,alpha_y,beta,curve,index,x,y,angle")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let cases = Scene::builtin().cases().len();
    for curve in ["beam_tip", "prb_tip"] {
        assert_eq!(rows.iter().filter(|r| r[4] == curve).count(), cases);
    }
    assert_eq!(
        rows.iter().filter(|r| r[4] == "beam_shape").count(),
        cases * 41
    );
    assert_eq!(
        rows.iter().filter(|r| r[4] == "prb_linkage").count(),
        cases * 5
    );
    // The PRB tip of the last case is what prbfit eval says for that load.
    let last = rows.iter().rfind(|r| r[4] == "prb_tip").unwrap();
    let load = format!("{},{},{}", last[1], last[2], last[3]);
    let out = prbfit(&["eval", "--prb", MATRIX, "--load", &load, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((num(last[6]) - v["a"].as_f64().unwrap()).abs() < 1e-12);
    assert!((num(last[7]) - v["b"].as_f64().unwrap()).abs() < 1e-12);
}

#[test]
fn existing_files_are_kept() {
    let dir = Dir::new("keep");
    let path = dir.file("m.xml");
    std::fs::write(&path, "old").unwrap();
    let out = prbfit(&[
        "export", "--model", "su-3r", "--format", "mjcf", "-o", &path,
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--force"));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    let out = prbfit(&[
        "export", "--model", "su-3r", "--format", "mjcf", "-o", &path, "--force",
    ]);
    assert!(out.status.success());
    assert!(std::fs::read_to_string(&path)
        .unwrap()
        .starts_with("<mujoco"));
    // A write that fails (the target is a directory) leaves what was there.
    let target = dir.0.join("taken");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("inside"), "keep me").unwrap();
    let out = prbfit(&[
        "export",
        "--model",
        "su-3r",
        "--format",
        "csv",
        "-o",
        target.to_str().unwrap(),
        "--force",
    ]);
    assert_ne!(out.status.code(), Some(0));
    assert_eq!(
        std::fs::read_to_string(target.join("inside")).unwrap(),
        "keep me"
    );
    let leftovers = std::fs::read_dir(&dir.0)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".tmp")
        })
        .count();
    assert_eq!(leftovers, 0, "no temporary files left behind");
}

#[test]
fn bad_export_requests_exit_2() {
    let dir = Dir::new("bad");
    let p = dir.file("m.x");
    for (args, needle) in [
        (
            vec!["export", "--model", "su-3r", "--format", "step", "-o", &p],
            "step",
        ),
        (
            vec![
                "export",
                "--model",
                "su-3r",
                "--format",
                "mjcf",
                "-o",
                &p,
                "--density",
                "-1",
            ],
            "--density",
        ),
        (vec!["export", "--format", "mjcf", "-o", &p], "--prb"),
        (
            vec!["export", "--prb", "1,2", "--format", "mjcf", "-o", &p],
            "--prb",
        ),
    ] {
        let out = prbfit(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!Path::new(&p).exists());
    }
}

/// A mechanism scene exports as the whole PRB mechanism in MJCF (checked in MuJoCo by
/// tests/mujoco_mech.rs) and as a model file judged on the mechanism (the figures `eval`
/// gives); URDF, SDF and CSV are refused as bad input naming what works, and write nothing.
#[test]
fn a_mechanism_scene_exports_as_mjcf_and_model_files_only() {
    let dir = Dir::new("mech");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/parallel-stage.toml"
    );
    let xml = dir.file("stage.xml");
    let out = prbfit(&[
        "export", "--scene", scene, "--model", "su-3r", "-o", &xml, "--json",
    ]);
    let report = common::json(&out);
    assert_eq!(report["format"], "mjcf");
    let text = std::fs::read_to_string(&xml).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let named = |tag: &str, name: &str| {
        doc.descendants()
            .any(|n| n.has_tag_name(tag) && n.attribute("name") == Some(name))
    };
    assert!(named("site", "stage") && named("body", "stage"));
    assert!(named("weld", "f1_clamp") && named("weld", "f2_clamp"));
    assert!(named("site", "f1_tip") && named("site", "f2_tip"));
    assert!(
        text.contains("parallel-guiding stage"),
        "the header names the scene"
    );
    let eval = common::json(&prbfit(&[
        "eval", "--scene", scene, "--model", "su-3r", "--json",
    ]));
    for format in ["toml", "json"] {
        let p = dir.file(&format!("m.{format}"));
        common::succeeded(&prbfit(&[
            "export", "--scene", scene, "--model", "su-3r", "-o", &p,
        ]));
        let text = std::fs::read_to_string(&p).unwrap();
        let model: serde_json::Value = if format == "json" {
            serde_json::from_str(&text).unwrap()
        } else {
            let v: toml::Value = toml::from_str(&text).unwrap();
            serde_json::to_value(v).unwrap()
        };
        assert_eq!(model["name"], "su-3r");
        assert_eq!(model["fit"]["flexure_si"].as_array().unwrap().len(), 2);
        // Judged as eval judges (both solve the same mechanisms at the same tolerances).
        let (a, b) = (
            model["fit"]["max_pos_err"].as_f64().unwrap(),
            eval["max_pos_err"].as_f64().unwrap(),
        );
        assert!((a - b).abs() <= 1e-6 * b, "{format}: {a} vs {b}");
    }
    for format in ["urdf", "sdf", "csv"] {
        let p = dir.file(&format!("m.{format}"));
        let out = prbfit(&[
            "export", "--scene", scene, "--model", "su-3r", "--format", format, "-o", &p,
        ]);
        common::assert_input_error(&out, &["--format", "mjcf", format]);
        assert!(!Path::new(&p).exists(), "{format}: nothing written");
    }
}

/// Issue 25.5: every robot format carries the mus' masses (DESIGN §10): segment i's link is
/// `mu_i rho A0 L` with a uniform rod's inertia `m l^2 / 12` about the bending axis at its
/// middle, and the `[tip]` body joins the last link (centre of mass and inertia by the
/// parallel axis theorem); `[beam] density` is the density without `--density`.
#[test]
fn robot_formats_carry_the_mus_masses_and_the_tip_body() {
    let dir = Dir::new("masses");
    let text = prbfit::scene::DEFAULT_SCENE_TOML.replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 2700.0",
        1,
    ) + "\n[tip]\nmass = 0.002\ninertia = 3e-8\n";
    let scene_path = dir.write("scene.toml", &text);
    let b = Scene::from_toml_str(&text, "scene.toml").unwrap().beam;
    let total = 2700.0 * b.area() * b.length;
    let l = b.length;
    // Mass parked on the rigid root, the rest over three R segments.
    let matrix = "0.1,inf,inf,0.3; 0.35,3.5,inf,0.2; 0.4,2.9,inf,0.3; 0.15,2.6,inf,0.2";
    let (gammas, mus) = ([0.1, 0.35, 0.4, 0.15], [0.3, 0.2, 0.3, 0.2]);
    // (mass, com from the link's root, izz about the com) as the formats should carry them.
    let want: Vec<(f64, f64, f64)> = (0..4)
        .map(|i| {
            let (m, li) = (mus[i] * total, gammas[i] * l);
            if i < 3 {
                return (m, li / 2.0, m * li * li / 12.0);
            }
            let (mt, it) = (0.002, 3e-8);
            let com = (m * li / 2.0 + mt * li) / (m + mt);
            let izz =
                m * li * li / 12.0 + m * (li / 2.0 - com).powi(2) + it + mt * (li - com).powi(2);
            (m + mt, com, izz)
        })
        .collect();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    let export = |format: &str| {
        let path = dir.file(&format!("m.{format}"));
        succeeded(&prbfit(&[
            "export",
            "--scene",
            &scene_path,
            "--prb",
            matrix,
            "--format",
            format,
            "-o",
            &path,
        ]));
        std::fs::read_to_string(&path).unwrap()
    };
    let first = |s: &str| num(s.split(' ').next().unwrap());
    // MJCF: each segment body's `inertial`.
    let text = export("mjcf");
    let doc = roxmltree::Document::parse(&text).unwrap();
    let inertials: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("inertial"))
        .collect();
    assert_eq!(inertials.len(), 4);
    for (n, &(m, com, izz)) in inertials.iter().zip(&want) {
        assert!(close(num(n.attribute("mass").unwrap()), m), "mjcf {n:?}");
        assert!(close(first(n.attribute("pos").unwrap()), com), "mjcf {n:?}");
        let diag: Vec<f64> = n
            .attribute("diaginertia")
            .unwrap()
            .split(' ')
            .map(num)
            .collect();
        assert!(close(diag[2], izz), "mjcf {diag:?} vs {izz}");
    }
    // URDF and SDF: each `segment{n}` link's `inertial`.
    for format in ["urdf", "sdf"] {
        let text = export(format);
        let doc = roxmltree::Document::parse(&text).unwrap();
        for (i, &(m, com, izz)) in want.iter().enumerate() {
            let name = format!("segment{}", i + 1);
            let link = doc
                .descendants()
                .find(|n| n.has_tag_name("link") && n.attribute("name") == Some(name.as_str()))
                .unwrap_or_else(|| panic!("{format}: {name}"));
            let inertial = link
                .children()
                .find(|c| c.has_tag_name("inertial"))
                .unwrap();
            let child = |tag: &str| {
                inertial
                    .descendants()
                    .find(|c| c.has_tag_name(tag))
                    .unwrap_or_else(|| panic!("{format}: {tag}"))
            };
            let (mass, pos, iz) = if format == "urdf" {
                (
                    num(child("mass").attribute("value").unwrap()),
                    first(child("origin").attribute("xyz").unwrap()),
                    num(child("inertia").attribute("izz").unwrap()),
                )
            } else {
                (
                    num(child("mass").text().unwrap()),
                    first(child("pose").text().unwrap()),
                    num(child("izz").text().unwrap()),
                )
            };
            assert!(close(mass, m), "{format} {name}: {mass} vs {m}");
            assert!(close(pos, com), "{format} {name}: {pos} vs {com}");
            assert!(close(iz, izz), "{format} {name}: {iz} vs {izz}");
        }
    }
}

/// The model file of a scene with `[beam] density` and a `[tip]` body carries each segment's
/// mass `mu_i rho A0 L` and rod inertia about its centre, and the tip body, in SI; an
/// export's `--density` sets the masses; the built-in scene (no density) writes none.
#[test]
fn model_files_carry_the_masses_in_si() {
    let dir = Dir::new("si-masses");
    let scene_path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/ringing-flexure.toml"
    );
    let scene = Scene::from_file(Path::new(scene_path)).unwrap();
    let b = scene.beam;
    let rho = b.density.unwrap();
    let matrix = "0.1,inf,inf,0.2; 0.35,3.51,inf,0.3; 0.4,2.99,inf,0.3; 0.15,2.58,inf,0.2";
    let m = PrbMatrix::parse(matrix).unwrap();
    for (density, file_name) in [(None, "m.toml"), (Some(1000.0), "m1000.json")] {
        let path = dir.file(file_name);
        let mut args = vec![
            "export", "--scene", scene_path, "--prb", matrix, "-o", &path,
        ];
        let given = density.map(|d: f64| d.to_string());
        if let Some(d) = &given {
            args.extend(["--density", d]);
        }
        succeeded(&prbfit(&args));
        let file = ModelFile::load(&path).unwrap();
        let si = file.si.unwrap();
        let rho_a_l = density.unwrap_or(rho) * b.width * b.thickness * b.length;
        for (seg, row) in si.segments.iter().zip(m.rows()) {
            let mass = row.mass() * rho_a_l;
            let inertia = mass * (row.gamma * b.length).powi(2) / 12.0;
            // The same products in another order, through a decimal round trip: ulps.
            assert!(close(seg.mass.unwrap(), mass), "{seg:?} vs {mass}");
            assert!(close(seg.inertia.unwrap(), inertia), "{seg:?} vs {inertia}");
        }
        assert_eq!(si.tip, Some(scene.body));
    }
    let path = dir.file("plain.toml");
    succeeded(&prbfit(&["export", "--prb", matrix, "-o", &path]));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        !text.contains("mass") && !text.contains("inertia"),
        "{text}"
    );
    // `--density` on a scene without one (the built-in) gives the masses too.
    let path = dir.file("given.toml");
    succeeded(&prbfit(&[
        "export",
        "--prb",
        matrix,
        "--density",
        "2700",
        "-o",
        &path,
    ]));
    let builtin = Scene::builtin().beam;
    let rho_a_l = 2700.0 * builtin.width * builtin.thickness * builtin.length;
    let si = ModelFile::load(&path).unwrap().si.unwrap();
    for (seg, row) in si.segments.iter().zip(m.rows()) {
        assert!(close(seg.mass.unwrap(), row.mass() * rho_a_l), "{seg:?}");
    }
}

/// A massless tip segment (floored to 1e-6 of the mass) on an extension spring of
/// `100 E A0 / L` rings 8e5 times above the first mode, 2.5e7 steps per period at the
/// export's time step: the MJCF export says so and writes nothing; a `mu = 0` row between
/// torsion springs exports.
#[test]
fn an_mjcf_too_stiff_to_simulate_is_refused() {
    let dir = Dir::new("too-stiff");
    let path = dir.file("m.xml");
    let out = prbfit(&[
        "export",
        "--prb",
        "0.1,inf,inf,0.1; 0.6,2,inf,0.9; 0.3,2,100,0",
        "--format",
        "mjcf",
        "-o",
        &path,
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("raise the smallest mus"), "{err}");
    assert!(!Path::new(&path).exists());
    let out = prbfit(&[
        "export",
        "--prb",
        "0.1,inf,inf,0.1; 0.35,3.51,inf,0; 0.4,2.99,inf,0.4; 0.15,2.58,inf,0.5",
        "--format",
        "mjcf",
        "-o",
        &path,
    ]);
    succeeded(&out);
}
