//! Where the fit starts: the given matrix, the topology's sensible default (in case the given
//! one is wild), the published models of the same topology (so a fitted 3R is never worse than
//! Su's or Chen's), and seeded random points in a box around them.

use nalgebra::DVector;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use crate::fidelity::Fidelity;
use crate::prb::{published, PrbMatrix};

use super::Parameterisation;

/// The starting points and the box the global phase searches.
pub(super) struct Starts {
    /// Encoded starting points; the given matrix first.
    pub points: Vec<DVector<f64>>,
    /// Lower corner of the search box.
    pub lower: DVector<f64>,
    /// Upper corner of the search box.
    pub upper: DVector<f64>,
    /// The seeded generator, for the swarm's extra particles.
    pub rng: StdRng,
}

/// The starts for fitting `start` at `fidelity`, deterministic for `seed`.
pub(super) fn starts(
    param: &Parameterisation,
    start: &PrbMatrix,
    fidelity: Fidelity,
    seed: u64,
) -> Starts {
    let p_start = param.encode(start);
    let topology = start.topology();
    let mut points = vec![p_start.clone()];
    if let Ok(default) = PrbMatrix::from_topology(&topology) {
        points.push(param.encode(&default));
    }
    for prb in published::matrices() {
        if prb.topology() == topology {
            points.push(param.encode(prb));
        }
    }
    let (mut lower, mut upper) = param.search_box(&p_start);
    for s in &points {
        let (lo, hi) = param.search_box(s);
        lower = lower.inf(&lo);
        upper = upper.sup(&hi);
    }
    let mut rng = StdRng::seed_from_u64(seed);
    for _ in 0..fidelity.random_starts() {
        points.push(DVector::from_fn(param.len(), |i, _| {
            rng.random_range(lower[i]..=upper[i])
        }));
    }
    Starts {
        points,
        lower,
        upper,
        rng,
    }
}
