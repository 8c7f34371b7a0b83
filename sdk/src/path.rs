//! The continuous path: a deep buffer of segments on the card (lines, arcs and helices,
//! dwells, output actions), look-ahead and corner blending within a tolerance on the card.
//!
//! Units are the group's: targets in each axis's user units, feeds, tolerances and path
//! distances in the first group axis's units (as for [`Group::move_linear`]).
//!
//! Segments are streamed without waiting for each ack: [`Group::stream_path`] keeps the
//! command ring full while the card's buffer has room (it never sends more than the card can
//! take, so the card never refuses a segment for want of space and nothing arrives out of
//! order), from the caller's thread; [`Group::spawn_path_stream`] does the same from a thread of
//! its own. Every segment is checked here first with the card's rules, and the first refusal
//! stops the stream with the segment's index and the card's reason; what was accepted before it
//! stays queued and runs. A stream sends runs of lines that sample a smooth curve as that
//! curve (`crate::fit`, [`PathSettings::chord_fit`]); its indices and counts are still those
//! of the items given.

use crate::card::{finite, positive, Card};
use crate::error::{Error, Result, Target};
use crate::fit::{FitIter, Fitted, Fitter};
use crate::group::{Group, GroupMotion};
use crate::nurbs::Nurbs;
use crate::segment::{Geometry, OutputAt, PathBuffer, PathItem, Segment, Transition};
use firmware_proto::cmd::{
    CurveSize, GroupCmd, IoCmd, PathArc, PathArcNormal, PathArcPlane, PathDwell, PathFlags,
    PathLine, PathNurbs, PathOutput, PathPause, SetOutputs,
};
use firmware_proto::{layout, raw, Command, Mem, NackCode};
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

pub use firmware_proto::GroupPath;

/// Where a path's pause is ([`Group::path_pause`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PauseState {
    /// No pause asked for.
    None,
    /// Braking for the pause point.
    Pausing,
    /// At rest on it: the end of segment `id` (the path's `path_id`; 0 when none ran).
    Paused {
        /// The segment it ended (0 when none ran).
        id: u32,
    },
}

/// A group's path configuration, in user units: `vmax`, `amax`, `jmax` per group axis in that
/// axis's units; `accel` and `jerk` (tangential, 0: from the axes) in the first axis's.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSettings {
    /// Checked (1..=PATH_LEN) and kept by the card; it looks ahead by distance, over as many
    /// queued segments as braking from its speed takes, not this many.
    pub lookahead: usize,
    /// The low-water event fires when the queued segments fall to this (0: never).
    pub low_water: usize,
    /// Tangential acceleration limit (0: from the axes).
    pub accel: f64,
    /// Tangential jerk limit (0: from the axes).
    pub jerk: f64,
    /// Each axis's velocity limit.
    pub vmax: Vec<f64>,
    /// Each axis's acceleration limit.
    pub amax: Vec<f64>,
    /// Each axis's jerk limit.
    pub jmax: Vec<f64>,
    /// The card's path planner period, s (0: its default, 1 ms; at most 10 ms), rounded to
    /// whole servo ticks: the look-ahead and the speed planner run once a period, and every
    /// servo tick in between follows the jerk-limited profile they chose (at a 10 kHz servo
    /// rate, a tenth of the card's planning work, the motion's limits the same).
    pub plan_period: f64,
    /// A path stream sends runs of lines that sample a smooth curve as that curve, fitted
    /// within their tolerance (see [`Group::stream_path`]); kept by this host, not the card.
    pub chord_fit: bool,
}

impl PathSettings {
    /// `BadAxis` unless the settings have limits for `n` axes.
    pub(crate) fn check_axes(&self, n: usize) -> Result<()> {
        for v in [&self.vmax, &self.amax, &self.jmax] {
            if v.len() != n {
                return Err(Error::BadAxis {
                    axis: v.len(),
                    count: n,
                });
            }
        }
        Ok(())
    }

    /// The `group_path` block of these settings, its tangential limits in counts (`ps`: counts
    /// per user unit of path quantities); the axes' limits are the caller's
    /// ([`PathSettings::axis_limits`]).
    pub(crate) fn block(&self, ps: f64) -> GroupPath {
        GroupPath {
            lookahead: self.lookahead.min(u32::MAX as usize) as u32,
            low_water: self.low_water.min(u32::MAX as usize) as u32,
            accel: self.accel * ps,
            jerk: self.jerk * ps,
            plan_period: self.plan_period,
            ..GroupPath::default()
        }
    }

