//! `command = "mission-upload"` in a SIL scenario file: `items`, a list of inline tables
//! `{ kind = "takeoff" | "waypoint" | "land", position_m = [x, y, z] (NWU), hold_s,
//! yaw_rad (NWU; absent: keep the yaw), acceptance_radius_m (0 or absent: the vehicle's) }`,
//! sent as `MISSION_COUNT` and one `MISSION_ITEM_INT` per item in `MAV_FRAME_LOCAL_NED` at the
//! command's time, in order (the vehicle takes items in sequence whether or not it has asked
//! for them yet).

use firmware::frames;
use firmware::ground_station;
use firmware::link::mavlink::dialects::common::{MavCmd, MavMessage};
use nalgebra::Vector3;
use serde::Deserialize;

/// One item of `items`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ItemKeys {
    kind: ItemKind,
    position_m: [f32; 3],
    #[serde(default)]
    hold_s: f32,
    #[serde(default)]
    yaw_rad: Option<f32>,
    #[serde(default)]
    acceptance_radius_m: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum ItemKind {
    Takeoff,
    Waypoint,
    Land,
}

/// The upload's messages: the count, then each item. `key(k)` names a key in errors.
///
/// Errors: a non-finite position, hold, yaw or radius, a negative hold or radius, no items.
pub(super) fn messages(
    key: &dyn Fn(&str) -> String,
    items: &[ItemKeys],
) -> Result<Vec<MavMessage>, String> {
    if items.is_empty() || items.len() > usize::from(u16::MAX) {
        return Err(format!("{}: must list at least one item", key("items")));
    }
    let mut out = vec![ground_station::mission_count(items.len() as u16)];
    for (i, item) in items.iter().enumerate() {
        let k = |f: &str| key(&format!("items[{i}].{f}"));
        if !item.position_m.iter().all(|v| v.is_finite()) {
            return Err(format!("{}: must be finite", k("position_m")));
        }
        for (name, v) in [
            ("hold_s", item.hold_s),
            ("acceptance_radius_m", item.acceptance_radius_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{}: must be finite and >= 0, got {v}", k(name)));
            }
        }
        let yaw_deg = match item.yaw_rad {
            Some(y) if y.is_finite() => frames::flip_yaw(y).to_degrees(),
            Some(y) => return Err(format!("{}: must be finite, got {y}", k("yaw_rad"))),
            None => f32::NAN,
        };
        let command = match item.kind {
            ItemKind::Takeoff => MavCmd::MAV_CMD_NAV_TAKEOFF,
            ItemKind::Waypoint => MavCmd::MAV_CMD_NAV_WAYPOINT,
            ItemKind::Land => MavCmd::MAV_CMD_NAV_LAND,
        };
        let ned = frames::flip_to_array(&Vector3::from(item.position_m));
        out.push(ground_station::mission_item_local(
            i as u16,
            command,
            ned,
            item.hold_s,
            item.acceptance_radius_m,
            yaw_deg,
        ));
    }
    Ok(out)
}
