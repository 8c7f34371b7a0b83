//! Tick step `feed`: the active move's arc length advances by one tick, and each member's
//! increment is taken from the path (Kim's pulse data f_i(k)). The feed is the move's own —
//! an S-curve of the path length (pre-interpolation acc/dec, Thinh eq 1–28), a constant feed
//! (post-interpolation acc/dec only), Kim's reference-word circle (eq 15–23), or Yeh's
//! speed-controlled NURBS interpolator (eq 3.1, saturation-aware with §3.4) — or, during a
//! halt or stop, the stop profile (`stop`). A move that ends is retired: its done event, or it
//! waits to be in position.

use super::stop::stop_progress;
use super::*;
use crate::motion::nurbs::Point;
use crate::motion::scurve::State;

/// One tick of a feed: the point it reached, when it computes points itself (reference word,
/// NURBS), and whether the move is over.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Advance {
    point: Option<[f64; MAX_AXES]>,
    finished: bool,
}

impl Group {
    /// Advance the active move (if any) by one tick: the members' increments, in group axis
    /// order. `axes` gives this tick's measurements (for the saturation-aware feed).
    pub(super) fn feed(
        &mut self,
        cfg: &GroupConfig,
        axes: &[Axis; MAX_AXES],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> [f64; MAX_AXES] {
        let n = cfg.naxes;
        let mut inc = [0.0; MAX_AXES];
        // This tick's measurements, for the saturation-aware feed (Yeh eq 3.3: θ_a[k], w_a[k]).
        let mut theta_a = Point::zeros();
        let mut w_a = Point::zeros();
        for (i, &a) in cfg.axes[..n].iter().enumerate() {
            (theta_a[i], w_a[i]) = axes[a].actual();
        }
        // A NURBS path runs on into the next queued curve without stopping when the two join
        // (the planner then plans over both; see `Interpolator::continuation`). Queued in time
        // or not is all that matters: without a next curve the planner stops at the end.
        let join = self.active.as_ref().is_some_and(|act| match &act.mv.feed {
            Feed::Nurbs(cur) => self.joinable(*cur, act.mv.feed_type, 0, cfg.post).is_some(),
            _ => false,
        });
        let index = self.index;
        let k = self
            .active
            .as_ref()
            .map_or(1.0, |act| self.factor_of(&act.mv));
        let mut finished = false;
        if let Some(act) = &mut self.active {
            let len = act.mv.geom.len();
            let prev_v = act.v;
            let adv = if let Feed::Nurbs(k) = act.mv.feed {
                let m = (&theta_a, &w_a);
                nurbs_feed(
                    act,
                    k,
                    join,
                    &mut self.queue,
                    &mut self.nurbs,
                    n,
                    m,
                    ts,
                    (index, tick),
                    out,
                )
            } else if let Some(stop) = &mut act.stopping {
                let st = stop_progress(stop, ts);
                act.s = st.s.min(len);
                act.v = st.v;
                let finished = st.done || act.s >= len;
                if finished {
                    act.v = 0.0;
                }
                Advance {
                    point: None,
                    finished,
                }
            } else {
                let adv = own_feed(act, n, ts, len, k);
                // The ramp down to a lowered feed ended: on to the end of the path.
                if let (Some((traj, t)), Feed::Profile { lim, .. }) = (&act.retimed, &act.mv.feed) {
                    if *t >= traj.duration() && traj.end().vel > 0.0 && !adv.finished {
                        let rate = crate::firmware::rate_hz(ts);
                        let (s, v) = (act.s, act.v);
                        // (What cannot be planned holds where it is, as a 0 % override.)
                        act.retimed = overrides::plan_path(s, v, 0.0, len, lim, k, rate)
                            .or_else(|_| overrides::plan_path(s, v, 0.0, len, lim, 0.0, rate))
                            .ok()
                            .map(|tr| (tr, 0.0));
                    }
                }
                adv
            };
            finished = adv.finished;
            act.a = (act.v - prev_v) / ts;
            let p = match (adv.point, finished, act.stopping.is_some()) {
                (Some(p), false, _) => p,
                // A curve stopped early: where its interpolator stopped.
                (Some(p), true, true) if matches!(act.mv.feed, Feed::Nurbs(_)) => p,
                (_, true, false) => act.mv.geom.end(n),
                _ => act.mv.geom.point(act.s, n),
            };
            for i in 0..n {
                inc[i] = p[i] - act.last[i];
            }
            act.last = p;
        }
        if finished {
            self.retire(tick, out);
        }
        inc
    }

    /// The active move is over: a stopped one sets the programmed position where it ended
    /// (and drops the curves kept for the stop's run-out, reported aborted already); then it
    /// is done at once when more is queued, else once the group is in position (`settle`).
    fn retire(&mut self, tick: u64, out: &mut Outbox) {
        let Some(act) = self.active.take() else {
            return;
        };
        if act.stopping.is_some() {
            self.queue_end = act.last;
            while self.peek().is_some_and(|m| m.runout) {
                self.pop();
            }
        }
        if !self.queue.is_empty() && self.stop.is_none() {
            // More queued: this one is done as soon as the next takes over.
            out.push(self.event(EventKind::GroupMotionDone, act.mv.seq, 0, 0.0, tick));
        } else if self.stop.is_none() {
            self.final_seq = Some(act.mv.seq);
            self.settled_for = 0.0;
        }
    }
}

/// The move's own feed (not stopping, not a curve): S-curve, constant or reference word;
/// `k` is the override in force (a constant feed is scaled by it; an S-curve was replanned
/// for it, and at 0 it waits on its path).
fn own_feed(act: &mut Active, n: usize, ts: f64, len: f64, k: f64) -> Advance {
    let (s, v, finished, point) = match (&mut act.mv.feed, &mut act.retimed) {
        (Feed::Profile { .. }, Some((traj, t))) => {
            let (s, v, done) = profile_feed(|t| traj.sample(t), traj.duration(), t, ts, len);
            // Not over while held at 0 %, nor at the end of a ramp down to a lowered feed.
            (s, v, done && k > 0.0 && traj.end().vel == 0.0, None)
        }
        (Feed::Profile { profile, t, .. }, None) => {
            let (s, v, done) = profile_feed(|t| profile.sample(t), profile.duration(), t, ts, len);
            (s, v, done, None)
        }
        (Feed::Constant { v }, _) => {
            let (s, done) = constant_feed(act.s, *v * k, ts, len);
            (s, *v * k, done, None)
        }
        (Feed::ReferenceWord(rw), _) => {
            match reference_word_feed(rw, &act.mv.geom, &act.last, n, len) {
                Some((p, s, v, done)) => (s, v, done, Some(p)),
                None => {
                    return Advance {
                        point: None,
                        finished: true,
                    }
                }
            }
        }
        // Curves have their own step.
        (Feed::Nurbs(_), _) => {
            return Advance {
                point: None,
                finished: true,
            }
        }
    };
    act.s = s;
    act.v = v;
    Advance { point, finished }
}

/// One tick along an S-curve of the path length (`sample`, lasting `duration`): (arc length,
/// speed, the profile is over).
fn profile_feed(
    sample: impl Fn(f64) -> State,
    duration: f64,
    t: &mut f64,
    ts: f64,
    len: f64,
) -> (f64, f64, bool) {
    *t += ts;
    let st = sample(*t);
    (st.pos.min(len), st.vel, *t >= duration)
}

/// One tick at the constant feed `v` from arc length `s`: (arc length, the end is reached).
fn constant_feed(s: f64, v: f64, ts: f64, len: f64) -> (f64, bool) {
    let s = (s + v * ts).min(len);
    (s, s >= len)
}

/// One tick of Kim's reference-word circle (eq 15–23) from the point `last`: the point (the
/// plane's increments from the circle, the helix's axes linear in the step count), the arc
/// length, the feed and whether it is done; None when the circle has no step left or `geom`
/// is not an arc.
fn reference_word_feed(
    rw: &mut ReferenceWordCircle,
    geom: &Geometry,
    last: &[f64; MAX_AXES],
    n: usize,
    len: f64,
) -> Option<([f64; MAX_AXES], f64, f64, bool)> {
    // Built for arcs only; anything else ends the move.
    let (u, v, helix, start) = match *geom {
        Geometry::Arc {
            u, v, helix, start, ..
        } => (u, v, helix, start),
        Geometry::Line { start, .. } | Geometry::Curve { start, .. } => {
            (0, 0, [0.0; MAX_AXES], start)
        }
        Geometry::ArcNormal(h) => (0, 0, [0.0; MAX_AXES], h.ends().0),
    };
    let (du, dv) = rw.next_increment().filter(|_| u != v)?;
    let k = rw.total_steps() - rw.remaining_steps();
    let f = k as f64 / rw.total_steps().max(1) as f64;
    let mut p = *last;
    p[u] += du;
    p[v] += dv;
    for i in 0..n {
        if i != u && i != v {
            p[i] = start[i] + helix[i] * f;
        }
    }
    Some((p, len * f, rw.feed(), rw.is_done()))
}

/// One tick of the NURBS move in slot `k`: its interpolator steps (at the stop profile's
/// speed during a halt or stop, saturation-aware when its slot has the model, else planned),
/// running on into the next queued curve when they `join`; a curve that ends inside the step
/// hands the rest of it over to the next one, which becomes the active move.
#[allow(clippy::too_many_arguments)]
fn nurbs_feed(
    act: &mut Active,
    k: usize,
    join: bool,
    queue: &mut Deque<Move, GROUP_QUEUE_LEN>,
    nurbs: &mut NurbsPool,
    n: usize,
    (theta_a, w_a): (&Point, &Point),
    ts: f64,
    (index, tick): (u16, u64),
    out: &mut Outbox,
) -> Advance {
    let len = act.mv.geom.len();
    let mut point = None;
    let mut finished = false;
    let mut hand_over = false;
    let mut stopped = false;
    let next_slot = match (join, queue.front()) {
        (
            true,
            Some(Move {
                feed: Feed::Nurbs(j),
                ..
            }),
        ) => Some(*j),
        _ => None,
    };
    let (nf, next) = match next_slot.and_then(|j| nurbs.pair(k, j)) {
        Some((nf, n2)) => {
            let next = nf.interp.continuation(&n2.interp);
            (Some(nf), next)
        }
        None => (nurbs.get_mut(k), None),
    };
    let joined = next.is_some();
    let step = match nf {
        // (a move names one of the slots: never)
        None => Err(InterpError::ZeroLengthCurve),
        Some(nf) => {
            if let Some(stop) = &mut act.stopping {
                // Halt/stop along the curve: the stop profile sets the feed.
                let st = stop_progress(stop, ts);
                stopped = st.done;
                nf.interp.advance(st.v.max(0.0))
            } else if let Some(sat) = &nf.sat {
                nf.interp
                    .tick_guarded_into(sat, theta_a, w_a, next)
                    .map(|(tk, _)| tk)
            } else {
                nf.interp.tick_into(next)
            }
        }
    };
    match step {
        Ok(tk) if tk.done && joined && !stopped => hand_over = true,
        Ok(tk) => {
            let mut p = act.last;
            p[..n].copy_from_slice(&tk.pos.as_slice()[..n]);
            point = Some(p);
            act.v = if stopped { 0.0 } else { tk.feed };
            act.s = (act.s + tk.feed * ts).min(len);
            finished = tk.done || stopped;
        }
        // The interpolator refused to step (it cannot on valid input): hold here.
        Err(_) => finished = true,
    }
    if !hand_over {
        return Advance { point, finished };
    }
    // The curve ended inside this tick's step: the next one takes the rest of it.
    let Some(next) = queue.pop_front() else {
        return Advance {
            point,
            finished: true,
        };
    };
    let prev = core::mem::replace(&mut act.mv, next);
    if !act.mv.runout {
        out.push(Event {
            seq: prev.seq,
            kind: EventKind::GroupMotionDone as u16,
            axis: index,
            code: 0,
            tick,
            value: 0.0,
        });
    }
    let step = match (&prev.feed, &mut act.mv.feed) {
        (Feed::Nurbs(a), Feed::Nurbs(b)) => nurbs
            .pair(*b, *a)
            .map(|(nb, na)| nb.interp.take_over(&na.interp)),
        _ => None,
    };
    match step {
        Some(Ok(tk)) => {
            let mut p = act.last;
            p[..n].copy_from_slice(&tk.pos.as_slice()[..n]);
            point = Some(p);
            act.v = tk.feed;
            act.s = tk.feed * ts;
            finished = tk.done;
        }
        _ => finished = true,
    }
    Advance { point, finished }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Bench, TS};
    use super::*;
    use crate::motion::nurbs::{clamped_uniform_knots, Nurbs};

