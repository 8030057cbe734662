//! Three build-time jobs of the firmware crate.
//!
//! **The flight file** (every build). The firmware flies one flight file chosen at build time:
//! env `FIRMWARE_FLIGHT_FILE` (default `firmware/flights/x500.toml`): a vehicle file (read by
//! the shared `src/vehicle_file/`) plus `[limits]`, `[gains]`, `[trajectory]` (read by the
//! shared `src/flight_tables.rs`) and `[design]`.
//! `build/flight.rs` writes it to `OUT_DIR/flight.rs`, which `src/built_flight.rs` includes
//! (`FlightConfig::built()`). The control law's rate is the file's `[design] control_rate_hz`
//! (100 Hz if absent), or env `FIRMWARE_CONTROL_RATE_HZ` when set (the same vehicle at another
//! rate, e.g. the 1 kHz processor-in-the-loop build). The paper's set-up (`[vehicle] real_propeller = false`) is refused
//! unless the `uncertified-paper` feature is on.
//!
//! **The board's memory map** (bare-metal builds only). cortex-m-rt's `link.x` does
//! `INCLUDE memory.x`; the linker looks for it in the current directory first, which for cargo
//! is the workspace root, whose `memory.x` only does `INCLUDE board-memory.x`. This script copies
//! the board's map (`boards/stm32f405/memory.x` by default, `boards/mps2-an386/memory.x` with the
//! `board-mps2-an386` feature) into `OUT_DIR` as `board-memory.x` and puts `OUT_DIR` on the
//! linker search path. (The board's map cannot simply be called `memory.x` on the search path:
//! the workspace root's file would shadow it.) Host builds do not link against `link.x`.
//!
//! **The bench fixtures' scenario values** (`bench-fixtures` feature only). `step_inputs` copies
//! the paper scenario's initial state (`../host-sim/scenarios/paper.toml`, `[initial]`) and the
//! software-in-the-loop sensor models (`../host-sim/scenarios/sil/sensors.toml`, `[imu]`,
//! `[mocap]`); this script reads both files and writes the constants to
//! `OUT_DIR/scenario_constants.rs`, which `src/step_inputs/scenario.rs` includes, so the files
//! are the one source of those values.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

// The vehicle file format, shared with the firmware library (`firmware::vehicle_file`).
// `FlightValues` is re-exported for the library; the build script names it through methods only.
#[allow(dead_code, unused_imports)]
#[path = "src/vehicle_file/mod.rs"]
mod vehicle_file;

// The flight file's `[limits]`, `[gains]` and `[trajectory]` tables, shared with the firmware
// library (`firmware::flight_tables`) and host-sim's scenario files.
#[path = "src/flight_tables.rs"]
mod flight_tables;

// The allowed control-law rates, shared with the firmware library (`firmware::control_rate`).
#[allow(dead_code)]
#[path = "src/control_rate.rs"]
mod control_rate;

#[path = "build/flight.rs"]
mod flight;

fn main() {
    let manifest_dir = PathBuf::from(
        env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR for build scripts"),
    );
    let out_dir =
        PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR for build scripts"));
    println!("cargo:rerun-if-changed=build.rs");
    memory_map(&manifest_dir, &out_dir);
    flight::write(&manifest_dir, &out_dir);
    // The `toml` build-dependency comes with the feature.
    #[cfg(feature = "bench-fixtures")]
    bench_fixtures::scenario_constants(&manifest_dir, &out_dir);
}

/// Copies the board's memory map to `OUT_DIR/board-memory.x` (bare-metal builds).
fn memory_map(manifest_dir: &Path, out_dir: &Path) {
    let board = if env::var_os("CARGO_FEATURE_BOARD_MPS2_AN386").is_some() {
        "mps2-an386"
    } else {
        "stm32f405"
    };
    let memory_x = manifest_dir.join("boards").join(board).join("memory.x");
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!(
        "cargo:rerun-if-changed={}",
        manifest_dir.join("..").join("memory.x").display()
    );
    // CARGO_CFG_TARGET_OS is the *target's* OS ("none" for thumbv7em-none-eabihf); the build
    // script itself always runs on the host.
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }
    let dest = out_dir.join("board-memory.x");
    fs::copy(&memory_x, &dest).unwrap_or_else(|e| {
        panic!(
            "cannot copy the linker memory map {} to {}: {e}",
            memory_x.display(),
            dest.display()
        )
    });
    println!("cargo:rustc-link-search={}", out_dir.display());
}

/// The bench fixtures' constants from host-sim's scenario files.
#[cfg(feature = "bench-fixtures")]
mod bench_fixtures {
    use std::fmt::Write as _;
    use std::fs;
    use std::path::Path;

    /// A parsed scenario file and its name for error messages.
    struct Source {
        name: String,
        table: toml::Table,
    }

    impl Source {
        fn read(path: &Path, name: &str) -> Self {
            println!("cargo:rerun-if-changed={}", path.display());
            let text = fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("bench fixtures: cannot read {name}: {e}"));
            let table = text
                .parse::<toml::Table>()
                .unwrap_or_else(|e| panic!("bench fixtures: {name} is not valid TOML: {e}"));
            Self {
                name: name.to_owned(),
                table,
            }
        }

        fn missing(&self, section: &str, key: &str, expected: &str) -> ! {
            panic!(
                "bench fixtures: {}: key `{key}` of `[{section}]` is missing or not {expected}",
                self.name
            )
        }

        fn value(&self, section: &str, key: &str) -> Option<&toml::Value> {
            self.table.get(section)?.as_table()?.get(key)
        }

