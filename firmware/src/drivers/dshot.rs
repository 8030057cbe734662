//! Motor output encodings, as pure functions: DShot frames, the DMA burst buffer that plays them
//! out of a timer's compare registers, the throttle → DShot value map, and the standard PWM
//! fallback (1000–2000 µs pulses).
//!
//! # DShot
//!
//! A DShot frame is 16 bits, sent most significant bit first: an 11-bit value, a telemetry request
//! bit, and a 4-bit checksum over the 12 bits before it (`crc = (v ^ v >> 4 ^ v >> 8) & 0xF` with
//! `v = value << 1 | telemetry`). Value 0 is "motor stop" (disarmed), 1..=47 are commands and
//! 48..=2047 are the throttle range.
//!
//! Every bit lasts the same time (1.667 µs at DShot600, 600 kbit/s); the line is high for 3/8 of
//! the bit for a 0 and 3/4 of the bit for a 1 (625 ns and 1250 ns at DShot600). On the MCU a timer
//! runs in PWM mode with a period of one bit; on each update event a DMA burst writes the next
//! compare values of all the timer's motor channels at once (`TIMx_DMAR`), so one DMA stream per
//! timer drives all its motors in lockstep. [`burst`] lays that buffer out.
//!
//! The frame encoding is cross-checked in the tests against the `dshot-frame` crate.

/// How the motors are driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotorProtocol {
    /// DShot600: digital frames, 600 kbit/s, one timer DMA burst per frame.
    Dshot600,
    /// Standard ESC PWM fallback: 1000–2000 µs pulses at [`PWM_RATE_HZ`].
    Pwm,
}

/// DShot600 bit rate [bit/s].
pub const DSHOT600_BIT_RATE: u32 = 600_000;

/// Bits in one DShot frame.
pub const FRAME_BITS: usize = 16;

/// Rows of zeros after the 16 bits of a frame: the timer keeps the last compare value, so the
/// line stays low after the frame (and the compare preload delays each value by one bit).
pub const TRAILING_ROWS: usize = 2;

/// Update events (rows) in one burst: the 16 bits then [`TRAILING_ROWS`] low rows.
pub const BURST_ROWS: usize = FRAME_BITS + TRAILING_ROWS;

/// Value of the "motor stop" frame (disarmed).
pub const MOTOR_STOP: u16 = 0;

/// Lowest throttle value; 1..=47 are ESC commands (beep, direction, …), never sent here.
pub const THROTTLE_MIN: u16 = 48;

/// Highest throttle value (11 bits).
pub const THROTTLE_MAX: u16 = 2047;

/// The 4-bit DShot checksum of the 12 bits `value << 1 | telemetry`.
pub const fn checksum(data12: u16) -> u16 {
    (data12 ^ (data12 >> 4) ^ (data12 >> 8)) & 0x0F
}

/// The 16-bit frame for an 11-bit `value` (values above 2047 are clamped to 2047) and the
/// telemetry request bit.
pub const fn frame(value: u16, telemetry: bool) -> u16 {
    let value = if value > THROTTLE_MAX {
        THROTTLE_MAX
    } else {
        value
    };
    let data12 = (value << 1) | telemetry as u16;
    (data12 << 4) | checksum(data12)
}

/// DShot value for a throttle in `[0, 1]`: `0` (motor stop) when disarmed, else `48 + t · 1999`
/// rounded, so that throttle 0 is the lowest throttle value and 1 is 2047. NaN and values outside
/// `[0, 1]` are clamped (NaN → 0).
pub fn throttle_to_dshot(throttle: f32, armed: bool) -> u16 {
    if !armed {
        return MOTOR_STOP;
    }
    let t = clamp01(throttle);
    let span = (THROTTLE_MAX - THROTTLE_MIN) as f32;
    // t ∈ [0, 1] so the sum is in [48, 2047.5); `as` truncates after the +0.5 rounding.
    THROTTLE_MIN + (t * span + 0.5) as u16
}