    /// The S-curve feed follows its profile tick by tick and ends exactly on the length.
    #[test]
    fn an_s_curve_feed_follows_its_profile_to_the_end() {
        let lim = Limits::symmetric(1e5, 1e6, 1e8);
        let p = Profile::plan(0.0, 1_000.0, 0.0, 0.0, &lim).unwrap();
        let mut t = 0.0;
        let (s, v, done) = profile_feed(|t| p.sample(t), p.duration(), &mut t, TS, 1_000.0);
        assert_eq!((s, v, done), (p.sample(TS).pos, p.sample(TS).vel, false));
        let mut ticks = 1;
        let mut last = (s, v, done);
        while !last.2 {
            last = profile_feed(|t| p.sample(t), p.duration(), &mut t, TS, 1_000.0);
            ticks += 1;
        }
        assert_eq!(ticks, (p.duration() / TS).ceil() as usize);
        assert!(
            (last.0 - 1_000.0).abs() < 1e-9 && last.0 <= 1_000.0,
            "{}",
            last.0
        );
        assert!(last.1.abs() < 1e-6);
    }

    /// The constant feed steps v·Ts and stops on the length.
    #[test]
    fn a_constant_feed_steps_v_ts_and_stops_on_the_length() {
        assert_eq!(constant_feed(0.0, 1e5, TS, 25.0), (10.0, false));
        assert_eq!(constant_feed(10.0, 1e5, TS, 25.0), (20.0, false));
        assert_eq!(constant_feed(20.0, 1e5, TS, 25.0), (25.0, true));
    }

