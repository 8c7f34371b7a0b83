//! The smoothing of micro-segments (see the module doc of `path`): a junction of two lines
//! turning by at most `SMOOTH_TURN` becomes a blend from the middle of one line to the middle
//! of the next, with the curvature vectors at its ends estimated from the neighbouring
//! vertices (`vertex_k`); the previous blend rebuilt with its end curvature when the next
//! point arrives (`Path::smooth`); the newest one only checked until it is needed
//! (`Path::due_blend`, `Path::settle_cap`); the bounds of a smoothing blend's distance from
//! its two lines, in closed form (`smooth_dev_bound`), by its control points (`hull_dev2`)
//! and sampled (`sampled_dev2`).

use super::*;
use crate::math;

/// A smoothing blend as `Path::smooth` built it: the previous one rebuilt (blend, cap,
/// deviation; its end curvature), the new one, its start curvature and its trims.
/// The blends themselves are built in the caller's buffers (see `Path::smooth`).
pub(super) struct Smooth<const D: usize = MAX_AXES> {
    /// The previous blend rebuilt: its cap, deviation and end curvature.
    pub(super) again: Option<(f64, f64, V<D>)>,
    /// The curvature of the vertex between the two lines (`vertex_k`), which the next push
    /// needs again.
    pub(super) kvertex: V<D>,
    /// The new blend's deviation.
    pub(super) dev: f64,
    pub(super) kstart: V<D>,
    pub(super) da: f64,
    pub(super) db: f64,
}

/// The curvature vector at `b` of the circle through `a`, `b`, `c`:
/// (T_bc − T_ab)·|T_ab + T_bc| / |c − a| (κ = 2 sin θ / |c − a|, toward the centre).
#[inline(always)]
pub(super) fn vertex_k<const D: usize>(n: usize, a: &V<D>, b: &V<D>, c: &V<D>) -> V<D> {
    let (mut lab, mut lbc, mut lac) = (0.0, 0.0, 0.0);
    for k in 0..n {
        lab += (b[k] - a[k]) * (b[k] - a[k]);
        lbc += (c[k] - b[k]) * (c[k] - b[k]);
        lac += (c[k] - a[k]) * (c[k] - a[k]);
    }
    let (lab, lbc, lac) = (math::sqrt(lab), math::sqrt(lbc), math::sqrt(lac));
    let mut d = [0.0; D];
    let mut sum2 = 0.0;
    for k in 0..n {
        let (ta, tc) = ((b[k] - a[k]) / lab, (c[k] - b[k]) / lbc);
        d[k] = tc - ta;
        sum2 += (ta + tc) * (ta + tc);
    }
    let f = math::sqrt(sum2) / lac;
    for x in d[..n].iter_mut() {
        *x *= f;
    }
    // (x·0 is 0 for a finite x, NaN for ∞ and NaN: one test, no branch per axis)
    let mut zero = 0.0;
    for x in d {
        zero += x * 0.0;
    }
    if zero == 0.0 {
        d
    } else {
        [0.0; D]
    }
}

