//! Layout 1.14: a path whose axes live on several cards of one sync bus, from C. The same thin
//! skin as [`crate::sync_bus`] over the SDK's `CardSet::path` and its `SetPath`: a path is an
//! integer handle (`mc_set_path`, like `mc_path_streamer`) that holds its own handles of the
//! cards, valid until `mc_set_path_close`.
//!
//! Each card's part is one of its groups; the path's dimensions are those groups' axes, in the
//! order the parts are given (up to 16). Every card plans every dimension alike and drives its
//! own: each axis moves, to the last bit, where one planner of all the dimensions puts it.
//! Segments are staged on every card as they are given and run from `mc_set_path_release`,
//! timed to one tick on every card; a halt, hold, override or pause is timed the same way.
//!
//! Units: each dimension's targets in its axis's user units; feeds, tolerances, the tangential
//! limits and the halt's ramp in the first dimension's.

use crate::ffi::{read_in, read_slice, Out};
use crate::handles::Handles;
use crate::path::{copy_limits, settings_of};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, Failure};
use crate::sync_bus::set_of;
use crate::types::{mc_arc, plane_of};
use motioncard_sdk::{ErrorKind, Geometry, PathPart, PathSettings, Segment, SetPath};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Dimensions a path across cards may have (`MC_PATH_MAX_DIMS`), as a length.
const DIMS: usize = 16;

/// A path across the cards of one sync bus (`mc_set_path_open`): an integer handle, never 0,
/// valid until `mc_set_path_close`.
#[allow(non_camel_case_types)]
pub type mc_set_path = u32;

/// One card's part of a path across cards: group `group` of the card `cards[card]` of
/// `mc_set_path_open`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_part {
    /// The card: its index in the `cards` array.
    pub card: u32,
    /// Its group (configured and enabled, at rest, its path idle).
    pub group: u32,
}

/// A path across cards' settings (`mc_set_path_open`), in user units: `vmax`, `amax`, `jmax`
/// per dimension (the first `ndims`, each in its axis's units); `accel` and `jerk` tangential,
/// in the first dimension's units. Start from `mc_set_path_settings_uniform`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_set_path_settings {
    /// Dimensions of the path (1..`MC_PATH_MAX_DIMS`): the axes of the parts' groups together.
    pub ndims: u32,
    /// Checked (1..`MC_PATH_SEGMENTS`) and kept by every card, as `mc_path_settings.lookahead`.
    pub lookahead: u32,
    /// `MC_EVENT_PATH_LOW_WATER` when the segments queued fall to this (0: never).
    pub low_water: u32,
    /// Tangential acceleration limit (0: from the dimensions' limits).
    pub accel: f64,
    /// Tangential jerk limit (0: from the dimensions' limits).
    pub jerk: f64,
    /// Each dimension's velocity limit (> 0).
    pub vmax: [f64; 16],
    /// Each dimension's acceleration limit (> 0).
    pub amax: [f64; 16],
    /// Each dimension's jerk limit (> 0).
    pub jmax: [f64; 16],
    /// The cards' path planner period, s (0: their default), as `mc_path_settings.plan_period`.
    pub plan_period: f64,
}

/// The paths.
static PATHS: Handles<Arc<Mutex<SetPath>>> = Handles::new("path across cards");

/// The path of handle `h`; `take` frees its handle.
fn path_of(h: mc_set_path, take: bool) -> Result<Arc<Mutex<SetPath>>, Failure> {
    PATHS.with(h, take, |p| p.clone().expect("checked"))
}

/// Run `f` on the path of handle `h` (one call at a time per path).
fn with_path<T>(
    h: mc_set_path,
    f: impl FnOnce(&mut SetPath) -> motioncard_sdk::Result<T>,
) -> Result<T, Failure> {
    let p = path_of(h, false)?;
    let mut p = p.lock().unwrap_or_else(|e| e.into_inner());
    Ok(f(&mut p)?)
}

