//! The one place where MAVLink's frames meet the controller's: NED/FRD ↔ NWU/FLU.
//!
//! MAVLink local frames are NED (x north, y east, z down) with FRD bodies (x forward, y right,
//! z down). The controller (and the paper) use a z-up inertial frame and a z-up body. Here the
//! z-up inertial frame is **NWU** (x north, y west, z up) and the body is **FLU** (x forward,
//! y left, z up): both are the MAVLink frame turned by 180° about its x axis, `D = diag(1, −1, −1)`.
//!
//! Hence, with `D = D⁻¹ = Dᵀ`:
//! - vectors (positions, velocities, body rates): `v_zup = D v_mav`;
//! - rotations (body to inertial): `R_nwu_flu = D R_ned_frd D`, which for Hamilton quaternions
//!   `q = (w, x, y, z)` is `(w, x, −y, −z)`;
//! - yaw (heading from north): `ψ_nwu = −ψ_ned`.
//!
//! Every function is its own inverse.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// A vector (position \[m\], velocity [m/s], angular velocity [rad/s], …) from NED/FRD to
/// NWU/FLU or back: `(x, y, z) ↦ (x, −y, −z)`.
pub fn flip_vector(v: [f32; 3]) -> Vector3<f32> {
    Vector3::new(v[0], -v[1], -v[2])
}

/// Back to a MAVLink array: the same map as [`flip_vector`].
pub fn flip_to_array(v: &Vector3<f32>) -> [f32; 3] {
    [v.x, -v.y, -v.z]
}

/// A body-to-inertial quaternion given as MAVLink's `[w, x, y, z]` (FRD body to NED) to the
/// controller's FLU body to NWU, unnormalised: `(w, x, −y, −z)`. The inverse map is the same.
pub fn flip_quaternion(q: [f32; 4]) -> Quaternion<f32> {
    Quaternion::new(q[0], q[1], -q[2], -q[3])
}

/// The controller's FLU→NWU attitude as MAVLink's FRD→NED `[w, x, y, z]`.
pub fn quaternion_to_mavlink(q: &UnitQuaternion<f32>) -> [f32; 4] {
    [q.w, q.i, -q.j, -q.k]
}

/// Yaw \[rad\] from NED (clockwise from north seen from above) to NWU (counter-clockwise from
/// north), or back: `ψ ↦ −ψ`.
pub fn flip_yaw(yaw: f32) -> f32 {
    -yaw
}

