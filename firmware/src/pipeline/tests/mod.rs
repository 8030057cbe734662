//! Cross-facet tests of the whole pipeline: boot, telemetry with command refusals, non-finite
//! IMU samples, and the HIL messages.

#[cfg_attr(feature = "uncertified-paper", allow(unused_imports, dead_code))]
mod airmode;
#[cfg_attr(feature = "uncertified-paper", allow(unused_imports))]
mod arming;
#[cfg(feature = "hil")]
mod lockstep;
mod mission;
mod over_link;
// Built with the paper's flight file, the tests that need the default x500 file are left out;
// their helpers and imports are then unused.
#[cfg_attr(feature = "uncertified-paper", allow(unused_imports, dead_code))]
mod param;
#[cfg_attr(feature = "uncertified-paper", allow(unused_imports, dead_code))]
mod param_store;
mod storage;
#[cfg(not(feature = "uncertified-paper"))] // every test there flies the x500 file
mod storage_command;

use super::*;
use crate::link;
use crate::mixer::MixerError;
use mavlink::dialects::common::MavMessage;
use mavlink::dialects::common::{
    MavModeFlag, MavState, ATTITUDE_QUATERNION_DATA, COMMAND_ACK_DATA, HEARTBEAT_DATA,
    LOCAL_POSITION_NED_DATA, STATUSTEXT_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

/// Splits telemetry bytes into (msgid, payload) frames (unsigned MAVLink 2 only).
fn all_frames(bytes: &[u8]) -> Vec<(u32, Vec<u8>)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i + 12 <= bytes.len() {
        assert_eq!(bytes[i], 0xFD);
        let len = bytes[i + 1] as usize;
        let id = u32::from_le_bytes([bytes[i + 7], bytes[i + 8], bytes[i + 9], 0]);
        out.push((id, bytes[i + 10..i + 10 + len].to_vec()));
        i += 12 + len;
    }
    assert_eq!(i, bytes.len());
    out
}

/// [`all_frames`] without the HIL outputs (`hil` feature), which lead every tick's
/// telemetry and have their own test.
pub(super) fn frames(bytes: &[u8]) -> Vec<(u32, Vec<u8>)> {
    #[cfg(feature = "hil")]
    let hil = [
        mavlink::dialects::common::HIL_ACTUATOR_CONTROLS_DATA::ID,
        mavlink::dialects::common::POSITION_TARGET_LOCAL_NED_DATA::ID,
    ];
    #[cfg(not(feature = "hil"))]
    let hil: [u32; 0] = [];
    all_frames(bytes)
        .into_iter()
        .filter(|(id, _)| !hil.contains(id))
        .collect()
}

/// The `COMMAND_ACK`s of the next telemetry call at `now_us`.
pub(super) fn sent_acks(p: &mut FlightPipeline, now_us: u64) -> Vec<link::CommandAck> {
    let mut buf = [0u8; 4096];
    let n = p.telemetry(now_us, &mut buf);
    frames(&buf[..n])
        .into_iter()
        .filter(|f| f.0 == mavlink::dialects::common::COMMAND_ACK_DATA::ID)
        .map(|f| link::CommandAck::deser(MavlinkVersion::V2, &f.1).unwrap())
        .collect()
}

pub(super) fn command(c: MavCmd, p1: f32, p2: f32) -> Vec<u8> {
    let m = MavMessage::COMMAND_LONG(mavlink::dialects::common::COMMAND_LONG_DATA {
        param1: p1,
        param2: p2,
        command: c,
        target_system: 1,
        ..Default::default()
    });
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(&m, 255, 190, 0, &mut b);
    b[..n].to_vec()
}

/// The boot report of the paper vehicle: the certificate as in boot_report.rs (only Theorem 2's
/// yaw condition fails), the a-priori box does not fit the rotors, 12 N of rotor thrust.
#[test]
fn boot_report() {
    let p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
    let r = p.boot_report();
    let names: Vec<_> = r.certificate.violations().map(|c| c.name).collect();
    assert_eq!(names, ["theorem2.torque_max_yaw"]);
    assert!(!r.a_priori_fit.fits);
    assert!((r.thrust_capacity - 12.0).abs() < 1e-6);
    assert!((r.a_priori_fit.thrust_needed[0] - 3.512).abs() < 1e-3);
}

