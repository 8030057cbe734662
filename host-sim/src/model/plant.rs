//! The rigid-body plant of eq:FullDynamics, integrated with fixed-step RK4.
//!
//! `ṗ = v`, `v̇ = −g e₃ + R e₃ T/m + f_d/m`, `Ṙ = R[ω]ₓ`, `Jω̇ = [Jω]ₓω + τ + τ_d`.
//! The attitude is integrated as a unit quaternion (`q̇ = ½ q ⊗ (0, ω)`) and renormalised after
//! every step, so `R(q)` stays on SO(3) to rounding.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// The state of the rigid body (f64).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBodyState {
    /// Position \[m\], inertial (z up).
    pub position: Vector3<f64>,
    /// Velocity [m/s], inertial.
    pub velocity: Vector3<f64>,
    /// Attitude, body to inertial.
    pub attitude: UnitQuaternion<f64>,
    /// Angular velocity [rad/s], body frame.
    pub angular_velocity: Vector3<f64>,
}

/// Rigid-body parameters of the plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody {
    /// Mass \[kg\].
    pub mass: f64,
    /// Inertia diagonal [kg m²], body frame.
    pub inertia: Vector3<f64>,
    /// Gravity [m/s²].
    pub gravity: f64,
}

/// Inputs held over an integration step.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PlantInput {
    /// Collective thrust \[N\] along body z.
    pub thrust: f64,
    /// Torque [N m], body frame.
    pub torque: Vector3<f64>,
    /// External force \[N\], inertial (disturbance).
    pub force_disturbance: Vector3<f64>,
    /// External torque [N m], body frame (disturbance).
    pub torque_disturbance: Vector3<f64>,
}

/// Time derivative of the state, with the quaternion rate unnormalised.
#[derive(Clone, Copy)]
struct Derivative {
    position: Vector3<f64>,
    velocity: Vector3<f64>,
    attitude: Quaternion<f64>,
    angular_velocity: Vector3<f64>,
}

/// A [`PlantInput`] held over a step, with the quotients by the mass and the gravity vector that
/// every derivative evaluation would otherwise recompute (the same operations on the same
/// operands, so the same bits, once per hold instead of four times per RK4 substep).
#[derive(Clone, Copy)]
struct HeldInput {
    /// `T / m` [m/s²].
    thrust_accel: f64,
    /// `f_d / m` [m/s²], inertial.
    force_accel: Vector3<f64>,
    /// `τ` [N m], body.
    torque: Vector3<f64>,
    /// `τ_d` [N m], body.
    torque_disturbance: Vector3<f64>,
    /// `g e₃` [m/s²], inertial.
    gravity: Vector3<f64>,
}

impl RigidBody {
    #[inline(always)]
    fn hold(&self, u: &PlantInput) -> HeldInput {
        HeldInput {
            thrust_accel: u.thrust / self.mass,
            force_accel: u.force_disturbance / self.mass,
            torque: u.torque,
            torque_disturbance: u.torque_disturbance,
            gravity: Vector3::z() * self.gravity,
        }
    }

    // Inlined into the RK4 step: as a call, its 13-float result went through memory four times
    // per step, which made up a quarter of a paper run.
    #[inline(always)]
    fn derivative(
        &self,
        v: &Vector3<f64>,
        q: &Quaternion<f64>,
        w: &Vector3<f64>,
        u: &HeldInput,
    ) -> Derivative {
        // Body z in the inertial frame, from the (nearly unit) quaternion in closed form.
        let (q0, x, y, z) = (q.w, q.i, q.j, q.k);
        let body_z = Vector3::new(
            2.0 * (x * z + q0 * y),
            2.0 * (y * z - q0 * x),
            1.0 - 2.0 * (x * x + y * y),
        );
        let accel = body_z * u.thrust_accel + u.force_accel - u.gravity;
        let jw = self.inertia.component_mul(w);
        let w_dot = (jw.cross(w) + u.torque + u.torque_disturbance).component_div(&self.inertia);
        Derivative {
            position: *v,
            velocity: accel,
            attitude: q * Quaternion::from_parts(0.0, *w) * 0.5,
            angular_velocity: w_dot,
        }
    }

    /// Advances `state` by `h` \[s\] with one classical RK4 step, inputs held.
    pub fn rk4_step(&self, state: &RigidBodyState, input: &PlantInput, h: f64) -> RigidBodyState {
        self.rk4_held(state, &self.hold(input), h)
    }

