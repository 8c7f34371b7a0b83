//! Least-squares cubic B-splines through a run of points: the fit, its check against the
//! polyline the points make, and the cut of a fitted spline at one of its knots.
//!
//! A spline here is clamped and cubic with `k` uniform spans on [0, 1] (knots 0 ×4, 1/k, …,
//! (k−1)/k, 1 ×4) and `k + 3` control points of `dim` coordinates, stored flat.

// Index loops over the band matrix and the control points read as the formulas do.
#![allow(clippy::needless_range_loop)]

/// Degree of the fitted splines.
pub(crate) const DEGREE: usize = 3;

/// A clamped cubic B-spline: knots and control points (flat, `dim` per point).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Spline {
    pub dim: usize,
    pub knots: Vec<f64>,
    pub ctrl: Vec<f64>,
}

/// How the fitted spline starts: at the first point only, or also with a given unit tangent
/// and curvature vector (the end of the spline before it: the join is curvature-continuous).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Start {
    Point,
    Continue {
        tangent: Vec<f64>,
        curvature: Vec<f64>,
    },
}

/// Clamped uniform knots of `k` cubic spans on [0, 1].
pub(crate) fn uniform_knots(k: usize) -> Vec<f64> {
    let mut u = vec![0.0; DEGREE + 1];
    u.extend((1..k).map(|i| i as f64 / k as f64));
    u.extend([1.0; DEGREE + 1]);
    u
}

impl Spline {
    pub fn n_ctrl(&self) -> usize {
        self.ctrl.len() / self.dim
    }

    fn point(&self, i: usize) -> &[f64] {
        &self.ctrl[i * self.dim..(i + 1) * self.dim]
    }

