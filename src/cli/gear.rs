//! `mcctl gear`: electronic gearing (MC_GearIn). The slave follows the master at an integer
//! ratio; the master runs --move (or an auxiliary encoder is watched --for seconds); then
//! MC_GearOut and a halt. Reports both travels and the slave's error against the ratio.

use super::args::{SyncArgs, TravelArgs};
use super::machine::{couple, coupling, parse_master, Coupling};
use super::{bad, on_card};
use crate::{Card, Master, Result};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl gear`.
#[derive(ClapArgs)]
pub struct Args {
    pub slave: usize,
    /// N (axis N's commanded position), actual:N (its encoder) or aux:K (an auxiliary
    /// encoder).
    #[arg(long, value_parser = parse_master)]
    pub master: Master,
    /// Slave counts per master count, NUM/DEN (integers).
    #[arg(long, default_value = "1/1", allow_hyphen_values = true, value_parser = parse_ratio)]
    pub ratio: (i64, i64),
    #[command(flatten)]
    pub sync: SyncArgs,
    #[command(flatten)]
    pub travel: TravelArgs,
    #[arg(long)]
    pub json: bool,
}

/// Couple, run the master, uncouple and report.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let c = match coupling(a.slave, a.master, &a.sync, &a.travel) {
        Ok(c) => c,
        Err(m) => return bad(m),
    };
    on_card(uri, |card| gear(card, &c, a.ratio.0, a.ratio.1, a.json))
}

/// A gear ratio `NUM/DEN` of integers.
pub fn parse_ratio(s: &str) -> Result<(i64, i64), String> {
    let (n, d) = s.split_once('/').unwrap_or((s, "1"));
    match (n.trim().parse(), d.trim().parse()) {
        (Ok(n), Ok(d)) => Ok((n, d)),
        _ => Err(format!("`{s}` is not a ratio NUM/DEN of integers")),
    }
}

/// `mcctl gear`: MC_GearIn at `numerator / denominator`, the master's move, MC_GearOut. Reports
/// both travels and the slave's error against the ratio (0 on the card's integer arithmetic).
pub fn gear(
    card: &Card,
    c: &Coupling,
    numerator: i64,
    denominator: i64,
    json: bool,
) -> Result<String> {
    let slave = card.axis(c.slave)?;
    let [(m0, s0), (m1, s1)] = couple(card, c, || {
        slave.gear_in(c.master, numerator, denominator, &c.limits)
    })?;
    let (dm, ds) = (m1 - m0, s1 - s0);
    let error = ds - dm * numerator as f64 / denominator as f64;
    Ok(if json {
        json!({
            "slave": c.slave,
            "ratio": [numerator, denominator],
            "master_travel": dm,
            "slave_travel": ds,
            "error": error,
        })
        .to_string()
    } else {
        format!(
            "axis {} geared {numerator}/{denominator}: master moved {dm}, slave {ds} (error \
             {error})\n",
            c.slave
        )
    })
}
