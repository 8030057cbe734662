//! The vehicle and flight configuration the pipeline flies with: rigid body, actuator limits,
//! gains, X-quad rotor geometry, the thrust-to-throttle curve, rates and safety timings.
//!
//! Units are SI (kg, m, N, N m, s, µs where named `_us`). Frames: body FLU (x forward, y left,
//! z up), inertial NWU (z up); see [`crate::frames`].

use controller_core::{
    Bounds, Gains, Limits, ParameterError, ReferenceTrajectory, ThrustMode, Vehicle,
};

use crate::airframe::Airframe;
pub use crate::airframe::{Rotor, RotorConfig};
use crate::control_rate::ControlRate;
use crate::link::LinkTrust;

/// Time limits of the safety state machine \[µs\] and the failsafe's level-hold law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SafetyConfig {
    /// A pose older than this refuses arming \[µs\]: the controller starts from the pose, so it
    /// must be no more than a few motion-capture periods old.
    pub arm_pose_max_age_us: u64,
    /// A pose older than this in flight starts the IMU-only failsafe \[µs\]: beyond it the
    /// estimate extrapolates too far for the position law to act on it.
    pub failsafe_pose_age_us: u64,
    /// Pose lost this long disarms \[µs\]: the failsafe descent has had time to reach the
    /// ground from a typical indoor height, so stopping the motors no longer drops the vehicle
    /// from height.
    pub disarm_pose_age_us: u64,
    /// Whether an arm command may ask to arm upside down (it must also say so explicitly).
    pub allow_inverted_arming: bool,
    /// Body z must satisfy `e₃ᵀ R e₃ ≥ this` to arm without the inverted flag.
    pub upright_min_cos: f32,
    /// Failsafe: commanded vertical descent speed [m/s] (positive down) from the IMU
    /// dead-reckoned vertical velocity.
    pub failsafe_descent_speed: f32,
    /// Failsafe: gain [1/s] from the vertical speed error to the commanded vertical
    /// acceleration (`a = g + k (−v_descent − v_z)`): a first-order approach to the descent
    /// speed with time constant `1/k`.
    pub failsafe_descent_gain: f32,
    /// Failsafe: smallest tilt cosine `e₃ᵀ R e₃` the thrust is divided by \[dimensionless\], so a
    /// strongly tilted vehicle asks at most `1/this` times the level thrust instead of diverging.
    pub failsafe_tilt_cos_min: f32,
    /// Failsafe: thrust is kept in `[lo, hi] · m g` \[dimensionless\].
    pub failsafe_thrust_ratio: [f32; 2],
}

/// Reference smoothing and missions (takeoff and landing targets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceConfig {
    /// Bandwidth `λ` [1/s] of the fourth-order critically damped setpoint filter.
    pub smoothing_rate: f32,
    /// Default takeoff height above the arming point \[m\] when the command gives none.
    pub takeoff_height: f32,
    /// Largest takeoff height a command may ask for \[m\]: a guard against a garbled or
    /// mis-scaled parameter (e.g. millimetres) sending the vehicle through the ceiling.
    pub takeoff_height_max: f32,
    /// A takeoff ends (mode hover) once the estimated position is within this distance of the
    /// takeoff target \[m\].
    pub takeoff_reached_distance: f32,
    /// Land target: this far below the arming height \[m\] so the vehicle settles on the ground.
    pub land_undershoot: f32,
    /// Uploaded missions: the peak speed of each leg \[m/s\] ([`controller_core::waypoint_path`]).
    pub mission_speed: f32,
    /// Uploaded missions: the peak acceleration of each leg \[m/s²\].
    pub mission_acceleration: f32,
    /// Uploaded missions: the peak yaw rate of each leg \[rad/s\].
    pub mission_yaw_rate: f32,
    /// Uploaded missions: a waypoint whose item gives no acceptance radius (param2 = 0) is
    /// reached within this distance \[m\].
    pub mission_acceptance_radius: f32,
}

