//! Lockstep pacing that depends only on the byte stream (`hil` feature, processor in the
//! loop). The simulation's clock is the `time_usec` of the `HIL_SENSOR` messages on the link, so
//! two runs fed the same bytes must do the same thing however the bytes were cut into reads.
//! The rule:
//!
//! - every message is dated by the clock of the last `HIL_SENSOR` *before it in the stream*
//!   (0 before the first), never by what was known when its read started;
//! - a control tick happens exactly after the `HIL_SENSOR` that reaches the deadline: the
//!   bytes before that frame are handled before the tick, the bytes after it (even from the same
//!   read) are held and handled after it.
//!
//! Deadlines: the first `HIL_SENSOR`'s time, then each tick's time plus the period.
//!
//! [`Lockstep`] is that rule with nothing else: no embassy, no queue, so that the host tests can
//! replay a stream in any chunking. `app::control::LockstepClock` reads the link into it.

use super::FlightPipeline;

/// What one call of [`LockstepLink::feed_message`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fed {
    /// Every byte given was taken and none completed a message.
    Incomplete,
    /// A message other than `HIL_SENSOR` was handled.
    Message,
    /// A `HIL_SENSOR` was handled; `clock_us` \[µs\] is the simulation's clock after it (the
    /// latest `time_usec` seen so far: a sample older than the clock does not move it back).
    HilSensor {
        /// The simulation's clock after this sample \[µs\].
        clock_us: u64,
    },
}

/// Where [`Lockstep`] hands the bytes: the flight pipeline, or a fake in tests.
pub trait LockstepLink {
    /// Takes bytes from the front of `bytes` until one completes a message, and handles that
    /// message dated by the clock of the last `HIL_SENSOR` before it in the stream. Returns
    /// how many bytes were taken and what happened. Never panics, whatever the bytes.
    fn feed_message(&mut self, bytes: &[u8]) -> (usize, Fed);
}

impl LockstepLink for FlightPipeline {
    fn feed_message(&mut self, bytes: &[u8]) -> (usize, Fed) {
        self.on_link_message(bytes)
    }
}

/// The lockstep rule over a read buffer of `N` bytes (see the module documentation).
///
/// Use: [`Lockstep::advance`] until it returns `None`, then read link bytes into
/// [`Lockstep::space`] and report them with [`Lockstep::filled`]; each `Some(t)` from
/// `advance` is a control tick at `t` \[µs\], to run before calling `advance` again.
#[derive(Clone, Debug)]
pub struct Lockstep<const N: usize> {
    period_us: u64,
    deadline_us: Option<u64>,
    buf: [u8; N],
    /// Bytes `buf[start..end]` are read but not yet fed (those after a tick's `HIL_SENSOR`).
    start: usize,
    end: usize,
}

impl<const N: usize> Lockstep<N> {
    /// A tick every `period_us` \[µs\] of simulated time.
    pub const fn new(period_us: u64) -> Self {
        Self {
            period_us,
            deadline_us: None,
            buf: [0; N],
            start: 0,
            end: 0,
        }
    }

    /// Feeds the held bytes to `link`, one message at a time, until a `HIL_SENSOR` brings the
    /// clock to the deadline: returns that tick's time \[µs\] (the simulation's clock), and the
    /// bytes after the frame stay held for the next call. `None`: every held byte was fed
    /// without reaching the deadline; read more.
    pub fn advance(&mut self, link: &mut impl LockstepLink) -> Option<u64> {
        loop {
            // Called even with nothing held: the decoder may still hold complete frames that
            // one byte released together, and they come out one per call.
            let (used, fed) = link.feed_message(&self.buf[self.start..self.end]);
            self.start = (self.start + used).min(self.end);
            match fed {
                Fed::Incomplete => {
                    self.start = 0;
                    self.end = 0;
                    return None;
                }
                Fed::Message => {}
                Fed::HilSensor { clock_us } => {
                    if clock_us >= *self.deadline_us.get_or_insert(clock_us) {
                        self.deadline_us = Some(clock_us.saturating_add(self.period_us));
                        return Some(clock_us);
                    }
                }
            }
        }
    }

