//! `mcctl home`: MC_Home with the axis's homing settings (CiA 402 methods), waited for.

use super::args::finite;
use super::{enable_if_needed, on_card, wait_showing};
use crate::{Card, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl home`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// What the home point reads (PLCopen's Position; plus the configured home offset).
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 0.0,
        value_parser = finite("--position")
    )]
    pub position: f64,
    /// The CiA 402 method (1-14, 17-30, 33, 34, 35, 37; -1..-4 hard stops) instead of the
    /// configured one.
    #[arg(long, allow_negative_numbers = true)]
    pub method: Option<i32>,
    /// Power the axis on first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    #[arg(long)]
    pub json: bool,
}

/// Home the axis.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        home(c, a.axis, a.position, a.method, a.json)
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
