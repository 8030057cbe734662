//! A reference through a list of stops (waypoints with a hold time), for missions: each leg is a
//! rest-to-rest move ([`profile`]) from one stop to the next, timed so that its peak speed,
//! acceleration and yaw rate stay within [`PathLimits`], followed by a hold at the stop. The
//! reference is four times continuously differentiable (every derivative up to the snap is zero
//! at each stop), and its Assumption 1 constants are exact closed forms of the legs
//! ([`WaypointPath::constants`]), so a mission can be certified before it is flown.
//!
//! A slower timing of the same path (every move `c ≥ 1` times longer) divides the k-th
//! derivative by `cᵏ` ([`TrajectoryConstants::time_scaled`]): the factor that makes a refused
//! path certifiable is found by bisection on the constants alone ([`slowdown_to_certify`]).
//! Pausing the reference at a stop (a longer hold) changes no constant, since the reference is
//! at rest there: the firmware may wait at a stop for the vehicle without a new certificate.
//!
//! Fixed capacity `N` legs, no allocation.

pub mod profile;
#[cfg(test)]
mod tests;

use core::fmt;

use nalgebra::{Vector2, Vector3};

use crate::reference::{ReferenceSample, Trajectory, TrajectoryConstants};
use crate::scalar::{lit, Scalar};

/// One stop of a path: where to go, the yaw to turn to on the way, how long to stay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stop<T: Scalar> {
    /// Position \[m\], inertial frame (z up).
    pub position: Vector3<T>,
    /// Yaw at the stop \[rad\], inertial; the leg turns the short way round.
    pub yaw: T,
    /// Time the reference stays at the stop after arriving \[s\], `≥ 0`.
    pub hold: T,
}

/// How fast a leg may be: its duration is the shortest that keeps the peak speed, acceleration
/// and yaw rate of the rest-to-rest profile within these, and at least `min_duration`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathLimits<T: Scalar> {
    /// Peak speed along a leg \[m/s\], `> 0`.
    pub speed: T,
    /// Peak acceleration along a leg \[m/s²\], `> 0`.
    pub acceleration: T,
    /// Peak yaw rate \[rad/s\], `> 0`.
    pub yaw_rate: T,
    /// Shortest leg that moves at all \[s\], `≥ 0`.
    pub min_duration: T,
}

/// Why a path was not built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathError {
    /// More stops than the capacity.
    TooManyStops {
        /// The capacity (legs).
        capacity: usize,
    },
    /// Stop `index`'s position, yaw or hold is not finite, or its hold is negative.
    BadStop {
        /// Index in the list of stops.
        index: usize,
    },
    /// A limit is not finite and positive (`min_duration`: not finite and non-negative).
    BadLimit {
        /// `"speed"`, `"acceleration"`, `"yaw_rate"` or `"min_duration"`.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

impl fmt::Display for PathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooManyStops { capacity } => write!(f, "more than {capacity} stops"),
            Self::BadStop { index } => {
                write!(
                    f,
                    "stop {index}: position, yaw or hold not finite, or hold < 0"
                )
            }
            Self::BadLimit { name, value } => write!(f, "path limit {name} = {value} is invalid"),
        }
    }
}

/// One leg: the move from `from` by `delta` (and yaw by `yaw_delta`) over `duration`, starting
/// at path time `start`, then the hold.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Leg<T: Scalar> {
    from: Vector3<T>,
    delta: Vector3<T>,
    yaw_from: T,
    yaw_delta: T,
    start: T,
    duration: T,
    hold: T,
}

impl<T: Scalar> Leg<T> {
    const fn rest(position: Vector3<T>, yaw: T, zero: T) -> Self {
        Self {
            from: position,
            delta: position,
            yaw_from: yaw,
            yaw_delta: zero,
            start: zero,
            duration: zero,
            hold: zero,
        }
    }
}

/// `a` wrapped into `(−π, π]`.
fn wrap_pi<T: Scalar>(a: T) -> T {
    let pi = T::pi();
    let two_pi = pi + pi;
    let mut x = (a + pi) % two_pi;
    if x < T::zero() {
        x += two_pi;
    }
    x - pi
}

/// A reference through up to `N` stops from a start at rest; after the last hold it stays at
/// the last stop. Times are path times \[s\] from the start (`t = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaypointPath<T: Scalar, const N: usize> {
    start: Vector3<T>,
    start_yaw: T,
    legs: [Leg<T>; N],
    len: usize,
}

