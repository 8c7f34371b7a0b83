//! An RS274/NGC subset front end: program text → a list of blocks in machine terms (mm,
//! mm/s, absolute coordinates), with the modal state tracked here.
//!
//! # What is understood
//!
//! | words | meaning |
//! | --- | --- |
//! | `G0` `G1` `G2` `G3` | rapid, feed, clockwise and counter-clockwise arcs (modal) |
//! | `X` `Y` `Z` | axis words (absolute or incremental, in the active units) |
//! | `I` `J` `K` | arc centre offsets from the start, always incremental; only the active plane's two |
//! | `R` | arc radius; negative R asks for the arc longer than half a turn |
//! | `G4 P` | dwell, P in seconds |
//! | `G17` `G18` `G19` | arc plane XY, ZX, YZ; the out-of-plane axis moves linearly (a helix) |
//! | `G20` `G21` | inch, mm: every length and feed is converted to mm |
//! | `G90` `G91` | absolute, incremental axis words |
//! | `F` | feed in units per minute (stored in mm/s) |
//! | `M62 P` `M63 P` | digital output P on/off, synchronised with the next motion |
//! | `M64 P` `M65 P` | digital output P on/off, immediately |
//! | `M2` `M30` | end of program |
//! | `G40` `G49` `G94` | accepted as no-ops: they cancel or select what is always the case here (no cutter or tool-length compensation, feed per minute) |
//! | `G80` | cancels the motion mode: axis words after it need a new G0–G3 |
//! | `N`, `( )`, `;`, a line holding only `%` | line numbers, comments and tape markers, ignored |
//!
//! Anything else is an error naming the (1-based) source line: an unsupported G, M, O or T
//! code, any other word (`S`, `A`, `H`, …), a word twice on a line, two codes of one modal
//! group on a line, an arc whose radius at the end differs from the one at the start by more
//! than [`ARC_RADIUS_TOLERANCE_MM`], an `R` arc whose |R| is less than half its chord, a
//! feed move before any `F`, words after `M2`/`M30`, unreadable text. Nothing is skipped
//! silently and no input panics. Moves shorter than [`ZERO_LENGTH_MM`] are dropped (the card
//! refuses them) and counted in [`Program::dropped_zero_length`].
//!
//! # Conventions
//!
//! - The program starts at `[0, 0, 0]` (mm) in G21 G90 G17 with no motion mode and no feed;
//!   [`parse_from`] starts elsewhere.
//! - Within a line the RS274 order of execution holds: units (G20/G21) first (so they apply
//!   to every number on their line), then F, the dwell, plane, distance mode, the output
//!   M-codes, the motion, the end of program. A feed stays the same physical speed when the
//!   units change afterwards.
//! - Arcs: `plane.axes()` = (a, b, n) is right-handed (XY→Z, ZX→Y, YZ→X), so "ccw" is the
//!   positive rotation from a to b in every plane, as in RS274 (for G18 the plane's first
//!   axis is Z). An arc whose start and end coincide in the plane is a full turn (only by
//!   I/J/K). The centre given by I/J/K is moved onto the chord's perpendicular bisector (by at
//!   most the tolerance) so every arc is an exact circle through both of its ends.
//!
//! # About the `gcode` crate (0.6)
//!
//! It tokenises and groups words. It is given one source line at a time ([`Parser`]; given a
//! whole text it joins a letter at the end of a line to a number on the next, and gives a
//! word to the last command seen, even one on an earlier line), so a program is read in
//! memory bounded by its longest line ([`Blocks`]) and no word reaches into another line.
//! This module then regroups the line's words (the crate gives a word to the last command
//! seen, even one of another kind, so `G1 G90 X1` gives `X1` to `G90`), and re-reads every
//! number from its source text as `f64` (the crate keeps `f32`, about 0.1 µm of error per
//! metre). The crate
//! panics on a sign or point with no digits (`X-`), a stray `)` and a non-ASCII character
//! outside a comment: those are refused here before it sees them, and the call is fenced by
//! `catch_unwind` all the same.

use std::fmt;

/// Largest difference between an arc's radius at its start and at its end (mm).
pub const ARC_RADIUS_TOLERANCE_MM: f64 = 0.005;
/// Moves no longer than this (mm) are dropped.
pub const ZERO_LENGTH_MM: f64 = 1e-6;
const MM_PER_INCH: f64 = 25.4;
const AXES: [char; 3] = ['X', 'Y', 'Z'];
const OFFSETS: [char; 3] = ['I', 'J', 'K'];

