//! Camming (layout 1.7): cam tables in the card's RAM, MC_CamIn, a table switch at the end of
//! a cycle, MC_CamOut. The same thin skin as [`crate::api`]: check the pointers, look the
//! handle up, call the SDK, write the outputs, all inside `guard`.

use crate::api::{axis_of, motion_of, ms, started};
use crate::codes::{MC_CAM_CUBIC, MC_CAM_MAX_POINTS, MC_CAM_PERIODIC};
use crate::ffi::{read_in, read_slice, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, unknown, Failure};
use crate::sync::{master_of, mc_sync_limits};
use crate::types::mc_motion;
use motioncard_sdk::{CamSettings, Error, SyncLimits};

/// Which cam table, and how it maps the master onto the slave (counts): slave = slave_offset +
/// slave_scale × table((master − master_offset) / master_scale).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_cam_settings {
    /// Table 0 .. `MC_CAM_TABLES` − 1.
    pub table: u32,
    /// Subtracted from the master's position, counts.
    pub master_offset: f64,
    /// Added to the table's slave position, counts.
    pub slave_offset: f64,
    /// Divides the master's position (nonzero).
    pub master_scale: f64,
    /// Multiplies the table's slave position (nonzero).
    pub slave_scale: f64,
    /// Nonzero: PLCopen StartMode relative (the card shifts the slave offset so the cam starts
    /// where the slave stands). 0: absolute, ramped in within the limits.
    pub relative: u32,
}

fn cam_of(c: *const mc_cam_settings) -> Result<CamSettings, Failure> {
    // SAFETY: the caller gives NULL or a readable mc_cam_settings.
    let c = unsafe { read_in(c, "cam") }?;
    Ok(CamSettings {
        table: c.table as usize,
        master_offset: c.master_offset,
        slave_offset: c.slave_offset,
        master_scale: c.master_scale,
        slave_scale: c.slave_scale,
        relative: c.relative != 0,
    })
}

fn limits_of(l: *const mc_sync_limits) -> Result<SyncLimits, Failure> {
    // SAFETY: the caller gives NULL or a readable mc_sync_limits.
    let l = unsafe { read_in(l, "limits") }?;
    Ok(SyncLimits::new(l.velocity, l.acceleration, l.jerk))
}

/// Load cam table `table` with `n` points (`master[i]`, `slave[i]`, counts; the master strictly
/// increasing; 2 ..= `MC_CAM_MAX_POINTS`, cubic 3 ..), `flags` `MC_CAM_CUBIC`,
/// `MC_CAM_PERIODIC`. `MC_ERR_CAM_TABLE` if the card refuses it (or a slave follows it),
/// `MC_ERR_NOT_FINITE`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_cam_load_table(
    card: mc_card,
    table: u32,
    master: *const f64,
    slave: *const f64,
    n: usize,
    flags: u32,
) -> mc_result {
    guard(|| {
        if flags & !(MC_CAM_CUBIC | MC_CAM_PERIODIC) != 0 {
            return Err(unknown("cam table flags", flags));
        }
        if n > MC_CAM_MAX_POINTS as usize {
            return Err(
                Error::BadConfig(format!("{n} points: at most {MC_CAM_MAX_POINTS}")).into(),
            );
        }
        // SAFETY: the caller gives NULL (n = 0) or n readable doubles in each.
        let (m, s) = unsafe {
            (
                read_slice(master, n, "master")?,
                read_slice(slave, n, "slave")?,
            )
        };
        let pts: Vec<(f64, f64)> = m.into_iter().zip(s).collect();
        let e = registry::get(card)?;
        Ok(e.card.load_cam_table(
            table as usize,
            &pts,
            flags & MC_CAM_CUBIC != 0,
            flags & MC_CAM_PERIODIC != 0,
        )?)
    })
}

/// MC_CamIn (Aborting): `axis` follows master `master` of kind `master_kind` (`MC_MASTER_`)
/// through `cam`, caught up within `limits`; `mc_motion_wait_in_sync` on `*motion` (may be
/// NULL) returns once it is on the cam. `MC_ERR_CAM_TABLE` for a table not loaded. Blocks until
/// the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_cam_in(
    card: mc_card,
    axis: u32,
    master_kind: u32,
    master: u32,
    cam: *const mc_cam_settings,
    limits: *const mc_sync_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (c, l) = (cam_of(cam)?, limits_of(limits)?);
        let m = master_of(master_kind, master)?;
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.cam_in(m, &c, &l)?, axis, motion)
    })
}

/// On an axis that cams: `cam`'s table takes over at the end of the current cycle, the slave's
/// position continuous (`mc_motion_wait_cam_switch` on `*motion`, may be NULL).
/// `MC_ERR_INVALID_STATE` if the axis does not cam. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_cam_switch(
    card: mc_card,
    axis: u32,
    master_kind: u32,
    master: u32,
    cam: *const mc_cam_settings,
    limits: *const mc_sync_limits,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (c, l) = (cam_of(cam)?, limits_of(limits)?);
        let m = master_of(master_kind, master)?;
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.cam_switch(m, &c, &l)?, axis, motion)
    })
}

/// MC_CamOut: the slave leaves the cam in velocity mode at its velocity
/// (`mc_motion_wait_in_velocity` on `*motion`, may be NULL). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_cam_out(card: mc_card, axis: u32, motion: *mut mc_motion) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.cam_out()?, axis, motion)
    })
}

/// Wait until the table switch of `mc_cam_switch` took place. `position` may be NULL;
/// otherwise it receives the slave's commanded position then. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_motion_wait_cam_switch(
    card: mc_card,
    motion: mc_motion,
    timeout_ms: u32,
    position: *mut f64,
) -> mc_result {
    guard(|| {
        let p = motion_of(card, motion)?.wait_cam_switch(ms(timeout_ms))?;
        if let Some(out) = Out::optional(position) {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(p) };
        }
        Ok::<(), Failure>(())
    })
}
