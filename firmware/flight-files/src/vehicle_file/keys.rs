//! The tables and keys a vehicle file may have, and errors that name them: serde's messages say
//! neither which table a key belongs to nor which key a TOML error is about.

use std::format;
use std::string::{String, ToString};
use std::vec::Vec;

use super::{error, VehicleFileError};

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

/// Guesses the key a toml error at byte `at` of `text` is about: the `[table]` header above it
/// and the `key =` at the start of its line.
pub(super) fn key_at(text: &str, at: usize) -> String {
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

/// Refuses unknown tables (other than `other_tables`, which are not looked into) and unknown
/// keys, and reports missing ones, naming them with their table (serde's own messages do not
/// say which table).
pub(super) fn check_keys(
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
