//! Jerk-limited 7-segment S-curve motion planner (units: counts and seconds, `f64`).
//!
//! The profile follows the classic 7-phase constant-jerk S-curve of Thinh 2014 eq 1-28:
//!
//! | phase | jerk  | what happens                                   |
//! |-------|-------|------------------------------------------------|
//! | 1     | `+J1` | acceleration rises to `Am`                     |
//! | 2     | `0`   | constant acceleration `Am`                     |
//! | 3     | `-J3` | acceleration falls back to 0 (peak speed `vp`) |
//! | 4     | `0`   | cruise at `vp`                                 |
//! | 5     | `-J5` | deceleration builds to `-Dm`                   |
//! | 6     | `0`   | constant deceleration `-Dm`                    |
//! | 7     | `+J7` | deceleration falls back to 0                   |
//!
//! Each phase `k` is described by four closed-form equations (jerk, acceleration, velocity,
//! position); this module numbers them `4k-3 .. 4k` (eq 1-4 for phase 1, ..., eq 25-28 for
//! phase 7), which is what the `// Thinh eq N` comments in [`Profile::sample`] refer to.
//!
//! Acceleration and deceleration have separate limits (`amax`, `dmax`) and every ramp has its
//! own jerk limit (`j1`, `j3`, `j5`, `j7`).
//!
//! ## Method
//! * All planning happens in a "motion frame" in which the move goes in the positive
//!   direction; a negative distance is mirrored (`dir = -1`).
//! * A velocity ramp `vs -> vp` reaches its acceleration limit `A` only if
//!   `vp - vs >= A^2/2 (1/ja + 1/jb)`; otherwise it is triangular with peak
//!   `a_p = sqrt(2 (vp - vs) / (1/ja + 1/jb))`.
//! * The peak speed `vp` is the largest `vp <= vmax` with
//!   `S_acc(vp) + S_dec(vp) <= |d|`.  `S_acc + S_dec` is strictly increasing in `vp`, and its
//!   regime only changes at the two saturation speeds, so the root is first bracketed between
//!   those breakpoints.  Inside a bracket the root is obtained in closed form when possible
//!   (both ramps saturated: a quadratic; both triangular from/to rest: `S ∝ vp^(3/2)`), and
//!   is then polished (or, in the mixed regimes, found) by a bracketed Newton iteration with
//!   bisection fallback, down to the last ulp, rounded so that the distance is never exceeded.
//! * The cruise duration is finally recomputed from the integrated end position, so the
//!   profile ends at `p0 + d` to rounding error; durations are never negative.
//! * Nothing allocates; all state lives in fixed-size arrays and no function panics.
//!
//! ## What the card runs
//! [`Profile::plan_checked`] and [`Profile::stop_checked`]: the limits first have to lie in
//! the range the register map defines for their order at the servo rate
//! ([`Limits::check_range`], `firmware_proto::limit_range`: `[MAX_MOVE_TIME^-k,
//! MAX_POSITION · rate^k]`, else `LimitRange`), then the profile planned from them has to pass
//! the card's own check ([`Profile::verify_plan`], [`Profile::verify_stop`], else `PlanCheck`):
//! on its target, within every limit, never backwards, no shorter than `|d| / vmax`. The range
//! keeps the planner away from the ends of `f64`, where `jmax = 1e-245` or a subnormal `amax`
//! once planned a 100,000-count move as a one-tick step; the check is the safety net under it.
//! Seeded property tests sweep both over the whole `f64` range (`tests::props`).
//!
//! Below the normal range of `f64` there is no relative precision, so the planner keeps its
//! intermediate products in range (`a (a / j)`, `sqrt(dv) / sqrt(k)`, `hypot`), and the check
//! counts velocities and accelerations under `f64::MIN_POSITIVE` as zero.
#![forbid(unsafe_code)]

use crate::math;
use core::fmt;

/// Kinematic limits. All values must be finite and strictly positive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Maximum speed (counts/s).
    pub vmax: f64,
    /// Maximum acceleration in the direction of motion (counts/s^2).
    pub amax: f64,
    /// Maximum deceleration (counts/s^2).
    pub dmax: f64,
    /// Jerk limit of phase 1 (acceleration build-up), counts/s^3.
    pub j1: f64,
    /// Jerk limit of phase 3 (acceleration ramp-down).
    pub j3: f64,
    /// Jerk limit of phase 5 (deceleration build-up).
    pub j5: f64,
    /// Jerk limit of phase 7 (deceleration ramp-down).
    pub j7: f64,
}

impl Limits {
    /// Limits with `dmax = amax` and all four jerk limits equal to `jmax`.
    pub fn symmetric(vmax: f64, amax: f64, jmax: f64) -> Self {
        Limits {
            vmax,
            amax,
            dmax: amax,
            j1: jmax,
            j3: jmax,
            j5: jmax,
            j7: jmax,
        }
    }

    /// `Err(NonFinite)` if any limit is NaN/inf, `Err(NonPositiveLimit)` if any is `<= 0`.
    ///
    /// Only the sign and finiteness: for callers that have no servo rate (the path-speed
    /// planner, host-side tools). The card checks its commands with [`Limits::check_range`].
    pub fn validate(&self) -> Result<(), PlanError> {
        let all = [
            self.vmax, self.amax, self.dmax, self.j1, self.j3, self.j5, self.j7,
        ];
        if all.iter().any(|x| !x.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        if all.iter().any(|&x| x <= 0.0) {
            return Err(PlanError::NonPositiveLimit);
        }
        Ok(())
    }

    /// [`Limits::validate`], then `Err(LimitRange)` if any limit lies outside the range the
    /// card accepts at `servo_rate_hz` ([`firmware_proto::limit_range`]: `vmax` of order 1,
    /// `amax` and `dmax` of order 2, the four jerks of order 3). Within those ranges
    /// [`Profile::plan`] and [`Profile::stop`] neither overflow nor lose the plan to rounding.
    pub fn check_range(&self, servo_rate_hz: u32) -> Result<(), PlanError> {
        let all = [
            (1, self.vmax),
            (2, self.amax),
            (2, self.dmax),
            (3, self.j1),
            (3, self.j3),
            (3, self.j5),
            (3, self.j7),
        ];
        check_limits(&all, servo_rate_hz)
    }

    /// The range check of the limits a stop uses (`dmax`, `j3`, `j5`, `j7`); `vmax`, `amax`
    /// and `j1` only have to be finite and positive (a stop passes `vmax = f64::MAX`).
    fn check_stop_range(&self, servo_rate_hz: u32) -> Result<(), PlanError> {
        self.validate()?;
        let used = [(2, self.dmax), (3, self.j3), (3, self.j5), (3, self.j7)];
        check_limits(&used, servo_rate_hz)
    }
}

/// Check kinematic limits given as `(order, value)` pairs (order 1 velocity, 2 acceleration,
/// 3 jerk), each test over all of them before the next: finite (`NonFinite`), positive
/// (`NonPositiveLimit`), within `limit_range(order, rate)` (`LimitRange`).
pub fn check_limits(limits: &[(i32, f64)], servo_rate_hz: u32) -> Result<(), PlanError> {
    if limits.iter().any(|(_, x)| !x.is_finite()) {
        return Err(PlanError::NonFinite);
    }
    if limits.iter().any(|(_, x)| *x <= 0.0) {
        return Err(PlanError::NonPositiveLimit);
    }
    if limits
        .iter()
        .any(|&(order, x)| !firmware_proto::limit_range(order, servo_rate_hz).contains(&x))
    {
        return Err(PlanError::LimitRange);
    }
    Ok(())
}

/// Planning failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanError {
    /// An input or limit is NaN or infinite, or the plan overflowed `f64`.
    NonFinite,
    /// A limit is zero or negative.
    NonPositiveLimit,
    /// No 7-phase profile satisfies the request (e.g. the end velocity cannot be reached within
    /// the distance, a velocity is negative or `v1 > vmax`, or a stop would have to reverse).
    Infeasible,
    /// `v0 > vmax`.
    StartVelocityTooHigh,
    /// A limit lies outside the range the card accepts ([`Limits::check_range`]).
    LimitRange,
    /// The planned profile failed the card's own check ([`Profile::verify_plan`],
    /// [`Profile::verify_stop`]): a planner defect caught before the profile runs.
    PlanCheck,
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            PlanError::NonFinite => "non-finite input or result",
            PlanError::NonPositiveLimit => "limit is zero or negative",
            PlanError::Infeasible => "no feasible profile",
            PlanError::StartVelocityTooHigh => "start velocity exceeds vmax",
            PlanError::LimitRange => "limit outside the range the card accepts",
            PlanError::PlanCheck => "the planned profile failed its check",
        };
        f.write_str(s)
    }
}

impl core::error::Error for PlanError {}

/// Kinematic state (world frame, signed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State {
    pub pos: f64,
    pub vel: f64,
    pub acc: f64,
    pub jerk: f64,
}

/// A planned profile of 7 constant-jerk segments.
///
/// Internally everything is stored in the motion frame (`dir * world`), relative to `p0`.
/// (The fields are visible to the crate for `otg::Trajectory::from_profile`, which runs the
/// same segments.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// World start position.
    pub(crate) p0: f64,
    /// +1 or -1: world = p0 + dir * frame.
    pub(crate) dir: f64,
    /// Segment durations (s).
    pub(crate) dur: [f64; 7],
    /// Segment jerks (motion frame).
    pub(crate) jerk: [f64; 7],
    /// Segment start times; `t0[7]` is the total duration.
    pub(crate) t0: [f64; 8],
    /// Segment start states in the motion frame (position relative to `p0`).
    pub(crate) x: [f64; 7],
    pub(crate) v: [f64; 7],
    pub(crate) a: [f64; 7],
    /// World state returned for `t >= duration`.
    pub(crate) end: State,
}

/// Segment description in the motion frame; `acc_after[i]` is the exact acceleration at the
/// end of segment `i` (used to remove rounding drift at the segment boundaries).
#[derive(Clone, Copy, Debug)]
struct Segs {
    dur: [f64; 7],
    jerk: [f64; 7],
    acc_after: [f64; 7],
}

#[derive(Clone, Copy, Debug)]
struct Integrated {
    x: [f64; 7],
    v: [f64; 7],
    a: [f64; 7],
    x_end: f64,
}

/// Exact piecewise-cubic integration of the segments from (x = 0, v0, a0).
fn integrate(v0: f64, a0: f64, s: &Segs) -> Integrated {
    let mut out = Integrated {
        x: [0.0; 7],
        v: [0.0; 7],
        a: [0.0; 7],
        x_end: 0.0,
    };
    let (mut x, mut v, mut a) = (0.0, v0, a0);
    for i in 0..7 {
        out.x[i] = x;
        out.v[i] = v;
        out.a[i] = a;
        let t = s.dur[i];
        let j = s.jerk[i];
        x += t * (v + t * (0.5 * a + t * j / 6.0));
        v += t * (a + 0.5 * j * t);
        if t > 0.0 {
            a = s.acc_after[i];
        }
    }
    out.x_end = x;
    out
}

/// One velocity ramp of height `dv >= 0`: jerk `ja` up to peak acceleration, optional
/// plateau at `amax`, jerk `jb` back down.  Returns `([t_up, t_plateau, t_down], peak)`.
fn ramp(dv: f64, amax: f64, ja: f64, jb: f64) -> ([f64; 3], f64) {
    let dv = if dv > 0.0 { dv } else { 0.0 };
    let half_k = 0.5 / ja + 0.5 / jb;
    let dv_sat = amax * amax * half_k;
    if dv >= dv_sat {
        ([amax / ja, (dv - dv_sat) / amax, amax / jb], amax)
    } else {
        // (sqrt(dv) / sqrt(half_k): dv / half_k underflows for a subnormal dv and a small jerk)
        let peak = (math::sqrt(dv) / math::sqrt(half_k)).min(amax);
        ([peak / ja, 0.0, peak / jb], peak)
    }
}

/// Derivative of a ramp's distance with respect to its end speed `vp`
/// (`vs` = start speed, `dv = vp - vs`).
fn ramp_distance_slope(vs: f64, dv: f64, amax: f64, ja: f64, jb: f64) -> f64 {
    let half_k = 0.5 / ja + 0.5 / jb;
    if dv >= amax * amax * half_k {
        // S = (vp^2 + vp amax^2/jb)/(2 amax) + const
        (vs + dv) / amax + 0.5 * amax / jb
    } else {
        // S = vs a_p k + c a_p^3,  vp = vs + a_p^2 k / 2
        let ap = math::sqrt(dv.max(0.0)) / math::sqrt(half_k);
        if ap <= 0.0 {
            return f64::INFINITY;
        }
        let k = 2.0 * half_k;
        let c = 1.0 / (6.0 * ja * ja) + 0.5 / (ja * jb) + 1.0 / (3.0 * jb * jb);
        (vs * k + 3.0 * c * ap * ap) / (ap * k)
    }
}

/// Point-to-point problem in the motion frame.
struct Move {
    v0: f64,
    v1: f64,
    lim: Limits,
}

impl Move {
    fn segs(&self, vp: f64) -> Segs {
        let l = &self.lim;
        let (ta, ap) = ramp(vp - self.v0, l.amax, l.j1, l.j3);
        // Deceleration vp -> v1 is the time reverse of a ramp v1 -> vp whose rising jerk is j7.
        let (td, dp) = ramp(vp - self.v1, l.dmax, l.j7, l.j5);
        Segs {
            dur: [ta[0], ta[1], ta[2], 0.0, td[2], td[1], td[0]],
            jerk: [l.j1, 0.0, -l.j3, 0.0, -l.j5, 0.0, l.j7],
            acc_after: [ap, ap, 0.0, 0.0, -dp, -dp, 0.0],
        }
    }

