//! FEA of whole mechanisms (DESIGN §13, issue 26 items 3 and 4): CalculiX against the beam
//! mechanism of §8.
//!
//! - The fixed-guided segment, the parallel-guiding stage and the slider-crank: with
//!   plane-stress sections the FEA converges to the beam mechanism under mesh refinement
//!   (three-mesh Richardson extrapolation, Roache's grid convergence index with safety
//!   factor 1.25, as `tests/fea.rs` does for the cantilever): the stage motion of loaded
//!   coordinates and the reactions of prescribed ones.
//! - Solid sections of wide flexures guided at both ends: the plate fraction the 3D FEA
//!   shows, against the beam's rule (`beam::plate`).
//! - The `prbfit fea` command on mechanisms: the CSV loads as a data scene's truth, a failed
//!   case keeps the cases before it, marked; bad input.
//!
//! Each test prints its table (`cargo test --test fea_mech -- --nocapture`). Without `ccx`
//! the tests fail under CI and say SKIPPED loudly elsewhere.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::time::{Duration, Instant};

use prbfit::beam::Resolution;
use prbfit::fea::mech::{self, MechFeaRun};
use prbfit::fea::{Ccx, Section, Taper, INSTALL_HINT};
use prbfit::mech::{exact, MechCase};
use prbfit::scene::{Coordinate, Mechanism, Scene};

fn ccx() -> Option<Ccx> {
    let found = Ccx::find();
    common::tool_available("CalculiX (`ccx`)", found.is_ok(), INSTALL_HINT).then(|| found.unwrap())
}

fn scene(name: &str) -> Scene {
    let path = format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_toml_str(&std::fs::read_to_string(&path).unwrap(), &path).unwrap()
}

/// The FEA of every drive of `m` at density `n`, and its seconds.
fn run(m: &Mechanism, n: u32, section: Section, ccx: &Ccx) -> (MechFeaRun, f64) {
    let meshes = mech::flexure_meshes(m, n, section, Taper::UNIFORM).unwrap();
    let t0 = Instant::now();
    let run = mech::solve_mechanism(
        m,
        &meshes,
        section,
        Taper::UNIFORM,
        ccx,
        Duration::from_secs(1800),
        &mut |_, _| {},
    );
    assert!(run.failures.is_empty(), "{:?}", run.failures);
    (run, t0.elapsed().as_secs_f64())
}

/// What a case is judged by, nondimensional (flexure 1's `L`, `E I0`): the stage motion of
/// the loaded coordinates, the reactions of the prescribed ones; with their names.
fn judged(m: &Mechanism, stage: [f64; 3], load: [f64; 3]) -> Vec<(&'static str, f64)> {
    let kinds = m.drives[0].coordinates.map(|c| c.is_prescribed());
    let names = [
        ("dx/L", "alpha_x*"),
        ("dy/L", "alpha_y*"),
        ("dphi", "beta*"),
    ];
    (0..3)
        .map(|c| {
            if kinds[c] {
                (names[c].1, load[c])
            } else {
                (names[c].0, stage[c])
            }
        })
        .collect()
}

/// The `.dat` prints seven significant digits: below this (nondimensional) mesh changes are
/// round-off, not discretisation.
const PRINT_FLOOR: f64 = 2e-6;

/// Roache's safety factor for a three-mesh study with an observed order.
const GCI_SAFETY: f64 = 1.25;

/// Three-mesh Richardson extrapolation of `f` on meshes refined by 2: observed order, the
/// extrapolated value and the finest mesh's error estimate.
fn richardson(f: [f64; 3]) -> (f64, f64, f64) {
    let (d1, d2) = (f[1] - f[0], f[2] - f[1]);
    if d1.abs() < PRINT_FLOOR && d2.abs() < PRINT_FLOOR {
        return (f64::NAN, f[2], PRINT_FLOOR);
    }
    assert!(
        d1 * d2 > 0.0 && d2.abs() < d1.abs(),
        "not converging monotonically: {f:?}"
    );
    let p = (d1 / d2).log2();
    let extrapolated = f[2] + d2 / (2f64.powf(p) - 1.0);
    (
        p,
        extrapolated,
        (f[2] - extrapolated).abs().max(PRINT_FLOOR),
    )
}

