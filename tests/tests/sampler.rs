//! The campaign samplers: Haar-uniform attitudes (checked statistically), balls, seeds.

use host_sim::campaign::sampler::{haar_quaternion, run_seed, seeded_rng, uniform_in_ball};
use host_sim::so3::rotation_angle;
use nalgebra::{Matrix3, UnitQuaternion};

/// Kolmogorov–Smirnov statistic of `samples` against the CDF `cdf`.
fn ks_statistic(mut samples: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let f = cdf(x);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// Critical value of the one-sample KS test at level `alpha` for large `n`:
/// `sqrt(−ln(α/2)/2) / sqrt(n)` (asymptotic Kolmogorov distribution).
fn ks_critical(alpha: f64, n: usize) -> f64 {
    (-(alpha / 2.0).ln() / 2.0).sqrt() / (n as f64).sqrt()
}

/// Rotation angle of a unit quaternion, in [0, π] (host-sim's, on its matrix).
fn angle(q: &UnitQuaternion<f64>) -> f64 {
    rotation_angle(q.to_rotation_matrix().matrix())
}

/// Haar measure on SO(3): the rotation angle has CDF (θ − sin θ)/π.
fn haar_angle_cdf(theta: f64) -> f64 {
    (theta - theta.sin()) / std::f64::consts::PI
}

const N: usize = 20_000;

#[test]
fn haar_rotation_angles_pass_kolmogorov_smirnov() {
    let mut rng = seeded_rng(2024);
    let angles: Vec<f64> = (0..N).map(|_| angle(&haar_quaternion(&mut rng))).collect();
    let d = ks_statistic(angles, haar_angle_cdf);
    let critical = ks_critical(1e-3, N);
    assert!(d < critical, "KS statistic {d} >= critical {critical}");
}

/// The same test rejects a plausible but wrong sampler (Euler angles uniform in their boxes),
/// so it has the power to catch a non-Haar sampler.
#[test]
fn kolmogorov_smirnov_rejects_uniform_euler_angles() {
    let mut rng = seeded_rng(2024);
    let mut uniform = |lo: f64, hi: f64| {
        // Map a Haar quaternion's component to [0, 1) is not uniform; use the ball sampler's
        // radius instead: |b|³ for b uniform in the unit ball is uniform on [0, 1).
        let u = uniform_in_ball(&mut rng, 1.0).norm().powi(3);
        lo + (hi - lo) * u
    };
    use std::f64::consts::PI;
    let angles: Vec<f64> = (0..N)
        .map(|_| {
            let q = UnitQuaternion::from_euler_angles(
                uniform(-PI, PI),
                uniform(-PI / 2.0, PI / 2.0),
                uniform(-PI, PI),
            );
            angle(&q)
        })
        .collect();
    let d = ks_statistic(angles, haar_angle_cdf);
    assert!(d > ks_critical(1e-3, N), "KS statistic {d} should reject");
}

#[test]
fn haar_mean_rotation_is_zero() {
    let mut rng = seeded_rng(7);
    let mut sum = Matrix3::zeros();
    for _ in 0..N {
        sum += haar_quaternion(&mut rng).to_rotation_matrix().into_inner();
    }
    let mean = sum / N as f64;
    // Each entry of a Haar rotation has mean 0 and variance 1/3: the standard error of the mean
    // is sqrt(1/(3N)) = 0.0041; 5 standard errors.
    let tol = 5.0 * (1.0 / (3.0 * N as f64)).sqrt();
    assert!(mean.amax() < tol, "E[R] = {mean}");
}

#[test]
fn ball_samples_are_inside_and_uniform_in_volume() {
    let mut rng = seeded_rng(11);
    let r = 3.0;
    let mut inner = 0usize;
    for _ in 0..N {
        let b = uniform_in_ball(&mut rng, r);
        assert!(b.norm() <= r);
        inner += usize::from(b.norm() < r / 2.0);
    }
    // P(|b| < r/2) = 1/8; standard error sqrt(p(1 − p)/N) = 0.0023; 5 standard errors.
    let p = inner as f64 / N as f64;
    assert!(
        (p - 0.125).abs() < 5.0 * (0.125 * 0.875 / N as f64).sqrt(),
        "{p}"
    );
}

#[test]
fn run_seeds_are_distinct() {
    let mut seeds: Vec<u64> = (0..10_000).map(|i| run_seed(1, i)).collect();
    seeds.extend((0..10_000).map(|i| run_seed(2, i)));
    seeds.sort_unstable();
    seeds.dedup();
    assert_eq!(seeds.len(), 20_000);
}
