//! The C ABI of the motion-card SDK: `libmotioncard.so` / `libmotioncard.a` and the header
//! `include/motioncard.h` that cbindgen generates from this crate (`cargo xtask codegen`).
//!
//! A thin skin over [`motioncard_sdk`], after rustls-ffi's conventions:
//!
//! - every function returns an `mc_result` (0 = `MC_OK`, negative = an `MC_ERR_` code, one per
//!   [`motioncard_sdk::ErrorKind`] plus four of the ABI's own); `mc_last_error_message` gives
//!   the calling thread's detailed message of its last failure;
//! - outputs are written only on success; every pointer is checked for NULL first;
//! - cards are integer handles (`mc_card`) in a process-wide table with generation counters:
//!   an unknown or closed handle is `MC_ERR_BAD_HANDLE`, never undefined behaviour;
//! - each function body runs inside a panic boundary ([`result::guard`]): a panic becomes
//!   `MC_ERR_PANIC`, and cbindgen sees plain signatures;
//! - no thread calls into the application: callbacks run inside `mc_dispatch_events`.
//!
//! The contract of every `unsafe` function is the one stated in the header: each pointer is
//! NULL or valid for the access its documentation describes, for the duration of the call.
#![deny(unsafe_op_in_unsafe_fn)]
// The safety contract is common to every function and stated once, above and in the header.
#![allow(clippy::missing_safety_doc)]

// Generated from the register map (`cargo xtask codegen`): the C ABI's constants that are the
// card's codes. First: cbindgen writes the header in module order.
pub mod codes;

pub mod api;
pub mod cam;
mod ffi;
pub mod group;
pub mod homing;
pub mod io;
pub mod modes;
pub mod path;
pub mod pvt;
pub mod registry;
pub mod result;
pub mod safety;
pub mod scope;
pub mod sync;
pub mod types;
// Layout 1.8, last: cbindgen writes the header in module order.
pub mod config;
// The raw commands (mc_send_raw) after everything typed.
pub mod raw_command;

pub use api::*;
pub use codes::*;
pub use config::*;
pub use group::*;
pub use homing::*;
pub use io::*;
pub use modes::*;
pub use path::*;
pub use raw_command::*;
pub use registry::{mc_card, mc_event_callback};
pub use result::*;
pub use safety::*;
pub use types::*;
