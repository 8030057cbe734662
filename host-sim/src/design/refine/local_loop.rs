//! The local position loop's natural frequency and damping polished last (docs/envelope-design.md,
//! "What `design` searches"): every other variable held at the design found so far (the search's,
//! its local regime and turn-over refinements included), the integral action and its observer
//! held at the frequency they were sized at (`Layout::local_integral`), and a grid of
//! [`FREQUENCY_POINTS`] × [`DAMPING_POINTS`] over the local regime's `ω_p,L` and `ζ_p,L` on their
//! whole ranges, kept only where it scores lower.
//!
//! Why, and why last: `k_p,L = ω_p,L²` and `k_v,L = 2 ζ_p,L ω_p,L` act inside the local
//! saturation `M_p,L`, so no torque, thrust or rate bound depends on them; only the integral
//! action's local stability conditions do, and each point is certified again as it is scored.
//! In the search the integral gain and the observer are sized at `ω_p,L` (`k_i = ω_p,L³/5`), so a
//! stiffer loop brings a faster integral, which winds up in the large manoeuvres and fails
//! convergence runs; the swarm settles on a soft loop (the x500's: 3.1 rad/s). A stiff loop
//! beside the slow integral it already has scores better up to the range's top, 8 rad/s
//! (docs/results.md, "The local position loop polished last"). Two variables on a fixed grid cost
//! 16 evaluations, scored in parallel, and move nothing the bounds depend on; the grid is coarse
//! because every attitude law and heading `design` compares polishes its own design, and a
//! Hummingbird evaluation takes about 1.3 s on 2 cores (32 points took its design to 645 s, past
//! the 10 minutes).

use rayon::prelude::*;

use super::super::evaluate::PENALTY;
use super::super::optimise::Optimum;
use super::super::variables::Layout;
use super::{keep_if_lower, Refinement};

/// Grid points over `ω_p,L`'s range (logarithmic in its coordinate: 0.5, 1.26, 3.17, 8 rad/s).
pub const FREQUENCY_POINTS: usize = 4;

/// Grid points over `ζ_p,L`'s range (0.6 to 1.5).
pub const DAMPING_POINTS: usize = 4;

/// The local position loop's frequency and damping: their indices among the local regime's
/// coordinates (`variables::local`'s table: 2 and 3).
const LOOP_COORDINATES: [usize; 2] = [2, 3];

/// `optimum` (a point laid out as `layout`) with its local position loop's frequency and damping
/// set to the grid point that scores lowest under `cost(x, layout)` (lower is better), with the
/// integral action held at `optimum`'s `ω_p,L`, when that is below `optimum.cost`. Returns the
/// design's point, its layout (`layout`, or with [`Layout::local_integral`] and one more
/// coordinate, the integral's frequency, when the polished loop is kept; `evaluations` counts
/// the grid too) and the refinement (`None` without a local regime in `layout`, when it already
/// holds the integral apart, or when `optimum` misses a constraint: its cost is at least
/// [`PENALTY`]). Ties go to the first grid point (frequency-major order), so the result does not
/// depend on the threads. No errors.
pub fn refine_local_loop<F: Fn(&[f64], Layout) -> f64 + Sync>(
    cost: &F,
    optimum: Optimum,
    layout: Layout,
) -> (Optimum, Layout, Option<Refinement>) {
    if !layout.local || layout.local_integral || optimum.cost >= PENALTY {
        return (optimum, layout, None);
    }
    let apart = Layout {
        local_integral: true,
        ..layout
    };
    // The local regime's coordinates are the last ones of a point (`variables::Layout`); the
    // integral's frequency is the new last one, in `ω_p,L`'s range: started (and held) at it.
    let first = layout.dimension() - layout.local_dimension();
    let [frequency, damping] = LOOP_COORDINATES.map(|i| first + i);
    let start = [optimum.x.as_slice(), &[optimum.x[frequency]]].concat();
    let point = |y: &[f64]| {
        let mut x = start.clone();
        x[frequency] = y[0];
        x[damping] = y[1];
        x
    };
    let at = |i: usize, n: usize| i as f64 / (n - 1) as f64;
    let grid: Vec<[f64; 2]> = (0..FREQUENCY_POINTS)
        .flat_map(|f| {
            (0..DAMPING_POINTS).map(move |d| [at(f, FREQUENCY_POINTS), at(d, DAMPING_POINTS)])
        })
        .collect();
    let scored: Vec<f64> = grid.par_iter().map(|y| cost(&point(y), apart)).collect();
    // The first lowest: NaN never wins (a NaN cost is no design).
    let (index, lowest) =
        scored
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |(bi, bc), (i, c)| {
                    if c < bc {
                        (i, c)
                    } else {
                        (bi, bc)
                    }
                },
            );
    let best = Optimum {
        x: grid[index].to_vec(),
        cost: lowest,
        evaluations: grid.len(),
    };
    keep_if_lower(optimum, best, point, (layout, apart))
}

#[cfg(test)]
mod tests;
