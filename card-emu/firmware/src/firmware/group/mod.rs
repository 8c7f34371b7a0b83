//! Axes groups: PLCopen group states, a queue of buffered moves (a `heapless::Deque` of
//! `GROUP_QUEUE_LEN`), the interpolators (linear, circular, helical, synchronised
//! point-to-point) and the tangential feed, feeding the axes through their post-interpolation
//! acc/dec filters.
//!
//! Per servo tick a moving group runs these steps, one file each, each with its own tests:
//! - `activate.rs`: the next queued move starts (the filters switch feed type only when empty);
//! - `stop.rs`: a halt or stop advances along its stop profile;
//! - `feed.rs`: the active move's tangential feed advances — an S-curve of the path length
//!   (pre-interpolation acc/dec, Thinh eq 1–28), a constant feed (post-interpolation acc/dec
//!   only, as in Kim), the reference-word circle of Kim eq 15–23 (constant feed), or Yeh's
//!   NURBS interpolator (`nurbs_pool.rs` holds the curves) — and the path at the new arc
//!   length gives each axis's increment (Kim's pulse data f_i(k));
//! - `filter.rs`: each increment passes through the axis's acc/dec filter (Kim eq 1/9, Shin eq
//!   36–40) when post-interpolation acc/dec is on, and is added to its commanded position;
//! - `snap.rs`, `settle.rs`: at rest, the snap to the programmed end, then in position the
//!   done events and the states.
//!
//! `nurbs_rx.rs` takes a curve in (begin, data, end) for a NURBS move or a path segment.
//! `testing.rs` holds the tests' fixtures.
//!
//! A synchronised point-to-point move (Kim eq 10–14) is a straight line in axis space whose
//! length is the largest axis distance `L`, run along one normalised profile (`f_iy = P_y/N`,
//! eq 11), so every axis starts and ends on the same tick. Each axis `i` has its own limits
//! (the command's, or those staged for it with `MC_OP_GROUP_PTP_LIMITS`); along the line they
//! become `limit_i·L/|P_i|`, and the profile is planned with the smallest of each: the axis
//! that needs the most time sets it and the others scale, each within its own limits.
//!
//! The commanded positions are error-free sums of the filtered increments; a group at rest is
//! snapped to its programmed end, and the largest correction that snap made is published
//! (`snap_last`, `snap_max`), so a filter that lost distance would show.

mod activate;
mod engine;
mod feed;
mod filter;
mod home;
mod normal;
mod nurbs_pool;
mod nurbs_rx;
mod overrides;
mod path;
mod settle;
mod snap;
mod stop;
#[cfg(test)]
mod testing;
mod wide;

pub use self::home::{GroupHoming, HomeOrder};
use self::nurbs_pool::NurbsPool;
pub use self::nurbs_pool::NURBS_SLOTS;
pub use self::nurbs_rx::nurbs_nack;
use self::nurbs_rx::{curve_header, NurbsRx, STAGE_LEN};
pub use self::path::{validate_path_config, SegmentCmd};
use crate::firmware::axis::Axis;
pub use crate::firmware::outbox::Outbox;
use crate::math;
use crate::motion::arc::{ArcDirection, ExactCircle, ReferenceWordCircle};
use crate::motion::filters::{AccDecFilter, CompensatedSum, FilterKind};
use crate::motion::nurbs::NurbsError;
use crate::motion::nurbs_interp::{InterpConfig, InterpError};
use crate::motion::otg::Trajectory;
use crate::motion::saturation::SaturationAwareFeed;
use crate::motion::scurve::{Limits, Profile};
use crate::ram::{FixedVec, Lazy};
use crate::servo::ffpiv::Reference;
use crate::servo::pdplus::{AxisModel, DriveModel, PdPlusGains};
use firmware_proto::cmd::{
    ArcGeometry, CircularMove, CircularNormalMove, CircularPlane, FeedLimits, LinearMove, MoveOpts,
    PtpLimits, PtpMove,
};
use firmware_proto::{
    raw, AxisState, Event, EventKind, GroupState, GroupStatus, NackCode, Opcode, GROUP_QUEUE_LEN,
    MAX_AXES,
};
use heapless::Deque;

// The steps' tests name the move flags (through `super::*`).
#[cfg(test)]
use firmware_proto::move_flags;

/// A group move command, decoded: MC_MoveLinear, synchronised point-to-point, MC_MoveCircular.
#[derive(Debug, Clone, Copy)]
pub enum GroupMove<'a> {
    /// `MC_OP_GROUP_MOVE_LINEAR`.
    Linear(&'a LinearMove),
    /// `MC_OP_GROUP_MOVE_PTP`.
    Ptp(&'a PtpMove),
    /// `MC_OP_GROUP_MOVE_CIRCULAR`.
    Circular(&'a CircularMove),
    /// Layout 1.13: `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` and its second entry,
    /// `MC_OP_GROUP_CIRCULAR_PLANE` (`normal.rs`).
    CircularNormal(&'a CircularNormalMove, &'a CircularPlane),
}

impl GroupMove<'_> {
    /// The limits along the path and the move's options.
    fn limits_opts(&self) -> (FeedLimits, MoveOpts) {
        match self {
            Self::Linear(m) => (m.limits, m.opts),
            Self::Ptp(m) => (m.line.limits, m.line.opts),
            Self::Circular(m) => (m.limits, m.opts),
            Self::CircularNormal(m, _) => (m.limits, m.opts),
        }
    }

    /// Are the numbers the move gives a group of `n` axes finite: the limits, then the targets
    /// (a line's) or the end, aux and helical targets (an arc's)?
    fn finite(&self, n: usize) -> bool {
        let (lim, _) = self.limits_opts();
        let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
        all(&lim.to_array())
            && match self {
                Self::Linear(m) => all(&m.targets[..n]),
                Self::Ptp(m) => all(&m.line.targets[..n]),
                Self::Circular(m) => {
                    let a = &m.arc;
                    all(&a.end) && all(&a.aux) && all(&a.helix[..n.saturating_sub(2)])
                }
                Self::CircularNormal(m, p) => {
                    all(&m.centre)
                        && all(&m.end)
                        && m.turns.is_finite()
                        && all(&p.plane.axes)
                        && all(&p.plane.normal)
                        && all(&p.helix[..n.saturating_sub(3)])
                }
            }
    }
}

/// A validated group configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupConfig {
    /// Axes in the group.
    pub naxes: usize,
    /// Card axis of each group axis (X, Y, Z, …).
    pub axes: [usize; MAX_AXES],
    /// S-curve of the tangential feed along the path.
    pub pre: bool,
    /// Per-axis acc/dec filters after interpolation.
    pub post: bool,
    /// Kim's reference-word interpolator for arcs (else exact).
    pub reference_word: bool,
    /// Geometry tolerance, counts.
    pub tolerance: f64,
    /// Layout 1.11: the configured home order (0 stages: none).
    pub home: HomeOrder,
}

/// The acc/dec filter configuration of one axis: kind and time constant per feed type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterConfig {
    /// Kind per feed type (rapid, cutting, jog).
    pub kind: [FilterKind; 3],
    /// Time constant per feed type, s.
    pub tau: [f64; 3],
}

