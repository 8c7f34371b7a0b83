//! Moves from any state, on the stepped card: PLCopen Aborting takes over in the tick it is
//! served without a jump in position, velocity or acceleration, from every phase of a profile;
//! Buffered moves queue (16 per axis) and each reports its own start and done; MC_MoveAdditive;
//! velocity mode and jog (ContinuousMotion, InVelocity); the velocity override, smooth, with
//! 0 % holding the axis in its motion state.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, BufferMode, Card, EmuOptions, ErrorKind, MotionFlags, MoveKind, MoveLimits, Status,
    VelocityLimits, AXIS_QUEUE_LEN,
};
use std::time::Duration;

const VMAX: f64 = 100_000.0;
const AMAX: f64 = 1e6;
const JMAX: f64 = 5e7;
const RATE: f64 = 10_000.0;
const LONG: Duration = Duration::from_secs(60);

fn lim() -> MoveLimits {
    MoveLimits::new(VMAX, AMAX, JMAX)
}

fn one_axis() -> Card {
    let card = stepped_card_with(EmuOptions::new(1, RATE as u32));
    card.axis(0).unwrap().enable().unwrap();
    card
}

fn status(card: &Card) -> Status {
    card.axis(0).unwrap().status().unwrap()
}

/// The reference of consecutive ticks: no step in acceleration beyond the jerk limit, none in
/// velocity beyond the acceleration limit, nothing beyond the limits.
fn assert_smooth(prev: &Status, s: &Status, (v, a, j): (f64, f64, f64), what: &str) {
    let ts = 1.0 / RATE;
    let tol = 1.0 + 1e-6;
    let da = (s.command_acceleration - prev.command_acceleration).abs();
    let dv = (s.command_velocity - prev.command_velocity).abs();
    let dp = (s.command_position - prev.command_position).abs();
    assert!(
        da <= j * ts * tol + 1e-6,
        "{what}: acceleration step {da} at tick {}: {prev:?} -> {s:?}",
        s.raw.tick
    );
    assert!(dv <= a * ts * tol + 1e-6, "{what}: velocity step {dv}");
    assert!(dp <= v * ts * tol + 1e-6, "{what}: position step {dp}");
    assert!(s.command_velocity.abs() <= v * tol, "{what}: velocity");
    assert!(
        s.command_acceleration.abs() <= a * tol,
        "{what}: acceleration"
    );
}

/// Step one tick at a time until `done` holds (at most `max` ticks), checking smoothness.
fn run_until(
    card: &Card,
    max: u64,
    limits: (f64, f64, f64),
    what: &str,
    mut done: impl FnMut(&Status) -> bool,
) -> Status {
    let sim = card.sim().unwrap();
    let mut prev = status(card);
    for _ in 0..max {
        sim.step(1);
        let s = status(card);
        assert_smooth(&prev, &s, limits, what);
        if done(&s) {
            return s;
        }
        prev = s;
    }
    panic!("{what}: not reached in {max} ticks: {prev:?}");
}

/// Aborting from every phase of a move (jerk, constant acceleration, cruise, deceleration), to
/// targets ahead, behind (must brake, overshoot and come back) and just ahead (inside the
/// braking distance): the new plan is in force in the first tick after the command, the
/// reference never jumps, and the axis ends in position on the new target. The replaced move
/// is aborted, the new one done.
#[test]
fn aborting_takes_over_in_the_same_tick_from_every_phase() {
    // The first move lasts about 1.1 s: jerk 20 ms, constant acceleration to 0.1 s, cruise
    // to about 1.0 s, then the deceleration.
    for frac in [0.005, 0.05, 0.3, 0.93, 0.99] {
        for new_target in [150_000.0, -20_000.0, f64::NAN] {
            let card = one_axis();
            let ax = card.axis(0).unwrap();
            let sim = card.sim().unwrap();
            let first = ax.move_absolute(100_000.0, &lim()).unwrap();
            sim.step((frac * 1.1 * RATE) as u64);
            let s0 = status(&card);
            // NaN: just ahead of where the axis can stop.
            let target = if new_target.is_nan() {
                s0.command_position + 0.5 * s0.command_velocity.abs() * 0.01 + 1.0
            } else {
                new_target
            };
            let what = format!("abort at {frac} of the move to {target}");
            let second = ax.move_absolute(target, &lim()).unwrap();
            // The card serves the command between ticks: the status it publishes with the
            // ack (the same tick) already names the new target, and the next tick runs the
            // new plan.
            let acked = status(&card);
            assert_eq!(acked.raw.tick, s0.raw.tick, "{what}");
            assert_eq!(acked.raw.target, target, "{what}: the new target in force");
            sim.step(1);
            let s1 = status(&card);
            assert_smooth(&s0, &s1, (VMAX, AMAX, JMAX), &what);
            assert_eq!(s1.state, AxisState::DiscreteMotion, "{what}");
            // Behind while still accelerating: the acceleration falls at once.
            if target < s0.command_position && s0.command_acceleration > 0.0 {
                assert!(
                    s1.command_acceleration < s0.command_acceleration,
                    "{what}: still accelerating towards the old target"
                );
            }
            run_until(&card, 60_000, (VMAX, AMAX, JMAX), &what, |s| {
                s.state == AxisState::Standstill
            });
            let err = first.wait(LONG).unwrap_err();
            assert_eq!(err.kind(), ErrorKind::Aborted, "{what}");
            let at = second.wait(LONG).unwrap();
            assert!((at - target).abs() <= 1.0, "{what}: ended at {at}");
        }
    }
}