/// A broken geometry is refused at boot.
#[test]
fn bad_rotors_refused() {
    let mut c = FlightConfig::paper();
    c.rotors.thrust_max = f32::NAN;
    assert!(matches!(
        FlightPipeline::new(&c),
        Err(BootError::Mixer(MixerError::BadThrustRange))
    ));
    let mut c = FlightConfig::paper();
    c.gains.reset_threshold = 2.0;
    assert!(matches!(
        FlightPipeline::new(&c),
        Err(BootError::Parameter(_))
    ));
}

/// Disarmed at boot: zero throttle; telemetry sends HEARTBEAT (standby, not armed, custom
/// mode flagged as meaningful), ATTITUDE_QUATERNION, LOCAL_POSITION_NED, SYS_STATUS,
/// EXTENDED_SYS_STATE and ATTITUDE (HOME_POSITION and AUTOPILOT_VERSION only on request); an arm during the
/// gyro calibration is refused over MAVLink (COMMAND_ACK TEMPORARILY_REJECTED, addressed to
/// the sender, + STATUSTEXT) and as an event.
#[test]
fn boot_telemetry_and_refusal() {
    let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
    let out = p.control_tick(10_000);
    assert_eq!(out, MotorOutput::STOPPED);
    let mut buf = [0u8; 1024];
    let n = p.telemetry(10_000, &mut buf);
    let ids: Vec<u32> = frames(&buf[..n]).iter().map(|f| f.0).collect();
    assert_eq!(
        ids,
        [
            HEARTBEAT_DATA::ID,
            ATTITUDE_QUATERNION_DATA::ID,
            LOCAL_POSITION_NED_DATA::ID,
            mavlink::dialects::common::SYS_STATUS_DATA::ID,
            mavlink::dialects::common::EXTENDED_SYS_STATE_DATA::ID,
            mavlink::dialects::common::ATTITUDE_DATA::ID,
        ]
    );
    let hb = HEARTBEAT_DATA::deser(MavlinkVersion::V2, &frames(&buf[..n])[0].1).unwrap();
    assert_eq!(hb.system_status, MavState::MAV_STATE_STANDBY);
    assert!(!hb
        .base_mode
        .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED));
    assert!(hb
        .base_mode
        .contains(MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED));

    p.on_link_bytes(
        &command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0),
        20_000,
    );
    assert_eq!(p.status().counters.refused_commands, 1);
    let n = p.telemetry(20_000, &mut buf);
    let f = frames(&buf[..n]);
    assert_eq!(f[0].0, COMMAND_ACK_DATA::ID);
    let ack = link::CommandAck::deser(MavlinkVersion::V2, &f[0].1).unwrap();
    assert_eq!(ack.result, MavResult::MAV_RESULT_TEMPORARILY_REJECTED);
    assert_eq!((ack.target_system, ack.target_component), (255, 190));
    assert_eq!(f[1].0, STATUSTEXT_DATA::ID);
    let text = STATUSTEXT_DATA::deser(MavlinkVersion::V2, &f[1].1).unwrap();
    assert!(text
        .text
        .to_str()
        .unwrap()
        .starts_with("arm: gyro calibrating"));
    let mut refused = false;
    while let Some(e) = p.take_events() {
        refused |= matches!(e, Event::CommandRefused { command: "arm", .. });
    }
    assert!(refused);
    // Small buffers: nothing is half-written.
    p.on_link_bytes(&command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0), 30_000);
    let mut tiny = [0u8; 8];
    assert_eq!(p.telemetry(30_000, &mut tiny), 0);
    let n = p.telemetry(30_000, &mut buf);
    assert_eq!(frames(&buf[..n])[0].0, COMMAND_ACK_DATA::ID);
}

