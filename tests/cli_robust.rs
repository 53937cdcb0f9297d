//! The command line as a hostile user meets it (issue "Nothing hangs, spins, panics or
//! replaces what it should not"): output that cannot be written, files that are not files,
//! oversized input, control characters, absurd numbers. Each case was a defect with a repro;
//! each test failed before its fix.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

mod common;

use std::io::Read;
use std::os::unix::fs::FileTypeExt;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{assert_input_error, prbfit, succeeded, Scratch};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prbfit"));
    c.stdin(Stdio::null());
    c
}

/// A character device like /dev/full (major 1, minor 7) inside a scratch directory, so a
/// regression replaces the copy, never the machine's own device. `None` where mknod is not
/// allowed.
fn device_copy(dir: &Scratch) -> Option<String> {
    let p = dir.file("full");
    let ok = Command::new("mknod")
        .args([p.as_str(), "c", "1", "7"])
        .status()
        .is_ok_and(|s| s.success());
    ok.then_some(p)
}

#[test]
fn a_closed_pipe_ends_quietly() {
    for args in [
        &["solve"][..],
        &["solve", "--json"][..],
        &["eval", "--model", "su-3r"][..],
    ] {
        let mut child = bin()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the reading end at once, like `| head -0`.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?}: quiet, but said: {err}");
    }
}

#[test]
fn a_full_disk_is_one_line_and_exit_1() {
    for args in [&["solve"][..], &["solve", "--json"][..]] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = bin().args(args).stdout(Stdio::from(full)).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("cannot write the output"), "{err}");
    }
}

#[test]
fn export_never_replaces_a_device() {
    let dir = Scratch::new("device");
    let Some(dev) = device_copy(&dir) else {
        eprintln!("!!! SKIPPED: mknod is not allowed here, so the device case did NOT run !!!");
        return;
    };
    for force in [false, true] {
        let mut args = vec!["export", "--model", "su-3r", "--format", "mjcf", "-o", &dev];
        if force {
            args.push("--force");
        }
        let out = prbfit(&args);
        assert_input_error(&out, &["not a regular file", "character device"]);
        let meta = std::fs::symlink_metadata(&dev).unwrap();
        assert!(meta.file_type().is_char_device(), "the device was replaced");
    }
}

#[test]
fn export_through_a_symlink_writes_the_target_and_keeps_the_link() {
    let dir = Scratch::new("link");
    let target = dir.write("real.xml", "old");
    let link = dir.file("link.mjcf");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let out = prbfit(&[
        "export", "--model", "su-3r", "--format", "mjcf", "-o", &link, "--force",
    ]);
    succeeded(&out);
    let meta = std::fs::symlink_metadata(&link).unwrap();
    assert!(meta.file_type().is_symlink(), "the link became a file");
    let text = std::fs::read_to_string(&target).unwrap();
    assert!(text.starts_with("<mujoco"), "{text}");
    // A dangling link is refused, and stays as it was.
    let dangling = dir.file("dangling.mjcf");
    std::os::unix::fs::symlink(dir.file("gone.xml"), &dangling).unwrap();
    let out = prbfit(&[
        "export", "--model", "su-3r", "--format", "mjcf", "-o", &dangling, "--force",
    ]);
    assert_input_error(&out, &["does not exist"]);
    assert!(!dir.path().join("gone.xml").exists());
}

#[test]
fn scene_files_that_are_not_files_are_refused_at_once() {
    let dir = Scratch::new("scenes");
    let t0 = Instant::now();
    for path in ["/dev/zero", "/dev/null", dir.file("").as_str()] {
        let out = prbfit(&["solve", "--scene", path]);
        assert_input_error(&out, &["not a regular file"]);
    }
    assert!(t0.elapsed() < Duration::from_secs(20), "reading never ends");
    // Bigger than the cap: refused before it is read.
    let big = dir.file("big.toml");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(17 * 1024 * 1024).unwrap();
    assert_input_error(
        &prbfit(&["solve", "--scene", &big]),
        &["big.toml", "16 MiB"],
    );
}

/// The plain beam with `paths` copies of the load path `path`, solved: its error.
fn solve_paths(tag: &str, paths: usize, path: &str) -> std::process::Output {
    let dir = Scratch::new(tag);
    let mut text = String::from(
        "name = \"huge\"\n[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\n\
         youngs_modulus = 200e9\npoisson_ratio = 0.3\neffects = \"none\"\n",
    );
    for _ in 0..paths {
        text.push_str(path);
    }
    let p = dir.write("huge.toml", &text);
    prbfit(&["solve", "--scene", &p])
}

