//! The terminal UI: edit the beam, the loads (or a mechanism's flexures, stage and drives)
//! and the PRB matrix; the worker refits live; the charts show the deformed shapes and the
//! errors (on a mechanism, the force–stroke chart and the reaction error).
//!
//! Both kinds of scene (a cantilever, a mechanism; either with measured data as its truth)
//! go through one path: the worker asks the study layer (DESIGN §7) and sends one set of
//! messages with one truth view and one model view, the app keeps one result slot, and each
//! chart has one renderer.
//!
//! The modules, each using only those before it:
//! - [`units`]: numbers and quantities as typed and shown;
//! - [`panel`]: the panels that take the keyboard;
//! - [`keymap`]: every key, read by the key handling, the help and the hint line;
//! - [`latest_job`]: the newest-job queue;
//! - [`worker`]: the background thread that solves and fits, fed by that queue;
//! - [`state`]: each panel's own state: cursor and edit handling;
//! - [`app`]: the UI's state (editing, job client, what is shown) and its update logic (no
//!   terminal), unit-tested;
//! - [`ui`]: drawing, one file per panel, snapshot-tested;
//! - this module: the terminal and the event loop.
//!
//! The terminal is restored on quit, on error, on SIGINT, SIGQUIT, SIGTERM and SIGHUP (the
//! process then exits with 128 + the signal), and on a panic of the UI thread (a panic hook);
//! a panic inside the worker is caught there and shown as a message, and the UI goes on.
//! With `PRBFIT_TRACE=FILE` the loop writes timings (edit to redrawn chart, edit to the
//! job's final chart, frame draws) and peak memory to FILE, for measuring.

pub mod app;
pub mod keymap;
pub mod latest_job;
#[cfg(test)]
mod layering;
pub mod panel;
pub mod state;
pub mod ui;
pub mod units;
pub mod worker;

use std::fs::OpenOptions;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use ratatui::backend::CrosstermBackend;
use ratatui::crossterm::event::{self, Event};
use ratatui::crossterm::execute;
use ratatui::crossterm::terminal::{
    disable_raw_mode, enable_raw_mode, EnterAlternateScreen, LeaveAlternateScreen,
};
use ratatui::Terminal;

use crate::io::files::{check_target, write_atomic, WriteError};
use crate::scene::Scene;

use app::{App, Command};
use worker::{Job, Worker, WorkerMsg, WORKER_THREAD};

/// Runs the UI on `scene` until the user quits.
pub fn run(scene: Scene, scene_path: Option<PathBuf>) -> Result<()> {
    if !std::io::stdout().is_terminal() || !std::io::stdin().is_terminal() {
        anyhow::bail!(
            "the terminal UI needs a terminal (stdin and stdout); for scripts use the headless \
             commands: prbfit --help"
        );
    }
    let mut app = App::new(scene, scene_path);
    app.mono = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
    let trace = std::env::var_os("PRBFIT_TRACE").map(PathBuf::from);
    install_panic_hook();
    enable_raw_mode().context("cannot switch the terminal to raw mode")?;
    let mut stdout = std::io::stdout();
    if let Err(e) = execute!(stdout, EnterAlternateScreen) {
        restore_terminal();
        return Err(e).context("cannot enter the alternate screen");
    }
    let result = Terminal::new(CrosstermBackend::new(std::io::stdout()))
        .context("cannot open the terminal")
        .and_then(|mut terminal| event_loop(&mut terminal, &mut app, trace.as_deref()));
    restore_terminal();
    result
}

fn restore_terminal() {
    let _ = disable_raw_mode();
    let _ = execute!(
        std::io::stdout(),
        LeaveAlternateScreen,
        ratatui::crossterm::cursor::Show
    );
}

/// Restores the terminal before a UI-thread panic is reported. The worker catches its own
/// panics and reports them as messages, so its panics neither restore the terminal nor print
/// over the screen.
fn install_panic_hook() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().name() == Some(WORKER_THREAD) {
            return;
        }
        restore_terminal();
        default(info);
    }));
}

