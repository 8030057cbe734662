//! When each periodic telemetry message is next due, and the ground station's control of it
//! (`MAV_CMD_REQUEST_MESSAGE`: once, now; `MAV_CMD_SET_MESSAGE_INTERVAL`: its period).
//! `HOME_POSITION` and `AUTOPILOT_VERSION` are stopped by default: sent on request (and the
//! home position once at every arming).

use mavlink::dialects::common::{
    ATTITUDE_DATA, ATTITUDE_QUATERNION_DATA, AUTOPILOT_VERSION_DATA, EXTENDED_SYS_STATE_DATA,
    HEARTBEAT_DATA, HOME_POSITION_DATA, LOCAL_POSITION_NED_DATA, SYS_STATUS_DATA,
};
use mavlink::MessageData;

use crate::config::TelemetryConfig;

/// A periodic message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Periodic {
    /// `HEARTBEAT`.
    Heartbeat = 0,
    /// `ATTITUDE_QUATERNION`.
    Attitude = 1,
    /// `LOCAL_POSITION_NED`.
    Position = 2,
    /// `SYS_STATUS`.
    SysStatus = 3,
    /// `EXTENDED_SYS_STATE`.
    ExtendedSysState = 4,
    /// `ATTITUDE` (Euler angles, what ground-station HUDs draw).
    AttitudeEuler = 5,
    /// `HOME_POSITION` (the arming point).
    Home = 6,
    /// `AUTOPILOT_VERSION`.
    Version = 7,
}

/// Number of [`Periodic`] messages.
const COUNT: usize = 8;

impl Periodic {
    /// Every periodic message, in the order telemetry sends them when several are due.
    pub const ALL: [Periodic; COUNT] = [
        Self::Heartbeat,
        Self::Attitude,
        Self::Position,
        Self::SysStatus,
        Self::ExtendedSysState,
        Self::AttitudeEuler,
        Self::Home,
        Self::Version,
    ];
}

impl Periodic {
    /// The periodic message with MAVLink id `id`, if the vehicle sends one.
    pub fn from_message_id(id: u32) -> Option<Self> {
        match id {
            HEARTBEAT_DATA::ID => Some(Self::Heartbeat),
            ATTITUDE_QUATERNION_DATA::ID => Some(Self::Attitude),
            LOCAL_POSITION_NED_DATA::ID => Some(Self::Position),
            SYS_STATUS_DATA::ID => Some(Self::SysStatus),
            EXTENDED_SYS_STATE_DATA::ID => Some(Self::ExtendedSysState),
            ATTITUDE_DATA::ID => Some(Self::AttitudeEuler),
            HOME_POSITION_DATA::ID => Some(Self::Home),
            AUTOPILOT_VERSION_DATA::ID => Some(Self::Version),
            _ => None,
        }
    }
}

/// Periods (`u64::MAX`: stopped) and next due times \[µs\] of the periodic messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Schedule {
    default_us: [u64; COUNT],
    period_us: [u64; COUNT],
    next_us: [u64; COUNT],
}

impl Schedule {
    /// The configured periods (the status messages at the heartbeat's, `ATTITUDE` at the
    /// state's), everything periodic due at once, the on-request messages stopped.
    pub fn new(cfg: &TelemetryConfig) -> Self {
        let (slow, fast) = (cfg.heartbeat_period_us, cfg.state_period_us);
        let default_us = [slow, fast, fast, slow, slow, fast, u64::MAX, u64::MAX];
        let mut next_us = [0; COUNT];
        next_us[Periodic::Home as usize] = u64::MAX;
        next_us[Periodic::Version as usize] = u64::MAX;
        Self {
            default_us,
            period_us: default_us,
            next_us,
        }
    }

    /// `m` once, at the next telemetry call.
    pub fn request_now(&mut self, m: Periodic) {
        self.next_us[m as usize] = 0;
    }

    /// Whether `m` is due at `now_us`.
    pub fn due(&self, m: Periodic, now_us: u64) -> bool {
        now_us >= self.next_us[m as usize]
    }

