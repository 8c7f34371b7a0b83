//! The path-speed planner: a continuous jerk-limited speed profile along a path (speed and
//! acceleration continuous, |jerk| ≤ J), integrated exactly over each tick, that plans its
//! stop to come to rest exactly at the remaining distance (re-solved every tick).
//!
//! A look-ahead that needs this tick's ramp step to choose its target keeps it
//! ([`PathSpeedPlanner::track`]) and hands it back ([`PathSpeedPlanner::next_tracked`]), so
//! the step is computed once. Far from the stop point the check that no stop is due yet is
//! made with a closed-form upper bound of the stopping distance
//! ([`PathSpeedPlanner::stopping_distance_bound`]: the stop from a = 0 at the speed where the
//! acceleration would be 0, and the ramp down to it) before the exact one. The slowing
//! distance to a lower speed has a closed form too where the ramp is the common descent
//! through the state (`slowing_estimate`: the descent from the speed at a = 0, plus or minus
//! the part between; it grows with that speed at V/(2D) at least, which a look-ahead uses to
//! keep a test's result for later ticks).
//!
//! [`PathSpeedPlanner::next`] allocates nothing and never panics.

use super::interp_error::InterpError;
use super::pos_finite;
use crate::math;

/// Relative margin below the jerk and deceleration limits with which the planner decides
/// when to stop: the stop it then follows may use the full limits, so the small corrections a
/// stop needs on a curve (the remaining length is re-estimated every tick) always fit.
pub const PLAN_MARGIN: f64 = 1e-3;

/// An acceleration this far (relative) beyond a limit is brought back within it by a phase
/// of its own; less is rounding, clamped as before.
const SHED: f64 = 1e-9;

/// The lesser of two numbers that are not NaN.
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// Up to seven phases of constant jerk: a piece of a continuous path-speed profile (speed and
/// acceleration continuous, |jerk| ≤ J).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Phases {
    j: [f64; 7],
    t: [f64; 7],
    n: usize,
}

impl Phases {
    /// The phases of `phases` (jerk, duration) that run, in order.
    fn of(phases: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let mut p = Self::default();
        for (j, t) in phases {
            p.push(j, t);
        }
        p
    }

    fn push(&mut self, j: f64, t: f64) {
        if runs(t) && self.n < 7 {
            self.j[self.n] = j;
            self.t[self.n] = t;
            self.n += 1;
        }
    }

    fn duration(&self) -> f64 {
        self.t[..self.n].iter().sum()
    }

    /// The phases, (jerk, duration) each.
    fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.j[..self.n]
            .iter()
            .copied()
            .zip(self.t[..self.n].iter().copied())
    }

    /// Distance, speed and acceleration `dt` into the profile started at (v, a) (see
    /// [`sample_phases`]).
    fn sample(&self, v: f64, a: f64, dt: f64) -> (f64, f64, f64) {
        sample_phases(self.iter(), v, a, dt)
    }
}

/// Three phases of constant jerk, (jerk, duration) each, in order: a ramp or a stop
/// ([`PathSpeedPlanner::track_ramp`], [`PathSpeedPlanner::brake_ramp`]), a phase that does
/// not [`run`](runs) included.
type Ramp3 = [(f64, f64); 3];

/// Whether a phase of this duration is run: positive and finite (`Phases::push` drops the
/// others). Written as two comparisons (`t > 0.0 && t.is_finite()` is the same test, but
/// compiles to a test of the bits, some twenty instructions).
#[inline(always)]
fn runs(t: f64) -> bool {
    t > 0.0 && t <= f64::MAX
}

/// A profile being sampled phase by phase ([`sample_phases`]): the distance, speed and
/// acceleration so far, and the time left to sample.
struct Sampling {
    d: f64,
    v: f64,
    a: f64,
    left: f64,
}

impl Sampling {
    /// `dt` of a profile started at (v, a) to sample.
    #[inline(always)]
    fn new(v: f64, a: f64, dt: f64) -> Self {
        Self {
            d: 0.0,
            v,
            a,
            left: dt,
        }
    }

    /// Runs the phase of jerk `j` and duration `tk` for as much of it as the time left
    /// holds (nothing when it does not [`run`](runs)); true when the sample ends there (no
    /// time left before it, or within it).
    #[inline(always)]
    fn phase(&mut self, j: f64, tk: f64) -> bool {
        if !runs(tk) {
            return false;
        }
        if self.left <= 0.0 {
            return true;
        }
        // tk.min(left), tk being a number
        let t = if self.left < tk { self.left } else { tk };
        let (v, a) = (self.v, self.a);
        self.d += t * (v + t * (0.5 * a + t * j / 6.0));
        self.v += t * (a + 0.5 * j * t);
        self.a += j * t;
        if t < tk {
            return true;
        }
        self.left -= t;
        false
    }

    /// (distance, speed, acceleration) where the sample ended within the profile.
    #[inline(always)]
    fn within(&self) -> (f64, f64, f64) {
        (self.d, self.v, self.a)
    }

    /// (distance, speed, acceleration) after the profile's end: the speed held for the time
    /// left, a = 0.
    #[inline(always)]
    fn after(&self) -> (f64, f64, f64) {
        let mut d = self.d;
        if self.left > 0.0 {
            d += self.v * self.left;
        }
        (d, self.v, 0.0)
    }
}

/// Distance, speed and acceleration `dt` into the profile of `phases` (jerk, duration)
/// started at (v, a), a phase that does not [`run`](runs) skipped (so for the phases of a
/// [`Phases`], all of which run, its `sample`). Every profile ends with a = 0; after its end
/// the speed is held.
#[inline(always)]
fn sample_phases(
    phases: impl IntoIterator<Item = (f64, f64)>,
    v: f64,
    a: f64,
    dt: f64,
) -> (f64, f64, f64) {
    let mut s = Sampling::new(v, a, dt);
    for (j, t) in phases {
        if s.phase(j, t) {
            return s.within();
        }
    }
    s.after()
}

