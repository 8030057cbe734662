//! `design.md`: the report rendered for a reader (binding conditions, certificate, gains,
//! objective, margins, plots), from the same [`Report`] as `design.json`.

use crate::output::markdown_table::{Rule, Table};
use std::fmt::Write as _;

use super::report::Report;

mod attempts;
mod what_binds;

fn opt(v: Option<f64>, unit: &str) -> String {
    v.map_or_else(|| "not settled".to_owned(), |v| format!("{v:.3} {unit}"))
}

/// `design.md`.
pub fn markdown(r: &Report, plots: &[&str]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Certified design: {}\n", r.vehicle);
    let _ = writeln!(
        s,
        "Vehicle file `{}` ({}).\n",
        r.vehicle_file, r.vehicle_source
    );
    let _ = writeln!(
        s,
        "Seed {}, {} evaluations, {:.1} s wall time. Runs of {} s (`--duration-s`): a run \
         converges when it has settled 5 s before its end.\n",
        r.seed, r.evaluations, r.wall_time_s, r.duration_s
    );
    attempts::write(&mut s, r);
    let _ = writeln!(
        s,
        "## Certificate\n\nEvery condition holds: **{}**. Rotor fit of the certified torque set (docs/torque-set.md): **{}** (with the {:.0} % margin: **{}**; \
         smallest headroom {:.2} % of the rotor range; the box of the per-axis bounds, every corner at once, fits: {}).\n",
        r.certificate.all_hold,
        r.rotor_fit.fits,
        100.0 * r.rotor_fit.requested_margin,
        r.rotor_fit.fits_with_margin,
        100.0 * r.rotor_fit.margin,
        r.rotor_fit.box_fits
    );
    if let (Some(aligned), Some(proven)) = (
        r.rotor_fit.aligned_margin,
        r.rotor_fit.airmode_convergence_proven,
    ) {
        let _ = writeln!(
            s,
            "**Airmode** (docs/airmode.md; the flight file's `[controller] airmode`): the headroom \
             above is the shadow fit's (every torque of the set at some thrust; the thrust moves \
             there). The feedforward at zero attitude error fits the whole thrust interval with \
             {:.2} % headroom: {}.\n",
            100.0 * aligned,
            if proven {
                "at least the margin, so airmode's convergence argument is a proof"
            } else {
                "below the margin, so convergence is shown by the simulations below only"
            }
        );
        let _ = writeln!(
            s,
            "{}\n",
            match r.thrust.airmode_low_margin {
                Some(low) => format!(
                    "Airmode keeps the margin free below the rotors' top and {:.1} % above their \
                     least thrust (`[controller] airmode_low_margin`): flown that way the design \
                     scored lower, so where the no-dive thrust cuts the thrust (upside down) the \
                     rotors may fall to their idle. The fits above are checked with the margin \
                     at both ends, so the certificate is the same.",
                    100.0 * low
                ),
                None => match r.thrust.airmode_idle_trial {
                    Some((cost, feasible)) => format!(
                        "Airmode keeps the margin free at both ends of the rotors' range: flown \
                         with almost none above their least thrust the design {} (objective {cost:.3}), \
                         so it keeps it (a rotor at idle spins up through its motor lag).",
                        if feasible {
                            "scored no better"
                        } else {
                            "missed a constraint"
                        }
                    ),
                    None => "Airmode keeps the margin free at both ends of the rotors' range."
                        .to_string(),
                },
            }
        );
    }
    if r.law_search.len() > 1 {
        let listed: Vec<String> = r
            .law_search
            .iter()
            .map(|c| {
                candidate(
                    &format!("`{}`", c.law.name()),
                    c.objective,
                    "",
                    c.constraints_met,
                )
            })
            .collect();
        // The laws are searched on the first attempt; a fallback designs again with its winner.
        let first = if r.fallback.is_some() || r.reference.heading_held.is_some() {
            " on the first attempt (the requested reference), designed again with it above"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "Attitude law: `{}`, the better of the laws searched{first} (`--law both`; objective, \
             lower is better): {}.\n",
            r.law.name(),
            listed.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "Lemma 1's bound on `|ω̇_d|`: the {} chain{}.\n",
        r.certificate.lemma1,
        match r.certificate.lemma1 {
            "tangential" => " (only the parts of `ρ̈` and `ϋ` that `ω̇_d` reads, docs/tangential-lemma1.md; the flight file carries `lemma1 = \"tangential\"` and the firmware's gate certifies with it)",
            "desired_frame" => " (the tangential chain, docs/tangential-lemma1.md, and Theorem 2's per-axis conditions judged on the desired frame's norms of `ω_d`, `ω̇_d`, the certified torque set's, docs/torque-set.md; the flight file carries `lemma1 = \"desired_frame\"` and the firmware's gate certifies with it)",
            _ => " (as the paper states it)",
        }
    );
    if let Some(h) = &r.gains.heading_compensator {
        let _ = writeln!(
            s,
            "**Compensated heading** (`--heading compensated`, docs/heading-compensator.md): the \
             desired frame is built from a heading whose rate cancels the tilt-induced yaw, \
             corrected towards the reference's at level L = {} rad/s with gain k_psi = {} 1/s; the \
             certificate takes the desired frame's yaw bounds from it and the flight file \
             carries `[gains.heading_compensator]`.\n",
            h.level_rad_s, h.gain_1_s
        );
    }
    if r.heading_search.len() > 1 {
        let listed: Vec<String> = r
            .heading_search
            .iter()
            .map(|c| {
                let name = if c.compensated {
                    "compensated"
                } else {
                    "paper's"
                };
                let runs = if c.long_runs {
                    " (on the long-run fallback's runs)"
                } else {
                    ""
                };
                candidate(name, c.objective, runs, c.constraints_met)
            })
            .collect();
        let _ = writeln!(
            s,
            "Heading: the {}, the better of the headings searched, each designed with its own \
             fallbacks (`--heading both`; objective, lower is better): {}.\n",
            if r.gains.heading_compensator.is_some() {
                "compensated heading"
            } else {
                "paper's desired frame"
            },
            listed.join(", ")
        );
    }
    if r.certificate.bounds == super::tight::BoundsKind::Tight {
        let _ = writeln!(
            s,
            "Certified with the **tight** a-priori bounds (`--bounds tight`, docs/tight-bounds.md): \
             Theorem 2's torque conditions use them and the certified torque set takes their norms of `ω_d`, `ω̇_d` \
             where they are below its own; the paper's bound is beside. \
             With the paper's bounds every condition holds and the torque set fits with the margin (the \
             firmware's gate): **{}**{}.\n",
            r.certificate.paper_certified,
            if r.certificate.paper_certified {
                ""
            } else {
                " (the firmware's gate re-checks the paper's certificate and rotor fit on board and \
                 would refuse to arm this design, so no `firmware.toml` is written: fly \
                 `scenario.toml` in simulation)"
            }
        );
    }
    if let (Some(spec), Some(i)) = (&r.integral, &r.gains.integral) {
        let _ = writeln!(
            s,
            "With the **bounded integral action** (the default, docs/integral-action.md), sized to \
             cover a plant mass error of {:.0} % and a constant force of {:.0} % of the weight: \
             level `M_i` = ({:.3}, {:.3}, {:.3}) m/s², rate limit `R_i` = ({:.3}, {:.3}, {:.3}) m/s³, \
             output filter `k_η` = {:.3} 1/s, `k_i` = {:.4} 1/s³, observer `L_v` = {:.3} 1/s, \
             `L_d` = {:.3} 1/s². Every bound below is the extended one (Theorem 1's interval and \
             Lemma 1 with the estimate's terms), and the loop's local stability conditions are in \
             the table.\n",
            100.0 * spec.mass_error_fraction,
            100.0 * spec.force_fraction,
            i.M_i_m_s2[0],
            i.M_i_m_s2[1],
            i.M_i_m_s2[2],
            i.rate_m_s3[0],
            i.rate_m_s3[1],
            i.rate_m_s3[2],
            i.k_eta,
            i.k_i,
            i.observer.as_ref().map_or(f64::NAN, |o| o.velocity_gain_1_s),
            i.observer.as_ref().map_or(f64::NAN, |o| o.disturbance_gain_1_s2),
        );
    }
    let mut table = Table::new(
        &mut s,
        &[
            "condition",
            "holds",
            "lhs",
            "rhs",
            "slack",
            "paper's rhs (holds)",
        ],
        Rule::Compact,
    );
    for c in &r.certificate.conditions {
        let paper = c.paper.map_or_else(
            || "–".to_owned(),
            |(rhs, holds)| format!("{rhs:.6} ({holds})"),
        );
        table.row(&[
            format!("`{}`", c.name),
            c.holds.to_string(),
            format!("{:.6}", c.lhs),
            format!("{:.6}", c.rhs),
            format!("{:.3e}", c.slack),
            paper,
        ]);
    }
    let _ = writeln!(
        s,
        "\nTightest condition: `{}` (relative slack {:.3}).\n\nA-priori bounds: T in [{:.4}, {:.4}] N, \
         |tau| <= [{:.4e}, {:.4e}, {:.4e}] N m. Rotor capacity over that interval (the limits): \
         T_max = {:.4} N, tau_max = [{:.4e}, {:.4e}, {:.4e}] N m.\n",
        r.margins.tightest_condition.0,
        r.margins.tightest_condition.1,
        r.a_priori.0,
        r.a_priori.1,
        r.a_priori.2[0],
        r.a_priori.2[1],
        r.a_priori.2[2],
        r.limits.thrust_max_N,
        r.limits.torque_max_Nm[0],
        r.limits.torque_max_Nm[1],
        r.limits.torque_max_Nm[2],
    );
    let g = &r.gains;
    let _ = writeln!(s, "## Gains\n");
    Table::new(
        &mut s,
        &[
            "k_p", "k_v", "k_f", "k_s", "M_p", "k_theta", "k_omega", "M_theta", "M_omega", "delta",
            "alpha",
        ],
        Rule::Compact,
    )
    .row(&[
        format!("{:.4}", g.kp),
        format!("{:.4}", g.kv),
        format!("{:.4}", g.kf),
        format!("{:.4}", g.ks),
        format!("{:.4}", g.M_p),
        format!("{:.4e}", g.k_theta),
        format!("{:.4e}", g.k_omega),
        format!("{:.4e}", g.M_theta),
        format!("{:.4e}", g.M_omega),
        g.delta.to_string(),
        g.alpha.to_string(),
    ]);
    let _ = writeln!(s);
    if let Some(t) = &g.tilt_priority {
        let _ = writeln!(
            s,
            "Tilt priority (`[gains.tilt_priority]`, docs/tilt-priority.md; `k_omega`, `M_omega` above \
             are unused): trace weights G = diag({:.4e}, {:.4e}, {:.4e}) N m, per-axis damping gains \
             [{:.4e}, {:.4e}, {:.4e}] N m s/rad, levels [{:.4e}, {:.4e}, {:.4e}] N m; feedback levels \
             iota_i = [{:.4e}, {:.4e}, {:.4e}] N m (roll and pitch first: the body z axis turns to the \
             thrust direction, the heading after).\n",
            t.trace_weights_Nm[0],
            t.trace_weights_Nm[1],
            t.trace_weights_Nm[2],
            t.omega_gains_Nm_s[0],
            t.omega_gains_Nm_s[1],
            t.omega_gains_Nm_s[2],
            t.omega_levels_Nm[0],
            t.omega_levels_Nm[1],
            t.omega_levels_Nm[2],
            r.feedback_torque_axes_Nm[0],
            r.feedback_torque_axes_Nm[1],
            r.feedback_torque_axes_Nm[2],
        );
        if let (Some(level), Some(onset)) = (t.turn_over_level_Nm, t.turn_over_onset) {
            let _ = writeln!(
                s,
                "Turn-over term (docs/turn-over.md; in the levels above): {level:.4e} N m about \
                 the axis of a horizontal half turn, from a horizontal MRP norm of {onset} ({:.1} \
                 deg) on.\n",
                4.0 * onset.atan().to_degrees()
            );
        }
    }
    if let Some(v) = &g.velocity_limit {
        let _ = writeln!(
            s,
            "Velocity-limited position feedback (`[gains.velocity_limit]`, `--speed-limit`, \
             docs/velocity-limit.md): speed limit {} m/s, braking {:.4} m/s^2 ({:.1} of M_p); the \
             paper's law within |z1| <= {:.4} m of the reference, the same certificate.\n",
            v.speed_m_s,
            v.braking_m_s2,
            v.braking_m_s2 / g.M_p,
            v.braking_m_s2 * (g.kv / g.kp).powi(2),
        );
        if let Some((up, down)) = v.vertical_braking() {
            let _ = writeln!(
                s,
                "Vertically, with the vertical channel apart, the profile brakes at {up:.4} m/s^2 \
                 above the reference and {down:.4} m/s^2 below it (the same share of M_up and \
                 M_down).\n",
            );
        }
    }
    if let Some(v) = &g.vertical {
        let _ = writeln!(
            s,
            "Vertical channel (`[gains.vertical]`, docs/vertical-channel.md): braking (upward) \
             level M_up = {:.4} m/s^2, downward level M_down = {:.4} m/s^2 (horizontal M_p = {:.4} \
             m/s^2), its own filters k_f,z = {:.4} 1/s, k_s,z = {:.4} 1/s.\n",
            v.up_m_s2, v.down_m_s2, g.M_p, v.kf, v.ks
        );
    }
    if let (Some(l), Some(e)) = (&g.local, &r.local_regime) {
        let vertical = l.vertical.map_or(String::new(), |v| {
            format!(
                " and its own vertical filters k_f,z,L = {:.4} 1/s, k_s,z,L = {:.4} 1/s",
                v.kf, v.ks
            )
        });
        let vertical = match l.vertical.and_then(|v| v.up_m_s2.zip(v.down_m_s2)) {
            Some((up, down)) => {
                format!("{vertical} and levels M_up,L = {up:.4} m/s^2, M_down,L = {down:.4} m/s^2")
            }
            None => vertical,
        };
        let braking = l.braking_m_s2.map_or(String::new(), |b| {
            format!(", its own horizontal braking {b:.4} m/s^2")
        });
        let attitude = l.attitude.map_or(String::new(), |a| {
            let damping = a.tilt_priority.map_or(
                format!("k_omega = {:.4e}, M_omega = {:.4e}", a.k_omega, a.M_omega),
                |t| {
                    format!(
                        "roll and pitch damping {:.4e} N m s/rad up to {:.4e} N m",
                        t.omega_gains_Nm_s[0], t.omega_levels_Nm[0]
                    )
                },
            );
            format!(
                ", its own attitude law (`[gains.local.attitude]`: k_theta = {:.4e}, M_theta = \
                 {:.4e}, {damping}; the energies below are this law's)",
                a.k_theta, a.M_theta
            )
        });
        let vertical = format!("{vertical}{braking}{attitude}");
        let _ = writeln!(
            s,
            "Envelope design (`[gains.local]`, docs/envelope-design.md): the local position gains \
             k_p = {:.4}, k_v = {:.4}, k_f = {:.4}, k_s = {:.4}, M_p,L = {:.4} m/s^2{} fly once the \
             attitude energy is at most E_in = {:.4e} J, the global ones again above E_out = {:.4e} J. \
             Inside {{E <= E_out}} (forward invariant): attitude error at most {:.1} deg, |omega \
             error| at most [{:.3}, {:.3}, {:.3}] rad/s; the local gains' U_omega_d_dot = {:.3} \
             rad/s^2 and torque set extents [{:.4e}, {:.4e}, {:.4e}] N m (conditions \
             `local_regime.*`).\n",
            l.kp,
            l.kv,
            l.kf,
            l.ks,
            l.M_p_m_s2,
            vertical,
            l.energy_in_J,
            l.energy_out_J,
            e.angle_out_deg,
            e.omega_error_out_rad_s[0],
            e.omega_error_out_rad_s[1],
            e.omega_error_out_rad_s[2],
            e.angular_acceleration_bound_rad_s2,
            e.torque_extent_Nm[0],
            e.torque_extent_Nm[1],
            e.torque_extent_Nm[2],
        );
    }
    let c = &r.choices;
    // With the turn-over term, roll's feedback level carries the term's bound on top of the
    // fraction of `ι_max` the search chose (docs/turn-over.md).
    let turn_over = match c.tilt.and_then(|t| t.turn_over_share) {
        Some(share) if share > 0.0 => format!(
            " plus the turn-over term's {:.4e} N m about roll",
            r.feedback_torque_Nm.1 - c.iota_fraction * r.feedback_torque_Nm.0
        ),
        _ => String::new(),
    };
    let _ = writeln!(
        s,
        "Chosen: M_p = {:.3} of its largest certifiable value {:.4} m/s^2; iota = {:.4e} N m = {:.3} of \
         iota_max = {:.4e} N m{turn_over}; attitude natural frequency {:.2} rad/s (smallest-inertia axis), \
         damping {:.2}; position natural frequency {:.2} rad/s, damping {:.2}.\n",
        c.saturation_fraction,
        r.saturation_max_m_s2,
        r.feedback_torque_Nm.1,
        c.iota_fraction,
        r.feedback_torque_Nm.0,
        c.attitude_frequency_rad_s,
        c.attitude_damping,
        c.position_frequency_rad_s,
        c.position_damping
    );
    if let Some(w) = &r.what_binds {
        what_binds::write(&mut s, r, w);
    }
    let o = &r.objective;
    let a = &o.authority;
    let [t_lo, t_hi] = a.thrust_interval_over_weight;
    let interval = format!("thrust interval [{t_lo:.3}, {t_hi:.3}] x the weight");
    let [x, y, z] = a.feedback_angular_acceleration_rad_s2;
    let acceleration =
        format!("feedback angular acceleration iota/J = [{x:.2}, {y:.2}, {z:.2}] rad/s^2");
    if !o.constraints_met {
        let _ = writeln!(
            s,
            "**NO DESIGN WITHIN THE BUDGET MET THE CONVERGENCE CONSTRAINTS** (every 180 degree start and \
             the upside-down start settled by {:.0} s, also with the motor time constant doubled, and \
             the turned and random starts with it doubled). The \
             certificate holds, but the certified authority is small: {interval}, {acceleration}. The \
             design below is the best found on the graded penalty.\n",
            r.duration_s - super::evaluate::TAIL_S,
        );
    }
    let _ = writeln!(s, "Certified authority: {interval}; {acceleration}.\n");
    let t = &r.thrust;
    let _ = writeln!(
        s,
        "Thrust: `{}`{}; certified thrust interval [{:.4}, {:.4}] N (with the torque set, what the \
         firmware's gate checks against the rotors).\n",
        t.mode,
        if t.floor_N > 0.0 {
            format!(
                ", floor {:.4} N (the lowest at which the certified torque set still fits the rotors \
                 with the margin)",
                t.floor_N
            )
        } else {
            String::new()
        },
        t.interval_N[0],
        t.interval_N[1]
    );
    let _ = writeln!(
        s,
        "## Objective\n\n{}.\n\nValue {:.3}; constraints met: **{}**. Worst settling from 180 degrees: **{}**; \
         altitude lost from upside down at hover: **{:.3} m**.\n",
        o.definition,
        o.value,
        o.constraints_met,
        opt(o.worst_settling_180_s, "s"),
        o.altitude_loss_upside_down_m
    );
    if let Some(t) = &o.upside_down_turn_over {
        let braking = t
            .mean_braking_m_s2(o.altitude_loss_upside_down_m)
            .map(|a| format!(", braked at {a:.2} m/s^2 on average"))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "Where the altitude goes upside down: the turn-over (until the body z axis is back \
             above the horizon) took {:.2} s and {:.2} m, sinking at {:.2} m/s by then; the \
             braking after it took the other {:.2} m{braking}. A long turn-over is the attitude \
             feedback's torque near the half turn (the radial MRP term); a long braking is the \
             position loop's level (`M_p`, or `M_up` with the vertical channel) and how fast its \
             filters (`k_f`, `k_s`, or `k_f,z`, `k_s,z`) let the command reach it.\n",
            t.time_s,
            t.altitude_loss_m,
            t.sink_rate_m_s,
            o.altitude_loss_upside_down_m - t.altitude_loss_m,
        );
    }
    let mut table = Table::new(
        &mut s,
        &[
            "start",
            "settling (nominal)",
            "settling (motor lag doubled)",
        ],
        Rule::Compact,
    );
    for (i, (name, t)) in o.settling_180_s.iter().enumerate() {
        let d = r
            .margins
            .doubled_lag_settling_180_s
            .get(i)
            .and_then(|x| x.1);
        table.row(&[name.to_string(), opt(*t, "s"), opt(d, "s")]);
    }
    s.push_str(
        "\nNominal tasks from hover (10 s runs, as `host-sim compare` flies them) and the \
         certified helix from the scenario's initial state over its run length, the design \
         beside the baselines on the same vehicle, plant and motor lag (what the certificate \
         costs):\n\n",
    );
    let mut tasks = Table::new(
        &mut s,
        &[
            "controller (same vehicle, plant, motor lag)",
            "1 m step: settling",
            "1 m step: error at 10 s",
            "30 deg roll: settling",
            "certified helix: mean error over the last 5 s",
        ],
        Rule::Compact,
    );
    for row in &o.nominal_tasks {
        tasks.row(&[
            row.label.clone(),
            opt(row.step_settling_time_s, "s"),
            format!("{:.2e} m", row.step_final_position_error_m),
            opt(row.tilt_settling_time_s, "s"),
            row.helix_tracking_error_m
                .map_or("–".to_owned(), |e| format!("{e:.2e} m")),
        ]);
    }
    if let Some(d) = &o.disturbed_hover {
        let _ = writeln!(
            s,
            "\nDisturbed hover (the integral action's covered disturbance: plant mass and a \
             downward force, from rest): settling **{}**, altitude lost {:.3} m, final error {:.2e} m.",
            opt(d.settling_s, "s"),
            d.altitude_loss_m,
            d.final_position_error_m
        );
    }
    let m = &r.margins;
    let _ = writeln!(
        s,
        "\n## Margins\n\n- rotor fit: {:.2} % of the rotor range (requested {:.0} %)\n- motor time constant: {} s; \
         doubled converges (180 degree, turned and random starts): {}; largest that still converges (seven 180 degree starts, bisection): {}\n",
        100.0 * m.rotor_fit,
        100.0 * r.rotor_fit.requested_margin,
        m.motor_time_constant_s,
        m.doubled_lag_converges,
        opt(m.motor_time_constant_max_converging_s, "s")
    );
    if !plots.is_empty() {
        let _ = writeln!(s, "## Plots\n");
        for p in plots {
            let _ = writeln!(s, "![{p}]({p})\n");
        }
    }
    s
}

const AXES: [&str; 3] = ["roll", "pitch", "yaw"];

/// One searched candidate as design.md lists it: `name`, its `objective` to three decimals,
/// `note`, and "(constraints not met)" when they are not.
fn candidate(name: &str, objective: f64, note: &str, constraints_met: bool) -> String {
    let unmet = if constraints_met {
        ""
    } else {
        " (constraints not met)"
    };
    format!("{name} {objective:.3}{note}{unmet}")
}
