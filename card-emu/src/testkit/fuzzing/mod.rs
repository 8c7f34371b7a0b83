//! The garbage harness: one place for the fuzz targets (`fuzz/fuzz_targets/*.rs`) and the plain
//! test that replays their corpus and sweeps a million random commands (`tests/garbage.rs`).
//!
//! - [`Source`]: where garbage comes from, a fuzzer's bytes ([`Bytes`]) or the tests' seeded
//!   generator ([`RngSource`]). The decoders read it byte by byte; an exhausted input reads as zeros.
//! - [`garbage_unit`]: one unit of command garbage: fully random entry words; a valid opcode
//!   with random axis, flags and argument bits (NaN, ±inf, ±0, subnormal, huge, random); a
//!   plausible command with one or two arguments broken; or a NURBS transfer
//!   (begin/data.../end continuation entries) with mutations.
//! - [`Card`]: a booted firmware on a [`HeapWindow`] with a plant, set up through valid
//!   commands (a session attached, every axis enabled, groups configured), a host side (command
//!   producer, event consumer, a heartbeat every tick, a new attach whenever garbage detached
//!   its session, so that garbage keeps reaching motion past the session gate) and the
//!   invariant checks.
//! - [`run_commands`], [`run_dpram`]: the two fuzz targets' bodies; [`sweep`]: the test's sweep.
//!
//! The garbage itself (the sources, [`garbage_unit`], [`plausible`]) is in `garbage.rs`.
//!
//! The invariants (a violation panics, which is what the fuzzer and the test look for):
//! - every command the card takes gets exactly one ack or nack, in order, carrying its seq and
//!   axis; a nack's code is a known [`NackCode`];
//! - a nacked command changes nothing the card publishes: every axis's and group's status
//!   (commanded position, velocity, acceleration, target, state, counters, statistics) is
//!   bit-for-bit what it was before the command;
//! - a card at rest stays at rest over the ticks that follow while only nacked commands (or
//!   accepted ones that left the motion state unchanged) arrive: same states, same commanded
//!   positions, zero commanded velocity, no group move;
//! - every tick: DAC outputs finite and within ±10 V (0 V on the axes the card does not have),
//!   commanded and actual positions, velocities and accelerations finite; a tick never acks or
//!   nacks anything and every event it posts has a known kind.
//!
//! Out-of-bounds accesses need no check of their own: [`Mem`] ignores out-of-range offsets, so
//! an index bug in the firmware shows up as a panic of slice indexing, which fails the run.
#![allow(missing_docs)]

use crate::firmware::Firmware;
use crate::plant::{Motor, MotorParams};
use firmware_proto::layout;
use firmware_proto::mem::HeapWindow;
use firmware_proto::ring::RingError;
use firmware_proto::ring::{CmdProducer, EvtConsumer, CMD_RING, EVT_RING};
use firmware_proto::wire::{CMD_ARGS, STATUS_WORDS};
use firmware_proto::{
    AxisState, Event, EventKind, GroupState, Io, Mem, NackCode, Opcode, MAX_AXES, MAX_GROUPS,
};
use std::sync::Arc;

mod garbage;
pub use garbage::*;

// ---------------------------------------------------------------------------------------------
// The card and its host

/// Every status the card publishes, as words (bitwise comparison: NaN equals itself).
pub type FullStatus = (
    [[u64; STATUS_WORDS]; AXES],
    [[u64; STATUS_WORDS]; MAX_GROUPS],
);

/// What must not change while a card at rest receives commands that are refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Motion {
    /// Per axis: state, and for a powered axis the commanded position, velocity, acceleration
    /// (bits). An unpowered axis's commanded position follows its encoder.
    pub axes: [(u32, [u64; 3]); AXES],
    /// Per group: state, queued moves, active move.
    pub groups: [(u32, u32, u32); MAX_GROUPS],
}

/// How one command was answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    Ack,
    Nack(NackCode),
    /// Not attributable (the host wrote over the window outside its own fields).
    Unknown,
}

/// Counters of a run.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub commands: u64,
    pub acks: u64,
    pub nacks: u64,
    /// Nacks per code (index: the code's raw value, 0..128).
    pub nack_codes: Vec<u64>,
    pub ticks: u64,
    pub reboots: u64,
    /// Ticks checked against a card at rest.
    pub quiet_ticks: u64,
}

