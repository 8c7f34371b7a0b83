//! The exported functions of a group's continuous path (layout 1.6): a deep buffer of
//! segments on the card (lines, arcs and helices, dwells) with look-ahead and corner blending
//! within each segment's tolerance, output actions at points of the path, and the card's
//! digital outputs. The same thin skin as [`crate::group`].
//!
//! Units are the group's: targets in each axis's user units; feeds, tolerances, distances and
//! the tangential limits in the first group axis's.

use crate::codes::{
    MC_CARD_OUTPUTS, MC_GROUP_MAX_AXES, MC_OUTPUT_AT_DISTANCE, MC_OUTPUT_AT_END,
    MC_OUTPUT_AT_START, MC_PATH_BUFFER_ABORTING, MC_PATH_BUFFER_BLEND_HIGH,
    MC_PATH_BUFFER_BLEND_LOW, MC_PATH_BUFFER_BLEND_NEXT, MC_PATH_BUFFER_BLEND_PREVIOUS,
    MC_PATH_BUFFER_BUFFERED, MC_PATH_TRANSITION_CORNER_DISTANCE, MC_PATH_TRANSITION_MAX_DEVIATION,
    MC_PATH_TRANSITION_NONE, MC_PATH_TRANSITION_TIME_SHIFT,
};
use crate::ffi::{read_at, read_in, Out};
use crate::group::{axis_values, group_of, nurbs_curve, started};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, unknown, Failure};
use crate::types::{mc_arc, mc_group_motion, mc_nurbs_curve, plane_of};
use firmware_proto::cmd::{Cmd, GroupCmd};
use motioncard_sdk::{
    Error, ErrorKind, Geometry, Group, OutputAt, PathBuffer, PathItem, PathProgress, PathSettings,
    PauseState, Segment, StreamError, Transition,
};
use std::cell::RefCell;
use std::ffi::c_void;

/// Most axes in a group, as a length.
const MAX_AXES: usize = MC_GROUP_MAX_AXES as usize;

/// `mc_path_segment.kind`: a straight line to `target` (`naxes` values, one per group axis).
pub const MC_SEGMENT_LINE: u32 = 0;
/// An arc in `plane` described by `arc` (a helix when `naxes` targets of the group's other
/// axes are given in `target`).
pub const MC_SEGMENT_ARC: u32 = 1;
/// An exact stop, then a wait of `seconds` (0 < seconds <= the card's longest move time).
pub const MC_SEGMENT_DWELL: u32 = 2;
/// Not a segment: an output action (`output`, `on`, `at`, `distance`) for the next motion
/// segment queued after it. It takes no room in the buffer; at most 8 may wait for their
/// segment (`MC_ERR_PATH_OUTPUT`).
pub const MC_SEGMENT_OUTPUT: u32 = 3;
/// A NURBS curve (`curve`, as the arguments of `mc_group_move_nurbs`: control points in group
/// axis order and user units), run within `fit_tolerance` (> 0, user units of the first axis)
/// of the curve. It must start within `fit_tolerance` of where the segment before ends
/// (`MC_ERR_NURBS_START`; `relative`: its control points are from there). On the card it takes
/// one buffer entry per piece (quintics fitted to the curve, curvature-continuous where it
/// is): `mc_group_path_stream` waits until they fit, `mc_group_path_push` answers
/// `MC_ERR_QUEUE_FULL`; `MC_ERR_PATH_CURVE` for a cusp or more pieces than the buffer holds.
/// The curve's arrays are read during the call that queues it.
pub const MC_SEGMENT_NURBS: u32 = 4;

/// Layout 1.12: an arc in the plane of three group axes given by a normal vector
/// (`plane_axes`, `normal`): counter-clockwise about the normal (the right-hand rule), in the
/// plane through the start, around `centre` to `end` (both on the three axes, in order; an end
/// at the start: a full turn); `rise` non-zero lets the end lie off the plane along the normal
/// (a helix along it). The targets of the group's other axes in group order (a helix) in
/// `target`, or none (`naxes` 0). The three axes need one scale. The card refuses a zero
/// normal (`MC_ERR_ARC_NORMAL`), an axis twice (`MC_ERR_ARC_AXES`), a centre or end off the
/// plane (`MC_ERR_ARC_OFF_PLANE`) or an end off the circle (`MC_ERR_CENTRE_NOT_EQUIDISTANT`) by
/// more than the group's tolerance.
pub const MC_SEGMENT_ARC_NORMAL: u32 = 5;

/// A group's path configuration (`mc_group_configure_path`), in user units: `vmax`, `amax`,
/// `jmax` per group axis (the first `naxes`, in group order, each in its axis's units);
/// `accel` and `jerk` tangential, in the first axis's units. Start from
/// `mc_path_settings_uniform`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_settings {
    /// Axes in the group: how many values of `vmax`, `amax`, `jmax` are used.
    pub naxes: u32,
    /// Checked (1..`MC_PATH_SEGMENTS`) and kept by the card; it looks ahead by distance, over
    /// as many queued segments as braking from its speed takes, not this many.
    pub lookahead: u32,
    /// `MC_EVENT_PATH_LOW_WATER` when the segments queued fall to this (0: never).
    pub low_water: u32,
    /// Tangential acceleration limit (0: from the axes' limits).
    pub accel: f64,
    /// Tangential jerk limit (0: from the axes' limits).
    pub jerk: f64,
    /// Each axis's velocity limit (> 0).
    pub vmax: [f64; 8],
    /// Each axis's acceleration limit (> 0).
    pub amax: [f64; 8],
    /// Each axis's jerk limit (> 0).
    pub jmax: [f64; 8],
    /// The card's path planner period, s (0: its default, 1 ms; at most 10 ms), rounded to
    /// whole servo ticks: the look-ahead and the speed planner run once a period, every servo
    /// tick in between follows the jerk-limited profile they chose.
    pub plan_period: f64,
    /// Nonzero: `mc_group_path_stream` sends runs of lines that sample a smooth curve as that
    /// curve, a cubic B-spline fitted within their tolerance (kept by the library, not the
    /// card; a run sent as one curve reports the id of its last line). 0: every line as it is.
    pub chord_fit: u32,
}

