//! Values on a cleaned line ([`super::lex`]): numbers, parameters (`#1`, `##1`, `#[expr]`,
//! `#<name>`), expressions in brackets with LinuxCNC's operators, and functions; then the
//! line's items: words, parameter settings, and the head of an O-word.
//!
//! Binary operators, highest precedence first, left to right within a level (LinuxCNC's
//! table, `**` included):
//!
//! | level | operators |
//! | --- | --- |
//! | 5 | `**` |
//! | 4 | `*` `/` `MOD` |
//! | 3 | `+` `-` |
//! | 2 | `EQ` `NE` `GT` `GE` `LT` `LE` |
//! | 1 | `AND` `OR` `XOR` |
//!
//! A sign before a value binds tighter than any of them (`[-2**2]` is 4). `MOD`'s result is
//! never negative (`[-7 MOD 3]` is 2); `EQ`, `NE`, `LE` and `GE` take values within 1e-6 as
//! equal; logical operators give 1 or 0 (non-zero is true); trigonometry is in degrees;
//! `FIX` rounds down, `FUP` up, `ROUND` half away from zero.

use super::super::{Block, GCode, Params};

/// How deeply values may nest (brackets, signs, `#` of `#`, functions).
pub(super) const MAX_NESTING: u32 = 64;
/// Two values closer than this are equal for `EQ`, `NE`, `LE` and `GE` (LinuxCNC's).
const TOLERANCE_EQUAL: f64 = 1e-6;
/// How far a value may be from an integer where an integer is wanted (LinuxCNC's).
const TOLERANCE_INTEGER: f64 = 1e-4;

/// A parameter, as set or read.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum ParamRef {
    /// `#n`, `n` within range.
    Number(u32),
    /// `#<name>`, lower-case, without blanks.
    Named(String),
}

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Op::Pow => 5,
            Op::Mul | Op::Div | Op::Mod => 4,
            Op::Add | Op::Sub => 3,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 2,
            Op::And | Op::Or | Op::Xor => 1,
        }
    }

    fn apply(self, a: f64, b: f64) -> Result<f64, String> {
        let truth = |t: bool| if t { 1.0 } else { 0.0 };
        let v = match self {
            Op::Pow => {
                if a < 0.0 && b.fract() != 0.0 {
                    return Err(format!("{a} raised to the non-integer power {b}"));
                }
                a.powf(b)
            }
            Op::Mul => a * b,
            Op::Div => {
                if b == 0.0 {
                    return Err("division by zero".into());
                }
                a / b
            }
            Op::Mod => {
                if b == 0.0 {
                    return Err("MOD by zero".into());
                }
                let r = a % b;
                if r < 0.0 {
                    r + b.abs()
                } else {
                    r
                }
            }
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Eq => truth((a - b).abs() < TOLERANCE_EQUAL),
            Op::Ne => truth((a - b).abs() >= TOLERANCE_EQUAL),
            Op::Gt => truth(a > b),
            Op::Ge => truth((a - b).abs() < TOLERANCE_EQUAL || a >= b),
            Op::Lt => truth(a < b),
            Op::Le => truth((a - b).abs() < TOLERANCE_EQUAL || a <= b),
            Op::And => truth(a != 0.0 && b != 0.0),
            Op::Or => truth(a != 0.0 || b != 0.0),
            Op::Xor => truth((a != 0.0) != (b != 0.0)),
        };
        finite(v)
    }
}

/// Word operators, as they appear lower-cased (none is a prefix of another).
const WORD_OPS: [(&[u8], Op); 10] = [
    (b"mod", Op::Mod),
    (b"and", Op::And),
    (b"xor", Op::Xor),
    (b"or", Op::Or),
    (b"eq", Op::Eq),
    (b"ne", Op::Ne),
    (b"gt", Op::Gt),
    (b"ge", Op::Ge),
    (b"lt", Op::Lt),
    (b"le", Op::Le),
];

fn finite(v: f64) -> Result<f64, String> {
    if v.is_nan() {
        Err("calculation resulted in 'not a number'".into())
    } else if v.is_infinite() {
        Err("calculation resulted in infinity".into())
    } else {
        Ok(v)
    }
}

/// A byte for a message: itself when printable ASCII, else its code.
pub(super) fn show(b: u8) -> String {
    if b.is_ascii_graphic() {
        format!("'{}'", char::from(b))
    } else {
        format!("byte 0x{b:02x}")
    }
}

