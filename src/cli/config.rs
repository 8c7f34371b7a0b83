//! `mcctl config save|load|diff`: card configuration files in TOML (every value in the card's
//! units).

use super::{bad, interrupted, with_card};
use crate::{Card, ErrorKind, Result};
use clap::Subcommand;
use serde_json::json;
use std::process::ExitCode;

/// `mcctl config`'s actions: card configuration files (layout 1.8).
#[derive(Subcommand)]
pub enum Action {
    /// Write what the card holds (read back from the card) to FILE as TOML (`-`: standard
    /// output).
    Save { file: std::path::PathBuf },
    /// Check FILE whole against the card (exit status 2, naming the key and its line, and
    /// nothing applied, when anything is wrong), then apply the sections that differ.
    Load {
        file: std::path::PathBuf,
        /// One JSON object (the sections applied) instead of lines.
        #[arg(long)]
        json: bool,
    },
    /// The keys where FILE and the card differ (FILE checked as by load). Exit status 0 when
    /// they are equal, 1 when they differ, like diff.
    Diff {
        file: std::path::PathBuf,
        /// One JSON array of {key, file, card} instead of lines.
        #[arg(long)]
        json: bool,
    },
}

/// `mcctl config`: as [`on_card`](super::on_card), but a file that does not parse or validate
/// (or cannot be read or written) is exit status 2, a bad argument, and `diff` exits 1 when
/// the file and the card differ.
pub fn run(uri: &str, action: Action) -> ExitCode {
    let r = with_card(uri, |card| match &action {
        Action::Save { file } => config_save(card, file).map(|t| (t, false)),
        Action::Load { file, json } => config_load(card, file, *json).map(|t| (t, false)),
        Action::Diff { file, json } => config_diff(card, file, *json),
    });
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
        Ok((text, differ)) => {
            print!("{text}");
            if differ {
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            }
        }
        // A file that does not parse or validate, or cannot be read or written, is a bad
        // argument.
        Err(e) if matches!(e.kind(), ErrorKind::ConfigFile | ErrorKind::Io) => bad(e.to_string()),
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// `mcctl config save FILE`: what the card holds, read back, as TOML into FILE (`-`: the text
/// itself).
pub fn config_save(card: &Card, file: &std::path::Path) -> Result<String> {
    if file.as_os_str() == "-" {
        return card.save_config();
    }
    card.save_config_file(file)?;
    Ok(format!("saved {}\n", file.display()))
}

/// `mcctl config load FILE`: the sections applied (those that differed from the card).
pub fn config_load(card: &Card, file: &std::path::Path, json: bool) -> Result<String> {
    let report = card.load_config_file(file)?;
    Ok(if json {
        json!({ "file": file.display().to_string(), "applied": report.applied }).to_string() + "\n"
    } else if report.applied.is_empty() {
        format!("{}: the card already holds it\n", file.display())
    } else {
        format!(
            "{}: applied {}\n",
            file.display(),
            report.applied.join(", ")
        )
    })
}

/// `mcctl config diff FILE`: the keys where FILE and the card differ, one a line (or a JSON
/// array), and whether there are any.
pub fn config_diff(card: &Card, file: &std::path::Path, json: bool) -> Result<(String, bool)> {
    let d = card.diff_config_file(file)?;
    let text = if json {
        let rows: Vec<_> = d
            .iter()
            .map(|x| json!({ "key": x.key, "file": x.file, "card": x.card }))
            .collect();
        serde_json::Value::Array(rows).to_string() + "\n"
    } else {
        d.iter()
            .map(|x| {
                let card = x.card.as_deref().unwrap_or("(none)");
                format!("{}: file {}, card {card}\n", x.key, x.file)
            })
            .collect()
    };
    Ok((text, !d.is_empty()))
}
