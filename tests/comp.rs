//! Layout 1.9: leadscrew pitch-error and backlash compensation on the stepped card, against a
//! plant whose load sits behind a leadscrew with a pitch error curve and a dead band
//! (`card_emu::plant::leadscrew`). Moves to several targets from both directions end with the
//! load within one count of the target with the compensation table, and off by the plant's
//! error (the pitch error at the target, ∓ half the backlash) without it. The errors are
//! printed: `cargo test --release --test comp -- --nocapture`.
mod common;

use card_emu::plant::leadscrew::Leadscrew;
use common::stepped_card_with;
use motioncard_sdk::{Card, CompPoint, Compensation, EmuOptions, ErrorKind, MoveLimits};
use std::time::Duration;

const RATE: u32 = 10_000;
const BACKLASH: f64 = 8.0;
const LONG: Duration = Duration::from_secs(30);

/// The plant's pitch error (motor counts, counts): up to ±12 counts over 40,000.
fn pitch_error() -> Vec<(f64, f64)> {
    [
        (0.0, 0.0),
        (5_000.0, 6.0),
        (10_000.0, 11.5),
        (15_000.0, 4.0),
        (20_000.0, -3.5),
        (25_000.0, -12.0),
        (30_000.0, -7.0),
        (35_000.0, 2.5),
        (40_000.0, 5.0),
    ]
    .to_vec()
}

/// The table a user measures for it: the correction is minus the error.
fn table() -> Compensation {
    Compensation {
        points: pitch_error()
            .iter()
            .map(|&(x, e)| CompPoint::new(x, -e))
            .collect(),
        bidirectional: false,
        backlash: BACKLASH,
        bound: 20.0,
        ramp_velocity: 2_000.0,
        ramp_acceleration: 2e6,
    }
}

/// Targets, each reached from the side the move before leaves it on: forward, reverse, ...
const TARGETS: [f64; 8] = [
    9_000.0, 12_345.0, 7_500.0, 26_000.0, 18_200.0, 33_333.0, 3_100.0, 29_000.0,
];

fn card() -> Card {
    let card = stepped_card_with(EmuOptions::new(1, RATE));
    card.sim().unwrap().with_emulator(|e| {
        e.set_leadscrew(0, Some(Leadscrew::new(pitch_error(), BACKLASH)));
    });
    let axis = card.axis(0).unwrap();
    axis.enable().unwrap();
    // The table is in the homed frame: the shaft's 0 is the position 0.
    axis.set_position(0.0, false).unwrap();
    card
}

fn load(card: &Card) -> f64 {
    card.sim()
        .unwrap()
        .with_emulator(|e| e.load_position(0).unwrap())
}

/// Each target's load error after the move to it and 20 ms at rest: load − (target + 0.5).
/// The encoder reads the shaft's count (its floor), so a motor held at count `n` stands
/// somewhere in `[n, n + 1)`: the load's error is taken from that cell's middle, as the card's
/// compare and probe positions are.
fn run(card: &Card) -> Vec<(f64, f64, bool)> {
    let axis = card.axis(0).unwrap();
    let lim = MoveLimits::new(2e5, 2e6, 1e8);
    let mut out = Vec::new();
    let mut at = 0.0;
    for &t in &TARGETS {
        axis.move_absolute(t, &lim).unwrap().wait(LONG).unwrap();
        card.sim().unwrap().step(200);
        out.push((t, load(card) - (t + 0.5), t > at));
        at = t;
    }
    out
}

