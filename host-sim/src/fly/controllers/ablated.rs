//! The paper's law with one design choice removed, for the ablations.
//!
//! This recomposes `controller_core::Controller::step` from the core's public building blocks
//! (position law, desired attitude, path lifting, torque law) so that one block can be swapped:
//! - [`Lifting::Memoryless`]: the MRP of the quaternion of `R̃` with the sign `q₀ ≥ 0`
//!   (principal MRP, no memory, no hysteresis) instead of the hybrid path lifting of the
//!   Appendix. Near 180° this switches between `ϑ` and its shadow whenever noise moves `q₀`
//!   across zero.
//! - `filters: false`: the position law without the two first-order filters,
//!   `u = ubar_p + g e₃ + p̈_d` with `ubar_p = −σ(s)`, `s = k_p p̃ + k_v ṽ`, `σ = M_p tanh(·/M_p)`
//!   componentwise. Its `u̇, ü` (needed for `ω_d, ω̇_d`) are taken along the ideal closed loop
//!   `p̃̈ = ubar_p` (the same idealisation the filtered law's `u̇, ü` rest on), in closed form:
//!   `ṡ = k_p ṽ + k_v ubar_p`, `u̇bar = −σ'(s) ṡ`, `s̈ = k_p ubar_p + k_v u̇bar`,
//!   `üabar = −σ''(s) ṡ² − σ'(s) s̈` (componentwise), with `σ'(s) = 1 − tanh²(s/M)` and
//!   `σ''(s) = −(2/M) tanh(s/M) (1 − tanh²(s/M))`; then `u̇ = u̇bar + p_d⁽³⁾`, `ü = übar + p_d⁽⁴⁾`.
//!   The a-priori bounds of Lemma 1 / Theorem 2 do not cover this law: its `ω_d, ω̇_d` are
//!   whatever the unfiltered feedback makes them.
//!
//! With `Ablation::NONE` the composition is bit-identical to `controller_core::Controller`
//! (a test pins it), so the copy cannot drift from the core.

use anyhow::{anyhow, bail, Result};
use controller_core::desired_attitude::desired_attitude;
use controller_core::mrp::{
    mrp_from_quaternion, quaternion_from_rotation, rotation_from_quaternion,
};
use controller_core::path_lifting::PathLifting;
use controller_core::position::FilterState;
use controller_core::saturation::tanh_saturation;
use controller_core::scalar::{lit, to_f64, Scalar};
use controller_core::{Controller, Gains, ReferenceTrajectory, ThrustMode, Trajectory, Vehicle};
use nalgebra::{Quaternion, Vector3};

use super::measure;
use super::paper::back3;
use super::{Command, FlightController, SwitchCounts};
use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// How the attitude error is lifted to an MRP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lifting {
    /// The hybrid path lifting of the Appendix (memory quaternion, hysteresis `δ`).
    Hybrid,
    /// Memoryless: `q₀ ≥ 0`, principal MRP.
    Memoryless,
}

/// Which design choices are kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ablation {
    /// The lifting.
    pub lifting: Lifting,
    /// True: the filtered outer loop of Section IV; false: `u = ubar_p + g e₃ + p̈_d`.
    pub filters: bool,
}

impl Ablation {
    /// Nothing removed: the paper's law.
    pub const NONE: Self = Self {
        lifting: Lifting::Hybrid,
        filters: true,
    };
}

/// The memoryless lifting: principal MRP of the `q₀ ≥ 0` quaternion; counts hemisphere changes
/// of that choice between consecutive samples (each one is a jump of `ϑ` to near its shadow).
#[derive(Clone, Copy, Debug)]
pub struct MemorylessLifting<T: Scalar> {
    previous: Option<Quaternion<T>>,
    switches: u32,
}

impl<T: Scalar> Default for MemorylessLifting<T> {
    fn default() -> Self {
        Self {
            previous: None,
            switches: 0,
        }
    }
}

