//! The rotor-level plant: the firmware's own mixer, four rotors with first-order motor dynamics,
//! optional quadratic body drag, and the rigid body of [`crate::model::plant`].
//!
//! Per controller sample the held command `(T, τ)` goes through [`firmware::mixer::Mixer::mix`]
//! (the same f32 code as on the flight controller: its desaturation, each rotor clipped to its
//! thrust range), giving the commanded rotor thrusts `f_cmd,k` \[N\]. Each rotor's speed follows
//! its command through a first-order lag. The state is `s_k = √f_k` (proportional to the rotor
//! speed `ϖ_k`, since `f = k_T ϖ²`), and
//!
//! `ṡ_k = (√f_cmd,k − s_k) / τ_m`, thrust `f_k = s_k²`, yaw drag torque `c f_k` (`c = k_Q/k_T`),
//!
//! i.e. thrust and drag torque proportional to speed squared, as the motor models of RotorPy
//! (`multirotor.py`, rotor speed first-order with `tau_m`) and PX4's Gazebo
//! (`gz MulticopterMotorModel`, speed first-order, force `k_T ϖ²`, moment `k_Q ϖ²`). With the
//! command held over a substep `h` the update is exact: `s ← s_cmd + (s − s_cmd) e^(−h/τ_m)`
//! (`τ_m = 0`: the rotors follow the command at once). The body sees `(T, τ) = B f`, with `B` the
//! mixer's effectiveness matrix (see [`firmware::mixer`]), plus, when configured, the drag force
//! `F_i = −c_i |v_i| v_i` per body axis (body-frame velocity), evaluated at the start of each
//! substep and held over it.

use anyhow::{anyhow, Result};
use firmware::config::RotorConfig;
use firmware::mixer::Mixer;
use nalgebra::{Matrix4, Vector3, Vector4};
use serde::Serialize;

use crate::model::plant::{PlantInput, RigidBody, RigidBodyState};

/// The parameters of a [`RotorPlant`]: what a vehicle's `[rotors]` and `[drag]` tables give.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct RotorParameters {
    /// Rotor geometry, spin, thrust range and yaw torque per newton (the firmware's type).
    pub rotors: RotorConfig,
    /// First-order time constant of the rotor speed \[s\] (`0`: no lag).
    pub motor_time_constant_s: f64,
    /// Quadratic body drag per body axis [N s²/m²] (`F_i = −c_i |v_i| v_i`).
    pub body_drag_N_s2_m2: [f64; 3],
}

/// What the mixer makes of one `(T, τ)` command, in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct MixReport {
    /// Commanded rotor thrusts \[N\], motor order, each within the rotor range.
    pub rotor_command_N: [f64; 4],
    /// Collective thrust the commanded rotor thrusts produce \[N\].
    pub achieved_thrust_N: f64,
    /// Torque the commanded rotor thrusts produce [N m], body frame.
    pub achieved_torque_Nm: Vector3<f64>,
    /// The mixer gave something up (scaled roll/pitch, shifted the collective or scaled yaw;
    /// [`firmware::mixer::MixOutput::saturated`]).
    pub gave_up: bool,
    /// `|T − T_achieved|` \[N\] when something was given up, else 0.
    pub thrust_given_up_N: f64,
    /// `max_i |τ_i − τ_achieved,i|` [N m] when something was given up, else 0.
    pub torque_given_up_Nm: f64,
}

/// Counts of what the mixer gave up over samples (`campaign.json`, `summary.json`).
#[derive(Clone, Copy, Debug, Default, Serialize, serde::Deserialize, PartialEq)]
#[allow(non_snake_case)]
pub struct MixerCounts {
    /// Samples whose command went through the mixer.
    pub samples: u64,
    /// Samples where the mixer gave something up (the command did not fit the rotors).
    pub samples_given_up: u64,
    /// Largest thrust given up in one sample \[N\].
    pub thrust_given_up_max_N: f64,
    /// Largest per-axis torque given up in one sample [N m].
    pub torque_given_up_max_Nm: f64,
}

impl MixerCounts {
    /// Adds one sample's report.
    pub fn push(&mut self, mix: &MixReport) {
        self.samples += 1;
        self.samples_given_up += u64::from(mix.gave_up);
        self.thrust_given_up_max_N = self.thrust_given_up_max_N.max(mix.thrust_given_up_N);
        self.torque_given_up_max_Nm = self.torque_given_up_max_Nm.max(mix.torque_given_up_Nm);
    }

    /// Adds another set of counts (another run's).
    pub fn merge(&mut self, other: &MixerCounts) {
        self.samples += other.samples;
        self.samples_given_up += other.samples_given_up;
        self.thrust_given_up_max_N = self.thrust_given_up_max_N.max(other.thrust_given_up_max_N);
        self.torque_given_up_max_Nm = self
            .torque_given_up_max_Nm
            .max(other.torque_given_up_max_Nm);
    }
}

