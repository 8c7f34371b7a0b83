//! Layout 1.12: `card-emu` processes on one sync bus (`--sync-from`). The followers' tick
//! counters track the master's (never ahead, not drifting); a synchronised start across
//! processes starts both axes on one tick; a follower whose master is killed halts its motion
//! on its stop ramp (reason `SyncLost`) within the stop bound and says it lost the master.
//! A host killed (SIGKILL) while it runs a path on every card of a bus, in each phase of the
//! path (accelerating, at its feed, in a corner blend, decelerating), stops every card's
//! axes within the watchdog timeout plus the stop ramp. A 12-axis path across two processes
//! moves every axis on every tick as one planner of all twelve does, to the last bit; a card
//! killed while such a path streams ends the stream with `CardGone` and the other is halted.
mod common;
#[path = "common/wide_path.rs"]
mod wide_path;

use common::{card_emu, host_ready, open_when_ready, start_host_role, Proc};
use motioncard_sdk::{
    AxisState, BusRole, BusState, CardSet, ErrorKind, EventKind, GroupSettings, GroupState,
    MoveLimits, PathSettings, Segment, StopReason, VelocityLimits,
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
/// most the master's tick) and tick in lock step with it: read between two reads of the
/// master that show the same tick, a follower's lag is 0 or 1 in most samples (the master
/// waits for them; a follower the OS holds back over `FOLLOWER_WAIT` is not waited for).
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
        for c in &cards[1..] {
            let (m1, t, m2) = (set.tick().unwrap(), c.tick().unwrap(), set.tick().unwrap());
            assert!(t <= m2, "a follower ran ahead: {t} > {m2}");
            if m1 == m2 {
                lags.push(m1 - t);
            }
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    lags.sort_unstable();
    let median = lags[lags.len() / 2];
    let within = lags.iter().filter(|&&l| l <= 1).count();
    eprintln!(
        "lag: median {median}, max {} ticks, {within} of {} samples 0 or 1",
        lags[lags.len() - 1],
        lags.len()
    );
    assert!(median <= 1, "median lag {median} ticks");
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

const HOST_CARDS: &str = "MC_BUS_HOST_CARDS";
const HOST_PHASE: &str = "MC_BUS_HOST_PHASE";
const HOST_TIMEOUT_MS: u64 = 100;
/// The servo's settling into the in-velocity window after a stop's command ramp, ticks.
const SETTLE_TICKS: f64 = 5.0;
/// The path's feed, counts/s, and its axes' limits.
const FEED: f64 = 200_000.0;
const PATH_LIMITS: (f64, f64, f64) = (300_000.0, 2e6, 2e8);

/// The host of `a_host_killed_mid_path_stops_every_cards_axes` (only when that test runs this
/// binary again with `MC_BUS_HOST_CARDS` set): opens the cards as a set, starts a blended
/// square on group 0 (axes 0 and 1) of every card on one tick, and prints `HOST-READY` once
/// the master's path is in the phase `MC_BUS_HOST_PHASE` names; then waits to be killed.
#[test]
fn bus_host_role() {
    let Ok(uris) = std::env::var(HOST_CARDS) else {
        return;
    };
    let phase = std::env::var(HOST_PHASE).unwrap();
    let cards: Vec<_> = uris.split(',').map(open_when_ready).collect();
    let set = CardSet::new(cards.clone()).unwrap();
    let (v, a, j) = PATH_LIMITS;
    let mut groups = Vec::new();
    for c in &cards {
        c.reset_faults().unwrap(); // the previous host's watchdog trip
        c.set_watchdog_timeout(Duration::from_millis(HOST_TIMEOUT_MS))
            .unwrap();
        for ax in 0..2 {
            c.axis(ax).unwrap().enable().unwrap();
        }
        let g = c.group(0).unwrap();
        // The previous host's path ended in the watchdog's stop.
        match g.status().unwrap().0 {
            GroupState::ErrorStop => g.reset().unwrap(),
            GroupState::Disabled => {}
            _ => g.disable().unwrap(),
        }
        if g.status().unwrap().0 != GroupState::Disabled {
            g.disable().unwrap();
        }
        g.configure(&GroupSettings::new(&[0, 1])).unwrap();
        g.enable().unwrap();
        g.configure_path(&PathSettings::uniform(2, v, a, j))
            .unwrap();
        groups.push(g);
    }
    // Each card's square starts where its axes stand (the previous run left them somewhere).
    let square = |at: [f64; 2]| {
        let d = 300_000.0;
        let corners = [[d, 0.0], [d, d], [0.0, d], [0.0, 0.0]];
        corners
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let s = Segment::line(k as u32 + 1, &[at[0] + c[0], at[1] + c[1]], FEED, 500.0);
                if k == 3 {
                    s.last().into()
                } else {
                    s.into()
                }
            })
            .collect::<Vec<motioncard_sdk::PathItem>>()
    };
    let starts: Vec<[f64; 2]> = cards
        .iter()
        .map(|c| {
            let p = |a| c.axis(a).unwrap().status().unwrap().command_position;
            [p(0), p(1)]
        })
        .collect();
    set.sync(|| {
        for (g, at) in groups.iter().zip(&starts) {
            for item in square(*at) {
                g.path_push(&item)?;
            }
        }
        Ok(())
    })
    .unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let (_, st) = groups[0].status().unwrap();
        let there = match phase.as_str() {
            "accelerating" => st.path_id == 1 && st.feed > 0.3 * FEED && st.feed_acc > 0.0,
            "at-feed" => st.path_id == 1 && st.feed >= 0.999 * FEED && st.path_pos > 100_000.0,
            // In the corner blend from the line along X to the line along Y: both move.
            "blending" => (0..2).all(|a| {
                let v = cards[0].axis(a).unwrap().status().unwrap().command_velocity;
                v.abs() > 0.1 * FEED
            }),
            "decelerating" => st.path_id == 4 && st.feed_acc < 0.0 && st.feed > 0.3 * FEED,
            p => panic!("unknown phase {p}"),
        };
        if there {
            break;
        }
        assert!(Instant::now() < deadline, "the path never got to {phase}");
        std::thread::sleep(Duration::from_micros(200));
    }
    host_ready();
}

