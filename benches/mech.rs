//! Mechanism solves (DESIGN §8): time per drive case of the exact mechanism (beam tol 1e-8)
//! and of PRB mechanisms (Newton at 1e-8), for the fixed-guided segment, the parallel-guiding stage and the
//! compliant slider-crank. Targets (issue 12): one-flexure driven case <= 50 us, parallel
//! stage <= 150 us, any PRB mechanism <= 5 us.
//!
//! Then the coverage grid of the parallel-guiding stage (`W = 0.3 L`, `Ay` 0..20,
//! `Ax` -10..10, `B` -3..3 in steps 2, 2, 1: 847 points, each by continuation from zero in
//! 10 steps): how many points each solver solves, how many end at a named critical point,
//! and how long the whole grid takes.
//!
//! Then the shipped parallel stage (`assets/scenes/parallel-stage.toml`: shear, extension and
//! Poisson on) at 500 steps a drive, 1000 cases at the default tol, as `prbfit solve --scene`
//! solves it (issue 24's stage job); and its flexures' root shots one by one against two at a
//! time side by side (`beam::root::shoot_root_pair`), at the wrench of a case late on its
//! first drive.
//!
//! Run: `cargo bench --bench mech` (release build). Prints tables; asserts nothing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::Instant;

use prbfit::beam::{Effects, Resolution};
use prbfit::mech::{exact, prb, MechCase, MechError};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};

use Coordinate::{Loaded, Prescribed};

const STEPS: u32 = 20;

fn flexure(root: [f64; 2], attach: Attach) -> Flexure {
    Flexure {
        root,
        angle: 0.0,
        attach,
        beam: BeamSpec {
            length: 1.0,
            width: 1.0,
            thickness: 0.01,
            youngs_modulus: 12e6,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Fixed(Effects::NONE),
            allowable_stress: None,
        },
    }
}

fn mechanism(flexures: Vec<Flexure>, point: [f64; 2], drive: [Coordinate; 3]) -> Mechanism {
    Mechanism {
        flexures,
        stage_point: point,
        drives: vec![Drive::proportional(drive, STEPS)],
    }
}

/// Median microseconds per case over `runs` solves of the whole path.
fn time(runs: usize, mut solve: impl FnMut() -> usize) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            let cases = black_box(solve());
            start.elapsed().as_secs_f64() * 1e6 / cases as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn main() {
    let (s45, c45) = std::f64::consts::FRAC_PI_4.sin_cos();
    let s0 = [1.0 + 0.5 * c45, -0.5 * s45];
    let scenes = [
        (
            "fixed-guided dy=0.5",
            mechanism(
                vec![flexure([0.0, 0.0], Attach::Clamped)],
                [1.0, 0.0],
                [Loaded(0.0), Prescribed(0.5), Prescribed(0.0)],
            ),
        ),
        (
            "parallel stage Ay=5",
            mechanism(
                vec![
                    flexure([0.0, 0.3], Attach::Clamped),
                    flexure([0.0, -0.3], Attach::Clamped),
                ],
                [1.0, 0.0],
                [Loaded(0.0), Loaded(5.0), Loaded(0.0)],
            ),
        ),
        (
            "slider-crank stroke 0.3",
            mechanism(
                vec![flexure([0.0, 0.0], Attach::Link { to: s0 })],
                s0,
                [Prescribed(0.0), Prescribed(0.3), Prescribed(0.0)],
            ),
        ),
    ];
    let models = [
        ("howell-1r", "0.15,inf,inf; 0.85,2.2525,inf"),
        (
            "su-3r",
            "0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf",
        ),
    ];
    println!("{:<26} {:<12} {:>12}", "mechanism", "model", "us/case");
    for (name, m) in &scenes {
        let us = time(5, || match exact::solve(m, Resolution::with_tol(1e-8)) {
            Ok(c) => c[0].len(),
            Err(e) => panic!("{name}: {e}"),
        });
        println!("{name:<26} {:<12} {us:>12.1}", "beam 1e-8");
        for (model, text) in models {
            let matrix = PrbMatrix::parse(text).unwrap();
            match prb::solve(m, &matrix, 1e-8) {
                Ok(_) => {
                    let us = time(21, || prb::solve(m, &matrix, 1e-8).unwrap()[0].len());
                    println!("{name:<26} {model:<12} {us:>12.1}");
                }
                Err(e) => println!("{name:<26} {model:<12} {e}"),
            }
        }
    }
    grid(&models[1]);
    shipped_stage();
}

