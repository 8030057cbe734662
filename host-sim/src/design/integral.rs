//! `design` (unless `--no-integral`): the bounded integral action (docs/integral-action.md) chosen by the
//! design, so that what `design` produces rejects constant mass, thrust-coefficient and force
//! errors and its certificate covers the estimate.
//!
//! The choices, and why each is made the way it is:
//! - **Level** `M_i` [m/s²], per inertial axis, from the disturbance the user asks to cover: a
//!   plant mass error up to a fraction `e` and a constant force up to a fraction `f` of the
//!   plant's weight, in any direction. Holding the plant `m(1 + e)` against gravity and a force
//!   of `f m (1 + e) g` straight down takes `u₃ = g(1 + e + f(1 + e))`, so the vertical estimate
//!   needs `(e + f(1 + e)) g`; a horizontal force needs `f(1 + e) g` on its axis.
//! - **Output filter** `k_η = k_s` [1/s] and **rate limit** `R_i = k_f M_i` [m/s³] (the
//!   estimate crosses its range in `1/k_f`): they are the only integral terms in the extended
//!   Lemma 1, through the reachable-set bound `b_i = min(2 k_η M_i, c R_i)` on `|η̇_f,i|`
//!   (`c ≈ 1`; `controller_core::integral`) and `k_η (b_i + R_i)` on `|η̈_f,i|`, i.e. about
//!   `k_f M_i` on `|u̇|` and `2 k_f k_s M_i` on `|ü|`, the same scaling as the paper's own filter
//!   terms `2√3 k_f M_p` and `2√3 k_f M_p (k_f + k_s)`; and they are known when `M_p,max(k_f,
//!   k_s)` is bisected, before the position gains are chosen.
//! - **Observer** `L_v = 2 ω_p` [1/s], `L_d = ω_p²` [1/s²] (critically damped at the position
//!   loop's natural frequency `ω_p = √k_p`), `z̄ = 0.05 m`, as in the hand-tuned
//!   `host-sim/scenarios/integral-ablation.toml` (`ω_p = 3`: `L_v = 6`, `L_d = 9`).
//! - **Integral gain** `k_i = ω_p³/5` [1/s³] (that file's 5 at `ω_p = 3`), halved until the
//!   Liénard–Chipart conditions of the linearised loop hold
//!   ([`controller_core::integral_stability::local_stability_conditions`]): every design
//!   `design` (unless `--no-integral`) maps is locally exponentially stable by construction.
//! - **Feedforward scale** (`controller_core::feedforward_scale`), when a mass error is
//!   covered: level `μ̄ = e + 0.02`, the values of `host-sim/scenarios/mass-error.toml` otherwise
//!   (`λ = 4 /s`, `a₀ = 0.1 m/s²`, `R_μ = 0.05 /s`, `z̄_μ = z̄`): it removes the periodic residual
//!   a mass error leaves on an accelerating reference, and its terms widen the reference's
//!   constants by `1 + μ̄` plus `R_μ`-sized terms, already in the probe's bounds.

use controller_core::integral_stability::local_stability_conditions;
use controller_core::position::PositionGains;
use controller_core::{FeedforwardScaleGains, IntegralGains, ObserverGains};
use nalgebra::Vector3;

/// `z̄` \[m\]: clamp of `z₁` before `k_i` (the hand-tuned scenarios' value).
pub const ERROR_LIMIT_M: f64 = 0.05;
/// Margin of the feedforward scale's level above the covered mass error (module docs).
const SCALE_LEVEL_MARGIN: f64 = 0.02;
/// Most halvings of `k_i` tried before a design is refused.
const HALVINGS: usize = 40;

/// The disturbance `design` (unless `--no-integral`) covers, and the estimate's level it needs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct IntegralSpec {
    /// Largest plant mass error covered, as a fraction of the model's mass.
    pub mass_error_fraction: f64,
    /// Largest constant force covered, as a fraction of the plant's weight.
    pub force_fraction: f64,
    /// `M_i` [m/s²] per inertial axis (x, y, z; module docs).
    pub level_m_s2: [f64; 3],
}

