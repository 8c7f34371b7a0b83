//! G18/G19 arcs, helices, canned cycles and cutter compensation in a coordinate system rotated
//! about Z (G10 L2 R): arcs in planes given by their normal ([`OpKind::ArcNormal`]), checked
//! against the circles worked out by hand in work coordinates, and every program checked to
//! be the same program turned about Z.

use crate::gcode::{Op, OpKind, Options, Plane, Program};
use crate::report::{blocks_of, Block};
use std::f64::consts::{FRAC_1_SQRT_2, PI, TAU};

fn ops(text: &str) -> Vec<Op> {
    Program::from_text(text, &Options::default())
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn arcs(ops: &[Op]) -> Vec<&Op> {
    ops.iter()
        .filter(|o| matches!(o.kind, OpKind::Arc { .. } | OpKind::ArcNormal { .. }))
        .collect()
}

#[track_caller]
fn near(a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{a:?} vs {b:?} (within {tol})");
    }
}

/// `p` (x, y, z) turned `deg` about Z.
fn turn(p: [f64; 3], deg: f64) -> [f64; 3] {
    let (s, c) = deg.to_radians().sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
}

fn xyz(p: &[f64]) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// Machine → work for `G10 L2 P0 X-2 Y1 R60` in inches (the LinuxCNC programs below), in
/// program inches.
fn to_work_inch(m: [f64; 3]) -> [f64; 3] {
    let d = [m[0] / 25.4 + 2.0, m[1] / 25.4 - 1.0, m[2] / 25.4];
    turn(d, -60.0)
}

/// LinuxCNC's `tests/trajectory-planner/circular-arcs/nc_files/arc-feed/full_yz.ngc` (a G18
/// arc in a system rotated 60° about Z, in inches) and `full_xz.ngc` (its G19 twin), their
/// motion lines: each arc runs about the rotated plane's normal, every point of it (in work
/// coordinates) on the circle worked out from the program, in the plane, at the angle its
/// share of the length gives; the lengths are r·θ.
#[test]
fn linuxcnc_arcs_in_a_rotated_g18_and_g19_plane() {
    // full_yz.ngc: from work X1.5 Z.5, a G2 about Z1.5 X1.5 (K1) to X.5 Z1.5: in (Z, X) from
    // the angle π clockwise to −π/2, 3π/2; then G3 R1 back, the short way about Z.5 X.5: π/2.
    let g18 = ops(
        "G20 G90\nG61\nG10 L2 P0 X-2 Y1 R60\nF1000\nG0 X0 Y0 Z0\nG1 X1.5 Z.5\nG18\n\
                   G2 X.5 Z1.5 K1 (270 deg. arc CCW)\nG3 X1.5 Z.5 R1\nG0 X0 Y0 Z0\nM2\n",
    );
    // full_xz.ngc: from work Y1.5 Z.5, a G2 about Y1.5 Z1.5 to Y.5 Z1.5: in (Y, Z) from −π/2
    // clockwise to π, π/2.
    let g19 = ops(
        "G20 G90\nG61\nG10 L2 P0 X-2 Y1 R60\nF10000\nG0 X0 Y0 Z0\nG0 Y1.5 Z.5\n\
                   G19\nG2 F10000 Y.5 Z1.5 K1 (270 deg. arc CCW)\nM2\n",
    );
    // (plane, work normal, centre in the plane's (first, second), start angle, signed sweep)
    let cases = [
        (
            &g18,
            8,
            Plane::Zx,
            [0.0, 1.0, 0.0],
            [1.5, 1.5],
            PI,
            -1.5 * PI,
        ),
        (
            &g18,
            9,
            Plane::Zx,
            [0.0, 1.0, 0.0],
            [0.5, 0.5],
            0.0,
            0.5 * PI,
        ),
        (
            &g19,
            8,
            Plane::Yz,
            [1.0, 0.0, 0.0],
            [1.5, 1.5],
            -0.5 * PI,
            -0.5 * PI,
        ),
    ];
    for (prog, line, plane, wn, c, a0, sw) in cases {
        let a = arcs(prog);
        let op = a.iter().find(|o| o.line == line).unwrap();
        let OpKind::ArcNormal {
            normal, ccw, turns, ..
        } = op.kind
        else {
            panic!("line {line}: {:?}", op.kind)
        };
        assert_eq!((ccw, turns), (sw > 0.0, 0), "line {line}");
        near(&normal, &turn(wn, 60.0), 1e-15);
        let len = op.kind.length().unwrap();
        let want = 25.4 * sw.abs();
        assert!(
            (len - want).abs() <= 1e-12 * want,
            "line {line}: {len} vs {want}"
        );
        let f = op.kind.normal_arc_frame().unwrap();
        let (u, v, n) = plane.axes();
        for k in 0..=16 {
            let t = k as f64 / 16.0;
            let w = to_work_inch(f.point(t));
            let th = a0 + t * sw;
            let mut want = [0.0; 3];
            want[u] = c[0] + th.cos();
            want[v] = c[1] + th.sin();
            // the plane's normal coordinate: Y0 in G18, X0 in G19 (where the arc starts)
            want[n] = 0.0;
            near(&w, &want, 1e-12);
        }
    }
    // the program's ends, exactly where the rotated system puts them
    let end = |ops: &[Op], line: usize| ops.iter().find(|o| o.line == line).unwrap().kind.ends();
    let (_, e) = end(&g18, 8).unwrap();
    near(&to_work_inch(xyz(&e)), &[0.5, 0.0, 1.5], 1e-12);
    let (_, e) = end(&g18, 9).unwrap();
    near(&to_work_inch(xyz(&e)), &[1.5, 0.0, 0.5], 1e-12);
    let (_, e) = end(&g19, 8).unwrap();
    near(&to_work_inch(xyz(&e)), &[0.0, 0.5, 1.5], 1e-12);
}