    /// Axis `i`'s velocity, acceleration and jerk limits in counts (`scale`: its counts per
    /// user unit), each checked above 0.
    pub(crate) fn axis_limits(&self, i: usize, scale: f64) -> Result<[f64; 3]> {
        positive("velocity limit", self.vmax[i])?;
        positive("acceleration limit", self.amax[i])?;
        positive("jerk limit", self.jmax[i])?;
        let s = scale.abs();
        Ok([self.vmax[i] * s, self.amax[i] * s, self.jmax[i] * s])
    }

    /// `n` axes with the same limits, look-ahead 256, no low-water event, the card's default
    /// planner period, chords fitted into curves.
    pub fn uniform(n: usize, vmax: f64, amax: f64, jmax: f64) -> Self {
        Self {
            lookahead: 256,
            low_water: 0,
            accel: 0.0,
            jerk: 0.0,
            vmax: vec![vmax; n],
            amax: vec![amax; n],
            jmax: vec![jmax; n],
            plan_period: 0.0,
            chord_fit: true,
        }
    }
}

/// Where `item` ends, after a path that ends at `prev` (user units; None: not known here).
pub(crate) fn item_end(prev: Option<Vec<f64>>, item: &PathItem) -> Option<Vec<f64>> {
    let PathItem::Segment(s) = item else {
        return prev;
    };
    match (&s.geometry, s.relative) {
        (Geometry::Line { target }, false) => Some(target.clone()),
        (Geometry::Line { target }, true) => {
            prev.map(|p| p.iter().zip(target).map(|(a, b)| a + b).collect())
        }
        (Geometry::Dwell { .. }, _) => prev,
        (Geometry::Nurbs { curve, .. }, false) => curve
            .control_point(curve.n_ctrl() - 1)
            .map(|p| p.iter().take(curve.dim()).copied().collect()),
        _ => None,
    }
}

/// How far a stream has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PathProgress {
    /// Items taken from the iterator and sent.
    pub sent: u64,
    /// Items the card accepted.
    pub accepted: u64,
    /// Segments the card finished since the group was enabled (wrapping counter of the card).
    pub done: u32,
    /// Segments queued on the card.
    pub queued: u32,
}

/// A stream that stopped at a refused item.
#[derive(Debug)]
pub struct StreamError {
    /// Index of the item (from 0) that stopped the stream: the earliest failure among
    /// everything sent (every command sent is answered before the stream returns).
    pub index: u64,
    /// Why.
    pub error: Error,
    /// Items the card accepted. Commands already in flight behind the failing one may have
    /// been accepted and are queued: when this exceeds `index`, the path holds segments past
    /// the one that failed (halt the group if they must not run).
    pub accepted: u64,
}

impl std::fmt::Display for StreamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "path item {}: {}", self.index, self.error)
    }
}

impl std::error::Error for StreamError {}

/// A path stream running on a thread of its own ([`Group::spawn_path_stream`]).
pub struct PathStreamer {
    progress: Arc<[AtomicU64; 2]>,
    cancel: Arc<AtomicBool>,
    handle: Option<std::thread::JoinHandle<std::result::Result<Option<GroupMotion>, StreamError>>>,
    group: Group,
}

impl PathStreamer {
    /// Items sent and accepted so far, and the card's counters.
    pub fn progress(&self) -> PathProgress {
        let (done, queued) = self.group.path_counts().unwrap_or((0, 0));
        PathProgress {
            sent: self.progress[0].load(Ordering::Relaxed),
            accepted: self.progress[1].load(Ordering::Relaxed),
            done,
            queued,
        }
    }

    /// Has the streaming thread ended (everything sent and answered, cancelled, or refused:
    /// [`PathStreamer::join`] says which)?
    pub fn is_finished(&self) -> bool {
        self.handle.as_ref().is_none_or(|h| h.is_finished())
    }

