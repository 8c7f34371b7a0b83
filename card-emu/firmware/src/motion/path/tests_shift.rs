//! Time-shifted lines (`shift.rs`): overlapping profiles within the limits and the
//! tolerance, one axis's speed changed without a stop, halts and holds in an overlap, a
//! segment arriving late, and what is refused.

use super::tests::*;
use super::*;
use crate::testkit::rng::Rng;

/// Runs `verts` as lines joined by `tr` (the first from `verts[0]`); returns the run.
fn chain(naxes: usize, verts: &[V], feeds: &[f64], tr: Transition) -> (Path, Run) {
    let mut p = path(naxes, TS, verts[0]);
    for (i, w) in verts.windows(2).enumerate() {
        let mut s = line(i as u32 + 1, w[1], feeds[i % feeds.len()], tr);
        s.last = i + 2 == verts.len();
        p.push(s).unwrap();
    }
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 1_000_000), "never idle");
    (p, r)
}

/// (id, tick) of events, in order.
type IdTicks = Vec<(u32, usize)>;

/// Ticks of each start and end event, by id.
fn event_ticks(r: &Run) -> (IdTicks, IdTicks) {
    let (mut st, mut en) = (vec![], vec![]);
    for &(k, e) in &r.events {
        match e {
            PathEvent::SegmentStart { id } => st.push((id, k)),
            PathEvent::SegmentEnd { id } => en.push((id, k)),
            _ => {}
        }
    }
    (st, en)
}

/// Thinh Fig 10 in two and three axes: a square, a zig-zag and a random polyline joined by
/// time-shifted profiles keep every axis limit and the tolerance, start each segment while the
/// one before still runs (ids in order), end exactly, and take less time than exact stops; with
/// a tolerance of 0 nothing overlaps and the time is the exact stops' time.
#[test]
fn time_shifted_lines_overlap_within_limits_and_tolerance() {
    let mut rng = Rng::new(17);
    let random: Vec<V> = (0..12)
        .map(|_| {
            pt(&[
                rng.uniform(-40_000.0, 40_000.0),
                rng.uniform(-40_000.0, 40_000.0),
                rng.uniform(-40_000.0, 40_000.0),
            ])
        })
        .collect();
    let square = [
        pt(&[0.0, 0.0]),
        pt(&[30_000.0, 0.0]),
        pt(&[30_000.0, 30_000.0]),
        pt(&[0.0, 30_000.0]),
        pt(&[0.0, 0.0]),
    ];
    let zigzag: Vec<V> = (0..10)
        .map(|i| pt(&[i as f64 * 4_000.0, if i % 2 == 0 { 0.0 } else { 3_000.0 }]))
        .collect();
    for (what, n, verts, tol) in [
        ("square", 2, &square[..], 500.0),
        ("zig-zag", 2, &zigzag[..], 100.0),
        ("random 3-axis", 3, &random[..], 2_000.0),
    ] {
        let feeds = [9e4, 3e4, 6e4];
        let (p, r) = chain(n, verts, &feeds, Transition::TimeShift(tol));
        r.assert_within(&p.lim, what);
        assert_eq!(r.pos.last().unwrap(), verts.last().unwrap(), "{what}: end");
        let dev = max_deviation_in_order(&r, verts);
        assert!(dev <= tol, "{what}: deviation {dev} > {tol}");
        let (st, en) = event_ticks(&r);
        let ids: Vec<u32> = (1..verts.len() as u32).collect();
        assert_eq!(st.iter().map(|x| x.0).collect::<Vec<_>>(), ids, "{what}");
        assert_eq!(en.iter().map(|x| x.0).collect::<Vec<_>>(), ids, "{what}");
        let overlaps = st[1..].iter().zip(&en).filter(|(s, e)| s.1 < e.1).count();
        assert_eq!(overlaps, ids.len() - 1, "{what}: every junction overlaps");
        // with a tolerance of 0 each segment starts after the one before has ended
        let (_, zero) = chain(n, verts, &feeds, Transition::TimeShift(0.0));
        zero.assert_within(&p.lim, what);
        let (st0, en0) = event_ticks(&zero);
        assert!(st0[1..].iter().zip(&en0).all(|(s, e)| s.1 >= e.1), "{what}");
        let (_, blended) = chain(n, verts, &feeds, Transition::MaxDeviation(tol));
        let (t, t0, tb) = (r.pos.len(), zero.pos.len(), blended.pos.len());
        println!(
            "{what}: time-shifted {t} ticks (deviation {dev:.1}), rest to rest {t0}, \
             G2 blends of the same tolerance {tb}"
        );
        assert!(t < t0, "{what}: {t} ticks, rest to rest {t0}");
    }
}

