//! Local exponential stability of the position loop with the integral action: the
//! characteristic polynomial of its per-axis linearisation and the Routh–Hurwitz conditions.
//!
//! Source: extension, docs/integral-action.md. Near an equilibrium the saturation `σ_p` has slope
//! 1, and with the attitude loop taken as ideal (`u` realised) each inertial axis obeys, with
//! `c = 1/k_f + 1/k_s` and `e = η_f + d` (`d` a constant acceleration disturbance),
//! `ż₁ = z₂ + c e`, `ż₂ = −k_p z₁ − k_v z₂ + e`, `η̇ = −k_i z₁`, `η̇_f = −k_η (η_f − η)`
//! (the filter states `u_f`, `u_s` follow as a stable cascade with poles `−k_f`, `−k_s`).
//!
//! **Integral of `z₁` alone.** Eliminating `e = −k_i k_η z₁ / (s (s + k_η))`:
//! `(s² + k_v s + k_p) s (s + k_η) + k_i k_η (1 + c k_v + c s) = 0`, i.e.
//! `s⁴ + a₃ s³ + a₂ s² + a₁ s + a₀` with `a₃ = k_v + k_η`, `a₂ = k_p + k_v k_η`,
//! `a₁ = k_η (k_p + c k_i)`, `a₀ = k_i k_η (1 + c k_v)`. (As `k_η → ∞` it tends to the
//! filterless cubic `s³ + k_v s² + (k_p + c k_i) s + k_i (1 + c k_v)`.)
//! Routh–Hurwitz for a monic quartic: all `aⱼ > 0` (true for positive gains),
//! `a₃ a₂ > a₁` and `a₃ a₂ a₁ > a₁² + a₃² a₀`.
//!
//! **With the disturbance observer** ([`crate::disturbance_observer`], `|z₁,i| < z̄` so that the
//! clamp is inactive): with `ξ = η + d` and the innovation `ε = v − v̂`, `ξ̇ = −k_i z₁ − L_d ε`,
//! `ε̇ = ξ − L_v ε`, `e = ξ_f` (`ξ̇_f = −k_η (ξ_f − ξ)`). The quintic
//! `s⁵ + a₄ s⁴ + a₃ s³ + a₂ s² + a₁ s + a₀` has
//! `a₄ = L_v + k_η + k_v`, `a₃ = L_d + k_p + k_η k_v + L_v (k_η + k_v)`,
//! `a₂ = L_d (k_η + k_v) + k_η k_p + L_v (k_η k_v + k_p) + c k_η k_i`,
//! `a₁ = L_d (k_η k_v + k_p) + k_η (k_i + L_v k_p + c k_i (k_v + L_v))`,
//! `a₀ = k_η (L_d k_p + L_v k_i (1 + c k_v))`, all positive for positive gains. By the
//! Liénard–Chipart criterion it is Hurwitz iff the Hurwitz determinants `Δ₂ = a₄ a₃ − a₂` and
//! `Δ₄` are positive. With `k_i = 0` it factors as
//! `(s² + L_v s + L_d)(s + k_η)(s² + k_v s + k_p)`: the observer alone is stable for any
//! positive gains.

use nalgebra::Matrix4;

use crate::condition::Condition;
use crate::integral::IntegralGains;
use crate::position::PositionGains;
use crate::scalar::Scalar;

/// Number of Routh–Hurwitz conditions reported.
pub const STABILITY_CONDITION_COUNT: usize = 2;

