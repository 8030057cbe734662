//! The STM32F405 board's pin table: every pin, peripheral, DMA stream and interrupt the firmware
//! uses, the IMU bus settings and the IMU mounting. Another board with this MCU is another
//! version of this one file.
//!
//! The table below names the pins; the values the code sets (SPI mode and clock, baud rate) are
//! the constants it links to, written once; the `hw` module (MCU build only) hands out exactly
//! these pins and DMA streams.
//!
//! # SpeedyBee F405 V4 (the default)
//!
//! STM32F405RGT6, ICM-42688-P on SPI1, 8 MHz crystal. The pin map is Betaflight's target
//! `SPEEDYBEEF405V4`, file `configs/SPEEDYBEEF405V4/config.h` of
//! <https://github.com/betaflight/config> (read at commit
//! `2976772e4e5bf59668511cf7608d3f6e6b5c0283`): `GYRO_1_SPI_INSTANCE SPI1` (`SPI1_SCK_PIN PA5`,
//! `SPI1_SDI_PIN PA6`, `SPI1_SDO_PIN PA7`), `GYRO_1_CS_PIN PA4`, `GYRO_1_EXTI_PIN PC4`,
//! `GYRO_1_ALIGN CW90_DEG`, `MOTOR1_PIN PB6` … `MOTOR4_PIN PB1` with their `TIMER_PIN_MAPPING`
//! (PB6 / PB7: TIM4 CH1 / CH2, PB0 / PB1: TIM3 CH3 / CH4), `UART1_TX_PIN PA9`,
//! `UART1_RX_PIN PA10`, `LED0_PIN PC13`, `SYSTEM_HSE_MHZ 8`.
//!
//! | function | pin | peripheral | DMA (RM0090 table 42/43) |
//! | --- | --- | --- | --- |
//! | IMU SCK / MISO / MOSI | PA5 / PA6 / PA7 | SPI1 (AF5), [`IMU_SPI_MODE`], [`IMU_SPI_HZ`] | RX DMA2 stream 0 ch 3, TX DMA2 stream 3 ch 3 |
//! | IMU chip select | PA4 | GPIO out, active low | – |
//! | IMU data ready (INT1) | PC4 | EXTI line 4, rising / high | – |
//! | MAVLink TX / RX | PA9 / PA10 | USART1 (AF7), [`MAVLINK_BAUD`] 8N1 | TX DMA2 stream 7 ch 4, RX DMA2 stream 5 ch 4 (circular) |
//! | motor 1 / 2 | PB6 / PB7 | TIM4 CH1 / CH2 (AF2) | TIM4_UP DMA1 stream 6 ch 2 (burst to CCR1..CCR2) |
//! | motor 3 / 4 | PB0 / PB1 | TIM3 CH3 / CH4 (AF2) | TIM3_UP DMA1 stream 2 ch 5 (burst to CCR3..CCR4) |
//! | status LED | PC13 | GPIO out, on = low (Betaflight's non-inverted LED) | – |
//! | control executor | – | UART5 interrupt vector (UART5 itself unused), priority 1 | – |
//!
//! The four motors sit on two timers (as on most F405 boards), so a DShot frame is two DMA bursts
//! started together, one per timer. TIM2 is embassy's time driver and is not used for motors.
//! USART1 (PA9 / PA10) is the board's UART1 (TX1 / RX1); which pad or connector carries it
//! depends on the board revision's wiring diagram (not checked on hardware here). It is the
//! only MAVLink link, untrusted unless built with `FIRMWARE_MAVLINK_LINK_TRUST=trusted`
//! (`firmware::built_flight::LINK_TRUST`: who may set the signing key). Betaflight's
//! defaults put the receiver on USART2, MSP on UART4 and the ESC sensor on UART5.
//!
//! Motor numbering follows Betaflight's quad-X: M1 rear right, M2 front right, M3 rear left,
//! M4 front left (see [`MOTOR_OUTPUT_OF_MIXER`]).

/// Board name for the boot banner.
pub const NAME: &str = "SpeedyBee F405 V4 (Betaflight target SPEEDYBEEF405V4)";

