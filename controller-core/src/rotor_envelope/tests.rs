//! The rotor envelope against the rotors it describes: airmode's thrust puts every rotor of a
//! set that passes the shadow fit inside its range, is the law's thrust wherever that already
//! fits, and stays in its a-priori interval; the shadow margin is exact (the set's own support
//! points sit on it); the thrust interval is the rotors' own.

use nalgebra::{Matrix4, Vector3, Vector4};
use proptest::prelude::*;

use super::RotorEnvelope;
use crate::torque_set::TorqueSet;

/// An X quad: arm `l` [m] on the diagonals, spins alternating, yaw torque `c` [m] per newton;
/// `B` maps rotor thrusts to `(T, τ)` (body FLU), the envelope holds the rows of `B⁻¹`.
pub(super) fn quad(l: f64, c: f64, lo: f64, hi: f64) -> (Matrix4<f64>, RotorEnvelope<f64>) {
    let pos = [(l, l), (l, -l), (-l, -l), (-l, l)];
    let spin = [-1.0, 1.0, -1.0, 1.0];
    let mut b = Matrix4::zeros();
    for k in 0..4 {
        b[(0, k)] = 1.0;
        b[(1, k)] = pos[k].1;
        b[(2, k)] = -pos[k].0;
        b[(3, k)] = -spin[k] * c;
    }
    let m = b.try_inverse().unwrap();
    let rows = [0, 1, 2, 3].map(|k| [m[(k, 0)], m[(k, 1)], m[(k, 2)], m[(k, 3)]]);
    (b, RotorEnvelope::new(rows, lo, hi).unwrap())
}

/// The rotor thrusts `M (T, τ)`.
fn rotors(e: &RotorEnvelope<f64>, t: f64, tau: &Vector3<f64>) -> Vector4<f64> {
    Vector4::from_fn(|k, _| e.collective[k] * t + e.torque[k].dot(tau))
}

/// A set like the law's: ellipsoid `U_ω̇d`, gyroscopic box, ball, disks and box scaled by `s`.
pub(super) fn set(s: f64) -> TorqueSet<f64> {
    let mut t = TorqueSet::new(
        Vector3::new(0.0036, 0.0037, 0.007),
        2.0 * s,
        20.0 * s,
        0.05 * s,
        Vector3::repeat(0.05 * s),
    );
    t.feedback_box = Vector3::new(0.02, 0.02, 0.005) * s;
    t.feedback_disks = Vector3::new(0.0, 0.0, 0.03) * s;
    t
}

/// A point of `set`: one point of each summand, from unit-ball draws `p[i]` (norm at most 1).
fn point(t: &TorqueSet<f64>, p: [Vector3<f64>; 5]) -> Vector3<f64> {
    let disk = |k: usize, v: Vector3<f64>| {
        let mut v = v;
        v[k] = 0.0;
        v * t.feedback_disks[k]
    };
    t.inertia.component_mul(&p[0]) * t.angular_acceleration
        + t.gyroscopic
            .component_mul(&p[1].map(|x| x.clamp(-1.0, 1.0)))
        + t.feedback_box
            .component_mul(&p[2].map(|x| x.clamp(-1.0, 1.0)))
        + p[3] * t.feedback_radius
        + disk(2, p[4])
}

/// The point of `set` where `dᵀτ` is largest (each summand's own maximiser).
pub(super) fn support_point(t: &TorqueSet<f64>, d: &Vector3<f64>) -> Vector3<f64> {
    let jd = t.inertia.component_mul(d);
    let mut planar = *d;
    planar.z = 0.0;
    t.inertia.component_mul(&jd) * (t.angular_acceleration / jd.norm())
        + (t.gyroscopic + t.feedback_box).component_mul(&d.map(f64::signum))
        + d * (t.feedback_radius / d.norm())
        + planar * (t.feedback_disks.z / planar.norm())
}

fn ball() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_map(|(x, y, z)| Vector3::new(x, y, z))
        .prop_filter("inside the unit ball", |v| v.norm() <= 1.0)
}

