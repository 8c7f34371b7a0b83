//! Layout 1.14: paths across cards. A group with path dimensions (`group_dims`,
//! `MC_OP_APPLY_GROUP_DIMS`) runs a path of up to [`DIMS`] axes (`engine.rs`), of which only
//! its own members are driven here; the others are axes another card of the sync bus drives.
//! Every card of such a path holds the same segments, and the speed profile depends only on
//! what is queued on each tick, so segments are staged as they come (checked, with their
//! geometry over every dimension) and go into the path on `MC_OP_PATH_RELEASE`, which the host
//! times to one tick on every card: each card then plans the same profile, to the last bit.

use super::engine::{validate_dims, Dims, Engine, Staged, Wide, DIMS};
use super::path::{path_mode, path_nack, segment_id, PathRun, SegmentCmd};
use super::*;
use crate::motion::path::{BlendSpeed, Geom, Path, PathLimits, Segment, Transition};
use firmware_proto::cmd::{PathFlags, PathMore};
use firmware_proto::layout::PATH_STAGE_LEN;
use firmware_proto::{GroupDims, PATH_LEN};

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
