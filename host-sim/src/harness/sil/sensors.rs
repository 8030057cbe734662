//! Simulated sensors for the software-in-the-loop runs: a seeded random source, the IMU
//! (1 kHz, white noise and a constant bias on gyro and accelerometer) and the motion-capture
//! system (100 Hz, noise, latency, random dropouts, scripted outages), whose poses leave as
//! real MAVLink 2 frames through the firmware's encoder.

use firmware::frames;
use firmware::link::mavlink::dialects::common::{
    MavFrame, MavMessage, ATT_POS_MOCAP_DATA, ODOMETRY_DATA,
};
use firmware::pipeline::ImuSample;
use nalgebra::{UnitQuaternion, Vector3};

use crate::model::plant::RigidBodyState;

/// SplitMix64: small, seeded, reproducible (written here; no dependency for a few lines).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// Seeded generator.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// A vector of independent normals with standard deviation `sigma`.
    pub fn normal3(&mut self, sigma: f64) -> Vector3<f64> {
        Vector3::new(self.normal(), self.normal(), self.normal()) * sigma
    }
}

/// IMU model: body FLU, as the pipeline expects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuModel {
    /// Sample rate \[Hz\].
    pub rate_hz: f64,
    /// Gyro white noise, standard deviation per sample [rad/s].
    pub gyro_noise: f64,
    /// Constant gyro bias [rad/s] (the pipeline calibrates it out at boot).
    pub gyro_bias: [f64; 3],
    /// Accelerometer white noise per sample [m/s²].
    pub accel_noise: f64,
    /// Constant accelerometer bias [m/s²].
    pub accel_bias: [f64; 3],
}

impl ImuModel {
    /// One sample at `time_us` of a body with `state` and specific force `specific_force`
    /// [m/s²] (body).
    pub fn sample(
        &self,
        rng: &mut Rng,
        state: &RigidBodyState,
        specific_force: &Vector3<f64>,
        time_us: u64,
    ) -> ImuSample {
        let g =
            state.angular_velocity + Vector3::from(self.gyro_bias) + rng.normal3(self.gyro_noise);
        let a = specific_force + Vector3::from(self.accel_bias) + rng.normal3(self.accel_noise);
        ImuSample {
            gyro_rad_s: [g.x as f32, g.y as f32, g.z as f32],
            accel_m_s2: [a.x as f32, a.y as f32, a.z as f32],
            time_us,
        }
    }
}

/// Which MAVLink message carries the pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum PoseMessage {
    /// `ODOMETRY` in `MAV_FRAME_LOCAL_NED`.
    Odometry,
    /// `ATT_POS_MOCAP`.
    AttPosMocap,
}

/// Motion-capture model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MocapModel {
    /// Pose rate \[Hz\].
    pub rate_hz: f64,
    /// Latency from measurement to arrival at the UART \[s\].
    pub latency_s: f64,
    /// Probability that a pose is lost.
    pub dropout: f64,
    /// Position noise standard deviation \[m\].
    pub position_noise: f64,
    /// Attitude noise standard deviation \[rad\] (small rotation about a random axis).
    pub attitude_noise: f64,
    /// Message type.
    pub message: PoseMessage,
}

impl MocapModel {
    /// The MAVLink message of a measurement of `state` at `time_us` (NED/FRD, via the
    /// firmware's frame conversion).
    pub fn measure(&self, rng: &mut Rng, state: &RigidBodyState, time_us: u64) -> MavMessage {
        let p = state.position + rng.normal3(self.position_noise);
        let noise = UnitQuaternion::from_scaled_axis(rng.normal3(self.attitude_noise));
        let q = (state.attitude * noise).cast::<f32>();
        let p = p.cast::<f32>();
        let [x, y, z] = frames::flip_to_array(&p);
        let q = frames::quaternion_to_mavlink(&q);
        match self.message {
            PoseMessage::AttPosMocap => MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
                time_usec: time_us,
                q,
                x,
                y,
                z,
            }),
            PoseMessage::Odometry => MavMessage::ODOMETRY(ODOMETRY_DATA {
                time_usec: time_us,
                x,
                y,
                z,
                q,
                vx: f32::NAN,
                vy: f32::NAN,
                vz: f32::NAN,
                frame_id: MavFrame::MAV_FRAME_LOCAL_NED,
                child_frame_id: MavFrame::MAV_FRAME_BODY_FRD,
                ..Default::default()
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_moments() {
        let mut r = Rng::new(7);
        let n = 200_000;
        let (mut s, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let x = r.normal();
            s += x;
            s2 += x * x;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.02,
            "{mean} {var}"
        );
    }
}
