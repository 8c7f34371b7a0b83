//! O-words: subroutines, conditionals and loops, as LinuxCNC runs them.
//!
//! The reader keeps a stack of the open constructs ([`Ctl`]) and, for the ones it may go back
//! to, the source position of one O-word line each; going back is [`Source::seek`]. Skipping
//! forward (a false `if`, a `break`, a subroutine's body met in the main flow) reads lines
//! until the O-word with the same label and one of the awaited keywords ([`Skip`]); the lines
//! in between are only cleaned, never evaluated. A subroutine called before its definition is
//! found by scanning the source once for every `sub` line. So memory is bounded by the
//! deepest nesting and the number of subroutines, whatever the program's length.
//!
//! Labels are local to a call, as in LinuxCNC: `break`, `endwhile` and the like only see the
//! constructs opened in the current subroutine call.

use super::expr::Cursor;
use super::{Reader, Source};
use crate::gcode::{GcodeError, Params, CALL_PARAMS};

/// The deepest subroutine nesting.
pub(super) const MAX_CALL_DEPTH: usize = 64;

/// An O-word keyword.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kw {
    Sub,
    Endsub,
    Return,
    Call,
    Do,
    While,
    Endwhile,
    Repeat,
    Endrepeat,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
}

impl Kw {
    /// The keyword spelled `s` (lower-case).
    pub fn parse(s: &[u8]) -> Option<Kw> {
        Some(match s {
            b"sub" => Kw::Sub,
            b"endsub" => Kw::Endsub,
            b"return" => Kw::Return,
            b"call" => Kw::Call,
            b"do" => Kw::Do,
            b"while" => Kw::While,
            b"endwhile" => Kw::Endwhile,
            b"repeat" => Kw::Repeat,
            b"endrepeat" => Kw::Endrepeat,
            b"if" => Kw::If,
            b"elseif" => Kw::Elseif,
            b"else" => Kw::Else,
            b"endif" => Kw::Endif,
            b"break" => Kw::Break,
            b"continue" => Kw::Continue,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Kw::Sub => "sub",
            Kw::Endsub => "endsub",
            Kw::Return => "return",
            Kw::Call => "call",
            Kw::Do => "do",
            Kw::While => "while",
            Kw::Endwhile => "endwhile",
            Kw::Repeat => "repeat",
            Kw::Endrepeat => "endrepeat",
            Kw::If => "if",
            Kw::Elseif => "elseif",
            Kw::Else => "else",
            Kw::Endif => "endif",
            Kw::Break => "break",
            Kw::Continue => "continue",
        }
    }
}

/// An open construct.
#[derive(Debug, Clone)]
pub(super) enum Ctl {
    /// `if`: whether a branch has been taken, whether `else` has been met.
    If {
        label: String,
        line: usize,
        taken: bool,
        in_else: bool,
    },
    /// `while`: the position of the `while` line itself (its condition is read again).
    While {
        label: String,
        line: usize,
        pos: u64,
    },
    /// `do`: the position after the `do` line.
    Do {
        label: String,
        line: usize,
        pos: u64,
    },
    /// `repeat`: the position after the `repeat` line, and the passes left after this one.
    Repeat {
        label: String,
        line: usize,
        pos: u64,
        left: u64,
    },
    /// A subroutine call: the position after the `call` line.
    Call {
        label: String,
        line: usize,
        pos: u64,
    },
}

impl Ctl {
    fn label(&self) -> &str {
        match self {
            Ctl::If { label, .. }
            | Ctl::While { label, .. }
            | Ctl::Do { label, .. }
            | Ctl::Repeat { label, .. }
            | Ctl::Call { label, .. } => label,
        }
    }

    fn line(&self) -> usize {
        match self {
            Ctl::If { line, .. }
            | Ctl::While { line, .. }
            | Ctl::Do { line, .. }
            | Ctl::Repeat { line, .. }
            | Ctl::Call { line, .. } => *line,
        }
    }

    fn kind(&self) -> &'static str {
        match self {
            Ctl::If { .. } => "if",
            Ctl::While { .. } => "while",
            Ctl::Do { .. } => "do",
            Ctl::Repeat { .. } => "repeat",
            Ctl::Call { .. } => "call",
        }
    }

    /// The keyword closing a loop (`None` for anything else).
    fn loop_end(&self) -> Option<Kw> {
        match self {
            Ctl::While { .. } => Some(Kw::Endwhile),
            Ctl::Do { .. } => Some(Kw::While),
            Ctl::Repeat { .. } => Some(Kw::Endrepeat),
            _ => None,
        }
    }

