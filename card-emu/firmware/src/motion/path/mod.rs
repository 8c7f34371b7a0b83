//! The continuous-path engine of an axes group: a deep ring of programmed segments (lines,
//! arcs/helices, dwells), G2 corner blends within a tolerance, look-ahead, and a per-tick
//! executor that returns the commanded position of every axis.
//!
//! Units: positions in counts, time in s. One [`Path`] per group: the owner pushes validated
//! segments ([`Path::push`]) and calls [`Path::tick`] once per servo tick.
//!
//! **Pieces.** Each motion segment is a body (its line or helix between its trim points) and,
//! when it joins the previous segment with a blend, a blend piece in front of it. All pieces
//! are parametrised by arc length. A blend is a quintic Bézier matching position, unit tangent
//! and curvature vector of both sides at the trim points (G2: the acceleration is continuous
//! through the corner); its arc length is a 4-interval Gauss–Legendre table and Newton on u.
//!
//! **Limits.** The path speed s(t) follows a [`PathSpeedPlanner`]. Every piece has tangential
//! limits (A_t, J_t) of its own (`Lim`) and a speed cap V such that at each sampled point, on
//! every axis k, |V T_k| ≤ vmax_k, A_t|T_k| + V²|K_k| ≤ amax_k and
//! J_t|T_k| + 3 V A_t |K_k| + V³|K'_k| ≤ jmax_k (each limit times [`CAP_MARGIN`]); since
//! |s̈| ≤ A_t and |s⃛| ≤ J_t on the piece, the axis velocity s̊T_k, acceleration s̈T_k + v²K_k and
//! jerk s⃛T_k + 3vs̈K_k + v³K'_k stay within the axis limits wherever v ≤ V. A line's are every
//! axis's own limits projected onto its direction (K = 0: all of each budget is the
//! tangential motion's) and its velocity limits exactly. A blend's are the shares
//! A_t = [`ACCEL_SHARE`]·min_k amax_k and J_t = [`JERK_SHARE`]·min_k jmax_k (or the group's
//! `accel`/`jerk` if lower): the other half is what curvature may use at full tangential
//! acceleration. An arc's, a helix's or a curve's piece fed below the cap those shares give
//! takes for A_t and J_t all that its curvature leaves at its feed (`curved_lim`).
//!
//! The planner's limits change from piece to piece: the look-ahead decides with the lowest
//! limits of the pieces it looks at (what a push may add past an unmarked queue end counts as
//! the lowest, the shares), and it looks as far as braking at the shares reaches, so that a
//! piece of lower limits is seen before braking within them is due; stops are planned with
//! those too. Each planning step ramps within the limits of the pieces up to where its ramp
//! toward the target ends and a step beyond (`exec::look`): a ramp never runs into limits it
//! cannot keep; an acceleration made within higher limits is brought back to 0 at the jerk it
//! needs, never above the limits of the pieces it crosses meanwhile.
//!
//! **Smoothing of micro-segments.** A junction of two lines turning by at most
//! [`SMOOTH_TURN`] under `MaxDeviation` is first tried as a smoothing blend: from the middle of
//! the previous line to the middle of the new one (nothing of either line is left straight),
//! with the curvature vector at its ends estimated from the neighbouring points (the circle
//! through three vertices, averaged over the two vertices of a line). The newest blend ends
//! with curvature 0, since the next point is not known yet; when it arrives, that blend is
//! rebuilt with its end curvature if the executor can still slow down before it. The newest
//! blend is only checked (its deviation bounded, see below; its length is its chord until
//! then): it is built, measured and capped only when that rebuild does not
//! happen, or when the look-ahead window reaches it first, so that a push builds one blend
//! and computes one cap, not two. The
//! curvature then follows the curve the points came from instead of dropping to 0 on every
//! chord, which is what made dense paths slow. A smoothing blend whose deviation from the two
//! lines is over the tolerance (×0.97) falls back to the corner blend below. A smoothing
//! blend's deviation is first bounded in closed form, from the trims, the turn and the end
//! curvatures (`smooth_dev_bound`: within a few per cent on evenly cut curves); where that
//! bound is over, by the blend's control points (cut in two by de Casteljau, each half within
//! the hull of its points, the distance to a chord convex); the curve is sampled only when
//! that bound is over too (never on the dense benchmark's curve).
//!
//! **Look-ahead.** Each tick the planner's target is the current piece's cap, lowered for any
//! lower cap ahead it must start slowing for now (the pieces within its jerk-limited braking
//! reach are scanned, however many segments that is; blocks of [`BLOCK`] segments whose
//! minimum cap is not below the speed are skipped, as `nurbs_interp`'s look-ahead does), and
//! its remaining distance is the distance to the next exact stop, or to the end of what is
//! queued. So the path can always stop within what is queued. A slowing holds its target
//! until its piece, unless it gets down to it long before (`CRAWL_TICKS` at that speed: it
//! decided within the lowest limits ahead and ramped within higher ones): then it lets go and
//! is decided again. A corner blend that would take ten times what an exact stop loses (a
//! near-reversal's, folded into a near-cusp) is an exact stop instead (`stop_is_faster`), and
//! an exact stop holds at rest for `STOP_SETTLE_TICKS` before the next segment starts. A walk that finds nothing to
//! slow for serves the ticks after it (`exec::Seen`): it keeps the smallest cap it passed for
//! being above the speed, the smallest envelope key c² + 2·D·d it passed for clearing the
//! envelope, the least room between a piece it tested and that piece's slowing distance (in
//! closed form), and how far it went; while the tick's speed bound is not above that cap, the
//! keys still clear from where the executor has got to, the room covers what the slowing
//! distances can have grown (the state on the same descent, its speed at a = 0 no higher),
//! and the reach ends before where the walk ended, the walk would find nothing again, and is
//! skipped (the same motion to the last bit: `tests_lookahead`). When the room no longer
//! covers that growth, the pieces the walk tested (it keeps up to 32) whose own room does not
//! cover it are tested again from the tick's state instead of walking again, and the rooms
//! are counted from there on. A push or a late cap that changes a segment the walk saw drops
//! it. Segments know where they start along the whole
//! path (`Seg::start`), so the executor's progress since a walk, and its distance to a
//! segment's end, are differences, not sums.
//!
//! **Tick.** [`Path::tick`] is `tick_plan` (dwells, the look-ahead, the speed planner: the
//! next planning step) then `tick_move` (this tick of the step taken along the pieces, segment
//! events and outputs, the position interpolated); the cost benchmark (`benches/path.rs`)
//! times the two apart. A planning step lasts [`PathLimits::plan_ticks`] servo ticks: the
//! look-ahead and the planner run once a step, with the step's period as their tick, and each
//! servo tick moves the executor to where the step's own profile is then
//! (`PathSpeedPlanner::sample_step`: constant jerk per phase, integrated exactly), so the
//! positions are the planner's profile at the servo rate. A halt cuts the step at its tick; a
//! step that comes to rest ends at the tick it lands; a tick before a step's last holds at a
//! stop point rather than cross it; a segment pushed during a step that joins its stop point
//! to more path turns the landing into the step's distance; a slowing to less than
//! `FINE_SLOWING` of the speed is re-decided for a step of one tick (up to a step early, it
//! would reach the slow piece's speed a step's distance before it and crawl there). One tick
//! per step is the engine planned at the servo rate, to the bit.
//!
//! **Dimension.** [`Path<D>`](Path) plans paths of up to `D` axes (with its [`PathLimits<D>`],
//! [`Segment<D>`] and [`Geom<D>`]): every point, tangent, curvature vector and axis limit is
//! a `[f64; D]`, of which a group of `naxes` ≤ D uses the first `naxes` (the others are 0 and
//! move nothing; `reset` refuses more with `BadAxis`). `D` defaults to [`MAX_AXES`], a group
//! of the card's: `Path` is `Path<8>` (made by [`Path::with_capacity`]; another dimension's by
//! `Path::<D>::with_segments`), the same engine as before it took `D`, to the last bit: its
//! loops over the axes and its lane code run to the constant 8 as they did, and its memory is
//! the same. (Being generic, it is compiled in the crate that uses it: the dense benchmark's
//! push is now compiled in the benchmark's crate, 1 % fewer instructions there; its plan and
//! move are the same to within 0.05 %.) A wider engine, `Path<16>`, is for a path whose axes
//! live on several cards (issue 37): each card plans every axis of the path, those it does not
//! drive too, so that all plan the same profile. An axis a segment does not move adds exact
//! zeros to every sum over the axes, so a 12-axis path whose last four axes stay still moves
//! the first eight as the 8-axis engine does, to the last bit (`tests_dims`). An entry of a
//! `Path<16>`'s ring is 2,832 bytes, an 8-axis one's 1,680 (each holds its points, blend and
//! program inline). NURBS curves have at most 8 dimensions (`nurbs::MAX_DIM`); a curve of
//! another dimension than the group's is refused (`BadAxis`).
//!
//! **Two builds.** `push`, `tick_plan`, `tick_move` and the look-ahead's walk run a build of
//! their bodies for x86-64-v3 (AVX2, FMA) where the CPU has it, and the baseline x86-64 build
//! elsewhere (`v3.rs`): the same motion to the last bit, about a fifth fewer instructions.
//!
//! `push`, `push_output`, `tick`, `halt` and `clear` allocate nothing and never panic;
//! [`Path::with_capacity`] allocates everything once.

