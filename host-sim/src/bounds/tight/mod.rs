//! Tight a-priori bounds on `|ω_d|`, `|ω̇_d|` and the per-axis torque, rigorous by interval
//! arithmetic and branch and bound.
//!
//! Lemma 1 and Theorem 2 (controller_core::bounds::certify) bound the same quantities by
//! chaining worst cases term by term; here the suprema of the law's actual expressions over a
//! superset of the set that the saturations and filters confine their arguments to are
//! enclosed by computation. What is **proven** (by the arguments below, each in the
//! documentation of its module) and what is **computed** (rigorously, by outward-rounded
//! interval arithmetic):
//!
//! 1. *Confining set* (proven, [`confining_set`], [`filter_l1`]). On every solution, per
//!    inertial component, `u`, `u̇`, `ü` lie in boxes built from `M_p`, `k_f`, `k_s` (L¹ norms
//!    of the filter's impulse responses, exact closed forms), `g` and the trajectory constants
//!    of Assumption 1; `ψ̇`, `ψ̈` of the heading angle lie in `[−K_ν̇, K_ν̇]`, `[−K_ν̈, K_ν̈]`. The
//!    product of these boxes (correlations dropped) contains every admissible argument.
//! 2. *Symmetries* (proven). The boxes are invariant under the dihedral group of the square
//!    acting on the horizontal components of `u`, `u̇`, `ü` (rotations by 90° about `e₃`,
//!    reflections). Rotating all inertial inputs and the heading by `Q` about `e₃` maps `ρ`,
//!    `ϖ = (ρ₃ν, −ρᵀν*)`, `υ` to `Qρ`, `Qϖ`, `Qυ`, hence `R_d` to `QR_d`, and leaves the body
//!    vectors `ω_d`, `ω̇_d` unchanged. The reflection `S = diag(1, −1, 1)` maps `R_d` to
//!    `S R_d D`, `D = diag(1, −1, 1)`, so `ω_d ↦ (−ω₁, ω₂, −ω₃)` and likewise `ω̇_d`: every
//!    bounded quantity (`|ω_d|`, `|ω̇_d|`, `|(ω̇₁, ω̇₂)|`, `|ω̇₃|`) is unchanged. These map the
//!    heading angle `ψ` to `ψ + kπ/2`, `−ψ`, `π/2 − ψ`, so `ψ ∈ [0, π/4]` suffices. Time
//!    reversal `(u̇, ψ̇) ↦ −(u̇, ψ̇)` (with `u`, `ü`, `ψ̈` kept, the boxes being symmetric) maps
//!    `ρ̇, υ̇, ω_d` to their negatives and keeps `ρ̈, ϋ, ω̇_d`, so `ψ̇ ≥ 0` suffices.
//! 3. *Reformulation* (proven, [`desired_rates`]). `ω_d`, `ω̇_d` are written in closed form in the
//!    desired body frame; on `f64` this agrees with `controller_core::desired_attitude` to
//!    rounding (tested), on intervals it encloses the exact values.
//! 4. *Vertices* (proven, [`search`]). `ω_d` is linear in `(u̇, ψ̇)` for fixed `(u, ψ)`, and `ω̇_d`
//!    affine in `(ü, ψ̈)` for fixed `(u, u̇, ψ, ψ̇)`; a squared norm of an affine map is convex, so
//!    the maxima over those boxes are at their vertices, which are enumerated.
//! 5. *Branch and bound* (computed, [`search`], [`branch_bound`]). Over the remaining
//!    variables, every box gets a rigorous upper bound (natural interval extension or the
//!    mean-value form with an interval gradient from forward-mode differentiation,
//!    [`gradient`]; monotonicity in a variable, proven on the box by its gradient enclosure,
//!    shrinks the box to a face). The returned bound is the largest upper bound over a cover of
//!    the (reduced) confining boxes, so it bounds the supremum. The search stops at a relative
//!    gap to the best point value seen ([`TightOptions`]); the gap changes how tight the bound
//!    is, never whether it holds. On request ([`TightOptions::coupled_boxes`]) the `|ω̇_d|` and
//!    `|(ω̇_d1, ω̇_d2)|` suprema are also bounded over a smaller superset that keeps the
//!    filters' correlations ([`filter_polygon`], [`coupled_search`]); each bound is kept where
//!    smaller.
//! 6. *Torque* (proven decomposition, computed supremum, [`torque`]). `|τ_i| ≤ M_ω +
//!    sup_{|ϑ̃|≤1+δ} φ_i(ϑ̃) + ½|J_jj − J_kk| W²` with `W ≥ sup|ω_d|` and `φ_i` built from
//!    `H₁₂ ≥ sup|(ω̇_d1, ω̇_d2)|`, `H₃ ≥ sup|ω̇_d3|`; the supremum of `φ_i` over the MRP ball is a
//!    3-D branch and bound. Also `|ω̇_d| ≤ √(H₁₂² + H₃²)`, kept when smaller than the direct
//!    search's bound.
//!
//! *Rounding* ([`interval`]): every `+ − × ÷ √` result is moved one ulp outward (IEEE 754
//! operations are correctly rounded); `cos`, `sin` two ulps (platform `libm`, below one ulp);
//! `U_l` of the filter bound (from `ln`, `exp`) by a relative `10⁻¹²`. The `inari` crate was
//! considered and not used: it needs `-C target-cpu=haswell` for the whole workspace, which
//! could change the code generated for the paper reproduction (byte-identical output).
//!
//! *Witnesses* ([`witness`], [`sampling`], [`setup`]): admissible states of the confining set
//! (filter states made reachable by integrating eq:FilterDynamics exactly) at which the actual
//! controller-core law is evaluated; the largest value found for each quantity is a lower bound
//! on its supremum, so witness/bound shows how tight a bound is.
//!
//! Not covered: the bound is for the continuous-time law on the confining set; sampling,
//! `f32` firmware arithmetic and the rotor model are outside it (as for the paper's bounds).