#[test]
fn a_scene_with_too_many_load_cases_is_refused_before_any_work() {
    assert_input_error(
        &solve_paths("cases", 20, "[[loads]]\nalpha_y = 1.0\nsteps = 10000\n"),
        &["200000 load cases", "100000"],
    );
}

/// The limit counts cases however they are spread: 100001 paths of one step each are
/// refused as surely as 20 paths of 10000 (the reader once searched every key it had read
/// for each new one, and a file of 100001 paths ran for minutes).
#[test]
fn a_scene_of_too_many_load_paths_is_refused_before_any_work() {
    assert_input_error(
        &solve_paths("paths", 100_001, "[[loads]]\nalpha_y = 1.0\n"),
        &["100001 load cases over 100001 paths", "100000"],
    );
}

/// A scene whose name is a terminal attack: colour, a window title, a bell.
const NASTY: &str = "\u{1b}[31mRED\u{1b}]0;pwned\u{7}--x-";

fn nasty_scene(dir: &Scratch) -> String {
    let text = format!(
        "name = {}\n[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\n\
         youngs_modulus = 200e9\npoisson_ratio = 0.3\neffects = \"none\"\n\
         [[loads]]\nalpha_y = 2.0\nsteps = 2\n",
        toml_string(NASTY)
    );
    dir.write("nasty.toml", &text)
}

fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[test]
fn control_characters_never_reach_the_terminal_or_break_an_export() {
    let dir = Scratch::new("nasty");
    let scene = nasty_scene(&dir);
    for args in [
        vec!["solve", "--scene", &scene],
        vec!["eval", "--scene", &scene, "--model", "su-3r"],
    ] {
        let out = prbfit(&args);
        succeeded(&out);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("RED"), "{text}");
        assert!(
            !text.chars().any(|c| c.is_control() && c != '\n'),
            "a control character reached the terminal: {text:?}"
        );
    }
    for (format, name) in [("mjcf", "m.xml"), ("urdf", "m.urdf"), ("sdf", "m.sdf")] {
        let path = dir.file(name);
        let out = prbfit(&[
            "export", "--scene", &scene, "--model", "chen-3r", "--format", format, "-o", &path,
        ]);
        succeeded(&out);
        let text = std::fs::read_to_string(&path).unwrap();
        roxmltree::Document::parse(&text)
            .unwrap_or_else(|e| panic!("{format} is not well-formed XML: {e}\n{text}"));
        assert!(
            !text.contains('\u{1b}'),
            "{format}: an escape character was written"
        );
    }
    // The model files: the scene's name in the title and the fit record, replaced too.
    for name in ["m.toml", "m.json"] {
        let path = dir.file(name);
        succeeded(&prbfit(&[
            "export", "--scene", &scene, "--model", "chen-3r", "-o", &path,
        ]));
        let text = std::fs::read_to_string(&path).unwrap();
        let file = prbfit::io::ModelFile::load(&path).unwrap();
        let title = file.title.unwrap_or_default();
        assert!(title.contains("RED"), "{name}: {title:?}");
        assert!(
            !title.chars().any(char::is_control),
            "{name}: a control character in the title: {title:?}\n{text}"
        );
    }
    // A mechanism's model file too (its title names the mechanism).
    let stage = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/parallel-stage.toml"
    ))
    .unwrap()
    .replacen(
        "name = \"parallel-guiding stage\"",
        &format!("name = {}", toml_string(NASTY)),
        1,
    );
    let stage = dir.write("stage.toml", &stage);
    let path = dir.file("stage-model.toml");
    succeeded(&prbfit(&[
        "export", "--scene", &stage, "--model", "su-3r", "-o", &path,
    ]));
    let title = prbfit::io::ModelFile::load(&path)
        .unwrap()
        .title
        .unwrap_or_default();
    assert!(
        title.contains("mechanism") && title.contains("RED"),
        "{title:?}"
    );
    assert!(!title.chars().any(char::is_control), "{title:?}");
    let csv = dir.file("m.csv");
    let out = prbfit(&[
        "export", "--scene", &scene, "--model", "chen-3r", "--format", "csv", "-o", &csv,
    ]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(!text.contains('\u{1b}') && !text.contains('\u{7}'));
}

