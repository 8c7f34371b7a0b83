//! `mcctl handwheel`: an auxiliary encoder jogs an axis (layout 1.10). The wheel is selected,
//! held --for seconds (the axis shown as it follows), then let go: the axis goes on to where
//! the wheel put it. `--off` only lets go of the axis's handwheel. A host that leaves closes its
//! session, and the card halts what it started: the wheel drives the axis only while mcctl runs.

use super::args::duration;
use super::{enable_if_needed, hold_showing, on_card, wait_showing};
use crate::{Card, Handwheel, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// `mcctl handwheel`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// The auxiliary encoder input.
    #[arg(long, default_value = "0")]
    pub input: usize,
    /// Encoder counts per detent: 1, 10, 100 (any whole number, 1 to 10000 either way).
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    pub ratio: i32,
    /// Auxiliary counts per detent (4: a quadrature wheel, one detent per cycle).
    #[arg(long, default_value_t = Handwheel::DEFAULT_DETENT)]
    pub detent: u32,
    /// Seconds the wheel drives the axis before it is let go.
    #[arg(
        long = "for",
        default_value = "10",
        allow_negative_numbers = true,
        value_parser = duration("--for")
    )]
    pub hold: Duration,
    /// Only let go of the axis's handwheel.
    #[arg(long, conflicts_with_all = ["input", "ratio", "detent", "hold"])]
    pub off: bool,
    /// Power the axis on first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    #[arg(long)]
    pub json: bool,
}

/// Select, hold, let go; or let go.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        if a.off {
            return off(c, a.axis, a.json);
        }
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        let w = Handwheel::new(a.input).ratio(a.ratio).detent(a.detent);
        handwheel(c, a.axis, &w, a.hold, a.json)
    })
}

/// `mcctl handwheel`: select `w` on `axis`, let it drive the axis for `hold`, let go and wait
/// until the axis is done. Reports the wheel's counts and the axis's travel.
pub fn handwheel(
    card: &Card,
    axis: usize,
    w: &Handwheel,
    hold: Duration,
    json: bool,
) -> Result<String> {
    let ax = card.axis(axis)?;
    let started = Instant::now();
    let x0 = ax.status()?.command_position;
    let motion = ax.handwheel(w)?;
    let m0 = card.aux_encoder(w.input)?;
    hold_showing(
        card,
        axis,
        hold.saturating_sub(started.elapsed()),
        "handwheel",
    )?;
    let turned = card.aux_encoder(w.input)? - m0;
    ax.handwheel_off()?;
    let at = wait_showing(card, axis, &motion, "letting go")?;
    let moved = ax.status()?.command_position - x0;
    Ok(if json {
        json!({
            "axis": axis,
            "input": w.input,
            "ratio": w.ratio,
            "detent": w.detent,
            "turned": turned,
            "moved": moved,
            "position": at,
        })
        .to_string()
    } else {
        format!(
            "axis {axis}: handwheel {} x{} ({} counts a detent): wheel turned {turned} counts, \
             axis moved {moved}, at {at}\n",
            w.input, w.ratio, w.detent
        )
    })
}

/// `mcctl handwheel --off`: let go of the axis's handwheel.
pub fn off(card: &Card, axis: usize, json: bool) -> Result<String> {
    card.axis(axis)?.handwheel_off()?;
    Ok(if json {
        json!({ "axis": axis, "handwheel": "off" }).to_string()
    } else {
        format!("axis {axis}: handwheel let go\n")
    })
}