/// One item of a path: a segment (`MC_SEGMENT_LINE`, `_ARC`, `_NURBS`, `_DWELL`) or an output
/// action (`MC_SEGMENT_OUTPUT`). Each kind reads only its own fields (listed with them); start
/// from `mc_path_segment_line`, `_arc`, `_nurbs`, `_dwell` or `_output`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_segment {
    /// `MC_SEGMENT_` value.
    pub kind: u32,
    /// Segments: the user's id, reported by `MC_EVENT_SEGMENT_START` / `_END` and in
    /// `mc_group_status.path_id`.
    pub id: u32,
    /// Lines and arcs: the path speed (> 0), user units of the first group axis per second.
    pub feed: f64,
    /// Lines and arcs: `MC_PATH_BUFFER_` value.
    pub buffer: u32,
    /// Lines and arcs: `MC_PATH_TRANSITION_` value (used by the blending buffer modes).
    pub transition: u32,
    /// Lines and arcs: the blend's size for `transition` (>= 0), user units of the first axis.
    pub tolerance: f64,
    /// Lines and arcs: non-zero for targets (and arc points) relative to where the segment
    /// before ends.
    pub relative: u32,
    /// Segments: non-zero on the last segment of a program (its stop is the end, not
    /// starvation: no `MC_EVENT_PATH_STARVED`).
    pub last: u32,
    /// Lines and arcs: how many values of `target` are used.
    pub naxes: u32,
    /// Arcs: `MC_ARC_PLANE_` value.
    pub plane: u32,
    /// Lines: the end point, one value per group axis in group order. Arcs: the targets of the
    /// group's other axes in group order (a helix), or none (`naxes` 0).
    pub target: [f64; 8],
    /// Arcs: the arc in its plane's coordinates.
    pub arc: mc_arc,
    /// Dwells: the wait, seconds.
    pub seconds: f64,
    /// Output actions: the output, 0..`MC_CARD_OUTPUTS` - 1.
    pub output: u32,
    /// Output actions: non-zero sets the output, zero clears it.
    pub on: u32,
    /// Output actions: `MC_OUTPUT_AT_` value.
    pub at: u32,
    /// Output actions with `MC_OUTPUT_AT_DISTANCE`: the distance into the segment.
    pub distance: f64,
    /// NURBS curves: the curve (its arrays read while the item is queued).
    pub curve: mc_nurbs_curve,
    /// NURBS curves: the largest distance of the path from the curve (> 0).
    pub fit_tolerance: f64,
    /// Normal-vector arcs (layout 1.12): the plane's three group axes.
    pub plane_axes: [u32; 3],
    /// Normal-vector arcs: the normal on them (any length but 0).
    pub normal: [f64; 3],
    /// Normal-vector arcs: the centre on the three axes.
    pub centre: [f64; 3],
    /// Normal-vector arcs: the end on the three axes.
    pub end: [f64; 3],
    /// Normal-vector arcs: non-zero lets the end lie off the plane along the normal.
    pub rise: u32,
}

/// How far `mc_group_path_stream` has come (given to its progress callback).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_progress {
    /// Items sent to the card.
    pub sent: u64,
    /// Items the card accepted (it lags `sent` by the commands in flight).
    pub accepted: u64,
    /// Segments the card finished since the group was enabled (wrapping).
    pub done: u32,
    /// Segments queued on the card.
    pub queued: u32,
}

impl From<PathProgress> for mc_path_progress {
    fn from(p: PathProgress) -> Self {
        Self {
            sent: p.sent,
            accepted: p.accepted,
            done: p.done,
            queued: p.queued,
        }
    }
}

/// The progress callback of `mc_group_path_stream`: called on the calling thread, inside
/// `mc_group_path_stream`, after each item is sent. `progress` is valid only during the call;
/// `user` is the pointer given to `mc_group_path_stream`. It must return (not unwind or
/// longjmp out of the library).
#[allow(non_camel_case_types)]
pub type mc_path_progress_callback =
    Option<unsafe extern "C" fn(progress: *const mc_path_progress, user: *mut c_void)>;

fn path_mode(what: &str, v: u32) -> Failure {
    Failure::new(ErrorKind::PathMode.code(), format!("unknown {what} {v}"))
}

fn axis_count(n: u32, what: &str) -> Result<usize, Failure> {
    if n as usize > MAX_AXES {
        return Err(Failure::new(
            ErrorKind::BadAxis.code(),
            format!("{n} values in {what}: a group has at most {MAX_AXES} axes"),
        ));
    }
    Ok(n as usize)
}

