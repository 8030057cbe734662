//! X-quad allocation: collective thrust `T` \[N\] and body torque `τ` [N m] (FLU) to four rotor
//! thrusts \[N\], with saturation handled by priority, and the a-priori box-fit report.
//!
//! Motor order is the order of [`crate::config::RotorConfig::rotors`]; the paper vehicle uses
//! Betaflight's quad X: 1 rear-right, 2 front-right, 3 rear-left, 4 front-left.
//!
//! Effectiveness: rotor `k` at `(x_k, y_k)` with spin `s_k` (+1 CCW from above) and thrust `f_k`
//! along body z gives `T = Σ f_k`, `τ_x = Σ y_k f_k`, `τ_y = −Σ x_k f_k`,
//! `τ_z = −Σ s_k c f_k` (`c = k_Q/k_T`), i.e. `(T, τ) = B f`. The mixer is `M = B⁻¹`.
//!
//! Desaturation (the idea of PX4's multirotor mixer, written here from its description):
//! 1. roll/pitch first: if the roll/pitch part alone spreads the rotors wider than their range,
//!    it is scaled down (direction kept);
//! 2. collective next: the thrust is shifted as little as possible, to fit roll/pitch and yaw if
//!    a shift can, else roll/pitch alone;
//! 3. yaw last: when no collective shift fits the full yaw demand too, yaw gets the headroom
//!    left (scaled down, never more than asked).
//!
//! Nothing is clipped silently: what was given up is returned in [`MixOutput`].

use controller_core::scalar::{fmax, fmin};
use controller_core::{RotorEnvelope, TorqueSet};
use nalgebra::{Matrix4, Vector3, Vector4};

use crate::config::RotorConfig;

/// Why a mixer could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MixerError {
    /// The effectiveness matrix is singular (rotor geometry degenerate).
    SingularGeometry,
    /// A rotor's thrust range is empty or not finite.
    BadThrustRange,
}

/// The allocation of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MixOutput {
    /// Rotor thrusts \[N\], motor order, each in `[thrust_min, thrust_max]`.
    pub thrust: [f32; 4],
    /// Collective thrust \[N\] and torque [N m] the rotor thrusts actually produce.
    pub achieved_thrust: f32,
    /// Achieved torque [N m], body FLU.
    pub achieved_torque: Vector3<f32>,
    /// Roll/pitch scale applied (1 = as asked).
    pub roll_pitch_scale: f32,
    /// Collective shift \[N\] (0 = as asked).
    pub thrust_shift: f32,
    /// Yaw scale applied (1 = as asked).
    pub yaw_scale: f32,
}

impl MixOutput {
    /// True when any axis was given up.
    pub fn saturated(&self) -> bool {
        self.roll_pitch_scale < 1.0 || self.thrust_shift != 0.0 || self.yaw_scale < 1.0
    }
}

/// The X-quad mixer: collective thrust `T` \[N\] and body torque `τ` [N m] (body frame FLU) to
/// the four rotor thrusts `f` \[N\], each in the rotor range `[f_min, f_max]`.
///
/// Holds the effectiveness `B` (4×4, `(T, τ) = B f`, rows `T, τ_x, τ_y, τ_z`; columns in the
/// order of [`crate::config::RotorConfig::rotors`]) and its inverse, the mixing matrix
/// `M = B⁻¹`. [`Mixer::mix`] allocates with the prioritised desaturation of the module docs
/// (roll/pitch, then collective, then yaw) and reports what it gave up; [`Mixer::box_fit`] and
/// [`Mixer::box_margin`] check, before flight, that the certified box `[T_lo, T_hi] × Π[−τ_i,
/// τ_i]` fits the rotor range at all its corners.
///
/// Errors: [`Mixer::new`] refuses a degenerate geometry ([`MixerError::SingularGeometry`]) and a
/// rotor range that is empty or not finite ([`MixerError::BadThrustRange`]).
/// Source: the effectiveness of a quadrotor (module docs); the desaturation order follows PX4's
/// multirotor mixer, written here from its description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixer {
    effectiveness: Matrix4<f32>,
    mix: Matrix4<f32>,
    f_min: f32,
    f_max: f32,
}

/// `f` clamped to `[lo, hi]` for `lo ≤ hi`, neither NaN (the rotor range, checked by
/// [`Mixer::new`]); a NaN `f` gives `lo`. The same value as `fmin(fmax(f, lo), hi)` for every
/// `f`, NaN included, in two comparisons: with the bounds known not to be NaN, the tests of
/// `fmax`/`fmin` for a NaN bound are not needed (about 6 instructions less per rotor on the
/// Cortex-M4F; docs/m4f-bench.md).
#[inline(always)]
fn clamp_rotor(f: f32, lo: f32, hi: f32) -> f32 {
    if f >= lo {
        if f <= hi {
            f
        } else {
            hi
        }
    } else {
        lo
    }
}

