//! The host heartbeat: while a card is open the SDK keeps `host.heartbeat` moving and
//! declares its period (`host.host_period_us` = [`HEARTBEAT_PERIOD_US`]). On a real-time card
//! a thread owned by the card writes it every half period (asking for `SCHED_FIFO`, best
//! effort) and stops when the card is closed; it also publishes the host clock command
//! deadlines are measured on and, for an `emu:` card, watches the connection. A stepped `sim`
//! card has no thread: it beats once per emulated tick the SDK steps.

use crate::device::Device;
use crate::error::{Error, Result};
use crate::session::{Link, Window};
use firmware_proto::layout;
use firmware_proto::Mem;
use std::os::fd::{AsFd, OwnedFd};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// The heartbeat period the SDK declares to the card, µs. The real-time heartbeat thread
/// writes twice per period.
pub const HEARTBEAT_PERIOD_US: u32 = 1000;

/// The host side of the watchdog: keeps `host.heartbeat` and the host clock
/// (`host.host_time_ms`) moving while the card is open, and, for an `emu:` card, watches the
/// connection: when the card process goes away the session is marked gone at once.
// (`window`, `link`, `count`: for the beats of a stepped `sim` card)
#[cfg_attr(not(feature = "emulator"), allow(dead_code))]
pub(crate) struct Heartbeat {
    window: Window,
    link: Arc<Link>,
    pub(crate) enabled: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    count: AtomicU32,
    thread: Option<JoinHandle<()>>,
}

impl Heartbeat {
    /// Declare the period and start beating: a thread for real-time cards, nothing for a
    /// stepped `sim` (it beats as it steps). `lease`: the `emu:` connection to watch.
    pub(crate) fn start(dev: &Device, link: Arc<Link>, lease: Option<OwnedFd>) -> Result<Self> {
        let window = dev.window.clone();
        window.write32(layout::HOST_PERIOD_US, HEARTBEAT_PERIOD_US);
        link.publish_time();
        let count = window.read32(layout::HEARTBEAT).wrapping_add(1);
        window.write32(layout::HEARTBEAT, count);
        let enabled = Arc::new(AtomicBool::new(true));
        let stop = Arc::new(AtomicBool::new(false));
        let thread = match dev.backend.is_stepped() {
            true => None,
            false => {
                let beat = Beat {
                    window: window.clone(),
                    link: link.clone(),
                    enabled: enabled.clone(),
                    stop: stop.clone(),
                    lease,
                };
                let t = std::thread::Builder::new()
                    .name("motioncard-heartbeat".into())
                    .spawn(move || beat.run(count))
                    .map_err(|e| Error::io("starting the heartbeat thread", e))?;
                Some(t)
            }
        };
        Ok(Self {
            window,
            link,
            enabled,
            stop,
            count: AtomicU32::new(count),
            thread,
        })
    }

    /// One beat (stepped cards: before each emulated tick).
    #[cfg(feature = "emulator")]
    pub(crate) fn beat(&self) {
        if self.thread.is_none() && self.enabled.load(Ordering::Relaxed) {
            self.link.publish_time();
            let c = self.count.fetch_add(1, Ordering::Relaxed).wrapping_add(1);
            self.window.write32(layout::HEARTBEAT, c);
        }
    }

    /// Stop beating (the thread ends); the card's watchdog then sees a silent host.
    pub(crate) fn halt(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Heartbeat {
    fn drop(&mut self) {
        self.halt();
    }
}

/// What the heartbeat thread owns.
struct Beat {
    window: Window,
    link: Arc<Link>,
    enabled: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    lease: Option<OwnedFd>,
}

impl Beat {
    fn run(self, mut count: u32) {
        raise_priority();
        let half = Duration::from_micros(HEARTBEAT_PERIOD_US as u64 / 2);
        while !self.stop.load(Ordering::Relaxed) {
            if self.enabled.load(Ordering::Relaxed) {
                self.link.publish_time();
                count = count.wrapping_add(1);
                self.window.write32(layout::HEARTBEAT, count);
            }
            // [emu] the connection is the lease: a hang-up means the card process is gone.
            if let Some(fd) = &self.lease {
                if !self.link.is_gone() && crate::session::hung_up(fd.as_fd()) {
                    self.link.mark_gone();
                }
            }
            std::thread::sleep(half);
        }
    }
}

/// Ask for SCHED_FIFO priority 10 for the calling (heartbeat) thread, so a busy machine does
/// not starve it into a watchdog trip. Best effort: ignored without the privilege.
fn raise_priority() {
    use nix::libc;
    let param = libc::sched_param { sched_priority: 10 };
    // SAFETY: pthread_self() is the calling thread, `param` is a valid sched_param that
    // outlives the call; the call only changes this thread's scheduling attributes.
    let _ = unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) };
}
