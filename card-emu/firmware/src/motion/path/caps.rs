//! The caps of the path's pieces: the most speed each axis's velocity, acceleration and jerk
//! limits leave at a point of a piece (its tangent, curvature and the curvature's
//! derivative), a body's and a blend's over their samples, the tangential limits a piece
//! keeps for the planner (`curved_lim`, `piece_lim`), how much a blend may trim and how far it
//! strays from the corner it replaces, and when an exact stop beats a blend.

use super::*;

/// Largest v ≥ 0 with p·v³ + q·v ≤ r (p, q ≥ 0, r > 0).
#[inline(always)]
pub(super) fn cubic_cap(p: f64, q: f64, r: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let mut v = f64::INFINITY;
    if q > 0.0 {
        v = r / q;
    }
    if p > 0.0 {
        v = v.min(math::cbrt(r / p));
    } else {
        return v;
    }
    if q == 0.0 {
        return v;
    }
    // Newton from above on an increasing convex function: monotone
    for _ in 0..60 {
        let f = p * v * v * v + q * v - r;
        let d = 3.0 * p * v * v + q;
        let nv = v - f / d;
        if nv.is_nan() || nv >= v || nv <= 0.0 {
            break;
        }
        let done = v - nv <= 1e-14 * v;
        v = nv;
        if done {
            break;
        }
    }
    v
}

impl<const D: usize> Path<D> {
    /// `min(cap, the cap of axis k)` at a point of tangent `t`, curvature `kk` and its
    /// derivative `dk` on that axis.
    #[inline(always)]
    pub(super) fn axis_cap(&self, k: usize, t: f64, kk: f64, dk: f64, cap: f64) -> f64 {
        self.axis_cap_with(k, t, kk, dk, cap, (self.at, self.jt, CAP_MARGIN))
    }

    /// [`axis_cap`](Self::axis_cap) with the tangential limits `(at, jt)` reserved, and the
    /// velocity limits times `vm`.
    #[inline(always)]
    pub(super) fn axis_cap_with(
        &self,
        k: usize,
        t: f64,
        kk: f64,
        dk: f64,
        mut cap: f64,
        (at, jt, vm): (f64, f64, f64),
    ) -> f64 {
        let l = &self.lim;
        let (t, kk, dk) = (t.abs(), kk.abs(), dk.abs());
        if t * cap > vm * l.vmax[k] {
            cap = vm * l.vmax[k] / t;
        }
        if kk > 0.0 {
            let room = (CAP_MARGIN * l.amax[k] - at * t).max(0.0);
            if kk * cap * cap > room {
                cap = math::sqrt(room / kk);
            }
        }
        let room = CAP_MARGIN * l.jmax[k] - jt * t;
        let (p, q) = (dk, 3.0 * at * kk);
        if !(cap.is_finite() && p * cap * cap * cap + q * cap <= room) {
            cap = cap.min(cubic_cap(p, q, room));
        }
        cap
    }

    /// `min(cap, the cap of blend b at parameter u)`.
    #[cfg(test)]
    #[inline(always)]
    pub(super) fn blend_cap_at(&self, b: &Blend<D>, u: f64, cap: f64) -> f64 {
        let mut cap = cap;
        b.each_term(u, |k, t, kk, dk| cap = self.axis_cap(k, t, kk, dk, cap));
        cap
    }

    /// An exact stop in place of a blend of this length and cap: the blend would take more
    /// than ten times what the stop loses (slowing from the cap to rest and back, at the
    /// tangential limits). A near-reversal's blend folds into a near-cusp: 34 counts at 11
    /// counts/s, 3 s, where the stop costs 2 ms. (At a right angle the blend takes about what
    /// the stop loses, and stays.)
    pub(super) fn stop_is_faster(&self, len: f64, cap: f64) -> bool {
        let (a, j) = (self.at, self.jt);
        let ramp = if cap * j <= a * a {
            2.0 * math::sqrt(cap / j)
        } else {
            cap / a + a / j
        };
        len > 20.0 * ramp * cap
    }

