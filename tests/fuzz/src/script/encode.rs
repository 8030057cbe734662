//! The writer of a script: [`encode`], operations as the bytes [`parse`](super::parse) reads
//! back.

use super::{FrameSpec, MissionSpec, Op};

fn put_f32s(out: &mut Vec<u8>, xs: &[f32]) {
    for x in xs {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

/// Writes a [`FrameSpec::Mission`] after the kind byte's place: kind 5, sub-kind, target, fields.
fn put_mission(out: &mut Vec<u8>, target: u8, m: &MissionSpec) {
    let sub = match m {
        MissionSpec::Count { .. } => 0,
        MissionSpec::ItemInt { .. } => 1,
        MissionSpec::Item { .. } => 2,
        MissionSpec::RequestInt { .. } => 3,
        MissionSpec::RequestList => 4,
        MissionSpec::ClearAll => 5,
        MissionSpec::SetCurrent { .. } => 6,
        MissionSpec::Ack { .. } => 7,
        MissionSpec::SetOrigin { .. } => 8,
    };
    out.extend_from_slice(&[5, sub, target]);
    match m {
        MissionSpec::Count { count: n }
        | MissionSpec::RequestInt { seq: n }
        | MissionSpec::SetCurrent { seq: n } => out.extend_from_slice(&n.to_le_bytes()),
        MissionSpec::ItemInt {
            seq,
            command,
            frame,
            xy,
            z,
            params,
        } => {
            out.extend_from_slice(&seq.to_le_bytes());
            out.extend_from_slice(&[*command, *frame]);
            for v in xy {
                out.extend_from_slice(&v.to_le_bytes());
            }
            put_f32s(out, &[*z]);
            put_f32s(out, params);
        }
        MissionSpec::Item {
            seq,
            command,
            frame,
            xy,
            z,
            params,
        } => {
            out.extend_from_slice(&seq.to_le_bytes());
            out.extend_from_slice(&[*command, *frame]);
            put_f32s(out, xy);
            put_f32s(out, &[*z]);
            put_f32s(out, params);
        }
        MissionSpec::RequestList | MissionSpec::ClearAll => {}
        MissionSpec::Ack { result } => out.push(*result),
        MissionSpec::SetOrigin { lla } => {
            for v in lla {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
}

/// Writes operations in the format [`parse`](super::parse) reads (`parse(&encode(ops)) == ops`
/// for ops whose fields are in range: at most 255 raw bytes, `chunk` in 1..=64, `room` < 2048).
pub fn encode(ops: &[Op]) -> Vec<u8> {
    let mut out = Vec::new();
    for op in ops {
        match op {
            Op::Bytes(b) => {
                out.push(0);
                out.push(b.len().min(255) as u8);
                out.extend_from_slice(&b[..b.len().min(255)]);
            }
            Op::Frame { spec, chunk } => {
                out.push(1);
                match spec {
                    FrameSpec::Mocap { position, q } => {
                        out.push(0);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, q);
                    }
                    FrameSpec::Odometry { frame, position, q } => {
                        out.push(1);
                        out.push(*frame);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, q);
                    }
                    FrameSpec::Command {
                        command,
                        target,
                        params,
                    } => {
                        out.extend_from_slice(&[2, *command, *target]);
                        put_f32s(&mut out, params);
                    }
                    FrameSpec::Setpoint {
                        frame,
                        mask,
                        target,
                        position,
                        yaw,
                    } => {
                        out.extend_from_slice(&[3, *frame]);
                        out.extend_from_slice(&mask.to_le_bytes());
                        out.push(*target);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, &[*yaw]);
                    }
                    FrameSpec::HilSensor {
                        fields,
                        accel,
                        gyro,
                        time_offset_us,
                    } => {
                        out.push(4);
                        out.extend_from_slice(&fields.to_le_bytes());
                        put_f32s(&mut out, accel);
                        put_f32s(&mut out, gyro);
                        out.extend_from_slice(&time_offset_us.to_le_bytes());
                    }
                    FrameSpec::Mission { target, message } => {
                        put_mission(&mut out, *target, message)
                    }
                }
                out.push(chunk.wrapping_sub(1) % 64);
            }
            Op::Imu { gyro, accel, dt } => {
                out.push(2);
                put_f32s(&mut out, gyro);
                put_f32s(&mut out, accel);
                out.extend_from_slice(&dt.to_le_bytes());
            }
            Op::ImuQuantised { gyro, accel } => {
                out.push(3);
                for x in gyro.iter().chain(accel) {
                    out.extend_from_slice(&x.to_le_bytes());
                }
            }
            Op::Rest(n) => out.extend_from_slice(&[4, *n]),
            Op::Tick { dt, room } => {
                out.push(5);
                out.extend_from_slice(&dt.to_le_bytes());
                out.extend_from_slice(&(room % 2048).to_le_bytes());
            }
        }
    }
    out
}
