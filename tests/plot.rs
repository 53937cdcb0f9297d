//! `prbfit plot` through the binary: every chart kind as SVG (parsed: the beam's and each
//! model's lines, legend texts, finite coordinates inside the canvas) and as PNG (signature,
//! size, decoded pixels in the palette's colours), the order of the models, and bad input
//! (exit 2, one line naming the flag or file, nothing written).
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::{assert_input_error, json, prbfit, succeeded, Scratch};

use std::collections::{HashMap, HashSet};

use prbfit::plot::{canvas_size, ChartKind, BEAM_RGB, MODEL_RGB, TARGET_RGB};
use prbfit::scene::Scene;

const KINDS: [(&str, ChartKind); 3] = [
    ("shapes", ChartKind::Shapes),
    ("errors", ChartKind::Errors),
    ("all", ChartKind::All),
];

fn hex((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02X}{g:02X}{b:02X}")
}

/// Load paths of the built-in scene and cases on its first path (the normal fidelity samples
/// the scene's own steps).
fn builtin_counts() -> (usize, usize) {
    let scene = Scene::builtin();
    (scene.loads.len(), scene.loads[0].steps as usize)
}

/// Runs `plot` on the built-in scene with Su's 3R as the model and Howell's 1R compared.
fn plot_two_models(dir: &Scratch, file: &str, kind: &str) -> (String, serde_json::Value) {
    let out_path = dir.file(file);
    let out = prbfit(&[
        "plot",
        "--model",
        "su-3r",
        "--model",
        "howell-1r",
        "--kind",
        kind,
        "-o",
        &out_path,
        "--json",
    ]);
    let report = json(&out);
    (out_path, report)
}

/// Every number in an SVG attribute that holds coordinates.
fn coordinates(node: &roxmltree::Node) -> Vec<f64> {
    let mut v = Vec::new();
    for attr in [
        "x", "y", "x1", "y1", "x2", "y2", "cx", "cy", "width", "height",
    ] {
        if let Some(t) = node.attribute(attr) {
            v.push(t.parse::<f64>().unwrap_or(f64::NAN));
        }
    }
    if let Some(points) = node.attribute("points") {
        for pair in points.split_whitespace() {
            for n in pair.split(',') {
                v.push(n.parse::<f64>().unwrap_or(f64::NAN));
            }
        }
    }
    v
}

#[test]
fn svg_has_the_beam_each_model_and_their_legend() {
    let dir = Scratch::new("plot-svg");
    let (paths, steps) = builtin_counts();
    for (kind_name, kind) in KINDS {
        let (file, report) = plot_two_models(&dir, &format!("{kind_name}.svg"), kind_name);
        assert_eq!(report["format"], "svg");
        assert_eq!(report["kind"], kind_name);
        assert_eq!(report["models"][0]["name"], "su-3r");
        assert_eq!(report["models"][1]["name"], "howell-1r");
        assert_eq!(report["unfollowed"].as_array().unwrap().len(), 0);
        let text = std::fs::read_to_string(&file).unwrap();
        assert_eq!(report["bytes"].as_u64().unwrap() as usize, text.len());
        let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
        let root = doc.root_element();
        let (w, h) = canvas_size(kind);
        assert_eq!(root.attribute("width"), Some(w.to_string().as_str()));
        assert_eq!(root.attribute("height"), Some(h.to_string().as_str()));

        // Polylines by colour: each line drawn plus one legend sample per series.
        let mut polylines: HashMap<String, usize> = HashMap::new();
        for n in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
            *polylines
                .entry(n.attribute("stroke").unwrap_or("").to_string())
                .or_default() += 1;
        }
        let count = |rgb| polylines.get(&hex(rgb)).copied().unwrap_or(0);
        let shapes = kind.has_shapes();
        let errors = kind.has_errors();
        // Shapes: one centre line / linkage per case of path 1. Errors: one curve per path
        // in each of the two panels; the legend sits in the position panel.
        let per_model = usize::from(shapes) * (steps + 1) + usize::from(errors) * (2 * paths + 1);
        assert_eq!(count(MODEL_RGB[0]), per_model, "su-3r lines in {kind_name}");
        assert_eq!(
            count(MODEL_RGB[1]),
            per_model,
            "howell-1r lines in {kind_name}"
        );
        assert_eq!(count(MODEL_RGB[2]), 0, "no third model in {kind_name}");
        assert_eq!(
            count(BEAM_RGB),
            if shapes { steps + 1 } else { 0 },
            "beam lines in {kind_name}"
        );
        assert_eq!(count(TARGET_RGB) > 0, errors, "target lines in {kind_name}");

        if shapes {
            // Joint dots: Su's 3R has three revolute joints, Howell's 1R one; one more dot
            // each in the legend.
            let dots = |rgb| {
                doc.descendants()
                    .filter(|n| n.has_tag_name("circle") && n.attribute("fill") == Some(&hex(rgb)))
                    .count()
            };
            // Path 1's error markers are dots too (every fourth path's, in both panels).
            let path_markers = if errors {
                2 * paths.div_ceil(4) * steps
            } else {
                0
            };
            assert_eq!(dots(MODEL_RGB[0]), 3 * steps + 1 + path_markers);
            assert_eq!(dots(MODEL_RGB[1]), steps + 1 + path_markers);
        }

        let texts: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .map(|n| n.text().unwrap_or("").trim().to_string())
            .collect();
        for needle in ["su-3r", "howell-1r"] {
            let legends = texts.iter().filter(|t| *t == needle).count();
            let panels = usize::from(shapes) + usize::from(errors);
            assert_eq!(
                legends, panels,
                "legend `{needle}` in {kind_name}: {texts:?}"
            );
        }
        assert_eq!(texts.iter().any(|t| t == "beam"), shapes);
        assert_eq!(texts.iter().any(|t| t == "target"), errors);
        assert!(texts
            .iter()
            .any(|t| t == "spring-steel flexure, mixed loads"));

        for n in doc.descendants().filter(|n| n.is_element()) {
            for v in coordinates(&n) {
                assert!(v.is_finite(), "non-finite coordinate in {kind_name}: {n:?}");
                assert!(
                    v >= -1.0 && v <= f64::from(w.max(h)) + 1.0,
                    "coordinate {v} off the canvas in {kind_name}: {n:?}"
                );
            }
        }
    }
}

