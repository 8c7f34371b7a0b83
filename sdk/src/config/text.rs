//! A configuration file as text: written and parsed, read within its size limit, and the key
//! and line an error names.

use crate::config::sections::{Config, CONFIG_HEADER};
use crate::error::{Error, Result};

impl Config {
    /// The file's text: [`CONFIG_HEADER`], then every section in a fixed order.
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a configuration always serializes");
        format!("{CONFIG_HEADER}{body}")
    }

    /// Parse a file's text (`origin` names it in errors). Only the syntax and the types are
    /// checked here; [`Card::load_config`](crate::Card::load_config) checks the values
    /// against a card.
    pub fn parse(text: &str, origin: &str) -> Result<Config> {
        if text.len() > MAX_CONFIG_BYTES {
            return Err(too_big(origin, &format!("{} bytes", text.len())));
        }
        let doc = toml::de::DeTable::parse(text).map_err(|e| {
            let line = e.span().map_or(0, |s| line_of(text, s.start));
            file_error(origin, String::new(), line, e.message().to_string())
        })?;
        toml::from_str::<Config>(text).map_err(|e| {
            let (key, line) = match e.span() {
                Some(s) => (key_at(doc.get_ref(), s.start), line_of(text, s.start)),
                None => (String::new(), 0),
            };
            file_error(origin, key, line, e.message().trim().to_string())
        })
    }
}

/// The largest configuration file read or parsed, in bytes. The largest file
/// [`Card::save_config`](crate::Card::save_config) can write (8 axes with every section: four
/// biquads and a bidirectional compensation table of the most points each; the 4 groups with
/// their path settings; every number at its longest) is 153,121 bytes (the test
/// `the_largest_file_save_writes_loads_back`); a quarter of a MiB leaves room for comments.
/// Parsing takes about 100 times a file's size in memory: a larger file is refused before it
/// is read.
pub const MAX_CONFIG_BYTES: usize = 256 * 1024;

/// Text from a file (a value, a key) is echoed in an error up to this many characters, then
/// cut with an ellipsis.
pub const ECHO_CHARS: usize = 60;

fn too_big(origin: &str, size: &str) -> Error {
    file_error(
        origin,
        String::new(),
        0,
        format!(
            "{size} is more than a configuration file may hold ({MAX_CONFIG_BYTES} bytes: the \
             largest `config save` writes is about 150 KiB); nothing was parsed"
        ),
    )
}

pub(super) fn read_file(path: &std::path::Path) -> Result<String> {
    use std::io::Read as _;
    let cannot = |e| Error::io(format!("{}: cannot read", path.display()), e);
    let origin = path.display().to_string();
    let f = std::fs::File::open(path).map_err(cannot)?;
    let meta = f.metadata().map_err(cannot)?;
    if meta.is_file() && meta.len() > MAX_CONFIG_BYTES as u64 {
        return Err(too_big(&origin, &format!("{} bytes", meta.len())));
    }
    // A pipe or a device says no size: read no more than the limit and one byte.
    let mut text = String::new();
    f.take(MAX_CONFIG_BYTES as u64 + 1)
        .read_to_string(&mut text)
        .map_err(cannot)?;
    if text.len() > MAX_CONFIG_BYTES {
        return Err(too_big(
            &origin,
            &format!("more than {MAX_CONFIG_BYTES} bytes"),
        ));
    }
    Ok(text)
}

/// `s` with every quoted run (between `"` or `` ` ``, `\` escaping) or, for a key, every
/// dotted part longer than [`ECHO_CHARS`] characters cut to that many and an ellipsis; and
/// the whole cut to eight times that.
fn cut_echoes(s: &str, quoted: bool) -> String {
    let mut out = String::new();
    let mut kept = 0usize;
    let (mut run, mut inside, mut escaped) = (0usize, false, false);
    for c in s.chars() {
        let delimiter = if quoted {
            (c == '"' || c == '`') && !escaped
        } else {
            c == '.'
        };
        escaped = quoted && inside && c == '\\' && !escaped;
        let keep = if delimiter {
            inside = quoted && !inside;
            run = 0;
            Some(c)
        } else if quoted && !inside {
            Some(c)
        } else {
            run += 1;
            match run {
                r if r <= ECHO_CHARS => Some(c),
                r if r == ECHO_CHARS + 1 => Some('…'),
                _ => None,
            }
        };
        if let Some(c) = keep {
            if kept == 8 * ECHO_CHARS {
                out.push('…');
                break;
            }
            out.push(c);
            kept += 1;
        }
    }
    out
}

pub(super) fn file_error(origin: &str, key: String, line: usize, message: String) -> Error {
    Error::ConfigFile {
        path: origin.to_string(),
        key: cut_echoes(&key, false),
        line,
        message: cut_echoes(&message, true),
    }
}

fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The dotted key whose key or value holds byte `at` (the deepest one).
fn key_at(t: &toml::de::DeTable<'_>, at: usize) -> String {
    fn walk(v: &toml::de::DeValue<'_>, at: usize, path: &mut Vec<String>) {
        match v {
            toml::de::DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    let (ks, vs) = (k.span(), v.span());
                    if ks.contains(&at) || vs.contains(&at) || contains_deep(v.get_ref(), at) {
                        path.push(k.get_ref().to_string());
                        walk(v.get_ref(), at, path);
                        return;
                    }
                }
            }
            toml::de::DeValue::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    if v.span().contains(&at) {
                        path.push(i.to_string());
                        walk(v.get_ref(), at, path);
                        return;
                    }
                }
            }
            _ => {}
        }
    }
    fn contains_deep(v: &toml::de::DeValue<'_>, at: usize) -> bool {
        match v {
            toml::de::DeValue::Table(t) => t.iter().any(|(k, v)| {
                k.span().contains(&at) || v.span().contains(&at) || contains_deep(v.get_ref(), at)
            }),
            _ => false,
        }
    }
    let mut path = Vec::new();
    walk(&toml::de::DeValue::Table(t.clone()), at, &mut path);
    path.join(".")
}

/// The line of a dotted key in the text (its deepest part the text has; 0: none).
pub(super) fn line_of_key(text: &str, key: &str) -> usize {
    let Ok(doc) = toml::de::DeTable::parse(text) else {
        return 0;
    };
    let mut table = doc.get_ref();
    let mut line = 0;
    for part in key.split('.') {
        let Some((k, v)) = table.iter().find(|(k, _)| k.get_ref().as_ref() == part) else {
            break;
        };
        line = line_of(text, k.span().start);
        match v.get_ref() {
            toml::de::DeValue::Table(t) => table = t,
            toml::de::DeValue::Array(a) => {
                // An array's element: the line of the element named next, if any.
                if let Some(i) = key.rsplit('.').next().and_then(|i| i.parse::<usize>().ok()) {
                    if let Some(e) = a.get(i) {
                        line = line_of(text, e.span().start);
                    }
                }
                break;
            }
            _ => break,
        }
    }
    line
}
