//! `mcctl reset`: MC_Reset, the axes out of ErrorStop (after the card's latched safety faults
//! with `--faults`).

use super::{on_card, state_after, state_name};
use crate::{AxisState, Card, Result};
use clap::Args as ClapArgs;
use std::fmt::Write as _;
use std::process::ExitCode;

/// `mcctl reset`.
#[derive(ClapArgs)]
pub struct Args {
    /// The axes (none: every axis in ErrorStop).
    pub axes: Vec<usize>,
    #[arg(long)]
    pub faults: bool,
}

/// Reset the axes given, or every axis in ErrorStop.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        let axes = if a.axes.is_empty() {
            // Every axis that needs it.
            let all: Vec<usize> = (0..c.info().axes).collect();
            let st = c.statuses(&all)?;
            all.into_iter()
                .zip(st)
                .filter(|(_, s)| s.state == AxisState::ErrorStop)
                .map(|(a, _)| a)
                .collect()
        } else {
            a.axes
        };
        reset(c, &axes, a.faults)
    })
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
