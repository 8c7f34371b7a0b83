//! What a run of a program did, measured from the commanded positions (and the actual ones,
//! where given). The G-code runner keeps one as it runs ([`crate::gcode::run::Runner::report`],
//! C `mc_gcode_report`); `mcctl run` prints it.
//!
//! [`Report`] takes the program's blocks as they are queued (the programmed geometry, from
//! [`blocks`]) and the commanded axis positions of every servo tick as they come (mm,
//! program coordinates), with the servo period and each axis's limits, in memory that does
//! not grow with the run (running peaks, the first and last moving ticks, a count of
//! stops, the largest deviation so far, a sliding window of the programmed path);
//! [`analyse`] does the same for a whole program and a list of points. It reports:
//!
//! - `path_time`: the time the commanded point moves. Tick `k` *moves* when
//!   `|p[k] − p[k−1]| / ts` is at least the rest speed ([`REST_SPEED`] unless given); the
//!   time is `(last moving tick − first moving tick + 1)·ts`, i.e. from the last sample at
//!   rest before the motion to the first sample at rest after it.
//! - `segments`: the number of motion blocks (lines and arcs, rapids included).
//! - `peak_vel_ratio`, `peak_accel_ratio`, `peak_jerk_ratio`: per axis, the largest
//!   |1st, 2nd, 3rd backward difference| / (ts, ts², ts³) over the axis's limit; the worst
//!   axis's ratio. Every tick counts, rests included.
//! - `max_deviation`: the largest distance from a commanded point to the programmed path
//!   (the union of the lines, arcs and helices held when the point comes, rapids included:
//!   the whole program for [`analyse`]; for [`Report`] the blocks added so far from
//!   [`WINDOW_BEHIND`] segments behind the point's nearest one), in mm. Lines and circles
//!   are exact; a helix is sampled (32 samples a turn, over the part of it close enough in
//!   height) and the best sample refined by golden-section search.
//! - `exact_stops`: the number of maximal runs of non-moving ticks strictly between the first
//!   and the last moving tick: the initial and the final rests are not counted. **Programmed
//!   dwells count** (a G4 is a rest like any other: this report looks only at the motion);
//!   subtract the program's `Dwell` blocks that fall between moves if only the planner's
//!   stops are wanted.
//! - `max_following_error`, `max_contour_error`: with the actual point of a tick
//!   ([`Report::push_actual`]), its largest distance to the commanded point of the same tick,
//!   and to the programmed path (searched as the deviation is, from the actual point's own
//!   nearest segment). 0 when no actual point was given.
//! - `ticks`, `ticks_seen`: the ticks from the first point to the last and how many of them
//!   had a point. A host sampling a card that runs on its own misses ticks
//!   ([`Report::push_at`]): the peaks then come only from differences over consecutive ticks
//!   seen, and a tick counts as moving when its point moved at the rest speed or faster on
//!   average since the last point seen.
//!
//! # The window rule for the deviation
//!
//! For each point the motion segments `cur−2 ..= cur+8` are searched first, `cur` being the
//! nearest segment of the previous point (ties go to the later segment, so the window
//! follows the program forward as the points advance). The window's best distance `d` is
//! only an upper bound: a path that comes back near itself (a zigzag, a rapid over the part,
//! the closing edge of a contour) can hold a nearer segment anywhere. So the search widens,
//! but only where it must: a tree of bounding boxes over contiguous runs of 8, 16, 32, …
//! segments is walked from its top, and a box is opened only when it is nearer to the point
//! than the best distance so far (the nearer child first). The result is the exact nearest
//! distance. (A rule on `d` alone, such as "widen when `d` grows faster than the point
//! moves", is not enough: at a square's closing corner it locks onto the last edge and
//! follows it while the point runs along the first one.) The cost per point is the 11
//! window segments, O(log blocks) box tests, and the segments of the boxes that truly come
//! within `d` of the point; never O(blocks) unless the path really crowds the point.
//! 200,000 ticks over 10,000 blocks cost about 11 segment distances a tick (a test counts
//! them).
//!
//! The tree is over the segments held: [`Report`] adds segments at its end as they are
//! queued and drops those more than [`WINDOW_BEHIND`] behind the nearest segment of the
//! last point, so a run of any length holds at most that many plus those queued ahead (the
//! card's path buffer, 4096), and the tree about log2(12,288 / 8) levels. Over the whole
//! program the walk grew with the program (in `perf`, the search took 15 % of `mcctl run`
//! on a 100,000-chord spiral and 33 % on a 300,000-chord one); over the window it does not.

pub mod blocks;

pub use blocks::{blocks_of, parse, parse_from, ArcGeom, Block, Blocks};
use std::collections::VecDeque;
use std::f64::consts::{PI, TAU};
use std::fmt;

/// Default rest speed (mm/s): a tick whose speed is below it does not move.
pub const REST_SPEED: f64 = 1e-6;
/// Segments searched behind and ahead of the last best one.
const WINDOW_BACK: usize = 2;
const WINDOW_AHEAD: usize = 8;
/// Helix samples per turn before refinement.
const HELIX_SAMPLES_PER_TURN: f64 = 32.0;

/// One axis's limits: mm/s, mm/s², mm/s³.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLimits {
    /// mm/s.
    pub vmax: f64,
    /// mm/s².
    pub amax: f64,
    /// mm/s³.
    pub jmax: f64,
}

/// See the [module documentation](self) for every field's definition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathReport {
    /// s.
    pub path_time: f64,
    /// Motion blocks.
    pub segments: usize,
    /// The worst axis's peak velocity over its limit.
    pub peak_vel_ratio: f64,
    /// The same for acceleration.
    pub peak_accel_ratio: f64,
    /// The same for jerk.
    pub peak_jerk_ratio: f64,
    /// mm.
    pub max_deviation: f64,
    /// Stops between the first and the last move.
    pub exact_stops: usize,
    /// The largest distance between the commanded and the actual point of one tick, mm
    /// (0 when no actual point was given: [`Report::push_actual`]).
    pub max_following_error: f64,
    /// The largest distance from an actual point to the programmed path, mm (0 when no
    /// actual point was given).
    pub max_contour_error: f64,
    /// Ticks from the first point to the last, and of them the ticks whose point was given
    /// (all of them on a stepped card; fewer when the card runs on its own and the host
    /// samples it: [`Report::push_at`]).
    pub ticks: u64,
    /// See `ticks`.
    pub ticks_seen: u64,
}

/// Why no report could be made.
#[derive(Debug, Clone, PartialEq)]
pub enum ReportError {
    /// The servo period is not a positive finite number.
    BadPeriod(f64),
    /// A limit is not positive (an infinite one is allowed: its ratio is 0).
    BadLimit {
        /// 0, 1, 2: X, Y, Z.
        axis: usize,
        /// Which limit.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The rest speed is negative or NaN.
    BadRestSpeed(f64),
    /// A commanded position is not finite.
    NonFinitePoint(usize),
    /// There are positions but the program has no motion block to measure them against.
    NoMotion,
    /// A point given for a tick not after the last one's.
    TickOrder {
        /// The point's tick.
        tick: u64,
        /// The last point's.
        last: u64,
    },
}

impl fmt::Display for ReportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReportError::BadPeriod(ts) => write!(f, "servo period {ts} s is not positive"),
            ReportError::BadLimit { axis, what, value } => {
                write!(f, "axis {axis}: {what} limit {value} is not positive")
            }
            ReportError::BadRestSpeed(v) => write!(f, "rest speed {v} is not >= 0"),
            ReportError::NonFinitePoint(k) => write!(f, "position of tick {k} is not finite"),
            ReportError::NoMotion => write!(f, "the program has no motion block"),
            ReportError::TickOrder { tick, last } => {
                write!(
                    f,
                    "a point for tick {tick}, not after the last one's ({last})"
                )
            }
        }
    }
}

