//! The group's continuous path (layout 1.6): a buffer of `PATH_LEN` segments on the card
//! (lines, arcs and helices, dwells), each with the user's id, run by `motion::path::Path`
//! (corner blends within each segment's tolerance, look-ahead by distance over whatever is
//! queued, a jerk-limited tangential feed within every axis's limits).
//!
//! The command manager validates each segment and pushes it (`path_segment`); `Group::tick`
//! runs the path instead of the move queue while it holds segments (`path_tick`) and drives
//! the members' references with its positions. The path and the move queue do not mix
//! (`PathBusy`). A halt or stop runs along the path; at rest what was not finished is aborted,
//! one `GroupMotionAborted` per segment with its own seq. Storage (the path's pieces and the
//! seqs of its segments) is allocated the first time a group needs it and kept, so a tick never
//! allocates.

use super::engine::Engine;
use super::*;
use crate::motion::nurbs::Nurbs;
use crate::motion::path::{
    BlendSpeed, CurveSegment, Geom, OutputAction, OutputAt, PathEvent, PathLimits, PauseState,
    Segment, Transition,
};
use crate::ram::FixedVec;
use firmware_proto::cmd::{
    PathArc, PathArcNormal, PathArcPlane, PathDwell, PathFlags, PathLine, PathMore, PathNurbs,
    PathOutput,
};
use firmware_proto::{GroupPath, OUTPUTS, PATH_LEN};
use heapless::Deque;

/// A path segment command, decoded: `MC_OP_PATH_LINE`, `_ARC`, `_DWELL`; or the
/// `MC_OP_NURBS_END` of a NURBS segment (its curve staged), as an Aborting segment waits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SegmentCmd {
    /// A line.
    Line(PathLine),
    /// An arc or helix.
    Arc(PathArc),
    /// A dwell.
    Dwell(PathDwell),
    /// A NURBS curve, staged in the group's transfer.
    Curve,
    /// Layout 1.12: an arc in a plane given by a normal vector, with the plane it was sent in.
    ArcNormal(PathArcNormal, ArcPlane),
}

/// Layout 1.12: the plane of normal-vector arcs (MC_OP_PATH_ARC_PLANE): three distinct group
/// axes and the unit normal on them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPlane {
    /// The group axes a, b, c.
    pub axes: [usize; 3],
    /// The unit normal on them.
    pub normal: [f64; 3],
}

/// A group's path and what the firmware keeps about its segments.
#[derive(Clone)]
pub(super) struct PathRun {
    /// The members' path, or a path across cards (layout 1.14, `wide.rs`).
    pub(super) path: Engine,
    /// The command seq of every segment not finished yet, in order (front: the oldest).
    seqs: Deque<u32, PATH_LEN>,
    /// How many of `seqs` have started.
    started: usize,
    /// The id of the last segment queued.
    last_id: u32,
    /// The low-water event may fire (re-armed when the queue grows past the mark).
    low_armed: bool,
    /// Braking for the end of what is queued (`PathStarved` was posted).
    starving: bool,
    /// A halt or stop runs along the path.
    halting: bool,
    /// Segments ended since enable.
    done: u32,
    /// Output bits to set and to clear, collected over a tick.
    set: u32,
    clear: u32,
    /// The group runs the path (from its first segment until the group is at rest after it).
    pub(super) engaged: bool,
    /// The path's state is stale (new, a fault, a disable or a halt dropped it, or its
    /// configuration changed): reset before the next segment.
    pub(super) stale: bool,
    /// The seq of the last segment that ended.
    last_seq: u32,
    /// An Aborting segment waiting for the path to come to rest: its command's seq and the
    /// segment (for a NURBS curve, its MC_OP_NURBS_END's seq; the curve stays staged).
    pending: Option<(u32, SegmentCmd)>,
    /// The NURBS curve being queued (room for the largest, allocated with the path), and its
    /// control points moved to the path's end (a relative curve).
    curve: Nurbs,
    moved: FixedVec<f64, { crate::motion::nurbs::MAX_CTRL * MAX_AXES }>,
}

impl core::fmt::Debug for PathRun {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PathRun")
            .field("queued", &self.seqs.len())
            .field("started", &self.started)
            .field("halting", &self.halting)
            .finish_non_exhaustive()
    }
}

impl PathRun {
    /// MC_GroupEnable: `path_done` starts again from 0.
    pub(super) fn reset_done(&mut self) {
        self.done = 0;
    }

    /// `GroupMotionAborted` (code: the opcode `by`) for every segment not finished, oldest
    /// first; none is left.
    fn abort_unfinished(&mut self, group: u16, by: Opcode, tick: u64, out: &mut Outbox) {
        while let Some(seq) = self.seqs.pop_front() {
            out.push(Event {
                seq,
                kind: EventKind::GroupMotionAborted as u16,
                axis: group,
                code: by as i32,
                tick,
                value: 0.0,
            });
        }
        // then what was staged, after them (layout 1.14)
        self.path.abort_staged(group, by as i32, tick, out);
    }