pub mod arith;
pub mod branch_bound;
pub mod confining_set;
pub mod coupled_search;
pub mod desired_rates;
pub mod filter_l1;
pub mod filter_polygon;
pub mod gradient;
pub mod interval;
pub mod sampling;
pub mod search;
pub mod setup;
pub mod torque;
pub mod witness;

use controller_core::{FilterStart, Gains, ParameterError, TrajectoryConstants, Vehicle};

use confining_set::ConfiningSet;
use coupled_search::maximise_coupled;
use filter_polygon::FilterPolygon;
use search::{maximise, Quantity};
use torque::{torque_bound, AttitudeTerm};

/// How hard the branch and bound works.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightOptions {
    /// Each search stops when `(upper − lower)/upper ≤ relative_gap` (dimensionless, `≥ 0`).
    pub relative_gap: f64,
    /// Cap on the boxes of each search; on hitting it the (still sound) upper bound of the
    /// unfinished search is returned. With the default cap this, not the gap, sets the run
    /// time for the `|ω̇_d|` quantities of the paper's set-up (8·10⁶ reaches the 1 % gap).
    pub max_boxes: usize,
    /// Box budget of the searches that keep the filter correlations ([`coupled_search`]) for
    /// `|(ω̇_d1, ω̇_d2)|` and `|ω̇_d|`; 0 skips them. Their bounds are kept where smaller. They
    /// converge slowly (the paper's set-up: 6.4·10⁷ boxes each, 32 min on two cores and 12.5 GB,
    /// to beat the box relaxation), so only `host-sim bounds --coupled-boxes N` runs them.
    pub coupled_boxes: usize,
}

impl Default for TightOptions {
    /// `relative_gap = 0.01`, `max_boxes = 150 000` per search: about 2–4 s (release, two
    /// cores) for the paper's set-up, where the `|ω̇_d|` searches stop at the cap, not the gap;
    /// no correlated searches (`coupled_boxes = 0`).
    fn default() -> Self {
        Self {
            relative_gap: 0.01,
            max_boxes: 150_000,
            coupled_boxes: 0,
        }
    }
}