    /// Stop sending (what was accepted stays queued).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// Was [`PathStreamer::cancel`] called?
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Wait for the stream to end: the motion of its last segment, to wait on.
    pub fn join(mut self) -> std::result::Result<Option<GroupMotion>, StreamError> {
        match self.handle.take().map(|h| h.join()) {
            Some(Ok(r)) => r,
            _ => Err(StreamError {
                index: self.progress[0].load(Ordering::Relaxed),
                error: Error::Protocol("the path stream's thread panicked".into()),
                accepted: self.progress[1].load(Ordering::Relaxed),
            }),
        }
    }
}

/// Commands in flight at most (a margin under the command ring's 64 entries).
const IN_FLIGHT: usize = 48;

impl Group {
    /// Write the path configuration and have the card check and apply it (path idle).
    pub fn configure_path(&self, s: &PathSettings) -> Result<()> {
        let (n, axes) = self.axes()?;
        s.check_axes(n)?;
        let mut b = s.block(self.path_scale()?);
        for (i, &axis) in axes[..n].iter().enumerate() {
            [b.vmax[i], b.amax[i], b.jmax[i]] = s.axis_limits(i, self.card_pub().scale(axis))?;
        }
        self.card_pub().apply_block(
            layout::GROUP_PATH.at(self.index()),
            |blk| *blk = b,
            self.cmd(GroupCmd::ApplyPath),
            "configure path",
            Target::Group(self.index()),
        )?;
        self.path_host(|h| h.chord_fit = s.chord_fit);
        Ok(())
    }

    /// Whether this host's path streams fit chords into curves ([`PathSettings::chord_fit`]).
    pub fn chord_fit(&self) -> bool {
        self.path_host(|h| h.chord_fit)
    }

    fn path_host<T>(&self, f: impl FnOnce(&mut crate::card::PathHost) -> T) -> T {
        f(&mut crate::card::lock(&self.card_pub().inner().path_host)[self.index()])
    }

    /// Where the next segment starts (user units), when it is known here: where the group is
    /// while its path is idle and at rest; else where the last segment this host queued ends.
    fn path_start(&self) -> Result<Option<Vec<f64>>> {
        let (n, axes) = self.axes()?;
        let st = self.status()?.1;
        let pause = raw::MC_PATHST_PAUSING | raw::MC_PATHST_PAUSED;
        if st.path_queued == 0 && st.path_flags & !pause == 0 {
            let s = self.card_pub().statuses(&axes[..n])?;
            return Ok(Some(s.iter().map(|a| a.command_position).collect()));
        }
        Ok(if st.path_queued > 0 {
            self.path_host(|h| h.end.clone())
        } else {
            None
        })
    }

    /// The path configuration the card holds (layout 1.8: read back from the card), in
    /// counts.
    pub fn path_config(&self) -> Result<GroupPath> {
        let g = self.index();
        self.card_pub().read_block(
            layout::GROUP_PATH.at(g),
            firmware_proto::ConfigKind::GroupPath,
            g,
        )
    }

    /// Pauses the path at the end of a segment (layout 1.11): it comes to rest at the end of
    /// the first segment it can stop at within its limits from where it is (an exact stop or a
    /// dwell's end ahead, or the first segment end beyond its braking distance; with nothing
    /// queued and at rest, at once), holds there, and goes on along the same path at
    /// [`path_resume`](Self::path_resume). Nothing queued changes, and more may be queued
    /// meanwhile. The end of a segment followed by a blend is where the blend starts, within the
    /// segment's tolerance of its programmed end. [`path_pause_state`](Self::path_pause_state)
    /// says when it is there; the card also posts `MC_EV_PATH_PAUSED`.
    pub fn path_pause(&self) -> Result<()> {
        self.run(
            self.cmd(GroupCmd::PathPause(PathPause { on: 1.0 })),
            "path pause",
        )
        .map(|_| ())
    }

    /// Ends a pause: the path goes on from the pause point (asked before it got there, it does
    /// not stop).
    pub fn path_resume(&self) -> Result<()> {
        self.run(
            self.cmd(GroupCmd::PathPause(PathPause { on: 0.0 })),
            "path resume",
        )
        .map(|_| ())
    }

    /// Where a pause is, from the status.
    pub fn path_pause_state(&self) -> Result<PauseState> {
        let st = self.status()?.1;
        Ok(if st.path_flags & raw::MC_PATHST_PAUSED != 0 {
            PauseState::Paused { id: st.path_id }
        } else if st.path_flags & raw::MC_PATHST_PAUSING != 0 {
            PauseState::Pausing
        } else {
            PauseState::None
        })
    }

