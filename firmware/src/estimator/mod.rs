//! State estimate for the controller: `x = (p, v, R, ω)` in NWU (inertial) and FLU (body).
//!
//! - `ω`: the gyro minus its bias, the bias from a stillness calibration at boot.
//! - `R`: the mocap attitude, corrected for the known latency by re-applying the gyro
//!   increments recorded since the pose was measured, then propagated by the gyro between poses.
//! - `p, v`: per axis, a Kalman filter on `(p, v)` driven by the inertial acceleration from the
//!   IMU (`R a − g e₃`, averaged over each interval), run at the measurement times (arrival
//!   time minus the known latency, so 100–300 Hz and irregular arrivals are handled by the
//!   measured intervals) and extrapolated to the control time with the same acceleration. The
//!   process noise covers accelerometer noise, bias and vibration.
//! - A vertical velocity dead-reckoned from the accelerometer between poses, for the failsafe.
//!
//! No allocation: the gyro and acceleration histories are fixed rings.

use controller_core::scalar::{finite_probe, fmin, norm, normalize_quaternion};
use nalgebra::{Matrix2, Quaternion, UnitQuaternion, Vector2, Vector3};

mod increment;
mod timed_ring;
pub(crate) use increment::mul_increment;
use timed_ring::TimedRing;

/// Stillness limits for the gyro calibration: `|ω| < 0.3 rad/s` and `| |a| − g | < 1 m/s²`.
const STILL_GYRO: f32 = 0.3;
const STILL_ACCEL: f32 = 1.0;

/// `us as f32` (round to nearest, like the cast) through the FPU's `u32` conversion when
/// `us < 2³²` (`vcvt.f32.u32`, one instruction, instead of the software `u64` conversion
/// `__aeabi_ul2f`, about 30 on the Cortex-M4F). The same bits: both are the correctly rounded
/// conversion of the same integer.
///
/// The wide case is a separate, never-inlined function: otherwise LLVM proves both branches
/// equal and folds them back into the software conversion.
#[inline(always)]
pub fn micros_f32(us: u64) -> f32 {
    match u32::try_from(us) {
        Ok(v) => v as f32,
        Err(_) => wide_micros_f32(us),
    }
}

#[cold]
#[inline(never)]
fn wide_micros_f32(us: u64) -> f32 {
    us as f32
}

/// What the estimator keeps of one IMU sample, under the sample's time stamp in one ring (one
/// time array and one push for both, instead of a ring each).
#[derive(Clone, Copy, Debug)]
struct ImuRecord {
    /// Gyro increment over the sample: the vector part `½ ω dt` of `(1, ½ ω dt)` (see
    /// [`mul_increment`]), for the latency correction.
    half: Vector3<f32>,
    /// Inertial acceleration `R a − g e₃` [m/s²], NWU; meaningful only once an attitude is
    /// known (see [`Estimator::accel_missing`]).
    accel: Vector3<f32>,
}

/// What the pose looked like when it arrived.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseCheck {
    /// Finite, unit-norm quaternion (within 10 %): used.
    Used,
    /// Some value NaN or infinite: refused and counted.
    NonFinite,
    /// The quaternion norm is far from 1: refused and counted.
    BadQuaternion,
    /// Measured before the last used pose: ignored.
    OutOfOrder,
}

/// One axis of the position/velocity Kalman filter.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Axis {
    x: Vector2<f32>,
    p: Matrix2<f32>,
}

impl Axis {
    fn predict(&mut self, dt: f32, q: f32, accel: f32) {
        let f = Matrix2::new(1.0, dt, 0.0, 1.0);
        let (dt2, dt3) = (dt * dt, dt * dt * dt);
        let qm = Matrix2::new(dt3 / 3.0, dt2 / 2.0, dt2 / 2.0, dt) * q;
        self.x = f * self.x + Vector2::new(0.5 * dt2, dt) * accel;
        self.p = f * self.p * f.transpose() + qm;
    }

    fn update(&mut self, z: f32, r: f32) {
        let s = self.p[(0, 0)] + r;
        let k = Vector2::new(self.p[(0, 0)], self.p[(1, 0)]) / s;
        let innovation = z - self.x[0];
        self.x += k * innovation;
        // Joseph-free form is fine here: k is exact for the scalar measurement.
        let ikh = Matrix2::new(1.0 - k[0], 0.0, -k[1], 1.0);
        self.p = ikh * self.p;
        self.p = (self.p + self.p.transpose()) * 0.5;
    }
}

