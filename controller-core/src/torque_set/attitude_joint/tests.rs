//! The joint bound against the law it bounds: the closed form of the plane reduction equals
//! the law at the points of the plane, no attitude of the flow set (sampled densely, and at
//! random) asks more than the bound along any direction, in `f64` and in `f32`, and the bound is
//! close to what the law asks (it would be useless, not unsound, otherwise).

use nalgebra::Vector3;
use proptest::prelude::*;

use super::{AttitudeJoint, Terms, JOINT_DIRECTIONS, JOINT_SLABS};
use crate::attitude_control::AttitudeGains;
use crate::mrp::rotation_from_mrp;
use crate::scalar::Scalar;
use crate::{TiltPriorityGains, TurnOver};

/// Gains shaped like the x500's design (`host-sim/designs/x500/scenario.toml`) with the
/// turn-over level `level` (zero: off).
fn x500_like(level: f64) -> (TiltPriorityGains<f64>, AttitudeGains<f64>, f64) {
    let mut attitude = crate::Gains::<f64>::paper().attitude;
    attitude.mrp_saturation = 0.0371;
    attitude.k_mrp = 3.98;
    let tilt = TiltPriorityGains {
        trace_weights: Vector3::new(0.0131, 0.0131, 0.797),
        omega_gains: Vector3::new(0.066, 0.066, 0.056),
        omega_levels: Vector3::new(0.38, 0.38, 0.013),
        turn_over: (level > 0.0).then_some(TurnOver { level, onset: 0.8 }),
    };
    (tilt, attitude, 0.02)
}

/// The attitude terms of the law itself at the lifted MRP error `mrp` (damping and
/// feedforward zero: `ω = ω_d = ω̇_d = 0`), body frame [N m].
fn law<T: Scalar>(
    tilt: &TiltPriorityGains<T>,
    attitude: &AttitudeGains<T>,
    mrp: &Vector3<T>,
) -> Vector3<T> {
    let zero = Vector3::zeros();
    tilt.evaluate(
        attitude,
        mrp,
        &zero,
        &rotation_from_mrp(mrp),
        &zero,
        &zero,
        &Vector3::repeat(T::one()),
    )
    .torque
}

fn joint(
    tilt: &TiltPriorityGains<f64>,
    attitude: &AttitudeGains<f64>,
    delta: f64,
) -> AttitudeJoint<f64> {
    AttitudeJoint::of(
        tilt,
        attitude.mrp_saturation,
        attitude.k_mrp,
        delta,
        JOINT_SLABS,
    )
    .expect("g₁ = g₂: the reduction applies")
}

/// The largest `cᵀA(ϑ̃)` over a cubic grid of `n` points per half axis of the flow set, the
/// points outside it taken onto its boundary sphere.
fn sampled(
    tilt: &TiltPriorityGains<f64>,
    attitude: &AttitudeGains<f64>,
    delta: f64,
    c: &Vector3<f64>,
    n: i32,
) -> f64 {
    let r = 1.0 + delta;
    let mut best = f64::NEG_INFINITY;
    for i in -n..=n {
        for j in -n..=n {
            for k in -n..=n {
                let mut m = Vector3::new(i, j, k).cast::<f64>() * (r / f64::from(n));
                if m.norm() > r {
                    m *= r / m.norm();
                }
                best = best.max(c.dot(&law(tilt, attitude, &m)));
            }
        }
    }
    best
}

/// Given a box shrunk to a point `(x, 0, z)` of the plane, when its extremes are taken, then
/// they are the law's `|A_xy|` and `|A_z|` there: the closed form is the law's.
#[test]
fn a_point_box_gives_the_law_at_the_point() {
    for level in [0.0, 0.2] {
        let (tilt, attitude, _) = x500_like(level);
        let terms = Terms::new(&tilt, attitude.mrp_saturation, attitude.k_mrp);
        assert_eq!(terms.turn_over, level);
        for (x, z) in [
            (0.3, 0.4),
            (0.95, 0.1),
            (1.0, 0.2),
            (0.05, 1.01),
            (0.7, 0.7),
        ] {
            let (p, q) = terms.box_extremes((x, x), (z, z), 4.0);
            let a = law(&tilt, &attitude, &Vector3::new(x, 0.0, z));
            assert!(
                (p - a.xy().norm()).abs() < 1e-12,
                "|A_xy| at ({x}, {z}): {p} vs {a:?}"
            );
            assert!(
                (q - a.z.abs()).abs() < 1e-12,
                "|A_z| at ({x}, {z}): {q} vs {a:?}"
            );
        }
    }
}

