//! The decision variables: nine numbers in `[0, 1]`, each mapped onto one physical choice, so
//! every point of the unit box is a certifiable design by construction.
//!
//! | # | variable | maps to |
//! |---|----------|---------|
//! | 0 | `k_f` | log scale on `[0.1, 6]` 1/s |
//! | 1 | `k_s / k_f` | log scale on `[1.5, 12]` (so `k_s > k_f`) |
//! | 2 | `M_p / M_p,max(k_f, k_s)` | `[0.05, 0.95]` ([`super::authority::saturation_max`]) |
//! | 3 | `ι / ι_max(M_p, k_f, k_s)` | `[0.2, 0.95]` ([`super::authority::iota_max`]) |
//! | 4 | share of `ι` taken by the MRP term `(1 + (1+δ)²) M_ϑ/4` | `[0.2, 0.9]`; `M_ω` is the rest |
//! | 5 | attitude natural frequency `ω_a` | log scale on `[0.5, 60]` rad/s |
//! | 6 | attitude damping `ζ_a` | `[0.2, 1.5]` |
//! | 7 | position natural frequency `ω_p` | log scale on `[0.5, 4]` rad/s |
//! | 8 | position damping `ζ_p` | `[0.6, 1.5]` |
//!
//! Attitude gains from the linearisation about zero error: the MRP is `ϑ ≈ θ/4` (θ the error
//! angle about one axis) and the torque law is `τ ≈ −(k_ϑ/4) ϑ − k_ω ω = −(k_ϑ/16) θ − k_ω ω`
//! (Section V, `(1 + |ϑ|²)/4 → 1/4`), so `J θ̈ = −(k_ϑ/16) θ − k_ω θ̇` gives
//! `k_ϑ = 16 J ω_a²`, `k_ω = 2 ζ_a ω_a J`, with `J` the *smallest* inertia diagonal entry: `ω_a`
//! is the natural frequency of the fastest axis, the one the motor lag threatens first (the
//! other axes are slower by `sqrt(J_min/J_ii)`). Table I (`k_ϑ = 100`, `k_ω = 0.1`,
//! `J_11 = 2.24e-3`) is `ω_a = 52.8` rad/s, `ζ_a = 0.42`.
//!
//! Position gains: in the z-coordinates of Section IV the loop is the double integrator
//! `z̈₁ = ubar_p = −σ_p(k_p z₁ + k_v ż₁)`, so `k_p = ω_p²`, `k_v = 2 ζ_p ω_p` (Table I: `ω_p = 3`,
//! `ζ_p = 1`).

use controller_core::{Gains, TrajectoryConstants, Vehicle};

use super::authority::{
    envelope, iota_max, mrp_factor, probe_gains, saturation_max, RotorSet, ALPHA, DELTA,
};

/// Number of decision variables.
pub const DIMENSION: usize = 9;

/// The interval of each variable: `(low, high, logarithmic)`.
const RANGES: [(f64, f64, bool); DIMENSION] = [
    (0.1, 6.0, true),
    (1.5, 12.0, true),
    (0.05, 0.95, false),
    (0.2, 0.95, false),
    (0.2, 0.9, false),
    (0.5, 60.0, true),
    (0.2, 1.5, false),
    (0.5, 4.0, true),
    (0.6, 1.5, false),
];

fn to_value(i: usize, x: f64) -> f64 {
    let (lo, hi, log) = RANGES[i];
    let x = x.clamp(0.0, 1.0);
    if log {
        (lo.ln() + x * (hi.ln() - lo.ln())).exp()
    } else {
        lo + x * (hi - lo)
    }
}

fn to_unit(i: usize, v: f64) -> f64 {
    let (lo, hi, log) = RANGES[i];
    let x = if log {
        (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
    } else {
        (v - lo) / (hi - lo)
    };
    x.clamp(0.0, 1.0)
}

/// The physical choices of one design (before they become gains).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Choices {
    /// `k_f` [1/s].
    pub kf: f64,
    /// `k_s` [1/s].
    pub ks: f64,
    /// `M_p / M_p,max`.
    pub saturation_fraction: f64,
    /// `ι / ι_max`.
    pub iota_fraction: f64,
    /// Share of `ι` in the MRP term.
    pub mrp_share: f64,
    /// Attitude natural frequency [rad/s] (smallest-inertia axis).
    pub attitude_frequency_rad_s: f64,
    /// Attitude damping ratio.
    pub attitude_damping: f64,
    /// Position natural frequency [rad/s].
    pub position_frequency_rad_s: f64,
    /// Position damping ratio.
    pub position_damping: f64,
}

impl Choices {
    /// From a point of the unit box (clamped into it).
    pub fn from_unit(x: &[f64]) -> Self {
        let v = |i: usize| to_value(i, x.get(i).copied().unwrap_or(0.5));
        let kf = v(0);
        Self {
            kf,
            ks: kf * v(1),
            saturation_fraction: v(2),
            iota_fraction: v(3),
            mrp_share: v(4),
            attitude_frequency_rad_s: v(5),
            attitude_damping: v(6),
            position_frequency_rad_s: v(7),
            position_damping: v(8),
        }
    }