/// The PNG's width and height from its IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR", "IHDR first");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn png_is_a_picture_of_the_right_size_in_the_palette() {
    let dir = Scratch::new("plot-png");
    for (kind_name, kind) in KINDS {
        let (file, report) = plot_two_models(&dir, &format!("{kind_name}.png"), kind_name);
        assert_eq!(report["format"], "png");
        let bytes = std::fs::read(&file).unwrap();
        assert_eq!(report["bytes"].as_u64().unwrap() as usize, bytes.len());
        let (w, h) = png_size(&bytes);
        assert_eq!((w, h), canvas_size(kind));
        assert_eq!(
            (report["width"].as_u64(), report["height"].as_u64()),
            (Some(u64::from(w)), Some(u64::from(h)))
        );

        let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
        let mut reader = decoder.read_info().expect("a PNG header");
        let mut pixels = vec![0; reader.output_buffer_size().expect("a buffer size")];
        let info = reader.next_frame(&mut pixels).expect("decodable pixels");
        assert_eq!((info.width, info.height), (w, h));
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let colours: HashSet<(u8, u8, u8)> = pixels[..info.buffer_size()]
            .chunks_exact(3)
            .map(|p| (p[0], p[1], p[2]))
            .collect();
        // Anti-aliased text alone gives dozens of shades; a blank image has one.
        assert!(colours.len() > 20, "{kind_name}: {} colours", colours.len());
        assert!(
            colours.contains(&(255, 255, 255)),
            "{kind_name}: white ground"
        );
        // Lines are drawn in their exact colour. (Absence proves nothing: the anti-aliased
        // edges of black text pass through every grey, the beam's included.)
        for (what, rgb, drawn) in [
            ("su-3r", MODEL_RGB[0], true),
            ("howell-1r", MODEL_RGB[1], true),
            ("beam", BEAM_RGB, kind.has_shapes()),
            ("target", TARGET_RGB, kind.has_errors()),
        ] {
            assert!(
                !drawn || colours.contains(&rgb),
                "{kind_name}: no {what} colour"
            );
        }
    }
}

#[test]
fn models_keep_the_command_line_order_and_the_scene_model_is_the_default() {
    let dir = Scratch::new("plot-order");
    let out = prbfit(&[
        "plot",
        "--prb",
        "0.2,inf,inf; 0.8,2.5,inf",
        "--model",
        "su-3r",
        "--prb",
        "0.2,inf,inf; 0.8,2.5,inf",
        "--prb",
        "0.2,inf,inf; 0.8,2.5,inf",
        "--kind",
        "shapes",
        "-o",
        &dir.file("order.svg"),
        "--json",
    ]);
    let report = json(&out);
    let names: Vec<&str> = report["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    // The third of a name is its #3 (it was a second #2).
    assert_eq!(names, ["l-r", "su-3r", "l-r #2", "l-r #3"]);

    let default = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/default.toml"),
    )
    .unwrap();
    let scene = dir.write(
        "with-model.toml",
        &format!("{default}\n[prb]\nmatrix = \"0.15,inf,inf; 0.85,2.2525,inf\"\n"),
    );
    let out = prbfit(&[
        "plot",
        "--scene",
        &scene,
        "--kind",
        "errors",
        "-o",
        &dir.file("scene.png"),
    ]);
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("wrote ") && text.contains("scene"),
        "{text}"
    );
}

