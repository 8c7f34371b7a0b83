//! Homing (PLCopen MC_Home with the CiA 402 homing methods) and MC_SetPosition. The same thin
//! skin as [`crate::api`]: check the pointers, look the handle up, call the SDK, write the
//! outputs, all inside `guard`.

use crate::api::{axis_of, started};
use crate::codes::MC_SET_POSITION_RELATIVE;
use crate::ffi::{read_in, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result};
use crate::types::mc_motion;
use motioncard_sdk::HomingSettings;

/// An axis's homing configuration, in counts and seconds: the card's `mc_axis_homing` register
/// block, the same struct as in the register map. Start from `mc_homing_settings_default`.
/// `method` is a CiA 402 homing method: 1..14 (a limit or home switch, then the index pulse),
/// 17..30 (the same, the switch edge itself), 33, 34 (the next index pulse, negative or
/// positive), 35, 37 (the current position), or `MC_HOMING_METHOD_HARD_STOP_` (-1..-4);
/// `flags` are `MC_HOMING_FLAG_` bits. The home point reads `mc_home`'s position plus
/// `home_offset`.
#[allow(non_camel_case_types)]
pub type mc_homing_settings = firmware_proto::raw::mc_axis_homing;

/// Homing method: a hard stop (a mechanical end stop) in the negative direction, found as a
/// following error of `hard_stop_ferror` held `hard_stop_dwell`, then the index pulse away from
/// it.
pub const MC_HOMING_METHOD_HARD_STOP_NEG_INDEX: i32 = -1;
/// Homing method: a hard stop in the positive direction, then the index pulse.
pub const MC_HOMING_METHOD_HARD_STOP_POS_INDEX: i32 = -2;
/// Homing method: a hard stop in the negative direction: the home point is where the axis
/// stalled.
pub const MC_HOMING_METHOD_HARD_STOP_NEG: i32 = -3;
/// Homing method: a hard stop in the positive direction.
pub const MC_HOMING_METHOD_HARD_STOP_POS: i32 = -4;
/// Homing method: the current position (nothing moves).
pub const MC_HOMING_METHOD_CURRENT_POSITION: i32 = 37;

/// The homing configuration the card loads at boot: method 37 (the current position), search
/// at 20000 counts/s, creep at 1000 counts/s, 200000 counts/s², 2e7 counts/s³, no offset, a 60 s
/// timeout, 1e6 counts of search, the index within 12000 counts, a hard stop at 200 counts of
/// following error held 20 ms, an index channel, and the axis ending at the home point. Never
/// blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_homing_settings_default(
    settings: *mut mc_homing_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(HomingSettings::default()) };
        Ok(())
    })
}

/// Write an axis's homing configuration and have the card apply it: an unknown method, or an
/// index method without `MC_HOMING_FLAG_INDEX`, is `MC_ERR_HOMING_METHOD`; a value that is not
/// finite `MC_ERR_NOT_FINITE`; one out of range `MC_ERR_BAD_CONFIG` or `MC_ERR_LIMIT_RANGE`.
/// Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_configure_homing(
    card: mc_card,
    axis: u32,
    settings: *const mc_homing_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_homing_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let (_, a) = axis_of(card, axis)?;
        Ok(a.configure_homing(&s)?)
    })
}

/// MC_Home from standstill with the configured method: the home point will read `position`
/// (user units) plus the configured home offset. `mc_motion_wait` on `*motion` (may be NULL;
/// `mc_wait_done` works too) gives the actual position once homed and in position, or
/// `MC_ERR_HOMING_FAILED` (switch, hard stop or index not found, or the timeout; an
/// `MC_EVENT_HOMING_FAILED` event says why, and the axis is at rest, not homed), or
/// `MC_ERR_ABORTED` (`mc_halt`, `mc_stop`, a safety stop). While the axis homes, moves and jogs
/// are `MC_ERR_AXIS_HOMING`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_home(
    card: mc_card,
    axis: u32,
    position: f64,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.home(position)?, axis, motion)
    })
}

/// MC_SetPosition: the actual and commanded positions become `position` (user units; with
/// `flags` `MC_SET_POSITION_RELATIVE`, they move by it) without moving the axis, and it counts
/// as homed (soft limits take effect). At standstill or disabled (`MC_ERR_INVALID_STATE`
/// otherwise, `MC_ERR_AXIS_HOMING` while it homes); other flag bits are `MC_ERR_BAD_CONFIG`.
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_position(
    card: mc_card,
    axis: u32,
    position: f64,
    flags: u32,
) -> mc_result {
    guard(|| {
        if flags & !MC_SET_POSITION_RELATIVE != 0 {
            return Err(crate::result::unknown("set_position flags", flags));
        }
        let (_, a) = axis_of(card, axis)?;
        Ok(a.set_position(position, flags & MC_SET_POSITION_RELATIVE != 0)?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_boot_method_is_the_current_position() {
        let d = HomingSettings::default();
        assert_eq!(d.method, MC_HOMING_METHOD_CURRENT_POSITION);
    }
}
