//! Free vibration of the exported MJCF in MuJoCo (DESIGN §10): a small tip (or stage)
//! displacement released with no gravity and no damping rings at prbfit's PRB first
//! frequency to 0.5 % — for a cantilever 3R with a tip body and for the parallel stage with a
//! stage mass. The exports carry the mus' masses and inertias, the scene's `[beam] density`
//! and the body; their time step is `0.2 / omega_max` (a mechanism's `0.01 / omega_max`),
//! `omega_max` the exported chain's highest natural frequency (`export::chain::time_step`),
//! inside MuJoCo's explicit bound `omega dt < 2`. A light link between two springs (mus of
//! 1e-6, where a rule from each spring alone left MuJoCo unstable) runs stably and rings at
//! prbfit's frequency too. Without the
//! `mujoco` package the test says SKIPPED (and fails under CI, as tests/mujoco.rs).
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::f64::consts::PI;
use std::process::Command;

use common::{prbfit, succeeded, Scratch};

use prbfit::beam::Load;
use prbfit::mech::prb_modes::{prb_modes, unloaded_state};
use prbfit::prb::{PrbMatrix, PrbSolver, TipBody};
use prbfit::scene::Scene;

/// The simulated frequency (Hz) of `model`'s export on the scene `scene` (file), pushed at
/// `site` by `fy` N, searched near `guess`.
fn simulated(dir: &Scratch, scene: &str, model: &str, site: &str, fy: f64, guess: f64) -> f64 {
    let out_file = dir.file(&format!("{site}.xml"));
    let which = if model.contains(',') {
        "--prb"
    } else {
        "--model"
    };
    let out = prbfit(&[
        "export", "--scene", scene, which, model, "--format", "mjcf", "-o", &out_file,
    ]);
    succeeded(&out);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mujoco_modes_check.py");
    let run = Command::new("python3")
        .args([script, &out_file, site, &fy.to_string(), &guess.to_string()])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    v["hz"].as_f64().unwrap()
}

#[test]
fn exported_mjcf_rings_at_prbfits_frequency() {
    if !common::tool_available(
        "MuJoCo (`python3 -c 'import mujoco'`)",
        common::command_works("python3", &["-c", "import mujoco"]),
        "pip install mujoco",
    ) {
        return;
    }
    let dir = Scratch::new("mujoco-modes");
    // The built-in scene's steel flexure with its density and a tip body of a quarter of
    // the beam's mass.
    let text = prbfit::scene::DEFAULT_SCENE_TOML.replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    ) + "\n[tip]\nmass = 0.0005\ninertia = 1e-9\n";
    let path = dir.write("cantilever.toml", &text);
    let scene = Scene::from_toml_str(&text, "cantilever.toml").unwrap();
    let b = &scene.beam;
    let rho_a = 7850.0 * b.area();
    let omega_unit = (b.youngs_modulus * b.second_moment() / (rho_a * b.length.powi(4))).sqrt();
    let su = "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf";
    let m = PrbMatrix::parse(su).unwrap();
    let tip = TipBody {
        mass: 0.0005 / (rho_a * b.length),
        inertia: 1e-9 / (rho_a * b.length.powi(3)),
    };
    let chain = PrbSolver::new(&m, b.model().axial_compliance());
    let omega = chain
        .modes(Load::new(0.0, 0.0, 0.0), &[0.0; 3], tip)
        .unwrap()[0];
    let hz = omega * omega_unit / (2.0 * PI);
    // A push of 1e-3 of the force of alpha = 1: a deflection of about 3e-4 L, linear.
    let fy = 1e-3 * b.youngs_modulus * b.second_moment() / b.length.powi(2);
    let sim = simulated(&dir, &path, su, "tip", fy, hz);
    eprintln!("cantilever su-3r: prbfit {hz:.6} Hz, MuJoCo {sim:.6} Hz");
    assert!(
        (sim / hz - 1.0).abs() < 5e-3,
        "MuJoCo {sim} Hz vs prbfit {hz} Hz"
    );

    // The parallel stage with a stage of twice a flexure's mass.
    let stage_text = common::dense_parallel_stage(0.0039, 1e-6);
    let stage_path = dir.write("stage.toml", &stage_text);
    let scene = Scene::from_toml_str(&stage_text, "stage.toml").unwrap();
    let mech = scene.mechanism.clone().unwrap();
    let b = &mech.flexures[0].beam;
    let rho_a = 7850.0 * b.area();
    let omega_unit = (b.youngs_modulus * b.second_moment() / (rho_a * b.length.powi(4))).sqrt();
    let body = TipBody {
        mass: 0.0039 / (rho_a * b.length),
        inertia: 1e-6 / (rho_a * b.length.powi(3)),
    };
    let state = unloaded_state(&mech, &m);
    let omega = prb_modes(&mech, &m, &state, body).unwrap()[0];
    let hz = omega * omega_unit / (2.0 * PI);
    let fy = 1e-3 * b.youngs_modulus * b.second_moment() / b.length.powi(2);
    let sim = simulated(&dir, &stage_path, su, "stage", fy, hz);
    eprintln!("parallel stage su-3r: prbfit {hz:.6} Hz, MuJoCo {sim:.6} Hz");
    assert!(
        (sim / hz - 1.0).abs() < 5e-3,
        "MuJoCo {sim} Hz vs prbfit {hz} Hz"
    );
}

/// The audit's light link: two middle segments of `mu = 1e-6` between springs, the steel
/// cantilever without a tip body. The file's time step follows the chain's highest
/// frequency (about 1e4 times its first); MuJoCo runs it without tripping its acceleration
/// guard (the script fails if it does) and rings at prbfit's PRB first frequency with the
/// matrix's own mus (the export's floor adds 1e-6 of the beam's inertia to each light link:
/// a change of about 1e-6 in the first frequency).
#[test]
fn a_light_link_between_two_springs_runs_stably_at_prbfits_frequency() {
    if !common::tool_available(
        "MuJoCo (`python3 -c 'import mujoco'`)",
        common::command_works("python3", &["-c", "import mujoco"]),
        "pip install mujoco",
    ) {
        return;
    }
    let dir = Scratch::new("mujoco-light-link");
    let text = prbfit::scene::DEFAULT_SCENE_TOML.replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    );
    let path = dir.write("cantilever.toml", &text);
    let scene = Scene::from_toml_str(&text, "cantilever.toml").unwrap();
    let b = &scene.beam;
    let rho_a = 7850.0 * b.area();
    let omega_unit = (b.youngs_modulus * b.second_moment() / (rho_a * b.length.powi(4))).sqrt();
    let light = "0.1,inf,inf,0.499998; 0.35,3.51,inf,1e-6; 0.4,2.99,inf,1e-6; 0.15,2.58,inf,0.5";
    let m = PrbMatrix::parse(light).unwrap();
    let chain = PrbSolver::new(&m, b.model().axial_compliance());
    let omega = chain
        .modes(Load::new(0.0, 0.0, 0.0), &[0.0; 3], TipBody::default())
        .unwrap()[0];
    let hz = omega * omega_unit / (2.0 * PI);
    let fy = 1e-3 * b.youngs_modulus * b.second_moment() / b.length.powi(2);
    let sim = simulated(&dir, &path, light, "tip", fy, hz);
    eprintln!("cantilever light link: prbfit {hz:.6} Hz, MuJoCo {sim:.6} Hz");
    assert!(
        (sim / hz - 1.0).abs() < 5e-3,
        "MuJoCo {sim} Hz vs prbfit {hz} Hz"
    );
}
