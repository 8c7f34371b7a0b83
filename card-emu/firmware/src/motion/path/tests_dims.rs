//! The engine's dimension `D` (`Path<D>`): a path of 12 axes on `Path<16>` keeps every axis
//! within its limits, its arcs on their circles and its ends; with four of its axes still it
//! moves as the 8-axis engine does on the other eight, to the last bit; and it moves the same
//! way every time, in either build of the engine.

use super::*;

const TS: f64 = 1e-3;
/// The axes of the wide path, and the dimension of its engine.
const N12: usize = 12;
const W: usize = 16;

/// A point of `D` coordinates, the first ones `xs`.
fn at<const D: usize>(xs: &[f64]) -> [f64; D] {
    let mut p = [0.0; D];
    p[..xs.len()].copy_from_slice(xs);
    p
}

/// Limits of `naxes` axes, each axis its own (axis k slower than axis k − 1).
fn lims<const D: usize>(naxes: usize, plan_ticks: usize) -> PathLimits<D> {
    let mut l = PathLimits {
        naxes,
        ts: TS,
        vmax: [0.0; D],
        amax: [0.0; D],
        jmax: [0.0; D],
        accel: 0.0,
        jerk: 0.0,
        plan_ticks,
    };
    for k in 0..D {
        let f = 1.0 - 0.05 * k as f64;
        l.vmax[k] = 1e5 * f;
        l.amax[k] = 1e7 * f;
        l.jmax[k] = 1e9 * f;
    }
    l
}

fn seg<const D: usize>(id: u32, geom: Geom<D>, feed: f64, tr: Transition) -> Segment<D> {
    Segment {
        id,
        geom,
        feed,
        transition: tr,
        blend: BlendSpeed::Low,
        last: false,
    }
}

fn line<const D: usize>(id: u32, end: [f64; D], feed: f64, tr: Transition) -> Segment<D> {
    seg(id, Geom::Line { end }, feed, tr)
}

/// What a run commanded, tick by tick.
struct Ran<const D: usize> {
    pos: Vec<[f64; D]>,
    speed: Vec<f64>,
    events: Vec<(usize, PathEvent)>,
    /// The segments joined to the one before by a blend, when all were pushed.
    blends: Vec<u32>,
}

impl<const D: usize> Ran<D> {
    /// The ticks of `p` until it is idle (panics after `max`), the program pushed first.
    fn go(p: &mut Path<D>, prog: &[Segment<D>], max: usize) -> Self {
        for s in prog {
            p.push(*s).unwrap();
        }
        let blends = prog
            .iter()
            .filter(|s| p.blend_info(s.id).is_some())
            .map(|s| s.id)
            .collect();
        let mut r = Ran {
            pos: vec![p.position()],
            speed: vec![0.0],
            events: vec![],
            blends,
        };
        for k in 0..max {
            let mut idle = false;
            let ev = &mut r.events;
            let q = p.tick(1.0, &mut |e| {
                idle |= e == PathEvent::Idle;
                ev.push((k, e));
            });
            r.pos.push(q);
            r.speed.push(p.speed());
            if idle {
                return r;
            }
        }
        panic!("not idle after {max} ticks");
    }

