//! The clock tree the firmware configures: SYSCLK 168 MHz from an 8 MHz crystal through the main
//! PLL; AHB 168 MHz, APB1 42 MHz, APB2 84 MHz, PLL48CK 48 MHz (USB OTG FS, SDIO, RNG).
//!
//! The divider values live here as numbers, checked against the STM32F405 limits of RM0090
//! (section 6 "Reset and clock control", and the datasheet's maximum bus frequencies) at compile
//! time; `main.rs` maps them to the HAL's register enums and compares the frequencies the HAL
//! reports after init with [`ClockPlan::frequencies`]. Pure: its unit tests run on the host
//! (`cargo test -p firmware`).

/// Dividers and multipliers of the STM32F4 main PLL and bus prescalers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockPlan {
    /// External crystal (HSE) frequency \[Hz\].
    pub hse_hz: u32,
    /// PLLM: HSE divider ahead of the VCO (2..=63).
    pub pll_m: u32,
    /// PLLN: VCO multiplier (50..=432).
    pub pll_n: u32,
    /// PLLP: VCO divider to SYSCLK (2, 4, 6 or 8).
    pub pll_p: u32,
    /// PLLQ: VCO divider to PLL48CK (2..=15).
    pub pll_q: u32,
    /// AHB prescaler (1, 2, 4, …, 512).
    pub ahb_div: u32,
    /// APB1 prescaler (1, 2, 4, 8, 16).
    pub apb1_div: u32,
    /// APB2 prescaler (1, 2, 4, 8, 16).
    pub apb2_div: u32,
}

/// The frequencies a [`ClockPlan`] produces \[Hz\].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frequencies {
    /// VCO input `HSE / PLLM`.
    pub vco_in: u32,
    /// VCO output `VCO_in · PLLN`.
    pub vco_out: u32,
    /// SYSCLK `VCO_out / PLLP`.
    pub sysclk: u32,
    /// HCLK (AHB, core, DMA).
    pub hclk: u32,
    /// PCLK1 (APB1: TIM2–7, TIM12–14, USART2/3, UART4/5, I2C, SPI2/3, CAN).
    pub pclk1: u32,
    /// PCLK2 (APB2: TIM1/8–11, USART1/6, SPI1, ADC, SDIO).
    pub pclk2: u32,
    /// Timer kernel clock on APB1: `PCLK1`, doubled when the APB1 prescaler is not 1.
    pub tim_apb1: u32,
    /// Timer kernel clock on APB2: `PCLK2`, doubled when the APB2 prescaler is not 1.
    pub tim_apb2: u32,
    /// PLL48CK `VCO_out / PLLQ`.
    pub pll48: u32,
}

/// A limit of RM0090 / the STM32F405 datasheet that a [`ClockPlan`] breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockError {
    /// What is out of range, e.g. `"VCO input"`.
    pub what: &'static str,
    /// Its value (a frequency in Hz or a divider).
    pub value: u32,
    /// Smallest allowed value.
    pub min: u32,
    /// Largest allowed value.
    pub max: u32,
}

const MHZ: u32 = 1_000_000;

/// The firmware's plan: 8 MHz / 4 = 2 MHz VCO input (the value RM0090 recommends to limit PLL
/// jitter), ×168 = 336 MHz, /2 = 168 MHz SYSCLK, /7 = 48 MHz PLL48CK; AHB /1, APB1 /4, APB2 /2.
pub const PLAN: ClockPlan = ClockPlan {
    hse_hz: 8 * MHZ,
    pll_m: 4,
    pll_n: 168,
    pll_p: 2,
    pll_q: 7,
    ahb_div: 1,
    apb1_div: 4,
    apb2_div: 2,
};

// A plan that breaks a limit does not compile.
const _: () = assert!(
    PLAN.check().is_ok(),
    "clock plan violates an STM32F405 limit"
);

const fn within(what: &'static str, value: u32, min: u32, max: u32) -> Result<(), ClockError> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(ClockError {
            what,
            value,
            min,
            max,
        })
    }
}

const fn power_of_two_at_most(what: &'static str, value: u32, max: u32) -> Result<(), ClockError> {
    if value.is_power_of_two() && value <= max {
        Ok(())
    } else {
        Err(ClockError {
            what,
            value,
            min: 1,
            max,
        })
    }
}