/// The plane of an arc (G17, G18, G19).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    /// G17: X then Y, normal Z.
    Xy,
    /// G18: Z then X, normal Y.
    Zx,
    /// G19: Y then Z, normal X.
    Yz,
}

impl Plane {
    /// The axis indices (first, second, normal): a right-handed triple.
    pub const fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }

    /// The G-code that selects this plane.
    pub const fn code(self) -> &'static str {
        match self {
            Plane::Xy => "G17",
            Plane::Zx => "G18",
            Plane::Yz => "G19",
        }
    }
}

impl From<Plane> for motioncard_sdk::Plane {
    fn from(p: Plane) -> Self {
        match p {
            Plane::Xy => motioncard_sdk::Plane::XY,
            Plane::Zx => motioncard_sdk::Plane::ZX,
            Plane::Yz => motioncard_sdk::Plane::YZ,
        }
    }
}

/// One block in machine terms. `line` is the 1-based source line; positions are absolute
/// mm, feeds mm/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Block {
    /// A straight move. `feed` is `f64::INFINITY` for a rapid (the runner picks the rapid feed).
    Line {
        line: usize,
        rapid: bool,
        start: [f64; 3],
        end: [f64; 3],
        feed: f64,
    },
    /// A circular arc in `plane`, with the plane's normal axis moving linearly from `start`
    /// to `end` (a helix when they differ). `centre` is absolute; its normal coordinate is
    /// the start's. Start and end coinciding in the plane make a full turn.
    Arc {
        line: usize,
        start: [f64; 3],
        end: [f64; 3],
        centre: [f64; 3],
        plane: Plane,
        ccw: bool,
        feed: f64,
    },
    /// G4: wait `seconds`.
    Dwell { line: usize, seconds: f64 },
    /// M62–M65: digital output `bit` on or off, `synced` with the start of the next motion
    /// (M62/M63) or at once (M64/M65).
    Output {
        line: usize,
        bit: u8,
        on: bool,
        synced: bool,
    },
}

/// An arc's geometry in its plane: point(t) for t in [0, 1] is
/// `centre + radius·(cos θ, sin θ)` in (a, b) with `θ = theta0 + t·sweep`, and
/// `n0 + t·(n1 − n0)` on the normal axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcGeom {
    /// (first, second, normal) axis indices, as [`Plane::axes`].
    pub axes: (usize, usize, usize),
    /// The centre in (a, b).
    pub centre: [f64; 2],
    pub radius: f64,
    /// Angle of the start, radians, from the a axis towards b.
    pub theta0: f64,
    /// Signed angle travelled: positive counter-clockwise, in (0, 2π] or [−2π, 0).
    pub sweep: f64,
    /// Normal-axis coordinate at the start and at the end.
    pub n0: f64,
    pub n1: f64,
}

impl ArcGeom {
    /// The point at parameter `t` in [0, 1] (clamped): angle and height both linear in `t`.
    pub fn point(&self, t: f64) -> [f64; 3] {
        let t = t.clamp(0.0, 1.0);
        let (a, b, n) = self.axes;
        let th = self.theta0 + t * self.sweep;
        let mut p = [0.0; 3];
        p[a] = self.centre[0] + self.radius * th.cos();
        p[b] = self.centre[1] + self.radius * th.sin();
        p[n] = self.n0 + t * (self.n1 - self.n0);
        p
    }

    /// Length along the arc or helix.
    pub fn length(&self) -> f64 {
        (self.radius * self.sweep).hypot(self.n1 - self.n0)
    }
}

impl Block {
    /// The 1-based source line.
    pub fn line(&self) -> usize {
        match *self {
            Block::Line { line, .. }
            | Block::Arc { line, .. }
            | Block::Dwell { line, .. }
            | Block::Output { line, .. } => line,
        }
    }

    /// Whether the block moves (a line or an arc).
    pub fn is_motion(&self) -> bool {
        matches!(self, Block::Line { .. } | Block::Arc { .. })
    }

    /// Start of a motion block.
    pub fn start(&self) -> Option<[f64; 3]> {
        match *self {
            Block::Line { start, .. } | Block::Arc { start, .. } => Some(start),
            _ => None,
        }
    }

    /// End of a motion block.
    pub fn end(&self) -> Option<[f64; 3]> {
        match *self {
            Block::Line { end, .. } | Block::Arc { end, .. } => Some(end),
            _ => None,
        }
    }

