//! The tight bounds of a set-up computed once per process.
//!
//! The branch and bound of [`crate::bounds::tight::tight_bounds`] takes seconds (about 5 s on
//! two cores for the paper's set-up at the main runs' budget), and it is a pure function of
//! the vehicle, the gains, the trajectory constants, the filters' start and the search options.
//! A process that flies the same set-up many times from different initial states (a test that
//! draws random attitudes, `compare`, an ablation) would otherwise spend most of its time
//! recomputing the same bounds. Each set-up's bounds are kept here under a key that spells
//! every input exactly (Rust's `Debug` prints an `f64` so that it reads back to the same bits),
//! so a hit returns what the search would have returned, bit for bit.
//!
//! Nothing is held while the search runs: two threads that miss on the same key both compute
//! (the result is the same), and a search that itself asks for bounds cannot deadlock.

use std::sync::Mutex;

use crate::bounds::tight::TightBounds;

/// How many set-ups the process keeps (the oldest goes first): it flies a handful at a time.
const KEPT: usize = 32;

/// The process's kept bounds.
static TIGHT: Memo = Memo::new(KEPT);

/// The bounds kept under `key`, else `compute()`'s (kept when `Ok`). `key` must determine the
/// result: every input of the search, spelled exactly. Errors: `compute`'s, not kept.
pub fn memoised<E>(
    key: String,
    compute: impl FnOnce() -> Result<TightBounds, E>,
) -> Result<TightBounds, E> {
    TIGHT.get_or_compute(key, compute)
}

/// Bounds kept by key, at most `capacity` of them, oldest first.
struct Memo {
    capacity: usize,
    kept: Mutex<Vec<(String, TightBounds)>>,
}

impl Memo {
    /// An empty memo that keeps at most `capacity` entries.
    const fn new(capacity: usize) -> Self {
        Self {
            capacity,
            kept: Mutex::new(Vec::new()),
        }
    }

    /// [`memoised`] on this memo.
    fn get_or_compute<E>(
        &self,
        key: String,
        compute: impl FnOnce() -> Result<TightBounds, E>,
    ) -> Result<TightBounds, E> {
        if let Some(hit) = self.lookup(&key) {
            return Ok(hit);
        }
        // Computed with the lock released (see the module documentation).
        let bounds = compute()?;
        let mut kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
        if !kept.iter().any(|(k, _)| *k == key) {
            if kept.len() == self.capacity {
                kept.remove(0);
            }
            kept.push((key, bounds));
        }
        Ok(bounds)
    }

    /// The bounds kept under `key`, if any.
    fn lookup(&self, key: &str) -> Option<TightBounds> {
        let kept = self.kept.lock().unwrap_or_else(|p| p.into_inner());
        kept.iter().find(|(k, _)| k == key).map(|(_, b)| *b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounds::certificate::scenario_tight_bounds_with;
    use crate::bounds::tight::{tight_bounds, TightOptions};
    use crate::model::scenario::Scenario;
    use controller_core::{FilterStart, Trajectory as _};

    /// The paper's set-up's bounds straight from the search (no entry), with `max_boxes`.
    fn searched(max_boxes: usize) -> TightBounds {
        let s = Scenario::paper();
        tight_bounds(
            &s.vehicle(),
            &s.gains(),
            &s.trajectory::<f64>().constants(),
            FilterStart::Zero,
            &TightOptions {
                max_boxes,
                ..TightOptions::default()
            },
        )
        .unwrap()
    }

    /// Whether an entry whose key holds `budget` (as `Debug` spells the options) holds `b`.
    fn kept_with(budget: &str, b: &TightBounds) -> bool {
        let kept = TIGHT.kept.lock().unwrap_or_else(|p| p.into_inner());
        kept.iter().any(|(k, v)| k.contains(budget) && v == b)
    }

    /// Given the paper's set-up at a small budget, when its bounds are asked for twice through
    /// the scenario, then both are what the search returns and the first left its entry; a
    /// different budget gets an entry of its own, with its own search's bounds.
    #[test]
    fn a_hit_is_what_the_search_returns() {
        let s = Scenario::paper();
        let options = |max_boxes| TightOptions {
            max_boxes,
            ..TightOptions::default()
        };
        let first = scenario_tight_bounds_with(&s, &options(2_000)).unwrap();
        let again = scenario_tight_bounds_with(&s, &options(2_000)).unwrap();
        assert_eq!(first, searched(2_000));
        assert_eq!(again, first);
        assert!(kept_with("max_boxes: 2000,", &first));
        let other = scenario_tight_bounds_with(&s, &options(4_000)).unwrap();
        assert_eq!(other, searched(4_000));
        assert!(kept_with("max_boxes: 4000,", &other));
    }

    /// Given a memo full of set-ups, when one more is kept, then the oldest is gone and the
    /// newest is served without computing; a failed computation is not kept.
    #[test]
    fn the_oldest_set_up_goes_first() {
        let memo = Memo::new(4);
        let base = searched(500);
        let bounds = |x: f64| TightBounds {
            angular_velocity: x,
            ..base
        };
        for i in 0..=4 {
            let got = memo.get_or_compute::<()>(format!("{i}"), || Ok(bounds(f64::from(i))));
            assert_eq!(got.map(|b| b.angular_velocity), Ok(f64::from(i)));
        }
        assert!(memo.lookup("0").is_none());
        let again = memo.get_or_compute::<()>("4".into(), || panic!("computed again"));
        assert_eq!(again.map(|b| b.angular_velocity), Ok(4.0));
        assert_eq!(
            memo.get_or_compute("5".into(), || Err("refused")),
            Err("refused")
        );
        assert!(memo.lookup("5").is_none());
        assert!(memo.lookup("1").is_some());
    }
}
