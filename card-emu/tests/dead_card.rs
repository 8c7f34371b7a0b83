//! A card that died or stopped is reported as such, everywhere, and never runs a command its
//! host gave up on.
//!
//! - Killed (`kill -9` of the `card-emu` process): the connection is the lease; the host's
//!   heartbeat thread sees it hang up, and every call on the card — waits in progress
//!   included — fails with `CardGone` within milliseconds.
//! - Stopped (SIGSTOP): the card's tick stands still; reads and waits fail with
//!   `NotResponding` once it has stood for the staleness limit, a command fails once its
//!   deadline passed without the card taking it, and that command is refused (expired) when
//!   the card continues: it never runs.
mod common;

use common::{card_emu, open_when_ready, Proc};
use motioncard_sdk::{AxisState, ErrorKind, MoveLimits, STALE_MIN};
use nix::sys::signal::{kill, Signal};
use nix::sys::wait::{waitpid, WaitPidFlag, WaitStatus};
use nix::unistd::Pid;
use std::time::{Duration, Instant};

fn start(name: &str) -> Proc {
    card_emu(name, &["--axes", "2"])
}

fn slow() -> MoveLimits {
    MoveLimits::new(1e5, 1e6, 1e8)
}

/// Run `call`, assert it fails with `kind` within `bound`, and return how long it took.
fn fails_within<T: std::fmt::Debug>(
    what: &str,
    kind: ErrorKind,
    bound: Duration,
    call: impl FnOnce() -> motioncard_sdk::Result<T>,
) -> Duration {
    let t0 = Instant::now();
    let r = call();
    let took = t0.elapsed();
    match r {
        Err(e) => assert_eq!(e.kind(), kind, "{what}: {e}"),
        Ok(v) => panic!("{what}: succeeded ({v:?}) on a dead card"),
    }
    assert!(took <= bound, "{what}: took {took:?}, bound {bound:?}");
    took
}

#[test]
fn a_killed_card_is_reported_gone_by_every_call_within_milliseconds() {
    let name = format!("deadcard-{}", std::process::id());
    let mut emu = start(&name);
    let card = open_when_ready(&format!("emu:{name}"));
    let ax = card.axis(1).unwrap();
    ax.enable().unwrap();
    let m = ax.move_relative(1e7, &slow()).unwrap();
    // Waits in progress in other threads: a motion wait and an event wait, long timeouts.
    let waiter = |f: Box<dyn FnOnce() -> ErrorKind + Send>| {
        std::thread::spawn(move || {
            let kind = f();
            (kind, Instant::now())
        })
    };
    let (m2, c2) = (m.clone(), card.clone());
    let motion = waiter(Box::new(move || {
        m2.wait(Duration::from_secs(30)).unwrap_err().kind()
    }));
    let events = waiter(Box::new(move || loop {
        match c2.next_event(Duration::from_secs(30)) {
            Ok(Some(_)) => continue,
            Ok(None) => return ErrorKind::Timeout,
            Err(e) => return e.kind(),
        }
    }));
    std::thread::sleep(Duration::from_millis(100)); // both are blocked now
    let t_kill = Instant::now();
    emu.0.kill().unwrap(); // SIGKILL
    emu.0.wait().unwrap();
    let mut latencies = Vec::new();
    for (what, w) in [("motion wait", motion), ("event wait", events)] {
        let (kind, at) = w.join().unwrap();
        assert_eq!(kind, ErrorKind::CardGone, "{what}");
        let latency = at.duration_since(t_kill);
        assert!(latency < Duration::from_millis(100), "{what}: {latency:?}");
        latencies.push((what, latency));
    }
    // Every call after it: reads, waits and commands, at once.
    let now = Duration::from_millis(20);
    let gone = ErrorKind::CardGone;
    fails_within("tick", gone, now, || card.tick());
    fails_within("status", gone, now, || ax.status());
    fails_within("statuses", gone, now, || card.statuses(&[0, 1]));
    fails_within("safety status", gone, now, || card.safety_status());
    fails_within("stop info", gone, now, || ax.stop_info());
    fails_within("next event", gone, now, || card.next_event(Duration::ZERO));
    fails_within("poll events", gone, now, || card.poll_events());
    fails_within("motion wait", gone, now, || m.wait(Duration::from_secs(5)));
    fails_within("wait done", gone, now, || {
        ax.wait_done(Duration::from_secs(5))
    });
    fails_within("ping", gone, now, || card.ping());
    fails_within("move", gone, now, || ax.move_relative(10.0, &slow()));
    fails_within("halt", gone, now, || ax.halt(1e6, 1e8));
    // Closing a gone card is fine; afterwards every call says closed.
    card.close().unwrap();
    assert_eq!(card.tick().unwrap_err().kind(), ErrorKind::Closed);
    for (what, l) in latencies {
        println!("card-emu killed: {what} failed with CardGone after {l:?}");
    }
}

