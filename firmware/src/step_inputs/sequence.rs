//! The input generator of the bench sequence: per tick, the IMU samples along the scripted
//! trajectory (with the SIL IMU model's biases and a deterministic noise), the motion-capture
//! pose frame (with its latency), and on the arming tick the ground station's commands.

use mavlink::dialects::common::{MavCmd, ATT_POS_MOCAP_DATA, COMMAND_LONG_DATA};
use mavlink::{MAVLinkV2MessageRaw, MavHeader, MessageData};
use nalgebra::Vector3;

use super::scenario::{
    ACCEL_BIAS, ACCEL_NOISE, GYRO_BIAS, GYRO_NOISE, POSE_LATENCY_US, POSE_NOISE,
};
use super::truth::truth;
use super::{Phase, StepInputs, ARM_TICK, IMU_PER_TICK, LINK_CAPACITY, TICK_US, TOTAL_TICKS};
use crate::frames;
use crate::pipeline::ImuSample;

/// Ground station ids.
const GCS_SYSTEM: u8 = 255;
const GCS_COMPONENT: u8 = 190;

/// Xorshift32 noise in `[−1, 1)` (integer arithmetic and an exact conversion: deterministic).
#[derive(Clone, Copy, Debug)]
struct Noise(u32);

impl Noise {
    fn next(&mut self) -> f32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        // 24 random bits, exactly representable: k · 2⁻²³ − 1 ∈ [−1, 1).
        (x >> 8) as f32 * (1.0 / 8_388_608.0) - 1.0
    }

    fn vector(&mut self, half_width: f32) -> Vector3<f32> {
        let x = self.next();
        let y = self.next();
        let z = self.next();
        Vector3::new(x, y, z) * half_width
    }
}

/// Writes a MAVLink 2 frame of `message` from the ground station into `out` at `*len`.
fn put<D: MessageData>(message: &D, sequence: &mut u8, out: &mut [u8], len: &mut usize) {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message_data(
        MavHeader {
            system_id: u32::from(GCS_SYSTEM),
            component_id: GCS_COMPONENT,
            sequence: *sequence,
        },
        message,
    );
    *sequence = sequence.wrapping_add(1);
    let bytes = raw.raw_bytes();
    out[*len..*len + bytes.len()].copy_from_slice(bytes);
    *len += bytes.len();
}

fn command(command: MavCmd, param1: f32, param2: f32) -> COMMAND_LONG_DATA {
    COMMAND_LONG_DATA {
        param1,
        param2,
        param3: 0.0,
        param4: 0.0,
        param5: 0.0,
        param6: 0.0,
        param7: 0.0,
        command,
        target_system: 1,
        target_component: 1,
        confirmation: 0,
    }
}

/// The deterministic sequence of [`TOTAL_TICKS`] full-step inputs (an iterator).
#[derive(Clone, Debug)]
pub struct StepSequence {
    tick: u32,
    sequence: u8,
    noise: Noise,
}

impl Default for StepSequence {
    fn default() -> Self {
        Self::new()
    }
}

impl StepSequence {
    /// The sequence from its first tick.
    pub fn new() -> Self {
        Self {
            tick: 0,
            sequence: 0,
            noise: Noise(0x2545_F491),
        }
    }
}

impl Iterator for StepSequence {
    type Item = StepInputs;

    fn next(&mut self) -> Option<StepInputs> {
        if self.tick >= TOTAL_TICKS {
            return None;
        }
        self.tick += 1;
        let tick = self.tick;
        let now_us = u64::from(tick) * TICK_US;
        let phase = match tick {
            t if t < ARM_TICK => Phase::Setup,
            ARM_TICK => Phase::Arm,
            _ => Phase::Flight,
        };
        let gyro_bias = Vector3::from(GYRO_BIAS);
        let accel_bias = Vector3::from(ACCEL_BIAS);
        let mut imu = [ImuSample {
            gyro_rad_s: [0.0; 3],
            accel_m_s2: [0.0; 3],
            time_us: 0,
        }; IMU_PER_TICK];
        let step_us = TICK_US / IMU_PER_TICK as u64;
        for (i, s) in imu.iter_mut().enumerate() {
            let time_us = now_us - TICK_US + (i as u64 + 1) * step_us;
            let x = truth(time_us);
            let g = x.angular_velocity + gyro_bias + self.noise.vector(GYRO_NOISE);
            let a = x.specific_force + accel_bias + self.noise.vector(ACCEL_NOISE);
            *s = ImuSample {
                gyro_rad_s: [g.x, g.y, g.z],
                accel_m_s2: [a.x, a.y, a.z],
                time_us,
            };
        }
        let mut link = [0u8; LINK_CAPACITY];
        let mut link_len = 0;
        let measured_us = now_us - POSE_LATENCY_US;
        let x = truth(measured_us);
        let p = x.position + self.noise.vector(POSE_NOISE);
        let [px, py, pz] = frames::flip_to_array(&p);
        let pose = ATT_POS_MOCAP_DATA {
            time_usec: measured_us,
            q: frames::quaternion_to_mavlink(&x.attitude),
            x: px,
            y: py,
            z: pz,
        };
        put(&pose, &mut self.sequence, &mut link, &mut link_len);
        if phase == Phase::Arm {
            // The explicit upside-down arm and the helix mission.
            let arm = command(
                MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                1.0,
                crate::link::FORCE_ARM_PARAM2,
            );
            put(&arm, &mut self.sequence, &mut link, &mut link_len);
            let start = command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0);
            put(&start, &mut self.sequence, &mut link, &mut link_len);
        }
        Some(StepInputs {
            tick,
            now_us,
            phase,
            imu,
            link,
            link_len,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sequence is a pure function of nothing: two runs agree bit for bit.
    #[test]
    fn sequence_is_deterministic() {
        let a: Vec<_> = StepSequence::new().collect();
        let b: Vec<_> = StepSequence::new().collect();
        assert_eq!(a.len(), TOTAL_TICKS as usize);
        assert!(a.iter().zip(&b).all(|(x, y)| x == y));
    }
}
