//! The whole PRB mechanism exported as MJCF (issue 13, item 4) in a real simulator: MuJoCo
//! (the `mujoco` package from PyPI, installed by .ci/run) loads `prbfit export --scene MECH
//! --format mjcf`, `tests/mujoco_mech_check.py` follows a drive path of the scene (prescribed
//! coordinates through the file's `drive_*` joint equalities, loads as generalized forces on
//! the stage joints, both ramped from case to case so the same branch is followed), damps it
//! to rest at the first, a middle and the last case, and reads the stage pose and the drive's
//! reactions (the drive equalities' constraint forces). They must match `prbfit eval --json`
//! of the same scene and model, case by case: the stage pose to 1e-6 L (1e-6 rad for dphi),
//! each reaction to 1e-4 of that coordinate's reaction scale (eval's `reaction_scale`: its
//! largest reaction over the scene, floored as the force error's). Without the package the
//! test fails under CI and says SKIPPED loudly elsewhere.
//!
//! Scenes: the slider-crank (everything prescribed, the coupler's loop closed by a `connect`;
//! Su's and Chen's 3R and Howell's 1R), the parallel-guiding stage (two welded flexures, the
//! stage loaded; both drive paths) and the fixed-guided segment (a weld, `dy` and `dphi`
//! prescribed, `dx` loaded with zero), and a scene of three flexures of different sizes,
//! turned, clamped, pinned and coupled ([`mixed`], on `common::MIXED_FLEXURES`). Howell's
//! 1R cannot keep its tip angle, so it is only on the slider-crank.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{json, prbfit, succeeded, Scratch};

use std::path::Path;
use std::process::Command;

use prbfit::scene::{Coordinate, Scene};
use prbfit::si::MechUnits;

/// The tolerances.
const POSE_TOL: f64 = 1e-6;
const REACTION_TOL: f64 = 1e-4;

fn mujoco_available() -> bool {
    common::tool_available(
        "MuJoCo (`python3 -c 'import mujoco'`)",
        common::command_works("python3", &["-c", "import mujoco"]),
        "pip install mujoco",
    )
}

/// Three flexures of their own sizes and stiffnesses, turned, clamped, pinned and coupled:
/// the per-flexure scaling, the clamps' rotation and every kind of closure at once. Drive 1
/// loads the stage (it turns by half a degree), drive 2 prescribes `dy` against a pull.
fn mixed() -> String {
    let drives = "[[drives]]\nfy = 4.0\nmz = 0.02\nsteps = 4\n\
                  [[drives]]\nfx = 1.0\ndy = 0.003\nsteps = 4\n";
    format!("{}{drives}", common::MIXED_FLEXURES)
}

