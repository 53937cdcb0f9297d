//! The baseline beam's speed/accuracy trade: for each resolution (integrator tolerance),
//! the median time per load case when stepping along load paths, and the worst tip error
//! against a converged solve (tol = 1e-13).
//!
//! Then loads far beyond the everyday range (issue 11): the time of one `solve` of each,
//! its continuation steps and Newton shots, and the tip error against the aligned-beam
//! asymptote where one is known; and the slowest single solve among a set of hard loads,
//! which the effort budget bounds.
//!
//! Then the cost of the largest fibre stress (DESIGN §11) that every case carries: the time
//! of recomputing it on each case of a path, over the time of the path's solve.
//!
//! An integration step is a Dormand-Prince step, or for the plain-bending beam (the elastica
//! rows) a Taylor step of order about `-ln(tol)/2 + 1` (`src/beam/taylor.rs`).
//!
//! Run: `cargo bench --bench beam` (release build). Prints tables; asserts nothing.
//! `HUGE_ONLY=1` skips the first table, `SKIP_HUGE=1` the others, `STRESS_ONLY=1` runs only
//! the stress table.

// A bench whose solve fails has nothing to measure: it stops loudly at the failing case
// rather than print a table with holes.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use prbfit::beam::{BeamModel, BeamSolver, Effects, Load, Resolution, SolveError, TipPose};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    stress_cost();
    if std::env::var("STRESS_ONLY").is_ok() {
        return;
    }
    if std::env::var("HUGE_ONLY").is_err() {
        resolution_table();
    }
    if std::env::var("SKIP_HUGE").is_err() {
        huge_loads();
        cancel_latency();
        worst_case();
    }
}

fn resolution_table() {
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
                " {:>9.2} {:>9.2e}   {:.2} shots/case, {:.1} integration steps/shot",
                median(all_times),
                worst,
                shots as f64 / cases as f64,
                rk as f64 / cases as f64
            );
        }
        println!();
    }
}

/// The elastica's tip under a huge force `F` at angle `theta` with `|beta| < 2 sqrt(F)`:
/// matched boundary layers at root and tip, exact up to `O(exp(-sqrt(F)))` (derived in
/// tests/beam_budget.rs).
fn aligned_asymptote(load: Load) -> TipPose {
    let force = load.alpha_x.hypot(load.alpha_y);
    let theta = load.alpha_y.atan2(load.alpha_x);
    let root = force.sqrt();
    let half_tip = (load.beta / (2.0 * root)).asin();
    let d_re = 2.0 / root * ((0.5 * theta).cos() - 1.0 + half_tip.cos() - 1.0);
    let d_im = 2.0 / root * (-(0.5 * theta).sin() + half_tip.sin());
    let (s, c) = theta.sin_cos();
    TipPose {
        a: c * (1.0 + d_re) - s * d_im,
        b: s * (1.0 + d_re) + c * d_im,
        phi: theta + 2.0 * half_tip,
    }
}

/// A short name for how a solve ended.
fn outcome(result: &Result<prbfit::beam::BeamSolution, SolveError>) -> String {
    match result {
        Ok(_) => "answered".into(),
        Err(SolveError::Unstable { fraction, .. }) => format!("unstable at {fraction:.3e}"),
        Err(SolveError::EffortExceeded { fraction, .. }) => format!("budget out at {fraction:.3}"),
        Err(SolveError::NoConvergence { fraction, .. }) => format!("no conv. at {fraction:.3}"),
        Err(e) => format!("{e}").chars().take(24).collect(),
    }
}

/// Median time of `reps` solves, and the last result.
fn timed(
    solver: &BeamSolver,
    load: Load,
    reps: usize,
) -> (f64, Result<prbfit::beam::BeamSolution, SolveError>) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let result = black_box(solver.solve(black_box(load)));
        times.push(t0.elapsed().as_secs_f64());
        last = Some(result);
    }
    (median(times), last.expect("at least one rep"))
}