    pub(super) fn new() -> Self {
        Self {
            path: Engine::narrow(),
            seqs: Deque::new(),
            started: 0,
            last_id: 0,
            low_armed: false,
            starving: false,
            halting: false,
            done: 0,
            set: 0,
            clear: 0,
            engaged: false,
            stale: true,
            last_seq: 0,
            pending: None,
            curve: Nurbs::with_capacity(),
            moved: FixedVec::with_capacity(crate::motion::nurbs::MAX_CTRL * MAX_AXES),
        }
    }

    /// Nothing queued and at rest (segments may be staged).
    pub(super) fn path_at_rest(&self) -> bool {
        self.seqs.is_empty() && (self.stale || !self.path.is_moving())
    }

    /// Nothing queued or staged, at rest.
    fn is_idle(&self) -> bool {
        self.path_at_rest() && self.path.staged() == 0
    }

    /// Room for more segments' seqs.
    pub(super) fn seqs_free(&self) -> usize {
        PATH_LEN - self.seqs.len()
    }

    /// Layout 1.14: run `engine` from now on (None: the one it has); either way the path
    /// starts afresh.
    pub(super) fn set_engine(&mut self, engine: Option<Engine>) {
        if let Some(e) = engine {
            self.path = e;
        }
        self.stale = true;
    }
}

/// Check a `group_path` block for a group of `n` axes at `rate` Hz.
pub fn validate_path_config(b: &GroupPath, n: usize, rate: u32) -> Result<(), NackCode> {
    if !(1..=PATH_LEN).contains(&(b.lookahead as usize)) || b.low_water as usize > PATH_LEN {
        return Err(NackCode::BadConfig);
    }
    if !b.plan_period.is_finite() {
        return Err(NackCode::NotFinite);
    }
    if !(0.0..=crate::motion::path::MAX_PLAN_PERIOD).contains(&b.plan_period) {
        return Err(NackCode::OutOfRange);
    }
    for x in [b.accel, b.jerk] {
        if !x.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if x < 0.0 {
            return Err(NackCode::NonPositiveLimit);
        }
    }
    let mut ranges = [(0i32, 0.0f64); 2 + 3 * MAX_AXES];
    let mut k = 0;
    for (order, x) in [(2i32, b.accel), (3, b.jerk)] {
        if x > 0.0 {
            ranges[k] = (order, x);
            k += 1;
        }
    }
    for i in 0..n {
        for (order, x) in [(1i32, b.vmax[i]), (2, b.amax[i]), (3, b.jmax[i])] {
            if !x.is_finite() {
                return Err(NackCode::NotFinite);
            }
            ranges[k] = (order, x);
            k += 1;
        }
    }
    crate::firmware::nack::check_ranges(rate, &ranges[..k])
}

impl Group {
    /// MC_OP_APPLY_GROUP_PATH: take a validated `group_path` block (the path must be idle).
    pub fn apply_path(&mut self, b: GroupPath, rate: u32) -> Result<(), NackCode> {
        let n = self.config.map_or(MAX_AXES, |c| c.naxes);
        if self.path.as_ref().is_some_and(|p| !p.is_idle()) {
            return Err(NackCode::PathBusy);
        }
        validate_path_config(&b, n, rate)?;
        self.path_cfg = b;
        if let Some(run) = self.path.as_mut() {
            run.stale = true;
        }
        Ok(())
    }

    /// The configuration the path runs with.
    pub fn path_config(&self) -> &GroupPath {
        &self.path_cfg
    }

    /// Does the path hold anything (segments queued or motion)?
    pub(super) fn path_busy(&self) -> bool {
        self.path.as_ref().is_some_and(|p| !p.is_idle())
    }

    /// Can a segment be queued now? The group's configuration.
    pub(super) fn can_path(&self) -> Result<GroupConfig, NackCode> {
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        match self.state {
            GroupState::Disabled => return Err(NackCode::GroupDisabled),
            GroupState::Standby | GroupState::Moving => {}
            _ => return Err(NackCode::InvalidState),
        }
        if cfg.post {
            // Post-interpolation filters would round the corners again, beyond the tolerance.
            return Err(NackCode::IncompatibleMode);
        }
        if self.active.is_some() || !self.queue.is_empty() {
            return Err(NackCode::PathBusy);
        }
        if self.stop.is_some() || self.path.as_ref().is_some_and(|p| p.halting) {
            return Err(NackCode::InvalidState);
        }
        Ok(cfg)
    }

