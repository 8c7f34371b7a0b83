//! Layout 1.10: rotary (modulo) axes: the period of an axis, and absolute moves that name
//! their way round (PLCopen `MC_Direction`, the register map's `MC_MOVE_DIR_*`).

use crate::api::{axis_of, started};
use crate::ffi::{read_in, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, unknown};
use crate::types::{mc_motion, mc_move_limits};
use motioncard_sdk::{MoveDirection, MoveLimits};

/// Make `axis` a rotary (modulo) axis of `period` user units (for example 360 with a scale in
/// counts per degree): its status's positions, motion done's and probe captures wrap into
/// [0, period) without drift; position compare is turn-aware (layout 1.13: positions in
/// [0, period), `mc_compare_single_each_turn`, `mc_compare_series_each_turn`); soft limits do
/// not apply. At rest only (`MC_ERR_MODULO_BUSY`), and not while an armed compare channel
/// watches the axis (`MC_ERR_COMPARE_TURN`). A
/// period of 0 is `MC_ERR_MODULO_ZERO` (`mc_axis_clear_modulo` makes an axis linear), a
/// negative, non-finite or out-of-range one (1 to 1e11 counts) `MC_ERR_MODULO_RANGE`; the axis
/// needs a positive scale (`MC_ERR_BAD_CONFIG`). A refusal changes nothing.
#[no_mangle]
pub extern "C" fn mc_axis_set_modulo(card: mc_card, axis: u32, period: f64) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.set_modulo(period)?))
}

/// Make `axis` linear again (its position stays where it is). At rest only
/// (`MC_ERR_MODULO_BUSY`).
#[no_mangle]
pub extern "C" fn mc_axis_clear_modulo(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.clear_modulo()?))
}

/// The modulo period the card holds for `axis` (read back), in user units; 0 for a linear
/// axis. `*period` is written on success.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_modulo(
    card: mc_card,
    axis: u32,
    period: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::new(period, "period")?;
        let m = axis_of(card, axis)?.1.modulo()?;
        // SAFETY: checked non-NULL; writable by the contract.
        unsafe { out.write(m) };
        Ok(())
    })
}

/// MC_MoveAbsolute (Aborting) the way `direction` names (`MC_MOVE_DIR_SHORTEST`, `_POSITIVE`,
/// `_NEGATIVE`, `_CURRENT`; another value: `MC_ERR_BAD_CONFIG`). On a modulo axis
/// `target` must be in [0, period) (else `MC_ERR_MODULO_MOVE`); the shortest way takes a tie of
/// half a turn positive, and a target within the in-position window of where the axis is is no
/// turn. On a linear axis only `MC_MOVE_DIR_SHORTEST` (else `MC_ERR_MODULO_MOVE`). Otherwise as
/// `mc_move_absolute`.
#[no_mangle]
pub unsafe extern "C" fn mc_move_absolute_dir(
    card: mc_card,
    axis: u32,
    target: f64,
    direction: u32,
    limits: *const mc_move_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_move_limits.
        let l: MoveLimits = unsafe { read_in(limits, "limits") }?.into();
        let dir = match direction {
            d if d <= 3 => MoveDirection::from_code(d),
            v => return Err(unknown("direction", v)),
        };
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.move_absolute_dir(target, dir, &l)?, axis, motion)
    })
}
