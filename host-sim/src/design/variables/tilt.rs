//! Tilt priority's choices (variables 9-11, and 12 in the turn-over refinement, of the parent module's table) and the gains they
//! map to: per-axis levels, the trace and radial terms (docs/tilt-priority.md) and the
//! turn-over term on top (docs/turn-over.md).

use controller_core::{TiltPriorityGains, TurnOver};
use nalgebra::Vector3;

use super::super::authority::{mrp_factor, DELTA};

/// The choices of tilt priority (variables 9-11 of the parent module's table, and 12 in the
/// turn-over refinement).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TiltChoices {
    /// `ρ = ι₃/ι₁`.
    pub yaw_share: f64,
    /// Share of `ι₃` in the radial MRP term.
    pub yaw_radial_share: f64,
    /// Share of `ι₁ − (1+(1+δ)²)M_ϑ/4` in the trace term.
    pub roll_trace_share: f64,
    /// The turn-over term's level as a share of roll's level, `M_t / ι₁`, on top of the levels
    /// (onset [`TURN_OVER_ONSET`]); `None`: not searched, the term off (as at 0).
    pub turn_over_share: Option<f64>,
}

impl TiltChoices {
    /// The initial guess: yaw a tenth of roll, mostly radial, roll mostly trace, the turn-over
    /// term not searched.
    pub fn initial_guess() -> Self {
        Self {
            yaw_share: 0.1,
            yaw_radial_share: 0.6,
            roll_trace_share: 0.6,
            turn_over_share: None,
        }
    }

    /// The turn-over share `M_t / ι₁` flown (dimensionless): 0 when not searched.
    pub fn turn_over(&self) -> f64 {
        self.turn_over_share.unwrap_or(0.0)
    }
}

/// The turn-over term's onset `ρ₀` in every design (a rotation by 4 atan 0.8 = 154.6° about a
/// horizontal axis): lower onsets act over more of the turn, at a slightly larger yaw bound.
pub const TURN_OVER_ONSET: f64 = 0.8;

/// The turn-over term of `share` (of roll's level `iota` [N m]); `None` when `share` is 0.
fn turn_over_of(share: f64, iota: f64) -> Option<TurnOver<f64>> {
    (share > 0.0).then_some(TurnOver {
        level: share * iota,
        onset: TURN_OVER_ONSET,
    })
}

/// The per-axis bounds of the turn-over term per newton metre of roll's level at `share`
/// (dimensionless): what it adds to the levels `(1, 1, ρ)`.
pub(super) fn turn_over_shares(share: f64) -> Vector3<f64> {
    turn_over_of(share, 1.0).map_or(Vector3::zeros(), |t| t.bounds(DELTA))
}

/// `((1 + δ)² − 1)(1 + δ)`: the factor of `tr G − min g` in tilt priority's hysteresis-band
/// condition ([`TiltPriorityGains::hysteresis_band`]).
pub(super) fn band_factor() -> f64 {
    ((1.0 + DELTA).powi(2) - 1.0) * (1.0 + DELTA)
}

/// Tilt priority's gains for roll/pitch level `iota` [N m] and yaw level `ρ iota` (module
/// table), with the turn-over term of `t.turn_over_share` (of `iota`) on top, for attitude
/// stiffness `k_mrp` [N m], the body-frame inertia diagonal `inertia` [kg m²] and damping ratio
/// `damping`. Returns the gains and `M_ϑ` (dimensionless). No errors.
pub(super) fn tilt_gains(
    t: &TiltChoices,
    iota: f64,
    k_mrp: f64,
    inertia: &Vector3<f64>,
    damping: f64,
) -> (TiltPriorityGains<f64>, f64) {
    let iota_yaw = t.yaw_share * iota;
    let radial = t.yaw_radial_share * iota_yaw;
    let mrp_saturation = radial / mrp_factor();
    // The band condition: M_ϑ k_ϑ/√(M_ϑ² + k_ϑ²) > (g₁ + g₃) · band_factor. With g₃ ≥ g₁ it
    // needs g₁ below half the cap; a soft stiffness (the slope `k_ϑ` below `M_ϑ`) can leave
    // less than yaw's share would give, and yaw's damping level takes the rest.
    let band_lhs = mrp_saturation * k_mrp / mrp_saturation.hypot(k_mrp);
    let g_tilt = (0.5 * (iota_yaw - radial)).min(0.45 * band_lhs / band_factor());
    let g_yaw_cap = 0.9 * band_lhs / band_factor() - g_tilt;
    let g_yaw = (2.0 * t.roll_trace_share * (iota - radial) - g_tilt)
        .min(g_yaw_cap)
        .max(g_tilt);
    let g = Vector3::new(g_tilt, g_tilt, g_yaw);
    let trace_level = Vector3::new(0.5 * (g.y + g.z), 0.5 * (g.x + g.z), 0.5 * (g.x + g.y));
    let levels = Vector3::new(iota, iota, iota_yaw);
    let omega_levels = levels - trace_level.add_scalar(radial);
    let stiffness = trace_level.add_scalar(k_mrp / 16.0);
    let omega_gains = stiffness.zip_map(inertia, |k, j| 2.0 * damping * (k * j).sqrt());
    (
        TiltPriorityGains {
            trace_weights: g,
            omega_gains,
            omega_levels,
            turn_over: turn_over_of(t.turn_over(), iota),
        },
        mrp_saturation,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Given levels whose radial term's stiffness `k_ϑ` is far below its level `M_ϑ` (a soft,
    /// slow attitude loop on a large level: the band condition's slope is then about `k_ϑ`,
    /// whatever `ι`), when mapped to gains over a wide range of `ι`, then tilt priority's
    /// hysteresis-band condition holds at every one, and the levels are spent as chosen.
    #[test]
    fn the_band_holds_when_the_stiffness_is_soft() {
        let t = TiltChoices {
            yaw_share: 0.3,
            yaw_radial_share: 0.5,
            roll_trace_share: 0.9,
            turn_over_share: Some(0.3),
        };
        let inertia = Vector3::new(1.4e-5, 1.4e-5, 2.2e-5);
        let k_mrp = 1e-4;
        for iota in [1e-4, 1e-3, 1e-2, 0.1, 1.0] {
            let (g, mrp_saturation) = tilt_gains(&t, iota, k_mrp, &inertia, 0.7);
            let attitude = controller_core::attitude_control::AttitudeGains {
                k_mrp,
                k_omega: 1.0,
                mrp_saturation,
                omega_saturation: 1.0,
            };
            let (lhs, rhs) = g.hysteresis_band(&attitude, DELTA);
            assert!(lhs > rhs, "iota {iota}: band {lhs} <= {rhs}");
            assert!(g.omega_levels.min() >= 0.0, "{:?}", g.omega_levels);
            let levels = g.feedback_levels(mrp_saturation, DELTA) - g.turn_over_bounds(DELTA);
            let chosen = Vector3::new(iota, iota, t.yaw_share * iota);
            assert!(
                (levels - chosen).abs().max() <= 1e-12 * iota,
                "iota {iota}: {levels:?} vs {chosen:?}"
            );
        }
    }
}
