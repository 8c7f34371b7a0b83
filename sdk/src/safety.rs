//! Safety: the host heartbeat, the card's watchdog, limits, following error, e-stop, stop
//! reasons, and fault reset.
//!
//! **The heartbeat.** While a card is open the SDK keeps `host.heartbeat` moving on its own and
//! declares its period (`host.host_period_us` = [`HEARTBEAT_PERIOD_US`]). On a real-time card
//! (`sim`, `emu:`, `uio:`, `pci:`) a thread owned by the card writes it every half period and
//! stops when the last clone of the [`Card`] is dropped; it asks for `SCHED_FIFO` priority
//! (best effort: without the privilege it runs at normal priority). On a stepped `sim` card
//! there is no thread: the heartbeat advances once per emulated servo tick the SDK steps
//! ([`crate::Sim::step`], waits), so stepped cards stay deterministic and their watchdog is on
//! like any other card's. (Stepping the emulator directly through `Sim::with_emulator` does
//! not beat: that is how a test makes a host hang, besides [`Card::set_heartbeat`].)
//!
//! The card arms its watchdog at the first heartbeat it sees, so closing a card (or a host
//! dying) with axes enabled makes them do a category 1 stop after the timeout and latches the
//! watchdog fault: the next host calls [`Card::reset_faults`].

use crate::card::{Axis, Card, Status};
use crate::device::Device;
use crate::error::{Error, Result, Target};
use crate::session::{Link, Window};
use firmware_proto::layout::{self, axis_safety as asf, safety_status as ss};
use firmware_proto::{
    AxisSafetyFlags, AxisState, CardFaults, Command, Faults, Io, Mem, Opcode, StopCategory,
    StopReason, MAX_AXES,
};
use std::os::fd::{AsFd, OwnedFd};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// The card's default watchdog timeout.
pub const WATCHDOG_TIMEOUT_DEFAULT: Duration =
    Duration::from_micros(card_emu::firmware::safety::WATCHDOG_TIMEOUT_DEFAULT_US as u64);

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
    enabled: Arc<AtomicBool>,
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

/// The card-wide safety state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SafetyStatus {
    /// The host watchdog tripped; latched until [`Card::reset_faults`].
    pub watchdog_tripped: bool,
    /// The host's e-stop command is latched.
    pub estop_command: bool,
    /// The e-stop input tripped; latched until reset with the input released.
    pub estop_input: bool,
    /// The card has seen a heartbeat since boot (or the last reset): the watchdog is watching.
    pub watchdog_armed: bool,
    /// Servo tick at which the card last saw the heartbeat change.
    pub last_heartbeat_tick: u64,
    /// Servo tick of the last watchdog trip (0: never).
    pub watchdog_trip_tick: u64,
    /// The tick of the last heartbeat the card saw before that trip.
    pub trip_heartbeat_tick: u64,
    /// Protocol errors (corrupt ring indices) the card detected since boot.
    pub protocol_errors: u32,
    /// The session id of the host attached to the card (this one's while it is open).
    pub session: u32,
    /// Servo tick of the last attach (this host's open, while it is open).
    pub attach_tick: u64,
    /// Hosts that opened the card while another's session was still open, since boot (each
    /// stopped the motion the vanished host left).
    pub host_changes: u32,
    /// Heartbeats that came later than the host's declared period after the one before,
    /// since this host attached: how close the host runs to its watchdog.
    pub late_heartbeats: u32,
    /// The longest gap between two heartbeats the card saw since this host attached.
    pub max_heartbeat_gap: Duration,
    /// What the card lost since boot (layout 1.4; 0 on an older card). Each nonzero count is a
    /// bug: accesses to the window out of range or misaligned that the card's handle refused,
    pub bad_accesses: u32,
    /// events that found the firmware's outbox full (before the event ring),
    pub outbox_lost: u32,
    /// and safety events that found the safety layer's event buffer full.
    pub safety_events_lost: u32,
}

/// How an axis's last safety stop went, measured by the card.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopInfo {
    /// Why the last motion ended.
    pub reason: StopReason,
    /// Servo tick at which the last safety stop began (0: none since boot).
    pub stop_tick: u64,
    /// Servo tick at which the axis came to rest after it (`None` while still stopping).
    pub rest_tick: Option<u64>,
    /// Planned duration of the stop's deceleration ramp (0 for category 0).
    pub ramp_time: Duration,
}

