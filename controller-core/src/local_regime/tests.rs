//! The envelope design's switch: the re-timed filter keeps `u̇`; the switch has its hysteresis.

use nalgebra::Vector3;
use proptest::prelude::*;

use super::{retime, LocalAttitude, LocalGains, Regime};
use crate::parameter_error::ParameterError;
use crate::position::{FilterState, PositionGains};
use crate::position_saturation::PositionSaturation;
use crate::vertical_channel::VerticalChannel;

fn vec3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Re-timing the inner filter to a faster `k_f` keeps `u̇ = −k_f(u_f − u_s)` and puts `u_s`
    /// between `u_f` and its old value (inside the saturation set); re-timed back to the slower
    /// `k_f` it is scaled into the set when it would leave it.
    #[test]
    fn retiming_keeps_the_filter_rate(uf in vec3(2.0), us in vec3(2.0), slow in 0.2..3.0f64, ratio in 1.0..10.0f64) {
        let set = PositionGains {
            kp: 1.0,
            kv: 1.0,
            kf: slow,
            ks: 2.0 * slow,
            saturation: 2.0,
            saturation_shape: PositionSaturation::Norm,
            vertical: None,
        };
        prop_assume!(uf.norm() <= 2.0 && us.norm() <= 2.0);
        let fast = slow * ratio;
        let f = FilterState { u_f: uf, u_s: us };
        let faster = PositionGains { kf: fast, ..set };
        let up = retime(&f, &set, &faster, &set);
        let before = (uf - us) * slow;
        let after = (up.u_f - up.u_s) * fast;
        prop_assert!((before - after).norm() <= 1e-12 * (1.0 + before.norm()));
        prop_assert!(up.u_s.norm() <= 2.0 + 1e-12 && up.u_f == uf);
        let down = retime(&f, &faster, &set, &set);
        prop_assert!(down.u_s.norm() <= 2.0 + 1e-12);
    }
}

/// The global position gains of the switch's tests (norm shape, `k_f` 0.5 1/s, `M_p` 2.5 m/s²),
/// with the vertical channel `vertical`.
fn global(vertical: Option<VerticalChannel<f64>>) -> PositionGains<f64> {
    PositionGains {
        kp: 1.0,
        kv: 2.0,
        kf: 0.5,
        ks: 1.0,
        saturation: 2.5,
        saturation_shape: PositionSaturation::Norm,
        vertical,
    }
}

/// A local regime eight times faster (`k_f,L` 4 1/s) with a smaller level (1.5 m/s²), `E_in`
/// 0.01 J, `E_out` 0.02 J, and the local vertical filters `vertical`.
fn local(vertical: Option<VerticalChannel<f64>>) -> LocalGains<f64> {
    LocalGains {
        kp: 9.0,
        kv: 6.0,
        kf: 4.0,
        ks: 10.0,
        saturation: 1.5,
        energy_in: 0.01,
        energy_out: 0.02,
        vertical,
        attitude: None,
        braking: None,
    }
}

