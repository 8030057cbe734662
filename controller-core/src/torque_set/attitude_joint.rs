//! Tilt priority's attitude terms bounded together: a certified support function of the set
//! the radial MRP term, the trace term and the turn-over term reach *at one attitude*, instead
//! of the Minkowski sum of their three sets (docs/torque-set.md, "The attitude terms bounded
//! together").
//!
//! **Why.** The certified set charges each attitude term at its own largest value along a
//! direction: the radial term's ball, the trace term's ball and disks, the turn-over term's
//! box. The three peak at different attitudes (the trace term vanishes at a horizontal half
//! turn, where the turn-over term peaks), so the sum charges a rotor pair far more than the law
//! ever asks at once (docs/results.md, "The attitude terms charged apart": 0.687 N charged
//! against 0.412 N sampled on the x500).
//!
//! **The reduction to a plane.** With `g₁ = g₂` (tilt priority's designs) the three terms at
//! `ϑ̃` are equivariant under rotations `Q` about body z: `A(Qϑ̃) = Q A(ϑ̃)` (the trace weights
//! commute with `Q`, `R(Qϑ̃) = Q R(ϑ̃) Qᵀ`, and the turn-over term depends on `ϑ̃₁² + ϑ̃₂²`).
//! So `sup_{|ϑ̃| ≤ 1+δ} cᵀA(ϑ̃) = sup |c_xy| |A_xy(x, 0, z)| + c_z A_z(x, 0, z)` over the half
//! disk `x ≥ 0, x² + z² ≤ (1+δ)²`, and by the symmetry `z → −z` (which keeps `|A_xy|` and flips
//! `A_z`) over its quarter `z ≥ 0` with `|c_z|`. There, with `u = x² + z²`,
//! `w(u) = 4(1 − u)/(1 + u)²` (`sin θ / |ϑ̃|`), `f(u) = (1 + u)/4 · M_ϑ k_ϑ/√(M_ϑ² + k_ϑ²u)`,
//! `G = diag(g, g, g + Δ)` and `b` the turn-over share at `ρ² = x²`:
//!
//! - `A_x = −x [f(u) + (g + Δ/2) w(u) + ½ M_t b (1 + x² − z²)]`,
//! - `A_y = x z [4Δ/(1 + u)² + M_t b]`,
//! - `A_z = −z [f(u) + g w(u) + M_t b x²]`.
//!
//! **The bound.** The quarter disk is covered by a grid of [`JOINT_SLABS`]² boxes (those that
//! meet it); on each box interval arithmetic encloses the brackets above (each operation is
//! inclusion-monotone), which gives `p ≥ |A_xy|` and `q ≥ |A_z|` over the box. The support of the
//! plane set `{(|A_xy|, |A_z|)}` along each of the [`JOINT_DIRECTIONS`] + 1 directions
//! `w_j = (j/K, 1 − j/K)` is then at most the largest `w_jᵀ(p, q)` over the boxes, and along any
//! `(|c_xy|, |c_z|)` between `w_j` and `w_{j+1}` at most the same combination of the two values
//! (a support function is sublinear). The values are raised by a rounding allowance of
//! `2⁸ ε` relative (ε the scalar's machine epsilon), so `f32` on the board and `f64` on the host
//! each give an upper bound in their own arithmetic. No search: the same deterministic grid on
//! the host and at the board's boot, so the gate repeats it.
//!
//! Source: extension of Theorem 2 (docs/torque-set.md); the terms are those of
//! docs/tilt-priority.md and docs/turn-over.md.

use nalgebra::Vector3;

use crate::scalar::{lit, Scalar};
use crate::tilt_priority::TiltPriorityGains;
use crate::turn_over::TurnOver;

/// `K`: the directions of the plane `(|c_xy|, |c_z|)` at which the bound is stored are
/// `w_j = (j/K, 1 − j/K)`, `j = 0..=K`.
pub const JOINT_DIRECTIONS: usize = 16;

/// Grid boxes per axis of the quarter disk's square `[0, 1 + δ]²` in the certified bound
/// (the gate's): a box's enclosure over-estimates by about its width times the terms' slope.
pub const JOINT_SLABS: usize = 128;

/// Blocks per axis the grid is pruned by: a block whose enclosure stays below the values
/// stored so far (the law at the blocks' centres, then boxes' enclosures) in every stored
/// direction is not split further; one that could raise one is split in four, down to the
/// grid's boxes.
pub const JOINT_BLOCKS: usize = 16;

