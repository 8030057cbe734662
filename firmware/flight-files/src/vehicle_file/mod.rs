//! Vehicle files (TOML): one quadrotor's rigid body, rotors, motors and body drag, with units in
//! the key names and each value's published source in a comment (format: `docs/vehicles.md`;
//! presets: `host-sim/vehicles/`).
//!
//! ```toml
//! [vehicle]            # name, source, mass_kg, inertia_kg_m2, gravity_m_s2, real_propeller
//! [rotors]             # positions_m, spin, thrust_min_N, thrust_max_N, yaw_torque_per_thrust_m,
//!                      # motor_time_constant_s, thrust_curve_factor, throttle_idle
//! [drag]               # optional: body_drag_N_s2_m2
//! ```
//!
//! Unknown keys are refused, every value is checked (finite, sign, ranges, four rotors, two
//! spinning each way, an invertible mixer, a thrust range above the weight), and every error
//! names the file, the key and the reason ([`VehicleFileError`]).
//!
//! Used by host-sim, by the firmware library (`firmware::vehicle_file`, with its `vehicle-file`
//! feature) and by the firmware's build script, which turns the build's vehicle into Rust
//! source for the firmware crate ([`VehicleFile::to_rust_source`]).

use std::fmt;
use std::format;
use std::path::Path;
use std::string::{String, ToString};
use std::vec::Vec;

use serde::{Deserialize, Serialize};

mod checks;
mod keys;
mod values;

use checks::error;
use keys::{check_keys, key_at};
pub use values::FlightValues;

/// `[vehicle]`: the rigid body, and (in a vehicle file, required there) its name and source.
///
/// The scenario files' `[vehicle]` table is this one too, where `name`, `source` and
/// `real_propeller` are optional.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VehicleTable {
    /// Short name, shown in reports and the firmware's boot banner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Where the numbers come from (publication, model file, commit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Mass `m` \[kg\].
    pub mass_kg: f64,
    /// Diagonal of the inertia `J` [kg m²], body frame.
    pub inertia_kg_m2: [f64; 3],
    /// Gravitational acceleration `g` [m/s²].
    pub gravity_m_s2: f64,
    /// Whether the yaw torque per newton is a real propeller's (`false` only for the paper's
    /// vehicle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub real_propeller: Option<bool>,
}

/// Spin direction of a rotor, seen from above (from +z of the body FLU frame).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Spin {
    /// Clockwise: the reaction torque on the body is counter-clockwise (+z).
    Cw,
    /// Counter-clockwise: the reaction torque on the body is clockwise (−z).
    Ccw,
}

impl Spin {
    /// The firmware's `Rotor::spin`: `+1` counter-clockwise, `−1` clockwise.
    pub fn sign(self) -> f32 {
        match self {
            Spin::Ccw => 1.0,
            Spin::Cw => -1.0,
        }
    }
}

/// `[rotors]`: geometry, thrust range, yaw torque per newton, motor lag and thrust curve.
/// Motor order = mixer order = ESC output order.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct RotorsTable {
    /// Rotor hub positions `(x, y)` \[m\], body FLU (x forward, y left); exactly four.
    pub positions_m: Vec<[f64; 2]>,
    /// Spin of each rotor seen from above, in the order of `positions_m`.
    pub spin: Vec<Spin>,
    /// Smallest thrust of one armed rotor \[N\] (at idle throttle).
    pub thrust_min_N: f64,
    /// Largest thrust of one rotor \[N\] (`k_T ϖ_max²`).
    pub thrust_max_N: f64,
    /// Yaw (drag) torque per newton of thrust, `k_Q / k_T` \[m\].
    pub yaw_torque_per_thrust_m: f64,
    /// First-order time constant of the rotor speed \[s\].
    pub motor_time_constant_s: f64,
    /// Thrust curve factor `k ∈ [0, 1]` (PX4's THR_MDL_FAC): normalised thrust
    /// `k u² + (1 − k) u` of the normalised throttle `u`.
    pub thrust_curve_factor: f64,
    /// Throttle in `[0, 1)` at which an armed motor idles.
    pub throttle_idle: f64,
}

