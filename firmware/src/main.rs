//! Flight firmware for an STM32F405RG quadrotor (thumbv7em-none-eabihf).
//!
//! On the MCU: set the clocks (168 MHz from the 8 MHz crystal), log a boot banner with the
//! set-up, its a-priori bound certificate and the mixer fit, then fly:
//!
//! - **control** (an `InterruptExecutor` on a spare interrupt vector, NVIC priority 1, above
//!   every thread-mode task): every `control_period` (100 Hz) it drains the IMU samples and the
//!   link bytes received since the last tick into the `FlightPipeline`, runs `control_tick`
//!   (estimate → controller → mixer), writes the motors (DShot600 or PWM), queues the telemetry,
//!   feeds the independent watchdog, and measures its step with the DWT cycle counter;
//! - **imu** (thread mode): ICM-42688-P data-ready (EXTI) → SPI (DMA) read → body frame → queue;
//! - **link_rx** / **link_tx** (thread mode): MAVLink bytes between USART1 (DMA, circular on
//!   receive) and the control task;
//! - **logger** (thread mode): state changes and refused commands, 1 Hz timing, 10 Hz flight
//!   summary, link counters, all as defmt over RTT.
//!
//! The control task owns the pipeline outright: the other tasks only exchange plain values
//! with it through fixed-size `embassy-sync` queues guarded by short critical sections, so no
//! lock is ever held across the control step and no I/O task can delay it.
//!
//! The board-independent parts are in the `firmware` library (`src/lib.rs`), unit-tested on the
//! host; every pin is in `src/board.rs`. On the host this binary is a stub that says what it is,
//! so that `cargo test --workspace` and host clippy can build every workspace member.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "firmware: this binary is built for thumbv7em-none-eabihf (STM32F405RG): \
         cargo build -p firmware --target thumbv7em-none-eabihf --release"
    );
}

#[cfg(target_os = "none")]
mod motors;

#[cfg(target_os = "none")]
mod mcu {
    use core::sync::atomic::{AtomicU32, Ordering};

    use controller_core::{Certificate, ParameterError, ReferenceTrajectory, Trajectory};
    use cortex_m::peripheral::DWT;
    use defmt::{error, info, unwrap, warn};
    use embassy_embedded_hal::shared_bus::asynch::spi::SpiDevice;
    use embassy_executor::{InterruptExecutor, Spawner};
    use embassy_futures::select::{select3, Either3};
    use embassy_stm32::exti::ExtiInput;
    use embassy_stm32::gpio::{Level, Output, Pull, Speed};
    use embassy_stm32::interrupt;
    use embassy_stm32::interrupt::{InterruptExt, Priority};
    use embassy_stm32::mode::Async;
    use embassy_stm32::peripherals::IWDG;
    use embassy_stm32::rcc::{
        self, AHBPrescaler, APBPrescaler, Hse, HseMode, Pll, PllPDiv, PllPreDiv, PllQDiv,
        PllSource, Sysclk,
    };
    use embassy_stm32::spi::{self, Spi};
    use embassy_stm32::time::{Hertz, MaybeHertz};
    use embassy_stm32::usart::{self, RingBufferedUartRx, Uart, UartTx};
    use embassy_stm32::wdg::IndependentWatchdog;
    use embassy_stm32::Peri;
    use embassy_sync::blocking_mutex::raw::{CriticalSectionRawMutex, NoopRawMutex};
    use embassy_sync::channel::Channel;
    use embassy_sync::mutex::Mutex;
    use embassy_sync::pipe::Pipe;
    use embassy_sync::signal::Signal;
    use embassy_time::{Delay, Duration, Instant, Timer};
    use firmware::board::{self, hw};
    use firmware::clocks::{self, Reported, PLAN};
    use firmware::config::FlightConfig;
    use firmware::drivers::icm42688::{self, Icm42688};
    use firmware::mixer::MixerError;
    use firmware::pipeline::{
        BootError, BootReport, Event, FlightPipeline, ImuSample, MotorOutput, PipelineStatus,
    };
    use firmware::report::{self, Setup, Severity, Value};
    use firmware::timing::{self, StepStats, WindowReport};
    use {defmt_rtt as _, panic_probe as _};

    use crate::motors::Motors;

    // ---------------------------------------------------------------------------------------
    // Clocks.

