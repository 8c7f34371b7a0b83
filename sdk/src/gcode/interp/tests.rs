//! Motion, coordinates and units, with numbers worked out from the RS274/NGC documents.

use super::*;
use crate::gcode::{Tool, ToolTable};
use std::f64::consts::PI;

/// A block from text such as `G1 X10 F100`: letters and numbers only (no comments, no
/// expressions), G codes in tenths; `(MSG,…)` at the end becomes the message.
pub(super) fn blk(line: usize, text: &str) -> Block {
    let mut b = Block {
        line,
        ..Block::default()
    };
    let (code, msg) = match text.find("(MSG,") {
        Some(i) => (
            &text[..i],
            Some(text[i + 5..].trim_end_matches(')').to_string()),
        ),
        None => (text, None),
    };
    b.message = msg;
    let chars: Vec<char> = code.chars().filter(|c| !c.is_whitespace()).collect();
    let mut i = 0;
    while i < chars.len() {
        let letter = chars[i].to_ascii_uppercase();
        i += 1;
        let start = i;
        while i < chars.len() && (chars[i].is_ascii_digit() || matches!(chars[i], '.' | '-' | '+'))
        {
            i += 1;
        }
        let s: String = chars[start..i].iter().collect();
        let v: f64 = s
            .parse()
            .unwrap_or_else(|_| panic!("bad number {s:?} in {text:?}"));
        match letter {
            'G' => b.g.push((v * 10.0).round() as u16),
            'M' => b.m.push(v as u32),
            'N' => {}
            '@' => b.polar[0] = Some(v),
            '^' => b.polar[1] = Some(v),
            c => {
                let k = (c as u8 - b'A') as usize;
                assert!(b.words[k].is_none(), "{c} twice in {text:?}");
                b.words[k] = Some(v);
            }
        }
    }
    b
}

/// Everything a run leaves: its operations, the interpreter, the parameters.
#[derive(Debug)]
pub(super) struct Run {
    pub ops: Vec<Op>,
    pub it: Interp,
    pub params: Params,
}

impl Run {
    /// The operations of source line `line`.
    pub fn line(&self, line: usize) -> Vec<&OpKind> {
        self.ops
            .iter()
            .filter(|o| o.line == line)
            .map(|o| &o.kind)
            .collect()
    }

    /// The only motion of line `line`.
    pub fn motion(&self, line: usize) -> &OpKind {
        let m: Vec<_> = self
            .line(line)
            .into_iter()
            .filter(|k| k.ends().is_some())
            .collect();
        assert_eq!(m.len(), 1, "line {line}: {m:?}");
        m[0]
    }
}

/// Runs the lines (numbered from 1) with `opts`, then `finish`.
pub(super) fn run_with(opts: &Options, lines: &[&str]) -> Result<Run, GcodeError> {
    let mut params = Params::new();
    let mut it = Interp::new(opts, &mut params);
    let mut ops = Vec::new();
    let mut ended = false;
    for (i, text) in lines.iter().enumerate() {
        if it.block(&blk(i + 1, text), &mut params, &mut ops)? == Flow::End {
            ended = true;
            break;
        }
    }
    if !ended {
        it.finish(lines.len(), &mut params, &mut ops)?;
    }
    Ok(Run { ops, it, params })
}

pub(super) fn run(lines: &[&str]) -> Result<Run, GcodeError> {
    run_with(&Options::default(), lines)
}

pub(super) fn run_err(lines: &[&str]) -> GcodeError {
    match run(lines) {
        Ok(r) => panic!("no error; ops {:?}", r.ops),
        Err(e) => e,
    }
}

pub(super) fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

#[track_caller]
pub(super) fn assert_pos(got: impl AsRef<[f64]> + std::fmt::Debug, want: [f64; 3]) {
    for i in 0..3 {
        let got = got.as_ref();
        assert!(close(got[i], want[i]), "got {got:?}, want {want:?}");
    }
}

#[track_caller]
pub(super) fn assert_rapid(k: &OpKind, to: [f64; 3]) {
    match k {
        OpKind::Rapid { end, .. } => assert_pos(*end, to),
        other => panic!("want a rapid to {to:?}, got {other:?}"),
    }
}

