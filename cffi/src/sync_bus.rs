//! Cards on one sync bus and commands timed to a tick (layout 1.12). The same thin skin as
//! [`crate::api`] over the SDK's `CardSet`, `Card::timed` and `Card::bus_status`.
//!
//! Timing is per thread, between a begin and its end: `mc_timed_begin` / `mc_timed_end` time
//! the commands this thread sends (to any card) to one tick and key; `mc_sync_begin` /
//! `mc_sync_start` do the same on a set of cards of one bus under a fresh key a margin ahead,
//! then commit it on the master so that every card runs them on that tick or none does.
//! Inside a timing, motion calls return as soon as the card holds the command; the motion
//! starts on the tick.

use crate::ffi::{read_slice, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, Failure};
use motioncard_sdk::{BusRole, BusState, Card, CardSet, ErrorKind, SyncScope, Timing, TimingScope};
use std::cell::RefCell;
use std::ffi::c_char;
use std::time::Duration;

/// Cards a set may hold.
pub const MC_SYNC_CARDS_MAX: u32 = 16;

/// A card's name, serial and place on the sync bus.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(non_camel_case_types)]
pub struct mc_bus_status {
    /// The card's name, NUL-terminated.
    pub name: [c_char; 32],
    /// Its serial number (0: none).
    pub serial: u64,
    /// `MC_BUS_ALONE`, `MC_BUS_MASTER` or `MC_BUS_FOLLOWER`.
    pub role: u32,
    /// `MC_BUSST_FREE`, `MC_BUSST_LOCKED` or `MC_BUSST_LOST`.
    pub state: u32,
    /// A follower's master, NUL-terminated ("" otherwise).
    pub master: [c_char; 32],
    /// A master's followers now.
    pub followers: u32,
    /// Timed commands held.
    pub timed_held: u32,
    /// The earliest held one's tick (0: none).
    pub timed_next: u64,
    /// Times it lost its master since boot.
    pub losses: u32,
}

fn name32(s: &str) -> [c_char; 32] {
    let mut b = [0 as c_char; 32];
    for (d, c) in b.iter_mut().zip(s.bytes().take(31)) {
        *d = c as c_char;
    }
    b
}

/// Open `n` (1..16) stepped emulated cards of `axes` axes on one sync bus, the first its
/// master (named `sim0`, `sim1`, …): stepping or waiting on any of them steps all of them,
/// master first. Writes their handles to `cards[0..n]`.
#[no_mangle]
pub unsafe extern "C" fn mc_open_sim_bus(
    n: usize,
    axes: u32,
    servo_rate_hz: u32,
    cards: *mut mc_card,
) -> mc_result {
    guard(|| {
        if cards.is_null() {
            return Err(Failure::null("cards"));
        }
        #[cfg(feature = "emulator")]
        {
            use motioncard_sdk::{Clock, EmuOptions, SimOptions};
            let set = CardSet::sim(
                n,
                SimOptions {
                    clock: Clock::Stepped,
                    emu: EmuOptions::new(axes as usize, servo_rate_hz),
                },
            )?;
            let mut handles = Vec::with_capacity(n);
            for c in set.cards() {
                handles.push(registry::insert(registry::Entry::new(c.clone()))?);
            }
            for (i, h) in handles.into_iter().enumerate() {
                // SAFETY: the caller gives room for n handles at `cards` (checked non-NULL).
                unsafe { cards.add(i).write_unaligned(h) };
            }
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (n, axes, servo_rate_hz);
            Err(crate::api::no_emulator())
        }
    })
}