impl Stats {
    fn new() -> Self {
        Self {
            nack_codes: vec![0; 128],
            ..Default::default()
        }
    }
}

/// The session id of the harness's host.
pub const SESSION: u32 = 0x5E55_1011;

/// A booted firmware with its plant and a host.
pub struct Card {
    window: Arc<HeapWindow>,
    fw: Firmware<Arc<HeapWindow>>,
    cmds: CmdProducer<Arc<HeapWindow>>,
    events: EvtConsumer<Arc<HeapWindow>>,
    motors: [Motor; MAX_AXES],
    dac: [f64; MAX_AXES],
    /// The motion state of the card at rest, while nothing has moved it since.
    rest: Option<Motion>,
    last_rest: Option<Motion>,
    /// The host wrote garbage into the window: its ring indices may be broken, so the host
    /// re-attaches before each command and only checks replies it can attribute.
    garbage: bool,
    /// The host wrote outside its own fields: replies cannot be attributed any more.
    wild: bool,
    pub stats: Stats,
}

impl Default for Card {
    fn default() -> Self {
        Self::new()
    }
}

impl Card {
    /// Boot a card with [`AXES`] axes at 10 kHz, and set it up through valid commands: a
    /// session attached ([`SESSION`]), every axis enabled, the groups of [`GROUPS`] configured
    /// (the first two enabled), every event raising the interrupt. Axes 5–7 are free for
    /// single-axis moves.
    pub fn new() -> Self {
        let window = Arc::new(HeapWindow::new());
        let fw = Firmware::boot(window.clone(), AXES, 10_000);
        let mut card = Self {
            cmds: CmdProducer::attach(window.clone(), CMD_RING),
            events: EvtConsumer::attach(window.clone(), EVT_RING),
            window,
            fw,
            motors: [Motor::new(MotorParams::default_servo()); MAX_AXES],
            dac: [0.0; MAX_AXES],
            rest: None,
            last_rest: None,
            garbage: false,
            wild: false,
            stats: Stats::new(),
        };
        card.window.write32(layout::IRQ_MASK, u32::MAX);
        card.attach();
        assert!(card.fw.safety().in_command(), "setup: no session");
        let ok = |card: &mut Self, op: Opcode, axis: usize| {
            let r = card.send(&RawCmd::new(op as u16, axis as u16, 0, &[0.0; CMD_ARGS]));
            assert_eq!(r, Reply::Ack, "setup: {op:?} {axis}");
        };
        for a in 0..AXES {
            ok(&mut card, Opcode::PowerOn, a);
        }
        for (g, (axes, accdec, interp, enable)) in GROUPS.iter().enumerate() {
            card.set_group_config(g, axes, *accdec, *interp);
            ok(&mut card, Opcode::GroupConfigure, g);
            if *enable {
                ok(&mut card, Opcode::GroupEnable, g);
            }
        }
        card.tick(2);
        assert!(card.rest.is_some(), "setup: the card is not at rest");
        card.stats = Stats::new();
        card
    }

    /// Write a valid `group_config[g]` block (the host's own business: not garbage), tolerance
    /// 1 count.
    pub fn set_group_config(&mut self, g: usize, axes: &[u8], accdec: u32, interp: u32) {
        let mut block = firmware_proto::raw::mc_group_config {
            naxes: axes.len().min(8) as u32,
            accdec,
            interpolator: interp,
            tolerance: 1.0,
            ..Default::default()
        };
        for (d, a) in block.axes.iter_mut().zip(axes) {
            *d = *a;
        }
        layout::GROUP_CONFIG.at(g).write(&self.window, &block);
    }

    /// Send a command made of its fields.
    pub fn command(&mut self, op: Opcode, axis: usize, flags: u32, args: &[f64]) -> Reply {
        let mut a = [0.0; CMD_ARGS];
        for (d, s) in a.iter_mut().zip(args) {
            *d = *s;
        }
        self.send(&RawCmd::new(op as u16, axis as u16, flags, &a))
    }

    /// The firmware.
    pub fn firmware(&self) -> &Firmware<Arc<HeapWindow>> {
        &self.fw
    }

    /// The window.
    pub fn window(&self) -> &HeapWindow {
        &self.window
    }