    /// The path, made when the group first needs it; an idle path is reset at the group's
    /// position when its state is stale or something else moved the group since it ended (a
    /// path that simply ran to its end goes on from there, keeping the output actions queued
    /// for its next segment).
    pub(super) fn path_ready(
        &mut self,
        cfg: &GroupConfig,
        ts: f64,
    ) -> Result<&mut PathRun, NackCode> {
        let n = cfg.naxes;
        let wide = self
            .path
            .as_ref()
            .and_then(|r| r.path.as_wide())
            .map(|w| self.wide_limits(w.dims(), ts));
        let run = self.path.get_or_insert_with(PathRun::new);
        if run.path_at_rest() && (run.stale || run.path.position()[..n] != self.queue_end[..n]) {
            let b = &self.path_cfg;
            if let (Engine::Wide(w), Some(lim)) = (&mut run.path, wide) {
                // Layout 1.14: at the staging's origin (wide.rs)
                w.reset_at_origin(&self.queue_end, lim, b.lookahead as usize)?;
                run.stale = false;
                run.started = 0;
                run.starving = false;
                run.halting = false;
                return Ok(run);
            }
            let Engine::Narrow(path) = &mut run.path else {
                return Err(NackCode::BadConfig);
            };
            run.stale = false;
            let mut lim = PathLimits {
                naxes: cfg.naxes,
                ts,
                vmax: [0.0; MAX_AXES],
                amax: [0.0; MAX_AXES],
                jmax: [0.0; MAX_AXES],
                accel: b.accel,
                jerk: b.jerk,
                plan_ticks: crate::motion::path::plan_ticks(b.plan_period, ts),
            };
            lim.vmax[..cfg.naxes].copy_from_slice(&b.vmax[..cfg.naxes]);
            lim.amax[..cfg.naxes].copy_from_slice(&b.amax[..cfg.naxes]);
            lim.jmax[..cfg.naxes].copy_from_slice(&b.jmax[..cfg.naxes]);
            path.reset(self.queue_end, lim, b.lookahead as usize)
                .map_err(|_| NackCode::BadConfig)?;
            run.started = 0;
            run.starving = false;
            run.halting = false;
        }
        Ok(run)
    }

    /// MC_OP_PATH_LINE, _ARC, _DWELL (command `seq`): validate a segment and queue it in
    /// the path. (`SegmentCmd::Curve` is `path_curve`'s.)
    pub fn path_segment(
        &mut self,
        seq: u32,
        sc: &SegmentCmd,
        more: Option<&PathMore>,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        if self.path_dims() > 0 {
            // Layout 1.14: a path across cards stages its segments (wide.rs).
            return self.stage_segment(seq, sc, more, ts);
        }
        if more.is_some() {
            return Err(NackCode::PathDims);
        }
        let (head, flags) = match sc {
            SegmentCmd::Line(l) => ([l.id, l.feed, l.tolerance], l.flags),
            SegmentCmd::Arc(a) => ([a.id, a.feed, a.tolerance], a.flags),
            SegmentCmd::ArcNormal(a, _) => ([a.id, a.feed, a.tolerance], a.flags),
            SegmentCmd::Dwell(d) => ([d.id, d.seconds, 0.0], PathFlags::default()),
            SegmentCmd::Curve => return self.path_curve(seq, ts, tick, out),
        };
        let cfg = self.can_path()?;
        let n = cfg.naxes;
        let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let finite = match sc {
            SegmentCmd::Line(l) => all(&head) && all(&l.targets[..n]),
            SegmentCmd::Arc(a) => {
                let g = &a.arc;
                all(&head) && all(&g.end) && all(&g.aux) && all(&g.helix[..n.saturating_sub(2)])
            }
            SegmentCmd::ArcNormal(a, _) => {
                all(&head) && all(&a.centre) && all(&a.end) && all(&a.helix[..n.saturating_sub(3)])
            }
            _ => all(&head[..2]),
        };
        if !finite {
            return Err(NackCode::NotFinite);
        }
        let a = head;
        let id = segment_id(a[0])?;
        let rate = crate::firmware::rate_hz(ts);
        if let SegmentCmd::Dwell(d) = sc {
            if !(a[1] > 0.0 && a[1] <= crate::MAX_MOVE_TIME) {
                return Err(NackCode::OutOfRange);
            }
            let seg = Segment {
                id,
                geom: Geom::Dwell { time: a[1] },
                feed: 1.0,
                transition: Transition::Exact,
                blend: BlendSpeed::Low,
                last: d.last,
            };
            return self.path_push(seg, seq, &cfg, ts, tick, out);
        }
        let last = flags.last;
        crate::firmware::nack::check_ranges(rate, &[(1, a[1])])?;
        let (transition, blend) = path_mode(&flags, a[2])?;
        let relative = flags.relative;
        let start = self.queue_end;
        let geom = if let SegmentCmd::Line(l) = sc {
            let mut end = start;
            for i in 0..n {
                end[i] = if relative {
                    start[i] + l.targets[i]
                } else {
                    l.targets[i]
                };
            }
            if !end[..n].iter().all(|x| x.abs() <= crate::MAX_POSITION) {
                return Err(NackCode::OutOfRange);
            }
            if (0..n).all(|i| end[i] == start[i]) {
                return Err(NackCode::PathZeroLength);
            }
            Geom::Line { end }
        } else if let SegmentCmd::Arc(arc) = sc {
            let g = self.arc(&cfg, &arc.arc, &start, relative)?;
            let Geometry::Arc { u, v, arc, .. } = g else {
                return Err(NackCode::BadConfig);
            };
            let (cu, cv) = arc.centre();
            Geom::Arc {
                u,
                v,
                centre: [cu, cv],
                ccw: arc.sweep() > 0.0,
                end: g.end(n),
            }
        } else if let SegmentCmd::ArcNormal(arc, plane) = sc {
            normal_arc(&cfg, arc, plane, &start, relative)?
        } else {
            return Err(NackCode::UnknownOpcode);
        };
        let seg = Segment {
            id,
            geom,
            feed: a[1],
            transition,
            blend,
            last,
        };
        if flags.buffer as u32 == raw::MC_PATH_ABORTING && self.path_busy() {
            // PLCopen Aborting on a running path: it stops along its geometry within its
            // limits, what it held is aborted at rest, and this segment starts from there
            // (relative targets from there). Until then the group takes no other segment
            // (InvalidState), as during MC_GroupHalt.
            if let Some(run) = self.path.as_mut() {
                run.path.halt(f64::MAX, f64::MAX);
                run.halting = true;
                run.pending = Some((seq, *sc));
            }
            return Ok(());
        }
        self.path_push(seg, seq, &cfg, ts, tick, out)
    }

