//! Lengths of motions: lines, arcs (with their extra turns and helix), splines (integrated
//! numerically), and NURBS evaluation.

use super::motion::{distances, sweep, SAME_POINT_MM};
use crate::gcode::{ArcFrame, OpKind, Spline};

impl OpKind {
    /// The angle an arc turns through (radians, > 0), its extra turns included; `None` for
    /// what is not an arc.
    pub fn arc_sweep(&self) -> Option<f64> {
        if let OpKind::ArcNormal { turns, .. } = self {
            let f = self.normal_arc_frame()?;
            return Some(f.sweep + std::f64::consts::TAU * f64::from(*turns));
        }
        let OpKind::Arc {
            start,
            end,
            centre,
            plane,
            ccw,
            turns,
            ..
        } = self
        else {
            return None;
        };
        let (a, b, _) = plane.axes();
        let partial = sweep(
            [start[a], start[b]],
            [end[a], end[b]],
            [centre[a], centre[b]],
            *ccw,
        );
        Some(partial + std::f64::consts::TAU * f64::from(*turns))
    }

    /// The length of a motion along its path: in mm over X Y Z, or, for a motion of A B C
    /// alone, in degrees. A rigid tap (G33.1) counts its way in and out. `None` for what is
    /// not a motion.
    pub fn length(&self) -> Option<f64> {
        let pick = |lin: f64, ang: f64| if lin > 0.0 { lin } else { ang };
        Some(match self {
            OpKind::Rapid { start, end, .. }
            | OpKind::Feed { start, end, .. }
            | OpKind::Probe { start, end, .. } => {
                let (l, a) = distances(*start, *end);
                pick(l, a)
            }
            OpKind::SpindleSync {
                start, end, tap, ..
            } => {
                let (l, a) = distances(*start, *end);
                pick(l, a) * if *tap { 2.0 } else { 1.0 }
            }
            OpKind::Arc {
                start,
                end,
                centre,
                plane,
                ccw,
                turns,
                ..
            } => {
                let (a, b, n) = plane.axes();
                let s = [start[a], start[b]];
                let e = [end[a], end[b]];
                let c = [centre[a], centre[b]];
                let r = (s[0] - c[0]).hypot(s[1] - c[1]);
                let theta = sweep(s, e, c, *ccw) + 2.0 * std::f64::consts::PI * f64::from(*turns);
                let lin = (r * theta).hypot(end[n] - start[n]);
                let (_, ang) = distances(*start, *end);
                pick(lin, ang)
            }
            OpKind::ArcNormal { start, end, .. } => {
                let f = self.normal_arc_frame()?;
                let lin = (f.radius * self.arc_sweep()?).hypot(f.rise);
                let (_, ang) = distances(*start, *end);
                pick(lin, ang)
            }
            OpKind::Spline { spline, .. } => spline_length(spline),
            _ => return None,
        })
    }
}

impl OpKind {
    /// The circle of an [`OpKind::ArcNormal`] (`None` for anything else, or a normal or
    /// radius of zero).
    pub fn normal_arc_frame(&self) -> Option<ArcFrame> {
        let OpKind::ArcNormal {
            start,
            end,
            centre,
            normal,
            ccw,
            ..
        } = self
        else {
            return None;
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let m = dot(*normal, *normal).sqrt();
        if !(m > 0.0 && m.is_finite()) {
            return None;
        }
        let sign = if *ccw { 1.0 / m } else { -1.0 / m };
        let axis = normal.map(|x| x * sign);
        let s = [start[0], start[1], start[2]];
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        // the centre into the plane through the start
        let hc = dot(sub(*centre, s), axis);
        let c = [
            centre[0] - hc * axis[0],
            centre[1] - hc * axis[1],
            centre[2] - hc * axis[2],
        ];
        let r0 = sub(s, c);
        let radius = dot(r0, r0).sqrt();
        if !(radius > 0.0 && radius.is_finite()) {
            return None;
        }
        let u = r0.map(|x| x / radius);
        let v = [
            axis[1] * u[2] - axis[2] * u[1],
            axis[2] * u[0] - axis[0] * u[2],
            axis[0] * u[1] - axis[1] * u[0],
        ];
        let e = sub([end[0], end[1], end[2]], c);
        let (x, y) = (dot(e, u), dot(e, v));
        let sweep = if (x - radius).hypot(y) < SAME_POINT_MM {
            std::f64::consts::TAU
        } else {
            match y.atan2(x).rem_euclid(std::f64::consts::TAU) {
                d if d > 0.0 => d,
                _ => std::f64::consts::TAU,
            }
        };
        Some(ArcFrame {
            centre: c,
            u,
            v,
            axis,
            radius,
            sweep,
            rise: dot(e, axis),
        })
    }
}

impl ArcFrame {
    /// The point a fraction `t` (clamped to [0, 1]) of the way: angle and height both linear
    /// in `t`.
    pub fn point(&self, t: f64) -> [f64; 3] {
        let t = t.clamp(0.0, 1.0);
        let (s, c) = (t * self.sweep).sin_cos();
        std::array::from_fn(|i| {
            self.centre[i]
                + self.radius * (c * self.u[i] + s * self.v[i])
                + t * self.rise * self.axis[i]
        })
    }

