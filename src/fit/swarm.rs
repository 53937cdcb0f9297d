//! The global phase: argmin's particle swarm over the reparameterised cells, its population
//! seeded with the starts, in a box around them.

use std::cell::RefCell;

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use nalgebra::DVector;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::objective::Objective;
use super::progress::Tracker;
use super::starts::Starts;

/// The swarm's view of J.
struct SwarmCost<'a, 'b, 'c, 'd> {
    objective: &'a Objective<'a>,
    tracker: RefCell<&'b mut Tracker<'c, 'd>>,
    particles: usize,
}

impl CostFunction for SwarmCost<'_, '_, '_, '_> {
    type Param = DVector<f64>;
    type Output = f64;

    fn cost(&self, p: &Self::Param) -> Result<f64, argmin::core::Error> {
        // Cancelled: no J, so nothing for the tracker, and an infinite cost (as a start-up
        // particle that cannot be evaluated gets) that no real one loses to: the swarm runs
        // out its few remaining iterations in microseconds, and no cancelled particle becomes
        // its best. (A flat 1000 did, once heavy weights put real J above it: a cancelled
        // fit then returned a particle never evaluated.)
        let Some(j) = self.objective.value(p) else {
            return Ok(f64::INFINITY);
        };
        let evaluations = self.objective.evaluations();
        let iteration = (evaluations / self.particles as u64) as u32;
        self.tracker
            .borrow_mut()
            .offer("swarm", iteration, j, p, evaluations);
        Ok(j)
    }
}

/// Runs the swarm from `starts` (topped up with random particles) for `iterations`;
/// returns its best point, if it found one, and the iterations it ran.
pub(super) fn run(
    objective: &Objective<'_>,
    tracker: &mut Tracker<'_, '_>,
    starts: &mut Starts,
    (particles, iterations): (usize, u64),
    seed: u64,
) -> (Option<DVector<f64>>, u32) {
    let n = starts.lower.len();
    let (lower, upper) = (starts.lower.clone(), starts.upper.clone());
    let mut population = Vec::with_capacity(particles);
    for s in starts.points.iter().take(particles) {
        let cost = objective.value(s).unwrap_or(f64::INFINITY);
        population.push(Particle::new(s.clone(), cost, DVector::zeros(n)));
    }
    let rng = starts.rng();
    while population.len() < particles {
        let p = DVector::from_fn(n, |i, _| rng.random_range(lower[i]..=upper[i]));
        let v = DVector::from_fn(n, |i, _| {
            0.1 * rng.random_range(lower[i] - upper[i]..=upper[i] - lower[i])
        });
        let cost = objective.value(&p).unwrap_or(f64::INFINITY);
        population.push(Particle::new(p, cost, v));
    }
    let swarm = ParticleSwarm::new((lower, upper), particles)
        .with_rng_generator(StdRng::seed_from_u64(seed ^ 0x5eed));
    let cost = SwarmCost {
        objective,
        tracker: RefCell::new(tracker),
        particles,
    };
    let result = Executor::new(cost, swarm)
        .configure(|state| state.population(population).max_iters(iterations))
        .timer(false)
        .run();
    // The swarm only reports errors of its own bookkeeping; if it fails the polish still
    // runs from the starts.
    match result {
        Ok(result) => (
            result
                .state()
                .get_best_param()
                .map(|best| best.position.clone()),
            result.state().get_iter() as u32,
        ),
        Err(_) => (None, 0),
    }
}
