//! One source line made ready for reading, as RS274/NGC reads text: spaces, tabs and carriage
//! returns dropped and letters lower-cased outside comments; `(…)` comments (closed on the
//! line, not nested) and `;` comments to the end of the line taken out; a leading `/` (block
//! delete) noted; a `%` line recognised. What is left, the code, holds words, parameter
//! settings and O-words only.
//!
//! Messages (`(MSG,…)`, `(PRINT,…)`, `(DEBUG,…)`) are the comments the reader keeps: their
//! text, with `#n` and `#<name>` replaced by the parameters' values ([`substitute`]).

use super::super::Params;
use std::ops::Range;

/// What [`clean`] found on a line besides its code.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct Cleaned {
    /// Nothing but blanks.
    pub blank: bool,
    /// The line is `%` (blanks around it allowed).
    pub percent: bool,
    /// The line starts with `/` (block delete), which is not in the code.
    pub slash: bool,
    /// The text of the line's last message comment (after `MSG,`, `PRINT,` or `DEBUG,`), as a
    /// byte range of the raw line.
    pub message: Option<Range<usize>>,
}

/// The comment keywords whose text becomes the block's message.
const MESSAGE_KEYS: [&str; 3] = ["msg,", "print,", "debug,"];

/// Cleans `raw` into `code` (lower-case, without blanks or comments).
pub(super) fn clean(raw: &str, code: &mut Vec<u8>) -> Result<Cleaned, String> {
    code.clear();
    let mut out = Cleaned::default();
    let trimmed = raw.trim_matches(|c| c == ' ' || c == '\t' || c == '\r');
    if trimmed.is_empty() {
        out.blank = true;
        return Ok(out);
    }
    if trimmed == "%" {
        out.percent = true;
        return Ok(out);
    }
    let bytes = raw.as_bytes();
    // Whether anything (code or comment) has been met yet: a `/` first is block delete.
    let mut first = true;
    let mut comment_start: Option<usize> = None;
    for (i, &b) in bytes.iter().enumerate() {
        if let Some(start) = comment_start {
            match b {
                b')' => {
                    let text = &raw[start..i];
                    if let Some(r) = message_range(text) {
                        out.message = Some(start + r.start..start + r.end);
                    }
                    comment_start = None;
                }
                b'(' => return Err("nested comment (a '(' inside a comment)".into()),
                _ => {}
            }
            continue;
        }
        match b {
            b' ' | b'\t' | b'\r' => {}
            b';' => break,
            b'(' => {
                first = false;
                comment_start = Some(i + 1);
            }
            b'/' if first => {
                first = false;
                out.slash = true;
            }
            _ => {
                first = false;
                code.push(b.to_ascii_lowercase());
            }
        }
    }
    if comment_start.is_some() {
        return Err("comment not closed on its line (missing ')')".into());
    }
    Ok(out)
}

/// Where a comment's message text starts and ends, if the comment is a message.
fn message_range(comment: &str) -> Option<Range<usize>> {
    let lead = comment.len() - comment.trim_start().len();
    let rest = &comment[lead..];
    MESSAGE_KEYS.iter().find_map(|key| {
        let head = rest.get(..key.len())?;
        head.eq_ignore_ascii_case(key)
            .then(|| lead + key.len()..comment.len())
    })
}

