//! What the firmware computes and reports at boot, as plain values: the set-up (vehicle, limits,
//! gains, trajectory constants), the a-priori bound certificate of
//! [`controller_core::certify`] and the controller built from the set-up.
//!
//! `main.rs` formats these with defmt; controller-core has no defmt support, so every number is
//! flattened here into a name, an `f32` and a unit.

use controller_core::{
    certify, Certificate, Condition, Controller, FilterStart, Gains, Limits, LocalAttitude,
    LocalGains, ParameterError, ReferenceTrajectory, Trajectory, TrajectoryConstants, Vehicle,
    VerticalChannel,
};

/// The parameters the firmware flies with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Rigid-body parameters.
    pub vehicle: Vehicle<f32>,
    /// Actuator limits.
    pub limits: Limits<f32>,
    /// Controller gains.
    pub gains: Gains<f32>,
    /// Assumption 1 constants of the reference the controller must accept.
    pub constants: TrajectoryConstants<f32>,
}

impl Setup {
    /// Section VI of the paper: its quadrotor, limits and Table I gains, with the constants of
    /// its helix reference.
    pub fn paper() -> Self {
        Self {
            vehicle: Vehicle::paper(),
            limits: Limits::paper(),
            gains: Gains::paper(),
            constants: ReferenceTrajectory::<f32>::paper_helix().constants(),
        }
    }
}

/// One named number of the boot banner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Value {
    /// Name as in the paper (ASCII), e.g. `"k_p"`.
    pub name: &'static str,
    /// The value.
    pub value: f32,
    /// SI unit, `""` if dimensionless.
    pub unit: &'static str,
}

const fn value(name: &'static str, value: f32, unit: &'static str) -> Value {
    Value { name, value, unit }
}

/// `m`, `J_11`, `J_22`, `J_33`, `g`.
pub fn vehicle_values(v: &Vehicle<f32>) -> [Value; 5] {
    [
        value("m", v.mass, "kg"),
        value("J_11", v.inertia[0], "kg m^2"),
        value("J_22", v.inertia[1], "kg m^2"),
        value("J_33", v.inertia[2], "kg m^2"),
        value("g", v.gravity, "m/s^2"),
    ]
}

/// `T_max` and the per-axis `tau_max` of the actuators.
pub fn limits_values(l: &Limits<f32>) -> [Value; 4] {
    [
        value("T_max", l.thrust_max, "N"),
        value("tau_max_1", l.torque_max[0], "N m"),
        value("tau_max_2", l.torque_max[1], "N m"),
        value("tau_max_3", l.torque_max[2], "N m"),
    ]
}

/// The gains of Table I, in its order, then `delta` and `alpha`.
pub fn gains_values(g: &Gains<f32>) -> [Value; 11] {
    let (p, a) = (&g.position, &g.attitude);
    [
        value("k_p", p.kp, "1/s^2"),
        value("k_v", p.kv, "1/s"),
        value("k_f", p.kf, "1/s"),
        value("k_s", p.ks, "1/s"),
        value("M_p", p.saturation, "m/s^2"),
        value("k_theta", a.k_mrp, "N m"),
        value("k_omega", a.k_omega, "N m s/rad"),
        value("M_theta", a.mrp_saturation, "N m"),
        value("M_omega", a.omega_saturation, "N m"),
        value("delta", g.hysteresis, ""),
        value("alpha", g.reset_threshold, ""),
    ]
}

/// The vertical channel apart (extension, docs/vertical-channel.md): its upward (braking) and
/// downward levels and its filter bandwidths.
pub fn vertical_values(v: &VerticalChannel<f32>) -> [Value; 4] {
    [
        value("M_up", v.up, "m/s^2"),
        value("M_down", v.down, "m/s^2"),
        value("k_f_z", v.kf, "1/s"),
        value("k_s_z", v.ks, "1/s"),
    ]
}

/// The envelope design's local regime (extension, docs/envelope-design.md): its position gains
/// and the attitude energy levels of its switch (`E_in`: the local gains take over at or below
/// it; `E_out`: the global gains take back over above it).
pub fn local_values(l: &LocalGains<f32>) -> [Value; 7] {
    [
        value("k_p_local", l.kp, "1/s^2"),
        value("k_v_local", l.kv, "1/s"),
        value("k_f_local", l.kf, "1/s"),
        value("k_s_local", l.ks, "1/s"),
        value("M_p_local", l.saturation, "m/s^2"),
        value("E_in", l.energy_in, "J"),
        value("E_out", l.energy_out, "J"),
    ]
}

