//! `design --bounds tight`: Theorem 2's torque condition and the rotor fit judged with the tight
//! a-priori bounds ([`crate::bounds::tight`], `docs/tight-bounds.md`) instead of Lemma 1's
//! closed form.
//!
//! Both are sound upper bounds of the same suprema, so any of them, or their minimum, certifies.
//! The search needs one per candidate and cannot afford the full branch and bound, so it takes
//! a small box budget ([`SEARCH_BOXES`]: still sound, looser); the final design is re-bounded
//! with the default budget, which can only lower the bounds (so what fitted still fits):
//!
//! - the certified torque set keeps its shape (Theorem 2's terms, `controller_core::TorqueSet`)
//!   and takes, for the feedforward's ellipsoid and gyroscopic box, the least of its own norms
//!   of `ω_d`, `ω̇_d` and the tight `sup |ω_d|`, `sup |ω̇_d|`: [`tightened_set`];
//! - the feedforward part of the per-axis torque bound, with the same structure as the paper's
//!   (`ff_i = J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²`, the feedforward `J R̃ᵀω̇_d` is rotated by
//!   the attitude error, so only the norm of `ω̇_d` bounds each axis) but with the tight
//!   norms: [`tight_feedforward`];
//! - the per-axis torque bound Theorem 2's conditions are judged with: the least of the paper's
//!   bound, that feedforward plus the feedback level `ι_i`, and the branch and bound's own joint
//!   bound on `|τ_i|`: [`tight_torque`].
//!
//! `M_p,max` is where the tight `ι_max` vanishes, found by a shorter bisection
//! ([`super::authority::saturation_max_with`]).

use anyhow::{anyhow, Result};
use controller_core::{
    certify, FilterStart, Gains, Limits, TorqueSet, TrajectoryConstants, Vehicle,
};
use nalgebra::Vector3;
use serde::Serialize;

use crate::bounds::tight::{tight_bounds, tight_rates, TightOptions};

/// Which bounds certify Theorem 2's torque condition and the box fit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundsKind {
    /// Lemma 1 and Theorem 2 as the paper writes them (what the firmware re-checks on board).
    #[default]
    Paper,
    /// The tight a-priori bounds (branch and bound, outward-rounded intervals).
    Tight,
}

/// Box budget of each tight search per candidate of the optimiser.
pub const SEARCH_BOXES: usize = 1_000;

fn options(boxes: usize) -> TightOptions {
    TightOptions {
        max_boxes: boxes,
        ..TightOptions::default()
    }
}

/// Runs a tight-bounds computation with `boxes` per search. Errors: the set-up is refused (the
/// parameter error, as text).
fn with_budget<R>(
    boxes: usize,
    run: impl FnOnce(&TightOptions) -> Result<R, controller_core::ParameterError>,
) -> Result<R> {
    run(&options(boxes))
        .map_err(|e| anyhow!("tight bounds: {}", crate::model::scenario::describe(&e)))
}

/// The feedforward part of the per-axis torque bound [N m] (body axes) from tight
/// `(sup |ω_d|, sup |ω̇_d|)` = `(W` [rad/s], `A` [rad/s²]`)`: `J_ii A + ½|J_jj − J_kk| W²`.
pub fn tight_feedforward(vehicle: &Vehicle<f64>, (w, a): (f64, f64)) -> Vector3<f64> {
    let j = vehicle.inertia;
    let w2 = w * w;
    Vector3::new(
        j.x * a + 0.5 * (j.y - j.z).abs() * w2,
        j.y * a + 0.5 * (j.z - j.x).abs() * w2,
        j.z * a + 0.5 * (j.x - j.y).abs() * w2,
    )
}

/// Tight `(sup |ω_d|, sup |ω̇_d|)` of `gains` [rad/s, rad/s²] with `boxes` per search.
/// Errors: the set-up is refused (the parameter error, as text).
pub fn rates(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    boxes: usize,
) -> Result<(f64, f64)> {
    with_budget(boxes, |o| {
        tight_rates(vehicle, gains, constants, FilterStart::Zero, o)
    })
}

/// `set` (a certified torque set [N m], body axes) with its feedforward's norms lowered to the
/// tight `(sup |ω_d|, sup |ω̇_d|)` = `(W` [rad/s], `A` [rad/s²]`)` where they are below its own:
/// the ellipsoid's `U_ω̇d` becomes `min(U_ω̇d, A)` and each gyroscopic half-width
/// `min(·, ½|J_jj − J_kk| W²)`; the feedback's parts are kept. Sound: each term of the set is
/// confined by any upper bound of those norms (controller_core's `torque_set` documentation),
/// and the least of two upper bounds is one. No errors.
pub fn tightened_set(set: &TorqueSet<f64>, (w, a): (f64, f64)) -> TorqueSet<f64> {
    let tight = TorqueSet::new(set.inertia, w, a, 0.0, Vector3::zeros());
    TorqueSet {
        angular_acceleration: set.angular_acceleration.min(a),
        gyroscopic: set.gyroscopic.inf(&tight.gyroscopic),
        ..*set
    }
}

