//! Airmode and the local regime at the gate (docs/airmode.md): with airmode the rotors must
//! realise the thrust interval at zero torque and every certified torque at some thrust (the
//! shadow), not every torque at every thrust; the armed controller flies the envelope the gate
//! checked, and the law's outputs moved by airmode reach the mixer whole. Without airmode a local
//! regime's set must fit over the thrust interval too.
//!
//! The flights are the default x500 build with its rotors changed: its yaw torque per newton
//! scaled down (so the certificate, which knows only `[limits]`, is the same while the rotors'
//! yaw authority shrinks).

use controller_core::{LocalGains, TorqueSet};
use nalgebra::Vector3;

use super::{arm_attempt, drain_events};
use crate::mixer::Mixer;
use crate::pipeline::gate::{self, RotorFits};
use crate::pipeline::*;
use crate::safety::FlightState;

use super::arming::arm_refusal;

/// The default build's flight with its rotors' yaw torque per newton scaled by `yaw`, airmode
/// as given.
fn flight(yaw: f32, airmode: bool) -> FlightConfig {
    let mut c = FlightConfig::built();
    c.rotors.drag_coefficient *= yaw;
    c.airmode = airmode;
    c
}

/// The fits of the boot report of `c`.
fn fits(c: &FlightConfig) -> RotorFits {
    FlightPipeline::new(c)
        .unwrap()
        .boot_report()
        .fits
        .expect("the thrust interval is certified")
}

/// The names of `fits`, in the gate's order.
fn names(fits: &RotorFits) -> Vec<&'static str> {
    fits.as_slice().iter().map(|f| f.name).collect()
}

/// A point of the torque set `set` [N m]: the point of each summand (ellipsoid, the boxes, the
/// ball, the disks) that maximises `cᵀτ` for its own direction `c`, scaled by its own factor in
/// `[0, 1]` (1: on the summand's boundary; each summand is convex and holds 0).
fn point_of(set: &TorqueSet<f32>, parts: [(Vector3<f32>, f32); 4]) -> Vector3<f32> {
    assert_eq!(set.aligned_acceleration, nalgebra::Vector2::zeros());
    let [(ce, se), (cb, sb), (cr, sr), (cd, sd)] = parts;
    let jc = set.inertia.component_mul(&ce);
    let ellipsoid = if jc.norm() > 0.0 {
        set.inertia
            .component_mul(&(jc * (set.angular_acceleration / jc.norm())))
    } else {
        Vector3::zeros()
    };
    let boxes = (set.gyroscopic + set.feedback_box).component_mul(&cb.map(f32::signum));
    let ball = cr.normalize() * set.feedback_radius;
    let disks = (0..3).fold(Vector3::zeros(), |acc, k| {
        let mut p = cd;
        p[k] = 0.0;
        if p.norm() > 0.0 {
            acc + p * (set.feedback_disks[k] / p.norm())
        } else {
            acc
        }
    });
    ellipsoid * se + boxes * sb + ball * sr + disks * sd
}

/// The point of `set` where `cᵀτ` is largest: [`point_of`] with every summand on its boundary
/// in the direction `c`; `cᵀτ` there is the support function `h(c)`.
fn support_point(set: &TorqueSet<f32>, c: Vector3<f32>) -> Vector3<f32> {
    let tau = point_of(set, [(c, 1.0); 4]);
    assert!(
        (c.dot(&tau) - set.support(&c)).abs() <= 1e-5 * set.support(&c).abs().max(1e-6),
        "{} vs {}",
        c.dot(&tau),
        set.support(&c)
    );
    tau
}

/// Given a flight with airmode and `airmode_low_margin` below the design margin, when the
/// envelope airmode flies is built, then its range keeps the design margin below the rotors'
/// top and only the low margin above their bottom, so it contains the range the gate's fits were
/// checked on; without the key (the design margin) it is that range.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn airmode_flies_its_low_margin_above_the_rotors_idle() {
    let c = flight(0.5, true);
    let mixer = Mixer::new(&c.rotors).unwrap();
    let full = mixer.envelope().unwrap();
    let (lo, hi) = full.range;
    let span = hi - lo;
    let checked = full.shrunk(c.box_margin).range;
    assert_eq!(gate::airmode_envelope(&c, &mixer).unwrap().range, checked);
    let low = FlightConfig {
        airmode_low_margin: 0.001,
        ..c
    };
    let (a, b) = gate::airmode_envelope(&low, &mixer).unwrap().range;
    assert!((a - (lo + 0.001 * span)).abs() <= 1e-6 * span, "{a}");
    assert_eq!(b, checked.1);
    assert!(a < checked.0);
}