/// A host running a path on both cards of a bus, killed in each phase of the path: on each
/// card the watchdog trips its timeout after the host's last heartbeat, and both axes are at
/// rest within that timeout plus their stop ramps (and `SETTLE_TICKS` of servo lag), reason
/// `Watchdog`, drives off, the fault latched until a host resets it.
#[test]
fn a_host_killed_mid_path_stops_every_cards_axes() {
    // The host drives the master and one follower; the test holds a second follower, whose
    // tick is the bus's (the master's or one less): it waits in card time, not wall time, for
    // the watchdog to have tripped before it opens the host's cards (opening one earlier would
    // stop the axes itself, as a new host). Under load the bus's clock runs slower than the
    // wall's: it ticks at the pace of its slowest card.
    let (_procs, mut names) = bus("h", 2);
    let observer = open_when_ready(&format!("emu:{}", names.pop().unwrap()));
    let uris: Vec<String> = names.iter().map(|n| format!("emu:{n}")).collect();
    for phase in ["accelerating", "at-feed", "blending", "decelerating"] {
        let env = [
            (HOST_CARDS, uris.join(",")),
            (HOST_PHASE, phase.to_string()),
        ];
        let mut host = start_host_role("bus_host_role", &env, phase);
        host.0.kill().unwrap(); // SIGKILL
        host.0.wait().unwrap();
        // The timeout and the slowest stop ramp (at most 0.1 s from the feed), in card time.
        let killed = observer.tick().unwrap();
        let rate = observer.info().servo_rate_hz as u64;
        while observer.tick().unwrap() < killed + (HOST_TIMEOUT_MS + 300) * rate / 1000 {
            std::thread::sleep(Duration::from_millis(10));
        }
        for (uri, name) in uris.iter().zip(&names) {
            let card = open_when_ready(uri);
            let rate = card.info().servo_rate_hz as f64;
            let deadline = Instant::now() + Duration::from_secs(10);
            let infos = loop {
                let infos: Vec<_> = (0..2)
                    .map(|a| card.axis(a).unwrap().stop_info().unwrap())
                    .collect();
                if card.safety_status().unwrap().watchdog_tripped
                    && infos.iter().all(|i| i.rest_tick.is_some())
                {
                    break infos;
                }
                assert!(
                    Instant::now() < deadline,
                    "{phase} {name}: not at rest: {:?} {infos:?}",
                    card.safety_status().unwrap()
                );
                std::thread::sleep(Duration::from_millis(5));
            };
            let st = card.safety_status().unwrap();
            let timeout = HOST_TIMEOUT_MS as f64 * 1e-3 * rate;
            assert_eq!(
                (st.watchdog_trip_tick - st.trip_heartbeat_tick) as f64,
                timeout,
                "{phase} {name}: the watchdog trips its timeout after the last heartbeat"
            );
            let mut moving = 0;
            for (i, info) in infos.iter().enumerate() {
                let s = card.axis(i).unwrap().status().unwrap();
                assert_eq!(info.reason, StopReason::Watchdog, "{phase} {name} axis {i}");
                assert_eq!(s.state, AxisState::ErrorStop, "{phase} {name} axis {i}");
                assert!(!s.drive_enabled() && s.dac_volts == 0.0, "drive still on");
                assert!(info.stop_tick >= st.watchdog_trip_tick);
                // The ramp is the command's; the axis is at rest once its measured velocity is
                // within its in-velocity window too, a few ticks of servo lag later when the
                // stop began in a deceleration (the ramp then ends at a higher jerk). An axis
                // the path did not move then has no ramp: it is at rest on the tick after the
                // trip.
                let ramp = (info.ramp_time.as_secs_f64() * rate).ceil() + SETTLE_TICKS;
                moving += usize::from(info.ramp_time > Duration::ZERO);
                let to_rest = (info.rest_tick.unwrap() - st.trip_heartbeat_tick) as f64;
                eprintln!(
                    "{phase} {name} axis {i}: at rest {:.2} ms after the last heartbeat, \
                     bound {:.2} ms (stop at +{} ticks from the trip, at rest {} ticks later, \
                     ramp {:?})",
                    to_rest / rate * 1e3,
                    (timeout + ramp) / rate * 1e3,
                    info.stop_tick - st.watchdog_trip_tick,
                    info.rest_tick.unwrap() - info.stop_tick,
                    info.ramp_time
                );
                assert!(
                    to_rest <= timeout + ramp,
                    "{phase} {name} axis {i}: at rest {to_rest} ticks after the last \
                     heartbeat, bound {} (timeout {timeout} + ramp {ramp})",
                    timeout + ramp
                );
            }
            // The host was killed with the path moving on every card.
            assert!(moving >= 1, "{phase} {name}: nothing was moving");
            let ax = card.axis(0).unwrap();
            assert_eq!(ax.enable().unwrap_err().kind(), ErrorKind::WatchdogTripped);
        }
    }
}

