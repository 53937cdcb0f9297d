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
    /// The seeded generator: drawn from for the random starts, then for the swarm's extra
    /// particles; built on first use (see [`Starts::rng`]).
    rng: Option<StdRng>,
    seed: u64,
}

impl Starts {
    /// The seeded generator, built on first use, so a draft fit (which draws nothing) never
    /// builds it. Building the first one in a process is dear: `ppv-lite86` (under
    /// `rand_chacha`) asks `is_x86_feature_detected!` which instructions to use, and that
    /// enumerates every processor feature (26-33 us in a virtual machine, where each `cpuid`
    /// traps: about a tenth of a draft fit's own time). Built late, it gives the same stream.
    pub fn rng(&mut self) -> &mut StdRng {
        let seed = self.seed;
        self.rng.get_or_insert_with(|| StdRng::seed_from_u64(seed))
    }
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
    let mut starts = Starts {
        points,
        lower,
        upper,
        rng: None,
        seed,
    };
    let (lower, upper) = (starts.lower.clone(), starts.upper.clone());
    for _ in 0..fidelity.random_starts() {
        let rng = starts.rng();
        let p = DVector::from_fn(param.len(), |i, _| rng.random_range(lower[i]..=upper[i]));
        starts.points.push(p);
    }
    starts
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A draft fit draws no random start and so builds no generator; the random starts of
    /// the other fidelities, and the swarm's draws after them, are the stream of a generator
    /// built at once from the same seed.
    #[test]
    fn the_generator_is_built_late_with_the_same_stream() {
        let start = PrbMatrix::from_topology("L-R-R-R").unwrap();
        let param = Parameterisation::new(&start).unwrap();
        let draft = starts(&param, &start, Fidelity::Draft, 7);
        assert!(draft.rng.is_none());
        assert_eq!(Fidelity::Draft.random_starts(), 0);

        let mut normal = starts(&param, &start, Fidelity::Normal, 7);
        let randoms = Fidelity::Normal.random_starts();
        assert!(randoms > 0);
        let mut eager = StdRng::seed_from_u64(7);
        let given = normal.points.len() - randoms;
        for p in &normal.points[given..] {
            let q = DVector::from_fn(param.len(), |i, _| {
                eager.random_range(normal.lower[i]..=normal.upper[i])
            });
            assert_eq!(p, &q);
        }
        let next: f64 = normal.rng().random();
        assert_eq!(next, eager.random::<f64>());
    }
}
