//! Branch and bound for the `ω̇_d` quantities over the filter states, with `ü` tied to them and
//! the filter states confined to their polygon ([`super::filter_polygon`]).
//!
//! The argument is that of [`super::search`] with other variables and two changes. The
//! variables ([`SEARCH_DIM`]) are the filter states `(u_f, d)` of the three components, `ψ`,
//! `ψ̇`, and the other terms of `u` and `u̇` (the reference's `p̈_d`, `p_d⁽³⁾` and the integral
//! action's `η_f`, `η̇_f`), all split by the search:
//! - `ü_i = −k_f(k_f + k_s) d_i − k_f k_s u_f,i + e_i`, and the vertices are those of the box of
//!   the residual `(e, ψ̈)` (`ω̇_d` is affine in `e`, so its squared norm is convex there);
//! - each component's `(u_f,i, d_i)` lies in the polygon. A box is contracted to it (interval
//!   propagation), dropped when no point is left, and its mean-value forms take the supremum of
//!   their linear part over the box clipped by the polygon instead of over the box: with
//!   interval slopes `G_j`, `Σ_j max(G_j.lo δ_j, G_j.hi δ_j)` is convex in `δ = x − c`, so its
//!   supremum over the clipped polygon (a convex polygon per component, the components
//!   independent) is at a vertex ([`super::filter_polygon::linear_sup`]); the mean value theorem
//!   still runs along the segment from the box's centre `c`, which lies in the box. A variable
//!   is shrunk to a face by monotonicity only when its component's box lies wholly inside the
//!   polygon (the face of a cut box may leave it); `ψ`, `ψ̇` and the other terms always.
//!
//! Time reversal `(u̇, ψ̇) ↦ −(u̇, ψ̇)` maps `d` to `−d` with `u_f` kept, which the reachable
//! set does not allow, so `ψ̇` ranges over `[−K_ν̇, K_ν̇]`; the square's symmetries map each
//! horizontal component's `(u_f, d)` and other terms to `±` the other's, under which the
//! polygon (symmetric) and the boxes (the horizontal pair equal) are invariant, so
//! `ψ ∈ [0, π/4]` still suffices.
//!
//! Point values (for stopping only) count only at points inside the polygon. Every node's upper
//! bound is rigorous for the admissible points of its box, so the largest over a cover bounds
//! the supremum over the confining set.

use super::arith::Arith;
use super::branch_bound::{best_first, Node, Outcome};
use super::confining_set::ConfiningSet;
use super::desired_rates::{desired_rates, Heading};
use super::filter_polygon::{linear_sup, Clipped, FilterPolygon, Placement};
use super::gradient::Gradient;
use super::interval::{next_down, next_up, Interval};
use super::search::{gradient_vertex, select, sum_of_squares, Quantity};

/// Number of variables: filter states `u_f` (3), `d = u_s − u_f` (3), `ψ`, `ψ̇`, the other terms
/// of `u` (`p̈_d` and `η_f`, 3) and of `u̇` (`p_d⁽³⁾` and `η̇_f`, 3).
pub const SEARCH_DIM: usize = 14;

/// The selected components of `ω̇_d` at `x` ([`SEARCH_DIM`]), heading `(cos ψ, sin ψ)` and the
/// vertex `y = (e, ψ̈)`: `u = u_f + g e₃ + x₈..₁₀`, `u̇ = k_f d + x₁₁..₁₃`,
/// `ü = e − k_f(k_f + k_s) d − k_f k_s u_f`.
fn components<T: Arith>(
    x: &[T; SEARCH_DIM],
    heading: (T, T),
    y: &[f64; 4],
    q: Quantity,
    poly: &FilterPolygon,
) -> ([T; 3], usize) {
    let c = T::constant;
    let u: [T; 3] = core::array::from_fn(|i| x[i] + c(poly.offset[i]) + x[8 + i]);
    let u_dot: [T; 3] = core::array::from_fn(|i| c(poly.kf) * x[3 + i] + x[11 + i]);
    let u_ddot: [T; 3] = core::array::from_fn(|i| {
        c(y[i]) - c(poly.rate_gain) * x[3 + i] - c(poly.state_gain) * x[i]
    });
    let h = Heading {
        cos: heading.0,
        sin: heading.1,
        rate: x[7],
        acceleration: c(y[3]),
    };
    select(&desired_rates(&u, &u_dot, &u_ddot, &h), q)
}