    /// MC_OP_PATH_ARC_PLANE: the group's plane for normal-vector arcs (configured group).
    pub fn set_arc_plane(&mut self, p: &PathArcPlane) -> Result<(), NackCode> {
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        self.arc_plane = Some(arc_plane(&cfg, p)?);
        Ok(())
    }

    /// MC_OP_PATH_ARC_NORMAL (command `seq`): an arc in the group's normal plane.
    pub fn path_arc_normal(
        &mut self,
        seq: u32,
        a: &PathArcNormal,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        self.can_path()?;
        let plane = self.arc_plane.ok_or(NackCode::ArcNormal)?;
        self.path_segment(seq, &SegmentCmd::ArcNormal(*a, plane), None, ts, tick, out)
    }

    fn path_push(
        &mut self,
        seg: Segment,
        seq: u32,
        cfg: &GroupConfig,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        let id = seg.id;
        self.path_push_with(id, seq, cfg, ts, tick, out, |run| {
            run.path.push(seg).map_err(path_nack)
        })
    }

    /// Queues what `push` puts in the path as segment `id` of command `seq`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn path_push_with(
        &mut self,
        id: u32,
        seq: u32,
        cfg: &GroupConfig,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
        push: impl FnOnce(&mut PathRun) -> Result<(), NackCode>,
    ) -> Result<(), NackCode> {
        let low_water = self.path_cfg.low_water as usize;
        let run = self.path_ready(cfg, ts)?;
        if run.seqs.len() >= PATH_LEN {
            return Err(NackCode::QueueFull);
        }
        push(run)?;
        // Room checked above: the segment and its seq go in together.
        let _ = run.seqs.push_back(seq);
        run.engaged = true;
        run.last_id = id;
        if run.seqs.len() > low_water {
            run.low_armed = true;
        }
        self.queue_end = run.path.end();
        self.move_count = self.move_count.wrapping_add(1);
        // A path that waited to be in position is done: this one goes on from there.
        if let Some(done) = self.final_seq.take() {
            out.push(self.event(EventKind::GroupMotionDone, done, 0, 0.0, tick));
        }
        if self.state == GroupState::Standby {
            self.set_state(GroupState::Moving, tick, out);
        }
        Ok(())
    }

    /// MC_OP_PATH_NURBS: check a NURBS path segment's header and open its transfer (its data
    /// follows in MC_OP_NURBS_DATA, MC_OP_NURBS_END queues it: `path_curve`).
    pub fn path_nurbs_begin(&mut self, p: &PathNurbs, ts: f64) -> Result<(), NackCode> {
        self.rx.open = false;
        let cfg = self.can_path()?;
        if self.path_dims() > 0 {
            return Err(NackCode::IncompatibleMode);
        }
        let [degree, n_ctrl, n_knots] = p.size.to_array();
        let a = [
            p.id,
            p.feed,
            p.tolerance,
            degree,
            n_ctrl,
            n_knots,
            p.fit_tolerance,
        ];
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let id = segment_id(a[0])?;
        crate::firmware::nack::check_ranges(crate::firmware::rate_hz(ts), &[(1, a[1])])?;
        path_mode(&p.flags, a[2])?;
        let (degree, n_ctrl) = curve_header(a[3], a[4], a[5], cfg.naxes)?;
        if a[6] <= 0.0 {
            return Err(NackCode::NonPositiveLimit);
        }
        let params = [a[1], a[2], a[6], id as f64, 0.0];
        let opts = MoveOpts::default();
        self.open_rx(
            (degree, cfg.naxes, n_ctrl),
            params,
            false,
            opts,
            Some(p.flags),
        );
        Ok(())
    }

    /// MC_OP_NURBS_END of a path segment (command `seq`): validate the staged curve and queue
    /// it. A curve refused for want of room (`QueueFull`) stays staged: the host sends the end
    /// again once the path has run on.
    pub(super) fn path_curve(
        &mut self,
        seq: u32,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        let stage = core::mem::take(&mut self.rx.stage);
        let r = self.path_curve_from(&stage, seq, ts, tick, out);
        self.rx.stage = stage;
        self.rx.open = r == Err(NackCode::QueueFull);
        r
    }

    fn path_curve_from(
        &mut self,
        stage: &[f64],
        seq: u32,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        let cfg = self.can_path()?;
        let n = cfg.naxes;
        let rx = &self.rx;
        let (degree, n_ctrl, flags) = (rx.degree, rx.n_ctrl, rx.path.unwrap_or_default());
        let [feed, tol, fit, id, _] = rx.params;
        if n != rx.naxes || stage.len() < rx.total {
            return Err(NackCode::NurbsSequence);
        }
        let (transition, blend) = path_mode(&flags, tol)?;
        if flags.buffer as u32 == raw::MC_PATH_ABORTING && self.path_busy() {
            // as for a line: the path stops along its geometry, and the curve (still staged)
            // is queued from there
            if let Some(run) = self.path.as_mut() {
                run.path.halt(f64::MAX, f64::MAX);
                run.halting = true;
                run.pending = Some((seq, SegmentCmd::Curve));
            }
            return Ok(());
        }
        let (pts, rest) = stage.split_at(n_ctrl * n);
        let (weights, rest) = rest.split_at(n_ctrl);
        let knots = &rest[..n_ctrl + degree + 1];
        let relative = flags.relative;
        let start = self.queue_end;
        let last = flags.last;
        let id = id as u32;
        self.path_push_with(id, seq, &cfg, ts, tick, out, |run| {
            let pts = if relative {
                run.moved.clear();
                for p in pts.chunks_exact(n) {
                    for (x, s) in p.iter().zip(&start) {
                        // `pts` holds at most MAX_CTRL points of n ≤ MAX_AXES values
                        let _ = run.moved.push(x + s);
                    }
                }
                if run.moved.iter().any(|x| x.abs() > crate::MAX_POSITION) {
                    return Err(NackCode::OutOfRange);
                }
                &run.moved[..]
            } else {
                pts
            };
            run.curve
                .set(degree, n, pts, weights, knots)
                .map_err(nurbs_nack)?;
            let seg = CurveSegment {
                id,
                curve: &run.curve,
                feed,
                transition,
                blend,
                last,
                tolerance: fit,
            };
            let path = run.path.as_narrow().ok_or(NackCode::IncompatibleMode)?;
            path.push_curve(&seg).map(|_| ()).map_err(path_nack)
        })
    }

    /// MC_OP_PATH_OUTPUT: an output action for the next motion segment queued.
    pub fn path_output(&mut self, o: &PathOutput, ts: f64) -> Result<(), NackCode> {
        let cfg = self.can_path()?;
        let a = [o.output, o.on, o.distance];
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let bit = whole(a[0])
            .filter(|&b| b < OUTPUTS)
            .ok_or(NackCode::PathOutput)? as u8;
        let on = match a[1] {
            0.0 => false,
            1.0 => true,
            _ => return Err(NackCode::PathOutput),
        };
        let at = match o.when as u32 {
            raw::MC_PATH_OUT_AT_START => OutputAt::Start,
            raw::MC_PATH_OUT_AT_END => OutputAt::End,
            raw::MC_PATH_OUT_AT_DISTANCE if a[2] >= 0.0 => OutputAt::Distance(a[2]),
            raw::MC_PATH_OUT_AT_DISTANCE => return Err(NackCode::OutOfRange),
            _ => return Err(NackCode::PathMode),
        };
        if self.path_dims() > 0 {
            // (an output fires on this card only: a path across cards has none)
            return Err(NackCode::IncompatibleMode);
        }
        let run = self.path_ready(&cfg, ts)?;
        let path = run.path.as_narrow().ok_or(NackCode::IncompatibleMode)?;
        path.push_output(OutputAction { bit, on, at })
            .map_err(|_| NackCode::PathOutput)
    }

    /// One tick of the path (the group is moving and the path holds something): drive the
    /// members along it, post its events. Whether the path is at rest with nothing left.
    pub(super) fn path_tick(
        &mut self,
        cfg: &GroupConfig,
        axes: &mut [Axis; MAX_AXES],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> bool {
        let index = self.index;
        let factor = self.overrides.0;
        let low_water = self.path_cfg.low_water as usize;
        let Some(run) = self.path.as_mut() else {
            return true;
        };
        if !run.seqs.is_empty() && !run.halting {
            for &a in &cfg.axes[..cfg.naxes] {
                if axes[a].state != AxisState::SynchronizedMotion {
                    let old = axes[a].join_group_motion();
                    axis_event(out, a, old, AxisState::SynchronizedMotion, tick);
                }
            }
        }
        let ev = |kind: EventKind, seq: u32, value: f64| Event {
            seq,
            kind: kind as u16,
            axis: index,
            code: 0,
            tick,
            value,
        };
        let PathRun {
            path,
            seqs,
            started,
            last_id,
            starving,
            done,
            set,
            clear,
            last_seq,
            ..
        } = &mut *run;
        let pos = path.tick(factor, &mut |e| match e {
            PathEvent::SegmentStart { id } => {
                let seq = seqs.get(*started).copied().unwrap_or(0);
                *started += 1;
                out.push(ev(EventKind::SegmentStart, seq, id as f64));
            }
            PathEvent::SegmentEnd { id } => {
                let seq = seqs.pop_front().unwrap_or(0);
                *started = started.saturating_sub(1);
                *last_seq = seq;
                *done = done.wrapping_add(1);
                out.push(ev(EventKind::SegmentEnd, seq, id as f64));
            }
            PathEvent::Output { bit, on, .. } => {
                let m = 1u32 << bit;
                if on {
                    *set |= m;
                    *clear &= !m;
                } else {
                    *clear |= m;
                    *set &= !m;
                }
            }
            PathEvent::Starving => {
                if !*starving {
                    *starving = true;
                    out.push(ev(EventKind::PathStarved, 0, *last_id as f64));
                }
            }
            PathEvent::Idle => {}
            PathEvent::Paused { id } => {
                out.push(ev(EventKind::PathPaused, 0, id.map_or(-1.0, f64::from)));
            }
        });
        if path.is_moving() {
            run.starving &= run.path.speed() > 0.0;
        } else {
            run.starving = false;
        }
        if run.low_armed && run.seqs.len() <= low_water {
            run.low_armed = false;
            out.push(ev(EventKind::PathLowWater, 0, run.seqs.len() as f64));
        }
        // The members follow the path (no post-interpolation filters on a path).
        for (i, &a) in cfg.axes[..cfg.naxes].iter().enumerate() {
            let vel = (pos[i] - self.pos_out[i]) / ts;
            let acc = (vel - self.prev_vel[i]) / ts;
            self.prev_vel[i] = vel;
            self.pos[i] = CompensatedSum::new();
            self.pos[i].add(pos[i]);
            self.pos_out[i] = pos[i];
            axes[a].drive(Reference {
                pos: pos[i],
                vel,
                acc,
            });
        }
        self.resting = false;
        let Some(run) = self.path.as_mut() else {
            return true;
        };
        if run.path.is_moving() {
            return false;
        }
        if run.halting {
            // At rest after a halt, a stop or an Aborting segment: what was not finished is
            // aborted.
            let by = match (self.stop, run.pending.is_some()) {
                (Some(StopKind::Stop), _) => Opcode::GroupStop,
                (_, true) => Opcode::PathLine,
                _ => Opcode::GroupHalt,
            };
            run.abort_unfinished(index, by, tick, out);
            run.halting = false;
            run.started = 0;
            run.stale = true;
            self.queue_end = run.path.position();
            if let Some((seq, sc)) = run.pending.take() {
                // The Aborting segment starts from here; one that cannot is aborted with the
                // nack it would have had as its code.
                let r = self.path_segment(seq, &sc, None, ts, tick, out);
                if let Err(e) = r {
                    out.push(self.event(EventKind::GroupMotionAborted, seq, e as i32, 0.0, tick));
                } else {
                    return false;
                }
            }
        }
        let Some(run) = self.path.as_mut() else {
            return true;
        };
        if !run.seqs.is_empty() {
            // A dwell or an exact stop between segments: the path goes on by itself.
            return false;
        }
        // At rest at the end of what was queued: done once in position (settle.rs).
        self.queue_end = run.path.position();
        if self.final_seq.is_none() && self.stop.is_none() {
            self.final_seq = Some(run.last_seq);
        }
        true
    }

    /// MC_OP_PATH_PAUSE: 1 pauses the path at the end of the first segment it can stop at,
    /// 0 goes on (see `motion::path::pause`).
    pub fn path_pause(
        &mut self,
        on: f64,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        if !on.is_finite() {
            return Err(NackCode::NotFinite);
        }
        let on = match on {
            0.0 => false,
            1.0 => true,
            _ => return Err(NackCode::OutOfRange),
        };
        let cfg = self.can_path()?;
        let index = self.index;
        let run = self.path_ready(&cfg, ts)?;
        if !on {
            run.path.resume();
        } else if run.path.pause() {
            // at rest with nothing queued: paused now
            let id = match run.path.pause_state() {
                PauseState::Paused { id } => id.map_or(-1.0, f64::from),
                _ => -1.0,
            };
            out.push(Event {
                seq: 0,
                kind: EventKind::PathPaused as u16,
                axis: index,
                code: 0,
                tick,
                value: id,
            });
        }
        Ok(())
    }

    /// A halt or stop on a running path: along its geometry within its limits. What is staged
    /// and not running yet is aborted at once (`by`).
    pub(super) fn path_halt(
        &mut self,
        (dmax, jerk): (f64, f64),
        by: Opcode,
        tick: u64,
        out: &mut Outbox,
    ) -> bool {
        let index = self.index;
        match self.path.as_mut() {
            Some(run) if run.path_at_rest() && run.path.staged() > 0 => {
                run.path.abort_staged(index, by as i32, tick, out);
                false
            }
            Some(run) if !run.is_idle() => {
                run.path.halt(dmax, jerk);
                run.halting = true;
                true
            }
            _ => false,
        }
    }

    /// Everything the path held is aborted now (a fault, a disable): one event per segment.
    pub(super) fn path_abort_all(&mut self, by: Opcode, tick: u64, out: &mut Outbox) {
        let index = self.index;
        let Some(run) = self.path.as_mut() else {
            return;
        };
        run.abort_unfinished(index, by, tick, out);
        run.started = 0;
        run.halting = false;
        run.starving = false;
        run.engaged = false;
        run.pending = None;
        // The next segment resets the path at the group's position.
        run.stale = true;
    }

    /// The outputs the path set and cleared since the last call.
    pub fn take_path_outputs(&mut self) -> (u32, u32) {
        match self.path.as_mut() {
            Some(run) => (
                core::mem::take(&mut run.set),
                core::mem::take(&mut run.clear),
            ),
            None => (0, 0),
        }
    }

    /// The path's words of the group status. Inline: the status does not leave registers and
    /// the stack frame of the publish it is built in (a call taking it would make it be copied
    /// out again, every group every tick).
    #[inline]
    pub(super) fn path_status(&self, s: &mut GroupStatus) {
        let Some(run) = self.path.as_ref() else {
            s.path_free = PATH_LEN as u32;
            return;
        };
        s.path_queued = run.seqs.len() as u32;
        s.path_staged = run.path.staged() as u32;
        // buffer entries: a NURBS curve takes one per piece
        s.path_free = if run.seqs.is_empty() {
            PATH_LEN
        } else {
            run.path.free()
        } as u32;
        s.path_done = run.done;
        let mut flags = 0;
        if let Some(id) = run.path.current_id() {
            s.path_id = id;
            flags |= raw::MC_PATHST_RUNNING;
        }
        if run.starving {
            flags |= raw::MC_PATHST_STARVING;
        }
        if run.halting {
            flags |= raw::MC_PATHST_HALTING;
        }
        match run.path.pause_state() {
            PauseState::None => {}
            PauseState::Pausing => flags |= raw::MC_PATHST_PAUSING,
            PauseState::Paused { id } => {
                flags |= raw::MC_PATHST_PAUSED;
                if let Some(id) = id {
                    s.path_id = id;
                }
            }
        }
        s.path_flags = flags;
        if run.path.is_moving() || !run.seqs.is_empty() {
            s.feed = run.path.speed();
            s.feed_acc = run.path.accel();
            s.path_pos = run.path.distance();
        }
    }
}

