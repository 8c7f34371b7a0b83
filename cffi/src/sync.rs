//! Synchronised motion (layout 1.7): electronic gearing, PLCopen MC_GearIn, MC_GearInPos and
//! MC_GearOut. The same thin skin as [`crate::api`]: check the pointers, look the handle up,
//! call the SDK, write the outputs, all inside `guard`.

use crate::api::{axis_of, motion_of, ms, started};
use crate::codes::{MC_MASTER_ACTUAL, MC_MASTER_ACTUAL_LEAD, MC_MASTER_AUX, MC_MASTER_COMMANDED};
use crate::ffi::{read_in, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, unknown, Failure};
use crate::types::mc_motion;
use motioncard_sdk::{Master, SyncLimits};

/// The slave's own limits while it engages, in its user units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_sync_limits {
    /// Velocity.
    pub velocity: f64,
    /// Acceleration (and deceleration).
    pub acceleration: f64,
    /// Jerk.
    pub jerk: f64,
}

pub(crate) fn master_of(kind: u32, index: u32) -> Result<Master, Failure> {
    let i = index as usize;
    match kind {
        MC_MASTER_COMMANDED => Ok(Master::Commanded(i)),
        MC_MASTER_ACTUAL => Ok(Master::Actual(i)),
        MC_MASTER_ACTUAL_LEAD => Ok(Master::ActualLead(i)),
        MC_MASTER_AUX => Ok(Master::Aux(i)),
        k => Err(unknown("master kind", k)),
    }
}

fn limits_of(l: *const mc_sync_limits) -> Result<SyncLimits, Failure> {
    // SAFETY: the caller gives NULL or a readable mc_sync_limits.
    let l = unsafe { read_in(l, "limits") }?;
    Ok(SyncLimits::new(l.velocity, l.acceleration, l.jerk))
}

/// MC_GearIn (Aborting): `axis` follows master `master` of kind `master_kind` (`MC_MASTER_`)
/// at `numerator / denominator` encoder counts per master count, computed on the card in
/// integer arithmetic (no drift). The coupling is relative to the engagement point: the slave
/// moves by the ratio times the master's travel from where both were when the card took the
/// command (`mc_gear_get_offset` reads the anchor back as an offset). A commanded master is
/// followed in the same servo tick; an actual one (its encoder, latched at the tick's start)
/// a tick behind, the slave trailing the ratio line by ratio x its velocity x the servo
/// period. It catches up within `limits`;
/// `mc_motion_wait_in_sync` on `*motion` (may be NULL) returns once it is in gear. Refused:
/// `MC_ERR_GEAR_RATIO`, `MC_ERR_SYNC_MASTER` (no such master, the axis itself, a master axis
/// disabled or in ErrorStop), `MC_ERR_INFEASIBLE` (the master runs faster than `limits` let
/// the slave follow), `MC_ERR_NOT_FINITE`, `MC_ERR_NON_POSITIVE_LIMIT`. Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_gear_in(
    card: mc_card,
    axis: u32,
    master_kind: u32,
    master: u32,
    numerator: i64,
    denominator: i64,
    limits: *const mc_sync_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let l = limits_of(limits)?;
        let m = master_of(master_kind, master)?;
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.gear_in(m, numerator, denominator, &l)?, axis, motion)
    })
}

/// MC_GearInPos (Aborting): as `mc_gear_in`, and `axis` is at `slave_position` (its user
/// units) exactly when the master is at `master_position` (the master axis's user units, or
/// an auxiliary encoder's counts), velocity and acceleration continuous on the way.
/// `MC_ERR_INFEASIBLE` if that breaks `limits` at the master's present velocity, or if the
/// master is at rest or moving away from the point. `mc_motion_wait_in_sync` returns at the
/// point. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_gear_in_pos(
    card: mc_card,
    axis: u32,
    master_kind: u32,
    master: u32,
    numerator: i64,
    denominator: i64,
    master_position: f64,
    slave_position: f64,
    limits: *const mc_sync_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let l = limits_of(limits)?;
        let m = master_of(master_kind, master)?;
        let (e, a) = axis_of(card, axis)?;
        let mv = a.gear_in_pos(
            m,
            numerator,
            denominator,
            master_position,
            slave_position,
            &l,
        )?;
        started(&e, mv, axis, motion)
    })
}