/// Every operation of `body` run after `G10 L2 P1 R<deg>` is the one run without the
/// rotation turned about Z: rapids, feeds and the ends of arcs turned, feeds and lengths the
/// same, a G18/G19 arc an arc about the turned normal (the report's blocks on the turned
/// curve, point for point), a G17 arc still a plane arc. The operations compared.
fn same_turned(body: &str, deg: f64) -> usize {
    let plain = ops(&format!("G10 L2 P1 R0\n{body}"));
    let turned = ops(&format!("G10 L2 P1 R{deg}\n{body}"));
    assert_eq!(plain.len(), turned.len());
    let mut normal_arcs = 0;
    for (p, t) in plain.iter().zip(&turned) {
        assert_eq!(p.line, t.line);
        let ctx = format!("line {}: {:?} / {:?}", p.line, p.kind, t.kind);
        assert_eq!(
            p.kind.name() == "arc",
            t.kind.name().starts_with("arc"),
            "{ctx}"
        );
        if let (Some((ps, pe)), Some((ts, te))) = (p.kind.ends(), t.kind.ends()) {
            near(&xyz(&ts), &turn(xyz(&ps), deg), 1e-9);
            near(&xyz(&te), &turn(xyz(&pe), deg), 1e-9);
            near(&te[3..], &pe[3..], 0.0);
            let (lp, lt) = (p.kind.length().unwrap(), t.kind.length().unwrap());
            assert!((lp - lt).abs() <= 1e-9 * lp.max(1.0), "{ctx}: {lp} vs {lt}");
        } else {
            assert_eq!(p.kind, t.kind);
        }
        match (&p.kind, &t.kind) {
            (OpKind::Rapid { .. }, OpKind::Rapid { .. }) => {}
            (OpKind::Feed { feed: a, .. }, OpKind::Feed { feed: b, .. }) => {
                assert!((a - b).abs() <= 1e-12 * a, "{ctx}")
            }
            (
                OpKind::Arc {
                    plane: Plane::Xy, ..
                },
                OpKind::Arc {
                    plane: Plane::Xy, ..
                },
            ) => {}
            (
                OpKind::Arc {
                    plane,
                    ccw,
                    turns,
                    feed,
                    ..
                },
                OpKind::ArcNormal {
                    normal,
                    ccw: ccw_t,
                    turns: turns_t,
                    feed: feed_t,
                    ..
                },
            ) => {
                normal_arcs += 1;
                assert_eq!((ccw, turns), (ccw_t, turns_t), "{ctx}");
                assert!((feed - feed_t).abs() <= 1e-12 * feed, "{ctx}");
                let mut n = [0.0; 3];
                n[plane.axes().2] = 1.0;
                near(normal, &turn(n, deg), 1e-15);
                let (mut bp, mut bt) = (Vec::new(), Vec::new());
                blocks_of(p, &mut bp);
                blocks_of(t, &mut bt);
                assert_eq!(bp.len(), bt.len(), "{ctx}");
                for (a, b) in bp.iter().zip(&bt) {
                    assert!(matches!(b, Block::ArcNormal { .. }), "{b:?}");
                    assert!((a.length() - b.length()).abs() <= 1e-9 * a.length());
                    for k in 0..=32 {
                        let f = k as f64 / 32.0;
                        let want = turn(a.point_at(f).unwrap(), deg);
                        near(&b.point_at(f).unwrap(), &want, 1e-9);
                    }
                }
            }
            (a, b) => assert_eq!(a.name(), b.name(), "{ctx}"),
        }
    }
    normal_arcs
}