/// [`sample_phases`] of three phases, unrolled: what `Phases::sample` gives for the phases
/// pushed, without building them (the ramp of a tick, [`PathSpeedPlanner::track`]).
#[inline(always)]
fn sample_three(phases: Ramp3, v: f64, a: f64, dt: f64) -> (f64, f64, f64) {
    let [(j0, t0), (j1, t1), (j2, t2)] = phases;
    let mut s = Sampling::new(v, a, dt);
    if s.phase(j0, t0) || s.phase(j1, t1) || s.phase(j2, t2) {
        s.within()
    } else {
        s.after()
    }
}

/// Runs the whole of `phases` (jerk, duration) from distance, speed and acceleration
/// `(d, v, a)`, a phase that does not [`run`](runs) skipped (as [`sample_phases`]): the
/// distance, speed and acceleration at their end. Running two lists one after the other is
/// running them as one.
#[inline(always)]
fn run_phases(
    phases: impl IntoIterator<Item = (f64, f64)>,
    (mut d, mut v, mut a): (f64, f64, f64),
) -> (f64, f64, f64) {
    for (j, t) in phases {
        if runs(t) {
            d += t * (v + t * (0.5 * a + t * j / 6.0));
            v += t * (a + 0.5 * j * t);
            a += j * t;
        }
    }
    (d, v, a)
}

/// Distance of the whole profile of `phases` from (v, a) (see [`run_phases`]).
#[inline(always)]
fn phases_distance(phases: impl IntoIterator<Item = (f64, f64)>, v: f64, a: f64) -> f64 {
    run_phases(phases, (0.0, v, a)).0
}

/// One tick of the ramp toward a target from a planner's state ([`PathSpeedPlanner::track`]):
/// the distance, speed and acceleration at the end of the tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Track {
    tgt: f64,
    /// The state it was computed from (v, a).
    from: (f64, f64),
    ds: f64,
    v: f64,
    a: f64,
}

impl Track {
    /// (distance, speed, acceleration) at the end of the tick.
    #[inline(always)]
    pub fn step(&self) -> (f64, f64, f64) {
        (self.ds, self.v, self.a)
    }
}

/// The profile of a planner's last tick, from the state it started at: what
/// [`PathSpeedPlanner::sample_step`] samples within the tick (a path planned every few servo
/// ticks is interpolated on it in between).
#[derive(Debug, Clone, Copy, PartialEq)]
enum StepProfile {
    /// At rest, or not planned yet.
    Rest,
    /// The ramp toward `tgt` from (v, a) ([`PathSpeedPlanner::track_sample`]).
    Ramp { v: f64, a: f64, tgt: f64 },
    /// A stop from (v, a).
    Stop { v: f64, a: f64, phases: Phases },
}

/// Scalar jerk-limited speed planner along the path. Its state is a continuous profile of the
/// path speed v(t) with a = dv/dt ∈ [−D, A] and |da/dt| ≤ J, integrated exactly over each
/// tick, and each tick's step is the distance that profile covers in the tick. Because a tick's
/// step over Ts is the mean of v over the tick, the sampled feed (step/Ts), its first and its
/// second difference over Ts and Ts² are weighted means of v, a and j: they keep the same
/// limits, up to rounding.
///
/// Each tick it follows the time-optimal ramp toward the target speed unless that would leave
/// less room than a stop needs (planned with [`PLAN_MARGIN`] below the limits); from then on it
/// follows a stop that comes to rest exactly at the remaining distance, re-solved every tick
/// from the current state (so a remaining distance that grows, because more path was queued,
/// lets it speed up again without a jump).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSpeedPlanner {
    pub(super) ts: f64,
    pub(super) amax: f64,
    pub(super) dmax: f64,
    pub(super) jmax: f64,
    pub(super) v: f64,
    pub(super) a: f64,
    /// The deceleration and jerk limits of stops (at most `dmax` and `jmax`, which are used
    /// where these are higher): a path whose limits differ from piece to piece ramps within
    /// those of the pieces near it and stops within those of every piece up to the stop point
    /// (see [`set_limits`](Self::set_limits)). ∞: the same as the ramps'.
    pub(super) sd: f64,
    pub(super) sj: f64,
    stopping: bool,
    lands: bool,
    /// The last tick's profile.
    step: StepProfile,
    /// The tick the positions are sampled at: `ts`, or a fraction of it where the path
    /// plans every few servo ticks (`Path::reset`).
    pub(super) servo_ts: f64,
}

impl PathSpeedPlanner {
    /// New planner at rest with acceleration and deceleration limit `amax` and jerk `jmax`.
    pub fn new(ts: f64, amax: f64, jmax: f64) -> Result<Self, InterpError> {
        if !(pos_finite(ts) && ts <= 1.0) {
            return Err(InterpError::BadSampleTime);
        }
        if !pos_finite(amax) {
            return Err(InterpError::BadAccel);
        }
        if !pos_finite(jmax) {
            return Err(InterpError::BadJerk);
        }
        Ok(Self {
            ts,
            amax,
            dmax: amax,
            jmax,
            v: 0.0,
            a: 0.0,
            sd: f64::INFINITY,
            sj: f64::INFINITY,
            stopping: false,
            lands: false,
            step: StepProfile::Rest,
            servo_ts: ts,
        })
    }

