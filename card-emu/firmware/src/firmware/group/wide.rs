//! Layout 1.14: paths across cards. A group with path dimensions (`group_dims`,
//! `MC_OP_APPLY_GROUP_DIMS`) runs a path of up to [`DIMS`] axes, `Path<16>`, of which only its
//! own members are driven here; the others are axes another card of the sync bus drives. Every
//! card of such a path holds the same segments, and the speed profile depends only on what is
//! queued on each tick, so segments are staged as they come (checked, with their geometry
//! over every dimension) and go into the path on `MC_OP_PATH_RELEASE`, which the host times to
//! one tick on every card: each card then plans the same profile, to the last bit.
//!
//! [`Engine`] is the path a group runs: its members' (`Path<8>`, the same engine as before
//! dimensions existed) or, with dimensions, the wide one ([`Wide`]). Its positions are handed
//! to the group as its members' (each member is one dimension).

use super::path::{path_mode, path_nack, segment_id, PathRun, SegmentCmd};
use super::*;
use crate::motion::path::{
    BlendSpeed, Geom, Path, PathError, PathEvent, PathLimits, PauseState, Segment, Transition,
};
use firmware_proto::cmd::{PathFlags, PathMore};
use firmware_proto::layout::{PATH_MAX_DIMS, PATH_STAGE_LEN};
use firmware_proto::{GroupDims, PATH_LEN};

/// Dimensions of a path across cards.
pub const DIMS: usize = PATH_MAX_DIMS;

/// A group's path dimensions, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Dims {
    /// How many (1..=DIMS).
    n: usize,
    /// Per dimension: the group axis it drives here (None: another card's).
    member: [Option<usize>; DIMS],
    vmax: [f64; DIMS],
    amax: [f64; DIMS],
    jmax: [f64; DIMS],
    /// Where the remote dimensions start (0 for the members').
    start: [f64; DIMS],
}

impl Dims {
    /// The members' positions in `p`, a point of the path.
    #[inline]
    fn members(&self, p: &[f64; DIMS]) -> [f64; MAX_AXES] {
        let mut out = [0.0; MAX_AXES];
        for (d, m) in self.member[..self.n].iter().enumerate() {
            if let Some(m) = *m {
                out[m] = p[d];
            }
        }
        out
    }
}

/// Check a `group_dims` block for a group of `cfg` at `rate` Hz: `None` for no dimensions.
pub(super) fn validate_dims(
    b: &GroupDims,
    cfg: &GroupConfig,
    rate: u32,
) -> Result<Option<Dims>, NackCode> {
    let n = b.ndims as usize;
    if n == 0 {
        return Ok(None);
    }
    if n > DIMS {
        return Err(NackCode::PathDims);
    }
    let mut member = [None; DIMS];
    let mut seen = [false; MAX_AXES];
    for (d, &a) in b.axis[..n].iter().enumerate() {
        if a == raw::MC_DIM_REMOTE {
            continue;
        }
        let m = usize::try_from(a).map_err(|_| NackCode::PathDims)?;
        if m >= cfg.naxes || seen[m] {
            return Err(NackCode::PathDims);
        }
        seen[m] = true;
        member[d] = Some(m);
    }
    if !seen[..cfg.naxes].iter().all(|&s| s) {
        return Err(NackCode::PathDims);
    }
    let mut ranges = [(0i32, 0.0f64); 3 * DIMS];
    for d in 0..n {
        for (k, (order, x)) in [(1i32, b.vmax[d]), (2, b.amax[d]), (3, b.jmax[d])]
            .into_iter()
            .enumerate()
        {
            if !x.is_finite() {
                return Err(NackCode::NotFinite);
            }
            ranges[3 * d + k] = (order, x);
        }
        let s = b.start[d];
        if member[d].is_none() && !s.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if member[d].is_none() && s.abs() > crate::MAX_POSITION {
            return Err(NackCode::OutOfRange);
        }
    }
    crate::firmware::nack::check_ranges(rate, &ranges[..3 * n])?;
    let mut dims = Dims {
        n,
        member,
        vmax: [0.0; DIMS],
        amax: [0.0; DIMS],
        jmax: [0.0; DIMS],
        start: [0.0; DIMS],
    };
    dims.vmax[..n].copy_from_slice(&b.vmax[..n]);
    dims.amax[..n].copy_from_slice(&b.amax[..n]);
    dims.jmax[..n].copy_from_slice(&b.jmax[..n]);
    for (d, m) in member[..n].iter().enumerate() {
        if m.is_none() {
            dims.start[d] = b.start[d];
        }
    }
    Ok(Some(dims))
}

