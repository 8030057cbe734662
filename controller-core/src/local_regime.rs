//! The envelope design's local regime: faster position gains flown while the attitude error is
//! inside a sublevel set of the attitude energy ([`crate::attitude_energy`]: every sublevel set
//! is forward invariant), the global gains outside it (extension, docs/envelope-design.md).
//!
//! **The switch.** The controller flies the global gains until `E ≤ E_in`, then the local ones
//! (`k_p, k_v, k_f, k_s` and the level `M_p,L`: faster filters, the shape is shared; with the
//! vertical channel apart, optionally its own vertical channel: filters `k_f,z,L, k_s,z,L` and
//! levels `M_up,L, M_down,L`) once the filter states lie in the local saturation set, and goes
//! back only if `E > E_out > E_in` (which the nominal model never does: `E` does not
//! increase). The local regime may fly its own attitude law too ([`LocalAttitude`]: stiffer
//! and better damped than the global gains afford at every attitude), and then `E` is that
//! law's energy; and its own horizontal braking ([`LocalGains::braking`]). At the switch to
//! the local gains the inner filter state is re-timed so that `u̇ = −k_f(u_f − u_s)` keeps its
//! value ([`retime`]): `ω_d` does not jump, and neither does
//! `E`. The re-timed state lies between `u_f` and `u_s` (the local `k_f` is at least the global
//! one), so it stays in the saturation set Lemma 1 assumes.
//!
//! **What it certifies.** Inside `{E ≤ E_out}` the MRP error, the rotation error and `ω̃` are
//! bounded ([`crate::attitude_energy::EnergyLimits`]), so the local regime's torque is bounded
//! by the feedback at those errors plus the feedforward of the local gains' Lemma 1, turned by
//! at most that rotation (`crate::bounds`' local certificate): much less than Theorem 2's worst
//! case over every attitude, so faster filters fit the same rotors.

use crate::parameter_error::{positive, ParameterError};
use crate::position::{FilterState, PositionGains};
use crate::scalar::{to_f64, Scalar};
use crate::velocity_limit::VelocityLimit;
use crate::vertical_channel::VerticalChannel;

mod attitude;
pub use attitude::LocalAttitude;

/// The local regime's position gains and the energy levels of its switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalGains<T: Scalar> {
    /// `k_p` [1/s²] of the local regime.
    pub kp: T,
    /// `k_v` [1/s] of the local regime.
    pub kv: T,
    /// `k_f` [1/s] of the local regime (at least the global `k_f`).
    pub kf: T,
    /// `k_s` [1/s] of the local regime.
    pub ks: T,
    /// `M_p,L` [m/s²] of the local regime (the global shape; the horizontal level with the
    /// vertical channel apart): below `M_p`, a smaller tilt range, so smaller thrust-direction
    /// rates and a smaller yaw share of them; above it, more authority where the attitude is
    /// near the reference and the torque demand small.
    pub saturation: T,
    /// `E_in` \[J\]: the local gains take over once the attitude energy is at most this (and the
    /// filter states lie in the local saturation set).
    pub energy_in: T,
    /// `E_out` \[J\], `> E_in`: the global gains take back over above this.
    pub energy_out: T,
    /// The local regime's own vertical channel (filters `k_f,z,L, k_s,z,L` and levels
    /// `M_up,L, M_down,L`), with the vertical channel apart ([`crate::vertical_channel`]);
    /// `None`: the global vertical channel in both regimes. Near the reference the tilt is small,
    /// and a vertical change of `u` turns the thrust direction only through the tilt
    /// (docs/vertical-channel.md), so faster vertical filters cost little torque there; smaller
    /// levels shrink the span `M_up + M_down` every vertical rate of Lemma 1 is proportional to,
    /// so the same torque pays for faster filters (extension, docs/envelope-design.md).
    pub vertical: Option<VerticalChannel<T>>,
    /// The local regime's own attitude law ([`LocalAttitude`]); `None`: the global law in both
    /// regimes. With it, the switch measures the attitude energy of this law.
    pub attitude: Option<LocalAttitude<T>>,
    /// The local regime's horizontal braking acceleration `a_L` [m/s²], `0 < a_L < M_p,L`
    /// (the vertical one too without the vertical channel apart), with the global velocity
    /// limit ([`crate::velocity_limit`]); `None`: the global braking at the local level's share
    /// ([`Self::velocity_limit`]). A larger level brakes no harder without it.
    pub braking: Option<T>,
}

