//! One vehicle, everything the flight code and the simulators need to know about it: rigid
//! body, rotor geometry and range, yaw torque per newton, motor time constant, body drag, and
//! where those numbers come from.
//!
//! An [`Airframe`] is what a vehicle file (`host-sim/vehicles/*.toml`, see `docs/vehicles.md`)
//! describes; [`Airframe::paper`] is the paper's Section VI vehicle, the one
//! [`FlightConfig::paper`](crate::config::FlightConfig::paper) flies. With the `vehicle-file`
//! feature, `Airframe::from_vehicle_file` builds one from a parsed file.
//!
//! Units are SI; frames: body FLU (x forward, y left, z up).

use controller_core::scalar::sqrt_f32;
use controller_core::Vehicle;

/// A quadrotor: rigid body, rotors and their motors, body drag, with its name and source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Airframe {
    /// Short name, shown in reports and the firmware's boot banner (e.g. `"x500"`).
    pub name: &'static str,
    /// Where the numbers come from (publication, model file, commit).
    pub source: &'static str,
    /// Whether the yaw torque per newton is a real propeller's. `false` only for the paper's
    /// vehicle, whose 0.1 m is what its `τ_max,3 = 0.5 N m` needs, about five times a real
    /// propeller's 0.01–0.02 m.
    pub real_propeller: bool,
    /// Rigid body: mass \[kg\], inertia diagonal [kg m²] (body frame), gravity [m/s²].
    pub vehicle: Vehicle<f32>,
    /// Rotor geometry, thrust range, yaw torque per newton, thrust curve (motor order = mixer
    /// order = ESC output order).
    pub rotors: RotorConfig,
    /// First-order time constant of the rotor *speed* \[s\] (ESC + motor + propeller):
    /// `dϖ/dt = (ϖ_cmd − ϖ)/τ_m`, as RotorPy's and PX4's Gazebo motor models.
    pub motor_time_constant_s: f32,
    /// Quadratic body drag coefficients `c_i` [N s²/m²] per body axis:
    /// `F_i = −c_i |v_i| v_i` (body frame); zero = no body drag.
    pub body_drag: [f32; 3],
}

impl Airframe {
    /// The paper's vehicle (Section VI: `m = 0.46 kg`, `J = diag(2.24, 2.9, 5.3)·10⁻³ kg m²`)
    /// on an X quad whose rotors can produce the paper's limits: arm 0.25 m, 0 to 3 N per rotor
    /// (12 N in all; roll and pitch up to `√2 · 0.25 · 3 = 1.06 N m`), yaw torque 0.1 m per
    /// newton (`2 · 0.1 · 3 = 0.6 N m`), thrust curve factor 0.3, idle throttle 0.05.
    ///
    /// Not from the paper (it models no rotors): the geometry and range above, and the motor
    /// time constant 0.02 s (a typical ESC + motor value). The yaw ratio 0.1 m is not a real
    /// propeller's ([`Airframe::real_propeller`] is `false`).
    ///
    /// Motor order (Betaflight's quad X): 1 rear-right (CW), 2 front-right (CCW),
    /// 3 rear-left (CCW), 4 front-left (CW), seen from above. `host-sim/vehicles/paper.toml`
    /// describes the same airframe (a test checks they agree).
    pub fn paper() -> Self {
        let arm = 0.25f32;
        let d = arm * core::f32::consts::FRAC_1_SQRT_2;
        // Only the ratio k_Q/k_T is used (the yaw torque per newton), so k_T is normalised to 1
        // as for an airframe built from a vehicle file.
        let k_t = 1.0f32;
        Self {
            name: "paper",
            source: "Section VI of the paper (rigid body); rotors sized to its limits",
            real_propeller: false,
            vehicle: Vehicle::paper(),
            rotors: RotorConfig {
                rotors: [
                    Rotor {
                        position: [-d, -d],
                        spin: -1.0,
                    },
                    Rotor {
                        position: [d, -d],
                        spin: 1.0,
                    },
                    Rotor {
                        position: [-d, d],
                        spin: 1.0,
                    },
                    Rotor {
                        position: [d, d],
                        spin: -1.0,
                    },
                ],
                arm_length: arm,
                thrust_coefficient: k_t,
                drag_coefficient: 0.1 * k_t,
                thrust_min: 0.0,
                thrust_max: 3.0,
                curve_factor: 0.3,
                throttle_idle: 0.05,
            },
            motor_time_constant_s: 0.02,
            body_drag: [0.0; 3],
        }
    }

    /// The rotor geometry and model (a copy of [`Airframe::rotors`]).
    pub fn rotor_config(&self) -> RotorConfig {
        self.rotors
    }

    /// Weight `m g` \[N\].
    pub fn weight(&self) -> f32 {
        self.vehicle.mass * self.vehicle.gravity
    }

