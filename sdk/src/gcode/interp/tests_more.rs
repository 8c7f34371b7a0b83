//! Canned cycles, probing, M codes, and the checks that refuse a line.

use super::tests::*;
use super::*;

#[test]
fn g81_g98_in_inches_under_g43() {
    let opts = Options {
        tools: tools(&[(1, 10.0, 6.0)]),
        ..Options::default()
    };
    let r = run_with(
        &opts,
        &[
            "G20 T1 M6",
            "G43 H1",
            "G0 X0 Y0 Z1",
            "G98 G81 X1 Y2 Z-0.5 R0.1 F10",
        ],
    )
    .unwrap();
    let ops = r.line(4);
    assert_eq!(ops.len(), 4, "{ops:?}");
    // Machine Z = program Z + 10 mm.
    assert_rapid(ops[0], [25.4, 50.8, 35.4]);
    assert_rapid(ops[1], [25.4, 50.8, 2.54 + 10.0]);
    assert_feed(ops[2], [25.4, 50.8, -12.7 + 10.0], 254.0 / 60.0);
    assert_rapid(ops[3], [25.4, 50.8, 35.4]);
    for k in &ops {
        match k {
            OpKind::Rapid { blend, .. } | OpKind::Feed { blend, .. } => {
                assert_eq!(*blend, Blend::ExactPath)
            }
            _ => unreachable!(),
        }
    }
    // The cycle stays in effect: the next hole with X alone, same R and Z.
    let r2 = run_with(
        &opts,
        &[
            "G20 T1 M6",
            "G43 H1",
            "G0 X0 Y0 Z1",
            "G98 G81 X1 Y2 Z-0.5 R0.1 F10",
            "X2",
        ],
    )
    .unwrap();
    let ops = r2.line(5);
    assert_eq!(ops.len(), 4, "{ops:?}");
    assert_rapid(ops[0], [50.8, 50.8, 35.4]);
    assert_rapid(ops[1], [50.8, 50.8, 12.54]);
}

#[test]
fn g83_pecks_back_to_r_and_down_to_the_clearance() {
    let r = run(&["G0 X0 Y0 Z10", "G99 G83 Z-10 R2 Q4 F60 X0"]).unwrap();
    let ops = r.line(2);
    let want: &[(&str, f64)] = &[
        ("r", 10.0), // at the hole, at the current level (LinuxCNC emits it)
        ("r", 2.0),
        ("f", -2.0),
        ("r", 2.0),
        ("r", -1.0), // 1 mm above the last depth
        ("f", -6.0),
        ("r", 2.0),
        ("r", -5.0),
        ("f", -10.0),
        ("r", 2.0), // G99: back to R
    ];
    assert_eq!(ops.len(), want.len(), "{ops:?}");
    for (k, (kind, z)) in ops.iter().zip(want) {
        if *kind == "r" {
            assert_rapid(k, [0.0, 0.0, *z]);
        } else {
            assert_feed(k, [0.0, 0.0, *z], 1.0);
        }
    }
}

#[test]
fn g73_breaks_chips_with_a_small_retract() {
    let r = run(&["G0 Z5", "G98 G73 X0 Y0 Z-5 R1 Q3 D0.5 F60"]).unwrap();
    let z: Vec<f64> = r.line(2).iter().map(|k| k.ends().unwrap().1[2]).collect();
    assert_eq!(z, vec![5.0, 1.0, -2.0, -1.5, -5.0, 5.0]);
}

#[test]
fn incremental_cycles_repeat_with_l() {
    // G91: R is from the initial level, Z from R; each repeat steps X.
    let r = run(&["G0 X0 Y0 Z10", "G91 G99 G81 X10 R-8 Z-5 L3 F60"]).unwrap();
    let ops = r.line(2);
    // First hole: at the level (10), down to R (2), feed to -3, back to R; then the others
    // from R.
    assert_rapid(ops[0], [10.0, 0.0, 10.0]);
    assert_rapid(ops[1], [10.0, 0.0, 2.0]);
    assert_feed(ops[2], [10.0, 0.0, -3.0], 1.0);
    assert_rapid(ops[3], [10.0, 0.0, 2.0]);
    assert_rapid(ops[4], [20.0, 0.0, 2.0]);
    assert_feed(ops[5], [20.0, 0.0, -3.0], 1.0);
    assert_rapid(ops[7], [30.0, 0.0, 2.0]);
    assert_eq!(ops.len(), 10);
}

