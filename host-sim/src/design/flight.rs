//! The scenario a design flies and writes: the vehicle file's tables, the certified limits, the
//! gains, the reference and `[simulation]` on the rotor plant, as one TOML table that
//! `host-sim --scenario` reads as is.

use anyhow::{anyhow, Result};
use controller_core::{Gains, Limits};
use serde::Serialize;

use super::reference::Reference;
use super::vehicle::DesignVehicle;
use crate::model::scenario::{
    ControllerConfig, GainsConfig, InitialConfig, LimitsConfig, PlantKind, Precision, Scenario,
    SimulationConfig, TrajectoryConfig,
};

/// Scenario `[gains]` of `gains`.
pub fn gains_config(g: &Gains<f64>) -> GainsConfig {
    GainsConfig {
        kp: g.position.kp,
        kv: g.position.kv,
        kf: g.position.kf,
        ks: g.position.ks,
        k_theta: g.attitude.k_mrp,
        k_omega: g.attitude.k_omega,
        M_p: g.position.saturation,
        position_saturation: match g.position.saturation_shape {
            controller_core::PositionSaturation::Componentwise => {
                firmware::flight_tables::PositionSaturationTable::Componentwise
            }
            controller_core::PositionSaturation::Norm => {
                firmware::flight_tables::PositionSaturationTable::Norm
            }
        },
        lemma1: match g.lemma1 {
            controller_core::Lemma1Form::Paper => firmware::flight_tables::Lemma1Table::Paper,
            controller_core::Lemma1Form::Tangential => {
                firmware::flight_tables::Lemma1Table::Tangential
            }
            controller_core::Lemma1Form::DesiredFrame => {
                firmware::flight_tables::Lemma1Table::DesiredFrame
            }
        },
        M_theta: g.attitude.mrp_saturation,
        M_omega: g.attitude.omega_saturation,
        delta: g.hysteresis,
        alpha: g.reset_threshold,
        integral: g.integral.map(|i| crate::model::scenario::IntegralConfig {
            k_i: i.gain,
            M_i_m_s2: i.level.into(),
            rate_m_s3: i.rate.into(),
            k_eta: i.bandwidth,
            observer: i.observer.map(|o| firmware::flight_tables::ObserverTable {
                velocity_gain_1_s: o.velocity_gain,
                disturbance_gain_1_s2: o.disturbance_gain,
                error_limit_m: o.error_limit,
            }),
            feedforward_scale: i.feedforward_scale.map(|f| {
                firmware::flight_tables::FeedforwardScaleTable {
                    gain_1_s: f.gain,
                    excitation_m_s2: f.excitation,
                    level: f.level,
                    rate_1_s: f.rate,
                    tracking_limit_m: f.tracking_limit,
                }
            }),
        }),
        tilt_priority: g.tilt_priority.as_ref().map(tilt_priority_table),
        velocity_limit: g
            .velocity_limit
            .map(|v| firmware::flight_tables::VelocityLimitTable {
                speed_m_s: v.speed,
                braking_m_s2: v.braking,
                braking_up_m_s2: v.vertical.map(|b| b.up),
                braking_down_m_s2: v.vertical.map(|b| b.down),
            }),
        vertical: g
            .position
            .vertical
            .map(|v| firmware::flight_tables::VerticalTable {
                up_m_s2: v.up,
                down_m_s2: v.down,
                kf: v.kf,
                ks: v.ks,
            }),
        local: g.local.map(|l| firmware::flight_tables::LocalTable {
            kp: l.kp,
            kv: l.kv,
            kf: l.kf,
            ks: l.ks,
            M_p_m_s2: l.saturation,
            energy_in_J: l.energy_in,
            energy_out_J: l.energy_out,
            vertical: l.vertical.map(|v| {
                // The levels are written only where they are not the global ones, so a file
                // without local levels reads as it always did.
                let global = g.position.vertical;
                let own =
                    |level: f64, global: Option<f64>| (global != Some(level)).then_some(level);
                firmware::flight_tables::LocalVerticalTable {
                    kf: v.kf,
                    ks: v.ks,
                    up_m_s2: own(v.up, global.map(|c| c.up)),
                    down_m_s2: own(v.down, global.map(|c| c.down)),
                }
            }),
            braking_m_s2: l.braking,
            attitude: l
                .attitude
                .map(|a| firmware::flight_tables::LocalAttitudeTable {
                    k_theta: a.attitude.k_mrp,
                    k_omega: a.attitude.k_omega,
                    M_theta: a.attitude.mrp_saturation,
                    M_omega: a.attitude.omega_saturation,
                    tilt_priority: a.tilt_priority.as_ref().map(tilt_priority_table),
                }),
        }),
        heading_compensator: g.heading_compensator.map(|h| {
            firmware::flight_tables::HeadingCompensatorTable {
                level_rad_s: h.level,
                gain_1_s: h.gain,
            }
        }),
    }
}

/// Scenario `[limits]` of `limits`.
pub fn limits_config(l: &Limits<f64>) -> LimitsConfig {
    LimitsConfig {
        thrust_max_N: l.thrust_max,
        torque_max_Nm: l.torque_max.into(),
    }
}

