//! Cutter compensation against answers worked out by hand from the geometry (squares, an L,
//! a 120° corner, tangent arcs, the entry tangent point, LinuxCNC's entry arc), its refusals,
//! and seeded property tests over random polygons and arcs: continuity, offset distance, no
//! panic on any finite input.

use super::*;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

const EPS: f64 = 1e-9;

fn line(x: f64, y: f64) -> Piece {
    Piece::Line { end: [x, y] }
}

fn arc(x: f64, y: f64, cx: f64, cy: f64, ccw: bool) -> Piece {
    Piece::Arc {
        end: [x, y],
        centre: [cx, cy],
        ccw,
    }
}

type Out = Vec<(Offset, bool, usize)>;

/// Compensates `pieces` (payload: their index) from `start`, then G40.
fn run(start: V, side: Side, r: f64, pieces: &[Piece]) -> Result<(Out, V), CompError> {
    let mut c = Compensator::new(start, side, r);
    let mut out = Vec::new();
    for (i, p) in pieces.iter().enumerate() {
        c.push(*p, i, &mut out)?;
    }
    let end = c.finish(&mut out)?;
    Ok((out, end))
}

fn ends(o: &Offset) -> (V, V) {
    match *o {
        Offset::Line { start, end } | Offset::Arc { start, end, .. } => (start, end),
    }
}

fn length(o: &Offset) -> f64 {
    match *o {
        Offset::Line { start, end } => norm(sub(end, start)),
        Offset::Arc {
            start,
            end,
            centre,
            ccw,
        } => {
            let (a, b) = (angle(sub(start, centre)), angle(sub(end, centre)));
            let mut sweep = if ccw { b - a } else { a - b }.rem_euclid(TAU);
            if start == end {
                sweep = TAU;
            }
            sweep * norm(sub(start, centre))
        }
    }
}

/// The offset piece (not a corner arc) made from programmed move `i`.
fn of(out: &Out, i: usize) -> Offset {
    out.iter()
        .find(|(_, c, d)| !c && *d == i)
        .map(|x| x.0)
        .unwrap_or_else(|| panic!("no piece for move {i}: {out:#?}"))
}

/// The corner arc before programmed move `i`, if any.
fn corner_before(out: &Out, i: usize) -> Option<Offset> {
    out.iter().find(|(_, c, d)| *c && *d == i).map(|x| x.0)
}

fn close(a: V, b: V, tol: f64) -> bool {
    norm(sub(a, b)) <= tol
}

fn assert_close(a: V, b: V) {
    assert!(close(a, b, EPS), "{a:?} != {b:?}");
}

/// Every piece starts where the one before ended, the first at `start`.
fn assert_continuous(start: V, out: &Out, tol: f64) {
    let mut at = start;
    for (o, _, _) in out {
        let (s, e) = ends(o);
        assert!(close(s, at, tol), "gap: {at:?} then {o:?}");
        at = e;
    }
}

