//! Reference trajectories `r(t)` and the constants of Assumption 1 they satisfy.
//!
//! A reference gives the desired position `p_d` [m, inertial, z up] with its derivatives up to
//! the fourth, and the desired heading `ν_d ∈ S¹` (horizontal unit vector, inertial) with two
//! derivatives. Its [`TrajectoryConstants`] are the bounds `K_a12, K_a3, K_j, K_s, K_ν̇, K_ν̈` of
//! Assumption 1, computed in closed form from the trajectory's parameters (exact maxima where the
//! maximum has a closed form, otherwise a documented upper bound, which is what the assumption
//! needs).

use nalgebra::{Vector2, Vector3};

use crate::parameter_error::ParameterError;
use crate::scalar::{lit, to_f64, Scalar};

/// One sample of the reference at time `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceSample<T: Scalar> {
    /// Desired position `p_d` \[m\], inertial frame (z up).
    pub position: Vector3<T>,
    /// `ṗ_d` [m/s], inertial.
    pub velocity: Vector3<T>,
    /// `p̈_d` [m/s²], inertial.
    pub acceleration: Vector3<T>,
    /// `p_d⁽³⁾` (jerk) [m/s³], inertial.
    pub jerk: Vector3<T>,
    /// `p_d⁽⁴⁾` (snap) [m/s⁴], inertial.
    pub snap: Vector3<T>,
    /// Desired heading `ν_d` (unit 2-vector in the inertial horizontal plane; `(cos ψ, sin ψ)`).
    pub heading: Vector2<T>,
    /// `ν̇_d` [1/s].
    pub heading_rate: Vector2<T>,
    /// `ν̈_d` [1/s²].
    pub heading_acceleration: Vector2<T>,
}

impl<T: Scalar> ReferenceSample<T> {
    /// A constant reference: hold `position` \[m\] with yaw `yaw` \[rad\]; all derivatives zero.
    pub fn hold(position: Vector3<T>, yaw: T) -> Self {
        Self {
            position,
            velocity: Vector3::zeros(),
            acceleration: Vector3::zeros(),
            jerk: Vector3::zeros(),
            snap: Vector3::zeros(),
            heading: Vector2::new(yaw.cos(), yaw.sin()),
            heading_rate: Vector2::zeros(),
            heading_acceleration: Vector2::zeros(),
        }
    }

    /// Desired yaw `ψ_d = atan2(ν₂, ν₁)` \[rad\].
    pub fn yaw(&self) -> T {
        self.heading.y.atan2(self.heading.x)
    }

    /// True when every field is finite.
    pub fn is_finite(&self) -> bool {
        use crate::scalar::finite_probe;
        let mut p = T::zero();
        for v in [
            &self.position,
            &self.velocity,
            &self.acceleration,
            &self.jerk,
            &self.snap,
        ] {
            p = finite_probe(p, v);
        }
        for v in [
            &self.heading,
            &self.heading_rate,
            &self.heading_acceleration,
        ] {
            p = finite_probe(p, v);
        }
        p.is_finite()
    }
}

/// The constants of Assumption 1 that bound a reference for all `t ≥ 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrajectoryConstants<T: Scalar> {
    /// `K_a12` [m/s²]: bound on the horizontal acceleration `|(p̈_d1, p̈_d2)|`.
    pub horizontal_acceleration: T,
    /// `K_a3` [m/s²]: bound on the vertical acceleration `|p̈_d3|`.
    pub vertical_acceleration: T,
    /// `K_j` [m/s³]: bound on `|p_d⁽³⁾|`.
    pub jerk: T,
    /// `K_s` [m/s⁴]: bound on `|p_d⁽⁴⁾|`.
    pub snap: T,
    /// `K_ν̇` [1/s]: bound on `|ν̇_d|`.
    pub heading_rate: T,
    /// `K_ν̈` [1/s²]: bound on `|ν̈_d|`.
    pub heading_acceleration: T,
}

impl<T: Scalar> TrajectoryConstants<T> {
    /// `Ok` when every constant is finite and non-negative.
    ///
    /// Errors: [`ParameterError::BadTrajectoryConstant`] naming the first that is not
    /// (`K_a12`, `K_a3`, `K_j`, `K_s`, `K_nu_dot`, `K_nu_ddot`, in that order).
    pub fn validate(&self) -> Result<(), ParameterError> {
        for (name, v) in [
            ("K_a12", self.horizontal_acceleration),
            ("K_a3", self.vertical_acceleration),
            ("K_j", self.jerk),
            ("K_s", self.snap),
            ("K_nu_dot", self.heading_rate),
            ("K_nu_ddot", self.heading_acceleration),
        ] {
            if !(v.is_finite() && v >= T::zero()) {
                return Err(ParameterError::BadTrajectoryConstant {
                    name,
                    value: to_f64(v),
                });
            }
        }
        Ok(())
    }

