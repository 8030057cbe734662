//! The flight firmware on QEMU's `mps2-an386` (ARM AN386: a Cortex-M4 with FPU on the MPS2
//! board), for processor-in-the-loop: the same `thumbv7em-none-eabihf` code, the same
//! `FlightPipeline` and the same task layer (`firmware::app`) as the STM32F405 build, with this
//! board layer at the edges:
//!
//! - **clock**: [`firmware::app::control::LockstepClock`]: the control ticks follow the
//!   simulation's clock carried by the `HIL_SENSOR` messages, so host-sim and the emulated MCU
//!   advance in lockstep however fast QEMU runs;
//! - **IMU**: none on the board; samples arrive as `HIL_SENSOR` over the link (the `hil`
//!   feature, never in the flight build);
//! - **motors**: the throttles leave as `HIL_ACTUATOR_CONTROLS` in the telemetry, each tick;
//! - **link**: the CMSDK UART0 ([`uart`]), QEMU's first serial port: the ground station's link
//!   (`host-sim pil`, the pymavlink client), untrusted by default as a radio would be (a
//!   `SETUP_SIGNING` must be signed with the key in force); built with
//!   `FIRMWARE_MAVLINK_LINK_TRUST=trusted` it plays a wired console, on which a key is set up
//!   unsigned (`tests/mavlink-client` flies both builds);
//! - **time**: a SysTick embassy-time driver ([`time_driver`]);
//! - **logs**: defmt over semihosting ([`defmt_console`]), to QEMU's semihosting console;
//! - **exit**: a panic or a hard fault logs and ends QEMU with status 1 (semihosting
//!   `SYS_EXIT`), so a crash is never mistaken for a stall;
//! - **watchdog**: none: host-sim's stall timeout plays its part.
//!
//! The control task runs on an `InterruptExecutor` above thread mode, as on the STM32. Run it
//! with `host-sim pil` (docs/sil-pil.md, "Processor in the loop").
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "firmware-mps2-an386: built for thumbv7em-none-eabihf and run under QEMU by `host-sim pil`: \
         cargo build -p firmware --target thumbv7em-none-eabihf --release \
         --no-default-features --features board-mps2-an386"
    );
}

#[cfg(target_os = "none")]
mod defmt_console;
#[cfg(target_os = "none")]
mod time_driver;
#[cfg(target_os = "none")]
mod uart;

#[cfg(target_os = "none")]
mod mcu {
    use cortex_m::interrupt::InterruptNumber;
    use cortex_m::peripheral::NVIC;
    use cortex_m_rt::{exception, ExceptionFrame};
    use cortex_m_semihosting::debug;
    use defmt::{error, info, unwrap};
    use embassy_executor::{InterruptExecutor, Spawner};
    use embassy_time::{Duration, Timer};
    use firmware::app::control::{self, LockstepClock, MotorSink, Watchdog};
    use firmware::app::{boot_log, logger};
    use firmware::config::FlightConfig;
    use firmware::pipeline::{FlightPipeline, MotorOutput};

    use crate::{time_driver, uart};

    /// A free IRQ line of the AN386 (QEMU `hw/arm/mps2.c` wires UARTs, timers, the dual timer,
    /// SPI and Ethernet below it): it runs the control executor.
    const CONTROL_IRQ: u16 = 31;

    /// The control executor's interrupt line.
    #[derive(Clone, Copy)]
    struct ControlIrq;

    // SAFETY: a valid external interrupt of the AN386 NVIC (32 lines).
    unsafe impl InterruptNumber for ControlIrq {
        fn number(self) -> u16 {
            CONTROL_IRQ
        }
    }

    /// NVIC priorities (upper bits significant; lower is more urgent): the control executor
    /// above the UART, both above thread mode.
    const CONTROL_PRIORITY: u8 = 0x20;
    const UART_PRIORITY: u8 = 0x40;

    /// How long the boot self-check of the clock reads it back to back \[µs\] (60 SysTick
    /// reloads).
    const CLOCK_CHECK_US: u64 = 60_000;

    static CONTROL_EXECUTOR: InterruptExecutor = InterruptExecutor::new();

    /// Without a device crate every external interrupt lands here; `irqn` is its number.
    #[exception]
    unsafe fn DefaultHandler(irqn: i16) {
        match u16::try_from(irqn) {
            Ok(uart::RX_IRQ) => uart::on_rx_interrupt(),
            // SAFETY: the executor was started on this interrupt in `start_control` and
            // nothing else pends it.
            Ok(CONTROL_IRQ) => unsafe { CONTROL_EXECUTOR.on_interrupt() },
            _ => {
                error!("unexpected interrupt {=i16}", irqn);
                exit_failure()
            }
        }
    }