#[track_caller]
pub(super) fn assert_feed(k: &OpKind, to: [f64; 3], mm_s: f64) {
    match k {
        OpKind::Feed { end, feed, .. } => {
            assert_pos(*end, to);
            assert!(close(*feed, mm_s), "feed {feed}, want {mm_s}");
        }
        other => panic!("want a feed to {to:?}, got {other:?}"),
    }
}

pub(super) fn tools(list: &[(u32, f64, f64)]) -> ToolTable {
    ToolTable {
        tools: list
            .iter()
            .map(|&(number, z, diameter)| Tool {
                number,
                pocket: number,
                offset: [0.0, 0.0, z, 0.0, 0.0, 0.0],
                diameter,
                comment: String::new(),
            })
            .collect(),
    }
}

#[test]
fn starts_as_linuxcnc_does() {
    let mut params = Params::new();
    let opts = Options {
        start: [1.0, 2.0, 3.0, 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let it = Interp::new(&opts, &mut params);
    assert_eq!(it.units(), Units::Mm);
    assert_eq!(it.plane(), Plane::Xy);
    assert!(it.absolute() && !it.arc_absolute());
    assert_eq!(it.feed_mode(), FeedMode::PerMinute);
    assert_eq!(it.coordinate_system(), 1);
    assert_eq!(it.motion_mode(), None);
    assert_eq!(it.comp_mode(), CompMode::Off);
    assert_eq!(it.spindle(), (0.0, SpindleDir::Off));
    assert!(matches!(
        it.blend(),
        Blend::Blended {
            tolerance: None,
            ..
        }
    ));
    assert_eq!(it.position(), opts.start);
    assert_eq!(params.get(5220), Some(1.0));
    assert_eq!(params.get(5422), Some(3.0));
}

#[test]
fn a_feed_move_without_f_is_an_error_naming_its_line() {
    let e = run_err(&["G0 X1", "G1 X2"]);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("feed"), "{e}");
}

#[test]
fn lines_and_feeds_in_mm() {
    let r = run(&["G1 X10 Y0 F600", "G91 X5 Y5", "G0 Z-1"]).unwrap();
    assert_feed(r.motion(1), [10.0, 0.0, 0.0], 10.0);
    assert_feed(r.motion(2), [15.0, 5.0, 0.0], 10.0);
    assert_rapid(r.motion(3), [15.0, 5.0, -1.0]);
    assert!(close(r.params.get(5420).unwrap(), 15.0));
    assert!(close(r.params.get(5422).unwrap(), -1.0));
    assert!(close(r.motion(2).length().unwrap(), 50f64.sqrt()));
}

#[test]
fn g20_converts_lengths_and_feeds_to_mm() {
    let r = run(&["G20", "G1 X1 Y2 F10", "A90 F360"]).unwrap();
    // 10 in/min = 254 mm/min.
    assert_feed(r.motion(2), [25.4, 50.8, 0.0], 254.0 / 60.0);
    // A alone: degrees, never converted; F in deg/min.
    match r.motion(3) {
        OpKind::Feed { end, feed, .. } => {
            assert!(close(end[3], 90.0));
            assert!(close(*feed, 6.0));
        }
        k => panic!("{k:?}"),
    }
    // #5420 reads program units.
    assert!(close(r.params.get(5420).unwrap(), 1.0));
}

#[test]
fn f_comes_before_g20_on_its_line_and_keeps_its_speed_afterwards() {
    // LinuxCNC's order: F (step 3) before G20 (step 15): F10 is mm/min here.
    let r = run(&["G20 G1 X1 F10", "G21", "G1 X30"]).unwrap();
    assert_feed(r.motion(1), [25.4, 0.0, 0.0], 10.0 / 60.0);
    assert_feed(r.motion(3), [30.0, 0.0, 0.0], 10.0 / 60.0);
}

#[test]
fn g93_inverse_time_needs_f_on_each_move() {
    let r = run(&["G93 G1 X30 Y40 F2"]).unwrap();
    // 50 mm in 1/2 minute: 100 mm/min.
    assert_feed(r.motion(1), [30.0, 40.0, 0.0], 50.0 * 2.0 / 60.0);
    let e = run_err(&["G93 G1 X30 F2", "X40"]);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("G93"), "{e}");
    // An arc: the quarter circle of radius 10 in 1/3 min.
    let r = run(&["G0 X10", "G93 G3 X0 Y10 I-10 F3"]).unwrap();
    match r.motion(2) {
        OpKind::Arc { feed, .. } => assert!(close(*feed, 5.0 * PI * 3.0 / 60.0)),
        k => panic!("{k:?}"),
    }
}