impl std::error::Error for ReportError {}

/// The report of a run, with the default rest speed [`REST_SPEED`].
pub fn analyse(
    blocks: &[Block],
    points: &[[f64; 3]],
    ts: f64,
    limits: &[AxisLimits; 3],
) -> Result<PathReport, ReportError> {
    analyse_with_rest_speed(blocks, points, ts, limits, REST_SPEED)
}

/// The report of a run; ticks slower than `rest_speed` (mm/s) are at rest (raise it for
/// positions quantised to encoder counts). The whole program is held: [`Report`] with every
/// block added before the first point.
pub fn analyse_with_rest_speed(
    blocks: &[Block],
    points: &[[f64; 3]],
    ts: f64,
    limits: &[AxisLimits; 3],
    rest_speed: f64,
) -> Result<PathReport, ReportError> {
    let mut r = Report::new(ts, limits, rest_speed)?;
    r.behind = usize::MAX;
    for b in blocks {
        r.add_block(b);
    }
    for &p in points {
        r.push(p)?;
    }
    r.finish()
}

/// The distance (mm) from `p` to a motion block; `None` for a dwell or an output.
pub fn distance_to_block(block: &Block, p: [f64; 3]) -> Option<f64> {
    Seg::new(block).map(|s| s.distance(p, f64::INFINITY))
}

/// Motion segments kept behind the one nearest the last point, for [`Report`]'s deviation.
/// The card's path buffer holds [`PATH_LEN`](firmware_proto::PATH_LEN) (4096) segments
/// ahead of the one it runs, so the nearest segment of a point is never more than that
/// ahead of the running one; twice that behind keeps the running segment and at least 4096
/// before it.
pub const WINDOW_BEHIND: usize = 8192;
/// Most source lines one fitted item stands for, as [`Report::running`] counts them (the
/// SDK's chord fitter: a chunk, or a straight run).
const FITTED_LINES: usize = 16 * 1024;
/// Points held before the first motion block is added (see [`Report::push`]).
const PENDING_MAX: usize = 1024;

/// A run's report computed as it runs, in memory that does not grow with the number of
/// ticks: running peaks of the axes' differences, the first and last moving ticks and the
/// stops between them, the largest deviation so far. The programmed path is held as a
/// sliding window: the motion blocks added (in program order, at least up to the one being
/// run: [`Report::add_block`]) from [`WINDOW_BEHIND`] segments behind the nearest segment of
/// the last point. A point's deviation is its distance to the segments held when it is
/// pushed (exactly as the module documentation says when the whole program is held, as in
/// [`analyse`]); a segment dropped behind, or not yet added, is not searched.
#[derive(Debug, Clone)]
pub struct Report {
    ts: f64,
    limits: [AxisLimits; 3],
    rest_speed: f64,
    /// Segments kept behind the nearest one.
    behind: usize,
    /// Ticks covered so far (points pushed and ticks missed between them).
    ticks: u64,
    /// Points pushed so far.
    pushed: u64,
    /// The card's tick of the last point, when the caller gives ticks ([`Report::push_at`]).
    last_tick: Option<u64>,
    /// Consecutive ticks ending with the newest point (differences reach back this far).
    run: u64,
    /// The last four points, the newest at `(pushed - 1) % 4`.
    last: [[f64; 3]; 4],
    peak: [[f64; 3]; 3],
    /// The first and last moving ticks.
    first_moving: Option<u64>,
    last_moving: u64,
    /// A tick at rest since the last moving one.
    rested: bool,
    stops: usize,
    segments: usize,
    path: Window,
    /// The nearest segment of the last point (absolute index).
    cur: usize,
    /// The source line of the segment the card runs, when the caller says
    /// ([`Report::running`]).
    running: Option<usize>,
    max_deviation: f64,
    /// The nearest segment of the last actual point, and the largest errors so far.
    cur_actual: Option<usize>,
    max_following: f64,
    max_contour: f64,
    /// Points pushed before any motion block (consecutive repeats once).
    pending: Vec<[f64; 3]>,
    stack: Vec<(usize, usize)>,
    /// Segment distances computed.
    evals: usize,
}

impl Report {
    /// An empty report for servo period `ts` (s), the axes' `limits` and the rest speed
    /// (mm/s, [`REST_SPEED`] by default).
    pub fn new(ts: f64, limits: &[AxisLimits; 3], rest_speed: f64) -> Result<Report, ReportError> {
        if !(ts > 0.0 && ts.is_finite()) {
            return Err(ReportError::BadPeriod(ts));
        }
        for (axis, l) in limits.iter().enumerate() {
            for (what, value) in [
                ("velocity", l.vmax),
                ("acceleration", l.amax),
                ("jerk", l.jmax),
            ] {
                if value.is_nan() || value <= 0.0 {
                    return Err(ReportError::BadLimit { axis, what, value });
                }
            }
        }
        if rest_speed.is_nan() || rest_speed < 0.0 {
            return Err(ReportError::BadRestSpeed(rest_speed));
        }
        Ok(Report {
            ts,
            limits: *limits,
            rest_speed,
            behind: WINDOW_BEHIND,
            running: None,
            ticks: 0,
            pushed: 0,
            last_tick: None,
            run: 0,
            cur_actual: None,
            max_following: 0.0,
            max_contour: 0.0,
            last: [[0.0; 3]; 4],
            peak: [[0.0; 3]; 3],
            first_moving: None,
            last_moving: 0,
            rested: false,
            stops: 0,
            segments: 0,
            path: Window::default(),
            cur: 0,
            max_deviation: 0.0,
            pending: Vec::new(),
            stack: Vec::new(),
            evals: 0,
        })
    }

    /// The program's next block (dwells and outputs are passed over).
    pub fn add_block(&mut self, block: &Block) {
        let Some(seg) = Seg::new(block) else {
            return;
        };
        self.segments += 1;
        self.path.add(seg, block.line());
        for p in std::mem::take(&mut self.pending) {
            self.measure(p);
        }
    }

    /// The card runs the segment of this source line (an item fitted from many lines carries
    /// the last one's). Nothing from the segment before its first line on is dropped from
    /// the window: where blocks are added far ahead of the card (the chord fitter holds
    /// thousands of lines before it sends their curve) and the path comes back near itself
    /// (a trochoid's next loops), the nearest segment can be one far ahead, and the window
    /// dropped the segments the card was still running (10.55 mm of "deviation" on
    /// LinuxCNC's trochoidal.ngc).
    pub fn running(&mut self, line: usize) {
        self.running = Some(line);
    }