impl mc_path_segment {
    /// The SDK's item. Unknown `MC_PATH_BUFFER_`, `MC_PATH_TRANSITION_` and `MC_OUTPUT_AT_`
    /// values are `MC_ERR_PATH_MODE` (as the card calls them), an unknown kind, plane or arc
    /// mode `MC_ERR_BAD_CONFIG`.
    ///
    /// # Safety
    /// A NURBS item's `curve` arrays are readable for their counts.
    pub(crate) unsafe fn to_sdk(self) -> Result<PathItem, Failure> {
        let geometry = match self.kind {
            MC_SEGMENT_LINE => Geometry::Line {
                target: self.target[..axis_count(self.naxes, "target")?].to_vec(),
            },
            MC_SEGMENT_ARC => Geometry::Arc {
                arc: self.arc.to_sdk()?,
                plane: plane_of(self.plane)?,
                helix: self.target[..axis_count(self.naxes, "target")?].to_vec(),
            },
            MC_SEGMENT_ARC_NORMAL => Geometry::ArcNormal {
                axes: self.plane_axes.map(|a| a as usize),
                normal: self.normal,
                centre: self.centre,
                end: self.end,
                rise: self.rise != 0,
                helix: self.target[..axis_count(self.naxes, "target")?].to_vec(),
            },
            MC_SEGMENT_NURBS => {
                let c = &self.curve;
                for (p, n, what) in [
                    (c.ctrl, c.n_ctrl, "curve.ctrl"),
                    (c.weights, c.n_ctrl, "curve.weights"),
                    (c.knots, c.n_knots, "curve.knots"),
                ] {
                    if p.is_null() && n > 0 {
                        return Err(Failure::null(what));
                    }
                }
                // SAFETY: the arrays are readable for their counts by this function's contract.
                let curve = unsafe {
                    nurbs_curve(
                        c.degree, c.ctrl, c.n_ctrl, c.dim, c.weights, c.knots, c.n_knots,
                    )
                }?;
                Geometry::Nurbs {
                    curve,
                    fit_tolerance: self.fit_tolerance,
                }
            }
            MC_SEGMENT_DWELL => {
                let mut s = Segment::dwell(self.id, self.seconds);
                s.last = self.last != 0;
                return Ok(s.into());
            }
            MC_SEGMENT_OUTPUT => {
                let at = match self.at {
                    MC_OUTPUT_AT_START => OutputAt::Start,
                    MC_OUTPUT_AT_END => OutputAt::End,
                    MC_OUTPUT_AT_DISTANCE => OutputAt::Distance(self.distance),
                    v => return Err(path_mode("output point (MC_OUTPUT_AT_)", v)),
                };
                let output = u8::try_from(self.output).map_err(|_| {
                    Failure::new(
                        ErrorKind::PathOutput.code(),
                        format!(
                            "output {}: the card has outputs 0..{}",
                            self.output,
                            MC_CARD_OUTPUTS - 1
                        ),
                    )
                })?;
                return Ok(PathItem::Output {
                    output,
                    on: self.on != 0,
                    at,
                });
            }
            v => return Err(unknown("path segment kind", v)),
        };
        let buffer = match self.buffer {
            MC_PATH_BUFFER_ABORTING => PathBuffer::Aborting,
            MC_PATH_BUFFER_BUFFERED => PathBuffer::Buffered,
            MC_PATH_BUFFER_BLEND_LOW => PathBuffer::BlendingLow,
            MC_PATH_BUFFER_BLEND_PREVIOUS => PathBuffer::BlendingPrevious,
            MC_PATH_BUFFER_BLEND_NEXT => PathBuffer::BlendingNext,
            MC_PATH_BUFFER_BLEND_HIGH => PathBuffer::BlendingHigh,
            v => return Err(path_mode("buffer mode (MC_PATH_BUFFER_)", v)),
        };
        let transition = match self.transition {
            MC_PATH_TRANSITION_NONE => Transition::None,
            MC_PATH_TRANSITION_MAX_DEVIATION => Transition::MaxDeviation(self.tolerance),
            MC_PATH_TRANSITION_CORNER_DISTANCE => Transition::CornerDistance(self.tolerance),
            MC_PATH_TRANSITION_TIME_SHIFT => Transition::TimeShift(self.tolerance),
            v => return Err(path_mode("transition mode (MC_PATH_TRANSITION_)", v)),
        };
        Ok(PathItem::Segment(Segment {
            id: self.id,
            geometry,
            feed: self.feed,
            buffer,
            transition,
            relative: self.relative != 0,
            last: self.last != 0,
            // (the chord fitter's tolerance is the transition's: mc_path_settings.chord_fit)
            fit_tolerance: None,
        }))
    }
}

/// The group's axis count and each axis's |counts per user unit|, and the path scale (counts
/// per user unit of path quantities), as the SDK converts them.
///
/// The SDK keeps the scales and the group's axes to itself (no public accessor); its public
/// `Group::path_command` applies them, so a probe line of unit targets, converted and never
/// sent, gives them back: decoded, its feed is the path scale and its targets the scales. The
/// probe is refused as `BadAxis` until its length is the group's.
fn group_scales(g: &Group) -> Result<(usize, f64, [f64; MAX_AXES]), Failure> {
    for n in 1..=MAX_AXES {
        let probe = PathItem::Segment(Segment::line(0, &[1.0; MAX_AXES][..n], 1.0, 0.0));
        match g.path_command(&probe) {
            Ok(c) => {
                let Ok(Cmd::Group(GroupCmd::PathLine(line))) = Cmd::from_command(&c) else {
                    return Err(Failure::new(
                        ErrorKind::Protocol.code(),
                        "a path line's command did not decode as one",
                    ));
                };
                let mut scales = [0.0; MAX_AXES];
                for (s, a) in scales.iter_mut().zip(&line.targets[..n]) {
                    *s = a.abs();
                }
                return Ok((n, line.feed, scales));
            }
            Err(Error::BadAxis { .. }) => continue,
            Err(e) => return Err(e.into()),
        }
    }
    Err(Failure::new(
        ErrorKind::BadAxis.code(),
        "the group's axis count is not 1..8",
    ))
}

fn stream_failure(e: StreamError) -> Failure {
    let f = Failure::from(e.error);
    Failure::new(f.code, format!("path item {}: {}", e.index, f.message))
}

// ---------------------------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------------------------

/// The SDK's settings of a C struct's fields (`mc_path_settings`, `mc_set_path_settings`):
/// `[lookahead, low_water]`, `[accel, jerk, plan_period]`, and the limits `[vmax, amax, jmax]`.
pub(crate) fn settings_of(
    [lookahead, low_water]: [u32; 2],
    [accel, jerk, plan_period]: [f64; 3],
    [vmax, amax, jmax]: [&[f64]; 3],
) -> PathSettings {
    PathSettings {
        lookahead: lookahead as usize,
        low_water: low_water as usize,
        accel,
        jerk,
        vmax: vmax.to_vec(),
        amax: amax.to_vec(),
        jmax: jmax.to_vec(),
        plan_period,
        ..PathSettings::uniform(vmax.len().max(1), 1.0, 1.0, 1.0)
    }
}