#[test]
fn g95_feed_per_revolution_uses_the_spindle_speed() {
    let r = run(&["S1200 M3", "G95 G1 X10 F0.1"]).unwrap();
    assert_feed(r.motion(2), [10.0, 0.0, 0.0], 0.1 * 1200.0 / 60.0);
    let e = run_err(&["G95 G1 X10 F0.1"]);
    assert!(e.message.contains("S0"), "{e}");
}

#[test]
fn g2_with_p2_is_two_turns_of_4_pi_r() {
    let r = run(&["G0 X10 Y0", "G2 X10 Y0 I-10 J0 P2 F100"]).unwrap();
    match r.motion(2) {
        k @ OpKind::Arc {
            centre,
            turns,
            ccw,
            end,
            ..
        } => {
            assert_eq!(*turns, 1);
            assert!(!ccw);
            assert_pos(*end, [10.0, 0.0, 0.0]);
            assert_pos([centre[0], centre[1], centre[2]], [0.0, 0.0, 0.0]);
            assert!(close(k.length().unwrap(), 4.0 * PI * 10.0));
        }
        k => panic!("{k:?}"),
    }
}

#[test]
fn a_helix_counts_its_rise() {
    let r = run(&["G0 X10 Y0", "G3 X10 Y0 Z5 I-10 F100"]).unwrap();
    let want = (2.0 * PI * 10.0).hypot(5.0);
    assert!(close(r.motion(2).length().unwrap(), want));
}

#[test]
fn g90_1_takes_the_centre_as_absolute() {
    let r = run(&["G0 X10 Y0", "G90.1 G3 X0 Y10 I0 J0 F100"]).unwrap();
    match r.motion(2) {
        k @ OpKind::Arc { centre, ccw, .. } => {
            assert!(*ccw);
            assert_pos(*centre, [0.0, 0.0, 0.0]);
            assert!(close(k.length().unwrap(), 5.0 * PI));
        }
        k => panic!("{k:?}"),
    }
    assert!(r.it.arc_absolute());
    // The same in G91.1: I-10 from the start.
    let r = run(&["G0 X10 Y0", "G3 X0 Y10 I-10 J0 F100"]).unwrap();
    match r.motion(2) {
        OpKind::Arc { centre, .. } => assert_pos(*centre, [0.0, 0.0, 0.0]),
        k => panic!("{k:?}"),
    }
}

#[test]
fn r_arcs_short_and_long() {
    let h = 75f64.sqrt();
    // G2 R10 from (0,0) to (10,0): the short arc (60 degrees) about a centre below.
    let r = run(&["G2 X10 Y0 R10 F100"]).unwrap();
    match r.motion(1) {
        k @ OpKind::Arc { centre, .. } => {
            assert_pos(*centre, [5.0, -h, 0.0]);
            assert!(close(k.length().unwrap(), 10.0 * PI / 3.0));
        }
        k => panic!("{k:?}"),
    }
    // the long one (300 degrees), centre above.
    let r = run(&["G2 X10 Y0 R-10 F100"]).unwrap();
    match r.motion(1) {
        k @ OpKind::Arc { centre, .. } => {
            assert_pos(*centre, [5.0, h, 0.0]);
            assert!(close(k.length().unwrap(), 10.0 * 5.0 * PI / 3.0));
        }
        k => panic!("{k:?}"),
    }
    // G3 R10: short, centre above.
    let r = run(&["G3 X10 Y0 R10 F100"]).unwrap();
    match r.motion(1) {
        OpKind::Arc { centre, .. } => assert_pos(*centre, [5.0, h, 0.0]),
        k => panic!("{k:?}"),
    }
    // Too small to reach.
    let e = run_err(&["G2 X10 Y0 R4.9 F100"]);
    assert!(e.message.contains("too small"), "{e}");
}