impl Default for FilterConfig {
    /// Shin Table 1 (x/y axes): rapid bell 35 ms, cutting linear 30 ms, jog exponential 50 ms.
    fn default() -> Self {
        let p = crate::motion::filters::FilterPreset::shin_table1();
        Self {
            kind: [p.rapid.kind, p.cutting.kind, p.jog.kind],
            tau: [
                p.rapid.time_constant_s,
                p.cutting.time_constant_s,
                p.jog.time_constant_s,
            ],
        }
    }
}

impl FilterConfig {
    /// Decode the wire kinds.
    pub fn kind_from_raw(k: u32) -> Option<FilterKind> {
        match k {
            raw::MC_FILTER_NONE => Some(FilterKind::None),
            raw::MC_FILTER_LINEAR => Some(FilterKind::Linear),
            raw::MC_FILTER_EXPONENTIAL => Some(FilterKind::Exponential),
            raw::MC_FILTER_BELL => Some(FilterKind::Bell),
            _ => None,
        }
    }

    /// Encode a kind for the wire.
    pub fn kind_to_raw(k: FilterKind) -> u32 {
        match k {
            FilterKind::None => raw::MC_FILTER_NONE,
            FilterKind::Linear => raw::MC_FILTER_LINEAR,
            FilterKind::Exponential => raw::MC_FILTER_EXPONENTIAL,
            FilterKind::Bell => raw::MC_FILTER_BELL,
        }
    }

    /// Every feed type's filter can be built at sample time `ts`.
    /// The register block that holds this configuration.
    pub fn to_block(&self) -> firmware_proto::raw::mc_axis_filter {
        firmware_proto::raw::mc_axis_filter {
            kind: self.kind.map(Self::kind_to_raw),
            tau: self.tau,
            ..Default::default()
        }
    }

    pub fn validate(&self, ts: f64) -> Result<(), NackCode> {
        for f in 0..3 {
            AccDecFilter::from_time_constant(self.kind[f], self.tau[f], ts)
                .map_err(|_| NackCode::BadConfig)?;
        }
        Ok(())
    }
}

/// One axis's live filter and the (feed type, servo period) it was built for.
#[derive(Debug, Clone)]
pub struct AxisFilter {
    /// Configuration.
    pub config: FilterConfig,
    live: AccDecFilter,
    built_for: Option<(usize, u64)>,
}

impl AxisFilter {
    fn new() -> Self {
        Self {
            config: FilterConfig::default(),
            live: AccDecFilter::None,
            built_for: None,
        }
    }

    /// No distance left inside.
    pub fn is_settled(&self) -> bool {
        self.live.is_settled()
    }

    /// Make the live filter the one for `feed` at `ts` (only call when settled).
    fn select(&mut self, feed: usize, ts: f64) {
        let key = (feed, ts.to_bits());
        if self.built_for != Some(key) {
            // Validated on apply; a failure here can only come from a servo-rate change, and
            // then the pass-through is the safe choice.
            self.live =
                AccDecFilter::from_time_constant(self.config.kind[feed], self.config.tau[feed], ts)
                    .unwrap_or(AccDecFilter::None);
            self.built_for = Some(key);
        }
    }
}

/// The path of one move. Points are in group axis order.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(clippy::large_enum_variant)] // inline on purpose: the firmware never allocates
enum Geometry {
    /// `p(s) = start + delta·s/len`; `len` is Euclidean (linear) or the largest axis distance
    /// (synchronised point-to-point).
    Line {
        start: [f64; MAX_AXES],
        delta: [f64; MAX_AXES],
        len: f64,
    },
    /// An arc in the plane of group axes `(u, v)`, the other axes moving linearly with it.
    Arc {
        start: [f64; MAX_AXES],
        u: usize,
        v: usize,
        arc: ExactCircle,
        helix: [f64; MAX_AXES],
        len: f64,
    },
    /// Layout 1.13: an arc in a plane given by a normal vector, the other axes (and a rise
    /// along the normal) moving linearly with it: the path's geometry (`normal.rs`).
    ArcNormal(crate::motion::path::Helix),
    /// A NURBS curve: its points come from its interpolator ([`Feed::Nurbs`]); the geometry
    /// keeps its ends and length.
    Curve {
        start: [f64; MAX_AXES],
        end: [f64; MAX_AXES],
        len: f64,
    },
}

impl Geometry {
    fn len(&self) -> f64 {
        match self {
            Geometry::Line { len, .. }
            | Geometry::Arc { len, .. }
            | Geometry::Curve { len, .. } => *len,
            Geometry::ArcNormal(h) => h.length(),
        }
    }

    fn start(&self) -> [f64; MAX_AXES] {
        match self {
            Geometry::Line { start, .. }
            | Geometry::Arc { start, .. }
            | Geometry::Curve { start, .. } => *start,
            Geometry::ArcNormal(h) => h.ends().0,
        }
    }

    /// The point at arc length `s` (clamped to the move).
    fn point(&self, s: f64, n: usize) -> [f64; MAX_AXES] {
        let mut p = self.start();
        let len = self.len();
        let f = if len > 0.0 {
            (s / len).clamp(0.0, 1.0)
        } else {
            1.0
        };
        match self {
            Geometry::Line { delta, .. } => {
                for i in 0..n {
                    p[i] += delta[i] * f;
                }
                if f >= 1.0 {
                    return self.end(n);
                }
            }
            Geometry::Arc {
                u, v, arc, helix, ..
            } => {
                for i in 0..n {
                    p[i] += helix[i] * f;
                }
                let (pu, pv) = arc.point_at(arc.length() * f).unwrap_or((p[*u], p[*v]));
                p[*u] = pu;
                p[*v] = pv;
            }
            Geometry::ArcNormal(h) => return h.point(s),
            // Points of a curve come from its interpolator; this is only ever asked for its
            // ends.
            Geometry::Curve { end, .. } => {
                if f >= 1.0 {
                    return *end;
                }
            }
        }
        p
    }

    fn end(&self, n: usize) -> [f64; MAX_AXES] {
        match self {
            Geometry::Line { start, delta, .. } => {
                let mut p = *start;
                for i in 0..n {
                    p[i] += delta[i];
                }
                p
            }
            Geometry::Arc {
                start,
                u,
                v,
                arc,
                helix,
                ..
            } => {
                let mut p = *start;
                for i in 0..n {
                    p[i] += helix[i];
                }
                let (pu, pv) = arc.point_at(arc.length()).unwrap_or((p[*u], p[*v]));
                p[*u] = pu;
                p[*v] = pv;
                p
            }
            Geometry::ArcNormal(h) => h.ends().1,
            Geometry::Curve { end, .. } => *end,
        }
    }
}

/// How the arc length advances.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // inline on purpose: the firmware never allocates
enum Feed {
    /// Pre-interpolation S-curve of the path length within `lim` (planned at the programmed
    /// feed; an override replans it into [`Active::retimed`]); `t` is the time into it.
    Profile {
        profile: Profile,
        t: f64,
        lim: Limits,
    },
    /// Constant feed (post-interpolation acc/dec only).
    Constant { v: f64 },
    /// Kim's reference-word arc at constant feed: the plane increments come from it.
    ReferenceWord(ReferenceWordCircle),
    /// A NURBS curve: Yeh's speed-controlled interpolator, saturation-aware when its slot's
    /// `sat` is set. The curve lives in the group's slot of this index (see [`NurbsPool`]).
    Nurbs(usize),
}