mod caps;
mod curve;
mod exec;
mod geom;
mod pause;
mod shift;
mod smooth;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_curve;
#[cfg(test)]
mod tests_dims;
#[cfg(test)]
mod tests_lookahead;
#[cfg(test)]
mod tests_normal;
#[cfg(test)]
mod tests_pause;
#[cfg(test)]
mod tests_period;
#[cfg(test)]
mod tests_shift;
#[allow(unsafe_code)] // the calls into the x86-64-v3 build, after the CPU check
mod v3;

pub use self::curve::{CurveSegment, FIT_SAMPLES};
#[doc(hidden)]
pub use self::exec::TickPlan;
pub use self::geom::{normal_basis, unit_normal, Helix};
pub use self::pause::PauseState;
use crate::math;
use crate::ram::FixedVec;

#[cfg(test)]
use self::geom::Frame;
use self::geom::{dist_to_chord, Blend, Prog, LANES, LANES_V3, V};
use self::shift::Chain;
use crate::motion::arc::CircleError;
use crate::motion::path_speed::{PathSpeedPlanner, Track};
use crate::motion::pos_finite;

/// Axes of a group of the card's: the engine's default dimension (`Path` is `Path<8>`; see
/// the module doc).
pub const MAX_AXES: usize = 8;
/// Largest |position|, counts.
pub const MAX_POS: f64 = 4.5e15;
/// Feed range, counts/s.
pub const MIN_FEED: f64 = 1e-6;
pub const MAX_FEED: f64 = 1e12;
/// Range of a blend tolerance or corner distance (0 = exact stop), counts.
pub const MIN_TOL: f64 = 1e-9;
pub const MAX_TOL: f64 = 1e15;
/// Longest dwell, s.
pub const MAX_DWELL: f64 = 1e6;
/// Ranges of the axis limits (velocity, acceleration, jerk) and of the sample time.
pub const LIMIT_RANGE: (f64, f64) = (1e-6, 1e18);
pub const TS_RANGE: (f64, f64) = (1e-6, 1.0);
/// Most servo ticks per planning step ([`PathLimits::plan_ticks`]).
pub const MAX_PLAN_TICKS: usize = 1000;
/// The planner's period when its owner chooses none, and the longest it may choose, s.
pub const DEFAULT_PLAN_PERIOD: f64 = 1e-3;
pub const MAX_PLAN_PERIOD: f64 = 0.01;

/// Servo ticks per planning step for a planner period of `period` s (0: the default) at the
/// servo period `ts`: the nearest whole number of ticks, at least one.
pub fn plan_ticks(period: f64, ts: f64) -> usize {
    let period = if period > 0.0 {
        period.min(MAX_PLAN_PERIOD)
    } else {
        DEFAULT_PLAN_PERIOD
    };
    let m = math::round(period / ts);
    if m.is_finite() && m >= 1.0 {
        (m as usize).min(MAX_PLAN_TICKS)
    } else {
        1
    }
}
/// Look-ahead window (segments) when the owner has no reason to choose another.
pub const DEFAULT_LOOKAHEAD: usize = 256;
/// Outputs waiting for the next motion segment, and outputs per segment.
pub const MAX_OUTPUTS: usize = 4;
/// Output bits.
pub const OUTPUT_BITS: u8 = 32;

/// Share of the smallest axis acceleration limit the tangential acceleration A_t may use;
/// the rest is what the curvature term v²|K_k| has left at full tangential acceleration.
pub const ACCEL_SHARE: f64 = 0.5;
/// Share of the smallest axis jerk limit the tangential jerk J_t may use; the rest is for
/// 3·v·A_t·|K_k| + v³|K'_k|.
pub const JERK_SHARE: f64 = 0.5;
/// The speed caps are computed against this fraction of every axis limit (sampling and
/// rounding margin).
pub const CAP_MARGIN: f64 = 0.98;
/// The velocity limits' share an arc's or helix's cap is computed against (see
/// `Path::curved_cap`).
pub const ARC_VEL_MARGIN: f64 = 0.9995;

