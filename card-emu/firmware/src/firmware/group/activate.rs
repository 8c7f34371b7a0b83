//! Tick step `activate`: the next queued move becomes the active one, unless a halt or stop
//! is in progress, or the post-interpolation filters must first empty to switch to the move's
//! feed type. Starting it ends the move that waited to be in position (its done event), and
//! takes the members into SynchronizedMotion.

use super::*;

impl Group {
    pub(super) fn activate(
        &mut self,
        cfg: &GroupConfig,
        axes: &mut [Axis; MAX_AXES],
        filters: &mut [AxisFilter],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) {
        if self.active.is_some() || self.stop.is_some() {
            return;
        }
        let members = &cfg.axes[..cfg.naxes];
        let Some(next) = self.peek() else { return };
        // Filters switch feed type only when empty.
        let ft = next.feed_type;
        let switching = cfg.post
            && members
                .iter()
                .any(|&a| filters[a].built_for.map(|k| k.0) != Some(ft));
        if switching && !members.iter().all(|&a| filters[a].is_settled()) {
            return;
        }
        let Some(mv) = self.pop() else { return };
        // The previous move was waiting to be in position: it is done now.
        if let Some(seq) = self.final_seq.take() {
            out.push(self.event(EventKind::GroupMotionDone, seq, 0, 0.0, tick));
        }
        if cfg.post {
            for &a in members {
                filters[a].select(ft, ts);
            }
        }
        for &a in members {
            let old = axes[a].join_group_motion();
            axis_event(out, a, old, AxisState::SynchronizedMotion, tick);
        }
        self.active = Some(Active {
            last: mv.geom.start(),
            mv,
            s: 0.0,
            stopping: None,
            retimed: None,
            v: 0.0,
            a: 0.0,
        });
        // Planned at the programmed feed when queued: replanned for an override in force.
        // (A factor that cannot be planned for this move holds it at its start.)
        if self
            .active
            .as_ref()
            .is_some_and(|a| self.factor_of(&a.mv) != 1.0)
        {
            let rate = crate::firmware::rate_hz(ts);
            if self.replan_active(rate).is_err() {
                self.hold_active(rate);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Bench, TS};
    use super::*;

    fn activate(b: &mut Bench) {
        let cfg = b.cfg();
        b.g.activate(&cfg, &mut b.axes, &mut b.filters, TS, 1, &mut b.out);
    }

    #[test]
    fn the_next_move_starts_and_the_members_join_it() {
        let mut b = Bench::new(2, true, false);
        b.line(7, &[300.0, 400.0], 0);
        b.events();
        activate(&mut b);
        let act = b.g.active.as_ref().unwrap();
        assert_eq!(act.mv.seq, 7);
        assert_eq!(
            (act.s, act.v, act.last[0], act.last[1]),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(act.mv.geom.len(), 500.0);
        assert_eq!(b.g.queue.len(), 0);
        for a in 0..2 {
            assert_eq!(b.axes[a].state, AxisState::SynchronizedMotion);
        }
        let ev = b.events();
        assert_eq!(ev.len(), 2, "{ev:?}");
        assert!(ev.iter().all(|e| e.kind == EventKind::StateChanged as u16
            && e.code == AxisState::SynchronizedMotion as i32
            && e.value == AxisState::Standstill as u32 as f64));
        // Nothing else starts while one is active.
        b.line(8, &[0.0, 0.0], 0);
        activate(&mut b);
        assert_eq!(b.g.active.as_ref().unwrap().mv.seq, 7);
        assert_eq!(b.g.queue.len(), 1);
    }

    #[test]
    fn starting_ends_the_move_waiting_to_be_in_position() {
        let mut b = Bench::new(2, true, false);
        b.line(4, &[10.0, 0.0], 0);
        b.events(); // Standby -> Moving
        b.g.final_seq = Some(3);
        activate(&mut b);
        let ev = b.events();
        assert_eq!(ev[0].kind, EventKind::GroupMotionDone as u16);
        assert_eq!((ev[0].seq, ev[0].value), (3, 0.0));
        assert_eq!(b.g.final_seq, None);
    }

    #[test]
    fn nothing_starts_during_a_halt() {
        let mut b = Bench::new(2, true, false);
        b.line(4, &[10.0, 0.0], 0);
        b.g.stop = Some(StopKind::Halt(9));
        activate(&mut b);
        assert!(b.g.active.is_none());
        assert_eq!(b.g.queue.len(), 1);
    }

    /// A move of another feed type waits until the filters are empty, then switches them.
    #[test]
    fn the_filters_switch_feed_type_only_when_empty() {
        let mut b = Bench::new(2, false, true);
        b.line(1, &[1_000.0, 0.0], 0); // rapid: bell
        let cutting = 1u32 << move_flags::FEED_TYPE_SHIFT;
        b.line(2, &[1_000.0, 1_000.0], cutting); // cutting: linear
        assert!(b.run_until(10_000, |b| b
            .g
            .active
            .as_ref()
            .is_some_and(|a| a.mv.seq == 2)));
        // When the cutting move started, the rapid filters had emptied: axis 0 had arrived.
        assert_eq!(b.filters[0].built_for, Some((1, TS.to_bits())));
        assert!((b.pos(0) - 1_000.0).abs() < 1e-9, "{}", b.pos(0));
        assert!(b.pos(1) < 1.0, "{}", b.pos(1));
    }
}