/// Given the x500's gains with the turn-over term off, at the design's level and at 0.2 N m,
/// when the law is sampled on 33³ points of the flow set along the body axes, rotor-like
/// diagonals and a few oblique directions, then it never asks more than the bound, and the bound is
/// within 4 % (plus 1 mN m) of the largest sample: tight enough to be worth certifying.
#[test]
fn the_law_stays_inside_and_close_to_the_bound_on_a_dense_grid() {
    let directions = [
        Vector3::x(),
        Vector3::z(),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::new(1.0, -1.0, 0.1),
        Vector3::new(0.7, 0.7, -1.0),
        Vector3::new(0.2, 0.0, 1.0),
        Vector3::new(-0.31, 0.83, 0.12),
        Vector3::new(0.55, -0.12, -0.41),
        Vector3::new(0.05, 0.93, 0.61),
    ];
    for level in [0.0, 0.0573, 0.2] {
        let (tilt, attitude, delta) = x500_like(level);
        let bound = joint(&tilt, &attitude, delta);
        for c in &directions {
            let h = bound.support(c);
            let s = sampled(&tilt, &attitude, delta, c, 16);
            assert!(
                s <= h,
                "level {level}, c {c:?}: sample {s} above the bound {h}"
            );
            assert!(
                h <= 1.04 * s + 1e-3,
                "level {level}, c {c:?}: bound {h}, sample {s}"
            );
        }
    }
}

/// Given the bound in `f32` (the board's arithmetic), when the law is sampled in `f64`, then
/// the sample stays below it: the rounding allowance covers `f32`.
#[test]
fn the_f32_bound_holds_the_f64_law() {
    let (tilt, attitude, delta) = x500_like(0.2);
    let tilt32 = TiltPriorityGains {
        trace_weights: tilt.trace_weights.cast::<f32>(),
        omega_gains: tilt.omega_gains.cast::<f32>(),
        omega_levels: tilt.omega_levels.cast::<f32>(),
        turn_over: tilt.turn_over.map(|t| TurnOver {
            level: t.level as f32,
            onset: t.onset as f32,
        }),
    };
    // The f32 gains are the f64 ones rounded: sample the law at the rounded gains too.
    let tilt_rounded = TiltPriorityGains {
        trace_weights: tilt32.trace_weights.cast::<f64>(),
        turn_over: tilt32.turn_over.map(|t| TurnOver {
            level: f64::from(t.level),
            onset: f64::from(t.onset),
        }),
        ..tilt
    };
    let mut attitude_rounded = attitude;
    attitude_rounded.mrp_saturation = f64::from(attitude.mrp_saturation as f32);
    attitude_rounded.k_mrp = f64::from(attitude.k_mrp as f32);
    let bound = AttitudeJoint::<f32>::of(
        &tilt32,
        attitude.mrp_saturation as f32,
        attitude.k_mrp as f32,
        delta as f32,
        JOINT_SLABS,
    )
    .expect("g₁ = g₂");
    for c in [Vector3::x(), Vector3::new(1.0, 0.0, 0.3), Vector3::z()] {
        let h = f64::from(bound.support(&c.cast::<f32>()));
        let s = sampled(
            &tilt_rounded,
            &attitude_rounded,
            f64::from(delta as f32),
            &c,
            16,
        );
        assert!(s <= h, "c {c:?}: sample {s} above the f32 bound {h}");
    }
}

/// Given a coarser grid that divides the certified one, when both bounds are built, then the
/// coarse one is nowhere smaller (a coarse box holds the fine boxes it splits into, and every
/// operation is inclusion-monotone): a design may bisect on the cheap grid and the gate's
/// certified grid still fits.
#[test]
fn a_coarser_grid_is_never_tighter() {
    let (tilt, attitude, delta) = x500_like(0.2);
    let fine = joint(&tilt, &attitude, delta);
    let coarse = AttitudeJoint::of(
        &tilt,
        attitude.mrp_saturation,
        attitude.k_mrp,
        delta,
        JOINT_SLABS / 4,
    )
    .expect("g₁ = g₂");
    for j in 0..=JOINT_DIRECTIONS {
        assert!(
            coarse.support_values[j] >= fine.support_values[j],
            "direction {j}"
        );
    }
}