/// Non-finite IMU samples are counted and never reach the motors.
#[test]
fn non_finite_imu_is_counted() {
    let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
    p.on_imu(&ImuSample {
        gyro_rad_s: [f32::NAN, 0.0, 0.0],
        accel_m_s2: [0.0, 0.0, 9.81],
        time_us: 1000,
    });
    assert_eq!(p.status().counters.non_finite, 1);
    let out = p.control_tick(10_000);
    assert!(out.throttle.iter().all(|u| *u == 0.0));
    assert!(matches!(
        p.take_events(),
        Some(Event::NonFinite { source: "imu" })
    ));
}

/// Found by the pipeline fuzz target (tests/fuzz, its reply accounting): nine arm commands
/// refused during the gyro calibration, with no telemetry call in between, overflow both
/// 8-slot reply queues. The ninth `COMMAND_ACK` was counted as dropped but the ninth refusal's
/// `STATUSTEXT` vanished uncounted; now every reply is sent or counted in `replies_dropped`.
#[test]
fn refusals_beyond_the_reply_queues_are_counted() {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
    let commands = 9;
    for _ in 0..commands {
        p.on_link_bytes(&arm, 1_000);
    }
    assert_eq!(p.status().counters.refused_commands, commands);
    let (mut acks, mut texts) = (0, 0);
    let mut buf = [0u8; 2048];
    loop {
        let n = p.telemetry(1_000, &mut buf);
        if n == 0 {
            break;
        }
        for (id, _) in frames(&buf[..n]) {
            acks += u32::from(id == COMMAND_ACK_DATA::ID);
            texts += u32::from(id == STATUSTEXT_DATA::ID);
        }
    }
    // One ack and one text per refusal: 8 of each fit their queues, 1 of each is dropped.
    assert_eq!((acks, texts), (8, 8));
    assert_eq!(p.status().counters.replies_dropped, 2);
}

/// HIL (`hil` feature): a `HIL_SENSOR` in body FRD reaches the estimator as a FLU sample on
/// the simulation's clock, one missing IMU flag makes it no sample, and each tick sends
/// its throttles and reference once, in NED, before any other telemetry.
#[cfg(feature = "hil")]
#[test]
fn hil_sensor_in_actuators_and_reference_out() {
    use mavlink::dialects::common::{
        HilSensorUpdatedFlags, HIL_ACTUATOR_CONTROLS_DATA, HIL_SENSOR_DATA,
        POSITION_TARGET_LOCAL_NED_DATA,
    };
    let sensor = |t: u64, fields: u32| {
        let m = MavMessage::HIL_SENSOR(HIL_SENSOR_DATA {
            time_usec: t,
            // Level and still: the accelerometer reads +g along down's opposite (FRD z up is -z).
            zacc: -9.81,
            xgyro: 0.01,
            ygyro: 0.02,
            zgyro: 0.03,
            fields_updated: HilSensorUpdatedFlags::from_bits_retain(fields),
            ..Default::default()
        });
        let mut b = [0u8; link::MAX_FRAME];
        let n = link::encode(&m, 255, 190, 0, &mut b);
        b[..n].to_vec()
    };
    let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
    assert_eq!(p.hil_time_us(), None);
    p.on_link_bytes(&sensor(1_000, link::HIL_SENSOR_IMU_FIELDS), 0);
    assert_eq!(p.hil_time_us(), Some(1_000));
    assert_eq!(p.status().counters.imu_samples, 1);
    // Without the gyro z flag it is not an IMU sample: dropped, the clock does not move.
    p.on_link_bytes(
        &sensor(2_000, link::HIL_SENSOR_IMU_FIELDS & !0b10_0000),
        1_000,
    );
    assert_eq!(p.hil_time_us(), Some(1_000));
    assert_eq!(p.status().counters.imu_samples, 1);
    assert_eq!(p.status().counters.link.frames_dropped, 1);

    let out = p.control_tick(10_000);
    let mut buf = [0u8; 1024];
    let n = p.telemetry(10_000, &mut buf);
    let got = all_frames(&buf[..n]);
    assert_eq!(got[0].0, HIL_ACTUATOR_CONTROLS_DATA::ID);
    assert_eq!(got[1].0, POSITION_TARGET_LOCAL_NED_DATA::ID);
    let a = HIL_ACTUATOR_CONTROLS_DATA::deser(MavlinkVersion::V2, &got[0].1).unwrap();
    assert_eq!(a.time_usec, 10_000);
    assert_eq!(&a.controls[..4], &out.throttle);
    assert!(a.controls[4..].iter().all(|&c| c == 0.0));
    assert_eq!(
        a.mode.contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED),
        out.armed
    );
    let r = POSITION_TARGET_LOCAL_NED_DATA::deser(MavlinkVersion::V2, &got[1].1).unwrap();
    let reference = p.status().reference_position;
    assert_eq!(
        [r.x, r.y, r.z],
        [reference[0], -reference[1], -reference[2]]
    );
    // Sent once per tick; too little room sends neither and keeps them for the next call.
    let n2 = p.telemetry(10_500, &mut buf);
    assert!(all_frames(&buf[..n2])
        .iter()
        .all(|(id, _)| *id != HIL_ACTUATOR_CONTROLS_DATA::ID));
    p.control_tick(20_000);
    assert_eq!(p.telemetry(20_000, &mut buf[..40]), 0);
    let n3 = p.telemetry(20_000, &mut buf);
    let got = all_frames(&buf[..n3]);
    let a = HIL_ACTUATOR_CONTROLS_DATA::deser(MavlinkVersion::V2, &got[0].1).unwrap();
    assert_eq!(a.time_usec, 20_000);
}