#[test]
fn an_arc_whose_radii_differ_beyond_linuxcncs_tolerance_is_refused() {
    // Within: 0.02 mm apart (abs tolerance 0.0283 mm); the centre lands on the bisector.
    let r = run(&["G0 X10", "G3 X-10.02 Y0 I-10 F100"]).unwrap();
    match r.motion(2) {
        OpKind::Arc { centre, .. } => assert_pos(*centre, [-0.01, 0.0, 0.0]),
        k => panic!("{k:?}"),
    }
    let e = run_err(&["G0 X10", "G3 X-10.05 Y0 I-10 F100"]);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("differs"), "{e}");
    // In inches the tolerance is 0.00283 in.
    assert!(run(&["G20 G0 X1", "G3 X-1.002 I-1 F10"]).is_ok());
    assert!(run(&["G20 G0 X1", "G3 X-1.004 I-1 F10"]).is_err());
}

#[test]
fn arcs_in_g18_and_g19_use_their_offsets() {
    // G18: Z then X; I and K are the offsets; J is not.
    let r = run(&["G0 X10", "G18 G2 X0 Z10 I-10 K0 F100"]).unwrap();
    match r.motion(2) {
        OpKind::Arc { centre, plane, .. } => {
            assert_eq!(*plane, Plane::Zx);
            assert_pos(*centre, [0.0, 0.0, 0.0]);
        }
        k => panic!("{k:?}"),
    }
    let e = run_err(&["G0 X10", "G18 G2 X0 Z10 I-10 J0 F100"]);
    assert!(e.message.contains("J0"), "{e}");
}

#[test]
fn g10_l2_sets_a_work_offset_then_used() {
    let r = run(&[
        "G10 L2 P1 X10 Y20 Z-5",
        "G0 X1 Y1 Z1",
        "G10 L2 P2 X100",
        "G55 G0 X0",
    ])
    .unwrap();
    assert_rapid(r.motion(2), [11.0, 21.0, -4.0]);
    assert_eq!(r.params.get(5221), Some(10.0));
    assert_eq!(r.params.get(5223), Some(-5.0));
    assert_eq!(r.params.get(5241), Some(100.0));
    // G55 has X100 and nothing else: Y, Z are machine 21, -4 there.
    assert_rapid(r.motion(4), [100.0, 21.0, -4.0]);
    assert_eq!(r.params.get(5220), Some(2.0));
    assert!(close(r.params.get(5421).unwrap(), 21.0));
}

#[test]
fn g10_l2_in_inches_stores_mm() {
    let r = run(&["G20 G10 L2 P0 X1", "G0 X0"]).unwrap();
    assert_eq!(r.params.get(5221), Some(25.4));
    assert_rapid(r.motion(2), [25.4, 0.0, 0.0]);
}

#[test]
fn g10_l2_r_rotates_the_system_about_z() {
    let r = run(&["G10 L2 P1 X10 R90", "G0 X1 Y0", "G1 X1 Y1 F60"]).unwrap();
    assert_rapid(r.motion(2), [10.0, 1.0, 0.0]);
    assert_feed(r.motion(3), [9.0, 1.0, 0.0], 1.0);
    assert!(close(r.params.get(5420).unwrap(), 1.0));
    assert!(close(r.params.get(5421).unwrap(), 1.0));
}

