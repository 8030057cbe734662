//! What the tasks exchange. Every queue is an `embassy-sync` structure over a
//! `CriticalSectionRawMutex`: safe between an interrupt executor, interrupt handlers and thread
//! mode, each access a few instructions long with interrupts masked. No lock is ever held
//! across the control step.

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;
use embassy_sync::pipe::Pipe;
use embassy_sync::signal::Signal;

use crate::config::FlightConfig;
use crate::pipeline::{Event, ImuSample, MotorOutput, PipelineStatus};
use crate::timing::WindowReport;

/// IMU samples (body FLU) from an IMU task to the control task: ~10 per tick at 1 kHz, room
/// for 3 ticks.
pub static IMU_SAMPLES: Channel<CriticalSectionRawMutex, ImuSample, 32> = Channel::new();
/// MAVLink bytes received, for the control task.
pub static LINK_RX: Pipe<CriticalSectionRawMutex, 1024> = Pipe::new();
/// MAVLink bytes (telemetry) to send.
pub static LINK_TX: Pipe<CriticalSectionRawMutex, 1024> = Pipe::new();
/// Pipeline events (state changes, refused commands) for the logger.
pub static EVENTS: Channel<CriticalSectionRawMutex, Event, 16> = Channel::new();
/// What a board's parameter store task should do (the newest request only: each one is about
/// the whole set, so an older one pending is superseded).
pub static PARAM_SAVE: Signal<CriticalSectionRawMutex, ParamSave> = Signal::new();

/// Whether a board's parameter store has a request pending or under way: set by the control
/// task with each [`PARAM_SAVE`] request, cleared by the store task (in a critical section,
/// only when no request is pending) once the flash is done. The control task hands it to the
/// pipeline every tick, which holds arming while it is set (an erase stalls the CPU).
pub static STORAGE_BUSY: AtomicBool = AtomicBool::new(false);

/// A request to a board's parameter store.
// No allocation to box into, and the signal holds one value of the enum's size either way.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy)]
pub enum ParamSave {
    /// Save this configuration (after an accepted `PARAM_SET`).
    Set(FlightConfig),
    /// Forget the stored parameters (`MAV_CMD_PREFLIGHT_STORAGE` reset).
    Clear,
}
/// 1 Hz step-time window, for the logger.
pub static TIMING: Signal<CriticalSectionRawMutex, WindowReport> = Signal::new();
/// 10 Hz flight summary, for the logger.
pub static SUMMARY: Signal<CriticalSectionRawMutex, Summary> = Signal::new();

/// What the logger prints at 10 Hz.
#[derive(Clone, Copy)]
pub struct Summary {
    /// Tick time \[µs\] (the pipeline's clock).
    pub now_us: u64,
    /// The pipeline's state and counters.
    pub status: PipelineStatus,
    /// The tick's motor commands.
    pub output: MotorOutput,
}

/// Counters of the I/O tasks (relaxed atomics: statistics only, logged at 1 Hz).
pub struct IoCounters {
    /// IMU samples read.
    pub imu_reads: AtomicU32,
    /// IMU reads that failed.
    pub imu_errors: AtomicU32,
    /// IMU samples lost to a full queue.
    pub imu_queue_full: AtomicU32,
    /// Link bytes received.
    pub link_rx_bytes: AtomicU32,
    /// Link bytes lost to a full queue.
    pub link_rx_dropped: AtomicU32,
    /// Receive errors (overrun, framing, noise, parity).
    pub link_rx_errors: AtomicU32,
    /// Telemetry writes that did not fit the transmit queue.
    pub link_tx_dropped: AtomicU32,
    /// Events lost to a full queue.
    pub events_dropped: AtomicU32,
}

/// The I/O counters.
pub static IO: IoCounters = IoCounters {
    imu_reads: AtomicU32::new(0),
    imu_errors: AtomicU32::new(0),
    imu_queue_full: AtomicU32::new(0),
    link_rx_bytes: AtomicU32::new(0),
    link_rx_dropped: AtomicU32::new(0),
    link_rx_errors: AtomicU32::new(0),
    link_tx_dropped: AtomicU32::new(0),
    events_dropped: AtomicU32::new(0),
};

/// Adds `n` to a statistics counter.
pub fn count(counter: &AtomicU32, n: u32) {
    counter.fetch_add(n, Ordering::Relaxed);
}

/// Writes as much of `bytes` into `pipe` as it has room for, without waiting; returns how many.
/// `Pipe::try_write` stops at the end of the pipe's ring even when there is room at its start,
/// so one call can take less than the free capacity: this keeps writing until the room is used.
pub fn try_write_all<const N: usize>(
    pipe: &Pipe<CriticalSectionRawMutex, N>,
    bytes: &[u8],
) -> usize {
    let mut written = 0;
    while written < bytes.len() {
        match pipe.try_write(&bytes[written..]) {
            Ok(k) if k > 0 => written += k,
            _ => break,
        }
    }
    written
}

/// Hands received link bytes to the control task without waiting; what does not fit is counted
/// as dropped (the MAVLink decoder resynchronises on the next frame). For receivers that cannot
/// hold data back (a DMA ring); a receiver with flow control should `LINK_RX.write(..).await`.
pub fn link_received(bytes: &[u8]) {
    count(&IO.link_rx_bytes, bytes.len() as u32);
    let written = try_write_all(&LINK_RX, bytes);
    if written < bytes.len() {
        count(&IO.link_rx_dropped, (bytes.len() - written) as u32);
    }
}
