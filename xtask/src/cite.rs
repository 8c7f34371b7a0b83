//! Every name a comment of `motioncard.h` cites exists in `motioncard.h` (issue 39).
//!
//! The header's comments come from cffi's doc comments and, through the register map's
//! generated code, from `mc_dpram.h`, whose comments name the register map's defines
//! (`MC_STATE_*`, `MC_EV_INPUT`, `MC_NACK_*`, `MC_MOVE_BUFFERED`...). [`complete`] makes them
//! true for a C user in two steps, on the comments only:
//!
//! 1. a name the C ABI has under another name is written under the C ABI's (`MC_STATE_*` ->
//!    `MC_AXIS_STATE_*`, `MC_EV_INPUT` -> `MC_EVENT_INPUT`: the renames of `codes.rs`);
//! 2. a register-map define still cited and not in the header is defined in it, after the
//!    C ABI's own names, from `mc_dpram.h` as it is there (value and comment; a pattern
//!    `PREFIX*` brings every define of the prefix; a function-like one its whole text), until
//!    nothing new is cited.
//!
//! A name is `MC_` followed by upper-case letters, digits and `_`, or `mc_` and lower-case ones;
//! `MC_` and a CamelCase word is PLCopen's name of a function block (`MC_MoveAbsolute`), not
//! a C name. `cffi/tests/c_programs.rs` checks the outcome: it compiles a use of every name
//! cited.

use crate::codes::{bindgen_values, c_renames, defines, doc_text};
use std::collections::{BTreeMap, BTreeSet};

/// Renames of patterns that name a set under another prefix than its selection's: the raw
/// flags of `MC_OP_PATH_OUTPUT` are `MC_PATH_OUT_AT_*`, the C ABI's `MC_OUTPUT_AT_*`.
const EXTRA_RENAMES: &[(&str, &str)] = &[("MC_PATH_OUT_*", "MC_OUTPUT_AT_*")];

/// A name a comment cites: the identifier, and whether it is a pattern (`NAME*`, or a prefix
/// ending in `_`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Cited {
    pub name: String,
    pub pattern: bool,
}

/// The ranges of the C comments of `text`.
fn comments(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(s) = text[at..].find("/*") {
        let start = at + s;
        let end = text[start + 2..]
            .find("*/")
            .map_or(text.len(), |e| start + 2 + e + 2);
        out.push((start, end));
        at = end;
    }
    out
}

fn ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The C names of a comment's text, with their byte ranges.
fn names_in(text: &str) -> Vec<(usize, usize, Cited)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if !ident_char(b[i]) || (i > 0 && ident_char(b[i - 1])) {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < b.len() && ident_char(b[j]) {
            j += 1;
        }
        let word = &text[i..j];
        let upper = word.starts_with("MC_")
            && word[3..]
                .bytes()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == b'_');
        let lower = word.starts_with("mc_")
            && word[3..]
                .bytes()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'_');
        // A file name (`mc_dpram.h`) is no C name.
        let file = text[j..].starts_with(".h") || text[j..].starts_with(".rs");
        if (upper || lower) && !file {
            let star = b.get(j) == Some(&b'*');
            let pattern = star || word.ends_with('_');
            out.push((
                i,
                j + star as usize,
                Cited {
                    name: word.to_string(),
                    pattern,
                },
            ));
        }
        i = j;
    }
    out
}

/// The names the code (not the comments) of a header declares or uses, and its defines.
pub fn declared(header: &str) -> BTreeSet<String> {
    let mut code = String::with_capacity(header.len());
    let mut at = 0;
    for (s, e) in comments(header) {
        code.push_str(&header[at..s]);
        code.push(' ');
        at = e;
    }
    code.push_str(&header[at..]);
    code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .map(String::from)
        .collect()
}

/// Is a cited name in the header's names?
pub fn resolves(c: &Cited, names: &BTreeSet<String>) -> bool {
    if c.pattern {
        names.iter().any(|n| n.starts_with(&c.name) && *n != c.name)
    } else {
        names.contains(&c.name)
    }
}

/// Every name the comments of `header` cite.
pub fn cited(header: &str) -> BTreeSet<Cited> {
    comments(header)
        .into_iter()
        .flat_map(|(s, e)| names_in(&header[s..e]).into_iter().map(|(_, _, c)| c))
        .collect()
}