/// Estimator settings (from [`crate::config::FlightConfig`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorConfig {
    /// Known pose latency \[µs\].
    pub latency_us: u64,
    /// Calibration length [IMU samples].
    pub calibration_samples: u32,
    /// Position noise σ \[m\].
    pub position_sigma: f32,
    /// Acceleration noise spectral density [(m/s²)²/Hz].
    pub accel_psd: f32,
    /// Gravity [m/s²].
    pub gravity: f32,
}

/// The estimated state, ready for the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Position \[m\], NWU.
    pub position: Vector3<f32>,
    /// Velocity [m/s], NWU.
    pub velocity: Vector3<f32>,
    /// Attitude, FLU body to NWU.
    pub attitude: UnitQuaternion<f32>,
    /// Angular velocity [rad/s], body FLU, bias-corrected.
    pub angular_velocity: Vector3<f32>,
}

/// The estimator.
#[derive(Clone, Debug)]
#[repr(C)]
pub struct Estimator {
    // `repr(C)`, the history last: every scalar the per-sample path and the pose fusion use is
    // then within the Cortex-M4's short load and store offsets of the estimator's base.
    // IMU.
    /// Time of the last accepted sample \[µs\]; `u64::MAX` before the first (no time is after
    /// it, so the first interval is 0, as after a time stamp that did not advance).
    last_imu_us: u64,
    imu_interval_s: f32,
    omega: Vector3<f32>,
    accel: Vector3<f32>,
    bias: Option<Vector3<f32>>,
    // Attitude.
    attitude: Option<UnitQuaternion<f32>>,
    vertical_velocity: f32,
    /// The oldest `accel_missing` records of `history` were taken before any attitude was
    /// known and have no inertial acceleration (the attitude, once known, stays known, so they
    /// are always the oldest).
    accel_missing: usize,
    cfg: EstimatorConfig,
    // Position and velocity.
    axes: [Axis; 3],
    filter_time_us: Option<u64>,
    /// [`TimedRing::mark`] of `filter_time_us` in `history` when it was set: the windows that
    /// start there then need no search.
    filter_mark: usize,
    /// `history.pushes` when the last pose was used: with it, [`Estimator::on_pose`] guesses the
    /// new measurement time's mark (as many samples on as were pushed since, exact for a steady
    /// IMU rate and latency) instead of searching.
    pose_pushes: usize,
    poses_used: u32,
    last_pose_rx_us: Option<u64>,
    last_pose_bad: bool,
    // Calibration.
    cal_sum: Vector3<f32>,
    cal_count: u32,
    history: TimedRing<ImuRecord>,
}

impl Estimator {
    /// A fresh estimator: calibrating, no pose.
    pub fn new(cfg: EstimatorConfig) -> Self {
        let axis = Axis {
            x: Vector2::zeros(),
            p: Matrix2::identity(),
        };
        Self {
            cfg,
            cal_sum: Vector3::zeros(),
            cal_count: 0,
            bias: None,
            last_imu_us: u64::MAX,
            imu_interval_s: 0.0,
            omega: Vector3::zeros(),
            accel: Vector3::zeros(),
            // Zero fill (never read: only the `len` newest entries are): a plain memory clear.
            history: TimedRing::new(ImuRecord {
                half: Vector3::zeros(),
                accel: Vector3::zeros(),
            }),
            accel_missing: 0,
            attitude: None,
            axes: [axis; 3],
            filter_time_us: None,
            filter_mark: 0,
            pose_pushes: 0,
            poses_used: 0,
            last_pose_rx_us: None,
            last_pose_bad: false,
            vertical_velocity: 0.0,
        }
    }

    /// True until the gyro bias is known.
    pub fn calibrating(&self) -> bool {
        self.bias.is_none()
    }

    /// The gyro bias [rad/s] (zero while calibrating).
    pub fn gyro_bias(&self) -> Vector3<f32> {
        self.bias.unwrap_or_else(Vector3::zeros)
    }

    /// Latest bias-corrected angular velocity [rad/s], FLU.
    pub fn angular_velocity(&self) -> Vector3<f32> {
        self.omega
    }

    /// Time \[s\] from the previous accepted IMU sample to the latest, unclamped (0 for the
    /// first sample and for a time stamp that did not advance); the attitude integration uses
    /// it clamped to 10 ms, the pipeline's Mahony filter to its own limit.
    pub fn imu_interval_s(&self) -> f32 {
        self.imu_interval_s
    }

