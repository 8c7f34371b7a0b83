//! `mcctl stop`: MC_Stop, waited for, then the stop released.

use super::args::positive;
use super::{on_card, state_after, state_name, wait_showing};
use crate::{AxisState, Card, Result};
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl stop`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e6,
        value_parser = positive("--dmax")
    )]
    pub dmax: f64,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 5e7,
        value_parser = positive("--jmax")
    )]
    pub jmax: f64,
    #[arg(long)]
    pub hold: bool,
}

/// Stop the axis.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| stop(c, a.axis, a.dmax, a.jmax, a.hold))
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