#[test]
fn g41_outside_a_square_clockwise() {
    // Clockwise from the bottom side's middle; entry from below, a concave join after it.
    let pieces = [
        line(0.0, -5.0),
        line(-5.0, -5.0),
        line(-5.0, 5.0),
        line(5.0, 5.0),
        line(5.0, -5.0),
        line(0.0, -5.0),
    ];
    let (out, end) = run([0.0, -15.0], Side::Left, 1.0, &pieces).unwrap();
    assert_continuous([0.0, -15.0], &out, EPS);
    assert_eq!(out.len(), 10, "{out:#?}");
    // The entry line meets the bottom's offset (y = −6) at x = −(√99/10)·(9/9.9).
    let x1 = -(99f64.sqrt() / 10.0) * (9.0 / 9.9);
    assert_close(ends(&out[0].0).1, [x1, -6.0]);
    assert_close(ends(&out[1].0).1, [-5.0, -6.0]);
    // Each side 1 outside, every corner an arc of radius 1 about the square's corner.
    let sides = [
        ([-6.0, -5.0], [-6.0, 5.0]),
        ([-5.0, 6.0], [5.0, 6.0]),
        ([6.0, 5.0], [6.0, -5.0]),
    ];
    for (k, (s, e)) in sides.iter().enumerate() {
        let (a, b) = ends(&out[3 + 2 * k].0);
        assert_close(a, *s);
        assert_close(b, *e);
        assert!(!out[3 + 2 * k].1);
    }
    let corners = [[-5.0, -5.0], [-5.0, 5.0], [5.0, 5.0], [5.0, -5.0]];
    for (k, c) in corners.iter().enumerate() {
        let (o, corner, data) = &out[2 + 2 * k];
        assert!(corner);
        assert_eq!(*data, 2 + k, "a corner arc carries the next move's payload");
        match *o {
            Offset::Arc {
                centre, ccw, start, ..
            } => {
                assert_close(centre, *c);
                assert!(!ccw);
                assert!((norm(sub(start, centre)) - 1.0).abs() < EPS);
            }
            _ => panic!("{o:?}"),
        }
        assert!((length(o) - std::f64::consts::FRAC_PI_2).abs() < EPS);
    }
    assert_close(end, [0.0, -6.0]);
    assert_close(ends(&out[9].0).0, [5.0, -6.0]);
    // Around the square: 4·10 + 2π·1, less what the entry cut off the bottom (0 to x1).
    let total: f64 = out[1..].iter().map(|(o, _, _)| length(o)).sum();
    let want = 40.0 + TAU - (0.0 - x1);
    assert!((total - want).abs() < 1e-9, "{total} != {want}");
}

#[test]
fn g42_inside_a_square_clockwise() {
    // Clockwise from the left side's middle, entry from the centre.
    let pieces = [
        line(-5.0, 0.0),
        line(-5.0, 5.0),
        line(5.0, 5.0),
        line(5.0, -5.0),
        line(-5.0, -5.0),
        line(-5.0, 0.0),
    ];
    let (out, end) = run([0.0, 0.0], Side::Right, 1.0, &pieces).unwrap();
    assert_continuous([0.0, 0.0], &out, EPS);
    assert_eq!(out.len(), 6, "{out:#?}");
    assert!(out.iter().all(|(_, corner, _)| !corner));
    // The entry line (to the tangent point (−4.8, √24/5)) meets x = −4 at y = √24/6.
    assert_close(ends(&out[0].0).1, [-4.0, 24f64.sqrt() / 6.0]);
    let corners = [[-4.0, 4.0], [4.0, 4.0], [4.0, -4.0], [-4.0, -4.0]];
    for (k, c) in corners.iter().enumerate() {
        assert_close(ends(&out[1 + k].0).1, *c);
    }
    for o in &out[2..5] {
        assert!((length(&o.0) - 8.0).abs() < EPS);
    }
    assert_close(end, [-4.0, 0.0]);
    let total: f64 = out[1..].iter().map(|(o, _, _)| length(o)).sum();
    assert!(
        (total - (32.0 - 24f64.sqrt() / 6.0)).abs() < 1e-9,
        "{total}"
    );
}

#[test]
fn concave_corners_end_at_the_intersection() {
    // An L: +x then +y, the tool on the left (inside).
    let (out, _) = run(
        [-10.0, -10.0],
        Side::Left,
        1.0,
        &[line(0.0, 0.0), line(10.0, 0.0), line(10.0, 10.0)],
    )
    .unwrap();
    assert_eq!(ends(&of(&out, 1)).1, [9.0, 1.0]);
    assert_eq!(ends(&of(&out, 2)), ([9.0, 1.0], [9.0, 10.0]));
    assert!(corner_before(&out, 2).is_none());
    // A 120° left turn: the corner r·tan 60° back along the first line.
    let d2 = [-0.5, 3f64.sqrt() / 2.0];
    let (out, _) = run(
        [-20.0, -10.0],
        Side::Left,
        1.0,
        &[
            line(-10.0, 0.0),
            line(0.0, 0.0),
            line(d2[0] * 10.0, d2[1] * 10.0),
        ],
    )
    .unwrap();
    let x = [-3f64.sqrt(), 1.0];
    assert_close(ends(&of(&out, 1)).1, x);
    assert_close(ends(&of(&out, 2)).0, x);
    // The second offset: 1 to the left of the line along d2.
    let e = ends(&of(&out, 2)).1;
    assert!((cross(d2, e) - 1.0).abs() < EPS);
}

