//! What a run of a program did, measured from the commanded positions alone.
//!
//! [`analyse`] takes the program's blocks (the programmed geometry, from
//! [`crate::gcode::parse`]), the commanded axis positions of every servo tick (mm, program
//! coordinates), the servo period and each axis's limits, and reports:
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
//!   (the union of all lines, arcs and helices, rapids included), in mm. Lines and circles
//!   are exact; a helix is sampled (32 samples a turn, over the part of it close enough in
//!   height) and the best sample refined by golden-section search.
//! - `exact_stops`: the number of maximal runs of non-moving ticks strictly between the first
//!   and the last moving tick: the initial and the final rests are not counted. **Programmed
//!   dwells count** (a G4 is a rest like any other: this report looks only at the motion);
//!   subtract the program's `Dwell` blocks that fall between moves if only the planner's
//!   stops are wanted.
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

use crate::gcode::{ArcGeom, Block};
use std::f64::consts::TAU;
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
    pub vmax: f64,
    pub amax: f64,
    pub jmax: f64,
}

/// See the [module documentation](self) for every field's definition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathReport {
    /// s.
    pub path_time: f64,
    pub segments: usize,
    pub peak_vel_ratio: f64,
    pub peak_accel_ratio: f64,
    pub peak_jerk_ratio: f64,
    /// mm.
    pub max_deviation: f64,
    pub exact_stops: usize,
}

impl PathReport {
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "path_time": self.path_time,
            "segments": self.segments,
            "peak_vel_ratio": self.peak_vel_ratio,
            "peak_accel_ratio": self.peak_accel_ratio,
            "peak_jerk_ratio": self.peak_jerk_ratio,
            "max_deviation": self.max_deviation,
            "exact_stops": self.exact_stops,
        })
    }
}

/// Why no report could be made.
#[derive(Debug, Clone, PartialEq)]
pub enum ReportError {
    /// The servo period is not a positive finite number.
    BadPeriod(f64),
    /// A limit is not positive (an infinite one is allowed: its ratio is 0).
    BadLimit {
        axis: usize,
        what: &'static str,
        value: f64,
    },
    /// The rest speed is negative or NaN.
    BadRestSpeed(f64),
    /// A commanded position is not finite.
    NonFinitePoint(usize),
    /// There are positions but the program has no motion block to measure them against.
    NoMotion,
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
/// positions quantised to encoder counts).
pub fn analyse_with_rest_speed(
    blocks: &[Block],
    points: &[[f64; 3]],
    ts: f64,
    limits: &[AxisLimits; 3],
    rest_speed: f64,
) -> Result<PathReport, ReportError> {
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
    if let Some(k) = points.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return Err(ReportError::NonFinitePoint(k));
    }
    let segs: Vec<Seg> = blocks.iter().filter_map(Seg::new).collect();
    if segs.is_empty() && !points.is_empty() {
        return Err(ReportError::NoMotion);
    }
    let (peak_vel_ratio, peak_accel_ratio, peak_jerk_ratio) = peaks(points, ts, limits);
    let (path_time, exact_stops) = motion_and_stops(points, ts, rest_speed);
    let mut max_deviation = 0.0f64;
    deviations(&segs, points, |_, d| max_deviation = max_deviation.max(d));
    Ok(PathReport {
        path_time,
        segments: segs.len(),
        peak_vel_ratio,
        peak_accel_ratio,
        peak_jerk_ratio,
        max_deviation,
        exact_stops,
    })
}

/// The distance (mm) from `p` to a motion block; `None` for a dwell or an output.
pub fn distance_to_block(block: &Block, p: [f64; 3]) -> Option<f64> {
    Seg::new(block).map(|s| s.distance(p, f64::INFINITY))
}

