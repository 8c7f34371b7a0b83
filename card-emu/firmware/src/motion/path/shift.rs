//! Time-shifted blending (Thinh 2014 Fig 10; [`Transition::TimeShift`]): a chain of lines, each
//! run as its own rest-to-rest S-curve (Thinh eq 1–28), the next one started while the one
//! before decelerates, so that their displacements add up. Where the geometric blend of the
//! module doc replaces the corner by a curve run at a planned speed, this one is a sum of two
//! point-to-point moves; it is the paper's behaviour, kept to show and compare.
//!
//! **Limits.** Each profile runs at its feed, within every axis's velocity limit, and at half of
//! every axis's acceleration and jerk limits along its own direction, so that the two
//! overlapping profiles never add up beyond an axis's acceleration or jerk. Their velocities
//! can: the overlap is chosen so that they do not.
//!
//! **Overlap.** When the segment after the newest profile is known, its start is chosen: at
//! most the previous profile's deceleration and its own acceleration overlap, and as much of
//! that as keeps every sampled point of the overlap within the axis velocity limits and within
//! the tolerance (× [`DEV_SAFETY`]) of the two programmed lines. Nothing overlaps with a
//! tolerance of 0, after a halt, or when the segment comes too late (the previous profile has
//! then ended, and the next starts from rest).
//!
//! **Stops.** A halt brakes each running profile along its own line within its own limits
//! (their sum stays within the axis limits), and the chain stays there until `clear`. A feed
//! hold (override 0) does the same and, when the override comes back, runs what is left of
//! each segment as a rest-to-rest profile, one after the other. Other override values do not
//! change a chain: its profiles are planned at the programmed feed.

use super::{Path, PathEvent, Transition, DEV_SAFETY};
use crate::math;
use crate::motion::path::geom::{dist_to_chord, Prog, V};
use crate::motion::scurve::{plan_stop, Limits, PlanError, Profile};

/// Samples of the overlap checked for the velocity limits and the tolerance.
const OVERLAP_SAMPLES: usize = 24;

/// A running profile of a time-shifted chain.
#[derive(Debug, Clone, Copy)]
pub(super) struct Run {
    /// Absolute index of its segment.
    i: usize,
    prof: Profile,
    /// Arc length of the segment where `prof` starts (0, or where a hold left it).
    base: f64,
    /// Chain-clock time at which `prof` starts.
    t0: f64,
    /// Its acceleration and jerk limits (for a stop).
    acc: f64,
    jerk: f64,
    /// Braking for a halt or a hold: its end is not the segment's end.
    stopping: bool,
    /// Arc length of the last tick.
    last: f64,
}

impl Run {
    fn done(&self, clock: f64) -> bool {
        clock - self.t0 >= self.prof.duration()
    }
    fn s(&self, clock: f64) -> f64 {
        self.base + self.prof.sample(clock - self.t0).pos
    }
}

/// The state of the time-shifted executor.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Chain {
    /// The running profiles, oldest first (at most two overlap).
    runs: [Option<Run>; 2],
    /// Time since the chain started, s.
    clock: f64,
    /// The segment after the newest profile, planned, its `t0` chosen, waiting to start.
    next: Option<Run>,
    /// Stopped by a feed hold, to resume.
    held: bool,
    /// Speed and its change over the last tick (norm of the velocity vector).
    speed: f64,
    accel: f64,
}

impl Chain {
    /// A profile runs (or waits to resume).
    pub(super) fn is_moving(&self) -> bool {
        self.runs.iter().flatten().any(|r| !r.done(self.clock))
    }
    pub(super) fn is_active(&self) -> bool {
        self.runs[0].is_some()
    }
    pub(super) fn speed(&self) -> f64 {
        self.speed
    }
    pub(super) fn accel(&self) -> f64 {
        self.accel
    }
}

impl<const D: usize> Path<D> {
    /// The S-curve limits of a time-shifted line at `feed`: the feed and every axis's velocity
    /// limit in full, half of every axis's acceleration and jerk limits (and the group's
    /// tangential limits, if set).
    fn shift_limits(&self, prog: &Prog<D>, feed: f64) -> Limits {
        let l = &self.lim;
        let t = prog.frame(0.0).t;
        let mut v = feed;
        let mut a = if l.accel > 0.0 { l.accel } else { f64::MAX };
        let mut j = if l.jerk > 0.0 { l.jerk } else { f64::MAX };
        for (k, d) in t[..l.naxes].iter().map(|x| x.abs()).enumerate() {
            if d > 0.0 {
                v = v.min(l.vmax[k] / d);
                a = a.min(0.5 * l.amax[k] / d);
                j = j.min(0.5 * l.jmax[k] / d);
            }
        }
        Limits::symmetric(v, a, j)
    }

    /// The rest-to-rest profile of line `prog` from arc length `base` to its end.
    pub(super) fn shift_profile(
        &self,
        prog: &Prog<D>,
        feed: f64,
        base: f64,
    ) -> Result<(Profile, Limits), PlanError> {
        let lim = self.shift_limits(prog, feed);
        let d = (prog.len() - base).max(0.0);
        Ok((Profile::plan(0.0, d, 0.0, 0.0, &lim)?, lim))
    }

