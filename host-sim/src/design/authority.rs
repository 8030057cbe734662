//! Certified authority in closed form: for fixed `(M_p, k_f, k_s)` and reference constants,
//! Theorem 1 fixes the thrust interval `[T_min, T_max]` and Lemma 1 fixes `U_ωd`, `U_ω̇d`, so the
//! per-axis torque bound of Theorem 2 is `ff_i + ι` with
//! `ff_i = J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²` and `ι = (1 + (1 + δ)²) M_ϑ/4 + M_ω`.
//!
//! The rotor fit (`firmware::mixer::Mixer::set_margin`): rotor `k` receives
//! `f_k = w_k T + c_kᵀτ` (`M = B⁻¹`, `w_k = M_k0 > 0`, `c_k` the rest of row `k`), and the torque
//! lies in the certified set `S` of Theorem 2's terms (`controller_core::TorqueSet`: the
//! feedforward's ellipsoid and gyroscopic box, plus the feedback's ball of radius `ι` for the
//! paper's law), so `[T_min, T_max] × S` fits the range shrunk by the margin,
//! `[lo', hi'] = [lo + m Δ, hi − m Δ]` (`Δ = hi − lo`), iff for every rotor
//! `w_k T_max + h_ff(c_k) + ι |c_k| ≤ hi'` and `w_k T_min − h_ff(c_k) − ι |c_k| ≥ lo'`
//! (`h_ff` the support function of the feedforward's part): linear in `ι`, hence the largest
//! `ι` in closed form ([`iota_max`]). Per-axis feedback levels (tilt priority) are proposed
//! with their box, `Σ_i |c_ki| ι_i` (it contains their set, so the certificate can only find
//! more room). With the tight bounds (`--bounds tight`) the set keeps its shape and takes the
//! least of its norms of `ω_d`, `ω̇_d` and theirs ([`super::tight::tightened_set`]). An
//! envelope without a feedforward set stands for the box of the per-axis bounds, whose fit is
//! `Σ_i |c_ki| (ff_i + ι_i)`: kept to measure what the set's shape frees.
//! This module only *proposes* numbers; the certificate of a design comes from
//! `controller_core::bounds::certify` and `Mixer::set_margin` ([`super::certificate`]).

use super::integral::IntegralSpec;
use controller_core::{
    certify, Bounds, FilterStart, Gains, Lemma1Form, Limits, PositionSaturation, RotorEnvelope,
    TorqueSet, TrajectoryConstants, Vehicle,
};
use firmware::config::RotorConfig;
use firmware::mixer::Mixer;
use nalgebra::{Matrix4, Vector3};

/// The paper's hysteresis `δ` (Table I), kept by every design.
pub const DELTA: f64 = 0.02;
/// The paper's reset threshold `α` (Table I), kept by every design.
pub const ALPHA: f64 = 0.25;

/// `(1 + (1 + δ)²)/4`: the factor of `M_ϑ` in `ι`.
pub fn mrp_factor() -> f64 {
    (1.0 + (1.0 + DELTA).powi(2)) / 4.0
}

/// The rotor set in f64: mixing matrix `M = B⁻¹` (rows motors; columns `T, τx, τy, τz`) and the
/// thrust range \[N\].
#[derive(Clone, Copy, Debug)]
pub struct RotorSet {
    /// `M = B⁻¹` of the firmware mixer.
    pub mix: Matrix4<f64>,
    /// Per-rotor thrust range `(lo, hi)` \[N\].
    pub range: (f64, f64),
    /// The firmware's mixer itself, for what `design` must judge exactly as the board does.
    mixer: Mixer,
}

impl RotorSet {
    /// From the firmware's mixer for `rotors`. Errors: the mixer's (degenerate geometry, empty
    /// range), as text.
    pub fn new(rotors: &RotorConfig) -> Result<Self, String> {
        let mixer = Mixer::new(rotors).map_err(|e| format!("{e:?}"))?;
        let (lo, hi) = mixer.thrust_range();
        Ok(Self {
            mix: mixer.mixing().map(f64::from),
            range: (f64::from(lo), f64::from(hi)),
            mixer,
        })
    }

