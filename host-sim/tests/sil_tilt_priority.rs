//! SIL with the tilt-priority attitude feedback (controller-core `tilt_priority`,
//! docs/tilt-priority.md) in the firmware's pipeline: the default build's x500 flight with
//! `[gains.tilt_priority]` levels no larger than its radial `ι` on any axis, so its certificate
//! and box still hold, flown on the rotor plant with realistic sensors.

use controller_core::TiltPriorityGains;
use host_sim::harness::sil::{run, scenarios, FlightExtremes};
use nalgebra::Vector3;

/// Given the demo-helix SIL scenario with tilt priority added (trace weights small, per-axis
/// damping levels chosen so that every `ι_i` stays at most the file's `ι`), when the pipeline
/// flies it, then it boots certified with the box fitting, arms, converges to the helix inside
/// the certified bounds with nothing given up by the mixer, and flies a different law from the
/// radial one (its settling time differs).
#[test]
fn the_pipeline_flies_tilt_priority_inside_its_certificate() {
    let radial = scenarios::helix(1);
    let mut setup = scenarios::helix(1);
    let a = setup.flight.gains.attitude;
    let iota = (1.0 + 1.02f32 * 1.02) * a.mrp_saturation / 4.0 + a.omega_saturation;
    let tilt = TiltPriorityGains {
        trace_weights: Vector3::new(0.002, 0.002, 0.01),
        omega_gains: Vector3::repeat(a.k_omega),
        omega_levels: Vector3::new(0.005, 0.005, 0.008),
        turn_over: None,
    };
    let levels = tilt.feedback_levels(a.mrp_saturation, setup.flight.gains.hysteresis);
    assert!(levels.max() <= iota, "{levels} vs {iota}");
    setup.flight.gains.tilt_priority = Some(tilt);

    let bounds = setup.a_priori_bounds().expect("boots");
    let mut seen = FlightExtremes::new(40.0);
    let s = run(&setup, |r| seen.observe(r)).unwrap();
    assert!(s.certificate_holds, "{:?}", s.violated_conditions);
    assert!(s.fit_margin >= s.required_fit_margin);
    assert_eq!(s.final_state, "armed", "{:#?}", s.events);
    assert_eq!(s.refused_commands, 0, "{:#?}", s.events);
    assert!(s.below_5cm_from_s.is_some(), "never below 5 cm");
    assert!(seen.max_error_late_m < 0.05, "{seen:?}");
    assert!(seen.inside(&bounds), "{seen:?} vs {bounds:?}");
    assert_eq!(s.mixer_saturated_ticks, 0);
    assert_eq!(s.non_finite, 0);

    let r = run(&radial, |_| {}).unwrap();
    println!(
        "settled below 5 cm: radial {:?} s, tilt priority {:?} s; late max error {:.4} m",
        r.below_5cm_from_s, s.below_5cm_from_s, seen.max_error_late_m
    );
    assert_ne!(r.below_5cm_from_s, s.below_5cm_from_s);
}
