//! Layout 1.14: a path whose axes live on several cards of one sync bus (`CardSet::path`), on
//! the stepped clock. The figure: a 12-axis path split over two cards moves every axis,
//! on every tick, exactly (to the last bit) where one planner of all twelve axes puts it, and
//! so does the same path split 8 + 4 or over three cards 4 + 4 + 4. Segments are streamed in
//! several releases while the path runs, and a halt and a hold are timed to one tick on every
//! card. Read back through each card's scope, as a user would.
mod common;

#[path = "../card-emu/tests/common/wide_path.rs"]
mod wide_path;

use motioncard_sdk::{
    CardSet, Clock, EmuOptions, ErrorKind, GroupSettings, GroupState, PathBuffer, PathPart,
    PathSettings, Segment, SimOptions,
};
use std::time::Duration;
use wide_path::{compare, engine, program, read_all, record, settings, Control, D, N};

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(60);

/// `split.len()` stepped cards of 8 axes on one bus, card k's group 0 over its first
/// `split[k]` axes (enabled), each card's scope sampling their commanded positions every
/// tick, continuously.
fn cards(split: &[usize]) -> CardSet {
    let set = CardSet::sim(
        split.len(),
        SimOptions {
            clock: Clock::Stepped,
            emu: EmuOptions::new(8, RATE),
        },
    )
    .unwrap();
    for (c, &n) in set.cards().iter().zip(split) {
        let axes: Vec<usize> = (0..n).collect();
        for &a in &axes {
            c.axis(a).unwrap().enable().unwrap();
        }
        let g = c.group(0).unwrap();
        g.configure(&GroupSettings::new(&axes)).unwrap();
        g.enable().unwrap();
        record(c, n);
    }
    set
}

/// Step the set until every card's group is at rest with nothing queued, reading the scopes
/// as it goes (every 2,000 ticks, within their 4,096 samples).
fn run_to_rest(
    set: &CardSet,
    split: &[usize],
    got: &mut std::collections::BTreeMap<u64, [f64; D]>,
) {
    for _ in 0..1_000 {
        read_all(set, split, got);
        let rest = set.cards().iter().all(|c| {
            let (state, st) = c.group(0).unwrap().status().unwrap();
            state == GroupState::Standby && st.path_queued == 0 && st.path_staged == 0
        });
        if rest {
            return;
        }
        set.cards()[0].sim().unwrap().step(2_000);
    }
    panic!("the path across cards never came to rest");
}

/// The figure: a 12-axis path split over two cards (6 + 6), over two cards 8 + 4 and
/// over three cards 4 + 4 + 4, streamed in three releases (the second and third while the path
/// runs): on every tick, every axis of every card is where one 12-axis planner puts it, to the
/// last bit; the path reaches its end at the origin.
#[test]
fn a_12_axis_path_over_cards_is_bit_identical_to_one_planner() {
    let prog = program();
    for split in [&[6, 6][..], &[8, 4], &[4, 4, 4]] {
        let set = cards(split);
        let parts: Vec<PathPart> = (0..split.len())
            .map(|card| PathPart { card, group: 0 })
            .collect();
        let mut path = set.path(&parts, &settings()).unwrap();
        assert_eq!(path.dims(), N);
        let mut got = std::collections::BTreeMap::new();
        let mut batches = Vec::new();
        for chunk in [&prog[..3], &prog[3..20], &prog[20..]] {
            for s in chunk {
                path.push(s).unwrap();
            }
            let t = path.release().unwrap();
            batches.push((t, chunk.to_vec()));
            read_all(&set, split, &mut got);
            // let it run a while before the next batch
            set.cards()[0].sim().unwrap().step(1_500);
            read_all(&set, split, &mut got);
        }
        run_to_rest(&set, split, &mut got);
        path.wait(LONG).unwrap();
        assert_eq!(path.progress().unwrap().done, prog.len() as u32);
        let (first, want) = engine(RATE, &batches, &[]);
        let ticks = compare(&got, first, &want);
        let last = got.values().next_back().unwrap();
        assert!(
            last[..N].iter().all(|&x| x == 0.0),
            "back at the origin: {last:?}"
        );
        println!(
            "{split:?}: {ticks} ticks from the start, releases at {:?}: every axis bit-identical \
             to one 12-axis planner",
            batches.iter().map(|b| b.0).collect::<Vec<_>>()
        );
    }
}

