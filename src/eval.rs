//! Judging a PRB model against the beam (DESIGN §4): per load case, the tip position error
//! `e_pos = |(a, b)_PRB - (a, b)_beam|` (units of L) and angle error
//! `e_ang = phi_PRB - phi_beam` (radians); over a scene their RMS and maxima and the objective
//! `J = mean(e_pos^2 + w e_ang^2)`.
//!
//! A scene's baseline (every beam solve) is computed once into a [`Baseline`] and reused for
//! every model judged on it.

use std::ops::ControlFlow;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::beam::{
    BeamModel, BeamSolution, BeamSolver, Convergence, Load, Resolution, SolveError, TipPose,
};
use crate::cancel::CancelToken;
use crate::fidelity::Fidelity;
use crate::prb::{PrbCase, PrbError, PrbMatrix, PrbSolver};
use crate::scene::data::DataTruth;
use crate::scene::{Accuracy, LoadPath, Scene};

/// The beam's answer for every load case of a scene.
#[derive(Debug, Clone)]
pub struct Baseline {
    /// The beam that was solved (effects decided).
    pub model: BeamModel,
    /// The load paths, as sampled.
    pub paths: Vec<LoadPath>,
    /// One per case, path by path.
    pub solutions: Vec<BeamSolution>,
    /// The solver's resolution.
    pub resolution: Resolution,
    /// Wall-clock time of the solves.
    pub seconds: f64,
    /// A data scene's truth (DESIGN §9): each path's measured loads, which the PRB model
    /// follows row by row (`solutions` then holds the measured tips); `None` for the beam.
    pub measured: Option<Vec<Vec<Load>>>,
}

/// Which load path failed, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path} of the scene: {source}")]
pub struct BaselineError {
    /// 1-based.
    pub path: usize,
    /// Why the beam failed there.
    pub source: SolveError,
}

impl Baseline {
    /// Solves every case of the scene's beam; a data scene's baseline is its data
    /// ([`Baseline::from_data`]).
    pub fn compute(scene: &Scene, resolution: Resolution) -> Result<Baseline, BaselineError> {
        if let Some(truth) = &scene.truth {
            return Ok(Baseline::from_data(scene.beam.model(), truth));
        }
        Baseline::for_model(scene.beam.model(), &scene.loads, resolution)
    }

    /// Solves every case of `paths` for a given beam.
    pub fn for_model(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
    ) -> Result<Baseline, BaselineError> {
        Baseline::solve(
            model,
            paths,
            resolution,
            &CancelToken::new(),
            &mut |_, _| {},
        )
    }

    /// As [`Baseline::for_model`], stopping with [`SolveError::Cancelled`] soon after
    /// `cancel` is set (the beam checks it every continuation step), and telling
    /// `on_path(paths_done, cases_done)` after each path (for progress).
    pub fn solve(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
        cancel: &CancelToken,
        on_path: &mut dyn FnMut(usize, usize),
    ) -> Result<Baseline, BaselineError> {
        let t0 = Instant::now();
        let solver = BeamSolver::new(model, resolution)
            .map_err(|source| BaselineError { path: 0, source })?;
        let mut solutions = Vec::new();
        for (i, p) in paths.iter().enumerate() {
            let sols = solver
                .solve_path_cancellable(p.end, p.steps, cancel)
                .map_err(|source| BaselineError {
                    path: i + 1,
                    source,
                })?;
            solutions.extend(sols);
            on_path(i + 1, solutions.len());
        }
        Ok(Baseline {
            model,
            paths: paths.to_vec(),
            solutions,
            resolution,
            seconds: t0.elapsed().as_secs_f64(),
            measured: None,
        })
    }

    /// The baseline of a data scene (DESIGN §9): the measured tips are the truth, and `model`
    /// (the scene's nominal beam, effects decided) only gives the PRB model its axial
    /// compliance. Each measured row becomes a solution with the measured tip; its root
    /// moment is the statics of the measured pose (`beta + a alpha_y - b alpha_x`), and it
    /// has no shape.
    pub fn from_data(model: BeamModel, truth: &DataTruth) -> Baseline {
        let solutions = truth
            .paths
            .iter()
            .flat_map(|p| &p.rows)
            .map(|r| BeamSolution {
                load: r.load,
                tip: r.tip,
                root_moment: r.load.beta + r.tip.a * r.load.alpha_y - r.tip.b * r.load.alpha_x,
                shape: Vec::new(),
                iterations: 0,
                continuation_steps: 0,
                rk_steps: 0,
                convergence: Convergence {
                    residual: 0.0,
                    last_update: 0.0,
                    stability: 1.0,
                },
            })
            .collect();
        let paths = truth
            .paths
            .iter()
            .filter_map(|p| {
                p.rows.last().map(|last| LoadPath {
                    end: last.load,
                    steps: u32::try_from(p.rows.len()).unwrap_or(u32::MAX),
                })
            })
            .collect();
        Baseline {
            model,
            paths,
            solutions,
            resolution: Resolution::default(),
            seconds: 0.0,
            measured: Some(truth.loads()),
        }
    }

