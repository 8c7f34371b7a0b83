//! Canned cycles G73, G74, G81–G89, as LinuxCNC's `interp_cycles.cc` makes them,
//! in any of the three planes: `aa`, `bb` the plane's axes, `cc` its normal (Z in G17).
//!
//! | cycle | after the preliminary moves (at the hole, at R) |
//! | --- | --- |
//! | G81 | feed to the bottom, rapid to the clearance level |
//! | G82 | feed, dwell P, rapid out |
//! | G73 | pecks of Q: feed down, rapid up by the clearance D (default 1 mm); last feed; rapid out |
//! | G83 | pecks of Q: feed down, rapid to R, rapid back to the clearance D above the last depth; last feed; rapid out |
//! | G74/G84 | overrides off, feed, spindle stop, reverse, dwell P (if any), feed out, stop, original direction, overrides back |
//! | G85 | feed to the bottom, feed back to R, rapid out |
//! | G86 | feed, dwell P, spindle stop, rapid out, spindle restarted |
//! | G88 | feed, dwell P, spindle stop, pause (M0: LinuxCNC's manual retract), rapid out, spindle restarted |
//! | G89 | feed, dwell P, feed out |
//! | G87 | rapid to the offset point (I, J), oriented stop, rapid down to the bottom, rapid to the hole, spindle on, feed up to K, feed back to the bottom, oriented stop, rapid to the offset point, rapid up to the clearance level and to the hole, spindle on |
//!
//! G87 (back boring, LinuxCNC's form): I and J offset the point where the tool goes through the
//! hole from the hole (incremental always), K is the top of the back bore (absolute in G90,
//! from the bottom in G91); in G18/G19 the plane's axes take the letters of their axes (K and
//! I in G18, J and K in G19) and the normal's letter gives the top. The clearance level is
//! the initial level (G98) or R (G99); the initial level is kept while cycles follow each
//! other. Every move of a cycle runs in exact path mode (G61.1), as in LinuxCNC. The cycle's
//! points are work coordinates, each taken to the machine through the frame in effect, so in a
//! coordinate system rotated about Z (G10 L2 R) a G18 or G19 cycle turns with it: it drills
//! along the rotated Y or X axis.

use super::{err, gname, CompMode, FeedMode, Interp};
use crate::gcode::{Blend, Block, GCode, GcodeError, Op, OpKind, Pos, SpindleDir};

/// LinuxCNC's default peck clearance of G73 and G83 on a metric machine (mm).
const PECK_CLEARANCE_MM: f64 = 1.0;

/// The moves of one cycle, in work coordinates.
struct Cycle<'a> {
    it: &'a mut Interp,
    out: &'a mut Vec<Op>,
    line: usize,
    axes: (usize, usize, usize),
    /// Work position the cycle's points are made from (its A, B, C and the like).
    base: Pos,
}

impl Cycle<'_> {
    fn point(&self, a: f64, b: f64, c: f64) -> Pos {
        let mut p = self.base;
        p[self.axes.0] = a;
        p[self.axes.1] = b;
        p[self.axes.2] = c;
        p
    }

    fn rapid(&mut self, a: f64, b: f64, c: f64) {
        let end = self.it.machine(self.point(a, b, c));
        self.it.rapid(self.line, end, self.out);
    }

    fn feed(&mut self, a: f64, b: f64, c: f64) -> Result<(), GcodeError> {
        let end = self.it.machine(self.point(a, b, c));
        let start = self.it.position;
        let (lin, ang) = super::motion::distances(start, end);
        let blk = Block {
            line: self.line,
            ..Block::default()
        };
        let feed = self.it.feed_rate(&blk, lin, ang)?;
        self.out.push(Op {
            line: self.line,
            kind: OpKind::Feed {
                start,
                end,
                feed,
                blend: self.it.blend,
            },
        });
        self.it.position = end;
        Ok(())
    }

    fn dwell(&mut self, seconds: f64) {
        if seconds > 0.0 {
            self.out.push(Op {
                line: self.line,
                kind: OpKind::Dwell { seconds },
            });
        }
    }

    fn spindle(&mut self, dir: SpindleDir) {
        self.out.push(Op {
            line: self.line,
            kind: OpKind::Spindle {
                speed: self.it.speed,
                dir,
            },
        });
    }

    fn orient(&mut self, dir: SpindleDir) {
        self.out.push(Op {
            line: self.line,
            kind: OpKind::SpindleOrient { angle: 0.0, dir },
        });
    }

    fn overrides(&mut self, feed: bool, spindle: bool) {
        self.out.push(Op {
            line: self.line,
            kind: OpKind::Overrides { feed, spindle },
        });
    }
}

