//! Layout 1.12: several cards on one servo clock (the sync bus), and commands timed to a tick.
//!
//! Cards on a sync bus share the master's servo tick and its numbering: tick N is one instant
//! on all of them (`card-emu --sync-from MASTER`, [`CardSet::sim`] in this process, a sync
//! cable between boards). A command may be timed to a tick ([`Card::timed`]): the card holds
//! it and runs it as the first thing of that tick, or refuses it at once (a tick already run:
//! `TickPassed`). [`CardSet::sync`] times every command a closure sends, on every card of the
//! set, to one tick a margin ahead, under one key, then commits the key on the master: the
//! commit travels to the followers with the ticks before that one, so either every card runs
//! the key's commands on that tick or none does (a timing refused by one card, or a commit
//! that comes too late, and nothing moves anywhere). A synchronised start, halt, hold and
//! override are built on it.
//!
//! A follower whose master stops (killed, hung, its bus ended) halts every motion on its stop
//! ramps (stop reason [`crate::StopReason::SyncLost`]), refuses its held commands
//! (`SyncLost`), shows `BusState::Lost` and posts `SyncBus`; it then runs on its own clock.

pub use crate::card::Timing;
use crate::card::{pop_timing, push_timing, Card, Saved, Sent};
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{CardCmd, SyncCommit, TimedCancel};
use firmware_proto::{layout, raw, AxisState};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// The commands this thread sends are timed to one tick from [`TimingScope::begin`] to
/// [`TimingScope::end`] ([`Card::timed`] in two calls, for the C ABI's `mc_timed_begin` /
/// `mc_timed_end`). Not `Send`: the timing is this thread's.
pub struct TimingScope {
    at: Timing,
    saved: Option<Saved>,
    _thread: std::marker::PhantomData<*const ()>,
}

impl TimingScope {
    /// Time what this thread sends from now to `at`.
    pub fn begin(at: Timing) -> Self {
        Self {
            at,
            saved: Some(push_timing(at)),
            _thread: std::marker::PhantomData,
        }
    }

    /// The timing.
    pub fn timing(&self) -> Timing {
        self.at
    }

    /// Stop timing: the commands held since [`TimingScope::begin`].
    pub fn end(mut self) -> TimedCommands {
        TimedCommands {
            tick: self.at.tick,
            commands: self.saved.take().map(pop_timing).unwrap_or_default(),
        }
    }
}

impl Drop for TimingScope {
    fn drop(&mut self) {
        if let Some(saved) = self.saved.take() {
            pop_timing(saved);
        }
    }
}

/// A card's place on the sync bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BusRole {
    /// On its own clock.
    Alone,
    /// Drives the bus (it has followers).
    Master,
    /// Runs on a master's ticks.
    Follower,
}

/// A follower's link to its master.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BusState {
    /// Alone or master: its own clock.
    Free,
    /// On the master's ticks.
    Locked,
    /// It lost the master: halted, on its own clock.
    Lost,
}

/// What a card says of itself and of its sync bus (`card_info`, layout 1.12).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BusStatus {
    /// The card's name (`card-emu --name`; `simN` in a [`CardSet::sim`]).
    pub name: String,
    /// Its serial number (0: none).
    pub serial: u64,
    /// Its role.
    pub role: BusRole,
    /// Its link.
    pub state: BusState,
    /// A follower's master ("" otherwise).
    pub master: String,
    /// A master's followers now.
    pub followers: u32,
    /// Timed commands held.
    pub timed_held: u32,
    /// The earliest held one's tick (`None`: none held).
    pub timed_next: Option<u64>,
    /// Times it lost its master since boot.
    pub losses: u32,
}

