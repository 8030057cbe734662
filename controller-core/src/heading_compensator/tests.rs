//! The compensated heading against the law it feeds: fed to `desired_attitude`, the frame's yaw
//! rate is `c ρ₃/|ϖ|²`; `ψ̇_c`, `ψ̈_c`, `ω_d` and `ω̇_d` agree with the exact evolution of the
//! state; the law's yaw components stay below `yaw_bounds` however large `ρ̈` is; with the thrust
//! direction and the reference held, the state converges on the computed time scale; and `f32`
//! agrees with `f64`.

use core::f64::consts::PI;

use approx::assert_relative_eq;
use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;

use super::{
    advance, compensated_heading, heading_rate_bound, wrap_angle, yaw_bounds, CompensatedHeading,
    CompensatorChain, HeadingCompensatorGains,
};
use crate::desired_attitude::{
    desired_attitude, normalize_with_derivatives, DesiredAttitude, UnitWithDerivatives,
};
use crate::desired_frame_bounds::tests::{signals as frame_signals, vec3};
use crate::parameter_error::ParameterError;

/// `(u, u̇, ü)` [m/s², m/s³, m/s⁴], inertial.
type ControlSignals = (Vector3<f64>, Vector3<f64>, Vector3<f64>);

/// `(ψ_d, ψ̇_d, ψ̈_d)` [rad, rad/s, rad/s²].
type HeadingReference = (f64, f64, f64);

/// `desired_frame_bounds`' signals: `(u, u̇, ü)` with `u` upward, at scales from calm to
/// violent, and a reference heading `(ψ_d, ψ̇_d, ψ̈_d)`, held a third of the time.
fn signals() -> impl Strategy<Value = (Vector3<f64>, Vector3<f64>, Vector3<f64>, HeadingReference)>
{
    frame_signals().prop_map(|(u, ud, udd, [psi, psid, psidd])| (u, ud, udd, (psi, psid, psidd)))
}

fn gains() -> impl Strategy<Value = HeadingCompensatorGains<f64>> {
    (0.05..3.0f64, 0.1..10.0f64).prop_map(|(level, gain)| HeadingCompensatorGains { level, gain })
}

fn thrust_direction(
    u: &Vector3<f64>,
    ud: &Vector3<f64>,
    udd: &Vector3<f64>,
) -> UnitWithDerivatives<f64> {
    normalize_with_derivatives(u, ud, udd).expect("u is not zero")
}