    /// The torque capacity [N m] on each body axis alone (the other torques at zero), the
    /// limits `τ_max,i` `design` writes (`[limits] torque_max_Nm`): with `fit` airmode's, the
    /// largest `t` with `±t e_i` in the rotors' shadow (at the best thrust for it); else the
    /// firmware mixer's capacity over the thrust interval `thrust` \[N\] (`Mixer::box_fit`,
    /// in f32 as the board computes it). No errors.
    pub fn axis_capacity(&self, fit: RotorFit, thrust: (f64, f64)) -> Vector3<f64> {
        match fit {
            RotorFit::Airmode => {
                let shadow = self.envelope(0.0);
                Vector3::from_fn(|i, _| shadow.shadow_axis(i))
            }
            RotorFit::Set => {
                let (t_lo, t_hi) = (thrust.0 as f32, thrust.1 as f32);
                let fit = self.mixer.box_fit(t_lo, t_hi, &Vector3::zeros());
                Vector3::from(fit.torque_capacity.map(f64::from))
            }
        }
    }

    /// The range shrunk by `margin` (fraction of the range) at both ends \[N\].
    pub fn shrunk(&self, margin: f64) -> (f64, f64) {
        let (lo, hi) = self.range;
        let m = margin * (hi - lo);
        (lo + m, hi - m)
    }

    /// Largest collective thrust the rotors give \[N\] (`Σ_k hi`).
    pub fn thrust_total_max(&self) -> f64 {
        4.0 * self.range.1
    }

    /// The core's envelope of these rotors with the range shrunk by `margin` (fraction of the
    /// range at both ends): the set airmode keeps the law's `(T, τ)` in.
    /// Panics only if the mixer's thrust column has a non-positive entry, which
    /// [`RotorSet::new`]'s mixer never builds for four rotors that carry collective.
    pub fn envelope(&self, margin: f64) -> RotorEnvelope<f64> {
        let m = &self.mix;
        let rows = [0, 1, 2, 3].map(|k| [m[(k, 0)], m[(k, 1)], m[(k, 2)], m[(k, 3)]]);
        let (lo, hi) = self.shrunk(margin);
        RotorEnvelope::new(rows, lo, hi).expect("a quad's mixer rows carry collective")
    }
}

/// How a certified set must sit in the rotors' set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RotorFit {
    /// The whole certified thrust interval times the torque set (every torque at both thrust
    /// ends; the mixer's set fit, docs/torque-set.md).
    #[default]
    Set,
    /// Airmode (docs/airmode.md): every torque of the set at *some* thrust (the shadow fit); the
    /// thrust moves where a torque needs it. Whether the feedforward at zero attitude error also
    /// fits the whole thrust interval (the aligned fit, with which airmode's convergence argument
    /// is proven) is reported, not required.
    Airmode,
}

/// The thrust interval and the feedforward part of Theorem 2's torque bound for one
/// `(M_p, k_f, k_s)`.
#[derive(Clone, Copy, Debug)]
pub struct Envelope {
    /// `[T_min, T_max]` of Theorem 1 \[N\].
    pub thrust: (f64, f64),
    /// `ff_i = J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²` [N m].
    pub feedforward: Vector3<f64>,
    /// The feedforward's part of the certified torque set (ellipsoid and gyroscopic box, no
    /// feedback; [`TorqueSet`]). `None`: the certified set is the box of
    /// [`Envelope::feedforward`] plus the feedback levels (no design builds it; the closed
    /// forms keep it to measure what the set's shape frees).
    pub feedforward_set: Option<TorqueSet<f64>>,
    /// All bounds (with the probe's `ι`, which [`Envelope::feedforward`] removes).
    pub bounds: Bounds<f64>,
}

