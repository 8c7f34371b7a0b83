//! Garbage from the host: the fuzz corpus replayed, and a seeded sweep of a million garbage
//! commands. The harness (decoders, card, invariants) is `card_emu::testkit::fuzzing`, shared with the
//! fuzz targets in `fuzz/`.

use card_emu::testkit::fuzzing::{run_commands, run_dpram, sweep};
use std::path::PathBuf;
use std::time::Instant;

fn corpus(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/corpus")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let data = std::fs::read(&p).unwrap();
            (p, data)
        })
        .collect()
}

fn replay(target: &str, run: fn(&[u8])) {
    let inputs = corpus(target);
    assert!(!inputs.is_empty(), "no corpus for {target}");
    for (path, data) in &inputs {
        let r = std::panic::catch_unwind(|| run(data));
        assert!(r.is_ok(), "{} failed", path.display());
    }
    eprintln!("{target}: {} corpus inputs replayed", inputs.len());
}

#[test]
fn commands_corpus_replays_clean() {
    replay("commands", run_commands);
}

#[test]
fn dpram_corpus_replays_clean() {
    replay("dpram", run_dpram);
}

/// A million garbage commands on cards with every axis enabled and at standstill. Every one
/// gets exactly one ack or nack with its seq and a known code; a nacked one changes no status
/// and the tick after it starts nothing. Cards that an accepted command set moving are
/// replaced by fresh ones.
#[test]
fn a_million_garbage_commands_move_nothing_they_are_refused() {
    let n = 1_000_000;
    let t = Instant::now();
    let s = sweep(0x5EED_CAFE_F00D_0001, n, 1).stats;
    let secs = t.elapsed().as_secs_f64();
    eprintln!(
        "{n} garbage commands in {secs:.1} s: {} acks, {} nacks, {} cards, {} ticks ({} at rest)",
        s.acks, s.nacks, s.reboots, s.ticks, s.quiet_ticks
    );
    let codes: Vec<String> = s
        .nack_codes
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(c, n)| format!("{:?}: {n}", firmware_proto::NackCode::from_raw(c as i32)))
        .collect();
    eprintln!("nacks: {}", codes.join(", "));
    assert!(s.commands >= n);
    assert_eq!(s.acks + s.nacks, s.commands, "a command went unanswered");
    // The sweep reaches deep validation: most codes show up, and some commands are accepted.
    assert!(s.acks > 1000 && s.nacks > n / 2);
    assert!(
        codes.len() >= 25,
        "only {} distinct nack codes: {codes:?}",
        codes.len()
    );
}

// ---- Regression tests for what the fuzzers and the sweep found ----

use card_emu::testkit::fuzzing::{nurbs_entries, Card, Reply};
use firmware_proto::wire::CMD_ARGS;
use firmware_proto::{raw, NackCode, Opcode};

/// Send a NURBS transfer to group `g` and return the reply to its end, timing the whole.
fn transfer(
    card: &mut Card,
    g: u16,
    degree: usize,
    points: &[f64],
    weights: &[f64],
    knots: &[f64],
) -> (Reply, f64) {
    let n_ctrl = weights.len();
    let mut header = [0.0; CMD_ARGS];
    header[..8].copy_from_slice(&[
        degree as f64,
        n_ctrl as f64,
        knots.len() as f64,
        2679.4,
        1.2e6,
        3.7e6,
        0.036,
        0.86,
    ]);
    let stream: Vec<f64> = [points, weights, knots].concat();
    let t = Instant::now();
    let mut last = Reply::Unknown;
    for e in nurbs_entries(g, 0, &header, &stream, |_| 12) {
        last = card.send(&e);
    }
    (last, t.elapsed().as_secs_f64())
}

