//! Driving the UI's [`App`] without a terminal, for the `tui_*` tests: keys, text typed into a
//! field, the shipped scenes, the jobs the app sends, the real worker run to a job's end, and
//! screens rendered into a `TestBackend`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use prbfit::cancel::CancelToken;
use prbfit::fit::Fidelity;
use prbfit::prb::PrbMatrix;
use prbfit::scene::Scene;
use prbfit::study::Study;
use prbfit::tui::app::{App, Command, Judged};
use prbfit::tui::worker::{model_view, study_of, truth_view, Job, Worker, WorkerMsg};
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;

/// A key pressed with no modifier.
pub fn key(code: KeyCode) -> KeyEvent {
    KeyEvent::new(code, KeyModifiers::NONE)
}

/// Presses the character key `c`; the commands it caused.
pub fn press(app: &mut App, c: char, now: Instant) -> Vec<Command> {
    app.on_key(key(KeyCode::Char(c)), now)
}

/// Types `text`, one key per character.
pub fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        press(app, c, now);
    }
}

/// Replaces the selected field's text with `text` and presses Enter; the commands the keys
/// caused.
pub fn edit(app: &mut App, text: &str, now: Instant) -> Vec<Command> {
    let mut out = app.on_key(key(KeyCode::Enter), now);
    for _ in 0..40 {
        app.on_key(key(KeyCode::Backspace), now);
    }
    for c in text.chars() {
        out.extend(press(app, c, now));
    }
    out.extend(app.on_key(key(KeyCode::Enter), now));
    out
}

/// How many of `cmds` are jobs for the worker.
pub fn jobs(cmds: &[Command]) -> usize {
    cmds.iter()
        .filter(|c| matches!(c, Command::Submit(_)))
        .count()
}

/// A shipped scene (or its data file) by file name: `assets/scenes/NAME`.
pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(name)
}

/// A shipped scene file by its name without `.toml`.
pub fn scene_path(name: &str) -> PathBuf {
    shipped(&format!("{name}.toml"))
}

/// A shipped scene, read as `prbfit` reads it.
pub fn scene(name: &str) -> Scene {
    Scene::from_file(&scene_path(name)).expect("a shipped scene reads")
}

/// The app started on the scene file `path`, as `prbfit tui PATH` starts it.
pub fn app_on(path: &Path) -> App {
    App::new(
        Scene::from_file(path).expect("the scene reads"),
        Some(path.to_path_buf()),
    )
}

/// The job a command (a key's, a tick's) sent.
pub fn job_of(cmd: Option<Command>) -> Job {
    match cmd {
        Some(Command::Submit(job)) => job,
        other => panic!("expected a job, got {other:?}"),
    }
}

/// Runs `job` on `worker` and hands every message to `app` until the job is done (its
/// `Done`, `SelectDone`, `Compared` or `Exported`), or fails; the last message.
pub fn run_job(app: &mut App, worker: &Worker, job: Job) -> WorkerMsg {
    let id = job.id;
    worker.submit(job);
    loop {
        let msg = worker
            .messages
            .recv_timeout(Duration::from_secs(120))
            .expect("the worker answers");
        let last = msg.id() == id
            && matches!(
                msg,
                WorkerMsg::Done { .. }
                    | WorkerMsg::Failed { .. }
                    | WorkerMsg::SelectDone { .. }
                    | WorkerMsg::Compared { .. }
                    | WorkerMsg::Exported { .. }
            );
        app.on_worker(msg.clone());
        if last {
            return msg;
        }
    }
}

/// `matrix` judged on `study` as the worker judges it (deterministic: no timing), with the
/// truth it was judged on: what the app shows after a judge job.
pub fn judged(study: &Study, matrix: &PrbMatrix) -> Judged {
    let truth = truth_view(study, &CancelToken::new()).expect("the truth view");
    Judged {
        truth: Arc::new(truth),
        model: model_view(study, matrix).expect("the model view"),
    }
}