/// MAVLink's roll, pitch, yaw \[rad\] (Z-Y-X Tait-Bryan, FRD body to NED, as in
/// `VISION_POSITION_ESTIMATE`) as MAVLink's `[w, x, y, z]`, the Hamilton quaternion
/// `q_yaw(z) ⊗ q_pitch(y) ⊗ q_roll(x)`, which [`flip_quaternion`] then takes to FLU→NWU.
/// Non-finite angles give non-finite components (the estimator refuses them).
pub fn euler_to_quaternion(roll: f32, pitch: f32, yaw: f32) -> [f32; 4] {
    let (sr, cr) = (libm::sinf(roll * 0.5), libm::cosf(roll * 0.5));
    let (sp, cp) = (libm::sinf(pitch * 0.5), libm::cosf(pitch * 0.5));
    let (sy, cy) = (libm::sinf(yaw * 0.5), libm::cosf(yaw * 0.5));
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f32::consts::FRAC_PI_2;

    /// Pinned vectors: 1 m north, 1 m east, 1 m down in NED are 1 m north, 1 m west (negative),
    /// 1 m up (negative) in NWU.
    #[test]
    fn vectors() {
        assert_eq!(flip_vector([1.0, 0.0, 0.0]), Vector3::new(1.0, 0.0, 0.0));
        assert_eq!(flip_vector([0.0, 1.0, 0.0]), Vector3::new(0.0, -1.0, 0.0));
        assert_eq!(flip_vector([0.0, 0.0, -2.5]), Vector3::new(0.0, 0.0, 2.5));
        let v = Vector3::new(0.3, -1.2, 4.0);
        assert_eq!(flip_vector(flip_to_array(&v)), v);
    }

    /// A vehicle facing east (NED yaw +90°) is at NWU yaw −90°, and its FLU nose points along
    /// −y_NWU = east; its FLU left axis points north; body up is inertial up.
    #[test]
    fn yaw_east_quaternion() {
        let q_ned = UnitQuaternion::from_euler_angles(0.0f32, 0.0, FRAC_PI_2);
        let q =
            UnitQuaternion::from_quaternion(flip_quaternion([q_ned.w, q_ned.i, q_ned.j, q_ned.k]));
        let nose = q * Vector3::x();
        let left = q * Vector3::y();
        let up = q * Vector3::z();
        assert!(
            (nose - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-6,
            "{nose}"
        );
        assert!((left - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-6, "{left}");
        assert!((up - Vector3::z()).norm() < 1e-6);
        let (_, _, yaw) = q.euler_angles();
        assert!((yaw - flip_yaw(FRAC_PI_2)).abs() < 1e-6);
    }

    /// Roll right (NED roll +0.5 rad, right wing down) is roll +0.5 rad about x in NWU too
    /// (x is shared; in FLU it puts the left axis up).
    /// Pitch up (NED +20°, nose up) is NWU pitch −20° (y flips).
    #[test]
    fn roll_and_pitch() {
        let check = |ned: (f32, f32, f32), nwu: (f32, f32, f32)| {
            let a = UnitQuaternion::from_euler_angles(ned.0, ned.1, ned.2);
            let b = UnitQuaternion::from_quaternion(flip_quaternion([a.w, a.i, a.j, a.k]));
            let c = UnitQuaternion::from_euler_angles(nwu.0, nwu.1, nwu.2);
            assert!(b.angle_to(&c) < 1e-5, "{ned:?}");
            // The rotation of any vector matches D R D.
            let v = Vector3::new(0.2, -0.7, 0.4);
            let d = |x: Vector3<f32>| Vector3::new(x.x, -x.y, -x.z);
            assert!((b * v - d(a * d(v))).norm() < 1e-6);
        };
        check((0.5, 0.0, 0.0), (0.5, 0.0, 0.0));
        check((0.0, 0.349, 0.0), (0.0, -0.349, 0.0));
        check((0.1, -0.2, 2.0), (0.1, 0.2, -2.0));
        // Upright level in NED ↔ identity in NWU; upside down stays upside down.
        assert_eq!(
            flip_quaternion([1.0, 0.0, 0.0, 0.0]),
            Quaternion::new(1.0, 0.0, 0.0, 0.0)
        );
        let inv = flip_quaternion([0.0, 1.0, 0.0, 0.0]);
        assert_eq!(inv, Quaternion::new(0.0, 1.0, 0.0, 0.0));
    }

    /// The quaternion map round-trips.
    #[test]
    fn round_trip() {
        let q = UnitQuaternion::from_euler_angles(0.3f32, -1.1, 2.9);
        let back = UnitQuaternion::from_quaternion(flip_quaternion(quaternion_to_mavlink(&q)));
        assert!(back.angle_to(&q) < 1e-6);
    }

    /// Euler angles to a quaternion agree with nalgebra's independent Z-Y-X construction.
    #[test]
    fn euler_angles_match_nalgebra() {
        for &(r, p, y) in &[
            (0.3f32, -0.7f32, 2.5f32),
            (-3.0, 1.2, -0.4),
            (0.0, 0.0, 3.1),
        ] {
            let q = euler_to_quaternion(r, p, y);
            let want = UnitQuaternion::from_euler_angles(r, p, y);
            // q and −q are the same rotation.
            let dot = q[0] * want.w + q[1] * want.i + q[2] * want.j + q[3] * want.k;
            assert!((dot.abs() - 1.0).abs() < 1e-6, "{q:?} vs {want:?}");
        }
    }
}
