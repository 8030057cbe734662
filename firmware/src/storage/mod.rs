//! Persisting the tunable parameters ([`crate::parameters`]) on the board's NOR flash: the store
//! that keeps the whole table as one record and restores it into the pipeline at boot only if
//! still certified ([`flash_store`]), and the watchdog rule that keeps a flash erase from
//! starving the control loop ([`erase_watchdog`]). Above the pipeline: it drives
//! [`crate::pipeline::FlightPipeline::restore_params`].

pub mod erase_watchdog;
pub mod flash_store;