/// An exact non-negative integer carried in an f64 argument.
fn whole(x: f64) -> Option<usize> {
    (x.is_finite() && math::fract(x) == 0.0 && (0.0..=1e9).contains(&x)).then_some(x as usize)
}

/// A queued move.
#[derive(Debug, Clone)]
struct Move {
    seq: u32,
    geom: Geometry,
    feed: Feed,
    feed_type: usize,
    /// A point-to-point move (MC_OP_GROUP_MOVE_PTP): the rapid override applies, else the
    /// feed override.
    ptp: bool,
    /// A NURBS curve a halt or stop keeps (already reported aborted) because the stop of the
    /// curve before it runs on into it.
    runout: bool,
}

/// The move being interpolated.
#[derive(Debug, Clone)]
struct Active {
    mv: Move,
    /// Arc length reached.
    s: f64,
    /// Last point emitted (group axis order).
    last: [f64; MAX_AXES],
    /// A halt or stop replaced the feed: (profile, time into it).
    stopping: Option<(Profile, f64)>,
    /// An override replanned the S-curve feed from where the path was: (the path's S-curve
    /// from then, time into it). It replaces the move's own profile.
    retimed: Option<(Trajectory, f64)>,
    /// Tangential velocity and acceleration, for status and stopping.
    v: f64,
    a: f64,
}

/// What ends a stop or halt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum StopKind {
    Halt(u32),
    Stop,
}

/// One axes group.
#[derive(Debug, Clone)]
pub struct Group {
    index: u16,
    /// PLCopen group state.
    pub state: GroupState,
    /// Configuration (None until configured).
    pub config: Option<GroupConfig>,
    /// The buffered moves, oldest first.
    queue: Deque<Move, GROUP_QUEUE_LEN>,
    active: Option<Active>,
    /// Programmed end of everything queued (group axis order).
    queue_end: [f64; MAX_AXES],
    /// A move finished interpolating and the group waits to be in position: its seq.
    final_seq: Option<u32>,
    settled_for: f64,
    stop: Option<StopKind>,
    stop_released: bool,
    /// A halt or stop in progress: seconds since it began (until the group is at rest).
    stop_elapsed: Option<f64>,
    move_count: u32,
    prev_vel: [f64; MAX_AXES],
    rx: NurbsRx,
    /// Commanded position of each member, an error-free sum of the increments driven.
    pos: [CompensatedSum; MAX_AXES],
    /// The position last driven (rounded `pos`): anything else moving the reference resyncs.
    pos_out: [f64; MAX_AXES],
    /// At rest and snapped since the last motion.
    resting: bool,
    /// Largest |programmed end − commanded position| over the axes at the last snap, counts.
    snap_last: f64,
    /// Largest such correction since the group was enabled, counts.
    snap_max: f64,
    /// Per-axis limits staged for the next point-to-point move: v, a, d, j (counts).
    ptp_stage: [Option<[f64; 4]>; MAX_AXES],
    /// The NURBS curves queued and active, in storage allocated once.
    nurbs: NurbsPool,
    /// MC_SetOverride: (feed factor, rapid factor), each 0..=OVERRIDE_MAX.
    overrides: (f64, f64),
    /// The continuous path (made when the group first needs it).
    path: Lazy<path::PathRun>,
    /// Its configuration (`group_path`, validated).
    path_cfg: firmware_proto::GroupPath,
    /// Layout 1.11: MC_GroupHome in progress.
    pub(crate) home: Option<GroupHoming>,
    /// Layout 1.12: the plane of normal-vector arcs (MC_OP_PATH_ARC_PLANE): three group axes
    /// and the unit normal on them.
    arc_plane: Option<path::ArcPlane>,
}

impl Group {
    /// A disabled, unconfigured group.
    pub fn new(index: usize) -> Self {
        Self {
            index: index as u16,
            state: GroupState::Disabled,
            config: None,
            queue: Deque::new(),
            active: None,
            queue_end: [0.0; MAX_AXES],
            final_seq: None,
            settled_for: 0.0,
            stop: None,
            stop_released: false,
            stop_elapsed: None,
            move_count: 0,
            prev_vel: [0.0; MAX_AXES],
            rx: NurbsRx {
                stage: FixedVec::from_elem(0.0, STAGE_LEN),
                ..NurbsRx::default()
            },
            pos: [CompensatedSum::new(); MAX_AXES],
            pos_out: [0.0; MAX_AXES],
            resting: true,
            snap_last: 0.0,
            snap_max: 0.0,
            ptp_stage: [None; MAX_AXES],
            nurbs: NurbsPool::new(),
            overrides: (1.0, 1.0),
            path: Lazy::new(),
            path_cfg: firmware_proto::GroupPath::default(),
            home: None,
            arc_plane: None,
        }
    }

    /// Start the members' position sums where their references are.
    fn sync_positions(&mut self, axes: &[Axis; MAX_AXES], cfg: &GroupConfig) {
        for (i, &a) in cfg.axes[..cfg.naxes].iter().enumerate() {
            let p = axes[a].reference().pos;
            self.queue_end[i] = p;
            self.pos[i] = CompensatedSum::new();
            self.pos[i].add(p);
            self.pos_out[i] = p;
        }
        self.resting = true;
    }

    /// Does the group hold axis `a` (configured and enabled)?
    pub fn owns_enabled(&self, a: usize) -> bool {
        self.state != GroupState::Disabled
            && self.config.is_some_and(|c| c.axes[..c.naxes].contains(&a))
    }

    /// The member axes while the group moves (GroupMoving or GroupStopping).
    pub fn moving_members(&self) -> Option<&[usize]> {
        match (&self.config, self.state) {
            (Some(c), GroupState::Moving | GroupState::Stopping) => Some(&c.axes[..c.naxes]),
            _ => None,
        }
    }

    /// Is a halt or stop of the group under way (MC_GroupHalt, MC_GroupStop, a detach)?
    pub fn stopping(&self) -> bool {
        self.stop.is_some() || self.state == GroupState::Stopping
    }

    /// Is axis `a` in this group's configuration?
    pub fn contains(&self, a: usize) -> bool {
        self.config.is_some_and(|c| c.axes[..c.naxes].contains(&a))
    }

    pub(crate) fn set_state(&mut self, s: GroupState, tick: u64, out: &mut Outbox) {
        if self.state != s {
            out.push(Event {
                seq: 0,
                kind: EventKind::GroupStateChanged as u16,
                axis: self.index,
                code: s as i32,
                tick,
                value: self.state as u32 as f64,
            });
            self.state = s;
        }
    }

    fn event(&self, kind: EventKind, seq: u32, code: i32, value: f64, tick: u64) -> Event {
        Event {
            seq,
            kind: kind as u16,
            axis: self.index,
            code,
            tick,
            value,
        }
    }

