//! The exported MJCF in a real simulator: MuJoCo (the `mujoco` package from PyPI, installed by
//! .ci/run) loads it, applies the scene's end loads at the `tip` site, lets the model settle,
//! and the settled tip must match `prbfit eval` to 1e-3 L (and 1e-3 rad). Without the
//! package the test fails under CI and says SKIPPED loudly elsewhere.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use common::{prbfit, succeeded};

use std::process::Command;

use prbfit::scene::Scene;

#[test]
fn exported_mjcf_settles_where_prbfit_says() {
    if !common::tool_available(
        "MuJoCo (`python3 -c 'import mujoco'`)",
        common::command_works("python3", &["-c", "import mujoco"]),
        "pip install mujoco",
    ) {
        return;
    }
    let dir = std::env::temp_dir().join(format!("prbfit-mujoco-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urethane = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/urethane-joint.toml"
    );
    // Published 1R and 3R models on the built-in scene (a transverse force, a force at 135
    // degrees, force and moment together), and a model with extension springs (slide joints)
    // on the stubby urethane joint (transverse force, a pull, everything together).
    let cases: [(Option<&str>, &str, &[usize]); 4] = [
        (None, "howell-1r", &[0, 1, 3]),
        (None, "su-3r", &[0, 1, 3]),
        (None, "chen-3r", &[0, 1, 3]),
        (
            Some(urethane),
            "0.1,inf,inf; 0.5,3,2; 0.4,2.5,inf",
            &[0, 1, 4],
        ),
    ];
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mujoco_check.py");
    for (k, (scene_path, model, load_ids)) in cases.iter().enumerate() {
        let scene = match scene_path {
            Some(p) => Scene::from_file(std::path::Path::new(p)).unwrap(),
            None => Scene::builtin(),
        };
        let b = &scene.beam;
        let ei = b.youngs_modulus * b.second_moment();
        let l = b.length;
        let mut common: Vec<&str> = Vec::new();
        if let Some(p) = scene_path {
            common.extend(["--scene", p]);
        }
        let which = if model.contains(',') {
            "--prb"
        } else {
            "--model"
        };
        let xml = dir.join(format!("model{k}.xml"));
        let mut args = vec![
            "export",
            which,
            model,
            "--format",
            "mjcf",
            "-o",
            xml.to_str().unwrap(),
            "--force",
        ];
        args.extend(&common);
        let out = prbfit(&args);
        succeeded(&out);
        for &i in load_ids.iter() {
            let load = scene.loads[i].end;
            let spec = format!("{},{},{}", load.alpha_x, load.alpha_y, load.beta);
            let mut args = vec!["eval", which, model, "--load", &spec, "--json"];
            args.extend(&common);
            let out = prbfit(&args);
            succeeded(&out);
            let expected: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            let (fx, fy, mz) = (
                load.alpha_x * ei / (l * l),
                load.alpha_y * ei / (l * l),
                load.beta * ei / l,
            );
            let out = Command::new("python3")
                .args([script, xml.to_str().unwrap()])
                .args([fx, fy, mz, l].map(|v| format!("{v:e}")))
                .output()
                .unwrap();
            succeeded(&out);
            let got: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            let d =
                |k: &str, e: &str| (got[k].as_f64().unwrap() - expected[e].as_f64().unwrap()).abs();
            let (dx, dy, dphi) = (d("x", "a"), d("y", "b"), d("angle", "phi"));
            println!(
                "{model} at {spec}: MuJoCo vs prbfit tip differ by {dx:.1e}, {dy:.1e} L, {dphi:.1e} rad"
            );
            assert!(
                dx.hypot(dy) < 1e-3 && dphi < 1e-3,
                "{model} at {spec}: {got} vs {expected}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