/// What of the position law, besides `(M_p, k_f, k_s)`, enters Theorem 1's interval and
/// Lemma 1's bounds: the integral action and the shape of `σ_p`.
#[derive(Clone, Copy, Debug, Default)]
pub struct PositionLaw<'a> {
    /// `Some`: the bounded integral action sized by this spec (the extended bounds,
    /// docs/integral-action.md).
    pub integral: Option<&'a IntegralSpec>,
    /// The shape of `σ_p`: the paper's componentwise one or the norm one
    /// (docs/position-saturation.md).
    pub shape: PositionSaturation,
    /// The chain `certify` bounds `|ω̇_d|` with: the paper's Lemma 1 or its tangential form
    /// (docs/tangential-lemma1.md); not a position law, but it enters the same bounds.
    pub lemma1: Lemma1Form,
    /// `Some((up, down, kf, ks))`: the vertical channel apart (docs/vertical-channel.md), its
    /// levels `M_up = up M_p` and `M_down = down M_p` and its filters `k_f,z = kf k_f`,
    /// `k_s,z = ks k_f,z` (ratios, dimensionless).
    pub vertical: Option<(f64, f64, f64, f64)>,
    /// `Some`: the desired frame built from the compensated heading with these gains
    /// (docs/heading-compensator.md); it enters the same bounds.
    pub heading: Option<controller_core::HeadingCompensatorGains<f64>>,
}

impl PositionLaw<'_> {
    /// The paper's position law: no integral action, the componentwise `σ_p`, the paper's
    /// Lemma 1.
    pub fn paper() -> Self {
        Self::default()
    }
}

/// Probe gains: every value that does not enter the bounds of Theorem 1 / Lemma 1 is set to 1
/// (Table I's); the shape of `σ_p` from `law`; with `law.integral`, its bound terms for `k_f`,
/// `k_s` ([`IntegralSpec::probe`]), so the bounds are the extended ones
/// (docs/integral-action.md).
pub fn probe_gains(mp: f64, kf: f64, ks: f64, law: PositionLaw<'_>) -> Gains<f64> {
    let mut g = Gains::<f64>::paper();
    g.position.saturation = mp;
    g.position.saturation_shape = law.shape;
    g.lemma1 = law.lemma1;
    g.position.kf = kf;
    g.position.ks = ks;
    g.hysteresis = DELTA;
    g.reset_threshold = ALPHA;
    g.integral = law.integral.map(|i| i.probe(kf, ks));
    g.heading_compensator = law.heading;
    g.position.vertical =
        law.vertical
            .map(|(up, down, kf_z, ks_z)| controller_core::VerticalChannel {
                up: up * mp,
                down: down * mp,
                kf: kf_z * kf,
                ks: ks_z * kf_z * kf,
            });
    g
}

/// Theorem 1's thrust interval and Lemma 1's feedforward torque for `(M_p, k_f, k_s)` and the
/// position law `law` (extended by the integral action when `law.integral` is `Some`). `None` when `certify` refuses the set-up
/// (e.g. `M_p ≥ g − K_a3`, or `M_p + M_i,z ≥ g − K_a3` with the integral action).
pub fn envelope(
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    (mp, kf, ks): (f64, f64, f64),
    law: PositionLaw<'_>,
) -> Option<Envelope> {
    // The bounds do not depend on the limits; any valid ones do.
    let limits = Limits {
        thrust_max: 1.0,
        torque_max: Vector3::repeat(1.0),
    };
    let c = certify(
        vehicle,
        &limits,
        &probe_gains(mp, kf, ks, law),
        constants,
        FilterStart::Zero,
    )
    .ok()?;
    let b = c.bounds;
    // The certified set's norms of `ω_d`, `ω̇_d` (`Bounds::torque_set`'s).
    let (rate, acceleration) = b
        .desired_frame
        .norm_bounds((b.angular_velocity, b.angular_acceleration));
    Some(Envelope {
        thrust: (b.thrust_min, b.thrust_max),
        feedforward: b.torque_max - b.feedback_torque_axes,
        feedforward_set: Some(TorqueSet::new(
            vehicle.inertia,
            rate,
            acceleration,
            0.0,
            Vector3::zeros(),
        )),
        bounds: b,
    })
}

