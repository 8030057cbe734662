//! What a software-in-the-loop run records at every control tick, what it shows at the end, and
//! the summary printed for a person.

use serde::Serialize;

/// One control tick of the run (at the law's rate, 100 Hz by default). Units in the names;
/// times after release.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct SilRecord {
    /// Time after release \[s\].
    pub t_s: f64,
    /// True position \[m\], NWU.
    pub x_m: f64,
    /// True y \[m\].
    pub y_m: f64,
    /// True z \[m\].
    pub z_m: f64,
    /// Reference x \[m\] (the pipeline's).
    pub x_ref_m: f64,
    /// Reference y \[m\].
    pub y_ref_m: f64,
    /// Reference z \[m\].
    pub z_ref_m: f64,
    /// Estimated position minus true position, norm \[m\].
    pub estimate_error_m: f64,
    /// True position minus reference, norm \[m\] (0 when not flying the controller).
    pub position_error_m: f64,
    /// Roll \[rad\] (`R = Rz Ry Rx`).
    pub roll_rad: f64,
    /// Pitch \[rad\].
    pub pitch_rad: f64,
    /// Yaw \[rad\].
    pub yaw_rad: f64,
    /// Tilt: angle between body z and inertial z \[rad\].
    pub tilt_rad: f64,
    /// Flight state (`disarmed`, `armed`, `failsafe`).
    pub state: &'static str,
    /// Reference mode.
    pub mode: &'static str,
    /// Collective thrust of the allocation \[N\].
    pub thrust_N: f64,
    /// Torque of the allocation x [N m], body.
    pub torque_x_Nm: f64,
    /// Torque y [N m].
    pub torque_y_Nm: f64,
    /// Torque z [N m].
    pub torque_z_Nm: f64,
    /// Actual rotor thrusts \[N\] (after the lag).
    pub rotor1_N: f64,
    /// Rotor 2 \[N\].
    pub rotor2_N: f64,
    /// Rotor 3 \[N\].
    pub rotor3_N: f64,
    /// Rotor 4 \[N\].
    pub rotor4_N: f64,
    /// Throttle commands.
    pub throttle1: f32,
    /// Throttle 2.
    pub throttle2: f32,
    /// Throttle 3.
    pub throttle3: f32,
    /// Throttle 4.
    pub throttle4: f32,
    /// Vertical velocity [m/s], z up.
    pub vz_m_s: f64,
}

/// What a run showed.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct SilSummary {
    /// Scenario name.
    pub scenario: String,
    /// Seed.
    pub seed: u64,
    /// The flown configuration's vehicle name (the flight file's `[vehicle] name`).
    pub vehicle: String,
    /// Whether every condition of the boot certificate holds (the firmware's boot banner:
    /// "certificate holds").
    pub certificate_holds: bool,
    /// The certified `(T, τ)` set's smallest headroom inside the rotors, a fraction of the rotor
    /// range (negative: it does not fit; what the gate checks).
    pub fit_margin: f64,
    /// The margin the configuration requires (the banner says "set fits" when
    /// `fit_margin >= required_fit_margin`).
    pub required_fit_margin: f64,
    /// Whether the box of the certificate's per-axis bounds fits inside the rotors, every corner
    /// at once (a per-axis report; the certified set inside it is what must fit).
    pub a_priori_box_fits: bool,
    /// Shortfall of that box per axis: thrust below/above \[N\], then torque x, y, z [N m].
    pub a_priori_box_shortfall: [f64; 5],
    /// Certificate conditions that fail (names).
    pub violated_conditions: Vec<String>,
    /// Every event with its time after release \[s\].
    pub events: Vec<(f64, String)>,
    /// Position error at the end \[m\] (true position vs the pipeline's reference).
    pub final_position_error_m: f64,
    /// RMS position error over the last 10 s of flight under the controller \[m\].
    pub rms_position_error_last_10s_m: f64,
    /// Time after release from which the error stays below 5 cm \[s\].
    pub below_5cm_from_s: Option<f64>,
    /// Largest actual rotor thrust \[N\] and the rotor maximum.
    pub rotor_thrust_max_N: f64,
    /// Smallest actual rotor thrust while armed \[N\].
    pub rotor_thrust_min_armed_N: f64,
    /// Per-rotor thrust range of the vehicle \[N\].
    pub rotor_range_N: [f64; 2],
    /// Throttle commands outside [0, 1] or non-finite (must be 0).
    pub throttle_violations: u64,
    /// Ticks with a spinning motor while disarmed (must be 0).
    pub spun_while_disarmed: u64,
    /// Ticks the mixer gave something up.
    pub mixer_saturated_ticks: u32,
    /// Frames the firmware's decoder accepted / dropped / found malformed.
    pub link_frames: [u32; 3],
    /// Telemetry frames sent (decoded back, CRC-valid) and malformed ones (must be 0).
    pub telemetry_frames: [u32; 2],
    /// Time of the last pose delivered before the failsafe (or the end) \[s\].
    pub last_pose_s: Option<f64>,
    /// Failsafe entry time \[s\].
    pub failsafe_at_s: Option<f64>,
    /// Disarm time \[s\] (last).
    pub disarmed_at_s: Option<f64>,
    /// Largest tilt during the failsafe after its first 0.5 s \[rad\].
    pub failsafe_max_tilt_rad: Option<f64>,
    /// Mean vertical velocity during the failsafe [m/s] (negative: descending).
    pub failsafe_mean_vz_m_s: Option<f64>,
    /// Final flight state.
    pub final_state: String,
    /// Non-finite values counted by the pipeline.
    pub non_finite: u32,
    /// Commands refused.
    pub refused_commands: u32,
}

