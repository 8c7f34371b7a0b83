//! The exported functions of axes groups, acc/dec filters, PD+ and NURBS moves: the same thin
//! skin as [`crate::api`] (check the pointers, look the handle up, call the SDK, write the
//! outputs, all inside `guard`).

use crate::codes::MC_GROUP_MAX_AXES;
use crate::ffi::{read_at, read_in, read_slice, ArrayBuf, Out};
use crate::registry::{self, mc_card, Entry};
use crate::result::{guard, mc_result, Failure, MC_ERR_BAD_HANDLE};
use crate::types::{
    filter_kind, mc_arc, mc_filter_settings, mc_group_motion, mc_group_settings, mc_group_status,
    mc_move_options, mc_normal_arc, mc_nurbs_curve, mc_nurbs_feed, mc_path_limits,
    mc_pdplus_settings, plane_of,
};
use motioncard_sdk::ErrorKind;
use motioncard_sdk::{
    clamped_uniform_knots, die_bonder_pdplus, Error, FilterSettings, Group, GroupMotion,
    GroupSettings, Nurbs, NurbsError, NurbsFeed, PathLimits, NURBS_MAX_CTRL, NURBS_MAX_DEGREE,
    NURBS_MAX_DIM,
};
use std::sync::Arc;
use std::time::Duration;

fn ms(timeout_ms: u32) -> Duration {
    Duration::from_millis(u64::from(timeout_ms))
}

/// The card and one of its groups (`MC_ERR_BAD_GROUP` for a group the card does not have).
pub(crate) fn group_of(card: mc_card, group: u32) -> Result<(Arc<Entry>, Group), Failure> {
    let e = registry::get(card)?;
    let g = e.card.group(group as usize)?;
    Ok((e, g))
}

/// Write a started group motion to `*motion` (when given) and keep it for
/// `mc_group_motion_wait`.
pub(crate) fn started(
    e: &Entry,
    m: GroupMotion,
    group: u32,
    motion: *mut mc_group_motion,
) -> Result<(), Failure> {
    let seq = m.seq();
    e.remember_group(group, m);
    if let Some(out) = Out::optional(motion) {
        // SAFETY: non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(mc_group_motion { group, seq }) };
    }
    Ok(())
}

/// Copy `n` per-axis values (a group has at most 8 axes: more is `MC_ERR_BAD_AXIS`, and
/// nothing is read).
///
/// # Safety
/// `p` is NULL or valid for reads of `n` doubles.
pub(crate) unsafe fn axis_values(p: *const f64, n: usize, what: &str) -> Result<Vec<f64>, Failure> {
    if n > MC_GROUP_MAX_AXES as usize {
        return Err(Failure::new(
            ErrorKind::BadAxis.code(),
            format!("{n} values in {what}: a group has at most {MC_GROUP_MAX_AXES} axes"),
        ));
    }
    // SAFETY: forwarded from this function's contract.
    unsafe { read_slice(p, n, what) }
}

/// Copy `n` per-axis limits, bounded like [`axis_values`].
///
/// # Safety
/// `p` is NULL or valid for reads of `n` `mc_path_limits`.
unsafe fn path_limits_array(
    p: *const mc_path_limits,
    n: usize,
) -> Result<Vec<PathLimits>, Failure> {
    if n > MC_GROUP_MAX_AXES as usize {
        return Err(Failure::new(
            ErrorKind::BadAxis.code(),
            format!("{n} axis limits: a group has at most {MC_GROUP_MAX_AXES} axes"),
        ));
    }
    // SAFETY: forwarded from this function's contract.
    let raw = unsafe { read_slice(p, n, "axis_limits") }?;
    Ok(raw.into_iter().map(PathLimits::from).collect())
}

// ---------------------------------------------------------------------------------------------
// Configuration and states
// ---------------------------------------------------------------------------------------------

