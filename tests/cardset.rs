//! Layout 1.12: cards on one sync bus, on the stepped clock. Four in-process cards of 8 axes:
//! their tick counters equal; a synchronised start of all 32 axes on one tick, every axis's
//! commanded trajectory bit-identical to the others' and to a lone card's; a timing that reaches
//! one card late, or a commit after the tick, and nothing moves on any card; a synchronised
//! hold and halt.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, BusRole, BusState, CardSet, Clock, EmuOptions, ErrorKind, EventKind, MoveLimits,
    SimOptions, StopReason,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(30);

fn limits() -> MoveLimits {
    MoveLimits::new(50_000.0, 1e6, 1e8)
}

fn set(n: usize) -> CardSet {
    let set = CardSet::sim(
        n,
        SimOptions {
            clock: Clock::Stepped,
            emu: EmuOptions::new(8, RATE),
        },
    )
    .unwrap();
    for c in set.cards() {
        for a in 0..8 {
            c.axis(a).unwrap().enable().unwrap();
        }
    }
    set
}

/// Every card reports its place on the bus; stepping any one card steps all of them, so
/// their tick counters never differ.
#[test]
fn four_cards_share_one_clock() {
    let set = set(4);
    let names: Vec<String> = set
        .cards()
        .iter()
        .map(|c| c.bus_status().unwrap().name)
        .collect();
    assert_eq!(names, ["sim0", "sim1", "sim2", "sim3"]);
    set.cards()[2].sim().unwrap().step(1);
    let m = set.cards()[0].bus_status().unwrap();
    assert_eq!(
        (m.role, m.state, m.followers),
        (BusRole::Master, BusState::Free, 3)
    );
    for c in &set.cards()[1..] {
        let s = c.bus_status().unwrap();
        assert_eq!(
            (s.role, s.state, s.master.as_str()),
            (BusRole::Follower, BusState::Locked, "sim0")
        );
    }
    for k in 0..4 {
        set.cards()[k].sim().unwrap().step(37 + k as u64);
        let ticks: Vec<u64> = set.cards().iter().map(|c| c.tick().unwrap()).collect();
        assert!(ticks.iter().all(|&t| t == ticks[0]), "{ticks:?}");
    }
    // A set whose first card is a follower is refused.
    let cards = set.cards().to_vec();
    let reversed = vec![cards[1].clone(), cards[0].clone()];
    assert_eq!(
        CardSet::new(reversed).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
}

/// 32 axes on 4 cards start on one tick: each card posts `Timed` for each move with that
/// tick, and every axis's commanded position is, tick by tick, bit-identical to every other's
/// and to the same move started on a lone card.
#[test]
fn a_synchronised_start_of_32_axes_starts_every_axis_on_one_tick() {
    let set = set(4);
    let lim = limits();
    let (tick, motions) = set
        .sync(|| {
            let mut v = Vec::new();
            for c in set.cards() {
                for a in 0..8 {
                    v.push(c.axis(a)?.move_absolute(20_000.0, &lim)?);
                }
            }
            Ok(v)
        })
        .unwrap();
    assert_eq!(motions.len(), 32);
    for c in set.cards() {
        let mut timed = Vec::new();
        while let Some(e) = c.next_event(Duration::ZERO).unwrap() {
            if e.kind == EventKind::Timed {
                timed.push(e.tick);
            }
        }
        assert_eq!(
            timed,
            vec![tick; 8],
            "every move of the card ran on tick {tick}"
        );
    }
    // The reference: the same move on a lone card, from rest.
    let lone = stepped_card_with(EmuOptions::new(1, RATE));
    let ax = lone.axis(0).unwrap();
    ax.enable().unwrap();
    let sim = lone.sim().unwrap();
    let start = lone.tick().unwrap();
    ax.move_absolute(20_000.0, &lim).unwrap();
    // The lone move started between ticks `start` and `start + 1`, as the timed ones between
    // `tick - 1` and `tick`: compare tick by tick from there.
    let elapsed = set.tick().unwrap() - (tick - 1);
    sim.step(elapsed - (lone.tick().unwrap() - start));
    let mut steps = 0;
    loop {
        let reference = ax.status().unwrap().command_position;
        for c in set.cards() {
            for a in 0..8 {
                let p = c.axis(a).unwrap().status().unwrap().command_position;
                assert_eq!(
                    p.to_bits(),
                    reference.to_bits(),
                    "card axis {a} at step {steps}"
                );
            }
        }
        if reference == 20_000.0 || steps > 20_000 {
            break;
        }
        set.cards()[0].sim().unwrap().step(1);
        sim.step(1);
        steps += 1;
    }
    assert!(steps > 100, "the move ran ({steps} ticks)");
    for m in motions {
        assert_eq!(m.wait(LONG).unwrap(), 20_000.0);
    }
}

fn all_at_rest(set: &CardSet) -> bool {
    set.cards().iter().all(|c| {
        (0..8).all(|a| {
            let s = c.axis(a).unwrap().status().unwrap();
            s.state == AxisState::Standstill && s.command_position == 0.0
        })
    })
}

/// A timing that reaches one card after its tick (the clock stepped past it before the last
/// card got its command) is refused there (`TickPassed`), the key is cancelled on the others,
/// and nothing moves on any card. A commit that reaches the master on or after the tick is
/// refused (`CommitLate`) and nothing moves either: every held command is refused on its tick.
#[test]
fn a_late_timing_or_commit_moves_nothing_anywhere() {
    let set = set(4);
    let lim = limits();
    let master = set.cards()[0].sim().unwrap();
    let err = set
        .sync(|| {
            for (k, c) in set.cards().iter().enumerate() {
                if k == 3 {
                    master.step(1_000); // the last card's command comes too late
                }
                c.axis(0)?.move_absolute(5_000.0, &lim)?;
            }
            Ok(())
        })
        .unwrap_err();
    assert_eq!(err.kind(), ErrorKind::TickPassed, "{err}");
    master.step(500);
    assert!(all_at_rest(&set));
    for c in set.cards() {
        assert_eq!(c.bus_status().unwrap().timed_held, 0, "cancelled");
    }
    // The commit too late: every card took its command, the master gets the commit after
    // the tick.
    let err = set
        .sync(|| {
            for c in set.cards() {
                c.axis(1)?.move_absolute(5_000.0, &lim)?;
            }
            master.step(1_000);
            Ok(())
        })
        .unwrap_err();
    assert_eq!(err.kind(), ErrorKind::CommitLate, "{err}");
    master.step(500);
    assert!(all_at_rest(&set));
}

/// A synchronised hold brings every moving axis of every card to rest with override 0 on one
/// tick, and a synchronised override of 1 resumes them together; a synchronised halt stops
/// them on one tick.
#[test]
fn a_synchronised_hold_and_halt_act_on_one_tick() {
    let set = set(2);
    let lim = limits();
    let (_, motions) = set
        .sync(|| {
            let mut v = Vec::new();
            for c in set.cards() {
                for a in 0..8 {
                    v.push(c.axis(a)?.move_absolute(200_000.0, &lim)?);
                }
            }
            Ok(v)
        })
        .unwrap();
    let sim = set.cards()[0].sim().unwrap();
    sim.step(3_000);
    let hold = set.hold().unwrap();
    sim.step(2_000);
    let held: Vec<f64> = set
        .cards()
        .iter()
        .flat_map(|c| (0..8).map(move |a| c.axis(a).unwrap().status().unwrap()))
        .map(|s| {
            assert_eq!(s.command_velocity, 0.0);
            s.command_position
        })
        .collect();
    assert!(
        held.iter().all(|p| p.to_bits() == held[0].to_bits()),
        "{held:?}"
    );
    assert!(held[0] < 200_000.0);
    set.set_override(1.0).unwrap();
    sim.step(500);
    let halt = set.halt(1e6, 1e8).unwrap();
    assert!(halt > hold);
    for m in motions {
        let e = m.wait(LONG).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Aborted, "{e}");
    }
    let ends: Vec<(f64, StopReason)> = set
        .cards()
        .iter()
        .flat_map(|c| (0..8).map(move |a| c.axis(a).unwrap()))
        .map(|a| {
            (
                a.status().unwrap().command_position,
                a.stop_reason().unwrap(),
            )
        })
        .collect();
    assert!(
        ends.iter().all(|e| e.0.to_bits() == ends[0].0.to_bits()),
        "{ends:?}"
    );
    assert!(ends.iter().all(|e| e.1 == StopReason::Halt), "{ends:?}");
}
