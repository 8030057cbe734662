//! Scenario files (TOML): vehicle, limits, gains, trajectory, initial state, simulation settings.
//!
//! A scenario file is a vehicle file (`[vehicle]`, and optionally `[rotors]` and `[drag]`: the
//! same tables as `host-sim/vehicles/*.toml`, see [`crate::model::vehicle`]) plus `[limits]`,
//! `[gains]`, `[trajectory]`, `[initial]`, `[simulation]`, `[perturbations]` and `[controller]`
//! (the no-dive thrust option, off by default). `[limits]`,
//! `[gains]` and `[trajectory]` are the tables of [`firmware::flight_tables`], shared with the
//! firmware build's flight file.
//!
//! Every key carries its unit in its name. Unknown keys are refused. Errors name the file, the
//! key and the reason. The paper's Section VI scenario is embedded ([`Scenario::paper`]).

use std::path::Path;

use anyhow::{anyhow, Context, Result};
use controller_core::scalar::{lit, Scalar};
use controller_core::{
    Gains, HeadingProfile, IntegralGains, Lemma1Form, Limits, PositionSaturation,
    ReferenceTrajectory, TiltPriorityGains, TurnOver, Vehicle, VelocityLimit,
};
use nalgebra::{UnitQuaternion, Vector3};

use crate::model::perturbation::PerturbationConfig;
use crate::model::plant::{RigidBody, RigidBodyState};
use crate::model::rotor_plant::RotorParameters;
use crate::model::vehicle::{DragTable, RotorsTable, VehicleFile, VehicleTable};

mod controller;
mod edit;
mod keys;
pub use controller::{ControllerConfig, ControllerOverrides, ThrustKind};
pub use edit::{apply_edits, describe_edits, KeyEdit};
use firmware::flight_tables::TiltPriorityTable;
pub use keys::describe;
use serde::{Deserialize, Serialize};

/// The embedded Section VI scenario, as TOML text (`scenarios/paper.toml`, a link to the file
/// the firmware's bench fixtures share: [`flight_files::shared::PAPER_SCENARIO`]).
pub const PAPER_SCENARIO: &str = flight_files::shared::PAPER_SCENARIO;

/// A whole scenario.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Rigid-body parameters (the vehicle files' `[vehicle]` table; name, source and
    /// `real_propeller` are optional here).
    pub vehicle: VehicleConfig,
    /// Optional `[rotors]`: the vehicle's rotors, as in a vehicle file (needed by the
    /// rotor-level plant).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotors: Option<RotorsTable>,
    /// Optional `[drag]`: quadratic body drag, as in a vehicle file (absent = none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag: Option<DragTable>,
    /// Actuator limits.
    pub limits: LimitsConfig,
    /// Controller gains (Table I).
    pub gains: GainsConfig,
    /// Reference trajectory.
    pub trajectory: TrajectoryConfig,
    /// Initial state of the vehicle.
    pub initial: InitialConfig,
    /// Simulation settings.
    pub simulation: SimulationConfig,
    /// Optional `[perturbations]`: noise, model errors, disturbances, motor lag (all off by
    /// default; see [`PerturbationConfig`]).
    #[serde(default, skip_serializing_if = "PerturbationConfig::is_nominal")]
    pub perturbations: PerturbationConfig,
    /// Optional `[controller]`: options of the law beyond the paper's (absent = the paper's
    /// law; see [`ControllerConfig`]).
    #[serde(default, skip_serializing_if = "ControllerConfig::is_paper")]
    pub controller: ControllerConfig,
}

/// `[vehicle]`: the vehicle files' table ([`VehicleTable`]).
pub type VehicleConfig = VehicleTable;

// `[limits]`, `[gains]` and `[trajectory]` are the firmware's flight file tables (one
// definition: the firmware build reads the same tables from its flight file).
pub use firmware::flight_tables::{
    GainsTable as GainsConfig, HeadingTable as HeadingConfig, IntegralTable as IntegralConfig,
    Lemma1Table as Lemma1Config, LimitsTable as LimitsConfig, ObserverTable as ObserverConfig,
    PositionSaturationTable as PositionSaturationConfig, TrajectoryTable as TrajectoryConfig,
};

