//! `mcctl gcode FILE`: the dry run. The SDK's interpreter reads the program without a card and
//! prints each canonical operation: one JSON object a line with `--json`, else a table. Probes
//! are taken as tripping at their programmed ends.

use super::bad;
use clap::Args as ClapArgs;
use motioncard_sdk::gcode::{
    Op, OpKind, Options, Pos, Program, SpindleDir, ToolTable, AXIS_LETTERS,
};
use std::io::Write as _;
use std::process::ExitCode;

/// `mcctl gcode`.
#[derive(ClapArgs)]
pub struct Args {
    /// The program.
    pub file: std::path::PathBuf,
    /// The tool table, in LinuxCNC's format (`T1 P1 Z10 D6 ;comment`, lengths in mm).
    #[arg(long)]
    pub tool_table: Option<std::path::PathBuf>,
    /// A directory where `o<name> call` looks for `name.ngc` when the program does not
    /// define the subroutine (before the program's own directory; may be repeated).
    #[arg(long)]
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// Lines starting with `/` are skipped.
    #[arg(long)]
    pub block_delete: bool,
    /// M1 pauses.
    #[arg(long)]
    pub optional_stop: bool,
    /// One JSON object per operation, a line each.
    #[arg(long)]
    pub json: bool,
}

/// Path length of a motion (mm over X Y Z; degrees for A B C alone).
pub fn length(op: &Op) -> f64 {
    op.kind.length().unwrap_or(0.0)
}

fn pos_json(p: &Pos) -> serde_json::Value {
    let mut m = serde_json::Map::new();
    for (l, v) in AXIS_LETTERS.iter().zip(p) {
        m.insert(l.to_ascii_lowercase().to_string(), (*v).into());
    }
    m.into()
}

/// The JSON object of one operation: `line`, `kind`, and for a motion `end` (machine
/// coordinates, mm and degrees) and `length` (mm); what each kind carries besides.
pub fn op_json(op: &Op) -> serde_json::Value {
    let mut j = serde_json::json!({"line": op.line, "kind": op.kind.name()});
    if let Some((_, end)) = op.kind.ends() {
        j["end"] = pos_json(&end);
        j["length"] = length(op).into();
    }
    match &op.kind {
        OpKind::Feed { feed, .. }
        | OpKind::Arc { feed, .. }
        | OpKind::Spline { feed, .. }
        | OpKind::Probe { feed, .. } => j["feed"] = (*feed).into(),
        OpKind::ArcNormal {
            feed,
            centre,
            normal,
            ccw,
            ..
        } => {
            j["feed"] = (*feed).into();
            let xyz = |v: &[f64; 3]| serde_json::json!({"x": v[0], "y": v[1], "z": v[2]});
            j["centre"] = xyz(centre);
            j["normal"] = xyz(normal);
            j["ccw"] = (*ccw).into();
        }
        OpKind::Dwell { seconds } => j["seconds"] = (*seconds).into(),
        OpKind::Spindle { speed, dir } => {
            j["speed"] = (*speed).into();
            j["direction"] = direction(*dir, "off").into();
        }
        OpKind::SpindleOrient { angle, dir } => {
            j["angle"] = (*angle).into();
            j["direction"] = direction(*dir, "shortest").into();
        }
        OpKind::Coolant { mist, flood } => {
            j["mist"] = (*mist).into();
            j["flood"] = (*flood).into();
        }
        OpKind::Output { index, on, synced } => {
            j["index"] = (*index).into();
            j["on"] = (*on).into();
            j["synced"] = (*synced).into();
        }
        OpKind::AnalogOutput {
            index,
            value,
            synced,
        } => {
            j["index"] = (*index).into();
            j["value"] = (*value).into();
            j["synced"] = (*synced).into();
        }
        OpKind::ToolChange { tool } => j["tool"] = (*tool).into(),
        OpKind::Message { text } => j["text"] = text.as_str().into(),
        OpKind::Hook { code, p, q } => {
            j["code"] = (*code).into();
            j["p"] = (*p).into();
            j["q"] = (*q).into();
        }
        OpKind::End { rewind } => j["rewind"] = (*rewind).into(),
        _ => {}
    }
    j
}

/// Read the program and print its operations.
pub fn run(a: Args) -> ExitCode {
    let tools = match &a.tool_table {
        Some(f) => match ToolTable::load(f) {
            Ok(t) => t,
            Err(e) => return bad(format!("--tool-table {}: {e}", f.display())),
        },
        None => ToolTable::default(),
    };
    let opts = Options {
        tools,
        block_delete: a.block_delete,
        optional_stop: a.optional_stop,
        subroutine_path: a.subroutine_path.clone(),
        ..Options::default()
    };
    let program = match Program::open(&a.file, &opts) {
        Ok(p) => p,
        Err(e) => return bad(format!("{}: {}", a.file.display(), e.message)),
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    for op in program {
        let op = match op {
            Ok(op) => op,
            Err(e) => {
                let _ = out.flush();
                eprintln!("mcctl: {}: {e}", a.file.display());
                return ExitCode::from(1);
            }
        };
        let written = if a.json {
            writeln!(out, "{}", op_json(&op))
        } else {
            let end = op
                .kind
                .ends()
                .map(|(_, e)| {
                    format!(
                        " to X{:.4} Y{:.4} Z{:.4} A{:.4} B{:.4} C{:.4}, {:.4} mm",
                        e[0],
                        e[1],
                        e[2],
                        e[3],
                        e[4],
                        e[5],
                        length(&op)
                    )
                })
                .unwrap_or_default();
            writeln!(out, "{:>6}  {}{end}", op.line, op.kind.name())
        };
        if written.is_err() {
            // (the reader of stdout went away)
            return ExitCode::SUCCESS;
        }
    }
    let _ = out.flush();
    ExitCode::SUCCESS
}

/// A spindle direction's name in the JSON (`off`: what `SpindleDir::Off` means there).
fn direction(d: SpindleDir, off: &'static str) -> &'static str {
    match d {
        SpindleDir::Cw => "cw",
        SpindleDir::Ccw => "ccw",
        SpindleDir::Off => off,
    }
}
