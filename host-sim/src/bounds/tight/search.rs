//! Best-first branch and bound for the suprema of `|ω_d|`, `|ω̇_d|`, `|(ω̇_d1, ω̇_d2)|`, `|ω̇_d3|`.
//!
//! The search splits the eight variables `x = (u, u̇, ψ, ψ̇)` of
//! [`super::confining_set::ConfiningSet::split`]. `ω̇_d` is affine in `y = (ü, ψ̈)` for fixed `x`
//! (`ρ̈`, `ϖ̈`, `ϋ` are affine in `ü`, `ν̈_d`, and `ν̈_d` in `ψ̈`; in the closed form of
//! [`super::desired_rates`], `β` is linear in `ü` and `ψ̈` appears once, in `ω̇_d3`), and `ω_d`
//! does not depend on `y`; a squared Euclidean norm of an affine function is convex, so for
//! every `x` its maximum over the `y` box is reached at one of the 16 vertices (8 for
//! `|(ω̇_d1, ω̇_d2)|`, which does not depend on `ψ̈`). The search therefore maximises
//! `F_v(x) = |selection of ω̇_d(x, y_v)|²` for each vertex `v` separately (a node is a box of `x`
//! and a vertex), and the supremum is the largest over the vertices. For `|ω_d|` the same
//! argument applies to `z = (u̇, ψ̇)`, in which `ω_d` is linear for fixed `(u, ψ)`
//! (`ω_d = (−α₂, α₁, (ψ̇ρ₃/c − α₁σ)/c)`, `α` linear in `u̇`): the roots are the 16 vertices of the
//! `z` box and only `(u, ψ)` is split.
//!
//! Per node (box `X`, centre `c`, radii `r_j`):
//! - forward-mode interval differentiation ([`super::gradient`]) encloses `F_v(X)` and
//!   `∂_j F_v(X)`;
//! - **monotonicity**: if an enclosure `∂_j F_v(X)` excludes 0, `F_v` is monotone in `x_j` on `X`
//!   for every value of the other variables, so the supremum over `X` is the supremum over the
//!   face where `x_j` is at the increasing end; `X_j` is replaced by that end (and `X` is
//!   re-evaluated);
//! - **upper bound**: the smallest of the natural enclosure's upper end, the mean-value form
//!   `F_v(c) + Σ_j |∂_j F_v(X)| r_j` (mean value theorem along the segment from `c`, which lies in
//!   `X`), and `Σ_i max(v_i²)` over the per-component mean-value forms
//!   `v_i(X) ⊆ v_i(c) + Σ_j ∂_j v_i(X)[−r_j, r_j]` of the selected components `v_i`, all rounded
//!   up; `F_v(c)`, `v_i(c)` are interval evaluations at the point `c`;
//! - **lower value**: `F_v` in `f64` at `c` and at the vertex of `X` the gradient points to
//!   (only to decide when to stop; never part of the bound).
//!
//! The node with the largest upper bound is split at the midpoint of the variable with the
//! largest `|∂_j F_v(X)| r_j` (its share of the mean-value form's width). The search stops when
//! `(upper − lower)/upper ≤` the requested gap, or after the box budget; either way it returns
//! the largest upper bound of all nodes not split (those in the queue, those discarded because
//! their upper bound was below the best lower value, those that could not be split), which
//! bounds the supremum over every box of the initial cover.

use super::arith::Arith;
use super::branch_bound::{best_first, Node, Outcome};
use super::confining_set::{ConfiningSet, SPLIT_DIM};
use super::desired_rates::{desired_rates, Heading, Rates};
use super::gradient::Gradient;
use super::interval::{next_down, next_up, Interval};

/// The quantity a search bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// `|ω_d|` [rad/s].
    AngularVelocity,
    /// `|ω̇_d|` [rad/s²].
    AngularAcceleration,
    /// `|(ω̇_d1, ω̇_d2)|` [rad/s²] (roll and pitch of the desired body frame).
    HorizontalAcceleration,
    /// `|ω̇_d3|` [rad/s²] (yaw).
    YawAcceleration,
}

impl Quantity {
    /// Whether the quantity is built from `ω̇_d` (else from `ω_d`), and which components.
    fn selection(self) -> (bool, core::ops::Range<usize>) {
        match self {
            Self::AngularVelocity => (false, 0..3),
            Self::AngularAcceleration => (true, 0..3),
            Self::HorizontalAcceleration => (true, 0..2),
            Self::YawAcceleration => (true, 2..3),
        }
    }
}