/// `v` as an integer, if within [`TOLERANCE_INTEGER`] of one.
fn integer(v: f64) -> Option<f64> {
    let r = v.round();
    ((v - r).abs() <= TOLERANCE_INTEGER).then_some(r)
}

/// A position on a cleaned line.
pub(super) struct Cursor<'a> {
    s: &'a [u8],
    i: usize,
    depth: u32,
}

impl<'a> Cursor<'a> {
    /// At the start of `code`.
    pub fn new(code: &'a [u8]) -> Self {
        Cursor {
            s: code,
            i: 0,
            depth: 0,
        }
    }

    /// The byte at the cursor.
    pub fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn peek_at(&self, k: usize) -> Option<u8> {
        self.s.get(self.i + k).copied()
    }

    fn bump(&mut self) {
        self.i += 1;
    }

    /// Whether the line is read to its end.
    pub fn at_end(&self) -> bool {
        self.i >= self.s.len()
    }

    /// Takes `b` if it is next.
    pub fn eat(&mut self, b: u8) -> bool {
        let hit = self.peek() == Some(b);
        if hit {
            self.bump();
        }
        hit
    }

    fn expect(&mut self, b: u8, what: &str) -> Result<(), String> {
        if self.eat(b) {
            Ok(())
        } else {
            Err(format!(
                "expected '{}' {what}, found {}",
                char::from(b),
                self.found()
            ))
        }
    }

    /// What is at the cursor, for a message.
    fn found(&self) -> String {
        match self.peek() {
            Some(b) => show(b),
            None => "the end of the line".into(),
        }
    }

