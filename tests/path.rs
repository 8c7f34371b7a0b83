//! The continuous path on the stepped emulated card: blends within the tolerance, every axis
//! within its limits (finite differences of the commanded positions per tick), segment events
//! in order, exact ends, starvation and resume, halts in a blend, each buffer and transition
//! mode (Thinh's time-shifted blending included), dwells and outputs, NURBS curves as path
//! segments, and the refusals.
mod common;

use common::stepped_card;
use motioncard_sdk::{
    ArcSpec, Card, ErrorKind, EventKind, Group, GroupSettings, GroupState, Nurbs, OutputAt,
    PathBuffer, PathItem, PathSettings, PauseState, Plane, Segment, Transition,
};
use std::time::Duration;

const T: Duration = Duration::from_secs(60);
/// Axis limits of these tests (counts): 1e5 counts/s, 1e6 counts/s², 1e8 counts/s³; the Y axis
/// (and Z) half as fast where a test says so.
const V: f64 = 1e5;
const A: f64 = 1e6;
const J: f64 = 1e8;

fn path_card(n: usize, settings: &PathSettings) -> (Card, Group) {
    let card = stepped_card();
    let axes: Vec<usize> = (0..n).collect();
    for &a in &axes {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&axes)).unwrap();
    g.enable().unwrap();
    g.configure_path(settings).unwrap();
    (card, g)
}

/// What a run recorded: the commanded position of every axis per tick, and the events.
struct Run {
    pos: Vec<Vec<f64>>,
    events: Vec<motioncard_sdk::CardEvent>,
}

fn cmd(card: &Card, n: usize) -> Vec<f64> {
    (0..n)
        .map(|a| card.axis(a).unwrap().status().unwrap().raw.cmd_pos)
        .collect()
}

fn drain(card: &Card, into: &mut Vec<motioncard_sdk::CardEvent>) {
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        into.push(e);
    }
}

/// Step until the group is at rest in Standby (or `max` ticks), recording.
fn run(card: &Card, g: &Group, n: usize, max: usize) -> Run {
    let sim = card.sim().unwrap();
    let mut r = Run {
        pos: vec![cmd(card, n)],
        events: Vec::new(),
    };
    for _ in 0..max {
        sim.step(1);
        r.pos.push(cmd(card, n));
        drain(card, &mut r.events);
        if g.status().unwrap().0 == GroupState::Standby {
            break;
        }
    }
    r
}

/// The largest |finite difference| of order 1, 2, 3 of axis `a` over Ts, Ts², Ts³, and the
/// tick where each is.
fn peaks(pos: &[Vec<f64>], a: usize, ts: f64) -> ([f64; 3], [usize; 3]) {
    let mut p = [0.0f64; 3];
    let mut at = [0usize; 3];
    let x: Vec<f64> = pos.iter().map(|q| q[a]).collect();
    for (k, w) in x.windows(4).enumerate() {
        let v = (w[3] - w[2]) / ts;
        let acc = (w[3] - 2.0 * w[2] + w[1]) / (ts * ts);
        let jerk = (w[3] - 3.0 * w[2] + 3.0 * w[1] - w[0]) / (ts * ts * ts);
        for (i, d) in [v, acc, jerk].into_iter().enumerate() {
            if d.abs() > p[i] {
                p[i] = d.abs();
                at[i] = k + 3;
            }
        }
    }
    (p, at)
}

fn assert_limits(r: &Run, lim: &PathSettings, what: &str) {
    let ts = 1e-4; // the default servo rate, 10 kHz
    for a in 0..lim.vmax.len() {
        let (p, at) = peaks(&r.pos, a, ts);
        let l = [lim.vmax[a], lim.amax[a], lim.jmax[a]];
        for k in 0..3 {
            let t = at[k];
            assert!(
                p[k] <= 1.01 * l[k],
                "{what}: axis {a} {} peak {} over its limit {} at tick {t} of {}: {:?}",
                ["velocity", "acceleration", "jerk"][k],
                p[k],
                l[k],
                r.pos.len(),
                &r.pos[t.saturating_sub(3)..(t + 2).min(r.pos.len())]
            );
        }
    }
}