/// The engagement offset of `axis`'s gear coupling (`mc_gear_in`, `mc_gear_in_pos`), in
/// counts: in gear the slave's commanded position is `offset + ratio * master` (both in
/// counts; a commanded master's position in counts; the ratio is the coupling's numerator
/// over its denominator). The coupling is relative to the engagement: `mc_gear_in` anchors the
/// ratio line where the slave and the master were when the card took it, `mc_gear_in_pos` at
/// the sync point; the offset is where that line puts the slave with the master at 0.
/// `MC_ERR_INVALID_STATE` when the axis is not geared (or was not geared through this
/// library). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_gear_get_offset(
    card: mc_card,
    axis: u32,
    offset: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::new(offset, "offset")?;
        let (_, a) = axis_of(card, axis)?;
        let o = a.gear_offset().ok_or_else(|| {
            Failure::new(
                motioncard_sdk::ErrorKind::InvalidState.code(),
                format!("axis {axis} is not geared through this library"),
            )
        })?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(o) };
        Ok(())
    })
}

/// MC_GearOut: the slave leaves the coupling and keeps moving at its velocity (velocity mode);
/// `mc_motion_wait_in_velocity` on `*motion` (may be NULL) gives the velocity; stop it with
/// `mc_halt`. The gear motion ends `MC_ERR_ABORTED`. `MC_ERR_INVALID_STATE` unless the axis is
/// geared. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_gear_out(
    card: mc_card,
    axis: u32,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.gear_out()?, axis, motion)
    })
}

/// Wait until a gear motion is in gear (`mc_gear_in`) or in sync (`mc_gear_in_pos`).
/// `position` may be NULL; otherwise it receives the slave's commanded position then (user
/// units). `MC_ERR_ABORTED` if it was aborted first (halt, stop, gear-out, a safety stop, the
/// master lost), `MC_ERR_TIMEOUT` after `timeout_ms`. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_motion_wait_in_sync(
    card: mc_card,
    motion: mc_motion,
    timeout_ms: u32,
    position: *mut f64,
) -> mc_result {
    guard(|| {
        let p = motion_of(card, motion)?.wait_in_sync(ms(timeout_ms))?;
        if let Some(out) = Out::optional(position) {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(p) };
        }
        Ok::<(), Failure>(())
    })
}

/// The count of auxiliary encoder `k` as the card published it last tick.
/// `MC_ERR_SYNC_MASTER` for an encoder the card does not have. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_aux_encoder(card: mc_card, k: u32, count: *mut i64) -> mc_result {
    guard(|| {
        let out = Out::new(count, "count")?;
        let c = registry::get(card)?.card.aux_encoder(k as usize)?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(c) };
        Ok(())
    })
}

/// Turn auxiliary encoder `k` of a stepped sim card at `velocity` counts/s (a conveyor, a
/// handwheel). `MC_ERR_UNSUPPORTED` on any other card, `MC_ERR_BAD_CONFIG` for an encoder the
/// card does not have, `MC_ERR_NOT_FINITE`. Never blocks.
#[no_mangle]
pub extern "C" fn mc_sim_set_aux_velocity(card: mc_card, k: u32, velocity: f64) -> mc_result {
    guard(|| {
        #[cfg(feature = "emulator")]
        {
            Ok(crate::api::sim_of(card)?.set_aux_velocity(k as usize, velocity)?)
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (card, k, velocity);
            Err(crate::api::no_emulator())
        }
    })
}