/// `p`'s limits into a C struct's `[vmax, amax, jmax]` (the first `p`'s count of each).
pub(crate) fn copy_limits(p: &PathSettings, [vmax, amax, jmax]: [&mut [f64]; 3]) {
    let n = p.vmax.len();
    vmax[..n].copy_from_slice(&p.vmax);
    amax[..n].copy_from_slice(&p.amax);
    jmax[..n].copy_from_slice(&p.jmax);
}

/// Path settings for `naxes` axes (1..8, else `MC_ERR_BAD_AXIS`) with the same limits:
/// look-ahead 256 segments, no low-water event, tangential limits from the axes' (0), chords
/// fitted into curves. Nothing is checked until `mc_group_configure_path`. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_settings_uniform(
    naxes: u32,
    vmax: f64,
    amax: f64,
    jmax: f64,
    settings: *mut mc_path_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let n = axis_count(naxes, "naxes")?;
        if n == 0 {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                "naxes = 0: a group has 1 to 8 axes",
            ));
        }
        let p = PathSettings::uniform(n, vmax, amax, jmax);
        let mut s = mc_path_settings {
            naxes,
            lookahead: p.lookahead as u32,
            low_water: p.low_water as u32,
            accel: p.accel,
            jerk: p.jerk,
            plan_period: p.plan_period,
            chord_fit: p.chord_fit.into(),
            ..Default::default()
        };
        copy_limits(&p, [&mut s.vmax, &mut s.amax, &mut s.jmax]);
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// Configure a group's path: its look-ahead, low-water mark and limits. The group must be
/// configured (`MC_ERR_GROUP_DISABLED`) and its path idle, nothing queued and at rest
/// (`MC_ERR_PATH_BUSY`). `naxes` must be the group's axis count (`MC_ERR_BAD_AXIS`); each axis
/// limit finite and > 0 (`MC_ERR_NOT_FINITE`, `MC_ERR_NON_POSITIVE_LIMIT`); the card refuses a
/// look-ahead outside 1..`MC_PATH_SEGMENTS` or a low-water mark above it (`MC_ERR_BAD_CONFIG`),
/// a planner period that is not a number (`MC_ERR_NOT_FINITE`) or outside 0..0.01 s
/// (`MC_ERR_OUT_OF_RANGE`), and limits it cannot run at its servo rate (`MC_ERR_LIMIT_RANGE`).
/// Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_group_configure_path(
    card: mc_card,
    group: u32,
    settings: *const mc_path_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_path_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let n = axis_count(s.naxes, "the settings")?;
        let p = PathSettings {
            chord_fit: s.chord_fit != 0,
            ..settings_of(
                [s.lookahead, s.low_water],
                [s.accel, s.jerk, s.plan_period],
                [&s.vmax[..n], &s.amax[..n], &s.jmax[..n]],
            )
        };
        let (_, g) = group_of(card, group)?;
        Ok(g.configure_path(&p)?)
    })
}

/// The path configuration the card holds for a group (read back from the card: its reset
/// values until the first `mc_group_configure_path`), converted to user units with the scales
/// in force now; `naxes` is the group's axis count, the unused limits 0. The group must be
/// configured (`MC_ERR_GROUP_DISABLED`). Blocks until the card answers (layout 1.8: the
/// settings are read back with a command).
#[no_mangle]
pub unsafe extern "C" fn mc_group_get_path_settings(
    card: mc_card,
    group: u32,
    settings: *mut mc_path_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let (_, g) = group_of(card, group)?;
        g.status()?; // a card that is stalled, before reading its window
        let (n, path_scale, scales) = group_scales(&g)?;
        let b = g.path_config()?;
        let mut s = mc_path_settings {
            naxes: n as u32,
            lookahead: b.lookahead,
            low_water: b.low_water,
            accel: b.accel / path_scale,
            jerk: b.jerk / path_scale,
            plan_period: b.plan_period,
            chord_fit: g.chord_fit().into(),
            ..Default::default()
        };
        for (i, scale) in scales.iter().enumerate().take(n) {
            s.vmax[i] = b.vmax[i] / scale;
            s.amax[i] = b.amax[i] / scale;
            s.jmax[i] = b.jmax[i] / scale;
        }
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// Free segments in a group's path buffer (`MC_PATH_SEGMENTS` when idle). Does not wait for
/// the card, as `mc_group_get_status`.
#[no_mangle]
pub unsafe extern "C" fn mc_group_path_free(
    card: mc_card,
    group: u32,
    free: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(free, "free")?;
        let n = group_of(card, group)?.1.path_free()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(n.min(u32::MAX as usize) as u32) };
        Ok(())
    })
}

/// No pause asked for (`mc_group_path_pause_state`).
pub const MC_PATH_PAUSE_NONE: u32 = 0;
/// Braking for the pause point.
pub const MC_PATH_PAUSE_PAUSING: u32 = 1;
/// At rest on it.
pub const MC_PATH_PAUSE_PAUSED: u32 = 2;

/// Pause a group's path at the end of a segment: it comes to rest at the end of the first
/// segment it can stop at within its limits from where it is (an exact stop or a dwell's end
/// ahead, or the first segment end beyond its braking distance; with nothing queued and at
/// rest, at once), and holds there. The end of a segment followed by a blend is the blend's
/// middle, within the segment's tolerance of its programmed end. Nothing queued changes and
/// more may be queued; `mc_group_path_resume` goes on along the same path. The card posts
/// `MC_EV_PATH_PAUSED` (value: the segment's id) on coming to rest. Blocks until the card
/// answers.
#[no_mangle]
pub extern "C" fn mc_group_path_pause(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.path_pause()?))
}

/// End a pause (`mc_group_path_pause`): the path goes on from the pause point (asked before
/// it got there, it does not stop). Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_path_resume(card: mc_card, group: u32) -> mc_result {
    guard(|| Ok(group_of(card, group)?.1.path_resume()?))
}