    /// The geometry of an arc block.
    pub fn arc_geom(&self) -> Option<ArcGeom> {
        let Block::Arc {
            start,
            end,
            centre,
            plane,
            ccw,
            ..
        } = *self
        else {
            return None;
        };
        let (a, b, n) = plane.axes();
        let c = [centre[a], centre[b]];
        let theta0 = (start[b] - c[1]).atan2(start[a] - c[0]);
        let theta1 = (end[b] - c[1]).atan2(end[a] - c[0]);
        let full = (end[a] - start[a]).hypot(end[b] - start[b]) <= ZERO_LENGTH_MM;
        let tau = std::f64::consts::TAU;
        let sweep = match (full, ccw) {
            (true, true) => tau,
            (true, false) => -tau,
            (false, true) => (theta1 - theta0).rem_euclid(tau),
            (false, false) => -(theta0 - theta1).rem_euclid(tau),
        };
        Some(ArcGeom {
            axes: (a, b, n),
            centre: c,
            radius: (start[a] - c[0]).hypot(start[b] - c[1]),
            theta0,
            sweep,
            n0: start[n],
            n1: end[n],
        })
    }

    /// Path length (mm) of a motion block; 0 for the others.
    pub fn length(&self) -> f64 {
        match *self {
            Block::Line { start, end, .. } => dist(start, end),
            Block::Arc { .. } => self.arc_geom().map_or(0.0, |g| g.length()),
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
            Block::Arc { .. } => self.arc_geom().map(|g| g.point(f)),
            _ => None,
        }
    }

    /// The programmed feed (mm/s) of a motion block (`INFINITY` for a rapid).
    pub fn feed(&self) -> Option<f64> {
        match *self {
            Block::Line { feed, .. } | Block::Arc { feed, .. } => Some(feed),
            _ => None,
        }
    }
}

/// A parsed program.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Program {
    pub blocks: Vec<Block>,
    /// Moves no longer than [`ZERO_LENGTH_MM`], dropped.
    pub dropped_zero_length: usize,
}

impl Program {
    /// How many blocks move (lines and arcs).
    pub fn motion_count(&self) -> usize {
        self.blocks.iter().filter(|b| b.is_motion()).count()
    }

    /// Total programmed path length (mm), rapids included.
    pub fn length(&self) -> f64 {
        self.blocks.iter().map(Block::length).sum()
    }
}

/// Why a program was refused: the 1-based source line and what is wrong there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GcodeError {
    pub line: usize,
    pub message: String,
}

impl fmt::Display for GcodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for GcodeError {}

fn err<T>(line: usize, message: impl Into<String>) -> Result<T, GcodeError> {
    Err(GcodeError {
        line,
        message: message.into(),
    })
}

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Parses `text`, starting at the origin.
pub fn parse(text: &str) -> Result<Program, GcodeError> {
    parse_from(text, [0.0; 3])
}

/// Parses `text`, starting at `start` (mm): [`Parser`] over its lines.
pub fn parse_from(text: &str, start: [f64; 3]) -> Result<Program, GcodeError> {
    let mut parser = Parser::new(start);
    let mut blocks = Vec::new();
    for line in text.split('\n') {
        parser.line(line, &mut blocks)?;
    }
    Ok(Program {
        blocks,
        dropped_zero_length: parser.dropped_zero_length(),
    })
}

/// The longest source line read by [`Blocks`], in bytes (RS274/NGC lines are short:
/// LinuxCNC's limit is 255 characters).
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// The program's parser, a line at a time: the modal state of the program so far. A line's
/// words never reach into the next line (a comment closes on its line), so a program parsed
/// line by line is the program parsed whole, and the first error is the first in the text.
#[derive(Debug)]
pub struct Parser {
    state: State,
    /// Lines seen so far.
    line: usize,
}

impl Parser {
    /// A program starting at `start` (mm) in G21 G90 G17, no motion mode, no feed.
    pub fn new(start: [f64; 3]) -> Self {
        Parser {
            state: State::new(start),
            line: 0,
        }
    }

    /// The next source line (without its `\n`): its blocks are appended to `out`. After an
    /// error the parser is not to be used again.
    pub fn line(&mut self, text: &str, out: &mut Vec<Block>) -> Result<(), GcodeError> {
        self.line += 1;
        let at = |e: GcodeError| GcodeError {
            line: self.line,
            message: e.message,
        };
        prescan(text).map_err(at)?;
        let items = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| collect(text))) {
            Ok(r) => r.map_err(at)?,
            Err(_) => return err(self.line, "the G-code tokenizer failed on this line"),
        };
        if items.is_empty() {
            return Ok(());
        }
        self.state.line(self.line, &items, out)
    }

    /// Lines seen so far (the 1-based number of the last one).
    pub fn lines(&self) -> usize {
        self.line
    }

    /// Moves no longer than [`ZERO_LENGTH_MM`] dropped so far.
    pub fn dropped_zero_length(&self) -> usize {
        self.state.dropped_zero_length
    }
}