    /// A run of lower-case letters.
    fn letters(&mut self) -> &'a [u8] {
        let start = self.i;
        while matches!(self.peek(), Some(b'a'..=b'z')) {
            self.bump();
        }
        &self.s[start..self.i]
    }

    /// Skips a line number (`N` and digits, with an optional fraction) at the cursor.
    pub fn skip_line_number(&mut self) -> Result<(), String> {
        if self.eat(b'n') {
            let start = self.i;
            while matches!(self.peek(), Some(b'0'..=b'9' | b'.')) {
                self.bump();
            }
            if self.i == start {
                return Err("N without a line number".into());
            }
        }
        Ok(())
    }

    /// A number: an optional sign, digits with an optional decimal point (`1.`, `.5`).
    fn number(&mut self) -> Result<f64, String> {
        let start = self.i;
        if matches!(self.peek(), Some(b'+' | b'-')) {
            self.bump();
        }
        let digits_start = self.i;
        while matches!(self.peek(), Some(b'0'..=b'9' | b'.')) {
            self.bump();
        }
        let digits = &self.s[digits_start..self.i];
        if !digits.iter().any(u8::is_ascii_digit) {
            self.i = start;
            return Err(format!("expected a number, found {}", self.found()));
        }
        // ASCII only, so this is text; a second '.' fails the parse.
        let text = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
        text.parse::<f64>()
            .map_err(|_| format!("bad number '{text}'"))
            .and_then(finite)
    }

    /// A value: a number, a parameter, a bracketed expression, a function, or a signed value.
    pub fn value(&mut self, p: &Params) -> Result<f64, String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!("values nested deeper than {MAX_NESTING}"));
        }
        let v = self.value_inner(p);
        self.depth -= 1;
        finite(v?)
    }

    fn value_inner(&mut self, p: &Params) -> Result<f64, String> {
        let signed_value = !matches!(self.peek_at(1), None | Some(b'0'..=b'9' | b'.'));
        match self.peek() {
            Some(b'[') => {
                self.bump();
                self.expression(p)
            }
            Some(b'#') => {
                self.bump();
                let r = self.param_ref(p)?;
                read_param(p, &r)
            }
            Some(b'+') if signed_value => {
                self.bump();
                self.value(p)
            }
            Some(b'-') if signed_value => {
                self.bump();
                Ok(-self.value(p)?)
            }
            Some(b'a'..=b'z') => self.function(p),
            _ => self.number(),
        }
    }

    /// The rest of a bracketed expression, its `[` taken, up to and with its `]`.
    fn expression(&mut self, p: &Params) -> Result<f64, String> {
        let v = self.binary(p, 1)?;
        if self.eat(b']') {
            Ok(v)
        } else if self.at_end() {
            Err("expression not closed (missing ']')".into())
        } else {
            Err(format!("unknown operator at {}", self.found()))
        }
    }

    /// Operands joined by operators of precedence `min` or above, left to right.
    fn binary(&mut self, p: &Params, min: u8) -> Result<f64, String> {
        let mut left = self.value(p)?;
        loop {
            let save = self.i;
            let Some(op) = self.operator() else {
                return Ok(left);
            };
            if op.precedence() < min {
                self.i = save;
                return Ok(left);
            }
            let right = self.binary(p, op.precedence() + 1)?;
            left = op.apply(left, right)?;
        }
    }

    /// A binary operator at the cursor, taken.
    fn operator(&mut self) -> Option<Op> {
        let op = match self.peek()? {
            b'+' => Op::Add,
            b'-' => Op::Sub,
            b'/' => Op::Div,
            b'*' if self.peek_at(1) == Some(b'*') => {
                self.i += 2;
                return Some(Op::Pow);
            }
            b'*' => Op::Mul,
            _ => {
                let (word, op) = WORD_OPS
                    .iter()
                    .find(|(w, _)| self.s.get(self.i..self.i + w.len()) == Some(*w))?;
                self.i += word.len();
                return Some(*op);
            }
        };
        self.bump();
        Some(op)
    }

    /// A function: `NAME[arg]`, `ATAN[y]/[x]`, `EXISTS[#<name>]` or `EXISTS[#n]`.
    fn function(&mut self, p: &Params) -> Result<f64, String> {
        let name = self.letters();
        let shown = String::from_utf8_lossy(name).to_ascii_uppercase();
        if self.peek() != Some(b'[') {
            return Err(format!("unknown word '{shown}' where a value should be"));
        }
        self.bump();
        if name == b"exists" {
            self.expect(b'#', "in EXISTS[#<name>] or EXISTS[#n]")?;
            let there = if self.peek() == Some(b'<') {
                let n = self.name()?;
                p.named(&n).is_some()
            } else {
                // A numbered parameter exists when its number is in range (LinuxCNC).
                let v = self.value(p)?;
                integer(v).is_some_and(|n| n >= 1.0 && p.get(n as u32).is_some())
            };
            self.expect(b']', "after EXISTS's parameter")?;
            return Ok(if there { 1.0 } else { 0.0 });
        }
        let x = self.expression(p)?;
        let deg = |r: f64| r.to_degrees();
        let v = match name {
            b"abs" => x.abs(),
            b"acos" | b"asin" => {
                if !(-1.0..=1.0).contains(&x) {
                    return Err(format!("{shown} of {x}, outside [-1, 1]"));
                }
                if name == b"acos" {
                    deg(x.acos())
                } else {
                    deg(x.asin())
                }
            }
            b"atan" => {
                self.expect(b'/', "after ATAN's first argument: ATAN[y]/[x]")?;
                self.expect(b'[', "for ATAN's second argument: ATAN[y]/[x]")?;
                let d = self.expression(p)?;
                deg(x.atan2(d))
            }
            b"cos" => x.to_radians().cos(),
            b"sin" => x.to_radians().sin(),
            b"tan" => x.to_radians().tan(),
            b"exp" => x.exp(),
            b"fix" => x.floor(),
            b"fup" => x.ceil(),
            b"round" => x.round(),
            b"ln" => {
                if x <= 0.0 {
                    return Err(format!("LN of {x} (zero or negative)"));
                }
                x.ln()
            }
            b"sqrt" => {
                if x < 0.0 {
                    return Err(format!("SQRT of the negative {x}"));
                }
                x.sqrt()
            }
            _ => return Err(format!("unknown function '{shown}'")),
        };
        finite(v)
    }

    /// A `<name>`: lower-case already, blanks already gone.
    fn name(&mut self) -> Result<String, String> {
        self.expect(b'<', "to open a name")?;
        let start = self.i;
        while self.peek().is_some_and(|b| b != b'>') {
            self.bump();
        }
        if self.at_end() {
            return Err("name not closed (missing '>')".into());
        }
        let name = &self.s[start..self.i];
        self.bump();
        if name.is_empty() {
            return Err("empty name '<>'".into());
        }
        String::from_utf8(name.to_vec()).map_err(|_| "name is not text".to_string())
    }

    /// The parameter after a `#` (taken): `<name>` or a value giving its number.
    pub fn param_ref(&mut self, p: &Params) -> Result<ParamRef, String> {
        if self.peek() == Some(b'<') {
            return self.name().map(ParamRef::Named);
        }
        let v = self.value(p)?;
        let n = integer(v).ok_or_else(|| format!("parameter number {v} is not an integer"))?;
        if n < 1.0 || p.get(n as u32).is_none() {
            return Err(format!("parameter #{n} out of range"));
        }
        Ok(ParamRef::Number(n as u32))
    }

    /// The line's items after its line number: words into `block`, parameter settings into
    /// `sets` (to be applied after the line).
    pub fn items(
        &mut self,
        p: &Params,
        block: &mut Block,
        sets: &mut Vec<(ParamRef, f64)>,
    ) -> Result<(), String> {
        while let Some(c) = self.peek() {
            self.bump();
            match c {
                b'#' => {
                    let r = self.param_ref(p)?;
                    self.expect(b'=', "after the parameter (a parameter setting)")?;
                    let v = self.value(p)?;
                    sets.push((r, v));
                }
                b'g' => {
                    let v = self.value(p)?;
                    block.g.push(g_code(v)?);
                }
                b'm' => {
                    let v = self.value(p)?;
                    block.m.push(m_code(v)?);
                }
                b'@' | b'^' => {
                    let v = self.value(p)?;
                    let slot = &mut block.polar[usize::from(c == b'^')];
                    if slot.is_some() {
                        return Err(format!("two {} words on one line", char::from(c)));
                    }
                    *slot = Some(v);
                }
                b'n' => return Err("N (line number) must start the line".into()),
                b'o' => return Err("O-word must start the line".into()),
                b'a'..=b'z' => {
                    let v = self.value(p)?;
                    let slot = &mut block.words[usize::from(c - b'a')];
                    if slot.is_some() {
                        let l = char::from(c.to_ascii_uppercase());
                        return Err(format!("two {l} words on one line"));
                    }
                    *slot = Some(v);
                }
                _ => return Err(format!("unexpected {}", show(c))),
            }
        }
        Ok(())
    }

    /// The head of an O-word line, the cursor on its `o`: the label (digits without leading
    /// zeros, or a name) and the keyword; the cursor is left on the arguments.
    pub fn o_head(&mut self) -> Result<(String, &'a [u8]), String> {
        self.expect(b'o', "")?;
        let label = if self.peek() == Some(b'<') {
            self.name()?
        } else {
            let start = self.i;
            while matches!(self.peek(), Some(b'0'..=b'9')) {
                self.bump();
            }
            let digits = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
            if digits.is_empty() {
                return Err(format!(
                    "O-word without a label (a number or <name>): found {}",
                    self.found()
                ));
            }
            let trimmed = digits.trim_start_matches('0');
            if trimmed.is_empty() { "0" } else { trimmed }.to_string()
        };
        Ok((label, self.letters()))
    }

    /// An O-word's bracketed argument: `[expr]`.
    pub fn bracketed(&mut self, p: &Params) -> Result<f64, String> {
        if self.peek() != Some(b'[') {
            return Err(format!(
                "expected '[' and an expression, found {}",
                self.found()
            ));
        }
        self.value(p)
    }
}

