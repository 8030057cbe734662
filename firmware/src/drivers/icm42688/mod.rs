//! TDK InvenSense ICM-42688-P 6-axis IMU over SPI, generic over
//! [`embedded_hal_async::spi::SpiDevice`] (the device owns chip select) and
//! [`embedded_hal_async::delay::DelayNs`].
//!
//! What it does: bank 0, soft reset, `WHO_AM_I` check, adaptive full-scale range (AFSR) off,
//! INT1 as a push-pull, active-high, *latched* data-ready output that clears when the sensor data
//! registers are read, gyro and accel ranges and output data rate (default ±2000 °/s, ±16 g,
//! 1 kHz), both sensors on in low-noise mode; then one 14-byte burst read per sample
//! (temperature, accel XYZ, gyro XYZ, big-endian, bank 0 registers 0x1D..=0x2A), converted to SI
//! units **in the sensor frame** (the board's pin table, `src/bin/stm32f405/pins.rs`, rotates it into the body frame). The gyro bias is
//! estimated downstream, by the pipeline's estimator
//! (`estimator.rs`), from the first still samples after boot.
//!
//! Register addresses and bit fields: ICM-42688-P datasheet (DS-000347), section 13–14 (user bank
//! 0 register map). SPI: mode 0 or 3, ≤ 24 MHz, the first byte is the register address with bit 7
//! set for a read; consecutive registers auto-increment.
//!
//! Why not the `icm426xx` crate: it reads through the FIFO with fixed full-scale ranges, needs a
//! `bilge` proc-macro stack, and its `async`/blocking variants are selected by crate features;
//! the flight loop only needs "configure, wait for data ready, read 14 bytes", which this file does
//! in a page, with every SPI transaction pinned by the tests below.

use embedded_hal_async::delay::DelayNs;
use embedded_hal_async::spi::{Operation, SpiDevice};

/// Bank 0 register addresses used here.
pub mod reg {
    /// `DEVICE_CONFIG`: bit 0 `SOFT_RESET_CONFIG`.
    pub const DEVICE_CONFIG: u8 = 0x11;
    /// `INT_CONFIG`: INT1 mode (bit 2, 1 = latched), drive (bit 1, 1 = push-pull), polarity
    /// (bit 0, 1 = active high).
    pub const INT_CONFIG: u8 = 0x14;
    /// `TEMP_DATA1`: first of the 14 data bytes (temperature, accel XYZ, gyro XYZ).
    pub const TEMP_DATA1: u8 = 0x1D;
    /// `INT_STATUS`: bit 3 `DATA_RDY_INT`, bit 4 `RESET_DONE_INT`.
    pub const INT_STATUS: u8 = 0x2D;
    /// `INTF_CONFIG1`: bits 7:6 select the adaptive full-scale range (AFSR) mode, not in the
    /// public register description; bits 1:0 `CLKSEL`.
    pub const INTF_CONFIG1: u8 = 0x4D;
    /// `PWR_MGMT0`: bits 3:2 `GYRO_MODE`, bits 1:0 `ACCEL_MODE` (0b11 = low noise).
    pub const PWR_MGMT0: u8 = 0x4E;
    /// `GYRO_CONFIG0`: bits 7:5 `GYRO_FS_SEL`, bits 3:0 `GYRO_ODR`.
    pub const GYRO_CONFIG0: u8 = 0x4F;
    /// `ACCEL_CONFIG0`: bits 7:5 `ACCEL_FS_SEL`, bits 3:0 `ACCEL_ODR`.
    pub const ACCEL_CONFIG0: u8 = 0x50;
    /// `INT_CONFIG0`: bits 5:4 `UI_DRDY_INT_CLEAR` (0b10 = clear on sensor register read).
    pub const INT_CONFIG0: u8 = 0x63;
    /// `INT_CONFIG1`: bit 4 `INT_ASYNC_RESET` (the datasheet asks for 0), bit 5
    /// `INT_TDEASSERT_DISABLE`, bit 6 `INT_TPULSE_DURATION`.
    pub const INT_CONFIG1: u8 = 0x64;
    /// `INT_SOURCE0`: bit 3 `UI_DRDY_INT1_EN`.
    pub const INT_SOURCE0: u8 = 0x65;
    /// `WHO_AM_I`: 0x47 for the ICM-42688-P.
    pub const WHO_AM_I: u8 = 0x75;
    /// `REG_BANK_SEL`.
    pub const REG_BANK_SEL: u8 = 0x76;
}

