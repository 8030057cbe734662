//! The filter states' reachable set as a polygon, and `ü` tied to the filter states.
//!
//! Per inertial component `i`, eq:FilterDynamics with the position law
//! (`PositionGains::evaluate`) gives, with `d = u_s − u_f`, `a = p̈_d,i`, `j = p_d⁽³⁾_i`,
//! `s = p_d⁽⁴⁾_i`, `g_i = g δ_{i3}` and, with the integral action on, its filtered estimate
//! `η_f,i`:
//! - `u_i = u_f + g_i + (a + η_f,i)` and `u̇_i = k_f d + (j + η̇_f,i)`;
//! - `ü_i = −k_f(k_f + k_s) d − k_f k_s u_f + e_i` with the residual
//!   `e_i = k_f k_s ubar_i + s + η̈_f,i`, `|e_i| ≤ E_i = k_f k_s M_p + K_s + k_η(b_i + R_i,i)`.
//!
//! **`ü` tied to the filter states** (proven, an identity). The other terms of `u_i` and `u̇_i`
//! range over `|a + η_f,i| ≤ A_i = K_a + M_i,i` and `|j + η̇_f,i| ≤ B_i = K_j + b_i` (`b_i = min(2k_η M_i,i, c R_i,i)`, the integral action's reachable-set bound)
//! (`K_a = K_a12` horizontally, `K_a3` vertically; each component of a vector is at most its
//! norm; the integral terms are zero with it off), and they do not enter `ü` except through
//! `e_i`. `ω̇_d` is affine in `ü` for fixed `(u, u̇, ψ, ψ̇)`, hence in `e`: its squared norm is
//! convex in `e`, so its maximum over the box of `e` is at a vertex. The product of boxes of
//! [`super::confining_set`] lets `ü_i` take any value of its box whatever `(u_i, u̇_i)` are; here
//! only `e_i` is free, and a filter settled at `+M_p` can only decelerate.
//!
//! **Reachable set of the filter states** (proven). From `x_f(0) = 0`, `(u_f, u_s)` at time `t`
//! is the convolution of the impulse responses `h_f(t) = k_f k_s (e^{−k_f t} − e^{−k_s t})/(k_s − k_f)`
//! (of `u_f`) and `h_s(t) = k_s e^{−k_s t}` (of `u_s`) with `ubar`, so for every direction `c` the
//! support function satisfies `c₁u_f + c₂d ≤ M_p ∫₀^∞ |(c₁ − c₂) h_f + c₂ h_s| = L(c)` (Young's
//! inequality). The integrand is `α e^{−k_f t} + β e^{−k_s t}`, with at most one sign change, so
//! the integral is closed form. Started anywhere in the saturation box, `(u_f, u_s)` stays in
//! `[−M_p, M_p]²` (invariant), whose support `M_p(|c₁ − c₂| + |c₂|)` bounds the zero start too;
//! the smaller is used. The sampled filter (exact propagation with `ubar` held) is a special
//! case of a measurable input. So `|c₁u_f + c₂d| ≤ L(c)` (the set is symmetric) for
//! [`DIRECTIONS`] directions over a half turn plus the direction of `ü`'s state part: a polygon,
//! the same for the three components, that contains every reachable `(u_f, d)`.
//!
//! Rounding: `L(c)` from `exp`/`ln` (a few ulps) is enlarged by [`SUPPORT_MARGIN`] (relative)
//! plus `10⁻¹²` of its terms' magnitudes and once more by [`LIMIT_MARGIN`]; the other constants
//! are outward-rounded. The clipped polygons of [`FilterPolygon::clip`] are computed in `f64`
//! against those enlarged limits, and [`linear_sup`] adds [`VERTEX_SLACK`] of each variable's
//! scale times its slope, which covers the few ulps of each computed intersection and of
//! `x − c` (a test checks the clipped bound against dense samples of the polygon).

use controller_core::{FilterStart, Gains, TrajectoryConstants, Vehicle};

use super::confining_set::IntegralTerms;
use super::interval::{next_up, Interval};

/// Number of evenly spread directions of the polygon (plus one for `ü`'s).
pub const DIRECTIONS: usize = 24;

/// Number of half-plane pairs of a component's polygon.
pub const HALF_PLANES: usize = DIRECTIONS + 1;

/// Relative enlargement of a support value computed with `exp` and `ln`.
pub const SUPPORT_MARGIN: f64 = 1e-9;

/// Relative enlargement of every polygon limit (covers the rounding of the clipping).
pub const LIMIT_MARGIN: f64 = 1e-9;

/// Relative slack on the vertices of a clipped polygon (module documentation).
pub const VERTEX_SLACK: f64 = 1e-9;