    /// Cap of a body on [s0, s1].
    #[inline(always)]
    pub(super) fn body_cap(&self, p: &Prog<D>, s0: f64, s1: f64) -> f64 {
        match p {
            // its direction, no curvature: each axis's velocity limit, exactly (a line needs
            // no sampling margin, and its tangential limits are its own: `piece_lim`)
            Prog::Line { dir, .. } => {
                let mut cap = f64::INFINITY;
                #[allow(clippy::needless_range_loop)] // (an index loop: fewer instructions)
                for k in 0..self.lim.naxes {
                    let t = dir[k].abs();
                    if t * cap > self.lim.vmax[k] {
                        cap = self.lim.vmax[k] / t;
                    }
                }
                cap
            }
            Prog::Helix(_) | Prog::Curve { .. } => self.curved_cap(p, s0, s1, (self.at, self.jt)),
            Prog::Dwell { .. } => 0.0,
        }
    }

    /// Each axis's tangent, curvature and its derivative (k, t, kk, dk) at the points of a
    /// curved body on [s0, s1] its cap is computed at.
    #[inline(always)]
    pub(super) fn body_terms(
        &self,
        p: &Prog<D>,
        s0: f64,
        s1: f64,
        mut f: impl FnMut(usize, f64, f64, f64),
    ) {
        match p {
            Prog::Helix(h) => {
                let ang = h.sweep().abs() * (s1 - s0) / p.len();
                let m = (math::ceil(ang / 1f64.to_radians()) as usize).clamp(16, 720);
                for i in 0..=m {
                    let fr = p.frame(s0 + (s1 - s0) * i as f64 / m as f64);
                    for k in 0..self.lim.naxes {
                        f(k, fr.t[k], fr.k[k], fr.dk[k]);
                    }
                }
            }
            Prog::Curve { b, .. } => {
                let (u0, u1) = (b.u_at(s0), b.u_at(s1));
                for i in 0..=CURVE_CAP_SAMPLES {
                    b.each_term(u0 + (u1 - u0) * i as f64 / CURVE_CAP_SAMPLES as f64, &mut f);
                }
            }
            _ => {}
        }
    }

    /// The cap of a curved body on [s0, s1] with the tangential limits `lim` reserved. An
    /// arc's or helix's tangent turns by at most half a degree between two of its samples, so
    /// that its velocity terms are within 4e-5 of their largest: its velocity limits take
    /// [`ARC_VEL_MARGIN`]; the others' all take [`CAP_MARGIN`].
    #[inline(always)]
    pub(super) fn curved_cap(&self, p: &Prog<D>, s0: f64, s1: f64, (at, jt): (f64, f64)) -> f64 {
        let vm = match p {
            Prog::Helix(_) => ARC_VEL_MARGIN,
            _ => CAP_MARGIN,
        };
        let mut cap = f64::INFINITY;
        self.body_terms(p, s0, s1, |k, t, kk, dk| {
            cap = self.axis_cap_with(k, t, kk, dk, cap, (at, jt, vm))
        });
        cap
    }

    /// The tangential limits and the cap of a curved body (an arc, a helix, a curve's piece)
    /// on [s0, s1] fed at `feed`: the shares of the smallest axis limits (`ACCEL_SHARE`,
    /// `JERK_SHARE`) reserve room for the curvature at any speed up to the cap they give;
    /// where the feed is below that cap, all that the curvature leaves at the feed goes to
    /// the tangential limits instead (an arc at its feed accelerates with nearly each axis's
    /// whole limit), and the cap is what those leave. (Out of line: the lines' push, the common
    /// one, is built without it.)
    #[inline(never)]
    pub(super) fn curved_lim(&self, p: &Prog<D>, s0: f64, s1: f64, feed: f64) -> (Lim, f64) {
        let shares = Lim {
            a: self.at,
            j: self.jt,
        };
        let cap0 = self.curved_cap(p, s0, s1, (self.at, self.jt));
        let vs = feed.min(cap0);
        if !(vs > 0.0 && vs.is_finite()) {
            return (shares, cap0);
        }
        let l = &self.lim;
        let mut a = f64::INFINITY;
        self.body_terms(p, s0, s1, |k, t, kk, _| {
            let t = t.abs();
            if t > 0.0 {
                a = a.min((CAP_MARGIN * l.amax[k] - vs * vs * kk.abs()) / t);
            }
        });
        if l.accel > 0.0 {
            a = a.min(l.accel);
        }
        let a = (a * LIM_SLACK).max(self.at);
        let mut j = f64::INFINITY;
        self.body_terms(p, s0, s1, |k, t, kk, dk| {
            let t = t.abs();
            if t > 0.0 {
                let curv = 3.0 * vs * a * kk.abs() + vs * vs * vs * dk.abs();
                j = j.min((CAP_MARGIN * l.jmax[k] - curv) / t);
            }
        });
        if l.jerk > 0.0 {
            j = j.min(l.jerk);
        }
        let lim = Lim {
            a,
            j: (j * LIM_SLACK).max(self.jt),
        };
        if lim == shares {
            return (shares, cap0);
        }
        // (never below the feed the limits were found for: the shares' cap otherwise)
        let cap = self.curved_cap(p, s0, s1, (lim.a, lim.j));
        if cap < vs {
            return (shares, cap0);
        }
        (lim, cap)
    }

