//! Random admissible states: where the draws fall (often on the boundaries of their sets, where
//! the suprema are) and how the filter inputs are shaped.

use rand::{Rng, RngExt};

use super::*;

/// A value in `[−1, 1]`: an end with probability `edge`, otherwise uniform.
fn unit_value<R: Rng + ?Sized>(rng: &mut R, edge: f64) -> f64 {
    if rng.random_bool(edge) {
        if rng.random_bool(0.5) {
            1.0
        } else {
            -1.0
        }
    } else {
        rng.random_range(-1.0..=1.0)
    }
}

/// A point of the unit ball in `N` dimensions: on the sphere with probability `edge`,
/// otherwise uniform in the ball (direction uniform, radius `U^{1/N}`).
fn ball_value<R: Rng + ?Sized, const N: usize>(rng: &mut R, edge: f64) -> [f64; N] {
    let direction: [f64; N] = loop {
        let v: [f64; N] = core::array::from_fn(|_| rng.random_range(-1.0..=1.0));
        let n2: f64 = v.iter().map(|x| x * x).sum();
        if n2 > 1e-6 && n2 <= 1.0 {
            let n = n2.sqrt();
            break v.map(|x| x / n);
        }
    };
    let radius = if rng.random_bool(edge) {
        1.0
    } else {
        rng.random_range(0.0f64..=1.0).powf(1.0 / N as f64)
    };
    direction.map(|x| x * radius)
}

/// The parameters of one filter history, from a mix of input shapes: random levels and
/// durations; bang-bang at `±M_p` with 1–3 switches; a long hold at `±M_p` then the opposite
/// level for a random time (the extreme points of the reachable set); a long hold at a random
/// level (a steady state).
fn filter_parameters<R: Rng + ?Sized>(rng: &mut R) -> [f64; FILTER_PARAMETERS] {
    let mut start = [unit_value(rng, 0.5), unit_value(rng, 0.5)];
    let mut levels = [0.0; SEGMENTS];
    let mut durations = [0.0; SEGMENTS];
    match rng.random_range(0..4u8) {
        0 => {
            for k in 0..SEGMENTS {
                levels[k] = rng.random_range(-1.0..=1.0);
                durations[k] = rng.random_range(0.0..=1.0);
            }
        }
        1 => {
            let switches = rng.random_range(1..SEGMENTS);
            let first = SEGMENTS - 1 - switches;
            let mut sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            for k in first..SEGMENTS {
                levels[k] = sign;
                durations[k] = rng.random_range(0.0..=1.0);
                sign = -sign;
            }
        }
        2 => {
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            levels[SEGMENTS - 2] = sign;
            durations[SEGMENTS - 2] = 1.0;
            levels[SEGMENTS - 1] = -sign;
            // Mostly short: the switch's transient is where u_f − u_s is largest.
            durations[SEGMENTS - 1] = rng.random_range(0.0f64..=1.0).powi(2);
        }
        _ => {
            levels[SEGMENTS - 1] = unit_value(rng, 0.5);
            durations[SEGMENTS - 1] = 1.0;
            start = [0.0; 2];
        }
    }
    let mut x = [0.0; FILTER_PARAMETERS];
    x[..2].copy_from_slice(&start);
    x[2..2 + SEGMENTS].copy_from_slice(&levels);
    x[2 + SEGMENTS..].copy_from_slice(&durations);
    x
}

/// A random admissible state's parameter vector (see [`sample`]).
pub fn sample_parameters<R: Rng + ?Sized>(rng: &mut R) -> Vec<f64> {
    let mut x = Vec::with_capacity(PARAMETER_COUNT);
    for _ in 0..3 {
        x.extend(filter_parameters(rng));
    }
    for _ in 0..3 {
        x.push(unit_value(rng, 0.5));
    }
    x.extend(ball_value::<_, 2>(rng, 0.5));
    x.push(unit_value(rng, 0.5));
    x.extend(ball_value::<_, 3>(rng, 0.5));
    x.extend(ball_value::<_, 3>(rng, 0.5));
    x.push(rng.random_range(-1.0..=1.0));
    x.push(unit_value(rng, 0.5));
    x.push(unit_value(rng, 0.5));
    x.extend(ball_value::<_, 3>(rng, 0.5));
    // ω̃: often large (s_ω near M_ω), otherwise anywhere down to 10⁻³ of the box.
    let scale = if rng.random_bool(0.5) {
        1.0
    } else {
        10f64.powf(-rng.random_range(0.0..3.0))
    };
    x.extend(ball_value::<_, 3>(rng, 0.5).map(|v| v * scale * 3f64.sqrt()));
    x
}

/// A random admissible state of `setup`, dense in the confining set with much weight on its
/// boundaries: filter inputs of mixed shapes ([`FilterHistory`]), `ubar` often at the corners
/// of `[−M_p, M_p]³`, reference derivatives and `ϑ̃` often on their spheres, `ψ̇`, `ψ̈` often
/// at their limits, `ω̃` often large.
pub fn sample<R: Rng + ?Sized>(rng: &mut R, setup: &Setup) -> AdmissibleState {
    AdmissibleState::from_parameters(setup, &sample_parameters_for(rng, setup))
}

/// [`sample_parameters`], followed by the integral action's [`INTEGRAL_PARAMETERS`] (`η`, `η_f`
/// and `η̇`, each often at its limit) when `setup` has it on; without it the draws, hence the
/// random stream, are exactly [`sample_parameters`]'.
pub fn sample_parameters_for<R: Rng + ?Sized>(rng: &mut R, setup: &Setup) -> Vec<f64> {
    let mut x = sample_parameters(rng);
    if setup.gains.integral.is_some() {
        x.extend((0..INTEGRAL_PARAMETERS).map(|_| unit_value(rng, 0.5)));
    }
    x
}