    /// The point of the unit box (inverse of [`Choices::from_unit`], clamped).
    pub fn to_unit(&self) -> Vec<f64> {
        [
            self.kf,
            self.ks / self.kf,
            self.saturation_fraction,
            self.iota_fraction,
            self.mrp_share,
            self.attitude_frequency_rad_s,
            self.attitude_damping,
            self.position_frequency_rad_s,
            self.position_damping,
        ]
        .iter()
        .enumerate()
        .map(|(i, &v)| to_unit(i, v))
        .collect()
    }

    /// The initial guess: the most certified torque authority (`ι` at 90 % of `ι_max`) with a
    /// moderate position saturation, slow filters and moderate, well-damped loops.
    pub fn initial_guess() -> Self {
        Self {
            kf: 0.6,
            ks: 1.5,
            saturation_fraction: 0.5,
            iota_fraction: 0.9,
            mrp_share: 0.8,
            attitude_frequency_rad_s: 10.0,
            attitude_damping: 0.8,
            position_frequency_rad_s: 1.0,
            position_damping: 1.0,
        }
    }
}

/// What the context of a design needs to turn choices into gains.
#[derive(Clone, Copy, Debug)]
pub struct Context<'a> {
    /// The vehicle's rigid body.
    pub vehicle: &'a Vehicle<f64>,
    /// The reference's Assumption 1 constants.
    pub constants: &'a TrajectoryConstants<f64>,
    /// The rotor set.
    pub rotors: &'a RotorSet,
    /// Box-fit margin (fraction of the rotor range).
    pub margin: f64,
}

/// The gains of `choices`, with `M_p,max` and `ι_max` they were scaled from.
#[derive(Clone, Copy, Debug)]
pub struct Mapped {
    /// Table I gains.
    pub gains: Gains<f64>,
    /// `M_p,max(k_f, k_s)` [m/s²].
    pub saturation_max: f64,
    /// `ι_max(M_p, k_f, k_s)` [N m].
    pub iota_max: f64,
}

/// Maps `choices` to gains. `None` when no positive `ι` exists for `(k_f, k_s)` (the reference
/// is not certifiable on this vehicle).
pub fn map(ctx: &Context<'_>, c: &Choices) -> Option<Mapped> {
    let mp_max = saturation_max(
        ctx.vehicle,
        ctx.constants,
        ctx.rotors,
        ctx.margin,
        c.kf,
        c.ks,
    )?;
    let mp = mp_max * c.saturation_fraction;
    let env = envelope(ctx.vehicle, ctx.constants, mp, c.kf, c.ks)?;
    let i_max = iota_max(ctx.rotors, &env, ctx.margin);
    if i_max <= 0.0 {
        return None;
    }
    let iota = c.iota_fraction * i_max;
    let j = ctx.vehicle.inertia.min();
    let w = c.attitude_frequency_rad_s;
    let wp = c.position_frequency_rad_s;
    let mut g = probe_gains(mp, c.kf, c.ks);
    g.position.kp = wp * wp;
    g.position.kv = 2.0 * c.position_damping * wp;
    g.attitude.k_mrp = 16.0 * j * w * w;
    g.attitude.k_omega = 2.0 * c.attitude_damping * w * j;
    g.attitude.mrp_saturation = c.mrp_share * iota / mrp_factor();
    g.attitude.omega_saturation = (1.0 - c.mrp_share) * iota;
    g.hysteresis = DELTA;
    g.reset_threshold = ALPHA;
    Some(Mapped {
        gains: g,
        saturation_max: mp_max,
        iota_max: i_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_box_round_trips() {
        let c = Choices::initial_guess();
        let back = Choices::from_unit(&c.to_unit());
        for (a, b) in c.to_unit().iter().zip(back.to_unit()) {
            assert!((a - b).abs() < 1e-12);
        }
        assert!((back.ks - c.ks).abs() < 1e-9 && (back.kf - c.kf).abs() < 1e-9);
    }

    /// Certified by construction: points all over the unit box map to gains that pass
    /// `certify` and `box_fit` with the margin.
    #[test]
    fn every_point_of_the_box_is_certified() {
        use crate::design::certificate::certify_design;
        use crate::design::vehicle::DesignVehicle;
        use crate::scenario::Scenario;
        use controller_core::Trajectory;
        let v = DesignVehicle::load(&crate::vehicle::preset_path("crazyflie-2.1")).unwrap();
        let set = RotorSet::new(&v.rotors).unwrap();
        let constants = Scenario::paper().trajectory::<f64>().constants();
        let ctx = Context {
            vehicle: &v.body,
            constants: &constants,
            rotors: &set,
            margin: 0.05,
        };
        let mut rng = crate::campaign::sampler::seeded_rng(11);
        for _ in 0..200 {
            use rand::RngExt;
            let x: Vec<f64> = (0..DIMENSION)
                .map(|_| rng.random_range(0.0..=1.0))
                .collect();
            let m = map(&ctx, &Choices::from_unit(&x))
                .expect("the paper helix is usable on the Crazyflie");
            let c = certify_design(&v.body, &v.rotors, &m.gains, &constants, 0.05).unwrap();
            assert!(
                c.ok(),
                "{x:?}: {:?} margin {}",
                c.certificate.require_feasible(),
                c.margin
            );
            assert!(c.margin >= 0.05 - 1e-6, "{}", c.margin);
        }
    }
}