    /// Apply a validated configuration (the group must be disabled).
    pub fn configure(&mut self, cfg: GroupConfig) -> Result<(), NackCode> {
        if self.state != GroupState::Disabled {
            return Err(NackCode::InvalidState);
        }
        self.config = Some(cfg);
        self.ptp_stage = [None; MAX_AXES];
        // Layout 1.14: the path's dimensions named the old axes.
        if self.path_dims() > 0 {
            if let Some(run) = self.path.as_mut() {
                run.set_engine(Some(engine::Engine::narrow()));
            }
        }
        self.arc_plane = None;
        // A transfer in progress was laid out for the old axes.
        self.rx.open = false;
        Ok(())
    }

    /// MC_GroupEnable.
    pub fn enable(
        &mut self,
        axes: &mut [Axis; MAX_AXES],
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        match self.state {
            GroupState::Disabled => {}
            GroupState::Standby => return Ok(()),
            _ => return Err(NackCode::InvalidState),
        }
        for &a in &cfg.axes[..cfg.naxes] {
            match axes[a].state {
                AxisState::Standstill => {}
                AxisState::Disabled => return Err(NackCode::AxisDisabled),
                AxisState::DiscreteMotion
                | AxisState::ContinuousMotion
                | AxisState::Stopping
                | AxisState::Homing => return Err(NackCode::AxisBusy),
                _ => return Err(NackCode::InvalidState),
            }
        }
        self.sync_positions(axes, &cfg);
        self.snap_last = 0.0;
        self.snap_max = 0.0;
        self.prev_vel = [0.0; MAX_AXES];
        // `path_done` counts the segments ended since this enable (issue 39: it carried on
        // across disable and enable, and across hosts).
        if let Some(p) = self.path.as_mut() {
            p.reset_done();
        }
        self.set_state(GroupState::Standby, tick, out);
        Ok(())
    }

    /// MC_GroupDisable: abort everything, keep the axes where they are.
    pub fn disable(
        &mut self,
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        tick: u64,
        out: &mut Outbox,
    ) {
        self.abort_all(Opcode::GroupDisable, tick, out);
        if let Some(cfg) = self.config {
            for &a in &cfg.axes[..cfg.naxes] {
                filters[a].live.reset();
                // (a member halting from a group homing ends its halt on its own)
                if matches!(axes[a].state, AxisState::Homing | AxisState::DiscreteMotion) {
                    continue;
                }
                let old = axes[a].release_from_group();
                axis_event(out, a, old, axes[a].state, tick);
            }
        }
        self.home = None;
        self.final_seq = None;
        self.stop = None;
        self.ptp_stage = [None; MAX_AXES];
        self.rx.open = false;
        self.set_state(GroupState::Disabled, tick, out);
    }

    /// MC_GroupReset: GroupErrorStop → GroupStandby.
    pub fn reset(
        &mut self,
        axes: &mut [Axis; MAX_AXES],
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        if self.state != GroupState::ErrorStop {
            return Err(NackCode::InvalidState);
        }
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        if cfg.axes[..cfg.naxes]
            .iter()
            .any(|&a| axes[a].state != AxisState::Standstill)
        {
            return Err(NackCode::InvalidState);
        }
        self.sync_positions(axes, &cfg);
        self.set_state(GroupState::Standby, tick, out);
        Ok(())
    }

    fn abort_all(&mut self, by: Opcode, tick: u64, out: &mut Outbox) {
        self.path_abort_all(by, tick, out);
        if let Some(act) = self.active.take() {
            out.push(self.event(
                EventKind::GroupMotionAborted,
                act.mv.seq,
                by as i32,
                0.0,
                tick,
            ));
        }
        self.flush_queue(by, tick, out);
        if let Some(seq) = self.final_seq.take() {
            out.push(self.event(EventKind::GroupMotionAborted, seq, by as i32, 0.0, tick));
        }
    }

    fn flush_queue(&mut self, by: Opcode, tick: u64, out: &mut Outbox) {
        while let Some(m) = self.pop() {
            if !m.runout {
                out.push(self.event(EventKind::GroupMotionAborted, m.seq, by as i32, 0.0, tick));
            }
        }
    }

    /// Reports every queued move aborted, but keeps the first `keep` (NURBS curves a stop runs
    /// on into), marked as run-out.
    fn flush_queue_keeping(&mut self, keep: usize, by: Opcode, tick: u64, out: &mut Outbox) {
        for i in 0..self.queue.len() {
            let Some(m) = self.queue.get_mut(i) else {
                break;
            };
            let (seq, reported) = (m.seq, m.runout);
            if i < keep {
                m.runout = true;
            }
            if !reported {
                out.push(self.event(EventKind::GroupMotionAborted, seq, by as i32, 0.0, tick));
            }
        }
        self.queue.truncate(keep);
    }

    /// How many queued NURBS curves a stop of the active curve at `dmax`/`jerk` runs on into:
    /// a path's curves join without stopping, so the stop may need more than what is left of
    /// the active one (it must never end in a jump at the curve's end).
    fn nurbs_runout(&self, dmax: f64, jerk: f64) -> usize {
        let Some(act) = &self.active else { return 0 };
        let Feed::Nurbs(cur) = act.mv.feed else {
            return 0;
        };
        let Some(running) = self.nurbs.get(cur) else {
            return 0;
        };
        let post = self.config.is_some_and(|c| c.post);
        let (v0, a0) = (act.v.max(0.0), if act.v > 0.0 { act.a } else { 0.0 });
        // (only an estimate of the halt's length, with a curve's worth of margin below)
        let need = match crate::motion::scurve::plan_stop(0.0, v0, a0, dmax, jerk) {
            Ok(p) => p.end_pos(),
            Err(_) => v0 * v0 / (2.0 * dmax) + v0 * dmax / jerk,
        };
        let mut left = need - (running.interp.length() - running.interp.travelled()).max(0.0);
        let (mut cur, mut ft, mut keep) = (cur, act.mv.feed_type, 0);
        while left > 0.0 {
            let Some((next, next_ft)) = self.joinable(cur, ft, keep, post) else {
                break;
            };
            left -= self.nurbs.get(next).map_or(0.0, |n| n.interp.length());
            (cur, ft, keep) = (next, next_ft, keep + 1);
        }
        keep
    }

    /// The slot of the queued curve at queue position `i` if the NURBS motion in slot `cur`
    /// may run on into it without stopping (see `Interpolator::continuation`): the same
    /// saturation mode and, with post-interpolation filters, the same feed type (they switch
    /// only when empty). With its feed type.
    fn joinable(
        &self,
        cur: usize,
        feed_type: usize,
        i: usize,
        post: bool,
    ) -> Option<(usize, usize)> {
        let mv = self.queue.get(i)?;
        let Feed::Nurbs(k) = mv.feed else {
            return None;
        };
        let (a, b) = (self.nurbs.get(cur)?, self.nurbs.get(k)?);
        (k != cur
            && (!post || mv.feed_type == feed_type)
            && a.sat.is_some() == b.sat.is_some()
            && a.interp.continuation(&b.interp).is_some())
        .then_some((k, mv.feed_type))
    }

    fn pop(&mut self) -> Option<Move> {
        self.queue.pop_front()
    }

