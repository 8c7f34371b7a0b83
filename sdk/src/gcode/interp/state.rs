//! The modal state as a whole: LinuxCNC's predefined named parameters (`#<_x>`,
//! `#<_motion_mode>`, …) published after each block, and M70–M73, which save the modal state
//! of the current call level and restore it (M72, or M73's automatic restore when the
//! subroutine that saved it returns).
//!
//! What is saved, as LinuxCNC's M70: units, plane, distance and arc distance modes, feed mode
//! and F, S and the spindle's direction, coolant, the override switches, the coordinate
//! system, the retract mode and the path control mode. Not saved (as LinuxCNC): the motion
//! mode and the position; nor (unlike LinuxCNC) tool length offset and cutter compensation,
//! which stay as they are.

use super::{err, FeedMode, Interp, Plane, Units};
use crate::gcode::{Blend, GcodeError, Op, OpKind, Params, SpindleDir};

/// The modal state M70 saves.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Saved {
    /// The call level it was saved at.
    level: usize,
    /// M73: restored when that level's subroutine returns.
    auto: bool,
    units: Units,
    plane: Plane,
    absolute: bool,
    arc_absolute: bool,
    feed_mode: FeedMode,
    feed: (f64, f64, f64),
    speed: f64,
    dir: SpindleDir,
    coolant: (bool, bool),
    overrides: (bool, bool),
    cs: u32,
    retract_r: bool,
    blend: Blend,
}

impl Interp {
    /// LinuxCNC's predefined named parameters (`#<_x>`, `#<_motion_mode>`, …) after a
    /// block (`_line` is the reader's).
    pub(super) fn publish_predefined(&self, params: &mut Params) {
        use crate::gcode::Predefined as P;
        let flag = |b: bool| f64::from(u8::from(b));
        let cs = [540, 550, 560, 570, 580, 590, 591, 592, 593];
        let pocket = |n: u32| {
            let t = self.tools.tools.iter().find(|t| t.number == n);
            t.map_or(0.0, |t| f64::from(t.pocket))
        };
        let feed = match self.feed_mode {
            FeedMode::PerMinute => self.feed_ang,
            FeedMode::PerRevolution => self.feed_rev / self.k(),
            FeedMode::InverseTime => 0.0,
        };
        let depth = params.depth() as f64;
        let values = [
            (P::Vmajor, 2.0),
            (P::Vminor, 9.0),
            (P::MotionMode, f64::from(self.motion.unwrap_or(800))),
            (
                P::Plane,
                match self.plane {
                    Plane::Xy => 170.0,
                    Plane::Zx => 180.0,
                    Plane::Yz => 190.0,
                },
            ),
            (P::Ccomp, f64::from(self.comp_code)),
            (P::Metric, flag(self.units == Units::Mm)),
            (P::Imperial, flag(self.units == Units::Inch)),
            (P::Absolute, flag(self.absolute)),
            (P::Incremental, flag(!self.absolute)),
            (
                P::InverseTime,
                flag(self.feed_mode == FeedMode::InverseTime),
            ),
            (
                P::UnitsPerMinute,
                flag(self.feed_mode == FeedMode::PerMinute),
            ),
            (
                P::UnitsPerRev,
                flag(self.feed_mode == FeedMode::PerRevolution),
            ),
            (
                P::CoordSystem,
                f64::from(cs[(self.cs as usize).clamp(1, 9) - 1]),
            ),
            (P::ToolOffset, flag(self.tlo_code != 490)),
            (P::RetractRPlane, flag(self.retract_r)),
            (P::RetractOldZ, flag(!self.retract_r)),
            (P::SpindleRpmMode, 1.0),
            (P::SpindleCssMode, 0.0),
            (P::IjkAbsoluteMode, flag(self.arc_absolute)),
            (P::LatheDiameterMode, 0.0),
            (P::LatheRadiusMode, 0.0),
            (P::SpindleOn, flag(self.dir != SpindleDir::Off)),
            (P::SpindleCw, flag(self.dir == SpindleDir::Cw)),
            (P::Mist, flag(self.mist)),
            (P::Flood, flag(self.flood)),
            (P::SpeedOverride, flag(self.spindle_override)),
            (P::FeedOverride, flag(self.feed_override)),
            (P::AdaptiveFeed, 0.0),
            (P::FeedHold, 0.0),
            (P::Feed, feed),
            (P::Rpm, self.speed),
            (P::CurrentTool, f64::from(self.tool)),
            (P::CurrentPocket, pocket(self.tool)),
            (P::SelectedTool, f64::from(self.selected)),
            (P::SelectedPocket, pocket(self.selected)),
            (P::CallLevel, depth),
            (P::RemapLevel, 0.0),
            (P::Task, 1.0),
        ];
        for (p, v) in values {
            params.set_predefined(p, 0, v);
        }
        let (work, machine) = (self.cur_work(), self.position);
        for i in 0..9 {
            let v = match work.get(i) {
                Some(v) if i < 3 => v / self.k(),
                Some(v) => *v,
                None => 0.0,
            };
            params.set_predefined(P::X, i, v);
        }
        for (i, v) in machine.iter().enumerate() {
            let v = if i < 3 { v / self.k() } else { *v };
            params.set_predefined(P::AbsX, i, v);
        }
    }

