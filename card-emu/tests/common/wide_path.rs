//! A 12-axis path and its reference, shared by the tests of paths across cards
//! (`tests/cardset_path.rs` on the stepped bus, `card-emu/tests/sync_bus.rs` across
//! processes): the program, every axis's limits, and one planner of all twelve axes (the
//! engine's `Path<16>`) replayed with the same segments on the same ticks.
#![allow(dead_code)]

use card_emu::motion::arc::{ArcDirection, ExactCircle};
use card_emu::motion::path::{
    plan_ticks, BlendSpeed, Geom, Path, PathLimits, Segment as EngineSegment, Transition as Tr,
};
use motioncard_sdk::{
    ArcSpec, Card, CardSet, Geometry, PathBuffer, PathSettings, Plane, ScopeMode, ScopeSample,
    ScopeSettings, Segment, Signal, Source, Transition,
};
use std::collections::BTreeMap;

/// Axes of the path.
pub const N: usize = 12;
/// The engine's dimension.
pub const D: usize = 16;

pub fn vmax(d: usize) -> f64 {
    [4e4, 6e4, 5e4][d % 3]
}
pub fn amax(d: usize) -> f64 {
    [6e5, 8e5, 1e6][d % 3]
}
pub fn jmax(d: usize) -> f64 {
    [6e7, 1e8, 8e7][d % 4 % 3]
}

pub fn settings() -> PathSettings {
    let mut s = PathSettings::uniform(N, 1.0, 1.0, 1.0);
    for d in 0..N {
        (s.vmax[d], s.amax[d], s.jmax[d]) = (vmax(d), amax(d), jmax(d));
    }
    s
}

pub fn pt(k: f64) -> Vec<f64> {
    (0..N)
        .map(|d| k * (1000.0 + 137.0 * d as f64) * if d % 2 == 0 { 1.0 } else { -0.5 })
        .collect()
}

/// The program: blended lines through all twelve axes, a helix (half a turn in dimensions 0
/// and 1, the other ten rising), a dwell, an exact stop, a run of short blended chords, back
/// to the origin.
pub fn program() -> Vec<Segment> {
    let a = pt(2.0);
    let helix: Vec<f64> = (2..N)
        .map(|d| 3.0 * pt(1.0)[d] - 400.0 * d as f64)
        .collect();
    let mut v = vec![
        Segment::line(1, &pt(1.0), 3e4, 5.0),
        Segment::line(2, &a, 2e4, 5.0),
        Segment {
            id: 3,
            geometry: Geometry::Arc {
                arc: ArcSpec::Centre {
                    end: [a[0] + 8000.0, a[1]],
                    centre: [a[0] + 4000.0, a[1]],
                    ccw: true,
                },
                plane: Plane::XY,
                helix: helix.clone(),
            },
            ..Segment::line(3, &a, 2.5e4, 2.0)
        },
        Segment {
            id: 4,
            geometry: Geometry::Dwell { seconds: 0.002 },
            ..Segment::line(4, &a, 1.0, 0.0)
        },
        Segment {
            buffer: PathBuffer::Buffered,
            ..Segment::line(5, &pt(0.5), 4e4, 0.0)
        },
    ];
    // 40 chords of a circle in dimensions 2 and 3, the others still
    let mut end = pt(0.5);
    let (c2, c3) = (end[2] - 3000.0, end[3]);
    for k in 1..=40 {
        let th = k as f64 * std::f64::consts::PI / 40.0;
        end[2] = c2 + 3000.0 * th.cos();
        end[3] = c3 + 3000.0 * th.sin();
        v.push(Segment::line(5 + k, &end, 3e4, 2.0));
    }
    v.push(Segment::line(50, &[0.0; N], 5e4, 0.0));
    v
}

/// The engine's segment for `s` from `start` (what one planner of all twelve axes gets; an
/// arc's end on its exact circle, as every path arc's is).
pub fn engine_segment(s: &Segment, start: &[f64; D]) -> EngineSegment<D> {
    let tr = |t: Transition| match t {
        Transition::MaxDeviation(x) if x > 0.0 => Tr::MaxDeviation(x),
        _ => Tr::Exact,
    };
    let exact = s.buffer == PathBuffer::Buffered;
    let (geom, transition) = match &s.geometry {
        Geometry::Line { target } => {
            let mut e = [0.0; D];
            e[..N].copy_from_slice(target);
            (Geom::Line { end: e }, tr(s.transition))
        }
        Geometry::Arc {
            arc: ArcSpec::Centre { end, centre, .. },
            helix,
            ..
        } => {
            let c = (centre[0], centre[1]);
            let a0 = ExactCircle::from_points(
                c,
                (start[0], start[1]),
                (end[0], end[1]),
                ArcDirection::Ccw,
            )
            .unwrap();
            let a = ExactCircle::new(c, a0.radius(), a0.start_angle(), a0.sweep()).unwrap();
            let mut e = [0.0; D];
            e[2..N].copy_from_slice(helix);
            (e[0], e[1]) = a.point_at(a.length()).unwrap();
            let g = Geom::Arc {
                u: 0,
                v: 1,
                centre: [c.0, c.1],
                ccw: true,
                end: e,
            };
            (g, tr(s.transition))
        }
        Geometry::Dwell { seconds } => (Geom::Dwell { time: *seconds }, Tr::Exact),
        _ => unreachable!(),
    };
    let dwell = matches!(geom, Geom::Dwell { .. });
    EngineSegment {
        id: s.id,
        geom,
        feed: if dwell { 1.0 } else { s.feed },
        transition: if exact || dwell {
            Tr::Exact
        } else {
            transition
        },
        blend: BlendSpeed::Low,
        last: s.last,
    }
}

