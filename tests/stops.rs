//! Bounded stops, on the stepped card: every stop ends within the card's maximum stop time
//! from any state, whatever ramp it was given; the watchdog trips and stops on time from every
//! phase of a profile; and a second writer on the command ring is reported, never silent.
mod common;

use common::{stepped_card_with, Rng};
use motioncard_sdk::proto::{Command, Faults, Opcode};
use motioncard_sdk::{
    AxisState, Card, EmuOptions, ErrorKind, EventKind, MoveLimits, StopReason,
    WATCHDOG_TIMEOUT_DEFAULT,
};
use std::time::Duration;

fn ticks_of(card: &Card, secs: f64) -> u64 {
    (secs * card.info().servo_rate_hz as f64).round() as u64
}

fn one_axis() -> Card {
    stepped_card_with(EmuOptions::new(1, 10_000))
}

/// A value anywhere in f64: subnormal, tiny, ordinary, huge, or an edge of the card's range.
fn any_limit(rng: &mut Rng, order: i32) -> f64 {
    let range = firmware_proto::limit_range(order, 10_000);
    match rng.next_u64() % 8 {
        0 => f64::from_bits(rng.next_u64() % (1 << 52)), // subnormal (or 0)
        1 => rng.log_uniform(1e-300, 1e-30),
        2 => rng.log_uniform(1e30, 1e300),
        3 => {
            *range.start()
                * if rng.next_u64().is_multiple_of(2) {
                    1.0
                } else {
                    0.999_999
                }
        }
        4 => {
            *range.end()
                * if rng.next_u64().is_multiple_of(2) {
                    1.0
                } else {
                    1.000_001
                }
        }
        _ => rng.log_uniform(1e3_f64.powi(order), 1e3_f64.powi(order + 2)),
    }
}

/// Back to an enabled axis at rest (after a safety stop: once it is at rest, at the latest
/// the maximum stop time after it began).
fn ready(card: &Card) {
    let ax = card.axis(0).unwrap();
    let s = ax.status().unwrap();
    if s.state == AxisState::ErrorStop {
        let sim = card.sim().unwrap();
        for _ in 0..30_000 {
            if ax.stop_info().unwrap().rest_tick.is_some() {
                break;
            }
            sim.step(1);
        }
        sim.step(1);
        card.reset_faults().unwrap();
    }
    if ax.status().unwrap().state == AxisState::Disabled {
        ax.enable().unwrap();
    }
}

/// Halts with ramps from anywhere in f64, at random moments of random moves: each is refused
/// (a limit outside the card's range), or the axis is at rest, or without power, within the
/// maximum stop time of the halt. A ramp too slow for the bound runs on the axis's stop ramp;
/// what even that cannot stop in time loses power at the bound.
#[test]
fn every_halt_ends_within_the_maximum_stop_time() {
    let card = one_axis();
    let sim = card.sim().unwrap();
    // The default stop ramp (5e6 counts/s^2) cannot stop the fastest moves in 0.3 s.
    card.set_max_stop_time(Duration::from_millis(300)).unwrap();
    let bound = ticks_of(&card, 0.3);
    let ax = card.axis(0).unwrap();
    // The seed decides how often each outcome comes up; a cut at the bound is rare (0 to 2 in
    // 800 cases over seeds 1..6): this one has two.
    let mut rng = Rng::new(1);
    let (mut refused, mut halted, mut cut, mut hardened, mut tripped) = (0, 0, 0, 0, 0);
    for case in 0..800 {
        ready(&card);
        let lim = MoveLimits::new(
            rng.log_uniform(1e4, 3e6),
            rng.log_uniform(1e6, 6e6), // what the default plant can follow
            rng.log_uniform(1e8, 1e10),
        );
        let d = rng.uniform(1e5, 3e6)
            * if rng.next_u64().is_multiple_of(2) {
                1.0
            } else {
                -1.0
            };
        let m = match ax.move_relative(d, &lim) {
            Ok(m) => m,
            Err(e) => {
                panic!("case {case}: move {e}");
            }
        };
        let planned = ax.status().unwrap().raw.planned_time;
        // Halted at any moment of its first second: accelerating, cruising or decelerating.
        sim.step(1 + rng.next_u64() % ticks_of(&card, planned.min(1.0)));
        if ax.status().unwrap().state == AxisState::ErrorStop {
            continue; // the plant could not follow the move (a following-error trip)
        }
        let (dmax, jerk) = (any_limit(&mut rng, 2), any_limit(&mut rng, 3));
        let h = match ax.halt(dmax, jerk) {
            Err(e) => {
                assert!(
                    matches!(
                        e.kind(),
                        ErrorKind::LimitRange | ErrorKind::NonPositiveLimit
                    ),
                    "case {case}: halt({dmax:e}, {jerk:e}): {e}"
                );
                refused += 1;
                let _ = m;
                if ax.status().unwrap().state == AxisState::DiscreteMotion {
                    // (done, or cut at the bound when too fast for the stop ramp)
                    let _ = ax.halt(5e6, 5e8).unwrap().wait(Duration::from_secs(2));
                }
                continue;
            }
            Ok(h) => h,
        };
        let s = ax.status().unwrap();
        let v0 = s.command_velocity.abs();
        if s.raw.planned_time < v0 / dmax {
            hardened += 1; // the given ramp would have taken longer than the card's one
        }
        sim.step(bound + 1);
        let s = ax.status().unwrap();
        let ended = match s.state {
            AxisState::Standstill | AxisState::DiscreteMotion => {
                s.command_velocity == 0.0 && s.command_acceleration == 0.0
            }
            AxisState::ErrorStop => !s.drive_enabled(),
            _ => false,
        };
        assert!(
            ended,
            "case {case}: halt({dmax:e}, {jerk:e}) from {v0:e} counts/s still running after \
             the bound: {:?} at {} counts/s",
            s.state, s.command_velocity
        );
        if s.stop_reason() == Some(StopReason::StopTimeout) {
            assert!(s.faults.contains(Faults::STOP_TIMEOUT));
            cut += 1;
        } else if s.state == AxisState::ErrorStop {
            // The plant could not follow the card's hard ramp: its own safety stop.
            tripped += 1;
        } else {
            h.wait(Duration::from_secs(1)).unwrap();
            halted += 1;
        }
    }
    println!(
        "halts over the whole f64 range: {refused} refused, {halted} at rest ({hardened} on the \
         card's stop ramp), {cut} cut at the bound, {tripped} tripped by the plant"
    );
    assert!(refused > 200 && halted > 80 && hardened > 15 && cut > 0);
}

