//! Initial conditions of a campaign, drawn reproducibly from `(campaign seed, run index)`.
//!
//! - Attitude: uniform on SO(3) (Haar measure): a unit quaternion from a normalised 4-D standard
//!   Gaussian, which is uniform on S³ by the rotational invariance of the Gaussian, hence Haar
//!   on SO(3) (Shoemake 1992, "Uniform random rotations", uses the same fact).
//! - A fixed set of starts exactly 180° from `R_d(0)` about the axes in [`HALF_TURN_AXES`]
//!   (desired body frame), with zero angular velocity and the reference velocity: the hardest
//!   starts for a continuous attitude law. They take the first run indices.
//! - Position `p_d(0) + b_p`, velocity `ṗ_d(0) + b_v`, body angular velocity `b_ω`, each `b`
//!   uniform in a ball of the configured radius (direction Gaussian-normalised, radius
//!   `r U^{1/3}`).
//!
//! `R_d(0)` is the paper law's desired attitude at `t = 0` with `x_f(0) = 0`: it depends only on
//! the reference (`u(0) = g e₃ + p̈_d(0)` and `ν_d(0)`), not on the start, so "180° from `R_d(0)`"
//! is well defined before the run.

use anyhow::{anyhow, Result};
use controller_core::desired_attitude::desired_attitude;
use controller_core::Trajectory;
use nalgebra::{Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
pub use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// Axes (desired body frame, normalised on use) of the fixed 180° starts, with their names.
pub const HALF_TURN_AXES: [(&str, [f64; 3]); 7] = [
    ("x", [1.0, 0.0, 0.0]),
    ("y", [0.0, 1.0, 0.0]),
    ("z", [0.0, 0.0, 1.0]),
    ("xy", [1.0, 1.0, 0.0]),
    ("xz", [1.0, 0.0, 1.0]),
    ("yz", [0.0, 1.0, 1.0]),
    ("xyz", [1.0, 1.0, 1.0]),
];

/// Radii of the balls the offsets are drawn from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SamplerRadii {
    /// Position offset from `p_d(0)` \[m\].
    pub position_m: f64,
    /// Velocity offset from `ṗ_d(0)` [m/s].
    pub velocity_m_s: f64,
    /// Body angular velocity [rad/s].
    pub angular_velocity_rad_s: f64,
}

impl Default for SamplerRadii {
    /// 10 m (the paper's start is 9.2 m away), 2 m/s, 2 rad/s.
    fn default() -> Self {
        Self {
            position_m: 10.0,
            velocity_m_s: 2.0,
            angular_velocity_rad_s: 2.0,
        }
    }
}

/// How a run's attitude was chosen.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartKind {
    /// Haar-uniform attitude.
    Haar,
    /// Exactly 180° from `R_d(0)` about the named axis.
    HalfTurn(&'static str),
}

impl StartKind {
    /// `"haar"` or `"half_turn_<axis>"`.
    pub fn label(&self) -> String {
        match self {
            Self::Haar => "haar".into(),
            Self::HalfTurn(a) => format!("half_turn_{a}"),
        }
    }
}

/// One run's initial condition.
#[derive(Clone, Debug)]
pub struct InitialCondition {
    /// How the attitude was chosen.
    pub kind: StartKind,
    /// The plant's initial state.
    pub state: RigidBodyState,
    /// Angle between `R(0)` and `R_d(0)` \[deg\].
    pub attitude_error_deg: f64,
}

