//! Time-optimal jerk-limited trajectories for one axis from any state ("online trajectory
//! generation"): from `(p0, v0, a0)` to a target position and velocity at rest acceleration
//! ([`Trajectory::to_position`]) or to a velocity ([`Trajectory::to_velocity`]), within
//! `vmin < 0 < vmax`, `amin < 0 < amax` and `|jerk| <= jmax`. Same problem and same durations
//! as Ruckig's single-DOF position and velocity interfaces (Berscheid & Kröger 2021, "Jerk-limited
//! real-time trajectory generation with arbitrary target states"), solved our own way.
//!
//! ## The profiles (Berscheid 2021 §III-IV)
//! After an optional brake pre-phase (below), the time-optimal trajectory to a target with zero
//! acceleration is one of a few 7-segment jerk patterns. In the "up" frame (the "down" frame is
//! the mirror image: every state, limit and jerk negated, `vmax <-> -vmin`, `amax <-> -amin`):
//!
//! | segment | jerk | acceleration            | held only when               |
//! |---------|------|-------------------------|------------------------------|
//! | 1       | `+j` | `a0 -> a1`              |                              |
//! | 2       | `0`  | `a1`                    | `a1 = amax` (family Acc0)    |
//! | 3       | `-j` | `a1 -> 0` (or `-> a2`)  |                              |
//! | 4       | `0`  | `0`, velocity `vmax`    | the cruise (family Vel)      |
//! | 5       | `-j` | `0 -> a2`               |                              |
//! | 6       | `0`  | `a2`                    | `a2 = amin` (family Acc1)    |
//! | 7       | `+j` | `a2 -> 0`               |                              |
//!
//! The families, each solved in closed form or on one variable:
//!
//! | family    | unknowns                         | equation for the position                 |
//! |-----------|----------------------------------|-------------------------------------------|
//! | Vel       | none (two ramps to and from `vmax`) | the cruise time, linear                |
//! | None      | `u = a1 - a2` (`= j t3`)          | quartic `3u⁴ + 12 C u² - 4 B u - 3 D² = 0` |
//! | Acc0      | `a2` (with `a1 = amax`)           | quartic in `a2`                           |
//! | Acc1      | `a1` (with `a2 = amin`)           | quartic in `a1`                           |
//! | Acc0Acc1  | `t2` (with `a1 = amax, a2 = amin`) | quadratic in `t2`                        |
//!
//! with `D = j (vf - v0) + a0²/2` (the velocity equation `a1² - a2² + j (a1 t2 + a2 t6) = D`),
//! `C = j (v0 + vf) - a0²/2`. The end position `r(x)` of each quartic family is monotone
//! between critical points known in closed form, independent of the distance:
//!
//! * None: `r'(u) = (3u⁴ + 4 C u² + D²) / (4 j² u²)`, zeros at `u² = (-2C ± √(4C² - 3D²)) / 3`;
//! * Acc0: `r'(a2) ∝ (a2 - amax)(2 a2² - amax a2 + 2 j vf)`;
//! * Acc1: `r'(a1) ∝ (a1 - amin)(2 a1² - amin a1 + 2 j v0 - a0²)`.
//!
//! So every family's domain (where all durations are `>= 0` and `amin <= a <= amax`) splits into
//! at most three pieces on which the position is monotone; each piece whose ends bracket the
//! target holds exactly one root. A root is a candidate if its velocity stays within
//! `[vmin, vmax]` from segment 3 on (where Ruckig checks it too) and it ends on the target; the
//! shortest candidate over all families and both frames is the plan (to rest, the first valid
//! one: it is unique).
//!
//! ### Finding the roots: on the polynomial, checked on the exact integration
//! Each quartic family's end position is, up to a positive factor on its domain, a polynomial
//! whose coefficients are closed-form (`Quartic`; e.g. None:
//! `4 j² u r(u) = u⁴ + 4C u² + 4 (a0³/3 - a0 j v0 - j² pd) u - D²`), evaluated by Horner's
//! rule with a bound on its rounding (the magnitudes of every term that makes up each
//! coefficient, summed the same way).
//! The polynomial decides the signs at the pieces' ends wherever its value exceeds that bound
//! (the exact end position decides the rest), and its root is found by Halley's method
//! (cubically convergent: about 4 evaluations) from the middle of the bracket, safeguarded by
//! bisection. That root is then integrated exactly once (by `offer`, which checks the
//! candidate anyway): within 4 ulps of the travel it is kept; else one Newton step on the exact
//! end position polishes it, and if that too misses, the exact end position's own root is found
//! (Newton safeguarded by bisection), as the planner did everywhere before: the polynomial's
//! cancellations (its constant coefficient) cost speed at worst, never the result. Ruckig
//! solves the same quartics in closed form and polishes with one or two Newton steps.
//!
//! Each family's duration is monotone in its variable (None: `(2u - a0)/j`; Acc0 falls with
//! `a2`; Acc1 and Acc0Acc1 grow with `a1`, `t2`), so its shortest candidate lies at a domain
//! end: a family whose shortest is no shorter than the best found is skipped (most of the
//! second frame when `vf != 0`).
//!
//! All of this runs in units scaled by powers of two (exact) so that `jmax` and
//! `max(amax, -amin)` lie in `[1, 2)`: the tolerances are relative, the products of four
//! accelerations cannot overflow, and nothing depends on the caller's units.
//!
//! ## The brake pre-phase (Ruckig's `brake.cpp`)
//! A start state beyond the limits, or one that will exceed a velocity limit whatever the jerk
//! does, is first brought back by up to two segments, by Ruckig's rules (so that the durations
//! agree): an acceleration beyond `amax` is ramped down at `-j` (and held at `amax` if the
//! velocity is still below `vmin`); a velocity beyond `vmax`, or one that will pass it
//! (`a0 > 0` and `v0 + a0²/(2j) > vmax`), is braked at `-j` until the velocity is back at `vmax`,
//! or the acceleration at `amin` (then held), or the state is one from which ramping the
//! acceleration back to zero just reaches `vmin`. Mirrored for the other side. Ruckig lengthens
//! or shortens these segments by 2.2e-14 s to land strictly inside; this planner does not (the
//! total duration moves by less than that).
//!
//! ## What the card runs
//! [`Trajectory::verify`] is the card's own check: every segment's jerk within `jmax`; the state
//! continuous from segment to segment and onto the stored end state (which for the position
//! interface is the target itself); the velocity and acceleration at every segment boundary and
//! interior extremum within the limits, widened to the start state where it is outside them
//! (relative slack 1e-9, as [`super::scurve`]). The planners run it on every plan they return
//! (`PlanCheck` otherwise).
#![forbid(unsafe_code)]

