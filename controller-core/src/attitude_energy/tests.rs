//! The envelope design's invariance, against an independent integration of the rigid body: the
//! attitude energy never increases under the law whatever `ω_d` does; its sublevel set bounds
//! the attitude error as stated.

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use proptest::prelude::*;

use super::{attitude_energy, energy_limits};
use crate::gains::Gains;
use crate::mrp::rotation_from_mrp;
use crate::path_lifting::PathLifting;
use crate::tilt_priority::TiltPriorityGains;

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Hummingbird-like gains: the paper's radial law, or tilt priority (yaw weak); the local
/// certificate's tests use them too.
pub(crate) fn gains(tilt: bool) -> Gains<f64> {
    let mut g = Gains::<f64>::paper();
    g.attitude.k_mrp = 2.0;
    g.attitude.k_omega = 0.05;
    g.attitude.mrp_saturation = 0.3;
    g.attitude.omega_saturation = 0.1;
    if tilt {
        g.tilt_priority = Some(TiltPriorityGains {
            trace_weights: Vector3::new(0.02, 0.02, 0.3),
            omega_gains: Vector3::new(0.05, 0.05, 0.02),
            omega_levels: Vector3::new(0.1, 0.1, 0.01),
            turn_over: None,
        });
    }
    g
}

/// `ω_d(t)` and `ω̇_d(t)`: sinusoids of amplitude `a` [rad/s] and frequency `f` [rad/s] per axis
/// (the reference of a violent position loop).
fn omega_d(a: &Vector3<f64>, f: &Vector3<f64>, t: f64) -> (Vector3<f64>, Vector3<f64>) {
    (
        Vector3::from_fn(|i, _| a[i] * (f[i] * t + i as f64).sin()),
        Vector3::from_fn(|i, _| a[i] * f[i] * (f[i] * t + i as f64).cos()),
    )
}

fn vec3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Given any start (attitude error up to a half turn, `ω̃` up to 4 rad/s) and a desired
    /// attitude driven by a violent `ω_d(t)`, when the body (`J ω̇ = (Jω) × ω + τ`, RK4 at
    /// 0.2 ms, `R_d` integrated along) flies the law with its exact feedforward, then the
    /// attitude energy never increases (within the integrator's error), for the paper's law and
    /// tilt priority: the invariance the envelope design's switch rests on.
    #[test]
    fn the_attitude_energy_never_increases(
        axis in vec3(1.0),
        angle in 0.0..3.1f64,
        w0 in vec3(4.0),
        amp in vec3(3.0),
        freq in vec3(6.0),
        tilt in proptest::bool::ANY,
    ) {
        prop_assume!(axis.norm() > 1e-3);
        let g = gains(tilt);
        let j = Vector3::new(3.65e-3, 3.68e-3, 7.03e-3);
        let mut rd = Matrix3::identity();
        let mut r = Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).into_inner();
        let mut lifting = PathLifting::new(g.hysteresis, g.reset_threshold);
        let (wd0, _) = omega_d(&amp, &freq, 0.0);
        let mut w = r.transpose() * rd * wd0 + w0;
        let h = 2e-4;
        let mut last = f64::INFINITY;
        for step in 0..4000 {
            let t = step as f64 * h;
            // Torque held over the step (a 5 kHz controller), the body and R_d integrated.
            let re = rd.transpose() * r;
            let lifted = lifting.lift(&re);
            let (wd, wdd) = omega_d(&amp, &freq, t);
            let out = g.attitude_torque(&lifted.mrp, &w, &re, &wd, &wdd, &j);
            let e = attitude_energy(&g.attitude, g.tilt_priority.as_ref(), &j, &lifted.mrp, &out.omega_error, &re);
            prop_assert!(
                e <= last + 2e-7 * (1.0 + last.abs().min(1e3)),
                "t = {t:.4}: energy {e} after {last}"
            );
            last = e;
            let f = |r: &Matrix3<f64>, w: &Vector3<f64>, rd: &Matrix3<f64>, s: f64| {
                let (wd, _) = omega_d(&amp, &freq, t + s);
                let jw = j.component_mul(w);
                (r * skew(w), (jw.cross(w) + out.torque).component_div(&j), rd * skew(&wd))
            };
            let (r1, w1, d1) = f(&r, &w, &rd, 0.0);
            let (r2, w2, d2) = f(&(r + r1 * (h / 2.0)), &(w + w1 * (h / 2.0)), &(rd + d1 * (h / 2.0)), h / 2.0);
            let (r3, w3, d3) = f(&(r + r2 * (h / 2.0)), &(w + w2 * (h / 2.0)), &(rd + d2 * (h / 2.0)), h / 2.0);
            let (r4, w4, d4) = f(&(r + r3 * h), &(w + w3 * h), &(rd + d3 * h), h);
            r += (r1 + r2 * 2.0 + r3 * 2.0 + r4) * (h / 6.0);
            w += (w1 + w2 * 2.0 + w3 * 2.0 + w4) * (h / 6.0);
            rd += (d1 + d2 * 2.0 + d3 * 2.0 + d4) * (h / 6.0);
            // Back onto SO(3) (the integrator drifts off it by O(h⁵) per step).
            r = Rotation3::from_matrix(&r).into_inner();
            rd = Rotation3::from_matrix(&rd).into_inner();
        }
    }

    /// Given a state inside `{E ≤ c}` (any `c` at least its energy), the MRP error, the
    /// rotation angle and each `|ω̃_i|` are within [`energy_limits`].
    #[test]
    fn the_energy_bounds_the_attitude_error(
        direction in vec3(1.0),
        size in prop_oneof![0.0..0.05f64, 0.0..1.0f64],
        w in prop_oneof![vec3(0.5), vec3(20.0)],
        extra in 0.0..1.0f64,
        tilt in proptest::bool::ANY,
    ) {
        let g = gains(tilt);
        let j = Vector3::new(3.65e-3, 3.68e-3, 7.03e-3);
        prop_assume!(direction.norm() > 1e-3);
        let mrp = direction.normalize() * size;
        let re = rotation_from_mrp(&mrp);
        let e = attitude_energy(&g.attitude, g.tilt_priority.as_ref(), &j, &mrp, &w, &re);
        let c = e * (1.0 + extra);
        let l = energy_limits(&g, &j, c);
        prop_assert!(mrp.norm() <= l.mrp * (1.0 + 1e-12));
        let angle = Rotation3::from_matrix_unchecked(re).angle();
        prop_assert!(angle <= l.angle * (1.0 + 1e-9) + 1e-12, "{angle} vs {}", l.angle);
        for i in 0..3 {
            prop_assert!(w[i].abs() <= l.omega_error[i] * (1.0 + 1e-12));
        }
    }
}
