//! Tick step `snap`: a group at rest (nothing active, nothing more to run, the filters empty)
//! is snapped to the exact programmed end. The correction the snap makes is what the
//! interpolation and the filters lost or invented (plus the rounding of the sums to f64): it
//! is published, the first one of each rest as `snap_last`, the largest since enable as
//! `snap_max`, so a filter that lost distance would show. A halt or stop has come to rest.

use super::*;

impl Group {
    /// Snap the `members` to the programmed end; the correction it made (counts).
    pub(super) fn snap(&mut self, members: &[usize], axes: &mut [Axis; MAX_AXES]) -> f64 {
        self.stop_elapsed = None; // a halt or stop has come to rest
        let mut correction: f64 = 0.0;
        for (i, &a) in members.iter().enumerate() {
            let mut e = self.pos[i];
            e.add(-self.queue_end[i]);
            correction = correction.max(e.value().abs());
            self.pos[i] = CompensatedSum::new();
            self.pos[i].add(self.queue_end[i]);
            self.pos_out[i] = self.queue_end[i];
            axes[a].drive(Reference {
                pos: self.queue_end[i],
                vel: 0.0,
                acc: 0.0,
            });
            self.prev_vel[i] = 0.0;
        }
        if !self.resting {
            self.resting = true;
            self.snap_last = correction;
        }
        self.snap_max = self.snap_max.max(correction);
        correction
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::Bench;
    use super::*;

    /// Members left 1e-9 and 3e-7 counts off the programmed end are put on it exactly, at
    /// rest; the larger correction is published as the rest's `snap_last` and in `snap_max`.
    #[test]
    fn the_snap_puts_the_members_on_the_end_and_publishes_its_correction() {
        let mut b = Bench::new(2, true, false);
        let members = [0, 1];
        b.g.queue_end[0] = 1_000.0;
        b.g.queue_end[1] = -250.0;
        b.g.pos[0] = CompensatedSum::new();
        b.g.pos[0].add(1_000.0);
        b.g.pos[0].add(1e-9);
        b.g.pos[1] = CompensatedSum::new();
        b.g.pos[1].add(-250.0);
        b.g.pos[1].add(-3e-7);
        b.g.prev_vel[0] = 12.0;
        b.g.resting = false;
        b.g.stop_elapsed = Some(0.5);
        let c = b.g.snap(&members, &mut b.axes);
        assert!((c - 3e-7).abs() < 1e-12, "{c}");
        assert_eq!(b.g.snap_last, c);
        assert_eq!(b.g.snap_max, c);
        assert!(b.g.resting);
        assert_eq!(b.g.stop_elapsed, None);
        let r = b.axes[0].reference();
        assert_eq!((r.pos, r.vel, r.acc), (1_000.0, 0.0, 0.0));
        assert_eq!(b.axes[1].reference().pos, -250.0);
        assert_eq!((b.g.pos_out[0], b.g.prev_vel[0]), (1_000.0, 0.0));
        // Still at rest: nothing to correct; snap_last keeps the rest's first correction.
        assert_eq!(b.g.snap(&members, &mut b.axes), 0.0);
        assert_eq!((b.g.snap_last, b.g.snap_max), (c, c));
        // The next rest's correction replaces snap_last; snap_max keeps the largest.
        b.g.resting = false;
        b.g.pos[0].add(2e-8);
        let c2 = b.g.snap(&members, &mut b.axes);
        assert!((c2 - 2e-8).abs() < 1e-15, "{c2}");
        assert_eq!((b.g.snap_last, b.g.snap_max), (c2, c));
    }
}
