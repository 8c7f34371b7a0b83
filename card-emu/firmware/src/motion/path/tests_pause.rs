//! A pause at the end of a segment (`pause.rs`): where it lands, that it holds, that the path
//! after a resume is the same path, asked for in every phase of a profile.

use super::tests::*;
use super::*;

/// A zigzag of lines blended within 10 counts, an exact corner, a dwell and an arc: ids 1..=9.
fn program(p: &mut Path) -> V {
    let tr = Transition::MaxDeviation(10.0);
    let mut segs = vec![];
    for i in 1..=5u32 {
        let x = i as f64 * 8_000.0;
        let y = if i % 2 == 0 { 0.0 } else { 3_000.0 };
        let t = if i == 3 { Transition::Exact } else { tr };
        segs.push(line(i, pt(&[x, y]), 6e4, t));
    }
    segs.push(Segment {
        id: 6,
        geom: Geom::Dwell { time: 0.02 },
        feed: 0.0,
        transition: Transition::Exact,
        blend: BlendSpeed::Low,
        last: false,
    });
    segs.push(line(7, pt(&[40_000.0, 9_000.0]), 6e4, tr));
    segs.push(arc_xy(
        8,
        [44_000.0, 9_000.0],
        pt(&[48_000.0, 9_000.0]),
        4e4,
        tr,
    ));
    let end = pt(&[60_000.0, 0.0]);
    segs.push(line(9, end, 6e4, tr));
    for s in segs {
        p.push(s).unwrap();
    }
    end
}

/// The programmed end of each segment (index: id − 1).
const CORNERS: [[f64; 2]; 9] = [
    [8_000.0, 3_000.0],
    [16_000.0, 0.0],
    [24_000.0, 3_000.0],
    [32_000.0, 0.0],
    [40_000.0, 3_000.0],
    [40_000.0, 3_000.0],
    [40_000.0, 9_000.0],
    [48_000.0, 9_000.0],
    [60_000.0, 0.0],
];

/// The segments whose ends are exact stops: before the exact corner, and the dwell's.
const STOPS: [usize; 3] = [2, 5, 6];

/// The distance along the path where each segment ends (index: id − 1): its programmed end,
/// or the middle of the blend after it.
fn ends(p: &Path) -> Vec<f64> {
    (1..=p.tail).map(|i| p.end_of(i)).collect()
}

