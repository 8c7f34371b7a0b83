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