/// The plane of normal-vector arcs `p` names for a group of `cfg` (the path's
/// `MC_OP_PATH_ARC_PLANE`, the move queue's `MC_OP_GROUP_CIRCULAR_PLANE`), checked: finite,
/// three distinct whole group axes, a normal not zero (made a unit vector).
pub(super) fn arc_plane(cfg: &GroupConfig, p: &PathArcPlane) -> Result<ArcPlane, NackCode> {
    if !p.axes.iter().chain(p.normal.iter()).all(|x| x.is_finite()) {
        return Err(NackCode::NotFinite);
    }
    let mut axes = [0usize; 3];
    for (a, &x) in axes.iter_mut().zip(&p.axes) {
        if !(x >= 0.0 && x == math::floor(x)) {
            return Err(NackCode::ArcAxes);
        }
        if x >= cfg.naxes as f64 {
            return Err(NackCode::AxisNotInGroup);
        }
        *a = x as usize;
    }
    if axes[0] == axes[1] || axes[1] == axes[2] || axes[0] == axes[2] {
        return Err(NackCode::ArcAxes);
    }
    let normal = crate::motion::path::unit_normal(p.normal).ok_or(NackCode::ArcNormal)?;
    Ok(ArcPlane { axes, normal })
}

/// A segment's user id: an integer in 0..2³²−1.
pub(super) fn segment_id(x: f64) -> Result<u32, NackCode> {
    whole(x)
        .filter(|&x| x <= u32::MAX as usize)
        .map(|x| x as u32)
        .ok_or(NackCode::PathId)
}

