//! A block as the reader hands it to the interpreter: one source line with every expression
//! evaluated, parameters already assigned, control flow (O-words) already taken.

/// A G code in tenths: `G1` is 10, `G38.2` is 382, `G59.3` is 593.
pub type GCode = u16;

/// One evaluated source line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Block {
    /// 1-based source line.
    pub line: usize,
    /// G codes on the line, in tenths ([`GCode`]), in the order written.
    pub g: Vec<GCode>,
    /// M codes on the line, in the order written.
    pub m: Vec<u32>,
    /// Value words by letter: `words[i]` is the letter `b'A' + i`. G, M, N and O never
    /// appear here (G and M are above; N and O are the reader's).
    pub words: [Option<f64>; 26],
    /// Polar coordinates of X and Y: `@` (the distance) and `^` (the angle, degrees).
    pub polar: [Option<f64>; 2],
    /// `(MSG, …)`, `(PRINT, …)` or `(DEBUG, …)` text on the line, parameters substituted.
    pub message: Option<String>,
}

impl Block {
    /// The value of word `letter` (an ASCII capital), if the line has it.
    pub fn word(&self, letter: char) -> Option<f64> {
        let i = (letter as u32).wrapping_sub('A' as u32) as usize;
        self.words.get(i).copied().flatten()
    }

    /// Whether the line holds nothing for the interpreter.
    pub fn is_empty(&self) -> bool {
        self.g.is_empty()
            && self.m.is_empty()
            && self.message.is_none()
            && self.words.iter().all(Option::is_none)
            && self.polar.iter().all(Option::is_none)
    }
}
