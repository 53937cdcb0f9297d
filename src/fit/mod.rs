//! The fit (DESIGN §4): the free cells of a PRB matrix that make the PRB tip follow the beam
//! tip over a scene's loads, i.e. that minimise
//!
//! ```text
//! J = mean over cases of (e_pos^2 + w e_ang^2)
//! ```
//!
//! written as least squares, `J = |r|^2` with three residuals per case,
//! `(da, db, sqrt(w) dphi) / sqrt(n)`.
//!
//! # Method
//! 1. The free cells are reparameterised ([`param`]) so every parameter vector is a valid
//!    matrix: gammas positive and summing to 1, spring constants positive.
//! 2. Starts: the given matrix, the published models of the same topology (so a fitted 3R is
//!    never worse than Su's or Chen's), and seeded random points.
//! 3. A global phase (`normal`, `precise`): argmin's particle swarm, its population seeded
//!    with the starts, in a box around them.
//! 4. A local polish: Levenberg-Marquardt ([`lm`]) from the swarm's best and from every start;
//!    the best result wins.
//!
//! A parameter set whose PRB model cannot follow a load path (it buckles or snaps where the
//! beam does not) gets a finite penalty residual for the cases it misses, so the optimisers
//! see a large but finite cost — never NaN, never infinity.
//!
//! The fit checks a [`CancelToken`] at every evaluation of `J` (tens of microseconds apart),
//! so a cancelled fit returns within milliseconds with the best matrix found so far.

pub mod lm;
mod param;

use std::cell::RefCell;
use std::fmt;
use std::str::FromStr;
use std::time::Instant;

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};

use crate::beam::Resolution;
use crate::eval::{evaluate, Baseline, BaselineError, ErrorFigures, EvalError};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::{LoadPath, ModelFile, Scene};

pub use crate::cancel::CancelToken;
pub use param::{ParamError, Parameterisation};

/// A residual given to each component of a case the PRB model cannot reach, and the cap on
/// every residual. With three components per case it adds 3 to `J` per missed case: far above
/// any usable model (J below 1e-2), yet finite.
pub const PENALTY: f64 = 1.0;

/// Trial models give up on a load path once continuation needs steps below this fraction of
/// it: failing trials stay cheap, and a model this close to failing is useless anyway.
const FIT_MIN_STEP: f64 = 1e-3;

/// Newton iterations a trial model may spend per load case of a path (a healthy model needs
/// about three): beyond, it counts as failing that path, so struggling trials stay cheap.
const FIT_NEWTON_PER_CASE: u32 = 20;

/// Newton iterations per continuation attempt for trial models (quadratic convergence from
/// a secant predictor needs about five).
const FIT_NEWTON_LIMIT: u32 = 12;

/// Levenberg-Marquardt iterations every candidate gets before only the best
/// [`POLISHED_CANDIDATES`] (that have not converged yet) are polished to the end.
const SCOUT_ITERATIONS: u32 = 12;
const POLISHED_CANDIDATES: usize = 3;

/// Speed against accuracy, all knobs together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Fidelity {
    /// Coarse baseline, half the load samples, local polish only.
    Draft,
    /// The scene's load samples, a small swarm, a tight polish.
    #[default]
    Normal,
    /// Fine baseline, twice the load samples, a large swarm, the tightest polish.
    Precise,
}

impl Fidelity {
    pub const ALL: [Fidelity; 3] = [Fidelity::Draft, Fidelity::Normal, Fidelity::Precise];

    /// Baseline integrator tolerance.
    pub fn resolution(self) -> Resolution {
        Resolution::with_tol(match self {
            Fidelity::Draft => 1e-6,
            Fidelity::Normal => 1e-8,
            Fidelity::Precise => 1e-10,
        })
    }

    /// The load paths as sampled for the fit.
    pub fn sample(self, paths: &[LoadPath]) -> Vec<LoadPath> {
        paths
            .iter()
            .map(|p| LoadPath {
                end: p.end,
                steps: match self {
                    Fidelity::Draft => p.steps.div_ceil(2),
                    Fidelity::Normal => p.steps,
                    Fidelity::Precise => p.steps * 2,
                },
            })
            .collect()
    }

