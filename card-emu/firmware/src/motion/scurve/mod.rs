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
mod tests;