/// `WHO_AM_I` of the ICM-42688-P.
pub const WHO_AM_I_VALUE: u8 = 0x47;
/// Read flag of the SPI address byte.
const READ: u8 = 0x80;
/// Bytes of one sample burst: temperature, accel XYZ, gyro XYZ, 2 bytes each.
pub const SAMPLE_BYTES: usize = 14;
/// Standard gravity [m/s²] for the accel scale.
pub const STANDARD_GRAVITY: f32 = 9.806_65;

/// Output data rate of gyro and accel (register code in the doc of each variant).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Odr {
    /// 8 kHz (0b0011).
    Hz8000,
    /// 4 kHz (0b0100).
    Hz4000,
    /// 2 kHz (0b0101).
    Hz2000,
    /// 1 kHz (0b0110).
    Hz1000,
}

impl Odr {
    /// `GYRO_ODR` / `ACCEL_ODR` code.
    pub const fn code(self) -> u8 {
        match self {
            Odr::Hz8000 => 0b0011,
            Odr::Hz4000 => 0b0100,
            Odr::Hz2000 => 0b0101,
            Odr::Hz1000 => 0b0110,
        }
    }

    /// Rate \[Hz\].
    pub const fn hz(self) -> u32 {
        match self {
            Odr::Hz8000 => 8000,
            Odr::Hz4000 => 4000,
            Odr::Hz2000 => 2000,
            Odr::Hz1000 => 1000,
        }
    }
}

/// Gyro full-scale range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GyroRange {
    /// ±2000 °/s (code 0), 16.4 LSB/(°/s).
    Dps2000,
    /// ±1000 °/s (code 1), 32.8 LSB/(°/s).
    Dps1000,
    /// ±500 °/s (code 2), 65.5 LSB/(°/s).
    Dps500,
    /// ±250 °/s (code 3), 131 LSB/(°/s).
    Dps250,
}

impl GyroRange {
    /// `GYRO_FS_SEL` code.
    pub const fn code(self) -> u8 {
        match self {
            GyroRange::Dps2000 => 0,
            GyroRange::Dps1000 => 1,
            GyroRange::Dps500 => 2,
            GyroRange::Dps250 => 3,
        }
    }

    /// Full scale [°/s].
    pub const fn full_scale_dps(self) -> f32 {
        match self {
            GyroRange::Dps2000 => 2000.0,
            GyroRange::Dps1000 => 1000.0,
            GyroRange::Dps500 => 500.0,
            GyroRange::Dps250 => 250.0,
        }
    }

    /// Scale [rad/s per LSB]: full scale / 32768 (the datasheet's 16.4 LSB/(°/s) at ±2000 °/s is
    /// this value rounded).
    pub fn rad_s_per_lsb(self) -> f32 {
        self.full_scale_dps() / 32768.0 * core::f32::consts::PI / 180.0
    }
}

/// Accelerometer full-scale range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelRange {
    /// ±16 g (code 0), 2048 LSB/g.
    G16,
    /// ±8 g (code 1), 4096 LSB/g.
    G8,
    /// ±4 g (code 2), 8192 LSB/g.
    G4,
    /// ±2 g (code 3), 16384 LSB/g.
    G2,
}

impl AccelRange {
    /// `ACCEL_FS_SEL` code.
    pub const fn code(self) -> u8 {
        match self {
            AccelRange::G16 => 0,
            AccelRange::G8 => 1,
            AccelRange::G4 => 2,
            AccelRange::G2 => 3,
        }
    }

    /// LSB per g.
    pub const fn lsb_per_g(self) -> f32 {
        match self {
            AccelRange::G16 => 2048.0,
            AccelRange::G8 => 4096.0,
            AccelRange::G4 => 8192.0,
            AccelRange::G2 => 16384.0,
        }
    }

