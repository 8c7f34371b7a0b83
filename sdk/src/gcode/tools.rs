//! The tool table, in LinuxCNC's format: `T1 P1 Z10 D6 ;comment`, lengths in mm.

use super::Pos;

/// One tool of the table (LinuxCNC's format: `T1 P1 Z10 D6 ;comment`), lengths in mm.
#[derive(Debug, Clone, PartialEq, Default)]
#[allow(missing_docs)]
pub struct Tool {
    pub number: u32,
    pub pocket: u32,
    /// Offsets X Y Z A B C (tool length is Z).
    pub offset: Pos,
    pub diameter: f64,
    pub comment: String,
}

/// The tool table.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ToolTable {
    /// In the table's order.
    pub tools: Vec<Tool>,
}

/// Why a tool table was refused: the 1-based line and what is wrong there.
pub type ToolTableError = super::GcodeError;

impl ToolTable {
    /// The tool numbered `number`.
    pub fn get(&self, number: u32) -> Option<&Tool> {
        self.tools.iter().find(|t| t.number == number)
    }

    /// Adds `tool`, or replaces the one with its number (G10 L1/L10).
    pub fn set(&mut self, tool: Tool) {
        match self.tools.iter_mut().find(|t| t.number == tool.number) {
            Some(t) => *t = tool,
            None => self.tools.push(tool),
        }
    }

    /// Reads a table in LinuxCNC's format: one tool a line, words `T` (number, required), `P`
    /// (pocket), `X Y Z A B C` (offsets), `D` (diameter), and `I J Q` (a lathe tool's
    /// angles and orientation, accepted and not kept), lengths in mm, then an optional
    /// `;comment`. Blank lines are skipped. A word twice, an unknown word, a number that does
    /// not read, a negative diameter or a tool number listed twice is an error naming its
    /// line.
    pub fn parse(text: &str) -> Result<ToolTable, ToolTableError> {
        let mut table = ToolTable::default();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let bad = |m: String| super::GcodeError::new(line, m);
            let (words, comment) = match raw.split_once(';') {
                Some((w, c)) => (w, c.trim()),
                None => (raw, ""),
            };
            if words.trim().is_empty() {
                continue;
            }
            let mut tool = Tool {
                comment: comment.to_owned(),
                ..Tool::default()
            };
            let (mut number, mut seen) = (None, String::new());
            for word in words.split_whitespace() {
                let mut chars = word.chars();
                let letter = chars.next().expect("split_whitespace gives no empty word");
                let letter = letter.to_ascii_uppercase();
                if seen.contains(letter) {
                    return Err(bad(format!("'{letter}' twice")));
                }
                seen.push(letter);
                let value: f64 = chars
                    .as_str()
                    .parse()
                    .ok()
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| bad(format!("'{word}' is not a letter and a number")))?;
                let whole = || -> Result<u32, super::GcodeError> {
                    (value >= 0.0 && value.fract() == 0.0 && value <= f64::from(u32::MAX))
                        .then_some(value as u32)
                        .ok_or_else(|| bad(format!("'{word}': a whole number is needed")))
                };
                match letter {
                    'T' => number = Some(whole()?),
                    'P' => tool.pocket = whole()?,
                    'D' if value < 0.0 => {
                        return Err(bad(format!("'{word}': a negative diameter")))
                    }
                    'D' => tool.diameter = value,
                    'I' | 'J' | 'Q' => {}
                    _ => match super::AXIS_LETTERS.iter().position(|&a| a == letter) {
                        Some(axis) => tool.offset[axis] = value,
                        None => return Err(bad(format!("unknown word '{word}'"))),
                    },
                }
            }
            tool.number = number.ok_or_else(|| bad("no tool number (T)".into()))?;
            if table.get(tool.number).is_some() {
                return Err(bad(format!("tool {} listed twice", tool.number)));
            }
            table.tools.push(tool);
        }
        Ok(table)
    }

    /// Reads the table file at `path` ([`ToolTable::parse`]).
    pub fn load(path: &std::path::Path) -> Result<ToolTable, ToolTableError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            super::GcodeError::new(0, format!("cannot read {}: {e}", path.display()))
        })?;
        ToolTable::parse(&text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linuxcnc_table_reads_with_its_comments() {
        let t = ToolTable::parse(
            "T1 P1 Z10 D6 ;6 mm end mill\n\
             \n\
             t2 p5 x0.5 z-2.25 d0.125 i0 j0 q0\n",
        )
        .unwrap();
        assert_eq!(t.tools.len(), 2);
        let one = t.get(1).unwrap();
        assert_eq!((one.pocket, one.offset[2], one.diameter), (1, 10.0, 6.0));
        assert_eq!(one.comment, "6 mm end mill");
        let two = t.get(2).unwrap();
        assert_eq!(two.offset, [0.5, 0.0, -2.25, 0.0, 0.0, 0.0]);
        assert_eq!((two.pocket, two.diameter), (5, 0.125));
        assert!(t.get(3).is_none());
    }

    #[test]
    fn bad_tables_name_their_line() {
        for (text, line, what) in [
            ("T1 Z1\nP2 Z1", 2, "no tool number"),
            ("T1 Z1 Z2", 1, "twice"),
            ("T1 U3", 1, "unknown word"),
            ("T1\nT1", 2, "listed twice"),
            ("T1 D-1", 1, "negative diameter"),
            ("T1.5", 1, "whole number"),
            ("T1 Zabc", 1, "not a letter and a number"),
            ("T1 Znan", 1, "not a letter and a number"),
        ] {
            let e = ToolTable::parse(text).unwrap_err();
            assert_eq!(e.line, line, "{text}");
            assert!(e.message.contains(what), "{text}: {}", e.message);
        }
    }

    #[test]
    fn set_replaces_a_tool_by_its_number() {
        let mut t = ToolTable::parse("T3 Z1").unwrap();
        t.set(Tool {
            number: 3,
            diameter: 2.0,
            ..Tool::default()
        });
        t.set(Tool {
            number: 4,
            ..Tool::default()
        });
        assert_eq!(t.tools.len(), 2);
        assert_eq!(t.get(3).unwrap().diameter, 2.0);
    }
}
