//! The flight pipeline: IMU and MAVLink in, motor throttles and telemetry out. Everything the
//! firmware flies, with no register and no logging, so host-sim runs the very same code.
//!
//! Per control tick (the law's rate, 100 Hz to 1 kHz): estimate at `now` → safety supervisor →
//! by state: disarmed (throttle 0), armed idle (idle throttle, waiting for takeoff / mission / setpoint), armed
//! flying (reference → controller-core law → mixer → thrust curve), failsafe (IMU-only level
//! attitude hold with the paper's saturated attitude law and a descent thrust). Any non-finite
//! value on the way is counted and sends an armed vehicle to the failsafe; the throttles are
//! checked finite last of all.
//!
//! One facet per file, each an `impl FlightPipeline` block or a small pure type:
//! `commands.rs` (commands and the certificate gate), `mission.rs` (the takeoff/land mode
//! machine, [`ModeMachine`]), `landed.rs` (the landed detector, [`LandedDetector`]),
//! `failsafe.rs` (the failsafe law), `telemetry.rs` (telemetry scheduling), `schedule.rs`
//! (when each periodic message is due), `status_messages.rs` (what a ground station shows),
//! `param_protocol.rs` (the MAVLink parameter protocol, each change certified like the boot set-up),
//! `events.rs` (events, counters, status) and, with the `hil` feature, `lockstep.rs` (the
//! processor-in-the-loop pacing rule, `lockstep::Lockstep`). This file holds the pipeline's
//! state, its construction and the
//! per-sample and per-tick flow.

mod boot;
mod commands;
mod events;
mod failsafe;
pub mod gate;
mod landed;
#[cfg(feature = "hil")]
pub mod lockstep;
mod mission;
mod mission_flight;
mod mission_protocol;
mod param_protocol;
mod param_queue;
mod param_text;
pub mod schedule;
mod status_messages;
mod storage;
mod telemetry;
#[cfg(test)]
#[cfg_attr(feature = "uncertified-paper", allow(dead_code))]
mod tests;

pub use boot::{BootError, BootReport};
pub use events::{Counters, Event, PipelineStatus};
pub use gate::{
    check as gate_check, fit_margin, GateFailure, RotorFit, RotorFits, ROTOR_FIT, ROTOR_FIT_LOCAL,
    ROTOR_FIT_LOCAL_SHADOW, ROTOR_FIT_SHADOW, ROTOR_FIT_THRUST,
};
pub use landed::{LandedDetector, LandedInputs};
pub use mission::{Mode, ModeMachine};
pub use param_protocol::{ParamRefusal, RestoreError, STREAM_PERIOD_US as PARAM_STREAM_PERIOD_US};

use controller_core::scalar::{finite_probe, fmax, fmin, norm};
use controller_core::{Controller, VehicleState};
use heapless::Deque;
use mavlink::dialects::common::{MavCmd, MavResult, MavSeverity};
use nalgebra::{UnitQuaternion, Vector3, Vector4};

use crate::config::FlightConfig;
use crate::estimator::{micros_f32, Estimate, Estimator};
use crate::flight_reference::{FlightReference, ReferenceMode, SupTable};
use crate::imu_attitude::Mahony;
use crate::link::{Decoder, Sender};
use crate::mixer::{MixOutput, Mixer};
use crate::safety::{FlightState, Supervisor, TickInputs, Transition};
use events::EventQueue;
use param_queue::ParamQueue;
use schedule::Schedule;

/// One IMU sample, body FLU (x forward, y left, z up: the controller's body frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSample {
    /// Angular rate [rad/s], raw (the bias is removed here).
    pub gyro_rad_s: [f32; 3],
    /// Specific force [m/s²] (reads `+g` along up at rest).
    pub accel_m_s2: [f32; 3],
    /// Sample time \[µs\], the same clock as `now_us` elsewhere.
    pub time_us: u64,
}

/// Motor commands of one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotorOutput {
    /// Throttle per motor in [0, 1] (0 = stopped), order of [`crate::mixer`]; never NaN;
    /// all 0 when disarmed.
    pub throttle: [f32; 4],
    /// Whether the motors may spin.
    pub armed: bool,
}

impl MotorOutput {
    const STOPPED: Self = Self {
        throttle: [0.0; 4],
        armed: false,
    };
}

