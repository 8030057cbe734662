//! The filtered saturated position controller of Section IV.
//!
//! The control vector `u = R (T/m) e₃` [m/s²] (inertial) is
//! `u = u_f + g e₃ + p̈_d` (eq:PositionControlLaw), where the feedback `u_f` is the output of two
//! cascaded first-order filters (eq:FilterDynamics)
//! `u̇_f = −k_f (u_f − u_s)`, `u̇_s = −k_s (u_s − ubar_p)`,
//! driven by the saturated feedback `ubar_p = −σ_p(k_p z₁ + k_v z₂)` in the z-coordinates
//! (eq:Zcoordinates) `z₁ = p̃ + (1/k_f + 1/k_s) ṽ + u_f/(k_s k_f)`, `z₂ = ṽ + u_f/k_f + u_s/k_s`,
//! in which the loop is the double integrator `ż₁ = z₂`, `ż₂ = ubar_p`.
//! The derivatives `u̇`, `ü` needed by the attitude reference come from the filter dynamics in
//! closed form (never by differencing).

use nalgebra::Vector3;

use crate::position_saturation::PositionSaturation;
use crate::scalar::Scalar;
use crate::velocity_limit::VelocityLimit;
use crate::vertical_channel::{horizontal, VerticalChannel};

/// Gains of the position loop (Table I names in brackets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionGains<T: Scalar> {
    /// `k_p` [1/s²]: proportional gain on `z₁`.
    pub kp: T,
    /// `k_v` [1/s]: gain on `z₂`.
    pub kv: T,
    /// `k_f` [1/s]: bandwidth of the output filter (`u_f`).
    pub kf: T,
    /// `k_s` [1/s]: bandwidth of the inner filter (`u_s`).
    pub ks: T,
    /// `M_p` [m/s²]: saturation level of `σ_p` (per component, or of the norm with
    /// [`PositionSaturation::Norm`]); must satisfy `M_p < g − K_a3`.
    pub saturation: T,
    /// Shape of `σ_p`: the paper's componentwise saturation (the default) or the norm
    /// saturation (extension, docs/position-saturation.md).
    pub saturation_shape: PositionSaturation,
    /// The vertical channel apart (extension, docs/vertical-channel.md): `Some` saturates the
    /// vertical component with its own upward and downward levels, and `saturation_shape` with
    /// `M_p` then applies to the horizontal pair only; `None` is the paper's, bit for bit.
    pub vertical: Option<VerticalChannel<T>>,
}

/// Filter states `x_f = (u_f, u_s)` [m/s²], inertial frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterState<T: Scalar> {
    /// Filtered feedback `u_f` [m/s²].
    pub u_f: Vector3<T>,
    /// Internal filter state `u_s` [m/s²].
    pub u_s: Vector3<T>,
}

impl<T: Scalar> FilterState<T> {
    /// `x_f = 0`, the initial condition of Section VI.
    pub fn zero() -> Self {
        Self {
            u_f: Vector3::zeros(),
            u_s: Vector3::zeros(),
        }
    }
}

/// What the position loop computes at one sample (all inertial frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionOutput<T: Scalar> {
    /// `z₁` \[m\]: forward-projected position error (eq:Zcoordinates).
    pub z1: Vector3<T>,
    /// `z₂` [m/s]: forward-projected velocity error (eq:Zcoordinates).
    pub z2: Vector3<T>,
    /// `ubar_p = −σ_p(k_p z₁ + k_v z₂)` [m/s²], each component in `(−M_p, M_p)` (its norm, with
    /// the norm shape).
    pub ubar_p: Vector3<T>,
    /// `u = u_f + g e₃ + p̈_d` [m/s²] (eq:PositionControlLaw).
    pub u: Vector3<T>,
    /// `u̇ = −k_f (u_f − u_s) + p_d⁽³⁾` [m/s³].
    pub u_dot: Vector3<T>,
    /// `ü = −k_f(−k_f(u_f − u_s) + k_s(u_s − ubar_p)) + p_d⁽⁴⁾` [m/s⁴].
    pub u_ddot: Vector3<T>,
}

