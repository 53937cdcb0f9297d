//! Helpers shared by the integration tests: running the binary, scratch directories, tools a
//! test needs, the independent equilibrium check of a beam shape, and (module [`tui`], with
//! the `tui` feature) driving the UI's app without a terminal.
#![allow(dead_code)]

#[cfg(feature = "tui")]
pub mod tui;

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

/// Fails the test, showing the command's stderr, unless it exited with success.
pub fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The one JSON object a successful command printed.
pub fn json(out: &Output) -> serde_json::Value {
    succeeded(out);
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

// Carlson's symmetric elliptic integrals, for the elastica's closed form (known-answer
// tests of the beam).

/// Carlson's symmetric elliptic integral R_F by duplication (Numerical Recipes' `rf`), iterated until the series remainder is below
/// round-off. Converges for arguments as unequal as 0 and 1e-290 (in ~500 halvings of the
/// logarithmic spread).
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    loop {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        let ave = (x + y + z) / 3.0;
        let (dx, dy, dz) = ((ave - x) / ave, (ave - y) / ave, (ave - z) / ave);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / ave.sqrt();
        }
    }
}

/// Carlson's R_D (Numerical Recipes' `rd`).
pub fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0);
    let (c5, c6) = (0.25 * c3, 1.5 * c4);
    let (mut x, mut y, mut z) = (x, y, z);
    let (mut sum, mut fac) = (0.0, 1.0);
    loop {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lambda));
        fac *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        let ave = 0.2 * (x + y + 3.0 * z);
        let (dx, dy, dz) = ((ave - x) / ave, (ave - y) / ave, (ave - z) / ave);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let ea = dx * dy;
            let eb = dz * dz;
            let ec = ea - eb;
            let ed = ea - 6.0 * eb;
            let ee = ed + ec + ec;
            return 3.0 * sum
                + fac
                    * (1.0
                        + ed * (-c1 + c5 * ed - c6 * dz * ee)
                        + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea)))
                    / (ave * ave.sqrt());
        }
    }
}

/// The seven figures of a mechanism scene's report (DESIGN §8), by their JSON keys.
pub const MECH_FIGURES: [&str; 7] = [
    "rms_pos_err",
    "max_pos_err",
    "rms_ang_err",
    "max_ang_err",
    "objective",
    "rms_force_err",
    "max_force_err",
];

/// A small deterministic Gaussian source (xorshift and Box-Muller): the tests need noise,
/// not a random crate.
pub struct Gauss(pub u64);

impl Gauss {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// The next draw from a normal distribution of mean 0 and deviation `sigma`.
    pub fn next(&mut self, sigma: f64) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        sigma * (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// Noise of `1e-3` L (and rad) on every measured position and angle coordinate: a 3R fitted
/// to the noisy data scene `noisy` and one fitted to the noiseless beam scene `clean`, both
/// judged against `clean`. With `residuals` residuals and 7 free cells, the fit absorbs
/// about `7 / residuals` of the noise's variance: its rms position residual against the
/// noisy data is about `sqrt(e_clean^2 + 2e-6 (1 - 7 / residuals))` (two position
/// coordinates of noise; within 30%: the noise's sample variance over some 50 draws), and
/// the noisy fit is no more than `0.7e-3` L rms further from the truth than the clean one
/// (about `1e-3 sqrt(7 / residuals)` expected; a model that chased the noise would sit about
/// `1.4e-3` L away). Returns the residual and both errors against the truth.
pub fn fit_does_not_chase_the_noise(noisy: &str, clean: &str, residuals: f64) -> [f64; 3] {
    let fit = |scene: &str| {
        json(&prbfit(&[
            "fit",
            "--scene",
            scene,
            "--topology",
            "3R",
            "--json",
        ]))
    };
    let (on_noisy, on_clean) = (fit(noisy), fit(clean));
    let rms = |v: &serde_json::Value| v["rms_pos_err"].as_f64().expect("rms_pos_err");
    let residual = rms(&on_noisy);
    let judged = |m: &serde_json::Value| {
        let matrix = m["prb"].as_str().expect("the fitted matrix");
        rms(&json(&prbfit(&[
            "eval", "--scene", clean, "--prb", matrix, "--json",
        ])))
    };
    let (noisy_truth, clean_truth) = (judged(&on_noisy), judged(&on_clean));
    eprintln!(
        "noise 1e-3 L: residual against the noisy data {residual:.3e} L rms; against the \
         noiseless truth {noisy_truth:.3e} (the noiseless fit's {clean_truth:.3e})"
    );
    let expected = (clean_truth.powi(2) + 2e-6 * (1.0 - 7.0 / residuals)).sqrt();
    assert!(
        (residual - expected).abs() < 0.3 * expected,
        "{residual} vs about {expected}"
    );
    assert!(
        noisy_truth < clean_truth + 0.7e-3,
        "{noisy_truth} vs {clean_truth}"
    );
    [residual, noisy_truth, clean_truth]
}

/// A bad data file and what its error must name: `(what it is, its text, needles)`.
pub type BadFile<'a> = (&'a str, String, &'a [&'a str]);

