//! The exported functions of the safety layer: the host heartbeat and the card's watchdog,
//! e-stop, fault reset, per-axis limits and following error, stop reasons. The same thin skin
//! as [`crate::api`] (check the pointers, look the handle up, call the SDK, write the outputs,
//! all inside `guard`).

use crate::ffi::{read_in, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result};
use crate::types::{mc_safety_settings, mc_safety_status, mc_stop_info, stop_category};
use motioncard_sdk::SafetySettings;
use std::time::Duration;

/// Stop (`on` = 0) or resume (non-zero) this process's heartbeat to the card. A stopped
/// heartbeat is a hung host to the card: its watchdog trips after the timeout, every axis makes
/// a category 1 stop, and the trip stays latched until `mc_reset_faults`. On a real-time card a
/// library thread writes the heartbeat; on a stepped sim it beats once per emulated tick, so
/// stepping with the heartbeat off trips the watchdog deterministically. For tests of the
/// watchdog; the heartbeat is on from `mc_open`. Never blocks.
#[no_mangle]
pub extern "C" fn mc_set_heartbeat(card: mc_card, on: u32) -> mc_result {
    guard(|| {
        registry::get(card)?.card.set_heartbeat(on != 0);
        Ok(())
    })
}

/// Set the card's watchdog timeout, µs (default 100000: above the heartbeat gaps of a loaded
/// host without real-time scheduling). The card refuses zero and anything under
/// 1.5 × the library's heartbeat period of 1 ms: `MC_ERR_WATCHDOG_TIMEOUT`. On a `sim` card
/// opened with `MOTIONCARD_SIM_WATCHDOG_MS` set (debugging), a shorter timeout gets that one.
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_watchdog_timeout(card: mc_card, timeout_us: u32) -> mc_result {
    guard(|| {
        let t = Duration::from_micros(u64::from(timeout_us));
        Ok(registry::get(card)?.card.set_watchdog_timeout(t)?)
    })
}

/// The stop the card's e-stop input makes (`MC_STOP_CATEGORY_`; default 1; any other value is
/// `MC_ERR_BAD_CATEGORY`). Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_estop_input_category(card: mc_card, category: u32) -> mc_result {
    guard(|| {
        let c = stop_category(category)?;
        Ok(registry::get(card)?.card.set_estop_input_category(c)?)
    })
}

/// E-stop every axis with the given stop category (`MC_STOP_CATEGORY_`; any other value is
/// `MC_ERR_BAD_CATEGORY`). Latched: moves, enables and resets are refused with
/// `MC_ERR_ESTOP_ACTIVE` until `mc_reset_faults`. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_estop(card: mc_card, category: u32) -> mc_result {
    guard(|| {
        let c = stop_category(category)?;
        Ok(registry::get(card)?.card.estop(c)?)
    })
}

/// Clear the card-wide latches (watchdog, e-stop), then MC_Reset every axis in ErrorStop.
/// `MC_ERR_CAUSE_ACTIVE` while the cause is still there (no live heartbeat, the e-stop input
/// pressed, an axis's alarm or encoder fault). Axes whose stop removed power end Disabled, the
/// others Standstill. Blocks until the card has answered each command (one, plus one per axis
/// in ErrorStop).
#[no_mangle]
pub extern "C" fn mc_reset_faults(card: mc_card) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.reset_faults()?))
}

/// Set the card's maximum stop time, µs (default 2000000): every stop — halt, stop, the safety
/// stops, starvation — ends within it; a halt whose own ramp would take longer runs on the
/// axis's stop ramp, and a stop still running at the bound loses power (stop reason
/// `MC_STOP_REASON_STOP_TIMEOUT`). 10 ms to 600 s, and every axis's stop ramp from its max
/// velocity must fit: `MC_ERR_STOP_TOO_LONG` otherwise. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_max_stop_time(card: mc_card, us: u32) -> mc_result {
    guard(|| {
        let t = std::time::Duration::from_micros(us as u64);
        Ok(registry::get(card)?.card.set_max_stop_time(t)?)
    })
}

/// The card-wide safety state: watchdog and e-stop latches, heartbeat ticks, protocol errors.
/// Reads the card's window; never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_get_safety_status(
    card: mc_card,
    status: *mut mc_safety_status,
) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let s = registry::get(card)?.card.safety_status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s.into()) };
        Ok(())
    })
}

/// The card's default safety configuration of an axis, in counts: hard limits, amplifier alarm
/// and encoder checks on, soft limits off, limit stops category 1, following error 10,000
/// counts at 10⁶ counts/s and 1,000 at rest, stops at 5·10⁶ counts/s² and 5·10⁸ counts/s³.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_safety_settings_default(
    settings: *mut mc_safety_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(SafetySettings::default().into()) };
        Ok(())
    })
}

/// Write an axis's safety configuration (limits, following error, stop ramp; user units
/// converted through the axis's scale) and have the card apply it. NaN or infinity:
/// `MC_ERR_NOT_FINITE`; an unknown `limit_stop`: `MC_ERR_BAD_CATEGORY`; values the card cannot
/// use (soft limits not increasing, `ferror` under `min_ferror`, a non-positive limit):
/// `MC_ERR_BAD_CONFIG`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_configure_safety(
    card: mc_card,
    axis: u32,
    settings: *const mc_safety_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_safety_settings.
        let s = unsafe { read_in(settings, "settings") }?.to_sdk()?;
        let a = registry::get(card)?.card.axis(axis as usize)?;
        Ok(a.configure_safety(&s)?)
    })
}

/// Why the axis's last motion ended, and the card's timing of its last safety stop: the tick
/// it began, the tick the axis came to rest (`at_rest` 0 while still stopping), the planned
/// ramp. Reads the status block as `mc_get_status` does (`MC_ERR_PROTOCOL` for a stop reason
/// this library does not know); does not wait for the card.
#[no_mangle]
pub unsafe extern "C" fn mc_get_stop_info(
    card: mc_card,
    axis: u32,
    info: *mut mc_stop_info,
) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let a = registry::get(card)?.card.axis(axis as usize)?;
        let i = a.stop_info()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(i.into()) };
        Ok(())
    })
}