/// The compensated heading at `ψ_c` and the desired attitude it gives.
fn compensated_frame(
    g: &HeadingCompensatorGains<f64>,
    psi_c: f64,
    (u, ud, udd): (&Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
    reference: HeadingReference,
) -> (CompensatedHeading<f64>, DesiredAttitude<f64>) {
    let c = compensated_heading(g, psi_c, &thrust_direction(u, ud, udd), reference);
    let d = desired_attitude(
        u,
        ud,
        udd,
        &c.heading,
        &c.heading_rate,
        &c.heading_acceleration,
    )
    .expect("u is upward and ν_c is a unit vector");
    (c, d)
}

/// The frame from the reference heading itself (no compensation), for comparison.
fn uncompensated_frame(
    (u, ud, udd): (&Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
    (psi, psid, psidd): HeadingReference,
) -> DesiredAttitude<f64> {
    let (s, c) = psi.sin_cos();
    let (nu, perp) = (Vector2::new(c, s), Vector2::new(-s, c));
    desired_attitude(
        u,
        ud,
        udd,
        &nu,
        &(perp * psid),
        &(perp * psidd - nu * (psid * psid)),
    )
    .expect("upward")
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4_000))]

    /// Given random `(u, u̇, ü)`, a reference heading and a random state `ψ_c`, when the
    /// compensated heading is fed to `desired_attitude`, then the frame's yaw rate is
    /// `c ρ₃/|ϖ|²` with `c = ψ̇_d + L tanh(k_ψ sin(ψ_d − ψ_c)/L)`, `|ϖ|² = 1 − s²`,
    /// `s = ρᵀ(sin ψ_c, −cos ψ_c, 0)`, all computed here from their definitions.
    #[test]
    fn the_frames_yaw_rate_is_the_commanded_rate(
        (u, ud, udd, reference) in signals(), g in gains(), psi_c in -PI..PI,
    ) {
        let (ch, d) = compensated_frame(&g, psi_c, (&u, &ud, &udd), reference);
        let (psi_d, psid, _) = reference;
        let c = psid + g.level * (g.gain * (psi_d - psi_c).sin() / g.level).tanh();
        prop_assert!((ch.commanded_rate - c).abs() <= 1e-12 * (1.0 + c.abs()));
        let rho = d.thrust_direction;
        let k = Vector3::new(psi_c.sin(), -psi_c.cos(), 0.0);
        let s = rho.unit.dot(&k);
        let varpi2 = 1.0 - s * s;
        assert_relative_eq!(rho.unit.cross(&k).norm_squared(), varpi2, epsilon = 1e-12);
        let expected = c * rho.unit.z / varpi2;
        let w3 = d.angular_velocity.z;
        // The cancelled terms are of size |ρ̇| and |ψ̇_c| over |ϖ|²: their rounding sets the scale.
        let scale = expected.abs() + (rho.rate.norm() + ch.rate.abs()) / varpi2;
        prop_assert!((w3 - expected).abs() <= 1e-9 * scale, "{w3} vs {expected}");
    }

    /// Given random states with `|ρ̇| ≤ U_ρ̇`, `|ρ_xy| ≤ h`, `ρ₃ ≥ L_ϖ`, `|ψ̇_d| ≤ K_ν̇`,
    /// `|ψ̈_d| ≤ K_ν̈` (each bound the state's own value), when the compensated frame is formed,
    /// then `|ω_d,3|`, `|ω̇_d,3|` and `|ψ̇_c|` stay below their bounds; and with `ü` a thousand
    /// times larger (`ρ̈` too, `ρ̇` unchanged) the same bounds still hold.
    #[test]
    fn the_yaw_components_stay_below_their_bounds(
        (u, ud, udd, reference) in signals(), g in gains(), psi_c in -PI..PI,
    ) {
        let rho = thrust_direction(&u, &ud, &udd);
        let h = rho.unit.xy().norm();
        let chain = CompensatorChain {
            thrust_direction_rate: rho.rate.norm(),
            horizontal_share: h,
            heading_projection_min: rho.unit.z,
            heading_rate: reference.1.abs(),
            heading_acceleration: reference.2.abs(),
        };
        let (rate_bound, acceleration_bound) = yaw_bounds(&g, &chain);
        let psi_rate_bound = heading_rate_bound(&g, &chain);
        let tol = |x: f64| 1e-9 * (1.0 + x.abs());
        let mut calm = None;
        for scale in [1.0, 1e3] {
            let udd = udd * scale;
            let (ch, d) = compensated_frame(&g, psi_c, (&u, &ud, &udd), reference);
            let (w, a) = (d.angular_velocity.z, d.angular_acceleration.z);
            prop_assert!(ch.rate.abs() <= psi_rate_bound + tol(psi_rate_bound));
            prop_assert!(w.abs() <= rate_bound + tol(rate_bound), "{w} vs {rate_bound}");
            // The law's ω̇_d,3 cancels terms in ρ̈ numerically: their rounding is its tolerance.
            let cancelled = d.thrust_direction.acceleration.norm() * (1.0 + ch.rate.abs())
                / (rho.unit.z * rho.unit.z);
            prop_assert!(
                a.abs() <= acceleration_bound + tol(acceleration_bound) + 1e-12 * cancelled,
                "scale {scale}: {a} vs {acceleration_bound}"
            );
            // Not only below the bound: ω̇_d,3 does not depend on ρ̈ at all.
            let a1 = *calm.get_or_insert(a);
            prop_assert!(
                (a - a1).abs() <= 1e-12 * (cancelled + 1.0 + a1.abs()),
                "scale {scale}: {a} vs {a1}"
            );
        }
    }

    /// Given moderate signals, when `compensated_heading::<f32>` runs on the `f32` thrust
    /// direction, then it agrees with `f64` to about `1e-4` relative.
    #[test]
    fn f32_agrees_with_f64(
        u in vec3(), ud in vec3(), udd in vec3(), psi_c in -PI..PI,
        (psi_d, psid, psidd) in (-PI..PI, -1.0..1.0f64, -2.0..2.0f64),
        (level, gain) in (0.2..2.0f64, 0.5..5.0f64),
    ) {
        let u = Vector3::new(3.0 * u.x, 3.0 * u.y, 9.81 + u.z);
        let (ud, udd) = (ud * 3.0, udd * 10.0);
        let g = HeadingCompensatorGains { level, gain };
        let wide = compensated_heading(&g, psi_c, &thrust_direction(&u, &ud, &udd), (psi_d, psid, psidd));
        let narrow_rho = normalize_with_derivatives(
            &u.cast::<f32>(), &ud.cast::<f32>(), &udd.cast::<f32>()).expect("u is not zero");
        let narrow = compensated_heading(
            &HeadingCompensatorGains { level: level as f32, gain: gain as f32 },
            psi_c as f32, &narrow_rho, (psi_d as f32, psid as f32, psidd as f32));
        let close = |a: f32, b: f64| (f64::from(a) - b).abs() <= 1e-4 * (1.0 + b.abs());
        prop_assert!(close(narrow.rate, wide.rate), "{} vs {}", narrow.rate, wide.rate);
        prop_assert!(close(narrow.acceleration, wide.acceleration),
            "{} vs {}", narrow.acceleration, wide.acceleration);
        prop_assert!(close(narrow.commanded_rate, wide.commanded_rate));
        for i in 0..2 {
            prop_assert!(close(narrow.heading[i], wide.heading[i]));
            prop_assert!(close(narrow.heading_rate[i], wide.heading_rate[i]));
            prop_assert!(close(narrow.heading_acceleration[i], wide.heading_acceleration[i]));
        }
    }
}