    fn shift_run(&self, i: usize, base: f64, t0: f64) -> Option<Run> {
        let sg = self.seg(i);
        let (prof, lim) = self.shift_profile(&sg.prog, sg.feed, base).ok()?;
        Some(Run {
            i,
            prof,
            base,
            t0,
            acc: lim.amax,
            jerk: lim.j1,
            stopping: false,
            last: base,
        })
    }

    /// The start (chain clock) of run `b`, the segment after run `a`.
    fn shift_start(&self, a: &Run, b: &Run, tol: f64) -> f64 {
        let ta = a.prof.duration();
        let end = a.t0 + ta;
        let (pa, pb) = (a.prof.phases(), b.prof.phases());
        let most = (end - self.chain.clock)
            .min(pa[4] + pa[5] + pa[6])
            .min(pb[0] + pb[1] + pb[2]);
        if !(most > 0.0 && tol > 0.0) || a.stopping {
            return end.max(self.chain.clock);
        }
        let n = self.lim.naxes;
        let (sa, sb) = (self.seg(a.i), self.seg(b.i));
        let (la, da, db) = (sa.prog.len(), sa.prog.frame(0.0).t, sb.prog.frame(0.0).t);
        let (a0, corner, b1) = (sa.prog.pos(0.0), sa.prog.end(), sb.prog.end());
        let vmax = self.lim.vmax;
        // at time `tau` into the overlap `delta`: the distances to the two lines, or None past
        // a velocity limit
        let at = |delta: f64, tau: f64| -> Option<(f64, f64)> {
            let xa = a.prof.sample(ta - delta + tau);
            let xb = b.prof.sample(tau);
            let left = la - a.base - xa.pos;
            let mut p: V<D> = [0.0; D];
            for k in 0..n {
                p[k] = corner[k] - da[k] * left + db[k] * (xb.pos + b.base);
                if (da[k] * xa.vel + db[k] * xb.vel).abs() > vmax[k] {
                    return None;
                }
            }
            Some((
                dist_to_chord(n, &p, &a0, &corner),
                dist_to_chord(n, &p, &corner, &b1),
            ))
        };
        // the overlap `delta` keeps the limits and the tolerance: at the samples, and where
        // the nearer line changes (the deviation has a kink there)
        let within = |delta: f64| -> Option<()> {
            let mut dev: f64 = 0.0;
            let mut prev: Option<(f64, f64)> = None;
            for m in 0..=OVERLAP_SAMPLES {
                let tau = delta * m as f64 / OVERLAP_SAMPLES as f64;
                let (d1, d2) = at(delta, tau)?;
                dev = dev.max(d1.min(d2));
                if let Some((t0, s0)) = prev.filter(|&(_, s0)| (s0 > 0.0) != (d1 > d2)) {
                    let (mut lo, mut hi) = (t0, tau);
                    for _ in 0..30 {
                        let mid = 0.5 * (lo + hi);
                        let (e1, e2) = at(delta, mid)?;
                        dev = dev.max(e1.min(e2));
                        if ((e1 - e2) > 0.0) == (s0 > 0.0) {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                }
                if dev > DEV_SAFETY * tol {
                    return None;
                }
                prev = Some((tau, d1 - d2));
            }
            Some(())
        };
        let mut lo = 0.0;
        if within(most).is_some() {
            lo = most;
        } else {
            let mut hi = most;
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                match within(mid) {
                    Some(()) => lo = mid,
                    None => hi = mid,
                }
                if hi - lo <= 1e-9 * most {
                    break;
                }
            }
        }
        (end - lo).max(self.chain.clock)
    }

    /// Brakes every running profile along its own line within `decel` and `jerk` (a halt, or
    /// a hold), or within its own limits where that stops it sooner. A stop that would run
    /// past the segment's end keeps the profile, which is braking for that end already.
    pub(super) fn shift_stop(&mut self, decel: f64, jerk: f64) {
        let clock = self.chain.clock;
        for r in self.chain.runs.iter_mut().flatten() {
            r.stopping = true;
            let st = r.prof.sample(clock - r.t0);
            // the motion frame is positive: a negative acceleration is a deceleration
            let d = if decel > 0.0 { decel.min(r.acc) } else { r.acc }.max(-st.acc);
            let j = if jerk > 0.0 { jerk.min(r.jerk) } else { r.jerk };
            match plan_stop(st.pos, st.vel, st.acc, d, j) {
                Ok(p) if p.end_pos() < r.prof.end_pos() => {
                    r.prof = p;
                    r.t0 = clock;
                }
                _ => {}
            }
        }
        self.chain.next = None;
    }

    /// After a hold: what is left of each segment, from rest, one after the other.
    fn shift_resume(&mut self) {
        let mut t = self.chain.clock;
        for k in 0..2 {
            if let Some(r) = self.chain.runs[k] {
                let s = r.s(self.chain.clock);
                if let Some(nr) = self.shift_run(r.i, s, t) {
                    t += nr.prof.duration();
                    self.chain.runs[k] = Some(Run { last: s, ..nr });
                }
            }
        }
        self.chain.held = false;
        self.chain.next = None;
    }

    /// Drops the chain's state (a clear or a reset).
    pub(super) fn shift_clear(&mut self) {
        self.chain = Chain::default();
    }

    /// One tick with the executor in a time-shifted chain (its segment is one of the lines).
    pub(super) fn shift_tick(&mut self, ovr: f64, ev: &mut impl FnMut(PathEvent)) -> V<D> {
        let ts = self.lim.ts;
        let (held, moving) = (self.chain.held, self.chain.is_moving());
        if ovr <= 0.0 && !held && moving {
            self.shift_stop(f64::MAX, f64::MAX);
            self.chain.held = true;
        } else if ovr > 0.0 && held && !self.halted && !moving {
            self.shift_resume();
        }
        if self.chain.runs[0].is_none() {
            if self.halted || ovr <= 0.0 {
                return self.pos;
            }
            if !self.started {
                self.start_seg(ev);
            }
            self.chain = Chain::default();
            match self.shift_run(self.exec, 0.0, 0.0) {
                Some(r) => self.chain.runs[0] = Some(r),
                None => return self.pos,
            }
        }
        self.chain.clock += ts;
        let clock = self.chain.clock;
        // the next segment starts when its overlap says
        let free = self.chain.runs[1].is_none();
        if let (true, Some(r)) = (free, self.chain.runs[0]) {
            let j = r.i + 1;
            if !self.halted
                && !self.chain.held
                && !r.stopping
                && j < self.tail
                && self.seg(j).shift_join
            {
                if self.chain.next.is_none() {
                    let tol = match self.seg(j).transition {
                        Transition::TimeShift(t) => t,
                        _ => 0.0,
                    };
                    self.chain.next = self.shift_run(j, 0.0, 0.0).map(|b| Run {
                        t0: self.shift_start(&r, &b, tol),
                        ..b
                    });
                }
                if let Some(b) = self.chain.next.filter(|b| clock >= b.t0) {
                    self.chain.runs[1] = Some(b);
                    self.chain.next = None;
                    self.open_seg(j, ev);
                }
            }
        }
        // the sum of the displacements, the distance and the outputs along the way
        let n = self.lim.naxes;
        let mut p = self.pos;
        let mut vel = [0.0; D];
        for k in 0..2 {
            let Some(mut r) = self.chain.runs[k] else {
                continue;
            };
            let sg = *self.seg(r.i);
            let st = r.prof.sample(clock - r.t0);
            let s = r.base + st.pos;
            let t = sg.prog.frame(0.0).t;
            if k == 0 {
                p = sg.prog.pos(s);
            } else {
                let (q, q0) = (sg.prog.pos(s), sg.prog.pos(0.0));
                for x in 0..n {
                    p[x] += q[x] - q0[x];
                }
            }
            for x in 0..n {
                vel[x] += t[x] * st.vel;
            }
            self.distance += (s - r.last).max(0.0);
            r.last = s;
            self.chain.runs[k] = Some(r);
            if sg.nouts > 0 {
                let sl = self.slot(r.i);
                let f = self.fire_outputs(r.i, 2, s, ev);
                self.segs[sl].fired = f;
            }
        }
        let speed = math::sqrt(vel[..n].iter().map(|v| v * v).sum::<f64>());
        self.chain.accel = (speed - self.chain.speed) / ts;
        self.chain.speed = speed;
        self.pos = p;
        // the oldest segment ends
        if let Some(r) = self.chain.runs[0] {
            if !r.stopping && r.done(clock) {
                self.end_seg(r.i, ev);
                self.exec += 1;
                self.chain.runs[0] = self.chain.runs[1].take();
                if self.chain.runs[0].is_none() {
                    self.started = false;
                    self.s = 0.0;
                    self.in_blend = false;
                    self.chain = Chain::default();
                    if self.exec >= self.tail && !self.idle_sent {
                        self.idle_sent = true;
                        ev(PathEvent::Idle);
                    }
                }
            } else if self.chain.runs[1].is_none()
                && !r.stopping
                && r.i + 1 >= self.tail
                && !self.seg(r.i).last
                && !self.starving_sent
                && clock - r.t0
                    >= r.prof.duration() - {
                        let ph = r.prof.phases();
                        ph[4] + ph[5] + ph[6]
                    }
            {
                // braking at the end of what is queued
                self.starving_sent = true;
                ev(PathEvent::Starving);
            }
        }
        self.pos
    }
}

#[cfg(test)]
impl<const D: usize> Path<D> {
    /// How long the newer of two running profiles has run.
    pub(super) fn chain_overlap(&self) -> Option<f64> {
        let r = self.chain.runs[1]?;
        (!r.stopping).then_some(self.chain.clock - r.t0)
    }
}