    /// The commanded point of the next tick (mm). A point pushed before any motion block
    /// was added is measured when the first one is (up to 1024 distinct points: a run adds
    /// what it queues on the card before it steps it).
    pub fn push(&mut self, p: [f64; 3]) -> Result<(), ReportError> {
        self.last_tick = self.last_tick.map(|t| t.wrapping_add(1));
        self.advance(0, p)
    }

    /// The commanded point of the card's tick `tick` (mm), for a host that samples a card
    /// running on its own: the ticks between the last point's and this one are missed. Only
    /// differences over consecutive ticks count towards the peaks; the path time and the
    /// stops count every tick.
    pub fn push_at(&mut self, tick: u64, p: [f64; 3]) -> Result<(), ReportError> {
        let missed = match self.last_tick {
            Some(last) if tick <= last => return Err(ReportError::TickOrder { tick, last }),
            Some(last) => tick - last - 1,
            None => 0,
        };
        self.advance(missed, p)?;
        self.last_tick = Some(tick);
        Ok(())
    }

    fn advance(&mut self, missed: u64, p: [f64; 3]) -> Result<(), ReportError> {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(ReportError::NonFinitePoint(self.ticks as usize));
        }
        if self.pushed > 0 {
            self.ticks += missed;
        }
        let k = self.ticks;
        let n = self.pushed;
        let ts = self.ts;
        // (differences reach back over the consecutive ticks before this one; wrapping: the
        // older points are only read once they exist, and 2⁶⁴ is a multiple of 4)
        let reach = if missed == 0 { self.run.min(3) } else { 0 };
        let at = |m: u64| self.last[(n.wrapping_sub(m) % 4) as usize];
        if n >= 1 {
            let (p1, p2, p3) = (at(1), at(2), at(3));
            for i in 0..3 {
                if reach >= 1 {
                    let v = &mut self.peak[0][i];
                    *v = v.max(((p[i] - p1[i]) / ts).abs());
                }
                if reach >= 2 {
                    let a = &mut self.peak[1][i];
                    *a = a.max(((p[i] - 2.0 * p1[i] + p2[i]) / (ts * ts)).abs());
                }
                if reach >= 3 {
                    let d3 = p[i] - 3.0 * p1[i] + 3.0 * p2[i] - p3[i];
                    let j = &mut self.peak[2][i];
                    *j = j.max((d3 / (ts * ts * ts)).abs());
                }
            }
            if dist(p, p1) / (ts * (missed + 1) as f64) >= self.rest_speed {
                if self.first_moving.is_none() {
                    self.first_moving = Some(k);
                } else if self.rested {
                    self.stops += 1;
                }
                self.last_moving = k;
                self.rested = false;
            } else if self.first_moving.is_some() {
                self.rested = true;
            }
        }
        self.run = if missed == 0 { self.run + 1 } else { 1 };
        self.last[(n % 4) as usize] = p;
        self.pushed += 1;
        self.ticks += 1;
        if self.path.is_empty() {
            if self.pending.last() != Some(&p) && self.pending.len() < PENDING_MAX {
                self.pending.push(p);
            }
        } else {
            self.measure(p);
        }
        Ok(())
    }

    /// The actual point (mm) of the tick of the last commanded point: its distance to the
    /// commanded point (the following error) and to the programmed path (the contour
    /// error). An actual point before any motion block, or before any commanded point, is
    /// not measured.
    pub fn push_actual(&mut self, a: [f64; 3]) -> Result<(), ReportError> {
        if a.iter().any(|x| !x.is_finite()) {
            return Err(ReportError::NonFinitePoint(self.ticks as usize));
        }
        if self.pushed == 0 || self.path.is_empty() {
            return Ok(());
        }
        let p = self.last[((self.pushed - 1) % 4) as usize];
        self.max_following = self.max_following.max(dist(p, a));
        let from = self.cur_actual.unwrap_or(self.cur).max(self.path.base);
        let (best, at) = self.nearest(a, from);
        self.cur_actual = Some(at);
        self.max_contour = self.max_contour.max(best);
        Ok(())
    }

    /// The report of the points pushed so far.
    pub fn finish(&self) -> Result<PathReport, ReportError> {
        if self.segments == 0 && self.ticks > 0 {
            return Err(ReportError::NoMotion);
        }
        let worst = |peak: [f64; 3], lim: fn(&AxisLimits) -> f64| {
            (0..3)
                .map(|i| peak[i] / lim(&self.limits[i]))
                .fold(0.0, f64::max)
        };
        let path_time = self
            .first_moving
            .map_or(0.0, |f| (self.last_moving - f + 1) as f64 * self.ts);
        Ok(PathReport {
            path_time,
            segments: self.segments,
            peak_vel_ratio: worst(self.peak[0], |l| l.vmax),
            peak_accel_ratio: worst(self.peak[1], |l| l.amax),
            peak_jerk_ratio: worst(self.peak[2], |l| l.jmax),
            max_deviation: self.max_deviation,
            exact_stops: self.stops,
            max_following_error: self.max_following,
            max_contour_error: self.max_contour,
            ticks: self.ticks,
            ticks_seen: self.pushed,
        })
    }

    /// Motion segments held now (for the programmed path's window).
    pub fn held_segments(&self) -> usize {
        self.path.segs.len()
    }

    /// The distance of `p` to the path held: the window of the module documentation, then
    /// the tree's proof; drops what falls [`WINDOW_BEHIND`] behind the nearest segment.
    fn measure(&mut self, p: [f64; 3]) -> f64 {
        let (best, at) = self.nearest(p, self.cur);
        self.cur = at;
        self.max_deviation = self.max_deviation.max(best);
        // (the actual point's segment is kept too: it lags the commanded one)
        let mut keep_from = self.cur_actual.map_or(at, |c| at.min(c));
        if let Some(line) = self.running {
            // (the fitted item's first line is at most a fitter's chunk before its last)
            let first = line.saturating_sub(FITTED_LINES);
            let w = &self.path;
            keep_from = keep_from.min(w.base + w.lines.partition_point(|&l| l < first));
        }
        let keep = keep_from.saturating_sub(self.behind);
        self.path.drop_before(keep);
        best
    }

    /// The distance of `p` to the path held and its nearest segment, searched from segment
    /// `cur` (the window, then the tree).
    fn nearest(&mut self, p: [f64; 3], cur: usize) -> (f64, usize) {
        let w = &self.path;
        let (base, end) = (w.base, w.base + w.segs.len());
        let lo = cur.saturating_sub(WINDOW_BACK).max(base);
        let hi = (cur + WINDOW_AHEAD + 1).min(end);
        let (mut best, mut at) = (f64::INFINITY, cur);
        for i in lo..hi.max(lo) {
            self.evals += 1;
            let d = w.segs[i - base].distance(p, best);
            if d <= best {
                (best, at) = (d, i);
            }
        }
        self.evals += w.improve(p, lo..hi, &mut best, &mut at, &mut self.stack);
        (best, at)
    }
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    fn add(&mut self, p: [f64; 3]) {
        for ((lo, hi), x) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
            *lo = lo.min(x);
            *hi = hi.max(x);
        }
    }

    fn union(mut self, o: &Aabb) -> Aabb {
        self.add(o.lo);
        self.add(o.hi);
        self
    }

    /// The distance from `p` to the box: no point inside it is nearer.
    fn distance(&self, p: [f64; 3]) -> f64 {
        let mut s = 0.0;
        for ((lo, hi), x) in self.lo.iter().zip(&self.hi).zip(p) {
            let e = (lo - x).max(x - hi).max(0.0);
            s += e * e;
        }
        s.sqrt()
    }
}