impl<T: Scalar> MemorylessLifting<T> {
    /// Lifts `R̃` (3×3 rotation) to the principal MRP, `|ϑ| ≤ 1`.
    pub fn lift(&mut self, error_rotation: &nalgebra::Matrix3<T>) -> Vector3<T> {
        let mut q = quaternion_from_rotation(error_rotation);
        if q.w < T::zero() {
            q = -q;
        }
        if self.previous.is_some_and(|p| p.dot(&q) < T::zero()) {
            self.switches += 1;
        }
        self.previous = Some(q);
        // q₀ ≥ 0 so 1 + q₀ ≥ 1: φ is always defined.
        mrp_from_quaternion(&q).unwrap_or_else(Vector3::zeros)
    }

    /// Hemisphere changes so far.
    pub fn switches(&self) -> u32 {
        self.switches
    }
}

#[derive(Clone, Copy, Debug)]
enum LiftingState<T: Scalar> {
    Hybrid(PathLifting<T>),
    Memoryless(MemorylessLifting<T>),
}

/// The paper's law with the chosen [`Ablation`].
#[derive(Clone, Debug)]
pub struct AblatedLaw<T: Scalar> {
    vehicle: Vehicle<T>,
    gains: Gains<T>,
    filter: FilterState<T>,
    lifting: LiftingState<T>,
    trajectory: ReferenceTrajectory<T>,
    ablation: Ablation,
    /// The scenario's `[controller] thrust` (the paper's `T = m|u|` by default).
    thrust_mode: ThrustMode<T>,
}

/// The unfiltered position law and its two derivatives along `p̃̈ = ubar_p` (see module docs).
/// Returns `(ubar_p, u, u̇, ü)`, inertial, [m/s²], [m/s²], [m/s³], [m/s⁴].
#[allow(clippy::too_many_arguments)]
pub fn unfiltered_position_law<T: Scalar>(
    kp: T,
    kv: T,
    level: T,
    position_error: &Vector3<T>,
    velocity_error: &Vector3<T>,
    reference: &controller_core::ReferenceSample<T>,
    gravity: T,
) -> (Vector3<T>, Vector3<T>, Vector3<T>, Vector3<T>) {
    let s = position_error * kp + velocity_error * kv;
    let ubar = -tanh_saturation(&s, level);
    let th = s.map(|x| (x / level).tanh());
    let slope = th.map(|t| T::one() - t * t);
    let curvature = th.zip_map(&slope, |t, d| -lit::<T>(2.0) / level * t * d);
    let s_dot = velocity_error * kp + ubar * kv;
    let ubar_dot = -slope.component_mul(&s_dot);
    let s_ddot = ubar * kp + ubar_dot * kv;
    let ubar_ddot =
        -(curvature.component_mul(&s_dot.component_mul(&s_dot)) + slope.component_mul(&s_ddot));
    let u = ubar + Vector3::z() * gravity + reference.acceleration;
    (
        ubar,
        u,
        ubar_dot + reference.jerk,
        ubar_ddot + reference.snap,
    )
}

impl<T: Scalar> AblatedLaw<T> {
    /// Errors: the parameters are refused, exactly as `Controller::new` refuses them.
    pub fn new(scenario: &Scenario, ablation: Ablation) -> Result<Self> {
        let trajectory = scenario.trajectory::<T>();
        let vehicle = scenario.vehicle::<T>();
        let gains = scenario.gains::<T>();
        if gains.velocity_limit.is_some() {
            bail!(
                "gains.velocity_limit: the ablated controllers fly the paper's position feedback \
                 only; remove [gains.velocity_limit] to compare them (docs/velocity-limit.md)"
            );
        }
        if gains.position.saturation_shape != controller_core::PositionSaturation::Componentwise {
            bail!(
                "gains.position_saturation: the ablated controllers fly the paper's componentwise \
                 saturation only; remove position_saturation to compare them \
                 (docs/position-saturation.md)"
            );
        }
        // Same validation as the core (the constructed controller is then dropped).
        let thrust_mode = scenario.thrust_mode::<T>().map_err(|e| anyhow!("{e}"))?;
        Controller::new(vehicle, gains, &trajectory.constants())
            .and_then(|mut c| c.set_thrust_mode(thrust_mode))
            .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?;
        let lifting = match ablation.lifting {
            Lifting::Hybrid => {
                LiftingState::Hybrid(PathLifting::new(gains.hysteresis, gains.reset_threshold))
            }
            Lifting::Memoryless => LiftingState::Memoryless(MemorylessLifting::default()),
        };
        Ok(Self {
            vehicle,
            gains,
            filter: FilterState::zero(),
            lifting,
            trajectory,
            ablation,
            thrust_mode,
        })
    }