impl<T: Scalar> PositionGains<T> {
    /// `ubar_p = −σ_p(y)` [m/s²] for the argument `y = k_p z₁ + k_v z₂` (inertial): the paper's
    /// shape with `M_p`, or with the vertical channel apart the shape on `(x, y)` and the
    /// vertical levels on `z` ([`VerticalChannel::feedback`]). Source: Section IV; extensions
    /// docs/position-saturation.md, docs/vertical-channel.md.
    #[inline]
    pub fn feedback_of(&self, y: &Vector3<T>) -> Vector3<T> {
        match &self.vertical {
            None => -self.saturation_shape.apply(y, self.saturation),
            Some(v) => {
                let mut out = -self.saturation_shape.apply(&horizontal(y), self.saturation);
                out.z = v.feedback(y.z);
                out
            }
        }
    }

    /// Whether `v` [m/s²] lies in the set `ubar_p` takes its values in (and the filters keep
    /// `u_f`, `u_s` in): the shape's `M_p` set, or with the vertical channel apart the horizontal
    /// shape's and `[−M_down, M_up]`.
    pub fn contains(&self, v: &Vector3<T>) -> bool {
        match &self.vertical {
            None => self.saturation_shape.size(v) <= self.saturation,
            Some(l) => {
                self.saturation_shape.size(&horizontal(v)) <= self.saturation && l.contains(v.z)
            }
        }
    }

    /// `v` [m/s²] brought into that set: scaled down in the shape's norm (its horizontal part
    /// with the vertical channel apart, whose component is clamped). Unchanged when inside.
    pub fn project(&self, v: &Vector3<T>) -> Vector3<T> {
        let scale = |w: Vector3<T>| {
            let size = self.saturation_shape.size(&w);
            if size > self.saturation {
                w * (self.saturation / size)
            } else {
                w
            }
        };
        match &self.vertical {
            None => scale(*v),
            Some(l) => {
                let mut out = scale(horizontal(v));
                out.z = l.clamp(v.z);
                out
            }
        }
    }

    /// The largest downward `|ubar_p,z|` [m/s²]: `M_p`, or `M_down` with the vertical channel
    /// apart. Theorem 1's thrust floor is `m(g − K_a3 − this)`.
    #[inline]
    pub fn downward_level(&self) -> T {
        self.vertical.map_or(self.saturation, |v| v.down)
    }

    /// The z-coordinates `(z₁, z₂)` of eq:Zcoordinates from the position error `p̃` \[m\], the
    /// velocity error `ṽ` [m/s] and the filter states.
    pub fn z_coordinates(
        &self,
        position_error: &Vector3<T>,
        velocity_error: &Vector3<T>,
        filter: &FilterState<T>,
    ) -> (Vector3<T>, Vector3<T>) {
        let inv_kf = T::one() / self.kf;
        let inv_ks = T::one() / self.ks;
        let mut z1 =
            position_error + velocity_error * (inv_kf + inv_ks) + filter.u_f * (inv_kf * inv_ks);
        let mut z2 = velocity_error + filter.u_f * inv_kf + filter.u_s * inv_ks;
        if let Some(v) = &self.vertical {
            // The vertical axis's own filters (eq:Zcoordinates on that axis alone).
            let (a, b) = (T::one() / v.kf, T::one() / v.ks);
            z1.z = position_error.z + velocity_error.z * (a + b) + filter.u_f.z * (a * b);
            z2.z = velocity_error.z + filter.u_f.z * a + filter.u_s.z * b;
        }
        (z1, z2)
    }

