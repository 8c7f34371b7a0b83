//! Geometry of the continuous path, by arc length: the programmed lines and arcs/helices and
//! the quintic Bézier corner blends (G2: position, unit tangent and curvature vector matched
//! at both trim points).

use super::MAX_AXES;
use crate::math;
use crate::motion::arc::{ArcDirection, CircleError, ExactCircle};
use crate::motion::nurbs_interp::{GL_W, GL_X};

/// A point or vector of the axes' space: `D` coordinates (see `Path`).
pub(super) type V<const D: usize = MAX_AXES> = [f64; D];
#[cfg(test)]
const Z: V = [0.0; MAX_AXES];

/// Point, unit tangent T, curvature vector K = κN and its derivative dK/ds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Frame<const D: usize = MAX_AXES> {
    pub p: V<D>,
    pub t: V<D>,
    pub k: V<D>,
    pub dk: V<D>,
}

impl<const D: usize> Default for Frame<D> {
    fn default() -> Self {
        let z = [0.0; D];
        Self {
            p: z,
            t: z,
            k: z,
            dk: z,
        }
    }
}

/// One programmed motion: a line, an arc/helix, a piece of a NURBS curve (a quintic fitted
/// to it, see `curve.rs`), or a dwell, which does not move.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(clippy::large_enum_variant)] // stored inline in the ring on purpose: nothing allocates
pub(super) enum Prog<const D: usize = MAX_AXES> {
    Line {
        p0: V<D>,
        p1: V<D>,
        dir: V<D>,
        len: f64,
    },
    Helix(Helix<D>),
    /// A quintic piece ending exactly at `p1` (the curve's point, not the polynomial's sum).
    Curve {
        b: Blend<D>,
        p1: V<D>,
    },
    Dwell {
        p: V<D>,
    },
}

/// An arc in a plane (`ExactCircle` in the plane's coordinates), the other axes moving
/// linearly with the arc length: a helix. The plane is spanned by two orthonormal vectors
/// `e1`, `e2` of the axes' space: the unit vectors of two group axes u and v for an arc in
/// their plane, or two vectors on three axes for an arc in a plane given by a normal vector
/// (`e1 × e2` the normal). A radial mismatch of the end (within the tolerance `push` allows) is
/// spread linearly over the sweep, so the end is reached exactly without a jump.
///
/// Layout 1.13: the group's move queue runs its arcs in a plane given by a normal vector on
/// this geometry too ([`Helix::normal_turns`], [`Helix::point`]), the same points as the path's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix<const D: usize = MAX_AXES> {
    p0: V<D>,
    p1: V<D>,
    e1: V<D>,
    e2: V<D>,
    /// `p0` less its components on `e1` and `e2`: where the plane's coordinates are added.
    off: V<D>,
    circle: ExactCircle,
    r1: f64,
    /// The linear motion off the plane (the other axes, and a rise along the normal) / len.
    lin: V<D>,
    len: f64,
    /// plane length / len
    c: f64,
    sgn: f64,
}

/// The coordinates of `p` on `e`.
#[inline(always)]
fn dot<const D: usize>(p: &V<D>, e: &V<D>) -> f64 {
    let mut d = 0.0;
    for k in 0..D {
        d += p[k] * e[k];
    }
    d
}

/// An orthonormal basis (e1, e2, n̂) of the space of the three axes `axes` with n̂ the unit
/// `normal` and e1 × e2 = n̂: e1 is the axis least along the normal (the first of equals) with
/// its component on the normal taken out, so that a normal along an axis gives the other two
/// axes exactly, in their order (the normal +Z of X, Y, Z gives e1 = X, e2 = Y). None when the
/// normal is zero or not finite.
pub fn normal_basis<const D: usize>(
    axes: [usize; 3],
    normal: [f64; 3],
) -> Option<(V<D>, V<D>, V<D>)> {
    let nh = unit_normal(normal)?;
    let mut i = 0;
    for k in 1..3 {
        if nh[k].abs() < nh[i].abs() {
            i = k;
        }
    }
    let mut a = [0.0; 3];
    a[i] = 1.0;
    let d = nh[i];
    for k in 0..3 {
        a[k] -= d * nh[k];
    }
    let am = math::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for x in a.iter_mut() {
        *x /= am;
    }
    let b = [
        nh[1] * a[2] - nh[2] * a[1],
        nh[2] * a[0] - nh[0] * a[2],
        nh[0] * a[1] - nh[1] * a[0],
    ];
    let (mut e1, mut e2, mut en) = ([0.0; D], [0.0; D], [0.0; D]);
    for k in 0..3 {
        e1[axes[k]] = a[k];
        e2[axes[k]] = b[k];
        en[axes[k]] = nh[k];
    }
    Some((e1, e2, en))
}