    /// One sample in scalar `T`: `(thrust \[N\], torque [N m], the command in f64)`.
    fn step_t(
        &mut self,
        measured: &RigidBodyState,
        t: f64,
        dt: f64,
    ) -> Result<(T, Vector3<T>, Command)> {
        let reference = self.trajectory.sample(lit(t));
        let state = measure::<T>(measured);
        let g = &self.gains;
        let position_error = state.position - reference.position;
        let velocity_error = state.velocity - reference.velocity;
        let (ubar_p, u, u_dot, u_ddot) = if self.ablation.filters {
            let p = g.position.evaluate(
                None,
                &position_error,
                &velocity_error,
                &self.filter,
                &reference.acceleration,
                &reference.jerk,
                &reference.snap,
                self.vehicle.gravity,
            );
            (p.ubar_p, p.u, p.u_dot, p.u_ddot)
        } else {
            unfiltered_position_law(
                g.position.kp,
                g.position.kv,
                g.position.saturation,
                &position_error,
                &velocity_error,
                &reference,
                self.vehicle.gravity,
            )
        };
        let desired = desired_attitude(
            &u,
            &u_dot,
            &u_ddot,
            &reference.heading,
            &reference.heading_rate,
            &reference.heading_acceleration,
        )
        .map_err(|e| anyhow!("desired attitude undefined at t = {t:.3} s: {e:?}"))?;
        let rotation = rotation_from_quaternion(state.attitude.quaternion());
        let error_rotation = desired.rotation.transpose() * rotation;
        let (mrp, switches) = match &mut self.lifting {
            LiftingState::Hybrid(l) => {
                let out = l.lift(&error_rotation);
                let c = l.counters();
                (
                    out.mrp,
                    SwitchCounts {
                        switches: c.m_flips,
                        resets: c.q_hat_resets,
                    },
                )
            }
            LiftingState::Memoryless(l) => {
                let mrp = l.lift(&error_rotation);
                (
                    mrp,
                    SwitchCounts {
                        switches: l.switches(),
                        resets: 0,
                    },
                )
            }
        };
        let torque = g.attitude_torque(
            &mrp,
            &state.angular_velocity,
            &error_rotation,
            &desired.angular_velocity,
            &desired.angular_acceleration,
            &self.vehicle.inertia,
        );
        let body_z = rotation.column(2).into_owned();
        let thrust = self.thrust_mode.thrust(self.vehicle.mass, &u, &body_z);
        if self.ablation.filters {
            self.filter = g.position.propagate(&self.filter, &ubar_p, lit(dt));
        }
        if !(thrust.is_finite() && torque.torque.iter().all(|x| x.is_finite())) {
            bail!("non-finite command at t = {t:.3} s");
        }
        let command = Command {
            thrust: to_f64(thrust),
            torque: back3(&torque.torque),
            desired_rotation: desired.rotation.map(to_f64),
            desired_angular_velocity: back3(&desired.angular_velocity),
            desired_angular_acceleration: back3(&desired.angular_acceleration),
            switches_total: switches,
        };
        Ok((thrust, torque.torque, command))
    }
}

impl<T: Scalar> FlightController for AblatedLaw<T> {
    fn name(&self) -> &str {
        match (self.ablation.lifting, self.ablation.filters) {
            (Lifting::Hybrid, true) => "paper (recomposed)",
            (Lifting::Memoryless, true) => "paper_memoryless",
            (Lifting::Hybrid, false) => "paper_no_filter",
            (Lifting::Memoryless, false) => "paper_memoryless_no_filter",
        }
    }