/// `header` with the register map's names in its comments renamed to the C ABI's, and the
/// register-map defines its comments still cite defined before `before` (see the module doc).
pub fn complete(header: &str, dpram: &str, bindings: &str, before: &str) -> Result<String, String> {
    let defs = defines(dpram);
    let values = bindgen_values(bindings);
    let mut renames = c_renames(&defs, &values)?;
    // Patterns of a whole set under a shorter prefix than the set's own.
    for (from, to) in EXTRA_RENAMES {
        renames.insert(from.to_string(), to.to_string());
    }
    // Step 1: renames, in the comments only.
    let rename_comments = |text: &str, names: &BTreeSet<String>| -> String {
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        for (s, e) in comments(text) {
            out.push_str(&text[at..s]);
            let comment = &text[s..e];
            let mut c_at = 0;
            for (ns, ne, c) in names_in(comment) {
                out.push_str(&comment[c_at..ns]);
                let key = if c.pattern {
                    format!("{}*", c.name)
                } else {
                    c.name.clone()
                };
                let star = if comment[..ne].ends_with('*') {
                    "*"
                } else {
                    ""
                };
                match renames.get(&key) {
                    Some(to) if !resolves(&c, names) => {
                        let to = to.trim_end_matches('*');
                        out.push_str(to);
                        out.push_str(star);
                    }
                    _ => out.push_str(&comment[ns..ne]),
                }
                c_at = ne;
            }
            out.push_str(&comment[c_at..]);
            at = e;
        }
        out.push_str(&text[at..]);
        out
    };
    let names = declared(header);
    let mut header = rename_comments(header, &names);
    // Step 2: the register map's defines still cited, to a fixed point.
    let dpram_lines: BTreeMap<String, String> = dpram
        .lines()
        .filter_map(|l| {
            let rest = l.trim().strip_prefix("#define ")?;
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            let body = rest.split("/*").next().unwrap_or(rest).trim_end();
            (!name.is_empty()).then(|| (name, body.to_string()))
        })
        .collect();
    let comment_of: BTreeMap<&str, &str> = defs
        .iter()
        .map(|d| (d.name.as_str(), d.comment.as_str()))
        .collect();
    let mut added: Vec<String> = Vec::new();
    let mut block = String::new();
    for _ in 0..8 {
        let names = declared(&header);
        let mut new = BTreeSet::new();
        for c in cited(&header) {
            if resolves(&c, &names) {
                continue;
            }
            for name in dpram_lines.keys() {
                let hit = if c.pattern {
                    name.starts_with(&c.name)
                } else {
                    *name == c.name
                };
                // The include guard is no constant.
                if hit && !names.contains(name) && name != "MC_DPRAM_H" {
                    new.insert(name.clone());
                }
            }
        }
        if new.is_empty() {
            break;
        }
        let mut text = String::new();
        for name in &new {
            let body = &dpram_lines[name];
            let comment = comment_of.get(name.as_str()).copied().unwrap_or("");
            let doc = doc_text(comment, &|w| {
                renames
                    .get(w)
                    .filter(|to| names.contains(to.trim_end_matches('*')))
                    .cloned()
                    .unwrap_or_else(|| w.to_string())
            });
            if !doc.is_empty() {
                text.push_str(&format!("\n/**\n * {doc}\n */"));
            }
            text.push_str(&format!("\n#define {body}\n"));
            added.push(name.clone());
        }
        let names_after: BTreeSet<String> = names.iter().cloned().chain(new).collect();
        let text = rename_comments(&text, &names_after);
        block.push_str(&text);
        let at = header.find(before).ok_or("the header has no trailer")?;
        header.insert_str(at, &text);
    }
    if block.is_empty() {
        return Ok(header);
    }
    // One introduction before the block.
    let intro = "\n/*\n * The register map's own constants that the comments of this header cite \
                 (firmware-proto/include/mc_dpram.h,\n * generated with it): the flags, sizes \
                 and codes of raw commands (mc_send_raw) and of the register map's blocks.\n \
                 * MC_NACK_ codes are what the card answers a raw command (positive); the \
                 library's calls return\n * MC_ERR_ codes.\n */\n";
    let at = header.find(block.as_str()).ok_or("lost the block")?;
    header.insert_str(at, intro);
    Ok(header)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_patterns_and_plcopen() {
        let c = cited("/** MC_STATE_*, `MC_EV_INPUT`, MC_MoveAbsolute, mc_open; the MC_ERR_ codes; mc_dpram.h */ int MC_X;");
        let names: Vec<(&str, bool)> = c.iter().map(|c| (c.name.as_str(), c.pattern)).collect();
        assert_eq!(
            names,
            [
                ("MC_ERR_", true),
                ("MC_EV_INPUT", false),
                ("MC_STATE_", true),
                ("mc_open", false)
            ]
        );
        let d = declared("/** MC_Y */\n#define MC_X 1\nint mc_f(void);");
        assert!(d.contains("MC_X") && d.contains("mc_f") && !d.contains("MC_Y"));
    }
}
