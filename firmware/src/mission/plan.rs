//! From the stored items to a reference the controller can fly: a [`WaypointPath`] through the
//! items' stops, starting at rest where the reference is when the mission starts, with the
//! items' sequence numbers and acceptance radii. The path's Assumption 1 constants are what the
//! certificate gate checks, at upload and again at the start.
//!
//! Items understood (frame `MAV_FRAME_LOCAL_NED`, positions NED \[m\], converted to the
//! controller's NWU by [`crate::frames`]):
//! - `MAV_CMD_NAV_WAYPOINT`: fly to (x, y, z); param1 hold \[s\], param2 acceptance radius
//!   \[m\] (0: the configured one), param4 yaw \[deg, NED\] (NaN: keep the yaw).
//! - `MAV_CMD_NAV_TAKEOFF`: straight up (or down) to z, keeping x, y; param4 yaw.
//! - `MAV_CMD_NAV_LAND`: fly at the current height to above (x, y), then land there (the land
//!   mode's descent and landed detection); it must be the last item.
//!
//! Global frames (`MAV_FRAME_GLOBAL`, `_RELATIVE_ALT` and their `_INT` forms) are flown once the
//! local frame's global origin is set (`SET_GPS_GLOBAL_ORIGIN`, [`super::origin`]); without one
//! they are refused (`MAV_MISSION_UNSUPPORTED_FRAME`), as are the terrain frames and any other.
//! Refused too: other commands
//! (`MAV_MISSION_UNSUPPORTED`), a non-finite or negative parameter, a position beyond
//! 10 km (`MAV_MISSION_INVALID_PARAM1`..`_PARAM7`, `MAV_MISSION_INVALID`), a land item that is
//! not last (`MAV_MISSION_INVALID_SEQUENCE`).

use controller_core::waypoint_path::{PathError, PathLimits, Stop, WaypointPath};
use mavlink::dialects::common::{MavCmd, MavFrame, MavMissionResult};
use nalgebra::Vector3;

use super::origin::GlobalOrigin;
use super::CAPACITY;
use crate::config::ReferenceConfig;
use crate::frames;
use crate::link::mission_item::{is_global, MissionItem};

/// Farthest a stop may be from the local origin \[m\]: a guard against mis-scaled coordinates
/// (e.g. latitudes read as a local frame's metres × 10⁴).
pub const MAX_DISTANCE: f32 = 10_000.0;

/// A mission as flown: the path through its stops and, per stop, the item it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plan {
    /// The reference from the start through every stop.
    pub path: WaypointPath<f32, CAPACITY>,
    /// Sequence number of the item behind each stop.
    pub seqs: [u16; CAPACITY],
    /// Acceptance radius of each stop \[m\].
    pub radius: [f32; CAPACITY],
    /// The last item is a land: land when its stop is reached.
    pub land_at_end: bool,
}

/// Why items cannot be planned: the `MISSION_ACK` result, the item and the reason.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanError {
    /// Result for `MISSION_ACK`.
    pub result: MavMissionResult,
    /// Sequence number of the offending item (0 when it concerns the whole mission).
    pub seq: u16,
    /// Why, for `STATUSTEXT`.
    pub reason: &'static str,
}

fn error(result: MavMissionResult, seq: u16, reason: &'static str) -> PlanError {
    PlanError {
        result,
        seq,
        reason,
    }
}

/// Where global items are: the local frame's global origin, and home (the arming point) for the
/// relative-altitude frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlobalFrame {
    /// The local frame's origin on WGS84, if set.
    pub origin: Option<GlobalOrigin>,
    /// Home's height \[m\] (NWU z): relative altitudes are above it.
    pub home_up: f32,
}

impl GlobalFrame {
    /// No origin: global items are refused.
    pub const NONE: Self = Self {
        origin: None,
        home_up: 0.0,
    };
}

