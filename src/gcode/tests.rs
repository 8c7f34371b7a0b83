//! The G-code reader's unit tests (`super`: `src/gcode.rs`).

use super::*;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    dist(a, b) < 1e-9
}

fn blocks(text: &str) -> Vec<Block> {
    parse(text).unwrap_or_else(|e| panic!("{e}")).blocks
}

fn error(text: &str) -> GcodeError {
    match parse(text) {
        Ok(p) => panic!("parsed: {p:?}"),
        Err(e) => e,
    }
}

#[test]
fn rapid_and_feed_lines() {
    let b = blocks("G0 X10 Y5\nG1 Z-2 F600\nX20\n");
    assert_eq!(
        b[0],
        Block::Line {
            line: 1,
            rapid: true,
            start: [0.0; 3],
            end: [10.0, 5.0, 0.0],
            feed: f64::INFINITY
        }
    );
    assert_eq!(
        b[1],
        Block::Line {
            line: 2,
            rapid: false,
            start: [10.0, 5.0, 0.0],
            end: [10.0, 5.0, -2.0],
            feed: 10.0
        }
    );
    // Modal G1 and F.
    assert_eq!(b[2].end(), Some([20.0, 5.0, -2.0]));
    assert_eq!(b[2].feed(), Some(10.0));
    assert_eq!(b[2].line(), 3);
}

#[test]
fn comments_line_numbers_percent_and_end() {
    let text =
        "%\n(header)\nN10 G21 G90 ; semicolon comment\nN20 G1 X1 F60 (inline)\n\nM2\n(after)\n%\n";
    let p = parse(text).unwrap();
    assert_eq!(p.blocks.len(), 1);
    assert_eq!(p.blocks[0].line(), 4);
    assert_eq!(p.blocks[0].feed(), Some(1.0));
    assert_eq!(parse("G0 X1\nM30\n").unwrap().blocks.len(), 1);
    assert_eq!(error("G0 X1\nM30\nG0 X2\n").line, 3);
}

#[test]
fn numbers_keep_f64_precision_and_lowercase() {
    let b = blocks("g1 x123.456789012 y-.5 f+60");
    assert_eq!(b[0].end(), Some([123.456789012, -0.5, 0.0]));
}

#[test]
fn inch_conversion() {
    let b = blocks("G20 G0 X1 Y2\nG1 Z-0.5 F10\nG21 X0\n");
    assert!(close(b[0].end().unwrap(), [25.4, 50.8, 0.0]));
    assert!(close(b[1].end().unwrap(), [25.4, 50.8, -12.7]));
    // 10 in/min = 254 mm/min; the feed keeps its physical value across G21.
    assert!((b[1].feed().unwrap() - 254.0 / 60.0).abs() < 1e-12);
    assert!(close(b[2].end().unwrap(), [0.0, 50.8, -12.7]));
    assert_eq!(b[2].feed(), b[1].feed());
    // Arc offsets and R are lengths too.
    let b = blocks("G20 G0 X1\nG3 X0 Y1 R1 F10\nG2 X1 Y0 I0 J-1\n");
    let g = b[1].arc_geom().unwrap();
    assert!((g.radius - 25.4).abs() < 1e-9 && g.centre.iter().all(|c| c.abs() < 1e-9));
    let g = b[2].arc_geom().unwrap();
    assert!((g.radius - 25.4).abs() < 1e-9 && g.centre.iter().all(|c| c.abs() < 1e-9));
}

#[test]
fn incremental_mode() {
    let b = blocks("G0 X10 Y10\nG91 G1 X5 F60\nY-3\nG3 X-5 Y5 I-5 J0\nG90 G1 X0 Y0\n");
    assert!(close(b[1].end().unwrap(), [15.0, 10.0, 0.0]));
    assert!(close(b[2].end().unwrap(), [15.0, 7.0, 0.0]));
    // I/J stay relative to the start in both modes; the end is incremental.
    assert!(close(b[3].end().unwrap(), [10.0, 12.0, 0.0]));
    let Block::Arc { centre, .. } = b[3] else {
        panic!()
    };
    assert!(close(centre, [10.0, 7.0, 0.0]));
    assert!(close(b[4].end().unwrap(), [0.0, 0.0, 0.0]));
}

