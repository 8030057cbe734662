//! Commands from the ground station and the certificate gate. Each inbound MAVLink message
//! (pose, command, hover setpoint, HIL sensor sample) is dispatched here; commands are
//! answered with a `COMMAND_ACK` and refusals logged and sent as `STATUSTEXT`. A new reference
//! (hold at arming, takeoff, land, setpoint, demo mission) is flown only if every condition of
//! the a-priori bound certificate holds for its constants and the certified `(T, τ)` box fits the
//! rotors with the configured margin ([`FlightPipeline::accept`], [`super::gate`]), and the
//! controller takes it; arming also needs the built set-up's own certificate (its demo mission).

use controller_core::{certify, Controller, FilterStart, TrajectoryConstants};
use mavlink::dialects::common::{MavCmd, MavResult, MavSeverity};
use nalgebra::Vector3;

#[cfg(feature = "hil")]
use super::ImuSample;
use super::{Event, FlightPipeline, Mode};
use crate::estimator::PoseCheck;
use crate::flight_reference::{FlightReference, ReferenceMode};
use crate::link::{Command, CommandFault, Inbound, Sender, SetupAuthority, SigningConfig};
use crate::safety::{check_arm, ArmInputs, FlightState, Remedy};

/// Refusal detail for events and STATUSTEXT: the reason, and for a certificate or
/// parameter refusal the condition with both sides (`condition` empty otherwise); `remedy`
/// decides the `COMMAND_ACK` result.
pub(super) struct Refusal {
    reason: &'static str,
    remedy: Remedy,
    condition: &'static str,
    lhs: f32,
    rhs: f32,
}

impl Refusal {
    /// Why, for logs and `STATUSTEXT`.
    pub(super) fn reason(&self) -> &'static str {
        self.reason
    }
}

