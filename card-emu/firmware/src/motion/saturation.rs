//! The actuator-saturation-aware feed of Yeh & Sun 2008 (eq 3.3–3.10, §3.4): the feed at
//! which no axis's predicted PD+ drive output exceeds Umax, from each axis's drive model and
//! state.
//!
//! [`SaturationAwareFeed::limit_feed`] allocates nothing and never panic.

use super::interp_error::InterpError;
use super::nurbs::{Point, MAX_DIM};
use super::pos_finite;
use crate::servo::pdplus::{AxisModel, DriveModel, DriveModelExt, PdPlusGainsExt};

/// Relative margin kept below Umax by the speed window (absorbs rounding).
pub const GUARD_MARGIN: f64 = 1e-6;

/// Plain-data state of one axis at the tick where the candidate reference is consumed
/// (index k of eq 3.5): the previous reference and the actual (measured or predicted) state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisSample {
    /// θ_d\[k-1\], counts.
    pub theta_d_prev: f64,
    /// w_d\[k-1\] = (θ_d\[k-1\]-θ_d\[k-2\])/Ts, counts/s.
    pub w_d_prev: f64,
    /// θ_a\[k\], counts.
    pub theta_a: f64,
    /// w_a\[k\] = (θ_a\[k\]-θ_a\[k-1\])/Ts, counts/s.
    pub w_a: f64,
}

impl AxisSample {
    /// State one tick ahead from the plant model: θ_a\[k+1\] from the model state
    /// `(theta, vel)` at tick k with `u` held, and `w_a[k+1] = (θ_a[k+1]-θ_a[k])/Ts`.
    /// Use this to predict u_a\[k+1\] when the next reference must be computed before the
    /// next encoder read.
    pub fn predicted(
        plant: &DriveModel,
        ts: f64,
        theta: f64,
        vel: f64,
        u: f64,
        theta_d_prev: f64,
        w_d_prev: f64,
    ) -> Self {
        let (theta_next, _) = plant.step(ts, theta, vel, u);
        Self {
            theta_d_prev,
            w_d_prev,
            theta_a: theta_next,
            w_a: (theta_next - theta) / ts,
        }
    }

    fn is_finite(&self) -> bool {
        self.theta_d_prev.is_finite()
            && self.w_d_prev.is_finite()
            && self.theta_a.is_finite()
            && self.w_a.is_finite()
    }
}

/// Result of one saturation check (§3.4 steps 1–8).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FeedDecision {
    /// Feed handed to the interpolator, counts/s.
    pub feed: f64,
    /// Feed that was asked for.
    pub requested: f64,
    /// Feasible feed interval `[v_min, v_max]` from eq 3.6 on every axis (empty when
    /// `v_min > v_max`).
    pub v_min: f64,
    pub v_max: f64,
    /// Feed lowered below the request (eq 3.10 first case).
    pub limited: bool,
    /// Feed raised above the request (eq 3.10 third case: an axis cannot slow down faster).
    pub raised: bool,
    /// Some feed keeps every |u_a| ≤ Umax.
    pub feasible: bool,
    /// Predicted max over axes of |u_a\[k\]| / Umax at the chosen feed.
    pub max_drive_ratio: f64,
}

/// Yeh's saturation-aware feed for up to `MAX_DIM` axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaturationAwareFeed {
    pub(super) axes: [AxisModel; MAX_DIM],
    pub(super) dim: usize,
    ts: f64,
}

impl SaturationAwareFeed {
    /// Validates `axes` (1..=MAX_DIM of them) and `ts`.
    pub fn new(axes: &[AxisModel], ts: f64) -> Result<Self, InterpError> {
        if axes.is_empty() || axes.len() > MAX_DIM {
            return Err(InterpError::DimensionMismatch {
                expected: MAX_DIM,
                got: axes.len(),
            });
        }
        if !(pos_finite(ts) && ts <= 1.0) {
            return Err(InterpError::BadSampleTime);
        }
        let filler = axes[0];
        let mut arr = [filler; MAX_DIM];
        for (i, (dst, a)) in arr.iter_mut().zip(axes.iter()).enumerate() {
            a.validate(i)?;
            *dst = *a;
        }
        Ok(Self {
            axes: arr,
            dim: axes.len(),
            ts,
        })
    }