/// The switch: into the local gains at `E ≤ E_in` once the re-timed filter states lie in the
/// local saturation set, back only above `E_out`; the local gains keep the global shape; a local
/// `M_p` above the global one is accepted, and on the way back both filter states are brought into
/// the global set; a local `k_f` below the global one or `E_out ≤ E_in` is refused by name.
#[test]
fn the_switch_has_its_hysteresis() {
    let (global, l) = (global(None), local(None));
    assert!(l.validate(&global).is_ok());
    let rest = FilterState::zero();
    let regime = |r: Regime, e: f64, f: &FilterState<f64>| l.switch(&global, r, e, f).0;
    assert_eq!(regime(Regime::Global, 0.011, &rest), Regime::Global);
    assert_eq!(regime(Regime::Global, 0.01, &rest), Regime::Local);
    assert_eq!(regime(Regime::Local, 0.019, &rest), Regime::Local);
    assert_eq!(regime(Regime::Local, 0.021, &rest), Regime::Global);
    // Filter states outside the local set (|u_f| = 2 > 1.5) keep the global gains.
    let wide = FilterState {
        u_f: Vector3::new(2.0, 0.0, 0.0),
        u_s: Vector3::new(2.0, 0.0, 0.0),
    };
    assert_eq!(regime(Regime::Global, 0.001, &wide), Regime::Global);
    // Entering, u̇ = −k_f(u_f − u_s) keeps its value.
    let moving = FilterState {
        u_f: Vector3::new(1.0, 0.0, 0.0),
        u_s: Vector3::new(0.2, 0.0, 0.0),
    };
    let (r, f) = l.switch(&global, Regime::Global, 0.001, &moving);
    assert_eq!(r, Regime::Local);
    let (before, after) = ((moving.u_f - moving.u_s) * 0.5, (f.u_f - f.u_s) * 4.0);
    assert!((before - after).norm() < 1e-12);
    let p = l.position(&global);
    assert_eq!(
        (p.kf, p.saturation, p.saturation_shape),
        (4.0, 1.5, PositionSaturation::Norm)
    );
    let wide_local = LocalGains {
        saturation: 3.0,
        ..l
    };
    assert!(wide_local.validate(&global).is_ok());
    // Leaving a wide local regime with |u_f| = 2.9 > M_p = 2.5: both states land in the global set.
    let far = FilterState {
        u_f: Vector3::new(0.0, 2.9, 0.0),
        u_s: Vector3::new(0.0, 2.0, 0.0),
    };
    let (r, back) = wide_local.switch(&global, Regime::Local, 0.03, &far);
    assert_eq!(r, Regime::Global);
    assert!(
        global.contains(&back.u_f) && global.contains(&back.u_s),
        "{back:?}"
    );
    assert!((back.u_f.norm() - 2.5).abs() < 1e-12);
    let slow = LocalGains { kf: 0.4, ..l };
    assert!(format!("{}", slow.validate(&global).unwrap_err()).contains("local k_f"));
    let inverted = LocalGains {
        energy_out: 0.01,
        ..l
    };
    assert!(format!("{}", inverted.validate(&global).unwrap_err()).contains("E_out"));
}

/// The global vertical channel of the tests below: levels 4 up and 1 down [m/s²], filters 1.5
/// and 2.5 1/s.
fn global_vertical() -> VerticalChannel<f64> {
    VerticalChannel {
        up: 4.0,
        down: 1.0,
        kf: 1.5,
        ks: 2.5,
    }
}

/// Given the vertical channel apart and a local regime with its own vertical filters (at the
/// global levels), when the switch enters and leaves the local regime, then each channel's
/// `u̇ = −k_f(u_f − u_s)` keeps its value with its own bandwidth, the local gains fly the local
/// vertical channel, and local vertical filters slower than the global ones, or without a
/// vertical channel, are refused by name.
#[test]
fn local_vertical_filters_are_retimed_by_their_own_bandwidth() {
    let vertical = global_vertical();
    let global = global(Some(vertical));
    let l = local(Some(VerticalChannel {
        kf: 6.0,
        ks: 20.0,
        ..vertical
    }));
    assert!(l.validate(&global).is_ok());
    let local = l.position(&global);
    assert_eq!(
        local.vertical,
        Some(VerticalChannel {
            kf: 6.0,
            ks: 20.0,
            ..vertical
        })
    );
    let moving = FilterState {
        u_f: Vector3::new(1.0, 0.0, 0.5),
        u_s: Vector3::new(0.2, 0.0, -0.5),
    };
    let rate = |f: &FilterState<f64>, kf: f64, kfz: f64| {
        let d = f.u_f - f.u_s;
        Vector3::new(d.x * kf, d.y * kf, d.z * kfz)
    };
    let (r, inside) = l.switch(&global, Regime::Global, 0.001, &moving);
    assert_eq!(r, Regime::Local);
    assert!((rate(&moving, 0.5, 1.5) - rate(&inside, 4.0, 6.0)).norm() < 1e-12);
    // Between the old inner state and u_f, so inside both sets.
    assert!(inside.u_s.z < moving.u_f.z && inside.u_s.z > moving.u_s.z);
    let (r, back) = l.switch(&global, Regime::Local, 0.03, &inside);
    assert_eq!(r, Regime::Global);
    assert!((rate(&back, 0.5, 1.5) - rate(&inside, 4.0, 6.0)).norm() < 1e-12);
    let slow = LocalGains {
        vertical: Some(VerticalChannel {
            kf: 1.0,
            ks: 20.0,
            ..vertical
        }),
        ..l
    };
    assert!(format!("{}", slow.validate(&global).unwrap_err()).contains("local k_f,z"));
    let flat = PositionGains {
        vertical: None,
        ..global
    };
    assert!(format!("{}", l.validate(&flat).unwrap_err()).contains("local k_f,z"));
    assert_eq!(l.position(&flat).vertical, None);
}