    /// Latest specific force [m/s²], FLU.
    pub fn specific_force(&self) -> Vector3<f32> {
        self.accel
    }

    /// One IMU sample: gyro [rad/s] and accelerometer [m/s²] (FLU) at `time_us`.
    /// Returns false (and changes nothing) if a value is non-finite.
    pub fn on_imu(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, time_us: u64) -> bool {
        if !finite_probe(finite_probe(0.0, gyro), accel).is_finite() {
            return false;
        }
        self.imu_interval_s = if time_us > self.last_imu_us {
            micros_f32(time_us - self.last_imu_us) * 1e-6
        } else {
            0.0
        };
        let dt = fmin(self.imu_interval_s, 0.01);
        self.last_imu_us = time_us;
        self.accel = *accel;
        match self.bias {
            None => {
                let still =
                    norm(gyro) < STILL_GYRO && (norm(accel) - self.cfg.gravity).abs() < STILL_ACCEL;
                if still {
                    self.cal_sum += gyro;
                    self.cal_count += 1;
                    if self.cal_count >= self.cfg.calibration_samples.max(1) {
                        self.bias = Some(self.cal_sum / self.cal_count as f32);
                    }
                } else {
                    // Moved: start again.
                    self.cal_sum = Vector3::zeros();
                    self.cal_count = 0;
                }
                self.omega = *gyro;
            }
            Some(b) => self.omega = gyro - b,
        }
        // Gyro increment over the sample, recorded for the latency correction.
        let half = self.omega * (0.5 * dt);
        // (Through `as_mut`: the attitude is updated in place, without storing the tag again.)
        let accel = match self.attitude.as_mut() {
            Some(att) => {
                let q = *att;
                *att = normalize_quaternion(mul_increment(&q, &half));
                // Inertial acceleration R a − g e₃, for the velocity filter and dead reckoning.
                // (`− g` on z alone: the same bits as `− e₃ g` for the positive, finite gravity
                // the vehicle parameters require, whose `0 · g` is +0 and `x − (+0)` is `x`.)
                let a = q * self.accel;
                let a = Vector3::new(a.x, a.y, a.z - self.cfg.gravity);
                self.vertical_velocity += a.z * dt;
                Some(a)
            }
            None => None,
        };
        let dropped = self.history.push(
            time_us,
            ImuRecord {
                half,
                accel: accel.unwrap_or_else(Vector3::zeros),
            },
        );
        // (Nothing to count in the usual case, a known attitude and no record without
        // acceleration left: one test instead of the two updates' tests.)
        if self.accel_missing > 0 || accel.is_none() {
            if dropped && self.accel_missing > 0 {
                self.accel_missing -= 1;
            }
            if accel.is_none() {
                self.accel_missing += 1;
            }
        }
        true
    }

    /// Mean inertial acceleration [m/s²] of the samples in `(t0, t1]` (zero if none).
    /// `t0` and `t1` come with [`TimedRing::mark`] hints.
    /// `t1_exact`: `t1`'s hint is its exact mark (see [`TimedRing::window`]).
    #[inline(always)]
    fn mean_accel(&self, t0: (u64, usize), t1: (u64, usize), t1_exact: bool) -> Vector3<f32> {
        let mut sum = Vector3::zeros();
        let mut n = 0u32;
        let exact = [false, t1_exact];
        self.history.window(self.accel_missing, t0, t1, exact, |r| {
            sum += r.accel;
            n += 1;
        });
        if n == 0 {
            sum
        } else {
            sum / n as f32
        }
    }