/// Settings for a group of the `naxes` card axes in `axes` (group axis 0 is X, 1 is Y, …):
/// S-curve feed (`MC_GROUP_ACCDEC_PRE`), exact arcs, tolerance 2 (user units of the first axis:
/// adjust it after `mc_set_scale`). `naxes` is 1..8 (`MC_ERR_BAD_AXIS`); the axis numbers are
/// checked by `mc_group_configure`. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_group_settings_new(
    axes: *const u32,
    naxes: usize,
    settings: *mut mc_group_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        if naxes == 0 || naxes > MC_GROUP_MAX_AXES as usize {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                format!("naxes = {naxes}: a group has 1 to {MC_GROUP_MAX_AXES} axes"),
            ));
        }
        // SAFETY: the caller gives `naxes` readable axis numbers.
        let axes: Vec<usize> = unsafe { read_slice(axes, naxes, "axes") }?
            .into_iter()
            .map(|a| a as usize)
            .collect();
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write((&GroupSettings::new(&axes)).into()) };
        Ok(())
    })
}

/// Configure a group: its axes, acc/dec mode, arc interpolator, tolerance and home order. The
/// group must be disabled; the card checks every value (`MC_ERR_BAD_AXIS`,
/// `MC_ERR_AXIS_IN_OTHER_GROUP`, `MC_ERR_INCOMPATIBLE_MODE`, …). Unknown `MC_GROUP_ACCDEC_` /
/// `MC_GROUP_INTERP_` values and `home_stages` above 8 are `MC_ERR_BAD_CONFIG`; a bad home
/// order is refused as `mc_group_home` refuses one (`MC_ERR_HOME_AXIS`, `MC_ERR_HOME_TWICE`,
/// `MC_ERR_HOME_STAGE`), the card's configuration unchanged. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_group_configure(
    card: mc_card,
    group: u32,
    settings: *const mc_group_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_group_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let (_, g) = group_of(card, group)?;
        Ok(g.configure(&s.to_sdk()?)?)
    })
}

/// MC_GroupEnable: GroupDisabled → GroupStandby. Every axis of the group must be enabled and at
/// rest. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_enable(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.enable()?))
}

/// MC_GroupDisable: aborts the queued moves and leaves the axes enabled where they are. Blocks
/// until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_disable(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.disable()?))
}

/// MC_GroupReset: GroupErrorStop → GroupStandby (`MC_ERR_INVALID_STATE` in any other state).
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_reset(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.reset()?))
}

/// MC_GroupHalt: decelerate along the path (at most `deceleration`, with `jerk`, user units
/// of the first axis), then GroupStandby; the queued moves are aborted. `motion` (may be NULL)
/// receives the halt, done when the group is at rest. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_group_halt(
    card: mc_card,
    group: u32,
    deceleration: f64,
    jerk: f64,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        let (e, g) = group_of(card, group)?;
        started(&e, g.halt(deceleration, jerk)?, group, motion)
    })
}

/// MC_GroupStop: decelerate along the path and stay in GroupStopping (moves refused) until
/// `mc_group_release_stop`. Otherwise as `mc_group_halt`.
#[no_mangle]
pub unsafe extern "C" fn mc_group_stop(
    card: mc_card,
    group: u32,
    deceleration: f64,
    jerk: f64,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        let (e, g) = group_of(card, group)?;
        started(&e, g.stop(deceleration, jerk)?, group, motion)
    })
}

/// Leave GroupStopping (once at rest the group goes to GroupStandby). Blocks until the card
/// answers.
#[no_mangle]
pub extern "C" fn mc_group_release_stop(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.release_stop()?))
}

/// MC_SetOverride of a group: `feed` scales the path speed of lines and arcs, `rapid` that of
/// point-to-point moves, each 0.0 to 2.0 (0 % to 200 %; else `MC_ERR_OVERRIDE_RANGE`). The
/// active move is replanned along its path within the path limits; 0 holds the group on its
/// path, a factor above 0 resumes. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_set_override(
    card: mc_card,
    group: u32,
    feed: f64,
    rapid: f64,
) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.set_override(feed, rapid)?))
}

// ---------------------------------------------------------------------------------------------
// Moves
// ---------------------------------------------------------------------------------------------

