//! The short human summary printed on stdout after a run.

use std::fmt::Write as _;

use crate::fly::sim::Summary;

fn status(ok: bool) -> &'static str {
    if ok {
        "ok"
    } else {
        "OUTSIDE"
    }
}

/// Formats bounds against observed extremes, the conditions, final errors and settling times.
pub fn human_summary(title: &str, summary: &Summary) -> String {
    let a = &summary.a_priori;
    let o = &summary.observed;
    let f = &summary.final_;
    let mut s = String::new();
    let _ = writeln!(s, "{title}");
    let _ = writeln!(
        s,
        "A-priori bounds (Theorem 1, Lemma 1, Theorem 2) vs observed over {} samples:",
        o.samples
    );
    // With the no-dive thrust the certified interval is [T_floor, T_max], not Theorem 1's.
    let [low, high] = a
        .no_dive_thrust_interval_N
        .unwrap_or([a.thrust_min_N, a.thrust_max_N]);
    let thrust_ok = o.thrust_min_N >= low * (1.0 - 1e-5) && o.thrust_max_N <= high * (1.0 + 1e-5);
    let _ = writeln!(
        s,
        "  thrust      bound [{:.3}, {:.3}] N{}    observed [{:.3}, {:.3}] N    {}",
        low,
        high,
        if a.no_dive_thrust_interval_N.is_some() {
            " (no-dive)"
        } else {
            ""
        },
        o.thrust_min_N,
        o.thrust_max_N,
        status(thrust_ok)
    );
    for (i, axis) in ["x (roll)", "y (pitch)", "z (yaw)"].iter().enumerate() {
        let ok = o.torque_abs_max_Nm[i] <= a.torque_max_Nm[i] * (1.0 + 1e-5);
        let _ = writeln!(
            s,
            "  torque {axis:<9} bound ±{:.3} N m      observed max |τ| {:.4} N m    {}",
            a.torque_max_Nm[i],
            o.torque_abs_max_Nm[i],
            status(ok)
        );
    }
    let _ = writeln!(
        s,
        "  |ω_d| ≤ {:.3} rad/s (observed {:.3});  |ω̇_d| ≤ {:.2} rad/s² (observed {:.2})",
        a.angular_velocity_max_rad_s,
        o.angular_velocity_d_max_rad_s,
        a.angular_acceleration_max_rad_s2,
        o.angular_acceleration_d_max_rad_s2
    );
    let held = a.conditions.iter().filter(|c| c.holds).count();
    let _ = writeln!(
        s,
        "Feasibility conditions: {held} of {} hold",
        a.conditions.len()
    );
    for c in a.conditions.iter().filter(|c| !c.holds) {
        let _ = writeln!(
            s,
            "  VIOLATED {}: {}  (lhs {:.4} vs rhs {:.4})",
            c.name, c.statement, c.lhs, c.rhs
        );
    }
    let t = &a.tight;
    let _ = writeln!(
        s,
        "Tight bounds (supremum of the law over its confining set, gap {:.1} %): torque ±({:.3}, {:.3}, {:.3}) N m, |ω_d| ≤ {:.3} rad/s, |ω̇_d| ≤ {:.2} rad/s²",
        100.0 * t.relative_gap,
        t.torque_max_Nm[0],
        t.torque_max_Nm[1],
        t.torque_max_Nm[2],
        t.angular_velocity_max_rad_s,
        t.angular_acceleration_max_rad_s2
    );
    for c in t.conditions.iter().filter(|c| !c.holds_paper) {
        let _ = writeln!(
            s,
            "  {} {}: tau_max {:.4} vs paper's bound {:.4}, tight bound {:.4}",
            c.name,
            c.verdict(),
            c.lhs,
            c.rhs_paper,
            c.rhs_tight
        );
    }
    let _ = writeln!(
        s,
        "Final (t = {:.2} s): position error {:.3e} m, MRP error {:.3e}, angular velocity error {:.3e} rad/s",
        f.time_s, f.position_error_m, f.mrp_error, f.angular_velocity_error_rad_s
    );
    let _ = writeln!(
        s,
        "Altitude lost (initial minus lowest altitude): {:.3} m",
        o.altitude_loss_m
    );
    let since =
        |v: Option<f64>| v.map_or_else(|| "never".to_string(), |t| format!("from {t:.2} s"));
    let _ = writeln!(
        s,
        "Settling: position error < 1 mm {}; MRP error < 1e-4 {}",
        since(summary.settling.position_error_below_1mm_from_s),
        since(summary.settling.mrp_error_below_1e_4_from_s)
    );
    let _ = writeln!(
        s,
        "Path lifting: {} memory-quaternion resets, {} MRP/shadow-MRP flips",
        summary.path_lifting.q_hat_resets, summary.path_lifting.m_flips
    );
    if o.samples_above_tight_bounds > 0 {
        let _ = writeln!(
            s,
            "{} samples exceeded the tight bounds",
            o.samples_above_tight_bounds
        );
    }
    if o.samples_outside_a_priori_bounds > 0 {
        let _ = writeln!(
            s,
            "{} samples left the a-priori bounds",
            o.samples_outside_a_priori_bounds
        );
    }
    s
}
