//! The reader: source lines → evaluated [`Block`]s, the program's control flow taken.
//!
//! - [`lex`]: a line cleaned: blanks and comments out, letters lower-cased, block delete and
//!   `%` noted, the message comment kept.
//! - [`expr`]: numbers, parameters, expressions and functions; a line's words and parameter
//!   settings.
//! - [`flow`]: O-words (subroutines, conditionals, loops), with [`Source::seek`] to go back.
//!   A call of a subroutine the program does not define opens `name.ngc` on the subroutine
//!   path (LinuxCNC's `SUBROUTINE_PATH`): the file's own `o<name> sub` is run, its lines
//!   numbered within it, and an error there names the file.
//!
//! A line's values are all computed with the parameters as they were before the line; its
//! parameter settings are applied after it (RS274/NGC's rule), then its message is
//! formatted. Lines holding nothing for the interpreter (blank, comments, settings only,
//! O-words) give no block.
//!
//! Not read (an error naming the line): polar words `@` and `^`, spindle selection `$`,
//! Fanuc-style subprograms (`O` alone, `M98`/`M99` as calls), computed O-word labels
//! (`o#1`, `o[…]`), and LinuxCNC's `#<_ini[…]>` and
//! `#<_hal[…]>` parameters. Comments other than messages (`(LOG,…)`, `(ABORT,…)`, …) are
//! comments.

mod expr;
mod flow;
mod lex;
#[cfg(test)]
mod prop_tests;
#[cfg(test)]
mod tests;

use super::{Block, GcodeError, Params};
use expr::{Cursor, ParamRef};
use flow::{Ctl, Kw, Skip};
use std::collections::HashMap;
use std::io::{self, BufRead};

/// The longest source line read, in bytes.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// How many times loops may go round without the reader giving a block (then it is an error,
/// so that a program cannot hang the reader).
const MAX_PASSES: u64 = 1_000_000;
/// How many lines may be read again (after a loop went back or a subroutine was called)
/// without the reader giving a block: the same guard for long loop bodies and for
/// subroutines calling each other many times.
const MAX_REREAD: u64 = 10_000_000;

/// Where the reader gets its lines, with positions it can come back to (loops, calls).
pub trait Source {
    /// Replaces `buf` with the next line (without its `\n`); `false` at the end. A line
    /// longer than [`MAX_LINE_BYTES`] or not UTF-8 is an error of kind
    /// [`io::ErrorKind::InvalidData`], after which the next call reads the line after it.
    fn read_line(&mut self, buf: &mut String) -> io::Result<bool>;
    /// The position of the next line.
    fn tell(&mut self) -> u64;
    /// Goes back (or forward) to a position [`Source::tell`] gave.
    fn seek(&mut self, pos: u64) -> io::Result<()>;
}

fn too_long() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("line longer than {MAX_LINE_BYTES} bytes"),
    )
}

/// A program in memory; positions are byte offsets.
pub struct TextSource {
    text: String,
    pos: usize,
}

impl TextSource {
    /// The text `text`.
    pub fn new(text: String) -> Self {
        TextSource { text, pos: 0 }
    }
}

impl Source for TextSource {
    fn read_line(&mut self, buf: &mut String) -> io::Result<bool> {
        buf.clear();
        let Some(rest) = self.text.get(self.pos..).filter(|r| !r.is_empty()) else {
            return Ok(false);
        };
        let (line, used) = match rest.find('\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        if line.len() > MAX_LINE_BYTES {
            return Err(too_long());
        }
        buf.push_str(line);
        Ok(true)
    }

    fn tell(&mut self) -> u64 {
        self.pos as u64
    }

    fn seek(&mut self, pos: u64) -> io::Result<()> {
        match usize::try_from(pos) {
            Ok(p) if self.text.is_char_boundary(p) => {
                self.pos = p;
                Ok(())
            }
            _ => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("position {pos} is not in the text"),
            )),
        }
    }
}

/// A program file, read through a buffer; positions are byte offsets in the file.
pub struct FileSource {
    file: io::BufReader<std::fs::File>,
    /// The file offset of the next byte the buffer gives.
    pos: u64,
}

impl FileSource {
    /// The file at `path`.
    pub fn open(path: &std::path::Path) -> io::Result<Self> {
        Ok(FileSource {
            file: io::BufReader::new(std::fs::File::open(path)?),
            pos: 0,
        })
    }
}

