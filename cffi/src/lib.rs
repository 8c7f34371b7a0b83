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
//! - each function body runs inside a panic boundary (`result::guard`): a panic becomes
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

pub mod analog;
pub mod api;
pub mod cam;
pub mod comp;
mod ffi;
pub mod freq;
pub mod gantry;
pub mod gcode;
pub mod group;
pub mod group_home;
mod handles;
pub mod handwheel;
pub mod homing;
pub mod io;
pub mod list;
pub mod modes;
pub mod path;
pub mod pvt;
pub mod registry;
pub mod result;
pub mod rotary;
pub mod safety;
pub mod scope;
pub mod servo;
pub mod set_path;
pub mod sync;
pub mod sync_bus;
pub mod types;
// Layout 1.8, last: cbindgen writes the header in module order.
pub mod config;
// The raw commands (mc_send_raw) after everything typed.
pub mod raw_command;

pub use api::*;
pub use codes::*;
pub use config::*;
pub use gcode::*;
pub use group::*;
pub use homing::*;
pub use io::*;
pub use list::*;
pub use modes::*;
pub use path::*;
pub use raw_command::*;
pub use registry::{mc_card, mc_event_callback};
pub use result::*;
pub use safety::*;
pub use types::*;

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::raw;

    /// Each C name equals the define of the register map it stands for, and has the type.
    macro_rules! same {
        ($ty:ty: $($ours:ident = $card:ident),+ $(,)?) => {
            $(assert_eq!($ours, raw::$card as $ty, stringify!($ours));)+
        };
    }

    /// `codes.rs` is generated (`cargo xtask codegen`, whose `--check` fails when it is stale):
    /// one C name of each set against the define it stands for, so that a rule of
    /// `xtask/src/codes.rs` that picks the wrong define, or a value copied wrong, fails here.
    /// An event's codes are `int32_t`, as `mc_event.code`.
    #[test]
    fn the_generated_codes_are_the_cards() {
        same!(u32:
            MC_EVENT_SCOPE = MC_EV_SCOPE,
            MC_AXIS_STATE_HOMING = MC_STATE_HOMING,
            MC_STOP_REASON_STOP_TIMEOUT = MC_STOP_TIMEOUT,
            MC_GROUP_COUNT = MC_MAX_GROUPS,
            MC_OP_SCOPE_ARM = MC_OP_SCOPE_ARM,
            MC_HOMING_FLAG_MOVE_TO_HOME = MC_HOMING_MOVE_TO_HOME,
            MC_SET_POSITION_RELATIVE = MC_SET_POSITION_RELATIVE,
            MC_PATH_SEGMENTS = MC_PATH_LEN,
            MC_CARD_OUTPUTS = MC_OUTPUTS,
            MC_PATH_BUFFER_BLEND_PREVIOUS = MC_PATH_BLEND_PREVIOUS,
            MC_PATH_TRANSITION_TIME_SHIFT = MC_TM_TIME_SHIFT,
            MC_OUTPUT_AT_DISTANCE = MC_PATH_OUT_AT_DISTANCE,
            MC_PATH_STATUS_HALTING = MC_PATHST_HALTING,
            MC_CARD_INPUTS = MC_INPUTS,
            MC_COMPARE_TABLE_LEN = MC_COMPARE_TABLE_LEN,
            MC_PROBE_QUEUE = MC_PROBE_QUEUE,
            MC_IO_STATE_DONE = MC_IO_DONE,
            MC_PROBE_INPUT_INDEX = MC_PROBE_INDEX,
            MC_PROBE_EDGE_FALLING = MC_PROBE_FALLING,
            MC_MASTER_AUX = MC_MASTER_AUX,
            MC_AUX_ENCODERS = MC_AUX_ENCODERS,
            MC_PVT_LEN = MC_PVT_LEN,
            MC_CAM_PERIODIC = MC_CAM_PERIODIC,
            MC_CAM_MAX_POINTS = MC_CAM_MAX_POINTS,
            MC_SCOPE_RING_LEN = MC_SCOPE_RING_LEN,
            MC_SCOPE_SIG_SERVO_FF = MC_SIG_SERVO_FF,
            MC_SCOPE_CONTINUOUS = MC_SCOPE_CONTINUOUS,
            MC_SCOPE_TRIG_FAULT = MC_SCOPE_TRIG_FAULT,
            MC_SCOPE_EITHER = MC_SCOPE_EITHER,
            MC_SCOPE_STATE_CAPTURING = MC_SCOPE_CAPTURING,
        );
        same!(i32:
            MC_HOMING_ERROR_NO_INDEX = MC_HOMING_ERR_NO_INDEX,
            MC_COMPARE_MISSED = MC_CMP_MISSED,
            MC_SYNC_CAM_SWITCH = MC_SYNC_CAM_SWITCH,
            MC_PVT_EVENT_STARVED = MC_PVT_EV_STARVED,
            MC_SCOPE_EVENT_LOST = MC_SCOPE_EV_LOST,
        );
    }
}