/// A parameter's value: numbered ones are 0 until set; named ones must have been set.
pub(super) fn read_param(p: &Params, r: &ParamRef) -> Result<f64, String> {
    match r {
        ParamRef::Number(n) => p
            .get(*n)
            .ok_or_else(|| format!("parameter #{n} out of range")),
        ParamRef::Named(name) => p
            .named(name)
            .ok_or_else(|| format!("parameter #<{name}> is not defined")),
    }
}

/// A G word's value in tenths: a multiple of 0.1 (within 1e-6) from 0 to 99.9.
fn g_code(v: f64) -> Result<GCode, String> {
    let tenths = (v * 10.0).round();
    if (v - tenths / 10.0).abs() > 1e-6 {
        return Err(format!("G{v}: not a G code (G codes are multiples of 0.1)"));
    }
    if tenths < 0.0 {
        return Err(format!("negative G code G{v}"));
    }
    if tenths > 999.0 {
        return Err(format!("G{v}: G code out of range"));
    }
    Ok(tenths as GCode)
}

/// An M word's value: a whole number from 0 to 9999.
fn m_code(v: f64) -> Result<u32, String> {
    let n = integer(v).ok_or_else(|| format!("M{v}: M codes are whole numbers"))?;
    if !(0.0..=9999.0).contains(&n) {
        return Err(format!("M{v}: M code out of range"));
    }
    Ok(n as u32)
}
