//! Cutter radius compensation wired to [`crate::gcode::comp::Compensator`]: G40–G42,
//! G41.1/G42.1, and the compensated pieces as operations.
//!
//! While compensation runs (radius > 0), G0/G1/G2/G3 in the plane go to the compensator as
//! [`Piece`]s, each with a [`Payload`] (line, rapid or feed, feed rate, blend, and the
//! programmed end in work coordinates). What comes out becomes operations: the plane's
//! coordinates from the piece, the other axes (normal axis, A B C) from the payload's end,
//! and a corner arc keeps them still. The program's position is the programmed one
//! ([`CompRun::prog`]); the machine's lags one move behind until G40 (or M2/M30, or the end
//! of the text) calls `finish`. Offsets, coordinate system and plane cannot change while it
//! runs; the tool length can (G43/G49): each payload carries the work → machine frame of
//! its move.

use super::{err, gname, CompMode, CompRun, Interp, Payload};
use crate::gcode::comp::{Compensator, Offset, Piece, Side};
use crate::gcode::{Block, GCode, GcodeError, Op, OpKind, Plane};

impl Interp {
    /// G40, G41, G42, G41.1, G42.1.
    pub(super) fn set_comp(
        &mut self,
        b: &Block,
        g: GCode,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        if g == 400 {
            self.comp_off(line, out)?;
            self.comp_mode = CompMode::Off;
            self.comp_code = 400;
            return Ok(());
        }
        if self.comp_mode != CompMode::Off {
            return err(
                line,
                format!(
                    "{} while cutter radius compensation is on: G40 first",
                    gname(g)
                ),
            );
        }
        if self.plane == Plane::Yz {
            return err(
                line,
                "cutter radius compensation is allowed only in the XY (G17) and XZ (G18) planes",
            );
        }
        let side = if g == 410 || g == 411 {
            Side::Left
        } else {
            Side::Right
        };
        let radius = if g == 411 || g == 421 {
            let Some(d) = b.word('D') else {
                return err(line, format!("{} needs D (the tool diameter)", gname(g)));
            };
            if d < 0.0 {
                return err(line, format!("{} D{d}: a negative diameter", gname(g)));
            }
            d * self.k() / 2.0
        } else {
            let n = match b.word('D') {
                Some(d) => super::modal::int_word(line, 'D', d, 0.0)?,
                None => self.tool,
            };
            if n == 0 {
                0.0
            } else {
                match self.tools.tools.iter().find(|t| t.number == n) {
                    Some(t) => t.diameter / 2.0,
                    None => return err(line, format!("tool D{n} is not in the tool table")),
                }
            }
        };
        if radius < 0.0 {
            return err(line, "a negative tool diameter in the tool table");
        }
        self.comp_mode = CompMode::On { side, radius };
        self.comp_code = g;
        if radius > 0.0 {
            let w = self.cur_work();
            let (a, bb, _) = self.plane.axes();
            self.comp = Some(CompRun {
                engine: Compensator::new([w[a], w[bb]], side, radius),
                prog: w,
            });
        }
        Ok(())
    }

    /// G40 (and the end): the compensator's last pieces, then the machine is where it says.
    pub(super) fn comp_off(&mut self, line: usize, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        self.comp_mode = CompMode::Off;
        self.comp_code = 400;
        let Some(mut run) = self.comp.take() else {
            return Ok(());
        };
        let mut pieces = Vec::new();
        let centre = run
            .engine
            .finish(&mut pieces)
            .map_err(|e| GcodeError::new(line, format!("cutter compensation: {}", e.0)))?;
        self.emit_pieces(pieces, out)?;
        // The exit move starts where the tool's centre is: the last piece's end.
        let w = self.frame().to_work(self.position);
        let (a, b, _) = self.plane.axes();
        if (w[a] - centre[0]).hypot(w[b] - centre[1]) > 1e-6 {
            return err(
                line,
                format!(
                    "cutter compensation ends at ({:.6}, {:.6}), not at its last piece's end \
                     ({:.6}, {:.6})",
                    centre[0], centre[1], w[a], w[b]
                ),
            );
        }
        Ok(())
    }

    /// A programmed move through the compensator.
    pub(super) fn comp_push(
        &mut self,
        line: usize,
        piece: Piece,
        pay: Payload,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let end = pay.end;
        let run: &mut CompRun = self.comp.as_mut().expect("called with compensation on");
        let mut pieces = Vec::new();
        run.engine
            .push(piece, pay, &mut pieces)
            .map_err(|e| GcodeError::new(line, format!("cutter compensation: {}", e.0)))?;
        run.prog = end;
        self.emit_pieces(pieces, out)
    }

    /// The compensator's pieces as operations: the plane's coordinates from the piece, the
    /// other axes from the programmed move (still during a corner arc).
    pub(super) fn emit_pieces(
        &mut self,
        pieces: Vec<(Offset, bool, Payload)>,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let (a, bb, _) = self.plane.axes();
        for (piece, corner, pay) in pieces {
            let frame = pay.frame;
            let start = self.position;
            let mut end_w = if corner {
                frame.to_work(start)
            } else {
                pay.end
            };
            let plane_end = match piece {
                Offset::Line { end, .. } | Offset::Arc { end, .. } => end,
            };
            end_w[a] = plane_end[0];
            end_w[bb] = plane_end[1];
            let end = frame.to_machine(end_w);
            let kind = match piece {
                Offset::Line { .. } if pay.rapid => OpKind::Rapid {
                    start,
                    end,
                    blend: pay.blend,
                },
                Offset::Line { .. } => OpKind::Feed {
                    start,
                    end,
                    feed: pay.feed,
                    blend: pay.blend,
                },
                Offset::Arc { centre, ccw, .. } => {
                    if pay.feed <= 0.0 {
                        return err(
                            pay.line,
                            "a corner arc of cutter compensation on a rapid needs a feed rate (F)",
                        );
                    }
                    let (kind, _) = super::motion::arc_op(
                        frame,
                        self.plane,
                        (start, end_w),
                        centre,
                        (ccw, 0),
                        (pay.feed, pay.blend),
                    );
                    kind
                }
            };
            out.push(Op {
                line: pay.line,
                kind,
            });
            self.position = end;
        }
        Ok(())
    }
}
