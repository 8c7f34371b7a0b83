//! Layout 1.14: paths across cards, at the command manager. Two cards of six axes run one
//! 12-dimension path, each driving its own six; every tick, every axis's reference is the
//! position the engine (`Path<16>`, one planner of all twelve) gives that dimension, to the
//! last bit. And what a group with dimensions refuses, each with its own nack, nothing staged
//! or changed.

use super::tests_timed::Card;
use super::*;
use crate::motion::arc::{ArcDirection, ExactCircle};
use crate::motion::path::{
    plan_ticks, BlendSpeed, Geom, Path, PathLimits, Segment, Transition, MAX_AXES as M,
};
use firmware_proto::{layout::PATH_MAX_DIMS as D, move_flags, path_flags, GroupState, Opcode};

const N: usize = 12;
const TS: f64 = 1e-4;

fn vmax(d: usize) -> f64 {
    [4e4, 6e4, 5e4][d % 3]
}
fn amax(d: usize) -> f64 {
    [6e5, 8e5, 1e6][d % 3]
}
fn jmax(d: usize) -> f64 {
    [6e7, 1e8, 8e7][d % 4 % 3]
}

/// A card of six axes, powered, group 0 over them configured and enabled, its dimensions
/// `mine` (the dimensions its axes 0..6 are) of 12, the others starting at `start`.
fn card(mine: std::ops::Range<usize>, start: &[f64; D]) -> Card {
    let mut c = Card::with_group(6);
    let r = apply(&mut c, &dims(mine, start));
    assert_eq!(r, Some(Ok(0)));
    c
}

fn dims(mine: std::ops::Range<usize>, start: &[f64; D]) -> raw::mc_group_dims {
    let mut b = raw::mc_group_dims {
        ndims: N as u32,
        ..Default::default()
    };
    for (d, &s) in start.iter().enumerate() {
        b.axis[d] = raw::MC_DIM_REMOTE;
        b.vmax[d] = vmax(d);
        b.amax[d] = amax(d);
        b.jmax[d] = jmax(d);
        b.start[d] = s;
    }
    for (k, d) in mine.enumerate() {
        b.axis[d] = k as i32;
    }
    b
}

fn apply(c: &mut Card, b: &raw::mc_group_dims) -> Option<Result<u64, NackCode>> {
    layout::GROUP_DIMS.at(0).write(&c.w, b);
    let a = c.entry(Opcode::ApplyGroupDims, 0, 0, &[]);
    c.send(&[a]);
    c.answer(a.seq)
}

/// A path segment as the host sends it: a line of 12 targets (its entry and MC_OP_PATH_MORE)
/// or an arc in dimensions 0, 1 by its centre, the other ten a helix.
enum Seg {
    Line {
        end: [f64; N],
        feed: f64,
        tol: f64,
    },
    Arc {
        end: [f64; 2],
        centre: [f64; 2],
        helix: [f64; N - 2],
        feed: f64,
    },
    Dwell(f64),
}

fn path_flags(blend: bool) -> u32 {
    let buffer = if blend {
        raw::MC_PATH_BLEND_LOW
    } else {
        raw::MC_PATH_BUFFERED
    };
    (buffer << path_flags::BUFFER_SHIFT)
        | (raw::MC_TM_MAX_DEVIATION << path_flags::TRANSITION_SHIFT)
}

fn entries(c: &mut Card, id: u32, s: &Seg) -> Vec<Command> {
    match s {
        Seg::Line { end, feed, tol } => {
            let mut a = vec![id as f64, *feed, *tol];
            a.extend_from_slice(&end[..M]);
            let l = c.entry(Opcode::PathLine, 0, path_flags(*tol > 0.0), &a);
            let m = c.entry(Opcode::PathMore, 0, 0, &end[M..]);
            vec![l, m]
        }
        Seg::Arc {
            end,
            centre,
            helix,
            feed,
        } => {
            let mut a = vec![id as f64, *feed, 2.0, end[0], end[1], centre[0], centre[1]];
            a.extend_from_slice(&helix[..M - 2]);
            let flags = path_flags(true)
                | move_flags::CIRC_CCW
                | (raw::MC_CIRC_BY_CENTRE << move_flags::CIRC_MODE_SHIFT)
                | (raw::MC_PLANE_XY << move_flags::PLANE_SHIFT);
            let l = c.entry(Opcode::PathArc, 0, flags, &a);
            let m = c.entry(Opcode::PathMore, 0, 0, &helix[M - 2..]);
            vec![l, m]
        }
        Seg::Dwell(t) => vec![c.entry(Opcode::PathDwell, 0, 0, &[id as f64, *t])],
    }
}

