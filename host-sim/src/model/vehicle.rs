//! Vehicle files in host-sim: load one, turn it into the firmware's [`Airframe`] (f32, what the
//! flight code and its mixer use) and into the simulators' f64 plant parameters.
//!
//! The format and its checks are the firmware's ([`firmware::vehicle_file`], shared with the
//! firmware build script); see `docs/vehicles.md`. A scenario file may carry the same
//! `[rotors]` and `[drag]` tables; [`crate::model::scenario::Scenario::with_vehicle`] replaces a
//! scenario's vehicle with a file's.

use std::path::Path;

use anyhow::Result;
use firmware::airframe::Airframe;
pub use firmware::vehicle_file::{
    DragTable, RotorsTable, Spin, VehicleFile, VehicleFileError, VehicleTable, ROTOR_COUNT,
};
use nalgebra::Vector3;

use crate::model::plant::RigidBody;

/// The preset vehicle files shipped in `host-sim/vehicles/`, by file stem.
pub const PRESETS: [&str; 4] = ["paper", "crazyflie-2.1", "hummingbird", "x500"];

/// The path of a preset vehicle file (`host-sim/vehicles/<name>.toml` of this source tree).
pub fn preset_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("vehicles")
        .join(format!("{name}.toml"))
}

/// Reads, parses and validates a vehicle file. Errors: `"<file>: <key>: <reason>"`
/// ([`VehicleFileError`]).
pub fn load(path: &Path) -> Result<VehicleFile> {
    Ok(VehicleFile::load(path)?)
}

/// The firmware's airframe of a (validated) vehicle file: the same f32 values the firmware
/// build generates from it. Leaks the name and source strings once per call.
pub fn airframe(file: &VehicleFile) -> Airframe {
    Airframe::from_vehicle_file(file)
}

/// The rigid body of a `[vehicle]` table (f64).
pub fn rigid_body(vehicle: &VehicleTable) -> RigidBody {
    RigidBody {
        mass: vehicle.mass_kg,
        inertia: Vector3::from(vehicle.inertia_kg_m2),
        gravity: vehicle.gravity_m_s2,
    }
}
