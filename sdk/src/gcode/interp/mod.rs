//! The interpreter: evaluated blocks → canonical operations in machine coordinates, with the
//! modal state of RS274/NGC as LinuxCNC runs it for a mill.
//!
//! # What is understood
//!
//! | codes | notes |
//! | --- | --- |
//! | G0 G1 | G0/G1 without axis words only set the mode |
//! | G2 G3 | I J K (G91.1 from the start, G90.1 absolute) or R (negative: the long arc); P turns; LinuxCNC's radius tolerances; the centre moved onto the chord's bisector; start = end is a full turn |
//! | G4 | P seconds |
//! | G5 G5.1 G5.2/G5.3 | XY plane only; Bézier pieces and NURBS ([`crate::gcode::Spline`]) |
//! | G10 L1 L2 L10 L20 | tool table (the interpreter's copy), coordinate systems with R (rotation about Z) |
//! | G17 G18 G19 | arcs, cycles and compensation (G17, G18) in every one |
//! | G20 G21 G90 G91 G90.1 G91.1 G93 G94 G95 | |
//! | G28 G28.1 G30 G30.1 | through the axis words' point, then home for the named axes (all when none) |
//! | G33 G33.1 | K pitch |
//! | G38.2–G38.5 | see [`Interp::probe_result`] |
//! | G40 G41 G42 G41.1 G42.1 | through [`crate::gcode::comp::Compensator`] |
//! | G43 G43.1 G43.2 G49 | |
//! | G52 G53 G54–G59.3 G92 G92.1 G92.2 G92.3 | |
//! | G61 G61.1 G64 P Q | |
//! | G73 G74 G80–G89 G98 G99 | see `canned` |
//! | G97 | (G96 refused) |
//! | M0 M1 M2 M30 M60 M3 M4 M5 M6 M61 M7 M8 M9 M19 M48–M51 M62–M68 M70–M73 M100–M199 | M52, M53 refused |
//!
//! Anything else (G7, G8, G12, G76, G96, U V W words, …) is an error naming its line, as is
//! a word no code on its line uses (LinuxCNC's rules). Moves of length zero are emitted as
//! programmed.
//!
//! # Coordinates
//!
//! Inside, every length is in mm and every angle in degrees, whatever G20/G21 says; program
//! units are converted on the way in (axis words, I J K, R, F, P/Q of G64 …) and on the way
//! out to the parameters that report program coordinates (#5061–#5069, #5420–#5428,
//! #5401–#5409, #5410). The parameters that store offsets and positions (#5161–#5186,
//! #5211–#5219, #5221–#5410 of the coordinate systems) hold machine units, mm, as LinuxCNC's
//! "user units" on a metric machine.
//!
//! A program (work) position `p` is at machine position `R(p + g92) + origin + tool`: the G92
//! offset, then the coordinate system's rotation about Z (its R word) and its origin, then the
//! tool offset ([`coords::Frame`]). The interpreter's truth is the machine position; the
//! program position is derived from it, so changing an offset never moves the machine. A
//! rotation keeps G17 arcs in the machine's XY plane; a G18 or G19 arc in a rotated system
//! is in an oblique plane and becomes an [`OpKind::ArcNormal`] about the plane's normal
//! turned into the machine (`motion::arc_op`).
//!
//! # Order of execution within a line
//!
//! LinuxCNC's: message, feed mode (G93–G95), F, S, T, I/O (M62–M68), M6/M61, M3–M5, M7–M9,
//! M48–M53, M100–M199, G4, G17–G19, G20/G21, G40–G42, G43/G49, G54–G59.3, G61/G64,
//! G90/G91, G98/G99, G10/G28/G30/G52/G92, motion (with G53), M0/M1/M2/M30/M60. As in
//! LinuxCNC, F is taken before G20/G21 on the same line (`G20 F10` is 10 mm/min) and a feed
//! keeps its physical speed when the units change.

