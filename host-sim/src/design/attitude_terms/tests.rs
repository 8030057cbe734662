//! Given tilt priority's gains, when its attitude terms are sampled along a direction, then the
//! sample never exceeds what the certified set charges them, the charge is the set's own, and a
//! term alone is sampled up to its support.

use approx::assert_relative_eq;
use nalgebra::Vector3;
use proptest::prelude::*;

use controller_core::tilt_priority::TiltPriorityGains;
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

#[test]
fn the_papers_law_has_nothing_to_sample() {
    let d = Vector3::new(0.7, 0.0, 7.8);
    assert!(sample_attitude_terms(&Gains::paper(), &d, 4).is_none());
    assert!(sample_attitude_terms(&gains(0.01, 0.8, 0.04, None), &d, 0).is_none());
}

#[test]
fn the_charge_is_the_certified_sets_own() {
    let g = gains(0.013, 0.8, 0.037, Some((0.2, 0.8)));
    let tilt = g.tilt_priority.expect("tilt priority");
    let a = 1.0 + g.hysteresis;
    let radial = (1.0 + a * a) * g.attitude.mrp_saturation * 0.25;
    // The set with the turn-over bounds as its only box: its feedback parts are the charge.
    let set = TorqueSet::tilt_priority(
        Vector3::repeat(0.02),
        0.0,
        0.0,
        radial,
        tilt.trace_weights,
        tilt.turn_over_bounds(g.hysteresis),
    );
    for d in [
        Vector3::new(0.718, 0.0, 7.812),
        Vector3::new(-1.4, 1.4, 15.6),
        Vector3::new(0.0, 1.0, 0.0),
    ] {
        let p = set.support_parts(&d);
        let s = sample_attitude_terms(&g, &d, 4).expect("tilt priority");
        assert_relative_eq!(
            s.charged_n,
            p.feedback_ball + p.feedback_box + p.feedback_disks,
            max_relative = 1e-12
        );
    }
}

#[test]
fn the_trace_terms_disk_alone_is_sampled_up_to_its_support() {
    // G = diag(0, 0, g₃) and a negligible radial term: the torque is ½ g₃ (R̃ᵀe₃) × e₃, which
    // reaches ½ g₃ |d_xy| at a 90° tilt about the right axis; the set's disk charges exactly that.
    let g = gains(0.0, 0.8, 1e-9, None);
    let d = Vector3::new(0.718, 0.3, 7.812);
    let s = sample_attitude_terms(&g, &d, 24).expect("tilt priority");
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
    fn the_sample_never_exceeds_the_charge(
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
        let s = sample_attitude_terms(&g, &d, 6).expect("tilt priority");
        prop_assert!(
            s.sampled_n <= s.charged_n * (1.0 + 1e-12) + 1e-12,
            "sampled {} > charged {}", s.sampled_n, s.charged_n
        );
    }
}
