//! The authority search's closed forms against bisections of the set fit.

use super::*;
use controller_core::{ReferenceTrajectory, Trajectory};
use firmware::config::FlightConfig;

/// `iota_max` agrees with a bisection on the firmware's own `Mixer::set_margin` over a
/// rotor set shrunk by the margin; at `ι_max` the set's headroom is the margin exactly; and
/// it is at least the largest `ι` of the per-axis box (the box contains the set).
#[test]
fn closed_form_iota_matches_set_fit_bisection() {
    let cfg = FlightConfig::paper();
    let mut rotors = cfg.rotors;
    rotors.thrust_max = 6.0;
    rotors.drag_coefficient = 0.03 * rotors.thrust_coefficient;
    let set = RotorSet::new(&rotors).unwrap();
    let vehicle = Vehicle::<f64>::paper();
    let k = ReferenceTrajectory::<f64>::paper_helix().constants();
    let margin = 0.05;
    let (lo, hi) = set.shrunk(margin);
    let mut shrunk = rotors;
    shrunk.thrust_min = lo as f32;
    shrunk.thrust_max = hi as f32;
    let mixer = Mixer::new(&shrunk).unwrap();
    for (mp, kf, ks) in [(0.3, 0.3, 0.6), (0.5, 0.5, 1.5), (1.5, 0.3, 1.0)] {
        let env = envelope(&vehicle, &k, (mp, kf, ks), PositionLaw::paper()).unwrap();
        let b = &env.bounds;
        // The certified set's norms (the desired-frame components' where tighter).
        let (rate, acceleration) = b
            .desired_frame
            .norm_bounds((b.angular_velocity, b.angular_acceleration));
        let torque_set = |iota: f64, levels: Vector3<f64>| {
            TorqueSet::new(vehicle.inertia, rate, acceleration, iota, levels)
        };
        let closed = iota_max(&set, &env, margin);
        let fits = |iota: f64| {
            let t = torque_set(iota, Vector3::repeat(iota));
            let t32 = TorqueSet::new(
                t.inertia.map(|x| x as f32),
                rate as f32,
                acceleration as f32,
                iota as f32,
                Vector3::repeat(iota as f32),
            );
            mixer.set_margin(env.thrust.0 as f32, env.thrust.1 as f32, &t32) >= 0.0
        };
        let (mut a, mut c) = (0.0, 10.0);
        assert!(
            closed > 0.0 && fits(a) && !fits(c),
            "bracket at {mp} {kf} {ks}: {closed}"
        );
        for _ in 0..50 {
            let m = 0.5 * (a + c);
            if fits(m) {
                a = m;
            } else {
                c = m;
            }
        }
        assert!(
            (a - closed).abs() <= 1e-5 * closed.abs().max(1e-3),
            "closed form {closed} vs bisection {a} at ({mp}, {kf}, {ks})"
        );
        // At ι_max the set's worst rotor sits exactly at the margin.
        let m = set_margin(
            &set,
            env.thrust,
            &torque_set(closed, Vector3::repeat(closed)),
        );
        assert!((m - margin).abs() < 1e-9, "set margin {m}");
        // The per-axis box of the same bounds fits at its own, smaller, ι_max, whose worst
        // corner sits at the margin.
        let boxed = Envelope {
            feedforward_set: None,
            ..env
        };
        let box_iota = iota_max(&set, &boxed, margin);
        let corner = box_margin(&set, env.thrust, &env.feedforward.add_scalar(box_iota));
        assert!((corner - margin).abs() < 1e-9, "corner margin {corner}");
        assert!(closed > box_iota, "set {closed} vs box {box_iota}");
        // Per-axis levels ι d (tilt priority's direction (1, 1, ρ)), proposed as a box.
        for rho in [0.05, 0.3, 1.0] {
            let d = Vector3::new(1.0, 1.0, rho);
            let along = iota_max_along(&set, &env, margin, &d);
            let m = set_margin(&set, env.thrust, &torque_set(0.0, d * along));
            assert!((m - margin).abs() < 1e-9, "rho {rho}: set margin {m}");
            assert!(
                along >= iota_max_along(&set, &boxed, margin, &d) - 1e-12,
                "the ellipsoid frees room: {along}"
            );
        }
    }
}

/// `iota_max_by` with tilt priority's shapes (a ball, a disk orthogonal to yaw, a box): the
/// set at its result leaves exactly the margin, and it is at least the box's level along
/// the same per-axis levels (the box contains the set).
#[test]
fn bisected_iota_of_a_shaped_feedback_sits_on_the_margin() {
    let mut rotors = FlightConfig::paper().rotors;
    rotors.thrust_max = 6.0;
    rotors.drag_coefficient = 0.03 * rotors.thrust_coefficient;
    let set = RotorSet::new(&rotors).unwrap();
    let vehicle = Vehicle::<f64>::paper();
    let k = ReferenceTrajectory::<f64>::paper_helix().constants();
    let env = envelope(&vehicle, &k, (0.5, 0.5, 1.5), PositionLaw::paper()).unwrap();
    // Per-axis levels (ι, ι, 0.2 ι): a radial 0.1 ι on every axis, trace weights
    // g = (0.05, 0.05, 1.05) ι (roll, pitch 0.55 ι; yaw 0.05 ι), damping the rest.
    let feedback = |iota: f64| {
        let g = Vector3::new(0.05, 0.05, 1.05) * iota;
        let omega = Vector3::new(0.35, 0.35, 0.05) * iota;
        TorqueSet::tilt_priority(Vector3::zeros(), 0.0, 0.0, 0.1 * iota, g, omega)
    };
    let d = Vector3::new(1.0, 1.0, 0.2);
    let boxed = iota_max_along(&set, &env, 0.05, &d);
    // The levels above are the box's direction: extents (ι, ι, 0.2 ι).
    let extents = feedback(1.0).axis_extents();
    assert!((extents - d).norm() < 1e-12, "{extents:?}");
    let shaped = iota_max_by(&set, &env, (0.05, RotorFit::Set), boxed, feedback);
    assert!(shaped > boxed, "{shaped} vs {boxed}");
    let fb = feedback(shaped);
    let whole = TorqueSet {
        feedback_radius: fb.feedback_radius,
        feedback_box: fb.feedback_box,
        feedback_disks: fb.feedback_disks,
        ..env.feedforward_set.unwrap()
    };
    let m = set_margin(&set, env.thrust, &whole);
    assert!((m - 0.05).abs() < 1e-9, "set margin {m}");
}

/// `M_p` at `saturation_max` leaves `ι_max` at zero (from above).
#[test]
fn saturation_max_is_where_iota_vanishes() {
    let mut rotors = FlightConfig::paper().rotors;
    rotors.thrust_max = 4.0;
    let set = RotorSet::new(&rotors).unwrap();
    let vehicle = Vehicle::<f64>::paper();
    let k = ReferenceTrajectory::<f64>::paper_helix().constants();
    let mp = saturation_max(&vehicle, &k, &set, 0.05, 1.0, 4.0).unwrap();
    let at = iota_max_at(&vehicle, &k, &set, 0.05, (mp, 1.0, 4.0));
    let above = iota_max_at(&vehicle, &k, &set, 0.05, (mp * 1.001, 1.0, 4.0));
    assert!((0.0..1e-6).contains(&at) && above < 0.0, "{at} {above}");
}