mod canned;
mod coords;
mod cutter;
mod geom;
mod modal;
mod motion;
mod spline;
mod state;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_comp;
#[cfg(test)]
mod tests_more;
#[cfg(test)]
mod tests_rotated;

use super::comp::{Compensator, Side};
use super::{Blend, Block, Flow, GCode, GcodeError, Op, OpKind, Params, Plane, Pos, SpindleDir};
use super::{PauseKind, ToolTable};
use coords::Frame;

/// The machine the program runs on, and the switches an operator sets.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Options {
    /// Where the machine is at the start (machine coordinates).
    pub start: Pos,
    /// The tool table.
    pub tools: ToolTable,
    /// Lines starting with `/` are skipped.
    pub block_delete: bool,
    /// M1 pauses.
    pub optional_stop: bool,
    /// Where `o<name> call` looks for `name.ngc` when the program does not define
    /// `o<name> sub` itself (LinuxCNC's `SUBROUTINE_PATH`), in order. [`super::Program::open`]
    /// adds the program file's own directory after these.
    pub subroutine_path: Vec<std::path::PathBuf>,
}

/// Length units of the program (G20, G21).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// G20.
    Inch,
    /// G21.
    Mm,
}

impl Units {
    /// mm per program unit.
    pub fn mm(self) -> f64 {
        match self {
            Units::Inch => 25.4,
            Units::Mm => 1.0,
        }
    }
}

/// Feed rate mode (G93, G94, G95).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedMode {
    /// G93: F is the inverse of the move's time in minutes, on every feed move.
    InverseTime,
    /// G94: units (or degrees) per minute.
    PerMinute,
    /// G95: units per spindle revolution.
    PerRevolution,
}

/// Cutter radius compensation in effect (G40, G41, G42, G41.1, G42.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CompMode {
    /// G40.
    Off,
    /// G41/G42 (G41.1/G42.1): `side`, tool `radius` in mm.
    On {
        /// Which side of the path.
        side: Side,
        /// Tool radius (mm); 0 runs the programmed path.
        radius: f64,
    },
}

/// What travels through the compensator with each programmed move.
#[derive(Debug, Clone)]
struct Payload {
    line: usize,
    rapid: bool,
    /// mm/s (deg/s); for a rapid, the feed in effect (used only by a corner arc).
    feed: f64,
    blend: Blend,
    /// The programmed end, work coordinates.
    end: Pos,
    /// Work → machine when the move was programmed (the tool length may change while
    /// compensation runs).
    frame: Frame,
}

/// Compensation running with a non-zero radius.
#[derive(Debug, Clone)]
struct CompRun {
    engine: Compensator<Payload>,
    /// The programmed position (work coordinates): where the next move starts as the program
    /// sees it; the machine is at the compensated point, one move behind.
    prog: Pos,
}

/// A probe move emitted and not yet answered by [`Interp::probe_result`].
#[derive(Debug, Clone, Copy)]
struct PendingProbe {
    end: Pos,
    must_trip: bool,
    line: usize,
    answered: Option<bool>,
}

/// What canned cycles remember between blocks (LinuxCNC's `cycle_*`).
#[derive(Debug, Clone, Copy, Default)]
struct CycleMemory {
    /// Initial level (normal axis, work mm) while cycles repeat block after block.
    initial: Option<f64>,
    /// R as last programmed (program value converted to mm; incremental in G91).
    r: f64,
    /// The normal-axis word as last programmed (mm; incremental in G91).
    cc: f64,
    p: f64,
    q: f64,
    /// G87's I, J, K as last programmed (mm; by axis X, Y, Z).
    ijk: [f64; 3],
}