/// The unit vector along `normal` (scaled by its largest component first, so that no
/// square under- or overflows); None when it is zero or not finite.
pub fn unit_normal(normal: [f64; 3]) -> Option<[f64; 3]> {
    let mx = normal[0].abs().max(normal[1].abs()).max(normal[2].abs());
    if !(mx.is_finite() && mx > 0.0) || normal.iter().any(|x| x.is_nan()) {
        return None;
    }
    let v = [normal[0] / mx, normal[1] / mx, normal[2] / mx];
    let m = math::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    Some([v[0] / m, v[1] / m, v[2] / m])
}

impl<const D: usize> Helix<D> {
    /// The helix from `p0` to `p1` around `centre` in the plane (u, v), of `n` axes.
    pub fn new(
        n: usize,
        p0: V<D>,
        p1: V<D>,
        u: usize,
        v: usize,
        centre: [f64; 2],
        ccw: bool,
    ) -> Result<Self, CircleError> {
        let (mut e1, mut e2) = ([0.0; D], [0.0; D]);
        e1[u] = 1.0;
        e2[v] = 1.0;
        Self::in_plane(n, p0, p1, e1, e2, centre, ccw, [0.0; D], 0)
    }

    /// The arc from `p0` counter-clockwise about the normal `en` (unit; `e1`, `e2` its plane's
    /// basis, `normal_basis`) around `centre` (its coordinates on e1, e2) to `p1`: what `p1`
    /// has off the plane along `en` is a rise, moving linearly with the arc length as the
    /// other axes do.
    pub fn normal(
        n: usize,
        p0: V<D>,
        p1: V<D>,
        basis: (V<D>, V<D>, V<D>),
        centre: [f64; 2],
    ) -> Result<Self, CircleError> {
        Self::normal_turns(n, p0, p1, basis, centre, 0)
    }

    /// [`Helix::normal`] with `turns` full turns added to the sweep (layout 1.13: the move
    /// queue's; the rise and the other axes spread over the whole length).
    pub fn normal_turns(
        n: usize,
        p0: V<D>,
        p1: V<D>,
        (e1, e2, en): (V<D>, V<D>, V<D>),
        centre: [f64; 2],
        turns: u32,
    ) -> Result<Self, CircleError> {
        Self::in_plane(n, p0, p1, e1, e2, centre, true, en, turns)
    }

    /// The length of the path (the arc and the motion off its plane together).
    pub fn length(&self) -> f64 {
        self.len
    }

    /// The start and the end (the programmed points).
    pub fn ends(&self) -> (V<D>, V<D>) {
        (self.p0, self.p1)
    }

    /// The point at arc length `s` (clamped; the ends are the programmed points exactly).
    pub fn point(&self, s: f64) -> V<D> {
        self.frame(s).p
    }

    /// The arc in the plane (e1, e2) with `centre` in its coordinates; what moves off the
    /// plane moves linearly: every axis off it, and along `en` (Z: none) the rise.
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn in_plane(
        n: usize,
        p0: V<D>,
        p1: V<D>,
        e1: V<D>,
        e2: V<D>,
        centre: [f64; 2],
        ccw: bool,
        en: V<D>,
        turns: u32,
    ) -> Result<Self, CircleError> {
        let dir = if ccw {
            ArcDirection::Ccw
        } else {
            ArcDirection::Cw
        };
        let (x0, y0) = (dot(&p0, &e1), dot(&p0, &e2));
        let (x1, y1) = (dot(&p1, &e1), dot(&p1, &e2));
        let mut circle = ExactCircle::from_points((centre[0], centre[1]), (x0, y0), (x1, y1), dir)?;
        if turns > 0 {
            // (the frame takes its angles from the start angle and the sweep, its ends from
            // p0 and p1: the end stays exact)
            let sweep = circle.sweep();
            let more = sweep.signum() * core::f64::consts::TAU * f64::from(turns);
            circle = ExactCircle::new(
                circle.centre(),
                circle.radius(),
                circle.start_angle(),
                sweep + more,
            )?;
        }
        let r0 = circle.radius();
        let r1 = math::hypot(x1 - centre[0], y1 - centre[1]);
        let lp = circle.length();
        // the motion off the plane: the axes off it, and the rise along the normal
        let mut d = [0.0; D];
        let mut off = [0.0; D];
        for k in 0..n {
            off[k] = p0[k] - x0 * e1[k] - y0 * e2[k];
            d[k] = if e1[k] == 0.0 && e2[k] == 0.0 && en[k] == 0.0 {
                p1[k] - p0[k]
            } else {
                0.0
            };
        }
        let rise = dot(&p1, &en) - dot(&p0, &en);
        for k in 0..n {
            d[k] += rise * en[k];
        }
        let mut h2 = 0.0;
        for k in 0..n {
            h2 += d[k] * d[k];
        }
        let len = math::hypot(lp, math::sqrt(h2));
        if !(len.is_finite() && len > 0.0 && r0.is_finite()) {
            return Err(CircleError::InvalidRadius);
        }
        let mut lin = [0.0; D];
        for k in 0..n {
            lin[k] = d[k] / len;
        }
        Ok(Self {
            p0,
            p1,
            e1,
            e2,
            off,
            circle,
            r1,
            lin,
            len,
            c: lp / len,
            sgn: circle.sweep().signum(),
        })
    }

