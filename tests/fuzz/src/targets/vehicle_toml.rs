//! The vehicle-file parser ([`firmware::vehicle_file::VehicleFile::parse`], which host-sim's
//! `--vehicle` files and the firmware build's flight files go through) on arbitrary text.
//!
//! Invariants: no panic (a bad file is an error naming the key); a file it accepts validates
//! again, and its flight values (the `f32` set the firmware is built with) are finite.

use firmware::vehicle_file::VehicleFile;

/// Runs the target on one input; panics on a broken invariant.
pub fn run(data: &[u8]) {
    let Some(text) = super::text(data) else {
        return;
    };
    // As a vehicle file, and as one embedded in a flight file (with its other tables).
    let as_flight_file = ["limits", "gains", "trajectory", "design"];
    for other in [&[][..], &as_flight_file[..]] {
        if let Ok(file) = VehicleFile::parse_embedded(text, "fuzz", other) {
            check(&file);
        }
    }
}

fn check(file: &VehicleFile) {
    if let Err(e) = file.validate("fuzz") {
        panic!("an accepted vehicle file fails validation: {e}");
    }
    let v = file.flight_values();
    let numbers = [
        v.mass,
        v.gravity,
        v.arm_length,
        v.thrust_min,
        v.thrust_max,
        v.yaw_torque_per_thrust,
        v.curve_factor,
        v.throttle_idle,
        v.motor_time_constant,
    ]
    .into_iter()
    .chain(v.inertia)
    .chain(v.positions.into_iter().flatten())
    .chain(v.spins)
    .chain(v.body_drag);
    for x in numbers {
        assert!(
            x.is_finite(),
            "an accepted vehicle file has a non-finite flight value: {v:?}"
        );
    }
}
