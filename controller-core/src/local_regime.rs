//! The envelope design's local regime: faster position gains flown while the attitude error is
//! inside a sublevel set of the attitude energy, the global gains outside it (extension,
//! docs/envelope-design.md).
//!
//! **The attitude energy.** With the law's exact feedforward `τ_c`, the attitude error obeys
//! `J ω̃̇ = Δ + τ_fb` with `ω̃ᵀΔ = 0` (the paper's `Δ`, Section V), whatever `ω_d` and `ω̇_d` are.
//! The energy `E = ½ ω̃ᵀJω̃ + Ψ(ϑ̃)`, with `Ψ(ϑ) = (M_ϑ/k_ϑ)(√(M_ϑ² + k_ϑ²|ϑ|²) − M_ϑ)` (whose
//! gradient is `s_ϑ(k_ϑ ϑ)`) and, with tilt priority, the trace potential `½ tr(G(I − R̃))`,
//! obeys `Ė = −ω̃ᵀ s_ω(ω̃) ≤ 0` along flows (the MRP identity `ϑᵀT(ϑ) = (1 + |ϑ|²)/4 ϑᵀ` turns the
//! MRP term into `d/dt Ψ`), and drops at the path lifting's jumps (`Ψ` falls as `|ϑ̃|` goes from
//! `1 + δ` to its shadow's `1/(1 + δ)`; the memory resets keep `ϑ̃`). So **every sublevel set
//! `{E ≤ c}` is forward invariant, whatever the position loop does**, as long as `ω_d` does not
//! jump (`ω̃` would).
//!
//! **The switch.** The controller flies the global gains until `E ≤ E_in`, then the local ones
//! (`k_p, k_v, k_f, k_s`: faster filters; `M_p` and the shape are shared), and goes back only if
//! `E > E_out > E_in` (which the nominal model never does: `E` does not increase). At the switch
//! to the local gains the inner filter state is re-timed so that `u̇ = −k_f(u_f − u_s)` keeps its
//! value ([`retime`]): `ω_d` does not jump, and neither does `E`. The re-timed state lies between
//! `u_f` and `u_s` (the local `k_f` is at least the global one), so it stays in the saturation set
//! Lemma 1 assumes.
//!
//! **What it certifies.** Inside `{E ≤ E_out}` the MRP error, the rotation error and `ω̃` are
//! bounded ([`EnergyLimits`]), so the local regime's torque is bounded by the feedback at those
//! errors plus the feedforward of the local gains' Lemma 1, turned by at most that rotation
//! (`crate::bounds`' local certificate): much less than Theorem 2's worst case over every
//! attitude, so faster filters fit the same rotors.

use nalgebra::{Matrix3, Vector3};

use crate::gains::Gains;
use crate::parameter_error::{positive, ParameterError};
use crate::position::{FilterState, PositionGains};
use crate::scalar::{lit, to_f64, Scalar};

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
    /// `M_p,L` [m/s²] of the local regime, in `(0, M_p]` (the global shape): a smaller tilt range,
    /// so smaller thrust-direction rates and a smaller yaw share of them.
    pub saturation: T,
    /// `E_in` [J]: the local gains take over once the attitude energy is at most this (and the
    /// filter states lie in the local saturation set).
    pub energy_in: T,
    /// `E_out` [J], `> E_in`: the global gains take back over above this.
    pub energy_out: T,
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

/// Bounds on the attitude error inside `{E ≤ c}`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyLimits<T: Scalar> {
    /// `c` [J].
    pub energy: T,
    /// Largest `|ϑ̃|` (dimensionless): `√((M_ϑ + c k_ϑ/M_ϑ)² − M_ϑ²)/k_ϑ`, from `Ψ(ϑ̃) ≤ c`,
    /// at most `1 + δ`.
    pub mrp: T,
    /// Largest rotation angle of `R̃` [rad]: `4 atan(|ϑ̃|)` (π once `|ϑ̃| ≥ 1`).
    pub angle: T,
    /// Largest `|ω̃_i|` per body axis [rad/s]: `√(2c/J_ii)`, from `½ ω̃ᵀJω̃ ≤ c`.
    pub omega_error: Vector3<T>,
}

impl<T: Scalar> LocalGains<T> {
    /// Checks the gains `> 0`, `0 < E_in < E_out`, `k_f` at least `global`'s and
    /// `0 < M_p,L ≤ M_p`.
    /// Errors: [`ParameterError::NotPositive`] naming the gain (`"local k_p"`, …, `"E_in"`),
    /// [`ParameterError::OutOfRange`] naming `"E_out"` (not above `E_in`), `"local k_f"`
    /// (below the global `k_f`) or `"local M_p"` (above the global `M_p`).
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
        if self.saturation > global.saturation {
            return Err(ParameterError::OutOfRange {
                name: "local M_p",
                value: to_f64(self.saturation),
                low: 0.0,
                high: to_f64(global.saturation),
            });
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
        Ok(())
    }