/// `[a₀, a₁, a₂, a₃, a₄, a₅]` of the per-axis closed-loop characteristic polynomial (see the
/// module docs), ascending powers of `s`, units `1/sʲ` for the coefficient of `s^{n−j}`: the
/// quartic `[a₀, a₁, a₂, a₃, 1, 0]` for the integral of `z₁` alone, the monic quintic with the
/// observer.
pub fn characteristic_polynomial<T: Scalar>(
    position: &PositionGains<T>,
    integral: &IntegralGains<T>,
) -> [T; 6] {
    let one = T::one();
    let c = one / position.kf + one / position.ks;
    let (kp, kv, ki, ke) = (position.kp, position.kv, integral.gain, integral.bandwidth);
    match &integral.observer {
        None => [
            ki * ke * (one + c * kv),
            ke * (kp + c * ki),
            kp + kv * ke,
            kv + ke,
            one,
            T::zero(),
        ],
        Some(o) => {
            let (lv, ld) = (o.velocity_gain, o.disturbance_gain);
            [
                ke * (ld * kp + lv * ki * (one + c * kv)),
                ld * (ke * kv + kp) + ke * (ki + lv * kp + c * ki * (kv + lv)),
                ld * (ke + kv) + ke * kp + lv * (ke * kv + kp) + c * ke * ki,
                ld + kp + ke * kv + lv * (ke + kv),
                lv + ke + kv,
                one,
            ]
        }
    }
}

/// The Routh–Hurwitz conditions of [`characteristic_polynomial`], each with both sides; all
/// holding is equivalent (for positive gains) to every root in the open left half-plane, i.e.
/// local exponential stability of the equilibrium `z = 0`, `η_f = −d` (and `v̂ = v` with the
/// observer). With the vertical channel apart ([`PositionGains::vertical`]) each condition is
/// checked on the horizontal and the vertical filters' linearisations, and the one that fails
/// (else the tighter) is returned.
pub fn local_stability_conditions<T: Scalar>(
    position: &PositionGains<T>,
    integral: &IntegralGains<T>,
) -> [Condition<T>; STABILITY_CONDITION_COUNT] {
    let Some(v) = &position.vertical else {
        return conditions_of(position, integral);
    };
    // The vertical channel apart has its own filters (docs/vertical-channel.md): each condition
    // must hold on both channels' linearisations; the one that fails, else the tighter, is kept.
    let horizontal = conditions_of(position, integral);
    let vertical = conditions_of(
        &PositionGains {
            kf: v.kf,
            ks: v.ks,
            vertical: None,
            ..*position
        },
        integral,
    );
    core::array::from_fn(|i| {
        let (h, z) = (horizontal[i], vertical[i]);
        let slack = |c: &Condition<T>| (c.lhs - c.rhs) / (c.lhs.abs() + c.rhs.abs() + T::one());
        match (h.holds, z.holds) {
            (_, false) => z,
            (false, true) => h,
            (true, true) if slack(&z) < slack(&h) => z,
            _ => h,
        }
    })
}

