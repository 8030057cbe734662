//! One SIL flight: the firmware's flight software against the rotor-level plant, in lockstep, with
//! the sensors, link and failures of the scenario.

use super::record::{SilRecord, SilSummary};
use super::sensors::Rng;
use super::setup::SilSetup;
use super::{encode, schedule, Delivery, FlightSoftware, Motors};
use crate::model::plant::{PlantInput, RigidBody};
use anyhow::Result;
use firmware::link::mavlink::dialects::common::MavMessage;
use firmware::pipeline::{BootReport, MotorOutput};
use firmware::safety::FlightState;
use nalgebra::{Matrix4, UnitQuaternion, Vector3, Vector4};
use std::collections::VecDeque;

/// The simulation loop of [`run`](super::run) for any flight software: plant, IMU, motion capture and
/// ground-station frames, motors, records (one per control tick, `observe`) and the summary.
/// `boot` is the set-up's boot report (certificate, rotor fit) and `effectiveness` the
/// mixer's matrix (rotor thrusts \[N\] → `(T [N], τ [N m])`), both from
/// `FlightPipeline::new(&setup.flight)`.
///
/// Errors: whatever `software` reports (crash, stall, transport).
pub fn fly(
    setup: &SilSetup,
    boot: &BootReport,
    effectiveness: &Matrix4<f64>,
    software: &mut impl FlightSoftware,
    mut observe: impl FnMut(&SilRecord),
) -> Result<SilSummary> {
    let cfg = setup.flight;
    let b = *effectiveness;
    let body = RigidBody {
        mass: f64::from(cfg.vehicle.mass) * setup.plant_mass_factor,
        inertia: cfg.vehicle.inertia.cast::<f64>(),
        gravity: f64::from(cfg.vehicle.gravity),
    };
    let mut rng = Rng::new(setup.seed);
    let h = 1e-3;
    let hold_us = (setup.hold_s * 1e6).round() as u64;
    let end_us = hold_us + (setup.duration_s * 1e6).round() as u64;
    let rel = |t_us: u64| (t_us as f64 - hold_us as f64) * 1e-6;
    let imu_every = (1e6 / setup.imu.rate_hz).round().max(1.0) as u64;
    // Pose times on their own clock (e.g. 300 Hz is not a whole number of 1 ms steps): a pose
    // is measured at the first step at or after each nominal time.
    let mocap_period_us = 1e6 / setup.mocap.rate_hz;
    let mut next_mocap_us = 0.0f64;
    let tick_every = cfg.control_rate.period_us();
    let latency_us = (setup.mocap.latency_s * 1e6).round() as u64;

    let mut state = setup.initial;
    let mut motors = Motors { thrust: [0.0; 4] };
    let mut queue: VecDeque<Delivery> = VecDeque::new();
    let mut commands: Vec<(u64, MavMessage)> = setup
        .commands
        .iter()
        .map(|(t, m)| {
            (
                ((hold_us as f64) + t * 1e6).max(0.0).round() as u64,
                m.clone(),
            )
        })
        .collect();
    commands.sort_by_key(|c| c.0);
    let mut next_command = 0;
    let mut seq = 0u8;
    let mut out = MotorOutput {
        throttle: [0.0; 4],
        armed: false,
    };

    let mut summary = SilSummary {
        scenario: setup.name.clone(),
        seed: setup.seed,
        vehicle: cfg.identity.name.to_string(),
        certificate_holds: boot.certificate.violations().next().is_none(),
        fit_margin: f64::from(boot.fit_margin),
        required_fit_margin: f64::from(boot.required_margin),
        a_priori_box_fits: boot.a_priori_fit.fits,
        a_priori_box_shortfall: {
            let f = &boot.a_priori_fit;
            [
                f64::from(f.thrust_shortfall[0]),
                f64::from(f.thrust_shortfall[1]),
                f64::from(f.torque_shortfall[0]),
                f64::from(f.torque_shortfall[1]),
                f64::from(f.torque_shortfall[2]),
            ]
        },
        violated_conditions: boot
            .certificate
            .violations()
            .map(|c| c.name.to_string())
            .collect(),
        events: Vec::new(),
        final_position_error_m: f64::NAN,
        rms_position_error_last_10s_m: f64::NAN,
        below_5cm_from_s: None,
        rotor_thrust_max_N: 0.0,
        rotor_thrust_min_armed_N: f64::INFINITY,
        rotor_range_N: [
            f64::from(cfg.rotors.thrust_min),
            f64::from(cfg.rotors.thrust_max),
        ],
        throttle_violations: 0,
        spun_while_disarmed: 0,
        mixer_saturated_ticks: 0,
        link_frames: [0; 3],
        telemetry_frames: [0; 2],
        last_pose_s: None,
        failsafe_at_s: None,
        disarmed_at_s: None,
        failsafe_max_tilt_rad: None,
        failsafe_mean_vz_m_s: None,
        final_state: String::new(),
        non_finite: 0,
        refused_commands: 0,
    };
    let mut errors: Vec<(f64, f64)> = Vec::new();
    // True positions at the last ticks, for estimates that arrive late (PIL telemetry).
    const TRUTH_KEPT: usize = 64;
    let mut truth: VecDeque<(u64, Vector3<f64>)> = VecDeque::with_capacity(TRUTH_KEPT);
    let mut below_since: Option<f64> = None;
    let (mut fs_vz_sum, mut fs_vz_n) = (0.0, 0u32);
    // The body's actual acceleration over the last plant step [m/s²], inertial (including
    // ground contacts): the accelerometer reads it plus gravity's reaction, `a + g e₃`.
    let mut acceleration = Vector3::zeros();

    let mut t_us = 0u64;
    while t_us <= end_us {
        let released = t_us >= hold_us;
        // Ground-station commands due now.
        while next_command < commands.len() && commands[next_command].0 <= t_us {
            let frame = encode(&commands[next_command].1, &mut seq);
            schedule(&mut queue, t_us, &frame, &mut rng, false);
            next_command += 1;
        }
        // Motion capture: measure now, deliver after the latency.
        if t_us as f64 >= next_mocap_us {
            next_mocap_us += mocap_period_us;
            let t = rel(t_us);
            let out_of_service = setup.pose_outage.is_some_and(|(a, b)| t >= a && t < b);
            if !out_of_service && rng.uniform() >= setup.mocap.dropout {
                let m = setup.mocap.measure(&mut rng, &state, t_us);
                let frame = encode(&m, &mut seq);
                schedule(&mut queue, t_us + latency_us, &frame, &mut rng, true);
            }
        }
        // Deliver due bytes (the queue is in time order except for latency-shifted poses).
        let mut i = 0;
        while i < queue.len() {
            if queue[i].at_us <= t_us {
                if let Some(d) = queue.remove(i) {
                    software.on_link_bytes(&d.bytes, t_us)?;
                    if d.pose_end && summary.failsafe_at_s.is_none() {
                        summary.last_pose_s = Some(rel(t_us));
                    }
                }
            } else {
                i += 1;
            }
        }
        // Specific force the IMU feels (body): the last step's acceleration plus gravity's
        // reaction (held still: just the reaction).
        let specific_force = state
            .attitude
            .inverse_transform_vector(&(acceleration + Vector3::z() * body.gravity));
        if t_us.is_multiple_of(imu_every) {
            let s = setup.imu.sample(&mut rng, &state, &specific_force, t_us);
            software.on_imu(&s)?;
        }
        if t_us.is_multiple_of(tick_every) {
            let report = software.control_tick(t_us)?;
            out = report.output;
            for (description, to) in report.events {
                let t = rel(t_us);
                match to {
                    Some(FlightState::Failsafe) => summary.failsafe_at_s = Some(t),
                    Some(FlightState::Disarmed) => summary.disarmed_at_s = Some(t),
                    Some(FlightState::Armed) | None => {}
                }
                summary.events.push((t, description));
            }
            for u in out.throttle {
                if !(u.is_finite() && (0.0..=1.0).contains(&u)) {
                    summary.throttle_violations += 1;
                }
            }
            if !out.armed && out.throttle.iter().any(|&u| u != 0.0) {
                summary.spun_while_disarmed += 1;
            }
            let flying = report.flying;
            let reference = report.reference;
            let err = if flying && report.state == FlightState::Armed {
                (state.position - reference).norm()
            } else {
                0.0
            };
            let t = rel(t_us);
            if released && report.state == FlightState::Armed && flying {
                errors.push((t, err));
                if err < 0.05 {
                    below_since.get_or_insert(t);
                } else {
                    below_since = None;
                }
            }
            let tilt = (state.attitude * Vector3::z()).z.clamp(-1.0, 1.0).acos();
            if report.state == FlightState::Failsafe {
                if let Some(fs) = summary.failsafe_at_s {
                    if t - fs >= 0.5 {
                        let m = summary.failsafe_max_tilt_rad.get_or_insert(0.0);
                        *m = m.max(tilt);
                        fs_vz_sum += state.velocity.z;
                        fs_vz_n += 1;
                    }
                }
            }
            let (roll, pitch, yaw) = state.attitude.euler_angles();
            if truth.len() == TRUTH_KEPT {
                truth.pop_front();
            }
            truth.push_back((t_us, state.position));
            let estimate_error = report.estimate.map_or(f64::NAN, |(at, est)| {
                truth
                    .iter()
                    .rev()
                    .find(|(t, _)| *t == at)
                    .map_or(f64::NAN, |(_, p)| (est - p).norm())
            });
            let record = SilRecord {
                t_s: t,
                x_m: state.position.x,
                y_m: state.position.y,
                z_m: state.position.z,
                x_ref_m: reference.x,
                y_ref_m: reference.y,
                z_ref_m: reference.z,
                estimate_error_m: estimate_error,
                position_error_m: err,
                roll_rad: roll,
                pitch_rad: pitch,
                yaw_rad: yaw,
                tilt_rad: tilt,
                state: report.state.name(),
                mode: report.mode.name(),
                thrust_N: report.thrust,
                torque_x_Nm: report.torque[0],
                torque_y_Nm: report.torque[1],
                torque_z_Nm: report.torque[2],
                rotor1_N: motors.thrust[0],
                rotor2_N: motors.thrust[1],
                rotor3_N: motors.thrust[2],
                rotor4_N: motors.thrust[3],
                throttle1: out.throttle[0],
                throttle2: out.throttle[1],
                throttle3: out.throttle[2],
                throttle4: out.throttle[3],
                vz_m_s: state.velocity.z,
            };
            observe(&record);
        }
        // Actuators and plant over [t, t + h].
        motors.step(&cfg, &out, h, setup.motor_time_constant_s);
        for &f in &motors.thrust {
            summary.rotor_thrust_max_N = summary.rotor_thrust_max_N.max(f);
            if out.armed {
                summary.rotor_thrust_min_armed_N = summary.rotor_thrust_min_armed_N.min(f);
            }
        }
        if released {
            let wrench = b * Vector4::from(motors.thrust);
            let input = PlantInput {
                thrust: wrench[0],
                torque: Vector3::new(wrench[1], wrench[2], wrench[3]),
                ..Default::default()
            };
            let before = state.velocity;
            state = body.rk4_step(&state, &input, h);
            // Flat ground: contact stops the body (no bounce, no sliding).
            if let Some(ground) = setup.ground_z.filter(|g| state.position.z < *g) {
                state.position.z = ground;
                state.velocity = Vector3::zeros();
                state.angular_velocity = Vector3::zeros();
            }
            acceleration = (state.velocity - before) / h;
            state.attitude = UnitQuaternion::new_normalize(*state.attitude.quaternion());
        }
        t_us += 1000;
    }

    let fin = software.finish()?;
    summary.final_position_error_m = errors.last().map_or(f64::NAN, |e| e.1);
    if let Some(&(t_end, _)) = errors.last() {
        let last: Vec<f64> = errors
            .iter()
            .filter(|(t, _)| *t > t_end - 10.0)
            .map(|e| e.1 * e.1)
            .collect();
        summary.rms_position_error_last_10s_m =
            (last.iter().sum::<f64>() / last.len() as f64).sqrt();
    }
    summary.below_5cm_from_s = below_since;
    summary.mixer_saturated_ticks = fin.mixer_saturations;
    summary.link_frames = fin.link_frames;
    summary.telemetry_frames = fin.telemetry_frames;
    summary.failsafe_mean_vz_m_s = (fs_vz_n > 0).then(|| fs_vz_sum / f64::from(fs_vz_n));
    summary.final_state = fin.state.name().to_string();
    summary.non_finite = fin.non_finite;
    summary.refused_commands = fin.refused_commands;
    if !summary.rotor_thrust_min_armed_N.is_finite() {
        summary.rotor_thrust_min_armed_N = 0.0;
    }
    Ok(summary)
}