    /// Every published status, from the firmware's own state.
    pub fn full_status(&self) -> FullStatus {
        let tick = self.fw.tick_count();
        let mut axes = [[0u64; STATUS_WORDS]; AXES];
        for (i, w) in axes.iter_mut().enumerate() {
            if let Some(a) = self.fw.axis(i) {
                *w = a.status(tick).to_words();
            }
        }
        let mut groups = [[0u64; STATUS_WORDS]; MAX_GROUPS];
        for (g, w) in groups.iter_mut().enumerate() {
            if let Some(gr) = self.fw.group(g) {
                *w = gr.status(tick).to_words();
            }
        }
        (axes, groups)
    }

    /// The motion state.
    pub fn motion(&self) -> Motion {
        let mut m = Motion {
            axes: [(0, [0; 3]); AXES],
            groups: [(0, 0, 0); MAX_GROUPS],
        };
        let tick = self.fw.tick_count();
        for (i, slot) in m.axes.iter_mut().enumerate() {
            if let Some(a) = self.fw.axis(i) {
                let s = a.status(tick);
                let powered = s.io().contains(Io::DRIVE_ENABLE) || a.state == AxisState::Standstill;
                let cmd = if powered {
                    [
                        s.cmd_pos.to_bits(),
                        s.cmd_vel.to_bits(),
                        s.cmd_acc.to_bits(),
                    ]
                } else {
                    [0; 3]
                };
                *slot = (s.state, cmd);
            }
        }
        for (g, slot) in m.groups.iter_mut().enumerate() {
            if let Some(gr) = self.fw.group(g) {
                let s = gr.status(tick);
                *slot = (s.state, s.queued, s.active_seq);
            }
        }
        m
    }

    /// At rest: every axis in Standstill (commanded velocity and acceleration zero, following
    /// error and measured velocity small) or unpowered; no group moving.
    pub fn at_rest(&self) -> bool {
        let tick = self.fw.tick_count();
        let axes_still = (0..AXES).all(|i| {
            let Some(a) = self.fw.axis(i) else {
                return true;
            };
            let s = a.status(tick);
            match a.state {
                AxisState::Standstill => {
                    s.cmd_vel == 0.0
                        && s.cmd_acc == 0.0
                        && s.ferr.abs() <= 2.0
                        && s.act_vel.abs() <= 50.0
                }
                AxisState::Disabled | AxisState::ErrorStop => !s.io().contains(Io::DRIVE_ENABLE),
                _ => false,
            }
        });
        let groups_still = (0..MAX_GROUPS).all(|g| {
            self.fw.group(g).is_none_or(|gr| {
                let s = gr.status(tick);
                matches!(
                    gr.state,
                    GroupState::Disabled | GroupState::Standby | GroupState::ErrorStop
                ) && s.queued == 0
                    && s.active_seq == 0
            })
        });
        axes_still && groups_still
    }

    /// At rest, and nothing accepted since.
    pub fn is_quiet(&self) -> bool {
        self.rest.is_some()
    }

    /// The motion state of the last time the card was found at rest.
    pub fn last_rest(&self) -> Option<Motion> {
        self.last_rest
    }

    /// Tick until the card is at rest again, at most `max` ticks. Returns whether it is.
    pub fn settle(&mut self, max: u32) -> bool {
        for _ in 0..max {
            if self.is_quiet() {
                break;
            }
            self.tick(1);
        }
        self.is_quiet()
    }

    /// Write a 32-bit word of the window as the host (`host_owned`: a field the header gives
    /// the host; anything else makes later replies unattributable).
    pub fn write32(&mut self, off: usize, val: u32, host_owned: bool) {
        self.wild |= !host_owned;
        self.garbage = true;
        self.rest = None;
        self.window.write32(off, val);
    }

    /// Write a 64-bit word of the window as the host.
    pub fn write64(&mut self, off: usize, val: u64, host_owned: bool) {
        self.wild |= !host_owned;
        self.garbage = true;
        self.rest = None;
        self.window.write64(off, val);
    }

    /// The host's ring indices after garbage writes: continue the command ring from the card's
    /// tail, like a host that re-attaches (the host owns `cmd_head`).
    fn resync_host(&mut self) {
        let tail = self.window.read32(layout::CMD_TAIL);
        if self.window.read32(layout::CMD_HEAD) != self.cmds.head()
            || self.cmds.head() != tail
            || self.cmds.free().is_err()
        {
            self.window.write32(layout::CMD_HEAD, tail);
            self.cmds = CmdProducer::attach(self.window.clone(), CMD_RING);
        }
    }