/// An `ATT_POS_MOCAP` frame (NED, level) at `(x, y, z)` m with sequence number `seq`.
fn mocap_frame(time_us: u64, [x, y, z]: [f32; 3], seq: u8) -> Vec<u8> {
    let m = MavMessage::ATT_POS_MOCAP(mavlink::dialects::common::ATT_POS_MOCAP_DATA {
        time_usec: time_us,
        q: [1.0, 0.0, 0.0, 0.0],
        x,
        y,
        z,
    });
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(&m, 255, 190, seq, &mut b);
    b[..n].to_vec()
}

/// A pipeline that has calibrated its gyro, converged on a pose 1 m up (NWU) and armed,
/// with the time \[µs\] reached. IMU at 1 kHz (level, still), poses and ticks at 100 Hz.
pub(super) fn armed_pipeline() -> (FlightPipeline, u64) {
    let (p, now) = arm_attempt(FlightConfig::built());
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    (p, now)
}

/// A pipeline flying `c` (with a short gyro calibration) that has calibrated, converged on a
/// pose 1 m up (NWU) and been sent an arm command, with the time \[µs\] reached; armed or not.
pub(super) fn arm_attempt(mut c: FlightConfig) -> (FlightPipeline, u64) {
    c.gyro_calibration_samples = 50;
    let mut p = FlightPipeline::new(&c).unwrap();
    let now = fly_ticks(&mut p, 0, 60, true);
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
    p.on_link_bytes(&arm, now);
    let mut sink = [0u8; 1024];
    p.telemetry(now, &mut sink);
    (p, now)
}

