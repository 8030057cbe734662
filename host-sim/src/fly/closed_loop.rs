//! The closed loop, one for every run: sample (measurement, noisy if the perturbations say
//! so) → command of any [`FlightController`] → optional clipping → disturbances → plant held
//! over the controller period: the ideal plant (RK4 rigid body, `(T, τ)` applied directly,
//! optional `(T, τ)` lag) or, with `simulation.plant = "rotors"`, the rotor-level plant of
//! [`crate::model::rotor_plant`] (the firmware's mixer, motor dynamics, body drag).
//!
//! [`fly_with`] is the loop itself; the caller steps its controller in it, so a caller that
//! knows the controller's type also sees its internals (the main run, [`crate::fly::sim`], reports
//! the paper law's diagnostics this way). [`fly`] is the loop for any controller with the
//! scenario's `[perturbations]` and a [`LoopSample`] of the errors at every sample, for
//! campaigns, comparisons and ablations.

use anyhow::{anyhow, bail, Result};
use controller_core::{Limits, Trajectory};
use nalgebra::Vector3;

use crate::fly::controllers::{Command, FlightController};
use crate::model::perturbation::{PerturbationConfig, Perturber};
use crate::model::plant::{PlantInput, RigidBodyState};
use crate::model::rotor_plant::{RotorPlant, RotorSample};
use crate::model::scenario::{PlantKind, Scenario};
use crate::model::so3::rotation_angle;

/// What the loop shows its observer at every controller sample.
#[derive(Clone, Copy, Debug)]
pub struct LoopSample<'a> {
    /// Sample index.
    pub k: u64,
    /// Time \[s\].
    pub t: f64,
    /// The true plant state (not the measurement).
    pub state: &'a RigidBodyState,
    /// Reference position \[m\], inertial.
    pub reference_position: Vector3<f64>,
    /// The controller's command (before clipping).
    pub command: &'a Command,
    /// `|p − p_d|` \[m\] (true state).
    pub position_error_m: f64,
    /// Angle of `R_dᵀR` \[rad\] (true attitude against the controller's own `R_d`), in `[0, π]`.
    pub attitude_error_rad: f64,
    /// With the rotor plant: the rotor thrusts at the sample and what the mixer makes of the
    /// command (after clipping); `None` with the ideal plant.
    pub rotors: Option<RotorSample>,
}

/// One controller sample of [`fly_with`], as the loop hands it to the control function.
#[derive(Clone, Copy, Debug)]
pub struct Step<'a> {
    /// Sample index `k` (time `k · controller_period_s`).
    pub k: u64,
    /// Time \[s\].
    pub t: f64,
    /// Controller period \[s\]: the command is held this long.
    pub dt: f64,
    /// The true plant state at the sample.
    pub state: &'a RigidBodyState,
    /// What the controller measures: the true state, plus noise if the perturbations say so.
    pub measured: &'a RigidBodyState,
    rotors: Option<&'a RotorPlant>,
    clip: Option<&'a Limits<f64>>,
}

impl Step<'_> {
    /// With the rotor plant, what it will make of `command` (clipped as the loop will clip it):
    /// the rotor thrusts now and the mixer's report; `None` with the ideal plant.
    pub fn rotors(&self, command: &Wrench) -> Option<RotorSample> {
        self.rotors.map(|p| {
            let applied = clipped(command, self.clip);
            p.sample(applied.thrust, &applied.torque)
        })
    }
}

/// The command the loop holds over a controller period (not clipped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wrench {
    /// Collective thrust \[N\] along body z.
    pub thrust: f64,
    /// Torque [N m], body frame.
    pub torque: Vector3<f64>,
}