/// Most vertices of a box clipped by [`HALF_PLANES`] pairs of half-planes.
pub const MAX_VERTICES: usize = 4 + 2 * HALF_PLANES;

/// Upper bound of `∫₀^∞ |α e^{−k_f t} + β e^{−k_s t}| dt` for `k_f ≠ k_s` (one sign change at
/// most), enlarged for the rounding of `exp` and `ln`.
fn exponential_pair_l1(alpha: f64, beta: f64, kf: f64, ks: f64) -> f64 {
    let primitive = |t: f64| alpha * (-(-kf * t).exp_m1()) / kf + beta * (-(-ks * t).exp_m1()) / ks;
    let total = alpha / kf + beta / ks;
    let ratio = -beta / alpha;
    let crossing = if alpha != 0.0 && ratio > 0.0 {
        ratio.ln() / (ks - kf)
    } else {
        f64::NAN
    };
    let value = if crossing > 0.0 && crossing.is_finite() {
        let at = primitive(crossing);
        at.abs() + (total - at).abs()
    } else {
        total.abs()
    };
    let magnitude = alpha.abs() / kf + beta.abs() / ks;
    next_up(value * (1.0 + SUPPORT_MARGIN) + 1e-12 * magnitude)
}

/// Upper bound of `max (c₁u_f + c₂(u_s − u_f))` [m/s²] over the filter states reachable under
/// `|ubar| ≤ M_p` (module documentation), for gains `k_f`, `k_s` [1/s] and `M_p` [m/s²].
pub fn support(kf: f64, ks: f64, mp: f64, start: FilterStart, c: [f64; 2]) -> f64 {
    let p = Interval::point;
    let (a, b) = (p(c[0]) - p(c[1]), p(c[1]));
    let in_box = (p(mp) * (a.abs() + b.abs())).hi;
    if start == FilterStart::InSaturationBox || kf == ks {
        return in_box;
    }
    let (a, b) = (c[0] - c[1], c[1]);
    let alpha = a * kf * ks / (ks - kf);
    let beta = -alpha + b * ks;
    let reachable = (p(mp) * p(exponential_pair_l1(alpha, beta, kf, ks))).hi;
    reachable.min(in_box)
}

/// One half-plane pair `lo ≤ a u_f + b d ≤ hi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlanes {
    /// Coefficient of `u_f` (dimensionless).
    pub a: f64,
    /// Coefficient of `d` (dimensionless).
    pub b: f64,
    /// Lower limit [m/s²].
    pub lo: f64,
    /// Upper limit [m/s²].
    pub hi: f64,
}

/// A clipped polygon: up to [`MAX_VERTICES`] vertices `(u_f, d)`.
#[derive(Clone, Copy, Debug)]
pub struct Clipped {
    /// The vertices (the first `count`).
    pub vertices: [[f64; 2]; MAX_VERTICES],
    /// How many.
    pub count: usize,
}

/// Where a box of `(u_f, d)` lies against the polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// Every point of the box satisfies every half-plane.
    Inside,
    /// Some half-plane cuts the box.
    Partial,
    /// Some half-plane excludes the whole box.
    Outside,
}

/// The polygon of the filter states (the same for the three components) and the ranges of the
/// other terms of `u`, `u̇`, `ü` (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterPolygon {
    /// `k_f` [1/s].
    pub kf: f64,
    /// `k_f(k_f + k_s)` [1/s²] (slope of `ü` in `d`).
    pub rate_gain: f64,
    /// `k_f k_s` [1/s²] (slope of `ü` in `u_f`).
    pub state_gain: f64,
    /// `g_i`: `(0, 0, g)` [m/s²].
    pub offset: [f64; 3],
    /// `E_i = k_f k_s M_p + K_s + C_i` [m/s⁴], rounded up; the horizontal pair equal.
    pub residual: [f64; 3],
    /// `A_i = K_a + M_i,i`: half-width of the other terms of `u_i` [m/s²].
    pub value_range: [f64; 3],
    /// `B_i = K_j + b_i`: half-width of the other terms of `u̇_i` [m/s³].
    pub rate_range: [f64; 3],
    /// Half-widths of the boxes of `u_f` and `d` [m/s²] (the supports along the axes).
    pub state_box: [f64; 2],
    /// The half-planes `−L(c) ≤ c₁u_f + c₂d ≤ L(c)`.
    pub planes: [HalfPlanes; HALF_PLANES],
}