/// Thinh's own test (Fig 10): one axis, speed segments of different feeds blended by shifting
/// each one's profile in time: the axis never stops in between, and keeps its limits.
#[test]
fn time_shift_on_one_axis_changes_speed_without_stopping() {
    let verts = [
        pt(&[0.0]),
        pt(&[20_000.0]),
        pt(&[60_000.0]),
        pt(&[70_000.0]),
        pt(&[100_000.0]),
    ];
    let feeds = [3e4, 9e4, 1e4, 6e4];
    let (p, r) = chain(1, &verts, &feeds, Transition::TimeShift(1.0));
    r.assert_within(&p.lim, "one axis");
    assert_eq!(*r.pos.last().unwrap(), verts[4]);
    let (st, en) = event_ticks(&r);
    // from the second segment's start to the third one's end (the three junctions) the axis
    // never rests
    let (a, b) = (st[1].1, en[2].1);
    let slowest = (a..b)
        .map(|k| (r.pos[k][0] - r.pos[k - 1][0]) / TS)
        .fold(f64::INFINITY, f64::min);
    assert!(slowest > 0.5 * 1e4, "slowest {slowest} counts/s");
}

/// A halt in the middle of an overlap (gentle or hard) stops both profiles within the limits,
/// in bounded time, and stays; `clear` aborts both segments. A hold there stops and resumes to
/// the exact end within the tolerance.
#[test]
fn halt_and_hold_in_a_time_shifted_overlap() {
    let verts = [
        pt(&[0.0, 0.0]),
        pt(&[30_000.0, 0.0]),
        pt(&[30_000.0, 30_000.0]),
        pt(&[60_000.0, 30_000.0]),
    ];
    let tol = 800.0;
    let mut stopped = vec![];
    for (hold, decel) in [(false, 1e6), (false, 1e8), (true, 0.0)] {
        let mut p = path(2, TS, verts[0]);
        for (i, w) in verts.windows(2).enumerate() {
            p.push(line(i as u32 + 1, w[1], 6e4, Transition::TimeShift(tol)))
                .unwrap();
        }
        let mut r = Run::default();
        let mut found = false;
        for _ in 0..100_000 {
            r.go(&mut p, 1.0, 1);
            if p.chain_overlap().is_some_and(|t| t >= 0.008) {
                found = true;
                break;
            }
        }
        assert!(found, "no overlap");
        let ovr = if hold { 0.0 } else { 1.0 };
        if !hold {
            p.halt(decel, 1e10);
        }
        let mut ticks = 0;
        r.go(&mut p, ovr, 1);
        while p.is_moving() {
            r.go(&mut p, ovr, 1);
            ticks += 1;
            assert!(ticks < 200, "the stop takes {ticks} ticks");
        }
        let here = p.position();
        r.go(&mut p, ovr, 50);
        assert_eq!(p.position(), here, "stays");
        // the first line decelerates at its own limit already and ends where it would have;
        // the second one stops sooner the harder the halt
        assert_eq!(here[0], 30_000.0);
        if !hold {
            stopped.push(here[1]);
        }

        r.assert_within(&p.lim, "stop in an overlap");
        if hold {
            assert!(r.go(&mut p, 1.0, 100_000), "resumes");
            assert_eq!(*r.pos.last().unwrap(), verts[3]);
            r.assert_within(&p.lim, "resume");
            let (_, en) = r.ids();
            assert_eq!(en, [1, 2, 3]);
        } else {
            let mut aborted = vec![];
            p.clear(&mut |id| aborted.push(id)).unwrap();
            let (_, en) = r.ids();
            assert_eq!(
                en.len() + aborted.len(),
                3,
                "ended {en:?}, aborted {aborted:?}"
            );
            assert!(
                aborted.len() >= 2,
                "both running segments aborted: {aborted:?}"
            );
        }
        let dev = max_deviation_in_order(&r, &verts);
        assert!(dev <= tol, "deviation {dev}");
    }
    assert!(
        stopped[1] < stopped[0],
        "second line stopped at {stopped:?}"
    );
}