    /// Scale [m/s² per LSB].
    pub fn m_s2_per_lsb(self) -> f32 {
        STANDARD_GRAVITY / self.lsb_per_g()
    }
}

/// Driver configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Gyro and accel output data rate (the data-ready rate).
    pub odr: Odr,
    /// Gyro range.
    pub gyro_range: GyroRange,
    /// Accel range.
    pub accel_range: AccelRange,
}

impl Default for Config {
    /// 1 kHz, ±2000 °/s, ±16 g: the ranges a multirotor needs through a crash or a flip.
    fn default() -> Self {
        Self {
            odr: Odr::Hz1000,
            gyro_range: GyroRange::Dps2000,
            accel_range: AccelRange::G16,
        }
    }
}

/// Driver errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error<E> {
    /// The SPI device failed.
    Spi(E),
    /// `WHO_AM_I` read this instead of 0x47: wrong chip, wiring or SPI mode.
    WrongDevice(u8),
    /// A data register held -32768, the chip's "no data" value (sensor off or not ready).
    NoData,
}

/// One sample in the sensor frame, raw counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RawSample {
    /// Temperature counts.
    pub temperature: i16,
    /// Accel X, Y, Z counts.
    pub accel: [i16; 3],
    /// Gyro X, Y, Z counts.
    pub gyro: [i16; 3],
}

impl RawSample {
    /// Parses the 14-byte burst from `TEMP_DATA1` (big-endian, the reset default).
    pub fn from_bytes(b: &[u8; SAMPLE_BYTES]) -> Self {
        let w = |i: usize| i16::from_be_bytes([b[2 * i], b[2 * i + 1]]);
        Self {
            temperature: w(0),
            accel: [w(1), w(2), w(3)],
            gyro: [w(4), w(5), w(6)],
        }
    }
}

/// One sample in the sensor frame, SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Angular rate [rad/s], sensor axes.
    pub gyro_rad_s: [f32; 3],
    /// Specific force [m/s²], sensor axes (+g on the axis pointing up when still).
    pub accel_m_s2: [f32; 3],
    /// Die temperature [°C].
    pub temperature_c: f32,
}

/// Converts raw counts at the given ranges; temperature is `counts / 132.48 + 25` °C.
pub fn convert(raw: &RawSample, gyro: GyroRange, accel: AccelRange) -> Sample {
    let g = gyro.rad_s_per_lsb();
    let a = accel.m_s2_per_lsb();
    Sample {
        gyro_rad_s: raw.gyro.map(|c| c as f32 * g),
        accel_m_s2: raw.accel.map(|c| c as f32 * a),
        temperature_c: raw.temperature as f32 / 132.48 + 25.0,
    }
}

/// The register writes of [`Icm42688::init`] after the soft reset, in order, for `config`.
pub fn init_writes(config: &Config) -> [(u8, u8); 7] {
    [
        // INT1: latched, push-pull, active high.
        (reg::INT_CONFIG, 0b0000_0111),
        // Data-ready interrupt clears on a sensor data register read.
        (reg::INT_CONFIG0, 0b0010_0000),
        // INT_ASYNC_RESET = 0 as the datasheet requires; 100 µs pulse and de-assert (unused when
        // latched).
        (reg::INT_CONFIG1, 0x00),
        // Data ready routed to INT1 (and nothing else).
        (reg::INT_SOURCE0, 0b0000_1000),
        (
            reg::GYRO_CONFIG0,
            (config.gyro_range.code() << 5) | config.odr.code(),
        ),
        (
            reg::ACCEL_CONFIG0,
            (config.accel_range.code() << 5) | config.odr.code(),
        ),
        // Gyro and accel in low-noise mode, temperature sensor on.
        (reg::PWR_MGMT0, 0b0000_1111),
    ]
}

/// `INTF_CONFIG1` with the AFSR bits (7:6) set to 0b01 (disabled), the other bits kept.
pub const fn afsr_disabled(intf_config1: u8) -> u8 {
    (intf_config1 & !0xC0) | 0x40
}

