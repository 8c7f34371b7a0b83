//! Safety on the stepped emulated card: watchdog, limits, following error, input faults,
//! e-stop, stop reasons, and the safety nack codes. Times are in servo ticks.
mod common;

use common::{stepped_card, Rng};
use motioncard_sdk::proto::{Command, Faults, Io, Opcode};
use motioncard_sdk::{
    AxisState, Card, CardEvent, ErrorKind, EventKind, MoveLimits, NackCode, SafetySettings,
    StopCategory, StopReason, Switches,
};
use std::time::Duration;

fn fast() -> MoveLimits {
    MoveLimits::new(300_000.0, 3e6, 3e8)
}

fn events(card: &Card) -> Vec<CardEvent> {
    std::iter::from_fn(|| card.next_event(Duration::ZERO).unwrap()).collect()
}

fn ticks_of(card: &Card, secs: f64) -> u64 {
    (secs * card.info().servo_rate_hz as f64).round() as u64
}

/// Host heartbeat stops mid-move at full speed: the watchdog trips after the timeout, every
/// axis decelerates (category 1) and is disabled at rest; the fault stays latched when the
/// heartbeat returns, until the host resets it.
#[test]
fn watchdog_stops_every_axis_and_latches_until_reset() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let axes = [card.axis(0).unwrap(), card.axis(5).unwrap()];
    let mut moves = Vec::new();
    for (k, ax) in axes.iter().enumerate() {
        ax.enable().unwrap();
        let d = if k == 0 { 1e6 } else { -1e6 };
        moves.push(ax.move_relative(d, &fast()).unwrap());
    }
    sim.step(3000); // cruising at 300,000 counts/s
    assert!(axes[0].status().unwrap().command_velocity == 300_000.0);
    assert!(card.safety_status().unwrap().watchdog_armed);
    events(&card);

    card.set_heartbeat(false);
    let timeout = ticks_of(
        &card,
        motioncard_sdk::WATCHDOG_TIMEOUT_DEFAULT.as_secs_f64(),
    );
    let mut tripped = None;
    for n in 1..=timeout + 2 {
        sim.step(1);
        if card.safety_status().unwrap().watchdog_tripped {
            tripped = Some(n);
            break;
        }
    }
    let st = card.safety_status().unwrap();
    // The card last saw the heartbeat the tick before we stopped it; it trips the first tick
    // the heartbeat is as old as the default timeout.
    assert_eq!(tripped, Some(timeout), "tripped after {tripped:?} ticks");
    assert_eq!(st.watchdog_trip_tick - st.last_heartbeat_tick, timeout);
    assert_eq!(st.trip_heartbeat_tick, st.last_heartbeat_tick);
    for m in &moves {
        let e = m.wait(Duration::ZERO).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Aborted);
        assert!(e.to_string().contains("watchdog"), "{e}");
    }
    // Category 1: a ramp within the stop deceleration, then the drive is disabled at rest.
    let stop_decel = SafetySettings::default().stop_deceleration;
    let mut peak_dec: f64 = 0.0;
    sim.trace(0, 20_000, |s| {
        peak_dec = peak_dec.max(-s.command_acceleration);
        s.drive_enabled()
    })
    .unwrap();
    sim.step(10);
    assert!(peak_dec <= stop_decel * (1.0 + 1e-9) && peak_dec > 0.9 * stop_decel);
    for ax in &axes {
        let s = ax.status().unwrap();
        assert_eq!(s.state, AxisState::ErrorStop);
        assert!(!s.drive_enabled() && s.dac_volts == 0.0);
        assert_eq!(s.stop_reason(), Some(StopReason::Watchdog));
        let info = ax.stop_info().unwrap();
        let rest = info.rest_tick.expect("at rest");
        // timeout + ramp, the ramp rounded up to whole ticks
        let ramp = (info.ramp_time.as_secs_f64() * card.info().servo_rate_hz as f64).ceil();
        let bound = timeout + ramp as u64;
        assert!(
            rest - st.last_heartbeat_tick <= bound,
            "at rest {} ticks after the last heartbeat, bound {bound}",
            rest - st.last_heartbeat_tick
        );
    }
    let ev = events(&card);
    let count = |k: EventKind, a: u16| ev.iter().filter(|e| e.kind == k && e.axis == a).count();
    assert_eq!(count(EventKind::SafetyStop, 0xFFFF), 1);
    for a in [0, 5] {
        assert_eq!(count(EventKind::SafetyStop, a), 1);
        assert_eq!(count(EventKind::AtRest, a), 1);
    }

    // The heartbeat comes back: still latched.
    card.set_heartbeat(true);
    sim.step(100);
    assert!(card.safety_status().unwrap().watchdog_tripped);
    assert_eq!(
        card.axis(1).unwrap().enable().unwrap_err().kind(),
        ErrorKind::WatchdogTripped
    );
    assert_eq!(
        axes[0].reset().unwrap_err().kind(),
        ErrorKind::WatchdogTripped
    );
    // A move on an axis the watchdog stopped names the watchdog, not just the state.
    assert_eq!(
        axes[0].move_relative(10.0, &fast()).unwrap_err().kind(),
        ErrorKind::WatchdogTripped
    );
    // A reset without a live heartbeat is refused.
    card.set_heartbeat(false);
    sim.step(ticks_of(&card, 0.11));
    assert_eq!(
        card.reset_faults().unwrap_err().kind(),
        ErrorKind::CauseActive
    );
    card.set_heartbeat(true);
    sim.step(1);
    card.reset_faults().unwrap();
    assert!(!card.safety_status().unwrap().watchdog_tripped);
    for ax in &axes {
        assert_eq!(ax.status().unwrap().state, AxisState::Disabled);
        ax.enable().unwrap();
        ax.move_relative(1000.0, &fast())
            .unwrap()
            .wait(Duration::from_secs(1))
            .unwrap();
        assert_eq!(ax.stop_reason().unwrap(), StopReason::Done);
    }
}