/// The landed detector: when the vehicle counts as on the ground, at the end of a landing or
/// in the failsafe (see [`crate::pipeline::LandedDetector`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LandedConfig {
    /// Landing: the vehicle is on the ground below this height above the arming point \[m\]
    /// (the land target undershoots the ground, so the height settles near 0) ...
    pub height: f32,
    /// ... with a speed `|v|` below this [m/s] (the landing reference is still moving, or the
    /// vehicle bounces, above it).
    pub speed: f32,
    /// Failsafe: no ground contact is detected before this time in the failsafe \[µs\], so the
    /// thrust step at its entry (which shakes the accelerometer and the dead-reckoned velocity)
    /// is not mistaken for a touchdown.
    pub failsafe_settle_us: u64,
    /// Failsafe: on the ground, the dead-reckoned vertical speed `|v_z|` is below this [m/s]
    /// (the failsafe descends faster, see [`SafetyConfig::failsafe_descent_speed`]) ...
    pub failsafe_vertical_speed: f32,
    /// ... the commanded thrust is below this fraction of the weight `m g`
    /// \[dimensionless\] (the descent law lowers it once the ground stops the descent) ...
    pub failsafe_thrust_ratio: f32,
    /// ... and the specific force `|f|` is above this fraction of `g` \[dimensionless\] (the
    /// ground carries the weight; in free fall it would read near 0).
    pub failsafe_specific_force_ratio: f32,
    /// How long the conditions must hold, on consecutive control ticks, before the vehicle
    /// counts as landed \[µs\] (counted in ticks of the law's rate, rounded up: see
    /// [`crate::control_rate::ControlRate::ticks_in`]): a bounce or one noisy estimate does not
    /// disarm it.
    pub confirm_us: u64,
}

/// Telemetry rates of [`crate::pipeline::FlightPipeline::telemetry`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TelemetryConfig {
    /// Period of the `HEARTBEAT` \[µs\] (MAVLink's 1 Hz convention: ground stations count the
    /// link lost after a few missed heartbeats).
    pub heartbeat_period_us: u64,
    /// Period of `ATTITUDE_QUATERNION` and `LOCAL_POSITION_NED` \[µs\]: fast enough for a ground
    /// station's display, a fraction of the link the pose stream leaves free.
    pub state_period_us: u64,
}

/// How the collective thrust is computed from the control vector `u` (the flight file's
/// `[controller]` table; docs/no-dive-thrust.md). Whatever the choice, the gate certifies the
/// certified torque set over the choice's thrust interval `[low, high]`
/// ([`ThrustChoice::interval`]; with airmode, that interval at zero torque and the set's shadow,
/// [`crate::pipeline::gate_check`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThrustChoice {
    /// `T = m|u|`: the paper's law (Theorem 1's `[T_min, T_max]`). The default.
    Norm,
    /// The no-dive thrust [`ThrustMode::VerticalPriority`]: tilt-compensated vertical thrust
    /// while the body z axis is above the horizon, ramped down over `e₃ᵀRe₃ ∈ [0, ramp]`, never
    /// below `floor`, capped at each accepted reference's Theorem 1 `T_max`; interval
    /// `[floor, T_max]`.
    VerticalPriority {
        /// `b₀ ∈ (0, 1]` (dimensionless).
        ramp: f32,
        /// `T_floor` \[N\], in `[0, T_min]`: what the rotors keep while the vehicle is upside
        /// down; the certified box must hold the torques there.
        floor: f32,
    },
}

impl ThrustChoice {
    /// The core's thrust mode for a reference whose certificate has `bounds` (the cap of
    /// vertical priority is its Theorem 1 `T_max` \[N\]).
    pub fn mode(&self, bounds: &Bounds<f32>) -> ThrustMode<f32> {
        match *self {
            Self::Norm => ThrustMode::Norm,
            Self::VerticalPriority { ramp, floor } => ThrustMode::VerticalPriority {
                cap: bounds.thrust_max,
                ramp,
                floor,
            },
        }
    }

    /// The thrust interval `[low, high]` \[N\] certified for `bounds` ([`ThrustMode::interval`]).
    /// Errors: [`ParameterError::OutOfRange`] naming `"thrust_floor"` when the floor is above
    /// Theorem 1's `T_min`.
    pub fn interval(&self, bounds: &Bounds<f32>) -> Result<(f32, f32), ParameterError> {
        self.mode(bounds).interval(bounds)
    }
}

