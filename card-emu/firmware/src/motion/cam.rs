//! Cam tables (layout 1.7): a slave position as a function of a master position, given at up
//! to [`CAM_MAX_POINTS`] points `(m_i, s_i)` with `m_i` strictly increasing, interpolated
//! linearly or by a cubic spline (continuous velocity and acceleration). Pure data and
//! functions, shared by the card (`firmware::cam`) and the host.
//!
//! - **Cubic**: the interpolating cubic spline, its second derivatives `M_i` from the
//!   tridiagonal system `h_{i−1} M_{i−1} + 2 (h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 (d_i −
//!   d_{i−1})` (`d` the chords' slopes): *natural* ends (`M = 0`) for a table that is not
//!   periodic, and for a periodic one the cyclic system (the first and last points are the same
//!   point of the cycle), solved by the Thomas algorithm with a Sherman–Morrison correction.
//! - **Periodic**: the master's period is `m_n − m_0`; the slave may rise by `s_n − s_0` per
//!   cycle (a rotary knife turns once per sheet), so `f(m + P) = f(m) + R`. A cubic periodic
//!   table has the same slope and curvature at both ends of the cycle.
//! - **Not periodic**: beyond the table the slave holds the end value.
//!
//! `eval` allocates nothing and never panics.
#![forbid(unsafe_code)]

use crate::math;
use heapless::Vec;

/// The largest table.
pub const CAM_MAX_POINTS: usize = 1024;

/// Why a table is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CamError {
    /// Fewer than 2 (cubic: 3) or more than [`CAM_MAX_POINTS`] points.
    Count,
    /// A value not finite.
    NotFinite,
    /// The master positions do not increase strictly.
    NotIncreasing,
}

/// A cam table ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct CamTable {
    m: Vec<f64, CAM_MAX_POINTS>,
    s: Vec<f64, CAM_MAX_POINTS>,
    /// Second derivatives at the points (cubic), else empty.
    m2: Vec<f64, CAM_MAX_POINTS>,
    periodic: bool,
}

/// Where the master is on a table: its position, velocity and acceleration along `m`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CamSample {
    /// Slave position.
    pub s: f64,
    /// ds/dm.
    pub ds: f64,
    /// d²s/dm².
    pub dds: f64,
    /// Cycles from the table's first cycle (periodic), else 0.
    pub cycle: i64,
}

impl CamTable {
    /// Build a table from `points` (master, slave).
    pub fn new(points: &[(f64, f64)], cubic: bool, periodic: bool) -> Result<Self, CamError> {
        let n = points.len();
        if n < if cubic { 3 } else { 2 } || n > CAM_MAX_POINTS {
            return Err(CamError::Count);
        }
        if points.iter().any(|(a, b)| !a.is_finite() || !b.is_finite()) {
            return Err(CamError::NotFinite);
        }
        if points.windows(2).any(|w| w[1].0 <= w[0].0) {
            return Err(CamError::NotIncreasing);
        }
        let mut t = CamTable {
            m: points.iter().map(|p| p.0).collect(),
            s: points.iter().map(|p| p.1).collect(),
            m2: Vec::new(),
            periodic,
        };
        if cubic {
            t.m2 = spline(&t.m, &t.s, periodic);
            if t.m2.iter().any(|x| !x.is_finite()) {
                return Err(CamError::NotFinite);
            }
        }
        Ok(t)
    }

    /// Points in the table.
    pub fn len(&self) -> usize {
        self.m.len()
    }

    /// Never: a table has at least two points.
    pub fn is_empty(&self) -> bool {
        self.m.is_empty()
    }

    /// The master's period (the table's span) and the slave's rise per cycle.
    pub fn period(&self) -> (f64, f64) {
        let n = self.m.len() - 1;
        (self.m[n] - self.m[0], self.s[n] - self.s[0])
    }

    /// Is it periodic?
    pub fn periodic(&self) -> bool {
        self.periodic
    }

    /// The master range of the table.
    pub fn master_range(&self) -> (f64, f64) {
        (self.m[0], self.m[self.m.len() - 1])
    }

