//! The build's flight file (`FIRMWARE_FLIGHT_FILE`, default `firmware/flights/x500.toml`):
//! the vehicle file tables (`[vehicle]`, `[rotors]`, optional `[drag]`, parsed and checked by
//! the shared `vehicle_file` module) plus `[limits]`, `[gains]`, `[trajectory]` (the certified
//! demo mission; the scenario files' tables, from the shared `flight_tables` module) and
//! `[design]` (free-text fields, the box-fit `margin`, `smoothing_rate_per_s` and
//! `control_rate_hz`, which env `FIRMWARE_CONTROL_RATE_HZ` overrides) and an optional
//! `[controller]` (the thrust: `thrust = "norm"`, the default, or `"vertical-priority"` with
//! `thrust_ramp` and `thrust_floor_N`; docs/no-dive-thrust.md; and `airmode = true`, keeping
//! `[design] margin` free, docs/airmode.md).
//! Written to `OUT_DIR/flight.rs` as Rust source, which `src/built_flight.rs` includes.
//!
//! Every error panics with the file, the key and the reason: a build must not quietly fly
//! something else than the file it was given.

use std::collections::BTreeMap;
use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::control_rate::ControlRate;
use crate::flight_tables::{GainsTable, LimitsTable, TiltPriorityTable, TrajectoryTable};
use crate::vehicle_file::VehicleFile;

mod source;
use source::*;

/// The least `[controller] airmode_low_margin` a flight or scenario file may give (fraction of
/// each rotor's thrust range): a thousandth, so airmode brings a rotor down to its idle but
/// never exactly onto it, where the f32 mixer's rounding (about 10⁻⁶ of the range) would clip
/// it and give a trace of the torque up.
pub const AIRMODE_LEAST_LOW_MARGIN: f64 = 1e-3;

/// The environment variable naming the flight file.
const ENV: &str = "FIRMWARE_FLIGHT_FILE";

/// The environment variable that overrides the flight file's `[design] control_rate_hz`.
const RATE_ENV: &str = "FIRMWARE_CONTROL_RATE_HZ";

/// The flight file's own tables; `[design]` is free text except `margin`,
/// `smoothing_rate_per_s` and `control_rate_hz` (numbers).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FlightTables {
    limits: LimitsTable,
    gains: GainsTable,
    trajectory: TrajectoryTable,
    #[serde(default)]
    design: BTreeMap<String, toml::Value>,
    #[serde(default)]
    controller: Option<ControllerTable>,
}

/// `[controller]`: how the thrust is computed from `u`, and airmode (the scenario files' keys).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct ControllerTable {
    /// `"norm"` (absent: the paper's `T = m|u|`) or `"vertical-priority"`.
    #[serde(default)]
    thrust: Option<String>,
    #[serde(default)]
    thrust_ramp: Option<f64>,
    #[serde(default)]
    thrust_floor_N: Option<f64>,
    /// Airmode (absent: off; docs/airmode.md).
    #[serde(default)]
    airmode: Option<bool>,
    /// The margin airmode keeps free: a scenario's key, accepted only with `airmode = true` and
    /// equal to `[design] margin`, which is what the firmware keeps free (so that a design's
    /// `[controller]` table reads here as in its scenario).
    #[serde(default)]
    airmode_margin: Option<f64>,
    /// The margin airmode keeps free above the rotors' least thrust, in `[0, [design] margin]`
    /// (absent: `[design] margin`, the same at both ends; docs/airmode.md).
    #[serde(default)]
    airmode_low_margin: Option<f64>,
}

/// Vertical priority's ramp `b₀` when `[controller]` gives none (the scenario files' default).
const DEFAULT_THRUST_RAMP: f64 = 0.2;

/// The box-fit margin when `[design]` has none: 5 % of each rotor's thrust range.
const DEFAULT_MARGIN: f64 = 0.05;

