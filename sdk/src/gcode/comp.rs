//! Cutter radius compensation (G41/G42) in the plane: the programmed path's lines and arcs
//! offset by the tool radius, arcs added at convex corners, intersections at concave ones,
//! after LinuxCNC's `convert_straight_comp1/2` and `convert_arc_comp1/2` (see
//! [`Compensator::push`] for the rules).
//!
//! Where it differs from LinuxCNC 2.9's code:
//! - The entry line ends at the tangent point from its start to the circle of the radius about
//!   the programmed end (as NIST's rs274ngc and the LinuxCNC manual's figure have it), not at
//!   the programmed end offset perpendicular to the entry line: the tool then meets the
//!   programmed end exactly tangent, and the entry line is the offset of a line through the
//!   programmed end, which the next corner treats like any other.
//! - Corners are told apart at [`ANGLE_TOL`] (1e-9 rad), not LinuxCNC's 0.05 rad: a slightly
//!   concave corner ends at the exact intersection instead of joining with a slightly skewed
//!   line, a slightly convex one gets its small arc, so every offset piece stays exactly at
//!   the radius.
//! - A reversal is classified by the two moves' curvatures (LinuxCNC special-cases the line
//!   or arc into an arc the tool is outside of, its "h" and "m" shapes, with the same result).

/// Which side of the programmed path the tool runs on, looking along the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// A programmed move in the plane's coordinates (first, second axis of the plane); it starts
/// where the one before ended.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum Piece {
    Line {
        end: [f64; 2],
    },
    Arc {
        end: [f64; 2],
        centre: [f64; 2],
        ccw: bool,
    },
}

/// A move of the tool's centre.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum Offset {
    Line {
        start: [f64; 2],
        end: [f64; 2],
    },
    Arc {
        start: [f64; 2],
        end: [f64; 2],
        centre: [f64; 2],
        ccw: bool,
    },
}

/// What the tool cannot do: gouge, a first move shorter than the radius, an arc smaller than
/// the tool on its inside.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompError(pub String);

/// A compensated path, one programmed move behind (a corner is known only when the next move
/// is). `T` travels with each programmed move (the caller's line number, feed, the other axes'
/// end) and comes out with every piece made from it.
#[derive(Debug, Clone)]
pub struct Compensator<T> {
    /// +1 for the tool on the left, −1 on the right.
    sign: f64,
    radius: f64,
    /// Where the last piece appended ended.
    pos: V,
    /// The largest magnitude seen (at least 1): the length tolerance's scale.
    scale: f64,
    pending: Option<Pending<T>>,
    failed: Option<CompError>,
}

/// Angles below this (radians) between one move's end and the next one's start are a tangent
/// join: no corner arc, no intersection.
pub const ANGLE_TOL: f64 = 1e-9;

/// Lengths below `LEN_TOL` times the path's scale (the largest coordinate magnitude seen, the
/// radius, and 1) count as zero.
pub const LEN_TOL: f64 = 1e-9;

type V = [f64; 2];

fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1]]
}

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1]]
}

fn mul(a: V, k: f64) -> V {
    [a[0] * k, a[1] * k]
}

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: V, b: V) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn norm(a: V) -> f64 {
    a[0].hypot(a[1])
}

/// `a` turned a quarter turn counter-clockwise.
fn left(a: V) -> V {
    [-a[1], a[0]]
}

fn finite(a: V) -> bool {
    a[0].is_finite() && a[1].is_finite()
}

fn angle(a: V) -> f64 {
    a[1].atan2(a[0])
}

const TAU: f64 = std::f64::consts::TAU;
const PI: f64 = std::f64::consts::PI;

/// The curve an offset piece lies on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Curve {
    /// Through `p` along the unit vector `t`; parameter: distance from `p` along `t`.
    Line { p: V, t: V },
    /// About `c` with radius `rad`, `dir` +1 counter-clockwise, −1 clockwise; parameter: the
    /// angle swept from the direction `a0` in the direction of travel (radians).
    Circle { c: V, rad: f64, dir: f64, a0: f64 },
}

impl Curve {
    /// `x`'s parameter; on a circle, the value in `[lo, lo + 2π)`.
    fn param(&self, x: V, lo: f64) -> f64 {
        match *self {
            Curve::Line { p, t } => dot(sub(x, p), t),
            Curve::Circle { c, dir, a0, .. } => {
                let raw = dir * (angle(sub(x, c)) - a0);
                lo + (raw - lo).rem_euclid(TAU)
            }
        }
    }