#[test]
fn concave_line_to_arc_and_arc_to_line() {
    // +x into (0, 0), then ccw about (−5, 0) (leaving upward): a left turn, G41 inside the
    // arc (radius 4). The line's offset y = 1 meets it at (√15 − 5, 1).
    let (out, end) = run(
        [-20.0, -10.0],
        Side::Left,
        1.0,
        &[
            line(-10.0, 0.0),
            line(0.0, 0.0),
            arc(-5.0, 5.0, -5.0, 0.0, true),
        ],
    )
    .unwrap();
    assert_continuous([-20.0, -10.0], &out, EPS);
    let x = [15f64.sqrt() - 5.0, 1.0];
    assert_close(ends(&of(&out, 1)).1, x);
    assert_close(ends(&of(&out, 2)).0, x);
    assert_close(end, [-5.0, 4.0]);
    // Back: ccw about (−5, 0) from (−5, 5) to (0, 0) (arriving downward), then −x: a right
    // turn, G42 inside the arc (radius 4): the same point mirrored in time.
    let (out, end) = run(
        [-5.0, 20.0],
        Side::Right,
        1.0,
        &[
            line(-5.0, 5.0),
            arc(0.0, 0.0, -5.0, 0.0, false),
            line(-10.0, 0.0),
        ],
    )
    .unwrap();
    assert_continuous([-5.0, 20.0], &out, EPS);
    assert_close(ends(&of(&out, 1)).1, x);
    assert_close(ends(&of(&out, 2)).0, x);
    assert_close(end, [-10.0, 1.0]);
}

#[test]
fn tangent_line_and_arc_join_without_a_corner() {
    // A line along +x, a ccw quarter about (0, 5), then a line up: all tangent.
    let pieces = [
        line(-10.0, 0.0),
        line(0.0, 0.0),
        arc(5.0, 5.0, 0.0, 5.0, true),
        line(5.0, 15.0),
    ];
    // G41: inside the arc, radius 4.
    let (out, end) = run([-20.0, -10.0], Side::Left, 1.0, &pieces).unwrap();
    assert_continuous([-20.0, -10.0], &out, EPS);
    for i in 2..4 {
        assert!(corner_before(&out, i).is_none());
    }
    assert_close(ends(&of(&out, 1)).1, [0.0, 1.0]);
    match of(&out, 2) {
        Offset::Arc {
            start,
            end,
            centre,
            ccw,
        } => {
            assert_close(start, [0.0, 1.0]);
            assert_close(end, [4.0, 5.0]);
            assert_eq!(centre, [0.0, 5.0]);
            assert!(ccw);
        }
        o => panic!("{o:?}"),
    }
    assert!((length(&of(&out, 2)) - 4.0 * std::f64::consts::FRAC_PI_2).abs() < EPS);
    assert_close(end, [4.0, 15.0]);
    // G42: outside, radius 6.
    let (out, end) = run([-20.0, 10.0], Side::Right, 1.0, &pieces).unwrap();
    assert_continuous([-20.0, 10.0], &out, EPS);
    assert!(corner_before(&out, 2).is_none() && corner_before(&out, 3).is_none());
    assert_eq!(ends(&of(&out, 2)), ([0.0, -1.0], [6.0, 5.0]));
    assert_close(end, [6.0, 15.0]);
}

