//! Vehicles and specifications refused before any search, with the condition that binds and
//! its numbers: a rotor set that cannot hover or give the needed authority, an integral action
//! that cannot be covered, and the binding condition of a certificate that fails.

use super::authority::{PositionLaw, RotorFit, RotorSet};
use super::certificate::{certify_design_with, Certified};
use super::integral::IntegralSpec;
use super::reference::Reference;
use super::tight::{tight_torque, BoundsKind, SEARCH_BOXES};
use super::variables::{map, AttitudeLaw, Choices, Context, Mapped};
use super::vehicle::DesignVehicle;
use anyhow::{bail, Result};

/// Why a reference cannot be used (the binding condition with its numbers), or `None`.
pub(crate) fn binding_condition(
    vehicle: &DesignVehicle,
    set: &RotorSet,
    (margin, law, bounds, fit): (f64, AttitudeLaw, BoundsKind, RotorFit),
    position: PositionLaw<'_>,
    r: &Reference,
) -> Option<String> {
    let constants = r.constants();
    let hover = iota_floor(
        vehicle,
        set,
        (margin, bounds, position, fit),
        &controller_core::TrajectoryConstants::zero(),
    );
    let floor = iota_floor(vehicle, set, (margin, bounds, position, fit), &constants);
    if floor < AUTHORITY_SHARE * hover {
        let env = super::authority::envelope_with(
            bounds,
            &vehicle.body,
            &constants,
            (1e-6, 0.3, 0.45),
            position,
        );
        let detail = env.map_or_else(String::new, |env| {
            format!(
                " (thrust interval [{:.4}, {:.4}] N; reference feedforward torque bound \
                 [{:.4e}, {:.4e}, {:.4e}] N m; rotor range [{}, {}] N)",
                env.thrust.0,
                env.thrust.1,
                env.feedforward.x,
                env.feedforward.y,
                env.feedforward.z,
                set.range.0,
                set.range.1
            )
        });
        return Some(if floor <= 0.0 {
            format!(
                "theorem2 + rotor fit: no feedback torque level iota > 0 fits the rotors with margin {margin} even as \
                 M_p -> 0: iota_max = {floor:.4e} N m{detail}"
            )
        } else {
            format!(
                "authority: the reference's feedforward leaves iota_max = {floor:.4e} N m as M_p -> 0, less than \
                 {AUTHORITY_SHARE} x the hover value {hover:.4e} N m{detail}"
            )
        });
    }
    let probe = probe_choices(law);
    let ctx = Context {
        vehicle: &vehicle.body,
        constants: &constants,
        rotors: set,
        margin,
        fit,
        bounds,
        position,
        speed_limit: None,
    };
    let Some(m) = map(&ctx, &probe) else {
        return Some(
            "theorem2 + rotor fit: no M_p > 0 leaves a positive feedback torque level".to_owned(),
        );
    };
    match certify_mapped(vehicle, &constants, &m, (margin, bounds, SEARCH_BOXES, fit)) {
        Err(e) => Some(format!("{e:#}")),
        Ok(c) if c.ok() => None,
        Ok(c) => {
            let mut why: Vec<String> = c
                .certificate
                .violations()
                .map(|v| {
                    format!(
                        "{} ({}): lhs = {:.6e}, rhs = {:.6e}",
                        v.name, v.statement, v.lhs, v.rhs
                    )
                })
                .collect();
            if !c.fits_with_margin {
                why.push(format!(
                    "rotor fit of the certified set with margin {margin}: smallest headroom {:.4}",
                    c.margin
                ));
            }
            Some(why.join("; "))
        }
    }
}

/// Refuses a vehicle that cannot fly at all, with the reason.
pub(crate) fn refuse_impossible(vehicle: &DesignVehicle) -> Result<RotorSet> {
    let r = &vehicle.rotors;
    if !(r.thrust_min.is_finite()
        && r.thrust_max.is_finite()
        && r.thrust_max > r.thrust_min
        && r.thrust_min >= 0.0)
    {
        bail!(
            "{}: rotors: thrust range empty or invalid: thrust_min_N = {}, thrust_max_N = {}",
            vehicle.origin,
            r.thrust_min,
            r.thrust_max
        );
    }
    let set = RotorSet::new(r).map_err(|e| anyhow::anyhow!("{}: rotors: {e}", vehicle.origin))?;
    let weight = vehicle.body.mass * vehicle.body.gravity;
    if set.thrust_total_max() <= weight {
        bail!(
            "{}: the vehicle cannot hover: 4 x thrust_max_N = {:.4} N <= weight m g = {:.4} N",
            vehicle.origin,
            set.thrust_total_max(),
            weight
        );
    }
    if 4.0 * set.range.0 >= weight {
        bail!(
            "{}: the vehicle cannot hover: 4 x thrust_min_N = {:.4} N >= weight m g = {:.4} N (it cannot descend)",
            vehicle.origin,
            4.0 * set.range.0,
            weight
        );
    }
    let hover = iota_floor(
        vehicle,
        &set,
        (0.0, BoundsKind::Paper, PositionLaw::paper(), RotorFit::Set),
        &controller_core::TrajectoryConstants::zero(),
    );
    if hover <= 0.0 {
        bail!(
            "{}: the rotors cannot hold the vehicle's hover thrust and any torque at once \
             (largest feedback torque at hover iota_max = {hover:.4e} N m)",
            vehicle.origin
        );
    }
    Ok(set)
}