fn clamp01(x: f32) -> f32 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}

/// The compare values of one DShot bit at a timer period of `period_ticks` (the timer's
/// auto-reload + 1, i.e. timer clock / bit rate).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitTiming {
    /// Timer ticks per bit.
    pub period_ticks: u16,
    /// High time of a 0 bit \[ticks\]: 3/8 of the bit, rounded.
    pub zero_high: u16,
    /// High time of a 1 bit \[ticks\]: 3/4 of the bit, rounded.
    pub one_high: u16,
}

impl BitTiming {
    /// Timing for a bit of `period_ticks` timer ticks.
    pub const fn from_period(period_ticks: u16) -> Self {
        let p = period_ticks as u32;
        Self {
            period_ticks,
            zero_high: ((3 * p + 4) / 8) as u16,
            one_high: ((3 * p + 2) / 4) as u16,
        }
    }

    /// Timing for `bit_rate` on a timer clocked at `timer_hz` without prescaler
    /// (e.g. 84 MHz / 600 kbit/s = 140 ticks). `None` if the period does not fit 16 bits or is
    /// too short to tell a 0 from a 1 (< 8 ticks).
    pub const fn for_bit_rate(timer_hz: u32, bit_rate: u32) -> Option<Self> {
        if bit_rate == 0 {
            return None;
        }
        let period = (timer_hz + bit_rate / 2) / bit_rate;
        if period < 8 || period > u16::MAX as u32 {
            return None;
        }
        Some(Self::from_period(period as u16))
    }

    /// High time of a 0 bit \[ns\] at a timer clock of `timer_hz`.
    pub fn zero_high_ns(&self, timer_hz: u32) -> f32 {
        self.zero_high as f32 * 1e9 / timer_hz as f32
    }

    /// High time of a 1 bit \[ns\] at a timer clock of `timer_hz`.
    pub fn one_high_ns(&self, timer_hz: u32) -> f32 {
        self.one_high as f32 * 1e9 / timer_hz as f32
    }

    /// Bit period \[ns\] at a timer clock of `timer_hz`.
    pub fn period_ns(&self, timer_hz: u32) -> f32 {
        self.period_ticks as f32 * 1e9 / timer_hz as f32
    }
}

/// Length of the burst buffer for `channels` consecutive timer channels.
pub const fn burst_len(channels: usize) -> usize {
    BURST_ROWS * channels
}

/// Fills `out` with the DMA burst that plays `frames` on `N` consecutive channels of one timer:
/// row `i` (one update event) holds the compare values of bit `15 − i` of every frame, in channel
/// order; then [`TRAILING_ROWS`] rows of 0. `out` must be `burst_len(N)` long (panics otherwise:
/// a wrong buffer size is a programming error caught by the first test run).
pub fn burst<const N: usize>(frames: &[u16; N], timing: &BitTiming, out: &mut [u16]) {
    assert_eq!(out.len(), burst_len(N), "DShot burst buffer length");
    for (row, chunk) in out.chunks_exact_mut(N).enumerate() {
        for (slot, &f) in chunk.iter_mut().zip(frames) {
            *slot = if row >= FRAME_BITS {
                0
            } else if f & (0x8000 >> row) != 0 {
                timing.one_high
            } else {
                timing.zero_high
            };
        }
    }
}

/// Decodes a burst buffer back into frames (by comparing each compare value with the middle of
/// the two high times). The inverse of [`burst`]; used by the tests and for self-checks.
pub fn decode_burst<const N: usize>(buf: &[u16], timing: &BitTiming) -> [u16; N] {
    let threshold = (timing.zero_high + timing.one_high) / 2;
    let mut frames = [0u16; N];
    for (row, chunk) in buf.chunks_exact(N).take(FRAME_BITS).enumerate() {
        for (f, &v) in frames.iter_mut().zip(chunk) {
            if v > threshold {
                *f |= 0x8000 >> row;
            }
        }
    }
    frames
}