    /// The tangential limits of a body (see [`Lim`]): a line's, every axis's acceleration and
    /// jerk limits projected onto its direction (within the group's tangential limits if
    /// set); a curved one's, the shares its cap was computed with.
    #[inline(always)]
    pub(super) fn piece_lim(&self, p: &Prog<D>) -> Lim {
        let curved = Lim {
            a: self.at,
            j: self.jt,
        };
        let Prog::Line { dir, .. } = p else {
            return curved;
        };
        let l = &self.lim;
        let mut m = Lim::NONE;
        #[allow(clippy::needless_range_loop)] // (an index loop: fewer instructions)
        for k in 0..l.naxes {
            let t = dir[k].abs();
            if t * m.a > l.amax[k] {
                m.a = l.amax[k] / t;
            }
            if t * m.j > l.jmax[k] {
                m.j = l.jmax[k] / t;
            }
        }
        if l.accel > 0.0 && l.accel < m.a {
            m.a = l.accel;
        }
        if l.jerk > 0.0 && l.jerk < m.j {
            m.j = l.jerk;
        }
        m
    }

    /// The cap of blend `b`: the smallest of `samples` + 1 evenly spaced parameters'.
    #[inline(always)]
    pub(super) fn blend_cap(&self, b: &Blend<D>, samples: usize) -> f64 {
        // (both widths are in both builds; each build runs its own: `v3.rs`)
        if self.v3 {
            self.blend_cap_l::<LANES_V3>(b, samples)
        } else {
            self.blend_cap_l::<LANES>(b, samples)
        }
    }

    #[inline(always)]
    pub(super) fn blend_cap_l<const L: usize>(&self, b: &Blend<D>, samples: usize) -> f64 {
        match b.axes() {
            1 => self.blend_cap_n::<1, L>(b, samples),
            2 => self.blend_cap_n::<2, L>(b, samples),
            3 => self.blend_cap_n::<3, L>(b, samples),
            _ => self.blend_cap_n::<D, L>(b, samples),
        }
    }