fn dims_count(n: usize, what: &str) -> Result<(), Failure> {
    if n > DIMS {
        return Err(Failure::new(
            ErrorKind::BadAxis.code(),
            format!("{n} values in {what}: a path across cards has at most {DIMS} dimensions"),
        ));
    }
    Ok(())
}

/// Write `t` to `tick` when it is not NULL.
fn tick_out(tick: *mut u64, t: u64) {
    if let Some(o) = Out::optional(tick) {
        // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
        unsafe { o.write(t) };
    }
}

/// Settings for a path of `ndims` dimensions (1..`MC_PATH_MAX_DIMS`, else `MC_ERR_BAD_AXIS`)
/// with the same limits: look-ahead 256 segments, no low-water event, tangential limits from
/// the dimensions' (0). Nothing is checked until `mc_set_path_open`. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_settings_uniform(
    ndims: u32,
    vmax: f64,
    amax: f64,
    jmax: f64,
    settings: *mut mc_set_path_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let n = ndims as usize;
        dims_count(n, "ndims")?;
        if n == 0 {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                "ndims = 0: a path across cards has 1 to 16 dimensions",
            ));
        }
        let p = PathSettings::uniform(n, vmax, amax, jmax);
        let mut s = mc_set_path_settings {
            ndims,
            lookahead: p.lookahead as u32,
            low_water: p.low_water as u32,
            accel: p.accel,
            jerk: p.jerk,
            plan_period: p.plan_period,
            ..Default::default()
        };
        copy_limits(&p, [&mut s.vmax, &mut s.amax, &mut s.jmax]);
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// Open a path across the cards `cards[0..ncards]` of one bus (the master first; else
/// `MC_ERR_BAD_CONFIG`): its dimensions are the axes of the groups `parts[0..nparts]` (each a
/// card's index in `cards` and a group of it, configured and enabled, at rest, its path idle),
/// in order, 1 to `MC_PATH_MAX_DIMS` in all. `settings->ndims` must be that count
/// (`MC_ERR_BAD_AXIS`); each limit finite and > 0. A card index outside `cards`, a part named
/// twice, no parts or more than 16: `MC_ERR_BAD_CONFIG`. Every card's group starts the path
/// where the axes are now. Writes the handle to `*path`; close it with `mc_set_path_close`.
/// Blocks until every card has answered.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_open(
    cards: *const mc_card,
    ncards: usize,
    parts: *const mc_path_part,
    nparts: usize,
    settings: *const mc_set_path_settings,
    path: *mut mc_set_path,
) -> mc_result {
    guard(|| {
        let out = Out::new(path, "path")?;
        // SAFETY: the caller gives NULL or a readable struct.
        let s = unsafe { read_in(settings, "settings") }?;
        if nparts == 0 || nparts > DIMS {
            return Err(Failure::new(
                ErrorKind::BadConfig.code(),
                format!("{nparts} parts: a path across cards has 1 to {DIMS}"),
            ));
        }
        // SAFETY: the caller gives `nparts` readable parts (bounded above).
        let parts = unsafe { read_slice(parts, nparts, "parts") }?;
        let n = s.ndims as usize;
        dims_count(n, "the settings")?;
        // SAFETY: forwarded from this function's contract.
        let set = unsafe { set_of(cards, ncards) }?;
        let p = settings_of(
            [s.lookahead, s.low_water],
            [s.accel, s.jerk, s.plan_period],
            [&s.vmax[..n], &s.amax[..n], &s.jmax[..n]],
        );
        let parts: Vec<PathPart> = parts
            .iter()
            .map(|p| PathPart {
                card: p.card as usize,
                group: p.group as usize,
            })
            .collect();
        let sp = set.path(&parts, &p)?;
        let h = PATHS.insert(Arc::new(Mutex::new(sp))).map_err(|(f, _)| f)?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(h) };
        Ok(())
    })
}

/// The path's dimensions. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_dims(path: mc_set_path, ndims: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(ndims, "ndims")?;
        let n = with_path(path, |p| Ok(p.dims()))?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(n as u32) };
        Ok(())
    })
}

fn push(path: mc_set_path, seg: Segment) -> Result<(), Failure> {
    with_path(path, |p| p.push(&seg))
}