    /// M70–M73 at call level `level`.
    pub(super) fn modal_save(
        &mut self,
        line: usize,
        m: u32,
        params: &mut Params,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        let level = params.depth();
        match m {
            70 | 73 => {
                self.saved.retain(|s| s.level < level);
                self.saved.push(Saved {
                    level,
                    auto: m == 73,
                    units: self.units,
                    plane: self.plane,
                    absolute: self.absolute,
                    arc_absolute: self.arc_absolute,
                    feed_mode: self.feed_mode,
                    feed: (self.feed_lin, self.feed_ang, self.feed_rev),
                    speed: self.speed,
                    dir: self.dir,
                    coolant: (self.mist, self.flood),
                    overrides: (self.feed_override, self.spindle_override),
                    cs: self.cs,
                    retract_r: self.retract_r,
                    blend: self.blend,
                });
            }
            71 => self.saved.retain(|s| s.level != level),
            _ => {
                let Some(i) = self.saved.iter().position(|s| s.level == level) else {
                    return err(
                        line,
                        "M72: no modal state was saved (M70) at this call level",
                    );
                };
                let s = self.saved[i].clone();
                self.restore(line, &s, params, out);
            }
        }
        Ok(())
    }

    /// M73's restores of the call levels that have returned (before the block of `line`).
    pub(super) fn auto_restore(&mut self, line: usize, params: &mut Params, out: &mut Vec<Op>) {
        let level = params.depth();
        while self.saved.last().is_some_and(|s| s.level > level) {
            if let Some(s) = self.saved.pop() {
                if s.auto {
                    self.restore(line, &s, params, out);
                }
            }
        }
    }

    fn restore(&mut self, line: usize, s: &Saved, params: &mut Params, out: &mut Vec<Op>) {
        self.units = s.units;
        self.plane = s.plane;
        self.absolute = s.absolute;
        self.arc_absolute = s.arc_absolute;
        self.feed_mode = s.feed_mode;
        (self.feed_lin, self.feed_ang, self.feed_rev) = s.feed;
        self.retract_r = s.retract_r;
        self.blend = s.blend;
        if self.cs != s.cs {
            self.cs = s.cs;
            self.load_coordinate_system(params);
            params.set(5220, f64::from(s.cs));
        }
        if (self.speed, self.dir) != (s.speed, s.dir) {
            (self.speed, self.dir) = (s.speed, s.dir);
            self.spindle_op(line, out);
        }
        if (self.mist, self.flood) != s.coolant {
            (self.mist, self.flood) = s.coolant;
            out.push(Op {
                line,
                kind: OpKind::Coolant {
                    mist: self.mist,
                    flood: self.flood,
                },
            });
        }
        if (self.feed_override, self.spindle_override) != s.overrides {
            (self.feed_override, self.spindle_override) = s.overrides;
            out.push(Op {
                line,
                kind: OpKind::Overrides {
                    feed: self.feed_override,
                    spindle: self.spindle_override,
                },
            });
        }
        self.publish_position(params);
    }
}