    pub fn sweep(&self) -> f64 {
        self.circle.sweep()
    }

    #[inline(always)]
    fn frame(&self, s: f64) -> Frame<D> {
        let mut f = Frame::default();
        let s = s.clamp(0.0, self.len);
        let sigma = s * self.c;
        let r0 = self.circle.radius();
        let th = self
            .circle
            .angle_at(sigma)
            .unwrap_or(self.circle.start_angle());
        let (sn, cs) = math::sin_cos(th);
        let (e1, e2) = (&self.e1, &self.e2);
        if s <= 0.0 {
            f.p = self.p0;
        } else if s >= self.len {
            f.p = self.p1;
        } else {
            let lp = self.circle.length();
            let r = r0 + (self.r1 - r0) * (sigma / lp);
            let (cx, cy) = self.circle.centre();
            let (x, y) = (cx + r * cs, cy + r * sn);
            for k in 0..D {
                f.p[k] = self.off[k] + self.lin[k] * s + e1[k] * x + e2[k] * y;
            }
        }
        let (c, g) = (self.c, self.sgn);
        let (tx, ty) = (-g * sn * c, g * cs * c);
        let kk = c * c / r0;
        let (kx, ky) = (-kk * cs, -kk * sn);
        let kd = c * c * c / (r0 * r0);
        let (dx, dy) = (kd * g * sn, -kd * g * cs);
        for k in 0..D {
            f.t[k] = e1[k] * tx + e2[k] * ty + self.lin[k];
            f.k[k] = e1[k] * kx + e2[k] * ky;
            f.dk[k] = e1[k] * dx + e2[k] * dy;
        }
        f
    }
}

impl<const D: usize> Default for Prog<D> {
    fn default() -> Self {
        Prog::Dwell { p: [0.0; D] }
    }
}

impl<const D: usize> Prog<D> {
    /// A line from `p0` to `p1` (`len` > 0 checked by the caller).
    #[inline(always)]
    pub fn line(n: usize, p0: V<D>, p1: V<D>) -> (Self, f64) {
        let mut d2 = 0.0;
        for k in 0..n {
            d2 += (p1[k] - p0[k]) * (p1[k] - p0[k]);
        }
        let len = math::sqrt(d2);
        let mut dir = [0.0; D];
        if len > 0.0 {
            for k in 0..n {
                dir[k] = (p1[k] - p0[k]) / len;
            }
        }
        (Prog::Line { p0, p1, dir, len }, len)
    }

    #[inline(always)]
    pub fn len(&self) -> f64 {
        match self {
            Prog::Line { len, .. } => *len,
            Prog::Helix(h) => h.len,
            Prog::Curve { b, .. } => b.len,
            Prog::Dwell { .. } => 0.0,
        }
    }

    #[inline(always)]
    pub fn end(&self) -> V<D> {
        match self {
            Prog::Line { p1, .. } => *p1,
            Prog::Helix(h) => h.p1,
            Prog::Curve { p1, .. } => *p1,
            Prog::Dwell { p } => *p,
        }
    }

    #[inline(always)]
    pub fn is_curved(&self) -> bool {
        matches!(self, Prog::Helix(_) | Prog::Curve { .. })
    }

    /// Point at arc length `s` (clamped; the ends are the programmed points exactly).
    #[inline(always)]
    pub fn pos(&self, s: f64) -> V<D> {
        match self {
            Prog::Line { p0, p1, dir, len } => {
                if s <= 0.0 {
                    *p0
                } else if s >= *len {
                    *p1
                } else {
                    let mut p = *p0;
                    for k in 0..D {
                        p[k] += dir[k] * s;
                    }
                    p
                }
            }
            Prog::Helix(h) => h.frame(s).p,
            Prog::Curve { b, p1 } => {
                if s >= b.len {
                    *p1
                } else {
                    b.pos(s)
                }
            }
            Prog::Dwell { p } => *p,
        }
    }

    /// The unit tangent and the curvature vector at arc length `s` (a line's without building
    /// its frame).
    #[inline(always)]
    pub fn tangent_curvature(&self, s: f64) -> (V<D>, V<D>) {
        match self {
            Prog::Line { dir, .. } => (*dir, [0.0; D]),
            _ => {
                let f = self.frame(s);
                (f.t, f.k)
            }
        }
    }