/// The certified joint support of tilt priority's attitude terms (module documentation),
/// stored at the directions `w_j` of the plane `(|c_xy|, |c_z|)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeJoint<T: Scalar> {
    /// `h_j ≥ sup_ϑ̃ w_jᵀ(|A_xy(ϑ̃)|, |A_z(ϑ̃)|)` [N m], `j = 0..=K`: `j = 0` is body z alone,
    /// `j = K` the body's horizontal plane.
    pub support_values: [T; JOINT_DIRECTIONS + 1],
    /// The turn-over term's per-axis bounds [N m] ([`crate::TurnOver::bounds`]) that the
    /// certified set's box holds beside the damping levels: the part of the box the joint
    /// bound replaces (zero when the term is off).
    pub turn_over_box: Vector3<T>,
}

/// A closed interval `[lo, hi]` with inclusion-monotone operations (round to nearest; the
/// rounding allowance is added once at the end).
#[derive(Clone, Copy)]
struct Span<T: Scalar> {
    lo: T,
    hi: T,
}

impl<T: Scalar> Span<T> {
    fn new(lo: T, hi: T) -> Self {
        Self { lo, hi }
    }

    fn add(self, o: Self) -> Self {
        Self::new(self.lo + o.lo, self.hi + o.hi)
    }

    /// `c · self` for `c ≥ 0`.
    fn scale(self, c: T) -> Self {
        Self::new(c * self.lo, c * self.hi)
    }

    /// `c · self` for any `c`.
    fn scale_signed(self, c: T) -> Self {
        if c >= T::zero() {
            self.scale(c)
        } else {
            Self::new(c * self.hi, c * self.lo)
        }
    }

    fn mul(self, o: Self) -> Self {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        let (mut lo, mut hi) = (p[0], p[0]);
        for v in &p[1..] {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        Self::new(lo, hi)
    }

    /// The largest `|v|` over the span.
    fn magnitude(self) -> T {
        self.lo.abs().max(self.hi.abs())
    }
}

/// The attitude terms' gains the bound reads.
struct Terms<T: Scalar> {
    /// `M_ϑ k_ϑ / 4` [N m].
    radial: T,
    /// `M_ϑ²`, `k_ϑ²`.
    m2: T,
    k2: T,
    /// `g = g₁ = g₂`, `Δ = g₃ − g` [N m].
    g: T,
    delta: T,
    /// `M_t` [N m] (zero: the term off).
    turn_over: T,
    /// The turn-over term itself, whose share `b` the brackets read (`None`: off).
    turn_over_term: Option<TurnOver<T>>,
}

impl<T: Scalar> Terms<T> {
    /// The terms of tilt priority's gains `tilt` (read with `g = g₁`), the radial MRP term's
    /// level `M_ϑ` and stiffness `k_ϑ` [N m].
    fn new(tilt: &TiltPriorityGains<T>, mrp_saturation: T, k_mrp: T) -> Self {
        let g = tilt.trace_weights;
        Self {
            radial: mrp_saturation * k_mrp * lit(0.25),
            m2: mrp_saturation * mrp_saturation,
            k2: k_mrp * k_mrp,
            g: g.x,
            delta: g.z - g.x,
            turn_over: tilt.turn_over.map_or(T::zero(), |t| t.level),
            turn_over_term: tilt.turn_over,
        }
    }

    /// `b(s)` of the turn-over term (`s = ρ²`): the law's own ([`TurnOver`]), zero when off.
    /// Nondecreasing in `s`, so a span of `s` maps to the span of its ends' shares.
    fn share(&self, s: T) -> T {
        self.turn_over_term.map_or(T::zero(), |t| t.share(s))
    }

