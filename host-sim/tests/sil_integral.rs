//! SIL: the firmware's pipeline with the bounded integral action on:
//! the default flight file (`firmware/flights/x500.toml`) carries it, sized by `design`'s rule,
//! and the firmware certifies it at boot (extended Theorem 1, Lemma 1 and Theorem 2, the
//! Liénard–Chipart conditions, and the box fit with its 5 % margin). Flown on a plant heavier than
//! the flight file says: without the estimate the same pipeline settles where the saturated
//! position law's equilibrium puts it; with it, at the reference.

use controller_core::position::PositionGains;
use firmware::config::FlightConfig;
use firmware::pipeline::FlightPipeline;
use host_sim::design::integral::IntegralSpec;
use host_sim::harness::sil::{run, scenarios, SilSetup};

/// Mass error and constant force the default flight's estimate covers (`design`'s defaults):
/// 10 % and 5 % of the weight. Its box cannot hold the 20 % / 10 % that `mass-error.toml`
/// covers: the yaw condition (0.196 N m against 0.14) and the box (28 % of the rotor range
/// short) refuse it (docs/integral-action.md, "In the firmware").
const MASS_ERROR: f64 = 0.1;
const FORCE_FRACTION: f64 = 0.05;
/// The hover is judged from here on \[s after release\]: the hand launch sinks the x500 first and
/// its output filter (`k_f` = 0.25/s) is the slowest mode (sil_pose_loss.rs).
const JUDGED_FROM_S: f64 = 70.0;
/// Length of the hover runs \[s after release\].
const DURATION_S: f64 = 90.0;
/// Release height \[m\]: high enough that the hand launch's sink (motors stopped at release,
/// the x500's idle throttle 0) does not reach the ground with the heavier plant.
const RELEASE_HEIGHT_M: f64 = 8.0;

/// The built (default) flight, with its integral action or with `[gains.integral]` removed.
fn flight(integral: bool) -> FlightConfig {
    let mut c = FlightConfig::built();
    if !integral {
        c.gains.integral = None;
    }
    c
}

/// Given the default flight file, when it is built, then its integral gains are what `design`'s
/// rule ([`IntegralSpec`]) gives for its position gains and the default coverage, computed here
/// from the rule rather than read back.
#[test]
fn the_default_flight_carries_designs_integral_action() {
    let c = FlightConfig::built();
    let p = c.gains.position;
    let position = PositionGains::<f64> {
        kp: p.kp.into(),
        kv: p.kv.into(),
        kf: p.kf.into(),
        ks: p.ks.into(),
        saturation: p.saturation.into(),
        saturation_shape: p.saturation_shape,
        vertical: p.vertical.map(|v| controller_core::VerticalChannel {
            up: v.up.into(),
            down: v.down.into(),
            kf: v.kf.into(),
            ks: v.ks.into(),
        }),
    };
    let spec = IntegralSpec::covering(f64::from(c.vehicle.gravity), MASS_ERROR, FORCE_FRACTION)
        .expect("a valid coverage");
    let rule = spec
        .gains(&position)
        .expect("locally stable integral gains");
    let built = c
        .gains
        .integral
        .expect("the default flight carries [gains.integral]");
    let close = |a: f32, b: f64| (f64::from(a) - b).abs() <= 1e-6 * b.abs().max(1.0);
    assert!(
        close(built.gain, rule.gain),
        "k_i {} vs {}",
        built.gain,
        rule.gain
    );
    assert!(close(built.bandwidth, rule.bandwidth));
    for i in 0..3 {
        assert!(
            close(built.level[i], rule.level[i]),
            "M_i {:?} vs {:?}",
            built.level,
            rule.level
        );
        assert!(
            close(built.rate[i], rule.rate[i]),
            "R_i {:?} vs {:?}",
            built.rate,
            rule.rate
        );
    }
    let (o, ro) = (built.observer.unwrap(), rule.observer.unwrap());
    assert!(close(o.velocity_gain, ro.velocity_gain));
    assert!(close(o.disturbance_gain, ro.disturbance_gain));
    assert!(close(o.error_limit, ro.error_limit));
    let (f, rf) = (
        built.feedforward_scale.unwrap(),
        rule.feedforward_scale.unwrap(),
    );
    assert!(close(f.level, rf.level) && close(f.rate, rf.rate) && close(f.gain, rf.gain));
    assert!(close(f.excitation, rf.excitation) && close(f.tracking_limit, rf.tracking_limit));
}

/// Hand launch at [`RELEASE_HEIGHT_M`], takeoff 0.5 m above it, hover for [`DURATION_S`], on a
/// plant `plant_mass_factor` times the flight's mass.
fn hover(flight: FlightConfig, plant_mass_factor: f64) -> SilSetup {
    let mut s = scenarios::pose_loss(3);
    s.pose_outage = None;
    s.duration_s = DURATION_S;
    s.initial.position.z = RELEASE_HEIGHT_M;
    s.flight = flight;
    s.plant_mass_factor = plant_mass_factor;
    s
}

