//! Splines in the XY plane (G17): G5 (cubic Bézier: I J from the start, P Q from the end),
//! G5.1 (quadratic Bézier: I J from the start), G5.2 … G5.3 (NURBS: control points X Y with
//! weights P, order L; LinuxCNC's clamped knot vector).

use super::{err, Interp};
use crate::gcode::{Block, GcodeError, Op, OpKind, Plane, Pos, Spline};

impl Interp {
    /// What every spline needs: the XY plane, no cutter compensation, no A B C, no Z change.
    fn spline_checks(&self, b: &Block, what: &str) -> Result<(), GcodeError> {
        let line = b.line;
        if self.plane != Plane::Xy {
            return err(line, format!("{what} only in the XY plane (G17)"));
        }
        if self.comp.is_some() || self.comp_mode != super::CompMode::Off {
            return err(line, format!("{what} with cutter radius compensation on"));
        }
        for c in ['A', 'B', 'C'] {
            if b.word(c).is_some() {
                return err(line, format!("{what} may not move {c}"));
            }
        }
        let cur = self.cur_work();
        if (self.target(b)[2] - cur[2]).abs() > 0.0 {
            return err(
                line,
                format!("{what} moves in the XY plane only: Z may not change"),
            );
        }
        Ok(())
    }

    /// Emits a spline through work control points.
    fn emit_spline(
        &mut self,
        b: &Block,
        points: Vec<Pos>,
        weights: Vec<f64>,
        degree: usize,
        knots: Vec<f64>,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let points: Vec<Pos> = points.into_iter().map(|p| self.machine(p)).collect();
        let spline = Spline {
            degree,
            points,
            weights,
            knots,
        };
        let start = self.position;
        let end = *spline.points.last().expect("a spline has points");
        let len = super::geom::spline_length(&spline);
        let feed = self.feed_rate(b, len, 0.0)?;
        out.push(Op {
            line: b.line,
            kind: OpKind::Spline {
                start,
                end,
                spline,
                feed,
                blend: self.blend,
            },
        });
        self.position = end;
        Ok(())
    }

    /// G5 / G5.1.
    pub(super) fn spline(
        &mut self,
        b: &Block,
        quadratic: bool,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        let name = if quadratic { "G5.1" } else { "G5" };
        self.spline_checks(b, name)?;
        let k = self.k();
        let s = self.cur_work();
        let e = self.target(b);
        let at = |p: Pos, dx: f64, dy: f64| -> Pos {
            let mut q = p;
            q[0] += dx;
            q[1] += dy;
            q
        };
        let ij = match (b.word('I'), b.word('J')) {
            (Some(i), Some(j)) => Some([i * k, j * k]),
            (None, None) => None,
            _ => return err(line, format!("{name} needs both I and J, or neither")),
        };
        if quadratic {
            let Some([i, j]) = ij else {
                return err(line, "G5.1 needs I and J");
            };
            let pts = vec![s, at(s, i, j), e];
            self.emit_spline(b, pts, vec![1.0; 3], 2, vec![0., 0., 0., 1., 1., 1.], out)
        } else {
            let (Some(p), Some(q)) = (b.word('P'), b.word('Q')) else {
                return err(line, "G5 needs P and Q");
            };
            let [i, j] = ij.unwrap_or(self.spline_ij);
            let (p, q) = (p * k, q * k);
            let pts = vec![s, at(s, i, j), at(e, p, q), e];
            self.emit_spline(
                b,
                pts,
                vec![1.0; 4],
                3,
                vec![0., 0., 0., 0., 1., 1., 1., 1.],
                out,
            )?;
            self.spline_ij = [-p, -q];
            Ok(())
        }
    }

    /// G5.2: a control point (and, on the first, the current position as the first).
    pub(super) fn nurbs_point(&mut self, b: &Block) -> Result<(), GcodeError> {
        let line = b.line;
        self.spline_checks(b, "G5.2")?;
        let (x, y) = (b.word('X'), b.word('Y'));
        if x.is_some() != y.is_some() {
            return err(line, "G5.2 control points need both X and Y");
        }
        let p = b.word('P');
        if self.nurbs.is_empty() {
            let cur = self.cur_work();
            let w = match (x, p) {
                (None, Some(p)) if p > 0.0 => p,
                _ => 1.0,
            };
            self.nurbs.push(([cur[0], cur[1]], w));
            self.nurbs_order = 3;
            self.nurbs_line = line;
        } else if x.is_none() {
            return err(
                line,
                "G5.2 without X and Y: P alone is only for the first point",
            );
        }
        if let Some(l) = b.word('L') {
            let l = super::modal::int_word(line, 'L', l, 0.0)? as usize;
            if l > 3 {
                self.nurbs_order = l;
            }
        }
        if x.is_some() {
            let Some(w) = p.filter(|&w| w > 0.0) else {
                return err(line, "every G5.2 control point needs a positive weight P");
            };
            let t = self.target(b);
            self.nurbs.push(([t[0], t[1]], w));
        }
        Ok(())
    }

    /// G5.3: the NURBS of the control points collected.
    pub(super) fn nurbs_end(&mut self, b: &Block, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        if self.nurbs.is_empty() {
            return err(line, "G5.3 without G5.2 first");
        }
        let order = self.nurbs_order;
        let n = self.nurbs.len();
        if n < order {
            return err(
                line,
                format!("G5.3: {n} control points, fewer than the order L{order}"),
            );
        }
        let cur = self.cur_work();
        let pts: Vec<Pos> = self
            .nurbs
            .iter()
            .map(|(p, _)| {
                let mut q = cur;
                q[0] = p[0];
                q[1] = p[1];
                q
            })
            .collect();
        let weights: Vec<f64> = self.nurbs.iter().map(|(_, w)| *w).collect();
        let knots = knot_vector(n - 1, order);
        self.nurbs.clear();
        self.emit_spline(b, pts, weights, order - 1, knots, out)?;
        self.motion = None;
        Ok(())
    }
}

/// LinuxCNC's clamped uniform knot vector for `n + 1` control points of order `k`: `k`
/// zeros, then 1, 2, …, then `n - k + 2` repeated `k` times.
pub(super) fn knot_vector(n: usize, k: usize) -> Vec<f64> {
    (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i - k + 1) as f64
            } else {
                (n + 2 - k) as f64
            }
        })
        .collect()
}
