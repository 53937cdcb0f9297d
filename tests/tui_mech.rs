//! The UI on mechanism scenes (DESIGN §8, issue 13), without a terminal: a mechanism scene
//! opens, its panel edits the flexures, the stage and the drives (valid edits queue one job,
//! invalid ones change nothing), `p` keeps a drive's end state, results are taken with the
//! exact mechanism they were judged on, the real worker judges and fits the PRB mechanism,
//! and no key sequence panics with mechanism results on screen.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::sync::Arc;
use std::time::{Duration, Instant};

use prbfit::fit::Fidelity;
use prbfit::io::ModelFile;
use prbfit::scene::{Attach, Coordinate, Scene};
use prbfit::tui::app::{Activity, App, Command, Panel, DEBOUNCE};
use prbfit::tui::run_command;
use prbfit::tui::state::mech::{fields, MechField};
use prbfit::tui::worker::{model_view, truth_view, FitStatus, JobKind, Worker, WorkerMsg};
use ratatui::crossterm::event::KeyCode;

mod common;

use common::tui::{any_key, drive, edit, job_of, key, press, scene, scene_path, study};

/// The app on `name`, focused on the mechanism panel's row `field`.
fn at_field(name: &str, field: MechField) -> App {
    common::tui::at_field(&scene_path(name), field)
}

/// The app on `name` with the exact mechanism and `model`'s PRB mechanism shown, on the
/// mechanism panel.
fn judged(name: &str, model: &str) -> App {
    common::tui::judged_mechanism(&scene_path(name), model, 0.0)
}

/// `prbfit tui MECH` starts on the mechanism (no refusal) and `o` opens one over a
/// cantilever: the middle panel becomes the mechanism's and the job carries the mechanism.
#[test]
fn mechanism_scenes_open() {
    let t0 = Instant::now();
    let mut app = App::new(Scene::builtin(), None);
    app.edit.focus = Panel::Loads;
    assert!(run_command(&mut app, Command::OpenScene(scene_path("slider-crank")), t0).is_none());
    assert!(app.edit.is_mechanism(), "{:?}", app.message);
    assert_eq!(app.edit.focus, Panel::Mechanism);
    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert!(job.scene.mechanism.is_some());
    // Tab cycles beam, mechanism, matrix.
    app.edit.focus = Panel::Beam;
    app.on_key(key(KeyCode::Tab), t0);
    assert_eq!(app.edit.focus, Panel::Mechanism);
    app.on_key(key(KeyCode::Tab), t0);
    assert_eq!(app.edit.focus, Panel::Matrix);
    // Back to a cantilever: the load paths again.
    app.edit.focus = Panel::Mechanism;
    run_command(&mut app, Command::OpenScene(scene_path("default")), t0);
    assert_eq!(app.edit.focus, Panel::Loads);
    assert!(app.shown.result.is_none());
}

/// A valid edit on the mechanism panel changes the scene and queues exactly one fit.
#[test]
fn drive_edits_queue_one_refit() {
    let t0 = Instant::now();
    let mut app = at_field("slider-crank", MechField::Coordinate { drive: 0, c: 1 });
    let cmds = edit(&mut app, "20", t0);
    assert!(cmds.is_empty(), "debounced");
    let m = app.edit.scene.mechanism.as_ref().unwrap();
    assert_eq!(m.drives[0].coordinates[1], Coordinate::Prescribed(0.02));
    assert!(app.unsaved());
    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Fit, "live refit is on");
    assert_eq!(
        job.scene.mechanism.as_ref().unwrap().drives[0].coordinates[1],
        Coordinate::Prescribed(0.02)
    );
    assert!(app.tick(t0 + DEBOUNCE * 3).is_none(), "exactly one");
}