/// Segments per leaf box.
const LEAF: usize = 8;

/// One level of the tree: the boxes of nodes `first ..`; node `i` of level `l` holds
/// segments `i·LEAF·2^l .. (i+1)·LEAF·2^l` (absolute indices).
#[derive(Debug, Clone, Default)]
struct Level {
    first: usize,
    boxes: VecDeque<Aabb>,
}

/// The programmed path held: segments `base ..` in program order, and a tree of bounding
/// boxes over contiguous runs of 8, 16, 32, … of them. Segments are added at the end and
/// dropped from the front; a box partly dropped keeps its extent (a box holds what it
/// holds, so it still bounds the distance from below), one wholly dropped goes. Levels are
/// added until the top has at most two boxes, so a window of `n` segments has about
/// log2(n / 8) levels, each of a few boxes.
#[derive(Debug, Clone, Default)]
struct Window {
    segs: VecDeque<Seg>,
    /// Each held segment's source line (increasing).
    lines: VecDeque<usize>,
    base: usize,
    levels: Vec<Level>,
}

impl Window {
    fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    fn add(&mut self, seg: Seg, line: usize) {
        let idx = self.base + self.segs.len();
        let b = seg.bounds();
        self.segs.push_back(seg);
        self.lines.push_back(line);
        if self.levels.is_empty() {
            self.levels.push(Level {
                first: idx / LEAF,
                boxes: VecDeque::new(),
            });
        }
        for (l, level) in self.levels.iter_mut().enumerate() {
            let node = idx / (LEAF << l);
            if level.boxes.is_empty() {
                level.first = node;
            }
            while level.first + level.boxes.len() <= node {
                level.boxes.push_back(Aabb::EMPTY);
            }
            let slot = &mut level.boxes[node - level.first];
            *slot = slot.union(&b);
        }
        while let Some(top) = self.levels.last().filter(|t| t.boxes.len() > 2) {
            let first = top.first / 2;
            let mut boxes = VecDeque::new();
            for (i, bx) in top.boxes.iter().enumerate() {
                let parent = (top.first + i) / 2 - first;
                if parent == boxes.len() {
                    boxes.push_back(Aabb::EMPTY);
                }
                boxes[parent] = boxes[parent].union(bx);
            }
            self.levels.push(Level { first, boxes });
        }
    }

    /// Drops the segments before absolute index `keep`.
    fn drop_before(&mut self, keep: usize) {
        while self.base < keep && !self.segs.is_empty() {
            self.segs.pop_front();
            self.lines.pop_front();
            self.base += 1;
        }
        for (l, level) in self.levels.iter_mut().enumerate() {
            let size = LEAF << l;
            while !level.boxes.is_empty() && (level.first + 1) * size <= self.base {
                level.boxes.pop_front();
                level.first += 1;
            }
        }
    }

    /// Lowers `best` (and moves `at`) to the nearest segment outside `skip` when one is
    /// nearer; visits only boxes nearer than `best`. Returns the segment distances computed.
    fn improve(
        &self,
        p: [f64; 3],
        skip: std::ops::Range<usize>,
        best: &mut f64,
        at: &mut usize,
        stack: &mut Vec<(usize, usize)>,
    ) -> usize {
        let mut evals = 0;
        stack.clear();
        let Some(top) = self.levels.len().checked_sub(1) else {
            return 0;
        };
        let node = |l: usize, i: usize| {
            let level = &self.levels[l];
            i.checked_sub(level.first)
                .and_then(|k| level.boxes.get(k))
                .map_or(f64::INFINITY, |b| b.distance(p))
        };
        let push_nearer_last =
            |stack: &mut Vec<(usize, usize)>, l: usize, mut kids: [(usize, f64); 2], best: f64| {
                // The nearer one is searched first (pushed last).
                kids.sort_by(|a, b| b.1.total_cmp(&a.1));
                for (c, d) in kids {
                    if d < best {
                        stack.push((l, c));
                    }
                }
            };
        let t = &self.levels[top];
        let kids = [t.first, t.first + 1].map(|i| (i, node(top, i)));
        push_nearer_last(stack, top, kids, *best);
        let end = self.base + self.segs.len();
        while let Some((l, i)) = stack.pop() {
            if node(l, i) >= *best {
                continue;
            }
            if l == 0 {
                let (from, to) = ((i * LEAF).max(self.base), ((i + 1) * LEAF).min(end));
                for s in from..to.max(from) {
                    if skip.contains(&s) {
                        continue;
                    }
                    evals += 1;
                    let d = self.segs[s - self.base].distance(p, *best);
                    if d < *best {
                        (*best, *at) = (d, s);
                    }
                }
                continue;
            }
            let kids = [2 * i, 2 * i + 1].map(|c| (c, node(l - 1, c)));
            push_nearer_last(stack, l - 1, kids, *best);
        }
        evals
    }
}

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// A motion block's geometry, ready for distances.
#[derive(Debug, Clone, Copy)]
enum Seg {
    Line { a: [f64; 3], d: [f64; 3], len2: f64 },
    Arc(ArcGeom),
}

impl Seg {
    fn new(b: &Block) -> Option<Seg> {
        match *b {
            Block::Line { start, end, .. } => {
                let d = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
                let len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                Some(Seg::Line { a: start, d, len2 })
            }
            Block::Arc { .. } | Block::ArcNormal { .. } => b.arc_geom().map(Seg::Arc),
            _ => None,
        }
    }

