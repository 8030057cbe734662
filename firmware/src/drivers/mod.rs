//! Device drivers and output encodings that touch no register: the IMU driver (generic over
//! `embedded-hal-async`), the DShot frame encoder. Tested on the host.

pub mod dshot;
pub mod icm42688;