/// The same segment for the engine, from `start`: what one planner of all twelve axes gets
/// (an arc's end on its exact circle, as every path arc's is).
fn engine_segment(id: u32, s: &Seg, start: &[f64; D]) -> Segment<D> {
    let (geom, feed, transition) = match s {
        Seg::Line { end, feed, tol } => {
            let mut e = [0.0; D];
            e[..N].copy_from_slice(end);
            (Geom::Line { end: e }, *feed, Transition::MaxDeviation(*tol))
        }
        Seg::Arc {
            end,
            centre,
            helix,
            feed,
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
            (g, *feed, Transition::MaxDeviation(2.0))
        }
        Seg::Dwell(t) => (Geom::Dwell { time: *t }, 1.0, Transition::Exact),
    };
    let blend = !matches!(s, Seg::Dwell(_));
    Segment {
        id,
        geom,
        feed,
        transition: if blend { transition } else { Transition::Exact },
        blend: BlendSpeed::Low,
        last: false,
    }
}

fn program() -> Vec<Seg> {
    let pt = |k: f64| {
        let mut p = [0.0; N];
        for (d, x) in p.iter_mut().enumerate() {
            *x = k * (1000.0 + 137.0 * d as f64) * if d % 2 == 0 { 1.0 } else { -0.5 };
        }
        p
    };
    let mut helix = [0.0; N - 2];
    for (i, h) in helix.iter_mut().enumerate() {
        *h = 3.0 * pt(1.0)[i + 2] - 400.0 * i as f64;
    }
    let a = pt(2.0);
    vec![
        Seg::Line {
            end: pt(1.0),
            feed: 3e4,
            tol: 5.0,
        },
        Seg::Line {
            end: a,
            feed: 2e4,
            tol: 5.0,
        },
        Seg::Arc {
            // half a turn about a centre 4000 counts off in dimension 0
            end: [a[0] + 8000.0, a[1]],
            centre: [a[0] + 4000.0, a[1]],
            helix,
            feed: 2.5e4,
        },
        Seg::Dwell(0.002),
        Seg::Line {
            end: pt(0.5),
            feed: 4e4,
            tol: 0.0,
        },
        Seg::Line {
            end: pt(-0.25),
            feed: 1e5,
            tol: 20.0,
        },
        Seg::Line {
            end: [0.0; N],
            feed: 3e4,
            tol: 0.0,
        },
    ]
}

/// Tick a card once, its encoders on their references and its host's heartbeat beating (so
/// nothing faults), and say
/// where each axis's reference is.
fn tick(c: &mut Card) -> [f64; 6] {
    let mut enc = [0i64; MAX_AXES];
    for (a, e) in enc.iter_mut().enumerate().take(6) {
        *e = c.fw.axes[a].reference().pos.round() as i64;
    }
    // the host's heartbeat, so the watchdog keeps quiet
    let hb = c.w.read32(layout::HEARTBEAT);
    c.w.write32(layout::HEARTBEAT, hb.wrapping_add(1));
    c.fw.tick(&enc, &mut [0.0; MAX_AXES]);
    let mut out = [0.0; 6];
    for (a, o) in out.iter_mut().enumerate() {
        *o = c.fw.axes[a].reference().pos;
    }
    c.drain();
    out
}

