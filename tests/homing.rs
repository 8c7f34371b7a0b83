//! Homing on the stepped card and its emulated plant (deterministic): every CiA 402 method the
//! card has, from several start positions (both sides of the switch, on it, on a limit
//! switch), ends with the same home point within ±1 count, the position the convention says
//! (the home point reads MC_Home's position + the home offset), and the homed bit; soft limits
//! take effect once homed. The failures: a missing switch, the maximum distance, the timeout,
//! no index, a move during homing, a halt or stop during homing, an unexpected limit switch.
//!
//! Each method's test prints its repeatability (the spread of the home point over the starts,
//! counts) and the time it took (emulated seconds, per start): `cargo test --test homing --
//! --nocapture`.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, Card, EmuOptions, EndStops, ErrorKind, EventKind, Faults, HomeSwitch, HomingError,
    HomingFlags, HomingSettings, IndexPulse, MoveLimits, SafetySettings, Status, StopReason,
    Switches,
};
use std::time::Duration;

const RATE: u32 = 10_000;
/// What MC_Home names the home point, and the home offset added to it.
const HOME: f64 = 1_000.0;
const OFFSET: f64 = 250.0;
const LONG: Duration = Duration::from_secs(120);

/// The lower and upper edges of the home switch, and the limit switches (between counts, so a
/// count is never on an edge).
const LOWER: f64 = 5_000.5;
const UPPER: f64 = 8_000.5;
const LIMIT: f64 = 35_000.5;
/// The mechanical end stops beyond the limit switches.
const END: f64 = 40_500.5;

fn fast() -> MoveLimits {
    MoveLimits::new(2e5, 2e6, 1e8)
}

/// A one-axis stepped card with the default plant (10,000 counts/rev, an index pulse per
/// revolution at 0 and its multiples) and its end stops.
fn card_with(index: IndexPulse) -> Card {
    let mut opts = EmuOptions::new(1, RATE);
    opts.index[0] = index;
    let card = stepped_card_with(opts);
    card.sim().unwrap().with_emulator(|e| {
        e.motor_mut(0).unwrap().end_stops = EndStops {
            neg: -END,
            pos: END,
        }
    });
    card.axis(0).unwrap().enable().unwrap();
    card
}

fn one_axis() -> Card {
    card_with(IndexPulse::default())
}

fn status(card: &Card) -> Status {
    card.axis(0).unwrap().status().unwrap()
}

fn set_switches(card: &Card, sw: Switches) {
    card.sim()
        .unwrap()
        .with_emulator(|e| e.faults().set_switches(0, sw));
}

fn configure(card: &Card, method: i32, change: impl FnOnce(&mut HomingSettings)) {
    let mut h = HomingSettings {
        method,
        home_offset: OFFSET,
        ..HomingSettings::default()
    };
    change(&mut h);
    card.axis(0).unwrap().configure_homing(&h).unwrap();
}

/// Move to `start` with no switches on the machine (so none trips on the way), then put them
/// there: the axis may then stand on one.
fn place(card: &Card, start: f64, sw: Switches) {
    set_switches(card, Switches::default());
    let ax = card.axis(0).unwrap();
    let to = start + (status(card).actual_position - status(card).raw.encoder as f64);
    ax.move_absolute(to, &fast()).unwrap().wait(LONG).unwrap();
    set_switches(card, sw);
    card.sim().unwrap().step(10);
}

/// One homing: the home point's raw count (what reads HOME + OFFSET now), the emulated time it
/// took, and the status after.
struct Homed {
    raw: f64,
    seconds: f64,
    status: Status,
}