#[test]
fn flags_obey_the_scene_rules_and_numbers_print_bounded() {
    assert_input_error(
        &prbfit(&["solve", "--slenderness", "0.5"]),
        &["--slenderness", "from 1"],
    );
    let out = prbfit(&["solve", "--tol", "1e-300"]);
    assert_input_error(&out, &["--tol", "1e-300"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.len() < 200, "a number printed unbounded: {err}");
    // A ratio just below the limit prints as given, not rounded onto the limit (it printed
    // `nu = 0.5`, which the reader refuses).
    let out = prbfit(&[
        "solve",
        "--load",
        "0,1,0",
        "--nu",
        "0.49999999",
        "--effects",
        "all",
    ]);
    succeeded(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("nu = 0.49999999,"), "{text}");
    // A length of 1e300 m is refused (past the largest size, before its slenderness), and
    // the message stays short.
    let dir = Scratch::new("long");
    let p = dir.write(
        "long.toml",
        "[beam]\nlength = 1e300\nwidth = 0.01\nthickness = 0.0005\nyoungs_modulus = 200e9\n\
         poisson_ratio = 0.3\n[[loads]]\nalpha_y = 1\n",
    );
    let out = prbfit(&["solve", "--scene", &p]);
    assert_input_error(&out, &["beam.length", "at most 1000 m"]);
    assert!(
        out.stderr.len() < 300,
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A modulus near f64::MAX overflowed every stress to infinity (JSON null): refused.
    let stiff = |e: &str| {
        format!(
            "[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\nyoungs_modulus = {e}\n\
             poisson_ratio = 0.3\n[[loads]]\nalpha_y = 2\nsteps = 2\n"
        )
    };
    let p = dir.write("stiff.toml", &stiff("1e308"));
    let out = prbfit(&["solve", "--scene", &p]);
    assert_input_error(
        &out,
        &[":5", "beam.youngs_modulus", "at most 1e13", "1e308"],
    );
    // One within the limit but absurd for a stress in MPa prints bounded, in the table and
    // in the limits line.
    let p = dir.write(
        "stiffish.toml",
        &stiff("1e13").replacen(
            "poisson_ratio = 0.3\n",
            "poisson_ratio = 0.3\nallowable_stress = 1e13\n",
            1,
        ),
    );
    let out = prbfit(&["solve", "--scene", &p]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("allowable stress 1e7 MPa"), "{text}");
    let longest = text.split_whitespace().map(str::len).max().unwrap_or(0);
    assert!(longest < 20, "a number printed unbounded: {text}");
}

/// Finite but absurd magnitudes are refused at their line and key (exit 2), before any work:
/// a load or drive past 1e9 nondimensional (alpha 1e308 ran two seconds to give up at 1e-303
/// of its path, exit 1), a mechanism point far beyond its flexures (a stage point at 1e300 m
/// was blamed on "three or more clamped flexures"), a flexure turned 1e300 degrees (was
/// accepted).
#[test]
fn absurd_magnitudes_are_refused_at_their_key() {
    let dir = Scratch::new("absurd");
    let builtin = prbfit::scene::DEFAULT_SCENE_TOML;
    let stage = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/parallel-stage.toml"
    ))
    .unwrap();
    let cases: [(&str, String, &[&str]); 11] = [
        (
            "load",
            builtin.replacen("alpha_y = 5.0", "alpha_y = 1e308", 1),
            &["loads[1].alpha_y", "1e308 is beyond the 1e9"],
        ),
        (
            "drive",
            stage.replacen("fy = 20.0", "fy = 1e308", 1),
            &["drives[1].fy", "1e308", "nondimensional) is beyond the 1e9"],
        ),
        (
            "drive in range in newtons, not nondimensional",
            stage.replacen("fy = 20.0", "fy = 1e11", 1),
            &["drives[1].fy", "1e11 (1.2e10 nondimensional)"],
        ),
        (
            "stage point",
            stage.replacen("point = [0.05, 0.0]", "point = [1e300, 0.0]", 1),
            &[
                "stage.point",
                "1e300 m from flexure 1's root",
                "1e4 lengths",
            ],
        ),
        (
            "angle",
            stage.replacen("angle_deg = 0.0", "angle_deg = 1e300", 1),
            &["flexures[1].angle_deg", "from -360 to 360 degrees", "1e300"],
        ),
        // SI sizes past any beam (a slip of units): at slenderness 100 a beam 1e300 m long
        // was accepted and put inf springs and NaN load ranges into its export, and a width
        // of 1e160 overflowed `solve --json` into an internal error.
        (
            "giant",
            builtin
                .replacen("length = 0.05", "length = 1e300", 1)
                .replacen("thickness = 0.0005", "thickness = 1e298", 1),
            &["beam.length", "at most 1000 m", "1e300"],
        ),
        (
            "wide",
            builtin.replacen("width = 0.01", "width = 1e160", 1),
            &["beam.width", "at most 1000 m", "1e160"],
        ),
        (
            "thin",
            builtin
                .replacen("length = 0.05", "length = 1e-10", 1)
                .replacen("thickness = 0.0005", "thickness = 1e-12", 1),
            &["beam.length", "at least 1e-9 m", "1e-10"],
        ),
        (
            "kappa",
            builtin.replacen(
                "poisson_ratio = 0.3",
                "poisson_ratio = 0.3\nshear_coefficient = 1e300",
                1,
            ),
            &["beam.shear_coefficient", "at most 10", "1e300"],
        ),
        (
            "density",
            builtin.replacen(
                "poisson_ratio = 0.3",
                "poisson_ratio = 0.3\ndensity = 1e-300",
                1,
            ),
            &["beam.density", "at least 0.001 kg/m^3", "1e-300"],
        ),
        (
            "allowable stress",
            builtin.replacen(
                "poisson_ratio = 0.3",
                "poisson_ratio = 0.3\nallowable_stress = 1e300",
                1,
            ),
            &["beam.allowable_stress", "at most 1e13 Pa", "1e300"],
        ),
    ];
    // The flags as the scene's keys: `--kappa 1e300` printed 300 digits, and `--density`
    // at 1e-300 exported masses of 2.5e-308 kg with MuJoCo's default time step.
    assert_input_error(
        &prbfit(&[
            "solve",
            "--load",
            "0,2,0",
            "--effects",
            "all",
            "--kappa",
            "1e300",
        ]),
        &["--kappa", "at most 10", "1e300"],
    );
    for density in ["1e-300", "1e300"] {
        let out = dir.file("dense.xml");
        assert_input_error(
            &prbfit(&[
                "export",
                "--model",
                "su-3r",
                "--format",
                "mjcf",
                "-o",
                &out,
                "--density",
                density,
            ]),
            &["--density", density],
        );
        assert!(
            !std::path::Path::new(&out).exists(),
            "{density}: a file was written"
        );
    }
    // The flag as the scene's key.
    assert_input_error(
        &prbfit(&["solve", "--load", "0,1e308,0"]),
        &["--load", "alpha_y", "1e308 is beyond the 1e9"],
    );
    for (name, text, expected) in cases {
        assert_ne!(text, builtin, "{name}: the replacement missed");
        assert_ne!(text, stage, "{name}: the replacement missed");
        let p = dir.write(&format!("{}.toml", name.replace(' ', "-")), &text);
        assert_input_error(&prbfit(&["solve", "--scene", &p]), expected);
    }
}

