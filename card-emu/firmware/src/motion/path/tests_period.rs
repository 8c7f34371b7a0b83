//! Planning every few servo ticks (`PathLimits::plan_ticks`): the look-ahead and the speed
//! planner run once a step, and every tick in between follows the step's own profile. The
//! commanded positions keep every axis limit (finite differences per servo tick) and the
//! tolerance, stops start at the tick they are asked in and land exactly, dwells and outputs
//! keep their servo-tick timing, and the steps are those of the same planner run at the
//! step's period.

use super::tests::{
    dwell_and_outputs, halt_then_clear, limits, line, line_arc_line, override_hold_and_resume,
    path_with, polyline_with, pt, random_program, starving_and_resuming, Run,
};
use super::*;
use crate::testkit::rng::Rng;

/// 10 kHz.
const TS: f64 = 1e-4;

fn lim(naxes: usize, ts: f64, plan_ticks: usize) -> PathLimits {
    PathLimits {
        plan_ticks,
        ..limits(naxes, ts)
    }
}

/// Two axes of 100,000 counts/s, 10⁶ counts/s², 10⁸ counts/s³ (the corner benchmark's).
fn even(ts: f64, plan_ticks: usize) -> PathLimits {
    PathLimits {
        vmax: [1e5; MAX_AXES],
        amax: [1e6; MAX_AXES],
        jmax: [1e8; MAX_AXES],
        ..lim(2, ts, plan_ticks)
    }
}

/// A square of `side` counts from the origin, back to it.
fn square(side: f64) -> [V; 5] {
    [
        pt(&[0.0, 0.0]),
        pt(&[side, 0.0]),
        pt(&[side, side]),
        pt(&[0.0, side]),
        pt(&[0.0, 0.0]),
    ]
}

#[test]
fn polylines_planned_every_few_ticks_keep_every_limit_and_the_tolerance() {
    let sq = square(20_000.0);
    let zz: Vec<V> = (0..12)
        .map(|i| pt(&[i as f64 * 3000.0, if i % 2 == 0 { 0.0 } else { 4000.0 }]))
        .collect();
    // a smooth curve in chords of ~0.1 mm
    let dense: Vec<V> = (0..=1500)
        .map(|i| {
            let t = i as f64 / 1500.0 * 150_000.0 / 40_000.0;
            let r = 40_000.0 + 10_000.0 * (3.0 * t).sin();
            pt(&[r * t.cos(), r * t.sin()])
        })
        .collect();
    let mut rng = Rng::new(0x9e71);
    for m in [2, 10, 37] {
        polyline_with(lim(2, TS, m), &sq, 8e4, 50.0, &format!("square, every {m}"));
        polyline_with(
            lim(2, TS, m),
            &zz,
            1e5,
            20.0,
            &format!("zig-zag, every {m}"),
        );
        polyline_with(
            lim(2, TS, m),
            &dense,
            1e5,
            2.0,
            &format!("dense, every {m}"),
        );
        for naxes in [2, 3] {
            let mut v = vec![pt(&[0.0; 3][..naxes])];
            for _ in 0..15 {
                let mut q = *v.last().unwrap();
                for x in q[..naxes].iter_mut() {
                    *x += rng.uniform(-8000.0, 8000.0);
                }
                v.push(q);
            }
            let (feed, tol) = (rng.uniform(2e4, 1e5), rng.log_uniform(5.0, 200.0));
            polyline_with(lim(naxes, TS, m), &v, feed, tol, "random polyline");
        }
    }
}

#[test]
fn lines_and_arcs_planned_every_few_ticks_end_exactly_within_limits_and_tolerance() {
    for m in [3, 10] {
        line_arc_line(lim(2, TS, m));
    }
}

/// Positions, one per tick, until the path is at rest with nothing queued.
fn positions(p: &mut Path) -> Vec<V> {
    let mut pos = vec![];
    for _ in 0..10_000_000 {
        pos.push(p.tick(1.0, &mut |_| {}));
        if p.queued() == 0 && !p.is_moving() {
            return pos;
        }
    }
    panic!("no end");
}