    /// The baseline a fit at this fidelity runs against.
    pub fn baseline(self, scene: &Scene) -> Result<Baseline, BaselineError> {
        Baseline::for_model(
            scene.beam.model(),
            &self.sample(&scene.loads),
            self.resolution(),
        )
    }

    /// `(particles, iterations)` of the swarm, if any.
    fn swarm(self) -> Option<(usize, u64)> {
        match self {
            Fidelity::Draft => None,
            Fidelity::Normal => Some((12, 15)),
            Fidelity::Precise => Some((30, 60)),
        }
    }

    fn random_starts(self) -> usize {
        match self {
            Fidelity::Draft => 0,
            Fidelity::Normal => 2,
            Fidelity::Precise => 6,
        }
    }

    fn lm(self) -> lm::LmOptions {
        match self {
            Fidelity::Draft => lm::LmOptions {
                ftol: 1e-5,
                xtol: 1e-6,
                max_iterations: 40,
            },
            Fidelity::Normal => lm::LmOptions {
                ftol: 1e-9,
                xtol: 1e-9,
                max_iterations: 100,
            },
            Fidelity::Precise => lm::LmOptions {
                ftol: 1e-13,
                xtol: 1e-12,
                max_iterations: 400,
            },
        }
    }
}

impl fmt::Display for Fidelity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Fidelity::Draft => "draft",
            Fidelity::Normal => "normal",
            Fidelity::Precise => "precise",
        })
    }
}

impl FromStr for Fidelity {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "draft" => Ok(Fidelity::Draft),
            "normal" => Ok(Fidelity::Normal),
            "precise" => Ok(Fidelity::Precise),
            other => Err(format!(
                "unknown fidelity `{other}` (expected draft, normal or precise)"
            )),
        }
    }
}

/// How to fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    pub fidelity: Fidelity,
    /// `w` in J.
    pub angle_weight: f64,
    /// Seed of the random starts and the swarm: the same seed gives the same fit.
    pub seed: u64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            fidelity: Fidelity::Normal,
            angle_weight: 1.0,
            seed: 1,
        }
    }
}

/// A progress report, at most every [`PROGRESS_INTERVAL`] seconds and at the end of each
/// phase.
#[derive(Debug, Clone, Copy)]
pub struct FitProgress<'a> {
    /// `swarm` or `polish`.
    pub phase: &'static str,
    pub iteration: u32,
    pub evaluations: u64,
    pub best_objective: f64,
    pub best: &'a PrbMatrix,
    pub seconds: f64,
}

/// Minimum time between progress reports.
pub const PROGRESS_INTERVAL: f64 = 0.02;

/// Why a fit stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The polish converged to its tolerance.
    Converged,
    /// The polish ran out of iterations before converging.
    IterationLimit,
    /// Cancelled; the report holds the best matrix so far.
    Cancelled,
    /// No cell is free.
    NothingToFit,
    /// Nothing found beats the starting matrix: it is already optimal to the fidelity's
    /// tolerance.
    CouldNotImprove,
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration limit reached",
            StopReason::Cancelled => "cancelled",
            StopReason::NothingToFit => "nothing to fit: no cell is free",
            StopReason::CouldNotImprove => "could not improve on the starting matrix",
        })
    }
}

/// What a fit found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    pub matrix: PrbMatrix,
    /// On the fit's baseline.
    pub figures: ErrorFigures,
    /// `J` of the starting matrix (the penalty value if it cannot follow the loads).
    pub start_objective: f64,
    /// Swarm iterations plus polish iterations.
    pub iterations: u32,
    /// Evaluations of J (each a PRB solve of every load case).
    pub evaluations: u64,
    pub seconds: f64,
    pub stop: StopReason,
    pub fidelity: Fidelity,
}

/// A fit that cannot start or ends with no usable model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error("no fitted model follows every load of the scene: {0}")]
    NoFeasibleModel(EvalError),
}