/// The card's name, serial and place on the sync bus.
#[no_mangle]
pub unsafe extern "C" fn mc_get_bus_status(card: mc_card, status: *mut mc_bus_status) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let s = registry::get(card)?.card.bus_status()?;
        let v = mc_bus_status {
            name: name32(&s.name),
            serial: s.serial,
            role: match s.role {
                BusRole::Alone => 0,
                BusRole::Master => 1,
                BusRole::Follower => 2,
            },
            state: match s.state {
                BusState::Free => 0,
                BusState::Locked => 1,
                BusState::Lost => 2,
            },
            master: name32(&s.master),
            followers: s.followers,
            timed_held: s.timed_held,
            timed_next: s.timed_next.unwrap_or(0),
            losses: s.losses,
        };
        // SAFETY: checked non-NULL; valid by the function's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

enum Scope {
    Timed(TimingScope),
    Sync(SyncScope),
}

thread_local! {
    static SCOPE: RefCell<Option<Scope>> = const { RefCell::new(None) };
}

fn begin(scope: Scope) -> Result<(), Failure> {
    SCOPE.with(|s| {
        let mut s = s.borrow_mut();
        if s.is_some() {
            return Err(Failure::new(
                ErrorKind::InvalidState.code(),
                "this thread times its commands already: end that first",
            ));
        }
        *s = Some(scope);
        Ok(())
    })
}

fn take() -> Option<Scope> {
    SCOPE.with(|s| s.borrow_mut().take())
}

/// From now until `mc_timed_end`, the commands this thread sends (to any card) are timed to
/// `tick` with commit key `key` (0: none needed): each call returns once its card holds the
/// command (or with its refusal: `MC_ERR_TICK_PASSED`, `MC_ERR_TICK_FAR`, `MC_ERR_TIMED_FULL`,
/// …), and the command runs as the first thing of that tick. `MC_ERR_INVALID_STATE` when
/// this thread times already.
#[no_mangle]
pub extern "C" fn mc_timed_begin(tick: u64, key: u32) -> mc_result {
    guard(|| begin(Scope::Timed(TimingScope::begin(Timing { tick, key }))))
}

/// End `mc_timed_begin`, and wait up to `timeout_ms` for the held commands' answers (they
/// come on their tick): the first refusal (`MC_ERR_NOT_COMMITTED` for a key never committed,
/// `MC_ERR_TIMED_CANCELLED`, or the command's own), `MC_ERR_TIMEOUT`. Without a begin:
/// `MC_ERR_INVALID_STATE`.
#[no_mangle]
pub extern "C" fn mc_timed_end(timeout_ms: u32) -> mc_result {
    guard(|| match take() {
        Some(Scope::Timed(t)) => Ok(t.end().wait(Duration::from_millis(timeout_ms as u64))?),
        other => {
            if let Some(Scope::Sync(s)) = other {
                drop(s); // cancelled
            }
            Err(Failure::new(
                ErrorKind::InvalidState.code(),
                "mc_timed_end without mc_timed_begin",
            ))
        }
    })
}

/// Commit `key` for `tick` on `card` (the bus's master, or a card alone): its timed commands
/// run on that tick on it and on every follower. `MC_ERR_NOT_MASTER` on a follower,
/// `MC_ERR_COMMIT_LATE` on or after the tick (nothing of the key runs anywhere).
#[no_mangle]
pub extern "C" fn mc_sync_commit(card: mc_card, key: u32, tick: u64) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.sync_commit(key, tick)?))
}

/// Drop the commands `card` holds timed under `key` (0: all); `*dropped` (may be NULL): how
/// many. Each is refused with `MC_ERR_TIMED_CANCELLED`.
#[no_mangle]
pub unsafe extern "C" fn mc_timed_cancel(card: mc_card, key: u32, dropped: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::optional(dropped);
        let n = registry::get(card)?.card.cancel_timed(key)?;
        if let Some(o) = out {
            // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
            unsafe { o.write(n) };
        }
        Ok(())
    })
}

