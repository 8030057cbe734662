use super::*;
use crate::config::FlightConfig;
use controller_core::TorqueSet;

fn mixer() -> Mixer {
    Mixer::new(&FlightConfig::paper().rotors).unwrap()
}

/// Unsaturated: the rotor thrusts reproduce (T, τ), checked against a hand allocation for
/// the symmetric X: f_k = T/4 + y_k τx/(4d²) − x_k τy/(4d²) − s_k τz/(4c).
#[test]
fn unsaturated_allocation_matches_hand_formula() {
    let cfg = FlightConfig::paper();
    let m = mixer();
    let (t, tau) = (4.5f32, Vector3::new(0.05f32, -0.03, 0.02));
    let out = m.mix(t, &tau);
    assert!(!out.saturated());
    let d = 0.25f32 * core::f32::consts::FRAC_1_SQRT_2;
    let c = cfg.rotors.torque_per_thrust();
    for (k, r) in cfg.rotors.rotors.iter().enumerate() {
        let f = t / 4.0 + r.position[1] * tau.x / (4.0 * d * d)
            - r.position[0] * tau.y / (4.0 * d * d)
            - r.spin * tau.z / (4.0 * c);
        assert!((out.thrust[k] - f).abs() < 1e-5, "motor {k}");
    }
    assert!((out.achieved_thrust - t).abs() < 1e-5);
    assert!((out.achieved_torque - tau).norm() < 1e-6);
}

/// Positive roll (τx > 0, right side down in FLU? no: +x torque lifts the left side... )
/// is made by the left rotors (y > 0) pushing harder; positive yaw by the CW rotors.
#[test]
fn signs_of_the_geometry() {
    let out = mixer().mix(4.0, &Vector3::new(0.1, 0.0, 0.0));
    // Motors 3 and 4 are on the left (y > 0).
    assert!(out.thrust[2] > out.thrust[0] && out.thrust[3] > out.thrust[1]);
    let out = mixer().mix(4.0, &Vector3::new(0.0, 0.1, 0.0));
    // +τy (nose down in FLU) comes from the rear rotors (1 and 3, x < 0).
    assert!(out.thrust[0] > out.thrust[1] && out.thrust[2] > out.thrust[3]);
    let out = mixer().mix(4.0, &Vector3::new(0.0, 0.0, 0.1));
    // +τz (counter-clockwise) from the CW rotors 1 and 4 (reaction of CW is CCW).
    assert!(out.thrust[0] > out.thrust[1] && out.thrust[3] > out.thrust[2]);
}

/// Yaw is given up first: full yaw demand with roll/pitch intact.
#[test]
fn yaw_is_given_up_before_roll_pitch() {
    let m = mixer();
    let tau = Vector3::new(0.6, 0.0, 0.6);
    let out = m.mix(6.0, &tau);
    assert!(out.yaw_scale < 1.0);
    assert_eq!(out.roll_pitch_scale, 1.0);
    assert!((out.achieved_torque.x - 0.6).abs() < 1e-5);
    assert!(out.thrust.iter().all(|&f| (0.0..=3.0).contains(&f)));
}

/// Collective is shifted before roll/pitch is reduced; roll/pitch are scaled together
/// (direction kept) only when their spread alone exceeds the range.
#[test]
fn collective_then_roll_pitch() {
    let m = mixer();
    // High thrust + roll: collective drops, roll intact.
    let out = m.mix(11.5, &Vector3::new(0.5, 0.0, 0.0));
    assert_eq!(out.roll_pitch_scale, 1.0);
    assert!(out.thrust_shift < 0.0);
    assert!((out.achieved_torque.x - 0.5).abs() < 1e-5);
    // Roll/pitch beyond what the rotors can do at all: scaled with direction kept.
    let tau = Vector3::new(1.5, 1.0, 0.0);
    let out = m.mix(6.0, &tau);
    assert!(out.roll_pitch_scale < 1.0);
    let a = out.achieved_torque;
    assert!((a.x / a.y - 1.5).abs() < 1e-4, "{a}");
    assert!(out.thrust.iter().all(|&f| (0.0..=3.0 + 1e-6).contains(&f)));
}

