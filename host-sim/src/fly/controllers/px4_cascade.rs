//! Baseline: a PX4-style cascade, after the structure of PX4's `mc_pos_control`
//! (PositionControl: position P → velocity PID → acceleration → tilt-limited thrust vector) and
//! `mc_att_control` / `mc_rate_control` (AttitudeControl: quaternion P with the canonical
//! `w ≥ 0` error; rate PID). Written for this repository (z up, SI), not ported.
//!
//! Per sample, with `(p_d, ṗ_d, p̈_d, ψ_d)` from the reference:
//! 1. `v_sp = ṗ_d + K_pos (p_d − p)`, horizontal norm `≤ v_xy,max`, vertical in
//!    `[−v_down,max, v_up,max]`;
//! 2. `a_sp = p̈_d + K_vp e_v + K_vi ∫e_v − K_vd â`, `e_v = v_sp − v`, where `â` is the
//!    low-passed backward difference of the measured velocity; the integral is clamped;
//! 3. thrust direction `b₃ = (a_x, a_y, g)/|·|` tilted at most `θ_max` from `e₃`;
//!    collective `T = m (a_z + g)/b₃·e₃` clipped to `[T_min, T_max]` (PX4 keeps the vertical
//!    acceleration and gives up horizontal authority);
//! 4. attitude setpoint from `b₃` and `ψ_d` (`b₁ = normalize((−sin ψ_d, cos ψ_d, 0) × b₃)`);
//! 5. `q_e = q⁻¹ ⊗ q_sp`, negated when `w < 0` (memoryless canonical sign: at 180° it switches
//!    with noise), `ω_sp = 2 K_att ⊙ vec(q_e) + ψ̇_d Rᵀe₃`, clipped per axis to the rate limits;
//! 6. `τ = J ⊙ (K_rp e_ω + K_ri ∫e_ω − K_rd ω̂̇)` with `ω̂̇` the low-passed backward difference of
//!    the gyro, clipped to `±τ_max` (PX4's mixer saturates the same way).
//!
//! Gains ([`Px4Gains::defaults`]): PX4's default multicopter parameters where their units are
//! physical (`MPC_XY_P = 0.95`, `MPC_Z_P = 1.0`, `MPC_XY_VEL_P/I/D_ACC = 1.8/0.4/0.2`,
//! `MPC_Z_VEL_P/I/D_ACC = 4/2/0`, `MPC_TILTMAX_AIR = 45°`, `MPC_XY_VEL_MAX = 12 m/s`,
//! `MPC_Z_VEL_MAX_UP/DN = 3/1.5 m/s`, `MPC_THR_MIN = 0.12`, `MC_ROLL_P = MC_PITCH_P = 6.5`,
//! `MC_YAW_P = 2.8`, `MC_ROLLRATE_MAX = MC_PITCHRATE_MAX = 220°/s`, `MC_YAWRATE_MAX = 200°/s`).
//! PX4's rate gains are in normalised actuator units, which depend on the airframe; here they
//! are per unit inertia, chosen for a 100 Hz loop on this vehicle: `K_rp = (20, 20, 10) s⁻¹`,
//! `K_ri = (10, 10, 5) s⁻²`, `K_rd = (0.05, 0.05, 0)`.

use anyhow::{bail, Result};
use controller_core::{ReferenceTrajectory, Trajectory};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::{Command, FlightController, SwitchCounts};
use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// Gains and limits of the cascade (units per field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Px4Gains {
    /// Position P `(xy, xy, z)` [1/s].
    pub position_p: Vector3<f64>,
    /// Velocity P [1/s].
    pub velocity_p: Vector3<f64>,
    /// Velocity I [1/s²].
    pub velocity_i: Vector3<f64>,
    /// Velocity D (dimensionless).
    pub velocity_d: Vector3<f64>,
    /// Largest `|K_vi ∫e_v|` per axis [m/s²].
    pub velocity_integral_limit_m_s2: f64,
    /// Horizontal speed limit [m/s].
    pub max_speed_xy_m_s: f64,
    /// Climb rate limit [m/s].
    pub max_speed_up_m_s: f64,
    /// Descent rate limit [m/s].
    pub max_speed_down_m_s: f64,
    /// Tilt limit \[rad\].
    pub max_tilt_rad: f64,
    /// Minimum collective thrust as a fraction of `T_max`.
    pub min_thrust_fraction: f64,
    /// Attitude P per body axis [1/s].
    pub attitude_p: Vector3<f64>,
    /// Body-rate limits [rad/s].
    pub max_rate_rad_s: Vector3<f64>,
    /// Rate P per body axis [1/s] (angular acceleration per rate error).
    pub rate_p: Vector3<f64>,
    /// Rate I [1/s²].
    pub rate_i: Vector3<f64>,
    /// Rate D (dimensionless).
    pub rate_d: Vector3<f64>,
    /// Largest `|J K_ri ∫e_ω|` per axis as a fraction of `τ_max` (PX4's `MC_*R_INT_LIM = 0.3`).
    pub rate_integral_limit_fraction: f64,
    /// Cut-off of the low-pass on the differentiated velocity and gyro \[Hz\].
    pub derivative_cutoff_hz: f64,
}

