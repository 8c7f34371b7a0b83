//! Circular interpolation and the closed-form steady-state radial path error
//! of a circle after the acc/dec filters (Kim 1991 §3–4).
//!
//! * [`ReferenceWordCircle`]: the reference-word interpolator of Kim eq 15–23,
//!   producing per-tick position increments (velocity data × T) to feed the
//!   per-axis [`crate::motion::filters::AccDecFilter`]s.
//! * [`ExactCircle`]: point on the arc at arc length `s` (cos/sin of the
//!   angle), for use with an external feed profile.
//! * [`linear_filter_radial_error`] (Kim eq 28, corrected) and
//!   [`exponential_filter_radial_error`] (Kim eq 32).
//!
//! Units: counts, seconds, radians. Angles are counter-clockwise from +x.
#![forbid(unsafe_code)]

use crate::math;
use core::f64::consts::{PI, TAU};
use core::fmt;

/// Largest accepted angle per tick `α = V·T/R` (rad). Beyond this the chord
/// deviates from the arc by more than `R(1 − cos(α/2)) ≈ 7.6 %·R`.
pub const MAX_STEP_ANGLE: f64 = PI / 4.0;

/// Largest accepted number of interpolation ticks for one arc.
pub const MAX_STEPS: u64 = 1 << 40;

/// Largest accepted difference (counts) between the end point's distance from
/// the centre and the start point's (plus `1e-9·R`). Programmed end points
/// are rounded to whole counts, so one count is allowed.
pub const END_RADIUS_TOLERANCE: f64 = 1.0;

/// Sweeps within this angle (rad) of 0 or 2π between start and end are a
/// full circle.
const FULL_CIRCLE_EPS: f64 = 1.0e-12;

/// Errors of the arc constructors and of [`ExactCircle::point_at`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CircleError {
    /// A point, centre or angle is not finite.
    InvalidGeometry,
    /// Radius not finite or `<= 0` (or start point equal to the centre).
    InvalidRadius,
    /// Feed not finite or `<= 0`.
    InvalidFeed,
    /// Sample time not finite or `<= 0`.
    InvalidSampleTime,
    /// Sweep angle not finite or zero.
    InvalidSweep,
    /// End point not on the circle through the start point.
    EndPointOffCircle,
    /// `V·T/R > MAX_STEP_ANGLE`.
    StepAngleTooLarge,
    /// More than `MAX_STEPS` ticks.
    TooManySteps,
    /// Arc length `s` is NaN.
    InvalidArcLength,
}

impl fmt::Display for CircleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            CircleError::InvalidGeometry => "arc points and angles must be finite",
            CircleError::InvalidRadius => "radius must be finite and > 0",
            CircleError::InvalidFeed => "feed must be finite and > 0",
            CircleError::InvalidSampleTime => "sample time must be finite and > 0",
            CircleError::InvalidSweep => "sweep angle must be finite and non-zero",
            CircleError::EndPointOffCircle => "end point is not on the circle",
            CircleError::StepAngleTooLarge => "feed*T/R exceeds MAX_STEP_ANGLE",
            CircleError::TooManySteps => "arc needs more than MAX_STEPS ticks",
            CircleError::InvalidArcLength => "arc length is NaN",
        };
        f.write_str(s)
    }
}

impl core::error::Error for CircleError {}

/// Direction of travel (G02 = clockwise, G03 = counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArcDirection {
    /// Clockwise (negative sweep).
    Cw,
    /// Counter-clockwise (positive sweep).
    Ccw,
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// Radius, start angle and signed sweep of the arc from `start` to `end`
/// around `centre` in direction `dir` (start == end: full circle).
fn arc_from_points(
    centre: (f64, f64),
    start: (f64, f64),
    end: (f64, f64),
    dir: ArcDirection,
) -> Result<(f64, f64, f64), CircleError> {
    if !(finite2(centre) && finite2(start) && finite2(end)) {
        return Err(CircleError::InvalidGeometry);
    }
    let (sx, sy) = (start.0 - centre.0, start.1 - centre.1);
    let (ex, ey) = (end.0 - centre.0, end.1 - centre.1);
    let r = math::hypot(sx, sy);
    if !(r.is_finite() && r > 0.0) {
        return Err(CircleError::InvalidRadius);
    }
    let re = math::hypot(ex, ey);
    // Inputs are finite, so `re` is finite or +inf (never NaN).
    if (re - r).abs() > END_RADIUS_TOLERANCE + 1.0e-9 * r {
        return Err(CircleError::EndPointOffCircle);
    }
    let theta_s = math::atan2(sy, sx);
    let theta_e = math::atan2(ey, ex);
    let d = math::rem_euclid(theta_e - theta_s, TAU); // CCW angle, [0, 2π]
    let full = !(FULL_CIRCLE_EPS..=TAU - FULL_CIRCLE_EPS).contains(&d);
    let sweep = match (dir, full) {
        (ArcDirection::Ccw, true) => TAU,
        (ArcDirection::Ccw, false) => d,
        (ArcDirection::Cw, true) => -TAU,
        (ArcDirection::Cw, false) => -(TAU - d),
    };
    Ok((r, theta_s, sweep))
}