    /// How the end of the program reports this construct left open.
    pub fn unclosed(&self) -> GcodeError {
        let message = match self {
            Ctl::Call { label, .. } => {
                format!(
                    "the subroutine o{} called here does not return",
                    show(label)
                )
            }
            Ctl::Do { label, .. } => format!("o{} do without its while", show(label)),
            _ => format!(
                "o{} {} without its end{}",
                show(self.label()),
                self.kind(),
                self.kind()
            ),
        };
        GcodeError::new(self.line(), message)
    }
}

/// A label as written: `100` or `<name>`.
pub(super) fn show(label: &str) -> String {
    if label.bytes().all(|b| b.is_ascii_digit()) {
        label.to_string()
    } else {
        format!("<{label}>")
    }
}

/// Lines being skipped, up to the O-word with `label` and one of `until`.
#[derive(Debug, Clone)]
pub(super) struct Skip {
    pub label: String,
    pub until: &'static [Kw],
    /// Run the O-word that ends the skip (else it is passed over too).
    pub run_end: bool,
    /// Where the skip started, and what for (for the error when the end never comes).
    pub line: usize,
    pub what: String,
}

impl Skip {
    /// Whether the O-word `label kw` ends the skip.
    pub fn ends_at(&self, label: &str, kw: Kw) -> bool {
        self.label == label && self.until.contains(&kw)
    }
}

impl<S: Source> Reader<S> {
    /// Index of the innermost call on the stack (the constructs above it are the current
    /// subroutine's), or 0 when in the main program (where everything is).
    fn frame_start(&self) -> usize {
        self.stack
            .iter()
            .rposition(|c| matches!(c, Ctl::Call { .. }))
            .map_or(0, |i| i + 1)
    }

    fn err(&self, message: impl Into<String>) -> GcodeError {
        GcodeError::new(self.line, message)
    }

    /// Starts skipping.
    fn skip(&mut self, label: &str, until: &'static [Kw], run_end: bool, what: String) {
        self.skip = Some(Skip {
            label: label.to_string(),
            until,
            run_end,
            line: self.line,
            what,
        });
    }

    /// Goes back to `pos`, where the next line is `line_before + 1`; counts the pass.
    fn loop_back(&mut self, pos: u64, line_before: usize) -> Result<(), GcodeError> {
        self.passes += 1;
        self.rereading = true;
        if self.passes > self.max_passes {
            return Err(self.err(format!(
                "a loop went round {} times without a block to run",
                self.max_passes
            )));
        }
        self.goto(pos, line_before)
    }

    /// Reads on from `pos`, where the next line is `line_before + 1`.
    pub(super) fn goto(&mut self, pos: u64, line_before: usize) -> Result<(), GcodeError> {
        self.source
            .seek(pos)
            .map_err(|e| self.err(format!("cannot go back in the source: {e}")))?;
        self.line = line_before;
        Ok(())
    }

    /// An error unless no construct with `label` is open in the current call.
    fn check_unique(&self, label: &str) -> Result<(), GcodeError> {
        match self.stack[self.frame_start()..]
            .iter()
            .find(|c| c.label() == label)
        {
            Some(c) => Err(self.err(format!(
                "label o{} already used by the open {} at line {}",
                show(label),
                c.kind(),
                c.line()
            ))),
            None => Ok(()),
        }
    }

    /// The innermost open construct of the current call, which must be `kind` with `label`
    /// for `kw`.
    fn top(&self, label: &str, kw: Kw, kind: &str) -> Result<usize, GcodeError> {
        let start = self.frame_start();
        let wrong = |what: String| {
            Err(self.err(format!(
                "o{} {} does not match {what}",
                show(label),
                kw.name()
            )))
        };
        match self.stack.len().checked_sub(1) {
            Some(i) if i >= start => {
                let c = &self.stack[i];
                if c.label() != label || c.kind() != kind {
                    wrong(format!(
                        "the open o{} {} at line {}",
                        show(c.label()),
                        c.kind(),
                        c.line()
                    ))
                } else {
                    Ok(i)
                }
            }
            _ => wrong(format!("any open {kind}")),
        }
    }

