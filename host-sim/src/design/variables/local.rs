//! The envelope design's local regime (docs/envelope-design.md): its decision variables, its
//! switching energies and the fit of its torque set inside the rotors, which slows its filters
//! until the set fits.

use controller_core::bounds::certify_without_joint_bound;
use controller_core::{FilterStart, Gains, Limits, LocalGains, VerticalChannel};
use nalgebra::Vector3;

use super::interval::{unit_in, value_in, Interval};
use super::{Context, LOCAL_DIMENSION};
use crate::design::authority::RotorFit;

/// The local regime's variables: `(low, high, logarithmic)`.
///
/// | # | variable | range |
/// |---|----------|-------|
/// | 0 | `k_f,L / k_f` | 1 to 30 (log) |
/// | 1 | `k_s,L / k_f,L` | 1.5 to 12 (log) |
/// | 2 | local position natural frequency `ω_p,L` | 0.5 to 8 rad/s (log) |
/// | 3 | local position damping `ζ_p,L` | 0.6 to 1.5 |
/// | 4 | the tilt error `θ_out` whose MRP potential is `E_out` | 2 to 60 degrees (log) |
/// | 5 | `M_p,L / M_p` | 0.25 to 4 (log): above 1, more authority near the reference than the
/// global level's worst-case torque allows |
pub(super) const LOCAL_RANGES: [Interval; LOCAL_DIMENSION] = [
    (1.0, 30.0, true),
    (1.5, 12.0, true),
    (0.5, 8.0, true),
    (0.6, 1.5, false),
    (2.0, 60.0, true),
    (0.25, 4.0, true),
];

/// The local regime's own vertical filters, one more variable after [`LOCAL_RANGES`]' when the
/// design searches them (`Layout::local_vertical`): `k_f,z,L / k_f,z`, 1 to 30 (log), with
/// `k_s,z,L / k_f,z,L` the global vertical filters' ratio.
pub(super) const LOCAL_VERTICAL_RANGE: Interval = (1.0, 30.0, true);

/// The name of [`LOCAL_VERTICAL_RANGE`]'s variable, as reports print it.
pub(super) const LOCAL_VERTICAL_NAME: &str = "k_f,z,L / k_f,z";

/// The name of the local integral frequency, one more variable after the others when the design
/// holds it apart (`Layout::local_integral`; the range of `ω_p,L`, variable 2), as reports print
/// it.
pub(super) const LOCAL_INTEGRAL_NAME: &str = "local integral and observer frequency [rad/s]";

/// The names of [`LOCAL_RANGES`]' variables, as reports print them.
pub(super) const LOCAL_NAMES: [&str; LOCAL_DIMENSION] = [
    "k_f,L / k_f",
    "k_s,L / k_f,L",
    "local position natural frequency [rad/s]",
    "local position damping",
    "theta_out [deg]",
    "M_p,L / M_p",
];

/// The envelope design's local regime, before it becomes gains (docs/envelope-design.md).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LocalChoices {
    /// `k_f,L / k_f`.
    pub kf_ratio: f64,
    /// `k_s,L / k_f,L`.
    pub ks_ratio: f64,
    /// Local position natural frequency [rad/s].
    pub position_frequency_rad_s: f64,
    /// Local position damping ratio.
    pub position_damping: f64,
    /// The tilt error \[deg\] at rest whose MRP potential is `E_out` (`E_in = E_out / 2`).
    pub tilt_out_deg: f64,
    /// `M_p,L / M_p`: the local regime's share of the saturation level.
    pub saturation_fraction: f64,
    /// `k_f,z,L / k_f,z`: the local regime's own vertical filters, both the global vertical
    /// filters times this (`None`, or 1: the global vertical filters in both regimes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vertical_kf_ratio: Option<f64>,
    /// The frequency `ω_i` [rad/s] at which the integral action and its observer are sized
    /// (`k_i = ω_i³/5`, observer gains `2ω_i`, `ω_i²`; `crate::design::integral`), apart from
    /// the local loop's (`None`: at `ω_p,L`). The local loop's polish holds it at the design's
    /// `ω_p,L` while the loop stiffens.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integral_frequency_rad_s: Option<f64>,
    /// Whether the envelope is narrowed when nothing fits at the chosen one (`local_gains`);
    /// not a coordinate of the box (`Layout::narrow_local`).
    #[serde(skip)]
    pub narrow: bool,
}

impl LocalChoices {
    /// The initial guess: filters twice the global ones (the fit then slows them as needed), a
    /// stiff 5 rad/s local loop, `E_out` at 30 degrees; the global vertical filters.
    pub fn initial_guess() -> Self {
        Self {
            vertical_kf_ratio: None,
            integral_frequency_rad_s: None,
            kf_ratio: 2.0,
            ks_ratio: 3.0,
            position_frequency_rad_s: 5.0,
            position_damping: 1.0,
            tilt_out_deg: 30.0,
            saturation_fraction: 0.7,
            narrow: false,
        }
    }