/// The flight pipeline.
///
/// `repr(C)`, the fields in the order the step uses them: the per-IMU-sample path's state
/// first (the estimator's scalars, the Mahony filter and the counters then sit within the
/// Cortex-M4's 1 KiB `vldr`/`vstr` offset range of one base register; in Rust's own order the
/// filter came about 7 KiB into the pipeline, and each of its loads and stores took an extra
/// address instruction, on every sample), then the control tick's and the pose frame's, then
/// what only commands, parameters and telemetry use. M4F bench: 193 instructions less per
/// full step (docs/m4f-bench.md).
#[repr(C)]
pub struct FlightPipeline {
    // The per-sample path's state.
    cfg: FlightConfig,
    estimator: Estimator,
    mahony: Mahony,
    /// [`mahony_dt_cap`] of `cfg`.
    mahony_dt_cap: f32,
    counters: Counters,
    was_calibrating: bool,
    // The control tick's and the pose frame's.
    supervisor: Supervisor,
    mission: ModeMachine,
    last_tick_us: Option<u64>,
    pending_non_finite: bool,
    landed: LandedDetector,
    last_mix: Option<MixOutput>,
    last_output: MotorOutput,
    failsafe_thrust: f32,
    status_position: [f32; 3],
    status_velocity: [f32; 3],
    status_attitude: UnitQuaternion<f32>,
    status_rates: [f32; 3],
    status_reference: [f32; 3],
    /// The reference's velocity \[m/s\], acceleration \[m/s²\] (NWU), heading (cos ψ, sin ψ)
    /// and its rate \[1/s\] at the last flown tick (`POSITION_TARGET_LOCAL_NED`; the yaw is
    /// computed when that is sent, outside the control step).
    status_reference_motion: ([f32; 3], [f32; 3], [f32; 2], [f32; 2]),
    status_error: f32,
    status_pose_age: u64,
    reference: FlightReference,
    mixer: Mixer,
    decoder: Decoder,
    controller: Option<Controller<f32>>,
    // The rest.
    /// The set-up the pipeline was built with: what `MAV_CMD_PREFLIGHT_STORAGE` resets to.
    built: FlightConfig,
    report: BootReport,
    table: SupTable,
    events: EventQueue,
    acks: Deque<(MavCmd, MavResult, Sender), 8>,
    texts: Deque<(MavSeverity, &'static str, &'static str), 8>,
    params: ParamQueue,
    sequence: u8,
    schedule: Schedule,
    /// `TIMESYNC` answers due: (tc1 \[ns\], the request's ts1).
    timesync: Deque<(i64, i64), 2>,
    /// The last arming point \[m\], NWU (`HOME_POSITION`).
    home: Vector3<f32>,
    /// The control step's share of its period \[per mille\] (`SYS_STATUS.load`).
    load_permille: u16,
    /// The parameter store's hold on arming.
    storage: storage::StorageHold,
    /// `HIL_ACTUATOR_CONTROLS.controls[k]` carries rotor `motor_slots[k]`'s throttle.
    #[cfg(feature = "hil")]
    motor_slots: [usize; 4],
    /// Time of the latest `HIL_SENSOR` \[µs\]: the simulation's clock.
    #[cfg(feature = "hil")]
    hil_time_us: Option<u64>,
    /// Tick time \[µs\] whose HIL outputs are not sent yet.
    #[cfg(feature = "hil")]
    hil_pending: Option<u64>,
    /// The stored mission (an accepted upload; [`crate::mission`]).
    mission_items: heapless::Vec<crate::mission::MissionItem, { crate::mission::CAPACITY }>,
    /// The upload in progress.
    mission_transfer: crate::mission::Transfer,
    /// The item a mission start begins with (`MISSION_SET_CURRENT`), then the one flown.
    mission_current: u16,
    /// The mission being flown.
    mission_run: Option<mission_flight::MissionRun>,
    /// Mission-protocol replies due.
    mission_replies: Deque<crate::mission::MissionReply, 8>,
    /// The local frame's origin on WGS84 (`SET_GPS_GLOBAL_ORIGIN`), for global mission items.
    global_origin: Option<crate::mission::GlobalOrigin>,
    /// `STATUSTEXT`s with numbers (mission refusals), formatted when queued.
    long_texts: Deque<(MavSeverity, heapless::String<50>), 4>,
}