#[test]
fn below_r_the_cycle_first_rises_to_r() {
    let r = run(&["G0 Z-1", "G98 G81 X5 Y0 Z-4 R2 F60"]).unwrap();
    let ops = r.line(2);
    assert_rapid(ops[0], [0.0, 0.0, 2.0]);
    assert_rapid(ops[1], [5.0, 0.0, 2.0]);
    assert_feed(ops[2], [5.0, 0.0, -4.0], 1.0);
    assert_rapid(ops[3], [5.0, 0.0, 2.0]);
}

#[test]
fn g84_reverses_the_spindle() {
    let r = run(&["S500 M3", "G0 Z5", "G99 G84 X0 Y0 Z-5 R1 F500"]).unwrap();
    let ops = r.line(3);
    let spin = |d| OpKind::Spindle {
        speed: 500.0,
        dir: d,
    };
    assert_eq!(
        ops[2],
        &OpKind::Overrides {
            feed: false,
            spindle: false
        }
    );
    assert_feed(ops[3], [0.0, 0.0, -5.0], 500.0 / 60.0);
    assert_eq!(ops[4], &spin(SpindleDir::Off));
    assert_eq!(ops[5], &spin(SpindleDir::Ccw));
    assert_feed(ops[6], [0.0, 0.0, 1.0], 500.0 / 60.0);
    assert_eq!(ops[7], &spin(SpindleDir::Off));
    assert_eq!(ops[8], &spin(SpindleDir::Cw));
    assert_eq!(
        ops[9],
        &OpKind::Overrides {
            feed: true,
            spindle: true
        }
    );
    let e = run_err(&["G0 Z5", "G84 X0 Y0 Z-5 R1 F500"]);
    assert!(e.message.contains("clockwise"), "{e}");
}

#[test]
fn dwelling_and_boring_cycles() {
    let r = run(&["S100 M4", "G0 Z5", "G98 G82 X0 Y0 Z-5 R1 P0.5 F60"]).unwrap();
    assert_eq!(r.line(3)[3], &OpKind::Dwell { seconds: 0.5 });
    let r = run(&["S100 M4", "G0 Z5", "G98 G86 X0 Y0 Z-5 R1 P0.5 F60"]).unwrap();
    let ops = r.line(3);
    assert_eq!(ops.len(), 7);
    assert_eq!(
        ops[6],
        &OpKind::Spindle {
            speed: 100.0,
            dir: SpindleDir::Ccw
        }
    );
    let r = run(&["G0 Z5", "G98 G85 X0 Y0 Z-5 R1 F60"]).unwrap();
    let ops = r.line(2);
    assert_feed(ops[3], [0.0, 0.0, 1.0], 1.0);
    assert_rapid(ops[4], [0.0, 0.0, 5.0]);
    let r = run(&["G0 Z5", "G98 G89 X0 Y0 Z-5 R1 P2 F60"]).unwrap();
    let ops = r.line(2);
    assert_eq!(ops[3], &OpKind::Dwell { seconds: 2.0 });
    assert_feed(ops[4], [0.0, 0.0, 5.0], 1.0);
    let e = run_err(&["G0 Z5", "G82 X0 Y0 Z-5 R1 F60"]);
    assert!(e.message.contains("P"), "{e}");
    // G87 (LinuxCNC's interp_cycles.cc): through the hole at the offset point with the
    // spindle oriented, back bore up to K and down again, out the same way.
    let e = run_err(&["G0 Z5", "G87 X0 Y0 Z-5 R1 I1 J0 K-1 F60"]);
    assert!(e.message.contains("spindle"), "{e}");
    let e = run_err(&["G0 Z5 M3 S100", "G87 X0 Y0 Z-5 R1 I1 K-1 F60"]);
    assert!(e.message.contains("needs J"), "{e}");
    let r = run(&["G0 Z5 M4 S100", "G98 G87 X2 Y3 Z-5 R1 I1 J-0.5 K-1 F60"]).unwrap();
    let ops = r.line(2);
    let orient = OpKind::SpindleOrient {
        angle: 0.0,
        dir: SpindleDir::Ccw,
    };
    let on = OpKind::Spindle {
        speed: 100.0,
        dir: SpindleDir::Ccw,
    };
    assert_eq!(ops.len(), 14, "{ops:?}");
    assert_rapid(ops[0], [2.0, 3.0, 5.0]);
    assert_rapid(ops[1], [2.0, 3.0, 1.0]);
    assert_rapid(ops[2], [3.0, 2.5, 1.0]);
    assert_eq!(ops[3], &orient);
    assert_rapid(ops[4], [3.0, 2.5, -5.0]);
    assert_rapid(ops[5], [2.0, 3.0, -5.0]);
    assert_eq!(ops[6], &on);
    assert_feed(ops[7], [2.0, 3.0, -1.0], 1.0);
    assert_feed(ops[8], [2.0, 3.0, -5.0], 1.0);
    assert_eq!(ops[9], &orient);
    assert_rapid(ops[10], [3.0, 2.5, -5.0]);
    assert_rapid(ops[11], [3.0, 2.5, 5.0]);
    assert_rapid(ops[12], [2.0, 3.0, 5.0]);
    assert_eq!(ops[13], &on);
    // M19: R, P; a bad P.
    let r = run(&["M3 S100", "M19 R90 P2"]).unwrap();
    assert_eq!(
        r.line(2),
        [&OpKind::SpindleOrient {
            angle: 90.0,
            dir: SpindleDir::Off
        }]
    );
    assert!(run_err(&["M19 P3"]).message.contains("P3"));
}