    /// Largest ratio of each axis's finite-difference velocity, acceleration and jerk to its
    /// limit.
    fn worst(&self, l: &PathLimits<D>) -> [f64; 3] {
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

    /// The tick on which `e` happened.
    fn tick_of(&self, e: PathEvent) -> usize {
        self.events
            .iter()
            .find(|(_, x)| *x == e)
            .unwrap_or_else(|| panic!("no {e:?}"))
            .0
    }

    /// Positions from the tick `id` starts to the tick it ends (`pos[k + 1]` is tick k's).
    fn during(&self, id: u32) -> &[[f64; D]] {
        let a = self.tick_of(PathEvent::SegmentStart { id });
        let b = self.tick_of(PathEvent::SegmentEnd { id });
        &self.pos[a + 1..=b + 1]
    }

    fn bits(&self) -> (Vec<Vec<u64>>, Vec<u64>) {
        (
            self.pos
                .iter()
                .map(|p| p.iter().map(|x| x.to_bits()).collect())
                .collect(),
            self.speed.iter().map(|x| x.to_bits()).collect(),
        )
    }
}

type P3 = [f64; 3];

fn dot3(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: P3) -> P3 {
    let m = dot3(a, a).sqrt();
    [a[0] / m, a[1] / m, a[2] / m]
}

/// The 12-axis program and what it checks: its segments, the plane arc's (id, centre on
/// axes 3 and 10, radius, start, end), the normal arc's (id, axes, unit normal, centre,
/// radius, start, end) and its end.
struct Wide {
    prog: Vec<Segment<W>>,
    arc: (u32, [f64; 2], f64, [f64; W], [f64; W]),
    normal: (u32, [usize; 3], P3, P3, f64, [f64; W], [f64; W]),
    /// The exact stops' points (the ends of segments followed by an exact stop).
    stops: Vec<[f64; W]>,
    end: [f64; W],
}

/// Lines of all 12 axes with corner blends and smoothing blends, an arc in the plane of axes
/// 3 and 10 with the other ten moving linearly (exact stops at both ends), an arc about a
/// normal vector on axes 9, 4, 11 with the other nine moving linearly (exact stops), an arc
/// of axes 0 and 7 joined by blends, a corner distance, a dwell, and a last line.
fn wide() -> Wide {
    let mut prog = vec![];
    let mut stops = vec![];
    let p0: [f64; W] = at(&[
        0.0, 0.0, 0.0, 100.0, -200.0, 300.0, 0.0, 50.0, 1_000.0, -1_000.0, 0.0, 7.0,
    ]);
    let step = |p: [f64; W], f: &dyn Fn(usize) -> f64| step(p, N12, f);
    // lines of every axis, a corner of ~40° and a run of small turns
    let a = step(p0, &|k| 3_000.0 + 250.0 * k as f64);
    prog.push(line(1, a, 6e4, Transition::Exact));
    let b = step(a, &|k| {
        if k % 2 == 0 {
            4_000.0
        } else {
            -500.0 * k as f64
        }
    });
    prog.push(line(2, b, 6e4, Transition::MaxDeviation(2.0)));
    let mut q = b;
    for i in 0..6u32 {
        let th = 0.15 * i as f64;
        q = step(q, &|k| {
            let w = 1.0 + 0.1 * k as f64;
            300.0 * w * (th + 0.2 * k as f64).cos()
        });
        prog.push(line(3 + i, q, 4e4, Transition::MaxDeviation(1.0)));
    }
    stops.push(q);
    // the plane arc: axes 3 and 10, 270° counter-clockwise, the others linear
    let r = 5_000.0;
    let s = q;
    let c = [s[3] - r, s[10]];
    let th = 1.5 * std::f64::consts::PI;
    let mut e = step(s, &|k| 700.0 - 90.0 * k as f64);
    e[3] = c[0] + r * th.cos();
    e[10] = c[1] + r * th.sin();
    prog.push(seg(
        10,
        Geom::Arc {
            u: 3,
            v: 10,
            centre: c,
            ccw: true,
            end: e,
        },
        5e4,
        Transition::Exact,
    ));
    stops.push(e);
    let arc = (10, c, r, s, e);
    // a line, then the normal arc on axes 9, 4, 11 (in that order), exact stops around it
    let s = step(e, &|k| -1_500.0 + 300.0 * k as f64);
    prog.push(line(11, s, 5e4, Transition::Exact));
    stops.push(s);
    let axes = [9, 4, 11];
    let nh = unit([1.0, 2.0, -2.0]);
    let rn = 4_000.0;
    // a radius in the plane: a vector off the normal with its normal part taken out
    let d = dot3([1.0, 0.0, 0.0], nh);
    let u = unit([1.0 - d * nh[0], -d * nh[1], -d * nh[2]]);
    let sv = [s[9], s[4], s[11]];
    let cn = [sv[0] - rn * u[0], sv[1] - rn * u[1], sv[2] - rn * u[2]];
    // the end: the radius turned by 200° about the normal (Rodrigues)
    let tn = 200f64.to_radians();
    let (sn, cs) = tn.sin_cos();
    let ru = [rn * u[0], rn * u[1], rn * u[2]];
    let kv = cross(nh, ru);
    let kd = dot3(nh, ru) * (1.0 - cs);
    let mut en = step(s, &|k| 250.0 + 60.0 * k as f64);
    for (i, &ax) in axes.iter().enumerate() {
        en[ax] = cn[i] + ru[i] * cs + kv[i] * sn + nh[i] * kd;
    }
    prog.push(seg(
        12,
        Geom::ArcNormal {
            axes,
            normal: [1.0, 2.0, -2.0],
            centre: cn,
            rise: false,
            end: en,
        },
        4e4,
        Transition::Exact,
    ));
    stops.push(en);
    let normal = (12, axes, nh, cn, rn, s, en);
    // blends into and out of an arc of axes 0 and 7, a corner distance, a dwell, the end
    let s = step(en, &|k| 2_000.0 - 100.0 * k as f64);
    prog.push(line(13, s, 6e4, Transition::Exact));
    let (ca, ra) = ([s[0], s[7] + 3_000.0], 3_000.0);
    let mut ea = step(s, &|k| 40.0 * k as f64);
    ea[0] = ca[0] + ra;
    ea[7] = ca[1];
    prog.push(seg(
        14,
        Geom::Arc {
            u: 0,
            v: 7,
            centre: ca,
            ccw: true,
            end: ea,
        },
        6e4,
        Transition::MaxDeviation(3.0),
    ));
    let f = step(ea, &|k| 1_000.0 + 200.0 * k as f64);
    prog.push(line(15, f, 6e4, Transition::MaxDeviation(3.0)));
    let g = step(f, &|k| 3_000.0 - 150.0 * k as f64);
    prog.push(line(16, g, 5e4, Transition::CornerDistance(60.0)));
    prog.push(seg(17, Geom::Dwell { time: 0.02 }, 0.0, Transition::Exact));
    stops.push(g);
    let end = step(g, &|k| 500.0 * (k as f64 - 5.5));
    let mut last = line(18, end, 5e4, Transition::Exact);
    last.last = true;
    prog.push(last);
    Wide {
        prog,
        arc,
        normal,
        stops,
        end,
    }
}

/// The wide path: `Path<16>` of 12 axes, reset at the program's start.
fn wide_path(plan_ticks: usize, v3: bool) -> Path<W> {
    let mut p = Path::<W>::with_segments(256);
    p.set_v3(v3);
    let start: [f64; W] = at(&[
        0.0, 0.0, 0.0, 100.0, -200.0, 300.0, 0.0, 50.0, 1_000.0, -1_000.0, 0.0, 7.0,
    ]);
    p.reset(start, lims(N12, plan_ticks), DEFAULT_LOOKAHEAD)
        .unwrap();
    p
}

/// A path of 12 axes on `Path<16>`: lines with corner and smoothing blends, an arc in the
/// plane of two axes with the other ten moving linearly, an arc about a normal vector, blends
/// into an arc, a corner distance, a dwell. Every axis keeps its own velocity, acceleration
/// and jerk limit (finite differences, 1 % for the sampling), the segments start and end in
/// order, every exact stop's point and the end are reached exactly, the axes past the 12th
/// stay 0, the plane arc's points are on its circle (1e-6 counts) with the other ten axes at
/// the share of their move that the angle turned is of the sweep (1e-9), and the normal arc's
/// on its circle and in its plane with the other nine axes likewise.
#[test]
fn twelve_axes_keep_their_limits_circles_and_ends() {
    let w = wide();
    for plan_ticks in [1, 5] {
        let mut p = wide_path(plan_ticks, true);
        let l = p.lim;
        let run = Ran::go(&mut p, &w.prog, 100_000);
        let worst = run.worst(&l);
        eprintln!(
            "plan_ticks {plan_ticks}: {} ticks, v, a, j ratios {worst:?}",
            run.pos.len()
        );
        assert!(
            worst.iter().all(|&x| x <= 1.01),
            "plan_ticks {plan_ticks}: v, a, j ratios {worst:?}"
        );
        // not all far below the limits either: the path is fed to them
        assert!(worst[0] > 0.5, "{worst:?}");
        let ids: Vec<u32> = w.prog.iter().map(|s| s.id).collect();
        let starts: Vec<u32> = run
            .events
            .iter()
            .filter_map(|(_, e)| match e {
                PathEvent::SegmentStart { id } => Some(*id),
                _ => None,
            })
            .collect();
        let ends: Vec<u32> = run
            .events
            .iter()
            .filter_map(|(_, e)| match e {
                PathEvent::SegmentEnd { id } => Some(*id),
                _ => None,
            })
            .collect();
        assert_eq!(starts, ids);
        assert_eq!(ends, ids);
        // the corner, the smoothing blends, the blends into and out of the last arc, the
        // corner distance
        assert_eq!(run.blends, [2, 3, 4, 5, 6, 7, 8, 14, 15, 16]);
        assert_eq!(*run.pos.last().unwrap(), w.end);
        for s in &w.stops {
            assert!(
                run.pos.contains(s),
                "the exact stop at {s:?} is not reached"
            );
        }
        assert!(run.pos.iter().all(|q| q[N12..].iter().all(|&x| x == 0.0)));

        // the plane arc
        let (id, c, r, s, e) = w.arc;
        let sweep = 1.5 * std::f64::consts::PI;
        let pts = run.during(id);
        assert!(pts.len() > 100, "{} points", pts.len());
        let (mut rad, mut lin) = (0.0f64, 0.0f64);
        for q in pts {
            rad = rad.max(((q[3] - c[0]).hypot(q[10] - c[1]) - r).abs());
            let ang = (q[10] - c[1])
                .atan2(q[3] - c[0])
                .rem_euclid(std::f64::consts::TAU);
            // (the start's angle is 0; its end, 3π/2, is not past 2π)
            let share = if ang > 1.75 * std::f64::consts::PI {
                0.0
            } else {
                ang / sweep
            };
            for k in (0..N12).filter(|&k| k != 3 && k != 10) {
                lin = lin.max(((q[k] - s[k]) / (e[k] - s[k]) - share).abs());
            }
        }
        eprintln!(
            "plane arc: {} points, radius off by {rad}, share by {lin}",
            pts.len()
        );
        assert!(rad < 1e-6, "plane arc: radius off by {rad}");
        assert!(
            lin < 1e-9,
            "plane arc: linear axes off their share by {lin}"
        );

        // the normal arc
        let (id, axes, nh, cn, rn, s, e) = w.normal;
        let tn = 200f64.to_radians();
        let r0 = [s[axes[0]] - cn[0], s[axes[1]] - cn[1], s[axes[2]] - cn[2]];
        let pts = run.during(id);
        assert!(pts.len() > 100, "{} points", pts.len());
        let (mut rad, mut off, mut lin) = (0.0f64, 0.0f64, 0.0f64);
        for q in pts {
            let d = [q[axes[0]] - cn[0], q[axes[1]] - cn[1], q[axes[2]] - cn[2]];
            let h = dot3(d, nh);
            off = off.max(h.abs());
            let rv = [d[0] - h * nh[0], d[1] - h * nh[1], d[2] - h * nh[2]];
            rad = rad.max((dot3(rv, rv).sqrt() - rn).abs());
            let ang = dot3(cross(r0, rv), nh)
                .atan2(dot3(r0, rv))
                .rem_euclid(std::f64::consts::TAU);
            let share = if ang > 0.5 * (tn + std::f64::consts::TAU) {
                0.0
            } else {
                ang / tn
            };
            for k in (0..N12).filter(|k| !axes.contains(k)) {
                lin = lin.max(((q[k] - s[k]) / (e[k] - s[k]) - share).abs());
            }
        }
        eprintln!(
            "normal arc: {} points, radius off by {rad}, plane by {off}, share by {lin}",
            pts.len()
        );
        assert!(rad < 1e-6, "normal arc: radius off by {rad}");
        assert!(off < 1e-6, "normal arc: off its plane by {off}");
        assert!(
            lin < 1e-9,
            "normal arc: linear axes off their share by {lin}"
        );
    }
}

/// The 8-axis program of [`eight_as_twelve`]: corner and smoothing blends, an arc of axes 0
/// and 1 and an arc about a normal on axes 0, 1, 2 joined by blends, a corner distance, a
/// dwell, the blend speeds, time-shifted lines, an output.
fn eight() -> (Vec<Segment>, [f64; MAX_AXES]) {
    let mut prog = vec![];
    let p0: [f64; MAX_AXES] = at(&[10.0, -20.0, 30.0, 0.0, 5.0, 0.0, -7.0, 1.0]);
    let step = |p: [f64; MAX_AXES], f: &dyn Fn(usize) -> f64| step(p, MAX_AXES, f);
    let a = step(p0, &|k| 2_000.0 + 300.0 * k as f64);
    prog.push(line(1, a, 7e4, Transition::Exact));
    let b = step(a, &|k| {
        if k % 3 == 0 {
            3_000.0
        } else {
            -400.0 * k as f64
        }
    });
    prog.push(line(2, b, 7e4, Transition::MaxDeviation(2.0)));
    let mut q = b;
    for i in 0..8u32 {
        let th = 0.2 * i as f64;
        q = step(q, &|k| 250.0 * (th + 0.3 * k as f64).sin() + 100.0);
        let mut s = line(3 + i, q, 5e4, Transition::MaxDeviation(0.5));
        s.blend = [
            BlendSpeed::Low,
            BlendSpeed::High,
            BlendSpeed::Previous,
            BlendSpeed::Next,
        ][i as usize % 4];
        prog.push(s);
    }
    // an arc of axes 0 and 1 (a helix: the others move), blended in and out
    let (c, r) = ([q[0], q[1] - 2_500.0], 2_500.0);
    let mut e = step(q, &|k| 30.0 * k as f64);
    e[0] = c[0] + r;
    e[1] = c[1];
    prog.push(seg(
        11,
        Geom::Arc {
            u: 0,
            v: 1,
            centre: c,
            ccw: false,
            end: e,
        },
        6e4,
        Transition::MaxDeviation(3.0),
    ));
    let s = step(e, &|k| match k {
        0 => 300.0,
        1 => -1_500.0,
        _ => 60.0 - 5.0 * k as f64,
    });
    prog.push(line(12, s, 6e4, Transition::CornerDistance(40.0)));
    // an arc about a normal on axes 0, 1, 2 (a rise along it), blended in
    let nh = unit([0.3, -1.0, 2.0]);
    let d = dot3([1.0, 0.0, 0.0], nh);
    let u = unit([1.0 - d * nh[0], -d * nh[1], -d * nh[2]]);
    let rn = 3_000.0;
    let cn = [s[0] - rn * u[0], s[1] - rn * u[1], s[2] - rn * u[2]];
    let (sn, cs) = 1.2f64.sin_cos();
    let ru = [rn * u[0], rn * u[1], rn * u[2]];
    let kv = cross(nh, ru);
    let kd = dot3(nh, ru) * (1.0 - cs);
    let mut en = step(s, &|k| 20.0 * k as f64);
    for i in 0..3 {
        en[i] = cn[i] + ru[i] * cs + kv[i] * sn + nh[i] * kd + 500.0 * nh[i];
    }
    prog.push(seg(
        13,
        Geom::ArcNormal {
            axes: [0, 1, 2],
            normal: [0.3, -1.0, 2.0],
            centre: cn,
            rise: true,
            end: en,
        },
        5e4,
        Transition::MaxDeviation(4.0),
    ));
    let f = step(en, &|k| -1_000.0 + 90.0 * k as f64);
    prog.push(line(14, f, 6e4, Transition::MaxDeviation(4.0)));
    prog.push(seg(15, Geom::Dwell { time: 0.015 }, 0.0, Transition::Exact));
    // time-shifted lines
    let g = step(f, &|k| 1_500.0 + 10.0 * k as f64);
    prog.push(line(16, g, 4e4, Transition::Exact));
    let h = step(g, &|k| if k % 2 == 0 { 1_200.0 } else { -900.0 });
    prog.push(line(17, h, 4e4, Transition::TimeShift(20.0)));
    let i = step(h, &|k| -700.0 + 25.0 * k as f64);
    let mut last = line(18, i, 5e4, Transition::Exact);
    last.last = true;
    prog.push(last);
    (prog, p0)
}

/// [`eight`]'s program on 12 axes of `Path<16>`, axes 8..11 held at `still`.
fn as_wide(prog: &[Segment], still: [f64; 4]) -> Vec<Segment<W>> {
    let widen = |p: [f64; MAX_AXES]| {
        let mut q: [f64; W] = at(&p);
        q[MAX_AXES..N12].copy_from_slice(&still);
        q
    };
    prog.iter()
        .map(|s| Segment {
            id: s.id,
            geom: match s.geom {
                Geom::Line { end } => Geom::Line { end: widen(end) },
                Geom::Arc {
                    u,
                    v,
                    centre,
                    ccw,
                    end,
                } => Geom::Arc {
                    u,
                    v,
                    centre,
                    ccw,
                    end: widen(end),
                },
                Geom::ArcNormal {
                    axes,
                    normal,
                    centre,
                    rise,
                    end,
                } => Geom::ArcNormal {
                    axes,
                    normal,
                    centre,
                    rise,
                    end: widen(end),
                },
                Geom::Dwell { time } => Geom::Dwell { time },
            },
            feed: s.feed,
            transition: s.transition,
            blend: s.blend,
            last: s.last,
        })
        .collect()
}

/// The 12-axis engine (`Path<16>`) on a path whose axes 8..11 stay still moves axes 0..7 as
/// the 8-axis engine (`Path<8>`) does on the same path of 8 axes, to the last bit, tick by
/// tick (positions, speeds, events, an output included): it plans the same profile. Axes
/// 8..11 (limits of their own, none below the 8-axis group's smallest) stay exactly where
/// they are. Planned every tick and every 4 ticks, in both builds of the engine.
#[test]
fn twelve_axes_with_four_still_move_as_eight_to_the_bit() {
    let (prog, p0) = eight();
    let still = [1_234.5, -3e3, 0.0, 77.25];
    let wide_prog = as_wide(&prog, still);
    let mut start: [f64; W] = at(&p0);
    start[MAX_AXES..N12].copy_from_slice(&still);
    for plan_ticks in [1, 4] {
        for v3 in [true, false] {
            let what = format!("plan_ticks {plan_ticks}, v3 {v3}");
            let mut narrow = Path::with_capacity(256);
            narrow.set_v3(v3);
            let ln: PathLimits = lims(MAX_AXES, plan_ticks);
            narrow.reset(p0, ln, DEFAULT_LOOKAHEAD).unwrap();
            let mut wide = Path::<W>::with_segments(256);
            wide.set_v3(v3);
            let mut lw: PathLimits<W> = lims(N12, plan_ticks);
            for k in MAX_AXES..N12 {
                // an axis of its own (faster than the slowest of the eight)
                lw.vmax[k] = 2e5 + k as f64;
                lw.amax[k] = 3e7;
                lw.jmax[k] = 1e10;
            }
            wide.reset(start, lw, DEFAULT_LOOKAHEAD).unwrap();
            assert_eq!(narrow.tangential_limits(), wide.tangential_limits());
            narrow
                .push_output(OutputAction {
                    bit: 3,
                    on: true,
                    at: OutputAt::Distance(1_500.0),
                })
                .unwrap();
            wide.push_output(OutputAction {
                bit: 3,
                on: true,
                at: OutputAt::Distance(1_500.0),
            })
            .unwrap();
            let a = Ran::go(&mut narrow, &prog, 100_000);
            let b = Ran::go(&mut wide, &wide_prog, 100_000);
            eprintln!("{what}: {} ticks, blends {:?}", a.pos.len(), a.blends);
            // the corner, the smoothing blends, into and out of the plane arc, out of the
            // normal arc (3 and 13 turn too sharply for their room: exact stops)
            assert_eq!(a.blends, [2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 14]);
            assert_eq!(a.blends, b.blends, "{what}");
            assert!(
                a.events
                    .iter()
                    .any(|(_, e)| matches!(e, PathEvent::Output { .. })),
                "{what}: no output"
            );
            assert_eq!(a.pos.len(), b.pos.len(), "{what}: ticks");
            for (i, (x, y)) in a.pos.iter().zip(&b.pos).enumerate() {
                for k in 0..MAX_AXES {
                    assert_eq!(
                        x[k].to_bits(),
                        y[k].to_bits(),
                        "{what}: axis {k} at tick {i}: {} and {}",
                        x[k],
                        y[k]
                    );
                }
                assert_eq!(y[MAX_AXES..N12], still, "{what}: tick {i}");
                assert!(y[N12..].iter().all(|&x| x == 0.0), "{what}: tick {i}");
            }
            assert_eq!(a.bits().1, b.bits().1, "{what}: speeds");
            assert_eq!(a.events, b.events, "{what}: events");
            // the program did move every axis, and ended where it should
            let end = match prog.last().unwrap().geom {
                Geom::Line { end } => end,
                _ => unreachable!(),
            };
            assert_eq!(*a.pos.last().unwrap(), end, "{what}");
        }
    }
}

/// `Path<16>` of 12 axes run twice gives the same positions, speeds and events to the last
/// bit; and so does its baseline build against its x86-64-v3 one (where the CPU has it).
#[test]
fn twelve_axes_run_the_same_every_time_and_in_both_builds() {
    let w = wide();
    let first = Ran::go(&mut wide_path(5, true), &w.prog, 100_000);
    let again = Ran::go(&mut wide_path(5, true), &w.prog, 100_000);
    assert_eq!(first.bits(), again.bits());
    assert_eq!(first.events, again.events);
    let base = Ran::go(&mut wide_path(5, false), &w.prog, 100_000);
    assert_eq!(first.bits(), base.bits());
    assert_eq!(first.events, base.events);
}

/// A group of more axes than the engine's dimension is refused, as an arc's axis or a normal
/// arc's axis past the group's, and a NURBS curve of another dimension than the group's
/// (curves have at most 8).
#[test]
fn axes_past_the_dimension_are_refused() {
    let mut p = Path::with_capacity(8);
    let l: PathLimits = lims(MAX_AXES, 1);
    assert_eq!(
        p.reset([0.0; MAX_AXES], PathLimits { naxes: 9, ..l }, 4),
        Err(PathError::BadAxis)
    );
    let mut p = Path::<W>::with_segments(8);
    let l: PathLimits<W> = lims(W, 1);
    assert_eq!(
        p.reset([0.0; W], PathLimits { naxes: W + 1, ..l }, 4),
        Err(PathError::BadAxis)
    );
    p.reset([0.0; W], l, 4).unwrap();
    eprintln!(
        "a segment of the ring: {} bytes at 8 axes, {} at 16",
        core::mem::size_of::<Seg>(),
        core::mem::size_of::<Seg<W>>()
    );
    let mut p = wide_path(1, true);
    let end: [f64; W] = at(&[100.0; N12]);
    let arc = |u, v| {
        seg(
            1,
            Geom::Arc {
                u,
                v,
                centre: [0.0, 0.0],
                ccw: true,
                end,
            },
            1e3,
            Transition::Exact,
        )
    };
    assert_eq!(p.push(arc(3, N12)), Err(PathError::BadAxis));
    let normal = seg(
        1,
        Geom::ArcNormal {
            axes: [0, 5, N12],
            normal: [0.0, 0.0, 1.0],
            centre: [0.0; 3],
            rise: false,
            end,
        },
        1e3,
        Transition::Exact,
    );
    assert_eq!(p.push(normal), Err(PathError::BadAxis));
    // a curve of the 12 axes' first three: refused on 12
    let curve = crate::motion::nurbs::Nurbs::new(
        1,
        3,
        &[0.0, 0.0, 0.0, 3_000.0, 0.0, 0.0],
        &[1.0, 1.0],
        &[0.0, 0.0, 1.0, 1.0],
    )
    .unwrap();
    let s = CurveSegment {
        id: 1,
        curve: &curve,
        feed: 1e3,
        transition: Transition::Exact,
        blend: BlendSpeed::Low,
        last: true,
        tolerance: 1.0,
    };
    assert_eq!(p.push_curve(&s), Err(PathError::BadAxis));
    assert_eq!(p.queued(), 0);
    // within the group: an arc of axes 0 and 11 (the start is 7 from the centre on axis 11)
    let mut end = end;
    (end[0], end[N12 - 1]) = (7.0, 0.0);
    let ok = seg(
        1,
        Geom::Arc {
            u: 0,
            v: N12 - 1,
            centre: [0.0, 0.0],
            ccw: false,
            end,
        },
        1e3,
        Transition::Exact,
    );
    assert_eq!(p.push(ok), Ok(()));
    assert_eq!(p.queued(), 1);
}

/// `p` moved by `f(k)` on each of its first `n` axes `k`.
fn step<const D: usize>(p: [f64; D], n: usize, f: &dyn Fn(usize) -> f64) -> [f64; D] {
    let mut q = p;
    for (k, x) in q[..n].iter_mut().enumerate() {
        *x += f(k);
    }
    q
}
