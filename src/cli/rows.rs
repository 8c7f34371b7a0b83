//! Files of numbers: read whole ([`number_rows`], `mcctl cam`'s table) or a row at a time
//! (`mcctl pvt`, `compare --table`: memory bounded by the longest line whatever the file's
//! length).

use std::io::BufRead;
use std::path::Path;

/// The longest line read, in bytes: a row is a few numbers and a comment.
pub const MAX_ROW_BYTES: usize = 4096;
/// Text of a line echoed in an error, in characters (then an ellipsis).
const ECHO_CHARS: usize = 60;

/// One row: its line (from 1) and its `n` numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    pub line: usize,
    pub values: [f64; 3],
    pub n: usize,
}

/// The rows of a file of numbers, as [`number_rows`] reads them (`widths` finite
/// numbers a line, commas or blanks between, `#` starts a comment, blank lines skipped),
/// one at a time. An error names its line (from 1); nothing follows it.
pub struct NumberRows<R> {
    reader: R,
    widths: std::ops::RangeInclusive<usize>,
    what: &'static str,
    line: usize,
    buf: Vec<u8>,
    done: bool,
}

impl<R: BufRead> NumberRows<R> {
    /// The rows of `reader`, `what` naming a row in errors.
    pub fn new(reader: R, widths: std::ops::RangeInclusive<usize>, what: &'static str) -> Self {
        debug_assert!(*widths.end() <= 3);
        NumberRows {
            reader,
            widths,
            what,
            line: 0,
            buf: Vec::new(),
            done: false,
        }
    }

    fn row(&mut self) -> Result<Option<Row>, String> {
        use std::io::Read as _;
        loop {
            self.buf.clear();
            self.line += 1;
            let n = (&mut self.reader)
                .take(MAX_ROW_BYTES as u64 + 1)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| format!("line {}: cannot read: {e}", self.line))?;
            if n == 0 {
                return Ok(None);
            }
            if self.buf.last() == Some(&b'\n') {
                self.buf.pop();
            }
            if self.buf.len() > MAX_ROW_BYTES {
                return Err(format!(
                    "line {}: longer than {MAX_ROW_BYTES} bytes",
                    self.line
                ));
            }
            let text = std::str::from_utf8(&self.buf)
                .map_err(|_| format!("line {}: not UTF-8 text", self.line))?;
            let text = text.split('#').next().unwrap_or("").trim();
            if text.is_empty() {
                continue;
            }
            let mut row = Row {
                line: self.line,
                values: [0.0; 3],
                n: 0,
            };
            let mut ok = true;
            for word in text
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
            {
                match word.parse::<f64>() {
                    Ok(v) if v.is_finite() && row.n < 3 => row.values[row.n] = v,
                    _ => ok = false,
                }
                row.n += 1;
            }
            if !ok || !self.widths.contains(&row.n) {
                let shown: String = text.chars().take(ECHO_CHARS).collect();
                let more = if text.chars().count() > ECHO_CHARS {
                    "…"
                } else {
                    ""
                };
                return Err(format!(
                    "line {}: expected `{}` (finite numbers), got `{shown}{more}`",
                    self.line, self.what
                ));
            }
            return Ok(Some(row));
        }
    }
}

impl<R: BufRead> Iterator for NumberRows<R> {
    type Item = Result<Row, String>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let r = self.row().transpose();
        if !matches!(r, Some(Ok(_))) {
            self.done = true;
        }
        r
    }
}

/// The rows of a file of numbers: `widths` finite numbers per line (commas or blanks between;
/// `#` starts a comment; blank lines skipped), `what` naming a row in the error. Err: the line
/// number (from 1) and what is wrong.
pub fn number_rows(
    text: &str,
    widths: std::ops::RangeInclusive<usize>,
    what: &str,
) -> std::result::Result<Vec<Vec<f64>>, String> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let vals: std::result::Result<Vec<f64>, _> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(str::parse::<f64>)
            .collect();
        match vals {
            Ok(v) if widths.contains(&v.len()) && v.iter().all(|x| x.is_finite()) => rows.push(v),
            _ => {
                return Err(format!(
                    "line {}: expected `{what}` (finite numbers), got `{line}`",
                    i + 1
                ))
            }
        }
    }
    if rows.is_empty() {
        return Err("no points".into());
    }
    Ok(rows)
}

/// The rows of the file at `path` (an error names the file's line, not the file).
pub fn file_rows(
    path: &Path,
    widths: std::ops::RangeInclusive<usize>,
    what: &'static str,
) -> Result<NumberRows<std::io::BufReader<std::fs::File>>, String> {
    let f = std::fs::File::open(path).map_err(|e| e.to_string())?;
    Ok(NumberRows::new(std::io::BufReader::new(f), widths, what))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_as_number_rows_reads_them_and_errors_name_their_line() {
        let text = "# t, p\n0.1, 5\n\n0.2 6 # c\n0.3,7,1\n";
        let rows: Vec<Row> = NumberRows::new(text.as_bytes(), 2..=3, "t, p")
            .map(Result::unwrap)
            .collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(
            (rows[1].line, rows[1].values, rows[1].n),
            (4, [0.2, 6.0, 0.0], 2)
        );
        assert_eq!(rows[2].values, [0.3, 7.0, 1.0]);
        let want: Vec<Vec<f64>> = super::number_rows(text, 2..=3, "t, p").unwrap();
        assert_eq!(
            want,
            rows.iter()
                .map(|r| r.values[..r.n].to_vec())
                .collect::<Vec<_>>()
        );
        for (bad, err) in [
            (
                "1\n2\nx\n",
                "line 3: expected `p` (finite numbers), got `x`",
            ),
            (
                "1\n2 3\n",
                "line 2: expected `p` (finite numbers), got `2 3`",
            ),
            (
                "1\ninf\n",
                "line 2: expected `p` (finite numbers), got `inf`",
            ),
            (
                "1\n1 2 3 4 5\n",
                "line 2: expected `p` (finite numbers), got `1 2 3 4 5`",
            ),
        ] {
            let got: Vec<_> = NumberRows::new(bad.as_bytes(), 1..=1, "p").collect();
            assert_eq!(got.last().unwrap().as_ref().unwrap_err(), err);
        }
        let long = format!("1\n{}\n2\n", "9".repeat(MAX_ROW_BYTES + 1));
        let got: Vec<_> = NumberRows::new(long.as_bytes(), 1..=1, "p").collect();
        assert_eq!(got.len(), 2, "nothing after the error");
        assert_eq!(
            got[1].as_ref().unwrap_err(),
            &format!("line 2: longer than {MAX_ROW_BYTES} bytes")
        );
        let wide = format!("1\n{}\n", "x".repeat(100));
        let got: Vec<_> = NumberRows::new(wide.as_bytes(), 1..=1, "p").collect();
        let e = got[1].as_ref().unwrap_err();
        assert!(e.ends_with(&format!("`{}…`", "x".repeat(60))), "{e}");
    }
}
