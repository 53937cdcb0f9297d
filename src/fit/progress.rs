//! Progress of a running fit: the best point seen so far, reported to the caller at most every
//! [`PROGRESS_INTERVAL`] seconds and at the end of each phase.

use std::time::Instant;

use nalgebra::DVector;

use crate::prb::PrbMatrix;

use super::Parameterisation;

/// A progress report, at most every [`PROGRESS_INTERVAL`] seconds and at the end of each
/// phase.
#[derive(Debug, Clone, Copy)]
pub struct FitProgress<'a> {
    /// `swarm` or `polish`.
    pub phase: &'static str,
    /// Iterations of the current phase.
    pub iteration: u32,
    /// Evaluations of J so far.
    pub evaluations: u64,
    /// J of the best matrix so far.
    pub best_objective: f64,
    /// The best matrix so far.
    pub best: &'a PrbMatrix,
    /// Since the fit started.
    pub seconds: f64,
}

/// Minimum time between progress reports.
pub const PROGRESS_INTERVAL: f64 = 0.02;

/// Keeps the best point seen and reports progress, throttled.
pub(super) struct Tracker<'a, 'b> {
    param: &'a Parameterisation,
    t0: Instant,
    last_report: f64,
    pub(super) best_j: f64,
    pub(super) best_p: DVector<f64>,
    best_matrix: Option<PrbMatrix>,
    unreported: bool,
    progress: &'b mut dyn FnMut(&FitProgress),
}

impl<'a, 'b> Tracker<'a, 'b> {
    pub(super) fn new(
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

    pub(super) fn offer(
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

    pub(super) fn flush(&mut self, phase: &'static str, iteration: u32, evaluations: u64) {
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