/// One free-text field of a flight file's `[design]` table (who designed the gains, with
/// which seed and objective), shown in the boot banner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DesignField {
    /// The key, e.g. `"seed"`.
    pub key: &'static str,
    /// The value as written in the file (strings unquoted).
    pub value: &'static str,
}

/// Where the flown set-up comes from, for the boot banner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlightIdentity {
    /// Vehicle name (`[vehicle] name` of the flight file).
    pub name: &'static str,
    /// Where the vehicle's values are published (`[vehicle] source`).
    pub source: &'static str,
    /// The flight file the firmware was built with (path as given to the build), or a
    /// description for configurations built in code.
    pub file: &'static str,
    /// The `[design]` fields other than `margin`, in file order.
    pub design: &'static [DesignField],
}

/// Everything [`crate::pipeline::FlightPipeline::new`] needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightConfig {
    /// Which vehicle and design this is (boot banner).
    pub identity: FlightIdentity,
    /// The demo mission flown on `MAV_CMD_MISSION_START` (the flight file's `[trajectory]`;
    /// the paper's helix for [`FlightConfig::paper`]). It is part of what is certified at boot.
    pub mission: ReferenceTrajectory<f32>,
    /// Smallest headroom the certified `(T, τ)` set must leave inside every rotor's thrust
    /// range, as a fraction of that range \[dimensionless\] (the flight file's
    /// `[design] margin`; see [`crate::mixer::Mixer::set_margin`]); with
    /// [`FlightConfig::airmode`] also the headroom airmode keeps free.
    pub box_margin: f32,
    /// Whether a set-up whose certificate fails or whose box does not fit may still arm (with a
    /// loud warning event). Only the `uncertified-paper` build of the paper's set-up sets it:
    /// everything else flies only what is certified.
    pub allow_uncertified: bool,
    /// Rigid-body parameters (mass \[kg\], inertia diagonal [kg m²], gravity [m/s²]).
    pub vehicle: Vehicle<f32>,
    /// Actuator limits the certificate assumes (`T_max` \[N\], `τ_max` [N m]).
    pub limits: Limits<f32>,
    /// Controller gains (Table I).
    pub gains: Gains<f32>,
    /// How the thrust is computed from `u` (the flight file's `[controller]`; `Norm` for
    /// [`FlightConfig::paper`]).
    pub thrust: ThrustChoice,
    /// Airmode (the flight file's `[controller] airmode`; off for [`FlightConfig::paper`];
    /// extension, docs/airmode.md): the thrust mode's thrust is moved, by as little as
    /// possible, to where the rotors realise the law's torque with
    /// [`FlightConfig::box_margin`] of each rotor's range kept free
    /// ([`controller_core::RotorEnvelope::airmode_thrust`]). The gate then asks the rotors to
    /// realise every certified torque at *some* thrust (the shadow fit) instead of at every
    /// thrust of the interval ([`crate::pipeline::gate_check`]).
    pub airmode: bool,
    /// With [`FlightConfig::airmode`], the headroom airmode keeps free above the rotors' least
    /// thrust, a fraction of the range in `[0, box_margin]` (the flight file's `[controller]
    /// airmode_low_margin`, else [`FlightConfig::box_margin`]). The gate's fits are checked with
    /// `box_margin` at both ends, so every range airmode flies holds the certified set; a smaller
    /// one lets the thrust fall towards the rotors' idle while the no-dive thrust cuts it
    /// (docs/airmode.md).
    pub airmode_low_margin: f32,
    /// Rotor geometry and model.
    pub rotors: RotorConfig,
    /// Safety timings.
    pub safety: SafetyConfig,
    /// Reference smoothing and missions.
    pub reference: ReferenceConfig,
    /// Landed detector thresholds.
    pub landed: LandedConfig,
    /// Telemetry rates.
    pub telemetry: TelemetryConfig,
    /// The control law's rate (100 Hz, the paper's, unless the flight file's
    /// `[design] control_rate_hz` says otherwise); its period is the law's nominal `dt`.
    pub control_rate: ControlRate,
    /// The control step `dt` measured between ticks is clamped to `[lo, hi] ·`
    /// [`FlightConfig::control_period`] \[dimensionless\], so a late, early or repeated tick (timer jitter, a
    /// stall) cannot feed the filters a zero or huge step.
    pub control_dt_ratio: [f32; 2],
    /// Known latency of the motion-capture pose \[µs\], subtracted from the arrival time.
    pub mocap_latency_us: u64,
    /// Stillness calibration length [samples of the IMU].
    pub gyro_calibration_samples: u32,
    /// Position measurement noise standard deviation \[m\] (velocity filter).
    pub mocap_position_sigma: f32,
    /// Acceleration noise spectral density of the velocity filter's model [(m/s²)²/Hz]: what
    /// the IMU's inertial acceleration gets wrong (noise, bias, vibration).
    pub velocity_filter_accel_psd: f32,
    /// Mahony proportional gain [1/s] and integral gain [1/s²] of the IMU-only attitude
    /// (`k_I = k_P²/4` makes the error dynamics critically damped).
    pub mahony_gains: [f32; 2],
    /// Longest step \[s\] the Mahony filter integrates between two IMU samples: after a gap
    /// (a stalled or restarted sensor) it does not integrate one stale rate over the whole gap.
    pub mahony_dt_max: f32,
    /// MAVLink system id of this vehicle.
    pub system_id: u8,
    /// MAVLink component id of this vehicle (1 = autopilot).
    pub component_id: u8,
    /// MAVLink 2 signing key (32 bytes), or `None`: signed frames are then dropped until a key
    /// is installed with `SETUP_SIGNING`, which only a trusted link may send unsigned
    /// ([`FlightConfig::link_trust`], [`crate::link::signing`]).
    pub signing_key: Option<[u8; 32]>,
    /// Whether the MAVLink link is a wired console only the owner can send on
    /// ([`LinkTrust::Trusted`]: `SETUP_SIGNING` taken unsigned, the way to install a first key
    /// or replace a lost one) or a link a stranger may reach, such as a radio
    /// ([`LinkTrust::Untrusted`], the default: `SETUP_SIGNING` only signed with the key in
    /// force). Either way only while disarmed.
    pub link_trust: LinkTrust,
    /// The order of the motor outputs in `HIL_ACTUATOR_CONTROLS` (processor in the loop):
    /// the vehicle file's, or PX4's or Betaflight's quad X order for simulators that assume it
    /// ([`crate::motor_order`]).
    pub hil_motor_order: crate::motor_order::MotorOrder,
    /// With a key: whether unsigned poses and `HIL_SENSOR` samples are used (commands,
    /// setpoints and `SETUP_SIGNING` must be signed whatever this says).
    pub accept_unsigned_sensors: bool,
}