    /// Number of axes.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Sample time, s.
    pub fn ts(&self) -> f64 {
        self.ts
    }
    /// Axis `j` (None when out of range).
    pub fn axis(&self, j: usize) -> Option<&AxisModel> {
        self.axes[..self.dim].get(j)
    }

    fn coeff(&self, j: usize) -> f64 {
        self.axes[j].gains.drive_coefficient(self.ts)
    }

    /// `v[k] = k_p(θ_d[k-1]-θ_a[k]) - k_d w_a[k] - k_a w_d[k-1]` (Yeh eq 3.5, discrete
    /// k_a = ka/Ts): the part of u_a\[k\] that does not depend on the new speed command.
    fn free_part(&self, j: usize, st: &AxisSample) -> f64 {
        let g = &self.axes[j].gains;
        g.kp * (st.theta_d_prev - st.theta_a) - g.kd * st.w_a - g.ka / self.ts * st.w_d_prev
    }

    /// Predicted drive output for speed command `w_d` on axis `j` (Yeh eq 3.5):
    /// `u_a[k] = (k_p'+k_d+k_v+k_a)·w_d[k] + v[k]`. NaN for an axis out of range.
    pub fn predict_drive(&self, j: usize, st: &AxisSample, w_d: f64) -> f64 {
        if j >= self.dim {
            return f64::NAN;
        }
        self.coeff(j) * w_d + self.free_part(j, st)
    }

    /// Speed window of axis `j` (Yeh eq 3.6 with the README's denominator):
    /// `(-Umax - v[k])/(k_p'+k_d+k_v+k_a) ≤ w_d[k] ≤ (Umax - v[k])/(k_p'+k_d+k_v+k_a)`.
    pub fn speed_window(&self, j: usize, st: &AxisSample) -> (f64, f64) {
        if j >= self.dim {
            return (f64::NAN, f64::NAN);
        }
        let c = self.coeff(j);
        let v = self.free_part(j, st);
        let um = self.axes[j].umax * (1.0 - GUARD_MARGIN);
        ((-um - v) / c, (um - v) / c)
    }

    /// §3.4 steps 1–8: given the requested feed `v_req` (counts/s), the unit direction of the
    /// axis speed command (`dir`, eq 3.7: `w_d = dir·V`; Yeh uses `D_i^u/‖D_i^u‖`), the
    /// per-axis state and a ceiling the feed may not exceed, return the feed closest to the
    /// request that keeps every predicted |u_a| ≤ Umax (eq 3.10 on every axis, min/max over
    /// axes as in steps 5–6). If no feed in `[0, v_ceiling]` does, the one that minimises the
    /// largest relative overshoot is returned with `feasible = false`.
    pub fn limit_feed(
        &self,
        v_req: f64,
        v_ceiling: f64,
        dir: &Point,
        states: &[AxisSample],
    ) -> Result<FeedDecision, InterpError> {
        if states.len() < self.dim {
            return Err(InterpError::DimensionMismatch {
                expected: self.dim,
                got: states.len(),
            });
        }
        if !(v_req.is_finite() && v_req >= 0.0 && v_ceiling.is_finite() && v_ceiling >= 0.0) {
            return Err(InterpError::BadFeed);
        }
        if dir.iter().any(|d| !d.is_finite()) || states[..self.dim].iter().any(|s| !s.is_finite()) {
            return Err(InterpError::NonFiniteInput);
        }
        let ceiling = v_ceiling.max(v_req);
        let mut v_min = 0.0f64;
        let mut v_max = ceiling;
        let mut axis_blocked = false;
        for j in 0..self.dim {
            // Step 2–3: axis window (eq 3.6) mapped through w_d^j = V·dir_j (eq 3.7) into a
            // feed interval (eq 3.10: V ≤ |w^max/D^j| or V ≥ |w^min/D^j|).
            let (lo, hi) = self.speed_window(j, &states[j]);
            let d = dir[j];
            if d > 0.0 {
                v_min = v_min.max(lo / d);
                v_max = v_max.min(hi / d);
            } else if d < 0.0 {
                v_min = v_min.max(hi / d);
                v_max = v_max.min(lo / d);
            } else if !(lo <= 0.0 && 0.0 <= hi) {
                axis_blocked = true;
            }
        }
        // Step 5–6: the intersection over axes; steps 7–8: modified or unmodified feed.
        let feasible = !axis_blocked && v_min <= v_max;
        let feed = if feasible {
            v_req.clamp(v_min, v_max)
        } else {
            self.least_violation(ceiling, dir, states)
        };
        Ok(FeedDecision {
            feed,
            requested: v_req,
            v_min,
            v_max,
            limited: feed < v_req,
            raised: feed > v_req,
            feasible,
            max_drive_ratio: self.drive_ratio(feed, dir, states),
        })
    }

