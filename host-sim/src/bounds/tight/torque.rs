//! Per-axis torque bound from the bounds on `ω_d`, `ω̇_d` and a search over the MRP error.
//!
//! The law (attitude_control.rs, Section V) is
//! `τ = −(1 + |ϑ̃|²)/4 · s_ϑ(k_ϑ ϑ̃) − s_ω(k_ω ω̃) − τ_c`,
//! `τ_c = (J w) × w − J ẇ`, `w = R̃ᵀω_d`, `ẇ = R̃ᵀω̇_d`, `R̃ = R(ϑ̃)` (rotation_from_mrp), with
//! `s(x) = M x/√(M² + |x|²)`. For axis `i` (`j, k` the other two), by the triangle inequality:
//! - `|s_ω,i| ≤ |s_ω| < M_ω`;
//! - `|((J w) × w)_i| = |J_jj − J_kk| |w_j w_k| ≤ ½|J_jj − J_kk| |w|² ≤ ½|J_jj − J_kk| W²`
//!   (`|w| = |ω_d|` since `R̃` is a rotation; `W` bounds `|ω_d|`);
//! - `(J ẇ)_i = J_ii (R̃ e_i)·ω̇_d`; with `q = R̃ e_i` (a unit vector, column `i` of `R(ϑ̃)`),
//!   Cauchy–Schwarz on the horizontal part gives
//!   `|q·ω̇_d| ≤ |(q₁, q₂)| H₁₂ + |q₃| H₃ = √(1 − q₃²) H₁₂ + |q₃| H₃`, with `H₁₂`, `H₃` bounds of
//!   `|(ω̇_d1, ω̇_d2)|` and `|ω̇_d3|`, and `|q·ω̇_d| ≤ |ω̇_d| ≤ A` (the smaller is used);
//! - `|(1 + |ϑ̃|²)/4 · s_ϑ,i| = (1 + |ϑ̃|²)/4 · M_ϑ k_ϑ |ϑ̃_i| / √(M_ϑ² + k_ϑ²|ϑ̃|²)`.
//!
//! So `|τ_i| ≤ M_ω + sup_{|ϑ̃| ≤ 1+δ} φ_i(ϑ̃) + ½|J_jj − J_kk| W²` with
//! `φ_i(ϑ) = (1 + |ϑ|²)/4 · M_ϑ k_ϑ |ϑ_i| / √(M_ϑ² + k_ϑ²|ϑ|²) + J_ii(√(1 − q₃²) H₁₂ + |q₃| H₃)`,
//! `q₃ = R(ϑ)₃ᵢ = δ₃ᵢ + (8(ϑ₃ϑᵢ − |ϑ|²δ₃ᵢ) + 4(1 − |ϑ|²)[ϑ]ₓ,₃ᵢ)/(1 + |ϑ|²)²`. The supremum of
//! `φ_i` over the ball is bounded by a 3-D branch and bound on the natural interval extension
//! ([`super::branch_bound`]), with `|ϑ|²` intersected with `[0, (1+δ)²]` (only points of the
//! ball count) and boxes outside the ball dropped. The Theorem 2 bound is the same sum with
//! `φ_i ≤ (1 + (1+δ)²)M_ϑ/4 + J_ii U_ω̇d` and `W = U_ωd`.

use controller_core::attitude_control::AttitudeGains;

use super::branch_bound::{best_first, Node, Outcome};
use super::interval::{next_up, Interval};

/// What `φ_i` needs: the attitude gains, `1 + δ`, `J_ii` and the bounds `H₁₂`, `H₃`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeTerm {
    /// Body axis `i` (0, 1, 2).
    pub axis: usize,
    /// Attitude gains (`k_ϑ`, `M_ϑ` are used).
    pub gains: AttitudeGains<f64>,
    /// Radius of the MRP ball, `1 + δ`.
    pub radius: f64,
    /// `J_ii` [kg m²].
    pub inertia: f64,
    /// Bound `H₁₂` of `|(ω̇_d1, ω̇_d2)|` [rad/s²].
    pub horizontal_acceleration: f64,
    /// Bound `H₃` of `|ω̇_d3|` [rad/s²].
    pub yaw_acceleration: f64,
    /// Bound `A` of `|ω̇_d|` [rad/s²] (`f64::INFINITY` for none): `|q·ω̇_d| ≤ A` too, which caps
    /// `√(1 − q₃²) H₁₂ + |q₃| H₃` where `H₁₂` and `H₃` are not reached together.
    pub total_acceleration: f64,
    /// Tilt priority's trace weights `(g₁, g₂, g₃)` [N m] (controller-core's `tilt_priority`);
    /// all zero for the paper's law. Nonzero, the attitude term is
    /// `|(1 + |ϑ|²)/4 · s_ϑ,i + ½ vee(G R − RᵀG)_i| + J_ii(…)`, with
    /// `½ vee(G R − RᵀG)_i = (4(g_k − g_j)ϑ_jϑ_k + 2(g_j + g_k)(1 − |ϑ|²)ϑ_i)/(1 + |ϑ|²)²` for
    /// `(i, j, k)` cyclic (from `R(ϑ)`'s entries).
    pub trace_weights: [f64; 3],
}

