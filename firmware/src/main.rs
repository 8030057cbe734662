//! Flight firmware for an STM32F405RG quadrotor (thumbv7em-none-eabihf).
//!
//! On the MCU: set the clocks (168 MHz from the 8 MHz crystal), log a boot banner with the
//! set-up, certify it with controller-core's a-priori bounds and log the certificate, build the
//! controller, then log a 1 Hz heartbeat. The board-independent parts are in the `firmware`
//! library (`src/lib.rs`) and are unit-tested on the host.
//!
//! On the host this binary is a stub that says what it is, so that `cargo test --workspace` and
//! host clippy can build every workspace member.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "firmware: this binary is built for thumbv7em-none-eabihf (STM32F405RG): \
         cargo build -p firmware --target thumbv7em-none-eabihf --release"
    );
}

#[cfg(target_os = "none")]
mod mcu {
    use controller_core::{Certificate, ParameterError};
    use defmt::{error, info, warn};
    use embassy_executor::Spawner;
    use embassy_stm32::rcc::{
        self, AHBPrescaler, APBPrescaler, Hse, HseMode, Pll, PllPDiv, PllPreDiv, PllQDiv,
        PllSource, Sysclk,
    };
    use embassy_stm32::time::{Hertz, MaybeHertz};
    use embassy_time::{Duration, Instant, Ticker};
    use firmware::clocks::{self, Reported, PLAN};
    use firmware::report::{self, Setup, Severity, Value};
    use {defmt_rtt as _, panic_probe as _};

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

    #[embassy_executor::main]
    async fn main(_spawner: Spawner) {
        let p = embassy_stm32::init(hal_config());
        info!(
            "{=str} {=str}: STM32F405RG, saturated hybrid position and heading tracking (f32)",
            env!("CARGO_PKG_NAME"),
            env!("CARGO_PKG_VERSION")
        );
        log_clocks(rcc::clocks(&p.RCC));

        let boot = report::boot(Setup::paper());
        info!("set-up: the paper's Section VI (helix reference)");
        log_setup(&boot.setup);
        log_certificate(&boot.certificate);
        // Held for the control loop of a later issue.
        let controller = match boot.controller {
            Ok(c) => {
                info!("controller ready");
                Some(c)
            }
            Err(e) => {
                log_refusal("controller", &e);
                None
            }
        };

        let mut ticker = Ticker::every(Duration::from_secs(1));
        loop {
            ticker.next().await;
            info!(
                "heartbeat: uptime {=u64} s, controller {=str}",
                Instant::now().as_secs(),
                if controller.is_some() {
                    "ready"
                } else {
                    "refused"
                }
            );
        }
    }
}