impl Source for FileSource {
    fn read_line(&mut self, buf: &mut String) -> io::Result<bool> {
        let mut bytes = std::mem::take(buf).into_bytes();
        bytes.clear();
        let mut any = false;
        let mut long = false;
        loop {
            let avail = match self.file.fill_buf() {
                Ok(a) => a,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if avail.is_empty() {
                break;
            }
            any = true;
            let (chunk, used, done) = match avail.iter().position(|&b| b == b'\n') {
                Some(i) => (&avail[..i], i + 1, true),
                None => (avail, avail.len(), false),
            };
            // Past the limit nothing more is kept: the rest of the line is only passed over.
            if !long {
                if bytes.len() + chunk.len() > MAX_LINE_BYTES {
                    long = true;
                    bytes = Vec::new();
                } else {
                    bytes.extend_from_slice(chunk);
                }
            }
            self.file.consume(used);
            self.pos += used as u64;
            if done {
                break;
            }
        }
        if long {
            return Err(too_long());
        }
        match String::from_utf8(bytes) {
            Ok(s) => *buf = s,
            Err(_) => {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    "the line is not valid UTF-8",
                ))
            }
        }
        Ok(any)
    }

    fn tell(&mut self) -> u64 {
        self.pos
    }

    fn seek(&mut self, pos: u64) -> io::Result<()> {
        // Relative to where the buffer stands: a short loop stays within the buffer.
        let delta = i64::try_from(i128::from(pos) - i128::from(self.pos))
            .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "position out of range"))?;
        self.file.seek_relative(delta)?;
        self.pos = pos;
        Ok(())
    }
}

/// Subroutine files a program may open (`o<name> call` of `name.ngc`).
const MAX_SUB_FILES: usize = 256;
/// A position in [`Sources`]: the offset in its file, the file's index above these bits.
const FILE_SHIFT: u32 = 48;

/// The program's source and the subroutine files its calls opened, as one source: a
/// position is the offset in its file with the file's index (0: the program) in the bits
/// from [`FILE_SHIFT`] up, so a call into a file and the return from it are a seek.
struct Sources<S> {
    main: S,
    /// Each file's name as the errors show it, and the file.
    files: Vec<(String, FileSource)>,
    /// The file lines are read from (0: the program).
    cur: usize,
}

impl<S: Source> Source for Sources<S> {
    fn read_line(&mut self, buf: &mut String) -> io::Result<bool> {
        match self.cur {
            0 => self.main.read_line(buf),
            k => self.files[k - 1].1.read_line(buf),
        }
    }

    fn tell(&mut self) -> u64 {
        let p = match self.cur {
            0 => self.main.tell(),
            k => self.files[k - 1].1.tell(),
        };
        ((self.cur as u64) << FILE_SHIFT) | p
    }

    fn seek(&mut self, pos: u64) -> io::Result<()> {
        let k = (pos >> FILE_SHIFT) as usize;
        let p = pos & ((1 << FILE_SHIFT) - 1);
        match k {
            0 => self.main.seek(p)?,
            k if k <= self.files.len() => self.files[k - 1].1.seek(p)?,
            _ => {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("no subroutine file {k}"),
                ))
            }
        }
        self.cur = k;
        Ok(())
    }
}

/// Source lines → blocks.
pub struct Reader<S: Source> {
    source: Sources<S>,
    /// Where a call looks for a subroutine file.
    sub_path: Vec<std::path::PathBuf>,
    block_delete: bool,
    /// The last line read.
    line: usize,
    /// The line read and its cleaned code (kept for their allocations).
    buf: String,
    code: Vec<u8>,
    /// The line's parameter settings, applied after it.
    sets: Vec<(ParamRef, f64)>,
    /// A line other than blanks has been read (a `%` after it ends the program).
    started: bool,
    /// The end of the program was met, or an error.
    done: bool,
    /// `#<_value>` and `#<_value_returned>` have been given their first values.
    primed: bool,
    /// Open constructs, innermost last.
    stack: Vec<Ctl>,
    /// Lines being skipped, if any.
    skip: Option<Skip>,
    /// Subroutines known: label → (position of the body, line of the `sub`).
    subs: HashMap<String, (u64, usize)>,
    /// The source has been scanned for every `sub`.
    scanned: bool,
    /// Loop passes since the last block given, and how many are allowed.
    passes: u64,
    max_passes: u64,
    /// Lines read since the last block given after going back or calling (counted from
    /// the first such jump), and how many are allowed.
    rereading: bool,
    reread: u64,
    max_reread: u64,
    /// A subroutine has just returned: an empty block marks it for the interpreter (M73's
    /// restore happens there, before the caller's next line is read).
    returned: Option<usize>,
}