/// Stage a line to `target` (`n` values, one per dimension, user units: `n` must be the
/// path's dimensions, else `MC_ERR_BAD_AXIS`) at `feed`, blended into the segment before
/// within `tolerance` of the corner (0: an exact stop), on every card. A segment the cards
/// refuse is refused by each alike (their code) and staged on none; `MC_ERR_QUEUE_FULL` once
/// 256 are staged: release them first. Blocks until every card has answered.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_line(
    path: mc_set_path,
    id: u32,
    target: *const f64,
    n: usize,
    feed: f64,
    tolerance: f64,
) -> mc_result {
    guard(|| {
        dims_count(n, "target")?;
        // SAFETY: the caller gives `n` readable doubles (bounded above).
        let t = unsafe { read_slice(target, n, "target") }?;
        push(path, Segment::line(id, &t, feed, tolerance))
    })
}

/// Stage an arc in `plane` (`MC_ARC_PLANE_`: of two of the first 8 dimensions) described by
/// `*arc` (as `mc_group_move_circular`), a helix when `nhelix` targets of the other dimensions
/// (in order) are given (`helix` may be NULL when `nhelix` is 0: they stay), at `feed`,
/// blended as `mc_set_path_line`. `MC_ERR_BAD_AXIS` for a plane beyond the first 8 dimensions
/// or a helix of another count. Blocks until every card has answered.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_set_path_arc(
    path: mc_set_path,
    id: u32,
    arc: *const mc_arc,
    plane: u32,
    helix: *const f64,
    nhelix: usize,
    feed: f64,
    tolerance: f64,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_arc.
        let a = unsafe { read_in(arc, "arc") }?.to_sdk()?;
        let plane = plane_of(plane)?;
        dims_count(nhelix, "helix")?;
        // SAFETY: the caller gives `nhelix` readable doubles (bounded above).
        let h = unsafe { read_slice(helix, nhelix, "helix") }?;
        let seg = Segment {
            geometry: Geometry::Arc {
                arc: a,
                plane,
                helix: h,
            },
            ..Segment::line(id, &[], feed, tolerance)
        };
        push(path, seg)
    })
}

/// Stage a dwell: an exact stop, then a wait of `seconds`. Blocks until every card has
/// answered.
#[no_mangle]
pub extern "C" fn mc_set_path_dwell(path: mc_set_path, id: u32, seconds: f64) -> mc_result {
    guard(|| push(path, Segment::dwell(id, seconds)))
}

/// Release everything staged into every card's path on one tick (`*tick`, may be NULL), once
/// every card's path has room for it (`MC_ERR_QUEUE_FULL` after 5 s of card time without
/// room). The first release starts the path; later ones stream the rest while it runs. With
/// nothing staged: the set's tick now. Blocks until the release ran.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_release(path: mc_set_path, tick: *mut u64) -> mc_result {
    guard(|| {
        let t = with_path(path, |p| p.release())?;
        tick_out(tick, t);
        Ok(())
    })
}

/// Wait until every card's path has run everything released and its group is at rest
/// (`MC_ERR_TIMEOUT` after `timeout_ms`, card time on stepped cards: they are stepped). A group
/// stopped or faulted on one card: the others are halted at once and that is the error
/// (`MC_ERR_INVALID_STATE`). It waits 10 ms at a time: another thread may halt, hold or
/// release the path meanwhile.
#[no_mangle]
pub extern "C" fn mc_set_path_wait(path: mc_set_path, timeout_ms: u32) -> mc_result {
    guard(|| {
        let total = Duration::from_millis(timeout_ms.into());
        let chunk = Duration::from_millis(10);
        let mut waited = Duration::ZERO;
        loop {
            let step = chunk
                .min(total.saturating_sub(waited))
                .max(Duration::from_millis(1));
            match with_path(path, |p| p.wait(step)) {
                Err(f) if f.code == ErrorKind::Timeout.code() => {
                    waited += step;
                    if waited >= total {
                        return Err(Failure::new(
                            f.code,
                            format!("the path across cards was not done within {timeout_ms} ms"),
                        ));
                    }
                }
                r => return r,
            }
        }
    })
}