/// The blocks of a program read from `reader` a line at a time ([`Parser`]): memory bounded
/// by the longest line ([`MAX_LINE_BYTES`]) whatever the program's length. An unreadable
/// line (I/O error, not UTF-8, too long) is an error naming it; nothing follows an error.
pub struct Blocks<R> {
    reader: R,
    parser: Parser,
    /// The current line's blocks not yet taken (at most a dwell, an output and a motion).
    pending: std::collections::VecDeque<Block>,
    scratch: Vec<Block>,
    buf: Vec<u8>,
    done: bool,
}

impl<R: std::io::BufRead> Blocks<R> {
    /// The program in `reader`, starting at `start` (mm).
    pub fn new(reader: R, start: [f64; 3]) -> Self {
        Blocks {
            reader,
            parser: Parser::new(start),
            pending: Default::default(),
            scratch: Vec::new(),
            buf: Vec::new(),
            done: false,
        }
    }

    /// The parser (its line count and dropped moves so far).
    pub fn parser(&self) -> &Parser {
        &self.parser
    }

    /// Reads the next line into `buf`; `false` at the end.
    fn next_line(&mut self) -> Result<bool, GcodeError> {
        use std::io::{BufRead as _, Read as _};
        self.buf.clear();
        let line = self.parser.lines() + 1;
        let limit = MAX_LINE_BYTES as u64 + 1;
        let n = (&mut self.reader)
            .take(limit)
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| GcodeError {
                line,
                message: format!("cannot read: {e}"),
            })?;
        if n == 0 {
            return Ok(false);
        }
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
        }
        if self.buf.len() > MAX_LINE_BYTES {
            return err(line, format!("longer than {MAX_LINE_BYTES} bytes"));
        }
        Ok(true)
    }
}

impl<R: std::io::BufRead> Iterator for Blocks<R> {
    type Item = Result<Block, GcodeError>;

    fn next(&mut self) -> Option<Self::Item> {
        while self.pending.is_empty() {
            if self.done {
                return None;
            }
            let step = self.next_line().and_then(|more| {
                if !more {
                    self.done = true;
                    return Ok(());
                }
                let line = self.parser.lines() + 1;
                let text = std::str::from_utf8(&self.buf).map_err(|_| GcodeError {
                    line,
                    message: "not UTF-8 text".into(),
                })?;
                self.scratch.clear();
                self.parser.line(text, &mut self.scratch)?;
                self.pending.extend(self.scratch.drain(..));
                Ok(())
            });
            if let Err(e) = step {
                self.done = true;
                return Some(Err(e));
            }
        }
        self.pending.pop_front().map(Ok)
    }
}

/// One word of a line: a command (`G`, `M`, `O`, `T`) or a value word; `start` the byte
/// offset, `text` as written.
#[derive(Debug, Clone)]
struct Item {
    start: usize,
    letter: char,
    value: f64,
    text: String,
    command: bool,
}

/// Refuses what the `gcode` crate would panic on, and unclosed comments.
fn prescan(src: &str) -> Result<(), GcodeError> {
    let b = src.as_bytes();
    let (mut i, mut line) = (0, 1);
    while i < b.len() {
        match b[i] {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b';' => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'(' => {
                while i < b.len() && b[i] != b'\n' && b[i] != b')' {
                    i += 1;
                }
                if i >= b.len() || b[i] != b')' {
                    return err(line, "comment '(' not closed on its line");
                }
                i += 1;
            }
            b')' => return err(line, "')' without an opening '('"),
            b'0'..=b'9' | b'.' | b'+' | b'-' => {
                // The crate's number token: a sign first, digits, at most one point.
                let (mut digits, mut point, st) = (false, false, i);
                while i < b.len() {
                    match b[i] {
                        b'+' | b'-' if i == st => {}
                        b'0'..=b'9' => digits = true,
                        b'.' if !point => point = true,
                        _ => break,
                    }
                    i += 1;
                }
                if !digits {
                    return err(line, format!("number with no digits: '{}'", &src[st..i]));
                }
            }
            c if c >= 0x80 => return err(line, "non-ASCII character outside a comment"),
            _ => i += 1,
        }
    }
    Ok(())
}

/// Line (1-based) of a byte offset.
fn line_of(line_starts: &[usize], offset: usize) -> usize {
    line_starts.partition_point(|&s| s <= offset)
}

