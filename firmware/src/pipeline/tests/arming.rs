//! Arming and the certificate gate: the built flight certified and armed, a failing
//! certificate or a box that does not fit refused with the condition and its numbers, the
//! paper's set-up only with the uncertified flag, a reference change only when certified.

use super::{arm_attempt, armed_pipeline, command, drain_events};
use crate::link;
use crate::pipeline::*;
use nalgebra::Vector3;

/// `(condition, lhs, rhs)` of the first `ReferenceRefused` event, if any.
fn reference_refusal(events: &[Event]) -> Option<(&'static str, f32, f32)> {
    events.iter().find_map(|e| match *e {
        Event::ReferenceRefused {
            condition,
            lhs,
            rhs,
        } => Some((condition, lhs, rhs)),
        _ => None,
    })
}

/// The refusal of the arm command: `(condition, lhs, rhs)` of its `ReferenceRefused` event.
pub(super) fn arm_refusal(events: &[Event]) -> (&'static str, f32, f32) {
    assert!(
        events
            .iter()
            .any(|e| matches!(e, Event::CommandRefused { command: "arm", .. })),
        "{events:?}"
    );
    reference_refusal(events).expect("the refusal names its condition")
}

/// The default build's flight file (and, in the test command, each preset design's and the
/// airmode fixture's) is certified at boot (every condition, every rotor fit's margin at least
/// the file's) and arms, with no uncertified warning; the armed controller flies airmode exactly
/// when the file asks for it, on the rotor range shrunk by the file's margin.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn built_config_is_certified_and_arms() {
    let c = FlightConfig::built();
    assert!(!c.allow_uncertified);
    let r = FlightPipeline::new(&c).unwrap().boot_report();
    assert_eq!(r.certificate.violations().count(), 0);
    assert!(
        r.fit_margin >= c.box_margin,
        "{} < {}",
        r.fit_margin,
        c.box_margin
    );
    assert_eq!(r.gate, Ok(r.fit_margin));
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    let events = drain_events(&mut p);
    assert!(!events
        .iter()
        .any(|e| matches!(e, Event::Uncertified { .. })));
    assert_eq!(p.airmode().is_some(), c.airmode);
    assert_eq!(p.airmode(), gate::airmode_envelope(&c, p.mixer()));
}

/// A configuration whose certificate fails refuses to arm and says which condition, with its
/// numbers: a yaw limit between Assumption 1's yaw requirement and Theorem 2's yaw bound, which is
/// at least the feedback torque `ι = (1 + (1 + δ)²) M_ϑ / 4 + M_ω`, computed here by hand.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn failing_certificate_refuses_to_arm() {
    let mut c = FlightConfig::built();
    let (g, a) = (c.gains, c.gains.attitude);
    let iota = (1.0 + (1.0 + g.hysteresis).powi(2)) * a.mrp_saturation / 4.0 + a.omega_saturation;
    let cert = FlightPipeline::new(&c).unwrap().boot_report().certificate;
    let rhs_of = |name: &str| cert.conditions.iter().find(|k| k.name == name).unwrap().rhs;
    let (assumption, theorem2) = (
        rhs_of("assumption1.torque_max_yaw"),
        rhs_of("theorem2.torque_max_yaw"),
    );
    assert!(theorem2 > iota && theorem2 > assumption);
    c.limits.torque_max.z = 0.5 * (assumption.max(iota) + theorem2);
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, crate::safety::FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!(condition, "theorem2.torque_max_yaw");
    assert_eq!(lhs, c.limits.torque_max.z);
    assert_eq!(rhs, theorem2);
    assert!(rhs > iota, "{rhs} vs iota {iota}");
}

/// The board's Theorem 2 yaw bound (`theorem2.torque_max_yaw`'s right-hand side) for the default
/// flight file certified with `form`.
fn board_yaw_bound(form: controller_core::Lemma1Form) -> f32 {
    let mut c = FlightConfig::built();
    c.gains.lemma1 = form;
    let cert = FlightPipeline::new(&c).unwrap().boot_report().certificate;
    let k = cert.conditions.iter();
    k.clone()
        .find(|k| k.name == "theorem2.torque_max_yaw")
        .unwrap()
        .rhs
}