impl IntegralSpec {
    /// The spec covering a mass error `e` and a force fraction `f` under gravity `g` [m/s²].
    /// Errors (with the value): `e` not in `[0, 1)`, `f` negative or non-finite, both zero
    /// (nothing to cover: `M_i` must be `> 0`).
    pub fn covering(gravity: f64, e: f64, f: f64) -> Result<Self, String> {
        if !(e.is_finite() && (0.0..1.0).contains(&e)) {
            return Err(format!("--integral-mass-error: must be in [0, 1), got {e}"));
        }
        if !(f.is_finite() && f >= 0.0) {
            return Err(format!(
                "--integral-force-fraction: must be finite and >= 0, got {f}"
            ));
        }
        let horizontal = f * (1.0 + e) * gravity;
        let vertical = (e + f * (1.0 + e)) * gravity;
        if horizontal <= 0.0 || vertical <= 0.0 {
            return Err(format!(
                "integral action: the levels must be > 0 on every axis (horizontal {horizontal} m/s^2 \
                 from --integral-force-fraction {f}, vertical {vertical} m/s^2): give a force \
                 fraction > 0"
            ));
        }
        Ok(Self {
            mass_error_fraction: e,
            force_fraction: f,
            level_m_s2: [horizontal, horizontal, vertical],
        })
    }

    /// The integral terms that enter the bounds (level, rate limit `k_f M_i`, output filter
    /// `k_η = k_s`, the feedforward scale) for the position filter gains `k_f`, `k_s` [1/s];
    /// `k_i = 1` and no observer, which enter none of them. For `certify`'s envelope only.
    pub fn probe(&self, kf: f64, ks: f64) -> IntegralGains<f64> {
        let level = Vector3::from(self.level_m_s2);
        IntegralGains {
            feedforward_scale: self.feedforward_scale(),
            gain: 1.0,
            level,
            rate: level * kf,
            bandwidth: ks,
            observer: None,
        }
    }

    /// The feedforward scale for the covered mass error (module docs); `None` when no mass
    /// error is covered.
    pub fn feedforward_scale(&self) -> Option<FeedforwardScaleGains<f64>> {
        let e = self.mass_error_fraction;
        (e > 0.0 && e + SCALE_LEVEL_MARGIN < 1.0).then_some(FeedforwardScaleGains {
            gain: 4.0,
            excitation: 0.1,
            level: e + SCALE_LEVEL_MARGIN,
            rate: 0.05,
            tracking_limit: ERROR_LIMIT_M,
        })
    }

    /// The full integral gains for the position gains `position` (module docs): the probe's
    /// bound terms, the observer at `ω_p = √k_p`, and `k_i` halved from `ω_p³/5` until the
    /// Liénard–Chipart conditions hold. `None` if they do not hold within 40 halvings.
    pub fn gains(&self, position: &PositionGains<f64>) -> Option<IntegralGains<f64>> {
        self.gains_with_filters(position, (position.kf, position.ks))
    }

    /// [`Self::gains`] with the bound terms of the filter gains `(k_f, k_s)` [1/s] instead of
    /// `position`'s: with the envelope design the integral action is sized by the global
    /// filters (so the global certificate is the one designed) and made stable with the local
    /// regime's position gains, the ones it settles with (docs/envelope-design.md).
    pub fn gains_with_filters(
        &self,
        position: &PositionGains<f64>,
        filters: (f64, f64),
    ) -> Option<IntegralGains<f64>> {
        self.gains_at(position.kp.sqrt(), position, filters)
    }

