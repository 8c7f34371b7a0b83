//! `mcctl run`: a G-code program (RS274/NGC subset) on group 0 over axes 0, 1, 2 through the
//! card's path buffer, measured; the work is [`crate::run`].

use super::args::{non_negative, positive};
use super::{bad, on_card};
use crate::Card;
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl run`.
#[derive(ClapArgs)]
pub struct Args {
    /// The program.
    pub file: std::path::PathBuf,
    /// Corner tolerance, mm (0: exact stop at every corner).
    #[arg(
        long,
        default_value_t = 0.01,
        allow_negative_numbers = true,
        value_parser = non_negative("--tolerance")
    )]
    pub tolerance: f64,
    /// The largest feed, mm/s (also the rapid feed).
    #[arg(
        long,
        default_value_t = 100.0,
        allow_negative_numbers = true,
        value_parser = positive("--feed-limit")
    )]
    pub feed_limit: f64,
    /// Every axis's velocity limit, mm/s (one value, or X,Y,Z).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "100",
        allow_negative_numbers = true,
        value_parser = positive("--vmax")
    )]
    pub vmax: Vec<f64>,
    /// Every axis's acceleration limit, mm/s² (one value, or X,Y,Z).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1000",
        allow_negative_numbers = true,
        value_parser = positive("--amax")
    )]
    pub amax: Vec<f64>,
    /// Every axis's jerk limit, mm/s³ (one value, or X,Y,Z).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "100000",
        allow_negative_numbers = true,
        value_parser = positive("--jmax")
    )]
    pub jmax: Vec<f64>,
    /// Counts per mm.
    #[arg(long, default_value_t = 1000.0, value_parser = positive("--scale"))]
    pub scale: f64,
    /// Send every line as it is: no runs of short lines sent as the curve they sample
    /// (see the SDK's chord fitting).
    #[arg(long)]
    pub no_chord_fit: bool,
    /// The tool table, in LinuxCNC's format (`T1 P1 Z10 D6 ;comment`, lengths in mm).
    #[arg(long)]
    pub tool_table: Option<std::path::PathBuf>,
    /// A directory where `o<name> call` looks for `name.ngc` when the program does not
    /// define the subroutine (before the program's own directory; may be repeated).
    #[arg(long)]
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// The card's digital input the touch probe is wired to (G38.2–G38.5; without it a
    /// probing move is an error).
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..16))]
    pub probe_input: Option<u32>,
    /// The spindle's card axis (not 0, 1, 2): M3/M4/M5 and S turn it, G33/G33.1 follow its
    /// encoder. Without it the spindle is not on the card and G33/G33.1 are refused.
    #[arg(long)]
    pub spindle_axis: Option<usize>,
    /// The spindle's encoder counts per revolution (its scale: its user unit a revolution).
    #[arg(long, default_value_t = 10_000.0, value_parser = positive("--spindle-scale"))]
    pub spindle_scale: f64,
    /// The spindle's largest speed, rpm (a larger S runs at this).
    #[arg(long, default_value_t = 3000.0, value_parser = positive("--spindle-max-rpm"))]
    pub spindle_max_rpm: f64,
    /// The spindle's acceleration, rev/s².
    #[arg(long, default_value_t = 100.0, value_parser = positive("--spindle-accel"))]
    pub spindle_accel: f64,
    /// The spindle's jerk, rev/s³.
    #[arg(long, default_value_t = 2000.0, value_parser = positive("--spindle-jerk"))]
    pub spindle_jerk: f64,
    /// The card output M7 (mist) sets and M9 clears.
    #[arg(long)]
    pub mist_output: Option<u32>,
    /// The card output M8 (flood) sets and M9 clears.
    #[arg(long)]
    pub flood_output: Option<u32>,
    #[arg(long)]
    pub json: bool,
}

/// One limit per axis: one value for all three, or X,Y,Z.
fn three(v: &[f64], what: &str) -> Result<[f64; 3], String> {
    match *v {
        [x] => Ok([x; 3]),
        [x, y, z] => Ok([x, y, z]),
        _ => Err(format!("--{what}: one positive value or three (X,Y,Z)")),
    }
}

/// Run the program: on `--card sim` a stepped card mcctl steps (every tick measured), else
/// the card given.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let limits = (|| {
        Ok::<_, String>((
            three(&a.vmax, "vmax")?,
            three(&a.amax, "amax")?,
            three(&a.jmax, "jmax")?,
        ))
    })();
    let (vmax, amax, jmax) = match limits {
        Ok(l) => l,
        Err(m) => return bad(m),
    };
    // Read as it runs; one that cannot be opened is a bad argument.
    if let Err(e) = std::fs::File::open(&a.file) {
        return bad(format!("{}: {e}", a.file.display()));
    }
    let tools = match &a.tool_table {
        Some(f) => match motioncard_sdk::gcode::ToolTable::load(f) {
            Ok(t) => t,
            Err(e) => return bad(format!("--tool-table {}: {e}", f.display())),
        },
        None => Default::default(),
    };
    let opts = crate::run::RunOptions {
        tools,
        subroutine_path: a.subroutine_path,
        tolerance: a.tolerance,
        feed_limit: a.feed_limit,
        vmax,
        amax,
        jmax,
        scale: a.scale,
        progress: !a.json,
        chord_fit: !a.no_chord_fit,
        probe_input: a.probe_input,
        spindle: a.spindle_axis.map(|axis| {
            (
                motioncard_sdk::gcode::run::SpindleSettings::new(
                    axis,
                    a.spindle_max_rpm,
                    a.spindle_accel,
                    a.spindle_jerk,
                ),
                a.spindle_scale,
            )
        }),
        mist_output: a.mist_output,
        flood_output: a.flood_output,
    };
    let (file, json) = (a.file, a.json);
    let body = |c: &Card| crate::run::run(c, &file, &opts, json);
    if uri == "sim" {
        // A stepped card: mcctl steps it and measures every tick.
        let card = match Card::open_sim(crate::SimOptions {
            clock: crate::Clock::Stepped,
            emu: Default::default(),
        }) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("mcctl: {e}");
                return ExitCode::from(1);
            }
        };
        match body(&card) {
            Ok(t) => {
                println!("{t}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("mcctl: {e}");
                ExitCode::from(1)
            }
        }
    } else {
        on_card(uri, body)
    }
}