/// Given an armed vehicle, when one bit error corrupts a pose frame's length byte and four
/// poses and a kill follow (so the decoder holds them back, then releases all six frames at
/// once when the bad frame's checksum fails), then the kill disarms the vehicle and is
/// acknowledged, whatever the chunking of the bytes, and every frame behind the damage is decoded.
#[test]
fn kill_behind_a_corrupted_length_byte_disarms_and_is_acknowledged() {
    for chunk in [1usize, 7, 32, 64, usize::MAX] {
        let (mut p, now) = armed_pipeline();
        let accepted_before = p.status().counters.link.frames_ok;
        let mut bad = mocap_frame(now, [0.0, 0.0, -1.0], 100);
        bad[1] = 255;
        let mut stream = bad;
        for k in 0..4u8 {
            stream.extend(mocap_frame(
                now + 1 + u64::from(k),
                [0.0, 0.0, -1.0],
                101 + k,
            ));
        }
        let kill = crate::ground_station::kill();
        let mut b = [0u8; link::MAX_FRAME];
        let n = link::encode(&kill, 255, 190, 105, &mut b);
        stream.extend_from_slice(&b[..n]);
        // Enough bytes that the bad frame's claimed length is complete and its CRC is checked.
        assert!(stream.len() >= 1 + 9 + 255 + 2, "{}", stream.len());
        for part in stream.chunks(chunk.min(stream.len())) {
            p.on_link_bytes(part, now + 5);
        }
        assert_eq!(
            p.status().state,
            crate::safety::FlightState::Disarmed,
            "chunk {chunk}"
        );
        assert_eq!(p.control_tick(now + 10_000), MotorOutput::STOPPED);
        // All five frames behind the damage were decoded and handed on (the poses share one
        // arrival time, so the estimator keeps the first; none is dropped unseen).
        assert_eq!(
            p.status().counters.link.frames_ok,
            accepted_before + 5,
            "chunk {chunk}"
        );
        assert!(p.status().counters.link.frames_malformed >= 1);
        assert_eq!(p.status().counters.replies_dropped, 0);
        let mut buf = [0u8; 1024];
        let n = p.telemetry(now + 10_000, &mut buf);
        let acks: Vec<link::CommandAck> = frames(&buf[..n])
            .iter()
            .filter(|(id, _)| *id == COMMAND_ACK_DATA::ID)
            .map(|(_, payload)| link::CommandAck::deser(MavlinkVersion::V2, payload).unwrap())
            .collect();
        assert_eq!(acks.len(), 1, "chunk {chunk}: {acks:?}");
        assert_eq!(acks[0].command, MavCmd::MAV_CMD_COMPONENT_ARM_DISARM);
        assert_eq!(acks[0].result, MavResult::MAV_RESULT_ACCEPTED);
    }
}

/// Every event queued so far, oldest first.
pub(super) fn drain_events(p: &mut FlightPipeline) -> Vec<Event> {
    std::iter::from_fn(|| p.take_events()).collect()
}

/// Given the same IMU samples (1 kHz) and poses (100 Hz) for 3 s, when the law ticks at
/// 100 Hz in one pipeline and at 1 kHz in another, then the estimate at every common tick is
/// the same bit for bit (the estimator runs per IMU sample and per pose, not per tick) and the
/// telemetry sends as many heartbeats and state messages (its periods are times, not ticks).
#[test]
fn estimator_and_telemetry_do_not_depend_on_the_law_rate() {
    use crate::control_rate::ControlRate;
    let run = |rate: ControlRate| {
        let mut c = FlightConfig::built();
        c.control_rate = rate;
        c.gyro_calibration_samples = 50;
        let mut p = FlightPipeline::new(&c).unwrap();
        let tick_every = rate.period_us();
        let mut estimates = Vec::new();
        let mut counts = [0usize; 3];
        let mut sink = [0u8; 2048];
        let mut seq = 0u8;
        for ms in 1..=3000u64 {
            let now = ms * 1_000;
            // A slow roll and a drifting position, so the estimate changes every sample.
            let s = (ms as f32 * 1e-3).sin();
            p.on_imu(&ImuSample {
                gyro_rad_s: [0.2 * s, 0.0, 0.05],
                accel_m_s2: [0.0, 0.3 * s, 9.81],
                time_us: now,
            });
            if ms % 10 == 0 {
                let x = 0.01 * ms as f32 * 1e-3;
                p.on_link_bytes(&mocap_frame(now, [x, 0.0, -1.0], seq), now);
                seq = seq.wrapping_add(1);
            }
            if now % tick_every == 0 {
                p.control_tick(now);
                let n = p.telemetry(now, &mut sink);
                for (id, _) in frames(&sink[..n]) {
                    let slot = [
                        HEARTBEAT_DATA::ID,
                        ATTITUDE_QUATERNION_DATA::ID,
                        LOCAL_POSITION_NED_DATA::ID,
                    ]
                    .iter()
                    .position(|&k| k == id);
                    if let Some(k) = slot {
                        counts[k] += 1;
                    }
                }
                if now % 10_000 == 0 {
                    estimates.push((now, p.estimator.estimate(now), p.status().position));
                }
            }
        }
        (estimates, counts)
    };
    let (slow, slow_counts) = run(ControlRate::Hz100);
    let (fast, fast_counts) = run(ControlRate::Hz1000);
    assert_eq!(slow.len(), 300);
    assert!(slow.iter().filter(|e| e.1.is_some()).count() > 250);
    assert_eq!(slow, fast);
    // 3 s: heartbeats at 0 s (the first tick), 1 s, 2 s; state messages every 50 ms.
    assert_eq!(slow_counts, fast_counts);
    assert_eq!(slow_counts[0], 3);
    assert_eq!(slow_counts[1], 60);
}

