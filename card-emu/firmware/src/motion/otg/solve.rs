//! The position problem's solver (see the module doc of [`super`]: the profiles, and finding
//! the roots): [`Step`] is the problem after the brake in one frame, each of its families
//! (Vel, None, Acc0, Acc1, Acc0Acc1) offers its candidates, the shortest valid one is the
//! [`Best`]; [`Quartic`] and [`bracketed`] are the root finders.

use super::{pulse, Lim, SIXTH};
use crate::math;

/// A 7-segment profile in the up frame: durations and the exact accelerations after each.
#[derive(Clone, Copy, Debug)]
pub(super) struct Prof {
    pub(super) t: [f64; 7],
    pub(super) acc: [f64; 7],
}

/// Jerks of the 7 segments in the up frame, in units of `j`.
pub(super) const UDDU: [f64; 7] = [1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0];

/// The best candidate so far: profile, frame sign and total duration.
#[derive(Clone, Copy, Debug)]
pub(super) struct Best {
    pub(super) prof: Prof,
    pub(super) s: f64,
    pub(super) total: f64,
}

/// The position problem after the brake in one frame (scaled units).
pub(super) struct Step {
    v0: f64,
    a0: f64,
    vf: f64,
    pd: f64,
    l: Lim,
    /// `j (vf - v0) + a0²/2`: `a1² - a2² + j (a1 t2 + a2 t6) = d` (the velocity equation).
    d: f64,
    /// Velocity scale of the tolerances.
    vscale: f64,
    /// Frame sign (+1 up, -1 down).
    s: f64,
    /// `1 / j`, `j / 2` and `j / 6`.
    ij: f64,
    jh: f64,
    j6: f64,
}

/// What [`Step::offer`] made of a candidate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Offer {
    /// Kept (valid and the shortest so far), or refused for good (not shorter, or beyond a
    /// limit).
    Done,
    /// Valid but off the target by more than rounding: a root that needs polishing.
    Missed,
}

/// Tolerance of a candidate's end position: ulps of the travel (the rounding of each term and
/// each running sum of the integration, summed)...
const OFFER_ULPS: f64 = 32.0;
/// ... and for a root not yet polished on the exact integration (the card's check allows 16
/// ulps of its own travel).
const ROUGH_ULPS: f64 = 4.0;

/// 1/3 (rounded).
const THIRD: f64 = 1.0 / 3.0;

/// Rounding bound of [`Quartic::eval`], relative to the sum of the magnitudes of its terms
/// (Horner's own `8u`, and a few roundings in each coefficient).
const QUARTIC_ERR: f64 = 32.0 * f64::EPSILON;

/// The polynomial `c[0] + c[1] x + ... + c[4] x⁴`, with `m[i]` the sum of the magnitudes of
/// the terms that make up `c[i]` (which its rounding is relative to).
#[derive(Clone, Copy, Debug)]
struct Quartic {
    c: [f64; 5],
    m: [f64; 5],
}

impl Quartic {
    /// Value, first and second derivative, and a bound on the value's rounding error at `x`
    /// (Horner).
    fn eval(&self, x: f64) -> (f64, f64, f64, f64) {
        let (c, m, ax) = (&self.c, &self.m, x.abs());
        let p = (((c[4] * x + c[3]) * x + c[2]) * x + c[1]) * x + c[0];
        let dp = ((4.0 * c[4] * x + 3.0 * c[3]) * x + 2.0 * c[2]) * x + c[1];
        let ddp = (12.0 * c[4] * x + 6.0 * c[3]) * x + 2.0 * c[2];
        let e = (((m[4] * ax + m[3]) * ax + m[2]) * ax + m[1]) * ax + m[0];
        (p, dp, ddp, QUARTIC_ERR * e)
    }