/// Which position gains fly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Regime {
    /// The global gains (certified for any attitude).
    #[default]
    Global,
    /// The local gains (certified inside `{E ≤ E_out}`).
    Local,
}

impl<T: Scalar> LocalGains<T> {
    /// Checks the gains `> 0`, `0 < E_in < E_out` and `k_f` at least `global`'s (`M_p,L` may
    /// exceed `M_p`: the certificate then checks Theorem 1 for the local level too); local
    /// vertical filters only with `global`'s vertical channel, and `k_f,z,L` at least its `k_f,z`.
    /// Errors: [`ParameterError::NotPositive`] naming the gain (`"local k_p"`, …, `"E_in"`,
    /// `"local k_f,z"`, `"local k_s,z"`, `"local M_up"`, `"local M_down"`, `"local braking"`,
    /// the local attitude law's, [`LocalAttitude::validate`]), `"local braking"` not below
    /// `M_p,L` ([`ParameterError::OutOfRange`]),
    /// [`ParameterError::OutOfRange`] naming `"E_out"` (not above `E_in`), `"local k_f"` (below
    /// the global `k_f`) or `"local k_f,z"` (below the global `k_f,z`, or without a vertical
    /// channel: the range is then empty).
    pub fn validate(&self, global: &PositionGains<T>) -> Result<(), ParameterError> {
        for (name, v) in [
            ("local k_p", self.kp),
            ("local k_v", self.kv),
            ("local k_f", self.kf),
            ("local k_s", self.ks),
            ("local M_p", self.saturation),
            ("E_in", self.energy_in),
        ] {
            positive(name, v)?;
        }
        if !(self.energy_out.is_finite() && self.energy_out > self.energy_in) {
            return Err(ParameterError::OutOfRange {
                name: "E_out",
                value: to_f64(self.energy_out),
                low: to_f64(self.energy_in),
                high: f64::INFINITY,
            });
        }
        if self.kf < global.kf {
            return Err(ParameterError::OutOfRange {
                name: "local k_f",
                value: to_f64(self.kf),
                low: to_f64(global.kf),
                high: f64::INFINITY,
            });
        }
        if let Some(f) = &self.vertical {
            positive("local k_f,z", f.kf)?;
            positive("local k_s,z", f.ks)?;
            let (low, high) = match &global.vertical {
                Some(v) => (to_f64(v.kf), f64::INFINITY),
                None => (f64::INFINITY, f64::NEG_INFINITY),
            };
            if !(to_f64(f.kf) >= low && to_f64(f.kf) <= high) {
                return Err(ParameterError::OutOfRange {
                    name: "local k_f,z",
                    value: to_f64(f.kf),
                    low,
                    high,
                });
            }
            positive("local M_up", f.up)?;
            positive("local M_down", f.down)?;
        }
        if let Some(a) = &self.attitude {
            a.validate()?;
        }
        if let Some(b) = self.braking {
            positive("local braking", b)?;
            if b >= self.saturation {
                return Err(ParameterError::OutOfRange {
                    name: "local braking",
                    value: to_f64(b),
                    low: 0.0,
                    high: to_f64(self.saturation),
                });
            }
        }
        Ok(())
    }

    /// The local regime's position gains: these `k_p, k_v, k_f, k_s, M_p,L` with `global`'s
    /// saturation shape, and the local vertical channel when there is one (`global`'s otherwise).
    pub fn position(&self, global: &PositionGains<T>) -> PositionGains<T> {
        let vertical = match (global.vertical, self.vertical) {
            (Some(_), Some(f)) => Some(f),
            (v, _) => v,
        };
        PositionGains {
            kp: self.kp,
            kv: self.kv,
            kf: self.kf,
            ks: self.ks,
            saturation: self.saturation,
            vertical,
            ..*global
        }
    }