#[test]
fn arc_offsets_outside_and_inside() {
    // A convex corner into a cw arc (tool outside for G41): arc radius 3 + 1, same centre.
    let pieces = [line(0.0, 0.0), arc(6.0, 0.0, 3.0, 0.0, false)];
    let (out, end) = run([0.0, -10.0], Side::Left, 1.0, &pieces).unwrap();
    assert_continuous([0.0, -10.0], &out, EPS);
    match out.last().unwrap().0 {
        Offset::Arc { centre, start, .. } => {
            assert_eq!(centre, [3.0, 0.0]);
            assert!((norm(sub(start, centre)) - 4.0).abs() < EPS);
        }
        o => panic!("{o:?}"),
    }
    assert_close(end, [7.0, 0.0]);
    // G42 on the same cw arc: inside, radius 2, ending at (5, 0).
    let (out, end) = run([-10.0, 0.0], Side::Right, 1.0, &pieces).unwrap();
    assert_continuous([-10.0, 0.0], &out, EPS);
    assert_close(end, [5.0, 0.0]);
    assert!((length(&out.last().unwrap().0) - 2.0 * std::f64::consts::PI).abs() < EPS);
}

#[test]
fn entry_line_ends_at_the_tangent_point() {
    for side in [Side::Left, Side::Right] {
        let (s, p, r) = ([1.0, 2.0], [7.0, -3.0], 1.5);
        let mut c = Compensator::new(s, side, r);
        let mut out = Vec::new();
        c.push(line(p[0], p[1]), 0, &mut out).unwrap();
        assert!(out.is_empty(), "the entry waits for the next move");
        let t = c.finish(&mut out).unwrap();
        assert_eq!(ends(&out[0].0), (s, t));
        assert!((norm(sub(t, p)) - r).abs() < EPS);
        assert!(dot(sub(t, p), sub(t, s)).abs() < EPS);
        let left = cross(sub(p, s), sub(t, s)) > 0.0;
        assert_eq!(left, side == Side::Left);
    }
}

#[test]
fn entry_arc_as_linuxcnc() {
    // From (10, 0) ccw about the origin to (0, 10), G42 (outside): the end moves to (0, 11),
    // the centre to (0, 11 − 221/22), equidistant from the start and the new end.
    let mut c = Compensator::new([10.0, 0.0], Side::Right, 1.0);
    let mut out = Vec::new();
    c.push(arc(0.0, 10.0, 0.0, 0.0, true), 0, &mut out).unwrap();
    assert_close(c.finish(&mut out).unwrap(), [0.0, 11.0]);
    match out[0].0 {
        Offset::Arc {
            start,
            end,
            centre,
            ccw,
        } => {
            assert_eq!(start, [10.0, 0.0]);
            assert_close(end, [0.0, 11.0]);
            assert_close(centre, [0.0, 11.0 - 221.0 / 22.0]);
            assert!(ccw);
        }
        o => panic!("{o:?}"),
    }
}

#[test]
fn refusals() {
    let gouge = |r: Result<(Out, V), CompError>| {
        let e = r.unwrap_err();
        assert!(
            e.0.contains("gouge") || e.0.contains("does not fit"),
            "{e:?}"
        );
    };
    // The tool inside an arc of radius 0.5.
    gouge(run(
        [0.0, -10.0],
        Side::Left,
        1.0,
        &[line(0.0, 0.0), arc(1.0, 0.0, 0.5, 0.0, true)],
    ));
    // An entry shorter than the radius.
    let e = run([0.0, 0.0], Side::Left, 1.0, &[line(0.5, 0.5)]).unwrap_err();
    assert!(e.0.contains("shorter than the tool radius"), "{e:?}");
    // A slot 1.5 wide for a tool 2 wide; 2.5 wide is fine.
    let slot = |w: f64| {
        run(
            [-10.0, 20.0],
            Side::Left,
            1.0,
            &[line(0.0, 10.0), line(0.0, 0.0), line(w, 0.0), line(w, 10.0)],
        )
    };
    gouge(slot(1.5));
    let (out, end) = slot(2.5).unwrap();
    assert_close(end, [1.5, 10.0]);
    assert_eq!(ends(&of(&out, 2)), ([1.0, 1.0], [1.5, 1.0]));
    // Not finite, and the error sticks.
    let mut c = Compensator::new([0.0, 0.0], Side::Left, 1.0);
    let mut out = Vec::new();
    assert!(c.push(line(f64::NAN, 1.0), 0, &mut out).is_err());
    assert!(c.push(line(10.0, 1.0), 0, &mut out).is_err());
    assert!(c.finish(&mut out).is_err());
    let mut c = Compensator::new([0.0, 0.0], Side::Left, f64::INFINITY);
    assert!(c.push(line(10.0, 1.0), 0, &mut out).is_err());
    let mut c = Compensator::new([0.0, 0.0], Side::Left, 1.0);
    assert!(c
        .push(arc(1.0, 1.0, f64::INFINITY, 0.0, true), 0, &mut out)
        .is_err());
    assert!(out.is_empty());
}

