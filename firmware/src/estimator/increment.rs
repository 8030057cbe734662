//! The gyro increment's quaternion product, shared by the estimator's attitude propagation,
//! its latency carry-forward and the Mahony filter.

use nalgebra::{Quaternion, Vector3};

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
