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

use common::{assert_input_error, json, prbfit, Scratch};
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
    converges(&scene(file), densities, ccx);
}

fn converges(s: &Scene, densities: [u32; 3], ccx: &Ccx) {
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

/// A pin: the fixed-fixed segment of `fixed-guided.toml` with its tip pinned to the guide
/// (`attach = "pinned"`: the guide holds the tip's position, not its angle; the guide itself
/// does not turn), pushed sideways: the guide's force converges to the beam mechanism's,
/// and its moment about the pin is zero.
#[test]
fn a_pinned_tip_fea_converges_to_the_beam_mechanism() {
    let Some(ccx) = ccx() else { return };
    let text = std::fs::read_to_string(asset("fixed-guided.toml"))
        .unwrap()
        .replace("attach = \"clamped\"", "attach = \"pinned\"");
    assert!(text.contains("pinned"));
    let s = Scene::from_toml_str(&text, "fixed-pinned").unwrap();
    converges(&s, [10, 20, 40], &ccx);
}

/// The heavy version: the parallel stage on meshes 20, 40, 80.
#[test]
#[ignore = "heavy: minutes of CalculiX; run with --ignored"]
fn parallel_stage_fea_converges_on_fine_meshes() {
    let Some(ccx) = ccx() else { return };
    converges_to_the_beam_mechanism("parallel-stage.toml", [20, 40, 80], &ccx);
}

/// A parallel-guiding stage of two steel flexures `b` wide, 1 mm thick and `b / ratio` long
/// (`b / t = width_over_thickness`, `b / L = width_over_length`), Poisson's ratio `nu`,
/// pushed sideways by a small force (`alpha_y = 0.2` over the pair: linear, so the
/// anticlastic curl of large curvature plays no part and the plate fraction is the ends').
fn guided_pair(width_over_thickness: f64, width_over_length: f64, nu: f64) -> Mechanism {
    let t = 0.001;
    let b = width_over_thickness * t;
    let l = b / width_over_length;
    let e = 200e9;
    let fy = 0.2 * e * b * t.powi(3) / 12.0 / (l * l);
    let text = format!(
        "name = \"guided pair b/t {width_over_thickness} b/L {width_over_length} nu {nu}\"\n\
         [beam]\nlength = {l}\nwidth = {b}\nthickness = {t}\nyoungs_modulus = {e}\n\
         poisson_ratio = {nu}\neffects = [\"shear\", \"extension\", \"poisson\"]\n\
         [[flexures]]\nroot = [0.0, {l}]\nattach = \"clamped\"\n\
         [[flexures]]\nroot = [0.0, -{l}]\nattach = \"clamped\"\n\
         [stage]\npoint = [{l}, 0.0]\n[[drives]]\nfy = {fy}\nsteps = 1\n"
    );
    Scene::from_toml_str(&text, "guided pair")
        .unwrap()
        .mechanism
        .unwrap()
}

/// The plate fraction of a guided flexure pair measured by 3D FEA: the solid model's stage
/// deflection against the plane-stress model's on the same bricks along and through (their
/// mesh errors, nearly alike, cancel in the ratio), the stiffening put on the bending
/// compliance alone (the beam mechanism gives its share, with and without shear):
/// `phi = (1 - dy_solid / dy_plane_stress) / (nu^2 bending share)`.
fn guided_plate_fraction(m: &Mechanism, n: u32, ccx: &Ccx) -> (f64, f64) {
    let dy = |section| {
        let (r, s) = run(m, n, section, ccx);
        (r.cases[0].stage[1], s)
    };
    let (solid, s1) = dy(Section::Solid);
    let (plane, s2) = dy(Section::PlaneStress);
    let beam_dy = |shear: bool| {
        let mut m = m.clone();
        for f in &mut m.flexures {
            let mut e = f.beam.effects.resolve();
            e.shear = shear;
            f.beam.effects = prbfit::scene::EffectsChoice::Fixed(e);
        }
        exact::solve(&m, Resolution::default()).unwrap()[0][0].stage[1]
    };
    let bending_share = beam_dy(false) / beam_dy(true);
    let nu = m.flexures[0].beam.poisson_ratio;
    ((1.0 - solid / plane) / (nu * nu * bending_share), s1 + s2)
}

/// The sweep behind `beam::plate`'s guided rule: prints the measured plate fractions of
/// guided pairs of several widths and lengths beside the cantilever's rule and the guided
/// one.
#[test]
#[ignore = "heavy: minutes of 3D CalculiX; run with --ignored"]
fn guided_flexure_plate_fraction_sweep() {
    let Some(ccx) = ccx() else { return };
    use prbfit::beam::plate::{ends_fraction, guided_ends_fraction};
    println!(
        "{:>6} {:>6} {:>5} {:>4} | {:>8} | {:>10} {:>10} | {:>6}",
        "b/t", "b/L", "nu", "n", "measured", "cantilever", "guided", "s"
    );
    // The densities of `beam::plate`'s table (its coarser meshes: 20 and 40, 40, 30).
    for (b_t, b_l, nu, n) in [
        (10.0, 0.25, 0.3, 80),
        (10.0, 0.5, 0.3, 40),
        (10.0, 2.0 / 3.0, 0.49, 60),
        (10.0, 1.0, 0.3, 30),
        (30.0, 0.25, 0.3, 80),
        (30.0, 2.0, 0.3, 30),
        (10.0 / 3.0, 0.8333, 0.3, 24),
    ] {
        let m = guided_pair(b_t, b_l, nu);
        let (phi, seconds) = guided_plate_fraction(&m, n, &ccx);
        println!(
            "{b_t:>6.2} {b_l:>6.3} {nu:>5.2} {n:>4} | {phi:>8.3} | {:>10.3} {:>10.3} | {seconds:>6.1}",
            ends_fraction(b_l, b_t),
            guided_ends_fraction(b_l, b_t),
        );
    }
}

fn asset(name: &str) -> String {
    format!("{}/assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `prbfit fea` on the fixed-guided segment: the CSV is DESIGN §9's mechanism CSV, and a
/// data scene naming it as its truth loads and calibrates to the nominal modulus within the
/// mesh's error (the reactions at density 20 are 0.8 % above the beam mechanism's,
/// `fixed_guided_fea_converges_to_the_beam_mechanism`).
#[test]
fn fea_of_a_mechanism_is_a_data_scene_truth() {
    let Some(_) = ccx() else { return };
    let dir = Scratch::new("fea-mech-cli");
    let out = dir.file("fea.csv");
    let report = json(&prbfit(&[
        "fea",
        "--scene",
        &asset("fixed-guided.toml"),
        "-o",
        &out,
        "--mesh",
        "20",
        "--json",
    ]));
    assert_eq!(report["meshes"][0]["along"], 20);
    assert!(report["failures"].as_array().unwrap().is_empty());
    // Like with like: the section follows the scene's flexures (solid when the beam
    // mechanism beside it keeps plane strain), and says so.
    let keeps = report["beam_effects"]
        .as_array()
        .unwrap()
        .iter()
        .any(|e| e == "plane_strain");
    assert_eq!(report["section_from"], "scene");
    assert_eq!(
        report["section"],
        if keeps { "solid" } else { "plane-stress" },
        "{report}"
    );
    // A section given: the beam mechanism beside it takes that section's plane strain.
    let given = json(&prbfit(&[
        "fea",
        "--scene",
        &asset("fixed-guided.toml"),
        "-o",
        &dir.file("given.csv"),
        "--mesh",
        "8",
        "--section",
        "plane-stress",
        "--json",
    ]));
    assert_eq!(given["section_from"], "flag");
    assert!(!given["beam_effects"]
        .as_array()
        .unwrap()
        .iter()
        .any(|e| e == "plane_strain"));
    assert!(given["like_with_like"]
        .as_str()
        .unwrap()
        .starts_with("--section plane-stress"));
    let csv = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "path,fx,dy,dphi,stage_dx,stage_dy,stage_dphi,stage_fx,stage_fy,stage_mz"
    );
    assert_eq!(lines.len(), 1 + 6, "{csv}");
    assert!(std::fs::read_to_string(dir.file("fea.inp"))
        .unwrap()
        .contains("*RIGID BODY, NSET=NSTAGEBODY"));
    // A data scene's drives are its file's rows: the scene without its [[drives]].
    let scene = std::fs::read_to_string(asset("fixed-guided.toml")).unwrap();
    let scene = scene.split("[[drives]]").next().unwrap().to_string()
        + &scene
            .split("[accuracy]")
            .nth(1)
            .map(|r| format!("[accuracy]{r}"))
            .unwrap();
    let data = dir.write(
        "data.toml",
        &format!("{scene}\n[truth]\ndata = \"fea.csv\"\n"),
    );
    let c = json(&prbfit(&["calibrate", "--scene", &data, "--json"]));
    let ratio = c["ratio"].as_f64().unwrap();
    assert!((ratio - 1.0).abs() < 0.02, "{c}");
}

/// A case CalculiX cannot converge: the slider-crank pushed by a force through its toggle
/// (the beam mechanism jumps from 0.32 L to 0.91 L between the first two cases). The first
/// case is kept, the file marked, the exit status 1 with the case and ccx's message.
#[test]
fn a_failed_case_keeps_the_cases_before_it_marked() {
    let Some(_) = ccx() else { return };
    let dir = Scratch::new("fea-mech-fail");
    let text = std::fs::read_to_string(asset("slider-crank.toml"))
        .unwrap()
        .replace("dy = 0.015 ", "fy = 20.0 ")
        .replace("steps = 10", "steps = 4");
    assert!(text.contains("fy = 20.0"));
    let scene = dir.write("pushed.toml", &text);
    let out = dir.file("fea.csv");
    let run = prbfit(&["fea", "--scene", &scene, "-o", &out, "--mesh", "8"]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("case 2 of 4"), "{err}");
    assert!(err.contains("ccx"), "{err}");
    let csv = std::fs::read_to_string(&out).unwrap();
    assert!(
        csv.starts_with("# INCOMPLETE: drive path 1 stopped at case 2 of 4"),
        "{csv}"
    );
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    assert!(rows[1].starts_with("1,0e0,5e0,0e0,"), "{csv}");
}

/// Bad input, exit 2 naming the key: drives that prescribe different coordinates (one CSV
/// names each coordinate's kind once).
#[test]
fn mechanism_fea_refuses_drives_of_different_kinds() {
    let dir = Scratch::new("fea-mech-bad");
    let text = std::fs::read_to_string(asset("parallel-stage.toml"))
        .unwrap()
        .replace("fx = 10.0\nfy = 20.0", "fx = 10.0\ndy = 0.002");
    assert!(text.contains("dy = 0.002"));
    let scene = dir.write("mixed.toml", &text);
    let out = dir.file("fea.csv");
    assert_input_error(
        &prbfit(&["fea", "--scene", &scene, "-o", &out]),
        &["drives[2]", "prescribes other stage coordinates"],
    );
    assert!(!std::path::Path::new(&out).exists());
}

/// Solid sections of a wide-flexure stage give the 3D truth, and the beam mechanism with the
/// plane-strain effect follows it: a parallel stage of steel flexures ten thicknesses wide
/// and four widths long, pushed sideways a little. The 3D FEA is stiffer than the
/// plane-stress FEA on the same bricks along and through by the plate stiffening; the beam
/// mechanism with plane strain (the guided rule of `beam::plate`) must stiffen by the same
/// ratio within the 1 % stiffness gap the rule is fitted to (the ratio of two FEA runs on
/// the same mesh cancels most of the mesh's error, which is 0.4 % of the deflection here,
/// `parallel_stage_fea_converges_to_the_beam_mechanism`), where the narrow beam misses it by
/// 3-4 % and the cantilever's ends rule by 2-3 %. (On this mesh the 3D fraction is 0.46;
/// at density 80, 0.43: `beam::plate`'s table.)
#[test]
fn a_wide_flexure_stage_in_solid_sections_meets_the_plane_strain_beam() {
    let Some(ccx) = ccx() else { return };
    let m = guided_pair(10.0, 0.25, 0.3);
    let dy = |section| run(&m, 40, section, &ccx).0.cases[0].stage[1];
    let fea_ratio = dy(Section::Solid) / dy(Section::PlaneStress);
    let beam_dy = |plane_strain: bool| {
        let mut m = m.clone();
        for f in &mut m.flexures {
            let e = f.beam.effects.resolve().with_plane_strain(plane_strain);
            f.beam.effects = prbfit::scene::EffectsChoice::Fixed(e);
        }
        exact::solve(&m, Resolution::default()).unwrap()[0][0].stage[1]
    };
    let beam_ratio = beam_dy(true) / beam_dy(false);
    let gap = (beam_ratio / fea_ratio - 1.0).abs();
    println!(
        "guided pair b/t 10, b/L 0.25: deflection solid / plane stress: FEA {fea_ratio:.5}, \
         beam mechanism (guided plate rule) {beam_ratio:.5}: stiffness gap {:.2} %",
        gap * 100.0
    );
    assert!(gap < 0.01, "{gap}");
    // The narrow beam would be off by the whole stiffening.
    assert!((1.0 / fea_ratio - 1.0) > 0.02, "{fea_ratio}");
}

/// A mechanism's FEA stops when cancelled, as a cantilever's does: the drive after the cancel
/// is not run (its `ccx` is killed at once) and no CSV is written.
#[test]
fn a_cancelled_mechanism_fea_writes_no_csv() {
    if ccx().is_none() {
        return;
    }
    let stage = scene("parallel-stage.toml");
    assert!(stage.mechanism.as_ref().unwrap().drives.len() >= 2);
    let dir = Scratch::new("fea-mech-cancel");
    let output = dir.file("stage.csv");
    let (reported, paths_done) = common::fea_cancelled_after_its_first_path(&output, |a, ctl| {
        prbfit::report::fea_mech::fea_mechanism(&stage, a, ctl)
    });
    assert!(!reported, "a cancelled FEA reported a result");
    assert_eq!(paths_done, 1, "the drives after the cancel were run");
    assert!(
        !std::path::Path::new(&output).exists(),
        "a cancelled FEA wrote its CSV"
    );
}
