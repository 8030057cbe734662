//! The safety state machine: when the vehicle may arm, when it falls back to the IMU-only
//! failsafe, when it disarms.
//!
//! - Boot: `Disarmed`.
//! - `Disarmed → Armed` on an arm command only if: the gyro is calibrated and the estimate
//!   converged, the last pose is fresh (`< arm_pose_max_age_us`, 50 ms) and finite, and the
//!   vehicle is upright (`e₃ᵀRe₃ ≥ upright_min_cos`) unless the command explicitly asks to arm
//!   upside down and the configuration allows it (the controller is global).
//! - `Armed → Failsafe` when the pose is older than `failsafe_pose_age_us` (100 ms), or on any
//!   non-finite value: IMU-only attitude hold, level, with a descent thrust.
//! - `Failsafe → Disarmed` when the pose is older than `disarm_pose_age_us` (2 s), after that
//!   long minus the failsafe threshold in the failsafe whatever its cause, or on the ground.
//!   A pose that comes back does not end the failsafe (it is a landing, not a pause).
//! - `Armed → Disarmed` when landed at the end of a landing, on a disarm command on the ground.
//! - Kill (any state): `Disarmed` at once.

use crate::config::SafetyConfig;

/// Flight state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlightState {
    /// Motors stopped (throttle 0).
    Disarmed,
    /// Flying the controller.
    Armed,
    /// IMU-only level attitude hold with descent thrust.
    Failsafe,
}

impl FlightState {
    /// Name for logs.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Disarmed => "disarmed",
            Self::Armed => "armed",
            Self::Failsafe => "failsafe",
        }
    }
}

/// Why an arm command was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArmRefusal {
    /// Already armed or in failsafe.
    NotDisarmed,
    /// Gyro calibration not finished (keep the vehicle still).
    Calibrating,
    /// No pose yet, or the estimator has not converged.
    NotConverged,
    /// The last pose is older than the limit.
    PoseStale,
    /// The last pose message held NaN/Inf or a bad quaternion.
    PoseNonFinite,
    /// Upside down (or tilted beyond the limit) without the explicit inverted-arm flag.
    NotUpright,
    /// Inverted arming asked for but disabled in the configuration.
    InvertedNotAllowed,
    /// The reference at arming is refused by the certificate.
    ReferenceRefused,
    /// A parameter save to flash is pending or under way: a sector erase stalls the CPU (and
    /// the control loop) for up to seconds on a single-bank flash, which only a disarmed vehicle
    /// can afford.
    SavingParameters,
}

impl ArmRefusal {
    /// Reason for logs and STATUSTEXT.
    pub fn reason(&self) -> &'static str {
        match self {
            Self::NotDisarmed => "not disarmed",
            Self::Calibrating => "gyro calibrating, keep still",
            Self::NotConverged => "estimate not converged",
            Self::PoseStale => "pose stale (> SAF_ARM_AGE)",
            Self::PoseNonFinite => "pose non-finite",
            Self::NotUpright => "not upright (use the inverted-arm flag)",
            Self::InvertedNotAllowed => "inverted arming disabled",
            Self::ReferenceRefused => "reference refused by the certificate",
            Self::SavingParameters => "saving parameters to flash, retry",
        }
    }

    /// What lifts it, hence its MAVLink answer ([`Remedy`]).
    pub fn remedy(&self) -> Remedy {
        match self {
            Self::Calibrating
            | Self::NotConverged
            | Self::PoseStale
            | Self::PoseNonFinite
            | Self::SavingParameters => Remedy::Wait,
            Self::NotUpright | Self::ReferenceRefused => Remedy::Fix,
            Self::NotDisarmed | Self::InvertedNotAllowed => Remedy::OtherCommand,
        }
    }
}

/// What lifts a refused command, which decides its `COMMAND_ACK` result (MAVLink common
/// `MAV_RESULT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Remedy {
    /// Waiting alone (the calibration ends, the estimate converges, the next pose arrives, the
    /// parameter save ends): `MAV_RESULT_TEMPORARILY_REJECTED`.
    Wait,
    /// The command is valid, but the vehicle must change first (its set-up certified, its
    /// attitude upright): `MAV_RESULT_FAILED`, as the spec's "arm with uncalibrated sensors".
    Fix,
    /// The same command will not work in this state or with these parameters (not armed, in
    /// flight, a mode or message it does not have, inverted arming disabled):
    /// `MAV_RESULT_DENIED`.
    OtherCommand,
}

/// What the arm check looks at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmInputs {
    /// Gyro still calibrating.
    pub calibrating: bool,
    /// Estimator converged.
    pub converged: bool,
    /// Age of the last good pose \[µs\] (`None`: never).
    pub pose_age_us: Option<u64>,
    /// The last pose message was refused as non-finite.
    pub pose_bad: bool,
    /// `e₃ᵀ R e₃` of the estimate (1 upright, −1 upside down).
    pub up_cos: f32,
    /// The command asked to arm upside down explicitly.
    pub inverted_requested: bool,
    /// The board's parameter store has a save (or reset) pending or under way.
    pub storage_busy: bool,
}