    /// A planner at rest for a motion not planned yet (1 ms, unit limits; [`new`](Self::new)
    /// checks real ones).
    pub(crate) fn unplanned() -> Self {
        Self {
            ts: 1e-3,
            amax: 1.0,
            dmax: 1.0,
            jmax: 1.0,
            v: 0.0,
            a: 0.0,
            sd: f64::INFINITY,
            sj: f64::INFINITY,
            stopping: false,
            lands: false,
            step: StepProfile::Rest,
            servo_ts: 1e-3,
        }
    }

    /// Sets a separate (usually lower) deceleration limit, counts/s².
    pub fn with_decel(mut self, dmax: f64) -> Result<Self, InterpError> {
        if !pos_finite(dmax) {
            return Err(InterpError::BadAccel);
        }
        self.dmax = dmax;
        Ok(self)
    }

    /// Path speed at the end of the last tick, counts/s.
    pub fn speed(&self) -> f64 {
        self.v
    }
    /// Path acceleration at the end of the last tick, counts/s².
    pub fn accel(&self) -> f64 {
        self.a
    }
    /// Acceleration limit, counts/s².
    pub fn accel_limit(&self) -> f64 {
        self.amax
    }
    /// Deceleration limit in use, counts/s².
    pub fn decel_limit(&self) -> f64 {
        self.dmax
    }
    /// Jerk limit, counts/s³.
    pub fn jerk_limit(&self) -> f64 {
        self.jmax
    }
    /// True while the planner follows a stop at the remaining distance.
    pub fn is_stopping(&self) -> bool {
        self.stopping
    }
    /// True when the last tick's stop came to rest within the tick (at the remaining distance).
    pub fn lands(&self) -> bool {
        self.lands
    }

    /// Takes over the motion state of another planner (the previous curve of a path).
    pub fn continue_from(&mut self, other: &PathSpeedPlanner) {
        self.v = other.v;
        self.a = other.a.clamp(-self.dmax, self.amax);
        self.stopping = other.stopping;
        self.lands = false;
    }

    /// The limits of the ramps (acceleration and deceleration `a`, jerk `j`) and of stops
    /// (`sd`, `sj`: within those of every piece up to where a stop could end; lowered to the
    /// ramps' where those are lower). An acceleration beyond the new limits is brought within
    /// them at the jerk limit (never a jump).
    pub fn set_limits(&mut self, a: f64, j: f64, sd: f64, sj: f64) {
        self.amax = a;
        self.dmax = a;
        self.jmax = j;
        self.sd = sd;
        self.sj = sj;
    }

    /// Deceleration and jerk limits of stops.
    #[inline(always)]
    pub(super) fn stop_limits(&self) -> (f64, f64) {
        (lesser(self.sd, self.dmax), lesser(self.sj, self.jmax))
    }

    /// Jerk and deceleration the stop decision is planned with.
    #[inline(always)]
    pub(super) fn plan_limits(&self) -> (f64, f64) {
        let (d, j) = self.stop_limits();
        (j * (1.0 - PLAN_MARGIN), d * (1.0 - PLAN_MARGIN))
    }

    /// Time-optimal jerk-limited ramp from (v, a) to speed `tgt` with a = 0 at the end: the
    /// acceleration it starts from (`a` within the limits) and its three phases, (jerk,
    /// duration) toward the peak, the hold, and back to a = 0. A phase whose duration is not
    /// positive and finite is not run (`Phases::push` drops it).
    #[inline(always)]
    fn track_ramp(&self, v: f64, a: f64, tgt: f64) -> (f64, Ramp3) {
        let j = self.jmax;
        // Beyond a limit lowered under it (a path's limits change from piece to piece): the
        // acceleration is brought back within it at the jerk limit, then the ramp goes on.
        if a > self.amax * (1.0 + SHED) {
            let flat = v + a * a / (2.0 * j);
            if tgt >= flat {
                let am = self.amax;
                return (
                    a,
                    [(-j, (a - am) / j), (0.0, (tgt - flat) / am), (-j, am / j)],
                );
            }
        } else if a < -self.dmax * (1.0 + SHED) {
            let flat = v - a * a / (2.0 * j);
            if tgt < flat {
                let dm = self.dmax;
                return (
                    a,
                    [(j, (-a - dm) / j), (0.0, (flat - tgt) / dm), (j, dm / j)],
                );
            }
        }
        let a = if a > self.amax * (1.0 + SHED) || a < -self.dmax * (1.0 + SHED) {
            // (the other direction: the ramp turns the acceleration around at once)
            a
        } else {
            a.clamp(-self.dmax, self.amax)
        };
        // the speed reached by bringing a to zero at once
        let flat = v + a * a.abs() / (2.0 * j);
        let phases = if tgt >= flat {
            let dv = tgt - v;
            let mut ap = math::sqrt((j * dv + 0.5 * a * a).max(0.0));
            let mut th = 0.0;
            if ap > self.amax {
                ap = self.amax;
                th = ((dv - (2.0 * ap * ap - a * a) / (2.0 * j)) / ap).max(0.0);
            }
            let ap = ap.max(a);
            [(j, (ap - a) / j), (0.0, th), (-j, ap / j)]
        } else {
            let dv = v - tgt;
            let mut dp = math::sqrt((j * dv + 0.5 * a * a).max(0.0));
            let mut th = 0.0;
            if dp > self.dmax {
                dp = self.dmax;
                th = ((dv - (2.0 * dp * dp - a * a) / (2.0 * j)) / dp).max(0.0);
            }
            let dp = dp.max(-a);
            [(-j, (a + dp) / j), (0.0, th), (j, dp / j)]
        };
        (a, phases)
    }