/// What the tight bounds certify of a design's torque.
#[derive(Clone, Copy, Debug)]
pub struct TightTorque {
    /// Per-axis bound on `|τ_i|` [N m] (body axes) that Theorem 2's conditions are judged with:
    /// the least of Theorem 2's bound, [`tight_feedforward`] plus the feedback level `ι_i`, and
    /// the branch and bound's bound on `|τ_i|`.
    pub torque_box: Vector3<f64>,
    /// The tight `(sup |ω_d|, sup |ω̇_d|)` [rad/s, rad/s²] the certified set takes
    /// ([`tightened_set`]).
    pub rates: (f64, f64),
}

/// The tight bounds of `gains`' torque ([`TightTorque`]), with `boxes` per search. Errors: the
/// set-up is refused by `certify` or the tight bounds.
pub fn tight_torque(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    boxes: usize,
) -> Result<TightTorque> {
    let limits = Limits {
        thrust_max: 1.0,
        torque_max: Vector3::repeat(1.0),
    };
    let paper = certify(vehicle, &limits, gains, constants, FilterStart::Zero)
        .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?
        .bounds;
    let t = with_budget(boxes, |o| {
        tight_bounds(vehicle, gains, constants, FilterStart::Zero, o)
    })?;
    let rates = (t.angular_velocity, t.angular_acceleration);
    let split = tight_feedforward(vehicle, rates) + paper.feedback_torque_axes;
    Ok(TightTorque {
        torque_box: Vector3::from_fn(|i, _| paper.torque_max[i].min(split[i]).min(t.torque_max[i])),
        rates,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use controller_core::{Bounds, ReferenceTrajectory, Trajectory};

    /// The paper's vehicle, gains and helix, and the core's bounds of them (limits that hold).
    fn paper_setup() -> (
        Vehicle<f64>,
        Gains<f64>,
        TrajectoryConstants<f64>,
        Bounds<f64>,
    ) {
        let v = Vehicle::<f64>::paper();
        let g = Gains::<f64>::paper();
        let k = ReferenceTrajectory::<f64>::paper_helix().constants();
        let limits = Limits {
            thrust_max: 7.0,
            torque_max: Vector3::repeat(0.5),
        };
        let b = certify(&v, &limits, &g, &k, FilterStart::Zero)
            .unwrap()
            .bounds;
        (v, g, k, b)
    }

    /// On the paper's set-up the tight box is below Theorem 2's bound on every axis, a larger
    /// budget never loosens it, and the feedforward part is below Lemma 1's. (That the tight
    /// bounds hold the law's values is the tight-bounds tests' job.)
    #[test]
    fn tight_box_is_below_the_papers_and_shrinks_with_the_budget() {
        let (v, g, k, paper) = paper_setup();
        let small = tight_torque(&v, &g, &k, SEARCH_BOXES).unwrap().torque_box;
        let large = tight_torque(&v, &g, &k, 20 * SEARCH_BOXES)
            .unwrap()
            .torque_box;
        let paper_ff = paper.torque_max - paper.feedback_torque_axes;
        let ff = tight_feedforward(&v, rates(&v, &g, &k, SEARCH_BOXES).unwrap());
        for i in 0..3 {
            assert!(
                small[i] < paper.torque_max[i],
                "axis {i}: {small:?} vs {:?}",
                paper.torque_max
            );
            assert!(large[i] <= small[i], "axis {i}: {large:?} vs {small:?}");
            assert!(ff[i] < paper_ff[i], "axis {i}: {ff:?} vs {paper_ff:?}");
        }
    }

    /// The tightened set lies in both sets it takes its norms from (its support function is
    /// below each along random directions), keeps the feedback's parts, and is the set itself
    /// when the tight norms are the larger.
    #[test]
    fn tightened_set_lies_in_both_sets() {
        use rand::RngExt;
        let (v, g, k, paper) = paper_setup();
        let own = paper.torque_set;
        let (w, a) = rates(&v, &g, &k, SEARCH_BOXES).unwrap();
        let set = tightened_set(&own, (w, a));
        let tight_only = TorqueSet {
            angular_acceleration: a,
            gyroscopic: TorqueSet::new(own.inertia, w, a, 0.0, Vector3::zeros()).gyroscopic,
            ..own
        };
        assert_eq!(set.feedback_radius, own.feedback_radius);
        let mut rng = crate::runs::sampler::seeded_rng(3);
        for _ in 0..1000 {
            let c = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let h = set.support(&c);
            assert!(h <= own.support(&c) * (1.0 + 1e-12), "{c:?}");
            assert!(h <= tight_only.support(&c) * (1.0 + 1e-12), "{c:?}");
        }
        // Tight norms below the set's own shrink it; larger ones leave it as it is.
        let half = tightened_set(&own, (w, 0.5 * own.angular_acceleration));
        assert!(half.support(&Vector3::x()) < own.support(&Vector3::x()));
        assert_eq!(tightened_set(&own, (1e3 * w, 1e3 * a)), own);
    }
}
