//! SIL scenario "mission": a mission uploaded over MAVLink (count and items, local NED),
//! certified by the firmware before it is accepted, flown from the ground on the simulated x500:
//! every item reached in order, the landing and the disarm, and no sample of the allocated
//! thrust and torque outside the bounds of the certificate the firmware checked for that
//! mission (recomputed here from the same items, start and flight configuration).

use controller_core::{certify, FilterStart, Trajectory};
use firmware::link::mavlink::dialects::common::MavMessage;
use firmware::mission::{plan, MissionItem};
use host_sim::harness::sil::{run, scenarios};
use nalgebra::Vector3;

#[test]
fn uploaded_mission_is_flown_item_by_item_inside_its_certified_bounds() {
    for seed in [1, 2, 3] {
        let setup = scenarios::by_name("mission", seed).expect("embedded scenario");
        let items: Vec<MissionItem> = setup
            .commands
            .iter()
            .filter_map(|(_, m)| match m {
                MavMessage::MISSION_ITEM_INT(d) => Some(MissionItem::from_int(d).1),
                _ => None,
            })
            .collect();
        assert_eq!(items.len(), 4);
        // The allocated thrust and torque of every tick flown in the mission, and where the
        // mission's reference started (its first sample is its start, exactly, in f32).
        let mut start: Option<Vector3<f32>> = None;
        let mut samples = Vec::new();
        let s = run(&setup, |r| {
            if r.mode == "mission" {
                start.get_or_insert(Vector3::new(r.x_ref_m, r.y_ref_m, r.z_ref_m).cast::<f32>());
                samples.push((r.thrust_N, [r.torque_x_Nm, r.torque_y_Nm, r.torque_z_Nm]));
            }
        })
        .expect("runs");
        let events: Vec<&str> = s.events.iter().map(|(_, e)| e.as_str()).collect();
        let reached: Vec<&str> = events
            .iter()
            .copied()
            .filter(|e| e.starts_with("mission item"))
            .collect();
        assert_eq!(
            reached,
            [
                "mission item 0 reached",
                "mission item 1 reached",
                "mission item 2 reached",
                "mission item 3 reached"
            ],
            "seed {seed}: {events:?}"
        );
        assert!(events.iter().any(|e| e.contains("mode land")), "{events:?}");
        assert!(events
            .iter()
            .any(|e| e.contains("armed -> disarmed (landed)")));
        assert_eq!(s.final_state, "disarmed");
        assert_eq!(s.refused_commands, 0);
        assert_eq!(s.mixer_saturated_ticks, 0);
        // The certificate the firmware checked at the start: the plan from the start (yaw
        // kept by every item, so the start's yaw does not enter), filters from zero (on the
        // ground).
        let cfg = &setup.flight;
        let start = start.expect("the mission was flown");
        let p = plan(&items, start, 0.0, &cfg.reference).expect("plans");
        let cert = certify(
            &cfg.vehicle,
            &cfg.limits,
            &cfg.gains,
            &p.path.constants(),
            FilterStart::Zero,
        )
        .expect("certifies");
        assert_eq!(cert.violations().count(), 0);
        let (lo, hi) = cfg.thrust.interval(&cert.bounds).expect("interval");
        let tau = cert.bounds.torque_max;
        assert!(samples.len() > 1000, "{}", samples.len());
        let outside = samples
            .iter()
            .filter(|(t, q)| {
                *t < f64::from(lo) * (1.0 - 1e-6)
                    || *t > f64::from(hi) * (1.0 + 1e-6)
                    || (0..3).any(|i| q[i].abs() > f64::from(tau[i]) * (1.0 + 1e-6))
            })
            .count();
        assert_eq!(outside, 0, "seed {seed}: [{lo}, {hi}] N, {tau:?} N m");
    }
}