    /// The distance, speed and acceleration `dt` into the ramp toward `tgt`
    /// ([`track_ramp`](Self::track_ramp)'s phases that run), sampled from `a` as given (not
    /// from the clamped one the ramp starts from), without building the phases.
    #[inline]
    fn track_sample(&self, v: f64, a: f64, tgt: f64, dt: f64) -> (f64, f64, f64) {
        let (_, phases) = self.track_ramp(v, a, tgt);
        sample_three(phases, v, a, dt)
    }

    /// A stop from (v, a) through a peak deceleration `ap`: jerk toward −ap, hold it, jerk +J
    /// back to zero, ending at rest. Its three phases, (jerk, duration) each, as
    /// [`track_ramp`](Self::track_ramp)'s: one that does not run is dropped by
    /// [`brake_phases`](Self::brake_phases) and skipped by `phases_distance`.
    #[inline(always)]
    fn brake_ramp(v: f64, a: f64, ap: f64, j: f64) -> Ramp3 {
        let t1 = (a + ap).abs() / j;
        let j1 = if a + ap >= 0.0 { -j } else { j };
        let v1 = v + 0.5 * (a - ap) * t1;
        let th = ((v1 - ap * ap / (2.0 * j)) / ap).max(0.0);
        [(j1, t1), (0.0, th), (j, ap / j)]
    }

    /// [`brake_ramp`](Self::brake_ramp) as phases to run.
    fn brake_phases(v: f64, a: f64, ap: f64, j: f64) -> Phases {
        Phases::of(Self::brake_ramp(v, a, ap, j))
    }

    /// The distance of `brake_phases(v, a, ap, j)`, summed phase by phase over the phases
    /// that run (not [`brake_distance`](Self::brake_distance)'s closed form, which rounds
    /// differently), without building them.
    fn brake_phases_distance(v: f64, a: f64, ap: f64, j: f64) -> f64 {
        phases_distance(Self::brake_ramp(v, a, ap, j), v, a)
    }

    /// The distance of `brake_phases(v, a, ap, j)`, in closed form.
    fn brake_distance(v: f64, a: f64, ap: f64, j: f64) -> f64 {
        let t1 = (a + ap).abs() / j;
        let j1 = if a + ap >= 0.0 { -j } else { j };
        let d1 = t1 * (v + t1 * (0.5 * a + t1 * j1 / 6.0));
        let v1 = v + 0.5 * (a - ap) * t1;
        let v2 = ap * ap / (2.0 * j);
        let d2 = if v1 > v2 {
            (v1 * v1 - v2 * v2) / (2.0 * ap)
        } else {
            0.0
        };
        // the last phase from (v2', −ap) with v2' = v1 when there is no hold
        let v3 = v1.min(v2);
        let t3 = ap / j;
        d1 + d2 + t3 * (v3 + t3 * (-0.5 * ap + t3 * j / 6.0))
    }

    /// The peak deceleration of the shortest stop from (v, a) with deceleration ≤ `d` and jerk
    /// `j`; None when the state cannot come to rest without a jump in acceleration (braking so
    /// hard that the speed reaches zero before the acceleration does).
    fn brake_peak(v: f64, a: f64, d: f64, j: f64) -> Option<f64> {
        let opt = math::sqrt(j * v.max(0.0) + 0.5 * a * a);
        // (a deceleration beyond `d` is brought back within it: see `set_limits`)
        let ap = if -a <= d * (1.0 + SHED) {
            d.min(opt).max(-a)
        } else {
            d.min(opt)
        };
        (a >= -opt * (1.0 + 1e-12) && ap > 0.0).then_some(ap)
    }

    /// Distance to come to rest (v = 0, a = 0) from speed `v ≥ 0` and acceleration `a`
    /// with deceleration ≤ `dmax` and jerk `jmax` (time-optimal stop).
    #[inline(always)]
    pub fn stopping_distance(v: f64, a: f64, dmax: f64, jmax: f64) -> f64 {
        let v = v.max(0.0);
        if v == 0.0 && a <= 0.0 {
            return 0.0;
        }
        match Self::brake_peak(v, a, dmax, jmax) {
            Some(ap) => Self::brake_distance(v, a, ap, jmax).max(0.0),
            None => {
                // release at +J until the speed is zero
                let t = (-a - math::sqrt((a * a - 2.0 * jmax * v).max(0.0))) / jmax;
                (v * t + 0.5 * a * t * t + jmax * t * t * t / 6.0).max(0.0)
            }
        }
    }

    /// Distance of the shortest stop from (v, a) that ends with a = 0 (∞ when none does).
    fn clean_stopping_distance(v: f64, a: f64, dmax: f64, jmax: f64) -> f64 {
        let v = v.max(0.0);
        if v == 0.0 && a <= 0.0 {
            return if a == 0.0 { 0.0 } else { f64::INFINITY };
        }
        match Self::brake_peak(v, a, dmax, jmax) {
            Some(ap) => Self::brake_distance(v, a, ap, jmax).max(0.0),
            None => f64::INFINITY,
        }
    }

    /// The distance of the ramp toward `tgt` ([`track_ramp`](Self::track_ramp)'s phases, each
    /// counted only when `Phases::push` would keep it: a positive, finite duration), from
    /// the clamped acceleration.
    pub(crate) fn track_distance(&self, v: f64, a: f64, tgt: f64) -> f64 {
        let (a, phases) = self.track_ramp(v, a, tgt);
        phases_distance(phases, v, a)
    }