/// Timings for `PRBFIT_TRACE`.
struct Trace {
    file: std::fs::File,
    /// The job answering the last accepted edit, and when the edit was accepted: until its
    /// first chart is drawn.
    edit_at: Option<(u64, Instant)>,
    /// The same, until the job's final chart (its fit done) is drawn.
    done_at: Option<(u64, Instant)>,
}

impl Trace {
    fn open(path: &Path) -> Option<Trace> {
        OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .ok()
            .map(|file| Trace {
                file,
                edit_at: None,
                done_at: None,
            })
    }

    fn line(&mut self, text: String) {
        let _ = writeln!(self.file, "{text}");
    }
}

fn peak_memory_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The thread that reads the terminal's input, so the UI loop never blocks in it: on a dead
/// terminal (its window closed, an ssh drop) crossterm's read can spin forever on EOF, and the
/// loop must still see the hang-up and end.
struct Input {
    events: Receiver<std::io::Result<Event>>,
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl Input {
    fn spawn() -> std::io::Result<Input> {
        let (tx, events) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let handle = std::thread::Builder::new()
            .name(INPUT_THREAD.into())
            .spawn(move || {
                while !flag.load(Ordering::Relaxed) {
                    let event = match event::poll(INPUT_POLL) {
                        Ok(false) => continue,
                        Ok(true) => event::read(),
                        Err(e) => Err(e),
                    };
                    let failed = event.is_err();
                    if tx.send(event).is_err() || failed {
                        return;
                    }
                }
            })?;
        Ok(Input {
            events,
            stop,
            handle: Some(handle),
        })
    }

    /// Stops the thread; one stuck on a dead terminal is left behind (the process is ending).
    fn shutdown(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = worker::join_within(h, INPUT_POLL * 2);
        }
    }
}

/// The input thread's name.
const INPUT_THREAD: &str = "prbfit-input";
/// How often the input thread looks at its stop flag.
const INPUT_POLL: Duration = Duration::from_millis(50);

/// Whether the terminal is still there: after a hang-up the tty answers every request with an
/// error, so it no longer reads as a terminal.
fn terminal_alive() -> bool {
    std::io::stdin().is_terminal()
}

fn event_loop(
    terminal: &mut Terminal<CrosstermBackend<std::io::Stdout>>,
    app: &mut App,
    trace_path: Option<&Path>,
) -> Result<()> {
    // SIGINT and SIGQUIT (sent by `kill` or a supervisor: in raw mode Ctrl-C is a key),
    // SIGTERM (kill) and SIGHUP (the terminal closed) end the loop like a quit, so the
    // terminal is restored on the way out instead of being left in raw mode; the process then
    // exits with the shell's status for the signal. A second one while the first is being
    // handled ends the process at once, with the same status.
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
    let stop = Arc::new(AtomicBool::new(false));
    let mut received = Vec::new();
    for (signal, name) in [
        (SIGINT, "SIGINT"),
        (SIGQUIT, "SIGQUIT"),
        (SIGTERM, "SIGTERM"),
        (SIGHUP, "SIGHUP"),
    ] {
        let this = Arc::new(AtomicBool::new(false));
        signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, stop.clone())
            .context("cannot install the signal handlers")?;
        signal_hook::flag::register(signal, stop.clone())
            .context("cannot install the signal handlers")?;
        signal_hook::flag::register(signal, this.clone())
            .context("cannot install the signal handlers")?;
        received.push((signal, name, this));
    }
    let worker = Worker::spawn().context("cannot start the worker thread")?;
    let input = Input::spawn().context("cannot start the input thread")?;
    let result = run_loop(terminal, app, trace_path, &worker, &input, &stop);
    // Never wait on a fit: its job is cancelled, and a worker that does not notice within the
    // deadline is left behind as the process ends.
    worker.shutdown(worker::SHUTDOWN_DEADLINE);
    input.shutdown();
    result?;
    match received
        .iter()
        .find(|(_, _, got)| got.load(Ordering::Relaxed))
    {
        Some(&(number, name, _)) => Err(Signalled { number, name }.into()),
        None => Ok(()),
    }
}

/// The UI ended on a signal (SIGINT, SIGQUIT, SIGTERM, SIGHUP), the terminal restored: the
/// process exits with the shell's status for it, 128 + the signal's number.
#[derive(Debug, thiserror::Error)]
#[error("the terminal UI ended on {name}")]
pub struct Signalled {
    /// The signal's number.
    pub number: i32,
    name: &'static str,
}

