//! Layout 1.12: the sync bus and commands timed to a tick.
//!
//! **The sync bus.** Several cards run on one servo clock: the master's. Whatever carries the
//! clock (a sync cable on hardware; in the emulator a shared page and an eventfd per follower,
//! `card_emu::bus`) steps each follower once per master tick and hands it the master's tick
//! number and commits; the firmware keeps its role, its state and the commits it has seen,
//! and publishes them in `card_info`. A follower joins with the master's tick count
//! ([`Firmware::join_bus`]), so a tick number means one instant on every card of the bus. A
//! follower that loses the master ([`Firmware::lose_bus`]) halts every motion (reason
//! `SyncLost`), refuses what it holds timed, and goes on on its own clock.
//!
//! **Timed commands.** `MC_OP_AT_TICK` and the entry published with it form one timed command:
//! checked when taken (the tick ahead and not too far, a slot free, the entry a command that
//! decodes and may be timed), held, and executed as the first thing of its tick, answered
//! then. With a key, it runs only if the card has seen that key's commit for that tick
//! (`MC_OP_SYNC_COMMIT` on the master, carried to the followers with the ticks before it):
//! the commit reaches every card of the bus or none, so a set of cards runs a key's commands
//! together or not at all.

use super::Firmware;
use firmware_proto::cmd::{self, CardCmd, Cmd};
use firmware_proto::raw::{
    MC_BUSST_FREE, MC_BUSST_LOCKED, MC_BUSST_LOST, MC_BUS_ALONE, MC_BUS_FOLLOWER, MC_BUS_MASTER,
    MC_TIMED_MAX_AHEAD, MC_TIMED_SLOTS,
};
use firmware_proto::{
    layout, AxisState, Command, Event, EventKind, Mem, NackCode, Opcode, StopReason,
};

/// Timed commands a card holds at once.
pub const TIMED_SLOTS: usize = MC_TIMED_SLOTS as usize;
/// Commits remembered (the bus's and this card's): more than can be pending at once.
const COMMITS: usize = 2 * TIMED_SLOTS;

/// A key committed for a tick: its timed commands of that tick run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Commit {
    /// The key (nonzero).
    pub key: u32,
    /// The tick its commands run on.
    pub tick: u64,
}

/// The card's place on the sync bus.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum BusRole {
    /// On its own clock.
    #[default]
    Alone,
    /// Drives the bus's clock (and carries its commits).
    Master,
    /// Runs on the master's ticks.
    Follower,
}

#[derive(Clone, Copy)]
struct Held {
    tick: u64,
    key: u32,
    cmd: Command,
}

/// The sync bus's state on this card and the timed commands it holds.
pub(crate) struct Timing {
    role: BusRole,
    lost: bool,
    held: [Option<Held>; TIMED_SLOTS],
    /// The earliest tick a held command runs on (`u64::MAX`: none), so that a tick with none
    /// due costs one compare.
    next: u64,
    commits: [Commit; COMMITS],
    commits_seen: u32,
    /// A master's (or a card alone's) commits not yet handed to the bus.
    outgoing: heapless::Vec<Commit, COMMITS>,
    name: [u8; 32],
    serial: u64,
    master: [u8; 32],
    followers: u32,
    losses: u32,
    dirty: bool,
}

impl Timing {
    pub(crate) fn new() -> Self {
        Self {
            role: BusRole::Alone,
            lost: false,
            held: [None; TIMED_SLOTS],
            next: u64::MAX,
            commits: [Commit::default(); COMMITS],
            commits_seen: 0,
            outgoing: heapless::Vec::new(),
            name: [0; 32],
            serial: 0,
            master: [0; 32],
            followers: 0,
            losses: 0,
            dirty: true,
        }
    }

    fn held_count(&self) -> u32 {
        self.held.iter().flatten().count() as u32
    }

    fn refresh_next(&mut self) {
        self.next = self
            .held
            .iter()
            .flatten()
            .map(|h| h.tick)
            .min()
            .unwrap_or(u64::MAX);
        self.dirty = true;
    }

    fn committed(&self, key: u32, tick: u64) -> bool {
        self.commits.iter().any(|c| c.key == key && c.tick == tick)
    }

    fn remember(&mut self, c: Commit) {
        if c.key == 0 || self.committed(c.key, c.tick) {
            return;
        }
        self.commits[self.commits_seen as usize % COMMITS] = c;
        self.commits_seen = self.commits_seen.wrapping_add(1);
        self.dirty = true;
    }

