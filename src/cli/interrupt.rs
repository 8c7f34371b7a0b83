//! `mcctl` interrupted: SIGINT (Ctrl-C), SIGTERM (systemd, `timeout`, a supervisor) and SIGHUP
//! (the terminal went away) end a command the way its own end would. The card halts what
//! mcctl started and no fault latches: mcctl closes its session (`Card::close`, the card's
//! detach halts every axis and group mcctl set moving, on its stop ramp, reason `HostDetach`;
//! axes mcctl never moved stay as they are) and exits with 128 + the signal's number. Killed
//! instead, mcctl would leave its session open, and the card's watchdog would stop every
//! enabled axis into ErrorStop and latch until `mcctl reset --faults`.
//!
//! How: [`install`] blocks the three signals in the main thread before any other thread exists
//! (every thread the SDK starts inherits the mask), and one thread takes them with `sigwait`.
//! On the first it records the signal and, from then on, keeps cancelling the waits on the card
//! [`watch`] names (`Card::cancel_waits`, every few milliseconds, so a wait that begins after
//! the signal ends too); the loops that poll or sleep look at [`check`]. Either way the
//! command returns [`Error::Cancelled`] and `mcctl` closes the card. A second signal exits at
//! once, for a close that does not come back (a card that does not answer).

use crate::{Card, Error, Result};
use nix::sys::signal::{SigSet, Signal};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// The signal that interrupted mcctl (0: none yet).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// The card whose waits a signal ends.
static CARD: Mutex<Option<Card>> = Mutex::new(None);

/// How often the waits on the card are cancelled again after a signal.
const RECANCEL: Duration = Duration::from_millis(5);

fn signals() -> SigSet {
    let mut set = SigSet::empty();
    for s in [Signal::SIGINT, Signal::SIGTERM, Signal::SIGHUP] {
        set.add(s);
    }
    set
}

fn card() -> Option<Card> {
    CARD.lock().unwrap_or_else(|p| p.into_inner()).clone()
}

/// Take SIGINT, SIGTERM and SIGHUP from now on. Call it from the main thread before any other
/// thread starts (before a card is opened), so that every thread inherits the mask.
pub fn install() -> Result<()> {
    let io = |context: &str, source: std::io::Error| Error::Io {
        context: context.into(),
        source,
    };
    let set = signals();
    set.thread_block()
        .map_err(|e| io("mcctl: blocking SIGINT, SIGTERM and SIGHUP", e.into()))?;
    std::thread::Builder::new()
        .name("mcctl-signals".into())
        .spawn(move || {
            let Ok(first) = set.wait() else { return };
            SIGNAL.store(first as i32, Ordering::SeqCst);
            // From now on every wait on the card ends, whenever it began.
            let _ = std::thread::Builder::new()
                .name("mcctl-cancel".into())
                .spawn(|| loop {
                    if let Some(c) = card() {
                        c.cancel_waits();
                    }
                    std::thread::sleep(RECANCEL);
                });
            // A second signal: the close did not come back (or the user insists).
            if let Ok(again) = set.wait() {
                std::process::exit(128 + again as i32);
            }
        })
        .map_err(|e| io("mcctl: starting the signal thread", e))?;
    Ok(())
}

/// The card a signal interrupts (`None`: no card any more).
pub fn watch(card: Option<&Card>) {
    *CARD.lock().unwrap_or_else(|p| p.into_inner()) = card.cloned();
}

/// The signal that interrupted mcctl, if one did.
pub fn signal() -> Option<Signal> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => Signal::try_from(s).ok(),
    }
}

/// [`Error::Cancelled`] once a signal came: what a loop that polls or sleeps returns.
pub fn check() -> Result<()> {
    match signal() {
        Some(_) => Err(Error::Cancelled),
        None => Ok(()),
    }
}
