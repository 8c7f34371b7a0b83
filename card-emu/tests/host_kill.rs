//! A host killed with SIGKILL mid-move at full speed, over 20 runs: the card (a separate
//! `card-emu` process on the real-time clock) stops every axis within the watchdog timeout
//! plus the deceleration ramp, disables the drives, and keeps the fault latched until a host
//! resets it. Everything is measured on the card, in servo ticks.
//!
//! A host that attaches after the previous one died, at any moment before or after the
//! watchdog trips, never inherits its motion.
//!
//! The host is this test binary run again with `MC_HOST_KILL_CARD` set: the `host_role` test
//! then opens the card, sets the watchdog timeout (`MC_HOST_KILL_TIMEOUT_MS`, default 100),
//! starts fast moves, prints `ready` once every axis cruises, and waits to be killed.
mod common;

use common::{card_emu, host_ready, open_when_ready, start_host_role, Proc};
use motioncard_sdk::{AxisState, ErrorKind, MoveLimits, StopReason};
use std::time::{Duration, Instant};

const ROLE: &str = "MC_HOST_KILL_CARD";
const TIMEOUT: &str = "MC_HOST_KILL_TIMEOUT_MS";
const AXES: usize = 4;
const RUNS: usize = 20;
const VMAX: f64 = 500_000.0; // counts/s: 3,000 rpm on the default 10,000-count encoder

fn fast() -> MoveLimits {
    MoveLimits::new(VMAX, 4e6, 4e8)
}

/// Start a host process on `uri` with watchdog timeout `timeout_ms`, and wait until its axes
/// cruise.
fn start_host(uri: &str, timeout_ms: u64, run: usize) -> Proc {
    let env = [(ROLE, uri.to_string()), (TIMEOUT, timeout_ms.to_string())];
    start_host_role("host_role", &env, &format!("run {run}"))
}

/// The host process (only when run by the test below).
#[test]
fn host_role() {
    let Ok(uri) = std::env::var(ROLE) else {
        return;
    };
    let card = open_when_ready(&uri);
    card.reset_faults().unwrap(); // the previous host's watchdog trip
    let ms = std::env::var(TIMEOUT).map_or(100, |v| v.parse().unwrap());
    card.set_watchdog_timeout(Duration::from_millis(ms))
        .unwrap();
    let mut dir = 1.0;
    for ax in card.axes().iter().take(AXES) {
        ax.enable().unwrap();
        ax.move_relative(dir * 4e6, &fast()).unwrap();
        dir = -dir;
    }
    let deadline = Instant::now() + Duration::from_secs(10);
    while !card
        .axes()
        .iter()
        .take(AXES)
        .all(|a| a.status().unwrap().command_velocity.abs() == VMAX)
    {
        assert!(Instant::now() < deadline, "never reached full speed");
        std::thread::sleep(Duration::from_millis(1));
    }
    host_ready();
}