    /// Take every waiting event. `None` if the host found the event ring corrupt (and
    /// resynchronised it).
    fn drain(&mut self, out: &mut Vec<Event>) -> Option<()> {
        out.clear();
        loop {
            match self.events.pop::<Event>() {
                Ok(Some(e)) => out.push(e),
                Ok(None) => break,
                Err(RingError::Corrupt { .. }) | Err(RingError::Full) => {
                    self.events.resync();
                    return None;
                }
            }
        }
        if self.wild || self.window.read32(layout::EVT_TAIL) != self.window.read32(layout::EVT_HEAD)
        {
            // The host owns evt_tail: put it back where the host is.
            self.events.resync();
        }
        Some(())
    }

    /// Attach the host's session ([`SESSION`]); its reply is checked as any command's.
    fn attach(&mut self) -> Reply {
        let op = Opcode::HostAttach as u16;
        self.send_one(&RawCmd::new(op, 0, SESSION, &[0.0; CMD_ARGS]))
    }

    /// Push one command (seq = its ring index + 1), let the card serve it, and check its reply.
    /// A host whose session garbage ended (a detach with its id) attaches again first, so that
    /// the command meets a card in command, as a host's would.
    pub fn send(&mut self, cmd: &RawCmd) -> Reply {
        if !self.fw.safety().in_command() {
            self.attach();
        }
        self.send_one(cmd)
    }

    fn send_one(&mut self, cmd: &RawCmd) -> Reply {
        let trusted = !self.garbage;
        if !trusted {
            self.resync_host();
        }
        let seq = self.cmds.head().wrapping_add(1);
        let cmd = cmd.with_seq(seq);
        let c = cmd.command();
        let before = self.full_status();
        if let Err(e) = self.cmds.push(&cmd) {
            assert!(!trusted, "host push failed on a healthy ring: {e}");
            return Reply::Unknown;
        }
        let served = self.fw.serve_commands();
        let mut events = Vec::new();
        let read = self.drain(&mut events);
        self.stats.commands += 1;
        let replies: Vec<&Event> = events
            .iter()
            .filter(|e| matches!(e.kind(), Some(EventKind::Ack | EventKind::Nack)))
            .collect();
        if trusted {
            assert_eq!(served, 1, "the card did not take {c:?}");
            assert!(read.is_some(), "event ring corrupt after {c:?}");
            check_event_kinds(&events);
            assert_eq!(
                replies.len(),
                1,
                "{c:?} got {} replies: {events:?}",
                replies.len()
            );
        }
        let attributable = !self.wild
            && read.is_some()
            && served == 1
            && replies.len() == 1
            && replies[0].seq == seq
            && !events
                .iter()
                .any(|e| e.kind() == Some(EventKind::ProtocolError));
        if !attributable {
            return Reply::Unknown;
        }
        let r = replies[0];
        assert_eq!(r.seq, seq, "reply to {c:?} carries another seq: {r:?}");
        assert_eq!(r.axis, c.axis, "reply to {c:?} names another axis: {r:?}");
        assert_eq!(
            r.tick,
            self.fw.tick_count(),
            "reply to {c:?} at another tick"
        );
        if r.kind() == Some(EventKind::Ack) {
            assert_eq!(r.code, 0, "ack with a code: {r:?}");
            self.stats.acks += 1;
            // An accepted command may start motion: the card is at rest again only once the
            // ticks find it so.
            self.rest = None;
            return Reply::Ack;
        }
        let code = NackCode::from_raw(r.code)
            .unwrap_or_else(|| panic!("nack of {c:?} with an unknown code {}", r.code));
        self.stats.nacks += 1;
        if let Some(n) = self.stats.nack_codes.get_mut(r.code as usize) {
            *n += 1;
        }
        let after = self.full_status();
        if before != after {
            let diff = describe_diff(&before, &after);
            panic!("{c:?} was nacked ({code:?}) but changed the card: {diff}");
        }
        Reply::Nack(code)
    }