/// A segment staged, with its command's seq.
#[derive(Debug, Clone, Copy)]
pub(super) struct Staged {
    seq: u32,
    seg: Segment<DIMS>,
}

/// A path across cards: the wide path, its dimensions, the segments staged.
#[derive(Clone)]
pub(super) struct Wide {
    path: Path<DIMS>,
    dims: Dims,
    staged: FixedVec<Staged, PATH_STAGE_LEN>,
    /// Where the next segment staged starts, every dimension.
    stage_end: [f64; DIMS],
    /// Where the path starts afresh (set when staging begins on an idle path).
    origin: [f64; DIMS],
    /// Applied and not reset since: the remote dimensions are at their `start`.
    fresh: bool,
}

/// The path a group runs: its members' or, with dimensions, a wide one. (Unboxed: a group
/// holds one or the other, and the card's build allocates nothing.)
#[derive(Clone)]
#[allow(clippy::large_enum_variant)]
pub(super) enum Engine {
    /// The members' path (`Path<8>`).
    Narrow(Path),
    /// A path across cards.
    Wide(Wide),
}

/// `$e` with `$p` the engine's path, of either width.
macro_rules! on_path {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            Engine::Narrow($p) => $e,
            Engine::Wide(w) => {
                let $p = &mut w.path;
                $e
            }
        }
    };
}
macro_rules! on_path_ref {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            Engine::Narrow($p) => $e,
            Engine::Wide(w) => {
                let $p = &w.path;
                $e
            }
        }
    };
}

impl Engine {
    /// The members' path, storage for `PATH_LEN` segments.
    pub(super) fn narrow() -> Self {
        Self::Narrow(Path::with_capacity(PATH_LEN))
    }

    /// The members' path (None: a wide one).
    pub(super) fn as_narrow(&mut self) -> Option<&mut Path> {
        match self {
            Self::Narrow(p) => Some(p),
            Self::Wide(_) => None,
        }
    }

    /// The wide path (None: the members').
    pub(super) fn as_wide(&self) -> Option<&Wide> {
        match self {
            Self::Narrow(_) => None,
            Self::Wide(w) => Some(w),
        }
    }

    /// Queue a members' segment (a wide path takes none: `BadAxis`).
    pub(super) fn push(&mut self, seg: Segment) -> Result<(), PathError> {
        match self {
            Self::Narrow(p) => p.push(seg),
            Self::Wide(_) => Err(PathError::BadAxis),
        }
    }

    /// Queue a segment of every dimension (a members' path takes none: `BadAxis`).
    pub(super) fn push_wide(&mut self, seg: Segment<DIMS>) -> Result<(), PathError> {
        match self {
            Self::Narrow(_) => Err(PathError::BadAxis),
            Self::Wide(w) => w.path.push(seg),
        }
    }