#[test]
fn the_load_reaches_the_target_within_one_count_with_compensation_and_misses_without() {
    let plain = card();
    let without = run(&plain);

    let comp = card();
    comp.axis(0).unwrap().set_compensation(&table()).unwrap();
    let with = run(&comp);

    let screw = Leadscrew::new(pitch_error(), BACKLASH);
    println!("target    dir  error without  plant's error  error with");
    for ((t, e0, fwd), (_, e1, _)) in without.iter().zip(&with) {
        // Without: the pitch error at the target, the load lagging half the band behind.
        let plant = screw.error_at(*t)
            + if *fwd {
                -BACKLASH / 2.0
            } else {
                BACKLASH / 2.0
            };
        println!(
            "{t:>8.0}  {}  {e0:>13.2}  {plant:>13.2}  {e1:>10.3}",
            if *fwd { "fwd" } else { "rev" }
        );
        // (The motor itself ends within a count of its reference, on the encoder's grid.)
        assert!(
            (e0 - plant).abs() <= 1.0,
            "{t}: without {e0}, plant {plant}"
        );
        assert!(
            e0.abs() > 2.0,
            "{t}: the plant's error is too small to show: {e0}"
        );
        assert!(
            e1.abs() <= 1.0,
            "{t}: with compensation the load is off by {e1}"
        );
    }
    // The status has both positions: the commanded one (the load's target) and the motor's.
    let s = comp.axis(0).unwrap().status().unwrap();
    let t = *TARGETS.last().unwrap();
    assert_eq!(s.command_position, t);
    let want = t - screw.error_at(t) + BACKLASH / 2.0;
    assert!(
        (s.compensated_position - want).abs() < 0.1,
        "compensated {} vs {want}",
        s.compensated_position
    );
    assert!(
        (s.actual_position - t).abs() <= 1.0,
        "{}",
        s.actual_position
    );
    // The worst of each, for the record.
    let worst = |v: &[(f64, f64, bool)]| v.iter().fold(0.0f64, |m, e| m.max(e.1.abs()));
    println!(
        "worst load error: {:.2} counts without, {:.3} with",
        worst(&without),
        worst(&with)
    );
}

#[test]
fn the_table_reads_back_as_loaded_and_refusals_change_nothing() {
    let card = card();
    let axis = card.axis(0).unwrap();
    assert_eq!(axis.compensation().unwrap(), None);
    let mut big = table();
    big.bidirectional = true;
    big.points = (0..200)
        .map(|i| CompPoint {
            position: i as f64 * 100.0,
            forward: (i % 7) as f64 * 0.5,
            reverse: (i % 5) as f64 * -0.5,
        })
        .collect();
    axis.set_compensation(&big).unwrap();
    assert_eq!(axis.compensation().unwrap(), Some(big.clone()));

    let kind = |c: &Compensation| axis.set_compensation(c).unwrap_err().kind();
    let mut bad = big.clone();
    bad.points[57].position = bad.points[56].position;
    assert_eq!(kind(&bad), ErrorKind::CompOrder);
    let mut bad = big.clone();
    bad.points[3].forward = f64::NAN;
    assert_eq!(kind(&bad), ErrorKind::NotFinite);
    let mut bad = big.clone();
    bad.points[3].forward = 16.5; // + 4 of backlash: beyond the bound of 20
    assert_eq!(kind(&bad), ErrorKind::CompBound);
    let mut bad = big.clone();
    bad.points = (0..257).map(|i| CompPoint::new(i as f64, 0.0)).collect();
    assert_eq!(kind(&bad), ErrorKind::CompTable);
    let mut bad = big.clone();
    bad.ramp_velocity = 0.0;
    assert_eq!(kind(&bad), ErrorKind::CompTable);
    let mut bad = table();
    bad.points[2].reverse = 1.0; // a one-column table with two columns
    assert_eq!(kind(&bad), ErrorKind::CompBound);
    // Moving: the card refuses (CompBusy), and the table stays.
    let m = axis
        .move_absolute(30_000.0, &MoveLimits::new(2e4, 2e5, 1e7))
        .unwrap();
    card.sim().unwrap().step(100);
    assert_eq!(kind(&table()), ErrorKind::CompBusy);
    assert_eq!(
        axis.clear_compensation().unwrap_err().kind(),
        ErrorKind::CompBusy
    );
    m.wait(LONG).unwrap();
    assert_eq!(axis.compensation().unwrap(), Some(big));
    // Cleared: none read back.
    axis.clear_compensation().unwrap();
    assert_eq!(axis.compensation().unwrap(), None);
}