/// The plan of `items` from `start` (NWU \[m\]) with yaw `start_yaw` \[rad\] at rest, with the
/// leg limits and default acceptance radius of `cfg`, global items placed by `global`.
///
/// Errors: [`PlanError`] naming the first item that cannot be flown (see the module's list).
pub fn plan(
    items: &[MissionItem],
    start: Vector3<f32>,
    start_yaw: f32,
    cfg: &ReferenceConfig,
    global: &GlobalFrame,
) -> Result<Plan, PlanError> {
    use MavMissionResult as R;
    if items.len() > CAPACITY {
        return Err(error(R::MAV_MISSION_NO_SPACE, 0, "too many items"));
    }
    let mut stops = [Stop {
        position: start,
        yaw: start_yaw,
        hold: 0.0,
    }; CAPACITY];
    let mut seqs = [0u16; CAPACITY];
    let mut radius = [0f32; CAPACITY];
    let (mut at, mut yaw) = (start, start_yaw);
    let mut land_at_end = false;
    for (i, item) in items.iter().enumerate() {
        let seq = i as u16;
        if land_at_end {
            return Err(error(
                R::MAV_MISSION_INVALID_SEQUENCE,
                seq,
                "items after a land",
            ));
        }
        let ned = if is_global(item.frame) {
            let Some(origin) = global.origin else {
                return Err(error(
                    R::MAV_MISSION_UNSUPPORTED_FRAME,
                    seq,
                    "global frame: no origin (SET_GPS_GLOBAL_ORIGIN)",
                ));
            };
            origin
                .to_local_ned(item.frame, item.x, item.y, item.z, -global.home_up)
                .ok_or_else(|| error(R::MAV_MISSION_UNSUPPORTED_FRAME, seq, "terrain frame"))?
        } else if item.frame == MavFrame::MAV_FRAME_LOCAL_NED {
            item.local_ned()
        } else {
            return Err(error(
                R::MAV_MISSION_UNSUPPORTED_FRAME,
                seq,
                "frame: use LOCAL_NED",
            ));
        };
        let [hold, accept, _, yaw_deg] = item.params;
        let target = frames::flip_vector(ned);
        if !target.iter().all(|v| v.is_finite()) || target.norm() > MAX_DISTANCE {
            return Err(error(
                R::MAV_MISSION_INVALID,
                seq,
                "position not finite or > 10 km",
            ));
        }
        if !yaw_deg.is_nan() && !yaw_deg.is_finite() {
            return Err(error(R::MAV_MISSION_INVALID_PARAM4, seq, "yaw not finite"));
        }
        // NaN yaw: keep the current one (MAVLink's "unchanged").
        let stop_yaw = if yaw_deg.is_nan() {
            yaw
        } else {
            frames::flip_yaw(yaw_deg.to_radians())
        };
        let (position, hold, accept) = match item.command {
            MavCmd::MAV_CMD_NAV_WAYPOINT => {
                if !(hold.is_finite() && hold >= 0.0) {
                    return Err(error(R::MAV_MISSION_INVALID_PARAM1, seq, "hold not >= 0"));
                }
                if !(accept.is_finite() && accept >= 0.0) {
                    return Err(error(R::MAV_MISSION_INVALID_PARAM2, seq, "radius not >= 0"));
                }
                (target, hold, accept)
            }
            MavCmd::MAV_CMD_NAV_TAKEOFF => (Vector3::new(at.x, at.y, target.z), 0.0, 0.0),
            MavCmd::MAV_CMD_NAV_LAND => {
                land_at_end = true;
                (Vector3::new(target.x, target.y, at.z), 0.0, 0.0)
            }
            _ => {
                return Err(error(
                    R::MAV_MISSION_UNSUPPORTED,
                    seq,
                    "command not supported",
                ))
            }
        };
        stops[i] = Stop {
            position,
            yaw: stop_yaw,
            hold,
        };
        seqs[i] = seq;
        radius[i] = if accept > 0.0 {
            accept
        } else {
            cfg.mission_acceptance_radius
        };
        at = position;
        yaw = stop_yaw;
    }
    let limits = PathLimits {
        speed: cfg.mission_speed,
        acceleration: cfg.mission_acceleration,
        yaw_rate: cfg.mission_yaw_rate,
        min_duration: 0.5,
    };
    let path = WaypointPath::new(start, start_yaw, &stops[..items.len()], &limits).map_err(
        |e| match e {
            PathError::TooManyStops { .. } => error(R::MAV_MISSION_NO_SPACE, 0, "too many items"),
            PathError::BadStop { index } => {
                error(R::MAV_MISSION_INVALID, index as u16, "stop not finite")
            }
            PathError::BadLimit { .. } => error(R::MAV_MISSION_ERROR, 0, "mission limits invalid"),
        },
    )?;
    Ok(Plan {
        path,
        seqs,
        radius,
        land_at_end,
    })
}