/// Distance from `p` to the segment `a`–`b` (independent of the card's geometry).
fn dist_to_segment(p: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let l2: f64 = d.iter().map(|x| x * x).sum();
    let t = if l2 > 0.0 {
        (p.iter()
            .zip(a)
            .zip(&d)
            .map(|((p, a), d)| (p - a) * d)
            .sum::<f64>()
            / l2)
            .clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.iter()
        .zip(a)
        .zip(&d)
        .map(|((p, a), d)| (p - a - t * d).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn dist_to_polyline(p: &[f64], pts: &[Vec<f64>]) -> f64 {
    pts.windows(2)
        .map(|w| dist_to_segment(p, &w[0], &w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// The largest distance of a commanded point of the run from the polyline.
fn farthest_off(r: &Run, pts: &[Vec<f64>]) -> f64 {
    r.pos
        .iter()
        .map(|p| dist_to_polyline(p, pts))
        .fold(0.0, f64::max)
}

fn ids(r: &Run, kind: EventKind) -> Vec<u32> {
    r.events
        .iter()
        .filter(|e| e.kind == kind)
        .map(|e| e.value as u32)
        .collect()
}

fn square(side: f64) -> Vec<Vec<f64>> {
    vec![
        vec![0.0, 0.0],
        vec![side, 0.0],
        vec![side, side],
        vec![0.0, side],
        vec![0.0, 0.0],
    ]
}

fn stream_polyline(g: &Group, pts: &[Vec<f64>], feed: f64, tol: f64, buffer: PathBuffer) {
    let n = pts.len();
    let segs = pts[1..].iter().enumerate().map(|(i, p)| {
        let s = Segment::line(i as u32 + 1, p, feed, tol).buffer(buffer);
        if i + 2 == n {
            s.last()
        } else {
            s
        }
    });
    g.stream_path(segs, |_| {}).unwrap().unwrap();
}

#[test]
fn a_blended_square_keeps_within_the_tolerance_and_every_axis_limit() {
    let lim = PathSettings::uniform(2, V, A, J);
    for tol in [10.0, 100.0] {
        let (card, g) = path_card(2, &lim);
        let pts = square(50_000.0);
        stream_polyline(&g, &pts, 80_000.0, tol, PathBuffer::BlendingLow);
        let r = run(&card, &g, 2, 200_000);
        assert_eq!(g.status().unwrap().0, GroupState::Standby);
        let worst = farthest_off(&r, &pts);
        assert!(
            worst <= tol * (1.0 + 1e-9),
            "tolerance {tol}: {worst} off the square"
        );
        assert!(
            worst > 0.05 * tol,
            "tolerance {tol}: corners not blended ({worst})"
        );
        assert_limits(&r, &lim, "square");
        assert_eq!(ids(&r, EventKind::SegmentStart), vec![1, 2, 3, 4]);
        assert_eq!(ids(&r, EventKind::SegmentEnd), vec![1, 2, 3, 4]);
        assert_eq!(r.pos.last().unwrap(), &vec![0.0, 0.0], "the end is exact");
        // No exact stop at the corners: the path speed stays up through them (until the
        // end, where the group settles in position).
        let end = r
            .pos
            .iter()
            .rposition(|p| p != r.pos.last().unwrap())
            .unwrap();
        let stops = r
            .pos
            .windows(2)
            .take(end)
            .skip(10)
            .filter(|w| w[0] == w[1])
            .count();
        assert_eq!(stops, 0, "tolerance {tol}: the path stopped");
        assert!(r.events.iter().all(|e| e.kind != EventKind::PathStarved));
    }
}

/// Issue 39: `path_done` counts the segments ended since the group's last enable: 4 after a
/// square, 0 again after a disable and an enable, 4 after the next square (it carried on,
/// 504 to 1008, before).
#[test]
fn path_done_counts_from_the_last_group_enable() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    for round in 0..2 {
        stream_polyline(
            &g,
            &square(20_000.0),
            80_000.0,
            10.0,
            PathBuffer::BlendingLow,
        );
        run(&card, &g, 2, 200_000);
        let st = g.status().unwrap();
        assert_eq!(
            (st.0, st.1.path_done),
            (GroupState::Standby, 4),
            "round {round}"
        );
        g.disable().unwrap();
        assert_eq!(
            g.status().unwrap().1.path_done,
            4,
            "a disable keeps the count"
        );
        g.enable().unwrap();
        assert_eq!(
            g.status().unwrap().1.path_done,
            0,
            "round {round}: enabled again"
        );
    }
}

#[test]
fn tolerance_zero_and_buffered_stop_exactly_at_every_corner() {
    let lim = PathSettings::uniform(2, V, A, J);
    for (tol, buffer) in [
        (0.0, PathBuffer::BlendingLow),
        (100.0, PathBuffer::Buffered),
    ] {
        let (card, g) = path_card(2, &lim);
        let pts = square(20_000.0);
        stream_polyline(&g, &pts, 80_000.0, tol, buffer);
        let r = run(&card, &g, 2, 200_000);
        for c in &pts[1..4] {
            assert!(
                r.pos.iter().any(|p| p == c),
                "{buffer:?} {tol}: never exactly at the corner {c:?}"
            );
        }
        let worst = farthest_off(&r, &pts);
        assert!(worst < 1e-6, "{buffer:?}: {worst} off the square");
        assert_limits(&r, &lim, "exact stops");
    }
}

#[test]
fn blending_high_runs_the_corner_faster_than_blending_low() {
    let lim = PathSettings::uniform(2, V, A, J);
    let corner_speed = |buffer: PathBuffer| {
        let (card, g) = path_card(2, &lim);
        // A slow first line into a fast second one through a shallow corner.
        let segs = vec![
            Segment::line(1, &[40_000.0, 0.0], 20_000.0, 200.0),
            Segment::line(2, &[80_000.0, 4_000.0], 90_000.0, 200.0)
                .buffer(buffer)
                .last(),
        ];
        g.stream_path(segs, |_| {}).unwrap();
        let r = run(&card, &g, 2, 200_000);
        assert_limits(&r, &lim, "blend speed");
        // The speed where the path passes closest to the corner.
        let (k, _) = r
            .pos
            .iter()
            .enumerate()
            .map(|(k, p)| (k, (p[0] - 40_000.0).hypot(p[1])))
            .fold((0, f64::INFINITY), |b, x| if x.1 < b.1 { x } else { b });
        let p = &r.pos;
        (p[k + 1][0] - p[k][0]).hypot(p[k + 1][1] - p[k][1]) / 1e-4
    };
    let low = corner_speed(PathBuffer::BlendingLow);
    let high = corner_speed(PathBuffer::BlendingHigh);
    let next = corner_speed(PathBuffer::BlendingNext);
    let prev = corner_speed(PathBuffer::BlendingPrevious);
    assert!(low <= 20_000.0 * 1.001, "BlendingLow corner at {low}");
    assert!(
        (prev - low).abs() < 1.0,
        "BlendingPrevious {prev} vs low {low}"
    );
    assert!(high > 1.5 * low, "BlendingHigh {high} vs low {low}");
    assert!(
        (next - high).abs() < 1.0,
        "BlendingNext {next} vs high {high}"
    );
}

#[test]
fn corner_distance_starts_the_blend_that_far_before_the_corner() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let segs = vec![
        Segment::line(1, &[30_000.0, 0.0], 50_000.0, 0.0),
        Segment::line(2, &[30_000.0, 30_000.0], 50_000.0, 0.0)
            .transition(Transition::CornerDistance(2_000.0))
            .last(),
    ];
    g.stream_path(segs, |_| {}).unwrap();
    let r = run(&card, &g, 2, 200_000);
    // Leaves the first line (y > 0) no earlier than 2000 counts before the corner, and not
    // much later either.
    let first_off = r.pos.iter().find(|p| p[1] > 1e-6).unwrap();
    assert!(
        first_off[0] >= 28_000.0 - 1e-6 && first_off[0] <= 28_200.0,
        "the blend starts at x = {}",
        first_off[0]
    );
    assert_limits(&r, &lim, "corner distance");
}

#[test]
fn a_path_that_runs_dry_stops_within_its_limits_and_resumes_without_a_jump() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let sim = card.sim().unwrap();
    let pts: Vec<Vec<f64>> = (0..=12)
        .map(|k| vec![k as f64 * 10_000.0, if k % 2 == 1 { 5_000.0 } else { 0.0 }])
        .collect();
    let seg = |i: usize| Segment::line(i as u32, &pts[i], 80_000.0, 100.0);
    g.stream_path((1..=4).map(seg), |_| {}).unwrap();
    let mut r = Run {
        pos: vec![cmd(&card, 2)],
        events: Vec::new(),
    };
    let step = |r: &mut Run, n: usize| {
        for _ in 0..n {
            sim.step(1);
            r.pos.push(cmd(&card, 2));
            drain(&card, &mut r.events);
        }
    };
    // Run until it starves, send more while it brakes.
    while !r.events.iter().any(|e| e.kind == EventKind::PathStarved) {
        step(&mut r, 1);
        assert!(r.pos.len() < 100_000);
    }
    step(&mut r, 50);
    g.stream_path((5..=8).map(seg), |_| {}).unwrap();
    // Then let it come to rest at the end of what it has, and send the rest.
    let mut still = 0;
    while still < 200 {
        step(&mut r, 1);
        let n = r.pos.len();
        still = if r.pos[n - 1] == r.pos[n - 2] {
            still + 1
        } else {
            0
        };
    }
    assert_eq!(
        r.pos.last().unwrap(),
        &pts[8],
        "at rest at the end of what was queued"
    );
    g.stream_path(
        (9..=12).map(|i| if i == 12 { seg(i).last() } else { seg(i) }),
        |_| {},
    )
    .unwrap();
    let rest = run(&card, &g, 2, 200_000);
    r.pos.extend(rest.pos.into_iter().skip(1));
    r.events.extend(rest.events);
    assert_limits(&r, &lim, "starvation and resume");
    assert_eq!(
        ids(&r, EventKind::SegmentEnd),
        (1..=12).collect::<Vec<u32>>()
    );
    assert_eq!(r.pos.last().unwrap(), &pts[12]);
    let worst = farthest_off(&r, &pts);
    assert!(worst <= 100.0 * (1.0 + 1e-9), "{worst}");
}

#[test]
fn a_halt_in_a_blend_stops_within_the_limits_and_aborts_the_rest() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let sim = card.sim().unwrap();
    let pts = square(50_000.0);
    stream_polyline(&g, &pts, 80_000.0, 500.0, PathBuffer::BlendingLow);
    let mut r = Run {
        pos: vec![cmd(&card, 2)],
        events: Vec::new(),
    };
    // Into the first blend: the first tick off the first line.
    while r.pos.last().unwrap()[1] <= 0.0 {
        sim.step(1);
        r.pos.push(cmd(&card, 2));
        drain(&card, &mut r.events);
        assert!(r.pos.len() < 100_000);
    }
    let halt = g.halt(5e5, 5e7).unwrap();
    let rest = run(&card, &g, 2, 100_000);
    r.pos.extend(rest.pos.into_iter().skip(1));
    r.events.extend(rest.events);
    halt.wait(T).unwrap();
    assert_limits(&r, &lim, "halt in a blend");
    let aborted = r
        .events
        .iter()
        .filter(|e| e.kind == EventKind::GroupMotionAborted)
        .count();
    assert!(aborted >= 3, "{aborted} segments aborted");
    let worst = farthest_off(&r, &pts);
    assert!(
        worst <= 500.0 * (1.0 + 1e-9),
        "the halt left the path: {worst}"
    );
    // The group takes a new path from where it stopped.
    let m = g
        .path_push(&Segment::line(9, &[0.0, 0.0], 50_000.0, 0.0).last().into())
        .unwrap();
    m.wait(T).unwrap();
    assert_eq!(cmd(&card, 2), vec![0.0, 0.0]);
}

/// A blended 50,000-count square streamed and 0.3 s under way, for an Aborting segment.
fn square_under_way() -> (Card, Group, PathSettings) {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    stream_polyline(
        &g,
        &square(50_000.0),
        80_000.0,
        100.0,
        PathBuffer::BlendingLow,
    );
    card.sim().unwrap().step(3_000);
    (card, g, lim)
}

#[test]
fn aborting_stops_the_path_and_starts_the_new_segment_from_there() {
    let (card, g, lim) = square_under_way();
    let m = g
        .path_push(
            &Segment::line(7, &[-10_000.0, -10_000.0], 50_000.0, 0.0)
                .buffer(PathBuffer::Aborting)
                .last()
                .into(),
        )
        .unwrap();
    let r = run(&card, &g, 2, 200_000);
    m.wait(T).unwrap();
    assert_eq!(r.pos.last().unwrap(), &vec![-10_000.0, -10_000.0]);
    assert_limits(&r, &lim, "aborting");
    assert!(r
        .events
        .iter()
        .any(|e| e.kind == EventKind::GroupMotionAborted));
    assert_eq!(ids(&r, EventKind::SegmentEnd).last(), Some(&7));
}

#[test]
fn dwells_and_outputs_fire_where_the_program_says() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let items: Vec<PathItem> = vec![
        Segment::line(1, &[20_000.0, 0.0], 50_000.0, 0.0).into(),
        PathItem::Output {
            output: 3,
            on: true,
            at: OutputAt::Distance(5_000.0),
        },
        PathItem::Output {
            output: 3,
            on: false,
            at: OutputAt::End,
        },
        Segment::line(2, &[20_000.0, 20_000.0], 50_000.0, 0.0).into(),
        Segment::dwell(3, 0.05).into(),
        Segment::line(4, &[0.0, 20_000.0], 50_000.0, 0.0)
            .last()
            .into(),
    ];
    g.stream_path(items, |_| {}).unwrap();
    let sim = card.sim().unwrap();
    let mut on_at = None;
    let mut off_at = None;
    let mut rest_ticks = 0;
    let mut prev = cmd(&card, 2);
    for k in 0..100_000 {
        sim.step(1);
        let p = cmd(&card, 2);
        let out = card.outputs().unwrap();
        if out & 8 != 0 && on_at.is_none() {
            on_at = Some(p.clone());
        }
        if on_at.is_some() && out & 8 == 0 && off_at.is_none() {
            off_at = Some(p.clone());
        }
        if p == prev && p == vec![20_000.0, 20_000.0] {
            rest_ticks += 1;
        }
        prev = p;
        if g.status().unwrap().0 == GroupState::Standby {
            break;
        }
        assert!(k < 99_999);
    }
    let on = on_at.expect("output 3 never set");
    let off = off_at.expect("output 3 never cleared");
    // Set 5000 counts into segment 2 (within one tick's travel), cleared at its end.
    assert!(
        on[0] == 20_000.0 && (on[1] - 5_000.0).abs() <= 5.0 + 1e-9,
        "{on:?}"
    );
    assert_eq!(off, vec![20_000.0, 20_000.0]);
    // The dwell holds the corner for 50 ms (500 ticks) or a settle more.
    assert!(
        (500..=560).contains(&rest_ticks),
        "{rest_ticks} ticks at the dwell"
    );
}

#[test]
fn bad_segments_get_their_own_error_and_change_nothing() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (_card, g) = path_card(2, &lim);
    let push = |s: Segment| g.path_push(&s.into()).map(|_| ()).unwrap_err().kind();
    assert_eq!(
        push(Segment::line(1, &[f64::NAN, 0.0], 1e4, 0.0)),
        ErrorKind::NotFinite
    );
    assert_eq!(
        push(Segment::line(1, &[1.0, 0.0], 1e300, 0.0)),
        ErrorKind::LimitRange
    );
    assert_eq!(
        push(Segment::line(1, &[0.0, 0.0], 1e4, 0.0)),
        ErrorKind::PathZeroLength
    );
    assert_eq!(push(Segment::line(1, &[1.0], 1e4, 0.0)), ErrorKind::BadAxis);
    assert_eq!(
        push(Segment::line(1, &[1e300, 0.0], 1e4, 0.0)),
        ErrorKind::OutOfRange
    );
    assert_eq!(push(Segment::dwell(1, -1.0)), ErrorKind::NonPositiveLimit);
    let (state, st) = g.status().unwrap();
    assert_eq!((state, st.path_queued), (GroupState::Standby, 0));
    assert_eq!(st.path_free, motioncard_sdk::proto::PATH_LEN as u32);
}