    // The PLL settings of `clocks::PLAN` as the HAL's register values. PLLM, PLLN and PLLQ are
    // encoded as the divider itself and PLLP as `P/2 - 1` (RM0090, RCC_PLLCFGR), so a plan
    // change that is not mirrored here fails to compile. The bus prescalers are checked at
    // run time against what the HAL reports (`log_clocks`).
    const PLL_M: PllPreDiv = PllPreDiv::DIV4;
    const PLL_N: rcc::PllMul = rcc::PllMul::MUL168;
    const PLL_P: PllPDiv = PllPDiv::DIV2;
    const PLL_Q: PllQDiv = PllQDiv::DIV7;
    const _: () = {
        assert!(PLL_M.to_bits() as u32 == PLAN.pll_m);
        assert!(PLL_N.to_bits() as u32 == PLAN.pll_n);
        assert!((PLL_P.to_bits() as u32 + 1) * 2 == PLAN.pll_p);
        assert!(PLL_Q.to_bits() as u32 == PLAN.pll_q);
    };

    /// Core clock \[Hz\]: the DWT cycle counter's rate.
    const CORE_HZ: u32 = PLAN.frequencies().hclk;

    /// SYSCLK 168 MHz from HSE 8 MHz through the main PLL; AHB /1, APB1 /4, APB2 /2.
    fn hal_config() -> embassy_stm32::Config {
        let mut config = embassy_stm32::Config::default();
        let rcc = &mut config.rcc;
        rcc.hse = Some(Hse {
            freq: Hertz(PLAN.hse_hz),
            mode: HseMode::Oscillator,
        });
        rcc.pll_src = PllSource::HSE;
        rcc.pll = Some(Pll {
            prediv: PLL_M,
            mul: PLL_N,
            divp: Some(PLL_P),
            divq: Some(PLL_Q),
            divr: None,
        });
        rcc.sys = Sysclk::PLL1_P;
        rcc.ahb_pre = AHBPrescaler::DIV1;
        rcc.apb1_pre = APBPrescaler::DIV4;
        rcc.apb2_pre = APBPrescaler::DIV2;
        config
    }

    fn hz(f: MaybeHertz) -> Option<u32> {
        f.to_hertz().map(|h| h.0)
    }