/// Fits the free cells of `start` against `baseline`.
pub fn fit(
    baseline: &Baseline,
    start: &PrbMatrix,
    options: &FitOptions,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
) -> Result<FitReport, FitError> {
    let t0 = Instant::now();
    let param = Parameterisation::new(start)?;
    let objective = Objective::new(baseline, &param, options.angle_weight, cancel);
    let p_start = param.encode(start);
    // J of the start itself (its encoding decodes to the start only up to round-off).
    let start_objective = objective.matrix_value(start).unwrap_or(f64::INFINITY);

    let report = |matrix: PrbMatrix, stop, iterations, evaluations| {
        let e =
            evaluate(&matrix, baseline, options.angle_weight).map_err(FitError::NoFeasibleModel)?;
        Ok(FitReport {
            matrix,
            figures: e.figures,
            start_objective,
            iterations,
            evaluations,
            seconds: t0.elapsed().as_secs_f64(),
            stop,
            fidelity: options.fidelity,
        })
    };
    if param.is_empty() {
        return report(
            start.clone(),
            StopReason::NothingToFit,
            0,
            objective.evaluations(),
        );
    }

    let fidelity = options.fidelity;
    let mut tracker = Tracker::new(&param, t0, progress);
    tracker.offer(
        "start",
        0,
        start_objective,
        &p_start,
        objective.evaluations(),
    );

    // Starts: the given matrix, the topology's sensible default (in case the given one is
    // wild), published models of the same topology, random points.
    let mut starts = vec![p_start.clone()];
    if let Ok(default) = PrbMatrix::from_topology(&start.topology()) {
        starts.push(param.encode(&default));
    }
    for model in ModelFile::published() {
        if model.prb.topology() == start.topology() {
            starts.push(param.encode(&model.prb));
        }
    }
    let (mut lower, mut upper) = param.search_box(&p_start);
    for s in &starts {
        let (lo, hi) = param.search_box(s);
        lower = lower.inf(&lo);
        upper = upper.sup(&hi);
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(options.seed);
    for _ in 0..fidelity.random_starts() {
        starts.push(DVector::from_fn(param.len(), |i, _| {
            rng.random_range(lower[i]..=upper[i])
        }));
    }
    let mut iterations = 0u32;

    // Global phase: a particle swarm seeded with the starts.
    let mut candidates = starts.clone();
    if let Some((particles, swarm_iterations)) = fidelity.swarm() {
        let mut population = Vec::with_capacity(particles);
        for s in starts.iter().take(particles) {
            let cost = objective.value(s).unwrap_or(f64::INFINITY);
            population.push(Particle::new(s.clone(), cost, DVector::zeros(param.len())));
        }
        while population.len() < particles {
            let p = DVector::from_fn(param.len(), |i, _| rng.random_range(lower[i]..=upper[i]));
            let v = DVector::from_fn(param.len(), |i, _| {
                0.1 * rng.random_range(lower[i] - upper[i]..=upper[i] - lower[i])
            });
            let cost = objective.value(&p).unwrap_or(f64::INFINITY);
            population.push(Particle::new(p, cost, v));
        }
        let swarm = ParticleSwarm::new((lower.clone(), upper.clone()), particles)
            .with_rng_generator(rand::rngs::StdRng::seed_from_u64(options.seed ^ 0x5eed));
        let cost = SwarmCost {
            objective: &objective,
            tracker: RefCell::new(&mut tracker),
            particles,
        };
        let result = Executor::new(cost, swarm)
            .configure(|state| state.population(population).max_iters(swarm_iterations))
            .timer(false)
            .run();
        // The swarm only reports errors of its own bookkeeping; if it fails the polish still
        // runs from the starts.
        if let Ok(result) = result {
            if let Some(best) = result.state().get_best_param() {
                candidates.insert(0, best.position.clone());
            }
            iterations += result.state().get_iter() as u32;
        }
    }

    // Local polish in two rounds: a short one from every candidate, then the full polish
    // from the best few only, so hopeless candidates cost little.
    let mut best: Option<lm::LmResult> = None;
    let mut scout = fidelity.lm();
    scout.max_iterations = SCOUT_ITERATIONS;
    let mut scouted: Vec<lm::LmResult> = Vec::new();
    for round in 0..2 {
        let starts: Vec<DVector<f64>> = if round == 0 {
            std::mem::take(&mut candidates)
        } else {
            scouted.sort_by(|a, b| a.objective.total_cmp(&b.objective));
            scouted
                .iter()
                .filter(|r| r.stop == lm::LmStop::IterationLimit)
                .take(POLISHED_CANDIDATES)
                .map(|r| r.p.clone())
                .collect()
        };
        for candidate in starts {
            if cancel.is_cancelled() {
                break;
            }
            let mut residuals = |p: &DVector<f64>, out: &mut Vec<f64>| objective.residuals(p, out);
            let mut on_iteration = |it: u32, j: f64, p: &DVector<f64>| {
                tracker.offer("polish", it, j, p, objective.evaluations());
            };
            let options = if round == 0 { scout } else { fidelity.lm() };
            let run = lm::minimise(candidate, options, &mut residuals, &mut on_iteration);
            iterations += run.iterations;
            if best.as_ref().is_none_or(|b| run.objective < b.objective) {
                best = Some(run.clone());
            }
            if round == 0 {
                scouted.push(run);
            }
        }
    }
    tracker.flush("polish", iterations, objective.evaluations());

    let evaluations = objective.evaluations();
    let (p, stop) = match best {
        // Cancelled before any polish finished: the best point seen anywhere.
        None => (tracker.best_p.clone(), StopReason::Cancelled),
        Some(b) => {
            let stop = if cancel.is_cancelled() {
                StopReason::Cancelled
            } else {
                match b.stop {
                    lm::LmStop::Converged | lm::LmStop::Stalled => StopReason::Converged,
                    lm::LmStop::IterationLimit => StopReason::IterationLimit,
                    lm::LmStop::Cancelled => StopReason::Cancelled,
                }
            };
            // The tracker may hold a better point (e.g. from the swarm) than the polish ended on.
            if tracker.best_j < b.objective {
                (tracker.best_p.clone(), stop)
            } else {
                (b.p, stop)
            }
        }
    };
    let best_j = objective.value(&p).unwrap_or(tracker.best_j);
    let improved = best_j < start_objective;
    let (matrix, stop) = if !improved {
        (
            start.clone(),
            if stop == StopReason::Cancelled {
                stop
            } else {
                StopReason::CouldNotImprove
            },
        )
    } else {
        (param.decode(&p).unwrap_or_else(|| start.clone()), stop)
    };
    report(matrix, stop, iterations, evaluations)
}

/// `J` and its residuals for parameter vectors, counting evaluations.
struct Objective<'a> {
    baseline: &'a Baseline,
    param: &'a Parameterisation,
    angle_scale: f64,
    case_scale: f64,
    cancel: &'a CancelToken,
    evaluations: std::cell::Cell<u64>,
}

