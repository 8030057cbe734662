//! The landed detector: whether the vehicle is on the ground, at the end of a landing (armed,
//! with the pose) or in the IMU-only failsafe (without it), confirmed over several control
//! ticks. A pure type ([`LandedDetector`]); the safety supervisor disarms on its answer.

use controller_core::Vehicle;
use nalgebra::Vector3;

use crate::config::LandedConfig;
use crate::control_rate::ControlRate;

/// What the detector looks at in one control tick, by situation. Frames: inertial NWU (z up)
/// for positions and velocities, body FLU for the specific force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LandedInputs {
    /// Armed and landing, with the estimate.
    Landing {
        /// Estimated height \[m\] (NWU z).
        position_z: f32,
        /// Estimated velocity [m/s], NWU.
        velocity: Vector3<f32>,
        /// Ground height latched at arming \[m\] (NWU z).
        ground_z: f32,
    },
    /// In the failsafe, from the IMU and the failsafe law.
    Failsafe {
        /// Time since the failsafe started \[µs\].
        time_in_failsafe_us: u64,
        /// Dead-reckoned vertical velocity [m/s] (z up).
        vertical_velocity: f32,
        /// Collective thrust the failsafe law asked for last \[N\].
        thrust: f32,
        /// Specific force [m/s²], body FLU.
        specific_force: Vector3<f32>,
    },
    /// Neither (flying another mode, disarmed, or landing without an estimate): never on the
    /// ground.
    Other,
}

/// Consecutive-tick landed detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LandedDetector {
    cfg: LandedConfig,
    mass: f32,
    gravity: f32,
    /// [`LandedConfig::confirm_us`] in ticks of the law's rate.
    confirm_ticks: u32,
    ticks: u32,
}

impl LandedDetector {
    /// Not landed, thresholds `cfg`, the vehicle's mass \[kg\] and gravity [m/s²] for its
    /// weight, ticking at `rate` (the confirmation time in ticks).
    pub fn new(cfg: LandedConfig, vehicle: &Vehicle<f32>, rate: ControlRate) -> Self {
        Self {
            cfg,
            mass: vehicle.mass,
            gravity: vehicle.gravity,
            confirm_ticks: rate.ticks_in(cfg.confirm_us),
            ticks: 0,
        }
    }

    /// Consecutive ticks [`LandedDetector::update`] needs: [`LandedConfig::confirm_us`] at the
    /// law's rate, rounded up.
    pub fn confirm_ticks(&self) -> u32 {
        self.confirm_ticks
    }

    /// Forgets the ticks counted so far (at arming and at the start of a landing).
    pub fn reset(&mut self) {
        self.ticks = 0;
    }

    /// Whether this tick's inputs look like the ground (no confirmation): landing, below
    /// [`LandedConfig::height`] above the ground and slower than [`LandedConfig::speed`]; in
    /// the failsafe, after [`LandedConfig::failsafe_settle_us`], with a small vertical speed,
    /// a thrust below the weight's fraction and the ground carrying the weight (specific
    /// force near `g`).
    #[inline]
    pub fn on_ground(&self, input: &LandedInputs) -> bool {
        let c = &self.cfg;
        match *input {
            LandedInputs::Landing {
                position_z,
                velocity,
                ground_z,
            } => position_z < ground_z + c.height && velocity.norm() < c.speed,
            LandedInputs::Failsafe {
                time_in_failsafe_us,
                vertical_velocity,
                thrust,
                specific_force,
            } => {
                let g = self.gravity;
                time_in_failsafe_us > c.failsafe_settle_us
                    && vertical_velocity.abs() < c.failsafe_vertical_speed
                    && thrust < c.failsafe_thrust_ratio * self.mass * g
                    && specific_force.norm() > c.failsafe_specific_force_ratio * g
            }
            LandedInputs::Other => false,
        }
    }

