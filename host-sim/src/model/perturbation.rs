//! Perturbations of a closed-loop run: measurement noise, model errors, disturbances, motor lag.
//!
//! The scenario table `[perturbations]` ([`PerturbationConfig`]) describes them; every key is
//! optional and defaults to "no perturbation", so existing scenario files stay valid and the
//! default run is the noise-free, exact-model run of [`crate::fly::sim`]. A [`Perturber`] realises
//! them for one run from a seed (ChaCha8), so a run is reproducible from `(config, seed)` alone,
//! whatever thread runs it.
//!
//! Model (all Gaussian draws are independent, zero-mean, per component):
//! - measurement noise on the state the controller sees: `p + n_p`, `v + n_v`,
//!   `R exp([n_R]ₓ)` (body-frame rotation-vector noise), `ω + n_ω` (gyro);
//! - model errors: the plant's mass and inertia diagonal are scaled by `1 + e` with `e` drawn
//!   uniformly in `±max_fraction` once per run (each inertia axis independently); the controller
//!   keeps the nominal values;
//! - disturbances on the plant: constant force (inertial) and torque (body), a constant force
//!   drawn once per run (direction uniform on the sphere, magnitude uniform in `[0, max]`), plus
//!   gusts, each a first-order Gauss–Markov process `ẋ = −x/τ_g + w` with stationary standard deviation `σ`,
//!   sampled exactly at the controller period and held in between;
//! - first-order motor lag on thrust and torque, `ȧ = (c − a)/τ_m`, integrated exactly at every
//!   RK4 substep (the command `c` is held over the controller period), on the ideal plant; on
//!   the rotor plant (`simulation.plant = "rotors"`) `motor_time_constant_s > 0` replaces the
//!   vehicle's own motor time constant of the rotor speeds instead
//!   ([`crate::fly::closed_loop::PlantModel::of`]), so a "doubled lag" run sets it to `2 τ_m`.

use nalgebra::{UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::model::plant::{PlantInput, RigidBody, RigidBodyState};

/// `[perturbations]`: every key optional, zero (off) by default. Units in the key names.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct PerturbationConfig {
    /// Standard deviation of the position measurement noise \[m\], per inertial axis.
    pub position_noise_std_m: f64,
    /// Standard deviation of the velocity measurement noise [m/s], per inertial axis.
    pub velocity_noise_std_m_s: f64,
    /// Standard deviation of the attitude measurement noise \[rad\], per body axis of a
    /// rotation-vector perturbation `R exp([n]ₓ)`.
    pub attitude_noise_std_rad: f64,
    /// Standard deviation of the gyro noise [rad/s], per body axis.
    pub gyro_noise_std_rad_s: f64,
    /// The plant's mass is `(1 + e) m` with `e` uniform in `±mass_error_max_fraction`.
    pub mass_error_max_fraction: f64,
    /// A fixed plant mass error `e₀ ∈ (−1, 1)`, added to the drawn one: the plant's mass is
    /// `(1 + e₀ + e) m` (e.g. `0.2` for a vehicle 20 % heavier than the controller assumes).
    #[serde(skip_serializing_if = "is_zero")]
    pub mass_error_fraction: f64,
    /// Each plant inertia axis is `(1 + e_i) J_ii`, `e_i` uniform in `±inertia_error_max_fraction`.
    pub inertia_error_max_fraction: f64,
    /// Constant force disturbance \[N\], inertial.
    pub force_disturbance_N: [f64; 3],
    /// Constant torque disturbance [N m], body.
    pub torque_disturbance_Nm: [f64; 3],
    /// Largest magnitude \[N\] of a constant force (inertial) drawn once per run: direction
    /// uniform on the unit sphere, magnitude uniform in `[0, force_disturbance_max_N]`; added to
    /// `force_disturbance_N`.
    pub force_disturbance_max_N: f64,
    /// Stationary standard deviation of the gust force \[N\], per inertial axis.
    pub gust_force_std_N: f64,
    /// Stationary standard deviation of the gust torque [N m], per body axis.
    pub gust_torque_std_Nm: f64,
    /// Correlation time `τ_g` of the gusts \[s\] (used when a gust std is > 0).
    pub gust_time_constant_s: f64,
    /// Motor time constant `τ_m` \[s\]: on the ideal plant, of a first-order lag on thrust and
    /// torque (0 = no lag); on the rotor plant, when > 0, it replaces the vehicle's time
    /// constant of the rotor speeds (0 = the vehicle's own).
    pub motor_time_constant_s: f64,
}