/// A category 1 stop the stop ramp cannot finish in time (the axis runs faster than the
/// `max_velocity` the ramp was sized for): power goes at the bound, the reason stays the one
/// that tripped it.
#[test]
fn a_safety_stop_still_running_at_the_bound_loses_power_there() {
    let card = one_axis();
    let sim = card.sim().unwrap();
    card.set_max_stop_time(Duration::from_millis(250)).unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    // 2.5e6 counts/s: the default stop ramp (5e6 counts/s^2) needs 0.5 s.
    ax.move_relative(1e7, &MoveLimits::new(2.5e6, 5e6, 2e8))
        .unwrap();
    sim.step(ticks_of(&card, 0.7));
    assert_eq!(ax.status().unwrap().command_velocity, 2.5e6);
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    card.estop(motioncard_sdk::StopCategory::Cat1).unwrap();
    let info = ax.stop_info().unwrap();
    assert!(info.ramp_time > Duration::from_millis(500), "{info:?}");
    sim.step(ticks_of(&card, 0.25) - 1);
    assert!(
        ax.status().unwrap().drive_enabled(),
        "powered until the bound"
    );
    sim.step(1);
    let s = ax.status().unwrap();
    assert!(
        !s.drive_enabled() && s.dac_volts == 0.0,
        "power removed at the bound"
    );
    assert_eq!(s.stop_reason(), Some(StopReason::EStopCommand));
    let ev: Vec<_> = std::iter::from_fn(|| card.next_event(Duration::ZERO).unwrap()).collect();
    let overran = ev
        .iter()
        .find(|e| e.kind == EventKind::SafetyStop && e.code == StopReason::StopTimeout as i32)
        .expect("a stop-timeout event");
    assert_eq!(overran.tick - info.stop_tick, ticks_of(&card, 0.25));
}

