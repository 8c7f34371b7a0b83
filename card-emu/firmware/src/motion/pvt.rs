//! PT/PVT interpolation (layout 1.7): cubic Hermite segments through streamed points, as Googol
//! GTS's PVT mode and Delta Tau's PVT moves. Pure functions over plain data, shared by the card
//! (`firmware::pvt`) and the host (the SDK finds which point of a refused command broke a
//! limit with the same check).
//!
//! A segment runs from `(t0, p0, v0)` to `(t1, p1, v1)` over `h = t1 − t0`:
//!
//! ```text
//! p(s) = h00(s/h)·p0 + h10(s/h)·h·v0 + h01(s/h)·p1 + h11(s/h)·h·v1,   0 ≤ s ≤ h
//! ```
//!
//! with the Hermite basis `h00 = 2u³ − 3u² + 1`, `h10 = u³ − 2u² + u`, `h01 = −2u³ + 3u²`,
//! `h11 = u³ − u²`. It passes through both points with both velocities, so a chain of segments
//! passes exactly through every point (at `s = 0` a segment is exactly `p0`) and its velocity
//! is continuous; its acceleration is linear on each segment (it may jump at a point), its jerk
//! constant on each.
//!
//! **PT** (no velocities given): the velocity at a point is the three-point estimate of the
//! non-uniform grid, `v_i = (d₋·h₊ + d₊·h₋)/(h₋ + h₊)` with `d₋`, `d₊` the slopes of the chords
//! before and after and `h₋`, `h₊` their durations (exact for a parabola; Catmull-Rom on a uniform
//! grid). The stream starts at rest and a point marked last ends at rest.
//!
//! **Limits.** Velocity is a quadratic in `s` (its extremes at the ends or at its vertex) and
//! acceleration linear (its extremes at the ends), so [`check_segment`] checks both exactly.
#![forbid(unsafe_code)]

/// One point of a stream: time from the stream's start (s), position (counts), velocity
/// (counts/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PvtPoint {
    /// Seconds from the start of the stream.
    pub t: f64,
    /// Counts.
    pub p: f64,
    /// Counts per second.
    pub v: f64,
}

/// Why a point is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PvtError {
    /// A value is not finite.
    NotFinite,
    /// Its time is not at least one servo period after the point before, or the segment is
    /// longer than the longest move.
    Time,
    /// A position beyond the card's range.
    Position,
    /// The segment into it breaks the velocity or acceleration limit.
    Limit,
}

/// The velocity and acceleration limits of a stream, counts/s and counts/s².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtLimits {
    /// Counts/s.
    pub vmax: f64,
    /// Counts/s².
    pub amax: f64,
}

/// Slack on the limit checks (rounding).
const SLACK: f64 = 1.0 + 1e-9;

/// Position, velocity and acceleration of the segment `a → b` at `s` seconds after `a`.
#[inline]
pub fn sample(a: &PvtPoint, b: &PvtPoint, s: f64) -> (f64, f64, f64) {
    let h = b.t - a.t;
    if s <= 0.0 {
        return (a.p, a.v, accel_at(a, b, 0.0));
    }
    let u = s / h;
    let (u2, u3) = (u * u, u * u * u);
    let p = (2.0 * u3 - 3.0 * u2 + 1.0) * a.p
        + (u3 - 2.0 * u2 + u) * h * a.v
        + (-2.0 * u3 + 3.0 * u2) * b.p
        + (u3 - u2) * h * b.v;
    let v = (6.0 * u2 - 6.0 * u) / h * (a.p - b.p)
        + (3.0 * u2 - 4.0 * u + 1.0) * a.v
        + (3.0 * u2 - 2.0 * u) * b.v;
    (p, v, accel_at(a, b, u))
}

/// The acceleration at `u = s/h` of the segment `a → b`.
#[inline]
fn accel_at(a: &PvtPoint, b: &PvtPoint, u: f64) -> f64 {
    let h = b.t - a.t;
    (12.0 * u - 6.0) / (h * h) * (a.p - b.p) + (6.0 * u - 4.0) / h * a.v + (6.0 * u - 2.0) / h * b.v
}

/// Is `b` a point that may follow `a` at a servo period of `ts` (finite, in range, at least one
/// period later, the segment no longer than `max_time`)? Its velocity is not looked at (PT).
pub fn check_point(a: &PvtPoint, b: &PvtPoint, ts: f64, max_time: f64) -> Result<(), PvtError> {
    if !(b.t.is_finite() && b.p.is_finite() && b.v.is_finite()) {
        return Err(PvtError::NotFinite);
    }
    let h = b.t - a.t;
    if !(h >= ts * (1.0 - 1e-9) && h <= max_time) {
        return Err(PvtError::Time);
    }
    if b.p.abs() > crate::MAX_POSITION {
        return Err(PvtError::Position);
    }
    Ok(())
}

