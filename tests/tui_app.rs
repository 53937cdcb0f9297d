//! The UI's state logic, without a terminal: edits queue jobs, stale results are dropped,
//! invalid edits change nothing, quitting with unsaved work asks, and no key sequence panics.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::time::{Duration, Instant};

use prbfit::fit::Fidelity;
use prbfit::prb::{Column, PrbMatrix};
use prbfit::scene::Scene;
use prbfit::study::{Sampling, Study};
use prbfit::tui::app::{Activity, App, Command, Panel, PromptKind, DEBOUNCE};
use prbfit::tui::worker::{model_view, truth_view, FitStatus, TruthView, WorkerMsg};
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

mod common;

use common::tui::{any_key, drive, edit, jobs, key, type_text};

fn app() -> App {
    App::new(Scene::builtin(), None)
}

/// The charts' view of `study`'s truth, as the worker sends it.
fn truth_of(study: &Study) -> TruthView {
    truth_view(study, &prbfit::cancel::CancelToken::new()).unwrap()
}

#[test]
fn an_edit_queues_exactly_one_job() {
    let mut app = app();
    let t0 = Instant::now();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    let cmds = edit(&mut app, "4.2", t0);
    assert_eq!(jobs(&cmds), 0, "debounced, not sent at once");
    assert_eq!(app.edit.matrix.rows()[1].k_theta, 4.2);
    assert!(app.tick(t0 + DEBOUNCE / 2).is_none());
    let sent = app.tick(t0 + DEBOUNCE);
    match sent {
        Some(Command::Submit(job)) => {
            assert_eq!(
                job.kind,
                prbfit::tui::worker::JobKind::Fit,
                "live refit is on"
            );
            assert_eq!(job.matrix.rows()[1].k_theta, 4.2);
        }
        other => panic!("expected one job, got {other:?}"),
    }
    assert!(app.tick(t0 + DEBOUNCE * 3).is_none(), "exactly one");
}

#[test]
fn quick_edits_coalesce_into_one_job() {
    let mut app = app();
    let t0 = Instant::now();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 2;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "3", t0);
    edit(&mut app, "3.5", t0 + DEBOUNCE / 2);
    assert!(
        app.tick(t0 + DEBOUNCE).is_none(),
        "the second edit restarted the debounce"
    );
    let mut sent = 0;
    for k in 1..10 {
        if app
            .tick(t0 + DEBOUNCE * 2 + Duration::from_millis(k))
            .is_some()
        {
            sent += 1;
        }
    }
    assert_eq!(sent, 1);
}

#[test]
fn paused_live_refit_only_judges() {
    let mut app = app();
    let t0 = Instant::now();
    app.on_key(key(KeyCode::Char(' ')), t0);
    assert!(!app.jobs.live);
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "2.5", t0);
    match app.tick(t0 + DEBOUNCE) {
        Some(Command::Submit(job)) => assert_eq!(job.kind, prbfit::tui::worker::JobKind::Judge),
        other => panic!("{other:?}"),
    }
    // r fits on demand, at once.
    let cmds = app.on_key(key(KeyCode::Char('r')), t0);
    assert!(
        matches!(&cmds[..], [Command::Submit(job)] if job.kind == prbfit::tui::worker::JobKind::Fit)
    );
}

/// A worker message for an older job than the newest is dropped; the newest one is taken.
#[test]
fn stale_results_are_dropped() {
    let mut app = app();
    let scene = Scene::builtin();
    let study = Study::as_given(&scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let old = app.submit(true);
    let new = app.submit(true);
    let (Command::Submit(old), Command::Submit(new)) = (old, new) else {
        panic!("jobs expected")
    };
    assert!(
        old.cancel.is_cancelled(),
        "sending a newer job cancels the older"
    );
    assert!(!new.cancel.is_cancelled());
    let view = model_view(&study, &app.edit.matrix).unwrap();
    let truth = std::sync::Arc::new(truth_of(&study));
    let stale = WorkerMsg::Progress {
        id: old.id,
        truth: truth.clone(),
        model: Box::new(view.clone()),
        status: FitStatus {
            phase: "polish",
            iteration: 3,
            evaluations: 10,
            seconds: 0.01,
        },
        compare: None,
    };
    assert!(!app.on_worker(stale));
    assert!(app.shown.result.is_none());
    assert_eq!(app.jobs.activity, Activity::Waiting);
    let fresh = WorkerMsg::Progress {
        id: new.id,
        truth,
        model: Box::new(view),
        status: FitStatus {
            phase: "polish",
            iteration: 1,
            evaluations: 5,
            seconds: 0.01,
        },
        compare: None,
    };
    assert!(app.on_worker(fresh));
    assert!(app.shown.model().is_some() && app.shown.truth().is_some());
    assert!(matches!(app.jobs.activity, Activity::Fitting(_)));
}

/// Invalid entries are rejected with a message, the old value kept and no job queued.
#[test]
fn invalid_edits_change_nothing() {
    let t0 = Instant::now();
    let cases: &[(Panel, usize, usize, &str, &str)] = &[
        (Panel::Matrix, 1, 1, "-3", "k_theta"),
        (Panel::Matrix, 1, 1, "abc", "number"),
        (Panel::Matrix, 1, 1, "nan", "number"),
        (Panel::Matrix, 1, 0, "1.5", "gamma"),
        (Panel::Matrix, 1, 2, "0", "k_ex"),
        (Panel::Beam, 2, 0, "-1 mm", "thickness"),
        (Panel::Beam, 4, 0, "0.7", "poisson"),
        (Panel::Beam, 0, 0, "5 furlongs", "furlongs"),
        (Panel::Beam, 6, 0, "poisson", "extension"),
        (Panel::Loads, 0, 3, "0", "steps"),
        (Panel::Loads, 0, 1, "1e999", "finite"),
    ];
    for &(panel, row, col, text, needle) in cases {
        let mut app = app();
        let (scene, matrix) = (app.edit.scene.clone(), app.edit.matrix.clone());
        app.edit.focus = panel;
        match panel {
            Panel::Matrix => {
                app.edit.matrix_state.row = row;
                app.edit.matrix_state.col = col;
            }
            Panel::Beam => app.edit.beam_state.row = row,
            Panel::Loads => {
                app.edit.loads_state.row = row;
                app.edit.loads_state.col = col;
            }
            Panel::Mechanism => app.edit.mech_state.row = row,
        }
        edit(&mut app, text, t0);
        assert_eq!(app.edit.scene, scene, "{text}");
        assert_eq!(app.edit.matrix, matrix, "{text}");
        let (message, _) = app.message.clone().expect("a message");
        assert!(message.to_lowercase().contains(needle), "{text}: {message}");
        assert!(app.tick(t0 + DEBOUNCE * 2).is_none(), "{text}: no job");
        assert!(!app.unsaved(), "{text}");
    }
}

/// Engineering input is accepted: 0.5 mm, 200 GPa; a gamma edit keeps the sum at 1.
#[test]
fn valid_edits_apply() {
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = 2;
    edit(&mut app, "0.4 mm", t0);
    assert!((app.edit.scene.beam.thickness - 0.4e-3).abs() < 1e-15);
    app.edit.beam_state.row = 3;
    edit(&mut app, "190GPa", t0);
    assert_eq!(app.edit.scene.beam.youngs_modulus, 190e9);
    app.edit.beam_state.row = 6;
    edit(&mut app, "shear,extension", t0);
    assert_eq!(app.edit.scene.beam.effects.to_string(), "shear,extension");
    assert!(app.edit.scene_dirty);

    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 0;
    app.edit.matrix_state.col = 0;
    edit(&mut app, "0.2", t0);
    let sum: f64 = app.edit.matrix.rows().iter().map(|r| r.gamma).sum();
    assert!((sum - 1.0).abs() < 1e-12);
    assert_eq!(app.edit.matrix.rows()[0].gamma, 0.2);
    // inf turns a joint off.
    app.edit.matrix_state.row = 3;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "inf", t0);
    assert_eq!(app.edit.matrix.topology(), "L-R-R-L");
}