/// `(u, u̇, ü)` and `(ψ_d, ψ̇_d, ψ̈_d)` at time `t`: `u(t) = a + b sin(1.3 t) + d t²` (upward
/// for the ranges used) and `ψ_d(t) = p₆ + p₇ sin(0.9 t) + p₈ t`, smooth in time.
fn smooth(t: f64, p: &[f64; 9]) -> (ControlSignals, HeadingReference) {
    let a = Vector3::new(p[0], p[1], 9.0 + p[2]);
    let b = Vector3::new(p[3], p[4], p[5]);
    let d = Vector3::new(0.2, -0.1, 0.05);
    let (s, c) = (1.3 * t).sin_cos();
    let u = a + b * s + d * (t * t);
    let ud = b * (1.3 * c) + d * (2.0 * t);
    let udd = -b * (1.69 * s) + d * 2.0;
    let (s, c) = (0.9 * t).sin_cos();
    let psi = (
        p[6] + p[7] * s + p[8] * t,
        p[7] * 0.9 * c + p[8],
        -p[7] * 0.81 * s,
    );
    ((u, ud, udd), psi)
}

/// `ψ̇_c` at time `t` and state `ψ_c` along [`smooth`].
fn rate_along(g: &HeadingCompensatorGains<f64>, t: f64, psi_c: f64, p: &[f64; 9]) -> f64 {
    let ((u, ud, udd), reference) = smooth(t, p);
    compensated_heading(g, psi_c, &thrust_direction(&u, &ud, &udd), reference).rate
}