fn home(card: &Card) -> Homed {
    let ax = card.axis(0).unwrap();
    let t0 = status(card).raw.tick;
    let m = ax.home(HOME).unwrap();
    assert_eq!(status(card).state, AxisState::Homing);
    assert!(!status(card).homed(), "homed while homing");
    let at = m.wait(LONG).unwrap();
    let s = status(card);
    let frame = s.raw.act_pos - s.raw.encoder as f64;
    // The home point reads HOME + OFFSET: its raw count.
    let raw = HOME + OFFSET - frame;
    assert_eq!(at, s.actual_position);
    Homed {
        raw,
        seconds: (s.raw.tick - t0) as f64 / RATE as f64,
        status: s,
    }
}

/// The switches of a method's world: limit switches at ±35,000.5, and the home switch its
/// geometry needs (active above 5,000.5 for 3, 4, 19, 20; below it for 5, 6, 21, 22; between
/// 5,000.5 and 8,000.5 for 7–14, 23–30; none for the limit methods).
fn switches(method: i32) -> Switches {
    let home = match method.rem_euclid(16) {
        3 | 4 => HomeSwitch::Above(LOWER),
        5 | 6 => HomeSwitch::Below(LOWER),
        7..=14 => HomeSwitch::Between {
            lower: LOWER,
            upper: UPPER,
        },
        _ => HomeSwitch::None,
    };
    Switches::limits(-LIMIT, LIMIT).with_home(home)
}

/// The home point each method must find (raw count), in [`switches`]: an edge at x.5 is count
/// x from either side; the limit switches' edges are counts -35,001 and 35,000; index pulses at
/// the multiples of 10,000.
fn expected(method: i32) -> f64 {
    match method {
        1 => -30_000.0,
        2 => 30_000.0,
        17 => -35_001.0,
        18 => 35_000.0,
        3 | 6 | 7 | 9 | 12 | 14 => 0.0,
        4 | 5 | 8 | 10 | 11 | 13 => 10_000.0,
        19..=24 | 29 | 30 => 5_000.0,
        25..=28 => 8_000.0,
        _ => unreachable!(),
    }
}

/// Home with `method` from every start; check the home point (`expect` of the raw count the
/// axis stood at), the position, the homed bit; print the spread and the times.
fn repeatable(method: i32, starts: &[f64], expect: impl Fn(f64) -> f64, sw: Switches) {
    let card = one_axis();
    configure(&card, method, |_| {});
    let mut points = Vec::new();
    let mut times = Vec::new();
    for &start in starts {
        place(&card, start, sw);
        let before = card.events_lost();
        let stood = status(&card).raw.encoder as f64;
        let h = home(&card);
        let what = format!("method {method} from {start}");
        let want = expect(stood);
        assert!(
            (h.raw - want).abs() <= 1.0,
            "{what}: home point at raw {} (expected {want})",
            h.raw
        );
        // The convention: the home point reads HOME + OFFSET, and the axis ends there.
        assert!(
            (h.status.actual_position - (HOME + OFFSET)).abs() <= 1.0,
            "{what}: at {}",
            h.status.actual_position
        );
        assert!(h.status.homed(), "{what}: not homed");
        assert_eq!(h.status.state, AxisState::Standstill, "{what}");
        assert_eq!(h.status.stop_reason(), Some(StopReason::Done), "{what}");
        assert!(
            !h.status.faults.intersects(
                Faults::HARD_LIMIT_POS | Faults::HARD_LIMIT_NEG | Faults::FOLLOWING_ERROR
            ),
            "{what}: {:?}",
            h.status.faults
        );
        assert_eq!(card.events_lost(), before);
        points.push(h.raw - want);
        times.push(h.seconds);
    }
    // No safety stop on the way (the limit switches the method reverses at are its own).
    let safety: Vec<_> = events(&card)
        .into_iter()
        .filter(|e| e.kind == EventKind::SafetyStop)
        .collect();
    assert!(safety.is_empty(), "method {method}: {safety:?}");
    let spread = points.iter().cloned().fold(f64::MIN, f64::max)
        - points.iter().cloned().fold(f64::MAX, f64::min);
    println!(
        "method {method:>3}: spread {spread:.0} counts over {} starts; time {} s",
        starts.len(),
        times
            .iter()
            .map(|t| format!("{t:.2}"))
            .collect::<Vec<_>>()
            .join(" / ")
    );
}

