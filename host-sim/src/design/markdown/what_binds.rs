//! `design.md`'s "What binds" section: what caps `M_p` and `ι`, the 1 m step's floor and the
//! search variables at an end of their range ([`crate::design::binding`], docs/design.md).

use std::fmt::Write as _;

use super::super::report::Report;
use crate::design::binding::WhatBinds;

/// Appends the "What binds" lines: what caps `M_p` and `ι`, the step's floor
/// ([`crate::design::binding`]), with their numbers.
pub(super) fn write(s: &mut String, r: &Report, w: &WhatBinds) {
    use crate::design::binding::SaturationCap;
    let margin = 100.0 * r.rotor_fit.requested_margin;
    let vertical_reach = {
        let up = r.gains.vertical.as_ref().map_or(r.gains.M_p, |v| v.up_m_s2);
        let integral = r.gains.integral.as_ref().map_or(0.0, |i| i.M_i_m_s2[2]);
        format!(
            "its top carries the braking level M_up = {up:.4} m/s^2 and the integral's \
             M_i,z = {integral:.4} m/s^2 above gravity: more thrust, or less of either, raises the cap"
        )
    };
    let why = match w.saturation {
        SaturationCap::ThrustFloor { level_m_s2 } => format!(
            "nothing binds before the end of its range, {level_m_s2:.4} m/s^2, where Theorem 1's \
             thrust floor m(g - K_a3 - M_down - M_i,z) reaches 0"
        ),
        SaturationCap::Refused => "`certify` refuses the set-up (its bounds are undefined)".into(),
        SaturationCap::ThrustFit {
            thrust_N: [t_lo, t_hi],
            capacity_N: [c_lo, c_hi],
        } => format!(
            "Theorem 1's thrust interval [{t_lo:.3}, {t_hi:.3}] N leaves the collective the rotors \
             give at zero torque with the {margin:.0} % margin, [{c_lo:.3}, {c_hi:.3}] N; {}",
            if t_hi > c_hi {
                vertical_reach
            } else {
                "its bottom is Theorem 1's floor m(g - K_a3 - M_down - M_i,z): a smaller descent \
                 level M_down raises it"
                    .to_owned()
            }
        ),
        SaturationCap::TorqueFit => format!(
            "the certified torque set's feedforward part alone fills the rotors with the {margin:.0} % \
             margin: no feedback torque fits (docs/torque-set.md)"
        ),
        SaturationCap::Assumption1 {
            axis,
            reference_Nm,
            capacity_Nm,
        } => format!(
            "Assumption 1's {} condition fails: the reference's feedforward alone needs \
             {reference_Nm:.4e} N m, more than the {capacity_Nm:.4e} N m the rotors give about that \
             axis over the whole thrust interval",
            super::AXES[axis]
        ),
        SaturationCap::Theorem2 {
            axis,
            feedforward_Nm,
            capacity_Nm,
        } => format!(
            "Theorem 2's {} condition fails: its feedforward terms J U_omega_d_dot + \
             |J_jj - J_kk| U_omega_d^2 / 2 = {feedforward_Nm:.4e} N m reach the axis's capacity \
             {capacity_Nm:.4e} N m (the rates Lemma 1 bounds grow with M_p)",
            super::AXES[axis]
        ),
    };
    let i = &w.iota;
    let iota_why = match i.theorem2_axis() {
        None => "the rotor fit of the certified torque set".to_owned(),
        Some(axis) => format!("Theorem 2's {} condition", super::AXES[axis]),
    };
    let per_axis = i
        .theorem2_Nm
        .map(|v| {
            if v.is_finite() {
                format!("{v:.4e}")
            } else {
                "none".into()
            }
        })
        .join(", ");
    let ends = if w.range_ends.is_empty() {
        "none".to_owned()
    } else {
        w.range_ends
            .iter()
            .map(|e| {
                format!(
                    "`{}` = {:.4} (searched from {} to {})",
                    e.variable, e.value, e.range[0], e.range[1]
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let f = &w.step;
    let flown = r
        .objective
        .nominal_tasks
        .first()
        .and_then(|t| t.step_settling_time_s)
        .map_or("does not settle within its 10 s".to_owned(), |t| {
            format!("settles in {t:.2} s")
        });
    let (step_m, band_m) = crate::design::binding::STEP_M;
    // The step starts inside the local regime where there is one: its gains set the floor.
    let (local, whose) = if f.local {
        (",L", ", with the local regime's gains")
    } else {
        ("", "")
    };
    let step = format!(
        "no faster than {:.2} s with perfect attitude tracking: the commanded acceleration is at \
         most M_p{local} = {:.4} m/s^2 and, from rest, changes at most at 2 k_f{local} U_l \
         M_p{local} = {:.3} m/s^3 (Lemma 1{whose}), and a move of {step_m} m from rest enters its \
         {band_m} m band and stays no sooner; the design {flown}.",
        f.time_s, f.acceleration_m_s2, f.jerk_m_s3,
    );
    let _ = writeln!(
        s,
        "## What binds\n\n\
         - **Position level**: M_p <= {:.4} m/s^2 (the design flies {:.3} of it). Above it, {why}.\n\
         - **Feedback torque level**: iota <= {:.4e} N m (roll's; the design flies {:.3} of it), set by \
         {iota_why}: the rotor fit allows {:.4e} N m, Theorem 2's roll, pitch and yaw conditions \
         [{per_axis}] N m{}.\n\
         - **1 m step**: {step}\n\
         - **Search variables at an end of their range**: {ends}.\n",
        r.saturation_max_m_s2,
        r.choices.saturation_fraction,
        r.feedback_torque_Nm.0,
        r.choices.iota_fraction,
        i.rotor_fit_Nm,
        if r.choices.tilt.is_some() {
            " (yaw's with the yaw level at its share of roll's)"
        } else {
            ""
        },
    );
}