/// `[initial]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InitialConfig {
    /// Position \[m\], inertial.
    pub position_m: [f64; 3],
    /// Velocity [m/s], inertial.
    #[serde(default)]
    pub velocity_m_s: [f64; 3],
    /// Roll, pitch, yaw \[deg\] with `R = Rz(yaw) Ry(pitch) Rx(roll)`.
    pub euler_deg: [f64; 3],
    /// Body angular velocity [rad/s].
    #[serde(default)]
    pub angular_velocity_rad_s: [f64; 3],
}

/// Controller scalar type.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// Single precision, as on the flight controller.
    F32,
    /// Double precision.
    F64,
}

/// `[simulation]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimulationConfig {
    /// Length of the run \[s\].
    pub duration_s: f64,
    /// Controller sampling period \[s\]; commands are held between samples.
    pub controller_period_s: f64,
    /// RK4 substep of the plant \[s\].
    #[serde(default = "default_plant_step")]
    pub plant_step_s: f64,
    /// Controller scalar.
    #[serde(default = "default_precision")]
    pub precision: Precision,
    /// Clip the commands to the physical limits before applying them.
    #[serde(default)]
    pub clip_to_limits: bool,
    /// Seed of the random draws of this run's `[perturbations]` (noise, sampled model errors,
    /// gusts); unused without perturbations. Campaigns draw their own seed per run.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub seed: u64,
    /// The plant flown: `"ideal"` (the command `(T, τ)` acts on the rigid body directly, the
    /// paper's model; the default) or `"rotors"` (the firmware's mixer, four rotors with motor
    /// dynamics and optional body drag: [`crate::model::rotor_plant`]; needs a `[rotors]` table).
    #[serde(default, skip_serializing_if = "PlantKind::is_ideal")]
    pub plant: PlantKind,
}

/// `simulation.plant`: which plant a run flies.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PlantKind {
    /// `(T, τ)` applied to the rigid body directly (eq:FullDynamics).
    #[default]
    Ideal,
    /// The rotor-level plant of [`crate::model::rotor_plant`].
    Rotors,
}

impl PlantKind {
    /// True for [`PlantKind::Ideal`] (the default, left out when a scenario is written).
    pub fn is_ideal(&self) -> bool {
        *self == Self::Ideal
    }

    /// The name used in scenario files and on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Ideal => "ideal",
            Self::Rotors => "rotors",
        }
    }
}

fn is_zero(seed: &u64) -> bool {
    *seed == 0
}

fn default_plant_step() -> f64 {
    1e-3
}

fn default_precision() -> Precision {
    Precision::F32
}

fn v3<T: Scalar>(a: &[f64; 3]) -> Vector3<T> {
    Vector3::new(lit(a[0]), lit(a[1]), lit(a[2]))
}

impl Scenario {
    /// The embedded Section VI scenario.
    pub fn paper() -> Self {
        Self::parse(PAPER_SCENARIO, "<embedded paper scenario>")
            .unwrap_or_else(|e| unreachable!("embedded scenario is valid: {e:#}"))
    }