/// What a curved piece fed below its cap keeps of the tangential room its curvature leaves
/// (`curved_lim`): the room less a millionth, so that the cap found with those limits is the
/// feed's, not a rounding's (where a tangent lies along an axis, the axis's curvature term is
/// 0 to within rounding, and no room at all would give a cap of 0 there).
const LIM_SLACK: f64 = 1.0 - 1e-6;
/// Samples per blend for its cap (and its deviation when not closed-form).
const BLEND_SAMPLES: usize = 96;
/// Largest share of a segment a blend may trim (at each end).
pub const MAX_TRIM_SHARE: f64 = 0.45;
/// Largest angle of an arc a blend may trim, rad.
const MAX_TRIM_ANGLE: f64 = core::f64::consts::FRAC_PI_4;
/// Turns above this (rad) are reversals: exact stop.
pub const REVERSAL: f64 = 175.0 * core::f64::consts::PI / 180.0;
/// The cosines of [`SMOOTH_TURN`] and [`REVERSAL`], which a push compares the tangents' dot
/// product with.
const COS_SMOOTH_TURN: f64 = 0.8660254037844387;
const COS_REVERSAL: f64 = -0.9961946980917455;
/// Tangents closer than this (|Ta − Tb|) with equal curvature join without a blend.
const TANGENT_EPS: f64 = 1e-9;
/// The numeric deviation is held this far below the tolerance.
const DEV_SAFETY: f64 = 0.97;
/// Segments per block of the look-ahead's block minima. Small: on dense paths the braking
/// reach spans a few dozen segments, and a block is passed only when none of its caps is
/// below the speed (32 passed almost none of them on the dense-curve benchmark).
pub const BLOCK: usize = 8;
/// The most segments a path's ring holds (a power of two): the card's own path buffer
/// (`MC_PATH_LEN`); a host's engine (feature `host`, the tests and benches) takes longer paths.
pub const MAX_RING: usize = if cfg!(feature = "host") {
    1 << 16
} else {
    firmware_proto::PATH_LEN.next_power_of_two()
};
/// Largest turn (rad) of a junction of two lines that may be smoothed (see [`Path::push`]).
pub const SMOOTH_TURN: f64 = 30.0 * core::f64::consts::PI / 180.0;
/// Longest ratio of two lines' lengths a smoothing blend joins. A blend from the middle of a
/// long line to the middle of a short one curves in its last few per cent: capped for that
/// curvature along all of its length (a 2 mm line before 2 µm zigzag chords ran at 0.04 mm/s),
/// and its curvature changing faster than its samples see (1.7 times an axis's jerk limit).
pub const SMOOTH_RATIO: f64 = 4.0;
/// Samples per smoothing blend for its deviation, and intervals for its cap (16 samples:
/// eight pairs of `geom::LANES`, or four fours of `geom::LANES_V3`; see `blend_cap_n`).
const SMOOTH_SAMPLES: usize = 32;
const SMOOTH_CAP_SAMPLES: usize = 15;
/// Golden sections per peak of a smoothing blend's sampled deviation (see
/// `smooth::sampled_dev2`): 0.618³⁰ of two sample steps, 10⁻⁸ of the blend's parameter.
const PEAK_STEPS: usize = 30;
/// Samples per NURBS piece for its cap.
const CURVE_CAP_SAMPLES: usize = 32;

/// Limits of the group, per axis (counts/s, /s², /s³), and optional tangential limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathLimits<const D: usize = MAX_AXES> {
    pub naxes: usize,
    pub ts: f64,
    pub vmax: [f64; D],
    pub amax: [f64; D],
    pub jmax: [f64; D],
    /// Tangential acceleration limit, 0 = derive from the axes.
    pub accel: f64,
    /// Tangential jerk limit, 0 = derive from the axes.
    pub jerk: f64,
    /// Servo ticks per planning step (1..=[`MAX_PLAN_TICKS`]): the look-ahead and the speed
    /// planner run once a step, and every tick in between follows the step's own
    /// jerk-limited profile (see the module doc).
    pub plan_ticks: usize,
}

/// The geometry of a segment. Arc: the plane is axes (u, v) of the group, `centre` in that
/// plane; the other axes move linearly with the arc length (a helix).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Geom<const D: usize = MAX_AXES> {
    Line {
        end: [f64; D],
    },
    Arc {
        u: usize,
        v: usize,
        centre: [f64; 2],
        ccw: bool,
        end: [f64; D],
    },
    /// An arc in the plane through the start of the three group axes `axes` with the normal
    /// `normal` (on those axes; any length but 0), counter-clockwise about it, around `centre`
    /// (on those axes, in the plane), to `end` (on its circle; off the plane along the normal
    /// only with `rise`: a helix along it); the other axes move linearly. An end at the start
    /// is a full turn.
    ArcNormal {
        axes: [usize; 3],
        normal: [f64; 3],
        centre: [f64; 3],
        rise: bool,
        end: [f64; D],
    },
    Dwell {
        time: f64,
    },
}

/// How a segment joins the previous one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transition {
    /// Exact stop at the corner.
    Exact,
    /// Blend whose distance to the corner geometry it replaces is ≤ the tolerance (0 = exact).
    MaxDeviation(f64),
    /// Blend trimming this length off each side (0 = exact).
    CornerDistance(f64),
    /// Thinh's blending of two lines (see `shift.rs`): each runs as its own rest-to-rest
    /// S-curve, this one starting while the previous one decelerates, within this deviation
    /// from the corner (0 = exact stop).
    TimeShift(f64),
}

/// PLCopen BlendingLow/Previous/Next/High: the feed cap at the junction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlendSpeed {
    Low,
    Previous,
    Next,
    High,
}

/// One programmed segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment<const D: usize = MAX_AXES> {
    pub id: u32,
    pub geom: Geom<D>,
    /// Programmed feed, counts/s (ignored by a dwell).
    pub feed: f64,
    pub transition: Transition,
    pub blend: BlendSpeed,
    /// The final segment of a program: stopping there is the end, not starvation.
    pub last: bool,
}

/// Where an output fires, in the next motion segment pushed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutputAt {
    Start,
    End,
    /// This far along the path from where the segment starts (its `SegmentStart`); at its
    /// end when the segment is shorter.
    Distance(f64),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputAction {
    pub bit: u8,
    pub on: bool,
    pub at: OutputAt,
}

/// What happened in a tick, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathEvent {
    SegmentStart {
        id: u32,
    },
    SegmentEnd {
        id: u32,
    },
    Output {
        bit: u8,
        on: bool,
        id: u32,
    },
    /// Started braking for the end of the queue (not marked `last`).
    Starving,
    /// Came to rest with nothing left.
    Idle,
    /// At rest at the pause point (`Path::pause`): the end of segment `id` (None: before any
    /// segment).
    Paused {
        id: Option<u32>,
    },
}

/// Refusals. The path is unchanged after each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathError {
    /// `reset` was never called.
    NotReady,
    /// A value is NaN or infinite.
    NotFinite,
    /// A value that must be positive (feed) or not negative (tolerance, time, distance) is
    /// not.
    NonPositive,
    /// A value is outside its range (includes subnormal feeds and tolerances, positions beyond
    /// [`MAX_POS`], output bits ≥ [`OUTPUT_BITS`]).
    OutOfRange,
    /// The ring (or the pending outputs) is full.
    Full,
    /// A line of no length.
    ZeroLength,
    /// An arc the circle code refuses (radius, end off the circle).
    BadArc(CircleError),
    /// An arc's end more than 1e-6·radius off its circle (a jump).
    ArcEndOffCircle,
    /// An axis index ≥ the group's axes, an arc plane of one axis, naxes not in 1..=D (the
    /// engine's dimension), or a NURBS curve of another dimension than the group's.
    BadAxis,
    /// A normal-vector arc's normal is zero.
    BadNormal,
    /// A normal-vector arc's centre, or its end (without a rise), more than 1e-6·radius off
    /// the plane through the start.
    OffPlane,
    /// A limit or the sample time is not finite, positive and in range.
    BadLimits,
    /// The look-ahead window is not in 1..=capacity.
    BadLookahead,
    /// `clear` while moving.
    Moving,
    /// A time-shifted transition on an arc or a curve, or after one, or a blend after a
    /// time-shifted line.
    TimeShift,
    /// A NURBS curve that does not start within its tolerance of where the path ends.
    CurveStart,
    /// A NURBS curve with a point of zero tangent, or that needs more pieces than the ring
    /// holds.
    Curve,
}

#[derive(Debug, Clone, Copy, Default)]
struct Block {
    /// Smallest geometric cap and smallest feed cap of its pieces.
    geo: f64,
    feed: f64,
    /// Path length of its segments.
    len: f64,
    stop: bool,
    /// Smallest c² + 2·A_t·x over its segments, x where a segment starts from the block's
    /// start and c its smallest geometric cap (`kg`) or feed cap (`kf`): a lower bound of the
    /// braking envelope that lets the look-ahead pass the whole block in one test (see
    /// `exec::Envelope`).
    kg: f64,
    kf: f64,
    /// Smallest tangential acceleration and jerk limits of its pieces (see `Seg::blim`).
    lim: Lim,
}