/// A G19 arc in a system rotated 90° about Z (R90: work Y is machine −X): the arc in work
/// YZ from Y0 Z0 about Y5 Z0 through a half turn to Y10 Z0, G3 (counter-clockwise seen from
/// +X, Y toward Z: from the circle's −Y side it goes down, through Z−5). In machine
/// coordinates that is the vertical XZ plane at Y0: an arc about machine (5, 0, 0) (the
/// centre, work (0, 5, 0)) whose normal is work X turned, machine +Y; every point of it is
/// 5 mm from the centre, and its length is 5π. A 270° G18 arc rotated 30° ends where the
/// program says, and a helix there runs too.
#[test]
fn an_arc_outside_xy_in_a_rotated_system_runs_about_its_turned_normal() {
    let r = run(&[
        "G10 L2 P1 X10 R90",
        "G0 X0 Y0 Z0",
        "G19 G3 Y10 Z0 J5 K0 F60",
    ])
    .unwrap();
    let k = r.motion(3);
    match k {
        OpKind::ArcNormal {
            start,
            end,
            centre,
            normal,
            ccw,
            ..
        } => {
            // work (x, y, z) -> machine (10 - y, x, z)
            assert_pos(*start, [10.0, 0.0, 0.0]);
            assert_pos(*end, [0.0, 0.0, 0.0]);
            assert_pos(*centre, [5.0, 0.0, 0.0]);
            assert_pos(*normal, [0.0, 1.0, 0.0]);
            assert!(*ccw);
            let f = k.normal_arc_frame().unwrap();
            for i in 0..=50 {
                let p = f.point(i as f64 / 50.0);
                let r = (p[0] - 5.0).hypot(p[2]);
                assert!(close(r, 5.0) && p[1].abs() < 1e-12, "{p:?}");
                // through work Z−5 at the middle
                if i == 25 {
                    assert_pos(p, [5.0, 0.0, -5.0]);
                }
            }
        }
        k => panic!("{k:?}"),
    }
    let len = k.length().unwrap();
    assert!((len - 5.0 * PI).abs() <= 1e-9 * len, "{len}");
    // G18 (Z, X), rotated 30°: a 270° G2, ending on the program's end
    let r = run(&["G10 L2 P1 R30", "G0 X0 Y0 Z0", "G18 G2 X5 Z5 I5 K0 F60"]).unwrap();
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let k = r.motion(3);
    match k {
        OpKind::ArcNormal { end, .. } => {
            assert_pos(*end, [5.0 * c, 5.0 * s, 5.0]);
            let mid = k.normal_arc_frame().unwrap().point(0.5);
            // on the circle about work (5, 0, 0) in the rotated XZ plane
            let w = [mid[0] * c + mid[1] * s, -mid[0] * s + mid[1] * c, mid[2]];
            assert!(
                close((w[0] - 5.0).hypot(w[2]), 5.0) && w[1].abs() < 1e-9,
                "{w:?}"
            );
        }
        k => panic!("{k:?}"),
    }
    assert!(close(k.length().unwrap(), 7.5 * PI));
    let r = run(&["G10 L2 P1 R30", "G0 X0 Y0 Z0", "G18 G2 X5 Z5 Y3 I5 K0 F60"]).unwrap();
    assert!(close(r.motion(3).length().unwrap(), (7.5 * PI).hypot(3.0)));
}