fn peaks(points: &[[f64; 3]], ts: f64, limits: &[AxisLimits; 3]) -> (f64, f64, f64) {
    let (mut v, mut a, mut j) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
    for k in 1..points.len() {
        for i in 0..3 {
            let p = |m: usize| points[k - m][i];
            v[i] = v[i].max(((p(0) - p(1)) / ts).abs());
            if k >= 2 {
                a[i] = a[i].max(((p(0) - 2.0 * p(1) + p(2)) / (ts * ts)).abs());
            }
            if k >= 3 {
                let d3 = p(0) - 3.0 * p(1) + 3.0 * p(2) - p(3);
                j[i] = j[i].max((d3 / (ts * ts * ts)).abs());
            }
        }
    }
    let worst = |peak: [f64; 3], lim: fn(&AxisLimits) -> f64| {
        (0..3)
            .map(|i| peak[i] / lim(&limits[i]))
            .fold(0.0, f64::max)
    };
    (
        worst(v, |l| l.vmax),
        worst(a, |l| l.amax),
        worst(j, |l| l.jmax),
    )
}

/// (path_time, exact_stops), as the module documentation defines them.
fn motion_and_stops(points: &[[f64; 3]], ts: f64, rest_speed: f64) -> (f64, usize) {
    let moving = |k: usize| dist(points[k], points[k - 1]) / ts >= rest_speed;
    let Some(first) = (1..points.len()).find(|&k| moving(k)) else {
        return (0.0, 0);
    };
    let last = (1..points.len())
        .rev()
        .find(|&k| moving(k))
        .unwrap_or(first);
    let mut stops = 0;
    let mut was_moving = true;
    for k in first + 1..last {
        let m = moving(k);
        if was_moving && !m {
            stops += 1;
        }
        was_moving = m;
    }
    ((last - first + 1) as f64 * ts, stops)
}