    /// Whether the truth is measured data rather than the beam.
    pub fn is_measured(&self) -> bool {
        self.measured.is_some()
    }

    /// Load cases in all.
    pub fn case_count(&self) -> usize {
        self.solutions.len()
    }

    /// Follows every load path with the PRB `solver` (continuation from the unloaded chain,
    /// as the beam was followed), handing each case to `visit` together with the beam's
    /// solution for the same load. This is the one loop that pairs PRB cases with beam cases:
    /// evaluation, the fit's residuals, the UI's charts and the CSV export all go through it.
    ///
    /// A path the model cannot follow is handed to `on_failure` with the beam solutions of
    /// the cases it did not reach: `Continue` goes on with the next path, `Break` stops with
    /// that path's error.
    pub fn follow(
        &self,
        solver: &PrbSolver,
        mut visit: impl FnMut(&BeamSolution, &PrbCase<'_>),
        mut on_failure: impl FnMut(&[BeamSolution]) -> ControlFlow<()>,
    ) -> Result<(), EvalError> {
        let mut start = 0;
        for (i, path) in self.paths.iter().enumerate() {
            let end = (start + path.steps as usize).min(self.solutions.len());
            let beam = &self.solutions[start..end];
            start = end;
            let mut reached = 0;
            let mut on_case = |case: PrbCase<'_>| {
                if let Some(b) = beam.get(reached) {
                    visit(b, &case);
                }
                reached += 1;
            };
            let outcome = match self.measured.as_ref().and_then(|m| m.get(i)) {
                Some(rows) => solver.solve_rows_with(rows, &mut on_case),
                None => solver.solve_path_with(path.end, path.steps, &mut on_case),
            };
            if let Err(source) = outcome {
                let missed = &beam[reached.min(beam.len())..];
                if on_failure(missed).is_break() {
                    return Err(EvalError {
                        path: i + 1,
                        source,
                    });
                }
            }
        }
        Ok(())
    }
}

/// The scene's own beam judged against a data scene's measurements (DESIGN §9: how far the
/// ideal beam is from the specimen): per row, the beam's tip under the row's load (solved by
/// continuation from the unloaded beam) against the measured tip, as [`CaseError`]s with the
/// data in the `beam` slot and the beam theory in the `prb` slot, and their figures. `None`
/// for a scene without data, and for a mechanism's (see `mech::measured::beam_against_data`).
pub fn beam_against_data(
    scene: &Scene,
    resolution: Resolution,
) -> Result<Option<Evaluation>, BaselineError> {
    let Some(truth) = scene.truth.as_ref().filter(|_| scene.mechanism.is_none()) else {
        return Ok(None);
    };
    beam_against_rows(&scene.beam, truth, 1.0, resolution, scene.fit.angle_weight).map(Some)
}

/// [`beam_against_data`] for `beam` (which may differ from the nominal beam the rows were
/// converted with): the rows' nondimensional loads are multiplied by `load_scale`, the
/// nominal `E I0` over this beam's, so that they stay the same physical loads.
fn beam_against_rows(
    beam: &crate::scene::BeamSpec,
    truth: &DataTruth,
    load_scale: f64,
    resolution: Resolution,
    angle_weight: f64,
) -> Result<Evaluation, BaselineError> {
    let solver = BeamSolver::new(beam.model(), resolution)
        .map_err(|source| BaselineError { path: 0, source })?;
    let mut cases = Vec::with_capacity(truth.row_count());
    for (i, path) in truth.paths.iter().enumerate() {
        for row in &path.rows {
            let load = row.load.scaled(load_scale);
            let solved = solver.solve(load).map_err(|source| BaselineError {
                path: i + 1,
                source,
            })?;
            cases.push(CaseError::new(row.load, row.tip, solved.tip));
        }
    }
    let figures = ErrorFigures::from_cases(&cases, angle_weight);
    Ok(Evaluation { cases, figures })
}