/// [`envelope`] with the feedforward part of the torque bound taken from `bounds`: with
/// [`super::tight::BoundsKind::Tight`], per axis the least of Lemma 1's and
/// [`super::tight::tight_feedforward`], and the feedforward's set with the least norms
/// ([`super::tight::tightened_set`]), the tight ones at [`super::tight::SEARCH_BOXES`] boxes per
/// search.
pub fn envelope_with(
    bounds: super::tight::BoundsKind,
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    (mp, kf, ks): (f64, f64, f64),
    law: PositionLaw<'_>,
) -> Option<Envelope> {
    let mut env = envelope(vehicle, constants, (mp, kf, ks), law)?;
    if bounds == super::tight::BoundsKind::Tight {
        let rates = super::tight::rates(
            vehicle,
            &probe_gains(mp, kf, ks, law),
            constants,
            super::tight::SEARCH_BOXES,
        )
        .ok()?;
        env.feedforward = env
            .feedforward
            .inf(&super::tight::tight_feedforward(vehicle, rates));
        env.feedforward_set = env
            .feedforward_set
            .map(|set| super::tight::tightened_set(&set, rates));
    }
    Some(env)
}

/// The largest `ι` [N m] for which the certified set of `env` with the paper's feedback (a
/// ball of radius `ι`; the box `ι` per axis without a feedforward set) fits `rotors` with `margin`
/// (fraction of the range at both ends); negative when even `ι = 0` does not fit.
pub fn iota_max(rotors: &RotorSet, env: &Envelope, margin: f64) -> f64 {
    iota_max_shaped(rotors, env, margin, None)
}

/// The largest `ι` [N m] for which the set with per-axis feedback levels `ι d` (a box;
/// `d` \[dimensionless\], each `≥ 0`, body axes: tilt priority's `(1, 1, ρ)`) fits `rotors`
/// with `margin`: the closed form of [`iota_max`] with the ball's `|c_k|` replaced by
/// `Σ_i |c_ki| d_i`. Negative when even `ι = 0` does not fit.
pub fn iota_max_along(
    rotors: &RotorSet,
    env: &Envelope,
    margin: f64,
    direction: &Vector3<f64>,
) -> f64 {
    iota_max_shaped(rotors, env, margin, Some(direction))
}

/// The largest `ι` [N m] for which the feedforward's set of `env` plus the feedback set
/// `feedback(ι)` (its ball, disks and box; the feedforward fields of what it returns are
/// ignored) fits `rotors` with `margin`, by bisection (60 steps) between `lower` (a level known
/// to fit, e.g. [`iota_max_along`]'s box, `> 0`) and the first of `2ᵏ lower` that does not fit.
/// For feedback sets that grow with `ι` (tilt priority's, whose shape changes with `ι` where
/// the hysteresis band caps `g₃`, so no closed form). `lower` itself when `env` has no
/// feedforward set (the box).
pub fn iota_max_by(
    rotors: &RotorSet,
    env: &Envelope,
    (margin, fit): (f64, RotorFit),
    lower: f64,
    feedback: impl Fn(f64) -> TorqueSet<f64>,
) -> f64 {
    let Some(ff) = env.feedforward_set else {
        return lower;
    };
    let shrunk = rotors.envelope(margin);
    let fits = |iota: f64| {
        let fb = feedback(iota);
        let set = TorqueSet {
            feedback_radius: fb.feedback_radius,
            feedback_box: fb.feedback_box,
            feedback_disks: fb.feedback_disks,
            attitude_joint: fb.attitude_joint,
            ..ff
        };
        match fit {
            RotorFit::Set => set_margin(rotors, env.thrust, &set) >= margin,
            RotorFit::Airmode => shrunk.shadow_margin(&set) >= 0.0,
        }
    };
    if !(lower > 0.0 && fits(lower)) {
        return lower;
    }
    let mut upper = 2.0 * lower;
    for _ in 0..40 {
        if !fits(upper) {
            break;
        }
        upper *= 2.0;
    }
    super::bisect::bisect(lower, upper, 60, fits)
}

