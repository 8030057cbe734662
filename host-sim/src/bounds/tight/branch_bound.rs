//! A generic best-first branch and bound over boxes, for an upper bound of a supremum.
//!
//! The caller supplies, for a box, an upper bound of the objective over it, a variable to split
//! (or none), and the objective's value at some point of the box. The node with the largest
//! upper bound is split at the midpoint of its variable; the two halves cover it. The search
//! stops when `(upper − lower)/upper ≤ gap` for the top of the queue, when the queue is empty,
//! or after the box budget, and returns the largest upper bound among the nodes never split:
//! the queue's, the ones discarded because their upper bound did not exceed the best point
//! value, and the ones that could not be split. Since the nodes never split cover the roots,
//! that is an upper bound of the supremum over the roots whenever each node's upper bound is.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::interval::{next_up, Interval};

/// A box with a tag (the caller's discrete variable) and its evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Node<const N: usize> {
    /// Upper bound of the objective over the box (`+∞` if unknown).
    pub upper: f64,
    /// The box (the caller may have shrunk it to a face, see `search`).
    pub region: [Interval; N],
    /// The caller's discrete variable (e.g. a vertex index).
    pub tag: usize,
    /// Variable to bisect, or `None` when the box cannot or need not be split.
    pub split: Option<usize>,
    /// The objective at a point of the box (not necessarily rigorous; only for stopping).
    pub lower: f64,
}

/// Orders nodes by upper bound.
struct ByUpper<const N: usize>(Node<N>);

impl<const N: usize> PartialEq for ByUpper<N> {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl<const N: usize> Eq for ByUpper<N> {}
impl<const N: usize> PartialOrd for ByUpper<N> {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl<const N: usize> Ord for ByUpper<N> {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.upper.total_cmp(&o.0.upper)
    }
}

/// What a search found, in the objective's units (after `value`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Upper bound of the supremum (rigorous when the node bounds are).
    pub upper: f64,
    /// Best point value seen.
    pub lower: f64,
    /// Nodes evaluated.
    pub boxes: usize,
}

/// Best point value and the largest upper bound among nodes dropped from the queue unsplit.
struct Tally {
    lower: f64,
    settled: f64,
}

impl Tally {
    /// Queues `node`, or drops it (keeping its bound) when it cannot beat the best point value.
    fn admit<const N: usize>(&mut self, node: Node<N>, heap: &mut BinaryHeap<ByUpper<N>>) {
        if !node.lower.is_nan() {
            self.lower = self.lower.max(node.lower);
        }
        if node.upper <= self.lower {
            self.settled = self.settled.max(node.upper);
        } else {
            heap.push(ByUpper(node));
        }
    }
}

/// Runs the search from `roots` (box, tag). `evaluate` bounds a box; `value` maps the
/// objective to the reported quantity (monotone non-decreasing, e.g. `√` for a squared norm;
/// its result is rounded up for the upper bound).
pub fn best_first<const N: usize>(
    roots: &[([Interval; N], usize)],
    evaluate: impl Fn([Interval; N], usize) -> Node<N>,
    value: impl Fn(f64) -> f64,
    relative_gap: f64,
    max_boxes: usize,
) -> Outcome {
    let mut heap = BinaryHeap::new();
    let mut tally = Tally {
        lower: 0.0,
        settled: f64::NEG_INFINITY,
    };
    let mut boxes = 0;
    for (region, tag) in roots {
        tally.admit(evaluate(*region, *tag), &mut heap);
        boxes += 1;
    }
    let top_upper = loop {
        let Some(ByUpper(top)) = heap.pop() else {
            break f64::NEG_INFINITY;
        };
        let upper = next_up(value(top.upper));
        if boxes >= max_boxes || upper - value(tally.lower) <= relative_gap * upper {
            break top.upper;
        }
        let Some(j) = top.split else {
            // Cannot be split: its bound stays part of the answer.
            tally.settled = tally.settled.max(top.upper);
            continue;
        };
        let x = top.region[j];
        let m = x.mid();
        for half in [Interval::new(x.lo, m), Interval::new(m, x.hi)] {
            let mut region = top.region;
            region[j] = half;
            let mut child = evaluate(region, top.tag);
            // The half lies in the parent, so the parent's bound holds for it too.
            child.upper = child.upper.min(top.upper);
            tally.admit(child, &mut heap);
            boxes += 1;
        }
    };
    Outcome {
        upper: next_up(value(top_upper.max(tally.settled))),
        lower: value(tally.lower),
        boxes,
    }
}