// ---------------------------------------------------------------------------
// Reference-word interpolator
// ---------------------------------------------------------------------------

/// Reference-word circular interpolator, Kim eq 15–23.
///
/// Each tick advances the angle by `α = V·T/R` (Kim eq 21–22) with the
/// rotation of Kim eq 15–16 (`B` signed by the direction, `−sin α` for CW):
///
/// `X(k+1) = A·X(k) − B·Y(k)`, `Y(k+1) = A·Y(k) + B·X(k)`, `A = cos α`,
/// `B = sin α`,
///
/// and emits the chord increments `DX(k), DY(k)` of Kim eq 17 (counts per
/// tick); the velocity data are `V_x = DX/T`, `V_y = DY/T`, which for a CCW arc
/// starting at angle 0 is Kim eq 23: `V_x(k) = −[2R sin(α/2)/T]·sin(kα + α/2)`,
/// `V_y(k) = [2R sin(α/2)/T]·cos(kα + α/2)` (README: eq 20's second line has
/// cos). These chord increments, not eq 18's `V·DX/DS`, are what the axes
/// must receive so that the accumulated position stays on the vertices of the
/// inscribed polygon.
///
/// Additions to the plain recurrence:
/// * a division- and sqrt-free Newton renormalisation of `(X, Y)` to the
///   radius each tick (factor `(3 − (X²+Y²)/R²)/2`), so the vertices stay on
///   the circle to a few ulps for any number of ticks (the plain recurrence
///   drifts by up to ~`k·ε·R` because `A² + B² ≠ 1` in floating point);
/// * the emitted increment is `target − position` where `position` is the
///   running sum of the emitted increments, so rounding does not accumulate;
/// * the number of ticks is `N = ceil(|sweep|/α)` and the last tick goes
///   straight to the programmed end point (shortened step, `<= α`).
///
/// Accumulating the increments with plain `f64` additions from the start point
/// (`p += d`, exactly what [`position`](Self::position) does) lands on the
/// programmed end point bit-exactly whenever the last subtraction is exact
/// (Sterbenz; always in practice, e.g. unless a coordinate of the
/// second-to-last vertex is within ~1e-16·step of zero without being zero).
#[derive(Debug, Clone)]
pub struct ReferenceWordCircle {
    centre: (f64, f64),
    radius: f64,
    inv_r2: f64,
    alpha: f64,
    cos_a: f64,
    sin_a: f64,
    sweep: f64,
    /// `(X(k), Y(k))` relative to the centre.
    rel: (f64, f64),
    /// Sum of the emitted increments, from the start point.
    pos: (f64, f64),
    end: (f64, f64),
    steps: u64,
    k: u64,
    ts: f64,
    feed: f64,
}

impl ReferenceWordCircle {
    /// Arc from `start` to `end` around `centre` in direction `dir`
    /// (`start == end`: full circle) at feed `feed` counts/s, sample time `ts`
    /// s. The radius is `|start − centre|`; `|end − centre|` must agree within
    /// `END_RADIUS_TOLERANCE`.
    pub fn new(
        centre: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        dir: ArcDirection,
        feed: f64,
        ts: f64,
    ) -> Result<Self, CircleError> {
        let (r, _theta_s, sweep) = arc_from_points(centre, start, end, dir)?;
        Self::build(centre, start, end, r, sweep, feed, ts)
    }

    /// Arc of signed `sweep` radians (positive CCW, may exceed 2π for several
    /// laps) from `start` around `centre`; the end point is
    /// `centre + R(cos, sin)(θ_start + sweep)`.
    pub fn from_sweep(
        centre: (f64, f64),
        start: (f64, f64),
        sweep: f64,
        feed: f64,
        ts: f64,
    ) -> Result<Self, CircleError> {
        if !(finite2(centre) && finite2(start)) {
            return Err(CircleError::InvalidGeometry);
        }
        if !(sweep.is_finite() && sweep != 0.0) {
            return Err(CircleError::InvalidSweep);
        }
        let (sx, sy) = (start.0 - centre.0, start.1 - centre.1);
        let r = math::hypot(sx, sy);
        if !(r.is_finite() && r > 0.0) {
            return Err(CircleError::InvalidRadius);
        }
        let te = math::atan2(sy, sx) + sweep;
        let end = (centre.0 + r * math::cos(te), centre.1 + r * math::sin(te));
        Self::build(centre, start, end, r, sweep, feed, ts)
    }