    /// Free segments in the card's path buffer.
    pub fn path_free(&self) -> Result<usize> {
        Ok(self.status()?.1.path_free as usize)
    }

    /// (segments finished since enable, segments queued) from the status.
    fn path_counts(&self) -> Result<(u32, u32)> {
        let st = self.status()?.1;
        Ok((st.path_done, st.path_queued))
    }

    /// The command for one item (checked here with the card's rules first). For a NURBS
    /// segment, the `MC_OP_PATH_NURBS` that opens its transfer (its data and end follow: see
    /// [`Group::path_push`]); for a normal-vector arc, its `MC_OP_PATH_ARC_NORMAL` (the
    /// `MC_OP_PATH_ARC_PLANE` that sets its plane goes before it: [`Group::path_push`] sends
    /// both).
    pub fn path_command(&self, item: &PathItem) -> Result<Command> {
        let ps = self.path_scale()?;
        let seg = match item {
            PathItem::Output { output, on, at } => {
                if *output as usize >= firmware_proto::OUTPUTS {
                    return Err(self.refused("path output", NackCode::PathOutput));
                }
                let (flags, d) = match *at {
                    OutputAt::Start => (raw::MC_PATH_OUT_AT_START, 0.0),
                    OutputAt::End => (raw::MC_PATH_OUT_AT_END, 0.0),
                    OutputAt::Distance(d) => {
                        finite("output distance", d)?;
                        if d < 0.0 {
                            return Err(self.refused("path output", NackCode::OutOfRange));
                        }
                        (raw::MC_PATH_OUT_AT_DISTANCE, d * ps)
                    }
                };
                let o = PathOutput {
                    output: *output as f64,
                    on: if *on { 1.0 } else { 0.0 },
                    distance: d,
                    when: flags as u8,
                };
                return Ok(self.cmd(GroupCmd::PathOutput(o)));
            }
            PathItem::Segment(s) => s,
        };
        if let Geometry::Dwell { seconds } = seg.geometry {
            positive("dwell", seconds)?;
            let d = PathDwell {
                id: seg.id as f64,
                seconds,
                last: seg.last,
            };
            return Ok(self.cmd(GroupCmd::PathDwell(d)));
        }
        positive("feed", seg.feed)?;
        let (tm, tol) = match seg.transition {
            Transition::None => (raw::MC_TM_NONE, 0.0),
            Transition::MaxDeviation(t) => (raw::MC_TM_MAX_DEVIATION, t),
            Transition::CornerDistance(t) => (raw::MC_TM_CORNER_DISTANCE, t),
            Transition::TimeShift(t) => (raw::MC_TM_TIME_SHIFT, t),
        };
        finite("tolerance", tol)?;
        if tol < 0.0 {
            return Err(self.refused("path segment", NackCode::OutOfRange));
        }
        let buffer = match seg.buffer {
            PathBuffer::Aborting => raw::MC_PATH_ABORTING,
            PathBuffer::Buffered => raw::MC_PATH_BUFFERED,
            PathBuffer::BlendingLow => raw::MC_PATH_BLEND_LOW,
            PathBuffer::BlendingPrevious => raw::MC_PATH_BLEND_PREVIOUS,
            PathBuffer::BlendingNext => raw::MC_PATH_BLEND_NEXT,
            PathBuffer::BlendingHigh => raw::MC_PATH_BLEND_HIGH,
        };
        let (id, feed, tolerance) = (seg.id as f64, seg.feed * ps, tol * ps);
        let flags = PathFlags {
            relative: seg.relative,
            buffer: buffer as u8,
            transition: tm as u8,
            last: seg.last,
        };
        let c = match &seg.geometry {
            Geometry::Line { target } => GroupCmd::PathLine(PathLine {
                id,
                feed,
                tolerance,
                targets: self.target_array(target)?,
                flags,
            }),
            Geometry::Arc { arc, plane, helix } => GroupCmd::PathArc(PathArc {
                id,
                feed,
                tolerance,
                arc: self.arc_geometry(arc, *plane, helix)?,
                flags,
            }),
            Geometry::ArcNormal {
                axes: ax,
                centre,
                end,
                rise,
                helix,
                ..
            } => {
                let (s3, others) = self.arc_normal_scales(ax)?;
                for x in centre.iter().chain(end).chain(helix) {
                    finite("arc coordinate", *x)?;
                }
                if !helix.is_empty() && helix.len() != others.len() {
                    return Err(Error::BadAxis {
                        axis: helix.len(),
                        count: others.len(),
                    });
                }
                let mut h = [0.0; firmware_proto::MAX_AXES - 3];
                for ((d, x), s) in h.iter_mut().zip(helix).zip(&others) {
                    *d = x * s;
                }
                GroupCmd::PathArcNormal(PathArcNormal {
                    id,
                    feed,
                    tolerance,
                    centre: centre.map(|x| x * s3),
                    end: end.map(|x| x * s3),
                    helix: h,
                    rise: *rise,
                    helix_relative: helix.is_empty(),
                    flags,
                })
            }
            Geometry::Nurbs {
                curve,
                fit_tolerance,
            } => {
                let (n, _) = self.axes()?;
                if curve.dim() != n {
                    return Err(self.refused("path nurbs", NackCode::NurbsDimension));
                }
                positive("fit tolerance", *fit_tolerance)?;
                GroupCmd::PathNurbs(PathNurbs {
                    id,
                    feed,
                    tolerance,
                    size: CurveSize {
                        degree: curve.degree() as f64,
                        n_ctrl: curve.n_ctrl() as f64,
                        n_knots: curve.knots().len() as f64,
                    },
                    fit_tolerance: fit_tolerance * ps,
                    flags,
                })
            }
            Geometry::Dwell { .. } => unreachable!("handled above"),
        };
        Ok(self.cmd(c))
    }