    /// An upper bound of [`stopping_distance`](Self::stopping_distance)`(v, a, d, j)` (and of
    /// the clean stop's) that costs no root and no trial stop (∞ where it does not hold): the stop from (v, a) is the tail of the stop
    /// from the speed v_p = v + a²/(2j) at a = 0 (a ≤ 0, within its peak) or that stop after
    /// bringing a ≥ 0 down to 0 at speed ≤ v_p (time a/j); from (v_p, 0) the stop is
    /// v_p²/(2d) + v_p·d/(2j) when it reaches d (v_p ≥ d²/j), else v_p·√(v_p/j).
    #[inline(always)]
    pub fn stopping_distance_bound(v: f64, a: f64, d: f64, j: f64) -> f64 {
        let v = v.max(0.0);
        let vp = v + a * a / (2.0 * j);
        if a < 0.0 && !(-a <= d && a * a <= j * vp) {
            return f64::INFINITY;
        }
        let from_peak = if vp * j >= d * d {
            vp * vp / (2.0 * d) + vp * d / (2.0 * j)
        } else {
            vp * math::sqrt(vp / j)
        };
        let bound = from_peak + a.max(0.0) * vp / j;
        // rounding room (the exact distance is summed differently)
        if bound.is_finite() {
            bound * (1.0 + 1e-12) + 1e-12
        } else {
            f64::INFINITY
        }
    }

    /// Distance needed from the current state to slow to `v_target` (0 when already there).
    pub fn slowing_distance(&self, v_target: f64) -> f64 {
        self.slowing_distance_from(self.v, self.a, v_target)
    }

    /// The descent through a state (v, a) with |jerk| = J, split at a = 0: the speed V where
    /// a is (a ≥ 0: will be) 0, V = v + a²/(2J), and the distance I of the part between:
    /// from a ≥ 0, bringing a down to 0 (v up to V) adds I ≥ 0; from a < 0 the part from
    /// (V, 0) down to here is done already, I ≤ 0.
    #[inline(always)]
    pub(crate) fn descent_split(&self, v: f64, a: f64) -> (f64, f64) {
        let j = self.jmax;
        let big = v + a * a / (2.0 * j);
        if a >= 0.0 {
            let t = a / j;
            (big, t * (v + a * t / 3.0))
        } else {
            let t = -a / j;
            (big, -(t * (big - j * t * t / 6.0)))
        }
    }

    /// The descent from (V, 0) down to `vt` < V: (V² − vt²)/(2D) + (V + vt)·D/(2J) when it
    /// reaches the deceleration limit D (V − vt ≥ D²/J), else (V + vt)·√((V − vt)/J). It
    /// grows with V at a rate of V/(2D) at least, on both sides of that bound.
    fn descent_from(&self, big: f64, vt: f64) -> f64 {
        let (j, d) = (self.jmax, self.dmax);
        let dv = big - vt;
        if j * dv >= d * d {
            dv * (big + vt) / (2.0 * d) + (big + vt) * d / (2.0 * j)
        } else {
            (big + vt) * math::sqrt(dv / j)
        }
    }

    /// Whether the ramp from (v, a) down to any speed ≥ 0 up to `vt` is the descent through
    /// (v, a) (see [`descent_split`](Self::descent_split)), whose distance is then
    /// I + `descent_from`(V, vt): a within the limits, and vt below where the ramp would
    /// rather rise (a ≥ 0: below V; a < 0: below v − a²/(2J), where the descent's peak
    /// deceleration √(J·(V − vt)) is beyond |a|).
    #[inline(always)]
    pub(crate) fn descent_holds(&self, v: f64, a: f64, vt: f64) -> bool {
        let j = self.jmax;
        if !(vt >= 0.0 && a <= self.amax && a >= -self.dmax) {
            return false;
        }
        if a >= 0.0 {
            vt < v + a * a / (2.0 * j)
        } else {
            vt < v - a * a / (2.0 * j)
        }
    }

    /// [`slowing_distance_from`](Self::slowing_distance_from)`(v, a, vt)` in closed form where
    /// the ramp is the descent through (v, a) (see [`descent_holds`](Self::descent_holds)),
    /// with the size of the terms it was made of (for a rounding bound); None elsewhere.
    #[inline(always)]
    pub(crate) fn slowing_estimate(&self, v: f64, a: f64, vt: f64) -> Option<(f64, f64)> {
        if !self.descent_holds(v, a, vt) {
            return None;
        }
        let (big, part) = self.descent_split(v, a);
        let down = self.descent_from(big, vt);
        Some((part + down, part.abs() + down))
    }

    /// Distance the time-optimal ramp from speed `v` and acceleration `a` down to `v_target`
    /// covers (0 when no slowing is needed).
    #[inline(always)]
    pub fn slowing_distance_from(&self, v: f64, a: f64, v_target: f64) -> f64 {
        let vt = v_target.max(0.0);
        if v <= vt && a <= 0.0 {
            return 0.0;
        }
        self.track_distance(v, a, vt).max(0.0)
    }

    /// One tick of the time-optimal ramp toward `tgt`: (distance, speed, acceleration) at the
    /// end of the tick.
    pub fn track_step(&self, tgt: f64) -> (f64, f64, f64) {
        self.track(tgt).step()
    }

    /// One tick of the time-optimal ramp toward `tgt` from the current state, kept so that
    /// [`next_tracked`](Self::next_tracked) does not compute it again (a look-ahead needs the
    /// same step to decide its target).
    #[inline(always)]
    pub fn track(&self, tgt: f64) -> Track {
        let tgt = if tgt.is_nan() { 0.0 } else { tgt.max(0.0) };
        let (ds, v, a) = self.track_sample(self.v, self.a, tgt, self.ts);
        Track {
            tgt,
            from: (self.v, self.a),
            ds,
            v,
            a,
        }
    }

