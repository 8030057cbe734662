//! The boot banner as defmt lines: the flight file the firmware was built with (vehicle name and
//! source, the `[design]` fields, the local regime's gains and energy levels), the MAVLink
//! link's trust and signing set-up, the set-up, its a-priori bound certificate (every condition
//! with `lhs`, `rhs` and their ratio; a failing one blocks arming), whether airmode flies, each
//! rotor fit the gate checks with its margin (the certified set, or airmode's thrust interval and
//! shadows), airmode's convergence verdict, the verdicts `certificate holds` / `set fits`, and
//! refusals with the violated condition and its numbers.

use controller_core::{Certificate, ParameterError};
use defmt::{error, info, warn};

use crate::config::ThrustChoice;
use crate::link::LinkTrust;
use crate::mixer::MixerError;
use crate::pipeline::{BootError, BootReport};
use crate::report::{self, Setup, Severity, Value};

fn log_values(section: &'static str, values: &[Value]) {
    for v in values {
        info!(
            "{=str}: {=str} = {=f32} {=str}",
            section, v.name, v.value, v.unit
        );
    }
}

/// Logs the vehicle, limits, gains and reference constants.
pub fn log_setup(s: &Setup) {
    log_values("vehicle", &report::vehicle_values(&s.vehicle));
    log_values("limits", &report::limits_values(&s.limits));
    log_values("gains", &report::gains_values(&s.gains));
    log_values("reference", &report::constants_values(&s.constants));
}

/// Logs a refused parameter set: what, the violated condition and its numbers.
pub fn log_refusal(what: &'static str, e: &ParameterError) {
    let r = report::refusal(e);
    error!(
        "{=str} refused: {=str} = {=f64} ({=str}; admissible ({=f64}, {=f64}))",
        what, r.name, r.value, r.requirement, r.low, r.high
    );
}

/// Logs the certificate's bounds and conditions, or its refusal.
pub fn log_certificate(certificate: &Result<Certificate<f32>, ParameterError>) {
    let c = match certificate {
        Ok(c) => c,
        Err(e) => return log_refusal("certificate", e),
    };
    log_values("bounds", &report::bound_values(c));
    // Every condition the gate checks: the paper's, then the integral action's and tilt
    // priority's when on (`Certificate::all_conditions`).
    for cond in c.all_conditions() {
        match report::condition_severity(cond) {
            Severity::Info => info!(
                "condition {=str}: holds = {=bool}, lhs = {=f32}, rhs = {=f32}, \
                 margin lhs/rhs = {=f32}",
                cond.name,
                cond.holds,
                cond.lhs,
                cond.rhs,
                report::condition_ratio(cond)
            ),
            Severity::Warn => warn!(
                "condition {=str}: holds = {=bool}, lhs = {=f32}, rhs = {=f32}, \
                 margin lhs/rhs = {=f32} ({=str}); the bounds are not guaranteed",
                cond.name,
                cond.holds,
                cond.lhs,
                cond.rhs,
                report::condition_ratio(cond),
                cond.statement
            ),
        }
    }
    let violated = c.violations().count();
    if violated == 0 {
        info!(
            "certificate: all {=usize} conditions hold: {=str}",
            c.all_conditions().count(),
            report::certificate_verdict(c)
        );
    } else {
        error!(
            "certificate: {=usize} of {=usize} conditions violated: {=str}",
            violated,
            c.all_conditions().count(),
            report::certificate_verdict(c)
        );
    }
}