impl<'a> Objective<'a> {
    fn new(
        baseline: &'a Baseline,
        param: &'a Parameterisation,
        angle_weight: f64,
        cancel: &'a CancelToken,
    ) -> Objective<'a> {
        Objective {
            baseline,
            param,
            angle_scale: angle_weight.sqrt(),
            case_scale: 1.0 / (baseline.case_count().max(1) as f64).sqrt(),
            cancel,
            evaluations: std::cell::Cell::new(0),
        }
    }

    fn evaluations(&self) -> u64 {
        self.evaluations.get()
    }

    /// Fills `out` with the residuals at `p`; false when cancelled.
    fn residuals(&self, p: &DVector<f64>, out: &mut Vec<f64>) -> bool {
        match self.param.decode(p) {
            Some(matrix) => self.matrix_residuals(&matrix, out),
            None => {
                if self.cancel.is_cancelled() {
                    return false;
                }
                self.evaluations.set(self.evaluations.get() + 1);
                out.clear();
                out.resize(3 * self.baseline.case_count(), PENALTY);
                true
            }
        }
    }

    /// Fills `out` with the residuals of `matrix`; false when cancelled.
    fn matrix_residuals(&self, matrix: &PrbMatrix, out: &mut Vec<f64>) -> bool {
        if self.cancel.is_cancelled() {
            return false;
        }
        self.evaluations.set(self.evaluations.get() + 1);
        out.clear();
        let solver = PrbSolver::new(matrix, self.baseline.model.axial_compliance())
            .with_min_step(FIT_MIN_STEP)
            .with_newton_limit(FIT_NEWTON_LIMIT)
            .with_case_budget(FIT_NEWTON_PER_CASE);
        let mut beam = self.baseline.solutions.iter();
        for path in &self.baseline.paths {
            let before = out.len();
            // Residuals are capped at the penalty, so that failing to reach a case is never
            // better than reaching it badly.
            let cap = PENALTY;
            let outcome = solver.solve_path_with(path.end, path.steps, |sol| {
                let b = beam.next().expect("one beam solution per case");
                out.push(((sol.tip.a - b.tip.a) * self.case_scale).clamp(-cap, cap));
                out.push(((sol.tip.b - b.tip.b) * self.case_scale).clamp(-cap, cap));
                let da = (sol.tip.phi - b.tip.phi) * self.angle_scale * self.case_scale;
                out.push(da.clamp(-cap, cap));
            });
            if outcome.is_err() {
                // The cases this model cannot reach.
                let reached = (out.len() - before) / 3;
                for _ in reached..path.steps as usize {
                    beam.next();
                    out.extend_from_slice(&[PENALTY; 3]);
                }
            }
        }
        true
    }

    /// `J` of `matrix`, or `None` when cancelled.
    fn matrix_value(&self, matrix: &PrbMatrix) -> Option<f64> {
        let mut r = Vec::new();
        self.matrix_residuals(matrix, &mut r)
            .then(|| r.iter().map(|v| v * v).sum())
    }

    /// `J` at `p`, or `None` when cancelled.
    fn value(&self, p: &DVector<f64>) -> Option<f64> {
        let mut r = Vec::new();
        self.residuals(p, &mut r)
            .then(|| r.iter().map(|v| v * v).sum())
    }
}