/// A master and a follower `card-emu` process of six axes at `rate` Hz, a set of both (a
/// release margin for a loaded machine: its commit must reach the master before its tick) with
/// group 0 of each over its six axes, configured and enabled.
fn two_of_six(tag: &str, rate: u32) -> ([Proc; 2], CardSet) {
    let master = format!("{tag}-{}", std::process::id());
    let follower = format!("{master}-f");
    let rate = rate.to_string();
    let args = ["--axes", "6", "--servo-rate", &rate];
    let m = card_emu(&master, &args);
    let f = card_emu(&follower, &[&args[..], &["--sync-from", &master]].concat());
    let cards = vec![
        open_when_ready(&format!("emu:{master}")),
        open_when_ready(&format!("emu:{follower}")),
    ];
    let mut set = CardSet::new(cards).unwrap();
    set.set_margin(Duration::from_millis(300));
    let axes: Vec<usize> = (0..6).collect();
    for c in set.cards() {
        for &a in &axes {
            c.axis(a).unwrap().enable().unwrap();
        }
        let g = c.group(0).unwrap();
        g.configure(&GroupSettings::new(&axes)).unwrap();
        g.enable().unwrap();
    }
    ([m, f], set)
}

/// The path's parts over [`two_of_six`]: group 0 of each card.
const PARTS: [motioncard_sdk::PathPart; 2] = [
    motioncard_sdk::PathPart { card: 0, group: 0 },
    motioncard_sdk::PathPart { card: 1, group: 0 },
];