proptest::proptest! {
    /// Any request: rotor thrusts in range; a realisable request is met exactly; roll and
    /// pitch keep their direction (and are met whenever they were not scaled); yaw never
    /// exceeds what was asked nor changes sign.
    #[test]
    fn priorities_hold(t in -5.0f32..20.0, x in -2.0f32..2.0, y in -2.0f32..2.0, z in -1.0f32..1.0) {
        let m = mixer();
        let tau = Vector3::new(x, y, z);
        let out = m.mix(t, &tau);
        for f in out.thrust {
            proptest::prop_assert!((0.0..=3.0).contains(&f));
        }
        let ideal = m.mixing() * nalgebra::Vector4::new(t, x, y, z);
        let a = out.achieved_torque;
        if ideal.iter().all(|f| (0.0..=3.0).contains(f)) {
            proptest::prop_assert!(!out.saturated());
            proptest::prop_assert!((out.achieved_thrust - t).abs() < 1e-4);
            proptest::prop_assert!((a - tau).norm() < 1e-4);
        }
        if out.roll_pitch_scale == 1.0 {
            proptest::prop_assert!((a.x - x).abs() < 1e-4 && (a.y - y).abs() < 1e-4);
        } else {
            // Parallel and shorter: cross product ~ 0, dot ≥ 0.
            proptest::prop_assert!((a.x * y - a.y * x).abs() < 1e-4);
            proptest::prop_assert!(a.x * x + a.y * y >= 0.0);
        }
        proptest::prop_assert!(a.z.abs() <= z.abs() + 1e-4 && a.z * z >= -1e-6);
    }
}

proptest::proptest! {
    /// `clamp_rotor` is `fmin(fmax(f, lo), hi)` bit for bit, for any `f` (NaN, ±0, ±∞ and
    /// every bit pattern) and any range `lo ≤ hi` the mixer accepts (`0 ≤ lo < hi`, finite).
    #[test]
    fn clamp_rotor_is_fmin_of_fmax(bits in proptest::num::u32::ANY, lo in 0.0f32..10.0, width in 1e-6f32..10.0, pick in 0usize..8) {
        let hi = lo + width;
        let special = [f32::NAN, -0.0, 0.0, f32::INFINITY, f32::NEG_INFINITY, lo, hi];
        let f = special.get(pick).copied().unwrap_or(f32::from_bits(bits));
        proptest::prop_assert_eq!(clamp_rotor(f, lo, hi).to_bits(), fmin(fmax(f, lo), hi).to_bits());
    }
}

proptest::proptest! {
    /// `shift_bounds` gives the bits of the `fmax`/`fmin` folds it stands for, NaN
    /// quotients (from a NaN base) and rotors without collective included.
    #[test]
    fn shift_bounds_are_the_fmax_fmin_folds(
        base in proptest::array::uniform4(-10.0f32..10.0),
        u_t in proptest::array::uniform4(-1.0f32..1.0),
        nan_at in 0usize..6,
        lo in 0.0f32..3.0,
        width in 1e-3f32..10.0,
    ) {
        let mut base = Vector4::from(base);
        if let Some(b) = base.get_mut(nan_at) {
            *b = f32::NAN;
        }
        let u_t = Vector4::from(u_t);
        let hi = lo + width;
        let (mut s_lo, mut s_hi) = (f32::NEG_INFINITY, f32::INFINITY);
        for k in 0..4 {
            if u_t[k] > 0.0 {
                s_lo = fmax(s_lo, (lo - base[k]) / u_t[k]);
                s_hi = fmin(s_hi, (hi - base[k]) / u_t[k]);
            }
        }
        let (a, b) = shift_bounds(&base, &u_t, lo, hi);
        proptest::prop_assert_eq!((a.to_bits(), b.to_bits()), (s_lo.to_bits(), s_hi.to_bits()));
    }
}

/// NaN in → finite rotor thrusts out.
#[test]
fn nan_never_reaches_rotors() {
    let out = mixer().mix(f32::NAN, &Vector3::new(f32::INFINITY, 0.0, f32::NAN));
    assert!(out.thrust.iter().all(|f| f.is_finite()));
}

/// Box fit: a small box fits; the paper's a-priori box does not, with the shortfall
/// recomputed by hand for rotor 1 (rear-right): max f = T_hi/4 + τx/(4d) + τy/(4d) + τz/(4c).
#[test]
fn box_fit_by_hand() {
    let m = mixer();
    let small = m.box_fit(3.0, 6.0, &Vector3::new(0.05, 0.05, 0.05));
    assert!(small.fits);
    assert_eq!(small.torque_shortfall, [0.0; 3]);
    let tau = Vector3::new(0.379f32, 0.446, 0.664);
    let fit = m.box_fit(3.512, 6.188, &tau);
    assert!(!fit.fits);
    let d = 0.25f32 * core::f32::consts::FRAC_1_SQRT_2;
    let c = 0.1f32;
    let demand = tau.x / (4.0 * d) + tau.y / (4.0 * d) + tau.z / (4.0 * c);
    assert!((fit.thrust_capacity[1] - 4.0 * (3.0 - demand)).abs() < 1e-4);
    assert!((fit.thrust_capacity[0] - 4.0 * demand).abs() < 1e-4);
    // Roll capacity at T_lo with pitch and yaw at their bounds: (T_lo/4 − others)·4d.
    let roll_cap = ((3.512 / 4.0 - tau.y / (4.0 * d) - tau.z / (4.0 * c)) * 4.0 * d).max(0.0);
    assert!((fit.torque_capacity[0] - roll_cap).abs() < 1e-4);
    assert!(fit.torque_shortfall[2] > 0.0);
    // Single axis: roll alone up to 2 d (f_max − f_min), yaw alone 2 c (f_max − f_min).
    assert!((fit.torque_single_axis[0] - 2.0 * d * 3.0).abs() < 1e-4);
    assert!((fit.torque_single_axis[2] - 2.0 * c * 3.0).abs() < 1e-4);
}

