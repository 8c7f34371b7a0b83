//! NURBS curves in the path (`curve.rs`): tolerance against the true curve, limits, one
//! segment's events and outputs, refusals that change nothing.

use super::tests::{dist_seg, limits, line, path, pt, Run, TS};
use super::*;
use crate::motion::nurbs::Nurbs;

/// A rational cubic in (x, y) from (2000, 0), leaving along +x, with a double knot at 0.4
/// (only C¹ there: the curvature jumps).
fn freeform() -> Nurbs {
    let ctrl = [
        2000.0, 0.0, 4000.0, 0.0, 5000.0, 2000.0, 7000.0, 3000.0, 8000.0, 1000.0, 10000.0, 0.0,
        11000.0, 2000.0, 12000.0, 4000.0,
    ];
    let w = [1.0, 1.0, 2.0, 1.0, 0.5, 1.0, 1.0, 1.0];
    let knots = [0.0, 0.0, 0.0, 0.0, 0.2, 0.4, 0.4, 0.7, 1.0, 1.0, 1.0, 1.0];
    Nurbs::new(3, 2, &ctrl, &w, &knots).unwrap()
}

fn curve_seg(id: u32, c: &Nurbs, feed: f64, tr: Transition, fit: f64) -> CurveSegment<'_> {
    CurveSegment {
        id,
        curve: c,
        feed,
        transition: tr,
        blend: BlendSpeed::Low,
        last: false,
        tolerance: fit,
    }
}

/// The curve sampled densely (an independent polyline: 200,001 points).
fn dense(c: &Nurbs) -> Vec<V> {
    let (a, b) = c.domain();
    let m = 200_000;
    (0..=m)
        .map(|i| {
            let q = c.point(a + (b - a) * i as f64 / m as f64).unwrap();
            pt(&[q[0], q[1]])
        })
        .collect()
}

/// Distance from `p` to the polyline `poly`, searched near `at` (updated).
fn dist_near(p: &V, poly: &[V], at: &mut usize) -> f64 {
    let lo = at.saturating_sub(2000);
    let hi = (*at + 2000).min(poly.len() - 1);
    let (mut best, mut arg) = (f64::INFINITY, *at);
    for j in lo..hi {
        let d = dist_seg(p, &poly[j], &poly[j + 1]);
        if d < best {
            best = d;
            arg = j;
        }
    }
    *at = arg;
    best
}

#[test]
fn a_nurbs_curve_between_lines_keeps_its_tolerance_the_limits_and_one_segments_events() {
    let c = freeform();
    let fit = 0.5;
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    let tr = Transition::MaxDeviation(5.0);
    p.push(line(1, pt(&[2000.0, 0.0]), 3e4, tr)).unwrap();
    let before = p.queued();
    let pieces = p.push_curve(&curve_seg(2, &c, 3e4, tr, fit)).unwrap();
    assert!(pieces > 7, "{pieces} pieces");
    assert_eq!(p.queued(), before + pieces);
    let end = pt(&[14000.0, 8000.0]);
    let mut last = line(3, end, 3e4, tr);
    last.last = true;
    p.push(last).unwrap();
    // the joins' blends, which keep the lines' tolerance
    let (t_in, t_out) = (p.blend_info(2).unwrap().trim, p.blend_info(3).unwrap().trim);
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "curve");
    r.assert_ids(&[1, 2, 3]);
    assert_eq!(*r.pos.last().unwrap(), end);
    assert!(!r.events.iter().any(|e| e.1 == PathEvent::Starving));
    // every point: within the blend tolerance of line ∪ curve ∪ line; outside the blends of
    // the two joins, within the fit tolerance of the curve
    let poly = dense(&c);
    let (c0, c1) = (poly[0], *poly.last().unwrap());
    let tick_of = |e: PathEvent| r.events.iter().find(|x| x.1 == e).unwrap().0;
    let (s2, e2) = (
        tick_of(PathEvent::SegmentStart { id: 2 }),
        tick_of(PathEvent::SegmentEnd { id: 2 }),
    );
    let (mut at, mut worst_curve, mut worst) = (0usize, 0.0f64, 0.0f64);
    for (i, q) in r.pos.iter().enumerate() {
        let dc = dist_near(q, &poly, &mut at);
        let d = dc
            .min(dist_seg(q, &pt(&[0.0, 0.0]), &c0))
            .min(dist_seg(q, &c1, &end));
        worst = worst.max(d);
        let far = |e: &V, trim: f64| (q[0] - e[0]).hypot(q[1] - e[1]) > trim;
        if (s2..e2).contains(&i) && far(&c0, t_in) && far(&c1, t_out) {
            worst_curve = worst_curve.max(dc);
        }
    }
    assert!(worst <= 5.0 * (1.0 + 1e-9), "deviation {worst}");
    assert!(
        worst_curve <= fit * (1.0 + 1e-6),
        "from the curve {worst_curve}"
    );
    // it does not crawl: at least half the feed on average over the curve
    let ticks = (e2 - s2) as f64;
    let len: f64 = poly
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    let mean = len / (ticks * TS);
    println!(
        "{pieces} pieces, trims {t_in:.0} and {t_out:.0}, curve {len:.0} counts in {ticks} \
         ticks: mean {mean:.0} counts/s, deviation {worst_curve:.3} from the curve"
    );
    assert!(mean > 0.5 * 3e4, "mean speed {mean}");
}