/// The arm decision for `state` and `inputs`.
pub fn check_arm(cfg: &SafetyConfig, state: FlightState, i: &ArmInputs) -> Result<(), ArmRefusal> {
    if state != FlightState::Disarmed {
        return Err(ArmRefusal::NotDisarmed);
    }
    if i.storage_busy {
        return Err(ArmRefusal::SavingParameters);
    }
    if i.calibrating {
        return Err(ArmRefusal::Calibrating);
    }
    if i.pose_bad {
        return Err(ArmRefusal::PoseNonFinite);
    }
    match i.pose_age_us {
        None => return Err(ArmRefusal::NotConverged),
        Some(a) if a >= cfg.arm_pose_max_age_us => return Err(ArmRefusal::PoseStale),
        Some(_) => {}
    }
    if !i.converged {
        return Err(ArmRefusal::NotConverged);
    }
    if !(i.up_cos.is_finite() && i.up_cos >= cfg.upright_min_cos) {
        if !i.inverted_requested {
            return Err(ArmRefusal::NotUpright);
        }
        if !cfg.allow_inverted_arming {
            return Err(ArmRefusal::InvertedNotAllowed);
        }
    }
    Ok(())
}

/// A state change with its reason.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Old state.
    pub from: FlightState,
    /// New state.
    pub to: FlightState,
    /// Why.
    pub reason: &'static str,
}

/// What the supervisor looks at every control tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TickInputs {
    /// Age of the last good pose \[µs\] (`None`: never).
    pub pose_age_us: Option<u64>,
    /// A non-finite value was seen since the last tick.
    pub non_finite: bool,
    /// Landed (end of a landing, or on the ground in failsafe).
    pub landed: bool,
}

/// The safety state machine of the module docs: the [`FlightState`] (`Disarmed`, `Armed`,
/// `Failsafe`), the thresholds it applies ([`SafetyConfig`]: pose ages in µs, the upright
/// cosine, the failsafe's duration) and when the failsafe began \[µs\].
///
/// It decides and reports, nothing more: each call ([`Supervisor::arm`], [`Supervisor::kill`],
/// [`Supervisor::disarm`], [`Supervisor::failsafe`], [`Supervisor::tick`]) takes the time and
/// plain inputs and returns the [`Transition`] it made, if any; the pipeline applies it to the
/// motors and logs it. Arming checks are separate ([`check_arm`], with its [`ArmRefusal`] and
/// remedy), as the state machine stays apart from the checks that feed it. Never fails: a call
/// that does not apply in the current state returns `None`.
/// Source: the project's safety rules (docs/firmware-safety.md), in the manner of PX4's
/// commander and Crazyflie's supervisor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Supervisor {
    cfg: SafetyConfig,
    state: FlightState,
    failsafe_since_us: u64,
}

impl Supervisor {
    /// Disarmed.
    pub fn new(cfg: SafetyConfig) -> Self {
        Self {
            cfg,
            state: FlightState::Disarmed,
            failsafe_since_us: 0,
        }
    }

    /// The state.
    pub fn state(&self) -> FlightState {
        self.state
    }

    /// Time in failsafe at `now_us` \[µs\] (0 when not in failsafe).
    pub fn failsafe_time_us(&self, now_us: u64) -> u64 {
        if self.state == FlightState::Failsafe {
            now_us.saturating_sub(self.failsafe_since_us)
        } else {
            0
        }
    }

    fn go(&mut self, to: FlightState, now_us: u64, reason: &'static str) -> Option<Transition> {
        if self.state == to {
            return None;
        }
        let t = Transition {
            from: self.state,
            to,
            reason,
        };
        if to == FlightState::Failsafe {
            self.failsafe_since_us = now_us;
        }
        self.state = to;
        Some(t)
    }

    /// Arms (the caller has run [`check_arm`]).
    pub fn arm(&mut self, now_us: u64) -> Option<Transition> {
        self.go(FlightState::Armed, now_us, "arm command")
    }

    /// Kill: disarmed at once.
    pub fn kill(&mut self, now_us: u64) -> Option<Transition> {
        self.go(FlightState::Disarmed, now_us, "kill command")
    }

    /// Disarm with `reason`.
    pub fn disarm(&mut self, now_us: u64, reason: &'static str) -> Option<Transition> {
        self.go(FlightState::Disarmed, now_us, reason)
    }

    /// Enters the failsafe with `reason` (from Armed only).
    pub fn failsafe(&mut self, now_us: u64, reason: &'static str) -> Option<Transition> {
        if self.state == FlightState::Armed {
            self.go(FlightState::Failsafe, now_us, reason)
        } else {
            None
        }
    }