fn events(card: &Card) -> Vec<motioncard_sdk::CardEvent> {
    let mut out = Vec::new();
    while let Ok(Some(e)) = card.next_event(Duration::ZERO) {
        out.push(e);
    }
    out
}

/// Below the switch, on it, above it, on the negative and on the positive limit switch.
const STARTS: [f64; 5] = [-20_000.0, 6_500.0, 20_000.0, -35_500.0, 35_500.0];

macro_rules! switch_methods {
    ($($name:ident = $m:literal;)+) => {$(
        #[test]
        fn $name() {
            repeatable($m, &STARTS, |_| expected($m), switches($m));
        }
    )+};
}

switch_methods! {
    method_01_negative_limit_and_index = 1;
    method_02_positive_limit_and_index = 2;
    method_03_switch_above_index_below = 3;
    method_04_switch_above_index_above = 4;
    method_05_switch_below_index_above = 5;
    method_06_switch_below_index_below = 6;
    method_07_lower_edge_index_below = 7;
    method_08_lower_edge_index_above = 8;
    method_09_upper_edge_index_below = 9;
    method_10_upper_edge_index_above = 10;
    method_11_upper_edge_index_above_start_negative = 11;
    method_12_upper_edge_index_below_start_negative = 12;
    method_13_lower_edge_index_above_start_negative = 13;
    method_14_lower_edge_index_below_start_negative = 14;
    method_17_negative_limit = 17;
    method_18_positive_limit = 18;
    method_19_switch_above_from_above = 19;
    method_20_switch_above_from_below = 20;
    method_21_switch_below_from_below = 21;
    method_22_switch_below_from_above = 22;
    method_23_lower_edge_from_above = 23;
    method_24_lower_edge_from_below = 24;
    method_25_upper_edge_from_above = 25;
    method_26_upper_edge_from_below = 26;
    method_27_upper_edge_from_below_start_negative = 27;
    method_28_upper_edge_from_above_start_negative = 28;
    method_29_lower_edge_from_below_start_negative = 29;
    method_30_lower_edge_from_above_start_negative = 30;
}

/// Methods 33 and 34: the next index pulse down or up, from starts in one revolution.
#[test]
fn method_33_index_negative() {
    let sw = Switches::limits(-LIMIT, LIMIT);
    repeatable(33, &[1_000.0, 4_321.0, 9_800.0], |_| 0.0, sw);
}

#[test]
fn method_34_index_positive() {
    let sw = Switches::limits(-LIMIT, LIMIT);
    repeatable(34, &[1_000.0, 4_321.0, 9_800.0], |_| 10_000.0, sw);
}

/// Methods 35 and 37: the current position is the home point; nothing moves.
fn current_position(method: i32) {
    let sw = Switches::limits(-LIMIT, LIMIT);
    repeatable(method, &[-1_234.0, 0.0, 22_222.0], |stood| stood, sw);
}

#[test]
fn method_35_current_position() {
    current_position(35);
}

#[test]
fn method_37_current_position() {
    current_position(37);
}

/// The hard-stop methods on a machine without limit switches: -3/-4 home where the axis
/// stalls on the end stop (counts -40,501 and 40,500), -1/-2 on the first index pulse away
/// from it (-40,000 and 40,000). The stop is approached at the creep velocity (1,000
/// counts/s): the starts are within 17,000 counts of it.
#[test]
fn hard_stop_methods() {
    for (method, point) in [
        (-1, -40_000.0),
        (-2, 40_000.0),
        (-3, -40_501.0),
        (-4, 40_500.0),
    ] {
        let dir: f64 = if point < 0.0 { -1.0 } else { 1.0 };
        let starts = [24_000.0 * dir, 31_000.0 * dir, 38_500.0 * dir];
        repeatable(method, &starts, |_| point, Switches::default());
    }
}

