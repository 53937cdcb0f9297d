//! `prbfit modes`: the natural frequencies of the scene's truth and of PRB models about the
//! same equilibria (DESIGN §10): the unloaded scene, one tip load (`--load`, a cantilever),
//! or every case (`--cases`). JSON `beam: {omega, hz}`, `models: [{model, omega, hz,
//! freq_err}]` (with `--cases`, the same per case under `cases`). Every kind of scene goes
//! through [`crate::study::Study::modes`]; a data scene's modes are its nominal beam's, and the report
//! says the measured data are not dynamic.

use std::fmt;

use serde::Serialize;

use crate::beam::{Load, Resolution};
use crate::io::ModelFile;
use crate::prb::PrbMatrix;
use crate::scene::Scene;
use crate::study::modes::{Equilibria, EquilibriumModes, Frequencies, StudyModesError};
use crate::study::Sampling;

use super::{num, parse_matrix, safe, study, Control, ReportError, Result};

/// `modes`' arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct ModesArgs {
    /// PRB matrices in text form (`--prb`, repeatable).
    pub prb: Vec<String>,
    /// Published model names or model files (`--model`, repeatable). With neither: the
    /// scene's `[prb] matrix` if it has one, else the beam alone.
    pub model: Vec<String>,
    /// How many of the lowest frequencies (`--count`, at least 1).
    pub count: usize,
    /// One tip load of a cantilever instead of the unloaded beam (`--load`).
    pub load: Option<Load>,
    /// Every case of the scene's paths (`--cases`).
    pub cases: bool,
    /// Baseline integrator tolerance (`--tol`).
    pub tol: f64,
}

impl Default for ModesArgs {
    fn default() -> ModesArgs {
        ModesArgs {
            prb: Vec::new(),
            model: Vec::new(),
            count: 3,
            load: None,
            cases: false,
            tol: Resolution::default().tol,
        }
    }
}

/// One model's frequencies at an equilibrium, or why it has none.
#[derive(Debug, Serialize)]
pub struct ModelRow {
    model: String,
    prb: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    omega: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    hz: Option<Vec<f64>>,
    /// Per frequency, `Omega_PRB / Omega_beam - 1`.
    #[serde(skip_serializing_if = "Option::is_none")]
    freq_err: Option<Vec<f64>>,
    /// Every `|freq_err|` within `[accuracy] max_freq_err`.
    #[serde(skip_serializing_if = "Option::is_none")]
    meets_target: Option<bool>,
    /// Why the model has no frequencies here.
    #[serde(skip_serializing_if = "Option::is_none")]
    failure: Option<String>,
}

/// The modes about one equilibrium.
#[derive(Debug, Serialize)]
pub struct CaseModes {
    /// The load path or drive (from 1); absent for the unloaded scene or a given load.
    #[serde(skip_serializing_if = "Option::is_none")]
    path: Option<usize>,
    fraction: f64,
    /// The tip (stage) load, flexure 1's nondimensional `[alpha_x, alpha_y, beta]`.
    load: [f64; 3],
    beam: Frequencies,
    models: Vec<ModelRow>,
}

/// One equilibrium, or every case.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum ModesBody {
    /// The unloaded scene or `--load`.
    One(CaseModes),
    /// `--cases`.
    Cases {
        /// In path order.
        cases: Vec<CaseModes>,
    },
}

/// What `modes` reports.
#[derive(Debug, Serialize)]
pub struct ModesReport {
    scene: String,
    /// `cantilever` or `mechanism`.
    kind: &'static str,
    /// `unloaded`, `load` or `cases`.
    equilibrium: &'static str,
    /// kg/m^3, the scene's `[beam] density`.
    density: f64,
    /// Hz per unit of `Omega` (flexure 1's).
    hz_per_omega: f64,
    max_freq_err: f64,
    /// The body at the tip (a mechanism's stage), SI: `mass` kg, `inertia` kg m^2 about
    /// the tip point (P).
    body: crate::scene::Body,
    /// A data scene: its measured data are not dynamic.
    #[serde(skip_serializing_if = "Option::is_none")]
    note: Option<String>,
    #[serde(flatten)]
    found: ModesBody,
}

/// The models asked for, in order: `--model`s then `--prb`s; with none, the scene's
/// `[prb] matrix` if any.
fn models(args: &ModesArgs, scene: &Scene) -> Result<Vec<(String, PrbMatrix)>> {
    let mut out = Vec::new();
    for name in &args.model {
        let m = ModelFile::load(name)?;
        out.push((m.name.clone(), m.prb));
    }
    for text in &args.prb {
        let m = parse_matrix("--prb", text)?;
        out.push((m.topology(), m));
    }
    if out.is_empty() {
        if let Some(m) = &scene.prb {
            out.push(("scene".to_string(), m.clone()));
        }
    }
    Ok(out)
}