/// Box margin: by hand for the symmetric X (every rotor's extremes are
/// `T/4 ± (τx/(4d) + τy/(4d) + τz/(4c))`), zero exactly when a corner touches a rotor limit,
/// and negative (consistently with `box_fit`) when the box does not fit.
#[test]
fn box_margin_by_hand() {
    let m = mixer();
    let d = 0.25f32 * core::f32::consts::FRAC_1_SQRT_2;
    let c = 0.1f32;
    let tau = Vector3::new(0.05f32, 0.04, 0.03);
    let a = tau.x / (4.0 * d) + tau.y / (4.0 * d) + tau.z / (4.0 * c);
    let (t_lo, t_hi) = (3.0f32, 6.0);
    let hand = (3.0 - (t_hi / 4.0 + a)).min(t_lo / 4.0 - a) / 3.0;
    let margin = m.box_margin(t_lo, t_hi, &tau);
    assert!((margin - hand).abs() < 1e-5, "{margin} vs {hand}");
    assert!(m.box_fit(t_lo, t_hi, &tau).fits && margin > 0.0);
    // Raise T_hi until the top corner touches f_max: margin 0.
    let t_touch = 4.0 * (3.0 - a);
    assert!(m.box_margin(t_lo, t_touch, &tau).abs() < 1e-5);
    // The paper's a-priori box does not fit: negative margin.
    let paper = m.box_margin(3.512, 6.188, &Vector3::new(0.379, 0.446, 0.664));
    assert!(paper < 0.0);
    assert!(
        !m.box_fit(3.512, 6.188, &Vector3::new(0.379, 0.446, 0.664))
            .fits
    );
}

mod set_margin_properties {
    use super::*;
    use proptest::prelude::*;

    fn unit(theta: f32, phi: f32) -> Vector3<f32> {
        Vector3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// Given a torque set (ellipsoid, boxes, ball) and a thrust interval, when points of the
        /// set at either thrust end are allocated through `M` (no desaturation), then every
        /// rotor's headroom is at least the set margin; and the set margin is at least the
        /// box margin of the set's per-axis extents.
        #[test]
        fn points_of_the_set_keep_the_margin(
            inertia in (0.01..0.1f32, 0.01..0.1f32, 0.01..0.2f32),
            rates in (0.0..3.0f32, 0.0..1.0f32),
            radius in 0.0..0.1f32,
            levels in (0.0..0.05f32, 0.0..0.05f32, 0.0..0.05f32),
            thrust in (2.0..5.0f32, 0.0..3.0f32, any::<bool>()),
            v in (0.0..std::f32::consts::PI, 0.0..std::f32::consts::TAU, 0.0..=1.0f32),
            w in (0.0..std::f32::consts::PI, 0.0..std::f32::consts::TAU, 0.0..=1.0f32),
            ball in (0.0..std::f32::consts::PI, 0.0..std::f32::consts::TAU, 0.0..=1.0f32),
            signs in any::<[bool; 3]>(),
        ) {
            let m = mixer();
            let j = Vector3::new(inertia.0, inertia.1, inertia.2);
            let (speed, accel) = (rates.0, rates.1 * 10.0);
            let axes = Vector3::new(levels.0, levels.1, levels.2).add_scalar(radius);
            let set = TorqueSet::new(j, speed, accel, radius, axes);
            let (t_lo, t_hi) = (thrust.0, thrust.0 + thrust.1);
            // A point of each summand, on the boundary for the radii drawn as 1.
            let ellipsoid = j.component_mul(&(unit(v.0, v.1) * (v.2 * accel)));
            let wv = unit(w.0, w.1) * (w.2 * speed);
            let gyro = j.component_mul(&wv).cross(&wv);
            let pick = |s: [bool; 3], h: Vector3<f32>| Vector3::from_fn(|i, _| if s[i] { h[i] } else { -h[i] });
            let tau = -ellipsoid + gyro + unit(ball.0, ball.1) * (ball.2 * radius)
                + pick(signs, set.feedback_box);
            let margin = m.set_margin(t_lo, t_hi, &set);
            let (lo, hi) = m.thrust_range();
            let t = if thrust.2 { t_hi } else { t_lo };
            let f = m.mixing() * nalgebra::Vector4::new(t, tau.x, tau.y, tau.z);
            let worst = (0..4).map(|k| (f[k] - lo).min(hi - f[k])).fold(f32::INFINITY, f32::min) / (hi - lo);
            prop_assert!(worst >= margin - 1e-5, "{worst} < {margin}");
            prop_assert!(margin >= m.box_margin(t_lo, t_hi, &set.axis_extents()) - 1e-6);
        }
    }
}