    fn block(&self) -> firmware_proto::raw::mc_card_info {
        let as_chars = |b: &[u8; 32]| b.map(|x| x as core::ffi::c_char);
        firmware_proto::raw::mc_card_info {
            name: as_chars(&self.name),
            serial: self.serial,
            sync_role: match self.role {
                BusRole::Alone => MC_BUS_ALONE,
                BusRole::Master => MC_BUS_MASTER,
                BusRole::Follower => MC_BUS_FOLLOWER,
            },
            sync_state: match (self.role, self.lost) {
                (_, true) => MC_BUSST_LOST,
                (BusRole::Follower, false) => MC_BUSST_LOCKED,
                _ => MC_BUSST_FREE,
            },
            sync_master: as_chars(&self.master),
            sync_followers: self.followers,
            timed_held: self.held_count(),
            timed_next: if self.next == u64::MAX { 0 } else { self.next },
            commits: self.commits_seen,
            sync_losses: self.losses,
            _reserved: [0; 8],
        }
    }
}

/// `s` cut to 31 bytes, NUL-padded.
fn name_bytes(s: &str) -> [u8; 32] {
    let mut b = [0u8; 32];
    let n = s.len().min(31);
    b[..n].copy_from_slice(&s.as_bytes()[..n]);
    b
}

/// Opcodes that cannot be timed: the timing's own, the session's (a session is the host's
/// here and now), and the pieces of a two-entry move (layout 1.13: a timing holds one entry).
fn untimable(op: Opcode) -> bool {
    matches!(
        op,
        Opcode::AtTick
            | Opcode::SyncCommit
            | Opcode::TimedCancel
            | Opcode::HostAttach
            | Opcode::HostDetach
            | Opcode::GroupMoveCircularNormal
            | Opcode::GroupCircularPlane
            | Opcode::PathMore
    )
}

impl<M: Mem + Clone> Firmware<M> {
    /// The board's name and serial number, as `card_info` shows them (an EEPROM's on a card;
    /// the emulator's `--name`). The name is cut to 31 bytes. Published at once, as a board's
    /// EEPROM name is there from power-on: a lister that reads the card before its first tick
    /// sees it.
    pub fn set_card_name(&mut self, name: &str, serial: u64) {
        self.timing.name = name_bytes(name);
        self.timing.serial = serial;
        self.timing.dirty = true;
        self.publish_card_info();
    }

    /// The card's place on the sync bus.
    pub fn bus_role(&self) -> BusRole {
        self.timing.role
    }

    /// Has this follower lost its master?
    pub fn bus_lost(&self) -> bool {
        self.timing.lost
    }

    /// Drive the bus's clock, with `followers` on it now: the master while it has any, alone
    /// otherwise (its commits are its own then).
    pub fn lead_bus(&mut self, followers: u32) {
        if self.timing.role == BusRole::Follower || self.timing.followers == followers {
            return;
        }
        self.timing.role = if followers > 0 {
            BusRole::Master
        } else {
            BusRole::Alone
        };
        self.timing.followers = followers;
        self.timing.dirty = true;
        self.publish_card_info();
    }

    /// Follow the bus of master `master`, whose last tick was `tick`: this card's tick count
    /// becomes the master's, so that its next tick is the master's next. Only a card at rest
    /// with no host attached joins (at its start): `false` otherwise, and nothing changes.
    pub fn join_bus(&mut self, master: &str, tick: u64) -> bool {
        let moving = self.axes[..self.num_axes].iter().any(|a| {
            !matches!(
                a.state,
                AxisState::Disabled | AxisState::Standstill | AxisState::ErrorStop
            )
        });
        if self.safety.in_command() || moving || self.timing.role == BusRole::Master {
            return false;
        }
        self.tick = tick;
        self.timing.role = BusRole::Follower;
        self.timing.lost = false;
        self.timing.master = name_bytes(master);
        self.timing.dirty = true;
        let code = MC_BUSST_LOCKED as i32;
        self.post_axis_event(EventKind::SyncBus, 0, 0, code, tick as f64);
        self.mem.write64(layout::TICK, self.tick);
        self.publish_card_info();
        true
    }

    /// A commit the bus carried (a follower's, from the master): its key's commands of that
    /// tick may run.
    pub fn bus_commit(&mut self, c: Commit) {
        self.timing.remember(c);
    }

