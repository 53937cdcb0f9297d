//! PRB statics speed: a 3R (and other topologies) equilibrium solved warm-started along a
//! load path, median time per load case; and the PRB natural frequencies (DESIGN §10) of each
//! model about an equilibrium, median time per call (the bound: 10 us).
//!
//! Run: `cargo bench --bench prb`. Prints a table; asserts nothing.

// A benchmark that cannot load its scene or solve its model should stop loudly, not measure
// something else: unwraps are the right tool here.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use prbfit::beam::Load;
use prbfit::prb::{PrbMatrix, PrbSolver, TipBody};

fn main() {
    let c135 = (3.0 * PI / 4.0).cos();
    let s135 = (3.0 * PI / 4.0).sin();
    let paths = [
        ("alpha_y=5", Load::new(0.0, 5.0, 0.0)),
        ("135deg a=3", Load::new(3.0 * c135, 3.0 * s135, 0.0)),
        ("beta=2", Load::new(0.0, 0.0, 2.0)),
        ("combined", Load::new(-1.0, 3.0, 1.0)),
    ];
    let models = [
        ("howell-1r", "0.15,inf,inf; 0.85,2.2525,inf"),
        (
            "su-3r",
            "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf",
        ),
        (
            "L-R-R-R-R",
            "0.06,inf,inf; 0.27,4,inf; 0.27,4,inf; 0.27,4,inf; 0.13,4,inf",
        ),
        (
            "L-RP-RP-RP",
            "0.1,inf,inf; 0.35,3.51,2.9; 0.4,2.99,2.5; 0.15,2.58,6.7",
        ),
    ];
    let steps = 20;
    println!("PRB equilibrium, warm-started along a {steps}-step load path: median us per case");
    print!("{:<12}", "model");
    for (name, _) in &paths {
        print!(" {name:>12}");
    }
    println!(" {:>8} {:>12}", "median", "Newton/case");
    for (name, text) in models {
        let m = PrbMatrix::parse(text).unwrap();
        let solver = PrbSolver::new(&m, 1.0 / 120000.0);
        print!("{name:<12}");
        let mut all = Vec::new();
        let (mut its, mut cases) = (0u64, 0u64);
        for (_, end) in &paths {
            let mut times = Vec::new();
            for _ in 0..400 {
                let t0 = Instant::now();
                let mut sink = 0.0;
                solver
                    .solve_path_with(black_box(*end), steps, |s| {
                        sink += s.tip.a;
                        its += s.iterations as u64;
                        cases += 1;
                    })
                    .unwrap();
                black_box(sink);
                times.push(t0.elapsed().as_secs_f64() * 1e6 / steps as f64);
            }
            times.sort_by(f64::total_cmp);
            let med = times[times.len() / 2];
            all.push(med);
            print!(" {med:>12.3}");
        }
        all.sort_by(f64::total_cmp);
        println!(
            " {:>8.3} {:>12.2}",
            all[all.len() / 2],
            its as f64 / cases as f64
        );
    }
    modes(&models);
}

/// Median microseconds per `PrbSolver::modes` call (linearise, mass matrix, eigenvalues)
/// about the equilibrium under `alpha_y = 2`, with a tip body.
fn modes(models: &[(&str, &str)]) {
    println!("\nPRB modes about the equilibrium at alpha_y = 2: median us per call");
    for (name, text) in models {
        let m = PrbMatrix::parse(text).unwrap();
        let solver = PrbSolver::new(&m, 1.0 / 120000.0);
        let load = Load::new(0.0, 2.0, 0.0);
        let q = solver.solve(load).unwrap().q;
        let body = TipBody {
            mass: 0.1,
            inertia: 0.001,
        };
        let mut times = Vec::new();
        let mut first = 0.0;
        for _ in 0..2000 {
            let t0 = Instant::now();
            let w = solver.modes(black_box(load), black_box(&q), body).unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            first = w[0];
        }
        times.sort_by(f64::total_cmp);
        println!(
            "{name:<12} {:>8.3} us  (first Omega {first:.4})",
            times[times.len() / 2]
        );
    }
}
