//! The estimator's history: a ring of time-stamped values that visits a time window without
//! scanning the whole ring when it can (the gyro increments and inertial accelerations of the
//! latency correction and the velocity filter, docs/firmware-pipeline.md).

/// Gyro increments kept for the latency correction: 128 samples = 128 ms at 1 kHz.
pub(super) const HISTORY: usize = 128;

/// A ring of the last [`HISTORY`] time-stamped values \[µs\], oldest first, that visits the
/// values of a time window without scanning the whole ring when it can.
///
/// The IMU stamps its samples in increasing order, so the ring is normally sorted by time and
/// the values with `after < t ≤ until` are one contiguous run, found by two binary searches
/// (7 steps each instead of a 128-entry scan). The ring counts its descents (adjacent pairs
/// whose time goes backwards); while there is one, it falls back to scanning every entry. Both
/// paths visit the same values in the same order, so sums over them are bit-identical.
/// Plain arrays with a power-of-two index mask (not `heapless::Deque`, whose bounds and
/// wrap-around checks cost several times the push itself on the MCU).
#[derive(Clone, Debug)]
#[repr(C)]
pub(super) struct TimedRing<T: Copy> {
    /// Time of the newest entry (meaningful when `len > 0`): the push's descent test and the
    /// windows' "ends at the newest" test read it without an indexed load.
    newest: u64,
    /// Physical index of the oldest entry.
    head: usize,
    len: usize,
    /// Adjacent pairs `(i, i + 1)` with `t[i + 1] < t[i]` currently in the ring.
    descents: u32,
    /// Entries ever pushed (wrapping): names an entry by its sequence number, which stays the
    /// same as older entries leave (see [`TimedRing::mark`]).
    pushes: usize,
    // The arrays last (`repr(C)`): the scalars above and the estimator's (see [`Estimator`])
    // stay within short load offsets of one another.
    time: [u64; HISTORY],
    value: [T; HISTORY],
}

/// Index mask of the ring (`HISTORY` is a power of two).
const MASK: usize = HISTORY - 1;
const _: () = assert!(HISTORY.is_power_of_two());

impl<T: Copy> TimedRing<T> {
    pub(super) fn new(fill: T) -> Self {
        Self {
            time: [0; HISTORY],
            value: [fill; HISTORY],
            head: 0,
            len: 0,
            descents: 0,
            pushes: 0,
            newest: 0,
        }
    }

    /// Entries ever pushed (wrapping): the sequence number the next push takes, and the end
    /// of a window that reaches the newest entry.
    #[inline(always)]
    pub(super) fn pushes(&self) -> usize {
        self.pushes
    }

    /// Time of the `i`-th oldest entry (`i < len`).
    #[inline(always)]
    pub(super) fn time_at(&self, i: usize) -> u64 {
        self.time[(self.head + i) & MASK]
    }

    /// Appends `(time_us, value)`, dropping the oldest entry when full; true if it dropped one.
    pub(super) fn push(&mut self, time_us: u64, value: T) -> bool {
        let full = self.len == HISTORY;
        // The newest entry stays when the oldest is dropped (HISTORY ≥ 2).
        if self.len > 0 && time_us < self.newest {
            self.descents += 1;
        }
        let i = (self.head + self.len) & MASK;
        if full {
            // (With no descent in the ring, the dropped pair is none: skip the comparison.)
            if self.descents > 0 && self.time_at(1) < self.time_at(0) {
                self.descents -= 1;
            }
            self.head = (self.head + 1) & MASK;
        } else {
            self.len += 1;
        }
        self.time[i] = time_us;
        self.value[i] = value;
        self.newest = time_us;
        self.pushes = self.pushes.wrapping_add(1);
        full
    }

    /// [`TimedRing::count_until`] as a sequence number (the number of entries ever pushed
    /// before the first entry after `x`), for [`TimedRing::window`]'s hints; `hint` is
    /// returned at once when it is still the answer (two comparisons instead of a search).
    pub(super) fn mark(&self, x: u64, hint: usize) -> usize {
        let first = self.pushes.wrapping_sub(self.len);
        first.wrapping_add(self.count_until_hinted(x, hint))
    }

    /// [`TimedRing::count_until`], trying the sequence number `hint` first: it is the answer
    /// when the entry before it is at or before `x` and the entry at it is after `x` (in a
    /// sorted ring, the definition of the prefix's end).
    pub(super) fn count_until_hinted(&self, x: u64, hint: usize) -> usize {
        let i = hint.wrapping_sub(self.pushes.wrapping_sub(self.len));
        // (At the end, the entry before is the newest: its time without an indexed load.)
        if i == self.len && (i == 0 || self.newest <= x) {
            return i;
        }
        if i < self.len && (i == 0 || self.time_at(i - 1) <= x) && self.time_at(i) > x {
            return i;
        }
        self.count_until(x)
    }