#[test]
fn the_buffer_holds_4096_segments_and_reports_its_room() {
    let mut lim = PathSettings::uniform(2, V, A, J);
    lim.low_water = 100;
    // (collinear lines: each its own segment, not one line)
    lim.chord_fit = false;
    let (card, g) = path_card(2, &lim);
    // Hold the path still (0 % feed override) and fill the buffer.
    g.set_override(0.0, 1.0).unwrap();
    let seg = |i: u32| Segment::line(i, &[i as f64 * 10.0, 0.0], 5e4, 1.0);
    g.stream_path((1..=4096).map(seg), |_| {}).unwrap();
    assert_eq!(g.path_free().unwrap(), 0);
    let full = g.path_push(&seg(4097).into()).map(|_| ()).unwrap_err();
    assert_eq!(full.kind(), ErrorKind::QueueFull);
    assert_eq!(g.status().unwrap().1.path_queued, 4096);
    // Let it run: the low-water event comes once the queue falls to 100.
    g.set_override(1.0, 1.0).unwrap();
    let r = run(&card, &g, 2, 2_000_000);
    let lw: Vec<_> = r
        .events
        .iter()
        .filter(|e| e.kind == EventKind::PathLowWater)
        .collect();
    assert_eq!(
        lw.len(),
        1,
        "low-water events; lost {:?}; ended {}; status {:?}",
        card.events_lost(),
        ids(&r, EventKind::SegmentEnd).len(),
        g.status().unwrap()
    );
    assert_eq!(lw[0].value, 100.0);
    assert_eq!(ids(&r, EventKind::SegmentEnd).len(), 4096);
}