/// The number written after the letter at `start`.
fn number_after_letter(src: &str, start: usize) -> Option<(f64, usize)> {
    let b = src.as_bytes();
    let mut i = start + 1;
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    let st = i;
    let mut point = false;
    while i < b.len() {
        match b[i] {
            b'+' | b'-' if i == st => {}
            b'0'..=b'9' => {}
            b'.' if !point => point = true,
            _ => break,
        }
        i += 1;
    }
    src[st..i].parse().ok().map(|v| (v, i))
}

#[derive(Default)]
struct Collector {
    /// Words the crate found before any command (so attached to none).
    orphans: Vec<::gcode::Word>,
    /// (byte offset, message) of what the crate could not read.
    problems: Vec<(usize, String)>,
    /// Byte offsets of `%` tape markers the crate saw as unknown content.
    percent: Vec<usize>,
}

impl ::gcode::Callbacks for Collector {
    fn unknown_content(&mut self, text: &str, span: ::gcode::Span) {
        if text.trim() == "%" {
            self.percent.push(span.start);
        } else {
            self.problems
                .push((span.start, format!("unrecognised text '{}'", text.trim())));
        }
    }
    fn gcode_buffer_overflowed(
        &mut self,
        _m: ::gcode::Mnemonic,
        _major: u32,
        _minor: u32,
        _args: &[::gcode::Word],
        span: ::gcode::Span,
    ) {
        self.problems.push((span.start, "too many codes".into()));
    }
    fn gcode_argument_buffer_overflowed(
        &mut self,
        _m: ::gcode::Mnemonic,
        _major: u32,
        _minor: u32,
        arg: ::gcode::Word,
    ) {
        self.problems
            .push((arg.span.start, "too many words".into()));
    }
    fn comment_buffer_overflow(&mut self, c: ::gcode::Comment<'_>) {
        self.problems
            .push((c.span.start, "too many comments".into()));
    }
    fn unexpected_line_number(&mut self, _n: f32, span: ::gcode::Span) {
        self.problems.push((
            span.start,
            "line number N must come first on its line".into(),
        ));
    }
    fn argument_without_a_command(&mut self, letter: char, value: f32, span: ::gcode::Span) {
        self.orphans.push(::gcode::Word {
            letter,
            value,
            span,
        });
    }
    fn number_without_a_letter(&mut self, value: &str, span: ::gcode::Span) {
        self.problems
            .push((span.start, format!("number '{value}' without a letter")));
    }
    fn letter_without_a_number(&mut self, value: &str, span: ::gcode::Span) {
        self.problems
            .push((span.start, format!("letter '{value}' without a number")));
    }
}

/// Every word of `src`, in source order, with `f64` values read from the text.
fn collect(src: &str) -> Result<Vec<Item>, GcodeError> {
    let mut line_starts = vec![0];
    line_starts.extend(src.match_indices('\n').map(|(i, _)| i + 1));
    let mut cb = Collector::default();
    let mut items = Vec::new();
    let mut seen_commands = std::collections::HashSet::new();
    // Words whose number is not where the crate put it (`X$2`): reported after the
    // crate's own complaints, which say why.
    let mut unreadable = Vec::new();
    let mut value_word = |w: &::gcode::Word, items: &mut Vec<Item>| {
        let line = line_of(&line_starts, w.span.start);
        let text = src.get(w.span.start..w.span.end).unwrap_or("");
        let Some((value, _)) = number_after_letter(src, w.span.start) else {
            unreadable.push((line, format!("unreadable word '{text}'")));
            return;
        };
        items.push(Item {
            start: w.span.start,
            letter: w.letter.to_ascii_uppercase(),
            value,
            text: text.split_whitespace().collect(),
            command: false,
        });
    };
    for l in ::gcode::full_parse_with_callbacks(src, &mut cb) {
        for g in l.gcodes() {
            let start = g.span().start;
            // A command the crate repeats for words on later lines (modal words) has the
            // span of the first one: only its first appearance is a command word.
            if seen_commands.insert(start) {
                let line = line_of(&line_starts, start);
                let letter = match g.mnemonic() {
                    ::gcode::Mnemonic::General => 'G',
                    ::gcode::Mnemonic::Miscellaneous => 'M',
                    ::gcode::Mnemonic::ProgramNumber => 'O',
                    ::gcode::Mnemonic::ToolChange => 'T',
                };
                let Some((value, end)) = number_after_letter(src, start) else {
                    return err(line, "unreadable command word");
                };
                items.push(Item {
                    start,
                    letter,
                    value,
                    text: src[start..end].split_whitespace().collect(),
                    command: true,
                });
            }
            for w in g.arguments() {
                value_word(w, &mut items);
            }
        }
    }
    for w in &cb.orphans {
        value_word(w, &mut items);
    }
    if let Some((at, msg)) = cb.problems.iter().min_by_key(|p| p.0) {
        return err(line_of(&line_starts, *at), msg.clone());
    }
    if let Some((line, msg)) = unreadable.into_iter().min_by_key(|u| u.0) {
        return err(line, msg);
    }
    for &at in &cb.percent {
        let line = line_of(&line_starts, at);
        let text = &src[line_starts[line - 1]..];
        if text.lines().next().unwrap_or("").trim() != "%" {
            return err(line, "'%' must stand alone on its line");
        }
    }
    items.sort_by_key(|it| it.start);
    Ok(items)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    Cw,
    Ccw,
}