    /// The span holding `u` (index of its first knot, DEGREE..n_ctrl−1).
    fn span(&self, u: f64) -> usize {
        let n = self.n_ctrl();
        if u >= self.knots[n] {
            return n - 1;
        }
        let (mut lo, mut hi) = (DEGREE, n);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if u < self.knots[mid] {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    }

    /// Position and first two derivatives at `u` (clamped to [0, 1]).
    pub fn eval(&self, u: f64) -> ([f64; 8], [f64; 8], [f64; 8]) {
        let u = u.clamp(self.knots[0], self.knots[self.knots.len() - 1]);
        let s = self.span(u);
        let d = ders(&self.knots, s, u);
        let mut out = [[0.0; 8]; 3];
        for (r, row) in d.iter().enumerate() {
            for (j, &b) in row.iter().enumerate() {
                let p = self.point(s - DEGREE + j);
                for (o, &x) in out[r].iter_mut().zip(p) {
                    *o += b * x;
                }
            }
        }
        (out[0], out[1], out[2])
    }

    /// The unit tangent and the curvature vector at `u`.
    pub fn frame(&self, u: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let (_, d1, d2) = self.eval(u);
        let n = self.dim;
        let s2: f64 = d1[..n].iter().map(|x| x * x).sum();
        if !(s2 > 0.0 && s2.is_finite()) {
            return None;
        }
        let s = s2.sqrt();
        let t: Vec<f64> = d1[..n].iter().map(|x| x / s).collect();
        let along: f64 = d2[..n].iter().zip(&t).map(|(a, b)| a * b).sum();
        let k = d2[..n]
            .iter()
            .zip(&t)
            .map(|(a, b)| (a - along * b) / s2)
            .collect();
        Some((t, k))
    }

    /// The part on [0, knots[DEGREE + m]] (m spans), reparametrised to [0, 1]: the knot
    /// inserted until the curve splits there (Boehm).
    pub fn left_of_knot(&self, m: usize) -> Spline {
        let n = self.dim;
        let mut knots = self.knots.clone();
        let mut ctrl = self.ctrl.clone();
        let ub = knots[DEGREE + m];
        // multiplicity of ub now
        let mut mult = knots.iter().filter(|&&x| x == ub).count();
        while mult < DEGREE {
            // insert ub once: span r with knots[r] <= ub < knots[r + 1] (ub is a knot: the
            // last of its copies)
            let r = knots.iter().rposition(|&x| x <= ub).unwrap_or(DEGREE);
            let np = ctrl.len() / n;
            let mut out = Vec::with_capacity(ctrl.len() + n);
            for i in 0..=np {
                if i + DEGREE <= r {
                    out.extend_from_slice(&ctrl[i * n..(i + 1) * n]);
                } else if i > r {
                    out.extend_from_slice(&ctrl[(i - 1) * n..i * n]);
                } else {
                    let den = knots[i + DEGREE] - knots[i];
                    let a = if den > 0.0 {
                        (ub - knots[i]) / den
                    } else {
                        0.0
                    };
                    for c in 0..n {
                        out.push(a * ctrl[i * n + c] + (1.0 - a) * ctrl[(i - 1) * n + c]);
                    }
                }
            }
            knots.insert(r + 1, ub);
            ctrl = out;
            mult += 1;
        }
        // the left curve: knots up to the first copy of ub, plus one more ub
        let first = knots.iter().position(|&x| x == ub).unwrap_or(knots.len());
        let mut lk: Vec<f64> = knots[..first + DEGREE].to_vec();
        lk.push(ub);
        let np = lk.len() - DEGREE - 1;
        let lc = ctrl[..np * n].to_vec();
        for x in lk.iter_mut() {
            *x /= ub;
        }
        Spline {
            dim: n,
            knots: lk,
            ctrl: lc,
        }
    }
}

/// The non-zero basis functions of span `s` at `u` and their first two derivatives (NURBS
/// Book A2.3 for degree 3).
fn ders(knots: &[f64], s: usize, u: f64) -> [[f64; DEGREE + 1]; 3] {
    const P: usize = DEGREE;
    let mut ndu = [[0.0; P + 1]; P + 1];
    let mut left = [0.0; P + 1];
    let mut right = [0.0; P + 1];
    ndu[0][0] = 1.0;
    for j in 1..=P {
        left[j] = u - knots[s + 1 - j];
        right[j] = knots[s + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = if ndu[j][r] != 0.0 {
                ndu[r][j - 1] / ndu[j][r]
            } else {
                0.0
            };
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut out = [[0.0; P + 1]; 3];
    for j in 0..=P {
        out[0][j] = ndu[j][P];
    }
    let mut a = [[0.0; P + 1]; 2];
    for r in 0..=P {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=2usize {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = P - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = if ndu[pk + 1][rk] != 0.0 {
                    a[s1][0] / ndu[pk + 1][rk]
                } else {
                    0.0
                };
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                P - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = if ndu[pk + 1][idx] != 0.0 {
                    (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx]
                } else {
                    0.0
                };
                d += a[s2][j] * ndu[idx][pk];
            }
            if r as isize <= pk as isize {
                a[s2][k] = if ndu[pk + 1][r] != 0.0 {
                    -a[s1][k - 1] / ndu[pk + 1][r]
                } else {
                    0.0
                };
                d += a[s2][k] * ndu[r][pk];
            }
            out[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut r = P as f64;
    for row in out.iter_mut().skip(1) {
        for x in row.iter_mut() {
            *x *= r;
        }
        r *= (P - 1) as f64;
    }
    out
}

/// A symmetric positive-definite band matrix (half-bandwidth `w`), factored in place by
/// Cholesky.
struct Band {
    n: usize,
    w: usize,
    /// `a[i][d] = A[i][i + d]`, `d` in `0..=w`
    a: Vec<f64>,
}

impl Band {
    fn new(n: usize, w: usize) -> Self {
        Self {
            n,
            w,
            a: vec![0.0; n * (w + 1)],
        }
    }
    fn add(&mut self, i: usize, j: usize, x: f64) {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        debug_assert!(j - i <= self.w);
        self.a[i * (self.w + 1) + (j - i)] += x;
    }
    /// Factor (L Lᵀ, L stored transposed in place); false when not positive definite.
    fn factor(&mut self) -> bool {
        let (n, w) = (self.n, self.w);
        let at = |i: usize, d: usize| i * (w + 1) + d;
        for i in 0..n {
            // diagonal
            let mut s = self.a[at(i, 0)];
            for k in i.saturating_sub(w)..i {
                let l = self.a[at(k, i - k)];
                s -= l * l;
            }
            if !(s > 0.0 && s.is_finite()) {
                return false;
            }
            let d = s.sqrt();
            self.a[at(i, 0)] = d;
            for j in i + 1..(i + w + 1).min(n) {
                let mut s = self.a[at(i, j - i)];
                for k in j.saturating_sub(w)..i {
                    s -= self.a[at(k, i - k)] * self.a[at(k, j - k)];
                }
                self.a[at(i, j - i)] = s / d;
            }
        }
        true
    }
    /// Solve with the factor, `b` in place.
    fn solve(&self, b: &mut [f64]) {
        let (n, w) = (self.n, self.w);
        let at = |i: usize, d: usize| i * (w + 1) + d;
        for i in 0..n {
            let mut s = b[i];
            for k in i.saturating_sub(w)..i {
                s -= self.a[at(k, i - k)] * b[k];
            }
            b[i] = s / self.a[at(i, 0)];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for j in i + 1..(i + w + 1).min(n) {
                s -= self.a[at(i, j - i)] * b[j];
            }
            b[i] = s / self.a[at(i, 0)];
        }
    }
}

/// What a fit is asked for (see [`fit`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FitSpec<'a> {
    /// Uniform spans.
    pub k: usize,
    /// How it starts; with a tangent and curvature, at the speed |C'(0)| = `speed`.
    pub start: &'a Start,
    pub speed: f64,
    /// It ends at the last point.
    pub pin_end: bool,
    /// Weight of the squared second differences of the control points.
    pub smooth: f64,
}

/// Least-squares cubic spline of `spec.k` uniform spans through `pts` (flat, `dim` per point)
/// at parameters `t` (increasing, `t[0] = 0`): it starts at the first point (and with the
/// start's tangent and curvature), ends at the last point when asked, and minimises
/// Σ|C(tᵢ) − Qᵢ|² plus `smooth` times the sum of the squared second differences of its
/// control points. None when the system is singular.
pub(crate) fn fit(pts: &[f64], dim: usize, t: &[f64], spec: &FitSpec) -> Option<Spline> {
    let FitSpec {
        k,
        start,
        speed,
        pin_end,
        smooth,
    } = *spec;
    let np = pts.len() / dim;
    let knots = uniform_knots(k);
    let nc = k + DEGREE;
    let mut ctrl = vec![0.0; nc * dim];
    let q = |i: usize| &pts[i * dim..(i + 1) * dim];
    // fixed control points
    let mut fixed = vec![false; nc];
    ctrl[..dim].copy_from_slice(q(0));
    fixed[0] = true;
    if let Start::Continue { tangent, curvature } = start {
        if nc < 4 {
            return None;
        }
        let (u4, u5) = (knots[4], knots[5]);
        for c in 0..dim {
            let p0 = ctrl[c];
            let d1 = speed * tangent[c];
            let d2 = speed * speed * curvature[c];
            let p1 = p0 + d1 * u4 / 3.0;
            let p2 = p1 + u5 * (d2 * u4 / 6.0 + (p1 - p0) / u4);
            ctrl[dim + c] = p1;
            ctrl[2 * dim + c] = p2;
        }
        fixed[1] = true;
        fixed[2] = true;
    }
    if pin_end {
        if fixed[nc - 1] {
            return None;
        }
        ctrl[(nc - 1) * dim..].copy_from_slice(q(np - 1));
        fixed[nc - 1] = true;
    }
    // unknowns: index of each free control point
    let mut idx = vec![usize::MAX; nc];
    let mut nu = 0;
    for j in 0..nc {
        if !fixed[j] {
            idx[j] = nu;
            nu += 1;
        }
    }
    let spline = |ctrl: Vec<f64>| Spline {
        dim,
        knots: knots.clone(),
        ctrl,
    };
    if nu == 0 {
        return Some(spline(ctrl));
    }
    // half-bandwidth: 3 from the points, 2 from the second differences
    let mut m = Band::new(nu, DEGREE);
    let mut rhs = vec![0.0; nu * dim];
    let probe = spline(ctrl.clone());
    for i in 0..np {
        let u = t[i];
        let s = probe.span(u);
        let b = ders(&knots, s, u)[0];
        let mut r = [0.0; 8];
        r[..dim].copy_from_slice(q(i));
        for (jj, &bj) in b.iter().enumerate() {
            let j = s - DEGREE + jj;
            if fixed[j] {
                for c in 0..dim {
                    r[c] -= bj * ctrl[j * dim + c];
                }
            }
        }
        for (aa, &ba) in b.iter().enumerate() {
            let a = s - DEGREE + aa;
            if fixed[a] || ba == 0.0 {
                continue;
            }
            for (bb, &bb_) in b.iter().enumerate() {
                let j = s - DEGREE + bb;
                if !fixed[j] && idx[j] >= idx[a] {
                    m.add(idx[a], idx[j], ba * bb_);
                }
            }
            for c in 0..dim {
                rhs[c * nu + idx[a]] += ba * r[c];
            }
        }
    }
    if smooth > 0.0 {
        for j in 1..nc - 1 {
            let w = [1.0, -2.0, 1.0];
            let js = [j - 1, j, j + 1];
            for (x, &a) in js.iter().enumerate() {
                if fixed[a] {
                    continue;
                }
                for (y, &b) in js.iter().enumerate() {
                    if fixed[b] {
                        for c in 0..dim {
                            rhs[c * nu + idx[a]] -= smooth * w[x] * w[y] * ctrl[b * dim + c];
                        }
                    } else if idx[b] >= idx[a] {
                        m.add(idx[a], idx[b], smooth * w[x] * w[y]);
                    }
                }
            }
        }
    }
    if !m.factor() {
        return None;
    }
    for c in 0..dim {
        m.solve(&mut rhs[c * nu..(c + 1) * nu]);
    }
    for j in 0..nc {
        if !fixed[j] {
            for c in 0..dim {
                ctrl[j * dim + c] = rhs[c * nu + idx[j]];
            }
        }
    }
    ctrl.iter().all(|x| x.is_finite()).then(|| spline(ctrl))
}

/// Moves each parameter to the foot of its point on the spline (one Newton step on
/// (C(t) − Q)·C'(t) = 0), keeping them increasing; the ends stay.
pub(crate) fn correct(s: &Spline, pts: &[f64], t: &mut [f64], pin_end: bool) {
    let dim = s.dim;
    let np = t.len();
    let last = if pin_end { np - 1 } else { np };
    for i in 1..last {
        let (p, d1, d2) = s.eval(t[i]);
        let q = &pts[i * dim..(i + 1) * dim];
        let (mut f, mut df) = (0.0, 0.0);
        for c in 0..dim {
            let e = p[c] - q[c];
            f += e * d1[c];
            df += d1[c] * d1[c] + e * d2[c];
        }
        if df > 0.0 {
            let lo = t[i - 1];
            let hi = if i + 1 < np { t[i + 1] } else { 1.0 };
            let nt = t[i] - f / df;
            if nt.is_finite() {
                t[i] = nt.clamp(lo, hi);
            }
        }
    }
}

/// Distance from `p` to the segment [a, b].
pub(crate) fn dist_to_segment(p: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let (mut ab2, mut ap_ab) = (0.0, 0.0);
    for c in 0..p.len() {
        let ab = b[c] - a[c];
        ab2 += ab * ab;
        ap_ab += (p[c] - a[c]) * ab;
    }
    let h = if ab2 > 0.0 {
        (ap_ab / ab2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut d2 = 0.0;
    for c in 0..p.len() {
        let x = a[c] + h * (b[c] - a[c]) - p[c];
        d2 += x * x;
    }
    d2.sqrt()
}

/// The largest distance between the spline and the polyline of `pts` near each point: each
/// point from the spline at its parameter, and the spline at quarters between two points'
/// parameters from the chord between them (at thirds, a bulge in the middle of a chord was
/// seen 11 % short: a parabola's). With the index of the point (or chord) where it
/// is largest.
pub(crate) fn deviation(s: &Spline, pts: &[f64], t: &[f64]) -> (f64, usize) {
    let dim = s.dim;
    let q = |i: usize| &pts[i * dim..(i + 1) * dim];
    let (mut worst, mut at) = (0.0f64, 0);
    for i in 0..t.len() {
        let (p, _, _) = s.eval(t[i]);
        let d = p[..dim]
            .iter()
            .zip(q(i))
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        if d > worst || d.is_nan() {
            worst = d;
            at = i;
        }
        if i + 1 < t.len() {
            for f in [0.25, 0.5, 0.75] {
                let (p, _, _) = s.eval(t[i] + f * (t[i + 1] - t[i]));
                let d = dist_to_segment(&p[..dim], q(i), q(i + 1));
                if d > worst || d.is_nan() {
                    worst = d;
                    at = i + 1;
                }
            }
        }
    }
    (worst, at)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(k: usize, start: &Start, speed: f64, pin_end: bool) -> FitSpec<'_> {
        FitSpec {
            k,
            start,
            speed,
            pin_end,
            smooth: 0.0,
        }
    }

    fn circle_points(n: usize, r: f64, turn: f64) -> (Vec<f64>, Vec<f64>) {
        let mut pts = Vec::new();
        let mut t = Vec::new();
        for i in 0..=n {
            let a = turn * i as f64 / n as f64;
            pts.extend([r * a.cos(), r * a.sin()]);
            t.push(i as f64 / n as f64);
        }
        (pts, t)
    }

    #[test]
    fn a_fitted_arc_is_within_the_cubic_error_of_the_circle() {
        let (pts, mut t) = circle_points(400, 1000.0, 1.0);
        let mut s = fit(&pts, 2, &t, &spec(4, &Start::Point, 0.0, true)).unwrap();
        for _ in 0..3 {
            correct(&s, &pts, &mut t, true);
            s = fit(&pts, 2, &t, &spec(4, &Start::Point, 0.0, true)).unwrap();
        }
        let (dev, _) = deviation(&s, &pts, &t);
        // four cubic spans on a radian of radius 1000: the error of a cubic on a quarter of
        // a radian is about r·θ⁶/2^11 ≈ 1e-4
        assert!(dev < 1e-2, "{dev}");
        // the ends are the points
        let (p0, _, _) = s.eval(0.0);
        let (p1, _, _) = s.eval(1.0);
        assert!((p0[0] - 1000.0).abs() < 1e-9 && p0[1].abs() < 1e-9);
        assert!((p1[0] - 1000.0 * 1f64.cos()).abs() < 1e-9);
        // its curvature is the circle's
        let (_, k) = s.frame(0.5).unwrap();
        let kk = (k[0] * k[0] + k[1] * k[1]).sqrt();
        assert!((kk - 1e-3).abs() < 1e-5, "{kk}");
    }

    #[test]
    fn a_continued_fit_starts_with_the_given_tangent_and_curvature() {
        let (pts, t) = circle_points(200, 1000.0, 0.5);
        let tangent = vec![0.0, 1.0];
        let curvature = vec![-1e-3, 0.0];
        let start = Start::Continue {
            tangent: tangent.clone(),
            curvature: curvature.clone(),
        };
        let s = fit(&pts, 2, &t, &spec(4, &start, 500.0, false)).unwrap();
        let (tt, kk) = s.frame(0.0).unwrap();
        for c in 0..2 {
            assert!((tt[c] - tangent[c]).abs() < 1e-12);
            assert!((kk[c] - curvature[c]).abs() < 1e-12, "{kk:?}");
        }
        let (dev, _) = deviation(&s, &pts, &t);
        assert!(dev < 0.05, "{dev}");
    }

    #[test]
    fn the_left_part_of_a_knot_is_the_same_curve() {
        let (pts, t) = circle_points(300, 1000.0, 2.0);
        let s = fit(&pts, 2, &t, &spec(8, &Start::Point, 0.0, true)).unwrap();
        for m in 1..8 {
            let l = s.left_of_knot(m);
            let ub = m as f64 / 8.0;
            assert_eq!(l.n_ctrl(), m + 3);
            for i in 0..=20 {
                let u = ub * i as f64 / 20.0;
                let (a, da, dda) = s.eval(u);
                let (b, db, ddb) = l.eval(u / ub);
                for c in 0..2 {
                    assert!((a[c] - b[c]).abs() < 1e-9, "{m} {u}");
                    assert!((da[c] - db[c] / ub).abs() < 1e-6 * (1.0 + da[c].abs()));
                    assert!((dda[c] - ddb[c] / (ub * ub)).abs() < 1e-6 * (1.0 + dda[c].abs()));
                }
            }
        }
    }

    #[test]
    fn band_cholesky_solves() {
        // a tridiagonal SPD system
        let n = 6;
        let mut m = Band::new(n, 3);
        for i in 0..n {
            m.add(i, i, 4.0);
            if i + 1 < n {
                m.add(i, i + 1, 1.0);
            }
        }
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| {
                4.0 * x[i]
                    + if i > 0 { x[i - 1] } else { 0.0 }
                    + if i + 1 < n { x[i + 1] } else { 0.0 }
            })
            .collect();
        assert!(m.factor());
        m.solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12);
        }
    }
}