/// The app on `scene` (read from `path`, if any) with its own model judged on the scene's
/// truth taken as given ([`Study::as_given`]) at normal fidelity, as the worker judges it
/// (deterministic: no timing).
pub fn judged_as_given(scene: Scene, path: Option<PathBuf>) -> App {
    use prbfit::study::Sampling;
    let mut app = App::new(scene, path);
    let study =
        Study::as_given(&app.edit.scene, Sampling::Fidelity(Fidelity::Normal)).expect("the study");
    app.shown.result = Some(judged(&study, &app.edit.matrix));
    app
}

/// The app on the mechanism scene file `path`, the mechanism panel focused with its cursor
/// on `field`.
pub fn at_field(path: &Path, field: prbfit::tui::state::mech::MechField) -> App {
    use prbfit::tui::app::Panel;
    use prbfit::tui::state::mech::fields;
    let mut app = app_on(path);
    app.edit.focus = Panel::Mechanism;
    let m = app.edit.scene.mechanism.clone().expect("a mechanism scene");
    app.edit.mech_state.row = fields(&m)
        .iter()
        .position(|f| *f == field)
        .expect("the field");
    app
}

/// The study of `scene` at `fidelity` as the worker solves it (`auto` effects decided).
pub fn study(scene: &Scene, fidelity: Fidelity) -> Study {
    study_of(scene, fidelity, &CancelToken::new()).expect("the study")
}

/// The whole screen of `app` at `w` x `h`, as text.
pub fn render(app: &App, w: u16, h: u16) -> String {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).expect("a test terminal");
    terminal
        .draw(|f| prbfit::tui::ui::draw(f, app))
        .expect("the screen draws");
    format!("{}", terminal.backend())
}

/// Presses `keys` 10 ms apart (ticking the debounce after each), drawing the whole screen
/// at `w` x `h` after every key, until the app quits: what the no-panic properties drive.
pub fn drive(app: &mut App, keys: &[KeyEvent], w: u16, h: u16) {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).expect("a test terminal");
    let t0 = Instant::now();
    for (i, k) in keys.iter().enumerate() {
        let now = t0 + Duration::from_millis(10 * i as u64);
        let _ = app.on_key(*k, now);
        let _ = app.tick(now);
        terminal
            .draw(|f| prbfit::tui::ui::draw(f, app))
            .expect("the screen draws");
        if app.quit {
            break;
        }
    }
}

/// The keys the no-panic properties press, each branch equally likely: Enter, Esc, Tab,
/// Shift-Tab, Backspace, the arrows, each of `codes` (say F1), one of `chars` (keys a panel
/// is known to use, drawn more often; none when empty) and any printable character; Ctrl held
/// half the time when `ctrl`.
pub fn any_key(
    codes: &[KeyCode],
    chars: &'static [char],
    ctrl: bool,
) -> impl proptest::strategy::Strategy<Value = KeyEvent> {
    use proptest::prelude::*;
    use proptest::strategy::{BoxedStrategy, Union};
    let mut branches: Vec<BoxedStrategy<KeyCode>> = [
        KeyCode::Enter,
        KeyCode::Esc,
        KeyCode::Tab,
        KeyCode::BackTab,
        KeyCode::Backspace,
        KeyCode::Up,
        KeyCode::Down,
        KeyCode::Left,
        KeyCode::Right,
    ]
    .into_iter()
    .chain(codes.iter().copied())
    .map(|c| Just(c).boxed())
    .collect();
    if !chars.is_empty() {
        branches.push(
            proptest::sample::select(chars)
                .prop_map(KeyCode::Char)
                .boxed(),
        );
    }
    branches.push(
        proptest::char::range(' ', '~')
            .prop_map(KeyCode::Char)
            .boxed(),
    );
    (Union::new(branches), any::<bool>()).prop_map(move |(c, held)| {
        KeyEvent::new(
            c,
            if ctrl && held {
                KeyModifiers::CONTROL
            } else {
                KeyModifiers::NONE
            },
        )
    })
}