#[test]
fn a_model_that_stops_on_a_path_is_drawn_as_far_as_it_got_and_reported() {
    // A long rigid root and a very soft joint: no equilibrium under the force-and-moment
    // path 4 of the built-in scene, from its first case on.
    let dir = Scratch::new("plot-stop");
    let file = dir.file("stop.svg");
    let (paths, steps) = builtin_counts();
    let out = prbfit(&[
        "plot",
        "--model",
        "su-3r",
        "--prb",
        "0.9,inf,inf; 0.1,0.01,inf",
        "--path",
        "4",
        "-o",
        &file,
        "--json",
    ]);
    let report = json(&out);
    let unfollowed = report["unfollowed"].as_array().unwrap();
    assert_eq!(unfollowed.len(), 1, "{report}");
    assert_eq!(unfollowed[0]["model"], "l-r");
    assert_eq!(unfollowed[0]["path"], 4);
    assert_eq!(unfollowed[0]["reached"], 0);
    assert_eq!(unfollowed[0]["steps"].as_u64(), Some(steps as u64));
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let lines = |rgb| {
        doc.descendants()
            .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke") == Some(&hex(rgb)))
            .count()
    };
    // No linkage on path 4, but the legend still names it; the error curves stay (path 4's
    // is the zero-load point alone).
    assert_eq!(lines(MODEL_RGB[1]), 1 + 2 * paths + 1);
    assert_eq!(lines(MODEL_RGB[0]), steps + 1 + 2 * paths + 1);
    let texts = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.text().map(str::trim) == Some("l-r"))
        .count();
    assert_eq!(texts, 2);

    // The text form says so too.
    let out = prbfit(&[
        "plot",
        "--prb",
        "0.9,inf,inf; 0.1,0.01,inf",
        "--kind",
        "errors",
        "-o",
        &dir.file("stop.png"),
    ]);
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("note: l-r reaches only 0 of the"), "{text}");
}

#[test]
fn bad_input_exits_2_naming_what_is_wrong_and_writes_nothing() {
    let dir = Scratch::new("plot-bad");
    let pdf = dir.file("fig.pdf");
    assert_input_error(
        &prbfit(&["plot", "--model", "su-3r", "-o", &pdf]),
        &["fig.pdf", ".svg", ".png"],
    );
    assert!(!std::path::Path::new(&pdf).exists());

    let kept = dir.write("kept.svg", "not a figure");
    assert_input_error(
        &prbfit(&["plot", "--model", "su-3r", "-o", &kept]),
        &["kept.svg", "--force"],
    );
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), "not a figure");
    let out = prbfit(&[
        "plot", "--model", "su-3r", "--kind", "shapes", "-o", &kept, "--force",
    ]);
    succeeded(&out);
    assert!(std::fs::read_to_string(&kept).unwrap().starts_with("<svg"));

    let fresh = dir.file("fresh.svg");
    let cases: [(&[&str], &[&str]); 6] = [
        (&["--model", "no-such-model"], &["no-such-model"]),
        (&["--prb", "0.5,inf"], &["--prb"]),
        (&[], &["--model", "--prb", "[prb]"]),
        (&["--model", "su-3r", "--path", "0"], &["--path 0"]),
        (
            &["--model", "su-3r", "--path", "9"],
            &["--path 9", "4 load path"],
        ),
        (&["--model", "su-3r", "--kind", "bars"], &["--kind", "bars"]),
    ];
    for (flags, needles) in cases {
        let mut args = vec!["plot"];
        args.extend_from_slice(flags);
        args.extend_from_slice(&["-o", &fresh]);
        assert_input_error(&prbfit(&args), needles);
        assert!(
            !std::path::Path::new(&fresh).exists(),
            "{flags:?} wrote a file"
        );
    }

    let many: Vec<&str> = std::iter::repeat_n(["--model", "su-3r"], MODEL_RGB.len() + 1)
        .flatten()
        .collect();
    let mut args = vec!["plot"];
    args.extend_from_slice(&many);
    args.extend_from_slice(&["-o", &fresh]);
    assert_input_error(&prbfit(&args), &["at most"]);
}

// ---- Mechanism scenes (DESIGN §8): the force–stroke chart ----

use prbfit::beam::Resolution;
use prbfit::io::ModelFile;
use prbfit::mech::{exact, prb as prb_mech};
use prbfit::plot::{mech, Output, PlotModel};

/// An example scene file's path.
fn example(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(format!("{name}.toml"))
        .display()
        .to_string()
}

/// Polylines of each stroke colour in an SVG.
fn polylines_by_colour(doc: &roxmltree::Document) -> HashMap<String, usize> {
    let mut polylines: HashMap<String, usize> = HashMap::new();
    for n in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
        *polylines
            .entry(n.attribute("stroke").unwrap_or("").to_string())
            .or_default() += 1;
    }
    polylines
}