/// One planner of all twelve axes at `rate` Hz: at rest at the origin, each batch pushed on
/// its release tick, `control` applied before the ticks it names (a halt, or an override from
/// a tick on), ticked to rest. Its position after each tick, from the first release's tick on.
pub fn engine(
    rate: u32,
    batches: &[(u64, Vec<Segment>)],
    control: &[(u64, Control)],
) -> (u64, Vec<[f64; D]>) {
    let mut lim = PathLimits::<D> {
        naxes: N,
        ts: 1.0 / rate as f64,
        vmax: [0.0; D],
        amax: [0.0; D],
        jmax: [0.0; D],
        accel: 0.0,
        jerk: 0.0,
        plan_ticks: plan_ticks(0.0, 1.0 / rate as f64),
    };
    for d in 0..N {
        (lim.vmax[d], lim.amax[d], lim.jmax[d]) = (vmax(d), amax(d), jmax(d));
    }
    let mut p = Path::<D>::with_segments(4096);
    p.reset([0.0; D], lim, 256).unwrap();
    let first = batches[0].0;
    let mut end = [0.0; D];
    let mut out = Vec::new();
    let mut factor = 1.0;
    let mut halted = false;
    let mut t = first;
    loop {
        for (at, segs) in batches {
            if *at == t {
                for s in segs {
                    let e = engine_segment(s, &end);
                    if let Geom::Line { end: x } | Geom::Arc { end: x, .. } = e.geom {
                        end = x;
                    }
                    p.push(e).unwrap();
                }
            }
        }
        for (at, c) in control {
            if *at == t {
                match *c {
                    Control::Halt(d, j) => {
                        p.halt(d, j);
                        halted = true;
                    }
                    Control::Override(f) => factor = f,
                }
            }
        }
        out.push(p.tick(factor, &mut |_| {}));
        let pending =
            batches.iter().any(|(at, _)| *at > t) || control.iter().any(|(at, _)| *at > t);
        // (a halted path keeps what it did not run: the cards abort it at rest)
        if !pending && !p.is_moving() && (p.queued() == 0 || halted) {
            return (first, out);
        }
        t += 1;
        assert!(out.len() < 2_000_000, "the engine's path ends");
    }
}

#[derive(Clone, Copy)]
pub enum Control {
    Halt(f64, f64),
    Override(f64),
}

/// Every sample of every card's scope, dimension by dimension: per tick, the twelve commanded
/// positions (cards in order, each its group's axes).
pub fn read_all(set: &CardSet, split: &[usize], got: &mut BTreeMap<u64, [f64; D]>) {
    let mut at = 0;
    for (c, &n) in set.cards().iter().zip(split) {
        let mut v: Vec<ScopeSample> = Vec::new();
        c.scope().read(&mut v).unwrap();
        for s in v {
            let e = got.entry(s.tick).or_insert([f64::NAN; D]);
            e[at..at + n].copy_from_slice(&s.value[..n]);
        }
        at += n;
    }
}

/// The cards' positions from `first` on, against the engine's, every dimension, to the bit;
/// ticks compared.
pub fn compare(got: &BTreeMap<u64, [f64; D]>, first: u64, want: &[[f64; D]]) -> usize {
    let mut n = 0;
    for (k, w) in want.iter().enumerate() {
        let t = first + k as u64;
        let g = got
            .get(&t)
            .unwrap_or_else(|| panic!("no sample at tick {t}"));
        for d in 0..N {
            assert_eq!(
                g[d].to_bits(),
                w[d].to_bits(),
                "tick {t} ({k} after the start), dimension {d}: {} against {}",
                g[d],
                w[d]
            );
        }
        n += 1;
    }
    // before the start, every axis stood at the origin (a card whose scope was armed later
    // has no samples of the first ticks: NaN)
    for (t, g) in got.range(..first) {
        assert!(
            g[..N].iter().all(|&x| x == 0.0 || x.is_nan()),
            "tick {t}: {g:?}"
        );
    }
    n
}

/// Have `card`'s scope sample the commanded positions of its axes `0..n` every tick,
/// continuously, from now on.
pub fn record(card: &Card, n: usize) {
    let channels: Vec<Source> = (0..n).map(|a| Source::axis(Signal::CmdPos, a)).collect();
    let s = ScopeSettings {
        mode: ScopeMode::Continuous,
        ..ScopeSettings::new(&channels, 1)
    };
    card.scope().configure(&s).unwrap();
    card.scope().arm().unwrap();
}