/// A seed per run from the campaign seed and the run index (SplitMix64 finaliser of a Weyl
/// sequence), so a run's draws depend on nothing else, e.g. not on thread scheduling.
pub fn run_seed(campaign_seed: u64, index: u64) -> u64 {
    let mut z =
        campaign_seed.wrapping_add(index.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random generator of the campaign (ChaCha8), seeded.
pub fn seeded_rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A Haar-uniform rotation (unit quaternion, body to inertial).
pub fn haar_quaternion(rng: &mut ChaCha8Rng) -> UnitQuaternion<f64> {
    loop {
        let q = Quaternion::from_vector(nalgebra::Vector4::from_fn(|_, _| {
            rng.sample::<f64, _>(StandardNormal)
        }));
        // The Gaussian norm is 0 with probability 0; reject it (and denormals) anyway.
        if q.norm() > 1e-6 {
            return UnitQuaternion::new_normalize(q);
        }
    }
}

/// A point uniform in the ball of `radius` (3-D).
pub fn uniform_in_ball(rng: &mut ChaCha8Rng, radius: f64) -> Vector3<f64> {
    if radius <= 0.0 {
        return Vector3::zeros();
    }
    loop {
        let d = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
        if let Some(u) = d.try_normalize(1e-9) {
            let r: f64 = rng.random_range(0.0..1.0);
            return u * (radius * r.cbrt());
        }
    }
}

/// Draws initial conditions for a scenario.
#[derive(Clone, Debug)]
pub struct Sampler {
    radii: SamplerRadii,
    desired0: Matrix3<f64>,
    position0: Vector3<f64>,
    velocity0: Vector3<f64>,
}

impl Sampler {
    /// Errors: the desired attitude at `t = 0` is undefined for the scenario's reference.
    pub fn new(scenario: &Scenario, radii: SamplerRadii) -> Result<Self> {
        let r = scenario.trajectory::<f64>().sample(0.0);
        let u = Vector3::z() * scenario.vehicle.gravity_m_s2 + r.acceleration;
        let d = desired_attitude(
            &u,
            &r.jerk,
            &r.snap,
            &r.heading,
            &r.heading_rate,
            &r.heading_acceleration,
        )
        .map_err(|e| anyhow!("R_d(0) undefined for this reference: {e:?}"))?;
        Ok(Self {
            radii,
            desired0: d.rotation,
            position0: r.position,
            velocity0: r.velocity,
        })
    }

    /// `R_d(0)` (desired body to inertial).
    pub fn desired_rotation0(&self) -> Matrix3<f64> {
        self.desired0
    }

    /// The initial condition of run `index` drawn from `seed` (= [`run_seed`] of the campaign).
    /// The first [`HALF_TURN_AXES`]`.len()` indices are the 180° starts when `half_turns` is set.
    pub fn sample(&self, index: u64, seed: u64, half_turns: bool) -> InitialCondition {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let position = self.position0 + uniform_in_ball(&mut rng, self.radii.position_m);
        let half_turn = HALF_TURN_AXES.get(index as usize).filter(|_| half_turns);
        let (kind, attitude, velocity, angular_velocity) = match half_turn {
            Some(&(name, axis)) => {
                let axis = Unit::new_normalize(Vector3::from(axis));
                let rd = Rotation3::from_matrix_unchecked(self.desired0);
                let r = rd * Rotation3::from_axis_angle(&axis, std::f64::consts::PI);
                (
                    StartKind::HalfTurn(name),
                    UnitQuaternion::from_rotation_matrix(&r),
                    self.velocity0,
                    Vector3::zeros(),
                )
            }
            None => (
                StartKind::Haar,
                haar_quaternion(&mut rng),
                self.velocity0 + uniform_in_ball(&mut rng, self.radii.velocity_m_s),
                uniform_in_ball(&mut rng, self.radii.angular_velocity_rad_s),
            ),
        };
        let error = self.desired0.transpose() * attitude.to_rotation_matrix().into_inner();
        InitialCondition {
            kind,
            state: RigidBodyState {
                position,
                velocity,
                attitude,
                angular_velocity,
            },
            attitude_error_deg: crate::model::so3::rotation_angle(&error).to_degrees(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_turn_starts_are_exactly_180_degrees() {
        let s = Sampler::new(&Scenario::paper(), SamplerRadii::default()).unwrap();
        for i in 0..HALF_TURN_AXES.len() as u64 {
            let ic = s.sample(i, run_seed(1, i), true);
            assert!(matches!(ic.kind, StartKind::HalfTurn(_)));
            assert!(
                (ic.attitude_error_deg - 180.0).abs() < 1e-6,
                "{}",
                ic.attitude_error_deg
            );
        }
        let ic = s.sample(7, run_seed(1, 7), true);
        assert_eq!(ic.kind, StartKind::Haar);
    }

    #[test]
    fn runs_are_reproducible_and_distinct() {
        let s = Sampler::new(&Scenario::paper(), SamplerRadii::default()).unwrap();
        let a = s.sample(20, run_seed(5, 20), true);
        let b = s.sample(20, run_seed(5, 20), true);
        let c = s.sample(21, run_seed(5, 21), true);
        assert_eq!(a.state, b.state);
        assert_ne!(a.state.attitude, c.state.attitude);
        assert_ne!(run_seed(5, 20), run_seed(6, 20));
    }
}