impl<S: Source> Reader<S> {
    /// Reads `source`; with `block_delete` on, lines starting with `/` are skipped (off, the
    /// `/` is ignored).
    pub fn new(source: S, block_delete: bool) -> Self {
        Reader {
            source: Sources {
                main: source,
                files: Vec::new(),
                cur: 0,
            },
            sub_path: Vec::new(),
            block_delete,
            line: 0,
            buf: String::new(),
            code: Vec::new(),
            sets: Vec::new(),
            started: false,
            done: false,
            primed: false,
            stack: Vec::new(),
            skip: None,
            subs: HashMap::new(),
            scanned: false,
            passes: 0,
            max_passes: MAX_PASSES,
            rereading: false,
            returned: None,
            reread: 0,
            max_reread: MAX_REREAD,
        }
    }

    /// Looks for the subroutine files of calls in `dirs`, in order.
    pub fn with_subroutine_path(mut self, dirs: Vec<std::path::PathBuf>) -> Self {
        self.sub_path = dirs;
        self
    }

    /// The next block the program runs (`None` at the end of the text or after a closing
    /// `%`), parameters of the line assigned and control flow taken. After an error (or the
    /// end) it gives `None`.
    pub fn next_block(&mut self, params: &mut Params) -> Result<Option<Block>, GcodeError> {
        loop {
            match self.next_item(params)? {
                Some(b) if b.is_empty() => continue,
                b => return Ok(b),
            }
        }
    }

    /// As [`Reader::next_block`], and an empty block (of the `endsub` or `return` line) each
    /// time a subroutine returns, before the caller's next line is read: the interpreter
    /// restores what M73 saved there.
    pub fn next_item(&mut self, params: &mut Params) -> Result<Option<Block>, GcodeError> {
        if self.done {
            return Ok(None);
        }
        if !self.primed {
            // LinuxCNC's predefined `#<_value>` and `#<_value_returned>`: 0 before any
            // subroutine returns.
            self.primed = true;
            for name in ["_value", "_value_returned"] {
                if params.named(name).is_none() {
                    params.set_named(name, 0.0);
                }
            }
        }
        let mut r = self.read_block(params);
        if !matches!(r, Ok(Some(_))) {
            self.done = true;
        }
        if let (Err(e), k @ 1..) = (&mut r, self.source.cur) {
            // (a line of a subroutine file: its number is the file's)
            e.message = format!("{} (in {})", e.message, self.source.files[k - 1].0);
        }
        r
    }

    /// The 1-based number of the last line read (0 before the first).
    pub fn line(&self) -> usize {
        self.line
    }

    /// Reads lines until one gives a block, or the end.
    fn read_block(&mut self, params: &mut Params) -> Result<Option<Block>, GcodeError> {
        loop {
            let pos = self.source.tell();
            if self.rereading {
                self.reread += 1;
                if self.reread > self.max_reread {
                    return Err(GcodeError::new(
                        self.line,
                        format!(
                            "{} lines read in loops or subroutines without a block to run",
                            self.max_reread
                        ),
                    ));
                }
            }
            match self.source.read_line(&mut self.buf) {
                Ok(true) => self.line += 1,
                Ok(false) => return self.end(),
                Err(e) => {
                    self.line += 1;
                    return Err(GcodeError::new(self.line, e.to_string()));
                }
            }
            let cleaned =
                lex::clean(&self.buf, &mut self.code).map_err(|m| GcodeError::new(self.line, m))?;
            if cleaned.blank {
                continue;
            }
            if cleaned.percent {
                if self.started {
                    return self.end();
                }
                self.started = true;
                continue;
            }
            self.started = true;
            if cleaned.slash && self.block_delete {
                continue;
            }
            let code = std::mem::take(&mut self.code);
            let r = self.run_line(&code, &cleaned, pos, params);
            self.code = code;
            if let Some(b) = r? {
                self.passes = 0;
                self.rereading = false;
                self.reread = 0;
                return Ok(Some(b));
            }
            if let Some(line) = self.returned.take() {
                // (not a block run: the loop guards keep counting)
                return Ok(Some(Block {
                    line,
                    ..Block::default()
                }));
            }
        }
    }

