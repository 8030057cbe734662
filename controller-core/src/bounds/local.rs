//! The local regime's certificate (extension, docs/envelope-design.md): Lemma 1 for the local
//! position gains, the attitude error inside the energy level `E_out` of the law the local
//! regime flies (its own, [`crate::LocalAttitude`], or the global one), and the torque set they
//! confine that law to.

use nalgebra::{Vector2, Vector3};

use super::certificate::{Bounds, FilterStart, LocalCertificate};
use super::{certify, Condition};
use crate::attitude_energy::{energy_limits, EnergyLimits};
use crate::gains::Gains;
use crate::local_regime::LocalGains;
use crate::parameter_error::ParameterError;
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, Scalar};
use crate::torque_set::TorqueSet;
use crate::vehicle::{Limits, Vehicle};

/// The local regime's certificate for `gains` (whose `local` is `l`) on `vehicle` with `limits`
/// and the reference `constants`. Errors: `certify` refuses the local gains.
/// Source: extension of Lemma 1 and Theorem 2 (docs/envelope-design.md).
pub(super) fn local_certificate<T: Scalar>(
    vehicle: &Vehicle<T>,
    limits: &Limits<T>,
    gains: &Gains<T>,
    l: &LocalGains<T>,
    constants: &TrajectoryConstants<T>,
) -> Result<LocalCertificate<T>, ParameterError> {
    let local_gains = Gains {
        position: l.position(&gains.position),
        velocity_limit: gains
            .velocity_limit
            .map(|v| l.velocity_limit(&gains.position, &v)),
        local: None,
        ..*gains
    };
    let local = certify(
        vehicle,
        limits,
        &local_gains,
        constants,
        FilterStart::InSaturationBox,
    )?;
    let bounds = local.bounds;
    // Theorem 1 for the local gains, renamed: the same inequalities, the local levels.
    let renamed = |from: &str, name: &'static str| {
        let c = local
            .conditions
            .iter()
            .find(|c| c.name == from)
            .copied()
            .unwrap_or_else(|| Condition::strict(name, "", T::zero(), T::zero()));
        Condition { name, ..c }
    };
    // The law the local regime flies: its energy bounds the errors, its feedback the torque.
    let law = l.attitude.map_or(*gains, |a| gains.with_attitude_law(&a));
    let energy = energy_limits(&law, &vehicle.inertia, l.energy_out);
    let torque_set = local_torque_set(&law, &vehicle.inertia, &bounds, &energy);
    let extents = torque_set.axis_extents();
    let tau = &limits.torque_max;
    let strict = Condition::strict;
    let conditions = [
        strict(
            "local_regime.torque_max_roll",
            "tau_max_1 > the local regime's roll extent (docs/envelope-design.md)",
            tau[0],
            extents[0],
        ),
        strict(
            "local_regime.torque_max_pitch",
            "tau_max_2 > the local regime's pitch extent (docs/envelope-design.md)",
            tau[1],
            extents[1],
        ),
        strict(
            "local_regime.torque_max_yaw",
            "tau_max_3 > the local regime's yaw extent (docs/envelope-design.md)",
            tau[2],
            extents[2],
        ),
        renamed(
            "theorem1.saturation_margin",
            "local_regime.saturation_margin",
        ),
        renamed(
            "theorem1.thrust_bound_within_actuator",
            "local_regime.thrust_bound_within_actuator",
        ),
    ];
    Ok(LocalCertificate {
        bounds,
        energy,
        torque_set,
        conditions,
    })
}