    /// The commits made here since the last call, for the bus to carry to the followers.
    pub fn take_commits(&mut self) -> heapless::Vec<Commit, COMMITS> {
        core::mem::take(&mut self.timing.outgoing)
    }

    /// The master is gone (no tick in time, or the bus closed): every moving axis and group
    /// halts on its stop ramp (reason `SyncLost`), every held timed command is refused
    /// (`MC_NACK_SYNC_LOST`), `MC_EV_SYNC_BUS` (`MC_BUSST_LOST`) is posted, and the card goes on
    /// on its own clock. Once per loss; a card not following does nothing.
    pub fn lose_bus(&mut self) {
        if self.timing.role != BusRole::Follower || self.timing.lost {
            return;
        }
        self.timing.lost = true;
        self.timing.losses = self.timing.losses.wrapping_add(1);
        self.timing.dirty = true;
        self.halt_motion(0, u32::MAX, StopReason::SyncLost, Opcode::AtTick);
        self.drop_held(0, NackCode::SyncLost);
        let (code, tick) = (MC_BUSST_LOST as i32, self.tick);
        self.post_axis_event(EventKind::SyncBus, 0, 0, code, tick as f64);
        self.post_outbox();
        self.publish_card_info();
        self.irq_pending = true;
    }

    /// `MC_OP_AT_TICK` and the entry after it: hold the pair for its tick, or refuse both.
    /// `c` is the `MC_OP_AT_TICK` entry; it is answered here, and so is its command when it is
    /// refused.
    pub(super) fn take_timed(&mut self, c: &Command) {
        // A corrupt ring reads as nothing here: the next serve finds it and stops the axes.
        let next = self.cmds.pop().unwrap_or_default();
        let outcome = self.arm(c, next.as_ref());
        let reply = |seq, r: Result<(), NackCode>| match r {
            Ok(()) => ack(seq, c.axis, 0.0),
            Err(code) => nack(seq, c.axis, code),
        };
        // The held count first, then the answer (as any ack follows the status it left).
        self.publish_card_info();
        let tick = self.tick;
        let mut e = reply(c.seq, outcome);
        e.tick = tick;
        self.post(e);
        if let (Some(n), Err(code)) = (next, outcome) {
            self.cmds_accepted = self.cmds_accepted.wrapping_add(1);
            let code = match code {
                NackCode::TickPassed
                | NackCode::TimedFull
                | NackCode::TickFar
                | NackCode::Expired
                | NackCode::NotFinite => NackCode::TimedRefused,
                other => other,
            };
            let mut e = nack(n.seq, n.axis, code);
            e.tick = tick;
            e.axis = n.axis;
            self.post(e);
        }
    }

    fn arm(&mut self, c: &Command, next: Option<&Command>) -> Result<(), NackCode> {
        if self.expired(c) {
            return Err(NackCode::Expired);
        }
        let at = match CardCmd::decode(Opcode::AtTick, c.flags, &c.args) {
            Ok(CardCmd::AtTick(a)) => a,
            Ok(_) => return Err(NackCode::UnknownOpcode),
            Err(e) => return Err(e.nack),
        };
        let Some(n) = next else {
            return Err(NackCode::TimedAlone);
        };
        let op = Opcode::from_raw(n.opcode).ok_or(NackCode::UnknownOpcode)?;
        if untimable(op) {
            return Err(NackCode::TimedAlone);
        }
        // [safety] the session gate, for the command it times (it meets it again on its tick)
        if !self.safety.in_command() && !super::safety::allowed_without_session(op) {
            return Err(NackCode::NoSession);
        }
        Cmd::decode(n.opcode, n.flags, &n.args).map_err(|e| e.nack)?;
        if at.tick <= self.tick {
            return Err(NackCode::TickPassed);
        }
        if at.tick - self.tick > MC_TIMED_MAX_AHEAD as u64 {
            return Err(NackCode::TickFar);
        }
        if self.timing.lost {
            return Err(NackCode::SyncLost);
        }
        let slot = self
            .timing
            .held
            .iter_mut()
            .find(|h| h.is_none())
            .ok_or(NackCode::TimedFull)?;
        *slot = Some(Held {
            tick: at.tick,
            key: at.key,
            cmd: *n,
        });
        self.cmds_accepted = self.cmds_accepted.wrapping_add(1);
        self.timing.refresh_next();
        Ok(())
    }