/// An axis's safety configuration, in user units (see [`Axis::set_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetySettings {
    /// Soft limits (negative, positive), or `None`.
    pub soft_limits: Option<(f64, f64)>,
    /// Honour the limit switch inputs.
    pub hard_limits: bool,
    /// Honour the amplifier alarm input.
    pub amp_alarm: bool,
    /// Honour encoder loss and jumps.
    pub encoder_checks: bool,
    /// The stop a hard or soft limit makes.
    pub limit_stop: StopCategory,
    /// Following-error limit at `max_velocity` (LinuxCNC FERROR).
    pub ferror: f64,
    /// Following-error limit at rest (LinuxCNC MIN_FERROR).
    pub min_ferror: f64,
    /// The velocity `ferror` applies at.
    pub max_velocity: f64,
    /// Deceleration of category 1 and 2 stops.
    pub stop_deceleration: f64,
    /// Jerk of those stops.
    pub stop_jerk: f64,
    /// Fastest physically possible encoder velocity: a larger change in one tick is a fault.
    pub encoder_max_velocity: f64,
}

impl Default for SafetySettings {
    /// The card's defaults, in counts.
    fn default() -> Self {
        let c = card_emu::firmware::axis_safety::AxisSafetyConfig::default();
        let has = |f| c.flags.contains(f);
        Self {
            soft_limits: has(AxisSafetyFlags::SOFT_LIMITS)
                .then_some((c.soft_limit_neg, c.soft_limit_pos)),
            hard_limits: has(AxisSafetyFlags::HARD_LIMITS),
            amp_alarm: has(AxisSafetyFlags::AMP_ALARM),
            encoder_checks: has(AxisSafetyFlags::ENCODER),
            limit_stop: c.limit_category,
            ferror: c.ferror,
            min_ferror: c.min_ferror,
            max_velocity: c.max_velocity,
            stop_deceleration: c.stop_decel,
            stop_jerk: c.stop_jerk,
            encoder_max_velocity: c.encoder_max_velocity,
        }
    }
}

impl Card {
    /// Stop (`false`) or resume the heartbeat. A stopped heartbeat is a hung host to the card:
    /// its watchdog trips after the timeout. For tests of the watchdog.
    pub fn set_heartbeat(&self, on: bool) {
        self.with_heartbeat(|h| h.enabled.store(on, Ordering::Relaxed));
    }

    /// Set the card's watchdog timeout (default [`WATCHDOG_TIMEOUT_DEFAULT`], 100 ms: above the
    /// heartbeat gaps of a loaded host without real-time scheduling; a real-time host can run
    /// a much shorter one, down to 1.5 × [`HEARTBEAT_PERIOD_US`]; see
    /// [`SafetyStatus::late_heartbeats`] for how close a host runs). The card refuses zero and anything under
    /// 1.5 × the heartbeat period ([`HEARTBEAT_PERIOD_US`]) with
    /// [`crate::ErrorKind::WatchdogTimeout`].
    pub fn set_watchdog_timeout(&self, timeout: Duration) -> Result<()> {
        let us = u32::try_from(timeout.as_micros()).unwrap_or(u32::MAX);
        self.apply_safety_config(layout::WATCHDOG_TIMEOUT_US, us, "set_watchdog_timeout")
    }

    /// The stop the card's e-stop input makes (default category 1).
    pub fn set_estop_input_category(&self, category: StopCategory) -> Result<()> {
        self.apply_safety_config(
            layout::ESTOP_INPUT_CATEGORY,
            category as u32,
            "set_estop_input_category",
        )
    }

    /// Write one field of the card-wide safety block and have the card apply the block.
    fn apply_safety_config(&self, field: usize, value: u32, what: &'static str) -> Result<()> {
        let block = layout::SAFETY_CONFIG..layout::SAFETY_CONFIG + layout::SAFETY_CONFIG_BYTES;
        self.apply_block(
            block,
            |w| w.write32(field, value),
            Command::new(Opcode::ApplySafetyConfig, 0),
            what,
            Target::Card,
        )
    }

    /// E-stop every axis with the given stop category. Latched: nothing moves again until
    /// [`Card::reset_faults`].
    pub fn estop(&self, category: StopCategory) -> Result<()> {
        self.execute(
            Command::new(Opcode::EStop, 0).with_args(&[category as u32 as f64]),
            "estop",
            Target::Card,
        )
    }

