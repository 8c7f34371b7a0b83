//! `mcctl replay`: an API trace (recorded with MOTIONCARD_TRACE=FILE or Card::open_traced)
//! replayed against an emulated card, and the first answer or event that differs.

use super::bad;
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl replay`.
#[derive(ClapArgs)]
pub struct Args {
    pub file: std::path::PathBuf,
    #[arg(long)]
    pub json: bool,
}

/// Replay on a stepped `sim` card (exit status 1 when an answer or event differs).
pub fn run(uri: &str, a: Args) -> ExitCode {
    if uri != "sim" {
        return bad(format!(
            "replay runs against an emulated card (--card sim), not {uri}"
        ));
    }
    match crate::replay(&a.file) {
        Ok(r) => {
            println!("{}", replay_report(&r, a.json));
            if r.difference.is_some() {
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            }
        }
        Err(e @ crate::Error::BadConfig(_)) => bad(e.to_string()),
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// `mcctl replay`: what the replay found.
pub fn replay_report(r: &crate::ReplayReport, json: bool) -> String {
    let h = &r.header;
    if json {
        return json!({
            "recorded_on": h.uri,
            "axes": h.axes,
            "servo_rate_hz": h.servo_rate_hz,
            "commands": r.commands,
            "events": r.events,
            "difference": r.difference.as_ref().map(|(line, what)| json!({ "line": line, "what": what })),
        })
        .to_string();
    }
    let head = format!(
        "replayed {} commands, compared {} events (recorded on {}, {} axes, {} Hz)",
        r.commands, r.events, h.uri, h.axes, h.servo_rate_hz
    );
    match &r.difference {
        None => format!("{head}: no difference"),
        Some((line, what)) => format!("{head}\nfirst difference at line {line}: {what}"),
    }
}
