use super::*;
use crate::testkit::rng::Rng;

pub(super) const TS: f64 = 1e-3;

/// Three axes of different limits; y is the slow one.
pub(super) fn limits(naxes: usize, ts: f64) -> PathLimits {
    let mut l = PathLimits {
        naxes,
        ts,
        vmax: [1e5; MAX_AXES],
        amax: [1e7; MAX_AXES],
        jmax: [1e9; MAX_AXES],
        accel: 0.0,
        jerk: 0.0,
        plan_ticks: 1,
    };
    l.vmax[1] = 4e4;
    l.amax[1] = 3e6;
    l.jmax[1] = 3e8;
    l.vmax[2] = 6e4;
    l.amax[2] = 5e6;
    l.jmax[2] = 5e8;
    l
}

pub(super) fn pt(xs: &[f64]) -> V {
    let mut p = [0.0; MAX_AXES];
    p[..xs.len()].copy_from_slice(xs);
    p
}

pub(super) fn line(id: u32, end: V, feed: f64, tr: Transition) -> Segment {
    Segment {
        id,
        geom: Geom::Line { end },
        feed,
        transition: tr,
        blend: BlendSpeed::Low,
        last: false,
    }
}

/// A counter-clockwise arc in the (x, y) plane around `centre` to `end` (a helix if `end`
/// moves other axes).
pub(super) fn arc_xy(id: u32, centre: [f64; 2], end: V, feed: f64, tr: Transition) -> Segment {
    Segment {
        id,
        geom: Geom::Arc {
            u: 0,
            v: 1,
            centre,
            ccw: true,
            end,
        },
        feed,
        transition: tr,
        blend: BlendSpeed::Low,
        last: false,
    }
}

/// A random program of `n` segments from the origin (its end returned): short and long
/// lines, small and sharp turns, some exact stops, some dwells, feeds from 5,000 to 100,000
/// counts/s.
pub(super) fn random_program(rng: &mut Rng, naxes: usize, n: u32) -> (Vec<Segment>, V) {
    let mut segs = vec![];
    let mut at = pt(&[0.0; 3][..naxes]);
    for i in 1..=n {
        let mut q = at;
        let len = rng.log_uniform(30.0, 20_000.0);
        for x in q[..naxes].iter_mut() {
            *x += len * rng.uniform(-1.0, 1.0);
        }
        let tr = match rng.int(0, 9) {
            0 => Transition::Exact,
            1 => Transition::CornerDistance(rng.log_uniform(1.0, 500.0)),
            _ => Transition::MaxDeviation(rng.log_uniform(0.5, 100.0)),
        };
        let geom = if rng.chance(0.05) {
            Geom::Dwell {
                time: rng.uniform(1e-3, 2e-2),
            }
        } else {
            at = q;
            Geom::Line { end: q }
        };
        segs.push(Segment {
            id: i,
            geom,
            feed: rng.log_uniform(5e3, 1e5),
            transition: tr,
            blend: BlendSpeed::Low,
            last: i == n,
        });
    }
    (segs, at)
}

pub(super) fn path(naxes: usize, ts: f64, start: V) -> Path {
    path_with(limits(naxes, ts), start)
}

pub(super) fn path_with(lim: PathLimits, start: V) -> Path {
    let mut p = Path::with_capacity(4096);
    p.reset(start, lim, DEFAULT_LOOKAHEAD).unwrap();
    p
}

#[derive(Default)]
pub(super) struct Run {
    pub(super) pos: Vec<V>,
    pub(super) speed: Vec<f64>,
    pub(super) events: Vec<(usize, PathEvent)>,
}

impl Run {
    /// Ticks until Idle (or `max` ticks), with 3 samples of rest before and after.
    pub(super) fn go(&mut self, p: &mut Path, ovr: f64, max: usize) -> bool {
        if self.pos.is_empty() {
            for _ in 0..3 {
                self.pos.push(p.position());
                self.speed.push(0.0);
            }
        }
        for _ in 0..max {
            let k = self.pos.len();
            let mut idle = false;
            let ev = &mut self.events;
            let q = p.tick(ovr, &mut |e| {
                idle |= e == PathEvent::Idle;
                ev.push((k, e));
            });
            self.pos.push(q);
            self.speed.push(p.speed());
            if idle {
                for _ in 0..3 {
                    let q = p.tick(ovr, &mut |e| ev.push((k, e)));
                    self.pos.push(q);
                    self.speed.push(p.speed());
                }
                return true;
            }
        }
        false
    }

    /// Largest ratio of the finite-difference velocity, acceleration and jerk of each axis
    /// to its limit.
    pub(super) fn worst(&self, l: &PathLimits) -> [f64; 3] {
        let mut w = [0.0f64; 3];
        let ts = l.ts;
        for k in 0..l.naxes {
            let x: Vec<f64> = self.pos.iter().map(|p| p[k]).collect();
            for i in 3..x.len() {
                let v = (x[i] - x[i - 1]) / ts;
                let a = (x[i] - 2.0 * x[i - 1] + x[i - 2]) / (ts * ts);
                let j = (x[i] - 3.0 * x[i - 1] + 3.0 * x[i - 2] - x[i - 3]) / (ts * ts * ts);
                w[0] = w[0].max(v.abs() / l.vmax[k]);
                w[1] = w[1].max(a.abs() / l.amax[k]);
                w[2] = w[2].max(j.abs() / l.jmax[k]);
            }
        }
        w
    }

    pub(super) fn assert_within(&self, l: &PathLimits, what: &str) {
        let w = self.worst(l);
        assert!(w.iter().all(|&r| r <= 1.01), "{what}: v, a, j ratios {w:?}");
    }

    pub(super) fn ids(&self) -> (Vec<u32>, Vec<u32>) {
        let mut st = vec![];
        let mut en = vec![];
        for (_, e) in &self.events {
            match e {
                PathEvent::SegmentStart { id } => st.push(*id),
                PathEvent::SegmentEnd { id } => en.push(*id),
                _ => {}
            }
        }
        (st, en)
    }

    /// Ids start and end in order, each once, a start before its end.
    pub(super) fn assert_ids(&self, ids: &[u32]) {
        let (st, en) = self.ids();
        assert_eq!(st, ids, "starts");
        assert_eq!(en, ids, "ends");
        let mut open: Option<u32> = None;
        for (_, e) in &self.events {
            match e {
                PathEvent::SegmentStart { id } => {
                    assert!(open.is_none(), "start {id} while {open:?} open");
                    open = Some(*id);
                }
                PathEvent::SegmentEnd { id } => {
                    assert_eq!(open, Some(*id));
                    open = None;
                }
                _ => {}
            }
        }
    }
}

/// The programmed geometry as the test sees it: polyline vertices and arcs.
enum Piece {
    Line(V, V),
    /// plane arc: centre, radius, start angle, signed sweep (2D only)
    Arc([f64; 2], f64, f64, f64),
}