    /// The root of a decreasing `f` on [lo, hi] (f(lo) ≥ 0 ≥ f(hi)): regula falsi with the
    /// Illinois modification (superlinear), falling back to bisection when it stalls; stops
    /// when |f| ≤ `tol` or the bracket cannot shrink. Returns the end of the final bracket
    /// where f ≤ 0 (or the point where |f| ≤ tol).
    fn solve_decreasing(mut lo: f64, mut hi: f64, tol: f64, f: impl Fn(f64) -> f64) -> f64 {
        let (mut flo, mut fhi) = (f(lo), f(hi));
        if flo <= tol {
            return lo;
        }
        if fhi >= -tol {
            return hi;
        }
        let mut side = 0i8;
        for k in 0..200 {
            let mut x = (lo * fhi - hi * flo) / (fhi - flo);
            if k % 8 == 7 || !(x > lo && x < hi) {
                x = 0.5 * (lo + hi); // every 8th step, and when false position leaves the bracket
            }
            if !(x > lo && x < hi) {
                break;
            }
            let fx = f(x);
            if fx.abs() <= tol {
                return x;
            }
            if fx > 0.0 {
                lo = x;
                flo = fx;
                if side == 1 {
                    fhi *= 0.5;
                }
                side = 1;
            } else {
                hi = x;
                fhi = fx;
                if side == -1 {
                    flo *= 0.5;
                }
                side = -1;
            }
        }
        hi
    }

    /// The ramp from (v, a) up to the peak speed `vp` and the stop from there at the full
    /// limits (see [`stop_phases`](Self::stop_phases)): the phases of each, run one after the
    /// other.
    #[inline(always)]
    fn ramp_and_stop(&self, v: f64, a: f64, vp: f64) -> (Ramp3, Ramp3) {
        let (d, j) = self.stop_limits();
        let ap = d.min(math::sqrt(j * vp));
        (
            self.track_ramp(v, a, vp).1,
            Self::brake_ramp(vp, 0.0, ap, j),
        )
    }

    /// A stop from (v, a) that comes to rest after `r`: the time-optimal stop's shape with a
    /// lower peak deceleration (longer) or, within the full limits, a higher one (shorter);
    /// from (near) rest, a short ramp up and down. When no stop fits, the nearest.
    fn stop_phases(&self, v: f64, a: f64, r: f64, tgt: f64) -> Phases {
        let (jp, dp) = self.plan_limits();
        let (sd, sj) = self.stop_limits();
        // the longest stop, when even it is too short: its peak deceleration and jerk
        let mut longest = None;
        for (j, d) in [(jp, dp), (sj, sd)] {
            let Some(hi) = Self::brake_peak(v, a, d, j) else {
                continue;
            };
            if Self::brake_phases_distance(v, a, hi, j) > r {
                if j == sj {
                    // cannot stop in time even at the full limits: the shortest stop
                    return Self::brake_phases(v, a, hi, j);
                }
                continue;
            }
            let lo = hi * 1e-9;
            if Self::brake_phases_distance(v, a, lo, j) < r {
                longest = Some((lo, j));
                continue;
            }
            let dist = |ap: f64| Self::brake_distance(v, a, ap, j) - r;
            let ap = Self::solve_decreasing(lo, hi, 1e-13 * r, dist);
            return Self::brake_phases(v, a, ap, j);
        }
        // Too far for a stop from here (at or near rest): ramp up to a peak speed and stop
        // (at most six phases: `Phases` holds them all).
        let j = self.jmax;
        let ramp = |vp: f64| {
            let (up, stop) = self.ramp_and_stop(v, a, vp);
            Phases::of(up.into_iter().chain(stop))
        };
        let ramp_distance = |vp: f64| {
            let (up, stop) = self.ramp_and_stop(v, a, vp);
            run_phases(stop, run_phases(up, (0.0, v, a))).0
        };
        let v_lo = (v + a * a.abs() / (2.0 * j)).max(0.0);
        let v_hi = tgt.max(v_lo);
        if ramp_distance(v_hi) <= r {
            return ramp(v_hi);
        }
        if ramp_distance(v_lo) <= r {
            let vp = Self::solve_decreasing(v_lo, v_hi, 1e-13 * r, |vp| r - ramp_distance(vp));
            return ramp(vp);
        }
        match longest {
            Some((lo, j)) => Self::brake_phases(v, a, lo, j),
            None => ramp(v_lo),
        }
    }

    /// One tick: returns the mean path speed over this tick (the step is that times Ts).
    /// `v_target` is the speed wanted now (commanded feed lowered by look-ahead limits),
    /// `remaining` the path length to the point where the motion must be at rest (counts).
    pub fn next(&mut self, v_target: f64, remaining: f64) -> f64 {
        self.next_inner(v_target, remaining, None)
    }

    /// [`next`](Self::next) toward the target of `track`, a [`track`](Self::track) of the
    /// current state (the same result, without computing the ramp's step again; a track of
    /// another state is computed again).
    #[inline(always)]
    pub fn next_tracked(&mut self, track: Track, remaining: f64) -> f64 {
        self.next_inner(track.tgt, remaining, Some(&track))
    }