    /// The parameter tolerance matching a length tolerance.
    fn ptol(&self, len: f64) -> f64 {
        match *self {
            Curve::Line { .. } => len,
            Curve::Circle { rad, .. } => len / rad,
        }
    }
}

/// The last programmed move's offset piece, whose end waits for the next move.
#[derive(Debug, Clone)]
struct Pending<T> {
    curve: Curve,
    /// Where the piece starts (fixed) and its parameter.
    start: V,
    s0: f64,
    /// Where it ends if nothing cuts it short (the offset of the programmed end) and its
    /// parameter.
    end: V,
    s1: f64,
    /// The programmed end, the unit direction of travel there and the signed curvature there
    /// (counter-clockwise positive).
    corner: V,
    tangent: V,
    kappa: f64,
    data: T,
    /// Payloads of moves without motion in the plane that came after it: they run at its end.
    tail: Vec<T>,
}

/// A programmed move turned into its offset piece, before its start is settled.
struct Next {
    curve: Curve,
    /// The offset of the programmed start and end, and the end's parameter (the start's is 0).
    start: V,
    end: V,
    s1: f64,
    /// Unit directions of travel at the programmed start and end, curvatures there.
    t_start: V,
    k_start: f64,
    t_end: V,
    k_end: f64,
}

/// How two moves meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Join {
    Tangent,
    Convex,
    Concave,
}

impl<T: Clone> Compensator<T> {
    /// Compensation starts with the tool's centre at `start`, on `side`, with `radius`.
    ///
    /// A negative radius swaps the side (as LinuxCNC does for a negative tool diameter); a
    /// zero radius passes every move through unchanged. A start or radius that is not finite
    /// makes every later call return an error.
    pub fn new(start: [f64; 2], side: Side, radius: f64) -> Self {
        let sign = match side {
            Side::Left => 1.0,
            Side::Right => -1.0,
        };
        let failed = if !finite(start) || !radius.is_finite() {
            Some(CompError(
                "cutter compensation: the start or the tool radius is not a finite number".into(),
            ))
        } else {
            None
        };
        Compensator {
            sign: if radius < 0.0 { -sign } else { sign },
            radius: radius.abs(),
            pos: start,
            scale: 1.0f64
                .max(start[0].abs())
                .max(start[1].abs())
                .max(radius.abs()),
            pending: None,
            failed,
        }
    }

    /// Where the last piece appended to an `out` ended (at first, `new`'s start).
    pub fn position(&self) -> [f64; 2] {
        self.pos
    }

    /// The side the tool runs on (after a negative radius's swap).
    pub fn side(&self) -> Side {
        if self.sign > 0.0 {
            Side::Left
        } else {
            Side::Right
        }
    }