#[test]
fn zero_radius_passes_through_and_negative_swaps_sides() {
    let pieces = [
        line(5.0, 0.0),
        line(5.0, 5.0),
        arc(0.0, 10.0, 0.0, 5.0, true),
    ];
    let (out, end) = run([0.0, 0.0], Side::Left, 0.0, &pieces).unwrap();
    assert_eq!(end, [0.0, 10.0]);
    assert_eq!(
        out.iter().map(|x| x.0).collect::<Vec<_>>(),
        vec![
            Offset::Line {
                start: [0.0, 0.0],
                end: [5.0, 0.0]
            },
            Offset::Line {
                start: [5.0, 0.0],
                end: [5.0, 5.0]
            },
            Offset::Arc {
                start: [5.0, 5.0],
                end: [0.0, 10.0],
                centre: [0.0, 5.0],
                ccw: true
            },
        ]
    );
    let a = run([0.0, 0.0], Side::Left, -1.0, &pieces).unwrap();
    let b = run([0.0, 0.0], Side::Right, 1.0, &pieces).unwrap();
    assert_eq!(a.0, b.0);
}

#[test]
fn moves_without_plane_motion_wait_at_the_corner() {
    // A Z move (no motion in the plane) between two sides of a convex corner.
    let (out, _) = run(
        [-10.0, -10.0],
        Side::Right,
        1.0,
        &[
            line(0.0, 0.0),
            line(10.0, 0.0),
            line(10.0, 0.0),
            line(10.0, 10.0),
        ],
    )
    .unwrap();
    assert_continuous([-10.0, -10.0], &out, EPS);
    // G42 along +x then +y: a left turn, the tool outside: line, Z move, corner arc, line.
    let datas: Vec<usize> = out.iter().map(|x| x.2).collect();
    assert_eq!(datas, vec![0, 1, 2, 3, 3]);
    assert_eq!(ends(&out[2].0), ([10.0, -1.0], [10.0, -1.0]));
    assert!(out[3].1);
}

#[test]
fn reversals_go_round_the_end() {
    // Out and back along a line: half a circle of radius r about the turning point.
    let (out, end) = run(
        [0.0, -10.0],
        Side::Left,
        1.0,
        &[line(0.0, 0.0), line(10.0, 0.0), line(0.0, 0.0)],
    )
    .unwrap();
    assert_continuous([0.0, -10.0], &out, EPS);
    let o = corner_before(&out, 2).unwrap();
    assert_eq!(ends(&o), ([10.0, 1.0], [10.0, -1.0]));
    assert!((length(&o) - std::f64::consts::PI).abs() < EPS);
    assert_close(end, [0.0, -1.0]);
}

fn runner(cases: u32, seed: u8) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

