use super::*;
use embassy_futures::block_on;
use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as DelayTx};
use embedded_hal_mock::eh1::spi::{Mock as SpiMock, Transaction as SpiTx};

fn write(register: u8, value: u8) -> [SpiTx<u8>; 3] {
    [
        SpiTx::transaction_start(),
        SpiTx::write_vec(vec![register, value]),
        SpiTx::transaction_end(),
    ]
}

fn read(register: u8, response: Vec<u8>) -> [SpiTx<u8>; 4] {
    [
        SpiTx::transaction_start(),
        SpiTx::write_vec(vec![register | 0x80]),
        SpiTx::read_vec(response),
        SpiTx::transaction_end(),
    ]
}

/// The whole init sequence, byte for byte, with the default configuration.
#[test]
fn init_sends_the_expected_transactions() {
    let mut expected = Vec::new();
    expected.extend(write(0x76, 0x00)); // bank 0
    expected.extend(write(0x11, 0x01)); // soft reset
    expected.extend(read(0x75, vec![0x47])); // WHO_AM_I
    expected.extend(read(0x4D, vec![0x91])); // INTF_CONFIG1 (reset value)
    expected.extend(write(0x4D, 0x51)); // AFSR disabled, CLKSEL kept
    expected.extend(write(0x14, 0x07)); // INT1 latched, push-pull, active high
    expected.extend(write(0x63, 0x20)); // DRDY clears on data read
    expected.extend(write(0x64, 0x00)); // INT_ASYNC_RESET = 0
    expected.extend(write(0x65, 0x08)); // DRDY → INT1
    expected.extend(write(0x4F, 0x06)); // ±2000 dps, 1 kHz
    expected.extend(write(0x50, 0x06)); // ±16 g, 1 kHz
    expected.extend(write(0x4E, 0x0F)); // gyro + accel low noise
    let mut spi = SpiMock::new(&expected);
    let mut delay = CheckedDelay::new(&[
        DelayTx::async_delay_ms(RESET_WAIT_MS),
        DelayTx::async_delay_ms(STARTUP_WAIT_MS),
    ]);
    let mut imu = Icm42688::new(spi.clone(), Config::default());
    block_on(imu.init(&mut delay)).unwrap();
    spi.done();
    delay.done();
}

#[test]
fn init_codes_follow_the_config() {
    let c = Config {
        odr: Odr::Hz2000,
        gyro_range: GyroRange::Dps500,
        accel_range: AccelRange::G8,
    };
    let w = init_writes(&c);
    assert!(w.contains(&(0x4F, (2 << 5) | 0b0101)));
    assert!(w.contains(&(0x50, (1 << 5) | 0b0101)));
    assert_eq!(w.last(), Some(&(0x4E, 0x0F)));
}

#[test]
fn init_refuses_another_chip() {
    let mut expected = Vec::new();
    expected.extend(write(0x76, 0x00));
    expected.extend(write(0x11, 0x01));
    expected.extend(read(0x75, vec![0x98])); // e.g. an MPU-6000 answer
    let mut spi = SpiMock::new(&expected);
    let mut delay = CheckedDelay::new(&[DelayTx::async_delay_ms(RESET_WAIT_MS)]);
    let mut imu = Icm42688::new(spi.clone(), Config::default());
    assert_eq!(
        block_on(imu.init(&mut delay)),
        Err(Error::WrongDevice(0x98))
    );
    spi.done();
    delay.done();
}

/// One 14-byte burst from 0x1D: temperature 0, accel (0, 0, +1 g = 2048 counts),
/// gyro (+16.4 counts·10 ≈ 10 °/s on x, −164 on y ≈ −10 °/s, 0).
#[test]
fn reads_and_converts_a_sample() {
    let bytes = vec![
        0x00, 0x00, // temp 0 → 25 °C
        0x00, 0x00, // ax
        0x00, 0x00, // ay
        0x08, 0x00, // az = 2048
        0x00, 0xA4, // gx = 164
        0xFF, 0x5C, // gy = −164
        0x00, 0x00, // gz
    ];
    let mut spi = SpiMock::new(&read(0x1D, bytes));
    let mut imu = Icm42688::new(spi.clone(), Config::default());
    let s = block_on(imu.read()).unwrap();
    spi.done();
    assert!((s.accel_m_s2[2] - STANDARD_GRAVITY).abs() < 1e-5);
    assert_eq!(s.accel_m_s2[0], 0.0);
    let ten_dps = 10.0f32.to_radians();
    // 164 counts at 2000/32768 °/s per count = 10.0098 °/s.
    assert!((s.gyro_rad_s[0] - ten_dps).abs() < 2e-4, "{:?}", s);
    assert!((s.gyro_rad_s[1] + ten_dps).abs() < 2e-4);
    assert_eq!(s.gyro_rad_s[2], 0.0);
    assert!((s.temperature_c - 25.0).abs() < 1e-6);
}

#[test]
fn no_data_marker_is_an_error() {
    let mut bytes = vec![0u8; 14];
    bytes[8] = 0x80; // gx = -32768
    let mut spi = SpiMock::new(&read(0x1D, bytes));
    let mut imu = Icm42688::new(spi.clone(), Config::default());
    assert_eq!(block_on(imu.read_raw()), Err(Error::NoData));
    spi.done();
}

#[test]
fn scales() {
    // Datasheet sensitivities: 16.4 LSB/(°/s) at ±2000, 2048 LSB/g at ±16 g.
    let lsb_per_dps = 1.0 / GyroRange::Dps2000.rad_s_per_lsb().to_degrees();
    assert!((lsb_per_dps - 16.384).abs() < 1e-3);
    assert!((1.0 / GyroRange::Dps250.rad_s_per_lsb().to_degrees() - 131.072).abs() < 1e-2);
    assert!((AccelRange::G16.m_s2_per_lsb() * 2048.0 - STANDARD_GRAVITY).abs() < 1e-6);
    assert_eq!(AccelRange::G2.lsb_per_g(), 16384.0);
    let raw = RawSample {
        temperature: 1325, // ≈ +10 °C
        accel: [-2048, 0, 0],
        gyro: [32767, 0, 0],
    };
    let s = convert(&raw, GyroRange::Dps2000, AccelRange::G16);
    assert!((s.temperature_c - 35.0).abs() < 0.01);
    assert!((s.accel_m_s2[0] + STANDARD_GRAVITY).abs() < 1e-5);
    assert!((s.gyro_rad_s[0].to_degrees() - 1999.94).abs() < 0.01);
}