/// Read a move's limits and options.
///
/// # Safety
/// Each pointer is NULL or readable.
unsafe fn path_and_options(
    limits: *const mc_path_limits,
    options: *const mc_move_options,
) -> Result<(PathLimits, motioncard_sdk::MoveOptions), Failure> {
    // SAFETY: the caller gives NULL or readable structs.
    let l = unsafe { read_in(limits, "limits") }?;
    // SAFETY: as above.
    let o = unsafe { read_in(options, "options") }?;
    Ok((l.into(), o.to_sdk()?))
}

#[allow(clippy::too_many_arguments)]
unsafe fn start_line(
    card: mc_card,
    group: u32,
    target: *const f64,
    n: usize,
    limits: *const mc_path_limits,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
    ptp: bool,
) -> Result<(), Failure> {
    // SAFETY: forwarded from the exported function's contract.
    let (l, o) = unsafe { path_and_options(limits, options) }?;
    // SAFETY: as above.
    let t = unsafe { axis_values(target, n, "target") }?;
    let (e, g) = group_of(card, group)?;
    let m = if ptp {
        g.move_ptp(&t, &l, o)?
    } else {
        g.move_linear(&t, &l, o)?
    };
    started(&e, m, group, motion)
}

/// MC_MoveLinearAbsolute / Relative: a straight line to `target` (`n` values, one per group
/// axis in group order, user units; `MC_ERR_BAD_AXIS` when `n` is not the group's axis count)
/// at the tangential feed of `*limits`. `options->buffered` queues it behind the moves already
/// queued (up to 32); otherwise the group must be at rest. `motion` may be NULL; otherwise it
/// receives the move to wait for. Blocks until the card has accepted or refused the move, not
/// until it is done.
#[no_mangle]
pub unsafe extern "C" fn mc_group_move_linear(
    card: mc_card,
    group: u32,
    target: *const f64,
    n: usize,
    limits: *const mc_path_limits,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { start_line(card, group, target, n, limits, options, motion, false) })
}

/// Synchronised point-to-point move (Kim eq 10–14): every axis starts and ends together, each
/// within `*limits` (the first axis's units): the axis with the longest distance moves at them
/// and the others scale. The cutting feed type becomes rapid. Otherwise as
/// `mc_group_move_linear`. `mc_group_move_ptp_axes` gives each axis its own limits.
#[no_mangle]
pub unsafe extern "C" fn mc_group_move_ptp(
    card: mc_card,
    group: u32,
    target: *const f64,
    n: usize,
    limits: *const mc_path_limits,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { start_line(card, group, target, n, limits, options, motion, true) })
}

/// Synchronised point-to-point move with each axis's own limits (Kim eq 10–14): `axis_limits`
/// holds `nlimits` `mc_path_limits`, one per group axis in group order, each in that axis's
/// user units (`MC_ERR_BAD_AXIS` when `n` or `nlimits` is not the group's axis count). The axis
/// that needs the most time within its limits sets the time, the others scale, every axis
/// stays within its own limits, and all start and end on the same servo tick. Otherwise as
/// `mc_group_move_ptp`; blocks until the card has accepted or refused the limits and the move.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_group_move_ptp_axes(
    card: mc_card,
    group: u32,
    target: *const f64,
    n: usize,
    axis_limits: *const mc_path_limits,
    nlimits: usize,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_move_options.
        let o = unsafe { read_in(options, "options") }?.to_sdk()?;
        // SAFETY: the caller gives `n` readable doubles.
        let t = unsafe { axis_values(target, n, "target") }?;
        // SAFETY: the caller gives `nlimits` readable mc_path_limits.
        let l = unsafe { path_limits_array(axis_limits, nlimits) }?;
        let (e, g) = group_of(card, group)?;
        started(&e, g.move_ptp_axes(&t, &l, o)?, group, motion)
    })
}