/// Tangential limits of a piece (acceleration and deceleration, jerk): a line's are every
/// axis's own limits projected onto its direction; a curved piece's are the shares of the
/// smallest axis limits ([`ACCEL_SHARE`], [`JERK_SHARE`]) its cap was computed with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lim {
    pub a: f64,
    pub j: f64,
}

impl Default for Lim {
    fn default() -> Self {
        Lim::NONE
    }
}

impl Lim {
    pub(super) const NONE: Lim = Lim {
        a: f64::INFINITY,
        j: f64::INFINITY,
    };
    /// The lower of each.
    #[inline(always)]
    pub(super) fn min(self, o: Lim) -> Lim {
        Lim {
            a: if o.a < self.a { o.a } else { self.a },
            j: if o.j < self.j { o.j } else { self.j },
        }
    }
    /// The greater of each.
    #[inline(always)]
    pub(super) fn max(self, o: Lim) -> Lim {
        Lim {
            a: if o.a > self.a { o.a } else { self.a },
            j: if o.j > self.j { o.j } else { self.j },
        }
    }
    /// Lower than `o` in either.
    #[inline(always)]
    pub(super) fn below(self, o: Lim) -> bool {
        self.a < o.a || self.j < o.j
    }
}

#[derive(Debug, Clone, Copy)]
struct Seg<const D: usize = MAX_AXES> {
    id: u32,
    prog: Prog<D>,
    feed: f64,
    last: bool,
    /// Exact stop at its start (the junction with the previous segment).
    stop_before: bool,
    has_blend: bool,
    blend: Blend<D>,
    /// Caps of the blend piece (or of the junction point of a tangent join): geometric and
    /// feed (before the override).
    jgeo: f64,
    jfeed: f64,
    /// Tangential limits of the blend piece (or of the junction point of a tangent join) and
    /// of the body.
    jlim: Lim,
    blim: Lim,
    /// Where it starts, from the start of its block (the block's length before it).
    x0: f64,
    /// Where it starts along the whole path: the distance the executor has covered since
    /// `reset` when it gets there (see `Path::exec_dist`).
    start: f64,
    /// The body: [body0, body1] in the segment's own arc length.
    body0: f64,
    body1: f64,
    bgeo: f64,
    /// The blend with the previous segment: trim length on the previous segment (on this
    /// one it is `body0`) and deviation.
    trim: f64,
    dev: f64,
    /// The blend is a smoothing blend (from the middle of the previous line to the middle of
    /// this one), with these curvature vectors at its ends.
    smooth: bool,
    kstart: V<D>,
    kend: V<D>,
    /// The curvature of the vertex where this line ends and the next one starts, when a
    /// smoothing blend was built there (`vertex_k`; the next push's rebuild needs it again).
    kvertex: Option<V<D>>,
    outs: [OutputAction; MAX_OUTPUTS],
    nouts: usize,
    fired: u8,
    dwell_ticks: u64,
    /// Runs as a time-shifted profile (see `shift.rs`), overlapping the previous one when
    /// `shift_join`.
    shift: bool,
    shift_join: bool,
    transition: Transition,
    /// A piece of a NURBS curve after its first: the same user segment as the piece before
    /// (no segment events between them; the outputs carry over).
    cont: bool,
}

impl<const D: usize> Default for Seg<D> {
    fn default() -> Self {
        Self {
            id: 0,
            prog: Prog::default(),
            feed: 0.0,
            last: false,
            stop_before: true,
            has_blend: false,
            blend: Blend::default(),
            jgeo: 0.0,
            jfeed: 0.0,
            jlim: Lim::NONE,
            blim: Lim::NONE,
            x0: 0.0,
            start: 0.0,
            body0: 0.0,
            body1: 0.0,
            bgeo: 0.0,
            trim: 0.0,
            dev: 0.0,
            smooth: false,
            kstart: [0.0; D],
            kend: [0.0; D],
            kvertex: None,
            outs: [OutputAction {
                bit: 0,
                on: false,
                at: OutputAt::Start,
            }; MAX_OUTPUTS],
            nouts: 0,
            fired: 0,
            dwell_ticks: 0,
            shift: false,
            shift_join: false,
            transition: Transition::Exact,
            cont: false,
        }
    }
}

impl<const D: usize> Seg<D> {
    fn len(&self) -> f64 {
        (if self.has_blend { self.blend.len } else { 0.0 }) + (self.body1 - self.body0)
    }
    fn is_dwell(&self) -> bool {
        matches!(self.prog, Prog::Dwell { .. })
    }
    /// Joins the previous segment with its blend, built in `blend` (its geometric and feed
    /// caps), trimming `trims.0` off the previous segment and `trims.1` off this one.
    fn join(&mut self, cap: f64, feed: f64, trims: (f64, f64), dev: f64) {
        self.stop_before = false;
        self.has_blend = true;
        self.jgeo = cap;
        self.jfeed = feed;
        self.trim = trims.0;
        self.body0 = trims.1;
        self.dev = dev;
    }
}

/// The blend of a junction, as built: trim length on each side and the deviation from the
/// programmed corner geometry (an upper bound where not closed-form).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlendInfo {
    pub trim: f64,
    pub deviation: f64,
    pub length: f64,
}

/// What the look-ahead found for this tick.
#[derive(Debug, Clone, Copy)]
struct Look {
    target: f64,
    rem: f64,
    /// `rem` is a stop point (exact stop, the end of the queue or of the window).
    stop: bool,
    queue_end: bool,
    window_end: usize,
    /// The planner's step toward `target` when the look-ahead computed it (see
    /// `PathSpeedPlanner::next_tracked`).
    track: Option<Track>,
    /// It lowered the target for a piece ahead this tick (it starts slowing for it).
    slowed: bool,
    /// The tangential limits it decided with: those of stops this step.
    dec: Lim,
    /// `rem` is a pause point's (see `pause`), not a stop point's.
    pause: bool,
}