/// Sixteen buffered moves wait behind the one running; the seventeenth is refused and nothing
/// queued is lost; each starts when the one before it is done (Active) and is done on its own
/// target, in order. An Aborting move then aborts the rest of the queue, each on its own.
#[test]
fn buffered_moves_queue_in_order_and_aborting_drops_them() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    let first = ax.move_absolute(1000.0, &lim()).unwrap();
    let queued: Vec<_> = (0..AXIS_QUEUE_LEN)
        .map(|k| {
            ax.move_with(MoveKind::Relative, 500.0, &lim(), BufferMode::Buffered)
                .unwrap_or_else(|e| panic!("buffered move {k}: {e}"))
        })
        .collect();
    let full = ax
        .move_with(MoveKind::Relative, 500.0, &lim(), BufferMode::Buffered)
        .unwrap_err();
    assert_eq!(full.kind(), ErrorKind::QueueFull);
    assert_eq!(status(&card).queued, AXIS_QUEUE_LEN as u32);
    first.wait(LONG).unwrap();
    for (k, m) in queued.iter().enumerate().take(4) {
        let target = 1000.0 + 500.0 * (k + 1) as f64;
        assert_eq!(m.wait_active(LONG).unwrap(), target);
        let at = m.wait(LONG).unwrap();
        assert!((at - target).abs() <= 1.0, "move {k} ended at {at}");
    }
    let s = status(&card);
    assert!(s.motion.contains(MotionFlags::BUFFERED_ACTIVE));
    assert_eq!(s.queued, AXIS_QUEUE_LEN as u32 - 5);
    // An Aborting move: the one running and every queued one are aborted.
    let last = ax.move_absolute(-3000.0, &lim()).unwrap();
    for m in &queued[4..] {
        assert_eq!(m.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    }
    assert_eq!(status(&card).queued, 0);
    assert!((last.wait(LONG).unwrap() + 3000.0).abs() <= 1.0);
}

/// MC_MoveAdditive adds to the target of the last move, also while that move runs; a buffered
/// MC_MoveRelative counts from the target of the move before it.
#[test]
fn additive_counts_from_the_last_target() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    ax.move_absolute(10_000.0, &lim()).unwrap();
    card.sim().unwrap().step(200);
    let m = ax.move_additive(2_500.0, &lim()).unwrap();
    assert!((m.wait(LONG).unwrap() - 12_500.0).abs() <= 1.0);
    let r = ax
        .move_with(MoveKind::Relative, -500.0, &lim(), BufferMode::Buffered)
        .unwrap();
    assert!((r.wait(LONG).unwrap() - 12_000.0).abs() <= 1.0);
}

