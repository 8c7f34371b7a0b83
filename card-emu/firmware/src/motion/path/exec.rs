//! The executor of the continuous path: halts and clears, the look-ahead's walk over the
//! pieces ahead, and the tick that advances along them with the segment events and outputs on
//! the way (see the module doc of `path`).

use super::*;
use crate::math;

/// The braking envelope of one look-ahead pass: a piece of cap c whose start is d ahead can
/// need the planner to slow for it only if c² + 2·D·(d − step) < θ (D the deceleration limit;
/// θ from `look`'s slowing test, see there). Whole blocks are passed with their `kg`/`kf`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Envelope {
    theta: f64,
    dm: f64,
    step: f64,
}

/// How far beyond its reach a look-ahead walk goes (a share of the reach): what it saw then
/// covers the reach of the next ticks too (see [`Seen`]).
const SEEN_BEYOND: f64 = 0.25;

impl Envelope {
    /// Rounding room of the test (the distances are sums of many lengths): relative, far
    /// above their error and far below what would change which pieces are tested.
    const SLACK: f64 = 1e-9;

    /// No piece of cap c (`c2` = c²) starting `d` ahead can need slowing for.
    #[inline(always)]
    fn clears(&self, c2: f64, d: f64) -> bool {
        let lhs = c2 + 2.0 * self.dm * (d - self.step);
        lhs >= self.theta + Self::SLACK * (self.theta.abs() + c2 + 2.0 * self.dm * d.abs())
    }

    /// No piece whose c² + 2·D·d (d ≥ 0 its distance from here) is `low` or more can need
    /// slowing for: `clears` for every such piece, since its test is monotone in c² + 2·D·d
    /// (with room for the rounding of distances found from positions as far as `far` along
    /// the whole path).
    #[inline(always)]
    pub(super) fn clears_all(&self, low: f64, far: f64) -> bool {
        let room = Self::SLACK * (self.theta.abs() + 2.0 * self.dm * far);
        low * (1.0 - Self::SLACK) >= self.theta + room + 2.0 * self.dm * self.step
    }

    /// A lower bound of c_k² + 2·D·x_k over the pieces k of block `b` (x_k from the block's
    /// start): min(1, D/A_t)·min(kg, min(1, ovr²)·kf) (a feed cap is scaled by the override;
    /// A_t is the rate the keys were made with). No piece of the block, which starts d ahead,
    /// can need slowing for when `clears(low, d)`: every piece k starts at d + x_k or later.
    #[inline(always)]
    fn block_low(&self, b: &Block, ovr: f64, at: f64) -> f64 {
        (self.dm / at).min(1.0) * b.kg.min((ovr * ovr).min(1.0) * b.kf)
    }
}

/// What a look-ahead walk passed without an exact test, kept for the ticks after it
/// (`Path::seen`): every piece starting less than `extent` ahead of where the walk started was
/// passed, either because its cap was not below the tick's speed bound (the smallest such cap:
/// `cap`) or because it cleared the braking envelope (the smallest c² + 2·D·d, d from there:
/// `key`). While the speed bound stays at most `cap`, the keys still clear the envelope from
/// where the executor is, and the reach ends before `extent`, the walk would pass the same
/// pieces the same way and find nothing to slow for: `look` skips it. Dropped when a push or
/// a late cap changes a segment it saw (`Path::window_changed`), and on halt, clear, reset.
#[derive(Debug, Clone, Copy)]
pub(super) struct Seen {
    cap: f64,
    key: f64,
    extent: f64,
    /// Where the walk started along the whole path (`Path::exec_dist`).
    from: f64,
    /// The first segment it did not see.
    end: usize,
    /// The override and the planner's deceleration and jerk limits it was made with.
    ovr: f64,
    dm: f64,
    jm: f64,
    /// The pieces it tested and found safe, each with the slowing distance in closed form
    /// (`PathSpeedPlanner::slowing_estimate`): the least room between a piece and its
    /// slowing distance (∞: none tested), the highest cap among them, and the descent split
    /// (V, I) and step of the state they were tested from. From a state of the same descent
    /// with V no higher, a piece's slowing distance is I + D_V(cap), D_V growing with V at
    /// V/(2D) at least: it has grown by at most ΔI − (V₀ − V)·V/(2D) since.
    room: f64,
    cap_tested: f64,
    split: (f64, f64),
    step: f64,
    /// Where the executor was when `room`, `split` and `step` were found (where the walk
    /// started, or a later tick that tested the pieces again).
    room_from: f64,
    /// Where (along the whole path) the first piece starts whose tangential limits are below
    /// those the executor ramps with (∞: none within `extent`): a tick whose near reach gets
    /// there walks again.
    drop: f64,
    /// The pieces tested, when there were at most [`TESTED`]: when `room` no longer covers
    /// what their slowing distances can have grown, a tick tests again those it no longer
    /// covers instead of walking (`still_safe`; the pieces passed by their caps or by the
    /// envelope are covered by `cap` and `key` as before).
    tested: Tested,
}

/// The planning step being run (`Path::step`). The look-ahead and the speed planner run once
/// every `plan_ticks` servo ticks (the planner's period); every tick of the step moves the
/// executor to where the step's own profile is at that tick (`PathSpeedPlanner::sample_step`:
/// the jerk-limited profile the planner chose, integrated exactly), so the commanded positions
/// are those of that profile at the servo rate, not an interpolation between planned points.
/// A step that comes to rest ends at the tick it lands.
#[derive(Debug, Clone, Copy)]
pub(super) struct Step {
    /// Ticks of it run, and how many it lasts (`done == ticks`: none is running).
    done: usize,
    ticks: usize,
    /// Its distance (the planner's step, clamped to a stop point), and what the executor
    /// has moved of it.
    ds: f64,
    moved: f64,
    /// It ends on the stop point the look-ahead found (at its last tick).
    land: bool,
    /// It comes to rest on a pause point (at its last tick: see `pause`).
    pub(super) rest: bool,
    /// The look-ahead window's end, and the queue's when it was planned: a segment pushed
    /// since may have joined the stop point to what follows (then the last tick moves the
    /// step's distance, not on to the next stop point).
    wend: usize,
    tail: usize,
}

impl Step {
    pub(super) const NONE: Step = Step {
        done: 0,
        ticks: 0,
        ds: 0.0,
        moved: 0.0,
        land: false,
        rest: false,
        wend: 0,
        tail: 0,
    };

