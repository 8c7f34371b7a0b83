//! Cards, axes, commands and waits.

#[cfg(feature = "emulator")]
use crate::device::SimOptions;
use crate::device::{self, Device};
use crate::error::{nack_reason, Error, Result, Target};
use crate::session::{host_ms, passed, Link};
#[cfg(feature = "emulator")]
use card_emu::Emulator;
use firmware_proto::cmd::{CardCmd, ReadConfig, Session};
use firmware_proto::layout;
use firmware_proto::ring::{CmdProducer, EvtConsumer, RingError, CMD_RING, EVT_RING};
use firmware_proto::seqlock::{self, SnapshotError};
use firmware_proto::{
    raw, AxisState, AxisStatus, Block, BlockAt, Command, Event, EventKind, Faults, Mem,
    MotionFlags, NackCode, Opcode, MAX_AXES,
};
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use std::collections::VecDeque;
use std::os::fd::BorrowedFd;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

pub(crate) use crate::session::Window;

pub use crate::session::ACK_TIMEOUT;

/// How long a wait looks at the event ring before it blocks in `poll()` on the interrupt fd:
/// about the round trip of a command to a card that busy-polls its ring, so that answer is
/// taken without a sleep and a wake-up.
pub const SPIN_BEFORE_POLL: Duration = Duration::from_micros(30);

/// How long an axis status block may stay busy (mid-write) before `Axis::status` gives
/// `Error::NotResponding`.
const STATUS_BUSY_TIMEOUT: Duration = Duration::from_millis(100);

/// Events kept for [`Card::next_event`] before the oldest are dropped (and counted).
pub const EVENT_QUEUE_CAP: usize = 4096;

/// The counts per user unit an axis's scale may have (in magnitude): from a nanometre-class
/// unit on a coarse encoder to a kilometre on a fine one (the card's `MC_SCALE_MIN..=MAX`).
pub const SCALE_RANGE: core::ops::RangeInclusive<f64> = firmware_proto::SCALE_RANGE;

/// Outcomes of motions kept for waiters.
const OUTCOME_CAP: usize = 1024;

/// What the card says about itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CardInfo {
    /// Firmware version, `major << 16 | minor << 8 | patch`.
    pub firmware_version: u32,
    /// DPRAM layout (major, minor).
    pub layout: (u16, u16),
    /// Axes on the card.
    pub axes: usize,
    /// Servo rate, Hz.
    pub servo_rate_hz: u32,
    /// Capability bits (`MC_CAP_*`).
    pub capabilities: u32,
}

/// How a motion ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// In position at this actual position (user units).
    Done(f64),
    /// Ended early by this command or fault (raw code).
    Aborted(i32),
    /// A buffered move started (PLCopen Active), towards this target (user units; velocity
    /// mode: its velocity).
    Active(f64),
    /// Velocity mode reached this velocity (PLCopen InVelocity), user units per second.
    InVelocity(f64),
    /// Homing failed (raw `MC_HOMING_ERR_` code) at this actual position (user units); the
    /// axis is at rest, not homed.
    HomingFailed(i32, f64),
    /// Layout 1.7 (sync): a gear motion's `MC_SYNC_*` event (raw code) and the slave's
    /// commanded position then (user units).
    Sync(i32, f64),
    /// Layout 1.10: a gantry's homing ended: code 0 squared (the value: slave 0's skew, user
    /// units of the master), else the `MC_HOMING_ERR_*` (or -1: a stop ended it) and the
    /// axis that failed.
    GantryHomed(i32, f64),
    /// Layout 1.11: a group's homing ended: homed (0 and the stages run), or failed (the
    /// `MC_HOMING_ERR_*` or `MC_GROUP_HOME_ABORTED`, and the axis, -1 for none): (homed,
    /// code, value).
    GroupHomed(bool, i32, f64),
}

/// An event from the card. One unit rule for every kind: a `value` that is a position or a
/// distance is in user units of the axis it concerns (the event's axis; a compare or probe
/// channel's: the axis the channel watches), whatever the kind (motion done and active, in
/// velocity (a velocity: user units/s), homing failed, sync, PVT done, compare fired or
/// missed, probe captures, and the safety stops whose measurement is a position, a following
/// error or an encoder count: limits, following error, encoder, amplifier alarm). Every other
/// value is as the card posts it: states, times in seconds, counts of things, ids, words.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CardEvent {
    /// Kind.
    pub kind: EventKind,
    /// Axis (0xFFFF for card-wide events).
    pub axis: u16,
    /// Seq of the command it concerns (motion events: the command that started the motion).
    pub seq: u32,
    /// Kind-specific code.
    pub code: i32,
    /// Servo tick.
    pub tick: u64,
    /// Kind-specific value (positions and distances in user units, see [`CardEvent`]).
    pub value: f64,
}

/// The command ring. A command's seq is its ring index + 1: unique across sessions, since
/// the ring's head carries on from whatever an earlier host left. `deadlines[seq & (len-1)]`
/// is the deadline the command in that slot was sent with.
struct Tx {
    ring: CmdProducer<Window>,
    deadlines: [u32; CMD_RING.len as usize],
}

struct Rx {
    ring: EvtConsumer<Window>,
    /// Someone is blocked in poll() on the interrupt fd; the others wait on the condvar.
    polling: bool,
    /// Answers: the ack's value, or the nack's code.
    acks: VecDeque<(u32, std::result::Result<f64, NackCode>)>,
    outcomes: VecDeque<(u32, Outcome)>,
    events: VecDeque<CardEvent>,
    events_dropped: u64,
    /// Protocol-error events seen (the card found the command ring corrupt and dropped what
    /// was in it), and the ring index of the last.
    protocol_errors: u32,
    protocol_index: f64,
}

/// A group's axis count and card axes, as the card accepted them.
pub(crate) type GroupAxes = (usize, [usize; MAX_AXES]);

/// What a wait gives up on, besides its deadline.
#[derive(Clone, Copy)]
struct WaitRules {
    /// A card whose tick stands still fails the wait with `NotResponding`.
    stale_fails: bool,
    /// [`Card::cancel_waits`] ends it with `Cancelled`.
    cancellable: bool,
    /// [`Card::close`] ends it with `Closed` (a card that is gone ends every wait).
    closable: bool,
}

/// Waits for motions and events: every rule.
const USER_WAIT: WaitRules = WaitRules {
    stale_fails: true,
    cancellable: true,
    closable: true,
};

/// The wait for a command's answer: it ends only when the command can no longer run (see
/// [`Inner::wait_answer`]).
const ACK_WAIT: WaitRules = WaitRules {
    stale_fails: false,
    cancellable: false,
    closable: false,
};

pub(crate) struct Inner {
    pub(crate) group_axes: Mutex<[Option<GroupAxes>; firmware_proto::MAX_GROUPS]>,
    pub(crate) last_group_motion: Mutex<[Option<u32>; firmware_proto::MAX_GROUPS]>,
    /// Per group, what this host keeps of its path: whether streams fit chords into curves
    /// (`PathSettings::chord_fit`) and where the last segment it queued ends.
    pub(crate) path_host: Mutex<[PathHost; firmware_proto::MAX_GROUPS]>,
    dev: Device,
    info: CardInfo,
    tx: Mutex<Tx>,
    rx: Mutex<Rx>,
    rx_cond: Condvar,
    pub(crate) scale: Mutex<[f64; MAX_AXES]>,
    /// Layout 1.8: held while a configuration block is written and applied, or read back, so
    /// that a read-back never interleaves with another thread's write of the same block.
    config: Mutex<()>,
    pub(crate) last_motion: Mutex<[Option<u32>; MAX_AXES]>,
    pub(crate) link: Arc<Link>,
    heartbeat: Mutex<Option<crate::heartbeat::Heartbeat>>,
    /// Axes the attach stopped because the previous host had vanished without closing.
    inherited_stops: u32,
    /// The API trace, when one is recorded.
    trace: Option<crate::trace::Tracer>,
    /// The axis of each compare or probe arm this host sent, by the arm's seq (the last
    /// [`IO_ARMS`]): their events name the channel, not the axis, and carry the arm's seq, so
    /// the drain finds the axis whose scale converts their positions.
    io_arms: Mutex<VecDeque<(u32, u16)>>,
    /// Per axis, the offset of the last gear command this host sent (its ack's value).
    pub(crate) gear_offset: Mutex<[Option<f64>; MAX_AXES]>,
    /// Layout 1.12: the stepped clock this stepped `sim` card shares with the other cards of
    /// its sync bus ([`crate::CardSet::sim`]): stepping it steps them all, master first.
    #[cfg(feature = "emulator")]
    pub(crate) sim_clock: Mutex<Option<Arc<SimClock>>>,
}

