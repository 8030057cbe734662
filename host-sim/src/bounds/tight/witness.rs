//! Witnesses: admissible states at which the actual law comes close to a bound.
//!
//! For each bounded quantity ([`Quantity`]) [`witnesses`] maximises the law's value over the
//! confining set of [`super::sampling`], in the parameter space of
//! [`AdmissibleState::from_parameters`] (which keeps every candidate admissible by clamping each
//! part to its set):
//! 1. a global phase evaluates many random admissible states
//!    ([`super::sampling::sample_parameters_for`]);
//! 2. local searches start from the best of them and from the best of disjoint groups of them
//!    (diverse basins): an adaptive compass search (per-coordinate steps, doubled on success,
//!    halved on failure), a (1+1) evolution strategy for ridges not aligned with the
//!    coordinates, the compass search again, then basin hopping (random kicks, each climbed
//!    again, kept if higher) until the budget is spent.
//!
//! Every value is the controller-core law's own ([`AdmissibleState::evaluate`]). A witness is
//! a lower bound on the supremum: a sound upper bound within a few per cent of it shows that
//! the bound is nearly exact.
//!
//! Deterministic for a given seed: samples are drawn in fixed chunks and each local search has
//! its own generator, all seeded from one generator; parallel results are collected in order.

use anyhow::{anyhow, Result};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;

use super::sampling::{sample_parameters_for, AdmissibleState, LawValues, PARAMETER_COUNT};
use super::setup::Setup;

/// A quantity the a-priori bounds bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `|ω_d|` [rad/s] (Lemma 1's `U_ωd`).
    AngularVelocity,
    /// `|ω̇_d|` [rad/s²] (Lemma 1's `U_ω̇d`).
    AngularAcceleration,
    /// `H₁₂ = |(ω̇_d1, ω̇_d2)|` [rad/s²]: the roll/pitch part of `ω̇_d`.
    HorizontalAngularAcceleration,
    /// `H₃ = |ω̇_d3|` [rad/s²]: the yaw part of `ω̇_d`.
    YawAngularAcceleration,
    /// `|τ_i|` [N m] on body axis `i ∈ {0, 1, 2}` (Theorem 2's `τ_max`).
    Torque(usize),
}

/// Every quantity, in the order of [`Witnesses::all`].
pub const QUANTITIES: [Quantity; 7] = [
    Quantity::AngularVelocity,
    Quantity::AngularAcceleration,
    Quantity::HorizontalAngularAcceleration,
    Quantity::YawAngularAcceleration,
    Quantity::Torque(0),
    Quantity::Torque(1),
    Quantity::Torque(2),
];

impl Quantity {
    /// The quantity's value in `values` (SI units as in the variant's documentation).
    pub fn of(self, values: &LawValues) -> f64 {
        match self {
            Self::AngularVelocity => values.angular_velocity_norm(),
            Self::AngularAcceleration => values.angular_acceleration_norm(),
            Self::HorizontalAngularAcceleration => values.horizontal_acceleration(),
            Self::YawAngularAcceleration => values.yaw_acceleration(),
            Self::Torque(i) => values.torque.get(i).map_or(f64::NAN, |t| t.abs()),
        }
    }

    /// A short name for reports, e.g. `"|tau_1|"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::AngularVelocity => "|omega_d|",
            Self::AngularAcceleration => "|omega_d_dot|",
            Self::HorizontalAngularAcceleration => "H12 = |(omega_d_dot_1, omega_d_dot_2)|",
            Self::YawAngularAcceleration => "H3 = |omega_d_dot_3|",
            Self::Torque(0) => "|tau_1|",
            Self::Torque(1) => "|tau_2|",
            Self::Torque(_) => "|tau_3|",
        }
    }
}

/// How much search [`witnesses`] spends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WitnessBudget {
    /// Random admissible states of the global phase (shared by all quantities).
    pub samples: usize,
    /// Local searches per quantity, started from the best samples for that quantity.
    pub restarts: usize,
    /// Law evaluations per local search.
    pub evaluations: usize,
}

impl Default for WitnessBudget {
    /// About two seconds for the paper's set-up on two cores (1.7·10⁶ law evaluations); four
    /// seeds gave the same witnesses to within 0.1 %.
    fn default() -> Self {
        Self {
            samples: 20_000,
            restarts: 12,
            evaluations: 20_000,
        }
    }
}

/// The best admissible state found for one quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Witness {
    /// What was maximised.
    pub quantity: Quantity,
    /// Its value at [`Self::state`] (units of the quantity).
    pub value: f64,
    /// The parameter vector ([`AdmissibleState::from_parameters`]) of the state.
    pub parameters: Vec<f64>,
    /// The admissible state (re-evaluate it with [`AdmissibleState::evaluate`]).
    pub state: AdmissibleState,
    /// Everything the law gives at the state.
    pub values: LawValues,
}