#[test]
fn watchdog_timeout_under_1_5_host_periods_or_zero_is_refused() {
    let card = stepped_card();
    let period = Duration::from_micros(motioncard_sdk::HEARTBEAT_PERIOD_US as u64);
    for bad in [
        Duration::ZERO,
        period,
        period * 3 / 2 - Duration::from_micros(1),
    ] {
        assert_eq!(
            card.set_watchdog_timeout(bad).unwrap_err().kind(),
            ErrorKind::WatchdogTimeout,
            "{bad:?}"
        );
    }
    card.set_watchdog_timeout(period * 3 / 2).unwrap();
    // The shorter timeout is in force: the watchdog trips 1.5 ms after the last beat.
    card.set_heartbeat(false);
    let sim = card.sim().unwrap();
    sim.step(ticks_of(&card, 0.0015));
    assert!(!card.safety_status().unwrap().watchdog_tripped);
    sim.step(1);
    assert!(card.safety_status().unwrap().watchdog_tripped);
}

/// The LinuxCNC rule with the card's configuration, from a status snapshot.
fn ferror_limit(s: &SafetySettings, cmd_vel: f64) -> f64 {
    (s.ferror * cmd_vel.abs() / s.max_velocity).max(s.min_ferror)
}

/// A stalled axis: the trip comes in the very tick the following error first exceeds its
/// limit (scaled by the commanded velocity), with the output cut in that tick.
#[test]
fn following_error_trips_within_one_tick_on_a_stalled_axis() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(3).unwrap();
    let cfg = SafetySettings {
        ferror: 2000.0,
        min_ferror: 200.0,
        max_velocity: 200_000.0,
        ..Default::default()
    };
    ax.configure_safety(&cfg).unwrap();
    ax.enable().unwrap();
    sim.with_emulator(|e| e.faults().stall(3, true));
    let m = ax
        .move_relative(100_000.0, &MoveLimits::new(200_000.0, 2e6, 1e8))
        .unwrap();
    let mut first_over = None;
    let mut prev_state = AxisState::DiscreteMotion;
    sim.trace(3, 10_000, |s| {
        let over = s.following_error.abs() > ferror_limit(&cfg, s.command_velocity);
        if over && first_over.is_none() {
            first_over = Some((s.raw.tick, s.state, prev_state, s.dac_volts, s.io()));
        }
        if !over {
            assert_ne!(s.state, AxisState::ErrorStop, "tripped within the limit");
        }
        prev_state = s.state;
        first_over.is_none()
    })
    .unwrap();
    let (tick, state, before, volts, iobits) = first_over.expect("the error grew past the limit");
    assert_eq!(before, AxisState::DiscreteMotion);
    assert_eq!(
        state,
        AxisState::ErrorStop,
        "not tripped in the tick it exceeded"
    );
    assert_eq!((volts, iobits.contains(Io::DRIVE_ENABLE)), (0.0, false));
    let ev = events(&card);
    let trip = ev
        .iter()
        .find(|e| e.kind == EventKind::SafetyStop && e.axis == 3)
        .unwrap();
    assert_eq!(trip.code, StopReason::FollowingError as i32);
    assert_eq!(trip.tick, tick);
    assert!(trip.value.abs() > cfg.min_ferror);
    assert_eq!(ax.stop_reason().unwrap(), StopReason::FollowingError);
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    // ErrorStop until reset (PLCopen); the jam is cleared, reset gives a disabled axis.
    sim.with_emulator(|e| e.faults().stall(3, false));
    assert_eq!(ax.enable().unwrap_err().kind(), ErrorKind::InvalidState);
    ax.reset().unwrap();
    assert_eq!(ax.status().unwrap().state, AxisState::Disabled);
    println!("following-error trip: tick {tick}, in the tick the limit was exceeded");
}

/// 1,000 random moves the plant can follow, on 8 axes at once: no following-error trip.
#[test]
fn no_false_following_error_trip_on_1000_random_in_limit_moves() {
    let card = stepped_card();
    let axes = card.axes();
    for ax in &axes {
        ax.enable().unwrap();
    }
    let cfg = SafetySettings::default();
    let mut rng = Rng::new(2024);
    let mut worst: f64 = 0.0;
    let mut moves = 0;
    while moves < 1000 {
        let mut ms = Vec::new();
        for ax in &axes {
            let v = rng.log_uniform(1e3, 5e5);
            let a = rng.log_uniform(1e5, 5e6);
            let lim = MoveLimits {
                velocity: v,
                acceleration: a,
                deceleration: rng.log_uniform(1e5, 5e6),
                jerk: [
                    rng.log_uniform(1e6, 1e9),
                    rng.log_uniform(1e6, 1e9),
                    rng.log_uniform(1e6, 1e9),
                    rng.log_uniform(1e6, 1e9),
                ],
            };
            // Whole counts: a fractional target makes the servo hunt between two counts (a
            // limit cycle of the quantised loop) and motion done waits for it to settle.
            let d = (rng.uniform(-1.0, 1.0) * v * rng.uniform(0.001, 0.3)).round();
            ms.push((ax.clone(), ax.move_relative(d, &lim).unwrap()));
            moves += 1;
        }
        for (ax, m) in ms {
            if let Err(e) = m.wait(Duration::from_secs(20)) {
                panic!("{e}: {:?}", ax.status().unwrap());
            }
            let s = ax.status().unwrap();
            assert_eq!(s.state, AxisState::Standstill);
            worst = worst.max(s.raw.max_ferr / cfg.min_ferror);
        }
    }
    for ax in &axes {
        assert!(!ax
            .status()
            .unwrap()
            .faults
            .contains(Faults::FOLLOWING_ERROR));
    }
    println!(
        "1000 random in-limit moves: no trip; largest |ferr| = {:.4} x MIN_FERROR",
        worst
    );
}