/// The modal state and the position.
#[derive(Debug, Clone)]
pub struct Interp {
    /// Machine position (what the ops have reached).
    position: Pos,
    units: Units,
    plane: Plane,
    absolute: bool,
    arc_absolute: bool,
    feed_mode: FeedMode,
    /// G94 feed: linear in mm/min, angular in deg/min (F as given).
    feed_lin: f64,
    feed_ang: f64,
    /// G95 feed, mm per revolution.
    feed_rev: f64,
    speed: f64,
    dir: SpindleDir,
    mist: bool,
    flood: bool,
    feed_override: bool,
    spindle_override: bool,
    tools: ToolTable,
    tool: u32,
    selected: u32,
    tool_offset: Pos,
    tlo_code: GCode,
    /// Coordinate system 1..=9 (G54..G59.3).
    cs: u32,
    origin: Pos,
    rotation: f64,
    g92: Pos,
    blend: Blend,
    /// G-code of the motion mode; `None` after G80 (and at the start).
    motion: Option<GCode>,
    /// G99 (retract to R) rather than G98.
    retract_r: bool,
    optional_stop: bool,
    cycle: CycleMemory,
    /// The last G5's P and Q negated (the next G5's default I and J), mm.
    spline_ij: [f64; 2],
    /// G5.2 control points collected (work plane coordinates, weight) and the order.
    nurbs: Vec<([f64; 2], f64)>,
    nurbs_order: usize,
    nurbs_line: usize,
    comp_mode: CompMode,
    comp_code: GCode,
    comp: Option<CompRun>,
    probe: Option<PendingProbe>,
    /// M70/M73 saves, by call level (innermost last).
    saved: Vec<state::Saved>,
}

/// A feed mode word check etc. helper: an error at `line`.
pub(crate) fn err<T>(line: usize, message: impl Into<String>) -> Result<T, GcodeError> {
    Err(GcodeError::new(line, message))
}

/// `G38.2` for 382, `G1` for 10.
pub(crate) fn gname(g: GCode) -> String {
    if g.is_multiple_of(10) {
        format!("G{}", g / 10)
    } else {
        format!("G{}.{}", g / 10, g % 10)
    }
}

impl Interp {
    /// A program starting as LinuxCNC starts one (G17 G21 G40 G49 G54 G64 G80 G90 G91.1 G94
    /// G97 G99 M5 M9), at `opts.start`; the parameters it keeps (#5220, …) set.
    pub fn new(opts: &Options, params: &mut Params) -> Self {
        let mut it = Interp {
            position: opts.start,
            units: Units::Mm,
            plane: Plane::Xy,
            absolute: true,
            arc_absolute: false,
            feed_mode: FeedMode::PerMinute,
            feed_lin: 0.0,
            feed_ang: 0.0,
            feed_rev: 0.0,
            speed: 0.0,
            dir: SpindleDir::Off,
            mist: false,
            flood: false,
            feed_override: true,
            spindle_override: true,
            tools: opts.tools.clone(),
            tool: 0,
            selected: 0,
            tool_offset: [0.0; 6],
            tlo_code: 490,
            cs: 1,
            origin: [0.0; 6],
            rotation: 0.0,
            g92: [0.0; 6],
            blend: Blend::Blended {
                tolerance: None,
                naive: None,
            },
            motion: None,
            retract_r: true,
            optional_stop: opts.optional_stop,
            cycle: CycleMemory::default(),
            spline_ij: [0.0; 2],
            nurbs: Vec::new(),
            nurbs_order: 3,
            nurbs_line: 0,
            comp_mode: CompMode::Off,
            comp_code: 400,
            comp: None,
            probe: None,
            saved: Vec::new(),
        };
        params.set(5220, 1.0);
        it.load_coordinate_system(params);
        it.load_g92(params);
        it.publish_tool(params);
        it.publish_position(params);
        it.publish_predefined(params);
        it
    }

