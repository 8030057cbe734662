//! Motor output on the MCU: DShot600 through the two motor timers' update-DMA bursts, or the
//! standard PWM fallback, per `pins::MOTOR_PROTOCOL`. The encodings are the host-tested pure
//! functions of `firmware::drivers::dshot`; this module only moves their results into the
//! timers.

use embassy_futures::join::join;
use embassy_stm32::time::Hertz;
use embassy_stm32::timer::simple_pwm::SimplePwm;
use embassy_stm32::timer::Channel;
use embassy_stm32::Peri;
use firmware::drivers::dshot::{self, BitTiming, MotorProtocol};
use firmware::pipeline::MotorOutput;

use crate::pins::{self, hw};

const BURST: usize = dshot::burst_len(2);

/// What one write puts on the four outputs (board order M1..M4).
#[derive(Clone, Copy)]
pub enum Frames {
    /// DShot frames.
    Dshot([u16; 4]),
    /// PWM compare values.
    Pwm([u32; 4]),
}

enum Mode {
    Dshot(BitTiming),
    Pwm { max_duty_a: u32, max_duty_b: u32 },
}

/// The motor outputs.
pub struct Motors {
    a: SimplePwm<'static, hw::MotorTimerA>,
    b: SimplePwm<'static, hw::MotorTimerB>,
    dma_a: Peri<'static, hw::MotorDmaA>,
    dma_b: Peri<'static, hw::MotorDmaB>,
    mode: Mode,
    // DMA sources: they live in the control task's (static) storage, in SRAM.
    buf_a: [u16; BURST],
    buf_b: [u16; BURST],
}

fn channels(first: Channel, last: Channel) -> [Channel; 2] {
    [first, last]
}

impl Motors {
    /// Sets both timers up for `protocol`, all outputs at "stop" (DShot: line low until the
    /// first frame; PWM: 1000 µs).
    pub fn new(m: hw::Motors, protocol: MotorProtocol) -> Self {
        let frequency = match protocol {
            MotorProtocol::Dshot600 => Hertz(dshot::DSHOT600_BIT_RATE),
            MotorProtocol::Pwm => Hertz(dshot::PWM_RATE_HZ),
        };
        let (mut a, mut b, dma_a, dma_b) = hw::motor_timers(m, frequency);
        let mode = match protocol {
            MotorProtocol::Dshot600 => {
                let period = a.max_duty_cycle();
                let timing = BitTiming::from_period(period as u16);
                defmt::info!(
                    "motors: DShot600, {=u16} timer ticks per bit ({=f32} ns), 0: {=u16} ticks, \
                     1: {=u16} ticks",
                    timing.period_ticks,
                    timing.period_ns(pins::MOTOR_TIMER_HZ),
                    timing.zero_high,
                    timing.one_high
                );
                if b.max_duty_cycle() != period {
                    defmt::warn!("motors: the two motor timers run at different periods");
                }
                Mode::Dshot(timing)
            }
            MotorProtocol::Pwm => {
                defmt::info!(
                    "motors: PWM {=u32} Hz, {=u16}..{=u16} us",
                    dshot::PWM_RATE_HZ,
                    dshot::PWM_MIN_US,
                    dshot::PWM_MAX_US
                );
                Mode::Pwm {
                    max_duty_a: a.max_duty_cycle(),
                    max_duty_b: b.max_duty_cycle(),
                }
            }
        };
        for ch in channels(hw::MOTOR_A_CHANNELS.0, hw::MOTOR_A_CHANNELS.1) {
            let mut c = a.channel(ch);
            c.set_duty_cycle(0);
            c.enable();
        }
        for ch in channels(hw::MOTOR_B_CHANNELS.0, hw::MOTOR_B_CHANNELS.1) {
            let mut c = b.channel(ch);
            c.set_duty_cycle(0);
            c.enable();
        }
        Self {
            a,
            b,
            dma_a,
            dma_b,
            mode,
            buf_a: [0; BURST],
            buf_b: [0; BURST],
        }
    }

    /// The frames for `out` (mixer order → board order; zero when disarmed). Pure and quick: the
    /// control task calls it inside its measured step.
    pub fn prepare(&self, out: &MotorOutput) -> Frames {
        let throttle = pins::to_motor_outputs(out.throttle);
        match self.mode {
            Mode::Dshot(_) => Frames::Dshot(
                throttle.map(|t| dshot::frame(dshot::throttle_to_dshot(t, out.armed), false)),
            ),
            Mode::Pwm {
                max_duty_a,
                max_duty_b,
            } => {
                let period_us = 1_000_000 / dshot::PWM_RATE_HZ;
                let mut c = [0u32; 4];
                for (i, (slot, t)) in c.iter_mut().zip(throttle).enumerate() {
                    let max = if i < 2 { max_duty_a } else { max_duty_b };
                    *slot = dshot::pulse_to_compare(
                        dshot::throttle_to_pwm_us(t, out.armed),
                        period_us,
                        max,
                    );
                }
                Frames::Pwm(c)
            }
        }
    }

    /// Puts `frames` on the outputs. DShot: both timers' bursts run together (~30 µs); PWM: the
    /// compare registers are written and take effect at the next period.
    pub async fn write(&mut self, frames: Frames) {
        let (a_first, a_last) = hw::MOTOR_A_CHANNELS;
        let (b_first, b_last) = hw::MOTOR_B_CHANNELS;
        match (frames, &self.mode) {
            (Frames::Dshot(f), Mode::Dshot(timing)) => {
                dshot::burst(&[f[0], f[1]], timing, &mut self.buf_a);
                dshot::burst(&[f[2], f[3]], timing, &mut self.buf_b);
                join(
                    self.a.waveform_up_multi_channel(
                        self.dma_a.reborrow(),
                        hw::Irqs,
                        a_first,
                        a_last,
                        &self.buf_a,
                    ),
                    self.b.waveform_up_multi_channel(
                        self.dma_b.reborrow(),
                        hw::Irqs,
                        b_first,
                        b_last,
                        &self.buf_b,
                    ),
                )
                .await;
            }
            (Frames::Pwm(c), Mode::Pwm { .. }) => {
                self.a.channel(a_first).set_duty_cycle(c[0]);
                self.a.channel(a_last).set_duty_cycle(c[1]);
                self.b.channel(b_first).set_duty_cycle(c[2]);
                self.b.channel(b_last).set_duty_cycle(c[3]);
            }
            // `prepare` builds frames for the mode it runs in; nothing else reaches here.
            _ => defmt::error!("motors: frames of the other protocol ignored"),
        }
    }

    /// All motors to "stop".
    pub async fn stop(&mut self) {
        let frames = self.prepare(&MotorOutput {
            throttle: [0.0; 4],
            armed: false,
        });
        self.write(frames).await;
    }
}