/// `?` is not usable in a `const fn`; this propagates the first error.
macro_rules! try_const {
    ($e:expr) => {
        if let Err(e) = $e {
            return Err(e);
        }
    };
}

impl ClockPlan {
    /// The frequencies this plan produces (integer division, as the hardware does).
    /// Call [`ClockPlan::check`] first: a zero divider would divide by zero.
    pub const fn frequencies(&self) -> Frequencies {
        let vco_in = self.hse_hz / self.pll_m;
        let vco_out = vco_in * self.pll_n;
        let sysclk = vco_out / self.pll_p;
        let hclk = sysclk / self.ahb_div;
        let pclk1 = hclk / self.apb1_div;
        let pclk2 = hclk / self.apb2_div;
        Frequencies {
            vco_in,
            vco_out,
            sysclk,
            hclk,
            pclk1,
            pclk2,
            tim_apb1: if self.apb1_div == 1 { pclk1 } else { 2 * pclk1 },
            tim_apb2: if self.apb2_div == 1 { pclk2 } else { 2 * pclk2 },
            pll48: vco_out / self.pll_q,
        }
    }

    /// Checks the plan against the STM32F405 limits: HSE 4–26 MHz, PLLM 2..=63, PLLN 50..=432,
    /// PLLP ∈ {2, 4, 6, 8}, PLLQ 2..=15, VCO input 1–2 MHz, VCO output 100–432 MHz,
    /// SYSCLK/HCLK ≤ 168 MHz, PCLK1 ≤ 42 MHz, PCLK2 ≤ 84 MHz, PLL48CK exactly 48 MHz (USB
    /// needs it; SDIO and RNG need ≤ 48 MHz).
    /// Errors: the first [`ClockError`] found, in that order.
    pub const fn check(&self) -> Result<(), ClockError> {
        try_const!(within("HSE", self.hse_hz, 4 * MHZ, 26 * MHZ));
        try_const!(within("PLLM", self.pll_m, 2, 63));
        try_const!(within("PLLN", self.pll_n, 50, 432));
        if !matches!(self.pll_p, 2 | 4 | 6 | 8) {
            return Err(ClockError {
                what: "PLLP",
                value: self.pll_p,
                min: 2,
                max: 8,
            });
        }
        try_const!(within("PLLQ", self.pll_q, 2, 15));
        try_const!(power_of_two_at_most("AHB prescaler", self.ahb_div, 512));
        if self.ahb_div == 32 {
            // HPRE has no /32 setting.
            return Err(ClockError {
                what: "AHB prescaler",
                value: self.ahb_div,
                min: 1,
                max: 512,
            });
        }
        try_const!(power_of_two_at_most("APB1 prescaler", self.apb1_div, 16));
        try_const!(power_of_two_at_most("APB2 prescaler", self.apb2_div, 16));
        let f = self.frequencies();
        try_const!(within("VCO input", f.vco_in, MHZ, 2 * MHZ));
        try_const!(within("VCO output", f.vco_out, 100 * MHZ, 432 * MHZ));
        try_const!(within("SYSCLK", f.sysclk, 1, 168 * MHZ));
        try_const!(within("HCLK", f.hclk, 1, 168 * MHZ));
        try_const!(within("PCLK1", f.pclk1, 1, 42 * MHZ));
        try_const!(within("PCLK2", f.pclk2, 1, 84 * MHZ));
        within("PLL48CK", f.pll48, 48 * MHZ, 48 * MHZ)
    }
}

/// Bus frequencies the HAL reports after init \[Hz\]; `None` where it reports none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Reported {
    /// SYSCLK.
    pub sysclk: Option<u32>,
    /// HCLK.
    pub hclk: Option<u32>,
    /// PCLK1.
    pub pclk1: Option<u32>,
    /// PCLK2.
    pub pclk2: Option<u32>,
    /// APB1 timer clock.
    pub tim_apb1: Option<u32>,
    /// APB2 timer clock.
    pub tim_apb2: Option<u32>,
    /// PLL48CK (the main PLL's Q output).
    pub pll48: Option<u32>,
}

