//! Helpers shared by the integration tests: running the binary, scratch directories, tools a
//! test needs, and the independent equilibrium check of a beam shape.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use prbfit::beam::{BeamModel, BeamSolution};

/// Runs the `prbfit` binary with `args` (no standard input) and returns what it did.
pub fn prbfit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_prbfit"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs")
}

/// The one JSON object a successful command printed.
pub fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

/// Bad input: one line on stderr naming every `must_contain`, exit status 2, nothing on
/// stdout.
pub fn assert_input_error(out: &Output, must_contain: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert!(
        out.stdout.is_empty(),
        "stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    for needle in must_contain {
        assert!(err.contains(needle), "`{needle}` missing from: {err}");
    }
}

/// A scratch directory, removed when dropped.
pub struct Scratch(pub PathBuf);

impl Scratch {
    /// A fresh, empty directory named after `tag` and this process.
    pub fn new(tag: &str) -> Scratch {
        use std::sync::atomic::{AtomicU32, Ordering};
        static N: AtomicU32 = AtomicU32::new(0);
        let p = std::env::temp_dir().join(format!(
            "prbfit-test-{tag}-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::SeqCst)
        ));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).expect("a scratch directory");
        Scratch(p)
    }

    /// A path inside, as a string for command lines.
    pub fn file(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }

    /// Writes `text` to `name` inside; returns its path.
    pub fn write(&self, name: &str, text: &str) -> String {
        let p = self.file(name);
        std::fs::write(&p, text).expect("a scratch file");
        p
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Whether a test that needs an outside tool (`what`, with `check` true when it is there)
/// can run. Missing under CI (the `CI` environment variable `.ci/run` sets) is a failure:
/// CI installs every tool, so a missing one means the check silently did not happen.
/// Elsewhere the test says SKIPPED loudly and passes.
pub fn tool_available(what: &str, check: bool, install: &str) -> bool {
    if check {
        return true;
    }
    let msg =
        format!("!!! SKIPPED: {what} is not available ({install}), so this test did NOT run !!!");
    if std::env::var_os("CI").is_some_and(|v| !v.is_empty()) {
        panic!("{msg} — under CI every tool must be installed by .ci/run");
    }
    eprintln!("{msg}");
    println!("{msg}");
    false
}

/// Whether a command runs and exits 0.
pub fn command_works(program: &str, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Checks a returned shape against the beam's equations *independently of the solver*:
/// fourth-order central differences of the sampled `psi, x, y` against `M(s) / EI(s)` (moment from DESIGN
/// Eq. 3 with the returned tip) and the strained tangent. Returns the largest defect, relative
/// to `1 + |load|`.
pub fn equilibrium_defect(model: &BeamModel, sol: &BeamSolution) -> f64 {
    let (ax, ay, beta) = (sol.load.alpha_x, sol.load.alpha_y, sol.load.beta);
    let (a, b) = (sol.tip.a, sol.tip.b);
    let pts = &sol.shape;
    let scale = 1.0 + sol.load.magnitude();
    let mut worst = 0.0_f64;
    let d = |f: &dyn Fn(&prbfit::beam::ShapePoint) -> f64, w: &[prbfit::beam::ShapePoint]| {
        let h = w[3].s - w[2].s;
        (-f(&w[4]) + 8.0 * f(&w[3]) - 8.0 * f(&w[1]) + f(&w[0])) / (12.0 * h)
    };
    for w in pts.windows(5) {
        let p1 = w[2];
        let (sn, cs) = p1.psi.sin_cos();
        let n = ax * cs + ay * sn;
        let q = -ax * sn + ay * cs;
        let (eps, gamma, stiffness) = model.section_strains(n, q).expect("valid state");
        let m = beta + ay * (a - p1.x) - ax * (b - p1.y);
        let curvature = d(&|p| p.psi, w);
        let dx = d(&|p| p.x, w);
        let dy = d(&|p| p.y, w);
        worst = worst
            .max((curvature * stiffness - m).abs() / scale)
            .max((dx - ((1.0 + eps) * cs - gamma * sn)).abs())
            .max((dy - ((1.0 + eps) * sn + gamma * cs)).abs());
    }
    worst
}