/// Every text element's content, trimmed.
fn svg_texts(doc: &roxmltree::Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

#[test]
fn slider_crank_force_stroke_chart_as_svg_and_png() {
    let dir = Scratch::new("plot-mech");
    let scene = example("slider-crank");
    for ext in ["svg", "png"] {
        let file = dir.file(&format!("slider-crank.{ext}"));
        let report = json(&prbfit(&[
            "plot",
            "--scene",
            &scene,
            "--model",
            "su-3r",
            "--model",
            "howell-1r",
            "-o",
            &file,
            "--json",
        ]));
        assert_eq!(report["format"], ext);
        assert_eq!(report["kind"], "all");
        assert!(report.get("path").is_none(), "{report}");
        assert_eq!(
            report["unfollowed"].as_array().unwrap().len(),
            0,
            "{report}"
        );
        // The drive prescribes dx, dy, dphi: the guide's normal force Fx and the drive force
        // Fy carry reactions; the coupler is pinned at the slider, so no moment (no panel).
        let panels = report["panels"].as_array().unwrap();
        let outputs: Vec<(&str, &str)> = panels
            .iter()
            .map(|p| {
                (
                    p["coordinate"].as_str().unwrap(),
                    p["output"].as_str().unwrap(),
                )
            })
            .collect();
        assert_eq!(outputs, [("dx", "reaction"), ("dy", "reaction")]);
        assert_eq!(panels[1]["x_label"], "stroke dy (mm)");
        assert_eq!(panels[1]["y_label"], "reaction Fy (N)");
        let (w, h) = (
            report["width"].as_u64().unwrap() as u32,
            report["height"].as_u64().unwrap() as u32,
        );
        let bytes = std::fs::read(&file).unwrap();
        assert_eq!(report["bytes"].as_u64().unwrap() as usize, bytes.len());

        if ext == "png" {
            assert_eq!(png_size(&bytes), (w, h));
            let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
            let mut reader = decoder.read_info().expect("a PNG header");
            let mut pixels = vec![0; reader.output_buffer_size().expect("a buffer size")];
            let info = reader.next_frame(&mut pixels).expect("decodable pixels");
            let colours: HashSet<(u8, u8, u8)> = pixels[..info.buffer_size()]
                .chunks_exact(3)
                .map(|p| (p[0], p[1], p[2]))
                .collect();
            for rgb in [BEAM_RGB, MODEL_RGB[0], MODEL_RGB[1]] {
                assert!(colours.contains(&rgb), "no {rgb:?} in the PNG");
            }
            continue;
        }

        let text = String::from_utf8(bytes).unwrap();
        let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
        let root = doc.root_element();
        assert_eq!(root.attribute("width"), Some(w.to_string().as_str()));
        assert_eq!(root.attribute("height"), Some(h.to_string().as_str()));
        // One curve per panel for the beam and each model, plus one legend sample each.
        let lines = polylines_by_colour(&doc);
        let count = |rgb| lines.get(&hex(rgb)).copied().unwrap_or(0);
        assert_eq!(count(BEAM_RGB), panels.len() + 1, "beam lines: {lines:?}");
        assert_eq!(count(MODEL_RGB[0]), panels.len() + 1, "su-3r lines");
        assert_eq!(count(MODEL_RGB[1]), panels.len() + 1, "howell-1r lines");
        assert_eq!(count(MODEL_RGB[2]), 0);
        // The beam's dots: one per case (10 steps) in each panel.
        let dots = doc
            .descendants()
            .filter(|n| n.has_tag_name("circle") && n.attribute("fill") == Some(&hex(BEAM_RGB)))
            .count();
        assert_eq!(dots, 10 * panels.len());
        let texts = svg_texts(&doc);
        for needle in [
            "compliant slider-crank",
            "stroke dy (mm)",
            "reaction Fx (N)",
            "reaction Fy (N)",
        ] {
            assert!(
                texts.iter().any(|t| t == needle),
                "no `{needle}`: {texts:?}"
            );
        }
        for legend in ["beam (exact)", "su-3r", "howell-1r"] {
            assert_eq!(
                texts.iter().filter(|t| *t == legend).count(),
                1,
                "legend `{legend}`: {texts:?}"
            );
        }
        for n in doc.descendants().filter(|n| n.is_element()) {
            for v in coordinates(&n) {
                assert!(v.is_finite(), "non-finite coordinate: {n:?}");
            }
        }
    }
}

#[test]
fn the_force_stroke_data_are_the_solvers_reactions_in_si_against_the_prescribed_stroke() {
    let scene = Scene::from_file(std::path::Path::new(&example("slider-crank"))).unwrap();
    let mechanism = scene.mechanism.clone().unwrap();
    let su = ModelFile::load("su-3r").unwrap();
    let models = [PlotModel {
        name: su.name.clone(),
        matrix: su.prb.clone(),
    }];
    let resolution = Resolution::with_tol(1e-8);
    let figure = mech::figure(&scene, &mechanism, &models, resolution, ChartKind::Force).unwrap();
    assert!(figure.unfollowed.is_empty());
    assert!(figure.shapes.is_none() && figure.errors.is_none());
    let chart = figure.force_stroke.as_ref().unwrap();
    assert_eq!(chart.legend, ["su-3r"]);

    // Computed independently: the solvers, flexure 1's E I0 and L, the scene's stroke.
    let beam = exact::solve(&mechanism, resolution).unwrap();
    let model = prb_mech::solve(&mechanism, &su.prb, resolution.tol).unwrap();
    let (length, ei) = mechanism.scale();
    let newtons = ei / (length * length);
    let stroke_mm = 15.0; // the scene's dy = 0.015 m
    let steps = mechanism.drives[0].steps as usize;
    assert_eq!(chart.panels.len(), 2);
    for (panel, c) in chart.panels.iter().zip([0, 1]) {
        assert_eq!(
            (panel.drive, panel.coordinate, panel.output),
            (1, c, Output::Reaction)
        );
        assert_eq!(panel.beam.len(), steps + 1);
        assert_eq!(panel.beam[0], [0.0, 0.0], "from rest");
        for (k, (point, case)) in panel.beam[1..].iter().zip(&beam[0]).enumerate() {
            let stroke = stroke_mm * (k + 1) as f64 / steps as f64;
            assert!(
                (point[0] - stroke).abs() < 1e-12,
                "stroke {point:?} vs {stroke}"
            );
            // ... and the stroke is where the solver put the slider.
            assert!((case.stage[1] * length * 1e3 - stroke).abs() < 1e-6);
            let reaction = case.stage_load[c] * newtons;
            assert!(
                (point[1] - reaction).abs() <= 1e-12 * reaction.abs().max(1.0),
                "reaction {point:?} vs {reaction}"
            );
        }
        let curve = &panel.models[0];
        assert_eq!(curve.len(), steps + 1);
        for (point, case) in curve[1..].iter().zip(&model[0]) {
            let reaction = case.stage_load[c] * newtons;
            assert!((point[1] - reaction).abs() <= 1e-12 * reaction.abs().max(1.0));
        }
    }
    // The drive force grows with the stroke, the guide's force is the other way.
    let fy = &chart.panels[1].beam;
    assert!(
        fy[steps][1] > 1.0 && fy.windows(2).all(|w| w[1][1] > w[0][1]),
        "{fy:?}"
    );
    assert!(chart.panels[0].beam[steps][1] < 0.0);

    // A cantilever kind is not a mechanism's.
    assert!(mech::figure(&scene, &mechanism, &models, resolution, ChartKind::Shapes).is_err());
}

#[test]
fn a_parallel_stage_all_loaded_gets_its_motion_against_the_load() {
    let dir = Scratch::new("plot-parallel");
    let scene = example("parallel-stage");
    let file = dir.file("parallel.svg");
    let report = json(&prbfit(&[
        "plot", "--scene", &scene, "--model", "su-3r", "-o", &file, "--json",
    ]));
    let panels = report["panels"].as_array().unwrap();
    assert!(!panels.is_empty());
    assert!(panels.iter().all(|p| p["output"] == "motion"), "{report}");
    // Both drives, each with its sideways motion against the sideways load.
    for drive in [1, 2] {
        assert!(
            panels.iter().any(|p| p["drive"] == drive
                && p["coordinate"] == "dy"
                && p["x_label"] == "load Fy (N)"
                && p["y_label"] == "stage dy (mm)"),
            "drive {drive}: {report}"
        );
    }
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let lines = polylines_by_colour(&doc);
    assert_eq!(lines.get(&hex(BEAM_RGB)).copied(), Some(panels.len() + 1));
    assert_eq!(
        lines.get(&hex(MODEL_RGB[0])).copied(),
        Some(panels.len() + 1)
    );
    assert!(svg_texts(&doc)
        .iter()
        .any(|t| t == "parallel-guiding stage"));

    // Small-motion check of the data (DESIGN §8: uy / L = Ay / 24), first case of drive 1.
    let s = Scene::from_file(std::path::Path::new(&scene)).unwrap();
    let m = s.mechanism.clone().unwrap();
    let f = mech::figure(&s, &m, &[], Resolution::with_tol(1e-8), ChartKind::Motion).unwrap();
    let chart = f.force_stroke.unwrap();
    let dy = chart
        .panels
        .iter()
        .find(|p| p.drive == 1 && p.coordinate == 1)
        .unwrap();
    let (length, ei) = m.scale();
    let [fy, uy_mm] = dy.beam[1];
    let linear_mm = fy * length * length / ei / 24.0 * length * 1e3;
    assert!(
        (uy_mm / linear_mm - 1.0).abs() < 0.02,
        "{uy_mm} vs {linear_mm}"
    );

    // Nothing is prescribed: no reaction to draw.
    assert_input_error(
        &prbfit(&[
            "plot",
            "--scene",
            &scene,
            "--model",
            "su-3r",
            "--kind",
            "force",
            "-o",
            &dir.file("force.svg"),
        ]),
        &["--kind force", "motion"],
    );
    assert!(!std::path::Path::new(&dir.file("force.svg")).exists());
}

#[test]
fn howell_1r_on_a_fixed_guided_flexure_is_listed_as_unfollowed_not_a_crash() {
    let dir = Scratch::new("plot-immobile");
    let scene = example("fixed-guided");
    let file = dir.file("fixed-guided.svg");
    let report = json(&prbfit(&[
        "plot",
        "--scene",
        &scene,
        "--model",
        "su-3r",
        "--model",
        "howell-1r",
        "-o",
        &file,
        "--json",
    ]));
    let unfollowed = report["unfollowed"].as_array().unwrap();
    assert_eq!(unfollowed.len(), 1, "{report}");
    assert_eq!(unfollowed[0]["model"], "howell-1r");
    assert_eq!(unfollowed[0]["path"], 1);
    assert_eq!(unfollowed[0]["reached"], 0);
    assert_eq!(unfollowed[0]["steps"], 6);
    assert!(unfollowed[0]["reason"]
        .as_str()
        .unwrap()
        .contains("even to first order"));
    let panels = report["panels"].as_array().unwrap().len();
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let lines = polylines_by_colour(&doc);
    // Howell's 1R: its legend sample alone; Su's 3R and the beam: every panel.
    assert_eq!(lines.get(&hex(MODEL_RGB[1])).copied(), Some(1), "{lines:?}");
    assert_eq!(lines.get(&hex(MODEL_RGB[0])).copied(), Some(panels + 1));
    assert_eq!(lines.get(&hex(BEAM_RGB)).copied(), Some(panels + 1));
    let texts = svg_texts(&doc);
    assert!(
        texts.iter().any(|t| t == "howell-1r (cannot follow)"),
        "{texts:?}"
    );

    // The text form says so, and exits 0.
    let out = prbfit(&[
        "plot",
        "--scene",
        &scene,
        "--model",
        "howell-1r",
        "-o",
        &dir.file("alone.png"),
    ]);
    succeeded(&out);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("note: howell-1r reaches only 0 of the 6 cases of drive 1 (not drawn)"),
        "{stdout}"
    );
}