    /// A box holding the whole segment.
    fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        match self {
            Seg::Line { a, d, .. } => {
                b.add(*a);
                b.add([a[0] + d[0], a[1] + d[1], a[2] + d[2]]);
            }
            Seg::Arc(g) => {
                b.add(g.point(0.0));
                b.add(g.point(1.0));
                // Each axis's coordinate is the circle's, r·(cos θ·u + sin θ·v), plus the
                // rise's share: the box holds the circle's extremes on each axis that the arc
                // passes and its ends' angles, each at the start's height and risen by the whole
                // rise.
                let mut angles = vec![0.0, g.sweep];
                for i in 0..3 {
                    let phi = g.v[i].atan2(g.u[i]);
                    for alpha in [phi, phi + PI] {
                        if alpha.rem_euclid(TAU) <= g.sweep {
                            angles.push(alpha);
                        }
                    }
                }
                for th in angles {
                    let (sn, cs) = th.sin_cos();
                    let q: [f64; 3] = std::array::from_fn(|i| {
                        g.centre[i] + g.radius * (cs * g.u[i] + sn * g.v[i])
                    });
                    b.add(q);
                    b.add(std::array::from_fn(|i| q[i] + g.rise * g.axis[i]));
                }
                // Rounding of the angle tests: a hair of margin.
                let m = 1e-9 * (1.0 + g.radius);
                for i in 0..3 {
                    b.lo[i] -= m;
                    b.hi[i] += m;
                }
            }
        }
        b
    }

    /// The distance from `p`; any value ≥ `best` when it cannot be less than `best`.
    fn distance(&self, p: [f64; 3], best: f64) -> f64 {
        match self {
            Seg::Line { a, d, len2 } => {
                let w = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
                let t = if *len2 > 0.0 {
                    ((w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                dist(p, [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]])
            }
            Seg::Arc(g) => arc_distance(g, p, best),
        }
    }
}

fn arc_distance(g: &ArcGeom, p: [f64; 3], best: f64) -> f64 {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let w = [p[0] - g.centre[0], p[1] - g.centre[1], p[2] - g.centre[2]];
    // In the arc's frame: (x, y) in its plane from the start's direction, z its height.
    let q = [dot(w, g.u), dot(w, g.v)];
    let rho = q[0].hypot(q[1]);
    let z = dot(w, g.axis);
    let (n0, n1) = (0.0f64, g.rise);
    let (nlo, nhi) = (n0.min(n1), n0.max(n1));
    let dz_range = (nlo - z).max(z - nhi).max(0.0);
    // No point of the arc is nearer than this.
    let lower = (rho - g.radius).hypot(dz_range);
    if lower >= best {
        return f64::INFINITY;
    }
    if g.rise == 0.0 {
        // A plane circle: the nearest point of the whole circle is at the point's angle.
        if rho == 0.0 {
            return g.radius.hypot(z);
        }
        let along = q[1].atan2(q[0]).rem_euclid(TAU);
        if along <= g.sweep {
            return (rho - g.radius).hypot(z);
        }
        return dist(p, g.point(0.0)).min(dist(p, g.point(1.0)));
    }
    // A helix: only where its height is within `best` of the point's can it beat `best`.
    let dn = n1 - n0;
    let (mut t0, mut t1) = if best.is_finite() {
        let (u, v) = ((z - best - n0) / dn, (z + best - n0) / dn);
        (u.min(v).max(0.0), u.max(v).min(1.0))
    } else {
        (0.0, 1.0)
    };
    if t0 > t1 {
        return f64::INFINITY;
    }
    let d2 = |t: f64| {
        let th = t * g.sweep;
        let e = [
            q[0] - g.radius * th.cos(),
            q[1] - g.radius * th.sin(),
            z - (n0 + t * dn),
        ];
        e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    };
    let samples = ((t1 - t0) * g.sweep / TAU * HELIX_SAMPLES_PER_TURN)
        .ceil()
        .clamp(4.0, 1e5) as usize;
    let h = (t1 - t0) / samples as f64;
    let (mut tb, mut fb) = (t0, d2(t0));
    for i in 1..=samples {
        let t = if i == samples { t1 } else { t0 + i as f64 * h };
        let f = d2(t);
        if f < fb {
            (tb, fb) = (t, f);
        }
    }
    // Golden-section search around the best sample.
    (t0, t1) = ((tb - h).max(t0), (tb + h).min(t1));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (t1 - r * (t1 - t0), t0 + r * (t1 - t0));
    let (mut f1, mut f2) = (d2(x1), d2(x2));
    for _ in 0..60 {
        if f1 < f2 {
            (t1, x2, f2) = (x2, x1, f1);
            x1 = t1 - r * (t1 - t0);
            f1 = d2(x1);
        } else {
            (t0, x1, f1) = (x1, x2, f2);
            x2 = t0 + r * (t1 - t0);
            f2 = d2(x2);
        }
    }
    fb.min(f1).min(f2).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

    const LIM: [AxisLimits; 3] = [AxisLimits {
        vmax: 100.0,
        amax: 1000.0,
        jmax: 1e5,
    }; 3];

    fn program(text: &str) -> Vec<Block> {
        parse(text).unwrap().blocks
    }

    /// Points every `step` mm along a polyline-and-arc description, plus its corners.
    fn push_line(pts: &mut Vec<[f64; 3]>, a: [f64; 2], b: [f64; 2], step: f64) {
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let m = (len / step).ceil() as usize;
        for i in 1..=m {
            let t = i as f64 / m as f64;
            pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0]);
        }
    }

    #[test]
    fn rounded_square_deviation_is_the_fillet_sag() {
        let blocks = program("G1 X50 F3000\nY50\nX0\nY0\n");
        let rho = 2.0;
        let mut pts = vec![[0.0; 3]];
        let mut at = [0.0, 0.0];
        // Corners (50,0), (50,50), (0,50) rounded by fillets of radius rho, tangent to both
        // edges; fillet k turns from angle θk to θk + π/2 about its centre.
        let fillets = [
            ([50.0 - rho, rho], -FRAC_PI_2),
            ([50.0 - rho, 50.0 - rho], 0.0),
            ([rho, 50.0 - rho], FRAC_PI_2),
        ];
        for (c, th) in fillets {
            let s = [c[0] + rho * f64::cos(th), c[1] + rho * f64::sin(th)];
            push_line(&mut pts, at, s, 0.05);
            let m = 64; // even: the fillet's midpoint is a sample
            for i in 1..=m {
                let a = th + FRAC_PI_2 * i as f64 / m as f64;
                pts.push([c[0] + rho * a.cos(), c[1] + rho * a.sin(), 0.0]);
            }
            at = [
                c[0] + rho * f64::cos(th + FRAC_PI_2),
                c[1] + rho * f64::sin(th + FRAC_PI_2),
            ];
        }
        push_line(&mut pts, at, [0.0, 0.0], 0.05);
        let r = analyse(&blocks, &pts, 1e-3, &LIM).unwrap();
        let sag = rho * (1.0 - FRAC_1_SQRT_2);
        assert!((r.max_deviation - sag).abs() < 1e-12, "{r:?} vs {sag}");
        assert_eq!(r.segments, 4);
        assert_eq!(r.exact_stops, 0);
        assert!((r.path_time - (pts.len() - 1) as f64 * 1e-3).abs() < 1e-12);
        // The sharp square itself deviates by nothing.
        let mut sharp = vec![[0.0; 3]];
        for (a, b) in [([0.0, 0.0], [50.0, 0.0]), ([50.0, 0.0], [50.0, 50.0])] {
            push_line(&mut sharp, a, b, 0.05);
        }
        let r = analyse(&blocks, &sharp, 1e-3, &LIM).unwrap();
        assert!(r.max_deviation < 1e-12, "{r:?}");
    }

    #[test]
    fn cubic_motion_gives_the_exact_jerk_ratio() {
        let (ts, j, k_end) = (1e-3, 2000.0, 400usize);
        let y = |k: usize| j * (k as f64 * ts).powi(3) / 6.0;
        let pts: Vec<[f64; 3]> = (0..=k_end).map(|k| [0.0, y(k), 0.0]).collect();
        let blocks = program(&format!("G1 Y{} F60", y(k_end)));
        let mut lim = LIM;
        lim[1] = AxisLimits {
            vmax: 50.0,
            amax: 500.0,
            jmax: 8000.0,
        };
        let r = analyse(&blocks, &pts, ts, &lim).unwrap();
        let kf = k_end as f64;
        let v = j * ts * ts * (3.0 * kf * kf - 3.0 * kf + 1.0) / 6.0;
        let a = j * (kf - 1.0) * ts;
        assert!((r.peak_jerk_ratio - j / 8000.0).abs() < 1e-6, "{r:?}");
        assert!((r.peak_accel_ratio - a / 500.0).abs() < 1e-9, "{r:?}");
        assert!((r.peak_vel_ratio - v / 50.0).abs() < 1e-9, "{r:?}");
        assert!(r.max_deviation < 1e-12);
        assert!((r.path_time - kf * ts).abs() < 1e-12);
        assert_eq!(r.exact_stops, 0);
    }

    #[test]
    fn two_stops_between_three_moves() {
        let blocks = program("G1 X10 F600\nG4 P0.005\nX20\nX30\n");
        let mut pts = vec![[0.0; 3]; 4]; // initial rest
        let mut x = 0.0;
        let mut go = |pts: &mut Vec<[f64; 3]>, to: f64, rest: usize| {
            for i in 1..=100 {
                pts.push([x + (to - x) * i as f64 / 100.0, 0.0, 0.0]);
            }
            x = to;
            pts.extend(std::iter::repeat_n([x, 0.0, 0.0], rest));
        };
        go(&mut pts, 10.0, 5); // the programmed dwell: counts
        go(&mut pts, 20.0, 3);
        go(&mut pts, 30.0, 6); // final rest: does not count
        let r = analyse(&blocks, &pts, 1e-3, &LIM).unwrap();
        assert_eq!(r.exact_stops, 2);
        assert!(
            (r.path_time - (300 + 5 + 3) as f64 * 1e-3).abs() < 1e-12,
            "{r:?}"
        );
        assert_eq!(r.segments, 3);
        assert!(r.max_deviation < 1e-12);
        assert_eq!(
            (r.ticks, r.ticks_seen),
            (pts.len() as u64, pts.len() as u64)
        );
    }

    #[test]
    fn sampled_ticks_give_peaks_from_consecutive_ticks_only() {
        // x = t² (a = 2 mm/s²) sampled at ticks 0, 1, 2, then 10, 11, 12 (ticks 3..9 missed):
        // the differences across the gap (a "velocity" of 7 ticks' travel over one tick)
        // must not count.
        let ts = 1e-3;
        let x = |k: u64| (k as f64 * ts).powi(2) * 1e3; // mm, a = 2000 mm/s²
        let blocks = program("G1 X10 F600");
        let mut r = Report::new(ts, &LIM, REST_SPEED).unwrap();
        for b in &blocks {
            r.add_block(b);
        }
        for k in [0, 1, 2, 10, 11, 12] {
            r.push_at(1000 + k, [x(k), 0.0, 0.0]).unwrap();
        }
        let f = r.finish().unwrap();
        // The fastest seen over one tick: ticks 11 → 12, (x(12) − x(11))/ts = 23 mm/s.
        let v = (x(12) - x(11)) / ts;
        assert!((f.peak_vel_ratio - v / 100.0).abs() < 1e-12, "{f:?}");
        assert!((f.peak_accel_ratio - 2000.0 / 1000.0).abs() < 1e-6, "{f:?}");
        assert_eq!((f.ticks, f.ticks_seen), (13, 6));
        // Moving from tick 1 (the first difference) to tick 12.
        assert!((f.path_time - 12.0 * ts).abs() < 1e-15, "{f:?}");
        assert_eq!(f.exact_stops, 0);
        // A tick not after the last: refused, nothing counted.
        assert_eq!(
            r.push_at(1012, [1.0, 0.0, 0.0]),
            Err(ReportError::TickOrder {
                tick: 1012,
                last: 1012
            })
        );
        assert_eq!(r.finish().unwrap(), f);
    }

    #[test]
    fn actual_points_give_the_following_and_the_contour_error() {
        // The commanded point on the X axis line; the actual one 0.003 behind and 0.004 to
        // the side: following error 0.005, contour error 0.004.
        let blocks = program("G1 X10 F600");
        let mut r = Report::new(1e-3, &LIM, REST_SPEED).unwrap();
        // Before any block or point: not measured.
        assert_eq!(r.push_actual([5.0, 5.0, 0.0]), Ok(()));
        for b in &blocks {
            r.add_block(b);
        }
        for k in 0..=100 {
            let x = k as f64 * 0.1;
            r.push([x, 0.0, 0.0]).unwrap();
            let side = if k == 50 { 0.004 } else { 0.0 };
            r.push_actual([(x - 0.003).max(0.0), side, 0.0]).unwrap();
        }
        let f = r.finish().unwrap();
        assert!((f.max_following_error - 0.005).abs() < 1e-12, "{f:?}");
        assert!((f.max_contour_error - 0.004).abs() < 1e-12, "{f:?}");
        assert!(f.max_deviation < 1e-12);
        assert_eq!(
            r.push_actual([f64::NAN, 0.0, 0.0]),
            Err(ReportError::NonFinitePoint(101))
        );
    }

    #[test]
    fn points_off_an_arc_and_a_helix() {
        let blocks = program("G0 X10\nG3 X0 Y10 I-10 F600\nG0 X30 Y0\nG2 X30 Y0 Z-6 I-5\n");
        let arc = &blocks[1];
        let c45 = FRAC_1_SQRT_2;
        let cases = [
            ([10.5 * c45, 10.5 * c45, 0.0], 0.5),
            ([5.0, 5.0, 0.0], 10.0 - 50f64.sqrt()),
            ([8.0, 6.0, 2.0], 2.0),
            ([-1.0, 10.0, 0.0], 1.0), // past the end: the end point
            ([10.0, -3.0, 4.0], 5.0), // before the start: the start point
            ([0.0, 0.0, 0.0], 10.0),  // the centre
            ([-10.0, -0.0, 0.0], 200f64.sqrt()), // opposite the arc: nearest an end
        ];
        for (p, d) in cases {
            let got = distance_to_block(arc, p).unwrap();
            assert!((got - d).abs() < 1e-12, "{p:?}: {got} vs {d}");
        }
        // The report: one point 0.5 off the arc's middle (the first rapid is farther; the
        // second passes about 0.1 mm from it, so it is left out).
        let r = analyse(&blocks[..2], &[cases[0].0], 1e-3, &LIM).unwrap();
        assert!((r.max_deviation - 0.5).abs() < 1e-12);
        let r = analyse(&blocks, &[cases[0].0], 1e-3, &LIM).unwrap();
        let off_rapid = (4.0 * 10.5 * c45 - 30.0).abs() / 10f64.sqrt(); // line x + 3y = 30
        assert!((r.max_deviation - off_rapid).abs() < 1e-12, "{r:?}");
        // The helix: a full cw turn of radius 5 about (25, 0) going down 6 mm. A point 0.3
        // outside it at the height of its angle is 0.3 away (nothing on the helix is nearer
        // than |ρ − r|).
        let helix = &blocks[3];
        for t in [0.1, 0.37, 0.5, 0.93] {
            let th = -TAU * t; // cw from angle 0
            let p = [25.0 + 5.3 * th.cos(), 5.3 * th.sin(), -6.0 * t];
            let got = distance_to_block(helix, p).unwrap();
            assert!((got - 0.3).abs() < 1e-9, "t {t}: {got}");
            assert!(
                dist(
                    helix.point_at(t).unwrap(),
                    [p[0] - 0.3 * th.cos(), p[1] - 0.3 * th.sin(), p[2]]
                ) < 1e-9
            );
        }
        // Above the top end, on the axis of the start: straight down to the start.
        let got = distance_to_block(helix, [30.0, 0.0, 2.0]).unwrap();
        assert!((got - 2.0).abs() < 1e-9, "{got}");
        // On the axis: the radius and the height difference to the nearest height.
        let got = distance_to_block(helix, [25.0, 0.0, -3.0]).unwrap();
        assert!((got - 5.0).abs() < 1e-9, "{got}");
        assert_eq!(
            distance_to_block(
                &Block::Dwell {
                    line: 1,
                    seconds: 1.0
                },
                [0.0; 3]
            ),
            None
        );
    }

    /// A G18 helix in a coordinate system rotated 30° about Z is an arc about the rotated Y
    /// (a [`Block::ArcNormal`]): every point's distance to it is the distance of the point
    /// turned back to the same helix unrotated (a plane arc), and its bounding box holds
    /// every point of it and is no more than the rise wider on any side.
    #[test]
    fn an_oblique_helix_measures_as_the_plane_helix_turned() {
        // from Z30 X0 about Z25 X0: a full clockwise turn in (Z, X), Y falling 6 mm
        let body = "G0 Z30\nG18 G2 Z30 X0 Y-6 K-5 F600\n";
        let plain = program(body)[1];
        let turned = program(&format!("G10 L2 P1 R30\n{body}"))[1];
        assert!(matches!(plain, Block::Arc { .. }), "{plain:?}");
        assert!(matches!(turned, Block::ArcNormal { .. }), "{turned:?}");
        let (s, c) = 30f64.to_radians().sin_cos();
        let turn = |p: [f64; 3]| [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
        assert!((plain.length() - turned.length()).abs() < 1e-12);
        assert!((turned.length() - (10.0 * PI).hypot(6.0)).abs() < 1e-12);
        let mut worst = 0.0f64;
        for k in 0..40 {
            let t = k as f64 / 39.0;
            let q = plain.point_at(t).unwrap();
            for (dx, dy, dz) in [(0.3, 0.0, 0.0), (0.0, -0.7, 0.2), (-2.0, 1.5, 3.0)] {
                let p = [q[0] + dx, q[1] + dy, q[2] + dz];
                let a = distance_to_block(&plain, p).unwrap();
                let b = distance_to_block(&turned, turn(p)).unwrap();
                worst = worst.max((a - b).abs());
            }
            let d = dist(turned.point_at(t).unwrap(), turn(q));
            assert!(d < 1e-12, "t {t}: {d}");
        }
        assert!(worst < 1e-9, "{worst}");
        let bx = Seg::new(&turned).unwrap().bounds();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for k in 0..=4000 {
            let p = turned.point_at(k as f64 / 4000.0).unwrap();
            for i in 0..3 {
                assert!(bx.lo[i] <= p[i] && p[i] <= bx.hi[i], "{p:?} outside {bx:?}");
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        for i in 0..3 {
            // (conservative by at most the rise on each axis)
            assert!(lo[i] - bx.lo[i] <= 6.0 + 1e-6 && bx.hi[i] - hi[i] <= 6.0 + 1e-6);
        }
    }

    /// Every point's distance to the path of `blocks` (all held, nothing dropped); returns
    /// the segment distances computed.
    fn deviations(blocks: &[Block], pts: &[[f64; 3]], mut f: impl FnMut(usize, f64)) -> usize {
        let mut r = Report::new(1e-3, &LIM, REST_SPEED).unwrap();
        r.behind = usize::MAX;
        for b in blocks {
            r.add_block(b);
        }
        for (k, &p) in pts.iter().enumerate() {
            f(k, r.measure(p));
        }
        r.evals
    }

    /// The brute force: every segment for every point.
    fn brute(segs: &[Seg], p: [f64; 3]) -> f64 {
        segs.iter()
            .map(|s| s.distance(p, f64::INFINITY))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn window_matches_brute_force_with_jumps_and_revisits() {
        // A zigzag of short blocks and a helix, walked by points that follow it with an
        // offset, jump 300 blocks ahead, then come back over blocks already passed.
        let mut text = String::from("G1 F600\n");
        for i in 0..600 {
            text += &format!(
                "X{} Y{}\n",
                i as f64 * 0.5,
                if i % 2 == 0 { 0.0 } else { 3.0 }
            );
        }
        text += "G2 X299.5 Y-7 Z-4 I0 J-5\nG0 X0 Y0 Z0\n";
        let blocks = program(&text);
        let segs: Vec<Seg> = blocks.iter().filter_map(Seg::new).collect();
        let mut pts = Vec::new();
        for b in blocks.iter().take(100) {
            for i in 0..10 {
                let q = b.point_at(i as f64 / 10.0).unwrap();
                pts.push([q[0] + 0.01 * i as f64, q[1] - 0.02, q[2] + 0.03]);
            }
        }
        for b in blocks[400..420]
            .iter()
            .chain(&blocks[50..60])
            .chain(&blocks[598..])
        {
            for i in 0..50 {
                let q = b.point_at(i as f64 / 50.0).unwrap();
                pts.push([q[0], q[1] + 0.2, q[2] - 0.1]);
            }
        }
        let mut got = vec![0.0; pts.len()];
        deviations(&blocks, &pts, |k, d| got[k] = d);
        for (k, p) in pts.iter().enumerate() {
            let want = brute(&segs, *p);
            assert!(
                (got[k] - want).abs() < 1e-9,
                "point {k} {p:?}: {} vs {want}",
                got[k]
            );
        }
    }

    #[test]
    fn ten_thousand_blocks_and_two_hundred_thousand_ticks_stay_in_the_window() {
        let mut text = String::from("G1 F6000\n");
        for i in 1..=10_000 {
            let x = i as f64;
            if i % 500 == 0 {
                text += &format!("G2 X{x} Y0 I0.5 J-0.5\nG1\n");
            } else {
                text += &format!("X{x} Y{}\n", if i % 2 == 0 { 0.0 } else { 1.0 });
            }
        }
        let blocks = program(&text);
        let segs: Vec<Seg> = blocks.iter().filter_map(Seg::new).collect();
        assert_eq!(segs.len(), 10_000);
        let per = 20;
        let pts: Vec<[f64; 3]> = blocks
            .iter()
            .flat_map(|b| (0..per).map(move |i| b.point_at(i as f64 / per as f64).unwrap()))
            .map(|q| [q[0], q[1], q[2] + 0.001])
            .collect();
        assert_eq!(pts.len(), 200_000);
        let mut worst = 0.0f64;
        let evals = deviations(&blocks, &pts, |_, d| worst = worst.max(d));
        // The first point scans everything; the others stay within the 11-segment window.
        eprintln!("{evals} segment distances for {} points", pts.len());
        assert!(
            evals <= segs.len() + 11 * pts.len(),
            "{evals} distance evaluations"
        );
        assert!((worst - 0.001).abs() < 1e-9, "{worst}");
    }

    /// Chords of a spiral (radius 50 mm growing 0.5 µm a chord, 1 mrad a chord: about
    /// 50 µm long), `n` of them from `from`.
    fn spiral(from: usize, n: usize) -> impl Iterator<Item = Block> {
        let at = |i: usize| {
            let (th, r) = (i as f64 * 1e-3, 50.0 + 5e-4 * i as f64);
            [r * th.cos(), r * th.sin(), 0.0]
        };
        (from..from + n).map(move |i| Block::Line {
            line: i + 1,
            rapid: false,
            start: at(i),
            end: at(i + 1),
            feed: 10.0,
        })
    }

    /// A run as `mcctl run` feeds it: 200,000 chords (32 turns) added at most 4096 ahead of
    /// the one the points are on, four points a chord. The report holds a window of the
    /// path that does not grow with the run (the old one held every point and every block),
    /// and its figures are those of the whole program held.
    #[test]
    fn a_long_run_holds_a_bounded_window_and_the_same_figures() {
        let (n, per, ahead) = (200_000, 4, 4096);
        let offset = 2e-3;
        let points = |i: usize| {
            let b = spiral(i, 1).next().unwrap();
            (0..per).map(move |k| {
                let q = b.point_at(k as f64 / per as f64).unwrap();
                // Outwards: the spiral's turns are 3 mm apart.
                let r = q[0].hypot(q[1]);
                [q[0] * (1.0 + offset / r), q[1] * (1.0 + offset / r), 0.0]
            })
        };
        let mut r = Report::new(1e-4, &LIM, REST_SPEED).unwrap();
        let mut blocks = spiral(0, n);
        let mut added = 0;
        let mut most = 0;
        for i in 0..n {
            while added < n && added < i + ahead {
                r.add_block(&blocks.next().unwrap());
                added += 1;
            }
            for p in points(i) {
                r.push(p).unwrap();
            }
            most = most.max(r.held_segments());
        }
        assert!(most <= WINDOW_BEHIND + ahead + 11, "{most} segments held");
        assert!(r.path.levels.len() <= 12, "{} levels", r.path.levels.len());
        let boxes: usize = r.path.levels.iter().map(|l| l.boxes.len()).sum();
        assert!(boxes <= 2 * (WINDOW_BEHIND + ahead) / LEAF, "{boxes} boxes");
        // About the 11 window segments a point, and a few more near the boxes' edges.
        assert!(r.evals <= 13 * per * n, "{} distances", r.evals);
        let streamed = r.finish().unwrap();
        assert!(
            (streamed.max_deviation - offset).abs() < 1e-6,
            "{streamed:?}"
        );
        // The whole program held, every point at once: the same figures to the bit.
        let all: Vec<Block> = spiral(0, n).collect();
        let pts: Vec<[f64; 3]> = (0..n).flat_map(points).collect();
        let whole = analyse(&all, &pts, 1e-4, &LIM).unwrap();
        assert_eq!(streamed, whole);
        assert_eq!(streamed.segments, n);
    }

    /// Blocks added far ahead of the card (as the chord fitter makes a run add them) on a
    /// path that comes back through where the card is: a line, and 20,000 later chords of a
    /// circle that passes through the points run 1 µm off the line. At that point the nearest segment is the circle's
    /// last chord, and the window dropped the line the card was on: the rest of the line
    /// measured 6 mm from the circle. Told the line the card runs, the window keeps it.
    #[test]
    fn blocks_far_ahead_on_a_path_that_comes_back_keep_the_running_segment() {
        let mut text = String::from("G1 X-10 Y0 F600\n");
        for i in 1..=200 {
            text += &format!("X{:.3} Y0\n", -10.0 + 0.1 * i as f64);
        }
        // (the circle of radius 5 about (0, 5.001) passes 1 µm above the origin, through the
        // points, which run 1 µm above the line)
        text += "X0 Y0.001\n";
        for i in 1..=20_000 {
            let a = i as f64 * 0.05;
            text += &format!("X{:.6} Y{:.6}\n", 5.0 * a.sin(), 5.001 - 5.0 * a.cos());
        }
        let blocks = program(&text);
        let run = |tell: bool| {
            let mut r = Report::new(1e-3, &LIM, REST_SPEED).unwrap();
            for b in &blocks {
                r.add_block(b);
            }
            // along the line, its chords' source lines 2..=201
            for (k, b) in blocks[1..201].iter().enumerate() {
                if tell {
                    r.running(b.line());
                }
                for j in 0..10 {
                    r.push([-10.0 + 0.1 * k as f64 + 0.01 * j as f64, 0.001, 0.0])
                        .unwrap();
                }
            }
            r.finish().unwrap().max_deviation
        };
        assert!(
            run(false) > 5.0,
            "the window did not drop the line: {}",
            run(false)
        );
        assert!((run(true) - 0.001).abs() < 1e-9, "{}", run(true));
    }

    /// Points before the first motion block are measured when it arrives; a run of stops
    /// and moves counted as it goes, as over the whole list.
    #[test]
    fn points_before_the_first_block_and_stops_as_they_come() {
        let blocks = program("G1 X10 F600\nG4 P0.005\nX20\n");
        let mut r = Report::new(1e-3, &LIM, REST_SPEED).unwrap();
        let mut pts = vec![[0.0, 0.5, 0.0]; 3];
        pts.extend((1..=10).map(|i| [i as f64, 0.0, 0.0]));
        pts.extend([[10.0, 0.0, 0.0]; 4]);
        pts.extend((11..=20).map(|i| [i as f64, 0.0, 0.0]));
        for p in &pts[..3] {
            r.push(*p).unwrap();
        }
        assert_eq!(r.pending.len(), 1);
        for b in &blocks {
            r.add_block(b);
        }
        for p in &pts[3..] {
            r.push(*p).unwrap();
        }
        let got = r.finish().unwrap();
        assert_eq!(got, analyse(&blocks, &pts, 1e-3, &LIM).unwrap());
        assert_eq!(got.exact_stops, 1);
        assert!((got.max_deviation - 0.5).abs() < 1e-12);
        assert_eq!(
            r.push([f64::NAN, 0.0, 0.0]),
            Err(ReportError::NonFinitePoint(pts.len()))
        );
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let blocks = program("G1 X1 F60");
        let p = [[0.0; 3]];
        assert_eq!(
            analyse(&blocks, &p, 0.0, &LIM),
            Err(ReportError::BadPeriod(0.0))
        );
        let mut lim = LIM;
        lim[2].jmax = f64::NAN;
        assert!(matches!(
            analyse(&blocks, &p, 1e-3, &lim),
            Err(ReportError::BadLimit {
                axis: 2,
                what: "jerk",
                ..
            })
        ));
        assert_eq!(
            analyse(&blocks, &[[0.0, f64::NAN, 0.0]], 1e-3, &LIM),
            Err(ReportError::NonFinitePoint(0))
        );
        assert_eq!(analyse(&[], &p, 1e-3, &LIM), Err(ReportError::NoMotion));
        let empty = analyse(&blocks, &[], 1e-3, &LIM).unwrap();
        assert_eq!(
            (empty.path_time, empty.max_deviation, empty.exact_stops),
            (0.0, 0.0, 0)
        );
    }
}
