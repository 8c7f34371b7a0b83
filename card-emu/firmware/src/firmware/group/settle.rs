//! Tick step `settle`: a group at rest (snapped) waits until every member is within its
//! in-position windows for the longest settle time among them; then the move waiting for it
//! is done (`GroupMotionDone`, value 1), and — unless an `MC_GroupStop` still holds it — the
//! members leave SynchronizedMotion for Standstill and the group goes to Standby.

use super::*;

impl Group {
    /// Count the time in position; at the settle time, post the done events and the states.
    pub(super) fn settle(
        &mut self,
        members: &[usize],
        axes: &mut [Axis; MAX_AXES],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) {
        let in_pos = members
            .iter()
            .all(|&a| axes[a].in_position_at(axes[a].reference().pos));
        self.settled_for = if in_pos { self.settled_for + ts } else { 0.0 };
        let settle = members
            .iter()
            .map(|&a| axes[a].config.settle_time)
            .fold(0.0, f64::max);
        if !(in_pos && self.settled_for + 1e-12 >= settle) {
            return;
        }
        if let Some(seq) = self.final_seq.take() {
            out.push(self.event(EventKind::GroupMotionDone, seq, 0, 1.0, tick));
        }
        match self.stop {
            Some(StopKind::Stop) if !self.stop_released => {}
            _ => {
                self.stop = None;
                for &a in members {
                    let old = axes[a].leave_group_motion();
                    axis_event(out, a, old, AxisState::Standstill, tick);
                }
                self.set_state(GroupState::Standby, tick, out);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Bench, TS};
    use super::*;

    /// A group moving two members that sit on their references: the default settle time
    /// (2 ms) is 20 ticks in position, then the waiting move is done and the group stands by.
    fn moving() -> Bench {
        let mut b = Bench::new(2, true, false);
        let mut out = Outbox::default();
        for a in 0..2 {
            b.axes[a].join_group_motion();
        }
        b.g.set_state(GroupState::Moving, 0, &mut out);
        b.g.final_seq = Some(42);
        b.follow();
        b
    }

    fn settle(b: &mut Bench) {
        b.tick += 1;
        b.g.settle(&[0, 1], &mut b.axes, TS, b.tick, &mut b.out);
    }

    #[test]
    fn in_position_for_the_settle_time_the_move_is_done_and_the_group_stands_by() {
        let mut b = moving();
        for _ in 0..19 {
            settle(&mut b);
        }
        assert!((b.g.settled_for - 19.0 * TS).abs() < 1e-12);
        assert!(b.events().is_empty());
        assert_eq!(b.g.state, GroupState::Moving);
        settle(&mut b);
        let ev = b.events();
        assert_eq!(ev[0].kind, EventKind::GroupMotionDone as u16);
        assert_eq!((ev[0].seq, ev[0].value, ev[0].tick), (42, 1.0, 20));
        let standstill = ev
            .iter()
            .filter(|e| {
                e.kind == EventKind::StateChanged as u16 && e.code == AxisState::Standstill as i32
            })
            .count();
        assert_eq!(standstill, 2);
        assert_eq!(ev.last().unwrap().kind, EventKind::GroupStateChanged as u16);
        assert_eq!(b.g.state, GroupState::Standby);
        assert_eq!(b.axes[0].state, AxisState::Standstill);
        assert_eq!(b.g.final_seq, None);
    }

    /// Out of position (2 counts off, the window is 1) the clock restarts.
    #[test]
    fn out_of_position_the_settle_time_restarts() {
        let mut b = moving();
        for _ in 0..10 {
            settle(&mut b);
        }
        b.axes[1].sense(2, TS);
        settle(&mut b);
        assert_eq!(b.g.settled_for, 0.0);
        assert_eq!(b.g.final_seq, Some(42));
        // Back on the reference (once the measured velocity is within its window too), the
        // settle time runs again from 0.
        b.axes[1].sense(0, TS);
        let mut ticks = 0;
        while b.g.state != GroupState::Standby {
            b.follow();
            settle(&mut b);
            ticks += 1;
            assert!(ticks < 10_000);
        }
        assert!(ticks >= 20, "{ticks} ticks");
    }

    /// An MC_GroupStop holds the group (Stopping) after its done, until released.
    #[test]
    fn a_stop_holds_the_group_until_released() {
        let mut b = moving();
        b.g.stop = Some(StopKind::Stop);
        b.g.stop_released = false;
        for _ in 0..30 {
            settle(&mut b);
        }
        assert!(b.events().iter().any(|e| e.seq == 42));
        assert_eq!(b.g.state, GroupState::Moving);
        assert_eq!(b.axes[0].state, AxisState::SynchronizedMotion);
        b.g.stop_released = true;
        settle(&mut b);
        assert_eq!(b.g.state, GroupState::Standby);
        assert_eq!(b.g.stop, None);
    }
}
