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
        narrow_local: false,
        local_vertical: false,
        turn_over: false,
        local_integral: false,
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

/// Distance \[m\] covered by `until` \[s\] and largest |acceleration| \[m/s²\] of the rest-to-rest
/// profile of duration `time` with the acceleration bound `a` and the jerk bound `j`,
/// integrated segment by segment over the whole profile (an independent check of
/// [`rest_to_rest_time`]'s closed forms and of [`band_entry_time`]): jerk `+j` until the
/// acceleration reaches `min(a, j time / 4)`, held, `−j` back to 0 at the midpoint, then the
/// mirror image. Each segment's jerk is constant, so its integration is exact.
fn fly_profile(time: f64, a: f64, j: f64, until: f64) -> (f64, f64) {
    let peak = a.min(j * time / 4.0);
    let ramp = peak / j;
    let hold = time / 2.0 - 2.0 * ramp;
    let segments = [
        (ramp, j),
        (hold, 0.0),
        (ramp, -j),
        (ramp, -j),
        (hold, 0.0),
        (ramp, j),
    ];
    let (mut acc, mut vel, mut pos, mut top, mut left) = (0.0f64, 0.0, 0.0, 0.0f64, until);
    for (length, jerk) in segments {
        assert!(length >= -1e-12, "{length}");
        let dt = length.min(left).max(0.0);
        pos += vel * dt + acc * dt * dt / 2.0 + jerk * dt.powi(3) / 6.0;
        vel += acc * dt + jerk * dt * dt / 2.0;
        acc += jerk * dt;
        top = top.max(acc.abs());
        left -= dt;
    }
    if until >= time {
        assert!(
            vel.abs() < 1e-9 * peak * time && acc.abs() < 1e-9 * peak,
            "{vel} {acc}"
        );
    }
    (pos, top)
}

/// Given moves with the acceleration bound reached and not, when the profile of the floor's
/// duration is flown, then it covers the distance and keeps both bounds; the two forms meet at
/// `d = 2A³/J²`, and the time tends to bang-bang `2√(d/A)` as the jerk bound grows and to
/// `(32 d/J)^(1/3)` as the acceleration bound does.
#[test]
fn the_rest_to_rest_time_is_a_profile_within_both_bounds() {
    for &(d, a, j) in &[
        (0.95, 0.94, 1.35),
        (0.95, 2.54, 15.1),
        (1.0, 0.5, 20.0),
        (3.0, 1.0, 1.0),
        (0.95, 5.0, 1.35),
    ] {
        let t = rest_to_rest_time(d, a, j);
        let (covered, top) = fly_profile(t, a, j, t);
        assert!(
            (covered - d).abs() < 1e-9 * d,
            "{d} {a} {j}: {covered} in {t}"
        );
        assert!(top <= a * (1.0 + 1e-12), "{top} > {a}");
    }
    let (a, j) = (1.3, 4.0);
    let edge = 2.0 * a * a * a / (j * j);
    let below = rest_to_rest_time(edge * (1.0 - 1e-9), a, j);
    let above = rest_to_rest_time(edge * (1.0 + 1e-9), a, j);
    assert!((below - above).abs() < 1e-6, "{below} vs {above}");
    let bang_bang = 2.0 * (0.95f64 / 0.94).sqrt();
    assert!((rest_to_rest_time(0.95, 0.94, 1e9) - bang_bang).abs() < 1e-3);
    let jerk_only = (32.0f64 * 0.95 / 1.35).cbrt();
    assert!((rest_to_rest_time(0.95, 1e9, 1.35) - jerk_only).abs() < 1e-9);
}

/// Given the step and its band, the floor is the moment the time-optimal move to the band's
/// far edge crosses its near edge (flown segment by segment), earlier than a rest-to-rest move
/// to the near edge; with an unbounded jerk it is bang-bang's crossing,
/// `2√(D/A) − √(2(D − x)/A)` for `D` = 1.05 m, `x` = 0.95 m.
#[test]
fn the_step_floor_is_where_the_fastest_stoppable_move_enters_the_band() {
    for &(a, j) in &[(0.94, 1.35), (2.54, 8.45), (1.98, 5.12), (0.5, 20.0)] {
        let entry = band_entry_time((1.0, 0.05), a, j);
        let time = rest_to_rest_time(1.05, a, j);
        let (at, _) = fly_profile(time, a, j, entry);
        assert!((at - 0.95).abs() < 1e-9, "{a} {j}: {at} at {entry}");
        let (before, _) = fly_profile(time, a, j, entry - 1e-3);
        assert!(before < 0.95, "{before}");
        assert!(entry < rest_to_rest_time(0.95, a, j));
    }
    let a = 0.94;
    let bang_bang = 2.0 * (1.05f64 / a).sqrt() - (2.0 * 0.1f64 / a).sqrt();
    let entry = band_entry_time((1.0, 0.05), a, 1e9);
    assert!((entry - bang_bang).abs() < 1e-4, "{entry} vs {bang_bang}");
}

/// Given the committed preset designs, their reported step floor lies below the step they fly
/// (design.md's nominal task): the floor drops the attitude's lag, so a floor above the flown
/// time would be a wrong floor; and it is the floor of their own gains.
#[test]
fn the_committed_designs_fly_the_step_no_faster_than_their_floor() {
    for preset in PRESETS {
        let path = format!(
            "{}/designs/{preset}/design.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let floor = json["what_binds"]["step"]["time_s"].as_f64().unwrap();
        let local = json["gains"]["local"].is_object();
        let (g, level) = if local {
            (&json["gains"]["local"], "M_p_m_s2")
        } else {
            (&json["gains"], "M_p")
        };
        let number = |key: &str| g[key].as_f64().unwrap();
        let own = StepFloor::new(number(level), (number("kf"), number("ks")), local);
        assert!(
            (own.time_s - floor).abs() < 1e-9 * floor,
            "{preset}: {own:?} vs {floor}"
        );
        let flown = json["objective"]["nominal_tasks"][0]["step_settling_time_s"]
            .as_f64()
            .unwrap();
        assert!(
            floor > 0.5 && floor < flown,
            "{preset}: floor {floor} s, flown {flown} s"
        );
    }
}