/// The largest values the searches saw at points of the confining boxes (same units as
/// [`TightBounds`]); they show how close the bounds are, they are not witnesses of the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightLower {
    /// `|ω_d|` [rad/s].
    pub angular_velocity: f64,
    /// `|ω̇_d|` [rad/s²].
    pub angular_acceleration: f64,
    /// `|(ω̇_d1, ω̇_d2)|` [rad/s²].
    pub horizontal_acceleration: f64,
    /// `|ω̇_d3|` [rad/s²].
    pub yaw_acceleration: f64,
    /// Per axis, the torque decomposition of [`torque`] at the best points [N m].
    pub torque_max: [f64; 3],
}

/// Rigorous upper bounds over the confining set (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightBounds {
    /// `sup |ω_d|` upper bound [rad/s].
    pub angular_velocity: f64,
    /// `sup |ω̇_d|` upper bound [rad/s²].
    pub angular_acceleration: f64,
    /// `sup |(ω̇_d1, ω̇_d2)|` upper bound [rad/s²] (`H₁₂` of [`torque`]).
    pub horizontal_acceleration: f64,
    /// `sup |ω̇_d3|` upper bound [rad/s²] (`H₃` of [`torque`]).
    pub yaw_acceleration: f64,
    /// Per body axis, `sup |τ_i|` upper bound [N m].
    pub torque_max: [f64; 3],
    /// Best point values the searches saw.
    pub lower: TightLower,
    /// Boxes processed over all searches.
    pub boxes: usize,
}

/// The tight `sup |ω_d|` [rad/s] and `sup |ω̇_d|` [rad/s²] alone (two of [`tight_bounds`]'s
/// searches, the same values it returns for them without the correlated searches), for callers
/// that need only the desired rates (`design --bounds tight`, per candidate).
///
/// Errors: as [`tight_bounds`].
pub fn tight_rates(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    filter_start: FilterStart,
    options: &TightOptions,
) -> Result<(f64, f64), ParameterError> {
    let set = ConfiningSet::new(vehicle, gains, constants, filter_start)?;
    let run = |q| maximise(&set, q, options.relative_gap, options.max_boxes);
    let (w, (a, (h12, h3))) = rayon::join(
        || run(Quantity::AngularVelocity),
        || {
            rayon::join(
                || run(Quantity::AngularAcceleration),
                || {
                    rayon::join(
                        || run(Quantity::HorizontalAcceleration),
                        || run(Quantity::YawAcceleration),
                    )
                },
            )
        },
    );
    let p = interval::Interval::point;
    let composed = (p(h12.upper).sqr() + p(h3.upper).sqr()).sqrt().hi;
    Ok((w.upper, a.upper.min(composed)))
}