    /// One control tick.
    pub fn tick(&mut self, now_us: u64, i: &TickInputs) -> Option<Transition> {
        let c = &self.cfg;
        let age = i.pose_age_us.unwrap_or(u64::MAX);
        match self.state {
            FlightState::Disarmed => None,
            FlightState::Armed => {
                if i.non_finite {
                    self.go(FlightState::Failsafe, now_us, "non-finite value")
                } else if age > c.failsafe_pose_age_us {
                    self.go(FlightState::Failsafe, now_us, "pose lost (> SAF_FS_AGE)")
                } else if i.landed {
                    self.go(FlightState::Disarmed, now_us, "landed")
                } else {
                    None
                }
            }
            FlightState::Failsafe => {
                let in_failsafe = now_us.saturating_sub(self.failsafe_since_us);
                let limit = c.disarm_pose_age_us.saturating_sub(c.failsafe_pose_age_us);
                if age > c.disarm_pose_age_us {
                    self.go(
                        FlightState::Disarmed,
                        now_us,
                        "pose lost (> SAF_DISARM_AGE)",
                    )
                } else if in_failsafe >= limit {
                    self.go(FlightState::Disarmed, now_us, "failsafe time out")
                } else if i.landed {
                    self.go(FlightState::Disarmed, now_us, "on the ground in failsafe")
                } else {
                    None
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::FlightConfig;

    fn cfg() -> SafetyConfig {
        FlightConfig::paper().safety
    }

    fn ok_inputs() -> ArmInputs {
        ArmInputs {
            calibrating: false,
            converged: true,
            pose_age_us: Some(10_000),
            pose_bad: false,
            up_cos: 1.0,
            inverted_requested: false,
            storage_busy: false,
        }
    }

    #[test]
    fn arm_checks() {
        let c = cfg();
        let d = FlightState::Disarmed;
        assert_eq!(check_arm(&c, d, &ok_inputs()), Ok(()));
        let with = |f: &dyn Fn(&mut ArmInputs)| {
            let mut i = ok_inputs();
            f(&mut i);
            check_arm(&c, d, &i)
        };
        assert_eq!(
            with(&|i| i.pose_age_us = Some(50_000)),
            Err(ArmRefusal::PoseStale)
        );
        assert_eq!(
            with(&|i| i.storage_busy = true),
            Err(ArmRefusal::SavingParameters)
        );
        assert_eq!(ArmRefusal::SavingParameters.remedy(), Remedy::Wait);
        assert_eq!(ArmRefusal::NotUpright.remedy(), Remedy::Fix);
        assert_eq!(ArmRefusal::NotDisarmed.remedy(), Remedy::OtherCommand);
        assert_eq!(with(&|i| i.pose_age_us = Some(49_999)), Ok(()));
        assert_eq!(
            with(&|i| i.pose_age_us = None),
            Err(ArmRefusal::NotConverged)
        );
        assert_eq!(with(&|i| i.pose_bad = true), Err(ArmRefusal::PoseNonFinite));
        assert_eq!(
            with(&|i| i.calibrating = true),
            Err(ArmRefusal::Calibrating)
        );
        assert_eq!(
            with(&|i| i.converged = false),
            Err(ArmRefusal::NotConverged)
        );
        assert_eq!(with(&|i| i.up_cos = -1.0), Err(ArmRefusal::NotUpright));
        assert_eq!(with(&|i| i.up_cos = f32::NAN), Err(ArmRefusal::NotUpright));
        assert_eq!(
            with(&|i| {
                i.up_cos = -1.0;
                i.inverted_requested = true
            }),
            Ok(())
        );
        let mut strict = c;
        strict.allow_inverted_arming = false;
        let mut i = ok_inputs();
        i.up_cos = -1.0;
        i.inverted_requested = true;
        assert_eq!(
            check_arm(&strict, d, &i),
            Err(ArmRefusal::InvertedNotAllowed)
        );
        assert_eq!(
            check_arm(&c, FlightState::Armed, &ok_inputs()),
            Err(ArmRefusal::NotDisarmed)
        );
    }

    /// The paper configuration's timings: failsafe after 100 ms without pose, disarm after 2 s.
    #[test]
    fn timings() {
        let mut s = Supervisor::new(cfg());
        s.arm(0);
        let tick = |s: &mut Supervisor, now: u64, last_pose: u64| {
            s.tick(
                now,
                &TickInputs {
                    pose_age_us: Some(now - last_pose),
                    non_finite: false,
                    landed: false,
                },
            )
        };
        assert_eq!(tick(&mut s, 1_100_000, 1_000_000), None);
        let t = tick(&mut s, 1_110_000, 1_000_000).unwrap();
        assert_eq!((t.from, t.to), (FlightState::Armed, FlightState::Failsafe));
        assert_eq!(tick(&mut s, 2_990_000, 1_000_000), None);
        let t = tick(&mut s, 3_010_000, 1_000_000).unwrap();
        assert_eq!(t.to, FlightState::Disarmed);
    }

    #[test]
    fn non_finite_and_kill() {
        let mut s = Supervisor::new(cfg());
        s.arm(0);
        let t = s
            .tick(
                10,
                &TickInputs {
                    pose_age_us: Some(0),
                    non_finite: true,
                    landed: false,
                },
            )
            .unwrap();
        assert_eq!(t.to, FlightState::Failsafe);
        assert_eq!(s.kill(20).unwrap().to, FlightState::Disarmed);
        assert_eq!(s.kill(30), None);
    }
}