pub(super) fn dist_seg(p: &V, a: &V, b: &V) -> f64 {
    let ab: Vec<f64> = (0..MAX_AXES).map(|k| b[k] - a[k]).collect();
    let ap: Vec<f64> = (0..MAX_AXES).map(|k| p[k] - a[k]).collect();
    let l2: f64 = ab.iter().map(|x| x * x).sum();
    let t = if l2 > 0.0 {
        (ab.iter().zip(&ap).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..MAX_AXES)
        .map(|k| (ap[k] - t * ab[k]).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn dist_arc(p: &V, c: [f64; 2], r: f64, a0: f64, sw: f64) -> f64 {
    let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
    let ang = dy.atan2(dx);
    // angle from the start along the sweep's direction
    let rel = ((ang - a0) * sw.signum()).rem_euclid(std::f64::consts::TAU);
    if rel <= sw.abs() {
        (dx.hypot(dy) - r).abs()
    } else {
        let e0 = [c[0] + r * a0.cos(), c[1] + r * a0.sin()];
        let e1 = [c[0] + r * (a0 + sw).cos(), c[1] + r * (a0 + sw).sin()];
        (p[0] - e0[0])
            .hypot(p[1] - e0[1])
            .min((p[0] - e1[0]).hypot(p[1] - e1[1]))
    }
}

fn max_deviation(run: &Run, geo: &[Piece]) -> f64 {
    run.pos
        .iter()
        .map(|p| {
            geo.iter()
                .map(|g| match g {
                    Piece::Line(a, b) => dist_seg(p, a, b),
                    Piece::Arc(c, r, a0, sw) => dist_arc(p, *c, *r, *a0, *sw),
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// `max_deviation` for long polylines run in order: each point against the chords near the
/// last nearest one (8 behind, 64 ahead).
pub(super) fn max_deviation_in_order(run: &Run, verts: &[V]) -> f64 {
    let mut at = 0usize;
    let mut worst = 0.0f64;
    for p in &run.pos {
        let lo = at.saturating_sub(8);
        let hi = (at + 64).min(verts.len() - 1);
        let (mut best, mut arg) = (f64::INFINITY, at);
        for j in lo..hi {
            let d = dist_seg(p, &verts[j], &verts[j + 1]);
            if d < best {
                best = d;
                arg = j;
            }
        }
        at = arg;
        worst = worst.max(best);
    }
    worst
}

/// Runs a polyline (from the first vertex) with MaxDeviation(tol): limits, tolerance, ids,
/// exact end.
fn polyline(naxes: usize, ts: f64, verts: &[V], feed: f64, tol: f64, what: &str) -> Run {
    polyline_with(limits(naxes, ts), verts, feed, tol, what)
}

/// [`polyline`] with these limits.
pub(super) fn polyline_with(lim: PathLimits, verts: &[V], feed: f64, tol: f64, what: &str) -> Run {
    let mut p = path_with(lim, verts[0]);
    let mut geo = vec![];
    for (i, w) in verts.windows(2).enumerate() {
        let mut s = line(i as u32 + 1, w[1], feed, Transition::MaxDeviation(tol));
        s.last = i + 2 == verts.len();
        p.push(s).unwrap();
        geo.push(Piece::Line(w[0], w[1]));
    }
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 2_000_000), "{what}: never idle");
    r.assert_within(&p.lim, what);
    let dev = max_deviation(&r, &geo);
    assert!(dev <= tol * (1.0 + 1e-9), "{what}: deviation {dev} > {tol}");
    let ids: Vec<u32> = (1..verts.len() as u32).collect();
    r.assert_ids(&ids);
    assert_eq!(
        *r.pos.last().unwrap(),
        *verts.last().unwrap(),
        "{what}: end"
    );
    assert!(!r.events.iter().any(|e| e.1 == PathEvent::Starving));
    r
}

/// The push compares cosines with the tangents' dot product instead of taking its arc
/// cosine: the constants are the cosines of the angles the module names.
#[test]
fn the_turn_cosines_are_those_of_the_turn_limits() {
    assert_eq!(COS_SMOOTH_TURN, SMOOTH_TURN.cos());
    assert_eq!(COS_REVERSAL, REVERSAL.cos());
}

#[test]
fn square_zigzag_and_random_polylines_keep_every_axis_limit_and_the_tolerance() {
    let sq = [
        pt(&[0.0, 0.0]),
        pt(&[20_000.0, 0.0]),
        pt(&[20_000.0, 20_000.0]),
        pt(&[0.0, 20_000.0]),
        pt(&[0.0, 0.0]),
    ];
    let r = polyline(2, TS, &sq, 8e4, 50.0, "square");
    // it blends: the corners are not exact stops
    let slowest_corner = r.speed[10..r.speed.len() - 10]
        .iter()
        .fold(f64::INFINITY, |m: f64, &v| m.min(v));
    assert!(slowest_corner > 1e3, "square stopped at a corner");
    // the same at 20 kHz: the third differences over Ts³ resolve the blends' jerk
    polyline(2, 5e-5, &sq, 8e4, 50.0, "square at 20 kHz");
    let zz: Vec<V> = (0..12)
        .map(|i| pt(&[i as f64 * 3000.0, if i % 2 == 0 { 0.0 } else { 4000.0 }]))
        .collect();
    polyline(2, TS, &zz, 1e5, 20.0, "zig-zag");
    let mut rng = Rng::new(7);
    for (naxes, seed) in [(2, 1u64), (3, 2), (3, 3)] {
        let mut rng2 = Rng::new(seed);
        let mut v = vec![pt(&[0.0; 3][..naxes])];
        for _ in 0..15 {
            let last = *v.last().unwrap();
            let mut q = last;
            for x in q[..naxes].iter_mut() {
                *x += rng2.uniform(-8000.0, 8000.0);
            }
            v.push(q);
        }
        let tol = rng.log_uniform(5.0, 200.0);
        polyline(naxes, TS, &v, rng.uniform(2e4, 1e5), tol, "random polyline");
    }
}

#[test]
fn dense_polyline_of_2000_chords_stays_within_limits() {
    // a smooth curve (radius 30–50 mm, 1 count = 1 µm) in 2000 chords of ~0.1 mm
    let mut v = vec![];
    for i in 0..=2000 {
        let t = i as f64 / 2000.0 * 200_000.0 / 40_000.0;
        let r = 40_000.0 + 10_000.0 * (3.0 * t).sin();
        v.push(pt(&[r * t.cos(), r * t.sin()]));
    }
    let r = polyline(2, TS, &v, 1e5, 2.0, "dense polyline");
    let moving = r.speed.iter().filter(|&&s| s > 0.0).count();
    assert!(moving > 0);
}

/// A line, a quarter circle tangent to it and a line back up-left under these limits, blended
/// within 30 counts: limits, tolerance against the lines and the arc, ids, exact end.
pub(super) fn line_arc_line(lim: PathLimits) {
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let tol = 30.0;
    let tr = Transition::MaxDeviation(tol);
    p.push(line(1, pt(&[20_000.0, 0.0]), 8e4, tr)).unwrap();
    // a quarter circle to (25000, 5000) around (20000, 5000), then a line back up-left
    p.push(arc_xy(
        2,
        [20_000.0, 5_000.0],
        pt(&[25_000.0, 5_000.0]),
        8e4,
        tr,
    ))
    .unwrap();
    let end = pt(&[5_000.0, 20_000.0]);
    let mut s3 = line(3, end, 8e4, tr);
    s3.last = true;
    p.push(s3).unwrap();
    // the arc is tangent to the first line: curvature jump only, blended
    assert!(p.blend_info(2).is_some());
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "line-arc-line");
    let geo = [
        Piece::Line(pt(&[0.0, 0.0]), pt(&[20_000.0, 0.0])),
        Piece::Arc(
            [20_000.0, 5_000.0],
            5_000.0,
            -std::f64::consts::FRAC_PI_2,
            std::f64::consts::FRAC_PI_2,
        ),
        Piece::Line(pt(&[25_000.0, 5_000.0]), end),
    ];
    let dev = max_deviation(&r, &geo);
    assert!(dev <= tol * (1.0 + 1e-9), "deviation {dev}");
    r.assert_ids(&[1, 2, 3]);
    assert_eq!(*r.pos.last().unwrap(), end);
}

#[test]
fn line_arc_line_and_helix_keep_limits_tolerance_and_end_exactly() {
    line_arc_line(limits(2, TS));
    let tr = Transition::MaxDeviation(30.0);
    // a helix of two turns in (x, y) rising on z (slow y), between two lines
    let mut p = path(3, TS, pt(&[10_000.0, 0.0, 0.0]));
    p.push(line(1, pt(&[10_000.0, -5_000.0, 0.0]), 6e4, tr))
        .unwrap();
    p.push(arc_xy(
        2,
        [5_000.0, -5_000.0],
        pt(&[10_000.0, -5_000.0, 8_000.0]),
        6e4,
        tr,
    ))
    .unwrap();
    let end = pt(&[10_000.0, -5_000.0, 20_000.0]);
    p.push(line(3, end, 6e4, tr)).unwrap();
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "helix");
    r.assert_ids(&[1, 2, 3]);
    assert_eq!(*r.pos.last().unwrap(), end);
    // every point of the helix at radius 5000 from its axis (within the tolerance)
    let mut worst = 0.0f64;
    for q in &r.pos {
        if q[2] > 1_000.0 && q[2] < 7_000.0 {
            worst = worst.max(((q[0] - 5_000.0).hypot(q[1] + 5_000.0) - 5_000.0).abs());
        }
    }
    assert!(worst < 1e-6, "helix radius off by {worst}");
}

#[test]
fn transitions_exact_tolerance_zero_and_corner_distance() {
    for (tr, stops) in [
        (Transition::Exact, true),
        (Transition::MaxDeviation(0.0), true),
        (Transition::CornerDistance(0.0), true),
        (Transition::MaxDeviation(10.0), false),
        (Transition::CornerDistance(500.0), false),
    ] {
        let mut p = path(2, TS, pt(&[0.0, 0.0]));
        p.push(line(1, pt(&[10_000.0, 0.0]), 5e4, Transition::Exact))
            .unwrap();
        p.push(line(2, pt(&[10_000.0, 10_000.0]), 5e4, tr)).unwrap();
        if let Transition::CornerDistance(d) = tr {
            if d > 0.0 {
                let b = p.blend_info(2).unwrap();
                assert_eq!(b.trim, d);
                // 90° line-line: deviation 0.375·d·sin 45°
                assert!((b.deviation - 0.375 * d * 0.5f64.sqrt()).abs() < 1e-9 * d);
            }
        }
        let mut r = Run::default();
        assert!(r.go(&mut p, 1.0, 100_000));
        r.assert_within(&p.lim, "transition");
        r.assert_ids(&[1, 2]);
        let k = r
            .events
            .iter()
            .find(|e| e.1 == PathEvent::SegmentEnd { id: 1 })
            .unwrap()
            .0;
        if stops {
            assert_eq!(r.speed[k], 0.0, "{tr:?}");
            assert_eq!(r.pos[k], pt(&[10_000.0, 0.0]), "{tr:?}");
        } else {
            assert!(r.speed[k] > 1e3, "{tr:?}: {}", r.speed[k]);
            if let Transition::CornerDistance(d) = tr {
                // the path leaves the first line d before the corner and never reaches it
                let cut = 10_000.0 - d;
                for q in &r.pos {
                    if q[0] > cut + 1e-9 && q[1] < 1e-3 {
                        assert!(q[1] > 0.0 && q[0] < 10_000.0, "{q:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn blend_speed_rules_set_the_junction_speed() {
    // a gentle 20° corner with a long blend, feeds 1e4 and 5e4 in both orders
    let corner = |rule: BlendSpeed, f1: f64, f2: f64| {
        let mut p = path(2, TS, pt(&[0.0, 0.0]));
        p.push(line(1, pt(&[40_000.0, 0.0]), f1, Transition::Exact))
            .unwrap();
        let a = 20f64.to_radians();
        let mut s = line(
            2,
            pt(&[40_000.0 + 40_000.0 * a.cos(), 40_000.0 * a.sin()]),
            f2,
            Transition::CornerDistance(15_000.0),
        );
        s.blend = rule;
        p.push(s).unwrap();
        let mut r = Run::default();
        assert!(r.go(&mut p, 1.0, 100_000));
        r.assert_within(&p.lim, "blend speed");
        let k = r
            .events
            .iter()
            .find(|e| e.1 == PathEvent::SegmentEnd { id: 1 })
            .unwrap()
            .0;
        r.speed[k]
    };
    for (f1, f2) in [(1e4f64, 5e4f64), (5e4, 1e4)] {
        let lo = f1.min(f2);
        let hi = f1.max(f2);
        let v_low = corner(BlendSpeed::Low, f1, f2);
        let v_prev = corner(BlendSpeed::Previous, f1, f2);
        let v_next = corner(BlendSpeed::Next, f1, f2);
        let v_high = corner(BlendSpeed::High, f1, f2);
        assert!((v_low - lo).abs() < 1e-6 * lo, "low {v_low}");
        let expect = |v: f64, f: f64| {
            if f == lo {
                assert!((v - lo).abs() < 1e-6 * lo, "{v} vs {f}");
            } else {
                assert!(v > 2.0 * lo && v <= hi * (1.0 + 1e-9), "{v} vs {f}");
            }
        };
        expect(v_prev, f1);
        expect(v_next, f2);
        expect(v_high, hi);
    }
}

#[test]
fn starving_and_resuming_without_a_jump() {
    starving_and_resuming(limits(2, TS));
}

pub(super) fn starving_and_resuming(lim: PathLimits) {
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let tr = Transition::MaxDeviation(20.0);
    let mut id = 0;
    let next = |p: &mut Path, id: &mut u32| {
        *id += 1;
        let i = *id as f64;
        p.push(line(
            *id,
            pt(&[
                i * 6_000.0,
                if id.is_multiple_of(2) { 0.0 } else { 2_000.0 },
            ]),
            8e4,
            tr,
        ))
        .unwrap();
    };
    for _ in 0..3 {
        next(&mut p, &mut id);
    }
    let mut r = Run::default();
    // until Starving, then push more while still braking
    let mut starving = false;
    for _ in 0..10_000 {
        r.go(&mut p, 1.0, 1);
        if r.events.iter().any(|e| e.1 == PathEvent::Starving) {
            starving = true;
            break;
        }
    }
    assert!(starving);
    assert!(p.is_moving());
    for _ in 0..2 {
        next(&mut p, &mut id);
    }
    // to rest at the end, then more after rest
    assert!(r.go(&mut p, 1.0, 100_000));
    assert!(!p.is_moving());
    assert_eq!(p.position(), pt(&[5.0 * 6_000.0, 2_000.0]));
    for _ in 0..3 {
        next(&mut p, &mut id);
    }
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "starvation");
    r.assert_ids(&[1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(p.position(), pt(&[8.0 * 6_000.0, 0.0]));
    let starvings = r
        .events
        .iter()
        .filter(|e| e.1 == PathEvent::Starving)
        .count();
    assert!(starvings >= 2);
    assert_eq!(
        r.events.iter().filter(|e| e.1 == PathEvent::Idle).count(),
        2
    );
}

#[test]
fn halt_in_a_blend_and_in_a_line_then_clear() {
    halt_then_clear(limits(2, TS), 0);
}

/// A halt in a blend and in a line, at a tick whose number is `phase` modulo the planner's
/// steps (a step of the planner may be under way): a stop as short as the state allows, then
/// a clear and a new program.
pub(super) fn halt_then_clear(lim: PathLimits, phase: usize) {
    let ts = lim.ts;
    for in_blend in [true, false] {
        let mut p = path_with(lim, pt(&[0.0, 0.0]));
        let tr = Transition::CornerDistance(3_000.0);
        for i in 1..=6u32 {
            let x = i as f64 * 10_000.0;
            p.push(line(
                i,
                pt(&[x, if i % 2 == 0 { 0.0 } else { 5_000.0 }]),
                8e4,
                tr,
            ))
            .unwrap();
        }
        let mut r = Run::default();
        let mut found = false;
        for k in 0..100_000 {
            r.go(&mut p, 1.0, 1);
            if p.exec >= 2
                && p.in_blend == in_blend
                && p.speed() > 2e4
                && k % lim.plan_ticks == phase
            {
                found = true;
                break;
            }
        }
        assert!(found);
        let (v, a) = (p.speed(), p.accel());
        let (d, j) = (1e6, 1e8);
        p.halt(d, j);
        let from = p.distance();
        // bring a to 0, then the stop from the speed reached
        let bound = a.abs() / j + (v + a.max(0.0).powi(2) / (2.0 * j)) / d + d / j + 3.0 * ts;
        let mut ticks = 0;
        while p.is_moving() {
            r.go(&mut p, 1.0, 1);
            ticks += 1;
            assert!(
                ticks as f64 * ts <= bound,
                "halt takes {ticks} ticks > {bound} s"
            );
        }
        // the stop from the state of the tick it was asked in (no later)
        let stop = PathSpeedPlanner::stopping_distance(v, a, d, j);
        let ran = p.distance() - from;
        assert!(
            ran <= stop * (1.0 + 1e-6) + v * ts,
            "halt ran {ran} counts, the stop from there {stop}"
        );
        // stays halted
        let here = p.position();
        r.go(&mut p, 1.0, 50);
        assert_eq!(p.position(), here);
        r.assert_within(&p.lim, "halt");
        let mut aborted = vec![];
        p.clear(&mut |id| aborted.push(id)).unwrap();
        let (_, ended) = r.ids();
        let first = ended.last().copied().unwrap_or(0) + 1;
        assert_eq!(aborted, (first..=6).collect::<Vec<_>>());
        assert_eq!(p.queued(), 0);
        assert_eq!(p.position(), here);
        // and a new program starts from here
        p.push(line(9, pt(&[0.0, 0.0]), 5e4, Transition::Exact))
            .unwrap();
        assert!(r.go(&mut p, 1.0, 100_000));
        r.assert_within(&p.lim, "after clear");
        assert_eq!(p.position(), pt(&[0.0, 0.0]));
    }
}

#[test]
fn feed_override_zero_holds_and_resumes() {
    override_hold_and_resume(limits(2, TS));
}

pub(super) fn override_hold_and_resume(lim: PathLimits) {
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let tr = Transition::MaxDeviation(10.0);
    p.push(line(1, pt(&[30_000.0, 0.0]), 5e4, tr)).unwrap();
    p.push(line(2, pt(&[30_000.0, 30_000.0]), 5e4, tr)).unwrap();
    let mut r = Run::default();
    // ticks of 0.3 s, 0.4 s, 10 ms
    let ms = (1e-3 / lim.ts).round() as usize;
    r.go(&mut p, 1.0, 300 * ms);
    r.go(&mut p, 0.0, 400 * ms);
    assert!(!p.is_moving());
    let held = p.position();
    r.go(&mut p, 0.0, 10 * ms);
    assert_eq!(p.position(), held);
    r.go(&mut p, 1.7, 300 * ms);
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "override");
    assert_eq!(p.position(), pt(&[30_000.0, 30_000.0]));
    assert!(r.speed.iter().all(|&v| v <= 1.7 * 5e4 * (1.0 + 1e-9)));
}

#[test]
fn dwell_and_outputs_fire_in_order() {
    dwell_and_outputs(limits(2, TS));
}

pub(super) fn dwell_and_outputs(lim: PathLimits) {
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let tr = Transition::MaxDeviation(10.0);
    p.push_output(OutputAction {
        bit: 1,
        on: true,
        at: OutputAt::Start,
    })
    .unwrap();
    p.push_output(OutputAction {
        bit: 2,
        on: true,
        at: OutputAt::Distance(4_000.0),
    })
    .unwrap();
    p.push_output(OutputAction {
        bit: 3,
        on: true,
        at: OutputAt::End,
    })
    .unwrap();
    p.push(line(1, pt(&[10_000.0, 0.0]), 5e4, tr)).unwrap();
    p.push(Segment {
        id: 2,
        geom: Geom::Dwell { time: 0.0505 },
        feed: 0.0,
        transition: Transition::Exact,
        blend: BlendSpeed::Low,
        last: false,
    })
    .unwrap();
    p.push(line(3, pt(&[10_000.0, 10_000.0]), 5e4, tr)).unwrap();
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "dwell");
    r.assert_ids(&[1, 2, 3]);
    let evs: Vec<PathEvent> = r.events.iter().map(|e| e.1).collect();
    let at = |e: PathEvent| r.events.iter().find(|x| x.1 == e).unwrap().0;
    assert_eq!(evs[0], PathEvent::SegmentStart { id: 1 });
    assert_eq!(
        evs[1],
        PathEvent::Output {
            bit: 1,
            on: true,
            id: 1
        }
    );
    // the distance output in the tick the path crosses x = 4000
    let k = at(PathEvent::Output {
        bit: 2,
        on: true,
        id: 1,
    });
    assert!(r.pos[k][0] >= 4_000.0 && r.pos[k - 1][0] < 4_000.0);
    let e1 = at(PathEvent::SegmentEnd { id: 1 });
    assert_eq!(
        at(PathEvent::Output {
            bit: 3,
            on: true,
            id: 1
        }),
        e1
    );
    // the dwell: at rest on the corner for ceil(0.0505/Ts) ticks
    let e2 = at(PathEvent::SegmentEnd { id: 2 });
    assert_eq!(at(PathEvent::SegmentStart { id: 2 }), e1);
    assert_eq!(e2 - e1, (0.0505 / lim.ts - 1e-9).ceil() as usize + 1);
    assert!(r.pos[e1..e2].iter().all(|q| *q == pt(&[10_000.0, 0.0])));
}

#[test]
fn bad_inputs_are_refused_and_leave_the_path_unchanged() {
    let mut p = Path::with_capacity(64);
    assert_eq!(
        p.push(line(1, pt(&[1.0, 0.0]), 1.0, Transition::Exact)),
        Err(PathError::NotReady)
    );
    p.reset(pt(&[0.0, 0.0]), limits(2, TS), 16).unwrap();
    p.push(line(1, pt(&[1_000.0, 0.0]), 1e4, Transition::Exact))
        .unwrap();
    let snap = format!("{p:?}");
    let sub = 5e-324;
    let feeds = [
        (f64::NAN, PathError::NotFinite),
        (f64::INFINITY, PathError::NotFinite),
        (-1.0, PathError::NonPositive),
        (0.0, PathError::NonPositive),
        (1e300, PathError::OutOfRange),
        (sub, PathError::OutOfRange),
    ];
    for (f, e) in feeds {
        let s = line(2, pt(&[2_000.0, 500.0]), f, Transition::MaxDeviation(1.0));
        assert_eq!(p.push(s), Err(e), "feed {f}");
    }
    let tols = [
        (f64::NAN, PathError::NotFinite),
        (f64::NEG_INFINITY, PathError::NotFinite),
        (-1.0, PathError::NonPositive),
        (1e300, PathError::OutOfRange),
        (sub, PathError::OutOfRange),
    ];
    for (t, e) in tols {
        for tr in [Transition::MaxDeviation(t), Transition::CornerDistance(t)] {
            let s = line(2, pt(&[2_000.0, 500.0]), 1e4, tr);
            assert_eq!(p.push(s), Err(e), "tol {t}");
        }
    }
    let poss = [
        (f64::NAN, PathError::NotFinite),
        (f64::INFINITY, PathError::NotFinite),
        (1e300, PathError::OutOfRange),
        (-4.6e15, PathError::OutOfRange),
    ];
    for (x, e) in poss {
        let s = line(2, pt(&[2_000.0, x]), 1e4, Transition::Exact);
        assert_eq!(p.push(s), Err(e), "pos {x}");
        let a = Segment {
            geom: Geom::Arc {
                u: 0,
                v: 1,
                centre: [x, 0.0],
                ccw: true,
                end: pt(&[0.0, 1_000.0]),
            },
            ..s
        };
        assert_eq!(p.push(a), Err(e), "centre {x}");
    }
    let zero = line(2, pt(&[1_000.0, 0.0]), 1e4, Transition::Exact);
    assert_eq!(p.push(zero), Err(PathError::ZeroLength));
    let arc = |u, v, c: [f64; 2], end| Segment {
        id: 2,
        geom: Geom::Arc {
            u,
            v,
            centre: c,
            ccw: true,
            end,
        },
        feed: 1e4,
        transition: Transition::Exact,
        blend: BlendSpeed::Low,
        last: false,
    };
    assert_eq!(
        p.push(arc(0, 0, [0.0, 0.0], pt(&[0.0, 1_000.0]))),
        Err(PathError::BadAxis)
    );
    assert_eq!(
        p.push(arc(0, 2, [0.0, 0.0], pt(&[0.0, 1_000.0]))),
        Err(PathError::BadAxis)
    );
    assert_eq!(
        p.push(arc(0, 1, [0.0, 0.0], pt(&[0.0, 1_500.0]))),
        Err(PathError::BadArc(CircleError::EndPointOffCircle))
    );
    assert_eq!(
        p.push(arc(0, 1, [0.0, 0.0], pt(&[0.0, 1_000.5]))),
        Err(PathError::ArcEndOffCircle)
    );
    assert_eq!(
        p.push(arc(0, 1, [1_000.0, 0.0], pt(&[0.0, 1_000.0]))),
        Err(PathError::BadArc(CircleError::InvalidRadius))
    );
    for (t, e) in [
        (f64::NAN, PathError::NotFinite),
        (-1.0, PathError::NonPositive),
        (1e300, PathError::OutOfRange),
    ] {
        let d = Segment {
            geom: Geom::Dwell { time: t },
            ..zero
        };
        assert_eq!(p.push(d), Err(e));
    }
    let out = |bit, at| OutputAction { bit, on: true, at };
    assert_eq!(
        p.push_output(out(40, OutputAt::Start)),
        Err(PathError::OutOfRange)
    );
    assert_eq!(
        p.push_output(out(1, OutputAt::Distance(f64::NAN))),
        Err(PathError::NotFinite)
    );
    assert_eq!(
        p.push_output(out(1, OutputAt::Distance(-1.0))),
        Err(PathError::NonPositive)
    );
    assert_eq!(format!("{p:?}"), snap, "a refusal changed the path");
    // limits: every field, NaN / 0 / huge / subnormal
    let good = limits(2, TS);
    let mut bad = vec![];
    for v in [f64::NAN, 0.0, -1.0, 1e300, sub, f64::INFINITY] {
        let mut l = good;
        l.ts = v;
        bad.push(l);
        for k in 0..2 {
            let mut l = good;
            l.vmax[k] = v;
            bad.push(l);
            let mut l = good;
            l.amax[k] = v;
            bad.push(l);
            let mut l = good;
            l.jmax[k] = v;
            bad.push(l);
        }
        if v != 0.0 {
            let mut l = good;
            l.accel = v;
            bad.push(l);
            let mut l = good;
            l.jerk = v;
            bad.push(l);
        }
    }
    for l in bad {
        assert_eq!(
            p.reset(pt(&[0.0, 0.0]), l, 16),
            Err(PathError::BadLimits),
            "{l:?}"
        );
    }
    let mut l = good;
    l.naxes = 9;
    assert_eq!(p.reset(pt(&[0.0]), l, 16), Err(PathError::BadAxis));
    l.naxes = 0;
    assert_eq!(p.reset(pt(&[0.0]), l, 16), Err(PathError::BadAxis));
    assert_eq!(p.reset(pt(&[0.0]), good, 0), Err(PathError::BadLookahead));
    assert_eq!(p.reset(pt(&[0.0]), good, 65), Err(PathError::BadLookahead));
    assert_eq!(
        p.reset(pt(&[f64::NAN]), good, 16),
        Err(PathError::NotFinite)
    );
    assert_eq!(format!("{p:?}"), snap, "a refused reset changed the path");
    // a subnormal position is a position (near 0): accepted
    p.push(line(2, pt(&[sub, 1_000.0]), 1e4, Transition::Exact))
        .unwrap();
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    assert_eq!(p.position(), pt(&[sub, 1_000.0]));
}

#[test]
fn seeded_sweep_of_random_inputs_never_panics_and_refusals_change_nothing() {
    let mut rng = Rng::new(99);
    let mut p = Path::with_capacity(64);
    p.reset(pt(&[0.0, 0.0, 0.0]), limits(3, TS), 8).unwrap();
    let odd = [
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        1e300,
        -1e300,
        5e-324,
        -5e-324,
        0.0,
        1e-9,
        4.5e15,
    ];
    let pick = |rng: &mut Rng| {
        if rng.chance(0.2) {
            odd[rng.int(0, odd.len() - 1)]
        } else {
            rng.uniform(-5e4, 5e4)
        }
    };
    for i in 0..3000u32 {
        let end = pt(&[pick(&mut rng), pick(&mut rng), pick(&mut rng)]);
        let x = pick(&mut rng);
        let geom = if rng.chance(0.2) {
            Geom::Arc {
                u: rng.int(0, 3),
                v: rng.int(0, 3),
                centre: [pick(&mut rng), pick(&mut rng)],
                ccw: rng.chance(0.5),
                end,
            }
        } else {
            Geom::Line { end }
        };
        let s = Segment {
            id: i,
            geom,
            feed: x.abs(),
            transition: Transition::MaxDeviation(pick(&mut rng).abs()),
            blend: BlendSpeed::High,
            last: false,
        };
        // what a push changes: the ring's end, the previous segment, its block, the outputs
        let snap = |p: &Path| {
            let prev = p.tail.checked_sub(1).map(|i| *p.seg(i));
            let blk = p.tail.checked_sub(1).map(|i| p.blocks[p.slot(i) / BLOCK]);
            format!(
                "{} {} {:?} {:?} {:?} {:?}",
                p.tail,
                p.npending,
                p.last_end,
                prev.map(|s| (s.body1, s.id)),
                blk,
                p.seg(p.tail).id
            )
        };
        let before = snap(&p);
        if p.push(s).is_err() {
            assert_eq!(snap(&p), before);
        }
        for _ in 0..rng.int(0, 20) {
            let q = p.tick(1.0, &mut |_| {});
            assert!(q.iter().all(|x| x.is_finite()));
        }
    }
}

#[test]
fn full_ring_refuses_and_loses_nothing() {
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    assert_eq!(p.free(), 4096);
    let tr = Transition::MaxDeviation(1.0);
    for i in 0..4096u32 {
        // 10-count chords of a gentle arc (radius ~ 1e5)
        let x = (i + 1) as f64 * 10.0;
        p.push(line(
            i,
            pt(&[x, 3.0 - (x - 20_480.0).powi(2) / 2e5]),
            1e5,
            tr,
        ))
        .unwrap();
    }
    assert_eq!(p.free(), 0);
    assert_eq!(
        p.push(line(4096, pt(&[0.0, 0.0]), 1e5, tr)),
        Err(PathError::Full)
    );
    assert_eq!(p.queued(), 4096);
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 1_000_000));
    r.assert_ids(&(0..4096).collect::<Vec<_>>());
    assert_eq!(p.position(), pt(&[40_960.0, 3.0 - 20_480f64.powi(2) / 2e5]));
    r.assert_within(&p.lim, "full");
}

#[test]
fn short_lookahead_window_still_blends_and_keeps_limits() {
    let mut p = Path::with_capacity(64);
    p.reset(pt(&[0.0, 0.0]), limits(2, TS), 1).unwrap();
    let tr = Transition::MaxDeviation(10.0);
    let v: Vec<V> = (1..10)
        .map(|i| pt(&[i as f64 * 2_000.0, if i % 2 == 0 { 0.0 } else { 800.0 }]))
        .collect();
    for (i, q) in v.iter().enumerate() {
        p.push(line(i as u32, *q, 1e5, tr)).unwrap();
    }
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "lookahead 1");
    r.assert_ids(&(0..9).collect::<Vec<_>>());
    assert_eq!(p.position(), v[8]);
}

/// The first bench's curve (benches/path.rs now runs path_run's hypotrochoid): 10,000 chords
/// of ~0.1 mm along a sum of sines.
fn bench_curve() -> (Vec<V>, PathLimits) {
    let mut v = vec![];
    let mut x = 0.0f64;
    for _ in 0..=10_000 {
        let y = 3000.0 * (x / 5000.0).sin() + 1000.0 * (x / 2000.0).sin();
        let dy = 0.6 * (x / 5000.0).cos() + 0.5 * (x / 2000.0).cos();
        v.push(pt(&[x, y]));
        x += 100.0 / (1.0 + dy * dy).sqrt();
    }
    let mut l = limits(2, 1e-4);
    l.vmax = [2e5; MAX_AXES];
    l.amax = [2e7; MAX_AXES];
    l.jmax = [2e9; MAX_AXES];
    l.vmax[1] = 1e5;
    l.amax[1] = 1e7;
    l.jmax[1] = 1e9;
    (v, l)
}

/// Prints the path time of the bench's curve against an offline bound: the same pieces
/// (blends included), capped with the full axis budgets (|vT_k| ≤ vmax_k, v²|K_k| ≤ amax_k,
/// v³|K'_k| ≤ jmax_k, no tangential share), then a forward/backward pass with the tangential
/// acceleration min_k amax_k/|T_k| (jerk ignored): a lower bound of any feasible time.
/// `cargo test -p card-emu --lib motion::path::tests::dense_curve -- --ignored --nocapture`
#[test]
#[ignore]
fn dense_curve_time_against_offline_bound() {
    let (v, l) = bench_curve();
    let mut p = Path::with_capacity(10_000);
    p.reset(v[0], l, DEFAULT_LOOKAHEAD).unwrap();
    for (i, q) in v[1..].iter().enumerate() {
        let mut s = line(i as u32, *q, 2e5, Transition::MaxDeviation(1.0));
        s.last = i + 2 == v.len();
        p.push(s).unwrap();
    }
    // offline bound on the planned pieces
    let cap = |f: &Frame| {
        let mut c = f64::INFINITY;
        let mut acc = f64::INFINITY;
        for k in 0..l.naxes {
            let (t, kk, dk) = (f.t[k].abs(), f.k[k].abs(), f.dk[k].abs());
            if t > 0.0 {
                c = c.min(l.vmax[k] / t);
                acc = acc.min(l.amax[k] / t);
            }
            if kk > 0.0 {
                c = c.min((l.amax[k] / kk).sqrt());
            }
            if dk > 0.0 {
                c = c.min((l.jmax[k] / dk).cbrt());
            }
        }
        (c.min(2e5), acc)
    };
    let mut samples: Vec<(f64, f64, f64)> = vec![]; // (ds from previous, cap, accel)
    let step = 2.0;
    for i in p.exec..p.tail {
        let sg = *p.seg(i);
        if sg.has_blend {
            let m = (sg.blend.len / step).ceil() as usize;
            for j in 0..m {
                let s = sg.blend.len * j as f64 / m as f64;
                let (c, a) = cap(&sg.blend.frame_u(sg.blend.u_at(s)));
                samples.push((sg.blend.len / m as f64, c, a));
            }
        }
        let bl = sg.body1 - sg.body0;
        let m = (bl / step).ceil().max(1.0) as usize;
        for j in 0..m {
            let (c, a) = cap(&sg.prog.frame(sg.body0 + bl * j as f64 / m as f64));
            samples.push((bl / m as f64, c, a));
        }
    }
    let n = samples.len();
    let mut vv: Vec<f64> = samples.iter().map(|s| s.1).collect();
    vv[0] = 0.0;
    vv.push(0.0);
    for i in 1..n {
        vv[i] = vv[i].min((vv[i - 1].powi(2) + 2.0 * samples[i - 1].2 * samples[i].0).sqrt());
    }
    for i in (0..n).rev() {
        let ds = if i + 1 < n {
            samples[i + 1].0
        } else {
            samples[i].0
        };
        vv[i] = vv[i].min((vv[i + 1].powi(2) + 2.0 * samples[i].2 * ds).sqrt());
    }
    let mut t_bound = 0.0;
    for i in 1..=n {
        let ds = if i < n {
            samples[i].0
        } else {
            samples[n - 1].0
        };
        t_bound += 2.0 * ds / (vv[i - 1] + vv[i]).max(1e-9);
    }
    let len: f64 = samples.iter().map(|s| s.0).sum();
    let mut ticks = 0u64;
    let t0 = std::time::Instant::now();
    while p.queued() > 0 || p.is_moving() {
        p.tick(1.0, &mut |_| {});
        ticks += 1;
    }
    let wall = t0.elapsed();
    let t_path = ticks as f64 * l.ts;
    println!(
        "dense curve: {:.1} mm, path time {t_path:.4} s, offline bound {t_bound:.4} s, ratio {:.2}; {ticks} ticks in {:?}",
        len / 1000.0,
        t_path / t_bound,
        wall
    );
}

/// The offline bound of the curve y = f(x) from x = 0 to `x1` at feed `feed`: the time at
/// the largest speed its curvature allows on every axis (|v T_k| ≤ vmax_k, v²|K_k| ≤ amax_k,
/// v³|dK_k/ds| ≤ jmax_k) with a tangential acceleration up to min_k amax_k, from rest to rest
/// (forward and backward passes on a fine grid). `f` gives (y', y'') at x.
fn curve_bound(l: &PathLimits, x1: f64, feed: f64, f: impl Fn(f64) -> (f64, f64)) -> f64 {
    let m = 200_000;
    let h = x1 / m as f64;
    let frame = |x: f64| {
        let (d1, d2) = f(x);
        let sp = (1.0 + d1 * d1).sqrt();
        let sp4 = sp.powi(4);
        ([1.0 / sp, d1 / sp], [-d1 * d2 / sp4, d2 / sp4], sp)
    };
    let a_t = l.amax[..2].iter().fold(f64::INFINITY, |m, &x| m.min(x));
    let mut cap = vec![0.0; m + 1];
    let mut ds = vec![0.0; m];
    for i in 0..=m {
        let x = i as f64 * h;
        let (t, k, sp) = frame(x);
        let (_, k1, _) = frame(x + h);
        let mut c = feed;
        for a in 0..2 {
            let dk = ((k1[a] - k[a]) / (sp * h)).abs();
            c = c.min(l.vmax[a] / t[a].abs().max(1e-300));
            c = c.min((l.amax[a] / k[a].abs().max(1e-300)).sqrt());
            c = c.min((l.jmax[a] / dk.max(1e-300)).cbrt());
        }
        cap[i] = c;
        if i < m {
            ds[i] = sp * h;
        }
    }
    cap[0] = 0.0;
    cap[m] = 0.0;
    for i in 0..m {
        cap[i + 1] = cap[i + 1].min((cap[i] * cap[i] + 2.0 * a_t * ds[i]).sqrt());
    }
    for i in (0..m).rev() {
        cap[i] = cap[i].min((cap[i + 1] * cap[i + 1] + 2.0 * a_t * ds[i]).sqrt());
    }
    (0..m).map(|i| 2.0 * ds[i] / (cap[i] + cap[i + 1])).sum()
}

/// Micro-segments of a smooth curve are smoothed: each junction's blend runs from the middle
/// of one chord to the middle of the next, with the curvature the neighbouring points give, so
/// the path runs near the speed the curve itself allows. The rest of the gap is the caps'
/// worst case (full tangential acceleration at the cap, `ACCEL_SHARE`, `JERK_SHARE`), which the
/// bound does not pay.
#[test]
fn micro_segments_of_a_smooth_curve_run_near_the_curves_own_bound() {
    let (v, mut l) = bench_curve();
    let v = &v[..3001];
    // 100 mm/s, 1 m/s², 100 m/s³ (1 count = 1 µm): the curvature limits the speed in places
    l.vmax = [1e5; MAX_AXES];
    l.amax = [1e6; MAX_AXES];
    l.jmax = [1e8; MAX_AXES];
    let mut p = Path::with_capacity(4096);
    p.reset(v[0], l, DEFAULT_LOOKAHEAD).unwrap();
    for (i, w) in v.windows(2).enumerate() {
        let mut s = line(i as u32 + 1, w[1], 2e5, Transition::MaxDeviation(1.0));
        s.last = i + 2 == v.len();
        p.push(s).unwrap();
    }
    // every junction is smoothed: its blend trims half of the chord before it
    for (i, w) in v.windows(2).enumerate().skip(1) {
        let before = dist_seg(&w[0], &v[i - 1], &v[i - 1]);
        let b = p.blend_info(i as u32 + 1).expect("a blend");
        assert!(
            (b.trim - 0.5 * before).abs() <= 1e-9 * before,
            "segment {}: trim {} of a {before} chord",
            i + 1,
            b.trim
        );
        assert!(b.deviation <= 1.0);
    }
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 1_000_000));
    r.assert_within(&l, "smoothed dense curve");
    let dev = max_deviation_in_order(&r, v);
    assert!(dev <= 1.0, "deviation {dev}");
    r.assert_ids(&(1..v.len() as u32).collect::<Vec<_>>());
    assert_eq!(*r.pos.last().unwrap(), v[v.len() - 1]);
    let time = (r.pos.len() - 6) as f64 * l.ts;
    let bound = curve_bound(&l, v[v.len() - 1][0], 2e5, |x| {
        (
            0.6 * (x / 5000.0).cos() + 0.5 * (x / 2000.0).cos(),
            -0.6 / 5000.0 * (x / 5000.0).sin() - 0.5 / 2000.0 * (x / 2000.0).sin(),
        )
    });
    let ratio = time / bound;
    // `cargo test --release -p card-emu --lib motion::path::tests::micro -- --nocapture`
    println!(
        "smoothed sine curve: path time {time:.4} s, the curve's bound {bound:.4} s: {ratio:.3}"
    );
    assert!(
        (0.98..=1.6).contains(&ratio),
        "path time {time} s against the curve's bound {bound} s: {ratio}"
    );
}

/// Smoothing while the path runs close behind the stream (a few segments queued): blends the
/// executor is too near to are not rebuilt, and the limits and the tolerance hold throughout.
#[test]
fn smoothing_close_behind_a_slow_stream_keeps_limits_and_tolerance() {
    let (v, l) = bench_curve();
    let v = &v[..1201];
    let mut p = Path::with_capacity(4096);
    p.reset(v[0], l, DEFAULT_LOOKAHEAD).unwrap();
    let mut r = Run::default();
    let mut rng = Rng::new(11);
    for (i, w) in v.windows(2).enumerate() {
        let mut s = line(i as u32 + 1, w[1], 2e5, Transition::MaxDeviation(1.0));
        s.last = i + 2 == v.len();
        p.push(s).unwrap();
        // a stream that keeps 1–4 segments ahead of the executor
        while p.queued() > 1 + (rng.uniform(0.0, 3.99) as usize) {
            r.go(&mut p, 1.0, 1);
        }
    }
    assert!(r.go(&mut p, 1.0, 1_000_000));
    r.assert_within(&l, "smoothing close behind the stream");
    let dev = max_deviation_in_order(&r, v);
    assert!(dev <= 1.0, "deviation {dev}");
    r.assert_ids(&(1..v.len() as u32).collect::<Vec<_>>());
    assert_eq!(*r.pos.last().unwrap(), v[v.len() - 1]);
}

/// Two lines that turn by 168° (LinuxCNC's tort.ngc: a rapid down and back up) at 10 counts
/// of tolerance: the blend that fits folds into a near-cusp, capped at 11 counts/s, and the
/// slowing for it came down to that speed 6,800 counts early: 0.6 s of path took 616 s. Now the
/// corner is an exact stop, and the run takes about the time of exact stops.
#[test]
fn a_near_reversal_runs_as_fast_as_an_exact_stop() {
    let l = PathLimits {
        vmax: [1e5; MAX_AXES],
        amax: [1e6; MAX_AXES],
        jmax: [1e8; MAX_AXES],
        ..limits(3, TS)
    };
    let v = [
        pt(&[-1828.427, 7449.383, 31656.854]),
        pt(&[0.0, 0.0, 20000.0]),
        pt(&[0.0, 3500.0, 24000.0]),
    ];
    let blended = polyline_with(l, &v, 1e5, 10.0, "near-reversal");
    let mut p = path_with(l, v[0]);
    for (i, w) in v.windows(2).enumerate() {
        let mut s = line(i as u32 + 1, w[1], 1e5, Transition::Exact);
        s.last = i == 1;
        p.push(s).unwrap();
    }
    let mut exact = Run::default();
    assert!(exact.go(&mut p, 1.0, 100_000));
    let (tb, te) = (blended.pos.len(), exact.pos.len());
    assert!(tb <= te + 2, "{tb} ticks blended, {te} with an exact stop");
    assert!(te < 500, "{te} ticks");
}

/// A slowing decided within the lowest limits ahead and ramped within the higher ones of the
/// line it is on gets to the slow piece's speed early; a slow enough piece made that a crawl
/// of minutes. A slow arc (10 counts/s) after a long line: the time spent at its speed before
/// its blend starts is a few ticks.
#[test]
fn a_slowing_that_arrives_early_does_not_crawl_to_its_piece() {
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    p.push(line(1, pt(&[20_000.0, 0.0]), 1e5, Transition::Exact))
        .unwrap();
    let mut arc = arc_xy(
        2,
        [20_000.0, 100.0],
        pt(&[20_100.0, 100.0]),
        10.0,
        Transition::MaxDeviation(5.0),
    );
    arc.last = true;
    p.push(arc).unwrap();
    // the arc's slow feed holds from the blend into it on
    let slow_from = 20_000.0 - p.blend_info(2).unwrap().trim;
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 3_000_000), "never idle");
    r.assert_within(&p.lim, "line and slow arc");
    let slow_before = (3..r.pos.len())
        .filter(|&i| r.speed[i] <= 10.0 * 1.001 && r.pos[i][0] < slow_from - 1e-6)
        .count();
    assert!(
        slow_before < 100,
        "{slow_before} ticks at the arc's speed before it"
    );
}

/// LinuxCNC's `zigzag_0.002_0.0005.ngc` read in mm, its first 1,961 chords fitted into one
/// line by the SDK: a 3,922-count line, then 2-count chords that zigzag by a count, then
/// back. The line and the first chord were smoothed as one blend from the line's middle: it
/// curved in its last few per cent, was capped for that all along (0.04 mm/s, 45 s in all),
/// and its curvature changed faster than its samples saw (1.69 times the jerk limit). Lines
/// of lengths this far apart are not smoothed now.
#[test]
fn a_long_line_into_micro_chords_is_not_smoothed_from_its_middle() {
    let l = PathLimits {
        vmax: [1e5; MAX_AXES],
        amax: [1e6; MAX_AXES],
        jmax: [1e8; MAX_AXES],
        plan_ticks: 10,
        ..limits(3, 1e-4)
    };
    let mut v = vec![pt(&[0.0, 0.0, 0.0]), pt(&[3922.0, -0.5, 0.0])];
    for i in 1962..=2000 {
        v.push(pt(&[
            2.0 * i as f64,
            if i % 2 == 1 { -0.5 } else { 0.5 },
            0.0,
        ]));
    }
    v.push(pt(&[0.0, 0.0, 0.0]));
    let r = polyline_with(l, &v, 1e5, 10.0, "long line into micro chords");
    let w = r.worst(&l);
    assert!(w[2] <= 1.0 + 1e-6, "v, a, j ratios {w:?}");
    // the line alone, there and back, takes about 1,300 ticks; the 39 chords, blended at a
    // few tens of counts a second, about 13,000
    assert!(r.pos.len() < 20_000, "{} ticks", r.pos.len());
}

/// Twenty-two points of a CAM program (LinuxCNC's test program `Pasta.ngc`, in µm counts): the
/// smoothing blend at the sixth-degree turn into (31102, −35775) was accepted at 9.70 counts
/// of a 10-count tolerance by its 33 samples and ran 10.15 from its lines (the distance to
/// the nearer line peaks at a kink between two samples). Within the tolerance now.
#[test]
fn a_smoothing_blend_is_checked_at_its_peak_not_only_at_its_samples() {
    let l = PathLimits {
        vmax: [1e5; MAX_AXES],
        amax: [1e6; MAX_AXES],
        jmax: [1e8; MAX_AXES],
        plan_ticks: 10,
        ..limits(3, 1e-4)
    };
    let v = vec![
        pt(&[25785.0, -36684.0, -949.0]),
        pt(&[25835.0, -36647.0, -1013.0]),
        pt(&[27624.0, -36646.0, -1015.0]),
        pt(&[28220.0, -36631.0, -1041.0]),
        pt(&[28816.0, -36581.0, -1127.0]),
        pt(&[29313.0, -36503.0, -1263.0]),
        pt(&[29810.0, -36379.0, -1477.0]),
        pt(&[30208.0, -36237.0, -1722.0]),
        pt(&[30605.0, -36058.0, -2033.0]),
        pt(&[31102.0, -35775.0, -2523.0]),
        pt(&[31599.0, -35426.0, -3127.0]),
        pt(&[31997.0, -35104.0, -3685.0]),
        pt(&[32494.0, -35502.0, -2996.0]),
        pt(&[32991.0, -35838.0, -2415.0]),
        pt(&[33388.0, -36058.0, -2033.0]),
        pt(&[33786.0, -36237.0, -1722.0]),
        pt(&[34184.0, -36379.0, -1477.0]),
        pt(&[34581.0, -36481.0, -1300.0]),
        pt(&[35078.0, -36568.0, -1149.0]),
        pt(&[35674.0, -36623.0, -1054.0]),
        pt(&[36469.0, -36646.0, -1014.0]),
        pt(&[38159.0, -36647.0, -1013.0]),
    ];
    polyline_with(l, &v, 2e4, 10.0, "CAM points");
}