/// The Mahony filter's limit on its time step \[s\]: [`FlightConfig::mahony_dt_max`], or +∞
/// when that is NaN (`fmin(x, NaN)` is `x`), so that `min(x, cap)` by one comparison is
/// `fmin(x, mahony_dt_max)` for every `x` that is not NaN.
fn mahony_dt_cap(cfg: &FlightConfig) -> f32 {
    if cfg.mahony_dt_max.is_nan() {
        f32::INFINITY
    } else {
        cfg.mahony_dt_max
    }
}

impl FlightPipeline {
    /// The configuration (with the accepted parameter changes).
    pub fn config(&self) -> &FlightConfig {
        &self.cfg
    }

    /// The mixer (geometry, for host-sim's plant).
    pub fn mixer(&self) -> &Mixer {
        &self.mixer
    }

    /// The last allocation (achieved thrust/torque, what was given up), if any.
    pub fn last_mix(&self) -> Option<MixOutput> {
        self.last_mix
    }

    /// Airmode's rotor envelope in the controller flying now (the rotors' range shrunk by
    /// [`FlightConfig::box_margin`]; [`gate::airmode_envelope`]), or `None` when disarmed or
    /// airmode is off ([`FlightConfig::airmode`]).
    pub fn airmode(&self) -> Option<controller_core::RotorEnvelope<f32>> {
        self.controller.as_ref().and_then(|c| c.airmode().copied())
    }

    /// Logs a state change and queues its STATUSTEXT; the failsafe freezes the integral
    /// estimate (the failsafe law does not step the controller today, so the estimate is held
    /// anyway; the freeze keeps it so should the failsafe ever fly the law while descending);
    /// disarming drops the controller and returns the mode machine to idle (arming builds a new
    /// one: the estimate restarts from zero).
    ///
    /// The test inline, the change out of line: most ticks have no transition.
    #[inline(always)]
    fn transition(&mut self, t: Option<Transition>) {
        if let Some(t) = t {
            self.change_state(t);
        }
    }