/// Does the segment `a → b` stay within `lim` (velocity over the whole segment, acceleration at
/// both ends, which bound it)?
pub fn check_segment(a: &PvtPoint, b: &PvtPoint, lim: &PvtLimits) -> Result<(), PvtError> {
    let h = b.t - a.t;
    // v(u) = A u² + B u + C.
    let dp = a.p - b.p;
    let qa = 6.0 * dp / h + 3.0 * a.v + 3.0 * b.v;
    let qb = -6.0 * dp / h - 4.0 * a.v - 2.0 * b.v;
    let mut vmax = a.v.abs().max(b.v.abs());
    if qa != 0.0 {
        let u = -qb / (2.0 * qa);
        if u > 0.0 && u < 1.0 {
            vmax = vmax.max((qa * u * u + qb * u + a.v).abs());
        }
    }
    let amax = accel_at(a, b, 0.0).abs().max(accel_at(a, b, 1.0).abs());
    if !(vmax.is_finite() && amax.is_finite()) {
        return Err(PvtError::Limit);
    }
    if vmax > lim.vmax * SLACK || amax > lim.amax * SLACK {
        return Err(PvtError::Limit);
    }
    Ok(())
}

/// PT: the velocity at `b` between `a` and `c` (the three-point estimate, see the module doc).
pub fn pt_velocity(a: &PvtPoint, b: &PvtPoint, c: &PvtPoint) -> f64 {
    let (hm, hp) = (b.t - a.t, c.t - b.t);
    let (dm, dp) = ((b.p - a.p) / hm, (c.p - b.p) / hp);
    (dm * hp + dp * hm) / (hm + hp)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(t: f64, p: f64, v: f64) -> PvtPoint {
        PvtPoint { t, p, v }
    }

    #[test]
    fn a_segment_meets_both_points_and_velocities() {
        let (a, b) = (pt(0.5, 100.0, 40.0), pt(0.75, 120.0, -8.0));
        let (p, v, _) = sample(&a, &b, 0.0);
        assert_eq!((p, v), (100.0, 40.0));
        let (p, v, _) = sample(&a, &b, 0.25);
        assert!(
            (p - 120.0).abs() < 1e-12 && (v + 8.0).abs() < 1e-12,
            "{p} {v}"
        );
        // Acceleration by finite differences of the velocity.
        let e = 1e-7;
        let (_, v1, acc) = sample(&a, &b, 0.1);
        let (_, v2, _) = sample(&a, &b, 0.1 + e);
        assert!(((v2 - v1) / e - acc).abs() < 1e-3 * acc.abs().max(1.0));
    }

    #[test]
    fn pt_velocity_is_exact_on_a_parabola() {
        let f = |t: f64| 3.0 * t * t - 2.0 * t + 1.0;
        let (a, b, c) = (
            pt(0.0, f(0.0), 0.0),
            pt(0.3, f(0.3), 0.0),
            pt(1.0, f(1.0), 0.0),
        );
        assert!((pt_velocity(&a, &b, &c) - (6.0 * 0.3 - 2.0)).abs() < 1e-12);
    }

    #[test]
    fn limits_are_checked_exactly() {
        let lim = PvtLimits {
            vmax: 100.0,
            amax: 1000.0,
        };
        // From rest to rest over 1 s, 50 counts: peak velocity 1.5 · 50 = 75, acceleration 300.
        let (a, b) = (pt(0.0, 0.0, 0.0), pt(1.0, 50.0, 0.0));
        assert_eq!(check_segment(&a, &b, &lim), Ok(()));
        let b = pt(1.0, 70.0, 0.0); // peak 105
        assert_eq!(check_segment(&a, &b, &lim), Err(PvtError::Limit));
        let b = pt(0.2, 5.0, 0.0); // acceleration 6 · 5 / 0.04 = 750
        assert_eq!(check_segment(&a, &b, &lim), Ok(()));
        let b = pt(0.2, 7.0, 0.0); // 1050
        assert_eq!(check_segment(&a, &b, &lim), Err(PvtError::Limit));
    }

    #[test]
    fn points_are_checked() {
        let a = pt(1.0, 0.0, 0.0);
        let ts = 1e-4;
        assert_eq!(check_point(&a, &pt(1.0001, 1.0, 0.0), ts, 1e3), Ok(()));
        assert_eq!(
            check_point(&a, &pt(1.0, 1.0, 0.0), ts, 1e3),
            Err(PvtError::Time)
        );
        assert_eq!(
            check_point(&a, &pt(0.5, 1.0, 0.0), ts, 1e3),
            Err(PvtError::Time)
        );
        assert_eq!(
            check_point(&a, &pt(f64::NAN, 1.0, 0.0), ts, 1e3),
            Err(PvtError::NotFinite)
        );
        assert_eq!(
            check_point(&a, &pt(2.0, 1e300, 0.0), ts, 1e3),
            Err(PvtError::Position)
        );
        assert_eq!(
            check_point(&a, &pt(2.0, 1.0, f64::INFINITY), ts, 1e3),
            Err(PvtError::NotFinite)
        );
    }
}