/// Where the pin map comes from.
pub const PIN_MAP_SOURCE: &str =
    "betaflight/config configs/SPEEDYBEEF405V4/config.h @ 2976772e4e5bf59668511cf7608d3f6e6b5c0283";

/// IMU SPI clock requested \[Hz\]; SPI1 runs from PCLK2 = 84 MHz, so the HAL picks 84 / 8 =
/// 10.5 MHz (the ICM-42688-P allows 24 MHz).
pub const IMU_SPI_HZ: u32 = 10_500_000;

/// Clock polarity and phase of an SPI bus (the four SPI modes: mode = 2·CPOL + CPHA).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpiMode {
    /// CPOL = 1: the clock idles high.
    pub clock_idles_high: bool,
    /// CPHA = 1: data is sampled on the clock's second edge.
    pub sample_on_second_edge: bool,
}

/// IMU SPI mode: mode 3 (clock idles high, data sampled on the second, rising, edge). The
/// ICM-42688-P accepts modes 0 and 3 (datasheet DS-000347, SPI interface; see
/// `firmware::drivers::icm42688`).
pub const IMU_SPI_MODE: SpiMode = SpiMode {
    clock_idles_high: true,
    sample_on_second_edge: true,
};

// Modes 1 and 2 (CPOL ≠ CPHA) do not talk to the ICM-42688-P: such a table does not compile.
const _: () = assert!(
    IMU_SPI_MODE.clock_idles_high == IMU_SPI_MODE.sample_on_second_edge,
    "the ICM-42688-P accepts SPI modes 0 and 3 only"
);

/// MAVLink UART baud rate.
pub const MAVLINK_BAUD: u32 = 921_600;

/// Motor protocol of the ESCs wired to this board: DShot600, or the PWM fallback for ESCs
/// without DShot (`MotorProtocol::Pwm`).
pub const MOTOR_PROTOCOL: firmware::drivers::dshot::MotorProtocol =
    firmware::drivers::dshot::MotorProtocol::Dshot600;

/// Timer kernel clock of the motor timers \[Hz\]: TIM3 and TIM4 are on APB1, so 2 × PCLK1 =
/// 84 MHz in the clock plan.
pub const MOTOR_TIMER_HZ: u32 = crate::clocks::PLAN.frequencies().tim_apb1;

/// Board motor output (0-based: M1 = 0) driven by each index of the mixer's `throttle` array.
/// The mixer (`firmware::mixer`) uses Betaflight's quad-X numbering, as the board's silkscreen does,
/// so this is the identity; a board with another numbering permutes it here.
pub const MOTOR_OUTPUT_OF_MIXER: [usize; 4] = [0, 1, 2, 3];

/// Sensor → body FLU rotation of the IMU (`v_body = R · v_sensor`).
///
/// Betaflight's `CW90_DEG` (the chip turned 90° clockwise seen from above) maps a sensor vector to
/// the board frame as `x_b = y_s, y_b = −x_s, z_b = z_s`; Betaflight's board frame is right-handed
/// with x forward and z up, i.e. FLU. Bench check (docs/logs.md): level → accel z ≈ +9.81 m/s²; roll
/// right → gyro x > 0; nose up → gyro y < 0; yaw left (counter-clockwise from above) → gyro z > 0.
pub const SENSOR_TO_BODY: [[f32; 3]; 3] = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];