fn text(b: &[core::ffi::c_char; 32]) -> String {
    let bytes: Vec<u8> = b.iter().map(|&c| c as u8).take_while(|&c| c != 0).collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

impl Card {
    /// The card's name, serial and place on the sync bus.
    pub fn bus_status(&self) -> Result<BusStatus> {
        self.tick()?; // a card that stopped or went away says so
                      // Written whole by the card when it changes: read until two reads agree.
        let mut b: raw::mc_card_info = layout::CARD_INFO.read(self.window());
        loop {
            let again = layout::CARD_INFO.read(self.window());
            if again == b {
                break;
            }
            b = again;
        }
        Ok(BusStatus {
            name: text(&b.name),
            serial: b.serial,
            role: match b.sync_role {
                raw::MC_BUS_MASTER => BusRole::Master,
                raw::MC_BUS_FOLLOWER => BusRole::Follower,
                _ => BusRole::Alone,
            },
            state: match b.sync_state {
                raw::MC_BUSST_LOCKED => BusState::Locked,
                raw::MC_BUSST_LOST => BusState::Lost,
                _ => BusState::Free,
            },
            master: text(&b.sync_master),
            followers: b.sync_followers,
            timed_held: b.timed_held,
            timed_next: (b.timed_next != 0).then_some(b.timed_next),
            losses: b.sync_losses,
        })
    }

    /// Send the commands `f` sends on this thread (to this card or any other) timed to `at`:
    /// each is checked and held by its card when sent (a refusal is the call's error inside
    /// `f`: `TickPassed`, `TickFar`, `TimedFull`, or the command's own fault when it does not
    /// decode), and runs as the first thing of tick `at.tick`, with key `at.key` only once the
    /// card has seen that key's commit ([`Card::sync_commit`]). A motion call returns its
    /// motion at once; the motion starts on the tick. What `f` returns, and the commands held,
    /// whose answers [`TimedCommands::wait`] waits for.
    pub fn timed<T>(
        &self,
        at: Timing,
        f: impl FnOnce() -> Result<T>,
    ) -> Result<(T, TimedCommands)> {
        let scope = TimingScope::begin(at);
        let r = f();
        let held = scope.end();
        r.map(|v| (v, held))
    }

    /// Commit `key` for `tick`: its timed commands run on that tick, on this card and on every
    /// follower of its bus. Only on a master or a card alone (`NotMaster`), and before the
    /// tick (`CommitLate`: then none of them runs, anywhere).
    pub fn sync_commit(&self, key: u32, tick: u64) -> Result<()> {
        let c = CardCmd::SyncCommit(SyncCommit { key, tick }).command(0);
        // Never timed itself (inside a timing too).
        self.inner()
            .execute_value(c, "sync_commit", Target::Card)
            .map(|_| ())
    }

    /// Drop the held timed commands of `key` (0: all); how many there were. Each is refused
    /// with `TimedCancelled`. Never timed itself.
    pub fn cancel_timed(&self, key: u32) -> Result<u32> {
        let c = CardCmd::TimedCancel(TimedCancel { key }).command(0);
        self.inner()
            .execute_value(c, "cancel_timed", Target::Card)
            .map(|(_, n)| n as u32)
    }
}

/// Timed commands held by their cards, answered on their tick.
pub struct TimedCommands {
    tick: u64,
    commands: Vec<Sent>,
}

impl std::fmt::Debug for TimedCommands {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let seqs: Vec<u32> = self.commands.iter().map(|c| c.1).collect();
        f.debug_struct("TimedCommands")
            .field("tick", &self.tick)
            .field("seqs", &seqs)
            .finish()
    }
}

impl TimedCommands {
    /// The tick they run on.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// How many.
    pub fn len(&self) -> usize {
        self.commands.len()
    }

    /// None?
    pub fn is_empty(&self) -> bool {
        self.commands.is_empty()
    }

    /// Wait for every command's answer (they come on the tick): the first refusal, after
    /// all have answered, or `Timeout` when `timeout` passes first.
    pub fn wait(&self, timeout: Duration) -> Result<()> {
        let until = Instant::now() + timeout;
        let mut first = None;
        for (card, seq, what, target) in &self.commands {
            match card.inner().wait_timed_answer(*seq, until)? {
                Ok(_) => {}
                Err(code) => {
                    first.get_or_insert(Error::Nack {
                        command: what,
                        target: *target,
                        code,
                        reason: crate::error::nack_reason(code),
                    });
                }
            }
        }
        first.map_or(Ok(()), Err)
    }
}

/// Cards on one sync bus, the first its master, driven as one: commands on several cards
/// timed to one tick ([`CardSet::sync`]), a synchronised start, halt, hold and override.
/// A clone drives the same cards (its keys are this process's, as every set's).
#[derive(Clone)]
pub struct CardSet {
    cards: Vec<Card>,
    margin: Duration,
}

