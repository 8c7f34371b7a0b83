//! `mcctl list`: every card reachable from this machine (`card-emu` processes, UIO devices,
//! PCI functions with the card's IDs), each with its URI, name, serial, axes, servo rate, sync
//! role and whether a host holds it, read without disturbing that host (`Card::list`). Opens
//! no card: `--card` is not used.

use crate::{Card, CardListing, SyncRole};
use clap::Args as ClapArgs;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl list`.
#[derive(ClapArgs)]
pub struct Args {
    /// One JSON object: `{"cards": [...]}`.
    #[arg(long)]
    pub json: bool,
}

/// List the cards; exit status 1 only when no listing could be made at all (a card that
/// could not be read is listed with its error).
pub fn run(a: Args) -> ExitCode {
    match Card::list().map(|cards| render(&cards, a.json)) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// The sync role as shown: `alone`, `master`, or `follower of NAME`.
fn role(l: &CardListing) -> String {
    match l.sync_role {
        SyncRole::Follower => format!("follower of {}", l.master),
        r => r.as_str().into(),
    }
}

/// The listing as a table, or one JSON object.
pub fn render(cards: &[CardListing], json: bool) -> String {
    if json {
        let cards: Vec<serde_json::Value> = cards
            .iter()
            .map(|l| {
                json!({
                    "uri": l.uri,
                    "name": l.name,
                    "serial": l.serial,
                    "axes": l.axes,
                    "servo_rate_hz": l.servo_rate_hz,
                    "layout": [l.layout.0, l.layout.1],
                    "firmware": l.firmware_version,
                    "sync_role": l.sync_role.as_str(),
                    "sync_state": l.sync_state.as_str(),
                    "master": l.master,
                    "available": l.available,
                    "open_here": l.open_here,
                    "error": l.error.as_ref().map(|e| json!({
                        "code": e.kind.c_name(),
                        "message": e.message,
                    })),
                })
            })
            .collect();
        return format!("{}\n", json!({ "cards": cards }));
    }
    if cards.is_empty() {
        return "no cards found (emu: processes, UIO devices, PCI functions)\n".into();
    }
    let rows: Vec<[String; 7]> = cards
        .iter()
        .map(|l| match &l.error {
            None => [
                l.uri.clone(),
                l.name.clone(),
                l.serial.to_string(),
                l.axes.to_string(),
                format!("{} Hz", l.servo_rate_hz),
                role(l),
                if l.available { "available" } else { "busy" }.into(),
            ],
            Some(e) => [
                l.uri.clone(),
                l.name.clone(),
                "-".into(),
                "-".into(),
                "-".into(),
                "-".into(),
                format!("not read: {}", e.message),
            ],
        })
        .collect();
    let head = ["URI", "NAME", "SERIAL", "AXES", "RATE", "SYNC", "STATE"];
    let mut width = head.map(str::len);
    for r in &rows {
        for (w, c) in width.iter_mut().zip(r) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i + 1 == cells.len() {
                s.push_str(c);
            } else {
                s.push_str(&format!("{c:<w$}  ", w = width[i]));
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(&head.map(String::from));
    for r in &rows {
        out.push_str(&line(r));
    }
    out
}