/// The set the local regime's torque stays in while `E ≤ E_out` (`energy`), for the local
/// gains' `bounds` (Lemma 1 and its desired-frame components) and the inertia `inertia`:
///
/// - the feedforward `−J R̃ᵀω̇_d`: `ω̇_d` in the desired frame's cylinder `(a, b)`
///   (`Bounds::desired_frame`), turned by every `R̃` of angle at most `θ`
///   ([`TorqueSet::turned_cylinder_support`], exact; it replaces the cylinder plus the ball of
///   radius `2 sin(θ/2) √(a² + b²)`, which it never exceeds);
/// - the gyroscopic term with `|ω_i|` at most its desired-frame bound plus `2 sin(θ/2)|ω_d|`;
/// - the radial MRP term at `|ϑ̃| ≤ ϑ_c`: `(1 + ϑ_c²)/4 · M_ϑ k_ϑ ϑ_c/√(M_ϑ² + k_ϑ²ϑ_c²)`;
/// - the paper's damping at `|ω̃| ≤ ω_c`: `M_ω k_ω ω_c/√(M_ω² + k_ω²ω_c²)`, the two in one ball
///   whose radius is their largest sum over the ways the energy splits between the MRP
///   potential and the kinetic energy (`joint_feedback_radius` in this module); tilt priority's damping per
///   axis (a box) and its trace term, at most
///   `½(sin θ' max_i(tr G − g_i) + (1 − cos θ)(g_max − g_min)/2)` (`θ' = min(θ, π/2)`; a ball),
///   each at the whole energy.
///
/// No errors. Source: extension of Theorem 2 (docs/envelope-design.md).
pub fn local_torque_set<T: Scalar>(
    gains: &Gains<T>,
    inertia: &Vector3<T>,
    bounds: &Bounds<T>,
    energy: &EnergyLimits<T>,
) -> TorqueSet<T> {
    let (half, two) = (lit::<T>(0.5), lit::<T>(2.0));
    let df = &bounds.desired_frame;
    let eps = two * (energy.angle * half).sin();
    let (a, b) = (df.tilt_acceleration, df.yaw_acceleration);
    let w = (df.tilt_rate * df.tilt_rate + df.yaw_rate * df.yaw_rate).sqrt();
    let (bt, by) = (df.tilt_rate + eps * w, df.yaw_rate + eps * w);
    let j = inertia;
    let global = &bounds.torque_set.gyroscopic;
    let gyroscopic = Vector3::new(
        ((j.y - j.z).abs() * bt * by).min(global.x),
        ((j.z - j.x).abs() * bt * by).min(global.y),
        (half * (j.x - j.y).abs() * bt * bt).min(global.z),
    );
    let (ball, feedback_box) = match &gains.tilt_priority {
        None => (
            joint_feedback_radius(gains, inertia, energy.energy),
            Vector3::zeros(),
        ),
        Some(t) => {
            let g = &t.trace_weights;
            let trace = g.x + g.y + g.z;
            let across = (trace - g.min()).max(trace - g.max());
            let quarter = energy.angle.min(T::frac_pi_2());
            let trace_ball = half
                * (quarter.sin() * across
                    + (T::one() - energy.angle.cos()) * half * (g.max() - g.min()));
            (
                radial_mrp_torque(gains, energy.mrp) + trace_ball,
                Vector3::from_fn(|i, _| {
                    damp(t.omega_levels[i], t.omega_gains[i], energy.omega_error[i])
                }),
            )
        }
    };
    TorqueSet {
        inertia: *inertia,
        angular_acceleration: T::zero(),
        gyroscopic,
        feedback_radius: ball,
        feedback_box,
        feedback_disks: Vector3::zeros(),
        aligned_acceleration: Vector2::new(a, b),
        aligned_turn: energy.angle,
        attitude_joint: None,
    }
}

/// The radial MRP term's norm `(1 + ϑ²)/4 · M_ϑ k_ϑ ϑ/√(M_ϑ² + k_ϑ²ϑ²)` [N m] at `|ϑ̃| = mrp`
/// (increasing in `mrp`). No errors. Source: Theorem 2's feedback term.
fn radial_mrp_torque<T: Scalar>(gains: &Gains<T>, mrp: T) -> T {
    let at = &gains.attitude;
    (T::one() + mrp * mrp)
        * lit(0.25)
        * (at.mrp_saturation * at.k_mrp * mrp
            / (at.mrp_saturation * at.mrp_saturation + at.k_mrp * at.k_mrp * mrp * mrp).sqrt())
}

/// The saturated damping's norm `M k w/√(M² + k²w²)` [N m] at `|ω̃| = w` (increasing in `w`).
fn damp<T: Scalar>(m: T, k: T, w: T) -> T {
    m * k * w / (m * m + k * k * w * w).sqrt()
}

/// Intervals of the energy split [`joint_feedback_radius`] takes the worst of.
pub const ENERGY_SPLITS: usize = 32;

/// The paper's feedback norm `|(1 + |ϑ̃|²)/4 s_ϑ + s_ω|` [N m] inside `{E ≤ energy}` (`energy`
/// \[J\]) for `gains` and `inertia` [kg m²]: both terms cannot reach their largest values at
/// once, since the MRP potential `Ψ(ϑ̃)` and the kinetic energy `½ω̃ᵀJω̃` share `energy`. With
/// `Ψ = s · energy` for some `s ∈ [0, 1]`, `|ϑ̃| ≤ ϑ(s · energy)` and `|ω̃| ≤ ω((1 − s) energy)`
/// ([`energy_limits`]); the radial term increases with `s` and the damping decreases, so on
/// each of [`ENERGY_SPLITS`] intervals `[s_i, s_{i+1}]` the norm is at most
/// `radial(s_{i+1}) + damping(s_i)`, and the radius is the largest of these (at most the sum of
/// the two terms' largest values, which it replaces). No errors. Source: extension of Theorem 2
/// (docs/envelope-design.md).
pub fn joint_feedback_radius<T: Scalar>(gains: &Gains<T>, inertia: &Vector3<T>, energy: T) -> T {
    let at = &gains.attitude;
    let n = lit::<T>(ENERGY_SPLITS as f64);
    let share = |i: usize| lit::<T>(i as f64) / n;
    (0..ENERGY_SPLITS).fold(T::zero(), |worst, i| {
        let potential = energy_limits(gains, inertia, energy * share(i + 1));
        let kinetic = energy_limits(gains, inertia, energy * (T::one() - share(i)));
        let w = kinetic.omega_error.max();
        let bound =
            radial_mrp_torque(gains, potential.mrp) + damp(at.omega_saturation, at.k_omega, w);
        worst.max(bound)
    })
}

#[cfg(test)]
mod tests;