    /// `(p, q)` with `p ≥ |A_xy|` and `q ≥ |A_z|` over the box `[x0, x1] × [z0, z1]`
    /// (`0 ≤ x0 ≤ x1`, `0 ≤ z0 ≤ z1`).
    /// The box may reach beyond the flow set's disk `u ≤ t2`: only its part inside counts, so
    /// `x`, `z` and `u` are clipped to it (each clip keeps every point of the box in the disk).
    fn box_extremes(&self, (x0, x1): (T, T), (z0, z1): (T, T), t2: T) -> (T, T) {
        let one = T::one();
        let (xx0, zz0) = (x0 * x0, z0 * z0);
        let clip = |v: T, room: T| {
            if v * v > room {
                (room, room.sqrt_ieee())
            } else {
                (v * v, v)
            }
        };
        let (xx1, x1) = clip(x1, t2 - zz0);
        let (zz1, z1) = clip(z1, t2 - xx0);
        let (u0, u1) = (xx0 + zz0, (xx1 + zz1).min(t2));
        // f(u): increasing numerator over an increasing denominator.
        let f = Span::new(
            (one + u0) * self.radial / (self.m2 + self.k2 * u1).sqrt_ieee(),
            (one + u1) * self.radial / (self.m2 + self.k2 * u0).sqrt_ieee(),
        );
        let inv = Span::new(
            one / ((one + u1) * (one + u1)),
            one / ((one + u0) * (one + u0)),
        );
        let w = Span::new(one - u1, one - u0).mul(inv).scale(lit(4.0));
        let b = Span::new(self.share(xx0), self.share(xx1));
        // b ≥ 0 and x² ≥ 0: the product's ends are the ends' products.
        let b_xx = Span::new(b.lo * xx0, b.hi * xx1).scale(self.turn_over);
        let half = lit::<T>(0.5);
        // A_x's bracket: f + (g + Δ/2) w + ½ M_t b (1 + x² − z²).
        let tilt_trace = self.g + half * self.delta;
        let bx = f.add(w.scale(tilt_trace)).add(
            b.scale(half * self.turn_over)
                .mul(Span::new(one + xx0 - zz1, one + xx1 - zz0)),
        );
        // A_y's bracket: 4Δ/(1 + u)² + M_t b.
        let by = inv
            .scale_signed(lit::<T>(4.0) * self.delta)
            .add(b.scale(self.turn_over));
        // A_z's bracket: f + g w + M_t b x².
        let bz = f.add(w.scale(self.g)).add(b_xx);
        let ax = x1 * bx.magnitude();
        let ay = x1 * z1 * by.magnitude();
        let az = z1 * bz.magnitude();
        ((ax * ax + ay * ay).sqrt_ieee(), az)
    }
}

/// The grid of boxes over the quarter disk and the values stored so far: a quadtree over
/// blocks of grid boxes, each split only where its enclosure could raise a stored value.
struct Sweep<'a, T: Scalar> {
    terms: &'a Terms<T>,
    /// `1 + δ` and its square.
    t: T,
    t2: T,
    /// Grid boxes per axis, and the side of a top-level block in boxes (a power of two, or
    /// 1 when the grid is not split into [`JOINT_BLOCKS`] blocks of one).
    slabs: usize,
    block: usize,
    /// `t/slabs`: a box's side.
    step: T,
    /// `j/K` for the stored directions.
    shares: [T; JOINT_DIRECTIONS + 1],
    /// `h_j` so far: values of the law itself, or enclosures of boxes, so each is at most
    /// the final bound and every box skipped stays below it.
    values: [T; JOINT_DIRECTIONS + 1],
}

impl<'a, T: Scalar> Sweep<'a, T> {
    fn new(terms: &'a Terms<T>, t: T, slabs: usize) -> Self {
        let per_block = slabs / JOINT_BLOCKS;
        let block = if slabs.is_multiple_of(JOINT_BLOCKS) && per_block.is_power_of_two() {
            per_block
        } else {
            1
        };
        let k = lit::<T>(JOINT_DIRECTIONS as f64);
        Self {
            terms,
            t,
            t2: t * t,
            slabs,
            block,
            step: t / lit::<T>(slabs as f64),
            shares: core::array::from_fn(|j| lit::<T>(j as f64) / k),
            values: [T::zero(); JOINT_DIRECTIONS + 1],
        }
    }

    /// The grid's `i`-th edge `i t/slabs` (the last one `t` exactly).
    fn edge(&self, i: usize) -> T {
        if i == self.slabs {
            self.t
        } else {
            self.step * lit::<T>(i as f64)
        }
    }

    fn raise(&mut self, (p, q): (T, T)) {
        for (v, s) in self.values.iter_mut().zip(&self.shares) {
            let h = *s * p + (T::one() - *s) * q;
            if h > *v {
                *v = h;
            }
        }
    }

    fn exceeds(&self, (p, q): (T, T)) -> bool {
        self.values
            .iter()
            .zip(&self.shares)
            .any(|(v, s)| *s * p + (T::one() - *s) * q > *v)
    }