    /// [`Self::gains_with_filters`] sized at the frequency `wp` [rad/s] instead of
    /// `√(position.k_p)`: `k_i` from `wp³/5`, the observer at `wp`, still halved until the
    /// Liénard–Chipart conditions hold with `position`'s gains. Why: a loop stiffer than the
    /// frequency its integral is sized at keeps the integral slow beside it (the local loop's
    /// polish, `crate::design::refine::local_loop`). `None` as [`Self::gains`].
    pub fn gains_at(
        &self,
        wp: f64,
        position: &PositionGains<f64>,
        (kf, ks): (f64, f64),
    ) -> Option<IntegralGains<f64>> {
        let mut g = IntegralGains {
            gain: wp.powi(3) / 5.0,
            observer: Some(ObserverGains {
                velocity_gain: 2.0 * wp,
                disturbance_gain: wp * wp,
                error_limit: ERROR_LIMIT_M,
            }),
            ..self.probe(kf, ks)
        };
        for _ in 0..HALVINGS {
            if local_stability_conditions(position, &g)
                .iter()
                .all(|c| c.holds)
            {
                return Some(g);
            }
            g.gain *= 0.5;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The feedforward scale comes with a covered mass error, above it, and not without one.
    #[test]
    fn feedforward_scale_covers_the_mass_error_only() {
        let s = IntegralSpec::covering(9.81, 0.2, 0.1).unwrap();
        let f = s.feedforward_scale().unwrap();
        assert!(f.level > 0.2 && f.level < 1.0 && f.validate().is_ok());
        assert_eq!(s.probe(1.0, 3.0).feedforward_scale, Some(f));
        let force_only = IntegralSpec::covering(9.81, 0.0, 0.1).unwrap();
        assert_eq!(force_only.feedforward_scale(), None);
    }

    #[test]
    fn levels_hold_the_heavier_plant_against_a_downward_force() {
        // Given a 20 % heavier plant and a force of 10 % of its weight straight down,
        let (g, e, f) = (9.81, 0.2, 0.1);
        let s = IntegralSpec::covering(g, e, f).unwrap();
        // when the vertical estimate sits at its level, the thrust per model mass m(g + M_i,z)
        // holds the plant's weight plus the force, m (1 + e) g (1 + f);
        let [x, y, z] = s.level_m_s2;
        assert!(((g + z) - (1.0 + e) * g * (1.0 + f)).abs() < 1e-12);
        // and a horizontal force of the same size needs exactly the horizontal level.
        assert!((x - f * (1.0 + e) * g).abs() < 1e-12);
        assert_eq!(x, y);
    }

    #[test]
    fn bad_coverage_is_refused_with_the_flag() {
        for (e, f, flag) in [
            (1.0, 0.1, "--integral-mass-error"),
            (-0.1, 0.1, "--integral-mass-error"),
            (0.2, f64::NAN, "--integral-force-fraction"),
            (0.2, 0.0, "force fraction > 0"),
        ] {
            let err = IntegralSpec::covering(9.81, e, f).unwrap_err();
            assert!(err.contains(flag), "{e} {f}: {err}");
        }
    }

    #[test]
    fn every_mapped_loop_is_locally_stable() {
        // Over the design's position box (ω_p in [0.5, 4], ζ_p in [0.6, 1.5], k_f in [0.1, 6],
        // k_s/k_f in [1.5, 12]) the gains found pass the Liénard–Chipart conditions, keep the
        // probe's bound terms, and k_i is the largest of its halvings that does.
        let s = IntegralSpec::covering(9.81, 0.2, 0.1).unwrap();
        for wp in [0.5, 1.0, 2.0, 4.0] {
            for zeta in [0.6, 1.0, 1.5] {
                for kf in [0.1, 1.0, 6.0] {
                    for ratio in [1.5, 12.0] {
                        let p = PositionGains {
                            kp: wp * wp,
                            kv: 2.0 * zeta * wp,
                            kf,
                            ks: ratio * kf,
                            saturation: 1.0,
                            saturation_shape: controller_core::position_saturation::PositionSaturation::Componentwise,
                            vertical: None,
                        };
                        let g = s.gains(&p).expect("stable within the halvings");
                        assert!(local_stability_conditions(&p, &g).iter().all(|c| c.holds));
                        let probe = s.probe(kf, ratio * kf);
                        assert_eq!(
                            (g.level, g.rate, g.bandwidth),
                            (probe.level, probe.rate, probe.bandwidth)
                        );
                        let twice = IntegralGains {
                            gain: 2.0 * g.gain,
                            ..g
                        };
                        assert!(
                            g.gain == wp.powi(3) / 5.0
                                || !local_stability_conditions(&p, &twice)
                                    .iter()
                                    .all(|c| c.holds),
                            "k_i {} not the largest halving at wp {wp} zeta {zeta} kf {kf}",
                            g.gain
                        );
                    }
                }
            }
        }
    }

    /// Given a stiff local loop (`ω_p` 8 rad/s, the top of the local range) and the integral
    /// sized at a slower frequency `ω_i`, when the gains are found, then the observer runs at
    /// `ω_i` (not at `ω_p`), `k_i` is the largest halving of `ω_i³/5` that passes the
    /// Liénard–Chipart conditions *with the stiff loop's gains*.
    #[test]
    fn an_integral_held_apart_is_sized_at_its_own_frequency_and_stable_with_the_loop() {
        let s = IntegralSpec::covering(9.81, 0.2, 0.1).unwrap();
        for (wp, zeta, wi) in [(8.0, 0.9, 3.09), (8.0, 0.6, 0.5), (5.2, 1.5, 2.0)] {
            let p = PositionGains {
                kp: wp * wp,
                kv: 2.0 * zeta * wp,
                kf: 1.77,
                ks: 3.0,
                saturation: 0.84,
                saturation_shape: controller_core::position_saturation::PositionSaturation::Norm,
                vertical: None,
            };
            let g = s.gains_at(wi, &p, (0.88, 1.4)).expect("stable");
            let o = g.observer.unwrap();
            assert_eq!((o.velocity_gain, o.disturbance_gain), (2.0 * wi, wi * wi));
            assert!(local_stability_conditions(&p, &g).iter().all(|c| c.holds));
            let twice = IntegralGains {
                gain: 2.0 * g.gain,
                ..g
            };
            assert!(
                g.gain == wi.powi(3) / 5.0
                    || !local_stability_conditions(&p, &twice)
                        .iter()
                        .all(|c| c.holds)
            );
        }
    }
}