#[test]
fn messages_say_what_is_wrong_once() {
    let dir = Scratch::new("msgs");
    let p = dir.write(
        "effects.toml",
        "[beam]\nlength = 0.05\nwidth = 0.01\nthickness = 0.0005\nyoungs_modulus = 200e9\n\
         poisson_ratio = 0.3\neffects = 42\n[[loads]]\nalpha_y = 1\n",
    );
    let out = prbfit(&["solve", "--scene", &p]);
    assert_input_error(&out, &[":7:", "beam.effects", "\"auto\"", "integer `42`"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("untagged"));
    // A matrix starting with a minus sign is a matrix, not a flag.
    let out = prbfit(&["eval", "--prb", "-0.2,inf,inf; 1.2,2,inf"]);
    assert_input_error(&out, &["--prb", "row 1", "gamma"]);
    // An absurdly stiff spring is refused by name, not reported as a buckling point.
    let out = prbfit(&["eval", "--prb", "0.1,inf,inf; 0.9,1e308,inf"]);
    assert_input_error(
        &out,
        &["--prb", "row 2", "k_theta", "at most 1e12", "1e308"],
    );
    // A gamma sum of 1e308 (or 1e-300) is quoted bounded, not in 309 digits.
    for (prb, sum) in [("1e308,2,inf", "1e308"), ("1e-300,2,inf", "1e-300")] {
        let out = prbfit(&["eval", "--prb", prb]);
        assert_input_error(
            &out,
            &["gammas must sum to 1", &format!("they sum to {sum} (")],
        );
        assert!(
            out.stderr.len() < 200,
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // A load past the Euler load: the cause is said once, not twice.
    let out = prbfit(&["eval", "--model", "su-3r", "--load", "-30,0,0"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let first = err.split(": ").nth(1).unwrap_or_default().to_string();
    assert!(
        err.matches(first.as_str()).count() == 1,
        "a cause repeated itself: {err}"
    );
}

#[test]
fn eval_prints_the_effects_decision_like_every_command() {
    let out = prbfit(&["eval", "--model", "su-3r"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("effects auto: kept"), "{text}");
}

#[test]
fn help_to_a_closed_pipe_is_quiet_too() {
    let mut child = bin()
        .arg("--help")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(status.code(), Some(0));
}

/// The built-in scene's text with `steps` steps on each of its load paths (5 each).
fn builtin_with_steps(steps: u32) -> String {
    std::fs::read_to_string(format!(
        "{}/assets/scenes/default.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("steps = 5", &format!("steps = {steps}"))
}

/// Sends SIGINT (Ctrl-C) to `child` once `wait` has passed, and returns its output.
fn interrupt_after(mut child: std::process::Child, wait: Duration) -> std::process::Output {
    std::thread::sleep(wait);
    let pid = child.id().to_string();
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before it could be interrupted; give it more work"
    );
    let sent = Command::new("kill").args(["-INT", &pid]).status().unwrap();
    assert!(sent.success());
    child.wait_with_output().unwrap()
}

/// Ctrl-C stops a long fit at its next check (issue 24: long fits can be cancelled): the best
/// matrix so far is printed with its own figures, marked cancelled, saved where `-o` says
/// (the file marked as stopped early, so nothing reading it takes it for a finished fit), and
/// the status is the shell's 130 for SIGINT.
#[test]
fn ctrl_c_stops_a_long_fit_with_its_best_so_far() {
    let dir = Scratch::new("ctrl-c-fit");
    let model = dir.file("best.toml");
    // Eight RP segments at precise fidelity on the built-in scene at 50 steps a path (400
    // cases at precise's doubled sampling): about 10 s of fitting on the 2-core machine (1.2
    // s at the built-in 5 steps, since the polish's exact Jacobian); the truth takes
    // milliseconds, so two seconds in, the fit is running.
    let scene = dir.write("long.toml", &builtin_with_steps(50));
    let child = bin()
        .args([
            "fit",
            "--scene",
            &scene,
            "--topology",
            "L-RP-RP-RP-RP-RP-RP-RP-RP",
            "--fidelity",
            "precise",
            "-o",
            &model,
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = interrupt_after(child, Duration::from_secs(2));
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(130), "{stdout}\n{stderr}");
    assert!(stdout.contains("cancelled"), "{stdout}");
    assert!(stdout.contains("fitted L-RP-RP"), "{stdout}");
    assert_eq!(
        stderr.trim(),
        "prbfit: interrupted (Ctrl-C): the best so far is above"
    );
    assert!(
        stdout.contains("(marked stopped early: the best so far)"),
        "{stdout}"
    );
    let saved = std::fs::read_to_string(&model).unwrap();
    assert!(saved.contains("stopped_early = \"cancelled\""), "{saved}");
    assert!(
        saved.contains("(stopped early: cancelled; the best so far)"),
        "{saved}"
    );
    // The saved model is whole: eval reads it back and judges it.
    succeeded(&prbfit(&["eval", "--model", &model]));
}

/// Ctrl-C stops a long solve too; a solve cut short prints nothing but says so.
#[test]
fn ctrl_c_stops_a_long_solve_and_prints_nothing_half_done() {
    let dir = Scratch::new("ctrl-c-solve");
    let path = dir.write("big.toml", &builtin_with_steps(10000));
    let child = bin()
        .args(["solve", "--scene", &path])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = interrupt_after(child, Duration::from_millis(300));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(stderr.trim(), "prbfit: interrupted (Ctrl-C)");
}

/// An output whose directory does not exist is refused as bad input before the work is done
/// (the fit's model file, checked with the rest of the arguments), naming the directory; so
/// is one under a plain file.
#[test]
fn an_output_in_a_missing_directory_is_refused_naming_it() {
    let dir = Scratch::new("no-dir");
    let missing = dir.file("missing/fitted.toml");
    let out = prbfit(&[
        "fit",
        "--topology",
        "L-R",
        "--fidelity",
        "draft",
        "-o",
        &missing,
    ]);
    assert_input_error(&out, &["its directory", "missing", "does not exist"]);
    let plain = dir.write("plain", "x");
    let under = format!("{plain}/model.mjcf");
    let out = prbfit(&[
        "export", "--model", "su-3r", "--format", "mjcf", "-o", &under,
    ]);
    assert_input_error(&out, &["Not a directory"]);
    assert!(!dir.path().join("missing").exists());
}
