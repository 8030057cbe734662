//! The binding pair against a search of its own: no pair has less slack, and at its support point the rotors' thrust interval is exactly as wide as its
//! slack says; on a yaw-only or roll-only set the pair is the one that axis splits.

use nalgebra::Vector3;
use proptest::prelude::*;

use crate::rotor_envelope::tests::{quad, set, support_point};
use crate::torque_set::TorqueSet;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2_000))]

    /// Given an X quad of any arm and yaw coefficient and a law-like set of any scale, when the
    /// binding pair is found, then its margin (the shadow margin) is the least slack of every
    /// ordered pair (searched here), its capacity and direction are the pair's, and at
    /// the support point of its direction the thrust interval's width is its slack divided by
    /// `w_k w_l` (the pair's two rotors set the interval's two ends there).
    #[test]
    fn the_binding_pair_sets_the_margin(
        arm in 0.03..0.3f64,
        yaw in 0.005..0.05f64,
        hi in 0.5..15.0f64,
        scale in 0.01..3.0f64,
    ) {
        let (_, e) = quad(arm, yaw, 0.0, hi);
        let s = set(scale);
        let b = e.shadow_binding(&s);
        let (k, l) = b.rotors;
        prop_assert!(k != l && k < 4 && l < 4);
        let (wk, wl) = (e.collective[k], e.collective[l]);
        prop_assert_eq!(b.direction, e.torque[l] * wk - e.torque[k] * wl);
        prop_assert_eq!(b.capacity, wk * hi);
        let span = (wk + wl) * hi;
        let least = (0..4)
            .flat_map(|k| (0..4).map(move |l| (k, l)))
            .filter(|(k, l)| k != l)
            .map(|(k, l)| {
                let d = e.torque[l] * e.collective[k] - e.torque[k] * e.collective[l];
                (e.collective[k] * hi - s.support(&d)) / ((e.collective[k] + e.collective[l]) * hi)
            })
            .fold(f64::INFINITY, f64::min);
        prop_assert_eq!(b.margin, least);
        let tau = support_point(&s, &b.direction);
        let (t_lo, t_hi) = e.thrust_interval(&tau);
        let width = b.margin * span / (wk * wl);
        prop_assert!(((t_hi - t_lo) - width).abs() <= 1e-9 * width.abs().max(1.0),
            "interval width {} vs the pair's slack {}", t_hi - t_lo, width);
    }
}

/// Given the x500's rotors (arm 0.174 m, yaw 0.016 m per newton, 0 to 8.55 N), when the set is
/// a yaw-only box, then the binding pair spins in opposite senses and its direction is almost
/// all yaw; when it is a roll-only box, the pair sits on opposite sides of the roll axis.
#[test]
fn the_binding_pair_is_the_one_the_axis_splits() {
    let (_, e) = quad(0.174, 0.016, 0.0, 8.55);
    let yaw = e.shadow_binding(&TorqueSet::boxed(Vector3::new(0.0, 0.0, 0.1)));
    let (k, l) = yaw.rotors;
    assert!(e.torque[k].z * e.torque[l].z < 0.0, "{:?}", yaw);
    assert!(
        yaw.direction.z.abs() > 10.0 * yaw.direction.xy().norm(),
        "{:?}",
        yaw
    );
    let roll = e.shadow_binding(&TorqueSet::boxed(Vector3::new(1.0, 0.0, 0.0)));
    let (k, l) = roll.rotors;
    assert!(e.torque[k].x * e.torque[l].x < 0.0, "{:?}", roll);
    // The yaw box is a tenth of the roll box in newton-metres, and still binds harder: a yaw
    // newton-metre costs the rotors `arm / yaw` = 10.9 times a roll one.
    assert!(
        yaw.margin < roll.margin,
        "{} vs {}",
        yaw.margin,
        roll.margin
    );
}