    /// Clear the card-wide latches (watchdog, e-stop: refused with
    /// [`crate::ErrorKind::CauseActive`] while the heartbeat is not alive or the e-stop input is
    /// pressed), then MC_Reset every axis in ErrorStop (refused while an axis's alarm or encoder
    /// fault persists). Axes whose drive was disabled by their stop end Disabled; the others
    /// Standstill.
    pub fn reset_faults(&self) -> Result<()> {
        self.execute(
            Command::new(Opcode::SafetyReset, 0),
            "reset_faults",
            Target::Card,
        )?;
        for ax in self.axes() {
            if ax.status()?.state == AxisState::ErrorStop {
                ax.reset()?;
            }
        }
        Ok(())
    }

    /// The card-wide safety state (`NotResponding` rather than a stale one).
    pub fn safety_status(&self) -> Result<SafetyStatus> {
        self.tick()?;
        let w = self.window();
        let faults = CardFaults::from_bits_retain(w.read32(ss::FAULTS));
        let us = |off| Duration::from_micros(w.read32(off) as u64);
        Ok(SafetyStatus {
            watchdog_tripped: faults.contains(CardFaults::WATCHDOG),
            estop_command: faults.contains(CardFaults::ESTOP_COMMAND),
            estop_input: faults.contains(CardFaults::ESTOP_INPUT),
            watchdog_armed: w.read32(ss::WATCHDOG_ARMED) != 0,
            last_heartbeat_tick: w.read64(ss::LAST_HEARTBEAT_TICK),
            watchdog_trip_tick: w.read64(ss::WATCHDOG_TRIP_TICK),
            trip_heartbeat_tick: w.read64(ss::TRIP_HEARTBEAT_TICK),
            protocol_errors: w.read32(ss::PROTOCOL_ERRORS),
            session: w.read32(ss::SESSION),
            attach_tick: w.read64(ss::ATTACH_TICK),
            host_changes: w.read32(ss::HOST_CHANGES),
            late_heartbeats: w.read32(ss::LATE_HEARTBEATS),
            max_heartbeat_gap: us(ss::MAX_HEARTBEAT_GAP_US),
            bad_accesses: w.read32(layout::BAD_ACCESSES),
            outbox_lost: w.read32(layout::OUTBOX_LOST),
            safety_events_lost: w.read32(layout::SAFETY_EVENTS_LOST),
        })
    }

    /// Set the card's maximum stop time (default 2 s): every stop — halt, stop, the safety
    /// stops, starvation — ends within it; a halt whose own ramp would take longer runs on the
    /// axis's stop ramp, and a stop still running at the bound loses power (reason
    /// [`StopReason::StopTimeout`]). 10 ms to 600 s, and every axis's stop ramp from its
    /// max velocity must fit ([`crate::ErrorKind::StopTooLong`]).
    pub fn set_max_stop_time(&self, t: Duration) -> Result<()> {
        let us = u32::try_from(t.as_micros()).unwrap_or(u32::MAX);
        self.apply_safety_config(layout::MAX_STOP_TIME_US, us, "set_max_stop_time")
    }
}

