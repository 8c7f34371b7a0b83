//! Card handles: small integers, looked up in one process-wide table.
//!
//! A handle is `generation << 16 | (slot + 1)`. Closing a card empties its slot and bumps the
//! slot's generation, so the old handle no longer matches anything (`MC_ERR_BAD_HANDLE`) even
//! after the slot holds another card; freed slots are reused oldest-first. 0 is never a handle.
//!
//! The table's lock is held only to look an entry up (an `Arc` clone), never during a call
//! into the card: a thread blocked in a wait on one card holds up nobody else. A card closed
//! while another thread is still inside a call on it stays alive until that call returns.

use crate::result::{Failure, MC_ERR_BAD_HANDLE};
use crate::types::mc_event;
use motioncard_sdk::ErrorKind;
#[cfg(feature = "emulator")]
use motioncard_sdk::Sim;
use motioncard_sdk::{Card, GroupMotion, Motion};
use std::collections::VecDeque;
use std::ffi::c_void;
use std::sync::{Arc, Mutex, MutexGuard};

/// A card handle: an integer, as in vendor libraries' card numbers. 0 is never a valid handle.
#[allow(non_camel_case_types)]
pub type mc_card = u32;

/// The event callback: called from `mc_dispatch_events`, on the thread that called it, once
/// per event. `event` is valid only during the call. `user` is the pointer given to
/// `mc_set_event_callback`.
#[allow(non_camel_case_types)]
pub type mc_event_callback =
    Option<unsafe extern "C" fn(card: mc_card, event: *const mc_event, user: *mut c_void)>;

/// Motions kept per card for `mc_motion_wait`, and group motions for `mc_group_motion_wait`
/// (the SDK keeps as many outcomes).
pub(crate) const MOTIONS_KEPT: usize = 1024;

/// A callback and its user pointer. The pointer is the application's: we only hand it back.
#[derive(Clone, Copy)]
pub(crate) struct Callback {
    pub f: unsafe extern "C" fn(mc_card, *const mc_event, *mut c_void),
    pub user: usize,
}

/// An open card.
pub(crate) struct Entry {
    pub card: Card,
    #[cfg(feature = "emulator")]
    pub sim: Option<Sim>,
    pub callback: Mutex<Option<Callback>>,
    /// Motions started through this handle, with their axis, for `mc_motion_wait`.
    pub motions: Mutex<VecDeque<(u32, Motion)>>,
    /// Group motions started through this handle, with their group, for `mc_group_motion_wait`.
    pub group_motions: Mutex<VecDeque<(u32, GroupMotion)>>,
}

impl Entry {
    pub(crate) fn new(card: Card) -> Self {
        Self {
            #[cfg(feature = "emulator")]
            sim: card.sim(),
            card,
            callback: Mutex::new(None),
            motions: Mutex::new(VecDeque::new()),
            group_motions: Mutex::new(VecDeque::new()),
        }
    }

    /// Keep a motion for `mc_motion_wait`.
    pub(crate) fn remember(&self, axis: u32, m: Motion) {
        let mut q = lock(&self.motions);
        if q.len() >= MOTIONS_KEPT {
            q.pop_front();
        }
        q.push_back((axis, m));
    }

    /// A motion kept by [`Entry::remember`].
    pub(crate) fn motion(&self, axis: u32, seq: u32) -> Option<Motion> {
        lock(&self.motions)
            .iter()
            .rev()
            .find(|(a, m)| *a == axis && m.seq() == seq)
            .map(|(_, m)| m.clone())
    }

    /// Keep a group motion for `mc_group_motion_wait`.
    pub(crate) fn remember_group(&self, group: u32, m: GroupMotion) {
        let mut q = lock(&self.group_motions);
        if q.len() >= MOTIONS_KEPT {
            q.pop_front();
        }
        q.push_back((group, m));
    }

    /// A group motion kept by [`Entry::remember_group`].
    pub(crate) fn group_motion(&self, group: u32, seq: u32) -> Option<GroupMotion> {
        lock(&self.group_motions)
            .iter()
            .rev()
            .find(|(g, m)| *g == group && m.seq() == seq)
            .map(|(_, m)| m.clone())
    }
}

struct Slot {
    generation: u16,
    entry: Option<Arc<Entry>>,
}