    #[inline(always)]
    pub fn frame(&self, s: f64) -> Frame<D> {
        match self {
            Prog::Line { dir, .. } => Frame {
                p: self.pos(s),
                t: *dir,
                ..Frame::default()
            },
            Prog::Helix(h) => h.frame(s),
            Prog::Curve { b, .. } => {
                let mut f = b.terms(b.u_at(s));
                f.p = self.pos(s);
                f
            }
            Prog::Dwell { p } => Frame {
                p: *p,
                ..Frame::default()
            },
        }
    }
}

/// Subintervals of the blend's arc-length table (5-point Gauss–Legendre on each).
pub(super) const NSUB: usize = 4;

/// Trim-length factor of the inner control points: B'(0) = 2d·Ta, B'(1) = 2d·Tb for a trim
/// d, so that the control points of a line–line blend are evenly spaced along the legs
/// (Q0..Q2 at −d, −0.6d, −0.2d from the corner on the incoming line, Q3..Q5 mirrored): the
/// parametric speed is then nearly constant and, for small turns, the curvature is a smooth
/// bump 3θu(1−u)/d (peak 0.75·θ/d).
const LAMBDA: f64 = 2.0;

/// A quintic Bézier corner blend, in power form around its first point, with its arc-length
/// table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Blend<const D: usize = MAX_AXES> {
    q0: V<D>,
    c: [V<D>; 6],
    n: usize,
    /// |B'(u)|² in power form (degree 8): the arc-length integrand then costs one polynomial
    /// and one square root per point, whatever the number of axes, which is what the
    /// Gauss–Legendre table and every tick's Newton on u evaluate most.
    sp2: [f64; 9],
    table: [f64; NSUB + 1],
    pub len: f64,
}

impl<const D: usize> Default for Blend<D> {
    fn default() -> Self {
        Self {
            q0: [0.0; D],
            c: [[0.0; D]; 6],
            n: 0,
            sp2: [0.0; 9],
            table: [0.0; NSUB + 1],
            len: 0.0,
        }
    }
}

impl<const D: usize> Blend<D> {
    /// The blend from frame `a` (on the incoming segment, trimmed by `da`) to frame `b` (on
    /// the outgoing one, trimmed by `db`). None when it is not finite.
    pub fn new(n: usize, a: &Frame<D>, b: &Frame<D>, da: f64, db: f64) -> Option<Self> {
        Self::from_bezier(n, a.p, &Self::controls(n, a, b, da, db))
    }

    /// The Bézier control points of [`new`](Self::new)'s blend, less the first (`a.p`).
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    #[inline(always)]
    pub fn controls(n: usize, a: &Frame<D>, b: &Frame<D>, da: f64, db: f64) -> [V<D>; 6] {
        let la = LAMBDA * da;
        let lb = LAMBDA * db;
        let mut q = [[0.0; D]; 6];
        for k in 0..n {
            let e = b.p[k] - a.p[k];
            q[1][k] = la / 5.0 * a.t[k];
            q[2][k] = 2.0 * q[1][k] + la * la / 20.0 * a.k[k];
            q[5][k] = e;
            q[4][k] = e - lb / 5.0 * b.t[k];
            q[3][k] = 2.0 * q[4][k] - e + lb * lb / 20.0 * b.k[k];
        }
        q
    }

    /// The quintic Hermite interpolant on u ∈ [0, 1] of the point, first and second
    /// derivative (with respect to u) at each end: `a` = (p, d, dd) at 0, `b` at 1.
    pub fn hermite(n: usize, a: [&V<D>; 3], b: [&V<D>; 3]) -> Option<Self> {
        let mut q = [[0.0; D]; 6];
        for k in 0..n {
            let e = b[0][k] - a[0][k];
            q[1][k] = a[1][k] / 5.0;
            q[2][k] = 2.0 * a[1][k] / 5.0 + a[2][k] / 20.0;
            q[5][k] = e;
            q[4][k] = e - b[1][k] / 5.0;
            q[3][k] = e - 2.0 * b[1][k] / 5.0 + b[2][k] / 20.0;
        }
        Self::from_bezier(n, *a[0], &q)
    }

    /// The quintic with Bézier control points `q0 + q[i]` (`q[0] = 0`).
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    pub fn from_bezier(n: usize, q0: V<D>, q: &[V<D>; 6]) -> Option<Self> {
        let mut bl = Self::default();
        bl.fill(n, q0, q).then_some(bl)
    }

    /// Makes this the quintic of [`from_bezier`](Self::from_bezier) in place (a blend is
    /// hundreds of bytes: built where it is kept, not moved there); false (and this blend
    /// unusable) when it is not finite.
    #[inline(always)]
    pub fn fill(&mut self, n: usize, q0: V<D>, q: &[V<D>; 6]) -> bool {
        self.shape(n, q0, q) && self.measure()
    }