    #[inline(always)]
    pub(super) fn running(&self) -> bool {
        self.done < self.ticks
    }

    /// What the executor has still to move in it.
    #[inline(always)]
    pub(super) fn ahead(&self) -> f64 {
        if self.running() {
            (self.ds - self.moved).max(0.0)
        } else {
            0.0
        }
    }
}

/// A slowing to less than this share of the speed is decided at the servo rate (see
/// `Path::tick_plan`).
const FINE_SLOWING: f64 = 0.5;

/// Ticks held at rest on an exact stop before the next segment starts. A stop lands within
/// its last tick with up to a tick's jerk of acceleration left, and the next segment started
/// at once, the other way where the corner turns back: the positions' third differences
/// mixed the two (with a start ramped within the limits of the line before, 2.7 times an
/// axis's jerk limit, in a random streamed program whose near-reversal became an exact stop).
/// Two ticks at rest keep the landing's and the start's out of any one difference. (A dwell
/// holds at rest itself.)
const STOP_SETTLE_TICKS: u8 = 2;

/// A slowing that reaches its speed more than this many ticks at that speed before its piece
/// lets go and is decided again (see `Path::look`).
const CRAWL_TICKS: f64 = 64.0;

/// Most pieces a [`Seen`] keeps to test again.
const TESTED: usize = 32;

/// The pieces a walk tested and found safe (see [`Seen::tested`]): where each starts along
/// the whole path, its cap and its room (as [`Seen::room`], from the same state); `n` >
/// [`TESTED`]: more than it keeps.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tested {
    at: [(f64, f64, f64); TESTED],
    n: usize,
}

impl Tested {
    const NONE: Tested = Tested {
        at: [(0.0, 0.0, 0.0); TESTED],
        n: 0,
    };

    #[inline(always)]
    fn push(&mut self, start: f64, cap: f64, room: f64) {
        if self.n < TESTED {
            self.at[self.n] = (start, cap, room);
        }
        self.n += 1;
    }
}

impl Seen {
    /// Whether every piece the walk tested is still at least its slowing distance away from
    /// this tick's state (`state` as [`retest`] takes it; the executor at `at`). The bound of
    /// [`room`](Self::room) decides when it covers what the slowing distances can have grown;
    /// else, when the walk kept its tested pieces, those whose own room the bound no longer
    /// covers are tested again, the others' rooms lowered by the bound, and this tick becomes
    /// the state the rooms are counted from. (On false the rooms may be left half updated:
    /// the walk that follows replaces what was seen.)
    #[inline(always)]
    fn still_safe(
        &mut self,
        pl: &PathSpeedPlanner,
        state: (f64, f64, f64, f64, f64),
        at: f64,
    ) -> Safe {
        if self.room == f64::INFINITY {
            return Safe::Bound;
        }
        let (vn, an, _, dm, step) = state;
        let moved = at - self.room_from;
        let (big, part) = pl.descent_split(vn, an);
        let (big0, part0) = self.split;
        let grown = moved + (step - self.step) + (part - part0) - (big0 - big) * big / (2.0 * dm);
        let slack = 1e-9 * (moved.abs() + part.abs() + part0.abs()) + 1e-9 * big0 * big0 / dm;
        let same_descent = pl.descent_holds(vn, an, self.cap_tested) && big <= big0;
        if same_descent && grown + slack <= self.room {
            return Safe::Bound;
        }
        if self.tested.n > TESTED {
            return Safe::No;
        }
        let mut least = f64::INFINITY;
        for (start, cap, room) in self.tested.at[..self.tested.n].iter_mut() {
            *room = if same_descent && grown + slack <= *room {
                *room - (grown + slack)
            } else {
                match retest(pl, state, at, *start, *cap) {
                    Some(r) => r,
                    None => return Safe::No,
                }
            };
            least = lesser(least, *room);
        }
        self.room = least;
        self.room_from = at;
        self.split = (big, part);
        self.step = step;
        Safe::Retested
    }
}

/// What [`Seen::still_safe`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Safe {
    No,
    /// By the bound of [`Seen::room`].
    Bound,
    /// By testing again the pieces the bound no longer covered.
    Retested,
}

/// The pieces a walk passed by their caps or by the envelope (see [`Seen`]): smallest cap,
/// smallest c² + 2·D·d.
#[derive(Debug, Clone, Copy)]
pub(super) struct Passed {
    cap: f64,
    key: f64,
}

impl Passed {
    pub(super) const NONE: Passed = Passed {
        cap: f64::INFINITY,
        key: f64::INFINITY,
    };
}

/// Where a walk ended: the stop found (Some(is the end of the queue)) or None, its distance,
/// and the first segment not walked.
#[derive(Debug, Clone, Copy)]
pub(super) struct Walked {
    pub stop: Option<bool>,
    pub d: f64,
    pub end: usize,
    /// The lowest tangential limits of the pieces it walked (the executor's included), of
    /// those that start within the `near` distance it was given, and where (from here) the
    /// first piece beyond that starts whose limits are below those (∞: none it saw).
    pub lim: Lim,
    pub near: Lim,
    pub drop: f64,
}

/// The tangential limits a walk meets (see [`Walked`]).
#[derive(Debug, Clone, Copy)]
struct Meets {
    near_at: f64,
    lim: Lim,
    near: Lim,
    drop: f64,
}

impl Meets {
    /// A piece (or a block of them) of limits `l` starting `d` ahead.
    #[inline(always)]
    fn meet(&mut self, d: f64, l: Lim) {
        self.lim = self.lim.min(l);
        if d <= self.near_at {
            self.near = self.near.min(l);
        } else if self.drop == f64::INFINITY && l.below(self.near) {
            self.drop = d;
        }
    }
}

