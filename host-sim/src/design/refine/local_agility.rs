//! The local regime's agility refined last (docs/envelope-design.md, "What `design`
//! searches"): every global gain held, a particle swarm over what the local regime alone
//! flies, kept only where it scores lower.
//!
//! What it searches, around the design's own local regime (the swarm starts there):
//! - the local filters, level and braking: `k_f,L`, `k_s,L`, `M_p,L` and the local regime's
//!   own horizontal braking (`LocalGains::braking`, a share of `M_p,L`; the global braking at
//!   the local level's share otherwise never brakes harder than the global level affords);
//! - the local position loop's natural frequency and damping;
//! - the local regime's own attitude law (`LocalAttitude`): a stiffer radial MRP term
//!   (the natural frequency about the roll axis, `k_ϑ,L = k_ϑ + 16 J₁₁(ω_a,L² − ω_a²)` since
//!   the MRP is a quarter of the angle), its level `M_ϑ,L`, and the roll and pitch damping at
//!   a damping ratio of that stiffness with its own level; the yaw damping and the trace
//!   weights stay the global law's;
//! - the envelope: the tilt at rest whose local energy is `E_out` (`E_in = E_out / 2`);
//! - with the vertical channel apart, the local vertical levels and filters.
//!
//! Why: the global gains are what Theorem 2 affords at every attitude; near the reference the
//! local torque set is small, and what it can pay for (faster filters, a larger level that
//! brakes harder, an attitude stiff and damped enough not to lag them) is what a step asks. Each
//! candidate is certified (the local certificate evaluates the law it flies) and fitted to the
//! rotors with the margin as it is scored; what is not certified costs the refusal's penalty.

use controller_core::attitude_control::AttitudeGains;
use controller_core::{Gains, LocalAttitude, LocalGains, VerticalChannel};
use nalgebra::Vector3;

use super::super::evaluate::PENALTY;
use super::super::optimise::{minimise, Optimum};
use super::super::variables::interval::{unit_in, value_in, Interval};
use super::Refinement;

/// Evaluations of the refinement (one swarm start at the design's local regime among them).
pub const AGILITY_BUDGET: usize = 240;

/// The variables `(low, high, logarithmic)`, each relative to the design's local regime `l₀`
/// and global gains:
///
/// | # | variable | range |
/// |---|----------|-------|
/// | 0 | `k_f,L / k_f,L₀` | 1 to 2.5 (log) |
/// | 1 | `k_s,L / k_f,L` | 1.5 to 4 (log) |
/// | 2 | `M_p,L / M_p,L₀` | 1 to 2.5 (log) |
/// | 3 | horizontal braking / `M_p,L` | 0.5 to 0.9 |
/// | 4 | `ω_p,L` [rad/s] | 3 to 12 (log) |
/// | 5 | `ζ_p,L` | 0.5 to 1.2 |
/// | 6 | `ω_a,L / ω_a` (roll natural frequency near the reference) | 1 to 2 (log) |
/// | 7 | `M_ϑ,L / M_ϑ` | 1 to 4 (log) |
/// | 8 | roll and pitch damping ratio `ζ_a,L` | 0.5 to 1.4 |
/// | 9 | roll and pitch damping level / the global one | 1 to 3 (log) |
/// | 10 | `θ_out` \[deg\], the tilt at rest whose local energy is `E_out` | 0.5 to 5 (log) |
/// | 11 | `M_up,L / M_up` | 0.4 to 1 (log) |
/// | 12 | `M_down,L / M_down` | 0.5 to 1 (log) |
/// | 13 | `k_f,z,L / k_f,z,L₀` (at least the global `k_f,z`) | 0.4 to 1.5 (log) |
///
/// The ranges are where the x500's certified steps near 2 s lie (docs/results.md, "The local
/// regime's agility refined last"), each with the design's own value or near it.
pub const AGILITY_RANGES: [Interval; 14] = [
    (1.0, 2.5, true),
    (1.5, 4.0, true),
    (1.0, 2.5, true),
    (0.5, 0.9, false),
    (3.0, 12.0, true),
    (0.5, 1.2, false),
    (1.0, 2.0, true),
    (1.0, 4.0, true),
    (0.5, 1.4, false),
    (1.0, 3.0, true),
    (0.5, 5.0, true),
    (0.4, 1.0, true),
    (0.5, 1.0, true),
    (0.4, 1.5, true),
];

