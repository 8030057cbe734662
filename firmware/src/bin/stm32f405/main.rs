//! Flight firmware for an STM32F405RG quadrotor (thumbv7em-none-eabihf).
//!
//! On the MCU: set the clocks (168 MHz from the 8 MHz crystal), log a boot banner with the
//! set-up, its a-priori bound certificate and the mixer fit, then fly:
//!
//! - **control** (an `InterruptExecutor` on a spare interrupt vector, NVIC priority 1, above
//!   every thread-mode task): every `control_period` (the law's rate, 100 Hz by default) it
//!   drains the IMU samples and the link bytes received since the last tick into the
//!   `FlightPipeline`, runs `control_tick`
//!   (estimate → controller → mixer), writes the motors (DShot600 or PWM), queues the telemetry,
//!   feeds the independent watchdog, and measures its step with the DWT cycle counter;
//! - **imu** (thread mode): ICM-42688-P data-ready (EXTI) → SPI (DMA) read → body frame → queue;
//! - **link_rx** / **link_tx** (thread mode): MAVLink bytes between USART1 (DMA, circular on
//!   receive) and the control task. USART1 is the board's only MAVLink link, and what is
//!   usually wired to it is a telemetry radio, so it is untrusted by default: a
//!   `SETUP_SIGNING` must be signed with the key in force. A build with
//!   `FIRMWARE_MAVLINK_LINK_TRUST=trusted` marks it a wired console (`SETUP_SIGNING` taken
//!   unsigned, while disarmed): only for a vehicle whose USART1 goes to a cable, e.g. a
//!   USB-serial adapter on the bench, never to a radio. The board's USB port is not used by
//!   this firmware (docs/mavlink.md, "Signing");
//! - **logger** (thread mode): state changes and refused commands, 1 Hz timing, 10 Hz flight
//!   summary, link counters, all as defmt over RTT;
//! - **param_store** (thread mode): saves the parameters to flash after each accepted
//!   `PARAM_SET` (`param_flash.rs`: the last two sectors); they are restored at boot, before
//!   the control task starts, if still certified.
//!
//! The control task owns the pipeline outright: the other tasks only exchange plain values
//! with it through fixed-size `embassy-sync` queues guarded by short critical sections, so no
//! lock is ever held across the control step and no I/O task can delay it.
//!
//! This folder is the STM32F405 board layer, all of it: the clock plan (`clocks.rs`), the pin
//! table (`pins.rs`), the motor outputs (`motors.rs`) and, here, the IMU and UART drivers, the
//! watchdog and the interrupt executor. The tasks' logic is the board-independent task layer
//! `firmware::app` (control loop, queues, logger, boot banner), which the QEMU board
//! (`src/bin/mps2_an386/`) runs too; the flight logic below it is the host-tested library
//! (`src/lib.rs`). On the host this binary is a stub that says what it is, so that
//! `cargo test --workspace` and host clippy can build every member; its pure modules (`clocks`,
//! `pins`) are compiled there too, so their unit tests run with `cargo test -p firmware`.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(all(feature = "board-stm32f405", feature = "board-mps2-an386"))]
compile_error!("pick one board feature: board-stm32f405 (default) or board-mps2-an386");

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "firmware: this binary is built for thumbv7em-none-eabihf (STM32F405RG): cargo fw-build \
         (cargo build -p firmware --target thumbv7em-none-eabihf --release)"
    );
}

// On the host only their unit tests use them.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
mod clocks;
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
mod erase_watchdog;
#[cfg(target_os = "none")]
mod motors;
#[cfg(target_os = "none")]
mod param_flash;
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
mod pins;

#[cfg(target_os = "none")]
mod mcu {
    use defmt::{error, info, unwrap, warn};
    use embassy_embedded_hal::shared_bus::asynch::spi::SpiDevice;
    use embassy_executor::{InterruptExecutor, Spawner};
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
    use embassy_sync::blocking_mutex::raw::NoopRawMutex;
    use embassy_sync::mutex::Mutex;
    use embassy_time::{Delay, Duration, Instant, Timer};
    use firmware::app::control::{self, DeadlineClock, MotorSink, Watchdog};
    use firmware::app::queues::{count, link_received, IMU_SAMPLES, IO, LINK_TX};
    use firmware::app::{boot_log, logger, param_flash as params};
    use firmware::config::FlightConfig;
    use firmware::drivers::icm42688::{self, Icm42688};
    use firmware::pipeline::{FlightPipeline, ImuSample, MotorOutput};
    use {defmt_rtt as _, panic_probe as _};

    use crate::clocks::{self, Reported, PLAN};
    use crate::motors::Motors;
    use crate::param_flash::{self, Store};
    use crate::pins::{self, hw};

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
    // Control: highest priority.

    static CONTROL_EXECUTOR: InterruptExecutor = InterruptExecutor::new();

