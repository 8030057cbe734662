//! `host-sim design` end to end: the written scenario is re-certified independently (the
//! core's `certify` and the firmware mixer's `set_margin` on the file as read back), it flies, and
//! impossible vehicles are refused with the reason.
//!
//! One test binary (`cargo test -p host-sim --test design`), its tests grouped by what they check:
//! the certificate of the written scenario ([`certification`]), the command line's options and
//! refusals ([`cli`]), and the designs flown ([`flight`]); [`support`] holds their shared helpers.

mod certification;
mod cli;
mod flight;
mod idle_airmode;
mod random_starts;
mod support;
mod turned_starts;
