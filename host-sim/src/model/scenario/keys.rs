//! The scenario key each parameter the core refuses comes from, for error messages that name
//! the file's key ([`describe`]).

use controller_core::ParameterError;

/// Maps the names used by the core's [`ParameterError`] to scenario keys.
fn key_of(name: &str) -> &'static str {
    match name {
        "mass" => "vehicle.mass_kg",
        "J_11" | "J_22" | "J_33" => "vehicle.inertia_kg_m2",
        "gravity" => "vehicle.gravity_m_s2",
        "thrust_max" => "limits.thrust_max_N",
        "tau_max_1" | "tau_max_2" | "tau_max_3" => "limits.torque_max_Nm",
        "k_p" => "gains.kp",
        "k_v" => "gains.kv",
        "k_f" => "gains.kf",
        "k_s" => "gains.ks",
        "M_p" => "gains.M_p",
        "k_theta" => "gains.k_theta",
        "k_omega" => "gains.k_omega",
        "M_theta" => "gains.M_theta",
        "M_omega" => "gains.M_omega",
        "delta" => "gains.delta",
        "alpha" => "gains.alpha",
        "k_i" => "gains.integral.k_i",
        "k_eta" => "gains.integral.k_eta",
        "L_v" => "gains.integral.observer.velocity_gain_1_s",
        "L_d" => "gains.integral.observer.disturbance_gain_1_s2",
        "z_bar" => "gains.integral.observer.error_limit_m",
        "mu_gain" => "gains.integral.feedforward_scale.gain_1_s",
        "mu_excitation" => "gains.integral.feedforward_scale.excitation_m_s2",
        "mu_level" => "gains.integral.feedforward_scale.level",
        "mu_rate" => "gains.integral.feedforward_scale.rate_1_s",
        "mu_tracking_limit" => "gains.integral.feedforward_scale.tracking_limit_m",
        "M_i_x" | "M_i_y" | "M_i_z" => "gains.integral.M_i_m_s2",
        "R_i_x" | "R_i_y" | "R_i_z" => "gains.integral.rate_m_s3",
        n if n.starts_with("M_p + M_i_z") => "gains.integral.M_i_m_s2",
        "g_1" | "g_2" | "g_3" => "gains.tilt_priority.trace_weights_Nm",
        "k_omega_1" | "k_omega_2" | "k_omega_3" => "gains.tilt_priority.omega_gains_Nm_s",
        "M_omega_1" | "M_omega_2" | "M_omega_3" => "gains.tilt_priority.omega_levels_Nm",
        "turn_over_level" => "gains.tilt_priority.turn_over_level_Nm",
        "turn_over_onset" => "gains.tilt_priority.turn_over_onset",
        "speed_limit" => "gains.velocity_limit.speed_m_s",
        "braking" => "gains.velocity_limit.braking_m_s2",
        "braking_up" => "gains.velocity_limit.braking_up_m_s2",
        "braking_down" => "gains.velocity_limit.braking_down_m_s2",
        "M_up" => "gains.vertical.up_m_s2",
        "M_down" => "gains.vertical.down_m_s2",
        "k_f,z" => "gains.vertical.kf",
        "k_s,z" => "gains.vertical.ks",
        "local k_p" => "gains.local.kp",
        "local k_v" => "gains.local.kv",
        "local k_f" => "gains.local.kf",
        "local k_s" => "gains.local.ks",
        "local M_p" => "gains.local.M_p_m_s2",
        "E_in" => "gains.local.energy_in_J",
        "E_out" => "gains.local.energy_out_J",
        "local k_f,z" => "gains.local.vertical.kf",
        "local M_up" => "gains.local.vertical.up_m_s2",
        "local M_down" => "gains.local.vertical.down_m_s2",
        "local k_s,z" => "gains.local.vertical.ks",
        "local braking" => "gains.local.braking_m_s2",
        "local k_theta" => "gains.local.attitude.k_theta",
        "local k_omega" => "gains.local.attitude.k_omega",
        "local M_theta" => "gains.local.attitude.M_theta",
        "local M_omega" => "gains.local.attitude.M_omega",
        "local g_1" | "local g_2" | "local g_3" => {
            "gains.local.attitude.tilt_priority.trace_weights_Nm"
        }
        "local k_omega_1" | "local k_omega_2" | "local k_omega_3" => {
            "gains.local.attitude.tilt_priority.omega_gains_Nm_s"
        }
        "local M_omega_1" | "local M_omega_2" | "local M_omega_3" => {
            "gains.local.attitude.tilt_priority.omega_levels_Nm"
        }
        "local turn_over_level" => "gains.local.attitude.tilt_priority.turn_over_level_Nm",
        "local turn_over_onset" => "gains.local.attitude.tilt_priority.turn_over_onset",
        "L_psi" => "gains.heading_compensator.level_rad_s",
        "k_psi" => "gains.heading_compensator.gain_1_s",
        "thrust_floor" => "controller.thrust_floor_N",
        "thrust_ramp" => "controller.thrust_ramp",
        "thrust_cap" => "controller.thrust",
        _ => "trajectory",
    }
}

/// Describes a [`ParameterError`] with the scenario key it comes from.
pub fn describe(e: &ParameterError) -> String {
    let key = match e {
        ParameterError::NotPositive { name, .. } | ParameterError::OutOfRange { name, .. } => {
            key_of(name)
        }
        ParameterError::SaturationTooLarge { .. } => "gains.M_p",
        ParameterError::BadTrajectoryConstant { .. } => "trajectory",
    };
    format!("{key}: {e}")
}