impl PerturbationConfig {
    /// True when nothing perturbs the run: no noise, exact model, no disturbance, no lag. Only
    /// such runs (without clipping) are covered by the paper's theorems as stated.
    pub fn is_nominal(&self) -> bool {
        *self == Self::default()
    }

    /// True when the plant departs from the model the theorems assume (model errors,
    /// disturbances, motor lag). Measurement noise alone does not count: the a-priori bounds of
    /// Theorems 1–2 hold for any measured state, since they come from the saturations.
    pub fn violates_model(&self) -> bool {
        let zero = Self::default();
        self.mass_error_max_fraction != 0.0
            || self.mass_error_fraction != 0.0
            || self.inertia_error_max_fraction != 0.0
            || self.force_disturbance_N != zero.force_disturbance_N
            || self.torque_disturbance_Nm != zero.torque_disturbance_Nm
            || self.force_disturbance_max_N != 0.0
            || self.gust_force_std_N != 0.0
            || self.gust_torque_std_Nm != 0.0
            || self.motor_time_constant_s != 0.0
    }

    /// Checks every value is finite and `≥ 0` (fractions `< 1`; gust time constant `> 0` when a
    /// gust is on). Errors: `"perturbations.<key>: <reason>"`.
    pub fn validate(&self) -> Result<(), String> {
        let scalars = [
            ("position_noise_std_m", self.position_noise_std_m),
            ("velocity_noise_std_m_s", self.velocity_noise_std_m_s),
            ("attitude_noise_std_rad", self.attitude_noise_std_rad),
            ("gyro_noise_std_rad_s", self.gyro_noise_std_rad_s),
            ("mass_error_max_fraction", self.mass_error_max_fraction),
            (
                "inertia_error_max_fraction",
                self.inertia_error_max_fraction,
            ),
            ("force_disturbance_max_N", self.force_disturbance_max_N),
            ("gust_force_std_N", self.gust_force_std_N),
            ("gust_torque_std_Nm", self.gust_torque_std_Nm),
            ("gust_time_constant_s", self.gust_time_constant_s),
            ("motor_time_constant_s", self.motor_time_constant_s),
        ];
        for (key, v) in scalars {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "perturbations.{key}: must be finite and >= 0, got {v}"
                ));
            }
        }
        for (key, v) in [
            ("mass_error_max_fraction", self.mass_error_max_fraction),
            (
                "inertia_error_max_fraction",
                self.inertia_error_max_fraction,
            ),
        ] {
            if v >= 1.0 {
                return Err(format!("perturbations.{key}: must be < 1, got {v}"));
            }
        }
        let fixed = self.mass_error_fraction;
        if !(fixed.is_finite() && fixed.abs() < 1.0) {
            return Err(format!(
                "perturbations.mass_error_fraction: must be finite and in (-1, 1), got {fixed}"
            ));
        }
        if fixed - self.mass_error_max_fraction <= -1.0 {
            return Err(format!(
                "perturbations.mass_error_fraction - mass_error_max_fraction must be > -1 (a \
                 positive plant mass), got {fixed} - {}",
                self.mass_error_max_fraction
            ));
        }
        let gusty = self.gust_force_std_N > 0.0 || self.gust_torque_std_Nm > 0.0;
        if gusty && self.gust_time_constant_s <= 0.0 {
            return Err(format!(
                "perturbations.gust_time_constant_s: must be > 0 when a gust is on, got {}",
                self.gust_time_constant_s
            ));
        }
        for (key, a) in [
            ("force_disturbance_N", self.force_disturbance_N),
            ("torque_disturbance_Nm", self.torque_disturbance_Nm),
        ] {
            if !a.iter().all(|x| x.is_finite()) {
                return Err(format!("perturbations.{key}: must be finite, got {a:?}"));
            }
        }
        Ok(())
    }
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// A vector of independent standard normal draws.
fn gaussian3(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal))
}