    /// All constants zero: a hover reference.
    pub fn zero() -> Self {
        Self {
            horizontal_acceleration: T::zero(),
            vertical_acceleration: T::zero(),
            jerk: T::zero(),
            snap: T::zero(),
            heading_rate: T::zero(),
            heading_acceleration: T::zero(),
        }
    }

    /// The constants of the same reference flown `factor` times slower (`t ↦ r(t/factor)`):
    /// the k-th time derivative is divided by `factorᵏ`, so `K_a12, K_a3` by `factor²`, `K_j` by
    /// `factor³`, `K_s` by `factor⁴`, `K_ν̇` by `factor` and `K_ν̈` (a bound on `|ν̈| ≤
    /// |ψ̈| + ψ̇²`, both terms of order two) by `factor²`. Exact for any `factor > 0`.
    pub fn time_scaled(&self, factor: T) -> Self {
        let f2 = factor * factor;
        Self {
            horizontal_acceleration: self.horizontal_acceleration / f2,
            vertical_acceleration: self.vertical_acceleration / f2,
            jerk: self.jerk / (f2 * factor),
            snap: self.snap / (f2 * f2),
            heading_rate: self.heading_rate / factor,
            heading_acceleration: self.heading_acceleration / f2,
        }
    }

    /// True if `sample` lies inside these bounds (with relative slack `tol` for rounding).
    /// Source: Assumption 1 (the compact set `Ω_r` and the inclusion `F_r`).
    pub fn contain(&self, sample: &ReferenceSample<T>, tol: T) -> bool {
        let ok = |v: T, k: T| v <= k * (T::one() + tol) + tol;
        let a = &sample.acceleration;
        ok(Vector2::new(a.x, a.y).norm(), self.horizontal_acceleration)
            && ok(a.z.abs(), self.vertical_acceleration)
            && ok(sample.jerk.norm(), self.jerk)
            && ok(sample.snap.norm(), self.snap)
            && ok(sample.heading_rate.norm(), self.heading_rate)
            && ok(
                sample.heading_acceleration.norm(),
                self.heading_acceleration,
            )
    }
}

/// A reference trajectory: samples at time `t` and the constants of Assumption 1.
pub trait Trajectory<T: Scalar> {
    /// The reference at time `t` \[s\].
    fn sample(&self, t: T) -> ReferenceSample<T>;
    /// Bounds of Assumption 1 valid for all `t ≥ 0`.
    fn constants(&self) -> TrajectoryConstants<T>;
}

/// How the desired yaw `ψ_d(t)` evolves; the heading is `ν_d = (cos ψ_d, sin ψ_d)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HeadingProfile<T: Scalar> {
    /// Constant yaw \[rad\].
    Constant {
        /// `ψ_d` \[rad\].
        yaw: T,
    },
    /// `ψ_d = offset + amplitude · sin(frequency · t)`; the paper uses `π sin(f t)`.
    Sinusoidal {
        /// Amplitude \[rad\].
        amplitude: T,
        /// Angular frequency [rad/s] inside the sine.
        frequency: T,
        /// Offset \[rad\].
        offset: T,
    },
}

impl<T: Scalar> HeadingProfile<T> {
    /// `(ψ, ψ̇, ψ̈)` at `t`, in rad, rad/s, rad/s².
    ///
    /// `known`: `sin_cos(w t)` already computed for some angular frequency `w` at this `t`
    /// (the helix's); reused when `w` equals the heading's frequency (equal non-zero floats
    /// have equal bits, so the result is the same as computing it again).
    fn yaw(&self, t: T, known: Option<(T, (T, T))>) -> (T, T, T) {
        match *self {
            Self::Constant { yaw } => (yaw, T::zero(), T::zero()),
            Self::Sinusoidal {
                amplitude,
                frequency,
                offset,
            } => {
                let (s, c) = match known {
                    Some((w, sc)) if w == frequency && w != T::zero() => sc,
                    _ => (frequency * t).sin_cos_bounded(),
                };
                (
                    offset + amplitude * s,
                    amplitude * frequency * c,
                    -amplitude * frequency * frequency * s,
                )
            }
        }
    }

