//! What caps a design's two certified levels (docs/design.md, "What binds"): the position
//! feedback's level `M_p` at its largest certifiable value, and the feedback torque level `ι`
//! at `ι_max`. Each cap is named with the numbers of the condition that stops it, so that on a
//! vehicle where the design is slow the engineer reads which of its limits to lift (thrust,
//! the torque about one axis, the reference's feedforward) and by how much. What the position
//! level and filters allow the 1 m step ([`StepFloor`]) says whether attitude gains could make
//! the step brisk or only a larger `k_f M_p` could.
//!
//! The search ([`super::authority::saturation_max_with`]) uses [`saturation_blocked`] itself,
//! so the cap reported is the one the design was bounded by, not a second opinion.

use super::authority::{
    envelope_with, iota_max, reference_torque_extents, shadow_iota_max, theorem2_iota_max_axes,
    thrust_fits, PositionLaw, RotorFit, RotorSet,
};
use super::tight::BoundsKind;
use controller_core::{TrajectoryConstants, Vehicle};
use nalgebra::Vector3;

/// Why a position level `M_p` leaves no certifiable feedback torque: the first condition, in
/// the order the search checks them, that fails there.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "condition", rename_all = "snake_case")]
#[allow(non_snake_case)]
pub enum SaturationCap {
    /// `M_p` reached the end of its range, where Theorem 1's thrust floor
    /// `T_min = m(g − K_a3 − M_down − M_i,z)` reaches 0 (`theorem1.saturation_margin`); nothing
    /// else bound it.
    ThrustFloor {
        /// The end of the range \[m/s²\] ([`saturation_top`]).
        level_m_s2: f64,
    },
    /// `certify` refused the set-up (its bounds are undefined there).
    Refused,
    /// Theorem 1's thrust interval at zero torque leaves the rotors' collective range shrunk by
    /// the margin (airmode's thrust fit; `theorem1.thrust_bound_within_actuator` with the
    /// margin).
    ThrustFit {
        /// `[T_min, T_max]` just above the cap \[N\].
        thrust_N: [f64; 2],
        /// The collective the rotors give at zero torque, each rotor inside the range shrunk by
        /// the margin \[N\].
        capacity_N: [f64; 2],
    },
    /// The certified torque set's feedforward part alone fills the rotors: no feedback torque
    /// fits with the margin (docs/torque-set.md).
    TorqueFit,
    /// Assumption 1's condition on one body axis: the reference's feedforward alone needs the
    /// axis's capacity over the thrust interval (which shrinks as the interval widens toward
    /// the rotors' ends; eq:TorqueMaxCondition).
    Assumption1 {
        /// Body axis (0 roll, 1 pitch, 2 yaw).
        axis: usize,
        /// The torque the reference's feedforward needs \[N m\].
        reference_Nm: f64,
        /// The axis's capacity just above the cap \[N m\].
        capacity_Nm: f64,
    },
    /// Theorem 2's condition on one body axis: the feedforward terms
    /// `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²` reach that axis's capacity
    /// (eq:TorqueMaxConditionsTheorem).
    Theorem2 {
        /// Body axis (0 roll, 1 pitch, 2 yaw).
        axis: usize,
        /// The feedforward terms just above the cap \[N m\].
        feedforward_Nm: f64,
        /// The axis's capacity \[N m\].
        capacity_Nm: f64,
    },
}

/// What caps `ι_max` at the chosen `(M_p, k_f, k_s)`: the least of the rotor fit's level and
/// Theorem 2's per-axis levels is `ι_max`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[allow(non_snake_case)]
pub struct IotaCap {
    /// The largest roll level \[N m\] whose certified torque set fits the rotors with the
    /// margin (the set over the thrust interval, or airmode's shadow).
    pub rotor_fit_Nm: f64,
    /// The largest roll level \[N m\] each body axis's Theorem 2 condition leaves (with tilt
    /// priority the yaw level is the yaw share of it; `+∞` where an axis does not bound it).
    pub theorem2_Nm: [f64; 3],
}

impl IotaCap {
    /// `None` when the rotor fit binds, else the Theorem 2 axis (0 roll, 1 pitch, 2 yaw) whose
    /// level is the least.
    pub fn theorem2_axis(&self) -> Option<usize> {
        let axis = Vector3::from(self.theorem2_Nm).imin();
        (self.theorem2_Nm[axis] < self.rotor_fit_Nm).then_some(axis)
    }
}

/// The least time the position loop's certified levels and filters allow for the 1 m step
/// (the nominal task from hover) to settle within its 5 cm band. The commanded acceleration
/// `u_f` stays in the ball of radius `M_p` and, by Lemma 1 from rest (the step starts from
/// hover, its filters at rest) without the reference's and the integral's terms, changes at
/// most at `2 k_f U_l M_p`, `U_l = (k_f/k_s)^{k_f/(k_s−k_f)}` (the local regime's `M_p,L`,
/// `k_f,L`, `k_s,L` where there is one: the step starts inside it). With perfect attitude
/// tracking and the integral's estimate at rest, `p̈ = u_f`, and [`band_entry_time`] is the
/// earliest such a move enters the band and stays. A floor of the model, not a guarantee about
/// the flown loop, which lags it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StepFloor {
    /// The acceleration bound `M_p` \[m/s²\].
    pub acceleration_m_s2: f64,
    /// The jerk bound `2 k_f U_l M_p` \[m/s³\].
    pub jerk_m_s3: f64,
    /// Whether the local regime's gains set them.
    pub local: bool,
    /// The least time \[s\] to enter the step's band and stay.
    pub time_s: f64,
}

