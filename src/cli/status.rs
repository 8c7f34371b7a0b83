//! `mcctl status`: the axes' state, positions, velocity, following error, queue, override and
//! faults, and the groups' state, queues, path segment and feed; once, or refreshed until
//! interrupted (`--watch`).

use super::args::positive_duration;
use super::{hold_for, interrupt, on_card, state_name, MAX_GROUPS};
use crate::{Card, GroupState, GroupStatus, MotionFlags, Result, Status};
use clap::Args as ClapArgs;
use serde_json::json;
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl status`.
#[derive(ClapArgs)]
pub struct Args {
    /// Only this axis.
    #[arg(long)]
    pub axis: Option<usize>,
    /// Refresh until interrupted (a live table; with --json one object per line).
    #[arg(long)]
    pub watch: bool,
    /// --watch: seconds between refreshes.
    #[arg(
        long,
        default_value = "0.2",
        allow_negative_numbers = true,
        value_parser = positive_duration("--interval")
    )]
    pub interval: Duration,
    /// --watch: stop after this many refreshes (0: never).
    #[arg(long, default_value_t = 0)]
    pub count: u64,
    /// One JSON object (`tick`, `axes`, `groups`) instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Print the status once, or watch it.
pub fn run(uri: &str, a: Args) -> ExitCode {
    if !a.watch {
        return on_card(uri, |c| status(c, a.axis, a.json));
    }
    on_card(uri, |c| watch(c, a.axis, a.json, a.interval, a.count))
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
        // The raw count: on a rotary axis the shaft's, past its turns (the positions wrap).
        "encoder": s.raw.encoder,
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
