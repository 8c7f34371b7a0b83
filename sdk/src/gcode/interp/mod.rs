//! The interpreter: evaluated blocks → canonical operations in machine coordinates, with the
//! modal state of RS274/NGC. SKELETON: to be written.

use super::{Block, Flow, GcodeError, Op, Params, Pos, ToolTable};

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
}

/// The modal state and the position.
#[derive(Debug, Clone)]
pub struct Interp {
    position: Pos,
}

impl Interp {
    /// A program starting as LinuxCNC starts one (G17 G21 G40 G49 G54 G64 G80 G90 G94 G97
    /// G99 M5 M9), at `opts.start`; the parameters it keeps (#5220, …) set.
    pub fn new(opts: &Options, _params: &mut Params) -> Self {
        Interp {
            position: opts.start,
        }
    }

    /// One block: its operations appended to `out`.
    pub fn block(
        &mut self,
        _b: &Block,
        _params: &mut Params,
        _out: &mut Vec<Op>,
    ) -> Result<Flow, GcodeError> {
        todo!()
    }

    /// The end of the text (`line`: its last line) without M2/M30: what is pending is
    /// flushed (cutter compensation's last move).
    pub fn finish(
        &mut self,
        _line: usize,
        _params: &mut Params,
        _out: &mut Vec<Op>,
    ) -> Result<(), GcodeError> {
        todo!()
    }

    /// Where the last probe stopped and whether it tripped.
    pub fn probe_result(&mut self, _at: Pos, _tripped: bool, _params: &mut Params) {
        todo!()
    }

    /// The current position (machine coordinates).
    pub fn position(&self) -> Pos {
        self.position
    }
}