/// Flies `scenario` from `initial` with `controller` for `simulation.duration_s`, drawing the
/// perturbations of the scenario's `[perturbations]` from `seed`, and calls `observe` at every
/// sample. Returns the final state.
///
/// Errors: the scenario's perturbations are invalid, or the controller refused a sample (with
/// the time and reason).
pub fn fly(
    scenario: &Scenario,
    controller: &mut dyn FlightController,
    initial: &RigidBodyState,
    seed: u64,
    mut observe: impl FnMut(&LoopSample<'_>),
) -> Result<RigidBodyState> {
    let trajectory = scenario.trajectory::<f64>();
    fly_with(scenario, &scenario.perturbations, initial, seed, |step| {
        let command = controller.step(step.measured, step.t, step.dt)?;
        let wrench = Wrench {
            thrust: command.thrust,
            torque: command.torque,
        };
        let state = step.state;
        let reference = trajectory.sample(step.t);
        let rotation = state.attitude.to_rotation_matrix().into_inner();
        observe(&LoopSample {
            k: step.k,
            t: step.t,
            state,
            reference_position: reference.position,
            command: &command,
            position_error_m: (state.position - reference.position).norm(),
            attitude_error_rad: rotation_angle(&(command.desired_rotation.transpose() * rotation)),
            rotors: step.rotors(&wrench),
        });
        Ok(wrench)
    })
}

/// The command the plant receives: `command` clipped to `limits` (`T ∈ [0, T_max]`,
/// `|τ_i| ≤ τ_max,i`) when given.
fn clipped(command: &Wrench, limits: Option<&Limits<f64>>) -> Wrench {
    match limits {
        None => *command,
        Some(l) => Wrench {
            thrust: command.thrust.clamp(0.0, l.thrust_max),
            torque: command.torque.zip_map(&l.torque_max, |t, m| t.clamp(-m, m)),
        },
    }
}

/// The plant a run flies, built from the scenario's `simulation.plant`.
#[derive(Clone, Debug)]
pub enum PlantModel {
    /// `(T, τ)` applied to the rigid body (with the perturbations' `(T, τ)` lag if any).
    Ideal,
    /// The rotor-level plant.
    Rotors(Box<RotorPlant>),
}

impl PlantModel {
    /// The plant of `scenario` under `perturbations`: with `plant = "rotors"`, the scenario's
    /// rotors, its motor time constant replaced by `perturbations.motor_time_constant_s` when
    /// that is > 0.
    ///
    /// Errors: `plant = "rotors"` without a `[rotors]` table; rotors the mixer refuses.
    pub fn of(scenario: &Scenario, perturbations: &PerturbationConfig) -> Result<Self> {
        match scenario.simulation.plant {
            PlantKind::Ideal => Ok(Self::Ideal),
            PlantKind::Rotors => {
                let Some(mut p) = scenario.rotor_config() else {
                    bail!("plant = rotors needs a [rotors] table (or --vehicle FILE)");
                };
                if perturbations.motor_time_constant_s > 0.0 {
                    p.motor_time_constant_s = perturbations.motor_time_constant_s;
                }
                Ok(Self::Rotors(Box::new(RotorPlant::from_parameters(&p)?)))
            }
        }
    }
}

/// The loop: flies `scenario` (its vehicle, limits, `[simulation]` and plant, see
/// [`PlantModel::of`]) from `initial` with the given `perturbations` (drawn from `seed`; with
/// none, the measurement is the true state and no random number is drawn): every
/// `controller_period_s` it asks `control` for the wrench of the sample (the controller's step,
/// and whatever the caller observes), holds it (clipped to the limits if
/// `simulation.clip_to_limits`) over the period while the plant advances, and returns the plant
/// state at the last sample.
///
/// Errors: `perturbations` are invalid, the plant cannot be built (`plant = "rotors"` without
/// rotors), or `control`'s error (a refused sample).
pub fn fly_with(
    scenario: &Scenario,
    perturbations: &PerturbationConfig,
    initial: &RigidBodyState,
    seed: u64,
    control: impl FnMut(&Step<'_>) -> Result<Wrench>,
) -> Result<RigidBodyState> {
    perturbations.validate().map_err(|e| anyhow!("{e}"))?;
    let plant = PlantModel::of(scenario, perturbations)?;
    fly_on(scenario, plant, perturbations, initial, seed, control)
}

/// [`fly_with`] on a given plant (`plant` replaces the scenario's `simulation.plant`; a
/// [`PlantModel::Rotors`] plant takes no motor time constant from `perturbations`, the
/// [`PlantModel::Ideal`] plant the `(T, τ)` lag).
///
/// Errors: `perturbations` are invalid, or `control`'s error (a refused sample).
pub fn fly_on(
    scenario: &Scenario,
    mut plant: PlantModel,
    perturbations: &PerturbationConfig,
    initial: &RigidBodyState,
    seed: u64,
    mut control: impl FnMut(&Step<'_>) -> Result<Wrench>,
) -> Result<RigidBodyState> {
    perturbations.validate().map_err(|e| anyhow!("{e}"))?;
    let sim = &scenario.simulation;
    let limits = scenario.limits::<f64>();
    let clip = sim.clip_to_limits.then_some(&limits);
    let mut perturber = Perturber::new(perturbations, seed);
    let body = perturber.plant(&scenario.plant());
    // Without perturbations the perturber's measurement, disturbances and actuator are the
    // identity (the same numbers, no random draw); skipping them keeps nominal runs as fast as
    // a loop without perturbations.
    let nominal = perturbations.is_nominal();
    let dt = sim.controller_period_s;
    let steps = (sim.duration_s / dt).round() as u64;
    let mut state = *initial;
    let mut noisy;
    for k in 0..=steps {
        let t = k as f64 * dt;
        let measured = if nominal {
            &state
        } else {
            noisy = perturber.measure(&state);
            &noisy
        };
        let command = control(&Step {
            k,
            t,
            dt,
            state: &state,
            measured,
            rotors: match &plant {
                PlantModel::Ideal => None,
                PlantModel::Rotors(r) => Some(r),
            },
            clip,
        })?;
        if k == steps {
            break;
        }
        let applied = clipped(&command, clip);
        let mut input = PlantInput {
            thrust: applied.thrust,
            torque: applied.torque,
            ..Default::default()
        };
        if !nominal {
            perturber.disturb(&mut input, dt);
        }
        state = match &mut plant {
            PlantModel::Ideal if nominal => body.advance(&state, &input, dt, sim.plant_step_s),
            PlantModel::Ideal => perturber.advance(&body, &state, &input, dt, sim.plant_step_s),
            PlantModel::Rotors(r) => r.advance(&body, &state, &input, dt, sim.plant_step_s).0,
        };
    }
    Ok(state)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::controllers::paper::PaperLaw;

    /// With the paper's law and no perturbation, [`fly`] (the campaigns' view of the loop)
    /// gives the commands and states of `sim::run` (the main run's) bit for bit.
    #[test]
    fn nominal_paper_loop_matches_sim_run() {
        let mut scenario = Scenario::paper();
        scenario.simulation.duration_s = 6.0;
        let (_, records) = crate::fly::sim::run(&scenario).unwrap();
        let mut law = PaperLaw::<f32>::new(&scenario).unwrap();
        let mut k = 0;
        fly(&scenario, &mut law, &scenario.initial_state(), 99, |s| {
            let r = &records[s.k as usize];
            assert_eq!(s.command.thrust, r.thrust_N, "thrust at t = {}", s.t);
            assert_eq!(s.command.torque.x, r.torque_x_Nm);
            assert_eq!(s.command.torque.z, r.torque_z_Nm);
            assert_eq!(s.state.position.x, r.x_m);
            k += 1;
        })
        .unwrap();
        assert_eq!(k, records.len());
    }

    fn paper_rotors(tau: f64) -> PlantModel {
        let rotors = firmware::config::FlightConfig::paper().rotors;
        PlantModel::Rotors(Box::new(RotorPlant::new(&rotors, tau, [0.0; 3]).unwrap()))
    }

    /// Flies the paper law on `plant`, returning the final state and every sample's rotor
    /// report.
    fn fly_paper(
        scenario: &Scenario,
        plant: PlantModel,
    ) -> (RigidBodyState, Vec<Option<RotorSample>>) {
        let mut law = PaperLaw::<f32>::new(scenario).unwrap();
        let mut rotors = Vec::new();
        let end = fly_on(
            scenario,
            plant,
            &scenario.perturbations,
            &scenario.initial_state(),
            0,
            |step| {
                let c = law.step(step.measured, step.t, step.dt)?;
                let w = Wrench {
                    thrust: c.thrust,
                    torque: c.torque,
                };
                rotors.push(step.rotors(&w));
                Ok(w)
            },
        )
        .unwrap();
        (end, rotors)
    }

    /// Near hover, where every command fits the rotors, the rotor plant without motor lag flies
    /// the ideal plant's run up to the mixer's f32 rounding; with lag it departs from it; the
    /// upside-down start of the paper makes the mixer give something up.
    #[test]
    fn rotor_plant_in_the_loop() {
        let mut s = Scenario::paper();
        s.simulation.duration_s = 3.0;
        s.initial.position_m = [-2.0, 1.0, 5.5];
        s.initial.euler_deg = [5.0, 0.0, 0.0];
        let (ideal, none) = fly_paper(&s, PlantModel::Ideal);
        assert!(none.iter().all(Option::is_none));
        let (fast, reports) = fly_paper(&s, paper_rotors(0.0));
        assert!(reports.iter().all(|r| r.is_some_and(|r| !r.mix.gave_up)));
        assert!((fast.position - ideal.position).norm() < 1e-4);
        let (slow, _) = fly_paper(&s, paper_rotors(0.05));
        assert!((slow.position - ideal.position).norm() > 1e-3);

        // Rotors of 1.3 N (5.2 N in all, hover 4.5 N): the paper's recovery from upside down
        // asks for more collective than that, which the mixer gives up.
        let mut weak = firmware::config::FlightConfig::paper().rotors;
        weak.thrust_max = 1.3;
        let weak = PlantModel::Rotors(Box::new(RotorPlant::new(&weak, 0.0, [0.0; 3]).unwrap()));
        let mut flipped = Scenario::paper();
        flipped.simulation.duration_s = 3.0;
        let (_, reports) = fly_paper(&flipped, weak);
        let given_up: Vec<_> = reports.iter().flatten().filter(|r| r.mix.gave_up).collect();
        assert!(!given_up.is_empty());
        assert!(given_up
            .iter()
            .all(|r| r.mix.thrust_given_up_N > 0.0 || r.mix.torque_given_up_Nm > 0.0));
        // The rotors never leave their range, whatever the command.
        assert!(reports
            .iter()
            .flatten()
            .all(|r| r.rotor_thrust_N.iter().all(|f| (0.0..=1.3).contains(f))));
    }

    /// `plant = "rotors"` without rotors is refused, naming what is missing.
    #[test]
    fn rotors_without_a_rotor_table_are_refused() {
        let mut s = Scenario::paper();
        s.simulation.plant = PlantKind::Rotors;
        assert!(s.rotors.is_none());
        let e = fly_with(&s, &s.perturbations, &s.initial_state(), 0, |_| {
            Ok(Wrench {
                thrust: 0.0,
                torque: Vector3::zeros(),
            })
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("plant = rotors needs a [rotors] table"), "{e}");
        assert!(s.validate().unwrap_err().contains("simulation.plant"));
    }
}
