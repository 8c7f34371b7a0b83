//! The path report's view of a G-code program: the X, Y, Z geometry of its motions (lines,
//! arcs and helices, splines as fine polylines), dwells and outputs, as [`Block`]s. The
//! program is read by the SDK's interpreter ([`crate::gcode`]): its canonical
//! operations become blocks here ([`blocks_of`]), for [`super`] (the path report) and `mcctl run`.

use crate::gcode::{Blend, GcodeError, Op, OpKind, Options, Plane, Pos};

/// One block in machine terms. `line` is the 1-based source line; positions are absolute
/// mm, feeds mm/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Block {
    /// A straight move. `feed` is `f64::INFINITY` for a rapid (the runner picks the rapid feed).
    Line {
        /// The source line.
        line: usize,
        /// G0.
        rapid: bool,
        /// Where it starts and ends.
        start: [f64; 3],
        /// See `start`.
        end: [f64; 3],
        /// mm/s.
        feed: f64,
    },
    /// A circular arc in `plane`, with the plane's normal axis moving linearly from `start`
    /// to `end` (a helix when they differ). `centre` is absolute; its normal coordinate is
    /// the start's. Start and end coinciding in the plane make a full turn.
    Arc {
        /// The source line.
        line: usize,
        /// Where it starts and ends.
        start: [f64; 3],
        /// See `start`.
        end: [f64; 3],
        /// The centre.
        centre: [f64; 3],
        /// G17, G18 or G19.
        plane: Plane,
        /// G3.
        ccw: bool,
        /// mm/s.
        feed: f64,
    },
    /// An arc in a plane that is not the plane of two machine axes (G18/G19 in a coordinate
    /// system rotated about Z: [`OpKind::ArcNormal`]): about `centre`, in the plane through
    /// `start` with normal `normal`, counter-clockwise about it when `ccw`; the end's height
    /// above that plane along the normal is a helix's rise. Start and end coinciding in the
    /// plane make a full turn.
    ArcNormal {
        /// The source line.
        line: usize,
        /// Where it starts and ends.
        start: [f64; 3],
        /// See `start`.
        end: [f64; 3],
        /// The centre (taken into the plane through the start).
        centre: [f64; 3],
        /// The plane's normal (any length but 0).
        normal: [f64; 3],
        /// Counter-clockwise about `normal`.
        ccw: bool,
        /// mm/s.
        feed: f64,
    },
    /// G4: wait `seconds`.
    Dwell {
        /// The source line.
        line: usize,
        /// How long.
        seconds: f64,
    },
    /// M62–M65: digital output `bit` on or off, `synced` with the start of the next motion
    /// (M62/M63) or at once (M64/M65).
    Output {
        /// The source line.
        line: usize,
        /// The card output.
        bit: u8,
        /// On (M62, M64) or off.
        on: bool,
        /// M62/M63.
        synced: bool,
    },
}

/// An arc's geometry ([`Block::arc_geom`]): the point at parameter t in [0, 1] is
/// `centre + radius·(cos(t·sweep)·u + sin(t·sweep)·v) + t·rise·axis`, `axis` the direction the
/// arc turns counter-clockwise about (a G2 arc's is its plane's normal reversed), `u` from the
/// centre toward the start.
pub type ArcGeom = crate::gcode::ArcFrame;

/// The circle from `start` about `centre` counter-clockwise about `normal` (`ccw`; else
/// clockwise) to `end`, whose height above the start's plane is a rise.
fn arc_frame(
    start: [f64; 3],
    end: [f64; 3],
    centre: [f64; 3],
    normal: [f64; 3],
    ccw: bool,
) -> Option<ArcGeom> {
    let pos = |p: [f64; 3]| [p[0], p[1], p[2], 0.0, 0.0, 0.0];
    OpKind::ArcNormal {
        start: pos(start),
        end: pos(end),
        centre,
        normal,
        ccw,
        turns: 0,
        feed: 0.0,
        blend: Blend::ExactStop,
    }
    .normal_arc_frame()
}