/// Given the x500 flight with half its rotors' yaw torque per newton, so that its certified set
/// does not fit the rotors over the whole thrust interval (some torque at some end of it leaves
/// the rotor range) but every torque fits at some thrust; when it arms without airmode, then it
/// is refused naming `rotor_fit.margin`; when it arms with airmode, then the gate checks the
/// thrust interval and the shadow, passes, and the armed controller flies the rotor range
/// shrunk by the margin; and at each end of the interval, the set's point that the mixer would
/// give up on is realised whole once airmode has moved the thrust.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn airmode_arms_where_only_the_shadow_fits() {
    let plain = flight(0.5, false);
    let (mut p, _) = arm_attempt(plain);
    assert_eq!(p.status().state, FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!((condition, rhs), (ROTOR_FIT, plain.box_margin));
    assert!(lhs < 0.0, "the set does not fit at all: {lhs}");

    let c = flight(0.5, true);
    let f = fits(&c);
    assert_eq!(names(&f), [ROTOR_FIT_THRUST, ROTOR_FIT_SHADOW]);
    assert!(
        f.as_slice().iter().all(|f| f.margin >= c.box_margin),
        "{f:?}"
    );
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    assert!(r.airmode);
    assert_eq!(r.gate, Ok(r.fit_margin));
    assert_eq!(r.fit_margin, f.smallest());
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Armed);
    assert!(!drain_events(&mut p)
        .iter()
        .any(|e| matches!(e, Event::Uncertified { .. })));
    let envelope = p.airmode().expect("the armed controller flies airmode");
    let mixer = *p.mixer();
    assert_eq!(
        Some(envelope),
        mixer.envelope().map(|e| e.shrunk(c.box_margin))
    );
    let (lo, hi) = mixer.thrust_range();
    let m = c.box_margin * (hi - lo);
    assert_eq!(envelope.range, (lo + m, hi - m));

    // The mixer gives something up at an end of the interval without airmode, nothing with it.
    let set = r.certificate.bounds.torque_set;
    let (t_lo, t_hi) = gate::thrust_interval(&r.certificate, &c.thrust).unwrap();
    let mut given_up = 0;
    for k in 0..4 {
        let row = Vector3::from_fn(|i, _| mixer.mixing()[(k, i + 1)]);
        for (t, tau) in [
            (t_hi, support_point(&set, row)),
            (t_lo, support_point(&set, -row)),
        ] {
            given_up += usize::from(mixer.mix(t, &tau).saturated());
            let moved = envelope.airmode_thrust(t, &tau);
            let out = mixer.mix(moved, &tau);
            assert!(
                !out.saturated(),
                "rotor {k}: {t} N moved to {moved} N: {out:?}"
            );
            assert!((out.achieved_torque - tau).norm() <= 1e-4 * tau.norm().max(1.0));
        }
    }
    assert!(
        given_up > 0,
        "the set fit's failure shows at a rotor's extreme"
    );
}

/// Given the x500 flight with 0.3 of its rotors' yaw torque per newton and airmode, so that
/// some certified torque is beyond the rotors at any thrust; when it arms, then it is refused
/// naming `rotor_fit.shadow`, with the shadow margin (checked against a hand computation for
/// the symmetric X) and the required margin.
///
/// Hand computation: rotor `k` takes `T/4 + c_kᵀτ` with `|c_k| = (1/(4d), 1/(4d), 1/(4c))` (`d`
/// the hub offset per axis, `c` the yaw torque per newton). For two rotors `k`, `l`, every
/// torque of the set is realised at some thrust with the range `[f_min + m s, f_max − m s]`
/// (`s = f_max − f_min`) iff `h(c_l − c_k)/4 ≤ s/4 − m s/2`, so the pair's margin is
/// `1/2 − h(c_l − c_k)/(2 s)`; `c_l − c_k` is `(1/(2d), 0, 1/(2c))` or `(0, 1/(2d), 1/(2c))` for
/// neighbours (opposite spins), `(1/(2d), 1/(2d), 0)` for a diagonal (`h` is even in each
/// component).
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn shadow_that_does_not_fit_refuses_to_arm() {
    let c = flight(0.3, true);
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    assert_eq!(r.certificate.violations().count(), 0);
    let set = r.certificate.bounds.torque_set;
    let d = c.rotors.rotors[0].position[0].abs();
    let yaw = c.rotors.torque_per_thrust();
    let span = c.rotors.thrust_max - c.rotors.thrust_min;
    let hand = [
        Vector3::new(1.0 / (2.0 * d), 0.0, 1.0 / (2.0 * yaw)),
        Vector3::new(0.0, 1.0 / (2.0 * d), 1.0 / (2.0 * yaw)),
        Vector3::new(1.0 / (2.0 * d), 1.0 / (2.0 * d), 0.0),
    ]
    .iter()
    .map(|delta| 0.5 - set.support(delta) / (2.0 * span))
    .fold(f32::INFINITY, f32::min);
    assert!(hand < c.box_margin, "{hand}");
    assert_eq!(
        fits(&c)
            .margin_of(ROTOR_FIT_THRUST)
            .map(|m| m >= c.box_margin),
        Some(true)
    );

    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!((condition, rhs), (ROTOR_FIT_SHADOW, c.box_margin));
    assert!((lhs - hand).abs() < 1e-4, "{lhs} vs {hand}");
}