/// A stream the card refuses partway answers everything it sent before it returns: the
/// earliest refusal is reported with its index, and `accepted` says how many items the card
/// took (here the two sent behind the refused one too). An output action pushed after the last
/// segment is not the motion `wait_done` waits for.
#[test]
fn a_refused_stream_reports_the_first_refusal_and_what_the_card_accepted() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let items = vec![
        Segment::line(1, &[10_000.0, 0.0], 50_000.0, 10.0),
        Segment::line(2, &[10_000.0, 0.0], 50_000.0, 10.0), // zero length: the card refuses
        Segment::line(3, &[10_000.0, 10_000.0], 50_000.0, 10.0),
        Segment::line(4, &[0.0, 10_000.0], 50_000.0, 10.0).last(),
    ];
    let e = g.stream_path(items, |_| {}).unwrap_err();
    assert_eq!(e.index, 1);
    assert_eq!(e.error.kind(), ErrorKind::PathZeroLength);
    assert_eq!(e.accepted, 3);
    assert_eq!(g.status().unwrap().1.path_queued, 3);
    g.path_push(&Segment::line(5, &[0.0, 0.0], 50_000.0, 10.0).last().into())
        .unwrap();
    // (for a segment queued later; it does not replace segment 5 as what wait_done waits for)
    g.path_push(&PathItem::Output {
        output: 1,
        on: true,
        at: OutputAt::Start,
    })
    .unwrap();
    g.wait_done(T).unwrap();
    assert_eq!(cmd(&card, 2), vec![0.0, 0.0]);
}

/// Thinh's blending (TransitionMode 3) on the card: each line starts while the one before
/// decelerates, within the tolerance and every axis's limits, and ends exactly; an arc with it
/// is refused (`PathMode`) and changes nothing.
#[test]
fn time_shifted_transition_overlaps_lines_on_the_card() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let pts = [
        vec![0.0, 0.0],
        vec![20_000.0, 0.0],
        vec![20_000.0, 20_000.0],
        vec![0.0, 30_000.0],
    ];
    let tol = 300.0;
    let shifted = |i: usize| {
        Segment::line(i as u32, &pts[i], 80_000.0, 0.0).transition(Transition::TimeShift(tol))
    };
    let arc = Segment::arc(
        9,
        ArcSpec::Centre {
            end: [0.0, 0.0],
            centre: [0.0, 15_000.0],
            ccw: true,
        },
        Plane::XY,
        &[],
        80_000.0,
        0.0,
    );
    let e = g
        .path_push(&arc.clone().transition(Transition::TimeShift(tol)).into())
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::PathMode);
    assert_eq!(g.status().unwrap().1.path_queued, 0);
    g.stream_path((1..=3).map(shifted), |_| {}).unwrap();
    let r = run(&card, &g, 2, 200_000);
    assert_limits(&r, &lim, "time shift");
    assert_eq!(r.pos.last().unwrap(), &pts[3]);
    let worst = r
        .pos
        .iter()
        .map(|p| dist_to_polyline(p, &pts))
        .fold(0.0, f64::max);
    assert!(worst <= tol, "deviation {worst}");
    // Segment k + 1 starts before segment k ends.
    let at = |kind: EventKind, id: f64| {
        r.events
            .iter()
            .position(|e| e.kind == kind && e.value == id)
            .unwrap()
    };
    for id in 1..3 {
        let next = at(EventKind::SegmentStart, id as f64 + 1.0);
        assert!(next < at(EventKind::SegmentEnd, id as f64), "segment {id}");
    }
}

/// A rational cubic from (x0, y0) leaving along +x, with a double knot (only C¹ there), 50,000
/// counts long in x; it ends at (x0 + 50,000, y0 + 20,000) heading (1, 2).
fn freeform(x0: f64, y0: f64) -> Nurbs {
    let pts = [
        (0.0, 0.0),
        (10e3, 0.0),
        (15e3, 10e3),
        (25e3, 15e3),
        (30e3, 5e3),
        (40e3, 0.0),
        (45e3, 10e3),
        (50e3, 20e3),
    ];
    let ctrl: Vec<f64> = pts.iter().flat_map(|p| [x0 + p.0, y0 + p.1]).collect();
    let w = [1.0, 1.0, 2.0, 1.0, 0.5, 1.0, 1.0, 1.0];
    let knots = [0.0, 0.0, 0.0, 0.0, 0.2, 0.4, 0.4, 0.7, 1.0, 1.0, 1.0, 1.0];
    Nurbs::new(3, 2, &ctrl, &w, &knots).unwrap()
}

/// The curve as 20,001 points (independent of the card's pieces).
fn sampled(c: &Nurbs) -> Vec<Vec<f64>> {
    (0..=20_000)
        .map(|i| {
            let q = c.point(i as f64 / 20_000.0).unwrap();
            vec![q[0], q[1]]
        })
        .collect()
}

