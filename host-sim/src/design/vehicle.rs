//! The vehicle a design is made for: rigid body, rotor set and motor time constant, read from a
//! vehicle file (`host-sim/vehicles/*.toml`), plus the file's own tables, which the design
//! copies verbatim into the scenario and flight files it writes.
//!
//! TEMPORARY STAND-IN: parses the contract's vehicle-file format locally until the shared
//! `firmware::vehicle_file` parser is merged.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use controller_core::Vehicle;
use firmware::config::{Rotor, RotorConfig};
use nalgebra::Vector3;
use serde::Deserialize;

/// A vehicle as the design sees it.
#[derive(Clone, Debug)]
pub struct DesignVehicle {
    /// Name (`[vehicle] name`).
    pub name: String,
    /// Published source of the values (`[vehicle] source`).
    pub source: String,
    /// Mass \[kg\], inertia diagonal [kg m²] (body), gravity [m/s²].
    pub body: Vehicle<f64>,
    /// The rotor set, as the firmware's mixer takes it.
    pub rotors: RotorConfig,
    /// First-order time constant of the rotor speed \[s\].
    pub motor_time_constant_s: f64,
    /// The file's `[vehicle]`, `[rotors]` and `[drag]` tables as read (copied into outputs).
    pub tables: toml::Table,
    /// The file the vehicle came from (for messages).
    pub origin: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StandInFile {
    vehicle: StandInVehicle,
    rotors: StandInRotors,
    #[allow(dead_code)]
    drag: Option<toml::Table>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StandInVehicle {
    name: String,
    source: String,
    mass_kg: f64,
    inertia_kg_m2: [f64; 3],
    gravity_m_s2: f64,
    #[allow(dead_code)]
    real_propeller: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct StandInRotors {
    positions_m: [[f64; 2]; 4],
    spin: [String; 4],
    thrust_min_N: f64,
    thrust_max_N: f64,
    yaw_torque_per_thrust_m: f64,
    motor_time_constant_s: f64,
    thrust_curve_factor: f64,
    throttle_idle: f64,
}

impl DesignVehicle {
    /// Reads a vehicle file. Errors: unreadable file, or a key missing/invalid (file, key,
    /// reason).
    pub fn load(path: &Path) -> Result<Self> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read vehicle file {origin}"))?;
        let file: StandInFile =
            toml::from_str(&text).map_err(|e| anyhow!("vehicle file {origin}: {e}"))?;
        let all: toml::Table =
            toml::from_str(&text).map_err(|e| anyhow!("vehicle file {origin}: {e}"))?;
        let tables = all
            .into_iter()
            .filter(|(k, _)| matches!(k.as_str(), "vehicle" | "rotors" | "drag"))
            .collect();
        let r = &file.rotors;
        let spin = |s: &str| -> Result<f32> {
            match s {
                "ccw" => Ok(1.0),
                "cw" => Ok(-1.0),
                other => bail!("{origin}: rotors.spin: \"{other}\" is not \"cw\" or \"ccw\""),
            }
        };
        let mut rotors = [Rotor {
            position: [0.0; 2],
            spin: 1.0,
        }; 4];
        for (k, rotor) in rotors.iter_mut().enumerate() {
            rotor.position = r.positions_m[k].map(|x| x as f32);
            rotor.spin = spin(&r.spin[k])?;
        }
        let arm = r.positions_m[0][0].hypot(r.positions_m[0][1]) as f32;
        Ok(Self {
            name: file.vehicle.name,
            source: file.vehicle.source,
            body: Vehicle {
                mass: file.vehicle.mass_kg,
                inertia: Vector3::from(file.vehicle.inertia_kg_m2),
                gravity: file.vehicle.gravity_m_s2,
            },
            rotors: RotorConfig {
                rotors,
                arm_length: arm,
                thrust_coefficient: 1.0,
                drag_coefficient: r.yaw_torque_per_thrust_m as f32,
                thrust_min: r.thrust_min_N as f32,
                thrust_max: r.thrust_max_N as f32,
                curve_factor: r.thrust_curve_factor as f32,
                throttle_idle: r.throttle_idle as f32,
            },
            motor_time_constant_s: r.motor_time_constant_s,
            tables,
            origin,
        })
    }
}
