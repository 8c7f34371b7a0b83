//! The emulated card: the firmware and the plant behind a DPRAM window in shared memory, with
//! an interrupt line, driven by a clock, and served to other processes.

pub mod bus;
pub mod emulator;
pub mod server;
