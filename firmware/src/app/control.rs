//! The control loop: every tick it drains the IMU samples and link bytes received since the
//! last one into the [`FlightPipeline`] (the link bytes only when the clock does not read the
//! link itself: the lockstep clock feeds them in stream order instead), runs `control_tick`
//! (estimate → controller → mixer), hands the throttles to the motors, queues the telemetry
//! and the log data, measures its step with the DWT cycle counter and feeds the watchdog.
//!
//! The loop is the same on every board; what paces it ([`ControlClock`]), where the throttles go
//! ([`MotorSink`]) and what resets a hung MCU ([`Watchdog`]) are the board's. Two clocks are
//! board-independent and live here: [`DeadlineClock`] (embassy-time deadlines, flight) and
//! [`LockstepClock`] (the simulation's clock carried by `HIL_SENSOR`, processor in the loop).

use core::sync::atomic::Ordering;

use cortex_m::peripheral::DWT;
use embassy_time::{Duration, Instant, Timer};

use super::queues::{
    count, try_write_all, ParamSave, Summary, EVENTS, IMU_SAMPLES, IO, LINK_RX, LINK_TX,
    PARAM_SAVE, STORAGE_BUSY, SUMMARY, TIMING,
};
#[cfg(feature = "hil")]
use crate::pipeline::lockstep::Lockstep;
use crate::pipeline::{Event, FlightPipeline, MotorOutput};
use crate::timing::{self, StepStats};

/// One control instant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tick {
    /// Tick time \[µs\] on the pipeline's clock.
    pub now_us: u64,
    /// How late the tick started after its deadline \[µs\] (0 when the clock is simulated).
    pub lateness_us: u64,
    /// Whole periods skipped since the previous tick (each counted as an overrun).
    pub missed: u32,
}

/// What paces the control loop.
// The executors here are single-core and never move a future between threads, so the
// `Send`-ness of these futures is irrelevant.
#[allow(async_fn_in_trait)]
pub trait ControlClock {
    /// Waits for the next control instant. A clock that lives in the link (the simulation's)
    /// may feed received bytes to `pipeline` while it waits; a hardware clock ignores it.
    async fn next_tick(&mut self, pipeline: &mut FlightPipeline) -> Tick;

    /// Whether this clock is the only reader of [`LINK_RX`]: then [`run`] does not drain it
    /// between ticks, so that which bytes come before a tick is the clock's decision alone
    /// (the lockstep's: `crate::pipeline::lockstep`, `hil` feature).
    fn reads_link(&self) -> bool {
        false
    }
}

/// Where the tick's throttles go.
#[allow(async_fn_in_trait)]
pub trait MotorSink {
    /// What [`MotorSink::prepare`] builds for [`MotorSink::write`] (e.g. DShot frames).
    type Frames;
    /// Turns the tick's throttles into what the outputs send; cheap and synchronous, so that
    /// it can run inside the timed step.
    fn prepare(&mut self, output: &MotorOutput) -> Self::Frames;
    /// Sends them (may wait for DMA).
    async fn write(&mut self, frames: Self::Frames);
}

/// What resets the MCU when the control loop stops.
pub trait Watchdog {
    /// Starts it (the first feed must follow within its timeout).
    fn start(&mut self);
    /// Feeds it, once per completed step.
    fn feed(&mut self);
}