    #[inline]
    pub(super) fn is_moving(&self) -> bool {
        on_path_ref!(self, p => p.is_moving())
    }
    pub(super) fn speed(&self) -> f64 {
        on_path_ref!(self, p => p.speed())
    }
    pub(super) fn accel(&self) -> f64 {
        on_path_ref!(self, p => p.accel())
    }
    pub(super) fn distance(&self) -> f64 {
        on_path_ref!(self, p => p.distance())
    }
    pub(super) fn current_id(&self) -> Option<u32> {
        on_path_ref!(self, p => p.current_id())
    }
    pub(super) fn free(&self) -> usize {
        on_path_ref!(self, p => p.free())
    }
    pub(super) fn pause_state(&self) -> PauseState {
        on_path_ref!(self, p => p.pause_state())
    }
    pub(super) fn pause(&mut self) -> bool {
        on_path!(self, p => p.pause())
    }
    pub(super) fn resume(&mut self) {
        on_path!(self, p => p.resume())
    }
    pub(super) fn halt(&mut self, decel: f64, jerk: f64) {
        on_path!(self, p => p.halt(decel, jerk))
    }
    /// Where the members are on the path.
    pub(super) fn position(&self) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.position(),
            Self::Wide(w) => w.dims.members(&w.path.position()),
        }
    }
    /// Where the members are at the end of what is queued.
    pub(super) fn end(&self) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.end(),
            Self::Wide(w) => w.dims.members(&w.path.end()),
        }
    }
    /// A servo tick: the members' positions.
    #[inline]
    pub(super) fn tick(&mut self, factor: f64, ev: &mut impl FnMut(PathEvent)) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.tick(factor, ev),
            Self::Wide(w) => {
                let p = w.path.tick(factor, ev);
                w.dims.members(&p)
            }
        }
    }
    /// Segments staged.
    pub(super) fn staged(&self) -> usize {
        self.as_wide().map_or(0, |w| w.staged.len())
    }
    /// Abort every staged segment (`code`: the opcode that did): one event each, oldest first.
    pub(super) fn abort_staged(&mut self, group: u16, code: i32, tick: u64, out: &mut Outbox) {
        if let Self::Wide(w) = self {
            for s in w.staged.iter() {
                out.push(Event {
                    seq: s.seq,
                    kind: EventKind::GroupMotionAborted as u16,
                    axis: group,
                    code,
                    tick,
                    value: 0.0,
                });
            }
            w.staged.clear();
        }
    }
}

impl Group {
    /// MC_OP_APPLY_GROUP_DIMS: take a `group_dims` block (the group configured, its path idle
    /// and nothing staged). The path starts afresh.
    pub fn apply_dims(&mut self, b: &GroupDims, rate: u32) -> Result<(), NackCode> {
        let cfg = self.config.ok_or(NackCode::PathDims)?;
        if self.path_busy() {
            return Err(NackCode::PathBusy);
        }
        let dims = validate_dims(b, &cfg, rate)?;
        let run = self.path.get_or_insert_with(PathRun::new);
        let engine = match (dims, &mut run.path) {
            (None, Engine::Narrow(_)) => None,
            (None, Engine::Wide(_)) => Some(Engine::narrow()),
            (Some(dims), Engine::Wide(w)) => {
                w.dims = dims;
                w.staged.clear();
                w.fresh = true;
                None
            }
            (Some(dims), Engine::Narrow(_)) => Some(Engine::Wide(Wide {
                path: Path::<DIMS>::with_segments(PATH_LEN),
                dims,
                staged: FixedVec::with_capacity(PATH_STAGE_LEN),
                stage_end: [0.0; DIMS],
                origin: [0.0; DIMS],
                fresh: true,
            })),
        };
        run.set_engine(engine);
        Ok(())
    }

    /// The group's path dimensions, if it has some.
    pub fn path_dims(&self) -> usize {
        self.path
            .as_ref()
            .and_then(|r| r.path.as_wide())
            .map_or(0, |w| w.dims.n)
    }