    /// From the local coordinates `x` of a point: [`LOCAL_RANGES`]' six, then
    /// [`LOCAL_VERTICAL_RANGE`]'s when `vertical`, then the integral frequency (in `ω_p,L`'s
    /// range) when `integral`.
    pub(super) fn from_unit(x: &[f64], narrow: bool, (vertical, integral): (bool, bool)) -> Self {
        let v = |i: usize| value_in(LOCAL_RANGES[i], x.get(i).copied().unwrap_or(0.5));
        let unit = x.get(LOCAL_RANGES.len()).copied().unwrap_or(0.0);
        let next = LOCAL_RANGES.len() + usize::from(vertical);
        let integral_unit = x.get(next).copied().unwrap_or(0.5);
        Self {
            vertical_kf_ratio: vertical.then(|| value_in(LOCAL_VERTICAL_RANGE, unit)),
            integral_frequency_rad_s: integral.then(|| value_in(LOCAL_RANGES[2], integral_unit)),
            kf_ratio: v(0),
            ks_ratio: v(1),
            position_frequency_rad_s: v(2),
            position_damping: v(3),
            tilt_out_deg: v(4),
            saturation_fraction: v(5),
            narrow,
        }
    }

    /// The local coordinates (inverse of [`LocalChoices::from_unit`], clamped).
    pub(super) fn to_unit(self) -> Vec<f64> {
        let values = [
            self.kf_ratio,
            self.ks_ratio,
            self.position_frequency_rad_s,
            self.position_damping,
            self.tilt_out_deg,
            self.saturation_fraction,
        ];
        (0..LOCAL_DIMENSION)
            .map(|i| unit_in(LOCAL_RANGES[i], values[i]))
            .chain(
                self.vertical_kf_ratio
                    .map(|r| unit_in(LOCAL_VERTICAL_RANGE, r)),
            )
            .chain(
                self.integral_frequency_rad_s
                    .map(|w| unit_in(LOCAL_RANGES[2], w)),
            )
            .collect()
    }
}

/// `E_out` \[J\] of `l`: the MRP potential `Ψ(ϑ) = (M_ϑ/k_ϑ)(√(M_ϑ² + k_ϑ²ϑ²) − M_ϑ)` of a rotation
/// by `θ_out` at rest (`ϑ = tan(θ_out/4)`).
pub fn energy_out(g: &Gains<f64>, l: &LocalChoices) -> f64 {
    let (m, k) = (g.attitude.mrp_saturation, g.attitude.k_mrp);
    let mrp = (l.tilt_out_deg.to_radians() / 4.0).tan();
    (m / k) * ((m * m + k * k * mrp * mrp).sqrt() - m)
}

/// Whether the local regime `local` added to `g` leaves its torque set inside the rotors as the
/// design's fit asks (the shadow with airmode, the certified thrust interval otherwise, both with
/// the margin). `false` when `certify` refuses it.
fn local_fits(ctx: &Context<'_>, g: &Gains<f64>, local: LocalGains<f64>) -> bool {
    let gains = Gains {
        local: Some(local),
        ..*g
    };
    let limits = Limits {
        thrust_max: 1.0,
        torque_max: Vector3::repeat(1.0),
    };
    // Only the local regime's set and Theorem 1's interval are read: the global set's joint
    // bound of the attitude terms is not built (this runs at every step of a bisection).
    let Ok(c) = certify_without_joint_bound(
        ctx.vehicle,
        &limits,
        &gains,
        ctx.constants,
        FilterStart::Zero,
    ) else {
        return false;
    };
    let Some(l) = c.local else {
        return false;
    };
    let b = &c.bounds;
    // The board re-evaluates these fits in f32 from the flight file's decimals: the local
    // filters are bisected onto the fit's boundary, so keep `F32_SLACK` of the rotor range more
    // than the margin, or the gate could refuse by rounding what the host accepted.
    let margin = ctx.margin + F32_SLACK;
    match ctx.fit {
        // Theorem 1's interval (the hull of both regimes') at zero torque, and the shadow.
        RotorFit::Airmode => {
            let thrust_alone = controller_core::TorqueSet::boxed(Vector3::zeros());
            crate::design::authority::set_margin(
                ctx.rotors,
                (b.thrust_min, b.thrust_max),
                &thrust_alone,
            ) >= margin
                && ctx.rotors.envelope(margin).shadow_margin(&l.torque_set) >= 0.0
        }
        RotorFit::Set => {
            crate::design::authority::set_margin(
                ctx.rotors,
                (b.thrust_min, b.thrust_max),
                &l.torque_set,
            ) >= margin
        }
    }
}

/// Headroom [fraction of the rotor range] the local regime's fits keep above the margin, for
/// the board's f32 re-evaluation (the flight file's x500 design: 2.2e-4 short without it).
pub const F32_SLACK: f64 = 2e-3;

