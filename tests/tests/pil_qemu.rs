//! Processor in the loop: the firmware built for Cortex-M4F (`firmware-mps2-an386`, the
//! default build: firmware/flights/x500.toml) runs in QEMU `mps2-an386` and flies SIL's paper
//! scenario (the x500 released upside down, then its demo mission) over its emulated serial
//! port, in lockstep with the rotor plant. The same checks as host-sim's `sil_paper.rs` where
//! the telemetry carries them, plus: the firmware neither crashed nor stalled (the stall
//! timeout bounds the wall time) and its defmt log decodes and holds the boot banner: the x500,
//! "certificate holds", "set fits" and its UART untrusted (a `SETUP_SIGNING` must be signed).
//!
//! Twice: at the default 100 Hz over the whole flight, and with the law at 1 kHz (the same flight
//! file built with `FIRMWARE_CONTROL_RATE_HZ=1000`) over the recovery (the first 12 s after
//! release: the flip, the path lifting's switches, the braking, the mission's start), where every
//! control step must also finish within its 1 ms period (0 overruns in the firmware's timing
//! log). A step costs the same at any point of the flight, and emulating the whole 1 kHz flight
//! takes QEMU twice the 100 Hz one's wall clock: `host-sim pil --rate-hz 1000` flies it
//! whole (docs/sil-pil.md).
//!
//! And the lockstep's determinism: two short runs of the same scenario and seed, the host's
//! writes cut whole and at random, give byte-identical telemetry (docs/sil-pil.md, "Lockstep
//! determinism").
//!
//! Needs `qemu-system-arm` and the ELFs: `PIL_FIRMWARE_ELF`, or the default path
//! (`host_sim::harness::pil::default_elf`, i.e. `$CARGO_TARGET_DIR` or `target/`, then
//! `thumbv7em-none-eabihf/release/firmware-mps2-an386`); `PIL_FIRMWARE_ELF_1KHZ` for the 1 kHz
//! build (no default: tests/run-all.sh builds it). `PIL_QEMU` overrides the QEMU binary.

use std::path::PathBuf;
use std::time::Duration;

use host_sim::harness::pil::{self, PilOptions, SendChunking};
use host_sim::harness::sil::{scenarios, FlightExtremes};

#[test]
#[ignore = "needs qemu-system-arm and the mps2-an386 firmware ELF; tests/run-all.sh builds both and runs it with --ignored"]
fn upside_down_recovery_on_the_emulated_mcu_stays_inside_the_certified_bounds() {
    let elf = std::env::var_os("PIL_FIRMWARE_ELF")
        .map(PathBuf::from)
        .unwrap_or_else(pil::default_elf);
    fly_and_check(elf, 100.0, WHOLE_FLIGHT_S, "pil-qemu-test");
}

#[test]
#[ignore = "needs qemu-system-arm and the mps2-an386 firmware ELF built with FIRMWARE_CONTROL_RATE_HZ=1000 (PIL_FIRMWARE_ELF_1KHZ); tests/run-all.sh builds both and runs it with --ignored"]
fn the_law_at_1_khz_on_the_emulated_mcu_recovers_with_no_overrun() {
    let elf = std::env::var_os("PIL_FIRMWARE_ELF_1KHZ")
        .map(PathBuf::from)
        .expect(
            "PIL_FIRMWARE_ELF_1KHZ: the mps2-an386 ELF built with FIRMWARE_CONTROL_RATE_HZ=1000 \
         (see tests/run-all.sh)",
        );
    fly_and_check(elf, 1000.0, RECOVERY_S, "pil-qemu-1khz-test");
}

#[test]
#[ignore = "needs qemu-system-arm and the mps2-an386 firmware ELF; tests/run-all.sh builds both and runs it with --ignored"]
fn the_telemetry_does_not_depend_on_how_the_host_cuts_its_writes() {
    let elf = std::env::var_os("PIL_FIRMWARE_ELF")
        .map(PathBuf::from)
        .unwrap_or_else(pil::default_elf);
    // Short: the 1.5 s upside-down hold and 1.5 s of the recovery (the arm, the flip, the
    // mission start), 301 ticks at 100 Hz.
    let whole = fly_recording(&elf, SendChunking::Whole, "pil-chunking-whole");
    let random = fly_recording(
        &elf,
        SendChunking::Random { seed: 7 },
        "pil-chunking-random",
    );
    // QEMU under load: busy threads on every core shift when each write reaches the emulated
    // UART relative to the firmware's execution, on top of another chunking.
    let loaded = {
        let _load = CpuLoad::start();
        fly_recording(
            &elf,
            SendChunking::Random { seed: 11 },
            "pil-chunking-loaded",
        )
    };
    assert_eq!(whole.1, 301, "ticks answered");
    assert_eq!(random.1, whole.1, "ticks answered");
    assert_eq!(loaded.1, whole.1, "ticks answered under load");
    assert_same_telemetry(&whole.0, &random.0, "random chunks");
    assert_same_telemetry(&whole.0, &loaded.0, "random chunks, host loaded");
}