    /// The root in `[lo, hi]` where the polynomial changes sign (from the sign of `flo` to that
    /// of `fhi`): Halley's method (`x - 2 p p' / (2 p'² - p p'')`, cubically convergent, 4
    /// steps where Newton takes 7 on the bench's states) from the middle, safeguarded by
    /// bisection as [`bracketed`]; until the value is within its rounding bound, or a step is
    /// below 2 ulps, or below 1e-6 (relative) and a thousandth of the one before (then the
    /// next would be below an ulp).
    fn root(&self, mut lo: f64, mut hi: f64, flo: f64) -> f64 {
        let rising = flo < 0.0;
        let mut x = mid(lo, hi);
        let (mut dx, mut dx_old) = (hi - lo, hi - lo);
        for _ in 0..200 {
            let (p, dp, ddp, err) = self.eval(x);
            if p.abs() <= err || p.is_nan() {
                break;
            }
            if (p < 0.0) == rising {
                lo = x;
            } else {
                hi = x;
            }
            let den = 2.0 * dp * dp - p * ddp;
            let step = if den > 0.0 {
                2.0 * p * dp / den
            } else {
                p / dp
            };
            let Some(nx) = safeguarded(x, step, lo, hi, &mut dx, &mut dx_old) else {
                break;
            };
            let s = (nx - x).abs();
            let done = s <= 2.0 * f64::EPSILON * x.abs()
                || (s <= 1e-6 * x.abs() && s <= 1e-3 * dx_old.abs());
            x = nx;
            if done {
                break;
            }
        }
        x
    }
}

/// Whether `best` is already at least as short as `lower`, a lower bound on the durations of a
/// family's candidates (then `offer` would refuse them all; a margin of 1e-12 for the
/// different roundings of the bound and of the candidates' own sums).
fn beaten(best: &Option<Best>, lower: f64) -> bool {
    best.is_some_and(|b| lower * (1.0 - 1e-12) >= b.total)
}

/// Relative tolerance of a candidate on the velocity limits (Ruckig: 1e-12 absolute).
const CAND_V_SLACK: f64 = 1e-12;

impl Step {
    pub(super) fn new(v0: f64, a0: f64, vf: f64, pd: f64, l: Lim, s: f64) -> Step {
        let vscale = 1.0f64
            .max(v0.abs())
            .max(vf.abs())
            .max(l.vmax)
            .max(-l.vmin)
            .max(a0 * a0 / l.j);
        Step {
            v0,
            a0,
            vf,
            pd,
            l,
            d: l.j * (vf - v0) + 0.5 * a0 * a0,
            vscale,
            s,
            ij: 1.0 / l.j,
            jh: 0.5 * l.j,
            j6: l.j * SIXTH,
        }
    }

    /// End position minus `pd`.
    fn residual(&self, p: &Prof) -> f64 {
        let (mut x, mut v, mut a) = (0.0, self.v0, self.a0);
        for ((&t, &ae), u) in p.t.iter().zip(&p.acc).zip(UDDU) {
            x += t * (v + t * (0.5 * a + t * (u * self.j6)));
            v += t * (a + t * (u * self.jh));
            a = ae;
        }
        x - self.pd
    }

    /// Keeps `p` if it is valid and shorter than `best`: every duration finite and `>= 0`, the
    /// accelerations within the limits, the velocity within the limits from segment 3 on (at
    /// the joints and where the acceleration crosses zero), on the target. `Missed` when it
    /// is all that but off the target (a root to polish).
    fn offer(&self, p: &Prof, best: &mut Option<Best>) -> Offer {
        self.offer_within(p, OFFER_ULPS, best)
    }