    /// Where to read the next link bytes: empty while bytes are held (call
    /// [`Lockstep::advance`] first), otherwise the whole buffer.
    pub fn space(&mut self) -> &mut [u8] {
        if self.start < self.end {
            return &mut [];
        }
        &mut self.buf
    }

    /// Records that the first `n` bytes of [`Lockstep::space`] were filled (clamped to what
    /// it offered).
    pub fn filled(&mut self, n: usize) {
        if self.start >= self.end {
            self.start = 0;
            self.end = n.min(N);
        }
    }

    /// Bytes read but not fed yet (those after the last tick's `HIL_SENSOR`).
    pub fn held(&self) -> usize {
        self.end - self.start
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fake link whose "messages" are single bytes: `b'S'` followed by nothing is a
    /// `HIL_SENSOR` whose clock is the count of sensors so far times 1000 µs; any other byte is
    /// another message. Records the clock each message was dated with.
    #[derive(Default)]
    struct Fake {
        clock: Option<u64>,
        sensors: u64,
        dated: Vec<(u8, u64)>,
    }

    impl LockstepLink for Fake {
        fn feed_message(&mut self, bytes: &[u8]) -> (usize, Fed) {
            let Some(&b) = bytes.first() else {
                return (0, Fed::Incomplete);
            };
            self.dated.push((b, self.clock.unwrap_or(0)));
            if b == b'S' {
                let t = self.sensors * 1000;
                self.sensors += 1;
                self.clock = Some(t);
                (1, Fed::HilSensor { clock_us: t })
            } else {
                (1, Fed::Message)
            }
        }
    }

    /// Each tick's time \[µs\] with how many messages came before it, and each message with
    /// its date \[µs\].
    type Trace = (Vec<(u64, usize)>, Vec<(u8, u64)>);

    /// Drives `stream` through a `Lockstep<8>` in reads of the given sizes (cycled).
    fn drive(stream: &[u8], sizes: &[usize]) -> Trace {
        let mut lock = Lockstep::<8>::new(2000);
        let mut link = Fake::default();
        let mut ticks = Vec::new();
        let mut at = 0;
        let mut k = 0;
        loop {
            while let Some(t) = lock.advance(&mut link) {
                ticks.push((t, link.dated.len()));
            }
            if at == stream.len() {
                break;
            }
            let want = sizes[k % sizes.len()].max(1);
            k += 1;
            let space = lock.space();
            let n = want.min(space.len()).min(stream.len() - at);
            space[..n].copy_from_slice(&stream[at..at + n]);
            lock.filled(n);
            at += n;
        }
        (ticks, link.dated)
    }

    /// Given a stream of sensors and other messages, when it is read in different chunkings,
    /// then the ticks (times and what came before each) and the dating of every message are
    /// the same; ticks come right after the sensor that reaches each deadline (0, 2000, 4000).
    #[test]
    fn ticks_and_dates_do_not_depend_on_the_chunking() {
        let stream = b"aSbSScSdSSeSf";
        let reference = drive(stream, &[1]);
        assert_eq!(
            reference.0,
            [(0, 2), (2000, 5), (4000, 9), (6000, 12)],
            "{reference:?}"
        );
        // `c` follows the third sensor (clock 2000), `b` the first (clock 0).
        assert!(reference.1.contains(&(b'c', 2000)));
        assert!(reference.1.contains(&(b'b', 0)));
        for sizes in [&[8][..], &[3], &[2, 5, 1], &[100], &[7, 1]] {
            assert_eq!(drive(stream, sizes), reference, "reads of {sizes:?}");
        }
    }

    /// Bytes after the tick's sensor stay held, and no read is offered until they are fed.
    #[test]
    fn bytes_after_the_tick_wait_for_the_next_advance() {
        let mut lock = Lockstep::<8>::new(1000);
        let mut link = Fake::default();
        lock.space()[..4].copy_from_slice(b"Sxyz");
        lock.filled(4);
        assert_eq!(lock.advance(&mut link), Some(0));
        assert_eq!(lock.held(), 3);
        assert!(lock.space().is_empty());
        assert_eq!(link.dated.len(), 1);
        assert_eq!(lock.advance(&mut link), None);
        assert_eq!(lock.held(), 0);
        assert_eq!(lock.space().len(), 8);
        assert_eq!(link.dated.len(), 4);
    }
}
