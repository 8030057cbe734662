//! The MAVLink mission microservice on the vehicle: upload (`MISSION_COUNT` → requests →
//! items → `MISSION_ACK`), download (`MISSION_REQUEST_LIST` → `MISSION_COUNT` → items),
//! `MISSION_CLEAR_ALL`, `MISSION_SET_CURRENT`, and the replies' encoding (with the
//! `mission_type` extension byte the `mavlink` crate's structs lack).
//!
//! **Certified before accepted.** A complete upload is planned ([`crate::mission::plan`]) from
//! where the reference is now (flying) or from the estimate (on the ground), and its path's
//! Assumption 1 constants go through the certificate gate that every reference passes
//! ([`super::gate::check`]: Assumption 1, Theorem 1, Lemma 1, Theorem 2, the rotor fit). A
//! mission that fails is refused with `MAV_MISSION_DENIED` and two `STATUSTEXT`s: the violated
//! condition, and its two sides with the slow-down factor of the same path that certifies
//! ([`slowdown_to_certify`]) if one up to [`MAX_SLOWDOWN`] does. The stored mission is replaced
//! only by an accepted upload. The start checks the gate again from where the vehicle then is.
//!
//! Fences and rally points are not supported: their lists are empty (`MISSION_COUNT` 0, as
//! QGroundControl asks for them on connect) and their uploads are refused
//! (`MAV_MISSION_UNSUPPORTED`).

use core::fmt::Write;

use controller_core::waypoint_path::slowdown_to_certify;
use controller_core::{certify, FilterStart, Trajectory, TrajectoryConstants};
use heapless::String;
use mavlink::dialects::common::{
    MavMissionResult, MavSeverity, GPS_GLOBAL_ORIGIN_DATA, MISSION_ACK_DATA, MISSION_COUNT_DATA,
    MISSION_CURRENT_DATA, MISSION_ITEM_REACHED_DATA, MISSION_REQUEST_INT_DATA,
};
use mavlink::error::ParserError;
use mavlink::{MavlinkVersion, MessageData};

use super::{FlightPipeline, GateFailure, Mode};
use crate::link::Sender;
use crate::mission::{
    plan, GlobalFrame, GlobalOrigin, MissionMessage, MissionReply, UploadStep, CAPACITY,
    MISSION_TYPE_ALL, MISSION_TYPE_MISSION,
};
use crate::safety::FlightState;

/// Largest slow-down factor offered for a refused mission.
pub const MAX_SLOWDOWN: f32 = 100.0;

/// A message with the `mission_type` extension byte after its base payload (`mavlink`'s
/// structs stop before the extensions); 0 is left out, as MAVLink 2 truncates trailing zeros.
struct WithMissionType<D>(D, u8);

impl<D: MessageData> MessageData for WithMissionType<D> {
    type Message = D::Message;
    const ID: u32 = D::ID;
    const NAME: &'static str = D::NAME;
    const EXTRA_CRC: u8 = D::EXTRA_CRC;
    const ENCODED_LEN: usize = D::ENCODED_LEN + 1;

    fn ser(&self, version: MavlinkVersion, payload: &mut [u8]) -> usize {
        let n = self.0.ser(version, payload);
        if self.1 == 0 {
            return n;
        }
        payload[n..D::ENCODED_LEN].fill(0);
        payload[D::ENCODED_LEN] = self.1;
        D::ENCODED_LEN + 1
    }

    fn deser(version: MavlinkVersion, payload: &[u8]) -> Result<Self, ParserError> {
        let t = payload.get(D::ENCODED_LEN).copied().unwrap_or(0);
        D::deser(version, payload).map(|d| Self(d, t))
    }
}

/// `value` with `decimals` digits after the point, rounded to nearest, by integer arithmetic;
/// "nan", "inf" or "-inf" when not finite, "big" beyond ±10⁹.
struct Fixed(f32, u32);

impl core::fmt::Display for Fixed {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let Self(v, decimals) = *self;
        if v.is_nan() {
            return f.write_str("nan");
        }
        if v.is_infinite() {
            return f.write_str(if v > 0.0 { "inf" } else { "-inf" });
        }
        if v.abs() >= 1e9 {
            return f.write_str("big");
        }
        let scale = 10u64.pow(decimals);
        let scaled = libm::round(f64::from(v.abs()) * scale as f64) as u64;
        let sign = if v < 0.0 && scaled > 0 { "-" } else { "" };
        let (int, frac) = (scaled / scale, scaled % scale);
        write!(f, "{sign}{int}.")?;
        // Leading zeros of the fraction, then its digits.
        let mut pad = scale / 10;
        while pad > 1 && frac < pad {
            f.write_str("0")?;
            pad /= 10;
        }
        write!(f, "{frac}")
    }
}