/// A NURBS curve between two blended lines on the card: one segment (its id starts and ends
/// once), several buffer entries, every axis within its limits, the end exact, every point
/// within the blend tolerance of line ∪ curve ∪ line, and on the curve away from the joins
/// within its fit tolerance.
#[test]
fn a_nurbs_segment_runs_within_its_fit_tolerance_between_blended_lines() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    card.sim().unwrap().step(10);
    let curve = freeform(20_000.0, 0.0);
    let (tol, fit) = (10.0, 1.0);
    let items = vec![
        Segment::line(1, &[20_000.0, 0.0], 60_000.0, tol),
        Segment::nurbs(2, curve.clone(), 60_000.0, tol, fit),
        Segment::line(3, &[80_000.0, 40_000.0], 60_000.0, tol).last(),
    ];
    g.stream_path(items, |_| {}).unwrap().unwrap();
    let entries = 4096 - g.path_free().unwrap();
    assert!(entries > 4, "{entries} entries for three segments");
    assert_eq!(g.status().unwrap().1.path_queued, 3);
    let r = run(&card, &g, 2, 200_000);
    assert_limits(&r, &lim, "nurbs");
    assert_eq!(ids(&r, EventKind::SegmentStart), vec![1, 2, 3]);
    assert_eq!(ids(&r, EventKind::SegmentEnd), vec![1, 2, 3]);
    assert_eq!(r.pos.last().unwrap(), &vec![80_000.0, 40_000.0]);
    let poly = sampled(&curve);
    let lines = [
        vec![vec![0.0, 0.0], vec![20_000.0, 0.0]],
        vec![vec![70_000.0, 20_000.0], vec![80_000.0, 40_000.0]],
    ];
    let (mut worst, mut on_curve) = (0.0f64, 0.0f64);
    for p in &r.pos {
        let dc = dist_to_polyline(p, &poly);
        let dl = lines
            .iter()
            .map(|l| dist_to_polyline(p, l))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(dc.min(dl));
        let far = |e: &Vec<f64>| (p[0] - e[0]).hypot(p[1] - e[1]) > 5_000.0;
        if dc < dl && far(&poly[0]) && far(poly.last().unwrap()) {
            on_curve = on_curve.max(dc);
        }
    }
    assert!(worst <= tol * (1.0 + 1e-9), "{worst}");
    assert!(on_curve <= fit * (1.0 + 1e-6), "{on_curve} from the curve");
}

/// PLCopen Aborting with a NURBS curve (relative: from where the path comes to rest): the
/// running path stops along its geometry, what it held is aborted, and the curve, still staged
/// on the card, runs from the point of rest.
#[test]
fn an_aborting_relative_nurbs_segment_starts_where_the_path_stopped() {
    let (card, g, lim) = square_under_way();
    let seg = Segment::nurbs(9, freeform(0.0, 0.0), 50_000.0, 0.0, 0.5)
        .relative()
        .buffer(PathBuffer::Aborting)
        .last();
    let m = g.path_push(&seg.into()).unwrap();
    let r = run(&card, &g, 2, 400_000);
    m.wait(T).unwrap();
    assert_limits(&r, &lim, "aborting nurbs");
    assert!(r
        .events
        .iter()
        .any(|e| e.kind == EventKind::GroupMotionAborted));
    assert_eq!(ids(&r, EventKind::SegmentEnd).last(), Some(&9));
    // the curve ran from the point of rest: its end minus its offset is where the path stood
    let end = r.pos.last().unwrap();
    let rest = [end[0] - 50_000.0, end[1] - 20_000.0];
    let at = r
        .pos
        .iter()
        .position(|p| (p[0] - rest[0]).abs() < 1e-6 && (p[1] - rest[1]).abs() < 1e-6);
    let at = at.unwrap_or_else(|| panic!("never at {rest:?}"));
    // at rest there: the step into it and the step out of it are both the path's first ticks
    let (a, b) = (&r.pos[at - 1], &r.pos[at + 1]);
    assert!((a[0] - rest[0]).abs() < 10.0 && (b[0] - rest[0]).abs() < 10.0);
    assert_eq!(rest[1], 0.0, "stopped on the first side of the square");
}

/// A curve the buffer has no room for yet is refused by a push (`QueueFull`) and changes
/// nothing; a stream waits until it fits. A cusp, a start off the path's end and a
/// time-shifted transition each get their own error.
#[test]
fn nurbs_segments_the_card_refuses_change_nothing() {
    let lim = PathSettings {
        chord_fit: false,
        ..PathSettings::uniform(2, V, A, J)
    };
    let (card, g) = path_card(2, &lim);
    g.set_override(0.0, 1.0).unwrap();
    let seg = |i: u32| Segment::line(i, &[i as f64 * 10.0, 0.0], 5e4, 1.0);
    g.stream_path((1..=4094).map(seg), |_| {}).unwrap();
    let end = 40_940.0;
    let curve = |x0: f64| Segment::nurbs(5000, freeform(x0, 0.0), 5e4, 1.0, 1.0);
    let refused = |s: Segment| {
        let e = g.path_push(&s.into()).map(|_| ()).unwrap_err();
        assert_eq!(g.status().unwrap().1.path_queued, 4094);
        assert_eq!(g.path_free().unwrap(), 2);
        e.kind()
    };
    assert_eq!(refused(curve(end)), ErrorKind::QueueFull);
    assert_eq!(refused(curve(end + 5.0)), ErrorKind::NurbsStart);
    assert_eq!(
        refused(curve(end).transition(Transition::TimeShift(1.0))),
        ErrorKind::PathMode
    );
    let cusp = Nurbs::new(
        3,
        2,
        &[
            end,
            0.0,
            end + 1e3,
            0.0,
            end + 2e3,
            1e3,
            end + 2e3,
            1e3,
            end + 2e3,
            1e3,
            end + 3e3,
            0.0,
            end + 4e3,
            0.0,
        ],
        &[1.0; 7],
        &[0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0],
    )
    .unwrap();
    assert_eq!(
        refused(Segment::nurbs(5000, cusp, 5e4, 1.0, 1.0)),
        ErrorKind::PathCurve
    );
    // with the path running, a stream waits until the curve fits (the card keeps it staged
    // and the end is sent again as the path frees entries)
    g.set_override(1.0, 1.0).unwrap();
    g.stream_path([curve(end).last()], |_| {}).unwrap();
    let st = g.status().unwrap().1;
    assert!(st.path_done > 0, "queued without waiting");
    assert_eq!(st.path_queued + st.path_done, 4095);
    let r = run(&card, &g, 2, 400_000);
    assert_eq!(ids(&r, EventKind::SegmentEnd).last(), Some(&5000));
    assert_eq!(r.pos.last().unwrap(), &vec![end + 50_000.0, 20_000.0]);
}

