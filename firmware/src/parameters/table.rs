//! The tunable parameters of [`FlightConfig`], as the MAVLink parameter protocol exposes them:
//! one table ([`PARAMS`]) of descriptors, each with its name (at most 16 characters, MAVLink's
//! `param_id`), unit, meaning and source, the accepted range, and a getter and a setter on
//! [`FlightConfig`].
//!
//! Every value is `MAV_PARAM_TYPE_REAL32`. The safety timings, stored in microseconds, are
//! exposed in milliseconds: a REAL32 holds every whole millisecond count up to 4.6 hours
//! exactly, whereas microseconds would be rounded beyond 16.7 s.
//!
//! The table checks only what one value can get wrong on its own (finite, in its range) and
//! the orderings between values ([`consistency`]); whether a set-up may fly is the certificate
//! gate's to decide ([`crate::pipeline::gate_check`]), which the pipeline runs on every
//! candidate set-up before it takes a new value.

use crate::config::FlightConfig;
use crate::gate_failure::GateFailure;

/// Longest parameter name: MAVLink's `param_id` is 16 bytes, NUL-padded only when shorter.
pub const NAME_LEN: usize = 16;

/// One parameter: its name, documentation, accepted range and accessors.
#[derive(Clone, Copy)]
pub struct ParamDesc {
    /// MAVLink `param_id`: ASCII, at most [`NAME_LEN`] bytes, PX4/ArduPilot style
    /// (`GROUP_NAME`).
    pub name: &'static str,
    /// Unit of the value as sent (SI, or `ms` for the safety timings; `-` dimensionless).
    pub unit: &'static str,
    /// What it is and where it comes from (the paper's symbol and section, or the config
    /// field).
    pub doc: &'static str,
    /// Smallest accepted value (inclusive), in [`ParamDesc::unit`].
    pub min: f32,
    /// Largest accepted value (inclusive), in [`ParamDesc::unit`].
    pub max: f32,
    /// The value in `config`, in [`ParamDesc::unit`].
    pub get: fn(&FlightConfig) -> f32,
    /// Writes `value` (in [`ParamDesc::unit`], already checked finite and in range) into
    /// `config`.
    pub set: fn(&mut FlightConfig, f32),
}

/// Why a value is refused before any certificate is computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamError {
    /// NaN or infinite.
    NotFinite,
    /// Outside the parameter's `[min, max]`.
    OutOfRange {
        /// [`ParamDesc::min`].
        min: f32,
        /// [`ParamDesc::max`].
        max: f32,
    },
}

impl ParamDesc {
    /// Writes `value` into `config` if it is finite and within `[min, max]`; otherwise leaves
    /// `config` unchanged. Errors: [`ParamError`].
    pub fn apply(&self, config: &mut FlightConfig, value: f32) -> Result<(), ParamError> {
        if !value.is_finite() {
            return Err(ParamError::NotFinite);
        }
        if !(self.min..=self.max).contains(&value) {
            return Err(ParamError::OutOfRange {
                min: self.min,
                max: self.max,
            });
        }
        (self.set)(config, value);
        Ok(())
    }

    /// The name as MAVLink's 16-byte `param_id` (NUL-padded).
    pub fn id(&self) -> [u8; NAME_LEN] {
        let mut id = [0u8; NAME_LEN];
        for (d, s) in id.iter_mut().zip(self.name.bytes()) {
            *d = s;
        }
        id
    }
}

/// One entry per parameter: name, unit, range, the `FlightConfig` field (read and written as
/// is), documentation. Brace-delimited in the table so that it stays one entry per two lines.
macro_rules! field {
    ($name:literal, $unit:literal, $min:expr, $max:expr, $($f:ident).+, $doc:literal) => {
        ParamDesc {
            name: $name,
            unit: $unit,
            doc: $doc,
            min: $min,
            max: $max,
            get: |c| c.$($f).+,
            set: |c, v| c.$($f).+ = v,
        }
    };
}