    #[exception]
    unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
        error!(
            "hard fault: pc {=u32:#010x}, lr {=u32:#010x}",
            frame.pc(),
            frame.lr()
        );
        exit_failure()
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo) -> ! {
        error!("panic: {}", defmt::Display2Format(info));
        exit_failure()
    }

    /// Ends QEMU with status 1 (semihosting `SYS_EXIT`, `ADP_Stopped_RunTimeErrorUnknown`).
    fn exit_failure() -> ! {
        debug::exit(debug::EXIT_FAILURE);
        // Without a semihosting host (a real board) `exit` returns: stop here.
        loop {
            cortex_m::asm::bkpt();
        }
    }

    /// The motors of a simulated vehicle: nothing to drive here, because the pipeline sends
    /// each tick's throttles to the simulator as `HIL_ACTUATOR_CONTROLS`.
    struct HilMotors;

    impl MotorSink for HilMotors {
        type Frames = ();
        fn prepare(&mut self, _output: &MotorOutput) {}
        async fn write(&mut self, _frames: ()) {}
    }

    /// No hardware watchdog on this board; a stalled control loop is caught by the simulator,
    /// which stops waiting for `HIL_ACTUATOR_CONTROLS` after its timeout and fails the run.
    struct NoWatchdog;

    impl Watchdog for NoWatchdog {
        fn start(&mut self) {}
        fn feed(&mut self) {}
    }

    #[embassy_executor::task]
    async fn control(mut pipeline: FlightPipeline, period: Duration) {
        let mut clock = LockstepClock::new(period);
        control::run(
            &mut pipeline,
            &mut clock,
            &mut HilMotors,
            &mut NoWatchdog,
            period,
        )
        .await
    }

    /// Builds the pipeline (logging the boot report) and starts the control task on the
    /// interrupt executor; `false` if the configuration is refused. Not `async`, so that the
    /// pipeline lives only in the control task's future.
    fn start_control(config: &FlightConfig, nvic: &mut NVIC) -> bool {
        let Some(pipeline) = boot_log::build_pipeline(config) else {
            return false;
        };
        let period = Duration::from_micros(config.control_rate.period_us());
        // SAFETY: priorities are set before the interrupts are unmasked; no priority-based
        // critical section is in use (critical sections mask all interrupts).
        unsafe { nvic.set_priority(ControlIrq, CONTROL_PRIORITY) };
        let spawner = CONTROL_EXECUTOR.start(ControlIrq);
        spawner.spawn(unwrap!(control(pipeline, period)));
        true
    }

    #[embassy_executor::main]
    async fn main(spawner: Spawner) {
        info!(
            "{=str} {=str}: mps2-an386 (QEMU Cortex-M4F), processor in the loop, saturated \
             hybrid position and heading tracking (f32)",
            env!("CARGO_PKG_NAME"),
            env!("CARGO_PKG_VERSION")
        );
        let mut core = unwrap!(cortex_m::Peripherals::take());
        // The DWT cycle counter reads 0 under QEMU: the logged step cycles are 0 here; the
        // instruction counts come from `firmware/qemu/bench.sh` instead.
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();
        time_driver::init(core.SYST);
        let clock = time_driver::self_check(CLOCK_CHECK_US);
        info!(
            "clock: {=u32} readings over {=u64} us, {=u32} backwards, {=u32} jumps over {=u64} us \
             (largest step {=u64} us)",
            clock.reads,
            CLOCK_CHECK_US,
            clock.backwards,
            clock.jumps,
            time_driver::JUMP_US,
            clock.max_step_us
        );

        let config = FlightConfig::built();
        if !start_control(&config, &mut core.NVIC) {
            error!("configuration refused; not flying");
            exit_failure();
        }

        uart::init();
        // SAFETY: as in `start_control`.
        unsafe {
            core.NVIC.set_priority(uart::RxIrq, UART_PRIORITY);
            NVIC::unmask(uart::RxIrq);
        }
        spawner.spawn(unwrap!(uart::rx_task()));
        spawner.spawn(unwrap!(uart::tx_task()));
        spawner.spawn(unwrap!(logger::logger(time_driver::CORE_HZ)));
        info!("link: UART0, waiting for HIL_SENSOR");
        loop {
            Timer::after_secs(3600).await;
        }
    }
}