/// Refuses an integral action the vehicle cannot carry, with the numbers: the extended
/// Theorem 1 needs `T_min = m(g − K_a3 − M_p − M_i,z) > 0`, and the rotors must at least hold
/// the covered plant, `m(g + M_i,z)`.
pub(crate) fn refuse_uncoverable(
    vehicle: &DesignVehicle,
    set: &RotorSet,
    spec: &IntegralSpec,
) -> Result<()> {
    let (m, g) = (vehicle.body.mass, vehicle.body.gravity);
    let level = spec.level_m_s2[2];
    if level >= g {
        bail!(
            "integral action: covering a mass error of {} and a force of {} of the weight needs a vertical \
             level M_i,z = {level:.4} m/s^2 >= g = {g} m/s^2, which leaves the extended Theorem 1 no \
             thrust floor T_min = m(g - K_a3 - M_p - M_i,z) > 0",
            spec.mass_error_fraction,
            spec.force_fraction
        );
    }
    let needed = m * (g + level);
    if set.thrust_total_max() <= needed {
        bail!(
            "integral action: {}: the rotors' 4 x thrust_max_N = {:.4} N cannot hold the covered plant \
             (mass error {}, force {} of the weight): m (g + M_i,z) = {needed:.4} N",
            vehicle.origin,
            set.thrust_total_max(),
            spec.mass_error_fraction,
            spec.force_fraction
        );
    }
    Ok(())
}

/// The probe design used to decide whether a reference can be certified at all: slow filters,
/// half the largest `M_p` and half of `ι_max`.
pub(crate) fn probe_choices(law: AttitudeLaw) -> Choices {
    Choices {
        kf: 0.3,
        ks: 0.45,
        saturation_fraction: 0.5,
        iota_fraction: 0.5,
        ..Choices::initial_guess(super::variables::Layout {
            law,
            ..Default::default()
        })
    }
}

/// Share of the vehicle's hover feedback authority a reference may take: the reference is
/// usable when, as `M_p → 0`, the largest feedback torque level `ι_max` left by its feedforward
/// is at least this share of `ι_max` at hover (without it, a "certified" design has too little
/// torque left to recover from 180 degrees).
pub const AUTHORITY_SHARE: f64 = 0.75;

/// `ι_max` as `M_p → 0` [N m] for `constants` (independent of `k_f`, `k_s` there).
pub(crate) fn iota_floor(
    vehicle: &DesignVehicle,
    set: &RotorSet,
    (margin, bounds, position, fit): (f64, BoundsKind, PositionLaw<'_>, RotorFit),
    constants: &controller_core::TrajectoryConstants<f64>,
) -> f64 {
    super::authority::envelope_with(
        bounds,
        &vehicle.body,
        constants,
        (1e-6, 0.3, 0.45),
        position,
    )
    .map_or(f64::NEG_INFINITY, |env| match fit {
        RotorFit::Set => super::authority::iota_max(set, &env, margin),
        RotorFit::Airmode => super::authority::shadow_iota_max(set, &env, margin),
    })
}

/// Certifies `mapped` with the bounds of `kind` (the tight ones with `boxes` per search).
pub(crate) fn certify_mapped(
    vehicle: &DesignVehicle,
    constants: &controller_core::TrajectoryConstants<f64>,
    mapped: &Mapped,
    (margin, kind, boxes, fit): (f64, BoundsKind, usize, RotorFit),
) -> Result<Certified> {
    let tight = match kind {
        BoundsKind::Paper => None,
        BoundsKind::Tight => Some(tight_torque(
            &vehicle.body,
            &mapped.gains,
            constants,
            boxes,
        )?),
    };
    certify_design_with(
        &vehicle.body,
        &vehicle.rotors,
        &mapped.gains,
        constants,
        margin,
        tight,
        fit,
    )
}