/// The figure at the firmware: a 12-axis path split over two cards of six axes runs,
/// on every tick, every axis exactly where one 12-axis planner puts it (to the last bit),
/// with the segments released in two batches (the second while the path runs).
#[test]
fn a_path_over_two_cards_moves_every_axis_as_one_planner_does() {
    let zero = [0.0; D];
    let mut a = card(0..6, &zero);
    let mut b = card(6..12, &zero);
    let prog = program();
    let mut lim = PathLimits::<D> {
        naxes: N,
        ts: TS,
        vmax: [0.0; D],
        amax: [0.0; D],
        jmax: [0.0; D],
        accel: 0.0,
        jerk: 0.0,
        plan_ticks: plan_ticks(0.0, TS),
    };
    for d in 0..N {
        (lim.vmax[d], lim.amax[d], lim.jmax[d]) = (vmax(d), amax(d), jmax(d));
    }
    let mut reference = Path::<D>::with_segments(firmware_proto::PATH_LEN);
    reference.reset(zero, lim, 256).unwrap();
    // stage everything on both cards; the engine takes each batch on its release tick
    let mut engine_segs = Vec::new();
    let mut end = zero;
    for (i, s) in prog.iter().enumerate() {
        let seg = engine_segment(i as u32 + 1, s, &end);
        if let Geom::Line { end: e } | Geom::Arc { end: e, .. } = seg.geom {
            end = e;
        }
        engine_segs.push(seg);
        for c in [&mut a, &mut b] {
            let e = entries(c, i as u32 + 1, s);
            c.send(&e);
            for x in &e {
                assert_eq!(c.answer(x.seq), Some(Ok(c.fw.tick_count())), "segment {i}");
            }
        }
    }
    for c in [&a, &b] {
        let st = c.fw.group(0).unwrap().status(0);
        assert_eq!((st.path_staged, st.path_queued), (7, 0), "staged, not run");
    }
    let release = |c: &mut Card, k: usize| {
        let r = c.entry(Opcode::PathRelease, 0, 0, &[k as f64]);
        c.send(&[r]);
        assert_eq!(c.answer(r.seq), Some(Ok(c.fw.tick_count())));
    };
    let mut moved = [0.0f64; N];
    let mut ticks = 0;
    for round in 0..2 {
        let k = if round == 0 { 3 } else { 4 };
        release(&mut a, k);
        release(&mut b, k);
        for s in engine_segs.drain(..k) {
            reference.push(s).unwrap();
        }
        for _ in 0..if round == 0 { 600 } else { 200_000 } {
            let p = reference.tick(1.0, &mut |_| {});
            let (pa, pb) = (tick(&mut a), tick(&mut b));
            ticks += 1;
            for d in 0..N {
                let got = if d < 6 { pa[d] } else { pb[d - 6] };
                assert_eq!(
                    got.to_bits(),
                    p[d].to_bits(),
                    "tick {ticks}, dimension {d}: {got} against {}",
                    p[d]
                );
                moved[d] = moved[d].max(got.abs());
            }
            if round == 1 && !reference.is_moving() && reference.queued() == 0 {
                break;
            }
        }
    }
    assert!(!reference.is_moving(), "the path ran to its end");
    for (d, m) in moved.iter().enumerate() {
        assert!(*m > 1000.0, "dimension {d} moved ({m})");
    }
    for c in [&a, &b] {
        let st = c.fw.group(0).unwrap().status(0);
        assert_eq!((st.path_staged, st.path_queued, st.path_done), (0, 0, 7));
        for x in 0..6 {
            assert_eq!(c.fw.axes[x].reference().pos, 0.0, "back at the origin");
        }
    }
    println!("{ticks} ticks, every axis of both cards bit-identical to the 12-axis engine");
}

/// A host that drains late while a dense path runs (thousands of segment events a second):
/// the segment events stop short of the room the ring keeps for answers (the rest counted in
/// `events_lost`), so a release timed to a tick in the middle of the flood is still answered,
/// on its tick, and what it released runs.
#[test]
fn segment_events_leave_room_for_the_answer_of_a_timed_release() {
    let zero = [0.0; D];
    let mut c = card(0..6, &zero);
    // 250 blended chords of 20 counts in dimension 0 (5 ticks each at full feed)
    for i in 1..=250 {
        let mut end = [0.0; N];
        end[0] = 20.0 * i as f64;
        let e = entries(
            &mut c,
            i,
            &Seg::Line {
                end,
                feed: 4e4,
                tol: 1.0,
            },
        );
        c.send(&e);
        assert_eq!(c.answer(e[0].seq), Some(Ok(c.fw.tick_count())), "chord {i}");
    }
    let r = c.entry(Opcode::PathRelease, 0, 0, &[200.0]);
    c.send(&[r]);
    assert_eq!(c.answer(r.seq), Some(Ok(c.fw.tick_count())));
    let t = c.fw.tick_count() + 1500;
    let pair = c.timed(t, 0, Opcode::PathRelease, &[50.0]);
    c.send(&pair);
    assert_eq!(c.answer(pair[0].seq), Some(Ok(c.fw.tick_count())), "held");
    let lost = || c.w.read32(layout::EVENTS_LOST);
    assert_eq!(lost(), 0);
    // the host takes no event for 2,000 ticks
    for _ in 0..2000 {
        let mut enc = [0i64; MAX_AXES];
        for (a, e) in enc.iter_mut().enumerate().take(6) {
            *e = c.fw.axes[a].reference().pos.round() as i64;
        }
        let hb = c.w.read32(layout::HEARTBEAT);
        c.w.write32(layout::HEARTBEAT, hb.wrapping_add(1));
        c.fw.tick(&enc, &mut [0.0; MAX_AXES]);
    }
    let lost = c.w.read32(layout::EVENTS_LOST);
    c.drain();
    assert!(lost > 0, "the flood was larger than the ring");
    assert_eq!(c.answer(pair[1].seq), Some(Ok(t)), "answered on its tick");
    assert!(
        c.events
            .iter()
            .any(|e| e.kind == EventKind::Timed as u16 && e.seq == pair[1].seq && e.tick == t),
        "MC_EV_TIMED"
    );
    let done = c.fw.group(0).unwrap().status(0).path_done;
    assert!(
        done > 200,
        "the path ran into what the timed release gave it ({done})"
    );
    let ends = c
        .events
        .iter()
        .filter(|e| e.kind == EventKind::SegmentEnd as u16)
        .count();
    println!("{done} chords ended, {ends} of their ends posted, {lost} events lost");
    while c.fw.group(0).unwrap().status(0).path_queued > 0 {
        tick(&mut c);
    }
    assert_eq!(
        c.fw.axes[0].reference().pos,
        5000.0,
        "at the last chord's end"
    );
}

