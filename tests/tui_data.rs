//! The UI on data scenes (DESIGN §9, issue 14.3), without a terminal: a data scene opens
//! (from the command line's scene and from the open prompt), the real worker judges and fits
//! against its rows exactly as the CLI does (same figures, same fitted matrix, the same beam
//! against the data), its loads are read-only, a beam edit converts its SI rows again as
//! reading the file with the edited beam would and reruns, a saved data scene reopens as the
//! same data scene, an export records the data as the CLI's does, and nothing panics: a path
//! of one row, a beam that cannot reach the data, a mechanism scene and back, any keys.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use common::tui::{any_key, app_on, drive, edit, job_of, key, press, render, run_job, shipped};
use common::{json, prbfit, Scratch};
use prbfit::eval::{beam_against_data, evaluate, Baseline};
use prbfit::fit::Fidelity;
use prbfit::io::ModelFile;
use prbfit::scene::Scene;
use prbfit::study::{Sampling, Study};
use prbfit::tui::app::{Activity, App, Command, EditTarget, Panel, Tone, DEBOUNCE};
use prbfit::tui::run_command;
use prbfit::tui::state::beam::BeamField;
use prbfit::tui::worker::{JobKind, Worker, WorkerMsg};
use ratatui::crossterm::event::KeyCode;

/// Per case, the position and angle errors of judged cases (path by path).
fn errors(cases: &[Vec<prbfit::mech::figures::JudgedCase>]) -> Vec<(f64, f64)> {
    cases
        .iter()
        .flatten()
        .map(|c| (c.pos_err, c.ang_err))
        .collect()
}

/// Per case, the position and angle errors of `eval`'s cases.
fn errors_of(cases: &[prbfit::eval::CaseError]) -> Vec<(f64, f64)> {
    cases.iter().map(|c| (c.pos_err, c.ang_err)).collect()
}

/// The shipped data scene: the wide steel strip's 3D FEA (8 rows in 2 paths, SI).
fn strip() -> PathBuf {
    shipped("wide-strip-fea.toml")
}