fn huge_loads() {
    let elastica = BeamModel::elastica();
    let stretchy =
        BeamModel::new(100.0, 0.3, None, Effects::parse_list("extension").unwrap()).unwrap();
    let cases: Vec<(&str, BeamModel, Load, bool)> = vec![
        ("alpha_y=1e3", elastica, Load::new(0.0, 1e3, 0.0), true),
        ("alpha_y=1e4", elastica, Load::new(0.0, 1e4, 0.0), true),
        ("alpha_y=1e5", elastica, Load::new(0.0, 1e5, 0.0), true),
        ("alpha_y=1e6", elastica, Load::new(0.0, 1e6, 0.0), true),
        ("alpha_y=1e7", elastica, Load::new(0.0, 1e7, 0.0), true),
        ("alpha_y=1e8", elastica, Load::new(0.0, 1e8, 0.0), true),
        ("45deg, 1.4e6", elastica, Load::new(1e6, 1e6, 0.0), true),
        (
            "alpha_y=1e6, beta=1e3",
            elastica,
            Load::new(0.0, 1e6, 1e3),
            true,
        ),
        (
            "alpha_x=1e6 (elastica)",
            elastica,
            Load::new(1e6, 0.0, 0.0),
            false,
        ),
        (
            "alpha_x=1e6 (ext, L/t=100)",
            stretchy,
            Load::new(1e6, 0.0, 0.0),
            false,
        ),
        ("alpha_x=-1e4", elastica, Load::new(-1e4, 0.0, 0.0), false),
        (
            "alpha_x=-1e4, alpha_y=1",
            elastica,
            Load::new(-1e4, 1.0, 0.0),
            true,
        ),
        ("alpha_x=-1e6", elastica, Load::new(-1e6, 0.0, 0.0), false),
        (
            "alpha_y=1e6, beta=3e3",
            elastica,
            Load::new(0.0, 1e6, 3e3),
            false,
        ),
    ];
    println!("Huge loads: one `solve` from the unloaded beam, tol = 1e-9 (median of 5).");
    println!("Tip error against the aligned-beam asymptote where it applies.\n");
    println!(
        "{:>28} | {:>22} | {:>10} | {:>6} | {:>6} | {:>9}",
        "load", "outcome", "ms/solve", "steps", "shots", "tip err"
    );
    for (name, model, load, asymptote) in cases {
        let solver = BeamSolver::new(model, Resolution::with_tol(1e-9)).unwrap();
        let (t, result) = timed(&solver, load, 5);
        let (steps, shots, err) = match &result {
            Ok(sol) => {
                let err = if asymptote {
                    format!("{:.2e}", sol.tip.max_diff(&aligned_asymptote(load)))
                } else if model.effects.extension {
                    let a = 1.0 + load.alpha_x * model.axial_compliance();
                    format!("{:.2e}", (sol.tip.a - a).abs())
                } else {
                    "-".into()
                };
                (
                    sol.continuation_steps.to_string(),
                    sol.iterations.to_string(),
                    err,
                )
            }
            Err(_) => ("-".into(), "-".into(), "-".into()),
        };
        println!(
            "{name:>28} | {:>22} | {:>10.2} | {steps:>6} | {shots:>6} | {err:>9}",
            outcome(&result),
            t * 1e3
        );
    }
    println!();
}