/// One witness per quantity and what the search cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Witnesses {
    /// The witnesses in the order of [`QUANTITIES`].
    pub all: Vec<Witness>,
    /// Law evaluations spent in all.
    pub evaluations: usize,
}

impl Witnesses {
    /// The witness of `quantity`.
    ///
    /// Panics only if `quantity` is `Torque(i)` with `i > 2` (not a quantity of the law).
    pub fn get(&self, quantity: Quantity) -> &Witness {
        self.all
            .iter()
            .find(|w| w.quantity == quantity)
            .unwrap_or_else(|| panic!("no witness for {quantity:?}: torque axes are 0, 1, 2"))
    }
}

/// The quantity at the state of `x`, or `−∞` if the law refuses it (impossible for a set-up
/// `certify` accepts).
fn objective(setup: &Setup, quantity: Quantity, x: &[f64]) -> f64 {
    AdmissibleState::from_parameters(setup, x)
        .evaluate(setup)
        .map_or(f64::NEG_INFINITY, |v| quantity.of(&v))
}

/// `x` moved onto the parameterised admissible family (idempotent).
fn project(setup: &Setup, x: &[f64]) -> Vec<f64> {
    AdmissibleState::from_parameters(setup, x).parameters(setup)
}

/// Adaptive compass search from `start`, at most `evaluations` law evaluations; returns the
/// best (projected) parameters, their value and the evaluations used.
fn compass(
    setup: &Setup,
    quantity: Quantity,
    start: &[f64],
    evaluations: usize,
) -> (Vec<f64>, f64, usize) {
    const INITIAL_STEP: f64 = 0.25;
    const SMALLEST_STEP: f64 = 1e-9;
    let mut x = project(setup, start);
    let mut best = objective(setup, quantity, &x);
    let mut used = 1;
    let mut steps = vec![INITIAL_STEP; x.len()];
    let mut round_start = best;
    while used < evaluations {
        for i in 0..x.len() {
            if steps[i] < SMALLEST_STEP || used >= evaluations {
                continue;
            }
            let mut moved = false;
            for direction in [1.0, -1.0] {
                let mut y = x.clone();
                y[i] += direction * steps[i];
                let y = project(setup, &y);
                if y == x {
                    continue;
                }
                let v = objective(setup, quantity, &y);
                used += 1;
                if v > best {
                    x = y;
                    best = v;
                    moved = true;
                    break;
                }
            }
            steps[i] = if moved {
                (steps[i] * 2.0).min(1.0)
            } else {
                steps[i] * 0.5
            };
        }
        if steps.iter().all(|s| *s < SMALLEST_STEP) {
            // Converged along every coordinate: restart the steps while the last round still
            // gained (a ridge not aligned with the axes is climbed in several rounds).
            if best <= round_start * (1.0 + 1e-9) {
                break;
            }
            round_start = best;
            steps.fill(INITIAL_STEP * 0.2);
        }
    }
    (x, best, used)
}

/// A (1+1) evolution strategy from `start` (step size by the one-fifth success rule): each
/// trial moves a random subset of the coordinates by Gaussian steps, so it climbs ridges that
/// are not aligned with the coordinates, where [`compass`] stalls.
fn evolve(
    setup: &Setup,
    quantity: Quantity,
    start: &[f64],
    evaluations: usize,
    rng: &mut ChaCha8Rng,
) -> (Vec<f64>, f64, usize) {
    let mut x = project(setup, start);
    let mut best = objective(setup, quantity, &x);
    let mut used = 1;
    let mut sigma = 0.05;
    while used < evaluations && sigma > 1e-9 {
        let fraction = rng.random_range(0.05..0.5);
        let y = project(setup, &perturb(&x, fraction, sigma, rng));
        if y == x {
            sigma *= 0.84;
            continue;
        }
        let v = objective(setup, quantity, &y);
        used += 1;
        if v > best {
            x = y;
            best = v;
            sigma *= 1.5;
        } else {
            // 1.5^(−1/4): the step size is stationary at one success in five.
            sigma *= 0.904;
        }
    }
    (x, best, used)
}

/// `x` with each coordinate, with probability `fraction`, moved by `scale` times a standard
/// normal draw (parameters are in `[0, 1]`, so `scale` is a fraction of a parameter's range).
fn perturb(x: &[f64], fraction: f64, scale: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    x.iter()
        .map(|v| {
            if rng.random_bool(fraction) {
                let n: f64 = rng.sample(StandardNormal);
                v + scale * n
            } else {
                *v
            }
        })
        .collect()
}