/// A beam parameter [`calibrate`] can fit to measured data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BeamParam {
    /// `E`, Pa: scales the bending stiffness (a rig's `E` is never the catalogue's).
    YoungsModulus,
    /// `t0`, m: scales the bending stiffness as its cube and the slenderness.
    Thickness,
}

impl BeamParam {
    /// The scene key's name.
    pub fn name(self) -> &'static str {
        match self {
            BeamParam::YoungsModulus => "youngs_modulus",
            BeamParam::Thickness => "thickness",
        }
    }

    /// From the scene key's name.
    pub fn from_name(name: &str) -> Option<BeamParam> {
        match name {
            "youngs_modulus" | "E" => Some(BeamParam::YoungsModulus),
            "thickness" => Some(BeamParam::Thickness),
            _ => None,
        }
    }

    fn get(self, beam: &crate::scene::BeamSpec) -> f64 {
        match self {
            BeamParam::YoungsModulus => beam.youngs_modulus,
            BeamParam::Thickness => beam.thickness,
        }
    }

    fn set(self, beam: &mut crate::scene::BeamSpec, v: f64) {
        match self {
            BeamParam::YoungsModulus => beam.youngs_modulus = v,
            BeamParam::Thickness => beam.thickness = v,
        }
    }
}

/// One beam parameter fitted to a data scene's measurements; `F` is the figures the beam is
/// judged by (a cantilever's [`ErrorFigures`], a mechanism's `MechFigures`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration<F = ErrorFigures> {
    /// Which parameter.
    pub param: BeamParam,
    /// The scene's value (SI; a mechanism's flexure 1's, every flexure's scaled alike).
    pub nominal: f64,
    /// The fitted value (SI).
    pub value: f64,
    /// The beam against the data with the nominal value.
    pub nominal_figures: F,
    /// The beam against the data with the fitted value: the residual.
    pub figures: F,
    /// The fit ended at the edge of the searched range (a factor of [`CALIBRATION_RANGE`]
    /// either way of the nominal value): the data wants a value further out, or the beam
    /// cannot explain it.
    pub at_edge: bool,
    /// Beam solves of every row (evaluations of `J`).
    pub evaluations: u32,
}

/// [`calibrate`] searches within this factor of the nominal value, either way.
pub const CALIBRATION_RANGE: f64 = 4.0;

/// Fits `param` of the scene's beam to its measured data: the value that minimises the
/// beam's `J` against the data (golden-section search on the logarithm of the value, within
/// [`CALIBRATION_RANGE`] of the nominal one, to a relative 1e-9; the nominal value is kept
/// if nothing searched does better). Trial values whose beam
/// cannot reach every row count as worse than any that can.
///
/// # Errors
/// The scene has no data, or the beam with the nominal value cannot reach its rows.
pub fn calibrate(
    scene: &Scene,
    param: BeamParam,
    resolution: Resolution,
) -> Result<Calibration, CalibrateError> {
    let truth = scene.truth.as_ref().ok_or(CalibrateError::NoData)?;
    if scene.mechanism.is_some() {
        return Err(CalibrateError::Mechanism);
    }
    let nominal_beam = scene.beam;
    let nominal = param.get(&nominal_beam);
    let ei0 = nominal_beam.youngs_modulus * nominal_beam.second_moment();
    let w = scene.fit.angle_weight;
    let mut evaluations = 0u32;
    let mut judge = |v: f64| -> Result<Evaluation, BaselineError> {
        evaluations += 1;
        let mut beam = nominal_beam;
        param.set(&mut beam, v);
        let scale = ei0 / (beam.youngs_modulus * beam.second_moment());
        beam_against_rows(&beam, truth, scale, resolution, w)
    };
    let mut c = search(
        param,
        nominal,
        |v| judge(v).map(|e| e.figures),
        |f| f.objective,
    )
    .map_err(CalibrateError::Nominal)?;
    c.evaluations = evaluations;
    Ok(c)
}