/// The continuous-path engine of one axes group.
#[derive(Debug, Clone)]
pub struct Path<const D: usize = MAX_AXES> {
    segs: FixedVec<Seg<D>, MAX_RING>,
    blocks: FixedVec<Block, { MAX_RING / BLOCK }>,
    capacity: usize,
    ready: bool,
    lim: PathLimits<D>,
    at: f64,
    jt: f64,
    /// The limits the look-ahead decides with and stops are planned with: the lowest of the
    /// pieces the last walk looked at (see `exec::look`); the limits the next planning step
    /// ramps with: the lowest of the pieces near the executor; a halt's own limits hold
    /// instead of both until `clear`.
    dec: Lim,
    near: Lim,
    halt_lim: bool,
    lookahead: usize,
    planner: PathSpeedPlanner,
    /// The planner's period (`plan_ticks` servo ticks), s.
    tsp: f64,
    /// The planning step being run (see `exec::Step`).
    step: exec::Step,
    /// Path speed and acceleration at the last tick (within a step, its profile's).
    now: (f64, f64),
    /// Absolute indices: the segment whose piece the executor is in, and the next free one.
    exec: usize,
    tail: usize,
    /// In the first half of exec's blend: exec − 1 has not ended yet.
    prev_open: bool,
    in_blend: bool,
    /// Position within the piece (blend: its arc length; body: the segment's arc length).
    s: f64,
    started: bool,
    seg_travel: f64,
    dwell_left: u64,
    /// Ticks still held at rest on the exact stop just landed on (`STOP_SETTLE_TICKS`).
    settle: u8,
    pos: V<D>,
    last_end: V<D>,
    halted: bool,
    slow: Option<(f64, f64)>,
    distance: f64,
    pending: [OutputAction; MAX_OUTPUTS],
    npending: usize,
    starving_sent: bool,
    idle_sent: bool,
    /// The newest segment, whose smoothing blend has no cap yet (see `settle_cap`).
    cap_due: Option<usize>,
    /// Where the queued path ends, along the whole path (the next segment's `start`).
    end_dist: f64,
    /// What the last look-ahead walk passed (see `exec::Seen`).
    seen: Option<exec::Seen>,
    /// Tests run the look-ahead without what earlier walks saw, to compare, and count the
    /// ticks served by testing the pieces a walk tested again (`exec::Seen::still_safe`).
    #[cfg(test)]
    walk_every_tick: bool,
    #[cfg(test)]
    retests: usize,
    /// The time-shifted executor, while the executor's segment is one of its lines.
    chain: Chain,
    /// Scratch of `push_curve`: the pieces of a curve (knot span, ua, ub).
    breaks: FixedVec<(usize, f64, f64), MAX_RING>,
    /// A pause at the end of a segment (see `pause`).
    pause: pause::Pause,
    /// Push and tick run the engine's x86-64-v3 build (see `v3`): where the CPU has it.
    v3: bool,
}

#[inline(always)]
fn finite_v<const D: usize>(n: usize, p: &V<D>) -> Result<(), PathError> {
    let (mut zero, mut most) = (0.0, 0.0f64);
    for x in &p[..n] {
        zero += x * 0.0;
        most = most.max(x.abs());
    }
    if zero != 0.0 {
        return Err(PathError::NotFinite);
    }
    if most > MAX_POS {
        return Err(PathError::OutOfRange);
    }
    Ok(())
}

/// A feed: finite, positive, in [MIN_FEED, MAX_FEED].
#[inline(always)]
fn check_feed(x: f64) -> Result<f64, PathError> {
    if !x.is_finite() {
        return Err(PathError::NotFinite);
    }
    if x <= 0.0 {
        return Err(PathError::NonPositive);
    }
    if !(MIN_FEED..=MAX_FEED).contains(&x) {
        return Err(PathError::OutOfRange);
    }
    Ok(x)
}

/// A tolerance-like value: finite, ≥ 0, 0 or in [MIN_TOL, MAX_TOL].
#[inline(always)]
fn check_tol(x: f64) -> Result<f64, PathError> {
    if !x.is_finite() {
        return Err(PathError::NotFinite);
    }
    if x < 0.0 {
        return Err(PathError::NonPositive);
    }
    if x != 0.0 && !(MIN_TOL..=MAX_TOL).contains(&x) {
        return Err(PathError::OutOfRange);
    }
    Ok(x)
}

impl Path {
    /// An engine of [`MAX_AXES`] dimensions (a group of the card's) with room for `segments`
    /// queued segments: [`with_segments`](Self::with_segments) of `Path<MAX_AXES>`, which
    /// `Path::with_capacity` names without saying its dimension.
    pub fn with_capacity(segments: usize) -> Self {
        Self::with_segments(segments)
    }
}

impl<const D: usize> Path<D> {
    /// A path of `D` dimensions with room for `segments` queued segments (at least 1, at
    /// most [`MAX_RING`]); everything is made here. Call [`reset`](Self::reset) before use.
    pub fn with_segments(segments: usize) -> Self {
        let capacity = segments.clamp(1, MAX_RING);
        // a power of two (of blocks): a slot is an index masked, not divided (a division
        // costs tens of cycles, and the executor looks its segments up several times a tick)
        let ring = capacity.next_power_of_two().max(BLOCK);
        let lim = PathLimits {
            naxes: 1,
            ts: 1e-3,
            vmax: [1.0; D],
            amax: [1.0; D],
            jmax: [1.0; D],
            accel: 0.0,
            jerk: 0.0,
            plan_ticks: 1,
        };
        Self {
            segs: FixedVec::from_elem(Seg::default(), ring),
            blocks: FixedVec::from_elem(Block::default(), ring / BLOCK),
            capacity,
            ready: false,
            lim,
            at: 1.0,
            jt: 1.0,
            dec: Lim { a: 1.0, j: 1.0 },
            near: Lim { a: 1.0, j: 1.0 },
            halt_lim: false,
            lookahead: DEFAULT_LOOKAHEAD.min(capacity),
            planner: PathSpeedPlanner::unplanned(),
            tsp: 1e-3,
            step: exec::Step::NONE,
            now: (0.0, 0.0),
            exec: 0,
            tail: 0,
            prev_open: false,
            in_blend: false,
            s: 0.0,
            started: false,
            seg_travel: 0.0,
            dwell_left: 0,
            settle: 0,
            pos: [0.0; D],
            last_end: [0.0; D],
            halted: false,
            slow: None,
            distance: 0.0,
            pending: [Seg::<D>::default().outs[0]; MAX_OUTPUTS],
            npending: 0,
            starving_sent: false,
            idle_sent: true,
            cap_due: None,
            end_dist: 0.0,
            seen: None,
            #[cfg(test)]
            walk_every_tick: false,
            #[cfg(test)]
            retests: 0,
            chain: Chain::default(),
            pause: pause::Pause::Off,
            breaks: FixedVec::with_capacity(capacity),
            v3: v3::detected(),
        }
    }

    /// Checks the limits: (A_t, J_t).
    fn check_limits(lim: &PathLimits<D>) -> Result<(f64, f64), PathError> {
        if !(1..=D).contains(&lim.naxes) {
            return Err(PathError::BadAxis);
        }
        let ok = |x: f64| x.is_finite() && (LIMIT_RANGE.0..=LIMIT_RANGE.1).contains(&x);
        if !(lim.ts.is_finite() && (TS_RANGE.0..=TS_RANGE.1).contains(&lim.ts)) {
            return Err(PathError::BadLimits);
        }
        if !(1..=MAX_PLAN_TICKS).contains(&lim.plan_ticks) || lim.ts * lim.plan_ticks as f64 > 1.0 {
            return Err(PathError::BadLimits);
        }
        let n = lim.naxes;
        if !(lim.vmax[..n].iter().all(|&x| ok(x))
            && lim.amax[..n].iter().all(|&x| ok(x))
            && lim.jmax[..n].iter().all(|&x| ok(x)))
        {
            return Err(PathError::BadLimits);
        }
        if !(lim.accel == 0.0 || ok(lim.accel)) || !(lim.jerk == 0.0 || ok(lim.jerk)) {
            return Err(PathError::BadLimits);
        }
        let amin = lim.amax[..n].iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let jmin = lim.jmax[..n].iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let mut at = ACCEL_SHARE * amin;
        let mut jt = JERK_SHARE * jmin;
        if lim.accel > 0.0 {
            at = at.min(lim.accel);
        }
        if lim.jerk > 0.0 {
            jt = jt.min(lim.jerk);
        }
        Ok((at, jt))
    }