/// Local improvement of one restart: compass search, then the evolution strategy, then
/// compass search again; the rest of the `evaluations` goes to basin hopping (a large random
/// kick to the best point, climbed again by compass search, kept if it ends higher).
fn improve(
    setup: &Setup,
    quantity: Quantity,
    start: &[f64],
    evaluations: usize,
    seed: u64,
) -> (Vec<f64>, f64, usize) {
    const HOP_EVALUATIONS: usize = 2000;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (x, _, a) = compass(setup, quantity, start, evaluations / 4);
    let (x, _, b) = evolve(setup, quantity, &x, evaluations / 4, &mut rng);
    let (mut x, mut best, c) = compass(setup, quantity, &x, evaluations / 4);
    let mut used = a + b + c;
    while used < evaluations {
        let kick = rng.random_range(0.05..0.5);
        let fraction = rng.random_range(0.05..0.3);
        let y = perturb(&x, fraction, kick, &mut rng);
        let (y, v, d) = compass(setup, quantity, &y, HOP_EVALUATIONS.min(evaluations - used));
        used += d;
        if v > best {
            x = y;
            best = v;
        }
    }
    (x, best, used)
}

/// Indices of the samples the local searches start from: the best `⌈restarts/2⌉` overall,
/// then the best of each of `⌊restarts/2⌋` disjoint groups of consecutive samples (diverse
/// starts: the best few overall often lie in one basin).
fn starts(count: usize, restarts: usize, value: impl Fn(usize) -> f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_by(|a, b| value(*b).total_cmp(&value(*a)));
    let mut chosen: Vec<usize> = order.into_iter().take(restarts.div_ceil(2)).collect();
    let groups = restarts / 2;
    for g in 0..groups {
        let range = g * count / groups..(g + 1) * count / groups;
        if let Some(i) = range
            .filter(|i| !chosen.contains(i))
            .max_by(|a, b| value(*a).total_cmp(&value(*b)).then(b.cmp(a)))
        {
            chosen.push(i);
        }
    }
    chosen
}

/// Number of samples drawn from one chunk's generator.
const CHUNK: usize = 1024;

/// Searches the confining set of `setup` for the largest value of every [`Quantity`].
///
/// Deterministic for a given `seed` and `budget` (independent of the thread count). Runtime
/// scales with `samples + 7 · restarts · evaluations` law evaluations (about a microsecond
/// each in a release build).
///
/// Errors: a set-up `certify` refuses (then `u` may point down and the law is undefined).
pub fn witnesses(setup: &Setup, seed: u64, budget: &WitnessBudget) -> Result<Witnesses> {
    setup.certificate()?;
    let mut master = ChaCha8Rng::seed_from_u64(seed);
    let chunk_seeds: Vec<u64> = (0..budget.samples.div_ceil(CHUNK))
        .map(|_| master.random())
        .collect();
    let samples: Vec<(Vec<f64>, Option<LawValues>)> = chunk_seeds
        .par_iter()
        .enumerate()
        .flat_map_iter(|(c, s)| {
            let mut rng = ChaCha8Rng::seed_from_u64(*s);
            let n = CHUNK.min(budget.samples - c * CHUNK);
            (0..n)
                .map(|_| {
                    let x = sample_parameters_for(&mut rng, setup);
                    let state = AdmissibleState::from_parameters(setup, &x);
                    (x, state.evaluate(setup).ok())
                })
                .collect::<Vec<_>>()
        })
        .collect();

    let value =
        |q: Quantity, i: usize| samples[i].1.as_ref().map_or(f64::NEG_INFINITY, |v| q.of(v));
    let jobs: Vec<(usize, Vec<f64>)> = QUANTITIES
        .iter()
        .enumerate()
        .flat_map(|(k, q)| {
            starts(samples.len(), budget.restarts.max(1), |i| value(*q, i))
                .into_iter()
                .map(move |i| (k, i))
        })
        .map(|(k, i)| {
            let start = samples
                .get(i)
                .map_or_else(|| vec![0.0; PARAMETER_COUNT], |s| s.0.clone());
            (k, start)
        })
        .collect();
    let job_seeds: Vec<u64> = jobs.iter().map(|_| master.random()).collect();
    let results: Vec<(usize, Vec<f64>, f64, usize)> = jobs
        .par_iter()
        .zip(&job_seeds)
        .map(|((k, start), seed)| {
            let (x, v, used) = improve(setup, QUANTITIES[*k], start, budget.evaluations, *seed);
            (*k, x, v, used)
        })
        .collect();

    let evaluations = samples.len() + results.iter().map(|r| r.3).sum::<usize>();
    let all = QUANTITIES
        .iter()
        .enumerate()
        .map(|(k, q)| {
            // The first best on ties: independent of scheduling.
            let best = results.iter().filter(|r| r.0 == k).fold(
                None::<&(usize, Vec<f64>, f64, usize)>,
                |acc, r| match acc {
                    Some(a) if a.2 >= r.2 => Some(a),
                    _ => Some(r),
                },
            );
            let parameters = best.map_or_else(|| vec![0.0; PARAMETER_COUNT], |r| r.1.clone());
            let state = AdmissibleState::from_parameters(setup, &parameters);
            let values = state
                .evaluate(setup)
                .map_err(|e| anyhow!("the law refuses the witness of {}: {e:?}", q.name()))?;
            Ok(Witness {
                quantity: *q,
                value: q.of(&values),
                parameters,
                state,
                values,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Witnesses { all, evaluations })
}