#[test]
fn arc_by_ijk_both_directions() {
    let b = blocks("G0 X10\nG3 X0 Y10 I-10 J0 F600\nG2 X10 Y0 I0 J-10\n");
    let Block::Arc {
        centre, ccw, feed, ..
    } = b[1]
    else {
        panic!()
    };
    assert!(close(centre, [0.0; 3]) && ccw && feed == 10.0);
    let g = b[1].arc_geom().unwrap();
    assert!((g.sweep - PI / 2.0).abs() < 1e-12 && (g.radius - 10.0).abs() < 1e-12);
    assert!((b[1].length() - 5.0 * PI).abs() < 1e-9);
    let mid = b[1].point_at(0.5).unwrap();
    assert!(close(
        mid,
        [10.0 * FRAC_1_SQRT_2, 10.0 * FRAC_1_SQRT_2, 0.0]
    ));
    let g = b[2].arc_geom().unwrap();
    assert!((g.sweep + PI / 2.0).abs() < 1e-12);
    // The cw arc back passes through the same quarter.
    assert!(close(b[2].point_at(0.5).unwrap(), mid));
    assert!(close(b[2].point_at(1.0).unwrap(), [10.0, 0.0, 0.0]));
}

#[test]
fn full_circle_by_ijk() {
    let b = blocks("G0 X10\nG2 X10 Y0 I-10 F60\n");
    let g = b[1].arc_geom().unwrap();
    assert!((g.sweep + 2.0 * PI).abs() < 1e-12);
    assert!((b[1].length() - 20.0 * PI).abs() < 1e-9);
    assert!(close(b[1].point_at(0.25).unwrap(), [0.0, -10.0, 0.0]));
}

#[test]
fn arc_by_radius_both_signs_and_directions() {
    // From (10,0) to (0,10): R>0 is the quarter, R<0 the three quarters.
    let cases = [
        ("G3", 10.0, [0.0, 0.0], PI / 2.0),
        ("G3", -10.0, [10.0, 10.0], 1.5 * PI),
        ("G2", 10.0, [10.0, 10.0], -PI / 2.0),
        ("G2", -10.0, [0.0, 0.0], -1.5 * PI),
    ];
    for (g, r, c, sweep) in cases {
        let b = blocks(&format!("G0 X10\n{g} X0 Y10 R{r} F60\n"));
        let geom = b[1].arc_geom().unwrap();
        assert!(
            (geom.centre[0] - c[0]).abs() < 1e-9 && (geom.centre[1] - c[1]).abs() < 1e-9,
            "{g} R{r}: {geom:?}"
        );
        assert!((geom.sweep - sweep).abs() < 1e-9, "{g} R{r}: {geom:?}");
        assert!(close(b[1].point_at(1.0).unwrap(), [0.0, 10.0, 0.0]));
    }
    // A half turn: |R| = half the chord.
    let b = blocks("G2 X20 R10 F60\n");
    let g = b[0].arc_geom().unwrap();
    assert!((g.centre[0] - 10.0).abs() < 1e-9 && (g.sweep + PI).abs() < 1e-9);
}