#[test]
fn cycle_errors() {
    assert!(run_err(&["G81 X0 Y0 Z-1 F60"]).message.contains("R"));
    assert!(run_err(&["G81 X0 Y0 R1 F60"]).message.contains("Z"));
    assert!(run_err(&["G81 X0 Y0 Z1 R0 F60"]).message.contains("below"));
    assert!(run_err(&["G83 X0 Y0 Z-1 R1 F60"]).message.contains("Q"));
    assert!(run_err(&["G81 X0 Y0 Z-1 R1 A3 F60"])
        .message
        .contains("A word"));
    assert!(run_err(&["G93 G81 X0 Y0 Z-1 R1 F60"])
        .message
        .contains("inverse"));
    // G80 cancels; axis words after it have nothing to use them.
    let e = run_err(&["G81 X0 Y0 Z-1 R1 F60", "G80", "X2"]);
    assert_eq!(e.line, 3);
    // G80 beside another motion code on a line (as LinuxCNC reads it): the other one wins,
    // in either order; two others are still an error.
    for line in ["G90 G17 G40 G80 G00 X1", "G0 G80 X1"] {
        let r = run(&["G81 X0 Y0 Z-1 R1 F60", line]).unwrap();
        assert_rapid(&r.ops.last().unwrap().kind, [1.0, 0.0, 1.0]);
    }
    assert!(run_err(&["G80 G0 G1 X1"])
        .message
        .contains("same modal group"));
}