/// Largest `s ∈ [0, 1]` with `lo ≤ base_k + s d_k ≤ hi` for every k (base assumed inside).
fn max_scale(base: &Vector4<f32>, d: &Vector4<f32>, lo: f32, hi: f32) -> f32 {
    let mut s = 1.0f32;
    for k in 0..4 {
        if d[k] > 0.0 {
            s = fmin(s, fmax((hi - base[k]) / d[k], 0.0));
        } else if d[k] < 0.0 {
            s = fmin(s, fmax((lo - base[k]) / d[k], 0.0));
        }
    }
    s
}

/// The interval `[s_lo, s_hi]` of collective shifts `s` with `lo ≤ base_k + s u_k ≤ hi` for every
/// rotor that carries collective (`u_k > 0`); empty when `s_lo > s_hi`.
fn shift_bounds(base: &Vector4<f32>, u_t: &Vector4<f32>, lo: f32, hi: f32) -> (f32, f32) {
    let (mut s_lo, mut s_hi) = (f32::NEG_INFINITY, f32::INFINITY);
    for k in 0..4 {
        if u_t[k] > 0.0 {
            // `fmax(s_lo, v)` and `fmin(s_hi, w)`, bit for bit: `s_lo` and `s_hi` start at ∓∞
            // and only ever take a value that compared, so they are never NaN, and a NaN `v`
            // or `w` is skipped as `fmax`/`fmin` skip it (one comparison each instead of two).
            let (v, w) = ((lo - base[k]) / u_t[k], (hi - base[k]) / u_t[k]);
            if s_lo < v {
                s_lo = v;
            }
            if w <= s_hi {
                s_hi = w;
            }
        }
    }
    (s_lo, s_hi)
}

/// [`shift_bounds`] when the interval is not empty.
fn shift_interval(base: &Vector4<f32>, u_t: &Vector4<f32>, lo: f32, hi: f32) -> Option<(f32, f32)> {
    let (s_lo, s_hi) = shift_bounds(base, u_t, lo, hi);
    (s_lo <= s_hi).then_some((s_lo, s_hi))
}

impl Mixer {
    /// Builds `B` and `M = B⁻¹` from the rotor geometry.
    /// Errors: [`MixerError`].
    pub fn new(r: &RotorConfig) -> Result<Self, MixerError> {
        if !(r.thrust_min.is_finite()
            && r.thrust_max.is_finite()
            && r.thrust_min >= 0.0
            && r.thrust_max > r.thrust_min)
        {
            return Err(MixerError::BadThrustRange);
        }
        let c = r.torque_per_thrust();
        let mut b = Matrix4::zeros();
        for (k, rotor) in r.rotors.iter().enumerate() {
            b[(0, k)] = 1.0;
            b[(1, k)] = rotor.position[1];
            b[(2, k)] = -rotor.position[0];
            b[(3, k)] = -rotor.spin * c;
        }
        let mix = b.try_inverse().ok_or(MixerError::SingularGeometry)?;
        if !mix.iter().all(|x| x.is_finite()) {
            return Err(MixerError::SingularGeometry);
        }
        Ok(Self {
            effectiveness: b,
            mix,
            f_min: r.thrust_min,
            f_max: r.thrust_max,
        })
    }

    /// The effectiveness matrix `B` (rows T, τ_x, τ_y, τ_z; columns motors).
    pub fn effectiveness(&self) -> &Matrix4<f32> {
        &self.effectiveness
    }

    /// The mixing matrix `M = B⁻¹` (rows motors; columns T, τ_x, τ_y, τ_z).
    pub fn mixing(&self) -> &Matrix4<f32> {
        &self.mix
    }

    /// Rotor thrust range \[N\].
    pub fn thrust_range(&self) -> (f32, f32) {
        (self.f_min, self.f_max)
    }