    /// One block: its operations appended to `out`.
    pub fn block(
        &mut self,
        b: &Block,
        params: &mut Params,
        out: &mut Vec<Op>,
    ) -> Result<Flow, GcodeError> {
        self.settle_probe(b.line, params)?;
        self.auto_restore(b.line, params, out);
        let line = modal::check(self, b)?;
        let flow = self.execute(b, &line, params, out)?;
        self.publish_tool(params);
        self.publish_position(params);
        self.publish_predefined(params);
        Ok(flow)
    }

    /// The end of the text (`line`: its last line) without M2/M30: what is pending is
    /// flushed (cutter compensation's last move).
    pub fn finish(
        &mut self,
        line: usize,
        params: &mut Params,
        out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        self.settle_probe(line, params)?;
        if !self.nurbs.is_empty() {
            return err(
                line,
                format!(
                    "the program ends with G5.2 control points (from line {}) not ended by G5.3",
                    self.nurbs_line
                ),
            );
        }
        self.comp_off(line, out)?;
        self.publish_position(params);
        Ok(())
    }

    /// The last probe's result: where the probe tripped (`at`, its end if it did not) and
    /// where the motion came to rest (`stopped`, a little past `at` when it tripped), machine
    /// coordinates. #5061–#5070 report `at`; the program goes on from `stopped`.
    pub fn probe_result(&mut self, at: Pos, stopped: Pos, tripped: bool, params: &mut Params) {
        // Settled at once so the position and #5061–#5070 are right for the caller; a
        // G38.2/G38.4 that did not trip is reported at the next block.
        if let Some(p) = self.probe {
            self.apply_probe(at, stopped, tripped, params);
            self.probe = (!tripped && p.must_trip).then_some(PendingProbe {
                answered: Some(tripped),
                ..p
            });
        }
    }

    /// The current position (machine coordinates).
    pub fn position(&self) -> Pos {
        self.position
    }

    /// The current position in the active work coordinates (mm, degrees): the programmed
    /// position while cutter compensation runs.
    pub fn work_position(&self) -> Pos {
        self.cur_work()
    }

    /// G20 or G21.
    pub fn units(&self) -> Units {
        self.units
    }

    /// G17, G18 or G19.
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// G90 (`true`) or G91.
    pub fn absolute(&self) -> bool {
        self.absolute
    }

    /// G90.1 (`true`) or G91.1.
    pub fn arc_absolute(&self) -> bool {
        self.arc_absolute
    }

    /// G93, G94 or G95.
    pub fn feed_mode(&self) -> FeedMode {
        self.feed_mode
    }

    /// The coordinate system: 1 (G54) to 9 (G59.3).
    pub fn coordinate_system(&self) -> u32 {
        self.cs
    }

    /// The tool in the spindle (after M6 or M61).
    pub fn tool(&self) -> u32 {
        self.tool
    }

    /// The interpreter's tool table: [`Options::tools`] as G10 L1/L10 left it.
    pub fn tool_table(&self) -> &ToolTable {
        &self.tools
    }

    /// The tool selected by the last T.
    pub fn selected_tool(&self) -> u32 {
        self.selected
    }

    /// The tool offset in effect (mm, degrees; G43/G43.1/G43.2, zero after G49).
    pub fn tool_offset(&self) -> Pos {
        self.tool_offset
    }

    /// The path control mode (G61, G61.1, G64).
    pub fn blend(&self) -> Blend {
        self.blend
    }

    /// The motion mode as a G code in tenths (`None` after G80 and at the start).
    pub fn motion_mode(&self) -> Option<GCode> {
        self.motion
    }

    /// Cutter radius compensation.
    pub fn comp_mode(&self) -> CompMode {
        self.comp_mode
    }

    /// The G code of cutter radius compensation in effect (400 for G40, 411 for G41.1, …).
    pub fn comp_code(&self) -> GCode {
        self.comp_code
    }

    /// The G code of the tool length offset in effect (490 for G49, 430, 431, 432).
    pub fn tool_length_code(&self) -> GCode {
        self.tlo_code
    }

