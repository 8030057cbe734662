//! The vehicle a design is made for: rigid body, rotor set and motor time constant, read from a
//! vehicle file (`host-sim/vehicles/*.toml`, [`crate::model::vehicle`]), plus the file's own tables,
//! which the design copies into the scenario and flight files it writes.

use std::path::Path;

use anyhow::{anyhow, Result};
use controller_core::Vehicle;
use firmware::config::RotorConfig;
use nalgebra::Vector3;

use crate::model::vehicle::VehicleFile;

/// A vehicle as the design sees it.
#[derive(Clone, Debug)]
pub struct DesignVehicle {
    /// Name (`[vehicle] name`).
    pub name: String,
    /// Published source of the values (`[vehicle] source`).
    pub source: String,
    /// Mass \[kg\], inertia diagonal [kg m²] (body), gravity [m/s²], as in the file (f64).
    pub body: Vehicle<f64>,
    /// The rotor set as the firmware's mixer takes it (the firmware's own conversion).
    pub rotors: RotorConfig,
    /// First-order time constant of the rotor speed \[s\].
    pub motor_time_constant_s: f64,
    /// The file's `[vehicle]`, `[rotors]` and `[drag]` tables (copied into outputs).
    pub tables: toml::Table,
    /// The file the vehicle came from (for messages).
    pub origin: String,
}

impl DesignVehicle {
    /// Reads and validates a vehicle file. Errors: `"<file>: <key>: <reason>"`.
    pub fn load(path: &Path) -> Result<Self> {
        let file = crate::model::vehicle::load(path)?;
        Self::from_file(&file, &path.display().to_string())
    }

    /// From a validated vehicle file; `origin` names it in messages.
    /// Errors: the tables cannot be written back as TOML (not expected).
    pub fn from_file(file: &VehicleFile, origin: &str) -> Result<Self> {
        let airframe = crate::model::vehicle::airframe(file);
        let tables = match toml::Value::try_from(file)
            .map_err(|e| anyhow!("{origin}: cannot copy the vehicle tables: {e}"))?
        {
            toml::Value::Table(t) => t,
            _ => toml::Table::new(),
        };
        let v = &file.vehicle;
        Ok(Self {
            name: airframe.name.to_owned(),
            source: airframe.source.to_owned(),
            body: Vehicle {
                mass: v.mass_kg,
                inertia: Vector3::from(v.inertia_kg_m2),
                gravity: v.gravity_m_s2,
            },
            rotors: airframe.rotors,
            motor_time_constant_s: file.rotors.motor_time_constant_s,
            tables,
            origin: origin.to_owned(),
        })
    }
}