/// Given the x500 flight with airmode and its rotors too weak for the top of the thrust interval
/// (each rotor's `f_max` the quarter of Theorem 1's `T_max`); when it arms, then it is refused
/// naming `rotor_fit.thrust`, with the headroom of `T_max/4` in the range (0) and the margin.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn thrust_interval_that_does_not_fit_refuses_airmode() {
    let mut c = flight(1.0, true);
    let t_max = FlightPipeline::new(&c)
        .unwrap()
        .boot_report()
        .certificate
        .bounds
        .thrust_max;
    c.rotors.thrust_max = t_max / 4.0;
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!((condition, rhs), (ROTOR_FIT_THRUST, c.box_margin));
    assert!(lhs.abs() < 1e-5, "{lhs}");
}

/// The x500 flight with a local regime of faster filters and the attitude energy up to 1 J (any
/// attitude error), its `[limits]` raised to the rotors' capacity on each axis alone at the best
/// thrust (what the rotors give with airmode), so that the local regime's per-axis conditions
/// hold: its filters are near the fastest the yaw condition allows (`k_f` = 1.3 1/s breaks
/// `local_regime.torque_max_yaw`), so its set's shadow is below the certified set's.
fn local_flight(airmode: bool) -> FlightConfig {
    let mut c = flight(1.0, airmode);
    let e = Mixer::new(&c.rotors).unwrap().envelope().unwrap();
    c.limits.torque_max = Vector3::from_fn(|i, _| 0.999 * e.shadow_axis(i));
    c.gains.local = Some(LocalGains {
        kp: 4.0,
        kv: 4.0,
        kf: 1.2,
        ks: 7.2,
        saturation: c.gains.position.saturation,
        energy_in: 0.5,
        energy_out: 1.0,
        vertical: None,
        attitude: None,
        braking: None,
    });
    c
}

/// Given the x500 flight with airmode and a local regime whose per-axis conditions hold, and the
/// required margin halfway between the certified set's shadow margin and the local set's (both
/// computed here by the mixer; the local set's is the smaller); when it arms, then it is refused
/// naming `rotor_fit.local_shadow` with that set's shadow margin and the required one, after the
/// certified set's shadow passed.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn local_regime_whose_shadow_does_not_fit_refuses_to_arm() {
    let mut c = local_flight(true);
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    assert_eq!(r.certificate.violations().count(), 0);
    let local = r.certificate.local.expect("the local regime is certified");
    let mixer = Mixer::new(&c.rotors).unwrap();
    let certified = mixer.shadow_margin(&r.certificate.bounds.torque_set);
    let expected = mixer.shadow_margin(&local.torque_set);
    assert!(expected < certified, "{expected} vs {certified}");
    c.box_margin = 0.5 * (expected + certified);

    let f = fits(&c);
    assert_eq!(
        names(&f),
        [ROTOR_FIT_THRUST, ROTOR_FIT_SHADOW, ROTOR_FIT_LOCAL_SHADOW]
    );
    assert!(f.margin_of(ROTOR_FIT_THRUST).unwrap() >= c.box_margin);
    assert!(f.margin_of(ROTOR_FIT_SHADOW).unwrap() >= c.box_margin);
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!(
        (condition, lhs, rhs),
        (ROTOR_FIT_LOCAL_SHADOW, expected, c.box_margin)
    );
}