/// Logs the pipeline's boot report (certificate and mixer fit).
pub fn log_boot_report(r: &BootReport) {
    log_certificate(&Ok(r.certificate));
    match r.thrust {
        ThrustChoice::Norm => {
            info!("thrust: norm (T = m|u|): the box spans Theorem 1's [T_min, T_max]")
        }
        ThrustChoice::VerticalPriority { ramp, floor } => info!(
            "thrust: vertical-priority (no-dive), floor {=f32} N, ramp {=f32}: the box spans \
             [floor, T_max] = [{=f32}, {=f32}] N",
            floor, ramp, floor, r.certificate.bounds.thrust_max
        ),
    }
    let f = &r.a_priori_fit;
    info!(
        "mixer fit: thrust needed [{=f32}, {=f32}] N, rotors give [{=f32}, {=f32}] N \
         (shortfall {=f32}, {=f32} N); 4 f_max = {=f32} N",
        f.thrust_needed[0],
        f.thrust_needed[1],
        f.thrust_capacity[0],
        f.thrust_capacity[1],
        f.thrust_shortfall[0],
        f.thrust_shortfall[1],
        r.thrust_capacity
    );
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        info!(
            "mixer fit: torque {=str}: needed {=f32} N m, rotors give {=f32} N m at the \
             box corners ({=f32} N m alone), shortfall {=f32} N m",
            axis,
            f.torque_needed[i],
            f.torque_capacity[i],
            f.torque_single_axis[i],
            f.torque_shortfall[i]
        );
    }
    if r.airmode {
        info!(
            "airmode: on, keeps {=f32} of each rotor's range free below its top and {=f32} above \
             its bottom: the thrust moves to where the rotors realise the law's torque; the gate \
             fits the thrust interval at zero torque and each certified torque at some thrust \
             (its shadow; docs/airmode.md)",
            r.required_margin, r.airmode_low_margin
        );
    } else {
        info!("airmode: off: the gate fits the certified set over the whole thrust interval");
    }
    // Each rotor fit the gate checks, in its order: the certified set (and the local regime's),
    // or airmode's thrust interval and shadows.
    match &r.fits {
        Some(fits) => {
            for f in fits.as_slice() {
                let verdict = report::fit_verdict(f.margin, r.required_margin);
                if f.margin >= r.required_margin {
                    info!(
                        "mixer fit: {=str} margin {=f32} of the rotor range (required {=f32}): \
                         {=str} [{=str}]",
                        f.what, f.margin, r.required_margin, verdict, f.name
                    );
                } else {
                    error!(
                        "mixer fit: {=str} margin {=f32} of the rotor range (required {=f32}): \
                         {=str} [{=str}]",
                        f.what, f.margin, r.required_margin, verdict, f.name
                    );
                }
            }
        }
        None => error!("mixer fit: the thrust interval is refused (see the gate)"),
    }
    if let Some(a) = r.aligned_margin {
        let verdict = report::convergence_verdict(a, r.required_margin);
        if a >= r.required_margin {
            info!(
                "airmode: aligned feedforward margin {=f32} over Theorem 1's [T_min, T_max] \
                 (required {=f32}): {=str} (docs/airmode.md)",
                a, r.required_margin, verdict
            );
        } else {
            warn!(
                "airmode: aligned feedforward margin {=f32} over Theorem 1's [T_min, T_max] \
                 (required {=f32}): {=str} (docs/airmode.md)",
                a, r.required_margin, verdict
            );
        }
    }
    match r.gate {
        Ok(_) => info!("gate: certificate holds and set fits; arming allowed"),
        Err(f) => error!(
            "gate: NOT certified: {=str} (lhs = {=f32}, rhs = {=f32}); arming refused unless \
             the build allows uncertified set-ups",
            f.condition, f.lhs, f.rhs
        ),
    }
}

