//! Vehicle files in host-sim: load one, turn it into the firmware's [`Airframe`] (f32, what the
//! flight code and its mixer use) and into the simulators' f64 plant parameters.
//!
//! The format and its checks are the firmware's ([`firmware::vehicle_file`], shared with the
//! firmware build script); see `docs/vehicles.md`. A scenario file may carry the same
//! `[rotors]` and `[drag]` tables; [`crate::scenario::Scenario::with_vehicle`] replaces a
//! scenario's vehicle with a file's.

use std::path::Path;

use anyhow::Result;
use firmware::airframe::Airframe;
pub use firmware::vehicle_file::{
    DragTable, RotorsTable, Spin, VehicleFile, VehicleFileError, VehicleTable, ROTOR_COUNT,
};
use nalgebra::Vector3;

use crate::plant::RigidBody;

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

/// The rotors of a vehicle or scenario file in f64, for the rotor-level plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorPlantParameters {
    /// Hub positions `(x, y)` \[m\], body FLU, in motor order.
    pub positions: [[f64; 2]; ROTOR_COUNT],
    /// `+1` counter-clockwise, `−1` clockwise seen from above (as `firmware::config::Rotor`):
    /// the rotor's drag torque on the body is `−spin · c · f` about body z.
    pub spins: [f64; ROTOR_COUNT],
    /// Per-rotor thrust range \[N\].
    pub thrust_min: f64,
    /// Per-rotor thrust range \[N\].
    pub thrust_max: f64,
    /// Yaw torque per newton of thrust `c = k_Q / k_T` \[m\].
    pub yaw_torque_per_thrust: f64,
    /// First-order time constant of the rotor speed \[s\].
    pub motor_time_constant: f64,
    /// Quadratic body drag `c_i` [N s²/m²] per body axis (`F_i = −c_i |v_i| v_i`).
    pub body_drag: [f64; 3],
}

/// [`RotorPlantParameters`] of validated `[rotors]` and optional `[drag]` tables (four rotors;
/// a missing rotor would read as a zero one).
pub fn plant_parameters(rotors: &RotorsTable, drag: Option<&DragTable>) -> RotorPlantParameters {
    RotorPlantParameters {
        positions: std::array::from_fn(|k| rotors.positions_m.get(k).copied().unwrap_or_default()),
        spins: std::array::from_fn(|k| rotors.spin.get(k).map_or(0.0, |s| f64::from(s.sign()))),
        thrust_min: rotors.thrust_min_N,
        thrust_max: rotors.thrust_max_N,
        yaw_torque_per_thrust: rotors.yaw_torque_per_thrust_m,
        motor_time_constant: rotors.motor_time_constant_s,
        body_drag: drag.map_or([0.0; 3], |d| d.body_drag_N_s2_m2),
    }
}
