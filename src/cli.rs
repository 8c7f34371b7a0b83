//! What `mcctl` does against a card (`--card URI`): status, moves (absolute, relative,
//! additive, velocity), jog, override, halt, I/O, PT/PVT and configuration files; compare, probe, gearing and
//! camming in [`machine`]. Each returns the text to print (a table, or one
//! JSON object with `json`), or the SDK's error.

use crate::{
    AxisState, BufferMode, Card, MotionFlags, MoveKind, MoveLimits, Result, Status, VelocityLimits,
};
use serde_json::json;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

mod machine;
pub use machine::*;

/// How long mcctl waits for a move to be done.
const WAIT: Duration = Duration::from_secs(600);

fn state_name(s: AxisState) -> String {
    format!("{s:?}")
}

fn status_json(axis: usize, s: &Status) -> serde_json::Value {
    json!({
        "axis": axis,
        "state": state_name(s.state),
        "command_position": s.command_position,
        "actual_position": s.actual_position,
        "command_velocity": s.command_velocity,
        "actual_velocity": s.actual_velocity,
        "following_error": s.following_error,
        "faults": s.faults.bits(),
        "in_velocity": s.motion.contains(MotionFlags::IN_VELOCITY),
        "paused": s.motion.contains(MotionFlags::PAUSED),
        "homed": s.motion.contains(MotionFlags::HOMED),
        "queued": s.queued,
        "override": s.override_factor,
        "target": s.raw.target,
        "tick": s.raw.tick,
    })
}

/// `mcctl status`: every axis (or one), as a table or a JSON array.
pub fn status(card: &Card, axis: Option<usize>, json: bool) -> Result<String> {
    let axes: Vec<usize> = match axis {
        Some(a) => vec![a],
        None => (0..card.info().axes).collect(),
    };
    let statuses = card.statuses(&axes)?;
    if json {
        let rows: Vec<_> = axes
            .iter()
            .zip(&statuses)
            .map(|(&a, s)| status_json(a, s))
            .collect();
        return Ok(serde_json::Value::Array(rows).to_string());
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:>4} {:<18} {:>14} {:>14} {:>12} {:>9} {:>6} {:>5} {:>8}",
        "axis", "state", "cmd pos", "act pos", "cmd vel", "ferr", "queue", "ovr%", "faults"
    );
    for (a, s) in axes.iter().zip(&statuses) {
        let mut state = state_name(s.state);
        if s.motion.contains(MotionFlags::PAUSED) {
            state.push_str(" paused");
        } else if s.motion.contains(MotionFlags::IN_VELOCITY) {
            state.push_str(" at vel");
        }
        let _ = writeln!(
            out,
            "{a:>4} {state:<18} {:>14.3} {:>14.3} {:>12.3} {:>9.3} {:>6} {:>5.0} {:>#8x}",
            s.command_position,
            s.actual_position,
            s.command_velocity,
            s.following_error,
            s.queued,
            s.override_factor * 100.0,
            s.faults.bits()
        );
    }
    Ok(out)
}

/// What `mcctl move` moves by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MoveCmd {
    /// A position move (absolute, relative or additive) within the limits.
    Position(MoveKind, MoveLimits),
    /// Velocity mode at the value, within the limits.
    Velocity(VelocityLimits),
}

/// Power the axis on if it is disabled (`--enable`).
pub fn enable_if_needed(card: &Card, axis: usize) -> Result<()> {
    let ax = card.axis(axis)?;
    if ax.status()?.state == AxisState::Disabled {
        ax.enable()?;
    }
    Ok(())
}

/// `mcctl move`: the move, waited for until done; velocity mode runs at its velocity for
/// `hold`, then halts at its deceleration. Reports where the axis ended.
pub fn run_move(
    card: &Card,
    axis: usize,
    value: f64,
    cmd: MoveCmd,
    hold: Duration,
    json: bool,
) -> Result<String> {
    let ax = card.axis(axis)?;
    let at = match cmd {
        MoveCmd::Position(kind, lim) => ax
            .move_with(kind, value, &lim, BufferMode::Aborting)?
            .wait(WAIT)?,
        MoveCmd::Velocity(lim) => {
            let started = Instant::now();
            ax.move_velocity(value, &lim)?;
            hold_for(card, hold.saturating_sub(started.elapsed()));
            ax.halt(lim.deceleration, lim.jerk)?.wait(WAIT)?
        }
    };
    Ok(if json {
        json!({ "axis": axis, "position": at }).to_string()
    } else {
        format!("axis {axis}: at {at}\n")
    })
}

/// Let `d` pass on the card: a stepped card's time moves only when asked, a real one's on its
/// own.
fn hold_for(card: &Card, d: Duration) {
    match card.sim() {
        Some(sim) => sim.step((d.as_secs_f64() * card.info().servo_rate_hz as f64).round() as u64),
        None => std::thread::sleep(d),
    }
}