/// Simulation settings of the design's runs.
#[derive(Clone, Copy, Debug)]
pub struct FlightSettings {
    /// Length of a run \[s\].
    pub duration_s: f64,
    /// Controller period \[s\] (sample and hold).
    pub controller_period_s: f64,
    /// The scenario's `[controller]` (the thrust; written only when not the paper's).
    pub controller: ControllerConfig,
}

fn table_of<T: Serialize>(value: &T) -> Result<toml::Value> {
    toml::Value::try_from(value).map_err(|e| anyhow!("cannot write TOML table: {e}"))
}

/// The scenario as a TOML table (vehicle tables first).
pub fn scenario_table(
    vehicle: &DesignVehicle,
    limits: &Limits<f64>,
    gains: &Gains<f64>,
    trajectory: &TrajectoryConfig,
    initial: &InitialConfig,
    settings: FlightSettings,
) -> Result<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in &vehicle.tables {
        t.insert(k.clone(), v.clone());
    }
    t.insert("limits".into(), table_of(&limits_config(limits))?);
    t.insert("gains".into(), table_of(&gains_config(gains))?);
    t.insert("trajectory".into(), table_of(trajectory)?);
    t.insert("initial".into(), table_of(initial)?);
    if !settings.controller.is_paper() {
        t.insert("controller".into(), table_of(&settings.controller)?);
    }
    let sim = SimulationConfig {
        duration_s: settings.duration_s,
        controller_period_s: settings.controller_period_s,
        plant_step_s: 1e-3f64.min(settings.controller_period_s),
        precision: Precision::F32,
        clip_to_limits: false,
        seed: 0,
        plant: PlantKind::Rotors,
    };
    t.insert("simulation".into(), table_of(&sim)?);
    Ok(t)
}

/// The order tables are written in: the vehicle's first, as in the vehicle files.
const TABLE_ORDER: [&str; 11] = [
    "vehicle",
    "rotors",
    "drag",
    "limits",
    "gains",
    "trajectory",
    "initial",
    "controller",
    "simulation",
    "perturbations",
    "design",
];

/// `table` as TOML text with its tables in `TABLE_ORDER` (others after, by name).
/// Errors: a value TOML cannot write (not expected).
pub fn ordered_toml(table: &toml::Table) -> Result<String> {
    let rank = |k: &str| {
        TABLE_ORDER
            .iter()
            .position(|t| *t == k)
            .unwrap_or(TABLE_ORDER.len())
    };
    let mut keys: Vec<&String> = table.keys().collect();
    keys.sort_by_key(|k| (rank(k), (*k).clone()));
    let mut out = String::new();
    for k in keys {
        let mut one = toml::Table::new();
        one.insert(k.clone(), table[k].clone());
        let text =
            toml::to_string(&one).map_err(|e| anyhow!("cannot write TOML table [{k}]: {e}"))?;
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&text);
    }
    Ok(out)
}

/// Parses a scenario table the way `host-sim --scenario` parses the file.
pub fn scenario_of(table: &toml::Table) -> Result<Scenario> {
    let text = toml::to_string(table).map_err(|e| anyhow!("cannot write scenario TOML: {e}"))?;
    Scenario::parse(&text, "<design scenario>")
}

/// The scenario of `reference` with `gains` and `limits`, and the hover scenario at the
/// reference's start (for the upside-down test).
pub fn scenarios(
    vehicle: &DesignVehicle,
    limits: &Limits<f64>,
    gains: &Gains<f64>,
    reference: &Reference,
    settings: FlightSettings,
) -> Result<(Scenario, Scenario)> {
    let main = scenario_table(
        vehicle,
        limits,
        gains,
        &reference.trajectory,
        &reference.initial,
        settings,
    )?;
    let hover = scenario_table(
        vehicle,
        limits,
        gains,
        &reference.hover_at_start(),
        &reference.initial,
        settings,
    )?;
    Ok((scenario_of(&main)?, scenario_of(&hover)?))
}

/// `scenario` with the motor time constant `tau_m` \[s\] (the rotor plant's `[perturbations]
/// motor_time_constant_s` replaces the vehicle's); the vehicle's own value `nominal` \[s\] is
/// flown as the scenario says (no perturbation).
pub fn with_motor_lag(scenario: &Scenario, tau_m: f64, nominal: f64) -> Scenario {
    let mut s = scenario.clone();
    s.perturbations.motor_time_constant_s = if tau_m == nominal { 0.0 } else { tau_m };
    s
}

/// The `[gains.tilt_priority]` table (or the local law's) of tilt-priority gains.
fn tilt_priority_table(
    t: &controller_core::TiltPriorityGains<f64>,
) -> firmware::flight_tables::TiltPriorityTable {
    firmware::flight_tables::TiltPriorityTable {
        trace_weights_Nm: t.trace_weights.into(),
        omega_gains_Nm_s: t.omega_gains.into(),
        omega_levels_Nm: t.omega_levels.into(),
        turn_over_level_Nm: t.turn_over.map(|o| o.level),
        turn_over_onset: t.turn_over.map(|o| o.onset),
    }
}