/// The watchdog from every phase of a profile (jerk up, constant acceleration, jerk down,
/// cruise, deceleration), the heartbeat stopped at every third tick of a move:
/// - the watchdog trips exactly its timeout after the last heartbeat;
/// - the stop ramp's commanded motion ends ⌈ramp⌉ ticks after the trip (± the one tick the
///   sum of servo periods may round to);
/// - the axis is at rest, drive off, within the maximum stop time of the trip.
///
/// That is the bound the card guarantees: timeout + maximum stop time after the last
/// heartbeat; in practice timeout + ramp + the few ticks the drive takes to settle after the
/// commanded motion ended (reported here).
#[test]
fn the_watchdog_stops_on_time_from_every_phase_of_a_profile() {
    let card = one_axis();
    let sim = card.sim().unwrap();
    card.set_watchdog_timeout(Duration::from_millis(2)).unwrap();
    let timeout = ticks_of(&card, 0.002);
    let max_stop = ticks_of(&card, 2.0);
    let ax = card.axis(0).unwrap();
    let lim = MoveLimits::new(400_000.0, 4e6, 2e8);
    let (mut runs, mut settle_max, mut beyond_ramp) = (0, 0u64, 0);
    let mut settle_hist = [0u32; 8]; // ticks after the ramp's end: 0, 1, 2, 3, 4..7, 8..15, ...
    let mut k = 1;
    loop {
        ready(&card);
        let m = ax.move_relative(50_000.0, &lim).unwrap();
        let planned = ticks_of(&card, ax.status().unwrap().raw.planned_time);
        if k > planned {
            m.wait(Duration::from_secs(5)).unwrap();
            break;
        }
        sim.step(k);
        card.set_heartbeat(false);
        let mut ticks = 0;
        while !card.safety_status().unwrap().watchdog_tripped {
            sim.step(1);
            ticks += 1;
            assert!(ticks <= timeout + 1, "kill at {k}: no trip");
        }
        let st = card.safety_status().unwrap();
        assert_eq!(
            st.watchdog_trip_tick - st.trip_heartbeat_tick,
            timeout,
            "kill at {k}"
        );
        let info = ax.stop_info().unwrap();
        let ramp = (info.ramp_time.as_secs_f64() * 10_000.0).ceil() as u64;
        let mut end = None;
        let mut n = 0;
        while ax.stop_info().unwrap().rest_tick.is_none() {
            sim.step(1);
            n += 1;
            let s = ax.status().unwrap();
            if end.is_none() && s.command_velocity == 0.0 && s.command_acceleration == 0.0 {
                end = Some(s.raw.tick);
            }
            assert!(
                n <= max_stop + 1,
                "kill at {k}: not at rest within the maximum stop time"
            );
        }
        let rest = ax.stop_info().unwrap().rest_tick.unwrap();
        let end = end.unwrap_or(rest);
        let ramp_end = end - info.stop_tick;
        // (the time into the ramp is a sum of servo periods: one tick of rounding either way)
        assert!(
            ramp_end <= ramp + 1 && ramp_end + 1 >= ramp,
            "kill at {k}: the ramp ended {ramp_end} ticks after the trip, planned {ramp}"
        );
        let s = ax.status().unwrap();
        assert!(!s.drive_enabled() && s.stop_reason() == Some(StopReason::Watchdog));
        let settle = rest - end; // the drive settling after the commanded motion ended
        settle_max = settle_max.max(settle);
        beyond_ramp += usize::from(settle > 0);
        let bin = match settle {
            0..=3 => settle as usize,
            _ => (4 + (settle.ilog2() - 2) as usize).min(7),
        };
        settle_hist[bin] += 1;
        card.set_heartbeat(true);
        sim.step(1);
        runs += 1;
        k += 3;
    }
    println!(
        "watchdog (2 ms) from {runs} moments of a move: tripped on time every run; drive off \
         at the ramp's end + 0..{settle_max} ticks ({beyond_ramp} runs later than the ramp's \
         end); settle histogram [0,1,2,3,4-7,8-15,16-31,32+] ticks: {settle_hist:?}"
    );
    assert!(runs > 250);
    assert!(settle_max < max_stop);
    let _ = WATCHDOG_TIMEOUT_DEFAULT;
}

/// Another process writing into this card's command ring (it mapped the window; the lease
/// does not stop that): this host's next command is refused before it is sent, with a
/// protocol error that says why, and when the other writer leaves the ring corrupt the card
/// stops every axis and the motion's waiter is told it was aborted by a protocol error.
#[test]
fn a_second_writer_on_the_command_ring_is_reported_not_silent() {
    use firmware_proto::ring::{CmdProducer, CMD_RING};
    use firmware_proto::{layout, Mem};
    let card = one_axis();
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(1e6, &MoveLimits::new(2e5, 2e6, 2e8))
        .unwrap();
    sim.step(100);
    let window = sim.with_emulator(|e| e.window().clone());
    // A well-formed command from elsewhere: the card runs it, but this host's view of the
    // ring is now wrong. Its next command is refused, nothing sent.
    let mut rogue = CmdProducer::attach(window.clone(), CMD_RING);
    rogue.push(&Command::new(Opcode::Nop, 0)).unwrap();
    let e = card.ping().unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Protocol);
    assert!(e.to_string().contains("another process"), "{e}");
    card.ping().unwrap(); // the host follows the ring again
                          // Garbage: a head far beyond anything written. The card stops every axis.
    window.write32(
        layout::CMD_HEAD,
        window.read32(layout::CMD_TAIL).wrapping_add(1000),
    );
    sim.step(1);
    let e = m.wait(Duration::from_secs(1)).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Aborted);
    assert!(e.to_string().contains("protocol"), "{e}");
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::ErrorStop);
    assert_eq!(s.stop_reason(), Some(StopReason::CmdRing));
    assert!(card.safety_status().unwrap().protocol_errors >= 1);
}

/// A clean close disarms the watchdog for good: beats the closing host still sends after its
/// detach (its heartbeat thread stops a moment later) do not arm it again, so the silence that
/// follows never trips it. Only the next attach arms it.
#[test]
fn heartbeats_after_a_detach_do_not_rearm_the_watchdog() {
    let card = one_axis();
    let sim = card.sim().unwrap();
    sim.step(10);
    let st = card.safety_status().unwrap();
    assert!(st.watchdog_armed);
    let mut detach = Command::new(Opcode::HostDetach, 0);
    detach.flags = st.session;
    let seq = card.send_raw(detach).unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Ok(()));
    sim.step(10); // still beating
    let st = card.safety_status().unwrap();
    assert!(!st.watchdog_armed && st.session == 0);
    card.set_heartbeat(false);
    sim.step(ticks_of(&card, 0.5));
    assert!(!card.safety_status().unwrap().watchdog_tripped);
}