#[test]
fn probing_dry_run_and_with_a_result() {
    let r = run(&["G10 L2 P1 Z-100", "G38.2 Z-10 F60", "G0 X1"]).unwrap();
    match r.motion(2) {
        OpKind::Probe {
            end,
            must_trip,
            toward,
            ..
        } => {
            assert!(*must_trip && *toward);
            assert_pos(*end, [0.0, 0.0, -110.0]);
        }
        k => panic!("{k:?}"),
    }
    // Dry run: tripped at the end.
    assert_eq!(r.params.get(5063), Some(-10.0));
    assert_eq!(r.params.get(5070), Some(1.0));
    assert_rapid(r.motion(3), [1.0, 0.0, -110.0]);

    // With a result from the machine.
    let mut params = Params::new();
    let mut it = Interp::new(&Options::default(), &mut params);
    let mut ops = Vec::new();
    it.block(&blk(1, "G38.3 Z-10 F60"), &mut params, &mut ops)
        .unwrap();
    // Tripped at −4, came to rest at −4.2: the parameters report the trip, the program
    // goes on from where the motion stopped.
    it.probe_result(
        [0.0, 0.0, -4.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, -4.2, 0.0, 0.0, 0.0],
        true,
        &mut params,
    );
    assert_eq!(params.get(5063), Some(-4.0));
    it.block(&blk(2, "G1 Z0"), &mut params, &mut ops).unwrap();
    assert_pos(ops[1].kind.ends().unwrap().0, [0.0, 0.0, -4.2]);

    // G38.2 not tripping: an error at the next block.
    let mut params = Params::new();
    let mut it = Interp::new(&Options::default(), &mut params);
    it.block(&blk(1, "G38.2 Z-10 F60"), &mut params, &mut ops)
        .unwrap();
    let end = [0.0, 0.0, -10.0, 0.0, 0.0, 0.0];
    it.probe_result(end, end, false, &mut params);
    assert_eq!(params.get(5070), Some(0.0));
    let e = it
        .block(&blk(2, "G0 Z0"), &mut params, &mut ops)
        .unwrap_err();
    assert_eq!(e.line, 2);
    assert!(e.message.contains("line 1"), "{e}");
    // G38.3 not tripping is fine.
    let mut it = Interp::new(&Options::default(), &mut params);
    it.block(&blk(1, "G38.3 Z-10 F60"), &mut params, &mut ops)
        .unwrap();
    let end = [0.0, 0.0, -10.0, 0.0, 0.0, 0.0];
    it.probe_result(end, end, false, &mut params);
    assert!(it.block(&blk(2, "G0 Z0"), &mut params, &mut ops).is_ok());
}

#[test]
fn spindle_synchronised_motion() {
    let r = run(&["S300 M3", "G33 Z-10 K1.5", "G33.1 Z-20 K1"]).unwrap();
    assert_eq!(
        r.motion(2),
        &OpKind::SpindleSync {
            start: [0.0; 6],
            end: [0.0, 0.0, -10.0, 0.0, 0.0, 0.0],
            pitch: 1.5,
            tap: false
        }
    );
    // The tap comes back: the position is its start.
    assert!(r.motion(3).length().unwrap() == 20.0);
    assert_eq!(r.it.position(), [0.0, 0.0, -10.0, 0.0, 0.0, 0.0]);
    assert!(run_err(&["G33 Z-10"]).message.contains("K"));
    assert!(run_err(&["G33 Z-10 K1 F10"]).message.contains("F word"));
}

#[test]
fn m_codes_make_their_operations() {
    let opts = Options {
        optional_stop: false,
        ..Options::default()
    };
    let r = run_with(
        &opts,
        &[
            "S1000 M3 M8 (MSG,hello)",
            "M7",
            "M9 S2000",
            "M62 P3",
            "M66 P1 L3 Q2.5",
            "M65 P4",
            "M68 E2 Q7.5",
            "M49 M101 P1 Q2",
            "M50 P0",
            "M0",
            "M1",
            "M60",
            "G4 P1.5",
            "M5",
            "M30",
            "G0 X1",
        ],
    )
    .unwrap();
    assert_eq!(
        r.line(1),
        vec![
            &OpKind::Message {
                text: "hello".into()
            },
            &OpKind::Spindle {
                speed: 1000.0,
                dir: SpindleDir::Cw
            },
            &OpKind::Coolant {
                mist: false,
                flood: true
            },
        ]
    );
    assert_eq!(
        r.line(2),
        vec![&OpKind::Coolant {
            mist: true,
            flood: true
        }]
    );
    assert_eq!(
        r.line(3),
        vec![
            &OpKind::Spindle {
                speed: 2000.0,
                dir: SpindleDir::Cw
            },
            &OpKind::Coolant {
                mist: false,
                flood: false
            }
        ]
    );
    assert_eq!(
        r.line(4),
        vec![&OpKind::Output {
            index: 3,
            on: true,
            synced: true
        }]
    );
    assert_eq!(
        r.line(5),
        vec![&OpKind::WaitInput {
            index: 1,
            analog: false,
            mode: 3,
            timeout: 2.5
        }]
    );
    assert_eq!(
        r.line(6),
        vec![&OpKind::Output {
            index: 4,
            on: false,
            synced: false
        }]
    );
    assert_eq!(
        r.line(7),
        vec![&OpKind::AnalogOutput {
            index: 2,
            value: 7.5,
            synced: false
        }]
    );
    assert_eq!(
        r.line(8),
        vec![
            &OpKind::Overrides {
                feed: false,
                spindle: false
            },
            &OpKind::Hook {
                code: 101,
                p: Some(1.0),
                q: Some(2.0)
            }
        ]
    );
    assert_eq!(
        r.line(9),
        vec![&OpKind::Overrides {
            feed: false,
            spindle: false
        }]
    );
    assert_eq!(
        r.line(10),
        vec![&OpKind::Pause {
            kind: PauseKind::Program
        }]
    );
    assert!(r.line(11).is_empty(), "M1 with the optional stop off");
    assert_eq!(
        r.line(12),
        vec![&OpKind::Pause {
            kind: PauseKind::Pallet
        }]
    );
    assert_eq!(r.line(13), vec![&OpKind::Dwell { seconds: 1.5 }]);
    assert_eq!(r.line(15), vec![&OpKind::End { rewind: true }]);
    assert!(r.line(16).is_empty(), "nothing after M30");
    let r = run_with(
        &Options {
            optional_stop: true,
            ..Options::default()
        },
        &["M1", "M2"],
    )
    .unwrap();
    assert_eq!(
        r.line(1),
        vec![&OpKind::Pause {
            kind: PauseKind::Optional
        }]
    );
    assert_eq!(r.line(2), vec![&OpKind::End { rewind: false }]);
}