/// Soft limits: not in force before the axis is homed (its positions mean nothing yet), in
/// force once it is. MC_SetPosition also homes, and a set position never looks like an encoder
/// jump.
#[test]
fn soft_limits_hold_once_homed_and_set_position_homes() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    ax.configure_safety(&SafetySettings {
        soft_limits: Some((-5_000.0, 5_000.0)),
        ..Default::default()
    })
    .unwrap();
    assert!(!status(&card).homed());
    ax.move_absolute(8_000.0, &fast())
        .unwrap()
        .wait(LONG)
        .unwrap();
    ax.move_absolute(0.0, &fast()).unwrap().wait(LONG).unwrap();
    configure(&card, 34, |h| h.home_offset = 0.0);
    let m = ax.home(0.0).unwrap();
    // Homing clears the bit while it runs.
    assert!(!status(&card).homed());
    m.wait(LONG).unwrap();
    assert!(status(&card).homed());
    assert_eq!(
        ax.move_absolute(8_000.0, &fast()).unwrap_err().kind(),
        ErrorKind::SoftLimit
    );
    ax.move_absolute(4_000.0, &fast())
        .unwrap()
        .wait(LONG)
        .unwrap();
    // MC_SetPosition: a jump of a million counts in the position, none in the raw count.
    let raw = status(&card).raw.encoder;
    ax.set_position(1e6, false).unwrap();
    let s = status(&card);
    assert_eq!(s.actual_position, 1e6);
    assert_eq!(s.raw.encoder, raw);
    assert!(s.homed());
    card.sim().unwrap().step(1_000);
    let s = status(&card);
    assert_eq!(s.state, AxisState::Standstill);
    assert!(!s.faults.contains(Faults::ENCODER), "{:?}", s.faults);
    // Beyond the soft limits now: moves further out are refused, back in allowed.
    assert_eq!(
        ax.move_relative(10.0, &fast()).unwrap_err().kind(),
        ErrorKind::SoftLimit
    );
    let here = status(&card).actual_position;
    ax.set_position(-1_000.0, true).unwrap();
    assert_eq!(status(&card).actual_position, here - 1_000.0);
    // Not while moving.
    ax.set_position(0.0, false).unwrap();
    let m = ax.move_absolute(3_000.0, &fast()).unwrap();
    assert_eq!(
        ax.set_position(0.0, false).unwrap_err().kind(),
        ErrorKind::InvalidState
    );
    m.wait(LONG).unwrap();
}

/// The state changes and events of a homing: Standstill -> Homing -> Standstill, motion done
/// with the MC_Home's seq at the position the home point reads.
#[test]
fn homing_reports_its_states_and_motion_done() {
    let card = one_axis();
    configure(&card, 20, |_| {});
    place(&card, -3_000.0, switches(20));
    events(&card);
    let m = card.axis(0).unwrap().home(HOME).unwrap();
    let at = m.wait(LONG).unwrap();
    let ev = events(&card);
    let states: Vec<(i32, f64)> = ev
        .iter()
        .filter(|e| e.kind == EventKind::StateChanged)
        .map(|e| (e.code, e.value))
        .collect();
    assert_eq!(
        states,
        [
            (
                AxisState::Homing as i32,
                AxisState::Standstill as u32 as f64
            ),
            (
                AxisState::Standstill as i32,
                AxisState::Homing as u32 as f64
            )
        ]
    );
    let done: Vec<_> = ev
        .iter()
        .filter(|e| e.kind == EventKind::MotionDone)
        .collect();
    assert_eq!(done.len(), 1);
    assert_eq!(done[0].seq, m.seq());
    assert_eq!(done[0].value, at);
    assert!(
        ev.iter().all(|e| e.kind != EventKind::InVelocity),
        "homing's searches report no InVelocity"
    );
}