fn conditions_of<T: Scalar>(
    position: &PositionGains<T>,
    integral: &IntegralGains<T>,
) -> [Condition<T>; STABILITY_CONDITION_COUNT] {
    let [a0, a1, a2, a3, a4, _] = characteristic_polynomial(position, integral);
    let strict = Condition::strict;
    match integral.observer {
        None => [
            strict(
                "integral.local_stability_hurwitz2",
                "a3 a2 > a1 (Routh-Hurwitz, docs/integral-action.md)",
                a3 * a2,
                a1,
            ),
            strict(
                "integral.local_stability_hurwitz3",
                "a3 a2 a1 > a1^2 + a3^2 a0 (Routh-Hurwitz, docs/integral-action.md)",
                a3 * a2 * a1,
                a1 * a1 + a3 * a3 * a0,
            ),
        ],
        Some(_) => {
            let zero = T::zero();
            let one = T::one();
            #[rustfmt::skip]
            let hurwitz4 = Matrix4::new(
                a4, a2, a0, zero,
                one, a3, a1, zero,
                zero, a4, a2, a0,
                zero, one, a3, a1,
            );
            [
                strict(
                    "integral.local_stability_observer_hurwitz2",
                    "a4 a3 > a2 (Lienard-Chipart, observer, docs/integral-action.md)",
                    a4 * a3,
                    a2,
                ),
                strict(
                    "integral.local_stability_observer_hurwitz4",
                    "Hurwitz determinant D4 > 0 (Lienard-Chipart, observer, docs/integral-action.md)",
                    hurwitz4.determinant(),
                    zero,
                ),
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix4;
    use proptest::prelude::*;

    /// The linearisation's matrix in `(z₁, z₂, η, η_f)`, written from the ODEs in the module
    /// docs (not from the polynomial).
    fn system_matrix(p: &PositionGains<f64>, i: &IntegralGains<f64>) -> Matrix4<f64> {
        let c = 1.0 / p.kf + 1.0 / p.ks;
        #[rustfmt::skip]
        let a = Matrix4::new(
            0.0, 1.0, 0.0, c,
            -p.kp, -p.kv, 0.0, 1.0,
            -i.gain, 0.0, 0.0, 0.0,
            0.0, 0.0, i.bandwidth, -i.bandwidth,
        );
        a
    }

    fn gains(
        kp: f64,
        kv: f64,
        kf: f64,
        ks: f64,
        ki: f64,
        ke: f64,
    ) -> (PositionGains<f64>, IntegralGains<f64>) {
        (
            PositionGains {
                kp,
                kv,
                kf,
                ks,
                saturation: 1.0,
                saturation_shape: crate::position_saturation::PositionSaturation::Componentwise,
                vertical: None,
            },
            IntegralGains {
                feedforward_scale: None,
                gain: ki,
                level: nalgebra::Vector3::repeat(1.0),
                rate: nalgebra::Vector3::repeat(1.0),
                bandwidth: ke,
                observer: None,
            },
        )
    }

    proptest! {
        /// The Routh–Hurwitz verdict agrees with the eigenvalues of the linearisation's matrix,
        /// and the polynomial's roots are those eigenvalues (checked through P(λ) ≈ 0).
        #[test]
        fn routh_hurwitz_matches_eigenvalues(
            kp in 0.1..30.0f64, kv in 0.1..20.0f64, kf in 0.2..30.0f64, ks in 0.2..60.0f64,
            ki in 0.01..60.0f64, ke in 0.1..60.0f64,
        ) {
            let (p, i) = gains(kp, kv, kf, ks, ki, ke);
            let eig = system_matrix(&p, &i).complex_eigenvalues();
            prop_assert_eq!(characteristic_polynomial(&p, &i)[5], 0.0);
            check_against_eigenvalues(&p, &i, eig.as_slice())?;
        }
    }

    /// The stability verdict of [`local_stability_conditions`] against the eigenvalues `eig` of
    /// the linearisation's matrix, and the polynomial's roots against them (`P(λ) ≈ 0`). Set-ups
    /// too close to the boundary for the eigen-solver to decide are rejected (`prop_assume`).
    fn check_against_eigenvalues(
        p: &PositionGains<f64>,
        i: &IntegralGains<f64>,
        eig: &[nalgebra::Complex<f64>],
    ) -> Result<(), TestCaseError> {
        let max_re = eig.iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max);
        let scale = eig.iter().map(|l| l.re.hypot(l.im)).fold(1.0, f64::max);
        prop_assume!(max_re.abs() > 1e-6 * scale);
        let conds = local_stability_conditions(p, i);
        let hurwitz = conds.iter().all(|c| c.holds);
        prop_assert_eq!(hurwitz, max_re < 0.0, "max Re = {}, {:?}", max_re, conds);
        let a = characteristic_polynomial(p, i);
        for l in eig {
            let v = a
                .iter()
                .rev()
                .fold(nalgebra::Complex::new(0.0, 0.0), |acc, c| acc * l + c);
            let mag = a
                .iter()
                .enumerate()
                .map(|(j, c)| c.abs() * l.re.hypot(l.im).powi(j as i32))
                .sum::<f64>();
            prop_assert!(v.re.hypot(v.im) <= 1e-9 * mag, "P({l}) = {v}");
        }
        Ok(())
    }

    /// The observer mode's linearisation in `(z₁, z₂, ξ, ξ_f, ε)`, written from the ODEs in the
    /// module docs (not from the polynomial).
    fn observer_matrix(
        p: &PositionGains<f64>,
        i: &IntegralGains<f64>,
    ) -> nalgebra::SMatrix<f64, 5, 5> {
        let c = 1.0 / p.kf + 1.0 / p.ks;
        let o = i.observer.unwrap();
        #[rustfmt::skip]
        let a = nalgebra::SMatrix::<f64, 5, 5>::from_row_slice(&[
            0.0, 1.0, 0.0, c, 0.0,
            -p.kp, -p.kv, 0.0, 1.0, 0.0,
            -i.gain, 0.0, 0.0, 0.0, -o.disturbance_gain,
            0.0, 0.0, i.bandwidth, -i.bandwidth, 0.0,
            0.0, 0.0, 1.0, 0.0, -o.velocity_gain,
        ]);
        a
    }

    proptest! {
        /// With the observer: the Liénard–Chipart verdict agrees with the eigenvalues of the
        /// linearisation's matrix, and the quintic's roots are those eigenvalues.
        #[test]
        fn observer_lienard_chipart_matches_eigenvalues(
            kp in 0.1..30.0f64, kv in 0.1..20.0f64, kf in 0.2..30.0f64, ks in 0.2..60.0f64,
            ki in 0.01..60.0f64, ke in 0.1..60.0f64, lv in 0.1..30.0f64, ld in 0.1..100.0f64,
        ) {
            let (p, mut i) = gains(kp, kv, kf, ks, ki, ke);
            i.observer = Some(crate::disturbance_observer::ObserverGains {
                velocity_gain: lv,
                disturbance_gain: ld,
                error_limit: 0.05,
            });
            let eig = observer_matrix(&p, &i).complex_eigenvalues();
            prop_assert!(characteristic_polynomial(&p, &i).iter().all(|c| *c > 0.0));
            check_against_eigenvalues(&p, &i, eig.as_slice())?;
        }
    }

    /// With k_i = 0 the quintic is the product of the observer's, the filter's and the position
    /// loop's polynomials (the observer is separate from the loop it serves).
    #[test]
    fn a_pure_observer_factors() {
        let (p, mut i) = gains(9.0, 6.0, 2.0, 20.0, 0.0, 3.0);
        let (lv, ld) = (4.0, 5.0);
        i.observer = Some(crate::disturbance_observer::ObserverGains {
            velocity_gain: lv,
            disturbance_gain: ld,
            error_limit: 0.05,
        });
        // (s² + L_v s + L_d)(s + k_η)(s² + k_v s + k_p), multiplied out by convolution.
        let mul = |a: &[f64], b: &[f64]| {
            let mut r = vec![0.0; a.len() + b.len() - 1];
            for (x, ca) in a.iter().enumerate() {
                for (y, cb) in b.iter().enumerate() {
                    r[x + y] += ca * cb;
                }
            }
            r
        };
        let expected = mul(&mul(&[ld, lv, 1.0], &[3.0, 1.0]), &[9.0, 6.0, 1.0]);
        let got = characteristic_polynomial(&p, &i);
        for (g, e) in got.iter().zip(&expected) {
            assert!(
                (g - e).abs() <= 1e-12 * e.abs().max(1.0),
                "{got:?} vs {expected:?}"
            );
        }
    }

    /// Some integral gains destabilise the loop, and the certificate says so: a large k_i with a
    /// slow filter.
    #[test]
    fn large_integral_gain_with_slow_filter_is_refused() {
        let (p, i) = gains(9.0, 6.0, 2.0, 20.0, 50.0, 0.5);
        let conds = local_stability_conditions(&p, &i);
        assert!(!conds.iter().all(|c| c.holds));
        let (p, i) = gains(9.0, 6.0, 2.0, 20.0, 2.0, 5.0);
        assert!(local_stability_conditions(&p, &i).iter().all(|c| c.holds));
    }
}