    /// The tool radius (≥ 0).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    fn tol(&self) -> f64 {
        LEN_TOL * self.scale
    }

    fn fail<R>(&mut self, msg: &str) -> Result<R, CompError> {
        let e = CompError(msg.into());
        self.failed = Some(e.clone());
        Err(e)
    }

    /// The next programmed move and its payload. The first is the entry move. What is now
    /// known of the moves before it is appended to `out`: each piece with its `corner` flag
    /// (`true` for an arc added at a convex corner, which carries the payload of the move
    /// after the corner) and its payload.
    ///
    /// The pieces appended, over all calls, form a continuous path: each starts exactly where
    /// the one before ended, the first at `new`'s start. An [`Offset::Arc`] whose start and
    /// end coincide is a full circle; a programmed [`Piece::Arc`] whose end is within the
    /// length tolerance of its start is a full circle too.
    ///
    /// - The entry move (the first push) goes from the tool's centre. A line ends where the
    ///   line from the start touches the circle of `radius` about the programmed end, on the
    ///   tool's side: the tool is then tangent to the programmed end, perpendicular to the
    ///   entry line. It is an error unless the programmed end is farther than `radius` from
    ///   the start. An arc (LinuxCNC's convert_arc_comp1) ends at the programmed end moved by
    ///   `radius` along the arc's radius (toward the centre when the tool is inside the arc,
    ///   away when outside), about a new centre on that radius, equidistant from the start
    ///   and the new end: the tool arrives tangent to the programmed arc's end. It is an error
    ///   when the end is within `radius` of the start, or when the tool is inside an arc whose
    ///   radius is not larger than the tool's.
    /// - Every later move is offset by `radius` to the side: a line parallel, an arc about the
    ///   same centre with radius R + r (tool outside) or R − r (inside; an error unless
    ///   R − r is larger than the length tolerance).
    /// - Where two moves meet at an angle below [`ANGLE_TOL`], the offset pieces join
    ///   directly (the next one starts where the first ended). At a convex corner (the tool
    ///   on the outside) an arc about the programmed corner joins the two offsets' ends
    ///   (clockwise for G41, counter-clockwise for G42), flagged `corner`. At a concave
    ///   corner both offset pieces end at their intersection nearest the corner; an error
    ///   (gouge) when there is none on both pieces, that is when the tool does not fit the
    ///   corner or the previous or the next piece. At a reversal (a turn of π within
    ///   [`ANGLE_TOL`]) the side is the one the new move's curvature leaves toward, relative
    ///   to the old move; two lines, or moves along one circle, are a convex corner (the tool
    ///   goes round the end).
    /// - A move without motion in the plane (shorter than the length tolerance; a pure Z move)
    ///   comes out as a zero-length [`Offset::Line`] at the end of the piece before it.
    /// - Non-finite input, or numbers so large the geometry overflows, are errors. After an
    ///   error every call returns it again.
    pub fn push(
        &mut self,
        piece: Piece,
        data: T,
        out: &mut Vec<(Offset, bool, T)>,
    ) -> Result<(), CompError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let (end, centre) = match piece {
            Piece::Line { end } => (end, None),
            Piece::Arc { end, centre, ccw } => (end, Some((centre, ccw))),
        };
        if !finite(end) || centre.is_some_and(|(c, _)| !finite(c)) {
            return self.fail("cutter compensation: a move's coordinates are not finite numbers");
        }
        for v in [end[0], end[1]]
            .into_iter()
            .chain(centre.into_iter().flat_map(|(c, _)| c))
        {
            self.scale = self.scale.max(v.abs());
        }
        let mark = out.len();
        let r = self.push_inner(end, centre, data, out);
        let r = r.and_then(|()| {
            let bad = out[mark..].iter().any(|(o, _, _)| match *o {
                Offset::Line { start, end } => !finite(start) || !finite(end),
                Offset::Arc {
                    start, end, centre, ..
                } => !finite(start) || !finite(end) || !finite(centre),
            });
            let pend_bad = self
                .pending
                .as_ref()
                .is_some_and(|p| !finite(p.start) || !finite(p.end) || !p.s1.is_finite());
            if bad || pend_bad || !finite(self.pos) {
                Err(CompError(
                    "cutter compensation: the coordinates are too large to compute with".into(),
                ))
            } else {
                Ok(())
            }
        });
        if let Err(e) = &r {
            out.truncate(mark);
            self.failed = Some(e.clone());
        }
        r
    }

    fn push_inner(
        &mut self,
        end: V,
        centre: Option<(V, bool)>,
        data: T,
        out: &mut Vec<(Offset, bool, T)>,
    ) -> Result<(), CompError> {
        let tol = self.tol();
        if self.radius == 0.0 {
            let start = self.pos;
            let o = match centre {
                None => Offset::Line { start, end },
                Some((centre, ccw)) => {
                    let end = if norm(sub(end, start)) <= tol {
                        start
                    } else {
                        end
                    };
                    Offset::Arc {
                        start,
                        end,
                        centre,
                        ccw,
                    }
                }
            };
            out.push((o, false, data));
            self.pos = end;
            if let Some(Offset::Arc { end, .. }) = out.last().map(|x| x.0) {
                self.pos = end;
            }
            return Ok(());
        }
        let Some(mut prev) = self.pending.take() else {
            let p = self.entry(end, centre, data)?;
            self.pending = Some(p);
            return Ok(());
        };
        let from = prev.corner;
        let next = match self.offset(from, end, centre) {
            Ok(Some(n)) => n,
            Ok(None) => {
                prev.tail.push(data);
                self.pending = Some(prev);
                return Ok(());
            }
            Err(e) => {
                self.pending = Some(prev);
                return Err(e);
            }
        };
        let join = self.join(&prev, &next);
        let (start, s0) = match join {
            Join::Tangent => {
                let (e, s1) = (prev.end, prev.s1);
                (self.flush(prev, e, s1, out), 0.0)
            }
            Join::Convex => {
                let (e, s1, corner) = (prev.end, prev.s1, prev.corner);
                let e = self.flush(prev, e, s1, out);
                out.push((
                    Offset::Arc {
                        start: e,
                        end: next.start,
                        centre: corner,
                        ccw: self.sign < 0.0,
                    },
                    true,
                    data.clone(),
                ));
                self.pos = next.start;
                (next.start, 0.0)
            }
            Join::Concave => {
                let Some((x, sp, sn)) = self.meet(&prev, &next) else {
                    self.pending = Some(prev);
                    return Err(CompError(
                        "the tool would gouge: it does not fit the concave corner between two \
                         moves under cutter compensation"
                            .into(),
                    ));
                };
                (self.flush(prev, x, sp, out), sn)
            }
        };
        self.pending = Some(Pending {
            curve: next.curve,
            start,
            s0,
            end: next.end,
            s1: next.s1,
            corner: end,
            tangent: next.t_end,
            kappa: next.k_end,
            data,
            tail: Vec::new(),
        });
        Ok(())
    }

    /// The entry move's piece from the tool's centre.
    fn entry(
        &mut self,
        end: V,
        centre: Option<(V, bool)>,
        data: T,
    ) -> Result<Pending<T>, CompError> {
        let (r, s, tol) = (self.radius, self.sign, self.tol());
        let start = self.pos;
        match centre {
            None => {
                // The tangent from the start to the circle of radius r about the end: the
                // tangent point is at angle θ from the end-to-start direction, cos θ = r/d.
                let d = norm(sub(start, end));
                let len = ((d - r) * (d + r)).max(0.0).sqrt();
                if d <= r || len <= tol {
                    return self.fail(
                        "the tool would gouge: the first move after G41/G42 is shorter than \
                         the tool radius",
                    );
                }
                let u = mul(sub(start, end), 1.0 / d);
                let n = add(mul(u, r / d), mul(left(u), -s * len / d));
                let touch = add(end, mul(n, r));
                let t = mul(sub(touch, start), 1.0 / norm(sub(touch, start)));
                Ok(Pending {
                    curve: Curve::Line { p: start, t },
                    start,
                    s0: 0.0,
                    end: touch,
                    s1: norm(sub(touch, start)),
                    corner: end,
                    tangent: t,
                    kappa: 0.0,
                    data,
                    tail: Vec::new(),
                })
            }
            Some((c, ccw)) => {
                let dir = if ccw { 1.0 } else { -1.0 };
                let rad = norm(sub(end, c));
                let inside = dir == s;
                if norm(sub(end, start)) <= r {
                    return self.fail(
                        "the tool would gouge: the first move after G41/G42 (an arc) ends within \
                         the tool radius of its start",
                    );
                }
                if rad <= tol || norm(sub(start, c)) <= tol {
                    return self.fail("cutter compensation: an arc with zero radius");
                }
                if inside && rad <= r {
                    return self.fail(
                        "the tool does not fit inside the arc: its radius is not larger than the \
                         tool's",
                    );
                }
                // w: from the programmed end toward the centre; the tool ends r along it
                // (inside) or against it (outside).
                let w = mul(sub(c, end), 1.0 / rad);
                let e2 = add(end, mul(w, if inside { r } else { -r }));
                // The new centre e2 + k·w, as far from the start as from e2.
                let q = sub(start, e2);
                let den = 2.0 * dot(w, q);
                let k = dot(q, q) / den;
                if den.abs() <= tol || k <= tol || !k.is_finite() {
                    return self.fail(
                        "cutter compensation: the entry arc cannot be offset (its start is not \
                         on the tool's side of the arc)",
                    );
                }
                let c2 = add(e2, mul(w, k));
                let a0 = angle(sub(start, c2));
                let curve = Curve::Circle {
                    c: c2,
                    rad: k,
                    dir,
                    a0,
                };
                let s1 = curve.param(e2, 0.0);
                Ok(Pending {
                    curve,
                    start,
                    s0: 0.0,
                    end: e2,
                    s1,
                    corner: end,
                    tangent: mul(left(mul(w, -1.0)), dir),
                    kappa: dir / rad,
                    data,
                    tail: Vec::new(),
                })
            }
        }
    }

    /// A programmed move from `from` offset to the tool's side; `None` for no motion in the
    /// plane.
    fn offset(
        &mut self,
        from: V,
        end: V,
        centre: Option<(V, bool)>,
    ) -> Result<Option<Next>, CompError> {
        let (r, s, tol) = (self.radius, self.sign, self.tol());
        match centre {
            None => {
                let len = norm(sub(end, from));
                if len <= tol {
                    return Ok(None);
                }
                let t = mul(sub(end, from), 1.0 / len);
                let n = mul(left(t), s * r);
                let start = add(from, n);
                Ok(Some(Next {
                    curve: Curve::Line { p: start, t },
                    start,
                    end: add(end, n),
                    s1: len,
                    t_start: t,
                    k_start: 0.0,
                    t_end: t,
                    k_end: 0.0,
                }))
            }
            Some((c, ccw)) => {
                let dir = if ccw { 1.0 } else { -1.0 };
                let (rs, re) = (norm(sub(from, c)), norm(sub(end, c)));
                if rs <= tol || re <= tol {
                    return Err(CompError(
                        "cutter compensation: an arc with zero radius".into(),
                    ));
                }
                let inside = dir == s;
                let rad = if inside { re - r } else { re + r };
                if rad <= tol {
                    return Err(CompError(
                        "the tool does not fit inside the arc: its radius is not larger than \
                         the tool's"
                            .into(),
                    ));
                }
                let (us, ue) = (mul(sub(from, c), 1.0 / rs), mul(sub(end, c), 1.0 / re));
                // Outward radial times r for the tool outside, inward inside.
                let k = if inside { -r } else { r };
                let start = add(from, mul(us, k));
                let a0 = angle(us);
                let curve = Curve::Circle { c, rad, dir, a0 };
                let s1 = if norm(sub(end, from)) <= tol {
                    TAU
                } else {
                    let v = curve.param(add(c, ue), 0.0);
                    if v <= 0.0 {
                        TAU
                    } else {
                        v
                    }
                };
                Ok(Some(Next {
                    curve,
                    start,
                    end: add(end, mul(ue, k)),
                    s1,
                    t_start: mul(left(us), dir),
                    k_start: dir / re,
                    t_end: mul(left(ue), dir),
                    k_end: dir / re,
                }))
            }
        }
    }

    /// How the pending piece meets the next.
    fn join(&self, prev: &Pending<T>, next: &Next) -> Join {
        let (t1, t2) = (prev.tangent, next.t_start);
        let phi = cross(t1, t2).atan2(dot(t1, t2));
        if phi.abs() <= ANGLE_TOL {
            return Join::Tangent;
        }
        let turn = if PI - phi.abs() <= ANGLE_TOL {
            // A reversal: the new move leaves to the left of the old one reversed (a right
            // turn of π) when its curvature is larger than the reversed old one's.
            let k = prev.kappa + next.k_start;
            let scale = prev.kappa.abs().max(next.k_start.abs());
            if k.abs() <= 1e-9 * scale || k == 0.0 {
                return Join::Convex;
            }
            if k > 0.0 {
                -PI
            } else {
                PI
            }
        } else {
            phi
        };
        if self.sign * turn < 0.0 {
            Join::Convex
        } else {
            Join::Concave
        }
    }

    /// Where the pending piece and the next one's offset meet at a concave corner: the point
    /// and its parameters on both, or `None` if no intersection lies on both pieces.
    fn meet(&self, prev: &Pending<T>, next: &Next) -> Option<(V, f64, f64)> {
        let tol = self.tol();
        let cands = intersect(prev.curve, prev.end, next.curve, next.start, tol);
        let (tp, tn) = (prev.curve.ptol(tol), next.curve.ptol(tol));
        let mut best: Option<(f64, V, f64, f64)> = None;
        for x in cands.into_iter().flatten() {
            if !finite(x) {
                continue;
            }
            let sp = prev.curve.param(x, prev.s1 + tp - TAU);
            let sn = next.curve.param(x, -tn);
            if sp < prev.s0 - tp || sp > prev.s1 + tp || sn < -tn || sn > next.s1 + tn {
                continue;
            }
            let d = norm(sub(x, prev.end)) + norm(sub(x, next.start));
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, x, sp, sn));
            }
        }
        best.map(|(_, x, sp, sn)| (x, sp.max(prev.s0), sn.max(0.0)))
    }

    /// Appends the pending piece, ended at `x` (parameter `s`), and the moves without motion
    /// after it.
    fn flush(&mut self, p: Pending<T>, x: V, s: f64, out: &mut Vec<(Offset, bool, T)>) -> V {
        let tol = self.tol();
        let o = match p.curve {
            Curve::Line { .. } => Offset::Line {
                start: p.start,
                end: x,
            },
            Curve::Circle { c, rad, dir, .. } => {
                let sweep = s - p.s0;
                if sweep * rad <= tol && norm(sub(x, p.start)) <= tol {
                    Offset::Line {
                        start: p.start,
                        end: x,
                    }
                } else if sweep >= TAU - tol / rad && norm(sub(x, p.start)) <= tol {
                    // A full circle: it ends where it starts.
                    Offset::Arc {
                        start: p.start,
                        end: p.start,
                        centre: c,
                        ccw: dir > 0.0,
                    }
                } else {
                    Offset::Arc {
                        start: p.start,
                        end: x,
                        centre: c,
                        ccw: dir > 0.0,
                    }
                }
            }
        };
        let e = match o {
            Offset::Line { end, .. } | Offset::Arc { end, .. } => end,
        };
        out.push((o, false, p.data));
        for d in p.tail {
            out.push((Offset::Line { start: e, end: e }, false, d));
        }
        self.pos = e;
        e
    }

    /// Ends compensation (G40): the last move's pieces appended to `out`, its offset piece
    /// ending at the offset of its programmed end (the tool perpendicular to the path's end).
    /// Returns where the tool's centre is; the next move (the exit move) starts there. The
    /// compensator is then ready to start again from there (the next push is an entry move).
    pub fn finish(&mut self, out: &mut Vec<(Offset, bool, T)>) -> Result<[f64; 2], CompError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if let Some(p) = self.pending.take() {
            let (e, s1) = (p.end, p.s1);
            self.flush(p, e, s1, out);
        }
        Ok(self.pos)
    }
}