/// The local regime's own vertical channel: its filter bandwidths and its levels (extension,
/// docs/envelope-design.md).
pub fn local_vertical_values(f: &VerticalChannel<f32>) -> [Value; 4] {
    [
        value("k_f_z_local", f.kf, "1/s"),
        value("k_s_z_local", f.ks, "1/s"),
        value("M_up_local", f.up, "m/s^2"),
        value("M_down_local", f.down, "m/s^2"),
    ]
}

/// The local regime's own attitude law (extension, docs/envelope-design.md): its radial MRP
/// gain and level, and its roll damping gain and level (tilt priority's first axis, or the
/// paper's radial `k_ω`, `M_ω`).
pub fn local_attitude_values(a: &LocalAttitude<f32>) -> [Value; 4] {
    let (gain, level) = match &a.tilt_priority {
        Some(t) => (t.omega_gains.x, t.omega_levels.x),
        None => (a.attitude.k_omega, a.attitude.omega_saturation),
    };
    [
        value("k_theta_local", a.attitude.k_mrp, "N m"),
        value("M_theta_local", a.attitude.mrp_saturation, "N m"),
        value("k_omega_roll_local", gain, "N m s/rad"),
        value("M_omega_roll_local", level, "N m"),
    ]
}

/// The Assumption 1 constants of the reference.
pub fn constants_values(k: &TrajectoryConstants<f32>) -> [Value; 6] {
    [
        value("K_a12", k.horizontal_acceleration, "m/s^2"),
        value("K_a3", k.vertical_acceleration, "m/s^2"),
        value("K_j", k.jerk, "m/s^3"),
        value("K_s", k.snap, "m/s^4"),
        value("K_nu_dot", k.heading_rate, "1/s"),
        value("K_nu_ddot", k.heading_acceleration, "1/s^2"),
    ]
}

/// The bounds the certificate guarantees when its conditions hold: the thrust interval of
/// Theorem 1, Lemma 1's bounds on `omega_d` and its derivative, and Theorem 2's per-axis torque.
pub fn bound_values(c: &Certificate<f32>) -> [Value; 7] {
    let b = &c.bounds;
    [
        value("T_min", b.thrust_min, "N"),
        value("T_max", b.thrust_max, "N"),
        value("U_wd", b.angular_velocity, "rad/s"),
        value("U_wd_dot", b.angular_acceleration, "rad/s^2"),
        value("tau_bound_1", b.torque_max[0], "N m"),
        value("tau_bound_2", b.torque_max[1], "N m"),
        value("tau_bound_3", b.torque_max[2], "N m"),
    ]
}

/// How loudly to report a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// Informational.
    Info,
    /// Worth an operator's attention; the firmware goes on.
    Warn,
}

/// A condition that holds is informational; a violated one is a warning: the bounds are then
/// not guaranteed (the paper's conditions are sufficient, not necessary), and the pipeline
/// refuses to arm ([`crate::pipeline::BootReport::gate`]) unless the build allows uncertified
/// set-ups.
pub fn condition_severity(c: &Condition<f32>) -> Severity {
    if c.holds {
        Severity::Info
    } else {
        Severity::Warn
    }
}

/// A condition's margin `lhs / rhs` \[dimensionless\]: above 1 when a strict condition holds,
/// and how far it is from binding (`+inf` when `rhs` is 0, e.g. `g > K_a3` on a hover).
pub fn condition_ratio(c: &Condition<f32>) -> f32 {
    c.lhs / c.rhs
}

/// The banner's verdict on the certificate: `"certificate holds"` when every condition holds.
pub fn certificate_verdict(c: &Certificate<f32>) -> &'static str {
    if c.violations().next().is_none() {
        "certificate holds"
    } else {
        "certificate FAILS"
    }
}