    /// Length along the arc or helix (of its partial turn).
    pub fn length(&self) -> f64 {
        (self.radius * self.sweep).hypot(self.rise)
    }
}

/// Homogeneous control points: X Y Z times the weight, then the weight.
fn homogeneous(s: &Spline) -> Vec<[f64; 4]> {
    s.points
        .iter()
        .zip(&s.weights)
        .map(|(p, &w)| [p[0] * w, p[1] * w, p[2] * w, w])
        .collect()
}

/// The B-spline of degree `p` over `knots` with control points `c`, at `u` (de Boor).
fn de_boor(p: usize, knots: &[f64], c: &[[f64; 4]], u: f64) -> [f64; 4] {
    let n = c.len();
    // The span: knots[k] <= u < knots[k + 1], within p..n.
    let mut k = p;
    while k + 1 < n && u >= knots[k + 1] {
        k += 1;
    }
    let mut d: Vec<[f64; 4]> = (0..=p).map(|j| c[j + k - p]).collect();
    for r in 1..=p {
        for j in (r..=p).rev() {
            let i = j + k - p;
            let den = knots[i + 1 + p - r] - knots[i];
            let alpha = if den > 0.0 { (u - knots[i]) / den } else { 0.0 };
            let prev = d[j - 1];
            for (m, v) in d[j].iter_mut().enumerate() {
                *v = (1.0 - alpha) * prev[m] + alpha * *v;
            }
        }
    }
    d[p]
}

/// The derivative's control points (degree `p - 1`, knots without the first and last).
fn derivative(p: usize, knots: &[f64], c: &[[f64; 4]]) -> Vec<[f64; 4]> {
    (0..c.len() - 1)
        .map(|i| {
            let den = knots[i + p + 1] - knots[i + 1];
            let f = if den > 0.0 { p as f64 / den } else { 0.0 };
            std::array::from_fn(|m| f * (c[i + 1][m] - c[i][m]))
        })
        .collect()
}

/// A point of the spline (X Y Z).
#[cfg(test)]
pub(super) fn spline_point(s: &Spline, u: f64) -> [f64; 3] {
    let h = de_boor(s.degree, &s.knots, &homogeneous(s), u);
    [h[0] / h[3], h[1] / h[3], h[2] / h[3]]
}

/// The length of a spline over X Y Z: Gauss–Legendre on each knot span, halved until two
/// estimates agree to 1e-13 of the span's length.
pub(super) fn spline_length(s: &Spline) -> f64 {
    let p = s.degree;
    if p == 0 || s.points.len() < 2 {
        return 0.0;
    }
    let c = homogeneous(s);
    let dc = derivative(p, &s.knots, &c);
    let dknots = &s.knots[1..s.knots.len() - 1];
    let speed = |u: f64| {
        let a = de_boor(p, &s.knots, &c, u);
        let da = de_boor(p - 1, dknots, &dc, u);
        // (A / w)' = (A' - w' A / w) / w
        let w = a[3];
        let v: [f64; 3] = std::array::from_fn(|m| (da[m] - da[3] * a[m] / w) / w);
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    };
    let mut total = 0.0;
    for w in s.knots.windows(2) {
        if w[1] > w[0] {
            total += adaptive(&speed, w[0], w[1], gauss(&speed, w[0], w[1]), 0);
        }
    }
    total
}

/// 7-point Gauss–Legendre over [a, b].
fn gauss(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const X: [f64; 4] = [
        0.0,
        0.405_845_151_377_397_2,
        0.741_531_185_599_394_4,
        0.949_107_912_342_758_5,
    ];
    const W: [f64; 4] = [
        0.417_959_183_673_469_4,
        0.381_830_050_505_118_9,
        0.279_705_391_489_276_7,
        0.129_484_966_168_869_7,
    ];
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    let mut sum = W[0] * f(m);
    for i in 1..4 {
        sum += W[i] * (f(m - h * X[i]) + f(m + h * X[i]));
    }
    sum * h
}

fn adaptive(f: &impl Fn(f64) -> f64, a: f64, b: f64, whole: f64, depth: u32) -> f64 {
    let m = (a + b) / 2.0;
    let (l, r) = (gauss(f, a, m), gauss(f, m, b));
    if depth >= 24 || (l + r - whole).abs() <= 1e-13 * (l + r).abs().max(1e-300) {
        l + r
    } else {
        adaptive(f, a, m, l, depth + 1) + adaptive(f, m, b, r, depth + 1)
    }
}
