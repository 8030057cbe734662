//! What one software-in-the-loop run flies: the firmware's configuration, the sensor and motor
//! models, the start, the ground-station script. The scenarios build it; [`super::run`] flies it.

use controller_core::Bounds;
use firmware::config::FlightConfig;
use firmware::control_rate::ControlRate;
use firmware::link::mavlink::dialects::common::MavMessage;
use firmware::pipeline::FlightPipeline;

use super::sensors::{ImuModel, MocapModel};
use crate::model::plant::RigidBodyState;

/// One software-in-the-loop run.
#[derive(Clone, Debug)]
pub struct SilSetup {
    /// Name (output directory, summary).
    pub name: String,
    /// The firmware's configuration.
    pub flight: FlightConfig,
    /// IMU model.
    pub imu: ImuModel,
    /// Motion-capture model.
    pub mocap: MocapModel,
    /// Motor time constant \[s\] (first-order lag of each rotor's thrust).
    pub motor_time_constant_s: f64,
    /// The plant's mass over the flight configuration's (dimensionless; 1: the firmware's model
    /// is exact): a payload, another battery, a thrust coefficient known only roughly. Only the
    /// simulated body changes; the firmware flies its configured mass.
    pub plant_mass_factor: f64,
    /// The body's state while held and at release.
    pub initial: RigidBodyState,
    /// Time held still (on a stand, in a hand, on the ground) before release \[s\]; the gyro
    /// calibrates and the estimator converges meanwhile.
    pub hold_s: f64,
    /// Time simulated after release \[s\].
    pub duration_s: f64,
    /// Ground-station messages: (time after release \[s\], message). Negative times fall in the
    /// hold.
    pub commands: Vec<(f64, MavMessage)>,
    /// Scripted pose outage `[start, end)` after release \[s\]: no pose is sent.
    pub pose_outage: Option<(f64, f64)>,
    /// Random seed (noise, dropouts, chunking).
    pub seed: u64,
    /// Height of a flat ground \[m\] (z up), `None` for none (the paper's scenario falls about
    /// 23 m during its recovery, as in the paper).
    pub ground_z: Option<f64>,
}

impl SilSetup {
    /// Flies the law at `hz` \[Hz\] instead of the flight's rate (the command lines'
    /// `--rate-hz`). Errors: `hz` is not 100, 250, 500 or 1000.
    pub fn set_control_rate_hz(&mut self, hz: f64) -> anyhow::Result<()> {
        self.flight.control_rate = ControlRate::from_hz(hz).map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(())
    }

    /// The a-priori bounds of the certificate the firmware computes at boot for this set-up's
    /// flight configuration and demo mission: `T ∈ [T_min, T_max]` \[N\] (Theorem 1), per-axis
    /// torque bound \[N m\] (Theorem 2), Lemma 1's rates.
    ///
    /// Errors: the firmware refuses the configuration (its boot error, with the parameter).
    pub fn a_priori_bounds(&self) -> anyhow::Result<Bounds<f32>> {
        let pipeline = FlightPipeline::new(&self.flight)
            .map_err(|e| anyhow::anyhow!("the firmware refuses this configuration: {e:?}"))?;
        Ok(pipeline.boot_report().certificate.bounds)
    }
}