/// The local regime of `l` for the global gains `g`: its filters as chosen when its torque set
/// fits ([`local_fits`]), else slowed (bisection on `k_f,L / k_f` towards 1, 40 steps, keeping
/// `k_s,L / k_f,L`); when even `k_f,L = k_f` does not fit with a local level above the global
/// one, the same with `M_p,L = M_p`. When nothing fits at the chosen envelope `θ_out` and
/// `l.narrow`, the envelope is narrowed instead ([`narrowed`]). With local vertical filters
/// (`l.vertical_kf_ratio` above 1 and the vertical channel apart) all of this is tried with them
/// first, then with the global vertical filters. `None` when nothing fits (even at the
/// narrowest).
pub(super) fn local_gains(
    ctx: &Context<'_>,
    g: &Gains<f64>,
    l: &LocalChoices,
) -> Option<LocalGains<f64>> {
    let own = match (l.vertical_kf_ratio, g.position.vertical) {
        (Some(r), Some(v)) if r > 1.0 => Some(VerticalChannel {
            kf: v.kf * r,
            ks: v.ks * r,
            ..v
        }),
        _ => None,
    };
    let verticals = [own, None];
    let tried = if own.is_some() {
        &verticals[..]
    } else {
        &verticals[1..]
    };
    tried
        .iter()
        .find_map(|&vertical| local_gains_with(ctx, g, l, vertical))
}

/// [`local_gains`] with the local vertical filters `vertical`.
fn local_gains_with(
    ctx: &Context<'_>,
    g: &Gains<f64>,
    l: &LocalChoices,
    vertical: Option<VerticalChannel<f64>>,
) -> Option<LocalGains<f64>> {
    let wp = l.position_frequency_rad_s;
    let build = |ratio: f64, fraction: f64, tilt_out_deg: f64| {
        let kf = g.position.kf * ratio;
        let e_out = energy_out(g, &LocalChoices { tilt_out_deg, ..*l });
        LocalGains {
            kp: wp * wp,
            kv: 2.0 * l.position_damping * wp,
            kf,
            ks: kf * l.ks_ratio,
            saturation: fraction * g.position.saturation,
            energy_in: 0.5 * e_out,
            energy_out: e_out,
            vertical,
            attitude: None,
            // The search's local regimes brake at the global braking (refused below it): a
            // level under it would brake a step more slowly than the global regime. The
            // agility refinement sets a braking of the local level's own.
            braking: g.velocity_limit.map(|v| v.braking),
        }
    };
    let fractions = [l.saturation_fraction, l.saturation_fraction.min(1.0)];
    let levels = if fractions[0] > fractions[1] {
        &fractions[..]
    } else {
        &fractions[..1]
    };
    let at = |fraction: f64, tilt: f64| {
        let fits = |ratio: f64| local_fits(ctx, g, build(ratio, fraction, tilt));
        if fits(l.kf_ratio) {
            return Some(l.kf_ratio);
        }
        if !fits(1.0) {
            return None;
        }
        Some(crate::design::bisect::bisect(1.0, l.kf_ratio, 40, fits))
    };
    let chosen = levels.iter().find_map(|&fraction| {
        at(fraction, l.tilt_out_deg).map(|ratio| build(ratio, fraction, l.tilt_out_deg))
    });
    if !l.narrow {
        return chosen;
    }
    chosen.or_else(|| {
        levels.iter().find_map(|&fraction| {
            let fits = |ratio: f64, tilt: f64| local_fits(ctx, g, build(ratio, fraction, tilt));
            narrowed(l, fits).map(|(ratio, tilt)| build(ratio, fraction, tilt))
        })
    })
}

/// The narrowest envelope `θ_out` \[deg\] the design narrows a local regime to: the low end of
/// its range.
const NARROWEST_TILT_OUT_DEG: f64 = LOCAL_RANGES[4].0;

/// `(k_f,L / k_f, θ_out [deg])` for a local regime whose torque set fits at no filter ratio
/// with the chosen envelope `l.tilt_out_deg` (`fits(ratio, θ_out)`): a smaller `E_out` bounds
/// the attitude error by which the local torque set turns the feedforward, so the set shrinks
/// with `θ_out` (docs/envelope-design.md). With the chosen filters the widest `θ_out` in
/// [[`NARROWEST_TILT_OUT_DEG`], chosen] that fits (bisection, 40 steps); if none, at the
/// narrowest envelope the fastest ratio in [1, chosen] that fits; `None` when even `k_f,L = k_f`
/// does not fit there. Why: without it most of the search box of a vehicle with little yaw
/// torque (the x500) has no local regime, a flat objective the search cannot climb out of.
fn narrowed(l: &LocalChoices, fits: impl Fn(f64, f64) -> bool) -> Option<(f64, f64)> {
    let (ratio, widest) = (l.kf_ratio, l.tilt_out_deg);
    let narrowest = NARROWEST_TILT_OUT_DEG.min(widest);
    if fits(ratio, narrowest) {
        let tilt = crate::design::bisect::bisect(narrowest, widest, 40, |t| fits(ratio, t));
        return Some((ratio, tilt));
    }
    if !fits(1.0, narrowest) {
        return None;
    }
    let ratio = crate::design::bisect::bisect(1.0, ratio, 40, |r| fits(r, narrowest));
    Some((ratio, narrowest))
}

#[cfg(test)]
mod tests;
