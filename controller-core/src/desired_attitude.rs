//! The desired attitude `R_d(ρ, υ)` and its angular velocity and acceleration (Sections III, V).
//!
//! `ρ = u/|u|` is the thrust direction and `υ = ϖ/|ϖ|` the desired body x-axis, with
//! `ϖ = sgn(ρ₃) (ρ₃ ν_d, −ρᵀν*)`, `ν* = (ν_d, 0)` (eq:DesiredRotationMatrix, after Basso et al.
//! 2022). `R_d = [υ, ρ × υ, ρ]`, and `ω_d`, `ω̇_d` follow eq:DesiredAngularVelocity and
//! eq:DesiredAngularAcceleration from the first two derivatives of `ρ` and `υ` (Lemma 1).

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::scalar::{lit, norm, Scalar};

/// A unit vector with its first two time derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitWithDerivatives<T: Scalar> {
    /// The unit vector `x/|x|` (inertial).
    pub unit: Vector3<T>,
    /// Its first derivative [1/s].
    pub rate: Vector3<T>,
    /// Its second derivative [1/s²].
    pub acceleration: Vector3<T>,
}

/// Normalises `x` and differentiates the result twice:
/// `ẏ = (I − yyᵀ) ẋ / |x|`, `ÿ = (I − yyᵀ) ẍ / |x| − 2 (yᵀẋ)/|x| ẏ − |ẏ|² y`.
///
/// Returns `None` if `|x|` is zero or not finite. Units: whatever `x` has, divided out.
/// Source: Lemma 1 proof (expressions of `ρ̇, ρ̈` and `υ̇, ϋ`).
pub fn normalize_with_derivatives<T: Scalar>(
    x: &Vector3<T>,
    x_dot: &Vector3<T>,
    x_ddot: &Vector3<T>,
) -> Option<UnitWithDerivatives<T>> {
    let n = norm(x);
    if !n.is_finite() || n <= T::zero() {
        return None;
    }
    let y = x / n;
    let project = |v: &Vector3<T>| v - y * y.dot(v);
    let rate = project(x_dot) / n;
    let radial_rate = y.dot(x_dot) / n;
    let acceleration =
        project(x_ddot) / n - rate * (lit::<T>(2.0) * radial_rate) - y * rate.norm_squared();
    Some(UnitWithDerivatives {
        unit: y,
        rate,
        acceleration,
    })
}

/// The desired attitude and its derivatives at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesiredAttitude<T: Scalar> {
    /// Thrust direction `ρ` with `ρ̇`, `ρ̈` (inertial).
    pub thrust_direction: UnitWithDerivatives<T>,
    /// Desired body x-axis `υ` with `υ̇`, `ϋ` (inertial).
    pub heading_axis: UnitWithDerivatives<T>,
    /// `R_d = [υ, ρ × υ, ρ]` (desired body to inertial).
    pub rotation: Matrix3<T>,
    /// `ω_d` [rad/s], desired body frame (eq:DesiredAngularVelocity).
    pub angular_velocity: Vector3<T>,
    /// `ω̇_d` [rad/s²], desired body frame (eq:DesiredAngularAcceleration).
    pub angular_acceleration: Vector3<T>,
}

/// Why a desired attitude could not be formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DesiredAttitudeError {
    /// `u = 0`: the thrust direction is undefined.
    ZeroThrust,
    /// `e₃ᵀρ ≤ 0`: the paper's `R_d` needs an upward thrust component (guaranteed when the
    /// reference satisfies `|p̈_d3| ≤ K_a3 < g − M_p`).
    ThrustNotUpward,
    /// `ϖ = 0`: the heading `ν_d` is zero.
    DegenerateHeading,
}