/// `[drag]` (optional): quadratic body drag.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct DragTable {
    /// Coefficients `c_i` [N s²/m²] per body axis: `F_i = −c_i |v_i| v_i` (body frame).
    pub body_drag_N_s2_m2: [f64; 3],
}

/// A whole vehicle file.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VehicleFile {
    /// `[vehicle]`.
    pub vehicle: VehicleTable,
    /// `[rotors]`.
    pub rotors: RotorsTable,
    /// `[drag]`; absent = no body drag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag: Option<DragTable>,
}

/// [`VehicleFile`]'s tables inside a larger file (other tables ignored; see
/// [`VehicleFile::parse_embedded`]).
#[derive(Deserialize)]
struct EmbeddedVehicle {
    vehicle: VehicleTable,
    rotors: RotorsTable,
    #[serde(default)]
    drag: Option<DragTable>,
}

/// A refused vehicle file: which file, which key (dotted, e.g. `rotors.thrust_max_N`, with
/// `[i]` for an array element), and why. Displays as `"<file>: <key>: <reason>"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VehicleFileError {
    /// The file (path or the origin given to [`VehicleFile::parse`]).
    pub file: String,
    /// The key, dotted from the table.
    pub key: String,
    /// What is wrong with it.
    pub reason: String,
}

impl fmt::Display for VehicleFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.key, self.reason)
    }
}

impl std::error::Error for VehicleFileError {}

/// The number of rotors this firmware flies (its mixer inverts a 4×4 effectiveness matrix).
pub const ROTOR_COUNT: usize = 4;

impl VehicleFile {
    /// Reads, parses and validates a vehicle file. Errors: unreadable file (key `(file)`), and
    /// those of [`VehicleFile::parse`].
    pub fn load(path: &Path) -> Result<Self, VehicleFileError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| error(&file, "(file)", format!("cannot read: {e}")))?;
        Self::parse(&text, &file)
    }

    /// Parses and validates vehicle-file text; `origin` names it in errors. Errors: TOML
    /// syntax, an unknown or missing table or key, a wrong type, then
    /// [`VehicleFile::validate`]'s.
    pub fn parse(text: &str, origin: &str) -> Result<Self, VehicleFileError> {
        Self::parse_embedded(text, origin, &[])
    }

    /// [`VehicleFile::parse`] of a file that carries the vehicle's tables among others (a
    /// scenario or flight file): the tables named in `other_tables` are skipped (their own
    /// parser checks them), any other unknown table is refused.
    pub fn parse_embedded(
        text: &str,
        origin: &str,
        other_tables: &[&str],
    ) -> Result<Self, VehicleFileError> {
        let keyed = |e: toml::de::Error| {
            e.span()
                .map_or_else(|| "(file)".to_string(), |s| key_at(text, s.start))
        };
        let table: toml::Table = toml::from_str(text).map_err(|e| {
            let reason = format!("TOML syntax: {}", e.message());
            error(origin, keyed(e), reason)
        })?;
        check_keys(&table, origin, other_tables)?;
        // The top level does not deny unknown tables here: `check_keys` has refused every one
        // not in `other_tables`. Parsing the text (not the table) keeps the spans for errors.
        let file: EmbeddedVehicle = toml::from_str(text).map_err(|e| {
            let reason = e.message().to_string();
            error(origin, keyed(e), reason)
        })?;
        let file = VehicleFile {
            vehicle: file.vehicle,
            rotors: file.rotors,
            drag: file.drag,
        };
        file.validate(origin)?;
        Ok(file)
    }

    /// Checks every value (see [`VehicleTable::validate`] with identity required,
    /// [`RotorsTable::validate`], [`DragTable::validate`]). Errors name `file`, the key and the
    /// reason.
    pub fn validate(&self, file: &str) -> Result<(), VehicleFileError> {
        self.vehicle.validate(file, true)?;
        self.rotors.validate(file, &self.vehicle)?;
        self.drag.as_ref().map_or(Ok(()), |d| d.validate(file))
    }
}
