//! `mcctl enable` and `mcctl disable`: MC_Power on or off.

use super::{on_card, state_after, state_name};
use crate::{AxisState, Card, Result};
use clap::Args as ClapArgs;
use std::fmt::Write as _;
use std::process::ExitCode;

/// `mcctl enable` and `mcctl disable`.
#[derive(ClapArgs)]
pub struct Args {
    #[arg(required = true)]
    pub axes: Vec<usize>,
}

/// Power the axes on (`on`) or off.
pub fn run(uri: &str, a: Args, on: bool) -> ExitCode {
    on_card(uri, |c| power(c, &a.axes, on))
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