impl Px4Gains {
    /// PX4's defaults (see the module docs for the parameter names and the rate-loop scaling).
    pub fn defaults() -> Self {
        Self {
            position_p: Vector3::new(0.95, 0.95, 1.0),
            velocity_p: Vector3::new(1.8, 1.8, 4.0),
            velocity_i: Vector3::new(0.4, 0.4, 2.0),
            velocity_d: Vector3::new(0.2, 0.2, 0.0),
            velocity_integral_limit_m_s2: 3.0,
            max_speed_xy_m_s: 12.0,
            max_speed_up_m_s: 3.0,
            max_speed_down_m_s: 1.5,
            max_tilt_rad: 45f64.to_radians(),
            min_thrust_fraction: 0.12,
            attitude_p: Vector3::new(6.5, 6.5, 2.8),
            max_rate_rad_s: Vector3::new(220f64, 220.0, 200.0).map(f64::to_radians),
            rate_p: Vector3::new(20.0, 20.0, 10.0),
            rate_i: Vector3::new(10.0, 10.0, 5.0),
            rate_d: Vector3::new(0.05, 0.05, 0.0),
            rate_integral_limit_fraction: 0.3,
            derivative_cutoff_hz: 20.0,
        }
    }
}

/// A first-order low-pass on a backward difference (the derivative estimate of the D terms).
#[derive(Clone, Copy, Debug, Default)]
struct Differentiator {
    previous: Option<Vector3<f64>>,
    filtered: Vector3<f64>,
}

impl Differentiator {
    fn update(&mut self, x: &Vector3<f64>, dt: f64, cutoff_hz: f64) -> Vector3<f64> {
        if let Some(p) = self.previous {
            let raw = (x - p) / dt;
            let a = 1.0 - (-2.0 * std::f64::consts::PI * cutoff_hz * dt).exp();
            self.filtered += (raw - self.filtered) * a;
        }
        self.previous = Some(*x);
        self.filtered
    }
}

/// The cascade with its integrators, derivative filters and the previous attitude error.
#[derive(Clone, Debug)]
pub struct Px4Cascade {
    gains: Px4Gains,
    mass: f64,
    gravity: f64,
    inertia: Vector3<f64>,
    thrust_max: f64,
    torque_max: Vector3<f64>,
    trajectory: ReferenceTrajectory<f64>,
    velocity_integral: Vector3<f64>,
    rate_integral: Vector3<f64>,
    acceleration: Differentiator,
    angular_acceleration: Differentiator,
    previous_error: Option<UnitQuaternion<f64>>,
    switches: u32,
}

/// `b₃` rotated towards `e₃` so that its angle from `e₃` is at most `max_tilt` \[rad\].
fn limit_tilt(b3: &Vector3<f64>, max_tilt: f64) -> Vector3<f64> {
    let tilt = b3.z.clamp(-1.0, 1.0).acos();
    if tilt <= max_tilt {
        return *b3;
    }
    let horizontal = Vector3::new(b3.x, b3.y, 0.0);
    match horizontal.try_normalize(1e-12) {
        Some(h) => Vector3::z() * max_tilt.cos() + h * max_tilt.sin(),
        None => Vector3::z(),
    }
}

impl Px4Cascade {
    /// The cascade for the scenario's (nominal) vehicle, limits and trajectory.
    pub fn new(scenario: &Scenario, gains: Px4Gains) -> Self {
        Self {
            gains,
            mass: scenario.vehicle.mass_kg,
            gravity: scenario.vehicle.gravity_m_s2,
            inertia: Vector3::from(scenario.vehicle.inertia_kg_m2),
            thrust_max: scenario.limits.thrust_max_N,
            torque_max: Vector3::from(scenario.limits.torque_max_Nm),
            trajectory: scenario.trajectory::<f64>(),
            velocity_integral: Vector3::zeros(),
            rate_integral: Vector3::zeros(),
            acceleration: Differentiator::default(),
            angular_acceleration: Differentiator::default(),
            previous_error: None,
            switches: 0,
        }
    }
}