#[test]
fn host_killed_mid_move_stops_every_axis_within_timeout_plus_ramp() {
    // The default timeout: what holds on a loaded host (5 ms, a real-time controller's, makes
    // the host's own heartbeat trip it when the machine is busy).
    const TIMEOUT_MS: u64 = 100;
    let name = format!("hostkill-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = card_emu(&name, &["--axes", &AXES.to_string()]);
    let mut worst: f64 = 0.0; // (time to rest) / (timeout + ramp)
    let mut rows = Vec::new();
    for run in 0..RUNS {
        let mut host = start_host(&uri, TIMEOUT_MS, run);
        // Kill at a varying point of the heartbeat period.
        std::thread::sleep(Duration::from_micros(1000 + 317 * run as u64 % 1000));
        host.0.kill().unwrap(); // SIGKILL
        host.0.wait().unwrap();
        // Open only once the card has surely tripped and stopped: a host that opens the card
        // within the timeout stops the dead host's axes itself (the next test), which is
        // right, but not what is measured here.
        std::thread::sleep(Duration::from_millis(TIMEOUT_MS + 300));

        let card = open_when_ready(&uri);
        let rate = card.info().servo_rate_hz as f64;
        let deadline = Instant::now() + Duration::from_secs(10);
        let infos = loop {
            let infos: Vec<_> = card
                .axes()
                .iter()
                .take(AXES)
                .map(|a| a.stop_info().unwrap())
                .collect();
            if card.safety_status().unwrap().watchdog_tripped
                && infos.iter().all(|i| i.rest_tick.is_some())
            {
                break infos;
            }
            assert!(Instant::now() < deadline, "run {run}: axes not at rest");
            std::thread::sleep(Duration::from_millis(5));
        };
        let st = card.safety_status().unwrap();
        let timeout = TIMEOUT_MS as f64 * 1e-3 * rate;
        assert_eq!(
            (st.watchdog_trip_tick - st.trip_heartbeat_tick) as f64,
            timeout,
            "run {run}: the watchdog trips its timeout after the last heartbeat"
        );
        let mut run_worst: (f64, f64) = (0.0, 0.0);
        for (i, info) in infos.iter().enumerate() {
            let ax = card.axis(i).unwrap();
            let s = ax.status().unwrap();
            assert_eq!(info.reason, StopReason::Watchdog, "run {run} axis {i}");
            assert_eq!(s.state, AxisState::ErrorStop);
            assert!(!s.drive_enabled() && s.dac_volts == 0.0, "drive still on");
            assert!(info.stop_tick >= st.watchdog_trip_tick);
            let ramp = (info.ramp_time.as_secs_f64() * rate).ceil();
            assert!(ramp > 0.05 * rate, "run {run}: the axis was not at speed");
            let to_rest = (info.rest_tick.unwrap() - st.trip_heartbeat_tick) as f64;
            assert!(
                to_rest <= timeout + ramp,
                "run {run} axis {i}: at rest {to_rest} ticks after the last heartbeat, \
                 bound {} (timeout {timeout} + ramp {ramp})",
                timeout + ramp
            );
            worst = worst.max(to_rest / (timeout + ramp));
            if to_rest / rate > run_worst.0 {
                run_worst = (to_rest / rate, (timeout + ramp) / rate);
            }
        }
        rows.push(run_worst);
        // Latched: nothing moves until a reset, which this live host may do.
        let ax = card.axis(0).unwrap();
        assert_eq!(ax.enable().unwrap_err().kind(), ErrorKind::WatchdogTripped);
        card.reset_faults().unwrap();
        assert_eq!(ax.status().unwrap().state, AxisState::Disabled);
        ax.enable().unwrap();
        ax.disable().unwrap();
    }
    println!("host SIGKILLed mid-move at {VMAX} counts/s, {RUNS} runs, {AXES} axes, 10 kHz:");
    println!("run  last heartbeat -> all axes at rest (ms)   bound = timeout + ramp (ms)");
    for (i, (t, b)) in rows.iter().enumerate() {
        println!("{i:>3}  {:>8.2}   {:>8.2}", t * 1e3, b * 1e3);
    }
    let max = rows.iter().map(|r| r.0).fold(0.0, f64::max);
    let min = rows.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    println!(
        "time to rest: min {:.2} ms, max {:.2} ms; worst ratio to the bound {worst:.4}",
        min * 1e3,
        max * 1e3
    );
}

/// A host that attaches after the previous host died — at once, or at any later moment
/// before or after the watchdog trips — never inherits its motion: the attach itself stops
/// every axis the dead host left moving (category 1, reason `HostChanged`), and the new host
/// sees why (`inherited_stops`, the stop reason, the host-change count).
#[test]
fn a_new_host_never_inherits_a_dead_hosts_motion() {
    const TIMEOUT_MS: u64 = 250;
    let name = format!("hostchange-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = card_emu(&name, &["--axes", &AXES.to_string()]);
    let mut rows = Vec::new();
    let mut changes = None;
    for (run, delay_ms) in [0u64, 0, 1, 2, 5, 20, 100, 200, 400]
        .into_iter()
        .enumerate()
    {
        let mut host = start_host(&uri, TIMEOUT_MS, run);
        host.0.kill().unwrap();
        let killed = Instant::now();
        host.0.wait().unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        let card = open_when_ready(&uri);
        let opened_ms = killed.elapsed().as_secs_f64() * 1e3;
        let st = card.safety_status().unwrap();
        let rate = card.info().servo_rate_hz as f64;
        let before = changes.unwrap_or(st.host_changes.wrapping_sub(1));
        assert_eq!(st.host_changes, before.wrapping_add(1), "run {run}");
        changes = Some(st.host_changes);
        // Which came first on the card: the watchdog (the dead host's last heartbeat is
        // older than the timeout) or this attach.
        let watchdog_first = st.watchdog_tripped && st.watchdog_trip_tick <= st.attach_tick;
        let want = if watchdog_first {
            StopReason::Watchdog
        } else {
            StopReason::HostChanged
        };
        assert_eq!(
            card.inherited_stops(),
            if watchdog_first { 0 } else { AXES as u32 },
            "run {run}"
        );
        // At rest within the stop ramp, drives off, nothing left moving for nobody.
        let deadline = Instant::now() + Duration::from_secs(5);
        let infos = loop {
            let infos: Vec<_> = card
                .axes()
                .iter()
                .take(AXES)
                .map(|a| a.stop_info().unwrap())
                .collect();
            if infos.iter().all(|i| i.rest_tick.is_some()) {
                break infos;
            }
            assert!(Instant::now() < deadline, "run {run}: axes not at rest");
            std::thread::sleep(Duration::from_millis(5));
        };
        let mut worst_ms: f64 = 0.0;
        for (i, info) in infos.iter().enumerate() {
            let s = card.axis(i).unwrap().status().unwrap();
            assert_eq!(info.reason, want, "run {run} axis {i}");
            assert_eq!(s.state, AxisState::ErrorStop, "run {run} axis {i}");
            assert!(!s.drive_enabled(), "run {run} axis {i}: drive on");
            if !watchdog_first {
                // The stop began with the attach (served between ticks: the same tick or
                // the next).
                assert!(
                    info.stop_tick >= st.attach_tick && info.stop_tick <= st.attach_tick + 1,
                    "run {run} axis {i}: stop at {}, attach at {}",
                    info.stop_tick,
                    st.attach_tick
                );
            }
            let rest = info.rest_tick.unwrap() - info.stop_tick;
            worst_ms = worst_ms.max(rest as f64 / rate * 1e3);
        }
        rows.push((delay_ms, opened_ms, want, worst_ms));
        card.reset_faults().unwrap();
    }
    println!(
        "host killed at cruise ({VMAX} counts/s, watchdog {TIMEOUT_MS} ms); a new host attaches:"
    );
    println!("delay (ms)  opened after the kill (ms)  stopped by   stop -> all axes at rest (ms)");
    for (d, opened, why, rest) in &rows {
        let why = format!("{why:?}");
        println!("{d:>10}  {opened:>26.1}  {why:<11}  {rest:>10.1}");
    }
    // Both cases were exercised.
    assert!(rows.iter().any(|r| r.2 == StopReason::HostChanged));
    assert!(rows.iter().any(|r| r.2 == StopReason::Watchdog));
}