/// With a yaw limit between the `tighter` form's Theorem 2 bound and the `looser` one's, the board
/// arms with `lemma1 = tighter` and refuses with `lemma1 = looser`, naming
/// `theorem2.torque_max_yaw` and the looser bound.
fn the_board_certifies_with_the_named_form(
    tighter: controller_core::Lemma1Form,
    looser: controller_core::Lemma1Form,
) {
    let (tight, loose) = (board_yaw_bound(tighter), board_yaw_bound(looser));
    assert!(tight < loose, "{tight} vs {loose}");
    for (form, arms) in [(tighter, true), (looser, false)] {
        let mut c = FlightConfig::built();
        c.gains.lemma1 = form;
        c.limits.torque_max.z = 0.5 * (tight + loose);
        let (mut p, _) = arm_attempt(c);
        let events = drain_events(&mut p);
        if arms {
            assert_eq!(
                p.status().state,
                crate::safety::FlightState::Armed,
                "{events:?}"
            );
        } else {
            assert_eq!(p.status().state, crate::safety::FlightState::Disarmed);
            let (condition, lhs, rhs) = arm_refusal(&events);
            assert_eq!(condition, "theorem2.torque_max_yaw");
            assert_eq!((lhs, rhs), (c.limits.torque_max.z, loose));
        }
    }
}

/// The board certifies with the chain the flight file names: a yaw limit between the tangential
/// Lemma 1's Theorem 2 bound and the paper's arms with `lemma1 = "tangential"` and is refused with
/// `lemma1 = "paper"`, naming `theorem2.torque_max_yaw` and the paper's bound.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn the_tangential_certificate_is_what_the_board_checks() {
    the_board_certifies_with_the_named_form(
        controller_core::Lemma1Form::Tangential,
        controller_core::Lemma1Form::Paper,
    );
}

/// Likewise one step further: with `lemma1 = "desired_frame"` the board judges Theorem 2's
/// per-axis conditions on the desired frame's norms (the certified set's), and a yaw limit
/// between that bound and the tangential one arms with it and is refused with the tangential
/// form.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn the_desired_frame_certificate_is_what_the_board_checks() {
    the_board_certifies_with_the_named_form(
        controller_core::Lemma1Form::DesiredFrame,
        controller_core::Lemma1Form::Tangential,
    );
}

/// A configuration whose certified set does not fit its rotors refuses to arm, and so does one
/// whose set fits with less than the required margin; the refusal carries the margin, checked
/// against a hand computation for the symmetric X (`d` the hub offset per axis, `c` the yaw
/// ratio): rotor `k` takes `T/4 + cᵀτ` with `|c| = (1/(4d), 1/(4d), 1/(4c))`, whose largest
/// value over the torque set is `U_ω̇d |J c| + Σ_i |c_i| (gyroscopic_i + box_i) + r |c|`
/// (docs/torque-set.md); headroom `f_max − (T_hi/4 + that)` over the range.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn box_that_does_not_fit_refuses_to_arm() {
    let built = FlightConfig::built();
    let bounds = FlightPipeline::new(&built)
        .unwrap()
        .boot_report()
        .certificate
        .bounds;
    let d = built.rotors.rotors[0].position[0].abs();
    let c = built.rotors.torque_per_thrust();
    let set = bounds.torque_set;
    let row = Vector3::new(1.0 / (4.0 * d), 1.0 / (4.0 * d), 1.0 / (4.0 * c));
    let j = built.vehicle.inertia;
    let ellipsoid = set.angular_acceleration
        * ((j.x * row.x).powi(2) + (j.y * row.y).powi(2) + (j.z * row.z).powi(2)).sqrt();
    let boxes = row.x * (set.gyroscopic.x + set.feedback_box.x)
        + row.y * (set.gyroscopic.y + set.feedback_box.y)
        + row.z * (set.gyroscopic.z + set.feedback_box.z);
    let ball = set.feedback_radius * (row.x * row.x + row.y * row.y + row.z * row.z).sqrt();
    let top = bounds.thrust_max / 4.0 + ellipsoid + boxes + ball;
    // The top corner needs `top` newtons of one rotor: give it 0.98 of that (does not fit),
    // then 2 % of the range more than it needs (fits, below the 5 % margin).
    for (f_max, fits) in [(0.98 * top, false), (top + 0.02 * (top - 0.2) / 0.98, true)] {
        let mut cfg = built;
        cfg.rotors.thrust_max = f_max;
        let r = FlightPipeline::new(&cfg).unwrap().boot_report();
        assert_eq!(r.certificate.violations().count(), 0);
        // The box of the per-axis bounds contains the set: where the set does not fit, neither
        // does the box.
        if !fits {
            assert!(!r.a_priori_fit.fits);
        }
        let hand = (f_max - top) / (f_max - cfg.rotors.thrust_min);
        assert!(
            (r.fit_margin - hand).abs() < 1e-4,
            "{} vs {hand}",
            r.fit_margin
        );
        let (mut p, _) = arm_attempt(cfg);
        assert_eq!(p.status().state, crate::safety::FlightState::Disarmed);
        let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
        assert_eq!((condition, rhs), (ROTOR_FIT, cfg.box_margin));
        assert!((lhs - hand).abs() < 1e-4 && lhs < cfg.box_margin);
    }
}