/// Invalid entries are rejected with a message naming what is wrong; nothing changes and no
/// job is queued.
#[test]
fn invalid_mechanism_edits_change_nothing() {
    let t0 = Instant::now();
    let cases: &[(MechField, &str, &str)] = &[
        (MechField::Root(0), "abc", "root"),
        (MechField::Root(0), "1, 2, 3", "x, y"),
        (MechField::Angle(0), "inf", "finite"),
        (MechField::Attach(0), "welded", "clamped, pinned or link"),
        // The coupler's stage end on the flexure's own tip: zero length.
        (MechField::Coupler(0), "50, 0", "zero length"),
        (MechField::Steps(0), "0", "steps"),
        (MechField::Steps(0), "99999", "steps"),
        (MechField::Coordinate { drive: 0, c: 1 }, "1e999", "finite"),
        // Every coordinate zero: the drive goes nowhere.
        (MechField::Coordinate { drive: 0, c: 1 }, "0", "nowhere"),
        // The stage point onto the flexure's tip: the coupler, which ends on the stage
        // point, would have zero length.
        (MechField::StagePoint, "50, 0", "zero length"),
    ];
    for &(field, text, needle) in cases {
        let mut app = at_field("slider-crank", field);
        let scene = app.edit.scene.clone();
        edit(&mut app, text, t0);
        assert_eq!(app.edit.scene, scene, "{field:?} {text}");
        let (message, _) = app.message.clone().expect("a message");
        assert!(
            message.to_lowercase().contains(needle),
            "{field:?} {text}: {message}"
        );
        assert!(app.tick(t0 + DEBOUNCE * 2).is_none(), "{text}: no job");
        assert!(!app.unsaved(), "{text}");
    }
}

/// A UI edit meets the rule the scene file's reader applies, and says what the reader says
/// (its key and message, without the file and line): the stage point onto the flexure's tip
/// (the coupler, which ends on it, would have no length), and a negative beam thickness.
#[test]
fn edits_are_refused_with_the_readers_words() {
    let t0 = Instant::now();
    let reader_says = |scene: &Scene| {
        let e = Scene::from_toml_str(&scene.to_toml(), "s.toml").unwrap_err();
        assert!(e.line.is_some(), "{e}");
        format!("{}: {}", e.key.unwrap(), e.message)
    };
    let mut app = at_field("slider-crank", MechField::StagePoint);
    let mut bad = app.edit.scene.clone();
    let m = bad.mechanism.as_ref().unwrap();
    bad.mechanism = Some(m.with_stage_point(m.flexures[0].tip()));
    let words = reader_says(&bad);
    assert!(words.starts_with("flexures[1].link_to: the coupler would have zero length"));
    let before = app.edit.scene.clone();
    edit(&mut app, "50, 0", t0);
    let (message, _) = app.message.clone().expect("a message");
    assert!(message.contains(&words), "{message} / {words}");
    assert_eq!(app.edit.scene, before);

    let mut app = App::new(scene("slider-crank"), None);
    app.edit.focus = Panel::Beam;
    app.edit.beam_state.row = 2;
    let mut bad = app.edit.scene.clone();
    bad.beam.thickness = -0.001;
    let words = reader_says(&bad);
    assert_eq!(
        words,
        "beam.thickness: must be a finite number > 0, got -0.001"
    );
    edit(&mut app, "-1 mm", t0);
    let (message, _) = app.message.clone().expect("a message");
    assert!(message.contains(&words), "{message} / {words}");
    assert_eq!(app.edit.scene, before);
}