/// The setpoint filter's bandwidth λ [1/s] when `[design]` has no `smoothing_rate_per_s`:
/// the filter's Assumption 1 constants grow as λ³ (jerk) and λ⁴ (snap), and Theorem 2's
/// torque bound with them, so a slow filter is what an unknown design can most likely certify
/// for setpoints of a metre or so (the gate refuses what it cannot).
const DEFAULT_SMOOTHING_RATE: f64 = 0.5;

/// The control law's rate: env [`RATE_ENV`] if set, else the flight file's
/// `[design] control_rate_hz` (a number), else 100 Hz. Anything but 100, 250, 500 or 1000 Hz
/// fails the build with the source and the allowed rates.
fn control_rate(file: &str, key: Option<toml::Value>) -> ControlRate {
    println!("cargo:rerun-if-env-changed={RATE_ENV}");
    if let Some(v) = env::var_os(RATE_ENV) {
        let text = v.to_string_lossy();
        return text
            .trim()
            .parse::<f64>()
            .map_err(|e| format!("{text:?} is not a number: {e}"))
            .and_then(|hz| ControlRate::from_hz(hz).map_err(|e| e.to_string()))
            .unwrap_or_else(|e| panic!("env {RATE_ENV}: {e}"));
    }
    match key {
        None => ControlRate::default(),
        Some(v) => design_number(&v)
            .ok_or_else(|| format!("{v} is not a number [Hz]"))
            .and_then(|hz| ControlRate::from_hz(hz).map_err(|e| e.to_string()))
            .unwrap_or_else(|e| fail(file, "design.control_rate_hz", e)),
    }
}

