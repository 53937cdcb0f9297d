//! The speed/accuracy trade, measured along each knob (time against error, the error taken
//! against a converged reference):
//!
//! - beam resolution: the integrator tolerance; time per load case and the worst tip error
//!   against tol = 1e-13;
//! - load sampling: how many cases along each path the fit sees; fit time and the fitted
//!   model's J on a dense, precise reference sampling;
//! - fidelity preset: the same for draft, normal, precise;
//! - topology: the cost of one PRB load case and the fitted model's J.

use std::time::Instant;

use serde::Serialize;

use crate::beam::Resolution;
use crate::eval::{Baseline, BaselineError};
use crate::fit::{CancelToken, Fidelity, FitOptions};
use crate::prb::PrbMatrix;
use crate::scene::{LoadPath, Scene};

use super::fit::FitError;
use super::select::ladder;
use super::{Sampling, Study, StudyError};

/// One measured setting of a knob.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeoffRow {
    /// The knob's setting, as shown (`tol 1e-6`, `2x steps (40 cases)`, `normal`, `L-R-R`).
    pub setting: String,
    /// The time measured at this setting, seconds (what it times is the knob's `time_of`).
    pub seconds: f64,
    /// The error measured at this setting (what it is, and its unit, is the knob's
    /// `error_of`): a tip error in L and radians, or `J`.
    pub error: f64,
}

/// One knob's measurements.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Knob {
    /// The knob's name: `beam resolution`, `load sampling`, `fidelity preset` or `topology`.
    pub knob: &'static str,
    /// What `seconds` measures.
    pub time_of: &'static str,
    /// What `error` measures.
    pub error_of: &'static str,
    /// One row per setting, in the order measured (cheapest setting first, except for
    /// topologies, which follow the selection ladder).
    pub rows: Vec<TradeoffRow>,
}