    /// [`Step::offer`] with the tolerance on the end position in ulps of the travel (the sum
    /// of the magnitudes of every term of the integration).
    #[inline(always)]
    fn offer_within(&self, p: &Prof, ulps: f64, best: &mut Option<Best>) -> Offer {
        let l = &self.l;
        let mut total = 0.0;
        let mut bad = false;
        for &t in &p.t {
            bad |= t.is_nan() || t < 0.0;
            total += t;
        }
        // (an infinite or NaN duration leaves the total so)
        if bad || !total.is_finite() || best.is_some_and(|b| total >= b.total) {
            return Offer::Done;
        }
        // Without a branch per segment: the segments of zero duration (which differ from one
        // candidate to the next) change nothing and are checked for nothing.
        let (vhi, vlo) = (
            l.vmax + CAND_V_SLACK * self.vscale,
            l.vmin - CAND_V_SLACK * self.vscale,
        );
        let atol = CAND_V_SLACK * l.amax.max(-l.amin);
        let (ahi, alo) = (l.amax + atol, l.amin - atol);
        let ij2 = 0.5 * self.ij;
        let (mut x, mut v, mut a): (f64, f64, f64) = (0.0, self.v0, self.a0);
        for (i, ((&t, &ae), u)) in p.t.iter().zip(&p.acc).zip(UDDU).enumerate() {
            let on = t > 0.0;
            bad |= on && (ae > ahi || ae < alo);
            // Where the acceleration crosses zero inside the segment, the velocity peaks at
            // `v - a²/2j`.
            let vx = v - u * a * a * ij2;
            bad |= i >= 2 && on && u != 0.0 && a * ae < 0.0 && (vx > vhi || vx < vlo);
            x += t * (v + t * (0.5 * a + t * (u * self.j6)));
            v += t * (a + t * (u * self.jh));
            a = ae;
            bad |= i >= 2 && on && (v > vhi || v < vlo);
        }
        if bad {
            return Offer::Done;
        }
        // On the target within `ulps` of the travel, which is at least `|pd|`: the travel
        // itself (another pass) only when that does not settle it.
        let miss = (x - self.pd).abs();
        let tol = ulps * f64::EPSILON;
        let on_target = miss <= tol * self.pd.abs() || miss <= tol * self.travel(p);
        if !on_target || (v - self.vf).abs() > 64.0 * f64::EPSILON * self.vscale {
            return Offer::Missed;
        }
        *best = Some(Best {
            prof: *p,
            s: self.s,
            total,
        });
        Offer::Done
    }

    /// The rounding scale of `p`'s integration: `|pd|` plus the magnitudes of each term and of
    /// each running sum of the end position.
    fn travel(&self, p: &Prof) -> f64 {
        let (mut x, mut v, mut a): (f64, f64, f64) = (0.0, self.v0, self.a0);
        let mut xm = self.pd.abs();
        for ((&t, &ae), u) in p.t.iter().zip(&p.acc).zip(UDDU) {
            if t > 0.0 {
                let j6 = u * self.j6;
                x += t * (v + t * (0.5 * a + t * j6));
                xm += x.abs() + t * (v.abs() + t * (0.5 * a.abs() + t * j6.abs()));
                v += t * (a + t * (u * self.jh));
            }
            a = ae;
        }
        xm
    }

    /// Profile Vel: up to `vmax` (ramp `+j`, hold `amax`, ramp `-j`), cruise, down to `vf`.
    fn vel(&self, best: &mut Option<Best>) {
        let l = &self.l;
        let j = l.j;
        let Some((a1, t0, t1, t2)) = pulse(self.v0, self.a0, l.vmax, l.amax, j) else {
            return;
        };
        let Some((na2, t6, t5, t4)) = pulse(-l.vmax, 0.0, -self.vf, -l.amin, j) else {
            return;
        };
        // (the cruise only adds)
        if beaten(best, t0 + t1 + t2 + t4 + t5 + t6) {
            return;
        }
        let mut p = Prof {
            t: [t0, t1, t2, 0.0, t4, t5, t6],
            acc: [a1, a1, 0.0, 0.0, -na2, -na2, 0.0],
        };
        // The cruise closes the distance, at the velocity the first pulse actually reaches
        // (vmax up to rounding, which a long cruise would multiply; or above vmax when a0
        // overshoots, which `offer` refuses).
        let r = self.residual(&p);
        let (mut v, mut a) = (self.v0, self.a0);
        for ((&t, &ae), u) in p.t.iter().zip(&p.acc).zip(UDDU).take(3) {
            v += t * (a + 0.5 * u * j * t);
            a = ae;
        }
        p.t[3] = -r / v;
        self.offer(&p, best);
    }

