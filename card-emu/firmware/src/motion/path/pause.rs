//! A pause at the end of a segment (`MC_OP_PATH_PAUSE`): the path comes to rest at the end
//! of the first segment it can stop at within its limits, holds there, and goes on along the
//! same path when resumed.
//!
//! The end of segment k is where the path is nearest its programmed end: the programmed end
//! itself where no blend follows it, else the middle of the blend into segment k + 1 (where
//! the card ends segment k: within k's tolerance of the programmed end). The pause point is
//! the first such end beyond the distance the path needs to brake from where it is (an
//! exact stop, a dwell's end or the queue's end ahead is always one: the look-ahead brakes for
//! those anyway). The look-ahead takes it as a stop point at that distance, so the path brakes
//! for it within its limits and comes to rest on it; nothing queued is changed, and the motion
//! after a resume is the path's own, from rest there. If the executor ever passes the point
//! moving (a push that rebuilt the blend there), the next end it can stop at is chosen.
#![forbid(unsafe_code)]

use super::{Path, PathEvent};
use crate::motion::path_speed::PathSpeedPlanner;

/// Where a pause is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) enum Pause {
    #[default]
    Off,
    /// Asked for: the point is chosen at the next planning step.
    Pending,
    /// Braking for the end of segment `p − 1`.
    At(usize),
    /// At rest there (`id`: the segment it ends, if any segment was run).
    Held { id: Option<u32> },
}

/// A pause as the status shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PauseState {
    None,
    /// Braking for the pause point.
    Pausing,
    /// At rest at it (`id`: the segment it ends, if any segment was run).
    Paused {
        id: Option<u32>,
    },
}

impl<const D: usize> Path<D> {
    /// Pauses at the end of the first segment the path can stop at within its limits (see the
    /// module doc). Nothing queued changes. At rest with nothing queued it is paused at once:
    /// `true` (no tick posts [`PathEvent::Paused`] then).
    pub fn pause(&mut self) -> bool {
        if !self.ready || self.pause != Pause::Off || self.halted {
            return false;
        }
        if self.exec >= self.tail && !self.is_moving() {
            let p = self.tail;
            let id = (p > 0).then(|| self.seg(p - 1).id);
            self.pause = Pause::Held { id };
            return true;
        }
        self.pause = Pause::Pending;
        false
    }

    /// Ends a pause: the path goes on from the pause point (or, braking for it, does not stop
    /// there).
    pub fn resume(&mut self) {
        if self.pause != Pause::Off {
            self.pause = Pause::Off;
            self.seen = None;
        }
    }

    pub fn pause_state(&self) -> PauseState {
        match self.pause {
            Pause::Off => PauseState::None,
            Pause::Pending | Pause::At(_) => PauseState::Pausing,
            Pause::Held { id } => PauseState::Paused { id },
        }
    }

    /// The end of segment `p − 1` along the whole path (see the module doc).
    pub(super) fn end_of(&self, p: usize) -> f64 {
        if p >= self.tail {
            return self.end_dist;
        }
        let n = self.seg(p);
        if n.has_blend {
            n.start + 0.5 * n.blend.len
        } else {
            n.start
        }
    }

    /// Where the executor is along the whole path.
    fn here(&self) -> f64 {
        if self.exec < self.tail {
            self.exec_dist()
        } else {
            self.end_dist
        }
    }

    /// The pause point the look-ahead stops at, along the whole path.
    #[inline(always)]
    pub(super) fn pause_dist(&self) -> Option<f64> {
        match self.pause {
            Pause::At(p) => Some(self.end_of(p)),
            _ => None,
        }
    }

    /// At a planning step (after the dwells): chooses the pause point, and `true` holds the
    /// path at rest on it.
    #[inline(always)]
    pub(super) fn pause_tick(&mut self, ev: &mut impl FnMut(PathEvent)) -> bool {
        match self.pause {
            Pause::Off => false,
            Pause::Held { .. } => true,
            Pause::Pending => match self.pause_choose() {
                Some(p) => self.pause_reached(p, ev),
                None => false,
            },
            Pause::At(p) => self.pause_reached(p, ev),
        }
    }

    /// A pause pending: its point, if it can be chosen now.
    pub(super) fn pause_choose(&mut self) -> Option<usize> {
        let p = self.pause_point()?;
        self.pause = Pause::At(p);
        self.seen = None;
        Some(p)
    }

    /// The path pauses on reaching segment `p` (a dwell before it does not start it).
    #[inline(always)]
    pub(super) fn pause_at(&self, p: usize) -> bool {
        self.pause == Pause::At(p)
    }

    #[inline(never)]
    fn pause_reached(&mut self, p: usize, ev: &mut impl FnMut(PathEvent)) -> bool {
        let d = self.end_of(p);
        let here = self.here();
        let eps = 1e-9 * (d.abs() + 1.0);
        // (a dwell ending there ends first)
        let dwelling = self.exec < p.min(self.tail) && self.seg(self.exec).is_dwell();
        if here < d - eps || dwelling {
            return false;
        }
        if here > d + eps {
            // passed it: the next end it can stop at
            self.pause = Pause::Pending;
            self.seen = None;
            return false;
        }
        if !(self.at_rest() || (self.step.rest && !self.step.running())) {
            // (a hair short, the last of its speed: the next step lands)
            return false;
        }
        self.planner.settle();
        self.now = (0.0, 0.0);
        let id = (p > 0).then(|| self.seg(p - 1).id);
        self.pause = Pause::Held { id };
        ev(PathEvent::Paused { id });
        true
    }

    /// The planner at rest, within the rounding a stop leaves.
    fn at_rest(&self) -> bool {
        let (jt, ts) = (self.jt, self.tsp);
        self.planner.v <= 1e-9 * jt * ts * ts && self.planner.a.abs() <= 1e-6 * jt * ts
    }

    /// The first segment end at or beyond the braking distance from here, or an exact stop
    /// ahead, whichever comes first (as the index of the segment after it), or None while
    /// none is queued that far (the queue's end is a stop point of its own: the path rests
    /// there, and the pause is chosen there once it is near). Segment ends inside a
    /// time-shifted run are passed.
    fn pause_point(&self) -> Option<usize> {
        if self.exec >= self.tail {
            return Some(self.tail);
        }
        let pl = &self.planner;
        let need = if pl.v <= 0.0 && pl.a <= 0.0 {
            0.0
        } else {
            let (d, j) = (pl.dmax.min(self.dec.a), pl.jmax.min(self.dec.j));
            1.05 * PathSpeedPlanner::stopping_distance(pl.v, pl.a, d, j) + 4.0 * pl.v * self.tsp
        };
        let at = self.exec_dist();
        // (in the first half of a blend, the segment before it has not ended)
        for k in self.exec - usize::from(self.prev_open)..self.tail {
            let next = k + 1;
            let end = self.end_of(next);
            let sk = self.seg(k);
            let shifted = sk.shift || (next < self.tail && self.seg(next).shift);
            // an exact stop (or a dwell's end, or the queue's end) is one the look-ahead
            // brakes for anyway
            let stop = next >= self.tail || self.seg(next).stop_before || sk.is_dwell();
            if (stop || end - at >= need) && !shifted && end >= at {
                return Some(next);
            }
        }
        None
    }
}