fn staged(c: &Card) -> (u32, u32) {
    let st = c.fw.group(0).unwrap().status(0);
    (st.path_staged, st.path_queued)
}

/// What a group's dimensions refuse, each with its own nack and nothing changed: blocks that
/// name a group axis twice, not at all, beyond the group, or 17 dimensions; a limit that is
/// NaN; a remote start beyond the card's positions.
#[test]
fn a_dims_block_that_does_not_name_each_group_axis_once_is_refused() {
    let zero = [0.0; D];
    let mut c = card(0..6, &zero);
    let good = dims(0..6, &zero);
    type Edit = Box<dyn Fn(&mut raw::mc_group_dims)>;
    let cases: [(&str, Edit, NackCode); 7] = [
        (
            "an axis twice",
            Box::new(|b| b.axis[7] = 0),
            NackCode::PathDims,
        ),
        (
            "an axis missing",
            Box::new(|b| b.axis[5] = -1),
            NackCode::PathDims,
        ),
        (
            "beyond the group",
            Box::new(|b| b.axis[7] = 6),
            NackCode::PathDims,
        ),
        (
            "below remote",
            Box::new(|b| b.axis[7] = -2),
            NackCode::PathDims,
        ),
        (
            "17 dimensions",
            Box::new(|b| b.ndims = 17),
            NackCode::PathDims,
        ),
        (
            "a NaN limit",
            Box::new(|b| b.jmax[9] = f64::NAN),
            NackCode::NotFinite,
        ),
        (
            "a start too far",
            Box::new(|b| b.start[9] = 1e300),
            NackCode::OutOfRange,
        ),
    ];
    for (what, f, code) in cases {
        let mut b = good;
        f(&mut b);
        assert_eq!(apply(&mut c, &b), Some(Err(code)), "{what}");
    }
    // a limit of 0, and one the card cannot run at its servo rate: the range check's
    let mut b = good;
    b.vmax[3] = 0.0;
    assert_eq!(apply(&mut c, &b), Some(Err(NackCode::NonPositiveLimit)));
    b.vmax[3] = 1e300;
    assert_eq!(apply(&mut c, &b), Some(Err(NackCode::LimitRange)));
    // (the card kept its dimensions: a 12-dimension line still needs its second entry)
    let mut e = entries(
        &mut c,
        1,
        &Seg::Line {
            end: [1.0; N],
            feed: 1e4,
            tol: 0.0,
        },
    );
    e.truncate(1);
    c.send(&e);
    assert_eq!(c.answer(e[0].seq), Some(Err(NackCode::PathMore)));
    assert_eq!(staged(&c), (0, 0));
}