/// Rotates a sensor-frame vector into the body frame with [`SENSOR_TO_BODY`].
pub fn to_body(v: [f32; 3]) -> [f32; 3] {
    let r = &SENSOR_TO_BODY;
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

/// Maps the mixer's four throttles to the board's motor outputs M1..M4.
pub fn to_motor_outputs<T: Copy + Default>(mixer: [T; 4]) -> [T; 4] {
    let mut out = [T::default(); 4];
    for (i, &o) in MOTOR_OUTPUT_OF_MIXER.iter().enumerate() {
        out[o] = mixer[i];
    }
    out
}

/// The hardware resources, as embassy peripherals (MCU build only).
#[cfg(target_os = "none")]
#[allow(missing_docs)] // field names are self-explanatory; the table above documents them.
pub mod hw {
    use embassy_stm32::gpio::OutputType;
    use embassy_stm32::peripherals::{
        DMA1_CH2, DMA1_CH6, DMA2_CH0, DMA2_CH3, DMA2_CH5, DMA2_CH7, EXTI4, FLASH, IWDG, PA10, PA4,
        PA5, PA6, PA7, PA9, PB0, PB1, PB6, PB7, PC13, PC4, SPI1, TIM3, TIM4, USART1,
    };
    use embassy_stm32::spi;
    use embassy_stm32::time::Hertz;
    use embassy_stm32::timer::low_level::CountingMode;
    use embassy_stm32::timer::simple_pwm::{PwmPin, SimplePwm};
    use embassy_stm32::timer::Channel;
    use embassy_stm32::{bind_interrupts, dma, exti, flash, interrupt, usart, Peri, Peripherals};

    bind_interrupts!(
        /// Interrupt bindings of the drivers the board uses.
        pub struct Irqs {
            USART1 => usart::InterruptHandler<USART1>;
            DMA2_STREAM0 => dma::InterruptHandler<DMA2_CH0>;
            DMA2_STREAM3 => dma::InterruptHandler<DMA2_CH3>;
            DMA2_STREAM5 => dma::InterruptHandler<DMA2_CH5>;
            DMA2_STREAM7 => dma::InterruptHandler<DMA2_CH7>;
            DMA1_STREAM2 => dma::InterruptHandler<DMA1_CH2>;
            DMA1_STREAM6 => dma::InterruptHandler<DMA1_CH6>;
            EXTI4 => exti::InterruptHandler<interrupt::typelevel::EXTI4>;
            FLASH => flash::InterruptHandler;
        }
    );

    /// [`super::IMU_SPI_MODE`] as the HAL's SPI mode.
    pub const fn imu_spi_mode() -> spi::Mode {
        let mode = super::IMU_SPI_MODE;
        spi::Mode {
            polarity: if mode.clock_idles_high {
                spi::Polarity::IdleHigh
            } else {
                spi::Polarity::IdleLow
            },
            phase: if mode.sample_on_second_edge {
                spi::Phase::CaptureOnSecondTransition
            } else {
                spi::Phase::CaptureOnFirstTransition
            },
        }
    }

    /// The software interrupt of the control executor: UART5's vector (the UART is unused).
    pub const CONTROL_IRQ: interrupt::Interrupt = interrupt::Interrupt::UART5;

    /// Timer of motors 1 and 2 (channels 1, 2).
    pub type MotorTimerA = TIM4;
    /// Timer of motors 3 and 4 (channels 3, 4).
    pub type MotorTimerB = TIM3;
    /// `TIM4_UP` DMA stream (DShot burst of timer A).
    pub type MotorDmaA = DMA1_CH6;
    /// `TIM3_UP` DMA stream (DShot burst of timer B).
    pub type MotorDmaB = DMA1_CH2;
    /// First and last channel of timer A (motors 1, 2: board outputs 0, 1). Consecutive: the
    /// DMA burst writes CCRfirst..=CCRlast.
    pub const MOTOR_A_CHANNELS: (Channel, Channel) = (Channel::Ch1, Channel::Ch2);
    /// First and last channel of timer B (motors 3, 4: board outputs 2, 3).
    pub const MOTOR_B_CHANNELS: (Channel, Channel) = (Channel::Ch3, Channel::Ch4);

    /// The two motor timers in PWM mode at `frequency` (600 kHz for DShot600, 400 Hz for PWM),
    /// their pins attached to the right channels, and the timers' update DMA streams.
    pub fn motor_timers(
        m: Motors,
        frequency: Hertz,
    ) -> (
        SimplePwm<'static, MotorTimerA>,
        SimplePwm<'static, MotorTimerB>,
        Peri<'static, MotorDmaA>,
        Peri<'static, MotorDmaB>,
    ) {
        let a = SimplePwm::new(
            m.tim_a,
            Some(PwmPin::new(m.m1, OutputType::PushPull)),
            Some(PwmPin::new(m.m2, OutputType::PushPull)),
            None,
            None,
            frequency,
            CountingMode::EdgeAlignedUp,
        );
        let b = SimplePwm::new(
            m.tim_b,
            None,
            None,
            Some(PwmPin::new(m.m3, OutputType::PushPull)),
            Some(PwmPin::new(m.m4, OutputType::PushPull)),
            frequency,
            CountingMode::EdgeAlignedUp,
        );
        (a, b, m.dma_a, m.dma_b)
    }

    pub struct Imu {
        pub spi: Peri<'static, SPI1>,
        pub sck: Peri<'static, PA5>,
        pub miso: Peri<'static, PA6>,
        pub mosi: Peri<'static, PA7>,
        pub cs: Peri<'static, PA4>,
        pub drdy: Peri<'static, PC4>,
        pub drdy_exti: Peri<'static, EXTI4>,
        pub tx_dma: Peri<'static, DMA2_CH3>,
        pub rx_dma: Peri<'static, DMA2_CH0>,
    }

    pub struct Link {
        pub uart: Peri<'static, USART1>,
        pub tx: Peri<'static, PA9>,
        pub rx: Peri<'static, PA10>,
        pub tx_dma: Peri<'static, DMA2_CH7>,
        pub rx_dma: Peri<'static, DMA2_CH5>,
    }

    pub struct Motors {
        pub tim_a: Peri<'static, TIM4>,
        pub m1: Peri<'static, PB6>,
        pub m2: Peri<'static, PB7>,
        pub dma_a: Peri<'static, DMA1_CH6>,
        pub tim_b: Peri<'static, TIM3>,
        pub m3: Peri<'static, PB0>,
        pub m4: Peri<'static, PB1>,
        pub dma_b: Peri<'static, DMA1_CH2>,
    }

    pub struct Board {
        pub imu: Imu,
        pub link: Link,
        pub motors: Motors,
        pub led: Peri<'static, PC13>,
        pub iwdg: Peri<'static, IWDG>,
        pub flash: Peri<'static, FLASH>,
    }

    /// Takes the board's resources out of the HAL's peripherals.
    pub fn split(p: Peripherals) -> Board {
        Board {
            imu: Imu {
                spi: p.SPI1,
                sck: p.PA5,
                miso: p.PA6,
                mosi: p.PA7,
                cs: p.PA4,
                drdy: p.PC4,
                drdy_exti: p.EXTI4,
                tx_dma: p.DMA2_CH3,
                rx_dma: p.DMA2_CH0,
            },
            link: Link {
                uart: p.USART1,
                tx: p.PA9,
                rx: p.PA10,
                tx_dma: p.DMA2_CH7,
                rx_dma: p.DMA2_CH5,
            },
            motors: Motors {
                tim_a: p.TIM4,
                m1: p.PB6,
                m2: p.PB7,
                dma_a: p.DMA1_CH6,
                tim_b: p.TIM3,
                m3: p.PB0,
                m4: p.PB1,
                dma_b: p.DMA1_CH2,
            },
            led: p.PC13,
            iwdg: p.IWDG,
            flash: p.FLASH,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn det(r: &[[f32; 3]; 3]) -> f32 {
        r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
            - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0])
    }

    #[test]
    fn mounting_is_a_proper_rotation() {
        let r = &SENSOR_TO_BODY;
        assert_eq!(det(r), 1.0);
        for i in 0..3 {
            for j in 0..3 {
                let dot: f32 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
                assert_eq!(dot, if i == j { 1.0 } else { 0.0 });
            }
        }
    }

    /// CW90: the sensor's x axis points to the body's right (−y), its y axis forward (+x).
    #[test]
    fn cw90_mounting() {
        assert_eq!(to_body([1.0, 0.0, 0.0]), [0.0, -1.0, 0.0]);
        assert_eq!(to_body([0.0, 1.0, 0.0]), [1.0, 0.0, 0.0]);
        assert_eq!(to_body([0.0, 0.0, 9.8]), [0.0, 0.0, 9.8]);
    }

    #[test]
    fn motor_map_is_a_permutation() {
        let mut seen = [false; 4];
        for &o in &MOTOR_OUTPUT_OF_MIXER {
            assert!(!seen[o]);
            seen[o] = true;
        }
        assert_eq!(to_motor_outputs([1, 2, 3, 4]), [1, 2, 3, 4]);
    }
}