    /// Profile None: `+j` to `a1`, `-j` to `a2 <= 0`, `+j` to 0, no hold, no cruise.
    fn none(&self, best: &mut Option<Best>) {
        let l = &self.l;
        let (a0, d, j, ij) = (self.a0, self.d, l.j, self.ij);
        // The domain of u = a1 - a2, from a1 <= amax, a2 >= amin, a2 <= 0, a1 >= a0 (each a
        // quadratic inequality in u, solved in its stable form).
        let s1 = l.amax * l.amax - d;
        let s2 = l.amin * l.amin + d;
        if !(s1 >= 0.0 && s2 >= 0.0) {
            return;
        }
        let (s1, s2) = (math::sqrt(s1), math::sqrt(s2));
        let mut lo = (d / (l.amax + s1)).max(-d / (s2 - l.amin)).max(0.0);
        let hi = (l.amax + s1).min(s2 - l.amin);
        if d > 0.0 {
            lo = lo.max(math::sqrt(d));
        }
        let s0 = a0 * a0 - d;
        if s0 > 0.0 {
            let s0 = math::sqrt(s0);
            lo = lo.max(if a0 >= 0.0 { a0 + s0 } else { -d / (s0 - a0) });
        }
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return;
        }
        // The duration t1 + t3 + t7 = (2u - a0)/j grows with u: the shortest at `lo`.
        if beaten(best, (2.0 * lo - a0) * ij) {
            return;
        }
        let prof = |u: f64| {
            let (a1, a2) = if u > 0.0 {
                (0.5 * (u + d / u), 0.5 * (d / u - u))
            } else {
                (0.0, 0.0)
            };
            let a1 = a1.min(l.amax).max(a0);
            let a2 = a2.max(l.amin).min(0.0);
            Prof {
                t: [(a1 - a0) * ij, 0.0, (a1 - a2) * ij, 0.0, 0.0, 0.0, -a2 * ij],
                acc: [a1, a1, a2, a2, a2, a2, 0.0],
            }
        };
        let (v0, vf, pd) = (self.v0, self.vf, self.pd);
        let c = j * (v0 + vf) - 0.5 * a0 * a0;
        let slope = |u: f64| {
            let w = u * u;
            (3.0 * w + 4.0 * c + d * (d / w)) / (4.0 * j * j)
        };
        // 4 j² u r(u) = u⁴ + 4c u² + 4 (a0³/3 - a0 j v0 - j² pd) u - d².
        let dm = j * (v0.abs() + vf.abs()) + 0.5 * a0 * a0;
        let poly = Quartic {
            c: [
                -d * d,
                4.0 * (a0 * a0 * a0 * THIRD - a0 * j * v0 - j * j * pd),
                4.0 * c,
                0.0,
                1.0,
            ],
            m: [
                dm * dm,
                4.0 * (a0.abs() * (a0 * a0 * THIRD + j * v0.abs()) + j * j * pd.abs()),
                4.0 * dm,
                0.0,
                1.0,
            ],
        };
        // Critical points: u² = (-2c ± √(4c² - 3d²)) / 3.
        let mut cuts = [f64::NAN; 2];
        let disc = 4.0 * c * c - 3.0 * d * d;
        if c < 0.0 && disc >= 0.0 {
            let w1 = (-2.0 * c + math::sqrt(disc)) / 3.0;
            cuts = [math::sqrt(w1), math::sqrt(d * d / (3.0 * w1))];
        }
        self.pieces(lo, hi, cuts, &poly, &prof, &slope, best);
    }

    /// Profile Acc0: `+j` to `amax`, hold, `-j` to `a2`, `+j` to 0.
    fn acc0(&self, best: &mut Option<Best>) {
        let l = &self.l;
        let (a0, d, j, ij) = (self.a0, self.d, l.j, self.ij);
        let lo = l.amin;
        let q = l.amax * l.amax - d;
        let hi = if q > 0.0 { -math::sqrt(q) } else { 0.0 };
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return;
        }
        let t0 = (l.amax - a0) * ij;
        let prof = |a2: f64| Prof {
            t: [
                t0,
                ((a2 * a2 - q) * (ij / l.amax)).max(0.0),
                (l.amax - a2) * ij,
                0.0,
                0.0,
                0.0,
                -a2 * ij,
            ],
            acc: [l.amax, l.amax, a2, a2, a2, a2, 0.0],
        };
        // The duration falls as a2 rises (its derivative is 2 (a2 - amax) / (j amax)): the
        // shortest at `hi`.
        if beaten(best, prof(hi).t.iter().sum()) {
            return;
        }
        let (v0, vf, pd, am) = (self.v0, self.vf, self.pd, l.amax);
        let slope = |x: f64| (x - am) * (2.0 * x * x - am * x + 2.0 * j * vf) / (am * j * j);
        // 2 j² amax r(a2) = a2⁴ - 2 amax a2³ + (amax² + 2 j vf) a2² - 4 amax j vf a2 + k0.
        let b = am - a0;
        let k0 = a0 * a0 * (a0 * (2.0 * THIRD * am - 0.25 * a0) - 0.5 * am * am)
            + j * v0 * b * b
            + am * am * j * vf
            - 2.0 * am * j * j * pd
            + j * j * (vf - v0) * (vf + v0);
        let m0 = a0 * a0 * (a0.abs() * (2.0 * THIRD * am + 0.25 * a0.abs()) + 0.5 * am * am)
            + j * v0.abs() * b * b
            + am * am * j * vf.abs()
            + 2.0 * am * j * j * pd.abs()
            + j * j * (vf.abs() + v0.abs()) * (vf.abs() + v0.abs());
        let poly = Quartic {
            c: [
                k0,
                -4.0 * am * j * vf,
                am * am + 2.0 * j * vf,
                -2.0 * am,
                1.0,
            ],
            m: [
                m0,
                4.0 * am * j * vf.abs(),
                am * am + 2.0 * j * vf.abs(),
                2.0 * am,
                1.0,
            ],
        };
        let mut cuts = [f64::NAN; 2];
        if vf < 0.0 {
            cuts[0] = 4.0 * j * vf / (am + math::sqrt(am * am - 16.0 * j * vf));
        }
        self.pieces(lo, hi, cuts, &poly, &prof, &slope, best);
    }

    /// Profile Acc1: `+j` to `a1`, `-j` to `amin`, hold, `+j` to 0.
    fn acc1(&self, best: &mut Option<Best>) {
        let l = &self.l;
        let (a0, d, j, ij) = (self.a0, self.d, l.j, self.ij);
        let q = d + l.amin * l.amin;
        let s = if q > 0.0 { math::sqrt(q) } else { 0.0 };
        let lo = a0.max(l.amin);
        let e = 2.0 * j * self.v0 - a0 * a0;
        let prof = |a1: f64| Prof {
            t: [
                (a1 - a0) * ij,
                0.0,
                (a1 - l.amin) * ij,
                0.0,
                0.0,
                ((a1 * a1 - q) * (ij / -l.amin)).max(0.0),
                -l.amin * ij,
            ],
            acc: [a1, a1, l.amin, l.amin, l.amin, l.amin, 0.0],
        };
        let slope = |x: f64| -(x - l.amin) * (2.0 * x * x - l.amin * x + e) / (l.amin * j * j);
        // -2 j² amin r(a1) = a1⁴ - 2 amin a1³ + (amin² - e') a1² + 2 amin e' a1 + k0 with
        // e' = a0² - 2 j v0 (= -e).
        let (v0, vf, pd, an) = (self.v0, self.vf, self.pd, l.amin);
        let em = a0 * a0 + 2.0 * j * v0.abs();
        let k0 = a0 * a0 * (a0 * (0.25 * a0 - 2.0 * THIRD * an) - 0.5 * an * an)
            + j * v0 * (an * an + 2.0 * a0 * an - a0 * a0)
            + an * an * j * vf
            + 2.0 * an * j * j * pd
            + j * j * (v0 - vf) * (v0 + vf);
        let m0 = a0 * a0 * (a0.abs() * (0.25 * a0.abs() - 2.0 * THIRD * an) + 0.5 * an * an)
            + j * v0.abs() * (an * an - 2.0 * a0.abs() * an + a0 * a0)
            + an * an * j * vf.abs()
            - 2.0 * an * j * j * pd.abs()
            + j * j * (vf.abs() + v0.abs()) * (vf.abs() + v0.abs());
        let poly = Quartic {
            c: [k0, -2.0 * an * e, an * an + e, -2.0 * an, 1.0],
            m: [m0, -2.0 * an * em, an * an + em, -2.0 * an, 1.0],
        };
        let disc = an * an - 8.0 * e;
        let mut cuts = [f64::NAN; 2];
        if disc >= 0.0 {
            let r1 = (an - math::sqrt(disc)) / 4.0;
            cuts = [r1, if r1 != 0.0 { e / (2.0 * r1) } else { 0.0 }];
        }
        // a1 outside (-s, s): up to two intervals. The duration grows with a1 (its
        // derivative is 2 (a1 - amin) / (j (-amin)) > 0): each interval's shortest is at its
        // lower end.
        let shorter = |a1: f64, best: &Option<Best>| !beaten(best, prof(a1).t.iter().sum());
        if s == 0.0 {
            if lo <= l.amax && shorter(lo, best) {
                self.pieces(lo, l.amax, cuts, &poly, &prof, &slope, best);
            }
            return;
        }
        if lo <= -s && shorter(lo, best) {
            self.pieces(lo, (-s).min(l.amax), cuts, &poly, &prof, &slope, best);
        }
        let lo2 = lo.max(s);
        if lo2 <= l.amax && shorter(lo2, best) {
            self.pieces(lo2, l.amax, cuts, &poly, &prof, &slope, best);
        }
    }

    /// Profile Acc0Acc1: `+j` to `amax`, hold `t2`, `-j` to `amin`, hold, `+j` to 0; the end
    /// position is quadratic in the first hold `t2`.
    fn acc0acc1(&self, best: &mut Option<Best>) {
        let l = &self.l;
        let (a0, j, ij) = (self.a0, l.j, self.ij);
        let dd = self.d - l.amax * l.amax + l.amin * l.amin;
        let lo = (dd / (j * l.amax)).max(0.0);
        let prof = |x: f64| Prof {
            t: [
                (l.amax - a0) * ij,
                x,
                (l.amax - l.amin) * ij,
                0.0,
                0.0,
                ((j * l.amax * x - dd) * (ij / -l.amin)).max(0.0),
                -l.amin * ij,
            ],
            acc: [l.amax, l.amax, l.amin, l.amin, l.amin, l.amin, 0.0],
        };
        // The duration grows with t2 (t6 with it): the shortest at `lo`.
        if beaten(best, prof(lo).t.iter().sum()) {
            return;
        }
        let e = 2.0 * j * self.v0 - a0 * a0;
        let alpha = -l.amax * (l.amax - l.amin) / (2.0 * l.amin);
        let beta =
            -(l.amax - l.amin) * (2.0 * l.amax * l.amax - l.amax * l.amin + e) / (2.0 * l.amin * j);
        let slope = |x: f64| 2.0 * alpha * x + beta;
        // r(lo + h) = r_lo + r'(lo) h + alpha h², exactly (up to rounding in r_lo).
        let r_lo = self.residual(&prof(lo));
        let s_lo = slope(lo);
        let disc = s_lo * s_lo - 4.0 * alpha * r_lo;
        if disc.is_nan() || disc < 0.0 {
            return;
        }
        let sq = math::sqrt(disc);
        // Stable pair of roots of alpha h² + s h + r = 0.
        let qq = -0.5 * (s_lo + if s_lo >= 0.0 { sq } else { -sq });
        let mut roots = [f64::NAN; 2];
        if qq != 0.0 {
            roots = [qq / alpha, r_lo / qq];
        } else if r_lo == 0.0 {
            roots[0] = 0.0;
        }
        for h in roots {
            if h >= 0.0 {
                // Newton on the exact residual while the root is off the target (by more than
                // rounding, then by more than the usual tolerance).
                let mut x = lo + h;
                let mut missed = true;
                for _ in 0..3 {
                    let p = prof(x);
                    if self.offer_within(&p, ROUGH_ULPS, best) == Offer::Done {
                        missed = false;
                        break;
                    }
                    let nx = (x - self.residual(&p) / slope(x)).max(lo);
                    if !nx.is_finite() || nx == x {
                        break;
                    }
                    x = nx;
                }
                if missed {
                    self.offer(&prof(x), best);
                }
            }
        }
    }

    /// Splits `[lo, hi]` at the critical points `cuts` into pieces on which the residual is
    /// monotone and solves each piece whose ends bracket zero. `poly` is a positive multiple of
    /// the residual on the domain, with its rounding bound: where its value exceeds the bound
    /// it has the residual's sign, elsewhere the exact residual decides.
    #[allow(clippy::too_many_arguments)]
    fn pieces<P, S>(
        &self,
        lo: f64,
        hi: f64,
        cuts: [f64; 2],
        poly: &Quartic,
        prof: &P,
        slope: &S,
        best: &mut Option<Best>,
    ) where
        P: Fn(f64) -> Prof,
        S: Fn(f64) -> f64,
    {
        let cuts = if cuts[0] > cuts[1] {
            [cuts[1], cuts[0]]
        } else {
            cuts
        };
        let mut xs = [lo, hi, hi, hi];
        let mut n = 1;
        for c in cuts {
            if c > lo && c < hi {
                xs[n] = c;
                n += 1;
            }
        }
        xs[n] = hi;
        let sign_at = |x: f64| {
            let (p, _, _, err) = poly.eval(x);
            if p.abs() > err {
                p
            } else {
                self.residual(&prof(x))
            }
        };
        let mut prev = (xs[0], sign_at(xs[0]));
        if prev.1 == 0.0 {
            self.offer(&prof(prev.0), best);
        }
        for &x in &xs[1..=n] {
            let fx = sign_at(x);
            let (x0, f0) = prev;
            if fx == 0.0 {
                self.offer(&prof(x), best);
            } else if f0 != 0.0 && (f0 < 0.0) != (fx < 0.0) {
                self.root(x0, x, f0, poly, prof, slope, best);
            }
            prev = (x, fx);
        }
    }

    /// The root in `[lo, hi]`, where the residual changes sign (from that of `flo`), offered:
    /// the polynomial's root first; if that is off the target, one Newton step on the exact
    /// residual; if still off, the exact residual's own root.
    #[allow(clippy::too_many_arguments)]
    fn root<P, S>(
        &self,
        lo: f64,
        hi: f64,
        flo: f64,
        poly: &Quartic,
        prof: &P,
        slope: &S,
        best: &mut Option<Best>,
    ) where
        P: Fn(f64) -> Prof,
        S: Fn(f64) -> f64,
    {
        let x = poly.root(lo, hi, flo);
        let p = prof(x);
        if self.offer_within(&p, ROUGH_ULPS, best) == Offer::Done {
            return;
        }
        let x = (x - self.residual(&p) / slope(x)).clamp(lo, hi);
        let p = prof(x);
        if self.offer_within(&p, ROUGH_ULPS, best) == Offer::Done {
            return;
        }
        let res = |y: f64| self.residual(&prof(y));
        let (rlo, rhi) = (res(lo), res(hi));
        if (rlo < 0.0) != (rhi < 0.0) {
            let x = bracketed(res, slope, lo, hi, rlo, rhi);
            self.offer(&prof(x), best);
        }
    }

    /// The families in this frame, the closed-form ones first; with `first`, only up to the
    /// first valid profile.
    pub(super) fn solve(&self, best: &mut Option<Best>, first: bool) {
        let families: [fn(&Step, &mut Option<Best>); 5] = [
            Step::vel,
            Step::acc0acc1,
            Step::none,
            Step::acc0,
            Step::acc1,
        ];
        for f in families {
            f(self, best);
            if first && best.is_some() {
                return;
            }
        }
    }
}

