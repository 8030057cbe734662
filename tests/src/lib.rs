//! Shared helpers for the cross-crate checks in `tests/tests/*.rs`: scenario builders and
//! conversions. The SO(3) helpers, the Haar sampler and the closed loop are host-sim's
//! (`host_sim::so3`, `host_sim::campaign::sampler`, `host_sim::sim::fly`).

use controller_core::scalar::{to_f64, Scalar};
use host_sim::scenario::{HeadingConfig, Scenario, TrajectoryConfig};
use host_sim::so3::rotation_angle;
use nalgebra::{UnitQuaternion, Vector3};

/// Writes `q` into `scenario.initial.euler_deg` (roll, pitch, yaw with
/// `R = Rz(yaw) Ry(pitch) Rx(roll)`) and checks the round trip through the scenario's own
/// conversion: the attitude the simulation starts from must be `q` to rounding.
pub fn set_initial_attitude(scenario: &mut Scenario, q: &UnitQuaternion<f64>) {
    let (roll, pitch, yaw) = q.euler_angles();
    scenario.initial.euler_deg = [roll.to_degrees(), pitch.to_degrees(), yaw.to_degrees()];
    let back = scenario.initial_attitude();
    // Euler angles → degrees → radians → quaternion: a few ulp per operation, ~1e-15 rad.
    let err = rotation_angle((back.inverse() * q).to_rotation_matrix().matrix());
    assert!(
        err < 1e-12,
        "initial attitude round trip off by {err} rad for {q:?}"
    );
}

/// The paper scenario with the reference replaced by hovering at `point` \[m\] with constant
/// yaw `yaw` \[rad\].
pub fn hover_scenario(point: [f64; 3], yaw: f64) -> Scenario {
    let mut s = Scenario::paper();
    s.trajectory = TrajectoryConfig::Hover {
        point_m: point,
        heading: HeadingConfig::Constant { yaw_rad: yaw },
    };
    s
}

/// A vector of the controller's scalar as f64.
pub fn to_f64_3<T: Scalar>(v: &Vector3<T>) -> Vector3<f64> {
    Vector3::new(to_f64(v.x), to_f64(v.y), to_f64(v.z))
}