    fn log_clocks(c: &rcc::Clocks) {
        let reported = Reported {
            sysclk: hz(c.sys),
            hclk: hz(c.hclk1),
            pclk1: hz(c.pclk1),
            pclk2: hz(c.pclk2),
            tim_apb1: hz(c.pclk1_tim),
            tim_apb2: hz(c.pclk2_tim),
            pll48: hz(c.pll1_q),
        };
        for line in clocks::compare(&PLAN.frequencies(), &reported) {
            if line.matches {
                info!("clock {=str}: {=u32} Hz", line.name, line.reported);
            } else {
                warn!(
                    "clock {=str}: {=u32} Hz, planned {=u32} Hz",
                    line.name, line.reported, line.planned
                );
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // Boot report.

    fn log_values(section: &'static str, values: &[Value]) {
        for v in values {
            info!(
                "{=str}: {=str} = {=f32} {=str}",
                section, v.name, v.value, v.unit
            );
        }
    }

    fn log_setup(s: &Setup) {
        log_values("vehicle", &report::vehicle_values(&s.vehicle));
        log_values("limits", &report::limits_values(&s.limits));
        log_values("gains", &report::gains_values(&s.gains));
        log_values("reference", &report::constants_values(&s.constants));
    }

    fn log_refusal(what: &'static str, e: &ParameterError) {
        let r = report::refusal(e);
        error!(
            "{=str} refused: {=str} = {=f64} ({=str}; admissible ({=f64}, {=f64}))",
            what, r.name, r.value, r.requirement, r.low, r.high
        );
    }

    fn log_certificate(certificate: &Result<Certificate<f32>, ParameterError>) {
        let c = match certificate {
            Ok(c) => c,
            Err(e) => return log_refusal("certificate", e),
        };
        log_values("bounds", &report::bound_values(c));
        for cond in &c.conditions {
            match report::condition_severity(cond) {
                Severity::Info => info!(
                    "condition {=str}: holds = {=bool}, lhs = {=f32}, rhs = {=f32}",
                    cond.name, cond.holds, cond.lhs, cond.rhs
                ),
                Severity::Warn => warn!(
                    "condition {=str}: holds = {=bool}, lhs = {=f32}, rhs = {=f32} ({=str}); \
                     the bounds are not guaranteed",
                    cond.name, cond.holds, cond.lhs, cond.rhs, cond.statement
                ),
            }
        }
        let violated = c.violations().count();
        if violated == 0 {
            info!(
                "certificate: all {=usize} conditions hold",
                c.conditions.len()
            );
        } else {
            warn!(
                "certificate: {=usize} of {=usize} conditions violated",
                violated,
                c.conditions.len()
            );
        }
    }

    // ---------------------------------------------------------------------------------------
    // What the tasks exchange. Every queue is an `embassy-sync` structure over a
    // `CriticalSectionRawMutex`: safe between the control interrupt executor and thread mode,
    // each access a few instructions long with interrupts masked.

    /// IMU samples (body frame) from the IMU task to the control task: ~10 per tick at 1 kHz,
    /// room for 3 ticks.
    static IMU_SAMPLES: Channel<CriticalSectionRawMutex, ImuSample, 32> = Channel::new();
    /// MAVLink bytes received, for the control task.
    static LINK_RX: Pipe<CriticalSectionRawMutex, 1024> = Pipe::new();
    /// MAVLink bytes (telemetry) to send.
    static LINK_TX: Pipe<CriticalSectionRawMutex, 1024> = Pipe::new();
    /// Pipeline events (state changes, refused commands) for the logger.
    static EVENTS: Channel<CriticalSectionRawMutex, Event, 16> = Channel::new();
    /// 1 Hz step-time window.
    static TIMING: Signal<CriticalSectionRawMutex, WindowReport> = Signal::new();
    /// 10 Hz flight summary.
    static SUMMARY: Signal<CriticalSectionRawMutex, Summary> = Signal::new();

    /// Counters of the I/O tasks (relaxed atomics: statistics only).
    static IMU_READS: AtomicU32 = AtomicU32::new(0);
    static IMU_ERRORS: AtomicU32 = AtomicU32::new(0);
    static IMU_QUEUE_FULL: AtomicU32 = AtomicU32::new(0);
    static LINK_RX_BYTES: AtomicU32 = AtomicU32::new(0);
    static LINK_RX_DROPPED: AtomicU32 = AtomicU32::new(0);
    static LINK_RX_ERRORS: AtomicU32 = AtomicU32::new(0);
    static LINK_TX_DROPPED: AtomicU32 = AtomicU32::new(0);
    static EVENTS_DROPPED: AtomicU32 = AtomicU32::new(0);

    /// What the logger prints at 10 Hz.
    #[derive(Clone, Copy)]
    struct Summary {
        now_us: u64,
        status: PipelineStatus,
        output: MotorOutput,
    }

    // ---------------------------------------------------------------------------------------
    // Control: highest priority.

    static CONTROL_EXECUTOR: InterruptExecutor = InterruptExecutor::new();

    /// The control executor runs in this (otherwise unused) interrupt; see `board::hw`.
    #[interrupt]
    unsafe fn UART5() {
        // SAFETY: the executor is started on this very interrupt in `main` and nothing else
        // pends or handles it.
        unsafe { CONTROL_EXECUTOR.on_interrupt() }
    }

    /// Watchdog timeout: five control periods at 100 Hz. A control step that stops (a hang, a
    /// fault loop, a starved executor) resets the MCU, and the ESCs see no frames (DShot) or
    /// 1000 µs (PWM after reset) — both stop the motors.
    const WATCHDOG_TIMEOUT_US: u32 = 50_000;

    #[embassy_executor::task]
    async fn control(
        mut pipeline: FlightPipeline,
        mut motors: Motors,
        mut watchdog: IndependentWatchdog<'static, IWDG>,
        period: Duration,
    ) {
        let period_us = period.as_micros();
        let ticks_per_second = (1_000_000 / period_us.max(1)).max(1) as u32;
        let summary_every = (ticks_per_second / 10).max(1);
        let mut stats = StepStats::new();
        let mut tick: u32 = 0;
        let mut link_buf = [0u8; 256];
        let mut telemetry_buf = [0u8; 512];

        watchdog.unleash();
        info!(
            "control: every {=u64} us at NVIC priority 1, watchdog {=u32} us",
            period_us, WATCHDOG_TIMEOUT_US
        );

        // Explicit deadlines rather than a `Ticker`, so the lateness of each start is known.
        let mut deadline = Instant::now() + period;
        loop {
            Timer::at(deadline).await;
            let started = Instant::now();
            let c0 = DWT::cycle_count();
            let now_us = started.as_micros();

            while let Ok(sample) = IMU_SAMPLES.try_receive() {
                pipeline.on_imu(&sample);
            }
            while let Ok(n) = LINK_RX.try_read(&mut link_buf) {
                pipeline.on_link_bytes(&link_buf[..n], now_us);
            }
            let output = pipeline.control_tick(now_us);
            let frames = motors.prepare(&output);
            while let Some(event) = pipeline.take_events() {
                if EVENTS.try_send(event).is_err() {
                    EVENTS_DROPPED.fetch_add(1, Ordering::Relaxed);
                }
            }
            // Only ask for as many bytes as the transmit pipe can take, so that a frame is
            // never cut; what does not fit waits in the pipeline for the next tick.
            let room = LINK_TX.free_capacity().min(telemetry_buf.len());
            let n = pipeline.telemetry(now_us, &mut telemetry_buf[..room]);
            if n > 0 && LINK_TX.try_write(&telemetry_buf[..n]) != Ok(n) {
                LINK_TX_DROPPED.fetch_add(1, Ordering::Relaxed);
            }

            let cycles = timing::cycles_between(c0, DWT::cycle_count());
            let lateness_us = started.saturating_duration_since(deadline).as_micros();
            let step_us = Instant::now()
                .saturating_duration_since(started)
                .as_micros();
            stats.record(cycles, timing::is_overrun(lateness_us, step_us, period_us));
            watchdog.pet();

            // The DMA plays the frames out (~30 us for DShot600) while this task waits.
            motors.write(frames).await;

            tick = tick.wrapping_add(1);
            if tick % summary_every == 0 {
                SUMMARY.signal(Summary {
                    now_us,
                    status: pipeline.status(),
                    output,
                });
            }
            if stats.window_steps() >= ticks_per_second {
                TIMING.signal(stats.take_window());
            }

            deadline += period;
            // Fell more than a period behind (e.g. a debugger halt): skip the missed ticks
            // instead of running them back to back, and count each as an overrun.
            let now = Instant::now();
            if now > deadline + period {
                let behind = (now - deadline).as_ticks() / period.as_ticks().max(1);
                deadline += Duration::from_ticks(period.as_ticks() * behind);
                stats.record_missed(behind.min(u32::MAX as u64) as u32);
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // IMU: thread mode, paced by the data-ready interrupt (1 kHz).

    type ImuSpi = Spi<'static, Async, spi::mode::Master>;

    #[embassy_executor::task]
    async fn imu(spi: ImuSpi, cs: Output<'static>, mut drdy: ExtiInput<'static, Async>) {
        let bus: Mutex<NoopRawMutex, ImuSpi> = Mutex::new(spi);
        let device = SpiDevice::new(&bus, cs);
        let config = icm42688::Config::default();
        let mut sensor = Icm42688::new(device, config);
        let mut attempt = 0u32;
        loop {
            attempt += 1;
            match sensor.init(&mut Delay).await {
                Ok(()) => break,
                Err(e) => {
                    error!(
                        "imu: ICM-42688-P init failed (attempt {=u32}): {}",
                        attempt,
                        ImuError(&e)
                    );
                    Timer::after_millis(500).await;
                }
            }
        }
        info!(
            "imu: ICM-42688-P ready: {=u32} Hz, +-{=f32} deg/s, {=f32} LSB/g; hold still for \
             the gyro calibration",
            config.odr.hz(),
            config.gyro_range.full_scale_dps(),
            config.accel_range.lsb_per_g()
        );
        loop {
            // Latched data ready: a sample that became ready before we got here leaves the
            // line high, so waiting for the level (not the edge) never misses one.
            drdy.wait_for_high().await;
            let time_us = Instant::now().as_micros();
            match sensor.read().await {
                Ok(s) => {
                    IMU_READS.fetch_add(1, Ordering::Relaxed);
                    let sample = ImuSample {
                        gyro_rad_s: board::to_body(s.gyro_rad_s),
                        accel_m_s2: board::to_body(s.accel_m_s2),
                        time_us,
                    };
                    if IMU_SAMPLES.try_send(sample).is_err() {
                        IMU_QUEUE_FULL.fetch_add(1, Ordering::Relaxed);
                    }
                }
                Err(_) => {
                    IMU_ERRORS.fetch_add(1, Ordering::Relaxed);
                    // A read that failed may not have cleared the latch; don't spin on it.
                    Timer::after_micros(200).await;
                }
            }
        }
    }

    struct ImuError<'a, E>(&'a icm42688::Error<E>);

    impl<E> defmt::Format for ImuError<'_, E> {
        fn format(&self, f: defmt::Formatter) {
            match self.0 {
                icm42688::Error::Spi(_) => defmt::write!(f, "SPI error"),
                icm42688::Error::WrongDevice(id) => {
                    defmt::write!(f, "WHO_AM_I = {=u8:#x}, expected 0x47", id)
                }
                icm42688::Error::NoData => defmt::write!(f, "no data"),
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // MAVLink link: thread mode.

    #[embassy_executor::task]
    async fn link_rx(mut rx: RingBufferedUartRx<'static>) {
        let mut buf = [0u8; 128];
        loop {
            match rx.read(&mut buf).await {
                Ok(n) => {
                    LINK_RX_BYTES.fetch_add(n as u32, Ordering::Relaxed);
                    let written = LINK_RX.try_write(&buf[..n]).unwrap_or(0);
                    if written < n {
                        LINK_RX_DROPPED.fetch_add((n - written) as u32, Ordering::Relaxed);
                    }
                }
                Err(e) => {
                    // Overrun, framing, noise or parity: the ring restarts on the next read;
                    // the MAVLink parser resynchronises on the next frame start.
                    LINK_RX_ERRORS.fetch_add(1, Ordering::Relaxed);
                    warn!("link: UART receive error {}", e);
                }
            }
        }
    }

    #[embassy_executor::task]
    async fn link_tx(mut tx: UartTx<'static, Async>) {
        let mut buf = [0u8; 256];
        loop {
            let n = LINK_TX.read(&mut buf).await;
            if let Err(e) = tx.write(&buf[..n]).await {
                warn!("link: UART transmit error {}", e);
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // Logs: thread mode, lowest priority.

    #[embassy_executor::task]
    async fn logger() {
        let mut last: Option<Summary> = None;
        loop {
            match select3(EVENTS.receive(), TIMING.wait(), SUMMARY.wait()).await {
                Either3::First(event) => log_event(&event),
                Either3::Second(w) => {
                    log_timing(&w);
                    if let Some(s) = &last {
                        log_counters(&s.status);
                    }
                }
                Either3::Third(s) => {
                    log_summary(&s);
                    last = Some(s);
                }
            }
        }
    }

    fn log_timing(w: &WindowReport) {
        let us = |c| timing::cycles_to_us(c, CORE_HZ);
        info!(
            "timing: {=u32} steps, mean {=u32} cyc ({=f32} us), max {=u32} cyc ({=f32} us), \
             overruns {=u32} (total {=u32})",
            w.steps,
            w.mean_cycles,
            us(w.mean_cycles),
            w.max_cycles,
            us(w.max_cycles),
            w.overruns,
            w.total_overruns
        );
        info!(
            "io: imu reads {=u32} errors {=u32} queue-full {=u32}; link rx {=u32} B dropped \
             {=u32} B errors {=u32}; tx dropped {=u32}; events dropped {=u32}",
            IMU_READS.load(Ordering::Relaxed),
            IMU_ERRORS.load(Ordering::Relaxed),
            IMU_QUEUE_FULL.load(Ordering::Relaxed),
            LINK_RX_BYTES.load(Ordering::Relaxed),
            LINK_RX_DROPPED.load(Ordering::Relaxed),
            LINK_RX_ERRORS.load(Ordering::Relaxed),
            LINK_TX_DROPPED.load(Ordering::Relaxed),
            EVENTS_DROPPED.load(Ordering::Relaxed)
        );
    }

    fn log_event(event: &Event) {
        match *event {
            Event::Calibrated { bias } => info!(
                "event: gyro calibrated, bias [{=f32}, {=f32}, {=f32}] rad/s",
                bias[0], bias[1], bias[2]
            ),
            Event::StateChanged { from, to, reason } => info!(
                "event: state {=str} -> {=str} ({=str})",
                from.name(),
                to.name(),
                reason
            ),
            Event::ModeChanged { mode } => info!("event: mode {=str}", mode.name()),
            Event::CommandAccepted { command } => info!("event: command {=str} accepted", command),
            Event::CommandRefused { command, reason } => {
                warn!("event: command {=str} refused: {=str}", command, reason)
            }
            Event::ReferenceRefused {
                condition,
                lhs,
                rhs,
            } => warn!(
                "event: reference refused: {=str} (lhs = {=f32}, rhs = {=f32})",
                condition, lhs, rhs
            ),
            Event::ReferenceWarning {
                condition,
                lhs,
                rhs,
            } => warn!(
                "event: reference accepted, bounds not guaranteed: {=str} (lhs = {=f32}, \
                 rhs = {=f32})",
                condition, lhs, rhs
            ),
            Event::NonFinite { source } => warn!("event: non-finite value in {=str}", source),
        }
    }

    fn log_summary(s: &Summary) {
        let st = &s.status;
        let pose_age_ms = if st.pose_age_us == u64::MAX {
            -1.0
        } else {
            st.pose_age_us as f32 * 1e-3
        };
        info!(
            "flight t={=u64} ms {=str}/{=str} cal={=bool} conv={=bool} pose_age={=f32} ms \
             p=[{=f32}, {=f32}, {=f32}] p_d=[{=f32}, {=f32}, {=f32}] |e|={=f32} m \
             T={=f32} N tau=[{=f32}, {=f32}, {=f32}] throttle=[{=f32}, {=f32}, {=f32}, {=f32}] \
             armed={=bool}",
            s.now_us / 1000,
            st.state.name(),
            st.mode.name(),
            st.calibrating,
            st.converged,
            pose_age_ms,
            st.position[0],
            st.position[1],
            st.position[2],
            st.reference_position[0],
            st.reference_position[1],
            st.reference_position[2],
            st.position_error,
            st.thrust,
            st.torque[0],
            st.torque[1],
            st.torque[2],
            s.output.throttle[0],
            s.output.throttle[1],
            s.output.throttle[2],
            s.output.throttle[3],
            s.output.armed
        );
    }

    fn log_counters(st: &PipelineStatus) {
        let c = &st.counters;
        info!(
            "link: frames ok {=u32} dropped {=u32} malformed {=u32}, bytes discarded {=u32}; \
             telemetry dropped {=u32}",
            c.link.frames_ok,
            c.link.frames_dropped,
            c.link.frames_malformed,
            c.link.bytes_discarded,
            c.telemetry_dropped
        );
        info!(
            "pipeline: ticks {=u32} imu {=u32} poses {=u32} non-finite {=u32} refused {=u32} \
             mixer-saturated {=u32} events dropped {=u32}",
            c.control_ticks,
            c.imu_samples,
            c.poses_used,
            c.non_finite,
            c.refused_commands,
            c.mixer_saturations,
            c.events_dropped
        );
    }

    fn log_boot_report(r: &BootReport) {
        log_certificate(&Ok(r.certificate));
        let f = &r.a_priori_fit;
        info!(
            "mixer fit: thrust needed [{=f32}, {=f32}] N, rotors give [{=f32}, {=f32}] N \
             (shortfall {=f32}, {=f32} N); 4 f_max = {=f32} N",
            f.thrust_needed[0],
            f.thrust_needed[1],
            f.thrust_capacity[0],
            f.thrust_capacity[1],
            f.thrust_shortfall[0],
            f.thrust_shortfall[1],
            r.thrust_capacity
        );
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            info!(
                "mixer fit: torque {=str}: needed {=f32} N m, rotors give {=f32} N m at the \
                 box corners ({=f32} N m alone), shortfall {=f32} N m",
                axis,
                f.torque_needed[i],
                f.torque_capacity[i],
                f.torque_single_axis[i],
                f.torque_shortfall[i]
            );
        }
        if f.fits {
            info!("mixer fit: the a-priori (T, tau) box fits the rotors");
        } else {
            warn!("mixer fit: the a-priori (T, tau) box does NOT fit the rotors (see shortfalls)");
        }
    }

    fn log_boot_error(e: &BootError) {
        match e {
            BootError::Parameter(p) => log_refusal("pipeline", p),
            BootError::Mixer(MixerError::SingularGeometry) => {
                error!("pipeline refused: rotor geometry is singular")
            }
            BootError::Mixer(MixerError::BadThrustRange) => {
                error!("pipeline refused: rotor thrust range empty or not finite")
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // Boot.

    /// Builds the pipeline, logs its boot report and starts the control task on the interrupt
    /// executor, or gives the motors back if the configuration is refused. Not `async` on
    /// purpose: the pipeline (several KiB) then never lives in `main`'s future, only in the
    /// control task's.
    // Called once at boot; moving the motors back out on refusal is the point.
    #[allow(clippy::result_large_err)]
    fn start_control(
        config: &FlightConfig,
        motors: Motors,
        iwdg: Peri<'static, IWDG>,
    ) -> Result<(), Motors> {
        let pipeline = match FlightPipeline::new(config) {
            Ok(p) => p,
            Err(e) => {
                log_boot_error(&e);
                return Err(motors);
            }
        };
        log_boot_report(&pipeline.boot_report());
        let period = Duration::from_micros((config.control_period * 1e6 + 0.5) as u64);
        // Control on the interrupt executor, above everything in thread mode.
        hw::CONTROL_IRQ.set_priority(Priority::P1);
        let spawner = CONTROL_EXECUTOR.start(hw::CONTROL_IRQ);
        let watchdog = IndependentWatchdog::new(iwdg, WATCHDOG_TIMEOUT_US);
        spawner.spawn(unwrap!(control(pipeline, motors, watchdog, period)));
        Ok(())
    }

    #[embassy_executor::main]
    async fn main(spawner: Spawner) {
        let p = embassy_stm32::init(hal_config());
        info!(
            "{=str} {=str}: STM32F405RG, saturated hybrid position and heading tracking (f32)",
            env!("CARGO_PKG_NAME"),
            env!("CARGO_PKG_VERSION")
        );
        info!(
            "board: {=str}; pin map from {=str}",
            board::NAME,
            board::PIN_MAP_SOURCE
        );
        log_clocks(rcc::clocks(&p.RCC));

        // DWT cycle counter for the step times.
        let mut core = unwrap!(cortex_m::Peripherals::take());
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();

        let b = hw::split(p);
        let mut led = Output::new(b.led, Level::High, Speed::Low);

        // Motors first, so the ESCs see "stop" from the earliest moment.
        let mut motors = Motors::new(b.motors, board::MOTOR_PROTOCOL);
        motors.stop().await;

        let config = FlightConfig::paper();
        info!("set-up: the paper's Section VI vehicle and gains; demo reference: its helix");
        log_setup(&Setup {
            vehicle: config.vehicle,
            limits: config.limits,
            gains: config.gains,
            constants: ReferenceTrajectory::<f32>::paper_helix().constants(),
        });
        if let Err(_motors) = start_control(&config, motors, b.iwdg) {
            // `_motors` stays alive and keeps the outputs at stop (DShot: no frame, line low;
            // PWM: 1000 us).
            error!("motors held at zero; not flying");
            loop {
                led.toggle();
                Timer::after_millis(100).await;
            }
        }

        // IMU.
        let mut spi_config = spi::Config::default();
        spi_config.frequency = Hertz(board::IMU_SPI_HZ);
        spi_config.mode = spi::MODE_3;
        let imu_bus = Spi::new(
            b.imu.spi,
            b.imu.sck,
            b.imu.mosi,
            b.imu.miso,
            b.imu.tx_dma,
            b.imu.rx_dma,
            hw::Irqs,
            spi_config,
        );
        let cs = Output::new(b.imu.cs, Level::High, Speed::VeryHigh);
        let drdy = ExtiInput::new(b.imu.drdy, b.imu.drdy_exti, Pull::Down, hw::Irqs);
        spawner.spawn(unwrap!(imu(imu_bus, cs, drdy)));

        // MAVLink link.
        let mut uart_config = usart::Config::default();
        uart_config.baudrate = board::MAVLINK_BAUD;
        let uart = unwrap!(Uart::new(
            b.link.uart,
            b.link.rx,
            b.link.tx,
            b.link.tx_dma,
            b.link.rx_dma,
            hw::Irqs,
            uart_config,
        ));
        let (tx, rx) = uart.split();
        let rx_ring = cortex_m::singleton!(: [u8; 512] = [0; 512]);
        let rx = rx.into_ring_buffered(unwrap!(rx_ring));
        spawner.spawn(unwrap!(link_rx(rx)));
        spawner.spawn(unwrap!(link_tx(tx)));
        spawner.spawn(unwrap!(logger()));

        // Heartbeat LED: 1 Hz blink while the firmware runs.
        loop {
            led.toggle();
            Timer::after_millis(500).await;
        }
    }
}