        /// A number (TOML float or integer).
        fn number(&self, section: &str, key: &str) -> f64 {
            self.value(section, key)
                .and_then(as_number)
                .unwrap_or_else(|| self.missing(section, key, "a number"))
        }

        /// An array of three numbers.
        fn vector(&self, section: &str, key: &str) -> [f64; 3] {
            let numbers: Option<Vec<f64>> = self
                .value(section, key)
                .and_then(toml::Value::as_array)
                .and_then(|a| a.iter().map(as_number).collect());
            match numbers.as_deref() {
                Some(&[x, y, z]) => [x, y, z],
                _ => self.missing(section, key, "an array of 3 numbers"),
            }
        }
    }

    fn as_number(v: &toml::Value) -> Option<f64> {
        match v {
            toml::Value::Float(x) if x.is_finite() => Some(*x),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        }
    }

    /// An `f32` literal that rounds like the decimal in the file: the shortest decimal that gives
    /// the same `f64` back (`{:?}`), parsed by rustc straight to `f32`.
    fn f32_literal(x: f64) -> String {
        format!("{x:?}_f32")
    }

    fn f32_array(v: [f64; 3]) -> String {
        format!(
            "[{}, {}, {}]",
            f32_literal(v[0]),
            f32_literal(v[1]),
            f32_literal(v[2])
        )
    }

    /// Writes `OUT_DIR/scenario_constants.rs` from the two scenario files.
    pub fn scenario_constants(manifest_dir: &Path, out_dir: &Path) {
        let scenarios = manifest_dir.join("..").join("host-sim").join("scenarios");
        let paper = Source::read(
            &scenarios.join("paper.toml"),
            "host-sim/scenarios/paper.toml",
        );
        let sensors = Source::read(
            &scenarios.join("sil").join("sensors.toml"),
            "host-sim/scenarios/sil/sensors.toml",
        );

        let position = paper.vector("initial", "position_m");
        let [roll_deg, pitch_deg, yaw_deg] = paper.vector("initial", "euler_deg");
        // The scripted trajectory rests at R = Rz(yaw) Rx(roll): it has no pitch.
        if pitch_deg != 0.0 {
            panic!(
                "bench fixtures: host-sim/scenarios/paper.toml: `[initial] euler_deg` has pitch \
                 {pitch_deg}°; the bench trajectory supports roll and yaw only (pitch 0)"
            );
        }
        let gyro_bias = sensors.vector("imu", "gyro_bias_rad_s");
        let accel_bias = sensors.vector("imu", "accel_bias_m_s2");
        let gyro_noise = sensors.number("imu", "gyro_noise_rad_s");
        let accel_noise = sensors.number("imu", "accel_noise_m_s2");
        let pose_noise = sensors.number("mocap", "position_noise_m");
        let latency_s = sensors.number("mocap", "latency_s");
        let latency_us = (latency_s * 1e6).round();
        if latency_s < 0.0 || (latency_s * 1e6 - latency_us).abs() > 1e-6 {
            sensors.missing(
                "mocap",
                "latency_s",
                "a whole, non-negative number of microseconds",
            );
        }

        let mut code = String::from(
            "// Generated by firmware/build.rs from host-sim/scenarios/paper.toml and\n\
             // host-sim/scenarios/sil/sensors.toml. Do not edit.\n",
        );
        let mut item = |doc: &str, decl: &str, value: String| {
            writeln!(code, "/// {doc}\n{decl} = {value};")
                .expect("writing to a String never fails");
        };
        item(
            "Resting position \\[m\\] NWU (paper.toml `[initial] position_m`).",
            "pub(crate) const REST_POSITION: [f32; 3]",
            f32_array(position),
        );
        item(
            "Resting roll \\[rad\\] (paper.toml `[initial] euler_deg[0]`).",
            "pub(crate) const REST_ROLL: f32",
            format!("{} * core::f32::consts::PI / 180.0", f32_literal(roll_deg)),
        );
        item(
            "Resting yaw \\[rad\\] (paper.toml `[initial] euler_deg[2]`).",
            "pub(crate) const REST_YAW: f32",
            format!("{} * core::f32::consts::PI / 180.0", f32_literal(yaw_deg)),
        );
        item(
            "Gyro bias \\[rad/s\\] (sensors.toml `[imu] gyro_bias_rad_s`).",
            "pub(crate) const GYRO_BIAS: [f32; 3]",
            f32_array(gyro_bias),
        );
        item(
            "Accelerometer bias \\[m/s²\\] (sensors.toml `[imu] accel_bias_m_s2`).",
            "pub(crate) const ACCEL_BIAS: [f32; 3]",
            f32_array(accel_bias),
        );
        item(
            "Half-width of the uniform gyro noise \\[rad/s\\] (sensors.toml `[imu] gyro_noise_rad_s`).",
            "pub(crate) const GYRO_NOISE: f32",
            f32_literal(gyro_noise),
        );
        item(
            "Half-width of the uniform accelerometer noise \\[m/s²\\] (sensors.toml `[imu] accel_noise_m_s2`).",
            "pub(crate) const ACCEL_NOISE: f32",
            f32_literal(accel_noise),
        );
        item(
            "Half-width of the uniform pose position noise \\[m\\] (sensors.toml `[mocap] position_noise_m`).",
            "pub(crate) const POSE_NOISE: f32",
            f32_literal(pose_noise),
        );
        item(
            "Pose latency \\[µs\\] (sensors.toml `[mocap] latency_s`).",
            "pub(crate) const POSE_LATENCY_US: u64",
            format!("{}", latency_us as u64),
        );
        let dest = out_dir.join("scenario_constants.rs");
        fs::write(&dest, code).unwrap_or_else(|e| panic!("cannot write {}: {e}", dest.display()));
    }
}
