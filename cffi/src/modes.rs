//! Moves from any state (PLCopen Aborting and Buffered, MC_MoveAdditive), velocity mode, jog
//! and override of one axis.

use crate::api::{axis_of, motion_of, ms, started};
use crate::ffi::{read_in, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, unknown, Failure};
use crate::types::{mc_motion, mc_move_limits};
use motioncard_sdk::{BufferMode, MoveKind, MoveLimits, VelocityLimits};

/// `mc_move` kind: MC_MoveAbsolute, `value` is the target.
pub const MC_MOVE_KIND_ABSOLUTE: u32 = 0;
/// `mc_move` kind: MC_MoveRelative, `value` is a distance from the commanded position
/// (buffered: from the target of the move before it).
pub const MC_MOVE_KIND_RELATIVE: u32 = 1;
/// `mc_move` kind: MC_MoveAdditive, `value` is a distance from the target of the last move.
pub const MC_MOVE_KIND_ADDITIVE: u32 = 2;

/// PLCopen BufferMode Aborting: take over at once from the current position, velocity and
/// acceleration; the motion in progress and every buffered move are aborted.
pub const MC_BUFFER_ABORTING: u32 = 0;
/// PLCopen BufferMode Buffered: wait in the axis's queue (16 moves, else `MC_ERR_QUEUE_FULL`)
/// until the motion before it is done; `mc_motion_wait_active` tells when it starts.
pub const MC_BUFFER_BUFFERED: u32 = 1;

/// Limits of velocity mode, in user units (see `mc_set_scale`); each finite and > 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_velocity_limits {
    /// Acceleration (speeding up).
    pub acceleration: f64,
    /// Deceleration (slowing down).
    pub deceleration: f64,
    /// Jerk.
    pub jerk: f64,
}

fn write_opt(out: *mut f64, v: f64) {
    if let Some(out) = Out::optional(out) {
        // SAFETY: non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
    }
}

/// MC_MoveAbsolute, MC_MoveRelative or MC_MoveAdditive (`kind`: `MC_MOVE_KIND_ABSOLUTE`,
/// `_RELATIVE`, `_ADDITIVE`) with a PLCopen buffer mode (`MC_BUFFER_ABORTING`,
/// `MC_BUFFER_BUFFERED`). From rest the move is the card's time-optimal S-curve with the four
/// jerks of `*limits`; from motion it is time-optimal from the current state with one jerk,
/// the smallest of the four. An unknown kind or mode is `MC_ERR_BAD_CONFIG`. `motion` may be
/// NULL. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_move(
    card: mc_card,
    axis: u32,
    kind: u32,
    value: f64,
    limits: *const mc_move_limits,
    buffer_mode: u32,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_move_limits.
        let l: MoveLimits = unsafe { read_in(limits, "limits") }?.into();
        let kind = match kind {
            MC_MOVE_KIND_ABSOLUTE => MoveKind::Absolute,
            MC_MOVE_KIND_RELATIVE => MoveKind::Relative,
            MC_MOVE_KIND_ADDITIVE => MoveKind::Additive,
            v => return Err(unknown("move kind", v)),
        };
        let mode = match buffer_mode {
            MC_BUFFER_ABORTING => BufferMode::Aborting,
            MC_BUFFER_BUFFERED => BufferMode::Buffered,
            v => return Err(unknown("buffer mode", v)),
        };
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.move_with(kind, value, &l, mode)?, axis, motion)
    })
}

/// MC_MoveAdditive (Aborting): by `distance` from the target of the last move; otherwise as
/// `mc_move_absolute`.
#[no_mangle]
pub unsafe extern "C" fn mc_move_additive(
    card: mc_card,
    axis: u32,
    distance: f64,
    limits: *const mc_move_limits,
    motion: *mut mc_motion,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        mc_move(
            card,
            axis,
            MC_MOVE_KIND_ADDITIVE,
            distance,
            limits,
            MC_BUFFER_ABORTING,
            motion,
        )
    }
}

/// MC_MoveVelocity: run at the signed `velocity` (user units/s), reached within `*limits` from
/// the current state (state ContinuousMotion); call again to change it, end it with `mc_halt`
/// or `mc_stop`. `mc_motion_wait_in_velocity` waits for the velocity; the motion is never
/// done, only aborted. `motion` may be NULL. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_move_velocity(
    card: mc_card,
    axis: u32,
    velocity: f64,
    limits: *const mc_velocity_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_velocity_limits.
        let l = unsafe { read_in(limits, "limits") }?;
        let l = VelocityLimits {
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        };
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.move_velocity(velocity, &l)?, axis, motion)
    })
}

/// Jog: velocity mode at the signed `velocity` (user units/s) with the axis's jog limits
/// (`jog_max_vel`, `jog_accel`, `jog_jerk` of `mc_axis_settings`); beyond `jog_max_vel` it is
/// `MC_ERR_OUT_OF_RANGE`. Releasing the button is `mc_jog_release`. `motion` may be NULL.
#[no_mangle]
pub unsafe extern "C" fn mc_jog(
    card: mc_card,
    axis: u32,
    velocity: f64,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.jog(velocity)?, axis, motion)
    })
}

/// Releasing the jog button: MC_Halt at the axis's jog deceleration and jerk. `motion` (may be
/// NULL) receives the halt.
#[no_mangle]
pub unsafe extern "C" fn mc_jog_release(
    card: mc_card,
    axis: u32,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.jog_release()?, axis, motion)
    })
}

/// MC_SetOverride: scale the axis's velocity by `factor`, 0.0 to 2.0 (0 % to 200 %; else
/// `MC_ERR_OVERRIDE_RANGE`), planned from the current state within the acceleration and jerk
/// limits. 0 holds the axis still in its motion state; a factor above 0 resumes.
#[no_mangle]
pub extern "C" fn mc_set_override(card: mc_card, axis: u32, factor: f64) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.set_override(factor)?))
}

/// Wait until a buffered move starts (PLCopen Active). `target` may be NULL; otherwise it
/// receives the move's target (velocity mode: its velocity). `MC_ERR_ABORTED` if it was
/// aborted first, `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_motion_wait_active(
    card: mc_card,
    motion: mc_motion,
    timeout_ms: u32,
    target: *mut f64,
) -> mc_result {
    guard(|| {
        let v = motion_of(card, motion)?.wait_active(ms(timeout_ms))?;
        write_opt(target, v);
        Ok::<(), Failure>(())
    })
}

/// Wait until velocity mode reaches its velocity (PLCopen InVelocity). `velocity` may be NULL;
/// otherwise it receives the velocity. `MC_ERR_ABORTED` if it was aborted first,
/// `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_motion_wait_in_velocity(
    card: mc_card,
    motion: mc_motion,
    timeout_ms: u32,
    velocity: *mut f64,
) -> mc_result {
    guard(|| {
        let v = motion_of(card, motion)?.wait_in_velocity(ms(timeout_ms))?;
        write_opt(velocity, v);
        Ok::<(), Failure>(())
    })
}