    fn build(
        centre: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        r: f64,
        sweep: f64,
        feed: f64,
        ts: f64,
    ) -> Result<Self, CircleError> {
        if !(feed.is_finite() && feed > 0.0) {
            return Err(CircleError::InvalidFeed);
        }
        if !(ts.is_finite() && ts > 0.0) {
            return Err(CircleError::InvalidSampleTime);
        }
        // Kim eq 21: Rα/V = T.
        let alpha = feed * ts / r;
        if !(alpha.is_finite() && alpha > 0.0) {
            return Err(CircleError::InvalidFeed);
        }
        if alpha > MAX_STEP_ANGLE {
            return Err(CircleError::StepAngleTooLarge);
        }
        let n = math::ceil(sweep.abs() / alpha - 1.0e-9).max(1.0);
        if !(n.is_finite() && n <= MAX_STEPS as f64) {
            return Err(CircleError::TooManySteps);
        }
        // Kim eq 16, B signed by the direction.
        let sin_a = if sweep > 0.0 {
            math::sin(alpha)
        } else {
            -math::sin(alpha)
        };
        Ok(Self {
            centre,
            radius: r,
            inv_r2: 1.0 / (r * r),
            alpha,
            cos_a: math::cos(alpha),
            sin_a,
            sweep,
            rel: (start.0 - centre.0, start.1 - centre.1),
            pos: start,
            end,
            steps: n as u64,
            k: 0,
            ts,
            feed,
        })
    }

    /// Next tick's increment `(DX, DY)` in counts (Kim eq 17), `None` once the
    /// end point has been reached.
    pub fn next_increment(&mut self) -> Option<(f64, f64)> {
        if self.k >= self.steps {
            return None;
        }
        self.k += 1;
        let target = if self.k == self.steps {
            // Last, shortened step: exactly to the end point.
            self.end
        } else {
            // Kim eq 15.
            let (x, y) = self.rel;
            let nx = self.cos_a * x - self.sin_a * y;
            let ny = self.cos_a * y + self.sin_a * x;
            // Newton step towards |(X, Y)| = R (keeps the vertices on the circle).
            let f = 1.5 - 0.5 * (nx * nx + ny * ny) * self.inv_r2;
            self.rel = (nx * f, ny * f);
            (self.centre.0 + self.rel.0, self.centre.1 + self.rel.1)
        };
        let d = (target.0 - self.pos.0, target.1 - self.pos.1);
        self.pos = (self.pos.0 + d.0, self.pos.1 + d.1);
        Some(d)
    }

    /// Velocity data of an increment, Kim eq 18/23: `(DX/T, DY/T)` counts/s.
    pub fn velocity(&self, increment: (f64, f64)) -> (f64, f64) {
        (increment.0 / self.ts, increment.1 / self.ts)
    }

    /// Radius `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Centre.
    pub fn centre(&self) -> (f64, f64) {
        self.centre
    }

    /// Angle per tick `α = V·T/R` (Kim eq 21–22), always positive.
    pub fn step_angle(&self) -> f64 {
        self.alpha
    }

    /// Signed sweep angle (positive CCW).
    pub fn sweep(&self) -> f64 {
        self.sweep
    }

    /// Total number of ticks `N = ceil(|sweep|/α)`.
    pub fn total_steps(&self) -> u64 {
        self.steps
    }

    /// Ticks still to come.
    pub fn remaining_steps(&self) -> u64 {
        self.steps.saturating_sub(self.k)
    }

    /// True once the end point has been emitted.
    pub fn is_done(&self) -> bool {
        self.k >= self.steps
    }

    /// Start point plus the sum of the increments emitted so far.
    pub fn position(&self) -> (f64, f64) {
        self.pos
    }

    /// Programmed end point.
    pub fn end_point(&self) -> (f64, f64) {
        self.end
    }

    /// Sample time.
    pub fn sample_time(&self) -> f64 {
        self.ts
    }

    /// Feed (counts/s).
    pub fn feed(&self) -> f64 {
        self.feed
    }
}

impl Iterator for ReferenceWordCircle {
    type Item = (f64, f64);

    fn next(&mut self) -> Option<(f64, f64)> {
        self.next_increment()
    }
}

// ---------------------------------------------------------------------------
// Exact circle
// ---------------------------------------------------------------------------

/// Exact arc: the point at arc length `s` is `centre + R·(cos θ, sin θ)` with
/// `θ = θ_start + sign(sweep)·s/R`, for an external feed profile to drive
/// (`s` from 0 to [`length`](Self::length)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactCircle {
    centre: (f64, f64),
    radius: f64,
    start_angle: f64,
    sweep: f64,
    start: (f64, f64),
    end: (f64, f64),
}

impl ExactCircle {
    /// Arc of `radius` around `centre` from `start_angle` sweeping the signed
    /// angle `sweep` (positive CCW, may exceed 2π).
    pub fn new(
        centre: (f64, f64),
        radius: f64,
        start_angle: f64,
        sweep: f64,
    ) -> Result<Self, CircleError> {
        if !(finite2(centre) && start_angle.is_finite()) {
            return Err(CircleError::InvalidGeometry);
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(CircleError::InvalidRadius);
        }
        if !(sweep.is_finite() && sweep != 0.0) {
            return Err(CircleError::InvalidSweep);
        }
        let te = start_angle + sweep;
        Ok(Self {
            centre,
            radius,
            start_angle,
            sweep,
            start: (
                centre.0 + radius * math::cos(start_angle),
                centre.1 + radius * math::sin(start_angle),
            ),
            end: (
                centre.0 + radius * math::cos(te),
                centre.1 + radius * math::sin(te),
            ),
        })
    }