    /// max_j |u_a^j| / Umax_j for the axis speed commands `w_d = dir·v`.
    pub(super) fn drive_ratio(&self, v: f64, dir: &Point, states: &[AxisSample]) -> f64 {
        let mut worst = 0.0f64;
        for j in 0..self.dim.min(states.len()) {
            let u = self.predict_drive(j, &states[j], v * dir[j]);
            worst = worst.max(u.abs() / self.axes[j].umax);
        }
        worst
    }

    /// Predicted max_j |u_a^j|/Umax_j for explicit axis speed commands `w_d` (counts/s).
    pub fn drive_ratio_for(&self, w_d: &Point, states: &[AxisSample]) -> f64 {
        let mut worst = 0.0f64;
        for j in 0..self.dim.min(states.len()) {
            let u = self.predict_drive(j, &states[j], w_d[j]);
            worst = worst.max(u.abs() / self.axes[j].umax);
        }
        worst
    }

    /// Golden-section search of the convex function `V ↦ max_j |u_j(V)|/Umax_j` on [0, hi].
    fn least_violation(&self, hi: f64, dir: &Point, states: &[AxisSample]) -> f64 {
        let g = 0.618_033_988_749_894_9;
        let (mut a, mut b) = (0.0, hi);
        let mut x1 = b - g * (b - a);
        let mut x2 = a + g * (b - a);
        let mut f1 = self.drive_ratio(x1, dir, states);
        let mut f2 = self.drive_ratio(x2, dir, states);
        for _ in 0..80 {
            if f1 <= f2 {
                b = x2;
                x2 = x1;
                f2 = f1;
                x1 = b - g * (b - a);
                f1 = self.drive_ratio(x1, dir, states);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (b - a);
                f2 = self.drive_ratio(x2, dir, states);
            }
        }
        let mid = 0.5 * (a + b);
        // the ends of the interval are candidates too (piecewise-linear, possibly flat)
        let mut best = (self.drive_ratio(mid, dir, states), mid);
        for v in [0.0, hi] {
            let r = self.drive_ratio(v, dir, states);
            if r < best.0 {
                best = (r, v);
            }
        }
        best.1
    }

    /// A tangential deceleration (counts/s²) every axis can give with `budget`·Umax on a
    /// straight path: braking, |kv·w − ka·d| ≤ budget·Umax holds for any speed when
    /// d ≤ budget·Umax/ka.
    pub fn safe_path_decel(&self, budget: f64) -> f64 {
        let mut best = f64::INFINITY;
        for a in &self.axes[..self.dim] {
            if a.gains.ka > 0.0 {
                best = best.min(budget * a.umax / a.gains.ka);
            }
        }
        best.max(0.0)
    }

    /// A conservative tangential acceleration (counts/s²) every axis can give at path speed
    /// `v` with `budget`·Umax (steady-state PD+: u ≈ kv·w + ka·α): the worst axis, worst
    /// direction. Useful to set `InterpConfig::accel`.
    pub fn safe_path_accel(&self, v: f64, budget: f64) -> f64 {
        let mut best = f64::INFINITY;
        for a in &self.axes[..self.dim] {
            let room = budget * a.umax - a.gains.kv * v.abs();
            let acc = if a.gains.ka > 0.0 {
                room / a.gains.ka
            } else {
                f64::INFINITY
            };
            best = best.min(acc);
        }
        best.max(0.0)
    }
}