/// Runs the control loop forever. `period`: the nominal tick period (logged; the clock paces).
/// The pipeline is borrowed so that it lives once, in the calling task's future (several KiB).
pub async fn run(
    pipeline: &mut FlightPipeline,
    clock: &mut impl ControlClock,
    motors: &mut impl MotorSink,
    watchdog: &mut impl Watchdog,
    period: Duration,
) -> ! {
    let period_us = period.as_micros();
    let ticks_per_second = (1_000_000 / period_us.max(1)).max(1) as u32;
    let summary_every = (ticks_per_second / 10).max(1);
    let mut stats = StepStats::new();
    let mut tick: u32 = 0;
    let mut busy_us: u64 = 0;
    let mut link_buf = [0u8; 256];
    let mut telemetry_buf = [0u8; 512];

    watchdog.start();
    defmt::info!("control: every {=u64} us", period_us);
    loop {
        let Tick {
            now_us,
            lateness_us,
            missed,
        } = clock.next_tick(pipeline).await;
        if missed > 0 {
            stats.record_missed(missed);
        }
        let started = Instant::now();
        let c0 = DWT::cycle_count();
        pipeline.set_storage_busy(STORAGE_BUSY.load(Ordering::Acquire));

        while let Ok(sample) = IMU_SAMPLES.try_receive() {
            pipeline.on_imu(&sample);
        }
        if !clock.reads_link() {
            while let Ok(n) = LINK_RX.try_read(&mut link_buf) {
                pipeline.on_link_bytes(&link_buf[..n], now_us);
            }
        }
        let output = pipeline.control_tick(now_us);
        let frames = motors.prepare(&output);
        while let Some(event) = pipeline.take_events() {
            // The flash write is a store task's, outside the step; it needs the whole set.
            let request = match event {
                Event::ParamChanged { .. } => Some(ParamSave::Set(*pipeline.config())),
                Event::ParamsReset => Some(ParamSave::Clear),
                _ => None,
            };
            if let Some(request) = request {
                // Busy before the request: the store task clears it only with no request left.
                STORAGE_BUSY.store(true, Ordering::Release);
                PARAM_SAVE.signal(request);
            }
            if EVENTS.try_send(event).is_err() {
                count(&IO.events_dropped, 1);
            }
        }
        // Only ask for as many bytes as the transmit pipe can take, so that a frame is never
        // cut; what does not fit waits in the pipeline for the next tick.
        let room = LINK_TX.free_capacity().min(telemetry_buf.len());
        let n = pipeline.telemetry(now_us, &mut telemetry_buf[..room]);
        if try_write_all(&LINK_TX, &telemetry_buf[..n]) != n {
            count(&IO.link_tx_dropped, 1);
        }

        let cycles = timing::cycles_between(c0, DWT::cycle_count());
        let step_us = Instant::now()
            .saturating_duration_since(started)
            .as_micros();
        stats.record(
            cycles,
            step_us,
            timing::is_overrun(lateness_us, step_us, period_us),
        );
        watchdog.feed();

        motors.write(frames).await;

        tick = tick.wrapping_add(1);
        if tick.is_multiple_of(summary_every) {
            SUMMARY.signal(Summary {
                now_us,
                status: pipeline.status(),
                output,
            });
        }
        busy_us = busy_us.saturating_add(step_us);
        if stats.window_steps() >= ticks_per_second {
            // SYS_STATUS.load: the steps' share of the window's periods [per mille]. Not in
            // lockstep: there a step's duration depends on the host (UART interrupts arrive in
            // real time), and the telemetry must be a function of the byte stream alone.
            if !clock.reads_link() {
                let window_us = u64::from(stats.window_steps())
                    .saturating_mul(period_us)
                    .max(1);
                pipeline.report_load((busy_us.saturating_mul(1000) / window_us).min(1000) as u16);
            }
            busy_us = 0;
            TIMING.signal(stats.take_window());
        }
    }
}

/// Hardware pacing: a tick every `period` on embassy-time, with explicit deadlines rather than
/// a `Ticker` so that the lateness of each start is known.
pub struct DeadlineClock {
    period: Duration,
    deadline: Instant,
}

impl DeadlineClock {
    /// First tick one `period` from now.
    pub fn new(period: Duration) -> Self {
        Self {
            period,
            deadline: Instant::now() + period,
        }
    }
}

impl ControlClock for DeadlineClock {
    async fn next_tick(&mut self, _pipeline: &mut FlightPipeline) -> Tick {
        // Fell more than a period behind (e.g. a debugger halt): skip the missed ticks instead
        // of running them back to back, and report them.
        let mut missed = 0;
        let now = Instant::now();
        if now > self.deadline + self.period {
            let behind = (now - self.deadline).as_ticks() / self.period.as_ticks().max(1);
            self.deadline += Duration::from_ticks(self.period.as_ticks() * behind);
            missed = behind.min(u64::from(u32::MAX)) as u32;
        }
        Timer::at(self.deadline).await;
        let started = Instant::now();
        let tick = Tick {
            now_us: started.as_micros(),
            lateness_us: started.saturating_duration_since(self.deadline).as_micros(),
            missed,
        };
        self.deadline += self.period;
        tick
    }
}

/// Processor-in-the-loop pacing (`hil` feature): the simulation's clock is the `time_usec` of
/// the `HIL_SENSOR` messages on the link, so this clock is the link's only reader and applies
/// the lockstep rule of [`crate::pipeline::lockstep`]: each message is dated by the last
/// `HIL_SENSOR` before it in the stream, and a tick happens right after the `HIL_SENSOR` that
/// reaches the deadline, with the bytes after it (even from the same read) held for the next
/// tick. Deadlines: the first sample's time, then each tick's time plus the period. The
/// simulator waits for each tick's `HIL_ACTUATOR_CONTROLS` before it sends more, so the firmware
/// and the plant advance in lockstep, independent of how fast the emulator runs and of how the
/// UART cuts the bytes into reads.
#[cfg(feature = "hil")]
pub struct LockstepClock {
    lockstep: Lockstep<128>,
}

#[cfg(feature = "hil")]
impl LockstepClock {
    /// A tick every `period` of simulated time.
    pub fn new(period: Duration) -> Self {
        Self {
            lockstep: Lockstep::new(period.as_micros()),
        }
    }
}

#[cfg(feature = "hil")]
impl ControlClock for LockstepClock {
    async fn next_tick(&mut self, pipeline: &mut FlightPipeline) -> Tick {
        loop {
            if let Some(now_us) = self.lockstep.advance(pipeline) {
                return Tick {
                    now_us,
                    lateness_us: 0,
                    missed: 0,
                };
            }
            let n = LINK_RX.read(self.lockstep.space()).await;
            self.lockstep.filled(n);
        }
    }

    fn reads_link(&self) -> bool {
        true
    }
}