/// Velocity mode: reaches its velocity within the limits (InVelocity, ContinuousMotion), takes
/// a new velocity on the fly (reversing), and ends with a halt in Standstill; the velocity
/// command is aborted by the halt, never done.
#[test]
fn velocity_mode_changes_on_the_fly_and_halts() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    let vl = VelocityLimits::new(AMAX, JMAX);
    let v1 = ax.move_velocity(50_000.0, &vl).unwrap();
    let lims = (60_000.0, AMAX, JMAX);
    let s = run_until(&card, 10_000, lims, "to 50,000", |s| {
        s.motion.contains(MotionFlags::IN_VELOCITY)
    });
    assert_eq!(s.state, AxisState::ContinuousMotion);
    assert_eq!(s.command_velocity, 50_000.0);
    assert_eq!(v1.wait_in_velocity(LONG).unwrap(), 50_000.0);
    card.sim().unwrap().step(500);
    let v2 = ax.move_velocity(-20_000.0, &vl).unwrap();
    assert_eq!(v1.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    run_until(&card, 10_000, lims, "to -20,000", |s| {
        s.motion.contains(MotionFlags::IN_VELOCITY)
    });
    assert_eq!(v2.wait_in_velocity(LONG).unwrap(), -20_000.0);
    assert_eq!(status(&card).command_velocity, -20_000.0);
    let h = ax.halt(AMAX, JMAX).unwrap();
    assert_eq!(v2.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    h.wait(LONG).unwrap();
    assert_eq!(status(&card).state, AxisState::Standstill);
    // Bad input: NaN, and a limit out of the card's range.
    assert_eq!(
        ax.move_velocity(f64::NAN, &vl).unwrap_err().kind(),
        ErrorKind::NotFinite
    );
    let bad = VelocityLimits::new(1e-300, JMAX);
    assert_eq!(
        ax.move_velocity(1000.0, &bad).unwrap_err().kind(),
        ErrorKind::LimitRange
    );
}

/// Jog: the axis's own jog limits (a velocity beyond jog_max_vel is refused), and releasing
/// the button halts at the jog deceleration.
#[test]
fn jog_runs_within_its_own_limits_and_release_halts() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    let cfg = motioncard_sdk::AxisSettings::default();
    let too_fast = ax.jog(cfg.jog_max_vel * 1.01).unwrap_err();
    assert_eq!(too_fast.kind(), ErrorKind::OutOfRange);
    let j = ax.jog(-cfg.jog_max_vel).unwrap();
    let lims = (cfg.jog_max_vel, cfg.jog_accel, cfg.jog_jerk);
    run_until(&card, 10_000, lims, "jog", |s| {
        s.motion.contains(MotionFlags::IN_VELOCITY)
    });
    j.wait_in_velocity(LONG).unwrap();
    let h = ax.jog_release().unwrap();
    run_until(&card, 10_000, lims, "release", |s| {
        s.state == AxisState::Standstill
    });
    h.wait(LONG).unwrap();
}

/// The override at cruise: 50 % brings the velocity to half within the acceleration and jerk
/// limits, without stopping; 0 % holds the axis still in DiscreteMotion (PAUSED); 200 % resumes
/// at twice the velocity; the move still ends on its target. In velocity mode it scales the
/// velocity.
#[test]
fn override_is_smooth_holds_at_zero_and_resumes() {
    let card = one_axis();
    let ax = card.axis(0).unwrap();
    let sim = card.sim().unwrap();
    let target = 1_000_000.0;
    let m = ax.move_absolute(target, &lim()).unwrap();
    sim.step((0.5 * RATE) as u64);
    assert_eq!(status(&card).command_velocity, VMAX);
    let l2 = (2.0 * VMAX, AMAX, JMAX);
    ax.set_override(0.5).unwrap();
    let mut slowest = VMAX;
    let s = run_until(&card, 10_000, l2, "50 %", |s| {
        slowest = slowest.min(s.command_velocity);
        s.command_velocity <= 0.5 * VMAX * (1.0 + 1e-9) && s.command_acceleration == 0.0
    });
    // Time-optimal from cruise: straight down to the new velocity, never below it.
    assert!(
        slowest >= 0.5 * VMAX * (1.0 - 1e-9),
        "slowed to {slowest}, below the overridden velocity"
    );
    assert_eq!(s.override_factor, 0.5);
    ax.set_override(0.0).unwrap();
    let s = run_until(&card, 10_000, l2, "0 %", |s| s.command_velocity == 0.0);
    sim.step(100);
    let held = status(&card);
    assert_eq!(held.command_position, s.command_position);
    assert_eq!(held.state, AxisState::DiscreteMotion);
    assert!(held.motion.contains(MotionFlags::PAUSED));
    ax.set_override(2.0).unwrap();
    run_until(&card, 20_000, l2, "200 %", |s| {
        (s.command_velocity - 2.0 * VMAX).abs() < 1e-6
    });
    run_until(&card, 100_000, l2, "to the end", |s| {
        s.state == AxisState::Standstill
    });
    assert!((m.wait(LONG).unwrap() - target).abs() <= 1.0);
    // Velocity mode: the override scales the velocity.
    ax.set_override(1.0).unwrap();
    let v = ax
        .move_velocity(40_000.0, &VelocityLimits::new(AMAX, JMAX))
        .unwrap();
    v.wait_in_velocity(LONG).unwrap();
    ax.set_override(1.5).unwrap();
    run_until(&card, 10_000, l2, "150 % of 40,000", |s| {
        s.motion.contains(MotionFlags::IN_VELOCITY)
    });
    assert_eq!(status(&card).command_velocity, 60_000.0);
}