/// Given the vertical channel apart (levels 4 up, 1 down) and a local regime with smaller
/// vertical levels (1 up, 0.5 down), when the attitude energy falls below `E_in` with a vertical
/// filter state outside the local levels, then the global gains keep flying; once the states lie
/// inside them, the local gains take over with the local levels (the vertical saturation clips
/// at them); back above `E_out` the states are in the global set as they are (the local set lies
/// inside it); a local level that is not positive is refused by name.
#[test]
fn local_vertical_levels_wait_for_the_filters_and_bound_the_feedback() {
    let vertical = global_vertical();
    let global = global(Some(vertical));
    let own = VerticalChannel {
        up: 1.0,
        down: 0.5,
        kf: 6.0,
        ks: 20.0,
    };
    let l = local(Some(own));
    assert!(l.validate(&global).is_ok());
    let braking = FilterState {
        u_f: Vector3::new(0.1, 0.0, 2.0),
        u_s: Vector3::new(0.1, 0.0, 1.8),
    };
    assert_eq!(
        l.switch(&global, Regime::Global, 0.001, &braking),
        (Regime::Global, braking)
    );
    let near = FilterState {
        u_f: Vector3::new(0.1, 0.0, 0.4),
        u_s: Vector3::new(0.1, 0.0, -0.3),
    };
    let (r, inside) = l.switch(&global, Regime::Global, 0.001, &near);
    assert_eq!(r, Regime::Local);
    let flown = l.position(&global);
    assert_eq!(flown.vertical, Some(own));
    assert!(flown.contains(&inside.u_f) && flown.contains(&inside.u_s));
    let push = flown.feedback_of(&Vector3::new(0.0, 0.0, -50.0));
    let pull = flown.feedback_of(&Vector3::new(0.0, 0.0, 50.0));
    assert!((push.z - own.up).abs() < 1e-9 && (pull.z + own.down).abs() < 1e-9);
    let (r, back) = l.switch(&global, Regime::Local, 0.03, &inside);
    assert_eq!(r, Regime::Global);
    assert_eq!(back.u_f, inside.u_f);
    for (name, bad) in [
        ("local M_up", VerticalChannel { up: 0.0, ..own }),
        ("local M_down", VerticalChannel { down: -1.0, ..own }),
    ] {
        let refused = LocalGains {
            vertical: Some(bad),
            ..l
        };
        assert!(format!("{}", refused.validate(&global).unwrap_err()).contains(name));
    }
}

/// Given the global gains (levels 2.5 horizontally, 4 up and 1 down) and their velocity limit
/// (braking 1.75, 2.8 up, 0.7 down: 0.7 of each level), when the local regime's levels are
/// smaller (1.5; 1 up and 0.5 down), then the local regime flies each braking at the same 0.7
/// of its local level, which validates against the local levels where the global braking would
/// not; when no local level is smaller (a wider horizontal level, the global vertical levels) the
/// velocity limit is the global one bit for bit.
#[test]
fn the_local_regime_brakes_at_its_share_of_smaller_levels() {
    use crate::velocity_limit::{VelocityLimit, VerticalBraking};
    let g = global(Some(global_vertical()));
    let limit = VelocityLimit {
        speed: 5.0,
        braking: 1.75,
        vertical: Some(VerticalBraking { up: 2.8, down: 0.7 }),
    };
    assert!(limit.validate(g.saturation, g.vertical.as_ref()).is_ok());
    let small = local(Some(VerticalChannel {
        up: 1.0,
        down: 0.5,
        ..global_vertical()
    }));
    let flown = small.velocity_limit(&g, &limit);
    let b = flown.vertical.unwrap();
    assert!((flown.braking - 0.7 * 1.5).abs() < 1e-12);
    assert!((b.up - 0.7 * 1.0).abs() < 1e-12 && (b.down - 0.7 * 0.5).abs() < 1e-12);
    assert_eq!(flown.speed, limit.speed);
    let p = small.position(&g);
    assert!(flown.validate(p.saturation, p.vertical.as_ref()).is_ok());
    assert!(limit.validate(p.saturation, p.vertical.as_ref()).is_err());
    let wide = LocalGains {
        saturation: 3.0,
        vertical: Some(global_vertical()),
        ..small
    };
    assert_eq!(wide.velocity_limit(&g, &limit), limit);
}