    /// The position law at one sample.
    ///
    /// Inputs: the feedback shape (`None`: the paper's `ubar_p = −σ_p(k_p z₁ + k_v z₂)`;
    /// `Some(limit)`: the velocity-limited feedback `−σ_p(`[`VelocityLimit::argument`]`)`, an
    /// extension, docs/velocity-limit.md), `p̃ = p − p_d` \[m\], `ṽ = v − ṗ_d` [m/s], filter states, the
    /// reference's `p̈_d`, `p_d⁽³⁾`, `p_d⁽⁴⁾`, and gravity `g` [m/s²]; all inertial. Source:
    /// Section IV, eq:PositionControlLaw, eq:FilterDynamics, eq:Zcoordinates;
    /// `σ_p = M tanh(·/M)` as in Section VI, or the norm shape of [`PositionSaturation`].
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        limit: Option<&VelocityLimit<T>>,
        position_error: &Vector3<T>,
        velocity_error: &Vector3<T>,
        filter: &FilterState<T>,
        acceleration: &Vector3<T>,
        jerk: &Vector3<T>,
        snap: &Vector3<T>,
        gravity: T,
    ) -> PositionOutput<T> {
        let (z1, z2) = self.z_coordinates(position_error, velocity_error, filter);
        let ubar_p = match limit {
            None => self.feedback_of(&(z1 * self.kp + z2 * self.kv)),
            Some(l) => self.feedback_of(&l.argument((self.kp, self.kv), &z1, &z2)),
        };
        let filter_gap = filter.u_f - filter.u_s;
        let mut u_f_dot = -filter_gap * self.kf;
        let mut u_s_dot = (filter.u_s - ubar_p) * (-self.ks);
        let u = filter.u_f + Vector3::z() * gravity + acceleration;
        if let Some(v) = &self.vertical {
            u_f_dot.z = -filter_gap.z * v.kf;
            u_s_dot.z = (filter.u_s.z - ubar_p.z) * (-v.ks);
        }
        let u_dot = u_f_dot + jerk;
        let mut u_ddot = (u_f_dot - u_s_dot) * (-self.kf) + snap;
        if let Some(v) = &self.vertical {
            u_ddot.z = (u_f_dot.z - u_s_dot.z) * (-v.kf) + snap.z;
        }
        PositionOutput {
            z1,
            z2,
            ubar_p,
            u,
            u_dot,
            u_ddot,
        }
    }

    /// Propagates the filter states over `dt` \[s\] with `ubar_p` held constant, by the exact
    /// solution of the linear ODE eq:FilterDynamics (the sampled reading of this crate).
    /// Equivalent to `self.propagator(dt).apply(filter, ubar_p)`.
    pub fn propagate(&self, filter: &FilterState<T>, ubar_p: &Vector3<T>, dt: T) -> FilterState<T> {
        self.propagator(dt).apply(filter, ubar_p)
    }

    /// The coefficients of the exact filter propagation over `dt` \[s\] (see
    /// [`FilterPropagator`]); they depend only on the gains and `dt`, so a fixed-rate caller
    /// computes them once.
    pub fn propagator(&self, dt: T) -> FilterPropagator<T> {
        let [decay_f, decay_s, coupling] = propagation(self.kf, self.ks, dt);
        FilterPropagator {
            dt,
            decay_f,
            decay_s,
            coupling,
            vertical: self.vertical.map(|v| propagation(v.kf, v.ks, dt)),
        }
    }
}

/// `[e^{−k_f dt}, e^{−k_s dt}, k_f dt e^{−k_f dt} φ₁((k_f − k_s) dt)]` ([`FilterPropagator`]).
fn propagation<T: Scalar>(kf: T, ks: T, dt: T) -> [T; 3] {
    let decay_f = (-kf * dt).exp();
    let decay_s = (-ks * dt).exp();
    let x = (kf - ks) * dt;
    let phi1 = if x.abs() < T::default_epsilon().sqrt() {
        T::one() + x * nalgebra::convert::<f64, T>(0.5)
    } else {
        x.exp_m1() / x
    };
    [decay_f, decay_s, kf * dt * decay_f * phi1]
}

/// The exact solution of eq:FilterDynamics over one sample of length `dt` with `ubar_p` held.
///
/// With `e_s = u_s − ubar_p`, `e_f = u_f − ubar_p`:
/// `e_s(t) = e_s(0) e^{−k_s t}`,
/// `e_f(t) = e_f(0) e^{−k_f t} + k_f e_s(0) t e^{−k_f t} · φ₁((k_f − k_s) t)`, with
/// `φ₁(x) = (eˣ − 1)/x`, which is well conditioned for `k_s ≈ k_f` (and `= 1` when equal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterPropagator<T: Scalar> {
    /// The sample length `dt` \[s\] the coefficients are for.
    pub dt: T,
    /// `e^{−k_f dt}`.
    decay_f: T,
    /// `e^{−k_s dt}`.
    decay_s: T,
    /// `k_f dt e^{−k_f dt} φ₁((k_f − k_s) dt)`.
    coupling: T,
    /// The vertical axis's own three coefficients with the vertical channel apart
    /// (docs/vertical-channel.md).
    vertical: Option<[T; 3]>,
}