#[test]
fn a_negative_scale_keeps_the_table_in_user_units() {
    let card = card();
    let axis = card.axis(0).unwrap();
    axis.set_scale(-1000.0).unwrap();
    let mut c = table();
    c.bidirectional = true;
    c.points = vec![
        CompPoint {
            position: -30.0,
            forward: 0.004,
            reverse: -0.002,
        },
        CompPoint {
            position: -10.0,
            forward: 0.001,
            reverse: 0.003,
        },
    ];
    c.bound = 0.02;
    c.backlash = 0.004;
    c.ramp_velocity = 2.0;
    c.ramp_acceleration = 2e3;
    axis.set_compensation(&c).unwrap();
    let back = axis.compensation().unwrap().unwrap();
    assert_eq!(back.points.len(), 2);
    for (a, b) in back.points.iter().zip(&c.points) {
        assert!((a.position - b.position).abs() < 1e-12);
        assert!((a.forward - b.forward).abs() < 1e-12);
        assert!((a.reverse - b.reverse).abs() < 1e-12);
    }
    assert!((back.backlash - c.backlash).abs() < 1e-15);
}

/// `[axis.N.compensation]` in the configuration file: a card's table saved, loaded into another
/// card (read back equal, no difference left), and a file with positions out of order refused
/// naming the section, nothing applied.
#[test]
fn the_table_goes_through_the_configuration_file() {
    let a = card();
    a.axis(0).unwrap().set_compensation(&table()).unwrap();
    let text = a.save_config().unwrap();
    assert!(text.contains("[axis.0.compensation]"), "{text}");
    let b = card();
    assert_eq!(b.axis(0).unwrap().compensation().unwrap(), None);
    let report = b.load_config(&text, "a.toml").unwrap();
    assert!(
        report.applied.iter().any(|k| k == "axis.0.compensation"),
        "{:?}",
        report.applied
    );
    let back = b.axis(0).unwrap().compensation().unwrap().unwrap();
    assert_eq!(back, a.axis(0).unwrap().compensation().unwrap().unwrap());
    assert!(b.diff_config(&text, "a.toml").unwrap().is_empty());

    let c = card();
    let mut t = table();
    t.points.swap(0, 1);
    let out_of_order = text.replace(
        &format!(
            "{:?}",
            [
                t.points[1].position,
                t.points[1].forward,
                t.points[1].reverse
            ]
        ),
        &format!(
            "{:?}",
            [
                t.points[0].position,
                t.points[0].forward,
                t.points[0].reverse
            ]
        ),
    );
    assert_ne!(out_of_order, text);
    match c.load_config(&out_of_order, "bad.toml").unwrap_err() {
        motioncard_sdk::Error::ConfigFile { key, .. } => assert_eq!(key, "axis.0.compensation"),
        e => panic!("{e}"),
    }
    assert_eq!(c.axis(0).unwrap().compensation().unwrap(), None);
}

/// Layout 1.10: the scope samples the compensated position (`Signal::CompPos`, counts): on
/// every tick of a move with the table loaded it is the status's, and it differs from the
/// commanded position by the correction (a count or more somewhere on the move).
#[test]
fn the_scope_samples_the_compensated_position() {
    use motioncard_sdk::{ScopeSettings, Signal, Source};
    let card = card();
    let axis = card.axis(0).unwrap();
    axis.set_compensation(&table()).unwrap();
    let settings = ScopeSettings::new(
        &[
            Source::axis(Signal::CmdPos, 0),
            Source::axis(Signal::CompPos, 0),
        ],
        2_000,
    );
    let cap = card
        .scope()
        .capture(&settings, LONG, |_| {
            axis.move_absolute(20_000.0, &MoveLimits::new(2e5, 2e6, 1e8))
                .map(|_| ())
        })
        .unwrap();
    assert_eq!(cap.samples.len(), 2_000);
    let largest = cap
        .samples
        .iter()
        .map(|s| (s.value[1] - s.value[0]).abs())
        .fold(0.0, f64::max);
    assert!(largest >= 1.0, "correction never above a count: {largest}");
    // At rest after the move, the last sample is the status's.
    card.sim().unwrap().step(20_000);
    let cap = card
        .scope()
        .capture(&ScopeSettings::new(&settings.channels, 1), LONG, |_| Ok(()))
        .unwrap();
    let s = axis.status().unwrap();
    assert_eq!(cap.samples[0].value[1], s.raw.comp_pos);
    assert_eq!(cap.samples[0].value[0], s.raw.cmd_pos);
}
