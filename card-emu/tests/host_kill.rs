//! A host killed with SIGKILL mid-move at full speed, over 20 runs: the card (a separate
//! `card-emu` process on the real-time clock) stops every axis within the watchdog timeout
//! plus the deceleration ramp, disables the drives, and keeps the fault latched until a host
//! resets it. Everything is measured on the card, in servo ticks.
//!
//! The host is this test binary run again with `MC_HOST_KILL_CARD` set: the `host_role` test
//! then opens the card, starts fast moves, prints `ready` once every axis cruises, and waits
//! to be killed.
use motioncard_sdk::{AxisState, Card, ErrorKind, MoveLimits, StopReason};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const ROLE: &str = "MC_HOST_KILL_CARD";
const AXES: usize = 4;
const RUNS: usize = 20;
const VMAX: f64 = 500_000.0; // counts/s: 3,000 rpm on the default 10,000-count encoder

fn fast() -> MoveLimits {
    MoveLimits::new(VMAX, 4e6, 4e8)
}

struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn open_when_ready(uri: &str) -> Card {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match Card::open(uri) {
            Ok(c) => return c,
            Err(e)
                if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::Busy)
                    && Instant::now() < deadline =>
            {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(e) => panic!("opening {uri}: {e}"),
        }
    }
}

/// The host process (only when run by the test below).
#[test]
fn host_role() {
    let Ok(uri) = std::env::var(ROLE) else {
        return;
    };
    let card = open_when_ready(&uri);
    card.reset_faults().unwrap(); // the previous host's watchdog trip
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
    println!("\nHOST-READY");
    loop {
        std::thread::sleep(Duration::from_secs(1));
    }
}

#[test]
fn host_killed_mid_move_stops_every_axis_within_timeout_plus_ramp() {
    let name = format!("hostkill-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = Proc(
        Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", &name, "--axes", &AXES.to_string()])
            .stdout(Stdio::null())
            .spawn()
            .expect("start card-emu"),
    );
    let mut worst: f64 = 0.0; // (time to rest) / (timeout + ramp)
    let mut rows = Vec::new();
    for run in 0..RUNS {
        let mut host = Proc(
            Command::new(std::env::current_exe().unwrap())
                .args(["--exact", "host_role", "--nocapture", "--test-threads=1"])
                .env(ROLE, &uri)
                .stdout(Stdio::piped())
                .spawn()
                .expect("start the host"),
        );
        let out = host.0.stdout.take().unwrap();
        let ready = BufReader::new(out)
            .lines()
            .map_while(Result::ok)
            .any(|l| l.contains("HOST-READY"));
        assert!(ready, "run {run}: the host died before it was ready");
        // Kill at a varying point of the heartbeat period.
        std::thread::sleep(Duration::from_micros(1000 + 317 * run as u64 % 1000));
        host.0.kill().unwrap(); // SIGKILL
        host.0.wait().unwrap();
        // Open only once the card has surely tripped: an SDK host that opens the card within
        // the timeout keeps the watchdog fed, which is right, but not what is measured here.
        std::thread::sleep(Duration::from_millis(300));

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
            if card.safety_status().watchdog_tripped && infos.iter().all(|i| i.rest_tick.is_some())
            {
                break infos;
            }
            assert!(Instant::now() < deadline, "run {run}: axes not at rest");
            std::thread::sleep(Duration::from_millis(5));
        };
        let st = card.safety_status();
        let timeout = 0.005 * rate;
        assert_eq!(
            (st.watchdog_trip_tick - st.trip_heartbeat_tick) as f64,
            timeout,
            "run {run}: the watchdog trips 5 ms after the last heartbeat"
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

/// Every wait with a timeout returns by its timeout when the card process dies mid-wait.
#[test]
fn waits_return_by_their_timeout_when_the_card_process_dies() {
    let name = format!("deadcard-{}", std::process::id());
    let mut emu = Proc(
        Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", &name, "--axes", "2"])
            .stdout(Stdio::null())
            .spawn()
            .expect("start card-emu"),
    );
    let card = open_when_ready(&format!("emu:{name}"));
    let ax = card.axis(1).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(1e7, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    let killer = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(100));
        let _ = emu.0.kill();
        let _ = emu.0.wait();
    });
    let generous = Duration::from_secs(5);
    let t = Duration::from_millis(600);
    let t0 = Instant::now();
    assert_eq!(m.wait(t).unwrap_err().kind(), ErrorKind::Timeout);
    let waited = t0.elapsed();
    assert!(waited >= t && waited < t + generous, "{waited:?}");
    killer.join().unwrap();
    // The card is gone now: each wait still ends by its own timeout.
    while card.next_event(Duration::ZERO).unwrap().is_some() {} // what it said before
    let t0 = Instant::now();
    assert_eq!(card.next_event(Duration::from_millis(200)).unwrap(), None);
    let waited = t0.elapsed();
    assert!(waited >= Duration::from_millis(200) && waited < generous);
    let t0 = Instant::now();
    assert_eq!(card.ping().unwrap_err().kind(), ErrorKind::NotResponding);
    let waited = t0.elapsed();
    assert!(
        waited >= motioncard_sdk::ACK_TIMEOUT && waited < motioncard_sdk::ACK_TIMEOUT + generous
    );
    assert_eq!(
        ax.wait_done(Duration::from_millis(100)).unwrap_err().kind(),
        ErrorKind::Timeout
    );
}