    /// One cleaned line: an O-word taken, or a block made (`None` when it holds nothing).
    fn run_line(
        &mut self,
        code: &[u8],
        cleaned: &lex::Cleaned,
        pos: u64,
        params: &mut Params,
    ) -> Result<Option<Block>, GcodeError> {
        let line = self.line;
        let at = |m: String| GcodeError::new(line, m);
        params.set_predefined(crate::gcode::params::Predefined::Line, 0, line as f64);
        let mut cur = Cursor::new(code);
        cur.skip_line_number().map_err(at)?;
        if cur.peek() == Some(b'o') {
            let (label, word) = cur.o_head().map_err(at)?;
            let Some(kw) = Kw::parse(word) else {
                return Err(at(format!(
                    "unknown O-word keyword '{}' after o{}",
                    String::from_utf8_lossy(word),
                    flow::show(&label)
                )));
            };
            if let Some(skip) = &self.skip {
                if !skip.ends_at(&label, kw) {
                    return Ok(None);
                }
                let run = skip.run_end;
                self.skip = None;
                if !run {
                    return Ok(None);
                }
            }
            self.o_word(label, kw, &mut cur, pos, params)?;
            return Ok(None);
        }
        if self.skip.is_some() {
            return Ok(None);
        }
        let mut block = Block {
            line,
            ..Block::default()
        };
        self.sets.clear();
        cur.items(params, &mut block, &mut self.sets).map_err(at)?;
        for (r, v) in self.sets.drain(..) {
            match r {
                ParamRef::Number(n) => {
                    params.set(n, v);
                }
                ParamRef::Named(name) => {
                    if !params.set_named(&name, v) {
                        return Err(at(format!(
                            "#<{name}> is a predefined parameter: it may be read, not set"
                        )));
                    }
                }
            }
        }
        if let Some(range) = cleaned.message.clone() {
            let text = self.buf.get(range).unwrap_or("");
            block.message = Some(lex::substitute(text, params).map_err(at)?);
        }
        Ok((!block.is_empty()).then_some(block))
    }

    /// The end of the text (or a closing `%`): an error if something is left open.
    fn end(&mut self) -> Result<Option<Block>, GcodeError> {
        if let Some(skip) = &self.skip {
            let message = format!("{}: its end never comes", skip.what);
            return Err(GcodeError::new(skip.line, message));
        }
        if let Some(c) = self.stack.last() {
            return Err(c.unclosed());
        }
        Ok(None)
    }

    /// Notes every subroutine in the source (to call one defined after its call), then reads
    /// on from where it was.
    fn scan_subs(&mut self) -> Result<(), GcodeError> {
        self.scanned = true;
        self.scan_file(0, None)
    }

    /// Notes every subroutine of file `k` of the sources (0: the program; a subroutine file
    /// only its `only`, as LinuxCNC, which runs nothing else of it), then reads on from where
    /// it was.
    fn scan_file(&mut self, k: usize, only: Option<&str>) -> Result<(), GcodeError> {
        let (back, back_line) = (self.source.tell(), self.line);
        self.goto((k as u64) << FILE_SHIFT, 0)?;
        let mut line = 0;
        let mut started = false;
        let mut buf = String::new();
        let mut code = Vec::new();
        loop {
            match self.source.read_line(&mut buf) {
                Ok(true) => line += 1,
                Ok(false) => break,
                Err(e) if e.kind() == io::ErrorKind::InvalidData => {
                    line += 1;
                    continue;
                }
                Err(e) => return Err(GcodeError::new(line + 1, e.to_string())),
            }
            let Ok(cleaned) = lex::clean(&buf, &mut code) else {
                started = true;
                continue;
            };
            if cleaned.percent && started {
                break;
            }
            started |= !cleaned.blank;
            if cleaned.slash && self.block_delete {
                continue;
            }
            let mut cur = Cursor::new(&code);
            if cur.skip_line_number().is_err() || cur.peek() != Some(b'o') {
                continue;
            }
            match cur.o_head() {
                Ok((label, b"sub")) if only.is_none_or(|o| o == label) => {
                    let body = self.source.tell();
                    self.note_sub(&label, body, line)?;
                }
                _ => {}
            }
        }
        self.goto(back, back_line)
    }

    /// `o<label> call` of a subroutine the program does not define: `label.ngc` from the
    /// first directory of the subroutine path that has it, opened and its `o<label> sub`
    /// noted (only it: another subroutine in the file is not callable, as in LinuxCNC).
    /// `Ok(false)` when no directory has it.
    fn open_sub_file(&mut self, label: &str) -> Result<bool, GcodeError> {
        let name = format!("{label}.ngc");
        let Some(path) = self
            .sub_path
            .iter()
            .map(|d| d.join(&name))
            .find(|p| p.is_file())
        else {
            return Ok(false);
        };
        if self.source.files.len() >= MAX_SUB_FILES {
            return Err(GcodeError::new(
                self.line,
                format!("{name}: more than {MAX_SUB_FILES} subroutine files"),
            ));
        }
        let file = FileSource::open(&path).map_err(|e| {
            GcodeError::new(self.line, format!("cannot open {}: {e}", path.display()))
        })?;
        self.source.files.push((path.display().to_string(), file));
        let k = self.source.files.len();
        self.scan_file(k, Some(label))?;
        if !self.subs.contains_key(label) {
            return Err(GcodeError::new(
                self.line,
                format!(
                    "o<{label}> call: {} does not define o<{label}> sub",
                    path.display()
                ),
            ));
        }
        Ok(true)
    }
}