    /// [`next`](Self::next), with the ramp's step of `track` when it is of this state and
    /// target. The common tick (the ramp, far from the stop point) is done here; the rest in
    /// [`near_stop`](Self::near_stop), kept out of line.
    #[inline(always)]
    fn next_inner(&mut self, v_target: f64, remaining: f64, track: Option<&Track>) -> f64 {
        let ts = self.ts;
        let remaining = if remaining.is_nan() {
            0.0
        } else {
            remaining.max(0.0)
        };
        let tgt = if v_target.is_nan() {
            0.0
        } else {
            v_target.max(0.0)
        };
        if !(self.v.is_finite() && self.a.is_finite()) {
            // (cannot happen from finite inputs; a state it cannot follow restarts at rest)
            self.rest();
        }
        let (v, a) = (self.v, self.a);
        self.lands = false;
        // At the stop point, or within what a thousandth of the jerk limit moves in a servo
        // tick of it at a speed and acceleration that move no more there: this tick covers
        // what is left and lands. (A stop re-solved every tick from a state that small never
        // lands within a tick: it crept toward the point for thousands of ticks.)
        let st = self.servo_ts;
        let crumb = 1e-3 * self.jmax * st * st * st;
        if (v <= 0.0 && a <= 0.0 && remaining <= 0.0)
            || (remaining <= crumb && v * st <= crumb && a.abs() * st * st <= crumb)
        {
            self.v = 0.0;
            self.a = 0.0;
            self.lands = true;
            self.step = StepProfile::Rest;
            return remaining / ts;
        }
        let (jp, dp) = self.plan_limits();
        let (ds, v1, a1) = match track {
            Some(t) if t.from == (v, a) && t.tgt == tgt => (t.ds, t.v, t.a),
            _ => self.track_sample(v, a, tgt, ts),
        };
        // far from the stop point, the bound decides without the exact stopping distance
        if ds + Self::stopping_distance_bound(v1, a1, dp, jp) <= remaining {
            return self.ramp_on((v, a, tgt), ds, v1, a1);
        }
        self.near_stop(v, a, remaining, tgt, (ds, v1, a1))
    }

    /// The tick follows the ramp toward `tgt` from `from` = (v, a), whose step is distance
    /// `ds`, ending at (`v1`, `a1`): the mean speed.
    #[inline(always)]
    fn ramp_on(&mut self, from: (f64, f64, f64), ds: f64, v1: f64, a1: f64) -> f64 {
        let (v, a, tgt) = from;
        self.step = StepProfile::Ramp { v, a, tgt };
        self.v = v1.max(0.0);
        self.a = a1;
        self.stopping = false;
        ds / self.ts
    }

    /// The distance, speed and acceleration `dt` (0 ≤ dt ≤ the tick) into the last tick's
    /// profile: at the tick, the step and the state it ended at (up to the rounding of the
    /// state's clamps: a speed below 0 is 0, a stop that landed ends at rest).
    #[inline(always)]
    pub fn sample_step(&self, dt: f64) -> (f64, f64, f64) {
        match self.step {
            StepProfile::Rest => (0.0, 0.0, 0.0),
            StepProfile::Ramp { v, a, tgt } => self.track_sample(v, a, tgt, dt),
            StepProfile::Stop { v, a, phases } => phases.sample(v, a, dt),
        }
    }

    /// How long the last tick's profile moves when it comes to rest within the tick (a stop
    /// that lands, or none at rest), from the tick's start; None when it moves on.
    pub fn rest_time(&self) -> Option<f64> {
        match self.step {
            StepProfile::Rest => Some(0.0),
            StepProfile::Stop { phases, .. } => {
                let t = phases.duration();
                (t <= self.ts).then_some(t)
            }
            // held at rest
            StepProfile::Ramp { v, a, tgt } => (v <= 0.0 && a == 0.0 && tgt <= 0.0).then_some(0.0),
        }
    }

    /// The rest of [`next_inner`](Self::next_inner) where the bound did not decide, from
    /// (`v`, `a`) with the ramp's `step` toward `tgt`: the ramp still, if the exact (clean)
    /// stopping distance after its step fits in `remaining`, else the stop at `remaining`.
    #[inline(always)]
    fn near_stop(
        &mut self,
        v: f64,
        a: f64,
        remaining: f64,
        tgt: f64,
        step: (f64, f64, f64),
    ) -> f64 {
        let ts = self.ts;
        let (jp, dp) = self.plan_limits();
        let (ds, v1, a1) = step;
        if ds + Self::clean_stopping_distance(v1, a1, dp, jp) <= remaining {
            return self.ramp_on((v, a, tgt), ds, v1, a1);
        }
        // A ramp down to a lower target braking too hard to come to rest cleanly from where
        // it gets (its deceleration is released toward the target, not toward rest) comes to
        // rest cleanly from the target: it goes on while that fits. A stop to a far remaining
        // distance would brake less than the target asks, past the pieces it slows for.
        if tgt > 0.0
            && tgt < v1
            && ds
                + self.track_distance(v1, a1, tgt)
                + Self::clean_stopping_distance(tgt, 0.0, dp, jp)
                <= remaining
        {
            return self.ramp_on((v, a, tgt), ds, v1, a1);
        }
        self.stopping = true;
        let stop = self.stop_phases(v, a, remaining, tgt);
        self.step = StepProfile::Stop { v, a, phases: stop };
        let (ds, v1, a1) = stop.sample(v, a, ts);
        if stop.duration() <= ts {
            self.v = 0.0;
            self.a = 0.0;
            self.lands = true;
        } else {
            self.v = v1.max(0.0);
            self.a = a1;
        }
        (ds / ts).max(0.0)
    }

    /// Re-synchronises the planner after a downstream limit changed the tick's mean speed
    /// from `v_planned` to `v_used`: the end speed moves by the same amount, the acceleration
    /// is kept (within the limits), and the ramp toward the target continues from there.
    pub fn resync(&mut self, v_used: f64, v_planned: f64) {
        if !v_used.is_finite() || (v_used - v_planned).abs() <= 1e-12 * (1.0 + v_planned.abs()) {
            return;
        }
        self.v = (self.v + v_used - v_planned).max(0.0);
        self.a = self.a.clamp(-self.dmax, self.amax);
        if self.v == 0.0 {
            self.a = self.a.max(0.0);
        }
        self.lands = false;
    }

    /// Sets the state to rest.
    pub(super) fn rest(&mut self) {
        self.v = 0.0;
        self.a = 0.0;
        self.stopping = false;
        self.lands = false;
        self.step = StepProfile::Rest;
    }