/// MC_MoveCircular: an arc in `plane` (`MC_ARC_PLANE_`), described by `*arc` in the plane's
/// coordinates. `helix` holds `nhelix` targets of the group's other axes (in group order),
/// which move linearly with the arc (a helix); `nhelix` 0 (helix may then be NULL) keeps them
/// where they are. The card checks the geometry: `MC_ERR_ZERO_LENGTH_ARC`,
/// `MC_ERR_CENTRE_NOT_EQUIDISTANT`, `MC_ERR_RADIUS_TOO_SMALL`, `MC_ERR_COLLINEAR_POINTS`.
/// Otherwise as `mc_group_move_linear`.
#[no_mangle]
pub unsafe extern "C" fn mc_group_move_circular(
    card: mc_card,
    group: u32,
    arc: *const mc_arc,
    plane: u32,
    helix: *const f64,
    nhelix: usize,
    limits: *const mc_path_limits,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_arc.
        let a = unsafe { read_in(arc, "arc") }?;
        // SAFETY: as above, for the limits and options.
        let (l, o) = unsafe { path_and_options(limits, options) }?;
        // SAFETY: the caller gives `nhelix` readable doubles.
        let h = unsafe { axis_values(helix, nhelix, "helix") }?;
        let (spec, plane) = (a.to_sdk()?, plane_of(plane)?);
        let (e, g) = group_of(card, group)?;
        started(&e, g.move_circular(&spec, plane, &h, &l, o)?, group, motion)
    })
}

/// Layout 1.13: MC_MoveCircular in a plane given by a normal vector (`*arc`, see
/// `mc_normal_arc`): a rest-to-rest S-curve along the arc within `*limits` (along the path, as
/// `mc_group_move_circular`). `helix` holds `nhelix` targets of the group's other axes (in
/// group order; `nhelix` 0 keeps them where they are, `helix` may then be NULL). The three
/// axes need one scale. The card checks the geometry: `MC_ERR_ARC_NORMAL` (a zero normal),
/// `MC_ERR_ARC_AXES` (an axis twice), `MC_ERR_ARC_OFF_PLANE` (the centre, or the end without
/// `rise`, off the plane), `MC_ERR_CENTRE_NOT_EQUIDISTANT` (the end off the circle),
/// `MC_ERR_ZERO_LENGTH_ARC`. The move takes two command entries, sent together
/// (`MC_ERR_ARC_PIECE` if the card saw one alone). Otherwise as `mc_group_move_linear`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_group_move_circular_normal(
    card: mc_card,
    group: u32,
    arc: *const mc_normal_arc,
    helix: *const f64,
    nhelix: usize,
    limits: *const mc_path_limits,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_normal_arc.
        let a = unsafe { read_in(arc, "arc") }?.to_sdk();
        // SAFETY: as above, for the limits and options.
        let (l, o) = unsafe { path_and_options(limits, options) }?;
        // SAFETY: the caller gives `nhelix` readable doubles.
        let h = unsafe { axis_values(helix, nhelix, "helix") }?;
        let (e, g) = group_of(card, group)?;
        started(&e, g.move_circular_normal(&a, &h, &l, o)?, group, motion)
    })
}

/// Path limits with the deceleration equal to the acceleration (`PathLimits::new`): feed
/// `velocity`, `acceleration`, `jerk`, in user units of the group's first axis. Nothing is
/// checked until a move uses them. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_limits_new(
    velocity: f64,
    acceleration: f64,
    jerk: f64,
    limits: *mut mc_path_limits,
) -> mc_result {
    guard(|| {
        let out = Out::new(limits, "limits")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(PathLimits::new(velocity, acceleration, jerk).into()) };
        Ok(())
    })
}

/// A NURBS feed with the SDK's defaults (`NurbsFeed::new`): `feed`, `accel`, `jerk` as given,
/// the default chord tolerance (`chord_tolerance` 0: one encoder count), not saturation-aware.
/// Nothing is checked until a move uses it. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_nurbs_feed_new(
    feed: f64,
    accel: f64,
    jerk: f64,
    out: *mut mc_nurbs_feed,
) -> mc_result {
    guard(|| {
        let o = Out::new(out, "out")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { o.write(NurbsFeed::new(feed, accel, jerk).into()) };
        Ok(())
    })
}