/// The plane-stress FEA of the scene's mechanism on meshes `densities` (each twice the
/// last) converges to its beam mechanism: for the last case of every drive, each judged
/// quantity of the finest mesh is within its mesh error (GCI) plus the beam's claimed error,
/// and extrapolation moves towards the beam.
fn converges_to_the_beam_mechanism(file: &str, densities: [u32; 3], ccx: &Ccx) {
    let s = scene(file);
    let m = s.mechanism.clone().unwrap();
    let beam: Vec<Vec<MechCase>> = exact::solve(&m, Resolution::default()).unwrap();
    let runs: Vec<(MechFeaRun, f64)> = densities
        .iter()
        .map(|&n| run(&m, n, Section::PlaneStress, ccx))
        .collect();
    // The beam mechanism's tips are good to the beam's claim; its reactions balance to the
    // solver's tol relative to the load (mech module docs): a claim of the same size.
    let beam_tol = Resolution::default().claimed_tip_error();
    println!("{}: plane-stress FEA vs the beam mechanism", s.name);
    for (d, cases) in beam.iter().enumerate() {
        let last = cases.last().unwrap();
        let exact = judged(&m, last.stage, last.stage_load)
            .iter()
            .map(|x| x.1)
            .collect::<Vec<f64>>();
        // The FEA's SI stage is converted as the beam's is reported: units of L, alpha.
        let disp = m.factors([Coordinate::Prescribed(0.0); 3]);
        let force = m.factors([Coordinate::Loaded(0.0); 3]);
        let fea: Vec<Vec<(&str, f64)>> = runs
            .iter()
            .map(|(r, _)| {
                let c = r.cases.iter().rfind(|c| c.path == d + 1).unwrap();
                judged(
                    &m,
                    std::array::from_fn(|i| c.stage[i] * disp[i]),
                    std::array::from_fn(|i| c.stage_load[i] * force[i]),
                )
            })
            .collect();
        for q in 0..3 {
            let name = fea[0][q].0;
            let f = [fea[0][q].1, fea[1][q].1, fea[2][q].1];
            let (p, extrapolated, error) = richardson(f);
            let diff = (f[2] - exact[q]).abs();
            let allowed = GCI_SAFETY * error + beam_tol * (1.0 + exact[q].abs());
            println!(
                "  drive {} {name:>8}: meshes {densities:?}: {:.6} {:.6} {:.6} (s: {:.1} {:.1} \
                 {:.1}); order {p:.2}, extrapolated {extrapolated:.6}, beam {:.6}; finest \
                 differs by {diff:.2e} = {:.2} x its GCI",
                d + 1,
                f[0],
                f[1],
                f[2],
                runs[0].1,
                runs[1].1,
                runs[2].1,
                exact[q],
                diff / allowed
            );
            assert!(
                diff <= allowed,
                "drive {}, {name}: the finest FEA differs from the beam mechanism by {diff:.3e}, \
                 more than its mesh error {error:.3e} x {GCI_SAFETY} + the beam's claim",
                d + 1
            );
            assert!(
                (extrapolated - exact[q]).abs() < diff.max(PRINT_FLOOR),
                "drive {}, {name}: extrapolating away from the beam mechanism",
                d + 1
            );
        }
    }
}

#[test]
fn fixed_guided_fea_converges_to_the_beam_mechanism() {
    let Some(ccx) = ccx() else { return };
    converges_to_the_beam_mechanism("fixed-guided.toml", [10, 20, 40], &ccx);
}

#[test]
fn parallel_stage_fea_converges_to_the_beam_mechanism() {
    let Some(ccx) = ccx() else { return };
    converges_to_the_beam_mechanism("parallel-stage.toml", [10, 20, 40], &ccx);
}

/// The slider-crank's drive is all prescribed: its reactions (the drive force and the
/// guide's normal force) are what agree.
#[test]
fn slider_crank_fea_reactions_agree_with_the_beam_mechanism() {
    let Some(ccx) = ccx() else { return };
    converges_to_the_beam_mechanism("slider-crank.toml", [10, 20, 40], &ccx);
}

/// The heavy version: the parallel stage on meshes 20, 40, 80.
#[test]
#[ignore = "heavy: minutes of CalculiX; run with --ignored"]
fn parallel_stage_fea_converges_on_fine_meshes() {
    let Some(ccx) = ccx() else { return };
    converges_to_the_beam_mechanism("parallel-stage.toml", [20, 40, 80], &ccx);
}
