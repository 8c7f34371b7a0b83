//! Motion: G0, G1, G2/G3, G33/G33.1, G38.x, with G53, feed modes and cutter compensation.

use super::coords::{rotate, Frame};
use super::modal::Line;
use super::{err, gname, FeedMode, Interp, Payload, PendingProbe, Units};
use crate::gcode::comp::Piece;
use crate::gcode::{Blend, Block, GCode, GcodeError, Op, OpKind, Plane, Pos};
use std::f64::consts::PI;

/// Two points closer than this in the plane (mm) are the same point (LinuxCNC's
/// `TOLERANCE_EQUAL`): an arc between them is a full turn.
pub(super) const SAME_POINT_MM: f64 = 1e-6;

/// LinuxCNC's tolerances for arcs (`interp_internal.hh`), in program units: the largest
/// difference between the radius at the start and at the end (`CENTER_ARC_RADIUS_TOLERANCE`),
/// and the smallest radius (`RADIUS_TOLERANCE`, also the slack of an R arc's chord check).
fn arc_tolerances(units: Units) -> (f64, f64) {
    match units {
        Units::Inch => (2.0 * 0.001 * std::f64::consts::SQRT_2, 0.00005),
        Units::Mm => (2.0 * 0.01 * std::f64::consts::SQRT_2, 0.00005 * 25.4),
    }
}
/// Relative tolerance of the radii (LinuxCNC's `SPIRAL_RELATIVE_TOLERANCE`).
const RADIUS_REL_TOLERANCE: f64 = 0.001;

/// Linear (X Y Z, mm) and angular (A B C, degrees) distance between two positions.
pub(super) fn distances(a: Pos, b: Pos) -> (f64, f64) {
    let d = |r: std::ops::Range<usize>| r.map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
    (d(0..3), d(3..6))
}

/// Sweep angle (radians, > 0) from `s` to `e` about `c`, counter-clockwise or not, in plane
/// coordinates; a full turn when the ends coincide.
pub(super) fn sweep(s: [f64; 2], e: [f64; 2], c: [f64; 2], ccw: bool) -> f64 {
    if (e[0] - s[0]).hypot(e[1] - s[1]) < SAME_POINT_MM {
        return 2.0 * PI;
    }
    let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
    let a1 = (e[1] - c[1]).atan2(e[0] - c[0]);
    let mut d = if ccw { a1 - a0 } else { a0 - a1 };
    while d <= 0.0 {
        d += 2.0 * PI;
    }
    while d > 2.0 * PI {
        d -= 2.0 * PI;
    }
    d
}

impl Interp {
    /// The feed (mm/s, or deg/s for rotary axes alone) of a feed move of `lin` mm and `ang`
    /// degrees.
    pub(super) fn feed_rate(&self, b: &Block, lin: f64, ang: f64) -> Result<f64, GcodeError> {
        let line = b.line;
        match self.feed_mode {
            FeedMode::InverseTime => {
                let Some(f) = b.word('F') else {
                    return err(
                        line,
                        "a feed move in inverse time mode (G93) needs F on its line",
                    );
                };
                if f <= 0.0 {
                    return err(line, format!("F{f} in inverse time mode (G93)"));
                }
                let len = if lin > 0.0 { lin } else { ang };
                Ok(len * f / 60.0)
            }
            FeedMode::PerMinute => {
                let f = if lin > 0.0 || ang == 0.0 {
                    self.feed_lin
                } else {
                    self.feed_ang
                };
                if f <= 0.0 {
                    return err(line, "a feed move with a zero feed rate (no F given)");
                }
                Ok(f / 60.0)
            }
            FeedMode::PerRevolution => {
                if self.feed_rev <= 0.0 {
                    return err(
                        line,
                        "a feed move with a zero feed per revolution (no F given)",
                    );
                }
                if self.speed <= 0.0 {
                    return err(line, "feed per revolution (G95) with spindle speed S0");
                }
                Ok(self.feed_rev * self.speed / 60.0)
            }
        }
    }