fn paused(r: &Run) -> Vec<(usize, Option<u32>)> {
    r.events
        .iter()
        .filter_map(|&(k, e)| match e {
            PathEvent::Paused { id } => Some((k, id)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_pause_asked_in_every_phase_lands_on_the_first_segment_end_it_can_and_the_path_goes_on_unchanged(
) {
    pause_in_every_phase(limits(2, TS));
    // with a planning step of several servo ticks (a pause may be asked within one)
    let mut lim = limits(2, TS / 4.0);
    lim.plan_ticks = 4;
    pause_in_every_phase(lim);
}

fn pause_in_every_phase(lim: PathLimits) {
    let ts = lim.ts * lim.plan_ticks as f64;
    // the path without a pause
    let mut p0 = path_with(lim, pt(&[0.0, 0.0]));
    let end = program(&mut p0);
    let mut r0 = Run::default();
    assert!(r0.go(&mut p0, 1.0, 100_000));
    let (total, n0) = (p0.distance(), r0.pos.len());
    let (at, jt) = p0.tangential_limits();
    let mut cases = 0;
    for ask in (2..n0 - 10).step_by(n0 / 90) {
        let mut p = path_with(lim, pt(&[0.0, 0.0]));
        program(&mut p);
        let e = ends(&p);
        let mut r = Run::default();
        r.go(&mut p, 1.0, ask);
        // (the pause is chosen as the next planning step starts: asked at its start, the
        // state it is chosen from is the state asked in)
        while p.step.running() {
            r.go(&mut p, 1.0, 1);
        }
        if !p.is_moving() && p.exec >= p.tail {
            continue;
        }
        let (d, v, a) = (p.exec_dist(), p.speed(), p.accel());
        p.pause();
        assert_eq!(p.pause_state(), PauseState::Pausing);
        let mut ticks = 0;
        while paused(&r).is_empty() {
            r.go(&mut p, 1.0, 1);
            ticks += 1;
            assert!(ticks < 80_000, "asked at tick {ask}: no pause");
        }
        let (k, id) = paused(&r)[0];
        let id = id.expect("a segment ended") as usize;
        assert_eq!(
            p.pause_state(),
            PauseState::Paused {
                id: Some(id as u32)
            }
        );
        // at rest on the end of segment `id`'s body
        assert!(!p.is_moving());
        assert!(
            (p.distance() - e[id - 1]).abs() <= 1e-6 * total,
            "asked at {ask}: at {} not {}",
            p.distance(),
            e[id - 1]
        );
        assert_eq!(r.speed[k], 0.0);
        // within the blend's tolerance (10 counts) of the segment's programmed end
        let corner = CORNERS[id - 1];
        let off = (p.position()[0] - corner[0]).hypot(p.position()[1] - corner[1]);
        assert!(
            off <= 10.0 + 1e-6,
            "asked at {ask}: {off} from the end of {id}"
        );
        // the first end it could stop at: every end before it is behind (or at: at rest on a
        // segment's end, the next is the one running) or nearer than the stop from the state
        // it was asked in (at the path's tangential limits, the lowest)
        let stop = 1.05 * PathSpeedPlanner::stopping_distance(v, a, at, jt) + 4.0 * v * ts;
        for (j, &ej) in e[..id - 1].iter().enumerate() {
            assert!(
                ej <= d + 1e-9 || (ej - d < stop && !STOPS.contains(&(j + 1))),
                "asked at {ask} (d {d}, v {v}): end of {} at {ej} was reachable",
                j + 1
            );
        }
        // it holds
        let here = p.position();
        r.go(&mut p, 1.0, 200);
        assert_eq!(p.position(), here);
        assert_eq!(paused(&r).len(), 1);
        // and goes on along the same path
        p.resume();
        assert_eq!(p.pause_state(), PauseState::None);
        // (paused at the end of the last segment, it was idle before it paused)
        assert!(r.go(&mut p, 1.0, 100_000) || id == 9, "asked at {ask}");
        r.assert_within(&p.lim, "pause");
        r.assert_ids(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
        assert_eq!(p.position(), end);
        assert!((p.distance() - total).abs() <= 1e-9 * total);
        cases += 1;
    }
    assert!(cases > 20, "{cases} cases");
}

#[test]
fn a_pause_at_rest_is_at_once_and_one_while_braking_for_the_queue_end_is_there() {
    let lim = limits(2, TS);
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let mut r = Run::default();
    // nothing queued: at once
    assert!(p.pause());
    assert_eq!(p.pause_state(), PauseState::Paused { id: None });
    p.resume();
    // braking for the end of what is queued: the pause is there
    let tr = Transition::MaxDeviation(10.0);
    p.push(line(1, pt(&[5_000.0, 0.0]), 6e4, tr)).unwrap();
    p.push(line(2, pt(&[9_000.0, 2_000.0]), 6e4, tr)).unwrap();
    let mut k = 0;
    while !r.events.iter().any(|e| e.1 == PathEvent::Starving) {
        r.go(&mut p, 1.0, 1);
        k += 1;
        assert!(k < 10_000);
    }
    assert!(!p.pause());
    while paused(&r).is_empty() {
        r.go(&mut p, 1.0, 1);
        k += 1;
        assert!(k < 20_000);
    }
    assert_eq!(paused(&r)[0].1, Some(2));
    assert_eq!(p.position(), pt(&[9_000.0, 2_000.0]));
    // more queued while paused does not move it; a resume runs it
    p.push(line(3, pt(&[12_000.0, 0.0]), 6e4, tr)).unwrap();
    r.go(&mut p, 1.0, 100);
    assert_eq!(p.position(), pt(&[9_000.0, 2_000.0]));
    p.resume();
    assert!(r.go(&mut p, 1.0, 100_000));
    assert_eq!(p.position(), pt(&[12_000.0, 0.0]));
    r.assert_ids(&[1, 2, 3]);
    r.assert_within(&p.lim, "queue end");
}

#[test]
fn a_resume_before_the_pause_point_does_not_stop_and_a_halt_ends_a_pause() {
    let lim = limits(2, TS);
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    let end = program(&mut p);
    let mut r = Run::default();
    r.go(&mut p, 1.0, 150);
    p.pause();
    r.go(&mut p, 1.0, 5);
    assert_eq!(p.pause_state(), PauseState::Pausing);
    p.resume();
    assert!(r.go(&mut p, 1.0, 100_000));
    assert!(paused(&r).is_empty());
    assert_eq!(p.position(), end);
    // a halt while pausing: the pause is over, the halt stops and clear drops the rest
    let mut p = path_with(lim, pt(&[0.0, 0.0]));
    program(&mut p);
    let mut r = Run::default();
    r.go(&mut p, 1.0, 150);
    p.pause();
    r.go(&mut p, 1.0, 2);
    p.halt(1e6, 1e8);
    assert_eq!(p.pause_state(), PauseState::None);
    while p.is_moving() {
        r.go(&mut p, 1.0, 1);
    }
    let mut aborted = vec![];
    p.clear(&mut |id| aborted.push(id)).unwrap();
    assert!(!aborted.is_empty());
    assert!(paused(&r).is_empty());
    // a pause is not taken while halted
    p.halt(1e6, 1e8);
    p.pause();
    assert_eq!(p.pause_state(), PauseState::None);
}
