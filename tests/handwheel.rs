//! The handwheel (layout 1.10, issue 35 part 6) on the stepped card and its emulated plant
//! (deterministic): an auxiliary encoder jogs an axis.
//!
//! - A detent moves the target by the ratio, exactly, forth and back; a new ratio on the
//!   running wheel goes on from where the target is, in the same motion.
//! - Spun ten times faster than the axis's jog velocity, the axis runs at its jog velocity
//!   within its acceleration and jerk (finite differences of the commanded position per tick,
//!   within 1.01 ×), and once the wheel stops it comes to rest within its reach (the stop
//!   distance from the jog velocity plus one tick at it) of where it was: the excess was
//!   dropped, nothing runs on; turning back acts at once.
//! - Once homed, the wheel stops the axis at a soft limit without a trip.
//! - Selecting from velocity mode aborts it and starts where the jog ramp stops; handing the
//!   input to another axis lets the first go on to its target, motion done; deselecting does
//!   the same; a halt or an e-stop ends it with its stop reason.
//! - The card refuses a bad input, ratio or detent, a grouped axis, a disabled one, and moves
//!   on an axis the wheel drives, each with its own code, changing nothing.
//!
//! The figures: `cargo test --release --test handwheel -- --nocapture`.
mod common;

use common::stepped_card_with;
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::{
    AxisState, Card, EmuOptions, ErrorKind, GroupSettings, Handwheel, MotionFlags, MoveLimits,
    NackCode, SafetySettings, StopCategory, StopReason, VelocityLimits,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const TS: f64 = 1.0 / RATE as f64;
const LONG: Duration = Duration::from_secs(60);
/// The default jog limits (`AxisSettings`'s reset values).
const VMAX: f64 = 50_000.0;
const AMAX: f64 = 500_000.0;
const JERK: f64 = 5e7;

fn card(axes: usize) -> Card {
    let card = stepped_card_with(EmuOptions::new(axes, RATE));
    for a in 0..axes {
        let ax = card.axis(a).unwrap();
        let s = ax.settings().unwrap();
        assert_eq!(
            (s.jog_max_vel, s.jog_accel, s.jog_jerk),
            (VMAX, AMAX, JERK),
            "the default jog limits"
        );
        ax.enable().unwrap();
    }
    card
}

fn turn(card: &Card, k: usize, counts: i64) {
    card.sim().unwrap().jump_aux(k, counts).unwrap();
}

fn spin(card: &Card, k: usize, counts_per_s: f64) {
    card.sim()
        .unwrap()
        .set_aux_velocity(k, counts_per_s)
        .unwrap();
}

fn step(card: &Card, n: u64) {
    card.sim().unwrap().step(n);
}

/// The stop distance from `VMAX` at `AMAX`, `JERK` (VMAX ≥ AMAX²/JERK) plus one tick at VMAX.
fn reach() -> f64 {
    VMAX * (VMAX / AMAX + AMAX / JERK) / 2.0 + VMAX * TS
}

/// The largest |first|, |second| and |third| finite difference of `x` per tick.
fn peaks(x: &[f64]) -> (f64, f64, f64) {
    let d1: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let d2: Vec<f64> = d1.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let d3: Vec<f64> = d2.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let max = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (max(&d1), max(&d2), max(&d3))
}

/// Step until the commanded position stood still for 100 ticks; it.
fn settle(card: &Card, a: usize) -> f64 {
    let ax = card.axis(a).unwrap();
    let mut last = f64::NAN;
    let mut still = 0;
    for _ in 0..200_000 {
        step(card, 1);
        let p = ax.status().unwrap().command_position;
        still = if p == last { still + 1 } else { 0 };
        last = p;
        if still == 100 {
            return p;
        }
    }
    panic!("axis {a} never came to rest");
}

#[test]
fn a_detent_moves_the_axis_by_the_ratio_exactly() {
    let card = card(1);
    let ax = card.axis(0).unwrap();
    let p0 = ax.status().unwrap().command_position;
    let m = ax.handwheel(&Handwheel::new(1).ratio(10)).unwrap();
    assert_eq!(ax.status().unwrap().state, AxisState::SynchronizedMotion);
    // 7 detents of 4 counts, ×10; the override (0 %: held) does not scale the wheel.
    ax.set_override(0.0).unwrap();
    turn(&card, 1, 28);
    assert_eq!(settle(&card, 0), p0 + 70.0);
    assert!(!ax.status().unwrap().motion.contains(MotionFlags::PAUSED));
    ax.set_override(1.0).unwrap();
    // Two counts: half a detent, half the ratio.
    turn(&card, 1, -2);
    assert_eq!(settle(&card, 0), p0 + 65.0);
    // ×100 from here, the same motion (the ack names the first selection's seq).
    let again = ax.handwheel(&Handwheel::new(1).ratio(100)).unwrap();
    assert_eq!(format!("{again:?}"), format!("{m:?}"));
    turn(&card, 1, -4 * 3);
    assert_eq!(settle(&card, 0), p0 + 65.0 - 300.0);
    // Forth and back by the same counts: the same target, to the bit.
    turn(&card, 1, 4 * 3);
    assert_eq!(settle(&card, 0), p0 + 65.0);
    // ×10 again, anchored at the target it has.
    ax.handwheel(&Handwheel::new(1).ratio(10)).unwrap();
    turn(&card, 1, 26);
    assert_eq!(settle(&card, 0), p0 + 65.0 + 65.0);
    ax.handwheel_off().unwrap();
    let at = m.wait(LONG).unwrap();
    assert!((at - (p0 + 130.0)).abs() <= 1.0, "{at}");
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
}

/// The wheel turned ten times faster than the axis may follow: the axis runs at its jog
/// velocity within its limits, and when the wheel stops it stops within its reach; the turns
/// beyond were dropped.
#[test]
fn spinning_beyond_the_limits_never_builds_a_backlog() {
    let card = card(1);
    let ax = card.axis(0).unwrap();
    let p0 = ax.status().unwrap().command_position;
    ax.handwheel(&Handwheel::new(0).ratio(100)).unwrap();
    // 20,000 counts/s = 5,000 detents/s ×100 = 500,000 counts/s: 10 × VMAX.
    spin(&card, 0, 20_000.0);
    let mut x = vec![p0];
    for _ in 0..5_000 {
        step(&card, 1);
        x.push(ax.status().unwrap().command_position);
    }
    spin(&card, 0, 0.0);
    let stopped_at = *x.last().unwrap();
    let mut t = 0;
    loop {
        step(&card, 1);
        t += 1;
        let s = ax.status().unwrap();
        x.push(s.command_position);
        if s.command_velocity == 0.0 && s.command_acceleration == 0.0 || t > 100_000 {
            break;
        }
    }
    let rest = *x.last().unwrap();
    let (v, a, j) = peaks(&x);
    let turned = 20_000.0 * 0.5 * 100.0 / 4.0;
    println!(
        "wheel: {turned} counts turned; axis: {:.1} counts, peak v {v:.1} a {a:.1} j {j:.4e}; \
         after the wheel stopped: {:.3} counts in {t} ticks (reach {:.3})",
        rest - p0,
        rest - stopped_at,
        reach()
    );
    assert!(v >= 0.999 * VMAX, "ran at its jog velocity: {v}");
    assert!(v <= 1.01 * VMAX, "velocity {v}");
    assert!(a <= 1.01 * AMAX, "acceleration {a}");
    assert!(j <= 1.01 * JERK, "jerk {j}");
    assert!(
        rest - stopped_at <= reach() + 1e-6,
        "ran on {} counts after the wheel stopped (reach {})",
        rest - stopped_at,
        reach()
    );
    assert!(rest - stopped_at >= 0.0, "never backwards");
    assert!(rest - p0 < 0.11 * turned, "the excess was dropped");
    // Never beyond the target, which is where it rests: turning back one detent acts at once.
    assert_eq!(settle(&card, 0), rest);
    turn(&card, 0, -4);
    assert_eq!(settle(&card, 0), rest - 100.0);
    assert_eq!(ax.status().unwrap().state, AxisState::SynchronizedMotion);
}

#[test]
fn the_wheel_stops_at_a_soft_limit_without_a_trip() {
    let card = card(1);
    let ax = card.axis(0).unwrap();
    ax.set_position(0.0, false).unwrap();
    let s = SafetySettings {
        soft_limits: Some((-1_000.0, 1_000.0)),
        ..ax.safety_settings().unwrap()
    };
    ax.configure_safety(&s).unwrap();
    ax.handwheel(&Handwheel::new(0).ratio(10)).unwrap();
    turn(&card, 0, 4 * 150); // 1,500 counts
    assert_eq!(settle(&card, 0), 1_000.0);
    let st = ax.status().unwrap();
    assert_eq!(st.state, AxisState::SynchronizedMotion);
    assert!(st.faults.is_empty(), "{:?}", st.faults);
    // The turns beyond were dropped: one detent back moves off the limit at once.
    turn(&card, 0, -4);
    assert_eq!(settle(&card, 0), 990.0);
}

#[test]
fn selecting_from_velocity_mode_aborts_it_where_the_jog_ramp_stops() {
    let card = card(1);
    let ax = card.axis(0).unwrap();
    let vl = VelocityLimits {
        acceleration: 1e5,
        deceleration: 1e5,
        jerk: 1e7,
    };
    let v = ax.move_velocity(20_000.0, &vl).unwrap();
    v.wait_in_velocity(LONG).unwrap();
    let m = ax.handwheel(&Handwheel::new(0)).unwrap();
    assert_eq!(v.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::SynchronizedMotion);
    // At the jog deceleration and jerk from 20,000 counts/s at rest acceleration: v²/2a + v·a/2j.
    let stop = 20_000.0f64.powi(2) / (2.0 * AMAX) + 20_000.0 * AMAX / (2.0 * JERK);
    let at = settle(&card, 0);
    assert!(
        (at - s.command_position - stop).abs() < 1.0,
        "stopped {} from where it was taken, the jog ramp's {stop}",
        at - s.command_position
    );
    turn(&card, 0, 8);
    assert_eq!(settle(&card, 0), at + 2.0);
    ax.handwheel_off().unwrap();
    m.wait(LONG).unwrap();
}

#[test]
fn an_input_is_handed_over_and_let_go_cleanly() {
    let card = card(2);
    let (a0, a1) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    let m0 = a0.handwheel(&Handwheel::new(0).ratio(10)).unwrap();
    turn(&card, 0, 40);
    step(&card, 5);
    // Axis 1 takes input 0 while axis 0 still moves: axis 0 goes on to its target, done.
    let m1 = a1.handwheel(&Handwheel::new(0)).unwrap();
    assert_eq!(a0.status().unwrap().state, AxisState::DiscreteMotion);
    let p0 = a0.status().unwrap().command_position;
    assert!(p0 < 100.0, "still on its way: {p0}");
    let done = m0.wait(LONG).unwrap();
    assert!((done - 100.0).abs() <= 1.0, "{done}");
    assert_eq!(a0.status().unwrap().state, AxisState::Standstill);
    assert_eq!(a0.status().unwrap().command_position, 100.0);
    // The wheel now turns axis 1 only.
    turn(&card, 0, 40);
    assert_eq!(settle(&card, 1), 10.0);
    assert_eq!(a0.status().unwrap().command_position, 100.0);
    // Let go: done where the wheel put it; the wheel no longer moves it.
    a1.handwheel_off().unwrap();
    assert!((m1.wait(LONG).unwrap() - 10.0).abs() <= 1.0);
    turn(&card, 0, 40);
    assert_eq!(settle(&card, 1), 10.0);
    assert_eq!(a1.status().unwrap().state, AxisState::Standstill);
    assert_eq!(
        a1.handwheel_off().unwrap_err().kind(),
        ErrorKind::InvalidState
    );
}

#[test]
fn a_halt_or_an_estop_ends_it_with_its_stop_reason() {
    let card = card(1);
    let ax = card.axis(0).unwrap();
    let m = ax.handwheel(&Handwheel::new(0).ratio(100)).unwrap();
    spin(&card, 0, 1_000.0);
    step(&card, 500);
    let h = ax.halt(AMAX, JERK).unwrap();
    assert_eq!(m.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    h.wait(LONG).unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::Halt);
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    let at = ax.status().unwrap().command_position;
    step(&card, 1_000);
    assert_eq!(
        ax.status().unwrap().command_position,
        at,
        "the wheel no longer drives it"
    );
    // A moving wheel's axis under an e-stop: ErrorStop, the wheel's motion aborted.
    let m = ax.handwheel(&Handwheel::new(0).ratio(100)).unwrap();
    step(&card, 500);
    card.estop(StopCategory::Cat2).unwrap();
    assert_eq!(m.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    step(&card, 5_000);
    assert_eq!(ax.status().unwrap().state, AxisState::ErrorStop);
    assert_eq!(ax.stop_reason().unwrap(), StopReason::EStopCommand);
    assert_eq!(
        ax.handwheel(&Handwheel::new(0)).unwrap_err().kind(),
        ErrorKind::EStopActive
    );
}

#[test]
fn bad_selections_are_refused_with_their_own_codes() {
    let card = card(4);
    let ax = card.axis(0).unwrap();
    let refused = |w: Handwheel| ax.handwheel(&w).unwrap_err().kind();
    assert_eq!(refused(Handwheel::new(2)), ErrorKind::HandwheelInput);
    assert_eq!(
        refused(Handwheel::new(0).ratio(0)),
        ErrorKind::HandwheelRatio
    );
    assert_eq!(
        refused(Handwheel::new(0).ratio(-10_001)),
        ErrorKind::HandwheelRatio
    );
    assert_eq!(
        refused(Handwheel::new(0).detent(0)),
        ErrorKind::HandwheelRatio
    );
    assert_eq!(
        refused(Handwheel::new(0).detent(1025)),
        ErrorKind::HandwheelRatio
    );
    // The card's own checks, past the SDK's: a fractional ratio, an input it does not have.
    let raw = |args: &[f64]| {
        let mut c = Command::new(Opcode::Handwheel, 0);
        c.args[..args.len()].copy_from_slice(args);
        card.execute_raw(c).unwrap_err().kind()
    };
    assert_eq!(raw(&[0.0, 2.5, 4.0]), ErrorKind::HandwheelRatio);
    assert_eq!(raw(&[5.0, 1.0, 4.0]), ErrorKind::HandwheelInput);
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    // A disabled axis, an axis of an enabled group.
    card.axis(3).unwrap().disable().unwrap();
    assert_eq!(
        card.axis(3)
            .unwrap()
            .handwheel(&Handwheel::new(0))
            .unwrap_err()
            .kind(),
        ErrorKind::AxisDisabled
    );
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[1, 2])).unwrap();
    g.enable().unwrap();
    assert_eq!(
        card.axis(1)
            .unwrap()
            .handwheel(&Handwheel::new(0))
            .unwrap_err()
            .kind(),
        ErrorKind::AxisGrouped
    );
    // On the wheel's axis: moves and jogs are refused, the wheel keeps it.
    ax.handwheel(&Handwheel::new(0)).unwrap();
    let l = MoveLimits::new(1e4, 1e5, 1e7);
    assert_eq!(
        ax.move_absolute(10.0, &l).unwrap_err().kind(),
        ErrorKind::InvalidState
    );
    assert_eq!(ax.jog(100.0).unwrap_err().kind(), ErrorKind::InvalidState);
    assert_eq!(ax.status().unwrap().state, AxisState::SynchronizedMotion);
    let _ = NackCode::HandwheelInput;
}