/// A hard limit tripped mid-move: the axis stops, the event arrives, a move further in is
/// refused with its own code, the move out works.
#[test]
fn hard_limit_mid_move_stops_refuses_further_allows_out() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(2).unwrap();
    sim.with_emulator(|e| {
        e.faults()
            .set_switches(2, Switches::limits(-50_000.0, 50_000.0))
    });
    ax.enable().unwrap();
    let m = ax.move_absolute(200_000.0, &fast()).unwrap();
    let err = m.wait(Duration::from_secs(5)).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Aborted);
    assert!(err.to_string().contains("positive limit switch"), "{err}");
    let ev = events(&card);
    let trip = ev
        .iter()
        .find(|e| e.kind == EventKind::SafetyStop && e.axis == 2)
        .expect("safety-stop event");
    assert_eq!(trip.code, StopReason::HardLimitPos as i32);
    assert!(trip.value >= 50_000.0 && trip.value < 50_000.0 + 300_000.0 * 1e-4 + 1.0);
    sim.step(5000);
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::ErrorStop);
    assert_eq!(s.stop_reason(), Some(StopReason::HardLimitPos));
    assert!(s.io().contains(Io::LIMIT_POS) && !s.drive_enabled());
    // Overtravel: the stopping distance of 300,000 counts/s at the stop ramp.
    let stopped_at = s.actual_position;
    assert!(
        stopped_at > 50_000.0 && stopped_at < 70_000.0,
        "{stopped_at}"
    );
    ax.reset().unwrap();
    ax.enable().unwrap();
    assert_eq!(
        ax.move_relative(10.0, &fast()).err().unwrap().kind(),
        ErrorKind::HardLimit
    );
    assert_eq!(
        ax.move_absolute(1e5, &fast()).err().unwrap().kind(),
        ErrorKind::HardLimit
    );
    let back = ax
        .move_absolute(0.0, &fast())
        .unwrap()
        .wait(Duration::from_secs(5))
        .unwrap();
    assert!(back.abs() <= 1.0);
    let s = ax.status().unwrap();
    assert!(!s.io().contains(Io::LIMIT_POS));
    assert!(!s.faults.contains(Faults::HARD_LIMIT_POS));

    // A switch forced by the injector mid-move, negative direction, category 2 configured:
    // stop, power kept.
    ax.configure_safety(&SafetySettings {
        limit_stop: StopCategory::Cat2,
        ..Default::default()
    })
    .unwrap();
    let m = ax.move_relative(-40_000.0, &fast()).unwrap();
    sim.step(800);
    sim.with_emulator(|e| {
        e.faults()
            .trip_limit(2, motioncard_faults::Direction::Negative, true)
    });
    assert_eq!(
        m.wait(Duration::from_secs(1)).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    sim.step(3000);
    let s = ax.status().unwrap();
    assert_eq!(s.stop_reason(), Some(StopReason::HardLimitNeg));
    assert!(s.drive_enabled() && s.state == AxisState::ErrorStop);
    ax.reset().unwrap();
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    assert_eq!(
        ax.move_relative(-1.0, &fast()).err().unwrap().kind(),
        ErrorKind::HardLimit
    );
    ax.move_relative(100.0, &fast())
        .unwrap()
        .wait(Duration::from_secs(1))
        .unwrap();
}

use card_emu::plant::faults as motioncard_faults;

