//! The motion card's DPRAM contract.
//!
//! The register map is written once, as the C header `include/mc_dpram.h`; [`raw`] holds the
//! Rust bindings bindgen generates from it (`cargo xtask codegen`, checked in, verified by
//! `cargo xtask codegen --check`). Nothing outside this crate uses [`raw`] directly: the safe
//! layer here gives
//!
//! - [`Mem`], word-addressed shared memory with the access width in each method name, and
//!   [`Dpram`], its implementation over a mapped window (raw pointers, never references);
//! - [`layout`], the byte offset of every field, derived from the bindings with `offset_of!` and
//!   pinned by compile-time asserts;
//! - [`ring`], the single-producer single-consumer rings (command and event);
//! - [`seqlock`], the per-axis status blocks;
//! - [`wire`], the encodings of commands, events and status, and the code enums (those that
//!   list a kind of the header's codes, such as [`Opcode`], are generated from it by `cargo
//!   xtask codegen`, checked in like [`raw`]);
//! - [`cmd`], the typed commands: one struct per opcode's arguments, encoded into and decoded
//!   from a command entry in one place;
//! - [`window`], a DPRAM window mapped from a file (a memfd, a UIO map, a PCI BAR), and
//!   [`emu_link`], the host's side of the `emu:` transport: what host and card share besides
//!   the register map.
//!
//! Memory-ordering rules (see ARCHITECTURE.md): each side loads its own ring index plainly and
//! the peer's with Acquire, and publishes with Release; every index read from the window is
//! validated before use, because the other side may be buggy.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

#[cfg(target_endian = "big")]
compile_error!("the DPRAM layout is little-endian; big-endian hosts need byte swapping");