/// Each bad data file of `cases`, written as `d.csv` in `dir` where the data scene `scene`
/// names it, makes `eval` exit 2 with every needle in its message; then a `d.csv` that is
/// not there and one that is a directory are errors naming the scene's `truth.data` key
/// (the scene file is `s.toml`). Leaves no `d.csv` behind.
pub fn assert_bad_data_files(dir: &Scratch, scene: &str, cases: &[BadFile<'_>]) {
    for (what, text, must) in cases {
        dir.write("d.csv", text);
        let out = prbfit(&["eval", "--scene", scene, "--model", "su-3r"]);
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(2), "{what}: {err}");
        for m in *must {
            assert!(err.contains(m), "{what}: {err:?} lacks {m:?}");
        }
    }
    let _ = std::fs::remove_file(dir.file("d.csv"));
    assert_input_error(
        &prbfit(&["eval", "--scene", scene, "--model", "su-3r"]),
        &["s.toml", "truth.data", "d.csv"],
    );
    std::fs::create_dir(dir.file("d.csv")).expect("a directory where the data should be");
    assert_input_error(
        &prbfit(&["fit", "--scene", scene, "--topology", "1R"]),
        &["s.toml", "truth.data", "d.csv"],
    );
    std::fs::remove_dir(dir.file("d.csv")).expect("the directory removed");
}

/// A mechanism of three flexures of their own sizes and stiffnesses, turned, clamped, pinned
/// and coupled (the per-flexure scaling, the clamps' rotation and every kind of closure at
/// once), without its drives: a scene file's text up to and including `[stage]`, named
/// "mixed attachments".
pub const MIXED_FLEXURES: &str = r#"
name = "mixed attachments"
[beam]
length = 0.05
width = 0.01
thickness = 0.0005
youngs_modulus = 200e9
poisson_ratio = 0.3
effects = ["shear", "extension", "poisson"]
[[flexures]]
root = [0.0, 0.015]
attach = "clamped"
[[flexures]]
root = [0.0, -0.015]
angle_deg = 10.0
attach = "pinned"
length = 0.06
thickness = 0.0006
[[flexures]]
root = [0.08, 0.05]
angle_deg = -90.0
attach = "link"
link_to = [0.06, 0.0]
length = 0.04
youngs_modulus = 150e9
[stage]
point = [0.05, 0.0]
"#;

/// The displacement-driven cantilever (`assets/scenes/driven-cantilever.toml`) pushed 35 mm
/// (0.7 L) in its 8 cases: a chain whose only joint sits at mid-length cannot reach past
/// about half its length sideways, so it stops part way; Su's 3R follows to the end.
pub fn driven_cantilever_pushed_deep() -> String {
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/driven-cantilever.toml"),
    )
    .expect("the shipped scene reads");
    base.lines()
        .map(|l| {
            if l.starts_with("dy = ") {
                "dy = 0.035"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A shipped scene's text (`assets/scenes/NAME.toml`) with steel's `[beam] density` (7850
/// kg/m^3), which its modes need.
pub fn dense_scene_text(name: &str) -> String {
    std::fs::read_to_string(format!(
        "{}/assets/scenes/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("a shipped scene")
    .replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    )
}

/// The parallel stage's text in steel ([`dense_scene_text`]) with a stage of `mass` kg and
/// `inertia` kg m^2 about its point (a flexure weighs 1.96 g).
pub fn dense_parallel_stage(mass: f64, inertia: f64) -> String {
    dense_scene_text("parallel-stage").replacen(
        "point = [0.05, 0.0]",
        &format!("point = [0.05, 0.0]\nmass = {mass}\ninertia = {inertia}"),
        1,
    )
}

/// Runs an FEA report (`fea` or `fea_mechanism`, given as `run`) on `output` at mesh 10 in
/// plane stress, cancelling as soon as its first path's CalculiX run is done; returns whether
/// it reported a result and how many paths it had done.
pub fn fea_cancelled_after_its_first_path<T, E>(
    output: &str,
    run: impl FnOnce(&prbfit::report::fea::FeaArgs, &mut prbfit::report::Control<'_>) -> Result<T, E>,
) -> (bool, usize) {
    use prbfit::report::{Control, Progress};
    let mut args = prbfit::report::fea::FeaArgs::new(output.into());
    args.mesh = 10;
    args.section = Some(prbfit::fea::Section::PlaneStress);
    let cancel = prbfit::fit::CancelToken::new();
    let on_path = cancel.clone();
    let mut paths_done = 0;
    let mut progress = |p: &Progress<'_>| {
        if let Progress::Fea { path, .. } = p {
            paths_done = *path;
            on_path.cancel();
        }
    };
    let mut ctl = Control {
        cancel,
        progress: &mut progress,
    };
    let reported = run(&args, &mut ctl).is_ok();
    (reported, paths_done)
}