/// The entries of a segment across cards: a 12-dimension line without its MC_OP_PATH_MORE,
/// an MC_OP_PATH_MORE alone, a second entry on a group without dimensions, the kinds of
/// segment a path across cards does not take, and releases of what is not staged: each
/// refused with its nack, nothing staged or queued.
#[test]
fn the_pieces_of_a_segment_across_cards_go_together() {
    let zero = [0.0; D];
    let mut c = card(0..6, &zero);
    let line = Seg::Line {
        end: [100.0; N],
        feed: 1e4,
        tol: 0.0,
    };
    let e = entries(&mut c, 1, &line);
    // the MC_OP_PATH_MORE alone, then the line alone
    c.send(&e[1..]);
    assert_eq!(c.answer(e[1].seq), Some(Err(NackCode::PathMore)));
    c.send(&e[..1]);
    assert_eq!(c.answer(e[0].seq), Some(Err(NackCode::PathMore)));
    // the pair is one segment, both answered
    let e = entries(&mut c, 2, &line);
    c.send(&e);
    assert_eq!(
        (c.answer(e[0].seq), c.answer(e[1].seq)),
        (Some(Ok(0)), Some(Ok(0)))
    );
    assert_eq!(staged(&c), (1, 0));
    // Aborting, an output, a NURBS segment: not across cards
    let mut a = vec![3.0, 1e4, 0.0];
    a.extend_from_slice(&[200.0; M]);
    let abort = c.entry(
        Opcode::PathLine,
        0,
        raw::MC_PATH_ABORTING << path_flags::BUFFER_SHIFT,
        &a,
    );
    let more = c.entry(Opcode::PathMore, 0, 0, &[200.0; 4]);
    c.send(&[abort, more]);
    assert_eq!(c.answer(abort.seq), Some(Err(NackCode::PathMode)));
    let out = c.entry(Opcode::PathOutput, 0, 0, &[0.0, 1.0, 0.0]);
    let nurbs = c.entry(
        Opcode::PathNurbs,
        0,
        0,
        &[4.0, 1e4, 0.0, 3.0, 4.0, 8.0, 1.0],
    );
    c.send(&[out, nurbs]);
    assert_eq!(c.answer(out.seq), Some(Err(NackCode::IncompatibleMode)));
    assert_eq!(c.answer(nurbs.seq), Some(Err(NackCode::IncompatibleMode)));
    // releases of nothing, of more than is staged, of a fraction
    for k in [0.0, 2.0, 0.5, -1.0] {
        let r = c.entry(Opcode::PathRelease, 0, 0, &[k]);
        c.send(&[r]);
        assert_eq!(c.answer(r.seq), Some(Err(NackCode::PathRelease)), "{k}");
    }
    let r = c.entry(Opcode::PathRelease, 0, 0, &[f64::NAN]);
    c.send(&[r]);
    assert_eq!(c.answer(r.seq), Some(Err(NackCode::NotFinite)));
    assert_eq!(staged(&c), (1, 0), "the one segment still staged");
    // new dimensions while a segment is staged: busy
    assert_eq!(
        apply(&mut c, &dims(0..6, &zero)),
        Some(Err(NackCode::PathBusy))
    );
    // without dimensions: a second entry is refused with the line, a release too
    let mut b = dims(0..6, &zero);
    b.ndims = 0;
    let h = c.entry(Opcode::GroupHalt, 0, 0, &[1e6, 1e8]);
    c.send(&[h]);
    assert_eq!(staged(&c), (0, 0), "a halt aborts what is staged");
    assert_eq!(apply(&mut c, &b), Some(Ok(0)));
    let e = entries(&mut c, 5, &line);
    c.send(&e);
    assert_eq!(c.answer(e[0].seq), Some(Err(NackCode::PathDims)));
    let r = c.entry(Opcode::PathRelease, 0, 0, &[1.0]);
    c.send(&[r]);
    assert_eq!(c.answer(r.seq), Some(Err(NackCode::PathDims)));
}