use super::scurve::{check_limits, Limits, PlanError, Profile, State};
use crate::math;

mod solve;
use solve::{Step, UDDU};

/// Relative slack of [`Trajectory::verify`] on the limits and the joints (as `scurve`'s).
const CHECK_SLACK: f64 = 1e-9;
/// Position tolerance of [`Trajectory::verify`]: ulps of the largest position of the move.
const CHECK_POS_ULPS: f64 = 16.0;
/// Most segments a trajectory has: a brake of up to 2, then 7 (one spare).
const MAX_SEGS: usize = 10;
/// 1/6, for the cubic term of a constant-jerk segment (a multiplication, not a division).
const SIXTH: f64 = 1.0 / 6.0;

/// World-frame limits, as Ruckig's single-DOF input: `vmin < 0 < vmax`, `amin < 0 < amax`,
/// `jmax > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OtgLimits {
    pub vmax: f64,
    pub vmin: f64,
    pub amax: f64,
    pub amin: f64,
    pub jmax: f64,
}

impl OtgLimits {
    /// `vmin = -vmax`, `amin = -amax`.
    pub fn symmetric(vmax: f64, amax: f64, jmax: f64) -> Self {
        OtgLimits {
            vmax,
            vmin: -vmax,
            amax,
            amin: -amax,
            jmax,
        }
    }

    /// From the card's motion-relative limits for a move heading in direction `dir` (+1, or -1
    /// for any negative `dir`): acceleration `amax` and deceleration `dmax` along `dir`, speed
    /// `vmax` both ways, one jerk (the smallest of `j1`, `j3`, `j5`, `j7`).
    pub fn along(dir: f64, lim: &Limits) -> Self {
        let jmax = lim.j1.min(lim.j3).min(lim.j5).min(lim.j7);
        let (amax, amin) = if dir < 0.0 {
            (lim.dmax, -lim.amax)
        } else {
            (lim.amax, -lim.dmax)
        };
        OtgLimits {
            vmax: lim.vmax,
            vmin: -lim.vmax,
            amax,
            amin,
            jmax,
        }
    }

    /// `Err(NonFinite)` if a limit is NaN or infinite, `Err(NonPositiveLimit)` if one is zero
    /// or on the wrong side of zero (`vmax`, `amax`, `jmax` must be `> 0`; `vmin`, `amin` `< 0`).
    pub fn validate(&self) -> Result<(), PlanError> {
        let signed = self.signed();
        if signed.iter().any(|(_, x)| !x.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        if signed.iter().any(|(_, x)| *x <= 0.0) {
            return Err(PlanError::NonPositiveLimit);
        }
        Ok(())
    }

    /// [`OtgLimits::validate`], then `Err(LimitRange)` if a limit's magnitude lies outside the
    /// range the card accepts at `servo_rate_hz` (as [`Limits::check_range`]: velocities of
    /// order 1, accelerations of order 2, the jerk of order 3).
    pub fn check_range(&self, servo_rate_hz: u32) -> Result<(), PlanError> {
        check_limits(&self.signed(), servo_rate_hz)
    }

    /// `(order, magnitude)` of each limit, every one `> 0` when the limits are valid.
    fn signed(&self) -> [(i32, f64); 5] {
        [
            (1, self.vmax),
            (1, -self.vmin),
            (2, self.amax),
            (2, -self.amin),
            (3, self.jmax),
        ]
    }
}

/// A trajectory of up to 10 constant-jerk segments (a brake pre-phase first, then up to 7),
/// stored as each segment's start state relative to `p0` in a frame `dir * world`
/// (`dir = 1` for the planners here; `from_profile` keeps the profile's own frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trajectory {
    /// World start position.
    p0: f64,
    /// +1 or -1: world = p0 + dir * frame.
    dir: f64,
    /// Segments in use (all with a duration > 0), of which the first `nbrake` brake.
    n: usize,
    nbrake: usize,
    dur: [f64; MAX_SEGS],
    /// Start time of each segment; `t0[n]` is the duration.
    t0: [f64; MAX_SEGS + 1],
    jerk: [f64; MAX_SEGS],
    x: [f64; MAX_SEGS],
    v: [f64; MAX_SEGS],
    a: [f64; MAX_SEGS],
    /// World state at the end (the target itself for the position interface).
    end: State,
}

