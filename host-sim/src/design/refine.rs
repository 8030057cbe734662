//! The local regime refined after the search (docs/envelope-design.md, "What `design`
//! searches"): the global variables held at the search's optimum, a second, small particle
//! swarm over the local regime's six variables (seven with the vertical channel apart: the
//! local regime's own vertical filters, started at the global ones), with envelopes that fit at
//! no filter ratio
//! narrowed instead of dropped. The refined design is kept only where it scores lower, so it
//! is never worse than the search's. `design` refines only designs that fly the compensated
//! heading (docs/heading-compensator.md): with the paper's desired frame the narrow regimes
//! still pay the frame's tilt-induced yaw and the refinement found nothing better on the
//! presets, so the designs without it stay as they were.
//!
//! Why apart from the search: narrowing inside the search changes the swarm's path everywhere
//! a candidate's local regime used to be dropped, which on the presets found better and worse
//! designs alike; after it, the same search finds the same global gains and the refinement
//! only adds what it measurably improves (the x500's search, whose every local regime was
//! dropped, gets one).

use anyhow::Result;

use super::optimise::{minimise, Optimum};
use super::variables::Layout;

pub mod local_agility;
pub mod local_loop;
pub mod turn_over;

/// Evaluations of the refinement: this share of the search's budget (at least one swarm); a
/// quarter since the refinement searches the local vertical filters too (seven variables).
pub const BUDGET_SHARE: f64 = 0.25;

/// A refinement's outcome (the local regime's here, the turn-over term's in [`turn_over`]), as
/// `design.json` reports it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Refinement {
    /// The search's objective (lower is better).
    pub searched: f64,
    /// The refinement's best objective (with narrowed envelopes); kept only when below
    /// `searched`.
    pub refined: f64,
    /// Whether the refined local regime is the design's.
    pub kept: bool,
    /// Points the refinement scored.
    pub evaluations: usize,
}

/// `optimum` with its local regime refined: `cost(x, layout)` scores a point of the unit box
/// laid out as `layout` (lower is better); `layout` is the search's, and the refinement scores
/// its points with `Layout::narrow_local`. Returns the design's point, its layout (the
/// search's, or the narrowing one when the refined point is kept; its `evaluations` count both)
/// and the refinement (`None` without a local regime in `layout`). `budget`: the search's
/// evaluations; `seed`: its seed. Errors: the optimiser's.
pub fn refine_local<F: Fn(&[f64], Layout) -> f64 + Sync>(
    cost: &F,
    optimum: Optimum,
    layout: Layout,
    budget: usize,
    seed: u64,
) -> Result<(Optimum, Layout, Option<Refinement>)> {
    if !layout.local {
        return Ok((optimum, layout, None));
    }
    let narrowing = Layout {
        narrow_local: true,
        local_vertical: layout.vertical,
        ..layout
    };
    // The local regime's coordinates are the last ones of a point (`variables::Layout`); the
    // refinement's own vertical filters start at the global ones (unit 0: a ratio of 1).
    let split = layout.dimension() - layout.local_dimension();
    let (global, searched) = optimum.x.split_at(split);
    let extra = narrowing.local_dimension() - layout.local_dimension();
    let local = [searched, &vec![0.0; extra]].concat();
    let local = local.as_slice();
    let global = global.to_vec();
    let point = |y: &[f64]| [global.as_slice(), y].concat();
    let local_cost = |y: &[f64]| cost(&point(y), narrowing);
    let share = (BUDGET_SHARE * budget as f64).ceil() as usize;
    let best = minimise(&local_cost, local, share.max(1), seed)?;
    Ok(keep_if_lower(optimum, best, point, (layout, narrowing)))
}

/// The refinement's outcome: `best` (a refinement's optimum over the coordinates `point` puts
/// into a whole point laid out as `layouts.1`) kept when it scores lower than the search's
/// `optimum` (laid out as `layouts.0`), else the search's; `evaluations` counts both. Returns
/// the design's point, its layout and the [`Refinement`]. No errors.
fn keep_if_lower(
    optimum: Optimum,
    best: Optimum,
    point: impl Fn(&[f64]) -> Vec<f64>,
    (searched, refined): (Layout, Layout),
) -> (Optimum, Layout, Option<Refinement>) {
    let kept = best.cost < optimum.cost;
    let refinement = Refinement {
        searched: optimum.cost,
        refined: best.cost,
        kept,
        evaluations: best.evaluations,
    };
    let evaluations = optimum.evaluations + best.evaluations;
    if kept {
        let x = point(&best.x);
        (
            Optimum {
                x,
                cost: best.cost,
                evaluations,
            },
            refined,
            Some(refinement),
        )
    } else {
        (
            Optimum {
                evaluations,
                ..optimum
            },
            searched,
            Some(refinement),
        )
    }
}

#[cfg(test)]
mod tests;