fn run_loop(
    terminal: &mut Terminal<CrosstermBackend<std::io::Stdout>>,
    app: &mut App,
    trace_path: Option<&Path>,
    worker: &Worker,
    input: &Input,
    stop: &AtomicBool,
) -> Result<()> {
    let mut trace = trace_path.and_then(Trace::open);
    let first = app.start();
    execute_command(app, worker, first, &mut trace);
    let mut redraw = true;
    // When the last key arrived, until the frame that answers it is drawn.
    let mut key_at: Option<Instant> = None;
    // A failed draw on a terminal that is gone ends the loop quietly; otherwise it is an error.
    let draw =
        |terminal: &mut Terminal<CrosstermBackend<std::io::Stdout>>, app: &App| match terminal
            .draw(|f| ui::draw(f, app))
        {
            Ok(_) => Ok(true),
            Err(_) if !terminal_alive() => Ok(false),
            Err(e) => Err(e),
        };
    loop {
        if stop.load(Ordering::Relaxed) || !terminal_alive() {
            break;
        }
        if let Ok(size) = terminal.size() {
            app.too_small = ui::too_small(size.width, size.height);
        }
        if redraw {
            let t0 = Instant::now();
            if !draw(terminal, app)? {
                break;
            }
            if let Some(t) = &mut trace {
                let ms = t0.elapsed().as_secs_f64() * 1e3;
                t.line(format!("frame_ms {ms:.3}"));
                if let Some(at) = key_at.take() {
                    let busy = matches!(app.jobs.activity, app::Activity::Fitting(_));
                    let ms = at.elapsed().as_secs_f64() * 1e3;
                    t.line(format!("key_to_frame_ms {ms:.3} fitting={busy}"));
                }
            }
            redraw = false;
        }
        let busy = app.has_pending() || app.jobs.busy();
        let timeout = if busy {
            Duration::from_millis(5)
        } else {
            Duration::from_millis(100)
        };
        let mut commands = Vec::new();
        let event = match input.events.recv_timeout(timeout) {
            Ok(event) => Some(event),
            Err(RecvTimeoutError::Timeout) => None,
            // The input thread ended: the terminal cannot be read any more.
            Err(RecvTimeoutError::Disconnected) => break,
        };
        match event {
            Some(Ok(Event::Key(key))) => {
                key_at = Some(Instant::now());
                commands.extend(app.on_key(key, Instant::now()));
                redraw = true;
            }
            Some(Ok(Event::Resize(..))) => redraw = true,
            Some(Ok(_)) | None => {}
            // EOF or EIO on the terminal: it is gone.
            Some(Err(_)) => break,
        }
        while let Ok(msg) = worker.messages.try_recv() {
            let shows_model = matches!(msg, WorkerMsg::Progress { .. } | WorkerMsg::Done { .. });
            let id = msg.id();
            let is_done = matches!(msg, WorkerMsg::Done { .. });
            if app.on_worker(msg) {
                redraw = true;
                if let (Some(t), true) = (&mut trace, shows_model) {
                    let first = t.edit_at.filter(|(edit_id, _)| *edit_id == id);
                    let last = t.done_at.filter(|(edit_id, _)| *edit_id == id && is_done);
                    if first.is_some() || last.is_some() {
                        // Drawn at the top of the next pass: include that frame.
                        if !draw(terminal, app)? {
                            return Ok(());
                        }
                    }
                    if let Some((_, at)) = first {
                        let ms = at.elapsed().as_secs_f64() * 1e3;
                        t.line(format!("edit_to_chart_ms {ms:.3}"));
                        t.edit_at = None;
                    }
                    if let Some((_, at)) = last {
                        let ms = at.elapsed().as_secs_f64() * 1e3;
                        t.line(format!("edit_to_done_ms {ms:.3}"));
                        t.done_at = None;
                    }
                }
            }
        }
        if let Some(cmd) = app.tick(Instant::now()) {
            commands.push(cmd);
            redraw = true;
        }
        for cmd in commands {
            execute_command(app, worker, cmd, &mut trace);
        }
        if app.quit {
            break;
        }
    }
    if let (Some(t), Some(kib)) = (&mut trace, peak_memory_kib()) {
        t.line(format!("peak_memory_kib {kib}"));
    }
    Ok(())
}

