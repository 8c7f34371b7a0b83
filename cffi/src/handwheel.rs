//! The handwheel (layout 1.10): an auxiliary encoder input jogs an axis (`mc_handwheel_*`).

use crate::api::{axis_of, started};
use crate::registry::mc_card;
use crate::result::{guard, mc_result};
use crate::types::mc_motion;
use motioncard_sdk::Handwheel;

/// The default detent of `mc_handwheel_select`: 4 auxiliary counts (a quadrature wheel with
/// one detent per cycle, 100 detents a turn).
pub const MC_HANDWHEEL_DEFAULT_DETENT: u32 = 4;
const _: () = assert!(MC_HANDWHEEL_DEFAULT_DETENT == Handwheel::DEFAULT_DETENT);

/// Select auxiliary encoder `input` as the handwheel of `axis`: each detent (`detent`
/// auxiliary counts, 1..1024, usually `MC_HANDWHEEL_DEFAULT_DETENT`) moves the axis by `ratio`
/// encoder counts (x1, x10, x100; 1 <= |ratio| <= 10000, negative: the other way; on an axis
/// whose scale is negative the ratio is negated, so the wheel turns the axis forward in user
/// units). The axis follows within its jog limits (`jog_max_vel`, `jog_accel`, `jog_jerk` of
/// `mc_axis_settings`), in SynchronizedMotion; turned faster, the excess is dropped: once the
/// wheel stops, the axis stops within its stop distance from `jog_max_vel` plus one servo
/// period at it. Once homed with soft limits on, the wheel stops the axis at a soft limit.
/// From Standstill, or taking over a move or velocity mode (aborted; the wheel starts where the
/// jog ramp stops the axis), or on the axis's own handwheel (a new input, ratio or detent: the
/// motion goes on, and `*motion` is the first selection's). An input selected for another axis
/// is handed over: that axis goes on to where the wheel put it, its motion done. `motion` (may
/// be NULL) receives the motion, done once the handwheel is let go (`mc_handwheel_off`, or its
/// input handed over) and the axis in position; `MC_ERR_ABORTED` after a halt, stop or fault.
/// Refused: `MC_ERR_HANDWHEEL_INPUT` (no such input), `MC_ERR_HANDWHEEL_RATIO` (a ratio of 0 or
/// beyond 10000, a detent outside 1..1024), `MC_ERR_AXIS_GROUPED`, `MC_ERR_AXIS_DISABLED`,
/// `MC_ERR_INVALID_STATE` (homing, stopping, geared, ErrorStop). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_handwheel_select(
    card: mc_card,
    axis: u32,
    input: u32,
    ratio: i32,
    detent: u32,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        let w = Handwheel::new(input as usize).ratio(ratio).detent(detent);
        started(&e, a.handwheel(&w)?, axis, motion)
    })
}

/// Let go of the handwheel of `axis`: the axis goes on to where the wheel put it, and the
/// handwheel's motion is done there. `MC_ERR_INVALID_STATE` when no handwheel drives the axis.
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_handwheel_off(card: mc_card, axis: u32) -> mc_result {
    guard(|| {
        let (_, a) = axis_of(card, axis)?;
        Ok(a.handwheel_off()?)
    })
}