impl FlightController for Px4Cascade {
    fn name(&self) -> &str {
        "px4"
    }

    fn step(&mut self, measured: &RigidBodyState, t: f64, dt: f64) -> Result<Command> {
        let k = self.gains;
        let r = self.trajectory.sample(t);
        // 1. Position P with speed limits.
        let mut v_sp = r.velocity
            + k.position_p
                .component_mul(&(r.position - measured.position));
        let xy = v_sp.xy().norm();
        if xy > k.max_speed_xy_m_s {
            let s = k.max_speed_xy_m_s / xy;
            v_sp.x *= s;
            v_sp.y *= s;
        }
        v_sp.z = v_sp.z.clamp(-k.max_speed_down_m_s, k.max_speed_up_m_s);
        // 2. Velocity PID.
        let e_v = v_sp - measured.velocity;
        let limit = k.velocity_integral_limit_m_s2;
        self.velocity_integral =
            (self.velocity_integral + e_v * dt).zip_map(&k.velocity_i, |x, ki| {
                if ki > 0.0 {
                    x.clamp(-limit / ki, limit / ki)
                } else {
                    0.0
                }
            });
        let a_hat = self
            .acceleration
            .update(&measured.velocity, dt, k.derivative_cutoff_hz);
        let a_sp = r.acceleration
            + k.velocity_p.component_mul(&e_v)
            + k.velocity_i.component_mul(&self.velocity_integral)
            - k.velocity_d.component_mul(&a_hat);
        // 3. Thrust vector with tilt limit; PX4 keeps the vertical acceleration.
        let b3 = limit_tilt(
            &Vector3::new(a_sp.x, a_sp.y, self.gravity).normalize(),
            k.max_tilt_rad,
        );
        let thrust = (self.mass * (a_sp.z + self.gravity) / b3.z)
            .clamp(k.min_thrust_fraction * self.thrust_max, self.thrust_max);
        // 4. Attitude setpoint from b₃ and the heading.
        let yaw = r.yaw();
        let Some(b1) = Vector3::new(-yaw.sin(), yaw.cos(), 0.0)
            .cross(&b3)
            .try_normalize(1e-9)
        else {
            bail!("px4: thrust direction horizontal at t = {t:.3} s");
        };
        let rd = Matrix3::from_columns(&[b1, b3.cross(&b1), b3]);
        let q_sp = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rd));
        // 5. Quaternion P with the canonical (memoryless) sign.
        let mut q_e = measured.attitude.inverse() * q_sp;
        if q_e.w < 0.0 {
            q_e = UnitQuaternion::new_unchecked(-q_e.into_inner());
        }
        if self
            .previous_error
            .is_some_and(|p| p.coords.dot(&q_e.coords) < 0.0)
        {
            self.switches += 1;
        }
        self.previous_error = Some(q_e);
        let yaw_rate = r.heading.x * r.heading_rate.y - r.heading.y * r.heading_rate.x;
        let e3_body = measured.attitude.inverse_transform_vector(&Vector3::z());
        let rate_sp = (k.attitude_p.component_mul(&q_e.imag()) * 2.0 + e3_body * yaw_rate)
            .zip_map(&k.max_rate_rad_s, |w, m| w.clamp(-m, m));
        // 6. Rate PID in angular-acceleration units, scaled by J, clipped to ±τ_max.
        let w = measured.angular_velocity;
        let e_w = rate_sp - w;
        let int_limit = self
            .torque_max
            .component_div(&self.inertia.component_mul(&k.rate_i))
            * k.rate_integral_limit_fraction;
        self.rate_integral = (self.rate_integral + e_w * dt).zip_map(&int_limit, |x, l| {
            if l.is_finite() {
                x.clamp(-l, l)
            } else {
                0.0
            }
        });
        let w_dot = self
            .angular_acceleration
            .update(&w, dt, k.derivative_cutoff_hz);
        let alpha = k.rate_p.component_mul(&e_w) + k.rate_i.component_mul(&self.rate_integral)
            - k.rate_d.component_mul(&w_dot);
        let torque = self
            .inertia
            .component_mul(&alpha)
            .zip_map(&self.torque_max, |x, m| x.clamp(-m, m));
        if !(thrust.is_finite() && torque.iter().all(|x| x.is_finite())) {
            bail!("px4: non-finite command at t = {t:.3} s");
        }
        Ok(Command {
            thrust,
            torque,
            desired_rotation: rd,
            desired_angular_velocity: rate_sp,
            desired_angular_acceleration: Vector3::zeros(),
            switches_total: SwitchCounts {
                switches: self.switches,
                resets: 0,
            },
        })
    }
}