/// The stiffness [N m/rad] of the law of `attitude` and `trace` about the roll axis at
/// `R̃ = I`: the radial MRP term's `k_ϑ/16` (a rotation by `φ` has the MRP `tan(φ/4)`, and
/// the term is `(1 + |ϑ̃|²)/4 · s_ϑ`) plus the trace term's `½(g₂ + g₃)`.
fn roll_stiffness(attitude: &AttitudeGains<f64>, trace: &Vector3<f64>) -> f64 {
    attitude.k_mrp / 16.0 + 0.5 * (trace.y + trace.z)
}

/// The local law's energy at rest at a tilt `tilt_rad` about roll: the MRP potential
/// `(M_ϑ/k_ϑ)(√(M_ϑ² + k_ϑ²ϑ²) − M_ϑ)` at `ϑ = tan(tilt/4)` plus the trace potential
/// `½(g₂ + g₃)(1 − cos tilt)` (`controller_core::attitude_energy`).
fn energy_at_tilt(attitude: &AttitudeGains<f64>, trace: &Vector3<f64>, tilt_rad: f64) -> f64 {
    let (m, k) = (attitude.mrp_saturation, attitude.k_mrp);
    let mrp = (tilt_rad / 4.0).tan();
    (m / k) * ((m * m + k * k * mrp * mrp).sqrt() - m)
        + 0.5 * (trace.y + trace.z) * (1.0 - tilt_rad.cos())
}

/// The trace weights of `g`'s law (zero without tilt priority).
fn trace_of(g: &Gains<f64>) -> Vector3<f64> {
    g.tilt_priority
        .map_or(Vector3::zeros(), |t| t.trace_weights)
}