    /// `MC_OP_SYNC_COMMIT`: on a master or a card alone, the commit of `key` for `tick`.
    pub(super) fn sync_commit(&mut self, c: cmd::SyncCommit) -> Result<f64, NackCode> {
        if self.timing.role == BusRole::Follower {
            return Err(NackCode::NotMaster);
        }
        if c.tick <= self.tick {
            return Err(NackCode::CommitLate);
        }
        let commit = Commit {
            key: c.key,
            tick: c.tick,
        };
        if self.timing.outgoing.is_full() {
            if self.timing.role == BusRole::Master {
                // More commits between two ticks than the bus carries: refuse rather than
                // let the followers miss one.
                return Err(NackCode::TimedFull);
            }
            // A card alone whose commits nobody takes: the oldest goes.
            self.timing.outgoing.remove(0);
        }
        self.timing.remember(commit);
        let _ = self.timing.outgoing.push(commit);
        Ok(0.0)
    }

    /// `MC_OP_TIMED_CANCEL`: drop the held commands of `key` (0: all). The count dropped.
    pub(super) fn timed_cancel(&mut self, key: u32) -> f64 {
        self.drop_held(key, NackCode::Cancelled) as f64
    }

    /// Refuse (nack `code`) and drop the held commands of `key` (0: all); how many.
    pub(in crate::firmware) fn drop_held(&mut self, key: u32, code: NackCode) -> u32 {
        if self.timing.next == u64::MAX {
            return 0;
        }
        let mut n = 0;
        for i in 0..TIMED_SLOTS {
            let Some(h) = self.timing.held[i] else {
                continue;
            };
            if key == 0 || h.key == key {
                self.timing.held[i] = None;
                let mut e = nack(h.cmd.seq, h.cmd.axis, code);
                e.tick = self.tick;
                self.post(e);
                n += 1;
            }
        }
        self.timing.refresh_next();
        n
    }

    /// The first thing of a tick: run the timed commands due now, in the order they were
    /// taken (slot order is not that order once slots are reused: by seq, wrapping).
    #[inline]
    pub(super) fn run_timed(&mut self) {
        if self.timing.next > self.tick {
            return;
        }
        self.run_due();
    }

    #[inline(never)]
    fn run_due(&mut self) {
        loop {
            let due = self
                .timing
                .held
                .iter()
                .enumerate()
                .filter_map(|(i, h)| h.filter(|h| h.tick <= self.tick).map(|h| (i, h)))
                .min_by_key(|(_, h)| h.cmd.seq.wrapping_sub(self.timing.held_base()));
            let Some((i, h)) = due else {
                break;
            };
            self.timing.held[i] = None;
            if h.key != 0 && !self.timing.committed(h.key, h.tick) {
                let mut e = nack(h.cmd.seq, h.cmd.axis, NackCode::NotCommitted);
                e.tick = self.tick;
                self.post(e);
                continue;
            }
            let (seq, op, tick) = (h.cmd.seq, h.cmd.opcode, self.tick);
            self.post_axis_event(EventKind::Timed, seq, h.cmd.axis, op as i32, tick as f64);
            self.answer_taken(&h.cmd);
        }
        self.timing.refresh_next();
    }

    /// Publish `card_info` when it changed.
    #[inline]
    pub(super) fn publish_card_info(&mut self) {
        if !self.timing.dirty {
            return;
        }
        self.timing.dirty = false;
        layout::CARD_INFO.write(&self.mem, &self.timing.block());
    }
}

impl Timing {
    /// The seq the held commands' order is counted from: the smallest held seq, wrapping
    /// (seqs of held commands lie within a ring's worth of each other).
    fn held_base(&self) -> u32 {
        let mut seqs = self.held.iter().flatten().map(|h| h.cmd.seq);
        let Some(first) = seqs.next() else {
            return 0;
        };
        seqs.fold(
            first,
            |b, s| if (s.wrapping_sub(b) as i32) < 0 { s } else { b },
        )
    }
}

fn ack(seq: u32, axis: u16, value: f64) -> Event {
    Event {
        seq,
        kind: EventKind::Ack as u16,
        axis,
        code: 0,
        tick: 0,
        value,
    }
}

fn nack(seq: u32, axis: u16, code: NackCode) -> Event {
    Event {
        seq,
        kind: EventKind::Nack as u16,
        axis,
        code: code as i32,
        tick: 0,
        value: 0.0,
    }
}