/// The largest `ι` [N m] for which Theorem 2's per-axis conditions hold with the feedback
/// levels `ι d` (`d` \[dimensionless\], body axes: the paper's `(1, 1, 1)`, tilt priority's
/// `(1, 1, ρ)`): `τ_max,i > ff_i + ι d_i` with `ff` = [`Envelope::feedforward`]
/// (`J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²` with the norms of the envelope's Lemma 1 form: the
/// chain's, or with [`Lemma1Form::DesiredFrame`] the certified set's; with the tight bounds the
/// least of it and the tight one, which is what their conditions are judged with), each axis's
/// capacity `τ_max,i` the one `design` writes as the limit (the rotors' on that axis alone: with
/// `fit` airmode's shadow, else over `env`'s thrust interval). Unless the form is the desired
/// frame's, the certified set takes tighter norms than these conditions (docs/torque-set.md), so
/// a set that fits does not imply them; the search caps `ι` by this as well. `-∞` when Assumption 1's per-axis conditions
/// (eq:TorqueMaxCondition) fail against the same capacities; negative when even `ι = 0` fails.
/// Source: eq:TorqueMaxConditionsTheorem.
pub fn theorem2_iota_max(
    rotors: &RotorSet,
    env: &Envelope,
    fit: RotorFit,
    direction: &Vector3<f64>,
) -> f64 {
    theorem2_iota_max_axes(rotors, env, fit, direction).min()
}

/// [`theorem2_iota_max`] axis by axis: the largest `ι` [N m] each body axis's condition leaves
/// (`+∞` on an axis where `direction` is 0; `-∞` on an axis where Assumption 1's condition
/// fails), so the least one names the binding axis ([`super::binding`]). No errors.
/// Source: eq:TorqueMaxConditionsTheorem, eq:TorqueMaxCondition.
pub fn theorem2_iota_max_axes(
    rotors: &RotorSet,
    env: &Envelope,
    fit: RotorFit,
    direction: &Vector3<f64>,
) -> Vector3<f64> {
    let feedforward = env.feedforward;
    // Strict conditions, judged again in f32 by the gate: keep a relative hair below.
    let capacity = rotors.axis_capacity(fit, env.thrust) * (1.0 - 1e-6);
    // Assumption 1's conditions (the reference's feedforward alone) leave no room for `ι` but
    // must hold as well: Lemma 1's terms contain them, the tight ones need not.
    let reference = reference_torque_extents(env);
    Vector3::from_fn(|i, _| {
        if capacity[i] <= reference[i] {
            f64::NEG_INFINITY
        } else if direction[i] > 0.0 {
            (capacity[i] - feedforward[i]) / direction[i]
        } else {
            f64::INFINITY
        }
    })
}

/// The torque [N m] per body axis the reference's feedforward alone needs, with Assumption 1's
/// starred bounds on its angular velocity and acceleration (eq:TorqueMaxCondition). No errors.
pub fn reference_torque_extents(env: &Envelope) -> Vector3<f64> {
    let a = &env.bounds.assumption;
    TorqueSet::new(
        env.bounds.torque_set.inertia,
        a.angular_velocity,
        a.angular_acceleration,
        0.0,
        Vector3::zeros(),
    )
    .axis_extents()
}

