//! The flight pipeline: IMU and MAVLink in, motor throttles and telemetry out. Everything the
//! firmware flies, with no register and no logging, so host-sim runs the very same code.
//!
//! Per control tick (100 Hz): estimate at `now` → safety supervisor → by state: disarmed
//! (throttle 0), armed idle (idle throttle, waiting for takeoff / mission / setpoint), armed
//! flying (reference → controller-core law → mixer → thrust curve), failsafe (IMU-only level
//! attitude hold with the paper's saturated attitude law and a descent thrust). Any non-finite
//! value on the way is counted and sends an armed vehicle to the failsafe; the throttles are
//! checked finite last of all.

use controller_core::attitude_control::AttitudeGains;
use controller_core::mrp::rotation_from_quaternion;
use controller_core::{
    certify, Certificate, Controller, FilterStart, ParameterError, TrajectoryConstants,
    VehicleState,
};
use heapless::Deque;
use mavlink::dialects::common::{
    MavAutopilot, MavCmd, MavModeFlag, MavResult, MavSeverity, MavState, MavType,
    ATTITUDE_QUATERNION_DATA, COMMAND_ACK_DATA, HEARTBEAT_DATA, LOCAL_POSITION_NED_DATA,
    STATUSTEXT_DATA,
};
use nalgebra::{UnitQuaternion, Vector3};

use crate::config::FlightConfig;
use crate::estimator::{Estimator, EstimatorConfig, PoseCheck};
use crate::flight_reference::{FlightReference, ReferenceMode, SupTable};
use crate::frames;
use crate::imu_attitude::Mahony;
use crate::link::{self, Command, Decoder, Inbound, LinkCounters};
use crate::mixer::{BoxFit, MixOutput, Mixer, MixerError};
use crate::safety::{check_arm, ArmInputs, FlightState, Supervisor, TickInputs, Transition};

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

/// Why the pipeline cannot be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BootError {
    /// A vehicle, limit, gain or reference parameter is refused (see
    /// [`crate::report::refusal`] to flatten it for logs).
    Parameter(ParameterError),
    /// The rotor geometry or range is unusable.
    Mixer(MixerError),
}

/// What the board logs at boot: the certificate of the demo mission (the paper's helix, filters
/// starting at zero) and whether its a-priori `(T, τ)` box fits inside the rotors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BootReport {
    /// The a-priori bound certificate for the helix demo.
    pub certificate: Certificate<f32>,
    /// The certificate's box `[T_min, T_max] × Π[−τ_i, τ_i]` against the rotors.
    pub a_priori_fit: BoxFit,
    /// Total rotor thrust capacity `4 f_max` \[N\] (vs the configured `T_max`).
    pub thrust_capacity: f32,
}

/// What the reference is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Armed on the ground at idle throttle, or disarmed.
    Idle,
    /// Hovering at / moving to a setpoint.
    Hover,
    /// Taking off to a height.
    Takeoff,
    /// Landing.
    Land,
    /// The paper's helix.
    Helix,
}

