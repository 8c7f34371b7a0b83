//! `mcctl override`: MC_SetOverride, the axis's velocity factor.

use super::args::finite;
use super::on_card;
use crate::{Card, Result};
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl override`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    // 0 to 2: the card refuses another factor itself (exit status 1, with its reason).
    #[arg(allow_hyphen_values = true, value_parser = finite("factor"))]
    pub factor: f64,
}

/// Set the override.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| set_override(c, a.axis, a.factor))
}

/// `mcctl override`: the axis's velocity override (0 to 2).
pub fn set_override(card: &Card, axis: usize, factor: f64) -> Result<String> {
    card.axis(axis)?.set_override(factor)?;
    Ok(format!("axis {axis}: override {:.1} %\n", factor * 100.0))
}