    /// Kim's reference-word arc (post filters only): every point within a count of the
    /// circle, the helix's axis linear in the arc, the end exact.
    #[test]
    fn a_reference_word_arc_stays_on_its_circle_and_ends_exactly() {
        let mut b = Bench::with(3, false, true, true);
        b.arc(5, [20_000.0, 0.0], [10_000.0, 0.0], &[3_000.0]);
        let cfg = b.cfg();
        let (mut worst, mut ticks) = (0.0f64, 0);
        let mut z_prev = 0.0;
        loop {
            b.g.activate(&cfg, &mut b.axes, &mut b.filters, TS, 1, &mut b.out);
            let inc = b.g.feed(&cfg, &b.axes, TS, 1, &mut b.out);
            let Some(act) = b.g.active.as_ref() else {
                break;
            };
            let (x, y) = (act.last[0], act.last[1]);
            worst = worst.max(((x - 10_000.0).hypot(y) - 10_000.0).abs());
            // z advances with the arc: 3000 counts over pi·1e4.
            assert!((act.last[2] - 3_000.0 * act.s / act.mv.geom.len()).abs() < 1.0);
            assert!(inc[2] >= 0.0 && act.last[2] >= z_prev);
            z_prev = act.last[2];
            assert!((act.v - 1e5).abs() < 1e-6 * 1e5, "{}", act.v);
            ticks += 1;
            assert!(ticks < 100_000);
        }
        // pi·1e4 counts at 1e5 counts/s: about 3142 ticks.
        assert!((3_100..=3_200).contains(&ticks), "{ticks} ticks");
        assert!(worst < 1.0, "radial error {worst}");
        assert_eq!(b.g.final_seq, Some(5));
        let end = b.g.queue_end;
        assert!(
            (end[0] - 20_000.0).abs() < 1e-9 && end[1].abs() < 1e-9,
            "{end:?}"
        );
        assert_eq!(end[2], 3_000.0);
    }