/// A G18 helix in a system rotated 30° about Z: three quarter turns plus two whole ones (P3)
/// about work X5 Z0 of radius 5, rising 6 mm along the rotated Y while A turns 90°: one
/// operation about the rotated Y axis; its length √((r·θ)² + 6²), θ = 2.75 turns; the
/// report's blocks a turn each, ending above the start by their share of the rise.
#[test]
fn a_rotated_g18_helix_with_turns_and_a_rotary_axis() {
    let o = ops("G10 L2 P1 X3 Y-4 R30\nG0 X0 Y0 Z0 A0\nG18 G2 X5 Z5 Y6 A90 I5 K0 P3 F600\nM2\n");
    let a = arcs(&o);
    assert_eq!(a.len(), 1);
    let OpKind::ArcNormal {
        start,
        end,
        normal,
        ccw,
        turns,
        ..
    } = a[0].kind
    else {
        panic!("{:?}", a[0].kind)
    };
    assert!(!ccw && turns == 2);
    near(&normal, &turn([0.0, 1.0, 0.0], 30.0), 1e-15);
    near(&xyz(&start), &[3.0, -4.0, 0.0], 1e-12);
    let w_end = turn([5.0, 6.0, 5.0], 30.0);
    near(&xyz(&end), &[w_end[0] + 3.0, w_end[1] - 4.0, 5.0], 1e-12);
    assert_eq!(end[3], 90.0);
    // from (Z0, X0) about (Z0, X5): the angle −π/2 (in (Z, X)) clockwise to 0 (Z5 X5):
    // three quarters, and two turns
    let theta = 2.75 * TAU;
    assert!((a[0].kind.arc_sweep().unwrap() - theta).abs() < 1e-12);
    let want = (5.0 * theta).hypot(6.0);
    let len = a[0].kind.length().unwrap();
    assert!((len - want).abs() <= 1e-12 * want, "{len} vs {want}");
    let mut b = Vec::new();
    blocks_of(a[0], &mut b);
    assert_eq!(b.len(), 3);
    let total: f64 = b.iter().map(Block::length).sum();
    assert!((total - want).abs() <= 1e-12 * want, "{total} vs {want}");
    for (k, blk) in b[..2].iter().enumerate() {
        let rise = 6.0 * (k + 1) as f64 / 2.75;
        let w = turn([0.0, rise, 0.0], 30.0);
        near(&blk.end().unwrap(), &[w[0] + 3.0, w[1] - 4.0, 0.0], 1e-12);
    }
    // and the same helix unrotated, turned
    assert_eq!(
        same_turned(
            "G0 X0 Y0 Z0 A0\nG18 G2 X5 Z5 Y6 A90 I5 K0 P3 F600\nM2\n",
            30.0
        ),
        1
    );
}