#[test]
fn soft_limits_refuse_moves_beyond_and_allow_moves_back() {
    let card = stepped_card();
    let ax = card.axis(1).unwrap();
    // Inverted limits are refused, not swapped; a negative scale maps the user's negative
    // limit to the larger count, and is not an inversion.
    let inverted = SafetySettings {
        soft_limits: Some((100.0, -100.0)),
        ..Default::default()
    };
    assert_eq!(
        ax.configure_safety(&inverted).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    ax.set_scale(-10.0).unwrap();
    ax.configure_safety(&SafetySettings {
        soft_limits: Some((-100.0, 50.0)),
        ..Default::default()
    })
    .unwrap();
    ax.set_scale(10.0).unwrap(); // counts per unit
    ax.configure_safety(&SafetySettings {
        soft_limits: Some((-100.0, 100.0)), // units: ±1000 counts
        ..Default::default()
    })
    .unwrap();
    ax.enable().unwrap();
    let lim = MoveLimits::new(1000.0, 1e5, 1e7);
    // Soft limits hold once the axis is homed: here, MC_SetPosition where it stands.
    assert!(!ax.status().unwrap().homed());
    ax.set_position(0.0, false).unwrap();
    assert!(ax.status().unwrap().homed());
    assert_eq!(
        ax.move_absolute(100.5, &lim).err().unwrap().kind(),
        ErrorKind::SoftLimit
    );
    assert_eq!(
        ax.move_relative(-101.0, &lim).err().unwrap().kind(),
        ErrorKind::SoftLimit
    );
    let at = ax
        .move_absolute(99.0, &lim)
        .unwrap()
        .wait(Duration::from_secs(5))
        .unwrap();
    assert!((at - 99.0).abs() <= 0.1);
    // Halting a fast move late overshoots the soft limit: the card stops the axis there.
    let fast = MoveLimits::new(5000.0, 1e5, 1e7);
    let m = ax.move_absolute(-99.0, &fast).unwrap();
    let sim = card.sim().unwrap();
    sim.trace(1, 100_000, |s| s.actual_position > -80.0)
        .unwrap();
    ax.halt(1e3, 1e5).unwrap(); // far too gentle: the stop would end beyond -100
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    sim.step(20_000);
    let s = ax.status().unwrap();
    assert_eq!(s.stop_reason(), Some(StopReason::SoftLimitNeg));
    assert_eq!(s.state, AxisState::ErrorStop);
    ax.reset().unwrap();
    ax.enable().unwrap();
    assert_eq!(
        ax.move_relative(-1.0, &lim).err().unwrap().kind(),
        ErrorKind::SoftLimit
    );
    ax.move_absolute(0.0, &lim)
        .unwrap()
        .wait(Duration::from_secs(5))
        .unwrap();
}

/// E-stop by command in each category, then by the input.
#[test]
fn estop_categories_0_1_2_for_all_axes_and_the_input() {
    for cat in [StopCategory::Cat0, StopCategory::Cat1, StopCategory::Cat2] {
        let card = stepped_card();
        let sim = card.sim().unwrap();
        let axes = card.axes();
        for ax in &axes {
            ax.enable().unwrap();
            ax.move_relative(1e6, &fast()).unwrap();
        }
        sim.step(2000);
        card.estop(cat).unwrap();
        let s = axes[4].status().unwrap();
        assert_eq!(s.state, AxisState::ErrorStop);
        assert_eq!(s.stop_reason(), Some(StopReason::EStopCommand));
        // Category 0 removes power at once (the e-stop is served between ticks).
        sim.step(1);
        assert_eq!(
            axes[4].status().unwrap().drive_enabled(),
            cat != StopCategory::Cat0,
            "{cat:?}"
        );
        // Unpowered axes coast: at rest once still, at the latest at the maximum stop time.
        sim.step(21_000);
        for ax in &axes {
            let s = ax.status().unwrap();
            assert_eq!(s.state, AxisState::ErrorStop);
            assert_eq!(s.drive_enabled(), cat == StopCategory::Cat2, "{cat:?}");
            assert!(ax.stop_info().unwrap().rest_tick.is_some());
            if cat == StopCategory::Cat2 {
                assert_eq!(s.command_velocity, 0.0);
                assert!(s.following_error.abs() <= 2.0, "holds position");
            }
        }
        let st = card.safety_status().unwrap();
        assert!(st.estop_command);
        // The safety layer's busiest moment (every axis stopping at once) lost nothing.
        assert_eq!(
            (st.safety_events_lost, st.outbox_lost, st.bad_accesses),
            (0, 0, 0)
        );
        assert_eq!(axes[0].reset().unwrap_err().kind(), ErrorKind::EStopActive);
        card.reset_faults().unwrap();
        let want = if cat == StopCategory::Cat2 {
            AxisState::Standstill
        } else {
            AxisState::Disabled
        };
        assert_eq!(axes[0].status().unwrap().state, want);
    }
    // The input, with category 0 configured.
    let card = stepped_card();
    let sim = card.sim().unwrap();
    card.set_estop_input_category(StopCategory::Cat0).unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    ax.move_relative(1e6, &fast()).unwrap();
    sim.step(1000);
    sim.with_emulator(|e| e.faults().set_estop(true));
    sim.step(1);
    let s = ax.status().unwrap();
    assert_eq!(s.stop_reason(), Some(StopReason::EStopInput));
    assert!(!s.drive_enabled() && s.io().contains(Io::ESTOP));
    sim.step(21_000);
    assert_eq!(
        card.reset_faults().unwrap_err().kind(),
        ErrorKind::CauseActive
    );
    assert_eq!(
        card.axis(1).unwrap().enable().unwrap_err().kind(),
        ErrorKind::EStopActive
    );
    sim.with_emulator(|e| e.faults().set_estop(false));
    sim.step(1);
    card.reset_faults().unwrap();
    ax.enable().unwrap();
}

/// Amplifier alarm, encoder loss, encoder jump, a saturated amplifier: category 0 stops with
/// their own reasons; reset refused while the alarm or the encoder fault persists.
#[test]
fn alarm_and_encoder_faults_stop_category_0() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let run = |axis: usize, inject: &dyn Fn(&mut card_emu::Emulator)| {
        let ax = card.axis(axis).unwrap();
        ax.enable().unwrap();
        let m = ax.move_relative(1e6, &fast()).unwrap();
        sim.step(1500);
        sim.with_emulator(inject);
        sim.step(1);
        assert_eq!(
            m.wait(Duration::ZERO).unwrap_err().kind(),
            ErrorKind::Aborted
        );
        let s = ax.status().unwrap();
        assert_eq!(s.state, AxisState::ErrorStop);
        assert!(!s.drive_enabled() && s.dac_volts == 0.0);
        sim.step(20_000); // coasts to rest
        assert!(ax.stop_info().unwrap().rest_tick.is_some());
        ax
    };
    let ax = run(0, &|e| e.faults().set_alarm(0, true));
    assert_eq!(ax.stop_reason().unwrap(), StopReason::AmpAlarm);
    assert_eq!(ax.reset().unwrap_err().kind(), ErrorKind::CauseActive);
    sim.with_emulator(|e| e.faults().set_alarm(0, false));
    sim.step(1);
    ax.reset().unwrap();

    let ax = run(1, &|e| e.lose_encoder(1, true));
    assert_eq!(ax.stop_reason().unwrap(), StopReason::EncoderLoss);
    assert_eq!(ax.reset().unwrap_err().kind(), ErrorKind::CauseActive);
    sim.with_emulator(|e| e.lose_encoder(1, false));
    sim.step(1);
    ax.reset().unwrap();

    let ax = run(2, &|e| e.faults().corrupt_encoder(2, 1 << 20));
    assert_eq!(ax.stop_reason().unwrap(), StopReason::EncoderJump);
    ax.reset().unwrap();
    assert_eq!(ax.status().unwrap().state, AxisState::Disabled);

    // A drive that saturates at 5 % cannot follow: following error.
    let ax = card.axis(3).unwrap();
    sim.with_emulator(|e| e.faults().saturate(3, Some(0.05)));
    ax.enable().unwrap();
    let m = ax.move_relative(1e6, &fast()).unwrap();
    assert_eq!(
        m.wait(Duration::from_secs(2)).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    assert_eq!(ax.stop_reason().unwrap(), StopReason::FollowingError);
}

/// Normal stops have reasons too (dmc_get_stop_reason).
#[test]
fn stop_reasons_of_normal_stops() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::None);
    ax.enable().unwrap();
    ax.move_relative(1000.0, &fast())
        .unwrap()
        .wait(Duration::from_secs(1))
        .unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::Done);
    ax.move_relative(1e6, &fast()).unwrap();
    sim.step(100);
    assert_eq!(ax.stop_reason().unwrap(), StopReason::None);
    ax.halt(1e6, 1e8)
        .unwrap()
        .wait(Duration::from_secs(1))
        .unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::Halt);
    ax.move_relative(1e6, &fast()).unwrap();
    sim.step(100);
    ax.stop(1e6, 1e8)
        .unwrap()
        .wait(Duration::from_secs(1))
        .unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::Stop);
    ax.release_stop().unwrap();
    sim.step(1);
    ax.disable().unwrap();
    assert_eq!(ax.stop_reason().unwrap(), StopReason::PowerOff);
}