    #[inline(always)]
    fn rk4_held(&self, state: &RigidBodyState, input: &HeldInput, h: f64) -> RigidBodyState {
        let (p, v, q, w) = (
            state.position,
            state.velocity,
            *state.attitude.quaternion(),
            state.angular_velocity,
        );
        let k1 = self.derivative(&v, &q, &w, input);
        let at = |k: &Derivative, s: f64| {
            (
                v + k.velocity * s,
                q + k.attitude * s,
                w + k.angular_velocity * s,
            )
        };
        let (v2, q2, w2) = at(&k1, h / 2.0);
        let k2 = self.derivative(&v2, &q2, &w2, input);
        let (v3, q3, w3) = at(&k2, h / 2.0);
        let k3 = self.derivative(&v3, &q3, &w3, input);
        let (v4, q4, w4) = at(&k3, h);
        let k4 = self.derivative(&v4, &q4, &w4, input);
        let s = h / 6.0;
        RigidBodyState {
            position: p + (k1.position + k2.position * 2.0 + k3.position * 2.0 + k4.position) * s,
            velocity: v + (k1.velocity + k2.velocity * 2.0 + k3.velocity * 2.0 + k4.velocity) * s,
            attitude: UnitQuaternion::from_quaternion(
                q + (k1.attitude + k2.attitude * 2.0 + k3.attitude * 2.0 + k4.attitude) * s,
            ),
            angular_velocity: w
                + (k1.angular_velocity
                    + k2.angular_velocity * 2.0
                    + k3.angular_velocity * 2.0
                    + k4.angular_velocity)
                    * s,
        }
    }

    /// Advances `state` by `duration` \[s\] in substeps of at most `max_step` \[s\], inputs held
    /// (zero-order hold between controller samples).
    pub fn advance(
        &self,
        state: &RigidBodyState,
        input: &PlantInput,
        duration: f64,
        max_step: f64,
    ) -> RigidBodyState {
        let n = (duration / max_step).ceil().max(1.0) as usize;
        let h = duration / n as f64;
        let held = self.hold(input);
        let mut s = *state;
        for _ in 0..n {
            s = self.rk4_held(&s, &held, h);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn body() -> RigidBody {
        RigidBody {
            mass: 0.46,
            inertia: Vector3::new(2.24e-3, 2.9e-3, 5.3e-3),
            gravity: 9.81,
        }
    }

    /// Torque-free rotation conserves kinetic energy and angular momentum (inertial frame);
    /// the attitude stays on SO(3).
    #[test]
    fn torque_free_rotation_conserves_invariants() {
        let b = body();
        let mut s = RigidBodyState {
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            attitude: UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1),
            angular_velocity: Vector3::new(3.0, 0.2, -1.0),
        };
        let energy = |s: &RigidBodyState| {
            s.angular_velocity
                .dot(&b.inertia.component_mul(&s.angular_velocity))
        };
        let momentum =
            |s: &RigidBodyState| s.attitude * b.inertia.component_mul(&s.angular_velocity);
        let (e0, h0) = (energy(&s), momentum(&s));
        let input = PlantInput {
            thrust: b.mass * b.gravity,
            ..Default::default()
        };
        for _ in 0..10_000 {
            s = b.rk4_step(&s, &input, 1e-3);
        }
        assert_relative_eq!(energy(&s), e0, max_relative = 1e-9);
        assert_relative_eq!(momentum(&s), h0, epsilon = 1e-9);
        let r = s.attitude.to_rotation_matrix().into_inner();
        assert_relative_eq!(
            r.transpose() * r,
            nalgebra::Matrix3::identity(),
            epsilon = 1e-12
        );
    }

    /// Hover thrust with level attitude: no motion. Free fall: p(t) = p₀ − g t²/2 exactly.
    #[test]
    fn translational_dynamics() {
        let b = body();
        let s0 = RigidBodyState {
            position: Vector3::new(1.0, 2.0, 3.0),
            velocity: Vector3::zeros(),
            attitude: UnitQuaternion::identity(),
            angular_velocity: Vector3::zeros(),
        };
        let hover = b.advance(
            &s0,
            &PlantInput {
                thrust: b.mass * b.gravity,
                ..Default::default()
            },
            2.0,
            1e-3,
        );
        assert_relative_eq!(hover.position, s0.position, epsilon = 1e-12);
        let fall = b.advance(&s0, &PlantInput::default(), 2.0, 1e-3);
        assert_relative_eq!(fall.position.z, 3.0 - 0.5 * 9.81 * 4.0, epsilon = 1e-9);
    }
}