    /// One control tick: true once [`LandedDetector::on_ground`] has held for
    /// [`LandedDetector::confirm_ticks`] consecutive ticks (this one included); any tick off the
    /// ground starts the count again.
    #[inline]
    pub fn update(&mut self, input: &LandedInputs) -> bool {
        self.ticks = if self.on_ground(input) {
            self.ticks + 1
        } else {
            0
        };
        self.ticks >= self.confirm_ticks
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::FlightConfig;

    fn detector() -> LandedDetector {
        let c = FlightConfig::paper();
        LandedDetector::new(c.landed, &c.vehicle, c.control_rate)
    }

    /// The confirmation is a time: the same 0.3 s at every rate, in whole ticks.
    #[test]
    fn confirmation_is_the_same_time_at_every_rate() {
        let c = FlightConfig::paper();
        for rate in ControlRate::ALL {
            let d = LandedDetector::new(c.landed, &c.vehicle, rate);
            let n = u64::from(d.confirm_ticks());
            assert!(n * rate.period_us() >= c.landed.confirm_us, "{rate:?}");
            assert!((n - 1) * rate.period_us() < c.landed.confirm_us, "{rate:?}");
        }
        assert_eq!(detector().confirm_ticks(), 30);
    }

    fn cfg() -> LandedConfig {
        FlightConfig::paper().landed
    }

    /// Landing at ground 1 m: just above it, still.
    fn touchdown() -> LandedInputs {
        LandedInputs::Landing {
            position_z: 1.0 + 0.5 * cfg().height,
            velocity: Vector3::new(0.0, 0.0, -0.5 * cfg().speed),
            ground_z: 1.0,
        }
    }

    /// Failsafe inputs: time in failsafe, vertical speed, thrust as a fraction of the weight,
    /// specific force along body z as a fraction of `g`.
    fn failsafe(time_us: u64, vz: f32, thrust_ratio: f32, force_ratio: f32) -> LandedInputs {
        let v = FlightConfig::paper().vehicle;
        LandedInputs::Failsafe {
            time_in_failsafe_us: time_us,
            vertical_velocity: vz,
            thrust: thrust_ratio * v.mass * v.gravity,
            specific_force: Vector3::new(0.0, 0.0, force_ratio * v.gravity),
        }
    }

    /// Failsafe on the ground: settled, still, thrust below the weight, the ground carrying it.
    fn failsafe_on_ground() -> LandedInputs {
        failsafe(cfg().failsafe_settle_us + 1, 0.0, 0.8, 1.0)
    }

    /// Runs `n` ticks of `input`, returns the last answer.
    fn run(d: &mut LandedDetector, input: &LandedInputs, n: u32) -> bool {
        (0..n).fold(false, |_, _| d.update(input))
    }

    #[test]
    fn given_touchdown_when_held_then_landed_exactly_at_the_confirm_tick() {
        let n = detector().confirm_ticks();
        let mut d = detector();
        assert!(!run(&mut d, &touchdown(), n - 1), "landed before tick {n}");
        assert!(d.update(&touchdown()), "not landed at tick {n}");
        assert!(d.update(&touchdown()), "landed stays landed");
    }

    #[test]
    fn given_touchdown_counting_when_one_tick_bounces_then_count_restarts() {
        let n = detector().confirm_ticks();
        let mut d = detector();
        run(&mut d, &touchdown(), n - 1);
        let bounce = LandedInputs::Landing {
            position_z: 1.0 + 2.0 * cfg().height,
            velocity: Vector3::zeros(),
            ground_z: 1.0,
        };
        assert!(!d.update(&bounce));
        assert!(!run(&mut d, &touchdown(), n - 1));
        assert!(d.update(&touchdown()));
    }

    #[test]
    fn given_touchdown_counting_when_reset_then_count_restarts() {
        let n = detector().confirm_ticks();
        let mut d = detector();
        run(&mut d, &touchdown(), n - 1);
        d.reset();
        assert!(!run(&mut d, &touchdown(), n - 1));
        assert!(d.update(&touchdown()));
    }

    #[test]
    fn given_landing_when_at_height_or_speed_threshold_then_not_on_ground() {
        let c = cfg();
        let d = detector();
        let at = |dz: f32, v: f32| LandedInputs::Landing {
            position_z: 1.0 + dz,
            velocity: Vector3::new(v, 0.0, 0.0),
            ground_z: 1.0,
        };
        // Both comparisons are strict; the height counts from the arming ground.
        assert!(!d.on_ground(&at(c.height, 0.0)));
        assert!(!d.on_ground(&at(0.0, c.speed)));
        assert!(d.on_ground(&at(0.99 * c.height, 0.99 * c.speed)));
        assert!(d.on_ground(&at(-1.0, 0.0)), "below the ground");
    }

    #[test]
    fn given_failsafe_when_not_yet_settled_then_not_on_ground() {
        let settle = cfg().failsafe_settle_us;
        let d = detector();
        assert!(
            !d.on_ground(&failsafe(settle, 0.0, 0.8, 1.0)),
            "at the settle time"
        );
        assert!(d.on_ground(&failsafe(settle + 1, 0.0, 0.8, 1.0)));
    }

    #[test]
    fn given_failsafe_when_any_ground_sign_is_missing_then_not_on_ground() {
        let c = cfg();
        let t = c.failsafe_settle_us + 1;
        let d = detector();
        assert!(d.on_ground(&failsafe_on_ground()));
        // Still moving vertically (either sign), at the threshold.
        let vz = c.failsafe_vertical_speed;
        assert!(!d.on_ground(&failsafe(t, -vz, 0.8, 1.0)));
        assert!(!d.on_ground(&failsafe(t, vz, 0.8, 1.0)));
        assert!(d.on_ground(&failsafe(t, 0.99 * vz, 0.8, 1.0)));
        // Thrust at the weight fraction or above: the law is not pushing against the ground.
        assert!(!d.on_ground(&failsafe(t, 0.0, c.failsafe_thrust_ratio, 1.0)));
        assert!(!d.on_ground(&failsafe(t, 0.0, 1.0, 1.0)));
        // Free fall, or the threshold itself: the ground does not carry the weight.
        assert!(!d.on_ground(&failsafe(t, 0.0, 0.8, 0.0)));
        let f = c.failsafe_specific_force_ratio;
        assert!(!d.on_ground(&failsafe(t, 0.0, 0.8, f)));
    }

    #[test]
    fn given_failsafe_on_ground_when_held_then_landed_at_the_confirm_tick() {
        let n = detector().confirm_ticks();
        let mut d = detector();
        assert!(!run(&mut d, &failsafe_on_ground(), n - 1));
        assert!(d.update(&failsafe_on_ground()));
    }

    #[test]
    fn given_other_situations_when_ticked_then_never_landed_and_count_cleared() {
        let n = detector().confirm_ticks();
        let mut d = detector();
        run(&mut d, &touchdown(), n - 1);
        assert!(!d.update(&LandedInputs::Other));
        assert!(!run(&mut d, &LandedInputs::Other, 10 * n));
        assert!(!run(&mut d, &touchdown(), n - 1));
    }
}