/// The cards of `cards[0..n]` as a set (the master first).
pub(crate) unsafe fn set_of(cards: *const mc_card, n: usize) -> Result<CardSet, Failure> {
    let n = n.min(MC_SYNC_CARDS_MAX as usize + 1);
    // SAFETY: the caller gives n readable handles.
    let handles = unsafe { read_slice(cards, n, "cards") }?;
    let cards: Vec<Card> = handles
        .iter()
        .map(|&h| registry::get(h).map(|e| e.card.clone()))
        .collect::<Result<_, _>>()?;
    Ok(CardSet::new(cards)?)
}

/// Begin a synchronised start on the cards `cards[0..n]` of one bus (the master first; else
/// `MC_ERR_BAD_CONFIG`): the commands this thread sends until `mc_sync_start` are timed to
/// one tick 20 ms ahead (`*tick`, may be NULL) under a fresh key.
#[no_mangle]
pub unsafe extern "C" fn mc_sync_begin(
    cards: *const mc_card,
    n: usize,
    tick: *mut u64,
) -> mc_result {
    guard(|| {
        let out = Out::optional(tick);
        // SAFETY: forwarded from this function's contract.
        let set = unsafe { set_of(cards, n) }?;
        let scope = set.begin()?;
        let t = scope.tick();
        begin(Scope::Sync(scope))?;
        if let Some(o) = out {
            // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
            unsafe { o.write(t) };
        }
        Ok(())
    })
}

/// Commit `mc_sync_begin`'s commands on the master and wait until they ran (every card on the
/// same tick, `*tick`, may be NULL). `MC_ERR_COMMIT_LATE`: nothing ran anywhere.
#[no_mangle]
pub unsafe extern "C" fn mc_sync_start(tick: *mut u64) -> mc_result {
    guard(|| {
        let out = Out::optional(tick);
        let Some(Scope::Sync(scope)) = take() else {
            return Err(Failure::new(
                ErrorKind::InvalidState.code(),
                "mc_sync_start without mc_sync_begin",
            ));
        };
        let t = scope.commit()?;
        if let Some(o) = out {
            // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
            unsafe { o.write(t) };
        }
        Ok(())
    })
}

/// Abandon `mc_sync_begin` (or `mc_timed_begin`): what it sent is cancelled on every card and
/// nothing of it runs.
#[no_mangle]
pub extern "C" fn mc_sync_abort() -> mc_result {
    guard(|| {
        drop(take());
        Ok(())
    })
}

unsafe fn sync_op(
    cards: *const mc_card,
    n: usize,
    tick: *mut u64,
    op: impl FnOnce(&CardSet) -> motioncard_sdk::Result<u64>,
) -> Result<(), Failure> {
    let out = Out::optional(tick);
    // SAFETY: forwarded from the caller's contract.
    let set = unsafe { set_of(cards, n) }?;
    let t = op(&set)?;
    if let Some(o) = out {
        // SAFETY: a non-NULL pointer given by the caller, valid by the contract.
        unsafe { o.write(t) };
    }
    Ok(())
}

/// Halt every moving axis of the cards `cards[0..n]` on one tick (`*tick`, may be NULL).
#[no_mangle]
pub unsafe extern "C" fn mc_sync_halt(
    cards: *const mc_card,
    n: usize,
    deceleration: f64,
    jerk: f64,
    tick: *mut u64,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { sync_op(cards, n, tick, |s| s.halt(deceleration, jerk)) })
}

/// Hold every moving axis of the cards `cards[0..n]` on one tick (override 0).
#[no_mangle]
pub unsafe extern "C" fn mc_sync_hold(
    cards: *const mc_card,
    n: usize,
    tick: *mut u64,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { sync_op(cards, n, tick, |s| s.hold()) })
}

/// Set the override of every moving axis of the cards `cards[0..n]` on one tick.
#[no_mangle]
pub unsafe extern "C" fn mc_sync_override(
    cards: *const mc_card,
    n: usize,
    factor: f64,
    tick: *mut u64,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { sync_op(cards, n, tick, |s| s.set_override(factor)) })
}
