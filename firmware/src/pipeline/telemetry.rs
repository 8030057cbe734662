//! Telemetry scheduling: what the pipeline sends to the ground station and when. Pending
//! command acks and status texts first, parameter replies and one streamed `PARAM_VALUE` at most
//! ([`super::param_protocol`]), then a `HEARTBEAT` and the state
//! (`ATTITUDE_QUATERNION`, `LOCAL_POSITION_NED`) at the rates of
//! [`crate::config::TelemetryConfig`] or as the ground station set them ([`super::schedule`]);
//! with the `hil` feature, each tick's motor commands and reference lead. Frames that do not fit
//! the caller's buffer wait for the next call, whole. With a signing key every frame is signed.

use mavlink::dialects::common::{
    MavAutopilot, MavModeFlag, MavState, MavType, ATTITUDE_QUATERNION_DATA, HEARTBEAT_DATA,
    LOCAL_POSITION_NED_DATA, STATUSTEXT_DATA, TIMESYNC_DATA,
};
use nalgebra::Vector3;

use super::schedule::Periodic;
use super::FlightPipeline;
use crate::frames;
use crate::link;
use crate::safety::FlightState;

impl FlightPipeline {
    /// MAVLink bytes to send now: pending command acks and status texts, parameter texts and
    /// `PARAM_VALUE`s (at most one of a list per call), a HEARTBEAT every
    /// [`crate::config::TelemetryConfig::heartbeat_period_us`], ATTITUDE_QUATERNION and
    /// LOCAL_POSITION_NED every [`crate::config::TelemetryConfig::state_period_us`] (NED/FRD).
    /// Returns the number of bytes written; frames that do not fit wait for the next call.
    pub fn telemetry(&mut self, now_us: u64, out: &mut [u8]) -> usize {
        let mut n = 0;
        #[cfg(feature = "hil")]
        if let Some(tick_us) = self.hil_pending {
            match self.hil_outputs(tick_us, out) {
                0 => return 0,
                k => n += k,
            }
            self.hil_pending = None;
        }
        while let Some(&(command, result, sender)) = self.acks.front() {
            let m = link::CommandAck {
                command,
                result,
                target_system: sender.system,
                target_component: sender.component,
            };
            match self.put(&m, &mut out[n..]) {
                0 => return n,
                k => n += k,
            }
            self.acks.pop_front();
        }
        while let Some(&(tc1, ts1)) = self.timesync.front() {
            match self.put(&TIMESYNC_DATA { tc1, ts1 }, &mut out[n..]) {
                0 => return n,
                k => n += k,
            }
            self.timesync.pop_front();
        }
        while let Some(&(severity, a, b)) = self.texts.front() {
            let mut text = [0u8; 50];
            let mut i = 0;
            for byte in a.bytes().chain(": ".bytes()).chain(b.bytes()) {
                if i < text.len() {
                    text[i] = byte;
                    i += 1;
                }
            }
            let m = STATUSTEXT_DATA {
                severity,
                text: text.into(),
            };
            match self.put(&m, &mut out[n..]) {
                0 => return n,
                k => n += k,
            }
            self.texts.pop_front();
        }
        if self.mission_transfer.uploading() {
            self.mission_poll(now_us);
        }
        match self.mission_telemetry(&mut out[n..]) {
            (k, true) => n += k,
            (k, false) => return n + k,
        }
        match self.param_telemetry(now_us, &mut out[n..]) {
            (k, true) => n += k,
            (k, false) => return n + k,
        }
        if self.schedule.due(Periodic::Heartbeat, now_us) {
            let armed = self.supervisor.state() != FlightState::Disarmed;
            // `custom_mode` is the mission mode (crate::pipeline::Mode), so the flag that says
            // it is meaningful is set.
            let mut mode = MavModeFlag::MAV_MODE_FLAG_GUIDED_ENABLED
                | MavModeFlag::MAV_MODE_FLAG_STABILIZE_ENABLED
                | MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
            if armed {
                mode |= MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED;
            }
            let system_status = match self.supervisor.state() {
                FlightState::Disarmed => MavState::MAV_STATE_STANDBY,
                FlightState::Armed => MavState::MAV_STATE_ACTIVE,
                FlightState::Failsafe => MavState::MAV_STATE_CRITICAL,
            };
            let m = HEARTBEAT_DATA {
                custom_mode: self.mission.mode() as u32,
                mavtype: MavType::MAV_TYPE_QUADROTOR,
                autopilot: MavAutopilot::MAV_AUTOPILOT_GENERIC,
                base_mode: mode,
                system_status,
                mavlink_version: 3,
            };
            match self.put(&m, &mut out[n..]) {
                0 => {
                    self.counters.telemetry_dropped += 1;
                    return n;
                }
                k => n += k,
            }
            self.schedule.sent(Periodic::Heartbeat, now_us);
        }
        let time_boot_ms = (now_us / 1000) as u32;
        if self.schedule.due(Periodic::Attitude, now_us) {
            let q = frames::quaternion_to_mavlink(&self.status_attitude);
            let w = frames::flip_to_array(&Vector3::from(self.status_rates));
            let att = ATTITUDE_QUATERNION_DATA {
                time_boot_ms,
                q1: q[0],
                q2: q[1],
                q3: q[2],
                q4: q[3],
                rollspeed: w[0],
                pitchspeed: w[1],
                yawspeed: w[2],
            };
            match self.put(&att, &mut out[n..]) {
                0 => {
                    self.counters.telemetry_dropped += 1;
                    return n;
                }
                k => n += k,
            }
            self.schedule.sent(Periodic::Attitude, now_us);
        }
        if self.schedule.due(Periodic::Position, now_us) {
            let p = frames::flip_to_array(&Vector3::from(self.status_position));
            let v = frames::flip_to_array(&Vector3::from(self.status_velocity));
            let pos = LOCAL_POSITION_NED_DATA {
                time_boot_ms,
                x: p[0],
                y: p[1],
                z: p[2],
                vx: v[0],
                vy: v[1],
                vz: v[2],
            };
            match self.put(&pos, &mut out[n..]) {
                0 => {
                    self.counters.telemetry_dropped += 1;
                    return n;
                }
                k => n += k,
            }
            self.schedule.sent(Periodic::Position, now_us);
        }
        for m in &Periodic::ALL[3..] {
            if !self.schedule.due(*m, now_us) {
                continue;
            }
            let k = match m {
                Periodic::SysStatus => self.put(&self.sys_status(), &mut out[n..]),
                Periodic::ExtendedSysState => self.put(&self.extended_sys_state(), &mut out[n..]),
                Periodic::AttitudeEuler => self.put(&self.attitude_euler(now_us), &mut out[n..]),
                Periodic::Home => self.put(&self.home_position(), &mut out[n..]),
                Periodic::Version => self.put(&self.autopilot_version(), &mut out[n..]),
                // Sent above.
                Periodic::Heartbeat | Periodic::Attitude | Periodic::Position => continue,
            };
            if k == 0 {
                self.counters.telemetry_dropped += 1;
                return n;
            }
            n += k;
            self.schedule.sent(*m, now_us);
        }
        n
    }