    fn peek(&self) -> Option<&Move> {
        self.queue.front()
    }

    /// A halt or stop that has run for `max_time` s or more without coming to rest: how long it
    /// has run (the safety layer then removes power). Reported once.
    pub fn stop_overdue(&mut self, max_time: f64) -> Option<f64> {
        let t = self.stop_elapsed?;
        if t + 1e-9 >= max_time {
            self.stop_elapsed = None;
            Some(t)
        } else {
            None
        }
    }

    /// MC_GroupHalt (`stop = false`) or MC_GroupStop: decelerate along the path within
    /// `(dmax, jerk)`, or within the harder `hard` ramp when the first would take longer than
    /// `max_time` s (`axis::plan_bounded_stop`). Queued moves are aborted. If the active move ends before the stop
    /// distance, a pre-interpolated move keeps its own profile (it ends at rest within its
    /// limits) and a constant-feed move stops at its end, its acceleration then bounded by the
    /// post-interpolation filters.
    #[allow(clippy::too_many_arguments)]
    pub fn start_stop(
        &mut self,
        seq: u32,
        stop: bool,
        (dmax, jerk): (f64, f64),
        hard: (f64, f64),
        max_time: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        match (self.state, stop) {
            (GroupState::Disabled, _) => return Err(NackCode::GroupDisabled),
            (GroupState::ErrorStop, _) | (GroupState::Stopping, false) => {
                return Err(NackCode::InvalidState)
            }
            _ => {}
        }
        let by = if stop {
            Opcode::GroupStop
        } else {
            Opcode::GroupHalt
        };
        // The ramp the stop will take: the given one, or the hard one if that is too long.
        let (dmax, jerk) = match &self.active {
            Some(act) => {
                let (v0, a0) = (act.v.max(0.0), if act.v > 0.0 { act.a } else { 0.0 });
                crate::motion::scurve::bounded_stop_limits((v0, a0), (dmax, jerk), hard, max_time)
            }
            None => (dmax, jerk),
        };
        // A running path stops along its geometry (within its own limits as well).
        self.path_halt((dmax, jerk), by, tick, out);
        let keep = self.nurbs_runout(dmax, jerk);
        self.flush_queue_keeping(keep, by, tick, out);
        if let Some(act) = &mut self.active {
            out.push(Event {
                seq: act.mv.seq,
                kind: EventKind::GroupMotionAborted as u16,
                axis: self.index,
                code: by as i32,
                tick,
                value: 0.0,
            });
            let (v0, a0) = (act.v.max(0.0), if act.v > 0.0 { act.a } else { 0.0 });
            let plan = crate::motion::scurve::plan_stop(act.s, v0, a0, dmax, jerk);
            if let Ok(p) = plan {
                let keep_own =
                    matches!(act.mv.feed, Feed::Profile { .. }) && p.end_pos() > act.mv.geom.len();
                if !keep_own {
                    act.stopping = Some((p, 0.0));
                }
            }
        }
        if let Some(old) = self.final_seq.take() {
            out.push(self.event(EventKind::GroupMotionAborted, old, by as i32, 0.0, tick));
        }
        self.final_seq = Some(seq);
        self.settled_for = 0.0;
        self.stop_elapsed = Some(0.0);
        if stop {
            self.stop = Some(StopKind::Stop);
            self.stop_released = false;
            self.set_state(GroupState::Stopping, tick, out);
        } else {
            self.stop = Some(StopKind::Halt(seq));
            if self.state == GroupState::Standby {
                self.set_state(GroupState::Moving, tick, out);
            }
        }
        self.move_count = self.move_count.wrapping_add(1);
        Ok(())
    }

    /// MC_GroupStop, Execute falling.
    pub fn release_stop(&mut self) -> Result<(), NackCode> {
        if self.state != GroupState::Stopping {
            return Err(NackCode::InvalidState);
        }
        self.stop_released = true;
        Ok(())
    }

    /// Validate a move command (of command `seq`) and queue it.
    pub fn queue_move(
        &mut self,
        seq: u32,
        mv: GroupMove<'_>,
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        let ptp = matches!(mv, GroupMove::Ptp(_));
        // Limits staged for a point-to-point move belong to the next one, whatever becomes of it.
        let staged = if ptp {
            core::mem::replace(&mut self.ptp_stage, [None; MAX_AXES])
        } else {
            [None; MAX_AXES]
        };
        let (lim, opts) = mv.limits_opts();
        let cfg = self.can_queue(opts.buffered)?;
        let n = cfg.naxes;
        if !mv.finite(n) {
            return Err(NackCode::NotFinite);
        }
        let rate = crate::firmware::rate_hz(ts);
        let ranges = [(1, lim.vmax), (2, lim.amax), (2, lim.dmax), (3, lim.jerk)];
        crate::firmware::nack::check_ranges(rate, &ranges)?;
        let limits = Limits {
            vmax: lim.vmax,
            amax: lim.amax,
            dmax: lim.dmax,
            j1: lim.jerk,
            j3: lim.jerk,
            j5: lim.jerk,
            j7: lim.jerk,
        };
        let feed_type = opts.feed_type as usize;
        if feed_type > 2 {
            return Err(NackCode::BadConfig);
        }
        let relative = opts.relative;
        let start = self.queue_end;
        let target = |i: usize, v: f64| if relative { start[i] + v } else { v };
        let in_range = |p: &[f64; MAX_AXES]| p[..n].iter().all(|x| x.abs() <= crate::MAX_POSITION);
        let geom = match mv {
            GroupMove::Linear(LinearMove { targets, .. })
            | GroupMove::Ptp(PtpMove {
                line: LinearMove { targets, .. },
                ..
            }) => {
                let mut delta = [0.0; MAX_AXES];
                let mut end = start;
                for i in 0..n {
                    end[i] = target(i, targets[i]);
                    delta[i] = end[i] - start[i];
                }
                if !in_range(&end) {
                    return Err(NackCode::OutOfRange);
                }
                let len = if ptp {
                    delta[..n].iter().fold(0.0f64, |m, d| m.max(d.abs()))
                } else {
                    math::sqrt(delta[..n].iter().map(|d| d * d).sum::<f64>())
                };
                Geometry::Line { start, delta, len }
            }
            GroupMove::Circular(c) => self.arc(&cfg, &c.arc, &start, relative)?,
            GroupMove::CircularNormal(m, p) => normal::geometry(&cfg, m, p, &start, relative)?,
        };
        let limits = match (&geom, mv) {
            (Geometry::Line { delta, len, .. }, GroupMove::Ptp(p)) => {
                let own = p.axis_limits;
                if own && staged[..n].iter().any(Option::is_none) {
                    return Err(NackCode::BadConfig);
                }
                ptp_path_limits(&limits, &delta[..n], *len, own.then_some(&staged[..n]))
            }
            _ => limits,
        };
        let len = geom.len();
        let feed = if let (true, Geometry::Arc { arc, u, v, .. }) = (cfg.reference_word, &geom) {
            let dir = if arc.sweep() > 0.0 {
                ArcDirection::Ccw
            } else {
                ArcDirection::Cw
            };
            let end = geom.end(n);
            // The reference-word circle runs at the constant feed v (Kim eq 21: α = VT/R).
            let rw = ReferenceWordCircle::new(
                arc.centre(),
                (start[*u], start[*v]),
                (end[*u], end[*v]),
                dir,
                limits.vmax,
                ts,
            )
            .map_err(|_| NackCode::Infeasible)?;
            Feed::ReferenceWord(rw)
        } else if cfg.pre {
            let p = Profile::plan(0.0, len, 0.0, 0.0, &limits)
                .map_err(crate::firmware::nack::plan_nack)?;
            if !p.duration().is_finite() || p.duration() > crate::MAX_MOVE_TIME {
                return Err(NackCode::Infeasible);
            }
            Feed::Profile {
                profile: p,
                t: 0.0,
                lim: limits,
            }
        } else {
            if len / limits.vmax > crate::MAX_MOVE_TIME {
                return Err(NackCode::Infeasible);
            }
            Feed::Constant { v: limits.vmax }
        };
        self.push(
            Move {
                seq,
                geom,
                feed,
                feed_type,
                ptp,
                runout: false,
            },
            n,
            tick,
            out,
        );
        Ok(())
    }

