//! The host's side of a session with a card: the host clock that command deadlines are
//! measured on, liveness (is the card still ticking, is its process still there), and the
//! wake-up that [`crate::Card::close`] and [`crate::Card::cancel_waits`] use to end waits in
//! other threads.
//!
//! **Deadlines.** Every command carries a deadline on the host's clock (`deadline_ms`, the
//! send time plus [`crate::ACK_TIMEOUT`]); the heartbeat publishes that clock in
//! `host.host_time_ms`, and the card refuses a command it takes after its deadline with
//! `MC_NACK_EXPIRED`. A host that gives up on a command first publishes its clock (past the
//! deadline), then looks at the ring's tail: if the card has not taken the command, it never
//! will run it (store, SeqCst fence, load on both sides: one of them sees the other), so the
//! SDK reports a failure only for a command that cannot run any more.
//!
//! **Liveness.** A status read is fresh only if the card's tick counter moved within
//! [`Link::stale_limit`] (the larger of [`STALE_TICKS`] servo periods and [`STALE_MIN`]);
//! otherwise it fails with `NotResponding` instead of returning the old snapshot. For `emu:`
//! cards the connection is the lease: the heartbeat thread looks at it every beat, and when the
//! card process goes away every call fails with `CardGone`.

use crate::error::{Error, Result};
use crate::lock::lock;
use firmware_proto::{layout, Mem};
use nix::sys::eventfd::{EfdFlags, EventFd};
use std::os::fd::{AsFd, BorrowedFd};
use std::sync::atomic::{fence, AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A command's deadline: the card refuses a command it takes later than this after it was
/// sent (`MC_NACK_EXPIRED`), and the SDK reports a failure only once the command can no longer
/// run.
pub const ACK_TIMEOUT: Duration = Duration::from_secs(2);

pub(crate) type Window = std::sync::Arc<firmware_proto::window::MappedWindow>;

/// A card whose tick counter has not moved for this many servo periods (and at least
/// [`STALE_MIN`]) is not responding.
pub const STALE_TICKS: u64 = 500;

/// The floor of the staleness limit: what an ordinary, loaded Linux host may stall a thread.
pub const STALE_MIN: Duration = Duration::from_millis(100);

/// The host's monotonic clock in ms, as the card sees it (`host.host_time_ms`): wrapping,
/// never 0 (0 means "no clock" to the card).
pub(crate) fn host_ms() -> u32 {
    let t = nix::time::clock_gettime(nix::time::ClockId::CLOCK_MONOTONIC)
        .unwrap_or_else(|_| nix::sys::time::TimeSpec::new(0, 0));
    let ms = (t.tv_sec() as u64)
        .wrapping_mul(1000)
        .wrapping_add(t.tv_nsec() as u64 / 1_000_000) as u32;
    ms.max(1)
}

/// Has host time `now` passed `deadline` (wrapping)?
pub(crate) fn passed(now: u32, deadline: u32) -> bool {
    (now.wrapping_sub(deadline) as i32) > 0
}

/// One session's shared state: read by every call, written by the heartbeat thread, `close`
/// and `cancel_waits`.
pub(crate) struct Link {
    window: Window,
    /// The session id the card knows this host by.
    pub session: u32,
    stepped: bool,
    clock: Mutex<()>,
    gone: AtomicBool,
    closed: AtomicBool,
    cancels: AtomicU64,
    wake: EventFd,
    seen: Mutex<(u64, Instant)>,
    stale_limit: Duration,
}

impl Link {
    pub(crate) fn new(window: Window, servo_rate_hz: u32, stepped: bool) -> Result<Self> {
        let wake = EventFd::from_value_and_flags(0, EfdFlags::EFD_CLOEXEC | EfdFlags::EFD_NONBLOCK)
            .map_err(|e| Error::io("creating the wake-up eventfd", e))?;
        let period = Duration::from_secs_f64(1.0 / servo_rate_hz.max(1) as f64);
        let tick = window.read64(layout::TICK);
        Ok(Self {
            session: new_session_id(),
            stepped,
            clock: Mutex::new(()),
            gone: AtomicBool::new(false),
            closed: AtomicBool::new(false),
            cancels: AtomicU64::new(0),
            wake,
            seen: Mutex::new((tick, Instant::now())),
            stale_limit: (period * STALE_TICKS as u32).max(STALE_MIN),
            window,
        })
    }

    /// Publish the host clock (`host.host_time_ms`) and fence: what the card reads after its
    /// next fence is at least this. Returns the time published.
    pub(crate) fn publish_time(&self) -> u32 {
        let _g = lock(&self.clock);
        let now = host_ms();
        self.window
            .store32(layout::HOST_TIME_MS, now, Ordering::SeqCst);
        fence(Ordering::SeqCst);
        now
    }

    /// The deadline of a command sent now.
    pub(crate) fn deadline(&self) -> u32 {
        host_ms()
            .wrapping_add(ACK_TIMEOUT.as_millis() as u32)
            .max(1)
    }

    /// How long a card's tick may stand still before it counts as not responding.
    pub(crate) fn stale_limit(&self) -> Duration {
        self.stale_limit
    }

    /// Closed or gone: the error every call gets.
    pub(crate) fn check(&self) -> Result<()> {
        if self.closed.load(Ordering::Acquire) {
            return Err(Error::Closed);
        }
        self.check_gone()
    }

    /// Gone: the card process went away.
    pub(crate) fn check_gone(&self) -> Result<()> {
        if self.gone.load(Ordering::Acquire) {
            return Err(Error::CardGone(
                "the card-emu process serving it went away (its connection hung up)".into(),
            ));
        }
        Ok(())
    }

    /// Is the card alive, given a tick it published? Fresh if the tick moved since the last
    /// look or within the staleness limit; a stepped card is always fresh (its time is the
    /// host's).
    pub(crate) fn alive(&self, tick: u64) -> Result<()> {
        self.alive_since(tick, None)
    }

    /// [`Link::alive`] for a wait that began at `since`: it fails only when the tick stood
    /// still for the whole limit during the wait (a card that just continued after a stall
    /// gets its chance to tick).
    pub(crate) fn alive_since(&self, tick: u64, since: Option<Instant>) -> Result<()> {
        self.check()?;
        if self.stepped {
            return Ok(());
        }
        let mut seen = lock(&self.seen);
        let now = Instant::now();
        if tick != seen.0 {
            *seen = (tick, now);
            return Ok(());
        }
        let from = since.map_or(seen.1, |s| s.max(seen.1));
        let still = now.duration_since(from);
        if still > self.stale_limit {
            return Err(Error::NotResponding(format!(
                "the card's tick counter has stood at {tick} for {} ms (limit {} ms): its \
                 status is stale",
                now.duration_since(seen.1).as_millis(),
                self.stale_limit.as_millis()
            )));
        }
        Ok(())
    }

    /// The card's current tick, if it is alive.
    pub(crate) fn tick(&self) -> Result<u64> {
        let t = self.window.read64(layout::TICK);
        self.alive(t).map(|()| t)
    }

    /// The card process went away: every call fails from now on, waits wake up.
    pub(crate) fn mark_gone(&self) {
        self.gone.store(true, Ordering::Release);
        self.wake();
    }

    /// Closed: every call fails from now on, waits wake up. False if it already was.
    pub(crate) fn mark_closed(&self) -> bool {
        let first = !self.closed.swap(true, Ordering::AcqRel);
        self.wake();
        first
    }

    pub(crate) fn is_gone(&self) -> bool {
        self.gone.load(Ordering::Acquire)
    }

    /// End the waits in progress with `Cancelled`.
    pub(crate) fn cancel(&self) {
        self.cancels.fetch_add(1, Ordering::AcqRel);
        self.wake();
    }

    /// The cancel generation: a wait that started at generation g is cancelled once it moves.
    pub(crate) fn cancels(&self) -> u64 {
        self.cancels.load(Ordering::Acquire)
    }

    fn wake(&self) {
        let _ = self.wake.write(1);
    }

    /// Readable when a wait must look at the flags (closed, gone, cancelled).
    pub(crate) fn wake_fd(&self) -> BorrowedFd<'_> {
        self.wake.as_fd()
    }

    /// Consume a wake-up (the one thread in poll() does, then tells the others).
    pub(crate) fn clear_wake(&self) {
        let _ = self.wake.read();
    }
}