    /// Distance covered without cruise when peaking at `vp`.
    fn dist(&self, vp: f64) -> f64 {
        integrate(self.v0, 0.0, &self.segs(vp)).x_end
    }

    fn slope(&self, vp: f64) -> f64 {
        let l = &self.lim;
        ramp_distance_slope(self.v0, vp - self.v0, l.amax, l.j1, l.j3)
            + ramp_distance_slope(self.v1, vp - self.v1, l.dmax, l.j7, l.j5)
    }

    /// Largest `vp` in `[max(v0, v1), vmax]` with `dist(vp) <= target`.
    fn solve_vp(&self, target: f64) -> Result<f64, PlanError> {
        let l = &self.lim;
        let vlo = self.v0.max(self.v1);
        let f_lo = self.dist(vlo);
        if f_lo >= target || f_lo.is_nan() {
            // Accept a rounding-level overshoot (4 ulps, or below the normal range: the plan
            // check allows 8 ulps and 1e-12 counts at the end); anything else cannot be done.
            // At `f_lo == target` there is no room either: a larger vp whose distance
            // underflows to the same value would only be noise.
            if f_lo - target <= 4.0 * f64::EPSILON * f_lo + f64::MIN_POSITIVE {
                return Ok(vlo);
            }
            return Err(if f_lo.is_finite() {
                PlanError::Infeasible
            } else {
                PlanError::NonFinite
            });
        }
        if self.dist(l.vmax) <= target {
            return Ok(l.vmax);
        }
        let (mut lo, mut hi) = (vlo, l.vmax);
        // Bracket the root between the saturation speeds so the regime is fixed inside.
        let ba = self.v0 + l.amax * l.amax * (0.5 / l.j1 + 0.5 / l.j3);
        let bd = self.v1 + l.dmax * l.dmax * (0.5 / l.j5 + 0.5 / l.j7);
        let (b1, b2) = if ba <= bd { (ba, bd) } else { (bd, ba) };
        for b in [b1, b2] {
            if b > lo && b < hi {
                if self.dist(b) <= target {
                    lo = b;
                } else {
                    hi = b;
                    break;
                }
            }
        }
        let guess = if lo >= ba && lo >= bd {
            // Both ramps saturated: dist is exactly quadratic in vp.
            let r = target - self.dist(lo);
            let qa = 0.5 / l.amax + 0.5 / l.dmax;
            let qb = self.slope(lo);
            // (hypot: qb^2 + 4 qa r underflows, or overflows, at the ends of the range)
            lo + 2.0 * r / (qb + math::hypot(qb, 2.0 * math::sqrt(qa) * math::sqrt(r)))
        } else if hi <= ba && hi <= bd && self.v0 == 0.0 && self.v1 == 0.0 {
            // Both ramps triangular from/to rest: dist = c * vp^(3/2).
            // (cbrt(q)^2, not cbrt(q^2): q^2 underflows to 0 for a tiny target)
            let c = math::cbrt(target / self.dist(hi));
            hi * c * c
        } else {
            0.5 * (lo + hi)
        };
        let mut x = if guess > lo && guess < hi {
            guess
        } else {
            0.5 * (lo + hi)
        };
        // Newton, safeguarded: when two steps have not halved the bracket, counted in floats
        // between its ends, it is bisected in that count instead. Far from the root, Newton on
        // this convex function only divides the speed by 1.5 to 3 per step, which from
        // vmax = 1e19 to a root at 1e-170 would take hundreds; the bisection in floats needs at
        // most 64 steps whatever decades the bracket spans.
        let key = |v: f64| if v > 0.0 { v.to_bits() } else { 0 };
        let mut spans = [u64::MAX; 2];
        for _ in 0..200 {
            let g = self.dist(x) - target;
            if g == 0.0 {
                return Ok(x);
            }
            if g < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let span = key(hi) - key(lo);
            let mut nx = x - g / self.slope(x);
            if !(nx > lo && nx < hi) || span > spans[0] / 2 {
                nx = f64::from_bits(key(lo) + span / 2);
                if !(nx > lo && nx < hi) {
                    break; // bracket collapsed to adjacent floats
                }
            }
            spans = [spans[1], span];
            let converged = (nx - x).abs() <= 4.0 * f64::EPSILON * x.abs();
            x = nx;
            if converged {
                break;
            }
        }
        // Round down to a speed whose distance does not exceed the target.
        let mut y = x;
        for _ in 0..16 {
            if y <= lo {
                break;
            }
            if self.dist(y) <= target {
                return Ok(y);
            }
            y = y.next_down();
        }
        Ok(lo)
    }
}

impl Profile {
    fn build(
        p0: f64,
        dir: f64,
        v0: f64,
        a0: f64,
        segs: &Segs,
        end: State,
    ) -> Result<Profile, PlanError> {
        let it = integrate(v0, a0, segs);
        let mut t0 = [0.0; 8];
        for i in 0..7 {
            t0[i + 1] = t0[i] + segs.dur[i];
        }
        let finite = segs.dur.iter().all(|t| t.is_finite() && *t >= 0.0)
            && t0[7].is_finite()
            && it
                .x
                .iter()
                .chain(it.v.iter())
                .chain(it.a.iter())
                .all(|q| q.is_finite())
            && it.x_end.is_finite()
            && end.pos.is_finite()
            && end.vel.is_finite();
        if !finite {
            return Err(PlanError::NonFinite);
        }
        Ok(Profile {
            p0,
            dir,
            dur: segs.dur,
            jerk: segs.jerk,
            t0,
            x: it.x,
            v: it.v,
            a: it.a,
            end,
        })
    }

