//! How the processor-in-the-loop host cuts what it sends to the firmware's serial port into
//! writes. The firmware's lockstep must not depend on it (docs/sil-pil.md, "Lockstep
//! determinism"); `--send-chunking` varies it to check that.

use std::fmt;
use std::str::FromStr;
use std::time::Duration;

/// How the bytes of one step (its link bytes and its `HIL_SENSOR`) go to the serial port.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SendChunking {
    /// One write per step (the default, as before).
    #[default]
    Whole,
    /// One write per byte.
    Bytes,
    /// Writes of 1 to [`RANDOM_MAX_WRITE`] bytes, one in [`RANDOM_PAUSE_ONE_IN`] followed by a
    /// pause of [`RANDOM_PAUSE`] (so that the emulated UART runs dry and the firmware's reads end
    /// there), sizes and pauses drawn from `seed` (the same seed cuts the same stream the same
    /// way; the pauses are wall-clock time, so where the firmware's reads end still varies).
    Random {
        /// Seed of the write sizes.
        seed: u64,
    },
}

/// Largest write of [`SendChunking::Random`] \[bytes\]: about a `HIL_SENSOR` and a pose, so
/// that the cuts fall anywhere in and between frames.
pub const RANDOM_MAX_WRITE: u64 = 96;

/// One write in this many is followed by a pause, in [`SendChunking::Random`].
pub const RANDOM_PAUSE_ONE_IN: u64 = 4;

/// The pause \[wall-clock time\] after some writes of [`SendChunking::Random`]: longer than the
/// firmware's receive task polls an empty UART before it hands on what it has (about 2000
/// register reads), so that the pause ends a read in the firmware.
pub const RANDOM_PAUSE: Duration = Duration::from_millis(5);

impl SendChunking {
    /// The write sizes for what is sent, in order; call [`Chunker::next_write`] until the bytes
    /// are used up.
    pub fn chunker(self) -> Chunker {
        Chunker {
            chunking: self,
            state: match self {
                Self::Random { seed } => seed,
                _ => 0,
            },
        }
    }
}

impl fmt::Display for SendChunking {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Whole => f.write_str("whole"),
            Self::Bytes => f.write_str("bytes"),
            Self::Random { seed } => write!(f, "random:{seed}"),
        }
    }
}

impl FromStr for SendChunking {
    type Err = String;

    /// `whole`, `bytes`, `random` (seed 1) or `random:<seed>`. Errors: anything else.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "whole" => Ok(Self::Whole),
            "bytes" => Ok(Self::Bytes),
            "random" => Ok(Self::Random { seed: 1 }),
            _ => s
                .strip_prefix("random:")
                .and_then(|seed| seed.parse().ok())
                .map(|seed| Self::Random { seed })
                .ok_or_else(|| {
                    format!("send chunking: whole, bytes, random or random:<seed>, not {s:?}")
                }),
        }
    }
}

/// The write sizes of a [`SendChunking`], across the whole run (a random chunker's sizes run
/// on from one step to the next).
#[derive(Clone, Debug)]
pub struct Chunker {
    chunking: SendChunking,
    state: u64,
}

impl Chunker {
    /// The size of the next write \[bytes\] out of `left` (> 0) bytes still to send, in
    /// 1..=`left`, and how long to pause after it (zero: none).
    pub fn next_write(&mut self, left: usize) -> (usize, Duration) {
        let (n, pause) = match self.chunking {
            SendChunking::Whole => (left, Duration::ZERO),
            SendChunking::Bytes => (1, Duration::ZERO),
            SendChunking::Random { .. } => {
                let r = self.splitmix();
                let pause = if (r >> 32).is_multiple_of(RANDOM_PAUSE_ONE_IN) {
                    RANDOM_PAUSE
                } else {
                    Duration::ZERO
                };
                ((r % RANDOM_MAX_WRITE + 1) as usize, pause)
            }
        };
        (n.clamp(1, left.max(1)), pause)
    }

    /// splitmix64 (Steele, Lea, Flood 2014): seeded, stable across releases of any crate.
    fn splitmix(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cuts(c: SendChunking, len: usize) -> Vec<usize> {
        let mut chunker = c.chunker();
        let mut out = Vec::new();
        let mut left = len;
        while left > 0 {
            let (n, _) = chunker.next_write(left);
            out.push(n);
            left -= n;
        }
        out
    }

    #[test]
    fn only_random_writes_pause_and_only_some_of_them() {
        let mut whole = SendChunking::Whole.chunker();
        let mut bytes = SendChunking::Bytes.chunker();
        let mut random = SendChunking::Random { seed: 9 }.chunker();
        let mut pauses = 0;
        for _ in 0..1000 {
            assert_eq!(whole.next_write(50).1, Duration::ZERO);
            assert_eq!(bytes.next_write(50).1, Duration::ZERO);
            let (_, p) = random.next_write(50);
            assert!(p == Duration::ZERO || p == RANDOM_PAUSE);
            pauses += usize::from(p > Duration::ZERO);
        }
        assert!(
            (150..350).contains(&pauses),
            "{pauses} pauses in 1000 writes"
        );
    }

    #[test]
    fn parses_and_prints_the_command_line_values() {
        for (s, c) in [
            ("whole", SendChunking::Whole),
            ("bytes", SendChunking::Bytes),
            ("random", SendChunking::Random { seed: 1 }),
            ("random:42", SendChunking::Random { seed: 42 }),
        ] {
            assert_eq!(s.parse::<SendChunking>(), Ok(c));
        }
        assert_eq!(
            SendChunking::Random { seed: 42 }.to_string().parse(),
            Ok(SendChunking::Random { seed: 42 })
        );
        assert!("random:x".parse::<SendChunking>().is_err());
        assert!("halves".parse::<SendChunking>().is_err());
        assert_eq!(SendChunking::default(), SendChunking::Whole);
    }

    #[test]
    fn writes_cover_the_bytes_in_the_chosen_sizes() {
        assert_eq!(cuts(SendChunking::Whole, 300), [300]);
        assert_eq!(cuts(SendChunking::Bytes, 3), [1, 1, 1]);
        let r = cuts(SendChunking::Random { seed: 5 }, 5000);
        assert_eq!(r.iter().sum::<usize>(), 5000);
        assert!(r
            .iter()
            .all(|&n| (1..=RANDOM_MAX_WRITE as usize).contains(&n)));
        // Really random sizes, reproducible from the seed, different for another seed.
        assert!(r.iter().collect::<std::collections::BTreeSet<_>>().len() > 20);
        assert_eq!(cuts(SendChunking::Random { seed: 5 }, 5000), r);
        assert_ne!(cuts(SendChunking::Random { seed: 6 }, 5000), r);
    }
}