/// Where a group's pause is: `*state` `MC_PATH_PAUSE_*`, `*id` (may be NULL) the id of the
/// segment it ended when paused (0 when none ran; else 0). From the status: does not wait
/// for the card.
#[no_mangle]
pub unsafe extern "C" fn mc_group_path_pause_state(
    card: mc_card,
    group: u32,
    state: *mut u32,
    id: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(state, "state")?;
        let out_id = Out::optional(id);
        let (st, i) = match group_of(card, group)?.1.path_pause_state()? {
            PauseState::None => (MC_PATH_PAUSE_NONE, 0),
            PauseState::Pausing => (MC_PATH_PAUSE_PAUSING, 0),
            PauseState::Paused { id } => (MC_PATH_PAUSE_PAUSED, id),
        };
        // SAFETY: checked non-NULL / optional; valid for writes by the caller's contract.
        unsafe {
            out.write(st);
            if let Some(o) = out_id {
                o.write(i);
            }
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Items
// ---------------------------------------------------------------------------------------------

/// A line to `target` (`n` values, one per group axis, user units; at most 8, else
/// `MC_ERR_BAD_AXIS`) at `feed`, blended into the segment before within `tolerance` of the
/// corner (`MC_PATH_BUFFER_BLEND_LOW`, `MC_PATH_TRANSITION_MAX_DEVIATION`; 0: an exact stop),
/// absolute, not last. Nothing else is checked until it is queued. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_segment_line(
    id: u32,
    target: *const f64,
    n: usize,
    feed: f64,
    tolerance: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        // SAFETY: the caller gives `n` readable doubles.
        let t = unsafe { axis_values(target, n, "target") }?;
        let mut s = mc_path_segment {
            kind: MC_SEGMENT_LINE,
            id,
            feed,
            buffer: MC_PATH_BUFFER_BLEND_LOW,
            transition: MC_PATH_TRANSITION_MAX_DEVIATION,
            tolerance,
            naxes: n as u32,
            ..Default::default()
        };
        s.target[..n].copy_from_slice(&t);
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// A normal-vector arc segment (`MC_SEGMENT_ARC_NORMAL`, layout 1.12) in the plane of group
/// axes `axes[3]` with `normal[3]`, around `centre[3]` to `end[3]` (on those axes) at `feed`,
/// blended as `mc_path_segment_line`; the other axes stay (set `target` and `naxes` for a
/// helix, `rise` for a rise along the normal). Never blocks.
///
/// # Safety
/// `axes`, `normal`, `centre` and `end` are NULL or point to 3 readable values each;
/// `segment` is NULL or valid for writes.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_path_segment_arc_normal(
    id: u32,
    axes: *const u32,
    normal: *const f64,
    centre: *const f64,
    end: *const f64,
    feed: f64,
    tolerance: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        let three = |p: *const f64, what: &'static str| -> Result<[f64; 3], Failure> {
            if p.is_null() {
                return Err(Failure::null(what));
            }
            // SAFETY: non-NULL, 3 readable doubles by the caller's contract.
            Ok(unsafe { [*p, *p.add(1), *p.add(2)] })
        };
        if axes.is_null() {
            return Err(Failure::null("axes"));
        }
        // SAFETY: non-NULL, 3 readable values by the caller's contract.
        let ax = unsafe { [*axes, *axes.add(1), *axes.add(2)] };
        let s = mc_path_segment {
            kind: MC_SEGMENT_ARC_NORMAL,
            id,
            feed,
            buffer: MC_PATH_BUFFER_BLEND_LOW,
            transition: MC_PATH_TRANSITION_MAX_DEVIATION,
            tolerance,
            plane_axes: ax,
            normal: three(normal, "normal")?,
            centre: three(centre, "centre")?,
            end: three(end, "end")?,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// An arc in `plane` (`MC_ARC_PLANE_`) described by `*arc` (as `mc_group_move_circular`), a
/// helix when `nhelix` targets of the group's other axes are given (`helix` may be NULL when
/// `nhelix` is 0), blended as `mc_path_segment_line`. Never blocks.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_path_segment_arc(
    id: u32,
    arc: *const mc_arc,
    plane: u32,
    helix: *const f64,
    nhelix: usize,
    feed: f64,
    tolerance: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        // SAFETY: the caller gives NULL or a readable mc_arc.
        let a = unsafe { read_in(arc, "arc") }?;
        // SAFETY: the caller gives `nhelix` readable doubles.
        let h = unsafe { axis_values(helix, nhelix, "helix") }?;
        let mut s = mc_path_segment {
            kind: MC_SEGMENT_ARC,
            id,
            feed,
            buffer: MC_PATH_BUFFER_BLEND_LOW,
            transition: MC_PATH_TRANSITION_MAX_DEVIATION,
            tolerance,
            naxes: nhelix as u32,
            plane,
            arc: a,
            ..Default::default()
        };
        s.target[..nhelix].copy_from_slice(&h);
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// A NURBS curve `*curve` (as the arguments of `mc_group_move_nurbs`) at `feed`, blended into
/// the segment before within `tolerance` of the corner (as `mc_path_segment_line`), run within
/// `fit_tolerance` of the curve, absolute, not last. The segment keeps `curve`'s array
/// pointers: they must stay readable until it is queued. Nothing else is checked until then.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_segment_nurbs(
    id: u32,
    curve: *const mc_nurbs_curve,
    feed: f64,
    tolerance: f64,
    fit_tolerance: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        // SAFETY: the caller gives NULL or a readable struct.
        let curve = unsafe { read_in(curve, "curve") }?;
        let s = mc_path_segment {
            kind: MC_SEGMENT_NURBS,
            id,
            feed,
            buffer: MC_PATH_BUFFER_BLEND_LOW,
            transition: MC_PATH_TRANSITION_MAX_DEVIATION,
            tolerance,
            curve,
            fit_tolerance,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// A dwell: an exact stop, then a wait of `seconds`. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_segment_dwell(
    id: u32,
    seconds: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        let s = mc_path_segment {
            kind: MC_SEGMENT_DWELL,
            id,
            buffer: MC_PATH_BUFFER_BUFFERED,
            seconds,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// An output action: set (`on` non-zero) or clear `output` when the next motion segment queued
/// after it starts, ends, or has run `distance` (`at`: `MC_OUTPUT_AT_`). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_path_segment_output(
    output: u32,
    on: u32,
    at: u32,
    distance: f64,
    segment: *mut mc_path_segment,
) -> mc_result {
    guard(|| {
        let out = Out::new(segment, "segment")?;
        let s = mc_path_segment {
            kind: MC_SEGMENT_OUTPUT,
            output,
            on,
            at,
            distance,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Queueing
// ---------------------------------------------------------------------------------------------

/// Queue one item in a group's path and wait for the card's answer (not for the motion). The
/// library checks the item first with the card's rules: a non-finite value is
/// `MC_ERR_NOT_FINITE`, a feed or dwell <= 0 `MC_ERR_NON_POSITIVE_LIMIT`, a negative tolerance
/// or distance `MC_ERR_OUT_OF_RANGE`, `naxes` not the group's count `MC_ERR_BAD_AXIS`, an
/// unknown buffer, transition or output point `MC_ERR_PATH_MODE`, an output >=
/// `MC_CARD_OUTPUTS` `MC_ERR_PATH_OUTPUT`. The card refuses a line of length zero
/// (`MC_ERR_PATH_ZERO_LENGTH`), a bad arc (as `mc_group_move_circular`), a segment while group
/// moves run (`MC_ERR_PATH_BUSY`), a full buffer (`MC_ERR_QUEUE_FULL`; `mc_group_path_stream`
/// waits for room instead), a group with post-interpolation filters
/// (`MC_ERR_INCOMPATIBLE_MODE`), a group halting or stopping (`MC_ERR_INVALID_STATE`).
///
/// `motion` may be NULL; otherwise it receives the segment's motion: done when the path has
/// left it, or, when it is the last queued, once the path is at rest in position at its end
/// (wait with `mc_group_motion_wait`); aborted by a halt, stop, fault or an Aborting segment.
/// An output action has no motion: it receives seq 0. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_group_path_push(
    card: mc_card,
    group: u32,
    segment: *const mc_path_segment,
    motion: *mut mc_group_motion,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_path_segment.
        let item = unsafe { read_in(segment, "segment")?.to_sdk() }?;
        let (e, g) = group_of(card, group)?;
        if matches!(item, PathItem::Output { .. }) {
            // Through the stream, which does not take the action's command for a motion.
            g.stream_path([item], |_| {}).map_err(stream_failure)?;
            if let Some(out) = Out::optional(motion) {
                // SAFETY: non-NULL; valid for writes by the caller's contract.
                unsafe { out.write(mc_group_motion { group, seq: 0 }) };
            }
            return Ok(());
        }
        started(&e, g.path_push(&item)?, group, motion)
    })
}

/// Queue an output action (`mc_path_segment_output`, then `mc_group_path_push`): set (`on`
/// non-zero) or clear `output` (0..`MC_CARD_OUTPUTS` - 1, else `MC_ERR_PATH_OUTPUT`) when the
/// next motion segment queued after it starts, ends, or has run `distance` (`at`:
/// `MC_OUTPUT_AT_`). At most 8 actions may wait for their segment (`MC_ERR_PATH_OUTPUT`).
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_group_path_output(
    card: mc_card,
    group: u32,
    output: u32,
    on: u32,
    at: u32,
    distance: f64,
) -> mc_result {
    let s = mc_path_segment {
        kind: MC_SEGMENT_OUTPUT,
        output,
        on,
        at,
        distance,
        ..Default::default()
    };
    // SAFETY: a valid segment on our stack; no motion pointer.
    unsafe { mc_group_path_push(card, group, &s, std::ptr::null_mut()) }
}

/// Stream `n` items (`segments`, may be NULL when `n` is 0) into a group's path: up to 48
/// commands in flight, never more segments than the card's buffer has room for, so a path
/// longer than `MC_PATH_SEGMENTS` streams while it runs. Every item is checked by the library
/// first, before anything is sent (as `mc_group_path_push`); the first refused item stops the
/// stream with its code, and the items before it are queued and run. An item the library
/// refuses stops the stream before it is sent. An item the card refuses (a line of length
/// zero, a bad arc, `MC_ERR_PATH_BUSY`, ...) is answered while the items behind it are on
/// their way: the stream waits for all their answers, and up to 47 of them may have been
/// queued after all (then `*accepted` exceeds the refused item's index); put such an item
/// last, or halt the group (`mc_group_halt`) to drop them.
///
/// `progress` (may be NULL) is called with `user` on this thread after each item sent.
/// `accepted` (may be NULL) always receives how many items the card accepted (an exception
/// to "outputs only on success"): on success `n`; after a refusal or a failure, the items
/// the card took (0 when nothing was sent). `last` (may be NULL) receives, on success, the motion of the last segment: done
/// once the path is at rest at its end (`mc_group_motion_wait`); seq 0 when the items hold no
/// segment.
///
/// Blocks while the items are sent, and whenever the buffer is full, until the running path
/// makes room; returns when the last item is accepted, not when the path is done.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn mc_group_path_stream(
    card: mc_card,
    group: u32,
    segments: *const mc_path_segment,
    n: usize,
    progress: mc_path_progress_callback,
    user: *mut c_void,
    accepted: *mut usize,
    last: *mut mc_group_motion,
) -> mc_result {
    let accepted_out = Out::optional(accepted);
    let mut stopped_at = 0;
    let r = guard(|| {
        if segments.is_null() && n > 0 {
            return Err(Failure::null("segments"));
        }
        let (e, g) = group_of(card, group)?;
        // SAFETY: non-NULL when n > 0 (checked above); `n` readable items by the contract.
        // (and a NURBS item's arrays readable, by the contract)
        let item = |i: usize| unsafe { read_at(segments, i).to_sdk() };
        // Check everything first, so that an item the library refuses stops the stream before
        // anything is sent.
        let mut refused = None;
        for i in 0..n {
            let checked = item(i).and_then(|it| g.path_command(&it).map_err(Failure::from));
            if let Err(f) = checked {
                refused = Some((i, f));
                break;
            }
        }
        let count = refused.as_ref().map_or(n, |(i, _)| *i);
        // The items are read again as they are streamed; they were checked above (a segment
        // the progress callback changed meanwhile and that no longer converts ends the stream).
        let changed = RefCell::new(None);
        let items = (0..count).map_while(|i| match item(i) {
            Ok(it) => Some(it),
            Err(f) => {
                *changed.borrow_mut() = Some((i, f));
                None
            }
        });
        let cb = |p: PathProgress| {
            if let Some(f) = progress {
                let p = mc_path_progress::from(p);
                // SAFETY: the application's callback, with a pointer valid for the call and
                // the user pointer it gave.
                unsafe { f(&p, user) };
            }
        };
        let m = match g.stream_path(items, cb) {
            Ok(m) => m,
            Err(se) => {
                stopped_at = se.accepted as usize;
                return Err(stream_failure(se));
            }
        };
        if let Some((i, f)) = changed.into_inner().or(refused) {
            stopped_at = i;
            return Err(Failure::new(
                f.code,
                format!("path item {i}: {}", f.message),
            ));
        }
        stopped_at = n;
        match m {
            Some(m) => started(&e, m, group, last),
            None => {
                if let Some(out) = Out::optional(last) {
                    // SAFETY: non-NULL; valid for writes by the caller's contract.
                    unsafe { out.write(mc_group_motion { group, seq: 0 }) };
                }
                Ok(())
            }
        }
    });
    if let Some(out) = accepted_out {
        // SAFETY: non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(stopped_at) };
    }
    r
}

/// A path stream running in a thread of the library (`mc_group_path_stream_start`): an
/// integer handle, never 0, valid until `mc_path_streamer_join`.
#[allow(non_camel_case_types)]
pub type mc_path_streamer = u32;

/// A streamer: the SDK's, and what its end needs (the card's entry, the group).
struct Streamer {
    streamer: motioncard_sdk::PathStreamer,
    entry: std::sync::Arc<registry::Entry>,
    group: u32,
    /// Items given.
    n: usize,
}

/// The streamers.
static STREAMERS: crate::handles::Handles<Streamer> = crate::handles::Handles::new("path streamer");

/// Start streaming `n` items (`segments`, may be NULL when `n` is 0) into a group's path from
/// a thread of the library, as `mc_group_path_stream` streams them, and return at once with
/// its handle in `*streamer`. Every item is checked and copied first (a NURBS item's arrays
/// too: the caller's memory is not read after this call): an item the library refuses is
/// returned with its code (the message names the item) and nothing is sent. The thread calls
/// no application code. Watch it with `mc_path_streamer_progress`, stop it with
/// `mc_path_streamer_cancel`, and end it with `mc_path_streamer_join` (which every handle
/// needs: it frees it). Blocks only while the items are checked.
#[no_mangle]
pub unsafe extern "C" fn mc_group_path_stream_start(
    card: mc_card,
    group: u32,
    segments: *const mc_path_segment,
    n: usize,
    streamer: *mut mc_path_streamer,
) -> mc_result {
    guard(|| {
        let out = Out::new(streamer, "streamer")?;
        if segments.is_null() && n > 0 {
            return Err(Failure::null("segments"));
        }
        let (e, g) = group_of(card, group)?;
        let mut items = Vec::with_capacity(n);
        for i in 0..n {
            // SAFETY: non-NULL when n > 0 (checked above); `n` readable items by the contract
            // (and a NURBS item's arrays readable, by the contract).
            let checked = unsafe { read_at(segments, i).to_sdk() }
                .and_then(|it| g.path_command(&it).map(|_| it).map_err(Failure::from));
            match checked {
                Ok(it) => items.push(it),
                Err(f) => {
                    return Err(Failure::new(
                        f.code,
                        format!("path item {i}: {}", f.message),
                    ))
                }
            }
        }
        let st = Streamer {
            streamer: g.spawn_path_stream(items),
            entry: e,
            group,
            n,
        };
        let h = STREAMERS.insert(st).map_err(|(f, st)| {
            st.streamer.cancel();
            f
        })?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(h) };
        Ok(())
    })
}

/// The stream's progress (`sent` and `accepted` items, the card's `done` and `queued`
/// segments) and, in `*finished` (may be NULL), 1 once its thread has ended (everything sent
/// and answered, cancelled, or stopped by a refusal: `mc_path_streamer_join` says which), else
/// 0. Never blocks (it reads the card's window).
#[no_mangle]
pub unsafe extern "C" fn mc_path_streamer_progress(
    streamer: mc_path_streamer,
    progress: *mut mc_path_progress,
    finished: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(progress, "progress")?;
        let fin = Out::optional(finished);
        let (p, f) = STREAMERS.with(streamer, false, |s| {
            let s = s.as_ref().expect("checked");
            (s.streamer.progress(), s.streamer.is_finished())
        })?;
        // SAFETY: checked non-NULL (`finished`: when given); valid by the caller's contract.
        unsafe {
            out.write(p.into());
            if let Some(fin) = fin {
                fin.write(f as u32);
            }
        }
        Ok(())
    })
}

