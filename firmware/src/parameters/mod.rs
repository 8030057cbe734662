//! The tunable parameters: the table a ground station sees over MAVLink's parameter protocol
//! ([`table`]: names, units, sources, ranges, accessors on [`crate::config::FlightConfig`]) and
//! the storage interface with its in-memory store ([`store`]). The protocol (every change
//! certified like boot) is the pipeline's (`pipeline/param_protocol.rs`); persisting them on
//! flash is [`crate::storage`]'s, above the pipeline.

pub mod store;
pub mod table;