    /// At rest at `start`, empty, with these limits; `lookahead` = segments the planner
    /// considers (1..=capacity).
    pub fn reset(
        &mut self,
        start: [f64; D],
        lim: PathLimits<D>,
        lookahead: usize,
    ) -> Result<(), PathError> {
        let (at, jt) = Self::check_limits(&lim)?;
        finite_v(lim.naxes, &start)?;
        if !(1..=self.capacity).contains(&lookahead) {
            return Err(PathError::BadLookahead);
        }
        let tsp = lim.ts * lim.plan_ticks as f64;
        let mut planner = PathSpeedPlanner::new(tsp, at, jt).map_err(|_| PathError::BadLimits)?;
        planner.servo_ts = lim.ts;
        let mut start = start;
        for x in start[lim.naxes..].iter_mut() {
            *x = 0.0;
        }
        self.ready = true;
        self.lim = lim;
        self.at = at;
        self.jt = jt;
        self.dec = Lim { a: at, j: jt };
        self.near = self.dec;
        self.halt_lim = false;
        self.lookahead = lookahead;
        self.planner = planner;
        self.tsp = tsp;
        self.step = exec::Step::NONE;
        self.now = (0.0, 0.0);
        self.exec = 0;
        self.tail = 0;
        self.prev_open = false;
        self.in_blend = false;
        self.s = 0.0;
        self.started = false;
        self.seg_travel = 0.0;
        self.dwell_left = 0;
        self.settle = 0;
        self.pos = start;
        self.last_end = start;
        self.halted = false;
        self.slow = None;
        self.distance = 0.0;
        self.npending = 0;
        self.starving_sent = false;
        self.idle_sent = true;
        self.cap_due = None;
        self.end_dist = 0.0;
        self.seen = None;
        self.pause = pause::Pause::Off;
        self.shift_clear();
        Ok(())
    }

    #[inline(always)]
    fn slot(&self, i: usize) -> usize {
        i & (self.segs.len() - 1)
    }
    #[inline(always)]
    fn seg(&self, i: usize) -> &Seg<D> {
        &self.segs[self.slot(i)]
    }

    /// Tests of the move queue's normal-vector arcs (layout 1.13, which share this geometry):
    /// the length of queued segment `i` and its point at arc length `s`.
    #[cfg(test)]
    pub(crate) fn seg_point(&self, i: usize, s: f64) -> (f64, [f64; D]) {
        let p = &self.seg(i).prog;
        (p.len(), p.pos(s))
    }

    /// Segments queued (not ended yet).
    pub fn queued(&self) -> usize {
        self.tail - self.exec + usize::from(self.prev_open)
    }
    /// Room left, segments.
    pub fn free(&self) -> usize {
        self.capacity - self.queued()
    }
    #[inline(always)]
    pub fn is_moving(&self) -> bool {
        self.now.0 > 0.0 || self.now.1 != 0.0 || self.step.ahead() > 0.0 || self.chain.is_moving()
    }
    /// Path speed at the last tick, counts/s (in a time-shifted chain, the norm of the
    /// velocity).
    pub fn speed(&self) -> f64 {
        if self.chain.is_active() {
            self.chain.speed()
        } else {
            self.now.0
        }
    }
    /// Path acceleration at the last tick, counts/s² (in a time-shifted chain, the change of
    /// the speed).
    pub fn accel(&self) -> f64 {
        if self.chain.is_active() {
            self.chain.accel()
        } else {
            self.now.1
        }
    }
    /// Servo ticks per planning step (see [`PathLimits::plan_ticks`]).
    pub fn plan_ticks(&self) -> usize {
        self.lim.plan_ticks
    }
    /// Commanded position of the last tick.
    pub fn position(&self) -> [f64; D] {
        self.pos
    }
    /// Where the last segment queued ends (where the next one starts).
    pub fn end(&self) -> [f64; D] {
        self.last_end
    }
    /// The segment the path is in (until a blend's middle, the one before it).
    pub fn current_id(&self) -> Option<u32> {
        if self.prev_open {
            Some(self.seg(self.exec - 1).id)
        } else if self.exec < self.tail {
            Some(self.seg(self.exec).id)
        } else {
            None
        }
    }
    /// Distance along the path since `reset`, counts.
    pub fn distance(&self) -> f64 {
        self.distance
    }
    /// The tangential limits in use (A_t, J_t).
    pub fn tangential_limits(&self) -> (f64, f64) {
        (self.at, self.jt)
    }
    /// The blend joining the queued segment `id` to the one before it (None: no blend, or
    /// not queued).
    pub fn blend_info(&self, id: u32) -> Option<BlendInfo> {
        (self.exec.saturating_sub(1)..self.tail)
            .find(|&i| self.seg(i).id == id && self.seg(i).has_blend)
            .map(|i| {
                let s = self.seg(i);
                let length = if self.cap_due == Some(i) {
                    // not built yet (see `settle_cap`)
                    self.due_blend(i).len
                } else {
                    s.blend.len
                };
                BlendInfo {
                    trim: s.trim,
                    deviation: s.dev,
                    length,
                }
            })
    }

    /// Distance from the executor to the end of segment `upto`'s body (a queued segment at
    /// or after the executor's).
    #[inline(always)]
    fn dist_to_body_end(&self, upto: usize) -> f64 {
        let sg = self.seg(upto);
        sg.start + sg.len() - self.exec_dist()
    }