    /// `(ν_d, ν̇_d, ν̈_d)` at `t`: `ν̇ = ψ̇ ν⊥`, `ν̈ = ψ̈ ν⊥ − ψ̇² ν` with `ν⊥ = (−sin ψ, cos ψ)`.
    fn heading(&self, t: T, known: Option<(T, (T, T))>) -> (Vector2<T>, Vector2<T>, Vector2<T>) {
        let (psi, rate, acc) = self.yaw(t, known);
        let (s, c) = psi.sin_cos_bounded();
        let nu = Vector2::new(c, s);
        let perp = Vector2::new(-s, c);
        (nu, perp * rate, perp * acc - nu * (rate * rate))
    }

    /// `(K_ν̇, K_ν̈)`: for the sinusoid, `max|ψ̇| = A f` and
    /// `max sqrt(ψ̈² + ψ̇⁴) = f² max(A, A²)` (the expression is convex in `cos²(f t)`, so its
    /// maximum sits at `cos² ∈ {0, 1}`): exact maxima.
    fn constants(&self) -> (T, T) {
        match *self {
            Self::Constant { .. } => (T::zero(), T::zero()),
            Self::Sinusoidal {
                amplitude,
                frequency,
                ..
            } => {
                let a = amplitude.abs();
                let f = frequency.abs();
                (a * f, f * f * a.max(a * a))
            }
        }
    }
}

/// The reference trajectories shipped with the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceTrajectory<T: Scalar> {
    /// Hold a point with a heading profile (usually constant).
    Hover {
        /// Point \[m\], inertial.
        point: Vector3<T>,
        /// Heading profile.
        heading: HeadingProfile<T>,
    },
    /// `p_d = center + (r cos f t, r sin f t, h cos f t)`: Section VI uses `r = h = 1 m`,
    /// `f = 2π/15 rad/s`, `center = (−3, 1, 4.5) m`, `ψ_d = π sin(f t)`.
    Helix {
        /// Center `p̄` \[m\], inertial.
        center: Vector3<T>,
        /// Horizontal radius `r` \[m\].
        radius: T,
        /// Vertical amplitude `h` \[m\].
        vertical_amplitude: T,
        /// Angular frequency `f` [rad/s].
        frequency: T,
        /// Heading profile.
        heading: HeadingProfile<T>,
    },
    /// Lemniscate of Gerono in a horizontal plane:
    /// `p_d = center + (a sin f t, (b/2) sin 2f t, 0)`.
    FigureEight {
        /// Center \[m\], inertial.
        center: Vector3<T>,
        /// Half-width along x, `a` \[m\].
        x_amplitude: T,
        /// Half-width along y, `b` \[m\] (the y excursion is `b/2`).
        y_amplitude: T,
        /// Angular frequency `f` [rad/s].
        frequency: T,
        /// Heading profile.
        heading: HeadingProfile<T>,
    },
}

/// `d^n/dt^n [A sin(w t)]` and `d^n/dt^n [A cos(w t)]` for `n = 0..=4`.
fn sin_cos_derivatives<T: Scalar>(amplitude: T, w: T, t: T) -> ([T; 5], [T; 5]) {
    derivatives_of_sin_cos(amplitude, w, (w * t).sin_cos_bounded())
}

/// [`sin_cos_derivatives`] from `(s, c) = sin_cos(w t)` already computed (one `sin_cos` for the
/// three axes of the helix: the same bits as three).
fn derivatives_of_sin_cos<T: Scalar>(amplitude: T, w: T, (s, c): (T, T)) -> ([T; 5], [T; 5]) {
    let mut sin_d = [T::zero(); 5];
    let mut cos_d = [T::zero(); 5];
    // Each derivative multiplies by w and rotates (sin → cos → −sin → −cos).
    let mut scale = amplitude;
    let phases = [(s, c), (c, -s), (-s, -c), (-c, s), (s, c)];
    for (n, (ps, pc)) in phases.iter().enumerate() {
        sin_d[n] = scale * *ps;
        cos_d[n] = scale * *pc;
        scale *= w;
    }
    (sin_d, cos_d)
}