/// `mcctl jog`: jog at `velocity` for `hold` (the button held), then release it (a halt at the
/// jog deceleration) and wait for rest. Reports where the axis stopped.
pub fn jog(card: &Card, axis: usize, velocity: f64, hold: Duration, json: bool) -> Result<String> {
    let ax = card.axis(axis)?;
    let started = Instant::now();
    ax.jog(velocity)?;
    hold_for(card, hold.saturating_sub(started.elapsed()));
    let at = ax.jog_release()?.wait(WAIT)?;
    Ok(if json {
        json!({ "axis": axis, "position": at }).to_string()
    } else {
        format!("axis {axis}: jogged to {at}\n")
    })
}

/// `mcctl home`: MC_Home with the axis's homing settings (the CiA 402 `method` instead of the
/// configured one when given), waited for; reports the actual position at the end.
pub fn home(
    card: &Card,
    axis: usize,
    position: f64,
    method: Option<i32>,
    json: bool,
) -> Result<String> {
    let ax = card.axis(axis)?;
    if let Some(m) = method {
        let mut h = ax.homing_settings()?;
        h.method = m;
        ax.configure_homing(&h)?;
    }
    let at = ax.home(position)?.wait(WAIT)?;
    Ok(if json {
        json!({ "axis": axis, "position": at, "homed": ax.status()?.homed() }).to_string()
    } else {
        format!("axis {axis}: homed, at {at}\n")
    })
}

/// `mcctl override`: the axis's velocity override (0 to 2).
pub fn set_override(card: &Card, axis: usize, factor: f64) -> Result<String> {
    card.axis(axis)?.set_override(factor)?;
    Ok(format!("axis {axis}: override {:.1} %\n", factor * 100.0))
}

/// `mcctl halt`: MC_Halt within the deceleration and jerk, waiting for rest.
pub fn halt(card: &Card, axis: usize, deceleration: f64, jerk: f64) -> Result<String> {
    let at = card.axis(axis)?.halt(deceleration, jerk)?.wait(WAIT)?;
    Ok(format!("axis {axis}: halted at {at}\n"))
}

/// `mcctl io`: the card's digital inputs (debounced and raw) and outputs; with `set`, the
/// outputs in `mask` set to `value` first.
pub fn io(card: &Card, set: Option<(u32, u32)>, json: bool) -> Result<String> {
    if let Some((mask, value)) = set {
        card.set_outputs(mask, value)?;
    }
    let (inputs, raw, outputs) = (card.inputs()?, card.inputs_raw()?, card.outputs()?);
    Ok(if json {
        json!({ "inputs": inputs, "inputs_raw": raw, "outputs": outputs }).to_string()
    } else {
        format!("inputs  {inputs:016b} (raw {raw:016b})\noutputs {outputs:016b}\n")
    })
}

/// `mcctl config save FILE`: what the card holds, read back, as TOML into FILE (`-`: the text
/// itself).
pub fn config_save(card: &Card, file: &std::path::Path) -> Result<String> {
    if file.as_os_str() == "-" {
        return card.save_config();
    }
    card.save_config_file(file)?;
    Ok(format!("saved {}\n", file.display()))
}

/// `mcctl config load FILE`: the sections applied (those that differed from the card).
pub fn config_load(card: &Card, file: &std::path::Path, json: bool) -> Result<String> {
    let report = card.load_config_file(file)?;
    Ok(if json {
        json!({ "file": file.display().to_string(), "applied": report.applied }).to_string() + "\n"
    } else if report.applied.is_empty() {
        format!("{}: the card already holds it\n", file.display())
    } else {
        format!(
            "{}: applied {}\n",
            file.display(),
            report.applied.join(", ")
        )
    })
}

/// `mcctl config diff FILE`: the keys where FILE and the card differ, one a line (or a JSON
/// array), and whether there are any.
pub fn config_diff(card: &Card, file: &std::path::Path, json: bool) -> Result<(String, bool)> {
    let d = card.diff_config_file(file)?;
    let text = if json {
        let rows: Vec<_> = d
            .iter()
            .map(|x| json!({ "key": x.key, "file": x.file, "card": x.card }))
            .collect();
        serde_json::Value::Array(rows).to_string() + "\n"
    } else {
        d.iter()
            .map(|x| {
                let card = x.card.as_deref().unwrap_or("(none)");
                format!("{}: file {}, card {card}\n", x.key, x.file)
            })
            .collect()
    };
    Ok((text, !d.is_empty()))
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

/// `mcctl pvt`: stream `points` through the axis's PT/PVT buffer (refilled as it runs),
/// wait for the end; reports the points, the stream's duration and where the axis ended.
pub fn pvt(
    card: &Card,
    axis: usize,
    points: &[crate::PvtPoint],
    mode: crate::PvtMode,
    limits: &crate::PvtLimits,
    json: bool,
) -> Result<String> {
    let ax = card.axis(axis)?;
    ax.pvt_begin(mode, limits, 0)?;
    let first = points.len().min(ax.pvt_free().max(1));
    ax.pvt_push(&points[..first], first == points.len())?;
    let motion = ax.pvt_start()?;
    let mut sent = first;
    while sent < points.len() {
        let room = ax.pvt_free();
        if room == 0 {
            std::thread::sleep(Duration::from_millis(1));
            continue;
        }
        let n = room.min(points.len() - sent);
        ax.pvt_push(&points[sent..sent + n], sent + n == points.len())?;
        sent += n;
    }
    let at = motion.wait(WAIT)?;
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