impl FlightConfig {
    /// The law's nominal sampling period \[s\] ([`ControlRate::period_s`] of
    /// [`FlightConfig::control_rate`]; 0.01 s at the paper's 100 Hz).
    pub fn control_period(&self) -> f32 {
        self.control_rate.period_s()
    }

    /// The paper's vehicle and rotors ([`Airframe::paper`]: Section VI's rigid body on an X
    /// quad sized to the paper's limits, arm 0.25 m, 0 to 3 N per rotor, yaw torque 0.1 m per
    /// newton, about five times a real propeller's), its limits (`T_max = 7 N`,
    /// `τ_max = 0.5 N m`) and Table I gains.
    ///
    /// Its certificate fails (Theorem 2, yaw) and its `(T, τ)` box does not fit its rotors, so
    /// it arms only with [`FlightConfig::allow_uncertified`] set: it is kept for the paper's
    /// tests and the bench fixtures, not for flight ([`FlightConfig::built`] is what the boards
    /// fly).
    pub fn paper() -> Self {
        let airframe = Airframe::paper();
        Self {
            identity: FlightIdentity {
                name: "paper",
                source: "Martins, Cardeira, Oliveira, Section VI and Table I (FlightConfig::paper)",
                file: "built in code: FlightConfig::paper()",
                design: &[],
            },
            mission: ReferenceTrajectory::paper_helix(),
            box_margin: 0.05,
            allow_uncertified: false,
            thrust: ThrustChoice::Norm,
            airmode: false,
            airmode_low_margin: 0.05,
            vehicle: airframe.vehicle,
            limits: Limits::paper(),
            gains: Gains::paper(),
            rotors: airframe.rotors,
            safety: SafetyConfig {
                arm_pose_max_age_us: 50_000,
                failsafe_pose_age_us: 100_000,
                disarm_pose_age_us: 2_000_000,
                allow_inverted_arming: true,
                upright_min_cos: 0.5,
                failsafe_descent_speed: 0.7,
                failsafe_descent_gain: 2.0,
                failsafe_tilt_cos_min: 0.5,
                failsafe_thrust_ratio: [0.6, 1.2],
            },
            reference: ReferenceConfig {
                smoothing_rate: 2.0,
                takeoff_height: 1.0,
                takeoff_height_max: 100.0,
                takeoff_reached_distance: 0.1,
                land_undershoot: 0.3,
                mission_speed: 0.5,
                mission_acceleration: 0.1,
                mission_yaw_rate: 0.07,
                mission_acceptance_radius: 0.3,
            },
            landed: LandedConfig {
                height: 0.08,
                speed: 0.15,
                failsafe_settle_us: 300_000,
                failsafe_vertical_speed: 0.15,
                failsafe_thrust_ratio: 0.9,
                failsafe_specific_force_ratio: 0.95,
                confirm_us: 300_000,
            },
            telemetry: TelemetryConfig {
                heartbeat_period_us: 1_000_000,
                state_period_us: 50_000,
            },
            control_rate: ControlRate::Hz100,
            control_dt_ratio: [0.2, 5.0],
            mocap_latency_us: 10_000,
            gyro_calibration_samples: 1000,
            mocap_position_sigma: 1.0e-3,
            velocity_filter_accel_psd: 2.0,
            mahony_gains: [1.0, 0.25],
            mahony_dt_max: 0.01,
            system_id: 1,
            component_id: 1,
            signing_key: None,
            link_trust: LinkTrust::Untrusted,
            accept_unsigned_sensors: true,
            hil_motor_order: crate::motor_order::MotorOrder::Mixer,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper vehicle's rotors meet the paper's T_max = 7 N and τ_max = 0.5 N m, axis by axis
    /// (hand computation: 4·3 N; √2·L·(f_max − f_min); 2·c·(f_max − f_min)).
    #[test]
    fn paper_rotors_meet_the_paper_limits() {
        let c = FlightConfig::paper();
        let r = &c.rotors;
        assert!(4.0 * r.thrust_max >= c.limits.thrust_max);
        let roll = 2.0f32.sqrt() * r.arm_length * (r.thrust_max - r.thrust_min);
        assert!(roll >= c.limits.torque_max[0] && roll >= c.limits.torque_max[1]);
        let yaw = 2.0 * r.torque_per_thrust() * (r.thrust_max - r.thrust_min);
        assert!(yaw >= c.limits.torque_max[2], "{yaw}");
        for rotor in &r.rotors {
            let l = (rotor.position[0].powi(2) + rotor.position[1].powi(2)).sqrt();
            assert!((l - r.arm_length).abs() < 1e-6);
        }
    }

    /// The throttle curve is monotone, maps the thrust range onto [idle, 1], and inverts.
    #[test]
    fn throttle_curve_inverts_and_is_monotone() {
        let r = FlightConfig::paper().rotors;
        assert!((r.throttle_from_thrust(r.thrust_min) - r.throttle_idle).abs() < 1e-6);
        assert!((r.throttle_from_thrust(r.thrust_max) - 1.0).abs() < 1e-6);
        let mut last = 0.0;
        for i in 0..=300 {
            let f = i as f32 * 0.01;
            let u = r.throttle_from_thrust(f);
            assert!(u >= last);
            last = u;
            assert!((r.thrust_from_throttle(u) - f).abs() < 1e-4, "{f}");
        }
        assert_eq!(r.throttle_from_thrust(f32::NAN), r.throttle_idle);
        assert_eq!(r.throttle_from_thrust(f32::INFINITY), r.throttle_idle);
        assert_eq!(r.throttle_from_thrust(-5.0), r.throttle_idle);
        assert_eq!(r.throttle_from_thrust(50.0), 1.0);
    }
}