impl Block {
    /// The 1-based source line.
    pub fn line(&self) -> usize {
        match *self {
            Block::Line { line, .. }
            | Block::Arc { line, .. }
            | Block::ArcNormal { line, .. }
            | Block::Dwell { line, .. }
            | Block::Output { line, .. } => line,
        }
    }

    /// Whether the block moves (a line or an arc).
    pub fn is_motion(&self) -> bool {
        matches!(
            self,
            Block::Line { .. } | Block::Arc { .. } | Block::ArcNormal { .. }
        )
    }

    /// Start of a motion block.
    pub fn start(&self) -> Option<[f64; 3]> {
        match *self {
            Block::Line { start, .. }
            | Block::Arc { start, .. }
            | Block::ArcNormal { start, .. } => Some(start),
            _ => None,
        }
    }

    /// End of a motion block.
    pub fn end(&self) -> Option<[f64; 3]> {
        match *self {
            Block::Line { end, .. } | Block::Arc { end, .. } | Block::ArcNormal { end, .. } => {
                Some(end)
            }
            _ => None,
        }
    }

    /// The geometry of an arc block (`None` for the others, or an arc of no radius).
    pub fn arc_geom(&self) -> Option<ArcGeom> {
        match *self {
            Block::Arc {
                start,
                end,
                centre,
                plane,
                ccw,
                ..
            } => {
                let mut normal = [0.0; 3];
                normal[plane.axes().2] = 1.0;
                arc_frame(start, end, centre, normal, ccw)
            }
            Block::ArcNormal {
                start,
                end,
                centre,
                normal,
                ccw,
                ..
            } => arc_frame(start, end, centre, normal, ccw),
            _ => None,
        }
    }

    /// Path length (mm) of a motion block; 0 for the others.
    pub fn length(&self) -> f64 {
        match *self {
            Block::Line { start, end, .. } => dist(start, end),
            Block::Arc { .. } | Block::ArcNormal { .. } => {
                self.arc_geom().map_or(0.0, |g| g.length())
            }
            _ => 0.0,
        }
    }

    /// The point a fraction `f` (clamped to [0, 1]) of the way along a motion block (by
    /// length); `None` for a dwell or an output.
    pub fn point_at(&self, f: f64) -> Option<[f64; 3]> {
        let f = f.clamp(0.0, 1.0);
        match *self {
            Block::Line { start, end, .. } => {
                Some(std::array::from_fn(|i| start[i] + f * (end[i] - start[i])))
            }
            Block::Arc { .. } | Block::ArcNormal { .. } => self.arc_geom().map(|g| g.point(f)),
            _ => None,
        }
    }

    /// The programmed feed (mm/s) of a motion block (`INFINITY` for a rapid).
    pub fn feed(&self) -> Option<f64> {
        match *self {
            Block::Line { feed, .. } | Block::Arc { feed, .. } | Block::ArcNormal { feed, .. } => {
                Some(feed)
            }
            _ => None,
        }
    }
}

/// A parsed program.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Blocks {
    /// In program order.
    pub blocks: Vec<Block>,
    /// Moves no longer than [`ZERO_LENGTH`](crate::gcode::ZERO_LENGTH), dropped.
    pub dropped_zero_length: usize,
}

impl Blocks {
    /// How many blocks move (lines and arcs).
    pub fn motion_count(&self) -> usize {
        self.blocks.iter().filter(|b| b.is_motion()).count()
    }

    /// Total programmed path length (mm), rapids included.
    pub fn length(&self) -> f64 {
        self.blocks.iter().map(Block::length).sum()
    }
}

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Parses `text`, starting at the origin.
pub fn parse(text: &str) -> Result<Blocks, GcodeError> {
    parse_from(text, [0.0; 3])
}

/// Parses `text`, starting at `start` (mm), through the SDK's interpreter: every operation's
/// blocks ([`blocks_of`]).
pub fn parse_from(text: &str, start: [f64; 3]) -> Result<Blocks, GcodeError> {
    let opts = Options {
        start: [start[0], start[1], start[2], 0.0, 0.0, 0.0],
        ..Options::default()
    };
    let mut p = Blocks::default();
    for op in crate::gcode::Program::from_text(text, &opts) {
        let op = op?;
        if op.kind.is_null_motion() {
            p.dropped_zero_length += 1;
            continue;
        }
        blocks_of(&op, &mut p.blocks);
    }
    Ok(p)
}