fn squared<T: Arith>(
    x: &[T; SEARCH_DIM],
    heading: (T, T),
    y: &[f64; 4],
    q: Quantity,
    poly: &FilterPolygon,
) -> T {
    let (v, count) = components(x, heading, y, q, poly);
    sum_of_squares(&v, count)
}

fn gradient_enclosure(
    region: &[Interval; SEARCH_DIM],
    y: &[f64; 4],
    q: Quantity,
    poly: &FilterPolygon,
) -> ([Gradient<SEARCH_DIM>; 3], usize, Gradient<SEARCH_DIM>) {
    let x: [Gradient<SEARCH_DIM>; SEARCH_DIM] =
        core::array::from_fn(|j| Gradient::variable(region[j], j));
    let (v, count) = components(&x, x[6].cos_sin(), y, q, poly);
    let f = sum_of_squares(&v, count);
    (v, count, f)
}

/// Upper bound of `sup_{x ∈ X ∩ polygon} Σ_j max(G_j.lo δ_j, G_j.hi δ_j)`, `δ = x − c`
/// (`clipped[i]`: component `i`'s box clipped by the polygon, `None` when wholly inside).
fn spread(
    region: &[Interval; SEARCH_DIM],
    centre: &[f64; SEARCH_DIM],
    slope: &[Interval; SEARCH_DIM],
    clipped: &[Option<Clipped>; 3],
) -> f64 {
    let box_term = |j: usize| -> f64 {
        let x = region[j];
        if x.lo == x.hi {
            return 0.0;
        }
        let up = next_up(x.hi - centre[j]);
        let down = next_up(centre[j] - x.lo);
        next_up((slope[j].hi * up).max(0.0).max(-slope[j].lo * down))
    };
    let mut total = (6..SEARCH_DIM).fold(0.0, |t, j| next_up(t + box_term(j)));
    for comp in 0..3 {
        let (a, b) = (comp, comp + 3);
        let part = match &clipped[comp] {
            None => next_up(box_term(a) + box_term(b)),
            Some(clipped) => {
                let scale = |x: Interval| x.lo.abs().max(x.hi.abs());
                let clipped_sup = linear_sup(
                    clipped,
                    [centre[a], centre[b]],
                    [slope[a], slope[b]],
                    [scale(region[a]), scale(region[b])],
                );
                clipped_sup.min(next_up(box_term(a) + box_term(b)))
            }
        };
        total = next_up(total + part);
    }
    total
}