#[test]
fn t_selects_and_m6_changes() {
    let opts = Options {
        tools: tools(&[(3, 1.0, 2.0)]),
        ..Options::default()
    };
    let r = run_with(&opts, &["T3", "M6", "M61 Q0"]).unwrap();
    assert!(r.line(1).is_empty());
    assert_eq!(r.line(2), vec![&OpKind::ToolChange { tool: 3 }]);
    assert_eq!(r.it.tool(), 0);
    assert_eq!(r.params.get(5400), Some(0.0));
    let e = run_with(&opts, &["T4"]).unwrap_err();
    assert!(e.message.contains("T4"), "{e}");
}

#[test]
fn lines_linuxcnc_refuses_are_refused_with_their_line() {
    let cases: &[(&[&str], &str)] = &[
        (&["G0 X1", "G0 G1 X2"], "same modal group"),
        (&["G0 X1", "G17 G18"], "same modal group"),
        (&["M3 M4"], "same modal group"),
        (&["G0 X1", "G1 X2 U1"], "no U axis"),
        (&["G0 X1", "Y2 W1"], "no W axis"),
        (&["G0 X1", "G80 X1"], "G80"),
        (&["X1"], "no motion mode"),
        (&["G0 X1", "G1 X2 F10 I1"], "I word"),
        (&["G0 X1", "G0 X2 P1"], "P word"),
        (&["G0 X1", "G0 X2 Q1"], "Q word"),
        (&["G0 X1", "G0 X2 R1"], "R word"),
        (&["G0 X1", "G0 X2 L1"], "L word"),
        (&["G0 X1", "G40 L1"], "L word"),
        (&["G0 X1", "G0 X2 H1"], "H word"),
        (&["G0 X1", "G0 X2 D1"], "D word"),
        (&["G0 X1", "G0 X2 E1"], "E word"),
        (&["G0 X1", "G0 X2 K1"], "K word"),
        (&["G0 X1", "G12 X1"], "G12"),
        (&["G0 X1", "M3 M19"], "same modal group"),
        (&["G0 X1", "M222"], "M222"),
        (&["G0 X1", "G92"], "axis word"),
        (&["G0 X1", "G38.2 F10"], "without any axis word"),
        (&["G0 X1", "G10 L2 P1 X0 G1"], "both use the axis words"),
        (&["G0 X1", "G4"], "P"),
        (&["G0 X1", "G2 X0 Y1 F10"], "R or the centre"),
        (&["G0 X1", "G2 X0 Y1 R1 I1 F10"], "both R"),
        (&["G0 X1", "G2 X0 Y1 R1 P1.5 F10"], "whole number"),
        (&["G0 X1", "G96 S100"], "G96"),
        (&["G0 X1", "G76 X1"], "G76"),
    ];
    for (lines, what) in cases {
        let e = run_err(lines);
        assert_eq!(e.line, lines.len(), "{lines:?}: {e}");
        assert!(e.message.contains(what), "{lines:?}: {e} (want {what:?})");
    }
}