impl AttitudeTerm {
    /// Encloses `φ_i` over the points of the box `t` inside the ball; `None` if there are none.
    pub fn enclosure(&self, t: &[Interval; 3]) -> Option<Interval> {
        let p = Interval::point;
        let r2 = p(self.radius).sqr();
        let n2 = t[0].sqr() + t[1].sqr() + t[2].sqr();
        if n2.lo > r2.hi {
            return None;
        }
        let n2 = Interval::new(n2.lo, n2.hi.min(r2.hi));
        let one = p(1.0);
        let (m, k) = (p(self.gains.mrp_saturation), p(self.gains.k_mrp));
        let shape = (one + n2) * p(0.25);
        let saturated = m * k * t[self.axis].abs() / (m.sqr() + k.sqr() * n2).sqrt();
        let den = (one + n2).sqr();
        let q3 = match self.axis {
            0 => (p(8.0) * t[2] * t[0] - p(4.0) * (one - n2) * t[1]) / den,
            1 => (p(8.0) * t[2] * t[1] + p(4.0) * (one - n2) * t[0]) / den,
            _ => one - p(8.0) * (t[0].sqr() + t[1].sqr()) / den,
        };
        // q₃ is a component of a unit vector.
        let q3 = Interval::new(q3.lo.max(-1.0), q3.hi.min(1.0));
        let horizontal = (one - q3.sqr()).sqrt();
        let projected =
            horizontal * p(self.horizontal_acceleration) + q3.abs() * p(self.yaw_acceleration);
        let a = self.total_acceleration;
        let projected = Interval::new(projected.lo.min(a), projected.hi.min(a));
        let feedback = if self.trace_weights == [0.0; 3] {
            shape * saturated
        } else {
            // (i, next, prev) cyclic: the formula's (i, j, k); `k` names the MRP gain here.
            let (i, next, prev) = (self.axis, (self.axis + 1) % 3, (self.axis + 2) % 3);
            let g = self.trace_weights;
            let trace = (p(4.0) * (p(g[prev]) - p(g[next])) * t[next] * t[prev]
                + p(2.0) * (p(g[next]) + p(g[prev])) * (one - n2) * t[i])
                / den;
            let signed = m * k * t[i] / (m.sqr() + k.sqr() * n2).sqrt();
            (shape * signed + trace).abs()
        };
        Some(feedback + p(self.inertia) * projected)
    }

    fn node(&self, region: [Interval; 3]) -> Node<3> {
        let Some(value) = self.enclosure(&region) else {
            return Node {
                upper: f64::NEG_INFINITY,
                region,
                tag: 0,
                split: None,
                lower: f64::NAN,
            };
        };
        let c = region.map(|x| x.mid());
        let norm = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        // A point of the ball: the centre, or the centre pulled onto the sphere.
        let shrink = if norm > self.radius {
            0.999_999 * self.radius / norm
        } else {
            1.0
        };
        let lower = self
            .enclosure(&c.map(|x| Interval::point(x * shrink)))
            .map_or(f64::NAN, |v| v.lo);
        let split = (0..3).max_by(|&a, &b| region[a].width().total_cmp(&region[b].width()));
        Node {
            upper: value.hi,
            region,
            tag: 0,
            split,
            lower,
        }
    }

    /// Upper bound of `sup φ_i` over the ball `|ϑ| ≤ 1 + δ` by branch and bound.
    ///
    /// Symmetries shrink the box: `φ₃` depends on `|ϑ₃|`, `ϑ₁² + ϑ₂²` and `|ϑ|²` only, so the
    /// octant `ϑ ≥ 0` suffices; for `i = 1` the flips `(−ϑ₁, −ϑ₂, ϑ₃)` and `(ϑ₁, −ϑ₂, −ϑ₃)`, for
    /// `i = 2` the flips `(−ϑ₁, ϑ₂, −ϑ₃)` and `(ϑ₁, −ϑ₂, −ϑ₃)` change at most the sign of `q₃` and
    /// keep `|ϑ_i|`, `|ϑ|²`, so `ϑ₁, ϑ₂ ≥ 0` suffices.
    pub fn maximise(&self, relative_gap: f64, max_boxes: usize) -> Outcome {
        let r = next_up(self.radius);
        let half = Interval::new(0.0, r);
        let third = if self.axis == 2 {
            half
        } else {
            Interval::symmetric(r)
        };
        // With trace weights the yaw term has `ϑ₁ϑ₂ + c ϑ₃`: the flips of `(ϑ₁, ϑ₂)` and of
        // `(ϑ₁, ϑ₃)` keep its modulus (and the rest), so `ϑ₁, ϑ₂ ≥ 0` suffices, not the octant.
        let start = if self.axis == 2 && self.trace_weights != [0.0; 3] {
            [half, half, Interval::symmetric(r)]
        } else {
            [half, half, third]
        };
        best_first(
            &[(start, 0)],
            |region, _| self.node(region),
            |x| x,
            relative_gap,
            max_boxes,
        )
    }
}

/// `M_ω + φ + ½|J_jj − J_kk| W²` [N m], rounded up: the per-axis torque bound from the bound
/// `φ` of the attitude term, the inertia diagonal and the bound `W` of `|ω_d|`.
pub fn torque_bound(
    axis: usize,
    omega_saturation: f64,
    phi: f64,
    inertia: [f64; 3],
    w: f64,
) -> f64 {
    let p = Interval::point;
    let (j, k) = (inertia[(axis + 1) % 3], inertia[(axis + 2) % 3]);
    (p(omega_saturation) + p(phi) + p(0.5) * (p(j) - p(k)).abs() * p(w).sqr()).hi
}
