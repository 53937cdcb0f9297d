//! The baseline beam's speed/accuracy trade: for each resolution (integrator tolerance),
//! the median time per load case when stepping along load paths, and the worst tip error
//! against a converged solve (tol = 1e-13).
//!
//! Run: `cargo bench --bench beam` (release build). Prints a table; asserts nothing.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let c135 = (3.0 * PI / 4.0).cos();
    let s135 = (3.0 * PI / 4.0).sin();
    let paths: Vec<(&str, Load)> = vec![
        ("alpha_y=3", Load::new(0.0, 3.0, 0.0)),
        ("alpha_y=10", Load::new(0.0, 10.0, 0.0)),
        ("135deg a=10", Load::new(10.0 * c135, 10.0 * s135, 0.0)),
        ("beta=2pi", Load::new(0.0, 0.0, 2.0 * PI)),
        ("combined", Load::new(1.0, 4.0, -2.0)),
        ("alpha_y=100", Load::new(0.0, 100.0, 0.0)),
    ];
    let steps = 20;
    let beams = [
        ("elastica", BeamModel::elastica()),
        (
            "all effects, L/t=10, nu=0.45",
            BeamModel::new(10.0, 0.45, None, Effects::ALL).unwrap(),
        ),
    ];
    let tols = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    println!("Baseline beam: time per load case stepping along a {steps}-step load path");
    println!("(median of repeated path solves, divided by {steps}), and the worst tip error");
    println!("(max |da|, |db|, |dphi| over all cases) against tol = 1e-13.\n");
    for (beam_name, model) in beams {
        let reference = BeamSolver::new(model, Resolution::with_tol(1e-13)).unwrap();
        let truth: Vec<Vec<_>> = paths
            .iter()
            .map(|(_, end)| reference.solve_path(*end, steps).unwrap())
            .collect();
        println!("beam: {beam_name}");
        print!("{:>8} |", "tol");
        for (name, _) in &paths {
            print!(" {:>22} |", name);
        }
        println!(" {:>9} {:>9}", "median", "max err");
        print!("{:>8} |", "");
        for _ in &paths {
            print!(" {:>10} {:>11} |", "us/case", "tip err");
        }
        println!(" {:>9} {:>9}", "us/case", "");
        for tol in tols {
            let solver = BeamSolver::new(
                model,
                Resolution {
                    tol,
                    shape_points: std::env::var("SHAPE")
                        .map(|s| s.parse().unwrap())
                        .unwrap_or(41),
                },
            )
            .unwrap();
            print!("{tol:>8.0e} |");
            let mut all_times = Vec::new();
            let mut worst = 0.0_f64;
            let (mut shots, mut rk, mut cases) = (0u64, 0u64, 0u64);
            for ((_, end), truth) in paths.iter().zip(&truth) {
                let mut err = 0.0_f64;
                let mut times = Vec::new();
                let reps = 30;
                for _ in 0..reps {
                    let t0 = Instant::now();
                    let sols = black_box(solver.solve_path(black_box(*end), steps)).unwrap();
                    times.push(t0.elapsed().as_secs_f64() / steps as f64 * 1e6);
                    for (a, b) in sols.iter().zip(truth) {
                        err = err.max(a.tip.max_diff(&b.tip));
                        shots += a.iterations as u64;
                        rk += a.rk_steps as u64;
                        cases += 1;
                    }
                }
                let t = median(times.clone());
                all_times.push(t);
                worst = worst.max(err);
                print!(" {t:>10.2} {err:>11.2e} |");
            }
            println!(
                " {:>9.2} {:>9.2e}   {:.2} shots/case, {:.1} RK steps/shot",
                median(all_times),
                worst,
                shots as f64 / cases as f64,
                rk as f64 / cases as f64
            );
        }
        println!();
    }
}
