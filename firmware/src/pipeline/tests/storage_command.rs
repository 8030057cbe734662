//! `MAV_CMD_PREFLIGHT_STORAGE`: param1 = 2 resets the parameters to the flight file the
//! pipeline was built with and tells the store ([`Event::ParamsReset`]); only while disarmed.
//! Given/when/then, on the host.

use mavlink::dialects::common::MavResult;

use super::{arm_attempt, command, drain_events, sent_acks};
use crate::param_store::{MemoryStore, ParamStore};
use crate::params::PARAMS;
use crate::pipeline::*;

fn acks(p: &mut FlightPipeline, now_us: u64) -> Vec<(MavCmd, MavResult)> {
    sent_acks(p, now_us)
        .into_iter()
        .map(|a| (a.command, a.result))
        .collect()
}

const STORAGE: MavCmd = MavCmd::MAV_CMD_PREFLIGHT_STORAGE;

/// Given a disarmed vehicle flying a restored, tuned set, when the ground station asks to write
/// (param1 = 1) and then to reset (param1 = 2), then the write is UNSUPPORTED (every accepted
/// set is already saved) and the reset ACCEPTED: the flight file's configuration and boot
/// report are back, and the store is told.
#[test]
fn a_storage_reset_flies_the_flight_file_again() {
    let c = FlightConfig::built();
    let fresh = FlightPipeline::new(&c).unwrap();
    let mut p = FlightPipeline::new(&c).unwrap();
    let mut store = MemoryStore::new();
    let kf = PARAMS.iter().position(|d| d.name == "POS_KF").unwrap();
    store.store(kf, 0.8 * c.gains.position.kf).unwrap();
    assert_eq!(p.restore_params(&store), Ok(1));
    assert_ne!(p.boot_report(), fresh.boot_report());

    p.on_link_bytes(&command(STORAGE, 1.0, 0.0), 0);
    assert_ne!(*p.config(), c);
    p.on_link_bytes(&command(STORAGE, 2.0, 0.0), 0);
    assert_eq!(
        acks(&mut p, 0),
        [
            (STORAGE, MavResult::MAV_RESULT_UNSUPPORTED),
            (STORAGE, MavResult::MAV_RESULT_ACCEPTED)
        ]
    );
    assert_eq!(*p.config(), c);
    assert_eq!(p.boot_report(), fresh.boot_report());
    assert!(drain_events(&mut p).contains(&Event::ParamsReset));
}

/// Given an armed vehicle, when a reset is asked, then it is DENIED and the store is not told.
#[test]
fn a_storage_reset_while_armed_is_denied() {
    let (mut p, now) = arm_attempt(FlightConfig::built());
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    drain_events(&mut p);
    let _ = acks(&mut p, now);
    p.on_link_bytes(&command(STORAGE, 2.0, 0.0), now);
    assert_eq!(acks(&mut p, now), [(STORAGE, MavResult::MAV_RESULT_DENIED)]);
    assert!(!drain_events(&mut p).contains(&Event::ParamsReset));
}