/// The banner's verdict on the rotor fit: `"set fits"` when the certified `(T, τ)` set leaves
/// at least `required` of every rotor's range free (`margin` from
/// [`crate::mixer::Mixer::set_margin`]); NaN fails.
pub fn fit_verdict(margin: f32, required: f32) -> &'static str {
    if margin >= required {
        "set fits"
    } else if margin >= 0.0 {
        "set fits WITHOUT the required margin"
    } else {
        "set does NOT fit"
    }
}

/// The banner's verdict on airmode's convergence from the aligned fit's `margin` (the
/// feedforward at zero attitude error over Theorem 1's interval,
/// [`crate::pipeline::gate::aligned_margin`]) and the `required` one: proven when it fits with
/// the margin (docs/airmode.md), else shown by simulation only; NaN is not a proof.
pub fn convergence_verdict(margin: f32, required: f32) -> &'static str {
    if margin >= required {
        "convergence proven (the aligned feedforward fits Theorem 1's interval)"
    } else {
        "convergence shown by simulation only (the aligned feedforward does not fit Theorem 1's \
         interval with the margin)"
    }
}

/// A [`ParameterError`] flattened for logging: `name = value` breaks `requirement`, whose
/// admissible values are the open interval `(low, high)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refusal {
    /// The parameter or constant refused.
    pub name: &'static str,
    /// Its value.
    pub value: f64,
    /// The requirement it breaks.
    pub requirement: &'static str,
    /// Lower end of the admissible interval (`-inf` if none).
    pub low: f64,
    /// Upper end of the admissible interval (`+inf` if none).
    pub high: f64,
}

/// Flattens a [`ParameterError`] into a [`Refusal`].
pub fn refusal(e: &ParameterError) -> Refusal {
    match *e {
        ParameterError::NotPositive { name, value } => Refusal {
            name,
            value,
            requirement: "must be finite and > 0",
            low: 0.0,
            high: f64::INFINITY,
        },
        ParameterError::OutOfRange {
            name,
            value,
            low,
            high,
        } => Refusal {
            name,
            value,
            requirement: "must lie in the open interval",
            low,
            high,
        },
        ParameterError::SaturationTooLarge { saturation, limit } => Refusal {
            name: "M_p",
            value: saturation,
            requirement: "M_p < g - K_a3 (Section IV)",
            low: 0.0,
            high: limit,
        },
        ParameterError::BadTrajectoryConstant { name, value } => Refusal {
            name,
            value,
            requirement: "trajectory constant must be finite and >= 0",
            low: 0.0,
            high: f64::INFINITY,
        },
    }
}

/// Everything computed at boot from a [`Setup`].
#[derive(Clone, Copy, Debug)]
pub struct Boot {
    /// The set-up.
    pub setup: Setup,
    /// The a-priori bound certificate, filters starting at zero (as [`Controller::new`] does),
    /// or why the set-up was refused.
    pub certificate: Result<Certificate<f32>, ParameterError>,
    /// The controller, or why it was refused.
    pub controller: Result<Controller<f32>, ParameterError>,
}

