//! The main run: the paper's law (controller-core, f32 or f64) in the closed loop
//! ([`crate::fly::closed_loop`]) at its sampling rate, a zero-order hold and the RK4 rigid-body
//! plant, with the law's diagnostics in every [`Record`] and the [`Summary`].

use anyhow::{anyhow, Result};
use controller_core::scalar::{to_f64, Scalar};
use controller_core::{ControlOutput, ReferenceSample, Trajectory};
use nalgebra::Vector3;
use serde::Serialize;

mod summary;
use summary::a_priori;
pub use summary::{
    APriori, ConditionReport, Final, IntegralReport, Observed, PathLiftingReport, Settling, Summary,
};

pub use crate::bounds::certificate::scenario_certificate as certificate;
use crate::bounds::certificate::{tight_limits, tight_report};
use crate::fly::closed_loop::{self, Wrench};
use crate::fly::controllers::paper::{back3, PaperLaw};
pub use crate::fly::setup::FlightSetup;
use crate::model::plant::RigidBodyState;
use crate::model::rotor_plant::{MixerCounts, RotorSample};
use crate::model::scenario::{PlantKind, Precision, Scenario};

/// One controller sample: the state, the reference, the command and the law's internals.
/// Column names carry units; angles are in rad unless named `_deg`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct Record {
    /// Time \[s\].
    pub t_s: f64,
    /// Position \[m\], inertial.
    pub x_m: f64,
    /// Position y \[m\].
    pub y_m: f64,
    /// Position z \[m\].
    pub z_m: f64,
    /// Reference position x \[m\].
    pub x_ref_m: f64,
    /// Reference position y \[m\].
    pub y_ref_m: f64,
    /// Reference position z \[m\].
    pub z_ref_m: f64,
    /// Roll \[rad\] (`R = Rz(yaw) Ry(pitch) Rx(roll)`).
    pub roll_rad: f64,
    /// Pitch \[rad\].
    pub pitch_rad: f64,
    /// Yaw \[rad\].
    pub yaw_rad: f64,
    /// Desired yaw `ψ_d` \[rad\].
    pub yaw_ref_rad: f64,
    /// `|p − p_d|` \[m\].
    pub position_error_m: f64,
    /// `|ϑ̃|` (dimensionless).
    pub mrp_error: f64,
    /// `|ω̃|` [rad/s].
    pub angular_velocity_error_rad_s: f64,
    /// Thrust command \[N\].
    pub thrust_N: f64,
    /// Torque command x [N m], body.
    pub torque_x_Nm: f64,
    /// Torque command y [N m], body.
    pub torque_y_Nm: f64,
    /// Torque command z [N m], body.
    pub torque_z_Nm: f64,
    /// `|ubar_p|` [m/s²].
    pub ubar_p_norm_m_s2: f64,
    /// `|u_f|` [m/s²].
    pub u_f_norm_m_s2: f64,
    /// `|u_s|` [m/s²].
    pub u_s_norm_m_s2: f64,
    /// `|s_ϑ(k_ϑ ϑ̃)|` [N m].
    pub s_theta_norm_Nm: f64,
    /// `|s_ω(k_ω ω̃)|` [N m].
    pub s_omega_norm_Nm: f64,
    /// `|ω_d|` [rad/s].
    pub omega_d_norm_rad_s: f64,
    /// `|ω̇_d|` [rad/s²].
    pub omega_d_dot_norm_rad_s2: f64,
    /// Memory-quaternion resets so far.
    pub q_hat_resets: u32,
    /// MRP sign flips so far.
    pub m_flips: u32,
    /// Rotor plant only (the columns are absent with the ideal plant): rotor 1 thrust at the
    /// sample \[N\] (motor order of the vehicle's `[rotors]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_1_thrust_N: Option<f64>,
    /// Rotor plant only: rotor 2 thrust \[N\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_2_thrust_N: Option<f64>,
    /// Rotor plant only: rotor 3 thrust \[N\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_3_thrust_N: Option<f64>,
    /// Rotor plant only: rotor 4 thrust \[N\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_4_thrust_N: Option<f64>,
    /// Rotor plant only: collective thrust the mixer achieves for the command \[N\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer_thrust_N: Option<f64>,
    /// Rotor plant only: thrust the mixer gave up \[N\] (0 when the command fits the rotors).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer_thrust_given_up_N: Option<f64>,
    /// Rotor plant only: largest per-axis torque the mixer gave up [N m].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer_torque_given_up_Nm: Option<f64>,
}

