//! The UI on a mechanism data scene (DESIGN §9 with §8), without a terminal: the shipped
//! slider-crank rig (`assets/scenes/slider-crank-rig.toml`, 10 measured rows of the drive's
//! reaction) opens from the command line's scene and from the open prompt; the real worker
//! judges, fits, selects and exports against the measured cases exactly as the CLI does (the
//! same fitted matrix and figures, the same beam mechanism against the data, the same
//! `[fit.truth]`); its drives are the file's rows and read-only (every key that edits a drive
//! says so and changes nothing), while a beam or flexure edit refits; a saved scene reopens
//! as the same data scene; the screen marks the data and names the file; no key panics.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use common::tui::{
    any_key, app_on, drive, edit, job_of, key, press, render, run_job, shipped, type_text,
};
use common::{json, prbfit, Scratch};
use prbfit::fit::Fidelity;
use prbfit::io::ModelFile;
use prbfit::mech::figures::compare;
use prbfit::mech::{measured, prb};
use prbfit::scene::Scene;
use prbfit::tui::app::{App, Command, EditTarget, Panel, Tone, DEBOUNCE};
use prbfit::tui::run_command;
use prbfit::tui::state::beam::BeamField;
use prbfit::tui::state::mech::{fields, MechField};
use prbfit::tui::worker::{JobKind, Worker, WorkerMsg};
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::KeyCode;
use ratatui::Terminal;

/// The shipped rig scene.
fn rig() -> PathBuf {
    shipped("slider-crank-rig.toml")
}

/// A float from a JSON object.
fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("no number `{key}` in {v}"))
}

