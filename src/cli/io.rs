//! `mcctl io`: the card's digital inputs (debounced and raw) and outputs, after setting some
//! outputs with `--set-outputs`; with `--analog` (layout 1.11) the analog inputs, the spare
//! DACs and the path-speed output too, after `--set-analog`, `--analog-input`, `--pso` or
//! `--pso-off`.

use super::on_card;
use crate::{Card, Result};
use clap::Args as ClapArgs;
use motioncard_sdk::{
    AnalogInputSettings, Pso, PsoOutput, PsoState, ANALOG_INPUTS, ANALOG_OUTPUTS,
};
use serde_json::json;
use std::process::ExitCode;

/// `mcctl io`.
#[derive(ClapArgs)]
pub struct Args {
    /// First set the outputs in MASK to VALUE (decimal or 0x hex).
    #[arg(long, num_args = 2, value_names = ["MASK", "VALUE"], value_parser = parse_word)]
    pub set_outputs: Option<Vec<u32>>,
    /// Set spare DAC output OUTPUT (0..3) to VOLTS (clamped to ±10 V, 12 bits). Repeatable.
    #[arg(long, num_args = 2, value_names = ["OUTPUT", "VOLTS"], allow_negative_numbers = true)]
    pub set_analog: Vec<f64>,
    /// Configure analog input INPUT (0..7): its filter's cut-off (Hz, 0: none), threshold (V)
    /// and hysteresis (V); with --events.
    #[arg(long, num_args = 4, value_names = ["INPUT", "CUTOFF_HZ", "THRESHOLD", "HYSTERESIS"], allow_negative_numbers = true)]
    pub analog_input: Option<Vec<f64>>,
    /// The threshold events of --analog-input: rise, fall, both or none.
    #[arg(long, default_value = "none", value_parser = ["rise", "fall", "both", "none"])]
    pub events: String,
    /// Run the path-speed output on group GROUP (configured): output = clamp(min + (max −
    /// min)·v/v_ref, min, max) from the group's actual speed, while --gate is on.
    #[arg(long, value_name = "GROUP")]
    pub pso: Option<usize>,
    /// The PSO's spare DAC (0..3; volts).
    #[arg(long, value_name = "OUTPUT", conflicts_with = "pso_pwm")]
    pub pso_dac: Option<usize>,
    /// The PSO's PWM on this digital output (0..15; duties 0..1), at --pwm-hz.
    #[arg(long, value_name = "OUTPUT")]
    pub pso_pwm: Option<usize>,
    /// The PWM's frequency, Hz.
    #[arg(long, default_value_t = 1000.0)]
    pub pwm_hz: f64,
    /// The digital output (0..15) that switches the PSO on (the path's M62..M65).
    #[arg(long, default_value_t = 0)]
    pub gate: usize,
    /// The PSO's output at rest (V or duty).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub min: f64,
    /// The PSO's output at --v-ref and beyond (V or duty).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    pub max: f64,
    /// The speed of full output, the group's user units per second.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub v_ref: f64,
    /// The PSO's speed filter, Hz (0: none).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub pso_filter: f64,
    /// Stop the path-speed output.
    #[arg(long)]
    pub pso_off: bool,
    /// Print the analog inputs, spare DACs and the PSO too.
    #[arg(long)]
    pub analog: bool,
    /// One JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Set the outputs asked for, then print the inputs and outputs.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        let set = a.set_outputs.as_ref().map(|v| (v[0], v[1]));
        analog_settings(c, &a)?;
        let text = io(c, set, a.json && !a.analog)?;
        if !a.analog {
            return Ok(text);
        }
        let analog = analog(c)?;
        Ok(if a.json {
            let (inputs, raw, outputs) = (c.inputs()?, c.inputs_raw()?, c.outputs()?);
            json!({ "inputs": inputs, "inputs_raw": raw, "outputs": outputs, "analog": analog })
                .to_string()
        } else {
            text + &analog_table(&analog)
        })
    })
}

/// The analog settings of `a`, in order: the spare DACs, the input, the PSO off or on.
fn analog_settings(card: &Card, a: &Args) -> Result<()> {
    for p in a.set_analog.chunks(2) {
        card.set_analog_output(p[0] as usize, p[1])?;
    }
    if let Some(v) = &a.analog_input {
        let (rise, fall) = match a.events.as_str() {
            "rise" => (true, false),
            "fall" => (false, true),
            "both" => (true, true),
            _ => (false, false),
        };
        let s = AnalogInputSettings {
            cutoff_hz: v[1],
            threshold: v[2],
            hysteresis: v[3],
            rise_event: rise,
            fall_event: fall,
        };
        card.configure_analog_input(v[0] as usize, &s)?;
    }
    if a.pso_off {
        card.pso_off()?;
    }
    if let Some(group) = a.pso {
        let output = match (a.pso_pwm, a.pso_dac) {
            (Some(o), _) => PsoOutput::Pwm {
                output: o,
                hz: a.pwm_hz,
            },
            (None, d) => PsoOutput::Dac(d.unwrap_or(0)),
        };
        let p = Pso {
            output,
            gate: a.gate,
            min: a.min,
            max: a.max,
            v_ref: a.v_ref,
            filter_hz: a.pso_filter,
        };
        match card.group(group) {
            Ok(g) => g.pso(&p)?,
            // No such group: the card says so (PsoGroup).
            Err(_) => card.pso_counts(group, &p)?,
        }
    }
    Ok(())
}

/// The analog inputs, spare DACs and PSO as JSON.
fn analog(card: &Card) -> Result<serde_json::Value> {
    let mut inputs = Vec::new();
    for i in 0..ANALOG_INPUTS {
        let a = card.analog_input(i)?;
        inputs.push(json!({
            "sample": a.sample, "value": a.value, "above": a.above,
            "cutoff_hz": a.settings.cutoff_hz, "threshold": a.settings.threshold,
            "hysteresis": a.settings.hysteresis,
            "rise_event": a.settings.rise_event, "fall_event": a.settings.fall_event,
        }));
    }
    let outputs = (0..ANALOG_OUTPUTS)
        .map(|o| card.analog_output(o))
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let p = card.pso_status()?;
    let state = match p.state {
        PsoState::Off => "off",
        PsoState::Closed => "closed",
        PsoState::On => "on",
    };
    Ok(json!({
        "inputs": inputs,
        "outputs": outputs,
        "pso": { "state": state, "group": p.group, "speed_counts": p.speed_counts, "value": p.value },
    }))
}

/// The analog part of the table.
fn analog_table(j: &serde_json::Value) -> String {
    let mut s = String::from("analog inputs (V):\n");
    for (i, a) in j["inputs"].as_array().into_iter().flatten().enumerate() {
        s += &format!(
            "  {i}: {:>9.5} (sample {:>9.5}){}\n",
            a["value"].as_f64().unwrap_or(0.0),
            a["sample"].as_f64().unwrap_or(0.0),
            if a["above"].as_bool() == Some(true) {
                " above"
            } else {
                ""
            }
        );
    }
    s += "analog outputs (V):";
    for v in j["outputs"].as_array().into_iter().flatten() {
        s += &format!(" {:.5}", v.as_f64().unwrap_or(0.0));
    }
    let p = &j["pso"];
    s += &format!(
        "\npso {} (group {}, speed {:.1} counts/s, output {:.5})\n",
        p["state"].as_str().unwrap_or("?"),
        p["group"],
        p["speed_counts"].as_f64().unwrap_or(0.0),
        p["value"].as_f64().unwrap_or(0.0)
    );
    s
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