/// The step \[m\] and its settling band \[m\] (design.md's nominal task).
pub const STEP_M: (f64, f64) = (1.0, 0.05);

impl StepFloor {
    /// The floor of the gains `g`: the local regime's level and filters where there is one, the
    /// global ones otherwise.
    pub fn of(g: &controller_core::Gains<f64>) -> Self {
        match &g.local {
            Some(l) => Self::new(l.saturation, (l.kf, l.ks), true),
            None => Self::new(g.position.saturation, (g.position.kf, g.position.ks), false),
        }
    }

    /// The floor for the position level `mp` \[m/s²\] and the filter gains `(k_f, k_s)` \[1/s\].
    pub fn new(mp: f64, (kf, ks): (f64, f64), local: bool) -> Self {
        let from_rest =
            controller_core::bounds::overshoot(kf, ks, controller_core::FilterStart::Zero);
        let jerk = 2.0 * kf * from_rest * mp;
        Self {
            acceleration_m_s2: mp,
            jerk_m_s3: jerk,
            local,
            time_s: band_entry_time(STEP_M, mp, jerk),
        }
    }
}

/// The least time \[s\] to move `distance` \[m\] from rest to rest with the acceleration at most
/// `acceleration` \[m/s²\] and its rate at most `jerk` \[m/s³\] (no speed limit): the profile
/// whose jerk is `±jerk` or 0 and symmetric about its midpoint. Without reaching the
/// acceleration bound (`distance ≤ 2 A³/J²`) it is `(32 d / J)^(1/3)`; otherwise, with `t_c` at
/// the bound in each half, `d = A (A/J + t_c)(2A/J + t_c)`, solved for `t_c ≥ 0`, and the time
/// is `2 (2A/J + t_c)`.
pub fn rest_to_rest_time(distance: f64, acceleration: f64, jerk: f64) -> f64 {
    let (d, a, j) = (distance, acceleration, jerk);
    if d <= 2.0 * a.powi(3) / (j * j) {
        return (32.0 * d / j).cbrt();
    }
    let r = a / j;
    // t_c² + 3 r t_c + 2 r² − d/A = 0.
    let t_c = 0.5 * (-3.0 * r + (r * r + 4.0 * d / a).sqrt());
    2.0 * (2.0 * r + t_c)
}

/// The distance \[m\] the rest-to-rest profile of duration `time` \[s\] ([`rest_to_rest_time`],
/// bounds `acceleration` \[m/s²\], `jerk` \[m/s³\]) covers in its first `tau` \[s\], `tau` at most
/// half of `time`: jerk `+J` until the acceleration reaches `min(A, J time / 4)`, held, then
/// `−J`; each piece integrated exactly.
fn distance_from_rest(tau: f64, time: f64, acceleration: f64, jerk: f64) -> f64 {
    let ramp = acceleration.min(jerk * time / 4.0) / jerk;
    let hold = 0.5 * time - 2.0 * ramp;
    let (mut left, mut a, mut v, mut x) = (tau, 0.0, 0.0, 0.0);
    for (length, j) in [(ramp, jerk), (hold, 0.0), (ramp, -jerk)] {
        let dt = left.min(length).max(0.0);
        x += v * dt + a * dt * dt / 2.0 + j * dt.powi(3) / 6.0;
        v += a * dt + j * dt * dt / 2.0;
        a += j * dt;
        left -= dt;
    }
    x
}

/// The least time \[s\] for a move of `step.0` \[m\] from rest to enter the band `step.1` \[m\]
/// around its end and stay, with the acceleration at most `acceleration` \[m/s²\] and its rate
/// at most `jerk` \[m/s³\]: the time-optimal move to the band's far edge, rest to rest, at the
/// moment it crosses the near edge. Taken as the earliest entry because a move that stops
/// inside the band stops no farther than the far edge, and the time-optimal one gets there
/// first; with the acceleration bound alone (bang-bang) this is the classical synthesis, with
/// the jerk bound it is the model's argument, not a proof. By the profile's symmetry the entry
/// is its duration less the time its first part takes to cover twice the band (bisection, 60
/// steps).
pub fn band_entry_time(step: (f64, f64), acceleration: f64, jerk: f64) -> f64 {
    let (d, band) = step;
    let time = rest_to_rest_time(d + band, acceleration, jerk);
    let left = |tau: f64| distance_from_rest(tau, time, acceleration, jerk) <= 2.0 * band;
    time - super::bisect::bisect(0.0, 0.5 * time, 60, left)
}