    /// Serve what is waiting without checking replies (after garbage ring indices).
    pub fn serve(&mut self) {
        self.fw.serve_commands();
        let mut events = Vec::new();
        let _ = self.drain(&mut events);
    }

    /// `n` servo periods: serve, encoders in, firmware tick, DAC out, plant.
    pub fn tick(&mut self, n: u32) {
        let mut events = Vec::new();
        for _ in 0..n {
            // Like the emulator's step: serve the ring first (a strict host has nothing waiting).
            let served = self.fw.serve_commands();
            assert!(
                self.garbage || served == 0,
                "a tick found {served} commands waiting"
            );
            let mut enc = [0i64; MAX_AXES];
            for (e, m) in enc.iter_mut().zip(&self.motors) {
                *e = m.encoder();
            }
            // The host's heartbeat, once per period (a garbage write to it is one more beat).
            let hb = self.window.read32(layout::HEARTBEAT);
            self.window.write32(layout::HEARTBEAT, hb.wrapping_add(1));
            self.fw.tick(&enc, &mut self.dac);
            // Nothing the card does may be refused by the window (the harness skips the
            // host's own wild accesses) or dropped before the event ring.
            for (what, off) in [
                ("refused window accesses", layout::BAD_ACCESSES),
                ("events lost in the outbox", layout::OUTBOX_LOST),
                ("safety events lost", layout::SAFETY_EVENTS_LOST),
            ] {
                let n = self.window.read32(off);
                assert_eq!(n, 0, "{what}: {n} (tick {})", self.fw.tick_count());
            }
            let ts = self.fw.ts();
            for (i, (m, v)) in self.motors.iter_mut().zip(self.dac).enumerate() {
                assert!(
                    v.is_finite() && v.abs() <= 10.0,
                    "DAC {i} at {v} V (tick {})",
                    self.fw.tick_count()
                );
                if i >= self.fw.num_axes() {
                    assert_eq!(v, 0.0, "DAC {i} of a missing axis at {v} V");
                }
                m.step(v, ts);
                assert!(
                    m.theta.is_finite() && m.omega.is_finite(),
                    "motor {i}: {m:?}"
                );
            }
            self.check_finite();
            self.stats.ticks += 1;
            let read = self.drain(&mut events);
            if !self.garbage && read.is_some() {
                check_event_kinds(&events);
                if let Some(e) = events
                    .iter()
                    .find(|e| matches!(e.kind(), Some(EventKind::Ack | EventKind::Nack)))
                {
                    panic!("a tick answered a command: {e:?}");
                }
            }
            match self.rest {
                Some(rest) => {
                    let now = self.motion();
                    assert_eq!(
                        rest,
                        now,
                        "a card at rest started moving without an accepted command (tick {})",
                        self.fw.tick_count()
                    );
                    self.stats.quiet_ticks += 1;
                }
                None if !self.garbage && self.at_rest() => {
                    self.rest = Some(self.motion());
                    self.last_rest = self.rest;
                }
                None => {}
            }
        }
    }

    fn check_finite(&self) {
        let tick = self.fw.tick_count();
        for i in 0..self.fw.num_axes() {
            if let Some(a) = self.fw.axis(i) {
                let s = a.status(tick);
                for (what, v) in [
                    ("cmd_pos", s.cmd_pos),
                    ("cmd_vel", s.cmd_vel),
                    ("cmd_acc", s.cmd_acc),
                    ("act_pos", s.act_pos),
                    ("act_vel", s.act_vel),
                    ("target", s.target),
                ] {
                    assert!(v.is_finite(), "axis {i} {what} = {v} (tick {tick}): {s:?}");
                }
            }
        }
    }
}

fn check_event_kinds(events: &[Event]) {
    for e in events {
        assert!(e.kind().is_some(), "event of unknown kind: {e:?}");
    }
}