    /// The motion of the line (`g` its motion code).
    pub(super) fn motion(
        &mut self,
        b: &Block,
        l: &Line,
        g: GCode,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        if !self.nurbs.is_empty() && g != 52 {
            return err(
                line,
                format!(
                    "{} between G5.2 and G5.3 (control points from line {})",
                    gname(g),
                    self.nurbs_line
                ),
            );
        }
        match g {
            0 | 10 if l.group(0) == Some(530) => self.machine_move(b, g == 0, out)?,
            0 | 10 => self.straight(b, g == 0, out)?,
            20 | 30 => self.arc(b, g == 30, out)?,
            50 | 51 => self.spline(b, g == 51, out)?,
            52 => self.nurbs_point(b)?,
            330 | 331 => self.spindle_sync(b, g == 331, out)?,
            382..=385 => self.probe(b, g, out)?,
            800 => {}
            _ => self.cycle(b, g, out)?,
        }
        self.set_motion_mode(g);
        Ok(())
    }

    /// G53 G0/G1: the axis words are machine coordinates, on this line only.
    fn machine_move(
        &mut self,
        b: &Block,
        rapid: bool,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        self.no_comp(b.line, "use G53")?;
        let w = self.axis_words(b);
        let end: Pos = std::array::from_fn(|i| w[i].unwrap_or(self.position[i]));
        self.line_to(b, rapid, end, out)
    }

    /// A straight move from here to `end` (machine).
    fn line_to(
        &mut self,
        b: &Block,
        rapid: bool,
        end: Pos,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let start = self.position;
        let kind = if rapid {
            OpKind::Rapid {
                start,
                end,
                blend: self.blend,
            }
        } else {
            let (lin, ang) = distances(start, end);
            OpKind::Feed {
                start,
                end,
                feed: self.feed_rate(b, lin, ang)?,
                blend: self.blend,
            }
        };
        out.push(Op { line: b.line, kind });
        self.position = end;
        Ok(())
    }

    /// G0 / G1.
    fn straight(&mut self, b: &Block, rapid: bool, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let end = self.target(b);
        if self.comp.is_some() {
            let (a, bb, _) = self.plane.axes();
            let start = self.cur_work();
            let (lin, ang) = distances(start, end);
            let feed = if rapid {
                self.feed_lin / 60.0
            } else {
                self.feed_rate(b, lin, ang)?
            };
            return self.comp_push(
                b.line,
                Piece::Line {
                    end: [end[a], end[bb]],
                },
                Payload {
                    line: b.line,
                    rapid,
                    feed,
                    blend: self.blend,
                    end,
                    frame: self.frame(),
                },
                out,
            );
        }
        let end = self.frame().to_machine(end);
        self.line_to(b, rapid, end, out)
    }

