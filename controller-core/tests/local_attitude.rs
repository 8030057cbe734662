//! The envelope design's local attitude law in the controller (extension,
//! docs/envelope-design.md): the local regime flies its own attitude law, the global regime the
//! global one, and the switch measures the local law's energy in both.
//!
//! Checked against an independent controller: one whose *global* law is the local law and that
//! has no local law of its own. Its switch measures the same energy, so both switch at the same
//! samples; in the local regime both fly the same law, so their torques agree, and in the
//! global regime they differ (the global laws differ).

use controller_core::attitude_control::AttitudeGains;
use controller_core::{
    Controller, Gains, LocalAttitude, LocalGains, ReferenceSample, Regime, TiltPriorityGains,
    TrajectoryConstants, Vehicle, VehicleState,
};
use nalgebra::{UnitQuaternion, Vector3};

const DT: f64 = 0.002;

/// A stiffer, better damped law than the global one, with tilt priority.
fn stiff() -> LocalAttitude<f64> {
    LocalAttitude {
        attitude: AttitudeGains {
            k_mrp: 40.0,
            k_omega: 0.1,
            mrp_saturation: 0.3,
            omega_saturation: 0.2,
        },
        tilt_priority: Some(TiltPriorityGains {
            trace_weights: Vector3::new(0.01, 0.01, 0.4),
            omega_gains: Vector3::new(0.12, 0.12, 0.05),
            omega_levels: Vector3::new(0.3, 0.3, 0.05),
            turn_over: None,
        }),
    }
}

fn local(attitude: Option<LocalAttitude<f64>>) -> LocalGains<f64> {
    LocalGains {
        kp: 16.0,
        kv: 8.0,
        kf: 3.0,
        ks: 25.0,
        saturation: 2.0,
        energy_in: 2e-3,
        energy_out: 4e-3,
        vertical: None,
        attitude,
        braking: None,
    }
}

/// The attitude at sample `k`: a roll error that decays from 0.4 rad (outside the envelope) to
/// zero and a small oscillating rate, the same for both controllers.
fn state(k: usize) -> VehicleState<f64> {
    let t = k as f64 * DT;
    let roll = 0.4 * (-3.0 * t).exp() * (1.0 + 0.2 * (9.0 * t).sin());
    VehicleState {
        position: Vector3::new(0.05, -0.02, 0.01),
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::from_euler_angles(roll, 0.3 * roll, 0.0),
        angular_velocity: Vector3::new(-1.2 * roll, 0.2 * roll, 0.05 * roll),
    }
}

/// Given a controller with a local attitude law and one whose global law is that law, when
/// both fly the same samples, then they switch at the same samples, their torques agree
/// wherever the local regime flies and differ where the global one does, and both regimes are
/// flown.
#[test]
fn the_local_regime_flies_its_own_law_and_switches_on_its_energy() {
    let vehicle = Vehicle::paper();
    let g = Gains {
        local: Some(local(Some(stiff()))),
        ..Gains::paper()
    };
    let law = stiff();
    let independent = Gains {
        attitude: law.attitude,
        tilt_priority: law.tilt_priority,
        local: Some(local(None)),
        ..Gains::paper()
    };
    let constants = TrajectoryConstants::zero();
    let mut a = Controller::new(vehicle, g, &constants).unwrap();
    let mut b = Controller::new(vehicle, independent, &constants).unwrap();
    let reference = ReferenceSample::hold(Vector3::zeros(), 0.0);
    let (mut local_samples, mut global_samples) = (0, 0);
    for k in 0..2000 {
        let s = state(k);
        let (x, y) = (
            a.step(&s, &reference, DT).unwrap(),
            b.step(&s, &reference, DT).unwrap(),
        );
        assert_eq!(x.diagnostics.regime, y.diagnostics.regime, "sample {k}");
        assert_eq!(
            x.diagnostics.attitude_energy, y.diagnostics.attitude_energy,
            "sample {k}"
        );
        let gap = (x.torque - y.torque).norm();
        match x.diagnostics.regime {
            Regime::Local => {
                local_samples += 1;
                assert!(gap <= 1e-12, "sample {k}: {gap}");
            }
            Regime::Global => {
                global_samples += 1;
                assert!(gap > 1e-6, "sample {k}: the global laws differ, yet {gap}");
            }
        }
    }
    assert!(
        local_samples > 100 && global_samples > 10,
        "{local_samples} / {global_samples}"
    );
}