    /// A normal-vector arc's one scale on its three axes and the other axes' scales, in
    /// group order (checked: the card has layout 1.12, the axes are the group's).
    pub(crate) fn arc_normal_scales(&self, ax: &[usize; 3]) -> Result<(f64, Vec<f64>)> {
        let layout = self.card_pub().info().layout;
        if layout.1 < 12 {
            return Err(Error::Unsupported(format!(
                "arcs in a plane given by a normal vector need layout 1.12 (the card has 1.{})",
                layout.1
            )));
        }
        let (n, axes) = self.axes()?;
        for &a in ax {
            if a >= n {
                return Err(Error::BadAxis { axis: a, count: n });
            }
        }
        // (one axis twice is the card's to refuse: MC_NACK_ARC_AXES, ErrorKind::ArcAxes)
        let card = self.card_pub();
        let s3 = card.scale(axes[ax[0]]);
        if ax.iter().any(|&a| card.scale(axes[a]) != s3) {
            return Err(Error::Unsupported(format!(
                "an arc in the plane of group axes {ax:?} needs one scale on the three (a circle \
                 in user units is not one in counts otherwise)"
            )));
        }
        let others = (0..n)
            .filter(|i| !ax.contains(i))
            .map(|i| card.scale(axes[i]))
            .collect();
        Ok((s3, others))
    }

    /// The MC_OP_PATH_ARC_PLANE a normal-vector arc's segment is sent after (None for any
    /// other item).
    fn arc_plane_command(&self, item: &PathItem) -> Result<Option<Command>> {
        let PathItem::Segment(Segment {
            geometry: Geometry::ArcNormal { axes, normal, .. },
            ..
        }) = item
        else {
            return Ok(None);
        };
        for x in normal {
            finite("arc normal", *x)?;
        }
        Ok(Some(self.cmd(GroupCmd::PathArcPlane(PathArcPlane {
            axes: axes.map(|a| a as f64),
            normal: *normal,
        }))))
    }

    fn refused(&self, command: &'static str, code: NackCode) -> Error {
        Error::Refused {
            command,
            target: Target::Group(self.index()),
            code,
            reason: crate::nack_reason(code),
        }
    }

    /// Queue one item and wait for the card's answer: the segment's motion (its done is the
    /// path's end when it is the last one queued).
    pub fn path_push(&self, item: &PathItem) -> Result<GroupMotion> {
        let c = self.path_command(item)?;
        let prev = self.path_start().ok().flatten();
        self.path_host(|h| h.end = None);
        let m = self.path_push_inner(item, c)?;
        self.path_host(|h| h.end = item_end(prev, item));
        Ok(m)
    }

