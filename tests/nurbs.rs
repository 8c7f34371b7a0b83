//! NURBS moves on the stepped emulated card: the die bonder with and without the
//! saturation-aware feed, exact circles, streaming, and every curve fault's nack.
mod common;

use common::stepped_card;
use motioncard::papers::yeh_die_bonder;
use motioncard::proto::{Command, Opcode};
use motioncard::{
    clamped_uniform_knots, Card, ErrorKind, GroupSettings, GroupState, MoveOptions, NackCode,
    Nurbs, NurbsFeed,
};
use std::time::Duration;

const T: Duration = Duration::from_secs(60);

/// Yeh Fig 5–7 on the card: with the saturation-aware feed every tick's drive output stays
/// within Umax and the contour error is bounded; without it the PD+ law asks for far more than
/// Umax, the DAC clips, and the contour error grows.
#[test]
fn die_bonder_saturation_aware_feed_keeps_u_within_umax() {
    let with = yeh_die_bonder(true).unwrap();
    let without = yeh_die_bonder(false).unwrap();
    assert_eq!(
        with.ticks_over, 0,
        "with: {:?} V over {} V",
        with.max_u, with.umax
    );
    assert!(
        with.max_u.iter().all(|u| *u <= with.umax),
        "{:?}",
        with.max_u
    );
    assert!(
        with.contour < 30.0,
        "with: contour error {} counts",
        with.contour
    );
    assert!(
        without.max_u[0] > 2.0 * without.umax && without.ticks_over > 10,
        "without: {:?}",
        without.max_u
    );
    assert!(
        without.contour > 10.0 * with.contour,
        "contour without {} vs with {}",
        without.contour,
        with.contour
    );
    // At constant feed the interpolated chord matches the feed within 0.01%.
    assert!(
        without.feed_fluctuation <= 1e-4,
        "feed fluctuation {}",
        without.feed_fluctuation
    );
}