/// A `STATUSTEXT`'s 50 characters, filled as far as they go (the rest is dropped, not an
/// error, so a long reason keeps its beginning).
struct Truncating(String<50>);

impl Write for Truncating {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for c in s.chars() {
            if self.0.push(c).is_err() {
                break;
            }
        }
        Ok(())
    }
}

impl FlightPipeline {
    /// One mission-protocol message from `sender` at `now_us`.
    pub(super) fn mission_message(&mut self, m: MissionMessage, sender: Sender, now_us: u64) {
        use MavMissionResult as R;
        match m {
            MissionMessage::RequestList { mission_type } => {
                let count = match mission_type {
                    MISSION_TYPE_MISSION => self.mission_items.len() as u16,
                    _ => 0,
                };
                self.mission_reply(MissionReply::Count {
                    count,
                    mission_type,
                    to: sender,
                });
            }
            MissionMessage::Request { seq, mission_type } => {
                let reply = if mission_type == MISSION_TYPE_MISSION
                    && usize::from(seq) < self.mission_items.len()
                {
                    MissionReply::Item { seq, to: sender }
                } else {
                    MissionReply::Ack {
                        result: R::MAV_MISSION_INVALID_SEQUENCE,
                        mission_type,
                        to: sender,
                    }
                };
                self.mission_reply(reply);
            }
            MissionMessage::Count {
                count,
                mission_type,
            } => {
                let refuse = |reason: &'static str, result| Err((reason, result));
                let check = if mission_type != MISSION_TYPE_MISSION {
                    refuse(
                        "only missions (no fence, rally)",
                        R::MAV_MISSION_UNSUPPORTED,
                    )
                } else if self.mission.mode() == Mode::Mission {
                    refuse("flying a mission", R::MAV_MISSION_DENIED)
                } else if usize::from(count) > CAPACITY {
                    refuse("more than 32 items", R::MAV_MISSION_NO_SPACE)
                } else {
                    Ok(())
                };
                match check {
                    Err((reason, result)) => {
                        self.mission_text(format_args!("mission refused: {reason}"));
                        self.mission_ack(result, mission_type, sender);
                    }
                    Ok(()) if count == 0 => {
                        self.mission_items.clear();
                        self.mission_current = 0;
                        self.mission_ack(R::MAV_MISSION_ACCEPTED, mission_type, sender);
                    }
                    Ok(()) => {
                        let seq = self.mission_transfer.begin(sender, count, now_us);
                        self.mission_reply(MissionReply::Request { seq, to: sender });
                    }
                }
            }
            MissionMessage::Item {
                seq,
                item,
                mission_type,
            } => {
                if mission_type != MISSION_TYPE_MISSION {
                    return;
                }
                match self.mission_transfer.item(sender, seq, item, now_us) {
                    UploadStep::Request(seq) => {
                        self.mission_reply(MissionReply::Request { seq, to: sender })
                    }
                    UploadStep::Complete(items) => {
                        let result = self.certify_upload(&items, now_us);
                        if result == R::MAV_MISSION_ACCEPTED {
                            self.mission_items = items;
                            self.mission_current = 0;
                        }
                        self.mission_ack(result, mission_type, sender);
                    }
                    UploadStep::Ignored => {}
                }
            }
            MissionMessage::ClearAll { mission_type } => {
                let result = if !matches!(mission_type, MISSION_TYPE_MISSION | MISSION_TYPE_ALL) {
                    R::MAV_MISSION_UNSUPPORTED
                } else if self.mission.mode() == Mode::Mission {
                    self.mission_text(format_args!("mission not cleared: flying it"));
                    R::MAV_MISSION_DENIED
                } else {
                    self.mission_items.clear();
                    self.mission_current = 0;
                    R::MAV_MISSION_ACCEPTED
                };
                self.mission_ack(result, mission_type, sender);
            }
            MissionMessage::SetCurrent { seq } => {
                if usize::from(seq) < self.mission_items.len()
                    && self.mission.mode() != Mode::Mission
                {
                    self.mission_current = seq;
                }
                self.mission_reply(MissionReply::Current {
                    seq: self.mission_current,
                });
            }
            MissionMessage::Ack { .. } => self.mission_transfer.cancel(sender),
            MissionMessage::SetOrigin {
                latitude_e7,
                longitude_e7,
                altitude_mm,
            } => {
                if self.mission.mode() == Mode::Mission {
                    self.mission_text(format_args!("origin not set: flying a mission"));
                } else if let Some(o) = GlobalOrigin::new(latitude_e7, longitude_e7, altitude_mm) {
                    self.global_origin = Some(o);
                    self.mission_reply(MissionReply::Origin);
                } else {
                    self.mission_text(format_args!("origin refused: latitude or longitude"));
                }
            }
        }
    }