/// Each safety nack code is provoked by its own fault.
#[test]
fn every_safety_nack_code_is_provoked_by_its_own_fault() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let raw = |cmd: Command| {
        let seq = card.send_raw(cmd).unwrap();
        card.wait_ack(seq).unwrap().err()
    };
    let mut seen = Vec::new();
    let mut expect = |code: NackCode, got: Option<NackCode>| {
        assert_eq!(got, Some(code));
        seen.push(code);
    };
    expect(
        NackCode::BadCategory,
        raw(Command::new(Opcode::EStop, 0).with_args(&[3.0])),
    );
    assert_eq!(
        raw(Command::new(Opcode::EStop, 0).with_args(&[0.5])),
        Some(NackCode::BadCategory)
    );
    assert_eq!(
        raw(Command::new(Opcode::EStop, 0).with_args(&[f64::NAN])),
        Some(NackCode::NotFinite)
    );
    expect(
        NackCode::WatchdogTimeout,
        card.set_watchdog_timeout(Duration::ZERO).err().map(nack),
    );
    let ax = card.axis(0).unwrap();
    sim.with_emulator(|e| {
        e.faults()
            .trip_limit(0, motioncard_faults::Direction::Positive, true)
    });
    sim.step(1);
    ax.enable().unwrap();
    expect(
        NackCode::HardLimit,
        ax.move_relative(5.0, &fast()).err().map(nack),
    );
    sim.with_emulator(|e| {
        e.faults()
            .trip_limit(0, motioncard_faults::Direction::Positive, false)
    });
    sim.step(1);
    ax.configure_safety(&SafetySettings {
        soft_limits: Some((-10.0, 10.0)),
        ..Default::default()
    })
    .unwrap();
    ax.set_position(0.0, true).unwrap(); // soft limits hold once homed
    expect(
        NackCode::SoftLimit,
        ax.move_relative(50.0, &fast()).err().map(nack),
    );
    sim.with_emulator(|e| e.faults().set_alarm(0, true));
    sim.step(1);
    expect(NackCode::CauseActive, ax.reset().err().map(nack));
    sim.with_emulator(|e| e.faults().set_alarm(0, false));
    sim.step(1);
    card.estop(StopCategory::Cat1).unwrap();
    expect(NackCode::EStopActive, ax.reset().err().map(nack));
    card.reset_faults().unwrap();
    // A stop ramp that could not stop the axis from its max velocity within the card's
    // maximum stop time (2 s): 10^6 counts/s at 10^5 counts/s^2 takes 10 s.
    expect(
        NackCode::StopTooLong,
        ax.configure_safety(&SafetySettings {
            stop_deceleration: 1e5,
            ..Default::default()
        })
        .err()
        .map(nack),
    );
    assert_eq!(
        card.set_max_stop_time(Duration::from_millis(5))
            .unwrap_err()
            .kind(),
        ErrorKind::StopTooLong
    );
    // The default ramp from 10^6 counts/s takes 0.21 s: a 0.1 s bound cannot hold it.
    assert_eq!(
        card.set_max_stop_time(Duration::from_millis(100))
            .unwrap_err()
            .kind(),
        ErrorKind::StopTooLong
    );
    // Only the attached host detaches.
    let mut detach = Command::new(Opcode::HostDetach, 0);
    detach.flags = card.safety_status().unwrap().session ^ 1;
    expect(NackCode::Session, raw(detach));
    // Outside a session (this host's own, ended by a raw detach) power and motion are refused;
    // a raw attach of the same session takes the card back.
    let own = card.safety_status().unwrap().session;
    assert_eq!(raw(session_command(Opcode::HostDetach, own)), None);
    expect(NackCode::NoSession, ax.enable().err().map(nack));
    assert_eq!(raw(session_command(Opcode::HostAttach, own)), None);
    card.set_heartbeat(false);
    sim.step(ticks_of(&card, 0.11));
    expect(NackCode::WatchdogTripped, ax.enable().err().map(nack));
    for code in NackCode::ALL
        .iter()
        .filter(|c| (32..48).contains(&(**c as i32)))
    {
        assert!(seen.contains(code), "{code:?} never provoked");
    }
}