/// `p` on a prescribed coordinate makes it the load that holds the exact mechanism where
/// the drive took it, and back; on the attach row it cycles the attachments that make a
/// valid mechanism.
#[test]
fn p_keeps_the_end_state_and_cycles_attachments() {
    let t0 = Instant::now();
    let mut app = judged("slider-crank", "su-3r");
    app.edit.focus = Panel::Mechanism;
    let m = app.edit.scene.mechanism.clone().unwrap();
    app.edit.mech_state.row = fields(&m)
        .iter()
        .position(|f| *f == MechField::Coordinate { drive: 0, c: 1 })
        .unwrap();
    let truth = app.shown.result.clone().unwrap().truth;
    let end = truth.cases[0].last().unwrap();
    let units = prbfit::si::MechUnits::new(&m);
    press(&mut app, 'p', t0);
    let toggled = app.edit.scene.mechanism.clone().unwrap();
    match toggled.drives[0].coordinates[1] {
        Coordinate::Loaded(f) => {
            assert!((f - end.stage_load[1] * units.force).abs() < 1e-12, "{f}");
            assert!(f.abs() > 1.0, "a real force, N: {f}");
        }
        other => panic!("{other:?}"),
    }
    assert!(app.tick(t0 + DEBOUNCE).is_some());
    // The exact view is of the old drive now: toggling back cannot use it, so it is zero,
    // which leaves a drive going nowhere -- refused.
    press(&mut app, 'p', t0);
    assert!(app.message.as_ref().unwrap().0.contains("nowhere"));
    assert_eq!(app.edit.scene.mechanism.as_ref().unwrap(), &toggled);

    // The attach row: link -> clamped (pinned comes next).
    let mut app = at_field("slider-crank", MechField::Attach(0));
    press(&mut app, 'p', t0);
    assert_eq!(
        app.edit.scene.mechanism.as_ref().unwrap().flexures[0].attach,
        Attach::Clamped
    );
    press(&mut app, 'p', t0);
    assert_eq!(
        app.edit.scene.mechanism.as_ref().unwrap().flexures[0].attach,
        Attach::Pinned
    );
    // Pinned -> link: the coupler ends at the stage point again.
    press(&mut app, 'p', t0);
    let m = app.edit.scene.mechanism.as_ref().unwrap();
    assert_eq!(m.flexures[0].attach, Attach::Link { to: m.stage_point });
}

/// `a` copies the selected drive after it, `d` deletes it (one is kept); the charts follow
/// the new drive; on a flexure's row they say what they can do instead.
#[test]
fn drives_are_added_and_deleted() {
    let t0 = Instant::now();
    let mut app = at_field("slider-crank", MechField::Steps(0));
    press(&mut app, 'd', t0);
    assert!(app
        .message
        .as_ref()
        .unwrap()
        .0
        .contains("at least one drive"));
    press(&mut app, 'a', t0);
    let m = app.edit.scene.mechanism.clone().unwrap();
    assert_eq!(m.drives.len(), 2);
    assert_eq!(m.drives[0], m.drives[1]);
    assert_eq!(app.edit.shown_path(), 1);
    assert_eq!(app.edit.mech_field().and_then(MechField::drive), Some(1));
    press(&mut app, 'd', t0);
    assert_eq!(app.edit.scene.mechanism.as_ref().unwrap().drives.len(), 1);
    assert_eq!(app.edit.shown_path(), 0);
    app.edit.mech_state.row = 0;
    press(&mut app, 'a', t0);
    assert!(app.message.as_ref().unwrap().0.contains("drive"));
    assert_eq!(app.edit.scene.mechanism.as_ref().unwrap().drives.len(), 1);
}

/// A beam edit on a mechanism scene reaches every flexure that does not override it, and
/// the reaction target and force weight are fields of the beam panel.
#[test]
fn beam_edits_reach_the_flexures() {
    use prbfit::tui::state::beam::BeamField;
    let t0 = Instant::now();
    let mut app = App::new(scene("parallel-stage"), None);
    app.edit.focus = Panel::Beam;
    let fields = BeamField::of(true);
    app.edit.beam_state.row = fields
        .iter()
        .position(|f| *f == BeamField::Thickness)
        .unwrap();
    edit(&mut app, "0.6 mm", t0);
    let m = app.edit.scene.mechanism.as_ref().unwrap();
    assert!(m.flexures.iter().all(|f| f.beam.thickness == 0.6e-3));
    app.edit.beam_state.row = fields
        .iter()
        .position(|f| *f == BeamField::MaxForceErr)
        .unwrap();
    edit(&mut app, "0.02", t0);
    assert_eq!(app.edit.scene.accuracy.max_force_err, 0.02);
    app.edit.beam_state.row = fields
        .iter()
        .position(|f| *f == BeamField::ForceWeight)
        .unwrap();
    edit(&mut app, "-1", t0);
    assert!(app.message.as_ref().unwrap().0.contains("force_weight"));
    // 1 / 2 / 3 switch the flexures' effects too.
    press(&mut app, '1', t0);
    let e = app.edit.scene.beam.effects;
    assert!(app
        .edit
        .scene
        .mechanism
        .as_ref()
        .unwrap()
        .flexures
        .iter()
        .all(|f| f.beam.effects == e));
}

