//! What `mcctl` does against a card (`--card URI`): info, status (and watch), power, moves
//! (absolute, relative, additive, velocity), jog, override, halt, stop, reset, I/O, PT/PVT and
//! configuration files; compare, probe, gearing and
//! camming in [`machine`]. Each returns the text to print (a table, or one
//! JSON object with `json`), or the SDK's error.

use crate::proto::raw;
use crate::{
    AxisState, BufferMode, Card, Error, GroupState, GroupStatus, Motion, MotionFlags, MoveKind,
    MoveLimits, Result, Status, VelocityLimits,
};

/// Groups on every card.
const MAX_GROUPS: usize = raw::MC_MAX_GROUPS as usize;
use serde_json::json;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

pub mod interrupt;
mod machine;
mod rows;
mod scope;
pub use machine::*;
pub use rows::*;
pub use scope::*;

/// How long mcctl waits for a move to be done.
const WAIT: Duration = Duration::from_secs(600);

/// How often mcctl looks at the card while a move runs.
const POLL: Duration = Duration::from_millis(2);

/// A progress bar of `len` steps (a spinner without) on stderr, for what takes a while. It is
/// drawn only on a terminal (indicatif hides it when stderr is not one), so a script, a pipe or
/// `--json` output on stdout sees only the result.
pub fn progress(len: Option<u64>, what: &str) -> indicatif::ProgressBar {
    let (bar, template) = match len {
        Some(n) => (
            indicatif::ProgressBar::new(n),
            "{prefix} {bar:20} {pos}/{len} {msg}",
        ),
        None => (
            indicatif::ProgressBar::new_spinner(),
            "{prefix} {spinner} {msg}",
        ),
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.with_prefix(what.to_string())
}

/// Show the axis's state and actual position on `bar` (when it is drawn at all).
fn show_axis(card: &Card, axis: usize, bar: &indicatif::ProgressBar) -> Result<()> {
    if !bar.is_hidden() {
        let s = card.axis(axis)?.status()?;
        bar.set_message(format!(
            "axis {axis} {} at {:.3}",
            state_name(s.state),
            s.actual_position
        ));
        bar.tick();
    }
    Ok(())
}

/// Wait up to [`WAIT`] for `motion` of `axis` to be done, with a spinner showing where the
/// axis is (see [`progress`]). Returns where it ended.
pub fn wait_showing(card: &Card, axis: usize, motion: &Motion, what: &str) -> Result<f64> {
    let bar = progress(None, what);
    let start = Instant::now();
    let r = loop {
        match motion.wait(POLL) {
            Err(Error::Timeout(_)) if start.elapsed() < WAIT => {}
            Err(Error::Timeout(_)) => break Err(Error::Timeout(WAIT)),
            r => break r,
        }
        if let Err(e) = interrupt::check().and_then(|()| show_axis(card, axis, &bar)) {
            break Err(e);
        }
    };
    bar.finish_and_clear();
    r
}

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

fn group_json(group: usize, state: GroupState, g: &GroupStatus) -> serde_json::Value {
    json!({
        "group": group,
        "state": format!("{state:?}"),
        "queued": g.queued,
        "path_queued": g.path_queued,
        "path_free": g.path_free,
        "path_id": g.path_id,
        "path_done": g.path_done,
        "feed": g.feed,
        "feed_override": g.feed_override,
        "tick": g.tick,
    })
}

/// `mcctl status`: every axis (or one) and every group, as a table or one JSON object
/// (`tick`, `axes`, `groups`).
pub fn status(card: &Card, axis: Option<usize>, json: bool) -> Result<String> {
    let axes: Vec<usize> = match axis {
        Some(a) => vec![a],
        None => (0..card.info().axes).collect(),
    };
    let statuses = card.statuses(&axes)?;
    let groups = (0..MAX_GROUPS)
        .map(|g| card.group(g)?.status())
        .collect::<Result<Vec<_>>>()?;
    if json {
        let rows: Vec<_> = axes
            .iter()
            .zip(&statuses)
            .map(|(&a, s)| status_json(a, s))
            .collect();
        let gs: Vec<_> = groups
            .iter()
            .enumerate()
            .map(|(g, (state, st))| group_json(g, *state, st))
            .collect();
        let tick = statuses.first().map_or(0, |s| s.raw.tick);
        return Ok(json!({ "tick": tick, "axes": rows, "groups": gs }).to_string());
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
    let _ = writeln!(
        out,
        "{:>5} {:<17} {:>6} {:>11} {:>10} {:>12} {:>5}",
        "group", "state", "queue", "path q/free", "segment", "feed", "ovr%"
    );
    for (g, (state, st)) in groups.iter().enumerate() {
        let _ = writeln!(
            out,
            "{g:>5} {:<17} {:>6} {:>11} {:>10} {:>12.3} {:>5.0}",
            format!("{state:?}"),
            st.queued,
            format!("{}/{}", st.path_queued, st.path_free),
            st.path_id,
            st.feed,
            st.feed_override * 100.0
        );
    }
    Ok(out)
}

/// `mcctl status --watch`: the status every `every` until `count` refreshes (0: until
/// interrupted), printed as it comes: the table redrawn on a terminal (else one after the
/// other), or one JSON object per line.
pub fn watch(
    card: &Card,
    axis: Option<usize>,
    json: bool,
    every: Duration,
    count: u64,
) -> Result<String> {
    use std::io::{IsTerminal, Write};
    let redraw = !json && std::io::stdout().is_terminal();
    let mut n = 0;
    loop {
        let text = status(card, axis, json)?;
        let mut o = std::io::stdout().lock();
        if redraw {
            let _ = write!(o, "\x1b[H\x1b[2J");
        }
        let _ = writeln!(o, "{}", text.trim_end());
        let _ = o.flush();
        n += 1;
        if count != 0 && n >= count {
            return Ok(String::new());
        }
        hold_for(card, every);
        interrupt::check()?;
    }
}

/// `mcctl info`: what the card is.
pub fn info(card: &Card, json: bool) -> Result<String> {
    let i = card.info();
    let v = i.firmware_version;
    let version = format!("{}.{}.{}", v >> 16, (v >> 8) & 0xff, v & 0xff);
    let caps: Vec<&str> = [
        (raw::MC_CAP_SCURVE, "s-curve"),
        (raw::MC_CAP_FFPIV, "ffpiv"),
        (raw::MC_CAP_EVENT_IRQ, "event-irq"),
    ]
    .iter()
    .filter(|(bit, _)| i.capabilities & bit != 0)
    .map(|(_, name)| *name)
    .collect();
    Ok(if json {
        json!({
            "firmware": version,
            "layout": [i.layout.0, i.layout.1],
            "axes": i.axes,
            "groups": MAX_GROUPS,
            "servo_rate_hz": i.servo_rate_hz,
            "capabilities": caps,
        })
        .to_string()
    } else {
        format!(
            "firmware {version}, DPRAM layout {}.{}\n{} axes, {MAX_GROUPS} groups, servo {} Hz\n\
             capabilities: {}\n",
            i.layout.0,
            i.layout.1,
            i.axes,
            i.servo_rate_hz,
            caps.join(", ")
        )
    })
}

/// `mcctl replay`: what the replay found.
pub fn replay_report(r: &crate::ReplayReport, json: bool) -> String {
    let h = &r.header;
    if json {
        return json!({
            "recorded_on": h.uri,
            "axes": h.axes,
            "servo_rate_hz": h.servo_rate_hz,
            "commands": r.commands,
            "events": r.events,
            "difference": r.difference.as_ref().map(|(line, what)| json!({ "line": line, "what": what })),
        })
        .to_string();
    }
    let head = format!(
        "replayed {} commands, compared {} events (recorded on {}, {} axes, {} Hz)",
        r.commands, r.events, h.uri, h.axes, h.servo_rate_hz
    );
    match &r.difference {
        None => format!("{head}: no difference"),
        Some((line, what)) => format!("{head}\nfirst difference at line {line}: {what}"),
    }
}

/// The axis's state once the card has published the effect of a command just acknowledged:
/// the ack comes within the tick, its status at the tick's end, so the first read may still
/// show the state before. Waits (up to a second) while `before` says it is the old one.
fn state_after(card: &Card, axis: usize, before: impl Fn(AxisState) -> bool) -> Result<AxisState> {
    let ax = card.axis(axis)?;
    for _ in 0..1000 {
        let s = ax.status()?.state;
        if !before(s) {
            return Ok(s);
        }
        hold_for(card, Duration::from_millis(1));
    }
    Ok(ax.status()?.state)
}

/// `mcctl enable` / `disable`: power the axes on or off (MC_Power).
pub fn power(card: &Card, axes: &[usize], on: bool) -> Result<String> {
    let mut out = String::new();
    for &a in axes {
        let ax = card.axis(a)?;
        if on {
            ax.enable()?;
        } else {
            ax.disable()?;
        }
        let now = state_after(card, a, |s| (s == AxisState::Disabled) == on)?;
        let _ = writeln!(out, "axis {a}: {}", state_name(now));
    }
    Ok(out)
}

/// `mcctl stop`: MC_Stop within the deceleration and jerk, waited for; then the stop is
/// released (MC_Stop's Execute falling) unless `hold`, and the axis is in Standstill again.
pub fn stop(card: &Card, axis: usize, deceleration: f64, jerk: f64, hold: bool) -> Result<String> {
    let ax = card.axis(axis)?;
    let at = wait_showing(card, axis, &ax.stop(deceleration, jerk)?, "stopping")?;
    if !hold {
        ax.release_stop()?;
    }
    let now = state_after(card, axis, |s| !hold && s == AxisState::Stopping)?;
    Ok(format!(
        "axis {axis}: stopped at {at}, {}\n",
        state_name(now)
    ))
}

/// `mcctl reset`: MC_Reset on the axes (ErrorStop to Standstill or Disabled), after the card's
/// latched safety faults (e-stop, watchdog) with `faults`.
pub fn reset(card: &Card, axes: &[usize], faults: bool) -> Result<String> {
    if faults {
        card.reset_faults()?;
    }
    let mut out = String::new();
    if axes.is_empty() {
        out.push_str("no axis to reset\n");
    }
    for &a in axes {
        let ax = card.axis(a)?;
        ax.reset()?;
        let now = state_after(card, a, |s| s == AxisState::ErrorStop)?;
        let _ = writeln!(out, "axis {a}: {}", state_name(now));
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
        MoveCmd::Position(kind, lim) => {
            let m = ax.move_with(kind, value, &lim, BufferMode::Aborting)?;
            wait_showing(card, axis, &m, "moving")?
        }
        MoveCmd::Velocity(lim) => {
            let started = Instant::now();
            ax.move_velocity(value, &lim)?;
            hold_showing(
                card,
                axis,
                hold.saturating_sub(started.elapsed()),
                "velocity",
            )?;
            wait_showing(card, axis, &ax.halt(lim.deceleration, lim.jerk)?, "halting")?
        }
    };
    Ok(if json {
        json!({ "axis": axis, "position": at }).to_string()
    } else {
        format!("axis {axis}: at {at}\n")
    })
}

/// Let `d` pass on the card: a stepped card's time moves only when asked, a real one's on its
/// own. A signal ([`interrupt`]) ends the wait early.
fn hold_for(card: &Card, d: Duration) {
    match card.sim() {
        Some(sim) => sim.step((d.as_secs_f64() * card.info().servo_rate_hz as f64).round() as u64),
        None => {
            let end = Instant::now() + d;
            while interrupt::signal().is_none() {
                let left = end.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    break;
                }
                std::thread::sleep(left.min(Duration::from_millis(10)));
            }
        }
    }
}

/// [`hold_for`] `d` in steps of [`POLL`], with a bar of the time held and where the axis is.
fn hold_showing(card: &Card, axis: usize, d: Duration, what: &str) -> Result<()> {
    let bar = progress(Some(d.as_millis() as u64), what);
    bar.set_prefix(format!("{what} (ms)"));
    let mut held = Duration::ZERO;
    while held < d {
        let step = POLL.min(d - held);
        hold_for(card, step);
        interrupt::check()?;
        held += step;
        bar.set_position(held.as_millis() as u64);
        show_axis(card, axis, &bar)?;
    }
    bar.finish_and_clear();
    Ok(())
}

/// `mcctl jog`: jog at `velocity` for `hold` (the button held), then release it (a halt at the
/// jog deceleration) and wait for rest. Reports where the axis stopped.
pub fn jog(card: &Card, axis: usize, velocity: f64, hold: Duration, json: bool) -> Result<String> {
    let ax = card.axis(axis)?;
    let started = Instant::now();
    ax.jog(velocity)?;
    hold_showing(
        card,
        axis,
        hold.saturating_sub(started.elapsed()),
        "jogging",
    )?;
    let at = wait_showing(card, axis, &ax.jog_release()?, "releasing")?;
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
    let at = wait_showing(card, axis, &ax.home(position)?, "homing")?;
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
    let at = wait_showing(
        card,
        axis,
        &card.axis(axis)?.halt(deceleration, jerk)?,
        "halting",
    )?;
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

/// Reads a PT/PVT file a line at a time ([`NumberRows`]: `time, position[, velocity]`).
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