impl<T: Scalar> ReferenceTrajectory<T> {
    /// The paper's Section VI trajectory (helix about `(−3, 1, 4.5) m`, `f = 2π/15 rad/s`,
    /// `ψ_d = π sin(f t)`). The paper writes `f = 2π(15)⁻¹ Hz`; it is used as an angular
    /// frequency inside `cos(f t)`, so a period of 15 s.
    pub fn paper_helix() -> Self {
        let f = lit::<T>(2.0 * core::f64::consts::PI / 15.0);
        Self::Helix {
            center: Vector3::new(lit(-3.0), lit(1.0), lit(4.5)),
            radius: T::one(),
            vertical_amplitude: T::one(),
            frequency: f,
            heading: HeadingProfile::Sinusoidal {
                amplitude: T::pi(),
                frequency: f,
                offset: T::zero(),
            },
        }
    }

    fn heading_profile(&self) -> &HeadingProfile<T> {
        match self {
            Self::Hover { heading, .. }
            | Self::Helix { heading, .. }
            | Self::FigureEight { heading, .. } => heading,
        }
    }
}

impl<T: Scalar> Trajectory<T> for ReferenceTrajectory<T> {
    fn sample(&self, t: T) -> ReferenceSample<T> {
        let mut d = [Vector3::<T>::zeros(); 5];
        let mut known = None;
        match *self {
            Self::Hover { point, .. } => d[0] = point,
            Self::Helix {
                center,
                radius,
                vertical_amplitude,
                frequency,
                ..
            } => {
                // One sin_cos(f t) for the three axes and, when its frequency is the same, the
                // heading (the paper's helix): 2 sin_cos per sample instead of 5.
                let sc = (frequency * t).sin_cos_bounded();
                known = Some((frequency, sc));
                let (_, xr) = derivatives_of_sin_cos(radius, frequency, sc);
                let (yr, _) = derivatives_of_sin_cos(radius, frequency, sc);
                let (_, zr) = derivatives_of_sin_cos(vertical_amplitude, frequency, sc);
                for n in 0..5 {
                    d[n] = Vector3::new(xr[n], yr[n], zr[n]);
                }
                d[0] += center;
            }
            Self::FigureEight {
                center,
                x_amplitude,
                y_amplitude,
                frequency,
                ..
            } => {
                let (xs, _) = sin_cos_derivatives(x_amplitude, frequency, t);
                let (ys, _) = sin_cos_derivatives(y_amplitude * lit(0.5), frequency * lit(2.0), t);
                for n in 0..5 {
                    d[n] = Vector3::new(xs[n], ys[n], T::zero());
                }
                d[0] += center;
            }
        }
        let (heading, heading_rate, heading_acceleration) =
            self.heading_profile().heading(t, known);
        ReferenceSample {
            position: d[0],
            velocity: d[1],
            acceleration: d[2],
            jerk: d[3],
            snap: d[4],
            heading,
            heading_rate,
            heading_acceleration,
        }
    }

    /// Helix: exact maxima `K_a12 = r f²`, `K_a3 = h f²`, `K_j = f³ sqrt(r² + h²)`,
    /// `K_s = f⁴ sqrt(r² + h²)`. Figure-eight: `K_a3 = 0` and, for the others, the upper bound
    /// `fⁿ sqrt(a² + (b 2ⁿ⁻¹)²)` from the component amplitudes (not the exact maximum).
    fn constants(&self) -> TrajectoryConstants<T> {
        let (heading_rate, heading_acceleration) = self.heading_profile().constants();
        let mut k = TrajectoryConstants {
            heading_rate,
            heading_acceleration,
            ..TrajectoryConstants::zero()
        };
        match *self {
            Self::Hover { .. } => {}
            Self::Helix {
                radius,
                vertical_amplitude,
                frequency,
                ..
            } => {
                let (r, h, f) = (radius.abs(), vertical_amplitude.abs(), frequency.abs());
                let f2 = f * f;
                let rh = (r * r + h * h).sqrt();
                k.horizontal_acceleration = r * f2;
                k.vertical_acceleration = h * f2;
                k.jerk = f2 * f * rh;
                k.snap = f2 * f2 * rh;
            }
            Self::FigureEight {
                x_amplitude,
                y_amplitude,
                frequency,
                ..
            } => {
                let (a, b, f) = (x_amplitude.abs(), y_amplitude.abs(), frequency.abs());
                let bound = |n: i32| {
                    let fy = b * lit::<T>(2.0).powi(n - 1);
                    f.powi(n) * (a * a + fy * fy).sqrt()
                };
                k.horizontal_acceleration = bound(2);
                k.jerk = bound(3);
                k.snap = bound(4);
            }
        }
        k
    }
}

#[cfg(test)]
mod tests;
