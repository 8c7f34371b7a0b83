//! `mcctl jog`: jog at a signed velocity with the axis's jog limits for a while (the button
//! held), then release.

use super::args::{duration, finite};
use super::{enable_if_needed, hold_showing, on_card, wait_showing};
use crate::{Card, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// `mcctl jog`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    #[arg(allow_hyphen_values = true, value_parser = finite("velocity"))]
    pub velocity: f64,
    /// Seconds the button is held.
    #[arg(
        long = "for",
        default_value = "1",
        allow_negative_numbers = true,
        value_parser = duration("--for")
    )]
    pub hold: Duration,
    /// Power the axis on first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    #[arg(long)]
    pub json: bool,
}

/// Jog, then release.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        jog(c, a.axis, a.velocity, a.hold, a.json)
    })
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