    /// Reads and validates a scenario file. Errors name the file, the key and the reason.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read scenario file {}", path.display()))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses and validates scenario text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let scenario: Scenario =
            toml::from_str(text).map_err(|e| anyhow!("scenario {origin}: {e}"))?;
        scenario
            .validate()
            .map_err(|e| anyhow!("scenario {origin}: {e}"))?;
        Ok(scenario)
    }

    /// Checks the values (not only their types): parameters via the core's validation, and the
    /// simulation settings. Errors: `"<key>: <reason>"`.
    pub fn validate(&self) -> std::result::Result<(), String> {
        let vehicle = self.vehicle::<f64>();
        vehicle.validate().map_err(|e| describe(&e))?;
        // The vehicle files' checks, with the file named by the caller: here only key and
        // reason.
        let keyed = |e: crate::model::vehicle::VehicleFileError| format!("{}: {}", e.key, e.reason);
        self.vehicle.validate("", false).map_err(keyed)?;
        if let Some(rotors) = &self.rotors {
            rotors.validate("", &self.vehicle).map_err(keyed)?;
        }
        if let Some(drag) = &self.drag {
            drag.validate("").map_err(keyed)?;
        }
        self.limits::<f64>().validate().map_err(|e| describe(&e))?;
        self.gains::<f64>().validate().map_err(|e| describe(&e))?;
        self.validate_controller()?;
        let s = &self.simulation;
        let positive = |key: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{key}: must be finite and > 0, got {v}"))
            }
        };
        positive("simulation.duration_s", s.duration_s)?;
        positive("simulation.controller_period_s", s.controller_period_s)?;
        positive("simulation.plant_step_s", s.plant_step_s)?;
        if s.plant_step_s > s.controller_period_s {
            return Err(format!(
                "simulation.plant_step_s: must not exceed controller_period_s ({} s), got {} s",
                s.controller_period_s, s.plant_step_s
            ));
        }
        let i = &self.initial;
        for (key, arr) in [
            ("initial.position_m", i.position_m),
            ("initial.velocity_m_s", i.velocity_m_s),
            ("initial.euler_deg", i.euler_deg),
            ("initial.angular_velocity_rad_s", i.angular_velocity_rad_s),
        ] {
            if !arr.iter().all(|x| x.is_finite()) {
                return Err(format!("{key}: must be finite, got {arr:?}"));
            }
        }
        self.perturbations.validate()?;
        if self.simulation.plant == PlantKind::Rotors && self.rotor_config().is_none() {
            return Err(
                "simulation.plant: plant = rotors needs a [rotors] table (or --vehicle FILE)"
                    .into(),
            );
        }
        Ok(())
    }

    /// The vehicle in scalar `T`.
    pub fn vehicle<T: Scalar>(&self) -> Vehicle<T> {
        Vehicle {
            mass: lit(self.vehicle.mass_kg),
            inertia: v3(&self.vehicle.inertia_kg_m2),
            gravity: lit(self.vehicle.gravity_m_s2),
        }
    }

    /// The limits in scalar `T`.
    pub fn limits<T: Scalar>(&self) -> Limits<T> {
        Limits {
            thrust_max: lit(self.limits.thrust_max_N),
            torque_max: v3(&self.limits.torque_max_Nm),
        }
    }

    /// The gains in scalar `T`.
    pub fn gains<T: Scalar>(&self) -> Gains<T> {
        let g = &self.gains;
        let mut out = Gains::<T>::paper();
        out.position.kp = lit(g.kp);
        out.position.kv = lit(g.kv);
        out.position.kf = lit(g.kf);
        out.position.ks = lit(g.ks);
        out.position.saturation = lit(g.M_p);
        out.position.saturation_shape = match g.position_saturation {
            PositionSaturationConfig::Componentwise => PositionSaturation::Componentwise,
            PositionSaturationConfig::Norm => PositionSaturation::Norm,
        };
        out.position.vertical = g.vertical.map(|v| controller_core::VerticalChannel {
            up: lit(v.up_m_s2),
            down: lit(v.down_m_s2),
            kf: lit(v.kf),
            ks: lit(v.ks),
        });
        out.lemma1 = match g.lemma1 {
            Lemma1Config::Paper => Lemma1Form::Paper,
            Lemma1Config::Tangential => Lemma1Form::Tangential,
            Lemma1Config::DesiredFrame => Lemma1Form::DesiredFrame,
        };
        out.attitude.k_mrp = lit(g.k_theta);
        out.attitude.k_omega = lit(g.k_omega);
        out.attitude.mrp_saturation = lit(g.M_theta);
        out.attitude.omega_saturation = lit(g.M_omega);
        out.hysteresis = lit(g.delta);
        out.reset_threshold = lit(g.alpha);
        out.tilt_priority = g.tilt_priority.as_ref().map(tilt_priority_gains);
        out.velocity_limit = g.velocity_limit.map(|v| VelocityLimit {
            speed: lit(v.speed_m_s),
            braking: lit(v.braking_m_s2),
            vertical: v
                .vertical_braking()
                .map(|(up, down)| controller_core::VerticalBraking {
                    up: lit(up),
                    down: lit(down),
                }),
        });
        out.local = g.local.map(|l| controller_core::LocalGains {
            kp: lit(l.kp),
            kv: lit(l.kv),
            kf: lit(l.kf),
            ks: lit(l.ks),
            saturation: lit(l.M_p_m_s2),
            energy_in: lit(l.energy_in_J),
            energy_out: lit(l.energy_out_J),
            vertical: l.vertical.map(|v| {
                let (up, down) = v.levels(g.vertical.as_ref());
                controller_core::VerticalChannel {
                    kf: lit(v.kf),
                    ks: lit(v.ks),
                    up: lit(up),
                    down: lit(down),
                }
            }),
            attitude: l.attitude.map(|a| controller_core::LocalAttitude {
                attitude: controller_core::attitude_control::AttitudeGains {
                    k_mrp: lit(a.k_theta),
                    k_omega: lit(a.k_omega),
                    mrp_saturation: lit(a.M_theta),
                    omega_saturation: lit(a.M_omega),
                },
                tilt_priority: a.tilt_priority.as_ref().map(tilt_priority_gains),
            }),
            braking: l.braking_m_s2.map(lit),
        });
        out.heading_compensator =
            g.heading_compensator
                .map(|h| controller_core::HeadingCompensatorGains {
                    level: lit(h.level_rad_s),
                    gain: lit(h.gain_1_s),
                });
        out.integral = g.integral.as_ref().map(|i| IntegralGains {
            gain: lit(i.k_i),
            level: v3(&i.M_i_m_s2),
            rate: v3(&i.rate_m_s3),
            bandwidth: lit(i.k_eta),
            observer: i.observer.map(|o| controller_core::ObserverGains {
                velocity_gain: lit(o.velocity_gain_1_s),
                disturbance_gain: lit(o.disturbance_gain_1_s2),
                error_limit: lit(o.error_limit_m),
            }),
            feedforward_scale: i.feedforward_scale.map(|f| {
                controller_core::FeedforwardScaleGains {
                    gain: lit(f.gain_1_s),
                    excitation: lit(f.excitation_m_s2),
                    level: lit(f.level),
                    rate: lit(f.rate_1_s),
                    tracking_limit: lit(f.tracking_limit_m),
                }
            }),
        });
        out
    }

    /// The reference trajectory in scalar `T`.
    pub fn trajectory<T: Scalar>(&self) -> ReferenceTrajectory<T> {
        let heading = |h: &HeadingConfig| match *h {
            HeadingConfig::Constant { yaw_rad } => HeadingProfile::Constant { yaw: lit(yaw_rad) },
            HeadingConfig::Sinusoidal {
                amplitude_rad,
                frequency_rad_s,
                offset_rad,
            } => HeadingProfile::Sinusoidal {
                amplitude: lit(amplitude_rad),
                frequency: lit(frequency_rad_s),
                offset: lit(offset_rad),
            },
        };
        match &self.trajectory {
            TrajectoryConfig::Hover {
                point_m,
                heading: h,
            } => ReferenceTrajectory::Hover {
                point: v3(point_m),
                heading: heading(h),
            },
            TrajectoryConfig::Helix {
                center_m,
                radius_m,
                vertical_amplitude_m,
                frequency_rad_s,
                heading: h,
            } => ReferenceTrajectory::Helix {
                center: v3(center_m),
                radius: lit(*radius_m),
                vertical_amplitude: lit(*vertical_amplitude_m),
                frequency: lit(*frequency_rad_s),
                heading: heading(h),
            },
            TrajectoryConfig::FigureEight {
                center_m,
                x_amplitude_m,
                y_amplitude_m,
                frequency_rad_s,
                heading: h,
            } => ReferenceTrajectory::FigureEight {
                center: v3(center_m),
                x_amplitude: lit(*x_amplitude_m),
                y_amplitude: lit(*y_amplitude_m),
                frequency: lit(*frequency_rad_s),
                heading: heading(h),
            },
        }
    }

    /// The rigid-body model of the scenario's vehicle (f64).
    pub fn plant(&self) -> RigidBody {
        crate::model::vehicle::rigid_body(&self.vehicle)
    }

    /// This scenario flown with a vehicle file's vehicle: its `[vehicle]`, `[rotors]` and
    /// `[drag]` replace the scenario's (no `[drag]` in the file = no body drag). Limits, gains
    /// and the rest are kept: whether they suit the new vehicle is for the certificate to say.
    pub fn with_vehicle(&self, file: &VehicleFile) -> Scenario {
        Scenario {
            vehicle: file.vehicle.clone(),
            rotors: Some(file.rotors.clone()),
            drag: file.drag.clone(),
            ..self.clone()
        }
    }

    /// This scenario with the command line's plant overrides, in this order: the vehicle file's
    /// `[vehicle]`, `[rotors]` and `[drag]` ([`Scenario::with_vehicle`]), the plant, and the motor
    /// time constant \[s\] as `[perturbations] motor_time_constant_s` (on the rotor plant it
    /// replaces the vehicle's; on the ideal plant it is a first-order lag on `(T, τ)`).
    ///
    /// Errors: the vehicle file cannot be read or is invalid (file, key, reason); the motor time
    /// constant is not finite and `≥ 0`.
    pub fn with_plant_overrides(
        mut self,
        vehicle: Option<&Path>,
        plant: Option<PlantKind>,
        motor_time_constant_s: Option<f64>,
    ) -> Result<Scenario> {
        if let Some(path) = vehicle {
            self = self.with_vehicle(&crate::model::vehicle::load(path)?);
        }
        if let Some(p) = plant {
            self.simulation.plant = p;
        }
        if let Some(t) = motor_time_constant_s {
            if !(t.is_finite() && t >= 0.0) {
                anyhow::bail!("--motor-time-constant-s must be finite and >= 0, got {t}");
            }
            self.perturbations.motor_time_constant_s = t;
        }
        Ok(self)
    }

    /// This scenario with the command line's `[controller]` overrides (`--thrust`,
    /// `--thrust-floor-n`, `--thrust-ramp`, `--thrust-exponent`); a `None` keeps the
    /// scenario's value. The result is checked by [`Scenario::validate`].
    pub fn with_controller_overrides(mut self, o: &ControllerOverrides) -> Scenario {
        let c = &mut self.controller;
        if let Some(t) = o.thrust {
            c.thrust = t;
        }
        if let Some(f) = o.thrust_floor_N {
            c.thrust_floor_N = f;
        }
        if let Some(b) = o.thrust_ramp {
            c.thrust_ramp = b;
        }
        if let Some(k) = o.thrust_exponent {
            c.thrust_exponent = k;
        }
        self
    }

    /// The scenario's rotors (geometry, thrust range, yaw torque per newton), motor time
    /// constant and body drag, for `plant = "rotors"`; `None` without a `[rotors]` table.
    ///
    /// The rotors are the firmware's f32 [`firmware::config::RotorConfig`] of the airframe the
    /// tables describe ([`crate::model::vehicle::airframe`], the values a firmware build takes), so the
    /// plant mixes with the flight code's numbers; the motor time constant and drag stay f64.
    pub fn rotor_config(&self) -> Option<RotorParameters> {
        let rotors = self.rotors.as_ref()?;
        // Without name and source the airframe leaks nothing (empty strings do not allocate),
        // so building the plant once per run costs no memory.
        let vehicle = VehicleTable {
            name: None,
            source: None,
            ..self.vehicle.clone()
        };
        let airframe = crate::model::vehicle::airframe(&VehicleFile {
            vehicle,
            rotors: rotors.clone(),
            drag: self.drag.clone(),
        });
        Some(RotorParameters {
            rotors: airframe.rotors,
            motor_time_constant_s: rotors.motor_time_constant_s,
            body_drag_N_s2_m2: self.drag.as_ref().map_or([0.0; 3], |d| d.body_drag_N_s2_m2),
        })
    }

    /// The initial state of the rigid body from `[initial]`.
    pub fn initial_state(&self) -> RigidBodyState {
        let i = &self.initial;
        RigidBodyState {
            position: Vector3::from(i.position_m),
            velocity: Vector3::from(i.velocity_m_s),
            attitude: self.initial_attitude(),
            angular_velocity: Vector3::from(i.angular_velocity_rad_s),
        }
    }

    /// The initial attitude (body to inertial) from `initial.euler_deg`.
    pub fn initial_attitude(&self) -> UnitQuaternion<f64> {
        let [r, p, y] = self.initial.euler_deg.map(f64::to_radians);
        // nalgebra's from_euler_angles(roll, pitch, yaw) is Rz(yaw) Ry(pitch) Rx(roll).
        UnitQuaternion::from_euler_angles(r, p, y)
    }
}

/// The tilt-priority gains of a `[gains.tilt_priority]` table (or the local law's) in scalar `T`.
fn tilt_priority_gains<T: Scalar>(t: &TiltPriorityTable) -> TiltPriorityGains<T> {
    TiltPriorityGains {
        trace_weights: v3(&t.trace_weights_Nm),
        omega_gains: v3(&t.omega_gains_Nm_s),
        omega_levels: v3(&t.omega_levels_Nm),
        turn_over: t.turn_over().map(|(level, onset)| TurnOver {
            level: lit(level),
            onset: lit(onset),
        }),
    }
}
#[cfg(test)]
mod tests;