/// Certifies `setup` and builds the controller for it. Never panics: refusals are values.
pub fn boot(setup: Setup) -> Boot {
    let Setup {
        vehicle,
        limits,
        gains,
        constants,
    } = setup;
    Boot {
        setup,
        certificate: certify(&vehicle, &limits, &gains, &constants, FilterStart::Zero),
        controller: Controller::new(vehicle, gains, &constants),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's set-up in f32: the thrust interval of Theorem 1 as printed, one violated
    /// condition (Theorem 2 yaw, as in f64), and a controller.
    #[test]
    fn paper_boot_in_f32() {
        let b = boot(Setup::paper());
        let c = b.certificate.expect("the paper's set-up is certified");
        let bounds = bound_values(&c);
        assert_eq!(bounds[0].name, "T_min");
        assert!((bounds[0].value - 3.51).abs() < 0.005, "{:?}", bounds[0]);
        assert!((bounds[1].value - 6.19).abs() < 0.005, "{:?}", bounds[1]);
        for (v, i) in bounds[4..].iter().zip(0..3) {
            assert_eq!(v.value, c.bounds.torque_max[i]);
        }
        let warned: Vec<_> = c
            .conditions
            .iter()
            .filter(|c| condition_severity(c) == Severity::Warn)
            .map(|c| c.name)
            .collect();
        assert_eq!(warned, ["theorem2.torque_max_yaw"]);
        assert!(b.controller.is_ok());
    }

    /// The f32 certificate agrees with the f64 one the host tools use.
    #[test]
    fn f32_certificate_matches_f64() {
        let c32 = boot(Setup::paper()).certificate.unwrap();
        let c64 = certify(
            &Vehicle::<f64>::paper(),
            &Limits::paper(),
            &Gains::paper(),
            &ReferenceTrajectory::<f64>::paper_helix().constants(),
            FilterStart::Zero,
        )
        .unwrap();
        for (a, b) in c32.conditions.iter().zip(c64.conditions.iter()) {
            assert_eq!((a.name, a.holds), (b.name, b.holds));
            let rel = |x: f32, y: f64| ((x as f64 - y) / y).abs();
            assert!(
                rel(a.lhs, b.lhs) < 1e-5 && rel(a.rhs, b.rhs) < 1e-5,
                "{}",
                a.name
            );
        }
    }

    #[test]
    fn banner_values_follow_the_setup() {
        let s = Setup::paper();
        let v = vehicle_values(&s.vehicle);
        assert_eq!((v[0].name, v[0].value, v[0].unit), ("m", 0.46, "kg"));
        assert_eq!(v[3].value, 5.3e-3);
        let l = limits_values(&s.limits);
        assert_eq!((l[0].name, l[0].value), ("T_max", 7.0));
        let g = gains_values(&s.gains);
        let names: Vec<_> = g.iter().map(|v| v.name).collect();
        assert_eq!(
            names,
            [
                "k_p", "k_v", "k_f", "k_s", "M_p", "k_theta", "k_omega", "M_theta", "M_omega",
                "delta", "alpha"
            ]
        );
        assert_eq!(g[5].value, 100.0);
        assert_eq!(g[10].value, 0.25);
        let k = constants_values(&s.constants);
        assert_eq!(k[1].value, s.constants.vertical_acceleration);
        // Every banner name is unique.
        let mut all: Vec<_> = v
            .iter()
            .chain(&l)
            .chain(&g)
            .chain(&k)
            .map(|v| v.name)
            .collect();
        let n = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), n);
    }

    /// The local attitude law's banner values are its radial MRP gain and level and its roll
    /// damping, tilt priority's where it has one (the paper's `k_ω`, `M_ω` are then unused).
    #[test]
    fn local_attitude_banner_values() {
        let attitude = controller_core::attitude_control::AttitudeGains {
            k_mrp: 40.0,
            k_omega: 0.3,
            mrp_saturation: 0.2,
            omega_saturation: 0.4,
        };
        let paper = local_attitude_values(&LocalAttitude {
            attitude,
            tilt_priority: None,
        });
        let tilt = local_attitude_values(&LocalAttitude {
            attitude,
            tilt_priority: Some(controller_core::TiltPriorityGains {
                trace_weights: nalgebra::Vector3::new(0.01, 0.01, 0.8),
                omega_gains: nalgebra::Vector3::new(0.25, 0.25, 0.05),
                omega_levels: nalgebra::Vector3::new(0.6, 0.6, 0.01),
                turn_over: None,
            }),
        });
        let read = |v: &[Value; 4]| v.map(|x| (x.name, x.value));
        assert_eq!(
            read(&paper),
            [
                ("k_theta_local", 40.0),
                ("M_theta_local", 0.2),
                ("k_omega_roll_local", 0.3),
                ("M_omega_roll_local", 0.4)
            ]
        );
        assert_eq!(
            read(&tilt)[2..],
            [("k_omega_roll_local", 0.25), ("M_omega_roll_local", 0.6)]
        );
    }

    /// The local regime's banner values are its gains and energy levels, with units, and their
    /// names differ from Table I's; airmode's convergence verdict needs the aligned fit to leave
    /// the required margin.
    #[test]
    fn local_regime_and_airmode_banner_values() {
        let l = LocalGains {
            kp: 25.0,
            kv: 10.0,
            kf: 3.0,
            ks: 9.0,
            saturation: 2.0,
            energy_in: 1.0e-4,
            energy_out: 2.0e-4,
            vertical: Some(VerticalChannel {
                up: 2.0,
                down: 0.5,
                kf: 6.0,
                ks: 20.0,
            }),
            attitude: None,
            braking: None,
        };
        let v = local_values(&l);
        let named: Vec<_> = v.iter().map(|v| (v.name, v.value, v.unit)).collect();
        assert_eq!(
            named,
            [
                ("k_p_local", 25.0, "1/s^2"),
                ("k_v_local", 10.0, "1/s"),
                ("k_f_local", 3.0, "1/s"),
                ("k_s_local", 9.0, "1/s"),
                ("M_p_local", 2.0, "m/s^2"),
                ("E_in", 1.0e-4, "J"),
                ("E_out", 2.0e-4, "J")
            ]
        );
        let table_i = gains_values(&Gains::paper());
        assert!(v.iter().all(|v| table_i.iter().all(|g| g.name != v.name)));
        let vertical = local_vertical_values(&VerticalChannel {
            up: 2.0,
            down: 0.5,
            kf: 6.0,
            ks: 20.0,
        });
        let global_vertical = vertical_values(&VerticalChannel {
            up: 4.0,
            down: 1.0,
            kf: 1.5,
            ks: 2.5,
        });
        assert_eq!(
            vertical.map(|v| (v.name, v.value)),
            [
                ("k_f_z_local", 6.0),
                ("k_s_z_local", 20.0),
                ("M_up_local", 2.0),
                ("M_down_local", 0.5)
            ]
        );
        assert!(vertical
            .iter()
            .all(|v| global_vertical.iter().all(|g| g.name != v.name)));
        assert!(convergence_verdict(0.06, 0.05).starts_with("convergence proven"));
        for below in [0.04, -0.1, f32::NAN] {
            assert!(convergence_verdict(below, 0.05).contains("simulation only"));
        }
    }

    /// A refused set-up yields refusals, not a panic, from both the certificate and the controller.
    #[test]
    fn refused_setup_is_reported() {
        let mut s = Setup::paper();
        s.gains.position.saturation = 9.7;
        let b = boot(s);
        let r = refusal(&b.certificate.unwrap_err());
        assert_eq!(r.name, "M_p");
        assert!((r.value - 9.7).abs() < 1e-6);
        assert!(r.high < r.value);
        assert!(b.controller.is_err());

        let mut s = Setup::paper();
        s.gains.reset_threshold = 1.5;
        let r = refusal(&boot(s).controller.unwrap_err());
        assert_eq!((r.name, r.low, r.high), ("alpha", 0.0, 1.0));

        let mut s = Setup::paper();
        s.vehicle.mass = f32::NAN;
        let r = refusal(&boot(s).certificate.unwrap_err());
        assert_eq!(r.name, "mass");
        assert!(r.value.is_nan());

        let mut s = Setup::paper();
        s.constants.jerk = -1.0;
        let r = refusal(&boot(s).certificate.unwrap_err());
        assert_eq!((r.name, r.value), ("K_j", -1.0));
    }

    /// The verdicts: the paper's certificate fails (Theorem 2 yaw) and its box does not fit;
    /// the built x500 set-up's certificate holds and its box fits with the file's margin.
    #[test]
    #[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
    fn verdicts() {
        let paper = boot(Setup::paper()).certificate.unwrap();
        assert_eq!(certificate_verdict(&paper), "certificate FAILS");
        let yaw = paper
            .conditions
            .iter()
            .find(|c| c.name == "theorem2.torque_max_yaw")
            .unwrap();
        assert!(condition_ratio(yaw) < 1.0);
        assert_eq!(fit_verdict(0.07, 0.05), "set fits");
        assert_eq!(
            fit_verdict(0.02, 0.05),
            "set fits WITHOUT the required margin"
        );
        assert_eq!(fit_verdict(-0.1, 0.05), "set does NOT fit");
        assert_eq!(fit_verdict(f32::NAN, 0.05), "set does NOT fit");

        let c = crate::config::FlightConfig::built();
        let p = crate::pipeline::FlightPipeline::new(&c).unwrap();
        let r = p.boot_report();
        assert_eq!(certificate_verdict(&r.certificate), "certificate holds");
        assert!(r
            .certificate
            .conditions
            .iter()
            .all(|c| condition_ratio(c) >= 1.0));
        assert_eq!(fit_verdict(r.fit_margin, r.required_margin), "set fits");
    }
}