    /// The slave at master `x` (with its derivatives along the master).
    pub fn eval(&self, x: f64) -> CamSample {
        let n = self.m.len() - 1;
        let (m0, mn) = (self.m[0], self.m[n]);
        let (mut x, mut base, mut cycle) = (x, 0.0, 0i64);
        if self.periodic {
            let (p, r) = self.period();
            let k = math::floor((x - m0) / p);
            if k.is_finite() {
                x -= k * p;
                base = k * r;
                cycle = k as i64;
            }
            x = x.clamp(m0, mn);
        } else if x <= m0 {
            return CamSample {
                s: self.s[0],
                ..Default::default()
            };
        } else if x >= mn {
            return CamSample {
                s: self.s[n],
                ..Default::default()
            };
        }
        // The segment: the last m_i ≤ x.
        let i = match self.m.binary_search_by(|m| m.total_cmp(&x)) {
            Ok(i) => i.min(n - 1),
            Err(i) => i.saturating_sub(1).min(n - 1),
        };
        let (x0, x1, y0, y1) = (self.m[i], self.m[i + 1], self.s[i], self.s[i + 1]);
        let h = x1 - x0;
        let mut out = if self.m2.is_empty() {
            let d = (y1 - y0) / h;
            CamSample {
                s: y0 + d * (x - x0),
                ds: d,
                dds: 0.0,
                cycle,
            }
        } else {
            let (a0, a1) = (self.m2[i], self.m2[i + 1]);
            let (u, w) = (x1 - x, x - x0);
            CamSample {
                s: a0 * u * u * u / (6.0 * h)
                    + a1 * w * w * w / (6.0 * h)
                    + (y0 / h - a0 * h / 6.0) * u
                    + (y1 / h - a1 * h / 6.0) * w,
                ds: -a0 * u * u / (2.0 * h) + a1 * w * w / (2.0 * h) + (y1 - y0) / h
                    - (a1 - a0) * h / 6.0,
                dds: (a0 * u + a1 * w) / h,
                cycle,
            }
        };
        out.s += base;
        out
    }
}

