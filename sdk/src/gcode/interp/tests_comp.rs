//! Cutter radius compensation through `comp.rs`: the interpreter's side of it (what becomes
//! of the other axes, flushing at G40, M2 and the end of the text, what is refused while it
//! is on).

use super::tests::*;
use super::*;

/// Tool 1 has diameter 2 (radius 1); tool 2 diameter 0.
fn opts() -> Options {
    Options {
        tools: tools(&[(1, 0.0, 2.0), (2, 0.0, 0.0)]),
        ..Options::default()
    }
}

/// A 10 mm square, clockwise from (0, 0): with G41 (left) the tool runs outside it.
const SQUARE: &[&str] = &[
    "T1 M6",
    "G0 X-5 Y-5",
    "G41 G1 X0 Y0 F600",
    "Y10",
    "X10",
    "Y0",
    "X0",
    "G40 G0 X-5 Y-5",
];

/// Every operation starts where the one before ended.
fn assert_continuous(ops: &[Op]) {
    let mut at: Option<Pos> = None;
    for op in ops {
        if let Some((s, e)) = op.kind.ends() {
            if let Some(a) = at {
                assert_pos(s, [a[0], a[1], a[2]]);
            }
            at = Some(e);
        }
    }
}

fn feeds_of(r: &Run, line: usize) -> Vec<(Pos, Pos)> {
    r.line(line)
        .into_iter()
        .filter_map(|k| match k {
            OpKind::Feed { start, end, .. } => Some((*start, *end)),
            _ => None,
        })
        .collect()
}

/// The corner arcs: (centre, radius, ccw).
fn corner_arcs(r: &Run) -> Vec<([f64; 3], f64, bool)> {
    r.ops
        .iter()
        .filter_map(|o| match o.kind {
            OpKind::Arc {
                start, centre, ccw, ..
            } => Some((
                centre,
                (start[0] - centre[0]).hypot(start[1] - centre[1]),
                ccw,
            )),
            _ => None,
        })
        .collect()
}

#[test]
fn g41_runs_a_square_at_the_radius_outside_with_arcs_at_its_corners() {
    let r = run_with(&opts(), SQUARE).unwrap();
    assert_continuous(&r.ops);
    // Side 1 (up x = 0) ends 1 mm left of it; sides 2 and 3 run their whole length 1 mm
    // outside; side 4 starts 1 mm below y = 0.
    let s1 = feeds_of(&r, 4);
    assert_pos(s1.last().unwrap().1, [-1.0, 10.0, 0.0]);
    let s2 = feeds_of(&r, 5);
    assert_eq!(s2.len(), 1, "{s2:?}");
    assert_pos(s2[0].0, [0.0, 11.0, 0.0]);
    assert_pos(s2[0].1, [10.0, 11.0, 0.0]);
    let s3 = feeds_of(&r, 6);
    assert_pos(s3[0].0, [11.0, 10.0, 0.0]);
    assert_pos(s3[0].1, [11.0, 0.0, 0.0]);
    let s4 = feeds_of(&r, 7);
    assert_pos(s4[0].0, [10.0, -1.0, 0.0]);
    // Convex corners: clockwise arcs of radius 1 about the square's corners.
    let arcs = corner_arcs(&r);
    for corner in [[0.0, 10.0], [10.0, 10.0], [10.0, 0.0]] {
        let a = arcs
            .iter()
            .find(|(c, _, _)| close(c[0], corner[0]) && close(c[1], corner[1]))
            .unwrap_or_else(|| panic!("no arc about {corner:?}: {arcs:?}"));
        assert!(close(a.1, 1.0) && !a.2, "{a:?}");
    }
    // The exit move (G40) ends at the programmed point.
    assert_pos(r.it.position(), [-5.0, -5.0, 0.0]);
    assert_eq!(r.it.comp_mode(), CompMode::Off);
}