#[test]
fn the_planner_period_is_checked_read_back_and_keeps_the_limits() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    // 0 held: the card's default (1 ms, every 10 ticks at 10 kHz)
    assert_eq!(g.path_config().unwrap().plan_period, 0.0);
    for (period, kind) in [
        (f64::NAN, ErrorKind::NotFinite),
        (f64::INFINITY, ErrorKind::NotFinite),
        (-1e-3, ErrorKind::OutOfRange),
        (0.0101, ErrorKind::OutOfRange),
    ] {
        let e = g
            .configure_path(&PathSettings {
                plan_period: period,
                ..lim.clone()
            })
            .unwrap_err();
        assert_eq!(e.kind(), kind, "{period}: {e}");
        assert_eq!(g.path_config().unwrap().plan_period, 0.0, "{period}");
    }
    // planned at every servo tick, by default and every 10 ms: the same blended square
    // within the tolerance and every axis limit, in about the same time (within 2 %: the
    // look-ahead decides when to brake for a corner with the lowest limits it looks at, the
    // corner blend's, and a planning step ramps within the limits of what it and the next
    // step reach, the line's own until the corner is that near; planned every tick, the
    // line brakes harder than decided and reaches the corner's speed a little early)
    let mut times = vec![];
    for period in [1e-4, 0.0, 0.01] {
        let s = PathSettings {
            plan_period: period,
            ..lim.clone()
        };
        g.configure_path(&s).unwrap();
        assert_eq!(g.path_config().unwrap().plan_period, period);
        // (each square ends where the next starts)
        let pts = square(50_000.0);
        stream_polyline(&g, &pts, 80_000.0, 10.0, PathBuffer::BlendingLow);
        let r = run(&card, &g, 2, 200_000);
        let what = format!("planner period {period}");
        assert_eq!(g.status().unwrap().0, GroupState::Standby, "{what}");
        let worst = farthest_off(&r, &pts);
        assert!(
            worst <= 10.0 * (1.0 + 1e-9),
            "{what}: {worst} off the square"
        );
        assert_limits(&r, &s, &what);
        assert_eq!(ids(&r, EventKind::SegmentEnd), vec![1, 2, 3, 4], "{what}");
        assert_eq!(r.pos.last().unwrap(), &pts[4], "{what}: the end is exact");
        times.push(r.pos.len() as f64);
    }
    for t in &times[1..] {
        assert!(
            (t / times[0] - 1.0).abs() < 0.02,
            "path times (ticks) {times:?}"
        );
    }
}

/// A circle as CAM posts it: 2,000 chords of a 25,400-count radius (1 inch in 1 µm counts),
/// every coordinate rounded to 2.54 counts (4 decimals in inches). With chord fitting (the
/// default) the stream sends it as curves: the path stays within the tolerance of the points
/// and of the true circle, within every axis limit, ends exactly on the last point, and runs
/// within 10 % of the time of the same circle as one arc. Sent chord by chord it follows the
/// rounding and takes several times as long. A bigger tolerance gives a path no slower: at 1
/// count, less than the rounding, the chords are not fitted and run as slowly as chord by
/// chord; at 3, 10 and 30 counts the circle is fitted, none slower than the one before.
#[test]
fn cam_chords_run_as_the_curve_they_sample() {
    let r = 25_400.0;
    let tol = 10.0;
    let q = |x: f64| (x / 2.54).round() * 2.54;
    let mut pts: Vec<Vec<f64>> = vec![vec![r, 0.0]];
    for i in 1..=2000 {
        let a = std::f64::consts::TAU * i as f64 / 2000.0;
        let p = vec![q(r * a.cos()), q(r * a.sin())];
        if p != *pts.last().unwrap() {
            pts.push(p);
        }
    }
    let feed = 0.8 * V;
    let timed = |fit: bool, arc: bool, tol: f64| {
        let lim = PathSettings {
            chord_fit: fit,
            ..PathSettings::uniform(2, V, A, J)
        };
        let (card, g) = path_card(2, &lim);
        // to the circle's start first, at rest
        g.path_push(&Segment::line(1, &[r, 0.0], feed, 0.0).into())
            .unwrap();
        run(&card, &g, 2, 100_000);
        if arc {
            let c = ArcSpec::Centre {
                end: [r, 0.0],
                centre: [0.0, 0.0],
                ccw: true,
            };
            let s = Segment::arc(2, c, Plane::XY, &[], feed, tol).last();
            g.path_push(&s.into()).unwrap();
        } else {
            let n = pts.len();
            let segs = pts[1..].iter().enumerate().map(|(i, p)| {
                let s = Segment::line(i as u32 + 2, p, feed, tol);
                if i + 2 == n {
                    s.last()
                } else {
                    s
                }
            });
            g.stream_path(segs, |_| {}).unwrap();
        }
        let rr = run(&card, &g, 2, 2_000_000);
        assert_limits(&rr, &lim, "the circle");
        (rr, cmd(&card, 2))
    };
    let (arc, _) = timed(true, true, tol);
    let (fitted, end) = timed(true, false, tol);
    assert_eq!(&end, pts.last().unwrap(), "ends exactly on the last point");
    let off = farthest_off(&fitted, &pts);
    assert!(off <= tol, "{off} counts from the points");
    let from_circle = fitted
        .pos
        .iter()
        .map(|p| (p[0].hypot(p[1]) - r).abs())
        .fold(0.0, f64::max);
    assert!(from_circle <= tol, "{from_circle} counts from the circle");
    let ratio = fitted.pos.len() as f64 / arc.pos.len() as f64;
    assert!(ratio <= 1.1, "{ratio}: chords as curves against the arc");
    let (chords, _) = timed(false, false, tol);
    assert!(
        chords.pos.len() as f64 > 2.0 * fitted.pos.len() as f64,
        "chord by chord: {} ticks, fitted {}",
        chords.pos.len(),
        fitted.pos.len()
    );
    let ticks: Vec<usize> = [1.0, 3.0, 10.0, 30.0]
        .iter()
        .map(|&t| timed(true, false, t).0.pos.len())
        .collect();
    assert!(
        ticks.windows(2).all(|w| w[1] <= w[0]) && ticks[0] > 2 * ticks[2],
        "ticks at tolerances 1, 3, 10, 30 counts: {ticks:?} (chord by chord at 10: {})",
        chords.pos.len()
    );
}

/// A corner next to a fitted curve: the card blends it within its tolerance of the curve,
/// and the curve is up to 0.8 of the tolerance from the points, so the stream gives that
/// corner only what the curve leaves near it. Twenty-two points of a CAM program (LinuxCNC's
/// test program `130207L.ngc`, in µm counts) with a sharp turn between two fitted runs ran
/// 10.9 counts from them at a 10-count tolerance; within it now.
#[test]
fn a_corner_beside_a_fitted_curve_keeps_the_tolerance_of_the_points() {
    let pts: Vec<Vec<f64>> = [
        [7961.0, 2670.6, -52.2],
        [7953.3, 2641.8, -45.1],
        [7953.0, 2640.7, -44.9],
        [7944.3, 2587.1, -37.5],
        [7943.2, 2577.2, -36.7],
        [7939.2, 2517.6, -34.1],
        [7937.9, 2485.2, -33.7],
        [7937.0, 2466.5, -33.4],
        [7932.9, 2432.3, -31.6],
        [7929.5, 2407.6, -31.1],
        [7922.0, 2348.4, -34.3],
        [7921.8, 2347.1, -34.5],
        [7922.5, 2326.9, -40.0],
        [7929.3, 2302.3, -53.2],
        [7941.1, 2303.8, -46.9],
        [7963.2, 2309.9, -38.8],
        [7971.4, 2313.1, -37.2],
        [8016.6, 2327.2, -31.6],
        [8018.2, 2327.6, -31.6],
        [8048.2, 2334.4, -30.7],
        [8086.4, 2341.0, -32.0],
        [8117.0, 2344.5, -34.5],
    ]
    .iter()
    .map(|p| p.to_vec())
    .collect();
    let lim = PathSettings::uniform(3, V, A, J);
    let (card, g) = path_card(3, &lim);
    let feed = 2e4;
    g.path_push(&Segment::line(1, &pts[0], feed, 0.0).into())
        .unwrap();
    run(&card, &g, 3, 100_000);
    let n = pts.len();
    let segs = pts[1..].iter().enumerate().map(|(i, p)| {
        let s = Segment::line(i as u32 + 2, p, feed, 10.0);
        if i + 2 == n {
            s.last()
        } else {
            s
        }
    });
    g.stream_path(segs, |_| {}).unwrap();
    let r = run(&card, &g, 3, 1_000_000);
    assert_limits(&r, &lim, "CAM points");
    assert_eq!(cmd(&card, 3), pts[n - 1], "ends on the last point");
    let off = farthest_off(&r, &pts);
    assert!(off <= 10.0, "{off} counts from the points");
}

