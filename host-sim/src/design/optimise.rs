//! The optimiser: argmin's particle swarm over the unit box of [`super::variables`], seeded
//! from `--seed` (the swarm's moves: Xoshiro256++; the first swarm: ChaCha8), with the initial guess as one particle of the first swarm, so
//! the result is never worse than the guess. Particles are scored in parallel (argmin's rayon
//! `bulk_cost`), and each score flies its runs in parallel too.

use std::sync::Mutex;

use anyhow::{anyhow, Result};
use argmin::core::{CostFunction, Error, Executor, PopulationState, State};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use rand::RngExt;
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::runs::sampler::seeded_rng;

/// Particles per swarm (capped by the budget).
pub const PARTICLES: usize = 16;

/// The cost function argmin sees: a closure over the unit box, remembering every point scored.
struct Objective<'a, F: Fn(&[f64]) -> f64 + Sync> {
    cost: &'a F,
    seen: &'a Mutex<Vec<(Vec<f64>, f64)>>,
}

impl<F: Fn(&[f64]) -> f64 + Sync> CostFunction for Objective<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Self::Param) -> Result<f64, Error> {
        let c = (self.cost)(x);
        if let Ok(mut seen) = self.seen.lock() {
            seen.push((x.clone(), c));
        }
        Ok(c)
    }
}

/// The best point found and how many points were scored.
#[derive(Clone, Debug)]
pub struct Optimum {
    /// Best point of the unit box.
    pub x: Vec<f64>,
    /// Its cost.
    pub cost: f64,
    /// Points scored.
    pub evaluations: usize,
}

/// Minimises `cost` over `[0, 1]^n` (`n = guess.len()`) with about `budget` evaluations, from
/// `guess`, reproducibly from `seed`. Errors: argmin's.
pub fn minimise<F: Fn(&[f64]) -> f64 + Sync>(
    cost: &F,
    guess: &[f64],
    budget: usize,
    seed: u64,
) -> Result<Optimum> {
    let dimension = guess.len();
    let seen = Mutex::new(Vec::new());
    let problem = Objective { cost, seen: &seen };
    let particles = PARTICLES.min(budget.max(1));
    let iterations = (budget / particles).saturating_sub(1) as u64;
    let mut rng = seeded_rng(seed);
    // The first swarm: the guess plus random points, velocities up to a quarter of the box.
    let mut positions = vec![guess.to_vec()];
    while positions.len() < particles {
        positions.push((0..dimension).map(|_| rng.random_range(0.0..1.0)).collect());
    }
    let population: Vec<Particle<Vec<f64>, f64>> = {
        use rayon::prelude::*;
        let costs: Vec<f64> = positions
            .par_iter()
            .map(|p| problem.cost(p).unwrap_or(f64::MAX))
            .collect();
        positions
            .into_iter()
            .zip(costs)
            .map(|(p, c)| {
                let v = (0..dimension)
                    .map(|_| rng.random_range(-0.25..0.25))
                    .collect();
                Particle::new(p, c, v)
            })
            .collect()
    };
    let solver = ParticleSwarm::new((vec![0.0; dimension], vec![1.0; dimension]), particles)
        .with_rng_generator(Xoshiro256PlusPlus::seed_from_u64(seed));
    let result = Executor::new(problem, solver)
        .configure(|state: PopulationState<Particle<Vec<f64>, f64>, f64>| {
            state.population(population).max_iters(iterations)
        })
        .run()
        .map_err(|e| anyhow!("particle swarm: {e}"))?;
    let best = result
        .state()
        .get_best_param()
        .map(|p| p.position.clone())
        .ok_or_else(|| anyhow!("particle swarm returned no point"))?;
    let evaluations = seen.lock().map(|s| s.len()).unwrap_or(0);
    Ok(Optimum {
        cost: result.state().get_best_cost(),
        x: best,
        evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a smooth bowl the swarm improves on its guess and is reproducible from the seed.
    #[test]
    fn reproducible_and_improves() {
        let target = [0.3, 0.7, 0.1, 0.9, 0.5, 0.2, 0.8, 0.4, 0.6];
        let f = |x: &[f64]| {
            x.iter()
                .zip(target)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
        };
        let guess = vec![0.5; target.len()];
        let a = minimise(&f, &guess, 200, 7).unwrap();
        let b = minimise(&f, &guess, 200, 7).unwrap();
        assert_eq!(a.x, b.x);
        assert!(a.cost < f(&guess) * 0.5, "{} vs {}", a.cost, f(&guess));
        assert!(
            a.evaluations <= 200 && a.evaluations >= 150,
            "{}",
            a.evaluations
        );
    }
}