/// Exponent `e` with `2^e <= x < 2^(e+1)`, for a finite `x > 0` (subnormals included).
fn exponent(x: f64) -> i32 {
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32;
    if e == 0 {
        let mant = bits & ((1u64 << 52) - 1);
        -1011 - mant.leading_zeros() as i32
    } else {
        e - 1023
    }
}

/// `x * 2^e`, exact unless the result leaves the normal range.
fn ldexp(mut x: f64, mut e: i32) -> f64 {
    while e > 1000 {
        x *= f64::from_bits(((1000 + 1023) as u64) << 52);
        e -= 1000;
    }
    while e < -1000 {
        x *= f64::from_bits(((-1000 + 1023) as u64) << 52);
        e += 1000;
    }
    x * f64::from_bits(((e + 1023) as u64) << 52)
}

/// The larger of `a` and `b`, `a` if `b` is NaN (one instruction, where `f64::max` takes
/// several for its NaN rule).
fn up(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// The smaller of `a` and `b`, `a` if `b` is NaN.
fn down(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// The state after a segment of jerk `j` and duration `t` from `(x, v, a)`.
fn advance(x: f64, v: f64, a: f64, j: f64, t: f64) -> (f64, f64, f64) {
    let jt = j * t;
    (
        x + t * (v + t * (0.5 * a + jt * SIXTH)),
        v + t * (a + 0.5 * jt),
        a + jt,
    )
}

/// A multiplication by `2^e`: by the power itself when that is a normal float, else by
/// [`ldexp`] (the same result).
#[derive(Clone, Copy, Debug)]
struct Pow2 {
    e: i32,
    f: f64,
}

impl Pow2 {
    fn new(e: i32) -> Pow2 {
        let f = if (-1000..=1000).contains(&e) {
            f64::from_bits(((e + 1023) as u64) << 52)
        } else {
            f64::NAN
        };
        Pow2 { e, f }
    }

    fn apply(&self, x: f64) -> f64 {
        if self.f.is_nan() {
            ldexp(x, self.e)
        } else {
            x * self.f
        }
    }
}

/// Powers of two that take the caller's units to the planner's: time `2^k`, position `2^m`
/// (so velocity `2^(m-k)`, acceleration `2^(m-2k)`, jerk `2^(m-3k)`).
#[derive(Clone, Copy, Debug)]
struct Units {
    k: i32,
    m: i32,
}

impl Units {
    /// `jmax` and `max(amax, -amin)` land in `[1, 2)`.
    fn new(lim: &OtgLimits) -> Units {
        let ea = exponent(lim.amax.max(-lim.amin));
        let ej = exponent(lim.jmax);
        Units {
            k: ea - ej,
            m: 3 * ea - 2 * ej,
        }
    }
    fn vel(&self) -> i32 {
        self.m - self.k
    }
    fn acc(&self) -> i32 {
        self.m - 2 * self.k
    }
    fn jerk(&self) -> i32 {
        self.m - 3 * self.k
    }
    /// The limits in the planner's units.
    fn limits(&self, l: &OtgLimits) -> Lim {
        Lim {
            vmax: ldexp(l.vmax, -self.vel()),
            vmin: ldexp(l.vmin, -self.vel()),
            amax: ldexp(l.amax, -self.acc()),
            amin: ldexp(l.amin, -self.acc()),
            j: ldexp(l.jmax, -self.jerk()),
        }
    }
}

/// Limits in one frame (scaled units): `vmin < 0 < vmax`, `amin < 0 < amax`, `j > 0`.
#[derive(Clone, Copy, Debug)]
struct Lim {
    vmax: f64,
    vmin: f64,
    amax: f64,
    amin: f64,
    j: f64,
}

impl Lim {
    /// The same limits seen in the mirrored frame (every quantity negated).
    fn mirror(&self) -> Lim {
        Lim {
            vmax: -self.vmin,
            vmin: -self.vmax,
            amax: -self.amin,
            amin: -self.amax,
            j: self.j,
        }
    }
}

/// Constant-jerk segments under construction (scaled units, world frame): duration, jerk and
/// the exact acceleration at the segment's end.
#[derive(Clone, Copy, Debug)]
struct Segs {
    n: usize,
    t: [f64; MAX_SEGS],
    j: [f64; MAX_SEGS],
    acc: [f64; MAX_SEGS],
}

impl Segs {
    fn new() -> Segs {
        Segs {
            n: 0,
            t: [0.0; MAX_SEGS],
            j: [0.0; MAX_SEGS],
            acc: [0.0; MAX_SEGS],
        }
    }

    /// Appends a segment; one of zero duration is dropped.
    fn push(&mut self, t: f64, j: f64, acc: f64) {
        if t > 0.0 && self.n < MAX_SEGS {
            self.t[self.n] = t;
            self.j[self.n] = j;
            self.acc[self.n] = acc;
            self.n += 1;
        }
    }

    /// The state after the segments from `(0, v, a)`: (position, velocity, acceleration).
    fn integrate(&self, mut v: f64, mut a: f64) -> (f64, f64, f64) {
        let mut x = 0.0;
        for i in 0..self.n.min(MAX_SEGS) {
            let (t, j) = (self.t[i], self.j[i]);
            x += t * (v + t * (0.5 * a + t * j / 6.0));
            v += t * (a + 0.5 * j * t);
            a = self.acc[i];
        }
        (x, v, a)
    }
}

/// Velocity at which `a` reaches zero under jerk `-sign(a) j` (the velocity a state "will
/// reach" when its acceleration is ramped out as fast as possible).
fn v_ramped(v: f64, a: f64, j: f64) -> f64 {
    v + a * a.abs() / (2.0 * j)
}

/// Ruckig's brake pre-phase for the position interface (brake.cpp,
/// `get_position_brake_trajectory`), in scaled units and the world frame: appended to `segs`.
fn position_brake(v0: f64, a0: f64, l: &Lim, segs: &mut Segs) {
    let j = l.j;
    let half = 0.5 / j;
    if a0 > l.amax {
        acceleration_brake(v0, a0, l, 1.0, segs);
    } else if a0 < l.amin {
        acceleration_brake(-v0, -a0, &l.mirror(), -1.0, segs);
    } else if (v0 > l.vmax && v0 - a0 * a0 * half > l.vmin)
        || (a0 > 0.0 && v0 + a0 * a0 * half > l.vmax)
    {
        velocity_brake(v0, a0, l, 1.0, segs);
    } else if (v0 < l.vmin && v0 + a0 * a0 * half < l.vmax)
        || (a0 < 0.0 && v0 - a0 * a0 * half < l.vmin)
    {
        velocity_brake(-v0, -a0, &l.mirror(), -1.0, segs);
    }
}

/// `a0 > amax` (in the frame `s * world`): ramp down to `amax`, or brake the velocity.
fn acceleration_brake(v0: f64, a0: f64, l: &Lim, s: f64, segs: &mut Segs) {
    let j = l.j;
    let t_amax = (a0 - l.amax) / j;
    let v_amax = v0 + t_amax * (a0 - 0.5 * j * t_amax);
    if v0 + a0 * a0 / (2.0 * j) > l.vmax {
        velocity_brake(v0, a0, l, s, segs);
    } else if v_amax < l.vmin {
        // Still below vmin at amax: hold amax until vmin, or until ramping out would pass vmax.
        let t_vmin = (l.vmin - v_amax) / l.amax;
        let t_vmax = -l.amax / (2.0 * j) + (l.vmax - v_amax) / l.amax;
        segs.push(t_amax, -s * j, s * l.amax);
        segs.push(t_vmin.min(t_vmax).max(0.0), 0.0, s * l.amax);
    } else {
        segs.push(t_amax, -s * j, s * l.amax);
    }
}

/// The velocity is beyond `vmax`, or will pass it (in the frame `s * world`): jerk `-j` until
/// the velocity is back at `vmax`, or until ramping the acceleration out would just reach
/// `vmin`, or until `amin` (then held until one of those).
fn velocity_brake(v0: f64, a0: f64, l: &Lim, s: f64, segs: &mut Segs) {
    let j = l.j;
    let t_amin = (a0 - l.amin) / j;
    let t_vmax = (a0 + math::sqrt(a0 * a0 + 2.0 * j * (v0 - l.vmax))) / j;
    let t_vmin = (a0 + math::sqrt(0.5 * a0 * a0 + j * (v0 - l.vmin))) / j;
    // (f64::min ignores a NaN: a time that does not exist is not the first)
    let t_first = t_vmax.min(t_vmin);
    if t_amin < t_first {
        let v_amin = v0 + t_amin * (a0 - 0.5 * j * t_amin);
        let hold_vmax = (v_amin - l.vmax) / -l.amin;
        let hold_vmin = l.amin / (2.0 * j) + (v_amin - l.vmin) / -l.amin;
        segs.push(t_amin.max(0.0), -s * j, s * l.amin);
        segs.push(hold_vmax.min(hold_vmin).max(0.0), 0.0, s * l.amin);
    } else {
        let t = t_first.max(0.0);
        segs.push(t, -s * j, s * (a0 - j * t));
    }
}

/// One velocity ramp up from `(v, a)` to `(v1, 0)`: jerk `+j` to the peak `a1 >= max(a, 0)`,
/// hold at `amax` if reached, `-j` to zero. `(a1, t_up, t_hold, t_down)`, or `None` when `v1`
/// lies below the velocity that ramping `a` out reaches from a negative `a` (a ramp down's
/// job). A positive `a` that would overshoot `v1` gives `a1 = a` (no rise; the overshoot is left
/// for the caller's check).
fn pulse(v: f64, a: f64, v1: f64, amax: f64, j: f64) -> Option<(f64, f64, f64, f64)> {
    let q = 0.5 * a * a + j * (v1 - v);
    if q.is_nan() || q < 0.0 {
        return None;
    }
    let peak = math::sqrt(q).max(a);
    if peak > amax {
        let a1 = amax.max(a);
        Some((
            a1,
            (a1 - a) / j,
            ((q - a1 * a1) / (j * a1)).max(0.0),
            a1 / j,
        ))
    } else {
        Some((peak, (peak - a) / j, 0.0, peak / j))
    }
}

impl Trajectory {
    /// An empty trajectory at `p0` in the world frame.
    #[inline(always)]
    fn empty(p0: f64, end: State) -> Trajectory {
        Trajectory {
            p0,
            dir: 1.0,
            n: 0,
            nbrake: 0,
            dur: [0.0; MAX_SEGS],
            t0: [0.0; MAX_SEGS + 1],
            jerk: [0.0; MAX_SEGS],
            x: [0.0; MAX_SEGS],
            v: [0.0; MAX_SEGS],
            a: [0.0; MAX_SEGS],
            end,
        }
    }

    /// The world trajectory of `segs` (scaled units) from `(p0, v0, a0)`, in the caller's
    /// units, checked against `lim` ([`Trajectory::verify`]); `end` with `pos = NaN` takes the
    /// integrated end position.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn build(
        p0: f64,
        v0: f64,
        a0: f64,
        segs: &Segs,
        nbrake: usize,
        u: &Units,
        end: State,
        lim: &OtgLimits,
    ) -> Result<Trajectory, PlanError> {
        // (filled in place: the trajectory is 552 bytes, a copy into the result costs)
        let mut out = Ok(Trajectory::empty(p0, end));
        if let Ok(tr) = &mut out {
            if let Err(e) = tr
                .fill(v0, a0, segs, nbrake, u)
                .and_then(|()| tr.verify(lim))
            {
                out = Err(e);
            }
        }
        out
    }

    /// [`Trajectory::build`]'s segments, on an empty trajectory.
    fn fill(
        &mut self,
        v0: f64,
        a0: f64,
        segs: &Segs,
        nbrake: usize,
        u: &Units,
    ) -> Result<(), PlanError> {
        let (ft, fj, fa) = (Pow2::new(u.k), Pow2::new(u.jerk()), Pow2::new(u.acc()));
        let (mut x, mut v, mut a) = (0.0, v0, a0);
        let mut time = 0.0;
        let mut k = 0;
        for i in 0..segs.n.min(MAX_SEGS) {
            let t = ft.apply(segs.t[i]);
            if t.is_nan() || t <= 0.0 {
                continue;
            }
            let j = fj.apply(segs.j[i]);
            self.dur[k] = t;
            self.jerk[k] = j;
            self.x[k] = x;
            self.v[k] = v;
            self.a[k] = a;
            self.t0[k] = time;
            if i < nbrake {
                self.nbrake += 1;
            }
            k += 1;
            (x, v, _) = advance(x, v, a, j, t);
            a = fa.apply(segs.acc[i]);
            time += t;
        }
        self.n = k;
        self.t0[k] = time;
        let end = &mut self.end;
        if end.pos.is_nan() {
            end.pos = self.p0 + x;
        }
        if (time + x + v + a + end.pos + end.vel).is_finite() {
            Ok(())
        } else {
            Err(PlanError::NonFinite)
        }
    }

    /// Ruckig's position interface: the time-optimal trajectory from `(p0, v0, a0)` to
    /// `(p1, v1)` with zero acceleration, within `lim`, after a brake pre-phase if the start
    /// is beyond the limits (see the module doc).
    ///
    /// Errors: `NonFinite` (an input, or a plan that overflows), `NonPositiveLimit`,
    /// `Infeasible` (`v1` outside `[vmin, vmax]`, or no profile found), `PlanCheck` (the plan
    /// failed [`Trajectory::verify`]).
    pub fn to_position(
        p0: f64,
        v0: f64,
        a0: f64,
        p1: f64,
        v1: f64,
        lim: &OtgLimits,
    ) -> Result<Trajectory, PlanError> {
        if ![p0, v0, a0, p1, v1].iter().all(|x| x.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.validate()?;
        if v1 > lim.vmax || v1 < lim.vmin {
            return Err(PlanError::Infeasible);
        }
        let pd = p1 - p0;
        if !pd.is_finite() {
            return Err(PlanError::NonFinite);
        }
        let u = Units::new(lim);
        let l = u.limits(lim);
        let (v0n, a0n) = (ldexp(v0, -u.vel()), ldexp(a0, -u.acc()));
        let v1n = ldexp(v1, -u.vel());
        let pdn = ldexp(pd, -u.m);
        let mut segs = Segs::new();
        position_brake(v0n, a0n, &l, &mut segs);
        let nbrake = segs.n;
        let (xb, vb, ab) = segs.integrate(v0n, a0n);
        let mut best = None;
        let rest = pdn - xb;
        // To rest (v1 = 0, a1 = 0) exactly one profile is valid (Berscheid 2021 §V: no blocked
        // interval), so the first one found is the plan; else the shortest of all. The frame
        // of the distance's sign is tried first.
        let first = v1n == 0.0;
        let up = Step::new(vb, ab, v1n, rest, l, 1.0);
        let down = Step::new(-vb, -ab, -v1n, -rest, l.mirror(), -1.0);
        let (a, b) = if rest >= 0.0 {
            (&up, &down)
        } else {
            (&down, &up)
        };
        a.solve(&mut best, first);
        if !(first && best.is_some()) {
            b.solve(&mut best, first);
        }
        let Some(b) = best else {
            return Err(if [vb, ab, rest].iter().all(|q| q.is_finite()) {
                PlanError::Infeasible
            } else {
                PlanError::NonFinite
            });
        };
        for ((&t, &acc), u) in b.prof.t.iter().zip(&b.prof.acc).zip(UDDU) {
            segs.push(t, b.s * u * l.j, b.s * acc);
        }
        let end = State {
            pos: p1,
            vel: v1,
            acc: 0.0,
            jerk: 0.0,
        };
        Trajectory::build(p0, v0, a0, &segs, nbrake, &u, end, lim)
    }

    /// Ruckig's velocity interface: the time-optimal trajectory from `(p0, v0, a0)` to the
    /// velocity `v1` with zero acceleration (the position is free), after ramping an
    /// acceleration beyond the limits back to the limit (Ruckig's velocity brake). The end state
    /// is the integrated position at `v1`, continued at `v1` by [`Trajectory::sample`].
    ///
    /// Errors as [`Trajectory::to_position`].
    pub fn to_velocity(
        p0: f64,
        v0: f64,
        a0: f64,
        v1: f64,
        lim: &OtgLimits,
    ) -> Result<Trajectory, PlanError> {
        if ![p0, v0, a0, v1].iter().all(|x| x.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.validate()?;
        if v1 > lim.vmax || v1 < lim.vmin {
            return Err(PlanError::Infeasible);
        }
        let u = Units::new(lim);
        let l = u.limits(lim);
        let (v0n, a0n) = (ldexp(v0, -u.vel()), ldexp(a0, -u.acc()));
        let v1n = ldexp(v1, -u.vel());
        let mut segs = Segs::new();
        if a0n > l.amax {
            segs.push((a0n - l.amax) / l.j, -l.j, l.amax);
        } else if a0n < l.amin {
            segs.push((l.amin - a0n) / l.j, l.j, l.amin);
        }
        let nbrake = segs.n;
        let (_, v, a) = segs.integrate(v0n, a0n);
        // Up if v1 lies at or above where ramping `a` out ends, else the mirror image.
        let (s, lim_s) = if v1n >= v_ramped(v, a, l.j) {
            (1.0, l)
        } else {
            (-1.0, l.mirror())
        };
        let Some((a1, t0, t1, t2)) = pulse(s * v, s * a, s * v1n, lim_s.amax, l.j) else {
            return Err(PlanError::NonFinite);
        };
        segs.push(t0, s * l.j, s * a1);
        segs.push(t1, 0.0, s * a1);
        segs.push(t2, -s * l.j, 0.0);
        let end = State {
            pos: f64::NAN,
            vel: v1,
            acc: 0.0,
            jerk: 0.0,
        };
        Trajectory::build(p0, v0, a0, &segs, nbrake, &u, end, lim)
    }

    /// Above a lowered velocity limit (an override turned down, a new move with a lower
    /// `vmax`) and heading for a target far enough ahead: the ramp down to the limit, arriving
    /// there with zero acceleration; the caller plans on to the target from its end. `None`
    /// when the plain [`Trajectory::to_position`] applies: within the limit, the target behind,
    /// or too close to slow down first. (Ruckig's brake pre-phase ends at the limit still
    /// decelerating, so the velocity dips below the limit by `a²/2j` before it settles; a feed
    /// override knob must not do that.)
    pub fn slow_to_limit(
        p0: f64,
        v0: f64,
        a0: f64,
        p1: f64,
        lim: &OtgLimits,
    ) -> Option<Trajectory> {
        let (vlim, ahead) = if v0 > 0.0 {
            (lim.vmax, p1 > p0)
        } else {
            (lim.vmin, p1 < p0)
        };
        if !ahead || v0.abs() <= vlim.abs() {
            return None;
        }
        let ramp = Trajectory::to_velocity(p0, v0, a0, vlim, lim).ok()?;
        let stop = Trajectory::to_velocity(0.0, vlim, 0.0, 0.0, lim).ok()?;
        let needed = (ramp.end().pos - p0).abs() + stop.end().pos.abs();
        (needed <= (p1 - p0).abs()).then_some(ramp)
    }

    /// The same trajectory as an existing `scurve` profile (a rest-to-rest move or a stop), so
    /// that the firmware can run one type: every sample within the profile's duration is the
    /// profile's own, bit for bit. (After the duration the trajectory continues at its end
    /// velocity, where the profile stays at its end state; the two differ only for `v1 != 0`.)
    pub fn from_profile(p: &Profile) -> Trajectory {
        let mut tr = Trajectory::empty(p.p0, p.end);
        tr.dir = p.dir;
        for i in 0..7 {
            if p.dur[i] > 0.0 && tr.n < MAX_SEGS {
                let k = tr.n;
                tr.dur[k] = p.dur[i];
                tr.jerk[k] = p.jerk[i];
                tr.x[k] = p.x[i];
                tr.v[k] = p.v[i];
                tr.a[k] = p.a[i];
                tr.t0[k] = p.t0[i];
                tr.n += 1;
            }
        }
        tr.t0[tr.n] = p.t0[7];
        tr
    }

    /// Total duration (s), brake included.
    #[inline]
    pub fn duration(&self) -> f64 {
        self.t0[self.n.min(MAX_SEGS)]
    }

    /// Duration of the brake pre-phase (0 when the start state was within the limits).
    #[inline]
    pub fn brake_duration(&self) -> f64 {
        self.t0[self.nbrake.min(MAX_SEGS)]
    }

    /// Durations of the segments in use (each `> 0`), brake first.
    #[inline]
    pub fn phases(&self) -> &[f64] {
        self.dur.get(..self.n).unwrap_or(&[])
    }

    /// World jerk of each segment in use, in the order of [`Trajectory::phases`].
    pub fn jerks(&self) -> [f64; MAX_SEGS] {
        let mut j = [0.0; MAX_SEGS];
        for (o, x) in j.iter_mut().zip(&self.jerk).take(self.n) {
            *o = self.dir * x;
        }
        j
    }

    /// Number of brake segments at the start of [`Trajectory::phases`].
    #[inline]
    pub fn brake_segments(&self) -> usize {
        self.nbrake
    }

    /// State at time `t` (clamped below at 0; NaN counts as 0). For `t >= duration`: the end
    /// state continued at constant velocity with zero acceleration
    /// (`pos = end.pos + end.vel * (t - duration)`).
    pub fn sample(&self, t: f64) -> State {
        self.sample_from(t, &mut 0)
    }

    /// [`Trajectory::sample`], the segment search starting at `*seg` (where the last sample
    /// was: a profile runs forward) when `t` is not before it, and `*seg` set to the segment
    /// sampled. The segments' start times never decrease, so no segment before `*seg` can hold
    /// `t`: the same state as [`Trajectory::sample`] whatever `*seg` holds.
    #[inline]
    pub fn sample_from(&self, t: f64, seg: &mut usize) -> State {
        let t = if t > 0.0 { t } else { 0.0 };
        let n = self.n.min(MAX_SEGS);
        let total = self.t0[n];
        if t >= total || n == 0 {
            let e = self.end;
            if e.vel == 0.0 {
                return e;
            }
            return State {
                pos: e.pos + e.vel * (t - total),
                ..e
            };
        }
        let mut i = if *seg < n && t >= self.t0[*seg] {
            *seg
        } else {
            0
        };
        while i + 1 < n && t >= self.t0[i + 1] {
            i += 1;
        }
        *seg = i;
        let tau = t - self.t0[i];
        let (x0, v0, a0, jerk) = (self.x[i], self.v[i], self.a[i], self.jerk[i]);
        // The same expressions as `scurve::Profile::sample` (Thinh eq 1-28), so that
        // `from_profile` samples bit for bit the same.
        let acc = a0 + jerk * tau;
        let vel = v0 + tau * (a0 + 0.5 * jerk * tau);
        let pos = x0 + tau * (v0 + tau * (0.5 * a0 + tau * jerk / 6.0));
        State {
            pos: self.p0 + self.dir * pos,
            vel: self.dir * vel,
            acc: self.dir * acc,
            jerk: self.dir * jerk,
        }
    }

    /// The end state (for the position interface the target itself).
    #[inline]
    pub fn end(&self) -> State {
        self.end
    }

    /// The same trajectory moved by `d` in position (layout 1.10: a modulo axis's frame moving
    /// by whole turns under it). Its times, velocities and accelerations are unchanged.
    pub fn shift(&mut self, d: f64) {
        self.p0 += d;
        self.end.pos += d;
    }

    /// Frame state at the end of segment `i`.
    fn seg_end(&self, i: usize) -> (f64, f64, f64) {
        advance(self.x[i], self.v[i], self.a[i], self.jerk[i], self.dur[i])
    }

    /// Smallest and largest world velocity over the trajectory (its end included).
    pub fn velocity_range(&self) -> (f64, f64) {
        let e = self.end.vel;
        let (mut lo, mut hi) = (e, e);
        for i in 0..self.n.min(MAX_SEGS) {
            let (v, a, j, t) = (self.v[i], self.a[i], self.jerk[i], self.dur[i]);
            let mut vs = [v, self.seg_end(i).1, v];
            if j != 0.0 {
                let tau = -a / j;
                if tau > 0.0 && tau < t {
                    vs[2] = v + tau * (a + 0.5 * j * tau);
                }
            }
            for w in vs {
                lo = lo.min(self.dir * w);
                hi = hi.max(self.dir * w);
            }
        }
        (lo, hi)
    }

    /// Smallest and largest world acceleration over the trajectory.
    pub fn acceleration_range(&self) -> (f64, f64) {
        let (mut lo, mut hi): (f64, f64) = (0.0, 0.0);
        for i in 0..self.n.min(MAX_SEGS) {
            for w in [self.a[i], self.seg_end(i).2] {
                lo = lo.min(self.dir * w);
                hi = hi.max(self.dir * w);
            }
        }
        (lo, hi)
    }

    /// Largest |velocity| over the trajectory.
    pub fn peak_velocity(&self) -> f64 {
        let (lo, hi) = self.velocity_range();
        hi.max(-lo)
    }

    /// The card's own check of a trajectory before it runs (O(1), no allocation, no panic):
    /// * well formed: at most 10 segments, each duration finite and `> 0`, the start times
    ///   their running sum, every stored state finite;
    /// * every jerk within `jmax` (slack 1e-9);
    /// * each segment ends where the next starts and the last on the end state, which has zero
    ///   acceleration and jerk (position within 16 ulps of the largest position of the move,
    ///   velocity and acceleration within 1e-9 of their scale);
    /// * the velocity at every joint and interior extremum within `[vmin, vmax]`, and the
    ///   acceleration at every joint within `[amin, amax]` (slack 1e-9), both widened to the
    ///   start state where it lies outside: to its acceleration, and to its velocity and the
    ///   velocity it reaches when its acceleration is ramped out at `jmax` (what a brake cannot
    ///   avoid).
    ///
    /// Anything else is `Err(PlanCheck)`; invalid limits are `validate`'s errors.
    pub fn verify(&self, lim: &OtgLimits) -> Result<(), PlanError> {
        lim.validate()?;
        if self.checks(lim) {
            Ok(())
        } else {
            Err(PlanError::PlanCheck)
        }
    }

    /// [`Trajectory::verify`]'s checks, in one pass over the segments, dividing only where the
    /// acceleration crosses zero inside a segment.
    fn checks(&self, lim: &OtgLimits) -> bool {
        let n = self.n;
        let (e, dir) = (&self.end, self.dir);
        if n > MAX_SEGS
            || self.nbrake > n
            || !(dir == 1.0 || dir == -1.0)
            || e.acc != 0.0
            || e.jerk != 0.0
            || !(self.p0 + e.pos + e.vel).is_finite()
        {
            return false;
        }
        // The start state (world) and the envelope it leaves no choice about.
        let (vs, as_) = if n > 0 {
            (dir * self.v[0], dir * self.a[0])
        } else {
            (e.vel, 0.0)
        };
        let vr = v_ramped(vs, as_, lim.jmax);
        let (vlo, vhi) = (lim.vmin.min(vs).min(vr), lim.vmax.max(vs).max(vr));
        let (alo, ahi) = (lim.amin.min(as_), lim.amax.max(as_));
        let vtol = CHECK_SLACK * vhi.max(-vlo) + f64::MIN_POSITIVE;
        let atol = CHECK_SLACK * ahi.max(-alo) + f64::MIN_POSITIVE;
        let jmax = lim.jmax * (1.0 + CHECK_SLACK);
        // The same bounds, widened by the slack, in the trajectory's frame (`dir * world`).
        let frame = |lo: f64, hi: f64| if dir > 0.0 { (lo, hi) } else { (-hi, -lo) };
        let (fvlo, fvhi) = frame(vlo - vtol, vhi + vtol);
        let (falo, fahi) = frame(alo - atol, ahi + atol);
        // The extremes the segments reach and their largest mismatches at the joints, held
        // against the limits and tolerances once, after the loop. (`up` and `down` drop a
        // NaN; a stored state, jerk or duration that is NaN or infinite leaves its segment's
        // end position so, and `ends` with it, or `time`: both are checked at the end.)
        let ev = dir * e.vel;
        let (mut vmin, mut vmax, mut amin, mut amax) = (ev, ev, 0.0, 0.0);
        let (mut dx, mut dv, mut da, mut jm): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
        let (mut tmin, mut time, mut ends) = (f64::INFINITY, 0.0, 0.0);
        let mut ok = true;
        for i in 0..n.min(MAX_SEGS) {
            let (t, j, x, v, a) = (self.dur[i], self.jerk[i], self.x[i], self.v[i], self.a[i]);
            ok &= self.t0[i] == time;
            tmin = down(tmin, t);
            time += t;
            let (x1, v1, a1) = advance(x, v, a, j, t);
            ends += x1;
            // Where the acceleration crosses zero inside the segment (at `-a/j`) the velocity
            // has an extremum, `v - a²/2j`: a minimum for `j > 0`, a maximum for `j < 0`. It
            // is within the limit when its distance from `v` is at most `v`'s own room to that
            // limit: `a² <= 2 |j| room` (no division).
            let room = if j > 0.0 { v - fvlo } else { fvhi - v };
            ok &= a * a1 >= 0.0 || a * a <= 2.0 * j.abs() * room;
            let (ex, nv, na) = if i + 1 < n {
                ((x1 - self.x[i + 1]).abs(), self.v[i + 1], self.a[i + 1])
            } else {
                // (the end state is in the world frame: compared there)
                ((self.p0 + dir * x1 - e.pos).abs(), ev, 0.0)
            };
            dx = up(dx, ex);
            dv = up(dv, (v1 - nv).abs());
            da = up(da, (a1 - na).abs());
            (vmin, vmax) = (down(down(vmin, v), v1), up(up(vmax, v), v1));
            (amin, amax) = (down(down(amin, a), a1), up(up(amax, a), a1));
            jm = up(jm, j.abs());
        }
        ok &= tmin > 0.0
            && vmin >= fvlo
            && vmax <= fvhi
            && amin >= falo
            && amax <= fahi
            && jm <= jmax
            && dv <= vtol
            && da <= atol;
        if n == 0 {
            // Nothing to run: the end is the start.
            dx = (e.pos - self.p0).abs();
        }
        // The joints within 16 ulps of the travel, which is at least the larger of the end
        // positions: the travel itself (another pass) only when that does not settle it.
        let tol = CHECK_POS_ULPS * f64::EPSILON;
        ok && self.t0[n.min(MAX_SEGS)] == time
            && time.is_finite()
            && ends.is_finite()
            && (dx <= tol * self.p0.abs().max(e.pos.abs()) + f64::MIN_POSITIVE
                || dx <= tol * self.travel() + f64::MIN_POSITIVE)
    }

    /// The rounding scale of the positions: the larger of the end positions (world), plus
    /// each segment's end position and the magnitudes of the terms of its displacement (each
    /// rounds once at its own size).
    fn travel(&self) -> f64 {
        let mut travel = self.p0.abs().max(self.end.pos.abs());
        for i in 0..self.n.min(MAX_SEGS) {
            let (t, j, x, v, a) = (self.dur[i], self.jerk[i], self.x[i], self.v[i], self.a[i]);
            let (x1, _, _) = advance(x, v, a, j, t);
            travel += x1.abs() + t * (v.abs() + t * (0.5 * a.abs() + t * j.abs() * SIXTH));
        }
        travel
    }
}

#[cfg(test)]
mod tests;