#[test]
fn every_plane() {
    // Quarter turns ccw about the origin, from the plane's first axis to its second.
    let b = blocks(
        "G0 X10\nG17 G3 X0 Y10 I-10 F60\n\
         G0 X0 Y0 Z10\nG18 G3 X10 Z0 K-10\n\
         G0 X0 Y10 Z0\nG19 G3 Y0 Z10 J-10\n",
    );
    let arcs: Vec<_> = b
        .iter()
        .filter(|b| matches!(b, Block::Arc { .. }))
        .collect();
    let expect = [
        (Plane::Xy, [7.0710678, 7.0710678, 0.0]),
        (Plane::Zx, [7.0710678, 0.0, 7.0710678]),
        (Plane::Yz, [0.0, 7.0710678, 7.0710678]),
    ];
    for (arc, (plane, mid)) in arcs.iter().zip(expect) {
        let Block::Arc { plane: p, .. } = arc else {
            panic!()
        };
        assert_eq!(*p, plane);
        let got = arc.point_at(0.5).unwrap();
        assert!(dist(got, mid) < 1e-6, "{plane:?}: {got:?}");
        assert!((arc.length() - 5.0 * PI).abs() < 1e-9);
    }
    // G18 ccw runs Z→X: a ccw arc from +X goes to −Z (so G2 goes to +Z).
    let b = blocks("G0 X10\nG18 G3 X0 Z-10 R10 F60\nG0 X10 Z0\nG2 X0 Z10 R10\n");
    assert!(b[1].arc_geom().unwrap().sweep > 0.0);
    assert!(dist(b[1].point_at(0.5).unwrap(), [7.0710678, 0.0, -7.0710678]) < 1e-6);
    assert!(dist(b[3].point_at(0.5).unwrap(), [7.0710678, 0.0, 7.0710678]) < 1e-6);
    assert_eq!(
        motioncard_sdk::Plane::from(Plane::Zx),
        motioncard_sdk::Plane::ZX
    );
}

#[test]
fn helix() {
    let b = blocks("G0 X10\nG17 G3 X10 Y0 Z-6 I-10 F60\n");
    let g = b[1].arc_geom().unwrap();
    assert!((g.sweep - 2.0 * PI).abs() < 1e-12 && g.n0 == 0.0 && g.n1 == -6.0);
    assert!(close(b[1].point_at(0.5).unwrap(), [-10.0, 0.0, -3.0]));
    let len = (20.0 * PI).hypot(6.0);
    assert!((b[1].length() - len).abs() < 1e-9);
    let Block::Arc { centre, .. } = b[1] else {
        panic!()
    };
    assert_eq!(centre, [0.0, 0.0, 0.0]);
    // In G19 the helix axis is X.
    let b = blocks("G19 G2 Y0 Z0 X5 J10 F60\n");
    assert!(close(b[0].point_at(0.5).unwrap(), [2.5, 20.0, 0.0]));
}

#[test]
fn dwell_outputs_and_order() {
    let b = blocks("G1 X1 F60\nG4 P0.5\nM62 P3 G1 X2\nM65 P200\nM63 P3\nM64 P0\n");
    assert_eq!(
        b[1],
        Block::Dwell {
            line: 2,
            seconds: 0.5
        }
    );
    let out = |line, bit, on, synced| Block::Output {
        line,
        bit,
        on,
        synced,
    };
    // The synced output comes before the motion it goes with.
    assert_eq!(b[2], out(3, 3, true, true));
    assert!(b[3].is_motion() && b[3].line() == 3);
    assert_eq!(b[4], out(4, 200, false, false));
    assert_eq!(b[5], out(5, 3, false, true));
    assert_eq!(b[6], out(6, 0, true, false));
    assert_eq!(error("M62 P256").line, 1);
    assert_eq!(error("M62 P1.5").line, 1);
    assert_eq!(error("G1 X1 F60\n\nM64").line, 3);
    assert_eq!(error("G4").line, 1);
    assert_eq!(error("G4 P-1").line, 1);
    assert_eq!(error("G4 P1 M62 P2").line, 1);
    assert_eq!(error("G0 X1 P2").line, 1);
}

#[test]
fn zero_length_moves_dropped_and_counted() {
    let p = parse("G0 X0 Y0\nG1 X5 F60\nX5\nG91 X0\nG90 G0 X5.0000001\nG0 X6\n").unwrap();
    assert_eq!(p.dropped_zero_length, 4);
    assert_eq!(p.motion_count(), 2);
    assert_eq!(p.blocks.len(), 2);
}

#[test]
fn modal_words_after_other_codes() {
    // The crate attaches X to M62 (the last command); it is still a G1 move here.
    let b = blocks("G1 X1 F60\nM62 P1\nX2\nG1 G90 X3\n");
    assert_eq!(b[2].end(), Some([2.0, 0.0, 0.0]));
    assert_eq!(b[3].end(), Some([3.0, 0.0, 0.0]));
}

