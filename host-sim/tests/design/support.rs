//! The helpers the design tests share: a fresh output directory, the design's options, a
//! refusal check, and the written scenario's rotors and certificate as read back.

use std::path::PathBuf;

use controller_core::{certify, FilterStart, Trajectory};
use host_sim::design::options::LawSearch;
use host_sim::design::variables::AttitudeLaw;
use host_sim::design::{run_design, DesignOptions};
use host_sim::model::scenario::Scenario;
use host_sim::model::vehicle::{airframe, preset_path, VehicleFile};

/// The f32 torque set the firmware computes, from the f64 one.
pub fn f32_set(s: &controller_core::TorqueSet<f64>) -> controller_core::TorqueSet<f32> {
    host_sim::design::certificate::set_f32(s)
}

pub fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "host-sim-design-test-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

pub fn options(vehicle: PathBuf, out: PathBuf, evaluations: usize) -> DesignOptions {
    DesignOptions {
        vehicle,
        reference: None,
        seed: 3,
        margin: 0.05,
        fit: Default::default(),
        envelope: false,
        vertical: false,
        heading: host_sim::design::options::HeadingSearch::Paper,
        evaluations,
        duration_s: host_sim::design::options::DEFAULT_DURATION_S,
        law: LawSearch::One(AttitudeLaw::Paper),
        bounds: Default::default(),
        integral: None,
        thrust: host_sim::model::scenario::ThrustKind::Norm,
        position_saturation: Default::default(),
        lemma1: controller_core::Lemma1Form::DesiredFrame,
        speed_limit: None,
        fallback: host_sim::design::options::Fallback::Off,
        heading_held: None,
        out,
    }
}

/// The Crazyflie's design with one option set to `bad` by `set` is refused naming `flag`, and
/// writes nothing.
pub fn assert_refused_unwritten(flag: &str, bad: f64, set: impl Fn(&mut DesignOptions)) {
    let out = out_dir(&format!("bad{flag}"));
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    set(&mut o);
    let msg = format!("{:#}", run_design(&o).unwrap_err());
    assert!(msg.contains(flag), "{msg}");
    assert!(!out.exists(), "{bad}: wrote {}", out.display());
}

/// The rotor set of a scenario file, through the firmware's own conversion.
pub fn rotors_of(s: &Scenario) -> firmware::config::RotorConfig {
    let file = VehicleFile {
        vehicle: s.vehicle.clone(),
        rotors: s
            .rotors
            .clone()
            .expect("the design's scenario carries [rotors]"),
        drag: s.drag.clone(),
    };
    airframe(&file).rotors
}

/// The core's `certify` on a written scenario as read back.
pub fn read_back(s: &Scenario) -> controller_core::Certificate<f64> {
    certify(
        &s.vehicle::<f64>(),
        &s.limits::<f64>(),
        &s.gains::<f64>(),
        &s.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .unwrap()
}

/// [`read_back`]; panics unless every condition holds.
pub fn certified_read_back(s: &Scenario) -> controller_core::Certificate<f64> {
    let cert = read_back(s);
    assert!(
        cert.require_feasible().is_ok(),
        "{:?}",
        cert.require_feasible()
    );
    cert
}

/// A scenario file of this crate, by its path relative to the crate's root.
pub fn crate_scenario(relative: &str) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative);
    Scenario::load(&path).unwrap()
}

/// `s` with its motor time constant doubled (the constraint's doubled-lag runs).
pub fn doubled_lag(s: &Scenario) -> Scenario {
    let tau = s.rotors.as_ref().unwrap().motor_time_constant_s;
    host_sim::design::flight::with_motor_lag(s, 2.0 * tau, tau)
}

/// The constraint's check of a set of starts (`starts`, flown with the motor lag doubled):
/// the design in the fixture `fixture` passes the seven 180° starts with the lag doubled, which
/// is why the search called it feasible, yet fails some of `starts` (`what` names them in the
/// message); the committed Crazyflie design passes all of them.
pub fn starts_catch_the_fixture(
    fixture: &str,
    starts: fn(&Scenario, bool) -> anyhow::Result<Vec<host_sim::design::evaluate::Trial>>,
    what: &str,
) {
    let caught = doubled_lag(&crate_scenario(fixture));
    let half_turns = host_sim::design::evaluate::half_turns(&caught, false).unwrap();
    assert!(
        half_turns.iter().all(|t| t.converged),
        "the fixture passes the doubled-lag half turns, which is why it was called feasible"
    );
    let failed = starts(&caught, false)
        .unwrap()
        .into_iter()
        .filter(|t| !t.converged)
        .count();
    assert!(failed > 0, "the {what} miss the fixture's design");

    let committed = doubled_lag(&crate_scenario("designs/crazyflie-2.1/scenario.toml"));
    let failed: Vec<String> = starts(&committed, false)
        .unwrap()
        .into_iter()
        .filter(|t| !t.converged)
        .map(|t| t.start)
        .collect();
    assert!(failed.is_empty(), "committed design fails {failed:?}");
}