/// The sweep found a degree-1 curve with weights 0.08 and 2.6e9: planning it took 8 s in the
/// command manager (the servo loop stalled) and measured half its length. Weights spread wider
/// than `MAX_WEIGHT_RATIO` are refused with the weight code, at once.
#[test]
fn extreme_nurbs_weights_are_refused_at_once() {
    let mut card = Card::new();
    let points = [
        0.0,
        0.0,
        0.0,
        -29010.0,
        -167890.0,
        5792.0,
        -28367000.0,
        -5051000.0,
        238700.0,
        32020.0,
        -23206000000.0,
        16080000.0,
        -164290.0,
        -17159000000.0,
        286530.0,
        -30408000000.0,
        -18292000000.0,
        -26436.0,
    ];
    let weights = [1.0, 1.0, 1.0, 0.0796, 2602990890.26, 1.0];
    let knots = [0.0, 0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.0];
    let (r, secs) = transfer(&mut card, 1, 1, &points, &weights, &knots);
    assert_eq!(r, Reply::Nack(NackCode::NurbsWeight));
    assert!(secs < 0.5, "{secs} s");
    // Within the ratio the same curve is planned, and refused as a move as long as any other
    // would be: 6e10 counts at 2679 counts/s is beyond MAX_MOVE_TIME.
    let mut card = Card::new();
    let weights = [1.0, 1.0, 1.0, 0.1, 900.0, 1.0];
    let (r, secs) = transfer(&mut card, 1, 1, &points, &weights, &knots);
    assert_eq!(r, Reply::Nack(NackCode::Infeasible));
    assert!(secs < 0.5, "{secs} s");
    // 10,000 times smaller, it is accepted.
    let mut card = Card::new();
    let small: Vec<f64> = points.iter().map(|p| p * 1e-4).collect();
    let (r, secs) = transfer(&mut card, 1, 1, &small, &weights, &knots);
    assert_eq!(r, Reply::Ack);
    assert!(secs < 0.5, "{secs} s");
}

/// Reconfiguring a group between a NURBS begin and its end (disable, configure with more
/// axes, enable) made the end split the staged stream at a point past its end: a panic.
#[test]
fn reconfiguring_a_group_during_a_nurbs_transfer_is_a_nack_not_a_panic() {
    let mut card = Card::new();
    let knots = [0.0, 0.0, 1.0, 1.0];
    let mut header = [0.0; CMD_ARGS];
    header[..8].copy_from_slice(&[1.0, 2.0, 4.0, 1e4, 1e6, 1e8, 0.1, 1.0]);
    let stream: Vec<f64> = [&[0.0, 0.0, 100.0, 100.0][..], &[1.0, 1.0], &knots].concat();
    let entries = nurbs_entries(0, 0, &header, &stream, |_| 12);
    assert_eq!(card.send(&entries[0]), Reply::Ack);
    // Free axes 5, 6 (group 2 → axis 7) and 2, 3, 4 (group 1 → axis 2 only), then give group
    // 0 six axes.
    let post = raw::MC_ACCDEC_POST;
    let exact = raw::MC_INTERP_EXACT;
    assert_eq!(card.command(Opcode::GroupDisable, 0, 0, &[]), Reply::Ack);
    assert_eq!(card.command(Opcode::GroupDisable, 1, 0, &[]), Reply::Ack);
    card.set_group_config(2, &[7], post, exact);
    assert_eq!(card.command(Opcode::GroupConfigure, 2, 0, &[]), Reply::Ack);
    card.set_group_config(1, &[2], post, exact);
    assert_eq!(card.command(Opcode::GroupConfigure, 1, 0, &[]), Reply::Ack);
    card.set_group_config(0, &[0, 1, 3, 4, 5, 6], post, exact);
    assert_eq!(card.command(Opcode::GroupConfigure, 0, 0, &[]), Reply::Ack);
    assert_eq!(card.command(Opcode::GroupEnable, 0, 0, &[]), Reply::Ack);
    for e in &entries[1..entries.len() - 1] {
        assert_eq!(card.send(e), Reply::Nack(NackCode::NurbsSequence));
    }
    assert_eq!(
        card.send(&entries[entries.len() - 1]),
        Reply::Nack(NackCode::NurbsSequence)
    );
    card.tick(10);
}

