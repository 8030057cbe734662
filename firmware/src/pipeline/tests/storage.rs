//! The parameter store's hold on arming ([`FlightPipeline::attach_storage`]): a vehicle whose
//! board saves parameters to flash does not arm between an accepted change and the end of its
//! save, because the save may erase a sector and stall the control loop for seconds. Boards
//! without a store arm as before. Given/when/then, on the host.
#![cfg(not(feature = "uncertified-paper"))] // the default flight file's x500

use super::{command, drain_events, fly_ticks, sent_acks};
use crate::link;
use crate::pipeline::*;

const ARM: MavCmd = MavCmd::MAV_CMD_COMPONENT_ARM_DISARM;

/// A disarmed vehicle on the flight file, calibrated and converged at the returned time, with
/// or without a store attached.
fn ready(attached: bool) -> (FlightPipeline, u64) {
    let mut c = FlightConfig::built();
    c.gyro_calibration_samples = 50;
    let mut p = FlightPipeline::new(&c).unwrap();
    if attached {
        p.attach_storage();
    }
    let now = fly_ticks(&mut p, 0, 60, true);
    (p, now)
}

/// A certified `PARAM_SET` (k_f lowered by 20 %) from the ground station.
fn certified_set(p: &FlightPipeline) -> Vec<u8> {
    let set = crate::ground_station::param_set("POS_KF", 0.8 * p.config().gains.position.kf);
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(&set, 255, 190, 0, &mut b);
    b[..n].to_vec()
}

/// The results of the `COMMAND_ACK`s for arming in the next telemetry.
fn arm_acks(p: &mut FlightPipeline, now_us: u64) -> Vec<MavResult> {
    sent_acks(p, now_us)
        .into_iter()
        .filter(|a| a.command == ARM)
        .map(|a| a.result)
        .collect()
}

/// Given a board with a store, when a certified PARAM_SET is accepted and an arm follows before
/// the store reports the save done, then the arm is TEMPORARILY_REJECTED ("saving parameters")
/// and the vehicle stays disarmed; once the store reports done, the same arm is ACCEPTED.
#[test]
fn an_arm_waits_for_the_parameter_save() {
    let (mut p, now) = ready(true);
    p.on_link_bytes(&certified_set(&p), now);
    assert!(p.storage_busy());
    // The board's store task took the request and is still writing (or erasing).
    p.set_storage_busy(true);
    p.on_link_bytes(&command(ARM, 1.0, 0.0), now);
    assert_eq!(
        arm_acks(&mut p, now),
        [MavResult::MAV_RESULT_TEMPORARILY_REJECTED]
    );
    assert_eq!(p.status().state, FlightState::Disarmed);
    assert!(drain_events(&mut p).contains(&Event::CommandRefused {
        command: "arm",
        reason: "saving parameters to flash, retry",
    }));

    p.set_storage_busy(false);
    p.on_link_bytes(&command(ARM, 1.0, 0.0), now);
    assert_eq!(arm_acks(&mut p, now), [MavResult::MAV_RESULT_ACCEPTED]);
    assert_eq!(p.status().state, FlightState::Armed);
}

/// Given a board with a store, when a PARAM_SET and an arm arrive in the same read (no tick,
/// so no word from the store task, in between), then the arm is still refused: the pipeline
/// marks the store busy the moment it accepts the change.
#[test]
fn an_arm_in_the_same_read_as_the_set_waits_too() {
    let (mut p, now) = ready(true);
    let mut stream = certified_set(&p);
    stream.extend(command(ARM, 1.0, 0.0));
    p.on_link_bytes(&stream, now);
    assert_eq!(
        arm_acks(&mut p, now),
        [MavResult::MAV_RESULT_TEMPORARILY_REJECTED]
    );
    assert_eq!(p.status().state, FlightState::Disarmed);
}

/// Given a board with a store, when a storage reset (MAV_CMD_PREFLIGHT_STORAGE, param1 = 2) is
/// accepted, then arming waits for the store as after a PARAM_SET.
#[test]
fn an_arm_waits_for_a_storage_reset() {
    let (mut p, now) = ready(true);
    p.on_link_bytes(&command(MavCmd::MAV_CMD_PREFLIGHT_STORAGE, 2.0, 0.0), now);
    assert!(p.storage_busy());
    p.on_link_bytes(&command(ARM, 1.0, 0.0), now);
    assert_eq!(
        arm_acks(&mut p, now),
        [MavResult::MAV_RESULT_TEMPORARILY_REJECTED]
    );
}

/// Given a board without a store (QEMU, SIL), when a certified PARAM_SET is accepted and an
/// arm follows at once, then it is ACCEPTED, and what the app reports changes nothing.
#[test]
fn without_a_store_arming_does_not_wait() {
    let (mut p, now) = ready(false);
    p.on_link_bytes(&certified_set(&p), now);
    p.set_storage_busy(true);
    assert!(!p.storage_busy());
    p.on_link_bytes(&command(ARM, 1.0, 0.0), now);
    assert_eq!(arm_acks(&mut p, now), [MavResult::MAV_RESULT_ACCEPTED]);
    assert_eq!(p.status().state, FlightState::Armed);
}

/// Given a board with a store and no change made, when the vehicle arms, then nothing holds it.
#[test]
fn an_idle_store_does_not_hold_arming() {
    let (mut p, now) = ready(true);
    assert!(!p.storage_busy());
    p.on_link_bytes(&command(ARM, 1.0, 0.0), now);
    assert_eq!(arm_acks(&mut p, now), [MavResult::MAV_RESULT_ACCEPTED]);
}