impl<T: Scalar> FilterPropagator<T> {
    /// Advances the filter states `(u_f, u_s)` \[m/s²\] by `dt` with `ubar_p` \[m/s²\] held.
    pub fn apply(&self, filter: &FilterState<T>, ubar_p: &Vector3<T>) -> FilterState<T> {
        let e_s = filter.u_s - ubar_p;
        let e_f = filter.u_f - ubar_p;
        let mut next = FilterState {
            u_f: ubar_p + e_f * self.decay_f + e_s * self.coupling,
            u_s: ubar_p + e_s * self.decay_s,
        };
        if let Some([decay_f, decay_s, coupling]) = self.vertical {
            next.u_f.z = ubar_p.z + e_f.z * decay_f + e_s.z * coupling;
            next.u_s.z = ubar_p.z + e_s.z * decay_s;
        }
        next
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::saturation::tanh_saturation;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn gains() -> PositionGains<f64> {
        PositionGains {
            kp: 9.0,
            kv: 6.0,
            kf: 2.0,
            ks: 20.0,
            saturation: 2.0,
            saturation_shape: PositionSaturation::Componentwise,
            vertical: None,
        }
    }

    fn v3() -> impl Strategy<Value = Vector3<f64>> {
        (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    /// Integrates the filtered double integrator p̃̈ = u_f (ideal inner loop, fixed reference)
    /// with fine RK4 steps and checks ż₁ = z₂ and ż₂ = ubar_p (the Brunovsky form of Section IV).
    #[test]
    fn z_coordinates_are_a_double_integrator() {
        let g = gains();
        // State (p̃, ṽ, u_f, u_s); ubar_p recomputed continuously.
        let f = |x: &[Vector3<f64>; 4]| {
            let filt = FilterState {
                u_f: x[2],
                u_s: x[3],
            };
            let (z1, z2) = g.z_coordinates(&x[0], &x[1], &filt);
            let ub = -tanh_saturation(&(z1 * g.kp + z2 * g.kv), g.saturation);
            [x[1], x[2], -(x[2] - x[3]) * g.kf, -(x[3] - ub) * g.ks]
        };
        let mut x = [
            Vector3::new(3.0, -1.0, 2.0),
            Vector3::new(0.5, 0.0, -1.0),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let h = 1e-4;
        for _ in 0..2000 {
            let filt = FilterState {
                u_f: x[2],
                u_s: x[3],
            };
            let (z1, z2) = g.z_coordinates(&x[0], &x[1], &filt);
            let ub = -tanh_saturation(&(z1 * g.kp + z2 * g.kv), g.saturation);
            let step = |x: &[Vector3<f64>; 4], k: &[Vector3<f64>; 4], s: f64| {
                core::array::from_fn(|i| x[i] + k[i] * s)
            };
            let k1 = f(&x);
            let k2 = f(&step(&x, &k1, h / 2.0));
            let k3 = f(&step(&x, &k2, h / 2.0));
            let k4 = f(&step(&x, &k3, h));
            let next: [Vector3<f64>; 4] = core::array::from_fn(|i| {
                x[i] + (k1[i] + k2[i] * 2.0 + k3[i] * 2.0 + k4[i]) * (h / 6.0)
            });
            let nf = FilterState {
                u_f: next[2],
                u_s: next[3],
            };
            let (n1, n2) = g.z_coordinates(&next[0], &next[1], &nf);
            assert_relative_eq!((n1 - z1) / h, z2, epsilon = 2e-3);
            assert_relative_eq!((n2 - z2) / h, ub, epsilon = 2e-3);
            x = next;
        }
    }

    proptest! {
        /// The exact propagation agrees with a fine RK4 integration of eq:FilterDynamics,
        /// including the resonant case k_f = k_s.
        #[test]
        fn propagation_is_exact(uf in v3(), us in v3(), ub in v3(), dt in 0.001..0.2f64,
                                equal in proptest::bool::ANY) {
            let mut g = gains();
            if equal { g.ks = g.kf; }
            let exact = g.propagate(&FilterState { u_f: uf, u_s: us }, &ub, dt);
            let (mut f, mut s) = (uf, us);
            let n = 4000;
            let h = dt / n as f64;
            let deriv = |f: Vector3<f64>, s: Vector3<f64>| (-(f - s) * g.kf, -(s - ub) * g.ks);
            for _ in 0..n {
                let (a1, b1) = deriv(f, s);
                let (a2, b2) = deriv(f + a1 * h / 2.0, s + b1 * h / 2.0);
                let (a3, b3) = deriv(f + a2 * h / 2.0, s + b2 * h / 2.0);
                let (a4, b4) = deriv(f + a3 * h, s + b3 * h);
                f += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0);
                s += (b1 + b2 * 2.0 + b3 * 2.0 + b4) * (h / 6.0);
            }
            assert_relative_eq!(exact.u_f, f, epsilon = 1e-9);
            assert_relative_eq!(exact.u_s, s, epsilon = 1e-9);
        }

        /// u̇ and ü agree with central differences of u_f along the filter flow (ubar_p held,
        /// p_d fixed), within a truncation bound derived from the closed-form solution:
        /// `u_f − ubar = A e^{−k_f t} + B e^{−k_s t}` per component, so on `[−h, h]` the n-th
        /// derivative is at most `(|A| k_fⁿ + |B| k_sⁿ) e^{k_s h}`; the first central difference
        /// errs by at most `h²/6` times the third derivative, the second by `h²/12` times the
        /// fourth, plus rounding (`ε |u_f| / h` and `4 ε |u_f| / h²`).
        #[test]
        fn u_derivatives_are_analytic(uf in v3(), us in v3(), pe in v3(), ve in v3()) {
            let g = gains();
            let filt = FilterState { u_f: uf, u_s: us };
            let zero = Vector3::zeros();
            let out = g.evaluate(None, &pe, &ve, &filt, &zero, &zero, &zero, 9.81);
            let at = |t: f64| g.propagate(&filt, &out.ubar_p, t).u_f;
            let (kf, ks) = (g.kf, g.ks);
            let e_s = us - out.ubar_p;
            let b_coef = -e_s * (kf / (ks - kf));
            let a_coef = (uf - out.ubar_p) - b_coef;
            let bound = |n: i32, h: f64| {
                a_coef.abs() * kf.powi(n) + b_coef.abs() * ks.powi(n)
            } * (ks * h).exp();
            let scale = 1.0 + uf.amax() + out.ubar_p.amax();
            let eps = f64::EPSILON;

            let h1 = 1e-4;
            let fd1 = (at(h1) - at(-h1)) / (2.0 * h1);
            let tol1 = bound(3, h1) * (h1 * h1 / 6.0) + Vector3::repeat(4.0 * eps * scale / h1);
            let h2 = 1e-3;
            let fd2 = (at(h2) - uf * 2.0 + at(-h2)) / (h2 * h2);
            let tol2 = bound(4, h2) * (h2 * h2 / 12.0) + Vector3::repeat(16.0 * eps * scale / (h2 * h2));
            for i in 0..3 {
                prop_assert!((out.u_dot[i] - fd1[i]).abs() <= tol1[i],
                    "u_dot[{i}] = {} vs {} (tol {})", out.u_dot[i], fd1[i], tol1[i]);
                prop_assert!((out.u_ddot[i] - fd2[i]).abs() <= tol2[i],
                    "u_ddot[{i}] = {} vs {} (tol {})", out.u_ddot[i], fd2[i], tol2[i]);
            }
        }

        /// Filter states started in M_p 𝔹∞ stay there (Theorem 1 proof; Fig. 2c).
        #[test]
        fn filters_stay_in_the_saturation_box(pe in v3(), ve in v3()) {
            let g = gains();
            let mut filt = FilterState::zero();
            let zero = Vector3::zeros();
            for _ in 0..500 {
                let out = g.evaluate(
                    None,
                    &(pe * 10.0),
                    &(ve * 3.0),
                    &filt,
                    &zero,
                    &zero,
                    &zero,
                    9.81,
                );
                filt = g.propagate(&filt, &out.ubar_p, 0.01);
                prop_assert!(filt.u_f.amax() <= g.saturation);
                prop_assert!(filt.u_s.amax() <= g.saturation);
            }
        }
    }
}
