//! Given tilt priority's gains, when its attitude terms are sampled along a direction, then the
//! sample never exceeds what the certified set charges them nor their certified joint bound, the charge is their share of the
//! set (by hand), and a term alone is sampled up to its support.

use approx::assert_relative_eq;
use nalgebra::Vector3;
use proptest::prelude::*;

use controller_core::tilt_priority::TiltPriorityGains;
use controller_core::torque_set::attitude_joint::{AttitudeJoint, JOINT_SLABS};
use controller_core::torque_set::TorqueSet;
use controller_core::turn_over::TurnOver;
use controller_core::Gains;

use super::sample_attitude_terms;

fn gains(g12: f64, g3: f64, mrp_saturation: f64, turn_over: Option<(f64, f64)>) -> Gains<f64> {
    let mut gains = Gains::paper();
    gains.attitude.mrp_saturation = mrp_saturation;
    gains.tilt_priority = Some(TiltPriorityGains {
        trace_weights: Vector3::new(g12, g12, g3),
        omega_gains: Vector3::repeat(0.1),
        omega_levels: Vector3::repeat(0.1),
        turn_over: turn_over.map(|(level, onset)| TurnOver { level, onset }),
    });
    gains
}

/// The certified set of `gains` as `certify` builds it for tilt priority, with the
/// feedforward's norms `rates` (`U_ωd`, `U_ω̇d`), the damping levels and turn-over bounds in
/// its box and the attitude terms' joint bound.
fn certified_set(gains: &Gains<f64>, rates: (f64, f64)) -> TorqueSet<f64> {
    let tilt = gains.tilt_priority.expect("tilt priority");
    let a = 1.0 + gains.hysteresis;
    TorqueSet {
        attitude_joint: AttitudeJoint::of(
            &tilt,
            gains.attitude.mrp_saturation,
            gains.attitude.k_mrp,
            gains.hysteresis,
            JOINT_SLABS,
        ),
        ..TorqueSet::tilt_priority(
            Vector3::new(0.024, 0.024, 0.044),
            rates.0,
            rates.1,
            (1.0 + a * a) * gains.attitude.mrp_saturation * 0.25,
            tilt.trace_weights,
            tilt.omega_levels + tilt.turn_over_bounds(gains.hysteresis),
        )
    }
}

#[test]
fn the_papers_law_has_nothing_to_sample() {
    let d = Vector3::new(0.7, 0.0, 7.8);
    let tilt = gains(0.01, 0.8, 0.04, None);
    let set = certified_set(&tilt, (1.0, 2.0));
    assert!(sample_attitude_terms(&Gains::paper(), &set, &d, 4).is_none());
    assert!(sample_attitude_terms(&tilt, &set, &d, 0).is_none());
}

#[test]
fn the_charge_is_the_attitude_terms_share_of_the_set() {
    // The balls `(r + g_min)|d|`, the disks `Σ_k ½(g_k − g_min)|d − d_k e_k|` and the turn-over
    // box `Σ_i |d_i| t_i`, by hand: neither the feedforward's parts nor the damping levels.
    let g = gains(0.013, 0.8, 0.037, Some((0.2, 0.8)));
    let tilt = g.tilt_priority.expect("tilt priority");
    let a = 1.0 + g.hysteresis;
    let radial = (1.0 + a * a) * g.attitude.mrp_saturation * 0.25;
    let w = tilt.trace_weights;
    let turn = tilt.turn_over_bounds(g.hysteresis);
    let set = certified_set(&g, (3.0, 5.0));
    for d in [
        Vector3::new(0.718, 0.0, 7.812),
        Vector3::new(-1.4, 1.4, 15.6),
        Vector3::new(0.0, 1.0, 0.0),
    ] {
        let disks: f64 = (0..3)
            .map(|k| {
                let mut off_axis = d;
                off_axis[k] = 0.0;
                0.5 * (w[k] - w.min()) * off_axis.norm()
            })
            .sum();
        let by_hand = (radial + w.min()) * d.norm() + disks + d.abs().dot(&turn);
        let s = sample_attitude_terms(&g, &set, &d, 4).expect("tilt priority");
        assert_relative_eq!(s.charged_n, by_hand, max_relative = 1e-12);
    }
}

#[test]
fn the_trace_terms_disk_alone_is_sampled_up_to_its_support() {
    // G = diag(0, 0, g₃) and a negligible radial term: the torque is ½ g₃ (R̃ᵀe₃) × e₃, which
    // reaches ½ g₃ |d_xy| at a 90° tilt about the right axis; the set's disk charges exactly that.
    let g = gains(0.0, 0.8, 1e-9, None);
    let d = Vector3::new(0.718, 0.3, 7.812);
    let s =
        sample_attitude_terms(&g, &certified_set(&g, (0.0, 0.0)), &d, 24).expect("tilt priority");
    assert_relative_eq!(s.charged_n, 0.4 * d.xy().norm(), max_relative = 1e-6);
    assert!(s.sampled_n <= s.charged_n);
    assert!(
        s.sampled_n >= 0.99 * s.charged_n,
        "sampled {} of {}",
        s.sampled_n,
        s.charged_n
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn the_sample_never_exceeds_the_charge_nor_the_joint_bound(
        g12 in 0.0..0.5f64,
        g3 in 0.0..2.0f64,
        mrp_saturation in 1e-3..0.5f64,
        level in 0.0..0.8f64,
        onset in 0.3..0.95f64,
        d in prop::array::uniform3(-10.0..10.0f64),
    ) {
        let turn_over = (level > 0.05).then_some((level, onset));
        let g = gains(g12, g3, mrp_saturation, turn_over);
        let d = Vector3::from(d);
        let s = sample_attitude_terms(&g, &certified_set(&g, (2.0, 4.0)), &d, 6)
            .expect("tilt priority");
        prop_assert!(
            s.sampled_n <= s.charged_n * (1.0 + 1e-12) + 1e-12,
            "sampled {} > charged {}", s.sampled_n, s.charged_n
        );
        let joint = s.joint_bound_n.expect("g₁ = g₂: a joint bound");
        prop_assert!(
            s.sampled_n <= joint * (1.0 + 1e-12) + 1e-12,
            "sampled {} > the joint bound {joint}", s.sampled_n
        );
    }
}