/// The next key of a synchronised command (odd, never 0): one counter for every set of this
/// process, so that two sets on one bus never time under one key; seeded by the process id so
/// that another host's keys differ.
fn next_key() -> u32 {
    static KEY: std::sync::OnceLock<AtomicU32> = std::sync::OnceLock::new();
    KEY.get_or_init(|| AtomicU32::new(std::process::id().wrapping_mul(2_654_435_761) | 1))
        .fetch_add(2, Ordering::Relaxed)
        .max(1)
}

impl std::fmt::Debug for CardSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CardSet")
            .field("cards", &self.cards.len())
            .field("margin", &self.margin)
            .finish()
    }
}

impl CardSet {
    /// The cards of one bus, its master first: `BadConfig` unless the first is no follower and
    /// every other one follows it (locked, its master's name the first card's).
    pub fn new(cards: Vec<Card>) -> Result<Self> {
        let Some(master) = cards.first() else {
            return Err(Error::BadConfig("a card set needs a card".into()));
        };
        let m = master.bus_status()?;
        if m.role == BusRole::Follower {
            return Err(Error::BadConfig(format!(
                "'{}' follows '{}': put the bus's master first",
                m.name, m.master
            )));
        }
        for c in &cards[1..] {
            let s = c.bus_status()?;
            if s.role != BusRole::Follower || s.state != BusState::Locked || s.master != m.name {
                return Err(Error::BadConfig(format!(
                    "'{}' is not locked to the sync bus of '{}' ({:?}, {:?}, master '{}'): \
                     start it with `card-emu --sync-from {}`",
                    s.name, m.name, s.role, s.state, s.master, m.name
                )));
            }
        }
        Ok(Self {
            margin: Duration::from_millis(20),
            cards,
        })
    }

    /// Open `uris` as one set (the master first).
    pub fn open(uris: &[&str]) -> Result<Self> {
        let cards = uris
            .iter()
            .map(|u| Card::open(u))
            .collect::<Result<Vec<_>>>()?;
        Self::new(cards)
    }

    /// `n` emulated cards in this process on one sync bus (the first the master, named
    /// `sim0`…): with a stepped clock, stepping or waiting on any of them steps all of them,
    /// master first, so that their tick counters are always equal.
    #[cfg(feature = "emulator")]
    pub fn sim(n: usize, opts: crate::SimOptions) -> Result<Self> {
        if !(1..=16).contains(&n) {
            return Err(Error::BadConfig(format!(
                "{n} cards: a simulated set has 1 to 16"
            )));
        }
        let devices = crate::device::open_sim_bus(&opts, n)?;
        let mut cards = Vec::with_capacity(n);
        for d in devices {
            cards.push(Card::attach("sim", d, None)?);
        }
        if opts.clock == crate::Clock::Stepped {
            let members = cards
                .iter()
                .map(|c| {
                    let emu = c.inner().stepped().expect("a stepped card").clone();
                    (emu, std::sync::Arc::downgrade(c.inner_arc()))
                })
                .collect();
            let clock = std::sync::Arc::new(crate::card::SimClock { members });
            for c in &cards {
                *crate::lock::lock(&c.inner().sim_clock) = Some(clock.clone());
            }
        }
        Self::new(cards)
    }

    /// The cards, the master first.
    pub fn cards(&self) -> &[Card] {
        &self.cards
    }

    /// How far ahead [`CardSet::sync`] times its commands (default 20 ms): long enough for
    /// every card to take its commands and the master its commit.
    pub fn set_margin(&mut self, margin: Duration) {
        self.margin = margin;
    }

    /// The master's tick.
    pub fn tick(&self) -> Result<u64> {
        self.cards[0].tick()
    }

    /// Run the commands `f` sends (to any cards of the set) on one tick, on every card or on
    /// none: each is timed to the tick a margin ahead under a fresh key and held by its card;
    /// if one is refused, the key is cancelled everywhere and that is the error; else the key
    /// is committed on the master (which carries it to the followers with the ticks), and the
    /// call returns once every command has run, with the tick. Refused commits
    /// (`CommitLate`: the margin was too short for this machine) run nothing anywhere.
    pub fn sync<T>(&self, f: impl FnOnce() -> Result<T>) -> Result<(u64, T)> {
        let scope = self.begin()?;
        let value = f()?; // the scope's drop cancels the key
        Ok((scope.commit()?, value))
    }