fn nack(e: motioncard_sdk::Error) -> NackCode {
    match e {
        motioncard_sdk::Error::Nack { code, .. } => code,
        e => panic!("not a nack: {e}"),
    }
}

/// Garbage in the command ring's indices: a protocol-error event and a category 1 stop.
#[test]
fn corrupt_command_ring_stops_the_axes_with_its_own_reason() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(6).unwrap();
    ax.enable().unwrap();
    ax.move_relative(1e6, &fast()).unwrap();
    sim.step(1000);
    sim.with_emulator(|e| {
        use firmware_proto::Mem;
        e.window()
            .write32(firmware_proto::layout::CMD_HEAD, 0xDEAD_0000);
    });
    sim.step(1);
    let ev = events(&card);
    let pe = ev
        .iter()
        .find(|e| e.kind == EventKind::ProtocolError)
        .expect("protocol error event");
    assert_eq!(pe.code, 1);
    sim.step(10_000);
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::ErrorStop);
    assert_eq!(s.stop_reason(), Some(StopReason::CmdRing));
    assert_eq!(card.safety_status().unwrap().protocol_errors, 1);
}

/// A member of a moving group trips: the other members make the same category of stop in the
/// same tick (reason Group), never left driving on or frozen on the spot; the group goes to
/// GroupErrorStop and comes back through the axes' and the group's resets.
#[test]
fn a_member_trip_stops_its_whole_group_the_same_way() {
    use motioncard_sdk::{AccDec, GroupSettings, GroupState, MoveOptions, PathLimits};
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let (x, y) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    for ax in [&x, &y] {
        ax.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        accdec: AccDec::Pre,
        ..GroupSettings::new(&[0, 1])
    })
    .unwrap();
    g.enable().unwrap();
    let feed = PathLimits::new(200_000.0, 2e6, 1e8);

    // Category 0: the following error of a stalled Y.
    let m = g
        .move_linear(&[400_000.0, 300_000.0], &feed, MoveOptions::default())
        .unwrap();
    sim.step(2000);
    assert!(x.status().unwrap().command_velocity > 100_000.0);
    sim.with_emulator(|e| e.faults().stall(1, true));
    let mut ticks = 0;
    while y.status().unwrap().state != AxisState::ErrorStop {
        assert_eq!(x.status().unwrap().state, AxisState::SynchronizedMotion);
        sim.step(1);
        ticks += 1;
        assert!(ticks < 20_000, "Y never tripped");
    }
    let (sx, sy) = (x.status().unwrap(), y.status().unwrap());
    assert_eq!(sy.stop_reason(), Some(StopReason::FollowingError));
    assert_eq!(sx.state, AxisState::ErrorStop, "X kept going");
    assert_eq!(sx.stop_reason(), Some(StopReason::Group));
    assert!(
        !sx.drive_enabled() && sx.dac_volts == 0.0,
        "X not category 0"
    );
    let ev = events(&card);
    let stop_x = ev
        .iter()
        .find(|e| e.kind == EventKind::SafetyStop && e.axis == 0)
        .expect("safety stop of X");
    assert_eq!((stop_x.code, stop_x.value), (StopReason::Group as i32, 1.0));
    assert_eq!(stop_x.tick, sy.raw.tick);
    sim.step(1);
    assert_eq!(g.status().unwrap().0, GroupState::ErrorStop);
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );

    // Back: the axes' resets, power, then the group's reset.
    sim.with_emulator(|e| e.faults().stall(1, false));
    sim.step(ticks_of(&card, 2.1)); // X coasts to rest (or the maximum stop time passes)
    assert_eq!(g.reset().unwrap_err().kind(), ErrorKind::InvalidState);
    for ax in [&x, &y] {
        ax.reset().unwrap();
        ax.enable().unwrap();
    }
    g.reset().unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Standby);

    // Category 1: X reaches its limit switch; Y decelerates on its own stop ramp, its
    // commanded velocity changing by no more than the ramp allows in any tick, then is
    // disabled at rest.
    let start = x.status().unwrap().command_position;
    let y_start = y.status().unwrap().command_position;
    sim.with_emulator(|e| {
        e.faults()
            .set_switches(0, Switches::limits(-1e9, start + 150_000.0))
    });
    let s = SafetySettings::default();
    let m = g
        .move_linear(
            &[start + 400_000.0, y_start + 300_000.0],
            &feed,
            MoveOptions::default(),
        )
        .unwrap();
    let mut prev_v = y.status().unwrap().command_velocity;
    let mut worst_dv: f64 = 0.0;
    let mut tripped_at = None;
    for _ in 0..ticks_of(&card, 3.0) {
        sim.step(1);
        let sy = y.status().unwrap();
        worst_dv = worst_dv.max((sy.command_velocity - prev_v).abs());
        prev_v = sy.command_velocity;
        if tripped_at.is_none() && sy.state == AxisState::ErrorStop {
            let sx = x.status().unwrap();
            assert_eq!(sx.stop_reason(), Some(StopReason::HardLimitPos));
            assert_eq!(sx.raw.tick, sy.raw.tick);
            assert!(sy.drive_enabled(), "category 1 keeps power while it ramps");
            assert!(sy.command_velocity.abs() > 10_000.0, "Y was moving");
            tripped_at = Some(sy.raw.tick);
        }
    }
    assert!(tripped_at.is_some(), "X never reached its limit");
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    // Under the feed's own acceleration or the stop ramp's deceleration, whichever is larger.
    assert!(
        worst_dv <= 2e6_f64.max(s.stop_deceleration) * ts * (1.0 + 1e-9),
        "Y's velocity jumped by {worst_dv} counts/s in one tick"
    );
    let sy = y.status().unwrap();
    assert_eq!(sy.stop_reason(), Some(StopReason::Group));
    assert_eq!((sy.command_velocity, sy.drive_enabled()), (0.0, false));
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
}