/// Midpoint for bisection: in the floats' bit patterns when both ends have one sign and span
/// more than a factor 4 (so that a bracket over many decades shrinks in at most 64 steps),
/// else the arithmetic mean.
fn mid(lo: f64, hi: f64) -> f64 {
    if lo > 0.0 && hi > 4.0 * lo {
        f64::from_bits(lo.to_bits() / 2 + hi.to_bits() / 2)
    } else if hi < 0.0 && lo < 4.0 * hi {
        -f64::from_bits((-lo).to_bits() / 2 + (-hi).to_bits() / 2)
    } else {
        0.5 * (lo + hi)
    }
}

/// The root of a monotone `f` in `[lo, hi]` where `f(lo) = flo` and `f(hi) = fhi` have
/// opposite signs: Newton with the slope `df`, safeguarded by bisection whenever a step would
/// leave the bracket or is not under half the one before last (Press et al., `rtsafe`), until a
/// step is below 2 ulps or the bracket holds no float between its ends. The best point found.
fn bracketed<F, D>(f: F, df: &D, mut lo: f64, mut hi: f64, flo: f64, fhi: f64) -> f64
where
    F: Fn(f64) -> f64,
    D: Fn(f64) -> f64,
{
    let rising = flo < 0.0;
    let (mut bx, mut bf) = if flo.abs() < fhi.abs() {
        (lo, flo.abs())
    } else {
        (hi, fhi.abs())
    };
    // Start on the secant.
    let mut x = lo - flo * ((hi - lo) / (fhi - flo));
    if !(x > lo && x < hi) {
        x = mid(lo, hi);
    }
    let (mut dx, mut dx_old) = (hi - lo, hi - lo);
    let mut last = false;
    for _ in 0..200 {
        let fx = f(x);
        if fx.abs() < bf {
            (bx, bf) = (x, fx.abs());
        }
        if fx == 0.0 || last || fx.is_nan() {
            break;
        }
        if (fx < 0.0) == rising {
            lo = x;
        } else {
            hi = x;
        }
        let step = fx / df(x);
        if x - step == x {
            // A step below half an ulp: converged (bisecting on would only confirm it).
            break;
        }
        let Some(nx) = safeguarded(x, step, lo, hi, &mut dx, &mut dx_old) else {
            break;
        };
        last = (nx - x).abs() <= 2.0 * f64::EPSILON * x.abs();
        x = nx;
    }
    bx
}

/// The safeguard of [`bracketed`] and [`Quartic::root`]: the next iterate is `x − step` when
/// it stays inside (lo, hi) and the step is at most half the one before the last (`dx`,
/// `dx_old`: the last two steps, updated), else the middle of the bracket; None once the
/// bracket has no middle left.
#[inline(always)]
fn safeguarded(x: f64, step: f64, lo: f64, hi: f64, dx: &mut f64, dx_old: &mut f64) -> Option<f64> {
    let next = x - step;
    if next > lo && next < hi && (2.0 * step).abs() <= dx_old.abs() {
        *dx_old = *dx;
        *dx = step;
        return Some(next);
    }
    let m = mid(lo, hi);
    if !(m > lo && m < hi) {
        return None;
    }
    *dx_old = *dx;
    *dx = x - m;
    Some(m)
}