/// The shipped parallel stage at 1000 cases, and its flexures' shots one by one and in pairs.
fn shipped_stage() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/parallel-stage.toml");
    let scene = prbfit::scene::Scene::from_file(&path).unwrap();
    let mut m = scene.mechanism.clone().unwrap();
    for d in &mut m.drives {
        d.steps = 500;
    }
    let resolution = Resolution::default();
    let best = |runs: usize, mut f: Box<dyn FnMut() -> usize + '_>| {
        (0..runs)
            .map(|_| {
                let start = Instant::now();
                black_box(f());
                start.elapsed().as_secs_f64()
            })
            .fold(f64::MAX, f64::min)
    };
    let cases = exact::solve(&m, resolution).unwrap();
    let n: usize = cases.iter().map(Vec::len).sum();
    let whole = best(
        15,
        Box::new(|| {
            exact::solve(&m, resolution)
                .unwrap()
                .iter()
                .map(Vec::len)
                .sum()
        }),
    );
    println!(
        "\nshipped parallel stage (shear, extension, Poisson), {n} cases at tol {:e}: best of 15 \
         {:.1} ms ({:.1} us/case)",
        resolution.tol,
        whole * 1e3,
        whole * 1e6 / n as f64
    );
    // A case late on the first drive: its two flexures' wrenches (own units). The two
    // flexures are the same beam in this scene, so flexure 1's solver shoots both.
    let case = &cases[0][400];
    let solver = prbfit::beam::BeamSolver::new(m.flexures[0].model(), resolution).unwrap();
    let w: Vec<[f64; 3]> = case
        .flexures
        .iter()
        .map(|f| {
            // The root moment from the tip wrench: beta + alpha_y a - alpha_x b.
            let (l, t) = (f.wrench, f.tip);
            [
                l.alpha_x,
                l.alpha_y,
                l.beta + l.alpha_y * t.a - l.alpha_x * t.b,
            ]
        })
        .collect();
    const SHOTS: usize = 2000;
    // The best of 9 runs of SHOTS pairs, each pair by `shoot`.
    let per_pairs = |shoot: &mut dyn FnMut()| {
        best(
            9,
            Box::new(|| {
                (0..SHOTS).for_each(|_| shoot());
                2 * SHOTS
            }),
        )
    };
    let alone = per_pairs(&mut || {
        let a = solver.shoot_root(w[0][0], w[0][1], w[0][2]).unwrap();
        let b = solver.shoot_root(w[1][0], w[1][1], w[1][2]).unwrap();
        black_box((a, b));
    });
    let paired = per_pairs(&mut || {
        let [a, b] =
            prbfit::beam::root::shoot_root_pair([(&solver, w[0], None), (&solver, w[1], None)]);
        black_box((a.unwrap(), b.unwrap()));
    });
    let mut shapes = (Vec::new(), Vec::new());
    let alone_values = per_pairs(&mut || {
        let a = solver.shoot_root_tip(w[0][0], w[0][1], w[0][2], Some(&mut shapes.0));
        let b = solver.shoot_root_tip(w[1][0], w[1][1], w[1][2], Some(&mut shapes.1));
        black_box((a.unwrap(), b.unwrap()));
    });
    let paired_values = per_pairs(&mut || {
        let [a, b] = prbfit::beam::root::shoot_root_tip_pair([
            (&solver, w[0], Some(&mut shapes.0)),
            (&solver, w[1], Some(&mut shapes.1)),
        ]);
        black_box((a.unwrap(), b.unwrap()));
    });
    let us = |t: f64| t * 1e6 / SHOTS as f64;
    println!(
        "its two flexures' root shots at case 401 of drive 1, us per pair: with the variational \
         equations {:.2} one by one, {:.2} side by side; by values with the shape {:.2} one by \
         one, {:.2} side by side",
        us(alone),
        us(paired),
        us(alone_values),
        us(paired_values)
    );
}

/// The coverage grid with the exact beam and with one PRB model.
fn grid(model: &(&str, &str)) {
    let matrix = PrbMatrix::parse(model.1).unwrap();
    let stage = |load: [f64; 3]| {
        let mut m = mechanism(
            vec![
                flexure([0.0, 0.3], Attach::Clamped),
                flexure([0.0, -0.3], Attach::Clamped),
            ],
            [1.0, 0.0],
            load.map(Loaded),
        );
        m.drives[0].steps = 10;
        m
    };
    let loads: Vec<[f64; 3]> = (0..=10)
        .flat_map(|iy| {
            (0..=10).flat_map(move |ix| {
                (0..=6).map(move |ib| [-10.0 + 2.0 * ix as f64, 2.0 * iy as f64, -3.0 + ib as f64])
            })
        })
        .collect();
    println!();
    println!("parallel-stage grid, {} points", loads.len());
    println!(
        "{:<12} {:>8} {:>10} {:>8} {:>10}",
        "solver", "solved", "critical", "failed", "seconds"
    );
    type Solve<'a> = Box<dyn Fn(&Mechanism) -> Result<Vec<Vec<MechCase>>, MechError> + 'a>;
    let solvers: [(&str, Solve); 2] = [
        (
            "beam 1e-8",
            Box::new(|m| exact::solve(m, Resolution::with_tol(1e-8))),
        ),
        (model.0, Box::new(|m| prb::solve(m, &matrix, 1e-8))),
    ];
    for (name, solve) in &solvers {
        let (mut solved, mut critical, mut failed) = (0, 0, 0);
        let start = Instant::now();
        for load in &loads {
            match solve(&stage(*load)) {
                Ok(_) => solved += 1,
                Err(MechError::Critical { .. }) => critical += 1,
                Err(_) => failed += 1,
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        println!("{name:<12} {solved:>8} {critical:>10} {failed:>8} {seconds:>10.3}");
    }
}