/// The largest squared distance from blend `b` to the nearer of two chords (start relative
/// to the blend's first point, unit direction, length), over the first `N` axes (N ≥ the
/// group's axes, the others being 0 everywhere): [`SMOOTH_SAMPLES`] + 1 points, then each
/// peak of those samples (within half the largest distance) found to [`PEAK_STEPS`] golden
/// sections between its neighbours; None when one is over `limit` (its root only taken when
/// the largest grows: the same figure without a root per sample) or not a number. (The
/// distance to the nearer chord peaks where the two distances cross, a kink the samples
/// straddle: on its own, 33 samples saw 9.70 counts of a blend 10.16 from its lines.)
#[allow(clippy::needless_range_loop)] // one index over several axis arrays
pub(super) fn sampled_dev2<const N: usize, const D: usize>(
    b: &Blend<D>,
    chords: &[(V<D>, V<D>, f64); 2],
    limit: f64,
) -> Option<f64> {
    let at = |u: f64| {
        let q = b.offset_u_n::<N>(u);
        let mut d2 = f64::INFINITY;
        for (a, u, l) in chords {
            let mut t = 0.0;
            for k in 0..N {
                t += (q[k] - a[k]) * u[k];
            }
            let t = t.clamp(0.0, *l);
            let mut e2 = 0.0;
            for k in 0..N {
                let e = q[k] - a[k] - t * u[k];
                e2 += e * e;
            }
            d2 = d2.min(e2);
        }
        d2
    };
    let mut worst2 = 0.0f64;
    let mut seen = [0.0; SMOOTH_SAMPLES + 1];
    let step = 1.0 / SMOOTH_SAMPLES as f64;
    let grow = |d2: f64, worst2: &mut f64| {
        if d2.is_nan() {
            return false;
        }
        if d2 > *worst2 {
            *worst2 = d2;
            if math::sqrt(d2) > limit {
                return false;
            }
        }
        true
    };
    for (i, d) in seen.iter_mut().enumerate() {
        *d = at(i as f64 * step);
        if !grow(*d, &mut worst2) {
            return None;
        }
    }
    for i in 0..=SMOOTH_SAMPLES {
        let (before, after) = (seen[i.saturating_sub(1)], seen[(i + 1).min(SMOOTH_SAMPLES)]);
        if seen[i] < before || seen[i] < after || 4.0 * seen[i] < worst2 {
            continue;
        }
        // golden sections of [u − step, u + step] for the largest distance there
        let (mut lo, mut hi) = ((i as f64 - 1.0) * step, (i as f64 + 1.0) * step);
        lo = lo.max(0.0);
        hi = hi.min(1.0);
        const G: f64 = 0.618_033_988_749_894_8;
        let (mut x1, mut x2) = (hi - G * (hi - lo), lo + G * (hi - lo));
        let (mut f1, mut f2) = (at(x1), at(x2));
        if !(grow(f1, &mut worst2) && grow(f2, &mut worst2)) {
            return None;
        }
        for _ in 0..PEAK_STEPS {
            let f = if f1 < f2 {
                lo = x1;
                (x1, f1) = (x2, f2);
                x2 = lo + G * (hi - lo);
                f2 = at(x2);
                f2
            } else {
                hi = x2;
                (x2, f2) = (x1, f1);
                x1 = hi - G * (hi - lo);
                f1 = at(x1);
                f1
            };
            if !grow(f, &mut worst2) {
                return None;
            }
        }
    }
    Some(worst2)
}

/// An upper bound, in closed form, of the distance from the smoothing blend of two lines (unit
/// directions `ua`, `ub`; trims `da`, `db`; curvature vectors `ka`, `kb` at its ends; a turn
/// θ below 90°) to the two lines. Without the curvatures its control points lie on the lines,
/// at da, 0.6·da and 0.2·da before the corner C and 0.2·db, 0.6·db and db after it
/// (`Blend::controls`): B(u) = C − a(u)·Ta + b(u)·Tb with a = da·(1 − u)³(1 + u) and
/// b = db·u³(2 − u), at most min(a, b)·sin θ from the line whose foot is within it, and
/// min(a, b) ≤ √(ab) ≤ 0.1875·√(da·db) (ab is largest at u = ½). The curvatures move Q2 and
/// Q3 by (2d)²/20·K, which moves the curve by at most 0.3456 times that (the largest of B₂
/// and B₃).
#[inline(always)]
pub(super) fn smooth_dev_bound<const D: usize>(
    n: usize,
    ua: &V<D>,
    ub: &V<D>,
    da: f64,
    db: f64,
    ka: &V<D>,
    kb: &V<D>,
) -> f64 {
    let (mut dt2, mut ka2, mut kb2) = (0.0, 0.0, 0.0);
    for k in 0..n {
        dt2 += (ua[k] - ub[k]) * (ua[k] - ub[k]);
        ka2 += ka[k] * ka[k];
        kb2 += kb[k] * kb[k];
    }
    // |Ta − Tb| = 2 sin(θ/2), sin θ = 2 sin(θ/2) cos(θ/2)
    let sin = math::sqrt(dt2 * (1.0 - 0.25 * dt2).max(0.0));
    0.1875 * math::sqrt(da * db) * sin
        + 0.06912 * (da * da * math::sqrt(ka2) + db * db * math::sqrt(kb2))
}