#[derive(Debug)]
struct State {
    pos: [f64; 3],
    mm_per_unit: f64,
    incremental: bool,
    plane: Plane,
    motion: Option<Motion>,
    feed: Option<f64>,
    ended: Option<usize>,
    dropped_zero_length: usize,
}

/// What a line asks for, gathered before it is executed.
#[derive(Default)]
struct LineWords {
    /// Value words by letter (A..Z), in source units.
    values: [Option<f64>; 26],
    motion: Option<Motion>,
    cancel_motion: bool,
    dwell: bool,
    plane: Option<Plane>,
    units: Option<f64>,
    incremental: Option<bool>,
    /// (on, synced) of M62–M65.
    output: Option<(bool, bool)>,
    end: bool,
}

impl LineWords {
    fn get(&self, c: char) -> Option<f64> {
        self.values[(c as u8 - b'A') as usize]
    }
}

impl State {
    fn new(start: [f64; 3]) -> Self {
        State {
            pos: start,
            mm_per_unit: 1.0,
            incremental: false,
            plane: Plane::Xy,
            motion: None,
            feed: None,
            ended: None,
            dropped_zero_length: 0,
        }
    }

    fn gather(line: usize, items: &[Item]) -> Result<LineWords, GcodeError> {
        let mut w = LineWords::default();
        // One code per modal group and line: the group's name and the code that took it.
        let mut groups: Vec<(&'static str, String)> = Vec::new();
        let mut take = |group: &'static str, code: &str| -> Result<(), GcodeError> {
            if let Some((_, first)) = groups.iter().find(|g| g.0 == group) {
                return err(
                    line,
                    format!("{first} and {code} on one line (both set the {group})"),
                );
            }
            groups.push((group, code.to_string()));
            Ok(())
        };
        for it in items {
            if it.command {
                let code = it.text.to_ascii_uppercase();
                let int = (it.value.fract() == 0.0 && (0.0..1000.0).contains(&it.value))
                    .then_some(it.value as u32);
                match (it.letter, int) {
                    ('G', Some(n @ 0..=3)) => {
                        take("motion mode", &code)?;
                        w.motion = Some(
                            [Motion::Rapid, Motion::Feed, Motion::Cw, Motion::Ccw][n as usize],
                        );
                    }
                    ('G', Some(80)) => {
                        take("motion mode", &code)?;
                        w.cancel_motion = true;
                    }
                    ('G', Some(4)) => {
                        take("dwell", &code)?;
                        w.dwell = true;
                    }
                    ('G', Some(n @ 17..=19)) => {
                        take("plane", &code)?;
                        w.plane = Some([Plane::Xy, Plane::Zx, Plane::Yz][n as usize - 17]);
                    }
                    ('G', Some(n @ 20..=21)) => {
                        take("units", &code)?;
                        w.units = Some(if n == 20 { MM_PER_INCH } else { 1.0 });
                    }
                    ('G', Some(n @ (90 | 91))) => {
                        take("distance mode", &code)?;
                        w.incremental = Some(n == 91);
                    }
                    ('G', Some(40)) => take("cutter compensation", &code)?,
                    ('G', Some(49)) => take("tool length offset", &code)?,
                    ('G', Some(94)) => take("feed mode", &code)?,
                    ('M', Some(n @ 62..=65)) => {
                        take("digital output", &code)?;
                        w.output = Some((n % 2 == 0, n <= 63));
                    }
                    ('M', Some(2 | 30)) => {
                        take("program end", &code)?;
                        w.end = true;
                    }
                    _ => return err(line, format!("unsupported code {code}")),
                }
            } else {
                let c = it.letter;
                match c {
                    'X' | 'Y' | 'Z' | 'I' | 'J' | 'K' | 'R' | 'P' | 'F' => {}
                    'A' | 'B' | 'C' => {
                        return err(
                            line,
                            format!("rotary axis word {} is not supported", it.text),
                        )
                    }
                    _ => return err(line, format!("unsupported word {}", it.text)),
                }
                if !it.value.is_finite() {
                    return err(line, format!("word {} is not a finite number", it.text));
                }
                let slot = &mut w.values[(c as u8 - b'A') as usize];
                if slot.is_some() {
                    return err(line, format!("word {c} given twice"));
                }
                *slot = Some(it.value);
            }
        }
        Ok(w)
    }

