//! The truth's modes (DESIGN §10): time per equilibrium for the first three frequencies at
//! the default degree (the 1e-6 claim), and their error against the degree raised by 16.
//! Prints a table; asserts nothing.
//!
//! Run: `cargo bench --bench modes`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::time::Instant;

use prbfit::beam::modes::{beam_modes, ModeSettings, TipBody};
use prbfit::beam::{BeamModel, BeamSolver, Effects, Load};
use prbfit::mech::modes::{mech_modes, MechMass};
use prbfit::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure, Mechanism};

fn main() {
    let cases: [(&str, Effects, Load); 6] = [
        (
            "unloaded, elastica",
            Effects::NONE,
            Load::new(0.0, 0.0, 0.0),
        ),
        (
            "unloaded, all effects",
            Effects::ALL,
            Load::new(0.0, 0.0, 0.0),
        ),
        (
            "alpha_y = 5, elastica",
            Effects::NONE,
            Load::new(0.0, 5.0, 0.0),
        ),
        (
            "alpha_y = 5, all effects",
            Effects::ALL,
            Load::new(0.0, 5.0, 0.0),
        ),
        (
            "compression -2, tilt 0.1",
            Effects::ALL,
            Load::new(-2.0, 0.1, 0.0),
        ),
        (
            "alpha = (50, 30), beta 1",
            Effects::ALL,
            Load::new(50.0, 30.0, 1.0),
        ),
    ];
    println!(
        "{:<28} {:>6} {:>12} {:>12} {:>10} {:>10} {:>10}",
        "equilibrium (L/t0 = 50)", "degree", "us/equil.", "Omega_1", "err 1", "err 2", "err 3"
    );
    for (name, effects, load) in cases {
        let model = BeamModel::new(50.0, 0.3, None, effects).expect("a valid beam");
        let solver = BeamSolver::new(model, Default::default()).expect("a valid solver");
        let m0 = solver.solve(load).expect("the statics").root_moment;
        let settings = ModeSettings::frequencies(3);
        let modes = beam_modes(&model, TipBody::NONE, load, m0, &settings).expect("modes");
        let finer = ModeSettings {
            degree: Some(modes.degree + 16),
            ..settings
        };
        let reference = beam_modes(&model, TipBody::NONE, load, m0, &finer).expect("modes");
        let err: Vec<f64> = modes
            .omega
            .iter()
            .zip(&reference.omega)
            .map(|(a, b)| (a - b).abs() / b)
            .collect();
        let runs = 200;
        let start = Instant::now();
        for _ in 0..runs {
            black_box(beam_modes(&model, TipBody::NONE, load, m0, &settings).expect("modes"));
        }
        let us = start.elapsed().as_secs_f64() / runs as f64 * 1e6;
        println!(
            "{:<28} {:>6} {:>12.1} {:>12.6} {:>10.1e} {:>10.1e} {:>10.1e}",
            name, modes.degree, us, modes.omega[0], err[0], err[1], err[2]
        );
    }
    // The parallel stage (two clamped flexures, L/t0 = 50, a stage of twice a flexure's
    // mass), unloaded: the whole mechanism's first three modes.
    for (label, effects) in [("elastica", Effects::NONE), ("all effects", Effects::ALL)] {
        let beam = BeamSpec {
            length: 0.05,
            width: 0.01,
            thickness: 0.001,
            youngs_modulus: 70e9,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            allowable_stress: None,
            effects: EffectsChoice::Fixed(effects),
        };
        let flexure = |y: f64| Flexure {
            root: [0.0, y],
            angle: 0.0,
            attach: Attach::Clamped,
            beam,
        };
        let mech = Mechanism {
            flexures: vec![flexure(0.015), flexure(-0.015)],
            stage_point: [0.05, 0.0],
            drives: vec![Drive::proportional([Coordinate::Loaded(0.0); 3], 1)],
        };
        let mass = MechMass::uniform(2, 2.0, 0.1);
        let settings = ModeSettings::frequencies(3);
        let modes = mech_modes(&mech, &mass, [false; 3], None, &settings).expect("modes");
        let runs = 100;
        let start = Instant::now();
        for _ in 0..runs {
            black_box(mech_modes(&mech, &mass, [false; 3], None, &settings).expect("modes"));
        }
        let us = start.elapsed().as_secs_f64() / runs as f64 * 1e6;
        println!(
            "{:<28} {:>6} {:>12.1} {:>12.6}",
            format!("parallel stage, {label}"),
            "",
            us,
            modes.omega[0]
        );
    }
}