impl<T: Scalar, const N: usize> WaypointPath<T, N> {
    /// The path from `start` (position \[m\], yaw \[rad\], inertial, at rest) through `stops`
    /// in order, each leg as fast as `limits` allow.
    ///
    /// Errors: [`PathError::TooManyStops`] beyond `N`, [`PathError::BadLimit`] for the first
    /// invalid limit, [`PathError::BadStop`] for the first stop with a non-finite field or a
    /// negative hold. A non-finite start gives `BadStop { index: 0 }`.
    pub fn new(
        start: Vector3<T>,
        start_yaw: T,
        stops: &[Stop<T>],
        limits: &PathLimits<T>,
    ) -> Result<Self, PathError> {
        if stops.len() > N {
            return Err(PathError::TooManyStops { capacity: N });
        }
        for (name, v) in [
            ("speed", limits.speed),
            ("acceleration", limits.acceleration),
            ("yaw_rate", limits.yaw_rate),
        ] {
            if !(v.is_finite() && v > T::zero()) {
                return Err(PathError::BadLimit {
                    name,
                    value: crate::scalar::to_f64(v),
                });
            }
        }
        if !(limits.min_duration.is_finite() && limits.min_duration >= T::zero()) {
            return Err(PathError::BadLimit {
                name: "min_duration",
                value: crate::scalar::to_f64(limits.min_duration),
            });
        }
        let finite3 = |v: &Vector3<T>| v.iter().all(|x| x.is_finite());
        if !(finite3(&start) && start_yaw.is_finite()) {
            return Err(PathError::BadStop { index: 0 });
        }
        let peak = |k: usize| -> T { lit(profile::PEAK[k]) };
        let mut legs = [Leg::rest(start, start_yaw, T::zero()); N];
        let (mut at, mut yaw, mut t) = (start, start_yaw, T::zero());
        for (index, (stop, leg)) in stops.iter().zip(legs.iter_mut()).enumerate() {
            if !(finite3(&stop.position)
                && stop.yaw.is_finite()
                && stop.hold.is_finite()
                && stop.hold >= T::zero())
            {
                return Err(PathError::BadStop { index });
            }
            let delta = stop.position - at;
            let yaw_delta = wrap_pi(stop.yaw - yaw);
            let distance = delta.norm();
            let turn = yaw_delta.abs();
            // Peak speed Φ₁|Δ|/T ≤ v, peak acceleration Φ₂|Δ|/T² ≤ a, peak yaw rate Φ₁|Δψ|/T ≤ r.
            let duration = if distance == T::zero() && turn == T::zero() {
                T::zero()
            } else {
                (peak(0) * distance / limits.speed)
                    .max((peak(1) * distance / limits.acceleration).sqrt())
                    .max(peak(0) * turn / limits.yaw_rate)
                    .max(limits.min_duration)
            };
            *leg = Leg {
                from: at,
                delta,
                yaw_from: yaw,
                yaw_delta,
                start: t,
                duration,
                hold: stop.hold,
            };
            t += duration + stop.hold;
            at = stop.position;
            yaw += yaw_delta;
        }
        Ok(Self {
            start,
            start_yaw,
            legs,
            len: stops.len(),
        })
    }

    /// The same path with every move `factor` times longer (holds unchanged): its constants are
    /// [`TrajectoryConstants::time_scaled`] of these. `factor` must be finite and `≥ 1`
    /// (otherwise the path is returned unchanged).
    pub fn slowed(&self, factor: T) -> Self {
        if !(factor.is_finite() && factor >= T::one()) {
            return *self;
        }
        let mut out = *self;
        let mut t = T::zero();
        for leg in out.legs[..self.len].iter_mut() {
            leg.start = t;
            leg.duration *= factor;
            t += leg.duration + leg.hold;
        }
        out
    }

    /// Number of stops (legs).
    pub fn len(&self) -> usize {
        self.len
    }

    /// True without stops (the path holds its start).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Path time \[s\] at which the reference arrives at stop `i` (`None` past the end).
    pub fn arrival(&self, i: usize) -> Option<T> {
        self.legs[..self.len].get(i).map(|l| l.start + l.duration)
    }

    /// Path time \[s\] at which the reference leaves stop `i` (arrival plus hold; `None` past
    /// the end).
    pub fn departure(&self, i: usize) -> Option<T> {
        self.legs[..self.len]
            .get(i)
            .map(|l| l.start + l.duration + l.hold)
    }

    /// Stop `i`'s position \[m\] and yaw \[rad\] as flown (yaw unwrapped along the path).
    pub fn stop(&self, i: usize) -> Option<(Vector3<T>, T)> {
        self.legs[..self.len]
            .get(i)
            .map(|l| (l.from + l.delta, l.yaw_from + l.yaw_delta))
    }

    /// Path time \[s\] when the last hold ends (0 without stops).
    pub fn duration(&self) -> T {
        self.departure(self.len.wrapping_sub(1))
            .unwrap_or(T::zero())
    }

