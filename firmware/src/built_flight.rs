//! The flight the firmware was built with: `FIRMWARE_FLIGHT_FILE` (default
//! `firmware/flights/x500.toml`), turned into Rust source by `build.rs` (`OUT_DIR/flight.rs`).
//! [`FlightConfig::built`] is what both boards fly; [`FlightConfig::paper`] stays for the
//! paper's tests and the bench fixtures.

use crate::airframe::Airframe;
use crate::config::{FlightConfig, FlightIdentity, ReferenceConfig};
use crate::link::LinkTrust;
use crate::motor_order::MotorOrder;

/// The generated items: `FILE`, `airframe()`, `limits()`, `gains()`, `mission()`, `MARGIN`,
/// `SMOOTHING_RATE`, `CONTROL_RATE`, `THRUST`, `AIRMODE`, `DESIGN`.
// Literals written from a file, not by hand: a value that happens to be π is the file's.
#[allow(clippy::approx_constant, clippy::excessive_precision)]
mod generated {
    include!(concat!(env!("OUT_DIR"), "/flight.rs"));
}

/// The build's MAVLink 2 signing key: env `FIRMWARE_MAVLINK_SIGNING_KEY` at build time, 64 hex
/// digits (unset or empty: no key). Anything else stops the build (a const panic), so a typo
/// never yields an unsigned vehicle that its owner thinks is signed.
pub const SIGNING_KEY: Option<[u8; 32]> = match option_env!("FIRMWARE_MAVLINK_SIGNING_KEY") {
    Some(hex) if !hex.is_empty() => Some(signing_key_from_hex(hex)),
    _ => None,
};

/// Whether a signing build uses unsigned poses and sensor samples: env
/// `FIRMWARE_MAVLINK_UNSIGNED_SENSORS` at build time, `accept` (the default: most motion-capture
/// bridges cannot sign) or `refuse`; anything else stops the build.
pub const ACCEPT_UNSIGNED_SENSORS: bool = match option_env!("FIRMWARE_MAVLINK_UNSIGNED_SENSORS") {
    None => true,
    Some(v) if bytes_eq(v.as_bytes(), b"accept") => true,
    Some(v) if bytes_eq(v.as_bytes(), b"refuse") => false,
    Some(_) => panic!("FIRMWARE_MAVLINK_UNSIGNED_SENSORS must be `accept` or `refuse`"),
};

/// Whether the board's MAVLink link is a wired console only the owner can send on: env
/// `FIRMWARE_MAVLINK_LINK_TRUST` at build time, `untrusted` (the default: a telemetry radio, or
/// any link a stranger may transmit on; `SETUP_SIGNING` then only signed with the key in force)
/// or `trusted` (a cable to the owner's computer: `SETUP_SIGNING` taken unsigned, while
/// disarmed); anything else stops the build. Say `trusted` only for a link that no radio
/// carries: on it, anyone who can send bytes can set the key.
pub const LINK_TRUST: LinkTrust = match option_env!("FIRMWARE_MAVLINK_LINK_TRUST") {
    None => LinkTrust::Untrusted,
    Some(v) if bytes_eq(v.as_bytes(), b"untrusted") => LinkTrust::Untrusted,
    Some(v) if bytes_eq(v.as_bytes(), b"trusted") => LinkTrust::Trusted,
    Some(_) => panic!("FIRMWARE_MAVLINK_LINK_TRUST must be `trusted` or `untrusted`"),
};

const fn bytes_eq(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// 64 hex digits to 32 bytes; anything else panics (at compile time where it is used).
pub const fn signing_key_from_hex(hex: &str) -> [u8; 32] {
    const fn digit(c: u8) -> u8 {
        match c {
            b'0'..=b'9' => c - b'0',
            b'a'..=b'f' => c - b'a' + 10,
            b'A'..=b'F' => c - b'A' + 10,
            _ => panic!("FIRMWARE_MAVLINK_SIGNING_KEY: not a hex digit"),
        }
    }
    let h = hex.as_bytes();
    if h.len() != 64 {
        panic!("FIRMWARE_MAVLINK_SIGNING_KEY must be 64 hex digits (32 bytes)");
    }
    let mut key = [0u8; 32];
    let mut i = 0;
    while i < 32 {
        key[i] = digit(h[2 * i]) * 16 + digit(h[2 * i + 1]);
        i += 1;
    }
    key
}

/// The order of the motor outputs in `HIL_ACTUATOR_CONTROLS`: env `FIRMWARE_HIL_MOTOR_ORDER`
/// at build time, `mixer` (the default: the vehicle file's order), `px4` or `betaflight`;
/// anything else stops the build.
pub const HIL_MOTOR_ORDER: MotorOrder = match option_env!("FIRMWARE_HIL_MOTOR_ORDER") {
    None => MotorOrder::Mixer,
    Some(s) => match MotorOrder::parse(s) {
        Some(o) => o,
        None => panic!("FIRMWARE_HIL_MOTOR_ORDER must be `mixer`, `px4` or `betaflight`"),
    },
};

/// Whether this build may arm an uncertified set-up (cargo feature `uncertified-paper`).
pub const UNCERTIFIED_BUILD: bool = cfg!(feature = "uncertified-paper");

impl FlightConfig {
    /// The build's flight file: its vehicle and rotors, `[limits]`, `[gains]`, the demo mission
    /// (`[trajectory]`), the rotor-fit margin, the thrust and airmode (`[controller]`), the
    /// setpoint filter's bandwidth
    /// (`[design] smoothing_rate_per_s`, 0.5/s if absent), the control law's rate
    /// (`[design] control_rate_hz` or the build's `FIRMWARE_CONTROL_RATE_HZ`, 100 Hz if
    /// neither), the `[design]` fields and the MAVLink signing set-up ([`SIGNING_KEY`],
    /// [`ACCEPT_UNSIGNED_SENSORS`], [`LINK_TRUST`]); safety,
    /// telemetry, estimator and the other reference settings as [`FlightConfig::paper`].
    /// `allow_uncertified` is set only in the `uncertified-paper` build.
    pub fn built() -> Self {
        let a = generated::airframe();
        let paper = Self::paper();
        Self {
            identity: FlightIdentity {
                name: a.name,
                source: a.source,
                file: generated::FILE,
                design: generated::DESIGN,
            },
            mission: generated::mission(),
            box_margin: generated::MARGIN,
            allow_uncertified: UNCERTIFIED_BUILD,
            vehicle: a.vehicle,
            rotors: a.rotors,
            limits: generated::limits(),
            gains: generated::gains(),
            thrust: generated::THRUST,
            airmode: generated::AIRMODE,
            airmode_low_margin: generated::AIRMODE_LOW_MARGIN,
            control_rate: generated::CONTROL_RATE,
            reference: ReferenceConfig {
                smoothing_rate: generated::SMOOTHING_RATE,
                ..paper.reference
            },
            signing_key: SIGNING_KEY,
            link_trust: LINK_TRUST,
            accept_unsigned_sensors: ACCEPT_UNSIGNED_SENSORS,
            hil_motor_order: HIL_MOTOR_ORDER,
            ..paper
        }
    }

    /// The build's airframe (vehicle, rotors, motor time constant, body drag): what host-sim's
    /// software-in-the-loop plant flies with the built firmware.
    pub fn built_airframe() -> Airframe {
        generated::airframe()
    }
}