/// The components of `ω_d` or `ω̇_d` that the quantity selects (the first `count` entries),
/// at `x = (u, u̇, ψ, ψ̇)` with `(cos ψ, sin ψ)` given and `y = (ü, ψ̈)`.
fn components<T: Arith>(
    x: &[T; SPLIT_DIM],
    heading: (T, T),
    y: &[f64; 4],
    q: Quantity,
) -> ([T; 3], usize) {
    let u = [x[0], x[1], x[2]];
    let u_dot = [x[3], x[4], x[5]];
    let u_ddot = [y[0], y[1], y[2]].map(T::constant);
    let h = Heading {
        cos: heading.0,
        sin: heading.1,
        rate: x[7],
        acceleration: T::constant(y[3]),
    };
    select(&desired_rates(&u, &u_dot, &u_ddot, &h), q)
}

/// The components of `ω_d` or `ω̇_d` in `rates` that `q` selects (the first `count` entries).
pub(super) fn select<T: Arith>(rates: &Rates<T>, q: Quantity) -> ([T; 3], usize) {
    let (accel, range) = q.selection();
    let v = if accel {
        rates.angular_acceleration
    } else {
        rates.angular_velocity
    };
    let mut out = [T::constant(0.0); 3];
    for (o, x) in out.iter_mut().zip(&v[range.clone()]) {
        *o = *x;
    }
    (out, range.len())
}

/// The vertex of `region` that the gradient enclosure `partial` points to (the upper end where
/// its midpoint is `≥ 0`): a point at which to look for a large value, for stopping only.
pub(super) fn gradient_vertex<const N: usize>(
    region: &[Interval; N],
    partial: &[Interval; N],
) -> [f64; N] {
    core::array::from_fn(|j| {
        if partial[j].mid() >= 0.0 {
            region[j].hi
        } else {
            region[j].lo
        }
    })
}

/// The sum of squares of the first `count` entries.
pub(super) fn sum_of_squares<T: Arith>(v: &[T; 3], count: usize) -> T {
    let mut parts = v[..count].iter().map(|x| x.sqr());
    let first = parts.next().unwrap_or_else(|| T::constant(0.0));
    parts.fold(first, |sum, x| sum + x)
}

/// The squared quantity `F_v(x)`.
fn squared<T: Arith>(x: &[T; SPLIT_DIM], heading: (T, T), y: &[f64; 4], q: Quantity) -> T {
    let (v, count) = components(x, heading, y, q);
    sum_of_squares(&v, count)
}

/// `F_v` at a point, in `f64`.
pub fn point_value(x: &[f64; SPLIT_DIM], y: &[f64; 4], q: Quantity) -> f64 {
    squared(x, (x[6].cos(), x[6].sin()), y, q).sqrt()
}

/// Interval enclosure of `F_v` over a box (natural extension).
pub fn enclosure(region: &[Interval; SPLIT_DIM], y: &[f64; 4], q: Quantity) -> Interval {
    squared(region, region[6].cos_sin(), y, q).sqrt()
}

/// The selected components and `F_v`, with their gradients, over a box.
fn gradient_enclosure(
    region: &[Interval; SPLIT_DIM],
    y: &[f64; 4],
    q: Quantity,
) -> ([Gradient<SPLIT_DIM>; 3], usize, Gradient<SPLIT_DIM>) {
    let x: [Gradient<SPLIT_DIM>; SPLIT_DIM] =
        core::array::from_fn(|j| Gradient::variable(region[j], j));
    let (v, count) = components(&x, x[6].cos_sin(), y, q);
    let f = sum_of_squares(&v, count);
    (v, count, f)
}