/// Tight bounds for one set-up: vehicle (`J`, `g`), gains (Table I), trajectory constants
/// (Assumption 1) and the filters' start.
///
/// Errors: [`ParameterError`] for an invalid vehicle, gain or trajectory constant, for
/// `M_p ≥ g − K_a3`, or for a `relative_gap` that is negative or not finite (reported as
/// `OutOfRange { name: "relative_gap" }`).
pub fn tight_bounds(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    filter_start: FilterStart,
    options: &TightOptions,
) -> Result<TightBounds, ParameterError> {
    if !(options.relative_gap.is_finite() && options.relative_gap >= 0.0) {
        return Err(ParameterError::OutOfRange {
            name: "relative_gap",
            value: options.relative_gap,
            low: 0.0,
            high: f64::INFINITY,
        });
    }
    let set = ConfiningSet::new(vehicle, gains, constants, filter_start)?;
    let run = |q, boxes| maximise(&set, q, options.relative_gap, boxes);
    let full = options.max_boxes;
    // The direct |ω̇_d| search: below the composed √(H₁₂² + H₃²) once converged, and it caps
    // the torque step's |q·ω̇_d| (torque.rs).
    let ((w, a), (h12, h3)) = rayon::join(
        || {
            (
                run(Quantity::AngularVelocity, full),
                run(Quantity::AngularAcceleration, full),
            )
        },
        || {
            rayon::join(
                || run(Quantity::HorizontalAcceleration, full),
                || run(Quantity::YawAcceleration, full),
            )
        },
    );
    let mut boxes = w.boxes + a.boxes + h12.boxes + h3.boxes;
    // The correlated searches bound the same suprema over a smaller superset of the confining
    // set (coupled_search): each bound is kept where smaller.
    let (mut h12_upper, mut a_upper) = (h12.upper, a.upper);
    if options.coupled_boxes > 0 {
        let polygon = FilterPolygon::new(vehicle, gains, constants, filter_start);
        let coupled = |q| {
            maximise_coupled(
                &set,
                &polygon,
                q,
                options.relative_gap,
                options.coupled_boxes,
            )
        };
        let (ch, ca) = rayon::join(
            || coupled(Quantity::HorizontalAcceleration),
            || coupled(Quantity::AngularAcceleration),
        );
        for (outcome, upper) in [(ch, &mut h12_upper), (ca, &mut a_upper)] {
            if let Some(o) = outcome {
                *upper = upper.min(o.upper);
                boxes += o.boxes;
            }
        }
    }
    // |ω̇_d|² = |(ω̇_d1, ω̇_d2)|² + ω̇_d3² ≤ H₁₂² + H₃²: a second bound, kept if smaller.
    let p = interval::Interval::point;
    let composed = (p(h12_upper).sqr() + p(h3.upper).sqr()).sqrt().hi;
    let acceleration = a_upper.min(composed);
    let inertia: [f64; 3] = vehicle.inertia.into();
    let mut torque_max = [0.0; 3];
    let mut torque_lower = [0.0; 3];
    for axis in 0..3 {
        let term = |h: f64, y: f64, total: f64| AttitudeTerm {
            axis,
            gains: gains.attitude,
            radius: 1.0 + gains.hysteresis,
            inertia: inertia[axis],
            horizontal_acceleration: h,
            yaw_acceleration: y,
            total_acceleration: total,
            trace_weights: gains
                .tilt_priority
                .map_or([0.0; 3], |t| t.trace_weights.into()),
        };
        // This search is cheap (3-D, no gradients): never looser than 0.1 % (at 1 % it left up
        // to 0.002 N m of the paper's torque bounds on the table, a tenth of a second to take).
        let phi_gap = options.relative_gap.min(0.001);
        let phi = term(h12_upper, h3.upper, acceleration).maximise(phi_gap, options.max_boxes);
        boxes += phi.boxes;
        let omega = gains
            .tilt_priority
            .map_or(gains.attitude.omega_saturation, |t| t.omega_levels[axis]);
        // Tilt priority's turn-over term (docs/turn-over.md) by its closed-form per-axis bound,
        // beside the damping's level (the triangle inequality; the search does not model it).
        let turn_over = gains
            .tilt_priority
            .map_or(0.0, |t| t.turn_over_bounds(gains.hysteresis)[axis]);
        torque_max[axis] = torque_bound(axis, omega + turn_over, phi.upper, inertia, w.upper);
        let phi_low = term(h12.lower, h3.lower, f64::INFINITY).maximise(phi_gap, options.max_boxes);
        torque_lower[axis] = torque_bound(axis, omega, phi_low.lower, inertia, w.lower);
    }
    Ok(TightBounds {
        angular_velocity: w.upper,
        angular_acceleration: acceleration,
        horizontal_acceleration: h12_upper,
        yaw_acceleration: h3.upper,
        torque_max,
        lower: TightLower {
            angular_velocity: w.lower,
            angular_acceleration: a.lower,
            horizontal_acceleration: h12.lower,
            yaw_acceleration: h3.lower,
            torque_max: torque_lower,
        },
        boxes,
    })
}