/// [`iota_max`] (`levels` `None`: the paper's radial feedback) or [`iota_max_along`].
fn iota_max_shaped(
    rotors: &RotorSet,
    env: &Envelope,
    margin: f64,
    levels: Option<&Vector3<f64>>,
) -> f64 {
    let (lo, hi) = rotors.shrunk(margin);
    let (t_lo, t_hi) = env.thrust;
    let mut best = f64::INFINITY;
    for k in 0..4 {
        let w = rotors.mix[(k, 0)];
        let c = Vector3::from_fn(|i, _| rotors.mix[(k, i + 1)]);
        let e = c.abs();
        let ff = match &env.feedforward_set {
            Some(set) => set.support(&c),
            None => e.dot(&env.feedforward),
        };
        let s = match (levels, &env.feedforward_set) {
            (Some(d), _) => e.dot(d),
            (None, Some(_)) => c.norm(),
            (None, None) => e.sum(),
        };
        if w <= 0.0 || s <= 0.0 {
            return f64::NEG_INFINITY;
        }
        best = best
            .min((hi - w * t_hi - ff) / s)
            .min((w * t_lo - lo - ff) / s);
    }
    best
}

/// Airmode's `ι_max` [N m] for the paper's feedback (a ball of radius `ι`): the largest `ι` for
/// which every torque of the feedforward's set plus the ball is realised at some thrust on the
/// range shrunk by `margin` (the shadow fit, [`RotorEnvelope::shadow_margin`]): per ordered pair
/// of rotors `(k, l)` with `d = w_k c_l − w_l c_k`, `h_ff(d) + ι |d| ≤ w_k hi' − w_l lo'`, linear
/// in `ι`. Negative when even `ι = 0` does not fit; `-∞` without a feedforward set (the box).
pub fn shadow_iota_max(rotors: &RotorSet, env: &Envelope, margin: f64) -> f64 {
    let Some(ff) = env.feedforward_set else {
        return f64::NEG_INFINITY;
    };
    let e = rotors.envelope(margin);
    let (lo, hi) = e.range;
    let mut best = f64::INFINITY;
    for k in 0..4 {
        for l in 0..4 {
            if k != l {
                let (wk, wl) = (e.collective[k], e.collective[l]);
                let d = e.torque[l] * wk - e.torque[k] * wl;
                best = best.min((wk * hi - wl * lo - ff.support(&d)) / d.norm());
            }
        }
    }
    best
}

/// Whether Theorem 1's thrust interval of `env` alone (no torque) fits the rotors' range shrunk
/// by `margin`: with airmode the torque set need only fit at some thrust, but the law's own
/// thrust must stay realisable (Theorem 1's condition on the actuator's `T_max`, with the margin).
pub fn thrust_fits(rotors: &RotorSet, env: &Envelope, margin: f64) -> bool {
    rotors.envelope(margin).set_margin(
        env.thrust.0,
        env.thrust.1,
        &TorqueSet::boxed(Vector3::zeros()),
    ) >= 0.0
}

/// Whether the feedforward at zero attitude error (`Bounds::aligned_feedforward`) fits the
/// certified thrust interval of `env` strictly inside the range shrunk by `margin`: with it,
/// airmode leaves the law's thrust unchanged near convergence (docs/airmode.md).
pub fn aligned_fits(rotors: &RotorSet, env: &Envelope, margin: f64) -> bool {
    rotors
        .envelope(margin)
        .set_margin(env.thrust.0, env.thrust.1, &env.bounds.aligned_feedforward)
        > 0.0
}

/// `ι_max` for `(M_p, k_f, k_s)` with the paper's feedback: the least of the rotor fit's
/// ([`iota_max`]) and Theorem 2's per-axis conditions' ([`theorem2_iota_max`]); `-∞` when the
/// bounds are undefined.
pub fn iota_max_at(
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    rotors: &RotorSet,
    margin: f64,
    (mp, kf, ks): (f64, f64, f64),
) -> f64 {
    envelope(vehicle, constants, (mp, kf, ks), PositionLaw::paper())
        .map(|env| {
            iota_max(rotors, &env, margin).min(theorem2_iota_max(
                rotors,
                &env,
                RotorFit::Set,
                &Vector3::repeat(1.0),
            ))
        })
        .unwrap_or(f64::NEG_INFINITY)
}