/// A study error as the CLI reports it: bad input naming the key or flag, else a failed
/// computation.
fn modes_error(e: StudyModesError) -> ReportError {
    match e {
        StudyModesError::NoModes => ReportError::input("--count 0: ask for at least 1 mode"),
        StudyModesError::LoadOnMechanism => ReportError::input(format!("--load: {e}")),
        e if e.is_input() => ReportError::input(e.to_string()),
        e => ReportError::failed(&e),
    }
}

/// `prbfit modes` on `scene`.
pub fn modes(scene: &Scene, args: &ModesArgs, ctl: &mut Control<'_>) -> Result<ModesReport> {
    if args.count == 0 {
        return Err(modes_error(StudyModesError::NoModes));
    }
    if args.load.is_some() && args.cases {
        return Err(ReportError::input(
            "--load and --cases: give one (a tip load, or every case of the scene)",
        ));
    }
    if scene.beam.density.is_none() {
        return Err(modes_error(StudyModesError::NoDensity));
    }
    let at = match (args.load, args.cases) {
        (Some(load), _) => {
            if scene.mechanism.is_some() {
                return Err(modes_error(StudyModesError::LoadOnMechanism));
            }
            if let Some(truth) = &scene.truth {
                return Err(ReportError::input(format!(
                    "--load: \"{}\" is a data scene: its load cases are the rows of {} \
                     (their nominal beam's modes: --cases)",
                    safe(&scene.name),
                    safe(&truth.file)
                )));
            }
            Equilibria::Load(load)
        }
        (None, true) => Equilibria::Cases,
        (None, false) => Equilibria::Unloaded,
    };
    let resolution = super::resolution(scene, args.tol)?;
    let named = models(args, scene)?;
    let study = study(scene, Sampling::Every(resolution), ctl)?;
    let matrices: Vec<PrbMatrix> = named.iter().map(|(_, m)| m.clone()).collect();
    let found = study
        .modes(&matrices, at, args.count, &ctl.cancel)
        .map_err(modes_error)?;
    let scene = study.scene();
    let max_freq_err = scene.accuracy.max_freq_err;
    let case = |e: EquilibriumModes| CaseModes {
        path: e.path,
        fraction: e.fraction,
        load: e.load,
        models: named
            .iter()
            .zip(e.models)
            .map(|((name, m), r)| {
                let failed = |why: String| ModelRow {
                    model: name.clone(),
                    prb: m.to_text(),
                    omega: None,
                    hz: None,
                    freq_err: None,
                    meets_target: Some(false),
                    failure: Some(why),
                };
                match r {
                    // Constraints that hold every joint (a slider-crank of 1R flexures with
                    // its slider held) leave nothing to ring: say so, as for a model with no
                    // solution there.
                    Ok(mm) if mm.omega.is_empty() => failed(
                        "no degree of freedom: the mechanism's constraints hold every joint \
                         of this model still about this equilibrium"
                            .to_string(),
                    ),
                    // A model with fewer frequencies than asked (a 1R has one) does not meet
                    // the target on the ones it lacks.
                    Ok(mm) => ModelRow {
                        model: name.clone(),
                        prb: m.to_text(),
                        meets_target: Some(
                            mm.worst() <= max_freq_err && mm.omega.len() >= e.beam.omega.len(),
                        ),
                        omega: Some(mm.omega),
                        hz: Some(mm.hz),
                        freq_err: Some(mm.freq_err),
                        failure: None,
                    },
                    Err(why) => failed(why),
                }
            })
            .collect(),
        beam: e.beam,
    };
    let mut cases: Vec<CaseModes> = found.into_iter().map(case).collect();
    let body = match at {
        Equilibria::Cases => ModesBody::Cases { cases },
        _ => match cases.pop() {
            Some(one) => ModesBody::One(one),
            None => return Err(ReportError::solve("no equilibrium to find the modes about")),
        },
    };
    let density = study.density().map_err(modes_error)?;
    let scale = study.frequency_scale().map_err(modes_error)?;
    Ok(ModesReport {
        scene: scene.name.clone(),
        kind: if scene.mechanism.is_some() {
            "mechanism"
        } else {
            "cantilever"
        },
        equilibrium: match at {
            Equilibria::Unloaded => "unloaded",
            Equilibria::Load(_) => "load",
            Equilibria::Cases => "cases",
        },
        density,
        hz_per_omega: scale.hz(1.0),
        max_freq_err,
        body: scene.body,
        note: scene.truth.as_ref().map(|t| {
            format!(
                "the truth is measured data ({}), which are not dynamic: these are the nominal \
                 beam's modes{}",
                t.file,
                if matches!(at, Equilibria::Cases) {
                    ", about its own equilibria under the measured loads"
                } else {
                    ""
                }
            )
        }),
        found: body,
    })
}

/// A row of numbers in fixed columns.
fn columns(values: &[f64], format: impl Fn(f64) -> String) -> String {
    values
        .iter()
        .map(|&v| format!("{:>13}", format(v)))
        .collect::<String>()
}

impl CaseModes {
    /// The models' column: 12 characters, or the longest name (a fitted model's file name).
    fn name_width(&self) -> usize {
        self.models
            .iter()
            .map(|m| safe(&m.model).chars().count())
            .fold(12, usize::max)
    }
}