/// Calls `f(k, distance)` for every point: the window of the module documentation, then
/// the tree's proof. Returns how many segment distances were computed.
fn deviations(segs: &[Seg], points: &[[f64; 3]], mut f: impl FnMut(usize, f64)) -> usize {
    let tree = Tree::new(segs);
    let mut evals = 0;
    let mut cur = 0usize;
    let mut stack = Vec::new();
    for (k, &p) in points.iter().enumerate() {
        let lo = cur.saturating_sub(WINDOW_BACK);
        let hi = (cur + WINDOW_AHEAD + 1).min(segs.len());
        let (mut best, mut at) = (f64::INFINITY, cur);
        for (i, s) in segs.iter().enumerate().take(hi).skip(lo) {
            evals += 1;
            let d = s.distance(p, best);
            if d <= best {
                (best, at) = (d, i);
            }
        }
        evals += tree.improve(segs, p, lo..hi, &mut best, &mut at, &mut stack);
        cur = at;
        f(k, best);
    }
    evals
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

/// Boxes over contiguous runs of segments: `levels[0][i]` holds segments
/// `i·LEAF .. (i+1)·LEAF`, each level above pairs the boxes below it.
struct Tree {
    levels: Vec<Vec<Aabb>>,
}

const LEAF: usize = 8;

impl Tree {
    fn new(segs: &[Seg]) -> Tree {
        let leaves: Vec<Aabb> = segs
            .chunks(LEAF)
            .map(|c| c.iter().fold(Aabb::EMPTY, |b, s| b.union(&s.bounds())))
            .collect();
        let mut levels = vec![leaves];
        while levels.last().is_some_and(|l| l.len() > 1) {
            let up = levels
                .last()
                .unwrap_or(&Vec::new())
                .chunks(2)
                .map(|c| c.iter().fold(Aabb::EMPTY, |b, x| b.union(x)))
                .collect();
            levels.push(up);
        }
        Tree { levels }
    }

    /// Lowers `best` (and moves `at`) to the nearest segment outside `skip` when one is
    /// nearer; visits only boxes nearer than `best`. Returns the segment distances computed.
    fn improve(
        &self,
        segs: &[Seg],
        p: [f64; 3],
        skip: std::ops::Range<usize>,
        best: &mut f64,
        at: &mut usize,
        stack: &mut Vec<(usize, usize)>,
    ) -> usize {
        let mut evals = 0;
        stack.clear();
        if !self.levels[0].is_empty() {
            stack.push((self.levels.len() - 1, 0));
        }
        while let Some((l, i)) = stack.pop() {
            if self.levels[l][i].distance(p) >= *best {
                continue;
            }
            if l == 0 {
                for (s, seg) in segs.iter().enumerate().skip(i * LEAF).take(LEAF) {
                    if skip.contains(&s) {
                        continue;
                    }
                    evals += 1;
                    let d = seg.distance(p, *best);
                    if d < *best {
                        (*best, *at) = (d, s);
                    }
                }
                continue;
            }
            let below = &self.levels[l - 1];
            let mut kids = [(2 * i, f64::INFINITY), (2 * i + 1, f64::INFINITY)];
            for k in &mut kids {
                if k.0 < below.len() {
                    k.1 = below[k.0].distance(p);
                }
            }
            // The nearer child is searched first (pushed last).
            kids.sort_by(|a, b| b.1.total_cmp(&a.1));
            for (c, d) in kids {
                if d < *best {
                    stack.push((l - 1, c));
                }
            }
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
            Block::Arc { .. } => b.arc_geom().map(Seg::Arc),
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
                let (a, bb, n) = g.axes;
                // The circle's extreme points in a and b that the arc passes.
                for k in 0..4 {
                    let alpha = k as f64 * TAU / 4.0;
                    let along = if g.sweep > 0.0 {
                        (alpha - g.theta0).rem_euclid(TAU)
                    } else {
                        (g.theta0 - alpha).rem_euclid(TAU)
                    };
                    if along <= g.sweep.abs() {
                        let mut q = [0.0; 3];
                        q[a] = g.centre[0] + g.radius * alpha.cos();
                        q[bb] = g.centre[1] + g.radius * alpha.sin();
                        q[n] = g.n0;
                        b.add(q);
                    }
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
    let (a, b, n) = g.axes;
    let q = [p[a] - g.centre[0], p[b] - g.centre[1]];
    let rho = q[0].hypot(q[1]);
    let z = p[n];
    let (nlo, nhi) = (g.n0.min(g.n1), g.n0.max(g.n1));
    let dz_range = (nlo - z).max(z - nhi).max(0.0);
    // No point of the arc is nearer than this.
    let lower = (rho - g.radius).hypot(dz_range);
    if lower >= best {
        return f64::INFINITY;
    }
    if g.n1 == g.n0 {
        // A plane circle: the nearest point of the whole circle is at the point's angle.
        let dz = z - g.n0;
        if rho == 0.0 {
            return g.radius.hypot(dz);
        }
        let phi = q[1].atan2(q[0]);
        let along = if g.sweep > 0.0 {
            (phi - g.theta0).rem_euclid(TAU)
        } else {
            (g.theta0 - phi).rem_euclid(TAU)
        };
        if along <= g.sweep.abs() {
            return (rho - g.radius).hypot(dz);
        }
        return dist(p, g.point(0.0)).min(dist(p, g.point(1.0)));
    }
    // A helix: only where its height is within `best` of the point's can it beat `best`.
    let dn = g.n1 - g.n0;
    let (mut t0, mut t1) = if best.is_finite() {
        let (u, v) = ((z - best - g.n0) / dn, (z + best - g.n0) / dn);
        (u.min(v).max(0.0), u.max(v).min(1.0))
    } else {
        (0.0, 1.0)
    };
    if t0 > t1 {
        return f64::INFINITY;
    }
    let d2 = |t: f64| {
        let th = g.theta0 + t * g.sweep;
        let e = [
            q[0] - g.radius * th.cos(),
            q[1] - g.radius * th.sin(),
            z - (g.n0 + t * dn),
        ];
        e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
    };
    let samples = ((t1 - t0) * g.sweep.abs() / TAU * HELIX_SAMPLES_PER_TURN)
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
    use crate::gcode::parse;
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
        let j = r.to_json();
        assert_eq!(j["exact_stops"], 2);
        assert_eq!(j["segments"], 3);
        assert!(j["path_time"].as_f64().unwrap() > 0.3);
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
        deviations(&segs, &pts, |k, d| got[k] = d);
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
        let evals = deviations(&segs, &pts, |_, d| worst = worst.max(d));
        // The first point scans everything; the others stay within the 11-segment window.
        eprintln!("{evals} segment distances for {} points", pts.len());
        assert!(
            evals <= segs.len() + 11 * pts.len(),
            "{evals} distance evaluations"
        );
        assert!((worst - 0.001).abs() < 1e-9, "{worst}");
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