    /// The law at each top-level block's centre inside the disk first (a point box is exact),
    /// then every block, split where it could raise a value.
    fn bound(&mut self) {
        let blocks = self.slabs / self.block;
        let half = lit::<T>(0.5);
        for i in 0..blocks {
            let x = (self.edge(i * self.block) + self.edge((i + 1) * self.block)) * half;
            for l in 0..blocks {
                let z = (self.edge(l * self.block) + self.edge((l + 1) * self.block)) * half;
                if x * x + z * z <= self.t2 {
                    let point = self.terms.box_extremes((x, x), (z, z), self.t2);
                    self.raise(point);
                }
            }
        }
        for i in 0..blocks {
            for l in 0..blocks {
                self.split(i * self.block, l * self.block, self.block);
            }
        }
    }

    /// The block of `size × size` grid boxes from box `(i, l)`: skipped beyond the disk or
    /// where its enclosure raises no value, stored when it is one box, else split in four.
    fn split(&mut self, i: usize, l: usize, size: usize) {
        let x = (self.edge(i), self.edge(i + size));
        let z = (self.edge(l), self.edge(l + size));
        if x.0 * x.0 + z.0 * z.0 > self.t2 {
            return;
        }
        let enclosure = self.terms.box_extremes(x, z, self.t2);
        if !self.exceeds(enclosure) {
            return;
        }
        if size == 1 {
            self.raise(enclosure);
            return;
        }
        let h = size / 2;
        for (a, b) in [(i, l), (i + h, l), (i, l + h), (i + h, l + h)] {
            self.split(a, b, h);
        }
    }
}

impl<T: Scalar> AttitudeJoint<T> {
    /// The bound for tilt priority's gains `tilt`, the radial MRP term's level `M_ϑ`
    /// (`mrp_saturation` [N m]) and stiffness `k_ϑ` (`k_mrp` [N m]) and the hysteresis `δ`,
    /// over `slabs`² grid boxes ([`JOINT_SLABS`] for the certified set; fewer give a looser
    /// bound, never a smaller one: a coarser box contains the finer ones when `slabs` divides).
    /// `None` when the reduction does not apply: `g₁ ≠ g₂`, a non-finite or negative input, or
    /// `slabs = 0`. Source: module documentation.
    pub fn of(
        tilt: &TiltPriorityGains<T>,
        mrp_saturation: T,
        k_mrp: T,
        hysteresis: T,
        slabs: usize,
    ) -> Option<Self> {
        let g = tilt.trace_weights;
        let (level, onset) = tilt
            .turn_over
            .map_or((T::zero(), T::zero()), |t| (t.level, t.onset));
        let inputs = [g.x, g.z, mrp_saturation, k_mrp, hysteresis, level, onset];
        if g.x != g.y || slabs == 0 || inputs.iter().any(|v| !(v.is_finite() && *v >= T::zero())) {
            return None;
        }
        let terms = Terms::new(tilt, mrp_saturation, k_mrp);
        let mut sweep = Sweep::new(&terms, T::one() + hysteresis, slabs);
        sweep.bound();
        let values = sweep.values;
        let allowance = T::one() + lit::<T>(256.0) * T::default_epsilon();
        Some(Self {
            support_values: values.map(|v| v * allowance),
            turn_over_box: tilt.turn_over_bounds(hysteresis),
        })
    }

    /// An upper bound of `sup_ϑ̃ cᵀA(ϑ̃)` over the flow set for any direction `c` (units of `c`
    /// times N m): with `(a, b) = (|c_xy|, |c_z|)`, `λ = a/(a + b)` between `j/K` and
    /// `(j + 1)/K`, `(a + b)((j + 1 − λK) h_j + (λK − j) h_{j+1})`. Zero at `c = 0`. No
    /// errors. Source: module documentation (sublinearity of the support function).
    pub fn support(&self, c: &Vector3<T>) -> T {
        let a = (c.x * c.x + c.y * c.y).sqrt_ieee();
        let b = c.z.abs();
        let sum = a + b;
        // `c = 0`; a NaN in `c` runs on to a NaN bound, which no fit accepts.
        if sum == T::zero() {
            return T::zero();
        }
        let position = a / sum * lit::<T>(JOINT_DIRECTIONS as f64);
        let mut j = 0;
        while j + 1 < JOINT_DIRECTIONS && position > lit::<T>((j + 1) as f64) {
            j += 1;
        }
        let upper = position - lit::<T>(j as f64);
        let lower = T::one() - upper;
        sum * (lower * self.support_values[j] + upper * self.support_values[j + 1])
    }
}

#[cfg(test)]
mod tests;
