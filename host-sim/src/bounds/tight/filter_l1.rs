//! Per-component bounds on `u̇` and `ü` from the L¹ norms of the filter's impulse responses.
//!
//! Per inertial component, eq:FilterDynamics is the linear system
//! `u̇_f = −k_f(u_f − u_s)`, `u̇_s = −k_s(u_s − ubar)` with `|ubar(t)| ≤ M_p`, and
//! (PositionGains::evaluate)
//! `u̇ − p_d⁽³⁾ = k_f (u_s − u_f)`,
//! `ü − p_d⁽⁴⁾ = k_f [k_f(u_f − u_s) − k_s u_s] + k_f k_s ubar(t)`.
//!
//! **Zero start** (`x_f(0) = 0`). A linear output `y = h ∗ ubar` satisfies
//! `|y(t)| ≤ M_p ∫₀^∞ |h|` for every input with `|ubar| ≤ M_p` (Young's inequality). With
//! `r = k_f/k_s` and `U_l = r^{r/(1−r)}` (`e⁻¹` at `r = 1`, Lemma 1's filter overshoot):
//! - `u_s − u_f` has `h_d(t) = k_s(k_s e^{−k_s t} − k_f e^{−k_f t})/(k_s − k_f)`, zero mean and
//!   one sign change at `t₀ = ln(k_s/k_f)/(k_s − k_f)`, so `∫|h_d| = 2∫₀^{t₀} h_d = 2U_l`;
//! - `k_f(u_f − u_s) − k_s u_s` has `h_c(t) = −k_s(k_s² e^{−k_s t} − k_f² e^{−k_f t})/(k_s − k_f)`,
//!   integral `−k_s`, one sign change at `t* = 2 ln(k_s/k_f)/(k_s − k_f)` where
//!   `e^{−k_f t*} = U_l²`, `e^{−k_s t*} = r²U_l²`; hence `∫|h_c| = k_s(1 + 2rU_l²)`
//!   (`k(1 + 2e⁻²)` in the limit `k_s = k_f = k`).
//!
//! Hence `|u̇_i − p⁽³⁾_i| ≤ b₁ = 2k_f M_p U_l` and, adding the current `k_f k_s |ubar| ≤ k_f k_s M_p`,
//! `|ü_i − p⁽⁴⁾_i| ≤ b₂ = k_f M_p (k_s(1 + 2rU_l²) + k_s) = 2k_f M_p (k_s + k_f U_l²)`.
//!
//! **Start in the saturation box** (`x_f(0) ∈ [−M_p, M_p]²` per component). The box is
//! invariant (each state is a convex combination of its start and of the input), so
//! `|u_s − u_f| ≤ 2M_p` and `|k_f(u_f − u_s) − k_s u_s + k_s ubar| ≤ 2k_f M_p + 2k_s M_p`: the same
//! formulas with `U_l = 1`.
//!
//! Compared with Lemma 1, whose `U_ü` has `k_f U_l` where these have `k_f U_l²`, and `√3` for
//! the vector norm where these stay per component.
//!
//! Rounding: `U_l` comes from `ln` and `exp` of `libm` (errors of a few ulps) and is enlarged by
//! the relative margin [`U_L_MARGIN`] before use; the rest is interval arithmetic.

use controller_core::FilterStart;

use super::interval::Interval;

/// Relative enlargement of the computed `U_l` (covers the few-ulp errors of `ln`, `exp` and
/// of `r = k_f/k_s`, whose effect on `U_l` is of the same relative order).
pub const U_L_MARGIN: f64 = 1e-12;

/// `U_l` enclosure: `r^{r/(1−r)}` for `r = k_f/k_s` (`e⁻¹` at `r = 1`), or 1 for
/// [`FilterStart::InSaturationBox`]. Dimensionless.
pub fn filter_overshoot(kf: f64, ks: f64, start: FilterStart) -> Interval {
    match start {
        FilterStart::InSaturationBox => Interval::point(1.0),
        FilterStart::Zero => {
            let r = kf / ks;
            // 1 − r is exact for r in [½, 2] (Sterbenz), and ln r is accurate relative to
            // itself near 1, so the quotient is accurate everywhere except at r = 1 itself.
            let ul = if r == 1.0 {
                (-1.0f64).exp()
            } else {
                (r * r.ln() / (1.0 - r)).exp()
            };
            Interval::new(ul * (1.0 - U_L_MARGIN), (ul * (1.0 + U_L_MARGIN)).min(1.0))
        }
    }
}

/// The half-widths `(b₁, b₂)` [m/s³, m/s⁴] of the per-component boxes of `u̇ − p_d⁽³⁾` and
/// `ü − p_d⁽⁴⁾` (see the module documentation), rounded up.
pub fn rate_and_acceleration_bounds(kf: f64, ks: f64, mp: f64, start: FilterStart) -> (f64, f64) {
    let ul = filter_overshoot(kf, ks, start);
    let (kf, ks, mp) = (
        Interval::point(kf),
        Interval::point(ks),
        Interval::point(mp),
    );
    let two = Interval::point(2.0);
    let b1 = two * kf * mp * ul;
    let b2 = two * kf * mp * (ks + kf * ul.sqr());
    (b1.hi, b2.hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫|h| by a fine midpoint rule on the closed-form impulse responses.
    fn l1(h: impl Fn(f64) -> f64, horizon: f64) -> f64 {
        let n = 2_000_000;
        let dt = horizon / n as f64;
        (0..n).map(|k| h((k as f64 + 0.5) * dt).abs() * dt).sum()
    }

    #[test]
    fn closed_forms_match_quadrature() {
        for (kf, ks) in [(2.0, 20.0), (3.0, 5.0), (7.0, 2.0)] {
            let hd = |t: f64| ks * (ks * (-ks * t).exp() - kf * (-kf * t).exp()) / (ks - kf);
            let hc =
                |t: f64| -ks * (ks * ks * (-ks * t).exp() - kf * kf * (-kf * t).exp()) / (ks - kf);
            let horizon = 40.0 / kf.min(ks);
            let (b1, b2) = rate_and_acceleration_bounds(kf, ks, 1.0, FilterStart::Zero);
            let q1 = kf * l1(hd, horizon);
            let q2 = kf * (l1(hc, horizon) + ks);
            assert!((b1 - q1).abs() < 1e-5 * q1, "{b1} vs {q1}");
            assert!((b2 - q2).abs() < 1e-5 * q2, "{b2} vs {q2}");
        }
        // The k_s = k_f limit: k(1 + 2e⁻²) for h_c, 2e⁻¹ for h_d.
        let (b1, b2) = rate_and_acceleration_bounds(4.0, 4.0, 1.0, FilterStart::Zero);
        assert!((b1 - 4.0 * 2.0 * (-1f64).exp()).abs() < 1e-9);
        assert!((b2 - 4.0 * (4.0 * (1.0 + 2.0 * (-2f64).exp()) + 4.0)).abs() < 1e-9);
    }
}