/// Why a trade-off could not be measured.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TradeoffError {
    /// The beam could not be solved for the scene's loads at some resolution.
    #[error(transparent)]
    Baseline(#[from] BaselineError),
    /// A fit of the starting model or of a ladder topology failed.
    #[error(transparent)]
    Fit(#[from] FitError),
    /// The truth of a sampling could not be had.
    #[error(transparent)]
    Study(#[from] StudyError),
}

/// The study of `scene` (effects decided) over `paths` at `sampling`.
fn study_on(scene: &Scene, paths: &[LoadPath], sampling: Sampling) -> Result<Study, StudyError> {
    let mut s = scene.clone();
    s.loads = paths.to_vec();
    Study::decided(s, None, sampling, &CancelToken::new(), &mut |_, _, _| {})
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn scaled(paths: &[LoadPath], factor: f64) -> Vec<LoadPath> {
    paths
        .iter()
        .map(|p| LoadPath {
            end: p.end,
            steps: ((p.steps as f64 * factor).ceil() as u32).max(1),
        })
        .collect()
}

/// Measures every knob on `scene` (effects already resolved). `start` is the model the
/// sampling and fidelity knobs fit. Cancelled, it returns the knobs finished so far.
pub fn measure(
    scene: &Scene,
    start: &PrbMatrix,
    cancel: &CancelToken,
) -> Result<Vec<Knob>, TradeoffError> {
    let model = scene.beam.model();
    let weight = scene.fit.angle_weight;
    let mut knobs = Vec::new();

    // Beam resolution.
    let truth = Baseline::for_model(model, &scene.loads, Resolution::with_tol(1e-13))?;
    let mut rows = Vec::new();
    for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11] {
        // Five solves, timed; the error is that of the last one.
        let per_case = |b: &Baseline| b.seconds / b.case_count().max(1) as f64;
        let mut b = Baseline::for_model(model, &scene.loads, Resolution::with_tol(tol))?;
        let mut times = vec![per_case(&b)];
        for _ in 1..5 {
            b = Baseline::for_model(model, &scene.loads, Resolution::with_tol(tol))?;
            times.push(per_case(&b));
        }
        let error = b
            .solutions
            .iter()
            .zip(&truth.solutions)
            .map(|(x, y)| x.tip.max_diff(&y.tip))
            .fold(0.0, f64::max);
        rows.push(TradeoffRow {
            setting: format!("tol {tol:.0e}"),
            seconds: median(times),
            error,
        });
    }
    knobs.push(Knob {
        knob: "beam resolution",
        time_of: "one load case (median of 5 scene solves)",
        error_of: "worst tip error against tol 1e-13 (L, rad)",
        rows,
    });

    if cancel.is_cancelled() {
        return Ok(knobs);
    }
    // The fitted knobs are judged on a dense, precise reference sampling.
    let reference = study_on(
        scene,
        &scaled(&scene.loads, 4.0),
        Sampling::Every(Resolution::with_tol(1e-10)),
    )?;
    let j_on_reference = |m: &PrbMatrix| {
        reference
            .judge(m)
            .map(|e| e.figures.objective)
            .unwrap_or(f64::INFINITY)
    };
    let fit_on = |paths: &[LoadPath], fidelity: Fidelity| -> Result<(f64, f64), TradeoffError> {
        let t0 = Instant::now();
        let study = study_on(scene, paths, Sampling::Every(fidelity.resolution()))?;
        let options = FitOptions {
            fidelity,
            angle_weight: weight,
            seed: 1,
        };
        let report = study.fit(start, &options, &mut |_| {}, &CancelToken::new())?;
        let seconds = t0.elapsed().as_secs_f64();
        Ok((seconds, j_on_reference(&report.matrix)))
    };

    if cancel.is_cancelled() {
        return Ok(knobs);
    }
    let mut rows = Vec::new();
    for factor in [0.25, 0.5, 1.0, 2.0, 4.0] {
        let paths = scaled(&scene.loads, factor);
        let cases: u32 = paths.iter().map(|p| p.steps).sum();
        let (seconds, j) = fit_on(&paths, Fidelity::Normal)?;
        rows.push(TradeoffRow {
            setting: format!("{factor}x steps ({cases} cases)"),
            seconds,
            error: j,
        });
    }
    knobs.push(Knob {
        knob: "load sampling",
        time_of: "baseline + fit, normal fidelity",
        error_of: "J of the fitted model on the reference (4x steps, tol 1e-10)",
        rows,
    });

    if cancel.is_cancelled() {
        return Ok(knobs);
    }
    let mut rows = Vec::new();
    for fidelity in Fidelity::ALL {
        let (seconds, j) = fit_on(&fidelity.sample(&scene.loads), fidelity)?;
        rows.push(TradeoffRow {
            setting: fidelity.to_string(),
            seconds,
            error: j,
        });
    }
    knobs.push(Knob {
        knob: "fidelity preset",
        time_of: "baseline + fit",
        error_of: "J of the fitted model on the reference (4x steps, tol 1e-10)",
        rows,
    });

    if cancel.is_cancelled() {
        return Ok(knobs);
    }
    let mut rows = Vec::new();
    let study = study_on(scene, &scene.loads, Sampling::Fidelity(Fidelity::Normal))?;
    for topo in ladder(model.effects) {
        // `ladder` lists only fixed names made of `L`, `R` and `RP` segments, which
        // `from_topology` always accepts (`select`'s `ladder_topologies_are_valid` checks
        // every one).
        #[allow(clippy::expect_used)]
        let start = PrbMatrix::from_topology(topo).expect("ladder topologies are valid");
        let options = FitOptions {
            fidelity: Fidelity::Normal,
            angle_weight: weight,
            seed: 1,
        };
        let report = study.fit(&start, &options, &mut |_| {}, &CancelToken::new())?;
        let per_case = study.eval_cost(&report.matrix);
        let j = j_on_reference(&report.matrix);
        rows.push(TradeoffRow {
            setting: topo.to_string(),
            seconds: per_case,
            error: j,
        });
    }
    knobs.push(Knob {
        knob: "topology",
        time_of: "one PRB load case",
        error_of: "J of the fitted model (normal fidelity) on the reference",
        rows,
    });
    Ok(knobs)
}
