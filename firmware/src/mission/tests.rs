//! The upload state and the plan, alone: duplicates and gaps re-requested, overdue items asked
//! again then the upload cancelled, another sender ignored; local NED items to NWU stops,
//! takeoff keeping x and y, a NaN yaw keeping the yaw.

use mavlink::dialects::common::{MavCmd, MavFrame, MavMissionResult};
use nalgebra::Vector3;

use super::transfer::{RETRIES, RETRY_US};
use super::*;
use crate::config::FlightConfig;
use crate::link::Sender;

const GCS: Sender = Sender {
    system: 255,
    component: 190,
};

fn item(command: MavCmd, ned: [f32; 3], yaw_deg: f32) -> MissionItem {
    MissionItem {
        params: [0.0, 0.0, 0.0, yaw_deg],
        x: (ned[0] * 1e4) as i32,
        y: (ned[1] * 1e4) as i32,
        z: ned[2],
        command,
        frame: MavFrame::MAV_FRAME_LOCAL_NED,
        autocontinue: 1,
    }
}

/// Given an upload of two items, when item 1 comes first, item 0 twice, or a stranger sends
/// one, then the expected item is requested again (or the stranger ignored); the two in order
/// complete it.
#[test]
fn upload_requests_in_order_and_ignores_others() {
    let mut t = Transfer::new();
    assert_eq!(t.begin(GCS, 2, 0), 0);
    let a = item(MavCmd::MAV_CMD_NAV_WAYPOINT, [1.0, 0.0, -1.0], 0.0);
    let stranger = Sender {
        system: 9,
        component: 1,
    };
    assert_eq!(t.item(stranger, 0, a, 1), UploadStep::Ignored);
    assert_eq!(t.item(GCS, 1, a, 2), UploadStep::Request(0));
    assert_eq!(t.item(GCS, 0, a, 3), UploadStep::Request(1));
    assert_eq!(t.item(GCS, 0, a, 4), UploadStep::Request(1));
    match t.item(GCS, 1, a, 5) {
        UploadStep::Complete(items) => assert_eq!(items.len(), 2),
        other => panic!("{other:?}"),
    }
    assert!(!t.uploading());
}

/// Given an upload waiting for an item, when nothing comes, then the item is requested again
/// every `RETRY_US`, and after `RETRIES` requests the upload is cancelled.
#[test]
fn overdue_items_are_requested_again_then_cancelled() {
    let mut t = Transfer::new();
    t.begin(GCS, 3, 0);
    assert_eq!(t.poll(RETRY_US - 1), None);
    let mut now = 0;
    for _ in 0..RETRIES {
        now += RETRY_US;
        assert_eq!(t.poll(now), Some(Ok((0, GCS))));
    }
    assert_eq!(t.poll(now + RETRY_US), Some(Err(GCS)));
    assert!(!t.uploading());
}

/// Local NED items become NWU stops; a takeoff keeps x and y; a NaN yaw keeps the yaw; the
/// yaw turns from NED (clockwise) to NWU (counter-clockwise).
#[test]
fn plan_converts_frames_and_keeps_what_is_not_given() {
    let cfg = FlightConfig::paper().reference;
    let items = [
        item(MavCmd::MAV_CMD_NAV_TAKEOFF, [9.0, 9.0, -2.0], f32::NAN),
        item(MavCmd::MAV_CMD_NAV_WAYPOINT, [1.0, 2.0, -3.0], 90.0),
        item(MavCmd::MAV_CMD_NAV_WAYPOINT, [1.0, 2.0, -3.0], f32::NAN),
    ];
    let p = plan(
        &items,
        Vector3::new(0.5, -0.5, 0.0),
        0.3,
        &cfg,
        &GlobalFrame::NONE,
    )
    .expect("plans");
    let (s0, y0) = p.path.stop(0).expect("stop 0");
    assert_eq!(s0, Vector3::new(0.5, -0.5, 2.0));
    assert_eq!(y0, 0.3);
    let (s1, y1) = p.path.stop(1).expect("stop 1");
    assert!((s1 - Vector3::new(1.0, -2.0, 3.0)).norm() < 1e-6);
    assert!((y1 + core::f32::consts::FRAC_PI_2).abs() < 1e-6);
    let (_, y2) = p.path.stop(2).expect("stop 2");
    assert!((y2 - y1).abs() < 1e-6, "{y2} vs {y1}");
    assert_eq!(p.radius[1], cfg.mission_acceptance_radius);
    assert!(!p.land_at_end);
}