fn failed(card: &Card) -> (HomingError, f64) {
    let e = card
        .axis(0)
        .unwrap()
        .home(HOME)
        .unwrap()
        .wait(LONG)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::HomingFailed, "{e}");
    match e {
        motioncard_sdk::Error::HomingFailed {
            error: Some(why),
            at,
            ..
        } => (why, at),
        e => panic!("{e}"),
    }
}

fn assert_stopped_not_homed(card: &Card, what: &str) {
    let s = status(card);
    assert_eq!(s.state, AxisState::Standstill, "{what}");
    assert!(!s.homed(), "{what}");
    assert_eq!(s.stop_reason(), Some(StopReason::HomingFailed), "{what}");
    assert!(s.command_velocity == 0.0, "{what}");
    // It stays where it stopped.
    let p = s.actual_position;
    card.sim().unwrap().step(5_000);
    assert!(
        (status(card).actual_position - p).abs() <= 1.0,
        "{what}: moved on"
    );
}

/// The home switch is missing: the search reverses at the limit switch ahead (CiA 402) and
/// fails at the other one; the axis stops short of the end stop. Without limit switches the
/// maximum distance ends it.
#[test]
fn a_missing_switch_fails_and_the_axis_stops_within_its_limits() {
    let card = one_axis();
    configure(&card, 23, |_| {});
    place(&card, 0.0, Switches::limits(-LIMIT, LIMIT));
    let (why, at) = failed(&card);
    assert_eq!(why, HomingError::LimitReached);
    assert!(at <= -LIMIT + 1.0, "failed at {at}");
    assert_stopped_not_homed(&card, "limit");
    let s = status(&card);
    let raw = s.raw.encoder as f64;
    assert!(raw < -LIMIT && raw > -END + 1.0, "stopped at raw {raw}");
    assert!(events(&card)
        .iter()
        .any(|e| e.kind == EventKind::HomingFailed && e.code == HomingError::LimitReached as i32));

    let card = one_axis();
    configure(&card, 19, |h| h.max_distance = 30_000.0);
    let (why, _) = failed(&card);
    assert_eq!(why, HomingError::DistanceExceeded);
    assert_stopped_not_homed(&card, "distance");
    let raw = status(&card).raw.encoder as f64;
    assert!(
        raw.abs() > 30_000.0 && raw.abs() < 33_000.0,
        "stopped at {raw}"
    );
}

#[test]
fn timeout_and_no_index_fail_with_their_own_codes() {
    let card = one_axis();
    configure(&card, 19, |h| h.timeout = 0.3);
    let (why, _) = failed(&card);
    assert_eq!(why, HomingError::Timeout);
    assert_stopped_not_homed(&card, "timeout");

    // An encoder without index pulses, but configured with one.
    let card = card_with(IndexPulse {
        present: false,
        ..IndexPulse::default()
    });
    configure(&card, 34, |_| {});
    let (why, _) = failed(&card);
    assert_eq!(why, HomingError::NoIndex);
    assert_stopped_not_homed(&card, "no index");
    // Configured without one, an index method is refused.
    let ax = card.axis(0).unwrap();
    let h = HomingSettings {
        method: 34,
        flags: HomingFlags::MOVE_TO_HOME.bits(),
        ..HomingSettings::default()
    };
    assert_eq!(
        ax.configure_homing(&h).unwrap_err().kind(),
        ErrorKind::HomingMethod
    );
    for method in [0, 15, 16, 31, 32, 36, -5] {
        let h = HomingSettings {
            method,
            ..HomingSettings::default()
        };
        assert_eq!(
            ax.configure_homing(&h).unwrap_err().kind(),
            ErrorKind::HomingMethod,
            "{method}"
        );
    }
}