#[test]
fn errors_name_the_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("G0 X1\nG28\n", 2, "unsupported code G28"),
        ("G0 X1\n\nM3\n", 3, "unsupported code M3"),
        ("G0 X1\nG17.1\n", 2, "unsupported code G17.1"),
        ("G0 X1 S1000\n", 1, "unsupported word S1000"),
        ("T1\n", 1, "unsupported code T1"),
        ("G0 A10\n", 1, "rotary axis"),
        ("G0 X1\nG1 X2\n", 2, "G1 with no F ever given"),
        ("G0 X1\nG2 X3 I1\n", 2, "G2 with no F"),
        (
            "G0 X10\nG3 X0 Y10 I-10 J0.1 F60\n",
            2,
            "differs from the radius",
        ),
        ("G0 X10 F60\nG2 X-10 R9.9\n", 2, "less than half the chord"),
        ("G0 X10 F60\nG2 X10 Y0 R9\n", 2, "cannot be a full turn"),
        ("G0 X10 F60\nG2 X0 Y10\n", 2, "needs I/J/K or R"),
        ("G0 X10 F60\nG2 X0 Y10 I-10 R10\n", 2, "not both"),
        (
            "G0 X10 F60\nG2 X0 Y10 K-10\n",
            2,
            "not an offset in the XY plane",
        ),
        ("G0 X10 F60\nG2 X10 I0 J0\n", 2, "radius is zero"),
        ("G0 X10 F60\nG2 I-10\n", 2, "at least one axis word"),
        ("G0 X10\nG1 X1 I2 F60\n", 2, "without a G2/G3"),
        ("X10\n", 1, "without a motion mode"),
        ("G0 X1\nG80\nX2\n", 3, "without a motion mode"),
        ("G0 X1 X2\n", 1, "given twice"),
        ("G0 G1 X1\n", 1, "G0 and G1 on one line"),
        ("G20 G21\n", 1, "units"),
        ("G1 X1 F0\n", 1, "must be positive"),
        ("G0 X1\nG0 X-\n", 2, "no digits"),
        ("G0 X1\nG0 X.\n", 2, "no digits"),
        ("G0 X1\n\nG0 X1 )\n", 3, "without an opening"),
        ("G0 X1\n(open\n", 2, "not closed"),
        ("G0 X1\nG0 X2 é\n", 2, "non-ASCII"),
        ("G0 X1\nG0 X$2\n", 2, "unrecognised"),
        ("G0 X1\nG0 XY2\n", 2, "without a number"),
        ("G0 X1\nG0 X2 N5\n", 2, "line number"),
        ("G0 X1\n%G0\n", 2, "'%'"),
        ("G0 X1\nG-1 X2\n", 2, "unsupported code G-1"),
    ];
    for &(text, line, what) in cases {
        let e = error(text);
        assert_eq!(e.line, line, "{text:?}: {e}");
        assert!(e.message.contains(what), "{text:?}: {e}");
        assert!(e.to_string().starts_with(&format!("line {line}: ")));
    }
}

#[test]
fn comments_may_hold_anything() {
    let b = blocks("(é ) ; ü)(\nG0 X1 (a ; b) ; (c\n");
    assert_eq!(b.len(), 1);
}

#[test]
fn no_input_panics() {
    // A small fixed-seed generator over the characters that matter to the tokenizer.
    let alphabet: Vec<char> = "GMXYZIJKRFPNST0123456789.-+ ()%;\n\téA$".chars().collect();
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let mut ok = 0;
    for _ in 0..20_000 {
        let len = (next() % 24) as usize;
        let text: String = (0..len)
            .map(|_| alphabet[(next() % alphabet.len() as u64) as usize])
            .collect();
        ok += usize::from(parse(&text).is_ok());
    }
    assert!(ok > 100, "only {ok} parsed");
}

#[test]
fn parse_from_a_start() {
    let b = parse_from("G1 X1 F60", [0.0, 2.0, 3.0]).unwrap().blocks;
    assert_eq!(b[0].start(), Some([0.0, 2.0, 3.0]));
    assert_eq!(b[0].end(), Some([1.0, 2.0, 3.0]));
}