impl Mode {
    /// Name for logs.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Idle => "idle",
            Self::Hover => "hover",
            Self::Takeoff => "takeoff",
            Self::Land => "land",
            Self::Helix => "helix",
        }
    }
}

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
    /// A command or setpoint was refused.
    CommandRefused {
        /// Command name (`"setpoint"` for a hover target).
        command: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// A reference was refused by the certificate: the violated condition with both sides
    /// (`lhs > rhs` should hold), or a parameter refusal (`lhs` = its value, `rhs` = NaN).
    ReferenceRefused {
        /// Condition or parameter name.
        condition: &'static str,
        /// Left-hand side / value.
        lhs: f32,
        /// Right-hand side.
        rhs: f32,
    },
    /// A reference was accepted although a Theorem 2 condition fails (bounds not guaranteed;
    /// the conditions are sufficient, not necessary).
    ReferenceWarning {
        /// Condition name.
        condition: &'static str,
        /// Left-hand side.
        lhs: f32,
        /// Right-hand side.
        rhs: f32,
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
}

/// Event queue length.
const EVENTS: usize = 16;

/// The flight pipeline.
pub struct FlightPipeline {
    cfg: FlightConfig,
    mixer: Mixer,
    report: BootReport,
    table: SupTable,
    estimator: Estimator,
    mahony: Mahony,
    decoder: Decoder,
    supervisor: Supervisor,
    controller: Option<Controller<f32>>,
    reference: FlightReference,
    mode: Mode,
    ground_z: f32,
    last_tick_us: Option<u64>,
    last_imu_us: Option<u64>,
    pending_non_finite: bool,
    landed_ticks: u32,
    last_mix: Option<MixOutput>,
    last_output: MotorOutput,
    failsafe_thrust: f32,
    events: Deque<Event, EVENTS>,
    acks: Deque<(MavCmd, MavResult), 8>,
    texts: Deque<(MavSeverity, &'static str, &'static str), 8>,
    sequence: u8,
    next_heartbeat_us: u64,
    next_state_us: u64,
    counters: Counters,
    status_position: [f32; 3],
    status_velocity: [f32; 3],
    status_attitude: UnitQuaternion<f32>,
    status_rates: [f32; 3],
    status_reference: [f32; 3],
    status_error: f32,
    status_pose_age: u64,
    was_calibrating: bool,
    /// Time of the latest `HIL_SENSOR` \[µs\]: the simulation's clock.
    #[cfg(feature = "hil")]
    hil_time_us: Option<u64>,
    /// Tick time \[µs\] whose HIL outputs are not sent yet.
    #[cfg(feature = "hil")]
    hil_pending: Option<u64>,
}

/// Refusal detail for events and STATUSTEXT.
struct Refusal {
    reason: &'static str,
    condition: &'static str,
    lhs: f32,
    rhs: f32,
}

impl FlightPipeline {
    /// Builds the pipeline: certifies the helix demo, builds the mixer and checks the a-priori
    /// box against the rotors. Errors: [`BootError`].
    pub fn new(config: &FlightConfig) -> Result<Self, BootError> {
        let cfg = *config;
        let mixer = Mixer::new(&cfg.rotors).map_err(BootError::Mixer)?;
        let table = SupTable::PRECOMPUTED;
        let reference =
            FlightReference::new(cfg.reference.smoothing_rate, Vector3::zeros(), 0.0, table);
        let certificate = certify(
            &cfg.vehicle,
            &cfg.limits,
            &cfg.gains,
            &reference.helix_constants(),
            FilterStart::Zero,
        )
        .map_err(BootError::Parameter)?;
        // The controller must accept a hover (constants zero) too.
        Controller::new(cfg.vehicle, cfg.gains, &TrajectoryConstants::zero())
            .map_err(BootError::Parameter)?;
        let b = &certificate.bounds;
        let a_priori_fit = mixer.box_fit(b.thrust_min, b.thrust_max, &b.torque_max);
        let report = BootReport {
            certificate,
            a_priori_fit,
            thrust_capacity: 4.0 * cfg.rotors.thrust_max,
        };
        let estimator = Estimator::new(EstimatorConfig {
            latency_us: cfg.mocap_latency_us,
            calibration_samples: cfg.gyro_calibration_samples,
            position_sigma: cfg.mocap_position_sigma,
            accel_psd: cfg.velocity_filter_accel_psd,
            gravity: cfg.vehicle.gravity,
        });
        Ok(Self {
            cfg,
            mixer,
            report,
            table,
            estimator,
            mahony: Mahony::new(
                cfg.mahony_gains[0],
                cfg.mahony_gains[1],
                cfg.vehicle.gravity,
            ),
            decoder: Decoder::new(cfg.system_id),
            supervisor: Supervisor::new(cfg.safety),
            controller: None,
            reference,
            mode: Mode::Idle,
            ground_z: 0.0,
            last_tick_us: None,
            last_imu_us: None,
            pending_non_finite: false,
            landed_ticks: 0,
            last_mix: None,
            last_output: MotorOutput::STOPPED,
            failsafe_thrust: 0.0,
            events: Deque::new(),
            acks: Deque::new(),
            texts: Deque::new(),
            sequence: 0,
            next_heartbeat_us: 0,
            next_state_us: 0,
            counters: Counters::default(),
            status_position: [0.0; 3],
            status_velocity: [0.0; 3],
            status_attitude: UnitQuaternion::identity(),
            status_rates: [0.0; 3],
            status_reference: [0.0; 3],
            status_error: 0.0,
            status_pose_age: u64::MAX,
            was_calibrating: true,
            #[cfg(feature = "hil")]
            hil_time_us: None,
            #[cfg(feature = "hil")]
            hil_pending: None,
        })
    }

    /// The boot certificate and the mixer fit, for the defmt banner.
    pub fn boot_report(&self) -> BootReport {
        self.report
    }

    /// The configuration.
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

    fn event(&mut self, e: Event) {
        if self.events.push_back(e).is_err() {
            self.counters.events_dropped = self.counters.events_dropped.saturating_add(1);
        }
    }

    fn non_finite(&mut self, source: &'static str) {
        self.counters.non_finite = self.counters.non_finite.saturating_add(1);
        self.pending_non_finite = true;
        self.event(Event::NonFinite { source });
    }

    fn transition(&mut self, t: Option<Transition>) {
        if let Some(t) = t {
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
            let _ = self.texts.push_back((severity, t.to.name(), t.reason));
            if t.to == FlightState::Disarmed {
                self.controller = None;
                self.set_mode(Mode::Idle);
            }
        }
    }

    fn set_mode(&mut self, mode: Mode) {
        if self.mode != mode {
            self.mode = mode;
            self.event(Event::ModeChanged { mode });
        }
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
        let dt = match self.last_imu_us {
            Some(t) if sample.time_us > t => ((sample.time_us - t) as f32 * 1e-6).min(0.01),
            _ => 0.0,
        };
        self.last_imu_us = Some(sample.time_us);
        self.mahony
            .update(&self.estimator.angular_velocity(), &accel, dt);
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
        // A 32-byte slice holds at most two complete frames (12 bytes minimum, plus a tail).
        for chunk in bytes.chunks(32) {
            let mut got: heapless::Vec<Inbound, 4> = heapless::Vec::new();
            self.decoder.push(chunk, |m| {
                let _ = got.push(m);
            });
            for m in got {
                self.handle(m, now_us);
            }
        }
        self.counters.link = self.decoder.counters();
    }

    fn handle(&mut self, m: Inbound, now_us: u64) {
        match m {
            Inbound::Pose {
                position, attitude, ..
            } => match self.estimator.on_pose(&position, &attitude, now_us) {
                PoseCheck::Used => {
                    self.counters.poses_used = self.counters.poses_used.saturating_add(1)
                }
                PoseCheck::NonFinite => self.non_finite("pose"),
                // A quaternion far from unit norm is as unusable as a NaN: same handling.
                PoseCheck::BadQuaternion => self.non_finite("pose quaternion"),
                PoseCheck::OutOfOrder => {}
            },
            Inbound::Command { command, mav_cmd } => {
                let result = self.command(command, now_us);
                let r = match result {
                    Ok(()) => {
                        self.event(Event::CommandAccepted {
                            command: command.name(),
                        });
                        MavResult::MAV_RESULT_ACCEPTED
                    }
                    Err(refusal) => {
                        self.refused(command.name(), &refusal);
                        MavResult::MAV_RESULT_DENIED
                    }
                };
                let _ = self.acks.push_back((mav_cmd, r));
            }
            Inbound::Setpoint { position, yaw } => {
                if let Err(r) = self.setpoint(position, yaw, now_us) {
                    self.refused("setpoint", &r);
                }
            }
            #[cfg(feature = "hil")]
            Inbound::HilSensor {
                gyro_rad_s,
                accel_m_s2,
                time_us,
            } => {
                self.on_imu(&ImuSample {
                    gyro_rad_s,
                    accel_m_s2,
                    time_us,
                });
                self.hil_time_us = Some(self.hil_time_us.map_or(time_us, |t| t.max(time_us)));
            }
        }
    }

    /// Time of the latest `HIL_SENSOR` sample \[µs\] (`hil` feature only): the simulation's
    /// clock, which paces the processor-in-the-loop control ticks. `None` before the first.
    #[cfg(feature = "hil")]
    pub fn hil_time_us(&self) -> Option<u64> {
        self.hil_time_us
    }

    fn refused(&mut self, command: &'static str, r: &Refusal) {
        self.counters.refused_commands = self.counters.refused_commands.saturating_add(1);
        self.event(Event::CommandRefused {
            command,
            reason: r.reason,
        });
        if !r.condition.is_empty() {
            self.event(Event::ReferenceRefused {
                condition: r.condition,
                lhs: r.lhs,
                rhs: r.rhs,
            });
        }
        let _ = self
            .texts
            .push_back((MavSeverity::MAV_SEVERITY_WARNING, command, r.reason));
    }

    fn simple(reason: &'static str) -> Refusal {
        Refusal {
            reason,
            condition: "",
            lhs: 0.0,
            rhs: 0.0,
        }
    }

    /// Certificate gate for a new reference: refuses when an Assumption 1 or Theorem 1
    /// condition fails (or Theorem 2 too if configured), or when the controller refuses it.
    fn accept(&mut self, k: &TrajectoryConstants<f32>, start: FilterStart) -> Result<(), Refusal> {
        let c = &self.cfg;
        let cert = match certify(&c.vehicle, &c.limits, &c.gains, k, start) {
            Ok(cert) => cert,
            Err(e) => {
                let r = crate::report::refusal(&e);
                return Err(Refusal {
                    reason: "reference refused: parameter",
                    condition: r.name,
                    lhs: r.value as f32,
                    rhs: f32::NAN,
                });
            }
        };
        let strict = c.safety.require_theorem2;
        let mut warnings: heapless::Vec<(&'static str, f32, f32), 4> = heapless::Vec::new();
        for cond in cert.violations() {
            if cond.name.starts_with("theorem2") && !strict {
                let _ = warnings.push((cond.name, cond.lhs, cond.rhs));
            } else {
                return Err(Refusal {
                    reason: "reference infeasible (certificate)",
                    condition: cond.name,
                    lhs: cond.lhs,
                    rhs: cond.rhs,
                });
            }
        }
        let controller = match self.controller.as_mut() {
            Some(ctl) => ctl,
            None => return Err(Self::simple("not armed")),
        };
        if let Err(e) = controller.accept_reference(k) {
            let r = crate::report::refusal(&e);
            return Err(Refusal {
                reason: "reference refused by the controller",
                condition: r.name,
                lhs: r.value as f32,
                rhs: r.high as f32,
            });
        }
        for (condition, lhs, rhs) in warnings {
            self.event(Event::ReferenceWarning {
                condition,
                lhs,
                rhs,
            });
        }
        Ok(())
    }

    /// Where the filter starts for a reference change: zero before the controller has run.
    fn filter_start(&self) -> FilterStart {
        if self.mode == Mode::Idle {
            FilterStart::Zero
        } else {
            FilterStart::InSaturationBox
        }
    }

    fn flying(&self) -> bool {
        self.supervisor.state() == FlightState::Armed && self.mode != Mode::Idle
    }

    fn go_to(
        &mut self,
        target: Vector3<f32>,
        yaw: f32,
        now_us: u64,
        mode: Mode,
    ) -> Result<(), Refusal> {
        let proposed = self.reference.proposed(now_us, target, yaw);
        let k = proposed.constants();
        self.accept(&k, self.filter_start())?;
        self.reference.set_target(proposed);
        self.set_mode(mode);
        Ok(())
    }

    fn command(&mut self, c: Command, now_us: u64) -> Result<(), Refusal> {
        let state = self.supervisor.state();
        match c {
            Command::Kill => {
                let t = self.supervisor.kill(now_us);
                self.transition(t);
                Ok(())
            }
            Command::Disarm => match state {
                FlightState::Disarmed => Ok(()),
                FlightState::Armed if self.mode == Mode::Idle => {
                    let t = self.supervisor.disarm(now_us, "disarm command");
                    self.transition(t);
                    Ok(())
                }
                _ => Err(Self::simple("in flight: land, or kill")),
            },
            Command::Arm { inverted } => {
                let est = self.estimator.estimate(now_us);
                let up_cos = est.map_or(f32::NAN, |e| (e.attitude * Vector3::z()).z);
                let inputs = ArmInputs {
                    calibrating: self.estimator.calibrating(),
                    converged: self.estimator.converged(),
                    pose_age_us: self.estimator.pose_age_us(now_us),
                    pose_bad: self.estimator.last_pose_bad(),
                    up_cos,
                    inverted_requested: inverted,
                };
                check_arm(&self.cfg.safety, state, &inputs)
                    .map_err(|r| Self::simple(r.reason()))?;
                let est = est.ok_or_else(|| Self::simple("no estimate"))?;
                let controller = Controller::new(
                    self.cfg.vehicle,
                    self.cfg.gains,
                    &TrajectoryConstants::zero(),
                )
                .map_err(|_| Self::simple("controller refused"))?;
                self.controller = Some(controller);
                let (_, _, yaw) = est.attitude.euler_angles();
                self.reference = FlightReference::new(
                    self.cfg.reference.smoothing_rate,
                    est.position,
                    yaw,
                    self.table,
                );
                // The hold reference (constants zero) must pass the gate too.
                if let Err(r) = self.accept(&TrajectoryConstants::zero(), FilterStart::Zero) {
                    self.controller = None;
                    return Err(r);
                }
                self.ground_z = est.position.z;
                self.landed_ticks = 0;
                self.set_mode(Mode::Idle);
                let t = self.supervisor.arm(now_us);
                self.transition(t);
                Ok(())
            }
            Command::Takeoff { height } => {
                if state != FlightState::Armed {
                    return Err(Self::simple("not armed"));
                }
                if !matches!(self.mode, Mode::Idle | Mode::Hover) {
                    return Err(Self::simple("busy"));
                }
                let est = self
                    .estimator
                    .estimate(now_us)
                    .ok_or_else(|| Self::simple("no estimate"))?;
                let h = height.unwrap_or(self.cfg.reference.takeoff_height);
                if !(h.is_finite() && h > 0.0 && h < 100.0) {
                    return Err(Self::simple("bad takeoff height"));
                }
                let (_, yaw) = self.reference.filter().output();
                let target = Vector3::new(est.position.x, est.position.y, self.ground_z + h);
                self.go_to(target, yaw, now_us, Mode::Takeoff)
            }
            Command::Land => {
                if !self.flying() {
                    return Err(Self::simple("not flying"));
                }
                let est = self
                    .estimator
                    .estimate(now_us)
                    .ok_or_else(|| Self::simple("no estimate"))?;
                let (_, yaw) = self.reference.filter().output();
                let target = Vector3::new(
                    est.position.x,
                    est.position.y,
                    self.ground_z - self.cfg.reference.land_undershoot,
                );
                self.landed_ticks = 0;
                self.go_to(target, yaw, now_us, Mode::Land)
            }
            Command::StartHelix => {
                if state != FlightState::Armed {
                    return Err(Self::simple("not armed"));
                }
                let k = self.reference.helix_constants();
                self.accept(&k, self.filter_start())?;
                self.reference.start_helix(now_us);
                self.set_mode(Mode::Helix);
                Ok(())
            }
        }
    }

    fn setpoint(
        &mut self,
        position: Vector3<f32>,
        yaw: Option<f32>,
        now_us: u64,
    ) -> Result<(), Refusal> {
        if !self.flying() {
            return Err(Self::simple("not flying (take off first)"));
        }
        if self.mode == Mode::Land {
            return Err(Self::simple("landing"));
        }
        let yaw = yaw.unwrap_or_else(|| self.reference.filter().target().1);
        if self.reference.filter().target() == (position, yaw)
            && self.reference.mode() == ReferenceMode::Setpoint
        {
            return Ok(()); // repeated setpoint (GCS streams): nothing to do
        }
        self.go_to(position, yaw, now_us, Mode::Hover)
    }

    /// 100 Hz: the motor throttles for `now_us`. Never panics; never NaN.
    pub fn control_tick(&mut self, now_us: u64) -> MotorOutput {
        self.counters.control_ticks = self.counters.control_ticks.saturating_add(1);
        let nominal = self.cfg.control_period;
        let dt = match self.last_tick_us {
            Some(t) if now_us > t => ((now_us - t) as f32 * 1e-6)
                .max(0.2 * nominal)
                .min(5.0 * nominal),
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
            FlightState::Armed if self.mode == Mode::Idle => {
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
        if !out.throttle.iter().all(|u| u.is_finite()) {
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

    /// Landed: at the end of a landing (armed), or on the ground in the failsafe.
    fn landed(&mut self, now_us: u64, est: Option<&crate::estimator::Estimate>) -> bool {
        let r = &self.cfg.reference;
        let on_ground = match self.supervisor.state() {
            FlightState::Armed if self.mode == Mode::Land => est.is_some_and(|e| {
                e.position.z < self.ground_z + r.landed_height && e.velocity.norm() < r.landed_speed
            }),
            FlightState::Failsafe => {
                let g = self.cfg.vehicle.gravity;
                self.supervisor.failsafe_time_us(now_us) > 300_000
                    && self.estimator.vertical_velocity().abs() < 0.15
                    && self.failsafe_thrust < 0.9 * self.cfg.vehicle.mass * g
                    && self.estimator.specific_force().norm() > 0.95 * g
            }
            _ => false,
        };
        self.landed_ticks = if on_ground { self.landed_ticks + 1 } else { 0 };
        self.landed_ticks >= 30
    }

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

    fn fly(
        &mut self,
        now_us: u64,
        dt: f32,
        est: Option<crate::estimator::Estimate>,
    ) -> Option<MotorOutput> {
        let e = est?;
        let reference = self.reference.sample(now_us);
        let state = VehicleState {
            position: e.position,
            velocity: e.velocity,
            attitude: e.attitude,
            angular_velocity: e.angular_velocity,
        };
        let ctl = self.controller.as_mut()?;
        let out = match ctl.step(&state, &reference, dt) {
            Ok(o) => o,
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
        self.status_error = (e.position - reference.position).norm();
        if self.mode == Mode::Takeoff {
            let (target, _) = self.reference.filter().target();
            if (e.position - target).norm() < 0.1 {
                self.set_mode(Mode::Hover);
            }
        }
        Some(self.mix_to_output(out.thrust, &out.torque))
    }

    /// IMU-only level hold: the paper's saturated attitude law towards level at the current
    /// yaw (ω_d = 0), and a thrust that tracks a descent speed on the dead-reckoned vertical
    /// velocity, divided by the tilt cosine (at most 2x).
    fn failsafe_output(&mut self) -> MotorOutput {
        let c = &self.cfg;
        let q = self.mahony.attitude();
        let (_, _, yaw) = q.euler_angles();
        let q_d = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        let mut q_e = (q_d.inverse() * q).into_inner();
        if q_e.w < 0.0 {
            q_e = -q_e;
        }
        let mrp = q_e.imag() / (1.0 + q_e.w);
        let r_e = rotation_from_quaternion(&q_e);
        let omega = self.estimator.angular_velocity();
        let gains: &AttitudeGains<f32> = &c.gains.attitude;
        let torque = gains
            .evaluate(
                &mrp,
                &omega,
                &r_e,
                &Vector3::zeros(),
                &Vector3::zeros(),
                &c.vehicle.inertia,
            )
            .torque;
        let (m, g) = (c.vehicle.mass, c.vehicle.gravity);
        let up = (q * Vector3::z()).z.max(0.5);
        let vz = self.estimator.vertical_velocity();
        let accel = g + 2.0 * (-c.safety.failsafe_descent_speed - vz);
        let [lo, hi] = c.safety.failsafe_thrust_ratio;
        let mut thrust = (m * accel / up).max(lo * m * g).min(hi * m * g);
        let mut torque = torque;
        if !(thrust.is_finite() && torque.iter().all(|x| x.is_finite())) {
            self.non_finite("failsafe");
            thrust = lo * m * g;
            torque = Vector3::zeros();
        }
        self.failsafe_thrust = thrust;
        self.mix_to_output(thrust, &torque)
    }

    /// MAVLink bytes to send now: pending command acks and status texts, a HEARTBEAT every
    /// second, ATTITUDE_QUATERNION and LOCAL_POSITION_NED at 20 Hz (NED/FRD). Returns the
    /// number of bytes written; frames that do not fit wait for the next call.
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
        while let Some(&(command, result)) = self.acks.front() {
            let m = COMMAND_ACK_DATA { command, result };
            match self.put(&m, &mut out[n..]) {
                0 => return n,
                k => n += k,
            }
            self.acks.pop_front();
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
        if now_us >= self.next_heartbeat_us {
            let armed = self.supervisor.state() != FlightState::Disarmed;
            let mut mode = MavModeFlag::MAV_MODE_FLAG_GUIDED_ENABLED
                | MavModeFlag::MAV_MODE_FLAG_STABILIZE_ENABLED;
            if armed {
                mode |= MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED;
            }
            let system_status = match self.supervisor.state() {
                FlightState::Disarmed => MavState::MAV_STATE_STANDBY,
                FlightState::Armed => MavState::MAV_STATE_ACTIVE,
                FlightState::Failsafe => MavState::MAV_STATE_CRITICAL,
            };
            let m = HEARTBEAT_DATA {
                custom_mode: self.mode as u32,
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
            self.next_heartbeat_us = now_us + 1_000_000;
        }
        if now_us >= self.next_state_us {
            let time_boot_ms = (now_us / 1000) as u32;
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
            match self.put(&att, &mut out[n..]) {
                0 => {
                    self.counters.telemetry_dropped += 1;
                    return n;
                }
                k => n += k,
            }
            match self.put(&pos, &mut out[n..]) {
                0 => {
                    self.counters.telemetry_dropped += 1;
                    return n;
                }
                k => n += k,
            }
            self.next_state_us = now_us + 50_000;
        }
        n
    }

    /// The tick's motor commands (`HIL_ACTUATOR_CONTROLS`: throttles in `controls[0..4]`, mixer
    /// order; `mode` has `SAFETY_ARMED` when armed) and reference (`POSITION_TARGET_LOCAL_NED`,
    /// NED \[m\]), both or nothing; returns the bytes written.
    #[cfg(feature = "hil")]
    fn hil_outputs(&mut self, tick_us: u64, out: &mut [u8]) -> usize {
        use mavlink::dialects::common::{
            HilActuatorControlsFlags, MavFrame, PositionTargetTypemask, HIL_ACTUATOR_CONTROLS_DATA,
            POSITION_TARGET_LOCAL_NED_DATA,
        };
        let mut controls = [0.0f32; 16];
        controls[..4].copy_from_slice(&self.last_output.throttle);
        let actuators = HIL_ACTUATOR_CONTROLS_DATA {
            time_usec: tick_us,
            flags: HilActuatorControlsFlags::empty(),
            controls,
            mode: if self.last_output.armed {
                MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
            } else {
                MavModeFlag::empty()
            },
        };
        let r = frames::flip_to_array(&Vector3::from(self.status_reference));
        let target = POSITION_TARGET_LOCAL_NED_DATA {
            time_boot_ms: (tick_us / 1000) as u32,
            x: r[0],
            y: r[1],
            z: r[2],
            type_mask: PositionTargetTypemask::empty(),
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..Default::default()
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

    fn put<D: mavlink::MessageData>(&mut self, m: &D, out: &mut [u8]) -> usize {
        let k = link::encode_data(
            m,
            self.cfg.system_id,
            self.cfg.component_id,
            self.sequence,
            out,
        );
        if k > 0 {
            self.sequence = self.sequence.wrapping_add(1);
        }
        k
    }

    /// Snapshot of the state and counters.
    pub fn status(&self) -> PipelineStatus {
        let mix = self.last_mix;
        PipelineStatus {
            state: self.supervisor.state(),
            mode: self.mode,
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
        }
    }

    /// The next event (state change, refusal, …), oldest first.
    pub fn take_events(&mut self) -> Option<Event> {
        self.events.pop_front()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::MavMessage;
    use mavlink::{MavlinkVersion, MessageData};

    /// Splits telemetry bytes into (msgid, payload) frames (unsigned MAVLink 2 only).
    fn all_frames(bytes: &[u8]) -> Vec<(u32, Vec<u8>)> {
        let mut out = Vec::new();
        let mut i = 0;
        while i + 12 <= bytes.len() {
            assert_eq!(bytes[i], 0xFD);
            let len = bytes[i + 1] as usize;
            let id = u32::from_le_bytes([bytes[i + 7], bytes[i + 8], bytes[i + 9], 0]);
            out.push((id, bytes[i + 10..i + 10 + len].to_vec()));
            i += 12 + len;
        }
        assert_eq!(i, bytes.len());
        out
    }

    /// [`all_frames`] without the HIL outputs (`hil` feature), which lead every tick's
    /// telemetry and have their own test.
    fn frames(bytes: &[u8]) -> Vec<(u32, Vec<u8>)> {
        #[cfg(feature = "hil")]
        let hil = [
            mavlink::dialects::common::HIL_ACTUATOR_CONTROLS_DATA::ID,
            mavlink::dialects::common::POSITION_TARGET_LOCAL_NED_DATA::ID,
        ];
        #[cfg(not(feature = "hil"))]
        let hil: [u32; 0] = [];
        all_frames(bytes)
            .into_iter()
            .filter(|(id, _)| !hil.contains(id))
            .collect()
    }

    fn command(c: MavCmd, p1: f32, p2: f32) -> Vec<u8> {
        let m = MavMessage::COMMAND_LONG(mavlink::dialects::common::COMMAND_LONG_DATA {
            param1: p1,
            param2: p2,
            command: c,
            target_system: 1,
            ..Default::default()
        });
        let mut b = [0u8; link::MAX_FRAME];
        let n = link::encode(&m, 255, 190, 0, &mut b);
        b[..n].to_vec()
    }

    /// The boot report of the paper vehicle: the certificate as in report.rs (only Theorem 2's
    /// yaw condition fails), the a-priori box does not fit the rotors, 12 N of rotor thrust.
    #[test]
    fn boot_report() {
        let p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
        let r = p.boot_report();
        let names: Vec<_> = r.certificate.violations().map(|c| c.name).collect();
        assert_eq!(names, ["theorem2.torque_max_yaw"]);
        assert!(!r.a_priori_fit.fits);
        assert!((r.thrust_capacity - 12.0).abs() < 1e-6);
        assert!((r.a_priori_fit.thrust_needed[0] - 3.512).abs() < 1e-3);
    }

    /// A broken geometry is refused at boot.
    #[test]
    fn bad_rotors_refused() {
        let mut c = FlightConfig::paper();
        c.rotors.thrust_max = f32::NAN;
        assert!(matches!(
            FlightPipeline::new(&c),
            Err(BootError::Mixer(MixerError::BadThrustRange))
        ));
        let mut c = FlightConfig::paper();
        c.gains.reset_threshold = 2.0;
        assert!(matches!(
            FlightPipeline::new(&c),
            Err(BootError::Parameter(_))
        ));
    }

    /// Disarmed at boot: zero throttle; telemetry sends HEARTBEAT (standby, not armed),
    /// ATTITUDE_QUATERNION and LOCAL_POSITION_NED; an arm without pose is denied over MAVLink
    /// (COMMAND_ACK DENIED + STATUSTEXT) and as an event.
    #[test]
    fn boot_telemetry_and_refusal() {
        let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
        let out = p.control_tick(10_000);
        assert_eq!(out, MotorOutput::STOPPED);
        let mut buf = [0u8; 1024];
        let n = p.telemetry(10_000, &mut buf);
        let ids: Vec<u32> = frames(&buf[..n]).iter().map(|f| f.0).collect();
        assert_eq!(
            ids,
            [
                HEARTBEAT_DATA::ID,
                ATTITUDE_QUATERNION_DATA::ID,
                LOCAL_POSITION_NED_DATA::ID
            ]
        );
        let hb = HEARTBEAT_DATA::deser(MavlinkVersion::V2, &frames(&buf[..n])[0].1).unwrap();
        assert_eq!(hb.system_status, MavState::MAV_STATE_STANDBY);
        assert!(!hb
            .base_mode
            .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED));

        p.on_link_bytes(
            &command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0),
            20_000,
        );
        assert_eq!(p.status().counters.refused_commands, 1);
        let n = p.telemetry(20_000, &mut buf);
        let f = frames(&buf[..n]);
        assert_eq!(f[0].0, COMMAND_ACK_DATA::ID);
        let ack = COMMAND_ACK_DATA::deser(MavlinkVersion::V2, &f[0].1).unwrap();
        assert_eq!(ack.result, MavResult::MAV_RESULT_DENIED);
        assert_eq!(f[1].0, STATUSTEXT_DATA::ID);
        let text = STATUSTEXT_DATA::deser(MavlinkVersion::V2, &f[1].1).unwrap();
        assert!(text
            .text
            .to_str()
            .unwrap()
            .starts_with("arm: gyro calibrating"));
        let mut refused = false;
        while let Some(e) = p.take_events() {
            refused |= matches!(e, Event::CommandRefused { command: "arm", .. });
        }
        assert!(refused);
        // Small buffers: nothing is half-written.
        p.on_link_bytes(&command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0), 30_000);
        let mut tiny = [0u8; 8];
        assert_eq!(p.telemetry(30_000, &mut tiny), 0);
        let n = p.telemetry(30_000, &mut buf);
        assert_eq!(frames(&buf[..n])[0].0, COMMAND_ACK_DATA::ID);
    }

    /// Non-finite IMU samples are counted and never reach the motors.
    #[test]
    fn non_finite_imu_is_counted() {
        let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
        p.on_imu(&ImuSample {
            gyro_rad_s: [f32::NAN, 0.0, 0.0],
            accel_m_s2: [0.0, 0.0, 9.81],
            time_us: 1000,
        });
        assert_eq!(p.status().counters.non_finite, 1);
        let out = p.control_tick(10_000);
        assert!(out.throttle.iter().all(|u| *u == 0.0));
        assert!(matches!(
            p.take_events(),
            Some(Event::NonFinite { source: "imu" })
        ));
    }

    /// HIL (`hil` feature): a `HIL_SENSOR` in body FRD reaches the estimator as a FLU sample on
    /// the simulation's clock, one missing IMU flag makes it no sample, and each tick sends
    /// its throttles and reference once, in NED, before any other telemetry.
    #[cfg(feature = "hil")]
    #[test]
    fn hil_sensor_in_actuators_and_reference_out() {
        use mavlink::dialects::common::{
            HilSensorUpdatedFlags, HIL_ACTUATOR_CONTROLS_DATA, HIL_SENSOR_DATA,
            POSITION_TARGET_LOCAL_NED_DATA,
        };
        let sensor = |t: u64, fields: u32| {
            let m = MavMessage::HIL_SENSOR(HIL_SENSOR_DATA {
                time_usec: t,
                // Level and still: the accelerometer reads +g along down's opposite (FRD z up is -z).
                zacc: -9.81,
                xgyro: 0.01,
                ygyro: 0.02,
                zgyro: 0.03,
                fields_updated: HilSensorUpdatedFlags::from_bits_retain(fields),
                ..Default::default()
            });
            let mut b = [0u8; link::MAX_FRAME];
            let n = link::encode(&m, 255, 190, 0, &mut b);
            b[..n].to_vec()
        };
        let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
        assert_eq!(p.hil_time_us(), None);
        p.on_link_bytes(&sensor(1_000, link::HIL_SENSOR_IMU_FIELDS), 0);
        assert_eq!(p.hil_time_us(), Some(1_000));
        assert_eq!(p.status().counters.imu_samples, 1);
        // Without the gyro z flag it is not an IMU sample: dropped, the clock does not move.
        p.on_link_bytes(
            &sensor(2_000, link::HIL_SENSOR_IMU_FIELDS & !0b10_0000),
            1_000,
        );
        assert_eq!(p.hil_time_us(), Some(1_000));
        assert_eq!(p.status().counters.imu_samples, 1);
        assert_eq!(p.status().counters.link.frames_dropped, 1);

        let out = p.control_tick(10_000);
        let mut buf = [0u8; 1024];
        let n = p.telemetry(10_000, &mut buf);
        let got = all_frames(&buf[..n]);
        assert_eq!(got[0].0, HIL_ACTUATOR_CONTROLS_DATA::ID);
        assert_eq!(got[1].0, POSITION_TARGET_LOCAL_NED_DATA::ID);
        let a = HIL_ACTUATOR_CONTROLS_DATA::deser(MavlinkVersion::V2, &got[0].1).unwrap();
        assert_eq!(a.time_usec, 10_000);
        assert_eq!(&a.controls[..4], &out.throttle);
        assert!(a.controls[4..].iter().all(|&c| c == 0.0));
        assert_eq!(
            a.mode.contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED),
            out.armed
        );
        let r = POSITION_TARGET_LOCAL_NED_DATA::deser(MavlinkVersion::V2, &got[1].1).unwrap();
        let reference = p.status().reference_position;
        assert_eq!(
            [r.x, r.y, r.z],
            [reference[0], -reference[1], -reference[2]]
        );
        // Sent once per tick; too little room sends neither and keeps them for the next call.
        let n2 = p.telemetry(10_500, &mut buf);
        assert!(all_frames(&buf[..n2])
            .iter()
            .all(|(id, _)| *id != HIL_ACTUATOR_CONTROLS_DATA::ID));
        p.control_tick(20_000);
        assert_eq!(p.telemetry(20_000, &mut buf[..40]), 0);
        let n3 = p.telemetry(20_000, &mut buf);
        let got = all_frames(&buf[..n3]);
        let a = HIL_ACTUATOR_CONTROLS_DATA::deser(MavlinkVersion::V2, &got[0].1).unwrap();
        assert_eq!(a.time_usec, 20_000);
    }
}