/// Stop sending: the items not sent yet are dropped, what the card accepted stays queued and
/// runs (`mc_group_halt` stops that too). The thread ends once the commands in flight are
/// answered; `mc_path_streamer_join` then returns `MC_ERR_CANCELLED`. Never blocks.
#[no_mangle]
pub extern "C" fn mc_path_streamer_cancel(streamer: mc_path_streamer) -> mc_result {
    guard(|| {
        STREAMERS.with(streamer, false, |s| {
            s.as_ref().expect("checked").streamer.cancel()
        })
    })
}

/// Wait for the stream's thread to end and free the handle (always, whatever it returns).
/// Returns the stream's result as `mc_group_path_stream` does: `MC_OK` when every item was
/// accepted (`*last`, may be NULL: the motion of the last segment, seq 0 when there was
/// none), `MC_ERR_CANCELLED` after `mc_path_streamer_cancel`, or the code of the item that
/// stopped it (the message names it). `accepted` (may be NULL) always receives how many
/// items the card accepted. Blocks until the thread ends (at most until the items are sent,
/// waiting for room as the path runs).
#[no_mangle]
pub unsafe extern "C" fn mc_path_streamer_join(
    streamer: mc_path_streamer,
    accepted: *mut usize,
    last: *mut mc_group_motion,
) -> mc_result {
    let accepted_out = Out::optional(accepted);
    let mut count = 0usize;
    let r = guard(|| {
        let st = STREAMERS.with(streamer, true, |s| s.take().expect("checked"))?;
        while !st.streamer.is_finished() {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let sent = st.streamer.progress().accepted as usize;
        let cancelled = st.streamer.is_cancelled();
        match st.streamer.join() {
            Ok(_) if cancelled && sent < st.n => {
                count = sent;
                Err(Failure::new(
                    motioncard_sdk::ErrorKind::Cancelled.code(),
                    format!(
                        "the path stream was cancelled after {sent} of {} items",
                        st.n
                    ),
                ))
            }
            Ok(m) => {
                count = st.n;
                match m {
                    Some(m) => started(&st.entry, m, st.group, last),
                    None => {
                        if let Some(out) = Out::optional(last) {
                            // SAFETY: non-NULL; valid for writes by the caller's contract.
                            unsafe {
                                out.write(mc_group_motion {
                                    group: st.group,
                                    seq: 0,
                                })
                            };
                        }
                        Ok(())
                    }
                }
            }
            Err(se) => {
                count = se.accepted as usize;
                Err(stream_failure(se))
            }
        }
    });
    if let Some(out) = accepted_out {
        // SAFETY: non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(count) };
    }
    r
}

// ---------------------------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------------------------

/// The card's digital outputs as it drives them (bit i = output i, `MC_CARD_OUTPUTS` of them):
/// set by `mc_set_outputs` or by a path's output actions. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_get_outputs(card: mc_card, outputs: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(outputs, "outputs")?;
        let v = registry::get(card)?.card.outputs()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// Set the outputs in `mask` to the bits of `value` now (the others keep theirs). A bit at or
/// above `MC_CARD_OUTPUTS` in either is `MC_ERR_PATH_OUTPUT`. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_outputs(card: mc_card, mask: u32, value: u32) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.set_outputs(mask, value)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use motioncard_sdk::Nurbs;

    #[test]
    fn segments_convert_and_unknown_modes_are_path_mode() {
        // SAFETY: no NURBS item here (no arrays to read).
        let sdk = |s: mc_path_segment| unsafe { s.to_sdk() };
        let mut s = mc_path_segment::default();
        // SAFETY: valid pointers.
        let r = unsafe { mc_path_segment_line(7, [1.0, 2.0].as_ptr(), 2, 10.0, 0.5, &mut s) };
        assert_eq!(r, 0);
        assert_eq!(
            sdk(s).unwrap(),
            PathItem::Segment(Segment::line(7, &[1.0, 2.0], 10.0, 0.5))
        );
        s.buffer = 6;
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::PathMode.code());
        s.buffer = MC_PATH_BUFFER_BUFFERED;
        s.transition = MC_PATH_TRANSITION_TIME_SHIFT;
        let PathItem::Segment(seg) = sdk(s).unwrap() else {
            panic!("a segment");
        };
        assert_eq!(seg.transition, Transition::TimeShift(0.5));
        s.transition = 4;
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::PathMode.code());
        s.naxes = 9;
        s.transition = MC_PATH_TRANSITION_NONE;
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::BadAxis.code());
        // SAFETY: valid pointers.
        assert_eq!(unsafe { mc_path_segment_dwell(3, 0.25, &mut s) }, 0);
        s.last = 1;
        assert_eq!(sdk(s).unwrap(), Segment::dwell(3, 0.25).last().into());
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { mc_path_segment_output(5, 1, MC_OUTPUT_AT_DISTANCE, 2.5, &mut s) },
            0
        );
        assert_eq!(
            sdk(s).unwrap(),
            PathItem::Output {
                output: 5,
                on: true,
                at: OutputAt::Distance(2.5)
            }
        );
        s.at = 3;
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::PathMode.code());
        s.at = MC_OUTPUT_AT_END;
        s.output = 300;
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::PathOutput.code());
        s.kind = MC_SEGMENT_ARC_NORMAL + 1; // the first kind the ABI does not define
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::BadConfig.code());
        // a NURBS item: its curve is read and checked as mc_group_move_nurbs checks it
        let (ctrl, w, k) = ([0.0, 0.0, 1.0, 1.0], [1.0, 1.0], [0.0, 0.0, 1.0, 1.0]);
        let mut c = mc_nurbs_curve {
            degree: 1,
            dim: 2,
            ctrl: ctrl.as_ptr(),
            n_ctrl: 2,
            weights: w.as_ptr(),
            knots: k.as_ptr(),
            n_knots: 4,
        };
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { mc_path_segment_nurbs(9, &c, 5.0, 0.5, 0.01, &mut s) },
            0
        );
        let want = Nurbs::new(1, 2, &ctrl, &w, &k).unwrap();
        assert_eq!(
            sdk(s).unwrap(),
            PathItem::Segment(Segment::nurbs(9, want, 5.0, 0.5, 0.01))
        );
        c.degree = 0;
        // SAFETY: valid pointers.
        assert_eq!(
            unsafe { mc_path_segment_nurbs(9, &c, 5.0, 0.5, 0.01, &mut s) },
            0
        );
        assert_eq!(sdk(s).unwrap_err().code, ErrorKind::NurbsDegree.code());
        s.curve.ctrl = std::ptr::null();
        assert_eq!(sdk(s).unwrap_err().code, crate::result::MC_ERR_NULL_POINTER);
    }
}