/// Layout 1.14: a 12-axis path across two `card-emu` processes of six axes on one bus (1 kHz,
/// so that each card's scope holds 4 s of samples between reads), streamed in two releases,
/// the second while it runs (the first pushed one by one, the second streamed by
/// `SetPath::run`): on every tick, every axis of both processes is where one planner of all
/// twelve axes puts it, to the last bit.
#[test]
fn a_path_across_processes_is_bit_identical_to_one_planner() {
    let (_procs, set) = two_of_six("widew", 1000);
    for c in set.cards() {
        wide_path::record(c, 6);
    }
    let mut path = set.path(&PARTS, &wide_path::settings()).unwrap();
    let prog = wide_path::program();
    let split = [6, 6];
    let mut got = std::collections::BTreeMap::new();
    let mut batches = Vec::new();
    for (k, chunk) in [&prog[..3], &prog[3..]].into_iter().enumerate() {
        let tick = if k == 0 {
            for s in chunk {
                path.push(s).unwrap();
            }
            path.release().unwrap()
        } else {
            // streamed: every segment published to both processes ahead of their answers
            path.run(chunk).unwrap()
        };
        batches.push((tick, chunk.to_vec()));
        wide_path::read_all(&set, &split, &mut got);
    }
    let t0 = Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(20));
        wide_path::read_all(&set, &split, &mut got);
        let rest = set.cards().iter().all(|c| {
            let (state, st) = c.group(0).unwrap().status().unwrap();
            state == GroupState::Standby && st.path_queued == 0
        });
        if rest {
            break;
        }
        assert!(t0.elapsed() < Duration::from_secs(60), "the path ends");
    }
    path.wait(Duration::from_secs(5)).unwrap();
    let (first, want) = wide_path::engine(1000, &batches, &[]);
    let ticks = wide_path::compare(&got, first, &want);
    eprintln!(
        "{ticks} ticks of two processes, releases at {:?}: every axis bit-identical to one \
         12-axis planner",
        batches.iter().map(|b| b.0).collect::<Vec<_>>()
    );
}

/// A follower process killed (SIGKILL) while `SetPath::run` streams a 12-axis path over it and
/// its master: the run ends with the follower's `CardGone` (the path can no longer run as one),
/// and the master, halted at once by the SDK, comes to rest on the path short of its end,
/// with nothing queued or staged.
#[test]
fn a_card_killed_while_a_path_across_cards_streams_ends_the_run_and_halts_the_others() {
    let ([_m, f], set) = two_of_six("widek", 10_000);
    let mut path = set
        .path(&PARTS, &PathSettings::uniform(12, 5e4, 1e6, 1e8))
        .unwrap();
    // 4,000 chords of 20 counts along a line through all twelve axes at 20,000 counts/s: 4 s
    let chord = |i: u32| Segment::line(i, &[20.0 * f64::from(i); 12], 2e4, 1.0);
    let prog: Vec<Segment> = (1..=4000).map(chord).collect();
    let end = 20.0 * 4000.0;
    // the follower is killed once the master's path is under way
    let watcher = set.cards()[0].clone();
    let killer = std::thread::spawn(move || {
        let g = watcher.group(0).unwrap();
        let t0 = Instant::now();
        while g.status().unwrap().1.path_done < 300 {
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "the path never got going"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        drop(f); // SIGKILL
    });
    let e = path.run(&prog).unwrap_err();
    killer.join().unwrap();
    assert_eq!(e.kind(), ErrorKind::CardGone, "{e}");
    let g = set.cards()[0].group(0).unwrap();
    let t0 = Instant::now();
    loop {
        let (state, st) = g.status().unwrap();
        if state == GroupState::Standby && st.path_queued == 0 && st.path_staged == 0 {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "the master came to rest: {state:?} {st:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let x = set.cards()[0]
        .axis(0)
        .unwrap()
        .status()
        .unwrap()
        .command_position;
    assert!(
        x > 0.0 && x < end,
        "halted on the path, short of its end: {x}"
    );
}
