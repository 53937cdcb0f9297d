//! The fit on a mechanism scene (DESIGN §8): a 3R (`L-R-R-R`) fitted on the compliant
//! slider-crank with its drive in 20 steps (20 cases), at each fidelity, the exact mechanism
//! included: median wall time, evaluations of `J`, and what the fit reached (`J`, max
//! reaction error). Target (issue 13): normal fidelity at most 100 ms.
//!
//! Then the path of the normal fit: the best `J` against evaluations, to show where the time
//! goes.
//!
//! Run: `cargo bench --bench mech_fit` (release build). Prints tables; asserts nothing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::Instant;

use prbfit::fit::{CancelToken, Fidelity, FitOptions, FitProgress};
use prbfit::prb::PrbMatrix;
use prbfit::scene::Scene;
use prbfit::study::{Sampling, Study};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut scene = Scene::from_file(Path::new(&format!(
        "{}/assets/scenes/slider-crank.toml",
        env!("CARGO_MANIFEST_DIR")
    )))
    .unwrap();
    scene.mechanism.as_mut().unwrap().drives[0].steps = 20;
    let start = PrbMatrix::from_topology("L-R-R-R").unwrap();
    let run = |fidelity: Fidelity, progress: &mut dyn FnMut(&FitProgress)| {
        let t0 = Instant::now();
        let study = Study::as_given(&scene, Sampling::Fidelity(fidelity)).unwrap();
        let options = FitOptions {
            fidelity,
            angle_weight: scene.fit.angle_weight,
            seed: 1,
        };
        let report = study
            .fit(&start, &options, progress, &CancelToken::new())
            .unwrap();
        (t0.elapsed().as_secs_f64(), report)
    };
    println!("3R fit, slider-crank in 20 steps (20 cases), exact mechanism included");
    println!(
        "{:<8} {:>10} {:>10} {:>12} {:>11} {:>13}",
        "fidelity", "median ms", "min ms", "evaluations", "J", "max force err"
    );
    for fidelity in [Fidelity::Draft, Fidelity::Normal, Fidelity::Precise] {
        let runs = if fidelity == Fidelity::Precise { 3 } else { 11 };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..runs {
            let (t, report) = run(fidelity, &mut |_| {});
            times.push(t);
            last = Some(report);
        }
        let report = last.unwrap();
        println!(
            "{:<8} {:>10.1} {:>10.1} {:>12} {:>11.3e} {:>13.3e}",
            fidelity.to_string(),
            median(times.clone()) * 1e3,
            times.iter().cloned().fold(f64::MAX, f64::min) * 1e3,
            report.evaluations,
            report.figures.objective,
            report.figures.max_force()
        );
    }
    println!("\nnormal fit's path (best J as the evaluations go):");
    let mut seen = f64::INFINITY;
    run(Fidelity::Normal, &mut |p| {
        if p.best_objective < 0.5 * seen {
            seen = p.best_objective;
            println!(
                "  {:>6} evaluations  {:<6} J {:.3e}",
                p.evaluations, p.phase, p.best_objective
            );
        }
    });
}