    /// A halt mid-line: the stop profile replaces the feed, the line ends where it came to
    /// rest, and that becomes the programmed end.
    #[test]
    fn a_halt_ends_the_line_where_it_comes_to_rest() {
        let mut b = Bench::new(2, true, false);
        b.line(1, &[100_000.0, 0.0], 0);
        let cfg = b.cfg();
        b.g.activate(&cfg, &mut b.axes, &mut b.filters, TS, 1, &mut b.out);
        for _ in 0..2_000 {
            b.g.feed(&cfg, &b.axes, TS, 1, &mut b.out);
        }
        let act = b.g.active.as_ref().unwrap();
        let (s0, v0, a0) = (act.s, act.v, act.a);
        assert!(v0 > 0.0);
        let ramp = (1e6, 1e8);
        b.g.start_stop(9, false, ramp, ramp, 10.0, 1, &mut b.out)
            .unwrap();
        let end = crate::motion::scurve::plan_stop(s0, v0, a0.max(0.0), 1e6, 1e8)
            .unwrap()
            .end_pos();
        let mut prev_v = v0;
        while b.g.active.is_some() {
            b.g.feed(&cfg, &b.axes, TS, 1, &mut b.out);
            if let Some(act) = b.g.active.as_ref() {
                assert!(act.v <= prev_v + 1e-6, "{} after {prev_v}", act.v);
                prev_v = act.v;
            }
        }
        assert!(
            (b.g.queue_end[0] - end).abs() < 1e-6,
            "{} vs {end}",
            b.g.queue_end[0]
        );
        assert_eq!(b.g.queue_end[1], 0.0);
        assert_eq!(b.g.final_seq, Some(9));
    }

