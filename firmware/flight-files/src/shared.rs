//! The two files that both the firmware and host-sim read, owned here so that neither reads the
//! other's tree: the paper's Section VI scenario (host-sim's default run; the firmware's bench
//! fixtures take its `[initial]` resting state) and the software-in-the-loop sensor models
//! (host-sim's SIL; the bench fixtures take its `[imu]` and `[mocap]` values). host-sim's
//! `scenarios/paper.toml` and `scenarios/sil/sensors.toml` are links to them, so users find the
//! scenario where the other scenarios are.

/// The paper's Section VI scenario (TOML text; keys in docs/scenarios.md).
pub const PAPER_SCENARIO: &str = include_str!("../shared/paper.toml");

/// Where [`PAPER_SCENARIO`] lives, for messages.
pub const PAPER_SCENARIO_PATH: &str = "firmware/flight-files/shared/paper.toml";

/// The software-in-the-loop sensor models (TOML text: `[imu]`, `[mocap]`, ...).
pub const SENSORS: &str = include_str!("../shared/sensors.toml");

/// Where [`SENSORS`] lives, for messages.
pub const SENSORS_PATH: &str = "firmware/flight-files/shared/sensors.toml";