/// Given the same local regime without airmode; when it arms, then the certified set fits over
/// the thrust interval but the local regime's set does not: refused naming `rotor_fit.local`
/// with that set's margin ([`Mixer::set_margin`] over the same interval) and the required one.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn local_regime_without_airmode_needs_its_set_to_fit() {
    let c = local_flight(false);
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    let f = r.fits.unwrap();
    assert_eq!(names(&f), [ROTOR_FIT, ROTOR_FIT_LOCAL]);
    assert!(f.margin_of(ROTOR_FIT).unwrap() >= c.box_margin);
    let (t_lo, t_hi) = gate::thrust_interval(&r.certificate, &c.thrust).unwrap();
    let mixer = Mixer::new(&c.rotors).unwrap();
    let expected = mixer.set_margin(t_lo, t_hi, &r.certificate.local.unwrap().torque_set);
    assert!(expected < c.box_margin, "{expected}");

    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!(
        (condition, lhs, rhs),
        (ROTOR_FIT_LOCAL, expected, c.box_margin)
    );
}

/// Given a flight with neither airmode nor a local regime; when the gate runs, then it checks
/// the certified set's fit alone and returns its margin bit for bit
/// ([`Mixer::set_margin`] over the thrust interval), as before airmode; and the armed controller
/// flies no airmode.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn without_airmode_or_local_regime_the_gate_is_the_set_fit() {
    let c = FlightConfig::built();
    assert!(!c.airmode && c.gains.local.is_none());
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    let (t_lo, t_hi) = gate::thrust_interval(&r.certificate, &c.thrust).unwrap();
    let mixer = Mixer::new(&c.rotors).unwrap();
    let set_margin = mixer.set_margin(t_lo, t_hi, &r.certificate.bounds.torque_set);
    let f = r.fits.unwrap();
    assert_eq!(names(&f), [ROTOR_FIT]);
    assert_eq!(r.fit_margin.to_bits(), set_margin.to_bits());
    assert_eq!(r.gate.map(f32::to_bits), Ok(set_margin.to_bits()));
    assert_eq!((r.airmode, r.aligned_margin), (false, None));
    let (p, _) = arm_attempt(c);
    assert_eq!(p.status().state, FlightState::Armed);
    assert_eq!(p.airmode(), None);
}

#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
mod airmode_properties {
    use super::*;
    use proptest::prelude::*;

    fn unit(theta: f32, phi: f32) -> Vector3<f32> {
        Vector3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    /// One summand's part of a point of the set: a direction and a scale, on the summand's
    /// boundary half the time.
    fn part() -> impl Strategy<Value = (Vector3<f32>, f32)> {
        (
            0.0..std::f32::consts::PI,
            0.0..std::f32::consts::TAU,
            prop_oneof![Just(1.0f32), 0.0..=1.0f32],
        )
            .prop_map(|(theta, phi, scale)| (unit(theta, phi), scale))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// Given the flight of [`airmode_arms_where_only_the_shadow_fits`] (its set does not fit
        /// the rotors over the thrust interval, its shadow does), airmode's margin above the
        /// rotors' least thrust anywhere from the least a flight file takes to the design margin
        /// (`airmode_low_margin`), and the envelope its armed controller flies
        /// ([`gate::airmode_envelope`]); when a law output with its thrust anywhere in the
        /// certified interval (or below it, as the no-dive thrust cuts it) and its torque
        /// anywhere in the certified set is moved by airmode, then the mixer gives nothing up
        /// and realises the thrust and the torque.
        #[test]
        fn airmode_then_the_mixer_never_gives_anything_up(
            parts in [part(), part(), part(), part()],
            at in -0.2..=1.0f32,
            low in prop_oneof![Just(1e-3f32), Just(0.05f32), 1e-3..=0.05f32],
        ) {
            let c = FlightConfig {
                airmode_low_margin: low,
                ..flight(0.5, true)
            };
            let r = FlightPipeline::new(&c).unwrap().boot_report();
            let mixer = Mixer::new(&c.rotors).unwrap();
            let envelope = gate::airmode_envelope(&c, &mixer).unwrap();
            let (t_lo, t_hi) = gate::thrust_interval(&r.certificate, &c.thrust).unwrap();
            let tau = point_of(&r.certificate.bounds.torque_set, parts);
            let thrust = (t_lo + at * (t_hi - t_lo)).max(0.0);
            let moved = envelope.airmode_thrust(thrust, &tau);
            let out = mixer.mix(moved, &tau);
            prop_assert!(!out.saturated(), "{thrust} N moved to {moved} N, {tau:?}: {out:?}");
            prop_assert!((out.achieved_torque - tau).norm() <= 1e-4 * tau.norm().max(1.0));
            prop_assert!((out.achieved_thrust - moved).abs() <= 1e-4 * moved.max(1.0));
        }
    }
}
