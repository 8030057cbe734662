//! The flight software under test, outside the desktop law: software in the loop ([`sil`]: the
//! firmware's flight pipeline in process), processor in the loop ([`pil`]: the firmware on an
//! emulated Cortex-M4F), and Cortex-M4F instruction counts of the control step ([`m4f`]). Both
//! emulated harnesses run QEMU through [`qemu`]. SIL and PIL share the UDP ground-station link
//! ([`gcs_udp`]).

pub mod gcs_udp;
pub mod m4f;
pub mod pil;
pub mod qemu;
pub mod sil;