impl FlightPipeline {
    /// One decoded inbound message at `now_us`.
    ///
    /// Never inlined: inlined into the message loop of `on_link_bytes`, its many field
    /// addresses were hoisted out of that loop and spilled to the stack on every call, about
    /// 180 Cortex-M4F instructions per tick for a loop that runs once.
    #[inline(never)]
    pub(super) fn handle(&mut self, m: Inbound, now_us: u64) {
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
            Inbound::Command {
                command,
                mav_cmd,
                sender,
            } => {
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
                        match refusal.remedy {
                            Remedy::Wait => MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
                            Remedy::Fix => MavResult::MAV_RESULT_FAILED,
                            Remedy::OtherCommand => MavResult::MAV_RESULT_DENIED,
                        }
                    }
                };
                self.ack(mav_cmd, r, sender);
            }
            Inbound::CommandFault {
                mav_cmd,
                fault,
                sender,
            } => {
                let r = match fault {
                    CommandFault::Unsupported => MavResult::MAV_RESULT_UNSUPPORTED,
                    CommandFault::BadParameter => MavResult::MAV_RESULT_DENIED,
                };
                self.ack(mav_cmd, r, sender);
            }
            Inbound::Timesync { tc1: 0, ts1 } => {
                let tc1 = (now_us as i64).saturating_mul(1000);
                if self.timesync.push_back((tc1, ts1)).is_err() {
                    self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
                }
            }
            // An answer to someone else's request.
            Inbound::Timesync { .. } => {}
            Inbound::SetupSigning {
                key,
                initial_timestamp,
                authority,
                ..
            } => {
                if let Err(r) = self.setup_signing(key, initial_timestamp, authority) {
                    self.refused("setup_signing", &r);
                }
            }
            Inbound::Setpoint { position, yaw } => {
                if let Err(r) = self.setpoint(position, yaw, now_us) {
                    self.refused("setpoint", &r);
                }
            }
            Inbound::Mission { message, sender } => self.mission_message(message, sender, now_us),
            Inbound::ParamRequestList => self.param_request_list(),
            Inbound::ParamRequestRead { id, index } => self.param_request_read(&id, index),
            Inbound::ParamSet { id, value, real32 } => self.param_set(&id, value, real32),
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

    /// Queues a `COMMAND_ACK` for `sender`, or counts it dropped when the queue is full.
    fn ack(&mut self, mav_cmd: MavCmd, result: MavResult, sender: Sender) {
        if self.acks.push_back((mav_cmd, result, sender)).is_err() {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    /// `SETUP_SIGNING`: installs the key, or replaces the one in force, if the message came
    /// over a link trusted at build time or was signed with the key in force (`authority`,
    /// from the decoder), and only while disarmed. A refusal changes nothing and is counted,
    /// logged and sent as a `STATUSTEXT` naming why.
    fn setup_signing(
        &mut self,
        key: [u8; 32],
        initial_timestamp: u64,
        authority: SetupAuthority,
    ) -> Result<(), Refusal> {
        // Checked first: a stranger's key is refused for who sent it, whatever the state.
        if authority == SetupAuthority::Unauthenticated {
            return Err(Self::simple("unsigned on an untrusted link"));
        }
        if self.supervisor.state() != FlightState::Disarmed {
            return Err(Self::simple("signing is set up while disarmed"));
        }
        let config = SigningConfig {
            key,
            link_id: 0,
            accept_unsigned_sensors: self.cfg.accept_unsigned_sensors,
        };
        if !self.decoder.install_signing_key(config, initial_timestamp) {
            return Err(Self::simple("signing key refused (all zero)"));
        }
        self.event(Event::CommandAccepted {
            command: "setup_signing",
        });
        Ok(())
    }

    /// Counts and logs a refused command or setpoint, and queues its STATUSTEXT.
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
        if self
            .texts
            .push_back((MavSeverity::MAV_SEVERITY_WARNING, command, r.reason))
            .is_err()
        {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    /// A refusal with a reason only, that waiting does not lift.
    pub(super) fn simple(reason: &'static str) -> Refusal {
        Refusal {
            reason,
            remedy: Remedy::OtherCommand,
            condition: "",
            lhs: 0.0,
            rhs: 0.0,
        }
    }

    /// Certificate gate for a new reference: refuses it unless every certificate condition
    /// holds (Assumption 1, Theorem 1, Lemma 1, Theorem 2, the extensions') and the rotors
    /// realise the certified `(T, τ)` with the configured margin ([`super::gate::check`]), or
    /// when the controller refuses it. Sets the controller's thrust mode for the reference and,
    /// with [`crate::config::FlightConfig::airmode`], its airmode envelope
    /// ([`super::gate::airmode_envelope`]). With
    /// [`crate::config::FlightConfig::allow_uncertified`] (the `uncertified-paper` build only) a
    /// failure is logged as [`Event::Uncertified`] instead.
    pub(super) fn accept(
        &mut self,
        k: &TrajectoryConstants<f32>,
        start: FilterStart,
    ) -> Result<(), Refusal> {
        let c = &self.cfg;
        let cert = match certify(&c.vehicle, &c.limits, &c.gains, k, start) {
            Ok(cert) => cert,
            Err(e) => {
                let r = crate::report::refusal(&e);
                return Err(Refusal {
                    reason: "reference refused: parameter",
                    remedy: Remedy::Fix,
                    condition: r.name,
                    lhs: r.value as f32,
                    rhs: f32::NAN,
                });
            }
        };
        let warning = match super::gate::check(&cert, c, &self.mixer) {
            Ok(_) => None,
            Err(f) if c.allow_uncertified => Some(f),
            Err(f) => {
                return Err(Refusal {
                    reason: "reference not certified",
                    remedy: Remedy::Fix,
                    condition: f.condition,
                    lhs: f.lhs,
                    rhs: f.rhs,
                })
            }
        };
        // Airmode flies the rotor range the gate's shadow fits were checked on.
        let airmode = super::gate::airmode_envelope(c, &self.mixer);
        let controller = match self.controller.as_mut() {
            Some(ctl) => ctl,
            None => return Err(Self::simple("not armed")),
        };
        // Vertical priority's cap is this reference's T_max; a floor the gate let through is
        // within T_min, so the mode is valid here (checked again by the controller).
        if let Err(e) = controller
            .accept_reference(k)
            .and_then(|()| controller.set_thrust_mode(c.thrust.mode(&cert.bounds)))
        {
            let r = crate::report::refusal(&e);
            return Err(Refusal {
                reason: "reference refused by the controller",
                remedy: Remedy::Fix,
                condition: r.name,
                lhs: r.value as f32,
                rhs: r.high as f32,
            });
        }
        controller.set_airmode(airmode);
        if let Some(f) = warning {
            self.event(Event::Uncertified {
                condition: f.condition,
                lhs: f.lhs,
                rhs: f.rhs,
            });
        }
        Ok(())
    }

    /// Where the filter starts for a reference change: zero before the controller has run.
    pub(super) fn filter_start(&self) -> FilterStart {
        if self.mission.mode() == Mode::Idle {
            FilterStart::Zero
        } else {
            FilterStart::InSaturationBox
        }
    }

    /// Flies to `target` (NWU \[m\]) with `yaw` \[rad\] through the setpoint filter in `mode`,
    /// if the certificate gate accepts the filter's constants.
    fn go_to(
        &mut self,
        target: Vector3<f32>,
        yaw: f32,
        now_us: u64,
        mode: Mode,
    ) -> Result<(), Refusal> {
        self.leave_mission();
        let proposed = self.reference.proposed(now_us, target, yaw);
        let k = proposed.constants();
        self.accept(&k, self.filter_start())?;
        self.reference.set_target(proposed);
        self.set_mode(mode);
        Ok(())
    }

    /// Runs command `c`, or says why not.
    pub(super) fn run_command(&mut self, c: Command, now_us: u64) -> Result<(), Refusal> {
        self.command(c, now_us)
    }

    /// Runs command `c`, or says why not.
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
                FlightState::Armed if self.mission.mode() == Mode::Idle => {
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
                    storage_busy: self.storage.busy(),
                };
                check_arm(&self.cfg.safety, state, &inputs).map_err(|r| Refusal {
                    remedy: r.remedy(),
                    ..Self::simple(r.reason())
                })?;
                // The set-up the firmware was built with (its demo mission, filters at zero)
                // must be certified before anything else is.
                match self.report.gate {
                    Ok(_) => {}
                    Err(f) if self.cfg.allow_uncertified => self.event(Event::Uncertified {
                        condition: f.condition,
                        lhs: f.lhs,
                        rhs: f.rhs,
                    }),
                    Err(f) => {
                        return Err(Refusal {
                            reason: "set-up not certified",
                            remedy: Remedy::Fix,
                            condition: f.condition,
                            lhs: f.lhs,
                            rhs: f.rhs,
                        })
                    }
                }
                let est = est.ok_or(Refusal {
                    remedy: Remedy::Wait,
                    ..Self::simple("no estimate")
                })?;
                let controller = Controller::new(
                    self.cfg.vehicle,
                    self.cfg.gains,
                    &TrajectoryConstants::zero(),
                )
                .map_err(|_| Refusal {
                    remedy: Remedy::Fix,
                    ..Self::simple("controller refused")
                })?;
                self.controller = Some(controller);
                let (_, _, yaw) = est.attitude.euler_angles();
                // A mission interrupted by a failsafe or a disarm is not resumed.
                self.mission_run = None;
                self.reference = FlightReference::new(
                    self.cfg.reference.smoothing_rate,
                    est.position,
                    yaw,
                    self.table,
                    self.cfg.mission,
                );
                // The hold reference (constants zero) must pass the gate too.
                if let Err(r) = self.accept(&TrajectoryConstants::zero(), FilterStart::Zero) {
                    self.controller = None;
                    return Err(r);
                }
                self.landed.reset();
                if let Some(mode) = self.mission.armed(est.position.z) {
                    self.event(Event::ModeChanged { mode });
                }
                let t = self.supervisor.arm(now_us);
                self.transition(t);
                self.home = est.position;
                self.schedule.request_now(super::schedule::Periodic::Home);
                Ok(())
            }
            Command::Takeoff { height } => {
                let position = self.estimator.estimate(now_us).map(|e| e.position);
                let target = self
                    .mission
                    .takeoff_target(&self.cfg.reference, state, position, height)
                    .map_err(Self::simple)?;
                let (_, yaw) = self.reference.filter().output();
                self.go_to(target, yaw, now_us, Mode::Takeoff)
            }
            Command::Land => {
                let position = self.estimator.estimate(now_us).map(|e| e.position);
                let target = self
                    .mission
                    .land_target(&self.cfg.reference, state, position)
                    .map_err(Self::simple)?;
                let (_, yaw) = self.reference.filter().output();
                self.landed.reset();
                self.go_to(target, yaw, now_us, Mode::Land)
            }
            Command::RequestMessage { id } => self.request_message(id).map_err(Self::simple),
            Command::SetMode { custom_mode } => self.set_mode_command(custom_mode, now_us),
            Command::SetMessageInterval { id, interval_us } => self
                .set_message_interval(id, interval_us)
                .map_err(Self::simple),
            Command::ResetParams => self.reset_params().map_err(Self::simple),
            // An uploaded mission is flown when one is stored; otherwise the built-in one.
            Command::StartHelix if !self.mission_items.is_empty() => self.start_mission(now_us),
            Command::StartHelix => self.start_helix(now_us),
        }
    }

    /// The built-in mission (the flight file's trajectory, e.g. the helix) from now on, if armed
    /// and the gate accepts its constants.
    fn start_helix(&mut self, now_us: u64) -> Result<(), Refusal> {
        if self.supervisor.state() != FlightState::Armed {
            return Err(Self::simple("not armed"));
        }
        let k = self.reference.helix_constants();
        self.accept(&k, self.filter_start())?;
        self.leave_mission();
        self.reference.start_helix(now_us);
        self.set_mode(Mode::Helix);
        Ok(())
    }

    /// `MAV_CMD_DO_SET_MODE`: custom mode 1 hovers where the vehicle is, 2 takes off, 3 lands,
    /// 4 flies the built-in helix, 5 the uploaded mission, through the same checks as their own
    /// commands.
    fn set_mode_command(&mut self, custom_mode: u8, now_us: u64) -> Result<(), Refusal> {
        match custom_mode {
            1 => {
                let est = self.estimator.estimate(now_us).ok_or_else(|| Refusal {
                    remedy: Remedy::Wait,
                    ..Self::simple("no estimate")
                })?;
                let (_, _, yaw) = est.attitude.euler_angles();
                self.setpoint(est.position, Some(yaw), now_us)
            }
            2 => self.command(Command::Takeoff { height: None }, now_us),
            3 => self.command(Command::Land, now_us),
            4 => self.start_helix(now_us),
            5 => self.start_mission(now_us),
            _ => Err(Self::simple("unknown mode")),
        }
    }

    /// A hover setpoint: position NWU \[m\], yaw \[rad\] (`None`: keep the current target's).
    fn setpoint(
        &mut self,
        position: Vector3<f32>,
        yaw: Option<f32>,
        now_us: u64,
    ) -> Result<(), Refusal> {
        self.mission
            .setpoint_allowed(self.supervisor.state())
            .map_err(Self::simple)?;
        let yaw = yaw.unwrap_or_else(|| self.reference.filter().target().1);
        if self.reference.filter().target() == (position, yaw)
            && self.reference.mode() == ReferenceMode::Setpoint
        {
            return Ok(()); // repeated setpoint (GCS streams): nothing to do
        }
        self.go_to(position, yaw, now_us, Mode::Hover)
    }
}
