use super::*;
use crate::design::authority::saturation_max_with;
use crate::design::variables::tests::{context, preset_on_the_paper_helix};
use crate::design::variables::{position_law, AttitudeLaw, Choices, Layout};
use controller_core::{Lemma1Form, PositionSaturation};
use nalgebra::Vector4;

const PRESETS: [&str; 3] = ["crazyflie-2.1", "hummingbird", "x500"];

/// Given random designs (tilt priority, vertical channel, airmode and the set fit) on each
/// preset, when the cap on `M_p` is reported, then it is where the search stops: `M_p,max`
/// itself is not blocked, and the reported condition is violated by its own numbers, checked
/// independently (the rotors' thrusts through the mixing matrix, the feedforward against the
/// capacity). Every kind of cap the presets reach is counted, and the thrust fit and Theorem
/// 2's yaw condition (the ones the presets' designs meet) both occur.
#[test]
fn the_reported_cap_is_where_the_search_stops() {
    let mut rng = crate::runs::sampler::seeded_rng(5);
    let layout = Layout {
        law: AttitudeLaw::TiltPriority,
        local: false,
        vertical: true,
    };
    let (mut thrust_fit, mut torque_fit, mut assumption) = (0, 0, 0);
    for name in PRESETS {
        let (v, set, constants) = preset_on_the_paper_helix(name);
        for fit in [RotorFit::Airmode, RotorFit::Set] {
            let ctx = context(
                (&v, &constants, &set),
                fit,
                PositionSaturation::Norm,
                Lemma1Form::DesiredFrame,
            );
            for _ in 0..25 {
                use rand::RngExt;
                let x: Vec<f64> = (0..layout.dimension())
                    .map(|_| rng.random_range(0.0..=1.0))
                    .collect();
                let c = Choices::from_unit(&x, layout);
                let law = position_law(&ctx, &c);
                let rotors = (&set, ctx.margin, fit);
                let Some(mp_max) =
                    saturation_max_with(ctx.bounds, &v.body, &constants, rotors, (c.kf, c.ks), law)
                else {
                    continue;
                };
                let args = (ctx.bounds, &v.body, &constants);
                assert_eq!(
                    saturation_blocked(args.0, args.1, args.2, rotors, (mp_max, c.kf, c.ks), law),
                    None,
                    "{name} {fit:?}: M_p,max {mp_max} is blocked"
                );
                let cap = saturation_cap(args.0, args.1, args.2, rotors, (mp_max, c.kf, c.ks), law);
                let (lo, hi) = set.shrunk(ctx.margin);
                match cap {
                    SaturationCap::ThrustFloor { level_m_s2 } => {
                        assert!(
                            mp_max >= level_m_s2 * (1.0 - 1e-6),
                            "{name}: {mp_max} {cap:?}"
                        )
                    }
                    SaturationCap::ThrustFit {
                        thrust_N: [t_lo, t_hi],
                        ..
                    } => {
                        thrust_fit += 1;
                        let rotor = |t: f64| set.mix * Vector4::new(t, 0.0, 0.0, 0.0);
                        let out = rotor(t_hi).max() > hi || rotor(t_lo).min() < lo;
                        assert!(out, "{name}: {cap:?} fits [{lo}, {hi}] per rotor");
                    }
                    SaturationCap::Theorem2 {
                        axis,
                        feedforward_Nm,
                        capacity_Nm,
                    } => {
                        assert!(axis < 3);
                        assert!(
                            feedforward_Nm >= capacity_Nm * (1.0 - 1e-6),
                            "{name}: {cap:?} leaves room"
                        );
                    }
                    SaturationCap::Assumption1 {
                        reference_Nm: needed,
                        capacity_Nm: capacity,
                        ..
                    } => {
                        assumption += 1;
                        assert!(needed >= capacity * (1.0 - 1e-6), "{name}: {cap:?}");
                    }
                    SaturationCap::TorqueFit => {
                        torque_fit += 1;
                        // The feedforward's set alone, without any feedback, leaves the rotors
                        // (controller-core's fit of the set, not the closed form) at one of
                        // the levels the cap is looked for at.
                        let overfull = [1e-3, 1e-2, 1e-1].iter().any(|step| {
                            let mp = mp_max * (1.0 + step);
                            envelope_with(ctx.bounds, &v.body, &constants, (mp, c.kf, c.ks), law)
                                .and_then(|env| env.feedforward_set.map(|ff| (env, ff)))
                                .is_some_and(|(env, ff)| match fit {
                                    RotorFit::Set => {
                                        crate::design::authority::set_margin(&set, env.thrust, &ff)
                                            < ctx.margin
                                    }
                                    RotorFit::Airmode => {
                                        set.envelope(ctx.margin).shadow_margin(&ff) < 0.0
                                    }
                                })
                        });
                        assert!(overfull, "{name} {fit:?}: the feedforward alone fits");
                    }
                    SaturationCap::Refused => {}
                }
            }
        }
    }
    assert!(
        thrust_fit > 0 && torque_fit > 0 && assumption > 0,
        "thrust fit {thrust_fit}, torque fit {torque_fit}, Assumption 1 {assumption}"
    );
}

/// Given each preset's rotors, when the collective range at zero torque is computed, then at
/// its ends the most loaded rotor sits exactly on the range shrunk by the margin (through the
/// mixing matrix, not the collective weights), and a hair beyond leaves it.
#[test]
fn the_collective_range_puts_a_rotor_on_its_limit() {
    for name in PRESETS {
        let (_, set, _) = preset_on_the_paper_helix(name);
        for margin in [0.0, 0.05, 0.2] {
            let [c_lo, c_hi] = collective_range(&set, margin);
            let (lo, hi) = set.shrunk(margin);
            let rotor = |t: f64| set.mix * Vector4::new(t, 0.0, 0.0, 0.0);
            let tol = 1e-9 * hi;
            assert!((rotor(c_hi).max() - hi).abs() <= tol, "{name}: {c_hi}");
            assert!((rotor(c_lo).min() - lo).abs() <= tol, "{name}: {c_lo}");
            let step = 1e-3 * c_hi;
            assert!(rotor(c_hi + step).max() > hi && rotor(c_lo - step).min() < lo);
        }
    }
}

/// Given the rotor fit's level and Theorem 2's per axis, then the binding axis is the least
/// level when it is below the fit's, and none (the rotor fit) otherwise.
#[test]
fn the_least_level_names_the_binding_axis() {
    let cap = |fit: f64, t2: [f64; 3]| IotaCap {
        rotor_fit_Nm: fit,
        theorem2_Nm: t2,
    };
    assert_eq!(cap(1.0, [2.0, 2.0, 0.5]).theorem2_axis(), Some(2));
    assert_eq!(cap(1.0, [0.7, 0.9, f64::INFINITY]).theorem2_axis(), Some(0));
    assert_eq!(cap(0.4, [2.0, 2.0, 0.5]).theorem2_axis(), None);
    assert_eq!(cap(0.4, [f64::INFINITY; 3]).theorem2_axis(), None);
}