impl FilterPolygon {
    /// The polygon for one set-up. The caller has validated the parameters (as
    /// [`super::confining_set::ConfiningSet::new`] does).
    pub fn new(
        vehicle: &Vehicle<f64>,
        gains: &Gains<f64>,
        constants: &TrajectoryConstants<f64>,
        start: FilterStart,
    ) -> Self {
        let p = Interval::point;
        let pos = &gains.position;
        let (kf, ks, mp) = (pos.kf, pos.ks, pos.saturation);
        // The reference as the law applies it (the feedforward scale widens its constants).
        let k = &gains.law_constants(constants);
        let i = IntegralTerms::new(gains);
        let (level, rate, accel) = (i.level, i.rate, i.acceleration);
        // The horizontal pair shares the larger terms (keeps the square's symmetries).
        let pair = |v: [f64; 3]| [v[0].max(v[1]), v[0].max(v[1]), v[2]];
        let (level, rate, accel) = (pair(level), pair(rate), pair(accel));
        let reference = [
            k.horizontal_acceleration,
            k.horizontal_acceleration,
            k.vertical_acceleration,
        ];
        let residual =
            core::array::from_fn(|c| (p(kf) * p(ks) * p(mp) + p(k.snap) + p(accel[c])).hi);
        let mut directions = [[0.0; 2]; HALF_PLANES];
        for (n, d) in directions.iter_mut().take(DIRECTIONS).enumerate() {
            let angle = core::f64::consts::PI * n as f64 / DIRECTIONS as f64;
            *d = [angle.cos(), angle.sin()];
        }
        // ü's state part, −k_f k_s u_f − k_f(k_f + k_s) d, in (u_f, d).
        let (c1, c2) = (kf * ks, kf * (kf + ks));
        let norm = c1.hypot(c2);
        directions[DIRECTIONS] = [c1 / norm, c2 / norm];
        let planes = directions.map(|c| {
            let limit = next_up(support(kf, ks, mp, start, c) * (1.0 + LIMIT_MARGIN) + 1e-300);
            HalfPlanes {
                a: c[0],
                b: c[1],
                lo: -limit,
                hi: limit,
            }
        });
        Self {
            kf,
            rate_gain: (p(kf) * (p(kf) + p(ks))).hi,
            state_gain: (p(kf) * p(ks)).hi,
            offset: [0.0, 0.0, vehicle.gravity],
            residual,
            value_range: core::array::from_fn(|c| (p(reference[c]) + p(level[c])).hi),
            rate_range: core::array::from_fn(|c| (p(k.jerk) + p(rate[c])).hi),
            state_box: [
                support(kf, ks, mp, start, [1.0, 0.0]),
                support(kf, ks, mp, start, [0.0, 1.0]),
            ],
            planes,
        }
    }

    /// Where the box `u_f ∈ value`, `d ∈ rate` lies against the polygon.
    pub fn place(&self, value: Interval, rate: Interval) -> Placement {
        let p = Interval::point;
        let mut placement = Placement::Inside;
        for h in &self.planes {
            let v = p(h.a) * value + p(h.b) * rate;
            if v.lo > h.hi || v.hi < h.lo {
                return Placement::Outside;
            }
            if v.hi > h.hi || v.lo < h.lo {
                placement = Placement::Partial;
            }
        }
        placement
    }

    /// Shrinks the box `u_f ∈ value`, `d ∈ rate` to a smaller box around its points inside the
    /// polygon (one round of interval constraint propagation, outward-rounded: only points
    /// outside are removed); `false` when no point is left.
    pub fn contract(&self, value: &mut Interval, rate: &mut Interval) -> bool {
        let p = Interval::point;
        for h in &self.planes {
            let band = Interval::new(h.lo, h.hi);
            if h.a.abs() > 1e-9 {
                let range = (band - p(h.b) * *rate) / p(h.a);
                let (lo, hi) = (value.lo.max(range.lo), value.hi.min(range.hi));
                if lo > hi {
                    return false;
                }
                *value = Interval::new(lo, hi);
            }
            if h.b.abs() > 1e-9 {
                let range = (band - p(h.a) * *value) / p(h.b);
                let (lo, hi) = (rate.lo.max(range.lo), rate.hi.min(range.hi));
                if lo > hi {
                    return false;
                }
                *rate = Interval::new(lo, hi);
            }
        }
        true
    }

    /// The box `u_f ∈ value`, `d ∈ rate` clipped by the half-planes (Sutherland–
    /// Hodgman, in `f64`; module documentation for the rounding).
    pub fn clip(&self, value: Interval, rate: Interval) -> Clipped {
        let mut poly = Clipped {
            vertices: [[0.0; 2]; MAX_VERTICES],
            count: 4,
        };
        poly.vertices[..4].copy_from_slice(&[
            [value.lo, rate.lo],
            [value.hi, rate.lo],
            [value.hi, rate.hi],
            [value.lo, rate.hi],
        ]);
        for h in &self.planes {
            poly = clip_half_plane(&poly, [h.a, h.b], h.hi);
            poly = clip_half_plane(&poly, [-h.a, -h.b], -h.lo);
            if poly.count == 0 {
                break;
            }
        }
        poly
    }