    fn line(
        &mut self,
        line: usize,
        items: &[Item],
        out: &mut Vec<Block>,
    ) -> Result<(), GcodeError> {
        if let Some(end) = self.ended {
            return err(
                line,
                format!("words after the end of the program (line {end})"),
            );
        }
        let w = Self::gather(line, items)?;
        if let Some(u) = w.units {
            self.mm_per_unit = u;
        }
        let k = self.mm_per_unit;
        if let Some(f) = w.get('F') {
            if f <= 0.0 {
                return err(line, format!("feed F{f} must be positive"));
            }
            self.feed = Some(f * k / 60.0);
        }
        match (w.get('P'), w.dwell, w.output.is_some()) {
            (Some(_), true, true) => return err(line, "G4 and M62-M65 on one line share P"),
            (Some(_), false, false) => return err(line, "P given without G4 or M62-M65"),
            (None, true, _) => return err(line, "G4 needs P (seconds)"),
            (None, _, true) => return err(line, "M62-M65 need P (the output number)"),
            _ => {}
        }
        if w.dwell {
            let p = w.get('P').unwrap_or(0.0);
            if p < 0.0 {
                return err(line, format!("dwell P{p} is negative"));
            }
            out.push(Block::Dwell { line, seconds: p });
        }
        if let Some(p) = w.plane {
            self.plane = p;
        }
        if let Some(inc) = w.incremental {
            self.incremental = inc;
        }
        if let Some((on, synced)) = w.output {
            let p = w.get('P').unwrap_or(-1.0);
            if p.fract() != 0.0 || !(0.0..=255.0).contains(&p) {
                return err(
                    line,
                    format!("output number P{p} is not an integer 0..=255"),
                );
            }
            out.push(Block::Output {
                line,
                bit: p as u8,
                on,
                synced,
            });
        }
        if w.cancel_motion {
            self.motion = None;
        }
        if let Some(m) = w.motion {
            self.motion = Some(m);
        }
        self.motion(line, &w, out)?;
        if w.end {
            self.ended = Some(line);
        }
        Ok(())
    }

    fn motion(
        &mut self,
        line: usize,
        w: &LineWords,
        out: &mut Vec<Block>,
    ) -> Result<(), GcodeError> {
        let k = self.mm_per_unit;
        let axis_words = AXES.map(|c| w.get(c));
        let has_axes = axis_words.iter().any(Option::is_some);
        let offsets = OFFSETS.map(|c| w.get(c));
        let has_offsets = offsets.iter().any(Option::is_some);
        let radius = w.get('R');
        let arc = matches!(self.motion, Some(Motion::Cw | Motion::Ccw));
        if has_offsets || radius.is_some() {
            if !arc {
                return err(line, "I/J/K/R given without a G2/G3 arc");
            }
            if !has_axes {
                return err(line, "an arc needs at least one axis word");
            }
        }
        if !has_axes {
            return Ok(());
        }
        let Some(motion) = self.motion else {
            return err(line, "axis words without a motion mode (G0/G1/G2/G3)");
        };
        let start = self.pos;
        let mut end = start;
        for i in 0..3 {
            if let Some(v) = axis_words[i] {
                end[i] = if self.incremental {
                    start[i] + v * k
                } else {
                    v * k
                };
            }
        }
        let name = ["G0", "G1", "G2", "G3"][motion as usize];
        let feed = match motion {
            Motion::Rapid => f64::INFINITY,
            _ => match self.feed {
                Some(f) => f,
                None => return err(line, format!("{name} with no F ever given")),
            },
        };
        let block = match motion {
            Motion::Rapid | Motion::Feed => {
                if dist(start, end) <= ZERO_LENGTH_MM {
                    self.dropped_zero_length += 1;
                    return Ok(());
                }
                Block::Line {
                    line,
                    rapid: motion == Motion::Rapid,
                    start,
                    end,
                    feed,
                }
            }
            Motion::Cw | Motion::Ccw => {
                let ccw = motion == Motion::Ccw;
                let spec = match (has_offsets, radius) {
                    (true, Some(_)) => return err(line, "an arc takes I/J/K or R, not both"),
                    (false, None) => return err(line, format!("{name} needs I/J/K or R")),
                    (true, None) => Centre::Offsets(offsets.map(|o| o.map(|v| v * k))),
                    (false, Some(r)) => Centre::Radius(r * k),
                };
                // Never of zero length: a full turn by I/J/K or an error.
                match arc_block(line, start, end, self.plane, ccw, spec, feed) {
                    Ok(b) => b,
                    Err(msg) => return err(line, format!("{name}: {msg}")),
                }
            }
        };
        // The arc may have snapped its end onto the start (a full turn).
        self.pos = block.end().unwrap_or(end);
        out.push(block);
        Ok(())
    }
}