    /// The local regime's position gains: these `k_p, k_v, k_f, k_s, M_p,L` with `global`'s
    /// saturation shape.
    pub fn position(&self, global: &PositionGains<T>) -> PositionGains<T> {
        PositionGains {
            kp: self.kp,
            kv: self.kv,
            kf: self.kf,
            ks: self.ks,
            saturation: self.saturation,
            ..*global
        }
    }

    /// The regime after a sample whose attitude energy is `energy` [J], from `current`, with the
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
                let f = retime(filter, global.kf, self.kf, global);
                if local.contains(&f.u_f) && local.contains(&f.u_s) {
                    (Regime::Local, f)
                } else {
                    (Regime::Global, *filter)
                }
            }
            Regime::Local if energy > self.energy_out => {
                (Regime::Global, retime(filter, self.kf, global.kf, global))
            }
            r => (r, *filter),
        }
    }
}

/// The attitude energy `E = ½ ω̃ᵀJω̃ + Ψ(ϑ̃) (+ ½ tr(G(I − R̃)) with tilt priority)` [J] of the
/// MRP error `mrp_error`, the angular velocity error `omega_error` [rad/s] (body) and the error
/// rotation `error_rotation` (`R̃ = R_dᵀR`) for `gains` and the inertia diagonal `inertia`
/// [kg m²] (module documentation). Non-increasing along the closed loop with the exact
/// feedforward. Source: extension of Theorem 2's argument (docs/envelope-design.md).
pub fn attitude_energy<T: Scalar>(
    gains: &Gains<T>,
    inertia: &Vector3<T>,
    mrp_error: &Vector3<T>,
    omega_error: &Vector3<T>,
    error_rotation: &Matrix3<T>,
) -> T {
    let a = &gains.attitude;
    let (m, k) = (a.mrp_saturation, a.k_mrp);
    let kinetic = omega_error.dot(&inertia.component_mul(omega_error)) * lit(0.5);
    let potential = (m / k) * ((m * m + k * k * mrp_error.norm_squared()).sqrt() - m);
    let trace = match &gains.tilt_priority {
        None => T::zero(),
        Some(t) => {
            let g = &t.trace_weights;
            let r = error_rotation;
            (g.x * (T::one() - r[(0, 0)])
                + g.y * (T::one() - r[(1, 1)])
                + g.z * (T::one() - r[(2, 2)]))
                * lit(0.5)
        }
    };
    kinetic + potential + trace
}

/// The attitude error's bounds inside `{E ≤ energy}` for `gains` and `inertia` [kg m²] (module
/// documentation). The trace potential (tilt priority) only lowers them further; it is left
/// out, so they hold with or without it.
pub fn energy_limits<T: Scalar>(
    gains: &Gains<T>,
    inertia: &Vector3<T>,
    energy: T,
) -> EnergyLimits<T> {
    let a = &gains.attitude;
    let (m, k) = (a.mrp_saturation, a.k_mrp);
    let r = m + energy * k / m;
    let mrp = ((r * r - m * m).max(T::zero()).sqrt() / k).min(T::one() + gains.hysteresis);
    let angle = if mrp >= T::one() {
        T::pi()
    } else {
        lit::<T>(4.0) * mrp.atan()
    };
    EnergyLimits {
        energy,
        mrp,
        angle,
        omega_error: inertia.map(|j| (lit::<T>(2.0) * energy / j).sqrt()),
    }
}

/// The inner filter state re-timed when `k_f` changes from `from_kf` to `to_kf` [1/s]:
/// `u_s' = u_f − (from_kf/to_kf)(u_f − u_s)`, so that `u̇ = −k_f(u_f − u_s)` keeps its value
/// (`ω_d` does not jump); with the vertical channel apart only its horizontal part, the vertical
/// filters being the same in both regimes. With `to_kf ≥ from_kf` the new state lies between `u_f` and `u_s`; the
/// other way it may leave the saturation set of `set` (the global gains'), and is then brought
/// back into it ([`PositionGains::project`]: a jump of `u̇`, only on the way back to the global
/// gains, whose certificate covers any attitude). Source: extension (docs/envelope-design.md).
pub fn retime<T: Scalar>(
    filter: &FilterState<T>,
    from_kf: T,
    to_kf: T,
    set: &PositionGains<T>,
) -> FilterState<T> {
    let mut u_s = filter.u_f - (filter.u_f - filter.u_s) * (from_kf / to_kf);
    if set.vertical.is_some() {
        // The vertical channel keeps its own filters in both regimes: nothing to re-time.
        u_s.z = filter.u_s.z;
    }
    FilterState {
        u_f: filter.u_f,
        u_s: set.project(&u_s),
    }
}

#[cfg(test)]
mod tests;