/// The session this host opened, as the card knows it.
fn session(card: &Card) -> u32 {
    card.safety_status().unwrap().session
}

fn raw_answer(card: &Card, cmd: Command) -> Option<NackCode> {
    let seq = card.send_raw(cmd).unwrap();
    card.wait_ack(seq).unwrap().err()
}

fn session_command(op: Opcode, session: u32) -> Command {
    let mut c = Command::new(op, 0);
    c.flags = session;
    c
}

/// Issue 31: a host detaches its own session through `send_raw` and keeps the card open,
/// then starts 4 velocity moves at ±100,000 counts/s. Outside a session the card refuses each
/// (`NoSession`) and nothing moves, however long the card runs: the status shows every axis
/// at rest with no session and no watchdog, and a host that then falls silent trips nothing.
/// The typed calls meet the same gate; stops and reads still work.
#[test]
fn a_detached_session_moves_nothing() {
    use motioncard_sdk::VelocityLimits;
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let axes: Vec<_> = (0..4).map(|a| card.axis(a).unwrap()).collect();
    for ax in &axes {
        ax.enable().unwrap();
    }
    sim.step(10);
    let own = session(&card);
    assert_ne!(own, 0);
    assert_eq!(
        raw_answer(&card, session_command(Opcode::HostDetach, own)),
        None
    );
    for (a, ax) in axes.iter().enumerate() {
        let v = if a % 2 == 0 { 100_000.0 } else { -100_000.0 };
        let mv = Command::new(Opcode::MoveVelocity, a as u16).with_args(&[v, 1e6, 1e6, 1e8]);
        assert_eq!(raw_answer(&card, mv), Some(NackCode::NoSession), "axis {a}");
        let e = ax
            .move_velocity(v, &VelocityLimits::new(1e6, 1e8))
            .unwrap_err();
        assert_eq!(e.kind(), ErrorKind::NoSession, "axis {a}: {e}");
        assert_eq!(
            ax.jog(1000.0).unwrap_err().kind(),
            ErrorKind::NoSession,
            "axis {a}"
        );
    }
    // Power, outputs, configuration and resets: refused the same way. Stops and reads: taken.
    assert_eq!(
        card.axis(5).unwrap().enable().unwrap_err().kind(),
        ErrorKind::NoSession
    );
    assert_eq!(
        card.set_outputs(1, 1).unwrap_err().kind(),
        ErrorKind::NoSession
    );
    assert_eq!(
        card.set_watchdog_timeout(Duration::from_secs(5))
            .unwrap_err()
            .kind(),
        ErrorKind::NoSession
    );
    assert_eq!(
        axes[0].set_override(0.5).unwrap_err().kind(),
        ErrorKind::NoSession
    );
    card.ping().unwrap();
    axes[0].settings().unwrap();
    axes[1].halt(1e6, 1e8).unwrap();
    // 11.5 s later (the measurement), and with the host silent: nothing moved.
    card.set_heartbeat(false);
    sim.step(ticks_of(&card, 11.5));
    let st = card.safety_status().unwrap();
    assert_eq!((st.session, st.watchdog_armed), (0, false));
    assert!(!st.watchdog_tripped);
    for (a, ax) in axes.iter().enumerate() {
        let s = ax.status().unwrap();
        assert_eq!(s.state, AxisState::Standstill, "axis {a}");
        assert_eq!(
            (s.command_velocity, s.raw.move_count),
            (0.0, (a == 1) as u32),
            "axis {a}"
        );
        assert!(s.actual_velocity.abs() < 1.0, "axis {a}: {s:?}");
    }
}