    /// At rest at the end of the last tick, whose profile stays (a stop that ends a hair
    /// above rest is settled there).
    pub(super) fn settle(&mut self) {
        self.v = 0.0;
        self.a = 0.0;
        self.stopping = false;
        self.lands = false;
    }

    /// Takes (v, a) as its state, within the tick of its last profile (the path cuts a
    /// planning step short: see `Path::halt`); the next tick plans from there.
    pub(super) fn cut_at(&mut self, v: f64, a: f64) {
        self.v = v.max(0.0);
        self.a = a.clamp(-self.dmax, self.amax);
        self.lands = false;
        self.step = StepProfile::Rest;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planner(rnd: &mut impl FnMut() -> f64) -> PathSpeedPlanner {
        let (ts, a, j) = (1e-4 + rnd() * 1e-3, 1e3 + rnd() * 1e7, 1e5 + rnd() * 1e10);
        let mut p = PathSpeedPlanner::new(ts, a, j).unwrap();
        p.v = rnd() * 5e5;
        p.a = (rnd() * 2.0 - 1.0) * a;
        p
    }

    #[test]
    fn the_stopping_bound_is_never_below_the_stop() {
        let mut rnd = crate::testkit::rng::Rng::new(0x5709).units();
        let (mut finite, mut tight) = (0, 0);
        for _ in 0..200_000 {
            let (v, a) = (rnd() * 5e5, (rnd() * 2.0 - 1.0) * 3e7);
            let (d, j) = (rnd() * 3e7 + 1.0, 1e5 + rnd() * 1e10);
            let bound = PathSpeedPlanner::stopping_distance_bound(v, a, d, j);
            let exact = PathSpeedPlanner::stopping_distance(v, a, d, j);
            let clean = PathSpeedPlanner::clean_stopping_distance(v, a, d, j);
            assert!(bound >= exact, "{v} {a} {d} {j}: {bound} < {exact}");
            assert!(bound >= clean || clean.is_infinite(), "{v} {a} {d} {j}");
            if bound.is_finite() {
                finite += 1;
                // from a = 0 it is the stop itself
                if a >= 0.0 && bound <= exact * (1.0 + 1e-6) + 1e-6 {
                    tight += 1;
                }
            }
        }
        assert!(
            finite > 100_000 && tight > 1_000,
            "{finite} finite, {tight} tight"
        );
        for (v, d, j) in [(1e5, 5e5, 5e7), (10.0, 5e5, 5e7)] {
            let (b, e) = (
                PathSpeedPlanner::stopping_distance_bound(v, 0.0, d, j),
                PathSpeedPlanner::stopping_distance(v, 0.0, d, j),
            );
            assert!((b - e).abs() <= 1e-9 * e, "{v}: {b} {e}");
        }
    }

    #[test]
    fn the_closed_form_slowing_distance_is_the_ramps() {
        let mut rnd = crate::testkit::rng::Rng::new(0x510e).units();
        let mut some = 0;
        for _ in 0..100_000 {
            let p = planner(&mut rnd);
            let vt = rnd() * p.v * 1.2;
            let exact = p.slowing_distance_from(p.v, p.a, vt);
            if let Some((e, size)) = p.slowing_estimate(p.v, p.a, vt) {
                some += 1;
                assert!(
                    (e - exact).abs() <= 1e-10 * size + 1e-9,
                    "{p:?} to {vt}: {e} vs {exact}"
                );
                // and the split it is made of: I + descent_from(V, vt), growing with V at
                // V/(2D) at least
                let (big, part) = p.descent_split(p.v, p.a);
                let dv = 1e-3 * big;
                let grown = p.descent_from(big + dv, vt) - p.descent_from(big, vt);
                assert!(grown >= dv * big / (2.0 * p.dmax) * (1.0 - 1e-6), "{p:?}");
                assert!((part + p.descent_from(big, vt) - e).abs() <= 1e-12 * size + 1e-12);
            }
        }
        assert!(some > 30_000, "{some}");
    }

    #[test]
    fn next_tracked_is_next() {
        let mut rnd = crate::testkit::rng::Rng::new(0x7ac4).units();
        for _ in 0..50_000 {
            let mut a = planner(&mut rnd);
            a.a = a.a.clamp(-a.dmax, a.amax);
            let mut b = a;
            let tgt = rnd() * 6e5;
            let rem = if rnd() < 0.3 {
                rnd() * 10.0
            } else {
                rnd() * 1e5
            };
            let track = b.track(tgt);
            let stale = b.track(tgt * 0.5);
            assert_eq!(a.next(tgt, rem), b.next_tracked(track, rem));
            assert_eq!(a, b);
            // a track of another state (the one before this tick) is computed again
            let mut c = b;
            assert_eq!(c.next_tracked(stale, rem), b.next(tgt * 0.5, rem));
            assert_eq!(b, c);
        }
    }

    #[test]
    fn brake_distance_in_closed_form() {
        let mut rnd = crate::testkit::rng::Rng::new(0x9e37_79b9_7f4a_7c15u64).units();
        for _ in 0..10_000 {
            let (v, a) = (rnd() * 5e5, (rnd() - 0.5) * 4e7);
            let (ap, j) = (rnd() * 3e7 + 1.0, 1e8 + rnd() * 1e10);
            let exact = PathSpeedPlanner::brake_phases_distance(v, a, ap, j);
            let closed = PathSpeedPlanner::brake_distance(v, a, ap, j);
            assert!(
                (exact - closed).abs() <= 1e-9 * (1.0 + exact.abs()),
                "{v} {a} {ap} {j}: {exact} vs {closed}"
            );
        }
    }
}
