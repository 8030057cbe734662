//! Clap types shared by several subcommands: the precision, the plant, and the base scenario
//! options of `campaign`, `ablation` and `compare`.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use host_sim::model::scenario::{ControllerOverrides, PlantKind, Precision, Scenario, ThrustKind};
use host_sim::studies::campaign::BaseOptions;

/// Controller scalar type (the command line's spelling of [`Precision`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// Single precision, as on the flight controller.
    F32,
    /// Double precision.
    F64,
}

impl From<PrecisionArg> for Precision {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::F32 => Precision::F32,
            PrecisionArg::F64 => Precision::F64,
        }
    }
}

/// Which plant a run flies (the command line's spelling of [`PlantKind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PlantArg {
    /// `(T, tau)` applied to the rigid body directly (the paper's model).
    Ideal,
    /// The firmware's mixer, four rotors with first-order speed dynamics, optional body drag
    /// (needs the scenario's `[rotors]` table or `--vehicle FILE`).
    Rotors,
}

impl From<PlantArg> for PlantKind {
    fn from(p: PlantArg) -> Self {
        match p {
            PlantArg::Ideal => PlantKind::Ideal,
            PlantArg::Rotors => PlantKind::Rotors,
        }
    }
}

/// How the thrust is computed from `u` (the command line's spelling of [`ThrustKind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ThrustArg {
    /// T = m|u|, the paper's law.
    Norm,
    /// No-dive thrust: T = max(m u . R e3, T_floor), the projection of m u on the body z axis.
    BodyAxisProjection,
    /// T = max(m|u| max(cos th, 0)^k, T_floor), th the angle between body z and u.
    AlignmentPower,
    /// Vertical priority.
    VerticalPriority,
}

impl From<ThrustArg> for ThrustKind {
    fn from(t: ThrustArg) -> Self {
        match t {
            ThrustArg::Norm => ThrustKind::Norm,
            ThrustArg::BodyAxisProjection => ThrustKind::BodyAxisProjection,
            ThrustArg::AlignmentPower => ThrustKind::AlignmentPower,
            ThrustArg::VerticalPriority => ThrustKind::VerticalPriority,
        }
    }
}

/// The `[controller]` options every flying command takes: `--thrust` and its parameters.
#[derive(Debug, Args, Clone, Default)]
pub struct ThrustArgs {
    /// Thrust law, overriding the scenario's `[controller] thrust` (default: the scenario's,
    /// `norm` = the paper's T = m|u|).
    #[arg(long, value_enum)]
    pub thrust: Option<ThrustArg>,
    /// Thrust floor T_floor (N) of the no-dive thrust, in [0, T_min], overriding
    /// `[controller] thrust_floor_N`.
    #[arg(long, value_name = "N")]
    pub thrust_floor_n: Option<f64>,
    /// Ramp width b0 in (0, 1] of `--thrust vertical-priority` (the vertical component of the
    /// body z axis below which the thrust cap ramps down to 0), overriding
    /// `[controller] thrust_ramp`.
    #[arg(long, value_name = "B0")]
    pub thrust_ramp: Option<f64>,
    /// Exponent k > 0 of `--thrust alignment-power`, overriding `[controller] thrust_exponent`.
    #[arg(long, value_name = "K")]
    pub thrust_exponent: Option<f64>,
}

impl ThrustArgs {
    /// The library's overrides.
    pub fn overrides(&self) -> ControllerOverrides {
        ControllerOverrides {
            thrust: self.thrust.map(ThrustKind::from),
            thrust_floor_N: self.thrust_floor_n,
            thrust_ramp: self.thrust_ramp,
            thrust_exponent: self.thrust_exponent,
        }
    }

    /// `scenario` with these overrides ([`Scenario::with_controller_overrides`]).
    pub fn apply(&self, scenario: Scenario) -> Scenario {
        scenario.with_controller_overrides(&self.overrides())
    }
}

/// The plant options every flying command takes: `--plant` and `--vehicle`.
#[derive(Debug, Args, Clone, Default)]
pub struct PlantArgs {
    /// Plant, overriding the scenario's `simulation.plant`.
    #[arg(long, value_enum)]
    pub plant: Option<PlantArg>,
    /// Vehicle file (e.g. `host-sim/vehicles/x500.toml`): its `[vehicle]`, `[rotors]` and
    /// `[drag]` replace the scenario's (limits, gains and the rest are kept).
    #[arg(long, value_name = "FILE")]
    pub vehicle: Option<PathBuf>,
    /// Motor time constant (s), overriding `[perturbations] motor_time_constant_s`: on the
    /// rotor plant it replaces the vehicle's (e.g. twice it, to test robustness to motor lag);
    /// on the ideal plant it is a first-order lag on (T, tau).
    #[arg(long, value_name = "S")]
    pub motor_time_constant_s: Option<f64>,
}

/// Options shared by the three commands: the base scenario and the seed.
#[derive(Debug, Args, Clone)]
pub struct BaseArgs {
    /// Base scenario file (TOML). Default: the embedded paper scenario. Its `[initial]` table is
    /// replaced by the sampled initial conditions; its `[perturbations]` apply to every run.
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Campaign seed: run i draws from splitmix(seed, i), so results do not depend on threads.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated duration of every run (s), overriding `simulation.duration_s`.
    #[arg(long, value_name = "S")]
    pub duration_s: Option<f64>,
    /// Controller rate (Hz), overriding `simulation.controller_period_s`.
    #[arg(long, value_name = "HZ")]
    pub controller_rate_hz: Option<f64>,
    /// Clip thrust and torque to the physical limits before the plant.
    #[arg(long)]
    pub clip: bool,
    /// Controller precision for the paper's law, overriding `simulation.precision`.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Plant and vehicle.
    #[command(flatten)]
    pub plant: PlantArgs,
    /// Thrust law.
    #[command(flatten)]
    pub thrust: ThrustArgs,
}

impl From<&BaseArgs> for BaseOptions {
    fn from(a: &BaseArgs) -> Self {
        Self {
            scenario: a.scenario.clone(),
            seed: a.seed,
            duration_s: a.duration_s,
            controller_rate_hz: a.controller_rate_hz,
            clip: a.clip,
            precision: a.precision.map(Precision::from),
            plant: a.plant.plant.map(PlantKind::from),
            vehicle: a.plant.vehicle.clone(),
            motor_time_constant_s: a.plant.motor_time_constant_s,
            controller: a.thrust.overrides(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every spelling on the command line names the precision of the same scenario-file name.
    #[test]
    fn precision_spellings_map_to_their_precisions() {
        for v in PrecisionArg::value_variants() {
            let name = v.to_possible_value().map(|p| p.get_name().to_string());
            let serde_name = serde_json::to_string(&Precision::from(*v)).ok();
            assert_eq!(name.map(|n| format!("\"{n}\"")), serde_name);
        }
    }

    /// Every spelling of `--thrust` is the scenario file's name of the same thrust law.
    #[test]
    fn thrust_spellings_map_to_their_laws() {
        for v in ThrustArg::value_variants() {
            let name = v.to_possible_value().map(|p| p.get_name().to_string());
            assert_eq!(name.as_deref(), Some(ThrustKind::from(*v).name()));
        }
    }

    /// Every spelling of `--plant` is the scenario file's name of the same plant.
    #[test]
    fn plant_spellings_map_to_their_plants() {
        for v in PlantArg::value_variants() {
            let name = v.to_possible_value().map(|p| p.get_name().to_string());
            assert_eq!(name.as_deref(), Some(PlantKind::from(*v).name()));
        }
    }
}