    /// [`CardSet::sync`] in two calls (the C ABI's `mc_sync_begin` / `mc_sync_start`): from
    /// now until the scope's [`SyncScope::commit`] the commands this thread sends are timed to
    /// one tick under one key; dropping the scope uncommitted cancels them.
    pub fn begin(&self) -> Result<SyncScope> {
        let master = &self.cards[0];
        let rate = master.info().servo_rate_hz as f64;
        let ahead = (self.margin.as_secs_f64() * rate).ceil().max(2.0) as u64;
        let key = next_key();
        let at = Timing {
            tick: master.tick()? + ahead,
            key,
        };
        Ok(SyncScope {
            cards: self.cards.clone(),
            at,
            saved: Some(push_timing(at)),
            _thread: std::marker::PhantomData,
        })
    }

    /// Halt every moving axis of every card on one tick (MC_Halt with `deceleration` and
    /// `jerk`, in each axis's units): the tick.
    pub fn halt(&self, deceleration: f64, jerk: f64) -> Result<u64> {
        let axes = self.moving_axes()?;
        self.sync(|| {
            for a in &axes {
                a.halt(deceleration, jerk)?;
            }
            Ok(())
        })
        .map(|(t, ())| t)
    }

    /// Hold every moving axis of every card on one tick (override 0: each comes to rest within
    /// its limits and stays in its motion); [`CardSet::set_override`] with a factor above 0
    /// resumes them together.
    pub fn hold(&self) -> Result<u64> {
        self.set_override(0.0)
    }

    /// Set the override of every moving axis of every card on one tick.
    pub fn set_override(&self, factor: f64) -> Result<u64> {
        let axes = self.moving_axes()?;
        self.sync(|| {
            for a in &axes {
                a.set_override(factor)?;
            }
            Ok(())
        })
        .map(|(t, ())| t)
    }

    fn moving_axes(&self) -> Result<Vec<crate::Axis>> {
        let mut v = Vec::new();
        for c in &self.cards {
            for i in 0..c.info().axes {
                let a = c.axis(i)?;
                let st = a.status()?.state;
                if matches!(
                    st,
                    AxisState::DiscreteMotion
                        | AxisState::ContinuousMotion
                        | AxisState::SynchronizedMotion
                        | AxisState::Homing
                ) {
                    v.push(a);
                }
            }
        }
        Ok(v)
    }
}

/// Commands being timed to one tick on the cards of a set ([`CardSet::begin`]).
pub struct SyncScope {
    cards: Vec<Card>,
    at: Timing,
    saved: Option<Saved>,
    /// Not `Send`: the timing is this thread's.
    _thread: std::marker::PhantomData<*const ()>,
}

impl SyncScope {
    /// The tick the commands run on.
    pub fn tick(&self) -> u64 {
        self.at.tick
    }

    /// Commit: the master carries the key to the followers, every command sent since
    /// [`CardSet::begin`] runs on the tick, and this returns once all have answered (the first
    /// refusal, after all answered). `CommitLate`: the commit came on or after the tick, and
    /// nothing runs anywhere.
    pub fn commit(mut self) -> Result<u64> {
        let sent = pop_timing(self.saved.take().expect("a scope commits once"));
        let held = TimedCommands {
            tick: self.at.tick,
            commands: sent,
        };
        let master = &self.cards[0];
        if let Err(e) = master.sync_commit(self.at.key, self.at.tick) {
            cancel(&self.cards, self.at.key);
            return Err(e);
        }
        let rate = master.info().servo_rate_hz as f64;
        let left = self.at.tick.saturating_sub(master.tick()?) as f64 / rate;
        held.wait(Duration::from_secs_f64(left) + crate::ACK_TIMEOUT)?;
        Ok(self.at.tick)
    }
}

impl Drop for SyncScope {
    /// Uncommitted: nothing of it runs (the key cancelled on every card).
    fn drop(&mut self) {
        if let Some(saved) = self.saved.take() {
            pop_timing(saved);
            cancel(&self.cards, self.at.key);
        }
    }
}

/// Cancel `key` on every card (best effort: a card that cannot be reached holds nothing that
/// runs, its key uncommitted).
fn cancel(cards: &[Card], key: u32) {
    for c in cards {
        let _ = c.cancel_timed(key);
    }
}