    /// The control executor runs in this (otherwise unused) interrupt; see `pins::hw`.
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

    /// The independent watchdog (LSI-clocked: it survives a clock failure).
    struct Iwdg(IndependentWatchdog<'static, IWDG>);

    impl Watchdog for Iwdg {
        fn start(&mut self) {
            self.0.unleash();
            info!("watchdog: {=u32} us", WATCHDOG_TIMEOUT_US);
        }
        fn feed(&mut self) {
            self.0.pet();
        }
    }

    impl MotorSink for Motors {
        type Frames = crate::motors::Frames;
        fn prepare(&mut self, output: &MotorOutput) -> Self::Frames {
            Motors::prepare(self, output)
        }
        async fn write(&mut self, frames: Self::Frames) {
            Motors::write(self, frames).await
        }
    }

    #[embassy_executor::task]
    async fn control(
        mut pipeline: FlightPipeline,
        mut motors: Motors,
        mut watchdog: Iwdg,
        period: Duration,
    ) {
        let mut clock = DeadlineClock::new(period);
        control::run(
            &mut pipeline,
            &mut clock,
            &mut motors,
            &mut watchdog,
            period,
        )
        .await
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
                    count(&IO.imu_reads, 1);
                    let sample = ImuSample {
                        gyro_rad_s: pins::to_body(s.gyro_rad_s),
                        accel_m_s2: pins::to_body(s.accel_m_s2),
                        time_us,
                    };
                    if IMU_SAMPLES.try_send(sample).is_err() {
                        count(&IO.imu_queue_full, 1);
                    }
                }
                Err(_) => {
                    count(&IO.imu_errors, 1);
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
                // A DMA ring cannot be held back: what does not fit is dropped and counted.
                Ok(n) => link_received(&buf[..n]),
                Err(e) => {
                    // Overrun, framing, noise or parity: the ring restarts on the next read;
                    // the MAVLink parser resynchronises on the next frame start.
                    count(&IO.link_rx_errors, 1);
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
    // Parameters: saved to flash after each accepted PARAM_SET, thread mode.

    #[embassy_executor::task]
    async fn param_store(store: Store) {
        params::run(store).await
    }

    // ---------------------------------------------------------------------------------------
    // Boot.

    /// Builds the pipeline (logging the set-up, certificate and mixer fit), restores the
    /// parameters stored in `store` if they are still certified, and starts the control task on
    /// the interrupt executor, or gives the motors back if the configuration is
    /// refused. Not `async` on purpose: the pipeline (several KiB) then never lives in `main`'s
    /// future, only in the control task's.
    // Called once at boot; moving the motors back out on refusal is the point.
    #[allow(clippy::result_large_err)]
    fn start_control(
        config: &FlightConfig,
        motors: Motors,
        iwdg: Peri<'static, IWDG>,
        store: Option<&mut Store>,
    ) -> Result<(), Motors> {
        let Some(mut pipeline) = boot_log::build_pipeline(config) else {
            return Err(motors);
        };
        if let Some(store) = store {
            params::restore(store, &mut pipeline);
            // From now on an accepted change holds arming until its save is done.
            pipeline.attach_storage();
        }
        let period = Duration::from_micros(config.control_rate.period_us());
        // Control on the interrupt executor, above everything in thread mode.
        hw::CONTROL_IRQ.set_priority(Priority::P1);
        let spawner = CONTROL_EXECUTOR.start(hw::CONTROL_IRQ);
        let watchdog = Iwdg(IndependentWatchdog::new(iwdg, WATCHDOG_TIMEOUT_US));
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
            pins::NAME,
            pins::PIN_MAP_SOURCE
        );
        log_clocks(rcc::clocks(&p.RCC));

        // DWT cycle counter for the step times.
        let mut core = unwrap!(cortex_m::Peripherals::take());
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();

        let b = hw::split(p);
        let mut led = Output::new(b.led, Level::High, Speed::Low);

        // Motors first, so the ESCs see "stop" from the earliest moment.
        let mut motors = Motors::new(b.motors, pins::MOTOR_PROTOCOL);
        motors.stop().await;

        let mut store = param_flash::open(b.flash);
        if store.is_none() {
            error!("params: no flash store; parameters are not persisted");
        }
        let config = FlightConfig::built();
        if let Err(_motors) = start_control(&config, motors, b.iwdg, store.as_mut()) {
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
        spi_config.frequency = Hertz(pins::IMU_SPI_HZ);
        spi_config.mode = hw::imu_spi_mode();
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
        uart_config.baudrate = pins::MAVLINK_BAUD;
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
        spawner.spawn(unwrap!(logger::logger(CORE_HZ)));
        if let Some(store) = store {
            spawner.spawn(unwrap!(param_store(store)));
        }

        // Heartbeat LED: 1 Hz blink while the firmware runs.
        loop {
            led.toggle();
            Timer::after_millis(500).await;
        }
    }
}