    /// A segment of a group with dimensions (command `seq`, its `MC_OP_PATH_MORE` `more`):
    /// checked and staged.
    pub(super) fn stage_segment(
        &mut self,
        seq: u32,
        sc: &SegmentCmd,
        more: Option<&PathMore>,
        ts: f64,
    ) -> Result<(), NackCode> {
        let cfg = self.can_path()?;
        let queue_end = self.queue_end;
        let tol = cfg.tolerance;
        let Some(run) = self.path.as_mut() else {
            return Err(NackCode::PathDims);
        };
        let idle = run.path_at_rest();
        let Engine::Wide(w) = &mut run.path else {
            return Err(NackCode::PathDims);
        };
        let n = w.dims.n;
        // what the entry holds, and what MC_OP_PATH_MORE must add
        let (head, flags, own) = match sc {
            SegmentCmd::Line(l) => ([l.id, l.feed, l.tolerance], l.flags, MAX_AXES),
            SegmentCmd::Arc(a) => ([a.id, a.feed, a.tolerance], a.flags, MAX_AXES),
            SegmentCmd::Dwell(d) => ([d.id, d.seconds, 0.0], PathFlags::default(), usize::MAX),
            SegmentCmd::Curve | SegmentCmd::ArcNormal(..) => {
                return Err(NackCode::IncompatibleMode)
            }
        };
        if (n > own) != more.is_some() {
            return Err(NackCode::PathMore);
        }
        if w.staged.len() >= PATH_STAGE_LEN {
            return Err(NackCode::QueueFull);
        }
        let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let extra = more.map_or(&[][..], |m| &m.targets[..n - own]);
        let finite = all(&head)
            && all(extra)
            && match sc {
                SegmentCmd::Line(l) => all(&l.targets[..n.min(MAX_AXES)]),
                SegmentCmd::Arc(a) => {
                    let g = &a.arc;
                    all(&g.end) && all(&g.aux) && all(&g.helix[..n.min(MAX_AXES) - 2])
                }
                _ => true,
            };
        if !finite {
            return Err(NackCode::NotFinite);
        }
        let id = segment_id(head[0])?;
        w.begin_staging(idle, &queue_end);
        let seg = if let SegmentCmd::Dwell(d) = sc {
            if !(head[1] > 0.0 && head[1] <= crate::MAX_MOVE_TIME) {
                return Err(NackCode::OutOfRange);
            }
            Segment {
                id,
                geom: Geom::Dwell { time: head[1] },
                feed: 1.0,
                transition: Transition::Exact,
                blend: BlendSpeed::Low,
                last: d.last,
            }
        } else {
            let rate = crate::firmware::rate_hz(ts);
            crate::firmware::nack::check_ranges(rate, &[(1, head[1])])?;
            if flags.buffer as u32 == raw::MC_PATH_ABORTING {
                return Err(NackCode::PathMode);
            }
            let (transition, blend) = path_mode(&flags, head[2])?;
            let geom = wide_geom(sc, extra, &w.stage_end, n, flags.relative, tol)?;
            Segment {
                id,
                geom,
                feed: head[1],
                transition,
                blend,
                last: flags.last,
            }
        };
        if let Geom::Line { end } | Geom::Arc { end, .. } = seg.geom {
            w.stage_end = end;
        }
        // (room checked above)
        let _ = w.staged.push(Staged { seq, seg });
        Ok(())
    }

    /// MC_OP_PATH_RELEASE: the oldest `count` staged segments go into the path, in order, as
    /// segments pushed now would (a path at rest starts afresh at the staging's origin). One
    /// the path refuses is aborted with its nack as the code, and so are those after it.
    pub fn path_release(
        &mut self,
        count: f64,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        if !count.is_finite() {
            return Err(NackCode::NotFinite);
        }
        let staged = match self.path.as_ref().and_then(|r| r.path.as_wide()) {
            Some(w) => w.staged.len(),
            None => return Err(NackCode::PathDims),
        };
        let k = whole(count)
            .filter(|&k| (1..=staged).contains(&k))
            .ok_or(NackCode::PathRelease)?;
        let cfg = self.can_path()?;
        let run = self.path_ready(&cfg, ts)?;
        if run.path.free() < k || run.seqs_free() < k {
            return Err(NackCode::QueueFull);
        }
        let mut failed = None;
        for i in 0..k {
            let Some(Staged { seq, seg }) = self
                .path
                .as_ref()
                .and_then(|r| r.path.as_wide())
                .map(|w| w.staged[i])
            else {
                break;
            };
            let r = match failed {
                Some(code) => Err(code),
                None => self.path_push_with(seg.id, seq, &cfg, ts, tick, out, |run| {
                    run.path.push_wide(seg).map_err(path_nack)
                }),
            };
            if let Err(code) = r {
                failed = Some(code);
                out.push(self.event(EventKind::GroupMotionAborted, seq, code as i32, 0.0, tick));
            }
        }
        if let Some(Engine::Wide(w)) = self.path.as_mut().map(|r| &mut r.path) {
            let n = w.staged.len();
            w.staged.copy_within(k..n, 0);
            w.staged.truncate(n - k);
        }
        Ok(())
    }

