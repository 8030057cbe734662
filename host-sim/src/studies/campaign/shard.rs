//! A campaign's share of run indices: shard `K/N` (0-based `K < N`) runs the contiguous block
//! `⌊K·runs/N⌋ .. ⌊(K+1)·runs/N⌋`, so the N blocks cover `0..runs` exactly once and differ in
//! size by at most one run. `K` is 0-based like Kubernetes' `JOB_COMPLETION_INDEX` and a Slurm
//! array `--array=0-(N-1)`'s `SLURM_ARRAY_TASK_ID`.

use std::fmt;
use std::ops::Range;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// Shard `index` of `count` (`index < count`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Shard {
    /// 0-based shard number `K`.
    pub index: u64,
    /// Number of shards `N` (≥ 1).
    pub count: u64,
}

impl Shard {
    /// Shard `index` of `count`.
    ///
    /// Errors: `count` is 0 or `index ≥ count`.
    pub fn new(index: u64, count: u64) -> Result<Self, String> {
        if count == 0 {
            return Err("the number of shards N must be at least 1".into());
        }
        if index >= count {
            return Err(format!(
                "shard number {index} is not below the number of shards {count} (K is 0-based: \
                 0..={})",
                count - 1
            ));
        }
        Ok(Self { index, count })
    }

    /// The run indices of this shard in a campaign of `runs` runs.
    pub fn runs(&self, runs: u64) -> Range<u64> {
        // u128: K·runs overflows u64 for campaigns beyond 2^32 runs split many ways.
        let edge = |k: u64| (u128::from(k) * u128::from(runs) / u128::from(self.count)) as u64;
        edge(self.index)..edge(self.index + 1)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    /// Parses `K/N`, e.g. `0/3`.
    fn from_str(s: &str) -> Result<Self, String> {
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| format!("expected K/N (e.g. 0/3), got {s:?}"))?;
        let number = |part: &str, what: &str| {
            part.trim()
                .parse::<u64>()
                .map_err(|e| format!("{what} in {s:?} is not a whole number: {e}"))
        };
        Self::new(number(k, "K")?, number(n, "N")?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shards of any split tile `0..runs` in order, without gaps or overlaps, and their
    /// sizes differ by at most one.
    #[test]
    fn shards_tile_the_runs() {
        for runs in [0, 1, 2, 7, 24, 1000, u64::MAX] {
            for count in [1, 2, 3, 7, 64] {
                let blocks: Vec<_> = (0..count)
                    .map(|k| Shard::new(k, count).unwrap().runs(runs))
                    .collect();
                assert_eq!(blocks[0].start, 0);
                assert_eq!(blocks[blocks.len() - 1].end, runs);
                for w in blocks.windows(2) {
                    assert_eq!(w[0].end, w[1].start);
                }
                let sizes: Vec<u64> = blocks.iter().map(|b| b.end - b.start).collect();
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "{runs} runs in {count}: {sizes:?}");
            }
        }
    }

    #[test]
    fn parses_k_of_n_and_refuses_the_rest() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        assert_eq!(" 0 / 1 ".parse(), Ok(Shard { index: 0, count: 1 }));
        for bad in ["3/3", "1/0", "3", "a/3", "-1/3", "1/3/4", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad:?} accepted");
        }
    }
}