/// The tilt [rad] at rest whose energy under `g`'s global law is `energy` (bisection; the
/// energy at rest increases with the tilt on `[0, π]`).
fn tilt_of_energy(g: &Gains<f64>, energy: f64) -> f64 {
    let trace = trace_of(g);
    let (mut low, mut high) = (0.0, std::f64::consts::PI);
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if energy_at_tilt(&g.attitude, &trace, mid) < energy {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

/// The unit point of the design's own local regime `l₀` in `g` (the swarm's first particle;
/// values outside a range are clamped to it), `l₀` flying the global attitude law as the search
/// leaves it (the refinement's local law is built from the global one, so a local law `l₀`
/// already has is not the start). `None` without a local regime.
pub fn start(g: &Gains<f64>, inertia: &Vector3<f64>) -> Option<Vec<f64>> {
    let l = g.local?;
    let braking = g.velocity_limit.map_or(0.7 * l.saturation, |v| {
        l.velocity_limit(&g.position, &v).braking
    });
    let omega_p = l.kp.sqrt();
    let trace = trace_of(g);
    let stiffness = roll_stiffness(&g.attitude, &trace);
    let (damping_gain, _) = roll_damping(g);
    let zeta_a = damping_gain / (2.0 * (stiffness * inertia.x).sqrt());
    let vertical_share = match (g.position.vertical, l.vertical) {
        (Some(global), Some(own)) => (own.up / global.up, own.down / global.down),
        _ => (1.0, 1.0),
    };
    let values = [
        1.0,
        l.ks / l.kf,
        1.0,
        braking / l.saturation,
        omega_p,
        l.kv / (2.0 * omega_p),
        1.0,
        1.0,
        zeta_a,
        1.0,
        tilt_of_energy(g, l.energy_out).to_degrees(),
        vertical_share.0,
        vertical_share.1,
        1.0,
    ];
    Some(
        AGILITY_RANGES
            .iter()
            .zip(values)
            .map(|(&r, v)| unit_in(r, v))
            .collect(),
    )
}

/// The roll damping gain [N m s/rad] and level [N m] of `g`'s law (tilt priority's first axis,
/// or the paper's radial `k_ω`, `M_ω`).
fn roll_damping(g: &Gains<f64>) -> (f64, f64) {
    match &g.tilt_priority {
        Some(t) => (t.omega_gains.x, t.omega_levels.x),
        None => (g.attitude.k_omega, g.attitude.omega_saturation),
    }
}

/// The local regime of unit point `x` (laid out as [`AGILITY_RANGES`]) for the design `g`
/// (whose local regime `l₀` it is relative to) and the inertia diagonal `inertia` [kg m²]:
/// `g` with that local regime. `None` without a local regime in `g`. The gains are not
/// validated here: the certificate refuses what is out of range.
pub fn agility_gains(g: &Gains<f64>, inertia: &Vector3<f64>, x: &[f64]) -> Option<Gains<f64>> {
    let l0 = g.local?;
    let v = |i: usize| value_in(AGILITY_RANGES[i], x.get(i).copied().unwrap_or(0.0));
    let kf = l0.kf * v(0);
    let saturation = l0.saturation * v(2);
    let omega_p = v(4);
    // The local law: a stiffer radial MRP term and roll/pitch damping at a damping ratio of it.
    let trace = trace_of(g);
    let stiffness = roll_stiffness(&g.attitude, &trace);
    let local_stiffness = stiffness * v(6) * v(6);
    let attitude = AttitudeGains {
        k_mrp: g.attitude.k_mrp + 16.0 * (local_stiffness - stiffness),
        mrp_saturation: g.attitude.mrp_saturation * v(7),
        ..g.attitude
    };
    let (_, level) = roll_damping(g);
    let damping = |j: f64| 2.0 * v(8) * (local_stiffness * j).sqrt();
    let (attitude, tilt_priority) = match g.tilt_priority {
        Some(t) => (
            attitude,
            Some(controller_core::TiltPriorityGains {
                omega_gains: Vector3::new(damping(inertia.x), damping(inertia.y), t.omega_gains.z),
                omega_levels: Vector3::new(level * v(9), level * v(9), t.omega_levels.z),
                ..t
            }),
        ),
        None => (
            AttitudeGains {
                k_omega: damping(inertia.x.min(inertia.y)),
                omega_saturation: level * v(9),
                ..attitude
            },
            None,
        ),
    };
    let energy_out = energy_at_tilt(&attitude, &trace, v(10).to_radians());
    let vertical = g.position.vertical.map(|global| {
        let own = l0.vertical.unwrap_or(global);
        let kf_z = (own.kf * v(13)).max(global.kf);
        VerticalChannel {
            up: global.up * v(11),
            down: global.down * v(12),
            kf: kf_z,
            ks: kf_z * own.ks / own.kf,
        }
    });
    let local = LocalGains {
        kp: omega_p * omega_p,
        kv: 2.0 * v(5) * omega_p,
        kf,
        ks: kf * v(1),
        saturation,
        energy_in: 0.5 * energy_out,
        energy_out,
        vertical,
        attitude: Some(LocalAttitude {
            attitude,
            tilt_priority,
        }),
        braking: g.velocity_limit.map(|_| v(3) * saturation),
    };
    Some(Gains {
        local: Some(local),
        ..*g
    })
}

/// The design `g` (objective `searched`) with its local regime refined: a swarm of
/// [`AGILITY_BUDGET`] evaluations over [`AGILITY_RANGES`] from the design's own local regime,
/// each scored by `cost(gains)` (lower is better; at least [`PENALTY`] when refused or not
/// converged). Returns the refined gains when they score lower than `searched`, and the
/// refinement (`None` without a local regime or when `g` misses a constraint). Errors: the
/// optimiser's.
pub fn refine_local_agility<F: Fn(&Gains<f64>) -> f64 + Sync>(
    cost: &F,
    g: &Gains<f64>,
    inertia: &Vector3<f64>,
    searched: f64,
    seed: u64,
) -> anyhow::Result<(Option<Gains<f64>>, Option<Refinement>)> {
    let Some(guess) = start(g, inertia) else {
        return Ok((None, None));
    };
    if searched >= PENALTY {
        return Ok((None, None));
    }
    let unit_cost = |x: &[f64]| match agility_gains(g, inertia, x) {
        Some(gains) => cost(&gains),
        None => 10.0 * PENALTY,
    };
    let Optimum {
        x,
        cost: refined,
        evaluations,
    } = minimise(&unit_cost, &guess, AGILITY_BUDGET, seed)?;
    let kept = refined < searched;
    let refinement = Refinement {
        searched,
        refined,
        kept,
        evaluations,
    };
    let gains = if kept {
        agility_gains(g, inertia, &x)
    } else {
        None
    };
    Ok((gains, Some(refinement)))
}

#[cfg(test)]
mod tests;
