//! End to end: the real binary in tmux, driven like a user (send-keys, capture-pane). It edits
//! a matrix cell and sees the error figures change, then quits through the unsaved-changes
//! question; the terminal is restored on quit and on SIGTERM; and the UI ends when its
//! terminal goes away, idle or in the middle of a fit; on the slider-crank (a mechanism
//! scene) Howell's 1R fails the reaction target and passes once fitted. Where tmux is missing the tests say
//! SKIPPED loudly, and under CI (`CI` set) they fail instead.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::process::Command;
use std::thread::sleep;
use std::time::{Duration, Instant};

/// Whether tmux is there to run the test; under CI a missing tmux is a failure.
fn have_tmux(test: &str) -> bool {
    if tmux(&["-V"]).is_some() {
        return true;
    }
    if std::env::var_os("CI").is_some() {
        panic!("{test}: tmux is not installed, and CI must run the end-to-end UI tests");
    }
    println!("\n*** SKIPPED: tmux not installed, so {test} cannot run ***\n");
    false
}

thread_local! {
    /// The tmux server of the running test. Each test has its own (`tmux -L`): with one
    /// shared server, a test killing its last session ends the server while another test's
    /// `new-session` is connecting, and that test fails for no fault of the UI's.
    static SOCKET: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

fn tmux(args: &[&str]) -> Option<String> {
    let socket = SOCKET.with(|s| s.borrow().clone());
    let mut cmd = Command::new("tmux");
    if let Some(socket) = socket {
        cmd.args(["-L", &socket]);
    }
    let out = cmd.args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Polls the pane until `pred` holds; returns the last screen.
fn wait_for(session: &str, what: &str, pred: impl Fn(&str) -> bool) -> String {
    let t0 = Instant::now();
    loop {
        let screen = tmux(&["capture-pane", "-p", "-t", session]).unwrap_or_default();
        if pred(&screen) {
            return screen;
        }
        if t0.elapsed() > Duration::from_secs(20) {
            let _ = tmux(&["kill-session", "-t", session]);
            panic!("timed out waiting for {what}; screen:\n{screen}");
        }
        sleep(Duration::from_millis(50));
    }
}

/// The J figure on the status line.
fn objective(screen: &str) -> Option<String> {
    let line = screen.lines().find(|l| l.trim_start().starts_with("J "))?;
    Some(
        line.trim_start()[2..]
            .split_whitespace()
            .next()?
            .to_string(),
    )
}

#[test]
fn edit_a_cell_and_see_the_errors_change() {
    if !have_tmux("edit_a_cell_and_see_the_errors_change") {
        return;
    }
    let session = format!("prbfit-e2e-{}", std::process::id());
    let bin = env!("CARGO_BIN_EXE_prbfit");
    SOCKET.with(|s| *s.borrow_mut() = Some(format!("prbfit-test-{session}")));
    tmux(&[
        "new-session",
        "-d",
        "-s",
        &session,
        "-x",
        "120",
        "-y",
        "40",
        bin,
    ])
    .expect("tmux starts the UI");
    // The first fit finishes.
    let screen = wait_for(&session, "the first fit", |s| {
        s.contains("converged") && objective(s).is_some()
    });
    assert!(screen.contains("PRB matrix") && screen.contains("Deformed shapes"));
    let fitted = objective(&screen).unwrap();

    // Pause live refit, so the edit is judged as typed: k_theta of segment 2 -> 9.
    tmux(&["send-keys", "-t", &session, "Space"]).unwrap();
    wait_for(&session, "live refit paused", |s| {
        s.contains("live refit paused")
    });
    tmux(&["send-keys", "-t", &session, "Enter"]).unwrap();
    for _ in 0..12 {
        tmux(&["send-keys", "-t", &session, "BSpace"]).unwrap();
    }
    tmux(&["send-keys", "-t", &session, "9", "Enter"]).unwrap();
    let screen = wait_for(&session, "the edited model judged", |s| {
        s.contains("judged") && objective(s).is_some_and(|j| j != fitted)
    });
    assert!(screen.contains("│2  "), "{screen}");
    let judged: f64 = objective(&screen).unwrap().parse().unwrap();
    assert!(
        judged > fitted.parse::<f64>().unwrap(),
        "a stiffer joint fits worse"
    );

    // Quit: the changed model is unsaved, so it asks first.
    tmux(&["send-keys", "-t", &session, "q"]).unwrap();
    wait_for(&session, "the quit question", |s| s.contains("quit anyway"));
    tmux(&["send-keys", "-t", &session, "y"]).unwrap();
    let t0 = Instant::now();
    while tmux(&["has-session", "-t", &session]).is_some() {
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "the UI did not exit"
        );
        sleep(Duration::from_millis(50));
    }
}

/// The terminal comes back as it was (stty settings compared before and after, the alternate
/// screen left, the cursor shown) when the UI quits and when it is killed with SIGTERM or
/// SIGINT (which left it raw, on the alternate screen, the cursor hidden), and the exit
/// status is the shell's for each: 0, 143, 130.
#[test]
fn terminal_is_restored_on_quit_and_on_sigterm() {
    if !have_tmux("terminal_is_restored_on_quit_and_on_sigterm") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("prbfit-restore-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let session = format!("prbfit-restore-{}", std::process::id());
    SOCKET.with(|s| *s.borrow_mut() = Some(format!("prbfit-test-{session}")));
    tmux(&[
        "new-session",
        "-d",
        "-s",
        &session,
        "-x",
        "120",
        "-y",
        "40",
        "sh",
    ])
    .unwrap();
    let bin = env!("CARGO_BIN_EXE_prbfit");
    for (round, (how, status)) in [("quit", 0), ("sigterm", 143), ("sigint", 130)]
        .iter()
        .enumerate()
    {
        let before = dir.join(format!("before{round}"));
        let after = dir.join(format!("after{round}"));
        // The shell prints the mark only after the UI has exited (the typed command line
        // shows the arithmetic, not its value), with the UI's exit status.
        let mark = format!("RESTORE-DONE-{}-{status}", 100 + round);
        let line = format!(
            "stty -g > {}; {bin}; s=$?; stty -g > {}; echo RESTORE-DONE-$((100+{round}))-$s",
            before.display(),
            after.display()
        );
        tmux(&["send-keys", "-t", &session, &line, "Enter"]).unwrap();
        wait_for(&session, "the UI", |s| {
            s.contains("PRB matrix") && s.contains("converged")
        });
        if *how == "quit" {
            // Nothing edited: the start-up fit is not the user's work, so q quits at once.
            tmux(&["send-keys", "-t", &session, "q"]).unwrap();
        } else {
            let shell = tmux(&["display", "-p", "-t", &session, "#{pane_pid}"]).unwrap();
            let out = Command::new("pgrep")
                .args(["-P", shell.trim()])
                .output()
                .unwrap();
            let pid = String::from_utf8_lossy(&out.stdout).trim().to_string();
            assert!(!pid.is_empty(), "the UI's pid");
            let signal = if *how == "sigterm" { "-TERM" } else { "-INT" };
            let ok = Command::new("kill").args([signal, &pid]).status().unwrap();
            assert!(ok.success());
        }
        wait_for(&session, "the shell after the UI", |s| s.contains(&mark));
        let b = std::fs::read_to_string(&before).unwrap();
        let a = std::fs::read_to_string(&after).unwrap();
        assert_eq!(a, b, "{how}: terminal settings after differ from before");
        let screen = tmux(&[
            "display",
            "-p",
            "-t",
            &session,
            "#{alternate_on} #{cursor_flag}",
        ])
        .unwrap();
        assert_eq!(
            screen.trim(),
            "0 1",
            "{how}: the alternate screen left and the cursor shown"
        );
    }
    let _ = tmux(&["kill-session", "-t", &session]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Whether process `pid` is gone (a zombie waiting for its parent counts as gone).
fn process_gone(pid: u32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(_) => true,
        // The state follows the parenthesised command name.
        Ok(stat) => stat
            .rsplit_once(')')
            .is_some_and(|(_, rest)| rest.trim_start().starts_with('Z')),
    }
}

/// The UI's pid in the session's pane: the pane's process, or its child when a shell runs it.
fn ui_pid(session: &str) -> u32 {
    let pane = tmux(&["display", "-p", "-t", session, "#{pane_pid}"]).expect("the pane's pid");
    let pane: u32 = pane.trim().parse().expect("a pid");
    let comm = std::fs::read_to_string(format!("/proc/{pane}/comm")).unwrap_or_default();
    if comm.trim() == "prbfit" {
        return pane;
    }
    let out = Command::new("pgrep")
        .args(["-P", &pane.to_string(), "prbfit"])
        .output()
        .expect("pgrep");
    String::from_utf8_lossy(&out.stdout)
        .trim()
        .parse()
        .expect("the UI runs under the pane's shell")
}

/// Kills the session under the UI and waits for the UI process to end.
fn kill_terminal_and_wait(session: &str, pid: u32, what: &str) {
    tmux(&["kill-session", "-t", session]).expect("tmux kills the session");
    let t0 = Instant::now();
    while !process_gone(pid) {
        if t0.elapsed() > Duration::from_secs(5) {
            let _ = Command::new("kill")
                .args(["-KILL", &pid.to_string()])
                .status();
            panic!("{what}: the UI (pid {pid}) still runs 5 s after its terminal was closed");
        }
        sleep(Duration::from_millis(50));
    }
}

fn start_ui(session: &str, args: &[&str]) {
    SOCKET.with(|s| *s.borrow_mut() = Some(format!("prbfit-test-{session}")));
    let bin = env!("CARGO_BIN_EXE_prbfit");
    let mut cmd = vec![
        "new-session",
        "-d",
        "-s",
        session,
        "-x",
        "120",
        "-y",
        "40",
        bin,
    ];
    cmd.extend_from_slice(args);
    tmux(&cmd).expect("tmux starts the UI");
}

/// Closing the terminal under an idle UI (tmux kill-session, like an ssh drop) ends it.
#[test]
fn ui_ends_when_its_terminal_is_killed_while_idle() {
    if !have_tmux("ui_ends_when_its_terminal_is_killed_while_idle") {
        return;
    }
    let session = format!("prbfit-hangup-idle-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| s.contains("converged"));
    let pid = ui_pid(&session);
    kill_terminal_and_wait(&session, pid, "idle");
}

/// Closing the terminal in the middle of a long precise fit ends the UI too: quitting never
/// waits on the worker.
#[test]
fn ui_ends_when_its_terminal_is_killed_mid_fit() {
    if !have_tmux("ui_ends_when_its_terminal_is_killed_mid_fit") {
        return;
    }
    let session = format!("prbfit-hangup-fit-{}", std::process::id());
    // The steel flexure with ten times the steps (240 cases): its precise 3R fit lasts
    // seconds, where the shipped scene's now takes about 0.2 s, shorter than the pane's
    // polling may see.
    let dir = std::env::temp_dir().join(format!("prbfit-hangup-fit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let shipped = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/steel-flexure.toml"
    ))
    .unwrap();
    let mut text = String::new();
    for line in shipped.lines() {
        match line.strip_prefix("steps = ") {
            Some(steps) => text += &format!("steps = {}0\n", steps.trim()),
            None => text += &format!("{line}\n"),
        }
    }
    assert!(
        text.contains("steps = 40"),
        "the scene's steps were not scaled"
    );
    let scene_path = dir.join("steel-many.toml");
    std::fs::write(&scene_path, text).unwrap();
    let scene = scene_path.to_str().unwrap();
    start_ui(&session, &["tui", scene]);
    wait_for(&session, "the UI", |s| s.contains("PRB matrix"));
    let keys = |k: &[&str]| {
        let mut args = vec!["send-keys", "-t", &session];
        args.extend_from_slice(k);
        tmux(&args).expect("send-keys");
    };
    // Live refit off, so nothing fits before the precise fit is asked for.
    keys(&["Space"]);
    wait_for(&session, "live refit paused", |s| {
        s.contains("live refit paused")
    });
    keys(&["t"]);
    wait_for(&session, "the topology prompt", |s| {
        s.contains("topology (e.g.")
    });
    for _ in 0..30 {
        keys(&["BSpace"]);
    }
    keys(&["L-RP-RP-RP", "Enter"]);
    wait_for(&session, "the new topology", |s| s.contains("L-RP-RP-RP"));
    // v cycles draft, normal, precise: press until precise, whatever the start, each press
    // once the last has shown (on a loaded machine a redraw can lag a fixed pause, and a
    // press too many cycles past precise).
    let fidelity = |s: &str| {
        s.split("fidelity ")
            .nth(1)
            .and_then(|rest| rest.split_whitespace().next())
            .map(str::to_string)
    };
    for _ in 0..3 {
        let s = tmux(&["capture-pane", "-p", "-t", &session]).unwrap_or_default();
        if s.contains("fidelity precise") {
            break;
        }
        let before = fidelity(&s);
        keys(&["v"]);
        wait_for(&session, "the next fidelity", |s| fidelity(s) != before);
    }
    wait_for(&session, "precise fidelity", |s| {
        s.contains("fidelity precise")
    });
    keys(&["r"]);
    wait_for(&session, "the precise fit running", |s| {
        s.contains("fitting ·") || s.contains("working...")
    });
    let pid = ui_pid(&session);
    kill_terminal_and_wait(&session, pid, "mid-fit");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Sends keys to the session's pane.
fn keys(session: &str, k: &[&str]) {
    let mut args = vec!["send-keys", "-t", session];
    args.extend_from_slice(k);
    tmux(&args).expect("send-keys");
}

/// Waits for the session (the UI in it) to end.
fn wait_exit(session: &str, what: &str) {
    let t0 = Instant::now();
    while tmux(&["has-session", "-t", session]).is_some() {
        if t0.elapsed() > Duration::from_secs(10) {
            let screen = tmux(&["capture-pane", "-p", "-t", session]).unwrap_or_default();
            let _ = tmux(&["kill-session", "-t", session]);
            panic!("{what}: the UI did not exit; screen:\n{screen}");
        }
        sleep(Duration::from_millis(50));
    }
}

/// The matrix panel's rows as drawn (the left column only).
fn matrix_rows(screen: &str) -> Vec<String> {
    screen
        .lines()
        .skip_while(|l| !l.contains("#  gamma"))
        .skip(1)
        .take_while(|l| !l.starts_with('└'))
        .map(|l| l.split("││").next().unwrap_or(l).trim_end().to_string())
        .collect()
}

/// Issue 15.4: a rejection is shown on its own line with J still visible, and the next
/// action that succeeds clears it.
#[test]
fn a_rejection_never_hides_j_and_goes_at_the_next_action() {
    if !have_tmux("a_rejection_never_hides_j_and_goes_at_the_next_action") {
        return;
    }
    let session = format!("prbfit-msg-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| {
        s.contains("converged") && objective(s).is_some()
    });
    keys(&session, &["t"]);
    wait_for(&session, "the topology prompt", |s| {
        s.contains("topology (e.g.")
    });
    keys(&session, &["L-X-R", "Enter"]);
    let screen = wait_for(&session, "the rejection", |s| s.contains("rejected"));
    assert!(objective(&screen).is_some(), "J stays visible:\n{screen}");
    assert!(
        screen.contains("PASS") || screen.contains("FAIL"),
        "{screen}"
    );
    // Tab (next panel) succeeds: the old rejection goes.
    keys(&session, &["Tab"]);
    let screen = wait_for(&session, "the message cleared", |s| !s.contains("rejected"));
    assert!(objective(&screen).is_some(), "{screen}");
    keys(&session, &["q"]);
    wait_exit(&session, "quit after a rejected topology");
}

/// Issue 15.5: a fresh start quits at once (the start-up fit is not the user's work); after
/// an edit, `o` asks before it would throw the edit away.
#[test]
fn unsaved_means_the_user_changed_something() {
    if !have_tmux("unsaved_means_the_user_changed_something") {
        return;
    }
    let session = format!("prbfit-dirty-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| s.contains("converged"));
    keys(&session, &["q"]);
    wait_exit(&session, "q on a fresh start");

    // A second UI in a session (and tmux server) of its own: the first's server may still be
    // shutting down, and a new-session connecting to it then fails.
    let session = format!("prbfit-dirty2-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| s.contains("converged"));
    // k_theta of segment 2 (the matrix panel has the focus): typing replaces the value.
    keys(&session, &["Enter", "4", "Enter"]);
    wait_for(&session, "the edit accepted", |s| {
        matrix_rows(s).iter().any(|r| r.starts_with("│2 ")) && s.contains("converged")
    });
    keys(&session, &["o"]);
    wait_for(&session, "the open question", |s| {
        s.contains("open another scene anyway")
    });
    keys(&session, &["n"]);
    wait_for(&session, "the question gone", |s| {
        !s.contains("open another scene anyway")
    });
    keys(&session, &["q"]);
    wait_for(&session, "the quit question", |s| s.contains("quit anyway"));
    keys(&session, &["y"]);
    wait_exit(&session, "quit after an edit");
}

/// Issue 15.1: `s` saves the model with the scene; `prbfit tui saved.toml` comes back with
/// that model, figures and all, not with Su's 3R.
#[test]
fn a_saved_scene_reopens_with_its_model() {
    if !have_tmux("a_saved_scene_reopens_with_its_model") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("prbfit-e2e-save-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("saved.toml");
    let path_text = path.display().to_string();
    let session = format!("prbfit-save-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| s.contains("converged"));
    keys(&session, &["t"]);
    wait_for(&session, "the topology prompt", |s| {
        s.contains("topology (e.g.")
    });
    keys(&session, &["2R", "Enter"]);
    // Fitted: converged, and segment 2's k_theta no longer the topology's start value 2.
    let screen = wait_for(&session, "the 2R fitted", |s| {
        let rows = matrix_rows(s);
        s.contains("PRB matrix  L-R-R ")
            && s.contains("converged")
            && rows.len() == 3
            && rows[1].split_whitespace().nth(2) != Some("2")
    });
    let before = matrix_rows(&screen);
    assert_eq!(before.len(), 3, "{screen}");
    keys(&session, &["s"]);
    wait_for(&session, "the save prompt", |s| s.contains("save scene to"));
    keys(&session, &[&path_text, "Enter"]);
    wait_for(&session, "saved", |s| s.contains("saved "));
    keys(&session, &["q"]);
    wait_exit(&session, "quit after saving");

    start_ui(&session, &["tui", &path_text]);
    let screen = wait_for(&session, "the saved scene judged", |s| {
        s.contains("judged") && objective(s).is_some()
    });
    assert!(screen.contains("PRB matrix  L-R-R "), "{screen}");
    assert_eq!(matrix_rows(&screen), before, "the same model:\n{screen}");
    keys(&session, &["q"]);
    wait_exit(&session, "quit the reopened scene");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 15.2: `m` to Chen's 3R shows Chen's own figures (0.126, 3.25: judged, not refitted
/// under live refit), and `C` compares with Su's 3R on a status row of its own while the
/// matrix stays Chen's.
#[test]
fn a_published_model_is_shown_as_published_and_compared() {
    if !have_tmux("a_published_model_is_shown_as_published_and_compared") {
        return;
    }
    let session = format!("prbfit-compare-{}", std::process::id());
    start_ui(&session, &[]);
    wait_for(&session, "the first fit", |s| s.contains("converged"));
    // m: Howell, Su, Chen.
    keys(&session, &["m", "m", "m"]);
    let screen = wait_for(&session, "Chen's 3R judged", |s| {
        s.contains("chen-3r") && s.contains("judged") && objective(s).is_some()
    });
    let rows = matrix_rows(&screen);
    assert!(rows[0].contains("0.126"), "{screen}");
    assert!(rows[1].contains("3.25"), "{screen}");
    // C: Howell, then Su.
    keys(&session, &["C", "C"]);
    let screen = wait_for(&session, "the comparison with Su", |s| {
        s.contains("compared with su-3r")
    });
    let rows = matrix_rows(&screen);
    assert!(rows[1].contains("3.25"), "still Chen's:\n{screen}");
    let j_lines = screen
        .lines()
        .filter(|l| l.trim_start().starts_with("J "))
        .count();
    assert_eq!(
        j_lines, 2,
        "one J for the model, one for the compared:\n{screen}"
    );
    keys(&session, &["q"]);
    // Loading a published model is the user's choice: quitting asks.
    wait_for(&session, "the quit question", |s| s.contains("quit anyway"));
    keys(&session, &["y"]);
    wait_exit(&session, "quit after comparing");
}

/// The largest reaction error on the status line of a mechanism scene, in % of each
/// coordinate's largest reaction, and its verdict: `force 5.81% FAIL<5` is (5.81, false).
fn force_error(screen: &str) -> Option<(f64, bool)> {
    let line = screen.lines().find(|l| l.trim_start().starts_with("J "))?;
    let rest = line.split("| force ").nth(1)?;
    let (value, verdict) = rest.split_once("% ")?;
    Some((value.parse().ok()?, verdict.starts_with("PASS")))
}

/// Whether the status line says the job finished (a judge or a fit's stop reason).
fn finished(screen: &str) -> bool {
    screen
        .lines()
        .find(|l| l.trim_start().starts_with("J "))
        .is_some_and(|l| l.contains("judged ·") || l.contains(" · it "))
}

/// Issue 13.3: the slider-crank opens in the UI; Howell's 1R (`m`) misses the reaction target
/// (about 5.8% against 5%: FAIL); `r` fits it and it passes.
#[test]
fn slider_crank_howell_fails_then_fitted_passes() {
    if !have_tmux("slider_crank_howell_fails_then_fitted_passes") {
        return;
    }
    let session = format!("prbfit-mech-{}", std::process::id());
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/slider-crank.toml"
    );
    start_ui(&session, &["tui", scene]);
    let screen = wait_for(&session, "the start-up fit of the slider-crank", |s| {
        finished(s) && force_error(s).is_some()
    });
    assert!(
        screen.contains("compliant slider-crank") && screen.contains("Mechanism"),
        "{screen}"
    );
    assert!(screen.contains("Fy reaction vs dy"), "{screen}");
    // m: Howell's 1R, judged as published.
    keys(&session, &["m"]);
    let screen = wait_for(&session, "Howell's 1R judged", |s| {
        s.contains("howell-1r") && s.contains("judged ·") && force_error(s).is_some()
    });
    let (judged, pass) = force_error(&screen).unwrap();
    assert!(
        judged > 5.0 && !pass,
        "Howell's 1R fails the 5% target:\n{screen}"
    );
    assert!(screen.contains("FAIL<5"), "{screen}");
    assert!(screen.contains("PRB matrix  L-R "), "{screen}");
    // r: fitted, it passes.
    keys(&session, &["r"]);
    let screen = wait_for(&session, "the 1R fitted", |s| {
        finished(s) && !s.contains("judged ·") && force_error(s).is_some_and(|(_, ok)| ok)
    });
    let (fitted, _) = force_error(&screen).unwrap();
    assert!(fitted < 5.0 && fitted < judged, "{screen}");
    assert!(screen.contains("PASS<5"), "{screen}");
    assert!(screen.contains("PRB matrix  L-R "), "still a 1R:\n{screen}");
    keys(&session, &["q"]);
    // Loading a model and fitting it is the user's work: quitting asks.
    wait_for(&session, "the quit question", |s| s.contains("quit anyway"));
    keys(&session, &["y"]);
    wait_exit(&session, "quit the slider-crank");
}

/// Issue 14.3: the shipped data scene (the wide strip's 3D FEA) opens in the UI: the data
/// line names the file and its hash, the measured tips are markers over the shapes with
/// their legend, the start-up fit against the rows ends with the CLI's `fit` figure (the same
/// start, seed and fidelity give the same fit), and the rows are read-only.
#[test]
fn a_data_scene_opens_with_its_markers_and_is_fitted() {
    if !have_tmux("a_data_scene_opens_with_its_markers_and_is_fitted") {
        return;
    }
    let session = format!("prbfit-data-{}", std::process::id());
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/wide-strip-fea.toml"
    );
    start_ui(&session, &["tui", scene]);
    let screen = wait_for(&session, "the start-up fit against the data", |s| {
        finished(s) && !s.contains("judged ·") && objective(s).is_some()
    });
    for needle in [
        "wide steel strip, 3D FEA",
        "data wide-strip-fea.csv sha256 1d3b0fb1 · beam vs data: J 1.115e-3",
        "Deformed shapes, data path 1 of 2",
        "measured ×  beam ─  PRB ─o",
        "Data rows (read-only)",
    ] {
        assert!(screen.contains(needle), "`{needle}` missing:\n{screen}");
    }
    // Path 1's four measured tips (and the legend's mark).
    assert_eq!(screen.matches('×').count(), 5, "{screen}");
    // The CLI's fit from the UI's start (Su's 3R).
    let su = prbfit::io::ModelFile::load("su-3r").unwrap().prb.to_text();
    let out = Command::new(env!("CARGO_BIN_EXE_prbfit"))
        .args(["fit", "--scene", scene, "--prb", &su, "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cli: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let j = cli["objective"].as_f64().unwrap();
    assert_eq!(objective(&screen).unwrap(), format!("{j:.3e}"), "{screen}");
    // Fitted to the FEA, the 3R meets the strip's targets (README: 4.1e-3 L, 2.3e-3 rad).
    let status = screen
        .lines()
        .find(|l| l.trim_start().starts_with("J "))
        .unwrap();
    assert!(
        status.contains("PASS<0.5") && status.contains("PASS<0.573"),
        "{screen}"
    );
    // The rows cannot be edited.
    keys(&session, &["Tab", "Tab", "Enter"]);
    wait_for(&session, "the read-only message", |s| {
        s.contains("read-only: a data scene's loads are the rows of wide-strip-fea.csv")
    });
    // Nothing was edited: q quits at once.
    keys(&session, &["q"]);
    wait_exit(&session, "quit the data scene");
}

/// The median of `values` (none when empty).
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    (n > 0).then(|| {
        if n % 2 == 1 {
            values[n / 2]
        } else {
            0.5 * (values[n / 2 - 1] + values[n / 2])
        }
    })
}

/// The values of the trace lines named `name`.
fn trace_values(trace: &str, name: &str) -> Vec<f64> {
    trace
        .lines()
        .filter_map(|l| l.strip_prefix(name)?.trim().parse().ok())
        .collect()
}

/// Live refit latency, measured (not a test of it: it prints and asserts nothing about
/// time). The UI runs under tmux with `PRBFIT_TRACE`; `edits` values are typed into one
/// field, each after the previous refit finished; the trace gives, per edit, the time from
/// the accepted edit (the debounce included) to the redrawn chart of the edited model
/// (`edit_to_chart_ms`) and to the chart of its finished fit (`edit_to_done_ms`). Run on a
/// release build:
///
/// `cargo test --release --test tui_tmux -- --ignored --nocapture live_refit_latency`
fn measure_live_refit(what: &str, args: &[&str], focus: &[&str], edits: &[String]) {
    let session = format!("prbfit-latency-{}", std::process::id());
    let trace = std::env::temp_dir().join(format!("{session}.trace"));
    let _ = std::fs::remove_file(&trace);
    SOCKET.with(|s| *s.borrow_mut() = Some(format!("prbfit-test-{session}")));
    let bin = env!("CARGO_BIN_EXE_prbfit");
    let env = format!("PRBFIT_TRACE={}", trace.display());
    let mut cmd = vec![
        "new-session",
        "-d",
        "-s",
        &session,
        "-x",
        "120",
        "-y",
        "40",
        "env",
        &env,
        bin,
    ];
    cmd.extend_from_slice(args);
    tmux(&cmd).expect("tmux starts the UI");
    wait_for(&session, "the start-up fit", |s| {
        s.contains(" · it ") || s.contains("judged ·")
    });
    keys(&session, focus);
    let done_lines = |t: &str| trace_values(t, "edit_to_done_ms").len();
    // Keys that start jobs of their own (a fidelity switch) finish before the edits.
    sleep(Duration::from_secs(2));
    let before = done_lines(&std::fs::read_to_string(&trace).unwrap_or_default());
    for (i, value) in edits.iter().enumerate() {
        keys(&session, &["Enter"]);
        keys(&session, &[value.as_str(), "Enter"]);
        let t0 = Instant::now();
        while done_lines(&std::fs::read_to_string(&trace).unwrap_or_default()) <= before + i {
            if t0.elapsed() > Duration::from_secs(30) {
                let screen = tmux(&["capture-pane", "-p", "-t", &session]).unwrap_or_default();
                let _ = tmux(&["kill-session", "-t", &session]);
                panic!("edit {i} ({value}) never finished; screen:\n{screen}");
            }
            sleep(Duration::from_millis(20));
        }
    }
    let _ = tmux(&["kill-session", "-t", &session]);
    let text = std::fs::read_to_string(&trace).unwrap_or_default();
    let last = |mut v: Vec<f64>| v.split_off(v.len().saturating_sub(edits.len()));
    let chart = last(trace_values(&text, "edit_to_chart_ms"));
    let done = last(trace_values(&text, "edit_to_done_ms"));
    let frames = trace_values(&text, "frame_ms");
    println!(
        "{what}: {} edits; edit to redrawn chart median {:.1} ms (min {:.1}, max {:.1}); \
         edit to fitted chart median {:.1} ms; frame draw median {:.2} ms",
        chart.len(),
        median(chart.clone()).unwrap_or(f64::NAN),
        chart.iter().copied().fold(f64::INFINITY, f64::min),
        chart.iter().copied().fold(0.0, f64::max),
        median(done).unwrap_or(f64::NAN),
        median(frames).unwrap_or(f64::NAN),
    );
    let _ = std::fs::remove_file(&trace);
}

/// Live refit on the slider-crank: 24 edits of the stroke (the mechanism panel's `dy`), at
/// normal and at draft fidelity, against the same on the built-in cantilever (24 edits of a
/// matrix cell).
#[test]
#[ignore = "a measurement: run on a release build with --ignored --nocapture"]
fn live_refit_latency() {
    if !have_tmux("live_refit_latency") {
        return;
    }
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/slider-crank.toml"
    );
    // From the matrix panel, Shift-Tab to the mechanism panel, down to drive 1's y.
    let focus = ["BTab", "Down", "Down", "Down", "Down", "Down", "Down"];
    let strokes: Vec<String> = (0..24).map(|k| format!("{}", 14 + k % 4)).collect();
    measure_live_refit("slider-crank, dy", &["tui", scene], &focus, &strokes);
    // v v: normal, precise, draft.
    let draft = [&focus[..], &["v", "v"]].concat();
    measure_live_refit(
        "slider-crank at draft, dy",
        &["tui", scene],
        &draft,
        &strokes,
    );
    let k_theta: Vec<String> = (0..24)
        .map(|k| format!("{}", 3.3 + 0.1 * (k % 4) as f64))
        .collect();
    measure_live_refit("built-in cantilever, k_theta", &[], &[], &k_theta);
}
