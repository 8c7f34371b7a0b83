//! NURBS curves in the path. A curve is one user segment; in the ring it is a run of
//! pieces, each the quintic Hermite interpolant of the curve's point, first and second
//! derivative at both ends of a parameter interval inside one knot span. Pieces meet with the
//! curve's own position, tangent and curvature (G2), so the executor runs through them like
//! through a blend, and the caps, look-ahead and limits of the path hold on them unchanged.
//!
//! **Fit.** Each knot span is cut into pieces greedily: the longest interval (from twice the
//! last piece's) whose quintic stays within half the curve's tolerance of the curve, checked
//! at [`FIT_SAMPLES`] parameters against the curve at the same parameter (an upper bound of
//! the distance, since the quintic's parametrisation matches the curve's to second order at
//! both ends). Where the curve is only C¹ (a knot of multiplicity p − 1) the curvature jumps:
//! the pieces there are joined by the path's own corner blend within the other half of the
//! tolerance. So every commanded point is within the tolerance of the curve.
//!
//! **Events.** The pieces after the first are marked `cont`: one `SegmentStart` and one
//! `SegmentEnd` for the curve, its outputs carried from piece to piece, its `Distance` outputs
//! measured from the curve's start.

use super::{BlendSpeed, Path, PathError, Prog, Seg, Transition, V};
use crate::math;
use crate::motion::nurbs::Nurbs;
use crate::motion::path::geom::Blend;

/// Parameters per piece where the quintic is checked against the curve.
pub const FIT_SAMPLES: usize = 16;
/// Smallest piece, as a share of its knot span's parameter width.
const MIN_STEP: f64 = 1e-9;

/// A NURBS curve for the path (its control points in counts, of the path's axes).
#[derive(Debug, Clone, Copy)]
pub struct CurveSegment<'a> {
    pub id: u32,
    pub curve: &'a Nurbs,
    /// Programmed feed, counts/s.
    pub feed: f64,
    /// How the curve joins the segment before it (a time-shifted transition is refused).
    pub transition: Transition,
    pub blend: BlendSpeed,
    pub last: bool,
    /// Largest distance of the commanded path from the curve, counts (> 0).
    pub tolerance: f64,
}

/// One piece: the quintic on [ua, ub] of knot span `span`, starting at `start` (else at the
/// curve's point), its end point (the curve's) and its largest sampled distance from the
/// curve. None where the curve stops (a zero tangent) or the quintic is not finite.
fn piece<const D: usize>(
    n: usize,
    c: &Nurbs,
    span: usize,
    (ua, ub): (f64, f64),
    start: Option<&V<D>>,
) -> Option<(Blend<D>, V<D>, f64)> {
    let h = ub - ua;
    let ends = |u: f64| {
        let (p, d, dd) = c.eval_in_span(span, u);
        let (mut a, mut b, mut e) = ([0.0; D], [0.0; D], [0.0; D]);
        for k in 0..n {
            a[k] = p[k];
            b[k] = h * d[k];
            e[k] = h * h * dd[k];
        }
        (a, b, e)
    };
    let (mut pa, da, dda) = ends(ua);
    let (pb, db, ddb) = ends(ub);
    let norm = |v: &V<D>| math::sqrt(v[..n].iter().map(|x| x * x).sum::<f64>());
    let chord = math::sqrt((0..n).map(|k| math::powi(pb[k] - pa[k], 2)).sum::<f64>());
    if !(norm(&da) > 1e-6 * chord && norm(&db) > 1e-6 * chord) {
        return None;
    }
    if let Some(s) = start {
        pa = *s;
    }
    let b = Blend::hermite(n, [&pa, &da, &dda], [&pb, &db, &ddb])?;
    let mut err = 0.0f64;
    for j in 1..FIT_SAMPLES {
        let w = j as f64 / FIT_SAMPLES as f64;
        let q = b.pos_u(w);
        let p = c.eval_in_span(span, ua + w * h).0;
        let d = math::sqrt((0..n).map(|k| math::powi(q[k] - p[k], 2)).sum::<f64>());
        if d.is_nan() {
            return None;
        }
        err = err.max(d);
    }
    // the end: the polynomial's sum against the curve's point
    let q = b.pos_u(1.0);
    err = err.max(math::sqrt(
        (0..n).map(|k| math::powi(q[k] - pb[k], 2)).sum::<f64>(),
    ));
    Some((b, pb, err))
}