/// A position 10 km out (e.g. a latitude read as local metres) and a negative hold are
/// refused, naming the item.
#[test]
fn plan_refuses_far_positions_and_negative_holds() {
    let cfg = FlightConfig::paper().reference;
    let mut far = item(MavCmd::MAV_CMD_NAV_WAYPOINT, [0.0; 3], 0.0);
    far.x = i32::MAX;
    let e = plan(&[far], Vector3::zeros(), 0.0, &cfg, &GlobalFrame::NONE).expect_err("refused");
    assert_eq!(
        (e.result, e.seq),
        (MavMissionResult::MAV_MISSION_INVALID, 0)
    );
    let mut hold = item(MavCmd::MAV_CMD_NAV_WAYPOINT, [0.0; 3], 0.0);
    hold.params[0] = -1.0;
    let ok = item(MavCmd::MAV_CMD_NAV_WAYPOINT, [0.0; 3], 0.0);
    let e =
        plan(&[ok, hold], Vector3::zeros(), 0.0, &cfg, &GlobalFrame::NONE).expect_err("refused");
    assert_eq!(
        (e.result, e.seq),
        (MavMissionResult::MAV_MISSION_INVALID_PARAM1, 1)
    );
}

/// A global item 10⁻⁵° north and east of an origin at 47° N lands 1.11 m north and
/// 1.11 · cos 47° m east (the tangent plane), its altitude above mean sea level or above home as
/// its frame says; without an origin, and in a terrain frame, it is refused.
#[test]
fn global_items_are_placed_about_the_origin() {
    use super::origin::EARTH_RADIUS;
    let cfg = FlightConfig::paper().reference;
    let origin = GlobalOrigin::new(470_000_000, 80_000_000, 400_000).expect("valid origin");
    let global = GlobalFrame {
        origin: Some(origin),
        home_up: 0.25,
    };
    let item = |frame, z| MissionItem {
        params: [0.0, 0.0, 0.0, f32::NAN],
        x: 470_000_100,
        y: 80_000_100,
        z,
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        frame,
        autocontinue: 1,
    };
    let d = 1e-5f64.to_radians() * EARTH_RADIUS;
    let east = d * 47f64.to_radians().cos();
    let absolute = item(MavFrame::MAV_FRAME_GLOBAL, 402.0);
    let p = plan(&[absolute], Vector3::zeros(), 0.0, &cfg, &global).expect("plans");
    let (s, _) = p.path.stop(0).expect("stop");
    // NWU: north, west (minus east), up.
    assert!((f64::from(s.x) - d).abs() < 1e-4, "{s:?} vs {d}");
    assert!((f64::from(s.y) + east).abs() < 1e-4, "{s:?} vs {east}");
    assert!((s.z - 2.0).abs() < 1e-4, "{s:?}");
    let relative = item(MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT, 1.5);
    let p = plan(&[relative], Vector3::zeros(), 0.0, &cfg, &global).expect("plans");
    assert!((p.path.stop(0).expect("stop").0.z - 1.75).abs() < 1e-5);
    let e =
        plan(&[relative], Vector3::zeros(), 0.0, &cfg, &GlobalFrame::NONE).expect_err("no origin");
    assert_eq!(e.result, MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME);
    let terrain = item(MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT, 1.5);
    let e = plan(&[terrain], Vector3::zeros(), 0.0, &cfg, &global).expect_err("terrain");
    assert_eq!(e.result, MavMissionResult::MAV_MISSION_UNSUPPORTED_FRAME);
    assert_eq!(GlobalOrigin::new(900_000_000, 0, 0), None, "a pole");
    assert_eq!(GlobalOrigin::new(0, 1_800_000_001, 0), None);
}