fn two_axis_group() -> (Card, motioncard::Group) {
    let card = stepped_card();
    for a in 0..2 {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    g.enable().unwrap();
    (card, g)
}

/// A full circle as a rational quadratic NURBS, run on the card: every commanded point on the
/// radius, the feed at its command on the way round, the end exact.
#[test]
fn rational_circle_on_the_card() {
    let (card, g) = two_axis_group();
    let sim = card.sim().unwrap();
    let r = 20_000.0;
    // Starts at (r, 0) relative to the centre (-r, 0)... i.e. at the origin.
    let circle = Nurbs::circle([-r, 0.0], r).unwrap();
    let feed = 80_000.0;
    let m = g
        .move_nurbs(
            &circle,
            &NurbsFeed::new(feed, 1e6, 1e8),
            MoveOptions::default(),
        )
        .unwrap();
    let (mut worst, mut chords) = (0.0f64, Vec::new());
    let mut prev = (0.0, 0.0);
    while g.status().unwrap().0 == GroupState::Moving {
        sim.step(1);
        let (x, y) = (
            card.axis(0).unwrap().status().unwrap().raw.cmd_pos,
            card.axis(1).unwrap().status().unwrap().raw.cmd_pos,
        );
        worst = worst.max(((x + r).hypot(y) - r).abs());
        chords.push((x - prev.0).hypot(y - prev.1) * 10_000.0);
        prev = (x, y);
    }
    // The middle half of the lap is at the commanded feed (constant curvature, no chord limit).
    let n = chords.len();
    let fluct = chords[n / 4..3 * n / 4]
        .iter()
        .map(|v| (v - feed).abs() / feed)
        .fold(0.0, f64::max);
    m.wait(T).unwrap();
    assert!(worst < 1e-6, "radius error {worst}");
    assert!(fluct <= 1e-4, "feed fluctuation {fluct}");
    let end = (
        card.axis(0).unwrap().status().unwrap().raw.cmd_pos,
        card.axis(1).unwrap().status().unwrap().raw.cmd_pos,
    );
    assert!(end.0.abs() < 1e-6 && end.1.abs() < 1e-6, "ended at {end:?}");
}

/// A path of more pieces than the card queues is streamed piece by piece.
#[test]
fn long_path_is_streamed_piece_by_piece() {
    let (card, g) = two_axis_group();
    let mut pieces = Vec::new();
    let mut at = [0.0, 0.0];
    for k in 0..40 {
        let next = [at[0] + 1_000.0, if k % 2 == 0 { 800.0 } else { 0.0 }];
        let mid = [(at[0] + next[0]) / 2.0, 1_500.0];
        let ctrl = [at[0], at[1], mid[0], mid[1], next[0], next[1]];
        pieces.push(
            Nurbs::new(
                2,
                2,
                &ctrl,
                &[1.0, 0.8, 1.0],
                &clamped_uniform_knots(3, 2).unwrap(),
            )
            .unwrap(),
        );
        at = next;
    }
    let last = g
        .move_nurbs_path(&pieces, &NurbsFeed::new(50_000.0, 1e6, 1e8), T)
        .unwrap();
    last.wait(T).unwrap();
    let x = card.axis(0).unwrap().status().unwrap().raw.cmd_pos;
    assert!((x - 40_000.0).abs() < 1e-6, "ended at x = {x}");
}

/// Send a raw NURBS transfer and return the nack of the first refused entry.
fn raw_nurbs(card: &Card, header: [f64; 8], flags: u32, stream: &[f64]) -> Option<NackCode> {
    let send = |c: Command| card.wait_ack(card.send_raw(c).unwrap()).unwrap().err();
    let mut b = Command::new(Opcode::NurbsBegin, 0).with_args(&header);
    b.flags = flags;
    if let Some(e) = send(b) {
        return Some(e);
    }
    for (k, chunk) in stream.chunks(12).enumerate() {
        let mut args = vec![(k * 12) as f64, chunk.len() as f64];
        args.extend_from_slice(chunk);
        if let Some(e) = send(Command::new(Opcode::NurbsData, 0).with_args(&args)) {
            return Some(e);
        }
    }
    send(Command::new(Opcode::NurbsEnd, 0))
}

#[test]
fn every_bad_curve_gets_its_own_nack() {
    let (card, _g) = two_axis_group();
    // A good cubic through 5 points starting at the origin: points, weights, knots.
    let pts = [
        0.0, 0.0, 1000.0, 0.0, 2000.0, 500.0, 3000.0, 0.0, 4000.0, 0.0,
    ];
    let w = [1.0; 5];
    let knots = [0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
    let hdr = |deg: f64, n: f64, nk: f64| [deg, n, nk, 1e4, 1e6, 1e8, 1.0, 0.0];
    let stream = |p: &[f64], w: &[f64], k: &[f64]| [p, w, k].concat();
    let mut seen = Vec::new();
    let mut expect = |want: NackCode, got: Option<NackCode>| {
        assert_eq!(got, Some(want));
        seen.push(want);
    };
    expect(
        NackCode::NurbsDegree,
        raw_nurbs(&card, hdr(6.0, 5.0, 9.0), 0, &[]),
    );
    expect(
        NackCode::NurbsCtrlCount,
        raw_nurbs(&card, hdr(3.0, 3.0, 7.0), 0, &[]),
    );
    expect(
        NackCode::NurbsKnotCount,
        raw_nurbs(&card, hdr(3.0, 5.0, 10.0), 0, &[]),
    );
    let mut k = knots;
    k[5] = 0.4;
    expect(
        NackCode::NurbsKnotsDecreasing,
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pts, &w, &k)),
    );
    let k = [0.0, 0.0, 0.0, 0.1, 0.5, 1.0, 1.0, 1.0, 1.0]; // start knot repeated 3 times, not 4
    expect(
        NackCode::NurbsNotClamped,
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pts, &w, &k)),
    );
    // An interior knot of multiplicity 4 > degree 3 (7 control points).
    let pts7 = [
        0.0, 0.0, 500.0, 0.0, 1000.0, 0.0, 1500.0, 300.0, 2000.0, 0.0, 2500.0, 0.0, 3000.0, 0.0,
    ];
    let k7 = [0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
    let mut big = hdr(3.0, 7.0, 11.0);
    big[1] = 7.0;
    expect(
        NackCode::NurbsKnotMultiplicity,
        raw_nurbs(&card, big, 0, &stream(&pts7, &[1.0; 7], &k7)),
    );
    let mut ww = w;
    ww[2] = 0.0;
    expect(
        NackCode::NurbsWeight,
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pts, &ww, &knots)),
    );
    let mut ww = w;
    ww[1] = f64::NAN;
    assert_eq!(
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pts, &ww, &knots)),
        Some(NackCode::NurbsWeight)
    );
    let mut pp = pts;
    pp[3] = f64::INFINITY;
    expect(
        NackCode::NurbsPoint,
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pp, &w, &knots)),
    );
    let mut pp = pts;
    pp[0] = 5000.0; // does not start at the group's position
    expect(
        NackCode::NurbsStart,
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pp, &w, &knots)),
    );
    expect(
        NackCode::NurbsZeroLength,
        raw_nurbs(
            &card,
            hdr(3.0, 5.0, 9.0),
            0,
            &stream(&[0.0; 10], &w, &knots),
        ),
    );
    // Sequence: data with no transfer open, data out of order, end with data missing.
    expect(
        NackCode::NurbsSequence,
        card.wait_ack(
            card.send_raw(Command::new(Opcode::NurbsData, 0).with_args(&[0.0, 1.0, 0.0]))
                .unwrap(),
        )
        .unwrap()
        .err(),
    );
    let b = Command::new(Opcode::NurbsBegin, 0).with_args(&hdr(3.0, 5.0, 9.0));
    assert_eq!(card.wait_ack(card.send_raw(b).unwrap()).unwrap(), Ok(()));
    assert_eq!(
        card.wait_ack(
            card.send_raw(Command::new(Opcode::NurbsData, 0).with_args(&[12.0, 1.0, 0.0]))
                .unwrap()
        )
        .unwrap(),
        Err(NackCode::NurbsSequence)
    );
    assert_eq!(
        card.wait_ack(card.send_raw(Command::new(Opcode::NurbsEnd, 0)).unwrap())
            .unwrap(),
        Err(NackCode::NurbsSequence)
    );
    // Saturation-aware feed on axes without PD+.
    assert_eq!(
        raw_nurbs(
            &card,
            [3.0, 5.0, 9.0, 1e4, 1e6, 1e8, 1.0, 0.8],
            motioncard::proto::move_flags::NURBS_SATURATION,
            &[]
        ),
        Some(NackCode::IncompatibleMode)
    );
    // A one-axis group cannot run a curve.
    let g1 = card.group(1).unwrap();
    card.axis(5).unwrap().enable().unwrap();
    g1.configure(&GroupSettings::new(&[5])).unwrap();
    g1.enable().unwrap();
    let mut b = Command::new(Opcode::NurbsBegin, 1).with_args(&hdr(3.0, 5.0, 9.0));
    b.flags = 0;
    expect(
        NackCode::NurbsDimension,
        card.wait_ack(card.send_raw(b).unwrap()).unwrap().err(),
    );
    // The good curve is accepted and runs to its end.
    assert_eq!(
        raw_nurbs(&card, hdr(3.0, 5.0, 9.0), 0, &stream(&pts, &w, &knots)),
        None
    );
    for code in NackCode::ALL
        .iter()
        .filter(|c| (48..64).contains(&(**c as i32)))
    {
        assert!(seen.contains(code), "{code:?} never provoked");
    }
    // Nothing moved for any refused curve; the good one ends at its last control point.
    card.group(0).unwrap().wait_done(T).ok();
    let sim = card.sim().unwrap();
    sim.step(20_000);
    let x = card.axis(0).unwrap().status().unwrap().raw.cmd_pos;
    assert!((x - 4000.0).abs() < 1e-6, "x = {x}");
    assert_eq!(
        card.group(0).unwrap().status().unwrap().0,
        GroupState::Standby
    );
    let _ = ErrorKind::NurbsStart;
}
