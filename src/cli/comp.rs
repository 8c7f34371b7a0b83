//! `mcctl comp AXIS load FILE|show|clear`: an axis's leadscrew pitch-error and backlash
//! compensation (layout 1.9) over [`Axis::set_compensation`], [`Axis::compensation`] and
//! [`Axis::clear_compensation`].
//!
//! FILE is the text a laser interferometer's software exports, reduced to its columns: one
//! point a line, `position, correction[, correction_negative]` in the axis's user units,
//! commas or blanks between, `#` starting a comment (a header line must be one), positions
//! strictly increasing. A third column on every line makes the table bidirectional (the
//! second column moving forward, the third in reverse); on none, one correction for both
//! directions; on some lines only, the file is refused. The corrections are what the card adds
//! to the commanded position; with `--errors` the columns are the measured errors (actual −
//! target, as an interferometer reports them) and their negatives are loaded. Backlash, the
//! bound and the ramp that takes up a jump are options. The file is read and checked whole
//! (the card's checks) before anything is sent; a refusal names its line or its reason and
//! leaves the card's table as it was.
//!
//! [`Axis::set_compensation`]: crate::Axis::set_compensation
//! [`Axis::compensation`]: crate::Axis::compensation
//! [`Axis::clear_compensation`]: crate::Axis::clear_compensation

use super::args::{non_negative, positive};
use super::rows::file_rows;
use super::{bad, interrupted, with_card};
use crate::{Card, CompPoint, Compensation, Result, COMP_POINTS_MAX};
use clap::{Args as ClapArgs, Subcommand};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The ramp's default velocity and acceleration, counts/s and counts/s² (the card's own ramp
/// when a table is cleared), taken into the axis's user units.
const RAMP_COUNTS: (f64, f64) = (1_000.0, 1e6);

/// `mcctl comp`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    #[command(subcommand)]
    pub action: Action,
}

/// `mcctl comp`'s actions.
#[derive(Subcommand)]
pub enum Action {
    /// Load FILE (`position, correction[, correction_negative]` a line, user units) as the
    /// axis's table; the axis at rest.
    Load {
        file: PathBuf,
        /// The largest |correction ± backlash/2| the card takes (user units): a table beyond
        /// it is refused.
        #[arg(long, value_parser = positive("--bound"))]
        bound: f64,
        /// Backlash (user units): +backlash/2 moving forward, −backlash/2 in reverse.
        #[arg(long, default_value_t = 0.0, value_parser = non_negative("--backlash"))]
        backlash: f64,
        /// The ramp's velocity, user units/s (default: 1000 counts/s).
        #[arg(long, value_parser = positive("--ramp-velocity"))]
        ramp_velocity: Option<f64>,
        /// The ramp's acceleration, user units/s² (default: 10⁶ counts/s²).
        #[arg(long, value_parser = positive("--ramp-acceleration"))]
        ramp_acceleration: Option<f64>,
        /// The columns are measured errors (actual − target): load their negatives.
        #[arg(long)]
        errors: bool,
        #[arg(long)]
        json: bool,
    },
    /// The table the card holds (read back), in FILE's format (`--json`: one object).
    Show {
        #[arg(long)]
        json: bool,
    },
    /// Switch the axis's compensation off (the correction ramps out); the axis at rest.
    Clear {
        #[arg(long)]
        json: bool,
    },
}