    fn path_push_inner(&self, item: &PathItem, c: Command) -> Result<GroupMotion> {
        if let Some(curve) = nurbs_of(item) {
            let seq = self.path_curve(c, curve, None)?;
            return Ok(self.motion(seq));
        }
        if let Some(plane) = self.arc_plane_command(item)? {
            self.run(plane, "path arc plane")?;
        }
        let seq = self.run(c, "path segment")?;
        Ok(match item {
            PathItem::Segment(_) => self.motion(seq),
            // An output action has no motion: it is not what `wait_done` waits for.
            PathItem::Output { .. } => self.motion_untracked(seq),
        })
    }

    /// Sends a NURBS segment: its begin `c`, its data, its end. When the card has no room for
    /// its pieces yet: in a stream (`cancel` given), waits for the path to run on and sends
    /// the end again (the card keeps the curve staged), until `cancel` is set or the room has
    /// not changed for 5 s of the card's ticks (`QueueFull`); else `QueueFull` at once.
    fn path_curve(&self, c: Command, curve: &Nurbs, cancel: Option<&AtomicBool>) -> Result<u32> {
        let card = self.card_pub();
        let target = Target::Group(self.index());
        card.execute_seq(c, "path nurbs", target)?;
        let (n, axes) = self.axes()?;
        self.send_data(&self.nurbs_stream(curve, &axes[..n]))?;
        // The room's last change, counted in the card's ticks (emulated time on a stepped
        // card: the same answer on a loaded machine).
        let patience = 5 * u64::from(card.info().servo_rate_hz);
        let mut seen = (usize::MAX, card.tick()?);
        loop {
            let end = self.cmd(GroupCmd::NurbsEnd);
            match card.execute_seq(end, "path nurbs end", target) {
                Err(e) if e.kind() == crate::ErrorKind::QueueFull => {
                    let Some(cancel) = cancel else {
                        return Err(e);
                    };
                    let (free, now) = (self.path_free()?, card.tick()?);
                    if free != seen.0 {
                        seen = (free, now);
                    }
                    if now.saturating_sub(seen.1) > patience || cancel.load(Ordering::Relaxed) {
                        return Err(e);
                    }
                    card.wait_next_tick(Duration::from_secs(1))?;
                }
                r => return r,
            }
        }
    }

    /// Stream `items` into the card's path buffer from this thread: up to 48 commands in
    /// flight, never more segments than the buffer has room for (it waits for room: the path
    /// runs meanwhile), `progress` called after each accepted item. Returns the motion of the
    /// last segment (wait on it for the end of the path), or where the stream stopped.
    ///
    /// With [`PathSettings::chord_fit`] (the default), runs of absolute lines under the same
    /// `MaxDeviation` tolerance, feed and blending buffer mode that sample a smooth curve are
    /// sent as that curve, a cubic B-spline within 0.8 of the tolerance of their polyline both
    /// ways (one line when they are collinear); a corner (a turn beyond 30° at the vertex and
    /// over 8 tolerances around it) ends a run and stays a corner. Such a segment carries the
    /// id of the last line it stands for. Where the path starts is the group's position while
    /// its path is idle, else the end of the last segment this host queued; where that is not
    /// known here (after an arc, or a path another host is filling), a run starts at the end of
    /// the first line, which is sent as given. A corner next to a fitted curve is blended
    /// within what the curve leaves of the tolerance near it. Runs do not cross calls: give a
    /// program as one stream (or batches of hundreds of items), not an item or two a call.
    /// The fitting itself is `crate::fit` (its module doc).
    pub fn stream_path<I>(
        &self,
        items: I,
        mut progress: impl FnMut(PathProgress),
    ) -> std::result::Result<Option<GroupMotion>, StreamError>
    where
        I: IntoIterator,
        I::Item: Into<PathItem>,
    {
        let never = AtomicBool::new(false);
        let counters = [AtomicU64::new(0), AtomicU64::new(0)];
        self.stream_inner(items, &never, &counters, &mut progress)
    }