#[test]
fn each_step_ends_where_the_planner_at_the_steps_period_is_at_its_tick() {
    // a dense curve whose caps change gently (no slowing to half the speed), queued before
    // the start: planned every m ticks of 0.1 ms, and at every tick of m × 0.1 ms, the same
    // planner takes the same steps
    let tr = Transition::MaxDeviation(5.0);
    let mut segs: Vec<Segment> = (1..=600)
        .map(|i| {
            let t = i as f64 / 600.0 * 2.5;
            let r = 40_000.0 + 10_000.0 * (3.0 * t).sin();
            line(i, pt(&[r * t.cos() - 40_000.0, r * t.sin()]), 1e5, tr)
        })
        .collect();
    segs.last_mut().unwrap().last = true;
    for m in [4, 10] {
        let run = |ts: f64, plan_ticks: usize| {
            let mut p = Path::with_capacity(1024);
            p.reset(pt(&[0.0, 0.0]), lim(2, ts, plan_ticks), 256)
                .unwrap();
            for s in &segs {
                p.push(*s).unwrap();
            }
            positions(&mut p)
        };
        let fine = run(TS, m);
        let coarse = run(TS * m as f64, 1);
        // the last step lands within its period: the fine run ends in the coarse run's
        // last period
        assert!(
            fine.len() > (coarse.len() - 1) * m && fine.len() <= coarse.len() * m,
            "every {m}: {} ticks against {} steps",
            fine.len(),
            coarse.len()
        );
        // (the stop at the end is re-solved every step from the distance left: there the
        // rounding of the two runs' positions moves it by a few hundredths of a count at most)
        let n = coarse.len() - 1;
        let (mut worst, mut worst_end) = (0.0f64, 0.0f64);
        for (k, q) in coarse.iter().enumerate().take(n) {
            let f = fine[(k + 1) * m - 1];
            let d = (f[0] - q[0]).hypot(f[1] - q[1]);
            if k < n - n / 50 {
                worst = worst.max(d);
            } else {
                worst_end = worst_end.max(d);
            }
        }
        assert!(worst < 1e-6, "every {m}: a step's end {worst} counts off");
        assert!(
            worst_end < 1e-2,
            "every {m}: a step's end {worst_end} counts off"
        );
        assert_eq!(fine.last(), coarse.last());
    }
}

#[test]
fn a_slowing_to_a_much_lower_speed_is_decided_at_the_servo_rate() {
    // sharp corners with small blends (about 1,000 counts/s from 80,000): planned every 1 ms
    // or 10 ms, the square takes the time it takes planned every tick (within 1 %: a step
    // ramps within the limits of every piece it and the next can reach, so a long step
    // brakes for a corner at the blend's limits a little earlier than the line's own would
    // need), where the planner run at 1 ms brakes for each corner up to a millisecond early
    // and crawls to it (the times are printed)
    let sq = square(50_000.0);
    let time = |ts: f64, m: usize| {
        let t = polyline_with(even(ts, m), &sq, 8e4, 10.0, "square")
            .pos
            .len() as f64
            * ts;
        eprintln!("square at 10 µm, ticks of {ts} s planned every {m}: {t:.4} s");
        t
    };
    let every_tick = time(TS, 1);
    for m in [10, 100] {
        let t = time(TS, m);
        assert!(
            (t / every_tick - 1.0).abs() < 0.01,
            "every {m} ticks: {t} s, every tick {every_tick} s"
        );
    }
    let at_1ms = time(1e-3, 1);
    assert!(at_1ms > 1.02 * every_tick, "{at_1ms} s, {every_tick} s");
}

#[test]
fn halts_stop_at_once_in_the_middle_of_a_step() {
    for phase in [0, 3, 9] {
        halt_then_clear(lim(2, TS, 10), phase);
    }
    halt_then_clear(lim(2, 1e-3, 4), 2);
}

#[test]
fn dwells_outputs_starvation_and_holds_keep_the_servo_ticks() {
    for (ts, m) in [(TS, 10), (TS, 7), (1e-3, 3)] {
        dwell_and_outputs(lim(2, ts, m));
        starving_and_resuming(lim(2, ts, m));
        override_hold_and_resume(lim(2, ts, m));
    }
}

#[test]
fn the_planner_period_is_whole_ticks_within_its_range() {
    // 1 ms by default, the nearest whole number of ticks, at least one
    assert_eq!(plan_ticks(0.0, 1e-4), 10);
    assert_eq!(plan_ticks(0.0, 1e-3), 1);
    assert_eq!(plan_ticks(0.0, 2.5e-4), 4);
    assert_eq!(plan_ticks(0.0, 2e-3), 1);
    assert_eq!(plan_ticks(5e-3, 1e-4), 50);
    assert_eq!(plan_ticks(1.24e-3, 2.5e-4), 5);
    assert_eq!(plan_ticks(1e-5, 1e-4), 1);
    assert_eq!(plan_ticks(1.0, 1e-4), 100);
    assert_eq!(plan_ticks(f64::MIN_POSITIVE, 1e-6), 1);
    // the engine refuses what is out of range
    let mut p = Path::with_capacity(8);
    for m in [0, MAX_PLAN_TICKS + 1] {
        assert_eq!(
            p.reset(pt(&[0.0, 0.0]), lim(2, TS, m), 8),
            Err(PathError::BadLimits)
        );
    }
    assert_eq!(
        p.reset(pt(&[0.0, 0.0]), lim(2, 0.5, 3), 8),
        Err(PathError::BadLimits)
    );
    assert!(p.reset(pt(&[0.0, 0.0]), lim(2, TS, 100), 8).is_ok());
    assert_eq!(p.plan_ticks(), 100);
}