    /// The tick's motor commands (`HIL_ACTUATOR_CONTROLS`: throttles in `controls[0..4]`, mixer
    /// order; `mode` has `SAFETY_ARMED` when armed; `flags` = `LOCKSTEP`) and reference (`POSITION_TARGET_LOCAL_NED`,
    /// NED \[m\]), both or nothing; returns the bytes written.
    #[cfg(feature = "hil")]
    fn hil_outputs(&mut self, tick_us: u64, out: &mut [u8]) -> usize {
        use mavlink::dialects::common::{
            HilActuatorControlsFlags, MavFrame, PositionTargetTypemask, HIL_ACTUATOR_CONTROLS_DATA,
            POSITION_TARGET_LOCAL_NED_DATA,
        };
        let mut controls = [0.0f32; 16];
        for (c, &rotor) in controls.iter_mut().zip(&self.motor_slots) {
            *c = self.last_output.throttle[rotor];
        }
        let actuators = HIL_ACTUATOR_CONTROLS_DATA {
            time_usec: tick_us,
            // The simulator must wait for this frame before it steps (docs/sil-pil.md).
            flags: HilActuatorControlsFlags::HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP,
            controls,
            mode: if self.last_output.armed {
                MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
            } else {
                MavModeFlag::empty()
            },
        };
        let r = frames::flip_to_array(&Vector3::from(self.status_reference));
        let (v, a, [hx, hy], [hx_dot, hy_dot]) = self.status_reference_motion;
        // The heading is a unit vector (cos ψ, sin ψ): ψ = atan2(sin, cos), ψ̇ = h × ḣ.
        let (yaw, yaw_rate) = (libm::atan2f(hy, hx), hx * hy_dot - hy * hx_dot);
        let v = frames::flip_to_array(&Vector3::from(v));
        let a = frames::flip_to_array(&Vector3::from(a));
        // Every field is the reference's (the mask ignores none): position, velocity,
        // acceleration, yaw and yaw rate, NED.
        let target = POSITION_TARGET_LOCAL_NED_DATA {
            time_boot_ms: (tick_us / 1000) as u32,
            x: r[0],
            y: r[1],
            z: r[2],
            vx: v[0],
            vy: v[1],
            vz: v[2],
            afx: a[0],
            afy: a[1],
            afz: a[2],
            yaw: frames::flip_yaw(yaw),
            yaw_rate: frames::flip_yaw(yaw_rate),
            type_mask: PositionTargetTypemask::empty(),
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
        };
        // Encode into a scratch copy first, so that a lack of room leaves nothing half-sent.
        let mut scratch = [0u8; 2 * link::MAX_FRAME];
        let a = self.put(&actuators, &mut scratch);
        let b = self.put(&target, &mut scratch[a..]);
        if a + b > out.len() {
            self.sequence = self.sequence.wrapping_sub(2);
            return 0;
        }
        out[..a + b].copy_from_slice(&scratch[..a + b]);
        a + b
    }