/// One run's realisation of a [`PerturbationConfig`]: the random stream, the drawn model errors,
/// the gust states and the lagged actuator state.
#[derive(Clone, Debug)]
pub struct Perturber {
    config: PerturbationConfig,
    rng: ChaCha8Rng,
    gust_force: Vector3<f64>,
    gust_torque: Vector3<f64>,
    actuator: Option<(f64, Vector3<f64>)>,
    mass_scale: f64,
    inertia_scale: Vector3<f64>,
    drawn_force: Vector3<f64>,
}

impl Perturber {
    /// Draws the run's model errors and initial gust states from `seed`.
    ///
    /// The draws happen in a fixed order (mass, inertia, gusts, the constant force), and a draw
    /// is skipped when its setting is zero, so a nominal config consumes nothing (and a config
    /// without the drawn force draws what it drew before that key existed).
    pub fn new(config: &PerturbationConfig, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let uniform = |max: f64, rng: &mut ChaCha8Rng| {
            if max > 0.0 {
                rng.random_range(-max..=max)
            } else {
                0.0
            }
        };
        // 1.0 + 0.0 is exactly 1.0: without a fixed error the scale is the drawn one, bit for bit.
        let mass_scale =
            1.0 + config.mass_error_fraction + uniform(config.mass_error_max_fraction, &mut rng);
        let inertia_scale =
            Vector3::from_fn(|_, _| 1.0 + uniform(config.inertia_error_max_fraction, &mut rng));
        // Start the gusts in their stationary distribution, so every second of the run is alike.
        let gust_force = if config.gust_force_std_N > 0.0 {
            gaussian3(&mut rng) * config.gust_force_std_N
        } else {
            Vector3::zeros()
        };
        let gust_torque = if config.gust_torque_std_Nm > 0.0 {
            gaussian3(&mut rng) * config.gust_torque_std_Nm
        } else {
            Vector3::zeros()
        };
        let drawn_force = if config.force_disturbance_max_N > 0.0 {
            // A normalised Gaussian vector is uniform on the sphere.
            let direction = gaussian3(&mut rng)
                .try_normalize(1e-12)
                .unwrap_or(Vector3::z());
            direction * rng.random_range(0.0..=config.force_disturbance_max_N)
        } else {
            Vector3::zeros()
        };
        Self {
            config: config.clone(),
            rng,
            gust_force,
            gust_torque,
            actuator: None,
            mass_scale,
            inertia_scale,
            drawn_force,
        }
    }

    /// The plant with this run's mass and inertia errors applied.
    pub fn plant(&self, nominal: &RigidBody) -> RigidBody {
        RigidBody {
            mass: nominal.mass * self.mass_scale,
            inertia: nominal.inertia.component_mul(&self.inertia_scale),
            gravity: nominal.gravity,
        }
    }

    /// The constant force drawn for this run \[N\], inertial (zero unless
    /// `force_disturbance_max_N > 0`).
    pub fn drawn_force(&self) -> Vector3<f64> {
        self.drawn_force
    }

    /// The drawn mass scale `1 + e` and inertia scales `1 + e_i`.
    pub fn model_scales(&self) -> (f64, Vector3<f64>) {
        (self.mass_scale, self.inertia_scale)
    }

    /// The state the controller measures: `state` with noise added (exactly `state` when every
    /// noise level is zero, and then no random number is consumed).
    pub fn measure(&mut self, state: &RigidBodyState) -> RigidBodyState {
        let c = &self.config;
        let mut noisy = *state;
        if c.position_noise_std_m > 0.0 {
            noisy.position += gaussian3(&mut self.rng) * c.position_noise_std_m;
        }
        if c.velocity_noise_std_m_s > 0.0 {
            noisy.velocity += gaussian3(&mut self.rng) * c.velocity_noise_std_m_s;
        }
        if c.attitude_noise_std_rad > 0.0 {
            let n = gaussian3(&mut self.rng) * c.attitude_noise_std_rad;
            noisy.attitude = state.attitude * UnitQuaternion::from_scaled_axis(n);
        }
        if c.gyro_noise_std_rad_s > 0.0 {
            noisy.angular_velocity += gaussian3(&mut self.rng) * c.gyro_noise_std_rad_s;
        }
        noisy
    }

