use super::*;
use crate::mrp::{mrp_kinematics, rotation_from_mrp};
use approx::assert_relative_eq;
use proptest::prelude::*;

fn attitude() -> AttitudeGains<f64> {
    AttitudeGains {
        k_mrp: 4.0,
        k_omega: 0.1,
        mrp_saturation: 0.03,
        omega_saturation: 0.045,
    }
}

fn tilt() -> TiltPriorityGains<f64> {
    TiltPriorityGains {
        trace_weights: Vector3::new(0.04, 0.06, 0.4),
        omega_gains: Vector3::new(0.08, 0.09, 0.05),
        omega_levels: Vector3::new(0.12, 0.11, 0.03),
        turn_over: None,
    }
}

const DELTA: f64 = 0.02;

/// `V_pot = Ψ_MRP(ϑ) + ½ tr(G(I − R(ϑ)))`, the potential part of the Lyapunov function.
fn potential(t: &TiltPriorityGains<f64>, a: &AttitudeGains<f64>, mrp: &Vector3<f64>) -> f64 {
    let (m, k) = (a.mrp_saturation, a.k_mrp);
    let radial = m / k * ((m * m + k * k * mrp.norm_squared()).sqrt() - m);
    let r = rotation_from_mrp(mrp);
    let g = Matrix3::from_diagonal(&t.trace_weights);
    radial + 0.5 * (g * (Matrix3::identity() - r)).trace()
}

fn ball_point() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.0..1.0f64).prop_filter_map(
        "nonzero direction",
        |(a, b, c, s)| {
            let v = Vector3::new(a, b, c);
            (v.norm() > 1e-3).then(|| v.normalize() * (s * (1.0 + DELTA)))
        },
    )
}

fn v3(scale: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-scale..scale, -scale..scale, -scale..scale).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

proptest! {
    /// The feedback's attitude part is minus the potential's rate per unit `ω̃`: along the MRP
    /// kinematics `ϑ̇ = T(ϑ)ω̃`, `d/dt V_pot = −ω̃ᵀ(τ_radial + τ_trace)` (finite difference of an
    /// independently written potential), which is what makes `V̇ = −ω̃ᵀ s_ω(ω̃)` on flows.
    #[test]
    fn attitude_feedback_is_the_potential_gradient(mrp in ball_point(), w in v3(3.0)) {
        let (t, a) = (tilt(), attitude());
        let out = t.evaluate(&a, &mrp, &w, &rotation_from_mrp(&mrp), &Vector3::zeros(),
            &Vector3::zeros(), &Vector3::new(1.0, 1.0, 1.0));
        let attitude_part = out.torque + out.s_omega;
        let rate = mrp_kinematics(&mrp) * w;
        let h = 1e-6;
        let fd = (potential(&t, &a, &(mrp + rate * h)) - potential(&t, &a, &(mrp - rate * h)))
            / (2.0 * h);
        prop_assert!((fd + w.dot(&attitude_part)).abs() < 1e-7 * (1.0 + fd.abs()),
            "dV/dt {fd} vs -w.tau {}", -w.dot(&attitude_part));
    }

    /// With `ω_d = ω̇_d = 0` every torque component stays within its `ι_i` (the trace term
    /// evaluated on `R(ϑ)`, any `ω̃`), and the damping is dissipative.
    #[test]
    fn feedback_is_bounded_by_the_per_axis_levels(mrp in ball_point(), w in v3(80.0)) {
        let (t, a) = (tilt(), attitude());
        let out = t.evaluate(&a, &mrp, &w, &rotation_from_mrp(&mrp), &Vector3::zeros(),
            &Vector3::zeros(), &Vector3::new(2.24e-3, 2.9e-3, 5.3e-3));
        let levels = t.feedback_levels(a.mrp_saturation, DELTA);
        for i in 0..3 {
            prop_assert!(out.torque[i].abs() <= levels[i], "axis {i}: {} > {}", out.torque[i], levels[i]);
        }
        prop_assert!(w.dot(&out.s_omega) >= 0.0);
    }

    /// Where the hysteresis-band condition holds, the potential grows along every ray of the
    /// flow set, including the band `1 ≤ |ϑ| ≤ 1 + δ` beyond the half turn.
    #[test]
    fn potential_grows_along_rays_when_the_band_condition_holds(
        n in ball_point(), s in 0.02..1.0f64
    ) {
        let (t, a) = (tilt(), attitude());
        let (lhs, rhs) = t.hysteresis_band(&a, DELTA);
        prop_assert!(lhs > rhs);
        let n = n.normalize();
        let r = s * (1.0 + DELTA);
        let h = 1e-6;
        let d = (potential(&t, &a, &(n * (r + h))) - potential(&t, &a, &(n * (r - h)))) / (2.0 * h);
        prop_assert!(d > 0.0, "dV/dr = {d} at r = {r}, n = {n:?}");
    }
}

/// Tilt priority with the turn-over term (docs/turn-over.md).
fn tilt_turning() -> TiltPriorityGains<f64> {
    TiltPriorityGains {
        turn_over: Some(crate::turn_over::TurnOver {
            level: 0.25,
            onset: 0.8,
        }),
        ..tilt()
    }
}