#[test]
fn a_stopped_card_is_reported_not_responding_and_never_runs_a_command_given_up_on() {
    let name = format!("stoppedcard-{}", std::process::id());
    let emu = start(&name);
    let pid = Pid::from_raw(emu.0.id() as i32);
    let card = open_when_ready(&format!("emu:{name}"));
    let stale = card.stale_limit();
    assert!(stale >= STALE_MIN);
    let (a0, a1) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    a0.enable().unwrap();
    a1.enable().unwrap();
    let m = a0.move_relative(20_000.0, &slow()).unwrap();
    let m2 = m.clone();
    let waiter = std::thread::spawn(move || {
        let r = m2.wait(Duration::from_secs(30));
        (r.unwrap_err().kind(), Instant::now())
    });
    std::thread::sleep(Duration::from_millis(20));
    kill(pid, Signal::SIGSTOP).unwrap();
    // The signal is asynchronous: wait until the card process has really stopped.
    assert!(matches!(
        waitpid(pid, Some(WaitPidFlag::WUNTRACED)).unwrap(),
        WaitStatus::Stopped(_, Signal::SIGSTOP)
    ));
    let t_stop = Instant::now();
    // The wait in progress: NotResponding once the tick has stood for the staleness limit
    // (it looks every half limit).
    let (kind, at) = waiter.join().unwrap();
    assert_eq!(kind, ErrorKind::NotResponding);
    let wait_latency = at.duration_since(t_stop);
    assert!(
        wait_latency >= stale / 2 && wait_latency <= stale * 2 + Duration::from_millis(200),
        "{wait_latency:?} (limit {stale:?})"
    );
    // Reads: never the old snapshot.
    let quick = Duration::from_millis(50);
    let nr = ErrorKind::NotResponding;
    fails_within("tick", nr, quick, || card.tick());
    fails_within("status", nr, quick, || a0.status());
    fails_within("statuses", nr, quick, || card.statuses(&[0, 1]));
    fails_within("safety status", nr, quick, || card.safety_status());
    // A wait gives the card the whole limit to tick again (one that just continued after a
    // stall would), then fails. Events posted before it stopped are still handed out: they
    // happened.
    fails_within("event wait", nr, stale * 2, || loop {
        if card.next_event(Duration::from_secs(5))?.is_none() {
            return Ok(());
        }
    });
    // A command: it fails once its deadline has passed untaken, and says it will not run.
    let t0 = Instant::now();
    let e = a1.move_relative(50_000.0, &slow()).unwrap_err();
    let took = t0.elapsed();
    assert_eq!(e.kind(), ErrorKind::NotResponding, "{e}");
    assert!(e.to_string().contains("will not run"), "{e}");
    assert!(
        took >= motioncard_sdk::ACK_TIMEOUT && took < motioncard_sdk::ACK_TIMEOUT * 2,
        "{took:?}"
    );
    // Continued: the card refuses that command (expired), so axis 1 never moves; the move
    // that was running carries on to its target, and the card answers again.
    kill(pid, Signal::SIGCONT).unwrap();
    let reached = m.wait(Duration::from_secs(10)).unwrap();
    assert!((reached - 20_000.0).abs() <= 1.0, "{reached}");
    card.ping().unwrap();
    std::thread::sleep(Duration::from_millis(200));
    let s1 = a1.status().unwrap();
    assert_eq!((s1.state, s1.raw.move_count), (AxisState::Standstill, 0));
    assert!(s1.actual_position.abs() <= 1.0, "{}", s1.actual_position);
    println!(
        "card-emu stopped: a wait in progress failed with NotResponding after {wait_latency:?} \
         (staleness limit {stale:?}); a command after {took:?} (its deadline)"
    );
    drop(emu);
}