    /// G2 / G3.
    fn arc(&mut self, b: &Block, ccw: bool, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        let (a, bb, n) = self.plane.axes();
        let offs = ['I', 'J', 'K'];
        if let Some(v) = b.word(offs[n]) {
            return err(
                line,
                format!(
                    "{}{v}: not a centre offset in the {} plane",
                    offs[n],
                    plane_name(self.plane)
                ),
            );
        }
        let start = self.cur_work();
        let mut end = self.target(b);
        let turns = match b.word('P') {
            Some(p) => p.round() as u32 - 1,
            None => 0,
        };
        let k = self.k();
        let (abs_tol, r_tol) = arc_tolerances(self.units);
        let (abs_tol, r_tol) = (abs_tol * k, r_tol * k);
        let s = [start[a], start[bb]];
        let e = [end[a], end[bb]];
        let chord = (e[0] - s[0]).hypot(e[1] - s[1]);
        let ij = (b.word(offs[a]), b.word(offs[bb]));
        let centre = match (b.word('R'), ij) {
            (Some(_), (Some(_), _) | (_, Some(_))) => {
                return err(line, "an arc with both R and a centre (I, J, K)")
            }
            (None, (None, None)) => {
                return err(
                    line,
                    format!("an arc needs R or the centre ({}, {})", offs[a], offs[bb]),
                )
            }
            (Some(r), _) => {
                let r = r * k;
                if chord < 1e-9 {
                    return err(
                        line,
                        "an R arc whose end is its start (use I, J, K for a circle)",
                    );
                }
                let half = chord / 2.0;
                let ar = r.abs();
                if half - ar > r_tol {
                    return err(
                        line,
                        format!(
                            "R{} is too small to reach the end point (half the chord is {:.6})",
                            r / k,
                            half / k
                        ),
                    );
                }
                let h = (ar * ar - half * half).max(0.0).sqrt();
                let u = [(e[0] - s[0]) / chord, (e[1] - s[1]) / chord];
                let left = [-u[1], u[0]];
                // The short arc turns about a centre on its inside: right of the chord for
                // G2, left for G3; a negative R takes the other one.
                let side = if ccw == (r > 0.0) { 1.0 } else { -1.0 };
                let m = [(s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0];
                [m[0] + side * h * left[0], m[1] + side * h * left[1]]
            }
            (None, (i, j)) => {
                let (i, j) = (i.unwrap_or(0.0) * k, j.unwrap_or(0.0) * k);
                let c = if self.arc_absolute {
                    [i, j]
                } else {
                    [s[0] + i, s[1] + j]
                };
                let r0 = (s[0] - c[0]).hypot(s[1] - c[1]);
                let r1 = (e[0] - c[0]).hypot(e[1] - c[1]);
                if r0 < r_tol || r1 < r_tol {
                    return err(
                        line,
                        format!(
                            "a zero-radius arc (radius {:.6} at the start, {:.6} at the end)",
                            r0 / k,
                            r1 / k
                        ),
                    );
                }
                let abs_err = (r0 - r1).abs();
                let rel_err = abs_err / r0.max(r1);
                if abs_err > 100.0 * abs_tol
                    || (rel_err > RADIUS_REL_TOLERANCE && abs_err > abs_tol)
                {
                    return err(
                        line,
                        format!(
                            "the radius to the end of the arc ({:.6}) differs from the radius to \
                             its start ({:.6}) by {:.6}",
                            r1 / k,
                            r0 / k,
                            abs_err / k
                        ),
                    );
                }
                if chord < SAME_POINT_MM {
                    end[a] = start[a];
                    end[bb] = start[bb];
                    c
                } else {
                    // Onto the chord's perpendicular bisector: an exact circle through both
                    // ends.
                    let u = [(e[0] - s[0]) / chord, (e[1] - s[1]) / chord];
                    let m = [(s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0];
                    let along = (c[0] - m[0]) * u[0] + (c[1] - m[1]) * u[1];
                    [c[0] - along * u[0], c[1] - along * u[1]]
                }
            }
        };
        let e = [end[a], end[bb]];
        let radius = (s[0] - centre[0]).hypot(s[1] - centre[1]);
        let theta = sweep(s, e, centre, ccw) + 2.0 * PI * turns as f64;
        let along = radius * theta;
        let normal = end[n] - start[n];
        let lin = if n < 3 { along.hypot(normal) } else { along };
        let (_, ang) = distances(start, end);
        if self.comp.is_some() {
            if turns > 0 {
                return err(
                    line,
                    "an arc of more than one turn (P) with cutter radius compensation",
                );
            }
            let feed = self.feed_rate(b, lin, ang)?;
            return self.comp_push(
                line,
                Piece::Arc {
                    end: e,
                    centre,
                    ccw,
                },
                Payload {
                    line,
                    rapid: false,
                    feed,
                    blend: self.blend,
                    end,
                    frame: self.frame(),
                },
                out,
            );
        }
        let feed = self.feed_rate(b, lin, ang)?;
        let start_m = self.position;
        let (kind, end_m) = arc_op(
            self.frame(),
            self.plane,
            (start_m, end),
            centre,
            (ccw, turns),
            (feed, self.blend),
        );
        out.push(Op { line, kind });
        self.position = end_m;
        Ok(())
    }

    /// G33 / G33.1.
    fn spindle_sync(&mut self, b: &Block, tap: bool, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        self.no_comp(line, "use G33/G33.1")?;
        if tap && b.word('I').is_some() {
            return err(
                line,
                "G33.1 with I (retract speed multiplier) is not supported",
            );
        }
        let pitch = b.word('K').unwrap_or(0.0) * self.k();
        if pitch <= 0.0 {
            return err(line, "G33/G33.1 need a positive pitch K");
        }
        let start = self.position;
        let end = self.frame().to_machine(self.target(b));
        out.push(Op {
            line,
            kind: OpKind::SpindleSync {
                start,
                end,
                pitch,
                tap,
            },
        });
        // A rigid tap comes back along its line.
        self.position = if tap { start } else { end };
        Ok(())
    }

    /// G38.2–G38.5.
    fn probe(&mut self, b: &Block, g: GCode, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        self.no_comp(line, "probe")?;
        if self.feed_mode == FeedMode::InverseTime {
            return err(line, "a probe move in inverse time mode (G93)");
        }
        let start = self.position;
        let end = self.frame().to_machine(self.target(b));
        let (lin, ang) = distances(start, end);
        if ang > 0.0 {
            return err(line, "a probe move may not move A, B or C");
        }
        if lin < SAME_POINT_MM {
            return err(line, "a probe move that ends where it starts");
        }
        let feed = self.feed_rate(b, lin, ang)?;
        let must_trip = g == 382 || g == 384;
        out.push(Op {
            line,
            kind: OpKind::Probe {
                start,
                end,
                feed,
                toward: g <= 383,
                must_trip,
            },
        });
        self.position = end;
        self.probe = Some(PendingProbe {
            end,
            must_trip,
            line,
            answered: None,
        });
        Ok(())
    }

    /// A work position on the machine, through the frame in effect.
    pub(super) fn machine(&self, w: Pos) -> Pos {
        self.frame().to_machine(w)
    }
}

/// The operation of an arc through `frame` (work → machine) from `ends.0` (machine) to
/// `ends.1` (work) about `centre` (the plane's two coordinates, work), and its end in machine
/// coordinates. In a plane of two machine axes (no rotation, or G17: a rotation about Z keeps
/// the XY plane) an [`OpKind::Arc`] (its centre's normal coordinate the start's); otherwise
/// (G18, G19 in a coordinate system rotated about Z) an [`OpKind::ArcNormal`]: the centre in
/// the plane through the start, the normal the plane's normal axis turned by the rotation.
pub(super) fn arc_op(
    frame: Frame,
    plane: Plane,
    ends: (Pos, Pos),
    centre: [f64; 2],
    (ccw, turns): (bool, u32),
    (feed, blend): (f64, Blend),
) -> (OpKind, Pos) {
    let (start, end_w) = ends;
    let (a, b, n) = plane.axes();
    let mut cw = frame.to_work(start);
    cw[a] = centre[0];
    cw[b] = centre[1];
    let cm = frame.to_machine(cw);
    let end = frame.to_machine(end_w);
    let mut c3 = [cm[0], cm[1], cm[2]];
    if frame.rotation == 0.0 || plane == Plane::Xy {
        c3[n] = start[n];
        let kind = OpKind::Arc {
            start,
            end,
            centre: c3,
            plane,
            ccw,
            turns,
            feed,
            blend,
        };
        return (kind, end);
    }
    let mut axis = [0.0; 6];
    axis[n] = 1.0;
    let nm = rotate(axis, frame.rotation);
    let normal = [nm[0], nm[1], nm[2]];
    // (the work centre has the start's normal coordinate: the machine one is in the plane
    // through the start, to the rounding of the transform, which the card takes up)
    let kind = OpKind::ArcNormal {
        start,
        end,
        centre: c3,
        normal,
        ccw,
        turns,
        feed,
        blend,
    };
    (kind, end)
}

/// "XY" (G17), "XZ" (G18), "YZ" (G19).
pub(super) fn plane_name(p: Plane) -> &'static str {
    match p {
        Plane::Xy => "XY (G17)",
        Plane::Zx => "XZ (G18)",
        Plane::Yz => "YZ (G19)",
    }
}