/// The calibration of `param` around `nominal`: `judge(value)` gives the beam's figures
/// against the data, `objective` their `J`; golden-section search on the logarithm
/// ([`golden_log`]), keeping the nominal value unless the search does better. A value whose
/// judging fails counts as worse than any that does not; the nominal one must not fail.
/// (`evaluations` is left 0 for the caller, who counts `judge`'s calls.)
fn search<F: Copy, E>(
    param: BeamParam,
    nominal: f64,
    mut judge: impl FnMut(f64) -> Result<F, E>,
    objective: impl Fn(&F) -> f64,
) -> Result<Calibration<F>, E> {
    let nominal_figures = judge(nominal)?;
    let best = golden_log(nominal, |log_v| {
        judge(log_v.exp()).map_or(f64::INFINITY, |f| objective(&f))
    });
    let mut figures = judge(best.exp())?;
    let (value, at_edge) = if objective(&nominal_figures) <= objective(&figures) {
        figures = nominal_figures;
        (nominal, false)
    } else {
        (best.exp(), at_edge(nominal, best))
    };
    Ok(Calibration {
        param,
        nominal,
        value,
        nominal_figures,
        figures,
        at_edge,
        evaluations: 0,
    })
}

/// Golden-section search of `cost` over the logarithm of the value, within
/// [`CALIBRATION_RANGE`] of `nominal` either way, to a relative 1e-9: the best logarithm.
fn golden_log(nominal: f64, mut cost: impl FnMut(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (
        (nominal / CALIBRATION_RANGE).ln(),
        (nominal * CALIBRATION_RANGE).ln(),
    );
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (cost(x1), cost(x2));
    while hi - lo > 1e-9 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = cost(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = cost(x2);
        }
    }
    0.5 * (lo + hi)
}

/// Whether the logarithm `best` is at the edge of the searched range around `nominal`.
fn at_edge(nominal: f64, best: f64) -> bool {
    (best - nominal.ln()).abs() > CALIBRATION_RANGE.ln() - 1e-3
}

/// One beam parameter of a mechanism's flexures fitted to its measured data (DESIGN §9 with
/// §8): flexure 1's values, the beam mechanism's figures against the data.
pub type MechCalibration = Calibration<crate::mech::figures::MechFigures>;

/// [`calibrate`] on a mechanism data scene: `param` of every flexure scaled by one ratio
/// (one material, one sheet: a rig's `E` or thickness differs from the catalogue's alike in
/// every flexure), chosen to minimise the exact beam mechanism's `J` (DESIGN §8) against
/// the data, followed through the measured drives. The data stays in newtons and metres:
/// each trial converts it with its own flexure 1 (the position and angle errors are in
/// units of `L`, which neither parameter changes, and the reaction errors are fractions of
/// the data's own reactions, so the trials' `J` compare). Trial values whose mechanism
/// cannot follow the drives count as worse than any that can.
///
/// # Errors
/// The scene is not a mechanism with data, or the nominal mechanism cannot follow its
/// drives.
pub fn calibrate_mechanism(
    scene: &Scene,
    param: BeamParam,
    resolution: Resolution,
) -> Result<MechCalibration, MechCalibrateError> {
    let (Some(mechanism), Some(_)) = (
        &scene.mechanism,
        scene.truth.as_ref().and_then(|t| t.stage.as_ref()),
    ) else {
        return Err(MechCalibrateError::NoData);
    };
    let nominal = mechanism
        .flexures
        .first()
        .map_or(1.0, |f| param.get(&f.beam));
    let mut evaluations = 0u32;
    let mut judge = |v: f64| {
        evaluations += 1;
        let mut trial = scene.clone();
        if let Some(m) = trial.mechanism.as_mut() {
            for f in &mut m.flexures {
                let mine = param.get(&f.beam);
                param.set(&mut f.beam, mine * v / nominal);
            }
        }
        let m = trial.mechanism.clone().unwrap_or_else(|| mechanism.clone());
        crate::mech::measured::beam_against_data(&trial, &m, resolution)
            .map(|e| e.map(|e| e.figures))
    };
    let mut c = search(
        param,
        nominal,
        |v| judge(v)?.ok_or(MechCalibrateError::NoData),
        |f| f.objective,
    )?;
    c.evaluations = evaluations;
    Ok(c)
}

/// Why a mechanism's calibration has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechCalibrateError {
    /// The scene is not a mechanism with measured data.
    #[error(
        "the scene is not a mechanism with measured data to calibrate against (add [truth] \
         data = \"file.csv\")"
    )]
    NoData,
    /// The beam mechanism cannot follow the data's drives.
    #[error("the beam mechanism cannot follow the measured drives: {0}")]
    Nominal(#[from] crate::mech::measured::BesideError),
}