/// The largest scale of [`set`] whose shadow margin on `e` is not negative (bisection).
fn largest_passing_scale(e: &RotorEnvelope<f64>) -> f64 {
    let (mut a, mut b) = (0.0, 100.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if e.shadow_margin(&set(m)) >= 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    a
}

/// Given the Hummingbird's rotors (arm 0.12 m, yaw 0.0244 m per newton, 0 to 12.5 N, 5 % kept
/// free at both ends), the largest scale of `set` that passes the shadow fit is where its
/// margin crosses zero, and the fit is exact: at that scale the support point of the binding
/// pair's direction needs the whole shrunk range, 1 % beyond it no thrust realises it.
#[test]
fn the_shadow_margin_is_exact() {
    let (_, full) = quad(0.12, 0.0244, 0.0, 12.5);
    let e = full.shrunk(0.05);
    let s = set(largest_passing_scale(&e));
    // The binding pair and its direction.
    let (lo, hi) = e.range;
    let mut best = (f64::INFINITY, Vector3::zeros());
    for k in 0..4 {
        for l in 0..4 {
            if k != l {
                let d = e.torque[l] * e.collective[k] - e.torque[k] * e.collective[l];
                let slack = e.collective[k] * hi - e.collective[l] * lo - s.support(&d);
                if slack < best.0 {
                    best = (slack, d);
                }
            }
        }
    }
    assert!(best.0.abs() < 1e-9, "binding slack {}", best.0);
    let tau = support_point(&s, &best.1);
    let (t_lo, t_hi) = e.thrust_interval(&tau);
    assert!((t_hi - t_lo).abs() < 1e-8, "[{t_lo}, {t_hi}]");
    let (u_lo, u_hi) = e.thrust_interval(&(tau * 1.01));
    assert!(u_lo > u_hi, "1 % more is realised: [{u_lo}, {u_hi}]");
    // On the whole range (no margin) the same torque still fits: the margin is kept.
    let (f_lo, f_hi) = full.thrust_interval(&tau);
    assert!(f_lo < f_hi);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3_000))]

    /// Given a set that passes the shadow fit with the margin at both ends, airmode flown on the
    /// range kept free only at the top (any smaller margin above the rotors' least thrust) still
    /// realises every torque of it: each rotor's thrust is in `[lo + low (hi − lo), hi − m (hi −
    /// lo)]`, and the thrust is never above the one airmode gives with the margin at both ends
    /// where the law's thrust is below that range.
    #[test]
    fn airmode_with_a_smaller_low_margin_realises_every_torque(
        p0 in ball(), p1 in ball(), p2 in ball(), p3 in ball(), p4 in ball(),
        scale in 0.0..1.0f64,
        low in 0.0..0.05f64,
        t in -5.0..60.0f64,
    ) {
        let (_, full) = quad(0.12, 0.0244, 0.0, 12.5);
        let both = full.shrunk(0.05);
        let flown = full.shrunk_ends(low, 0.05);
        let s = set(scale * largest_passing_scale(&both));
        prop_assert!(both.shadow_margin(&s) >= 0.0);
        prop_assert!(flown.shadow_margin(&s) >= both.shadow_margin(&s));
        let tau = point(&s, [p0, p1, p2, p3, p4]);
        let applied = flown.airmode_thrust(t, &tau);
        let f = rotors(&flown, applied, &tau);
        let (lo, hi) = flown.range;
        prop_assert!((lo - low * 12.5).abs() < 1e-12 && (hi - 0.95 * 12.5).abs() < 1e-12);
        for k in 0..4 {
            prop_assert!(f[k] >= lo - 1e-9 && f[k] <= hi + 1e-9, "rotor {k}: {}", f[k]);
        }
        let with_both = both.airmode_thrust(t, &tau);
        if t <= with_both {
            prop_assert!(applied <= with_both + 1e-9, "{applied} > {with_both}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3_000))]

    /// Given a set that passes the shadow fit on the shrunk range, for any torque of it and any
    /// law thrust: every rotor's airmode thrust lies in the shrunk range (so nothing is given
    /// up), the thrust is the law's whenever the law's `(T, τ)` already fits, and it lies in
    /// the set's airmode interval around the law's `[t_lo, t_hi]`.
    #[test]
    fn airmode_realises_every_torque_of_a_set_that_passes(
        p0 in ball(), p1 in ball(), p2 in ball(), p3 in ball(), p4 in ball(),
        scale in 0.0..1.0f64,
        t in -5.0..60.0f64,
    ) {
        let (_, full) = quad(0.12, 0.0244, 0.0, 12.5);
        let e = full.shrunk(0.05);
        let s = set(scale * largest_passing_scale(&e));
        prop_assert!(e.shadow_margin(&s) >= 0.0);
        let tau = point(&s, [p0, p1, p2, p3, p4]);
        let applied = e.airmode_thrust(t, &tau);
        let f = rotors(&e, applied, &tau);
        let (lo, hi) = e.range;
        for k in 0..4 {
            prop_assert!(f[k] >= lo - 1e-9 && f[k] <= hi + 1e-9, "rotor {k}: {}", f[k]);
        }
        let law = rotors(&e, t, &tau);
        if law.iter().all(|&x| x >= lo && x <= hi) {
            prop_assert_eq!(applied, t);
        }
        let (t_lo, t_hi) = (4.0, 9.0);
        let (a_lo, a_hi) = e.airmode_interval(t_lo, t_hi, &s);
        let clamped = e.airmode_thrust(t.clamp(t_lo, t_hi), &tau);
        prop_assert!(clamped >= a_lo - 1e-9 && clamped <= a_hi + 1e-9);
    }
}

/// The thrust interval of zero torque is `[4 lo, 4 hi]` on a symmetric quad, a pure roll torque
/// narrows it by the roll spread at both ends, and `set_margin` of a box is the headroom of its
/// worst corner computed rotor by rotor.
#[test]
fn intervals_and_margins_by_hand() {
    let (b, e) = quad(0.1, 0.02, 1.0, 6.0);
    let (lo, hi) = e.thrust_interval(&Vector3::zeros());
    assert!((lo - 4.0).abs() < 1e-12 && (hi - 24.0).abs() < 1e-12);
    // τ_x = 0.2 N m: the left pair carries 0.5 N more, the right 0.5 N less, per rotor.
    let (lo, hi) = e.thrust_interval(&Vector3::new(0.2, 0.0, 0.0));
    assert!(
        (lo - 6.0).abs() < 1e-12 && (hi - 22.0).abs() < 1e-12,
        "[{lo}, {hi}]"
    );
    let f = rotors(&e, lo, &Vector3::new(0.2, 0.0, 0.0));
    assert!((b * f - Vector4::new(lo, 0.2, 0.0, 0.0)).norm() < 1e-12);
    let half = Vector3::new(0.1, 0.05, 0.01);
    let mut worst = f64::INFINITY;
    for corner in 0..16u32 {
        let sign = |bit: u32| if corner & (1 << bit) == 0 { -1.0 } else { 1.0 };
        let t = if corner & 1 == 0 { 8.0 } else { 16.0 };
        let tau = Vector3::new(sign(1) * half.x, sign(2) * half.y, sign(3) * half.z);
        for f in rotors(&e, t, &tau).iter() {
            worst = worst.min((f - 1.0).min(6.0 - f) / 5.0);
        }
    }
    let m = e.set_margin(8.0, 16.0, &TorqueSet::boxed(half));
    assert!((m - worst).abs() < 1e-12, "{m} vs {worst}");
}

/// A rotor that carries no collective, a non-finite row or an empty range is refused by name.
#[test]
fn bad_rotors_are_refused() {
    let ok = [[0.25, 1.0, 1.0, 1.0]; 4];
    let mut zero = ok;
    zero[2][0] = 0.0;
    let e = RotorEnvelope::new(zero, 0.0, 1.0).unwrap_err();
    assert!(format!("{e}").contains("collective share"), "{e}");
    let mut nan = ok;
    nan[1][3] = f64::NAN;
    assert!(format!("{}", RotorEnvelope::new(nan, 0.0, 1.0).unwrap_err()).contains("mixer row"));
    let e = RotorEnvelope::new(ok, 2.0, 1.0).unwrap_err();
    assert!(format!("{e}").contains("rotor thrust range"), "{e}");
}
