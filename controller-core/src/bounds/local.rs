//! The local regime's certificate (extension, docs/envelope-design.md): Lemma 1 for the local
//! position gains, the attitude error inside the energy level `E_out`, and the torque set they
//! confine the law to.

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
    let energy = energy_limits(gains, &vehicle.inertia, l.energy_out);
    let torque_set = local_torque_set(gains, &vehicle.inertia, &bounds, &energy);
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
///   (`Bounds::desired_frame`), turned by `R̃` of angle at most `θ`, which moves it by at most
///   `2 sin(θ/2)` of its norm: the cylinder plus the ellipsoid of radius
///   `2 sin(θ/2) √(a² + b²)`;
/// - the gyroscopic term with `|ω_i|` at most its desired-frame bound plus `2 sin(θ/2)|ω_d|`;
/// - the radial MRP term at `|ϑ̃| ≤ ϑ_c`: `(1 + ϑ_c²)/4 · M_ϑ k_ϑ ϑ_c/√(M_ϑ² + k_ϑ²ϑ_c²)`;
/// - the paper's damping at `|ω̃| ≤ ω_c`: `M_ω k_ω ω_c/√(M_ω² + k_ω²ω_c²)` (a ball); tilt
///   priority's per axis (a box) and its trace term, at most
///   `½(sin θ' max_i(tr G − g_i) + (1 − cos θ)(g_max − g_min)/2)` (`θ' = min(θ, π/2)`; a ball).
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
    let at = &gains.attitude;
    let mrp = energy.mrp;
    let radial = (T::one() + mrp * mrp)
        * lit(0.25)
        * (at.mrp_saturation * at.k_mrp * mrp
            / (at.mrp_saturation * at.mrp_saturation + at.k_mrp * at.k_mrp * mrp * mrp).sqrt());
    let damp = |m: T, k: T, w: T| m * k * w / (m * m + k * k * w * w).sqrt();
    let (ball, feedback_box) = match &gains.tilt_priority {
        None => {
            let w_max = energy.omega_error.max();
            (
                radial + damp(at.omega_saturation, at.k_omega, w_max),
                Vector3::zeros(),
            )
        }
        Some(t) => {
            let g = &t.trace_weights;
            let trace = g.x + g.y + g.z;
            let across = (trace - g.min()).max(trace - g.max());
            let quarter = energy.angle.min(T::frac_pi_2());
            let trace_ball = half
                * (quarter.sin() * across
                    + (T::one() - energy.angle.cos()) * half * (g.max() - g.min()));
            (
                radial + trace_ball,
                Vector3::from_fn(|i, _| {
                    damp(t.omega_levels[i], t.omega_gains[i], energy.omega_error[i])
                }),
            )
        }
    };
    TorqueSet {
        inertia: *inertia,
        angular_acceleration: eps * (a * a + b * b).sqrt(),
        gyroscopic,
        feedback_radius: ball,
        feedback_box,
        feedback_disks: Vector3::zeros(),
        aligned_acceleration: Vector2::new(a, b),
    }
}

#[cfg(test)]
mod tests;