    /// Runs an O-word line (`pos`: where the line starts), the cursor past its keyword.
    pub(super) fn o_word(
        &mut self,
        label: String,
        kw: Kw,
        cur: &mut Cursor<'_>,
        pos: u64,
        params: &mut Params,
    ) -> Result<(), GcodeError> {
        let line = self.line;
        let at = |m: String| GcodeError::new(line, m);
        let shown = show(&label);
        // The bracketed argument the keyword needs.
        let arg = |cur: &mut Cursor<'_>, params: &Params| {
            cur.bracketed(params)
                .map_err(|m| at(format!("o{shown} {}: {m}", kw.name())))
        };
        let mut args: Vec<f64> = Vec::new();
        let mut unchecked = false;
        let mut cond = None;
        match kw {
            Kw::If | Kw::While | Kw::Repeat => cond = Some(arg(cur, params)?),
            // An `elseif` after a branch taken is not evaluated.
            Kw::Elseif => {
                if matches!(self.stack.last(), Some(Ctl::If { taken: true, .. })) {
                    unchecked = true;
                } else {
                    cond = Some(arg(cur, params)?);
                }
            }
            Kw::Call => {
                while cur.peek() == Some(b'[') {
                    if args.len() == CALL_PARAMS {
                        return Err(at(format!("more than {CALL_PARAMS} arguments in a call")));
                    }
                    args.push(arg(cur, params)?);
                }
            }
            Kw::Return | Kw::Endsub if cur.peek() == Some(b'[') => {
                cond = Some(arg(cur, params)?);
            }
            _ => {}
        }
        if !unchecked && !cur.at_end() {
            return Err(at(format!("unexpected text after o{shown} {}", kw.name())));
        }
        let truth = cond.is_some_and(|v| v != 0.0);
        match kw {
            Kw::Sub => self.define(label),
            Kw::Endsub | Kw::Return => self.ret(&label, kw, cond, params),
            Kw::Call => self.call(label, &args, params),
            Kw::Do => {
                self.check_unique(&label)?;
                let pos = self.source.tell();
                self.stack.push(Ctl::Do { label, line, pos });
                Ok(())
            }
            Kw::While => {
                let start = self.frame_start();
                let ends_do = self.stack.len() > start
                    && matches!(self.stack.last(), Some(Ctl::Do { label: l, .. }) if *l == label);
                if ends_do {
                    match self.stack.last() {
                        Some(&Ctl::Do { pos, line, .. }) if truth => self.loop_back(pos, line),
                        _ => {
                            self.stack.pop();
                            Ok(())
                        }
                    }
                } else {
                    self.check_unique(&label)?;
                    if truth {
                        self.stack.push(Ctl::While { label, line, pos });
                    } else {
                        let what = format!("o{shown} while");
                        self.skip(&label, &[Kw::Endwhile], false, what);
                    }
                    Ok(())
                }
            }
            Kw::Endwhile => {
                let i = self.top(&label, kw, "while")?;
                match self.stack.remove(i) {
                    Ctl::While { pos, line, .. } => self.loop_back(pos, line - 1),
                    _ => Ok(()),
                }
            }
            Kw::Repeat => {
                self.check_unique(&label)?;
                // LinuxCNC rounds the count to the nearest integer.
                let n = cond.unwrap_or(0.0).round();
                if n >= 1.0 {
                    let pos = self.source.tell();
                    let left = (n - 1.0).min(u64::MAX as f64) as u64;
                    self.stack.push(Ctl::Repeat {
                        label,
                        line,
                        pos,
                        left,
                    });
                } else {
                    let what = format!("o{shown} repeat");
                    self.skip(&label, &[Kw::Endrepeat], false, what);
                }
                Ok(())
            }
            Kw::Endrepeat => {
                let i = self.top(&label, kw, "repeat")?;
                match &mut self.stack[i] {
                    Ctl::Repeat {
                        left, pos, line, ..
                    } if *left > 0 => {
                        *left -= 1;
                        let (pos, line) = (*pos, *line);
                        self.loop_back(pos, line)
                    }
                    _ => {
                        self.stack.pop();
                        Ok(())
                    }
                }
            }
            Kw::If => {
                self.check_unique(&label)?;
                self.stack.push(Ctl::If {
                    label: label.clone(),
                    line,
                    taken: truth,
                    in_else: false,
                });
                if !truth {
                    let what = format!("o{shown} if");
                    self.skip(&label, &[Kw::Elseif, Kw::Else, Kw::Endif], true, what);
                }
                Ok(())
            }
            Kw::Elseif | Kw::Else => {
                let i = self.top(&label, kw, "if")?;
                let Ctl::If { taken, in_else, .. } = &mut self.stack[i] else {
                    return Ok(());
                };
                if *in_else {
                    return Err(at(format!("o{shown} {} after o{shown} else", kw.name())));
                }
                let was_taken = *taken;
                if kw == Kw::Else {
                    *in_else = true;
                    *taken = true;
                } else {
                    *taken = was_taken || truth;
                }
                if was_taken {
                    let what = format!("o{shown} {}", kw.name());
                    self.skip(&label, &[Kw::Endif], true, what);
                } else if kw == Kw::Elseif && !truth {
                    let what = format!("o{shown} elseif");
                    self.skip(&label, &[Kw::Elseif, Kw::Else, Kw::Endif], true, what);
                }
                Ok(())
            }
            Kw::Endif => {
                self.top(&label, kw, "if")?;
                self.stack.pop();
                Ok(())
            }
            Kw::Break | Kw::Continue => {
                let start = self.frame_start();
                let Some(i) = self.stack[start..]
                    .iter()
                    .rposition(|c| c.label() == label && c.loop_end().is_some())
                    .map(|i| i + start)
                else {
                    return Err(at(format!(
                        "o{shown} {} outside a loop labelled o{shown}",
                        kw.name()
                    )));
                };
                let end = match self.stack[i].loop_end() {
                    Some(Kw::Endwhile) => &[Kw::Endwhile],
                    Some(Kw::While) => &[Kw::While],
                    _ => &[Kw::Endrepeat],
                };
                let what = format!("o{shown} {}", kw.name());
                if kw == Kw::Break {
                    self.stack.truncate(i);
                    self.skip(&label, end, false, what);
                } else {
                    self.stack.truncate(i + 1);
                    self.skip(&label, end, true, what);
                }
                Ok(())
            }
        }
    }

    /// `sub` met in the main flow: noted, its body skipped.
    fn define(&mut self, label: String) -> Result<(), GcodeError> {
        let shown = show(&label);
        if !self.stack.is_empty() {
            let c = &self.stack[self.stack.len() - 1];
            return Err(self.err(format!(
                "o{shown} sub inside the open o{} {} at line {} (subroutines are defined at \
                 the top level)",
                show(c.label()),
                c.kind(),
                c.line()
            )));
        }
        let body = self.source.tell();
        self.note_sub(&label, body, self.line)?;
        self.skip(&label, &[Kw::Endsub], false, format!("o{shown} sub"));
        Ok(())
    }

    /// Notes subroutine `label`'s body at `body` (its `sub` on `line`).
    pub(super) fn note_sub(
        &mut self,
        label: &str,
        body: u64,
        line: usize,
    ) -> Result<(), GcodeError> {
        match self.subs.get(label) {
            Some(&(_, first)) if first != line => Err(GcodeError::new(
                line,
                format!(
                    "subroutine o{} defined twice (first at line {first})",
                    show(label)
                ),
            )),
            Some(_) => Ok(()),
            None => {
                self.subs.insert(label.to_string(), (body, line));
                Ok(())
            }
        }
    }

    /// `call`: the arguments into #1–#30, on to the body.
    fn call(&mut self, label: String, args: &[f64], params: &mut Params) -> Result<(), GcodeError> {
        let shown = show(&label);
        if params.depth() >= MAX_CALL_DEPTH {
            return Err(self.err(format!(
                "o{shown} call: subroutine calls nested deeper than {MAX_CALL_DEPTH}"
            )));
        }
        if !self.subs.contains_key(&label) && !self.scanned {
            self.scan_subs()?;
        }
        if !self.subs.contains_key(&label) && !self.open_sub_file(&label)? {
            return Err(self.err(format!(
                "o{shown} call: no subroutine o{shown} in the program, and no {label}.ngc on \
                 the subroutine path"
            )));
        }
        let (body, sub_line) = self.subs[&label];
        let pos = self.source.tell();
        self.stack.push(Ctl::Call {
            label,
            line: self.line,
            pos,
        });
        params.call(args);
        self.rereading = true;
        self.goto(body, sub_line)
    }

    /// `endsub` or `return` in a call: back after the `call`, with `value` in `#<_value>`.
    fn ret(
        &mut self,
        label: &str,
        kw: Kw,
        value: Option<f64>,
        params: &mut Params,
    ) -> Result<(), GcodeError> {
        let shown = show(label);
        let Some(i) = self
            .stack
            .iter()
            .rposition(|c| matches!(c, Ctl::Call { .. }))
        else {
            return Err(self.err(format!("o{shown} {} outside a subroutine call", kw.name())));
        };
        let Ctl::Call {
            label: called,
            line,
            pos,
        } = self.stack[i].clone()
        else {
            return Ok(());
        };
        // `return` may carry any label (LinuxCNC's own examples return with the label of
        // an enclosing `if`); `endsub` closes its own subroutine.
        if kw == Kw::Endsub && called != label {
            return Err(self.err(format!(
                "o{shown} {} inside subroutine o{}",
                kw.name(),
                show(&called)
            )));
        }
        if kw == Kw::Endsub && i + 1 < self.stack.len() {
            return Err(self.stack[self.stack.len() - 1].unclosed());
        }
        self.stack.truncate(i);
        params.ret();
        self.returned = Some(self.line);
        params.set_named("_value", value.unwrap_or(0.0));
        params.set_named("_value_returned", if value.is_some() { 1.0 } else { 0.0 });
        self.goto(pos, line)
    }
}