    /// Whether the point `(u_f, d)` satisfies every half-plane.
    pub fn admits(&self, value: f64, rate: f64) -> bool {
        self.planes.iter().all(|h| {
            let v = h.a * value + h.b * rate;
            v >= h.lo && v <= h.hi
        })
    }
}

/// `poly ∩ {x: n·x ≤ limit}`.
fn clip_half_plane(poly: &Clipped, n: [f64; 2], limit: f64) -> Clipped {
    let mut out = Clipped {
        vertices: [[0.0; 2]; MAX_VERTICES],
        count: 0,
    };
    let level = |x: &[f64; 2]| n[0] * x[0] + n[1] * x[1] - limit;
    for k in 0..poly.count {
        let a = poly.vertices[k];
        let b = poly.vertices[(k + 1) % poly.count];
        let (la, lb) = (level(&a), level(&b));
        if la <= 0.0 {
            push(&mut out, a);
        }
        if (la < 0.0 && lb > 0.0) || (la > 0.0 && lb < 0.0) {
            let t = la / (la - lb);
            push(
                &mut out,
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            );
        }
    }
    out
}

fn push(poly: &mut Clipped, x: [f64; 2]) {
    if poly.count < MAX_VERTICES {
        poly.vertices[poly.count] = x;
        poly.count += 1;
    }
}