    /// The leg flown at path time `t`: the last one that has started (`None` before the first
    /// leg starts or without legs).
    fn leg_at(&self, t: T) -> Option<&Leg<T>> {
        let legs = &self.legs[..self.len];
        // Legs start in increasing time: the number of legs started is a partition point.
        let started = legs.partition_point(|l| l.start <= t);
        started.checked_sub(1).map(|i| &legs[i])
    }
}

impl<T: Scalar, const N: usize> Trajectory<T> for WaypointPath<T, N> {
    /// The reference at path time `t` \[s\]: at rest at the start before `t = 0`, at rest at the
    /// last stop after the path.
    fn sample(&self, t: T) -> ReferenceSample<T> {
        let Some(leg) = self.leg_at(t) else {
            return ReferenceSample::hold(self.start, self.start_yaw);
        };
        let phi = if leg.duration > T::zero() {
            profile::eval((t - leg.start) / leg.duration)
        } else {
            [T::one(), T::zero(), T::zero(), T::zero(), T::zero()]
        };
        // d/dt of φ(t/T) brings 1/T per derivative.
        let inv = if leg.duration > T::zero() {
            T::one() / leg.duration
        } else {
            T::zero()
        };
        let scale = [
            T::one(),
            inv,
            inv * inv,
            inv * inv * inv,
            inv * inv * inv * inv,
        ];
        let d = |k: usize| phi[k] * scale[k];
        let psi = leg.yaw_from + leg.yaw_delta * phi[0];
        let psi_dot = leg.yaw_delta * d(1);
        let psi_ddot = leg.yaw_delta * d(2);
        let (s, c) = psi.sin_cos();
        let nu = Vector2::new(c, s);
        let perp = Vector2::new(-s, c);
        ReferenceSample {
            position: leg.from + leg.delta * phi[0],
            velocity: leg.delta * d(1),
            acceleration: leg.delta * d(2),
            jerk: leg.delta * d(3),
            snap: leg.delta * d(4),
            heading: nu,
            heading_rate: perp * psi_dot,
            heading_acceleration: perp * psi_ddot - nu * (psi_dot * psi_dot),
        }
    }

    /// The largest over the legs of `|Δ_xy| Φ₂/T²`, `|Δ_z| Φ₂/T²`, `|Δ| Φ₃/T³`, `|Δ| Φ₄/T⁴`,
    /// `|Δψ| Φ₁/T` and `|Δψ| Φ₂/T² + (|Δψ| Φ₁/T)²` (Φₖ = [`profile::PEAK`]; `|ν̈| =
    /// √(ψ̈² + ψ̇⁴) ≤ |ψ̈| + ψ̇²`). Exact suprema for the position terms.
    fn constants(&self) -> TrajectoryConstants<T> {
        let peak = |k: usize| -> T { lit(profile::PEAK[k]) };
        let mut k = TrajectoryConstants::<T>::zero();
        for leg in self.legs[..self.len]
            .iter()
            .filter(|l| l.duration > T::zero())
        {
            let inv = T::one() / leg.duration;
            let inv2 = inv * inv;
            let distance = leg.delta.norm();
            let turn = leg.yaw_delta.abs();
            let rate = turn * peak(0) * inv;
            k.horizontal_acceleration = k
                .horizontal_acceleration
                .max(leg.delta.xy().norm() * peak(1) * inv2);
            k.vertical_acceleration = k
                .vertical_acceleration
                .max(leg.delta.z.abs() * peak(1) * inv2);
            k.jerk = k.jerk.max(distance * peak(2) * inv2 * inv);
            k.snap = k.snap.max(distance * peak(3) * inv2 * inv2);
            k.heading_rate = k.heading_rate.max(rate);
            k.heading_acceleration = k
                .heading_acceleration
                .max(turn * peak(1) * inv2 + rate * rate);
        }
        k
    }
}

/// The smallest slow-down factor `c ∈ [1, max_factor]` (to within 1 %) for which `certifies`
/// accepts `base.time_scaled(c)`, by bisection on the constants alone (each evaluation one call
/// of `certifies`, about 12 calls); `Some(1)` when `base` itself certifies, `None` when not even
/// `max_factor` does. Assumes that slower is never harder to certify, which holds for the
/// certificate's conditions: each is monotone in the constants, all of which shrink with `c`.
pub fn slowdown_to_certify<T: Scalar>(
    base: &TrajectoryConstants<T>,
    max_factor: T,
    mut certifies: impl FnMut(&TrajectoryConstants<T>) -> bool,
) -> Option<T> {
    if certifies(base) {
        return Some(T::one());
    }
    if !(max_factor.is_finite()
        && max_factor > T::one()
        && certifies(&base.time_scaled(max_factor)))
    {
        return None;
    }
    let (mut lo, mut hi) = (T::one(), max_factor);
    let tolerance: T = lit(1.01);
    while hi > lo * tolerance {
        let mid = (lo * hi).sqrt();
        if certifies(&base.time_scaled(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}