/// Programs turned by the rotation: G18 and G19 arcs and helices (I/K, R, full circles, G3
/// and G2) beside G17 ones; LinuxCNC's G18 and G19 drilling and tapping cycles
/// (`tests/interp/g81/g18/g98/g18-g98-g81.ngc`, `g81/g19/g99/g19-g99-g81.ngc`,
/// `g84/g19/g98/g19-g98-g84.ngc`, their cycle lines); cutter compensation in G18 with its
/// corner arcs.
#[test]
fn g18_g19_arcs_cycles_and_compensation_turn_with_the_system() {
    let arcs_body = "G21 G0 X1 Y2 Z3\nG18 G3 X11 Z3 I5 K0 F300\nG2 X1 Z3 R5 Y-2\n\
                     G2 X1 Z3 I5 K0 Y4 P2\nG19 G3 Y14 Z3 J5 K0 X2\nG2 Y2 Z13 R-10\n\
                     G17 G2 X6 Y2 I2 J2 Z1\nM2\n";
    for deg in [30.0, -135.0, 90.0, 7.5] {
        assert_eq!(same_turned(arcs_body, deg), 5, "R{deg}");
    }
    let g81_g18 = "G18\nG98\nG90\nG20\nF10\nG0 X0 Y2 Z0\nG81 X1 Z1 Y-1 R1\nG81 X1 Z2 Y0.5 R3\n\
                   G81 X1 Z3 Y4 R5\nG90 G0 X10 Z0 Y2\nG91 G81 X1 Z1 Y-2 R-1 L2\n\
                   G90 G0 X30 Z0 Y2\nG91 G81 X1 Z1 Y-1 R3 L2\nM2\n";
    let g81_g19 = "G19\nG99\nG90\nG20\nF10\nG0 Y0 Z0 X2\nG81 Y1 Z1 X-1 R1\nG81 Y1 Z2 X0.5 R3\n\
                   G81 Y1 Z3 X4 R5\nG90 G0 Y10 Z0 X2\nG91 G81 Y1 Z1 X-2 R-1 L2\nM2\n";
    let g84_g19 = "G19\nG98\nG90\nG20\nM3 S1000\nF10\nG0 X2 Y0 Z0\nG84 Y1 Z1 X-1 R1\n\
                   G84 Y1 Z2 X0.5 R3\nM2\n";
    for body in [g81_g18, g81_g19, g84_g19] {
        same_turned(body, 30.0);
    }
    // (the cycle drills along the rotated axis: G18's first hole from Y1 down to Y−1, in
    // inches, is a feed along the rotated Y)
    let o = ops(&format!("G10 L2 P1 R30\n{g81_g18}"));
    let feed = o.iter().find(|o| o.line == 8 && o.kind.name() == "feed");
    let OpKind::Feed { start, end, .. } = feed.unwrap().kind else {
        panic!()
    };
    let d = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
    near(&d, &turn([0.0, -2.0 * 25.4, 0.0], 30.0), 1e-12);
    let comp = "G21 G18 G0 X0 Y0 Z0\nG41.1 D4 G1 X10 Z0 F300\nG1 X10 Z10\nG3 X0 Z10 R5\n\
                G1 X0 Z0\nG1 X10 Z0\nG40 G0 X-10\nM2\n";
    assert!(same_turned(comp, 30.0) >= 2);
}

/// The old refusals that remain: a G19 compensation, and an arc whose centre offset names
/// the plane's normal, each with its line.
#[test]
fn what_stays_refused_names_its_line() {
    let e = Program::from_text(
        "G10 L2 P1 R30\nG19 G0 X0 Y0 Z0\nG41.1 D4 G1 Y10\nM2\n",
        &Options::default(),
    )
    .find_map(Result::err)
    .unwrap();
    assert_eq!(e.line, 3, "{e}");
    let e = Program::from_text(
        "G10 L2 P1 R30\nG0 X0 Y0 Z0\nG18 G2 X5 Z5 I5 J1 K0 F60\n",
        &Options::default(),
    )
    .find_map(Result::err)
    .unwrap();
    assert_eq!(e.line, 3, "{e}");
}

/// A G19 half turn in a system rotated 45°: the circle's frame has the half turn's sweep and
/// no rise, and its middle is work Y5 Z−5 (G3 in (Y, Z) from the −Y side goes down) turned.
#[test]
fn a_rotated_g19_half_turn_passes_below_its_centre() {
    let o = ops("G10 L2 P1 R45\nG0 X0 Y0 Z0\nG19 G3 Y10 Z0 J5 K0 F60\nM2\n");
    let f = arcs(&o)[0].kind.normal_arc_frame().unwrap();
    assert!((f.sweep - PI).abs() < 1e-12 && f.rise.abs() < 1e-12);
    // work (0, 5, −5) (G3 in (Y, Z) from the −Y side goes down) turned 45°
    near(
        &f.point(0.5),
        &[-5.0 * FRAC_1_SQRT_2, 5.0 * FRAC_1_SQRT_2, -5.0],
        1e-12,
    );
}