/// The intersections of two curves (at most two): `a` near `pa`, `b` near `pb` (points used
/// as the lines' bases, for conditioning). A near miss within `tol` counts as a touch.
fn intersect(a: Curve, pa: V, b: Curve, pb: V, tol: f64) -> [Option<V>; 2] {
    match (a, b) {
        (Curve::Line { t: t1, .. }, Curve::Line { t: t2, .. }) => {
            let c = cross(t1, t2);
            if c.abs() <= 1e-15 {
                return [None, None];
            }
            let u = cross(sub(pb, pa), t2) / c;
            [Some(add(pa, mul(t1, u))), None]
        }
        (Curve::Line { t, .. }, Curve::Circle { c, rad, .. }) => line_circle(pa, t, c, rad, tol),
        (Curve::Circle { c, rad, .. }, Curve::Line { t, .. }) => line_circle(pb, t, c, rad, tol),
        (Curve::Circle { c: c1, rad: r1, .. }, Curve::Circle { c: c2, rad: r2, .. }) => {
            let dv = sub(c2, c1);
            let d = norm(dv);
            if d <= 1e-15 * (r1 + r2) {
                return [None, None];
            }
            let e = mul(dv, 1.0 / d);
            let a = (d + (r1 - r2) * (r1 + r2) / d) / 2.0;
            let h2 = (r1 - a) * (r1 + a);
            let h = if h2 >= 0.0 {
                h2.sqrt()
            } else if h2 >= -tol * tol {
                0.0
            } else {
                return [None, None];
            };
            let m = add(c1, mul(e, a));
            [
                Some(add(m, mul(left(e), h))),
                Some(add(m, mul(left(e), -h))),
            ]
        }
    }
}

/// The intersections of the line through `p` along unit `t` with a circle.
fn line_circle(p: V, t: V, c: V, rad: f64, tol: f64) -> [Option<V>; 2] {
    let w = sub(p, c);
    let b = dot(w, t);
    let q = (norm(w) - rad) * (norm(w) + rad);
    let disc = b * b - q;
    let sq = if disc >= 0.0 {
        disc.sqrt()
    } else if disc >= -tol * tol {
        0.0
    } else {
        return [None, None];
    };
    // The stable pair of roots of u² + 2bu + q = 0.
    let u1 = -b - sq.copysign(b);
    let u2 = if u1 != 0.0 { q / u1 } else { 0.0 };
    [Some(add(p, mul(t, u1))), Some(add(p, mul(t, u2)))]
}

#[cfg(test)]
mod tests;
