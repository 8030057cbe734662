//! Tilt priority's turn-over term refined after the search (docs/turn-over.md, "In `design`"):
//! a second, small particle swarm over the turn-over share `M_t / ι₁` and the attitude
//! variables that share the rotors' torque with it (`ι / ι_max`, the attitude natural frequency
//! and damping, and tilt priority's three shares), started at the search's optimum with the
//! term off; the position loop, the vertical channel and the local regime stay the search's.
//! The refined design is kept only where it scores lower, so it is never worse than the
//! search's.
//!
//! Why apart from the search: the term's yaw component takes yaw authority the levels need, so
//! the term moves the whole attitude law with it; a thirteenth variable in the search's swarm,
//! on the same budget, found no design that met the constraints on the x500 where the search
//! without it does (docs/results.md, "The turn-over term in `design`"), and trying shares on
//! the search's optimum alone met no constraint at any share (the optimum sits at the
//! doubled-lag edge the term's smaller levels cross).

use anyhow::Result;

use super::super::evaluate::PENALTY;
use super::super::optimise::{minimise, Optimum};
use super::super::variables::{Layout, TURN_OVER};
use super::{keep_if_lower, Refinement, BUDGET_SHARE};

/// The variables refined with the turn-over share (indices of the module table of
/// `crate::design::variables`): `ι / ι_max`, attitude natural frequency and damping, yaw share,
/// radial share of `ι₃`, trace share of `ι₁`.
pub const ATTITUDE_VARIABLES: [usize; 6] = [3, 5, 6, 9, 10, 11];

/// `optimum` (a point laid out as `layout`, tilt priority without the turn-over share) with the
/// turn-over term refined: `cost(x, layout)` scores a point of the unit box (lower is better).
/// Returns the design's point, its layout (`layout`, or with [`Layout::turn_over`] when the
/// refined point is kept; `evaluations` counts both swarms) and the refinement (`None` when
/// `layout` is not tilt priority's or already searches the share, or when `optimum` misses a
/// constraint: its cost is at least [`PENALTY`]). `budget`: the search's
/// evaluations, of which [`BUDGET_SHARE`] are spent here; `seed`: its seed. Errors: the
/// optimiser's.
pub fn refine_turn_over<F: Fn(&[f64], Layout) -> f64 + Sync>(
    cost: &F,
    optimum: Optimum,
    layout: Layout,
    budget: usize,
    seed: u64,
) -> Result<(Optimum, Layout, Option<Refinement>)> {
    let with = Layout {
        turn_over: true,
        ..layout
    };
    // A search whose best design misses a constraint is refined no further: `design` falls back
    // (another heading, the heading held, a slower reference) and refines the design it keeps,
    // so the refinement's budget goes to designs that can be written.
    if with.dimension() == layout.dimension() || optimum.cost >= PENALTY {
        return Ok((optimum, layout, None));
    }
    // The share's coordinate goes right after the law's (`Layout::attitude_dimension`); it
    // starts at 0, the search's own design.
    let (law, rest) = optimum.x.split_at(TURN_OVER);
    let start = [law, &[0.0], rest].concat();
    let refined: Vec<usize> = ATTITUDE_VARIABLES
        .iter()
        .copied()
        .chain([TURN_OVER])
        .collect();
    let point = |y: &[f64]| {
        let mut x = start.clone();
        for (&i, &v) in refined.iter().zip(y) {
            x[i] = v;
        }
        x
    };
    let guess: Vec<f64> = refined.iter().map(|&i| start[i]).collect();
    let refined_cost = |y: &[f64]| cost(&point(y), with);
    let share = (BUDGET_SHARE * budget as f64).ceil() as usize;
    let best = minimise(&refined_cost, &guess, share.max(1), seed)?;
    Ok(keep_if_lower(optimum, best, point, (layout, with)))
}

#[cfg(test)]
mod tests;