    /// The wide path's limits: `group_dims`' per dimension, `group_path`'s tangential ones.
    pub(super) fn wide_limits(&self, dims: &Dims, ts: f64) -> PathLimits<DIMS> {
        let b = &self.path_cfg;
        PathLimits {
            naxes: dims.n,
            ts,
            vmax: dims.vmax,
            amax: dims.amax,
            jmax: dims.jmax,
            accel: b.accel,
            jerk: b.jerk,
            plan_ticks: crate::motion::path::plan_ticks(b.plan_period, ts),
        }
    }
}

impl Wide {
    /// At rest with nothing queued (`path_at_rest`) and nothing staged: the next segment staged
    /// starts afresh, where the members are (`members`) and the remote dimensions were left.
    fn begin_staging(&mut self, path_at_rest: bool, members: &[f64; MAX_AXES]) {
        if !(self.staged.is_empty() && path_at_rest) {
            return;
        }
        let mut o = if self.fresh {
            self.dims.start
        } else {
            self.path.position()
        };
        for (o, m) in o.iter_mut().zip(&self.dims.member[..self.dims.n]) {
            if let Some(m) = *m {
                *o = members[m];
            }
        }
        self.origin = o;
        self.stage_end = o;
    }

    /// Reset at the staging's origin (the members must be there: `PathRelease` else).
    pub(super) fn reset_at_origin(
        &mut self,
        members: &[f64; MAX_AXES],
        lim: PathLimits<DIMS>,
        lookahead: usize,
    ) -> Result<(), NackCode> {
        let moved = (0..self.dims.n)
            .any(|d| self.dims.member[d].is_some_and(|m| self.origin[d] != members[m]));
        if moved {
            // the group moved since these segments were staged from where it was
            return Err(NackCode::PathRelease);
        }
        self.path
            .reset(self.origin, lim, lookahead)
            .map_err(|_| NackCode::BadConfig)?;
        self.fresh = false;
        Ok(())
    }

    /// The dimensions.
    pub(super) fn dims(&self) -> &Dims {
        &self.dims
    }
}

/// The geometry over `n` dimensions of a line or an arc staged from `start` (`extra`: the
/// targets its `MC_OP_PATH_MORE` adds), checked as the path will take it.
fn wide_geom(
    sc: &SegmentCmd,
    extra: &[f64],
    start: &[f64; DIMS],
    n: usize,
    relative: bool,
    tol: f64,
) -> Result<Geom<DIMS>, NackCode> {
    let rel = |d: usize, x: f64| if relative { start[d] + x } else { x };
    let mut end = *start;
    let geom = match sc {
        SegmentCmd::Line(l) => {
            let own = n.min(MAX_AXES);
            for (d, &x) in l.targets[..own].iter().chain(extra).enumerate() {
                end[d] = rel(d, x);
            }
            if (0..n).all(|d| end[d] == start[d]) {
                return Err(NackCode::PathZeroLength);
            }
            Geom::Line { end }
        }
        SegmentCmd::Arc(a) => {
            let g = &a.arc;
            let (u, v) = arc_axes(g, n)?;
            let arc = arc_circle(g, (u, v), (start[u], start[v]), rel, tol)?;
            let helix_relative = relative || g.flags.helix_relative;
            let own = n.min(MAX_AXES) - 2;
            let mut targets = g.helix[..own].iter().chain(extra);
            for (d, e) in end.iter_mut().enumerate().take(n) {
                if d != u && d != v {
                    let h = targets.next().copied().unwrap_or(0.0);
                    *e = if helix_relative { start[d] + h } else { h };
                }
            }
            let (pu, pv) = arc.point_at(arc.length()).unwrap_or((start[u], start[v]));
            end[u] = pu;
            end[v] = pv;
            let (cu, cv) = arc.centre();
            Geom::Arc {
                u,
                v,
                centre: [cu, cv],
                ccw: arc.sweep() > 0.0,
                end,
            }
        }
        _ => return Err(NackCode::IncompatibleMode),
    };
    if !end[..n].iter().all(|x| x.abs() <= crate::MAX_POSITION) {
        return Err(NackCode::OutOfRange);
    }
    Ok(geom)
}
