//! The mission microservice against the whole pipeline (the x500 flight file): what a ground
//! station sees on connect, an upload accepted and downloaded back, uploads refused with the
//! certificate's condition and the slow-down that certifies, capacity and frames refused
//! cleanly, a mission flown to each item reached.

use mavlink::dialects::common::{
    MavCmd, MavMessage, MavMissionResult, MISSION_ACK_DATA, MISSION_COUNT_DATA,
    MISSION_CURRENT_DATA, MISSION_ITEM_INT_DATA, MISSION_ITEM_REACHED_DATA,
    MISSION_REQUEST_INT_DATA, STATUSTEXT_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

use super::{armed_pipeline, fly_ticks, frames};
use crate::config::FlightConfig;
use crate::ground_station as gs;
use crate::link;
use crate::pipeline::*;

/// Sends `m` as the ground station (255, 190) and returns the frames of the next telemetry.
fn exchange(p: &mut FlightPipeline, m: &MavMessage, now: u64) -> Vec<(u32, Vec<u8>)> {
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(m, 255, 190, 0, &mut b);
    p.on_link_bytes(&b[..n], now);
    let mut out = [0u8; 4096];
    let n = p.telemetry(now, &mut out);
    frames(&out[..n])
}

fn find<D: MessageData>(frames: &[(u32, Vec<u8>)]) -> Vec<(D, Vec<u8>)> {
    frames
        .iter()
        .filter(|f| f.0 == D::ID)
        .map(|f| {
            (
                D::deser(MavlinkVersion::V2, &f.1).expect("decodes"),
                f.1.clone(),
            )
        })
        .collect()
}

fn texts(frames: &[(u32, Vec<u8>)]) -> Vec<String> {
    find::<STATUSTEXT_DATA>(frames)
        .into_iter()
        .map(|(t, _)| {
            let b: [u8; 50] = t.text.into();
            String::from_utf8_lossy(&b)
                .trim_end_matches('\0')
                .to_string()
        })
        .collect()
}

/// Uploads `items` as a ground station does (count, then each requested item); returns the
/// final ack's result and the frames received after the last item.
fn upload(
    p: &mut FlightPipeline,
    items: &[MavMessage],
    now: u64,
) -> (MavMissionResult, Vec<(u32, Vec<u8>)>) {
    let mut got = exchange(p, &gs::mission_count(items.len() as u16), now);
    for (i, item) in items.iter().enumerate() {
        let req = find::<MISSION_REQUEST_INT_DATA>(&got);
        assert_eq!(req.len(), 1, "one request for item {i}: {got:?}");
        assert_eq!(req[0].0.seq as usize, i);
        assert_eq!(
            (req[0].0.target_system, req[0].0.target_component),
            (255, 190)
        );
        got = exchange(p, item, now + 1 + i as u64);
    }
    let ack = find::<MISSION_ACK_DATA>(&got);
    assert_eq!(ack.len(), 1, "{got:?}");
    (ack[0].0.mavtype, got)
}

/// A calibrated, disarmed pipeline on the x500 flight file whose poses hold it 1 m up, with
/// the time reached (parameters can be set).
fn disarmed_pipeline() -> (FlightPipeline, u64) {
    let mut c = FlightConfig::built();
    c.gyro_calibration_samples = 50;
    let mut p = FlightPipeline::new(&c).expect("boots");
    let now = fly_ticks(&mut p, 0, 60, true);
    (p, now)
}

/// A takeoff to 2 m, a 1.6 m leg turning 30°, a land.
fn three_items() -> [MavMessage; 3] {
    [
        gs::mission_item_local(
            0,
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            [0.0, 0.0, -2.0],
            0.0,
            0.0,
            f32::NAN,
        ),
        waypoint(1, [1.5, -0.5, -2.0], 30.0),
        gs::mission_item_local(
            2,
            MavCmd::MAV_CMD_NAV_LAND,
            [1.5, -0.5, 0.0],
            0.0,
            0.0,
            f32::NAN,
        ),
    ]
}

fn waypoint(seq: u16, ned: [f32; 3], yaw_deg: f32) -> MavMessage {
    gs::mission_item_local(seq, MavCmd::MAV_CMD_NAV_WAYPOINT, ned, 0.0, 0.0, yaw_deg)
}

/// Given a vehicle with no mission, when a ground station asks for the mission, the fence and
/// the rally points on connect (QGroundControl's sequence), then each list is empty and the
/// answer carries the type asked for.
#[test]
fn given_no_mission_when_lists_requested_then_each_is_empty() {
    let mut p = FlightPipeline::new(&FlightConfig::built()).expect("boots");
    for t in [0u8, 1, 2] {
        // With the extension byte `mission_type` (left out for 0, as MAVLink 2 truncates it).
        let bytes = super::super::mission_protocol::tests_support::request_list_with_type(t);
        p.on_link_bytes(&bytes, 1_000);
        let mut out = [0u8; 1024];
        let k = p.telemetry(1_000, &mut out);
        let counts = find::<MISSION_COUNT_DATA>(&frames(&out[..k]));
        assert_eq!(counts.len(), 1);
        assert_eq!(counts[0].0.count, 0);
        assert_eq!(
            counts[0].1.get(4).copied().unwrap_or(0),
            t,
            "mission_type echoed"
        );
    }
}

/// Given an armed vehicle, when a certifiable three-item mission is uploaded, then it is
/// accepted, and a download returns the same items.
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn given_certifiable_mission_when_uploaded_then_accepted_and_downloaded_back() {
    let (mut p, now) = armed_pipeline();
    let items = three_items();
    let (result, got) = upload(&mut p, &items, now);
    assert_eq!(
        result,
        MavMissionResult::MAV_MISSION_ACCEPTED,
        "{:?}",
        texts(&got)
    );
    let got = exchange(&mut p, &gs::mission_request_list(), now + 100);
    assert_eq!(find::<MISSION_COUNT_DATA>(&got)[0].0.count, 3);
    for (i, sent) in items.iter().enumerate() {
        let got = exchange(&mut p, &gs::mission_request(i as u16), now + 200 + i as u64);
        let item = &find::<MISSION_ITEM_INT_DATA>(&got)[0].0;
        let MavMessage::MISSION_ITEM_INT(sent) = sent else {
            unreachable!()
        };
        assert_eq!(
            (
                item.seq,
                item.command,
                item.frame,
                item.x,
                item.y,
                item.z.to_bits()
            ),
            (
                sent.seq,
                sent.command,
                sent.frame,
                sent.x,
                sent.y,
                sent.z.to_bits()
            )
        );
        assert_eq!((item.target_system, item.target_component), (255, 190));
    }
}

/// Given a disarmed x500 whose mission legs may reach 1 m/s, 1 m/s² and 0.15 rad/s
/// (`MIS_SPEED`, `MIS_ACCEL`, `MIS_YAW_RATE`), when a takeoff, a 1.6 m leg with a 30° turn and a
/// land are uploaded, then the upload is denied naming Theorem 2's yaw torque condition with
/// both sides and the slow-down that certifies, and the stored mission is unchanged; when the
/// limits are divided by that factor (its square for the acceleration), then the same path is
/// accepted.
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn given_too_fast_mission_when_uploaded_then_denied_naming_theorem2_and_the_slowdown() {
    let (mut p, now) = disarmed_pipeline();
    let keep = [waypoint(0, [0.0, 0.0, -1.0], f32::NAN)];
    assert_eq!(
        upload(&mut p, &keep, now).0,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    let set = |p: &mut FlightPipeline, c: f32, t: u64| {
        exchange(p, &gs::param_set("MIS_SPEED", 1.0 / c), t);
        exchange(p, &gs::param_set("MIS_ACCEL", 1.0 / (c * c)), t + 1);
        exchange(p, &gs::param_set("MIS_YAW_RATE", 0.15 / c), t + 2);
        assert_eq!(p.config().reference.mission_speed, 1.0 / c);
    };
    set(&mut p, 1.0, now + 10);
    let mission = three_items();
    let (result, got) = upload(&mut p, &mission, now + 20);
    assert_eq!(result, MavMissionResult::MAV_MISSION_DENIED);
    let t = texts(&got);
    assert_eq!(t[0], "mission denied: theorem2.torque_max_yaw", "{t:?}");
    assert!(t[1].contains("slower certifies"), "{t:?}");
    let sides: Vec<f32> = t[1]
        .split(';')
        .next()
        .map(|s| {
            s.split(" vs ")
                .filter_map(|x| x.trim().parse().ok())
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(sides.len(), 2, "{t:?}");
    assert!(
        sides[0] <= sides[1],
        "a failed condition has lhs <= rhs: {t:?}"
    );
    let factor: f32 = t[1]
        .split(';')
        .nth(1)
        .and_then(|s| s.trim().split('x').next())
        .and_then(|s| s.parse().ok())
        .expect("a factor");
    assert!(factor > 1.0, "{factor}");
    let got = exchange(&mut p, &gs::mission_request_list(), now + 30);
    assert_eq!(
        find::<MISSION_COUNT_DATA>(&got)[0].0.count,
        1,
        "the old mission is kept"
    );
    set(&mut p, factor, now + 40);
    let (result, got) = upload(&mut p, &mission, now + 50);
    assert_eq!(
        result,
        MavMissionResult::MAV_MISSION_ACCEPTED,
        "{:?}",
        texts(&got)
    );
}

/// Refused cleanly, nothing stored: more items than the capacity (`NO_SPACE`), a global frame
/// (`UNSUPPORTED_FRAME`), an unsupported command (`UNSUPPORTED`), a land that is not last
/// (`INVALID_SEQUENCE`).
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn bad_uploads_are_refused_and_lose_nothing() {
    let (mut p, now) = armed_pipeline();
    let got = exchange(&mut p, &gs::mission_count(33), now);
    assert_eq!(
        find::<MISSION_ACK_DATA>(&got)[0].0.mavtype,
        MavMissionResult::MAV_MISSION_NO_SPACE
    );
    let MavMessage::MISSION_ITEM_INT(mut global) = waypoint(0, [0.0, 0.0, -1.0], 0.0) else {
        unreachable!()
    };
    global.frame = mavlink::dialects::common::MavFrame::MAV_FRAME_GLOBAL;
    let (r, got) = upload(&mut p, &[MavMessage::MISSION_ITEM_INT(global)], now + 10);
    assert_eq!(r, MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME);
    assert!(
        texts(&got)[0].contains("global frame: no origin"),
        "{:?}",
        texts(&got)
    );
    let loiter =
        gs::mission_item_local(0, MavCmd::MAV_CMD_NAV_LOITER_UNLIM, [0.0; 3], 0.0, 0.0, 0.0);
    assert_eq!(
        upload(&mut p, &[loiter], now + 20).0,
        MavMissionResult::MAV_MISSION_UNSUPPORTED
    );
    let land = gs::mission_item_local(0, MavCmd::MAV_CMD_NAV_LAND, [0.0; 3], 0.0, 0.0, 0.0);
    assert_eq!(
        upload(
            &mut p,
            &[land, waypoint(1, [0.0, 0.0, -1.0], 0.0)],
            now + 30
        )
        .0,
        MavMissionResult::MAV_MISSION_INVALID_SEQUENCE
    );
    let got = exchange(&mut p, &gs::mission_request_list(), now + 40);
    assert_eq!(find::<MISSION_COUNT_DATA>(&got)[0].0.count, 0);
}

/// Given a stored mission, when cleared, then the list is empty; a count of 0 clears too.
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn clear_all_empties_the_mission() {
    let (mut p, now) = armed_pipeline();
    let one = [waypoint(0, [0.0, 0.0, -1.0], f32::NAN)];
    assert_eq!(
        upload(&mut p, &one, now).0,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    let got = exchange(&mut p, &gs::mission_clear_all(), now + 10);
    assert_eq!(
        find::<MISSION_ACK_DATA>(&got)[0].0.mavtype,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    let got = exchange(&mut p, &gs::mission_request_list(), now + 20);
    assert_eq!(find::<MISSION_COUNT_DATA>(&got)[0].0.count, 0);
}

/// Given an armed vehicle on the ground (its poses hold it 1 m up) and a mission of a takeoff
/// to that height and a waypoint there, when the mission is started, then the mode is the
/// mission's, each item is reported reached in order with `MISSION_CURRENT` following, and at
/// the end the vehicle hovers at the last stop.
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn started_mission_reports_each_item_reached_then_hovers() {
    let (mut p, now) = armed_pipeline();
    let items = [
        gs::mission_item_local(
            0,
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            [0.0, 0.0, -1.0],
            0.0,
            0.0,
            f32::NAN,
        ),
        gs::mission_item_local(
            1,
            MavCmd::MAV_CMD_NAV_WAYPOINT,
            [0.0, 0.0, -1.0],
            0.2,
            0.0,
            f32::NAN,
        ),
    ];
    assert_eq!(
        upload(&mut p, &items, now).0,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    let got = exchange(&mut p, &gs::mission_start(), now + 10);
    assert_eq!(p.status().mode, Mode::Mission, "{:?}", texts(&got));
    assert_eq!(find::<MISSION_CURRENT_DATA>(&got)[0].0.seq, 0);
    let mut reached = Vec::new();
    let mut current = Vec::new();
    let mut t = now + 10;
    for _ in 0..100 {
        t = fly_ticks(&mut p, t, 1, true);
        let mut out = [0u8; 4096];
        let n = p.telemetry(t, &mut out);
        let f = frames(&out[..n]);
        reached.extend(
            find::<MISSION_ITEM_REACHED_DATA>(&f)
                .iter()
                .map(|r| r.0.seq),
        );
        current.extend(find::<MISSION_CURRENT_DATA>(&f).iter().map(|r| r.0.seq));
    }
    assert_eq!(reached, [0, 1]);
    assert_eq!(current, [1], "the next item once the first is done");
    let events = super::drain_events(&mut p);
    let logged: Vec<u16> = events
        .iter()
        .filter_map(|e| match e {
            Event::MissionItemReached { seq } => Some(*seq),
            _ => None,
        })
        .collect();
    assert_eq!(logged, [0, 1]);
    assert_eq!(p.status().mode, Mode::Hover);
}

/// Given a mission flown and interrupted by a kill, when the vehicle is armed again and takes
/// off, then the takeoff starts from where the vehicle is (the reference built at arming), not
/// from the interrupted mission's point, and the mode is the takeoff's.
#[test]
#[cfg(not(feature = "uncertified-paper"))]
fn interrupted_mission_is_not_resumed_after_rearming() {
    let (mut p, now) = armed_pipeline();
    let items = [
        gs::mission_item_local(
            0,
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            [0.0, 0.0, -3.0],
            0.0,
            0.0,
            f32::NAN,
        ),
        waypoint(1, [2.0, 0.0, -3.0], f32::NAN),
    ];
    assert_eq!(
        upload(&mut p, &items, now).0,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    exchange(&mut p, &gs::mission_start(), now + 10);
    assert_eq!(p.status().mode, Mode::Mission);
    // Fly part of the takeoff leg (the poses hold the vehicle 1 m up), then kill.
    let t = fly_ticks(&mut p, now + 10, 800, true);
    exchange(&mut p, &gs::kill(), t);
    assert_eq!(p.status().state, crate::safety::FlightState::Disarmed);
    let t = fly_ticks(&mut p, t, 10, true);
    exchange(&mut p, &gs::arm(false), t);
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    exchange(&mut p, &gs::takeoff(0.5), t + 10);
    assert_eq!(p.status().mode, Mode::Takeoff);
    fly_ticks(&mut p, t + 10, 1, true);
    // The reference starts at the vehicle (1 m up, NWU z = 1), not at the mission's point.
    let r = p.status().reference_position;
    assert!(
        (r[2] - 1.0).abs() < 0.05,
        "reference z {} (mission's was above 1 m)",
        r[2]
    );
}

/// Given an origin set by `SET_GPS_GLOBAL_ORIGIN` (answered with `GPS_GLOBAL_ORIGIN`), when a
/// waypoint 10⁻⁵° north of it at home's height + 1 m (relative altitude) is uploaded, then it is
/// accepted; the same before any origin was refused (above).
#[test]
#[cfg(not(feature = "uncertified-paper"))]
// SET_GPS_GLOBAL_ORIGIN is superseded by MAV_CMD_DO_SET_GLOBAL_ORIGIN (2025) but is what
// MAVProxy and QGroundControl send.
#[allow(deprecated)]
fn global_items_fly_once_an_origin_is_set() {
    let (mut p, now) = armed_pipeline();
    let origin =
        MavMessage::SET_GPS_GLOBAL_ORIGIN(mavlink::dialects::common::SET_GPS_GLOBAL_ORIGIN_DATA {
            latitude: 470_000_000,
            longitude: 80_000_000,
            altitude: 400_000,
            target_system: 1,
        });
    let got = exchange(&mut p, &origin, now);
    let echo = find::<mavlink::dialects::common::GPS_GLOBAL_ORIGIN_DATA>(&got);
    assert_eq!(echo.len(), 1);
    assert_eq!(
        (echo[0].0.latitude, echo[0].0.longitude, echo[0].0.altitude),
        (470_000_000, 80_000_000, 400_000)
    );
    let MavMessage::MISSION_ITEM_INT(mut global) = waypoint(0, [0.0, 0.0, -1.0], f32::NAN) else {
        unreachable!()
    };
    global.frame = mavlink::dialects::common::MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT;
    global.x = 470_000_100;
    global.y = 80_000_000;
    global.z = 1.0;
    let (r, got) = upload(&mut p, &[MavMessage::MISSION_ITEM_INT(global)], now + 10);
    assert_eq!(
        r,
        MavMissionResult::MAV_MISSION_ACCEPTED,
        "{:?}",
        texts(&got)
    );
}