/// A halt aborts every staged segment at once, one `GroupMotionAborted` each under its own
/// seq, oldest first; staging then begins afresh.
#[test]
fn a_halt_aborts_what_is_staged() {
    let zero = [0.0; D];
    let mut c = card(0..6, &zero);
    let mut seqs = Vec::new();
    for i in 0..3 {
        let e = entries(
            &mut c,
            i + 1,
            &Seg::Line {
                end: [100.0 * (i + 1) as f64; N],
                feed: 1e4,
                tol: 0.0,
            },
        );
        c.send(&e);
        seqs.push(e[0].seq);
    }
    assert_eq!(staged(&c), (3, 0));
    let h = c.entry(Opcode::GroupHalt, 0, 0, &[1e6, 1e8]);
    c.send(&[h]);
    let aborted: Vec<u32> = c
        .events
        .iter()
        .filter(|e| e.kind == EventKind::GroupMotionAborted as u16)
        .map(|e| {
            assert_eq!(e.code, Opcode::GroupHalt as i32);
            e.seq
        })
        .collect();
    assert_eq!(aborted, seqs);
    assert_eq!(staged(&c), (0, 0));
    // the halt ends in position (the group took no segment meanwhile: it halts)
    let mut ticks = 0;
    while c.fw.group(0).unwrap().state != GroupState::Standby {
        tick(&mut c);
        ticks += 1;
        assert!(ticks < 100, "the halt ends");
    }
    // staging begins afresh: the next segment stages from where the group is
    let e = entries(
        &mut c,
        9,
        &Seg::Line {
            end: [50.0; N],
            feed: 1e4,
            tol: 0.0,
        },
    );
    c.send(&e);
    assert_eq!(c.answer(e[0].seq), Some(Ok(c.fw.tick_count())));
    assert_eq!(staged(&c), (1, 0));
    let r = c.entry(Opcode::PathRelease, 0, 0, &[1.0]);
    c.send(&[r]);
    assert_eq!(c.answer(r.seq), Some(Ok(c.fw.tick_count())));
    assert_eq!(staged(&c), (0, 1), "released");
}

/// A number from the whole f64 range: the edges (NaN, ±∞, 0, −0, subnormals, 1e−300, 1e300,
/// the card's position limit and just past it) or a plausible one.
fn any_f64() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![
        prop::sample::select(vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            f64::MIN_POSITIVE / 4.0,
            1e-300,
            -1e300,
            1e300,
            crate::MAX_POSITION,
            -crate::MAX_POSITION * 1.0000001,
        ]),
        -1e6..1e6f64,
        1e3..1e9f64,
    ]
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
    /// Any dimensions block and any 12-dimension line (with its MC_OP_PATH_MORE) over the
    /// whole f64 range: never a panic; each refused with a nack, or accepted, and what was
    /// accepted then runs with finite references on every axis (released, 3,000 ticks).
    #[test]
    fn any_dims_and_any_line_are_refused_or_run_finite(
        mapped in proptest::prelude::any::<bool>(),
        ndims in 0u32..20,
        axis in proptest::collection::vec(-3i32..9, 16),
        edges in proptest::prelude::any::<bool>(),
        lim in proptest::collection::vec(any_f64(), 48),
        start in proptest::collection::vec(any_f64(), 16),
        target in proptest::collection::vec(any_f64(), 12),
        feed in any_f64(),
        tol in any_f64(),
    ) {
        let mut c = Card::with_group(6);
        // half the cases a block that names each group axis once (else it is refused before
        // anything else is looked at), half of those with limits the card can run
        let mut b = if mapped {
            dims(0..6, &[0.0; D])
        } else {
            raw::mc_group_dims { ndims, ..Default::default() }
        };
        if !mapped {
            b.axis.copy_from_slice(&axis);
        }
        if edges || !mapped {
            b.vmax.copy_from_slice(&lim[..16]);
            b.amax.copy_from_slice(&lim[16..32]);
            b.jmax.copy_from_slice(&lim[32..]);
        }
        b.start.copy_from_slice(&start);
        // and half the cases with numbers a path can run, the others from the whole range
        let tame = |x: f64| if x.is_finite() && x.abs() < 1e6 { x } else { 1e3 };
        let (feed, tol) = if edges { (feed, tol) } else { (tame(feed).abs() + 1.0, 1.0) };
        let target: Vec<f64> = target.iter().map(|&x| if edges { x } else { tame(x) }).collect();
        if !edges {
            b.start = [0.0; D];
        }
        let applied = apply(&mut c, &b).expect("answered");
        let line = Seg::Line { end: target.clone().try_into().unwrap(), feed, tol };
        let e = entries(&mut c, 1, &line);
        c.send(&e);
        let staged = c.answer(e[0].seq).expect("answered").is_ok();
        proptest::prop_assert!(staged <= (applied.is_ok() && b.ndims == 12));
        if staged {
            let r = c.entry(Opcode::PathRelease, 0, 0, &[1.0]);
            c.send(&[r]);
            for _ in 0..3_000 {
                let p = tick(&mut c);
                proptest::prop_assert!(p.iter().all(|x| x.is_finite()), "{p:?}");
            }
        }
    }
}