/// Standard ESC PWM ("PWM fallback"): pulse width \[µs\] for a throttle in `[0, 1]`.
/// 1000 µs when disarmed (every ESC reads it as stop) and at zero throttle; 2000 µs at full.
pub fn throttle_to_pwm_us(throttle: f32, armed: bool) -> u16 {
    if !armed {
        return PWM_MIN_US;
    }
    PWM_MIN_US + (clamp01(throttle) * (PWM_MAX_US - PWM_MIN_US) as f32 + 0.5) as u16
}

/// Shortest standard ESC pulse (stop / zero throttle) \[µs\].
pub const PWM_MIN_US: u16 = 1000;
/// Longest standard ESC pulse (full throttle) \[µs\].
pub const PWM_MAX_US: u16 = 2000;
/// Frame rate of the PWM fallback \[Hz\]: 2.5 ms period, room for a 2 ms pulse.
pub const PWM_RATE_HZ: u32 = 400;

/// Timer compare value for a pulse of `pulse_us` when one PWM period of `period_us` spans
/// `max_duty` compare ticks (the timer's auto-reload + 1), rounded; never above `max_duty`.
pub fn pulse_to_compare(pulse_us: u16, period_us: u32, max_duty: u32) -> u32 {
    if period_us == 0 {
        return 0;
    }
    let c = (pulse_us as u64 * max_duty as u64 + period_us as u64 / 2) / period_us as u64;
    c.min(max_duty as u64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use dshot_frame::{Command, NormalFrame};

    /// Worked examples: value 1046, no telemetry, is 0x8 2C 6 → 0b1000_0010_1100_0110 (the
    /// common DShot write-up example: 12 data bits 0x82C, crc 0x8^0x2^0xC = 0x6).
    #[test]
    fn known_frames() {
        assert_eq!(frame(1046, false), 0b1000_0010_1100_0110);
        assert_eq!(checksum(0x82C), 0x6);
        // Motor stop: all zero, checksum zero.
        assert_eq!(frame(0, false), 0x0000);
        // Lowest throttle 48 = 0b000_0011_0000 → data12 0x060, crc 0x0^0x6^0x0 = 6.
        assert_eq!(frame(48, false), 0x0606);
        // Full throttle 2047 with telemetry: data12 0xFFF, crc 0xF^0xF^0xF = 0xF.
        assert_eq!(frame(2047, true), 0xFFFF);
        // Over range clamps.
        assert_eq!(frame(5000, false), frame(2047, false));
    }

    /// Every value and telemetry bit agrees with the independent `dshot-frame` crate.
    #[test]
    fn matches_dshot_frame_crate() {
        for speed in 0..2000u16 {
            for telemetry in [false, true] {
                let theirs = NormalFrame::new(speed, telemetry).unwrap().inner();
                assert_eq!(frame(speed + 48, telemetry), theirs, "speed {speed}");
            }
        }
        assert_eq!(
            frame(MOTOR_STOP, false),
            NormalFrame::command(Command::MotorStop, false).inner()
        );
    }

    #[test]
    fn throttle_mapping() {
        assert_eq!(throttle_to_dshot(0.7, false), 0);
        assert_eq!(throttle_to_dshot(0.0, true), 48);
        assert_eq!(throttle_to_dshot(1.0, true), 2047);
        assert_eq!(throttle_to_dshot(0.5, true), 48 + 1000); // 999.5 rounds up
        assert_eq!(throttle_to_dshot(-3.0, true), 48);
        assert_eq!(throttle_to_dshot(7.0, true), 2047);
        assert_eq!(throttle_to_dshot(f32::NAN, true), 48);
        // Monotone over the whole range.
        let mut last = 0;
        for i in 0..=10_000 {
            let v = throttle_to_dshot(i as f32 / 10_000.0, true);
            assert!(v >= last && (48..=2047).contains(&v));
            last = v;
        }
    }

    /// DShot600 on an APB1 timer of the F405 (84 MHz, see `src/bin/stm32f405/clocks.rs`): 140 ticks per bit,
    /// 0-bit high 53 ticks (631 ns, spec 625 ns), 1-bit high 105 ticks (1250 ns).
    #[test]
    fn dshot600_timing_at_84_mhz() {
        let t = BitTiming::for_bit_rate(84_000_000, DSHOT600_BIT_RATE).unwrap();
        assert_eq!(
            t,
            BitTiming {
                period_ticks: 140,
                zero_high: 53,
                one_high: 105
            }
        );
        assert!((t.period_ns(84_000_000) - 1666.67).abs() < 0.01);
        assert!((t.zero_high_ns(84_000_000) - 625.0).abs() < 10.0);
        assert!((t.one_high_ns(84_000_000) - 1250.0).abs() < 1.0);
        // On an APB2 timer (168 MHz): 280 ticks.
        let t2 = BitTiming::for_bit_rate(168_000_000, DSHOT600_BIT_RATE).unwrap();
        assert_eq!(
            (t2.period_ticks, t2.zero_high, t2.one_high),
            (280, 105, 210)
        );
        assert_eq!(BitTiming::for_bit_rate(1_000_000, DSHOT600_BIT_RATE), None);
        assert_eq!(BitTiming::for_bit_rate(84_000_000, 0), None);
    }

    #[test]
    fn burst_layout_two_channels() {
        let t = BitTiming::from_period(140);
        let frames = [frame(1046, false), frame(48, false)];
        let mut buf = [0xAAAAu16; burst_len(2)];
        burst(&frames, &t, &mut buf);
        // Row 0 = MSB of each frame: 1046 frame starts with 1, 48 frame with 0.
        assert_eq!(&buf[0..2], &[105, 53]);
        // Row 15 = LSB: 0x..6 → 0; 0x0606 → 0.
        assert_eq!(&buf[30..32], &[53, 53]);
        // Row 13 = bit 2: 0x6 has it; so does 0x0606.
        assert_eq!(&buf[26..28], &[105, 105]);
        // Trailing rows hold the line low.
        assert_eq!(&buf[32..36], &[0, 0, 0, 0]);
        assert_eq!(decode_burst::<2>(&buf, &t), frames);
        // DMA memory bursts of 4 half-words need a multiple of 4 items.
        assert_eq!(buf.len() % 4, 0);
        assert_eq!(burst_len(4) % 4, 0);
    }

    #[test]
    fn burst_round_trips_every_value() {
        let t = BitTiming::for_bit_rate(84_000_000, DSHOT600_BIT_RATE).unwrap();
        let mut buf = [0u16; burst_len(4)];
        for v in (0..=2047u16).step_by(7) {
            let frames = [frame(v, false), frame(2047 - v, true), frame(48, false), 0];
            burst(&frames, &t, &mut buf);
            assert_eq!(decode_burst::<4>(&buf, &t), frames);
        }
    }

    #[test]
    fn pwm_fallback() {
        assert_eq!(throttle_to_pwm_us(0.9, false), 1000);
        assert_eq!(throttle_to_pwm_us(0.0, true), 1000);
        assert_eq!(throttle_to_pwm_us(0.25, true), 1250);
        assert_eq!(throttle_to_pwm_us(1.0, true), 2000);
        assert_eq!(throttle_to_pwm_us(f32::NAN, true), 1000);
        assert_eq!(throttle_to_pwm_us(2.0, true), 2000);
        // 400 Hz → 2500 µs period. At 84 MHz with prescaler 4: 52500 ticks per period.
        assert_eq!(pulse_to_compare(1000, 2500, 52_500), 21_000);
        assert_eq!(pulse_to_compare(2000, 2500, 52_500), 42_000);
        assert_eq!(pulse_to_compare(1500, 2500, 52_500), 31_500);
        assert_eq!(pulse_to_compare(3000, 2500, 52_500), 52_500);
        assert_eq!(pulse_to_compare(1000, 0, 52_500), 0);
    }
}