/// Checks a compensated polygon: continuity, every offset line at distance r on its side of
/// the programmed line, every corner arc of radius r about the programmed vertex.
fn check_polygon(start: V, pts: &[V], side: Side, r: f64, out: &Out, end: V) {
    let scale = pts
        .iter()
        .chain([&start])
        .fold(1.0f64.max(r), |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let tol = 1e-9 * scale * 10.0;
    assert_continuous(start, out, tol);
    if let Some(last) = out.last() {
        assert!(close(ends(&last.0).1, end, tol));
    }
    let s = if side == Side::Left { 1.0 } else { -1.0 };
    for (o, corner, i) in out {
        let i = *i;
        if i == 0 {
            continue; // the entry move
        }
        let (a, b) = (pts[i - 1], pts[i]);
        match *o {
            Offset::Line { start, end } if !corner => {
                let len = norm(sub(b, a));
                if len <= 1e-9 * scale {
                    assert!(close(start, end, tol));
                    continue;
                }
                let t = mul(sub(b, a), 1.0 / len);
                for p in [start, end] {
                    let d = cross(t, sub(p, a)) * s;
                    assert!((d - r).abs() <= tol, "{d} != {r}: {o:?} from {a:?}-{b:?}");
                }
            }
            Offset::Arc {
                start, end, centre, ..
            } if *corner => {
                assert_eq!(centre, a);
                assert!((norm(sub(start, centre)) - r).abs() <= tol);
                assert!((norm(sub(end, centre)) - r).abs() <= tol);
            }
            _ => panic!("{o:?} (corner {corner})"),
        }
    }
}

#[test]
fn random_polygons_stay_at_the_radius() {
    let pt = (-50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y)| [x, y]);
    let strat = (
        pt.clone(),
        prop::collection::vec(pt, 1..12),
        0.01..10.0f64,
        any::<bool>(),
    );
    let ok = std::cell::Cell::new(0u32);
    runner(2000, 41)
        .run(&strat, |(start, pts, r, left)| {
            let side = if left { Side::Left } else { Side::Right };
            let pieces: Vec<Piece> = pts.iter().map(|p| Piece::Line { end: *p }).collect();
            if let Ok((out, end)) = run(start, side, r, &pieces) {
                check_polygon(start, &pts, side, r, &out, end);
                ok.set(ok.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    assert!(ok.get() > 200, "only {} polygons compensated", ok.get());
}

#[test]
fn nearly_degenerate_polygons() {
    // Nearly collinear vertices, repeated and tiny steps, and near reversals.
    let strat = (
        prop::collection::vec((0usize..5, -1.0..1.0f64, -1.0..1.0f64), 2..16),
        0.1..2.0f64,
        any::<bool>(),
    );
    runner(2000, 42)
        .run(&strat, |(steps, r, left)| {
            let side = if left { Side::Left } else { Side::Right };
            let mut pts = vec![[0.0, 0.0], [20.0, 0.0]];
            let mut dir = [1.0, 0.0];
            for (kind, a, b) in steps {
                let last = pts[pts.len() - 1];
                let step = match kind {
                    0 => mul(add(dir, mul(left_of(dir), a * 1e-10)), 5.0 + b), // collinear
                    1 => [a * 1e-10, b * 1e-10],                               // tiny
                    2 => mul(add(mul(dir, -1.0), mul(left_of(dir), a * 1e-9)), 3.0), // back
                    3 => [0.0, 0.0],                                           // repeat
                    _ => [a * 10.0, b * 10.0],
                };
                if norm(step) > 1e-6 {
                    dir = mul(step, 1.0 / norm(step));
                }
                pts.push(add(last, step));
            }
            let start = [-10.0, -10.0];
            let pieces: Vec<Piece> = pts.iter().map(|p| Piece::Line { end: *p }).collect();
            if let Ok((out, end)) = run(start, side, r, &pieces) {
                let scale = 1e3;
                assert_continuous(start, &out, 1e-9 * scale);
                assert!(close(ends(&out[out.len() - 1].0).1, end, 1e-9 * scale));
                for (o, _, _) in &out {
                    let (a, b) = ends(o);
                    assert!(norm(a) < 1e3 && norm(b) < 1e3, "{o:?}");
                }
            }
            Ok(())
        })
        .unwrap();
}

fn left_of(v: V) -> V {
    left(v)
}

#[test]
fn random_lines_and_arcs_never_panic() {
    // Any magnitude, any arc (centres anywhere, so spirals too): an answer or an error.
    let mag = prop_oneof![
        Just(1e-12),
        Just(1e-3),
        Just(1.0),
        Just(1e6),
        Just(1e150),
        Just(1e300)
    ];
    let piece = (
        any::<bool>(),
        -1.0..1.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        -1.0..1.0f64,
        any::<bool>(),
    );
    let strat = (
        mag,
        prop::collection::vec(piece, 1..10),
        0.0..2.0f64,
        any::<bool>(),
    );
    runner(3000, 43)
        .run(&strat, |(m, ps, r, left)| {
            let side = if left { Side::Left } else { Side::Right };
            let pieces: Vec<Piece> = ps
                .iter()
                .map(|&(is_arc, x, y, cx, cy, ccw)| {
                    if is_arc {
                        arc(x * m, y * m, cx * m, cy * m, ccw)
                    } else {
                        line(x * m, y * m)
                    }
                })
                .collect();
            if let Ok((out, end)) = run([0.0, 0.0], side, r * m, &pieces) {
                assert!(finite(end));
                let mut at = [0.0, 0.0];
                for (o, _, _) in &out {
                    let (a, b) = ends(o);
                    assert!(finite(a) && finite(b));
                    assert!(close(a, at, 1e-8 * m.max(1.0)), "{at:?} then {o:?}");
                    at = b;
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn random_arc_chains_keep_their_offset_radius() {
    // Chains of tangent-or-not arcs and lines of moderate size: every offset arc (not a corner)
    // has its programmed centre and radius R ± r.
    let piece = (
        any::<bool>(),
        -20.0..20.0f64,
        -20.0..20.0f64,
        -20.0..20.0f64,
        -20.0..20.0f64,
        any::<bool>(),
    );
    let strat = (
        prop::collection::vec(piece, 1..8),
        0.1..3.0f64,
        any::<bool>(),
    );
    let ok = std::cell::Cell::new(0u32);
    runner(2000, 44)
        .run(&strat, |(ps, r, left)| {
            let side = if left { Side::Left } else { Side::Right };
            let s = if left { 1.0 } else { -1.0 };
            // Arcs made consistent: the centre on the chord's bisector.
            let mut at = [30.0, 30.0];
            let mut pieces = vec![line(at[0], at[1])];
            for &(is_arc, x, y, k, _, ccw) in &ps {
                let end = [x, y];
                if is_arc && norm(sub(end, at)) > 1e-3 {
                    let mid = mul(add(at, end), 0.5);
                    let c = add(mid, mul(left_of(sub(end, at)), k / 20.0));
                    pieces.push(arc(end[0], end[1], c[0], c[1], ccw));
                } else {
                    pieces.push(line(end[0], end[1]));
                }
                at = end;
            }
            let start = [50.0, 50.0];
            if let Ok((out, _)) = run(start, side, r, &pieces) {
                ok.set(ok.get() + 1);
                assert_continuous(start, &out, 1e-7);
                for (o, corner, i) in &out {
                    if let (
                        Offset::Arc {
                            start,
                            end,
                            centre,
                            ccw,
                        },
                        false,
                        i @ 1..,
                    ) = (o, corner, *i)
                    {
                        if let Piece::Arc {
                            end: pe,
                            centre: pc,
                            ..
                        } = pieces[i]
                        {
                            assert_eq!(*centre, pc);
                            let inside = (*ccw) == (s > 0.0);
                            let want = norm(sub(pe, pc)) + if inside { -r } else { r };
                            for p in [start, end] {
                                assert!((norm(sub(*p, pc)) - want).abs() < 1e-6, "{o:?}");
                            }
                        }
                    }
                }
            }
            Ok(())
        })
        .unwrap();
    assert!(ok.get() > 100, "only {} chains compensated", ok.get());
}