/// An upper bound of the largest squared distance from a quintic Bézier (control points
/// `q`, relative to its first point, over the first `N` axes) to the nearer of two chords
/// (start relative to the same point, unit direction, length): the curve cut in two at
/// u = 1/2 (de Casteljau), each half within the convex hull of its control points, and the
/// distance to a segment convex, so the first half is no farther from the first chord than
/// its farthest control point, the second from the second. Never below what
/// [`sampled_dev2`] finds on the same curve.
#[allow(clippy::needless_range_loop)] // one index over several axis arrays
#[inline(always)]
pub(super) fn hull_dev2<const N: usize, const D: usize>(
    q: &[V<D>; 6],
    chords: &[(V<D>, V<D>, f64); 2],
) -> f64 {
    let d2 = |p: &V<D>, (a, u, l): &(V<D>, V<D>, f64)| {
        let mut t = 0.0;
        for k in 0..N {
            t += (p[k] - a[k]) * u[k];
        }
        // (without a branch; a NaN gives 0, and its distance is passed over by the max below)
        let t = t.max(0.0).min(*l);
        let mut e2 = 0.0;
        for k in 0..N {
            let e = p[k] - a[k] - t * u[k];
            e2 += e * e;
        }
        e2
    };
    let mut p = *q;
    let mut worst = d2(&p[0], &chords[0]).max(d2(&p[5], &chords[1]));
    for r in 1..6 {
        for i in 0..6 - r {
            for k in 0..N {
                p[i][k] = 0.5 * (p[i][k] + p[i + 1][k]);
            }
        }
        // p[0] is the first half's control point r, p[5 − r] the second half's 5 − r
        worst = worst
            .max(d2(&p[0], &chords[0]))
            .max(d2(&p[5 - r], &chords[1]));
    }
    worst
}