/// The geometry of a normal-vector arc from `start` (absolute: `relative` targets added),
/// checked within the group's tolerance and made exact: the centre moved into the plane
/// through the start, the end onto the circle (and into the plane without a rise).
pub(super) fn normal_arc(
    cfg: &GroupConfig,
    a: &PathArcNormal,
    plane: &ArcPlane,
    start: &[f64; MAX_AXES],
    relative: bool,
) -> Result<Geom, NackCode> {
    let n = cfg.naxes;
    let tol = cfg.tolerance;
    let ax = plane.axes;
    let nh = plane.normal;
    if ax.iter().any(|&k| k >= n) {
        // (a plane set for the group's axes: only a configure changes them, and clears it)
        return Err(NackCode::AxisNotInGroup);
    }
    let rel = |k: usize, x: f64| if relative { start[k] + x } else { x };
    let p0 = [start[ax[0]], start[ax[1]], start[ax[2]]];
    let mut c = [0.0; 3];
    let mut e = [0.0; 3];
    for i in 0..3 {
        c[i] = rel(ax[i], a.centre[i]);
        e[i] = rel(ax[i], a.end[i]);
    }
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let norm = |p: [f64; 3]| math::sqrt(dot(p, p));
    // the centre's and the end's heights above the plane through the start
    let hc = dot(sub(c, p0), nh);
    let he = dot(sub(e, p0), nh);
    // in the plane: the start, the end and the centre projected into it
    let inplane = |p: [f64; 3], h: f64| [p[0] - h * nh[0], p[1] - h * nh[1], p[2] - h * nh[2]];
    let cp = inplane(c, hc);
    let ep = inplane(e, he);
    let r0 = norm(sub(p0, cp));
    let r1 = norm(sub(ep, cp));
    if !(r0.is_finite() && r1.is_finite()) {
        return Err(NackCode::OutOfRange);
    }
    if r0 <= tol {
        return Err(NackCode::ZeroLengthArc);
    }
    if hc.abs() > tol || (!a.rise && he.abs() > tol) {
        return Err(NackCode::ArcOffPlane);
    }
    if (r1 - r0).abs() > tol {
        return Err(NackCode::CentreNotEquidistant);
    }
    // the end on the circle, at its height (a rise) or in the plane
    let h = if a.rise { he } else { 0.0 };
    let mut end = *start;
    for i in 0..3 {
        end[ax[i]] = cp[i] + (ep[i] - cp[i]) * (r0 / r1) + h * nh[i];
    }
    let mut k = 0;
    for (i, x) in end.iter_mut().enumerate().take(n) {
        if !ax.contains(&i) {
            *x = if a.helix_relative {
                start[i] + a.helix[k]
            } else {
                rel(i, a.helix[k])
            };
            k += 1;
        }
    }
    if !end[..n].iter().all(|x| x.abs() <= crate::MAX_POSITION) {
        return Err(NackCode::OutOfRange);
    }
    Ok(Geom::ArcNormal {
        axes: ax,
        normal: nh,
        centre: cp,
        rise: a.rise,
        end,
    })
}