/// Bounds `F_v` over the admissible points of `region` (module documentation).
fn bound(
    mut region: [Interval; SEARCH_DIM],
    y: &[f64; 4],
    vertex: usize,
    q: Quantity,
    poly: &FilterPolygon,
) -> Node<SEARCH_DIM> {
    let outside = |region| Node {
        upper: f64::NEG_INFINITY,
        region,
        tag: vertex,
        split: None,
        lower: f64::NAN,
    };
    let mut placement = [Placement::Inside; 3];
    for comp in 0..3 {
        let (mut value, mut rate) = (region[comp], region[comp + 3]);
        if !poly.contract(&mut value, &mut rate) {
            return outside(region);
        }
        region[comp] = value;
        region[comp + 3] = rate;
        placement[comp] = poly.place(value, rate);
        if placement[comp] == Placement::Outside {
            return outside(region);
        }
    }
    let collapsible = |j: usize| j >= 6 || placement[j % 3] == Placement::Inside;
    let (mut v, count, mut g) = gradient_enclosure(&region, y, q, poly);
    for _ in 0..SEARCH_DIM {
        let mut collapsed = false;
        for (j, (x, d)) in region.iter_mut().zip(g.partial).enumerate() {
            if collapsible(j) && x.lo < x.hi && (d.lo > 0.0 || d.hi < 0.0) {
                *x = Interval::point(if d.lo > 0.0 { x.hi } else { x.lo });
                collapsed = true;
            }
        }
        if !collapsed {
            break;
        }
        (v, _, g) = gradient_enclosure(&region, y, q, poly);
    }
    let c = region.map(|x| x.mid());
    // A cut box's clipped polygon; an empty one (rounding only) falls back to the box (sound).
    let clipped: [Option<Clipped>; 3] = core::array::from_fn(|comp| {
        if placement[comp] == Placement::Inside {
            return None;
        }
        let polygon = poly.clip(region[comp], region[comp + 3]);
        (polygon.count > 0).then_some(polygon)
    });
    let point = c.map(Interval::point);
    let (at_centre, _) = components(&point, point[6].cos_sin(), y, q, poly);
    let mean_value =
        next_up(sum_of_squares(&at_centre, count).hi + spread(&region, &c, &g.partial, &clipped));
    let mut per_component = Interval::point(0.0);
    for (vi, ci) in v[..count].iter().zip(&at_centre[..count]) {
        let up = spread(&region, &c, &vi.partial, &clipped);
        let negated = vi.partial.map(|d| Interval::new(-d.hi, -d.lo));
        let down = spread(&region, &c, &negated, &clipped);
        let form = Interval::new(next_down(ci.lo - down), next_up(ci.hi + up));
        let enclosed = Interval::new(form.lo.max(vi.value.lo), form.hi.min(vi.value.hi));
        per_component = per_component + enclosed.sqr();
    }
    let upper_sq = g.value.hi.min(mean_value).min(per_component.hi);
    let upper_sq = if upper_sq.is_nan() {
        f64::INFINITY
    } else {
        upper_sq
    };
    let mut split = None;
    let mut widest = 0.0;
    for (j, (x, d)) in region.iter().zip(g.partial).enumerate() {
        if x.lo < x.hi {
            let share = next_up(d.mag() * x.width());
            if share > widest || (split.is_none() && share.is_nan()) {
                widest = share;
                split = Some(j);
            }
        }
    }
    let toward = gradient_vertex(&region, &g.partial);
    let at = |x: &[f64; SEARCH_DIM]| {
        if (0..3).all(|comp| poly.admits(x[comp], x[comp + 3])) {
            squared(x, (x[6].cos(), x[6].sin()), y, q, poly)
        } else {
            f64::NAN
        }
    };
    // f64::max ignores a NaN (a point outside the polygon) unless both are.
    let lower_sq = at(&c).max(at(&toward));
    Node {
        upper: upper_sq,
        region,
        tag: vertex,
        split,
        lower: lower_sq,
    }
}

/// The vertices of the `(e, ψ̈)` box that the quantity needs.
fn vertices(poly: &FilterPolygon, heading_acceleration: f64, q: Quantity) -> Vec<[f64; 4]> {
    let e = poly.residual;
    let count = if q == Quantity::HorizontalAcceleration {
        8
    } else {
        16
    };
    (0..count)
        .map(|k| {
            let s = |bit: usize| if k >> bit & 1 == 1 { -1.0 } else { 1.0 };
            [
                s(0) * e[0],
                s(1) * e[1],
                s(2) * e[2],
                s(3) * heading_acceleration,
            ]
        })
        .collect()
}

/// Upper bound on the supremum of an `ω̇_d` quantity (not [`Quantity::AngularVelocity`], for
/// which `None`) over the confining set with the filter coupling, until the relative gap or
/// `max_boxes` nodes. The outcome is in the quantity's units [rad/s²].
pub fn maximise_coupled(
    set: &ConfiningSet,
    poly: &FilterPolygon,
    q: Quantity,
    relative_gap: f64,
    max_boxes: usize,
) -> Option<Outcome> {
    if q == Quantity::AngularVelocity {
        return None;
    }
    let ys = vertices(poly, set.heading_acceleration, q);
    let sym = Interval::symmetric;
    let root: [Interval; SEARCH_DIM] = core::array::from_fn(|j| match j {
        0..=2 => sym(poly.state_box[0]),
        3..=5 => sym(poly.state_box[1]),
        6 => set.split[6],
        7 => sym(set.split[7].hi),
        8..=10 => sym(poly.value_range[j - 8]),
        _ => sym(poly.rate_range[j - 11]),
    });
    let roots: Vec<_> = (0..ys.len()).map(|v| (root, v)).collect();
    Some(best_first(
        &roots,
        |region, v| bound(region, &ys[v], v, q, poly),
        f64::sqrt,
        relative_gap,
        max_boxes,
    ))
}