    fn wave(n: usize, from: [f64; 2]) -> Nurbs {
        let ctrl: Vec<f64> = (0..n)
            .flat_map(|i| {
                let t = i as f64;
                [from[0] + 500.0 * t, from[1] + 300.0 * (0.5 * t).sin()]
            })
            .collect();
        let w = vec![1.0; n];
        Nurbs::new(3, 2, &ctrl, &w, &clamped_uniform_knots(n, 3).unwrap()).unwrap()
    }

    /// Two NURBS curves that join run through the joint without stopping: the first is done
    /// when the second takes over, the feed never drops to 0 in between, and the path ends
    /// exactly on the second curve's end.
    #[test]
    fn a_nurbs_path_runs_through_its_joint_and_ends_on_the_curve() {
        let mut b = Bench::new(2, true, false);
        let first = wave(12, [0.0, 0.0]);
        // The second curve goes straight on along the first's end tangent: no turn at the
        // joint, so no speed cap there.
        let (end, d1, _) = first.eval(first.domain().1).unwrap();
        let dir = d1 / d1.norm();
        let ctrl: Vec<f64> = (0..12)
            .flat_map(|i| {
                let p = end + dir * (500.0 * i as f64);
                [p[0], p[1]]
            })
            .collect();
        let second = Nurbs::new(
            3,
            2,
            &ctrl,
            &[1.0; 12],
            &clamped_uniform_knots(12, 3).unwrap(),
        )
        .unwrap();
        assert!((second.point(0.0).unwrap() - end).norm() < 1e-9);
        b.nurbs(1, &first, 50_000.0);
        b.nurbs(2, &second, 50_000.0);
        let cfg = b.cfg();
        b.g.activate(&cfg, &mut b.axes, &mut b.filters, TS, 1, &mut b.out);
        b.events();
        let mut handed = None;
        let mut min_v = f64::INFINITY;
        let mut ticks = 0;
        while b.g.active.is_some() {
            b.g.feed(&cfg, &b.axes, TS, 7, &mut b.out);
            ticks += 1;
            if handed.is_none() && b.pushed(EventKind::GroupMotionDone, 1) {
                handed = Some(ticks);
                assert_eq!(b.g.active.as_ref().unwrap().mv.seq, 2);
                assert_eq!(b.g.queue.len(), 0);
            }
            if let (Some(_), Some(act)) = (handed, b.g.active.as_ref()) {
                if act.s < 0.5 * act.mv.geom.len() {
                    min_v = min_v.min(act.v);
                }
            }
            assert!(ticks < 100_000);
        }
        assert!(handed.is_some());
        // At cruise through the joint: the feed stays at its command.
        assert!(
            min_v > 0.999 * 50_000.0,
            "the feed dropped to {min_v} at the joint"
        );
        let last = second.point(second.domain().1).unwrap();
        assert_eq!(b.g.final_seq, Some(2));
        assert!((b.g.queue_end[0] - last[0]).abs() < 1e-6);
        assert!((b.g.queue_end[1] - last[1]).abs() < 1e-6);
    }
}
