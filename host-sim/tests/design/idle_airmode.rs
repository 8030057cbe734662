//! Airmode's margin above the rotors' least thrust (`[controller] airmode_low_margin`,
//! docs/airmode.md): what it buys upside down on the design that keeps it.

use controller_core::Trajectory as _;
use host_sim::design::evaluate::upside_down;
use host_sim::model::scenario::{HeadingConfig, Scenario, TrajectoryConfig};

use crate::support::crate_scenario as scenario;

/// `s` hovering at its reference's start `p_d(0)` with the heading `ψ_d(0)`, as `design` flies
/// its upside-down start.
fn hover_at_start(s: &Scenario) -> Scenario {
    let start = s.trajectory::<f64>().sample(0.0);
    let mut hover = s.clone();
    hover.trajectory = TrajectoryConfig::Hover {
        point_m: start.position.into(),
        heading: HeadingConfig::Constant {
            yaw_rad: start.heading.y.atan2(start.heading.x),
        },
    };
    hover
}

/// Given the committed Hummingbird design, which keeps only 0.1 % of each rotor's range above
/// its least thrust, when it is flown upside down at hover with that margin and again with the
/// design margin at both ends (the key removed), then the idle margin meets the 3 m target,
/// loses less altitude and sinks slower when the body z axis comes back above the horizon, and
/// both runs converge: the design margin at the bottom holds every rotor at 5 % of its range and
/// so pushes the inverted vehicle down while the no-dive thrust asks for none. (On the design
/// committed with this key the margin at both ends lost more than a metre more, past the
/// target; on today's, whose turn-over term is 2.4 times as strong, 0.84 m more, under it.)
#[test]
fn the_hummingbird_loses_less_altitude_upside_down_with_its_rotors_down_to_idle() {
    let idle = hover_at_start(&scenario("designs/hummingbird/scenario.toml"));
    let low = idle.controller.airmode_low_margin;
    assert_eq!(
        low,
        Some(flight_files::flight_file::AIRMODE_LEAST_LOW_MARGIN)
    );
    let mut both = idle.clone();
    both.controller.airmode_low_margin = None;
    let (with_idle, with_both) = (
        upside_down(&idle, false).unwrap(),
        upside_down(&both, false).unwrap(),
    );
    assert!(with_idle.converged && with_both.converged);
    assert!(
        with_idle.altitude_loss_m < 3.0 && with_both.altitude_loss_m > with_idle.altitude_loss_m,
        "idle {} m, margin at both ends {} m",
        with_idle.altitude_loss_m,
        with_both.altitude_loss_m
    );
    let (a, b) = (with_idle.turn_over.unwrap(), with_both.turn_over.unwrap());
    assert!(a.sink_rate_m_s < b.sink_rate_m_s, "{a:?} vs {b:?}");
}