/// Why a calibration has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrateError {
    /// The scene's truth is the beam itself.
    #[error(
        "the scene has no measured data to calibrate against (add [truth] data = \"file.csv\")"
    )]
    NoData,
    /// The beam cannot reach the data's loads.
    #[error("the beam cannot reach the measured loads: {0}")]
    Nominal(BaselineError),
    /// A mechanism's data: its flexures are calibrated by [`calibrate_mechanism`].
    #[error("a mechanism scene's data calibrate its flexures (calibrate_mechanism), not one beam")]
    Mechanism,
}

impl Fidelity {
    /// The baseline a fit at this fidelity runs against: the scene's beam at this
    /// fidelity's resolution, over its sampling of the scene's loads.
    pub fn baseline(self, scene: &Scene) -> Result<Baseline, BaselineError> {
        if let Some(truth) = &scene.truth {
            // Measured data is what it is: no resolution or sampling to choose.
            return Ok(Baseline::from_data(scene.beam.model(), truth));
        }
        Baseline::for_model(
            scene.beam.model(),
            &self.sample(&scene.loads),
            self.resolution(),
        )
    }
}

/// One load case: both tips and the errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CaseError {
    /// The load.
    pub load: Load,
    /// The beam's tip.
    pub beam: TipPose,
    /// The PRB model's tip.
    pub prb: TipPose,
    /// `|(a, b)_PRB - (a, b)_beam|`, units of L.
    pub pos_err: f64,
    /// `phi_PRB - phi_beam`, radians.
    pub ang_err: f64,
}

impl CaseError {
    /// The errors of the PRB tip against the beam tip.
    pub fn new(load: Load, beam: TipPose, prb: TipPose) -> CaseError {
        CaseError {
            load,
            beam,
            prb,
            pos_err: (prb.a - beam.a).hypot(prb.b - beam.b),
            ang_err: prb.phi - beam.phi,
        }
    }
}

/// The five error figures of DESIGN §4.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ErrorFigures {
    /// RMS of `e_pos`, units of L.
    pub rms_pos_err: f64,
    /// Largest `e_pos`, units of L.
    pub max_pos_err: f64,
    /// RMS of `e_ang`, radians.
    pub rms_ang_err: f64,
    /// Largest `|e_ang|`, radians.
    pub max_ang_err: f64,
    /// `J = mean(e_pos^2 + w e_ang^2)`.
    pub objective: f64,
}

impl ErrorFigures {
    /// The figures over `cases`, with `w = angle_weight` in `J`.
    pub fn from_cases(cases: &[CaseError], angle_weight: f64) -> ErrorFigures {
        let n = cases.len().max(1) as f64;
        let (mut sp, mut sa, mut mp, mut ma) = (0.0, 0.0, 0.0_f64, 0.0_f64);
        for c in cases {
            sp += c.pos_err * c.pos_err;
            sa += c.ang_err * c.ang_err;
            mp = mp.max(c.pos_err);
            ma = ma.max(c.ang_err.abs());
        }
        ErrorFigures {
            rms_pos_err: (sp / n).sqrt(),
            max_pos_err: mp,
            rms_ang_err: (sa / n).sqrt(),
            max_ang_err: ma,
            objective: (sp + angle_weight * sa) / n,
        }
    }

    /// Whether the figures meet a scene's targets.
    pub fn meets(&self, accuracy: &Accuracy) -> bool {
        self.max_pos_err <= accuracy.max_pos_err && self.max_ang_err <= accuracy.max_ang_err
    }
}

/// A model judged on a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Per case, path by path.
    pub cases: Vec<CaseError>,
    /// Over all cases.
    pub figures: ErrorFigures,
}

/// The PRB model fails to follow one of the scene's load paths.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path}: {source}")]
pub struct EvalError {
    /// 1-based.
    pub path: usize,
    /// Why the model failed there.
    pub source: PrbError,
}

/// Judges `matrix` against the baseline.
pub fn evaluate(
    matrix: &PrbMatrix,
    baseline: &Baseline,
    angle_weight: f64,
) -> Result<Evaluation, EvalError> {
    let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
    let mut cases = Vec::with_capacity(baseline.case_count());
    baseline.follow(
        &solver,
        |beam, prb| cases.push(CaseError::new(prb.load, beam.tip, prb.tip)),
        |_| ControlFlow::Break(()),
    )?;
    let figures = ErrorFigures::from_cases(&cases, angle_weight);
    Ok(Evaluation { cases, figures })
}
