//! `mcctl io`: the card's digital inputs (debounced and raw) and outputs, after setting some
//! outputs with `--set-outputs`.

use super::on_card;
use crate::{Card, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl io`.
#[derive(ClapArgs)]
pub struct Args {
    /// First set the outputs in MASK to VALUE (decimal or 0x hex).
    #[arg(long, num_args = 2, value_names = ["MASK", "VALUE"], value_parser = parse_word)]
    pub set_outputs: Option<Vec<u32>>,
    /// One JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Set the outputs asked for, then print the inputs and outputs.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let set = a.set_outputs.map(|v| (v[0], v[1]));
    on_card(uri, |c| io(c, set, a.json))
}

/// A 32-bit word in decimal or 0x hex.
pub fn parse_word(s: &str) -> Result<u32, String> {
    let r = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16),
        None => s.parse::<u32>(),
    };
    r.map_err(|e| format!("`{s}` is not a 32-bit word: {e}"))
}

/// `mcctl io`: the card's digital inputs (debounced and raw) and outputs; with `set`, the
/// outputs in `mask` set to `value` first.
pub fn io(card: &Card, set: Option<(u32, u32)>, json: bool) -> Result<String> {
    if let Some((mask, value)) = set {
        card.set_outputs(mask, value)?;
    }
    let (inputs, raw, outputs) = (card.inputs()?, card.inputs_raw()?, card.outputs()?);
    Ok(if json {
        json!({ "inputs": inputs, "inputs_raw": raw, "outputs": outputs }).to_string()
    } else {
        format!("inputs  {inputs:016b} (raw {raw:016b})\noutputs {outputs:016b}\n")
    })
}