/// The largest `M_p` [m/s²] in `(0, g − K_a3)` with `ι_max > 0` for `(k_f, k_s)` (bisection:
/// `ι_max` decreases with `M_p`, since `T_min` falls, `T_max` rises and `U_ωd`, `U_ω̇d` grow).
/// `None` when even `M_p → 0` leaves no positive `ι`.
pub fn saturation_max(
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    rotors: &RotorSet,
    margin: f64,
    kf: f64,
    ks: f64,
) -> Option<f64> {
    saturation_max_with(
        super::tight::BoundsKind::Paper,
        vehicle,
        constants,
        (rotors, margin, RotorFit::Set),
        (kf, ks),
        PositionLaw::paper(),
    )
}

/// [`saturation_max`] with the feedforward of `bounds` ([`envelope_with`]). With the tight
/// bounds each step is a branch and bound, so the bisection stops after 12 steps (the bracket
/// at `2⁻¹²` of `g − K_a3`) instead of 60; the value returned is always one where `ι_max > 0`
/// was evaluated.
pub fn saturation_max_with(
    bounds: super::tight::BoundsKind,
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    (rotors, margin, fit): (&RotorSet, f64, RotorFit),
    (kf, ks): (f64, f64),
    law: PositionLaw<'_>,
) -> Option<f64> {
    let top = super::binding::saturation_top(vehicle, constants, law);
    if top <= 0.0 {
        return None;
    }
    // Some feedback fits the rotors, and Theorem 2's per-axis conditions leave some too.
    let positive = |mp: f64| {
        super::binding::saturation_blocked(
            bounds,
            vehicle,
            constants,
            (rotors, margin, fit),
            (mp, kf, ks),
            law,
        )
        .is_none()
    };
    let steps = match bounds {
        super::tight::BoundsKind::Paper => 60,
        super::tight::BoundsKind::Tight => 12,
    };
    let (lo, hi) = (top * 1e-6, top * (1.0 - 1e-9));
    if !positive(lo) {
        return None;
    }
    if positive(hi) {
        return Some(hi);
    }
    Some(super::bisect::bisect(lo, hi, steps, positive))
}

/// Smallest headroom over rotors and the 16 corners of the box `T ∈ {t_lo, t_hi}`,
/// `τ_i = ±tau_i`, as a fraction of the rotor range (negative: a corner leaves the range).
/// Evaluated corner by corner through `M`, independently of `Mixer::box_fit`.
pub fn box_margin(rotors: &RotorSet, thrust: (f64, f64), tau: &Vector3<f64>) -> f64 {
    let (lo, hi) = rotors.range;
    let mut worst = f64::INFINITY;
    for corner in 0..16u32 {
        let t = if corner & 1 == 0 { thrust.0 } else { thrust.1 };
        let sign = |bit: u32| if corner & (1 << bit) == 0 { -1.0 } else { 1.0 };
        let request = nalgebra::Vector4::new(t, sign(1) * tau.x, sign(2) * tau.y, sign(3) * tau.z);
        let f = rotors.mix * request;
        for k in 0..4 {
            worst = worst.min((f[k] - lo).min(hi - f[k]) / (hi - lo));
        }
    }
    worst
}

/// Smallest headroom of `[thrust.0, thrust.1] × set` over the rotors, as a fraction of the
/// rotor range (negative: the set leaves the range): rotor `k`'s extremes are
/// `w_k T_hi + h(c_k)` and `w_k T_lo − h(c_k)` ([`TorqueSet::support`]). The f64 twin of the
/// firmware's `Mixer::set_margin`, for reports.
pub fn set_margin(rotors: &RotorSet, thrust: (f64, f64), set: &TorqueSet<f64>) -> f64 {
    let (lo, hi) = rotors.range;
    let mut worst = f64::INFINITY;
    for k in 0..4 {
        let w = rotors.mix[(k, 0)];
        let h = set.support(&Vector3::from_fn(|i, _| rotors.mix[(k, i + 1)]));
        worst = worst
            .min(hi - (w * thrust.1 + h))
            .min(w * thrust.0 - h - lo);
    }
    worst / (hi - lo)
}

#[cfg(test)]
mod tests;
