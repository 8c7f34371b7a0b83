//! Tick step `filter`: each member's increment passes through its acc/dec filter (Kim eq 1/9,
//! Shin eq 36–40) when post-interpolation acc/dec is on, and the axis's commanded position is
//! the error-free sum of what comes out (the filters' sub-ulp remainders included). The
//! filters' exponential stages empty together, on the tick every member's input is zero and
//! every member's tail is small enough (Kim eq 10–14: the axes of a move end on the same
//! tick).

use super::*;

impl Group {
    /// Filter the increments `inc` (group axis order) and drive the members' references.
    /// Whether every member's filter is empty (always, without post-interpolation filters).
    pub(super) fn filter(
        &mut self,
        cfg: &GroupConfig,
        inc: &[f64; MAX_AXES],
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        ts: f64,
    ) -> bool {
        let n = cfg.naxes;
        let members = &cfg.axes[..n];
        let flush = cfg.post
            && inc[..n].iter().all(|d| *d == 0.0)
            && members.iter().all(|&a| filters[a].live.tail_ready());
        let mut settled = true;
        for (i, &a) in members.iter().enumerate() {
            let (d, d_lo) = if cfg.post {
                filters[a].live.step_group(inc[i], flush)
            } else {
                (inc[i], 0.0)
            };
            settled &= !cfg.post || filters[a].is_settled();
            // The commanded position is the error-free sum of what the filters emit (their
            // remainders' sub-ulp parts included), restarted if anything else moved it.
            let r = axes[a].reference();
            if r.pos.to_bits() != self.pos_out[i].to_bits() {
                self.pos[i] = CompensatedSum::new();
                self.pos[i].add(r.pos);
            }
            self.pos[i].add(d);
            if d_lo != 0.0 {
                self.pos[i].add(d_lo);
            }
            let pos = self.pos[i].value();
            self.pos_out[i] = pos;
            let vel = (d + d_lo) / ts;
            let acc = (vel - self.prev_vel[i]) / ts;
            self.prev_vel[i] = vel;
            axes[a].drive(Reference { pos, vel, acc });
        }
        if self.active.is_some() || !settled {
            self.resting = false;
        }
        settled
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Bench, TS};
    use super::*;

    /// Without post-interpolation filters an increment goes straight to the reference:
    /// position, velocity inc/Ts and acceleration Δvel/Ts.
    #[test]
    fn without_filters_the_increment_is_the_reference() {
        let mut b = Bench::new(2, true, false);
        let cfg = b.cfg();
        let mut inc = [0.0; MAX_AXES];
        inc[0] = 2.5;
        inc[1] = -1.0;
        for k in 1..=3 {
            let settled = b.g.filter(&cfg, &inc, &mut b.axes, &mut b.filters, TS);
            assert!(settled);
            let r = b.axes[0].reference();
            assert_eq!(r.pos, 2.5 * k as f64);
            assert!((r.vel - 25_000.0).abs() < 1e-9);
            let expected_acc = if k == 1 { 25_000.0 / TS } else { 0.0 };
            assert!((r.acc - expected_acc).abs() < 1e-3, "{}", r.acc);
            assert_eq!(b.axes[1].reference().pos, -(k as f64));
        }
    }

    /// Through the default filters (rapid: bell, 35 ms) a step of 1000 counts in one tick
    /// comes out spread over the filter's time (its linear stage alone takes 350 ticks, its
    /// exponential tail longer) and whole: not settled until it is out, then exactly 1000 (the
    /// filters neither lose nor invent distance).
    #[test]
    fn a_filter_spreads_an_increment_and_loses_nothing() {
        let mut b = Bench::new(2, false, true);
        for a in 0..2 {
            b.filters[a].select(0, TS);
        }
        let cfg = b.cfg();
        let mut inc = [0.0; MAX_AXES];
        inc[0] = 1_000.0;
        inc[1] = 1e-3;
        assert!(!b.g.filter(&cfg, &inc, &mut b.axes, &mut b.filters, TS));
        let first = b.axes[0].reference().pos;
        assert!(
            first > 0.0 && first < 10.0,
            "bell filter's first output {first}"
        );
        let zero = [0.0; MAX_AXES];
        let mut ticks = 1;
        while !b.g.filter(&cfg, &zero, &mut b.axes, &mut b.filters, TS) {
            ticks += 1;
            assert!(ticks < 50_000);
        }
        assert!(ticks > 350, "{ticks} ticks");
        assert_eq!(b.axes[0].reference().pos, 1_000.0);
        assert_eq!(b.axes[1].reference().pos, 1e-3);
        assert!(!b.g.resting);
    }

    /// A reference moved by anything else restarts the sum there.
    #[test]
    fn the_sum_restarts_where_something_else_moved_the_reference() {
        let mut b = Bench::new(2, true, false);
        let cfg = b.cfg();
        b.axes[0].drive(Reference {
            pos: 500.0,
            vel: 0.0,
            acc: 0.0,
        });
        let mut inc = [0.0; MAX_AXES];
        inc[0] = 1.0;
        b.g.filter(&cfg, &inc, &mut b.axes, &mut b.filters, TS);
        assert_eq!(b.axes[0].reference().pos, 501.0);
    }
}