/// Tracks "below threshold from time t on".
#[derive(Clone, Copy, Debug)]
struct SettleTracker {
    threshold: f64,
    since: Option<f64>,
}

impl SettleTracker {
    fn new(threshold: f64) -> Self {
        Self {
            threshold,
            since: None,
        }
    }
    fn push(&mut self, t: f64, value: f64) {
        if value < self.threshold {
            self.since.get_or_insert(t);
        } else {
            self.since = None;
        }
    }
}

/// Runs the scenario, calling `observe` with every sample's [`Record`], and returns the summary.
///
/// Errors: invalid parameters (named by scenario key), or a controller step refused (with the
/// time and the reason).
pub fn run_with(scenario: &Scenario, observe: impl FnMut(&Record)) -> Result<Summary> {
    run_set_up_with(scenario, &FlightSetup::new(scenario)?, observe)
}

/// [`run_with`] on a set-up already built from `scenario` ([`FlightSetup::new`]): what the
/// run checks its samples against is computed once, by the caller.
///
/// Errors: a controller step refused (with the time and the reason), or the scenario's thrust
/// interval is empty.
pub fn run_set_up_with(
    scenario: &Scenario,
    setup: &FlightSetup,
    mut observe: impl FnMut(&Record),
) -> Result<Summary> {
    match scenario.simulation.precision {
        Precision::F32 => run_generic::<f32>(scenario, setup, Some(&mut observe)),
        Precision::F64 => run_generic::<f64>(scenario, setup, Some(&mut observe)),
    }
}

/// Runs the scenario for its [`Summary`] only (the one [`run_with`] returns, bit for bit),
/// without building a [`Record`] per sample: the run without output files.
///
/// Errors: as [`run_with`].
pub fn run_summary(scenario: &Scenario) -> Result<Summary> {
    let setup = FlightSetup::new(scenario)?;
    match scenario.simulation.precision {
        Precision::F32 => run_generic::<f32>(scenario, &setup, None),
        Precision::F64 => run_generic::<f64>(scenario, &setup, None),
    }
}

/// Runs the scenario and keeps every sample.
///
/// Errors: as [`run_with`].
pub fn run(scenario: &Scenario) -> Result<(Summary, Vec<Record>)> {
    run_set_up(scenario, &FlightSetup::new(scenario)?)
}

/// [`run`] on a set-up already built from `scenario` ([`FlightSetup::new`]).
///
/// Errors: as [`run_set_up_with`].
pub fn run_set_up(scenario: &Scenario, setup: &FlightSetup) -> Result<(Summary, Vec<Record>)> {
    let mut records = Vec::with_capacity(
        (scenario.simulation.duration_s / scenario.simulation.controller_period_s) as usize + 1,
    );
    let summary = run_set_up_with(scenario, setup, |r| records.push(r.clone()))?;
    Ok((summary, records))
}

/// One controller sample of [`fly`].
pub struct Sample<'a, T: Scalar> {
    /// Sample index `k` (time `k · controller_period_s`).
    pub k: u64,
    /// Time \[s\].
    pub t: f64,
    /// The true plant state at the sample (the controller measured it exactly unless the
    /// scenario has measurement noise).
    pub state: &'a RigidBodyState,
    /// The reference sample the controller used.
    pub reference: &'a ReferenceSample<T>,
    /// The controller's output (before any clipping).
    pub output: &'a ControlOutput<T>,
    /// With the rotor plant, the rotor thrusts at the sample and the mixer's report on the
    /// command; `None` with the ideal plant.
    pub rotors: Option<RotorSample>,
}