    /// Adds the disturbances to `input` for the coming controller period `dt` \[s\], advancing
    /// the gusts by one exact Gauss–Markov step.
    pub fn disturb(&mut self, input: &mut PlantInput, dt: f64) {
        let c = &self.config;
        let step = |x: &mut Vector3<f64>, std: f64, rng: &mut ChaCha8Rng| {
            if std > 0.0 {
                // Exact discretisation: x' = a x + σ √(1 − a²) n keeps the stationary σ.
                let a = (-dt / c.gust_time_constant_s).exp();
                *x = *x * a + gaussian3(rng) * (std * (1.0 - a * a).sqrt());
            }
        };
        input.force_disturbance =
            Vector3::from(c.force_disturbance_N) + self.drawn_force + self.gust_force;
        input.torque_disturbance = Vector3::from(c.torque_disturbance_Nm) + self.gust_torque;
        step(&mut self.gust_force, c.gust_force_std_N, &mut self.rng);
        step(&mut self.gust_torque, c.gust_torque_std_Nm, &mut self.rng);
    }

    /// Advances `plant` over `duration` \[s\] (RK4 substeps of at most `max_step` \[s\]) with the
    /// command `input` held; with a motor lag, the applied thrust and torque follow the command
    /// through `ȧ = (c − a)/τ_m`, updated exactly before each substep. Without a lag this is
    /// exactly [`RigidBody::advance`].
    pub fn advance(
        &mut self,
        plant: &RigidBody,
        state: &RigidBodyState,
        input: &PlantInput,
        duration: f64,
        max_step: f64,
    ) -> RigidBodyState {
        let tau = self.config.motor_time_constant_s;
        if tau <= 0.0 {
            return plant.advance(state, input, duration, max_step);
        }
        let n = (duration / max_step).ceil().max(1.0) as usize;
        let h = duration / n as f64;
        let decay = (-h / tau).exp();
        // The motors start at the first command (spun up before the run).
        let (mut thrust, mut torque) = self.actuator.unwrap_or((input.thrust, input.torque));
        let mut s = *state;
        for _ in 0..n {
            thrust = input.thrust + (thrust - input.thrust) * decay;
            torque = input.torque + (torque - input.torque) * decay;
            let applied = PlantInput {
                thrust,
                torque,
                ..*input
            };
            s = plant.rk4_step(&s, &applied, h);
        }
        self.actuator = Some((thrust, torque));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nominal_config_is_identity_and_draws_nothing() {
        let c = PerturbationConfig::default();
        assert!(c.is_nominal() && !c.violates_model());
        let mut p = Perturber::new(&c, 7);
        let s = RigidBodyState {
            position: Vector3::new(1.0, 2.0, 3.0),
            velocity: Vector3::new(0.1, 0.2, 0.3),
            attitude: UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
            angular_velocity: Vector3::new(0.5, 0.6, 0.7),
        };
        assert_eq!(p.measure(&s), s);
        assert_eq!(p.model_scales(), (1.0, Vector3::repeat(1.0)));
    }

    #[test]
    fn same_seed_same_noise_different_seed_different_noise() {
        let c = PerturbationConfig {
            position_noise_std_m: 0.1,
            attitude_noise_std_rad: 0.01,
            ..Default::default()
        };
        let s = RigidBodyState {
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            attitude: UnitQuaternion::identity(),
            angular_velocity: Vector3::zeros(),
        };
        let a = Perturber::new(&c, 1).measure(&s);
        let b = Perturber::new(&c, 1).measure(&s);
        let d = Perturber::new(&c, 2).measure(&s);
        assert_eq!(a, b);
        assert_ne!(a.position, d.position);
    }

    #[test]
    fn drawn_force_is_bounded_isotropic_applied_and_leaves_earlier_draws_alone() {
        let base = PerturbationConfig {
            mass_error_max_fraction: 0.2,
            inertia_error_max_fraction: 0.2,
            ..Default::default()
        };
        let c = PerturbationConfig {
            force_disturbance_max_N: 0.45,
            ..base.clone()
        };
        assert!(c.violates_model() && c.validate().is_ok());
        let n = 20_000;
        let mut mean_direction = Vector3::zeros();
        let mut mean_magnitude = 0.0;
        for seed in 0..n {
            let p = Perturber::new(&c, seed);
            // The model errors are drawn first: the same with and without the force.
            assert_eq!(p.model_scales(), Perturber::new(&base, seed).model_scales());
            let f = p.drawn_force();
            assert!(f.norm() <= 0.45);
            mean_direction += f.normalize() / n as f64;
            mean_magnitude += f.norm() / n as f64;
            let mut q = p.clone();
            let mut input = PlantInput::default();
            q.disturb(&mut input, 0.01);
            assert_eq!(input.force_disturbance, f);
        }
        // Uniform on the sphere: each component of the mean direction has standard deviation
        // sqrt(1/3 / n) = 0.0041; uniform magnitude: mean 0.225 N, standard error 0.0009 N.
        assert!(mean_direction.amax() < 5.0 * (1.0 / 3.0 / n as f64).sqrt());
        assert!((mean_magnitude - 0.225).abs() < 5.0 * 0.45 / (12.0 * n as f64).sqrt());
        let bad = PerturbationConfig {
            force_disturbance_max_N: f64::NAN,
            ..Default::default()
        };
        assert!(bad
            .validate()
            .is_err_and(|e| e.contains("force_disturbance_max_N")));
    }

    #[test]
    fn gust_keeps_its_stationary_standard_deviation() {
        let c = PerturbationConfig {
            gust_force_std_N: 0.3,
            gust_time_constant_s: 0.5,
            ..Default::default()
        };
        let mut p = Perturber::new(&c, 3);
        let n = 200_000;
        let mut sum2 = 0.0;
        for _ in 0..n {
            let mut input = PlantInput::default();
            p.disturb(&mut input, 0.01);
            sum2 += input.force_disturbance.x.powi(2);
        }
        let std = (sum2 / n as f64).sqrt();
        // Correlated samples: ~n dt / (2 τ) = 2000 independent ones, so ~1.6 % relative error.
        assert!((std - 0.3).abs() < 0.3 * 0.06, "std {std}");
    }

    /// The fixed mass error scales the plant exactly, adds to the drawn one, and is refused
    /// outside (−1, 1).
    #[test]
    fn fixed_mass_error_scales_the_plant() {
        let c = PerturbationConfig {
            mass_error_fraction: 0.2,
            ..Default::default()
        };
        assert!(c.violates_model() && c.validate().is_ok());
        assert_eq!(Perturber::new(&c, 7).model_scales().0, 1.2);
        let both = PerturbationConfig {
            mass_error_max_fraction: 0.1,
            ..c.clone()
        };
        let drawn = Perturber::new(
            &PerturbationConfig {
                mass_error_max_fraction: 0.1,
                ..Default::default()
            },
            7,
        )
        .model_scales()
        .0;
        // Recovering the draw as `drawn − 1` rounds once (≤ 1 ulp of 1.2).
        let sum = Perturber::new(&both, 7).model_scales().0;
        assert!(
            (sum - (1.2 + (drawn - 1.0))).abs() <= 2.0 * f64::EPSILON,
            "{sum}"
        );
        for bad in [1.0, -1.0, f64::NAN] {
            let c = PerturbationConfig {
                mass_error_fraction: bad,
                ..Default::default()
            };
            assert!(c.validate().unwrap_err().contains("mass_error_fraction"));
        }
    }

    #[test]
    fn invalid_values_are_named() {
        let c = PerturbationConfig {
            gust_torque_std_Nm: 0.1,
            ..Default::default()
        };
        let e = c.validate().unwrap_err();
        assert!(e.contains("gust_time_constant_s"), "{e}");
        let c = PerturbationConfig {
            mass_error_max_fraction: -0.1,
            ..Default::default()
        };
        assert!(c
            .validate()
            .unwrap_err()
            .contains("mass_error_max_fraction"));
    }
}