impl Interp {
    /// One block of a canned cycle `g` (its L repeats).
    pub(super) fn cycle(
        &mut self,
        b: &Block,
        g: GCode,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        let name = gname(g);
        match self.feed_mode {
            FeedMode::InverseTime => {
                return err(line, "canned cycles cannot run in inverse time mode (G93)")
            }
            FeedMode::PerMinute if self.feed_lin <= 0.0 => {
                return err(line, format!("{name} with a zero feed rate (no F given)"))
            }
            FeedMode::PerRevolution if self.feed_rev <= 0.0 => {
                return err(
                    line,
                    format!("{name} with a zero feed per revolution (no F given)"),
                )
            }
            _ => {}
        }
        if self.comp_mode != CompMode::Off {
            return err(
                line,
                "canned cycles cannot run with cutter radius compensation on",
            );
        }
        let same = self.motion == Some(g);
        let k = self.k();
        let (aa, bb, cc) = self.plane.axes();
        let letters = super::coords::AXES;
        let r_word = match b.word('R') {
            Some(r) => r * k,
            None if same => self.cycle.r,
            None => return err(line, format!("{name} needs R (the retract level)")),
        };
        let repeats = match b.word('L') {
            Some(l) => {
                let l = super::modal::int_word(line, 'L', l, 0.0)?;
                if l == 0 {
                    return err(line, format!("{name} L0: zero repeats of a cycle"));
                }
                l
            }
            None => 1,
        };
        let cc_word = match b.word(letters[cc]) {
            Some(v) => v * k,
            None if same => self.cycle.cc,
            None => {
                return err(
                    line,
                    format!("{name} needs {} (the bottom) the first time", letters[cc]),
                )
            }
        };
        let p = match b.word('P') {
            Some(p) if p < 0.0 => return err(line, format!("{name} P{p}: a negative dwell")),
            Some(p) => p,
            None if same || matches!(g, 740 | 840) => self.cycle.p,
            None if matches!(g, 820 | 860 | 880 | 890) => {
                return err(line, format!("{name} needs P (the dwell in seconds)"))
            }
            None => self.cycle.p,
        };
        let q = match b.word('Q') {
            Some(q) if q <= 0.0 => {
                return err(line, format!("{name} Q{q}: the peck must be positive"))
            }
            Some(q) => q * k,
            None if same || !matches!(g, 730 | 830) => self.cycle.q,
            None => return err(line, format!("{name} needs Q (the peck depth)")),
        };
        let clearance = b.word('D').map_or(PECK_CLEARANCE_MM, |d| d * k);
        // G87's offsets and top, by axis (I for X, J for Y, K for Z).
        let mut ijk = self.cycle.ijk;
        if g == 870 {
            let (pa, pb, pc) = self.plane.axes();
            for (i, c) in ['I', 'J', 'K'].into_iter().enumerate() {
                match b.word(c) {
                    Some(v) => ijk[i] = v * k,
                    None if !same && [pa, pb, pc].contains(&i) => {
                        return err(line, format!("{name} needs {c} the first time"))
                    }
                    None => {}
                }
            }
        }
        let spindle = self.dir;
        match g {
            840 if spindle != SpindleDir::Cw => {
                return err(line, "G84 needs the spindle turning clockwise (M3)")
            }
            740 if spindle != SpindleDir::Ccw => {
                return err(line, "G74 needs the spindle turning counter-clockwise (M4)")
            }
            860 | 870 | 880 if spindle == SpindleDir::Off => {
                return err(line, format!("{name} needs the spindle turning"))
            }
            _ => {}
        }

        let cur = self.cur_work();
        let mut current_cc = cur[cc];
        let mut old_cc = self.cycle.initial.unwrap_or(current_cc);
        let words = self.axis_words(b);
        let (mut a, mut bv, a_inc, b_inc, r, bottom);
        if self.absolute {
            a = words[aa].unwrap_or(cur[aa]);
            bv = words[bb].unwrap_or(cur[bb]);
            (a_inc, b_inc) = (0.0, 0.0);
            r = r_word;
            bottom = cc_word;
        } else {
            a = cur[aa];
            bv = cur[bb];
            a_inc = words[aa].unwrap_or(0.0);
            b_inc = words[bb].unwrap_or(0.0);
            r = r_word + old_cc;
            bottom = r + cc_word;
        }
        if r < bottom {
            return err(
                line,
                format!("{name}: R is below the bottom ({})", letters[cc]),
            );
        }
        let top = if self.absolute {
            ijk[cc]
        } else {
            bottom + ijk[cc]
        };
        self.cycle.initial = Some(old_cc);
        let saved_blend = self.blend;
        self.blend = Blend::ExactPath;
        let mut c = Cycle {
            it: self,
            out,
            line,
            axes: (aa, bb, cc),
            base: cur,
        };
        if old_cc < r {
            c.rapid(cur[aa], cur[bb], r);
            old_cc = r;
            current_cc = r;
        }
        let clear = if c.it.retract_r { r } else { old_cc };
        let result = (|| -> Result<(), GcodeError> {
            for n in 0..repeats {
                a += a_inc;
                bv += b_inc;
                if n == 0 && current_cc > r {
                    c.rapid(a, bv, current_cc);
                    c.rapid(a, bv, r);
                } else {
                    c.rapid(a, bv, clear);
                    if clear > r {
                        c.rapid(a, bv, r);
                    }
                }
                match g {
                    810 => {
                        c.feed(a, bv, bottom)?;
                        c.rapid(a, bv, clear);
                    }
                    820 => {
                        c.feed(a, bv, bottom)?;
                        c.dwell(p);
                        c.rapid(a, bv, clear);
                    }
                    730 | 830 => {
                        let mut depth = r - q;
                        while depth > bottom {
                            c.feed(a, bv, depth)?;
                            if g == 830 {
                                c.rapid(a, bv, r);
                            }
                            c.rapid(a, bv, depth + clearance);
                            depth -= q;
                        }
                        c.feed(a, bv, bottom)?;
                        c.rapid(a, bv, clear);
                    }
                    740 | 840 => {
                        let (fo, so) = (c.it.feed_override, c.it.spindle_override);
                        let (there, back) = if g == 840 {
                            (SpindleDir::Ccw, SpindleDir::Cw)
                        } else {
                            (SpindleDir::Cw, SpindleDir::Ccw)
                        };
                        c.overrides(false, false);
                        c.feed(a, bv, bottom)?;
                        c.spindle(SpindleDir::Off);
                        c.spindle(there);
                        c.dwell(p);
                        c.feed(a, bv, clear)?;
                        c.spindle(SpindleDir::Off);
                        c.spindle(back);
                        c.overrides(fo, so);
                    }
                    850 => {
                        c.feed(a, bv, bottom)?;
                        c.feed(a, bv, r)?;
                        c.rapid(a, bv, clear);
                    }
                    860 => {
                        c.feed(a, bv, bottom)?;
                        c.dwell(p);
                        c.spindle(SpindleDir::Off);
                        c.rapid(a, bv, clear);
                        c.spindle(spindle);
                    }
                    880 => {
                        c.feed(a, bv, bottom)?;
                        c.dwell(p);
                        c.spindle(SpindleDir::Off);
                        c.out.push(Op {
                            line,
                            kind: OpKind::Pause {
                                kind: crate::gcode::PauseKind::Program,
                            },
                        });
                        c.rapid(a, bv, clear);
                        c.spindle(spindle);
                    }
                    890 => {
                        c.feed(a, bv, bottom)?;
                        c.dwell(p);
                        c.feed(a, bv, clear)?;
                    }
                    870 => {
                        let (oa, ob) = (a + ijk[aa], bv + ijk[bb]);
                        c.rapid(oa, ob, r);
                        c.orient(spindle);
                        c.rapid(oa, ob, bottom);
                        c.rapid(a, bv, bottom);
                        c.spindle(spindle);
                        c.feed(a, bv, top)?;
                        c.feed(a, bv, bottom)?;
                        c.orient(spindle);
                        c.rapid(oa, ob, bottom);
                        c.rapid(oa, ob, clear);
                        c.rapid(a, bv, clear);
                        c.spindle(spindle);
                    }
                    _ => return err(line, format!("{name} is not a canned cycle")),
                }
            }
            Ok(())
        })();
        self.blend = saved_blend;
        result?;
        self.cycle.r = r_word;
        self.cycle.cc = cc_word;
        self.cycle.p = p;
        self.cycle.q = q;
        self.cycle.ijk = ijk;
        Ok(())
    }
}