    /// The first half of [`fill`](Self::fill): the quintic's shape (its points, tangents and
    /// curvatures can be evaluated by the parameter u) without its arc-length table, which
    /// [`measure`](Self::measure) makes; until then `len` is the chord |B(1) − B(0)|, a lower
    /// bound of the length. False when it is not finite.
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    #[inline(always)]
    pub fn shape(&mut self, n: usize, q0: V<D>, q: &[V<D>; 6]) -> bool {
        // Bernstein → power basis: c_j = C(5,j) Σ_i (−1)^(j−i) C(j,i) Q_i; the axes after the
        // blend's are 0 (`each_term_n` may run over them)
        let c = &mut self.c;
        *c = [[0.0; D]; 6];
        for k in 0..n {
            let [q0, q1, q2, q3, q4, q5] = [q[0][k], q[1][k], q[2][k], q[3][k], q[4][k], q[5][k]];
            c[0][k] = q0;
            c[1][k] = 5.0 * (q1 - q0);
            c[2][k] = 10.0 * (q2 - 2.0 * q1 + q0);
            c[3][k] = 10.0 * (q3 - 3.0 * (q2 - q1) - q0);
            c[4][k] = 5.0 * (q4 - 4.0 * (q3 + q1) + 6.0 * q2 + q0);
            c[5][k] = q5 - 5.0 * (q4 - q1) + 10.0 * (q3 - q2) - q0;
        }
        self.q0 = q0;
        self.n = n;
        let mut chord2 = 0.0;
        for k in 0..n {
            chord2 += q[5][k] * q[5][k];
        }
        self.len = math::sqrt(chord2);
        // (x·0 is 0 for a finite x, NaN for ∞ and NaN: one test, no branch per coefficient)
        let mut zero = 0.0;
        for r in c.iter() {
            for x in &r[..n] {
                zero += x * 0.0;
            }
        }
        self.len.is_finite() && zero == 0.0
    }

    /// Only the first point `q0` of a quintic and, as its length, its chord |B(1) − B(0)|: a
    /// blend checked but not built yet (its shape and table left as they were; the caller
    /// checks that its shape would be finite).
    #[inline(always)]
    pub fn chord_only(&mut self, n: usize, q0: V<D>, chord: f64) {
        self.q0 = q0;
        self.n = n;
        self.len = chord;
    }

    /// The second half of [`fill`](Self::fill): the arc-length table and the length of a
    /// [`shape`](Self::shape)d quintic. False (the table then spread evenly over the chord,
    /// so that the blend still runs from its start to its end) when it is not finite.
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    #[inline(always)]
    pub fn measure(&mut self) -> bool {
        let c = &self.c;
        // B'(u) = Σ d_m u^m with d_m = (m + 1)·c_(m+1); |B'|² = Σ_k Σ_(m,l) d_m d_l u^(m+l)
        let sp2 = &mut self.sp2;
        *sp2 = [0.0; 9];
        for k in 0..self.n {
            let d = [
                c[1][k],
                2.0 * c[2][k],
                3.0 * c[3][k],
                4.0 * c[4][k],
                5.0 * c[5][k],
            ];
            for m in 0..5 {
                sp2[2 * m] += d[m] * d[m];
                for l in m + 1..5 {
                    sp2[m + l] += 2.0 * d[m] * d[l];
                }
            }
        }
        let chord = self.len;
        // `gl` on each subinterval: its 5·NSUB speeds first, in one loop the compiler runs
        // two points at a time, then each subinterval's sum in order (the same figures)
        let mut sp = [[0.0; 5]; NSUB];
        for i in 0..NSUB {
            let (a, b) = (i as f64 / NSUB as f64, (i + 1) as f64 / NSUB as f64);
            let (h, m) = (0.5 * (b - a), 0.5 * (a + b));
            for j in 0..5 {
                sp[i][j] = m + h * GL_X[j];
            }
        }
        for x in sp.as_flattened_mut() {
            *x = self.speed(*x);
        }
        self.table[0] = 0.0;
        for i in 0..NSUB {
            let (a, b) = (i as f64 / NSUB as f64, (i + 1) as f64 / NSUB as f64);
            let mut sum = 0.0;
            for j in 0..5 {
                sum += GL_W[j] * sp[i][j];
            }
            self.table[i + 1] = self.table[i] + sum * (0.5 * (b - a));
        }
        self.len = self.table[NSUB];
        let ok = self.len.is_finite() && self.len > 0.0;
        if !ok {
            self.len = chord;
            for i in 0..=NSUB {
                self.table[i] = chord * i as f64 / NSUB as f64;
            }
        }
        ok
    }

    /// |B'(u)|.
    #[inline(always)]
    fn speed(&self, u: f64) -> f64 {
        let q = &self.sp2;
        let s2 = q[0]
            + u * (q[1]
                + u * (q[2]
                    + u * (q[3] + u * (q[4] + u * (q[5] + u * (q[6] + u * (q[7] + u * q[8])))))));
        // rounding may take a square that is 0 just below it
        math::sqrt(s2.max(0.0))
    }