/// One clock of the plan next to what the hardware reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockLine {
    /// Clock name, e.g. `"SYSCLK"`.
    pub name: &'static str,
    /// Planned frequency \[Hz\].
    pub planned: u32,
    /// Reported frequency \[Hz\], `0` if the HAL reports none.
    pub reported: u32,
    /// Whether the two agree exactly.
    pub matches: bool,
}

/// Lines up the planned and the reported frequencies, clock by clock.
pub fn compare(plan: &Frequencies, reported: &Reported) -> [ClockLine; 7] {
    let line = |name, planned, reported: Option<u32>| ClockLine {
        name,
        planned,
        reported: reported.unwrap_or(0),
        matches: reported == Some(planned),
    };
    [
        line("SYSCLK", plan.sysclk, reported.sysclk),
        line("HCLK", plan.hclk, reported.hclk),
        line("PCLK1", plan.pclk1, reported.pclk1),
        line("PCLK2", plan.pclk2, reported.pclk2),
        line("TIM APB1", plan.tim_apb1, reported.tim_apb1),
        line("TIM APB2", plan.tim_apb2, reported.tim_apb2),
        line("PLL48CK", plan.pll48, reported.pll48),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_gives_the_intended_tree() {
        assert_eq!(PLAN.check(), Ok(()));
        let f = PLAN.frequencies();
        assert_eq!(f.vco_in, 2 * MHZ);
        assert_eq!(f.vco_out, 336 * MHZ);
        assert_eq!(f.sysclk, 168 * MHZ);
        assert_eq!(f.hclk, 168 * MHZ);
        assert_eq!(f.pclk1, 42 * MHZ);
        assert_eq!(f.pclk2, 84 * MHZ);
        // TIM2 (the embassy time driver) runs at 84 MHz because APB1 is divided.
        assert_eq!(f.tim_apb1, 84 * MHZ);
        assert_eq!(f.tim_apb2, 168 * MHZ);
        assert_eq!(f.pll48, 48 * MHZ);
    }

    #[test]
    fn limits_are_enforced_with_names() {
        let overclocked = ClockPlan { pll_n: 180, ..PLAN };
        let e = overclocked.check().unwrap_err();
        assert_eq!((e.what, e.value), ("SYSCLK", 180 * MHZ));
        let vco_too_fast = ClockPlan {
            pll_n: 220,
            pll_p: 2,
            ..PLAN
        };
        assert_eq!(vco_too_fast.check().unwrap_err().what, "VCO output");
        let fast_apb1 = ClockPlan {
            apb1_div: 2,
            ..PLAN
        };
        let e = fast_apb1.check().unwrap_err();
        assert_eq!((e.what, e.value), ("PCLK1", 84 * MHZ));
        let odd_p = ClockPlan { pll_p: 3, ..PLAN };
        assert_eq!(odd_p.check().unwrap_err().what, "PLLP");
        let coarse_m = ClockPlan { pll_m: 2, ..PLAN };
        assert_eq!(coarse_m.check().unwrap_err().what, "VCO input");
        let no_ahb32 = ClockPlan {
            ahb_div: 32,
            ..PLAN
        };
        assert_eq!(no_ahb32.check().unwrap_err().what, "AHB prescaler");
        let bad_usb = ClockPlan { pll_q: 6, ..PLAN };
        let e = bad_usb.check().unwrap_err();
        assert_eq!((e.what, e.value), ("PLL48CK", 56 * MHZ));
    }

    #[test]
    fn comparison_flags_differences_and_missing_clocks() {
        let f = PLAN.frequencies();
        let exact = Reported {
            sysclk: Some(f.sysclk),
            hclk: Some(f.hclk),
            pclk1: Some(f.pclk1),
            pclk2: Some(f.pclk2),
            tim_apb1: Some(f.tim_apb1),
            tim_apb2: Some(f.tim_apb2),
            pll48: Some(f.pll48),
        };
        assert!(compare(&f, &exact).iter().all(|l| l.matches));
        let off = Reported {
            sysclk: Some(16 * MHZ),
            pll48: None,
            ..exact
        };
        let bad: Vec<_> = compare(&f, &off)
            .iter()
            .filter(|l| !l.matches)
            .map(|l| (l.name, l.reported))
            .collect();
        assert_eq!(bad, [("SYSCLK", 16 * MHZ), ("PLL48CK", 0)]);
    }
}