/// The classical fourth-order Runge–Kutta step of `ψ̇_c = f(t, ψ_c)`.
fn rk4(f: impl Fn(f64, f64) -> f64, t: f64, psi: f64, dt: f64) -> f64 {
    let k1 = f(t, psi);
    let k2 = f(t + 0.5 * dt, psi + 0.5 * dt * k1);
    let k3 = f(t + 0.5 * dt, psi + 0.5 * dt * k2);
    let k4 = f(t + dt, psi + dt * k3);
    psi + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Given a smooth `u(t)`, `ψ_d(t)` and a start `ψ_c(0)`, when `ψ_c` is integrated by RK4
    /// (step 50 µs) to `t₀ ± δ`, then along that solution `ψ̈_c` from `compensated_heading` is
    /// the central difference of `ψ̇_c(t)`, and `ω_d`, `ω̇_d` from `desired_attitude(ν_c, ...)`
    /// are those of central differences of `R_d(t)` (`[ω_d]ₓ = R_dᵀṘ_d`) and of `ω_d(t)`.
    #[test]
    fn the_rates_match_the_exact_evolution(
        p0 in -3.0..3.0f64, p1 in -3.0..3.0f64, p2 in -2.0..2.0f64, p3 in -2.0..2.0f64,
        p4 in -2.0..2.0f64, p5 in -2.0..2.0f64, p6 in -3.0..3.0f64, p7 in -2.0..2.0f64,
        p8 in -1.0..1.0f64, psi0 in -PI..PI, g in gains(), steps in 400usize..40_000,
    ) {
        let p = [p0, p1, p2, p3, p4, p5, p6, p7, p8];
        let (dt, delta) = (5e-5, 1e-4);
        let f = |t: f64, psi: f64| rate_along(&g, t, psi, &p);
        let mut psi = psi0;
        for i in 0..steps {
            psi = rk4(f, i as f64 * dt, psi, dt);
        }
        // Three samples δ apart (two RK4 steps each) around t₀ = steps·dt + δ.
        let t_minus = steps as f64 * dt;
        let mut samples = [(t_minus, psi); 3];
        for j in 1..3 {
            let (t, x) = samples[j - 1];
            samples[j] = (t + delta, rk4(f, t + dt, rk4(f, t, x, dt), dt));
        }
        let frames = samples.map(|(t, x)| {
            let ((u, ud, udd), reference) = smooth(t, &p);
            compensated_frame(&g, x, (&u, &ud, &udd), reference)
        });
        let [(ca, da), (cb, db), (cc, dc)] = frames;
        let psi_rate = (samples[2].1 - samples[0].1) / (2.0 * delta);
        prop_assert!((cb.rate - psi_rate).abs() <= 1e-6 * (1.0 + psi_rate.abs()));
        let psi_acceleration = (cc.rate - ca.rate) / (2.0 * delta);
        prop_assert!(
            (cb.acceleration - psi_acceleration).abs() <= 1e-5 * (1.0 + psi_acceleration.abs()),
            "{} vs {psi_acceleration}", cb.acceleration
        );
        let skew = db.rotation.transpose() * (dc.rotation - da.rotation) / (2.0 * delta);
        let w = Vector3::new(skew[(2, 1)], skew[(0, 2)], skew[(1, 0)]);
        assert_relative_eq!(db.angular_velocity, w, epsilon = 1e-6 * (1.0 + w.norm()));
        let wdot = (dc.angular_velocity - da.angular_velocity) / (2.0 * delta);
        assert_relative_eq!(db.angular_acceleration, wdot, epsilon = 1e-5 * (1.0 + wdot.norm()));
        // The frame's x axis lies along ν_c in the horizontal plane.
        let x = db.rotation.column(0);
        assert_relative_eq!(Vector2::new(x[0], x[1]).normalize(), cb.heading, epsilon = 1e-9);
    }

    /// Given `u` and `ψ_d` held and any start `ψ_c(0) ≠ ψ_d + π`, when `ψ_c` is integrated (RK4,
    /// and the explicit [`advance`]) for `t* = ln(2|tan(e₀/2)|/ε)/κ` with `κ = L tanh(k_ψ/L)`,
    /// `ε = 10⁻⁶` (the time by which `|e| ≤ 2|tan(e/2)| ≤ 2|tan(e₀/2)| e^{−κt}` is below `ε`),
    /// then `|ψ_c − ψ_d| < ε` (modulo 2π); and all along, `|tan(e/2)|` decays at a rate between
    /// `κ` and `k_ψ` (`d/dt ln|tan(e/2)| = −L tanh(k_ψ sin e/L)/sin e`).
    #[test]
    fn the_state_converges_on_the_computed_time_scale(
        u in vec3(), g in gains(), psi_d in -PI..PI,
        e0 in prop_oneof![-3.1..3.1f64, (1.0..8.0f64, any::<bool>()).prop_map(|(m, neg)| {
            let e = PI - 10f64.powf(-m);
            if neg { -e } else { e }
        })],
    ) {
        let u = Vector3::new(6.0 * u.x, 6.0 * u.y, 9.81 + u.z);
        let z = Vector3::zeros();
        let rho = thrust_direction(&u, &z, &z);
        let reference = (psi_d, 0.0, 0.0);
        let f = |_t: f64, psi: f64| compensated_heading(&g, psi, &rho, reference).rate;
        let tolerance = 1e-6f64;
        let kappa = g.level * (g.gain / g.level).tanh();
        let start = (0.5 * e0).tan().abs().ln();
        let horizon = ((2.0 * tolerance.recip()).ln() + start) / kappa;
        // k_ψ dt ≤ 0.02: RK4's error per step (k_ψ dt)⁵/120 stays far below the slack below.
        let dt = (0.01f64).min(0.02 / g.gain);
        let steps = (horizon / dt).ceil() as usize;
        let error = |psi: f64| wrap_angle(psi_d - psi);
        let (mut by_rk4, mut by_euler) = (psi_d - e0, psi_d - e0);
        for i in 0..steps {
            by_rk4 = wrap_angle(rk4(f, 0.0, by_rk4, dt));
            by_euler = advance(by_euler, f(0.0, by_euler), dt);
            if error(by_rk4).abs() < 1e-10 {
                // Within 10⁶ ulps of ψ_d: the rounding of ψ_c, not the law, sets the rate here.
                continue;
            }
            let t = (i + 1) as f64 * dt;
            let decay = (0.5 * error(by_rk4)).tan().abs().ln();
            prop_assert!(decay <= start - kappa * t + 1e-6, "slower than κ at {t} s");
            prop_assert!(decay >= start - g.gain * t - 1e-6, "faster than k_ψ at {t} s");
        }
        prop_assert!(error(by_rk4).abs() < tolerance, "{} after {horizon} s", error(by_rk4));
        prop_assert!(error(by_euler).abs() < tolerance, "{} after {horizon} s", error(by_euler));
        // Held there: the commanded rate and the frame's yaw vanish at ψ_c = ψ_d.
        let c = compensated_heading(&g, psi_d, &rho, reference);
        prop_assert!(c.rate == 0.0 && c.acceleration == 0.0);
    }
}