#[test]
fn kinds_and_flags_that_do_not_fit_the_scene_exit_2() {
    let dir = Scratch::new("plot-mech-bad");
    let fresh = dir.file("fresh.svg");
    let crank = example("slider-crank");
    let cases: [(&[&str], &[&str]); 4] = [
        (
            &["--scene", &crank, "--kind", "shapes"],
            &["--kind shapes", "mechanism", "force"],
        ),
        (
            &["--scene", &crank, "--kind", "errors"],
            &["--kind errors", "mechanism"],
        ),
        (
            &["--scene", &crank, "--path", "2"],
            &["--path 2", "mechanism"],
        ),
        (
            &["--kind", "force"],
            &["--kind force", "cantilever", "shapes"],
        ),
    ];
    for (flags, needles) in cases {
        let mut args = vec!["plot", "--model", "su-3r"];
        args.extend_from_slice(flags);
        args.extend_from_slice(&["-o", &fresh]);
        assert_input_error(&prbfit(&args), needles);
        assert!(
            !std::path::Path::new(&fresh).exists(),
            "{flags:?} wrote a file"
        );
    }
    // --kind motion on the slider-crank: every coordinate is prescribed.
    assert_input_error(
        &prbfit(&[
            "plot", "--scene", &crank, "--model", "su-3r", "--kind", "motion", "-o", &fresh,
        ]),
        &["--kind motion", "force"],
    );
}

