//! A vehicle file's values in the firmware's `f32`, and the Rust source of its airframe for the
//! firmware build.

use std::format;
use std::string::String;
use std::vec::Vec;

use super::{VehicleFile, ROTOR_COUNT};

/// The values of a vehicle file in the `f32` the firmware flies with, computed in one place so
/// that the firmware build's generated source ([`VehicleFile::to_rust_source`]) and host-sim's
/// airframe (`Airframe::from_vehicle_file`) agree bit for bit.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightValues {
    /// Name (empty when the table has none).
    pub name: String,
    /// Source (empty when the table has none).
    pub source: String,
    /// Whether the yaw ratio is a real propeller's (`true` when the table does not say).
    pub real_propeller: bool,
    /// Mass \[kg\].
    pub mass: f32,
    /// Inertia diagonal [kg m²], body frame.
    pub inertia: [f32; 3],
    /// Gravity [m/s²].
    pub gravity: f32,
    /// Hub positions `(x, y)` \[m\], body FLU.
    pub positions: [[f32; 2]; ROTOR_COUNT],
    /// Spins as the firmware's `Rotor::spin` (`+1` CCW, `−1` CW, seen from above).
    pub spins: [f32; ROTOR_COUNT],
    /// Largest hub distance from the centre of mass \[m\] (computed in f64, then rounded).
    pub arm_length: f32,
    /// Per-rotor thrust range \[N\].
    pub thrust_min: f32,
    /// Per-rotor thrust range \[N\].
    pub thrust_max: f32,
    /// `k_Q / k_T` \[m\].
    pub yaw_torque_per_thrust: f32,
    /// Thrust curve factor.
    pub curve_factor: f32,
    /// Idle throttle.
    pub throttle_idle: f32,
    /// Motor time constant \[s\].
    pub motor_time_constant: f32,
    /// Body drag coefficients [N s²/m²] (zero without `[drag]`).
    pub body_drag: [f32; 3],
}

impl VehicleFile {
    /// The file's values in `f32` (see [`FlightValues`]). Call on a validated file (four
    /// rotors); missing rotors would read as zeros.
    pub fn flight_values(&self) -> FlightValues {
        let r = &self.rotors;
        let v = &self.vehicle;
        let f = |x: f64| x as f32;
        let positions = core::array::from_fn(|k| {
            r.positions_m
                .get(k)
                .map_or([0.0; 2], |p| [f(p[0]), f(p[1])])
        });
        let spins = core::array::from_fn(|k| r.spin.get(k).map_or(0.0, |s| s.sign()));
        let arm = r
            .positions_m
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0f64, f64::max);
        FlightValues {
            name: v.name.clone().unwrap_or_default(),
            source: v.source.clone().unwrap_or_default(),
            real_propeller: v.real_propeller.unwrap_or(true),
            mass: f(v.mass_kg),
            inertia: v.inertia_kg_m2.map(f),
            gravity: f(v.gravity_m_s2),
            positions,
            spins,
            arm_length: f(arm),
            thrust_min: f(r.thrust_min_N),
            thrust_max: f(r.thrust_max_N),
            yaw_torque_per_thrust: f(r.yaw_torque_per_thrust_m),
            curve_factor: f(r.thrust_curve_factor),
            throttle_idle: f(r.throttle_idle),
            motor_time_constant: f(r.motor_time_constant_s),
            body_drag: self
                .drag
                .as_ref()
                .map_or([0.0; 3], |d| d.body_drag_N_s2_m2.map(f)),
        }
    }

    /// Rust source of an expression of type `firmware::airframe::Airframe` (written with
    /// `crate::` paths, for code generated into the firmware crate) equal, field for field
    /// and bit for bit, to `Airframe::from_vehicle_file(self)`. `f32` literals are printed
    /// with Rust's shortest round-trip formatting. Call on a validated file.
    pub fn to_rust_source(&self) -> String {
        let v = self.flight_values();
        let lit = |x: f32| format!("{x:?}f32");
        let arr = |xs: &[f32]| {
            let items: Vec<String> = xs.iter().map(|&x| lit(x)).collect();
            format!("[{}]", items.join(", "))
        };
        let rotors: Vec<String> = v
            .positions
            .iter()
            .zip(v.spins)
            .map(|(p, s)| {
                format!(
                    "crate::config::Rotor {{ position: {}, spin: {} }}",
                    arr(p),
                    lit(s)
                )
            })
            .collect();
        format!(
            "crate::airframe::Airframe {{\n    \
             name: {name:?},\n    \
             source: {source:?},\n    \
             real_propeller: {real},\n    \
             vehicle: controller_core::Vehicle {{\n        \
             mass: {mass},\n        \
             inertia: nalgebra::Vector3::new({j0}, {j1}, {j2}),\n        \
             gravity: {g},\n    }},\n    \
             rotors: crate::config::RotorConfig {{\n        \
             rotors: [\n            {rotors}\n        ],\n        \
             arm_length: {arm},\n        \
             thrust_coefficient: 1.0f32,\n        \
             drag_coefficient: {c},\n        \
             thrust_min: {fmin},\n        \
             thrust_max: {fmax},\n        \
             curve_factor: {k},\n        \
             throttle_idle: {idle},\n    }},\n    \
             motor_time_constant_s: {tau},\n    \
             body_drag: {drag},\n}}",
            name = v.name,
            source = v.source,
            real = v.real_propeller,
            mass = lit(v.mass),
            j0 = lit(v.inertia[0]),
            j1 = lit(v.inertia[1]),
            j2 = lit(v.inertia[2]),
            g = lit(v.gravity),
            rotors = rotors.join(",\n            "),
            arm = lit(v.arm_length),
            c = lit(v.yaw_torque_per_thrust),
            fmin = lit(v.thrust_min),
            fmax = lit(v.thrust_max),
            k = lit(v.curve_factor),
            idle = lit(v.throttle_idle),
            tau = lit(v.motor_time_constant),
            drag = arr(&v.body_drag),
        )
    }
}
