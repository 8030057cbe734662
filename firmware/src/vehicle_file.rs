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
//! This file is compiled twice: as `firmware::vehicle_file` (feature `vehicle-file`, which
//! brings std, serde and toml) and by `firmware/build.rs` with `#[path]`, which turns the
//! build's vehicle into Rust source ([`VehicleFile::to_rust_source`]). So it names nothing of
//! the firmware crate (no `crate::` paths) and uses only std, serde and toml.

use std::fmt;
use std::format;
use std::path::Path;
use std::string::{String, ToString};
use std::vec::Vec;

use serde::{Deserialize, Serialize};

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

/// Keys of each table (all required in a vehicle file). The serde structs above are the types;
/// these lists only let the errors name a missing or unknown key with its table (a test checks
/// they match the structs).
const VEHICLE_KEYS: &[&str] = &[
    "name",
    "source",
    "mass_kg",
    "inertia_kg_m2",
    "gravity_m_s2",
    "real_propeller",
];
const ROTORS_KEYS: &[&str] = &[
    "positions_m",
    "spin",
    "thrust_min_N",
    "thrust_max_N",
    "yaw_torque_per_thrust_m",
    "motor_time_constant_s",
    "thrust_curve_factor",
    "throttle_idle",
];
const DRAG_KEYS: &[&str] = &["body_drag_N_s2_m2"];
/// `(table, its keys, required)`.
const TABLES: &[(&str, &[&str], bool)] = &[
    ("vehicle", VEHICLE_KEYS, true),
    ("rotors", ROTORS_KEYS, true),
    ("drag", DRAG_KEYS, false),
];

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

fn error(file: &str, key: impl Into<String>, reason: impl Into<String>) -> VehicleFileError {
    VehicleFileError {
        file: file.to_string(),
        key: key.into(),
        reason: reason.into(),
    }
}

/// A value that must be finite and `> 0` (`positive`) or `≥ 0` (not), in f32 too.
fn check_sign(file: &str, key: &str, v: f64, positive: bool) -> Result<(), VehicleFileError> {
    if !v.is_finite() {
        return Err(error(file, key, format!("must be finite, got {v}")));
    }
    if v < 0.0 {
        return Err(error(file, key, format!("must not be negative, got {v}")));
    }
    if positive && v == 0.0 {
        return Err(error(file, key, "must be > 0, got 0"));
    }
    // The firmware flies f32: the value must survive the conversion.
    let single = v as f32;
    if single.is_infinite() || (positive && single == 0.0) {
        return Err(error(
            file,
            key,
            format!("out of the firmware's f32 range, got {v}"),
        ));
    }
    Ok(())
}

/// [`check_sign`] on each element, naming it `key[i]`.
fn check_signs(file: &str, key: &str, v: &[f64], positive: bool) -> Result<(), VehicleFileError> {
    v.iter()
        .enumerate()
        .try_for_each(|(i, &x)| check_sign(file, &format!("{key}[{i}]"), x, positive))
}

/// A value that must be finite and in `[lo, hi]` (`hi` excluded when `hi_open`).
fn check_range(
    file: &str,
    key: &str,
    v: f64,
    lo: f64,
    hi: f64,
    hi_open: bool,
) -> Result<(), VehicleFileError> {
    let above = if hi_open { v >= hi } else { v > hi };
    if !v.is_finite() {
        Err(error(file, key, format!("must be finite, got {v}")))
    } else if v < lo || above {
        let close = if hi_open { ")" } else { "]" };
        Err(error(
            file,
            key,
            format!("must be in [{lo}, {hi}{close}, got {v}"),
        ))
    } else {
        Ok(())
    }
}