/// The rotors at one controller sample: their thrusts then, and the mixer's report on the
/// sample's command.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct RotorSample {
    /// Rotor thrusts at the sample time \[N\], motor order (the motor state, before the
    /// sample's command acts).
    pub rotor_thrust_N: [f64; 4],
    /// The mixer's report on the sample's command.
    pub mix: MixReport,
}

/// The rotor-level plant (see the module docs). Holds the rotor state between calls.
#[derive(Clone, Debug)]
pub struct RotorPlant {
    mixer: Mixer,
    effectiveness: Matrix4<f64>,
    motor_time_constant_s: f64,
    body_drag: Vector3<f64>,
    /// `s_k = √f_k`; `None` until the first command (the motors start at it: spun up before
    /// the run, as the ideal plant's lag starts at its first command).
    speed: Option<Vector4<f64>>,
}

impl RotorPlant {
    /// A plant with the rotors of `rotors` (geometry, thrust range, yaw torque per newton),
    /// motor time constant `motor_time_constant_s` \[s\] (`0`: no lag) of the rotor speed, and
    /// quadratic body drag coefficients `body_drag` [N s²/m²] per body axis.
    ///
    /// Errors: the mixer refuses the rotors (degenerate geometry, empty thrust range), or the
    /// time constant or a drag coefficient is negative or not finite.
    pub fn new(
        rotors: &RotorConfig,
        motor_time_constant_s: f64,
        body_drag: [f64; 3],
    ) -> Result<Self> {
        let mixer = Mixer::new(rotors).map_err(|e| anyhow!("rotors: {e:?}"))?;
        if !(motor_time_constant_s.is_finite() && motor_time_constant_s >= 0.0) {
            return Err(anyhow!(
                "motor_time_constant_s: must be finite and >= 0, got {motor_time_constant_s}"
            ));
        }
        if !body_drag.iter().all(|c| c.is_finite() && *c >= 0.0) {
            return Err(anyhow!(
                "body_drag_N_s2_m2: must be finite and >= 0, got {body_drag:?}"
            ));
        }
        Ok(Self {
            effectiveness: mixer.effectiveness().map(f64::from),
            mixer,
            motor_time_constant_s,
            body_drag: Vector3::from(body_drag),
            speed: None,
        })
    }

    /// [`RotorPlant::new`] from [`RotorParameters`].
    ///
    /// Errors: as [`RotorPlant::new`].
    pub fn from_parameters(p: &RotorParameters) -> Result<Self> {
        Self::new(&p.rotors, p.motor_time_constant_s, p.body_drag_N_s2_m2)
    }

    /// The motor time constant `τ_m` \[s\] of the rotor speed.
    pub fn motor_time_constant_s(&self) -> f64 {
        self.motor_time_constant_s
    }

    /// The firmware mixer this plant allocates with.
    pub fn mixer(&self) -> &Mixer {
        &self.mixer
    }

    /// Collective thrust \[N\] and body torque [N m] of rotor thrusts `f` \[N\]: `(T, τ) = B f`.
    pub fn wrench(&self, f: &[f64; 4]) -> (f64, Vector3<f64>) {
        let w = self.effectiveness * Vector4::from(*f);
        (w[0], Vector3::new(w[1], w[2], w[3]))
    }

    /// What the mixer makes of the command `thrust` \[N\], `torque` [N m] (pure: the rotor state
    /// is not touched).
    pub fn mix(&self, thrust: f64, torque: &Vector3<f64>) -> MixReport {
        let out = self.mixer.mix(thrust as f32, &torque.map(|t| t as f32));
        let command = out.thrust.map(f64::from);
        let (achieved_thrust, achieved_torque) = self.wrench(&command);
        let gave_up = out.saturated();
        let (thrust_given_up, torque_given_up) = if gave_up {
            (
                (thrust - achieved_thrust).abs(),
                (torque - achieved_torque).amax(),
            )
        } else {
            (0.0, 0.0)
        };
        MixReport {
            rotor_command_N: command,
            achieved_thrust_N: achieved_thrust,
            achieved_torque_Nm: achieved_torque,
            gave_up,
            thrust_given_up_N: thrust_given_up,
            torque_given_up_Nm: torque_given_up,
        }
    }

    /// The rotor thrusts now \[N\]; before the first command, `None`.
    pub fn rotor_thrusts(&self) -> Option<[f64; 4]> {
        self.speed
            .map(|s| [s[0] * s[0], s[1] * s[1], s[2] * s[2], s[3] * s[3]])
    }