    /// 5-point Gauss–Legendre of |B'| on [a, b].
    #[inline(always)]
    fn gl(&self, a: f64, b: f64) -> f64 {
        let h = 0.5 * (b - a);
        let m = 0.5 * (a + b);
        let mut sum = 0.0;
        for i in 0..5 {
            sum += GL_W[i] * self.speed(m + h * GL_X[i]);
        }
        sum * h
    }

    /// The parameter at arc length `s`: the table's subinterval, then Newton on the
    /// Gauss–Legendre length within it (to ~1e-15 in u).
    #[inline(always)]
    pub fn u_at(&self, s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.len {
            return 1.0;
        }
        let i = self.table[1..NSUB].partition_point(|&x| x <= s);
        let h = 1.0 / NSUB as f64;
        let (u0, u1) = (i as f64 * h, (i + 1) as f64 * h);
        let (s0, s1) = (self.table[i], self.table[i + 1]);
        let mut u = u0 + h * ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
        for _ in 0..12 {
            let f = s0 + self.gl(u0, u) - s;
            let sp = self.speed(u);
            if sp.is_nan() || sp <= 0.0 {
                break;
            }
            let du = f / sp;
            let un = (u - du).clamp(u0, u1);
            let moved = (un - u).abs();
            u = un;
            if moved <= 1e-15 {
                break;
            }
        }
        u
    }

    #[inline(always)]
    pub fn pos_u(&self, u: f64) -> V<D> {
        let mut p = self.q0;
        if u <= 0.0 {
            return p;
        }
        let c = &self.c;
        for k in 0..self.n {
            let o = u * (c[1][k] + u * (c[2][k] + u * (c[3][k] + u * (c[4][k] + u * c[5][k]))));
            p[k] += o;
        }
        p
    }

    /// [`pos_u`](Self::pos_u) less the first point (what the quintic adds to it), over the
    /// first `N` axes (N ≥ the blend's axes; the others are 0).
    #[inline(always)]
    pub fn offset_u_n<const N: usize>(&self, u: f64) -> V<D> {
        let mut p = [0.0; D];
        let c = &self.c;
        for k in 0..N {
            p[k] = u * (c[1][k] + u * (c[2][k] + u * (c[3][k] + u * (c[4][k] + u * c[5][k]))));
        }
        p
    }

    #[inline(always)]
    pub fn pos(&self, s: f64) -> V<D> {
        self.pos_u(self.u_at(s))
    }

    /// Frame at parameter u (T, K = κN and dK/ds from B', B'', B''').
    #[cfg(test)]
    pub fn frame_u(&self, u: f64) -> Frame<D> {
        let mut f = self.terms(u);
        f.p = self.pos_u(u);
        f
    }

    /// Its axes.
    #[inline(always)]
    pub fn axes(&self) -> usize {
        self.n
    }

    /// The frame at u without its point: T, K and dK/ds.
    pub fn terms(&self, u: f64) -> Frame<D> {
        let mut f = Frame::default();
        self.each_term(u, |k, t, kk, dk| {
            f.t[k] = t;
            f.k[k] = kk;
            f.dk[k] = dk;
        });
        f
    }

    /// T, K and dK/ds at u, axis by axis: `f(axis, T, K, dK/ds)` for each of the blend's
    /// axes (none where B'(u) = 0, where the frame is 0). The speed caps need only these, so
    /// they are handed over without building a whole [`Frame`].
    #[inline(always)]
    pub fn each_term(&self, u: f64, f: impl FnMut(usize, f64, f64, f64)) {
        match self.n {
            1 => self.each_term_n::<1>(u, f),
            2 => self.each_term_n::<2>(u, f),
            3 => self.each_term_n::<3>(u, f),
            _ => self.each_term_n::<D>(u, f),
        }
    }

    /// [`each_term`](Self::each_term) over the first `N` axes (N ≥ the blend's axes: the
    /// axes after them are 0 in every coefficient, so they change no sum), with loops the
    /// compiler unrolls for the common 1, 2 and 3 axes.
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    #[inline(always)]
    pub fn each_term_n<const N: usize>(&self, u: f64, mut f: impl FnMut(usize, f64, f64, f64)) {
        let c = &self.c;
        let (mut r1, mut r2, mut r3) = ([0.0; N], [0.0; N], [0.0; N]);
        let (mut s11, mut s12, mut s13, mut s22) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..N {
            r1[k] = c[1][k]
                + u * (2.0 * c[2][k]
                    + u * (3.0 * c[3][k] + u * (4.0 * c[4][k] + u * 5.0 * c[5][k])));
            r2[k] = 2.0 * c[2][k] + u * (6.0 * c[3][k] + u * (12.0 * c[4][k] + u * 20.0 * c[5][k]));
            r3[k] = 6.0 * c[3][k] + u * (24.0 * c[4][k] + u * 60.0 * c[5][k]);
            s11 += r1[k] * r1[k];
            s12 += r1[k] * r2[k];
            s13 += r1[k] * r3[k];
            s22 += r2[k] * r2[k];
        }
        let sig = math::sqrt(s11);
        if sig.is_nan() || sig <= 0.0 {
            return;
        }
        // T = r1/σ, σ' = r2·T, perp = r2 − σ'T, T' = perp/σ, K = perp/σ²,
        // dperp/du = r3 − (r3·T + r2·T')T − σ'T', dK/ds = (dperp/du/σ² − 2·perp·σ'/σ³)/σ.
        // one division: the powers of 1/σ by products
        let i1 = 1.0 / sig;
        let (i2, sp, r3t) = (i1 * i1, s12 * i1, s13 * i1);
        let (i3, r2dt) = (i2 * i1, (s22 - sp * sp) * i1);
        for k in 0..N {
            if N == D && k >= self.n {
                break;
            }
            let t = r1[k] * i1;
            let perp = r2[k] - sp * t;
            let dt = perp * i1;
            let dperp = r3[k] - (r3t + r2dt) * t - sp * dt;
            f(k, t, perp * i2, (dperp * i2 - 2.0 * perp * sp * i3) * i1);
        }
    }
}