/// A short human summary.
pub fn human_summary(s: &SilSummary) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "SIL scenario {} (seed {}), vehicle {}",
        s.scenario, s.seed, s.vehicle
    );
    let _ = writeln!(
        o,
        "  boot: certificate holds: {}; certified set margin {:.4} of the rotor range (required {:.4})",
        s.certificate_holds, s.fit_margin, s.required_fit_margin
    );
    let _ = writeln!(
        o,
        "  box of the per-axis bounds inside the rotors (every corner at once; informative): {}{}",
        s.a_priori_box_fits,
        if s.a_priori_box_fits {
            String::new()
        } else {
            format!(
                " (short by T_low {:.3} N, T_high {:.3} N, tau {:.3} / {:.3} / {:.3} N m)",
                s.a_priori_box_shortfall[0],
                s.a_priori_box_shortfall[1],
                s.a_priori_box_shortfall[2],
                s.a_priori_box_shortfall[3],
                s.a_priori_box_shortfall[4]
            )
        }
    );
    let _ = writeln!(
        o,
        "  certificate conditions violated: {:?}",
        s.violated_conditions
    );
    for (t, e) in &s.events {
        let _ = writeln!(o, "  t = {t:8.3} s  {e}");
    }
    let _ = writeln!(
        o,
        "  position error: final {:.4} m, RMS last 10 s {:.4} m, below 5 cm from {}",
        s.final_position_error_m,
        s.rms_position_error_last_10s_m,
        s.below_5cm_from_s
            .map_or_else(|| "never".to_string(), |t| format!("{t:.2} s"))
    );
    let _ = writeln!(
        o,
        "  rotor thrust: max {:.3} N, min while armed {:.3} N (range [{}, {}] N); throttle violations {}; spun while disarmed {}; mixer saturated {} ticks",
        s.rotor_thrust_max_N,
        s.rotor_thrust_min_armed_N,
        s.rotor_range_N[0],
        s.rotor_range_N[1],
        s.throttle_violations,
        s.spun_while_disarmed,
        s.mixer_saturated_ticks
    );
    let _ = writeln!(
        o,
        "  link frames ok/dropped/malformed {:?}; telemetry frames valid/malformed {:?}; non-finite {}; refused {}",
        s.link_frames, s.telemetry_frames, s.non_finite, s.refused_commands
    );
    if let Some(f) = s.failsafe_at_s {
        let _ = writeln!(
            o,
            "  failsafe at {f:.3} s (last pose {}), disarmed at {}, max tilt after 0.5 s {:.2} deg, mean vz {:.2} m/s",
            s.last_pose_s.map_or("-".into(), |t| format!("{t:.3} s")),
            s.disarmed_at_s.map_or("-".into(), |t| format!("{t:.3} s")),
            s.failsafe_max_tilt_rad.unwrap_or(f64::NAN).to_degrees(),
            s.failsafe_mean_vz_m_s.unwrap_or(f64::NAN)
        );
    }
    let _ = writeln!(o, "  final state: {}", s.final_state);
    o
}