/// Exports the shipped scene `scene_name` with each of `models`, drives every drive path in
/// MuJoCo and compares with `prbfit eval`, printing one line of agreement per case.
fn check_scene(scene_name: &str, models: &[&str]) {
    let scene_path = format!(
        "{}/assets/scenes/{scene_name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    check(scene_name, &scene_path, models);
}

/// [`check_scene`] of the scene file at `scene_path`, called `scene_name` in messages.
fn check(scene_name: &str, scene_path: &str, models: &[&str]) {
    if !mujoco_available() {
        return;
    }
    let dir = Scratch::new(&format!("mujoco-mech-{scene_name}"));
    let scene = Scene::from_file(Path::new(scene_path)).unwrap();
    let mechanism = scene.mechanism.as_ref().expect("a mechanism scene");
    let units = MechUnits::new(mechanism);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mujoco_mech_check.py");
    for model in models {
        let xml = dir.file(&format!("{model}.xml"));
        succeeded(&prbfit(&[
            "export", "--scene", scene_path, "--model", model, "--format", "mjcf", "-o", &xml,
        ]));
        let expected = json(&prbfit(&[
            "eval", "--scene", scene_path, "--model", model, "--json",
        ]));
        let scale = &expected["reaction_scale"];
        let rows = expected["cases"].as_array().unwrap();
        for (d, drive) in mechanism.drives.iter().enumerate() {
            let steps = drive.steps;
            let mut ks = vec![1, steps.div_ceil(2), steps];
            ks.dedup();
            let fractions: Vec<f64> = ks
                .iter()
                .map(|&k| f64::from(k) / f64::from(steps))
                .collect();
            let coordinates: Vec<(&str, f64)> = drive
                .coordinates
                .iter()
                .map(|c| match c {
                    Coordinate::Prescribed(v) => ("prescribed", *v),
                    Coordinate::Loaded(v) => ("loaded", *v),
                })
                .collect();
            let spec = serde_json::json!({
                "length": units.length,
                "force": units.force,
                "moment": units.moment,
                "drive": coordinates,
                "fractions": fractions,
            });
            let spec_path = dir.write(&format!("{model}-{d}.json"), &spec.to_string());
            let out = Command::new("python3")
                .args([script, &xml, &spec_path])
                .output()
                .unwrap();
            succeeded(&out);
            let got: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            for (case, &k) in got["cases"].as_array().unwrap().iter().zip(&ks) {
                let fraction = case["fraction"].as_f64().unwrap();
                let reference = rows
                    .iter()
                    .find(|r| {
                        r["drive"].as_u64() == Some(d as u64 + 1)
                            && (r["fraction"].as_f64().unwrap() - fraction).abs() < 1e-12
                    })
                    .unwrap_or_else(|| panic!("eval has no case at {fraction} of drive {d}"));
                let at = |v: &serde_json::Value, c: usize| v[c].as_f64().unwrap();
                assert_eq!(
                    case["unstable"], 0,
                    "{scene_name} {model}: MuJoCo went unstable"
                );
                assert_eq!(case["settled"], true, "{scene_name} {model}: never settled");
                let pose_err = (0..3).fold(0.0_f64, |m, c| {
                    m.max((at(&case["stage"], c) - at(&reference["stage"], c)).abs())
                });
                let mut reaction_err = None::<f64>;
                for (c, coordinate) in drive.coordinates.iter().enumerate() {
                    if coordinate.is_prescribed() {
                        let e = (at(&case["stage_load"], c) - at(&reference["stage_load"], c))
                            .abs()
                            / at(scale, c);
                        reaction_err = Some(reaction_err.map_or(e, |m| m.max(e)));
                    }
                }
                println!(
                    "{scene_name} | {model} | drive {} case {k}/{steps} | pose {pose_err:.1e} L | \
                     reaction {} | closure residual {:.1e} L, {:.1e} rad | {} steps",
                    d + 1,
                    reaction_err.map_or("-".to_string(), |e| format!("{e:.1e}")),
                    at(&case["violation"], 0),
                    at(&case["violation"], 1),
                    case["steps"]
                );
                assert!(
                    pose_err <= POSE_TOL,
                    "{scene_name} {model} drive {} case {k}: stage {} vs prbfit {}",
                    d + 1,
                    case["stage"],
                    reference["stage"]
                );
                assert!(
                    reaction_err.is_none_or(|e| e <= REACTION_TOL),
                    "{scene_name} {model} drive {} case {k}: reaction {} vs prbfit {} (scale {})",
                    d + 1,
                    case["stage_load"],
                    reference["stage_load"],
                    scale
                );
            }
        }
    }
}

#[test]
fn slider_crank_in_mujoco_needs_the_force_prbfit_says() {
    check_scene("slider-crank", &["su-3r", "chen-3r", "howell-1r"]);
}

#[test]
fn parallel_stage_in_mujoco_goes_where_prbfit_says() {
    check_scene("parallel-stage", &["su-3r", "chen-3r"]);
}

#[test]
fn fixed_guided_in_mujoco_goes_and_pushes_as_prbfit_says() {
    check_scene("fixed-guided", &["su-3r", "chen-3r"]);
}

#[test]
fn mixed_attachments_in_mujoco_go_and_push_as_prbfit_says() {
    let dir = Scratch::new("mujoco-mech-mixed-scene");
    let path = dir.write("mixed.toml", &mixed());
    check("mixed", &path, &["su-3r"]);
}