/// The slowest single `solve` among loads chosen to be hard: beyond reach (1e9), tip moments
/// that snap under huge forces, tilted huge compressions, huge moments, tight tolerances.
fn worst_case() {
    let elastica = BeamModel::elastica();
    let everything = BeamModel::new(10.0, 0.45, None, Effects::ALL).unwrap();
    let mut candidates: Vec<(BeamModel, f64, Load)> = Vec::new();
    for magnitude in [1e6f64, 1e7, 1e8, 1e9] {
        for angle in [0.1f64, 1.67, 2.46, 3.04, -1.47] {
            for beta_ratio in [0.0, 1.0, 3.0] {
                let beta = beta_ratio * magnitude.sqrt();
                let load = Load::new(magnitude * angle.cos(), magnitude * angle.sin(), beta);
                candidates.push((elastica, 1e-9, load));
            }
        }
    }
    for load in [
        Load::new(0.0, 0.0, 1e3),
        Load::new(0.0, 0.0, 1e6),
        Load::new(-1e5, 0.0, 1e3),
        Load::new(0.0, 1e6, -2e3),
    ] {
        candidates.push((elastica, 1e-9, load));
    }
    let stubby =
        BeamModel::new(10.0, 0.3, None, Effects::parse_list("extension").unwrap()).unwrap();
    candidates.push((stubby, 1e-9, Load::new(1e6, 0.0, 0.0)));
    candidates.push((everything, 1e-9, Load::new(0.0, 1e6, 0.0)));
    for tol in [1e-12, 1e-14] {
        candidates.push((elastica, tol, Load::new(0.0, 1e6, 0.0)));
        candidates.push((elastica, tol, Load::new(0.0, 1e8, 0.0)));
        candidates.push((everything, tol, Load::new(0.0, 1e6, 0.0)));
    }
    let mut rows = Vec::new();
    for (model, tol, load) in candidates {
        let solver = BeamSolver::new(model, Resolution::with_tol(tol)).unwrap();
        let (t, result) = timed(&solver, load, 1);
        rows.push((t, tol, model.effects, load, outcome(&result)));
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    let total: f64 = rows.iter().map(|r| r.0).sum();
    println!(
        "Hard loads: {} single solves, {total:.1} s in all; the five slowest:",
        rows.len()
    );
    for (t, tol, effects, load, what) in rows.iter().take(5) {
        println!("  {t:>6.3} s  tol {tol:.0e}, effects {effects}: {load} -> {what}");
    }
    println!();
}

/// How long a long path solve takes to stop after its token is cancelled.
fn cancel_latency() {
    let solver = BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-9)).unwrap();
    let mut latencies = Vec::new();
    for delay_ms in [5u64, 13, 29, 61, 97] {
        let token = prbfit::cancel::CancelToken::new();
        let remote = token.clone();
        let canceller = std::thread::spawn(move || {
            std::thread::sleep(std::time::Duration::from_millis(delay_ms));
            remote.cancel();
            Instant::now()
        });
        let result = solver.solve_path_cancellable(Load::new(0.0, 1e8, 0.0), 40, &token);
        let stopped = Instant::now();
        let cancelled_at = canceller.join().unwrap();
        assert!(matches!(result, Err(SolveError::Cancelled { .. })));
        latencies.push(stopped.duration_since(cancelled_at).as_secs_f64() * 1e6);
    }
    let worst = latencies.iter().cloned().fold(0.0, f64::max);
    println!(
        "Cancellation: a 40-case alpha_y = 1e8 path stops {:.0} us (median; worst {worst:.0} us) \
         after its token is cancelled.\n",
        median(latencies)
    );
}

/// The stress's share of a solve: each path solved (stress included, as every solve does),
/// then the stress of each of its cases computed again on its own; the ratio is the stress's
/// share of the solve.
fn stress_cost() {
    let paths: Vec<(&str, Load)> = vec![
        ("alpha_y=3", Load::new(0.0, 3.0, 0.0)),
        ("alpha_y=10", Load::new(0.0, 10.0, 0.0)),
        ("beta=2pi", Load::new(0.0, 0.0, 2.0 * PI)),
        ("combined", Load::new(1.0, 4.0, -2.0)),
        ("interior peak", Load::new(-1.5, -2.0, 1.5)),
        ("alpha_y=100", Load::new(0.0, 100.0, 0.0)),
    ];
    let steps = 20;
    println!("Stress: its cost per {steps}-case path (median of 9), tol 1e-9, 41 shape points,");
    println!("all effects, L/t0 = 20, nu = 0.3.\n");
    println!(
        "{:>14} {:>12} {:>12} {:>8}",
        "path", "solve us", "stress us", "share"
    );
    let model = BeamModel::new(20.0, 0.3, None, Effects::ALL).unwrap();
    let solver = BeamSolver::new(model, Resolution::with_tol(1e-9)).unwrap();
    for (name, end) in paths {
        let mut solve = Vec::new();
        let mut stress = Vec::new();
        for _ in 0..9 {
            let t = Instant::now();
            let cases = black_box(solver.solve_path(end, steps).unwrap());
            solve.push(t.elapsed().as_secs_f64() * 1e6);
            let t = Instant::now();
            for c in &cases {
                black_box(solver.max_stress(c.load, c.tip, &c.shape));
            }
            stress.push(t.elapsed().as_secs_f64() * 1e6);
        }
        let (solve, stress) = (median(solve), median(stress));
        println!(
            "{name:>14} {solve:>12.0} {stress:>12.1} {:>7.2}%",
            100.0 * stress / solve
        );
    }
    println!();
}
