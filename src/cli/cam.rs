//! `mcctl cam`: camming (MC_CamTableSelect, MC_CamIn). Loads a cam table (one `master, slave`
//! per line), couples the slave to the master through it, runs the master's --move, then
//! MC_CamOut and a halt. Reports the slave's end position against the table's.

use super::args::{finite, SyncArgs, TravelArgs};
use super::machine::{couple, coupling, parse_master, Coupling};
use super::rows::number_rows;
use super::{bad, on_card};
use crate::{CamSettings, Card, Error, Master, Result};
use card_emu::motion::cam::CamTable;
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl cam`.
#[derive(ClapArgs)]
pub struct Args {
    pub slave: usize,
    pub file: std::path::PathBuf,
    #[arg(long, value_parser = parse_master)]
    pub master: Master,
    /// The card's table (0..4) loaded.
    #[arg(long, default_value_t = 0)]
    pub table: usize,
    /// Cubic spline (else linear).
    #[arg(long)]
    pub cubic: bool,
    /// The table repeats every master span.
    #[arg(long)]
    pub periodic: bool,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 0.0,
        value_parser = finite("--master-offset")
    )]
    pub master_offset: f64,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 0.0,
        value_parser = finite("--slave-offset")
    )]
    pub slave_offset: f64,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1.0,
        value_parser = finite("--master-scale")
    )]
    pub master_scale: f64,
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1.0,
        value_parser = finite("--slave-scale")
    )]
    pub slave_scale: f64,
    /// Start where the slave stands (PLCopen StartMode relative; else absolute, ramped in).
    #[arg(long)]
    pub relative: bool,
    #[command(flatten)]
    pub sync: SyncArgs,
    #[command(flatten)]
    pub travel: TravelArgs,
    #[arg(long)]
    pub json: bool,
}

/// Read the table (exit status 2 naming the file), then load, couple, run and report.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let c = match coupling(a.slave, a.master, &a.sync, &a.travel) {
        Ok(c) => c,
        Err(m) => return bad(m),
    };
    let rows = std::fs::read_to_string(&a.file)
        .map_err(|e| e.to_string())
        .and_then(|t| number_rows(&t, 2..=2, "master, slave"));
    let points = match rows {
        Ok(r) => r.into_iter().map(|v| (v[0], v[1])).collect(),
        Err(e) => return bad(format!("{}: {e}", a.file.display())),
    };
    let job = CamJob {
        points,
        cubic: a.cubic,
        periodic: a.periodic,
        settings: CamSettings {
            table: a.table,
            master_offset: a.master_offset,
            slave_offset: a.slave_offset,
            master_scale: a.master_scale,
            slave_scale: a.slave_scale,
            relative: a.relative,
        },
    };
    on_card(uri, |card| cam(card, &c, &job, a.json))
}

/// A cam table's shape and the mapping of `mcctl cam`.
#[derive(Debug, Clone, PartialEq)]
pub struct CamJob {
    pub points: Vec<(f64, f64)>,
    pub cubic: bool,
    pub periodic: bool,
    pub settings: CamSettings,
}

/// `mcctl cam`: load the table, MC_CamIn, the master's move, MC_CamOut. Reports where the
/// slave ended against where the table puts it for the master's end position (relative: the
/// table's difference from where the cam started).
pub fn cam(card: &Card, c: &Coupling, job: &CamJob, json: bool) -> Result<String> {
    let cs = &job.settings;
    // The card's refusal first (`CamTable`, `NotFinite`); then the same table on the host.
    card.load_cam_table(cs.table, &job.points, job.cubic, job.periodic)?;
    let table = CamTable::new(&job.points, job.cubic, job.periodic).map_err(|e| {
        Error::Protocol(format!("the card took a cam table the host refuses: {e:?}"))
    })?;
    let slave = card.axis(c.slave)?;
    let [(m0, s0), (m, s)] = couple(card, c, || slave.cam_in(c.master, cs, &c.limits))?;
    let at = |m: f64| cs.slave_scale * table.eval((m - cs.master_offset) / cs.master_scale).s;
    // Relative: the card moved the offset so that the cam started where the slave stood.
    let want = if cs.relative {
        s0 + at(m) - at(m0)
    } else {
        cs.slave_offset + at(m)
    };
    Ok(if json {
        json!({
            "slave": c.slave,
            "table": cs.table,
            "points": job.points.len(),
            "master": m,
            "slave_position": s,
            "table_position": want,
            "error": s - want,
        })
        .to_string()
    } else {
        format!(
            "axis {} on cam table {} ({} points): master at {m}, slave at {s}, the table says \
             {want} (error {})\n",
            c.slave,
            cs.table,
            job.points.len(),
            s - want
        )
    })
}