/// Build the curve of `mc_group_move_nurbs`, refusing before reading what `Nurbs::new` would
/// refuse for its size, with the same error (so nothing unbounded is copied).
///
/// # Safety
/// `ctrl` is valid for `n_ctrl * dim` doubles, `weights` for `n_ctrl`, `knots` for `n_knots`
/// (each may be NULL when its count is 0).
pub(crate) unsafe fn nurbs_curve(
    degree: u32,
    ctrl: *const f64,
    n_ctrl: usize,
    dim: u32,
    weights: *const f64,
    knots: *const f64,
    n_knots: usize,
) -> Result<Nurbs, Failure> {
    let (p, d) = (degree as usize, dim as usize);
    let refuse = |e: NurbsError| Err(Failure::from(Error::from(e)));
    // In the order of Nurbs::new's own checks.
    if p == 0 || p > NURBS_MAX_DEGREE {
        return refuse(NurbsError::BadDegree { degree: p });
    }
    if !(2..=NURBS_MAX_DIM).contains(&d) {
        return refuse(NurbsError::BadDimension { dim: d });
    }
    if n_ctrl == 0 {
        return refuse(NurbsError::ControlDataLength { len: 0, dim: d });
    }
    if n_ctrl < p + 1 {
        return refuse(NurbsError::TooFewControlPoints { n_ctrl, min: p + 1 });
    }
    if n_ctrl > NURBS_MAX_CTRL {
        return refuse(NurbsError::TooManyControlPoints {
            n_ctrl,
            max: NURBS_MAX_CTRL,
        });
    }
    if n_knots != n_ctrl + p + 1 {
        return refuse(NurbsError::KnotCountMismatch {
            knots: n_knots,
            expected: n_ctrl + p + 1,
        });
    }
    // SAFETY: the counts are bounded above; the pointers are valid for them by the contract.
    let (c, w, k) = unsafe {
        (
            read_slice(ctrl, n_ctrl * d, "ctrl")?,
            read_slice(weights, n_ctrl, "weights")?,
            read_slice(knots, n_knots, "knots")?,
        )
    };
    Ok(Nurbs::new(p, d, &c, &w, &k).map_err(Error::from)?)
}

/// Move along a NURBS curve of `degree` (1..5) in `dim` dimensions (the group's axis count):
/// `n_ctrl` control points in `ctrl` (`n_ctrl * dim` doubles, point after point, in group axis
/// order and user units, absolute; `options->relative` is ignored), `n_ctrl` weights (finite
/// and positive) and `n_knots` = `n_ctrl + degree + 1` knots (clamped, non-decreasing). The
/// curve must start where the group's path is (`MC_ERR_NURBS_START`). A curve the library
/// refuses gets the code the card gives for the same fault (`MC_ERR_NURBS_DEGREE`, `_DIMENSION`,
/// `_CTRL_COUNT`, `_KNOT_COUNT`, `_KNOTS_DECREASING`, `_KNOT_MULTIPLICITY`, `_NOT_CLAMPED`,
/// `_WEIGHT`, `_POINT`). `motion` may be NULL; otherwise it receives the move to wait for.
///
/// Blocks while the curve is sent: a begin, data entries of up to 12 values and an end, each
/// answered by the card (at most 32 entries in flight; a long curve takes many round trips),
/// not until the move is done.
#[no_mangle]
pub unsafe extern "C" fn mc_group_move_nurbs(
    card: mc_card,
    group: u32,
    degree: u32,
    ctrl: *const f64,
    n_ctrl: usize,
    dim: u32,
    weights: *const f64,
    knots: *const f64,
    n_knots: usize,
    feed: *const mc_nurbs_feed,
    options: *const mc_move_options,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or readable structs.
        let f = unsafe { read_in(feed, "feed") }?;
        // SAFETY: as above.
        let o = unsafe { read_in(options, "options") }?.to_sdk()?;
        for (p, n, what) in [(ctrl, n_ctrl, "ctrl"), (weights, n_ctrl, "weights")] {
            if p.is_null() && n > 0 {
                return Err(Failure::null(what));
            }
        }
        if knots.is_null() && n_knots > 0 {
            return Err(Failure::null("knots"));
        }
        let (e, g) = group_of(card, group)?;
        // SAFETY: the caller gives arrays of the sizes documented above.
        let curve = unsafe { nurbs_curve(degree, ctrl, n_ctrl, dim, weights, knots, n_knots) }?;
        started(&e, g.move_nurbs(&curve, &f.into(), o)?, group, motion)
    })
}