/// Every wait with a timeout returns by its timeout while the card process is stopped
/// (SIGSTOP) mid-wait, and the card carries on where it was once it continues.
#[test]
fn waits_return_by_their_timeout_while_the_card_process_is_stopped() {
    use nix::sys::signal::{kill, Signal};
    use nix::sys::wait::{waitpid, WaitPidFlag, WaitStatus};
    use nix::unistd::Pid;
    let name = format!("stoppedcard-{}", std::process::id());
    let emu = Proc(
        Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", &name, "--axes", "2"])
            .stdout(Stdio::null())
            .spawn()
            .expect("start card-emu"),
    );
    let pid = Pid::from_raw(emu.0.id() as i32);
    let card = open_when_ready(&format!("emu:{name}"));
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(20_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    kill(pid, Signal::SIGSTOP).unwrap();
    // The signal is asynchronous: wait until the card process has really stopped.
    assert!(matches!(
        waitpid(pid, Some(WaitPidFlag::WUNTRACED)).unwrap(),
        WaitStatus::Stopped(_, Signal::SIGSTOP)
    ));
    let tick = card.tick();
    let generous = Duration::from_secs(5);
    let t = Duration::from_millis(300);
    let t0 = Instant::now();
    assert_eq!(m.wait(t).unwrap_err().kind(), ErrorKind::Timeout);
    let waited = t0.elapsed();
    assert!(waited >= t && waited < t + generous, "{waited:?}");
    while card.next_event(Duration::ZERO).unwrap().is_some() {} // what it said before
    let t0 = Instant::now();
    assert_eq!(card.next_event(Duration::from_millis(100)).unwrap(), None);
    assert!(t0.elapsed() >= Duration::from_millis(100) && t0.elapsed() < generous);
    let t0 = Instant::now();
    assert_eq!(card.ping().unwrap_err().kind(), ErrorKind::NotResponding);
    let waited = t0.elapsed();
    assert!(
        waited >= motioncard_sdk::ACK_TIMEOUT && waited < motioncard_sdk::ACK_TIMEOUT + generous
    );
    assert_eq!(card.tick(), tick, "a stopped card does not tick");

    // Continued: the command the host gave up on is still answered (its ack is simply late),
    // the move finishes on its target, and the card answers again.
    kill(pid, Signal::SIGCONT).unwrap();
    m.wait(Duration::from_secs(5)).unwrap();
    let s = ax.status().unwrap();
    assert!((s.actual_position - 20_000.0).abs() <= 1.0, "{s:?}");
    card.ping().unwrap();
    drop(emu);
}