    /// [`FlightPipeline::transition`]'s work.
    #[inline(never)]
    fn change_state(&mut self, t: Transition) {
        self.event(Event::StateChanged {
            from: t.from,
            to: t.to,
            reason: t.reason,
        });
        let severity = if t.to == FlightState::Failsafe {
            MavSeverity::MAV_SEVERITY_CRITICAL
        } else {
            MavSeverity::MAV_SEVERITY_INFO
        };
        if self
            .texts
            .push_back((severity, t.to.name(), t.reason))
            .is_err()
        {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
        if t.to == FlightState::Failsafe {
            if let Some(c) = self.controller.as_mut() {
                c.set_integral_frozen(true);
            }
        }
        if t.to == FlightState::Disarmed {
            self.controller = None;
            self.set_mode(Mode::Idle);
        }
    }

    /// Switches the mode machine to `mode`, logging a change.
    fn set_mode(&mut self, mode: Mode) {
        if let Some(mode) = self.mission.enter(mode) {
            self.event(Event::ModeChanged { mode });
        }
    }

    /// Whether the controller flies (armed, not idle on the ground).
    fn flying(&self) -> bool {
        self.mission.flying(self.supervisor.state())
    }

    /// One IMU sample (≥ 1 kHz). Non-finite samples are counted and ignored.
    pub fn on_imu(&mut self, sample: &ImuSample) {
        self.counters.imu_samples = self.counters.imu_samples.saturating_add(1);
        let gyro = Vector3::from(sample.gyro_rad_s);
        let accel = Vector3::from(sample.accel_m_s2);
        if !self.estimator.on_imu(&gyro, &accel, sample.time_us) {
            self.non_finite("imu");
            return;
        }
        // `fmin(interval, cfg.mahony_dt_max)` (the interval is never NaN: 0 or a positive
        // time), with the test of the limit for NaN done once, in `mahony_dt_cap`.
        let interval = self.estimator.imu_interval_s();
        let dt = if interval < self.mahony_dt_cap {
            interval
        } else {
            self.mahony_dt_cap
        };
        // The estimator has refused non-finite samples already.
        // (`dt` is never NaN or +∞: see `update_finite_dt`.)
        self.mahony
            .update_finite_dt(&self.estimator.angular_velocity(), &accel, dt);
        if self.was_calibrating && !self.estimator.calibrating() {
            self.was_calibrating = false;
            let b = self.estimator.gyro_bias();
            self.event(Event::Calibrated {
                bias: [b.x, b.y, b.z],
            });
        }
    }

    /// MAVLink bytes from the UART, any chunking.
    pub fn on_link_bytes(&mut self, bytes: &[u8], now_us: u64) {
        // Each message is handled as soon as its last byte is in: one byte can release many
        // frames at once (those a corrupted length byte held back), and none may be lost.
        // (`feed_into`, not `feed`: the message is written where it is handled, not copied.)
        let mut rest = bytes;
        loop {
            let mut message = None;
            let used = self.decoder.feed_into(rest, &mut message);
            rest = &rest[used..];
            match message {
                Some(m) => self.handle(m, now_us),
                None => break,
            }
            // Fed whole and nothing held back: another call could complete nothing.
            if rest.is_empty() && self.decoder.holds_nothing() {
                break;
            }
        }
        self.counters.link = self.decoder.counters();
    }

    /// Lockstep input (`hil` feature; [`lockstep`]): takes bytes from the front of `bytes`
    /// until one completes a message and handles it, dated by the simulation's clock as the
    /// stream left it, i.e. the time of the last `HIL_SENSOR` before it in the stream \[µs\]
    /// (0 before the first). Returns how many bytes were taken and what was handled; `(n,
    /// Incomplete)` when all `n` given completed nothing. Unlike [`Self::on_link_bytes`], whose
    /// caller dates a whole read, this makes the date and the tick boundary depend on the bytes
    /// only, not on how they were cut into reads.
    #[cfg(feature = "hil")]
    pub fn on_link_message(&mut self, bytes: &[u8]) -> (usize, lockstep::Fed) {
        let (used, message) = self.decoder.feed(bytes);
        let fed = match message {
            None => lockstep::Fed::Incomplete,
            Some(m) => {
                let sensor = matches!(m, crate::link::Inbound::HilSensor { .. });
                self.handle(m, self.hil_time_us.unwrap_or(0));
                match (sensor, self.hil_time_us) {
                    (true, Some(clock_us)) => lockstep::Fed::HilSensor { clock_us },
                    _ => lockstep::Fed::Message,
                }
            }
        };
        self.counters.link = self.decoder.counters();
        (used, fed)
    }

    /// One control tick (every [`FlightConfig::control_period`]): the motor throttles for
    /// `now_us`. Never panics; never NaN.
    pub fn control_tick(&mut self, now_us: u64) -> MotorOutput {
        self.counters.control_ticks = self.counters.control_ticks.saturating_add(1);
        let nominal = self.cfg.control_period();
        let [lo, hi] = self.cfg.control_dt_ratio;
        let dt = match self.last_tick_us {
            // (`micros_f32`, `fmax`, `fmin`: the same values as the `u64` cast and `f32::max`
            // and `min`, without their library calls on the MCU.)
            Some(t) if now_us > t => fmin(
                fmax(micros_f32(now_us - t) * 1e-6, lo * nominal),
                hi * nominal,
            ),
            _ => nominal,
        };
        self.last_tick_us = Some(now_us);
        let est = self.estimator.estimate(now_us);
        let pose_age = self.estimator.pose_age_us(now_us);
        self.status_pose_age = pose_age.unwrap_or(u64::MAX);
        if let (Some(e), Some(age)) = (est, pose_age) {
            if age <= self.cfg.safety.failsafe_pose_age_us {
                self.mahony.anchor(&e.attitude);
            }
        }
        let landed = self.landed(now_us, est.as_ref());
        let inputs = TickInputs {
            pose_age_us: pose_age,
            non_finite: core::mem::take(&mut self.pending_non_finite),
            landed,
        };
        let t = self.supervisor.tick(now_us, &inputs);
        self.transition(t);

        let mut out = match self.supervisor.state() {
            FlightState::Disarmed => {
                self.last_mix = None;
                MotorOutput::STOPPED
            }
            FlightState::Armed if self.mission.mode() == Mode::Idle => {
                self.last_mix = None;
                MotorOutput {
                    throttle: [self.cfg.rotors.throttle_idle; 4],
                    armed: true,
                }
            }
            FlightState::Armed => match self.fly(now_us, dt, est) {
                Some(o) => o,
                None => {
                    let t = self
                        .supervisor
                        .failsafe(now_us, "controller or estimate failed");
                    self.transition(t);
                    self.failsafe_output()
                }
            },
            FlightState::Failsafe => self.failsafe_output(),
        };
        // Last line of defence: no NaN reaches a motor, nothing spins disarmed.
        // (One probe, `Σ 0·u`, finite iff every throttle is, instead of four tests.)
        if !finite_probe(0.0, &Vector4::from(out.throttle)).is_finite() {
            self.non_finite("throttle");
            out.throttle = [0.0; 4];
        }
        if !out.armed {
            out.throttle = [0.0; 4];
        }
        for u in out.throttle.iter_mut() {
            *u = u.clamp(0.0, 1.0);
        }
        if let Some(e) = est {
            self.status_position = [e.position.x, e.position.y, e.position.z];
            self.status_velocity = [e.velocity.x, e.velocity.y, e.velocity.z];
            self.status_attitude = e.attitude;
            self.status_rates = [
                e.angular_velocity.x,
                e.angular_velocity.y,
                e.angular_velocity.z,
            ];
        }
        self.last_output = out;
        #[cfg(feature = "hil")]
        {
            self.hil_pending = Some(now_us);
        }
        out
    }

    /// Landed: at the end of a landing (armed), or on the ground in the failsafe
    /// ([`LandedDetector`] on this tick's inputs).
    fn landed(&mut self, now_us: u64, est: Option<&Estimate>) -> bool {
        let input = match self.supervisor.state() {
            FlightState::Armed if self.mission.mode() == Mode::Land => match est {
                Some(e) => LandedInputs::Landing {
                    position_z: e.position.z,
                    velocity: e.velocity,
                    ground_z: self.mission.ground_z(),
                },
                None => LandedInputs::Other,
            },
            FlightState::Failsafe => LandedInputs::Failsafe {
                time_in_failsafe_us: self.supervisor.failsafe_time_us(now_us),
                vertical_velocity: self.estimator.vertical_velocity(),
                thrust: self.failsafe_thrust,
                specific_force: self.estimator.specific_force(),
            },
            _ => LandedInputs::Other,
        };
        self.landed.update(&input)
    }

    /// Allocates `thrust` \[N\] and `torque` [N m] (FLU) to the rotors and converts to
    /// throttles; counts a saturated allocation.
    fn mix_to_output(&mut self, thrust: f32, torque: &Vector3<f32>) -> MotorOutput {
        let m = self.mixer.mix(thrust, torque);
        if m.saturated() {
            self.counters.mixer_saturations = self.counters.mixer_saturations.saturating_add(1);
        }
        self.last_mix = Some(m);
        MotorOutput {
            throttle: m.thrust.map(|f| self.cfg.rotors.throttle_from_thrust(f)),
            armed: true,
        }
    }

    /// The controller's tick on the estimate: reference sample, law, mode machine, mixer.
    /// `None` when there is no estimate or controller, or the law failed (non-finite).
    fn fly(&mut self, now_us: u64, dt: f32, est: Option<Estimate>) -> Option<MotorOutput> {
        let e = est?;
        let (reference, end) = if self.reference.mode() == ReferenceMode::Waypoints {
            self.mission_sample(now_us, &e.position)
        } else {
            (
                self.reference.sample(now_us),
                mission_flight::MissionEnd::Flying,
            )
        };
        let state = VehicleState {
            position: e.position,
            velocity: e.velocity,
            attitude: e.attitude,
            angular_velocity: e.angular_velocity,
        };
        let ctl = self.controller.as_mut()?;
        // Only the thrust and torque leave the match: moving the whole output (its diagnostics
        // are about 200 bytes) would copy it.
        let (thrust, torque) = match ctl.step(&state, &reference, dt) {
            Ok(o) => (o.thrust, o.torque),
            Err(_) => {
                self.non_finite("controller");
                return None;
            }
        };
        self.status_reference = [
            reference.position.x,
            reference.position.y,
            reference.position.z,
        ];
        self.status_reference_motion = (
            reference.velocity.into(),
            reference.acceleration.into(),
            reference.heading.into(),
            reference.heading_rate.into(),
        );
        self.status_error = norm(&(e.position - reference.position));
        let target = self.reference.filter().target().0;
        if let Some(mode) = self.mission.tick(&self.cfg.reference, &e.position, &target) {
            self.event(Event::ModeChanged { mode });
        }
        if let mission_flight::MissionEnd::Done { land } = end {
            self.end_mission(land, &reference, now_us);
        }
        Some(self.mix_to_output(thrust, &torque))
    }
}