/// `SetPath::run` streams a long program (the 12-axis program with 300 short blended chords
/// through all twelve axes spliced in) in batches of 256, the second released while the path
/// runs: the release ticks, read from each card's `Timed` events, are the same on both cards,
/// and every axis moves on every tick as one planner fed those batches on those ticks, to the
/// last bit.
#[test]
fn a_program_streamed_by_run_is_bit_identical_to_one_planner() {
    let mut prog = program();
    let tail = prog.split_off(5);
    let from = wide_path::pt(0.5);
    for k in 1..=300u32 {
        let th = f64::from(k) * std::f64::consts::PI / 150.0;
        let p: Vec<f64> = (0..N)
            .map(|d| from[d] + 400.0 * (th + d as f64).sin() - 400.0 * (d as f64).sin())
            .collect();
        prog.push(Segment::line(100 + k, &p, 3e4, 2.0));
    }
    prog.extend(tail);
    let split = [6, 6];
    let (set, mut path) = six_and_six();
    let mut got = std::collections::BTreeMap::new();
    let t0 = path.run(&prog).unwrap();
    read_all(&set, &split, &mut got);
    run_to_rest(&set, &split, &mut got);
    path.wait(LONG).unwrap();
    let releases: Vec<Vec<u64>> = set
        .cards()
        .iter()
        .map(|c| {
            let mut ticks = Vec::new();
            while let Some(e) = c.next_event(Duration::ZERO).unwrap() {
                if e.kind == motioncard_sdk::EventKind::Timed
                    && e.code == motioncard_sdk::proto::Opcode::PathRelease as i32
                {
                    ticks.push(e.tick);
                }
            }
            ticks
        })
        .collect();
    assert_eq!(
        releases[0], releases[1],
        "the same release ticks on both cards"
    );
    assert_eq!(
        releases[0].len(),
        prog.len().div_ceil(256),
        "batches of 256"
    );
    assert_eq!(releases[0][0], t0);
    let batches: Vec<(u64, Vec<Segment>)> = releases[0]
        .iter()
        .zip(prog.chunks(256))
        .map(|(&t, c)| (t, c.to_vec()))
        .collect();
    let (first, want) = engine(RATE, &batches, &[]);
    let ticks = compare(&got, first, &want);
    assert!(got.values().next_back().unwrap()[..N]
        .iter()
        .all(|&x| x == 0.0));
    println!(
        "{} segments in {} releases (ticks {:?}): {ticks} ticks, every axis bit-identical to \
         one 12-axis planner",
        prog.len(),
        batches.len(),
        releases[0]
    );
}