/// Both ways in: `prbfit tui SCENE` (the CLI no longer refuses it) and the open prompt. The
/// start-up fit runs against the rows: the worker's fitted matrix and figures are the CLI's
/// `fit` (same start, same seed, same fidelity), its view of the PRB is `eval::evaluate` on
/// the data, and the beam beside the data is `eval::beam_against_data`, to the last bit (the
/// same solves on the same loads).
#[test]
fn a_data_scene_opens_and_fits_against_its_rows_as_the_cli_does() {
    // The command line: the UI starts (it needs a terminal, which a test has not: the
    // refusal of data scenes is gone, the terminal's is what is left).
    let out = prbfit(&["tui", strip().to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("needs a terminal"), "{err}");
    assert!(!err.contains("data scene"), "{err}");
    // `--scene FILE`, as every other command takes the scene (it was an unknown argument):
    // the file is read (a missing one is named), then the terminal is what is missing.
    let out = prbfit(&["tui", "--scene", strip().to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("needs a terminal"), "{err}");
    let out = prbfit(&["tui", "--scene", "no-such-scene.toml"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no-such-scene.toml"), "{err}");
    assert_eq!(out.status.code(), Some(2));

    // The open prompt, over the built-in scene.
    let t0 = Instant::now();
    let mut app = App::new(Scene::builtin(), None);
    press(&mut app, 'o', t0);
    for c in strip().to_str().unwrap().chars() {
        press(&mut app, c, t0);
    }
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    assert!(matches!(&cmds[..], [Command::OpenScene(_)]), "{cmds:?}");
    for cmd in cmds {
        assert!(run_command(&mut app, cmd, t0).is_none());
    }
    let (message, tone) = app.message.clone().unwrap();
    assert_eq!(tone, Tone::Info, "{message}");
    assert!(message.starts_with("opened"), "{message}");
    assert!(app.edit.is_data() && !app.unsaved());
    assert_eq!(app.edit.load_rows(), 8);

    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Fit, "live refit fits the opened scene");
    let start = job.matrix.clone();
    let worker = Worker::spawn().unwrap();
    let msg = run_job(&mut app, &worker, job);
    let WorkerMsg::Done { truth, report, .. } = msg else {
        panic!("{msg:?}")
    };
    let report = report.expect("a fit's report");

    // The CLI's fit from the same start.
    let cli = json(&prbfit(&[
        "fit",
        "--scene",
        strip().to_str().unwrap(),
        "--prb",
        &start.to_text(),
        "--json",
    ]));
    assert_eq!(cli["prb"].as_str().unwrap(), report.matrix.to_text());
    // serde_json writes the shortest text that reads back as the same f64.
    assert_eq!(cli["objective"].as_f64().unwrap(), report.figures.objective);
    assert_eq!(cli["truth"]["data"].as_str().unwrap(), "wide-strip-fea.csv");

    // The shown model is judged on the data.
    let scene = Scene::from_file(&strip()).unwrap();
    let data = Baseline::from_data(scene.beam.model(), scene.truth.as_ref().unwrap());
    let judged = evaluate(&report.matrix, &data, scene.fit.angle_weight).unwrap();
    let model = app.shown.model().unwrap();
    assert_eq!(model.figures, judged.figures);
    assert_eq!(errors(&model.cases), errors_of(&judged.cases));

    // The beam beside the data: the reports' "beam vs data".
    let measured = truth.measured.as_ref().expect("a data scene's view");
    assert_eq!(measured.sha256, scene.truth.as_ref().unwrap().sha256);
    assert_eq!(truth.case_count(), 8);
    let beam = measured
        .beam
        .as_ref()
        .expect("the strip's beam reaches every row");
    let shapes: Vec<_> = truth.poses.iter().flatten().collect();
    assert_eq!(shapes.len(), 8);
    assert!(shapes.iter().all(|s| s.flexures[0].len() > 2));
    let reports = beam_against_data(&scene, Fidelity::Normal.resolution())
        .unwrap()
        .unwrap();
    assert_eq!(errors(beam), errors_of(&reports.cases));
    let (w, w_f) = (scene.fit.angle_weight, scene.fit.force_weight);
    let figures = truth.beam_against_data(w, w_f).unwrap().unwrap();
    assert_eq!(figures, reports.figures);
    // The uniform beam is 2.6% L from this strip (README): far outside the FEA's own error.
    assert!(reports.figures.max_pos_err > 0.02, "{:?}", reports.figures);

    let screen = render(&app, 120, 40);
    assert!(
        screen.contains("data wide-strip-fea.csv sha256 "),
        "{screen}"
    );
    assert!(screen.contains("measured ×"), "{screen}");
    assert!(screen.contains("Data rows (read-only)"), "{screen}");
}

/// The loads of a data scene are its rows: Enter, a and d on the load panel change nothing
/// and say why; the cursor moves over the rows and `[ ]` jump between paths, the shape chart
/// following; `H` says what a beam edit keeps.
#[test]
fn loads_are_the_rows_and_read_only() {
    let t0 = Instant::now();
    let mut app = app_on(&strip());
    app.edit.focus = Panel::Loads;
    let before = app.edit.scene.clone();
    for k in [KeyCode::Enter, KeyCode::Char('a'), KeyCode::Char('d')] {
        let cmds = app.on_key(key(k), t0);
        assert!(cmds.is_empty(), "{k:?}: {cmds:?}");
        assert!(app.edit.editing.is_none(), "{k:?} opened an editor");
        let (message, tone) = app.message.clone().unwrap();
        assert_eq!(tone, Tone::Error, "{k:?}: {message}");
        assert!(
            message.contains("read-only") && message.contains("wide-strip-fea.csv"),
            "{k:?}: {message}"
        );
        assert_eq!(app.edit.scene, before, "{k:?} changed the scene");
        assert!(app.tick(t0 + DEBOUNCE * 2).is_none(), "{k:?} queued a job");
        assert!(!app.unsaved());
    }
    let cell = EditTarget::Load { row: 0, col: 1 };
    assert!(app.edit.apply_edit(&cell, "3").is_err());
    assert_eq!(app.edit.scene, before);

    // Rows 1-4 are path 1 (Fy), 5-8 path 2 (Mz).
    assert_eq!(app.edit.shown_path(), 0);
    for _ in 0..4 {
        app.on_key(key(KeyCode::Down), t0);
    }
    assert_eq!((app.edit.loads_state.row, app.edit.shown_path()), (4, 1));
    for _ in 0..10 {
        app.on_key(key(KeyCode::Down), t0);
    }
    assert_eq!(
        app.edit.loads_state.row, 7,
        "the cursor stops at the last row"
    );
    press(&mut app, ']', t0);
    assert_eq!(
        (app.edit.loads_state.row, app.edit.shown_path()),
        (0, 0),
        "wraps"
    );
    press(&mut app, '[', t0);
    assert_eq!((app.edit.loads_state.row, app.edit.shown_path()), (4, 1));

    press(&mut app, 'H', t0);
    let (message, _) = app.message.clone().unwrap();
    assert!(message.contains("N, N m"), "{message}");
    assert_eq!(app.edit.scene, before);
}

/// Copies the shipped strip scene and its data into `dir`, with `edit` applied to the
/// scene's text; the scene's path.
fn strip_copy(dir: &Scratch, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(strip()).unwrap();
    let csv = std::fs::read_to_string(shipped("wide-strip-fea.csv")).unwrap();
    dir.write("wide-strip-fea.csv", &csv);
    PathBuf::from(dir.write(name, &edit(text)))
}

/// A beam edit of a data scene changes the nominal beam the SI rows are converted with:
/// the rows sent to the worker are the rows a scene file with that beam reads (to rounding:
/// a rescale against a conversion, a few ulps), and the worker's beam beside the data is
/// the reports' for that file. The edit reruns (one job), and the beam's error moves: a
/// stiffer E is closer to this strip (README: calibrated E = 1.054 x nominal).
#[test]
fn a_beam_edit_converts_the_rows_again_and_reruns() {
    let dir = Scratch::new("ui-data-edit");
    let t0 = Instant::now();
    let mut app = app_on(&strip());
    let worker = Worker::spawn().unwrap();
    let first = {
        let job = job_of(Some(app.submit(false)));
        run_job(&mut app, &worker, job)
    };
    let WorkerMsg::Done { truth, .. } = first else {
        panic!("{first:?}")
    };
    let (w, w_f) = (
        app.edit.scene.fit.angle_weight,
        app.edit.scene.fit.force_weight,
    );
    let nominal = truth.beam_against_data(w, w_f).unwrap().unwrap();

    app.edit.focus = Panel::Beam;
    let row = BeamField::of(false)
        .iter()
        .position(|&f| f == BeamField::YoungsModulus)
        .unwrap();
    app.edit.beam_state.row = row;
    edit(&mut app, "210.8 GPa", t0);
    assert!(app.message.is_none(), "{:?}", app.message);
    assert_eq!(app.edit.scene.beam.youngs_modulus, 210.8e9);
    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert!(app.tick(t0 + DEBOUNCE * 3).is_none(), "one job");

    let reread = Scene::from_file(&strip_copy(&dir, "stiffer.toml", |t| {
        t.replace("youngs_modulus = 200e9", "youngs_modulus = 210.8e9")
    }))
    .unwrap();
    assert_eq!(reread.beam, app.edit.scene.beam);
    let (sent, read) = (
        job.scene.truth.as_ref().unwrap(),
        reread.truth.as_ref().unwrap(),
    );
    assert_eq!(sent.sha256, read.sha256);
    let rows = |t: &prbfit::scene::data::DataTruth| -> Vec<prbfit::scene::data::MeasuredRow> {
        t.paths.iter().flat_map(|p| p.rows.clone()).collect()
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * a.abs().max(b.abs());
    for (s, r) in rows(sent).iter().zip(rows(read).iter()) {
        assert_eq!(s.line, r.line);
        for (x, y) in [
            (s.load.alpha_x, r.load.alpha_x),
            (s.load.alpha_y, r.load.alpha_y),
            (s.load.beta, r.load.beta),
            (s.tip.a, r.tip.a),
            (s.tip.b, r.tip.b),
            (s.tip.phi, r.tip.phi),
        ] {
            assert!(close(x, y), "line {}: {x} against {y}", s.line);
        }
    }
    // A stiffer beam: the same newtons are smaller alphas.
    assert!(
        rows(sent)[3].load.alpha_y
            < rows(&app_on(&strip()).edit.scene.truth.unwrap())[3]
                .load
                .alpha_y
    );
    for (s, r) in job.scene.loads.iter().zip(&reread.loads) {
        assert_eq!(s.steps, r.steps);
        assert!(close(s.end.alpha_y, r.end.alpha_y) && close(s.end.beta, r.end.beta));
    }

    let done = run_job(&mut app, &worker, job);
    let WorkerMsg::Done { truth, .. } = done else {
        panic!("{done:?}")
    };
    let reports = beam_against_data(&reread, Fidelity::Normal.resolution())
        .unwrap()
        .unwrap();
    // The loads differ from the file's conversion by a few ulps: the tips by as little.
    let (e, r) = (
        truth.beam_against_data(w, w_f).unwrap().unwrap(),
        reports.figures,
    );
    assert!((e.max_pos_err - r.max_pos_err).abs() < 1e-12, "{e:?} {r:?}");
    assert!((e.max_ang_err - r.max_ang_err).abs() < 1e-12, "{e:?} {r:?}");
    assert!(
        e.max_pos_err < 0.5 * nominal.max_pos_err,
        "the calibrated E brings the beam closer: {e:?} against {nominal:?}"
    );
}

/// Saving keeps `[truth] data`: to its own file the text is the scene's; from another
/// folder it names the same data file, relative when the data is under the new folder, else
/// by its absolute path; each saved file reopens as the same data scene (same hash, same
/// rows) with the model, in the UI too.
#[test]
fn a_saved_data_scene_reopens_as_the_same_data_scene() {
    let root = Scratch::new("ui-data-save");
    let (home, elsewhere) = (root.path().join("home"), root.path().join("elsewhere"));
    let sub = home.join("sub");
    for d in [&home, &elsewhere, &sub] {
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::copy(
        shipped("wide-strip-fea.csv"),
        home.join("wide-strip-fea.csv"),
    )
    .unwrap();
    let own = home.join("strip.toml");
    std::fs::copy(strip(), &own).unwrap();
    let absolute = home
        .canonicalize()
        .unwrap()
        .join("wide-strip-fea.csv")
        .display()
        .to_string();
    let t0 = Instant::now();
    let mut app = app_on(&own);
    let original = app.edit.scene.truth.clone().unwrap();
    app.edit.matrix = ModelFile::load("chen-3r").unwrap().prb;
    // In order: each save starts from where the one before left the scene.
    let targets = [
        (own.clone(), "wide-strip-fea.csv".to_string()),
        (elsewhere.join("moved.toml"), absolute.clone()),
        (
            root.path().join("above.toml"),
            "home/wide-strip-fea.csv".into(),
        ),
        (sub.join("below.toml"), absolute),
    ];
    for (path, named) in targets {
        let again = common::tui::save_data_scene(&mut app, &path, &named, "[[loads]]", t0);
        let truth = again.truth.as_ref().unwrap();
        assert_eq!(truth.sha256, original.sha256);
        assert_eq!(truth.paths, original.paths);
        assert_eq!(again.prb.as_ref(), Some(&app.edit.matrix));
        assert_eq!(app.edit.scene.truth.as_ref().unwrap().file, named);
        let mut other = App::new(Scene::builtin(), None);
        run_command(&mut other, Command::OpenScene(path.clone()), t0);
        assert_eq!(
            other.edit.scene.truth.as_ref().unwrap().paths,
            original.paths
        );
        assert_eq!(other.edit.matrix, app.edit.matrix);
    }
}

/// An export from the UI records the data it was fitted to, as the CLI's export does: the
/// same `[fit.truth]` (file, hash, rows) and the same figures against the data.
#[test]
fn an_export_records_the_data_as_the_cli_does() {
    let dir = Scratch::new("ui-data-export");
    let mut app = app_on(&strip());
    app.edit.matrix = ModelFile::load("su-3r").unwrap().prb;
    common::tui::export_records_the_data_as_the_cli(
        &mut app,
        &strip(),
        &dir,
        "wide-strip-fea.csv",
        8,
    );
}

/// The selection on a data scene runs the ladder against the rows (a published row's
/// figures are `evaluate` on the data) and measures no trade-off (the CLI refuses
/// `tradeoff` on data for the same reason: no beam resolution or load sampling), and the
/// view says so.
#[test]
fn selection_on_data_has_no_tradeoff() {
    let mut app = app_on(&strip());
    let worker = Worker::spawn().unwrap();
    let job = job_of(press(&mut app, 'S', Instant::now()).into_iter().next());
    assert_eq!(job.kind, JobKind::Select);
    let msg = run_job(&mut app, &worker, job);
    let WorkerMsg::SelectDone {
        selection, knobs, ..
    } = msg
    else {
        panic!("{msg:?}")
    };
    assert!(knobs.is_empty(), "{knobs:?}");
    let scene = Scene::from_file(&strip()).unwrap();
    let data = Baseline::from_data(scene.beam.model(), scene.truth.as_ref().unwrap());
    let su = selection
        .rows
        .iter()
        .find(|r| r.name == "su-3r")
        .expect("the published 3R models are judged");
    assert_eq!(
        su.figures,
        evaluate(&su.prb, &data, scene.fit.angle_weight)
            .unwrap()
            .figures
    );
    let screen = render(&app, 120, 40);
    assert!(screen.contains("none on measured data"), "{screen}");
}

/// A data file with a path of one row, and a row the beam cannot reach within its effort
/// budget (alpha_y = 1e9 from rest: the solver gives up near 4e8), which the PRB follows
/// row by row (its links just line up with the force), and a path of one row at rest: the
/// PRB is judged on the rows, the beam beside the data is absent and says why, every size
/// draws, and the beam can still be edited.
#[test]
fn one_row_paths_and_a_beam_that_cannot_reach_the_data() {
    let dir = Scratch::new("ui-data-edge");
    dir.write(
        "edge.csv",
        "path,alpha_x,alpha_y,beta,a,b,phi\n\
         1,0,1,0,0.95,0.3,0.5\n\
         2,0,1,0,0.95,0.3,0.5\n\
         2,0,1e3,0,0.1,0.95,1.5\n\
         2,0,1e6,0,0.01,1,1.57\n\
         2,0,1e9,0,0,1,1.57\n\
         3,0,0,0,1,0,0\n",
    );
    let scene = dir.write(
        "edge.toml",
        "name = \"edge\"\n[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\n\
         youngs_modulus = 200e9\npoisson_ratio = 0.3\neffects = []\n\
         [truth]\ndata = \"edge.csv\"\n",
    );
    let mut app = app_on(Path::new(&scene));
    assert_eq!(app.edit.load_rows(), 6);
    let worker = Worker::spawn().unwrap();
    let msg = {
        let job = job_of(Some(app.submit(false)));
        run_job(&mut app, &worker, job)
    };
    let WorkerMsg::Done { truth, .. } = msg else {
        panic!("{msg:?}")
    };
    let why = truth.measured.as_ref().unwrap().beam.clone().unwrap_err();
    assert!(why.contains("line 6 of edge.csv"), "{why}");
    assert_eq!(app.shown.model().unwrap().case_count(), 6);
    for (w, h) in [(120, 40), (80, 24), (60, 20), (30, 10)] {
        let screen = render(&app, w, h);
        if w == 120 {
            println!("{screen}");
            assert!(
                screen.contains("beam vs data: none: the beam cannot reach"),
                "{screen}"
            );
            assert!(
                !screen.contains("beam ─"),
                "no beam in the legends: {screen}"
            );
        }
    }
    for (row, path) in [(0, 0), (1, 1), (4, 1), (5, 2)] {
        app.edit.loads_state.row = row;
        assert_eq!(app.edit.shown_path(), path);
        render(&app, 120, 40);
    }
    // A path of one row at rest (allowed in a data file, not in a [[loads]] table) does
    // not stop beam edits.
    let t0 = Instant::now();
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = BeamField::of(false)
        .iter()
        .position(|&f| f == BeamField::Thickness)
        .unwrap();
    edit(&mut app, "0.6 mm", t0);
    assert!(app.message.is_none(), "{:?}", app.message);
    assert_eq!(app.edit.scene.beam.thickness, 0.6e-3);
    assert!(matches!(app.tick(t0 + DEBOUNCE), Some(Command::Submit(_))));
}

/// From a data scene to a mechanism scene and back (each opened over the other, each
/// judged by the real worker and drawn): the right panels each time, no stale rows.
#[test]
fn a_mechanism_scene_and_back() {
    let t0 = Instant::now();
    let mut app = app_on(&strip());
    // Judged, not fitted: the scenes, not the fits, are what this is about.
    app.jobs.live = false;
    app.edit.focus = Panel::Loads;
    app.edit.loads_state.row = 6;
    let worker = Worker::spawn().unwrap();
    {
        let job = job_of(Some(app.submit(false)));
        run_job(&mut app, &worker, job)
    };
    assert!(render(&app, 120, 40).contains("measured ×"));
    for (path, data) in [
        (shipped("slider-crank.toml"), false),
        (strip(), true),
        (shipped("fixed-guided.toml"), false),
    ] {
        run_command(&mut app, Command::OpenScene(path.clone()), t0);
        assert_eq!(app.edit.is_data(), data);
        assert_eq!(app.edit.is_mechanism(), !data);
        render(&app, 120, 40);
        let job = job_of(app.tick(t0 + DEBOUNCE));
        let msg = run_job(&mut app, &worker, job);
        assert!(matches!(msg, WorkerMsg::Done { .. }), "{msg:?}");
        let screen = render(&app, 120, 40);
        assert_eq!(screen.contains("Data rows (read-only)"), data, "{screen}");
        assert_eq!(screen.contains("measured ×"), data, "{screen}");
        render(&app, 80, 24);
    }
}

/// A data scene's results arriving with a view of another scene's rows (a job sent before
/// an open) never draw out of range.
#[test]
fn stale_results_draw_without_panicking() {
    let mut app = app_on(&strip());
    let worker = Worker::spawn().unwrap();
    {
        let job = job_of(Some(app.submit(false)));
        run_job(&mut app, &worker, job)
    };
    let result = app.shown.result.clone();
    app = App::new(Scene::builtin(), None);
    app.shown.result = result;
    app.jobs.activity = Activity::Idle;
    for (w, h) in [(120, 40), (80, 24)] {
        render(&app, w, h);
    }
    let mut data = app_on(&strip());
    let builtin = App::new(Scene::builtin(), None);
    let b = Study::as_given(&builtin.edit.scene, Sampling::Fidelity(Fidelity::Normal)).unwrap();
    data.shown.result = Some(common::tui::judged(&b, &builtin.edit.matrix));
    data.edit.loads_state.row = 7;
    for (w, h) in [(120, 40), (80, 24)] {
        render(&data, w, h);
    }
}

mod no_panics {
    use super::*;
    use proptest::prelude::*;

    /// The strip judged once (as the worker would), for every case below.
    fn judged() -> App {
        common::tui::judged_as_given(Scene::from_file(&strip()).unwrap(), Some(strip()))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]

        /// Any key sequence on the data scene with its results on screen, drawn at any size,
        /// never panics, never changes the rows but by a beam edit (the rows then are those
        /// of the edited beam: one per row still, the same lines and hash) and leaves a
        /// scene that writes and reads back.
        #[test]
        fn no_input_sequence_panics_on_data(keys in proptest::collection::vec(any_key(&[], &[], true), 1..80),
                                            w in 1u16..140, h in 1u16..50) {
            let mut app = judged();
            let lines: Vec<usize> = app.edit.scene.truth.as_ref().unwrap().paths.iter()
                .flat_map(|p| p.rows.iter().map(|r| r.line)).collect();
            drive(&mut app, &keys, w, h);
            let truth = app.edit.scene.truth.as_ref().unwrap();
            let now: Vec<usize> = truth.paths.iter()
                .flat_map(|p| p.rows.iter().map(|r| r.line)).collect();
            prop_assert_eq!(now, lines);
            prop_assert_eq!(app.edit.scene.loads.len(), truth.paths.len());
            let again = Scene::from_toml_str(&app.edit.scene.to_toml(), "check");
            prop_assert!(again.is_ok(), "{:?}", again);
            prop_assert!(again.unwrap().truth.is_some());
        }
    }
}