    /// MC_OP_GROUP_PTP_LIMITS: stage the limits (v, a, d, j) of `count` group axes from
    /// `first` for the next point-to-point move (used with `MC_PTP_AXIS_LIMITS`). `l` is the
    /// decoded command, or the nack of a malformed first axis or count, which the group's
    /// state comes before.
    pub fn stage_ptp_limits(
        &mut self,
        l: Result<&PtpLimits, NackCode>,
        ts: f64,
    ) -> Result<(), NackCode> {
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        if self.state == GroupState::Disabled {
            return Err(NackCode::GroupDisabled);
        }
        let l = l?;
        let (first, count) = (l.first as usize, l.limits.len());
        if first + count > cfg.naxes {
            return Err(NackCode::AxisNotInGroup);
        }
        if l.limits
            .iter()
            .flat_map(|x| x.to_array())
            .any(|x| !x.is_finite())
        {
            return Err(NackCode::NotFinite);
        }
        let rate = crate::firmware::rate_hz(ts);
        for l in &l.limits {
            crate::firmware::nack::check_ranges(
                rate,
                &[(1, l.vmax), (2, l.amax), (2, l.dmax), (3, l.jerk)],
            )?;
        }
        for (k, l) in l.limits.iter().enumerate() {
            self.ptp_stage[first + k] = Some(l.to_array());
        }
        Ok(())
    }

    /// The group accepts a move now (`buffered`: the command's)?
    fn can_queue(&self, buffered: bool) -> Result<GroupConfig, NackCode> {
        let cfg = self.config.ok_or(NackCode::GroupDisabled)?;
        match self.state {
            GroupState::Disabled => return Err(NackCode::GroupDisabled),
            GroupState::Standby => {}
            GroupState::Moving if buffered && self.stop.is_none() => {}
            _ => return Err(NackCode::InvalidState),
        }
        if self.path.as_ref().is_some_and(|p| p.engaged) {
            return Err(NackCode::PathBusy);
        }
        if self.queue.is_full() {
            return Err(NackCode::QueueFull);
        }
        Ok(cfg)
    }

    fn push(&mut self, mv: Move, n: usize, tick: u64, out: &mut Outbox) {
        self.queue_end = mv.geom.end(n);
        // (never full: `can_queue` refused the move then)
        let _ = self.queue.push_back(mv);
        self.move_count = self.move_count.wrapping_add(1);
        if self.state == GroupState::Standby {
            self.final_seq = None;
            self.set_state(GroupState::Moving, tick, out);
        }
    }

    /// Build and check an arc (circular or helical move).
    fn arc(
        &self,
        cfg: &GroupConfig,
        a: &ArcGeometry,
        start: &[f64; MAX_AXES],
        relative: bool,
    ) -> Result<Geometry, NackCode> {
        let n = cfg.naxes;
        let (u, v) = arc_axes(a, n)?;
        let rel = |i: usize, x: f64| if relative { start[i] + x } else { x };
        let arc = arc_circle(a, (u, v), (start[u], start[v]), rel, cfg.tolerance)?;
        // Helical part: the other group axes, in group order.
        let mut helix = [0.0; MAX_AXES];
        let mut k = 0;
        let helix_relative = relative || a.flags.helix_relative;
        for (i, h) in helix.iter_mut().enumerate().take(n) {
            if i != u && i != v {
                *h = if helix_relative {
                    a.helix[k]
                } else {
                    a.helix[k] - start[i]
                };
                k += 1;
            }
        }
        let hl = helix.iter().map(|h| h * h).sum::<f64>();
        let len = math::sqrt(arc.length() * arc.length() + hl);
        let geom = Geometry::Arc {
            start: *start,
            u,
            v,
            arc,
            helix,
            len,
        };
        if !geom.end(n)[..n]
            .iter()
            .all(|x| x.abs() <= crate::MAX_POSITION)
        {
            return Err(NackCode::OutOfRange);
        }
        Ok(geom)
    }

    /// One servo tick, in steps (each with its own tests, in the file of its name): `guard`
    /// (a member that faulted stops the group), `activate` (the next queued move starts),
    /// `stop` and `feed` (the path advances: along a halt or stop, or the move's own feed),
    /// `filter` (the members' acc/dec filters and references), then at rest `snap` (to the
    /// programmed end, with its statistics) and `settle` (in position: the done events and
    /// the states).
    pub fn tick(
        &mut self,
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) {
        let Some(cfg) = self.config else { return };
        if !self.guard(&cfg, axes, filters, ts, tick, out) {
            if let Some(p) = self.path.as_mut() {
                p.engaged &= !matches!(self.state, GroupState::Standby | GroupState::ErrorStop);
            }
            return;
        }
        self.tick_moving(&cfg, axes, filters, ts, tick, out);
    }

    /// The tick of a group that moves (past [`Group::guard`]). Out of line: its frame is large
    /// (the path engine's and the filters' locals), and a group with nothing to do (most, most
    /// of the time) should not pay for it in stack touched.
    #[inline(never)]
    fn tick_moving(
        &mut self,
        cfg: &GroupConfig,
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) {
        if self.path.as_ref().is_some_and(|p| p.engaged) {
            if self.path_tick(cfg, axes, ts, tick, out) {
                let members = &cfg.axes[..cfg.naxes];
                self.snap(members, axes);
                self.settle(members, axes, ts, tick, out);
            }
            return;
        }
        self.activate(cfg, axes, filters, ts, tick, out);
        let inc = self.feed(cfg, axes, ts, tick, out);
        let settled = self.filter(cfg, &inc, axes, filters, ts);
        if self.active.is_none() && (self.queue.is_empty() || self.stop.is_some()) && settled {
            let members = &cfg.axes[..cfg.naxes];
            self.snap(members, axes);
            self.settle(members, axes, ts, tick, out);
        }
    }

