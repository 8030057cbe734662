//! Small SO(3) helpers shared by the baselines, the loops and the tests.

use nalgebra::{Matrix3, Vector3};

/// The vee map of the skew-symmetric part of a 3×3 matrix `M`: `vee(½(M − Mᵀ))`, so
/// `vee_skew([w]ₓ) = w` for every `w`. The result has the unit of `M`'s entries (rad/s for
/// `[ω]ₓ`, dimensionless for a rotation matrix); frame as `M`'s.
pub fn vee_skew(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    ) * 0.5
}

/// The rotation angle of a rotation matrix \[rad\], in `[0, π]`:
/// `atan2(2|vee_skew(R)|, tr R − 1)` (`2 sin θ` and `2 cos θ`), accurate near 0 and π.
pub fn rotation_angle(r: &Matrix3<f64>) -> f64 {
    (vee_skew(r).norm() * 2.0).atan2(r.trace() - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Unit};

    #[test]
    fn vee_inverts_the_hat_map() {
        let w = Vector3::new(0.3, -1.2, 2.5);
        assert_eq!(vee_skew(&w.cross_matrix()), w);
        // Only the skew part counts.
        let m = w.cross_matrix() + Matrix3::new(1.0, 2.0, 3.0, 2.0, 5.0, 6.0, 3.0, 6.0, 9.0);
        assert!((vee_skew(&m) - w).norm() < 1e-15);
    }

    #[test]
    fn rotation_angle_is_exact_at_half_turn_and_small_angles() {
        let axis = Unit::new_normalize(Vector3::new(1.0, -2.0, 0.5));
        for angle in [0.0, 1e-9, 0.3, 2.0, std::f64::consts::PI] {
            let r = Rotation3::from_axis_angle(&axis, angle);
            assert!(
                (rotation_angle(r.matrix()) - angle).abs() < 1e-12,
                "{angle}"
            );
        }
    }
}