/// Results are taken only from the newest job; the compared model is drawn only with the
/// exact mechanism it was judged on.
#[test]
fn mechanism_results_follow_the_newest_job() {
    let mut app = judged("slider-crank", "howell-1r");
    let result = app.shown.result.take().unwrap();
    let (truth, model) = (result.truth, result.model);
    let (Command::Submit(old), Command::Submit(new)) = (app.submit(true), app.submit(true)) else {
        panic!("jobs expected")
    };
    let progress = |id| WorkerMsg::Progress {
        id,
        truth: truth.clone(),
        model: Box::new(model.clone()),
        status: FitStatus {
            phase: "polish",
            iteration: 1,
            evaluations: 2,
            seconds: 0.0,
        },
        compare: None,
    };
    assert!(!app.on_worker(progress(old.id)));
    assert!(app.shown.result.is_none());
    assert!(app.on_worker(progress(new.id)));
    assert!(app.shown.model().is_some() && app.shown.truth().is_some());
    assert!(matches!(app.jobs.activity, Activity::Fitting(_)));
    // A compared model on another exact mechanism is not drawn.
    let su = ModelFile::load("su-3r").unwrap().prb;
    app.shown.compare = Some(("su-3r".into(), su.clone()));
    let (other, su_view) = {
        let mut s = app.edit.scene.clone();
        s.mechanism.as_mut().unwrap().drives[0].steps = 4;
        let other = study(&s, Fidelity::Normal);
        let truth = truth_view(&other, &prbfit::cancel::CancelToken::new()).unwrap();
        (Arc::new(truth), model_view(&other, &su).unwrap())
    };
    assert!(app.on_worker(WorkerMsg::Compared {
        id: 99,
        truth: other,
        model: Box::new(su_view),
    }));
    assert!(app.shown.shown_compare().is_none());
    let su_view = model_view(&study(&app.edit.scene, Fidelity::Normal), &su).unwrap();
    app.on_worker(WorkerMsg::Compared {
        id: 100,
        truth,
        model: Box::new(su_view),
    });
    assert!(app.shown.shown_compare().is_some());
}