/// Wait after the soft reset \[ms\] (datasheet: 1 ms).
pub const RESET_WAIT_MS: u32 = 1;
/// Wait after turning the sensors on \[ms\]: the gyro needs 45 ms to start (datasheet table 1);
/// no register write may follow `PWR_MGMT0` within 200 µs.
pub const STARTUP_WAIT_MS: u32 = 50;

/// ICM-42688-P driver.
pub struct Icm42688<SPI> {
    spi: SPI,
    config: Config,
}

impl<SPI: SpiDevice> Icm42688<SPI> {
    /// Wraps the SPI device; nothing is sent until [`Self::init`].
    pub fn new(spi: SPI, config: Config) -> Self {
        Self { spi, config }
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Gives the SPI device back.
    pub fn release(self) -> SPI {
        self.spi
    }

    /// Writes one register.
    pub async fn write_register(
        &mut self,
        register: u8,
        value: u8,
    ) -> Result<(), Error<SPI::Error>> {
        self.spi
            .write(&[register & !READ, value])
            .await
            .map_err(Error::Spi)
    }

    /// Reads one register.
    pub async fn read_register(&mut self, register: u8) -> Result<u8, Error<SPI::Error>> {
        let mut value = [0u8];
        self.spi
            .transaction(&mut [
                Operation::Write(&[register | READ]),
                Operation::Read(&mut value),
            ])
            .await
            .map_err(Error::Spi)?;
        Ok(value[0])
    }

    /// Soft reset, identity check, configuration (see the module doc); returns once the gyro has
    /// started. Errors: [`Error::WrongDevice`] if `WHO_AM_I` is not 0x47, or the SPI error.
    pub async fn init(&mut self, delay: &mut impl DelayNs) -> Result<(), Error<SPI::Error>> {
        // Bank 0 first (REG_BANK_SEL is in every bank): a previous firmware may have left another
        // bank selected, and DEVICE_CONFIG is a bank 0 register.
        self.write_register(reg::REG_BANK_SEL, 0x00).await?;
        self.write_register(reg::DEVICE_CONFIG, 0x01).await?;
        delay.delay_ms(RESET_WAIT_MS).await;
        let id = self.read_register(reg::WHO_AM_I).await?;
        if id != WHO_AM_I_VALUE {
            return Err(Error::WrongDevice(id));
        }
        // AFSR off: the ICM-42688-P's adaptive full-scale range switches ranges on its own and
        // stalls the gyro output around the switch (a known issue; Betaflight's ICM-426xx driver
        // disables it the same way). Read-modify-write keeps the clock selection.
        let intf1 = self.read_register(reg::INTF_CONFIG1).await?;
        self.write_register(reg::INTF_CONFIG1, afsr_disabled(intf1))
            .await?;
        for (register, value) in init_writes(&self.config) {
            self.write_register(register, value).await?;
        }
        delay.delay_ms(STARTUP_WAIT_MS).await;
        Ok(())
    }

    /// Reads the 14 data bytes in one transaction (this also clears the latched data-ready).
    pub async fn read_raw(&mut self) -> Result<RawSample, Error<SPI::Error>> {
        let mut buf = [0u8; SAMPLE_BYTES];
        self.spi
            .transaction(&mut [
                Operation::Write(&[reg::TEMP_DATA1 | READ]),
                Operation::Read(&mut buf),
            ])
            .await
            .map_err(Error::Spi)?;
        let raw = RawSample::from_bytes(&buf);
        if raw.accel.contains(&i16::MIN) || raw.gyro.contains(&i16::MIN) {
            return Err(Error::NoData);
        }
        Ok(raw)
    }

    /// Reads one sample in SI units, sensor frame.
    pub async fn read(&mut self) -> Result<Sample, Error<SPI::Error>> {
        let raw = self.read_raw().await?;
        Ok(convert(
            &raw,
            self.config.gyro_range,
            self.config.accel_range,
        ))
    }
}

#[cfg(test)]
mod tests;