/// Stepped `sim` cards on one sync bus: one tick of any of them is one tick of all, the
/// master's first, each host's heartbeat beating before its card's tick.
#[cfg(feature = "emulator")]
pub(crate) struct SimClock {
    pub(crate) members: Vec<(Arc<Mutex<Emulator>>, std::sync::Weak<Inner>)>,
}

#[cfg(feature = "emulator")]
impl SimClock {
    fn step(&self) {
        for (emu, host) in &self.members {
            if let Some(h) = host.upgrade() {
                h.beat();
            }
            lock(emu).step();
        }
    }
}

// Layout 1.12: commands timed to a tick (`crate::cardset`). The timing is this thread's: while
// it is set, `Card::execute_value` sends each command timed and records it here.

/// The tick a timed command runs on, and its commit key (0: none needed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Timing {
    /// The card tick (the bus's tick on a follower).
    pub tick: u64,
    /// The key whose commit the command waits for (0: runs without one).
    pub key: u32,
}

struct Pending {
    timing: Option<Timing>,
    sent: Vec<Sent>,
}

thread_local! {
    static PENDING: std::cell::RefCell<Pending> = const {
        std::cell::RefCell::new(Pending {
            timing: None,
            sent: Vec::new(),
        })
    };
}

/// The timing of commands sent now on this thread (inside [`Card::timed`] or
/// [`CardSet::sync`](crate::CardSet::sync)).
pub(crate) fn timing() -> Option<Timing> {
    PENDING.with(|p| p.borrow().timing)
}

/// A timed command was taken (held by `card`).
pub(crate) fn sent(card: &Card, seq: u32, what: &'static str, target: Target) {
    PENDING.with(|p| p.borrow_mut().sent.push((card.clone(), seq, what, target)));
}

/// What `push_timing` replaced on this thread (restored by `pop_timing`).
pub(crate) struct Saved(Option<Timing>, Vec<Sent>);

/// Time the commands this thread sends from now to `at`.
pub(crate) fn push_timing(at: Timing) -> Saved {
    PENDING.with(|p| {
        let mut p = p.borrow_mut();
        let outer = p.timing.replace(at);
        Saved(outer, std::mem::take(&mut p.sent))
    })
}

/// Stop timing; the commands held since `push_timing`.
pub(crate) fn pop_timing(saved: Saved) -> Vec<Sent> {
    PENDING.with(|p| {
        let mut p = p.borrow_mut();
        p.timing = saved.0;
        std::mem::replace(&mut p.sent, saved.1)
    })
}

