//! `mcctl info`: what the card is: firmware and layout versions, axes, groups, servo rate,
//! capabilities.

use super::{on_card, MAX_GROUPS};
use crate::proto::raw;
use crate::{Card, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl info`.
#[derive(ClapArgs)]
pub struct Args {
    #[arg(long)]
    pub json: bool,
}

/// Print what the card is.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| info(c, a.json))
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