proptest! {
    /// With the turn-over term the law is still bounded by its per-axis levels (which carry the
    /// term's bounds), and its attitude part is still minus the rate of the potential, now
    /// `Ψ_MRP + ½ tr(G(I − R̃)) + Ψ_t`.
    #[test]
    fn the_turn_over_term_keeps_the_levels_and_the_gradient(mrp in ball_point(), w in v3(3.0)) {
        let (t, a) = (tilt_turning(), attitude());
        let j = Vector3::new(2.24e-3, 2.9e-3, 5.3e-3);
        let out = t.evaluate(&a, &mrp, &w, &rotation_from_mrp(&mrp), &Vector3::zeros(),
            &Vector3::zeros(), &j);
        let levels = t.feedback_levels(a.mrp_saturation, DELTA);
        for i in 0..3 {
            prop_assert!(out.torque[i].abs() <= levels[i], "axis {i}: {} > {}", out.torque[i], levels[i]);
        }
        let turn = t.turn_over.expect("on");
        let v = |m: &Vector3<f64>| potential(&t, &a, m) + turn.potential(m);
        let rate = mrp_kinematics(&mrp) * w;
        let h = 1e-6;
        let fd = (v(&(mrp + rate * h)) - v(&(mrp - rate * h))) / (2.0 * h);
        let attitude_part = out.torque + out.s_omega;
        prop_assert!((fd + w.dot(&attitude_part)).abs() < 1e-6 * (1.0 + fd.abs()),
            "dV/dt {fd} vs -w.tau {}", -w.dot(&attitude_part));
    }
}

/// Given the vehicle exactly upside down (a half turn about x), when tilt priority evaluates,
/// then without the turn-over term only the small radial MRP term pushes; with it, roll gets
/// the term's whole level more, and yaw nothing.
#[test]
fn upside_down_the_turn_over_term_adds_its_level_about_roll() {
    let a = attitude();
    let mrp = Vector3::new(1.0, 0.0, 0.0);
    let r = rotation_from_mrp(&mrp);
    let j = Vector3::new(2.24e-3, 2.9e-3, 5.3e-3);
    let z = Vector3::zeros();
    let off = tilt().evaluate(&a, &mrp, &z, &r, &z, &z, &j).torque;
    let on = tilt_turning().evaluate(&a, &mrp, &z, &r, &z, &z, &j).torque;
    // The radial term at |ϑ| = 1: (1 + 1)/4 · s_ϑ, s_ϑ just below its level M_ϑ.
    assert_relative_eq!(off.x, -0.5 * a.mrp_saturation, max_relative = 1e-3);
    assert_relative_eq!(on - off, Vector3::new(-0.25, 0.0, 0.0), epsilon = 1e-12);
}

/// The band condition is not vacuous: with the radial level far below it, the potential
/// decreases along the ray through a half turn about a horizontal axis inside the band, so
/// the feedback has a zero there (a spurious equilibrium the condition excludes).
#[test]
fn a_weak_radial_term_leaves_a_zero_in_the_band() {
    let t = tilt();
    let a = AttitudeGains {
        mrp_saturation: 1e-4,
        ..attitude()
    };
    let (lhs, rhs) = t.hysteresis_band(&a, DELTA);
    assert!(lhs < rhs);
    let n = Vector3::new(1.0, 0.0, 0.0);
    let r = 1.0 + DELTA;
    let h = 1e-6;
    let d = (potential(&t, &a, &(n * (r + h))) - potential(&t, &a, &(n * (r - h)))) / (2.0 * h);
    assert!(d < 0.0, "dV/dr = {d}");
}

/// The trace torque near `R̃ = I` is the stiffness `½(g_j + g_k)` per axis, and for a tilt
/// about x it has no yaw component; yaw alone gets only `½(g₁ + g₂)`.
#[test]
fn trace_torque_stiffness_and_tilt_has_no_yaw() {
    let t = tilt();
    let g = t.trace_weights;
    let eps = 1e-6;
    for (i, k) in [
        (0, 0.5 * (g.y + g.z)),
        (1, 0.5 * (g.z + g.x)),
        (2, 0.5 * (g.x + g.y)),
    ] {
        let phi = Vector3::ith(i, eps);
        let tau = t.trace_torque(&rotation_from_mrp(&(phi / 4.0)));
        assert_relative_eq!(tau[i], -k * eps, max_relative = 1e-5);
    }
    for angle in [0.3f64, 1.5, 3.0] {
        let tilt_x = rotation_from_mrp(&Vector3::new((angle / 4.0).tan(), 0.0, 0.0));
        let tau = t.trace_torque(&tilt_x);
        assert_relative_eq!(tau.x, -0.5 * (g.y + g.z) * angle.sin(), epsilon = 1e-12);
        assert_eq!(tau.z, 0.0);
    }
}

/// At zero error the law gives exactly the feedforward torque, as the paper's does.
#[test]
fn zero_error_gives_the_feedforward_torque() {
    let (t, a) = (tilt(), attitude());
    let j = Vector3::new(2.24e-3, 2.9e-3, 5.3e-3);
    let wd = Vector3::new(0.3, -1.2, 2.0);
    let wdd = Vector3::new(4.0, 1.0, -3.0);
    let out = t.evaluate(
        &a,
        &Vector3::zeros(),
        &wd,
        &Matrix3::identity(),
        &wd,
        &wdd,
        &j,
    );
    let paper = a.evaluate(&Vector3::zeros(), &wd, &Matrix3::identity(), &wd, &wdd, &j);
    assert_relative_eq!(out.torque, paper.torque, epsilon = 1e-15);
}

#[test]
fn bad_gains_are_refused_by_name() {
    let mut t = tilt();
    t.trace_weights.y = -0.1;
    assert!(matches!(
        t.validate(),
        Err(ParameterError::NotPositive { name: "g_2", .. })
    ));
    let mut t = tilt();
    t.omega_levels.z = f64::NAN;
    assert!(matches!(
        t.validate(),
        Err(ParameterError::NotPositive {
            name: "M_omega_3",
            ..
        })
    ));
    assert!(tilt().validate().is_ok());
}