    /// Arc from `start` to `end` around `centre` in direction `dir`
    /// (`start == end`: full circle). `point_at(0)` and `point_at(length)`
    /// return the given points exactly.
    pub fn from_points(
        centre: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        dir: ArcDirection,
    ) -> Result<Self, CircleError> {
        let (radius, start_angle, sweep) = arc_from_points(centre, start, end, dir)?;
        Ok(Self {
            centre,
            radius,
            start_angle,
            sweep,
            start,
            end,
        })
    }

    /// Radius.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Centre.
    pub fn centre(&self) -> (f64, f64) {
        self.centre
    }

    /// Signed sweep angle.
    pub fn sweep(&self) -> f64 {
        self.sweep
    }

    /// Start angle.
    pub fn start_angle(&self) -> f64 {
        self.start_angle
    }

    /// Arc length `R·|sweep|`.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep.abs()
    }

    /// Angle at arc length `s` (clamped to `[0, length]`).
    pub fn angle_at(&self, s: f64) -> Result<f64, CircleError> {
        if s.is_nan() {
            return Err(CircleError::InvalidArcLength);
        }
        let s = s.clamp(0.0, self.length());
        let phi = s / self.radius;
        Ok(if self.sweep > 0.0 {
            self.start_angle + phi
        } else {
            self.start_angle - phi
        })
    }

    /// Point at arc length `s` (clamped to `[0, length]`; the ends return the
    /// start and end points exactly).
    pub fn point_at(&self, s: f64) -> Result<(f64, f64), CircleError> {
        let theta = self.angle_at(s)?;
        if s <= 0.0 {
            return Ok(self.start);
        }
        if s >= self.length() {
            return Ok(self.end);
        }
        Ok((
            self.centre.0 + self.radius * math::cos(theta),
            self.centre.1 + self.radius * math::sin(theta),
        ))
    }

    /// Unit tangent (direction of travel) at arc length `s`.
    pub fn tangent_at(&self, s: f64) -> Result<(f64, f64), CircleError> {
        let theta = self.angle_at(s)?;
        let sgn = if self.sweep > 0.0 { 1.0 } else { -1.0 };
        Ok((-sgn * math::sin(theta), sgn * math::cos(theta)))
    }
}

// ---------------------------------------------------------------------------
// Closed-form radial errors
// ---------------------------------------------------------------------------

fn valid_rvt(r: f64, v: f64, ts: f64) -> bool {
    r.is_finite() && r > 0.0 && v.is_finite() && v >= 0.0 && ts.is_finite() && ts > 0.0
}

/// Steady-state radial error `ΔR = R − R'` of a circle of radius `r` at feed
/// `v` (counts/s) and sample time `ts` after the `m`-tap linear filter
/// (`filters::LinearFilter`), Kim eq 28 as corrected from eq 27 (README):
///
/// `ΔR = R·[1 − 2·sin(Ω·T·m/2)/(m·sqrt(2 − 2·c0))]`, `Ω = V/R`, `c0 = cos ΩT`,
///
/// i.e. `R·(1 − |H(e^{jΩT})|)` with `|H| = |sin(mΩT/2)/(m·sin(ΩT/2))|` (Kim eq 3).
/// Computed with `sqrt(2 − 2c0) = 2 sin(ΩT/2)` (no cancellation) and the
/// magnitude of the gain (the radius is `R·|H|` also past the first notch).
/// Returns NaN for invalid arguments (`m == 0`, non-finite or non-positive
/// `r`/`ts`, negative `v`); `v = 0` gives 0.
pub fn linear_filter_radial_error(r: f64, v: f64, ts: f64, m: usize) -> f64 {
    if !valid_rvt(r, v, ts) || m == 0 {
        return f64::NAN;
    }
    let w = v * ts / r; // ΩT
    let half = 0.5 * w;
    let s_half = math::sin(half);
    if s_half == 0.0 {
        return 0.0;
    }
    let mf = m as f64;
    let gain = (2.0 * math::sin(mf * half) / (mf * 2.0 * s_half)).abs();
    r * (1.0 - gain)
}

