//! The reader: source lines → evaluated [`Block`]s (comments, block delete, parameters,
//! expressions and O-word control flow). SKELETON: to be written.

use super::{Block, GcodeError, Params};

/// The longest source line read, in bytes.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// Where the reader gets its lines, with positions it can come back to (loops, calls).
pub trait Source {
    /// Replaces `buf` with the next line (without its `\n`); `false` at the end.
    fn read_line(&mut self, buf: &mut String) -> std::io::Result<bool>;
    /// The position of the next line.
    fn tell(&mut self) -> u64;
    /// Goes back (or forward) to a position [`Source::tell`] gave.
    fn seek(&mut self, pos: u64) -> std::io::Result<()>;
}

/// A program in memory.
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
    fn read_line(&mut self, _buf: &mut String) -> std::io::Result<bool> {
        let _ = (&self.text, self.pos);
        todo!()
    }
    fn tell(&mut self) -> u64 {
        todo!()
    }
    fn seek(&mut self, _pos: u64) -> std::io::Result<()> {
        todo!()
    }
}

/// A program file, read through a buffer.
pub struct FileSource {
    file: std::io::BufReader<std::fs::File>,
}

impl FileSource {
    /// The file at `path`.
    pub fn open(path: &std::path::Path) -> std::io::Result<Self> {
        Ok(FileSource {
            file: std::io::BufReader::new(std::fs::File::open(path)?),
        })
    }
}

impl Source for FileSource {
    fn read_line(&mut self, _buf: &mut String) -> std::io::Result<bool> {
        let _ = &self.file;
        todo!()
    }
    fn tell(&mut self) -> u64 {
        todo!()
    }
    fn seek(&mut self, _pos: u64) -> std::io::Result<()> {
        todo!()
    }
}

/// Source lines → blocks.
pub struct Reader<S: Source> {
    source: S,
    block_delete: bool,
    line: usize,
}

impl<S: Source> Reader<S> {
    /// Reads `source`; with `block_delete` on, lines starting with `/` are skipped.
    pub fn new(source: S, block_delete: bool) -> Self {
        Reader {
            source,
            block_delete,
            line: 0,
        }
    }

    /// The next block the program runs (`None` at the end of the text), parameters of the
    /// line assigned and control flow taken.
    pub fn next_block(&mut self, _params: &mut Params) -> Result<Option<Block>, GcodeError> {
        let _ = (&mut self.source, self.block_delete);
        todo!()
    }

    /// The 1-based number of the last line read (0 before the first).
    pub fn line(&self) -> usize {
        self.line
    }
}