/// A safety timing stored in µs, sent in ms.
macro_rules! millis {
    ($name:literal, $($f:ident).+, $doc:literal) => {
        ParamDesc {
            name: $name,
            unit: "ms",
            doc: $doc,
            min: 1.0,
            max: 600_000.0,
            get: |c| c.$($f).+ as f32 / 1000.0,
            // The range check keeps the product in 1e3..6e8: exact in u64 after rounding.
            set: |c, v| c.$($f).+ = libm::roundf(v * 1e3) as u64,
        }
    };
}

/// Every parameter, in the order of `PARAM_REQUEST_LIST` (`param_index` is the position here).
/// The ranges are sanity limits against a mistyped value (a gain of 1e6, a negative level);
/// the certificate gate decides what may fly.
pub const PARAMS: &[ParamDesc] = &[
    field! { "POS_KP", "1/s^2", 1e-3, 100.0, gains.position.kp,
    "k_p, position error gain (Table I; Section IV)" },
    field! { "POS_KV", "1/s", 1e-3, 100.0, gains.position.kv,
    "k_v, velocity error gain (Table I; Section IV)" },
    field! { "POS_KF", "1/s", 1e-3, 100.0, gains.position.kf,
    "k_f, output filter bandwidth (Table I; Section IV)" },
    field! { "POS_KS", "1/s", 1e-3, 1000.0, gains.position.ks,
    "k_s, inner filter bandwidth (Table I; Section IV)" },
    field! { "POS_MP", "m/s^2", 1e-3, 20.0, gains.position.saturation,
    "M_p, position saturation level, M_p < g - K_a3 (Table I; Section IV)" },
    field! { "ATT_KTH", "N m", 1e-3, 1000.0, gains.attitude.k_mrp,
    "k_theta, MRP error gain before saturation (Table I; Section V)" },
    field! { "ATT_KW", "N m s/rad", 1e-4, 100.0, gains.attitude.k_omega,
    "k_omega, angular velocity error gain (Table I; Section V)" },
    field! { "ATT_MTH", "N m", 1e-4, 100.0, gains.attitude.mrp_saturation,
    "M_theta, MRP saturation level (Table I; Section V)" },
    field! { "ATT_MW", "N m", 1e-4, 100.0, gains.attitude.omega_saturation,
    "M_omega, angular velocity saturation level (Table I; Section V)" },
    field! { "ATT_HYST", "-", 1e-4, 1.0, gains.hysteresis,
    "delta, hysteresis of the MRP shadow switch (Table I; Appendix)" },
    field! { "ATT_RST_ALPHA", "-", 1e-3, 0.999, gains.reset_threshold,
    "alpha, path-lifting memory reset threshold in (0, 1) (Table I; Appendix)" },
    field! { "LIM_TMAX", "N", 1e-2, 1000.0, limits.thrust_max,
    "T_max, thrust limit the certificate assumes (Section III, Omega_T)" },
    field! { "LIM_TAU_X", "N m", 1e-4, 100.0, limits.torque_max.x,
    "tau_max,1, roll torque limit, body x (Section III, Omega_tau)" },
    field! { "LIM_TAU_Y", "N m", 1e-4, 100.0, limits.torque_max.y,
    "tau_max,2, pitch torque limit, body y (Section III, Omega_tau)" },
    field! { "LIM_TAU_Z", "N m", 1e-4, 100.0, limits.torque_max.z,
    "tau_max,3, yaw torque limit, body z (Section III, Omega_tau)" },
    field! { "REF_SMOOTH", "1/s", 1e-2, 10.0, reference.smoothing_rate,
    "lambda, setpoint filter bandwidth (ReferenceConfig::smoothing_rate)" },
    field! { "REF_TKOFF_H", "m", 1e-2, 100.0, reference.takeoff_height,
    "default takeoff height above the arming point (ReferenceConfig::takeoff_height)" },
    field! { "MIS_SPEED", "m/s", 1e-2, 20.0, reference.mission_speed,
    "peak speed of each leg of an uploaded mission (ReferenceConfig::mission_speed)" },
    field! { "MIS_ACCEL", "m/s^2", 1e-2, 20.0, reference.mission_acceleration,
    "peak acceleration of each mission leg (ReferenceConfig::mission_acceleration)" },
    field! { "MIS_YAW_RATE", "rad/s", 1e-2, 10.0, reference.mission_yaw_rate,
    "peak yaw rate of each mission leg (ReferenceConfig::mission_yaw_rate)" },
    field! { "MIS_ACC_RAD", "m", 1e-2, 10.0, reference.mission_acceptance_radius,
    "waypoint reached within this distance when its item gives none" },
    millis! { "SAF_ARM_AGE", safety.arm_pose_max_age_us,
    "a pose older than this refuses arming (SafetyConfig::arm_pose_max_age_us)" },
    millis! { "SAF_FS_AGE", safety.failsafe_pose_age_us,
    "a pose older than this in flight starts the failsafe (failsafe_pose_age_us)" },
    millis! { "SAF_DISARM_AGE", safety.disarm_pose_age_us,
    "pose lost this long disarms (SafetyConfig::disarm_pose_age_us)" },
];