impl<const D: usize> Path<D> {
    /// Appends a NURBS curve as one segment (see the module doc): the pieces it needs, all or
    /// none. Returns how many ring entries it took. Its start must be within its tolerance
    /// of where the path ends (`CurveStart`); `Curve` when it has a point of zero tangent, or
    /// needs more pieces than the ring holds; `Full` when they do not fit now. Allocates
    /// nothing.
    pub fn push_curve(&mut self, seg: &CurveSegment) -> Result<usize, PathError> {
        if !self.ready {
            return Err(PathError::NotReady);
        }
        let n = self.lim.naxes;
        let c = seg.curve;
        if c.dim() != n {
            return Err(PathError::BadAxis);
        }
        let feed = super::check_feed(seg.feed)?;
        let tol = match seg.transition {
            Transition::Exact => 0.0,
            Transition::MaxDeviation(x) | Transition::CornerDistance(x) => super::check_tol(x)?,
            Transition::TimeShift(_) => return Err(PathError::TimeShift),
        };
        let fit = super::check_tol(seg.tolerance)?;
        if fit == 0.0 {
            return Err(PathError::NonPositive);
        }
        let start = self.last_end;
        let (u0, _) = c.domain();
        let p0 = c.eval_clamped(u0).0;
        let off = math::sqrt((0..n).map(|k| math::powi(p0[k] - start[k], 2)).sum::<f64>());
        if off.is_nan() || off > fit {
            return Err(PathError::CurveStart);
        }
        let half = 0.5 * fit;
        // the pieces: (knot span, ua, ub)
        self.breaks.clear();
        let knots = c.knots();
        for span in c.degree()..c.n_ctrl() {
            let (ka, kb) = (knots[span], knots[span + 1]);
            if kb <= ka {
                continue;
            }
            let (mut ua, mut h) = (ka, kb - ka);
            while ua < kb {
                let mut ub = if kb - (ua + h) <= 1e-6 * (kb - ka) {
                    kb
                } else {
                    ua + h
                };
                loop {
                    let first = self.breaks.is_empty() && ua == ka;
                    let at = first.then_some(&start);
                    match piece(n, c, span, (ua, ub), at) {
                        Some((_, _, err)) if err <= half => break,
                        Some(_) => {}
                        None => return Err(PathError::Curve),
                    }
                    if ub - ua <= MIN_STEP * (kb - ka) {
                        return Err(PathError::Curve);
                    }
                    ub = ua + 0.5 * (ub - ua);
                }
                if self.breaks.len() >= self.capacity {
                    return Err(PathError::Curve);
                }
                // room checked above (capacity ≤ MAX_RING)
                let _ = self.breaks.push((span, ua, ub));
                h = 2.0 * (ub - ua);
                ua = ub;
            }
        }
        let count = self.breaks.len();
        if count == 0 {
            return Err(PathError::ZeroLength);
        }
        if count > self.free() {
            return Err(PathError::Full);
        }
        for i in 0..count {
            let (span, ua, ub) = self.breaks[i];
            let at = (i == 0).then_some(&start);
            let Some((b, p1, _)) = piece(n, c, span, (ua, ub), at) else {
                return Err(PathError::Curve);
            };
            let rec = Seg {
                id: seg.id,
                feed,
                last: seg.last && i + 1 == count,
                cont: i > 0,
                prog: Prog::Curve { b, p1 },
                ..Seg::default()
            };
            let r = if i == 0 {
                self.append(rec, seg.transition, seg.blend, tol)
            } else {
                self.append(rec, Transition::MaxDeviation(half), BlendSpeed::High, half)
            };
            // Only the first piece can be refused (before anything changed): the later ones
            // were checked above.
            r?;
        }
        Ok(count)
    }
}
