//! `mcctl pvt`: a PT/PVT file streamed through the axis's point buffer, to its end.

use super::args::positive;
use super::rows::{file_rows, number_rows};
use super::{bad, enable_if_needed, interrupt, on_card, progress, wait_showing};
use crate::{Card, Error, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl pvt`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    pub file: std::path::PathBuf,
    /// PT: ignore the velocities, let the card estimate them.
    #[arg(long)]
    pub pt: bool,
    /// Velocity limit of every segment.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 100_000.0,
        value_parser = positive("--vmax")
    )]
    pub vmax: f64,
    /// Acceleration limit of every segment.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e6,
        value_parser = positive("--amax")
    )]
    pub amax: f64,
    /// Enable the axis first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    /// One JSON object instead of a line.
    #[arg(long)]
    pub json: bool,
}

/// Check the whole file (exit status 2 naming its line), then stream it.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let file = match pvt_file(&a.file) {
        Ok(f) => f,
        Err(e) => return bad(e),
    };
    let mode = if a.pt || !file.velocities {
        crate::PvtMode::Pt
    } else {
        crate::PvtMode::Pvt
    };
    let limits = crate::PvtLimits {
        velocity: a.vmax,
        acceleration: a.amax,
    };
    on_card(uri, |c| {
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        pvt(c, a.axis, &file, mode, &limits, a.json)
    })
}

/// The points of a PT/PVT file: one `time, position[, velocity]` per line ([`number_rows`]),
/// and whether every line gave a velocity (PVT, else PT).
pub fn pvt_points(text: &str) -> std::result::Result<(Vec<crate::PvtPoint>, bool), String> {
    let rows = number_rows(text, 2..=3, "time, position[, velocity]")?;
    let velocities = rows.iter().all(|v| v.len() == 3);
    let pts = rows
        .iter()
        .map(|v| crate::PvtPoint::new(v[0], v[1], v.get(2).copied().unwrap_or(0.0)))
        .collect();
    Ok((pts, velocities))
}

/// A PT/PVT file for `mcctl pvt`: its points, the line of each, and whether every line gave
/// a velocity (PVT, else PT).
#[derive(Debug, Clone, PartialEq)]
pub struct PvtFile {
    /// The file, as errors name it.
    pub origin: String,
    pub points: Vec<crate::PvtPoint>,
    /// The line (from 1) of each point.
    pub lines: Vec<usize>,
    pub velocities: bool,
}

/// Reads a PT/PVT file a line at a time ([`NumberRows`](super::rows::NumberRows): `time,
/// position[, velocity]`).
pub fn pvt_file(path: &std::path::Path) -> std::result::Result<PvtFile, String> {
    let origin = path.display().to_string();
    let mut f = PvtFile {
        origin: origin.clone(),
        points: Vec::new(),
        lines: Vec::new(),
        velocities: true,
    };
    for row in file_rows(path, 2..=3, "time, position[, velocity]")
        .map_err(|e| format!("{origin}: {e}"))?
    {
        let r = row.map_err(|e| format!("{origin}: {e}"))?;
        f.points
            .push(crate::PvtPoint::new(r.values[0], r.values[1], r.values[2]));
        f.lines.push(r.line);
        f.velocities &= r.n == 3;
    }
    if f.points.is_empty() {
        return Err(format!("{origin}: no points"));
    }
    Ok(f)
}

/// A point's refusal from a push of the points from `from`: the point's index in the file, its
/// line, and for a time refusal the reason its own gap gives (too soon, or later than the
/// longest segment).
fn pvt_refusal(file: &PvtFile, from: usize, e: Error) -> Error {
    let Error::PvtPoint {
        target,
        index,
        code,
        reason,
    } = e
    else {
        return e;
    };
    let i = from + index;
    let reason = match code {
        crate::NackCode::PvtTime => {
            let before = i.checked_sub(1).map_or(0.0, |b| file.points[b].time);
            crate::pvt_time_reason(Some(file.points[i].time - before))
        }
        _ => reason,
    };
    Error::AtLine {
        origin: file.origin.clone(),
        line: file.lines[i],
        source: Box::new(Error::PvtPoint {
            target,
            index: i,
            code,
            reason,
        }),
    }
}

/// `mcctl pvt`: stream the file's points through the axis's PT/PVT buffer (refilled as it
/// runs), wait for the end; reports the points, the stream's duration and where the axis
/// ended. A refused point is named by its index in the file and its line.
pub fn pvt(
    card: &Card,
    axis: usize,
    file: &PvtFile,
    mode: crate::PvtMode,
    limits: &crate::PvtLimits,
    json: bool,
) -> Result<String> {
    let ax = card.axis(axis)?;
    let points = &file.points[..];
    let push = |from: usize, to: usize| {
        ax.pvt_push(&points[from..to], to == points.len())
            .map_err(|e| pvt_refusal(file, from, e))
    };
    ax.pvt_begin(mode, limits, 0)?;
    let first = points.len().min(ax.pvt_free().max(1));
    push(0, first)?;
    let motion = ax.pvt_start()?;
    let mut sent = first;
    let bar = progress(Some(points.len() as u64), "streaming points");
    bar.set_position(sent as u64);
    while sent < points.len() {
        interrupt::check()?;
        let room = ax.pvt_free();
        if room == 0 {
            std::thread::sleep(Duration::from_millis(1));
            continue;
        }
        let n = room.min(points.len() - sent);
        push(sent, sent + n)?;
        sent += n;
        bar.set_position(sent as u64);
    }
    bar.finish_and_clear();
    let at = wait_showing(card, axis, &motion, "running the stream")?;
    let last = points[points.len() - 1];
    Ok(if json {
        json!({
            "axis": axis,
            "points": points.len(),
            "duration": last.time,
            "target": last.position,
            "position": at,
        })
        .to_string()
    } else {
        format!(
            "axis {axis}: {} points in {} s, at {at} (last point {})\n",
            points.len(),
            last.time,
            last.position
        )
    })
}
