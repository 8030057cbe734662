//! SIL scenario "mission": a mission uploaded over MAVLink (count and items, local NED),
//! certified by the firmware before it is accepted, flown from the ground on the simulated x500:
//! every item reached in order, the landing and the disarm, and no sample of the allocated
//! thrust and torque outside the bounds of the certificate the firmware checked for that
//! mission (recomputed here from the same items, start and flight configuration).

use controller_core::waypoint_path::slowdown_to_certify;
use controller_core::{certify, FilterStart, Trajectory};
use firmware::config::FlightConfig;
use firmware::frames;
use firmware::ground_station;
use firmware::link::mavlink::dialects::common::{MavCmd, MavMessage};
use firmware::mission::{plan, GlobalFrame, MissionItem};
use firmware::pipeline::{gate_check, FlightPipeline};
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
        assert!(samples.len() > 1000, "{}", samples.len());
        let start = start.expect("the mission was flown");
        let outside = outside_certificate(&setup.flight, &items, start, &samples);
        assert_eq!(outside, 0, "seed {seed}");
    }
}

/// The upload's messages for items (kind, NWU position): count then `MISSION_ITEM_INT`s, at
/// `at_s`, as the scenario file's `mission-upload` sends them.
fn upload(at_s: f64, items: &[(MavCmd, [f32; 3])]) -> Vec<(f64, MavMessage)> {
    let mut out = vec![(at_s, ground_station::mission_count(items.len() as u16))];
    for (i, (command, nwu)) in items.iter().enumerate() {
        let ned = frames::flip_to_array(&Vector3::from(*nwu));
        out.push((
            at_s,
            ground_station::mission_item_local(i as u16, *command, ned, 0.0, 0.0, f32::NAN),
        ));
    }
    out
}

/// Given mission legs allowed 1 m/s and 1 m/s² (`MIS_SPEED`, `MIS_ACCEL`), when a takeoff to
/// 2 m, a 1.6 m leg and a land are uploaded, then the firmware refuses them naming one of
/// Theorem 2's torque conditions with both sides (the left below the right) and flies nothing;
/// when the same path is uploaded with the limits slowed by the factor that certifies it
/// (`slowdown_to_certify` on the plan's constants, as the firmware computes it for its refusal),
/// then it is accepted and flown, every item reached, and no allocated thrust or torque sample
/// leaves that mission's certificate.
#[test]
fn too_fast_path_refused_by_theorem2_then_flown_slowed_inside_its_bounds() {
    let path = [
        (MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0, 0.0, 2.0]),
        (MavCmd::MAV_CMD_NAV_WAYPOINT, [1.5, 0.5, 2.0]),
        (MavCmd::MAV_CMD_NAV_LAND, [1.5, 0.5, 0.0]),
    ];
    let mut setup = scenarios::by_name("mission", 1).expect("embedded scenario");
    setup.flight.reference.mission_speed = 1.0;
    setup.flight.reference.mission_acceleration = 1.0;
    setup.commands = vec![(0.0, ground_station::arm(false))];
    setup.commands.extend(upload(0.1, &path));
    setup.commands.push((0.5, ground_station::mission_start()));
    let s = run(&setup, |_| {}).expect("runs");
    let refused = s
        .events
        .iter()
        .find(|(_, e)| e.starts_with("ReferenceRefused"))
        .map(|(_, e)| e.clone())
        .expect("the upload is refused with its condition");
    assert!(refused.contains("theorem2.torque_max_"), "{refused}");
    assert!(
        !s.events.iter().any(|(_, e)| e.starts_with("mission item")),
        "nothing flown: {:?}",
        s.events
    );
    // The factor the firmware offers: the same search on the same plan from the same start
    // (the estimate on the ground; the path keeps the yaw, so the start's yaw does not enter).
    let cfg = setup.flight;
    let items: Vec<MissionItem> = upload(0.0, &path)
        .iter()
        .filter_map(|(_, m)| match m {
            MavMessage::MISSION_ITEM_INT(d) => Some(MissionItem::from_int(d).1),
            _ => None,
        })
        .collect();
    // The firmware's gate: every condition, then the rotor fit with the file's margin.
    let pipeline = FlightPipeline::new(&cfg).expect("boots");
    let gate = |k: &controller_core::TrajectoryConstants<f32>| {
        certify(
            &cfg.vehicle,
            &cfg.limits,
            &cfg.gains,
            k,
            FilterStart::InSaturationBox,
        )
        .is_ok_and(|c| gate_check(&c, &cfg, pipeline.mixer()).is_ok())
    };
    let k = plan(
        &items,
        Vector3::zeros(),
        0.0,
        &cfg.reference,
        &GlobalFrame::NONE,
    )
    .expect("plans")
    .path
    .constants();
    let factor = slowdown_to_certify(&k, 100.0, gate).expect("a slower timing certifies");
    let c = factor;
    setup.flight.reference.mission_speed = 1.0 / c;
    setup.flight.reference.mission_acceleration = 1.0 / (c * c);
    setup.duration_s = 120.0;
    let mut start: Option<Vector3<f32>> = None;
    let mut samples = Vec::new();
    let s = run(&setup, |r| {
        if r.mode == "mission" {
            start.get_or_insert(Vector3::new(r.x_ref_m, r.y_ref_m, r.z_ref_m).cast::<f32>());
            samples.push((r.thrust_N, [r.torque_x_Nm, r.torque_y_Nm, r.torque_z_Nm]));
        }
    })
    .expect("runs");
    let reached: Vec<&str> = s
        .events
        .iter()
        .map(|(_, e)| e.as_str())
        .filter(|e| e.starts_with("mission item"))
        .collect();
    assert_eq!(
        reached,
        [
            "mission item 0 reached",
            "mission item 1 reached",
            "mission item 2 reached"
        ],
        "{:?}",
        s.events
    );
    assert_eq!(s.final_state, "disarmed");
    let outside = outside_certificate(&setup.flight, &items, start.expect("flown"), &samples);
    assert_eq!(outside, 0);
}

/// Samples `(thrust [N], torque [N m])` outside the certificate the firmware checks when it
/// starts `items` from `start` on the ground (filters from zero; every item keeps the yaw, so
/// the start's yaw does not enter), with 1e-6 relative slack for the mixer's f32 rounding.
fn outside_certificate(
    cfg: &FlightConfig,
    items: &[MissionItem],
    start: Vector3<f32>,
    samples: &[(f64, [f64; 3])],
) -> usize {
    let p = plan(items, start, 0.0, &cfg.reference, &GlobalFrame::NONE).expect("plans");
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
    samples
        .iter()
        .filter(|(t, q)| {
            *t < f64::from(lo) * (1.0 - 1e-6)
                || *t > f64::from(hi) * (1.0 + 1e-6)
                || (0..3).any(|i| q[i].abs() > f64::from(tau[i]) * (1.0 + 1e-6))
        })
        .count()
}