/// Both caps of a design, the step's floor, and the search variables at an end of their range,
/// as `design.json`'s `what_binds`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct WhatBinds {
    /// What stops `M_p` above its largest certifiable value.
    pub saturation: SaturationCap,
    /// What sets `ι_max`.
    pub iota: IotaCap,
    /// The least time the certified levels and filters allow for the 1 m step.
    pub step: StepFloor,
    /// The decision variables within [`RANGE_END`] of an end of their search range
    /// ([`super::variables::Choices::range_ends`]).
    pub range_ends: Vec<super::variables::RangeEnd>,
}

/// How close to an end of its search range (fraction of the unit interval) a decision variable
/// is reported at it.
pub const RANGE_END: f64 = 0.01;

/// `None` when the position level `mp` \[m/s²\] with filters `(k_f, k_s)` \[1/s\] and `law`
/// leaves some certifiable feedback torque on `rotors` with `margin` (fraction of the range);
/// else the first condition that fails. The test [`super::authority::saturation_max_with`]
/// bisects on.
pub fn saturation_blocked(
    bounds: BoundsKind,
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    (rotors, margin, fit): (&RotorSet, f64, RotorFit),
    (mp, kf, ks): (f64, f64, f64),
    law: PositionLaw<'_>,
) -> Option<SaturationCap> {
    let Some(env) = envelope_with(bounds, vehicle, constants, (mp, kf, ks), law) else {
        return Some(SaturationCap::Refused);
    };
    match fit {
        RotorFit::Set => {
            if iota_max(rotors, &env, margin) <= 0.0 {
                return Some(SaturationCap::TorqueFit);
            }
        }
        RotorFit::Airmode => {
            if !thrust_fits(rotors, &env, margin) {
                return Some(SaturationCap::ThrustFit {
                    thrust_N: [env.thrust.0, env.thrust.1],
                    capacity_N: collective_range(rotors, margin),
                });
            }
            if shadow_iota_max(rotors, &env, margin) <= 0.0 {
                return Some(SaturationCap::TorqueFit);
            }
        }
    }
    let levels = theorem2_iota_max_axes(rotors, &env, fit, &Vector3::repeat(1.0));
    let axis = levels.imin();
    let capacity = rotors.axis_capacity(fit, env.thrust)[axis];
    if levels[axis] == f64::NEG_INFINITY {
        return Some(SaturationCap::Assumption1 {
            axis,
            reference_Nm: reference_torque_extents(&env)[axis],
            capacity_Nm: capacity,
        });
    }
    (levels[axis] <= 0.0).then_some(SaturationCap::Theorem2 {
        axis,
        feedforward_Nm: env.feedforward[axis],
        capacity_Nm: capacity,
    })
}

/// The end of `M_p`'s range [m/s²]: Theorem 1's thrust floor `T_min = m(g − K_a3 − M_p)` (with
/// the integral action `− M_i,z`; with the vertical channel apart `M_down = down M_p` in place of
/// `M_p`) reaches 0 there (`theorem1.saturation_margin`). Not positive when the reference's
/// vertical acceleration and the integral's level leave no room. No errors.
pub fn saturation_top(
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    law: PositionLaw<'_>,
) -> f64 {
    (vehicle.gravity
        - constants.vertical_acceleration
        - law.integral.map_or(0.0, |i| i.level_m_s2[2]))
        / law.vertical.map_or(1.0, |(_, down, _, _)| down)
}

/// What stops `M_p` above `mp_max` \[m/s²\], its largest certifiable value for the same
/// arguments as [`saturation_blocked`]: the first condition that fails a relative 10⁻³, 10⁻²
/// or 10⁻¹ above it (the bisection brackets the cap closer than the first, 10⁻³ of the range's
/// end with the tight bounds' 12 steps), or the end of the range when nothing fails before it.
pub fn saturation_cap(
    bounds: BoundsKind,
    vehicle: &Vehicle<f64>,
    constants: &TrajectoryConstants<f64>,
    rotors: (&RotorSet, f64, RotorFit),
    (mp_max, kf, ks): (f64, f64, f64),
    law: PositionLaw<'_>,
) -> SaturationCap {
    let top = saturation_top(vehicle, constants, law);
    [1e-3, 1e-2, 1e-1, f64::INFINITY]
        .into_iter()
        .map(|step| (mp_max * (1.0 + step)).min(top * (1.0 - 1e-9)))
        .find_map(|above| {
            saturation_blocked(bounds, vehicle, constants, rotors, (above, kf, ks), law)
        })
        .unwrap_or(SaturationCap::ThrustFloor { level_m_s2: top })
}

/// The collective thrust range \[N\] the rotors give at zero torque with every rotor inside
/// its range shrunk by `margin`: rotor `k` takes `w_k T`.
pub fn collective_range(rotors: &RotorSet, margin: f64) -> [f64; 2] {
    let (lo, hi) = rotors.shrunk(margin);
    (0..4).fold([0.0, f64::INFINITY], |[a, b], k| {
        let w = rotors.mix[(k, 0)];
        [a.max(lo / w), b.min(hi / w)]
    })
}

#[cfg(test)]
mod tests;