/// Points a spline is sampled at for its polyline.
pub const SPLINE_SAMPLES: usize = 256;

fn xyz(p: &Pos) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// The blocks of one operation, appended to `out`: a line for a rapid, a feed, a probe or a
/// spindle-synchronised move; an arc a turn for an arc with extra turns (the turns first, as
/// the card runs them); [`SPLINE_SAMPLES`] lines for a spline; a dwell; an output. Other
/// operations have none.
pub fn blocks_of(op: &Op, out: &mut Vec<Block>) {
    let line = op.line;
    match &op.kind {
        OpKind::Rapid { start, end, .. } => out.push(Block::Line {
            line,
            rapid: true,
            start: xyz(start),
            end: xyz(end),
            feed: f64::INFINITY,
        }),
        OpKind::Feed {
            start, end, feed, ..
        }
        | OpKind::Probe {
            start, end, feed, ..
        } => out.push(Block::Line {
            line,
            rapid: false,
            start: xyz(start),
            end: xyz(end),
            feed: *feed,
        }),
        OpKind::SpindleSync { start, end, .. } => out.push(Block::Line {
            line,
            rapid: false,
            start: xyz(start),
            end: xyz(end),
            feed: f64::INFINITY,
        }),
        OpKind::Arc {
            start,
            end,
            centre,
            plane,
            ccw,
            turns,
            feed,
            ..
        } => {
            let total = op.kind.arc_sweep().unwrap_or(std::f64::consts::TAU);
            let n = plane.axes().2;
            let arc = |start: [f64; 3], end: [f64; 3]| Block::Arc {
                line,
                start,
                end,
                centre: *centre,
                plane: *plane,
                ccw: *ccw,
                feed: *feed,
            };
            // The full turns first, each back where the arc started in its plane, the normal
            // axis moved by its share (as the runner sends them).
            let mut from = xyz(start);
            for k in 1..=*turns {
                let mut to = xyz(start);
                to[n] =
                    start[n] + f64::from(k) * std::f64::consts::TAU / total * (end[n] - start[n]);
                out.push(arc(from, to));
                from = to;
            }
            out.push(arc(from, xyz(end)));
        }
        OpKind::ArcNormal {
            start,
            end,
            centre,
            normal,
            ccw,
            turns,
            feed,
            ..
        } => {
            let total = op.kind.arc_sweep().unwrap_or(std::f64::consts::TAU);
            let rise = op
                .kind
                .normal_arc_frame()
                .map_or([0.0; 3], |f| f.axis.map(|x| x * f.rise));
            let arc = |start: [f64; 3], end: [f64; 3]| Block::ArcNormal {
                line,
                start,
                end,
                centre: *centre,
                normal: *normal,
                ccw: *ccw,
                feed: *feed,
            };
            // The full turns first, each back above where the arc started, by its share of the
            // rise (as the runner sends them).
            let mut from = xyz(start);
            for k in 1..=*turns {
                let share = f64::from(k) * std::f64::consts::TAU / total;
                let to = std::array::from_fn(|i| start[i] + share * rise[i]);
                out.push(arc(from, to));
                from = to;
            }
            out.push(arc(from, xyz(end)));
        }
        OpKind::Spline {
            start,
            end,
            spline,
            feed,
            ..
        } => {
            let pts: Vec<f64> = spline.points.iter().flat_map(xyz).collect();
            let curve = crate::Nurbs::new(spline.degree, 3, &pts, &spline.weights, &spline.knots);
            let mut from = xyz(start);
            let mut line_to = |to: [f64; 3]| {
                out.push(Block::Line {
                    line,
                    rapid: false,
                    start: from,
                    end: to,
                    feed: *feed,
                });
                from = to;
            };
            if let Ok(c) = curve {
                let (u0, u1) = c.domain();
                for i in 1..SPLINE_SAMPLES {
                    let u = u0 + (u1 - u0) * i as f64 / SPLINE_SAMPLES as f64;
                    let (p, _, _) = c.eval_clamped(u);
                    line_to([p[0], p[1], p[2]]);
                }
            }
            line_to(xyz(end));
        }
        OpKind::Dwell { seconds } => out.push(Block::Dwell {
            line,
            seconds: *seconds,
        }),
        OpKind::Output {
            index, on, synced, ..
        } => out.push(Block::Output {
            line,
            bit: u8::try_from(*index).unwrap_or(u8::MAX),
            on: *on,
            synced: *synced,
        }),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn blocks(text: &str) -> Vec<Block> {
        parse(text).unwrap_or_else(|e| panic!("{e}")).blocks
    }

    #[test]
    fn a_full_circle_is_one_arc_of_a_whole_turn() {
        let b = blocks("G0 X10\nG2 X10 Y0 I-10 F60\n");
        assert_eq!(b.len(), 2);
        let g = b[1].arc_geom().unwrap();
        // clockwise: a whole turn about −Z
        assert!((g.sweep - 2.0 * PI).abs() < 1e-12 && g.axis == [0.0, 0.0, -1.0]);
        assert!((b[1].length() - 20.0 * PI).abs() < 1e-9);
        assert!((dist(b[1].point_at(0.25).unwrap(), [0.0, -10.0, 0.0])) < 1e-9);
    }

    #[test]
    fn extra_turns_are_an_arc_a_turn_the_helix_shared_by_angle() {
        // A quarter turn plus two whole turns (P3), Z falling 9 mm over the 2.25 turns.
        let b = blocks("G0 X10\nG3 X0 Y10 Z-9 I-10 P3 F60\n");
        assert_eq!(b.len(), 4);
        let total = 2.25 * 2.0 * PI;
        for (k, blk) in b[1..3].iter().enumerate() {
            let end = blk.end().unwrap();
            let z = -9.0 * (k as f64 + 1.0) * 2.0 * PI / total;
            assert!(dist(end, [10.0, 0.0, z]) < 1e-9, "turn {k}: {end:?}");
        }
        assert!(dist(b[3].end().unwrap(), [0.0, 10.0, -9.0]) < 1e-12);
        let length: f64 = b[1..].iter().map(Block::length).sum();
        assert!(
            (length - (10.0 * total).hypot(9.0)).abs() < 1e-9,
            "{length}"
        );
    }

    #[test]
    fn a_spline_is_a_polyline_on_its_curve() {
        // G5.1: the quadratic from (0,0) with control point (5,10) to (10,0).
        let b = blocks("G1 X0 Y0 F60\nG5.1 X10 Y0 I5 J10\n");
        assert_eq!(b.len(), SPLINE_SAMPLES);
        assert!(dist(b.last().unwrap().end().unwrap(), [10.0, 0.0, 0.0]) < 1e-12);
        // The apex of the parabola, halfway: (5, 5).
        let mid = b[SPLINE_SAMPLES / 2 - 1].end().unwrap();
        assert!(dist(mid, [5.0, 5.0, 0.0]) < 1e-9, "{mid:?}");
    }

    #[test]
    fn null_moves_are_counted_not_kept() {
        let p = parse("G0 X0 Y0\nG1 X5 F60\nX5\nG91 X0\nG90 G0 X5.0000001\nG0 X6\n").unwrap();
        assert_eq!(p.dropped_zero_length, 4);
        assert_eq!(p.motion_count(), 2);
    }

    #[test]
    fn example_programs_parse() {
        let square = parse(include_str!("../../../examples/gcode/square.ngc")).unwrap();
        assert_eq!(square.motion_count(), 5);
        let cuts: Vec<_> = square
            .blocks
            .iter()
            .filter(|b| !matches!(b, Block::Line { rapid: true, .. }))
            .collect();
        assert_eq!(cuts.len(), 4);
        assert!(cuts
            .iter()
            .all(|b| b.feed() == Some(50.0) && (b.length() - 50.0).abs() < 1e-12));
        for text in [
            include_str!("../../../examples/gcode/part.ngc"),
            include_str!("../../../examples/gcode/zigzag.ngc"),
        ] {
            let p = parse(text).unwrap();
            assert!(p.motion_count() > 10 && p.length() > 0.0);
        }
    }
}