/// Steady-state radial error after the exponential filter with pole `a`
/// (`filters::ExponentialFilter::pole()`, `a = tau/(tau + ts)` for a time
/// constant `tau`), Kim eq 32:
///
/// `ΔR = R·[1 − 1/sqrt(1 + 2a(1 − c0)/(a − 1)²)]`, `c0 = cos(V·T/R)`,
///
/// which is `R·(1 − |H(e^{jΩT})|)` for Kim eq 8, `H(z) = (1−a)z/(z−a)`.
/// Computed with `1 − c0 = 2 sin²(ΩT/2)` and `1 − 1/s = q/(s(1+s))`.
/// Returns NaN for invalid arguments (`a` outside `[0, 1)` etc.).
pub fn exponential_filter_radial_error(r: f64, v: f64, ts: f64, a: f64) -> f64 {
    if !(valid_rvt(r, v, ts) && a.is_finite() && (0.0..1.0).contains(&a)) {
        return f64::NAN;
    }
    let w = v * ts / r;
    let sh = math::sin(0.5 * w);
    let one_minus_c0 = 2.0 * sh * sh;
    let q = 2.0 * a * one_minus_c0 / ((a - 1.0) * (a - 1.0));
    let s = math::sqrt(1.0 + q);
    r * (q / (s * (1.0 + s)))
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::filters::{AccDecFilter, CompensatedSum, ExponentialFilter, LinearFilter};

    const EPS: f64 = f64::EPSILON;

    #[test]
    fn reference_word_stays_on_radius() {
        // (centre, R, feed, ts, laps): up to ~1.9e6 ticks.
        let cases = [
            ((0.0, 0.0), 1000.0, 1000.0, 0.001, 1.0),
            ((12345.5, -6789.25), 50_000.0, 5000.0, 0.0005, 3.0),
            ((-3.0e5, 2.0e5), 1.0e5, 2000.0, 0.001, 3.0),
            ((7.0, 7.0), 10.0, 300.0, 0.002, 50.0),
        ];
        for &(c, r, feed, ts, laps) in &cases {
            let start = (c.0 + r, c.1);
            let mut circ = ReferenceWordCircle::from_sweep(c, start, laps * TAU, feed, ts).unwrap();
            let n = circ.total_steps();
            let mut p = start;
            let mut worst: f64 = 0.0;
            let mut k = 0;
            while let Some(d) = circ.next_increment() {
                p = (p.0 + d.0, p.1 + d.1);
                k += 1;
                if k < n {
                    let dev = ((p.0 - c.0).hypot(p.1 - c.1) - r).abs();
                    worst = worst.max(dev);
                }
            }
            // Drift bound: vertices on the circle within 8 ulps of |c| + R
            // (Newton renormalisation each tick + one rounding in c + rel and
            // one in the running sum), independent of the number of ticks.
            let bound = 8.0 * EPS * (c.0.abs().max(c.1.abs()) + r);
            assert!(worst <= bound, "R={r}: worst={worst:e} bound={bound:e}");
            println!("R={r} ticks={n}: max |r−R| = {worst:e} (bound {bound:e})");
        }
    }

    #[test]
    fn plain_recurrence_drift_for_reference() {
        // Without renormalisation Kim eq 15 drifts ~ k·ε·R; documents why the
        // interpolator renormalises.
        let alpha: f64 = 1e-4;
        let (c, s) = (alpha.cos(), alpha.sin());
        let (mut x, mut y) = (1.0f64, 0.0f64);
        for _ in 0..2_000_000 {
            let nx = c * x - s * y;
            y = c * y + s * x;
            x = nx;
        }
        let drift = (x.hypot(y) - 1.0).abs();
        println!("plain Kim eq 15, 2e6 ticks: relative radius drift {drift:e}");
        assert!(drift < 2e6 * 2.0 * EPS);
    }

    fn end_exact(circ: &mut ReferenceWordCircle, start: (f64, f64)) -> (f64, f64) {
        let mut p = start;
        let chord = 2.0 * circ.radius() * (0.5 * circ.step_angle()).sin();
        while let Some(d) = circ.next_increment() {
            p = (p.0 + d.0, p.1 + d.1);
            // Every step is a chord of angle α; the last one spans at most α
            // (plus the end point's distance from the circle, < 1 count).
            let len = d.0.hypot(d.1);
            let slack = if circ.is_done() {
                END_RADIUS_TOLERANCE
            } else {
                0.0
            };
            assert!(len <= chord * (1.0 + 1e-9) + 1e-9 + slack);
        }
        p
    }

    #[test]
    fn reference_word_ends_exactly_on_end_point() {
        let r = 1000.0;
        let cases = [
            // centre, start, end, dir
            ((0.0, 0.0), (r, 0.0), (0.0, r), ArcDirection::Ccw),
            ((0.0, 0.0), (r, 0.0), (0.0, -r), ArcDirection::Cw),
            ((0.0, 0.0), (r, 0.0), (r, 0.0), ArcDirection::Ccw),
            ((0.0, 0.0), (r, 0.0), (r, 0.0), ArcDirection::Cw),
            (
                (100.0, 200.0),
                (100.0, 200.0 + r),
                (100.0 - r, 200.0),
                ArcDirection::Ccw,
            ),
            (
                (100.0, 200.0),
                (100.0, 200.0 + r),
                (100.0 - r, 200.0),
                ArcDirection::Cw,
            ),
            (
                (-5000.0, 3000.0),
                (-5000.0 + 600.0, 3000.0 + 800.0),
                (-5000.0 - 800.0, 3000.0 - 600.0),
                ArcDirection::Ccw,
            ),
            (
                (-5000.0, 3000.0),
                (-5000.0 + 600.0, 3000.0 + 800.0),
                (-5000.0 - 800.0, 3000.0 - 600.0),
                ArcDirection::Cw,
            ),
            // End point rounded to whole counts (off the circle by < 1 count).
            ((0.0, 0.0), (1000.0, 0.0), (707.0, 707.0), ArcDirection::Ccw),
            ((0.0, 0.0), (1000.0, 0.0), (707.0, 707.0), ArcDirection::Cw),
        ];
        for &(c, s, e, dir) in &cases {
            for &(feed, ts) in &[(3000.0, 0.001), (12345.0, 0.0005), (777.7, 0.002)] {
                let mut circ = ReferenceWordCircle::new(c, s, e, dir, feed, ts).unwrap();
                let sweep = circ.sweep();
                assert_eq!(sweep > 0.0, dir == ArcDirection::Ccw);
                let n = circ.total_steps();
                assert_eq!(n as f64, (sweep.abs() / circ.step_angle() - 1e-9).ceil());
                let p = end_exact(&mut circ, s);
                assert_eq!(p, e, "c={c:?} s={s:?} e={e:?} {dir:?}");
                assert_eq!(circ.position(), e);
                assert!(circ.is_done());
                assert_eq!(circ.next_increment(), None);
            }
        }
        // Sweep angles of the classic cases.
        let q = ReferenceWordCircle::new(
            (0.0, 0.0),
            (r, 0.0),
            (0.0, r),
            ArcDirection::Cw,
            1000.0,
            0.001,
        )
        .unwrap();
        assert!((q.sweep() + 1.5 * PI).abs() < 1e-12);
        let f = ReferenceWordCircle::new(
            (0.0, 0.0),
            (r, 0.0),
            (r, 0.0),
            ArcDirection::Cw,
            1000.0,
            0.001,
        )
        .unwrap();
        assert_eq!(f.sweep(), -TAU);
    }

    #[test]
    fn reference_word_random_arcs_end_exactly() {
        let mut rnd = crate::testkit::rng::Rng::new(42).units();
        for _ in 0..300 {
            let c = ((rnd() - 0.5) * 2e5, (rnd() - 0.5) * 2e5);
            let r = 10.0 + rnd() * 5e4;
            let t0 = rnd() * TAU;
            let t1 = rnd() * TAU;
            let s = ((c.0 + r * t0.cos()).round(), (c.1 + r * t0.sin()).round());
            let e = ((c.0 + r * t1.cos()).round(), (c.1 + r * t1.sin()).round());
            let dir = if rnd() < 0.5 {
                ArcDirection::Cw
            } else {
                ArcDirection::Ccw
            };
            let feed = r * (0.5 + 20.0 * rnd());
            let ts = 0.0005;
            let mut circ = match ReferenceWordCircle::new(c, s, e, dir, feed, ts) {
                Ok(v) => v,
                Err(CircleError::EndPointOffCircle) => continue,
                Err(err) => panic!("{err}"),
            };
            let p = end_exact(&mut circ, s);
            assert_eq!(p, e);
        }
    }

    #[test]
    fn reference_word_matches_kim_eq23() {
        let (r, v, ts) = (2000.0, 40_000.0, 0.001);
        let mut circ = ReferenceWordCircle::from_sweep((0.0, 0.0), (r, 0.0), TAU, v, ts).unwrap();
        let a = circ.step_angle();
        assert!((a - v * ts / r).abs() < 1e-18);
        let amp = 2.0 * r * (0.5 * a).sin() / ts;
        let n = circ.total_steps();
        for k in 0..n - 1 {
            let d = circ.next_increment().unwrap();
            let (vx, vy) = circ.velocity(d);
            let ph = k as f64 * a + 0.5 * a;
            // Kim eq 23 (README: second line with cos).
            assert!((vx + amp * ph.sin()).abs() <= 1e-9 * v, "k={k}");
            assert!((vy - amp * ph.cos()).abs() <= 1e-9 * v, "k={k}");
        }
        // CW mirrors y.
        let mut cw = ReferenceWordCircle::from_sweep((0.0, 0.0), (r, 0.0), -TAU, v, ts).unwrap();
        let d = cw.next_increment().unwrap();
        assert!((d.0 + amp * ts * (0.5 * a).sin()).abs() < 1e-9);
        assert!((d.1 + amp * ts * (0.5 * a).cos()).abs() < 1e-9);
    }

    #[test]
    fn exact_circle_points() {
        let arc = ExactCircle::new((10.0, -20.0), 500.0, 0.3, -2.0).unwrap();
        assert!((arc.length() - 1000.0).abs() < 1e-12);
        for i in 0..=1000 {
            let s = i as f64;
            let p = arc.point_at(s).unwrap();
            let th = 0.3 - s / 500.0;
            assert!((p.0 - (10.0 + 500.0 * th.cos())).abs() < 1e-9);
            assert!((p.1 - (-20.0 + 500.0 * th.sin())).abs() < 1e-9);
            assert!(((p.0 - 10.0).hypot(p.1 + 20.0) - 500.0).abs() < 1e-9);
            let t = arc.tangent_at(s).unwrap();
            assert!((t.0.hypot(t.1) - 1.0).abs() < 1e-12);
        }
        assert_eq!(arc.point_at(-5.0).unwrap(), arc.point_at(0.0).unwrap());
        assert_eq!(arc.point_at(1e9).unwrap(), arc.point_at(1000.0).unwrap());
        assert_eq!(
            arc.point_at(f64::INFINITY).unwrap(),
            arc.point_at(1000.0).unwrap()
        );
        assert_eq!(arc.point_at(f64::NAN), Err(CircleError::InvalidArcLength));
        // From points: the ends are returned exactly.
        let (s, e) = ((1000.0, 0.0), (707.0, 707.0));
        let arc = ExactCircle::from_points((0.0, 0.0), s, e, ArcDirection::Ccw).unwrap();
        assert_eq!(arc.point_at(0.0).unwrap(), s);
        assert_eq!(arc.point_at(arc.length()).unwrap(), e);
        assert!((arc.sweep() - PI / 4.0).abs() < 1e-3);
        let mid = arc.point_at(0.5 * arc.length()).unwrap();
        assert!((mid.0.hypot(mid.1) - 1000.0).abs() < 1e-9);
        let full = ExactCircle::from_points((0.0, 0.0), s, s, ArcDirection::Cw).unwrap();
        assert_eq!(full.sweep(), -TAU);
        let t = full.tangent_at(0.0).unwrap();
        assert!((t.0).abs() < 1e-12 && (t.1 + 1.0).abs() < 1e-12);
    }

    #[test]
    fn invalid_parameters_are_errors() {
        use CircleError::*;
        let o = (0.0, 0.0);
        let s = (100.0, 0.0);
        let e = (0.0, 100.0);
        let ccw = ArcDirection::Ccw;
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, f64::NAN, 0.001).err(),
            Some(InvalidFeed)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, 0.0, 0.001).err(),
            Some(InvalidFeed)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, -1.0, 0.001).err(),
            Some(InvalidFeed)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, 100.0, 0.0).err(),
            Some(InvalidSampleTime)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, 100.0, f64::NAN).err(),
            Some(InvalidSampleTime)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, o, e, ccw, 100.0, 0.001).err(),
            Some(InvalidRadius)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, (0.0, 150.0), ccw, 100.0, 0.001).err(),
            Some(EndPointOffCircle)
        );
        assert_eq!(
            ReferenceWordCircle::new((f64::NAN, 0.0), s, e, ccw, 100.0, 0.001).err(),
            Some(InvalidGeometry)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, 1e6, 0.001).err(),
            Some(StepAngleTooLarge)
        );
        assert_eq!(
            ReferenceWordCircle::new(o, s, e, ccw, f64::MAX, 1e10).err(),
            Some(InvalidFeed)
        );
        assert_eq!(
            ReferenceWordCircle::from_sweep(o, s, 1e12, 1e-6, 1e-6).err(),
            Some(TooManySteps)
        );
        assert_eq!(
            ReferenceWordCircle::from_sweep(o, s, 0.0, 100.0, 0.001).err(),
            Some(InvalidSweep)
        );
        assert_eq!(
            ReferenceWordCircle::from_sweep(o, s, f64::INFINITY, 100.0, 0.001).err(),
            Some(InvalidSweep)
        );
        assert_eq!(
            ExactCircle::new(o, 0.0, 0.0, 1.0).err(),
            Some(InvalidRadius)
        );
        assert_eq!(
            ExactCircle::new(o, -1.0, 0.0, 1.0).err(),
            Some(InvalidRadius)
        );
        assert_eq!(
            ExactCircle::new(o, 1.0, f64::NAN, 1.0).err(),
            Some(InvalidGeometry)
        );
        assert_eq!(ExactCircle::new(o, 1.0, 0.0, 0.0).err(), Some(InvalidSweep));
        assert!(linear_filter_radial_error(100.0, 10.0, 0.001, 0).is_nan());
        assert!(linear_filter_radial_error(-1.0, 10.0, 0.001, 3).is_nan());
        assert!(linear_filter_radial_error(1.0, f64::NAN, 0.001, 3).is_nan());
        assert_eq!(linear_filter_radial_error(100.0, 0.0, 0.001, 3), 0.0);
        assert!(exponential_filter_radial_error(100.0, 10.0, 0.001, 1.0).is_nan());
        assert!(exponential_filter_radial_error(100.0, 10.0, 0.0, 0.5).is_nan());
        assert_eq!(exponential_filter_radial_error(100.0, 0.0, 0.001, 0.5), 0.0);
        assert_eq!(
            exponential_filter_radial_error(100.0, 10.0, 0.001, 0.0),
            0.0
        );
    }

    /// Runs `laps` of a circle through one filter per axis and returns
    /// (R − mean radius, max − min radius) of the filtered position over the
    /// last full revolution before the final (shortened) step.
    fn measured_radial_error(
        r: f64,
        v: f64,
        ts: f64,
        mut fx: AccDecFilter,
        mut fy: AccDecFilter,
        transient_ticks: usize,
    ) -> (f64, f64) {
        let c = (1234.5, -987.25);
        let alpha = v * ts / r;
        let rev = (TAU / alpha).ceil() as usize;
        let laps = ((transient_ticks + rev) as f64 / rev as f64).ceil() + 2.0;
        let start = (c.0 + r, c.1);
        let mut circ = ReferenceWordCircle::from_sweep(c, start, laps * TAU, v, ts).unwrap();
        let n = circ.total_steps() as usize;
        assert!(n >= transient_ticks + rev + 2);
        let (mut px, mut py) = (CompensatedSum::new(), CompensatedSum::new());
        px.add(start.0);
        py.add(start.1);
        let (mut sum, mut cnt, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
        let first = n - 1 - rev;
        for k in 0..n - 1 {
            let d = circ.next_increment().unwrap();
            px.add(fx.step(d.0));
            py.add(fy.step(d.1));
            if k >= first {
                let rad = (px.value() - c.0).hypot(py.value() - c.1);
                sum += rad;
                cnt += 1;
                lo = lo.min(rad);
                hi = hi.max(rad);
            }
        }
        (r - sum / cnt as f64, hi - lo)
    }

    const RADII: [f64; 4] = [200.0, 1000.0, 5000.0, 20000.0];
    const OMEGAS: [f64; 5] = [2.0, 5.0, 10.0, 20.0, 50.0];
    const SAMPLE_TIMES: [f64; 3] = [0.00025, 0.001, 0.002];

    #[test]
    fn linear_filter_radius_matches_kim_eq28() {
        let mut cases = 0;
        let mut worst: f64 = 0.0;
        for &r in &RADII {
            for &omega in &OMEGAS {
                for &ts in &SAMPLE_TIMES {
                    for &m in &[4usize, 16, 40, 100] {
                        let v = omega * r;
                        let dr = linear_filter_radial_error(r, v, ts, m);
                        if !(1e-4..=0.1).contains(&(dr / r)) || (TAU / (omega * ts)) > 30_000.0 {
                            continue;
                        }
                        let f = || AccDecFilter::Linear(LinearFilter::new(m).unwrap());
                        let (meas, spread) = measured_radial_error(r, v, ts, f(), f(), m + 1);
                        let rel = (meas - dr).abs() / dr;
                        worst = worst.max(rel);
                        cases += 1;
                        assert!(
                            rel <= 0.01,
                            "R={r} V={v} ts={ts} m={m}: meas {meas} vs {dr}"
                        );
                        assert!(spread <= 1e-3 * dr, "not steady: spread {spread}");
                    }
                }
            }
        }
        println!("linear: {cases} cases, worst |ΔR_meas − ΔR_eq28|/ΔR = {worst:e}");
        assert!(cases >= 20);
    }

    #[test]
    fn exponential_filter_radius_matches_kim_eq32() {
        let mut cases = 0;
        let mut worst: f64 = 0.0;
        for &r in &RADII {
            for &omega in &OMEGAS {
                for &ts in &SAMPLE_TIMES {
                    for &tau in &[0.005, 0.015, 0.03, 0.06] {
                        let v = omega * r;
                        let proto = ExponentialFilter::from_time_constant(tau, ts).unwrap();
                        let a = proto.pole();
                        let dr = exponential_filter_radial_error(r, v, ts, a);
                        if !(1e-4..=0.1).contains(&(dr / r)) || (TAU / (omega * ts)) > 30_000.0 {
                            continue;
                        }
                        // Transient a^k: 40 time constants shrink it by e^-40.
                        let transient = (40.0 * tau / ts).ceil() as usize;
                        let (meas, spread) = measured_radial_error(
                            r,
                            v,
                            ts,
                            AccDecFilter::Exponential(proto.clone()),
                            AccDecFilter::Exponential(proto),
                            transient,
                        );
                        let rel = (meas - dr).abs() / dr;
                        worst = worst.max(rel);
                        cases += 1;
                        assert!(
                            rel <= 0.01,
                            "R={r} V={v} ts={ts} tau={tau}: meas {meas} vs {dr}"
                        );
                        assert!(spread <= 1e-3 * dr, "not steady: spread {spread}");
                    }
                }
            }
        }
        println!("exponential: {cases} cases, worst |ΔR_meas − ΔR_eq32|/ΔR = {worst:e}");
        assert!(cases >= 20);
    }

    #[test]
    fn bell_filter_radius_is_product_of_gains() {
        // Not a paper equation: linear then exponential multiplies the gains.
        let (r, ts) = (2000.0, 0.001);
        for &(omega, tau) in &[(5.0f64, 0.02f64), (10.0, 0.035), (20.0, 0.01)] {
            let v = omega * r;
            let m = (tau / ts).round() as usize;
            let a = crate::motion::filters::exponential_pole(tau, ts);
            let g = (1.0 - linear_filter_radial_error(r, v, ts, m) / r)
                * (1.0 - exponential_filter_radial_error(r, v, ts, a) / r);
            let dr = r * (1.0 - g);
            let f = || {
                AccDecFilter::from_time_constant(crate::motion::filters::FilterKind::Bell, tau, ts)
                    .unwrap()
            };
            let (meas, _) =
                measured_radial_error(r, v, ts, f(), f(), m + (40.0 * tau / ts) as usize);
            assert!((meas - dr).abs() <= 0.01 * dr, "meas {meas} vs {dr}");
        }
    }
}