/// A segment's PLCopen BufferMode and TransitionMode (its flags) with its tolerance `tol`.
pub(super) fn path_mode(flags: &PathFlags, tol: f64) -> Result<(Transition, BlendSpeed), NackCode> {
    if tol < 0.0 {
        return Err(NackCode::OutOfRange);
    }
    match flags.buffer as u32 {
        raw::MC_PATH_ABORTING | raw::MC_PATH_BUFFERED => Ok((Transition::Exact, BlendSpeed::Low)),
        m @ raw::MC_PATH_BLEND_LOW..=raw::MC_PATH_BLEND_HIGH => {
            let blend = match m {
                raw::MC_PATH_BLEND_LOW => BlendSpeed::Low,
                raw::MC_PATH_BLEND_PREVIOUS => BlendSpeed::Previous,
                raw::MC_PATH_BLEND_NEXT => BlendSpeed::Next,
                _ => BlendSpeed::High,
            };
            let t = match flags.transition as u32 {
                raw::MC_TM_NONE => Transition::Exact,
                raw::MC_TM_MAX_DEVIATION => Transition::MaxDeviation(tol),
                raw::MC_TM_CORNER_DISTANCE => Transition::CornerDistance(tol),
                raw::MC_TM_TIME_SHIFT => Transition::TimeShift(tol),
                _ => return Err(NackCode::PathMode),
            };
            Ok((t, blend))
        }
        _ => Err(NackCode::PathMode),
    }
}

/// The nack for a segment the path refuses.
pub(super) fn path_nack(e: crate::motion::path::PathError) -> NackCode {
    use crate::motion::path::PathError as E;
    match e {
        E::Full => NackCode::QueueFull,
        E::NotFinite => NackCode::NotFinite,
        E::NonPositive => NackCode::NonPositiveLimit,
        E::OutOfRange => NackCode::OutOfRange,
        E::ZeroLength => NackCode::PathZeroLength,
        E::BadArc(_) | E::ArcEndOffCircle => NackCode::CentreNotEquidistant,
        E::BadAxis => NackCode::AxisNotInGroup,
        E::BadNormal => NackCode::ArcNormal,
        E::OffPlane => NackCode::ArcOffPlane,
        E::BadLimits => NackCode::LimitRange,
        E::Moving => NackCode::InvalidState,
        E::TimeShift => NackCode::PathMode,
        E::CurveStart => NackCode::NurbsStart,
        E::Curve => NackCode::PathCurve,
        E::NotReady | E::BadLookahead => NackCode::BadConfig,
    }
}