#[test]
fn a_model_that_stops_partway_along_a_drive_is_drawn_up_to_there() {
    // The displacement-driven cantilever pushed 35 mm (0.7 L): a chain whose only joint sits
    // at mid-length cannot reach past about half its length sideways, so it stops between
    // the 5th and the 6th of the 8 cases; Su's 3R follows to the end.
    let dir = Scratch::new("plot-partway");
    let scene = dir.write("deep.toml", &common::driven_cantilever_pushed_deep());
    let file = dir.file("deep.svg");
    let report = json(&prbfit(&[
        "plot",
        "--scene",
        &scene,
        "--model",
        "su-3r",
        "--prb",
        "0.5,inf,inf; 0.5,2.0,inf",
        "-o",
        &file,
        "--json",
    ]));
    let unfollowed = report["unfollowed"].as_array().unwrap();
    assert_eq!(unfollowed.len(), 1, "{report}");
    assert_eq!(unfollowed[0]["model"], "l-r");
    assert_eq!(unfollowed[0]["steps"], 8);
    let reached = unfollowed[0]["reached"].as_u64().unwrap() as usize;
    assert!((1..8).contains(&reached), "{report}");

    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let points = |rgb| -> Vec<usize> {
        doc.descendants()
            .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke") == Some(&hex(rgb)))
            .map(|n| n.attribute("points").unwrap().split_whitespace().count())
            .filter(|&n| n > 2) // not a legend sample
            .collect()
    };
    let panels = report["panels"].as_array().unwrap().len();
    assert_eq!(points(MODEL_RGB[1]), vec![reached + 1; panels]);
    assert_eq!(points(MODEL_RGB[0]), vec![8 + 1; panels]);
    assert!(svg_texts(&doc)
        .iter()
        .any(|t| t == "l-r (stops on drive 1)"));
}