/// An enum of the header's codes (`MC_*` of one kind): its variants, `ALL` in declaration
/// order, and `from_raw`, `None` for a value the layout does not define. Defined before the
/// modules so each of them (`codes`, generated from the header, `wire`, `scope`) can declare its
/// codes with it.
macro_rules! code_enum {
    ($(#[$m:meta])* $name:ident : $repr:ty { $($(#[$vm:meta])* $variant:ident = $value:expr),+ $(,)? }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr($repr)]
        pub enum $name { $($(#[$vm])* $variant = $value as $repr),+ }
        impl $name {
            /// Every value, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];
            /// Decode, or `None` for a value this layout does not define.
            pub fn from_raw(v: $repr) -> Option<Self> {
                match v { $(x if x == $value as $repr => Some($name::$variant),)+ _ => None }
            }
        }
    };
}

#[allow(missing_docs)]
pub mod raw;
// Generated from the header: the enums of its codes (`cargo xtask codegen`).
mod codes;

pub mod block;
pub mod cmd;
pub mod layout;
pub mod mem;
pub mod motion_sync;
pub mod reset;
pub mod ring;
pub mod scope;
pub mod seqlock;
pub mod wire;

#[cfg(all(feature = "std", not(loom)))]
pub mod emu_link;
#[cfg(all(feature = "std", not(loom)))]
pub mod window;

pub use block::{Block, BlockAt, Blocks};
#[cfg(target_has_atomic = "64")]
pub use mem::Dpram;
pub use mem::Mem;
pub use motion_sync::*;
pub use reset::{
    AxisConfig, AxisHoming, AxisPdPlus, AxisPidff, DriveModel, FfpivGains, GroupDims, GroupPath,
    PdPlusGains,
};
pub use ring::{Consumer, Producer, RingError};
pub use scope::*;
pub use wire::*;

pub(crate) mod sync {
    #[cfg(not(loom))]
    pub use core::sync::atomic::{fence, Ordering};
    #[cfg(loom)]
    pub use loom::sync::atomic::{fence, Ordering};
}

/// Layout version this build speaks. A card whose major version differs is refused.
pub const LAYOUT_MAJOR: u16 = raw::MC_LAYOUT_MAJOR as u16;
/// Minor layout version: additions that older hosts can ignore.
pub const LAYOUT_MINOR: u16 = raw::MC_LAYOUT_MINOR as u16;
/// Identity magic.
pub const MAGIC: u32 = raw::MC_MAGIC;
/// Axes per card.
pub const MAX_AXES: usize = raw::MC_MAX_AXES as usize;
/// Axes groups per card.
pub const MAX_GROUPS: usize = raw::MC_MAX_GROUPS as usize;
/// Buffered moves per group.
pub const GROUP_QUEUE_LEN: usize = raw::MC_GROUP_QUEUE_LEN as usize;
/// Segments in a group's path buffer.
pub const PATH_LEN: usize = raw::MC_PATH_LEN as usize;
/// The card's digital outputs.
pub const OUTPUTS: usize = raw::MC_OUTPUTS as usize;
/// The card's digital inputs (layout 1.7).
pub const INPUTS: usize = raw::MC_INPUTS as usize;
/// Analog inputs (layout 1.11).
pub const ANALOG_INPUTS: usize = raw::MC_ANALOG_INPUTS as usize;
/// Spare analog (DAC) outputs (layout 1.11).
pub const ANALOG_OUTPUTS: usize = raw::MC_ANALOG_OUTPUTS as usize;
/// Position-compare channels (layout 1.7).
pub const COMPARE_CHANNELS: usize = raw::MC_COMPARE_CHANNELS as usize;
/// Positions a compare channel's table holds.
pub const COMPARE_TABLE_LEN: usize = raw::MC_COMPARE_TABLE_LEN as usize;
/// Positions per `CompareTable` command.
pub const COMPARE_TABLE_MAX: usize = raw::MC_COMPARE_TABLE_MAX as usize;
/// Touch-probe channels (layout 1.7).
pub const PROBE_CHANNELS: usize = raw::MC_PROBE_CHANNELS as usize;
/// Captures a probe channel keeps in its status.
pub const PROBE_QUEUE: usize = raw::MC_PROBE_QUEUE as usize;
/// Size of the mapped window in bytes.
pub const DPRAM_SIZE: usize = raw::MC_DPRAM_SIZE as usize;
/// Servo-rate bounds, Hz.
pub const SERVO_RATE_MIN_HZ: u32 = raw::MC_SERVO_RATE_MIN_HZ;
/// Servo-rate bounds, Hz.
pub const SERVO_RATE_MAX_HZ: u32 = raw::MC_SERVO_RATE_MAX_HZ;

/// Largest |position| a command may name, counts (2^52: binary64 still resolves one count).
pub const MAX_POSITION: f64 = raw::MC_MAX_POSITION;
/// Longest move the card accepts, s (about 11.6 days): anything longer comes from limits that
/// are almost certainly wrong, and is refused as infeasible.
pub const MAX_MOVE_TIME: f64 = raw::MC_MAX_MOVE_TIME;
/// Largest velocity override factor (`MC_OVERRIDE_MAX`: 200 %).
pub const OVERRIDE_MAX: f64 = raw::MC_OVERRIDE_MAX;
/// Buffered single-axis moves per axis (`MC_AXIS_QUEUE_LEN`).
pub const AXIS_QUEUE_LEN: usize = raw::MC_AXIS_QUEUE_LEN as usize;

/// Layout 1.8: the counts per user unit an axis's scale may have, in magnitude
/// (`MC_SCALE_MIN..=MC_SCALE_MAX`): from a nanometre-class unit on a coarse encoder to a
/// kilometre on a fine one. The card keeps each axis's scale for hosts (`MC_OP_SET_SCALE`).
pub const SCALE_RANGE: core::ops::RangeInclusive<f64> = raw::MC_SCALE_MIN..=raw::MC_SCALE_MAX;
/// A modulo axis's period, counts (layout 1.10, `MC_OP_SET_MODULO`; 0 is a linear axis). The card
/// holds it in 1/[`COMMANDED_SUBCOUNTS`] count.
pub const MODULO_RANGE: core::ops::RangeInclusive<f64> = raw::MC_MODULO_MIN..=raw::MC_MODULO_MAX;

/// A modulo period as the card holds it: `modulo` rounded to 1/[`COMMANDED_SUBCOUNTS`] count
/// (0 for 0). The caller has checked it (0, or in [`MODULO_RANGE`]).
pub fn modulo_subcounts(modulo: f64) -> i64 {
    let q = modulo * COMMANDED_SUBCOUNTS as f64;
    // round half away from zero without std (the period is positive)
    let f = q as i64;
    if q - f as f64 >= 0.5 {
        f + 1
    } else {
        f
    }
}

/// The range the card accepts for a kinematic limit of order `order` (1 velocity, 2
/// acceleration, 3 jerk; counts and seconds) at `servo_rate_hz`:
/// `[MAX_MOVE_TIME^-k, MAX_POSITION · rate^k]`, from one count in the longest move to the
/// whole position range in one servo tick. Subnormal and absurd values lie outside by
/// construction; the card refuses them with [`NackCode::LimitRange`].
pub fn limit_range(order: i32, servo_rate_hz: u32) -> core::ops::RangeInclusive<f64> {
    let rate = servo_rate_hz.clamp(SERVO_RATE_MIN_HZ, SERVO_RATE_MAX_HZ) as f64;
    powi(MAX_MOVE_TIME, -order)..=MAX_POSITION * powi(rate, order)
}

/// `x^n` by repeated squaring, the multiplications `f64::powi` makes (compiler-rt's
/// `__powidf2`), so the result is the same bit for bit, without std (the firmware's
/// `math::powi` too).
pub fn powi(mut x: f64, n: i32) -> f64 {
    let mut k = n.unsigned_abs();
    let mut r = 1.0;
    loop {
        if k & 1 == 1 {
            r *= x;
        }
        k >>= 1;
        if k == 0 {
            break;
        }
        x *= x;
    }
    if n < 0 {
        1.0 / r
    } else {
        r
    }
}

const _: () = assert!(core::mem::size_of::<raw::mc_dpram>() <= DPRAM_SIZE);
