//! The local frame's global origin (`SET_GPS_GLOBAL_ORIGIN`): where the local NED frame's
//! origin lies on the WGS84 ellipsoid, so that mission items in global frames (latitude,
//! longitude, altitude) can be flown in the local frame the vehicle's poses are in.
//!
//! The conversion is the local tangent plane's equirectangular approximation about the origin:
//! north = Δlatitude · R, east = Δlongitude · R · cos(origin latitude), with R = 6 371 000 m
//! (the mean Earth radius). Within [`super::plan::MAX_DISTANCE`] (10 km) of the origin it is
//! within about 0.2 % of the geodesic distances, far inside what a motion-capture or local
//! positioning frame spans in practice.

// The `_INT` global frames are superseded in MAVLink's common set but still what ground stations
// put in MISSION_ITEM_INT.
#![allow(deprecated)]

use mavlink::dialects::common::MavFrame;

/// Mean Earth radius \[m\].
pub const EARTH_RADIUS: f64 = 6_371_000.0;

/// The local frame's origin on WGS84 (MAVLink's integer units).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlobalOrigin {
    /// Latitude \[deg × 10⁷\].
    pub latitude_e7: i32,
    /// Longitude \[deg × 10⁷\].
    pub longitude_e7: i32,
    /// Altitude above mean sea level \[mm\].
    pub altitude_mm: i32,
}

impl GlobalOrigin {
    /// The origin from `SET_GPS_GLOBAL_ORIGIN`'s fields, or `None` when the latitude or longitude
    /// is out of range (|latitude| > 90°, |longitude| > 180°) or the latitude is within 1° of a
    /// pole (where the tangent-plane approximation breaks down).
    pub fn new(latitude_e7: i32, longitude_e7: i32, altitude_mm: i32) -> Option<Self> {
        let ok = latitude_e7.unsigned_abs() <= 890_000_000
            && longitude_e7.unsigned_abs() <= 1_800_000_000;
        ok.then_some(Self {
            latitude_e7,
            longitude_e7,
            altitude_mm,
        })
    }

    /// A global item's position as local NED \[m\]: `x`, `y` latitude and longitude \[deg ×
    /// 10⁷\], `z` its altitude \[m\] in `frame`: above mean sea level (`MAV_FRAME_GLOBAL`,
    /// `_INT`), or above home (`_RELATIVE_ALT`, `_RELATIVE_ALT_INT`), home being `home_down`
    /// \[m\] down in the local frame. `None` for the terrain frames and non-global ones.
    pub fn to_local_ned(
        &self,
        frame: MavFrame,
        x: i32,
        y: i32,
        z: f32,
        home_down: f32,
    ) -> Option<[f32; 3]> {
        use MavFrame::*;
        // f32 throughout (no soft f64 on the Cortex-M4F): the integer differences are exact in
        // f32 up to 2²⁴ × 10⁻⁷° (about 186 km), far beyond the 10 km a plan accepts.
        let down = match frame {
            MAV_FRAME_GLOBAL | MAV_FRAME_GLOBAL_INT => -(z - self.altitude_mm as f32 * 1e-3),
            MAV_FRAME_GLOBAL_RELATIVE_ALT | MAV_FRAME_GLOBAL_RELATIVE_ALT_INT => home_down - z,
            _ => return None,
        };
        let rad = |e7: i64| e7 as f32 * 1e-7 * core::f32::consts::PI / 180.0;
        let lat0 = rad(i64::from(self.latitude_e7));
        let radius = EARTH_RADIUS as f32;
        let north = rad(i64::from(x) - i64::from(self.latitude_e7)) * radius;
        let east = rad(i64::from(y) - i64::from(self.longitude_e7)) * radius * libm::cosf(lat0);
        Some([north, east, down])
    }
}