/// Line elements drawn in `rgb` (plotters draws a cross marker as two lines).
fn lines_of(doc: &roxmltree::Document, rgb: (u8, u8, u8)) -> usize {
    doc.descendants()
        .filter(|n| n.has_tag_name("line") && n.attribute("stroke") == Some(hex(rgb).as_str()))
        .count()
}

/// A data scene (DESIGN §9) is drawn with its measured tips as crosses over the PRB linkage
/// and, in grey, the scene's nominal beam solved at each measured load; the error chart has
/// the PRB's error at each row. The wide strip's path 1 has 4 rows: 4 crosses and the
/// legend's, 4 beam lines.
#[test]
fn a_data_scene_is_drawn_with_its_measured_tips() {
    use prbfit::plot::MEASURED_RGB;
    let dir = Scratch::new("plot-data");
    let file = dir.file("strip.svg");
    let report = json(&prbfit(&[
        "plot",
        "--scene",
        &example("wide-strip-fea"),
        "--model",
        "su-3r",
        "--kind",
        "all",
        "-o",
        &file,
        "--json",
    ]));
    assert_eq!(report["path"], 1);
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let texts = svg_texts(&doc);
    assert!(texts.iter().any(|t| t == "measured tip"), "{texts:?}");
    assert!(
        texts.iter().any(|t| t == "beam (the scene's, nominal)"),
        "{texts:?}"
    );
    assert_eq!(lines_of(&doc, MEASURED_RGB), 2 * (4 + 1));
    let beam = polylines_by_colour(&doc)
        .get(&hex(BEAM_RGB))
        .copied()
        .unwrap_or(0);
    assert!(beam >= 4, "{beam} beam lines");
}

/// A mechanism data scene's force-stroke chart marks the measured reactions (crosses, no
/// curve) against the stroke: the rig slider-crank's 10 rows in each panel, and the legend's.
#[test]
fn mechanism_data_are_drawn_as_markers_on_the_force_stroke_chart() {
    use prbfit::plot::MEASURED_RGB;
    let dir = Scratch::new("plot-mech-data");
    let file = dir.file("rig.svg");
    let report = json(&prbfit(&[
        "plot",
        "--scene",
        &example("slider-crank-rig"),
        "--model",
        "su-3r",
        "-o",
        &file,
        "--json",
    ]));
    let panels = report["panels"].as_array().unwrap().len();
    assert!(panels >= 2, "{report}");
    let text = std::fs::read_to_string(&file).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert!(svg_texts(&doc).iter().any(|t| t == "measured"));
    assert!(!svg_texts(&doc).iter().any(|t| t == "beam (exact)"));
    assert_eq!(lines_of(&doc, MEASURED_RGB), 2 * (10 * panels + 1));
}

/// The built-in scene with an allowable stress of 1.3 GPa (every path reaches it).
fn builtin_with_allowable(dir: &Scratch) -> String {
    let text = std::fs::read_to_string(example("default")).unwrap();
    dir.write(
        "allowable.toml",
        &text.replacen("[beam]", "[beam]\nallowable_stress = 1.3e9", 1),
    )
}