    /// G98 (`false`: back to the initial level) or G99 (`true`: to R).
    pub fn retract_to_r(&self) -> bool {
        self.retract_r
    }

    /// Spindle speed (rpm) and direction.
    pub fn spindle(&self) -> (f64, SpindleDir) {
        (self.speed, self.dir)
    }

    /// The work → machine transform in effect.
    fn frame(&self) -> Frame {
        Frame {
            origin: self.origin,
            rotation: self.rotation,
            g92: self.g92,
            tool: self.tool_offset,
        }
    }

    /// The program's position (work coordinates, mm).
    fn cur_work(&self) -> Pos {
        match &self.comp {
            Some(c) => c.prog,
            None => self.frame().to_work(self.position),
        }
    }

    /// mm per program unit.
    fn k(&self) -> f64 {
        self.units.mm()
    }

    /// #5420–#5428: the position in the active work coordinates, program units.
    fn publish_position(&self, params: &mut Params) {
        let w = self.cur_work();
        for (i, v) in w.iter().enumerate() {
            let v = if i < 3 { v / self.k() } else { *v };
            params.set(5420 + i as u32, v);
        }
        for n in 5426..=5428 {
            params.set(n, 0.0);
        }
    }

    /// #5400 tool number, #5401–#5409 its table offsets (program units), #5410 diameter.
    fn publish_tool(&self, params: &mut Params) {
        params.set(5400, self.tool as f64);
        let t = self.tools.tools.iter().find(|t| t.number == self.tool);
        let (off, dia) = t.map_or(([0.0; 6], 0.0), |t| (t.offset, t.diameter));
        for (i, v) in off.iter().enumerate() {
            let v = if i < 3 { v / self.k() } else { *v };
            params.set(5401 + i as u32, v);
        }
        for n in 5407..=5409 {
            params.set(n, 0.0);
        }
        params.set(5410, dia / self.k());
    }

    /// A probe left unanswered is taken as tripping at its end (a dry run); one that did not
    /// trip but had to is an error here, at the block after it.
    fn settle_probe(&mut self, line: usize, params: &mut Params) -> Result<(), GcodeError> {
        let Some(p) = self.probe.take() else {
            return Ok(());
        };
        match p.answered {
            None => {
                self.apply_probe(p.end, p.end, true, params);
                Ok(())
            }
            Some(false) if p.must_trip => err(
                line,
                format!(
                    "the probe move of line {} ended without the probe tripping",
                    p.line
                ),
            ),
            Some(_) => Ok(()),
        }
    }

    /// The probe tripped at `at` and stopped at `stopped` (machine): #5061–#5070 and the
    /// position.
    fn apply_probe(&mut self, at: Pos, stopped: Pos, tripped: bool, params: &mut Params) {
        self.position = stopped;
        let w = self.frame().to_work(at);
        for (i, v) in w.iter().enumerate() {
            let v = if i < 3 { v / self.k() } else { *v };
            params.set(5061 + i as u32, v);
        }
        for n in 5067..=5069 {
            params.set(n, 0.0);
        }
        params.set(5070, if tripped { 1.0 } else { 0.0 });
        self.publish_position(params);
    }