/// Rank test of the 4×4 effectiveness matrix `B` (rows T, τx, τy, τz per newton of each rotor,
/// as the firmware's mixer builds it), each row scaled to its largest entry so the tolerance
/// does not depend on the vehicle's size: `true` when `B` is invertible.
fn geometry_invertible(positions: &[[f64; 2]], spin: &[Spin], yaw_ratio: f64) -> bool {
    let mut b = [[0.0f64; ROTOR_COUNT]; ROTOR_COUNT];
    for (k, (p, s)) in positions.iter().zip(spin).enumerate() {
        b[0][k] = 1.0;
        b[1][k] = p[1];
        b[2][k] = -p[0];
        b[3][k] = -f64::from(s.sign()) * yaw_ratio;
    }
    for row in &mut b {
        let scale = row.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return false;
        }
        row.iter_mut().for_each(|x| *x /= scale);
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..ROTOR_COUNT {
        let pivot = (col..ROTOR_COUNT)
            .max_by(|&i, &j| b[i][col].abs().total_cmp(&b[j][col].abs()))
            .unwrap_or(col);
        if b[pivot][col].abs() < 1e-9 {
            return false;
        }
        b.swap(col, pivot);
        let (done, rest) = b.split_at_mut(col + 1);
        let top = done[col];
        for row in rest {
            let f = row[col] / top[col];
            row.iter_mut().zip(top).for_each(|(x, t)| *x -= f * t);
        }
    }
    true
}

/// Guesses the key a toml error at byte `at` of `text` is about: the `[table]` header above it
/// and the `key =` at the start of its line.
fn key_at(text: &str, at: usize) -> String {
    let before = text.get(..at).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = &before[line_start..];
    let key = line.split('=').next().unwrap_or("").trim();
    let table = before[..line_start].lines().rev().find_map(table_header);
    match (table, key.is_empty() || !line.contains('=')) {
        (Some(t), false) => format!("{t}.{key}"),
        (Some(t), true) => t.to_string(),
        (None, false) => key.to_string(),
        (None, true) => "(file)".to_string(),
    }
}

/// The name of a `[table]` header line (not an array row such as `[0.1, 0.2],`).
fn table_header(line: &str) -> Option<&str> {
    let line = line.split('#').next().unwrap_or("").trim();
    let inner = line.strip_prefix('[')?.strip_suffix(']')?.trim();
    let is_name = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.');
    (!inner.is_empty() && inner.chars().all(is_name)).then_some(inner)
}

impl VehicleTable {
    /// Checks the rigid body (and, when `identity`, that name and source are given and not
    /// empty and `real_propeller` is stated, as a vehicle file must). Errors name `file`, the
    /// key and the reason.
    pub fn validate(&self, file: &str, identity: bool) -> Result<(), VehicleFileError> {
        if identity {
            for (key, v) in [
                ("vehicle.name", &self.name),
                ("vehicle.source", &self.source),
            ] {
                match v {
                    None => return Err(error(file, key, "missing")),
                    Some(s) if s.trim().is_empty() => {
                        return Err(error(file, key, "must not be empty"))
                    }
                    Some(_) => {}
                }
            }
            if self.real_propeller.is_none() {
                return Err(error(file, "vehicle.real_propeller", "missing"));
            }
        }
        check_sign(file, "vehicle.mass_kg", self.mass_kg, true)?;
        check_signs(file, "vehicle.inertia_kg_m2", &self.inertia_kg_m2, true)?;
        check_sign(file, "vehicle.gravity_m_s2", self.gravity_m_s2, true)
    }
}