/// Each axis's full limits along a line: one line along X runs X's own S-curve (its time
/// within 1 % of `Profile::plan`'s, the feed reached in full, every limit held); a thousand
/// collinear pieces of it sent one by one (no chord fitting) run in the same time, the card
/// looking ahead over as many of them as braking from the feed takes (25 counts each: 4,000
/// counts of braking are 160 of them).
#[test]
fn a_line_runs_its_axis_s_curve_and_collinear_pieces_run_as_the_line() {
    use motioncard_sdk::plan::{Limits, Profile};
    let lim = PathSettings {
        chord_fit: false,
        ..PathSettings::uniform(2, V, A, J)
    };
    let len = 25_400.0;
    let time = |n: usize| {
        let (card, g) = path_card(2, &lim);
        let segs = (1..=n).map(|i| {
            let s = Segment::line(i as u32, &[len * i as f64 / n as f64, 0.0], V, 10.0);
            if i == n {
                s.last()
            } else {
                s
            }
        });
        g.stream_path(segs, |_| {}).unwrap();
        let r = run(&card, &g, 2, 1_000_000);
        assert_limits(&r, &lim, "a line");
        let (p, _) = peaks(&r.pos, 0, 1e-4);
        assert!(p[0] > 0.9999 * V, "the feed reached in full: {}", p[0]);
        assert_eq!(r.pos.last().unwrap(), &vec![len, 0.0]);
        // from the first tick that moves to the one that arrives
        let first = r.pos.iter().position(|q| q[0] != 0.0).unwrap();
        let last = r.pos.iter().position(|q| q[0] == len).unwrap();
        (last - first + 1) as f64 * 1e-4
    };
    let scurve = Profile::plan(
        0.0,
        len,
        0.0,
        0.0,
        &Limits {
            vmax: V,
            amax: A,
            dmax: A,
            j1: J,
            j3: J,
            j5: J,
            j7: J,
        },
    )
    .unwrap()
    .duration();
    let one = time(1);
    assert!(
        (one / scurve - 1.0).abs() < 0.01,
        "{one} s, the S-curve {scurve} s"
    );
    let pieces = time(1000);
    assert!(
        (pieces / one - 1.0).abs() < 0.001,
        "{pieces} s, one line {one} s"
    );
}

/// An arc at its feed takes for its tangential acceleration and jerk what its curvature
/// leaves of each axis's limits at that feed: a full circle of 25,400 counts' radius at
/// 10⁵ counts/s (its centripetal acceleration 39 % of the axes') runs within 4 % of L/F + F/A,
/// the time of a trapezoid ramping at one axis's whole acceleration (1.081× with the half
/// shares of before), every limit held.
#[test]
fn an_arc_accelerates_with_what_its_curvature_leaves() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (card, g) = path_card(2, &lim);
    let r = 25_400.0;
    let c = ArcSpec::Centre {
        end: [0.0, 0.0],
        centre: [r, 0.0],
        ccw: true,
    };
    g.path_push(&Segment::arc(1, c, Plane::XY, &[], V, 10.0).last().into())
        .unwrap();
    let run = run(&card, &g, 2, 1_000_000);
    assert_limits(&run, &lim, "the circle");
    let first = run.pos.iter().position(|q| q[1] != 0.0).unwrap();
    let last = run.pos.iter().rposition(|q| q != &vec![0.0, 0.0]).unwrap();
    let t = (last - first + 2) as f64 * 1e-4;
    let bound = std::f64::consts::TAU * r / V + V / A;
    assert!(t < 1.04 * bound, "{t} s against {bound} s");
}

/// A slow arc moves and ends: a quarter circle fed far below its cap (a CAM program's small
/// fillet at a low feed) runs at its feed and stops on its end point, every limit held.
/// Before, such an arc's tangential limits left no room where its tangent lies along an axis
/// (that axis's curvature term is 0 there but for rounding): its cap came out 0 and the group
/// stayed Moving at rest for ever.
#[test]
fn a_slow_arc_moves_and_ends() {
    let lim = PathSettings::uniform(2, V, A, J);
    for (feed, r) in [
        (833.0, 250.0),
        (1_400.0, 250.0),
        (833.0, 100.0),
        (833.0, 10_000.0),
        (20_000.0, 100_000.0),
    ] {
        let (card, g) = path_card(2, &lim);
        let c = ArcSpec::Centre {
            end: [r, r],
            centre: [0.0, r],
            ccw: true,
        };
        g.path_push(&Segment::arc(1, c, Plane::XY, &[], feed, 10.0).last().into())
            .unwrap();
        let len = std::f64::consts::FRAC_PI_2 * r;
        let ticks = (len / feed * 1e4) as usize;
        let run = run(&card, &g, 2, 2 * ticks + 10_000);
        let what = format!("a quarter circle of radius {r} at {feed} counts/s");
        assert_eq!(
            g.status().unwrap().0,
            GroupState::Standby,
            "{what}: not ended"
        );
        assert_eq!(run.pos.last().unwrap(), &vec![r, r], "{what}: its end");
        assert_limits(&run, &lim, &what);
        let t = run.pos.len() as f64 * 1e-4;
        assert!(
            t < 1.05 * len / feed + 0.01,
            "{what}: {t} s against {} s at the feed",
            len / feed
        );
    }
}