/// Number of parameters (`param_count`).
pub const COUNT: usize = PARAMS.len();

// `param_index` is a u16 on the wire (and an i16 in PARAM_REQUEST_READ).
const _: () = assert!(COUNT <= i16::MAX as usize);

/// Index of the parameter named by the MAVLink `param_id` `id` (NUL-padded, or exactly 16
/// bytes with no NUL), if any. Exact, case-sensitive match (as PX4 and ArduPilot).
pub fn find(id: &[u8; NAME_LEN]) -> Option<usize> {
    let len = id.iter().position(|&b| b == 0).unwrap_or(NAME_LEN);
    let name = &id[..len];
    PARAMS.iter().position(|p| p.name.as_bytes() == name)
}

/// Condition names of [`consistency`], in the [`GateFailure`] convention (`lhs ≥ rhs` must
/// hold).
pub const TAKEOFF_WITHIN_MAX: &str = "takeoff_height_max";
/// See [`TAKEOFF_WITHIN_MAX`]: the failsafe starts no sooner than arming is refused.
pub const FAILSAFE_AFTER_ARM_AGE: &str = "failsafe_pose_age";
/// See [`TAKEOFF_WITHIN_MAX`]: the failsafe has time to descend before the disarm.
pub const DISARM_AFTER_FAILSAFE: &str = "disarm_pose_age";

/// The orderings between parameters that no single range can express, as a [`GateFailure`]
/// (`lhs ≥ rhs` should hold, `lhs < rhs` found): the default takeoff height within the largest
/// one a command may ask for; arm pose age ≤ failsafe pose age < disarm pose age (a vehicle
/// must not arm on a pose the failsafe would refuse, and the supervisor's failsafe time-out is
/// `disarm − failsafe`, which must stay positive). Values as in the table's units.
pub fn consistency(c: &FlightConfig) -> Result<(), GateFailure> {
    let s = &c.safety;
    let ms = |us: u64| us as f32 / 1000.0;
    let r = &c.reference;
    let checks = [
        (
            TAKEOFF_WITHIN_MAX,
            r.takeoff_height_max,
            r.takeoff_height,
            true,
        ),
        (
            FAILSAFE_AFTER_ARM_AGE,
            ms(s.failsafe_pose_age_us),
            ms(s.arm_pose_max_age_us),
            true,
        ),
        (
            DISARM_AFTER_FAILSAFE,
            ms(s.disarm_pose_age_us),
            ms(s.failsafe_pose_age_us),
            false,
        ),
    ];
    for (condition, lhs, rhs, equal_ok) in checks {
        let holds = if equal_ok { lhs >= rhs } else { lhs > rhs };
        if !holds {
            return Err(GateFailure {
                condition,
                lhs,
                rhs,
            });
        }
    }
    Ok(())
}