#[test]
fn g10_l20_makes_the_current_position_read_the_value() {
    let opts = Options {
        start: [30.0, 40.0, 50.0, 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let r = run_with(&opts, &["G10 L20 P1 X0 Y5", "G0 X0 Y0"]).unwrap();
    assert_eq!(r.params.get(5221), Some(30.0));
    assert_eq!(r.params.get(5222), Some(35.0));
    assert_eq!(r.params.get(5223), Some(0.0));
    assert_rapid(r.motion(2), [30.0, 35.0, 50.0]);
}

#[test]
fn g92_then_g92_1() {
    let opts = Options {
        start: [5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let r = run_with(&opts, &["G92 X0", "G0 X1", "G92.1", "G0 X1"]).unwrap();
    assert_rapid(r.motion(2), [6.0, 0.0, 0.0]);
    assert_rapid(r.motion(4), [1.0, 0.0, 0.0]);
    assert_eq!(r.params.get(5210), Some(0.0));
    assert_eq!(r.params.get(5211), Some(0.0));
    let r = run_with(&opts, &["G92 X0", "G0 X1"]).unwrap();
    assert_eq!(r.params.get(5210), Some(1.0));
    assert_eq!(r.params.get(5211), Some(5.0));
    // G92.2 suspends, G92.3 restores from the parameters.
    let r = run_with(&opts, &["G92 X0", "G92.2", "G0 X1", "G92.3", "G0 X1"]).unwrap();
    assert_rapid(r.motion(3), [1.0, 0.0, 0.0]);
    assert_rapid(r.motion(5), [6.0, 0.0, 0.0]);
}

#[test]
fn g53_moves_in_machine_coordinates_on_its_line_only() {
    let r = run(&["G10 L2 P1 X10", "G53 G0 X-5", "G0 X0", "G53 X3"]).unwrap();
    assert_rapid(r.motion(2), [-5.0, 0.0, 0.0]);
    assert_rapid(r.motion(3), [10.0, 0.0, 0.0]);
    // G0 is in effect: G53 X3 rapids to machine 3.
    assert_rapid(r.motion(4), [3.0, 0.0, 0.0]);
    let e = run_err(&["G91 G53 G0 X1"]);
    assert!(e.message.contains("incremental"), "{e}");
}

#[test]
fn g28_goes_through_the_intermediate_point_then_home_for_the_named_axes() {
    let opts = Options {
        start: [7.0, 8.0, 9.0, 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let r = run_with(
        &opts,
        &["G28.1", "G10 L2 P1 X100", "G0 X0 Y0 Z0", "G28 Z20", "G28"],
    )
    .unwrap();
    assert_eq!(r.params.get(5161), Some(7.0));
    assert_eq!(r.params.get(5163), Some(9.0));
    let l4 = r.line(4);
    assert_eq!(l4.len(), 2);
    // Through Z20 of G54 (machine Z 20), then Z home only.
    assert_rapid(l4[0], [100.0, 0.0, 20.0]);
    assert_rapid(l4[1], [100.0, 0.0, 9.0]);
    // No axis words: straight home, every axis.
    let l5 = r.line(5);
    assert_eq!(l5.len(), 1);
    assert_rapid(l5[0], [7.0, 8.0, 9.0]);
}

#[test]
fn g30_uses_its_own_position() {
    let r = run(&["G0 X1 Y2 Z3", "G30.1", "G0 X0 Y0 Z0", "G91 G30 X0"]).unwrap();
    assert_eq!(r.params.get(5181), Some(1.0));
    let l = r.line(4);
    assert_rapid(l[0], [0.0, 0.0, 0.0]);
    assert_rapid(l[1], [1.0, 0.0, 0.0]);
}

#[test]
fn tool_length_via_g43_h() {
    let opts = Options {
        tools: tools(&[(1, 12.5, 6.0), (2, 30.0, 10.0)]),
        ..Options::default()
    };
    let r = run_with(
        &opts,
        &[
            "T1 M6",
            "G43 G0 Z0",
            "G43 H2 Z0",
            "G49 G0 Z0",
            "G43.1 Z4",
            "G0 Z1",
            "T2 M6",
        ],
    )
    .unwrap();
    assert_eq!(r.line(1), vec![&OpKind::ToolChange { tool: 1 }]);
    assert_rapid(r.motion(2), [0.0, 0.0, 12.5]);
    assert_rapid(r.motion(3), [0.0, 0.0, 30.0]);
    assert_rapid(r.motion(4), [0.0, 0.0, 0.0]);
    assert!(r.line(5).is_empty(), "G43.1 with axis words does not move");
    assert_rapid(r.motion(6), [0.0, 0.0, 5.0]);
    assert_eq!(r.params.get(5400), Some(2.0));
    assert_eq!(r.params.get(5403), Some(30.0));
    assert_eq!(r.params.get(5410), Some(10.0));
    // The work position reads Z1 with the offset applied.
    assert!(close(r.params.get(5422).unwrap(), 1.0));
    let e = run_with(&opts, &["G43 H7"]).unwrap_err();
    assert!(e.message.contains("H7"), "{e}");
}

#[test]
fn g10_l1_and_l10_edit_the_tool_table() {
    let opts = Options {
        tools: tools(&[(1, 0.0, 6.0)]),
        start: [0.0, 0.0, 40.0, 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let r = run_with(&opts, &["T1 M6", "G10 L1 P1 Z5 R4", "G43", "G0 Z0"]).unwrap();
    assert_rapid(r.motion(4), [0.0, 0.0, 5.0]);
    assert_eq!(r.params.get(5410), Some(8.0));
    // L10: the current position (machine Z 40) reads Z10 with this tool.
    let r = run_with(&opts, &["T1 M6", "G10 L10 P1 Z10", "G43", "G0 Z0"]).unwrap();
    assert_rapid(r.motion(4), [0.0, 0.0, 30.0]);
    assert_eq!(r.it.tool_table().tools[0].offset[2], 30.0);
}

#[test]
fn path_control_modes_reach_every_motion() {
    let r = run(&[
        "G64 P0.05 Q0.01 G1 X1 F60",
        "G61 X2",
        "G61.1 X3",
        "G20 G64 P0.001 X1",
    ])
    .unwrap();
    let blend = |l| match r.motion(l) {
        OpKind::Feed { blend, .. } => *blend,
        k => panic!("{k:?}"),
    };
    assert_eq!(
        blend(1),
        Blend::Blended {
            tolerance: Some(0.05),
            naive: Some(0.01)
        }
    );
    assert_eq!(blend(2), Blend::ExactStop);
    assert_eq!(blend(3), Blend::ExactPath);
    match blend(4) {
        Blend::Blended {
            tolerance: Some(t),
            naive: None,
        } => assert!(close(t, 0.0254)),
        b => panic!("{b:?}"),
    }
}

#[test]
fn splines_as_bezier_pieces_and_nurbs() {
    // G5.1 from (0,0) through control (5,10) to (10,0): a parabola; length known.
    let r = run(&["G5.1 X10 Y0 I5 J10 F60"]).unwrap();
    let k = r.motion(1);
    match k {
        OpKind::Spline { spline, .. } => {
            assert_eq!(spline.degree, 2);
            assert_eq!(spline.knots, vec![0., 0., 0., 1., 1., 1.]);
            let mid = super::geom::spline_point(spline, 0.5);
            assert_pos([mid[0], mid[1], mid[2]], [5.0, 5.0, 0.0]);
        }
        k => panic!("{k:?}"),
    }
    // B(t) = (10t, 20t(1-t)): speed sqrt(100 + (20 - 40t)^2); closed form.
    // ∫0^1 sqrt(100 + (20-40t)^2) dt = 10/4 * ∫_{-2}^{2} sqrt(1+u^2) du (u = (20-40t)/10).
    let want = 2.5 * 2.0 * {
        let u: f64 = 2.0;
        0.5 * (u * (1.0 + u * u).sqrt() + u.asinh())
    };
    assert!(
        (k.length().unwrap() - want).abs() <= 1e-9 * want,
        "{:?} vs {want}",
        k.length()
    );

    // A quarter circle as a NURBS (weights 1, √2/2, 1): length π r / 2.
    let w = std::f64::consts::FRAC_1_SQRT_2.to_string();
    let p1 = format!("G5.2 X10 Y10 P{w} L3");
    let r = run(&["G0 X10 Y0", "F60", &p1, "X0 Y10 P1", "G5.3"]).unwrap();
    let k = r.motion(5);
    match k {
        OpKind::Spline { spline, end, .. } => {
            assert_eq!(spline.points.len(), 3);
            assert_eq!(spline.knots, vec![0., 0., 0., 1., 1., 1.]);
            assert_pos(*end, [0.0, 10.0, 0.0]);
            let m = super::geom::spline_point(spline, 0.3);
            assert!(close(m[0].hypot(m[1]), 10.0));
        }
        k => panic!("{k:?}"),
    }
    let len = k.length().unwrap();
    assert!((len - 5.0 * PI).abs() <= 1e-9 * len, "{len}");

    // G5: I J from the start, P Q from the end; the next G5 mirrors P Q.
    let r = run(&["G5 X10 Y0 I0 J5 P0 Q5 F60", "G5 X20 Y0 P0 Q-5"]).unwrap();
    match r.motion(2) {
        OpKind::Spline { spline, .. } => {
            assert_pos(spline.points[1], [10.0, -5.0, 0.0]);
            assert_pos(spline.points[2], [20.0, -5.0, 0.0]);
        }
        k => panic!("{k:?}"),
    }
}

#[test]
fn nurbs_knots_are_linuxcncs() {
    assert_eq!(
        super::spline::knot_vector(4, 3),
        vec![0., 0., 0., 1., 2., 3., 3., 3.]
    );
}
