//! The local regime's torque set holds the law's torque: at random states inside the energy
//! level (any MRP error, `ω̃` and rotation it allows) and random desired-frame `ω_d`, `ω̇_d`
//! inside their bounds, the law's own torque never leaves the set in any direction.

use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;

use super::local_torque_set;
use crate::attitude_energy::{attitude_energy, energy_limits};
use crate::bounds::{certify, FilterStart};
use crate::gains::Gains;
use crate::mrp::rotation_from_mrp;
use crate::{Limits, TrajectoryConstants, Vehicle};

/// The attitude energy tests' gains with a position loop whose filters fit the local set.
fn gains(tilt: bool) -> Gains<f64> {
    let mut g = crate::attitude_energy::tests::gains(tilt);
    g.position.kf = 4.0;
    g.position.ks = 10.0;
    g.position.saturation = 3.0;
    g
}

/// The bounds of the local position gains `local` alone (over `g`'s), the filters anywhere in
/// their saturation set: what the local certificate computes, computed again.
fn local_alone(
    v: &Vehicle<f64>,
    g: &Gains<f64>,
    local: &crate::local_regime::LocalGains<f64>,
    constants: &TrajectoryConstants<f64>,
) -> crate::Bounds<f64> {
    let gains = Gains {
        position: local.position(&g.position),
        local: None,
        ..*g
    };
    certify(
        v,
        &Limits::paper(),
        &gains,
        constants,
        FilterStart::InSaturationBox,
    )
    .unwrap()
    .bounds
}

fn unit3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_map(|(x, y, z)| Vector3::new(x, y, z))
        .prop_filter("not zero", |v| v.norm() > 1e-3)
        .prop_map(|v| v.normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4_000))]

    /// Given an energy level `c`, a state inside it and desired-frame `(ω_d, ω̇_d)` inside the
    /// Lemma 1 per-axis bounds, the law's torque (feedback and feedforward, computed by the law
    /// itself) satisfies `dᵀτ ≤ h(d)` for random directions `d` of the local set.
    #[test]
    fn the_laws_torque_stays_in_the_local_set(
        tilt in proptest::bool::ANY,
        c in prop_oneof![1e-5..1e-3f64, 1e-3..0.2f64],
        mrp_dir in unit3(), mrp_share in 0.0..1.0f64,
        w_dir in unit3(), w_share in 0.0..1.0f64,
        wd in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        wdd in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        d in unit3(),
    ) {
        let g = gains(tilt);
        let v = Vehicle::<f64>::paper();
        let j = v.inertia;
        let b = certify(&v, &Limits::paper(), &g, &TrajectoryConstants::zero(), FilterStart::InSaturationBox)
            .unwrap()
            .bounds;
        let l = energy_limits(&g, &j, c);
        // A state with energy at most c: the MRP error and ω̃ scaled until it is.
        let mut mrp = mrp_dir * (mrp_share * l.mrp.min(1.0));
        let mut w = w_dir.component_mul(&l.omega_error) * w_share;
        let energy = |m: &Vector3<f64>, w: &Vector3<f64>| {
            attitude_energy(&g.attitude, g.tilt_priority.as_ref(), &j, m, w, &rotation_from_mrp(m))
        };
        while energy(&mrp, &w) > c {
            mrp *= 0.9;
            w *= 0.9;
        }
        let re: Matrix3<f64> = rotation_from_mrp(&mrp);
        let f = &b.desired_frame;
        let (x, y, z) = wd;
        let planar = Vector3::new(x, y, 0.0);
        let planar = if planar.norm() > 1.0 { planar.normalize() } else { planar };
        let omega_d = planar * f.tilt_rate + Vector3::z() * (z * f.yaw_rate);
        let (x, y, z) = wdd;
        let planar = Vector3::new(x, y, 0.0);
        let planar = if planar.norm() > 1.0 { planar.normalize() } else { planar };
        let omega_d_dot = planar * f.tilt_acceleration + Vector3::z() * (z * f.yaw_acceleration);
        let omega = w + re.transpose() * omega_d;
        let out = g.attitude_torque(&mrp, &omega, &re, &omega_d, &omega_d_dot, &j);
        let set = local_torque_set(&g, &j, &b, &l);
        let h = set.support(&d);
        prop_assert!(d.dot(&out.torque) <= h * (1.0 + 1e-9) + 1e-12, "{} > {h}", d.dot(&out.torque));
    }
}