    /// [`stream_path`](Self::stream_path) from a thread of its own.
    pub fn spawn_path_stream<I>(&self, items: I) -> PathStreamer
    where
        I: IntoIterator + Send + 'static,
        I::IntoIter: Send,
        I::Item: Into<PathItem>,
    {
        let progress = Arc::new([AtomicU64::new(0), AtomicU64::new(0)]);
        let cancel = Arc::new(AtomicBool::new(false));
        let (g, p, c) = (self.clone(), progress.clone(), cancel.clone());
        let handle = std::thread::spawn(move || g.stream_inner(items, &c, &p, &mut |_| {}));
        PathStreamer {
            progress,
            cancel,
            handle: Some(handle),
            group: self.clone(),
        }
    }

    fn stream_inner<I>(
        &self,
        items: I,
        cancel: &AtomicBool,
        counters: &[AtomicU64; 2],
        progress: &mut dyn FnMut(PathProgress),
    ) -> std::result::Result<Option<GroupMotion>, StreamError>
    where
        I: IntoIterator,
        I::Item: Into<PathItem>,
    {
        let items = items.into_iter().map(Into::into);
        let at_start = |e| StreamError {
            index: 0,
            error: e,
            accepted: 0,
        };
        let start = self.path_start().map_err(at_start)?;
        // where the path ends after each item sent (this host's record, see `path_start`)
        let end = std::cell::RefCell::new(start.clone());
        let track = |f: Fitted| {
            let e = item_end(end.borrow_mut().take(), &f.item);
            *end.borrow_mut() = e;
            f
        };
        let outcome = if !self.chord_fit() {
            let plain = items.enumerate().map(|(i, item)| Fitted {
                item,
                first: i as u64,
                last: i as u64,
            });
            self.stream_fitted(plain.map(track), cancel, counters, progress)
        } else {
            let (n, axes) = self.axes().map_err(at_start)?;
            let scales: Vec<f64> = axes[..n]
                .iter()
                .map(|&a| self.card_pub().scale(a))
                .collect();
            let mut fitter = Fitter::new(&scales);
            if let Some(s) = &start {
                fitter.set_start(s);
            }
            self.stream_fitted(
                FitIter::new(items, fitter).map(track),
                cancel,
                counters,
                progress,
            )
        };
        // (an item sent but refused leaves the record unknown: the card's end is the last
        // accepted item's)
        let end = if outcome.is_ok() {
            end.into_inner()
        } else {
            None
        };
        self.path_host(|h| h.end = end);
        outcome
    }