/// A `[design]` number: a TOML float or integer (a string is refused, not parsed).
fn design_number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// A `[design]` value as banner text (strings unquoted).
fn design_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Reads the build's flight file and writes `OUT_DIR/flight.rs`.
pub fn write(manifest_dir: &Path, out_dir: &Path) {
    println!("cargo:rerun-if-env-changed={ENV}");
    let (path, shown) = match env::var_os(ENV) {
        Some(p) => {
            let p = PathBuf::from(p);
            let shown = p.display().to_string();
            // A relative path is taken from the workspace root (where `cargo` is usually run)
            // if it exists there, else from the firmware crate.
            let abs = if p.is_absolute() {
                p
            } else {
                let root = manifest_dir.join("..").join(&p);
                if root.exists() {
                    root
                } else {
                    manifest_dir.join(&p)
                }
            };
            (abs, shown)
        }
        None => (
            manifest_dir.join("flights").join("x500.toml"),
            "firmware/flights/x500.toml".to_string(),
        ),
    };
    println!("cargo:rerun-if-changed={}", path.display());
    let file = shown.as_str();
    let text = fs::read_to_string(&path).unwrap_or_else(|e| {
        fail(
            file,
            "(file)",
            format!("cannot read {}: {e}", path.display()),
        )
    });
    let mut table: toml::Table = text
        .parse()
        .unwrap_or_else(|e| fail(file, "(file)", format!("not valid TOML: {e}")));

    // The vehicle file tables, checked by the shared parser (which skips the flight file's own
    // tables and refuses any other); then the flight file's own tables.
    const OWN: [&str; 5] = ["limits", "gains", "trajectory", "design", "controller"];
    let vehicle = VehicleFile::parse_embedded(&text, file, &OWN).unwrap_or_else(|e| panic!("{e}"));
    let mut own = toml::Table::new();
    for key in OWN {
        if let Some(v) = table.remove(key) {
            own.insert(key.to_string(), v);
        }
    }
    let tables: FlightTables = own.try_into().unwrap_or_else(|e: toml::de::Error| {
        fail(
            file,
            "[limits]/[gains]/[trajectory]/[design]/[controller]",
            e.message(),
        )
    });

    let uncertified_feature = env::var_os("CARGO_FEATURE_UNCERTIFIED_PAPER").is_some();
    if !vehicle.vehicle.real_propeller.unwrap_or(true) && !uncertified_feature {
        panic!(
            "flight file {file}: [vehicle] real_propeller = false: this is the paper's set-up, \
             whose certificate fails (Theorem 2, yaw) and whose (T, tau) box does not fit its \
             rotors; the firmware flies only certified set-ups. Build it only for study, with \
             `--features uncertified-paper` (it then arms with a loud warning)."
        );
    }

    let l = &tables.limits;
    finite(file, "limits.torque_max_Nm", &l.torque_max_Nm);
    finite(file, "limits.thrust_max_N", &[l.thrust_max_N]);
    let g = &tables.gains;
    finite(
        file,
        "gains",
        &[
            g.kp, g.kv, g.kf, g.ks, g.k_theta, g.k_omega, g.M_p, g.M_theta, g.M_omega, g.delta,
            g.alpha,
        ],
    );
    if let Some(i) = &g.integral {
        finite(file, "gains.integral.M_i_m_s2", &i.M_i_m_s2);
        finite(file, "gains.integral.rate_m_s3", &i.rate_m_s3);
        finite(file, "gains.integral", &[i.k_i, i.k_eta]);
        if let Some(f) = &i.feedforward_scale {
            finite(
                file,
                "gains.integral.feedforward_scale",
                &[
                    f.gain_1_s,
                    f.excitation_m_s2,
                    f.level,
                    f.rate_1_s,
                    f.tracking_limit_m,
                ],
            );
        }
    }
    let mut design = tables.design;
    let margin = match design.remove("margin") {
        None => DEFAULT_MARGIN,
        Some(v) => match design_number(&v) {
            Some(m) if m.is_finite() && (0.0..1.0).contains(&m) => m,
            _ => fail(
                file,
                "design.margin",
                format!("{v} is not a fraction of the rotor range in [0, 1)"),
            ),
        },
    };
    let smoothing = match design.remove("smoothing_rate_per_s") {
        None => DEFAULT_SMOOTHING_RATE,
        Some(v) => match design_number(&v) {
            Some(x) if x.is_finite() && x > 0.0 => x,
            _ => fail(
                file,
                "design.smoothing_rate_per_s",
                format!("{v} is not a finite bandwidth > 0 [1/s]"),
            ),
        },
    };
    let rate = control_rate(file, design.remove("control_rate_hz"));
    let fields: Vec<String> = design
        .iter()
        .map(|(k, v)| {
            format!(
                "crate::config::DesignField {{ key: {k:?}, value: {:?} }}",
                design_text(v)
            )
        })
        .collect();

    let mut code = String::new();
    let w = &mut code;
    let mut put = |s: String| writeln!(w, "{s}").expect("writing to a String never fails");
    put(format!(
        "// Generated by firmware/build.rs from the flight file {file}. Do not edit."
    ));
    put(format!(
        "/// The flight file as given to the build.\npub(crate) const FILE: &str = {file:?};"
    ));
    put(format!(
        "/// The vehicle, rotors and motors of the flight file.\n\
         pub(crate) fn airframe() -> crate::airframe::Airframe {{\n{}\n}}",
        vehicle.to_rust_source()
    ));
    put(format!(
        "/// `[limits]`.\npub(crate) fn limits() -> controller_core::Limits<f32> {{\n    \
         controller_core::Limits {{ thrust_max: {}, torque_max: {} }}\n}}",
        lit(l.thrust_max_N),
        vec3(l.torque_max_Nm)
    ));
    put(format!(
        "/// `[gains]` (Table I names).\npub(crate) fn gains() -> controller_core::Gains<f32> {{\n    \
         controller_core::Gains {{\n        \
         position: controller_core::position::PositionGains {{ kp: {}, kv: {}, kf: {}, ks: {}, saturation: {}, saturation_shape: controller_core::PositionSaturation::{:?}, vertical: {} }},\n        \
         attitude: controller_core::attitude_control::AttitudeGains {{ k_mrp: {}, k_omega: {}, mrp_saturation: {}, omega_saturation: {} }},\n        \
         hysteresis: {},\n        reset_threshold: {},\n        integral: {},\n        tilt_priority: {},\n        velocity_limit: {},\n        lemma1: controller_core::Lemma1Form::{:?},\n        local: {},\n        heading_compensator: {},\n    }}\n}}",
        lit(g.kp),
        lit(g.kv),
        lit(g.kf),
        lit(g.ks),
        lit(g.M_p),
        g.position_saturation,
        // `[gains.vertical]` (absent = None, the paper's one level on every axis).
        g.vertical.map_or("None".to_string(), |v| format!(
            "Some(controller_core::VerticalChannel {{ up: {}, down: {}, kf: {}, ks: {} }})",
            lit(v.up_m_s2),
            lit(v.down_m_s2),
            lit(v.kf),
            lit(v.ks)
        )),
        lit(g.k_theta),
        lit(g.k_omega),
        lit(g.M_theta),
        lit(g.M_omega),
        lit(g.delta),
        lit(g.alpha),
        // `[gains.integral]` (absent = None, the paper's law).
        match &g.integral {
            None => "None".to_string(),
            Some(i) => format!(
                "Some(controller_core::IntegralGains {{ gain: {}, level: {}, rate: {}, bandwidth: {}, observer: {}, feedforward_scale: {} }})",
                lit(i.k_i),
                vec3(i.M_i_m_s2),
                vec3(i.rate_m_s3),
                lit(i.k_eta),
                i.observer.map_or("None".to_string(), |o| format!(
                    "Some(controller_core::ObserverGains {{ velocity_gain: {}, disturbance_gain: {}, error_limit: {} }})",
                    lit(o.velocity_gain_1_s),
                    lit(o.disturbance_gain_1_s2),
                    lit(o.error_limit_m)
                )),
                i.feedforward_scale.map_or("None".to_string(), |f| format!(
                    "Some(controller_core::FeedforwardScaleGains {{ gain: {}, excitation: {}, level: {}, rate: {}, tracking_limit: {} }})",
                    lit(f.gain_1_s),
                    lit(f.excitation_m_s2),
                    lit(f.level),
                    lit(f.rate_1_s),
                    lit(f.tracking_limit_m)
                ))
            ),
        },
        // `[gains.tilt_priority]` (absent = None, the paper's radial feedback).
        g.tilt_priority.as_ref().map_or("None".to_string(), tilt_priority_source),
        // `[gains.velocity_limit]` (absent = None, the paper's position feedback).
        g.velocity_limit.map_or("None".to_string(), |v| format!(
            "Some(controller_core::VelocityLimit {{ speed: {}, braking: {}, vertical: {} }})",
            lit(v.speed_m_s),
            lit(v.braking_m_s2),
            v.vertical_braking().map_or("None".to_string(), |(up, down)| format!(
                "Some(controller_core::VerticalBraking {{ up: {}, down: {} }})",
                lit(up),
                lit(down)
            ))
        )),
        // `[gains] lemma1` (absent = the paper's chain); the variant names match.
        g.lemma1,
        // `[gains.local]` (absent = None, one set of position gains).
        g.local.map_or("None".to_string(), |l| format!(
            "Some(controller_core::LocalGains {{ kp: {}, kv: {}, kf: {}, ks: {}, saturation: {}, energy_in: {}, energy_out: {}, vertical: {}, attitude: {}, braking: {} }})",
            lit(l.kp),
            lit(l.kv),
            lit(l.kf),
            lit(l.ks),
            lit(l.M_p_m_s2),
            lit(l.energy_in_J),
            lit(l.energy_out_J),
            l.vertical.map_or("None".to_string(), |v| {
                let (up, down) = v.levels(g.vertical.as_ref());
                format!(
                    "Some(controller_core::VerticalChannel {{ up: {}, down: {}, kf: {}, ks: {} }})",
                    lit(up),
                    lit(down),
                    lit(v.kf),
                    lit(v.ks)
                )
            }),
            // `[gains.local.attitude]` (absent = None, the global law in both regimes).
            l.attitude.as_ref().map_or("None".to_string(), |a| format!(
                "Some(controller_core::LocalAttitude {{ attitude: controller_core::attitude_control::AttitudeGains {{ k_mrp: {}, k_omega: {}, mrp_saturation: {}, omega_saturation: {} }}, tilt_priority: {} }})",
                lit(a.k_theta),
                lit(a.k_omega),
                lit(a.M_theta),
                lit(a.M_omega),
                a.tilt_priority.as_ref().map_or("None".to_string(), tilt_priority_source)
            )),
            l.braking_m_s2
                .map_or("None".to_string(), |b| format!("Some({})", lit(b)))
        )),
        // `[gains.heading_compensator]` (absent = None, the reference heading).
        g.heading_compensator.map_or("None".to_string(), |h| format!(
            "Some(controller_core::HeadingCompensatorGains {{ level: {}, gain: {} }})",
            lit(h.level_rad_s),
            lit(h.gain_1_s)
        ))
    ));
    put(format!(
        "/// `[trajectory]`: the demo mission.\n\
         pub(crate) fn mission() -> controller_core::ReferenceTrajectory<f32> {{\n    {}\n}}",
        trajectory_source(file, &tables.trajectory)
    ));
    put(format!(
        "/// `[design] margin`: required box-fit headroom, fraction of the rotor range.\n\
         pub(crate) const MARGIN: f32 = {};",
        lit(margin)
    ));
    put(format!(
        "/// `[design] smoothing_rate_per_s`: the setpoint filter's bandwidth λ [1/s].\n\
         pub(crate) const SMOOTHING_RATE: f32 = {};",
        lit(smoothing)
    ));
    put(format!(
        "/// `[design] control_rate_hz` or `{RATE_ENV}`: the control law's rate.\n\
         pub(crate) const CONTROL_RATE: crate::control_rate::ControlRate = \
         crate::control_rate::ControlRate::{rate:?};"
    ));
    put(format!(
        "/// `[controller]`: the thrust.\n\
         pub(crate) const THRUST: crate::config::ThrustChoice = {};",
        thrust_source(file, tables.controller.as_ref())
    ));
    put(format!(
        "/// `[controller] airmode`: airmode on, keeping `MARGIN` of each rotor's range free.\n\
         pub(crate) const AIRMODE: bool = {};",
        airmode_source(file, tables.controller.as_ref(), margin)
    ));
    put(format!(
        "/// `[controller] airmode_low_margin`: the margin airmode keeps free above the rotors' \
         least thrust (`MARGIN` when absent).\n\
         pub(crate) const AIRMODE_LOW_MARGIN: f32 = {};",
        lit(airmode_low_margin_source(
            file,
            tables.controller.as_ref(),
            margin
        ))
    ));
    put(format!(
        "/// The other `[design]` fields, in key order.\n\
         pub(crate) const DESIGN: &[crate::config::DesignField] = &[{}];",
        fields.join(", ")
    ));
    let dest = out_dir.join("flight.rs");
    fs::write(&dest, code).unwrap_or_else(|e| panic!("cannot write {}: {e}", dest.display()));
}

/// Rust source of a `[gains.tilt_priority]` table (or the local law's): a
/// `Some(controller_core::TiltPriorityGains { .. })` expression.
fn tilt_priority_source(t: &TiltPriorityTable) -> String {
    format!(
        "Some(controller_core::TiltPriorityGains {{ trace_weights: {}, omega_gains: {}, omega_levels: {}, turn_over: {} }})",
        vec3(t.trace_weights_Nm),
        vec3(t.omega_gains_Nm_s),
        vec3(t.omega_levels_Nm),
        t.turn_over().map_or("None".to_string(), |(level, onset)| format!(
            "Some(controller_core::TurnOver {{ level: {}, onset: {} }})",
            lit(level),
            lit(onset)
        ))
    )
}