/// `--kind stress` on a cantilever: one beam curve (grey) and one curve per model per load
/// path, plus a legend sample each; the allowable stress and the stroke limits in red with
/// their legends; as PNG, the canvas's size.
#[test]
fn stress_chart_has_the_beam_each_model_the_allowable_and_the_limits() {
    let dir = Scratch::new("plot-stress");
    let scene = builtin_with_allowable(&dir);
    let (paths, _) = builtin_counts();
    let svg = dir.file("stress.svg");
    let report = json(&prbfit(&[
        "plot",
        "--scene",
        &scene,
        "--model",
        "su-3r",
        "--model",
        "howell-1r",
        "--kind",
        "stress",
        "-o",
        &svg,
        "--json",
    ]));
    assert_eq!(report["kind"], "stress");
    assert!(report.get("path").is_none());
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let (w, h) = canvas_size(ChartKind::Stress);
    assert_eq!(
        doc.root_element().attribute("width"),
        Some(w.to_string().as_str())
    );
    assert_eq!(
        doc.root_element().attribute("height"),
        Some(h.to_string().as_str())
    );
    let lines = polylines_by_colour(&doc);
    let count = |rgb| lines.get(&hex(rgb)).copied().unwrap_or(0);
    assert_eq!(count(BEAM_RGB), paths + 1);
    assert_eq!(count(MODEL_RGB[0]), paths + 1);
    assert_eq!(count(MODEL_RGB[1]), paths + 1);
    assert_eq!(count(MODEL_RGB[2]), 0);
    assert!(count(TARGET_RGB) > 0);
    let texts = svg_texts(&doc);
    for needle in [
        "beam",
        "su-3r",
        "howell-1r",
        "allowable stress",
        "stroke limit",
    ] {
        assert!(texts.iter().any(|t| t == needle), "`{needle}`: {texts:?}");
    }
    let png = dir.file("stress.png");
    succeeded(&prbfit(&[
        "plot", "--scene", &scene, "--model", "su-3r", "--kind", "stress", "-o", &png,
    ]));
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (w, h));
    // Without an allowable: the curves, no allowable line or limits.
    let bare = dir.file("bare.svg");
    succeeded(&prbfit(&[
        "plot", "--model", "su-3r", "--kind", "stress", "-o", &bare,
    ]));
    let text = std::fs::read_to_string(&bare).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert!(!svg_texts(&doc).iter().any(|t| t == "allowable stress"));
}

/// The chart's data are the study's: the truth's curve is each case's stress in MPa, each
/// model's its judged cases' own estimate (eval's numbers), the limits the study's; on a
/// mechanism one curve per drive and flexure.
#[test]
fn the_stress_chart_data_are_the_cases_stresses() {
    use prbfit::plot::{PlotModel, StressChart};
    use prbfit::prb::published;
    use prbfit::study::{Sampling, Study};
    let dir = Scratch::new("plot-stress-data");
    let scene = Scene::from_file(std::path::Path::new(&builtin_with_allowable(&dir))).unwrap();
    let study = Study::new(&scene, Sampling::Every(Default::default())).unwrap();
    let su = published::by_name("su-3r").unwrap().prb;
    let models = [PlotModel {
        name: "su-3r".into(),
        matrix: su.clone(),
    }];
    let chart = StressChart::build(&study, &models).unwrap();
    let e = scene.beam.youngs_modulus;
    assert_eq!(chart.truth.len(), study.truth().len());
    for (curve, cases) in chart.truth.iter().zip(study.truth()) {
        assert_eq!(curve.points[0], (0.0, 0.0));
        for (p, c) in curve.points[1..].iter().zip(cases) {
            assert_eq!(
                *p,
                (c.fraction, c.flexures[0].stress.unwrap().max * e / 1e6)
            );
        }
    }
    let judged = study.judge_followed(&su).unwrap();
    let model_points: Vec<(f64, f64)> = chart.models[0]
        .1
        .iter()
        .flat_map(|c| c.points[1..].to_vec())
        .collect();
    assert_eq!(model_points.len(), judged.cases.len());
    for (p, c) in model_points.iter().zip(&judged.cases) {
        assert_eq!(p.1, c.model.flexures[0].stress.unwrap().max * e / 1e6);
    }
    let limits: Vec<Option<f64>> = study
        .stroke_limits()
        .unwrap()
        .iter()
        .map(|l| l.fraction)
        .collect();
    assert_eq!(chart.limits, limits);
    assert_eq!(chart.allowable, vec![1300.0]);

    let stage = Scene::from_file(std::path::Path::new(&example("parallel-stage"))).unwrap();
    let study = Study::new(&stage, Sampling::Every(Default::default())).unwrap();
    let chart = StressChart::build(&study, &models).unwrap();
    assert_eq!(chart.truth.len(), 2 * 2);
    assert_eq!(chart.models[0].1.len(), 2 * 2);
    assert!(chart.mechanism);
}

/// Measured data has no stress: `--kind stress` on a data scene is refused, naming why.
#[test]
fn a_stress_chart_of_measured_data_exits_2() {
    let dir = Scratch::new("plot-stress-data-scene");
    let fresh = dir.file("fresh.svg");
    assert_input_error(
        &prbfit(&[
            "plot",
            "--scene",
            &example("slider-crank-rig"),
            "--model",
            "su-3r",
            "--kind",
            "stress",
            "-o",
            &fresh,
        ]),
        &["--kind stress", "measured data has no stress"],
    );
    assert!(!std::path::Path::new(&fresh).exists());
}
