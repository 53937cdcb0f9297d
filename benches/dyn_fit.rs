//! The dynamics' cost (issue 25, DESIGN §10), on the built-in scene with steel's density:
//!
//! 1. PRB natural frequencies per call ([`Study::prb_frequencies`]: Su's 3R with the tip
//!    chain; the parallel stage's whole PRB mechanism), median of many calls (the issue's
//!    bound: 10 us).
//! 2. A 3R fit at `normal` fidelity with `[fit] modes = 3` against the statics-only fit
//!    (the truth solved beforehand, the fit alone timed): median wall time, evaluations of
//!    `J`, and the ratio (the bound: 2x).
//!
//! Run: `cargo bench --bench dyn_fit`. Prints tables; asserts nothing.

// A benchmark that cannot load its scene or solve its model should stop loudly, not measure
// something else: unwraps are the right tool here.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::Instant;

use prbfit::fit::{CancelToken, Fidelity, FitOptions};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{Scene, DEFAULT_SCENE_TOML};
use prbfit::study::{Sampling, Study};

const SU: &str = "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf";

fn builtin(fit: &str) -> Scene {
    let text = DEFAULT_SCENE_TOML
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        )
        .replacen(
            "angle_weight = 1.0",
            &format!("angle_weight = 1.0\n{fit}"),
            1,
        );
    Scene::from_toml_str(&text, "dynamic.toml").unwrap()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median microseconds per call of the study's PRB frequencies for `matrix`.
fn per_call(study: &Study, matrix: &PrbMatrix) -> f64 {
    let body = study.truth_modes().unwrap().body;
    let mut times = Vec::new();
    for _ in 0..50 {
        let t0 = Instant::now();
        for _ in 0..200 {
            black_box(study.prb_frequencies(black_box(matrix), body).unwrap());
        }
        times.push(t0.elapsed().as_secs_f64() / 200.0 * 1e6);
    }
    median(times)
}

fn main() {
    let su = PrbMatrix::parse(SU).unwrap();
    println!("PRB natural frequencies per call (median us):");
    let cantilever = Study::new(&builtin(""), Sampling::Fidelity(Fidelity::Normal)).unwrap();
    println!(
        "  {:<34} {:>8.2}",
        "su-3r cantilever chain",
        per_call(&cantilever, &su)
    );
    let stage = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/parallel-stage.toml"
    ))
    .unwrap()
    .replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    )
    .replacen(
        "point = [0.05, 0.0]",
        "point = [0.05, 0.0]\nmass = 0.0039\ninertia = 1e-6",
        1,
    );
    let stage = Scene::from_toml_str(&stage, "stage.toml").unwrap();
    let stage = Study::new(&stage, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    println!(
        "  {:<34} {:>8.2}",
        "su-3r parallel stage (2 chains)",
        per_call(&stage, &su)
    );

    println!();
    println!("3R fit on the built-in scene at normal fidelity (fit only, median of 7):");
    println!(
        "  {:<18} {:>10} {:>12} {:>14} {:>12}",
        "fit", "ms", "evaluations", "us/evaluation", "max_freq_err"
    );
    let start = PrbMatrix::from_topology("3R").unwrap();
    let mut medians = Vec::new();
    for (label, fit) in [("statics only", ""), ("modes = 3", "modes = 3")] {
        let study = Study::new(&builtin(fit), Sampling::Fidelity(Fidelity::Normal)).unwrap();
        let options = FitOptions {
            fidelity: Fidelity::Normal,
            angle_weight: 1.0,
            seed: 1,
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..7 {
            let t0 = Instant::now();
            let report = study
                .fit(&start, &options, &mut |_| {}, &CancelToken::new())
                .unwrap();
            times.push(t0.elapsed().as_secs_f64());
            last = Some(report);
        }
        let report = last.unwrap();
        let ms = median(times) * 1e3;
        let freq = study.frequencies(&report.matrix).map_or(f64::NAN, |f| {
            f.freq_err[..3].iter().fold(0.0, |m, e| m.max(e.abs()))
        });
        println!(
            "  {label:<18} {ms:>10.1} {:>12} {:>14.1} {freq:>12.2e}",
            report.evaluations,
            ms * 1e3 / report.evaluations as f64
        );
        medians.push(ms);
    }
    println!(
        "  ratio modes = 3 / statics only: {:.2}x",
        medians[1] / medians[0]
    );
}