enum Centre {
    /// I, J, K in mm, by axis.
    Offsets([Option<f64>; 3]),
    /// R in mm, signed.
    Radius(f64),
}

/// An arc block, or what is wrong with it.
fn arc_block(
    line: usize,
    start: [f64; 3],
    mut end: [f64; 3],
    plane: Plane,
    ccw: bool,
    spec: Centre,
    feed: f64,
) -> Result<Block, String> {
    let (a, b, n) = plane.axes();
    let chord = (end[a] - start[a]).hypot(end[b] - start[b]);
    let mid = [(start[a] + end[a]) / 2.0, (start[b] + end[b]) / 2.0];
    let c = match spec {
        Centre::Offsets(off) => {
            if let Some(o) = off[n] {
                return Err(format!(
                    "{}{} is not an offset in the {} plane ({})",
                    OFFSETS[n],
                    o,
                    ["XY", "ZX", "YZ"][plane as usize],
                    plane.code()
                ));
            }
            if off[a].is_none() && off[b].is_none() {
                return Err(format!(
                    "needs {} or {} (centre offsets in the {} plane)",
                    OFFSETS[a],
                    OFFSETS[b],
                    plane.code()
                ));
            }
            let c = [
                start[a] + off[a].unwrap_or(0.0),
                start[b] + off[b].unwrap_or(0.0),
            ];
            let r0 = (start[a] - c[0]).hypot(start[b] - c[1]);
            let r1 = (end[a] - c[0]).hypot(end[b] - c[1]);
            if r0 <= ZERO_LENGTH_MM {
                return Err("the arc's radius is zero".into());
            }
            if (r0 - r1).abs() > ARC_RADIUS_TOLERANCE_MM {
                return Err(format!(
                    "radius at the end ({r1:.4} mm) differs from the radius at the start \
                     ({r0:.4} mm) by {:.4} mm (tolerance {ARC_RADIUS_TOLERANCE_MM} mm)",
                    (r1 - r0).abs()
                ));
            }
            if chord <= ZERO_LENGTH_MM {
                // A full turn: the end is the start in the plane.
                end[a] = start[a];
                end[b] = start[b];
                c
            } else {
                // Onto the chord's perpendicular bisector: an exact circle through both ends.
                let u = [(end[a] - start[a]) / chord, (end[b] - start[b]) / chord];
                let along = (c[0] - mid[0]) * u[0] + (c[1] - mid[1]) * u[1];
                [c[0] - along * u[0], c[1] - along * u[1]]
            }
        }
        Centre::Radius(r) => {
            if r.abs() <= ZERO_LENGTH_MM {
                return Err("R is zero".into());
            }
            if chord <= ZERO_LENGTH_MM {
                return Err("start and end coincide in the plane: an R arc cannot be a \
                            full turn (use I/J/K)"
                    .into());
            }
            let half = chord / 2.0;
            if r.abs() < half - ARC_RADIUS_TOLERANCE_MM {
                return Err(format!(
                    "|R| = {:.4} mm is less than half the chord ({half:.4} mm)",
                    r.abs()
                ));
            }
            let h = (r * r - half * half).max(0.0).sqrt();
            let u = [(end[a] - start[a]) / chord, (end[b] - start[b]) / chord];
            let left = [-u[1], u[0]];
            // The short arc (R > 0) turns about a centre on its inside: left of the chord
            // for ccw, right for cw; the long one about the mirror image.
            let side = if ccw == (r > 0.0) { 1.0 } else { -1.0 };
            [mid[0] + side * h * left[0], mid[1] + side * h * left[1]]
        }
    };
    let mut centre = [0.0; 3];
    centre[a] = c[0];
    centre[b] = c[1];
    centre[n] = start[n];
    Ok(Block::Arc {
        line,
        start,
        end,
        centre,
        plane,
        ccw,
        feed,
    })
}

#[cfg(test)]
mod tests;