#[test]
fn random_programs_streamed_and_planned_every_few_ticks_keep_every_limit_and_their_order() {
    let mut rng = Rng::new(0x9e72);
    for case in 0..16 {
        let naxes = 2 + case % 2;
        let m = [3, 10, 25][case % 3];
        let ts = if case % 4 == 0 { 1e-3 } else { TS };
        let l = lim(naxes, ts, m);
        let mut p = Path::with_capacity(16 + rng.int(0, 100));
        p.reset(pt(&[0.0; 3][..naxes]), l, 1 + rng.int(0, 15))
            .unwrap();
        let (segs, at) = random_program(&mut rng, naxes, 60);
        let (every, chunk) = (1 + rng.int(0, 20), 1 + rng.int(0, 5));
        let (ovr_at, ovr) = (rng.int(0, 2000), rng.uniform(0.3, 1.6));
        let mut r = Run::default();
        let mut next = 0;
        for k in 0..5_000_000 {
            if k % every == 0 {
                for _ in 0..chunk {
                    if next == segs.len() || p.free() == 0 {
                        break;
                    }
                    p.push(segs[next]).unwrap();
                    next += 1;
                }
            }
            r.go(&mut p, if k >= ovr_at { ovr } else { 1.0 }, 1);
            if next == segs.len() && p.queued() == 0 && !p.is_moving() {
                break;
            }
        }
        let what = format!("case {case}, every {m} ticks of {ts} s");
        r.assert_within(&l, &what);
        r.assert_ids(&(1..=60).collect::<Vec<_>>());
        assert_eq!(*r.pos.last().unwrap(), at, "{what}: end");
    }
}

/// An exact stop lands: the stop re-solved every tick used to creep toward the corner for
/// thousands of ticks once its state was a few ulps from rest (0.65 s a corner of a square
/// at 10 kHz, its exact stops taking 5.5 s against 2.9 s).
#[test]
fn exact_stops_land_without_creeping_whatever_the_planner_s_period() {
    let sq = square(50_000.0);
    let mut times = vec![];
    for m in [1, 10] {
        let l = even(TS, m);
        let mut p = path_with(l, sq[0]);
        for (i, w) in sq.windows(2).enumerate() {
            let mut s = line(i as u32 + 1, w[1], 1e5, Transition::Exact);
            s.last = i + 2 == sq.len();
            p.push(s).unwrap();
        }
        let mut r = Run::default();
        assert!(r.go(&mut p, 1.0, 1_000_000), "every {m}: never idle");
        r.assert_within(&l, "exact stops");
        r.assert_ids(&[1, 2, 3, 4]);
        for c in &sq[1..] {
            assert!(r.pos.contains(c), "every {m}: not exactly at {c:?}");
        }
        // at each corner the path is at rest for a tick or two, not for hundreds
        let still = r
            .pos
            .windows(2)
            .skip(3)
            .take(r.pos.len() - 10)
            .filter(|w| w[0] == w[1])
            .count();
        assert!(still <= 3 * 2, "every {m}: {still} ticks at rest");
        times.push(r.pos.len() as f64 * TS);
    }
    eprintln!("square, exact stops, planned every tick and every 10: {times:?} s");
    assert!((times[0] / times[1] - 1.0).abs() < 1e-3, "{times:?}");
    // the time of five rest-to-rest ramps of 0.21 s and 200,000 counts at 98,000 counts/s
    assert!(times[0] < 3.0, "{times:?}");
}

/// Exact stops where the path turns back, planned every few ticks at 10 kHz: a stop lands with
/// a tick's jerk of acceleration left, and the next line started at once the other way,
/// within the limits of the line before: 2.7 times an axis's jerk limit.
#[test]
fn exact_stops_where_the_path_turns_back_keep_the_jerk_limit() {
    let mut rng = Rng::new(0x5eed);
    for m in [1, 3, 10] {
        let l = lim(2, TS, m);
        let mut v = vec![pt(&[0.0, 0.0])];
        let mut heading: f64 = rng.uniform(0.0, 6.3);
        for _ in 0..30 {
            heading += core::f64::consts::PI + rng.uniform(-1.0, 1.0);
            let len = rng.uniform(200.0, 5000.0);
            let q = *v.last().unwrap();
            v.push(pt(&[
                q[0] + len * heading.cos(),
                q[1] + len * heading.sin(),
            ]));
        }
        let segs: Vec<Segment> = v
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let mut s = line(i as u32 + 1, w[1], rng.uniform(2e4, 1e5), Transition::Exact);
                s.last = i + 2 == v.len();
                s
            })
            .collect();
        // streamed two segments every 8 ticks, at 157 % feed
        let mut p = path_with(l, v[0]);
        let mut r = Run::default();
        let mut next = 0;
        for k in 0..1_000_000 {
            if k % 8 == 0 {
                for s in segs.iter().skip(next).take(2) {
                    p.push(*s).unwrap();
                    next += 1;
                }
            }
            r.go(&mut p, 1.57, 1);
            if next == segs.len() && p.queued() == 0 && !p.is_moving() {
                break;
            }
        }
        r.assert_within(&l, &format!("turns back, planned every {m} ticks"));
        for c in &v[1..] {
            assert!(r.pos.contains(c), "every {m}: not exactly at {c:?}");
        }
    }
}