    /// Time-optimal (for `v0 = v1 = 0`) point-to-point move from `p0` by signed distance `d`.
    ///
    /// `v0`, `v1` are speeds along the direction of motion (`0 <= v <= vmax`); the profile
    /// starts and ends with zero acceleration.  Among 7-phase profiles the one with the largest
    /// feasible peak speed `vp >= max(v0, v1)` is returned; `Infeasible` if even
    /// `vp = max(v0, v1)` needs more than `|d|`.
    pub fn plan(p0: f64, d: f64, v0: f64, v1: f64, lim: &Limits) -> Result<Profile, PlanError> {
        if !(p0.is_finite() && d.is_finite() && v0.is_finite() && v1.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.validate()?;
        if v0 > lim.vmax {
            return Err(PlanError::StartVelocityTooHigh);
        }
        if v0 < 0.0 || v1 < 0.0 || v1 > lim.vmax {
            return Err(PlanError::Infeasible);
        }
        let dir = if d < 0.0 { -1.0 } else { 1.0 };
        let dist = d.abs();
        let mv = Move { v0, v1, lim: *lim };
        let vp = mv.solve_vp(dist)?;
        let mut segs = mv.segs(vp);
        // Close the position exactly with the cruise phase (never negative).
        let first = integrate(v0, 0.0, &segs);
        let vc = first.v[3];
        let resid = dist - first.x_end;
        if resid > 0.0 && vc > 0.0 {
            segs.dur[3] = resid / vc;
        }
        let end = State {
            pos: p0 + d,
            vel: dir * v1,
            acc: 0.0,
            jerk: 0.0,
        };
        Profile::build(p0, dir, v0, 0.0, &segs, end)
    }

    /// Jerk-limited stop from `(p0, v0, a0)` to rest.
    ///
    /// Segment slots used (motion frame, where the velocity is `>= 0`):
    /// * slot 3 (`-j3`): a positive acceleration is first brought to zero;
    /// * slot 5: `-j5` builds deceleration, or `+j7` if the initial deceleration exceeds
    ///   `dmax` and must first be reduced to `dmax`;
    /// * slot 6: constant deceleration `dmax` (if reached); slot 7 (`+j7`) back to zero.
    ///
    /// If the current deceleration is so large that even ramping it out at `j7` would drive
    /// the velocity through zero (`v0 < a0^2 / (2 j7)`), the state cannot be stopped without
    /// reversing and `Infeasible` is returned. Near that bound, the speed left to remove at
    /// `dmax` after the excess deceleration is ramped out is a difference of nearly equal
    /// speeds; when it is below its rounding (8 ulps of the speed) it is not held out at
    /// `dmax`, and the stop ends at that ulp-level speed.
    pub fn stop(p0: f64, v0: f64, a0: f64, lim: &Limits) -> Result<Profile, PlanError> {
        if !(p0.is_finite() && v0.is_finite() && a0.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.validate()?;
        let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let v = v0.abs();
        let a = dir * a0;
        let dm = lim.dmax;
        let mut segs = Segs {
            dur: [0.0; 7],
            jerk: [lim.j1, 0.0, -lim.j3, 0.0, -lim.j5, 0.0, lim.j7],
            acc_after: [0.0; 7],
        };
        let (vc, ad) = if a > 0.0 {
            segs.dur[2] = a / lim.j3;
            (v + 0.5 * a * (a / lim.j3), 0.0)
        } else {
            (v, -a)
        };
        // (a (a / j), not a^2 / j: a^2 leaves the normal range for a tiny acceleration)
        let vmin = 0.5 * ad * (ad / lim.j7);
        if vc < vmin && vmin - vc > 1e-12 * vmin {
            return Err(PlanError::Infeasible);
        }
        if ad > dm {
            // Reduce the excess deceleration at the phase-7 jerk limit, then hold and ramp out.
            segs.jerk[4] = lim.j7;
            segs.dur[4] = (ad - dm) / lim.j7;
            let v_after = vc - 0.5 * (ad - dm) * (ad + dm) / lim.j7;
            // What is left to remove at dmax is a difference of nearly equal speeds when the
            // state is close to the reversal bound: below its rounding (a few ulps of vc) it
            // is noise, and holding a tiny dmax to remove noise would take for ever (from
            // 4e19 counts/s at dmax 1e-12, 1e16 s) and could even reverse. The stop then ends
            // at that noise (an ulp-level velocity) instead.
            let rest = v_after - 0.5 * dm * (dm / lim.j7);
            segs.dur[5] = if rest > 8.0 * f64::EPSILON * vc {
                rest / dm
            } else {
                0.0
            };
            segs.dur[6] = dm / lim.j7;
            segs.acc_after[4] = -dm;
            segs.acc_after[5] = -dm;
        } else {
            let v_sat = 0.5 * (dm - ad) * (dm + ad) / lim.j5 + 0.5 * dm * dm / lim.j7;
            let (peak, rise) = if vc >= v_sat {
                segs.dur[5] = (vc - v_sat) / dm;
                (dm, dm - ad)
            } else {
                // Solve for the decel increase r = peak - ad directly (stable even when
                // ad^2/j5 >> vc):  q r^2 + 2 q ad r - (vc - ad^2/(2 j7)) = 0,
                // q = 1/(2 j5) + 1/(2 j7).
                let q = 0.5 / lim.j5 + 0.5 / lim.j7;
                let qb = 2.0 * q * ad;
                let c = (vc - vmin).max(0.0);
                // (hypot: qb^2 + 4 q c underflows to 0 for a tiny speed and a large jerk, and
                // r would become infinite: a full-dmax stop that reverses)
                let r = 2.0 * c / (qb + math::hypot(qb, 2.0 * math::sqrt(q) * math::sqrt(c)));
                let r = if r > 0.0 { r.min(dm - ad) } else { 0.0 };
                (ad + r, r)
            };
            segs.dur[4] = rise / lim.j5;
            segs.dur[6] = peak / lim.j7;
            segs.acc_after[4] = -peak;
            segs.acc_after[5] = -peak;
        }
        let it = integrate(v, a, &segs);
        let end = State {
            pos: p0 + dir * it.x_end,
            vel: 0.0,
            acc: 0.0,
            jerk: 0.0,
        };
        Profile::build(p0, dir, v, a, &segs, end)
    }

    /// The seven segment durations (s).
    pub fn phases(&self) -> [f64; 7] {
        self.dur
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        self.t0[7]
    }

    /// Final position.
    pub fn end_pos(&self) -> f64 {
        self.end.pos
    }

    /// Closed-form state at time `t` (clamped to `[0, duration]`; NaN counts as 0).
    /// For `t >= duration` the exact final state is returned (rest for rest-to-rest moves).
    pub fn sample(&self, t: f64) -> State {
        let t = if t > 0.0 { t } else { 0.0 };
        if t >= self.t0[7] {
            return self.end;
        }
        let mut i = 0;
        while i < 6 && t >= self.t0[i + 1] {
            i += 1;
        }
        let tau = t - self.t0[i];
        let (x0, v0, a0) = (self.x[i], self.v[i], self.a[i]);
        // Segment i is phase k = i + 1 of Thinh 2014 and uses eq 4k-3 .. 4k, e.g. phase 1
        // (eq 1-4): j = J1, a = J1 t, v = v0 + J1 t^2/2, s = v0 t + J1 t^3/6; phase 2 (eq 5-8):
        // j = 0, a = Am, ...; phase 7 (eq 25-28): j = J7, a = -Dm + J7 t, ...  The start values
        // (x0, v0, a0) are the end values of the previous phase, precomputed at plan time.
        let jerk = self.jerk[i]; // Thinh eq 1, 5, 9, 13, 17, 21, 25 (jerk of phase k)
        let acc = a0 + jerk * tau; // Thinh eq 2, 6, 10, 14, 18, 22, 26 (acceleration)
        let vel = v0 + tau * (a0 + 0.5 * jerk * tau); // Thinh eq 3, 7, 11, 15, 19, 23, 27 (velocity)
        let pos = x0 + tau * (v0 + tau * (0.5 * a0 + tau * jerk / 6.0)); // Thinh eq 4, 8, ..., 28 (position)
        State {
            pos: self.p0 + self.dir * pos,
            vel: self.dir * vel,
            acc: self.dir * acc,
            jerk: self.dir * jerk,
        }
    }

    /// Largest speed reached (magnitude).
    pub fn peak_velocity(&self) -> f64 {
        let mut m = self.end.vel.abs();
        for i in 0..7 {
            let (v, a, j, t) = (self.v[i], self.a[i], self.jerk[i], self.dur[i]);
            m = m.max(v.abs());
            if j != 0.0 {
                let tau = -a / j;
                if tau > 0.0 && tau < t {
                    m = m.max((v + tau * (a + 0.5 * j * tau)).abs());
                }
            }
        }
        m
    }

    /// Largest acceleration in the direction of motion (>= 0).
    pub fn peak_acceleration(&self) -> f64 {
        self.acc_extreme(1.0)
    }

    /// Largest deceleration, i.e. acceleration against the direction of motion (>= 0).
    pub fn peak_deceleration(&self) -> f64 {
        self.acc_extreme(-1.0)
    }

    fn acc_extreme(&self, sign: f64) -> f64 {
        let mut m: f64 = 0.0;
        for i in 0..7 {
            if self.dur[i] > 0.0 {
                let a = self.a[i];
                let b = a + self.jerk[i] * self.dur[i];
                m = m.max(sign * a).max(sign * b);
            }
        }
        m
    }
}

/// Relative slack of the plan check: on every limit (velocity, acceleration, jerk), on the
/// velocity and acceleration at the joints and at the end (relative to the profile's own peak
/// velocity and acceleration), and on the shortest duration `|d| / vmax`.
const CHECK_SLACK: f64 = 1e-9;
/// Position tolerance of the plan check: `CHECK_POS_ULPS` ulps of the larger of `|p0|` and the
/// distance, plus `CHECK_POS_ABS` counts.
const CHECK_POS_ULPS: f64 = 8.0;
const CHECK_POS_ABS: f64 = 1e-12;

/// The tolerance on a velocity or acceleration whose scale is `scale`: `CHECK_SLACK` of it,
/// and never less than the smallest normal `f64` (below it there is no relative precision).
fn slack(scale: f64) -> f64 {
    CHECK_SLACK * scale + f64::MIN_POSITIVE
}

/// `j` has the sign of the slot's signed limit `lim` (or is 0) and stays within `|lim|`.
fn jerk_within(j: f64, lim: f64) -> bool {
    j == 0.0 || (j.signum() == lim.signum() && j.abs() <= lim.abs() * (1.0 + CHECK_SLACK))
}

/// The card's own check of a profile before it runs (O(1), no allocation, no panic), and the
/// planner as the card calls it.
impl Profile {
    /// A plan within the limits and on its target, or one to refuse.
    ///
    /// Checks the profile `Profile::plan(p0, d, v0, v1, lim)` returned against the request:
    /// * every segment duration finite and `>= 0`, every stored state finite;
    /// * `Err(Infeasible)` if it lasts longer than [`crate::MAX_MOVE_TIME`] (the documented
    ///   refusal of a move that is too slow, not a planner defect);
    /// * it starts at `(p0, v0, 0)` in the direction of `d`;
    /// * each slot's jerk has its sign and is within its limit (`j1`, `j3`, `j5`, `j7`; none in
    ///   slots 2, 4, 6);
    /// * position, velocity and acceleration are continuous across the slots, and the last
    ///   slot ends on `p0 + d` within the position tolerance (8 ulps of `max(|p0|, |d|)` +
    ///   1e-12 counts), at `v1` and zero acceleration within 1e-9 of the profile's peak
    ///   velocity and acceleration (+ `f64::MIN_POSITIVE`, + jerk × 2e-323 for slots whose
    ///   duration is subnormal);
    /// * it does not go backwards: the velocity stays above -1e-9 of its peak, and the distance
    ///   travelled at negative velocity is within the position tolerance;
    /// * the velocity never exceeds `vmax`, the acceleration at the start of every slot never
    ///   `amax`, the deceleration never `dmax` (relative slack 1e-9; the acceleration is
    ///   linear in a slot and its end is held to the next start by the continuity above);
    /// * it takes at least `|d| / vmax` (less 1e-9, and less the position tolerance: a move
    ///   shorter than that may take no time).
    ///
    /// Anything else is `Err(PlanCheck)`.
    pub fn verify_plan(
        &self,
        p0: f64,
        d: f64,
        v0: f64,
        v1: f64,
        lim: &Limits,
    ) -> Result<(), PlanError> {
        let fail = Err(PlanError::PlanCheck);
        if !self.well_formed() {
            return fail;
        }
        if self.duration() > crate::MAX_MOVE_TIME {
            return Err(PlanError::Infeasible);
        }
        let dir = if d < 0.0 { -1.0 } else { 1.0 };
        let dist = d.abs();
        if self.p0 != p0
            || self.dir != dir
            || self.x[0] != 0.0
            || self.v[0] != v0
            || self.a[0] != 0.0
        {
            return fail;
        }
        let jerk = [lim.j1, 0.0, -lim.j3, 0.0, -lim.j5, 0.0, lim.j7];
        if (0..7).any(|i| self.dur[i] > 0.0 && !jerk_within(self.jerk[i], jerk[i])) {
            return fail;
        }
        let (vlow, vhigh) = self.velocity_range();
        let vscale = vhigh.max(v0).max(v1);
        let (acc, dec) = self.slot_start_accelerations();
        let pos_tol = CHECK_POS_ULPS * f64::EPSILON * p0.abs().max(dist) + CHECK_POS_ABS;
        let tol = (pos_tol, slack(vscale), slack(acc.max(dec)));
        let end = &self.end;
        let ok = self.continuous((dist, v1), tol)
            && (end.pos - (p0 + d)).abs() <= pos_tol
            && end.vel == dir * v1
            && end.acc == 0.0
            && end.jerk == 0.0
            && vlow >= -tol.1
            && self.backward_travel() <= pos_tol
            && vhigh <= lim.vmax * (1.0 + CHECK_SLACK)
            && acc <= lim.amax * (1.0 + CHECK_SLACK)
            && dec <= lim.dmax * (1.0 + CHECK_SLACK)
            && self.duration() >= (dist - pos_tol) / lim.vmax * (1.0 - CHECK_SLACK);
        if ok {
            Ok(())
        } else {
            fail
        }
    }

    /// A stop the way [`Profile::stop`] promises it, or one to refuse.
    ///
    /// Checks the profile `Profile::stop(p0, v0, a0, lim)` returned: every segment duration
    /// finite and `>= 0` (any total: a stop is not bounded by `MAX_MOVE_TIME`), every stored
    /// state finite; it starts at `(p0, v0, a0)`; only the documented slots are used (slot 3 at
    /// `-j3` only to bring a positive acceleration to zero, slot 5 at `-j5`, or at `+j7` only
    /// when the deceleration exceeds `dmax`, slot 6 without jerk, slot 7 at `+j7`); the states
    /// are continuous across the slots and the last one ends at rest on its end position
    /// (tolerances as in [`Profile::verify_plan`], the position's from `max(|p0|, distance)`);
    /// it does not go backwards (velocity above -1e-9 of its peak, distance at negative
    /// velocity within the position tolerance); the acceleration never exceeds a positive
    /// initial acceleration (a positive one is only brought down); the deceleration stays
    /// within the larger of `dmax` and the initial deceleration (slack 1e-9). Anything else
    /// is `Err(PlanCheck)`.
    pub fn verify_stop(&self, p0: f64, v0: f64, a0: f64, lim: &Limits) -> Result<(), PlanError> {
        let fail = Err(PlanError::PlanCheck);
        if !self.well_formed() {
            return fail;
        }
        let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let (v, a) = (v0.abs(), dir * a0);
        if self.p0 != p0 || self.dir != dir || self.x[0] != 0.0 || self.v[0] != v || self.a[0] != a
        {
            return fail;
        }
        let slot_ok = |i: usize| {
            let j = self.jerk[i];
            match i {
                2 => a > 0.0 && jerk_within(j, -lim.j3),
                4 if j > 0.0 => -a > lim.dmax && jerk_within(j, lim.j7),
                4 => jerk_within(j, -lim.j5),
                5 => j == 0.0,
                6 => jerk_within(j, lim.j7),
                _ => false,
            }
        };
        if (0..7).any(|i| self.dur[i] > 0.0 && !slot_ok(i)) {
            return fail;
        }
        let (vlow, vhigh) = self.velocity_range();
        let vscale = vhigh.max(v);
        let (acc, dec) = self.slot_start_accelerations();
        let atol = slack(acc.max(dec));
        let x_end = self.slot_end(6).0;
        let pos_tol = CHECK_POS_ULPS * f64::EPSILON * p0.abs().max(x_end.abs()) + CHECK_POS_ABS;
        let end = &self.end;
        let ok = self.continuous((x_end, 0.0), (pos_tol, slack(vscale), atol))
            && (end.pos - (p0 + dir * x_end)).abs() <= pos_tol
            && (end.vel, end.acc, end.jerk) == (0.0, 0.0, 0.0)
            && vlow >= -slack(vscale)
            && self.backward_travel() <= pos_tol
            && acc <= a.max(0.0) * (1.0 + CHECK_SLACK)
            && dec <= lim.dmax.max(-a) * (1.0 + CHECK_SLACK);
        if ok {
            Ok(())
        } else {
            fail
        }
    }

    /// [`Profile::plan`] as the card runs it: the inputs finite, the limits within their range
    /// at `servo_rate_hz` ([`Limits::check_range`]), the plan, then [`Profile::verify_plan`].
    /// Errors: `NonFinite` (an input or the plan), `NonPositiveLimit`, `LimitRange`,
    /// `StartVelocityTooHigh`, `Infeasible` (no profile, or one longer than `MAX_MOVE_TIME`),
    /// `PlanCheck` (the plan failed its check).
    pub fn plan_checked(
        p0: f64,
        d: f64,
        v0: f64,
        v1: f64,
        lim: &Limits,
        servo_rate_hz: u32,
    ) -> Result<Profile, PlanError> {
        if !(p0.is_finite() && d.is_finite() && v0.is_finite() && v1.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.check_range(servo_rate_hz)?;
        let p = Profile::plan(p0, d, v0, v1, lim)?;
        p.verify_plan(p0, d, v0, v1, lim)?;
        Ok(p)
    }

    /// [`Profile::stop`] as the card runs it: the state finite, the limits a stop uses (`dmax`,
    /// `j3`, `j5`, `j7`) within their range at `servo_rate_hz` (the others only finite and
    /// positive: a stop passes `vmax = f64::MAX`), the stop, then [`Profile::verify_stop`].
    /// Errors: `NonFinite` (the state, or a stop that overflows), `NonPositiveLimit`,
    /// `LimitRange`, `Infeasible` (the stop would have to reverse), `PlanCheck`.
    pub fn stop_checked(
        p0: f64,
        v0: f64,
        a0: f64,
        lim: &Limits,
        servo_rate_hz: u32,
    ) -> Result<Profile, PlanError> {
        if !(p0.is_finite() && v0.is_finite() && a0.is_finite()) {
            return Err(PlanError::NonFinite);
        }
        lim.check_stop_range(servo_rate_hz)?;
        let p = Profile::stop(p0, v0, a0, lim)?;
        p.verify_stop(p0, v0, a0, lim)?;
        Ok(p)
    }

    /// Durations finite and `>= 0` with a finite total, every stored state finite.
    fn well_formed(&self) -> bool {
        let states = self
            .x
            .iter()
            .chain(&self.v)
            .chain(&self.a)
            .chain(&self.jerk);
        self.dur.iter().all(|t| t.is_finite() && *t >= 0.0)
            && self.t0[0] == 0.0
            && self.t0.windows(2).all(|w| w[1] >= w[0])
            && self.t0[7].is_finite()
            && states.into_iter().all(|q| q.is_finite())
            && [
                self.p0,
                self.end.pos,
                self.end.vel,
                self.end.acc,
                self.end.jerk,
            ]
            .iter()
            .all(|q| q.is_finite())
            && (self.dir == 1.0 || self.dir == -1.0)
    }

    /// Motion-frame state (position from `p0`, velocity, acceleration) at the end of slot `i`.
    fn slot_end(&self, i: usize) -> (f64, f64, f64) {
        let (t, j) = (self.dur[i], self.jerk[i]);
        let (x, v, a) = (self.x[i], self.v[i], self.a[i]);
        if t > 0.0 {
            (
                x + t * (v + t * (0.5 * a + t * j / 6.0)),
                v + t * (a + 0.5 * j * t),
                a + j * t,
            )
        } else {
            (x, v, a)
        }
    }

    /// Each slot ends where the next one starts, the last one on `end` (frame position and
    /// velocity, zero acceleration), within `tol` (position, velocity, acceleration) plus what
    /// the rounding of a duration near the subnormals does: a ramp of a negligible
    /// acceleration lasts 1e-320 s with a few bits, or underflows to 0 and leaves its
    /// acceleration (< jerk x 5e-324) in place.
    fn continuous(&self, end: (f64, f64), tol: (f64, f64, f64)) -> bool {
        const DT: f64 = f64::from_bits(4); // 4 x the smallest subnormal
        let jdt = self.jerk.iter().fold(0.0f64, |m, j| m.max(j.abs())) * DT;
        (0..7).all(|i| {
            let (x, v, a) = self.slot_end(i);
            let next = if i < 6 {
                (self.x[i + 1], self.v[i + 1], self.a[i + 1])
            } else {
                (end.0, end.1, 0.0)
            };
            let adt = (self.a[i].abs() + a.abs()) * DT;
            (x - next.0).abs() <= tol.0
                && (v - next.1).abs() <= tol.1 + adt
                && (a - next.2).abs() <= tol.2 + jdt
        })
    }

    /// Largest acceleration and deceleration (both `>= 0`, motion frame) at the start of the
    /// non-empty slots. The acceleration is linear in each slot, and [`Profile::continuous`]
    /// holds each slot's end to the next start (the last to 0) within its tolerance, so these
    /// bound it everywhere up to that tolerance; a ramp's extrapolated end itself carries the
    /// rounding of the ramp (`-Dm + J7 (Dm / J7)` is a few ulps of `Dm`, not 0).
    fn slot_start_accelerations(&self) -> (f64, f64) {
        let (mut acc, mut dec): (f64, f64) = (0.0, 0.0);
        for i in 0..7 {
            if self.dur[i] > 0.0 {
                acc = acc.max(self.a[i]);
                dec = dec.max(-self.a[i]);
            }
        }
        (acc, dec)
    }

    /// The distance travelled backwards (motion frame): the integral of the negative part of
    /// the velocity over every slot, from the slots' velocity zeros. A velocity that rounding
    /// leaves a few ulps below zero for a moment travels nothing measurable; one held below
    /// zero (a stop whose velocity cancelled out in a long ramp at a tiny deceleration) does.
    fn backward_travel(&self) -> f64 {
        let mut back = 0.0;
        for i in 0..7 {
            let (t, v, a, j) = (self.dur[i], self.v[i], self.a[i], self.jerk[i]);
            if t <= 0.0 {
                continue;
            }
            // v(s) = v + a s + j s^2 / 2: its zeros inside (0, t) split the slot.
            let mut cuts = [0.0, t, t, t];
            let mut n = 1;
            let mut cut = |s: f64| {
                if s > 0.0 && s < t {
                    cuts[n] = s;
                    n += 1;
                }
            };
            if j == 0.0 {
                if a != 0.0 {
                    cut(-v / a);
                }
            } else {
                let disc = a * a - 2.0 * j * v;
                if disc >= 0.0 {
                    // (the stable pair of roots of j/2 s^2 + a s + v)
                    let q = -(a + a.signum() * math::sqrt(disc));
                    if q != 0.0 {
                        cut(q / j);
                        cut(2.0 * v / q);
                    }
                }
            }
            if n == 3 && cuts[2] < cuts[1] {
                cuts.swap(1, 2);
            }
            let x = |s: f64| s * (v + s * (0.5 * a + s * j / 6.0));
            for k in 0..n {
                let (s0, s1) = (cuts[k], cuts[k + 1]);
                let m = 0.5 * (s0 + s1);
                if v + m * (a + 0.5 * j * m) < 0.0 {
                    back += x(s0) - x(s1);
                }
            }
        }
        back
    }

    /// Smallest and largest motion-frame velocity over the non-empty slots.
    fn velocity_range(&self) -> (f64, f64) {
        let (mut lo, mut hi) = (self.v[0], self.v[0]);
        for i in 0..7 {
            if self.dur[i] > 0.0 {
                let (v, a, j, t) = (self.v[i], self.a[i], self.jerk[i], self.dur[i]);
                let ve = self.slot_end(i).1;
                lo = lo.min(v).min(ve);
                hi = hi.max(v).max(ve);
                if j != 0.0 {
                    let tau = -a / j;
                    if tau > 0.0 && tau < t {
                        let vm = v + tau * (a + 0.5 * j * tau);
                        lo = lo.min(vm);
                        hi = hi.max(vm);
                    }
                }
            }
        }
        (lo, hi)
    }
}

/// The limits of a stop from `(vel, acc)` that ends within `max_time` s when it can: the given
/// `(dmax, jerk)` if their ramp is short enough, else the harder of each and the card's own stop
/// ramp `hard` (a harder ramp is never longer). What still takes longer is cut at the bound by
/// the safety layer (power off).
pub fn bounded_stop_limits(
    (v0, a0): (f64, f64),
    (dmax, jerk): (f64, f64),
    hard: (f64, f64),
    max_time: f64,
) -> (f64, f64) {
    match plan_stop(0.0, v0, a0, dmax, jerk) {
        Ok(p) if p.duration() <= max_time => (dmax, jerk),
        _ => (dmax.max(hard.0), jerk.max(hard.1)),
    }
}

/// A jerk-limited stop from (pos, vel, acc) within `dmax` and `jerk` (MC_Halt, MC_Stop and the
/// category 1 and 2 safety stops).
pub fn plan_stop(pos: f64, v0: f64, a0: f64, dmax: f64, jerk: f64) -> Result<Profile, PlanError> {
    let limits = Limits {
        vmax: f64::MAX,
        amax: dmax,
        dmax,
        j1: jerk,
        j3: jerk,
        j5: jerk,
        j7: jerk,
    };
    // Every stop is checked before it runs (the card's own check: `verify_stop`).
    let checked = |lim: &Limits| {
        let p = Profile::stop(pos, v0, a0, lim)?;
        p.verify_stop(pos, v0, a0, lim).map(|()| p)
    };
    match checked(&limits) {
        // Late in a deceleration the remaining velocity is smaller than what the given jerk
        // needs to bring the deceleration to zero: stopping at that jerk would reverse. Use
        // the smallest jerk that stops without reversing (a stop never moves backwards).
        Err(PlanError::Infeasible) if v0 != 0.0 && a0 * v0 < 0.0 => {
            let j = (a0 * (a0 / (2.0 * v0.abs()))).max(jerk) * (1.0 + 1e-9);
            let limits = Limits {
                j1: j,
                j3: j,
                j5: j,
                j7: j,
                ..limits
            };
            checked(&limits)
        }
        r => r,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::testkit::rng::Rng;

    fn random_limits(rng: &mut Rng) -> Limits {
        let vmax = rng.log_uniform(1e-2, 1e5);
        let amax = rng.log_uniform(1e-1, 1e6);
        let dmax = if rng.chance(0.25) {
            amax
        } else {
            rng.log_uniform(1e-1, 1e6)
        };
        if rng.chance(0.25) {
            let j = rng.log_uniform(1.0, 1e9);
            Limits {
                vmax,
                amax,
                dmax,
                j1: j,
                j3: j,
                j5: j,
                j7: j,
            }
        } else {
            Limits {
                vmax,
                amax,
                dmax,
                j1: rng.log_uniform(1.0, 1e9),
                j3: rng.log_uniform(1.0, 1e9),
                j5: rng.log_uniform(1.0, 1e9),
                j7: rng.log_uniform(1.0, 1e9),
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // Independent reference model (written separately from the planner's formulas).
    //
    // A ramp of speed change dv has acceleration magnitude a(t) = min(ja t, ap, jb (T - t)),
    // and the distance it contributes beyond the start speed is  ∫_0^T (T - t) a(t) dt,
    // evaluated with Simpson's rule on each of the three pieces (exact: the integrand is a
    // quadratic on each piece).
    // ---------------------------------------------------------------------------------------

    /// Returns (T, peak, ∫_0^T (T - t) a(t) dt).
    fn ref_ramp(dv: f64, amax: f64, ja: f64, jb: f64) -> (f64, f64, f64) {
        if dv <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let h = 0.5 / ja + 0.5 / jb;
        let ap = if dv >= amax * amax * h {
            amax
        } else {
            dv.sqrt() / h.sqrt()
        };
        let plateau = ((dv - ap * ap * h) / ap).max(0.0);
        let (ta, tb) = (ap / ja, ap / jb);
        let total = ta + plateau + tb;
        let g = |t: f64| (total - t) * (ja * t).min(ap).min(jb * (total - t)).max(0.0);
        let simpson = |p: f64, q: f64| (q - p) / 6.0 * (g(p) + 4.0 * g(0.5 * (p + q)) + g(q));
        let m = simpson(0.0, ta) + simpson(ta, ta + plateau) + simpson(ta + plateau, total);
        (total, ap, m)
    }

    /// (time without cruise, distance) for peak speed vp.
    fn ref_dist(v0: f64, v1: f64, vp: f64, l: &Limits) -> (f64, f64) {
        let (ta, _, ma) = ref_ramp(vp - v0, l.amax, l.j1, l.j3);
        // deceleration magnitude d(t) = min(j5 t, dp, j7 (T - t)); v = vp - ∫ d
        let (td, _, md) = ref_ramp(vp - v1, l.dmax, l.j5, l.j7);
        (ta + td, v0 * ta + ma + vp * td - md)
    }

    /// Minimum time by bisection on vp (to f64 convergence).  None if infeasible.
    fn ref_min_time(v0: f64, v1: f64, dist: f64, l: &Limits) -> Option<(f64, f64)> {
        let vlo = v0.max(v1);
        if ref_dist(v0, v1, vlo, l).1 > dist {
            return None;
        }
        let vp = if ref_dist(v0, v1, l.vmax, l).1 <= dist {
            l.vmax
        } else {
            let (mut lo, mut hi) = (vlo, l.vmax);
            for _ in 0..3000 {
                let mid = 0.5 * (lo + hi);
                if !(mid > lo && mid < hi) {
                    break;
                }
                if ref_dist(v0, v1, mid, l).1 <= dist {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let (t, s) = ref_dist(v0, v1, vp, l);
        let cruise = if vp > 0.0 {
            (dist - s).max(0.0) / vp
        } else {
            0.0
        };
        Some((t + cruise, vp))
    }

    /// Distance drawn so that every regime (triangular / saturated on each side, with and
    /// without cruise, tiny, huge) is exercised.
    fn random_distance(rng: &mut Rng, v0: f64, v1: f64, l: &Limits) -> f64 {
        let vlo = v0.max(v1);
        let mag = match rng.next_u64() % 8 {
            0 => rng.log_uniform(1e-9, 1e-3),
            1 => rng.log_uniform(1.0, 1e12),
            2 => ref_dist(v0, v1, l.vmax, l).1 * rng.log_uniform(1.0, 1e3),
            _ => {
                let lo = (l.vmax * 1e-7).max(vlo);
                let vp = if lo < l.vmax {
                    rng.log_uniform(lo, l.vmax)
                } else {
                    l.vmax
                };
                ref_dist(v0, v1, vp, l).1
            }
        };
        rng.sign() * mag
    }

    fn segment_of(p: &Profile, t: f64) -> usize {
        (0..7).find(|&i| t < p.t0[i + 1]).unwrap_or(7)
    }

    /// Worst values seen by a check.
    #[derive(Default, Clone, Copy, Debug)]
    struct Worst {
        limit_excess: f64,
        end_pos_err: f64,
        continuity_err: f64,
    }

    impl Worst {
        fn merge(&mut self, o: Worst) {
            self.limit_excess = self.limit_excess.max(o.limit_excess);
            self.end_pos_err = self.end_pos_err.max(o.end_pos_err);
            self.continuity_err = self.continuity_err.max(o.continuity_err);
        }
    }

    /// Test-side exact cubic extrapolation of a state by tau.
    fn extrapolate(s: State, tau: f64) -> State {
        State {
            pos: s.pos + s.vel * tau + 0.5 * s.acc * tau * tau + s.jerk * tau * tau * tau / 6.0,
            vel: s.vel + s.acc * tau + 0.5 * s.jerk * tau * tau,
            acc: s.acc + s.jerk * tau,
            jerk: s.jerk,
        }
    }

    /// Continuity of position, velocity and acceleration across all segment boundaries,
    /// checked in the motion frame (relative to p0, so no world-coordinate rounding) with a
    /// test-side extrapolation.  The last non-empty segment must land on `end`
    /// (frame position, if given, and velocity; acceleration 0).
    /// Returns (worst relative error, relative end position error).
    fn check_continuity(
        p: &Profile,
        end: (Option<f64>, f64),
        scales: (f64, f64, f64),
    ) -> (f64, f64) {
        let (pos_scale, vel_scale, acc_scale) = scales;
        let mut worst: f64 = 0.0;
        let mut end_err: f64 = 0.0;
        for i in 0..7 {
            let d = p.dur[i];
            if d <= 0.0 {
                continue;
            }
            let start = State {
                pos: p.x[i],
                vel: p.v[i],
                acc: p.a[i],
                jerk: p.jerk[i],
            };
            let left = extrapolate(start, d);
            // Decide "last" by index, not by time: a segment much shorter than ulp(total)
            // can vanish from the time axis but still exists in the state chain.
            let last = p.dur[i + 1..].iter().all(|&t| t <= 0.0);
            let right = if last {
                (end.0.unwrap_or(left.pos), end.1, 0.0)
            } else {
                (p.x[i + 1], p.v[i + 1], p.a[i + 1])
            };
            let ep = (left.pos - right.0).abs() / pos_scale;
            // (velocities and accelerations below the normal range count as 0)
            let beyond = |e: f64| (e - f64::MIN_POSITIVE).max(0.0);
            let ev = beyond((left.vel - right.1).abs()) / vel_scale;
            let ea = beyond((left.acc - right.2).abs()) / acc_scale;
            assert!(
                ep <= 1e-9 && ev <= 1e-9 && ea <= 1e-9,
                "discontinuity at boundary {i}: {ep:e} {ev:e} {ea:e} {p:?}"
            );
            worst = worst.max(ep).max(ev).max(ea);
            if last {
                end_err = end_err.max(ep);
            }
        }
        (worst, end_err)
    }

    fn check_plan(p: &Profile, l: &Limits, p0: f64, d: f64, v0: f64, v1: f64) -> Worst {
        let tol = 1e-9;
        let dir = if d < 0.0 { -1.0 } else { 1.0 };
        let jlim = [l.j1, 0.0, l.j3, 0.0, l.j5, 0.0, l.j7, 0.0];
        let total = p.duration();
        assert!(total.is_finite() && total >= 0.0);
        assert!(p.phases().iter().all(|&t| t >= 0.0), "{:?}", p.phases());
        let mut w = Worst::default();
        let mut visit = |t: f64| {
            let s = p.sample(t);
            let seg = segment_of(p, t.max(0.0));
            let (v, a) = (dir * s.vel, dir * s.acc);
            assert!(v >= -tol * l.vmax, "velocity reversal {v} at {t}");
            let ej = if jlim[seg] == 0.0 {
                assert_eq!(s.jerk, 0.0, "jerk in zero-jerk segment {seg}");
                0.0
            } else {
                s.jerk.abs() / jlim[seg] - 1.0
            };
            let ex = (v.abs() / l.vmax - 1.0)
                .max(a / l.amax - 1.0)
                .max(-a / l.dmax - 1.0)
                .max(ej);
            assert!(
                ex <= tol,
                "limit exceeded by {ex:e} at t={t} seg={seg} {s:?} {l:?} d={d}"
            );
            w.limit_excess = w.limit_excess.max(ex);
        };
        for k in 0..=2000 {
            visit(total * k as f64 / 2000.0);
        }
        for i in 0..8 {
            visit(p.t0[i]);
            visit(p.t0[i] * (1.0 - 1e-13));
        }
        visit(total * 2.0 + 1.0);
        // start / end states (a zero-duration plan only has its end, no farther than the
        // position tolerance of the plan check from its start)
        let s = p.sample(0.0);
        if total > 0.0 {
            assert_eq!(s.pos, p0);
            assert!((s.vel - dir * v0).abs() <= 1e-12 * l.vmax);
        } else {
            assert!(d.abs() <= 8.0 * f64::EPSILON * p0.abs() + 1e-12 || v0 == v1 && d == 0.0);
        }
        let e = p.sample(total);
        assert_eq!(e, p.sample(total + 1.0));
        assert_eq!(e.pos, p0 + d);
        assert_eq!(e.vel, dir * v1);
        assert_eq!((e.acc, e.jerk), (0.0, 0.0));
        assert_eq!(p.end_pos(), p0 + d);
        // continuity, including the integrated end (left limit) vs the exact target
        let pos_scale = d.abs().max(1.0e-9);
        let scales = (pos_scale, l.vmax, l.amax.max(l.dmax));
        let (c, end_err) = check_continuity(p, (Some(d.abs()), v1), scales);
        w.continuity_err = c;
        w.end_pos_err = end_err;
        w
    }

    #[test]
    fn hand_computed_cases() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-3);
        // vmax=1000, amax=1e4, j=1e6, d=1e4:
        //   amax^2/j = 100 <= 1000 -> amax reached; T1 = T3 = amax/j = 0.01,
        //   T2 = (1000 - 100)/1e4 = 0.09; accel distance = vmax/2 * 0.11 = 55 each side,
        //   cruise = (1e4 - 110)/1000 = 9.89; total 10.11.
        let l = Limits::symmetric(1000.0, 1e4, 1e6);
        let p = Profile::plan(5.0, 1e4, 0.0, 0.0, &l).unwrap();
        let want = [0.01, 0.09, 0.01, 9.89, 0.01, 0.09, 0.01];
        for (g, w) in p.phases().iter().zip(want) {
            assert!(close(*g, w), "{:?}", p.phases());
        }
        assert!(close(p.duration(), 10.11));
        assert!(close(p.peak_velocity(), 1000.0));
        assert!(close(p.peak_acceleration(), 1e4) && close(p.peak_deceleration(), 1e4));
        assert_eq!(p.end_pos(), 1e4 + 5.0);

        // Same limits, d = 100 (no cruise, amax reached): each side covers
        // vp/2 (vp/amax + amax/j), so vp^2/1e4 + 0.01 vp = 100 ->
        // vp = (-100 + sqrt(4.01e6))/2 = 951.249219725...; T = 2 (0.02 + (vp - 100)/1e4).
        let vp = (-100.0 + 4.01e6f64.sqrt()) / 2.0;
        let p = Profile::plan(0.0, 100.0, 0.0, 0.0, &l).unwrap();
        assert!(close(p.peak_velocity(), vp));
        assert!(close(p.duration(), 2.0 * (0.02 + (vp - 100.0) / 1e4)));
        assert!(p.phases()[3] < 1e-12);

        // d = 1 (triangular acceleration): 2 a_p^3 / j^2 = d -> a_p = cbrt(j^2 d / 2) = 7937.005...,
        // T = 4 a_p / j = 4 cbrt(d/(2j)) = 0.0317480210..., vp = a_p^2 / j.
        let ap = (1e12f64 / 2.0).cbrt();
        let p = Profile::plan(0.0, -1.0, 0.0, 0.0, &l).unwrap();
        assert!(close(p.duration(), 4.0 * (1.0f64 / 2e6).cbrt()));
        assert!(close(p.peak_acceleration(), ap));
        assert!(close(p.peak_velocity(), ap * ap / 1e6));
        assert_eq!(p.end_pos(), -1.0);

        // Asymmetric: dmax = 5e3: T5 = T7 = 0.005, T6 = (1000 - 25)/5e3 = 0.195,
        // decel distance = 500 * 0.205 = 102.5, cruise = (1e4 - 55 - 102.5)/1000 = 9.8425.
        let la = Limits { dmax: 5e3, ..l };
        let p = Profile::plan(0.0, 1e4, 0.0, 0.0, &la).unwrap();
        let want = [0.01, 0.09, 0.01, 9.8425, 0.005, 0.195, 0.005];
        for (g, w) in p.phases().iter().zip(want) {
            assert!(close(*g, w), "{:?}", p.phases());
        }

        // Non-zero v0 = 100: accel ramp 100 -> 1000 has T1 = T3 = 0.01, T2 = (900 - 100)/1e4 = 0.08,
        // distance (100 + 1000)/2 * 0.1 = 55 (symmetric jerks); decel 55; cruise 9.89.
        let p = Profile::plan(0.0, 1e4, 100.0, 0.0, &l).unwrap();
        assert!(close(p.phases()[1], 0.08));
        assert!(close(p.phases()[3], (1e4 - 55.0 - 55.0) / 1000.0));

        // stop from 1000 counts/s, a = 0: T5 = T7 = 0.01, T6 = 0.09, distance 55.
        let s = Profile::stop(1.0, -1000.0, 0.0, &l).unwrap();
        let want = [0.0, 0.0, 0.0, 0.0, 0.01, 0.09, 0.01];
        for (g, w) in s.phases().iter().zip(want) {
            assert!(close(*g, w), "{:?}", s.phases());
        }
        assert!(close(s.end_pos(), 1.0 - 55.0));

        // stop from v = 100, a = +5000: T3 = 0.005, v -> 100 + 12.5 = 112.5;
        // then T5 = T7 = 0.01, T6 = (112.5 - 100)/1e4 = 0.00125.
        let s = Profile::stop(0.0, 100.0, 5000.0, &l).unwrap();
        let want = [0.0, 0.0, 0.005, 0.0, 0.01, 0.00125, 0.01];
        for (g, w) in s.phases().iter().zip(want) {
            assert!(close(*g, w), "{:?}", s.phases());
        }

        // stop from v = 1000, a = -2e4 (|a| > dmax): +j7 for 0.01 s (dv = (4e8-1e8)/2e6 = 150),
        // v = 850; hold (850 - 50)/1e4 = 0.08; ramp-out 0.01.
        let s = Profile::stop(0.0, 1000.0, -2e4, &l).unwrap();
        let want = [0.0, 0.0, 0.0, 0.0, 0.01, 0.08, 0.01];
        for (g, w) in s.phases().iter().zip(want) {
            assert!(close(*g, w), "{:?}", s.phases());
        }
        assert!(s.sample(0.005).jerk > 0.0);
    }

    #[test]
    fn limits_end_and_continuity_random() {
        let mut rng = Rng::new(0x5eed_0001);
        let mut worst = Worst::default();
        let mut n = 0;
        let mut regimes = [0usize; 4]; // [amax reached, dmax reached, cruise, neither]
        for _ in 0..1500 {
            let l = random_limits(&mut rng);
            let (v0, v1) = if rng.chance(0.6) {
                (0.0, 0.0)
            } else {
                (
                    rng.uniform(0.0, l.vmax) * f64::from(u8::from(rng.chance(0.7))),
                    rng.uniform(0.0, l.vmax) * f64::from(u8::from(rng.chance(0.7))),
                )
            };
            let d = random_distance(&mut rng, v0, v1, &l);
            let p0 = rng.uniform(-1e3, 1e3);
            match Profile::plan(p0, d, v0, v1, &l) {
                Ok(p) => {
                    worst.merge(check_plan(&p, &l, p0, d, v0, v1));
                    n += 1;
                    let ph = p.phases();
                    regimes[0] += usize::from(ph[1] > 0.0);
                    regimes[1] += usize::from(ph[5] > 0.0);
                    regimes[2] += usize::from(ph[3] > 1e-9 * p.duration());
                    regimes[3] += usize::from(ph[1] == 0.0 && ph[5] == 0.0);
                }
                Err(e) => {
                    assert_eq!(e, PlanError::Infeasible);
                    assert!(ref_dist(v0, v1, v0.max(v1), &l).1 > d.abs() * (1.0 - 1e-9));
                }
            }
        }
        eprintln!("limits: {n} feasible plans, regimes {regimes:?}, worst {worst:?}");
        assert!(n >= 1000);
        assert!(regimes.iter().all(|&r| r >= 100), "{regimes:?}");
    }

    #[test]
    fn time_optimal_vs_independent_bisection() {
        let mut rng = Rng::new(0x0071_3e57);
        let mut worst_rel: f64 = 0.0;
        let mut worst_vp: f64 = 0.0;
        let (mut n, mut infeasible) = (0, 0);
        for case in 0..2000 {
            let l = random_limits(&mut rng);
            let (v0, v1) = if case % 2 == 0 {
                (0.0, 0.0)
            } else {
                (rng.uniform(0.0, l.vmax), rng.uniform(0.0, l.vmax))
            };
            let d = random_distance(&mut rng, v0, v1, &l) * if case % 7 == 0 { 0.5 } else { 1.0 };
            let dist = d.abs();
            let min_dist = ref_dist(v0, v1, v0.max(v1), &l).1;
            let res = Profile::plan(0.0, d, v0, v1, &l);
            match ref_min_time(v0, v1, dist, &l) {
                None => {
                    if min_dist > dist * (1.0 + 1e-9) {
                        assert_eq!(res, Err(PlanError::Infeasible));
                        infeasible += 1;
                    }
                }
                Some((t_ref, vp_ref)) => {
                    let p =
                        res.unwrap_or_else(|e| panic!("{e:?} for feasible {l:?} {d} {v0} {v1}"));
                    let rel = (p.duration() - t_ref).abs() / t_ref.max(1e-300);
                    assert!(
                        (p.duration() - t_ref).abs() <= 1e-9 * t_ref + 1e-15,
                        "duration {} vs reference {t_ref} ({rel:e}) {l:?} d={d} v0={v0} v1={v1}",
                        p.duration()
                    );
                    let evp = (p.peak_velocity() - vp_ref).abs() / l.vmax;
                    assert!(evp <= 1e-9, "vp {} vs {vp_ref}", p.peak_velocity());
                    worst_rel = worst_rel.max(rel);
                    worst_vp = worst_vp.max(evp);
                    n += 1;
                }
            }
        }
        eprintln!(
            "optimality: {n} feasible cases, {infeasible} infeasible; worst rel duration \
             mismatch {worst_rel:e}, worst vp mismatch/vmax {worst_vp:e}"
        );
        assert!(n >= 1000 && infeasible >= 50);
    }

    #[test]
    fn derivatives_consistent() {
        // Central differences of the closed-form samples must reproduce vel/acc/jerk
        // (pos is cubic: (x(t+h) - x(t-h)) / 2h = v + j h^2/6 exactly; v quadratic; a linear).
        let mut rng = Rng::new(77);
        for _ in 0..300 {
            let l = random_limits(&mut rng);
            let d = random_distance(&mut rng, 0.0, 0.0, &l);
            let p = Profile::plan(0.0, d, 0.0, 0.0, &l).unwrap();
            for i in 0..7 {
                let dur = p.phases()[i];
                if dur <= p.duration() * 1e-6 {
                    continue;
                }
                let t = p.t0[i] + dur * rng.uniform(0.3, 0.7);
                let h = dur * 0.1;
                let (a, b, c) = (p.sample(t - h), p.sample(t), p.sample(t + h));
                let x_scale = d.abs() / h;
                let dv = (c.pos - a.pos) / (2.0 * h) - b.vel - b.jerk * h * h / 6.0;
                assert!(
                    dv.abs() <= 1e-9 * x_scale,
                    "pos/vel mismatch {dv:e} in seg {i}"
                );
                let da = (c.vel - a.vel) / (2.0 * h) - b.acc;
                assert!(da.abs() <= 1e-9 * l.vmax / h, "vel/acc mismatch {da:e}");
                let dj = (c.acc - a.acc) / (2.0 * h) - b.jerk;
                assert!(
                    dj.abs() <= 1e-9 * l.amax.max(l.dmax) / h,
                    "acc/jerk mismatch"
                );
            }
        }
    }

    #[test]
    fn degenerate_distances() {
        let l = Limits {
            vmax: 3000.0,
            amax: 2e5,
            dmax: 5e4,
            j1: 1e8,
            j3: 3e7,
            j5: 2e6,
            j7: 9e8,
        };
        // d = 0: zero-duration, at rest
        let p = Profile::plan(12.0, 0.0, 0.0, 0.0, &l).unwrap();
        assert_eq!(p.duration(), 0.0);
        assert_eq!(p.phases(), [0.0; 7]);
        let rest = State {
            pos: 12.0,
            vel: 0.0,
            acc: 0.0,
            jerk: 0.0,
        };
        assert_eq!(p.sample(0.0), rest);
        assert_eq!(p.sample(1.0), rest);
        assert_eq!(p.sample(f64::NAN), rest);
        // tiny / huge / mirrored
        for d in [1e-9, -1e-9, 1e-6, 1e12, -1e12, 0.37] {
            let p = Profile::plan(-4.0, d, 0.0, 0.0, &l).unwrap();
            check_plan(&p, &l, -4.0, d, 0.0, 0.0);
            let (t, _) = ref_min_time(0.0, 0.0, d.abs(), &l).unwrap();
            assert!((p.duration() - t).abs() <= 1e-9 * t, "{d}");
            let (p, q) = (
                Profile::plan(0.0, d, 0.0, 0.0, &l).unwrap(),
                Profile::plan(0.0, -d, 0.0, 0.0, &l).unwrap(),
            );
            assert_eq!(p.phases(), q.phases());
            for k in 0..=50 {
                let t = p.duration() * k as f64 / 50.0;
                let (a, b) = (p.sample(t), q.sample(t));
                assert_eq!(a.pos, -b.pos);
                assert_eq!((a.vel, a.acc, a.jerk), (-b.vel, -b.acc, -b.jerk));
            }
        }
        // pure cruise at vmax
        let p = Profile::plan(0.0, 30.0, 3000.0, 3000.0, &l).unwrap();
        assert_eq!(p.phases()[3], 0.01);
        assert_eq!(p.duration(), 0.01);
        // v0 = v1 > 0 and d = 0: zero duration moving state
        let p = Profile::plan(1.0, 0.0, 5.0, 5.0, &l).unwrap();
        assert_eq!(p.duration(), 0.0);
        assert_eq!(p.sample(3.0).vel, 5.0);
    }

    #[test]
    fn nonzero_boundary_velocities() {
        let mut rng = Rng::new(0xbeef);
        let (mut ok, mut bad) = (0, 0);
        for _ in 0..2000 {
            let l = random_limits(&mut rng);
            let v0 = rng.uniform(0.0, l.vmax);
            let v1 = rng.uniform(0.0, l.vmax);
            let need = ref_dist(v0, v1, v0.max(v1), &l).1;
            let dist = need * rng.log_uniform(0.01, 100.0);
            let d = rng.sign() * dist;
            let r = Profile::plan(3.0, d, v0, v1, &l);
            if dist >= need * (1.0 + 1e-9) {
                let p = r.unwrap();
                check_plan(&p, &l, 3.0, d, v0, v1);
                let dir = d.signum();
                assert_eq!(p.sample(p.duration()).vel, dir * v1);
                // the integrated velocity at the end (left limit) also matches v1
                let last = (0..7).rev().find(|&i| p.phases()[i] > 0.0).unwrap();
                let left = extrapolate(p.sample(p.t0[last]), p.phases()[last]);
                assert!((left.vel - dir * v1).abs() <= 1e-9 * l.vmax);
                assert!((left.pos - (3.0 + d)).abs() <= 1e-9 * dist + 1e-14);
                ok += 1;
            } else if dist <= need * (1.0 - 1e-9) {
                assert_eq!(r, Err(PlanError::Infeasible), "{l:?} {d} {v0} {v1}");
                bad += 1;
            }
        }
        assert!(ok >= 500 && bad >= 500, "{ok} {bad}");
        let l = Limits::symmetric(100.0, 1000.0, 1e5);
        assert_eq!(
            Profile::plan(0.0, 1e-3, 100.0, 0.0, &l),
            Err(PlanError::Infeasible)
        );
        assert_eq!(
            Profile::plan(0.0, 1e-3, 0.0, 100.0, &l),
            Err(PlanError::Infeasible)
        );
    }

    #[test]
    fn input_errors() {
        let l = Limits::symmetric(100.0, 1000.0, 1e5);
        let nan = f64::NAN;
        let inf = f64::INFINITY;
        for (p0, d, v0, v1) in [
            (nan, 1.0, 0.0, 0.0),
            (0.0, nan, 0.0, 0.0),
            (0.0, 1.0, nan, 0.0),
            (0.0, 1.0, 0.0, nan),
            (inf, 1.0, 0.0, 0.0),
            (0.0, -inf, 0.0, 0.0),
            (0.0, 1.0, inf, 0.0),
        ] {
            assert_eq!(Profile::plan(p0, d, v0, v1, &l), Err(PlanError::NonFinite));
        }
        for (p0, v0, a0) in [(nan, 0.0, 0.0), (0.0, inf, 0.0), (0.0, 1.0, nan)] {
            assert_eq!(Profile::stop(p0, v0, a0, &l), Err(PlanError::NonFinite));
        }
        let fields: [fn(&mut Limits) -> &mut f64; 7] = [
            |l| &mut l.vmax,
            |l| &mut l.amax,
            |l| &mut l.dmax,
            |l| &mut l.j1,
            |l| &mut l.j3,
            |l| &mut l.j5,
            |l| &mut l.j7,
        ];
        for f in fields {
            for (bad, err) in [
                (nan, PlanError::NonFinite),
                (inf, PlanError::NonFinite),
                (0.0, PlanError::NonPositiveLimit),
                (-1.0, PlanError::NonPositiveLimit),
            ] {
                let mut lb = l;
                *f(&mut lb) = bad;
                assert_eq!(lb.validate(), Err(err));
                assert_eq!(Profile::plan(0.0, 1.0, 0.0, 0.0, &lb), Err(err));
                assert_eq!(Profile::stop(0.0, 1.0, 0.0, &lb), Err(err));
            }
        }
        assert_eq!(l.validate(), Ok(()));
        assert_eq!(
            Profile::plan(0.0, 1.0, 100.0001, 0.0, &l),
            Err(PlanError::StartVelocityTooHigh)
        );
        assert_eq!(
            Profile::plan(0.0, 1e6, 0.0, 100.0001, &l),
            Err(PlanError::Infeasible)
        );
        assert_eq!(
            Profile::plan(0.0, 1e6, -1.0, 0.0, &l),
            Err(PlanError::Infeasible)
        );
    }

    fn check_stop(p: &Profile, l: &Limits, p0: f64, v0: f64, a0: f64) -> f64 {
        let tol = 1e-9;
        let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let a_start = dir * a0;
        let total = p.duration();
        let vscale = p.peak_velocity().max(v0.abs()).max(1e-300);
        let ascale = a0.abs().max(l.dmax);
        let mut worst: f64 = 0.0;
        let mut prev_dec = f64::INFINITY;
        let mut prev_acc = f64::INFINITY;
        let n = 2000;
        for k in 0..=n + 16 {
            let t = if k <= n {
                total * k as f64 / n as f64
            } else {
                p.t0[(k - n - 1) / 2] * if k % 2 == 0 { 1.0 } else { 1.0 - 1e-13 }
            };
            let s = p.sample(t);
            let seg = segment_of(p, t);
            let (v, a, j) = (dir * s.vel, dir * s.acc, dir * s.jerk);
            // (below the normal range there is no relative precision: as in the plan check)
            assert!(
                v >= -tol * vscale - f64::MIN_POSITIVE,
                "velocity sign change {v} ({s:?})"
            );
            let jl = match seg {
                2 => l.j3,
                4 if j > 0.0 => l.j7,
                4 => l.j5,
                6 => l.j7,
                _ => 0.0,
            };
            if jl == 0.0 {
                assert_eq!(j, 0.0, "unexpected jerk in slot {seg}");
            } else {
                let ej = j.abs() / jl - 1.0;
                assert!(ej <= tol, "jerk excess {ej:e}");
                worst = worst.max(ej);
            }
            let dec = -a;
            if dec > l.dmax * (1.0 + tol) {
                // still correcting an initial |a| > dmax: only allowed to shrink
                assert!(
                    k > n || dec <= prev_dec * (1.0 + 1e-12),
                    "decel grew above dmax"
                );
                assert!(dec <= -a_start * (1.0 + 1e-12) + 1e-12 * ascale);
            } else if !(seg == 4 && j > 0.0) {
                // (inside the correction segment the decel is legitimately still >= dmax)
                worst = worst.max(dec / l.dmax - 1.0);
            }
            if a > 0.0 {
                // (a ramp-out of a deceleration ends within rounding of 0, on either side)
                assert!(a <= a_start.max(0.0) * (1.0 + 1e-12) + 1e-12 * ascale);
                assert!(k > n || a <= prev_acc.max(0.0) * (1.0 + 1e-12) + 1e-12 * ascale);
            }
            if k <= n {
                prev_dec = dec;
                prev_acc = a;
            }
        }
        let e = p.sample(total);
        assert_eq!((e.vel, e.acc, e.jerk), (0.0, 0.0, 0.0));
        assert_eq!(e, p.sample(total * 3.0 + 1.0));
        let s = p.sample(0.0);
        assert_eq!((s.pos, s.vel), (p0, v0));
        // (a stop from rest with an acceleration below jerk x 5e-324 may take no time: its start
        // is its end)
        let jdt = [l.j3, l.j5, l.j7].iter().fold(0.0f64, |m, &j| m.max(j)) * 2e-323;
        assert!((s.acc - a0).abs() <= 1e-15 * a0.abs() + f64::MIN_POSITIVE + jdt);
        let pos_scale = p.x[6].abs().max(1e-12);
        check_continuity(p, (None, 0.0), (pos_scale, vscale, ascale));
        worst
    }

    #[test]
    fn stop_random_states() {
        let mut rng = Rng::new(0x5709);
        let mut worst: f64 = 0.0;
        let mut counts = [0usize; 5]; // ok, infeasible, a>0, |a|>dmax, v0=0
        for _ in 0..3000 {
            let l = random_limits(&mut rng);
            let dir = rng.sign();
            let a_frame = match rng.next_u64() % 5 {
                0 => 0.0,
                1 => rng.uniform(0.0, 3.0) * l.amax,
                2 => -rng.uniform(0.0, 1.0) * l.dmax,
                _ => -rng.uniform(1.0, 4.0) * l.dmax,
            };
            let need = if a_frame < 0.0 {
                0.5 * a_frame * a_frame / l.j7
            } else {
                0.0
            };
            let v = match rng.next_u64() % 4 {
                0 => 0.0,
                1 => rng.log_uniform(1e-6, 1.0) * l.vmax,
                _ if need == 0.0 => rng.log_uniform(1e-6, 1.0) * l.vmax,
                _ => need * rng.log_uniform(0.3, 100.0),
            };
            let (v0, a0) = (dir * v, dir * a_frame);
            // At v0 = 0 the motion direction is that of a0, so the acceleration is "positive".
            let (a_frame, need) = if v == 0.0 {
                (a_frame.abs(), 0.0)
            } else {
                (a_frame, need)
            };
            let p0 = rng.uniform(-1e3, 1e3);
            match Profile::stop(p0, v0, a0, &l) {
                Ok(p) => {
                    assert!(
                        v >= need * (1.0 - 1e-9),
                        "accepted a state that must reverse"
                    );
                    worst = worst.max(check_stop(&p, &l, p0, v0, a0));
                    counts[0] += 1;
                    counts[2] += usize::from(a_frame > 0.0 && v > 0.0);
                    counts[3] += usize::from(-a_frame > l.dmax);
                    counts[4] += usize::from(v == 0.0);
                }
                Err(e) => {
                    assert_eq!(e, PlanError::Infeasible);
                    assert!(v < need * (1.0 + 1e-9));
                    counts[1] += 1;
                }
            }
        }
        eprintln!("stop: counts [ok, infeasible, a>0, |a|>dmax, v0=0] = {counts:?}, worst excess {worst:e}");
        assert!(counts.iter().all(|&c| c >= 100), "{counts:?}");
    }

    #[test]
    fn garbage_inputs_never_panic() {
        let mut rng = Rng::new(0xdead);
        fn pick(rng: &mut Rng) -> f64 {
            match rng.next_u64() % 6 {
                0 => f64::from_bits(rng.next_u64()),
                1 => rng.log_uniform(1e-300, 1e300) * rng.sign(),
                2 => 0.0,
                3 => f64::MIN_POSITIVE * rng.unit(),
                _ => rng.log_uniform(1e-3, 1e6),
            }
        }
        for _ in 0..20000 {
            let l = Limits {
                vmax: pick(&mut rng),
                amax: pick(&mut rng),
                dmax: pick(&mut rng),
                j1: pick(&mut rng),
                j3: pick(&mut rng),
                j5: pick(&mut rng),
                j7: pick(&mut rng),
            };
            let (a, b, c, d) = (
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
            );
            for p in [Profile::plan(a, b, c, d, &l), Profile::stop(a, b, c, &l)]
                .into_iter()
                .flatten()
            {
                assert!(p.duration().is_finite());
                for k in 0..=8 {
                    let _ = p.sample(p.duration() * k as f64 / 8.0);
                }
                let _ = (
                    p.peak_velocity(),
                    p.peak_acceleration(),
                    p.peak_deceleration(),
                );
            }
        }
    }

    /// The attacks that produced impossible plans before the range check and the plan check:
    /// each is refused by `plan_checked`, and the plan `plan` still makes of it fails its check.
    #[test]
    fn attacks_are_refused() {
        let sym = |v, a, j| Limits::symmetric(v, a, j);
        let sub = f64::MIN_POSITIVE / 3.0;
        let cases = [
            ("jmax 1e-246", sym(2e5, 2e6, 1e-246)),
            ("amax 1e-306", sym(2e5, 1e-306, 1e8)),
            ("subnormal amax", sym(2e5, sub, 1e8)),
            (
                "subnormal dmax",
                Limits {
                    dmax: sub,
                    ..sym(2e5, 2e6, 1e8)
                },
            ),
            (
                "jdec 1e-320",
                Limits {
                    j5: 1e-320,
                    j7: 1e-320,
                    ..sym(2e5, 2e6, 1e8)
                },
            ),
            ("vmax 1e300", sym(1e300, 2e6, 1e8)),
        ];
        for (what, l) in cases {
            let r = Profile::plan_checked(0.0, 1e5, 0.0, 0.0, &l, 10_000);
            assert_eq!(r.map(|_| ()), Err(PlanError::LimitRange), "{what}");
            // The safety net under the range: what the bare planner makes of it is refused.
            if let Ok(p) = Profile::plan(0.0, 1e5, 0.0, 0.0, &l) {
                let v = p.verify_plan(0.0, 1e5, 0.0, 0.0, &l);
                assert!(
                    matches!(v, Err(PlanError::PlanCheck | PlanError::Infeasible))
                        || (what == "vmax 1e300" && v.is_ok()),
                    "{what}: {v:?} for {p:?}"
                );
            }
        }
        // The range's ends are inside, one ulp beyond is not.
        for rate in [1000, 10_000, 20_000] {
            for order in 1..=3 {
                let r = firmware_proto::limit_range(order, rate);
                for (x, inside) in [
                    (*r.start(), true),
                    (*r.end(), true),
                    (r.start().next_down(), false),
                    (r.end().next_up(), false),
                ] {
                    let mut l = sym(1e3, 1e5, 1e7);
                    match order {
                        1 => l.vmax = x,
                        2 => l.dmax = x,
                        _ => l.j5 = x,
                    }
                    let want = if inside {
                        Ok(())
                    } else {
                        Err(PlanError::LimitRange)
                    };
                    assert_eq!(l.check_range(rate), want, "order {order} {x:e} at {rate}");
                }
            }
        }
        // A stop ignores vmax, amax and j1 (the axis passes vmax = f64::MAX).
        let l = Limits {
            vmax: f64::MAX,
            ..sym(1e3, 1e5, 1e7)
        };
        assert_eq!(l.check_range(10_000), Err(PlanError::LimitRange));
        assert!(Profile::stop_checked(0.0, 500.0, 0.0, &l, 10_000).is_ok());
        let l = Limits { j7: 1e-19, ..l };
        assert_eq!(
            Profile::stop_checked(0.0, 500.0, 0.0, &l, 10_000),
            Err(PlanError::LimitRange)
        );
    }

    /// The check refuses a profile that does not do what was asked of it.
    #[test]
    fn verify_refuses_a_wrong_profile() {
        let l = Limits::symmetric(1000.0, 1e4, 1e6);
        let p = Profile::plan(5.0, 1e4, 0.0, 0.0, &l).unwrap();
        assert_eq!(p.verify_plan(5.0, 1e4, 0.0, 0.0, &l), Ok(()));
        // another request than the one planned
        assert_eq!(
            p.verify_plan(5.0, 1e4 + 1e-6, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        assert_eq!(
            p.verify_plan(4.0, 1e4, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        assert_eq!(
            p.verify_plan(5.0, -1e4, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        // tighter limits than those planned with
        for tight in [
            Limits { vmax: 999.0, ..l },
            Limits { amax: 9e3, ..l },
            Limits { dmax: 9e3, ..l },
            Limits { j3: 9e5, ..l },
            Limits { j7: 9e5, ..l },
        ] {
            assert_eq!(
                p.verify_plan(5.0, 1e4, 0.0, 0.0, &tight),
                Err(PlanError::PlanCheck)
            );
        }
        // broken profiles: a cruise too short (off target, and shorter than |d|/vmax), a NaN,
        // an acceleration jump, a move too long
        let mut q = p;
        q.dur[3] *= 0.5;
        q.t0[4..].iter_mut().for_each(|t| *t -= p.dur[3] * 0.5);
        assert_eq!(
            q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        let mut q = p;
        q.x[5] = f64::NAN;
        assert_eq!(
            q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        let mut q = p;
        q.a[2] *= 1.001;
        assert_eq!(
            q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        let slow = Limits::symmetric(1e-3, 1.0, 1.0);
        let p = Profile::plan(0.0, 2e3, 0.0, 0.0, &slow).unwrap();
        assert!(p.duration() > crate::MAX_MOVE_TIME);
        assert_eq!(
            p.verify_plan(0.0, 2e3, 0.0, 0.0, &slow),
            Err(PlanError::Infeasible)
        );
        // a stop: checked against its own state, reversal refused
        let s = Profile::stop(1.0, -1000.0, 0.0, &l).unwrap();
        assert_eq!(s.verify_stop(1.0, -1000.0, 0.0, &l), Ok(()));
        assert_eq!(
            s.verify_stop(1.0, -999.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
        assert_eq!(
            s.verify_stop(1.0, -1000.0, 0.0, &Limits { j5: 9e5, ..l }),
            Err(PlanError::PlanCheck)
        );
        let mut q = s;
        q.dur[6] *= 2.0; // ramps the deceleration out past zero: backwards
        q.t0[7] += s.dur[6];
        assert_eq!(
            q.verify_stop(1.0, -1000.0, 0.0, &l),
            Err(PlanError::PlanCheck)
        );
    }

    /// Seeded property tests over the whole `f64` range (proptest with a fixed ChaCha seed:
    /// the same cases on every run; `PROPTEST_CASES` is overridden by the counts here).
    mod props {
        use super::*;
        use firmware_proto::limit_range;
        use proptest::prelude::*;
        use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
        use std::cell::RefCell;

        fn runner(cases: u32, seed: u8) -> TestRunner {
            let config = Config {
                cases,
                failure_persistence: None,
                max_shrink_iters: 4096,
                ..Config::default()
            };
            TestRunner::new_with_rng(
                config,
                TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
            )
        }

        /// Any `f64` an attacker could pick: every bit pattern, log-uniform magnitudes over the
        /// whole exponent range (subnormals included), and the named extremes.
        fn wild() -> impl Strategy<Value = f64> {
            prop_oneof![
                any::<f64>(),
                (0u64..2047, any::<u64>(), any::<bool>()).prop_map(|(e, m, neg)| {
                    let x = f64::from_bits(e << 52 | m >> 12);
                    if neg {
                        -x
                    } else {
                        x
                    }
                }),
                (1u64..1 << 52).prop_map(f64::from_bits),
                prop::sample::select(vec![
                    0.0,
                    -0.0,
                    1e-320,
                    1e-300,
                    1e-30,
                    1e300,
                    f64::MAX,
                    -f64::MAX,
                    f64::MIN_POSITIVE,
                    -1.0,
                    f64::NAN,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                ]),
            ]
        }

        /// A limit: any value, log-uniform inside the range of its order, or the range's
        /// low or high end moved by -1, 0 or +1 ulp.
        #[derive(Clone, Copy, Debug)]
        enum Pick {
            Value(f64),
            InRange(f64),
            Edge(bool, i8),
        }

        fn pick() -> impl Strategy<Value = Pick> {
            prop_oneof![
                1 => wild().prop_map(Pick::Value),
                24 => (0.0..=1.0f64).prop_map(Pick::InRange),
                3 => (any::<bool>(), -1i8..=1).prop_map(|(hi, u)| Pick::Edge(hi, u)),
            ]
        }

        fn ulps(x: f64, k: i8) -> f64 {
            match k {
                -1 => x.next_down(),
                1 => x.next_up(),
                _ => x,
            }
        }

        fn resolve(p: Pick, order: i32, rate: u32) -> f64 {
            let r = limit_range(order, rate);
            let (lo, hi) = (*r.start(), *r.end());
            match p {
                Pick::Value(x) => x,
                Pick::InRange(u) => (lo.ln() + u * (hi.ln() - lo.ln())).exp().clamp(lo, hi),
                Pick::Edge(top, k) => ulps(if top { hi } else { lo }, k),
            }
        }

        /// Seven picks and how they are tied: 0 independent, 1 symmetric (`dmax = amax`, one
        /// jerk), 2 as `mcctl` (`j3 = j1`, `j7 = j5`).
        fn limits(p: [Pick; 7], tie: u8, rate: u32) -> Limits {
            let x = |i: usize, order| resolve(p[i], order, rate);
            let mut l = Limits {
                vmax: x(0, 1),
                amax: x(1, 2),
                dmax: x(2, 2),
                j1: x(3, 3),
                j3: x(4, 3),
                j5: x(5, 3),
                j7: x(6, 3),
            };
            if tie == 1 {
                (l.dmax, l.j3, l.j5, l.j7) = (l.amax, l.j1, l.j1, l.j1);
            } else if tie == 2 {
                (l.j3, l.j7) = (l.j1, l.j5);
            }
            l
        }

        /// A start or end velocity: any value, a fraction of vmax (uniform, or log-uniform down
        /// to underflow), or vmax moved by -1, 0, +1 ulp.
        #[derive(Clone, Copy, Debug)]
        enum Vel {
            Value(f64),
            Frac(f64),
            Tiny(f64),
            Vmax(i8),
        }

        fn vel() -> impl Strategy<Value = Vel> {
            prop_oneof![
                6 => Just(Vel::Frac(0.0)),
                1 => wild().prop_map(Vel::Value),
                2 => (0.0..=1.0f64).prop_map(Vel::Frac),
                1 => (0.0..=1.0f64).prop_map(Vel::Tiny),
                1 => (-1i8..=1).prop_map(Vel::Vmax),
            ]
        }

        fn resolve_vel(v: Vel, vmax: f64) -> f64 {
            match v {
                Vel::Value(x) => x,
                Vel::Frac(u) => u * vmax,
                Vel::Tiny(u) => vmax * (-1100.0 * u).exp2(),
                Vel::Vmax(k) => ulps(vmax, k),
            }
        }

        /// A distance: any value, log-uniform 1e-12..1e16 counts, a factor or ±1 ulp of the
        /// shortest feasible distance, a factor of the distance that reaches vmax, or one that
        /// takes about MAX_MOVE_TIME at vmax.
        #[derive(Clone, Copy, Debug)]
        enum Dist {
            Value(f64),
            Log(f64),
            Shortest(f64),
            ShortestUlps(i8),
            Cruise(f64),
            Longest(f64),
        }

        fn dist() -> impl Strategy<Value = (Dist, bool)> {
            let d = prop_oneof![
                1 => wild().prop_map(Dist::Value),
                4 => (0.0..=1.0f64).prop_map(Dist::Log),
                1 => (0.5..2.0f64).prop_map(Dist::Shortest),
                1 => (-1i8..=1).prop_map(Dist::ShortestUlps),
                1 => (0.3..3.0f64).prop_map(Dist::Cruise),
                1 => (0.9..1.1f64).prop_map(Dist::Longest),
            ];
            (d, any::<bool>())
        }

        fn resolve_dist(d: (Dist, bool), v0: f64, v1: f64, l: &Limits) -> f64 {
            let shortest = || ref_dist(v0, v1, v0.max(v1), l).1;
            let mag = match d.0 {
                Dist::Value(x) => x,
                Dist::Log(u) => 10f64.powf(-12.0 + 28.0 * u),
                Dist::Shortest(f) => shortest() * f,
                Dist::ShortestUlps(k) => ulps(shortest(), k),
                Dist::Cruise(f) => ref_dist(v0, v1, l.vmax, l).1 * f,
                Dist::Longest(f) => l.vmax * crate::MAX_MOVE_TIME * f,
            };
            if d.1 {
                -mag
            } else {
                mag
            }
        }

        fn start_pos() -> impl Strategy<Value = f64> {
            prop_oneof![
                2 => Just(0.0),
                2 => -1e3..1e3f64,
                2 => -crate::MAX_POSITION..=crate::MAX_POSITION,
                1 => wild(),
            ]
        }

        fn rate() -> impl Strategy<Value = u32> {
            prop_oneof![
                1 => Just(1000u32),
                1 => Just(20_000u32),
                4 => 1000u32..=20_000,
            ]
        }

        /// The refusal the request earns before any planning, in `plan_checked`'s order.
        fn refusal(p0: f64, d: f64, v0: f64, v1: f64, l: &Limits, rate: u32) -> Option<PlanError> {
            let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
            let orders = [1, 2, 2, 3, 3, 3, 3];
            if ![p0, d, v0, v1].iter().all(|x| x.is_finite()) || !all.iter().all(|x| x.is_finite())
            {
                Some(PlanError::NonFinite)
            } else if all.iter().any(|&x| x <= 0.0) {
                Some(PlanError::NonPositiveLimit)
            } else if all
                .iter()
                .zip(orders)
                .any(|(x, k)| !limit_range(k, rate).contains(x))
            {
                Some(PlanError::LimitRange)
            } else if v0 > l.vmax {
                Some(PlanError::StartVelocityTooHigh)
            } else if v0 < 0.0 || v1 < 0.0 || v1 > l.vmax {
                Some(PlanError::Infeasible)
            } else {
                None
            }
        }

        fn index(e: PlanError) -> usize {
            match e {
                PlanError::NonFinite => 0,
                PlanError::NonPositiveLimit => 1,
                PlanError::LimitRange => 2,
                PlanError::StartVelocityTooHigh => 3,
                PlanError::Infeasible => 4,
                PlanError::PlanCheck => 5,
            }
        }

        #[derive(Default, Debug)]
        struct Figures {
            /// Refusals by error (NonFinite, NonPositiveLimit, LimitRange,
            /// StartVelocityTooHigh, Infeasible, PlanCheck), then accepted.
            outcomes: [usize; 7],
            /// Accepted plans with non-zero boundary velocities, and ones reaching vmax.
            moving_ends: usize,
            at_vmax: usize,
            /// Worst relative limit excess (velocity, acceleration, jerk) sampled densely.
            limit_excess: f64,
            /// Worst end-position error of the integrated profile, in ulps of max(|p0|, |d|)
            /// where that is at least 1 count, and in counts where it is less.
            end_ulps: f64,
            end_small: f64,
            /// Infeasible: shorter than the shortest distance, or longer than MAX_MOVE_TIME.
            too_short: usize,
            too_long: usize,
            /// Plans the bare planner makes from limits out of range (positive and finite):
            /// passed the check (and then kept every limit), too long, failed the check.
            net: [usize; 3],
            /// Worst relative mismatch of the duration against the reference minimum time.
            time_rel: f64,
        }

        const CASES: u32 = 100_000;

        #[test]
        fn plan_checked_over_the_whole_f64_range() {
            let strategy = (
                prop::array::uniform7(pick()),
                0u8..3,
                rate(),
                (vel(), vel()),
                dist(),
                start_pos(),
            );
            let fig = RefCell::new(Figures::default());
            let result = runner(CASES, 0x5c).run(&strategy, |(p, tie, rate, (a, b), dd, p0)| {
                let l = limits(p, tie, rate);
                let (v0, v1) = (resolve_vel(a, l.vmax), resolve_vel(b, l.vmax));
                let d = resolve_dist(dd, v0, v1, &l);
                let r = Profile::plan_checked(p0, d, v0, v1, &l, rate);
                let mut f = fig.borrow_mut();
                let case = format!("p0={p0:e} d={d:e} v0={v0:e} v1={v1:e} {l:?} rate={rate}");
                if let Some(e) = refusal(p0, d, v0, v1, &l, rate) {
                    prop_assert_eq!(r.map(|_| ()), Err(e), "{}", case);
                    f.outcomes[index(e)] += 1;
                    // The check as a safety net under the range check: a plan the bare
                    // planner makes from out-of-range limits runs only if it passes, and
                    // then it must keep every limit and reach its target.
                    if e == PlanError::LimitRange {
                        if let Ok(p) = Profile::plan(p0, d, v0, v1, &l) {
                            match p.verify_plan(p0, d, v0, v1, &l) {
                                Ok(()) => {
                                    // (the test's tolerances are relative to the limits:
                                    // meaningless for limits near the subnormals, where the
                                    // check allows MIN_POSITIVE)
                                    // (and slots shorter than the normal range, whose few
                                    // bits the check allows for)
                                    let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
                                    let normal = |t: &f64| *t == 0.0 || t.is_normal();
                                    if all.iter().all(|&x| x >= 1e-290)
                                        && p.phases().iter().all(normal)
                                    {
                                        check_plan(&p, &l, p0, d, v0, v1);
                                    }
                                    f.net[0] += 1;
                                }
                                Err(PlanError::Infeasible) => f.net[1] += 1,
                                Err(_) => f.net[2] += 1,
                            }
                        }
                    }
                    return Ok(());
                }
                let dist = d.abs();
                let shortest = ref_dist(v0, v1, v0.max(v1), &l).1;
                let reference = ref_min_time(v0, v1, dist, &l);
                match r {
                    Ok(p) => {
                        let w = check_plan(&p, &l, p0, d, v0, v1);
                        let t = p.duration();
                        prop_assert!(t.is_finite() && t <= crate::MAX_MOVE_TIME, "{}", case);
                        let tol = 8.0 * f64::EPSILON * p0.abs().max(dist) + 1e-12;
                        prop_assert!(t >= (dist - tol) / l.vmax * (1.0 - 1e-9), "{t:e} {}", case);
                        prop_assert!(shortest <= dist * (1.0 + 1e-9) + tol, "{}", case);
                        // (None: accepted within rounding of the shortest distance; the
                        // reference's bisection ends on a tiny vp for d = 0)
                        let t_ref = match reference {
                            _ if dist == 0.0 => 0.0,
                            Some((t_ref, _)) => t_ref,
                            None => t,
                        };
                        let rel = (t - t_ref).abs() / t_ref.max(f64::MIN_POSITIVE);
                        if dist > 1e-250 {
                            prop_assert!(rel <= 1e-9, "duration {t:e} vs {t_ref:e}: {}", case);
                            f.time_rel = f.time_rel.max(rel);
                        }
                        let err = (p.slot_end(6).0 - dist).abs();
                        let scale = p0.abs().max(dist);
                        if scale >= 1.0 {
                            f.end_ulps = f.end_ulps.max(err / (f64::EPSILON * scale));
                        } else {
                            f.end_small = f.end_small.max(err);
                        }
                        f.limit_excess = f.limit_excess.max(w.limit_excess);
                        f.outcomes[6] += 1;
                        f.moving_ends += usize::from(v0 > 0.0 || v1 > 0.0);
                        f.at_vmax += usize::from(p.peak_velocity() == l.vmax);
                    }
                    Err(PlanError::Infeasible) => {
                        let too_long =
                            reference.is_some_and(|(t, _)| t > crate::MAX_MOVE_TIME * (1.0 - 1e-9));
                        let too_short = shortest > dist * (1.0 - 1e-9);
                        prop_assert!(too_short || too_long, "refused a feasible move: {}", case);
                        f.too_short += usize::from(too_short);
                        f.too_long += usize::from(!too_short);
                        f.outcomes[4] += 1;
                    }
                    Err(PlanError::NonFinite) => {
                        // the positions or the cruise time overflow
                        let overflow = p0.abs() + dist > 1e300 || !(dist / l.vmax).is_finite();
                        prop_assert!(overflow, "{}", case);
                        f.outcomes[0] += 1;
                    }
                    Err(e) => prop_assert!(false, "{e:?} for limits in range: {}", case),
                }
                Ok(())
            });
            let f = fig.into_inner();
            eprintln!("plan_checked, {CASES} cases: {f:?}");
            if let Err(e) = result {
                panic!("{e}");
            }
            // Every way of refusing, and enough accepted plans of each kind.
            assert!(
                f.outcomes
                    .iter()
                    .enumerate()
                    .all(|(i, &n)| n >= 200 || i == 5),
                "{f:?}"
            );
            assert_eq!(f.outcomes[5], 0);
            assert!(f.moving_ends >= 500 && f.at_vmax >= 500, "{f:?}");
        }

        /// A stop's start velocity: any value, 0, or log-uniform up to the velocity range's
        /// top; signed.
        #[derive(Clone, Copy, Debug)]
        enum StopVel {
            Value(f64),
            Zero,
            Log(f64),
        }

        /// A stop's start acceleration (along the velocity): any value, 0, a factor of dmax,
        /// or a factor (or ±1 ulp) of the largest deceleration that can be ramped out at j7
        /// without reversing, `sqrt(2 j7 v)`.
        #[derive(Clone, Copy, Debug)]
        enum StopAcc {
            Value(f64),
            Zero,
            Dmax(f64),
            Reverse(f64),
            ReverseUlps(i8),
        }

        fn stop_state() -> impl Strategy<Value = (f64, (StopVel, bool), StopAcc)> {
            let v = prop_oneof![
                1 => wild().prop_map(StopVel::Value),
                1 => Just(StopVel::Zero),
                6 => (0.0..=1.0f64).prop_map(StopVel::Log),
            ];
            let a = prop_oneof![
                1 => wild().prop_map(StopAcc::Value),
                2 => Just(StopAcc::Zero),
                4 => (-4.0..3.0f64).prop_map(StopAcc::Dmax),
                2 => (0.5..2.0f64).prop_map(StopAcc::Reverse),
                1 => (-1i8..=1).prop_map(StopAcc::ReverseUlps),
            ];
            (start_pos(), (v, any::<bool>()), a)
        }

        #[derive(Default, Debug)]
        struct StopFigures {
            /// Refusals by error (as for plans), then accepted.
            outcomes: [usize; 7],
            /// Accepted stops with a > 0, with a deceleration beyond dmax, from v = 0.
            kinds: [usize; 3],
            /// Worst relative jerk or deceleration excess (sampled densely).
            excess: f64,
            /// Worst backwards velocity relative to the stop's peak velocity.
            backwards: f64,
            /// Longest accepted stop, s.
            longest: f64,
            /// Accepted stops from a state beyond what the card can hold (position, velocity or
            /// acceleration out of range): checked by the card's check only.
            beyond: usize,
        }

        #[test]
        fn stop_checked_over_the_whole_f64_range() {
            let strategy = (
                prop::array::uniform4(pick()),
                0u8..2,
                prop::option::weighted(0.1, prop::array::uniform3(wild())),
                rate(),
                stop_state(),
            );
            let fig = RefCell::new(StopFigures::default());
            let result = runner(CASES, 0x57).run(&strategy, |(p, tie, other, rate, st)| {
                let x = |i: usize, order| resolve(p[i], order, rate);
                let (dmax, j3) = (x(0, 2), x(1, 3));
                let (j5, j7) = if tie == 1 {
                    (j3, j3)
                } else {
                    (x(2, 3), x(3, 3))
                };
                // As the axis stops: vmax = f64::MAX, amax = dmax, j1 = j3 (or anything).
                let [vmax, amax, j1] = other.unwrap_or([f64::MAX, dmax, j3]);
                let l = Limits {
                    vmax,
                    amax,
                    dmax,
                    j1,
                    j3,
                    j5,
                    j7,
                };
                let (p0, (sv, neg), sa) = st;
                let top = *limit_range(1, rate).end();
                let v = match sv {
                    StopVel::Value(x) => x,
                    StopVel::Zero => 0.0,
                    StopVel::Log(u) => (1e-12f64.ln() + u * (top.ln() - 1e-12f64.ln())).exp(),
                };
                let reverse = (2.0 * j7).sqrt() * v.abs().sqrt();
                let a = match sa {
                    StopAcc::Value(x) => x,
                    StopAcc::Zero => 0.0,
                    StopAcc::Dmax(f) => f * dmax,
                    StopAcc::Reverse(f) => -f * reverse,
                    StopAcc::ReverseUlps(k) => -ulps(reverse, k),
                };
                let (v0, a0) = if neg { (-v, -a) } else { (v, a) };
                let r = Profile::stop_checked(p0, v0, a0, &l, rate);
                let case = format!("p0={p0:e} v0={v0:e} a0={a0:e} {l:?} rate={rate}");
                let mut f = fig.borrow_mut();
                let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
                let used = [(2, dmax), (3, j3), (3, j5), (3, j7)];
                let want = if ![p0, v0, a0].iter().chain(&all).all(|x| x.is_finite()) {
                    Some(PlanError::NonFinite)
                } else if all.iter().any(|&x| x <= 0.0) {
                    Some(PlanError::NonPositiveLimit)
                } else if used.iter().any(|(k, x)| !limit_range(*k, rate).contains(x)) {
                    Some(PlanError::LimitRange)
                } else {
                    None
                };
                if let Some(e) = want {
                    prop_assert_eq!(r.map(|_| ()), Err(e), "{}", case);
                    f.outcomes[index(e)] += 1;
                    return Ok(());
                }
                // Motion frame: the direction of v0, or of a0 from rest.
                let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
                    1.0
                } else {
                    -1.0
                };
                let (v, a) = (v0.abs(), dir * a0);
                let need = if a < 0.0 { 0.5 * a * (a / j7) } else { 0.0 };
                // A state the card can hold: from one beyond (1e210 counts/s) the test's own
                // extrapolation overflows.
                let sane = p0.abs() <= crate::MAX_POSITION
                    && v <= top
                    && a.abs() <= *limit_range(2, rate).end();
                match r {
                    Ok(p) => {
                        if sane {
                            f.excess = f.excess.max(check_stop(&p, &l, p0, v0, a0));
                        } else {
                            f.beyond += 1;
                        }
                        prop_assert!(p.duration().is_finite(), "{}", case);
                        prop_assert!(v >= need * (1.0 - 1e-9), "must reverse: {}", case);
                        let (vlow, vhigh) = p.velocity_range();
                        let back = (-vlow / vhigh.max(v).max(f64::MIN_POSITIVE)).max(0.0);
                        f.backwards = f.backwards.max(back);
                        f.longest = f.longest.max(p.duration());
                        f.outcomes[6] += 1;
                        f.kinds[0] += usize::from(a > 0.0 && v > 0.0);
                        f.kinds[1] += usize::from(-a > dmax);
                        f.kinds[2] += usize::from(v == 0.0);
                    }
                    Err(PlanError::Infeasible) => {
                        prop_assert!(a < 0.0 && v < need * (1.0 + 1e-9), "{}", case);
                        f.outcomes[4] += 1;
                    }
                    // Only from a state beyond anything the card holds: the stop overflows,
                    // or loses its velocity to rounding (its check refuses it).
                    Err(e @ (PlanError::NonFinite | PlanError::PlanCheck)) => {
                        prop_assert!(!sane, "{e:?}: {}", case);
                        f.outcomes[index(e)] += 1;
                    }
                    Err(e) => prop_assert!(false, "{e:?} for limits in range: {}", case),
                }
                Ok(())
            });
            let f = fig.into_inner();
            eprintln!("stop_checked, {CASES} cases: {f:?}");
            if let Err(e) = result {
                panic!("{e}");
            }
            let o = f.outcomes;
            assert!(
                o[0] >= 200 && o[1] >= 200 && o[2] >= 200 && o[4] >= 200,
                "{f:?}"
            );
            assert!(
                o[6] >= CASES as usize / 2 && f.kinds.iter().all(|&n| n >= 1000),
                "{f:?}"
            );
            assert!(o[5] <= CASES as usize / 1000, "{f:?}");
        }
    }
}