    /// Whether the group moves on this tick. A member that lost power or faulted takes it to
    /// ErrorStop (everything aborted, the members released); a group at rest (Standby,
    /// ErrorStop) has nothing to do. Counts the time of a halt or stop in progress.
    fn guard(
        &mut self,
        cfg: &GroupConfig,
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> bool {
        if matches!(self.state, GroupState::Disabled) {
            return false;
        }
        let members = &cfg.axes[..cfg.naxes];
        // A member that lost power or faulted takes the group to ErrorStop.
        if self.state != GroupState::ErrorStop
            && members
                .iter()
                .any(|&a| matches!(axes[a].state, AxisState::ErrorStop | AxisState::Disabled))
        {
            self.abort_all(Opcode::GroupDisable, tick, out);
            self.stop = None;
            for &a in members {
                filters[a].live.reset();
                let old = axes[a].release_from_group();
                axis_event(out, a, old, axes[a].state, tick);
            }
            self.set_state(GroupState::ErrorStop, tick, out);
            return false;
        }
        if matches!(self.state, GroupState::Standby | GroupState::ErrorStop) {
            self.stop_elapsed = None;
            return false;
        }
        // Layout 1.11: the members home on their own (group_home.rs).
        if self.home.is_some() {
            return false;
        }
        if let Some(t) = &mut self.stop_elapsed {
            *t += ts;
        }
        true
    }

    /// The status block to publish.
    #[inline]
    pub fn status(&self, tick: u64) -> GroupStatus {
        let (active_seq, path_pos, path_len, feed, feed_acc) = match &self.active {
            Some(a) => (a.mv.seq, a.s, a.mv.geom.len(), a.v, a.a),
            None => (0, 0.0, 0.0, 0.0, 0.0),
        };
        let mut s = GroupStatus {
            state: self.state as u32,
            queued: self.queue.len() as u32,
            active_seq,
            move_count: self.move_count,
            path_pos,
            path_len,
            feed,
            feed_acc,
            tick,
            snap_last: self.snap_last,
            snap_max: self.snap_max,
            feed_override: self.overrides.0,
            rapid_override: self.overrides.1,
            ..Default::default()
        };
        self.path_status(&mut s);
        s
    }
}

/// Is NURBS slot `k` named by the active move or one of the queued ones?
fn slot_taken(active: &Option<Active>, queue: &Deque<Move, GROUP_QUEUE_LEN>, k: usize) -> bool {
    let names = |m: &Move| matches!(m.feed, Feed::Nurbs(j) if j == k);
    active.as_ref().is_some_and(|a| names(&a.mv)) || queue.iter().any(names)
}

/// The limits along a synchronised point-to-point line of length `len` (the largest axis
/// distance) that keep every axis within its own (Kim eq 10–14 with per-axis limits). Axis `i`
/// travels `|delta_i|/len` of the path, so its limit `l_i` allows `l_i·len/|delta_i|` along
/// it; the smallest of each wins, which sets the time, and the other axes scale. Each axis's
/// limit is `base`, or the smaller of `base` and its own when `own` is given.
fn ptp_path_limits(
    base: &Limits,
    delta: &[f64],
    len: f64,
    own: Option<&[Option<[f64; 4]>]>,
) -> Limits {
    if len.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
        return *base;
    }
    let mut l = [f64::INFINITY; 4];
    for (i, d) in delta.iter().enumerate() {
        let d = d.abs();
        if d == 0.0 {
            continue;
        }
        let r = len / d;
        let mut ax = [base.vmax, base.amax, base.dmax, base.j1];
        if let Some(Some(o)) = own.and_then(|o| o.get(i)) {
            for (x, y) in ax.iter_mut().zip(o) {
                *x = x.min(*y);
            }
        }
        for (x, y) in l.iter_mut().zip(ax) {
            *x = x.min(y * r);
        }
    }
    Limits {
        vmax: l[0],
        amax: l[1],
        dmax: l[2],
        j1: l[3],
        j3: l[3],
        j5: l[3],
        j7: l[3],
    }
}

/// The StateChanged event of an axis the group moved from `old` to `new`.
fn axis_event(out: &mut Outbox, axis: usize, old: Option<AxisState>, new: AxisState, tick: u64) {
    if let Some(old) = old {
        out.push(Event {
            seq: 0,
            kind: EventKind::StateChanged as u16,
            axis: axis as u16,
            code: new as i32,
            tick,
            value: old as u32 as f64,
        });
    }
}

/// A card's filters, one per axis (a linear filter holds 4096 taps).
pub type FilterBank = FixedVec<AxisFilter, MAX_AXES>;

/// The filter bank of a card, made once at boot.
pub fn filter_bank() -> FilterBank {
    let mut bank = FilterBank::with_capacity(MAX_AXES);
    for _ in 0..MAX_AXES {
        let _ = bank.push(AxisFilter::new()); // room for MAX_AXES
    }
    bank
}

/// The plane of an arc (`MC_PLANE_*`): its two axes (of `n`), checked.
pub(super) fn arc_axes(a: &ArcGeometry, n: usize) -> Result<(usize, usize), NackCode> {
    let (u, v) = match a.flags.plane as u32 {
        raw::MC_PLANE_XY => (0, 1),
        raw::MC_PLANE_YZ => (1, 2),
        raw::MC_PLANE_ZX => (2, 0),
        raw::MC_PLANE_AXES => {
            let (u, v) = (a.flags.axes.0 as usize, a.flags.axes.1 as usize);
            if u == v {
                return Err(NackCode::PlaneAxes);
            }
            (u, v)
        }
        _ => return Err(NackCode::BadConfig),
    };
    if u >= n || v >= n {
        return Err(NackCode::AxisNotInGroup);
    }
    Ok((u, v))
}