/// Busy threads, two per core, until dropped: a host under load.
struct CpuLoad {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    threads: Vec<std::thread::JoinHandle<u64>>,
}

impl CpuLoad {
    fn start() -> Self {
        use std::sync::atomic::{AtomicBool, Ordering};
        let stop = std::sync::Arc::new(AtomicBool::new(false));
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        let threads = (0..2 * cores)
            .map(|_| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let mut spins = 0u64;
                    while !stop.load(Ordering::Relaxed) {
                        spins = std::hint::black_box(spins.wrapping_add(1));
                    }
                    spins
                })
            })
            .collect();
        Self { stop, threads }
    }
}

impl Drop for CpuLoad {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// Byte-for-byte equality of two telemetry recordings, with the first difference on failure.
fn assert_same_telemetry(whole: &[u8], other: &[u8], what: &str) {
    // Byte for byte, every frame up to the last tick's answer (docs/sil-pil.md: nothing in the
    // telemetry is a wall-clock or cycle figure; the frames after the last answer are not
    // compared because the run ends while they are on their way).
    let first_difference = whole.iter().zip(other).position(|(a, b)| a != b);
    println!(
        "telemetry: {} B (whole), {} B ({what}), first difference at byte {first_difference:?}",
        whole.len(),
        other.len()
    );
    assert!(
        whole == other,
        "{what}: {} vs {} bytes of telemetry, first difference at byte {first_difference:?}",
        whole.len(),
        other.len()
    );
}

/// Flies the paper scenario (3 s simulated) on `elf` with the host's writes cut as `chunking`
/// says, and returns the telemetry taken in (raw frames) and the number of ticks answered.
fn fly_recording(elf: &std::path::Path, chunking: SendChunking, tag: &str) -> (Vec<u8>, u32) {
    let out = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
    let options = PilOptions {
        elf: elf.to_path_buf(),
        qemu: std::env::var_os("PIL_QEMU")
            .map_or_else(|| PathBuf::from("qemu-system-arm"), PathBuf::from),
        out: out.clone(),
        timeout: Duration::from_secs_f64(pil::DEFAULT_TIMEOUT_S),
        send_chunking: chunking,
        motor_order: pil::MotorOrder::Mixer,
        record_telemetry: true,
        gcs_udp: None,
    };
    let mut setup = scenarios::paper(1);
    setup.duration_s = 1.5;
    let mut ticks = 0;
    let s = pil::run(&setup, &options, |_| ticks += 1)
        .unwrap_or_else(|e| panic!("PIL run ({chunking}) failed: {e:#}"));
    print!("{}", pil::human_summary(&s));
    // It armed and flew: the comparison is not one of idle motors.
    assert_eq!(s.flight.final_state, "armed", "{:#?}", s.flight.events);
    let telemetry = std::fs::read(out.join(pil::TELEMETRY_FILE)).expect("telemetry.bin");
    let _ = std::fs::remove_dir_all(&out);
    (telemetry, ticks)
}

/// The paper scenario's flight after release [s] (SIL's `paper` setup).
const WHOLE_FLIGHT_S: f64 = 30.0;

/// The recovery [s] after release: upright from 10 s on (the late window below), with 2 s of it.
const RECOVERY_S: f64 = 12.0;

/// Flies SIL's paper scenario for `flight_s` after release with the law at `rate_hz` on the
/// firmware `elf` in QEMU and checks the flight, the link, the boot banner and that no control
/// step overran its period.
fn fly_and_check(elf: PathBuf, rate_hz: f64, flight_s: f64, tag: &str) {
    let out = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
    let options = PilOptions {
        elf,
        qemu: std::env::var_os("PIL_QEMU")
            .map_or_else(|| PathBuf::from("qemu-system-arm"), PathBuf::from),
        out: out.clone(),
        timeout: Duration::from_secs_f64(pil::DEFAULT_TIMEOUT_S),
        send_chunking: SendChunking::Whole,
        motor_order: pil::MotorOrder::Mixer,
        record_telemetry: false,
        gcs_udp: None,
    };
    let mut setup = scenarios::paper(1);
    setup
        .set_control_rate_hz(rate_hz)
        .expect("a supported rate");
    assert_eq!(
        setup.duration_s, WHOLE_FLIGHT_S,
        "SIL's paper flight changed"
    );
    setup.duration_s = flight_s;
    // The certificate the firmware computes at boot for the configuration it flies.
    let bounds = setup
        .a_priori_bounds()
        .expect("the built configuration boots");
    let mut seen = FlightExtremes::new(10.0);
    // A crash, a stall (no answer within the timeout) or a lost lockstep is an error here.
    let s = pil::run(&setup, &options, |r| seen.observe(r))
        .unwrap_or_else(|e| panic!("PIL run failed: {e:#}"));
    print!("{}", pil::human_summary(&s));
    let f = &s.flight;
    // It really started upside down, and every tick was answered.
    assert!(seen.max_tilt_early_rad > 3.0, "{seen:?}");
    // One record per tick over the hold and the flight, both ends included.
    let seconds = setup.hold_s + flight_s;
    let ticks = (seconds * rate_hz).round() as u32 + 1;
    assert_eq!(seen.samples, ticks);
    // Armed (explicit upside-down arm), flew the mission to the end, never failsafe.
    assert_eq!(f.final_state, "armed", "{:#?}", f.events);
    assert!(f.failsafe_at_s.is_none(), "{:#?}", f.events);
    // Upright again from 10 s on: within the tilt the saturated position loop can ask for plus
    // 0.05 rad (host-sim/tests/sil_paper.rs derives the envelope, 0.165 rad for the x500).
    assert!(seen.max_tilt_late_rad < 0.215, "{seen:?}");
    // The (T, τ) rebuilt from the throttles stays inside the certificate's a-priori bounds.
    assert!(seen.inside(&bounds), "{seen:?} vs {bounds:?}");
    // Rotor limits held: throttles finite in [0, 1], nothing spinning while disarmed.
    assert!(f.rotor_thrust_max_N <= f.rotor_range_N[1] + 1e-9);
    assert_eq!(f.throttle_violations, 0);
    assert_eq!(f.spun_while_disarmed, 0);
    // No malformed frame either way: the firmware's decoder (its last defmt counters; every
    // HIL_SENSOR and pose) and the host's reader of its serial output.
    let c = s
        .firmware_counters
        .expect("no link:/pipeline: counter lines in the defmt log");
    assert_eq!(c.link_frames[2], 0, "{c:?}");
    // The IMU at 1 kHz and the pose at 100 Hz: over 950 frames a second decoded.
    assert!(f64::from(c.link_frames[0]) > 950.0 * seconds, "{c:?}");
    assert_eq!(c.non_finite, 0, "{c:?}");
    assert_eq!(s.serial.malformed, 0, "{:?}", s.serial);
    assert!(
        f64::from(f.telemetry_frames[0]) > 190.0 * seconds,
        "{:?}",
        f.telemetry_frames
    );
    // Every control step finished within its period (the firmware's own count; see
    // `defmt_log::overruns` for what the period is measured on under QEMU).
    assert_eq!(s.firmware_overruns, Some(0), "control-step overruns");
    assert!(c.ticks >= ticks - (rate_hz as u32), "{c:?}");
    // Certified at boot, as in SIL.
    assert!(f.certificate_holds, "{:?}", f.violated_conditions);
    assert!(f.fit_margin >= f.required_fit_margin);
    // The defmt boot banner: the vehicle, "certificate holds", "set fits".
    assert!(s.defmt_error.is_none(), "{:?}", s.defmt_error);
    assert_eq!(s.defmt_malformed, 0);
    let line = s.certificate_line.as_deref().expect("no certificate line");
    assert!(line.contains("certificate holds"), "{line}");
    let line = s.box_line.as_deref().expect("no box-fit line");
    assert!(
        line.contains("set fits") && !line.contains("WITHOUT") && !line.contains("NOT"),
        "{line}"
    );
    let line = s.vehicle_line.as_deref().expect("no vehicle line");
    assert!(line.contains("x500"), "{line}");
    let log = std::fs::read_to_string(out.join("defmt.log")).unwrap();
    assert!(log.contains("gate: certificate holds and set fits"));
    // The default build's UART is untrusted, as a radio would be: a SETUP_SIGNING must be
    // signed with the key in force (tests/mavlink-client checks the refusal over the link).
    let link = log
        .lines()
        .find(|l| l.contains("link: ") && l.contains("SETUP_SIGNING"))
        .expect("no link trust line");
    assert!(link.contains("link: untrusted"), "{link}");
    // The clock the steps are timed on (and overruns judged on) is monotonic across SysTick
    // reloads: the board's boot self-check reads it back to back over 60 of them. Misreading
    // QEMU's counter at a reload made it jump 1 ms ahead and back at one reload in three, and
    // a step that ended on such a reading counted as an overrun.
    let clock = log
        .lines()
        .find(|l| l.contains("clock: "))
        .expect("no clock self-check line");
    assert!(clock.contains(" 0 backwards, 0 jumps"), "{clock}");
    let _ = std::fs::remove_dir_all(&out);
}
