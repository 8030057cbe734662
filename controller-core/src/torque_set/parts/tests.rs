//! The support function's parts against the support function: they add up to it, each is
//! non-negative, and a set with one summand puts all of it in that part.

use approx::assert_relative_eq;
use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;

use crate::torque_set::TorqueSet;

/// A set with every summand drawn from the strategy's values (the cylinder turned by `turn`).
fn any_set() -> impl Strategy<Value = TorqueSet<f64>> {
    (
        prop::array::uniform3(0.001..0.05f64),
        0.0..40.0f64,
        prop::array::uniform3(0.0..0.05f64),
        0.0..0.3f64,
        prop::array::uniform3(0.0..0.4f64),
        prop::array::uniform3(0.0..0.4f64),
        (0.0..80.0f64, 0.0..5.0f64, 0.0..std::f64::consts::PI),
    )
        .prop_map(|(j, u, gyro, r, bx, disks, (a, b, turn))| TorqueSet {
            inertia: Vector3::from(j),
            angular_acceleration: u,
            gyroscopic: Vector3::from(gyro),
            feedback_radius: r,
            feedback_box: Vector3::from(bx),
            feedback_disks: Vector3::from(disks),
            aligned_acceleration: Vector2::new(a, b),
            aligned_turn: turn,
            attitude_joint: None,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Given any set and any direction (a rotor pair's row is any vector), when the support is
    /// split, then the parts are non-negative, the feedforward without its yaw leg is at most the
    /// feedforward, and the parts add up to `support(c)`.
    #[test]
    fn the_parts_add_up_to_the_support(
        s in any_set(),
        c in prop::array::uniform3(-40.0..40.0f64),
        turned in any::<bool>(),
    ) {
        let mut s = s;
        if !turned {
            s.aligned_turn = 0.0;
        }
        let c = Vector3::from(c);
        let p = s.support_parts(&c);
        for part in [p.feedforward, p.feedforward_without_yaw, p.gyroscopic, p.feedback_ball,
                     p.feedback_box, p.feedback_disks, p.aligned] {
            prop_assert!(part >= 0.0);
        }
        prop_assert!(p.feedforward_without_yaw <= p.feedforward);
        let h = s.support(&c);
        prop_assert!((p.total() - h).abs() <= 1e-12 * h.max(1.0), "{} vs {h}", p.total());
    }
}

/// Given sets with a single summand, when the support along a rotor-pair-like direction is
/// split, then that summand's part is the whole support, computed here from its own formula,
/// and every other part is zero.
#[test]
fn a_single_summand_takes_the_whole_support() {
    let j = Vector3::<f64>::new(0.0239, 0.0239, 0.044);
    let c = Vector3::<f64>::new(2.87, -0.4, 31.25);
    let zero = TorqueSet::boxed(Vector3::zeros());
    let ellipsoid = TorqueSet {
        inertia: j,
        angular_acceleration: 2.2,
        ..zero
    };
    let p = ellipsoid.support_parts(&c);
    let by_hand = 2.2 * ((j.x * c.x).powi(2) + (j.y * c.y).powi(2) + (j.z * c.z).powi(2)).sqrt();
    assert_relative_eq!(p.feedforward, by_hand, max_relative = 1e-14);
    assert_relative_eq!(p.total(), by_hand, max_relative = 1e-14);
    let no_yaw = 2.2 * ((j.x * c.x).powi(2) + (j.y * c.y).powi(2)).sqrt();
    assert_relative_eq!(p.feedforward_without_yaw, no_yaw, max_relative = 1e-14);
    // Along this direction the yaw leg is most of the ellipsoid: J₃₃ c₃ dwarfs J₁₁ c₁.
    assert!(p.feedforward - p.feedforward_without_yaw > 0.9 * p.feedforward);

    let ball = TorqueSet {
        feedback_radius: 0.032,
        ..zero
    };
    let p = ball.support_parts(&c);
    assert_relative_eq!(p.feedback_ball, 0.032 * c.norm(), max_relative = 1e-14);
    assert_eq!(p.total(), p.feedback_ball);

    let disks = TorqueSet {
        feedback_disks: Vector3::new(0.0, 0.0, 0.39),
        ..zero
    };
    let p = disks.support_parts(&c);
    // The disk orthogonal to body z: its radius times the length of c's roll-pitch part.
    assert_relative_eq!(p.feedback_disks, 0.39 * c.xy().norm(), max_relative = 1e-14);
    assert_eq!(p.total(), p.feedback_disks);

    let boxed = TorqueSet::boxed(Vector3::new(0.44, 0.44, 0.027));
    let p = boxed.support_parts(&c);
    assert_relative_eq!(
        p.feedback_box,
        0.44 * 2.87 + 0.44 * 0.4 + 0.027 * 31.25,
        max_relative = 1e-14
    );
    assert_eq!(p.total(), p.feedback_box);
}