/// Run the action: a FILE that cannot be read or is malformed is exit status 2 (a bad
/// argument), a refusal of the card 1.
pub fn run(uri: &str, a: Args) -> ExitCode {
    // The file is read and parsed before the card is opened.
    let mut points = None;
    if let Action::Load { file, errors, .. } = &a.action {
        match read_table(file, *errors) {
            Ok(p) => points = Some(p),
            Err(e) => return bad(format!("{}: {e}", file.display())),
        }
    }
    let r = with_card(uri, |c| match a.action {
        Action::Load {
            bound,
            backlash,
            ramp_velocity,
            ramp_acceleration,
            json,
            ..
        } => {
            let (points, bidirectional) = points.take().expect("read above");
            let k = c.axis(a.axis)?.scale_factor().abs();
            let comp = Compensation {
                points,
                bidirectional,
                backlash,
                bound,
                ramp_velocity: ramp_velocity.unwrap_or(RAMP_COUNTS.0 / k),
                ramp_acceleration: ramp_acceleration.unwrap_or(RAMP_COUNTS.1 / k),
            };
            load(c, a.axis, &comp, json)
        }
        Action::Show { json } => show(c, a.axis, json),
        Action::Clear { json } => clear(c, a.axis, json),
    });
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
        Ok(text) => {
            print!("{text}");
            if !text.ends_with('\n') {
                println!();
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// The points of a table file and whether it gives a correction per direction. Err: the line
/// and what is wrong.
pub fn read_table(
    path: &Path,
    errors: bool,
) -> std::result::Result<(Vec<CompPoint>, bool), String> {
    let what = "position, correction[, correction_negative]";
    let mut points = Vec::new();
    let mut width = None::<(usize, usize)>;
    for row in file_rows(path, 2..=3, what)? {
        let row = row?;
        match width {
            None => width = Some((row.n, row.line)),
            Some((n, line)) if n != row.n => {
                return Err(format!(
                    "line {}: {} columns, line {line} {n}: give the reverse correction on \
                     every line or on none",
                    row.line, row.n
                ))
            }
            Some(_) => {}
        }
        if points.len() == COMP_POINTS_MAX {
            return Err(format!(
                "line {}: more than {COMP_POINTS_MAX} points (the card's table)",
                row.line
            ));
        }
        if let Some(last) = points.last().map(|p: &CompPoint| p.position) {
            if row.values[0] <= last {
                return Err(format!(
                    "line {}: position {} after {last}: positions must strictly increase",
                    row.line, row.values[0]
                ));
            }
        }
        // `+ 0.0`: an error of 0 is a correction of 0, not −0.
        let sign = if errors { -1.0 } else { 1.0 };
        let forward = sign * row.values[1] + 0.0;
        let reverse = if row.n == 3 {
            sign * row.values[2] + 0.0
        } else {
            forward
        };
        points.push(CompPoint {
            position: row.values[0],
            forward,
            reverse,
        });
    }
    if points.is_empty() {
        return Err(format!("no points (one `{what}` a line)"));
    }
    Ok((points, width.is_some_and(|(n, _)| n == 3)))
}

/// `mcctl comp AXIS load`: load the table; report what the card holds now.
pub fn load(card: &Card, axis: usize, comp: &Compensation, json: bool) -> Result<String> {
    let ax = card.axis(axis)?;
    ax.set_compensation(comp)?;
    let held = ax.compensation()?;
    Ok(if json {
        json!({ "axis": axis, "loaded": comp.points.len(), "table": held.as_ref().map(table_json) })
            .to_string()
    } else {
        format!(
            "axis {axis}: {} points loaded ({}), backlash {}, bound {}\n",
            comp.points.len(),
            if comp.bidirectional {
                "a correction per direction"
            } else {
                "one correction for both directions"
            },
            comp.backlash,
            comp.bound
        )
    })
}

/// `mcctl comp AXIS show`: the table read back from the card, in the file's format.
pub fn show(card: &Card, axis: usize, json: bool) -> Result<String> {
    let held = card.axis(axis)?.compensation()?;
    Ok(match (json, held) {
        (true, h) => json!({ "axis": axis, "table": h.as_ref().map(table_json) }).to_string(),
        (false, None) => format!("# axis {axis}: no compensation\n"),
        (false, Some(c)) => {
            let mut out = format!(
                "# axis {axis}: backlash {}, bound {}, ramp {} /s, {} /s²\n# position, correction{}\n",
                c.backlash,
                c.bound,
                c.ramp_velocity,
                c.ramp_acceleration,
                if c.bidirectional {
                    ", correction_negative"
                } else {
                    ""
                }
            );
            for p in &c.points {
                out += &if c.bidirectional {
                    format!("{}, {}, {}\n", p.position, p.forward, p.reverse)
                } else {
                    format!("{}, {}\n", p.position, p.forward)
                };
            }
            out
        }
    })
}

/// `mcctl comp AXIS clear`.
pub fn clear(card: &Card, axis: usize, json: bool) -> Result<String> {
    card.axis(axis)?.clear_compensation()?;
    Ok(if json {
        json!({ "axis": axis, "table": null }).to_string()
    } else {
        format!("axis {axis}: compensation off\n")
    })
}

fn table_json(c: &Compensation) -> serde_json::Value {
    json!({
        "backlash": c.backlash,
        "bound": c.bound,
        "ramp_velocity": c.ramp_velocity,
        "ramp_acceleration": c.ramp_acceleration,
        "bidirectional": c.bidirectional,
        "points": c.points.iter().map(|p| [p.position, p.forward, p.reverse]).collect::<Vec<_>>(),
    })
}