/// The room a piece of cap `cap` that starts at `start` along the whole path has beyond its
/// slowing distance from the planner's state of this tick (`state`: the speed and
/// acceleration after this tick's step, the speed where the acceleration would be 0, the
/// deceleration limit and the step), the executor being at `at`; None when the walk's
/// test of that piece could find it violated: when the piece is nearer than the lower
/// bound of that distance or than its closed form (`look`'s test, with the rounding of a
/// distance found from positions along the whole path instead of summed from here).
#[inline(always)]
fn retest(
    pl: &PathSpeedPlanner,
    (vn, an, vf, dm, step): (f64, f64, f64, f64, f64),
    at: f64,
    start: f64,
    cap: f64,
) -> Option<f64> {
    let dist = start - at - step;
    let rounding = 1e-10 * (start.abs() + at.abs());
    let lower = (vf * vf - cap * cap) / (2.0 * dm);
    if dist < lower + rounding {
        return None;
    }
    let (e, size) = pl.slowing_estimate(vn, an, cap)?;
    let r = dist - e - 1e-9 * (size + dist.abs()) - rounding;
    (r >= 0.0).then_some(r)
}

/// The lesser and the greater of two numbers that are not NaN (the look-ahead's figures are
/// finite or ∞): one comparison, not `f64::min`'s and `max`'s handling of NaN.
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// What a walk does with each piece it does not pass whole (see `Path::walk`).
pub(super) trait Visit {
    /// A piece of cap `cap` that starts `d` ahead.
    fn visit(&mut self, d: f64, cap: f64);
}

/// A walk that only looks for the next stop (`Path::halt`).
pub(super) struct NoVisit;

impl Visit for NoVisit {
    #[inline(always)]
    fn visit(&mut self, _: f64, _: f64) {}
}

/// `look`'s test of each piece a walk meets, with what the walk passed and found: the pieces
/// passed by their caps or by the envelope (`passed`), the first violated one (`worst`), and
/// those tested safe with the closed form (least room, highest cap, the pieces; `untracked`:
/// a piece neither passed nor tested so, after which nothing is kept for the next ticks). A
/// type with a method rather than a closure so that it is built into the walk (in either of
/// the engine's builds, see `v3.rs`).
struct Consider<'a> {
    vmax: f64,
    target: f64,
    env: Envelope,
    jm: f64,
    vf: f64,
    rising: f64,
    pl: &'a PathSpeedPlanner,
    vn: f64,
    an: f64,
    here: f64,
    at: f64,
    worst: Option<(f64, f64)>,
    passed: Passed,
    room: f64,
    cap_tested: f64,
    untracked: bool,
    tested: Tested,
}

impl Visit for Consider<'_> {
    #[inline(always)]
    fn visit(&mut self, d: f64, raw: f64) {
        let (env, dm, step) = (self.env, self.env.dm, self.env.step);
        if !(raw < self.vmax && raw < self.target) {
            self.passed.cap = lesser(self.passed.cap, raw);
        } else if self.worst.is_some_and(|(_, c)| raw >= c) {
            self.untracked = true;
        } else if env.clears(raw * raw, d) {
            self.passed.key = lesser(self.passed.key, raw * raw + 2.0 * dm * d);
        } else {
            let (vf, jm, pl, vn, an) = (self.vf, self.jm, self.pl, self.vn, self.an);
            let dist = d - step;
            let lower = (vf * vf - raw * raw) / (2.0 * dm);
            let upper = self.rising + 0.5 * (vf + raw) * ((vf - raw) / dm + dm / jm);
            // the closed form, and the room it leaves beyond its rounding
            let clear = pl
                .slowing_estimate(vn, an, raw)
                .map(|(e, size)| dist - e - 1e-9 * (size + dist.abs()));
            let violated = dist < lower
                || (dist < upper
                    && match clear {
                        Some(r) if r >= 0.0 => false,
                        _ => dist < pl.slowing_distance_from(vn, an, raw),
                    });
            if violated {
                self.worst = Some((self.here + d, raw));
            }
            match clear {
                Some(r) if r >= 0.0 => {
                    self.room = lesser(self.room, r);
                    self.cap_tested = greater(self.cap_tested, raw);
                    self.tested.push(self.at + d, raw, r);
                }
                _ => self.untracked = true,
            }
        }
    }
}

impl<const D: usize> Path<D> {
    /// Where the executor is along the whole path (the `start` of segments ahead minus this
    /// is the distance to them).
    #[inline(always)]
    pub(super) fn exec_dist(&self) -> f64 {
        let sg = self.seg(self.exec);
        if self.in_blend {
            sg.start + self.s
        } else {
            let blend = if sg.has_blend { sg.blend.len } else { 0.0 };
            sg.start + blend + (self.s - sg.body0)
        }
    }

    /// Whether a test asked for the look-ahead to walk on every tick (see `look`).
    fn walks_every_tick(&self) -> bool {
        #[cfg(test)]
        return self.walk_every_tick;
        #[cfg(not(test))]
        false
    }

    /// Segment `i` changed (its caps or its length): what a walk saw of it is dropped.
    #[inline(always)]
    pub(super) fn window_changed(&mut self, i: usize) {
        if self.seen.is_some_and(|w| i < w.end) {
            self.seen = None;
        }
    }

    /// Comes to rest along the path as fast as `decel` and `jerk` allow (clamped to the
    /// tangential limits, and never below what the current deceleration needs), then stays;
    /// the queue stays until [`clear`](Self::clear). If that stop would run past the next exact
    /// stop or the end of the queue, the path's own limits are kept (it is braking for that
    /// point already).
    pub fn halt(&mut self, decel: f64, jerk: f64) {
        if !self.ready {
            return;
        }
        self.halted = true;
        self.pause = super::pause::Pause::Off;
        if self.step.running() {
            // the stop starts now, not at the end of the step being run
            self.planner.cut_at(self.now.0, self.now.1);
            self.step = Step::NONE;
        }
        let pl = self.planner;
        let d = if pos_finite(decel) {
            decel.min(self.at)
        } else {
            self.at
        };
        let j = if pos_finite(jerk) {
            jerk.min(self.jt)
        } else {
            self.jt
        };
        let d = d.max(-pl.a).min(self.at);
        if self.chain.is_active() {
            self.shift_stop(decel, jerk);
            return;
        }
        if self.exec >= self.tail {
            return;
        }
        let need =
            1.05 * PathSpeedPlanner::stopping_distance(pl.v, pl.a, d, j) + 4.0 * pl.v * self.tsp;
        let wend = self.tail;
        let mut none = Passed::NONE;
        let w = self.walk((need, 0.0), 0.0, 0.0, wend, None, &mut none, &mut NoVisit);
        self.seen = None;
        if w.stop.is_none() || w.d >= need {
            // (within every piece's: the curved pieces' shares are the lowest limits)
            self.planner.set_limits(d, j, f64::INFINITY, f64::INFINITY);
            self.halt_lim = true;
        }
    }

