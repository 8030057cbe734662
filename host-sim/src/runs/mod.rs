//! The toolkit for many runs, shared by campaigns, ablations, the comparison, the rate study and
//! `design`: initial conditions drawn reproducibly ([`sampler`]), per-run metrics ([`metrics`]),
//! the parallel runner ([`runner`]), statistics over runs ([`stats`]) and one run with its time
//! series kept ([`trace`]).

pub mod metrics;
pub mod runner;
pub mod sampler;
pub mod stats;
pub mod trace;