/// A segment that comes late overlaps only what is left of the one before (or starts from rest
/// once it has ended): no jump, the limits and the tolerance kept.
#[test]
fn time_shift_segment_arriving_late_overlaps_what_is_left() {
    for wait in [50usize, 200, 330, 400, 2_000] {
        let mut p = path(2, TS, pt(&[0.0, 0.0]));
        let tol = 1_000.0;
        p.push(line(
            1,
            pt(&[20_000.0, 0.0]),
            6e4,
            Transition::TimeShift(tol),
        ))
        .unwrap();
        let mut r = Run::default();
        r.go(&mut p, 1.0, wait);
        p.push(line(
            2,
            pt(&[20_000.0, 20_000.0]),
            6e4,
            Transition::TimeShift(tol),
        ))
        .unwrap();
        assert!(r.go(&mut p, 1.0, 100_000));
        r.assert_within(&p.lim, "late");
        assert_eq!(*r.pos.last().unwrap(), pt(&[20_000.0, 20_000.0]));
        let verts = [
            pt(&[0.0, 0.0]),
            pt(&[20_000.0, 0.0]),
            pt(&[20_000.0, 20_000.0]),
        ];
        assert!(max_deviation_in_order(&r, &verts) <= tol);
    }
}

/// Time-shifted transitions need lines: on an arc, after an arc, and a blend after a
/// time-shifted line are refused, and the path is unchanged.
#[test]
fn time_shift_refusals() {
    let mut p = path(2, TS, pt(&[0.0, 0.0]));
    let arc = |id, tr| arc_xy(id, [0.0, 5_000.0], pt(&[0.0, 10_000.0]), 5e4, tr);
    assert_eq!(
        p.push(arc(1, Transition::TimeShift(10.0))),
        Err(PathError::TimeShift)
    );
    assert_eq!(p.queued(), 0);
    p.push(arc(1, Transition::Exact)).unwrap();
    assert_eq!(
        p.push(line(
            2,
            pt(&[5_000.0, 10_000.0]),
            5e4,
            Transition::TimeShift(10.0)
        )),
        Err(PathError::TimeShift)
    );
    p.push(line(2, pt(&[5_000.0, 10_000.0]), 5e4, Transition::Exact))
        .unwrap();
    p.push(line(
        3,
        pt(&[5_000.0, 0.0]),
        5e4,
        Transition::TimeShift(10.0),
    ))
    .unwrap();
    for tr in [
        Transition::MaxDeviation(10.0),
        Transition::CornerDistance(10.0),
    ] {
        assert_eq!(
            p.push(line(4, pt(&[0.0, 0.0]), 5e4, tr)),
            Err(PathError::TimeShift)
        );
    }
    assert_eq!(p.queued(), 3);
    p.push(line(4, pt(&[0.0, 0.0]), 5e4, Transition::Exact))
        .unwrap();
    let mut r = Run::default();
    assert!(r.go(&mut p, 1.0, 100_000));
    r.assert_within(&p.lim, "mixed");
    assert_eq!(p.position(), pt(&[0.0, 0.0]));
    let (_, en) = r.ids();
    assert_eq!(en, [1, 2, 3, 4]);
}
