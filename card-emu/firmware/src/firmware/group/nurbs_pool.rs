//! The NURBS curves of a group, in slots whose storage is allocated once and kept.
//!
//! A slot holds one curve's interpolator — its control points, knots and look-ahead profile,
//! each with room for the largest curve — and, for the saturation-aware feed, the axes' model.
//! The command manager plans an accepted curve into a free slot (`MC_OP_NURBS_END`); a queued
//! or active move names its slot. A slot is free when no move names it, so a move that ends
//! or is aborted (in the servo tick as anywhere else) releases its slot by being dropped,
//! without touching the heap. There is a slot for every move the group can hold; were every
//! slot taken all the same, the next curve would be refused with `QueueFull`.
//!
//! A slot's storage (about 410 kB) is made the first time the command manager needs the
//! slot, and kept for the life of the card: the pool never shrinks, and neither the tick nor
//! a curve that ends frees anything. On a host (the emulator) boot allocates none of it:
//! reserving all 33 slots of the four groups at boot (528 allocations, 54 MB of address
//! space) made booting a card seven times slower and the garbage sweep, which boots tens of
//! thousands of cards, 38 % slower. On the card the slots are its RAM (see `crate::ram`).

use crate::motion::nurbs_interp::Interpolator;
use crate::motion::saturation::SaturationAwareFeed;
use crate::ram::FixedVec;

/// NURBS curves a group holds at once: as many as it has moves, the active one and a full
/// queue, so a path of curves queues as deep as any other (a slot short of that would only
/// ever be refused with `QueueFull` like a full queue).
pub const NURBS_SLOTS: usize = firmware_proto::GROUP_QUEUE_LEN + 1;

/// The interpolator of a NURBS move and, for the saturation-aware feed, the axes' model.
#[derive(Clone)]
pub(super) struct NurbsFeed {
    pub(super) interp: Interpolator,
    pub(super) sat: Option<SaturationAwareFeed>,
}

impl core::fmt::Debug for NurbsFeed {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "NurbsFeed {{ length: {}, saturation-aware: {} }}",
            self.interp.length(),
            self.sat.is_some()
        )
    }
}

/// A group's curve slots: at most [`NURBS_SLOTS`], made as the command manager needs them.
#[derive(Clone, Default)]
pub(super) struct NurbsPool {
    slots: FixedVec<NurbsFeed, NURBS_SLOTS>,
}

impl core::fmt::Debug for NurbsPool {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "NurbsPool {{ slots: {} }}", self.slots.len())
    }
}

impl NurbsPool {
    /// No slot yet (allocates nothing).
    pub(super) fn new() -> Self {
        Self::default()
    }

    /// Slot `k`.
    pub(super) fn get(&self, k: usize) -> Option<&NurbsFeed> {
        self.slots.get(k)
    }

    /// Slot `k`, to plan a curve into or to step.
    pub(super) fn get_mut(&mut self, k: usize) -> Option<&mut NurbsFeed> {
        self.slots.get_mut(k)
    }

    /// Slot `k` to step and slot `j` to look ahead to or take over from (None unless two
    /// different slots).
    pub(super) fn pair(&mut self, k: usize, j: usize) -> Option<(&mut NurbsFeed, &NurbsFeed)> {
        if k == j || k >= self.slots.len() || j >= self.slots.len() {
            return None;
        }
        if k < j {
            let (lo, hi) = self.slots.split_at_mut(j);
            Some((&mut lo[k], &hi[0]))
        } else {
            let (lo, hi) = self.slots.split_at_mut(k);
            Some((&mut hi[0], &lo[j]))
        }
    }

    /// The first slot for which `taken` is false; a new slot (its storage allocated now, once)
    /// when every one made so far is taken; None when all [`NURBS_SLOTS`] are. Command
    /// manager only.
    pub(super) fn free(&mut self, taken: impl Fn(usize) -> bool) -> Option<usize> {
        if let Some(k) = (0..self.slots.len()).find(|&k| !taken(k)) {
            return Some(k);
        }
        let slot = NurbsFeed {
            interp: Interpolator::with_capacity(),
            sat: None,
        };
        self.slots.push(slot).ok()?; // all NURBS_SLOTS taken
        Some(self.slots.len() - 1)
    }

    /// Slots made so far.
    #[cfg(test)]
    pub(super) fn made(&self) -> usize {
        self.slots.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_are_made_once_as_needed_and_reused() {
        let mut p = NurbsPool::new();
        assert_eq!(p.made(), 0);
        // Every slot made so far is taken: a new one, up to NURBS_SLOTS.
        for k in 0..NURBS_SLOTS {
            assert_eq!(p.free(|j| j < k), Some(k));
        }
        assert_eq!(p.made(), NURBS_SLOTS);
        assert_eq!(p.free(|_| true), None);
        assert_eq!(p.made(), NURBS_SLOTS);
        // A released slot is found again; nothing new is made.
        assert_eq!(p.free(|j| j != 7), Some(7));
        assert_eq!(p.made(), NURBS_SLOTS);
    }

    #[test]
    fn pair_gives_two_different_slots_in_either_order() {
        let mut p = NurbsPool::new();
        for k in 0..6 {
            assert_eq!(p.free(|j| j < k), Some(k));
        }
        let knots = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let ctrl = [0.0, 0.0, 1.0, 1.0, 2.0, 0.0];
        p.slots[2]
            .interp
            .set_curve(2, 2, &ctrl, &[1.0; 3], &knots)
            .unwrap();
        assert!(p.pair(3, 3).is_none());
        assert!(p.pair(0, 6).is_none());
        let (a, b) = p.pair(5, 2).unwrap();
        assert_eq!(
            (a.interp.curve().n_ctrl(), b.interp.curve().n_ctrl()),
            (2, 3)
        );
        let (a, b) = p.pair(2, 5).unwrap();
        assert_eq!(
            (a.interp.curve().n_ctrl(), b.interp.curve().n_ctrl()),
            (3, 2)
        );
    }
}