/// A program read a line at a time from a reader is the program parsed whole; a word's
/// letter and number never join across lines (the crate joined `G` and `0` of "G\n0");
/// an unreadable line is named.
#[test]
fn blocks_from_a_reader_a_line_at_a_time() {
    let text = include_str!("../../examples/gcode/part.ngc");
    let whole = parse_from(text, [1.0, 2.0, 3.0]).unwrap();
    let mut read = Blocks::new(text.as_bytes(), [1.0, 2.0, 3.0]);
    let streamed: Vec<Block> = (&mut read).map(Result::unwrap).collect();
    assert_eq!(streamed, whole.blocks);
    assert_eq!(
        read.parser().dropped_zero_length(),
        whole.dropped_zero_length
    );
    assert_eq!(read.parser().lines(), text.lines().count());
    for split in ["G\n0 X1", "G0 X\n1", "F\n2"] {
        let e = error(split);
        assert_eq!(e.line, 1, "{split:?}: {e}");
        assert!(e.message.contains("without a number"), "{split:?}: {e}");
    }
    let bytes: &[u8] = b"G0 X1\nG0 X2 (\xff)\n";
    let got: Vec<_> = Blocks::new(bytes, [0.0; 3]).collect();
    assert_eq!(got.len(), 2);
    assert_eq!(
        got[1].as_ref().unwrap_err().to_string(),
        "line 2: not UTF-8 text"
    );
    let long = format!("G0 X1\n({})\nG0 X2\n", "c".repeat(MAX_LINE_BYTES));
    let got: Vec<_> = Blocks::new(long.as_bytes(), [0.0; 3]).collect();
    assert_eq!(got.len(), 2, "nothing after the error");
    assert_eq!(
        got[1].as_ref().unwrap_err().to_string(),
        format!("line 2: longer than {MAX_LINE_BYTES} bytes")
    );
    // The longest line allowed, a comment.
    let ok = format!("({})\nG0 X2\n", "c".repeat(MAX_LINE_BYTES - 2));
    assert_eq!(Blocks::new(ok.as_bytes(), [0.0; 3]).count(), 1);
}

#[test]
fn example_programs_parse() {
    let square = parse(include_str!("../../examples/gcode/square.ngc")).unwrap();
    assert_eq!(square.motion_count(), 5);
    let cuts: Vec<_> = square
        .blocks
        .iter()
        .filter(|b| !matches!(b, Block::Line { rapid: true, .. }))
        .collect();
    assert_eq!(cuts.len(), 4);
    assert!(cuts
        .iter()
        .all(|b| b.feed() == Some(50.0) && (b.length() - 50.0).abs() < 1e-12));
    assert_eq!(square.blocks[0].end(), square.blocks.last().unwrap().end());

    let zigzag = parse(include_str!("../../examples/gcode/zigzag.ngc")).unwrap();
    assert!(zigzag.motion_count() >= 20);
    assert_eq!(zigzag.dropped_zero_length, 0);

    let part = parse(include_str!("../../examples/gcode/part.ngc")).unwrap();
    let has = |f: &dyn Fn(&Block) -> bool| part.blocks.iter().any(f);
    assert!(has(
        &|b| matches!(b, Block::Arc { start, end, .. } if start[2] != end[2])
    ));
    assert!(has(&|b| matches!(b, Block::Arc { ccw: true, .. })));
    assert!(has(&|b| matches!(b, Block::Arc { ccw: false, .. })));
    assert!(has(&|b| matches!(b, Block::Dwell { .. })));
    assert!(has(&|b| matches!(
        b,
        Block::Output {
            synced: true,
            on: true,
            ..
        }
    )));
    assert!(has(&|b| matches!(
        b,
        Block::Output {
            synced: true,
            on: false,
            ..
        }
    )));
    assert!(has(&|b| matches!(b, Block::Line { rapid: false, .. })));
    assert_eq!(part.dropped_zero_length, 0);
}