    /// The velocity limit the local regime flies, for the global gains `global` and their
    /// velocity limit `limit`: each braking acceleration times `min(1, local level / global
    /// level)` of its axis (`M_p,L / M_p`, and with the local vertical channel `M_up,L / M_up`
    /// and `M_down,L / M_down`), so it keeps its share of a smaller local level and stays below
    /// it, and is `limit` itself, bit for bit, where no local level is smaller; with the local
    /// regime's own braking ([`Self::braking`]) its horizontal braking is that one instead.
    /// No errors. Source: extension (docs/envelope-design.md).
    pub fn velocity_limit(
        &self,
        global: &PositionGains<T>,
        limit: &VelocityLimit<T>,
    ) -> VelocityLimit<T> {
        let share = |local: T, of: T| (local / of).min(T::one());
        let vertical = match (global.vertical, self.vertical) {
            (Some(g), Some(l)) => (share(l.up, g.up), share(l.down, g.down)),
            _ => (T::one(), T::one()),
        };
        let scaled = limit.scaled(share(self.saturation, global.saturation), vertical);
        match self.braking {
            Some(braking) => VelocityLimit { braking, ..scaled },
            None => scaled,
        }
    }

    /// The regime after a sample whose attitude energy is `energy` \[J\], from `current`, with the
    /// filter states `filter` [m/s²] the next sample starts from under `global`'s gains: the
    /// hysteresis `Global → Local` at `E ≤ E_in` once the filter states re-timed to the local
    /// `k_f` lie in the local saturation set (so Lemma 1's premise holds for the local gains),
    /// `Local → Global` at `E > E_out`. Returns the regime and the filter states it starts from
    /// ([`retime`]d when the regime changes).
    pub fn switch(
        &self,
        global: &PositionGains<T>,
        current: Regime,
        energy: T,
        filter: &FilterState<T>,
    ) -> (Regime, FilterState<T>) {
        match current {
            Regime::Global if energy <= self.energy_in => {
                let local = self.position(global);
                let f = retime(filter, global, &local, global);
                if local.contains(&f.u_f) && local.contains(&f.u_s) {
                    (Regime::Local, f)
                } else {
                    (Regime::Global, *filter)
                }
            }
            Regime::Local if energy > self.energy_out => {
                let local = self.position(global);
                (Regime::Global, retime(filter, &local, global, global))
            }
            r => (r, *filter),
        }
    }
}

/// The inner filter state re-timed when the position gains change from `from` to `to`:
/// `u_s' = u_f − (k_f,from/k_f,to)(u_f − u_s)` (per channel with the vertical channel apart,
/// each with its own `k_f`), so that `u̇ = −k_f(u_f − u_s)` keeps its value (`ω_d` does not
/// jump). With `to`'s `k_f` at least `from`'s the new state lies between `u_f` and `u_s`; the
/// other way it may leave the saturation set of `set` (the global gains'), and both states are
/// then brought back into it ([`PositionGains::project`]; `u_f` too when `M_p,L > M_p`: a jump
/// of `u` and `u̇`, only on the way back to the global gains, whose certificate covers any
/// attitude). Source: extension (docs/envelope-design.md).
pub fn retime<T: Scalar>(
    filter: &FilterState<T>,
    from: &PositionGains<T>,
    to: &PositionGains<T>,
    set: &PositionGains<T>,
) -> FilterState<T> {
    let mut u_s = filter.u_f - (filter.u_f - filter.u_s) * (from.kf / to.kf);
    if let (Some(a), Some(b)) = (&from.vertical, &to.vertical) {
        // The vertical channel has its own filters: re-timed by its own bandwidths (unchanged
        // when both regimes share them).
        u_s.z = if a.kf == b.kf {
            filter.u_s.z
        } else {
            filter.u_f.z - (filter.u_f.z - filter.u_s.z) * (a.kf / b.kf)
        };
    }
    FilterState {
        u_f: set.project(&filter.u_f),
        u_s: set.project(&u_s),
    }
}

#[cfg(test)]
mod tests;