/// Parameters evaluated together by [`Blend::terms_lanes`] in the engine's baseline build:
/// two f64 fill an SSE2 register, which every x86-64 has (4 and 8 lanes spill registers and
/// cost more instructions, 2 fewer than one at a time: measured on the dense benchmark with
/// `path_callgrind.sh --baseline`).
pub(super) const LANES: usize = 2;
/// The same in its x86-64-v3 build (`v3.rs`): four f64 fill an AVX register (436 fewer
/// instructions a push than 2 lanes there; the same caps to the bit).
pub(super) const LANES_V3: usize = 4;

/// |T|, |K| and |dK/ds| of each of the first `N` axes at `L` parameters (axis-major: one
/// row of lanes per axis), as [`Blend::terms_lanes`] gives them.
pub(super) struct Lanes<const N: usize, const L: usize> {
    pub t: [[f64; L]; N],
    pub k: [[f64; L]; N],
    pub dk: [[f64; L]; N],
}

impl<const D: usize> Blend<D> {
    /// [`each_term_n`](Self::each_term_n) at `L` parameters at once, as absolute values,
    /// computed lane by lane in the same way (the same figures) so that the compiler can
    /// evaluate several lanes per instruction. A lane where B'(u) = 0 gets 0 everywhere (no
    /// limit), as `each_term_n` calls nothing there.
    #[allow(clippy::needless_range_loop)] // one index over several axis arrays
    #[inline(always)]
    pub fn terms_lanes<const N: usize, const L: usize>(&self, u: &[f64; L]) -> Lanes<N, L> {
        let c = &self.c;
        let z = [0.0; L];
        let (mut r1, mut r2, mut r3) = ([z; N], [z; N], [z; N]);
        let (mut s11, mut s12, mut s13, mut s22) = (z, z, z, z);
        for k in 0..N {
            let (c1, c2, c3, c4, c5) = (c[1][k], c[2][k], c[3][k], c[4][k], c[5][k]);
            for i in 0..L {
                let u = u[i];
                let a = c1 + u * (2.0 * c2 + u * (3.0 * c3 + u * (4.0 * c4 + u * 5.0 * c5)));
                let b = 2.0 * c2 + u * (6.0 * c3 + u * (12.0 * c4 + u * 20.0 * c5));
                let d = 6.0 * c3 + u * (24.0 * c4 + u * 60.0 * c5);
                r1[k][i] = a;
                r2[k][i] = b;
                r3[k][i] = d;
                s11[i] += a * a;
                s12[i] += a * b;
                s13[i] += a * d;
                s22[i] += b * b;
            }
        }
        let mut out = Lanes {
            t: [z; N],
            k: [z; N],
            dk: [z; N],
        };
        let (mut ok, mut sp, mut r3t, mut r2dt) = ([false; L], z, z, z);
        let (mut i1, mut i2, mut i3) = (z, z, z);
        for i in 0..L {
            let sig = math::sqrt(s11[i]);
            ok[i] = sig > 0.0;
            i1[i] = 1.0 / sig;
            i2[i] = i1[i] * i1[i];
            sp[i] = s12[i] * i1[i];
            r3t[i] = s13[i] * i1[i];
            i3[i] = i2[i] * i1[i];
            r2dt[i] = (s22[i] - sp[i] * sp[i]) * i1[i];
        }
        for k in 0..N {
            if N == D && k >= self.n {
                break;
            }
            for i in 0..L {
                let t = r1[k][i] * i1[i];
                let perp = r2[k][i] - sp[i] * t;
                let dt = perp * i1[i];
                let dperp = r3[k][i] - (r3t[i] + r2dt[i]) * t - sp[i] * dt;
                let kk = perp * i2[i];
                let dk = (dperp * i2[i] - 2.0 * perp * sp[i] * i3[i]) * i1[i];
                // a lane where B'(u) = 0 (or not a number) limits nothing
                out.t[k][i] = if ok[i] { t.abs() } else { 0.0 };
                out.k[k][i] = if ok[i] { kk.abs() } else { 0.0 };
                out.dk[k][i] = if ok[i] { dk.abs() } else { 0.0 };
            }
        }
        out
    }
}