    /// Number of entries at or before `x` (the ring must be sorted: they are a prefix).
    pub(super) fn count_until(&self, x: u64) -> usize {
        // The windows asked for mostly end at the newest entry (`now`, or open-ended).
        if self.len == 0 || self.newest <= x {
            return self.len;
        }
        let (mut lo, mut hi) = (0, self.len - 1);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.time_at(mid) <= x {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// [`TimedRing::window`] with hints that are checked (the tests' name for it).
    #[cfg(test)]
    pub(super) fn for_each_in(
        &self,
        from: usize,
        after: (u64, usize),
        until: (u64, usize),
        f: impl FnMut(&T),
    ) {
        self.window(from, after, until, [false; 2], f);
    }

    /// Calls `f` on every value with `after.0 < t ≤ until.0`, oldest first, among the entries
    /// from the `from`-th oldest on (`from = 0`: all). The second element of `after` and
    /// `until` is a hint, the [`TimedRing::mark`] of that time when it was last asked for (any
    /// value: a wrong hint only costs the search), unless `exact[0]` (`exact[1]`) says that the
    /// hint of `after` (`until`) is that time's mark on the ring as it is now: it is then used
    /// without the two comparisons that check it.
    #[inline(always)]
    pub(super) fn window(
        &self,
        from: usize,
        after: (u64, usize),
        until: (u64, usize),
        exact: [bool; 2],
        mut f: impl FnMut(&T),
    ) {
        let ((after, after_hint), (until, until_hint)) = (after, until);
        let first = self.pushes.wrapping_sub(self.len);
        let count = |x: u64, hint: usize, exact: bool| {
            if exact {
                hint.wrapping_sub(first)
            } else {
                self.count_until_hinted(x, hint)
            }
        };
        // Sorted: exactly the run [lo, hi). Otherwise: every entry, filtered.
        let sorted = self.descents == 0;
        let (lo, hi) = if sorted {
            (
                count(after, after_hint, exact[0]),
                count(until, until_hint, exact[1]),
            )
        } else {
            (0, self.len)
        };
        let lo = lo.max(from);
        if sorted {
            // The run is at most two contiguous pieces of the arrays (before and after the
            // wrap): iterated as slices, with no index mask or test per entry.
            if lo < hi {
                let start = (self.head + lo) & MASK;
                let n = hi - lo;
                let first = n.min(HISTORY - start);
                self.value[start..start + first].iter().for_each(&mut f);
                self.value[..n - first].iter().for_each(&mut f);
            }
            return;
        }
        let mut i = lo;
        while i < hi {
            let j = (self.head + i) & MASK;
            if self.time[j] > after && self.time[j] <= until {
                f(&self.value[j]);
            }
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ring's window visits exactly the entries a full scan would, in the same order, for
    /// sorted and unsorted (descending steps) time stamps, before and after wrapping; the
    /// descent count returns to zero once the out-of-order entries have left the ring.
    #[test]
    fn timed_ring_window_equals_full_scan() {
        let mut x = 0x9e37_79b9u32;
        let mut rnd = |n: u32| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x % n
        };
        let mut ring = TimedRing::new(0u32);
        let mut all: Vec<(u64, u32)> = Vec::new();
        let mut t = 1_000u64;
        for i in 0..2_000u32 {
            // Mostly increasing by 1 ms, sometimes repeated, a few steps backwards early on.
            t = match rnd(50) {
                0 if i < 300 => t.saturating_sub(u64::from(rnd(5_000))),
                1 => t,
                _ => t + 1_000,
            };
            ring.push(t, i);
            all.push((t, i));
            let kept = &all[all.len().saturating_sub(HISTORY)..];
            let descents = kept.windows(2).filter(|w| w[1].0 < w[0].0).count() as u32;
            assert_eq!(ring.descents, descents, "at {i}");
            for _ in 0..3 {
                let after = t.saturating_sub(u64::from(rnd(140_000)));
                let until = after + u64::from(rnd(150_000));
                let mut got = Vec::new();
                let from = rnd(8) as usize;
                // Hints: right, wrong or stale ones (the answer must not depend on them).
                let mut hint = |x: u64| match rnd(3) {
                    0 => ring.mark(x, 0),
                    1 => rnd(400) as usize,
                    _ => ring.pushes.wrapping_sub(rnd(20) as usize),
                };
                let (ha, hu) = (hint(after), hint(until));
                ring.for_each_in(from, (after, ha), (until, hu), |v| got.push(*v));
                let want: Vec<u32> = kept
                    .iter()
                    .skip(from)
                    .filter(|(tt, _)| *tt > after && *tt <= until)
                    .map(|(_, v)| *v)
                    .collect();
                assert_eq!(got, want, "at {i}: ({after}, {until}]");
                // With exact marks, taken unchecked: the same entries.
                let (ma, mu) = (ring.mark(after, 0), ring.mark(until, 0));
                let mut exact = Vec::new();
                ring.window(from, (after, ma), (until, mu), [true; 2], |v| {
                    exact.push(*v)
                });
                assert_eq!(exact, want, "exact marks, at {i}: ({after}, {until}]");
            }
        }
        assert_eq!(ring.descents, 0);
    }
}