/// The exact circle of an arc from `p0` (its plane axes `(u, v)`'s start) whose end and aux
/// point are `rel(axis, x)` (the start added for a relative move), checked within `tol`: the
/// end on the circle through the start.
pub(super) fn arc_circle(
    a: &ArcGeometry,
    (u, v): (usize, usize),
    p0: (f64, f64),
    rel: impl Fn(usize, f64) -> f64,
    tol: f64,
) -> Result<ExactCircle, NackCode> {
    let p1 = (rel(u, a.end[0]), rel(v, a.end[1]));
    let ccw = a.flags.ccw;
    let dir = if ccw {
        ArcDirection::Ccw
    } else {
        ArcDirection::Cw
    };
    let dist = |p: (f64, f64), q: (f64, f64)| math::hypot(p.0 - q.0, p.1 - q.1);
    let (centre, dir) = match a.flags.mode as u32 {
        raw::MC_CIRC_BY_CENTRE => {
            let centre = (rel(u, a.aux[0]), rel(v, a.aux[1]));
            let (r0, r1) = (dist(p0, centre), dist(p1, centre));
            if r0 <= tol {
                return Err(NackCode::ZeroLengthArc);
            }
            if (r0 - r1).abs() > tol {
                return Err(NackCode::CentreNotEquidistant);
            }
            (centre, dir)
        }
        raw::MC_CIRC_BY_RADIUS => {
            let r = a.aux[0];
            let chord = dist(p0, p1);
            if chord <= tol || r.abs() <= tol {
                return Err(NackCode::ZeroLengthArc);
            }
            if r.abs() < chord / 2.0 - tol {
                return Err(NackCode::RadiusTooSmall);
            }
            let h = math::sqrt((r * r - chord * chord / 4.0).max(0.0));
            let mid = ((p0.0 + p1.0) / 2.0, (p0.1 + p1.1) / 2.0);
            let (dx, dy) = ((p1.0 - p0.0) / chord, (p1.1 - p0.1) / chord);
            // The centre on the left of start→end gives the short arc when going CCW.
            let left = (ccw && r > 0.0) || (!ccw && r < 0.0);
            let s = if left { 1.0 } else { -1.0 };
            ((mid.0 - s * dy * h, mid.1 + s * dx * h), dir)
        }
        raw::MC_CIRC_BY_BORDER => {
            let b = (rel(u, a.aux[0]), rel(v, a.aux[1]));
            if dist(p0, p1) <= tol || dist(p0, b) <= tol || dist(b, p1) <= tol {
                return Err(NackCode::ZeroLengthArc);
            }
            // Circumcentre of start, border point, end.
            let d = 2.0 * (p0.0 * (b.1 - p1.1) + b.0 * (p1.1 - p0.1) + p1.0 * (p0.1 - b.1));
            let cross = (b.0 - p0.0) * (p1.1 - p0.1) - (b.1 - p0.1) * (p1.0 - p0.0);
            // Collinear within the tolerance: the border point is within tol of the chord.
            if cross.abs() <= tol * dist(p0, p1) || d == 0.0 {
                return Err(NackCode::CollinearPoints);
            }
            let s0 = p0.0 * p0.0 + p0.1 * p0.1;
            let sb = b.0 * b.0 + b.1 * b.1;
            let s1 = p1.0 * p1.0 + p1.1 * p1.1;
            let centre = (
                (s0 * (b.1 - p1.1) + sb * (p1.1 - p0.1) + s1 * (p0.1 - b.1)) / d,
                (s0 * (p1.0 - b.0) + sb * (p0.0 - p1.0) + s1 * (b.0 - p0.0)) / d,
            );
            // start → border → end turns counter-clockwise when the border point lies to
            // the right of the chord start → end (cross > 0).
            (
                centre,
                if cross > 0.0 {
                    ArcDirection::Ccw
                } else {
                    ArcDirection::Cw
                },
            )
        }
        _ => return Err(NackCode::BadConfig),
    };
    let mut arc =
        ExactCircle::from_points(centre, p0, p1, dir).map_err(|_| NackCode::ZeroLengthArc)?;
    if (dist(p1, centre) - arc.radius()).abs() > tol {
        return Err(NackCode::CentreNotEquidistant);
    }
    // End exactly on the circle through the start: re-anchor the end angle.
    arc = ExactCircle::new(centre, arc.radius(), arc.start_angle(), arc.sweep())
        .map_err(|_| NackCode::ZeroLengthArc)?;
    Ok(arc)
}

#[cfg(test)]
mod tests {
    use super::testing::{Bench, TS};
    use super::*;
    use firmware_proto::cmd::Args;

    /// The queue holds `GROUP_QUEUE_LEN` moves besides the active one and refuses the next
    /// (leaving `queue_end` as it was); they start in the order queued, and a stop aborts every
    /// queued one in order, then the active one, and leaves the queue empty.
    #[test]
    fn queue_holds_its_length_in_order_and_a_stop_aborts_them_all() {
        let len = GROUP_QUEUE_LEN as u32;
        let mut b = Bench::new(2, true, false);
        for k in 1..=len {
            b.line(k, &[100.0 * k as f64, 0.0], 0);
        }
        assert_eq!(b.g.status(b.tick).queued, len);
        let c = firmware_proto::Command::new(Opcode::GroupMoveLinear, 0)
            .with_args(&[1e5, 1e6, 1e6, 1e8, -5.0, -5.0]);
        let extra = LinearMove::decode(move_flags::BUFFERED, &c.args).unwrap();
        let refused = |b: &mut Bench| {
            let tick = b.tick;
            b.g.queue_move(99, GroupMove::Linear(&extra), TS, tick, &mut b.out)
        };
        assert_eq!(refused(&mut b), Err(NackCode::QueueFull));
        assert_eq!(b.g.queue_end[..2], [100.0 * len as f64, 0.0]);
        b.tick();
        assert_eq!(b.g.active.as_ref().map(|a| a.mv.seq), Some(1));
        assert_eq!(b.g.status(b.tick).queued, len - 1);
        b.line(len + 1, &[0.0, 100.0], 0);
        assert_eq!(refused(&mut b), Err(NackCode::QueueFull));
        assert_eq!(b.g.queue_end[..2], [0.0, 100.0]);
        b.events();
        let tick = b.tick;
        b.g.start_stop(100, true, (1e6, 1e8), (1e7, 1e9), 1.0, tick, &mut b.out)
            .unwrap();
        let aborted: Vec<u32> = b
            .events()
            .iter()
            .filter(|e| e.kind == EventKind::GroupMotionAborted as u16)
            .map(|e| e.seq)
            .collect();
        let mut expected: Vec<u32> = (2..=len + 1).collect();
        expected.push(1);
        assert_eq!(aborted, expected);
        assert_eq!(b.g.status(b.tick).queued, 0);
    }

    /// A member that faults takes the moving group to ErrorStop: the active and queued moves
    /// are aborted, the members released; the group then does nothing until reset.
    #[test]
    fn guard_a_faulted_member_stops_the_group_in_error() {
        let mut b = Bench::new(2, true, false);
        b.line(1, &[10_000.0, 0.0], 0);
        b.line(2, &[0.0, 0.0], 0);
        for _ in 0..100 {
            b.tick();
        }
        assert!(b.g.active.is_some());
        b.events();
        b.axes[1].power(false).unwrap();
        let cfg = b.cfg();
        let moving =
            b.g.guard(&cfg, &mut b.axes, &mut b.filters, TS, 101, &mut b.out);
        assert!(!moving);
        assert_eq!(b.g.state, GroupState::ErrorStop);
        assert!(b.g.active.is_none() && b.g.queue.is_empty());
        assert!(b.pushed(EventKind::GroupMotionAborted, 1));
        assert!(b.pushed(EventKind::GroupMotionAborted, 2));
        assert_eq!(b.axes[0].state, AxisState::Standstill);
        assert_eq!(b.axes[0].reference().vel, 0.0);
        let pos = b.pos(0);
        b.tick();
        assert_eq!(b.pos(0), pos);
    }

    /// The whole tick, step after step: a line runs to its end and settles there, the snap
    /// correcting nothing (the S-curve's sum ends on the target), then the group stands by.
    #[test]
    fn tick_runs_a_line_to_rest_on_its_end() {
        let mut b = Bench::new(2, true, true);
        b.line(1, &[3_000.0, -4_000.0], 0);
        assert!(b.run_until(100_000, |b| b.g.state == GroupState::Standby));
        assert_eq!((b.pos(0), b.pos(1)), (3_000.0, -4_000.0));
        assert!(b.g.snap_last <= 1e-9, "snap {}", b.g.snap_last);
        assert!(b.pushed(EventKind::GroupMotionDone, 1));
        assert_eq!(b.axes[1].state, AxisState::Standstill);
    }
}