/// Bounds `F_v` over `region` (module documentation).
fn bound(
    mut region: [Interval; SPLIT_DIM],
    y: &[f64; 4],
    vertex: usize,
    q: Quantity,
) -> Node<SPLIT_DIM> {
    let (mut v, count, mut g) = gradient_enclosure(&region, y, q);
    for _ in 0..SPLIT_DIM {
        let mut collapsed = false;
        for (x, d) in region.iter_mut().zip(g.partial) {
            if x.lo < x.hi && (d.lo > 0.0 || d.hi < 0.0) {
                *x = Interval::point(if d.lo > 0.0 { x.hi } else { x.lo });
                collapsed = true;
            }
        }
        if !collapsed {
            break;
        }
        (v, _, g) = gradient_enclosure(&region, y, q);
    }
    let c = region.map(|x| x.mid());
    let radius = region.map(|x| {
        let m = x.mid();
        if x.lo < x.hi {
            next_up((m - x.lo).max(x.hi - m))
        } else {
            0.0
        }
    });
    let point = c.map(Interval::point);
    let (at_centre, _) = components(&point, point[6].cos_sin(), y, q);
    let mut mean_value = sum_of_squares(&at_centre, count).hi;
    // The mean-value form per component, then the norm of the resulting box: often tighter
    // than the form of the squared norm, whose gradient multiplies two wide enclosures.
    let mut per_component = Interval::point(0.0);
    for (vi, ci) in v[..count].iter().zip(&at_centre[..count]) {
        let mut spread = 0.0;
        for (r, d) in radius.iter().zip(vi.partial) {
            if *r > 0.0 {
                spread = next_up(spread + next_up(d.mag() * r));
            }
        }
        let form = Interval::new(next_down(ci.lo - spread), next_up(ci.hi + spread));
        let enclosed = Interval::new(form.lo.max(vi.value.lo), form.hi.min(vi.value.hi));
        per_component = per_component + enclosed.sqr();
    }
    let mut split = None;
    let mut widest = 0.0;
    for (j, (r, d)) in radius.iter().zip(g.partial).enumerate() {
        if *r > 0.0 {
            let share = next_up(d.mag() * r);
            mean_value = next_up(mean_value + share);
            if share > widest || (split.is_none() && share.is_nan()) {
                widest = share;
                split = Some(j);
            }
        }
    }
    let upper_sq = g.value.hi.min(mean_value).min(per_component.hi);
    let upper_sq = if upper_sq.is_nan() {
        f64::INFINITY
    } else {
        upper_sq
    };
    let toward = gradient_vertex(&region, &g.partial);
    let at = |x: &[f64; SPLIT_DIM]| squared(x, (x[6].cos(), x[6].sin()), y, q);
    let lower_sq = at(&c).max(at(&toward));
    Node {
        upper: upper_sq,
        region,
        tag: vertex,
        split,
        lower: lower_sq,
    }
}

/// The vertices of the `y = (ü, ψ̈)` box that the quantity needs.
fn vertices(set: &ConfiningSet, q: Quantity) -> Vec<[f64; 4]> {
    if q == Quantity::AngularVelocity {
        return vec![[0.0; 4]];
    }
    let (a, h) = (set.u_ddot, set.heading_acceleration);
    // ψ̈ enters ω̇_d3 only.
    let count = if q == Quantity::HorizontalAcceleration {
        8
    } else {
        16
    };
    (0..count)
        .map(|k| {
            let s = |bit: usize| if k >> bit & 1 == 1 { -1.0 } else { 1.0 };
            [s(0) * a, s(1) * a, s(2) * a, s(3) * h]
        })
        .collect()
}

/// Upper bound on the supremum of `q` over the confining set, by branch and bound until the
/// relative gap `(upper − lower)/upper ≤ relative_gap` or `max_boxes` nodes (module
/// documentation). The outcome is in the quantity's units.
pub fn maximise(set: &ConfiningSet, q: Quantity, relative_gap: f64, max_boxes: usize) -> Outcome {
    let ys = vertices(set, q);
    let roots: Vec<_> = if q == Quantity::AngularVelocity {
        // ω_d is linear in z = (u̇, ψ̇) for fixed (u, ψ): its norm is convex in z, so its
        // maximum over the z box is at one of the box's 16 vertices. ψ (index 6) stays a box.
        (0..16)
            .map(|k| {
                let mut region = set.split;
                for (bit, j) in [3, 4, 5, 7].into_iter().enumerate() {
                    let x = region[j];
                    region[j] = Interval::point(if k >> bit & 1 == 1 { x.lo } else { x.hi });
                }
                (region, 0)
            })
            .collect()
    } else {
        (0..ys.len()).map(|v| (set.split, v)).collect()
    };
    best_first(
        &roots,
        |region, v| bound(region, &ys[v], v, q),
        f64::sqrt,
        relative_gap,
        max_boxes,
    )
}
