//! `mcctl move`: MC_MoveAbsolute, MC_MoveRelative, MC_MoveAdditive or MC_MoveVelocity, waited
//! for (velocity mode: run for a while, then halt).

use super::args::{duration, finite, MoveArgs};
use super::{enable_if_needed, hold_showing, on_card, wait_showing};
use crate::{BufferMode, Card, MoveDirection, MoveKind, MoveLimits, Result, VelocityLimits};
use clap::{Args as ClapArgs, ValueEnum};
use serde_json::json;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// `mcctl move`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// Target, distance or velocity.
    #[arg(allow_hyphen_values = true, value_parser = finite("value"))]
    pub value: f64,
    /// VALUE is a distance from the commanded position.
    #[arg(long, conflicts_with_all = ["additive", "velocity"])]
    pub relative: bool,
    /// VALUE is a distance from the target of the last move.
    #[arg(long, conflicts_with = "velocity")]
    pub additive: bool,
    /// VALUE is a velocity (velocity mode, ContinuousMotion).
    #[arg(long)]
    pub velocity: bool,
    /// An absolute move on a rotary (modulo) axis: the way round (PLCopen MC_Direction; a linear
    /// axis takes only `shortest`).
    #[arg(long, value_enum, default_value = "shortest", conflicts_with_all = ["relative", "additive", "velocity"])]
    pub direction: Direction,
    /// Velocity mode: seconds at the velocity before the halt.
    #[arg(
        long = "for",
        default_value = "1",
        allow_negative_numbers = true,
        value_parser = duration("--for")
    )]
    pub hold: Duration,
    #[command(flatten)]
    pub limits: MoveArgs,
    /// Power the axis on first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    #[arg(long)]
    pub json: bool,
}

/// `mcctl move --direction`.
#[derive(Clone, Copy, ValueEnum)]
pub enum Direction {
    /// The shorter way round (a tie of half a turn: positive).
    Shortest,
    /// Positive.
    Positive,
    /// Negative.
    Negative,
    /// The way the axis moves now (at rest: the way it last moved).
    Current,
}

impl From<Direction> for MoveDirection {
    fn from(d: Direction) -> Self {
        match d {
            Direction::Shortest => MoveDirection::Shortest,
            Direction::Positive => MoveDirection::Positive,
            Direction::Negative => MoveDirection::Negative,
            Direction::Current => MoveDirection::Current,
        }
    }
}

/// The move, waited for.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let l = a.limits;
    let cmd = if a.velocity {
        MoveCmd::Velocity(VelocityLimits {
            acceleration: l.amax,
            deceleration: l.dmax.unwrap_or(l.amax),
            jerk: l.jmax,
        })
    } else {
        let kind = match (a.relative, a.additive) {
            (true, _) => MoveKind::Relative,
            (_, true) => MoveKind::Additive,
            _ => MoveKind::Absolute,
        };
        MoveCmd::Position(kind, l.limits(), a.direction.into())
    };
    on_card(uri, |c| {
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        run_move(c, a.axis, a.value, cmd, a.hold, a.json)
    })
}

/// What `mcctl move` moves by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MoveCmd {
    /// A position move (absolute, relative or additive) within the limits, an absolute one
    /// the way named (a modulo axis).
    Position(MoveKind, MoveLimits, MoveDirection),
    /// Velocity mode at the value, within the limits.
    Velocity(VelocityLimits),
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
        MoveCmd::Position(kind, lim, dir) => {
            let m = ax.move_with_dir(kind, value, &lim, BufferMode::Aborting, dir)?;
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
