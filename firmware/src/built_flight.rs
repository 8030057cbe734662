//! The flight the firmware was built with: `FIRMWARE_FLIGHT_FILE` (default
//! `firmware/flights/x500.toml`), turned into Rust source by `build.rs` (`OUT_DIR/flight.rs`).
//! [`FlightConfig::built`] is what both boards fly; [`FlightConfig::paper`] stays for the
//! paper's tests and the bench fixtures.

use crate::airframe::Airframe;
use crate::config::{FlightConfig, FlightIdentity, ReferenceConfig};

/// The generated items: `FILE`, `airframe()`, `limits()`, `gains()`, `mission()`, `MARGIN`,
/// `SMOOTHING_RATE`, `CONTROL_RATE`, `DESIGN`.
// Literals written from a file, not by hand: a value that happens to be π is the file's.
#[allow(clippy::approx_constant, clippy::excessive_precision)]
mod generated {
    include!(concat!(env!("OUT_DIR"), "/flight.rs"));
}

/// Whether this build may arm an uncertified set-up (cargo feature `uncertified-paper`).
pub const UNCERTIFIED_BUILD: bool = cfg!(feature = "uncertified-paper");

impl FlightConfig {
    /// The build's flight file: its vehicle and rotors, `[limits]`, `[gains]`, the demo mission
    /// (`[trajectory]`), the box-fit margin, the setpoint filter's bandwidth
    /// (`[design] smoothing_rate_per_s`, 0.5/s if absent), the control law's rate
    /// (`[design] control_rate_hz` or the build's `FIRMWARE_CONTROL_RATE_HZ`, 100 Hz if
    /// neither) and the `[design]` fields; safety,
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
            control_rate: generated::CONTROL_RATE,
            reference: ReferenceConfig {
                smoothing_rate: generated::SMOOTHING_RATE,
                ..paper.reference
            },
            ..paper
        }
    }

    /// The build's airframe (vehicle, rotors, motor time constant, body drag): what host-sim's
    /// software-in-the-loop plant flies with the built firmware.
    pub fn built_airframe() -> Airframe {
        generated::airframe()
    }
}