    /// The sample a controller would see for the command `thrust`, `torque`: the rotor thrusts
    /// now (the command's own rotor thrusts before the first command) and the mixer's report.
    pub fn sample(&self, thrust: f64, torque: &Vector3<f64>) -> RotorSample {
        let mix = self.mix(thrust, torque);
        RotorSample {
            rotor_thrust_N: self.rotor_thrusts().unwrap_or(mix.rotor_command_N),
            mix,
        }
    }

    /// The quadratic body drag force \[N\], inertial, at `state`.
    fn drag(&self, state: &RigidBodyState) -> Vector3<f64> {
        if self.body_drag == Vector3::zeros() {
            return Vector3::zeros();
        }
        let v_body = state.attitude.inverse_transform_vector(&state.velocity);
        let f_body = -self
            .body_drag
            .component_mul(&v_body.abs())
            .component_mul(&v_body);
        state.attitude.transform_vector(&f_body)
    }

    /// Advances `body` from `state` over `duration` \[s\] (RK4 substeps of at most `max_step`
    /// \[s\]) with the command `input.thrust`, `input.torque` held: mixed once, the rotor speeds
    /// updated exactly before each substep, the body driven by `B f`, the drag and the
    /// disturbances `input.force_disturbance` (inertial) and `input.torque_disturbance` (body).
    /// Returns the state at the end and the mixer's report on the command.
    pub fn advance(
        &mut self,
        body: &RigidBody,
        state: &RigidBodyState,
        input: &PlantInput,
        duration: f64,
        max_step: f64,
    ) -> (RigidBodyState, MixReport) {
        let mix = self.mix(input.thrust, &input.torque);
        let target = Vector4::from(mix.rotor_command_N).map(f64::sqrt);
        let n = (duration / max_step).ceil().max(1.0) as usize;
        let h = duration / n as f64;
        let decay = if self.motor_time_constant_s > 0.0 {
            (-h / self.motor_time_constant_s).exp()
        } else {
            0.0
        };
        let mut speed = self.speed.unwrap_or(target);
        let mut s = *state;
        for _ in 0..n {
            speed = target + (speed - target) * decay;
            let f = speed.component_mul(&speed);
            let (thrust, torque) = self.wrench(&[f[0], f[1], f[2], f[3]]);
            let applied = PlantInput {
                thrust,
                torque,
                force_disturbance: input.force_disturbance + self.drag(&s),
                torque_disturbance: input.torque_disturbance,
            };
            s = body.rk4_step(&s, &applied, h);
        }
        self.speed = Some(speed);
        (s, mix)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use firmware::config::FlightConfig;
    use nalgebra::UnitQuaternion;

    fn body() -> RigidBody {
        RigidBody {
            mass: 0.46,
            inertia: Vector3::new(2.24e-3, 2.9e-3, 5.3e-3),
            gravity: 9.81,
        }
    }

    fn at_rest() -> RigidBodyState {
        RigidBodyState {
            position: Vector3::new(0.0, 0.0, 2.0),
            velocity: Vector3::zeros(),
            attitude: UnitQuaternion::identity(),
            angular_velocity: Vector3::zeros(),
        }
    }

    fn plant(tau: f64) -> RotorPlant {
        RotorPlant::new(&FlightConfig::paper().rotors, tau, [0.0; 3]).unwrap()
    }

    /// Hover: the command m g with zero torque puts every rotor at m g / 4 and the body does
    /// not move (with and without motor lag).
    #[test]
    fn hover_is_an_equilibrium() {
        let b = body();
        for tau in [0.0, 0.03] {
            let mut p = plant(tau);
            let hover = PlantInput {
                thrust: b.mass * b.gravity,
                ..Default::default()
            };
            let mut s = at_rest();
            for _ in 0..200 {
                let (next, mix) = p.advance(&b, &s, &hover, 0.01, 1e-3);
                assert!(!mix.gave_up);
                s = next;
            }
            let f = p.rotor_thrusts().unwrap();
            for fk in f {
                // The mixer is f32: m g / 4 to f32 rounding.
                assert_relative_eq!(fk, b.mass * b.gravity / 4.0, max_relative = 1e-6);
            }
            // The mixer's f32 rounding leaves a residual torque of at most ~4 ε₃₂ f d per
            // axis; over T = 2 s it may spin the body up to τ T / J and move it by about
            // g (τ T² / 2J) T² / 2: bounds far below any controller-visible motion.
            let (t, d) = (2.0, 0.25 * std::f64::consts::FRAC_1_SQRT_2);
            let tau_r = 4.0 * f64::from(f32::EPSILON) * b.mass * b.gravity / 4.0 * d;
            let j = b.inertia.min();
            assert!(s.angular_velocity.norm() < tau_r * t / j, "{s:?}");
            let drift = b.gravity * (tau_r * t * t / (2.0 * j)) * t * t / 2.0;
            assert!((s.position - at_rest().position).norm() < drift, "{s:?}");
            assert!(s.velocity.z.abs() < 1e-5, "{s:?}");
        }
    }

    /// Step of one rotor's command from f0 to f1: its speed √f is first order, so after one
    /// time constant f = (√f1 + (√f0 − √f1) e⁻¹)², computed here from the definition (and not
    /// the first-order thrust value f1 + (f0 − f1) e⁻¹, which the test tells apart).
    #[test]
    fn rotor_speed_is_first_order_with_its_time_constant() {
        let tau = 0.04;
        let mut p = plant(tau);
        let b = body();
        let m = *p.mixer().mixing();
        // Hover first (rotors at the hover command), then a roll command that moves rotor 3
        // (left) up: the collective and other axes unchanged.
        let hover = PlantInput {
            thrust: 4.0,
            ..Default::default()
        };
        let _ = p.advance(&b, &at_rest(), &hover, 0.01, 1e-3);
        let f0 = p.rotor_thrusts().unwrap()[2];
        let step = PlantInput {
            thrust: 4.0,
            torque: Vector3::new(0.3, 0.0, 0.0),
            ..Default::default()
        };
        let f1 = f64::from(m[(2, 0)] * 4.0 + m[(2, 1)] * 0.3);
        assert!(f1 > f0 + 0.3);
        // One time constant in 4 controller periods of τ/4, substeps of τ/40.
        let mut s = at_rest();
        for _ in 0..4 {
            s = p.advance(&b, &s, &step, tau / 4.0, tau / 40.0).0;
        }
        let e = (-1.0f64).exp();
        let expected = (f1.sqrt() + (f0.sqrt() - f1.sqrt()) * e).powi(2);
        let f = p.rotor_thrusts().unwrap()[2];
        assert_relative_eq!(f, expected, max_relative = 1e-6);
        let thrust_first_order = f1 + (f0 - f1) * e;
        assert!(
            (f - thrust_first_order).abs() > 1e-3,
            "{f} vs {thrust_first_order}"
        );
        // τ_m = 0: the rotor is at its command at once.
        let mut p0 = plant(0.0);
        let _ = p0.advance(&b, &at_rest(), &hover, 0.01, 1e-3);
        let _ = p0.advance(&b, &at_rest(), &step, 1e-3, 1e-3);
        assert_relative_eq!(p0.rotor_thrusts().unwrap()[2], f1, max_relative = 1e-6);
    }

    /// A command outside the rotor box is reported as given up, by how much it was: here a
    /// collective of 14 N from four 0–3 N rotors (12 N at most) and a yaw torque beyond
    /// 2 c (f_max − f_min) = 0.6 N m.
    #[test]
    fn unrealisable_command_is_given_up() {
        let p = plant(0.0);
        let mix = p.mix(14.0, &Vector3::zeros());
        assert!(mix.gave_up);
        assert_relative_eq!(mix.achieved_thrust_N, 12.0, max_relative = 1e-6);
        assert_relative_eq!(mix.thrust_given_up_N, 2.0, max_relative = 1e-5);
        let mix = p.mix(6.0, &Vector3::new(0.0, 0.0, 0.9));
        assert!(mix.gave_up);
        assert!(mix.torque_given_up_Nm >= 0.9 - 0.6 - 1e-5, "{mix:?}");
        assert!(mix.rotor_command_N.iter().all(|f| (0.0..=3.0).contains(f)));
        // Realisable: nothing given up, the achieved wrench is the command.
        let mix = p.mix(6.0, &Vector3::new(0.05, -0.02, 0.01));
        assert!(!mix.gave_up);
        assert_eq!((mix.thrust_given_up_N, mix.torque_given_up_Nm), (0.0, 0.0));
        assert_relative_eq!(mix.achieved_thrust_N, 6.0, max_relative = 1e-6);
    }

    /// Quadratic body drag: a level body moving along body x at v with thrust m g decelerates
    /// at c v² / m (checked over a short step).
    #[test]
    fn body_drag_is_quadratic_in_body_velocity() {
        let b = body();
        let c = 0.2;
        let mut p = RotorPlant::new(&FlightConfig::paper().rotors, 0.0, [c, 0.0, 0.0]).unwrap();
        let mut s = at_rest();
        s.velocity = Vector3::new(-3.0, 0.0, 0.0);
        let hover = PlantInput {
            thrust: b.mass * b.gravity,
            ..Default::default()
        };
        let h = 1e-4;
        let (next, _) = p.advance(&b, &s, &hover, h, h);
        let accel = (next.velocity.x - s.velocity.x) / h;
        assert_relative_eq!(accel, c * 9.0 / b.mass, max_relative = 1e-3);
        assert!(RotorPlant::new(&FlightConfig::paper().rotors, -1.0, [0.0; 3]).is_err());
    }
}