    /// Where global mission items are: the origin (if set) and home's height.
    pub(super) fn global_frame(&self) -> GlobalFrame {
        GlobalFrame {
            origin: self.global_origin,
            home_up: self.home.z,
        }
    }

    /// Re-requests an overdue item of the upload in progress, or cancels the upload.
    pub(super) fn mission_poll(&mut self, now_us: u64) {
        match self.mission_transfer.poll(now_us) {
            Some(Ok((seq, to))) => self.mission_reply(MissionReply::Request { seq, to }),
            Some(Err(to)) => self.mission_ack(
                MavMissionResult::MAV_MISSION_OPERATION_CANCELLED,
                MISSION_TYPE_MISSION,
                to,
            ),
            None => {}
        }
    }

    /// Plans `items` from where the reference is (flying) or the estimate (on the ground) and
    /// runs the certificate gate on the plan's constants: `MAV_MISSION_ACCEPTED`, or the
    /// refusal's result with its `STATUSTEXT`s.
    fn certify_upload(
        &mut self,
        items: &[crate::mission::MissionItem],
        now_us: u64,
    ) -> MavMissionResult {
        let (start, yaw) = self.mission_start_point(now_us);
        let plan = match plan(items, start, yaw, &self.cfg.reference, &self.global_frame()) {
            Ok(p) => p,
            Err(e) => {
                self.mission_text(format_args!("mission item {}: {}", e.seq, e.reason));
                return e.result;
            }
        };
        let k = plan.path.constants();
        // Where the position filters may be when the mission starts: anywhere in their box
        // once flying (the gate's conservative start).
        let filter = FilterStart::InSaturationBox;
        match self.gate_only(&k, filter) {
            Ok(()) => MavMissionResult::MAV_MISSION_ACCEPTED,
            Err(f) if self.cfg.allow_uncertified => {
                self.event(super::Event::Uncertified {
                    condition: f.condition,
                    lhs: f.lhs,
                    rhs: f.rhs,
                });
                MavMissionResult::MAV_MISSION_ACCEPTED
            }
            Err(f) => {
                self.event(super::Event::ReferenceRefused {
                    condition: f.condition,
                    lhs: f.lhs,
                    rhs: f.rhs,
                });
                self.counters.refused_commands = self.counters.refused_commands.saturating_add(1);
                self.mission_text(format_args!("mission denied: {}", f.condition));
                let slower = if f.rhs.is_nan() {
                    None
                } else {
                    slowdown_to_certify(&k, MAX_SLOWDOWN, |k| self.gate_only(k, filter).is_ok())
                };
                // Numbers as fixed-point decimals (core's float formatting would add tens of
                // KiB of flash for one message).
                let lhs = Fixed(f.lhs, 4);
                let rhs = Fixed(f.rhs, 4);
                match (f.rhs.is_nan(), slower) {
                    (true, _) => self.mission_text(format_args!("value {lhs}")),
                    // Rounded up, so the factor as printed certifies too.
                    (false, Some(c)) => self.mission_text(format_args!(
                        "{lhs} vs {rhs}; {}x slower certifies",
                        Fixed(libm::ceilf(c * 100.0) / 100.0, 2)
                    )),
                    (false, None) => self
                        .mission_text(format_args!("{lhs} vs {rhs}; no slower timing certifies")),
                }
                MavMissionResult::MAV_MISSION_DENIED
            }
        }
    }

    /// Where a mission would start now: the reference's current point when flying, else the
    /// estimate (or the arming point without one), position NWU \[m\] and yaw \[rad\].
    pub(super) fn mission_start_point(&self, now_us: u64) -> (nalgebra::Vector3<f32>, f32) {
        if self.flying() {
            let p = nalgebra::Vector3::from(self.status_reference);
            let (c, s) = (
                self.status_reference_motion.2[0],
                self.status_reference_motion.2[1],
            );
            return (p, libm::atan2f(s, c));
        }
        match self.estimator.estimate(now_us) {
            Some(e) => {
                let (_, _, yaw) = e.attitude.euler_angles();
                (e.position, yaw)
            }
            None => (self.home, 0.0),
        }
    }

    /// The certificate gate alone (no controller change): every condition of the certificate
    /// for the constants `k` from `start`, then the rotor fit ([`super::gate::check`]).
    pub(super) fn gate_only(
        &self,
        k: &TrajectoryConstants<f32>,
        start: FilterStart,
    ) -> Result<(), GateFailure> {
        let c = &self.cfg;
        let cert = certify(&c.vehicle, &c.limits, &c.gains, k, start).map_err(|e| {
            let r = crate::report::refusal(&e);
            GateFailure {
                condition: r.name,
                lhs: r.value as f32,
                rhs: f32::NAN,
            }
        })?;
        super::gate::check(&cert, c, &self.mixer).map(|_| ())
    }