/// Distance from `p` to the segment [a, b] (first `n` axes).
pub(super) fn dist_to_chord<const D: usize>(n: usize, p: &V<D>, a: &V<D>, b: &V<D>) -> f64 {
    let (mut ab2, mut apab) = (0.0, 0.0);
    for k in 0..n {
        ab2 += (b[k] - a[k]) * (b[k] - a[k]);
        apab += (p[k] - a[k]) * (b[k] - a[k]);
    }
    let t = if ab2 > 0.0 {
        (apab / ab2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut d2 = 0.0;
    for k in 0..n {
        let q = a[k] + t * (b[k] - a[k]) - p[k];
        d2 += q * q;
    }
    math::sqrt(d2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame_fd(bl: &Blend, s: f64, h: f64) -> (V, V) {
        // K and dK/ds by central differences of the position in s
        let p = |x: f64| bl.pos(x);
        let (pm2, pm, p0, pp, pp2) = (p(s - 2.0 * h), p(s - h), p(s), p(s + h), p(s + 2.0 * h));
        let mut k = Z;
        let mut dk = Z;
        for i in 0..2 {
            k[i] = (pp[i] - 2.0 * p0[i] + pm[i]) / (h * h);
            dk[i] = (pp2[i] - 2.0 * pp[i] + 2.0 * pm[i] - pm2[i]) / (2.0 * h * h * h);
        }
        (k, dk)
    }

    #[test]
    fn blend_frames_match_the_arc_length_derivatives() {
        let a = Frame {
            p: [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            t: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            k: [0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..Frame::default()
        };
        let s2 = 0.5f64.sqrt();
        let b = Frame {
            p: [100.0, 60.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            t: [s2, s2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..Frame::default()
        };
        let bl = Blend::new(2, &a, &b, 50.0, 40.0).unwrap();
        // ends match position, tangent and curvature
        let f0 = bl.frame_u(0.0);
        let f1 = bl.frame_u(1.0);
        for k in 0..2 {
            assert!((f0.t[k] - a.t[k]).abs() < 1e-12 && (f0.k[k] - a.k[k]).abs() < 1e-12);
            assert!((f1.p[k] - b.p[k]).abs() < 1e-9 && (f1.t[k] - b.t[k]).abs() < 1e-12);
            assert!((f1.k[k] - b.k[k]).abs() < 1e-12);
        }
        for i in 1..10 {
            let s = bl.len * i as f64 / 10.0;
            let u = bl.u_at(s);
            let f = bl.frame_u(u);
            let (k, dk) = frame_fd(&bl, s, 0.05);
            for j in 0..2 {
                assert!((f.k[j] - k[j]).abs() < 1e-5, "{i} {j} {:?} {:?}", f.k, k);
                assert!(
                    (f.dk[j] - dk[j]).abs() < 1e-5,
                    "{i} {j} {:?} {:?}",
                    f.dk,
                    dk
                );
            }
            // arc length consistent with the chord sum
            let (mut sum, m) = (0.0, 2000);
            for q in 0..m {
                let pa = bl.pos_u(q as f64 / m as f64);
                let pb = bl.pos_u((q + 1) as f64 / m as f64);
                sum += (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            }
            assert!((sum - bl.len).abs() < 1e-4 * bl.len);
        }
    }

    #[test]
    fn helix_frame_is_the_derivative_of_its_position() {
        let p0 = [10.0, 0.0, 5.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let p1 = [0.0, 10.0, 25.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let h = Helix::new(3, p0, p1, 0, 1, [0.0, 0.0], true).unwrap();
        let pr = Prog::Helix(h);
        assert_eq!(pr.pos(0.0), p0);
        assert_eq!(pr.pos(pr.len()), p1);
        let e = 1e-3;
        for i in 1..8 {
            let s = pr.len() * i as f64 / 8.0;
            let f = pr.frame(s);
            let (a, b) = (pr.frame(s - e), pr.frame(s + e));
            for k in 0..3 {
                let t = (b.p[k] - a.p[k]) / (2.0 * e);
                let kk = (b.t[k] - a.t[k]) / (2.0 * e);
                let dk = (b.k[k] - a.k[k]) / (2.0 * e);
                assert!((t - f.t[k]).abs() < 1e-6, "{k}");
                assert!((kk - f.k[k]).abs() < 1e-6, "{k}");
                assert!((dk - f.dk[k]).abs() < 1e-6, "{k}");
            }
        }
    }
}
