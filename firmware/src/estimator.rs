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

/// Gyro increments kept for the latency correction: 128 samples = 128 ms at 1 kHz.
const HISTORY: usize = 128;

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

/// A ring of the last [`HISTORY`] time-stamped values \[µs\], oldest first, that visits the
/// values of a time window without scanning the whole ring when it can.
///
/// The IMU stamps its samples in increasing order, so the ring is normally sorted by time and
/// the values with `after < t ≤ until` are one contiguous run, found by two binary searches
/// (7 steps each instead of a 128-entry scan). The ring counts its descents (adjacent pairs
/// whose time goes backwards); while there is one, it falls back to scanning every entry. Both
/// paths visit the same values in the same order, so sums over them are bit-identical.
/// Plain arrays with a power-of-two index mask (not `heapless::Deque`, whose bounds and
/// wrap-around checks cost several times the push itself on the MCU).
#[derive(Clone, Debug)]
#[repr(C)]
struct TimedRing<T: Copy> {
    /// Time of the newest entry (meaningful when `len > 0`): the push's descent test and the
    /// windows' "ends at the newest" test read it without an indexed load.
    newest: u64,
    /// Physical index of the oldest entry.
    head: usize,
    len: usize,
    /// Adjacent pairs `(i, i + 1)` with `t[i + 1] < t[i]` currently in the ring.
    descents: u32,
    /// Entries ever pushed (wrapping): names an entry by its sequence number, which stays the
    /// same as older entries leave (see [`TimedRing::mark`]).
    pushes: usize,
    // The arrays last (`repr(C)`): the scalars above and the estimator's (see [`Estimator`])
    // stay within short load offsets of one another.
    time: [u64; HISTORY],
    value: [T; HISTORY],
}

/// Index mask of the ring (`HISTORY` is a power of two).
const MASK: usize = HISTORY - 1;
const _: () = assert!(HISTORY.is_power_of_two());

impl<T: Copy> TimedRing<T> {
    fn new(fill: T) -> Self {
        Self {
            time: [0; HISTORY],
            value: [fill; HISTORY],
            head: 0,
            len: 0,
            descents: 0,
            pushes: 0,
            newest: 0,
        }
    }

    /// Time of the `i`-th oldest entry (`i < len`).
    #[inline(always)]
    fn time_at(&self, i: usize) -> u64 {
        self.time[(self.head + i) & MASK]
    }

    /// Appends `(time_us, value)`, dropping the oldest entry when full; true if it dropped one.
    fn push(&mut self, time_us: u64, value: T) -> bool {
        let full = self.len == HISTORY;
        // The newest entry stays when the oldest is dropped (HISTORY ≥ 2).
        if self.len > 0 && time_us < self.newest {
            self.descents += 1;
        }
        let i = (self.head + self.len) & MASK;
        if full {
            // (With no descent in the ring, the dropped pair is none: skip the comparison.)
            if self.descents > 0 && self.time_at(1) < self.time_at(0) {
                self.descents -= 1;
            }
            self.head = (self.head + 1) & MASK;
        } else {
            self.len += 1;
        }
        self.time[i] = time_us;
        self.value[i] = value;
        self.newest = time_us;
        self.pushes = self.pushes.wrapping_add(1);
        full
    }

    /// [`TimedRing::count_until`] as a sequence number (the number of entries ever pushed
    /// before the first entry after `x`), for [`TimedRing::window`]'s hints; `hint` is
    /// returned at once when it is still the answer (two comparisons instead of a search).
    fn mark(&self, x: u64, hint: usize) -> usize {
        let first = self.pushes.wrapping_sub(self.len);
        first.wrapping_add(self.count_until_hinted(x, hint))
    }

    /// [`TimedRing::count_until`], trying the sequence number `hint` first: it is the answer
    /// when the entry before it is at or before `x` and the entry at it is after `x` (in a
    /// sorted ring, the definition of the prefix's end).
    fn count_until_hinted(&self, x: u64, hint: usize) -> usize {
        let i = hint.wrapping_sub(self.pushes.wrapping_sub(self.len));
        // (At the end, the entry before is the newest: its time without an indexed load.)
        if i == self.len && (i == 0 || self.newest <= x) {
            return i;
        }
        if i < self.len && (i == 0 || self.time_at(i - 1) <= x) && self.time_at(i) > x {
            return i;
        }
        self.count_until(x)
    }

