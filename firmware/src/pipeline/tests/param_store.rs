//! Parameter persistence through [`ParamStore`]: what is saved comes back, and what comes back
//! is certified like a `PARAM_SET` or not taken at all. Given/when/then, on the host.

use controller_core::reference::Trajectory;
use controller_core::{certify, FilterStart};

use super::{arm_attempt, command};
use crate::link;
use crate::param_store::{save, MemoryStore, NoSuchParam, ParamStore};
use crate::params::{ParamError, COUNT, PARAMS};
use crate::pipeline::*;

fn index_of(name: &str) -> usize {
    PARAMS.iter().position(|p| p.name == name).unwrap()
}

/// Given an empty in-memory store, then it holds nothing; when values are stored, then they
/// load back, and an index beyond the table is refused.
#[test]
fn memory_store_round_trips() {
    let mut s = MemoryStore::new();
    assert!((0..=COUNT).all(|i| s.load(i).is_none()));
    s.store(3, 1.25).unwrap();
    s.store(3, 2.5).unwrap();
    assert_eq!(s.load(3), Some(2.5));
    assert_eq!(s.store(COUNT, 1.0), Err(NoSuchParam));
    assert_eq!(s.load(COUNT), None);
}

/// Given a vehicle that took a certified PARAM_SET and saved its parameters, when a freshly
/// booted vehicle restores them, then it flies the same configuration with the same boot
/// report, and every parameter was restored.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn saved_parameters_restore_the_certified_set_up() {
    let c = FlightConfig::built();
    let mut a = FlightPipeline::new(&c).unwrap();
    let kf = 0.8 * c.gains.position.kf;
    let mut m = [0u8; link::MAX_FRAME];
    let set = crate::ground_station::param_set("POS_KF", kf);
    let n = link::encode(&set, 255, 190, 0, &mut m);
    a.on_link_bytes(&m[..n], 0);
    assert_eq!(a.config().gains.position.kf, kf);
    let mut store = MemoryStore::new();
    save(&mut store, a.config()).unwrap();
    assert_eq!(store.load(index_of("POS_KF")), Some(kf));

    let mut b = FlightPipeline::new(&c).unwrap();
    assert_eq!(b.restore_params(&store), Ok(COUNT));
    assert_eq!(b.config(), a.config());
    assert_eq!(b.boot_report(), a.boot_report());
    assert_ne!(
        b.boot_report(),
        FlightPipeline::new(&c).unwrap().boot_report()
    );
}

/// Given a store whose yaw torque limit breaks Theorem 2 (written by another build, say), when
/// it is restored, then nothing is taken and the error names the condition with the sides
/// `certify` computes on the candidate; given a stored NaN, then the error names the parameter.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn an_uncertified_or_unusable_store_restores_nothing() {
    let c = FlightConfig::built();
    let mut p = FlightPipeline::new(&c).unwrap();
    let boot = p.boot_report();
    let rhs_of = |name: &str| {
        boot.certificate
            .conditions
            .iter()
            .find(|k| k.name == name)
            .unwrap()
            .rhs
    };
    let tau_z = 0.5 * (rhs_of("assumption1.torque_max_yaw") + rhs_of("theorem2.torque_max_yaw"));
    // The candidate is the whole store applied: a lower k_f and the yaw limit.
    let mut candidate = c;
    candidate.gains.position.kf = 0.8 * c.gains.position.kf;
    candidate.limits.torque_max.z = tau_z;
    let cert = certify(
        &candidate.vehicle,
        &candidate.limits,
        &candidate.gains,
        &candidate.mission.constants(),
        FilterStart::Zero,
    )
    .unwrap();
    let first = cert.violations().next().unwrap();
    assert_eq!(first.name, "theorem2.torque_max_yaw");

    let mut store = MemoryStore::new();
    store
        .store(index_of("POS_KF"), 0.8 * c.gains.position.kf)
        .unwrap();
    store.store(index_of("LIM_TAU_Z"), tau_z).unwrap();
    assert_eq!(
        p.restore_params(&store),
        Err(RestoreError {
            name: None,
            refusal: ParamRefusal::Condition(GateFailure {
                condition: first.name,
                lhs: first.lhs,
                rhs: first.rhs,
            }),
        })
    );
    store.store(index_of("POS_KP"), f32::NAN).unwrap();
    assert_eq!(
        p.restore_params(&store),
        Err(RestoreError {
            name: Some("POS_KP"),
            refusal: ParamRefusal::Value(ParamError::NotFinite),
        })
    );
    assert_eq!(*p.config(), c);
    assert_eq!(p.boot_report(), boot);
}

/// Given an armed vehicle, when parameters are restored, then it is refused and nothing
/// changes.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn restore_while_armed_is_refused() {
    let (mut p, now) = arm_attempt(FlightConfig::built());
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    let before = *p.config();
    let mut store = MemoryStore::new();
    store
        .store(index_of("POS_KF"), 0.8 * before.gains.position.kf)
        .unwrap();
    assert_eq!(
        p.restore_params(&store).map_err(|e| e.refusal),
        Err(ParamRefusal::Armed)
    );
    assert_eq!(*p.config(), before);
    // Disarmed again (idle on the ground), the same store is taken.
    p.on_link_bytes(
        &command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 0.0),
        now,
    );
    assert_eq!(p.restore_params(&store), Ok(1));
}