/// A path longer than the card holds (`move_nurbs_path`): the `ncurves` curves of `curves`,
/// each as the arguments of `mc_group_move_nurbs`, queued one after another behind the moves
/// already queued. Every curve is checked before anything is sent (a refused curve's message
/// names its index). Each piece starts and ends at rest (Yeh's planner runs per curve), and
/// each must start where the previous one ends. `MC_ERR_UNSUPPORTED` for an empty path (`curves`
/// may then be NULL). `motion` may be NULL; otherwise it receives the last piece's move.
///
/// Blocks while the pieces are sent, and whenever the group's queue is full, until an earlier
/// piece is done (up to `timeout_ms` for each such wait: `MC_ERR_TIMEOUT`); returns when the
/// last piece is queued, not when it is done.
#[no_mangle]
pub unsafe extern "C" fn mc_group_move_nurbs_path(
    card: mc_card,
    group: u32,
    curves: *const mc_nurbs_curve,
    ncurves: usize,
    feed: *const mc_nurbs_feed,
    timeout_ms: u32,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_nurbs_feed.
        let f = unsafe { read_in(feed, "feed") }?;
        if curves.is_null() && ncurves > 0 {
            return Err(Failure::null("curves"));
        }
        let (e, g) = group_of(card, group)?;
        let mut pieces = Vec::new();
        for i in 0..ncurves {
            // SAFETY: non-NULL (checked above), `ncurves` readable curves by the contract.
            let c = unsafe { read_at(curves, i) };
            for (p, n, what) in [
                (c.ctrl, c.n_ctrl, "ctrl"),
                (c.weights, c.n_ctrl, "weights"),
                (c.knots, c.n_knots, "knots"),
            ] {
                if p.is_null() && n > 0 {
                    return Err(Failure::null(&format!("curves[{i}].{what}")));
                }
            }
            // SAFETY: each curve's arrays have the sizes it states, by the contract.
            let piece = unsafe {
                nurbs_curve(
                    c.degree, c.ctrl, c.n_ctrl, c.dim, c.weights, c.knots, c.n_knots,
                )
            }
            .map_err(|f| Failure::new(f.code, format!("curve {i}: {}", f.message)))?;
            pieces.push(piece);
        }
        let m = g.move_nurbs_path(&pieces, &f.into(), ms(timeout_ms))?;
        started(&e, m, group, motion)
    })
}

/// A clamped knot vector with uniform interior knots for `n_ctrl` control points of `degree`
/// (`n_ctrl + degree + 1` knots from 0 to 1; the SDK's `clamped_uniform_knots`). Writes the
/// knots to `knots` and their count to `*needed`; when `len` is too small, only `*needed` and
/// `MC_ERR_BUFFER_TOO_SMALL` (`knots` may be NULL when `len` is 0, to ask for the count).
/// `MC_ERR_NURBS_DEGREE` for a degree outside 1..5, `MC_ERR_NURBS_CTRL_COUNT` for fewer than
/// `degree + 1` or more than 1024 control points. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_nurbs_clamped_uniform_knots(
    n_ctrl: usize,
    degree: u32,
    knots: *mut f64,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let out = ArrayBuf::new(knots, len, needed)?;
        let k = clamped_uniform_knots(n_ctrl, degree as usize).map_err(Error::from)?;
        // SAFETY: the caller gives `len` writable doubles at `knots` and a writable `*needed`.
        unsafe { out.fill(&k) }
    })
}

// ---------------------------------------------------------------------------------------------
// Waits and status
// ---------------------------------------------------------------------------------------------

/// Wait until a group move is done: the last move of a queue when the group is at rest and in
/// position, an earlier one when the next move takes over. `MC_ERR_ABORTED` when a halt, stop,
/// disable or fault ended it, `MC_ERR_TIMEOUT` after `timeout_ms` (0: only look). A move can be
/// waited for more than once. `MC_ERR_BAD_HANDLE` for a motion not started on this card (the
/// last 1024 group motions are kept). Blocks.
#[no_mangle]
pub extern "C" fn mc_group_motion_wait(
    card: mc_card,
    motion: mc_group_motion,
    timeout_ms: u32,
) -> mc_result {
    guard(|| {
        let e = registry::get(card)?;
        let m = e.group_motion(motion.group, motion.seq).ok_or_else(|| {
            Failure::new(
                MC_ERR_BAD_HANDLE,
                format!(
                    "no group motion with seq {} on group {} was started on card {card} (or it is older than the last {})",
                    motion.seq,
                    motion.group,
                    registry::MOTIONS_KEPT
                ),
            )
        })?;
        Ok(m.wait(ms(timeout_ms))?)
    })
}