#[test]
fn a_rational_circle_joins_its_pieces_without_blends_and_outputs_fire_along_it() {
    // exact circle of radius 5000 (quadratic, double knots): G2 everywhere
    let c = Nurbs::circle([0.0, 0.0], 5000.0).unwrap();
    let mut p = path(2, TS, pt(&[5000.0, 0.0]));
    for (bit, at) in [
        (1, OutputAt::Start),
        (2, OutputAt::Distance(20_000.0)),
        (3, OutputAt::End),
    ] {
        p.push_output(OutputAction { bit, on: true, at }).unwrap();
    }
    let mut s = curve_seg(7, &c, 2e4, Transition::Exact, 0.1);
    s.last = true;
    let pieces = p.push_curve(&s).unwrap();
    // the pieces meet tangent and curvature-continuous: no blend between them
    let first = p.exec;
    for i in first + 1..first + pieces {
        assert!(!p.seg(i).has_blend && !p.seg(i).stop_before, "piece {i}");
        assert!(p.seg(i).cont);
    }
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "circle");
    r.assert_ids(&[7]);
    let worst = r
        .pos
        .iter()
        .map(|q| (q[0].hypot(q[1]) - 5000.0).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 0.1, "off the circle by {worst}");
    assert!((r.pos.last().unwrap()[0] - 5000.0).abs() < 1e-6);
    let at = |e: PathEvent| r.events.iter().find(|x| x.1 == e).map(|x| x.0);
    let out = |bit| PathEvent::Output {
        bit,
        on: true,
        id: 7,
    };
    let start = at(PathEvent::SegmentStart { id: 7 }).unwrap();
    assert_eq!(at(out(1)), Some(start));
    assert_eq!(at(out(3)), at(PathEvent::SegmentEnd { id: 7 }));
    // 20,000 counts along the circle (chords of one tick: within one tick's travel)
    let k = at(out(2)).unwrap();
    let travel = |to: usize| -> f64 {
        r.pos[start..=to]
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum()
    };
    assert!(
        travel(k) >= 20_000.0 - 1e-3 && travel(k - 1) < 20_000.0,
        "{}",
        travel(k)
    );
}

