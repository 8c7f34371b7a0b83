//! Layout 1.12: `card-emu` processes on one sync bus (`--sync-from`). The followers' tick
//! counters track the master's (never ahead, not drifting); a synchronised start across
//! processes starts both axes on one tick; a follower whose master is killed halts its motion
//! on its stop ramp (reason `SyncLost`) within the stop bound and says it lost the master.
mod common;

use common::{card_emu, open_when_ready, Proc};
use motioncard_sdk::{
    AxisState, BusRole, BusState, CardSet, ErrorKind, EventKind, MoveLimits, StopReason,
    VelocityLimits,
};
use std::time::{Duration, Instant};

fn bus(tag: &str, followers: usize) -> (Vec<Proc>, Vec<String>) {
    let master = format!("bus{tag}-{}", std::process::id());
    let mut procs = vec![card_emu(&master, &["--axes", "2", "--serial", "100"])];
    let mut names = vec![master.clone()];
    for k in 0..followers {
        let n = format!("{master}-f{k}");
        procs.push(card_emu(&n, &["--axes", "2", "--sync-from", &master]));
        names.push(n);
    }
    (procs, names)
}

/// The followers never run ahead of the master (a follower read before the master reads at
/// most the master's tick) and keep up with it: over half a second of samples their lag stays
/// a few ticks at most (the followers run once woken; the lag is scheduling, not drift).
#[test]
fn followers_track_the_masters_tick_and_report_their_place() {
    let (_procs, names) = bus("t", 2);
    let cards: Vec<_> = names
        .iter()
        .map(|n| open_when_ready(&format!("emu:{n}")))
        .collect();
    let set = CardSet::new(cards.clone()).unwrap();
    let m = cards[0].bus_status().unwrap();
    assert_eq!((m.role, m.followers, m.serial), (BusRole::Master, 2, 100));
    for (c, n) in cards[1..].iter().zip(&names[1..]) {
        let s = c.bus_status().unwrap();
        assert_eq!((s.role, s.state), (BusRole::Follower, BusState::Locked));
        assert_eq!(
            (s.name.as_str(), s.master.as_str()),
            (n.as_str(), names[0].as_str())
        );
    }
    let mut lags = Vec::new();
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_millis(500) {
        let f: Vec<u64> = cards[1..].iter().map(|c| c.tick().unwrap()).collect();
        let m = set.tick().unwrap();
        for t in f {
            assert!(t <= m, "a follower ran ahead: {t} > {m}");
            lags.push(m - t);
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    lags.sort_unstable();
    let median = lags[lags.len() / 2];
    eprintln!("lag: median {median}, max {} ticks", lags[lags.len() - 1]);
    assert!(median <= 2, "median lag {median} ticks");
}

/// A synchronised start across two processes: both axes of both cards start on one tick.
#[test]
fn a_synchronised_start_across_processes_starts_on_one_tick() {
    let (_procs, names) = bus("s", 1);
    let uris: Vec<String> = names.iter().map(|n| format!("emu:{n}")).collect();
    let cards: Vec<_> = uris.iter().map(|u| open_when_ready(u)).collect();
    let set = CardSet::new(cards).unwrap();
    let lim = MoveLimits::new(1e5, 1e6, 1e8);
    for c in set.cards() {
        for a in 0..2 {
            c.axis(a).unwrap().enable().unwrap();
        }
    }
    let (tick, motions) = set
        .sync(|| {
            let mut v = Vec::new();
            for c in set.cards() {
                for a in 0..2 {
                    v.push(c.axis(a)?.move_absolute(3_000.0, &lim)?);
                }
            }
            Ok(v)
        })
        .unwrap();
    for m in motions {
        assert_eq!(m.wait(Duration::from_secs(10)).unwrap(), 3_000.0);
    }
    for c in set.cards() {
        let mut ticks = Vec::new();
        while let Some(e) = c.next_event(Duration::ZERO).unwrap() {
            if e.kind == EventKind::Timed {
                ticks.push(e.tick);
            }
        }
        assert_eq!(ticks, [tick, tick]);
    }
}

/// The master killed: the follower halts its moving axis on its stop ramp, reason
/// `SyncLost`, and is at rest within the stop bound (its ramp from the speed it ran plus the
/// slack for a loaded machine: the connection's hang-up is seen at once, no timeout); it reports the
/// loss and keeps running on its own clock (its tick goes on, its host can go on).
#[test]
fn a_follower_whose_master_dies_halts_within_the_stop_bound() {
    let (mut procs, names) = bus("k", 1);
    let follower = open_when_ready(&format!("emu:{}", names[1]));
    let ax = follower.axis(0).unwrap();
    ax.enable().unwrap();
    let v = 50_000.0;
    ax.move_velocity(v, &VelocityLimits::new(1e6, 1e8))
        .unwrap()
        .wait_in_velocity(Duration::from_secs(5))
        .unwrap();
    let t_kill = Instant::now();
    procs[0].0.kill().unwrap();
    procs[0].0.wait().unwrap();
    let bound = Duration::from_millis(100 + 300);
    loop {
        let s = ax.status().unwrap();
        if s.state == AxisState::Standstill && s.command_velocity == 0.0 {
            break;
        }
        assert!(
            t_kill.elapsed() < bound * 4,
            "still moving {:?} after the master died",
            t_kill.elapsed()
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    let took = t_kill.elapsed();
    eprintln!("at rest {took:?} after the master's death");
    assert!(took < bound, "{took:?} > {bound:?}");
    assert_eq!(ax.stop_reason().unwrap(), StopReason::SyncLost);
    let s = follower.bus_status().unwrap();
    assert_eq!((s.state, s.losses), (BusState::Lost, 1));
    let t = follower.tick().unwrap();
    std::thread::sleep(Duration::from_millis(20));
    assert!(follower.tick().unwrap() > t, "its own clock runs");
    // Nothing can be timed on it any more.
    let at = motioncard_sdk::Timing {
        tick: follower.tick().unwrap() + 1_000,
        key: 0,
    };
    let e = follower
        .timed(at, || {
            ax.move_absolute(0.0, &MoveLimits::new(1e4, 1e5, 1e7))
        })
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::SyncLost);
}