/// A message's text with its parameters' values: `#123` and `#<name>` become the value with
/// six decimals (LinuxCNC's `%lf`), or `######` when the parameter does not exist. As in
/// LinuxCNC, `%d` (no decimals), `%f` (four) and `%.Nf` (N, one digit) change the format of
/// the parameters after them; any other `%` stays.
pub(super) fn substitute(text: &str, params: &Params) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    let mut decimals = 6usize;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        let b = rest.as_bytes();
        match c {
            '%' => {
                let fmt = match (b.get(1), b.get(2), b.get(3)) {
                    (Some(b'd'), _, _) => Some((0, 2)),
                    (Some(b'f'), _, _) => Some((4, 2)),
                    (Some(b'.'), Some(d @ b'0'..=b'9'), Some(b'f')) => {
                        Some((usize::from(d - b'0'), 4))
                    }
                    _ => None,
                };
                match fmt {
                    Some((d, len)) => {
                        decimals = d;
                        rest = &rest[len..];
                    }
                    None => {
                        out.push('%');
                        rest = &rest[1..];
                    }
                }
            }
            '#' => {
                let after = &rest[1..];
                let digits = after.bytes().take_while(u8::is_ascii_digit).count();
                let value;
                if digits > 0 {
                    value = after[..digits]
                        .parse::<u32>()
                        .ok()
                        .and_then(|n| params.get(n));
                    rest = &after[digits..];
                } else if let Some(inner) = after.strip_prefix('<') {
                    let end = inner
                        .find('>')
                        .ok_or("named parameter in a message not closed (missing '>')")?;
                    let name: String = inner[..end]
                        .chars()
                        .filter(|c| !c.is_whitespace())
                        .flat_map(char::to_lowercase)
                        .collect();
                    value = params.named(&name);
                    rest = &inner[end + 1..];
                } else {
                    out.push('#');
                    rest = after;
                    continue;
                }
                match value {
                    Some(v) => {
                        // LinuxCNC prints values within 1e-6 of 0 as 0 (no "-0.000000").
                        let v = if v.abs() < 1e-6 { 0.0 } else { v };
                        out.push_str(&format!("{v:.decimals$}"));
                    }
                    None => out.push_str("######"),
                }
            }
            _ => {
                out.push(c);
                rest = &rest[c.len_utf8()..];
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn code_of(raw: &str) -> (String, Cleaned) {
        let mut code = Vec::new();
        let c = clean(raw, &mut code).unwrap();
        (String::from_utf8(code).unwrap(), c)
    }

    #[test]
    fn blanks_case_and_comments_go() {
        let (code, c) = code_of("G1 x 1.5\t(Move) ; (MSG, not) here");
        assert_eq!(code, "g1x1.5");
        assert_eq!(c.message, None, "a ';' comment holds no message");
        let mut v = Vec::new();
        assert!(clean("G1 (a ( b)", &mut v).is_err(), "nested comment");
        assert!(clean("G1 (open", &mut v).is_err(), "unclosed comment");
        let (code, c) = code_of("G1 X1 (first) Y2 ; (not a comment");
        assert_eq!(code, "g1x1y2");
        assert_eq!(c.message, None);
    }

    #[test]
    fn slash_percent_and_messages() {
        let (code, c) = code_of("  / G0 X/2");
        assert!(c.slash);
        assert_eq!(code, "g0x/2");
        let (_, c) = code_of("(c) /G0");
        assert!(!c.slash, "a / after a comment is not block delete");
        let (_, c) = code_of(" \t% \r");
        assert!(c.percent);
        let (_, c) = code_of("%G0");
        assert!(!c.percent);
        let raw = "G0 ( Msg,Hello #1) (PRINT,x=#<X>)";
        let (_, c) = code_of(raw);
        assert_eq!(&raw[c.message.unwrap()], "x=#<X>", "the last message wins");
        let raw = "(debug, a)";
        assert_eq!(&raw[code_of(raw).1.message.unwrap()], " a");
    }

    #[test]
    fn substitution_as_linuxcnc_formats_it() {
        let mut p = Params::new();
        p.set(1, 2.5);
        p.set(2, -1e-9);
        p.set_named("my_x", 1.0 / 3.0);
        let s = substitute(
            "a=#1 b=#2 c=#< My_X > d=#<nope> e=#9999 %d#1 %.2f#1 %q #",
            &p,
        );
        assert_eq!(
            s.unwrap(),
            "a=2.500000 b=0.000000 c=0.333333 d=###### e=###### 2 2.50 %q #"
        );
        assert!(substitute("#<open", &p).is_err());
    }
}
