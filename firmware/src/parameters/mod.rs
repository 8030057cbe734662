//! The tunable parameters, in one place: the table a ground station sees over MAVLink's
//! parameter protocol ([`table`]: names, units, sources, ranges, accessors on
//! [`crate::config::FlightConfig`]), the storage interface and its in-memory store ([`store`]),
//! the NOR-flash store that persists them ([`flash_store`]) and the watchdog rule that keeps a
//! flash erase from starving the control loop ([`erase_watchdog`]). The protocol itself (every
//! change certified like boot) is the pipeline's (`pipeline/param_protocol.rs`).

pub mod erase_watchdog;
pub mod flash_store;
pub mod store;
pub mod table;