    fn step(&mut self, measured: &RigidBodyState, t: f64, dt: f64) -> Result<Command> {
        self.step_t(measured, t, dt).map(|(_, _, c)| c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    /// The non-ablated recomposition gives bit-identical thrust and torque (in the controller's
    /// own scalar) to `controller_core::Controller` along a closed-loop run from 179°.
    fn bit_identical<T: Scalar>() {
        let scenario = Scenario::paper();
        let trajectory = scenario.trajectory::<T>();
        let mut core = Controller::new(
            scenario.vehicle::<T>(),
            scenario.gains::<T>(),
            &trajectory.constants(),
        )
        .unwrap();
        let mut ours = AblatedLaw::<T>::new(&scenario, Ablation::NONE).unwrap();
        let plant = scenario.plant();
        let mut state = scenario.initial_state();
        let dt = 0.01;
        for k in 0..800 {
            let t = k as f64 * dt;
            let out = core
                .step(&measure::<T>(&state), &trajectory.sample(lit(t)), lit(dt))
                .unwrap();
            let (thrust, torque, cmd) = ours.step_t(&state, t, dt).unwrap();
            assert_eq!(thrust, out.thrust, "thrust at k = {k}");
            assert_eq!(torque, out.torque, "torque at k = {k}");
            assert_eq!(
                cmd.switches_total.switches,
                out.diagnostics.jumps_total.m_flips
            );
            let input = crate::model::plant::PlantInput {
                thrust: cmd.thrust,
                torque: cmd.torque,
                ..Default::default()
            };
            state = plant.advance(&state, &input, dt, 1e-3);
        }
    }

    #[test]
    fn recomposition_is_bit_identical_to_core_f64() {
        bit_identical::<f64>();
    }

    #[test]
    fn recomposition_is_bit_identical_to_core_f32() {
        bit_identical::<f32>();
    }

    /// The closed-form u̇, ü of the unfiltered law match central differences of u along the
    /// ideal closed loop p̃̈ = ubar_p (fixed reference), integrated finely.
    #[test]
    fn unfiltered_derivatives_match_finite_differences() {
        let reference = controller_core::ReferenceSample::hold(Vector3::zeros(), 0.0);
        let (kp, kv, m, g) = (9.0, 6.0, 2.0, 9.81);
        let law = |p: &Vector3<f64>, v: &Vector3<f64>| {
            unfiltered_position_law(kp, kv, m, p, v, &reference, g)
        };
        // Integrate p̃̈ = ubar_p with RK4, h small, and sample u at three consecutive points.
        let h = 1e-4;
        let f = |x: &(Vector3<f64>, Vector3<f64>)| (x.1, law(&x.0, &x.1).0);
        let mut x = (Vector3::new(0.3, -0.2, 0.1), Vector3::new(-0.4, 0.5, 0.2));
        let mut us = Vec::new();
        for _ in 0..3 {
            us.push(law(&x.0, &x.1));
            let k1 = f(&x);
            let k2 = f(&(x.0 + k1.0 * h / 2.0, x.1 + k1.1 * h / 2.0));
            let k3 = f(&(x.0 + k2.0 * h / 2.0, x.1 + k2.1 * h / 2.0));
            let k4 = f(&(x.0 + k3.0 * h, x.1 + k3.1 * h));
            x.0 += (k1.0 + k2.0 * 2.0 + k3.0 * 2.0 + k4.0) * h / 6.0;
            x.1 += (k1.1 + k2.1 * 2.0 + k3.1 * 2.0 + k4.1) * h / 6.0;
        }
        let fd1 = (us[2].1 - us[0].1) / (2.0 * h);
        let fd2 = (us[2].1 - us[1].1 * 2.0 + us[0].1) / (h * h);
        assert!(
            (fd1 - us[1].2).norm() < 1e-6 * us[1].2.norm().max(1.0),
            "{fd1} vs {}",
            us[1].2
        );
        assert!(
            (fd2 - us[1].3).norm() < 1e-3 * us[1].3.norm().max(1.0),
            "{fd2} vs {}",
            us[1].3
        );
    }

    #[test]
    fn memoryless_lifting_switches_with_noise_at_180_degrees() {
        let mut l = MemorylessLifting::<f64>::default();
        for k in 0..100 {
            let noise = 0.5f64.to_radians() * ((k as f64) * 1.7).sin();
            let r = UnitQuaternion::from_scaled_axis(Vector3::z() * (std::f64::consts::PI + noise));
            let mrp = l.lift(r.to_rotation_matrix().matrix());
            assert!(mrp.norm() <= 1.0 + 1e-12);
        }
        // sin(1.7 k) changes sign about every 1.85 samples.
        assert!(l.switches() > 40, "{}", l.switches());
    }
}