/// A detach stops what its session started, whatever drives it: a jog, velocity mode, a
/// position move, homing, a geared slave, a PT/PVT stream and a group's move all halt on
/// the stop ramps and come to rest, no fault latched and nothing in ErrorStop; each axis's
/// status says why (`HostDetach`), which is what the next host reads.
#[test]
fn a_detach_stops_everything_its_session_started() {
    use motioncard_sdk::{
        GroupSettings, GroupState, HomingSettings, Master, MoveOptions, PathLimits, PvtLimits,
        PvtMode, PvtPoint, SyncLimits, VelocityLimits,
    };
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax: Vec<_> = (0..8).map(|a| card.axis(a).unwrap()).collect();
    for a in &ax {
        a.enable().unwrap();
    }
    let mut motions = Vec::new();
    motions.push(("jog", ax[0].jog(20_000.0).unwrap()));
    motions.push((
        "velocity",
        ax[1]
            .move_velocity(-50_000.0, &VelocityLimits::new(5e5, 5e7))
            .unwrap(),
    ));
    motions.push((
        "move",
        ax[2]
            .move_relative(1e7, &MoveLimits::new(1e5, 1e6, 1e8))
            .unwrap(),
    ));
    // Homing on the negative limit switch, which this machine does not have: it searches.
    ax[3]
        .configure_homing(&HomingSettings {
            method: 17,
            ..HomingSettings::default()
        })
        .unwrap();
    motions.push(("homing", ax[3].home(0.0).unwrap()));
    // Axis 4 geared 1:2 to the jogging axis 0.
    motions.push((
        "gear",
        ax[4]
            .gear_in(Master::Commanded(0), 1, 2, &SyncLimits::new(2e5, 2e6, 2e8))
            .unwrap(),
    ));
    // A PT/PVT stream of 5 s on axis 5.
    let pts: Vec<PvtPoint> = (1..=50)
        .map(|k| PvtPoint::new(0.1 * k as f64, 1000.0 * k as f64, 10_000.0))
        .collect();
    let lim = PvtLimits {
        velocity: 40_000.0,
        acceleration: 4e5,
    };
    ax[5].pvt_begin(PvtMode::Pt, &lim, 0).unwrap();
    ax[5].pvt_push(&pts, true).unwrap();
    motions.push(("pvt", ax[5].pvt_start().unwrap()));
    // A group line over axes 6 and 7.
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[6, 7])).unwrap();
    g.enable().unwrap();
    let gm = g
        .move_linear(
            &[2e6, -1e6],
            &PathLimits::new(50_000.0, 5e5, 5e7),
            MoveOptions::default(),
        )
        .unwrap();
    sim.step(3000);
    let moving = [
        AxisState::ContinuousMotion,
        AxisState::ContinuousMotion,
        AxisState::DiscreteMotion,
        AxisState::Homing,
        AxisState::SynchronizedMotion,
        AxisState::SynchronizedMotion,
        AxisState::SynchronizedMotion,
        AxisState::SynchronizedMotion,
    ];
    for (a, want) in moving.iter().enumerate() {
        let s = ax[a].status().unwrap();
        assert_eq!(s.state, *want, "axis {a} before the detach");
        assert!(
            s.command_velocity.abs() > 1000.0,
            "axis {a} not moving: {s:?}"
        );
    }

    let own = session(&card);
    assert_eq!(
        raw_answer(&card, session_command(Opcode::HostDetach, own)),
        None
    );
    sim.step(ticks_of(&card, 2.5)); // the maximum stop time, and settling
    let st = card.safety_status().unwrap();
    assert_eq!((st.session, st.watchdog_armed), (0, false));
    assert!(
        !st.watchdog_tripped && !st.estop_command && !st.estop_input,
        "{st:?}"
    );
    for (a, axis) in ax.iter().enumerate() {
        let s = axis.status().unwrap();
        assert_eq!(s.state, AxisState::Standstill, "axis {a}: {s:?}");
        assert_eq!(s.command_velocity, 0.0, "axis {a}");
        assert!(s.drive_enabled(), "axis {a}: power kept, no fault");
        assert_eq!(s.stop_reason(), Some(StopReason::HostDetach), "axis {a}");
    }
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    for (what, m) in &motions {
        let e = m.wait(Duration::ZERO).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Aborted, "{what}: {e}");
    }
    assert_eq!(
        gm.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    // Nothing starts again: the session is gone.
    assert_eq!(ax[0].jog(1000.0).unwrap_err().kind(), ErrorKind::NoSession);
}

/// A host that attaches by a raw command (its own session again, after a raw detach) has its
/// watchdog armed by the attach itself, before any heartbeat: if it then falls silent with an
/// axis moving, the watchdog stops the axis the timeout after the attach at the latest.
#[test]
fn a_raw_attach_arms_the_watchdog_at_once() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let own = session(&card);
    assert_eq!(
        raw_answer(&card, session_command(Opcode::HostDetach, own)),
        None
    );
    assert!(!card.safety_status().unwrap().watchdog_armed);
    // Silent from now on: no beat between the attach and the trip.
    card.set_heartbeat(false);
    assert_eq!(
        raw_answer(&card, session_command(Opcode::HostAttach, own)),
        None
    );
    let st = card.safety_status().unwrap();
    assert_eq!(st.session, own);
    assert!(st.watchdog_armed, "armed by the attach");
    assert_eq!(st.last_heartbeat_tick, st.attach_tick);
    let m = ax
        .move_velocity(100_000.0, &motioncard_sdk::VelocityLimits::new(1e6, 1e8))
        .unwrap();
    let timeout = ticks_of(
        &card,
        motioncard_sdk::WATCHDOG_TIMEOUT_DEFAULT.as_secs_f64(),
    );
    sim.step(timeout + 1);
    let st = card.safety_status().unwrap();
    assert!(st.watchdog_tripped);
    assert_eq!(st.watchdog_trip_tick - st.attach_tick, timeout);
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::ErrorStop);
    assert_eq!(s.stop_reason(), Some(StopReason::Watchdog));
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
}