/// The second derivatives of the cubic spline through `(m, s)` (see the module doc).
fn spline(m: &[f64], s: &[f64], periodic: bool) -> Vec<f64, CAM_MAX_POINTS> {
    let n = m.len() - 1; // segments
    let h = |i: usize| m[i + 1] - m[i];
    let d = |i: usize| (s[i + 1] - s[i]) / h(i);
    let mut out: Vec<f64, CAM_MAX_POINTS> = Vec::new();
    let _ = out.resize(n + 1, 0.0);
    if !periodic {
        // Natural: unknowns M_1..M_{n-1}.
        let k = n - 1;
        if k == 0 {
            return out;
        }
        let mut c: Vec<f64, CAM_MAX_POINTS> = Vec::new();
        let mut r: Vec<f64, CAM_MAX_POINTS> = Vec::new();
        for j in 0..k {
            let i = j + 1;
            let (a, b, cc) = (h(i - 1), 2.0 * (h(i - 1) + h(i)), h(i));
            let rhs = 6.0 * (d(i) - d(i - 1));
            let (cp, rp) = if j == 0 {
                (0.0, 0.0)
            } else {
                (c[j - 1], r[j - 1])
            };
            let den = b - a * cp;
            let _ = c.push(if j + 1 < k { cc / den } else { 0.0 });
            let _ = r.push((rhs - a * rp) / den);
        }
        for j in (0..k).rev() {
            let next = if j + 1 < k { out[j + 2] } else { 0.0 };
            out[j + 1] = r[j] - c[j] * next;
        }
        return out;
    }
    // Periodic: unknowns M_0..M_{n-1} (M_n = M_0), a cyclic tridiagonal system.
    let k = n;
    let hp = |i: usize| h((i + n - 1) % n); // the segment before point i
    let dp = |i: usize| d((i + n - 1) % n);
    let a = |i: usize| hp(i);
    let b = |i: usize| 2.0 * (hp(i) + h(i));
    let c = |i: usize| h(i);
    let rhs = |i: usize| 6.0 * (d(i) - dp(i));
    if k == 2 {
        // Two segments: [b0, a0+c0; a1+c1, b1].
        let (a11, a12, a21, a22) = (b(0), a(0) + c(0), a(1) + c(1), b(1));
        let det = a11 * a22 - a12 * a21;
        let (r0, r1) = (rhs(0), rhs(1));
        out[0] = (r0 * a22 - a12 * r1) / det;
        out[1] = (a11 * r1 - a21 * r0) / det;
        out[2] = out[0];
        return out;
    }
    // Sherman–Morrison: A = T + u vᵀ with u = (γ, 0…, c_{k−1}), v = (1, 0…, a_0/γ).
    let gamma = -b(0);
    let solve = |rhs_of: &dyn Fn(usize) -> f64, x: &mut Vec<f64, CAM_MAX_POINTS>| {
        let mut cp: Vec<f64, CAM_MAX_POINTS> = Vec::new();
        let mut rp: Vec<f64, CAM_MAX_POINTS> = Vec::new();
        for i in 0..k {
            let mut bi = b(i);
            if i == 0 {
                bi -= gamma;
            }
            if i == k - 1 {
                bi -= a(0) * c(k - 1) / gamma;
            }
            let ai = if i == 0 { 0.0 } else { a(i) };
            let (cprev, rprev) = if i == 0 {
                (0.0, 0.0)
            } else {
                (cp[i - 1], rp[i - 1])
            };
            let den = bi - ai * cprev;
            let _ = cp.push(c(i) / den);
            let _ = rp.push((rhs_of(i) - ai * rprev) / den);
        }
        x.clear();
        let _ = x.resize(k, 0.0);
        for i in (0..k).rev() {
            x[i] = rp[i] - if i + 1 < k { cp[i] * x[i + 1] } else { 0.0 };
        }
    };
    let mut y: Vec<f64, CAM_MAX_POINTS> = Vec::new();
    let mut z: Vec<f64, CAM_MAX_POINTS> = Vec::new();
    solve(&rhs, &mut y);
    let uu = |i: usize| {
        if i == 0 {
            gamma
        } else if i == k - 1 {
            c(k - 1)
        } else {
            0.0
        }
    };
    solve(&uu, &mut z);
    let vy = y[0] + a(0) / gamma * y[k - 1];
    let vz = z[0] + a(0) / gamma * z[k - 1];
    let f = vy / (1.0 + vz);
    for i in 0..k {
        out[i] = y[i] - f * z[i];
    }
    out[n] = out[0];
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic table meets its points; velocity and acceleration are continuous at them.
    fn smooth_at_points(t: &CamTable, pts: &[(f64, f64)]) {
        let e = 1e-7;
        for (i, (m, s)) in pts.iter().enumerate() {
            assert!(
                (t.eval(*m).s - s).abs() < 1e-9 * s.abs().max(1.0),
                "point {i}"
            );
            if i == 0 || i + 1 == pts.len() {
                continue;
            }
            let (l, r) = (t.eval(m - e), t.eval(m + e));
            assert!(
                (l.ds - r.ds).abs() < 1e-4 * l.ds.abs().max(1.0),
                "slope at {i}"
            );
            assert!(
                (l.dds - r.dds).abs() < 1e-3 * l.dds.abs().max(1.0),
                "curvature at {i}"
            );
        }
    }

    #[test]
    fn natural_and_periodic_splines() {
        let pts: std::vec::Vec<(f64, f64)> = (0..=12)
            .map(|i| {
                let m = i as f64 * 30.0;
                (m, 100.0 * (m.to_radians()).sin())
            })
            .collect();
        let t = CamTable::new(&pts, true, false).unwrap();
        smooth_at_points(&t, &pts);
        assert_eq!(t.eval(-5.0).s, pts[0].1);
        let p = CamTable::new(&pts, true, true).unwrap();
        smooth_at_points(&p, &pts);
        // Across the cycle: the same slope and curvature at both ends, and it repeats.
        let (a, b) = (p.eval(360.0 - 1e-7), p.eval(360.0 + 1e-7));
        assert!((a.ds - b.ds).abs() < 1e-4 && (a.dds - b.dds).abs() < 1e-3);
        assert!((p.eval(400.0).s - p.eval(40.0).s).abs() < 1e-9);
        // sin through 13 points: close to the sine between them.
        assert!((p.eval(45.0).s - 100.0 * 45f64.to_radians().sin()).abs() < 0.05);
    }

    #[test]
    fn a_rise_per_cycle_and_linear_tables() {
        let pts = [(0.0, 0.0), (10.0, 3.0), (20.0, 10.0)];
        let t = CamTable::new(&pts, false, true).unwrap();
        assert_eq!(t.period(), (20.0, 10.0));
        assert_eq!(t.eval(25.0).s, 11.5);
        assert_eq!(t.eval(25.0).cycle, 1);
        assert_eq!(t.eval(-15.0).s, -10.0 + 1.5);
        assert_eq!(
            CamTable::new(&[(0.0, 0.0), (0.0, 1.0)], false, false),
            Err(CamError::NotIncreasing)
        );
        assert_eq!(
            CamTable::new(&[(0.0, f64::NAN), (1.0, 1.0)], false, false),
            Err(CamError::NotFinite)
        );
        assert_eq!(
            CamTable::new(&[(0.0, 0.0)], false, false),
            Err(CamError::Count)
        );
    }
}
