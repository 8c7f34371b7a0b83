//! The motion card in software, in layers:
//!
//! - [`firmware`], [`motion`], [`servo`], [`presets`]: the crate `card-firmware`, re-exported
//!   here.
//!   [`firmware`]: the card's firmware — boot and the servo tick, the command manager, PLCopen
//!   axes and groups, the safety layer. It sees only the DPRAM window and plain values (encoder
//!   counts and input bits in, DAC volts out), exactly as on the card's DSP.
//! - [`motion`]: the pure motion algorithms, used by the firmware and by the host: the S-curve
//!   planner, the acc/dec filters, the arc interpolators, NURBS curves, the speed-controlled
//!   NURBS interpolation with its path-speed planner and saturation-aware feed.
//! - [`servo`]: the servo laws (FFPIV, PD+).
//! - [`plant`]: what hangs off the card — amplifier, motor and load, encoder, switches — and
//!   the fault injector the tests drive. The firmware never imports it.
//! - [`emu`]: the emulated card — firmware + plant + interrupt line on a stepped, free-running
//!   or real-time clock, its DPRAM in shared memory, served to other processes as `emu:NAME`.
//! - [`testkit`]: the fuzzing harness and the tests' seeded generator (doc-hidden).
//!
//! The cargo feature `emulator` (default) brings `plant` and `emu` (and the `card-emu`
//! binary); without it the crate is only the firmware crate's re-exports.
#![deny(unsafe_op_in_unsafe_fn)]

pub use card_firmware::{firmware, motion, presets, servo};

#[cfg(feature = "emulator")]
pub mod emu;
#[cfg(feature = "emulator")]
pub mod plant;
#[doc(hidden)]
pub mod testkit;

#[cfg(feature = "emulator")]
pub use emu::emulator::{Clock, EmuOptions, Emulator, Runner};
pub use firmware::Firmware;
#[cfg(feature = "emulator")]
pub use plant::analog::{AnalogBank, AnalogSource, Noise};
#[cfg(feature = "emulator")]
pub use plant::io::{FireRecord, InputBank, Sensor};
#[cfg(feature = "emulator")]
pub use plant::{EndStops, HomeSwitch, IndexPulse, Motor, MotorParams, Switches};

pub use firmware_proto::{
    limit_range, MAX_MOVE_TIME, MAX_POSITION, SERVO_RATE_MAX_HZ, SERVO_RATE_MIN_HZ,
};