/// A session id: nonzero, different for every open (process id, time and a per-process
/// counter mixed).
fn new_session_id() -> u32 {
    use std::hash::{BuildHasher, Hasher};
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u32(std::process::id());
    h.write_u64(COUNT.fetch_add(1, Ordering::Relaxed));
    h.write_u32(host_ms());
    (h.finish() as u32).max(1)
}

/// Has the peer of a connected stream socket hung up? Never blocks.
pub(crate) fn hung_up(fd: BorrowedFd<'_>) -> bool {
    use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
    // POLLRDHUP: the peer closed its end (Linux); nix has no name for it.
    let rdhup = PollFlags::from_bits_retain(nix::libc::POLLRDHUP);
    let mut fds = [PollFd::new(
        fd,
        rdhup | PollFlags::POLLHUP | PollFlags::POLLERR,
    )];
    matches!(poll(&mut fds, PollTimeout::ZERO), Ok(n) if n > 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deadlines_compare_across_the_wrap() {
        assert!(passed(5, 3));
        assert!(!passed(3, 3));
        assert!(!passed(3, 5));
        assert!(passed(2, u32::MAX - 1));
        assert!(!passed(u32::MAX - 1, 2));
    }

    #[test]
    fn session_ids_are_nonzero_and_differ() {
        let ids: std::collections::HashSet<u32> = (0..1000).map(|_| new_session_id()).collect();
        assert!(ids.len() > 990 && !ids.contains(&0));
    }
}
