//! The motion card's firmware and the motion algorithms it runs, in layers:
//!
//! - [`firmware`]: the card's firmware — boot and the servo tick, the command manager, PLCopen
//!   axes and groups, the safety layer, homing, I/O, sync, the scope. It sees only the DPRAM
//!   window and plain values (encoder counts and input bits in, DAC volts out), exactly as on
//!   the card's DSP.
//! - [`motion`]: the pure motion algorithms, used by the firmware and by the host: the S-curve
//!   planner, the acc/dec filters, the arc interpolators, NURBS curves, the speed-controlled
//!   NURBS interpolation with its path-speed planner and saturation-aware feed.
//! - [`servo`]: the servo laws (FFPIV, PD+).
//! - [`presets`]: the papers' parameter sets (drive models, gains, paths).
//! - `testkit`: the tests' seeded generator and trajectory cases (doc-hidden).
//!
//! [`host`] is what a host shares with the card (configuration checks, offline planners): the
//! SDK uses this crate only through it.
//!
//! The emulated card (`card-emu`) wraps this crate with a plant, clocks and a server.
#![cfg_attr(not(test), no_std)]
#![deny(unsafe_op_in_unsafe_fn)]

#[cfg(any(test, feature = "host"))]
extern crate alloc;
#[cfg(all(feature = "host", not(test)))]
extern crate std;

pub mod firmware;
#[cfg(feature = "host")]
pub mod host;
pub mod math;
pub mod motion;
#[cfg(feature = "host")]
pub mod presets;
pub mod ram;
pub mod servo;

pub use firmware::Firmware;

pub use firmware_proto::{
    limit_range, MAX_MOVE_TIME, MAX_POSITION, SERVO_RATE_MAX_HZ, SERVO_RATE_MIN_HZ,
};
#[cfg(feature = "host")]
#[doc(hidden)]
pub mod testkit;