/// Given global gains and a local regime whose level `M_p,L` is above `M_p`, when certified,
/// then the certificate's thrust interval is the hull of the two regimes' Theorem 1 intervals
/// (computed again here from the local gains alone), the local interval is the wider one, and
/// `local_regime.thrust_bound_within_actuator` compares the local `T_max` with the actuator's:
/// it holds with room and fails, by name, once the actuator is below the local `T_max` though
/// above the global one.
#[test]
fn a_wider_local_level_widens_the_certified_thrust_interval() {
    let mut g = gains(false);
    let v = Vehicle::<f64>::paper();
    let constants = TrajectoryConstants::<f64>::zero();
    let local = crate::local_regime::LocalGains {
        kp: 4.0,
        kv: 4.0,
        kf: 6.0,
        ks: 15.0,
        saturation: 3.5,
        energy_in: 1e-4,
        energy_out: 2e-4,
        vertical: None,
        attitude: None,
        braking: None,
    };
    let global_only = certify(&v, &Limits::paper(), &g, &constants, FilterStart::Zero).unwrap();
    g.local = Some(local);
    let local_alone = local_alone(&v, &g, &local, &constants);
    let both = |thrust_max: f64| {
        let limits = Limits {
            thrust_max,
            ..Limits::paper()
        };
        certify(&v, &limits, &g, &constants, FilterStart::Zero).unwrap()
    };
    let c = both(2.0 * local_alone.thrust_max);
    let (lo, hi) = (c.bounds.thrust_min, c.bounds.thrust_max);
    assert!(local_alone.thrust_max > global_only.bounds.thrust_max);
    assert!(local_alone.thrust_min < global_only.bounds.thrust_min);
    assert_eq!(lo, local_alone.thrust_min);
    assert_eq!(hi, local_alone.thrust_max);
    let named = |c: &crate::Certificate<f64>, name: &str| {
        c.all_conditions()
            .find(|k| k.name == name)
            .copied()
            .unwrap()
    };
    let held = named(&c, "local_regime.thrust_bound_within_actuator");
    assert!(held.holds && held.rhs == local_alone.thrust_max, "{held:?}");
    let between = 0.5 * (global_only.bounds.thrust_max + local_alone.thrust_max);
    let tight = both(between);
    assert!(named(&tight, "theorem1.thrust_bound_within_actuator").holds);
    let failed = named(&tight, "local_regime.thrust_bound_within_actuator");
    assert!(!failed.holds && failed.lhs == between, "{failed:?}");
    assert!(named(&c, "local_regime.saturation_margin").holds);
}