    /// Allocates `thrust` \[N\] and `torque` [N m] (FLU) with roll/pitch > collective > yaw
    /// priority. Non-finite inputs are treated as zero torque and minimum thrust (the pipeline
    /// never passes them; this keeps NaN away from the motors regardless).
    pub fn mix(&self, thrust: f32, torque: &Vector3<f32>) -> MixOutput {
        let thrust = if thrust.is_finite() { thrust } else { 0.0 };
        let torque = if torque.iter().all(|x| x.is_finite()) {
            *torque
        } else {
            Vector3::zeros()
        };
        let col = |j: usize| self.mix.column(j).into_owned();
        let u_t = col(0);
        let rp = col(1) * torque.x + col(2) * torque.y;
        let yaw = col(3) * torque.z;
        let (lo, hi) = (self.f_min, self.f_max);

        // 1. Roll/pitch: the spread must fit the range.
        let spread = rp.max() - rp.min();
        let rp_scale = if spread > hi - lo {
            (hi - lo) / spread
        } else {
            1.0
        };
        let rp = rp * rp_scale;

        // 2. Collective: shift along the thrust column as little as possible, first keeping the
        // full yaw demand (a realisable request then comes out exactly); if no shift fits with
        // it, fit roll/pitch alone and let yaw take the headroom left (3).
        let base = u_t * thrust + rp;
        let (shift, yaw_scale, f) = match shift_interval(&(base + yaw), &u_t, lo, hi) {
            Some((s_lo, s_hi)) => {
                let shift = fmin(fmax(0.0, s_lo), s_hi);
                (shift, 1.0, base + yaw + u_t * shift)
            }
            None => {
                // After step 1 a shift for roll/pitch alone exists up to rounding; if rounding
                // says otherwise, take the middle of the (empty) interval.
                let (s_lo, s_hi) = shift_bounds(&base, &u_t, lo, hi);
                let shift = if s_lo <= s_hi {
                    fmin(fmax(0.0, s_lo), s_hi)
                } else {
                    0.5 * (s_lo + s_hi)
                };
                let base = (base + u_t * shift).map(|f| clamp_rotor(f, lo, hi));
                // 3. Yaw with the headroom left.
                let yaw_scale = max_scale(&base, &yaw, lo, hi);
                (shift, yaw_scale, base + yaw * yaw_scale)
            }
        };
        // Rounding can leave a rotor an ulp outside the range.
        let f = f.map(|f| clamp_rotor(f, lo, hi));
        let achieved = self.effectiveness * f;
        MixOutput {
            thrust: [f[0], f[1], f[2], f[3]],
            achieved_thrust: achieved[0],
            achieved_torque: Vector3::new(achieved[1], achieved[2], achieved[3]),
            roll_pitch_scale: rp_scale,
            thrust_shift: shift,
            yaw_scale,
        }
    }

    /// The smallest headroom the box `T ∈ [t_lo, t_hi]`, `|τ_i| ≤ tau_i` leaves inside the rotor
    /// range, over the four rotors and the box's corners, as a fraction of the range
    /// `f_max − f_min` \[dimensionless\]: `min_k min(f_max − max f_k, min f_k − f_min)/(f_max −
    /// f_min)`, where rotor `k`'s extremes over the box are `w_k T_hi + Σ_i |M_ki| τ_i` and
    /// `w_k T_lo − Σ_i |M_ki| τ_i` (the map `M` is linear, so a corner decides). Negative when
    /// the box does not fit; `−∞` when a rotor's thrust column entry is not positive (it cannot
    /// carry collective).
    pub fn box_margin(&self, t_lo: f32, t_hi: f32, tau: &Vector3<f32>) -> f32 {
        // A box's support function is `Σ_i |c_i| τ_i`: the box is the set with only a box part.
        self.set_margin(t_lo, t_hi, &TorqueSet::boxed(*tau))
    }

    /// The smallest headroom the certified set `T ∈ [t_lo, t_hi]`, `τ ∈ set` leaves inside the
    /// rotor range, as a fraction of the range `f_max − f_min` \[dimensionless\]. Rotor `k`
    /// receives `f_k = w_k T + c_kᵀτ` (`w_k`, `c_k` its row of `M`), linear, so its extremes over
    /// the set are `w_k t_hi + h(c_k)` and `w_k t_lo − h(c_k)` with `h` the set's support function
    /// ([`TorqueSet::support`]): exact, where [`Mixer::box_margin`] of the set's per-axis extents
    /// takes `Σ_i |c_ki| τ_i ≥ h(c_k)` (that is this function on the box, [`TorqueSet::boxed`]). Negative when the set does not fit; `−∞` when a rotor's
    /// thrust column entry is not positive. Source: extension of Theorem 2 (docs/torque-set.md).
    pub fn set_margin(&self, t_lo: f32, t_hi: f32, set: &TorqueSet<f32>) -> f32 {
        match self.envelope() {
            Some(e) => e.set_margin(t_lo, t_hi, set),
            None => f32::NEG_INFINITY,
        }
    }

    /// The largest headroom `m` (a fraction of the range `f_max − f_min`) such that every torque
    /// of `set` is realised at *some* collective thrust with every rotor at least `m` of its
    /// range inside it: [`RotorEnvelope::shadow_margin`] of [`Mixer::envelope`] (negative when
    /// some torque of the set is beyond the rotors at any thrust; `−∞` when a rotor's thrust
    /// column entry is not positive). What airmode needs (docs/airmode.md).
    pub fn shadow_margin(&self, set: &TorqueSet<f32>) -> f32 {
        match self.envelope() {
            Some(e) => e.shadow_margin(set),
            None => f32::NEG_INFINITY,
        }
    }