/// Control points out of the card's range: 1e300 made the planner integrate an infinite
/// length for 13 s before refusing the curve as zero-length; 1e20 (a finite length) was
/// accepted and sent the axes towards it. Both are out of range, refused at the data entry.
#[test]
fn nurbs_points_beyond_the_card_range_are_refused_at_once() {
    for far in [1e300, 1e20, 2.0 * card_emu::MAX_POSITION] {
        let mut card = Card::new();
        let points = [0.0, 0.0, far, 5.0, 3.0, 4.0];
        let (r, secs) = transfer(
            &mut card,
            0,
            1,
            &points,
            &[1.0; 3],
            &[0.0, 0.0, 0.5, 1.0, 1.0],
        );
        // The data entry was refused, so the end finds the transfer incomplete.
        assert_eq!(r, Reply::Nack(NackCode::NurbsSequence), "{far}");
        assert!(secs < 0.5, "{far}: {secs} s");
        let mut card = Card::new();
        let mut header = [0.0; CMD_ARGS];
        header[..8].copy_from_slice(&[1.0, 3.0, 5.0, 1e4, 1e6, 1e8, 0.1, 1.0]);
        let stream = [&points[..], &[1.0; 3], &[0.0, 0.0, 0.5, 1.0, 1.0]].concat();
        let e = nurbs_entries(0, 0, &header, &stream, |_| 12);
        assert_eq!(card.send(&e[0]), Reply::Ack);
        assert_eq!(card.send(&e[1]), Reply::Nack(NackCode::OutOfRange), "{far}");
    }
}

/// Knot spans so short that the curve's derivative overflows: the planner's arc-length
/// quadrature split non-finite pieces to its limits for 11–51 s before refusing the curve.
#[test]
fn nurbs_knots_that_overflow_the_derivative_are_refused_at_once() {
    let cases: [(usize, &[f64], &[f64]); 3] = [
        (
            1,
            &[0.0, 0.0, 1e6, 5.0, 3.0, 4.0],
            &[0.0, 0.0, 1e-300, 1.0, 1.0],
        ),
        (
            3,
            &[0.0, 0.0, 1e6, 5.0, 3.0, 4.0, 7.0, 7.0, 1e15, 1e15],
            &[0.0, 0.0, 0.0, 0.0, 1e-300, 1.0, 1.0, 1.0, 1.0],
        ),
        (
            2,
            &[0.0, 0.0, 4.5e15, -4.5e15, 3.0, 4.0],
            &[0.0, 0.0, 0.0, 1e-310, 1e-310, 1e-310],
        ),
    ];
    for (degree, points, knots) in cases {
        let mut card = Card::new();
        let weights = vec![1.0; points.len() / 2];
        let (r, secs) = transfer(&mut card, 0, degree, points, &weights, knots);
        assert_eq!(r, Reply::Nack(NackCode::NurbsZeroLength), "{knots:?}");
        assert!(secs < 0.5, "{knots:?}: {secs} s");
    }
}

/// The fuzzer found a curve that stands still over two spans (three coincident control
/// points): the arc-length quadrature's tolerance, relative to an estimate that was rounding
/// noise there, was never met, and accepting the curve took 5 s.
#[test]
fn nurbs_curve_standing_still_is_planned_at_once() {
    let mut card = Card::new();
    let p = -5_398_000.0;
    let points = [0.0, 0.0, p, p, p, p, p, p, -261.0, -1e6];
    let weights = [100.0, 1.2197603440923492, 100.0, 1.0, 1.0];
    let knots = [0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0];
    let (r, secs) = transfer(&mut card, 0, 1, &points, &weights, &knots);
    assert_eq!(r, Reply::Ack);
    assert!(secs < 0.5, "{secs} s");
    card.tick(100);
}