#[test]
fn effect_toggles_keep_poisson_with_extension() {
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Beam;
    // auto means all on; 2 switches extension off, and poisson with it.
    app.on_key(key(KeyCode::Char('2')), t0);
    assert_eq!(app.edit.scene.beam.effects.to_string(), "shear");
    app.on_key(key(KeyCode::Char('3')), t0);
    assert_eq!(
        app.edit.scene.beam.effects.to_string(),
        "shear,extension,poisson"
    );
    app.on_key(key(KeyCode::Char('1')), t0);
    assert_eq!(app.edit.scene.beam.effects.to_string(), "extension,poisson");
    // 4 switches plane strain (the plate stiffening of wide sections) alone.
    app.on_key(key(KeyCode::Char('4')), t0);
    assert_eq!(
        app.edit.scene.beam.effects.to_string(),
        "extension,poisson,plane_strain"
    );
    app.on_key(key(KeyCode::Char('4')), t0);
    assert_eq!(app.edit.scene.beam.effects.to_string(), "extension,poisson");
    assert!(app.edit.scene_dirty);
    assert!(app.tick(t0 + DEBOUNCE).is_some());
}

#[test]
fn free_flags_rows_and_presets() {
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    app.on_key(key(KeyCode::Char('f')), t0);
    assert!(!app.edit.matrix.rows()[1].is_free(Column::KTheta));
    assert!(app.tick(t0 + DEBOUNCE).is_some(), "a flag change refits");
    app.edit.matrix_state.col = 2;
    app.on_key(key(KeyCode::Char('f')), t0);
    assert!(
        app.message.as_ref().unwrap().0.contains("inf"),
        "inf cells are not parameters"
    );
    let n = app.edit.matrix.len();
    app.on_key(key(KeyCode::Char('a')), t0);
    assert_eq!(app.edit.matrix.len(), n + 1);
    app.on_key(key(KeyCode::Char('d')), t0);
    app.on_key(key(KeyCode::Char('d')), t0);
    assert_eq!(app.edit.matrix.len(), n - 1);
    app.on_key(key(KeyCode::Char('t')), t0);
    assert!(matches!(app.prompt, Some((PromptKind::Topology, _))));
    for _ in 0..20 {
        app.on_key(key(KeyCode::Backspace), t0);
    }
    type_text(&mut app, "L-RP", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(app.edit.matrix, PrbMatrix::from_topology("L-RP").unwrap());
    app.on_key(key(KeyCode::Char('m')), t0);
    assert_eq!(app.edit.matrix.topology(), "L-R", "howell-1r first");
}

#[test]
fn quitting_with_unsaved_changes_asks() {
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('q')), t0);
    assert!(app.quit, "nothing unsaved: quits at once");

    let mut app = self::app();
    app.edit.focus = Panel::Loads;
    app.edit.loads_state.col = 1;
    edit(&mut app, "4", t0);
    app.on_key(key(KeyCode::Char('q')), t0);
    assert!(!app.quit);
    assert!(matches!(app.prompt, Some((PromptKind::ConfirmQuit, _))));
    app.on_key(key(KeyCode::Char('n')), t0);
    assert!(!app.quit && app.prompt.is_none());
    app.on_key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL), t0);
    app.on_key(key(KeyCode::Char('y')), t0);
    assert!(app.quit);
}

#[test]
fn prompts_produce_file_commands() {
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('e')), t0);
    for _ in 0..20 {
        app.on_key(key(KeyCode::Backspace), t0);
    }
    type_text(&mut app, "out.json", t0);
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    // The target is checked, then the worker exports from its baseline.
    assert!(matches!(
        &cmds[..],
        [Command::Export { path, overwrite: false }] if path.as_os_str() == "out.json"
    ));
    app.on_key(key(KeyCode::Char('o')), t0);
    app.on_key(key(KeyCode::Esc), t0);
    assert!(app.prompt.is_none());
}

mod no_panics {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Any key sequence, rendered at any size (tiny included), never panics and never
        /// leaves an invalid scene or matrix.
        #[test]
        fn no_input_sequence_panics(keys in proptest::collection::vec(any_key(&[KeyCode::F(1)], &[], true), 1..80),
                                    w in 1u16..140, h in 1u16..50) {
            let mut app = App::new(Scene::builtin(), None);
            drive(&mut app, &keys, w, h);
            prop_assert!(app.edit.matrix.validate().is_ok());
            let again = Scene::from_toml_str(&app.edit.scene.to_toml(), "check");
            prop_assert!(again.is_ok(), "{:?}", again);
        }
    }
}

/// The real worker: a job whose beam cannot be solved comes back as a message, and the
/// worker goes on to answer the next job. The figures shown before the failed edit are not
/// left beside its failure (they read PASS for a scene that cannot be solved).
#[test]
fn worker_reports_failures_and_goes_on() {
    use prbfit::beam::Load;
    use prbfit::tui::worker::Worker;
    let worker = Worker::spawn().unwrap();
    let mut app = app();
    let id = job_id(app.start());
    let m = app.edit.matrix.clone();
    app.on_worker(done_with_fit(&app, id, m));
    assert!(app.shown.model().is_some());
    // An exactly axial push far past Euler's load: the beam has no unique answer.
    app.edit.scene.loads[0].end = Load::new(-30.0, 0.0, 0.0);
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let bad_id = job.id;
    worker.submit(job);
    let msg = worker
        .messages
        .recv_timeout(Duration::from_secs(30))
        .unwrap();
    match &msg {
        WorkerMsg::Failed { id, message } => {
            assert_eq!(*id, bad_id);
            assert!(message.contains("critical point"), "{message}");
        }
        other => panic!("expected a failure, got {other:?}"),
    }
    app.on_worker(msg);
    assert!(matches!(app.jobs.activity, Activity::Failed(_)));
    assert!(app.shown.model().is_none() && app.shown.truth().is_none());
    assert!(app.shown.report.is_none());
    app.edit.scene = Scene::builtin();
    let Command::Submit(job) = app.submit(true) else {
        panic!()
    };
    let good_id = job.id;
    worker.submit(job);
    loop {
        let msg = worker
            .messages
            .recv_timeout(Duration::from_secs(60))
            .unwrap();
        assert_eq!(msg.id(), good_id);
        let done = matches!(msg, WorkerMsg::Done { .. });
        app.on_worker(msg);
        if done {
            break;
        }
    }
    assert!(matches!(
        app.jobs.activity,
        Activity::Done { stop: Some(_), .. }
    ));
    assert!(app.shown.report.is_some() && app.shown.result.is_some());
}

/// Issue 11: load paths the beam needs a minute for (a hundred paths to alpha_y = 1e8, each
/// ~0.5 s from zero) keep the worker only until a newer job arrives: the baseline solve is
/// cancelled with the job, and the newer job is answered. Before, the worker finished the
/// old solve first (and with a huge enough load, never).
#[test]
fn a_slow_baseline_is_cancelled_by_a_newer_job() {
    use prbfit::beam::Load;
    use prbfit::tui::worker::Worker;
    let worker = Worker::spawn().unwrap();
    let mut app = app();
    app.edit.scene.beam.effects = prbfit::scene::EffectsChoice::Fixed(prbfit::beam::Effects::NONE);
    app.edit.scene.loads = vec![
        prbfit::scene::LoadPath {
            end: Load::new(0.0, 1e8, 0.0),
            steps: 1,
        };
        100
    ];
    let Command::Submit(slow) = app.submit(false) else {
        panic!()
    };
    worker.submit(slow);
    // Let the worker get well into the slow solve.
    std::thread::sleep(Duration::from_millis(300));
    app.edit.scene = Scene::builtin();
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let good_id = job.id;
    worker.submit(job);
    // Minutes for the old job; the new one's answer must come long before.
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        let msg = worker
            .messages
            .recv_timeout(left)
            .expect("the newer job was answered while the old solve ran on");
        if msg.id() == good_id && matches!(msg, WorkerMsg::Done { .. }) {
            break;
        }
        assert!(
            !matches!(msg, WorkerMsg::Failed { .. }),
            "a cancelled job reported a failure: {msg:?}"
        );
    }
    assert!(
        worker.shutdown(Duration::from_secs(5)),
        "the worker did not stop"
    );
}