    /// Number of entries at or before `x` (the ring must be sorted: they are a prefix).
    fn count_until(&self, x: u64) -> usize {
        // The windows asked for mostly end at the newest entry (`now`, or open-ended).
        if self.len == 0 || self.newest <= x {
            return self.len;
        }
        let (mut lo, mut hi) = (0, self.len - 1);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.time_at(mid) <= x {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// [`TimedRing::window`] with hints that are checked (the tests' name for it).
    #[cfg(test)]
    fn for_each_in(
        &self,
        from: usize,
        after: (u64, usize),
        until: (u64, usize),
        f: impl FnMut(&T),
    ) {
        self.window(from, after, until, [false; 2], f);
    }

    /// Calls `f` on every value with `after.0 < t ≤ until.0`, oldest first, among the entries
    /// from the `from`-th oldest on (`from = 0`: all). The second element of `after` and
    /// `until` is a hint, the [`TimedRing::mark`] of that time when it was last asked for (any
    /// value: a wrong hint only costs the search), unless `exact[0]` (`exact[1]`) says that the
    /// hint of `after` (`until`) is that time's mark on the ring as it is now: it is then used
    /// without the two comparisons that check it.
    #[inline(always)]
    fn window(
        &self,
        from: usize,
        after: (u64, usize),
        until: (u64, usize),
        exact: [bool; 2],
        mut f: impl FnMut(&T),
    ) {
        let ((after, after_hint), (until, until_hint)) = (after, until);
        let first = self.pushes.wrapping_sub(self.len);
        let count = |x: u64, hint: usize, exact: bool| {
            if exact {
                hint.wrapping_sub(first)
            } else {
                self.count_until_hinted(x, hint)
            }
        };
        // Sorted: exactly the run [lo, hi). Otherwise: every entry, filtered.
        let sorted = self.descents == 0;
        let (lo, hi) = if sorted {
            (
                count(after, after_hint, exact[0]),
                count(until, until_hint, exact[1]),
            )
        } else {
            (0, self.len)
        };
        let lo = lo.max(from);
        if sorted {
            // The run is at most two contiguous pieces of the arrays (before and after the
            // wrap): iterated as slices, with no index mask or test per entry.
            if lo < hi {
                let start = (self.head + lo) & MASK;
                let n = hi - lo;
                let first = n.min(HISTORY - start);
                self.value[start..start + first].iter().for_each(&mut f);
                self.value[..n - first].iter().for_each(&mut f);
            }
            return;
        }
        let mut i = lo;
        while i < hi {
            let j = (self.head + i) & MASK;
            if self.time[j] > after && self.time[j] <= until {
                f(&self.value[j]);
            }
            i += 1;
        }
    }
}

/// `q ⊗ (1, h)`: `q` times the unnormalised gyro increment `(1, h)`, `h = ½ ω dt` (the
/// first-order quaternion of a rotation by `ω dt`; `q̇ = ½ q ⊗ (0, ω)`), with the product's
/// terms in nalgebra's order and its four products by the scalar part 1 left out: the same
/// bits as `q * Quaternion::new(1.0, h.x, h.y, h.z)` (`x · 1 = x` exactly) in 12 multiplications
/// instead of 16.
#[inline(always)]
pub(crate) fn mul_increment(q: &Quaternion<f32>, h: &Vector3<f32>) -> Quaternion<f32> {
    let (w, i, j, k) = (q.w, q.i, q.j, q.k);
    Quaternion::new(
        w - i * h.x - j * h.y - k * h.z,
        w * h.x + i + j * h.z - k * h.y,
        w * h.y - i * h.z + j + k * h.x,
        w * h.z + i * h.y - j * h.x + k,
    )
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
        let end = self.history.pushes;
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
        let end = self.history.pushes;
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
mod tests {
    use super::*;

    fn cfg() -> EstimatorConfig {
        EstimatorConfig {
            latency_us: 10_000,
            calibration_samples: 100,
            position_sigma: 1e-3,
            accel_psd: 2.0,
            gravity: 9.81,
        }
    }

    /// The bias is the mean of the still samples; motion restarts the calibration.
    #[test]
    fn gyro_calibration() {
        let mut e = Estimator::new(cfg());
        let g = Vector3::new(0.0, 0.0, 9.81);
        let b = Vector3::new(0.01, -0.02, 0.005);
        for i in 0..50 {
            e.on_imu(&b, &g, i * 1000);
        }
        e.on_imu(&Vector3::new(1.0, 0.0, 0.0), &g, 50_000); // moved
        for i in 0..99 {
            e.on_imu(&b, &g, 51_000 + i * 1000);
        }
        assert!(e.calibrating());
        e.on_imu(&b, &g, 200_000);
        assert!(!e.calibrating());
        assert!((e.gyro_bias() - b).norm() < 1e-7);
        e.on_imu(&(b + Vector3::new(0.3, 0.0, 0.0)), &g, 201_000);
        assert!((e.angular_velocity() - Vector3::new(0.3, 0.0, 0.0)).norm() < 1e-6);
    }

    /// A ramp p = 2 t m measured at 200 Hz with the known latency: the velocity converges
    /// to 2 m/s and the extrapolated position to the true position at "now".
    #[test]
    fn velocity_from_positions_with_latency() {
        let mut e = Estimator::new(cfg());
        let q = Quaternion::identity();
        for k in 1..400u64 {
            let t_meas = k * 5_000;
            let p = Vector3::new(2.0 * t_meas as f32 * 1e-6, 0.0, 1.0);
            assert_eq!(e.on_pose(&p, &q, t_meas + 10_000), PoseCheck::Used);
        }
        let now = 399 * 5_000 + 10_000 + 3_000;
        let s = e.estimate(now).unwrap();
        assert!((s.velocity.x - 2.0).abs() < 1e-2, "{}", s.velocity);
        let truth = 2.0 * now as f32 * 1e-6;
        assert!(
            (s.position.x - truth).abs() < 1e-3,
            "{} vs {truth}",
            s.position.x
        );
    }

    /// The latency correction: a pose measured 10 ms ago while the body turned at 1 rad/s
    /// about z gives today's attitude (yaw advanced by ~10 mrad).
    #[test]
    fn attitude_latency_is_propagated() {
        let mut c = cfg();
        c.calibration_samples = 1;
        let mut e = Estimator::new(c);
        let g = Vector3::new(0.0, 0.0, 9.81);
        e.on_imu(&Vector3::zeros(), &g, 0); // calibrated with zero bias
        for k in 1..=30u64 {
            e.on_imu(&Vector3::new(0.0, 0.0, 1.0), &g, k * 1000);
        }
        // Measured at t = 20 ms (yaw 0.02 rad then, if yaw started at 0 at t = 0), arrives at 30.
        let q_meas = UnitQuaternion::from_euler_angles(0.0f32, 0.0, 0.02);
        e.on_pose(&Vector3::zeros(), q_meas.quaternion(), 30_000);
        let (_, _, yaw) = e.estimate(30_000).unwrap().attitude.euler_angles();
        assert!((yaw - 0.03).abs() < 2e-4, "{yaw}");
    }

    /// The samples taken before the first pose (no attitude, so no inertial acceleration) share
    /// the history with the later ones but stay out of the acceleration mean: over a window
    /// holding 10 such samples and 5 later ones at 2 m/s² up, the mean is 2 m/s² (it would be
    /// 2/3 if the early ones counted as zeros).
    #[test]
    fn samples_before_the_first_pose_stay_out_of_the_acceleration_mean() {
        let mut c = cfg();
        c.calibration_samples = 1;
        let mut e = Estimator::new(c);
        let still = Vector3::new(0.0, 0.0, 9.81);
        for k in 1..=30u64 {
            e.on_imu(&Vector3::zeros(), &still, k * 1000);
        }
        // Measured at 20 ms (latency 10 ms), level: the window (20, 35] ms starts here.
        let q = Quaternion::identity();
        assert_eq!(e.on_pose(&Vector3::zeros(), &q, 30_000), PoseCheck::Used);
        for k in 31..=35u64 {
            e.on_imu(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 11.81), k * 1000);
        }
        let s = e.estimate(35_000).unwrap();
        // v = 0 + ā dt over dt = 15 ms.
        assert!(
            (s.velocity.z - 2.0 * 0.015).abs() < 1e-6,
            "{}",
            s.velocity.z
        );
    }

    /// Non-finite poses and bad quaternions are refused and flagged.
    #[test]
    fn refuses_bad_poses() {
        let mut e = Estimator::new(cfg());
        let q = Quaternion::identity();
        assert_eq!(
            e.on_pose(&Vector3::new(f32::NAN, 0.0, 0.0), &q, 20_000),
            PoseCheck::NonFinite
        );
        assert!(e.last_pose_bad());
        assert_eq!(
            e.on_pose(&Vector3::zeros(), &(q * 2.0), 20_000),
            PoseCheck::BadQuaternion
        );
        assert_eq!(e.on_pose(&Vector3::zeros(), &q, 20_000), PoseCheck::Used);
        assert!(!e.last_pose_bad());
        assert_eq!(
            e.on_pose(&Vector3::zeros(), &q, 19_000),
            PoseCheck::OutOfOrder
        );
        assert!(e.estimate(20_000).is_some());
        assert!(!e.on_imu(&Vector3::new(f32::INFINITY, 0.0, 0.0), &Vector3::z(), 1));
    }

    /// `mul_increment` is nalgebra's product with `(1, h)`, bit for bit, over random values of
    /// both signs and many magnitudes.
    #[test]
    fn increment_product_is_nalgebras() {
        let mut x = 0x2545_f491u32;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            (x as f32 / u32::MAX as f32 - 0.5) * 10f32.powi((x % 7) as i32 - 3)
        };
        for _ in 0..10_000 {
            let q = Quaternion::new(rnd(), rnd(), rnd(), rnd());
            let h = Vector3::new(rnd(), rnd(), rnd());
            let want = q * Quaternion::new(1.0, h.x, h.y, h.z);
            let got = mul_increment(&q, &h);
            for (a, b) in got.coords.iter().zip(want.coords.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{q:?} {h:?}");
            }
        }
    }

    /// The ring's window visits exactly the entries a full scan would, in the same order, for
    /// sorted and unsorted (descending steps) time stamps, before and after wrapping; the
    /// descent count returns to zero once the out-of-order entries have left the ring.
    #[test]
    fn timed_ring_window_equals_full_scan() {
        let mut x = 0x9e37_79b9u32;
        let mut rnd = |n: u32| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x % n
        };
        let mut ring = TimedRing::new(0u32);
        let mut all: Vec<(u64, u32)> = Vec::new();
        let mut t = 1_000u64;
        for i in 0..2_000u32 {
            // Mostly increasing by 1 ms, sometimes repeated, a few steps backwards early on.
            t = match rnd(50) {
                0 if i < 300 => t.saturating_sub(u64::from(rnd(5_000))),
                1 => t,
                _ => t + 1_000,
            };
            ring.push(t, i);
            all.push((t, i));
            let kept = &all[all.len().saturating_sub(HISTORY)..];
            let descents = kept.windows(2).filter(|w| w[1].0 < w[0].0).count() as u32;
            assert_eq!(ring.descents, descents, "at {i}");
            for _ in 0..3 {
                let after = t.saturating_sub(u64::from(rnd(140_000)));
                let until = after + u64::from(rnd(150_000));
                let mut got = Vec::new();
                let from = rnd(8) as usize;
                // Hints: right, wrong or stale ones (the answer must not depend on them).
                let mut hint = |x: u64| match rnd(3) {
                    0 => ring.mark(x, 0),
                    1 => rnd(400) as usize,
                    _ => ring.pushes.wrapping_sub(rnd(20) as usize),
                };
                let (ha, hu) = (hint(after), hint(until));
                ring.for_each_in(from, (after, ha), (until, hu), |v| got.push(*v));
                let want: Vec<u32> = kept
                    .iter()
                    .skip(from)
                    .filter(|(tt, _)| *tt > after && *tt <= until)
                    .map(|(_, v)| *v)
                    .collect();
                assert_eq!(got, want, "at {i}: ({after}, {until}]");
                // With exact marks, taken unchecked: the same entries.
                let (ma, mu) = (ring.mark(after, 0), ring.mark(until, 0));
                let mut exact = Vec::new();
                ring.window(from, (after, ma), (until, mu), [true; 2], |v| {
                    exact.push(*v)
                });
                assert_eq!(exact, want, "exact marks, at {i}: ({after}, {until}]");
            }
        }
        assert_eq!(ring.descents, 0);
    }
}