impl<const D: usize> Path<D> {
    /// A smoothing blend from `pa` (trimmed by `da` at its end) to `pb` (trimmed by `db` at
    /// its start), two lines, with curvature vectors `ka`, `kb` at its ends, built in `out`:
    /// its cap and its deviation from the two lines, or None when the deviation is over
    /// `limit` (or it is not finite; `out` is then left unusable). Without `with_cap` the
    /// blend is only checked (by `smooth_dev_bound` where that is enough, without its control
    /// points; a rebuilt blend is checked by it first too), and `out` holds its first point
    /// and its chord as its length (`Blend::chord_only`, a lower bound of the length): the
    /// next push rebuilds it in the common case, else `settle_cap` builds it (`due_blend`)
    /// and computes its cap.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn smooth_piece(
        &self,
        pa: &Prog<D>,
        pb: &Prog<D>,
        da: f64,
        db: f64,
        ka: &V<D>,
        kb: &V<D>,
        limit: f64,
        with_cap: bool,
        out: &mut Blend<D>,
    ) -> Option<(f64, f64)> {
        let n = self.lim.naxes;
        // (bound by reference: the points are not copied)
        let (
            Prog::Line {
                dir: ua,
                p1: corner,
                ..
            },
            Prog::Line { dir: ub, .. },
        ) = (pa, pb)
        else {
            return None;
        };
        // A power-basis coefficient is a sum of control points with weights below 10², each
        // control point within a few trims, chords and curvature offsets of the first: the
        // shape is finite where these are below 10²⁹⁰.
        const LARGE: f64 = 1e290;
        // the closed-form bound first (no control points: the newest blend is then only a
        // chord until it is needed); where it is over, the hull's; the samples where that is
        // over too
        let closed = smooth_dev_bound(n, ua, ub, da, db, ka, kb);
        if !with_cap && closed <= limit {
            let (a, b) = (pa.pos(pa.len() - da), pb.pos(db));
            let mut chord2 = 0.0;
            for k in 0..n {
                chord2 += (b[k] - a[k]) * (b[k] - a[k]);
            }
            let chord = math::sqrt(chord2);
            if chord > 0.0 && da.max(db).max(chord).max(closed) < LARGE {
                out.chord_only(n, a, chord);
                return Some((0.0, closed));
            }
        }
        let mut fa = pa.frame(pa.len() - da);
        fa.k = *ka;
        let mut fb = pb.frame(db);
        fb.k = *kb;
        let q = Blend::controls(n, &fa, &fb, da, db);
        let dev = if closed <= limit {
            closed
        } else {
            // the two chords as (start, unit direction, length), from the blend's first point
            let mut c2 = [0.0; D];
            for k in 0..n {
                c2[k] = corner[k] - fa.p[k];
            }
            let chords = [([0.0; D], *ua, da), (c2, *ub, db)];
            let hull2 = match n {
                1 => hull_dev2::<1, D>(&q, &chords),
                2 => hull_dev2::<2, D>(&q, &chords),
                3 => hull_dev2::<3, D>(&q, &chords),
                _ => hull_dev2::<D, D>(&q, &chords),
            };
            let worst2 = if math::sqrt(hull2) <= limit {
                hull2
            } else {
                if !out.shape(n, fa.p, &q) {
                    return None;
                }
                match n {
                    1 => sampled_dev2::<1, D>(out, &chords, limit)?,
                    2 => sampled_dev2::<2, D>(out, &chords, limit)?,
                    3 => sampled_dev2::<3, D>(out, &chords, limit)?,
                    _ => sampled_dev2::<D, D>(out, &chords, limit)?,
                }
            };
            math::sqrt(worst2)
        };
        if !with_cap {
            let chord = math::sqrt(q[5][..n].iter().map(|x| x * x).sum::<f64>());
            let small = q.iter().all(|p| p[..n].iter().all(|x| x.abs() < LARGE));
            out.chord_only(n, fa.p, chord);
            return (chord > 0.0 && chord.is_finite() && small).then_some((0.0, dev));
        }
        if !out.fill(n, fa.p, &q) {
            return None;
        }
        let cap = self.blend_cap(out, SMOOTH_CAP_SAMPLES);
        (cap > 0.0 && cap.is_finite()).then_some((cap, dev))
    }

    /// Smoothing of a junction of two lines (see [`Path::push`]): the blend from the middle of
    /// the last queued line to the middle of `prog` (the new line), and the previous smoothing
    /// blend rebuilt with the curvature the new point gives it, where the executor is far
    /// enough away; the blends are built in `again` and `new`.
    #[inline(always)]
    pub(super) fn smooth(
        &self,
        prog: &Prog<D>,
        tol: f64,
        need: f64,
        again: &mut Blend<D>,
        new: &mut Blend<D>,
    ) -> Option<Smooth<D>> {
        let n = self.lim.naxes;
        let pi = self.tail - 1;
        let prev = self.seg(pi);
        // (bound by reference: the points are not copied)
        let (
            Prog::Line {
                p0,
                p1,
                dir,
                len: la,
            },
            Prog::Line {
                p1: p2, len: lb, ..
            },
        ) = (&prev.prog, prog)
        else {
            return None;
        };
        let (la, lb) = (*la, *lb);
        let da = (0.5 * la).min(la - prev.body0);
        let db = 0.5 * lb;
        if !(da > 0.0 && db > 0.0)
            || la.max(lb) > SMOOTH_RATIO * la.min(lb)
            || self.dist_to_body_end(pi) - need < da
        {
            return None;
        }
        let limit = DEV_SAFETY * tol;
        let k1 = vertex_k(n, p0, p1, p2);
        if prev.smooth && self.exec < pi && self.dist_to_body_end(pi - 1) >= need {
            let pp = self.seg(pi - 1);
            if let Prog::Line { p0: pm, .. } = &pp.prog {
                // the vertex at p0, as the push of `prev` found it (the same points)
                let k0 = pp.kvertex.unwrap_or_else(|| vertex_k(n, pm, p0, p1));
                let mut kmid = [0.0; D];
                for k in 0..n {
                    kmid[k] = 0.5 * (k0[k] + k1[k]);
                }
                let mut along = 0.0;
                for k in 0..n {
                    along += kmid[k] * dir[k];
                }
                for k in 0..n {
                    kmid[k] -= along * dir[k];
                }
                let rebuilt = self.smooth_piece(
                    &pp.prog,
                    &prev.prog,
                    prev.trim,
                    prev.body0,
                    &prev.kstart,
                    &kmid,
                    limit,
                    true,
                    again,
                );
                if let Some((cap, dev)) = rebuilt {
                    let z = [0.0; D];
                    if let Some((_, new_dev)) =
                        self.smooth_piece(&prev.prog, prog, da, db, &kmid, &z, limit, false, new)
                    {
                        return Some(Smooth {
                            again: Some((cap, dev, kmid)),
                            kvertex: k1,
                            dev: new_dev,
                            kstart: kmid,
                            da,
                            db,
                        });
                    }
                }
            }
        }
        let z = [0.0; D];
        let (_, dev) = self.smooth_piece(&prev.prog, prog, da, db, &z, &z, limit, false, new)?;
        Some(Smooth {
            again: None,
            kvertex: k1,
            dev,
            kstart: z,
            da,
            db,
        })
    }

    /// Builds and measures segment `i`'s smoothing blend and computes its cap, left for later
    /// by `append` (the newest blend, which the next push usually rebuilds): when the next push
    /// does not rebuild it, or when the executor's look-ahead window reaches it (`tick`
    /// checks before each look-ahead). Until then its length is its chord, a lower bound (the
    /// distances to what follows it are short, never long) and its cap 0.
    pub(super) fn settle_cap(&mut self, i: usize) {
        let sl = self.slot(i);
        // its shape and arc-length table, and its length instead of the chord it had (it is
        // the newest segment: where the queue ends moves by the difference, nothing after it)
        let chord = self.segs[sl].blend.len;
        self.segs[sl].blend = self.due_blend(i);
        let grown = self.segs[sl].blend.len - chord;
        self.end_dist += grown;
        self.blocks[sl / BLOCK].len += grown;
        let mut cap = self.blend_cap(&self.segs[sl].blend, SMOOTH_CAP_SAMPLES);
        if !(cap > 0.0 && cap.is_finite()) {
            // a blend of finite positive length has a finite positive cap (every limit
            // leaves room); should rounding break that, it is run at a crawl, not blindly
            let l = &self.lim;
            cap = 1e-3
                * CAP_MARGIN
                * l.vmax[..l.naxes]
                    .iter()
                    .fold(f64::INFINITY, |m, &x| m.min(x));
        }
        self.segs[sl].jgeo = cap;
        let x0 = self.segs[sl].x0;
        let b = &mut self.blocks[sl / BLOCK];
        b.geo = b.geo.min(cap);
        b.kg = b.kg.min(cap * cap + 2.0 * self.at * x0);
        self.cap_due = None;
        self.window_changed(i);
    }

    /// Segment `i`'s smoothing blend as `smooth_piece` checked it without building it (the
    /// newest one, see `settle_cap`): from the line before, trimmed by its `trim`, to its
    /// line, trimmed by its `body0`, with the curvature vectors `kstart` and `kend` at its
    /// ends (`smooth_piece` checked that its shape is finite).
    pub(super) fn due_blend(&self, i: usize) -> Blend<D> {
        let (prev, sg) = (self.seg(i - 1), self.seg(i));
        let n = self.lim.naxes;
        let mut fa = prev.prog.frame(prev.prog.len() - sg.trim);
        fa.k = sg.kstart;
        let mut fb = sg.prog.frame(sg.body0);
        fb.k = sg.kend;
        let mut b = sg.blend;
        let q = Blend::controls(n, &fa, &fb, sg.trim, sg.body0);
        b.shape(n, fa.p, &q);
        b.measure();
        b
    }
}
