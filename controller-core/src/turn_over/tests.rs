use super::*;
use crate::mrp::{mrp_kinematics, rotation_from_mrp, shadow_mrp};
use crate::tilt_priority::TiltPriorityGains;
use approx::assert_relative_eq;
use proptest::prelude::*;

const DELTA: f64 = 0.02;

fn term(onset: f64) -> TurnOver<f64> {
    TurnOver { level: 0.3, onset }
}

/// A point of the flow set `|ϑ| ≤ 1 + δ`, weighted towards the band near the half turn where
/// the term acts.
fn ball_point() -> impl Strategy<Value = Vector3<f64>> {
    (
        -1.0..1.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        0.0..1.0f64,
        any::<bool>(),
    )
        .prop_filter_map("nonzero direction", |(a, b, c, s, near)| {
            let v = Vector3::new(a, b, c);
            let r = if near { 0.7 + 0.3 * s } else { s };
            (v.norm() > 1e-3).then(|| v.normalize() * (r * (1.0 + DELTA)))
        })
}

/// Given a horizontal half turn, when the term is evaluated, then it pushes about that axis
/// with its whole level, back towards zero error, with no yaw.
#[test]
fn a_horizontal_half_turn_gets_the_whole_level_about_its_axis() {
    let t = term(0.8);
    for angle in [0.0f64, 0.7, 2.0, 4.0] {
        let axis = Vector3::new(angle.cos(), angle.sin(), 0.0);
        let tau = t.torque(&axis);
        assert_relative_eq!(tau, -axis * t.level, epsilon = 1e-12);
    }
}

/// Given an error inside the onset (a rotation by less than 4 atan ρ₀ about a horizontal axis,
/// or any yaw error), the term is zero and so is its potential.
#[test]
fn the_term_is_off_below_its_onset() {
    let t = term(0.8);
    for mrp in [
        Vector3::new(0.79, 0.0, 0.3),
        Vector3::new(0.3, -0.5, 0.9),
        Vector3::new(0.0, 0.0, 1.02),
    ] {
        assert_eq!(t.torque(&mrp), Vector3::zeros());
        assert_eq!(t.potential(&mrp), 0.0);
    }
}

/// Parameters outside their ranges are refused by name.
#[test]
fn bad_parameters_are_refused_by_name() {
    let bad = |t: TurnOver<f64>| match t.validate() {
        Err(ParameterError::NotPositive { name, .. } | ParameterError::OutOfRange { name, .. }) => {
            name
        }
        other => panic!("{other:?}"),
    };
    assert_eq!(
        bad(TurnOver {
            level: 0.0,
            onset: 0.8
        }),
        "turn_over_level"
    );
    assert_eq!(
        bad(TurnOver {
            level: f64::NAN,
            onset: 0.8
        }),
        "turn_over_level"
    );
    assert_eq!(
        bad(TurnOver {
            level: 0.2,
            onset: 1.0
        }),
        "turn_over_onset"
    );
    assert_eq!(
        bad(TurnOver {
            level: 0.2,
            onset: 0.0
        }),
        "turn_over_onset"
    );
    assert!(term(0.8).validate().is_ok());
    // Through tilt priority's validation too.
    let tilt = TiltPriorityGains {
        trace_weights: Vector3::new(0.01, 0.01, 0.3),
        omega_gains: Vector3::repeat(0.05),
        omega_levels: Vector3::repeat(0.05),
        turn_over: Some(TurnOver {
            level: 0.2,
            onset: 1.5,
        }),
    };
    assert!(matches!(
        tilt.validate(),
        Err(ParameterError::OutOfRange {
            name: "turn_over_onset",
            ..
        })
    ));
}