/// Computes `R_d`, `ω_d`, `ω̇_d` from the control vector `u` [m/s²] with `u̇`, `ü` (inertial)
/// and the heading `ν_d` with `ν̇_d`, `ν̈_d` (inertial horizontal plane).
///
/// Errors: [`DesiredAttitudeError`] when `u = 0`, `e₃ᵀu ≤ 0` or `ν_d = 0`.
/// Source: eq:DesiredRotationMatrix, eq:DesiredAngularVelocity, eq:DesiredAngularAcceleration,
/// Lemma 1.
pub fn desired_attitude<T: Scalar>(
    u: &Vector3<T>,
    u_dot: &Vector3<T>,
    u_ddot: &Vector3<T>,
    heading: &Vector2<T>,
    heading_rate: &Vector2<T>,
    heading_acceleration: &Vector2<T>,
) -> Result<DesiredAttitude<T>, DesiredAttitudeError> {
    let rho =
        normalize_with_derivatives(u, u_dot, u_ddot).ok_or(DesiredAttitudeError::ZeroThrust)?;
    let (r, rd, rdd) = (rho.unit, rho.rate, rho.acceleration);
    // r is finite here (n finite and > 0), so this also holds for every non-upward thrust.
    if r.z <= T::zero() {
        return Err(DesiredAttitudeError::ThrustNotUpward);
    }
    // ϖ with sgn(ρ₃) = +1; its derivatives by the product rule.
    let lift = |v: &Vector2<T>| Vector3::new(v.x, v.y, T::zero());
    let (nu, nu_d, nu_dd) = (
        lift(heading),
        lift(heading_rate),
        lift(heading_acceleration),
    );
    let two = lit::<T>(2.0);
    let varpi_of = |a: Vector3<T>, b: T| Vector3::new(a.x, a.y, -b);
    let varpi = varpi_of(nu * r.z, r.dot(&nu));
    let varpi_dot = varpi_of(nu * rd.z + nu_d * r.z, rd.dot(&nu) + r.dot(&nu_d));
    let varpi_ddot = varpi_of(
        nu * rdd.z + nu_d * (two * rd.z) + nu_dd * r.z,
        rdd.dot(&nu) + two * rd.dot(&nu_d) + r.dot(&nu_dd),
    );
    let ups = normalize_with_derivatives(&varpi, &varpi_dot, &varpi_ddot)
        .ok_or(DesiredAttitudeError::DegenerateHeading)?;
    let (y, yd, ydd) = (ups.unit, ups.rate, ups.acceleration);

    let second = r.cross(&y);
    let rotation = Matrix3::from_columns(&[y, second, r]);
    // υᵀ[ρ]ₓa = υ·(ρ×a) = a·(υ×ρ) = −a·(ρ×υ): one cross product serves all three terms.
    let w = Vector3::new(-rd.dot(&second), y.dot(&rd), yd.dot(&second));
    let gyro = Vector3::new(w.y * w.z, -w.x * w.z, -w.x * w.y);
    let angular_acceleration =
        gyro + Vector3::new(-rdd.dot(&second), y.dot(&rdd), ydd.dot(&second));
    Ok(DesiredAttitude {
        thrust_direction: rho,
        heading_axis: ups,
        rotation,
        angular_velocity: w,
        angular_acceleration,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    /// `(u, u̇, ü, ν_d, ν̇_d, ν̈_d)` at one time.
    type Signals = (
        Vector3<f64>,
        Vector3<f64>,
        Vector3<f64>,
        Vector2<f64>,
        Vector2<f64>,
        Vector2<f64>,
    );

    /// A smooth test signal: u(t) = a + b sin(ct) + d t², ν_d(t) = (cos ψ, sin ψ).
    fn signals(t: f64, p: &[f64; 8]) -> Signals {
        let a = Vector3::new(p[0], p[1], 9.0 + p[2]);
        let b = Vector3::new(p[3], p[4], p[5]);
        let (s, c) = (1.3 * t).sin_cos();
        let u = a + b * s + Vector3::new(0.2, -0.1, 0.05) * t * t;
        let ud = b * (1.3 * c) + Vector3::new(0.4, -0.2, 0.1) * t;
        let udd = -b * (1.69 * s) + Vector3::new(0.4, -0.2, 0.1);
        let psi = p[6] + p[7] * (0.9 * t).sin();
        let psid = p[7] * 0.9 * (0.9 * t).cos();
        let psidd = -p[7] * 0.81 * (0.9 * t).sin();
        let nu = Vector2::new(psi.cos(), psi.sin());
        let perp = Vector2::new(-psi.sin(), psi.cos());
        (
            u,
            ud,
            udd,
            nu,
            perp * psid,
            perp * psidd - nu * (psid * psid),
        )
    }

    fn at(t: f64, p: &[f64; 8]) -> DesiredAttitude<f64> {
        let (u, ud, udd, n, nd, ndd) = signals(t, p);
        desired_attitude(&u, &ud, &udd, &n, &nd, &ndd).unwrap()
    }

    proptest! {
        /// ω_d and ω̇_d agree with central differences of R_d: [ω_d]ₓ = R_dᵀṘ_d.
        #[test]
        fn angular_velocity_and_acceleration_match_differences(
            p0 in -3.0..3.0f64, p1 in -3.0..3.0f64, p2 in -2.0..2.0f64, p3 in -2.0..2.0f64,
            p4 in -2.0..2.0f64, p5 in -2.0..2.0f64, p6 in -3.0..3.0f64, p7 in -2.0..2.0f64,
            t in 0.0..10.0f64) {
            let p = [p0, p1, p2, p3, p4, p5, p6, p7];
            let h = 1e-5;
            let (a, b, c) = (at(t - h, &p), at(t, &p), at(t + h, &p));
            let rdot = (c.rotation - a.rotation) / (2.0 * h);
            let skew = b.rotation.transpose() * rdot;
            let w = Vector3::new(skew[(2, 1)], skew[(0, 2)], skew[(1, 0)]);
            assert_relative_eq!(b.angular_velocity, w, epsilon = 1e-6 * (1.0 + w.norm()));
            let wdot = (c.angular_velocity - a.angular_velocity) / (2.0 * h);
            assert_relative_eq!(b.angular_acceleration, wdot, epsilon = 1e-5 * (1.0 + wdot.norm()));
            // R_d on SO(3) and its heading aligned with ν_d in the horizontal plane.
            assert_relative_eq!(b.rotation.transpose() * b.rotation, Matrix3::identity(), epsilon = 1e-12);
            assert_relative_eq!(b.rotation.determinant(), 1.0, epsilon = 1e-12);
            let (_, _, _, nu, _, _) = signals(t, &p);
            let x = b.rotation.column(0);
            let horizontal = Vector2::new(x[0], x[1]).normalize();
            assert_relative_eq!(horizontal, nu, epsilon = 1e-9);
        }
    }

    #[test]
    fn refuses_degenerate_inputs() {
        let z = Vector3::zeros();
        let n = Vector2::new(1.0, 0.0);
        let n0 = Vector2::zeros();
        assert_eq!(
            desired_attitude(&z, &z, &z, &n, &n0, &n0),
            Err(DesiredAttitudeError::ZeroThrust)
        );
        let down = Vector3::new(0.0, 0.0, -1.0);
        assert_eq!(
            desired_attitude(&down, &z, &z, &n, &n0, &n0),
            Err(DesiredAttitudeError::ThrustNotUpward)
        );
        let up = Vector3::new(0.0, 0.0, 9.81);
        assert_eq!(
            desired_attitude(&up, &z, &z, &n0, &n0, &n0),
            Err(DesiredAttitudeError::DegenerateHeading)
        );
    }
}