    /// Queues a mission reply, or counts it dropped.
    pub(super) fn mission_reply(&mut self, r: MissionReply) {
        if self.mission_replies.push_back(r).is_err() {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    fn mission_ack(&mut self, result: MavMissionResult, mission_type: u8, to: Sender) {
        self.mission_reply(MissionReply::Ack {
            result,
            mission_type,
            to,
        });
    }

    /// Queues a formatted `STATUSTEXT` (warning; cut at 50 characters).
    pub(super) fn mission_text(&mut self, args: core::fmt::Arguments<'_>) {
        let mut s = Truncating(String::new());
        // `Truncating` never fails: a longer text is cut at 50 characters.
        let _ = s.write_fmt(args);
        let s = s.0;
        if self
            .long_texts
            .push_back((MavSeverity::MAV_SEVERITY_WARNING, s))
            .is_err()
        {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    /// Writes the queued mission replies and formatted texts into `out`; the number of bytes
    /// and whether all were written (frames that do not fit wait, whole).
    pub(super) fn mission_telemetry(&mut self, out: &mut [u8]) -> (usize, bool) {
        let mut n = 0;
        while let Some(&r) = self.mission_replies.front() {
            let k = match r {
                MissionReply::Count {
                    count,
                    mission_type,
                    to,
                } => self.put(
                    &WithMissionType(
                        MISSION_COUNT_DATA {
                            count,
                            target_system: to.system,
                            target_component: to.component,
                        },
                        mission_type,
                    ),
                    &mut out[n..],
                ),
                MissionReply::Request { seq, to } => self.put(
                    &MISSION_REQUEST_INT_DATA {
                        seq,
                        target_system: to.system,
                        target_component: to.component,
                    },
                    &mut out[n..],
                ),
                MissionReply::Item { seq, to } => match self.mission_items.get(usize::from(seq)) {
                    Some(item) => {
                        let m = item.to_int(seq, to.system, to.component);
                        self.put(&m, &mut out[n..])
                    }
                    // Cleared since the request: nothing to send.
                    None => usize::MAX,
                },
                MissionReply::Ack {
                    result,
                    mission_type,
                    to,
                } => self.put(
                    &WithMissionType(
                        MISSION_ACK_DATA {
                            target_system: to.system,
                            target_component: to.component,
                            mavtype: result,
                        },
                        mission_type,
                    ),
                    &mut out[n..],
                ),
                MissionReply::Current { seq } => {
                    self.put(&MISSION_CURRENT_DATA { seq }, &mut out[n..])
                }
                MissionReply::Reached { seq } => {
                    self.put(&MISSION_ITEM_REACHED_DATA { seq }, &mut out[n..])
                }
                MissionReply::Origin => match self.global_origin {
                    Some(o) => self.put(
                        &GPS_GLOBAL_ORIGIN_DATA {
                            latitude: o.latitude_e7,
                            longitude: o.longitude_e7,
                            altitude: o.altitude_mm,
                        },
                        &mut out[n..],
                    ),
                    None => usize::MAX,
                },
            };
            match k {
                0 => return (n, false),
                usize::MAX => {}
                k => n += k,
            }
            self.mission_replies.pop_front();
        }
        while let Some((severity, text)) = self.long_texts.front() {
            let mut bytes = [0u8; 50];
            bytes[..text.len()].copy_from_slice(text.as_bytes());
            let m = mavlink::dialects::common::STATUSTEXT_DATA {
                severity: *severity,
                text: bytes.into(),
            };
            match self.put(&m, &mut out[n..]) {
                0 => return (n, false),
                k => n += k,
            }
            self.long_texts.pop_front();
        }
        (n, true)
    }

    /// Whether the vehicle is armed (mission start needs it).
    pub(super) fn armed(&self) -> bool {
        self.supervisor.state() == FlightState::Armed
    }
}

/// Frames the tests need that the ground-station builders cannot express (the extension byte).
#[cfg(test)]
pub(super) mod tests_support {
    use super::WithMissionType;
    use crate::ground_station::{TARGET_COMPONENT, TARGET_SYSTEM};
    use crate::link;
    use mavlink::dialects::common::MISSION_REQUEST_LIST_DATA;

    /// `MISSION_REQUEST_LIST` with `mission_type` from the ground station (255, 190).
    pub fn request_list_with_type(mission_type: u8) -> std::vec::Vec<u8> {
        let m = WithMissionType(
            MISSION_REQUEST_LIST_DATA {
                target_system: TARGET_SYSTEM,
                target_component: TARGET_COMPONENT,
            },
            mission_type,
        );
        let mut b = [0u8; link::MAX_FRAME];
        let n = link::encode_data(&m, 255, 190, 0, &mut b);
        b[..n].to_vec()
    }
}
