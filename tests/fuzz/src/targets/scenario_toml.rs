//! host-sim's scenario parsers on arbitrary text: the simulation scenarios
//! ([`host_sim::scenario::Scenario::parse`], which also reads the `[vehicle]`, `[rotors]`,
//! `[limits]`, `[gains]` and `[trajectory]` tables) and the software-in-the-loop scenarios
//! ([`host_sim::harness::sil::scenario_file::parse`]).
//!
//! Invariants: no panic (a bad file is an error); an accepted simulation scenario validates
//! again, its initial state is finite, and its trajectory and rotors are built without a
//! panic; an accepted SIL scenario's flight configuration boots the
//! firmware's pipeline or is refused with an error, never a panic.

use firmware::pipeline::FlightPipeline;
use host_sim::harness::sil::scenario_file;
use host_sim::scenario::Scenario;

/// Runs the target on one input; panics on a broken invariant.
pub fn run(data: &[u8]) {
    let Some(text) = super::text(data) else {
        return;
    };
    // Both parsers on every input: the two formats share their tables and comments.
    simulation(text);
    sil(text);
}

fn simulation(text: &str) {
    let Ok(s) = Scenario::parse(text, "fuzz") else {
        return;
    };
    if let Err(e) = s.validate() {
        panic!("an accepted scenario fails validation: {e}");
    }
    let x = s.initial_state();
    let q = x.attitude.quaternion().coords;
    let finite = x
        .position
        .iter()
        .chain(x.velocity.iter())
        .chain(q.iter())
        .chain(x.angular_velocity.iter())
        .all(|v| v.is_finite());
    assert!(
        finite,
        "an accepted scenario gives a non-finite initial state: {x:?}"
    );
    let _ = s.trajectory::<f64>();
    let _ = s.rotor_config();
}

fn sil(text: &str) {
    let Ok(setup) = scenario_file::parse(text, "fuzz", None, "fuzz", 0) else {
        return;
    };
    // A refusal is fine; a panic while booting is not.
    let _ = FlightPipeline::new(&setup.flight);
}