/// Upper bound of `sup Σ_j max(G_j.lo δ_j, G_j.hi δ_j)` over `δ = x − centre`, `x` in the
/// clipped polygon (a convex function: its maximum is at a vertex), plus the vertex slack of
/// the module documentation. `slope` holds the interval slopes of `(u_i, u̇_i)`; `scale` their
/// magnitudes.
pub fn linear_sup(poly: &Clipped, centre: [f64; 2], slope: [Interval; 2], scale: [f64; 2]) -> f64 {
    let term = |g: Interval, d: f64| -> f64 { next_up(if d >= 0.0 { g.hi * d } else { g.lo * d }) };
    let mut best = f64::NEG_INFINITY;
    for x in &poly.vertices[..poly.count] {
        let s = next_up(term(slope[0], x[0] - centre[0]) + term(slope[1], x[1] - centre[1]));
        // x − centre is itself rounded: a relative ulp of the larger operand, inside the slack.
        best = best.max(s);
    }
    let slack = next_up(
        slope[0].mag() * VERTEX_SLACK * (scale[0] + 1.0)
            + slope[1].mag() * VERTEX_SLACK * (scale[1] + 1.0),
    );
    next_up(best + slack)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form against a fine quadrature of the same integrand.
    #[test]
    fn exponential_pair_matches_quadrature() {
        for (alpha, beta, kf, ks) in [
            (1.0, -3.0, 2.0, 20.0),
            (-2.0, 0.5, 2.0, 20.0),
            (1.0, 1.0, 3.0, 5.0),
            (4.0, -1.0, 7.0, 2.0),
        ] {
            let n = 2_000_000;
            let horizon = 40.0 / f64::min(kf, ks);
            let dt = horizon / n as f64;
            let q: f64 = (0..n)
                .map(|k| {
                    let t = (k as f64 + 0.5) * dt;
                    (alpha * (-kf * t).exp() + beta * (-ks * t).exp()).abs() * dt
                })
                .sum();
            let closed = exponential_pair_l1(alpha, beta, kf, ks);
            assert!(
                closed >= q * (1.0 - 1e-6) && closed <= q * (1.0 + 1e-6),
                "{closed} {q}"
            );
        }
    }

    /// The support along `d` is Lemma 1's per-component `u̇` term over `k_f`, along `ü`'s
    /// state direction it is the per-component `ü` box minus the current input, along `u_f` it
    /// is `M_p` (filter_l1 computes the first two independently).
    #[test]
    fn support_matches_the_impulse_response_bounds() {
        let (kf, ks, mp) = (2.0, 20.0, 2.0);
        let (b1, b2) =
            super::super::filter_l1::rate_and_acceleration_bounds(kf, ks, mp, FilterStart::Zero);
        let d = support(kf, ks, mp, FilterStart::Zero, [0.0, 1.0]);
        // The support is enlarged by SUPPORT_MARGIN for the rounding of exp and ln.
        assert!(kf * d >= b1 && kf * d - b1 < 3e-9 * b1, "{} {b1}", kf * d);
        let state = support(kf, ks, mp, FilterStart::Zero, [kf * ks, kf * (kf + ks)]);
        assert!(
            (state + kf * ks * mp - b2).abs() < 3e-9 * b2,
            "{state} {b2}"
        );
        let f = support(kf, ks, mp, FilterStart::Zero, [1.0, 0.0]);
        assert!(f >= mp && f - mp < 3e-9);
    }

    /// Filter states reached by bang-bang inputs (the extreme points of the reachable set)
    /// lie inside every half-plane, and a clipped box contains them when the box does.
    #[test]
    fn reachable_states_lie_in_the_polygon() {
        let (kf, ks, mp) = (2.0_f64, 20.0_f64, 2.0_f64);
        let gains = controller_core::Gains::<f64>::paper();
        let vehicle = controller_core::Vehicle::<f64>::paper();
        let constants = controller_core::TrajectoryConstants::<f64> {
            horizontal_acceleration: 0.0,
            vertical_acceleration: 0.0,
            jerk: 0.0,
            snap: 0.0,
            heading_rate: 0.0,
            heading_acceleration: 0.0,
        };
        let poly = FilterPolygon::new(&vehicle, &gains, &constants, FilterStart::Zero);
        // Exact propagation over 1 ms with the input held (eq:FilterDynamics).
        let h = 1e-3;
        let (ef, es) = ((-kf * h).exp(), (-ks * h).exp());
        let mut state = (0.0_f64, 0.0_f64);
        let mut inside = 0;
        for step in 0..20_000 {
            // Switching periods spread over the filters' time constants.
            let period = 1 + (step / 2000) * 97;
            let ubar = if (step / period) % 2 == 0 { mp } else { -mp };
            let (uf, us) = state;
            let b = kf * (us - ubar) / (kf - ks);
            let a = uf - ubar - b;
            state = (ubar + a * ef + b * es, ubar + (us - ubar) * es);
            let (uf, us) = state;
            let (u, rate) = (uf, us - uf);
            assert!(poly.admits(u, rate), "({u}, {rate}) at step {step}");
            let clipped = poly.clip(
                Interval::new(u - 0.01, u + 0.01),
                Interval::new(rate - 0.01, rate + 0.01),
            );
            assert!(clipped.count >= 3);
            inside += 1;
        }
        assert_eq!(inside, 20_000);
    }

    /// The clipped polygon's vertex bound is at least the convex function's value at every
    /// admissible point of the box (dense random points, random slopes, boxes that the
    /// polygon cuts): the clipping never drops part of the box inside the polygon.
    #[test]
    fn clipped_bound_covers_every_admissible_point() {
        use rand::{RngExt, SeedableRng};
        let setup = super::super::setup::Setup::paper();
        let poly = FilterPolygon::new(
            &setup.vehicle,
            &setup.gains,
            &setup.constants,
            FilterStart::Zero,
        );
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let (fx, dx) = (poly.state_box[0], poly.state_box[1]);
        let mut cut = 0;
        for _ in 0..2000 {
            let centre = [rng.random_range(-fx..fx), rng.random_range(-dx..dx)];
            let half = [rng.random_range(0.01..1.0), rng.random_range(0.01..1.0)];
            let value = Interval::new(centre[0] - half[0], centre[0] + half[0]);
            let rate = Interval::new(centre[1] - half[1], centre[1] + half[1]);
            if poly.place(value, rate) != Placement::Partial {
                continue;
            }
            cut += 1;
            let clipped = poly.clip(value, rate);
            let slope = [0, 1].map(|_| {
                let (a, b) = (rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0));
                Interval::new(f64::min(a, b), f64::max(a, b))
            });
            let scale = [value.mag(), rate.mag()];
            let bound = if clipped.count == 0 {
                f64::NEG_INFINITY
            } else {
                linear_sup(&clipped, centre, slope, scale)
            };
            for _ in 0..200 {
                let x = [
                    rng.random_range(value.lo..value.hi),
                    rng.random_range(rate.lo..rate.hi),
                ];
                if !poly.admits(x[0], x[1]) {
                    continue;
                }
                let f: f64 = (0..2)
                    .map(|j| {
                        let d = x[j] - centre[j];
                        (slope[j].lo * d).max(slope[j].hi * d)
                    })
                    .sum();
                assert!(f <= bound, "{f} > {bound} at {x:?} in {value:?} x {rate:?}");
            }
        }
        assert!(cut > 200, "only {cut} boxes cut by the polygon");
    }
}