    /// Only at rest: drops every segment not finished (ids reported in order) and the pending
    /// outputs, keeps the position, ends a halt.
    pub fn clear(&mut self, aborted: &mut impl FnMut(u32)) -> Result<(), PathError> {
        if self.is_moving() {
            return Err(PathError::Moving);
        }
        if self.exec < self.tail {
            // the next segment starts where the executor is
            self.end_dist = self.exec_dist();
        }
        self.seen = None;
        let first = self.exec - usize::from(self.prev_open);
        for i in first..self.tail {
            if i == first || !self.seg(i).cont {
                aborted(self.seg(i).id);
            }
        }
        self.exec = self.tail;
        self.prev_open = false;
        self.in_blend = false;
        self.s = 0.0;
        self.started = false;
        self.last_end = self.pos;
        self.npending = 0;
        self.halted = false;
        self.pause = super::pause::Pause::Off;
        self.slow = None;
        self.planner
            .set_limits(self.at, self.jt, f64::INFINITY, f64::INFINITY);
        self.dec = Lim {
            a: self.at,
            j: self.jt,
        };
        self.near = self.dec;
        self.halt_lim = false;
        self.rest();
        self.idle_sent = true;
        self.cap_due = None;
        self.shift_clear();
        Ok(())
    }

    /// [`walk`](Self::walk)'s body (which `v3.rs` builds twice): walks the pieces ahead of
    /// the executor up to distance `until` (or the window end
    /// `wend`), calling `f.visit(distance to the piece's start, cap)` for each piece whose cap may
    /// be below `below` (blocks that have none, or none that `env` says can need slowing
    /// for, are skipped; what they held goes into `passed`). Returns the stop found
    /// (Some(is the end of the queue)) and its distance, or None and a distance beyond
    /// `until`, and the first segment not walked.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn walk_impl(
        &self,
        (until, near): (f64, f64),
        below: f64,
        ovr: f64,
        wend: usize,
        env: Option<Envelope>,
        passed: &mut Passed,
        f: &mut impl Visit,
    ) -> Walked {
        let e = self.exec;
        let sg = self.seg(e);
        let here = if self.in_blend { sg.jlim } else { sg.blim };
        let mut m = Meets {
            near_at: near,
            lim: here,
            near: here,
            drop: f64::INFINITY,
        };
        let mut d = if self.in_blend {
            let d = sg.blend.len - self.s;
            f.visit(d, lesser(sg.bgeo, sg.feed * ovr));
            m.meet(d, sg.blim);
            d + (sg.body1 - sg.body0)
        } else {
            sg.body1 - self.s
        };
        let walked = |stop, d, end, m: Meets| Walked {
            stop,
            d,
            end,
            lim: m.lim,
            near: m.near,
            drop: m.drop,
        };
        let mut j = e + 1;
        // j's slot, followed along instead of a division per segment (the ring's length is a
        // multiple of BLOCK, so a block's first slot is a multiple of BLOCK too)
        let ring = self.segs.len();
        let mut sl = self.slot(j);
        loop {
            if j >= wend {
                if j >= self.tail && !self.seg(self.tail - 1).last {
                    // what a push adds at the end of the queue can have the lowest limits
                    // of any piece: a curved one's
                    m.meet(
                        d,
                        Lim {
                            a: self.at,
                            j: self.jt,
                        },
                    );
                }
                return walked(Some(j >= self.tail), d, j, m);
            }
            if d > until {
                return walked(None, d, j, m);
            }
            if j.is_multiple_of(BLOCK) && j + BLOCK <= wend {
                let b = &self.blocks[sl / BLOCK];
                let mut pass = false;
                if !b.stop {
                    let caps = lesser(b.geo, b.feed * ovr);
                    if b.geo >= below && b.feed * ovr >= below {
                        passed.cap = lesser(passed.cap, caps);
                        pass = true;
                    } else if let Some(e) = env {
                        let low = e.block_low(b, ovr, self.at);
                        if low >= 0.0 && e.clears(low, d) {
                            passed.key = lesser(passed.key, low + 2.0 * e.dm * d);
                            pass = true;
                        }
                    }
                }
                if pass {
                    m.meet(d, b.lim);
                    d += b.len;
                    j += BLOCK;
                    sl += BLOCK;
                    if sl >= ring {
                        sl -= ring;
                    }
                    continue;
                }
            }
            let s = &self.segs[sl];
            if s.stop_before {
                return walked(Some(false), d, j, m);
            }
            f.visit(d, lesser(s.jgeo, s.jfeed * ovr));
            m.meet(d, s.jlim);
            if s.has_blend {
                d += s.blend.len;
            }
            f.visit(d, lesser(s.bgeo, s.feed * ovr));
            m.meet(d, s.blim);
            d += s.body1 - s.body0;
            j += 1;
            sl += 1;
            if sl == ring {
                sl = 0;
            }
        }
    }

    /// The planner's target and remaining distance for a step of `ts` (see the module doc;
    /// the slowing test is `nurbs_interp`'s).
    #[inline(always)]
    pub(super) fn look(&mut self, ovr: f64, ts: f64) -> Look {
        let sg = self.seg(self.exec);
        let (cg, cf) = if self.in_blend {
            (sg.jgeo, sg.jfeed)
        } else {
            (sg.bgeo, sg.feed)
        };
        let ceiling = lesser(cg, cf * ovr);
        let here = self.distance;
        if matches!(self.slow, Some((sc, _)) if here >= sc) {
            self.slow = None;
        }
        if let Some((sc, c)) = self.slow {
            // A slowing that has come down to its piece's speed, with no acceleration left,
            // more than `CRAWL_TICKS` at that speed before the piece: let go, so that the walk
            // decides again from here. (It decides with the lowest limits within its reach
            // and ramps with those of the pieces near here: it can get there early, and
            // behind a near-reversal's blend, capped at a few counts a second, the crawl to
            // it took minutes.)
            let pl = &self.planner;
            if pl.v <= c && pl.a.abs() <= 1e-9 * self.at && sc - here > CRAWL_TICKS * c * ts {
                self.slow = None;
            }
        }
        let mut target = match self.slow {
            Some((_, c)) => lesser(ceiling, c),
            None => ceiling,
        };
        if self.halted || ovr <= 0.0 {
            target = 0.0;
        }
        // the look-ahead is by distance: whatever is queued, as far as the walk's reach
        let wend = self.tail;
        let pl = self.planner;
        // where the executor is, for what an earlier walk saw (see `Seen`)
        let at = self.exec_dist();
        let mut out = Look {
            target,
            rem: 0.0,
            stop: false,
            queue_end: false,
            window_end: wend,
            track: None,
            slowed: false,
            dec: self.dec,
            pause: false,
        };
        // The decisions are made with the lowest tangential limits of the pieces the walk
        // looks at (each piece is braked for through those before it, and stops end within
        // them): those of the last walk, lowered and the look made again when this walk
        // meets a lower one. The next step ramps within the lowest of the pieces near here.
        let (slow0, target0) = (self.slow, target);
        let mut dec = if self.halt_lim {
            Lim {
                a: pl.dmax,
                j: pl.jmax,
            }
        } else {
            self.dec
        };
        let mut again = 0;
        // what an earlier walk saw serves this step: the limits stay
        let mut keep = false;
        let mut kept = None;
        let low = Lim {
            a: self.at * (1.0 - crate::motion::path_speed::PLAN_MARGIN),
            j: self.jt * (1.0 - crate::motion::path_speed::PLAN_MARGIN),
        };
        'limits: loop {
            let mut pld = pl;
            pld.set_limits(dec.a, dec.j, f64::INFINITY, f64::INFINITY);
            let (jp, dp) = pld.plan_limits();
            let (jm, dm) = (pld.jmax, pld.dmax);
            let mut met: Option<(Lim, Lim, f64, f64)> = None;
            for it in 0..3 {
                let track = pl.track(target);
                let (step, vn, an) = track.step();
                let ap = greater(an, 0.0);
                let vmax = greater(greater(pl.v, vn), vn + ap * ap / (2.0 * jm));
                // (with a closed-form bound of the braking distance: nothing beyond its reach
                // can need slowing for, the reach of the exact one being shorter; at the
                // lowest limits any piece has, the curved pieces' shares, so that a piece of
                // lower limits is seen as far ahead as braking within them needs)
                let reach =
                    1.05 * PathSpeedPlanner::stopping_distance_bound(
                        vmax,
                        greater(greater(an, pl.a), 0.0),
                        lesser(dp, low.a),
                        lesser(jp, low.j),
                    ) + 4.0 * vmax * ts
                        + 1e-9;
                // where the ramp toward the target ends (a = 0 there), after this step and
                // the next: the next step ramps within the limits of the pieces up to there
                let near = step + pl.track_distance(vn, an, target) + 2.0 * vmax * ts + 1e-9;
                let below = lesser(vmax, target);
                let vf = vn + ap * ap / (2.0 * jm);
                let rising = vf * ap / jm;
                // A piece is violated only if dist < upper (upper ≥ lower), that is
                // raw² + 2·dm·dist < vf² + 2·dm·rising + (vf + raw)·dm²/jm, with raw < vmax:
                // the envelope's θ, with which whole blocks and single pieces are passed
                // cheaply.
                let env = Envelope {
                    theta: vf * vf + greater(2.0 * dm * rising + (vf + vmax) * dm * dm / jm, 0.0),
                    dm,
                    step,
                };
                // the walk goes a little beyond the reach, so that what it saw serves longer,
                // and as far as the ramp's limits are looked for
                let until = greater(reach * (1.0 + SEEN_BEYOND), near);
                if let Some(i) = self.cap_due {
                    if self.seg(i).start - at <= until * (1.0 + Envelope::SLACK) {
                        // the walk can reach the newest blend before a push rebuilt it
                        self.settle_cap(i);
                    }
                }
                if it == 0 && again == 0 {
                    let safe;
                    let every = self.walks_every_tick();
                    if let Some(w) = self.seen.as_mut() {
                        let moved = at - w.from;
                        if w.ovr == ovr
                            && w.dm == dm
                            && w.jm == jm
                            && below <= w.cap
                            && moved + greater(reach, near) < w.extent * (1.0 - Envelope::SLACK)
                            && at + near < w.drop
                            && env.clears_all(w.key - 2.0 * dm * moved, at.abs() + moved.abs())
                            && {
                                safe = w.still_safe(&pld, (vn, an, vf, dm, step), at);
                                safe != Safe::No
                            }
                        {
                            // The walk would pass every piece within the reach as it did
                            // then, and meet no stop point within it: nothing to slow for
                            // (its distance beyond the reach changes nothing the planner
                            // does); and no lower limits near here. (A test that walks on
                            // every tick walks, but keeps the limits as they are: the same
                            // motion.)
                            keep = true;
                            kept = Some(*w);
                            if !every {
                                out.rem = w.extent - moved;
                                out.track = Some(track);
                                #[cfg(test)]
                                if safe == Safe::Retested {
                                    self.retests += 1;
                                }
                                break;
                            }
                        }
                    }
                }
                let mut c = Consider {
                    vmax,
                    target,
                    env,
                    jm,
                    vf,
                    rising,
                    pl: &pld,
                    vn,
                    an,
                    here,
                    at,
                    worst: None,
                    passed: Passed::NONE,
                    room: f64::INFINITY,
                    cap_tested: 0.0,
                    untracked: false,
                    tested: Tested::NONE,
                };
                let mut blocks = Passed::NONE;
                let w = self.walk(
                    (until, near),
                    below,
                    ovr,
                    wend,
                    Some(env),
                    &mut blocks,
                    &mut c,
                );
                met = Some(match met {
                    None => (w.lim, w.near, at + w.drop, near),
                    Some((l, n, d, r)) => (l.min(w.lim), n.min(w.near), d.min(at + w.drop), r),
                });
                if it == 0 {
                    out.rem = w.d;
                    out.stop = w.stop.is_some();
                    out.queue_end = w.stop == Some(true);
                }
                match c.worst {
                    Some((sc, c)) => {
                        self.slow = Some((sc, c));
                        target = target.min(c);
                        self.seen = None;
                        out.slowed = true;
                    }
                    None => {
                        // the planner follows this very step unless it must stop
                        out.track = Some(track);
                        self.seen = (!c.untracked).then_some(Seen {
                            cap: c.passed.cap.min(blocks.cap),
                            key: c.passed.key.min(blocks.key),
                            extent: w.d,
                            from: at,
                            end: w.end,
                            ovr,
                            dm,
                            jm,
                            room: c.room,
                            cap_tested: c.cap_tested,
                            split: pld.descent_split(vn, an),
                            step,
                            room_from: at,
                            tested: c.tested,
                            drop: at + w.drop,
                        });
                        break;
                    }
                }
            }
            out.dec = dec;
            if keep && self.walks_every_tick() {
                // (a test walking every tick: what the earlier walk saw stays, as it does
                // where the walk is skipped)
                self.seen = kept;
            }
            if let Some((lim, near, _, _)) = met {
                if lim.below(dec) && !self.halt_lim && !keep {
                    // a piece with lower limits than the decisions were made with: again
                    // with those (a few times at most; then the lowest of any piece)
                    again += 1;
                    dec = if again < 8 {
                        dec.min(lim)
                    } else {
                        Lim {
                            a: self.at,
                            j: self.jt,
                        }
                    };
                    self.slow = slow0;
                    target = target0;
                    self.seen = None;
                    out.slowed = false;
                    out.track = None;
                    continue 'limits;
                }
                if !self.halt_lim && !keep {
                    // for the next step: the lowest limits ahead (they rise as slower pieces
                    // are passed); and it ramps within those, or, while it still brings an
                    // acceleration made within higher limits back to 0, as high as that needs
                    // (never above those of the pieces it gets to meanwhile)
                    self.dec = lim;
                    let (_, vn, an) = match out.track {
                        Some(t) => t.step(),
                        None => pl.track(target).step(),
                    };
                    let room = if an > 0.0 {
                        target - vn
                    } else if target < vn {
                        vn - target
                    } else {
                        vn
                    };
                    let guard = Lim {
                        a: an.abs(),
                        j: if room > 0.0 {
                            an * an / (2.0 * room)
                        } else {
                            f64::INFINITY
                        },
                    };
                    self.near = near.min(lim.max(guard));
                }
            }
            break;
        }
        out.target = target;
        if let Some(d) = self.pause_dist() {
            // a pause point nearer than the stop the walk found: a stop there
            // (at the stop point the walk found, within rounding, it is that stop)
            let r = greater(d - at, 0.0);
            if r < out.rem - 1e-9 * (d.abs() + 1.0) {
                out.rem = r;
                out.stop = true;
                out.queue_end = false;
                out.pause = true;
            }
        }
        if target == 0.0 {
            // holding or halting: the time-optimal stop from here (re-solved every tick, so
            // it lands with v = a = 0), unless a stop point is nearer
            let (d, j) = (lesser(pl.dmax, out.dec.a), lesser(pl.jmax, out.dec.j));
            let brake = PathSpeedPlanner::stopping_distance(pl.v, pl.a, d, j);
            if brake < out.rem {
                out.rem = brake;
                out.stop = false;
                out.queue_end = false;
            }
        }
        out
    }

    #[inline(always)]
    pub(super) fn fire_outputs(
        &self,
        i: usize,
        which: u8,
        upto: f64,
        ev: &mut impl FnMut(PathEvent),
    ) -> u8 {
        // which: 0 = Start, 1 = End, 2 = Distance ≤ upto (in order of distance)
        let s = self.seg(i);
        let mut fired = s.fired;
        loop {
            let mut best: Option<(usize, f64)> = None;
            for (k, o) in s.outs[..s.nouts].iter().enumerate() {
                if fired & (1 << k) != 0 {
                    continue;
                }
                let key = match (which, o.at) {
                    (0, OutputAt::Start) | (1, OutputAt::End) => 0.0,
                    (2, OutputAt::Distance(d)) if d <= upto => d,
                    _ => continue,
                };
                if best.is_none_or(|(_, b)| key < b) {
                    best = Some((k, key));
                }
            }
            let Some((k, _)) = best else { break };
            fired |= 1 << k;
            let o = s.outs[k];
            ev(PathEvent::Output {
                bit: o.bit,
                on: o.on,
                id: s.id,
            });
        }
        fired
    }

    /// Segment `i` starts: its event, and its outputs at the start.
    pub(super) fn open_seg(&mut self, i: usize, ev: &mut impl FnMut(PathEvent)) {
        let sl = self.slot(i);
        ev(PathEvent::SegmentStart {
            id: self.segs[sl].id,
        });
        let f = self.fire_outputs(i, 0, 0.0, ev);
        self.segs[sl].fired = f;
        let f = self.fire_outputs(i, 2, 0.0, ev);
        self.segs[sl].fired = f;
    }

    #[inline(always)]
    pub(super) fn start_seg(&mut self, ev: &mut impl FnMut(PathEvent)) {
        self.started = true;
        if self.seg(self.exec).cont {
            // the next piece of the curve: the same segment goes on
            return;
        }
        self.seg_travel = 0.0;
        self.open_seg(self.exec, ev);
        self.dwell_left = self.seg(self.exec).dwell_ticks;
    }

    #[inline(always)]
    pub(super) fn end_seg(&mut self, i: usize, ev: &mut impl FnMut(PathEvent)) {
        let sl = self.slot(i);
        if i + 1 < self.tail && self.seg(i + 1).cont {
            // a piece of a curve: its outputs not fired yet go on with the next piece
            let (outs, nouts, fired) = {
                let s = &self.segs[sl];
                (s.outs, s.nouts, s.fired)
            };
            let nx = self.slot(i + 1);
            let next = &mut self.segs[nx];
            next.outs = outs;
            next.nouts = nouts;
            next.fired = fired;
            return;
        }
        let f = self.fire_outputs(i, 2, f64::INFINITY, ev);
        self.segs[sl].fired = f;
        ev(PathEvent::SegmentEnd {
            id: self.segs[sl].id,
        });
        let f = self.fire_outputs(i, 1, 0.0, ev);
        self.segs[sl].fired = f;
    }

    /// Travel of the open segment: Distance outputs crossed.
    #[inline(always)]
    pub(super) fn travel(&mut self, step: f64, ev: &mut impl FnMut(PathEvent)) {
        if step <= 0.0 {
            return;
        }
        self.seg_travel += step;
        let i = self.exec - usize::from(self.prev_open);
        let sl = self.slot(i);
        if self.segs[sl].nouts > 0 {
            let f = self.fire_outputs(i, 2, self.seg_travel, ev);
            self.segs[sl].fired = f;
        }
    }

    /// Moves the executor `ds` along the path (or, when `land`, exactly to the stop point the
    /// look-ahead found), with the events on the way; when `hold` (a tick of a planning step
    /// before its last), not past a stop point (the step's last tick lands there or goes on).
    #[inline(always)]
    pub(super) fn advance(
        &mut self,
        ds: f64,
        land: bool,
        hold: bool,
        wend: usize,
        resting: bool,
        ev: &mut impl FnMut(PathEvent),
    ) {
        let mut left = if land { f64::INFINITY } else { ds };
        if !self.started && !self.in_blend && self.exec < self.tail && (ds > 0.0 || land) {
            self.start_seg(ev);
        }
        for _ in 0..4 * self.segs.len() + 8 {
            if self.exec >= self.tail {
                return;
            }
            // the few fields needed, not a copy of the whole segment (it holds two quintics)
            let sg = self.seg(self.exec);
            if sg.is_dwell() {
                return;
            }
            let (blend_len, body0, end) = (sg.blend.len, sg.body0, sg.body1);
            if self.in_blend {
                let len = blend_len;
                if self.prev_open {
                    let mid = 0.5 * len;
                    if self.s + left >= mid {
                        let step = (mid - self.s).max(0.0);
                        self.travel(step, ev);
                        left -= step;
                        self.s = mid;
                        self.end_seg(self.exec - 1, ev);
                        self.prev_open = false;
                        self.start_seg(ev);
                    } else {
                        self.s += left;
                        self.travel(left, ev);
                        return;
                    }
                }
                let step = (len - self.s).max(0.0).min(left);
                self.s += step;
                self.travel(step, ev);
                left -= step;
                if self.s >= len {
                    self.in_blend = false;
                    self.s = body0;
                    continue;
                }
                return;
            }
            let step = (end - self.s).max(0.0).min(left);
            self.s += step;
            self.travel(step, ev);
            left -= step;
            if self.s < end {
                return;
            }
            self.s = end;
            let next = self.exec + 1;
            if next >= self.tail {
                if resting {
                    self.pos = self.seg(self.exec).prog.pos(end);
                    self.end_seg(self.exec, ev);
                    self.exec = next;
                    self.started = false;
                }
                return;
            }
            let ns = self.seg(next);
            let (ns_stop, ns_blend, ns_body0) = (ns.stop_before, ns.has_blend, ns.body0);
            if hold && (ns_stop || next >= wend) {
                return;
            }
            // at rest at the window's end: step into the next piece (the same point), so
            // that the window moves on
            let window_stop = land && next >= wend;
            if ns_stop {
                // never past an exact stop without landing on it; and at rest on it for a
                // few ticks before the next segment starts
                if !self.seg(next).is_dwell() {
                    self.settle = STOP_SETTLE_TICKS;
                }
                // at rest: the next segment starts from rest within its own limits (a landing
                // leaves a hair of speed and acceleration in the planner, and a start from
                // there ramped within the limits of the pieces before the stop)
                self.planner.settle();
                self.end_seg(self.exec, ev);
                self.exec = next;
                self.in_blend = false;
                self.s = 0.0;
                self.start_seg(ev);
                return;
            }
            if ns_blend {
                self.exec = next;
                self.in_blend = true;
                self.prev_open = true;
                self.started = false;
                self.s = 0.0;
            } else {
                self.end_seg(self.exec, ev);
                self.exec = next;
                self.s = ns_body0;
                self.start_seg(ev);
            }
            if window_stop {
                return;
            }
        }
    }

    #[inline(always)]
    pub(super) fn eval_here(&self) -> V<D> {
        if self.exec >= self.tail {
            return self.pos;
        }
        let sg = self.seg(self.exec);
        if self.in_blend {
            sg.blend.pos(self.s)
        } else {
            sg.prog.pos(self.s)
        }
    }

    /// One servo tick: returns the commanded position of every group axis. `feed_override`
    /// (0..2) scales every feed; 0 holds the path still (ramping down, resuming when > 0).
    pub fn tick(&mut self, feed_override: f64, ev: &mut impl FnMut(PathEvent)) -> [f64; D] {
        let plan = self.tick_plan(feed_override, ev);
        self.tick_move(plan, ev)
    }

    /// At rest: the planner, the step and the state of the last tick.
    pub(super) fn rest(&mut self) {
        self.planner.rest();
        self.step = Step::NONE;
        self.now = (0.0, 0.0);
    }

    /// [`tick_plan`](Self::tick_plan)'s body (which `v3.rs` builds twice).
    #[inline(always)]
    pub(super) fn tick_plan_impl(
        &mut self,
        feed_override: f64,
        ev: &mut impl FnMut(PathEvent),
    ) -> TickPlan {
        let hold = TickPlan(Plan::Hold);
        if !self.ready {
            return hold;
        }
        if self.step.running() {
            return TickPlan(Plan::Step);
        }
        if self.settle > 0 {
            self.settle -= 1;
            return hold;
        }
        let ovr = if feed_override.is_nan() {
            0.0
        } else {
            feed_override.clamp(0.0, 2.0)
        };
        if self.pause == super::pause::Pause::Pending {
            // (asked in a dwell: the pause is at its end)
            self.pause_choose();
        }
        // dwells
        while self.exec < self.tail && self.seg(self.exec).is_dwell() {
            if !self.started {
                self.start_seg(ev);
            }
            if self.dwell_left > 0 {
                if !self.halted {
                    self.dwell_left -= 1;
                }
                return hold;
            }
            self.end_seg(self.exec, ev);
            self.exec += 1;
            self.s = 0.0;
            self.in_blend = false;
            self.started = false;
            if self.exec < self.tail && !self.pause_at(self.exec) {
                self.start_seg(ev);
            }
        }
        if self.pause_tick(ev) {
            return hold;
        }
        if self.exec >= self.tail {
            self.rest();
            if !self.idle_sent {
                self.idle_sent = true;
                ev(PathEvent::Idle);
            }
            return hold;
        }
        if self.seg(self.exec).shift {
            return TickPlan(Plan::Shift(ovr));
        }
        let before = self.slow;
        let mut ts = self.tsp;
        if !self.halt_lim {
            // this step ramps within the limits of the pieces near here (the last walk's; at
            // rest, the executor's own piece's), stops within those of what it looks at
            let pl = &self.planner;
            let near = if pl.v == 0.0 && pl.a == 0.0 {
                // from rest (a start, or after an exact stop): within the pieces up to where
                // a ramp to the executor's piece's speed at its limits ends, and a step more
                let sg = self.seg(self.exec);
                let (l, cap) = if self.in_blend {
                    (sg.jlim, lesser(sg.jgeo, sg.jfeed))
                } else {
                    (sg.blim, lesser(sg.bgeo, sg.feed))
                };
                let cap = cap * lesser(greater(ovr, 1.0), 2.0);
                let mut probe = self.planner;
                probe.set_limits(l.a, l.j, f64::INFINITY, f64::INFINITY);
                let span = probe.track_distance(0.0, 0.0, cap) + 2.0 * cap * ts + 1e-9;
                let mut none = Passed::NONE;
                let w = self.walk(
                    (span, span),
                    0.0,
                    0.0,
                    self.tail,
                    None,
                    &mut none,
                    &mut NoVisit,
                );
                w.near
            } else {
                self.near
            };
            let (sd, sj) = (self.planner.sd, self.planner.sj);
            self.planner.set_limits(near.a, near.j, sd, sj);
        }
        let mut lk = self.look(ovr, ts);
        let fine =
            lk.slowed && self.lim.plan_ticks > 1 && lk.target < FINE_SLOWING * self.planner.v;
        if fine {
            // It starts slowing for a much slower piece ahead within this step: decided at
            // the servo rate instead. Up to a step's worth too early, it would reach that
            // piece's speed up to a step's distance before the piece and crawl there: up to
            // v/c steps' time (a slowing to half the speed or more costs at most a step).
            self.slow = before;
            ts = self.lim.ts;
            self.planner.ts = ts;
            lk = self.look(ovr, ts);
        }
        if !self.halt_lim {
            self.planner.sd = lk.dec.a;
            self.planner.sj = lk.dec.j;
        }
        let v = match lk.track {
            Some(t) => self.planner.next_tracked(t, lk.rem),
            None => self.planner.next(lk.target, lk.rem),
        };
        let mut ds = (v * ts).max(0.0);
        let (mut land, mut rest) = (false, false);
        if lk.stop {
            // a stop that comes to rest on the stop point lands on it exactly (one that comes
            // to rest short of it, such as a short ramp up and down from near rest in a long
            // planning step, has not arrived: the next step goes on from there)
            if self.planner.lands() && lk.rem - ds <= 1e-9 * lk.rem + 1e-6 {
                // (a pause point may be within a piece: the step moves to it, no further)
                land = !lk.pause;
                rest = lk.pause;
                ds = lk.rem;
            } else if ds >= lk.rem {
                ds = lk.rem;
            }
        }
        if lk.target == 0.0
            && self.planner.v <= 1e-9 * self.jt * ts * ts
            && self.planner.a.abs() <= 1e-6 * self.jt * ts
        {
            self.planner.settle();
        }
        // the step lasts the planner's period, or ends at the tick its profile comes to rest
        // (a step that does not move lasts a tick: a resume starts at once)
        let ticks = match self.planner.rest_time() {
            _ if fine => 1,
            Some(t) => (math::ceil(t / self.lim.ts - 1e-9) as usize).clamp(1, self.lim.plan_ticks),
            None => self.lim.plan_ticks,
        };
        self.planner.ts = self.tsp;
        if self.planner.is_stopping()
            && lk.queue_end
            && lk.target > 0.0
            && !self.starving_sent
            && !self.seg(self.tail - 1).last
        {
            self.starving_sent = true;
            ev(PathEvent::Starving);
        }
        self.step = Step {
            done: 0,
            ticks,
            ds,
            moved: 0.0,
            land,
            rest,
            wend: lk.window_end,
            tail: self.tail,
        };
        TickPlan(Plan::Step)
    }

    /// [`tick_move`](Self::tick_move)'s body (which `v3.rs` builds twice).
    #[inline(always)]
    pub(super) fn tick_move_impl(
        &mut self,
        plan: TickPlan,
        ev: &mut impl FnMut(PathEvent),
    ) -> [f64; D] {
        match plan.0 {
            Plan::Hold => return self.pos,
            // a time-shifted chain runs its own profiles
            Plan::Shift(ovr) => return self.shift_tick(ovr, ev),
            Plan::Step => {}
        }
        // this tick of the step: its last moves to the step's end (the planner's state);
        // the others to where its profile is at the tick
        let st = &mut self.step;
        st.done += 1;
        let last = st.done >= st.ticks;
        let (ds, land) = if last {
            self.now = (self.planner.v, self.planner.a);
            (st.ds - st.moved, st.land && st.tail == self.tail)
        } else {
            let (d, v, a) = self.planner.sample_step(st.done as f64 * self.lim.ts);
            self.now = (v.max(0.0), a);
            // a step that lands gets to its stop point at its last tick, not before (the
            // profile comes to rest there: at most a rounding's worth is held back)
            let d = if st.land {
                d.min(st.ds * (1.0 - 1e-9))
            } else {
                d.min(st.ds)
            };
            ((d - st.moved).max(0.0), false)
        };
        st.moved += ds;
        let wend = st.wend;
        let resting = !self.is_moving();
        self.advance(ds, land, !last, wend, resting, ev);
        self.distance += ds;
        self.pos = self.eval_here();
        if self.exec >= self.tail && resting && !self.idle_sent {
            self.idle_sent = true;
            ev(PathEvent::Idle);
        }
        self.pos
    }
}

/// What the first half of a tick decided (see [`Path::tick_plan`]).
#[doc(hidden)]
#[derive(Debug, Clone, Copy)]
pub struct TickPlan(Plan);

#[derive(Debug, Clone, Copy)]
enum Plan {
    /// Nothing moves this tick (not ready, a dwell, idle).
    Hold,
    /// A time-shifted chain's tick, at this override.
    Shift(f64),
    /// A tick of the planning step (`Path::step`).
    Step,
}

#[cfg(test)]
#[path = "tests_exec.rs"]
mod tests;