/// Halt the path on every card on one tick (`*tick`, may be NULL), along its geometry within
/// `deceleration` and `jerk` (> 0, the first dimension's units). What is staged is dropped.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_halt(
    path: mc_set_path,
    deceleration: f64,
    jerk: f64,
    tick: *mut u64,
) -> mc_result {
    guard(|| {
        let t = with_path(path, |p| p.halt(deceleration, jerk))?;
        tick_out(tick, t);
        Ok(())
    })
}

/// Hold the path on every card on one tick (`*tick`, may be NULL): feed override 0, it comes
/// to rest along its geometry; `mc_set_path_override` above 0 resumes it on every card
/// together.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_hold(path: mc_set_path, tick: *mut u64) -> mc_result {
    guard(|| {
        let t = with_path(path, |p| p.hold())?;
        tick_out(tick, t);
        Ok(())
    })
}

/// Set the feed override of every card's group on one tick (`*tick`, may be NULL).
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_override(
    path: mc_set_path,
    factor: f64,
    tick: *mut u64,
) -> mc_result {
    guard(|| {
        let t = with_path(path, |p| p.set_override(factor))?;
        tick_out(tick, t);
        Ok(())
    })
}

/// Pause the path at the end of a segment on every card on one tick (`on` non-zero), or let it
/// go on (`on` 0); `*tick` (may be NULL): the tick.
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_pause(
    path: mc_set_path,
    on: u32,
    tick: *mut u64,
) -> mc_result {
    guard(|| {
        let t = with_path(path, |p| p.pause(on != 0))?;
        tick_out(tick, t);
        Ok(())
    })
}

/// How far the path has come (each may be NULL): `*staged` segments given and not released,
/// `*queued` released and not finished (on the card that has the most), `*done` finished (on
/// the card that has the fewest). Never blocks (it reads the cards' windows).
#[no_mangle]
pub unsafe extern "C" fn mc_set_path_progress(
    path: mc_set_path,
    staged: *mut u32,
    queued: *mut u32,
    done: *mut u32,
) -> mc_result {
    guard(|| {
        let p = with_path(path, |p| p.progress())?;
        for (o, v) in [
            (staged, p.staged as u32),
            (queued, p.queued as u32),
            (done, p.done),
        ] {
            if let Some(o) = Out::optional(o) {
                // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
                unsafe { o.write(v) };
            }
        }
        Ok(())
    })
}

/// Free the path's handle. What runs goes on (halt it first to stop it); the cards stay open.
/// Closing twice: `MC_ERR_BAD_HANDLE`.
#[no_mangle]
pub extern "C" fn mc_set_path_close(path: mc_set_path) -> mc_result {
    guard(|| {
        drop(path_of(path, true)?);
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::result::MC_ERR_BAD_HANDLE;

    #[test]
    fn handles_are_checked_and_settings_bounded() {
        assert_eq!(mc_set_path_close(0), MC_ERR_BAD_HANDLE);
        assert_eq!(mc_set_path_dwell(0x1_0001, 1, 0.1), MC_ERR_BAD_HANDLE);
        let mut s = mc_set_path_settings::default();
        // SAFETY: a valid pointer, or NULL on purpose.
        unsafe {
            assert_eq!(
                mc_set_path_settings_uniform(17, 1.0, 1.0, 1.0, &mut s),
                ErrorKind::BadAxis.code()
            );
            assert_eq!(
                mc_set_path_settings_uniform(12, 1.0, 1.0, 1.0, std::ptr::null_mut()),
                crate::result::MC_ERR_NULL_POINTER
            );
            assert_eq!(mc_set_path_settings_uniform(12, 2.0, 3.0, 4.0, &mut s), 0);
        }
        assert_eq!(s.ndims, 12);
        assert_eq!((s.vmax[11], s.amax[11], s.jmax[11]), (2.0, 3.0, 4.0));
        assert_eq!(s.vmax[12], 0.0);
    }
}