/// S opens the selection view and starts a selection job; rows of a stale job are dropped;
/// Enter loads the selected row's model and closes the view; Esc closes and cancels.
#[test]
fn selection_view() {
    use prbfit::tui::worker::JobKind;
    let t0 = Instant::now();
    let mut app = app();
    // Cancelled: the view says it stopped, not that it is done (it said "done").
    app.on_key(key(KeyCode::Char('S')), t0);
    app.on_key(key(KeyCode::Char('c')), t0);
    let view = app.shown.select.as_ref().unwrap();
    assert!(!view.running && view.stopped);
    let backend = ratatui::backend::TestBackend::new(120, 40);
    let mut terminal = ratatui::Terminal::new(backend).unwrap();
    terminal.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    let screen = format!("{}", terminal.backend());
    assert!(screen.contains("Model selection (stopped"), "{screen}");
    app.on_key(key(KeyCode::Esc), t0);
    let cmds = app.on_key(key(KeyCode::Char('S')), t0);
    let Some(Command::Submit(job)) = cmds.into_iter().next() else {
        panic!("a job")
    };
    assert_eq!(job.kind, JobKind::Select);
    assert!(app.shown.select.as_ref().unwrap().running);
    assert!(!app.shown.select.as_ref().unwrap().stopped);

    let scene = Scene::builtin();
    let study = Study::as_given(&scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let sel = study
        .select(
            Fidelity::Draft,
            &prbfit::fit::CancelToken::new(),
            &mut |_| {},
        )
        .unwrap();
    // A row for an older job is ignored.
    assert!(!app.on_worker(WorkerMsg::SelectRow {
        id: job.id - 1,
        row: Box::new(sel.rows[0].clone())
    }));
    assert!(app.shown.select.as_ref().unwrap().rows.is_empty());
    assert!(app.on_worker(WorkerMsg::SelectDone {
        id: job.id,
        selection: Box::new(sel.clone()),
        knobs: Vec::new(),
    }));
    let view = app.shown.select.as_ref().unwrap();
    assert!(!view.running);
    assert_eq!(view.selected, sel.chosen.unwrap_or(sel.closest));
    app.on_key(key(KeyCode::Up), t0);
    let pick = app.shown.select.as_ref().unwrap().selected;
    app.on_key(key(KeyCode::Enter), t0);
    assert!(app.shown.select.is_none());
    assert_eq!(app.edit.matrix, sel.rows[pick].prb);
    assert!(
        app.tick(t0 + DEBOUNCE).is_some(),
        "the loaded model is judged/fitted"
    );

    // Esc while running cancels the selection job.
    let cmds = app.on_key(key(KeyCode::Char('S')), t0);
    let Some(Command::Submit(job)) = cmds.into_iter().next() else {
        panic!("a job")
    };
    app.on_key(key(KeyCode::Esc), t0);
    assert!(app.shown.select.is_none());
    assert!(job.cancel.is_cancelled());
}

/// Exporting from the UI goes through the worker (no solve on the UI thread) and writes the
/// file the extension names; an existing file is refused.
#[test]
fn worker_exports_and_refuses_to_overwrite() {
    use prbfit::tui::worker::Worker;
    let dir = std::env::temp_dir().join(format!("prbfit-ui-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let worker = Worker::spawn().unwrap();
    let mut app = app();
    let path = dir.join("model.xml");
    for expect_ok in [true, false] {
        let Command::Submit(job) = app.export(path.clone()) else {
            panic!()
        };
        worker.submit(job);
        loop {
            let msg = worker
                .messages
                .recv_timeout(Duration::from_secs(30))
                .unwrap();
            let done = matches!(msg, WorkerMsg::Exported { .. });
            app.on_worker(msg);
            if done {
                break;
            }
        }
        let (message, _) = app.message.clone().unwrap();
        if expect_ok {
            assert!(message.starts_with("exported"), "{message}");
            assert!(std::fs::read_to_string(&path)
                .unwrap()
                .starts_with("<mujoco"));
        } else {
            assert!(message.contains("exists"), "{message}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The scene's targets and angle weight are edited in the beam panel, validated like the
/// scene file.
#[test]
fn targets_are_editable() {
    use prbfit::tui::state::beam::BeamField;
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Beam;
    let row = |f: BeamField| BeamField::ALL.iter().position(|&g| g == f).unwrap();
    app.edit.beam_state.row = row(BeamField::MaxPosErr);
    edit(&mut app, "0.005", t0);
    assert_eq!(app.edit.scene.accuracy.max_pos_err, 0.005);
    app.edit.beam_state.row = row(BeamField::AngleWeight);
    edit(&mut app, "0.5", t0);
    assert_eq!(app.edit.scene.fit.angle_weight, 0.5);
    assert!(
        app.tick(t0 + DEBOUNCE).is_some(),
        "a target change is a change"
    );
    let before = app.edit.scene.clone();
    app.edit.beam_state.row = row(BeamField::MaxAngErr);
    edit(&mut app, "-1", t0);
    assert_eq!(app.edit.scene, before);
    assert!(app.message.as_ref().unwrap().0.contains("max_ang_err"));
}

/// `u` shows the matrix in SI for the scene's beam and takes SI input: 1.4625 N m/rad is
/// k_theta 3.51 for the built-in beam (E I0 / L = 0.41667 N m/rad), 10 mm is gamma 0.2.
#[test]
fn si_view_shows_and_takes_si_values() {
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('u')), t0);
    assert!(app.edit.matrix_state.si);
    let ei_l = prbfit::si::column_factor(&app.edit.scene.beam, Column::KTheta);
    assert!((ei_l - 200e9 * 0.01 * 0.0005f64.powi(3) / 12.0 / 0.05).abs() < 1e-12);
    assert_eq!(
        app.edit.cell_text(1, Column::KTheta),
        prbfit::tui::units::trim_number(3.51 * ei_l, 5)
    );
    assert_eq!(app.edit.cell_text(1, Column::Gamma), "17.5 mm");
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 2;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "1.5", t0);
    assert!((app.edit.matrix.rows()[2].k_theta - 1.5 / ei_l).abs() < 1e-12);
    app.edit.matrix_state.col = 0;
    edit(&mut app, "10 mm", t0);
    assert!((app.edit.matrix.rows()[2].gamma - 0.2).abs() < 1e-12);
    let sum: f64 = app.edit.matrix.rows().iter().map(|r| r.gamma).sum();
    assert!((sum - 1.0).abs() < 1e-12);
}

/// Issue 10, the lost baseline: job N solves a new beam, job N+1 (same beam, `r` right after
/// the edit) is a cache hit, and the UI reads job N's messages only after N+1 was sent. The
/// model shown after N+1's Done must come with the baseline it was judged on, never with none
/// and never with the previous beam's.
#[test]
fn baseline_survives_a_newer_job_on_the_same_beam() {
    use prbfit::tui::worker::Worker;
    let worker = Worker::spawn().unwrap();
    let mut app = app();
    app.jobs.fidelity = Fidelity::Draft;
    let recv = |worker: &Worker| {
        worker
            .messages
            .recv_timeout(Duration::from_secs(60))
            .expect("the worker answers")
    };
    // Job 1 on the built-in beam, fully taken by the UI.
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let first = job.id;
    worker.submit(job);
    loop {
        let msg = recv(&worker);
        let done = matches!(msg, WorkerMsg::Done { id, .. } if id == first);
        app.on_worker(msg);
        if done {
            break;
        }
    }
    let old_poses = app.shown.truth().expect("a truth").poses.clone();

    // A load edit: job N solves the beam anew; its messages wait unread.
    app.edit.scene.loads[0].end.alpha_y *= 0.5;
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let n = job.id;
    worker.submit(job);
    let mut unread = Vec::new();
    loop {
        let msg = recv(&worker);
        let done = matches!(msg, WorkerMsg::Done { id, .. } if id == n);
        unread.push(msg);
        if done {
            break;
        }
    }
    // `r` on the same beam before the UI took N's messages.
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let n1 = job.id;
    worker.submit(job);
    for msg in unread {
        app.on_worker(msg);
    }
    loop {
        let msg = recv(&worker);
        let done = matches!(msg, WorkerMsg::Done { id, .. } if id == n1);
        app.on_worker(msg);
        if done {
            break;
        }
    }
    let model = app.shown.model().expect("a model after N+1's Done");
    let truth = app
        .shown
        .truth()
        .expect("a truth after N+1's Done (issue 10: it was lost)");
    assert!(truth.poses != old_poses, "not the previous beam's");
    assert_eq!(truth.poses.concat().len(), model.case_count());
    // Same load cases, and the same beam tips (up to the drawn shape's resolution).
    assert_eq!(truth.case_count(), model.case_count());
    let poses = truth.poses.iter().flatten();
    for ((pose, case), judged) in poses
        .zip(truth.cases.iter().flatten())
        .zip(model.cases.iter().flatten())
    {
        assert_eq!(*case, judged.truth, "the model was judged on this truth");
        let tip = pose.flexures[0].last().unwrap();
        let beam = case.flexures[0].tip;
        assert!(
            (tip[0] - beam.a).abs() < 1e-4 && (tip[1] - beam.b).abs() < 1e-4,
            "{tip:?} vs {beam:?}"
        );
    }
}

/// An export is a side effect the user asked for: an edit that starts a refit right after it
/// neither cancels it nor makes its result stale; the app shows "exported".
#[test]
fn export_survives_a_refit() {
    use prbfit::tui::worker::Worker;
    let dir = std::env::temp_dir().join(format!("prbfit-ui-export-refit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("model.json");
    let worker = Worker::spawn().unwrap();
    let mut app = app();
    app.jobs.fidelity = Fidelity::Draft;
    let t0 = Instant::now();
    let Command::Submit(export) = app.export(path.clone()) else {
        panic!()
    };
    let export_token = export.cancel.clone();
    worker.submit(export);
    // An edit, then the debounced refit goes out before the UI reads anything.
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "4", t0);
    let Some(Command::Submit(refit)) = app.tick(t0 + DEBOUNCE) else {
        panic!("a refit")
    };
    assert_eq!(refit.kind, prbfit::tui::worker::JobKind::Fit);
    let refit_id = refit.id;
    worker.submit(refit);
    assert!(!export_token.is_cancelled());
    let (mut exported, mut fitted) = (false, false);
    while !(exported && fitted) {
        let msg = worker
            .messages
            .recv_timeout(Duration::from_secs(60))
            .expect("the worker answers");
        exported |= matches!(msg, WorkerMsg::Exported { .. });
        fitted |= matches!(msg, WorkerMsg::Done { id, .. } if id == refit_id);
        assert!(app.on_worker(msg));
    }
    let (message, _) = app.message.clone().unwrap();
    assert!(message.starts_with("exported"), "{message}");
    assert!(std::fs::read_to_string(&path).unwrap().contains('{'));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The guide's key table (docs/ui.md, section "Keys") is the keymap: every entry with the
/// same text, in the same order, and nothing else.
#[test]
fn guide_key_table_is_the_keymap() {
    use prbfit::tui::keymap::KEYMAP;
    let guide = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/ui.md"))
        .expect("docs/ui.md");
    let section = guide.split("\n## Keys").nth(1).expect("a section \"Keys\"");
    let section = section.split("\n## ").next().unwrap_or(section);
    let mut lines = section.lines().skip_while(|l| l.trim() != "| key | does |");
    assert!(lines.next().is_some(), "a `| key | does |` table");
    let rows: Vec<(String, String)> = lines
        .skip(1) // |---|---|
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.trim().trim_matches('|').split(" | ").collect();
            assert_eq!(cells.len(), 2, "two cells in {l:?}");
            (cells[0].trim().to_string(), cells[1].trim().to_string())
        })
        .collect();
    let keymap: Vec<(String, String)> = KEYMAP
        .iter()
        .map(|e| (e.keys.to_string(), e.does.to_string()))
        .collect();
    for k in &keymap {
        assert!(rows.contains(k), "docs/ui.md lacks the keymap's row {k:?}");
    }
    for r in &rows {
        assert!(
            keymap.contains(r),
            "docs/ui.md row {r:?} is not in the keymap"
        );
    }
    assert_eq!(rows, keymap, "same order");
}

/// The help lists every key of the keymap, `u` and `q` included.
#[test]
fn help_lists_every_key() {
    use prbfit::tui::keymap::KEYMAP;
    use ratatui::backend::TestBackend;
    use ratatui::Terminal;
    let mut app = app();
    app.help = true;
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    terminal.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    let screen = format!("{}", terminal.backend());
    for e in KEYMAP {
        assert!(screen.contains(e.keys), "{} missing from the help", e.keys);
        assert!(screen.contains(e.does), "{} missing from the help", e.does);
    }
    assert!(screen.contains(" u ") && screen.contains(" q, Ctrl-C"));
}

/// A fitted model of `matrix`'s topology as a worker's Done for job `id` would bring it.
fn done_with_fit(app: &App, id: u64, matrix: PrbMatrix) -> WorkerMsg {
    let study = Study::as_given(&app.edit.scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let view = model_view(&study, &matrix).unwrap();
    let report = prbfit::fit::FitReport {
        matrix,
        figures: view.figures,
        start_objective: view.figures.objective,
        fidelity: Fidelity::Draft,
        iterations: 3,
        evaluations: 30,
        seconds: 0.01,
        stop: prbfit::fit::StopReason::Converged,
    };
    WorkerMsg::Done {
        id,
        truth: std::sync::Arc::new(truth_of(&study)),
        model: Box::new(view),
        report: Some(Box::new(report)),
        seconds: 0.01,
        compare: None,
    }
}

fn job_id(cmd: Command) -> u64 {
    match cmd {
        Command::Submit(job) => job.id,
        other => panic!("a job expected, got {other:?}"),
    }
}

/// Issue 15.4: a message is news about the last action. A rejected edit's message goes at
/// the next action that succeeds (it used to stay through six actions), and a worker's
/// failure goes with the next good result.
#[test]
fn messages_clear_on_the_next_successful_action() {
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('t')), t0);
    for _ in 0..20 {
        app.on_key(key(KeyCode::Backspace), t0);
    }
    type_text(&mut app, "L-2R", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert!(app.message.as_ref().unwrap().0.contains("rejected"));
    // Any key that does something clears it: a cursor move here.
    app.on_key(key(KeyCode::Down), t0);
    assert!(app.message.is_none(), "{:?}", app.message);

    // A rejected beam value, then an accepted one: the rejection is gone.
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = 4;
    edit(&mut app, "0.5", t0);
    assert!(app.message.as_ref().unwrap().0.contains("rejected"));
    edit(&mut app, "0.49999999", t0);
    assert_eq!(app.edit.scene.beam.poisson_ratio, 0.49999999);
    assert!(app.message.is_none(), "{:?}", app.message);

    // A worker failure, then a good result.
    let id = job_id(app.submit(false));
    app.on_worker(WorkerMsg::Failed {
        id,
        message: "the beam cannot be solved".into(),
    });
    assert!(app.message.is_some());
    let id = job_id(app.submit(false));
    let m = app.edit.matrix.clone();
    app.on_worker(done_with_fit(&app, id, m));
    assert!(app.message.is_none(), "{:?}", app.message);
}

/// Issue 15.5: the fit the program starts (at start-up, after an open) is not the user's
/// work: quitting a fresh start asks nothing. A fit the user asked for (`r`) that changes the
/// model is, and so is any edit; open asks before it throws that away.
#[test]
fn only_user_work_is_unsaved() {
    let t0 = Instant::now();
    let mut app = app();
    let id = job_id(app.start());
    let mut fitted = app.edit.matrix.clone();
    fitted = fitted.with_cell(1, Column::KTheta, 3.3).unwrap();
    app.on_worker(done_with_fit(&app, id, fitted.clone()));
    assert_eq!(app.edit.matrix, fitted, "the fit result is shown");
    assert!(!app.unsaved(), "the start-up fit is not the user's work");
    app.on_key(key(KeyCode::Char('o')), t0);
    assert!(
        matches!(app.prompt, Some((PromptKind::OpenScene, _))),
        "nothing to lose: open asks only for the file"
    );
    app.on_key(key(KeyCode::Esc), t0);
    app.on_key(key(KeyCode::Char('q')), t0);
    assert!(app.quit, "nothing unsaved: quits at once");

    // `r` is the user's: its result is unsaved work.
    let mut app = self::app();
    let id = job_id(app.on_key(key(KeyCode::Char('r')), t0).remove(0));
    let m = app.edit.matrix.with_cell(1, Column::KTheta, 3.2).unwrap();
    app.on_worker(done_with_fit(&app, id, m));
    assert!(app.unsaved());

    // An edit is, and open asks before discarding it; n keeps it, y goes on to the file.
    let mut app = self::app();
    app.edit.focus = Panel::Matrix;
    edit(&mut app, "4", t0);
    assert!(app.unsaved());
    app.on_key(key(KeyCode::Char('o')), t0);
    assert!(matches!(app.prompt, Some((PromptKind::ConfirmOpen, _))));
    app.on_key(key(KeyCode::Char('n')), t0);
    assert!(app.prompt.is_none());
    app.on_key(key(KeyCode::Char('o')), t0);
    app.on_key(key(KeyCode::Char('y')), t0);
    assert!(matches!(app.prompt, Some((PromptKind::OpenScene, _))));
}

/// Issue 15.1: the scene is saved with the model being worked on (`[prb] matrix`, fixed
/// cells with `!`); opening it, or starting on it, brings that model back, judged as saved.
#[test]
fn save_keeps_the_model_and_open_brings_it_back() {
    use prbfit::tui::run_command;
    use prbfit::tui::worker::JobKind;
    let dir = std::env::temp_dir().join(format!("prbfit-ui-save-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("saved.toml");
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('t')), t0);
    for _ in 0..20 {
        app.on_key(key(KeyCode::Backspace), t0);
    }
    type_text(&mut app, "L-R-R", t0);
    app.on_key(key(KeyCode::Enter), t0);
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    app.on_key(key(KeyCode::Char('f')), t0);
    let model = app.edit.matrix.clone();
    assert!(app.unsaved());
    assert!(run_command(
        &mut app,
        Command::SaveScene {
            path: path.clone(),
            overwrite: false
        },
        t0
    )
    .is_none());
    assert!(!app.unsaved(), "{:?}", app.message);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("[prb]"), "{text}");
    assert_eq!(Scene::from_file(&path).unwrap().prb, Some(model.clone()));

    // Start-up on the saved file: that model, judged (not refitted) first.
    let mut again = App::new(Scene::from_file(&path).unwrap(), Some(path.clone()));
    assert_eq!(again.edit.matrix, model);
    match again.start() {
        Command::Submit(job) => {
            assert_eq!(job.kind, JobKind::Judge);
            assert_eq!(job.matrix, model);
        }
        other => panic!("{other:?}"),
    }

    // Open from another model: the file's model comes back.
    let mut other = self::app();
    assert_ne!(other.edit.matrix, model);
    run_command(&mut other, Command::OpenScene(path.clone()), t0);
    assert_eq!(other.edit.matrix, model);
    assert!(!other.unsaved());
    match other.tick(t0 + DEBOUNCE) {
        Some(Command::Submit(job)) => assert_eq!(job.kind, JobKind::Judge),
        o => panic!("{o:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An opened scene without its own model starts from the model a fresh start on it has
/// (Su's 3R, fitted), whatever model was worked on before: Howell's 1R kept from the built-in
/// scene could not follow a parallel stage that a fresh start fits, and a pinned mass column
/// went with another beam's gammas.
#[test]
fn an_opened_scene_without_a_model_starts_as_a_fresh_start_does() {
    use prbfit::tui::run_command;
    use prbfit::tui::worker::JobKind;
    let t0 = Instant::now();
    let path = std::path::PathBuf::from(format!(
        "{}/assets/scenes/parallel-stage.toml",
        env!("CARGO_MANIFEST_DIR")
    ));
    let fresh = App::new(Scene::from_file(&path).unwrap(), Some(path.clone()));
    let mut app = app();
    app.on_key(key(KeyCode::Char('m')), t0);
    assert_eq!(app.edit.matrix.topology(), "L-R", "Howell's 1R loaded");
    run_command(&mut app, Command::OpenScene(path), t0);
    assert_eq!(app.edit.matrix, fresh.edit.matrix);
    assert!(!app.unsaved());
    // Fitted, as at start-up (a model the scene brings is only judged).
    match app.tick(t0 + DEBOUNCE) {
        Some(Command::Submit(job)) => assert_eq!(job.kind, JobKind::Fit),
        o => panic!("{o:?}"),
    }
}

/// Below the minimum size only the "too small" note is drawn, so keys act on nothing the
/// user cannot see (typed blind, `d d t howell-1r Enter` replaced the model), but q, and the
/// answer to the question the note then shows.
#[test]
fn keys_act_on_nothing_hidden_while_the_terminal_is_too_small() {
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Matrix;
    let before = app.edit.matrix.clone();
    app.too_small = true;
    for c in ['d', 'd', 't'] {
        assert!(app.on_key(key(KeyCode::Char(c)), t0).is_empty());
    }
    type_text(&mut app, "howell-1r", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert!(app.prompt.is_none());
    assert_eq!(app.edit.matrix, before);
    assert!(!app.unsaved());
    // Some unsaved work: q asks, and the note shows the question; y answers it.
    app.edit.model_dirty = true;
    app.on_key(key(KeyCode::Char('q')), t0);
    assert!(matches!(app.prompt, Some((PromptKind::ConfirmQuit, _))));
    let backend = ratatui::backend::TestBackend::new(40, 12);
    let mut terminal = ratatui::Terminal::new(backend).unwrap();
    terminal.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    let screen: String = terminal
        .backend()
        .buffer()
        .content()
        .iter()
        .map(|c| c.symbol())
        .collect();
    assert!(screen.contains("quit anyway? (y/n)"), "{screen}");
    app.on_key(key(KeyCode::Char('y')), t0);
    assert!(app.quit);

    // With a text prompt open behind the note, q drops it and quits (it did nothing).
    let mut app = self::app();
    app.on_key(key(KeyCode::Char('s')), t0);
    assert!(matches!(app.prompt, Some((PromptKind::SaveScene, _))));
    app.too_small = true;
    app.on_key(key(KeyCode::Char('q')), t0);
    assert!(app.prompt.is_none() && app.quit);
}

/// A length that breaks the slenderness rule is refused naming the length, the field edited
/// (it named `beam.thickness`, the scene file's key for the rule).
#[test]
fn a_length_past_the_slenderness_limit_is_refused_naming_the_length() {
    use prbfit::tui::app::EditTarget;
    use prbfit::tui::state::beam::BeamField;
    let mut app = app();
    let before = app.edit.scene.beam.length;
    let e = app
        .edit
        .apply_edit(&EditTarget::Beam(BeamField::Length), "1000 m")
        .unwrap_err();
    assert!(
        e.starts_with("beam.length (against the thickness): slenderness"),
        "{e}"
    );
    assert_eq!(app.edit.scene.beam.length, before);
    let e = app
        .edit
        .apply_edit(&EditTarget::Beam(BeamField::Thickness), "1 m")
        .unwrap_err();
    assert!(e.starts_with("beam.thickness:"), "{e}");
}

/// The first key typed replaces the shown `50 mm`, so `45` is typed bare: as SI it would be
/// a 45 m beam, silently (slenderness 90000 is within the limits). It is refused with both
/// readings; with a unit, or a bare SI value near the present one, it is taken.
#[test]
fn a_bare_number_meant_in_the_shown_unit_is_not_taken_as_metres() {
    use prbfit::tui::app::EditTarget;
    use prbfit::tui::state::beam::BeamField;
    let mut app = app();
    let length = EditTarget::Beam(BeamField::Length);
    let before = app.edit.scene.beam.length;
    assert_eq!(before, 0.05);
    let e = app.edit.apply_edit(&length, "45").unwrap_err();
    assert!(
        e.contains("`45` has no unit, so it is SI: 45 m") && e.contains("`45 mm`"),
        "{e}"
    );
    assert_eq!(app.edit.scene.beam.length, before);
    app.edit.apply_edit(&length, "45 mm").unwrap();
    assert_eq!(app.edit.scene.beam.length, 0.045);
    app.edit.apply_edit(&length, "0.04").unwrap();
    assert_eq!(app.edit.scene.beam.length, 0.04);
    let modulus = EditTarget::Beam(BeamField::YoungsModulus);
    assert!(app.edit.apply_edit(&modulus, "70").is_err());
    app.edit.apply_edit(&modulus, "70e9").unwrap();
    assert_eq!(app.edit.scene.beam.youngs_modulus, 70e9);
    // The matrix's SI view shows gammas in mm too (segment 1 of Su's 3R: 0.1 of 40 mm).
    app.edit.matrix =
        PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
    app.edit.matrix_state.si = true;
    let gamma = EditTarget::Cell {
        row: 0,
        col: prbfit::prb::Column::Gamma,
    };
    let e = app.edit.apply_edit(&gamma, "5").unwrap_err();
    assert!(e.contains("`5` has no unit, so it is SI: 5 m"), "{e}");
    app.edit.apply_edit(&gamma, "5 mm").unwrap();
    assert!((app.edit.matrix.rows()[0].gamma - 0.125).abs() < 1e-12);
}

/// A typed gamma is balanced by another segment's (the gammas sum to 1); the message says
/// which, and that it was fixed when every gamma was (a pinned gamma changed without a word).
#[test]
fn a_typed_gamma_says_which_segment_took_the_difference() {
    let t0 = Instant::now();
    let mut app = app();
    app.edit.matrix = PrbMatrix::parse("0.2!,inf,inf; 0.5!,3,inf; 0.3!,3,inf").unwrap();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 0;
    app.edit.matrix_state.col = 0;
    edit(&mut app, "0.25", t0);
    let gammas: Vec<f64> = app.edit.matrix.rows().iter().map(|r| r.gamma).collect();
    assert_eq!(gammas[0], 0.25);
    let (m, _) = app.message.clone().unwrap();
    assert!(
        m.starts_with("row 3's gamma took the difference: 0.3 -> 0.25"),
        "{m}"
    );
    assert!(m.contains("(fixed"), "{m}");
    // A value typed with `!`, as a scene file writes a fixed cell, is set and fixed (it was
    // refused: "`!`: this value takes no unit").
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    edit(&mut app, "3.3!", t0);
    assert_eq!(app.edit.matrix.rows()[1].k_theta, 3.3);
    assert!(!app.edit.matrix.rows()[1].is_free(Column::KTheta));
    app.edit.matrix_state.row = 0;
    app.edit.matrix_state.col = 0;
    // A free gamma takes it, and no fixed one is said to.
    app.edit.matrix = PrbMatrix::parse("0.2!,inf,inf; 0.5,3,inf; 0.3!,3,inf").unwrap();
    edit(&mut app, "0.25", t0);
    let (m, _) = app.message.clone().unwrap();
    assert!(
        m.starts_with("row 2's gamma took the difference: 0.5 -> 0.45"),
        "{m}"
    );
    assert!(!m.contains("fixed"), "{m}");
    // In the SI view, as the cells show it (the built-in beam is 50 mm long).
    app.edit.matrix_state.si = true;
    edit(&mut app, "10 mm", t0);
    let (m, _) = app.message.clone().unwrap();
    assert!(
        m.starts_with("row 2's gamma took the difference: 22.5 mm -> 25 mm"),
        "{m}"
    );
    app.edit.matrix_state.si = false;
    // A mu too (it changed another row's mu without a word).
    app.edit.matrix = PrbMatrix::parse("0.2,inf,inf,0.2; 0.5,3,inf,0.5; 0.3,3,inf,0.3").unwrap();
    app.edit.matrix_state.col = 3;
    edit(&mut app, "0.4", t0);
    let (m, _) = app.message.clone().unwrap();
    assert!(
        m.starts_with("row 3's mu took the difference: 0.3 -> 0.1"),
        "{m}"
    );
}

/// A prompt answered with nothing is a cancel, and says so (it left a blank line).
#[test]
fn an_empty_answer_to_a_file_prompt_says_nothing_was_done() {
    let t0 = Instant::now();
    let mut app = app();
    for (k, said) in [
        ('s', "not saved: no file given"),
        ('o', "not opened: no file given"),
        ('e', "not exported: no file given"),
    ] {
        app.on_key(key(KeyCode::Char(k)), t0);
        assert!(app.prompt.is_some());
        for _ in 0..80 {
            app.on_key(key(KeyCode::Backspace), t0);
        }
        assert!(app.on_key(key(KeyCode::Enter), t0).is_empty());
        assert!(app.prompt.is_none());
        assert_eq!(app.message.as_ref().unwrap().0, said);
    }
}

/// Saving over the file a scene was opened from asks first when the UI did not write it
/// (the save rewrites it in prbfit's layout: a hand-written file's comments went without a
/// word); once the UI has saved there, saving there again just saves.
#[test]
fn the_first_save_over_an_opened_file_asks() {
    use prbfit::tui::run_command;
    let dir = common::Scratch::new("ui-save-own");
    let text = format!(
        "# my notes\n{}",
        std::fs::read_to_string(format!(
            "{}/assets/scenes/steel-flexure.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
    );
    let path = std::path::PathBuf::from(dir.write("mine.toml", &text));
    let t0 = Instant::now();
    let mut app = app();
    run_command(&mut app, Command::OpenScene(path.clone()), t0);
    let save = || Command::SaveScene {
        path: path.clone(),
        overwrite: false,
    };
    assert!(run_command(&mut app, save(), t0).is_none());
    assert!(matches!(
        app.prompt,
        Some((PromptKind::ConfirmOverwrite, _))
    ));
    assert!(app
        .message
        .as_ref()
        .unwrap()
        .0
        .contains("without its comments"));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        text,
        "asked, not written"
    );
    let cmds = app.on_key(key(KeyCode::Char('y')), t0);
    run_command(&mut app, cmds.into_iter().next().unwrap(), t0);
    assert!(!std::fs::read_to_string(&path)
        .unwrap()
        .contains("# my notes"));
    // Saved here by the UI: the next save asks nothing.
    run_command(&mut app, save(), t0);
    assert!(app.prompt.is_none());
    assert!(app.message.as_ref().unwrap().0.starts_with("saved"));
}

/// Issue 15.6: saving or exporting over an existing file asks "overwrite? (y/n)"; n leaves
/// the file, y writes it. Saving to the scene's own file just saves.
#[test]
fn writing_over_a_file_asks_first() {
    use prbfit::tui::run_command;
    use prbfit::tui::worker::JobKind;
    let dir = std::env::temp_dir().join(format!("prbfit-ui-overwrite-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("there.toml");
    std::fs::write(&path, "old").unwrap();
    let t0 = Instant::now();
    let mut app = app();
    let save = || Command::SaveScene {
        path: path.clone(),
        overwrite: false,
    };
    run_command(&mut app, save(), t0);
    assert!(matches!(
        app.prompt,
        Some((PromptKind::ConfirmOverwrite, _))
    ));
    assert!(app.on_key(key(KeyCode::Char('n')), t0).is_empty());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    run_command(&mut app, save(), t0);
    let cmds = app.on_key(key(KeyCode::Char('y')), t0);
    for c in cmds {
        run_command(&mut app, c, t0);
    }
    assert!(std::fs::read_to_string(&path).unwrap().contains("[beam]"));
    assert_eq!(app.edit.scene_path.as_deref(), Some(path.as_path()));
    // Its own file: no question.
    run_command(&mut app, save(), t0);
    assert!(app.prompt.is_none());
    assert!(app.message.as_ref().unwrap().0.starts_with("saved"));

    // An export over a file: asked, then a job that may overwrite.
    let out = dir.join("model.json");
    std::fs::write(&out, "old").unwrap();
    let export = Command::Export {
        path: out.clone(),
        overwrite: false,
    };
    assert!(run_command(&mut app, export, t0).is_none());
    assert!(matches!(
        app.prompt,
        Some((PromptKind::ConfirmOverwrite, _))
    ));
    let cmds = app.on_key(key(KeyCode::Char('y')), t0);
    let job = run_command(&mut app, cmds.into_iter().next().unwrap(), t0).unwrap();
    assert!(matches!(
        job.kind,
        JobKind::Export {
            overwrite: true,
            ..
        }
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 15.6: the robot formats ask for the links' density (kg/m^3), which goes with the
/// export job; formats without masses do not ask.
#[test]
fn export_asks_for_the_density_of_the_robot_formats() {
    use prbfit::tui::run_command;
    use prbfit::tui::worker::JobKind;
    let t0 = Instant::now();
    let mut app = app();
    app.on_key(key(KeyCode::Char('e')), t0);
    type_text(&mut app, "/nonexistent-dir-prbfit/arm.xml", t0);
    assert!(app.on_key(key(KeyCode::Enter), t0).is_empty());
    assert!(matches!(app.prompt, Some((PromptKind::ExportDensity, _))));
    type_text(&mut app, "7850 kg/m^3", t0);
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(app.export_density, 7850.0);
    let Some(Command::Export { path, overwrite }) = cmds.into_iter().next() else {
        panic!("an export")
    };
    let job = app.export_job(path, overwrite);
    assert!(matches!(job.kind, JobKind::Export { density, .. } if density == Some(7850.0)));
    // A bad density is refused, nothing exported.
    app.on_key(key(KeyCode::Char('e')), t0);
    type_text(&mut app, "arm.urdf", t0);
    app.on_key(key(KeyCode::Enter), t0);
    type_text(&mut app, "heavy", t0);
    assert!(app.on_key(key(KeyCode::Enter), t0).is_empty());
    assert!(app.message.as_ref().unwrap().0.contains("density"));
    // So is one the scene's rule refuses (it was kept, and the export failed later).
    app.on_key(key(KeyCode::Char('e')), t0);
    type_text(&mut app, "arm.urdf", t0);
    app.on_key(key(KeyCode::Enter), t0);
    type_text(&mut app, "1e-300", t0);
    assert!(app.on_key(key(KeyCode::Enter), t0).is_empty());
    let message = &app.message.as_ref().unwrap().0;
    assert!(message.contains("at least 0.001 kg/m^3"), "{message}");
    assert_eq!(app.export_density, 7850.0);
    // A model file of a scene without a density has no masses, as the CLI writes it: the
    // density typed for the robot format above does not go with it (it gave every segment
    // a mass from 7850 kg/m^3, which nobody gave the scene).
    let job = app.export_job("/nonexistent-dir-prbfit/model.toml".into(), false);
    assert!(matches!(job.kind, JobKind::Export { density: None, .. }));
    let _ = run_command;
}

/// Issue 25.5: a scene giving `[beam] density` is not asked for one; its density goes with
/// the export job.
#[test]
fn export_takes_the_scenes_density_without_asking() {
    use prbfit::tui::worker::JobKind;
    let t0 = Instant::now();
    let mut app = app();
    app.edit.scene.beam.density = Some(2700.0);
    app.on_key(key(KeyCode::Char('e')), t0);
    type_text(&mut app, "/nonexistent-dir-prbfit/arm.xml", t0);
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    assert!(app.prompt.is_none());
    let Some(Command::Export { path, overwrite }) = cmds.into_iter().next() else {
        panic!("an export")
    };
    let job = app.export_job(path, overwrite);
    assert!(matches!(job.kind, JobKind::Export { density, .. } if density == Some(2700.0)));
}

/// Issue 15.6: the text box takes the readline keys (they used to insert `u` and `a`), and
/// the first character typed over a pre-filled value replaces it.
#[test]
fn text_boxes_take_the_readline_keys() {
    let ctrl = |c| KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL);
    let t0 = Instant::now();
    let mut app = app();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 1;
    let text = |app: &App| app.edit.editing.as_ref().unwrap().1.text.clone();
    // Typing over the shown value replaces it.
    app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(text(&app), "3.51");
    type_text(&mut app, "4", t0);
    assert_eq!(text(&app), "4");
    // Ctrl-U clears, Ctrl-A/E and Home/End move, Left/Right, Delete, Ctrl-W.
    app.on_key(ctrl('u'), t0);
    assert_eq!(text(&app), "");
    type_text(&mut app, "2.5", t0);
    app.on_key(ctrl('a'), t0);
    type_text(&mut app, "1", t0);
    assert_eq!(text(&app), "12.5");
    app.on_key(key(KeyCode::Delete), t0);
    assert_eq!(text(&app), "1.5");
    app.on_key(ctrl('e'), t0);
    app.on_key(key(KeyCode::Left), t0);
    app.on_key(key(KeyCode::Backspace), t0);
    assert_eq!(text(&app), "15");
    app.on_key(key(KeyCode::Home), t0);
    app.on_key(key(KeyCode::Right), t0);
    type_text(&mut app, ".", t0);
    app.on_key(key(KeyCode::End), t0);
    assert_eq!(text(&app), "1.5");
    assert_eq!(app.edit.editing.as_ref().unwrap().1.with_cursor(), "1.5_");
    app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(app.edit.matrix.rows()[1].k_theta, 1.5);
    // A cursor key keeps the shown value for editing.
    app.on_key(key(KeyCode::Enter), t0);
    app.on_key(key(KeyCode::End), t0);
    type_text(&mut app, "5", t0);
    assert_eq!(text(&app), "1.55");
    app.on_key(key(KeyCode::Esc), t0);
    assert!(app.edit.editing.is_none());
    // Ctrl-W in the topology prompt deletes a word; an unused Ctrl key types nothing.
    app.on_key(key(KeyCode::Char('t')), t0);
    app.on_key(ctrl('w'), t0);
    app.on_key(ctrl('x'), t0);
    assert_eq!(app.prompt.as_ref().unwrap().1.text, "L-R-R-");
    // A separator goes on its own, then the word before it.
    app.on_key(ctrl('w'), t0);
    assert_eq!(app.prompt.as_ref().unwrap().1.text, "L-R-R");
    app.on_key(ctrl('w'), t0);
    assert_eq!(app.prompt.as_ref().unwrap().1.text, "L-R-");
    // Topology shorthand: 4R is L-R-R-R-R.
    app.on_key(ctrl('u'), t0);
    type_text(&mut app, "4R", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(app.edit.matrix.topology(), "L-R-R-R-R");
}

/// Issue 15.3: the loads in SI for the beam as it is (`u`: the table, typed values too; the
/// other units on the panel's border), and `H` choosing what a beam edit holds: alpha (the
/// force follows: 4x thicker is 64x the force) or the force (the alphas are rescaled, alpha =
/// F L^2 / (E I0)).
#[test]
fn loads_in_si_and_what_a_beam_edit_holds() {
    use prbfit::si::load_si;
    use prbfit::tui::state::loads::Hold;
    let t0 = Instant::now();
    let thickness_row = 2;
    // Holding alpha (the default): the force grows with t0^3.
    let mut app = app();
    let alpha = app.edit.scene.loads[0].end;
    let force = load_si(&app.edit.scene.beam, &alpha);
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = thickness_row;
    edit(&mut app, "2 mm", t0);
    assert_eq!(app.edit.scene.loads[0].end, alpha);
    let grown = load_si(&app.edit.scene.beam, &app.edit.scene.loads[0].end);
    assert!((grown[1] / force[1] - 64.0).abs() < 1e-9, "{grown:?}");

    // Holding the force: the alphas shrink by 64, Fx, Fy, Mz stay.
    let mut app = self::app();
    app.edit.focus = Panel::Loads;
    app.on_key(key(KeyCode::Char('H')), t0);
    assert_eq!(app.edit.loads_state.hold, Hold::Force);
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = thickness_row;
    edit(&mut app, "2 mm", t0);
    for (old, new) in Scene::builtin().loads.iter().zip(&app.edit.scene.loads) {
        let (a, b) = (
            load_si(&Scene::builtin().beam, &old.end),
            load_si(&app.edit.scene.beam, &new.end),
        );
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-9 * a[k].abs().max(1e-12),
                "{a:?} {b:?}"
            );
        }
    }
    assert!((app.edit.scene.loads[0].end.alpha_y - 5.0 / 64.0).abs() < 1e-12);

    // The SI view: the table in N, and a force typed in N.
    let mut app = self::app();
    app.on_key(key(KeyCode::Char('u')), t0);
    let (f, _) = prbfit::si::load_factors(&app.edit.scene.beam);
    app.edit.focus = Panel::Loads;
    app.edit.loads_state.col = 1;
    app.on_key(key(KeyCode::Enter), t0);
    let shown = app.edit.editing.as_ref().unwrap().1.text.clone();
    assert_eq!(shown, prbfit::tui::units::trim_number(5.0 * f, 5));
    type_text(&mut app, "1", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert!((app.edit.scene.loads[0].end.alpha_y - 1.0 / f).abs() < 1e-12);
    // Drawn: the title says what is held, the border shows the other units.
    use ratatui::backend::TestBackend;
    use ratatui::Terminal;
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    terminal.draw(|fr| prbfit::tui::ui::draw(fr, &app)).unwrap();
    let screen = format!("{}", terminal.backend());
    assert!(
        screen.contains("hold alpha") && screen.contains("Fy N"),
        "{screen}"
    );
    assert!(screen.contains("alpha_y "), "{screen}");
}

/// Issue 15.2: a published model is shown with its own figures first: `m` and `t chen-3r`
/// load it judged, not fitted, even with live refit on (r fits it).
#[test]
fn published_models_are_judged_not_refitted() {
    use prbfit::tui::worker::JobKind;
    let t0 = Instant::now();
    let mut app = app();
    assert!(app.jobs.live);
    for _ in 0..3 {
        app.on_key(key(KeyCode::Char('m')), t0);
    }
    let chen = prbfit::io::ModelFile::load("chen-3r").unwrap().prb;
    assert_eq!(app.edit.matrix, chen);
    assert_eq!(app.edit.cell_text(1, Column::KTheta), "3.25");
    match app.tick(t0 + DEBOUNCE) {
        Some(Command::Submit(job)) => {
            assert_eq!(job.kind, JobKind::Judge, "Chen's own figures first");
            assert_eq!(job.matrix, chen);
        }
        o => panic!("{o:?}"),
    }
    // A done judge leaves Chen's values in the cells.
    let id = app.jobs.current.as_ref().unwrap().0;
    let study = Study::as_given(&app.edit.scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    app.on_worker(WorkerMsg::Done {
        id,
        truth: std::sync::Arc::new(truth_of(&study)),
        model: Box::new(model_view(&study, &chen).unwrap()),
        report: None,
        seconds: 0.01,
        compare: None,
    });
    assert_eq!(app.edit.matrix, chen);
    // The next edit refits as usual.
    app.edit.focus = Panel::Matrix;
    edit(&mut app, "3.3", t0);
    match app.tick(t0 + DEBOUNCE * 2) {
        Some(Command::Submit(job)) => assert_eq!(job.kind, JobKind::Fit),
        o => panic!("{o:?}"),
    }
    // By name at `t` too.
    let mut app = self::app();
    app.on_key(key(KeyCode::Char('t')), t0);
    type_text(&mut app, "howell-1r", t0);
    app.on_key(key(KeyCode::Enter), t0);
    assert_eq!(app.edit.matrix.topology(), "L-R");
    assert!(
        matches!(app.tick(t0 + DEBOUNCE), Some(Command::Submit(j)) if j.kind == JobKind::Judge)
    );
}

/// Issue 15.2: `C` compares with another model without touching the one being worked on: a
/// kept compare job (the running fit is not cancelled), every later job judges it too on its
/// own baseline, and it is shown only with the baseline it was judged on.
#[test]
fn compare_with_another_model() {
    use prbfit::tui::worker::{JobKind, Worker};
    let t0 = Instant::now();
    let mut app = app();
    app.jobs.fidelity = Fidelity::Draft;
    let worker = Worker::spawn().unwrap();
    let recv = |worker: &Worker| {
        worker
            .messages
            .recv_timeout(Duration::from_secs(60))
            .expect("the worker answers")
    };
    let Command::Submit(job) = app.submit(false) else {
        panic!()
    };
    let running = job.cancel.clone();
    worker.submit(job);
    let before = app.edit.matrix.clone();
    // C: Howell's 1R first.
    let cmds = app.on_key(key(KeyCode::Char('C')), t0);
    let Some(Command::Submit(cmp)) = cmds.into_iter().next() else {
        panic!("a compare job")
    };
    assert_eq!(cmp.kind, JobKind::Compare);
    assert_eq!(cmp.matrix.topology(), "L-R");
    assert!(!running.is_cancelled(), "the main job goes on");
    assert_eq!(app.edit.matrix, before, "the model being worked on stays");
    worker.submit(cmp);
    let (mut done, mut compared) = (false, false);
    while !(done && compared) {
        let msg = recv(&worker);
        done |= matches!(msg, WorkerMsg::Done { .. });
        compared |= matches!(msg, WorkerMsg::Compared { .. });
        app.on_worker(msg);
    }
    let (name, view) = app.shown.shown_compare().expect("the compared model shown");
    assert_eq!(name, "howell-1r");
    assert_eq!(view.cases.len(), app.shown.model().unwrap().cases.len());
    assert!(view.figures.objective != app.shown.model().unwrap().figures.objective);
    // Drawn: its row in the status lines.
    use ratatui::backend::TestBackend;
    use ratatui::Terminal;
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    terminal.draw(|f| prbfit::tui::ui::draw(f, &app)).unwrap();
    let screen = format!("{}", terminal.backend());
    assert!(screen.contains("compared with howell-1r"), "{screen}");

    // A load edit: the compared view of the old loads is not shown with the new baseline;
    // the new job judges the compared model on its own baseline.
    app.edit.focus = Panel::Loads;
    app.edit.loads_state.col = 1;
    edit(&mut app, "3", t0);
    let Some(Command::Submit(job)) = app.tick(t0 + DEBOUNCE) else {
        panic!()
    };
    assert_eq!(
        job.compare.as_ref().map(|m| m.topology()),
        Some("L-R".into())
    );
    let id = job.id;
    worker.submit(job);
    let mut first = true;
    loop {
        let msg = recv(&worker);
        if let (
            WorkerMsg::Progress { truth, model, .. } | WorkerMsg::Done { truth, model, .. },
            true,
        ) = (&msg, first)
        {
            first = false;
            // Before the UI takes it, the old compared view is not drawn with a new baseline.
            let mut probe = App::new(Scene::builtin(), None);
            probe.shown.compare = app.shown.compare.clone();
            probe.shown.compared = app.shown.compared.clone();
            probe.shown.result = Some(prbfit::tui::app::Judged {
                truth: truth.clone(),
                model: (**model).clone(),
            });
            assert!(
                probe.shown.shown_compare().is_none(),
                "another beam's compare is hidden"
            );
        }
        let end = matches!(msg, WorkerMsg::Done { id: i, .. } if i == id);
        app.on_worker(msg);
        if end {
            break;
        }
    }
    let (_, view) = app
        .shown
        .shown_compare()
        .expect("judged again on the new beam");
    assert_eq!(view.cases.len(), app.shown.model().unwrap().cases.len());
    // C cycles on to none.
    for _ in 0..3 {
        app.on_key(key(KeyCode::Char('C')), t0);
    }
    assert!(app.shown.compare.is_none() && app.shown.shown_compare().is_none());
}

/// The matrix panel's fourth column (issue 25): a typed mu keeps the mus summing to 1 (as a
/// typed gamma keeps the gammas), `f` fixes it, a bad mu is refused with a message and the
/// matrix unchanged; and on a scene that asks for modes the live refit frees the mus and
/// matches the frequencies (the shown model's `max_freq_err` within the target, where the
/// starting model with uniform mass is far off).
#[test]
fn mu_cells_edit_fix_and_refit_with_the_modes() {
    use prbfit::scene::DEFAULT_SCENE_TOML;
    use prbfit::tui::worker::Worker;
    let text = DEFAULT_SCENE_TOML
        .replacen(
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ndensity = 7850.0",
            1,
        )
        .replacen("angle_weight = 1.0", "angle_weight = 1.0\nmodes = 3", 1);
    let scene = Scene::from_toml_str(&text, "dynamic.toml").unwrap();
    let mut app = App::new(scene, None);
    app.jobs.fidelity = Fidelity::Normal;
    let t0 = Instant::now();
    app.edit.focus = Panel::Matrix;
    app.edit.matrix_state.row = 1;
    app.edit.matrix_state.col = 3;
    edit(&mut app, "0.3", t0);
    let rows = app.edit.matrix.rows();
    assert_eq!(rows[1].mu, Some(0.3));
    let sum: f64 = rows.iter().map(|r| r.mass()).sum();
    assert!((sum - 1.0).abs() < 1e-12, "mus sum to {sum}");

    app.on_key(key(KeyCode::Char('f')), t0);
    assert!(!app.edit.matrix.rows()[1].is_free(Column::Mu));
    app.on_key(key(KeyCode::Char('f')), t0);
    assert!(app.edit.matrix.rows()[1].is_free(Column::Mu));

    let before = app.edit.matrix.clone();
    edit(&mut app, "-0.1", t0);
    assert_eq!(app.edit.matrix, before, "a bad mu leaves the matrix");
    let (message, _) = app.message.clone().expect("a message");
    assert!(message.contains("mu"), "{message}");

    // The live refit: the debounced job, answered by the real worker.
    let Some(Command::Submit(job)) = app.tick(t0 + DEBOUNCE * 2) else {
        panic!("a refit")
    };
    assert_eq!(job.kind, prbfit::tui::worker::JobKind::Fit);
    let worker = Worker::spawn().unwrap();
    let last = common::tui::run_job(&mut app, &worker, job);
    assert!(matches!(last, WorkerMsg::Done { .. }), "{last:?}");
    let model = app.shown.model().expect("a fitted model");
    let err = model.figures.max_freq_err.expect("frequencies judged");
    let target = app.edit.scene.accuracy.max_freq_err;
    assert!(err <= target, "the refit rings {err} off (target {target})");
    let su = PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
    let study = Study::new(&app.edit.scene, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let uniform = study.frequencies(&su).unwrap().max_err();
    assert!(
        uniform > 10.0 * target,
        "Su's 3R with uniform mass: {uniform}"
    );
}
