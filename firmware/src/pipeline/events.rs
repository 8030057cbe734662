//! What the board logs: events (state and mode changes, refusals, non-finite values) in a
//! bounded queue, monotone counters and the status snapshot. Plain numbers and static strings,
//! so the board formats them with defmt and host-sim prints them.

use heapless::Deque;

use super::{FlightPipeline, Mode};
use crate::link::LinkCounters;
use crate::safety::FlightState;

/// Something the board logs with defmt (plain numbers and static strings).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// The gyro calibration finished; bias [rad/s] FLU.
    Calibrated {
        /// Bias [rad/s].
        bias: [f32; 3],
    },
    /// The flight state changed.
    StateChanged {
        /// Old state.
        from: FlightState,
        /// New state.
        to: FlightState,
        /// Why.
        reason: &'static str,
    },
    /// The reference mode changed.
    ModeChanged {
        /// New mode.
        mode: Mode,
    },
    /// A command was accepted.
    CommandAccepted {
        /// Command name.
        command: &'static str,
    },
    /// A command, setpoint or parameter change was refused.
    CommandRefused {
        /// Command name (`"setpoint"` for a hover target, the parameter's name for a
        /// `PARAM_SET`, `"param_set"` for one with an unknown name).
        command: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// A reference or parameter change was refused by the certificate: the violated condition
    /// with both sides (`lhs > rhs` should hold), or a parameter refusal (`lhs` = its value,
    /// `rhs` = NaN or the admissible bound).
    ReferenceRefused {
        /// Condition or parameter name.
        condition: &'static str,
        /// Left-hand side / value.
        lhs: f32,
        /// Right-hand side.
        rhs: f32,
    },
    /// An uncertified set-up or reference was accepted (only with
    /// [`crate::config::FlightConfig::allow_uncertified`], the `uncertified-paper` build): the
    /// first failing condition (or a `rotor_fit.*` fit) with both sides. The a-priori bounds are
    /// not guaranteed, or the rotors cannot deliver them.
    Uncertified {
        /// Condition name.
        condition: &'static str,
        /// Left-hand side.
        lhs: f32,
        /// Right-hand side.
        rhs: f32,
    },
    /// A `PARAM_SET` was taken: the set-up flown from now on has `name` = `value` (in the
    /// parameter's unit, [`crate::params::ParamDesc::unit`]) and is certified.
    ParamChanged {
        /// Parameter name ([`crate::params::ParamDesc::name`]).
        name: &'static str,
        /// The new value.
        value: f32,
    },
    /// `MAV_CMD_PREFLIGHT_STORAGE` reset: the build's flight file is flown again, and a board's
    /// store should forget the saved parameters.
    ParamsReset,
    /// An uploaded mission's item was reached (`MISSION_ITEM_REACHED`).
    MissionItemReached {
        /// The item's sequence number.
        seq: u16,
    },
    /// A non-finite value was found (and counted).
    NonFinite {
        /// Where.
        source: &'static str,
    },
}

/// Counters for the logs (monotone).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// MAVLink frame counters.
    pub link: LinkCounters,
    /// Non-finite values found (pose, IMU, controller, mixer).
    pub non_finite: u32,
    /// Commands and setpoints refused.
    pub refused_commands: u32,
    /// Events lost because the queue was full.
    pub events_dropped: u32,
    /// Ticks in which the mixer gave something up.
    pub mixer_saturations: u32,
    /// Control ticks run.
    pub control_ticks: u32,
    /// IMU samples received.
    pub imu_samples: u32,
    /// Poses used by the estimator.
    pub poses_used: u32,
    /// Telemetry frames not sent for lack of room.
    pub telemetry_dropped: u32,
    /// `COMMAND_ACK`s and `STATUSTEXT`s lost because their queue was full (the command itself
    /// was handled; a ground station retries an unacknowledged one).
    pub replies_dropped: u32,
}

/// Snapshot for the logs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PipelineStatus {
    /// Flight state.
    pub state: FlightState,
    /// Reference mode.
    pub mode: Mode,
    /// Gyro calibration running.
    pub calibrating: bool,
    /// Estimator converged.
    pub converged: bool,
    /// Age of the last good pose \[µs\] at the last tick (`u64::MAX`: never).
    pub pose_age_us: u64,
    /// Counters.
    pub counters: Counters,
    /// Estimated position \[m\], NWU.
    pub position: [f32; 3],
    /// Estimated velocity [m/s], NWU.
    pub velocity: [f32; 3],
    /// Reference position \[m\], NWU.
    pub reference_position: [f32; 3],
    /// `|p − p_d|` \[m\] (0 when not flying the controller).
    pub position_error: f32,
    /// Commanded collective thrust \[N\] (after the mixer).
    pub thrust: f32,
    /// Commanded torque [N m], FLU (after the mixer).
    pub torque: [f32; 3],
    /// Last motor throttles.
    pub throttle: [f32; 4],
    /// The integral action's filtered estimate `η_f` [m/s²], NWU (inertial): what the law adds
    /// to `u` against a constant disturbance (docs/integral-action.md). Zero while disarmed or
    /// with the integral action off; held from the failsafe's start.
    pub integral: [f32; 3],
    /// The feedforward scale `μ_f` (dimensionless): the law applies `(1 + μ_f) p̈_d`
    /// (controller-core `feedforward_scale`). Zero while disarmed or with it off; held from the
    /// failsafe's start.
    pub feedforward_scale: f32,
}

/// Event queue length: the events of a burst of commands and state changes within one log
/// period; more are counted as dropped ([`Counters::events_dropped`]).
pub(super) const EVENTS: usize = 16;

/// The bounded event queue, oldest first.
pub(super) type EventQueue = Deque<Event, EVENTS>;

impl FlightPipeline {
    /// Queues `e` for the log; counts it as dropped when the queue is full.
    pub(super) fn event(&mut self, e: Event) {
        if self.events.push_back(e).is_err() {
            self.counters.events_dropped = self.counters.events_dropped.saturating_add(1);
        }
    }

    /// Counts a non-finite value found at `source`, logs it, and tells the next tick's
    /// supervisor (which sends an armed vehicle to the failsafe).
    pub(super) fn non_finite(&mut self, source: &'static str) {
        self.counters.non_finite = self.counters.non_finite.saturating_add(1);
        self.pending_non_finite = true;
        self.event(Event::NonFinite { source });
    }

    /// Snapshot of the state and counters.
    pub fn status(&self) -> PipelineStatus {
        let mix = self.last_mix;
        PipelineStatus {
            state: self.supervisor.state(),
            mode: self.mission.mode(),
            calibrating: self.estimator.calibrating(),
            converged: self.estimator.converged(),
            pose_age_us: self.status_pose_age,
            counters: self.counters,
            position: self.status_position,
            velocity: self.status_velocity,
            reference_position: self.status_reference,
            position_error: if self.flying() {
                self.status_error
            } else {
                0.0
            },
            thrust: mix.map_or(0.0, |m| m.achieved_thrust),
            torque: mix.map_or([0.0; 3], |m| {
                [
                    m.achieved_torque.x,
                    m.achieved_torque.y,
                    m.achieved_torque.z,
                ]
            }),
            throttle: self.last_output.throttle,
            integral: self
                .controller
                .as_ref()
                .map_or([0.0; 3], |c| c.integral_state().filtered.into()),
            feedforward_scale: self
                .controller
                .as_ref()
                .map_or(0.0, |c| c.feedforward_scale_state().filtered),
        }
    }

    /// The next event (state change, refusal, …), oldest first.
    pub fn take_events(&mut self) -> Option<Event> {
        self.events.pop_front()
    }
}