impl Axis {
    /// Write the axis's safety configuration and have the card apply it (limits, following
    /// error, stop ramp), converting user units through the axis's scale.
    pub fn configure_safety(&self, s: &SafetySettings) -> Result<()> {
        let scale = self.scale();
        let k = scale.abs();
        let (neg, pos) = s.soft_limits.unwrap_or((-f64::MAX, f64::MAX));
        let named = [
            ("soft limit", neg),
            ("soft limit", pos),
            ("ferror", s.ferror),
            ("min_ferror", s.min_ferror),
            ("max velocity", s.max_velocity),
            ("stop deceleration", s.stop_deceleration),
            ("stop jerk", s.stop_jerk),
            ("encoder max velocity", s.encoder_max_velocity),
        ];
        for (what, v) in named {
            if !v.is_finite() {
                return Err(Error::NotFinite { what, value: v });
            }
        }
        let (neg, pos) = match s.soft_limits {
            Some((neg, pos)) if neg >= pos => {
                return Err(Error::BadConfig(format!(
                    "soft limits: the negative limit {neg} must be below the positive limit {pos}"
                )))
            }
            // In counts: a negative scale turns the user's negative limit into the larger count.
            Some((neg, pos)) if scale < 0.0 => (pos * scale, neg * scale),
            Some((neg, pos)) => (neg * scale, pos * scale),
            None => (-card_emu::MAX_POSITION, card_emu::MAX_POSITION),
        };
        let mut flags = AxisSafetyFlags::empty();
        flags.set(AxisSafetyFlags::SOFT_LIMITS, s.soft_limits.is_some());
        flags.set(AxisSafetyFlags::HARD_LIMITS, s.hard_limits);
        flags.set(AxisSafetyFlags::AMP_ALARM, s.amp_alarm);
        flags.set(AxisSafetyFlags::ENCODER, s.encoder_checks);
        let a = self.index();
        let fields = [
            (asf::SOFT_LIMIT_NEG, neg),
            (asf::SOFT_LIMIT_POS, pos),
            (asf::FERROR, s.ferror * k),
            (asf::MIN_FERROR, s.min_ferror * k),
            (asf::MAX_VELOCITY, s.max_velocity * k),
            (asf::STOP_DECEL, s.stop_deceleration * k),
            (asf::STOP_JERK, s.stop_jerk * k),
            (asf::ENCODER_MAX_VELOCITY, s.encoder_max_velocity * k),
        ];
        let block = layout::axis_safety(a, 0)..layout::axis_safety(a, layout::AXIS_SAFETY_BYTES);
        self.card().apply_block(
            block,
            |w| {
                w.write32(layout::axis_safety(a, asf::FLAGS), flags.bits());
                w.write32(
                    layout::axis_safety(a, asf::LIMIT_CATEGORY),
                    s.limit_stop as u32,
                );
                for (off, v) in fields {
                    w.write_f64(layout::axis_safety(a, off), v);
                }
            },
            Command::new(Opcode::ApplyAxisSafety, a as u16),
            "configure_safety",
            Target::Axis(a),
        )
    }

    /// Why the axis's last motion ended (`dmc_get_stop_reason`).
    pub fn stop_reason(&self) -> Result<StopReason> {
        let s = self.status()?;
        s.stop_reason().ok_or_else(|| {
            Error::Protocol(format!(
                "axis {} reports unknown stop reason {}",
                self.index(),
                s.raw.stop_reason
            ))
        })
    }

    /// The stop reason and the card's timing of the axis's last safety stop.
    pub fn stop_info(&self) -> Result<StopInfo> {
        let a = self.index();
        let w = self.card().window();
        let reason = self.stop_reason()?; // fresh, or NotResponding
        let rest = w.read64(ss::rest_tick(a));
        let ramp = w.read_f64(ss::ramp_time(a));
        Ok(StopInfo {
            reason,
            stop_tick: w.read64(ss::stop_tick(a)),
            rest_tick: (rest != 0).then_some(rest),
            ramp_time: Duration::try_from_secs_f64(ramp).unwrap_or_default(),
        })
    }
}

impl Status {
    /// Why the axis's last motion ended (`None`: a reason this library does not know).
    pub fn stop_reason(&self) -> Option<StopReason> {
        self.raw.stop_reason()
    }

    /// The axis's input bits and drive-enable output.
    pub fn io(&self) -> Io {
        self.raw.io
    }

    /// Is the axis's drive (amplifier) enabled?
    pub fn drive_enabled(&self) -> bool {
        self.raw.io.contains(Io::DRIVE_ENABLE)
    }
}

/// The name of a fault bit (as carried by a motion-aborted event), if it is one.
pub(crate) fn fault_name(code: i32) -> Option<&'static str> {
    let names = [
        (Faults::WATCHDOG, "the host watchdog"),
        (Faults::ESTOP, "an e-stop"),
        (Faults::HARD_LIMIT_POS, "the positive limit switch"),
        (Faults::HARD_LIMIT_NEG, "the negative limit switch"),
        (Faults::SOFT_LIMIT_POS, "the positive soft limit"),
        (Faults::SOFT_LIMIT_NEG, "the negative soft limit"),
        (Faults::FOLLOWING_ERROR, "a following error"),
        (Faults::AMP_ALARM, "an amplifier alarm"),
        (Faults::ENCODER, "an encoder fault"),
        (Faults::PROTOCOL, "a protocol error"),
        (
            Faults::STOP_TIMEOUT,
            "a stop that ran past the maximum stop time",
        ),
    ];
    names
        .iter()
        .find(|(bit, _)| bit.bits() as i32 == code)
        .map(|(_, n)| *n)
}

const _: () = assert!(MAX_AXES <= 8);