    /// The stream of `items`, each standing for the input items `first..=last` (one each,
    /// or a run of lines fitted into one curve): progress and failures count input items.
    fn stream_fitted(
        &self,
        items: impl Iterator<Item = Fitted>,
        cancel: &AtomicBool,
        counters: &[AtomicU64; 2],
        progress: &mut dyn FnMut(PathProgress),
    ) -> std::result::Result<Option<GroupMotion>, StreamError> {
        let card: &Card = self.card_pub();
        // (first input index, last input index, seq, is a segment)
        let mut in_flight: VecDeque<(u64, u64, u32, bool)> = VecDeque::new();
        let (mut sent, mut accepted) = (0u64, 0u64);
        let mut last_motion = None;
        // Room on the card as last read, minus the segments sent since.
        let mut room = 0usize;
        let fail = |index: u64, error: Error| StreamError {
            index,
            error,
            accepted: 0,
        };
        let settle_one = |in_flight: &mut VecDeque<(u64, u64, u32, bool)>,
                          accepted: &mut u64,
                          last_motion: &mut Option<GroupMotion>|
         -> std::result::Result<(), StreamError> {
            let Some((index, last, seq, is_segment)) = in_flight.pop_front() else {
                return Ok(());
            };
            match card.wait_ack(seq).map_err(|e| fail(index, e))? {
                Ok(()) => {
                    *accepted += last - index + 1;
                    counters[1].store(*accepted, Ordering::Relaxed);
                    if is_segment {
                        *last_motion = Some(self.motion(seq));
                    }
                    Ok(())
                }
                Err(code) => Err(fail(
                    index,
                    Error::Nack {
                        command: "path segment",
                        target: Target::Group(self.index()),
                        code,
                        reason: crate::nack_reason(code),
                    },
                )),
            }
        };
        let send_all = || -> std::result::Result<(), StreamError> {
            for Fitted { item, first, last } in items {
                if cancel.load(Ordering::Relaxed) {
                    break;
                }
                let cmd = self.path_command(&item).map_err(|e| fail(first, e))?;
                if let Some(curve) = nurbs_of(&item) {
                    // A curve's transfer runs alone: what was sent before is answered first,
                    // and its pieces fit when the card says so (the room is read again after).
                    while !in_flight.is_empty() {
                        settle_one(&mut in_flight, &mut accepted, &mut last_motion)?;
                    }
                    let seq = self
                        .path_curve(cmd, curve, Some(cancel))
                        .map_err(|e| fail(first, e))?;
                    accepted += last - first + 1;
                    counters[1].store(accepted, Ordering::Relaxed);
                    last_motion = Some(self.motion(seq));
                    room = 0;
                } else {
                    let is_segment = matches!(item, PathItem::Segment(_));
                    if is_segment {
                        // Wait for room in the card's buffer (the path runs and frees it).
                        while room == 0 {
                            while !in_flight.is_empty() {
                                settle_one(&mut in_flight, &mut accepted, &mut last_motion)?;
                            }
                            room = self.path_free().map_err(|e| fail(first, e))?;
                            if room == 0 {
                                if cancel.load(Ordering::Relaxed) {
                                    return Ok(());
                                }
                                card.wait_next_tick(Duration::from_secs(1))
                                    .map_err(|e| fail(first, e))?;
                            }
                        }
                        room -= 1;
                    }
                    if in_flight.len() >= IN_FLIGHT {
                        settle_one(&mut in_flight, &mut accepted, &mut last_motion)?;
                    }
                    // A normal-vector arc's plane goes first (the ring keeps the order; its
                    // answer is awaited: a plane refused is this item's failure).
                    if let Some(plane) =
                        self.arc_plane_command(&item).map_err(|e| fail(first, e))?
                    {
                        card.execute_seq(plane, "path arc plane", Target::Group(self.index()))
                            .map_err(|e| fail(first, e))?;
                    }
                    let seq = loop {
                        match card.send_raw(cmd) {
                            Ok(seq) => break seq,
                            Err(Error::RingFull(_)) if !in_flight.is_empty() => {
                                settle_one(&mut in_flight, &mut accepted, &mut last_motion)?;
                            }
                            Err(e) => return Err(fail(first, e)),
                        }
                    };
                    in_flight.push_back((first, last, seq, is_segment));
                }
                sent = last + 1;
                counters[0].store(sent, Ordering::Relaxed);
                if let Ok((done, queued)) = self.path_counts() {
                    progress(PathProgress {
                        sent,
                        accepted,
                        done,
                        queued,
                    });
                }
            }
            Ok(())
        };
        let outcome = send_all();
        // Every command sent gets its answer before the stream returns, whatever stopped it,
        // and the earliest failure is the one reported.
        let mut first = outcome.err();
        while !in_flight.is_empty() {
            if let Err(e) = settle_one(&mut in_flight, &mut accepted, &mut last_motion) {
                if first.as_ref().is_none_or(|f| e.index < f.index) {
                    first = Some(e);
                }
            }
        }
        match first {
            Some(e) => Err(StreamError { accepted, ..e }),
            None => Ok(last_motion),
        }
    }
}

/// The curve of a NURBS segment.
fn nurbs_of(item: &PathItem) -> Option<&Nurbs> {
    match item {
        PathItem::Segment(Segment {
            geometry: Geometry::Nurbs { curve, .. },
            ..
        }) => Some(curve),
        _ => None,
    }
}

impl Card {
    /// The card's digital outputs (bit i = output i, `proto::OUTPUTS` of them), as it drives
    /// them: set by [`Card::set_outputs`] or by a path's output actions.
    pub fn outputs(&self) -> Result<u32> {
        self.inner().link.check()?;
        Ok(self.window().read32(layout::OUTPUTS))
    }

    /// Set the outputs in `mask` to the bits of `value` now.
    pub fn set_outputs(&self, mask: u32, value: u32) -> Result<()> {
        let c = IoCmd::SetOutputs(SetOutputs { mask, value }).command(0);
        self.execute(c, "set outputs", Target::Card)
    }
}