/// Given the paper's law and energy levels from small to past the MRP's cap, the joint feedback
/// radius is at least the feedback norm's largest value over a dense scan of the energy's split
/// between the MRP potential and the kinetic energy (computed here from the two terms'
/// formulas), at most that plus one interval's rise of each term, and at most the sum of the
/// two terms' largest values it replaces.
#[test]
fn the_joint_feedback_radius_bounds_every_split() {
    let g = gains(false);
    let j = Vehicle::<f64>::paper().inertia;
    let at = &g.attitude;
    let (m, k) = (at.mrp_saturation, at.k_mrp);
    let radial = |c: f64| {
        let q = energy_limits(&g, &j, c).mrp;
        (1.0 + q * q) / 4.0 * m * k * q / (m * m + k * k * q * q).sqrt()
    };
    let damping = |c: f64| {
        let w = energy_limits(&g, &j, c).omega_error.max();
        let (mw, kw) = (at.omega_saturation, at.k_omega);
        mw * kw * w / (mw * mw + kw * kw * w * w).sqrt()
    };
    for c in [1e-5, 1e-3, 0.02, 0.2, 5.0] {
        let r = super::joint_feedback_radius(&g, &j, c);
        let n = 20_000;
        let dense = (0..=n)
            .map(|i| {
                let s = f64::from(i) / f64::from(n);
                radial(s * c) + damping((1.0 - s) * c)
            })
            .fold(0.0, f64::max);
        let splits = super::ENERGY_SPLITS;
        let step = |f: &dyn Fn(f64) -> f64| {
            (0..splits)
                .map(|i| {
                    let s = |i: usize| i as f64 / splits as f64;
                    (f(s(i + 1) * c) - f(s(i) * c)).abs()
                })
                .fold(0.0, f64::max)
        };
        let rise = step(&|x| radial(x)) + step(&|x| damping(x));
        assert!(r >= dense * (1.0 - 1e-12), "c {c}: {r} < {dense}");
        assert!(
            r <= dense + rise * (1.0 + 1e-9),
            "c {c}: {r} > {dense} + {rise}"
        );
        assert!(r <= radial(c) + damping(c), "c {c}");
        if c < 0.1 {
            // Below the MRP's cap both terms grow with the energy: the split saves.
            assert!(r < 0.95 * (radial(c) + damping(c)), "c {c}: {r}");
        }
    }
}

/// Given global gains with the vertical channel apart (levels 4 up, 1 down) and a local regime
/// with its own vertical filters, when its vertical levels shrink to 1.5 up and 0.5 down, then
/// the local certificate is the one of the local position gains alone with those levels (the
/// same bounds, computed again here), the span `M_up + M_down` that every vertical rate of
/// Lemma 1 is proportional to shrinks, and with it the local `|ω̇_d|` bound and the local torque
/// set's roll extent; the global certificate does not change.
#[test]
fn smaller_local_vertical_levels_shrink_the_local_set() {
    let mut g = gains(false);
    g.position.saturation = 1.0;
    g.position.vertical = Some(crate::VerticalChannel {
        up: 4.0,
        down: 1.0,
        kf: 2.0,
        ks: 5.0,
    });
    let v = Vehicle::<f64>::paper();
    let constants = TrajectoryConstants::<f64>::zero();
    let with_levels = |up: f64, down: f64| {
        let local = crate::local_regime::LocalGains {
            kp: 9.0,
            kv: 6.0,
            kf: 4.0,
            ks: 10.0,
            saturation: 1.0,
            energy_in: 1e-4,
            energy_out: 2e-4,
            vertical: Some(crate::VerticalChannel {
                up,
                down,
                kf: 12.0,
                ks: 24.0,
            }),
            attitude: None,
            braking: None,
        };
        let gains = Gains {
            local: Some(local),
            ..g
        };
        let c = certify(&v, &Limits::paper(), &gains, &constants, FilterStart::Zero).unwrap();
        let alone = local_alone(&v, &g, &local, &constants);
        (c, alone)
    };
    let (wide, _) = with_levels(4.0, 1.0);
    let (narrow, alone) = with_levels(1.5, 0.5);
    let (lw, ln) = (wide.local.unwrap(), narrow.local.unwrap());
    assert_eq!(ln.bounds.angular_acceleration, alone.angular_acceleration);
    assert_eq!(ln.bounds.desired_frame, alone.desired_frame);
    assert!(
        ln.bounds.angular_acceleration < 0.6 * lw.bounds.angular_acceleration,
        "{} against {}",
        ln.bounds.angular_acceleration,
        lw.bounds.angular_acceleration
    );
    assert!(ln.torque_set.axis_extents().x < lw.torque_set.axis_extents().x);
    assert_eq!(
        narrow.bounds.angular_acceleration,
        wide.bounds.angular_acceleration
    );
    assert_eq!(narrow.bounds.torque_max, wide.bounds.torque_max);
}