/// While homing: moves, jogs, velocity mode and another MC_Home are refused with their own
/// code; halt and stop abort it.
#[test]
fn moves_during_homing_are_refused_and_halt_or_stop_abort_it() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    configure(&card, 19, |_| {});
    let m = ax.home(HOME).unwrap();
    card.sim().unwrap().step(2_000);
    assert_eq!(status(&card).state, AxisState::Homing);
    for e in [
        ax.move_absolute(0.0, &fast()).map(|_| ()),
        ax.move_relative(10.0, &fast()).map(|_| ()),
        ax.jog(1_000.0).map(|_| ()),
        ax.home(0.0).map(|_| ()),
        ax.set_position(0.0, false),
    ] {
        assert_eq!(e.unwrap_err().kind(), ErrorKind::AxisHoming);
    }
    assert_eq!(status(&card).state, AxisState::Homing);
    let halt = ax.halt(1e6, 1e8).unwrap();
    let e = m.wait(Duration::ZERO).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Aborted);
    assert!(e.to_string().contains("Halt"), "{e}");
    halt.wait(LONG).unwrap();
    let s = status(&card);
    assert_eq!(s.state, AxisState::Standstill);
    assert!(!s.homed());

    let m = ax.home(HOME).unwrap();
    card.sim().unwrap().step(2_000);
    ax.stop(1e6, 1e8).unwrap().wait(LONG).unwrap();
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    assert_eq!(status(&card).state, AxisState::Stopping);
    ax.release_stop().unwrap();
    card.sim().unwrap().step(10);
    assert_eq!(status(&card).state, AxisState::Standstill);
    assert!(!status(&card).homed());
}

/// A limit switch a method has no use for (19 looks for a home switch only) is unexpected: the
/// safety layer stops the axis as always, and the homing is aborted.
#[test]
fn an_unexpected_limit_switch_still_stops_the_axis() {
    let card = one_axis();
    configure(&card, 19, |_| {});
    place(&card, 0.0, Switches::limits(-LIMIT, LIMIT));
    let e = card
        .axis(0)
        .unwrap()
        .home(HOME)
        .unwrap()
        .wait(LONG)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Aborted, "{e}");
    assert!(e.to_string().contains("limit switch"), "{e}");
    card.sim().unwrap().step(5_000);
    let s = status(&card);
    assert_eq!(s.state, AxisState::ErrorStop);
    assert_eq!(s.stop_reason(), Some(StopReason::HardLimitPos));
    assert!(!s.homed());
}

/// A hard-stop threshold the following-error limit would trip first is refused at MC_Home.
#[test]
fn a_hard_stop_threshold_beyond_the_following_error_limit_is_refused() {
    let card = one_axis();
    configure(&card, -3, |h| h.hard_stop_ferror = 5_000.0);
    assert_eq!(
        card.axis(0).unwrap().home(0.0).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    assert_eq!(status(&card).state, AxisState::Standstill);
}

/// Every homing nack (codes 64..79) has a command that provokes it.
#[test]
fn every_homing_nack_is_provoked() {
    use motioncard_sdk::{Error, NackCode};
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    let nack = |e: Error| match e {
        Error::Nack { code, .. } => code,
        e => panic!("{e}"),
    };
    let mut seen = Vec::new();
    let h = HomingSettings {
        method: 16,
        ..HomingSettings::default()
    };
    seen.push(nack(ax.configure_homing(&h).unwrap_err()));
    configure(&card, 19, |_| {});
    let m = ax.home(0.0).unwrap();
    seen.push(nack(ax.move_relative(1.0, &fast()).unwrap_err()));
    ax.halt(1e6, 1e8).unwrap();
    assert_eq!(m.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    for code in NackCode::ALL
        .iter()
        .filter(|c| (64..80).contains(&(**c as i32)))
    {
        assert!(seen.contains(code), "{code:?} never provoked");
    }
    assert_eq!(seen, [NackCode::HomingMethod, NackCode::AxisHoming]);
}