/// Largest position error after [`JUDGED_FROM_S`] \[m\] and the final state.
fn judged(setup: &SilSetup) -> (f64, String) {
    let mut worst = 0.0f64;
    let s = run(setup, |r| {
        if r.t_s >= JUDGED_FROM_S {
            worst = worst.max(r.position_error_m);
        }
    })
    .unwrap();
    (worst, s.final_state)
}

/// Given the default x500 flight, with the estimate sized for 10 % of mass and 5 % of the weight
/// in force, when the firmware boots, then its gate passes: the extended certificate holds (with the
/// integral's terms and its local-stability conditions) and the box fits with the margin.
#[test]
fn the_firmware_certifies_the_integral_configuration() {
    let with = FlightPipeline::new(&flight(true)).expect("parameters accepted");
    let boot = with.boot_report();
    assert!(boot.gate.is_ok(), "{:?}", boot.gate);
    assert!(
        boot.fit_margin >= boot.required_margin,
        "{}",
        boot.fit_margin
    );
    let extended = boot
        .certificate
        .integral
        .as_ref()
        .expect("extended certificate");
    assert!(extended.level_sum.z > 0.0);
    assert!(boot.certificate.violations().next().is_none());
    // The estimate's terms are in the bounds: the extended interval is wider than without it.
    let without = FlightPipeline::new(&flight(false)).expect("parameters accepted");
    let (b, b0) = (
        boot.certificate.bounds,
        without.boot_report().certificate.bounds,
    );
    assert!(b.thrust_min < b0.thrust_min && b.thrust_max > b0.thrust_max);
    assert!(b.u_acceleration > b0.u_acceleration);
}

/// Steady height error \[m\] of the law without the estimate when the plant lacks `δ` \[m/s²\] of
/// acceleration (independent of the simulator): at rest `ṽ = 0` and the filters hold
/// `u_f = u_s = ū_p = δ`, so eq:Zcoordinates gives `z₂ = δ (1/k_f + 1/k_s)`,
/// `z₁ = p̃ + δ/(k_f k_s)`, and `ū_p = −M_p tanh((k_p z₁ + k_v z₂)/M_p)` closes it:
/// `p̃ = −(M_p atanh(δ/M_p) + k_v z₂)/k_p − δ/(k_f k_s)`. With the x500's slow filters the
/// filter terms dominate: 14 m per m/s² in the linear range.
fn sag(c: &FlightConfig, delta: f64) -> f64 {
    let p = c.gains.position;
    let (kp, kv, kf, ks, mp) = (
        f64::from(p.kp),
        f64::from(p.kv),
        f64::from(p.kf),
        f64::from(p.ks),
        f64::from(p.saturation),
    );
    let z2 = delta * (1.0 / kf + 1.0 / ks);
    (mp * (delta / mp).atanh() + kv * z2) / kp + delta / (kf * ks)
}

/// The SIL summary's settling criterion \[m\]; on the nominal plant the pipeline without the
/// estimate hovers 2-3 cm off (sensor offsets, sil_pose_loss.rs), which the estimate does not
/// claim to remove.
const SETTLED_M: f64 = 0.05;

/// Given a plant 5 % heavier than the flight file (thrust `m|u|` on a body of `1.05 m`: hovering
/// needs `u₃ = 1.05 g`), when the pipeline hovers without the estimate, then it settles below the
/// target where the law's equilibrium ([`sag`]) puts it; with the estimate, at the target.
#[test]
fn the_estimate_removes_the_sag_of_a_heavier_plant() {
    let factor = 1.05;
    let c = flight(false);
    let expected = sag(&c, (factor - 1.0) * f64::from(c.vehicle.gravity));
    let (without, state) = judged(&hover(c, factor));
    assert_eq!(state, "armed");
    assert!(
        (without - expected).abs() < 0.05 * expected,
        "without the estimate: {without} m, equilibrium {expected} m"
    );
    let (with, state) = judged(&hover(flight(true), factor));
    assert_eq!(state, "armed");
    assert!(with < SETTLED_M, "with the estimate: {with} m");
}

/// Given a plant 10 % heavier (a missing 0.98 m/s², more than `M_p` = 0.7 m/s² can give), when
/// the pipeline hovers without the estimate, then it cannot hold any height and ends on the
/// ground, 8.5 m below the target; with the estimate (sized for 10 %), it hovers at the target.
#[test]
fn the_estimate_holds_a_plant_heavier_than_the_position_law_can() {
    let factor = 1.0 + MASS_ERROR;
    let c = flight(false);
    assert!((factor - 1.0) * f64::from(c.vehicle.gravity) > f64::from(c.gains.position.saturation));
    let (without, _) = judged(&hover(c, factor));
    assert!(
        without > RELEASE_HEIGHT_M,
        "without the estimate: {without} m"
    );
    let (with, state) = judged(&hover(flight(true), factor));
    assert_eq!(state, "armed");
    assert!(with < SETTLED_M, "with the estimate: {with} m");
}