    /// Everything on the line, in LinuxCNC's order.
    fn execute(
        &mut self,
        b: &Block,
        l: &modal::Line,
        params: &mut Params,
        out: &mut Vec<Op>,
    ) -> Result<Flow, GcodeError> {
        let line = b.line;
        if let Some(text) = &b.message {
            out.push(Op {
                line,
                kind: OpKind::Message { text: text.clone() },
            });
        }
        // Feed mode, F, S.
        if let Some(g) = l.group(5) {
            // As LinuxCNC: G94 and G95 set the feed to zero (an F must follow).
            match g {
                930 => self.feed_mode = FeedMode::InverseTime,
                940 => {
                    self.feed_mode = FeedMode::PerMinute;
                    (self.feed_lin, self.feed_ang) = (0.0, 0.0);
                }
                _ => {
                    self.feed_mode = FeedMode::PerRevolution;
                    self.feed_rev = 0.0;
                }
            }
        }
        if let Some(f) = b.word('F') {
            if f < 0.0 {
                return err(line, format!("negative feed rate F{f}"));
            }
            match self.feed_mode {
                FeedMode::PerMinute => {
                    self.feed_lin = f * self.k();
                    self.feed_ang = f;
                }
                FeedMode::PerRevolution => self.feed_rev = f * self.k(),
                // Inverse time: F belongs to its line's move only.
                FeedMode::InverseTime => {}
            }
        }
        let spindle_m = l.m_group(7);
        let mut speed_changed = false;
        if let Some(s) = b.word('S') {
            if s < 0.0 {
                return err(line, format!("negative spindle speed S{s}"));
            }
            speed_changed = s != self.speed;
            self.speed = s;
            if speed_changed && spindle_m.is_none() {
                self.spindle_op(line, out);
            }
        }
        if let Some(t) = b.word('T') {
            let t = modal::int_word(line, 'T', t, 0.0)?;
            if t != 0 && !self.tools.tools.iter().any(|x| x.number == t) {
                return err(line, format!("tool T{t} is not in the tool table"));
            }
            self.selected = t;
        }
        for &m in &b.m {
            if (62..=68).contains(&m) {
                self.io(b, m, out)?;
            }
        }
        if let Some(m) = l.m_group(6) {
            if self.comp.is_some() || self.comp_mode != CompMode::Off {
                return err(
                    line,
                    "cannot change tools with cutter radius compensation on",
                );
            }
            if m == 6 {
                out.push(Op {
                    line,
                    kind: OpKind::ToolChange {
                        tool: self.selected,
                    },
                });
                self.tool = self.selected;
            } else {
                // M61 Q: the tool in the spindle is Q, nothing moves.
                let Some(q) = b.word('Q') else {
                    return err(line, "M61 needs Q (the tool number)");
                };
                let q = modal::int_word(line, 'Q', q, 0.0)?;
                if q != 0 && !self.tools.tools.iter().any(|x| x.number == q) {
                    return err(line, format!("tool {q} (M61 Q) is not in the tool table"));
                }
                self.tool = q;
                self.selected = q;
            }
            self.publish_tool(params);
        }
        if spindle_m == Some(19) {
            self.orient(b, out)?;
        } else if let Some(m) = spindle_m {
            let dir = match m {
                3 => SpindleDir::Cw,
                4 => SpindleDir::Ccw,
                _ => SpindleDir::Off,
            };
            if dir != self.dir || speed_changed {
                self.dir = dir;
                self.spindle_op(line, out);
            }
        }
        if let Some(m) = l.m_group(11) {
            self.modal_save(line, m, params, out)?;
        }
        let coolant: Vec<u32> =
            b.m.iter()
                .copied()
                .filter(|m| (7..=9).contains(m))
                .collect();
        if !coolant.is_empty() {
            for m in &coolant {
                match m {
                    7 => self.mist = true,
                    8 => self.flood = true,
                    _ => {
                        self.mist = false;
                        self.flood = false;
                    }
                }
            }
            out.push(Op {
                line,
                kind: OpKind::Coolant {
                    mist: self.mist,
                    flood: self.flood,
                },
            });
        }
        if let Some(m) = l.m_group(9) {
            let on = match b.word('P') {
                None => true,
                Some(p) => p != 0.0,
            };
            match m {
                48 => (self.feed_override, self.spindle_override) = (true, true),
                49 => (self.feed_override, self.spindle_override) = (false, false),
                50 => self.feed_override = on,
                _ => self.spindle_override = on,
            }
            out.push(Op {
                line,
                kind: OpKind::Overrides {
                    feed: self.feed_override,
                    spindle: self.spindle_override,
                },
            });
        }
        if let Some(m) = l.m_group(10) {
            out.push(Op {
                line,
                kind: OpKind::Hook {
                    code: m,
                    p: b.word('P'),
                    q: b.word('Q'),
                },
            });
        }
        if l.group(0) == Some(40) {
            let p = b.word('P').unwrap_or(0.0);
            if p < 0.0 {
                return err(line, format!("negative dwell time P{p}"));
            }
            out.push(Op {
                line,
                kind: OpKind::Dwell { seconds: p },
            });
        }
        if let Some(g) = l.group(2) {
            let plane = match g {
                170 => Plane::Xy,
                180 => Plane::Zx,
                _ => Plane::Yz,
            };
            if plane != self.plane && self.comp_mode != CompMode::Off {
                return err(
                    line,
                    "cannot change the plane with cutter radius compensation on",
                );
            }
            if plane != self.plane && !self.nurbs.is_empty() {
                return err(line, "cannot change the plane between G5.2 and G5.3");
            }
            self.plane = plane;
        }
        if let Some(g) = l.group(6) {
            self.units = if g == 200 { Units::Inch } else { Units::Mm };
        }
        if let Some(g) = l.group(7) {
            self.set_comp(b, g, out)?;
        }
        if let Some(g) = l.group(8) {
            self.set_tool_length(b, g)?;
        }
        if let Some(g) = l.group(12) {
            self.select_coordinate_system(line, g, params)?;
        }
        if let Some(g) = l.group(13) {
            self.blend = match g {
                610 => Blend::ExactStop,
                611 => Blend::ExactPath,
                _ => {
                    for w in ['P', 'Q'] {
                        if let Some(v) = b.word(w).filter(|v| v.is_nan() || *v < 0.0) {
                            return Err(GcodeError::new(
                                line,
                                format!("G64 {w}{v}: a tolerance of 0 or more"),
                            ));
                        }
                    }
                    Blend::Blended {
                        tolerance: b.word('P').map(|p| p * self.k()),
                        naive: b.word('Q').map(|q| q * self.k()),
                    }
                }
            };
        }
        if let Some(g) = l.group(3) {
            self.absolute = g == 900;
        }
        if let Some(g) = l.group(4) {
            self.arc_absolute = g == 901;
        }
        if let Some(g) = l.group(10) {
            self.retract_r = g == 990;
        }
        match l.group(0) {
            Some(100) => self.g10(b, params)?,
            Some(g @ (280 | 300)) => self.go_home(b, g, params, out)?,
            Some(g @ (281 | 301)) => self.store_home(g, params),
            Some(g @ (520 | 920 | 921 | 922 | 923)) => self.axis_offsets(b, g, params)?,
            _ => {}
        }
        if let Some(g) = l.motion {
            self.motion(b, l, g, out)?;
        } else if let Some(g) = l.group(1) {
            // A motion code with nothing to do: G80, or G0/G1/G2/G3 alone.
            self.set_motion_mode(g);
        }
        if l.group(0) == Some(53) {
            self.nurbs_end(b, out)?;
        }
        if let Some(m) = l.m_group(4) {
            match m {
                0 => out.push(Op {
                    line,
                    kind: OpKind::Pause {
                        kind: PauseKind::Program,
                    },
                }),
                1 => {
                    if self.optional_stop {
                        out.push(Op {
                            line,
                            kind: OpKind::Pause {
                                kind: PauseKind::Optional,
                            },
                        });
                    }
                }
                60 => out.push(Op {
                    line,
                    kind: OpKind::Pause {
                        kind: PauseKind::Pallet,
                    },
                }),
                _ => {
                    if !self.nurbs.is_empty() {
                        return err(line, "the program ends between G5.2 and G5.3");
                    }
                    self.comp_off(line, out)?;
                    out.push(Op {
                        line,
                        kind: OpKind::End { rewind: m == 30 },
                    });
                    return Ok(Flow::End);
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// The motion mode becomes `g` (a cycle's initial level is forgotten when it is not one).
    fn set_motion_mode(&mut self, g: GCode) {
        if !modal::is_cycle(g) {
            self.cycle.initial = None;
        }
        self.motion = if g == 800 { None } else { Some(g) };
    }

    fn spindle_op(&self, line: usize, out: &mut Vec<Op>) {
        out.push(Op {
            line,
            kind: OpKind::Spindle {
                speed: self.speed,
                dir: self.dir,
            },
        });
    }

    /// M19 R (degrees, 0 by default) P (0 clockwise, 1 counter-clockwise, 2 the shorter
    /// way): the spindle stops, turned to R. (Q, LinuxCNC's time to wait for it, is taken and
    /// not used: the run waits until the spindle is there.)
    fn orient(&mut self, b: &Block, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        let angle = b.word('R').unwrap_or(0.0);
        let p = b.word('P').unwrap_or(0.0);
        let dir = match p as u8 {
            0 if p == 0.0 => SpindleDir::Cw,
            1 if p == 1.0 => SpindleDir::Ccw,
            2 if p == 2.0 => SpindleDir::Off,
            _ => return err(line, format!("M19 P{p}: P is 0, 1 or 2")),
        };
        if b.word('Q').is_some_and(|q| q < 0.0) {
            return err(line, "M19 with a negative Q (the time to wait)");
        }
        self.dir = SpindleDir::Off;
        out.push(Op {
            line,
            kind: OpKind::SpindleOrient { angle, dir },
        });
        Ok(())
    }

    /// M62–M68.
    fn io(&mut self, b: &Block, m: u32, out: &mut Vec<Op>) -> Result<(), GcodeError> {
        let line = b.line;
        let kind = match m {
            62..=65 => {
                let Some(p) = b.word('P') else {
                    return err(line, format!("M{m} needs P (the output number)"));
                };
                OpKind::Output {
                    index: modal::int_word(line, 'P', p, 0.0)?,
                    on: m == 62 || m == 64,
                    synced: m <= 63,
                }
            }
            66 => {
                let (index, analog) = match (b.word('P'), b.word('E')) {
                    (Some(p), None) => (modal::int_word(line, 'P', p, 0.0)?, false),
                    (None, Some(e)) => (modal::int_word(line, 'E', e, 0.0)?, true),
                    (Some(_), Some(_)) => return err(line, "M66 takes P or E, not both"),
                    (None, None) => {
                        return err(line, "M66 needs P (digital input) or E (analog input)")
                    }
                };
                let mode = modal::int_word(line, 'L', b.word('L').unwrap_or(0.0), 0.0)?;
                if mode > 4 {
                    return err(line, format!("M66 L{mode}: the mode is 0 to 4"));
                }
                if analog && mode != 0 {
                    return err(line, "M66 with E (analog input) waits only in mode L0");
                }
                let timeout = b.word('Q').unwrap_or(0.0);
                if timeout < 0.0 {
                    return err(line, format!("M66 Q{timeout}: a negative timeout"));
                }
                if mode != 0 && b.word('Q').is_none() {
                    return err(line, format!("M66 L{mode} needs Q (the timeout)"));
                }
                OpKind::WaitInput {
                    index,
                    analog,
                    mode: mode as u8,
                    timeout,
                }
            }
            _ => {
                let Some(e) = b.word('E') else {
                    return err(line, format!("M{m} needs E (the analog output number)"));
                };
                let Some(q) = b.word('Q') else {
                    return err(line, format!("M{m} needs Q (the value)"));
                };
                OpKind::AnalogOutput {
                    index: modal::int_word(line, 'E', e, 0.0)?,
                    value: q,
                    synced: m == 67,
                }
            }
        };
        out.push(Op { line, kind });
        Ok(())
    }
}