    /// The rotors' `(T, τ)` set as the law sees it: the rows of `M` and the rotor range
    /// ([`RotorEnvelope`], the one implementation of the fits the gate checks and of airmode's
    /// thrust). `None` when a rotor's thrust column entry is not positive (it cannot carry
    /// collective; no set fits then).
    pub fn envelope(&self) -> Option<RotorEnvelope<f32>> {
        let m = &self.mix;
        let rows = [0, 1, 2, 3].map(|k| [m[(k, 0)], m[(k, 1)], m[(k, 2)], m[(k, 3)]]);
        RotorEnvelope::new(rows, self.f_min, self.f_max).ok()
    }

    /// Whether the box `T ∈ [t_lo, t_hi]`, `|τ_i| ≤ tau_i` maps inside the rotor range, and by
    /// how much each axis falls short. Every corner of the box is checked through `M`
    /// (the map is linear, so the corners decide).
    pub fn box_fit(&self, t_lo: f32, t_hi: f32, tau: &Vector3<f32>) -> BoxFit {
        let (lo, hi) = (self.f_min, self.f_max);
        let m = &self.mix;
        // Per rotor, the torque demand of axes other than `skip` at their box extremes.
        let others = |k: usize, skip: usize| -> f32 {
            (0..3)
                .filter(|&i| i != skip)
                .map(|i| m[(k, i + 1)].abs() * tau[i])
                .sum()
        };
        let all = |k: usize| others(k, 3);
        let (mut cap_hi, mut cap_lo) = (f32::INFINITY, f32::NEG_INFINITY);
        for k in 0..4 {
            let (w, a) = (m[(k, 0)], all(k));
            // Thrust column entries are positive for any sensible quad; a non-positive entry
            // cannot carry collective (`box_margin` then says the box does not fit).
            if w <= 0.0 {
                continue;
            }
            cap_hi = cap_hi.min((hi - a) / w);
            cap_lo = cap_lo.max((lo + a) / w);
        }
        let mut torque_capacity = [0.0f32; 3];
        for (i, cap) in torque_capacity.iter_mut().enumerate() {
            let mut c = f32::INFINITY;
            for k in 0..4 {
                let (w, a, e) = (m[(k, 0)], others(k, i), m[(k, i + 1)].abs());
                if e > 0.0 {
                    c = c.min((hi - w * t_hi - a) / e).min((w * t_lo - lo - a) / e);
                }
            }
            *cap = c.max(0.0);
        }
        let mut single_axis = [0.0f32; 3];
        for (i, s) in single_axis.iter_mut().enumerate() {
            // Alone (others zero, collective free): the largest column entry limits it.
            let e = (0..4).map(|k| m[(k, i + 1)].abs()).fold(0.0f32, f32::max);
            *s = if e > 0.0 { (hi - lo) / (2.0 * e) } else { 0.0 };
        }
        BoxFit {
            fits: self.box_margin(t_lo, t_hi, tau) >= 0.0,
            thrust_needed: [t_lo, t_hi],
            thrust_capacity: [cap_lo, cap_hi],
            thrust_shortfall: [(cap_lo - t_lo).max(0.0), (t_hi - cap_hi).max(0.0)],
            torque_needed: [tau.x, tau.y, tau.z],
            torque_capacity,
            torque_shortfall: [0, 1, 2].map(|i| (tau[i] - torque_capacity[i]).max(0.0)),
            torque_single_axis: single_axis,
        }
    }
}

/// Whether a `(T, τ)` box fits inside what the four rotors can produce, per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxFit {
    /// Every corner of the box is realisable.
    pub fits: bool,
    /// The box's thrust interval `[T_lo, T_hi]` \[N\].
    pub thrust_needed: [f32; 2],
    /// The thrust interval the rotors realise while every torque is at its box bound \[N\].
    pub thrust_capacity: [f32; 2],
    /// How far the needed interval sticks out below and above the capacity \[N\] (0 = fits).
    pub thrust_shortfall: [f32; 2],
    /// The box's torque half-widths [N m].
    pub torque_needed: [f32; 3],
    /// Per axis, the largest `|τ_i|` realisable at both thrust ends with the other torques at
    /// their box bounds [N m].
    pub torque_capacity: [f32; 3],
    /// `max(0, needed − capacity)` per axis [N m].
    pub torque_shortfall: [f32; 3],
    /// Per axis, the largest `|τ_i|` with the other torques zero and the collective free [N m].
    pub torque_single_axis: [f32; 3],
}

#[cfg(test)]
mod tests;