/// The model `app.edit.matrix` exported from the UI (the worker's export job) and by `prbfit
/// export --scene scene --prb <the matrix>` into `dir`: the UI's export records the data
/// scene's file `data` (as the scene names it), its `rows` and the hash the app read, and
/// is the CLI's (the same truth record, figures and matrix).
pub fn export_records_the_data_as_the_cli(
    app: &mut App,
    scene: &Path,
    dir: &super::Scratch,
    data: &str,
    rows: usize,
) {
    use prbfit::io::ModelFile;
    let worker = Worker::spawn().expect("the worker starts");
    let ui_file = dir.path().join("ui.toml");
    let msg = {
        let job = job_of(Some(app.export(ui_file.clone())));
        run_job(app, &worker, job)
    };
    assert!(
        matches!(msg, WorkerMsg::Exported { result: Ok(()), .. }),
        "{msg:?}"
    );
    let cli_file = dir.file("cli.toml");
    let out = super::prbfit(&[
        "export",
        "--scene",
        &scene.display().to_string(),
        "--prb",
        &app.edit.matrix.to_text(),
        "-o",
        &cli_file,
    ]);
    super::succeeded(&out);
    let ui = ModelFile::load(&ui_file.display().to_string()).expect("the UI's export reads");
    let cli = ModelFile::load(&cli_file).expect("the CLI's export reads");
    let ui_fit = ui.fit.expect("the UI's export has a fit record");
    let cli_fit = cli.fit.expect("the CLI's export has a fit record");
    let truth = ui_fit.truth.clone().expect("the export records the data");
    assert_eq!(truth.data, data);
    assert_eq!(truth.rows, rows);
    let read = app.edit.scene.truth.as_ref().expect("a data scene");
    assert_eq!(truth.sha256, read.sha256, "the file's hash");
    assert_eq!(ui_fit.truth, cli_fit.truth);
    assert_eq!(ui_fit.figures, cli_fit.figures);
    assert_eq!(ui.prb, cli.prb);
}

/// Saves `app`'s scene at `path` (the UI's save command) and reads it back: it names its
/// data file `named` under `[truth]`, has no `table` (the rows are the data's), and is
/// saved. Returns the scene read back.
pub fn save_data_scene(
    app: &mut App,
    path: &Path,
    named: &str,
    table: &str,
    now: Instant,
) -> Scene {
    let cmd = Command::SaveScene {
        path: path.to_path_buf(),
        overwrite: false,
    };
    assert!(prbfit::tui::run_command(app, cmd, now).is_none());
    // The first save over the file the scene was opened from asks first: yes.
    if app.prompt.is_some() {
        let answer = app.on_key(key(KeyCode::Char('y')), now);
        for cmd in answer {
            assert!(prbfit::tui::run_command(app, cmd, now).is_none());
        }
    }
    assert!(!app.unsaved(), "{:?}", app.message);
    let text = std::fs::read_to_string(path).expect("the saved scene");
    let expect = format!(
        "[truth]\ndata = {}\n",
        toml::Value::String(named.to_string())
    );
    assert!(text.contains(&expect), "{}:\n{text}", path.display());
    assert!(!text.contains(table), "{text}");
    Scene::from_file(path).expect("the saved scene reads back")
}

/// The app on the mechanism scene file `path` with `model` (a published name or model file)
/// judged as the worker judges it at normal fidelity (deterministic: no timing), the job
/// done in `seconds`, the mechanism panel focused.
pub fn judged_mechanism(path: &Path, model: &str, seconds: f64) -> App {
    use prbfit::tui::app::{Activity, Panel};
    let mut app = app_on(path);
    app.edit.matrix = prbfit::io::ModelFile::load(model).expect("the model").prb;
    let study = study(&app.edit.scene, Fidelity::Normal);
    app.shown.result = Some(judged(&study, &app.edit.matrix));
    app.jobs.activity = Activity::Done {
        seconds,
        stop: None,
        iterations: 0,
        evaluations: 0,
    };
    app.edit.focus = Panel::Mechanism;
    app
}