/// A halt, and a hold then a resume, each timed to one tick on both cards: every axis stops
/// (and goes on) where one planner told the same on that tick stops it, to the last bit.
#[test]
fn a_halt_and_a_hold_across_cards_are_one_tick_on_every_card() {
    let prog = program();
    for halt in [false, true] {
        let split = [6, 6];
        let set = cards(&split);
        let parts = [
            PathPart { card: 0, group: 0 },
            PathPart { card: 1, group: 0 },
        ];
        let mut path = set.path(&parts, &settings()).unwrap();
        let mut got = std::collections::BTreeMap::new();
        let t0 = path.run(&prog).unwrap();
        read_all(&set, &split, &mut got);
        set.cards()[0].sim().unwrap().step(1_200);
        read_all(&set, &split, &mut got);
        let mut control = Vec::new();
        if halt {
            let t = path.halt(2e5, 5e7).unwrap();
            control.push((t, Control::Halt(2e5, 5e7)));
        } else {
            let t = path.hold().unwrap();
            control.push((t, Control::Override(0.0)));
            read_all(&set, &split, &mut got);
            set.cards()[0].sim().unwrap().step(3_000);
            read_all(&set, &split, &mut got);
            let t = path.set_override(1.0).unwrap();
            control.push((t, Control::Override(1.0)));
        }
        run_to_rest(&set, &split, &mut got);
        let (first, want) = engine(RATE, &[(t0, prog.clone())], &control);
        assert_eq!(first, t0);
        let ticks = compare(&got, first, &want);
        let last = got.values().next_back().unwrap();
        let at_origin = last[..N].iter().all(|&x| x == 0.0);
        assert_eq!(
            at_origin, !halt,
            "halted short of the end, or held and finished"
        );
        println!(
            "{}: {ticks} ticks, every axis bit-identical to one planner",
            if halt { "halt" } else { "hold and resume" }
        );
    }
}

/// What `CardSet::path` refuses before anything moves: more than 16 axes, a card not in the
/// set, a group named twice, limits of the wrong count; an Aborting segment; a line of the
/// wrong count; and a segment refused by the cards (NaN is the host's, a zero-length line
/// the cards'), leaving nothing staged.
#[test]
fn what_a_path_across_cards_refuses() {
    let set = cards(&[8, 8]);
    let two = [
        PathPart { card: 0, group: 0 },
        PathPart { card: 1, group: 0 },
    ];
    let s16 = PathSettings::uniform(16, 5e4, 1e6, 1e8);
    // 16 axes is the most: fine; a third card's part does not exist
    assert!(set.path(&two, &s16).is_ok());
    let bad = [PathPart { card: 2, group: 0 }];
    assert_eq!(
        set.path(&bad, &s16).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    let twice = [
        PathPart { card: 0, group: 0 },
        PathPart { card: 0, group: 0 },
    ];
    assert_eq!(
        set.path(&twice, &s16).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    let s12 = PathSettings::uniform(12, 5e4, 1e6, 1e8);
    assert_eq!(set.path(&two, &s12).unwrap_err().kind(), ErrorKind::BadAxis);
    let mut path = set.path(&two, &s16).unwrap();
    let aborting = Segment {
        buffer: PathBuffer::Aborting,
        ..Segment::line(1, &[1.0; 16], 1e4, 0.0)
    };
    assert_eq!(
        path.push(&aborting).unwrap_err().kind(),
        ErrorKind::Unsupported
    );
    let short = Segment::line(1, &[1.0; 12], 1e4, 0.0);
    assert_eq!(path.push(&short).unwrap_err().kind(), ErrorKind::BadAxis);
    let mut nan = vec![1.0; 16];
    nan[13] = f64::NAN;
    let e = path.push(&Segment::line(1, &nan, 1e4, 0.0)).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::NotFinite);
    let zero = path
        .push(&Segment::line(1, &[0.0; 16], 1e4, 0.0))
        .unwrap_err();
    assert_eq!(zero.kind(), ErrorKind::PathZeroLength);
    assert_eq!(path.progress().unwrap().staged, 0);
    for c in set.cards() {
        assert_eq!(c.group(0).unwrap().status().unwrap().1.path_staged, 0);
    }
    // a 16-axis line is one segment on both cards
    path.push(&Segment::line(1, &[10.0; 16], 1e4, 0.0)).unwrap();
    for c in set.cards() {
        assert_eq!(c.group(0).unwrap().status().unwrap().1.path_staged, 1);
    }
    path.release().unwrap();
    path.wait(LONG).unwrap();
    for c in set.cards() {
        for a in 0..8 {
            assert_eq!(c.axis(a).unwrap().status().unwrap().command_position, 10.0);
        }
    }
}

/// Two stepped cards of six axes each, and a 12-axis path over them.
fn six_and_six() -> (CardSet, motioncard_sdk::SetPath) {
    let set = cards(&[6, 6]);
    let parts = [
        PathPart { card: 0, group: 0 },
        PathPart { card: 1, group: 0 },
    ];
    let path = set.path(&parts, &settings()).unwrap();
    (set, path)
}

/// A drive alarm on one card mid-path: that card's group stops (ErrorStop); `SetPath::wait`
/// halts the other card's path at once and returns the fault; the other card's axes come to
/// rest along the path, short of its end, within their stop.
#[test]
fn a_fault_on_one_card_halts_the_path_on_the_others() {
    let (set, mut path) = six_and_six();
    path.run(&program()).unwrap();
    set.cards()[0].sim().unwrap().step(2_000);
    set.cards()[1]
        .sim()
        .unwrap()
        .with_emulator(|e| e.faults().set_alarm(3, true));
    let e = path.wait(LONG).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidState, "{e}");
    let (state, _) = set.cards()[1].group(0).unwrap().status().unwrap();
    assert_eq!(state, GroupState::ErrorStop);
    // the other card halts along the path: at rest within its stop, not at the end
    let g0 = set.cards()[0].group(0).unwrap();
    let mut ticks = 0;
    while g0.status().unwrap().0 != GroupState::Standby {
        set.cards()[0].sim().unwrap().step(10);
        ticks += 10;
        assert!(ticks < 5_000, "card 0 comes to rest within its stop");
    }
    let p: Vec<f64> = (0..6)
        .map(|a| {
            set.cards()[0]
                .axis(a)
                .unwrap()
                .status()
                .unwrap()
                .command_position
        })
        .collect();
    assert!(
        p.iter().any(|&x| x != 0.0),
        "halted short of the end: {p:?}"
    );
    assert_eq!(
        g0.status().unwrap().1.path_queued,
        0,
        "what it held was aborted"
    );
    println!("card 0 at rest {ticks} ticks after the fault was seen");
}

