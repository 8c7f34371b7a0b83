//! RS274/NGC, as LinuxCNC documents it for milling: a program read into canonical operations
//! in machine coordinates ([`Op`]), for the card's path buffer ([`run`]), for `mcctl gcode`'s
//! dry run and for C (`mc_gcode_*`).
//!
//! Three layers, each its own module:
//! - [`Reader`] (`reader`, with `lex`, `expr` and `flow`): source text → [`Block`]s. Comments,
//!   block delete, `%`, line numbers, parameters and expressions, and O-word control flow
//!   (subroutines, conditionals, loops) end here: a block is one line's words with their
//!   values, in the order the program runs them.
//! - [`Interp`] (`interp`): blocks → [`Op`]s. The modal state (units, distance modes, plane,
//!   coordinate systems, offsets, tool length, feed mode, path control, spindle, coolant),
//!   canned cycles, splines and cutter radius compensation ([`comp`]).
//! - [`Program`]: the two together, an operation at a time, in memory bounded by the longest
//!   line and the deepest call, whatever the program's length.
//!
//! Whatever is not understood is an error naming its 1-based line ([`GcodeError`]); nothing
//! is skipped.

mod block;
pub mod comp;
mod interp;
mod ops;
mod params;
mod probe;
mod reader;
pub mod run;
pub mod spindle;
mod tools;

pub use block::{Block, GCode};
pub use interp::{CompMode, FeedMode, Interp, Options, Units};
pub use ops::{
    ArcFrame, Blend, Op, OpKind, PauseKind, Plane, Pos, SpindleDir, Spline, AXIS_LETTERS,
    ZERO_LENGTH,
};
pub use params::{Params, Predefined, CALL_PARAMS, MAX_PARAM, PREDEFINED};
pub use reader::{FileSource, Reader, Source, TextSource, MAX_LINE_BYTES};
pub use tools::{Tool, ToolTable};

use std::collections::VecDeque;
use std::fmt;

/// Why a program was refused: the 1-based source line and what is wrong there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GcodeError {
    /// 1-based source line (0: before any line, such as a file that cannot be opened).
    pub line: usize,
    /// What is wrong there.
    pub message: String,
}

impl GcodeError {
    /// An error at `line`.
    pub fn new(line: usize, message: impl Into<String>) -> Self {
        GcodeError {
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for GcodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for GcodeError {}

/// What the interpreter says after a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Read on.
    Continue,
    /// M2 or M30: nothing after it is read.
    End,
}

/// A program running: its reader, its parameters and its interpreter, giving one operation
/// at a time.
pub struct Program<S: Source> {
    reader: Reader<S>,
    interp: Interp,
    params: Params,
    pending: VecDeque<Op>,
    scratch: Vec<Op>,
    done: bool,
}

impl Program<TextSource> {
    /// A program in memory.
    pub fn from_text(text: impl Into<String>, opts: &Options) -> Self {
        Program::new(TextSource::new(text.into()), opts)
    }
}

impl Program<FileSource> {
    /// A program file, read a line at a time.
    pub fn open(path: &std::path::Path, opts: &Options) -> Result<Self, GcodeError> {
        let src = FileSource::open(path)
            .map_err(|e| GcodeError::new(0, format!("cannot open {}: {e}", path.display())))?;
        let mut opts = opts.clone();
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        opts.subroutine_path
            .push(dir.map_or_else(|| ".".into(), |d| d.to_path_buf()));
        Ok(Program::new(src, &opts))
    }
}

impl<S: Source> Program<S> {
    /// The program in `source`, the machine as `opts` says.
    pub fn new(source: S, opts: &Options) -> Self {
        let mut params = Params::new();
        let interp = Interp::new(opts, &mut params);
        Program {
            reader: Reader::new(source, opts.block_delete)
                .with_subroutine_path(opts.subroutine_path.clone()),
            interp,
            params,
            pending: VecDeque::new(),
            scratch: Vec::new(),
            done: false,
        }
    }

    /// The next operation; `None` after the end (M2/M30, or the end of the text). After an
    /// error nothing follows.
    pub fn next_op(&mut self) -> Option<Result<Op, GcodeError>> {
        while self.pending.is_empty() {
            if self.done {
                return None;
            }
            if let Err(e) = self.step() {
                self.done = true;
                return Some(Err(e));
            }
        }
        self.pending.pop_front().map(Ok)
    }

    /// Reads and interprets one block (or finishes at the end of the text).
    fn step(&mut self) -> Result<(), GcodeError> {
        self.scratch.clear();
        match self.reader.next_item(&mut self.params)? {
            Some(b) => {
                if self.interp.block(&b, &mut self.params, &mut self.scratch)? == Flow::End {
                    self.done = true;
                }
            }
            None => {
                self.interp
                    .finish(self.reader.line(), &mut self.params, &mut self.scratch)?;
                self.done = true;
            }
        }
        self.pending.extend(self.scratch.drain(..));
        Ok(())
    }

    /// The last probe's ([`OpKind::Probe`]) result: where it tripped (`at`; its end if it did
    /// not), where the motion came to rest (`stopped`), and whether it tripped. #5061–#5070
    /// report `at`, the program goes on from `stopped`. Without it (a dry run) a probe is
    /// taken as tripping at its programmed end.
    pub fn probe_result(&mut self, at: Pos, stopped: Pos, tripped: bool) {
        self.interp
            .probe_result(at, stopped, tripped, &mut self.params);
    }

    /// The result of the last [`OpKind::WaitInput`] (#5399: the input's value, −1 on a
    /// timeout).
    pub fn input_result(&mut self, value: f64) {
        self.params.set(5399, value);
    }

    /// The source line being read (1-based; 0 before the first).
    pub fn line(&self) -> usize {
        self.reader.line()
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The interpreter (its modal state and position).
    pub fn interp(&self) -> &Interp {
        &self.interp
    }
}

impl<S: Source> Iterator for Program<S> {
    type Item = Result<Op, GcodeError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_op()
    }
}

/// A boxed source is a source (a host that reads programs from files and from memory keeps
/// one type of runner).
impl<S: Source + ?Sized> Source for Box<S> {
    fn read_line(&mut self, buf: &mut String) -> std::io::Result<bool> {
        (**self).read_line(buf)
    }
    fn tell(&mut self) -> u64 {
        (**self).tell()
    }
    fn seek(&mut self, pos: u64) -> std::io::Result<()> {
        (**self).seek(pos)
    }
}