/// Ticks `p` for `ticks` control periods of 10 ms from `now` (IMU level and still at 1 kHz),
/// with a pose 1 m up (NED z = −1) each tick when `poses`; returns the time reached.
pub(super) fn fly_ticks(p: &mut FlightPipeline, mut now: u64, ticks: u32, poses: bool) -> u64 {
    for k in 0..ticks {
        for _ in 0..10 {
            now += 1_000;
            p.on_imu(&ImuSample {
                gyro_rad_s: [0.0; 3],
                accel_m_s2: [0.0, 0.0, 9.81],
                time_us: now,
            });
        }
        if poses {
            p.on_link_bytes(&mocap_frame(now, [0.0, 0.0, -1.0], k as u8), now);
        }
        p.control_tick(now);
    }
    now
}

/// Given an armed vehicle with the integral action on, taking off while its poses say it stays
/// where it is (so the error below the target persists), when the law runs, then the estimate
/// pushes up and stays within its level; when the poses stop (failsafe), then the estimate is
/// held exactly; when the failsafe disarms and the vehicle arms again, then it starts from zero.
#[test]
fn integral_estimate_grows_is_held_in_failsafe_and_restarts_at_zero_on_arming() {
    use controller_core::integral::IntegralGains;
    use nalgebra::Vector3;
    let mut c = FlightConfig::built();
    let level = Vector3::new(0.5, 0.5, 1.0);
    c.gains.integral = Some(IntegralGains {
        feedforward_scale: None,
        gain: 2.0,
        level,
        rate: Vector3::repeat(1.0),
        bandwidth: 5.0,
        observer: None,
    });
    // The lifecycle is under test here, not the certificate of these levels.
    c.allow_uncertified = true;
    let (mut p, now) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Armed);
    assert_eq!(p.status().integral, [0.0; 3]);
    let takeoff = command(MavCmd::MAV_CMD_NAV_TAKEOFF, 0.0, 0.0);
    p.on_link_bytes(&takeoff, now);
    let now = fly_ticks(&mut p, now, 300, true);
    let eta = p.status().integral;
    assert_eq!(p.status().state, FlightState::Armed);
    assert!(eta[2] > 0.1, "{eta:?}");
    assert!((0..3).all(|i| eta[i].abs() <= level[i]), "{eta:?}");
    // Poses stop: the failsafe (after 100 ms) holds the estimate while it descends.
    let now = fly_ticks(&mut p, now, 15, false);
    assert_eq!(p.status().state, FlightState::Failsafe);
    let held = p.status().integral;
    let now = fly_ticks(&mut p, now, 50, false);
    assert_eq!(p.status().state, FlightState::Failsafe);
    assert_eq!(p.status().integral, held);
    // Disarmed by the failsafe's time-out or pose loss: no estimate; armed again: from zero.
    let now = fly_ticks(&mut p, now, 300, false);
    assert_eq!(p.status().state, FlightState::Disarmed);
    assert_eq!(p.status().integral, [0.0; 3]);
    let now = fly_ticks(&mut p, now, 60, true);
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
    p.on_link_bytes(&arm, now);
    let now = fly_ticks(&mut p, now, 1, true);
    assert_eq!(
        p.status().state,
        FlightState::Armed,
        "{:?}",
        drain_events(&mut p)
    );
    assert_eq!(p.status().integral, [0.0; 3]);
    p.on_link_bytes(&takeoff, now);
    fly_ticks(&mut p, now, 300, true);
    assert!(p.status().integral[2] > 0.1, "{:?}", p.status());
}
