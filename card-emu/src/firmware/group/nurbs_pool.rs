//! The NURBS curves of a group, in storage allocated once when the group is made (at boot).
//!
//! A slot holds one curve's interpolator — its control points, knots and look-ahead profile,
//! each with room for the largest curve — and, for the saturation-aware feed, the axes' model.
//! The command manager plans an accepted curve into a free slot (`MC_OP_NURBS_END`); a queued
//! or active move names its slot. A slot is free when no move names it, so a move that ends
//! or is aborted (in the servo tick as anywhere else) releases its slot by being dropped,
//! without touching the heap. There is a slot for every move the group can hold; were every
//! slot taken all the same, the next curve would be refused with `QueueFull`.
//!
//! The storage is reserved, never written until a curve is planned into it: a card that runs
//! no curve never touches its pages, which keeps booting a card cheap.

use crate::motion::nurbs_interp::Interpolator;
use crate::motion::saturation::SaturationAwareFeed;

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

/// A group's [`NURBS_SLOTS`] curve slots.
#[derive(Clone)]
pub(super) struct NurbsPool {
    slots: Box<[NurbsFeed]>,
}

impl core::fmt::Debug for NurbsPool {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "NurbsPool {{ slots: {} }}", self.slots.len())
    }
}

impl NurbsPool {
    /// Every slot with room for the largest curve (allocated here, once).
    pub(super) fn new() -> Self {
        Self {
            slots: (0..NURBS_SLOTS)
                .map(|_| NurbsFeed {
                    interp: Interpolator::with_capacity(),
                    sat: None,
                })
                .collect(),
        }
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

    /// The first slot for which `taken` is false.
    pub(super) fn free(&self, taken: impl Fn(usize) -> bool) -> Option<usize> {
        (0..self.slots.len()).find(|&k| !taken(k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_gives_two_different_slots_in_either_order() {
        let mut p = NurbsPool::new();
        let knots = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let ctrl = [0.0, 0.0, 1.0, 1.0, 2.0, 0.0];
        p.slots[2]
            .interp
            .set_curve(2, 2, &ctrl, &[1.0; 3], &knots)
            .unwrap();
        assert!(p.pair(3, 3).is_none());
        assert!(p.pair(0, NURBS_SLOTS).is_none());
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
        assert_eq!(p.free(|k| k < 3), Some(3));
        assert_eq!(p.free(|_| true), None);
    }
}