    /// [`blend_cap`](Self::blend_cap) over the first `N` axes, `L` samples at a time
    /// (`Blend::terms_lanes`): each lane's velocity and acceleration caps are computed
    /// together, then the jerk cubic is solved only where the lowest cap so far breaks it, as
    /// [`axis_cap`](Self::axis_cap) does sample by sample. The cap's lowest point lies between
    /// two samples, up to a few per cent below the lowest sample: the middles of the two
    /// intervals next to the lowest sample are sampled too, which finds most of it
    /// (`tests_lookahead` measures what is left).
    #[allow(clippy::needless_range_loop)] // one index over several lane arrays
    #[inline(always)]
    pub(super) fn blend_cap_n<const N: usize, const L: usize>(
        &self,
        b: &Blend<D>,
        samples: usize,
    ) -> f64 {
        let l = &self.lim;
        let (at, jt) = (self.at, self.jt);
        let samples = samples.max(1);
        let h = 1.0 / samples as f64;
        let (mut cap, mut low) = (f64::INFINITY, 0.0);
        // the groups from the ends inwards (the lowest cap is often near an end: a cap found
        // early leaves fewer jerk cubics to solve)
        let groups = samples / L + 1;
        for m in (0..groups).map(|m| {
            if m % 2 == 0 {
                m / 2
            } else {
                groups - 1 - m / 2
            }
        }) {
            let first = m * L;
            // the last lanes past the end repeat it
            let mut u = [0.0; L];
            for j in 0..L {
                u[j] = (first + j).min(samples) as f64 * h;
            }
            let tm = b.terms_lanes::<N, L>(&u);
            let mut c = [f64::INFINITY; L];
            for k in 0..N {
                let (vm, am) = (CAP_MARGIN * l.vmax[k], CAP_MARGIN * l.amax[k]);
                for i in 0..L {
                    let (t, kk) = (tm.t[k][i], tm.k[k][i]);
                    // t = 0: no velocity cap; kk = 0: no acceleration cap (room/0 is ∞, or
                    // NaN when room is 0 too, which `min` passes over)
                    let v = vm / t;
                    let room = (am - at * t).max(0.0);
                    let a = math::sqrt(room / kk);
                    c[i] = c[i].min(v).min(a);
                }
            }
            let mut lowest = cap;
            for x in c {
                lowest = lowest.min(x);
            }
            // the jerk terms at the lowest cap so far, all lanes at once: p·v³ + q·v grows
            // with v, so a term within its room there is within it at any lower cap, and only
            // the others are looked at one by one (as the lowest cap falls)
            let mut over = !lowest.is_finite();
            for k in 0..N {
                let jm = CAP_MARGIN * l.jmax[k];
                for i in 0..L {
                    let (p, q) = (tm.dk[k][i], 3.0 * at * tm.k[k][i]);
                    let room = jm - jt * tm.t[k][i];
                    // (NaN: not within)
                    let within = p * lowest * lowest * lowest + q * lowest <= room;
                    over |= !within;
                }
            }
            if over {
                for k in 0..N {
                    let jm = CAP_MARGIN * l.jmax[k];
                    for i in 0..L {
                        let (p, q) = (tm.dk[k][i], 3.0 * at * tm.k[k][i]);
                        let room = jm - jt * tm.t[k][i];
                        if !(lowest.is_finite()
                            && p * lowest * lowest * lowest + q * lowest <= room)
                        {
                            c[i] = c[i].min(cubic_cap(p, q, room));
                            lowest = lowest.min(c[i]);
                        }
                    }
                }
            }
            for i in 0..L {
                if c[i] < cap {
                    cap = c[i];
                    low = u[i];
                }
            }
        }
        for u in [low - 0.5 * h, low + 0.5 * h] {
            if (0.0..=1.0).contains(&u) {
                b.each_term_n::<N>(u, |k, t, kk, dk| cap = self.axis_cap(k, t, kk, dk, cap));
            }
        }
        cap
    }

    /// Most a blend may trim off `p` at one end (share, angle).
    pub(super) fn room(p: &Prog<D>) -> f64 {
        let l = p.len();
        match p {
            Prog::Helix(h) => (MAX_TRIM_SHARE * l).min(MAX_TRIM_ANGLE * l / h.sweep().abs()),
            _ => MAX_TRIM_SHARE * l,
        }
    }

    /// Upper bound of the distance between `b` and the programmed geometry it replaces (the
    /// last `d` of `pa`, the first `d` of `pb`): the blend sampled against chords of the
    /// geometry, plus their sagitta.
    pub(super) fn deviation(n: usize, b: &Blend<D>, pa: &Prog<D>, pb: &Prog<D>, d: f64) -> f64 {
        const M: usize = 32;
        let la = pa.len();
        let mut pts = [[0.0; D]; 2 * M + 1];
        for (i, q) in pts.iter_mut().enumerate() {
            *q = if i <= M {
                pa.pos(la - d + d * i as f64 / M as f64)
            } else {
                pb.pos(d * (i - M) as f64 / M as f64)
            };
        }
        let mut sag = 0.0f64;
        for p in [pa, pb] {
            if p.is_curved() {
                let k = math::sqrt(p.frame(0.0).k[..n].iter().map(|x| x * x).sum::<f64>());
                let h = d / M as f64;
                sag = sag.max(k * h * h / 8.0 * 1.01);
            }
        }
        let mut worst = 0.0f64;
        for i in 0..=BLEND_SAMPLES {
            let q = b.pos_u(i as f64 / BLEND_SAMPLES as f64);
            let mut best = f64::INFINITY;
            for w in pts.windows(2) {
                best = best.min(dist_to_chord(n, &q, &w[0], &w[1]));
            }
            worst = worst.max(best);
        }
        worst + sag
    }
}