/// `e` exports the PRB mechanism through the worker: MJCF (after the links' density) and the
/// model file; a format a mechanism has no place in is refused, saying which work. Selection
/// opens the mechanism's own view, takes its rows and its choice, and loads the chosen model.
#[test]
fn export_and_selection_run_on_the_mechanism() {
    use prbfit::tui::app::PromptKind;
    let dir = std::env::temp_dir().join(format!("prbfit-ui-mech-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let t0 = Instant::now();
    let mut app = App::new(scene("slider-crank"), None);
    let worker = Worker::spawn().unwrap();
    let export = |app: &mut App, file: &str| -> Result<(), String> {
        press(app, 'e', t0);
        assert!(matches!(app.prompt, Some((PromptKind::ExportMechanism, _))));
        let path = dir.join(file);
        let mut cmds = Vec::new();
        for _ in 0..40 {
            app.on_key(key(KeyCode::Backspace), t0);
        }
        for c in path.display().to_string().chars() {
            press(app, c, t0);
        }
        cmds.extend(app.on_key(key(KeyCode::Enter), t0));
        if matches!(app.prompt, Some((PromptKind::ExportDensity, _))) {
            cmds.extend(app.on_key(key(KeyCode::Enter), t0));
        }
        let [cmd] = <[Command; 1]>::try_from(cmds).unwrap();
        let job = run_command(app, cmd, t0).expect("an export job");
        worker.submit(job);
        loop {
            let msg = worker
                .messages
                .recv_timeout(Duration::from_secs(60))
                .unwrap();
            if let WorkerMsg::Exported { result, .. } = msg {
                return result;
            }
        }
    };
    export(&mut app, "slider.xml").unwrap();
    let text = std::fs::read_to_string(dir.join("slider.xml")).unwrap();
    assert!(text.contains("<mujoco"), "{text}");
    export(&mut app, "slider.toml").unwrap();
    let text = std::fs::read_to_string(dir.join("slider.toml")).unwrap();
    assert!(text.contains("max_force_err"), "{text}");
    let e = export(&mut app, "slider.urdf").unwrap_err();
    assert!(e.contains("mjcf"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();

    app.jobs.fidelity = Fidelity::Draft;
    let cmds = press(&mut app, 'S', t0);
    let [Command::Submit(job)] = &cmds[..] else {
        panic!("{cmds:?}")
    };
    assert_eq!(job.kind, JobKind::Select);
    assert!(app.shown.select.is_some());
    let id = job.id;
    worker.submit(job.clone());
    let (mut rows, mut fitting) = (0, 0);
    loop {
        let msg = worker
            .messages
            .recv_timeout(Duration::from_secs(120))
            .unwrap();
        assert_eq!(msg.id(), id);
        let done = matches!(msg, WorkerMsg::SelectDone { .. });
        rows += usize::from(matches!(msg, WorkerMsg::SelectRow { .. }));
        let fit = matches!(msg, WorkerMsg::Fitting { .. });
        assert!(!matches!(msg, WorkerMsg::Failed { .. }), "{msg:?}");
        app.on_worker(msg);
        // Between rows, the ladder's fit shows in the status bar as any fit does.
        if fit {
            fitting += 1;
            assert!(matches!(app.jobs.activity, Activity::Fitting(_)));
        }
        // A row ends its fit: the status does not freeze on it.
        if matches!(app.jobs.activity, Activity::Fitting(_)) {
            assert!(fit, "still fitting after a message that was no fit's");
        }
        if done {
            break;
        }
    }
    let view = app.shown.select.clone().unwrap();
    assert!(!view.running && rows > 0 && fitting > 0);
    // The slider-crank's simplest model meeting its targets is a fitted 1R.
    let chosen = view.chosen.expect("a model meets the targets");
    assert_eq!(view.rows[chosen].topology, "L-R");
    assert!(view.rows[chosen].figures.max_force() < app.edit.scene.accuracy.max_force_err);
    assert_eq!(view.selected, chosen);
    // Enter loads it (judged as the table showed it) and closes the view.
    let cmds = app.on_key(key(KeyCode::Enter), t0);
    assert!(cmds.is_empty());
    assert!(!app.shown.selection_open());
    assert_eq!(app.edit.matrix, view.rows[chosen].prb);
    let job = job_of(app.tick(t0 + DEBOUNCE));
    assert_eq!(job.kind, JobKind::Judge);
}

/// The case and drive keys move the shape chart and wrap around.
#[test]
fn case_and_drive_keys() {
    let t0 = Instant::now();
    let mut app = judged("parallel-stage", "su-3r");
    let cases = app.shown_cases();
    assert_eq!(app.edit.mech_state.shown_case(cases), Some(cases - 1));
    press(&mut app, '>', t0);
    assert_eq!(app.edit.mech_state.shown_case(cases), Some(0));
    press(&mut app, '<', t0);
    press(&mut app, '<', t0);
    assert_eq!(app.edit.mech_state.shown_case(cases), Some(cases - 2));
    press(&mut app, ']', t0);
    assert_eq!(app.edit.shown_path(), 1);
    assert_eq!(
        app.edit.mech_state.case, None,
        "a new drive is shown at its end"
    );
    press(&mut app, ']', t0);
    assert_eq!(app.edit.shown_path(), 0);
}

/// The real worker on the slider-crank: Howell's 1R, judged, misses the reaction target
/// (its largest reaction error is about 5.8% against 5%); fitted, it meets it. The exact
/// mechanism is solved once for both jobs.
#[test]
fn worker_judges_and_fits_the_slider_crank() {
    let worker = Worker::spawn().unwrap();
    let mut app = App::new(scene("slider-crank"), None);
    app.edit.matrix = ModelFile::load("howell-1r").unwrap().prb;
    let target = app.edit.scene.accuracy.max_force_err;
    let run = |app: &mut App, fit: bool| {
        let Command::Submit(job) = app.submit(fit) else {
            panic!()
        };
        let id = job.id;
        worker.submit(job);
        loop {
            let msg = worker
                .messages
                .recv_timeout(Duration::from_secs(60))
                .unwrap();
            assert_eq!(msg.id(), id, "{msg:?}");
            let done = matches!(msg, WorkerMsg::Done { .. });
            assert!(!matches!(msg, WorkerMsg::Failed { .. }), "{msg:?}");
            app.on_worker(msg);
            if done {
                break;
            }
        }
        app.shown.model().unwrap().figures
    };
    let judged = run(&mut app, false);
    assert!(
        judged.max_force() > target && judged.max_force() < 0.07,
        "{judged:?}"
    );
    let truth = app.shown.result.clone().unwrap().truth;
    let fitted = run(&mut app, true);
    assert!(fitted.max_force() < target, "{fitted:?}");
    assert!(
        Arc::ptr_eq(&truth, &app.shown.result.as_ref().unwrap().truth),
        "cached"
    );
    assert!(matches!(
        app.jobs.activity,
        Activity::Done { stop: Some(_), .. }
    ));
    assert_eq!(
        app.edit.matrix.topology(),
        "L-R",
        "the fit keeps the topology"
    );
}

/// A model that stops part way along a path (DESIGN §6): the UI shows its figures over the
/// cases it followed, marks them PARTIAL on the status line (never a pass), draws what it
/// followed, and says where and why it stopped.
#[test]
fn a_model_that_stops_part_way_is_shown_partial() {
    let dir = common::Scratch::new("tui-partial");
    let path = dir.write("deep.toml", &common::driven_cantilever_pushed_deep());
    let worker = Worker::spawn().unwrap();
    let mut app = common::tui::app_on(std::path::Path::new(&path));
    // One joint at mid-length cannot reach 0.7 L sideways (tests/study.rs).
    app.edit.matrix = prbfit::prb::PrbMatrix::parse("0.5,inf,inf; 0.5,2.0,inf").unwrap();
    let Command::Submit(job) = app.submit(false) else {
        panic!("a judge job")
    };
    let msg = common::tui::run_job(&mut app, &worker, job);
    assert!(matches!(msg, WorkerMsg::Done { .. }), "{msg:?}");
    let model = app.shown.model().unwrap();
    assert_eq!(model.unfollowed.len(), 1, "{:?}", model.unfollowed);
    let u = &model.unfollowed[0];
    assert_eq!(u.path, 1);
    assert!(u.fraction > 0.0 && u.fraction < 1.0, "{u:?}");
    let followed = model.case_count();
    assert!(followed > 0 && followed < 8, "{followed} cases");
    assert!(model.figures.max_pos_err.is_finite());
    let (message, _) = app.message.clone().expect("a message");
    assert!(
        message.contains("the model stops on 1 path (path 1 at"),
        "{message}"
    );
    // The job's own time is not part of the snapshot.
    app.jobs.activity = Activity::Done {
        seconds: 0.01,
        stop: None,
        iterations: 0,
        evaluations: 0,
    };
    let screen = common::tui::render(&app, 120, 40);
    assert!(
        screen.contains("PARTIAL 0/1 paths: path 1 stops at"),
        "{screen}"
    );
    insta::assert_snapshot!("mech_partial_model_120x40", screen);
    // Every case is drawn, the ones past the model's stop with the truth alone.
    for case in 0..8 {
        app.edit.mech_state.case = Some(case);
        common::tui::render(&app, 120, 40);
    }
}

mod no_panics {
    use super::*;
    use proptest::prelude::*;

    /// The mechanism panel's own keys, and what its fields take, drawn more often.
    const MECH_KEYS: &[char] = &['p', 'a', 'd', '<', '>', '[', ']', 'F', '0', '5', '-', ','];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Any key sequence on a mechanism scene with results shown (which the edits make
        /// stale: fewer drives, other steps), rendered at any size, never panics and never
        /// leaves a scene its own file would refuse.
        #[test]
        fn no_input_sequence_panics(keys in proptest::collection::vec(any_key(&[], MECH_KEYS, false), 1..80),
                                    w in 1u16..140, h in 1u16..50) {
            let mut app = judged("slider-crank", "su-3r");
            app.edit.focus = Panel::Mechanism;
            drive(&mut app, &keys, w, h);
            prop_assert!(app.edit.matrix.validate().is_ok());
            let again = Scene::from_toml_str(&app.edit.scene.to_toml(), "check");
            prop_assert!(again.is_ok(), "{:?}", again);
        }
    }
}

/// Issue 25.6: `M` on a mechanism with `[beam] density` draws its first three mode shapes
/// about the unloaded mechanism (grey): the beam mechanism's lines and Su's 3R PRB
/// mechanism's through its joints (`o`), each mode in its colour, displaced by the same
/// scale, with each mode's frequencies (beam / PRB, Hz) in the title.
#[test]
fn mech_mode_shapes_120x40() {
    let text = common::dense_parallel_stage(0.02, 2e-6);
    let mut scene = Scene::from_toml_str(&text, "dense-parallel-stage.toml").unwrap();
    scene.prb = Some(ModelFile::load("su-3r").unwrap().prb);
    let mut app = common::tui::judged_as_given(scene, None);
    app.jobs.activity = Activity::Done {
        seconds: 0.01,
        stop: None,
        iterations: 0,
        evaluations: 0,
    };
    app.on_key(key(KeyCode::Char('M')), Instant::now());
    assert!(app.show_modes);
    let model = app.shown.model().unwrap();
    assert_eq!(model.mode_shapes.len(), 3, "{:?}", model.mode_shapes);
    let screen = common::tui::render(&app, 120, 40);
    assert!(screen.contains(" Mode shapes: beam ─ PRB ─o "), "{screen}");
    let m = &model.mode_shapes[0];
    let first = format!(
        "{}/{}",
        prbfit::tui::units::trim_number(m.beam_hz, 4),
        prbfit::tui::units::trim_number(m.model_hz, 4)
    );
    assert!(screen.contains(&first), "{first} in {screen}");
    assert!(
        screen.contains("displaced about the unloaded mechanism"),
        "{screen}"
    );
    insta::assert_snapshot!("mech_mode_shapes_120x40", screen);
}

/// `M` on a mechanism without `[beam] density` says what the mode shapes need instead of
/// drawing nothing.
#[test]
fn mech_mode_shapes_need_a_density() {
    let mut app = judged("parallel-stage", "su-3r");
    app.on_key(key(KeyCode::Char('M')), Instant::now());
    assert!(app.show_modes);
    assert!(app.shown.model().unwrap().mode_shapes.is_empty());
    let screen = common::tui::render(&app, 120, 40);
    assert!(
        screen.contains("no mode shapes: they need [beam]"),
        "{screen}"
    );
}