#[test]
fn the_work_position_is_published_after_every_block() {
    let r = run(&["G10 L2 P1 X1 Y2 Z3", "G0 X5 Y5 Z5 A7"]).unwrap();
    let w: Vec<f64> = (5420..=5425).map(|n| r.params.get(n).unwrap()).collect();
    assert_eq!(w, vec![5.0, 5.0, 5.0, 7.0, 0.0, 0.0]);
    assert_eq!(r.it.position(), [6.0, 7.0, 8.0, 7.0, 0.0, 0.0]);
}

#[test]
fn a_g52_offset_adds_to_the_work_system() {
    let r = run(&["G52 X10", "G0 X1", "G52 X0", "G0 X1"]).unwrap();
    assert_rapid(r.motion(2), [11.0, 0.0, 0.0]);
    assert_rapid(r.motion(4), [1.0, 0.0, 0.0]);
}

#[test]
fn the_spindle_reports_changes_only() {
    let r = run(&["S100 M3", "M3", "S100", "S200", "M5"]).unwrap();
    assert_eq!(r.line(1).len(), 1);
    assert!(r.line(2).is_empty() && r.line(3).is_empty());
    assert_eq!(
        r.line(4),
        vec![&OpKind::Spindle {
            speed: 200.0,
            dir: SpindleDir::Cw
        }]
    );
    assert_eq!(
        r.line(5),
        vec![&OpKind::Spindle {
            speed: 200.0,
            dir: SpindleDir::Off
        }]
    );
}

#[test]
fn a_motion_code_alone_sets_the_mode_without_moving() {
    let r = run(&["G1", "G0", "X3"]).unwrap();
    assert!(r.line(1).is_empty() && r.line(2).is_empty());
    assert_rapid(r.motion(3), [3.0, 0.0, 0.0]);
    assert_eq!(r.it.motion_mode(), Some(0));
}

#[test]
fn g94_and_g95_clear_the_feed_as_linuxcnc_does() {
    let e = run_err(&["G1 X1 F100", "G94", "X2"]);
    assert_eq!(e.line, 3);
    let r = run(&["G1 X1 F100", "G93 X2 F30", "G94 X3 F120"]).unwrap();
    assert_feed(r.motion(3), [3.0, 0.0, 0.0], 2.0);
}

#[test]
fn tool_parameters_follow_the_units() {
    let opts = Options {
        tools: tools(&[(1, 25.4, 12.7)]),
        ..Options::default()
    };
    let r = run_with(&opts, &["T1 M6", "G20"]).unwrap();
    assert_eq!(r.params.get(5400), Some(1.0));
    assert!(close(r.params.get(5403).unwrap(), 1.0));
    assert!(close(r.params.get(5410).unwrap(), 0.5));
}

/// The messages of a program read whole (`(DEBUG, …)` with parameters substituted), or its
/// error.
fn debug_texts(text: &str) -> Result<Vec<String>, GcodeError> {
    let mut p = crate::gcode::Program::from_text(text.to_string(), &Options::default());
    let mut out = Vec::new();
    for op in &mut p {
        if let OpKind::Message { text } = op?.kind {
            out.push(text.trim().to_string());
        }
    }
    Ok(out)
}