fn describe_diff(a: &FullStatus, b: &FullStatus) -> String {
    let mut out = String::new();
    for (i, (x, y)) in a.0.iter().zip(&b.0).enumerate() {
        if x != y {
            let (x, y) = (
                firmware_proto::AxisStatus::from_words(x),
                firmware_proto::AxisStatus::from_words(y),
            );
            out += &format!("\naxis {i}: {x:?}\n     -> {y:?}");
        }
    }
    for (g, (x, y)) in a.1.iter().zip(&b.1).enumerate() {
        if x != y {
            let (x, y) = (
                firmware_proto::GroupStatus::from_words(x),
                firmware_proto::GroupStatus::from_words(y),
            );
            out += &format!("\ngroup {g}: {x:?}\n      -> {y:?}");
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// The fuzz targets' bodies

/// Commands and ticks per fuzz input, so one input cannot run for long.
pub const MAX_OPS: usize = 2000;
/// Servo ticks per fuzz input.
pub const MAX_TICKS: u32 = 5000;

fn ticks<S: Source>(s: &mut S) -> u32 {
    match s.u8() {
        0..=191 => 1,
        192..=247 => 2 + (s.u8() % 32) as u32,
        _ => 100 + 4 * s.u8() as u32,
    }
}

/// Fuzz target `commands`: the input is a script of command units (any entry words) and servo
/// ticks for a card set up by [`Card::new`]; every invariant is checked after each step.
pub fn run_commands(data: &[u8]) {
    let mut s = Bytes::new(data);
    let mut card = Card::new();
    let mut cmds = Vec::new();
    let (mut ops, mut left) = (0, MAX_TICKS);
    while !s.is_empty() && ops < MAX_OPS {
        ops += 1;
        if s.u8() < 40 {
            let n = ticks(&mut s).min(left);
            left -= n;
            card.tick(n);
        } else {
            cmds.clear();
            garbage_unit(&mut s, &mut cmds);
            for c in &cmds {
                card.send(c);
            }
        }
    }
    card.tick(1);
}

/// Host-owned fields of the window (mc_dpram.h: "host writes"), as byte ranges.
pub fn host_owned() -> [(usize, usize); 11] {
    let block = |start: usize, bytes: usize, n: usize| (start, start + bytes * n);
    let array = |r: core::ops::Range<usize>| (r.start, r.end);
    [
        (layout::HEARTBEAT, layout::HEARTBEAT + 64),
        (layout::CMD_HEAD, layout::CMD_HEAD + 64),
        (layout::EVT_TAIL, layout::EVT_TAIL + 64),
        block(layout::CMD_RING, layout::CMD_BYTES, CMD_RING.len as usize),
        (
            layout::CARD_CONFIG.offset(),
            layout::AXIS_CONFIG.at(0).offset(),
        ),
        array(layout::AXIS_CONFIG.range()),
        array(layout::AXIS_FILTER.range()),
        array(layout::GROUP_CONFIG.range()),
        array(layout::AXIS_PDPLUS.range()),
        (
            layout::SAFETY_CONFIG.offset(),
            layout::AXIS_SAFETY.at(0).offset(),
        ),
        array(layout::AXIS_SAFETY.range()),
    ]
}

fn is_host_owned(off: usize, width: usize) -> bool {
    host_owned()
        .iter()
        .any(|&(a, b)| off >= a && off + width <= b)
}

/// A garbage write: mostly a field of a host-owned block (32- or 64-bit, a plausible float or
/// any bits), sometimes anywhere in the window, past its end or misaligned.
fn garbage_write<S: Source>(s: &mut S, card: &mut Card) {
    let regions = host_owned();
    let k = s.u8();
    let (off, wide) = match k {
        0..=215 => {
            let (a, b) = regions[k as usize % regions.len()];
            let wide = s.u8() & 1 == 1;
            let step = if wide { 8 } else { 4 };
            (a + (s.u16() as usize % ((b - a) / step)) * step, wide)
        }
        216..=247 => {
            let wide = s.u8() & 1 == 1;
            let step = if wide { 8 } else { 4 };
            let off = (s.u16() as usize % (firmware_proto::DPRAM_SIZE / step)) * step;
            (off, wide)
        }
        _ => (s.u32() as usize, s.u8() & 1 == 1),
    };
    let width = if wide { 8 } else { 4 };
    // A write past the window or misaligned would be refused by the window (a debug build
    // panics on it; a release build counts it and changes nothing): it is skipped, its value
    // still read so that the rest of the script parses the same.
    let refused = off % width != 0 || off.saturating_add(width) > firmware_proto::DPRAM_SIZE;
    let host = is_host_owned(off, width);
    if wide {
        let v = if s.u8() < 160 {
            garbage_f64(s).to_bits()
        } else {
            s.u64()
        };
        if !refused {
            card.write64(off, v, host);
        }
    } else {
        let v = match s.u8() % 4 {
            0 => s.u32(),
            1 => s.u8() as u32,
            2 => u32::MAX - s.u8() as u32,
            _ => {
                let old = if refused {
                    0
                } else {
                    card.window().read32(off)
                };
                old.wrapping_add(s.u8() as u32)
            }
        };
        if !refused {
            card.write32(off, v, host);
        }
    }
}

/// Fuzz target `dpram`: the input is a script of garbage writes over the window (mostly the
/// host's fields: configuration blocks, ring indices and entries, heartbeat, doorbell,
/// interrupt mask; sometimes anywhere), commands (an `Apply…` of the block just written, or
/// any command unit), serves and ticks.
pub fn run_dpram(data: &[u8]) {
    let mut s = Bytes::new(data);
    let mut card = Card::new();
    let mut cmds = Vec::new();
    let (mut ops, mut left) = (0, MAX_TICKS);
    while !s.is_empty() && ops < MAX_OPS {
        ops += 1;
        match s.u8() {
            0..=119 => garbage_write(&mut s, &mut card),
            120..=159 => {
                let op = [
                    Opcode::ApplyAxisConfig,
                    Opcode::ApplyCardConfig,
                    Opcode::ApplyAxisFilter,
                    Opcode::GroupConfigure,
                    Opcode::ApplySafetyConfig,
                    Opcode::ApplyAxisSafety,
                    Opcode::PowerOff,
                    Opcode::GroupDisable,
                ][(s.u8() % 8) as usize];
                let axis = target_index(&mut s, is_group_op(op));
                card.send(&RawCmd::new(op as u16, axis, 0, &[0.0; CMD_ARGS]));
            }
            160..=199 => {
                cmds.clear();
                garbage_unit(&mut s, &mut cmds);
                for c in &cmds {
                    card.send(c);
                }
            }
            200..=209 => card.serve(),
            _ => {
                let n = ticks(&mut s).min(left);
                left -= n;
                card.tick(n);
            }
        }
    }
    card.tick(1);
}

// ---------------------------------------------------------------------------------------------
// The sweep

/// Ticks an accepted command that changed no motion state gets to leave the card at rest.
pub const SETTLE_TICKS: u32 = 4;

/// The result of [`sweep`].
#[derive(Debug, Clone)]
pub struct Sweep {
    pub stats: Stats,
}

/// `commands` garbage commands from `seed` on cards at rest (every axis enabled, groups
/// enabled): each checked on its own (one reply, nack changes nothing); a servo tick after
/// every `tick_every` commands checks that a card at rest stays at rest. An accepted command
/// that changed no motion state gets [`SETTLE_TICKS`] ticks to be found at rest again; when
/// one moved something (or the card did not come to rest), the card is replaced by a fresh one
/// (booted and set up through valid commands), so that every command meets a card at rest.
pub fn sweep(seed: u64, commands: u64, tick_every: u64) -> Sweep {
    let mut rng = RngSource::new(seed);
    let mut card = Card::new();
    let mut total = Stats::new();
    let mut cmds = Vec::new();
    let mut since_tick = 0;
    let mut sent = 0;
    let add = |total: &mut Stats, s: &Stats| {
        total.commands += s.commands;
        total.acks += s.acks;
        total.nacks += s.nacks;
        total.ticks += s.ticks;
        total.quiet_ticks += s.quiet_ticks;
        for (t, n) in total.nack_codes.iter_mut().zip(&s.nack_codes) {
            *t += n;
        }
    };
    while sent < commands {
        cmds.clear();
        garbage_unit(&mut rng, &mut cmds);
        for c in &cmds {
            assert!(card.is_quiet());
            let before = card.motion();
            card.send(c);
            sent += 1;
            since_tick += 1;
            if card.is_quiet() {
                if since_tick >= tick_every {
                    card.tick(1);
                    since_tick = 0;
                }
            } else if card.motion() != before || !card.settle(SETTLE_TICKS) {
                // Accepted, and something moves (or may): start again from a card at rest.
                add(&mut total, &card.stats);
                card = Card::new();
                total.reboots += 1;
                since_tick = 0;
            }
        }
    }
    add(&mut total, &card.stats);
    Sweep { stats: total }
}