/// A command sent timed: its card, seq, name and target.
pub(crate) type Sent = (Card, u32, &'static str, Target);

/// How many compare and probe arms [`Inner`] remembers the axis of.
const IO_ARMS: usize = 64;

/// What a host keeps of a group's path (see `Card`'s `path_host`).
#[derive(Debug, Clone)]
pub(crate) struct PathHost {
    pub chord_fit: bool,
    /// Where the last segment this host queued ends (user units), when known.
    pub end: Option<Vec<f64>>,
}

impl Default for PathHost {
    fn default() -> Self {
        Self {
            chord_fit: true,
            end: None,
        }
    }
}

/// An open card. Cheap to clone; every clone talks to the same card. Safe to use from several
/// threads at once. Dropping the last clone closes it ([`Card::close`]).
#[derive(Clone)]
pub struct Card {
    inner: Arc<Inner>,
}

pub use crate::limits::MoveLimits;
pub(crate) use crate::limits::{finite, positive};
pub(crate) use crate::lock::lock;

impl Card {
    /// Every card reachable from this process: `card-emu` processes, UIO devices and PCI
    /// functions with the card's IDs, each with its name, serial, axes, rate, sync role and
    /// whether a host holds it, read without disturbing that host ([`crate::CardListing`]; how
    /// each is found and read: the `list` module's table in ARCHITECTURE.md).
    pub fn list() -> Result<Vec<crate::CardListing>> {
        let mut out = crate::list::list()?;
        let here = device::open_here();
        for l in &mut out {
            l.open_here = here.contains(&l.uri);
        }
        Ok(out)
    }

    /// The device of `uri`, a `name:` or `serial:` URI resolved through the listing first.
    fn open_device(uri: &str) -> Result<device::Device> {
        if uri.starts_with("name:") || uri.starts_with("serial:") {
            return device::open(&crate::list::resolve(uri)?);
        }
        device::open(uri)
    }

    /// Open a card by URI: `sim` (an emulated card in this process, real-time clock),
    /// `emu:NAME` (a `card-emu` process), `uio:/dev/uioN` or `pci:DDDD:BB:DD.F` (hardware), or
    /// `name:NAME` / `serial:N`: the card [`Card::list`] shows with that name or serial
    /// (`NotFound` if none, `Ambiguous` if several).
    ///
    /// Opening begins a session: if the previous host left the card without closing it (it
    /// died or hung), the card stops every axis that host left enabled (category 1, reason
    /// [`crate::StopReason::HostChanged`]; see [`Card::inherited_stops`]), so a new host never
    /// inherits motion it did not start.
    ///
    /// With [`crate::trace::TRACE_ENV`] set, the card records an API trace ([`crate::trace`]).
    pub fn open(uri: &str) -> Result<Card> {
        Self::attach(
            uri,
            Self::open_device(uri)?,
            crate::trace::Tracer::from_env()?,
        )
    }

    /// [`Card::open`], recording an API trace to `trace` ([`crate::trace`]).
    pub fn open_traced(uri: &str, trace: &std::path::Path) -> Result<Card> {
        let t = crate::trace::Tracer::create(trace)?;
        Self::attach(uri, Self::open_device(uri)?, Some(t))
    }

    /// Open an in-process emulated card with explicit options (for example a stepped clock).
    #[cfg(feature = "emulator")]
    pub fn open_sim(opts: SimOptions) -> Result<Card> {
        Self::attach(
            "sim",
            device::open_sim(&opts)?,
            crate::trace::Tracer::from_env()?,
        )
    }

    /// [`Card::open_sim`], recording an API trace to `trace` ([`crate::trace`]).
    #[cfg(feature = "emulator")]
    pub fn open_sim_traced(opts: SimOptions, trace: &std::path::Path) -> Result<Card> {
        let t = crate::trace::Tracer::create(trace)?;
        Self::attach("sim", device::open_sim(&opts)?, Some(t))
    }

    pub(crate) fn attach(
        uri: &str,
        dev: Device,
        trace: Option<crate::trace::Tracer>,
    ) -> Result<Card> {
        let w = &dev.window;
        let magic = w.read32(layout::MAGIC);
        if magic != firmware_proto::MAGIC {
            return Err(Error::Protocol(format!(
                "{uri}: no motion-card signature in the DPRAM (read {magic:#010x})"
            )));
        }
        let deadline = Instant::now() + Duration::from_secs(1);
        while w.load32(layout::CARD_STATE, Ordering::Acquire) != raw::MC_CARD_RUNNING {
            if Instant::now() > deadline {
                return Err(Error::NotResponding(format!(
                    "{uri}: the card did not finish booting"
                )));
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let lv = w.read32(layout::LAYOUT);
        let (major, minor) = (lv as u16, (lv >> 16) as u16);
        // Layout 1.9 moved the status blocks' checksum (25-word payloads): an older card's
        // status cannot be read (and before 1.3 it could not keep a new host from inheriting
        // motion).
        if major != firmware_proto::LAYOUT_MAJOR || minor < 9 {
            return Err(Error::VersionMismatch {
                card_major: major,
                card_minor: minor,
                lib_major: firmware_proto::LAYOUT_MAJOR,
                lib_minor: firmware_proto::LAYOUT_MINOR,
            });
        }
        let axes = w.read32(layout::NUM_AXES) as usize;
        if axes == 0
            || axes > MAX_AXES
            || w.read32(layout::CMD_RING_LEN) != CMD_RING.len
            || w.read32(layout::EVT_RING_LEN) != EVT_RING.len
        {
            return Err(Error::Protocol(format!(
                "{uri}: identity block is inconsistent ({axes} axes)"
            )));
        }
        let info = CardInfo {
            firmware_version: w.read32(layout::FW_VERSION),
            layout: (major, minor),
            axes,
            servo_rate_hz: w.read32(layout::SERVO_RATE_HZ),
            capabilities: w.read32(layout::CAPABILITIES),
        };
        if let Some(t) = &trace {
            t.header(uri, info.layout, info.axes, info.servo_rate_hz);
        }
        // Every event kind raises the interrupt.
        w.write32(layout::IRQ_MASK, u32::MAX);
        let tx = CmdProducer::attach(w.clone(), CMD_RING);
        let mut rx = EvtConsumer::attach(w.clone(), EVT_RING);
        rx.resync(); // events of an earlier session are not ours
        let stepped = dev.backend.is_stepped();
        let link = Arc::new(Link::new(w.clone(), info.servo_rate_hz, stepped)?);
        let lease = dev.lease_watch();
        let mut inner = Inner {
            heartbeat: Mutex::new(None),
            #[cfg(feature = "emulator")]
            sim_clock: Mutex::new(None),
            link,
            inherited_stops: 0,
            info,
            tx: Mutex::new(Tx {
                ring: tx,
                deadlines: [0; CMD_RING.len as usize],
            }),
            rx: Mutex::new(Rx {
                ring: rx,
                polling: false,
                acks: VecDeque::new(),
                outcomes: VecDeque::new(),
                events: VecDeque::new(),
                events_dropped: 0,
                protocol_errors: 0,
                protocol_index: 0.0,
            }),
            rx_cond: Condvar::new(),
            scale: Mutex::new([1.0; MAX_AXES]),
            config: Mutex::new(()),
            last_motion: Mutex::new([None; MAX_AXES]),
            last_group_motion: Mutex::new([None; firmware_proto::MAX_GROUPS]),
            path_host: Mutex::new(Default::default()),
            group_axes: Mutex::new([None; firmware_proto::MAX_GROUPS]),
            dev,
            trace,
            io_arms: Mutex::new(VecDeque::new()),
            gear_offset: Mutex::new([None; MAX_AXES]),
        };
        // [safety] the session, then at once the heartbeat. The attach arms the card's watchdog
        // (it counts as the first heartbeat), so the beats start as it is sent, not after its
        // ack's round trip, which a short watchdog timeout may not allow. Beats that land
        // before the card serves the attach (one servo period) are a vanished host's for that
        // long at most: the attach then stops what that host left moving.
        inner.link.publish_time();
        let attach = CardCmd::HostAttach(Session {
            id: inner.link.session,
        });
        let seq = inner.send_raw(attach.command(0))?;
        let heartbeat = crate::heartbeat::Heartbeat::start(&inner.dev, inner.link.clone(), lease)?;
        *lock(&inner.heartbeat) = Some(heartbeat);
        match inner.wait_answer(seq)? {
            Ok(stopped) => inner.inherited_stops = stopped as u32,
            Err(code) => {
                inner.link.mark_closed(); // nothing to detach (the attach was refused)
                if let Some(mut h) = lock(&inner.heartbeat).take() {
                    h.halt();
                }
                return Err(Error::Nack {
                    command: "open",
                    target: Target::Card,
                    code,
                    reason: nack_reason(code),
                });
            }
        }
        let card = Card {
            inner: Arc::new(inner),
        };
        // Layout 1.8: the card keeps each axis's scale; a host adopts the units the machine
        // was set up in (an older card keeps none: counts).
        if minor >= 8 {
            for a in 0..axes {
                let s = card.read_axis_config(a)?.0.scale;
                if SCALE_RANGE.contains(&s.abs()) {
                    lock(&card.inner.scale)[a] = s;
                }
            }
        }
        Ok(card)
    }

    /// Layout 1.8: have the card write the settings it holds into the configuration block
    /// `at` (`MC_OP_READ_CONFIG` of `kind`, `index`), and read it after the ack.
    pub(crate) fn read_block<B: Block>(
        &self,
        at: BlockAt<B>,
        kind: firmware_proto::ConfigKind,
        index: usize,
    ) -> Result<B> {
        let _g = lock(&self.inner.config);
        self.read_block_locked(at, kind, index)
    }

    fn read_block_locked<B: Block>(
        &self,
        at: BlockAt<B>,
        kind: firmware_proto::ConfigKind,
        index: usize,
    ) -> Result<B> {
        let target = if kind.per_axis() {
            Target::Axis(index)
        } else if kind.per_group() {
            Target::Group(index)
        } else {
            Target::Card
        };
        // An index beyond the card's integers is refused as the card would (`ConfigKind`).
        let index = u16::try_from(index).map_err(|_| Error::Refused {
            command: "read configuration",
            target,
            code: NackCode::ConfigKind,
            reason: crate::error::nack_reason(NackCode::ConfigKind),
        })?;
        let cmd = CardCmd::ReadConfig(ReadConfig { kind, index }).command(0);
        self.execute(cmd, "read configuration", target)?;
        Ok(at.read(self.window()))
    }

    /// Layout 1.8: an axis's configuration block and its PD+ block as the card holds them
    /// (layout 1.11: and its PID+FF block).
    pub(crate) fn read_axis_config(
        &self,
        a: usize,
    ) -> Result<(
        AxisSettings,
        firmware_proto::AxisPdPlus,
        firmware_proto::AxisPidff,
    )> {
        let _g = lock(&self.inner.config);
        let cfg = self.read_block_locked(
            layout::AXIS_CONFIG.at(a),
            firmware_proto::ConfigKind::Axis,
            a,
        )?;
        let w = self.window();
        Ok((
            cfg,
            layout::AXIS_PDPLUS.at(a).read(w),
            layout::AXIS_PIDFF.at(a).read(w),
        ))
    }

    /// Hold the configuration blocks (a write and its apply, or a read-back) for one thread.
    pub(crate) fn config_lock(&self) -> std::sync::MutexGuard<'_, ()> {
        lock(&self.inner.config)
    }

    pub(crate) fn window(&self) -> &Window {
        &self.inner.dev.window
    }

    #[cfg(feature = "emulator")]
    pub(crate) fn inner_arc(&self) -> &Arc<Inner> {
        &self.inner
    }

    pub(crate) fn inner(&self) -> &Inner {
        &self.inner
    }

    /// Run `f` with the heartbeat (`None` once the card is closed).
    pub(crate) fn with_heartbeat<T>(
        &self,
        f: impl FnOnce(&crate::heartbeat::Heartbeat) -> T,
    ) -> Option<T> {
        lock(&self.inner.heartbeat).as_ref().map(f)
    }

    /// Identity of the card.
    pub fn info(&self) -> CardInfo {
        let mut i = self.inner.info;
        i.servo_rate_hz = self.inner.dev.window.read32(layout::SERVO_RATE_HZ);
        i
    }

    /// How many axes this host's open stopped because the host before it had left the card
    /// without closing it (it died or hung): those axes are in ErrorStop with reason
    /// [`crate::StopReason::HostChanged`] until [`Card::reset_faults`]. 0 when the previous host
    /// closed cleanly or left nothing enabled.
    pub fn inherited_stops(&self) -> u32 {
        self.inner.inherited_stops
    }

    /// The servo tick counter. `NotResponding` when it has stood still for longer than
    /// [`Card::stale_limit`] (a stopped or hung card), `CardGone` when the card process went
    /// away.
    pub fn tick(&self) -> Result<u64> {
        self.inner.link.tick()
    }

    /// How long the card's tick may stand still before reads and waits call it not
    /// responding: the larger of [`crate::STALE_TICKS`] servo periods and
    /// [`crate::STALE_MIN`].
    pub fn stale_limit(&self) -> Duration {
        self.inner.link.stale_limit()
    }

    /// An axis handle.
    pub fn axis(&self, index: usize) -> Result<Axis> {
        if index >= self.inner.info.axes {
            return Err(Error::BadAxis {
                axis: index,
                count: self.inner.info.axes,
            });
        }
        Ok(Axis {
            card: self.clone(),
            index,
        })
    }

    /// All axes.
    pub fn axes(&self) -> Vec<Axis> {
        (0..self.inner.info.axes)
            .map(|i| Axis {
                card: self.clone(),
                index: i,
            })
            .collect()
    }

    /// The interrupt file descriptor, for an application's own epoll loop: it becomes
    /// readable when the card raises an interrupt; then call [`Card::poll_events`].
    /// `None` on `pci:` cards, which have no interrupt line.
    pub fn irq_fd(&self) -> Option<BorrowedFd<'_>> {
        self.inner.dev.irq.fd()
    }

    /// The stepping control of a stepped `sim` card.
    #[cfg(feature = "emulator")]
    pub fn sim(&self) -> Option<Sim> {
        let emu = self.inner.dev.backend.stepped()?;
        Some(Sim {
            emu: emu.clone(),
            card: self.clone(),
        })
    }

    /// Change the servo rate (all axes must be disabled: `AxesEnabled`; outside
    /// 1,000..=20,000 Hz: `BadConfig`). Every filter the card runs keeps its frequencies and
    /// is designed again at the new rate; a rate one of them cannot run at (a frequency at or
    /// above half of it) is refused with that filter's refusal (`FilterFreq`,
    /// `AnalogFilter`, `PsoConfig`), and nothing changes.
    pub fn set_servo_rate(&self, hz: u32) -> Result<()> {
        let block = firmware_proto::raw::mc_card_config {
            servo_rate_hz: hz,
            ..Default::default()
        };
        let _guard = self.config_lock();
        self.write_block(layout::CARD_CONFIG, &block);
        self.execute(
            CardCmd::ApplyCardConfig.command(0),
            "set_servo_rate",
            Target::Card,
        )
    }

    /// A command that does nothing but come back: the round trip through the card.
    pub fn ping(&self) -> Result<()> {
        self.execute(CardCmd::Nop.command(0), "ping", Target::Card)
    }

    /// Close the card: a clean end of this host's session. Moving axes and groups halt along
    /// their stop ramps (reason [`crate::StopReason::HostDetach`]), the card's watchdog is
    /// disarmed without latching a fault (the next host opens a card that is ready to move),
    /// and the heartbeat stops. Every wait in progress on this card, in any thread, returns
    /// [`crate::ErrorKind::Closed`] at once, and so does every later call. Closing twice is
    /// harmless. Dropping the last clone of a `Card` closes it too; only a host that vanishes
    /// without closing trips the watchdog.
    pub fn close(&self) -> Result<()> {
        self.inner.close()
    }

    /// End every wait in progress on this card (motion, group and event waits, in any thread)
    /// with [`crate::ErrorKind::Cancelled`]. Waits that begin afterwards are not affected. The
    /// waits for a command's own answer are not cancelled: the command may still run.
    pub fn cancel_waits(&self) {
        self.inner.link.cancel();
        // the waiters on the condvar look at the flags too
        let _g = lock(&self.inner.rx);
        self.inner.rx_cond.notify_all();
    }

    /// Queue a raw command without waiting for its ack; returns its seq. For tools and tests
    /// that need to send what the typed API would refuse. Its deadline is [`ACK_TIMEOUT`] from
    /// now unless `cmd.deadline_ms` names one.
    ///
    /// The card checks a raw command as any other. A raw `MC_OP_HOST_DETACH` of this card's
    /// own session ends the session on the card while this `Card` stays open: the card halts
    /// what moves and from then on refuses motion, power, outputs and configuration
    /// ([`crate::ErrorKind::NoSession`]) until a host attaches again (a raw `MC_OP_HOST_ATTACH`
    /// with [`crate::SafetyStatus::session`], which arms the watchdog at once).
    pub fn send_raw(&self, cmd: Command) -> Result<u32> {
        self.inner.send_raw(cmd)
    }

    /// [`Card::send_raw`], then wait for the card's answer: the ack's value, or the nack as
    /// [`Error::Nack`] (its kind the nack's, e.g. [`crate::ErrorKind::NoSession`]).
    pub fn execute_raw(&self, cmd: Command) -> Result<f64> {
        self.execute_value(cmd, "send_raw", Target::Card)
            .map(|(_, v)| v)
    }

    /// Wait for the ack or nack of command `seq`. It returns a failure only when the command
    /// can no longer run (see [`ACK_TIMEOUT`]).
    pub fn wait_ack(&self, seq: u32) -> Result<std::result::Result<(), NackCode>> {
        self.inner.wait_answer(seq).map(|r| r.map(|_| ()))
    }

    pub(crate) fn execute(&self, cmd: Command, what: &'static str, target: Target) -> Result<()> {
        self.execute_seq(cmd, what, target).map(|_| ())
    }

    pub(crate) fn execute_seq(
        &self,
        cmd: Command,
        what: &'static str,
        target: Target,
    ) -> Result<u32> {
        self.execute_value(cmd, what, target).map(|(seq, _)| seq)
    }

    /// Layout 1.13: `cmds` published together (a move whose arguments take several entries),
    /// and the first one's seq once the card accepted them (it answers each; a refusal is the
    /// first one's). Not inside [`Card::timed`]: the card times one entry.
    pub(crate) fn execute_together(
        &self,
        cmds: &mut [Command],
        what: &'static str,
        target: Target,
    ) -> Result<u32> {
        if timing().is_some() {
            return Err(Error::Unsupported(format!(
                "{what} takes {} command entries: it cannot be timed",
                cmds.len()
            )));
        }
        self.inner.execute_together(cmds, what, target)
    }

    /// [`Card::execute_seq`] with the ack's value (a compare table's or a PT/PVT buffer's
    /// room). Inside [`Card::timed`] or [`crate::CardSet::sync`] (layout 1.12) the command is
    /// sent timed: the seq once the card holds it, the value 0.
    pub(crate) fn execute_value(
        &self,
        cmd: Command,
        what: &'static str,
        target: Target,
    ) -> Result<(u32, f64)> {
        if let Some(at) = timing() {
            let seq = self.inner.execute_timed(at, cmd, what, target)?;
            sent(self, seq, what, target);
            return Ok((seq, 0.0));
        }
        self.inner.execute_value(cmd, what, target)
    }

    /// Wait until `check` (reading the window) gives an answer, up to `timeout` (emulated time
    /// on a stepped card, which is stepped meanwhile).
    pub(crate) fn wait_window<T>(
        &self,
        timeout: Duration,
        mut check: impl FnMut() -> Option<Result<T>>,
    ) -> Result<T> {
        self.inner
            .wait_until(Instant::now() + timeout, USER_WAIT, |_| check())?
    }

    /// Take the next event, waiting up to `timeout` (zero: don't wait).
    pub fn next_event(&self, timeout: Duration) -> Result<Option<CardEvent>> {
        let r = self
            .inner
            .wait_until(Instant::now() + timeout, USER_WAIT, |rx| {
                rx.events.pop_front()
            });
        match r {
            Ok(e) => Ok(Some(e)),
            Err(Error::Timeout(_)) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Drain the card's event ring without waiting (call when the irq fd is readable).
    /// Returns how many events were queued.
    pub fn poll_events(&self) -> Result<usize> {
        self.inner.link.check()?;
        self.inner.dev.irq.acknowledge();
        let mut rx = lock(&self.inner.rx);
        let before = rx.events.len();
        self.inner.drain(&mut rx)?;
        Ok(rx.events.len().saturating_sub(before))
    }

    /// Events dropped because nobody took them from the queue (beyond [`EVENT_QUEUE_CAP`]),
    /// and events the card could not post because its event ring was full.
    pub fn events_lost(&self) -> (u64, u32) {
        (
            lock(&self.inner.rx).events_dropped,
            self.inner.dev.window.read32(layout::EVENTS_LOST),
        )
    }

    pub(crate) fn scale(&self, axis: usize) -> f64 {
        self.inner.scale(axis)
    }

    /// Wait until the card has run at least one more servo tick (a stepped card is stepped).
    pub(crate) fn wait_next_tick(&self, timeout: Duration) -> Result<()> {
        let w = &self.inner.dev.window;
        let t0 = w.read64(layout::TICK);
        self.inner
            .wait_until(Instant::now() + timeout, USER_WAIT, |_| {
                (w.read64(layout::TICK) != t0).then_some(())
            })
    }

    pub(crate) fn wait_outcome(&self, target: Target, seq: u32, timeout: Duration) -> Result<f64> {
        self.wait_for(target, seq, timeout, |o| match o {
            Outcome::Done(p) => Some(p),
            _ => None,
        })
    }

    /// Wait for the first outcome of motion `seq` that `pick` takes, or its abort (or, for a
    /// homing, its failure).
    pub(crate) fn wait_for(
        &self,
        target: Target,
        seq: u32,
        timeout: Duration,
        pick: impl Fn(Outcome) -> Option<f64>,
    ) -> Result<f64> {
        let r = self
            .inner
            .wait_until(Instant::now() + timeout, USER_WAIT, |rx| {
                rx.outcomes
                    .iter()
                    .filter(|(s, _)| *s == seq)
                    .find_map(|(_, o)| match *o {
                        Outcome::Aborted(_) | Outcome::HomingFailed(..) => Some(Err(*o)),
                        o => pick(o).map(Ok),
                    })
            })?;
        r.map_err(|o| match o {
            Outcome::HomingFailed(code, at) => Error::HomingFailed {
                target,
                error: firmware_proto::HomingError::from_raw(code),
                at,
            },
            Outcome::Aborted(code) => Error::Aborted {
                target,
                by: abort_reason(code),
            },
            _ => Error::Protocol(format!("motion {seq} ended as {o:?}")),
        })
    }
}

impl Card {
    /// Layout 1.10: wait for the end of gantry `g`'s homing `seq` (its members' own motion
    /// events carry the same seq and are not it): slave 0's skew once squared, user units.
    pub(crate) fn wait_gantry_homed(&self, g: usize, seq: u32, timeout: Duration) -> Result<f64> {
        let (code, value) = self
            .inner
            .wait_until(Instant::now() + timeout, USER_WAIT, |rx| {
                rx.outcomes.iter().find_map(|(s, o)| match *o {
                    Outcome::GantryHomed(code, value) if *s == seq => Some((code, value)),
                    _ => None,
                })
            })?;
        if code == 0 {
            return Ok(value);
        }
        Err(Error::GantryHomingFailed {
            gantry: g,
            axis: value as usize,
            error: firmware_proto::HomingError::from_raw(code),
        })
    }
}

impl Card {
    /// Layout 1.11: wait for the end of group `g`'s homing `seq` (its members' own motion
    /// events carry the same seq and are not it): the stages run.
    pub(crate) fn wait_group_homed(&self, g: usize, seq: u32, timeout: Duration) -> Result<usize> {
        let (homed, code, value) =
            self.inner
                .wait_until(Instant::now() + timeout, USER_WAIT, |rx| {
                    rx.outcomes.iter().find_map(|(s, o)| match *o {
                        Outcome::GroupHomed(homed, code, value) if *s == seq => {
                            Some((homed, code, value))
                        }
                        _ => None,
                    })
                })?;
        if homed {
            return Ok(value as usize);
        }
        Err(Error::GroupHomingFailed {
            group: g,
            axis: (value >= 0.0).then_some(value as usize),
            error: firmware_proto::HomingError::from_raw(code),
        })
    }
}

impl Card {
    /// The status of several axes in one call (`GT_GetSts` with a count, `APS_get_*` over
    /// axes): every one of the same servo tick (the card publishes every axis each tick; a
    /// pass that straddles two ticks is read again, for up to 100 ms, then `NotResponding`),
    /// each a consistent snapshot, and one check that the card is alive. Axes appear in the
    /// order asked.
    pub fn statuses(&self, axes: &[usize]) -> Result<Vec<Status>> {
        for &a in axes {
            if a >= self.inner.info.axes {
                return Err(Error::BadAxis {
                    axis: a,
                    count: self.inner.info.axes,
                });
            }
        }
        let until = Instant::now() + Duration::from_millis(100);
        let raws = loop {
            let mut raws = Vec::with_capacity(axes.len());
            for &a in axes {
                raws.push((a, self.read_axis_status(a)?));
            }
            let first = raws.first().map(|(_, r)| r.tick);
            if raws.iter().all(|(_, r)| Some(r.tick) == first) {
                break raws;
            }
            if Instant::now() > until {
                return Err(Error::NotResponding(format!(
                    "the statuses of axes {axes:?} were never all of one tick in 100 ms"
                )));
            }
            std::thread::yield_now();
        };
        let newest = raws.iter().map(|(_, r)| r.tick).max();
        self.link_alive(newest.unwrap_or_else(|| self.inner.dev.window.read64(layout::TICK)))?;
        raws.into_iter()
            .map(|(a, raw)| Status::from_raw(a, raw, self.scale(a)))
            .collect()
    }

    /// Change a configuration block with `change` and have the card apply it with `cmd`. The
    /// block is the card's input and the host its one writer: when the card refuses the new
    /// contents, the block is put back as it was, so a refused value never rides along with the
    /// next accepted change of another field.
    pub(crate) fn apply_block<B: Block>(
        &self,
        at: BlockAt<B>,
        change: impl FnOnce(&mut B),
        cmd: Command,
        what: &'static str,
        target: Target,
    ) -> Result<()> {
        let _g = lock(&self.inner.config);
        let w = self.window();
        let saved = at.read(w);
        let mut block = saved;
        change(&mut block);
        self.write_block(at, &block);
        let r = self.execute(cmd, what, target);
        if matches!(r, Err(Error::Nack { .. })) {
            self.write_block(at, &saved);
        }
        r
    }

    /// Write a configuration block into the window (and into the trace).
    pub(crate) fn write_block<B: Block>(&self, at: BlockAt<B>, block: &B) {
        at.write(self.window(), block);
        self.inner.traced(at.range());
    }

    /// Is the card alive, given a tick it published (see [`Card::stale_limit`])?
    pub(crate) fn link_alive(&self, tick: u64) -> Result<()> {
        self.inner.link.alive(tick)
    }

    /// A consistent snapshot of axis `a`'s status block, in counts.
    pub(crate) fn read_axis_status(&self, a: usize) -> Result<AxisStatus> {
        self.inner.link.check()?;
        self.read_snapshot(&format!("axis {a}"), |w| seqlock::read_axis_status(w, a))
    }

    /// A consistent snapshot read with `read` (the status of `what`).
    ///
    /// When the block stays busy through the seqlock's spins, the reader yields and tries
    /// again for up to 100 ms: an emulated card's writer is a thread that the OS can deschedule
    /// mid-write, and a reader descheduled mid-read sees a block rewritten every tick, which
    /// are stalls, not a dead card.
    pub(crate) fn read_snapshot<T>(
        &self,
        what: &str,
        read: impl Fn(&Window) -> std::result::Result<T, SnapshotError>,
    ) -> Result<T> {
        let window = &self.inner.dev.window;
        let mut deadline = None;
        loop {
            match read(window) {
                Err(SnapshotError::Busy)
                    if Instant::now()
                        < *deadline.get_or_insert_with(|| Instant::now() + STATUS_BUSY_TIMEOUT) =>
                {
                    std::thread::yield_now()
                }
                r => break r,
            }
        }
        .map_err(|e| match e {
            SnapshotError::Busy => Error::NotResponding(format!(
                "status of {what} stayed busy for {STATUS_BUSY_TIMEOUT:?}"
            )),
            SnapshotError::Corrupt => {
                Error::Protocol(format!("status of {what} failed its checksum"))
            }
        })
    }
}

impl Status {
    pub(crate) fn from_raw(axis: usize, raw: AxisStatus, s: f64) -> Result<Status> {
        let state = raw.state().ok_or_else(|| {
            Error::Protocol(format!("axis {axis} reports unknown state {}", raw.state))
        })?;
        Ok(Status {
            state,
            command_position: raw.cmd_pos / s,
            command_velocity: raw.cmd_vel / s,
            command_acceleration: raw.cmd_acc / s,
            actual_position: raw.act_pos / s,
            compensated_position: raw.comp_pos / s,
            actual_velocity: raw.act_vel / s,
            following_error: raw.ferr / s,
            dac_volts: raw.dac_v,
            faults: raw.faults(),
            motion: raw.motion(),
            queued: raw.queued,
            override_factor: raw.override_factor,
            raw,
        })
    }
}

impl Inner {
    fn scale(&self, axis: usize) -> f64 {
        lock(&self.scale).get(axis).copied().unwrap_or(1.0)
    }

    /// The emulator of a stepped `sim` card.
    #[cfg(feature = "emulator")]
    pub(crate) fn stepped(&self) -> Option<&Arc<Mutex<Emulator>>> {
        self.dev.backend.stepped()
    }

    /// One servo tick of a stepped card, with the host's heartbeat before it (of every card
    /// of its stepped sync bus, layout 1.12).
    #[cfg(feature = "emulator")]
    fn step_stepped(&self, emu: &Mutex<Emulator>) {
        let clock = lock(&self.sim_clock).clone();
        match clock {
            Some(c) => c.step(),
            None => {
                self.beat();
                lock(emu).step();
            }
        }
    }

    #[cfg(feature = "emulator")]
    fn beat(&self) {
        if let Some(h) = lock(&self.heartbeat).as_ref() {
            h.beat();
        }
    }

    pub(crate) fn send_raw(&self, cmd: Command) -> Result<u32> {
        self.link.check()?;
        self.push(cmd)
    }

    /// Take the events in the card's ring as they are (a replay compares them), without the
    /// bookkeeping of [`Inner::drain`].
    #[cfg(feature = "emulator")]
    pub(crate) fn take_raw_events(&self, out: &mut VecDeque<Event>) -> Result<()> {
        let mut rx = lock(&self.rx);
        loop {
            match rx.ring.pop() {
                Ok(Some(e)) => out.push_back(e),
                Ok(None) => return Ok(()),
                Err(e) => return Err(Error::Protocol(format!("event ring: {e}"))),
            }
        }
    }

    /// The host wrote the window over `range`: into the trace.
    pub(crate) fn traced(&self, range: std::ops::Range<usize>) {
        if let Some(t) = &self.trace {
            t.block(&self.dev.window, range);
        }
    }

    /// Put a command into the ring (whether the session is closed is the caller's business).
    fn push(&self, cmd: Command) -> Result<u32> {
        self.push_all(&mut [cmd])
    }

    /// Put `cmds` into the ring together (published at once: the card takes all or none of
    /// them in one go); the first one's seq (the others follow it).
    pub(crate) fn push_all(&self, cmds: &mut [Command]) -> Result<u32> {
        self.link.check_gone()?;
        let w = &self.dev.window;
        let mut tx = lock(&self.tx);
        // One writer per ring: a head this host did not write means another process writes
        // into this card's window. The card then finds the ring corrupt and stops every axis.
        let head = w.load32(CMD_RING.head, Ordering::Acquire);
        if head != tx.ring.head() {
            let mine = tx.ring.head();
            tx.ring = CmdProducer::attach(w.clone(), CMD_RING);
            return Err(Error::Protocol(format!(
                "the command ring's head is {head}, this host wrote {mine}: another process \
                 is writing commands into this card's window (the card stops every axis when \
                 it finds its ring corrupt); nothing was sent"
            )));
        }
        for (k, cmd) in cmds.iter_mut().enumerate() {
            cmd.seq = tx.ring.head().wrapping_add(1 + k as u32);
            if cmd.deadline_ms == 0 {
                cmd.deadline_ms = self.link.deadline();
            }
        }
        for cmd in cmds.iter() {
            if cmd.opcode == raw::MC_OP_COMPARE_ARM as u16
                || cmd.opcode == raw::MC_OP_PROBE_ARM as u16
            {
                // Before the ring: no event of this arm can be drained before it is known.
                let mut arms = lock(&self.io_arms);
                if arms.len() >= IO_ARMS {
                    arms.pop_front();
                }
                arms.push_back((cmd.seq, cmd.axis));
            }
        }
        match tx.ring.push_all(cmds) {
            Ok(()) => {}
            Err(RingError::Full) => return Err(Error::RingFull(CMD_RING.len)),
            Err(RingError::Corrupt { head, tail }) => {
                return Err(Error::Protocol(format!(
                    "command ring indices corrupt (head {head}, tail {tail})"
                )))
            }
        }
        for cmd in cmds.iter() {
            tx.deadlines[(cmd.seq & (CMD_RING.len - 1)) as usize] = cmd.deadline_ms;
            if let Some(t) = &self.trace {
                t.command(cmd);
            }
        }
        w.write32(layout::DOORBELL, w.read32(layout::DOORBELL).wrapping_add(1));
        drop(tx);
        #[cfg(feature = "emulator")]
        if let Some(emu) = self.dev.backend.stepped() {
            // A stepped card serves its channel when the doorbell rings, between ticks.
            lock(emu).serve();
        }
        Ok(cmds[0].seq)
    }

    pub(crate) fn execute_value(
        &self,
        cmd: Command,
        what: &'static str,
        target: Target,
    ) -> Result<(u32, f64)> {
        let seq = self.send_raw(cmd)?;
        match self.wait_answer(seq)? {
            Ok(v) => Ok((seq, v)),
            Err(code) => Err(Error::Nack {
                command: what,
                target,
                code,
                reason: nack_reason(code),
            }),
        }
    }

    /// Layout 1.13: [`Card::execute_together`]: `cmds` published at once, then each one's
    /// answer (the card gives them together), the first one's outcome returned.
    pub(crate) fn execute_together(
        &self,
        cmds: &mut [Command],
        what: &'static str,
        target: Target,
    ) -> Result<u32> {
        self.link.check()?;
        let first = self.push_all(cmds)?;
        let answer = self.wait_answer(first)?;
        for k in 1..cmds.len() as u32 {
            // (the same outcome: taken off the answers so that none is left behind)
            let _ = self.wait_answer(first.wrapping_add(k))?;
        }
        match answer {
            Ok(_) => Ok(first),
            Err(code) => Err(Error::Nack {
                command: what,
                target,
                code,
                reason: nack_reason(code),
            }),
        }
    }

    /// Layout 1.12: send `cmd` timed to `at` (`MC_OP_AT_TICK` and `cmd` published together)
    /// and wait for the timing's answer: the command's seq once the card holds it (its own
    /// answer comes on its tick: [`Inner::wait_timed_answer`]), else the refusal.
    pub(crate) fn execute_timed(
        &self,
        at: Timing,
        cmd: Command,
        what: &'static str,
        target: Target,
    ) -> Result<u32> {
        self.link.check()?;
        let timing = firmware_proto::cmd::CardCmd::AtTick(firmware_proto::cmd::AtTick {
            tick: at.tick,
            key: at.key,
        })
        .command(0);
        let first = self.push_all(&mut [timing, cmd])?;
        match self.wait_answer(first)? {
            Ok(_) => Ok(first.wrapping_add(1)),
            Err(code) => Err(Error::Nack {
                command: what,
                target,
                code,
                reason: nack_reason(code),
            }),
        }
    }

    /// The answer to timed command `seq`, due on its tick: wait until `until` (stepping a
    /// stepped card).
    pub(crate) fn wait_timed_answer(
        &self,
        seq: u32,
        until: Instant,
    ) -> Result<std::result::Result<f64, NackCode>> {
        let find = |rx: &mut Rx| {
            let i = rx.acks.iter().position(|(s, _)| *s == seq)?;
            rx.acks.remove(i).map(|(_, r)| r)
        };
        self.wait_until(until, ACK_WAIT, find)
    }

    /// Wait for the answer to command `seq` (the ack's value, or the nack). A failure is
    /// returned only when the command can no longer run: the card is gone, the card dropped
    /// the command ring's contents (a protocol error), or its deadline passed and the card
    /// has not taken it (then the card refuses it when it does: `MC_NACK_EXPIRED`).
    fn wait_answer(&self, seq: u32) -> Result<std::result::Result<f64, NackCode>> {
        let deadline = lock(&self.tx).deadlines[(seq & (CMD_RING.len - 1)) as usize];
        let protocol_errors = lock(&self.rx).protocol_errors;
        let find = |rx: &mut Rx| {
            if let Some(i) = rx.acks.iter().position(|(s, _)| *s == seq) {
                return rx.acks.remove(i).map(|(_, r)| Ok(r));
            }
            (rx.protocol_errors != protocol_errors).then_some(Err(rx.protocol_index))
        };
        let corrupt = |index: f64| {
            Error::Protocol(format!(
                "the card found its command ring corrupt (head {index}) and dropped command \
                 {seq} unexecuted; it stopped every axis. Another process may be writing into \
                 this card's window"
            ))
        };
        // Until the deadline has surely passed on the host's clock.
        let ms_left = deadline.wrapping_sub(host_ms()) as i32;
        let until = Instant::now() + Duration::from_millis(ms_left.clamp(0, 60_000) as u64 + 2);
        let mut r = self.wait_until(until, ACK_WAIT, find);
        if matches!(r, Err(Error::Timeout(_))) {
            while !passed(host_ms(), deadline) {
                std::thread::sleep(Duration::from_millis(1));
            }
            // Give up only on a command the card will not run: publish the clock past the
            // deadline, then look whether the card has taken the command (the card takes,
            // fences, then reads the clock; see the session module).
            self.link.publish_time();
            let tail = self.dev.window.load32(CMD_RING.tail, Ordering::SeqCst);
            let taken = (tail.wrapping_sub(seq) as i32) >= 0;
            r = if taken {
                // Taken before the deadline passed: its answer is on its way.
                match self.wait_until(Instant::now() + ACK_TIMEOUT, ACK_WAIT, find) {
                    Err(Error::Timeout(_)) => Err(Error::NotResponding(format!(
                        "the card took command {seq} but has not answered in {:?}: its \
                         outcome is unknown",
                        ACK_TIMEOUT * 2
                    ))),
                    r => r,
                }
            } else {
                let mut rx = lock(&self.rx);
                self.drain(&mut rx)?;
                find(&mut rx).ok_or_else(|| {
                    let tick = self.dev.window.read64(layout::TICK);
                    Error::NotResponding(format!(
                        "the card did not take command {seq} within {ACK_TIMEOUT:?} (its tick \
                         counter reads {tick}); the command has expired and will not run"
                    ))
                })
            };
        }
        r?.map_err(corrupt)
    }

    /// The axis in whose units an event's value is a position or a distance (`None`: the value
    /// is no position: a state, a time, a count, an id, a word). The one rule of
    /// [`CardEvent::value`]: every position or distance is in user units.
    fn position_axis(&self, kind: EventKind, e: &Event) -> Option<usize> {
        let axis = e.axis as usize;
        match kind {
            EventKind::MotionDone
            | EventKind::MotionActive
            | EventKind::InVelocity
            | EventKind::HomingFailed => Some(axis),
            EventKind::Sync => {
                (e.code != firmware_proto::SyncEvent::MasterLost as i32).then_some(axis)
            }
            EventKind::Pvt => (e.code == firmware_proto::PvtEvent::Done as i32).then_some(axis),
            // Layout 1.10: a skew or a squared gantry's skew, in its master's units.
            EventKind::GantryHomed if e.code == 0 => self.gantry_master(axis),
            EventKind::GantryFault if e.code == firmware_proto::StopReason::GantrySkew as i32 => {
                self.gantry_master(axis)
            }
            EventKind::SafetyStop if e.axis != 0xFFFF => {
                let reason = firmware_proto::StopReason::from_raw(e.code as u32)?;
                use firmware_proto::StopReason as R;
                matches!(
                    reason,
                    R::HardLimitPos
                        | R::HardLimitNeg
                        | R::SoftLimitPos
                        | R::SoftLimitNeg
                        | R::FollowingError
                        | R::EncoderLoss
                        | R::EncoderJump
                        | R::AmpAlarm
                )
                .then_some(axis)
            }
            // The channel's axis: the arm's, by its seq (else the card's word for the
            // channel, when this host did not send the arm).
            EventKind::Compare if e.code != raw::MC_CMP_LOW_WATER as i32 => {
                self.io_arm_axis(e.seq).or_else(|| {
                    let b = layout::COMPARE_STATUS.try_at(axis)?;
                    Some(b.read(&self.dev.window).axis as usize)
                })
            }
            EventKind::Probe => self.io_arm_axis(e.seq).or_else(|| {
                let b = layout::PROBE_STATUS.try_at(axis)?;
                Some(b.read(&self.dev.window).axis as usize)
            }),
            _ => None,
        }
    }

    /// The master of gantry `g`, as its status block says (`None`: not formed).
    fn gantry_master(&self, g: usize) -> Option<usize> {
        let b = layout::GANTRY_STATUS.try_at(g)?.read(&self.dev.window);
        (b.phase != raw::MC_GANTRY_NONE).then_some(b.master as usize)
    }

    /// The least watchdog timeout this card takes from a host, µs (0: none; see
    /// [`crate::SIM_WATCHDOG_ENV`]).
    pub(crate) fn watchdog_floor_us(&self) -> u32 {
        self.dev.watchdog_floor_us
    }

    fn io_arm_axis(&self, seq: u32) -> Option<usize> {
        lock(&self.io_arms)
            .iter()
            .rev()
            .find(|(s, _)| *s == seq)
            .map(|(_, a)| *a as usize)
    }

    fn drain(&self, rx: &mut Rx) -> Result<()> {
        loop {
            let e: Event = match rx.ring.pop() {
                Ok(Some(e)) => e,
                Ok(None) => return Ok(()),
                Err(e) => return Err(Error::Protocol(format!("event ring: {e}"))),
            };
            if let Some(t) = &self.trace {
                t.event(&e);
            }
            let Some(kind) = e.kind() else { continue };
            match kind {
                EventKind::Ack => push_capped(&mut rx.acks, (e.seq, Ok(e.value)), OUTCOME_CAP),
                EventKind::Nack => {
                    let code = NackCode::from_raw(e.code).unwrap_or(NackCode::UnknownOpcode);
                    push_capped(&mut rx.acks, (e.seq, Err(code)), OUTCOME_CAP)
                }
                _ => {
                    let value = match self.position_axis(kind, &e) {
                        Some(axis) => e.value / self.scale(axis),
                        None => e.value,
                    };
                    match kind {
                        EventKind::MotionDone | EventKind::GroupMotionDone => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::Done(value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::MotionAborted | EventKind::GroupMotionAborted => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::Aborted(e.code)),
                            OUTCOME_CAP,
                        ),
                        EventKind::MotionActive => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::Active(value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::InVelocity => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::InVelocity(value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::HomingFailed => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::HomingFailed(e.code, value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::Sync => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::Sync(e.code, value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::GantryHomed => push_capped(
                            &mut rx.outcomes,
                            (e.seq, Outcome::GantryHomed(e.code, value)),
                            OUTCOME_CAP,
                        ),
                        EventKind::GroupHomed | EventKind::GroupHomingFailed => push_capped(
                            &mut rx.outcomes,
                            (
                                e.seq,
                                Outcome::GroupHomed(
                                    e.kind == EventKind::GroupHomed as u16,
                                    e.code,
                                    value,
                                ),
                            ),
                            OUTCOME_CAP,
                        ),
                        EventKind::ProtocolError if e.code == raw::MC_PROTO_CMD_RING as i32 => {
                            rx.protocol_errors = rx.protocol_errors.wrapping_add(1);
                            rx.protocol_index = e.value;
                        }
                        _ => {}
                    }
                    if rx.events.len() >= EVENT_QUEUE_CAP {
                        rx.events.pop_front();
                        rx.events_dropped += 1;
                    }
                    rx.events.push_back(CardEvent {
                        kind,
                        axis: e.axis,
                        seq: e.seq,
                        code: e.code,
                        tick: e.tick,
                        value,
                    });
                }
            }
        }
    }

    /// Wait until `check` finds what it wants in the drained events, or `deadline`.
    ///
    /// One waiter at a time blocks in poll() on the interrupt fd and the session's wake-up fd;
    /// the others sleep on a condvar and are woken when it has drained the ring. Every wait
    /// ends at once when the card is closed or its process goes away; `rules` say whether a
    /// card that stopped ticking, or a cancel, ends it too. On a stepped `sim` card, waiting
    /// advances the card's time instead (the deadline is then in emulated time).
    fn wait_until<T>(
        &self,
        deadline: Instant,
        rules: WaitRules,
        mut check: impl FnMut(&mut Rx) -> Option<T>,
    ) -> Result<T> {
        let start = Instant::now();
        let cancels = self.link.cancels();
        let ended = || -> Result<()> {
            if rules.closable {
                self.link.check()?;
            } else {
                self.link.check_gone()?;
            }
            if rules.cancellable && self.link.cancels() != cancels {
                return Err(Error::Cancelled);
            }
            Ok(())
        };
        #[cfg(feature = "emulator")]
        if let Some(emu) = self.dev.backend.stepped() {
            let timeout = deadline.saturating_duration_since(start);
            return self.wait_stepped(emu, timeout, ended, check);
        }
        // Poll in slices, so a card that stops ticking is noticed within its staleness limit.
        let slice = (self.link.stale_limit() / 2).max(Duration::from_millis(1));
        let mut rx = lock(&self.rx);
        loop {
            ended()?;
            self.drain(&mut rx)?;
            if let Some(t) = check(&mut rx) {
                return Ok(t);
            }
            if rules.stale_fails {
                let tick = self.dev.window.read64(layout::TICK);
                self.link.alive_since(tick, Some(start))?;
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(Error::Timeout(deadline.saturating_duration_since(start)));
            }
            let left = (deadline - now).min(slice);
            // A card that busy-polls its command ring answers within microseconds: look at the
            // ring a little longer before paying for a sleep and a wake-up in poll().
            if !rx.polling && now - start < SPIN_BEFORE_POLL {
                drop(rx);
                for _ in 0..64 {
                    std::hint::spin_loop();
                }
                rx = lock(&self.rx);
                continue;
            }
            if rx.polling {
                rx = self
                    .rx_cond
                    .wait_timeout(rx, left)
                    .map(|(g, _)| g)
                    .unwrap_or_else(|p| p.into_inner().0);
                continue;
            }
            rx.polling = true;
            drop(rx);
            let ms = PollTimeout::from(left.as_millis().clamp(1, 60_000) as u16);
            let wake = self.link.wake_fd();
            let (irq_ready, woken) = match self.dev.irq.fd() {
                Some(fd) => {
                    let mut fds = [
                        PollFd::new(fd, PollFlags::POLLIN),
                        PollFd::new(wake, PollFlags::POLLIN),
                    ];
                    let ok = matches!(poll(&mut fds, ms), Ok(n) if n > 0);
                    let ready = |f: &PollFd| f.revents().is_some_and(|r| !r.is_empty());
                    (ok && ready(&fds[0]), ok && ready(&fds[1]))
                }
                None => {
                    // pci: no interrupt line; look at the ring again shortly.
                    let mut fds = [PollFd::new(wake, PollFlags::POLLIN)];
                    let step = PollTimeout::from(left.as_millis().clamp(0, 1) as u16);
                    (false, matches!(poll(&mut fds, step), Ok(n) if n > 0))
                }
            };
            if irq_ready {
                self.dev.irq.acknowledge();
            }
            if woken {
                self.link.clear_wake();
            }
            rx = lock(&self.rx);
            rx.polling = false;
            self.rx_cond.notify_all();
        }
    }

    #[cfg(feature = "emulator")]
    fn wait_stepped<T>(
        &self,
        emu: &Mutex<Emulator>,
        timeout: Duration,
        ended: impl Fn() -> Result<()>,
        mut check: impl FnMut(&mut Rx) -> Option<T>,
    ) -> Result<T> {
        let ticks = {
            let e = lock(emu);
            (timeout.as_secs_f64() * e.firmware().servo_rate_hz() as f64).ceil() as u64
        };
        let mut n = 0u64;
        loop {
            ended()?;
            {
                let mut rx = lock(&self.rx);
                self.drain(&mut rx)?;
                if let Some(t) = check(&mut rx) {
                    return Ok(t);
                }
            }
            // A card that stopped serving for want of room for its answers (the host had not
            // drained them) serves again now that the drain made room, before a tick passes:
            // a stream of hundreds of commands then runs between two ticks, as the doorbell's
            // serve runs it, instead of stepping the card in the middle.
            if lock(emu).serve() > 0 {
                continue;
            }
            if n >= ticks {
                return Err(Error::Timeout(timeout));
            }
            self.step_stepped(emu);
            n += 1;
        }
    }

    /// The clean end of the session: every wait in progress ends and every later call fails
    /// (`Closed`), then the detach (the card halts what moves and disarms its watchdog), then
    /// the heartbeat stops. Once; later calls do nothing.
    fn close(&self) -> Result<()> {
        if !self.link.mark_closed() {
            return Ok(());
        }
        drop(lock(&self.rx));
        self.rx_cond.notify_all();
        let detach = CardCmd::HostDetach(Session {
            id: self.link.session,
        })
        .command(0);
        // A card that is gone or does not answer cannot be detached: closing still ends the
        // session on this side (the card's watchdog then does what it must).
        let sent = self
            .push(detach)
            .and_then(|seq| match self.wait_answer(seq)? {
                Ok(_) => Ok(()),
                Err(code) => Err(Error::Nack {
                    command: "close",
                    target: Target::Card,
                    code,
                    reason: nack_reason(code),
                }),
            });
        if let Some(mut h) = lock(&self.heartbeat).take() {
            h.halt();
        }
        self.dev.release_lease();
        match sent {
            Err(e) if e.kind() == crate::ErrorKind::CardGone => Ok(()),
            r => r,
        }
    }
}

impl Drop for Inner {
    fn drop(&mut self) {
        let _ = self.close();
    }
}

fn abort_reason(code: i32) -> String {
    match u16::try_from(code).ok().and_then(Opcode::from_raw) {
        Some(op) => format!("{op:?}"),
        None => crate::error::fault_name(code).map_or(format!("fault {code}"), String::from),
    }
}

fn push_capped<T>(q: &mut VecDeque<T>, v: T, cap: usize) {
    if q.len() >= cap {
        q.pop_front();
    }
    q.push_back(v);
}

/// Stepping control of a stepped `sim` card: time advances only when asked.
#[cfg(feature = "emulator")]
#[derive(Clone)]
pub struct Sim {
    emu: Arc<Mutex<Emulator>>,
    card: Card,
}

#[cfg(feature = "emulator")]
impl Sim {
    /// Advance `n` servo periods (the host's heartbeat beats once per period).
    pub fn step(&self, n: u64) {
        for _ in 0..n {
            self.card.inner.step_stepped(&self.emu);
        }
    }

    /// Emulated time since boot, s.
    pub fn time(&self) -> f64 {
        lock(&self.emu).time()
    }

    /// Run `f` on the emulator (plant access, fault injection).
    pub fn with_emulator<T>(&self, f: impl FnOnce(&mut Emulator) -> T) -> T {
        f(&mut lock(&self.emu))
    }

    /// Step one period at a time, calling `f` with the axis statuses after each, for `n`
    /// periods or until `f` returns false.
    pub fn trace(&self, axis: usize, n: u64, mut f: impl FnMut(&Status) -> bool) -> Result<()> {
        let ax = self.card.axis(axis)?;
        for _ in 0..n {
            self.step(1);
            if !f(&ax.status()?) {
                break;
            }
        }
        Ok(())
    }
}

/// An axis's status, in user units (and the raw counts in `raw`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Status {
    /// PLCopen state.
    pub state: AxisState,
    /// Commanded position.
    pub command_position: f64,
    /// Commanded velocity.
    pub command_velocity: f64,
    /// Commanded acceleration.
    pub command_acceleration: f64,
    /// Actual position (layout 1.9: the load's, the encoder's less the compensation's
    /// correction).
    pub actual_position: f64,
    /// Layout 1.9: the compensated position, the motor's reference (the commanded position
    /// plus the pitch-error and backlash correction; the commanded position without
    /// compensation).
    pub compensated_position: f64,
    /// Actual velocity.
    pub actual_velocity: f64,
    /// Following error (commanded − actual).
    pub following_error: f64,
    /// DAC output, volts.
    pub dac_volts: f64,
    /// Fault bits.
    pub faults: Faults,
    /// Motion bits: in velocity, paused by a 0 % override, running a buffered move.
    pub motion: MotionFlags,
    /// Buffered moves waiting in the axis's queue.
    pub queued: u32,
    /// The velocity override in force (1.0 = 100 %).
    pub override_factor: f64,
    /// Everything the card published, in counts.
    pub raw: AxisStatus,
}

/// A handle to one axis of a card.
#[derive(Clone)]
pub struct Axis {
    card: Card,
    index: usize,
}

/// A motion in progress; wait for it with [`Motion::wait`].
#[derive(Clone)]
pub struct Motion {
    card: Card,
    axis: usize,
    seq: u32,
}

impl std::fmt::Debug for Motion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Motion")
            .field("axis", &self.axis)
            .field("seq", &self.seq)
            .finish()
    }
}

impl Motion {
    pub(crate) fn new(card: Card, axis: usize, seq: u32) -> Self {
        Self { card, axis, seq }
    }

    /// The seq of the command that started it.
    pub fn seq(&self) -> u32 {
        self.seq
    }

    /// Wait until the axis is in position (motion done) and return the actual position, or an
    /// error when it is aborted or the timeout passes.
    pub fn wait(&self, timeout: Duration) -> Result<f64> {
        self.card
            .wait_outcome(Target::Axis(self.axis), self.seq, timeout)
    }

    /// Wait for the first outcome of this motion that `pick` takes, or its abort.
    pub(crate) fn wait_outcome_of(
        &self,
        timeout: Duration,
        pick: impl Fn(Outcome) -> Option<f64>,
    ) -> Result<f64> {
        self.card
            .wait_for(Target::Axis(self.axis), self.seq, timeout, pick)
    }
}

impl Axis {
    pub(crate) fn card(&self) -> &Card {
        &self.card
    }

    /// Axis number.
    pub fn index(&self) -> usize {
        self.index
    }
}

/// Servo gains and in-position windows of an axis (counts, seconds, volts): the card's
/// `mc_axis_config` block, whose fields the register map's header lists. Its `Default` is what
/// the card loads at boot (FFPIV with the default tuning); [`Axis::configure`] selects FFPIV
/// whatever `servo_law` says (PD+: [`Axis::configure_pdplus`]). `scale` (layout 1.8) is the
/// axis's scale as the card keeps it, given by [`Axis::settings`]; [`Axis::configure`] ignores
/// it ([`Axis::set_scale`] sets it).
pub use firmware_proto::AxisConfig as AxisSettings;
