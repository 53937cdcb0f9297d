//! The fit's cost and accuracy by fidelity preset.
//!
//! 1. A 3R (`L-R-R-R`) fit on the built-in 20-case scene at `normal` fidelity, baseline
//!    included: median wall time.
//! 2. The scipy job's fit (`benches/scipy/fit3r.py`: the built-in scene's loads on the plain
//!    elastica, `L-R-R-R` at `draft`) in this warm process: its baseline and its fit apart,
//!    the best of many runs, and its evaluations (deterministic: the figure to compare
//!    across changes when the machine is noisy).
//! 3. For three example scenes and a few topologies, each fidelity's time (baseline + fit) and
//!    how far its answer is from `precise`: every fitted matrix is judged on the precise
//!    baseline (fine resolution, doubled load sampling), so the J column is comparable.
//!
//! Run: `cargo bench --bench fit`. Prints tables; asserts nothing.

// A benchmark that cannot load its scene or solve its model should stop loudly, not measure
// something else: unwraps are the right tool here.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::Instant;

use prbfit::eval::evaluate;
use prbfit::fit::{CancelToken, Fidelity, FitOptions};
use prbfit::prb::PrbMatrix;
use prbfit::scene::Scene;
use prbfit::study::{Sampling, Study};

fn run(scene: &Scene, topology: &str, fidelity: Fidelity) -> (f64, PrbMatrix, u64) {
    let t0 = Instant::now();
    let study = Study::as_given(scene, Sampling::Fidelity(fidelity)).unwrap();
    let options = FitOptions {
        fidelity,
        angle_weight: scene.fit.angle_weight,
        seed: 1,
    };
    let start = PrbMatrix::from_topology(topology).unwrap();
    let report = study
        .fit(&start, &options, &mut |_| {}, &CancelToken::new())
        .unwrap();
    (
        t0.elapsed().as_secs_f64(),
        report.matrix,
        report.evaluations,
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let builtin = Scene::builtin();
    let times: Vec<f64> = (0..15)
        .map(|_| run(&builtin, "L-R-R-R", Fidelity::Normal).0)
        .collect();
    println!(
        "3R fit, built-in scene ({} cases), normal fidelity, baseline included: median {:.1} ms \
         (min {:.1}, max {:.1}) over {} runs\n",
        builtin.cases().len(),
        median(times.clone()) * 1e3,
        times.iter().cloned().fold(f64::MAX, f64::min) * 1e3,
        times.iter().cloned().fold(0.0, f64::max) * 1e3,
        times.len()
    );

    // The scipy job's fit: the truth (`Study::as_given`, the draft baseline) and the fit
    // timed apart, each the best of 200 runs.
    let elastica = Scene::from_toml_str(
        &prbfit::scene::DEFAULT_SCENE_TOML.replacen("effects = \"auto\"", "effects = []", 1),
        "elastica.toml",
    )
    .unwrap();
    let (mut truth, mut fit, mut evaluations) = (f64::MAX, f64::MAX, 0);
    for _ in 0..200 {
        let t0 = Instant::now();
        let study = Study::as_given(&elastica, Sampling::Fidelity(Fidelity::Draft)).unwrap();
        let t1 = Instant::now();
        let options = FitOptions {
            fidelity: Fidelity::Draft,
            angle_weight: elastica.fit.angle_weight,
            seed: 1,
        };
        let start = PrbMatrix::from_topology("L-R-R-R").unwrap();
        let report = study
            .fit(&start, &options, &mut |_| {}, &CancelToken::new())
            .unwrap();
        truth = truth.min((t1 - t0).as_secs_f64());
        fit = fit.min(t1.elapsed().as_secs_f64());
        evaluations = report.evaluations;
    }
    println!(
        "the scipy job's fit (built-in loads, elastica, L-R-R-R, draft), best of 200 in this \
         process: truth {:.1} us, fit {:.1} us, {} evaluations\n",
        truth * 1e6,
        fit * 1e6,
        evaluations
    );

    // Cancellation: a precise fit (several hundred ms) cancelled 30 ms in; the time from the
    // cancel to the fit's return.
    let steel = Scene::from_file(Path::new(&format!(
        "{}/assets/scenes/steel-flexure.toml",
        env!("CARGO_MANIFEST_DIR")
    )))
    .unwrap();
    let study = Study::as_given(&steel, Sampling::Fidelity(Fidelity::Precise)).unwrap();
    let mut latencies = Vec::new();
    for _ in 0..10 {
        let cancel = CancelToken::new();
        let token = cancel.clone();
        let start = PrbMatrix::from_topology("L-RP-RP-RP").unwrap();
        let options = FitOptions {
            fidelity: Fidelity::Precise,
            angle_weight: 1.0,
            seed: 1,
        };
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::scope(|s| {
            s.spawn(|| {
                let r = study.fit(&start, &options, &mut |_| {}, &cancel).unwrap();
                tx.send((Instant::now(), r.stop)).unwrap();
            });
            std::thread::sleep(std::time::Duration::from_millis(30));
            let at = Instant::now();
            token.cancel();
            let (done, stop) = rx.recv().unwrap();
            latencies.push((done.duration_since(at).as_secs_f64(), stop));
        });
    }
    let ms: Vec<f64> = latencies.iter().map(|l| l.0 * 1e3).collect();
    println!(
        "cancel to return, precise L-RP-RP-RP fit on the steel flexure: median {:.3} ms, max {:.3} ms \
         over {} runs (stop reasons: {:?})\n",
        median(ms.clone()),
        ms.iter().cloned().fold(0.0, f64::max),
        ms.len(),
        latencies.iter().map(|l| l.1).collect::<Vec<_>>()
    );

    println!("Fidelity presets: time (baseline + fit, median of 5) and J on the precise baseline");
    println!(
        "{:<28} {:<11} {:<8} {:>10} {:>8} {:>12} {:>10}",
        "scene", "topology", "fidelity", "ms", "evals", "J (precise)", "vs precise"
    );
    for name in ["default", "steel-flexure", "urethane-joint"] {
        let path = format!("{}/assets/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        let scene = Scene::from_file(Path::new(&path)).unwrap();
        let reference = Study::as_given(&scene, Sampling::Fidelity(Fidelity::Precise)).unwrap();
        let reference = reference.baseline().unwrap();
        for topology in ["L-R", "L-R-R-R", "L-RP-RP-RP"] {
            let mut rows = Vec::new();
            for fidelity in Fidelity::ALL {
                let reps = if fidelity == Fidelity::Precise { 3 } else { 5 };
                let mut ts = Vec::new();
                let mut last = None;
                for _ in 0..reps {
                    let (t, m, evals) = run(&scene, topology, fidelity);
                    ts.push(t);
                    last = Some((m, evals));
                }
                let (m, evals) = last.unwrap();
                let j = evaluate(&m, reference, scene.fit.angle_weight)
                    .unwrap()
                    .figures
                    .objective;
                rows.push((fidelity, median(ts), evals, j));
            }
            let j_precise = rows[2].3;
            for (fidelity, t, evals, j) in rows {
                println!(
                    "{:<28} {:<11} {:<8} {:>10.1} {:>8} {:>12.4e} {:>+9.2}%",
                    scene.name.chars().take(28).collect::<String>(),
                    topology,
                    fidelity.to_string(),
                    t * 1e3,
                    evals,
                    j,
                    (j / j_precise - 1.0) * 100.0
                );
            }
        }
    }
}