/// Flies `scenario` from `initial` with the paper's law in scalar `T` through the one closed
/// loop ([`crate::fly::closed_loop::fly_with`]) with the scenario's `[perturbations]`, every key
/// applied (drawn from `simulation.seed`; with none the controller measures the true state):
/// sample the state every `controller_period_s`, step the controller, hold `(T, τ)` (clipped to
/// the limits if `simulation.clip_to_limits`), advance the RK4 plant; calls `observe` at every
/// sample with the true state, the law's reference and whole output, and returns the plant
/// state at the last one.
///
/// Errors: the parameters or the perturbations are refused (named by scenario key), or the
/// controller refused a sample (with its time and reason).
pub fn fly<T: Scalar>(
    scenario: &Scenario,
    initial: RigidBodyState,
    mut observe: impl FnMut(&Sample<'_, T>),
) -> Result<RigidBodyState> {
    let mut law = PaperLaw::<T>::new(scenario)?;
    closed_loop::fly_with(
        scenario,
        &scenario.perturbations,
        &initial,
        scenario.simulation.seed,
        |step| {
            let (reference, output) = law.sample(step.measured, step.t, step.dt)?;
            let wrench = Wrench {
                thrust: to_f64(output.thrust),
                torque: back3(&output.torque),
            };
            observe(&Sample {
                k: step.k,
                t: step.t,
                state: step.state,
                reference: &reference,
                output: &output,
                rotors: step.rotors(&wrench),
            });
            Ok(wrench)
        },
    )
}

/// What the summary keeps of the last sample.
#[derive(Clone, Copy)]
struct LastSample {
    t: f64,
    position_error: f64,
    mrp_error: f64,
    omega_error: f64,
    q_hat_resets: u32,
    m_flips: u32,
}

/// The main run; with `observe`, builds and shows every sample's [`Record`] (the summary does
/// not depend on it).
fn run_generic<T: Scalar>(
    scenario: &Scenario,
    setup: &FlightSetup,
    mut observe: Option<&mut dyn FnMut(&Record)>,
) -> Result<Summary> {
    let (cert, tight) = (&setup.certificate, &setup.tight);
    let tight_limits = tight_limits(tight);
    let [thrust_low, thrust_high] = scenario.thrust_interval(cert).map_err(|e| anyhow!("{e}"))?;
    // Rounding slack for the bound checks: f32 carries ~1e-7 relative error.
    let slack = 1e-5;
    // Theorem 2's per-axis bounds, or with the envelope design each the larger of them and the
    // local regime's (bit for bit Theorem 2's without it).
    let torque_max = cert.torque_max_all();

    let mut observed = Observed {
        thrust_min_N: f64::INFINITY,
        thrust_max_N: f64::NEG_INFINITY,
        torque_abs_max_Nm: [0.0; 3],
        angular_velocity_d_max_rad_s: 0.0,
        angular_acceleration_d_max_rad_s2: 0.0,
        samples_outside_a_priori_bounds: 0,
        samples_above_tight_bounds: 0,
        samples: 0,
        altitude_loss_m: 0.0,
    };
    let initial_altitude = scenario.initial_state().position.z;
    let mut settle_p = SettleTracker::new(1e-3);
    let mut settle_m = SettleTracker::new(1e-4);
    let mut last = None;
    let mut mixer = MixerCounts::default();

    fly::<T>(scenario, scenario.initial_state(), |sample| {
        let (t, state, d) = (sample.t, sample.state, &sample.output.diagnostics);
        let thrust = to_f64(sample.output.thrust);
        let torque = back3(&sample.output.torque);

        observed.samples += 1;
        observed.thrust_min_N = observed.thrust_min_N.min(thrust);
        observed.thrust_max_N = observed.thrust_max_N.max(thrust);
        for i in 0..3 {
            observed.torque_abs_max_Nm[i] = observed.torque_abs_max_Nm[i].max(torque[i].abs());
        }
        let w_d = back3(&d.desired_angular_velocity).norm();
        let w_d_dot = back3(&d.desired_angular_acceleration).norm();
        observed.angular_velocity_d_max_rad_s = observed.angular_velocity_d_max_rad_s.max(w_d);
        observed.angular_acceleration_d_max_rad_s2 =
            observed.angular_acceleration_d_max_rad_s2.max(w_d_dot);
        let outside = thrust < thrust_low * (1.0 - slack)
            || thrust > thrust_high * (1.0 + slack)
            || (0..3).any(|i| torque[i].abs() > torque_max[i] * (1.0 + slack));
        observed.samples_outside_a_priori_bounds += u64::from(outside);
        observed.samples_above_tight_bounds +=
            u64::from(tight_limits.exceeded(&torque, w_d, w_d_dot, slack));
        observed.altitude_loss_m = observed
            .altitude_loss_m
            .max(initial_altitude - state.position.z);

        let reference_f64 = trajectory_sample_f64(sample.reference);
        let position_error = (state.position - reference_f64.0).norm();
        let mrp_error = back3(&d.mrp_error).norm();
        let omega_error = back3(&d.omega_error).norm();
        settle_p.push(t, position_error);
        settle_m.push(t, mrp_error);
        last = Some(LastSample {
            t,
            position_error,
            mrp_error,
            omega_error,
            q_hat_resets: d.jumps_total.q_hat_resets,
            m_flips: d.jumps_total.m_flips,
        });
        if let Some(r) = &sample.rotors {
            mixer.push(&r.mix);
        }
        let Some(observe) = observe.as_mut() else {
            return;
        };
        let (roll, pitch, yaw) = state.attitude.euler_angles();
        let mut record = Record {
            t_s: t,
            x_m: state.position.x,
            y_m: state.position.y,
            z_m: state.position.z,
            x_ref_m: reference_f64.0.x,
            y_ref_m: reference_f64.0.y,
            z_ref_m: reference_f64.0.z,
            roll_rad: roll,
            pitch_rad: pitch,
            yaw_rad: yaw,
            yaw_ref_rad: reference_f64.1,
            position_error_m: position_error,
            mrp_error,
            angular_velocity_error_rad_s: omega_error,
            thrust_N: thrust,
            torque_x_Nm: torque.x,
            torque_y_Nm: torque.y,
            torque_z_Nm: torque.z,
            ubar_p_norm_m_s2: back3(&d.ubar_p).norm(),
            u_f_norm_m_s2: back3(&d.u_f).norm(),
            u_s_norm_m_s2: back3(&d.u_s).norm(),
            s_theta_norm_Nm: back3(&d.s_mrp).norm(),
            s_omega_norm_Nm: back3(&d.s_omega).norm(),
            omega_d_norm_rad_s: w_d,
            omega_d_dot_norm_rad_s2: w_d_dot,
            q_hat_resets: d.jumps_total.q_hat_resets,
            m_flips: d.jumps_total.m_flips,
            ..Record::default()
        };
        if let Some(r) = &sample.rotors {
            let f = r.rotor_thrust_N;
            record.rotor_1_thrust_N = Some(f[0]);
            record.rotor_2_thrust_N = Some(f[1]);
            record.rotor_3_thrust_N = Some(f[2]);
            record.rotor_4_thrust_N = Some(f[3]);
            record.mixer_thrust_N = Some(r.mix.achieved_thrust_N);
            record.mixer_thrust_given_up_N = Some(r.mix.thrust_given_up_N);
            record.mixer_torque_given_up_Nm = Some(r.mix.torque_given_up_Nm);
        }
        observe(&record);
    })?;

    let last = last.ok_or_else(|| anyhow!("the run produced no sample"))?;
    Ok(Summary {
        precision: scenario.simulation.precision,
        a_priori: a_priori(
            cert,
            &scenario.gains(),
            &scenario.trajectory::<f64>().constants(),
            (!scenario.controller.is_paper()).then_some([thrust_low, thrust_high]),
            tight_report(cert, tight),
        ),
        observed,
        final_: Final {
            time_s: last.t,
            position_error_m: last.position_error,
            mrp_error: last.mrp_error,
            angular_velocity_error_rad_s: last.omega_error,
        },
        path_lifting: PathLiftingReport {
            q_hat_resets: last.q_hat_resets,
            m_flips: last.m_flips,
        },
        settling: Settling {
            position_error_below_1mm_from_s: settle_p.since,
            mrp_error_below_1e_4_from_s: settle_m.since,
        },
        mixer: (scenario.simulation.plant == PlantKind::Rotors).then_some(mixer),
    })
}

/// Reference position \[m\] and yaw \[rad\] as f64.
fn trajectory_sample_f64<T: Scalar>(
    s: &controller_core::ReferenceSample<T>,
) -> (Vector3<f64>, f64) {
    (back3(&s.position), to_f64(s.yaw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The summary-only run gives the summary of the run with records, bit for bit (Debug
    /// prints every float in full), in both precisions, and with the rotor plant's mixer
    /// counts.
    #[test]
    fn summary_only_run_matches_the_recorded_run() {
        let paper_rotors =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("vehicles/paper.toml");
        let rotors = Scenario::paper()
            .with_plant_overrides(Some(&paper_rotors), Some(PlantKind::Rotors), None)
            .unwrap();
        for mut s in [Scenario::paper(), rotors] {
            s.simulation.duration_s = 4.0;
            for precision in [Precision::F32, Precision::F64] {
                s.simulation.precision = precision;
                let mut samples = 0;
                let recorded = run_with(&s, |_| samples += 1).unwrap();
                let summary = run_summary(&s).unwrap();
                assert_eq!(samples, 401);
                assert_eq!(format!("{summary:?}"), format!("{recorded:?}"));
            }
        }
    }
}