    /// Encodes `m` into `out` with the next sequence number, signed when the link has a key;
    /// 0 (and the number unused) if it does not fit.
    pub(super) fn put<D: mavlink::MessageData>(&mut self, m: &D, out: &mut [u8]) -> usize {
        let (system, component, sequence) =
            (self.cfg.system_id, self.cfg.component_id, self.sequence);
        let k = if self.decoder.signing_active() {
            // Signed: built in a scratch frame, so that no room for the signature leaves
            // nothing half-written in `out`.
            let mut frame = [0u8; link::MAX_FRAME];
            let k = link::encode_data(m, system, component, sequence, &mut frame);
            match self.decoder.sign(&mut frame, k) {
                k if k > 0 && k <= out.len() => {
                    out[..k].copy_from_slice(&frame[..k]);
                    k
                }
                _ => 0,
            }
        } else {
            // Unsigned (the common case, inside the timed control step): straight into `out`.
            link::encode_data(m, system, component, sequence, out)
        };
        if k > 0 {
            self.sequence = self.sequence.wrapping_add(1);
        }
        k
    }

    /// `MAV_CMD_REQUEST_MESSAGE`: a periodic message once, now. Error: one the vehicle does
    /// not send.
    pub(super) fn request_message(&mut self, id: u32) -> Result<(), &'static str> {
        self.schedule.request(id)
    }

    /// `MAV_CMD_SET_MESSAGE_INTERVAL` ([`super::schedule::Schedule::set_interval`]).
    pub(super) fn set_message_interval(
        &mut self,
        id: u32,
        interval_us: f32,
    ) -> Result<(), &'static str> {
        let min = self.cfg.control_rate.period_us();
        self.schedule.set_interval(id, interval_us, min)
    }
}