/// Keeps the best point seen and reports progress, throttled.
struct Tracker<'a, 'b> {
    param: &'a Parameterisation,
    t0: Instant,
    last_report: f64,
    best_j: f64,
    best_p: DVector<f64>,
    best_matrix: Option<PrbMatrix>,
    unreported: bool,
    progress: &'b mut dyn FnMut(&FitProgress),
}

impl<'a, 'b> Tracker<'a, 'b> {
    fn new(
        param: &'a Parameterisation,
        t0: Instant,
        progress: &'b mut dyn FnMut(&FitProgress),
    ) -> Self {
        Tracker {
            param,
            t0,
            last_report: f64::NEG_INFINITY,
            best_j: f64::INFINITY,
            best_p: DVector::zeros(param.len()),
            best_matrix: None,
            unreported: false,
            progress,
        }
    }

    fn offer(
        &mut self,
        phase: &'static str,
        iteration: u32,
        j: f64,
        p: &DVector<f64>,
        evaluations: u64,
    ) {
        if j < self.best_j {
            if let Some(m) = self.param.decode(p) {
                self.best_j = j;
                self.best_p = p.clone();
                self.best_matrix = Some(m);
                self.unreported = true;
            }
        }
        let now = self.t0.elapsed().as_secs_f64();
        if self.unreported && now - self.last_report >= PROGRESS_INTERVAL {
            self.report(phase, iteration, evaluations, now);
        }
    }

    fn flush(&mut self, phase: &'static str, iteration: u32, evaluations: u64) {
        if self.unreported {
            let now = self.t0.elapsed().as_secs_f64();
            self.report(phase, iteration, evaluations, now);
        }
    }

    fn report(&mut self, phase: &'static str, iteration: u32, evaluations: u64, now: f64) {
        if let Some(best) = &self.best_matrix {
            (self.progress)(&FitProgress {
                phase,
                iteration,
                evaluations,
                best_objective: self.best_j,
                best,
                seconds: now,
            });
            self.last_report = now;
            self.unreported = false;
        }
    }
}

/// The swarm's view of J.
struct SwarmCost<'a, 'b, 'c> {
    objective: &'a Objective<'a>,
    tracker: RefCell<&'b mut Tracker<'c, 'c>>,
    particles: usize,
}

impl CostFunction for SwarmCost<'_, '_, '_> {
    type Param = DVector<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, argmin::core::Error> {
        // Cancelled: a flat penalty, returned at once, lets the swarm run out its few
        // remaining iterations in microseconds.
        let j = self.objective.value(p).unwrap_or(PENALTY * 1e3);
        let evaluations = self.objective.evaluations();
        let iteration = (evaluations / self.particles as u64) as u32;
        self.tracker
            .borrow_mut()
            .offer("swarm", iteration, j, p, evaluations);
        Ok(j)
    }
}