/// Logs which flight file the firmware flies: vehicle name and source, the file, the
/// `[design]` fields, and (loudly) whether this build may arm an uncertified set-up.
pub fn log_identity(config: &crate::config::FlightConfig) {
    let id = &config.identity;
    info!("flight: vehicle {=str} ({=str})", id.name, id.source);
    info!("flight: file {=str}", id.file);
    for d in id.design {
        info!("flight: design {=str} = {=str}", d.key, d.value);
    }
    info!(
        "flight: design margin = {=f32} (box-fit headroom required, fraction of the rotor range)",
        config.box_margin
    );
    match &config.gains.velocity_limit {
        None => info!("flight: position feedback: the paper's -sat(k_p z1 + k_v z2)"),
        Some(v) => info!(
            "flight: position feedback: velocity-limited, speed limit {=f32} m/s, braking \
             {=f32} m/s^2 (the paper's law near the reference; the same certificate)",
            v.speed, v.braking
        ),
    }
    if let Some(b) = config.gains.velocity_limit.and_then(|v| v.vertical) {
        info!(
            "flight: position feedback: vertical braking {=f32} m/s^2 above the reference, \
             {=f32} m/s^2 below (the vertical channel's levels)",
            b.up, b.down
        );
    }
    match config.gains.position.saturation_shape {
        controller_core::PositionSaturation::Componentwise => info!(
            "flight: position saturation: componentwise (the paper's; |ubar_p| < sqrt(3) M_p)"
        ),
        controller_core::PositionSaturation::Norm => {
            info!("flight: position saturation: norm (|ubar_p| < M_p; docs/position-saturation.md)")
        }
    }
    match &config.gains.position.vertical {
        None => info!("flight: vertical channel: as the horizontal one (M_p on every axis)"),
        Some(v) => {
            info!(
                "flight: vertical channel apart: its own braking and descent levels and filters \
                 (docs/vertical-channel.md)"
            );
            log_values("vertical", &report::vertical_values(v));
        }
    }
    match &config.gains.local {
        None => info!("flight: local regime: off (one set of position gains)"),
        Some(l) => {
            info!(
                "flight: local regime: on: faster position gains while the attitude energy is at \
                 most E_in, the global ones again above E_out (docs/envelope-design.md)"
            );
            log_values("local", &report::local_values(l));
            if let Some(f) = &l.vertical {
                log_values("local vertical", &report::local_vertical_values(f));
            }
            if let Some(a) = &l.attitude {
                info!("flight: local regime: its own attitude law (E is that law's energy)");
                log_values("local attitude", &report::local_attitude_values(a));
            }
            if let Some(b) = l.braking {
                info!("flight: local regime: its own braking {=f32} m/s^2", b);
            }
        }
    }
    match config.gains.lemma1 {
        controller_core::Lemma1Form::Paper => {
            info!("flight: Lemma 1: as the paper states it (U_wd_dot)")
        }
        controller_core::Lemma1Form::Tangential => info!(
            "flight: Lemma 1: tangential form (U_wd_dot from the parts of rho'' and ups'' that \
             w_d' reads; docs/tangential-lemma1.md)"
        ),
        controller_core::Lemma1Form::DesiredFrame => info!(
            "flight: Lemma 1: tangential form, Theorem 2's per-axis conditions on the desired \
             frame's norms of w_d, w_d' (docs/torque-set.md)"
        ),
    }
    if config.allow_uncertified {
        error!(
            "flight: UNCERTIFIED BUILD (feature uncertified-paper): this firmware arms set-ups \
             whose certificate fails or whose box does not fit; the a-priori bounds are NOT \
             guaranteed. Never fly it."
        );
    }
}

/// Logs the MAVLink link's trust and signing set-up: whether the build holds a key, and who
/// may install or change one with `SETUP_SIGNING` (docs/mavlink.md, "Signing").
pub fn log_link(config: &crate::config::FlightConfig) {
    let key = if config.signing_key.is_some() {
        "key from the build"
    } else {
        "no key yet"
    };
    match config.link_trust {
        LinkTrust::Trusted => warn!(
            "link: trusted (wired console), {=str}: SETUP_SIGNING taken unsigned while \
             disarmed; never put this link on a radio",
            key
        ),
        LinkTrust::Untrusted => info!(
            "link: untrusted (radio or unknown), {=str}: SETUP_SIGNING taken only signed with \
             the key in force, while disarmed",
            key
        ),
    }
}

/// Logs why the pipeline refused its configuration.
pub fn log_boot_error(e: &BootError) {
    match e {
        BootError::Parameter(p) => log_refusal("pipeline", p),
        BootError::Mixer(MixerError::SingularGeometry) => {
            error!("pipeline refused: rotor geometry is singular")
        }
        BootError::Mixer(MixerError::BadThrustRange) => {
            error!("pipeline refused: rotor thrust range empty or not finite")
        }
        BootError::MotorOrder(_) => {
            error!("pipeline refused: FIRMWARE_HIL_MOTOR_ORDER needs one rotor per quadrant")
        }
    }
}

/// Logs the flight file's identity and the set-up (`config` with its demo mission's constants),
/// builds the pipeline and logs its boot report; on a refusal logs why and returns `None` (the board then keeps the motors
/// stopped).
pub fn build_pipeline(
    config: &crate::config::FlightConfig,
) -> Option<crate::pipeline::FlightPipeline> {
    use controller_core::Trajectory;
    log_identity(config);
    log_link(config);
    log_setup(&Setup {
        vehicle: config.vehicle,
        limits: config.limits,
        gains: config.gains,
        constants: config.mission.constants(),
    });
    match crate::pipeline::FlightPipeline::new(config) {
        Ok(p) => {
            log_boot_report(&p.boot_report());
            Some(p)
        }
        Err(e) => {
            log_boot_error(&e);
            None
        }
    }
}
