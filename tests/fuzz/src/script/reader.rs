//! The reader of a script: the input's bytes as little-endian fields (0 past the end), and
//! [`parse`], the whole input as operations.

use super::{FrameSpec, MissionSpec, Op};

/// Reads fields from the input; past its end every byte is 0.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn done(&self) -> bool {
        self.at >= self.data.len()
    }
    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }
    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut a = [0u8; N];
        for b in a.iter_mut() {
            *b = self.u8();
        }
        a
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.array())
    }
    fn i16(&mut self) -> i16 {
        i16::from_le_bytes(self.array())
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.array())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.array())
    }
    fn f32s<const N: usize>(&mut self) -> [f32; N] {
        let mut a = [0.0; N];
        for x in a.iter_mut() {
            *x = self.f32();
        }
        a
    }
    fn i16s<const N: usize>(&mut self) -> [i16; N] {
        let mut a = [0; N];
        for x in a.iter_mut() {
            *x = self.i16();
        }
        a
    }
}

/// Reads the whole input as operations (never fails: see the module's table).
pub fn parse(data: &[u8]) -> Vec<Op> {
    let mut r = Reader { data, at: 0 };
    let mut ops = Vec::new();
    while !r.done() {
        let op = match r.u8() % 6 {
            0 => {
                let n = usize::from(r.u8());
                let end = (r.at + n).min(data.len());
                let bytes = data.get(r.at..end).unwrap_or(&[]).to_vec();
                r.at += n;
                Op::Bytes(bytes)
            }
            1 => {
                let spec = match r.u8() % 6 {
                    0 => FrameSpec::Mocap {
                        position: r.f32s(),
                        q: r.f32s(),
                    },
                    1 => FrameSpec::Odometry {
                        frame: r.u8(),
                        position: r.f32s(),
                        q: r.f32s(),
                    },
                    2 => FrameSpec::Command {
                        command: r.u8(),
                        target: r.u8(),
                        params: r.f32s(),
                    },
                    3 => FrameSpec::Setpoint {
                        frame: r.u8(),
                        mask: r.u16(),
                        target: r.u8(),
                        position: r.f32s(),
                        yaw: r.f32(),
                    },
                    4 => FrameSpec::HilSensor {
                        fields: r.u32(),
                        accel: r.f32s(),
                        gyro: r.f32s(),
                        time_offset_us: r.i32(),
                    },
                    _ => {
                        let sub = r.u8() % 9;
                        let target = r.u8();
                        let message = match sub {
                            0 => MissionSpec::Count { count: r.u16() },
                            1 => MissionSpec::ItemInt {
                                seq: r.u16(),
                                command: r.u8(),
                                frame: r.u8(),
                                xy: [r.i32(), r.i32()],
                                z: r.f32(),
                                params: r.f32s(),
                            },
                            2 => MissionSpec::Item {
                                seq: r.u16(),
                                command: r.u8(),
                                frame: r.u8(),
                                xy: r.f32s(),
                                z: r.f32(),
                                params: r.f32s(),
                            },
                            3 => MissionSpec::RequestInt { seq: r.u16() },
                            4 => MissionSpec::RequestList,
                            5 => MissionSpec::ClearAll,
                            6 => MissionSpec::SetCurrent { seq: r.u16() },
                            7 => MissionSpec::Ack { result: r.u8() },
                            _ => MissionSpec::SetOrigin {
                                lla: [r.i32(), r.i32(), r.i32()],
                            },
                        };
                        FrameSpec::Mission { target, message }
                    }
                };
                Op::Frame {
                    spec,
                    chunk: r.u8() % 64 + 1,
                }
            }
            2 => Op::Imu {
                gyro: r.f32s(),
                accel: r.f32s(),
                dt: r.u16(),
            },
            3 => Op::ImuQuantised {
                gyro: r.i16s(),
                accel: r.i16s(),
            },
            4 => Op::Rest(r.u8()),
            _ => Op::Tick {
                dt: r.u16(),
                room: r.u16() % 2048,
            },
        };
        ops.push(op);
    }
    ops
}