/// Given global gains with the vertical channel apart and a velocity limit whose vertical
/// braking (2.8 up) lies above a local regime's own up level (1.5), when certified, then the
/// certificate holds: the local regime flies the braking at its share of the local levels
/// (`LocalGains::velocity_limit`), which validates there.
#[test]
fn a_local_level_below_the_global_braking_is_certified() {
    use crate::velocity_limit::{VelocityLimit, VerticalBraking};
    let mut g = gains(false);
    g.position.vertical = Some(crate::VerticalChannel {
        up: 4.0,
        down: 1.0,
        kf: 2.0,
        ks: 5.0,
    });
    g.velocity_limit = Some(VelocityLimit {
        speed: 5.0,
        braking: 0.7 * g.position.saturation,
        vertical: Some(VerticalBraking { up: 2.8, down: 0.7 }),
    });
    g.local = Some(crate::local_regime::LocalGains {
        kp: 9.0,
        kv: 6.0,
        kf: 4.0,
        ks: 10.0,
        saturation: g.position.saturation,
        energy_in: 1e-4,
        energy_out: 2e-4,
        vertical: Some(crate::VerticalChannel {
            up: 1.5,
            down: 0.5,
            kf: 12.0,
            ks: 24.0,
        }),
        attitude: None,
        braking: None,
    });
    let v = Vehicle::<f64>::paper();
    let c = certify(
        &v,
        &Limits::paper(),
        &g,
        &TrajectoryConstants::zero(),
        FilterStart::Zero,
    );
    assert!(c.is_ok(), "{:?}", c.err());
    assert!(c.unwrap().local.is_some());
}

/// Given global gains and a local regime with its own, stiffer attitude law, when certified,
/// then the local certificate's energy limits and torque set are those of the local law
/// (computed again here from a gain set whose global law is the local law), they differ from
/// what the global law would give at the same energy, and the global certificate's own bounds
/// are those of the gains without the local law.
#[test]
fn the_local_certificate_bounds_the_law_the_local_regime_flies() {
    let g = gains(true);
    let v = Vehicle::<f64>::paper();
    let constants = TrajectoryConstants::<f64>::zero();
    let law = crate::LocalAttitude {
        attitude: crate::attitude_control::AttitudeGains {
            k_mrp: 3.0 * g.attitude.k_mrp,
            mrp_saturation: 2.0 * g.attitude.mrp_saturation,
            ..g.attitude
        },
        tilt_priority: g.tilt_priority.map(|t| crate::TiltPriorityGains {
            omega_gains: t.omega_gains * 2.0,
            omega_levels: t.omega_levels * 1.5,
            ..t
        }),
    };
    let local = crate::local_regime::LocalGains {
        kp: 4.0,
        kv: 4.0,
        kf: 4.0,
        ks: 10.0,
        saturation: 3.0,
        energy_in: 1e-3,
        energy_out: 2e-3,
        vertical: None,
        attitude: None,
        braking: None,
    };
    let certify_local = |g: &Gains<f64>, local| {
        let gains = Gains {
            local: Some(local),
            ..*g
        };
        certify(&v, &Limits::paper(), &gains, &constants, FilterStart::Zero).unwrap()
    };
    let own = certify_local(
        &g,
        crate::local_regime::LocalGains {
            attitude: Some(law),
            ..local
        },
    );
    let global_law = certify_local(&g, local);
    let independent = certify_local(&g.with_attitude_law(&law), local);
    let (l, i, gl) = (
        own.local.unwrap(),
        independent.local.unwrap(),
        global_law.local.unwrap(),
    );
    assert_eq!(l.energy, i.energy);
    assert_eq!(l.torque_set.axis_extents(), i.torque_set.axis_extents());
    assert_ne!(l.energy, gl.energy);
    assert_ne!(l.torque_set.axis_extents(), gl.torque_set.axis_extents());
    assert_eq!(own.bounds.torque_set, global_law.bounds.torque_set);
    assert_eq!(own.conditions, global_law.conditions);
}