struct Registry {
    slots: Vec<Slot>,
    free: VecDeque<usize>,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    slots: Vec::new(),
    free: VecDeque::new(),
});

const MAX_SLOTS: usize = 0xFFFF;

/// Lock, recovering from poisoning: a panic in another call must not brick every card.
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

fn handle(slot: usize, generation: u16) -> mc_card {
    ((generation as u32) << 16) | (slot as u32 + 1)
}

fn bad_handle(h: mc_card) -> Failure {
    Failure::new(
        MC_ERR_BAD_HANDLE,
        format!("card handle {h} is not open (never opened, or already closed)"),
    )
}

/// Register an open card; returns its handle.
pub(crate) fn insert(entry: Entry) -> Result<mc_card, Failure> {
    let mut r = lock(&REGISTRY);
    let slot = match r.free.pop_front() {
        Some(s) => s,
        None if r.slots.len() < MAX_SLOTS => {
            r.slots.push(Slot {
                generation: 0,
                entry: None,
            });
            r.slots.len() - 1
        }
        None => {
            return Err(Failure::new(
                ErrorKind::Unsupported.code(),
                format!("{MAX_SLOTS} cards are open: close one first"),
            ))
        }
    };
    let s = &mut r.slots[slot];
    s.entry = Some(Arc::new(entry));
    Ok(handle(slot, s.generation))
}

fn slot_of(h: mc_card) -> Option<(usize, u16)> {
    let low = (h & 0xFFFF) as usize;
    (low != 0).then(|| (low - 1, (h >> 16) as u16))
}

/// The card behind a handle.
pub(crate) fn get(h: mc_card) -> Result<Arc<Entry>, Failure> {
    let (slot, generation) = slot_of(h).ok_or_else(|| bad_handle(h))?;
    let r = lock(&REGISTRY);
    match r.slots.get(slot) {
        Some(Slot {
            generation: g,
            entry: Some(e),
        }) if *g == generation => Ok(e.clone()),
        _ => Err(bad_handle(h)),
    }
}

/// Unregister a card. The caller drops the returned entry after the table is unlocked
/// (dropping a `sim` card joins its emulator thread).
pub(crate) fn remove(h: mc_card) -> Result<Arc<Entry>, Failure> {
    let (slot, generation) = slot_of(h).ok_or_else(|| bad_handle(h))?;
    let mut r = lock(&REGISTRY);
    let entry = match r.slots.get_mut(slot) {
        Some(s) if s.generation == generation && s.entry.is_some() => {
            s.generation = s.generation.wrapping_add(1);
            s.entry.take()
        }
        _ => None,
    };
    let entry = entry.ok_or_else(|| bad_handle(h))?;
    r.free.push_back(slot);
    Ok(entry)
}

#[cfg(all(test, feature = "emulator"))]
mod tests {
    use super::*;
    use motioncard_sdk::{Clock, EmuOptions, SimOptions};

    fn card() -> Card {
        Card::open_sim(SimOptions {
            clock: Clock::Stepped,
            emu: EmuOptions::new(1, 1000),
        })
        .unwrap()
    }

    #[test]
    fn closed_handles_stay_invalid_when_their_slot_is_reused() {
        let a = insert(Entry::new(card())).unwrap();
        assert_ne!(a, 0);
        assert!(get(a).is_ok());
        drop(remove(a).unwrap());
        assert_eq!(get(a).err().unwrap().code, MC_ERR_BAD_HANDLE);
        assert_eq!(remove(a).err().unwrap().code, MC_ERR_BAD_HANDLE);
        // Reuse slots until a's slot comes back: the old handle still does not match.
        let mut open = Vec::new();
        for _ in 0..4 {
            let h = insert(Entry::new(card())).unwrap();
            assert_ne!(h, a);
            open.push(h);
        }
        assert_eq!(get(a).err().unwrap().code, MC_ERR_BAD_HANDLE);
        for h in open {
            assert!(get(h).is_ok());
            drop(remove(h).unwrap());
        }
        for h in [0, 0xFFFF_0000, 0xFFFF, u32::MAX] {
            assert_eq!(get(h).err().unwrap().code, MC_ERR_BAD_HANDLE, "{h:#x}");
        }
    }
}