impl fmt::Display for CaseModes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.name_width();
        let omega = |w: f64| format!("{w:.6}");
        let hz = |h: f64| num(h);
        writeln!(
            f,
            "{:<n$} {:<6}{}",
            "beam",
            "Omega",
            columns(&self.beam.omega, omega)
        )?;
        writeln!(f, "{:<n$} {:<6}{}", "", "Hz", columns(&self.beam.hz, hz))?;
        for m in &self.models {
            let name = safe(&m.model);
            match (&m.omega, &m.hz, &m.freq_err) {
                (Some(w), Some(h), Some(e)) => {
                    writeln!(f, "{name:<n$} {:<6}{}", "Omega", columns(w, omega))?;
                    writeln!(f, "{:<n$} {:<6}{}", "", "Hz", columns(h, hz))?;
                    writeln!(
                        f,
                        "{:<n$} {:<6}{}",
                        "",
                        "error",
                        columns(e, |x| format!("{:+.3}%", 100.0 * x))
                    )?;
                }
                _ => writeln!(
                    f,
                    "{name:<n$} no frequencies: {}",
                    safe(m.failure.as_deref().unwrap_or("unknown"))
                )?,
            }
        }
        Ok(())
    }
}

impl fmt::Display for ModesReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let about = match (&self.found, self.equilibrium) {
            (ModesBody::One(c), "load") => format!(
                "under the tip load {}",
                Load::new(c.load[0], c.load[1], c.load[2])
            ),
            (ModesBody::Cases { cases }, _) => format!("about each of its {} cases", cases.len()),
            _ => "unloaded".to_string(),
        };
        writeln!(
            f,
            "modes of \"{}\" ({}), {about}",
            safe(&self.scene),
            self.kind
        )?;
        writeln!(
            f,
            "Omega = omega sqrt(rho A0 L^4 / (E I0)){}; density {} kg/m^3: Omega 1 = {} Hz",
            if self.kind == "mechanism" {
                " of flexure 1"
            } else {
                ""
            },
            num(self.density),
            num(self.hz_per_omega)
        )?;
        if !self.body.is_none() {
            writeln!(
                f,
                "{} body: {} kg, {} kg m^2 about {}",
                if self.kind == "mechanism" {
                    "stage"
                } else {
                    "tip"
                },
                num(self.body.mass),
                num(self.body.inertia),
                if self.kind == "mechanism" {
                    "P"
                } else {
                    "the tip point"
                }
            )?;
        }
        if let Some(note) = &self.note {
            writeln!(f, "{}", safe(note))?;
        }
        let width = match &self.found {
            ModesBody::One(c) => c.beam.omega.len(),
            ModesBody::Cases { cases } => cases.first().map_or(0, |c| c.beam.omega.len()),
        };
        let header: String = (1..=width)
            .map(|k| format!("{:>13}", format!("mode {k}")))
            .collect();
        match &self.found {
            ModesBody::One(c) => {
                writeln!(f, "{:<w$}{header}", "", w = c.name_width() + 7)?;
                write!(f, "{c}")?;
                targets(f, std::slice::from_ref(c), self.max_freq_err)
            }
            ModesBody::Cases { cases } => {
                for c in cases {
                    writeln!(
                        f,
                        "{:<w$}{header}",
                        format!(
                            "path {} at {}",
                            c.path.unwrap_or(1),
                            num((c.fraction * 1e6).round() / 1e6)
                        ),
                        w = c.name_width() + 7
                    )?;
                    write!(f, "{c}")?;
                }
                targets(f, cases, self.max_freq_err)
            }
        }
    }
}

/// One line per model: its largest frequency error over the cases against the target.
fn targets(f: &mut fmt::Formatter<'_>, cases: &[CaseModes], target: f64) -> fmt::Result {
    let Some(first) = cases.first() else {
        return Ok(());
    };
    for (i, m) in first.models.iter().enumerate() {
        let rows = cases.iter().filter_map(|c| c.models.get(i));
        let mut worst: f64 = 0.0;
        let mut failed = false;
        let mut fewer = None;
        for (c, r) in cases.iter().zip(rows) {
            match &r.freq_err {
                Some(e) => {
                    worst = e.iter().fold(worst, |a, x| a.max(x.abs()));
                    if e.len() < c.beam.omega.len() {
                        fewer = Some((e.len(), c.beam.omega.len()));
                    }
                }
                None => failed = true,
            }
        }
        let verdict = if failed {
            "FAIL (no frequencies at some equilibrium)".to_string()
        } else if let Some((has, asked)) = fewer {
            format!(
                "FAIL (it has {has} of the {asked} frequencies asked; largest error {:.3}%)",
                100.0 * worst
            )
        } else if worst <= target {
            format!("PASS (largest {:.3}%)", 100.0 * worst)
        } else {
            format!("FAIL (largest {:.3}%)", 100.0 * worst)
        };
        writeln!(
            f,
            "{}: max_freq_err {}%: {verdict}",
            safe(&m.model),
            num(100.0 * target)
        )?;
    }
    Ok(())
}