    /// Builds the airframe a parsed, validated vehicle file describes, with the same f32
    /// values as the firmware build's generated source
    /// ([`VehicleFile::to_rust_source`](crate::vehicle_file::VehicleFile::to_rust_source)).
    /// The name and source strings are leaked once per call (an airframe is built once per
    /// run, and its strings must be `'static` like the firmware's).
    #[cfg(feature = "vehicle-file")]
    pub fn from_vehicle_file(file: &crate::vehicle_file::VehicleFile) -> Self {
        use std::boxed::Box;
        let v = file.flight_values();
        let leak = |s: &str| -> &'static str { Box::leak(Box::from(s)) };
        let rotors = core::array::from_fn(|k| Rotor {
            position: v.positions[k],
            spin: v.spins[k],
        });
        Self {
            name: leak(&v.name),
            source: leak(&v.source),
            real_propeller: v.real_propeller,
            vehicle: Vehicle {
                mass: v.mass,
                inertia: nalgebra::Vector3::from(v.inertia),
                gravity: v.gravity,
            },
            rotors: RotorConfig {
                rotors,
                arm_length: v.arm_length,
                thrust_coefficient: 1.0,
                drag_coefficient: v.yaw_torque_per_thrust,
                thrust_min: v.thrust_min,
                thrust_max: v.thrust_max,
                curve_factor: v.curve_factor,
                throttle_idle: v.throttle_idle,
            },
            motor_time_constant_s: v.motor_time_constant,
            body_drag: v.body_drag,
        }
    }
}

/// Position and spin of one rotor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotor {
    /// Rotor hub position `(x, y)` \[m\] in the body FLU frame (x forward, y left).
    pub position: [f32; 2],
    /// `+1` if the rotor spins counter-clockwise seen from above (its reaction torque on the
    /// body is clockwise, i.e. negative about body z), `-1` if clockwise.
    pub spin: f32,
}

/// X-quad geometry and rotor model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorConfig {
    /// The four rotors, in motor-output order (see [`crate::mixer`]).
    pub rotors: [Rotor; 4],
    /// Arm length \[m\]: the largest distance from the centre of mass to a hub (documentation
    /// of the positions; [`Airframe::paper`] builds the positions from it).
    pub arm_length: f32,
    /// Rotor thrust coefficient `k_T` [N/(rad/s)²]: `f = k_T ϖ²`. Only the ratio
    /// `k_Q / k_T` is used; airframes from vehicle files (which give that ratio) and
    /// [`Airframe::paper`] set `k_T = 1`, so `drag_coefficient` is the ratio itself.
    pub thrust_coefficient: f32,
    /// Rotor drag-torque coefficient `k_Q` [N m/(rad/s)²]: `q = k_Q ϖ²`; the yaw torque per
    /// newton of thrust is `k_Q / k_T` \[m\].
    pub drag_coefficient: f32,
    /// Smallest thrust one rotor produces when armed \[N\] (at idle throttle).
    pub thrust_min: f32,
    /// Largest thrust one rotor produces \[N\] (at full throttle).
    pub thrust_max: f32,
    /// Thrust curve factor `k ∈ [0, 1]` (PX4's THR_MDL_FAC idea): the normalised thrust
    /// `f̂ = (f − f_min)/(f_max − f_min)` relates to the normalised command `u` by
    /// `f̂ = k u² + (1 − k) u`.
    pub curve_factor: f32,
    /// Throttle [0, 1] at which an armed motor idles (produces `thrust_min`).
    pub throttle_idle: f32,
}

impl RotorConfig {
    /// Yaw torque per newton of rotor thrust, `k_Q / k_T` \[m\].
    pub fn torque_per_thrust(&self) -> f32 {
        self.drag_coefficient / self.thrust_coefficient
    }

    /// Throttle [0, 1] for a rotor thrust `f` \[N\], clamped to `[thrust_min, thrust_max]`.
    /// Inverse of [`RotorConfig::thrust_from_throttle`] on `[throttle_idle, 1]`. A non-finite
    /// `f` gives the idle throttle (never NaN).
    pub fn throttle_from_thrust(&self, f: f32) -> f32 {
        let span = self.thrust_max - self.thrust_min;
        let mut n = (f - self.thrust_min) / span;
        if !n.is_finite() {
            n = 0.0;
        }
        let n = n.clamp(0.0, 1.0);
        let k = self.curve_factor;
        // Solve k u² + (1 − k) u = n for u ∈ [0, 1].
        let u = if k < 1e-6 {
            n
        } else {
            let b = 1.0 - k;
            (-b + sqrt_f32(b * b + 4.0 * k * n)) / (2.0 * k)
        };
        let t = self.throttle_idle + (1.0 - self.throttle_idle) * u.clamp(0.0, 1.0);
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            self.throttle_idle
        }
    }

    /// Rotor thrust \[N\] for an armed throttle in `[throttle_idle, 1]` (clamped).
    pub fn thrust_from_throttle(&self, throttle: f32) -> f32 {
        let u = ((throttle - self.throttle_idle) / (1.0 - self.throttle_idle)).clamp(0.0, 1.0);
        let k = self.curve_factor;
        self.thrust_min + (self.thrust_max - self.thrust_min) * (k * u * u + (1.0 - k) * u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::FlightConfig;

    /// The paper configuration flies this airframe, and normalising `k_T` to 1 kept the yaw
    /// torque per newton bit for bit (it was `k_Q/k_T = (0.1 · 10⁻⁵)/10⁻⁵` in f32 before).
    #[test]
    fn paper_config_flies_the_paper_airframe() {
        let a = Airframe::paper();
        let c = FlightConfig::paper();
        assert_eq!((a.vehicle, a.rotors), (c.vehicle, c.rotors));
        let k_t_before = 1.0e-5f32;
        let before = (0.1 * k_t_before) / k_t_before;
        assert_eq!(a.rotors.torque_per_thrust().to_bits(), before.to_bits());
        assert!(4.0 * a.rotors.thrust_max > a.weight());
        assert!(!a.real_propeller);
    }
}