/// Given a local regime with its own braking, when it flies, then its horizontal braking is
/// that one whatever the levels (above the global braking too), the vertical ones keep their
/// share, and the profile validates against the local levels; a braking not below `M_p,L` is
/// refused by name, and so is one without a velocity limit to brake with.
#[test]
fn the_local_regime_brakes_at_its_own_braking() {
    use crate::velocity_limit::{VelocityLimit, VerticalBraking};
    let g = global(Some(global_vertical()));
    let limit = VelocityLimit {
        speed: 5.0,
        braking: 1.75,
        vertical: Some(VerticalBraking { up: 2.8, down: 0.7 }),
    };
    let wide = LocalGains {
        saturation: 4.0,
        braking: Some(3.0),
        vertical: Some(global_vertical()),
        ..local(None)
    };
    assert!(wide.validate(&g).is_ok());
    let flown = wide.velocity_limit(&g, &limit);
    assert_eq!(flown.braking, 3.0);
    assert_eq!(flown.vertical, limit.vertical);
    let p = wide.position(&g);
    assert!(flown.validate(p.saturation, p.vertical.as_ref()).is_ok());
    let too_hard = LocalGains {
        braking: Some(4.0),
        ..wide
    };
    assert!(matches!(
        too_hard.validate(&g),
        Err(ParameterError::OutOfRange { name: "local braking", high, .. }) if high == 4.0
    ));
    let mut gains = crate::Gains::<f64>::paper();
    gains.position = g;
    gains.local = Some(wide);
    assert!(matches!(
        gains.validate(),
        Err(ParameterError::OutOfRange {
            name: "local braking",
            ..
        })
    ));
    gains.velocity_limit = Some(limit);
    assert!(gains.validate().is_ok());
}

/// Given a local attitude law with a gain that is not positive, when validated, then it is
/// refused with the local law's name for it (`"local k_theta"`, `"local g_3"`), not the global
/// gain's.
#[test]
fn a_bad_local_attitude_law_is_refused_by_its_own_name() {
    use crate::attitude_control::AttitudeGains;
    let g = global(None);
    let attitude = AttitudeGains {
        k_mrp: 0.0,
        k_omega: 0.1,
        mrp_saturation: 0.2,
        omega_saturation: 0.1,
    };
    let bad = LocalGains {
        attitude: Some(LocalAttitude {
            attitude,
            tilt_priority: None,
        }),
        ..local(None)
    };
    assert!(matches!(
        bad.validate(&g),
        Err(ParameterError::NotPositive {
            name: "local k_theta",
            ..
        })
    ));
    let bad_trace = LocalGains {
        attitude: Some(LocalAttitude {
            attitude: AttitudeGains {
                k_mrp: 1.0,
                ..attitude
            },
            tilt_priority: Some(crate::TiltPriorityGains {
                trace_weights: Vector3::new(0.0, 0.0, -1.0),
                omega_gains: Vector3::repeat(0.1),
                omega_levels: Vector3::repeat(0.1),
                turn_over: None,
            }),
        }),
        ..local(None)
    };
    assert!(matches!(
        bad_trace.validate(&g),
        Err(ParameterError::NotPositive {
            name: "local g_3",
            ..
        })
    ));
}