#[test]
fn predefined_named_parameters_follow_the_modal_state() {
    let t = debug_texts(
        "G20 G91 G55 G1 X1 F20 S1200 M3 M8\n\
         (DEBUG, #<_x> #<_abs_x> #<_motion_mode> #<_imperial> #<_incremental> #<_coord_system>)\n\
         (DEBUG, #<_feed> #<_rpm> #<_spindle_on> #<_flood> #<_plane> #<_line>)\n\
         G21 G90 G54 G0 X2 G18 M5\n\
         (DEBUG, #<_x> #<_motion_mode> #<_metric> #<_absolute> #<_coord_system> #<_plane>)\n\
         (DEBUG, #<_spindle_on> #<_vmajor> #<_task> #<_call_level>)\n",
    )
    .unwrap();
    assert_eq!(
        t,
        [
            "1.000000 1.000000 10.000000 1.000000 1.000000 550.000000",
            "20.000000 1200.000000 1.000000 1.000000 170.000000 3.000000",
            "2.000000 0.000000 1.000000 1.000000 540.000000 180.000000",
            "0.000000 2.000000 1.000000 0.000000",
        ]
    );
    let e = debug_texts("#<_x> = 3\n").unwrap_err();
    assert!(e.message.contains("predefined"), "{e}");
    assert_eq!(e.line, 1);
}

#[test]
fn m70_to_m73_save_and_restore_the_modal_state() {
    let text = "\
o100 sub
  M73
  G20 G91 G55 G18 S500 M4 M8 F7
  (DEBUG, #<_imperial> #<_incremental> #<_coord_system> #<_plane> #<_rpm> #<_flood>)
o100 endsub
G21 G90 G17 S1000 M3 F100
o100 call
(DEBUG, #<_metric> #<_absolute> #<_coord_system> #<_plane> #<_rpm> #<_spindle_cw> #<_flood> #<_feed>)
M70
G20 M9 M5
M72
(DEBUG, #<_metric> #<_spindle_on> #<_flood>)
M71
M72
";
    let mut p = crate::gcode::Program::from_text(text.to_string(), &Options::default());
    let mut texts = Vec::new();
    let mut spindle = Vec::new();
    let mut e = None;
    for op in &mut p {
        match op {
            Ok(op) => match op.kind {
                OpKind::Message { text } => texts.push(text.trim().to_string()),
                OpKind::Spindle { speed, dir } => spindle.push((op.line, speed, dir)),
                _ => {}
            },
            Err(err) => e = Some(err),
        }
    }
    assert_eq!(
        texts,
        [
            "1.000000 1.000000 550.000000 180.000000 500.000000 1.000000",
            "1.000000 1.000000 540.000000 170.000000 1000.000000 1.000000 0.000000 100.000000",
            "1.000000 1.000000 0.000000",
        ]
    );
    // M3 S1000, the sub's M4 S500, its restore at its endsub, M5, M72's restore (M3 S1000).
    assert_eq!(
        spindle
            .iter()
            .map(|&(l, s, d)| (l, s, d == SpindleDir::Cw))
            .collect::<Vec<_>>(),
        [
            (6, 1000.0, true),
            (3, 500.0, false),
            (5, 1000.0, true),
            (10, 1000.0, false),
            (11, 1000.0, true),
        ]
    );
    let e = e.expect("M72 after M71");
    assert_eq!(e.line, 14);
    assert!(e.message.contains("M72"), "{e}");
}

#[test]
fn polar_coordinates_as_linuxcnc_reads_them() {
    // G90: the point at @ and ^ about the work origin; one missing is the current point's.
    let r = run(&["G0 @10 ^90", "G1 ^0 F60", "G1 @5", "G91 G1 ^90", "G1 @-1"]).unwrap();
    assert_rapid(r.motion(1), [0.0, 10.0, 0.0]);
    assert_feed(r.motion(2), [10.0, 0.0, 0.0], 1.0);
    assert_feed(r.motion(3), [5.0, 0.0, 0.0], 1.0);
    // G91: the current distance and angle increased.
    assert_feed(r.motion(4), [0.0, 5.0, 0.0], 1.0);
    assert_feed(r.motion(5), [0.0, 4.0, 0.0], 1.0);
    // In inches, from a work offset.
    let r = run(&["G10 L2 P1 X100", "G20 G0 @1 ^180"]).unwrap();
    assert_rapid(r.motion(2), [100.0 - 25.4, 0.0, 0.0]);
    for (lines, says) in [
        (&["G0 @1"][..], "origin"),
        (&["G91 G0 ^90"][..], "origin"),
        (&["G0 @1 ^0 X1"][..], "X or Y"),
        (&["G2 @1 ^0 R1"][..], "G0 and G1"),
    ] {
        let e = run_err(lines);
        assert!(e.message.contains(says), "{lines:?}: {e}");
    }
}
