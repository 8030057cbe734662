//! SIL: the firmware flies the no-dive thrust (`[controller] thrust = "vertical-priority"` in a
//! flight file, [`ThrustChoice::VerticalPriority`]) inside its certificate: the gate certifies
//! the box `[T_floor, T_max] × Π[−τ_i, τ_i]` against the rotors, so the floor is the one the
//! rotors can hold the certified torques at, and the thrust never leaves that interval.

use firmware::config::{FlightConfig, ThrustChoice};
use firmware::pipeline::FlightPipeline;
use host_sim::harness::sil::{run, scenarios, SilSetup};

/// Vertical priority's ramp `b₀` (the scenario files' default).
const RAMP: f32 = 0.2;

/// The default x500 flight with thrust `thrust`.
fn flight(thrust: ThrustChoice) -> FlightConfig {
    FlightConfig {
        thrust,
        ..FlightConfig::built()
    }
}

fn vertical_priority(floor: f32) -> ThrustChoice {
    ThrustChoice::VerticalPriority { ramp: RAMP, floor }
}

/// Whether the firmware's boot gate passes for `thrust` on the built flight.
fn certified(thrust: ThrustChoice) -> bool {
    FlightPipeline::new(&flight(thrust))
        .map(|p| p.boot_report().gate.is_ok())
        .unwrap_or(false)
}

/// The lowest floor \[N\] the gate certifies, by bisection over `[0, T_min]` (the box's lower
/// end rises with the floor, so the gate passes above some floor and fails below it), with
/// Theorem 1's `T_min` of the demo mission.
fn lowest_certified_floor() -> (f32, f32) {
    let boot = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let t_min = boot.boot_report().certificate.bounds.thrust_min;
    assert!(certified(vertical_priority(t_min)));
    assert!(!certified(vertical_priority(0.0)));
    let (mut lo, mut hi) = (0.0f32, t_min);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if certified(vertical_priority(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (hi, t_min)
}

/// Altitude lost (start height minus the lowest) \[m\], the thrust range commanded while armed
/// \[N\], and the summary's mixer-saturated ticks.
fn upside_down(setup: &SilSetup) -> (f64, [f64; 2], u32) {
    let start = setup.initial.position.z;
    let (mut lowest, mut range) = (start, [f64::INFINITY, f64::NEG_INFINITY]);
    let s = run(setup, |r| {
        lowest = lowest.min(r.z_m);
        if r.state == "armed" {
            range = [range[0].min(r.thrust_N), range[1].max(r.thrust_N)];
        }
    })
    .unwrap();
    (start - lowest, range, s.mixer_saturated_ticks)
}

/// Given the x500 flight with the no-dive thrust, when the floor is below what the rotors need
/// to hold the certified torques, then the gate refuses it (box fit), and at or above the
/// lowest certified floor it passes; a floor above Theorem 1's `T_min` is refused by name.
#[test]
fn the_gate_certifies_the_floor_the_rotors_can_hold() {
    let (floor, t_min) = lowest_certified_floor();
    assert!(
        floor > 0.0 && floor < t_min,
        "floor {floor} N, T_min {t_min} N"
    );
    let boot = FlightPipeline::new(&flight(vertical_priority(floor))).unwrap();
    let r = boot.boot_report();
    assert!(r.gate.is_ok(), "{:?}", r.gate);
    assert_eq!(r.a_priori_fit.thrust_needed[0], floor);
    let below = FlightPipeline::new(&flight(vertical_priority(0.99 * floor))).unwrap();
    let refusal = below.boot_report().gate.unwrap_err();
    assert_eq!(refusal.condition, "rotor_fit.margin");
    let above = FlightPipeline::new(&flight(vertical_priority(1.01 * t_min))).unwrap();
    let refusal = above.boot_report().gate.unwrap_err();
    assert_eq!(refusal.condition, "thrust_floor");
    assert_eq!(refusal.rhs, t_min);
}

/// Given the x500 released upside down (the SIL `paper` scenario), when the firmware flies the
/// no-dive thrust with the lowest certified floor, then it loses less altitude than with the
/// paper's thrust, its thrust stays in `[T_floor, T_max]`, and the mixer never gives anything
/// up.
#[test]
fn the_no_dive_thrust_loses_less_altitude_inside_its_box() {
    let (floor, _) = lowest_certified_floor();
    let thrust = vertical_priority(floor);
    let t_max = FlightPipeline::new(&flight(thrust))
        .unwrap()
        .boot_report()
        .certificate
        .bounds
        .thrust_max;
    let mut paper = scenarios::paper(1);
    paper.flight = flight(ThrustChoice::Norm);
    let mut no_dive = scenarios::paper(1);
    no_dive.flight = flight(thrust);
    let (lost_paper, _, _) = upside_down(&paper);
    let (lost, range, saturated) = upside_down(&no_dive);
    assert!(lost < lost_paper, "{lost} m against {lost_paper} m");
    assert!(
        range[0] >= f64::from(floor) - 1e-3 && range[1] <= f64::from(t_max) + 1e-3,
        "{range:?} outside [{floor}, {t_max}]"
    );
    assert_eq!(saturated, 0);
}