/// Given a thrust direction tilting across the heading, when `ü` (and so `ρ̈`) is scaled by 10³,
/// then the frame formed from the reference heading itself has `|ω̇_d,3|` growing in proportion,
/// far above `yaw_bounds`; the frame formed from the compensated heading keeps the same
/// `ω̇_d,3`, below the bound.
#[test]
fn only_the_uncompensated_frame_pays_for_rho_ddot() {
    let g = HeadingCompensatorGains {
        level: 0.5,
        gain: 2.0,
    };
    let (u, ud) = (Vector3::new(0.5, 3.0, 9.0), Vector3::new(1.0, -0.5, 0.2));
    let reference = (0.1, 0.2, 0.0);
    let rho = thrust_direction(&u, &ud, &Vector3::zeros());
    let h = rho.unit.xy().norm();
    let chain = CompensatorChain {
        thrust_direction_rate: rho.rate.norm(),
        horizontal_share: h,
        heading_projection_min: rho.unit.z,
        heading_rate: 0.2,
        heading_acceleration: 0.0,
    };
    let (_, bound) = yaw_bounds(&g, &chain);
    let yaw_accelerations = [1.0, 1e3].map(|scale| {
        let udd = Vector3::new(2.0, 0.0, 0.0) * scale;
        let (_, d) = compensated_frame(&g, reference.0, (&u, &ud, &udd), reference);
        let plain = uncompensated_frame((&u, &ud, &udd), reference);
        (d.angular_acceleration.z, plain.angular_acceleration.z)
    });
    let [(compensated, plain), (compensated_violent, plain_violent)] = yaw_accelerations;
    assert!(compensated.abs() <= bound, "{compensated} vs {bound}");
    assert_relative_eq!(compensated_violent, compensated, max_relative = 1e-9);
    assert!(
        plain_violent.abs() > 20.0 * bound,
        "{plain_violent} vs {bound}"
    );
    assert!(
        plain_violent.abs() > 100.0 * plain.abs(),
        "{plain_violent} vs {plain}"
    );
}

