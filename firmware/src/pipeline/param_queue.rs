//! The parameter protocol's pending replies: single answers, a list stream's position and the
//! refusal texts, bounded (no allocation).

use heapless::Deque;

use super::param_text::Text;
use crate::params::COUNT;

/// Pending parameter replies: single answers, a list stream's position and texts.
pub(super) struct ParamQueue {
    /// Indices of `PARAM_VALUE`s to send (answers to reads and sets), oldest first.
    pub(super) replies: Deque<u8, 8>,
    /// Next index of a `PARAM_REQUEST_LIST` stream, if one is running.
    pub(super) stream_next: Option<u8>,
    /// When the stream last sent \[µs\].
    pub(super) stream_sent_us: Option<u64>,
    /// STATUSTEXTs of refusals and unknown names.
    pub(super) texts: Deque<Text, 4>,
}

impl ParamQueue {
    /// Nothing pending.
    pub(super) const fn new() -> Self {
        Self {
            replies: Deque::new(),
            stream_next: None,
            stream_sent_us: None,
            texts: Deque::new(),
        }
    }
}

// The reply queue holds indices as u8.

const _: () = assert!(COUNT <= u8::MAX as usize);