    /// A pose received at `rx_us`: position \[m\] NWU and attitude FLU→NWU (unnormalised).
    pub fn on_pose(
        &mut self,
        position: &Vector3<f32>,
        attitude: &Quaternion<f32>,
        rx_us: u64,
    ) -> PoseCheck {
        // One probe (`Σ 0·x`, finite iff every value is) instead of seven tests.
        if !finite_probe(finite_probe(0.0, position), &attitude.coords).is_finite() {
            self.last_pose_bad = true;
            return PoseCheck::NonFinite;
        }
        let n = norm(&attitude.coords);
        if !(0.9..=1.1).contains(&n) {
            self.last_pose_bad = true;
            return PoseCheck::BadQuaternion;
        }
        let t_meas = rx_us.saturating_sub(self.cfg.latency_us);
        if let Some(t) = self.filter_time_us {
            if t_meas <= t {
                return PoseCheck::OutOfOrder;
            }
        }
        self.last_pose_bad = false;
        self.last_pose_rx_us = Some(rx_us);

        // Where the measurement time falls in the history, searched once: the end of the
        // velocity filter's window, the start of the attitude's carry-forward, and the start
        // of the next windows.
        // The hint: the last measurement time's mark moved on by the samples pushed since
        // (checked by two comparisons; a search when wrong).
        let end = self.history.pushes();
        let hint = self
            .filter_mark
            .wrapping_add(end.wrapping_sub(self.pose_pushes));
        let meas_mark = self.history.mark(t_meas, hint);

        // Attitude: the measured one, carried forward through the gyro increments recorded
        // after the measurement time.
        let mut q = attitude / n;
        self.history
            .window(0, (t_meas, meas_mark), (u64::MAX, end), [true; 2], |r| {
                q = mul_increment(&q, &r.half)
            });
        self.attitude = Some(normalize_quaternion(q));

        // Position and velocity at the measurement time.
        let r = self.cfg.position_sigma * self.cfg.position_sigma;
        match self.filter_time_us {
            None => {
                for (i, a) in self.axes.iter_mut().enumerate() {
                    a.x = Vector2::new(position[i], 0.0);
                    a.p = Matrix2::new(r, 0.0, 0.0, 1.0);
                }
            }
            Some(t) => {
                let dt = micros_f32(t_meas - t) * 1e-6;
                let accel = self.mean_accel((t, self.filter_mark), (t_meas, meas_mark), true);
                for (i, a) in self.axes.iter_mut().enumerate() {
                    a.predict(dt, self.cfg.accel_psd, accel[i]);
                    a.update(position[i], r);
                }
            }
        }
        self.filter_time_us = Some(t_meas);
        self.filter_mark = meas_mark;
        self.pose_pushes = end;
        self.poses_used = self.poses_used.saturating_add(1);
        self.vertical_velocity = self.axes[2].x[1];
        PoseCheck::Used
    }

    /// Arrival time of the last used pose \[µs\].
    pub fn last_pose_us(&self) -> Option<u64> {
        self.last_pose_rx_us
    }

    /// Age of the last used pose at `now_us` \[µs\] (`None` before the first pose).
    pub fn pose_age_us(&self, now_us: u64) -> Option<u64> {
        self.last_pose_rx_us.map(|t| now_us.saturating_sub(t))
    }

    /// True when the latest pose message was refused (non-finite or bad quaternion).
    pub fn last_pose_bad(&self) -> bool {
        self.last_pose_bad
    }

    /// Calibrated, ≥ 10 poses used, velocity standard deviation below 0.2 m/s on every axis.
    pub fn converged(&self) -> bool {
        self.bias.is_some() && self.poses_used >= 10 && self.axes.iter().all(|a| a.p[(1, 1)] < 0.04)
    }

    /// Number of poses used.
    pub fn poses_used(&self) -> u32 {
        self.poses_used
    }

    /// Dead-reckoned vertical velocity [m/s] (z up), reset to the filter's at every pose.
    pub fn vertical_velocity(&self) -> f32 {
        self.vertical_velocity
    }

    /// The state at `now_us`, extrapolating from the last measurement time with the velocity
    /// and the mean inertial acceleration since. `None` before the first pose.
    #[inline(always)]
    pub fn estimate(&self, now_us: u64) -> Option<Estimate> {
        let attitude = self.attitude?;
        let t = self.filter_time_us?;
        // Extrapolate over at most 0.2 s: beyond, the failsafe has taken over anyway.
        let dt = fmin(micros_f32(now_us.saturating_sub(t)) * 1e-6, 0.2);
        let end = self.history.pushes();
        let a = self.mean_accel((t, self.filter_mark), (now_us, end), false);
        let position = Vector3::from_fn(|i, _| {
            self.axes[i].x[0] + self.axes[i].x[1] * dt + 0.5 * a[i] * dt * dt
        });
        let velocity = Vector3::from_fn(|i, _| self.axes[i].x[1] + a[i] * dt);
        Some(Estimate {
            position,
            velocity,
            attitude,
            angular_velocity: self.omega,
        })
    }
}

#[cfg(test)]
mod tests;