/// Given trace weights with `g₁ ≠ g₂` (no symmetry about body z), or a negative input, when the
/// bound is asked for, then there is none.
#[test]
fn no_bound_without_the_symmetry() {
    let (mut tilt, attitude, delta) = x500_like(0.2);
    assert!(AttitudeJoint::of(&tilt, attitude.mrp_saturation, -1.0, delta, JOINT_SLABS).is_none());
    tilt.trace_weights.y *= 1.0 + 1e-9;
    assert!(AttitudeJoint::of(
        &tilt,
        attitude.mrp_saturation,
        attitude.k_mrp,
        delta,
        JOINT_SLABS
    )
    .is_none());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Given random gains with `g₁ = g₂` (turn-over on or off), a random attitude of the flow
    /// set (a third of them on its boundary sphere) and a random direction, when the law's
    /// attitude terms are evaluated there, then they never exceed the bound along the direction.
    #[test]
    fn no_attitude_of_the_flow_set_exceeds_the_bound(
        g in 0.0..1.0f64, g3 in 0.0..2.0f64, m in 0.01..2.0f64, k in 0.1..20.0f64,
        level in prop_oneof![Just(0.0), 0.01..1.0f64], onset in 0.3..0.95f64,
        delta in 0.0..0.3f64,
        mrp in prop::array::uniform3(-1.0..1.0f64), on_sphere in prop::bool::weighted(0.33),
        cs in prop::collection::vec(prop::array::uniform3(-1.0..1.0f64), 8),
    ) {
        let mut attitude = crate::Gains::<f64>::paper().attitude;
        attitude.mrp_saturation = m;
        attitude.k_mrp = k;
        let tilt = TiltPriorityGains {
            trace_weights: Vector3::new(g, g, g3),
            omega_gains: Vector3::repeat(1.0),
            omega_levels: Vector3::repeat(1.0),
            turn_over: (level > 0.0).then_some(TurnOver { level, onset }),
        };
        let bound = AttitudeJoint::of(&tilt, m, k, delta, 48).expect("g₁ = g₂");
        let r = 1.0 + delta;
        let mut point = Vector3::from(mrp) * r;
        let n = point.norm();
        if n > r || (on_sphere && n > 0.0) {
            point *= r / n;
        }
        let a = law(&tilt, &attitude, &point);
        for c in cs {
            let c = Vector3::from(c);
            prop_assert!(c.dot(&a) <= bound.support(&c) * (1.0 + 1e-12) + 1e-15,
                "{c:?} at {point:?}: {} above {}", c.dot(&a), bound.support(&c));
        }
    }
}

/// Given tilt priority's certified set with and without the joint bound, when the support is
/// taken along directions, then the joint never charges more, its parts still add up to the
/// support, and along roll at a 0.2 N m turn-over term it frees what the set charged beyond
/// the law (the joint bound is no larger than the law's sample plus
/// 4 %). Along roll the trace term alone is what the law asks, so what is freed is nearly the
/// whole of the turn-over term's box.
#[test]
fn the_set_with_the_joint_bound_charges_less_and_splits() {
    let (tilt, attitude, delta) = x500_like(0.2);
    let radial = (1.0 + (1.0 + delta).powi(2)) * attitude.mrp_saturation / 4.0;
    let apart = crate::TorqueSet::tilt_priority(
        Vector3::new(0.02, 0.02, 0.04),
        1.0,
        3.0,
        radial,
        tilt.trace_weights,
        tilt.omega_levels + tilt.turn_over_bounds(delta),
    );
    let together = crate::TorqueSet {
        attitude_joint: Some(joint(&tilt, &attitude, delta)),
        ..apart
    };
    for c in [
        Vector3::x(),
        Vector3::z(),
        Vector3::new(0.7, -0.7, 0.2),
        Vector3::new(-0.3, 0.1, -0.9),
    ] {
        let (h, h_apart) = (together.support(&c), apart.support(&c));
        assert!(h <= h_apart, "{c:?}: {h} above {h_apart}");
        assert!(
            (together.support_parts(&c).total() - h).abs() < 1e-12,
            "{c:?}"
        );
    }
    let roll = Vector3::x();
    let law_roll = sampled(&tilt, &attitude, delta, &roll, 16);
    let bound = together.attitude_joint.map(|j| j.support(&roll));
    assert!(
        bound.is_some_and(|h| h <= 1.04 * law_roll),
        "roll: {bound:?}, law {law_roll}"
    );
    let freed = apart.support(&roll) - together.support(&roll);
    assert!(
        freed > 0.95 * tilt.turn_over_bounds(delta).x,
        "roll: freed {freed}"
    );
}