fn execute_command(app: &mut App, worker: &Worker, cmd: Command, trace: &mut Option<Trace>) {
    let Some(job) = run_command(app, cmd, Instant::now()) else {
        return;
    };
    if let (Some(t), Some(at)) = (trace.as_mut(), app.jobs.edit_accepted_at) {
        // Time from the accepted edit (debounce included) to the chart.
        t.edit_at = Some((job.id, at));
        t.done_at = Some((job.id, at));
    }
    worker.submit(job);
}

/// Carries out a command: the file side effects here (save, open; an export's target is
/// checked), jobs returned for the worker. A save or an export over an existing file asks
/// "overwrite? (y/n)" first, except a save to the scene's own file once the UI has saved it
/// there, which is what saving is; the first save over a file opened as written (by hand,
/// with comments) asks, saying that its layout and comments go.
pub fn run_command(app: &mut App, cmd: Command, now: Instant) -> Option<Job> {
    match cmd {
        Command::Submit(job) => return Some(job),
        Command::SaveScene { path, overwrite } => {
            let own = app.edit.scene_path.as_deref() == Some(path.as_path());
            let overwrite = overwrite || (own && app.edit.saved_here);
            let mut scene = app.edit.scene_to_save();
            // A data scene names its file relative to the scene file: from elsewhere, the
            // same file by another path.
            if let Some(t) = scene.truth.as_mut() {
                t.file = data_file_from(app.edit.scene_path.as_deref(), &t.file, &path);
            }
            let text = scene.to_toml();
            match write_atomic(&path, text.as_bytes(), overwrite) {
                Ok(()) => {
                    app.edit.scene.truth = scene.truth;
                    app.saved(path);
                }
                Err(WriteError::Exists(_)) => {
                    if own {
                        app.set_info(format!(
                            "{}: saving rewrites the file as prbfit writes scenes, without its \
                             comments and layout",
                            path.display()
                        ));
                    }
                    app.ask_overwrite(Command::SaveScene {
                        path,
                        overwrite: true,
                    })
                }
                Err(e) => app.set_error(format!("not saved: {}", worker::write_error(e))),
            }
        }
        Command::OpenScene(path) => match Scene::from_file(&path) {
            Ok(scene) => {
                app.set_scene(scene, path.clone(), now);
                app.set_info(format!("opened {}", path.display()));
            }
            Err(e) => app.set_error(format!("not opened: {e}")),
        },
        Command::Export { path, overwrite } => match check_target(&path, overwrite) {
            Ok(()) => return Some(app.export_job(path, overwrite)),
            Err(WriteError::Exists(_)) => app.ask_overwrite(Command::Export {
                path,
                overwrite: true,
            }),
            Err(e) => app.set_error(format!("not exported: {}", worker::write_error(e))),
        },
    }
    None
}

/// How a scene saved at `target` names the data file that the scene read from `scene_path`
/// names `file` (DESIGN §9: relative to the scene file): `file` itself when the scene stays
/// in its folder (or its folder is unknown), else the data file's path relative to
/// `target`'s folder, or its absolute path when it is not under that folder.
pub fn data_file_from(scene_path: Option<&Path>, file: &str, target: &Path) -> String {
    let folder = |p: &Path| match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let Some(old_dir) = scene_path.map(folder).and_then(|d| d.canonicalize().ok()) else {
        return file.to_string();
    };
    let Ok(new_dir) = folder(target).canonicalize() else {
        // The write will fail (no such folder) and say so; nothing to name.
        return file.to_string();
    };
    if old_dir == new_dir {
        return file.to_string();
    }
    let data = old_dir.join(file);
    let data = data.canonicalize().unwrap_or(data);
    let named = data.strip_prefix(&new_dir).unwrap_or(&data);
    match named.to_str() {
        Some(s) => s.to_string(),
        // A path TOML cannot hold as text: keep the scene's own.
        None => file.to_string(),
    }
}