impl RotorsTable {
    /// Checks the rotors on their own (counts, spins, signs, ranges, an invertible mixer) and
    /// against the rigid body (`4 thrust_max_N > m g`, or the vehicle cannot hover). Errors
    /// name `file`, the key and the reason.
    pub fn validate(&self, file: &str, vehicle: &VehicleTable) -> Result<(), VehicleFileError> {
        if self.positions_m.len() != ROTOR_COUNT {
            return Err(error(
                file,
                "rotors.positions_m",
                format!(
                    "{} rotors given; exactly {ROTOR_COUNT} (a quadrotor) are supported",
                    self.positions_m.len()
                ),
            ));
        }
        for (i, p) in self.positions_m.iter().enumerate() {
            if !p.iter().all(|x| x.is_finite()) {
                return Err(error(
                    file,
                    format!("rotors.positions_m[{i}]"),
                    format!("must be finite, got {p:?}"),
                ));
            }
        }
        if self.spin.len() != ROTOR_COUNT {
            return Err(error(
                file,
                "rotors.spin",
                format!(
                    "{} spins given; one per rotor ({ROTOR_COUNT}) is needed",
                    self.spin.len()
                ),
            ));
        }
        let ccw = self.spin.iter().filter(|s| **s == Spin::Ccw).count();
        if ccw != ROTOR_COUNT / 2 {
            return Err(error(
                file,
                "rotors.spin",
                format!(
                    "must be two \"cw\" and two \"ccw\" (the yaw torques must cancel at \
                     hover), got {ccw} ccw"
                ),
            ));
        }
        check_sign(file, "rotors.thrust_min_N", self.thrust_min_N, false)?;
        check_sign(file, "rotors.thrust_max_N", self.thrust_max_N, true)?;
        if self.thrust_max_N <= self.thrust_min_N {
            return Err(error(
                file,
                "rotors.thrust_max_N",
                format!(
                    "thrust range empty: thrust_max_N = {} N is not above thrust_min_N = {} N",
                    self.thrust_max_N, self.thrust_min_N
                ),
            ));
        }
        check_sign(
            file,
            "rotors.yaw_torque_per_thrust_m",
            self.yaw_torque_per_thrust_m,
            true,
        )?;
        check_sign(
            file,
            "rotors.motor_time_constant_s",
            self.motor_time_constant_s,
            true,
        )?;
        check_range(
            file,
            "rotors.thrust_curve_factor",
            self.thrust_curve_factor,
            0.0,
            1.0,
            false,
        )?;
        check_range(
            file,
            "rotors.throttle_idle",
            self.throttle_idle,
            0.0,
            1.0,
            true,
        )?;
        if !geometry_invertible(&self.positions_m, &self.spin, self.yaw_torque_per_thrust_m) {
            return Err(error(
                file,
                "rotors.positions_m",
                "singular geometry: these positions and spins cannot produce thrust, roll, \
                 pitch and yaw independently (the mixer cannot be inverted)",
            ));
        }
        let weight = vehicle.mass_kg * vehicle.gravity_m_s2;
        let most = ROTOR_COUNT as f64 * self.thrust_max_N;
        if most <= weight {
            return Err(error(
                file,
                "rotors.thrust_max_N",
                format!(
                    "cannot hover: {ROTOR_COUNT} x thrust_max_N = {most} N is not above the \
                     weight m g = {weight} N"
                ),
            ));
        }
        Ok(())
    }
}

impl DragTable {
    /// Checks the coefficients: finite and not negative.
    pub fn validate(&self, file: &str) -> Result<(), VehicleFileError> {
        check_signs(
            file,
            "drag.body_drag_N_s2_m2",
            &self.body_drag_N_s2_m2,
            false,
        )
    }
}

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

/// Refuses unknown tables (other than `other_tables`, which are not looked into) and unknown
/// keys, and reports missing ones, naming them with their table (serde's own messages do not
/// say which table).
fn check_keys(
    table: &toml::Table,
    file: &str,
    other_tables: &[&str],
) -> Result<(), VehicleFileError> {
    for (name, value) in table {
        if other_tables.contains(&name.as_str()) {
            continue;
        }
        let Some((_, keys, _)) = TABLES.iter().find(|(t, _, _)| t == name) else {
            let mut known: Vec<&str> = TABLES.iter().map(|(t, _, _)| *t).collect();
            known.extend(other_tables);
            return Err(error(
                file,
                name.as_str(),
                format!("unknown key (tables: {})", known.join(", ")),
            ));
        };
        let Some(inner) = value.as_table() else {
            return Err(error(file, name.as_str(), "must be a table"));
        };
        for key in inner.keys() {
            if !keys.contains(&key.as_str()) {
                return Err(error(
                    file,
                    format!("{name}.{key}"),
                    format!("unknown key (known: {})", keys.join(", ")),
                ));
            }
        }
        if let Some(missing) = keys.iter().find(|k| !inner.contains_key(**k)) {
            return Err(error(file, format!("{name}.{missing}"), "missing"));
        }
    }
    if let Some((missing, _, _)) = TABLES
        .iter()
        .find(|(t, _, required)| *required && !table.contains_key(*t))
    {
        return Err(error(file, format!("[{missing}]"), "missing table"));
    }
    Ok(())
}