/// The bounds' closed forms at one chain, term by term (module documentation).
#[test]
fn the_bounds_have_their_closed_forms() {
    let g = HeadingCompensatorGains {
        level: 0.5,
        gain: 2.0,
    };
    let (r, h, l, kd, kdd) = (3.0, 0.6, 0.8, 0.4, 0.7);
    let chain = CompensatorChain {
        thrust_direction_rate: r,
        horizontal_share: h,
        heading_projection_min: l,
        heading_rate: kd,
        heading_acceleration: kdd,
    };
    let upsi = kd + 0.5 + h * r / l;
    assert_relative_eq!(heading_rate_bound(&g, &chain), upsi, max_relative = 1e-15);
    let (w, a) = yaw_bounds(&g, &chain);
    assert_relative_eq!(w, (kd + 0.5) / l, max_relative = 1e-15);
    let cdot = kdd + 2.0 * (0.5 + h * r / l);
    let expected = cdot / l
        + (kd + 0.5) * h * r / (l * l)
        + 2.0 * (kd + 0.5) * h * (r + h * upsi) / (l * l * l);
    assert_relative_eq!(a, expected, max_relative = 1e-15);
    // Level thrust, held reference: the frame's yaw is the feedback's, L and k_ψ L at most.
    let hover = CompensatorChain {
        thrust_direction_rate: 0.0,
        horizontal_share: 0.0,
        heading_projection_min: 1.0,
        heading_rate: 0.0,
        heading_acceleration: 0.0,
    };
    assert_eq!(yaw_bounds(&g, &hover), (0.5, 1.0));
}

/// `validate` refuses non-positive or non-finite gains, naming them; `advance` steps
/// `ψ_c + ψ̇_c dt` and wraps it to `(−π, π]`.
#[test]
fn gains_are_validated_and_the_step_wraps() {
    let ok = HeadingCompensatorGains {
        level: 0.5,
        gain: 2.0,
    };
    assert!(ok.validate().is_ok());
    for (level, gain, name) in [
        (0.0, 2.0, "L_psi"),
        (f64::NAN, 2.0, "L_psi"),
        (0.5, -1.0, "k_psi"),
        (0.5, f64::INFINITY, "k_psi"),
    ] {
        let err = HeadingCompensatorGains { level, gain }.validate();
        assert!(
            matches!(err, Err(ParameterError::NotPositive { name: n, .. }) if n == name),
            "{err:?}"
        );
    }
    assert_relative_eq!(advance(0.3, 2.0, 0.1), 0.5, epsilon = 1e-15);
    assert_relative_eq!(advance(3.1, 1.0, 0.1), 3.2 - 2.0 * PI, epsilon = 1e-15);
    assert_relative_eq!(advance(-3.1, -1.0, 0.1), 2.0 * PI - 3.2, epsilon = 1e-15);
    assert_eq!(advance(PI, 0.0, 0.0), PI);
    assert_eq!(advance(-PI, 0.0, 0.0), PI);
    for k in -20..20 {
        let x = 0.37 * f64::from(k) + 100.0 * f64::from(k % 3);
        let y = advance(x, 0.0, 1.0);
        assert!(y > -PI && y <= PI, "{x} -> {y}");
        assert_relative_eq!(y.sin(), x.sin(), epsilon = 1e-12);
        assert_relative_eq!(y.cos(), x.cos(), epsilon = 1e-12);
    }
    let narrow = advance(3.1f32, 1.0, 0.1);
    assert!(narrow > -core::f32::consts::PI && narrow <= core::f32::consts::PI);
}
