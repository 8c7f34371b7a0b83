//! `mcctl halt`: MC_Halt, waited for.

use super::args::positive;
use super::{on_card, wait_showing};
use crate::{Card, Result};
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl halt`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    #[arg(long, default_value_t = 1e6, value_parser = positive("--dmax"))]
    pub dmax: f64,
    #[arg(long, default_value_t = 5e7, value_parser = positive("--jmax"))]
    pub jmax: f64,
}

/// Halt the axis.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| halt(c, a.axis, a.dmax, a.jmax))
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