/// `SetPath::run` streams segments to every card before their answers come back: a segment
/// the cards refuse (here a chord of zero length, the 301st, after a first batch of 256 was
/// released and started) ends the stream with that refusal, halts the path on every card on
/// its geometry, and drops what was staged after it on every card: nothing more runs.
#[test]
fn a_segment_refused_in_a_run_halts_the_path_on_every_card() {
    let (set, mut path) = six_and_six();
    let chord = |i: u32| {
        let p: Vec<f64> = (0..N)
            .map(|d| 40.0 * f64::from(i) * (1.0 + d as f64 / 10.0))
            .collect();
        Segment::line(i, &p, 3e4, 1.0)
    };
    let mut prog: Vec<Segment> = (1..=400).map(chord).collect();
    prog[300] = chord(300); // the 301st ends where the 300th did
    let e = path.run(&prog).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::PathZeroLength, "{e}");
    assert_eq!(path.progress().unwrap().staged, 0);
    for c in set.cards() {
        let st = c.group(0).unwrap().status().unwrap().1;
        assert!(st.path_queued <= 256, "only the first batch was released");
    }
    set.cards()[0].sim().unwrap().step(20_000);
    let far = 40.0 * 256.0;
    for c in set.cards() {
        let (state, st) = c.group(0).unwrap().status().unwrap();
        assert_eq!(state, GroupState::Standby);
        assert_eq!(
            (st.path_queued, st.path_staged),
            (0, 0),
            "what was queued and staged was aborted at rest"
        );
        let x = c.axis(0).unwrap().status().unwrap().command_position;
        assert!(
            x > 0.0 && x < far,
            "halted short of the first batch's end: {x}"
        );
    }
    // both cards halted on one tick, at one place on the path: dimension 6 (card 1's first
    // axis) moves 1.6 times as far as dimension 0 on every chord
    let x: Vec<f64> = set
        .cards()
        .iter()
        .map(|c| c.axis(0).unwrap().status().unwrap().command_position)
        .collect();
    assert!((x[1] / x[0] - 1.6).abs() < 1e-9, "{x:?}");
}