    /// [`push`](Self::push)'s body (which `v3.rs` builds twice).
    #[inline(always)]
    pub(super) fn push_impl(&mut self, seg: Segment<D>) -> Result<(), PathError> {
        if !self.ready {
            return Err(PathError::NotReady);
        }
        let n = self.lim.naxes;
        let p0 = self.last_end;
        let mut rec = Seg {
            id: seg.id,
            last: seg.last,
            ..Seg::default()
        };
        if !matches!(seg.geom, Geom::Dwell { .. }) {
            rec.feed = check_feed(seg.feed)?;
        }
        let tol = match seg.transition {
            Transition::Exact => 0.0,
            Transition::MaxDeviation(x)
            | Transition::CornerDistance(x)
            | Transition::TimeShift(x) => check_tol(x)?,
        };
        let fix_axes = |e: &mut V<D>| {
            for x in e[n..].iter_mut() {
                *x = 0.0;
            }
        };
        match seg.geom {
            Geom::Line { mut end } => {
                finite_v(n, &end)?;
                fix_axes(&mut end);
                let (p, len) = Prog::line(n, p0, end);
                let mut scale = 1.0f64;
                for k in 0..n {
                    scale = scale.max(p0[k].abs()).max(end[k].abs());
                }
                if len.is_nan() || len <= 64.0 * f64::EPSILON * scale {
                    return Err(PathError::ZeroLength);
                }
                rec.prog = p;
            }
            Geom::Arc {
                u,
                v,
                centre,
                ccw,
                mut end,
            } => {
                if u >= n || v >= n || u == v {
                    return Err(PathError::BadAxis);
                }
                finite_v(n, &end)?;
                if !(centre[0].is_finite() && centre[1].is_finite()) {
                    return Err(PathError::NotFinite);
                }
                if centre.iter().any(|x| x.abs() > MAX_POS) {
                    return Err(PathError::OutOfRange);
                }
                fix_axes(&mut end);
                let h = Helix::new(n, p0, end, u, v, centre, ccw).map_err(PathError::BadArc)?;
                let r0 = math::hypot(p0[u] - centre[0], p0[v] - centre[1]);
                let r1 = math::hypot(end[u] - centre[0], end[v] - centre[1]);
                if (r1 - r0).abs() > 1e-6 * r0.max(1.0) {
                    return Err(PathError::ArcEndOffCircle);
                }
                rec.prog = Prog::Helix(h);
            }
            Geom::ArcNormal {
                axes,
                normal,
                centre,
                rise,
                mut end,
            } => {
                let [a, b, c] = axes;
                if a >= n || b >= n || c >= n || a == b || b == c || a == c {
                    return Err(PathError::BadAxis);
                }
                finite_v(n, &end)?;
                if !centre.iter().chain(normal.iter()).all(|x| x.is_finite()) {
                    return Err(PathError::NotFinite);
                }
                if centre.iter().any(|x| x.abs() > MAX_POS) {
                    return Err(PathError::OutOfRange);
                }
                fix_axes(&mut end);
                let basis = geom::normal_basis(axes, normal).ok_or(PathError::BadNormal)?;
                let (e1, e2, en) = basis;
                let mut cv = p0;
                for k in 0..3 {
                    cv[axes[k]] = centre[k];
                }
                let on = |p: &V<D>, e: &V<D>| (0..n).map(|k| p[k] * e[k]).sum::<f64>();
                let r0 = math::hypot(on(&p0, &e1) - on(&cv, &e1), on(&p0, &e2) - on(&cv, &e2));
                let r1 = math::hypot(on(&end, &e1) - on(&cv, &e1), on(&end, &e2) - on(&cv, &e2));
                let eps = 1e-6 * r0.max(1.0);
                let h0 = on(&p0, &en);
                if (on(&cv, &en) - h0).abs() > eps || (!rise && (on(&end, &en) - h0).abs() > eps) {
                    return Err(PathError::OffPlane);
                }
                let h = Helix::normal(n, p0, end, basis, [on(&cv, &e1), on(&cv, &e2)])
                    .map_err(PathError::BadArc)?;
                if (r1 - r0).abs() > eps {
                    return Err(PathError::ArcEndOffCircle);
                }
                rec.prog = Prog::Helix(h);
            }
            Geom::Dwell { time } => {
                if !time.is_finite() {
                    return Err(PathError::NotFinite);
                }
                if time < 0.0 {
                    return Err(PathError::NonPositive);
                }
                if time > MAX_DWELL {
                    return Err(PathError::OutOfRange);
                }
                rec.prog = Prog::Dwell { p: p0 };
                rec.dwell_ticks = math::ceil(time / self.lim.ts - 1e-9).max(0.0) as u64;
            }
        }
        self.append(rec, seg.transition, seg.blend, tol)
    }