/// The bounds are attained: a fine grid over the half-ball `ϑ₁ ≥ 0`, `ϑ₂ = 0` (the term is
/// symmetric about the vertical) comes within 1 % of each closed form.
#[test]
fn the_bounds_are_tight() {
    for onset in [0.5, 0.8, 0.95] {
        let t = term(onset);
        let b = t.bounds(DELTA);
        let mut seen = Vector3::<f64>::zeros();
        let n = 2000;
        for i in 0..=n {
            for j in 0..=n {
                let r = (1.0 + DELTA) * i as f64 / n as f64;
                let phi = std::f64::consts::FRAC_PI_2 * j as f64 / n as f64;
                let mrp = Vector3::new(r * phi.cos(), 0.0, r * phi.sin());
                seen = seen.sup(&t.torque(&mrp).abs());
            }
        }
        assert!(
            seen.x >= 0.99 * b.x && seen.x <= b.x,
            "{onset}: roll {seen:?} vs {b:?}"
        );
        assert!(
            seen.z >= 0.99 * b.z && seen.z <= b.z,
            "{onset}: yaw {seen:?} vs {b:?}"
        );
        // Yaw's bound is a fraction of roll's: the point of the term.
        assert!(b.z < 0.3 * b.x, "{onset}: {b:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// Every component stays within its bound over the flow set, for any onset.
    #[test]
    fn the_torque_stays_within_its_bounds(mrp in ball_point(), onset in 0.05..0.99f64) {
        let t = term(onset);
        let (tau, b) = (t.torque(&mrp), t.bounds(DELTA));
        for i in 0..3 {
            prop_assert!(tau[i].abs() <= b[i] * (1.0 + 1e-12), "axis {i}: {} > {}", tau[i], b[i]);
        }
    }

    /// The torque is minus the potential's rate per unit `ω̃`: along `ϑ̇ = T(ϑ)ω̃`,
    /// `d/dt Ψ_t = −ω̃ᵀτ_t` (finite difference of the potential), so adding `Ψ_t` to tilt
    /// priority's Lyapunov function keeps `V̇ = −ω̃ᵀ s_ω(ω̃)` on flows.
    #[test]
    fn the_torque_is_the_potential_gradient(
        mrp in ball_point(), w in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64), onset in 0.3..0.95f64
    ) {
        let t = term(onset);
        let w = Vector3::new(w.0, w.1, w.2);
        let rate = mrp_kinematics(&mrp) * w;
        let h = 1e-6;
        let fd = (t.potential(&(mrp + rate * h)) - t.potential(&(mrp - rate * h))) / (2.0 * h);
        prop_assert!((fd + w.dot(&t.torque(&mrp))).abs() < 1e-6 * (1.0 + fd.abs()),
            "dPsi/dt {fd} vs -w.tau {}", -w.dot(&t.torque(&mrp)));
    }

    /// At the path lifting's jump `ϑ → −ϑ/|ϑ|²` (the same rotation, `|ϑ| > 1`) the potential
    /// does not grow: the horizontal part shrinks by `1/|ϑ|²`, so tilt priority's Lyapunov
    /// function with `Ψ_t` still decreases at jumps.
    #[test]
    fn the_path_lifting_jump_does_not_raise_the_potential(
        n in ball_point(), r in 1.0..(1.0 + DELTA), onset in 0.3..0.95f64
    ) {
        let mrp = n.normalize() * r;
        let t = term(onset);
        let s = shadow_mrp(&mrp).expect("nonzero MRP");
        assert_relative_eq!(rotation_from_mrp(&s), rotation_from_mrp(&mrp), epsilon = 1e-9);
        prop_assert!(t.potential(&s) <= t.potential(&mrp));
    }

    /// Along every ray of the flow set the potential does not decrease, so it adds no zero to
    /// tilt priority's feedback (its hysteresis-band condition is unchanged).
    #[test]
    fn the_potential_does_not_decrease_along_rays(n in ball_point(), s in 0.02..1.0f64) {
        let t = term(0.8);
        let n = n.normalize();
        let r = s * (1.0 + DELTA);
        prop_assert!(t.potential(&(n * (r + 1e-4))) >= t.potential(&(n * r)));
    }
}
