//! Progress of a running fit: the best point seen so far, reported to the caller at most every
//! [`PROGRESS_INTERVAL`] seconds and at the end of each phase, and at least every
//! [`HEARTBEAT`] seconds while the search goes on without a better point (so a long fit
//! never looks stalled).

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
    /// Whether `best` is new since the last report; false for a report that only says the
    /// search goes on ([`HEARTBEAT`]).
    pub improved: bool,
}

/// Minimum time between progress reports.
pub const PROGRESS_INTERVAL: f64 = 0.02;

/// Maximum time between progress reports while the search goes on without a better point
/// (seconds): a fit on many cases can search for minutes between two improvements, and its
/// evaluations and time should still move on screen.
pub const HEARTBEAT: f64 = 0.5;

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
        let since = now - self.last_report;
        if (self.unreported && since >= PROGRESS_INTERVAL) || since >= HEARTBEAT {
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
                improved: self.unreported,
            });
            self.last_report = now;
            self.unreported = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A better point is reported (`improved`); a worse one is not, until the search has gone
    /// [`HEARTBEAT`] seconds without a report, when the best so far is reported again, not
    /// improved (a long fit's status used to stand still for as long as nothing improved).
    #[test]
    fn a_search_without_a_better_point_still_reports_at_the_heartbeat() {
        let m = PrbMatrix::parse("0.1,inf,inf; 0.9,2.2,inf").unwrap();
        let param = Parameterisation::new(&m).unwrap();
        let p = param.encode(&m);
        let mut seen = Vec::new();
        let mut progress =
            |f: &FitProgress| seen.push((f.improved, f.evaluations, f.best_objective));
        let mut tracker = Tracker::new(&param, Instant::now(), &mut progress);
        tracker.offer("swarm", 0, 1.0, &p, 1);
        tracker.offer("swarm", 0, 2.0, &p, 2);
        // As if HEARTBEAT had passed since the last report.
        tracker.last_report -= HEARTBEAT;
        tracker.offer("swarm", 1, 3.0, &p, 3);
        tracker.offer("swarm", 1, 4.0, &p, 4);
        drop(tracker);
        assert_eq!(seen, vec![(true, 1, 1.0), (false, 3, 1.0)]);
    }
}
