//! PT/PVT streaming (layout 1.7): points of (time, position[, velocity]) run by the card as
//! cubic Hermite segments. The same thin skin as [`crate::api`]: check the pointers, look the
//! handle up, call the SDK, write the outputs, all inside `guard`.

use crate::api::{axis_of, started};
use crate::codes::MC_PVT_LEN;
use crate::ffi::{read_in, read_slice, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, unknown};
use crate::types::mc_motion;
use motioncard_sdk::{Error, PvtLimits, PvtMode, PvtPoint};

/// `mode` of `mc_pvt_begin`: PT, the card estimates each point's velocity from its neighbours
/// (the stream starts, and at a last point ends, at rest).
pub const MC_PVT_MODE_PT: u32 = 0;
/// PVT: each point's velocity as given.
pub const MC_PVT_MODE_PVT: u32 = 1;

/// One point, user units: seconds from the start of the stream, position, velocity (PVT).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_pvt_point {
    /// Seconds from the start of the stream.
    pub time: f64,
    /// Position.
    pub position: f64,
    /// Velocity (ignored in PT).
    pub velocity: f64,
}

/// A stream's limits, user units: every segment's velocity and acceleration stay within them.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_pvt_limits {
    /// Velocity.
    pub velocity: f64,
    /// Acceleration.
    pub acceleration: f64,
}

/// Open a PT/PVT stream on `axis` at its commanded position (standstill), at rest, time 0:
/// `mode` `MC_PVT_MODE_`, `limits`, a low-water event (`MC_EVENT_PVT`,
/// `MC_PVT_EVENT_LOW_WATER`) once `low_water` points or fewer are left (0: none). Blocks until
/// the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_pvt_begin(
    card: mc_card,
    axis: u32,
    mode: u32,
    limits: *const mc_pvt_limits,
    low_water: u32,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_pvt_limits.
        let l = unsafe { read_in(limits, "limits") }?;
        let mode = match mode {
            MC_PVT_MODE_PT => PvtMode::Pt,
            MC_PVT_MODE_PVT => PvtMode::Pvt,
            m => return Err(unknown("PVT mode", m)),
        };
        let (_, a) = axis_of(card, axis)?;
        let l = PvtLimits {
            velocity: l.velocity,
            acceleration: l.acceleration,
        };
        Ok(a.pvt_begin(mode, &l, low_water)?)
    })
}

/// Append `n` points (at most `MC_PVT_LEN`) to the stream; with `last` nonzero the last of them
/// ends it (PVT: at velocity 0). `free` (may be NULL) receives the points still free on the
/// card. A refused point (`MC_ERR_PVT_LIMIT`, `MC_ERR_PVT_TIME`, `MC_ERR_NOT_FINITE`,
/// `MC_ERR_OUT_OF_RANGE`, `MC_ERR_QUEUE_FULL`, `MC_ERR_PVT_SEQUENCE`) is named in the error
/// message ("PT/PVT point I ..."); the points before it were queued. Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_pvt_push(
    card: mc_card,
    axis: u32,
    points: *const mc_pvt_point,
    n: usize,
    last: u32,
    free: *mut usize,
) -> mc_result {
    guard(|| {
        if n > MC_PVT_LEN as usize {
            return Err(
                Error::BadConfig(format!("{n} points: at most {MC_PVT_LEN} a call")).into(),
            );
        }
        // SAFETY: the caller gives NULL (n = 0) or n readable mc_pvt_points.
        let pts = unsafe { read_slice(points, n, "points") }?;
        let pts: Vec<PvtPoint> = pts
            .iter()
            .map(|p| PvtPoint::new(p.time, p.position, p.velocity))
            .collect();
        let (_, a) = axis_of(card, axis)?;
        let f = a.pvt_push(&pts, last != 0)?;
        if let Some(out) = Out::optional(free) {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(f) };
        }
        Ok(())
    })
}

/// Run `axis`'s stream: `mc_motion_wait` on `*motion` (may be NULL) returns once the last
/// point is reached and the axis is in position, or `MC_ERR_ABORTED` if the stream ran dry
/// (`MC_PVT_EVENT_STARVED`; the axis stops on its stop ramp) or a halt, stop or safety stop
/// ended it. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_pvt_start(
    card: mc_card,
    axis: u32,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.pvt_start()?, axis, motion)
    })
}

/// Points queued in `axis`'s stream and free, as the card published them last tick (either
/// pointer may be NULL). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_pvt_room(
    card: mc_card,
    axis: u32,
    queued: *mut usize,
    free: *mut usize,
) -> mc_result {
    guard(|| {
        let (_, a) = axis_of(card, axis)?;
        let (q, f) = a.pvt_room();
        if let Some(out) = Out::optional(queued) {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(q) };
        }
        if let Some(out) = Out::optional(free) {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(f) };
        }
        Ok(())
    })
}