/// The paper's set-up (Theorem 2 yaw fails, box does not fit) refuses to arm; with
/// `allow_uncertified` (the `uncertified-paper` build) it arms with a loud warning event naming
/// the failing condition.
#[test]
fn paper_config_arms_only_when_uncertified_is_allowed() {
    let (mut p, _) = arm_attempt(FlightConfig::paper());
    assert_eq!(p.status().state, crate::safety::FlightState::Disarmed);
    let (condition, lhs, rhs) = arm_refusal(&drain_events(&mut p));
    assert_eq!(condition, "theorem2.torque_max_yaw");
    assert!(lhs < rhs);

    let allowed = FlightConfig {
        allow_uncertified: true,
        ..FlightConfig::paper()
    };
    arms_warning_of_the_yaw_condition(allowed);
}

/// A reference change is gated too: armed on the certified x500 set-up, the demo mission is
/// accepted; a hover target 100 m away is refused (the setpoint filter's acceleration bound,
/// about `λ² · 0.17 · 100 m` = 68 m/s² with λ = 2/s, exceeds `g`), naming the condition, and the
/// mission goes on.
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn reference_change_needs_the_certificate() {
    let (mut p, now) = armed_pipeline();
    let start = command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0);
    p.on_link_bytes(&start, now);
    assert_eq!(p.status().mode, Mode::Helix);
    drain_events(&mut p);
    let far = crate::ground_station::setpoint_nwu(Vector3::new(100.0, 0.0, 1.0), 0.0);
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(&far, 255, 190, 0, &mut b);
    p.on_link_bytes(&b[..n], now + 10_000);
    let events = drain_events(&mut p);
    let (condition, lhs, rhs) = reference_refusal(&events).expect("the far setpoint is refused");
    assert!(
        !condition.is_empty() && lhs.partial_cmp(&rhs) != Some(core::cmp::Ordering::Greater),
        "{condition}: {lhs} vs {rhs}"
    );
    assert_eq!(p.status().mode, Mode::Helix);
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
}

/// The `uncertified-paper` build of `firmware/flights/paper.toml` is the paper's set-up
/// (`FlightConfig::paper()`'s vehicle, rotors, limits, gains and helix), allowed to arm: it
/// arms with a loud `Uncertified` event naming Theorem 2's yaw condition.
#[test]
#[cfg(feature = "uncertified-paper")]
fn uncertified_paper_build_is_the_paper_set_up_and_arms_loudly() {
    let built = FlightConfig::built();
    let paper = FlightConfig::paper();
    assert!(built.allow_uncertified);
    assert_eq!(built.identity.name, "paper");
    assert_eq!(
        (
            built.vehicle,
            built.rotors,
            built.limits,
            built.gains,
            built.mission
        ),
        (
            paper.vehicle,
            paper.rotors,
            paper.limits,
            paper.gains,
            paper.mission
        )
    );
    arms_warning_of_the_yaw_condition(built);
}

/// `c` arms, and says loudly that Theorem 2's yaw condition does not hold (the paper's set-up).
fn arms_warning_of_the_yaw_condition(c: FlightConfig) {
    let (mut p, _) = arm_attempt(c);
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    let events = drain_events(&mut p);
    assert!(events.iter().any(|e| matches!(
        e,
        Event::Uncertified {
            condition: "theorem2.torque_max_yaw",
            ..
        }
    )));
}
