//! `mcctl freq`: the frequency response measured on the card (layout 1.12): a stepped sine on
//! the axis's position reference (the closed loop, the default) or, with `--plant`, on its
//! servo output (the plant and the open loop), from `--from` to `--to` Hz in `--points`
//! log-spaced points. Prints each point's gain (dB) and phase (degrees) and the resonances
//! found; `--json` one object: `{"points": [{"hz", "gain_db", "phase_deg", ...}], "resonances":
//! [...], ...}`.

use super::{enable_if_needed, on_card};
use crate::{Bode, Card, FreqMode, FreqResponse, FreqSweep, Resonance, Result};
use clap::Args as ClapArgs;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl freq`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// The first frequency, Hz.
    #[arg(long, default_value = "5")]
    pub from: f64,
    /// The last frequency, Hz (at most a quarter of the servo rate; default: 1000 Hz or that
    /// quarter, the lower).
    #[arg(long)]
    pub to: Option<f64>,
    /// Points, log-spaced (1..256).
    #[arg(long, default_value = "40")]
    pub points: usize,
    /// The sine's amplitude: user units on the reference (default 100), volts on the servo
    /// output with --plant (default 0.5).
    #[arg(long, allow_negative_numbers = true)]
    pub amplitude: Option<f64>,
    /// Periods measured at each frequency.
    #[arg(long, default_value = "4")]
    pub cycles: u32,
    /// Least settling time before each measurement, s.
    #[arg(long, default_value = "0.2", allow_negative_numbers = true)]
    pub settle: f64,
    /// The sine on the servo output (volts): the plant P = X/U and the open loop measured
    /// directly; the points are the plant's.
    #[arg(long)]
    pub plant: bool,
    /// Power the axis on first if it is disabled.
    #[arg(long)]
    pub enable: bool,
    #[arg(long)]
    pub json: bool,
}

/// Sweep and print.
pub fn run(uri: &str, a: Args) -> ExitCode {
    on_card(uri, |c| {
        if a.enable {
            enable_if_needed(c, a.axis)?;
        }
        let sweep = sweep_of(c, &a);
        let r = freq(c, a.axis, &sweep)?;
        Ok(if a.json {
            to_json(&r).to_string()
        } else {
            table(&r)
        })
    })
}

/// The sweep the arguments ask for on `card`.
pub fn sweep_of(card: &Card, a: &Args) -> FreqSweep {
    let quarter = card.info().servo_rate_hz as f64 / 4.0;
    let mode = if a.plant {
        FreqMode::Output
    } else {
        FreqMode::Reference
    };
    FreqSweep {
        mode,
        from_hz: a.from,
        to_hz: a.to.unwrap_or(1000f64.min(quarter)),
        points: a.points,
        amplitude: a.amplitude.unwrap_or(if a.plant { 0.5 } else { 100.0 }),
        cycles: a.cycles,
        settle_s: a.settle,
    }
}

/// Run `sweep` on `axis` to its end.
pub fn freq(card: &Card, axis: usize, sweep: &FreqSweep) -> Result<FreqResponse> {
    let ax = card.axis(axis)?;
    let rate = card.info().servo_rate_hz;
    // The card's own time, and as long again for a host that runs slower than it.
    let t = crate::sweep_duration(sweep, rate) * 2.0 + 10.0;
    ax.frequency_response(sweep, Duration::from_secs_f64(t))
}

fn bode_json(b: &[Bode]) -> Vec<Value> {
    b.iter()
        .map(|p| json!({"hz": p.hz, "gain_db": p.gain_db, "phase_deg": p.phase_deg}))
        .collect()
}

fn resonances_json(r: &[Resonance]) -> Vec<Value> {
    r.iter()
        .map(|r| {
            json!({
                "name": r.name(),
                "hz": r.hz,
                "gain_db": r.gain_db,
                "height_db": r.height_db,
                "kind": if r.anti { "anti-resonance" } else { "resonance" },
            })
        })
        .collect()
}

/// The JSON object: `points` (the mode's response: the closed loop, or with --plant the
/// plant), `resonances` (its peaks and dips), `plant`, `open_loop`, `plant_resonances`.
pub fn to_json(r: &FreqResponse) -> Value {
    json!({
        "mode": match r.mode { FreqMode::Reference => "closed_loop", FreqMode::Output => "plant" },
        "complete": r.complete,
        "points": bode_json(&r.response()),
        "resonances": resonances_json(&r.resonances()),
        "plant": bode_json(&r.plant()),
        "open_loop": bode_json(&r.open_loop()),
        "plant_resonances": resonances_json(&r.plant_resonances()),
    })
}

/// One line a point: Hz, the mode's response, the plant, the open loop; then the resonances.
pub fn table(r: &FreqResponse) -> String {
    let (resp, plant, open) = (r.response(), r.plant(), r.open_loop());
    let name = match r.mode {
        FreqMode::Reference => "closed loop",
        FreqMode::Output => "plant",
    };
    let mut s = format!(
        "{:>10}  {:>22}  {:>22}  {:>22}\n",
        "Hz",
        format!("{name} dB / deg"),
        "plant dB / deg",
        "open loop dB / deg"
    );
    for k in 0..resp.len() {
        let _ = writeln!(
            s,
            "{:>10.2}  {:>10.2} {:>11.1}  {:>10.2} {:>11.1}  {:>10.2} {:>11.1}",
            resp[k].hz,
            resp[k].gain_db,
            resp[k].phase_deg,
            plant[k].gain_db,
            plant[k].phase_deg,
            open[k].gain_db,
            open[k].phase_deg
        );
    }
    let found = r.resonances();
    if found.is_empty() {
        let _ = writeln!(s, "no resonance found ({name})");
    }
    for res in found {
        let _ = writeln!(s, "{name}: {}", res.name());
    }
    for res in r.plant_resonances() {
        let _ = writeln!(s, "plant: {}", res.name());
    }
    s
}