    /// Appends a validated segment or curve piece `rec` (its feed and program set), joining
    /// it to the previous one as `transition` and `blend` say (`tol`: the transition's
    /// checked tolerance). Nothing changes when it fails (it fails only before it changes
    /// anything).
    #[inline(always)]
    fn append(
        &mut self,
        mut rec: Seg<D>,
        transition: Transition,
        blend: BlendSpeed,
        tol: f64,
    ) -> Result<(), PathError> {
        if self.queued() >= self.capacity {
            return Err(PathError::Full);
        }
        let n = self.lim.naxes;
        let p0 = self.last_end;
        let motion = !rec.is_dwell();
        let len = rec.prog.len();
        rec.body1 = len;
        if rec.prog.is_curved() {
            (rec.blim, rec.bgeo) = self.curved_lim(&rec.prog, 0.0, len, rec.feed);
        } else {
            rec.bgeo = self.body_cap(&rec.prog, 0.0, len);
            rec.blim = self.piece_lim(&rec.prog);
        }
        // a blend is curved
        rec.jlim = Lim {
            a: self.at,
            j: self.jt,
        };
        rec.transition = transition;
        // The junction with the previous segment.
        let idle = self.exec >= self.tail;
        let prev_live = !idle && self.tail > self.exec;
        let mut prev_trim = 0.0;
        let mut convert_prev = false;
        let mut cap_due = false;
        if let Transition::TimeShift(_) = transition {
            if rec.prog.is_curved() || (prev_live && self.seg(self.tail - 1).prog.is_curved()) {
                return Err(PathError::TimeShift);
            }
            if self.shift_profile(&rec.prog, rec.feed, 0.0).is_err() {
                return Err(PathError::OutOfRange);
            }
            rec.shift = true;
            if prev_live && tol > 0.0 {
                let pi = self.tail - 1;
                let prev = self.seg(pi);
                if prev.shift {
                    rec.shift_join = true;
                } else if !prev.is_dwell()
                    && prev.stop_before
                    && (self.exec < pi || (!self.in_blend && self.s == 0.0 && !self.is_moving()))
                    && self.shift_profile(&prev.prog, prev.feed, 0.0).is_ok()
                {
                    // the line before starts from rest and has not moved: it runs as the
                    // chain's first profile (else this corner is an exact stop)
                    convert_prev = true;
                    rec.shift_join = true;
                }
            }
        } else if motion && prev_live && tol > 0.0 && self.seg(self.tail - 1).shift {
            return Err(PathError::TimeShift);
        } else if motion && prev_live && tol > 0.0 && !self.seg(self.tail - 1).is_dwell() {
            let prev = self.seg(self.tail - 1);
            let la = prev.prog.len();
            let (ta, ka) = prev.prog.tangent_curvature(la);
            let (tb, kb) = rec.prog.tangent_curvature(0.0);
            let (mut dt2, mut dot, mut dk2, mut k2) = (0.0, 0.0, 0.0, 0.0);
            for k in 0..n {
                dt2 += (ta[k] - tb[k]) * (ta[k] - tb[k]);
                dot += ta[k] * tb[k];
                dk2 += (ka[k] - kb[k]) * (ka[k] - kb[k]);
                k2 += ka[k] * ka[k] + kb[k] * kb[k];
            }
            // the turn's cosine (the turn itself, an arc cosine, where a corner blend needs it)
            let cos_turn = dot.clamp(-1.0, 1.0);
            // where a smoothing blend and the previous one rebuilt are built
            // (the new one in the segment's own, which holds nothing until it is joined)
            let mut again = Blend::default();
            // (the planner's state is where the step being run ends: the executor gets there
            // first, whatever it is told now)
            let need = {
                let pl = &self.planner;
                1.05 * PathSpeedPlanner::stopping_distance(pl.v, pl.a.max(0.0), self.at, self.jt)
                    + 4.0 * pl.v * self.tsp
                    + self.step.ahead()
                    + 1e-9
            };
            let rule = match blend {
                BlendSpeed::Low => prev.feed.min(rec.feed),
                BlendSpeed::Previous => prev.feed,
                BlendSpeed::Next => rec.feed,
                BlendSpeed::High => prev.feed.max(rec.feed),
            };
            if math::sqrt(dt2) <= TANGENT_EPS && dk2 <= 1e-18 * k2 {
                // tangent and curvature-continuous: no blend, the caps of both sides
                rec.stop_before = false;
                rec.jgeo = prev.bgeo.min(rec.bgeo);
                rec.jfeed = rule;
                rec.jlim = prev.blim.min(rec.blim);
            } else if let Some(sm) = if !prev.prog.is_curved()
                && matches!(transition, Transition::MaxDeviation(_))
                && cos_turn >= COS_SMOOTH_TURN
            {
                self.smooth(&rec.prog, tol, need, &mut again, &mut rec.blend)
            } else {
                None
            } {
                let ps = self.slot(self.tail - 1);
                self.segs[ps].kvertex = Some(sm.kvertex);
                if let Some((cap, dev, kend)) = sm.again {
                    let pi = self.tail - 1;
                    let ps = self.slot(pi);
                    let old = self.segs[ps].blend.len;
                    let sp = &mut self.segs[ps];
                    sp.blend = again;
                    sp.jgeo = cap;
                    sp.dev = dev;
                    sp.kend = kend;
                    let x0 = sp.x0;
                    let new_len = sp.blend.len;
                    self.end_dist += new_len - old;
                    let bk = &mut self.blocks[ps / BLOCK];
                    bk.len += new_len - old;
                    bk.geo = bk.geo.min(cap);
                    bk.kg = bk.kg.min(cap * cap + 2.0 * self.at * x0);
                    self.cap_due = None;
                }
                // The newest blend ends with curvature 0 and is rebuilt by the next push in
                // the common case: only checked so far, it is built and capped when the
                // look-ahead may reach it (see `settle_cap`), so that each push builds one
                // blend and computes one cap, not two.
                rec.join(0.0, rule, (sm.da, sm.db), sm.dev);
                cap_due = true;
                rec.smooth = true;
                rec.kstart = sm.kstart;
                prev_trim = sm.da;
            } else if cos_turn > COS_REVERSAL {
                let turn = math::acos(cos_turn);
                // room on each side: the share of the segment, and on the executor's side
                // what it can still slow down before
                let mut room = Self::room(&prev.prog)
                    .min(la - prev.body0)
                    .min(Self::room(&rec.prog));
                let to_corner = self.dist_to_body_end(self.tail - 1);
                room = room.min(to_corner - need);
                let build =
                    |d: f64| Blend::new(n, &prev.prog.frame(la - d), &rec.prog.frame(d), d, d);
                let line_line = !prev.prog.is_curved() && !rec.prog.is_curved();
                let (d, dev) = match transition {
                    Transition::MaxDeviation(tol) => {
                        if line_line {
                            let f = 0.375 * math::sin(0.5 * turn);
                            let d = if f > 0.0 { (tol / f).min(room) } else { room };
                            (d, f * d)
                        } else {
                            let target = DEV_SAFETY * tol;
                            let dev_at = |d: f64| match build(d) {
                                Some(b) => Self::deviation(n, &b, &prev.prog, &rec.prog, d),
                                None => f64::INFINITY,
                            };
                            let dmax = dev_at(room.max(0.0));
                            if room > 0.0 && dmax <= target {
                                (room, dmax)
                            } else {
                                let (mut lo, mut hi) = (0.0, room.max(0.0));
                                let mut dev_lo = 0.0;
                                for _ in 0..40 {
                                    let mid = 0.5 * (lo + hi);
                                    let dm = dev_at(mid);
                                    if dm <= target {
                                        lo = mid;
                                        dev_lo = dm;
                                    } else {
                                        hi = mid;
                                    }
                                    if hi - lo <= 1e-6 * hi {
                                        break;
                                    }
                                }
                                (lo, dev_lo)
                            }
                        }
                    }
                    Transition::CornerDistance(cd) => {
                        let d = cd.min(room);
                        let dev = if line_line {
                            0.375 * math::sin(0.5 * turn) * d
                        } else {
                            build(d)
                                .map(|b| Self::deviation(n, &b, &prev.prog, &rec.prog, d))
                                .unwrap_or(f64::INFINITY)
                        };
                        (d, dev)
                    }
                    Transition::Exact | Transition::TimeShift(_) => (0.0, 0.0),
                };
                let scale = p0[..n].iter().fold(1.0f64, |m, x| m.max(x.abs()));
                if d > 1e3 * f64::EPSILON * scale && d.is_finite() {
                    if let Some(b) = build(d) {
                        let cap = self.blend_cap(&b, BLEND_SAMPLES);
                        if cap > 0.0 && cap.is_finite() && !self.stop_is_faster(b.len, cap) {
                            rec.blend = b;
                            rec.join(cap, rule, (d, d), dev);
                            prev_trim = d;
                        }
                    }
                }
            }
        }
        if rec.has_blend && rec.prog.is_curved() {
            // the body's cap without the trimmed start (a line's is the same everywhere)
            (rec.blim, rec.bgeo) = self.curved_lim(&rec.prog, rec.body0, len, rec.feed);
        }
        if motion {
            rec.outs[..self.npending].copy_from_slice(&self.pending[..self.npending]);
            rec.nouts = self.npending;
            self.npending = 0;
        }
        // commit
        if let Some(i) = self.cap_due {
            // not rebuilt by this push: the previous blend keeps its shape and gets its cap
            self.settle_cap(i);
        }
        if convert_prev {
            let ps = self.slot(self.tail - 1);
            self.segs[ps].shift = true;
        }
        if prev_trim > 0.0 {
            let pi = self.tail - 1;
            let ps = self.slot(pi);
            self.segs[ps].body1 -= prev_trim;
            self.blocks[ps / BLOCK].len -= prev_trim;
            self.end_dist -= prev_trim;
        }
        if self.tail > 0 {
            // the segment before is rebuilt or trimmed above
            self.window_changed(self.tail - 1);
        }
        if idle {
            self.in_blend = false;
            self.prev_open = false;
            self.s = 0.0;
            self.started = false;
        }
        let sl = self.slot(self.tail);
        let b = &mut self.blocks[sl / BLOCK];
        if sl.is_multiple_of(BLOCK) {
            *b = Block {
                geo: f64::INFINITY,
                feed: f64::INFINITY,
                len: 0.0,
                stop: false,
                kg: f64::INFINITY,
                kf: f64::INFINITY,
                lim: Lim::NONE,
            };
        }
        rec.x0 = b.len;
        b.lim = b.lim.min(rec.blim);
        if !rec.stop_before {
            b.lim = b.lim.min(rec.jlim);
        }
        rec.start = self.end_dist;
        self.end_dist += rec.len();
        b.len += rec.len();
        b.stop |= rec.stop_before;
        b.geo = b.geo.min(rec.bgeo);
        b.feed = b.feed.min(rec.feed);
        let (mut g, mut f) = (rec.bgeo, rec.feed);
        if !rec.stop_before {
            if !cap_due {
                g = g.min(rec.jgeo);
            }
            f = f.min(rec.jfeed);
        }
        b.geo = b.geo.min(g);
        b.feed = b.feed.min(f);
        b.kg = b.kg.min(g * g + 2.0 * self.at * rec.x0);
        b.kf = b.kf.min(f * f + 2.0 * self.at * rec.x0);
        if cap_due {
            self.cap_due = Some(self.tail);
        }
        self.last_end = rec.prog.end();
        self.segs[sl] = rec;
        self.tail += 1;
        self.starving_sent = false;
        self.idle_sent = false;
        Ok(())
    }

    /// Attaches an output to the next motion segment pushed (at most [`MAX_OUTPUTS`]).
    pub fn push_output(&mut self, o: OutputAction) -> Result<(), PathError> {
        if o.bit >= OUTPUT_BITS {
            return Err(PathError::OutOfRange);
        }
        if let OutputAt::Distance(d) = o.at {
            if !d.is_finite() {
                return Err(PathError::NotFinite);
            }
            if d < 0.0 {
                return Err(PathError::NonPositive);
            }
            if d > 4.0 * MAX_POS {
                return Err(PathError::OutOfRange);
            }
        }
        if self.npending >= MAX_OUTPUTS {
            return Err(PathError::Full);
        }
        self.pending[self.npending] = o;
        self.npending += 1;
        Ok(())
    }
}