/// Copies the rig scene (with `edit` applied to its text) and its data into `dir`; the
/// scene's path.
fn rig_copy(dir: &std::path::Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(rig()).unwrap();
    std::fs::copy(
        shipped("slider-crank-rig.csv"),
        dir.join("slider-crank-rig.csv"),
    )
    .unwrap();
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// Both ways in, and the start-up fit against the rows: the worker's fitted matrix and
/// figures are the CLI's `fit` from the same start (same seed, same fidelity: the truth is
/// the measured cases, which no resolution changes, so to the last bit); the shown model is
/// `compare` on the measured truth ([`measured::truth`]); the beam mechanism beside the data
/// is `measured::beam_against_data` at the UI's resolution to the bit, and the CLI's (solved
/// at tol 1e-9 against the UI's 1e-8) to 1e-7 of each figure.
#[test]
fn a_mechanism_data_scene_opens_and_fits_as_the_cli_does() {
    // The command line: the refusal is gone, only the terminal's is left.
    let out = prbfit(&["tui", rig().to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("needs a terminal"), "{err}");
    assert!(!err.contains("mechanism data"), "{err}");

    // The open prompt, over the built-in scene.
    let t0 = Instant::now();
    let mut app = App::new(Scene::builtin(), None);
    press(&mut app, 'o', t0);
    type_text(&mut app, rig().to_str().unwrap(), t0);
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    assert!(matches!(&cmds[..], [Command::OpenScene(_)]), "{cmds:?}");
    for cmd in cmds {
        assert!(run_command(&mut app, cmd, t0).is_none());
    }
    let (message, tone) = app.message.clone().unwrap();
    assert_eq!(tone, Tone::Info, "{message}");
    assert!(message.starts_with("opened"), "{message}");
    assert!(app.edit.is_mech_data() && !app.unsaved());
    assert_ne!(
        app.edit.focus,
        Panel::Loads,
        "a mechanism has no load panel"
    );

    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Fit, "live refit fits the opened scene");
    let start = job.matrix.clone();
    let worker = Worker::spawn().unwrap();
    let msg = run_job(&mut app, &worker, job);
    let WorkerMsg::Done { truth, report, .. } = msg else {
        panic!("{msg:?}")
    };
    let report = report.expect("a fit's report");

    let cli = json(&prbfit(&[
        "fit",
        "--scene",
        rig().to_str().unwrap(),
        "--prb",
        &start.to_text(),
        "--json",
    ]));
    assert_eq!(cli["prb"].as_str().unwrap(), report.matrix.to_text());
    // serde_json writes the shortest text that reads back as the same f64.
    for (name, ui) in [
        ("objective", report.figures.objective),
        ("max_force_err", report.figures.max_force()),
        ("rms_force_err", report.figures.rms_force_err.unwrap()),
    ] {
        assert_eq!(f(&cli, name), ui, "{name}");
    }
    assert_eq!(cli["truth"]["data"], "slider-crank-rig.csv");
    assert_eq!(cli["cases"].as_u64().unwrap() as usize, truth.case_count());

    // The truth is the measured cases, and the shown model is judged on them.
    let scene = Scene::from_file(&rig()).unwrap();
    let m = scene.mechanism.as_ref().unwrap();
    let measured = measured::truth(&scene, m, Fidelity::Normal.resolution()).unwrap();
    assert_eq!(truth.cases, measured);
    assert_eq!(truth.case_count(), 10);
    let paths = prb::solve(m, &report.matrix, prbfit::study::PRB_TOL).unwrap();
    let (w, w_f) = (scene.fit.angle_weight, scene.fit.force_weight);
    let judged = compare(&m.drives, &paths, &measured, w, w_f).unwrap();
    let shown = app.shown.model().unwrap();
    assert_eq!(shown.figures, judged.figures);
    assert_eq!(shown.figures, report.figures);

    // The beam mechanism beside the data.
    let data = truth.measured.as_ref().expect("a data scene's view");
    assert_eq!(data.file, "slider-crank-rig.csv");
    assert_eq!(data.sha256, cli["truth"]["sha256"].as_str().unwrap());
    assert_eq!(data.beam.as_ref().unwrap().len(), 1);
    let beside = truth.beam_against_data(w, w_f).unwrap().unwrap();
    let reports = measured::beam_against_data(&scene, m, Fidelity::Normal.resolution())
        .unwrap()
        .unwrap();
    assert_eq!(beside, reports.figures);
    let cli_beam = &cli["truth"]["beam_vs_data"];
    // The UI solves the beam beside the data at normal fidelity (tol 1e-8), the CLI at the
    // default 1e-9. Each force figure (a reaction error over the largest reaction) agrees to
    // 1e-7 of itself, so each case's error moves by about 1e-7 max_force (7e-9 here); J, a
    // mean of squared errors, moves by at most 2 sqrt(J) times the largest such move
    // (Cauchy-Schwarz): 2e-7 max_force sqrt(J).
    let max_force = beside.max_force();
    let rms_force = beside.rms_force_err.unwrap();
    for (name, ui, bound) in [
        ("max_force_err", max_force, 1e-7 * max_force),
        ("rms_force_err", rms_force, 1e-7 * rms_force),
        (
            "objective",
            beside.objective,
            2e-7 * max_force * beside.objective.sqrt(),
        ),
    ] {
        let c = f(cli_beam, name);
        assert!((ui - c).abs() <= bound, "{name}: UI {ui}, CLI {c}");
    }
    // The catalogue's 200 GPa against a 190 GPa rig (README): 7.4% of the largest reaction.
    assert!((beside.max_force() - 0.0744).abs() < 1e-3, "{beside:?}");
    // The beam mechanism's shapes along the measured drive, one per row.
    assert_eq!(truth.poses[0].len(), 10);

    let screen = render(&app, 120, 40);
    for needle in [
        &format!("data slider-crank-rig.csv sha256 {}", &data.sha256[..8]),
        "beam vs data: J 2.389e-3 | force 7.44% FAIL<5",
        "measured ×",
        "1 drive (data)",
        "drives read-only",
    ] {
        assert!(screen.contains(needle), "`{needle}` missing:\n{screen}");
    }
}

/// The app on the rig, on the mechanism panel, with the cursor on `field`.
fn at(field: MechField) -> App {
    common::tui::at_field(&rig(), field)
}

/// The drives are the file's rows: on every drive row, Enter (edit), `p` (prescribed /
/// loaded), `a` and `d` (add, delete a drive) say so naming the file, open no editor, change
/// nothing and queue no job; `a` and `d` on a flexure's row too (no drive to add either), and
/// a drive edit applied directly is refused.
#[test]
fn drives_are_read_only() {
    let t0 = Instant::now();
    let drive_rows = [
        MechField::Coordinate { drive: 0, c: 0 },
        MechField::Coordinate { drive: 0, c: 1 },
        MechField::Coordinate { drive: 0, c: 2 },
        MechField::Steps(0),
    ];
    for field in drive_rows {
        for k in ['\n', 'p', 'a', 'd'] {
            let mut app = at(field);
            let before = app.edit.scene.clone();
            let code = if k == '\n' {
                KeyCode::Enter
            } else {
                KeyCode::Char(k)
            };
            let cmds = app.on_key(key(code), t0);
            assert!(cmds.is_empty(), "{field:?} {k:?}: {cmds:?}");
            assert!(
                app.edit.editing.is_none(),
                "{field:?} {k:?} opened an editor"
            );
            let (message, tone) = app.message.clone().unwrap();
            assert_eq!(tone, Tone::Error, "{field:?} {k:?}: {message}");
            assert!(
                message.contains("read-only") && message.contains("slider-crank-rig.csv"),
                "{field:?} {k:?}: {message}"
            );
            assert_eq!(app.edit.scene, before, "{field:?} {k:?} changed the scene");
            assert!(app.tick(t0 + DEBOUNCE * 2).is_none(), "{k:?} queued a job");
            assert!(!app.unsaved());
        }
    }
    for k in ['a', 'd'] {
        let mut app = at(MechField::Root(0));
        let before = app.edit.scene.clone();
        press(&mut app, k, t0);
        assert!(app.message.clone().unwrap().0.contains("read-only"));
        assert_eq!(app.edit.scene, before);
    }
    let mut app = at(MechField::Steps(0));
    let before = app.edit.scene.clone();
    for (field, text) in [
        (MechField::Coordinate { drive: 0, c: 1 }, "20"),
        (MechField::Steps(0), "5"),
    ] {
        let e = app
            .edit
            .apply_edit(&EditTarget::Mech(field), text)
            .unwrap_err();
        assert!(e.contains("read-only"), "{e}");
    }
    assert_eq!(app.edit.scene, before);
}

/// A beam edit refits against the same rows (they are SI: nothing physical in them moves):
/// the flexure at 190 GPa, the rig's own modulus, is the data to their printing (the README's
/// calibrated 1.1e-5 of the largest reaction against 7.4% at 200 GPa), and the refit is the
/// CLI's fit of the scene file with that modulus. A flexure edit (its angle) is taken and
/// queues one refit with the drives untouched.
#[test]
fn beam_and_flexure_edits_refit() {
    let dir = Scratch::new("ui-mech-data-edit");
    let t0 = Instant::now();
    let mut app = app_on(&rig());
    let drives = app.edit.scene.mechanism.as_ref().unwrap().drives.clone();
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = BeamField::of(true)
        .iter()
        .position(|&f| f == BeamField::YoungsModulus)
        .unwrap();
    edit(&mut app, "190 GPa", t0);
    assert!(app.message.is_none(), "{:?}", app.message);
    assert!(app.unsaved());
    let m = app.edit.scene.mechanism.as_ref().unwrap();
    assert_eq!(m.flexures[0].beam.youngs_modulus, 190e9);
    assert_eq!(m.drives, drives, "the rows stay");
    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Fit);
    assert!(app.tick(t0 + DEBOUNCE * 3).is_none(), "one job");
    let start = job.matrix.clone();
    let worker = Worker::spawn().unwrap();
    let msg = run_job(&mut app, &worker, job);
    let WorkerMsg::Done { truth, report, .. } = msg else {
        panic!("{msg:?}")
    };
    let (w, w_f) = (
        app.edit.scene.fit.angle_weight,
        app.edit.scene.fit.force_weight,
    );
    let beside = truth.beam_against_data(w, w_f).unwrap().unwrap();
    assert!(beside.max_force() < 1e-4, "{beside:?}");

    let stiff = rig_copy(dir.path(), "rig190.toml", |t| {
        t.replace("youngs_modulus = 200e9", "youngs_modulus = 190e9")
    });
    let cli = json(&prbfit(&[
        "fit",
        "--scene",
        stiff.to_str().unwrap(),
        "--prb",
        &start.to_text(),
        "--json",
    ]));
    let report = report.unwrap();
    assert_eq!(cli["prb"].as_str().unwrap(), report.matrix.to_text());
    assert_eq!(f(&cli, "objective"), report.figures.objective);

    app.edit.focus = Panel::Mechanism;
    let m = app.edit.scene.mechanism.clone().unwrap();
    app.edit.mech_state.row = fields(&m)
        .iter()
        .position(|f| *f == MechField::Angle(0))
        .unwrap();
    let t1 = t0 + DEBOUNCE * 10;
    edit(&mut app, "1", t1);
    assert!(app.message.is_none(), "{:?}", app.message);
    let m = app.edit.scene.mechanism.as_ref().unwrap();
    assert!((m.flexures[0].angle - 1f64.to_radians()).abs() < 1e-15);
    assert_eq!(m.drives, drives, "the rows stay");
    let job = job_of(app.tick(t1 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Fit);
}

/// Saving writes `[truth] data` and no `[[drives]]`: to its own file the data's name; from
/// another folder the same data file by its absolute path; each saved file reopens as the
/// same mechanism data scene (same hash, same drives, the model), in the UI too.
#[test]
fn a_saved_mechanism_data_scene_reopens_as_the_same() {
    let root = Scratch::new("ui-mech-data-save");
    let (home, elsewhere) = (root.path().join("home"), root.path().join("elsewhere"));
    for d in [&home, &elsewhere] {
        std::fs::create_dir_all(d).unwrap();
    }
    let own = rig_copy(&home, "rig.toml", |t| t);
    let absolute = home
        .canonicalize()
        .unwrap()
        .join("slider-crank-rig.csv")
        .display()
        .to_string();
    let t0 = Instant::now();
    let mut app = app_on(&own);
    let original = app.edit.scene.clone();
    app.edit.matrix = ModelFile::load("howell-1r").unwrap().prb;
    for (path, named) in [
        (own.clone(), "slider-crank-rig.csv".to_string()),
        (elsewhere.join("moved.toml"), absolute),
        (
            root.path().join("above.toml"),
            "home/slider-crank-rig.csv".into(),
        ),
    ] {
        let again = common::tui::save_data_scene(&mut app, &path, &named, "[[drives]]", t0);
        let truth = again.truth.as_ref().unwrap();
        let was = original.truth.as_ref().unwrap();
        assert_eq!(truth.sha256, was.sha256);
        assert_eq!(truth.stage, was.stage);
        assert_eq!(again.mechanism, original.mechanism);
        assert_eq!(again.prb.as_ref(), Some(&app.edit.matrix));
        let mut other = App::new(Scene::builtin(), None);
        run_command(&mut other, Command::OpenScene(path.clone()), t0);
        assert!(other.edit.is_mech_data(), "{:?}", other.message);
        assert_eq!(other.edit.scene.mechanism, original.mechanism);
        assert_eq!(other.edit.matrix, app.edit.matrix);
    }
}

/// An export from the UI records the data as the CLI's export does: the same `[fit.truth]`
/// (file, hash, rows) and the same figures against the data.
#[test]
fn an_export_records_the_data_as_the_cli_does() {
    let dir = Scratch::new("ui-mech-data-export");
    let mut app = app_on(&rig());
    app.edit.matrix = ModelFile::load("howell-1r").unwrap().prb;
    common::tui::export_records_the_data_as_the_cli(
        &mut app,
        &rig(),
        &dir,
        "slider-crank-rig.csv",
        10,
    );
}

/// The selection runs the ladder against the rows (a published model's row is the CLI's
/// `eval` of it on the data) and the view says no trade-off is measured on data.
#[test]
fn selection_runs_on_the_data() {
    let mut app = app_on(&rig());
    let worker = Worker::spawn().unwrap();
    let job = job_of(press(&mut app, 'S', Instant::now()).into_iter().next());
    assert_eq!(job.kind, JobKind::Select);
    let msg = run_job(&mut app, &worker, job);
    let WorkerMsg::SelectDone { selection, .. } = msg else {
        panic!("{msg:?}")
    };
    let howell = selection
        .rows
        .iter()
        .find(|r| r.name == "howell-1r")
        .expect("the published models are judged");
    let eval = json(&prbfit(&[
        "eval",
        "--scene",
        rig().to_str().unwrap(),
        "--model",
        "howell-1r",
        "--json",
    ]));
    // One model: its row is the report itself.
    assert_eq!(f(&eval, "max_force_err"), howell.figures.max_force());
    assert_eq!(f(&eval, "objective"), howell.figures.objective);
    // The README: a fitted 1R meets the rig's targets.
    let chosen = app.shown.select.as_ref().unwrap().chosen.expect("a choice");
    assert_eq!(selection.rows[chosen].topology, "L-R");
    let screen = render(&app, 120, 40);
    assert!(screen.contains("none on measured data"), "{screen}");
}

/// The rig with Howell's 1R judged, as the worker computes it (deterministic: no timing).
fn judged() -> App {
    common::tui::judged_mechanism(&rig(), "howell-1r", 0.0021)
}

/// The rig on screen: the measured reactions as markers (×, one per row but the shown
/// case's, which is the cyan case dot) on the force-stroke chart with the beam mechanism in
/// grey and the legend naming the three, the measured stage point marked on the shape chart,
/// the beam mechanism's reaction error beside the PRB's, the PRB's marked at every measured
/// row (•, as a cantilever's data chart marks them), the drives read-only, the data line
/// under the figures.
#[test]
fn rig_screen_120x40() {
    let app = judged();
    let mut t = Terminal::new(TestBackend::new(120, 40)).unwrap();
    t.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    let text = format!("{}", t.backend());
    for needle in [
        "measured ×  beam ─  PRB ─",
        "measured P ×",
        "1 drive (data)",
        "drives read-only",
        "data slider-crank-rig.csv sha256 4d786bec · beam vs data:",
        "Fy reaction vs dy",
        "PRB • beam ─",
    ] {
        assert!(text.contains(needle), "`{needle}` missing:\n{text}");
    }
    // Nine rows' markers (the tenth is the shown case), the shape chart's measured stage
    // point, and the two legends.
    assert_eq!(text.matches('×').count(), 9 + 1 + 2, "{text}");
    // The markers are the data's colour.
    let buf = t.backend().buffer();
    let magenta = buf
        .content()
        .iter()
        .filter(|c| c.symbol() == "×" && c.fg == ratatui::style::Color::Magenta)
        .count();
    assert_eq!(magenta, 9 + 1 + 2);
    insta::assert_snapshot!("rig_120x40", t.backend());
}

#[test]
fn rig_screen_80x24() {
    let mut app = judged();
    // The third case of the drive, from the chart keys.
    app.edit.mech_state.case = Some(2);
    let mut t = Terminal::new(TestBackend::new(80, 24)).unwrap();
    t.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    insta::assert_snapshot!("rig_80x24", t.backend());
}

/// A beam mechanism that cannot follow the measured drives is no failure: the PRB is judged
/// on the rows, the data line says why the beam has no figures, the shape chart draws the
/// PRB and the measured point, and every size draws.
#[test]
fn a_beam_that_cannot_follow_the_data_draws() {
    let mut app = judged();
    let result = app.shown.result.as_mut().unwrap();
    let mut view = (*result.truth).clone();
    let m = view.measured.as_mut().unwrap();
    m.beam = Err("the beam mechanism along the measured drives: no equilibrium".into());
    view.poses = vec![Vec::new()];
    result.truth = Arc::new(view);
    for (w, h) in [(120, 40), (80, 24), (60, 20), (30, 10)] {
        let screen = render(&app, w, h);
        if w == 120 {
            assert!(
                screen.contains("beam vs data: none: the beam mechanism along"),
                "{screen}"
            );
            assert!(screen.contains("measured P ×"), "{screen}");
            assert!(
                !screen.contains("beam ─"),
                "no beam in the legends: {screen}"
            );
        }
    }
}

mod no_panics {
    use super::*;
    use proptest::prelude::*;

    /// The mechanism panel's own keys, and what its fields take, drawn more often.
    const MECH_KEYS: &[char] = &['p', 'a', 'd', '<', '>', '[', ']', 'F', '0', '5', '-', ','];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]

        /// Any key sequence on the rig with its results on screen, drawn at any size, never
        /// panics, never changes the drives or the data (only a beam or flexure edit can
        /// change the scene) and leaves a scene that writes and reads back as a data scene.
        #[test]
        fn no_input_sequence_panics_on_mechanism_data(
            keys in proptest::collection::vec(any_key(&[], MECH_KEYS, true), 1..80),
            w in 1u16..140, h in 1u16..50,
        ) {
            let mut app = judged();
            let (drives, truth) = (
                app.edit.scene.mechanism.as_ref().unwrap().drives.clone(),
                app.edit.scene.truth.clone(),
            );
            drive(&mut app, &keys, w, h);
            prop_assert_eq!(&app.edit.scene.mechanism.as_ref().unwrap().drives, &drives);
            prop_assert_eq!(&app.edit.scene.truth, &truth);
            let again = Scene::from_toml_str(&app.edit.scene.to_toml(), "check");
            prop_assert!(again.is_ok(), "{:?}", again);
            prop_assert!(again.unwrap().truth.is_some());
        }
    }
}