/// A pause on the card (`MC_OP_PATH_PAUSE`): the square under way comes to rest on the end of
/// a segment (within the 100-count tolerance of its corner: the middle of the blend), posts
/// `MC_EV_PATH_PAUSED` with that segment's id, shows it in the status and holds there with the
/// rest queued; a resume runs the rest to the square's end within every limit. The card's own
/// checks refuse a NaN and anything but 0 and 1.
#[test]
fn a_pause_rests_at_the_end_of_a_segment_and_a_resume_runs_the_rest() {
    let (card, g, lim) = square_under_way();
    let sim = card.sim().unwrap();
    let before = cmd(&card, 2);
    g.path_pause().unwrap();
    assert_eq!(g.path_pause_state().unwrap(), PauseState::Pausing);
    let mut r = Run {
        pos: vec![before],
        events: Vec::new(),
    };
    while !r.events.iter().any(|e| e.kind == EventKind::PathPaused) {
        sim.step(1);
        r.pos.push(cmd(&card, 2));
        drain(&card, &mut r.events);
        assert!(r.pos.len() < 100_000, "no pause");
    }
    let id = ids(&r, EventKind::PathPaused)[0];
    assert!((1..4).contains(&id), "paused after {id}");
    assert_eq!(g.path_pause_state().unwrap(), PauseState::Paused { id });
    let corner = &square(50_000.0)[id as usize];
    let here = cmd(&card, 2);
    let off = (here[0] - corner[0]).hypot(here[1] - corner[1]);
    assert!(off <= 100.0 + 1e-6, "{off} counts from the end of {id}");
    // held, with the rest queued
    sim.step(500);
    assert_eq!(cmd(&card, 2), here);
    assert_eq!(g.status().unwrap().0, GroupState::Moving);
    assert!(g.status().unwrap().1.path_queued > 0);
    // the card's own checks
    let raw = |on: f64| {
        let mut c =
            motioncard_sdk::proto::Command::new(motioncard_sdk::proto::Opcode::PathPause, 0);
        c.args[0] = on;
        card.execute_raw(c).err().map(|e| e.kind())
    };
    assert_eq!(raw(f64::NAN), Some(ErrorKind::NotFinite));
    assert_eq!(raw(2.0), Some(ErrorKind::OutOfRange));
    assert_eq!(raw(0.5), Some(ErrorKind::OutOfRange));
    assert_eq!(g.path_pause_state().unwrap(), PauseState::Paused { id });
    // and on along the same path
    g.path_resume().unwrap();
    assert_eq!(g.path_pause_state().unwrap(), PauseState::None);
    let rest = run(&card, &g, 2, 200_000);
    r.pos.extend(rest.pos);
    r.events.extend(rest.events);
    assert_eq!(r.pos.last().unwrap(), &vec![0.0, 0.0]);
    assert_limits(&r, &lim, "pause and resume");
    let ends = ids(&r, EventKind::SegmentEnd);
    assert_eq!(ends.last(), Some(&4));
}

/// Layout 1.12: an arc in a plane given by a normal vector on the card, through the SDK: a
/// circle about (1, 1, 1) from the origin runs on its circle and in its plane, every axis
/// within its limits, and ends exactly; a helix rising along the normal with a fourth axis
/// ends where it was sent; the card's refusals (a zero normal, a plane of one axis twice, a
/// centre off the plane, an end off the plane or off the circle) each with its own code,
/// nothing queued.
#[test]
fn arcs_in_a_plane_given_by_a_normal_vector_on_the_card() {
    let mut lim = PathSettings::uniform(4, V, A, J);
    lim.vmax[1] = V / 2.0;
    lim.amax[1] = A / 2.0;
    let (card, g) = path_card(4, &lim);
    let n = [1.0, 1.0, 1.0];
    let nh = [1.0 / 3f64.sqrt(); 3];
    // centre in the plane x + y + z = 0 through the origin, radius 10000·√2
    let c = [10_000.0, -10_000.0, 0.0];
    let r = 10_000.0 * 2f64.sqrt();
    // a half turn: the end is the start mirrored through the centre
    let end = [20_000.0, -20_000.0, 0.0];
    let s = Segment::arc_normal(1, [0, 1, 2], n, c, end, 60_000.0, 10.0).last();
    g.path_push(&s.into()).unwrap();
    let rr = run(&card, &g, 4, 200_000);
    assert_limits(&rr, &lim, "oblique circle");
    assert_eq!(rr.pos.last().unwrap(), &vec![20_000.0, -20_000.0, 0.0, 0.0]);
    let mut worst = (0.0f64, 0.0f64);
    for p in &rr.pos {
        let d = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        let h = d[0] * nh[0] + d[1] * nh[1] + d[2] * nh[2];
        worst.0 = worst.0.max(h.abs());
        worst.1 = worst
            .1
            .max(((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() - r).abs());
    }
    // (the card's commanded positions are whole counts apart from rounding: within a count)
    assert!(
        worst.0 < 1e-6 && worst.1 < 1e-6,
        "off the plane / circle by {worst:?}"
    );
    // a helix: back to the start with a rise of 3000 along the normal, the fourth axis to 5000
    let rise = 3_000.0;
    let e2 = [rise * nh[0], rise * nh[1], rise * nh[2]];
    let h = Segment {
        geometry: motioncard_sdk::Geometry::ArcNormal {
            axes: [0, 1, 2],
            normal: n,
            centre: [c[0] + e2[0], c[1] + e2[1], c[2] + e2[2]],
            end: e2,
            rise: true,
            helix: vec![5_000.0],
        },
        ..Segment::line(2, &[], 60_000.0, 10.0).last()
    };
    // the centre given at the end's height is off the plane through the start: refused
    let e = g.path_push(&h.clone().into()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::ArcOffPlane, "{e}");
    let mut h = h;
    if let motioncard_sdk::Geometry::ArcNormal { centre, .. } = &mut h.geometry {
        *centre = c;
    }
    g.path_push(&h.into()).unwrap();
    let rr = run(&card, &g, 4, 400_000);
    assert_limits(&rr, &lim, "oblique helix");
    let last = rr.pos.last().unwrap();
    // a half turn from where the circle ended: back over the start, risen along the normal
    for k in 0..3 {
        assert!((last[k] - e2[k]).abs() < 1e-9, "{last:?}");
    }
    assert_eq!(last[3], 5_000.0);
    // the refusals, each with its own code, nothing queued
    let at = cmd(&card, 3);
    let refused = |axes: [usize; 3], normal: [f64; 3], centre: [f64; 3], end: [f64; 3]| {
        let s = Segment::arc_normal(3, axes, normal, centre, end, 60_000.0, 10.0);
        let e = g.path_push(&s.into()).unwrap_err();
        assert_eq!(g.status().unwrap().1.path_queued, 0);
        e.kind()
    };
    let c0 = [at[0] - 1_000.0, at[1], at[2]];
    let z = [0.0, 0.0, 1.0];
    let e_ok = [at[0] - 2_000.0, at[1], at[2]];
    assert_eq!(refused([0, 1, 2], [0.0; 3], c0, e_ok), ErrorKind::ArcNormal);
    assert_eq!(refused([0, 1, 1], z, c0, e_ok), ErrorKind::ArcAxes);
    assert_eq!(
        refused([0, 1, 2], z, [c0[0], c0[1], c0[2] + 50.0], e_ok),
        ErrorKind::ArcOffPlane
    );
    assert_eq!(
        refused([0, 1, 2], z, c0, [e_ok[0], e_ok[1], e_ok[2] + 50.0]),
        ErrorKind::ArcOffPlane
    );
    assert_eq!(
        refused([0, 1, 2], z, c0, [e_ok[0] - 50.0, e_ok[1], e_ok[2]]),
        ErrorKind::CentreNotEquidistant
    );
    assert_eq!(
        refused([0, 1, 2], z, [at[0], at[1], at[2]], e_ok),
        ErrorKind::ZeroLengthArc
    );
}