/// Wait for the last move queued on this group by this process, as `mc_group_motion_wait`.
/// `MC_ERR_NO_MOTION` when none was queued since the card was opened (nothing to
/// wait for). Blocks.
#[no_mangle]
pub extern "C" fn mc_group_wait_done(card: mc_card, group: u32, timeout_ms: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.wait_done(ms(timeout_ms))?))
}

/// A consistent snapshot of a group's status (state, queue, active move, path position and
/// feed in counts). Does not wait for the card, as `mc_get_status`.
#[no_mangle]
pub unsafe extern "C" fn mc_group_get_status(
    card: mc_card,
    group: u32,
    status: *mut mc_group_status,
) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let s = group_of(card, group)?.1.status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s.into()) };
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Acc/dec filters and PD+
// ---------------------------------------------------------------------------------------------

/// Shin's Table 1 for the x and y axes: rapid bell 35 ms, cutting linear 30 ms, jog exponential
/// 50 ms (the card's default). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_filter_settings_shin_table1(
    settings: *mut mc_filter_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(FilterSettings::shin_table1().into()) };
        Ok(())
    })
}

/// Shin's Table 1 for the z axis: rapid bell 85 ms, cutting linear 30 ms, jog exponential 40 ms.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_filter_settings_shin_table1_z(
    settings: *mut mc_filter_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(FilterSettings::shin_table1_z().into()) };
        Ok(())
    })
}

/// One filter (`MC_FILTER_KIND_` value; unknown: `MC_ERR_BAD_CONFIG`) with time constant `tau`
/// (s) for every feed type. Nothing is checked until `mc_axis_set_filters`. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_filter_settings_all(
    kind: u32,
    tau: f64,
    settings: *mut mc_filter_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let f = FilterSettings::all(filter_kind(kind)?, tau);
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(f.into()) };
        Ok(())
    })
}

/// Set an axis's post-interpolation acc/dec filters (used by groups with
/// `MC_GROUP_ACCDEC_POST` or `_BOTH`; the move's feed type picks one). Refused while the filters
/// still hold distance (`MC_ERR_FILTER_BUSY`); an unknown `MC_FILTER_KIND_` is
/// `MC_ERR_BAD_CONFIG`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_set_filters(
    card: mc_card,
    axis: u32,
    settings: *const mc_filter_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_filter_settings.
        let f = unsafe { read_in(settings, "settings") }?.to_sdk()?;
        let a = registry::get(card)?.card.axis(axis as usize)?;
        Ok(a.set_filters(&f)?)
    })
}

/// The PD+ gains and drive model of Yeh's die bonder (Table 1), axis 0 (X) or 1 (Y), in volts
/// (`MC_ERR_BAD_AXIS` for any other axis). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_pdplus_settings_die_bonder(
    axis: u32,
    settings: *mut mc_pdplus_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        if axis > 1 {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                format!("the die bonder has axes 0 (X) and 1 (Y), not {axis}"),
            ));
        }
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(die_bonder_pdplus(axis as usize)) };
        Ok(())
    })
}

/// Switch an axis to the PD+ servo law with these gains and drive model (NaN or infinity:
/// `MC_ERR_NOT_FINITE`; the card refuses gains or a model it cannot use, and a `umax` above the
/// axis's `dac_limit_v`: `MC_ERR_BAD_CONFIG`). Needed on every group axis for a
/// saturation-aware NURBS feed. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_configure_pdplus(
    card: mc_card,
    axis: u32,
    settings: *const mc_pdplus_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_pdplus_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let a = registry::get(card)?.card.axis(axis as usize)?;
        Ok(a.configure_pdplus(&s)?)
    })
}