#[test]
fn bad_curves_are_refused_and_change_nothing() {
    let c = freeform();
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    p.push(line(1, pt(&[2000.0, 0.0]), 3e4, Transition::Exact))
        .unwrap();
    let q = p.queued();
    let tr = Transition::MaxDeviation(5.0);
    let mut bad = |s: CurveSegment, e: PathError| {
        assert_eq!(p.push_curve(&s), Err(e));
        assert_eq!(p.queued(), q);
        assert_eq!(p.last_end, pt(&[2000.0, 0.0]));
    };
    bad(curve_seg(2, &c, 3e4, tr, 0.0), PathError::NonPositive);
    bad(curve_seg(2, &c, 3e4, tr, f64::NAN), PathError::NotFinite);
    bad(curve_seg(2, &c, 3e4, tr, 1e-300), PathError::OutOfRange);
    bad(
        curve_seg(2, &c, f64::INFINITY, tr, 0.5),
        PathError::NotFinite,
    );
    bad(curve_seg(2, &c, 0.0, tr, 0.5), PathError::NonPositive);
    bad(
        curve_seg(2, &c, 3e4, Transition::TimeShift(5.0), 0.5),
        PathError::TimeShift,
    );
    // not from the path's end
    let off = Nurbs::new(
        1,
        2,
        &[2001.0, 0.0, 3000.0, 0.0],
        &[1.0, 1.0],
        &[0.0, 0.0, 1.0, 1.0],
    )
    .unwrap();
    bad(curve_seg(2, &off, 3e4, tr, 0.5), PathError::CurveStart);
    // a stop in the middle (a cusp: three equal control points of a cubic)
    let cusp = Nurbs::new(
        3,
        2,
        &[
            2000.0, 0.0, 3000.0, 0.0, 4000.0, 1000.0, 4000.0, 1000.0, 4000.0, 1000.0, 5000.0, 0.0,
            6000.0, 0.0,
        ],
        &[1.0; 7],
        &[0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0],
    )
    .unwrap();
    bad(curve_seg(2, &cusp, 3e4, tr, 0.5), PathError::Curve);
    // three axes of curve on a two-axis path
    let c3 = Nurbs::new(
        1,
        3,
        &[2000.0, 0.0, 0.0, 3000.0, 0.0, 0.0],
        &[1.0, 1.0],
        &[0.0, 0.0, 1.0, 1.0],
    )
    .unwrap();
    bad(curve_seg(2, &c3, 3e4, tr, 0.5), PathError::BadAxis);
    // too many pieces for what is free now, then for the whole ring
    let mut small = Path::with_capacity(6);
    small.reset(pt(&[0.0, 0.0]), limits(2, TS), 6).unwrap();
    small
        .push(line(1, pt(&[2000.0, 0.0]), 3e4, Transition::Exact))
        .unwrap();
    assert_eq!(
        small.push_curve(&curve_seg(2, &c, 3e4, tr, 0.5)),
        Err(PathError::Curve)
    );
    assert_eq!(small.queued(), 1);
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    p.push(line(1, pt(&[2000.0, 0.0]), 3e4, Transition::Exact))
        .unwrap();
    let mut k = 0;
    while p.free() > 4 {
        k += 1;
        let x = 2000.0 + k as f64;
        p.push(line(1 + k, pt(&[x, 0.0]), 3e4, Transition::Exact))
            .unwrap();
    }
    let mut c2 = freeform();
    let x = 2000.0 + k as f64;
    let mut ctrl = [0.0; 16];
    for i in 0..8 {
        let q = c.control_point(i).unwrap();
        ctrl[2 * i] = q[0] - 2000.0 + x;
        ctrl[2 * i + 1] = q[1];
    }
    c2.set(
        3,
        2,
        &ctrl,
        &[1.0, 1.0, 2.0, 1.0, 0.5, 1.0, 1.0, 1.0],
        c.knots(),
    )
    .unwrap();
    let q = p.queued();
    assert_eq!(
        p.push_curve(&curve_seg(99, &c2, 3e4, tr, 0.5)),
        Err(PathError::Full)
    );
    assert_eq!(p.queued(), q);
}