    /// `m` was sent at `now_us`.
    pub fn sent(&mut self, m: Periodic, now_us: u64) {
        self.next_us[m as usize] = now_us.saturating_add(self.period_us[m as usize]);
    }

    /// `MAV_CMD_REQUEST_MESSAGE`: message `id` once, at the next telemetry call (a stopped
    /// message too). Error: the vehicle does not send that message.
    pub fn request(&mut self, id: u32) -> Result<(), &'static str> {
        let m = Periodic::from_message_id(id).ok_or("message not sent by this vehicle")?;
        self.next_us[m as usize] = 0;
        Ok(())
    }

    /// `MAV_CMD_SET_MESSAGE_INTERVAL`: message `id` every `interval_us` \[µs\] (−1 stops it, 0
    /// restores the default). Errors (nothing changed): a message the vehicle does not send, a
    /// period shorter than `min_period_us` (the control period: nothing is sent faster), a
    /// stopped `HEARTBEAT` (the ground station would lose the link), any other value.
    pub fn set_interval(
        &mut self,
        id: u32,
        interval_us: f32,
        min_period_us: u64,
    ) -> Result<(), &'static str> {
        let m = Periodic::from_message_id(id).ok_or("message not sent by this vehicle")?;
        let period = if interval_us == -1.0 {
            if m == Periodic::Heartbeat {
                return Err("the heartbeat cannot be stopped");
            }
            u64::MAX
        } else if interval_us == 0.0 {
            self.default_us[m as usize]
        } else if interval_us >= min_period_us as f32 && interval_us <= 1.0e9 {
            interval_us as u64
        } else {
            return Err("interval out of range (control period to 1000 s, 0, or -1)");
        };
        self.period_us[m as usize] = period;
        self.next_us[m as usize] = 0;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn schedule() -> Schedule {
        Schedule::new(&TelemetryConfig {
            heartbeat_period_us: 1_000_000,
            state_period_us: 50_000,
        })
    }

    /// Given the default periods, when the attitude is set to 10 Hz and the position stopped,
    /// then each follows its own period, and a request sends the stopped one once.
    #[test]
    fn intervals_and_requests() {
        let mut s = schedule();
        s.set_interval(ATTITUDE_QUATERNION_DATA::ID, 100_000.0, 10_000)
            .unwrap();
        s.set_interval(LOCAL_POSITION_NED_DATA::ID, -1.0, 10_000)
            .unwrap();
        assert!(s.due(Periodic::Attitude, 0));
        s.sent(Periodic::Attitude, 0);
        assert!(!s.due(Periodic::Attitude, 99_999));
        assert!(s.due(Periodic::Attitude, 100_000));
        s.sent(Periodic::Position, 0);
        assert!(!s.due(Periodic::Position, u64::MAX - 1));
        s.request(LOCAL_POSITION_NED_DATA::ID).unwrap();
        assert!(s.due(Periodic::Position, 5));
        s.sent(Periodic::Position, 5);
        assert!(!s.due(Periodic::Position, 10_000_000));
        // Back to the default.
        s.set_interval(LOCAL_POSITION_NED_DATA::ID, 0.0, 10_000)
            .unwrap();
        s.sent(Periodic::Position, 0);
        assert!(s.due(Periodic::Position, 50_000));
    }

    /// Refusals change nothing.
    #[test]
    fn refusals() {
        let mut s = schedule();
        let before = s;
        assert!(s.set_interval(HEARTBEAT_DATA::ID, -1.0, 10_000).is_err());
        assert!(s
            .set_interval(ATTITUDE_QUATERNION_DATA::ID, 5_000.0, 10_000)
            .is_err());
        assert!(s
            .set_interval(ATTITUDE_QUATERNION_DATA::ID, -2.0, 10_000)
            .is_err());
        assert!(s.set_interval(77, 100_000.0, 10_000).is_err());
        assert!(s.request(77).is_err());
        assert_eq!(s, before);
    }
}
