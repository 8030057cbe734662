//! The main run applies every key of a scenario file's `[perturbations]` table: motor lag,
//! measurement noise (drawn from `simulation.seed`), model errors and disturbances change the
//! flight; without the table the run is the paper's nominal one. The same on the rotor plant
//! (`plant = "rotors"`), where `motor_time_constant_s` replaces the vehicle's own.

use std::sync::atomic::{AtomicUsize, Ordering};

use host_sim::fly::sim::{run, Record};
use host_sim::model::scenario::{Scenario, PAPER_SCENARIO};

/// The paper scenario from a file with `extra` appended, shortened to 3 s.
fn from_file(extra: &str) -> Scenario {
    // Tests run in parallel threads: one file name per call.
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let path = std::env::temp_dir().join(format!(
        "host-sim-perturbations-{}-{}.toml",
        std::process::id(),
        CALLS.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::write(&path, format!("{PAPER_SCENARIO}\n{extra}\n")).unwrap();
    let mut s = Scenario::load(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    s.simulation.duration_s = 3.0;
    s
}

fn records(s: &Scenario) -> Vec<Record> {
    let (_, records) = run(s).unwrap();
    assert!(records
        .iter()
        .all(|r| r.thrust_N.is_finite() && r.z_m.is_finite()));
    records
}

#[test]
fn motor_lag_changes_the_main_run() {
    let nominal = records(&from_file(""));
    let zero = records(&from_file("[perturbations]\nmotor_time_constant_s = 0.0"));
    assert_eq!(nominal, zero, "a zero lag is the nominal run");
    let slow = records(&from_file("[perturbations]\nmotor_time_constant_s = 0.05"));
    let fast = records(&from_file("[perturbations]\nmotor_time_constant_s = 0.02"));
    // The first sample is taken before any lag has acted; every later one sees it.
    assert_eq!(nominal[0].x_m, slow[0].x_m);
    assert_ne!(nominal[100], slow[100]);
    assert_ne!(fast[100], slow[100]);
}

#[test]
fn measurement_noise_follows_the_seed() {
    let noisy = "[perturbations]\nposition_noise_std_m = 0.01";
    let a = records(&from_file(noisy));
    let again = records(&from_file(noisy));
    let mut other = from_file(noisy);
    other.simulation.seed = 7;
    let b = records(&other);
    assert_eq!(a, again, "same seed, same run");
    assert_ne!(a, b, "another seed, other noise");
    assert_ne!(a, records(&from_file("")));
}

#[test]
fn model_errors_and_disturbances_change_the_main_run() {
    let nominal = records(&from_file(""));
    for table in [
        "mass_error_max_fraction = 0.2",
        "force_disturbance_N = [0.0, 0.0, -0.5]",
        "torque_disturbance_Nm = [0.01, 0.0, 0.0]",
        "gust_force_std_N = 0.2\ngust_time_constant_s = 0.5",
    ] {
        let perturbed = records(&from_file(&format!("[perturbations]\n{table}")));
        assert_ne!(nominal, perturbed, "{table}");
    }
}

/// The paper scenario of [`from_file`] flown on the rotor plant with the paper vehicle file's
/// rotors (`[perturbations]` from `extra`).
fn on_rotors(extra: &str) -> Scenario {
    let vehicle =
        host_sim::model::vehicle::load(&host_sim::model::vehicle::preset_path("paper")).unwrap();
    let mut s = from_file(extra).with_vehicle(&vehicle);
    s.simulation.plant = host_sim::model::scenario::PlantKind::Rotors;
    s.validate().unwrap();
    s
}

#[test]
fn rotor_plant_changes_the_main_run_and_its_motor_lag_applies() {
    let ideal = records(&from_file(""));
    let rotors = records(&on_rotors(""));
    assert!(rotors.iter().all(|r| r.rotor_1_thrust_N.is_some()));
    assert!(ideal.iter().all(|r| r.rotor_1_thrust_N.is_none()));
    // The first sample is the same state; the rotor plant's motors change what follows.
    assert_eq!(ideal[0].x_m, rotors[0].x_m);
    let differs = |a: &[Record], b: &[Record]| a.iter().zip(b).any(|(a, b)| a.z_m != b.z_m);
    assert!(differs(&ideal, &rotors));
    let zero = records(&on_rotors("[perturbations]\nmotor_time_constant_s = 0.0"));
    assert_eq!(
        rotors, zero,
        "0 keeps the vehicle's own motor time constant"
    );
    let slow = records(&on_rotors("[perturbations]\nmotor_time_constant_s = 0.05"));
    assert!(differs(&rotors, &slow));
    assert_ne!(rotors[100], slow[100]);
}

#[test]
fn every_perturbation_key_applies_on_the_rotor_plant() {
    let nominal = records(&on_rotors(""));
    for table in [
        "position_noise_std_m = 0.01",
        "mass_error_max_fraction = 0.2",
        "force_disturbance_N = [0.0, 0.0, -0.5]",
        "torque_disturbance_Nm = [0.01, 0.0, 0.0]",
        "gust_force_std_N = 0.2\ngust_time_constant_s = 0.5",
    ] {
        let perturbed = records(&on_rotors(&format!("[perturbations]\n{table}")));
        assert_ne!(nominal, perturbed, "{table}");
    }
}