#[test]
fn g41_1_takes_the_diameter_from_d_and_g42_the_other_side() {
    let mut lines = SQUARE.to_vec();
    lines[2] = "G41.1 D2 G1 X0 Y0 F600";
    let r = run_with(&opts(), &lines).unwrap();
    let s2 = feeds_of(&r, 5);
    assert_pos(s2[0].0, [0.0, 11.0, 0.0]);
    // G42 on the same clockwise square: inside, 1 mm.
    lines[2] = "G42 D1 G1 X0 Y0 F600";
    let r = run_with(&opts(), &lines).unwrap();
    let s2 = feeds_of(&r, 5);
    assert_pos(s2[0].1, [9.0, 9.0, 0.0]);
    assert_continuous(&r.ops);
}

#[test]
fn other_axes_move_along_the_pieces_and_stand_still_in_corner_arcs() {
    let mut lines = SQUARE.to_vec();
    lines[4] = "X10 Z-2";
    let r = run_with(&opts(), &lines).unwrap();
    let s2 = feeds_of(&r, 5);
    assert!(close(s2[0].1[2], -2.0));
    for o in &r.ops {
        if let OpKind::Arc { start, end, .. } = o.kind {
            assert!(close(start[2], end[2]), "a corner arc moved Z: {o:?}");
        }
    }
    assert_continuous(&r.ops);
}

#[test]
fn compensation_flushes_at_the_end_of_the_program() {
    let r = run_with(&opts(), &SQUARE[..7]).unwrap();
    let s4 = feeds_of(&r, 7);
    assert!(!s4.is_empty(), "the last side came out at the end");
    let r = run_with(&opts(), &[&SQUARE[..7], &["M2"]].concat()).unwrap();
    assert!(!feeds_of(&r, 7).is_empty());
    assert_eq!(r.ops.last().unwrap().kind, OpKind::End { rewind: false });
}

#[test]
fn a_zero_diameter_runs_the_programmed_path() {
    let o = Options {
        tools: tools(&[(1, 0.0, 2.0), (2, 5.0, 0.0)]),
        ..Options::default()
    };
    let r = run_with(&o, &["T2 M6", "G41 G43 G1 X10 Y0 Z0 F600", "Y10", "G40"]).unwrap();
    assert_eq!(r.it.comp_code(), 400);
    assert_eq!(r.it.tool_length_code(), 430);
    assert_feed(r.motion(2), [10.0, 0.0, 5.0], 10.0);
    assert_feed(r.motion(3), [10.0, 10.0, 5.0], 10.0);
}

#[test]
fn compensation_refuses_what_linuxcnc_refuses() {
    let o = opts();
    let e = run_with(&o, &["G19 G41 D1"]).unwrap_err();
    assert!(e.message.contains("XY"), "{e}");
    let e = run_with(&o, &["T2 M6", "G41", "G18"]).unwrap_err();
    assert_eq!(e.line, 3);
    assert!(e.message.contains("plane"), "{e}");
    let e = run_with(&o, &["G41 D9"]).unwrap_err();
    assert!(e.message.contains("D9"), "{e}");
    let e = run_with(&o, &["T2 M6", "G41", "G81 X0 Y0 Z-1 R1 F60"]).unwrap_err();
    assert!(e.message.contains("compensation"), "{e}");
    let e = run_with(&o, &["T2 M6", "G41", "G42"]).unwrap_err();
    assert!(e.message.contains("G40 first"), "{e}");
    for what in [
        "G28",
        "G53 G0 X1",
        "G38.2 Z-1 F10",
        "G92 X0",
        "G55",
        "G33 Z-1 K1",
    ] {
        let e = run_with(&o, &["T2 M6", "G41", what]).unwrap_err();
        assert_eq!(e.line, 3, "{what}: {e}");
        assert!(e.message.contains("compensation"), "{what}: {e}");
    }
    let e = run_with(&o, &["T2 M6", "G41", "T1 M6"]).unwrap_err();
    assert!(e.message.contains("tools"), "{e}");
}
