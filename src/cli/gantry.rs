//! `mcctl gantry form|home|status|dissolve`: gantry axes (layout 1.10) over the SDK's
//! [`Card::gantry_at`], [`Gantry::home`], [`Card::gantries`] and [`Gantry::dissolve`]. Lengths
//! (the skew limit, the offsets, every skew) are in the master's user units. A gantry stays
//! formed on the card after mcctl ends (on `--card sim` the card ends with mcctl).
//!
//! [`Gantry::home`]: crate::Gantry::home
//! [`Gantry::dissolve`]: crate::Gantry::dissolve

use super::args::{finite, non_negative, positive};
use super::{enable_if_needed, hold_for, on_card};
use crate::{Card, GantryConfig, GantryPhase, GantryStatus, Result};
use clap::Subcommand;
use serde_json::json;
use std::process::ExitCode;
use std::time::Duration;

/// How long `mcctl gantry home` waits for the bridge to be squared.
const HOME_WAIT: Duration = Duration::from_secs(120);

/// `mcctl gantry`'s actions.
#[derive(Subcommand)]
pub enum Action {
    /// Form a gantry: MASTER and its --slaves (each with the master's scale), every one at
    /// rest, all powered or all disabled; each slave is coupled where it stands. Prints the
    /// gantry's status.
    Form {
        master: usize,
        /// The slave axes (1 to 4), comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        slaves: Vec<usize>,
        /// The skew beyond which every axis of the gantry stops (master's user units).
        #[arg(long, value_parser = positive("--skew-limit"))]
        skew_limit: f64,
        /// Proportional gain of the yaw loop, 1/s².
        #[arg(long, default_value_t = GantryConfig::default().kp, value_parser = non_negative("--kp"))]
        kp: f64,
        /// Integral gain of the yaw loop, 1/s³.
        #[arg(long, default_value_t = 0.0, value_parser = non_negative("--ki"))]
        ki: f64,
        /// Each slave's square offset (slave − master when square), comma-separated, one per
        /// slave; left out: 0 each.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_parser = finite("--offsets"))]
        offsets: Vec<f64>,
        /// The gantry's number (else the first free one).
        #[arg(long)]
        index: Option<usize>,
        /// Power the axes on first (the master's MC_Power powers the slaves).
        #[arg(long)]
        enable: bool,
        #[arg(long)]
        json: bool,
    },
    /// Home gantry INDEX: each side runs its own homing method, then the slaves square the
    /// bridge to their offsets; waited for. Prints the skew once square.
    Home {
        index: usize,
        #[arg(long)]
        json: bool,
    },
    /// The formed gantries (or gantry INDEX): phase, master, slaves with their offsets, skew
    /// and largest skew, gains, skew limit, squared.
    Status {
        index: Option<usize>,
        #[arg(long)]
        json: bool,
    },
    /// Dissolve gantry INDEX (its master at rest): the slaves hold where they are, each its
    /// own axis again.
    Dissolve {
        index: usize,
        #[arg(long)]
        json: bool,
    },
}

/// Run one action on the card.
pub fn run(uri: &str, action: Action) -> ExitCode {
    on_card(uri, |c| match action {
        Action::Form {
            master,
            slaves,
            skew_limit,
            kp,
            ki,
            offsets,
            index,
            enable,
            json,
        } => {
            let cfg = GantryConfig {
                kp,
                ki,
                skew_limit,
                offsets,
            };
            if enable {
                for &a in std::iter::once(&master).chain(&slaves) {
                    enable_if_needed(c, a)?;
                }
            }
            form(c, index, master, &slaves, &cfg, json)
        }
        Action::Home { index, json } => home(c, index, json),
        Action::Status { index, json } => status(c, index, json),
        Action::Dissolve { index, json } => dissolve(c, index, json),
    })
}

/// `mcctl gantry form`: form it (gantry `index`, else the first free one), print its status.
pub fn form(
    card: &Card,
    index: Option<usize>,
    master: usize,
    slaves: &[usize],
    cfg: &GantryConfig,
    json: bool,
) -> Result<String> {
    let g = match index {
        Some(i) => card.gantry_at(i, master, slaves, cfg)?,
        None => card.gantry(master, slaves, cfg)?,
    };
    // A stepped card couples the slaves on its next tick.
    if card.sim().is_some() {
        hold_for(card, Duration::from_millis(1));
    }
    let st = g.status()?;
    Ok(if json {
        status_json(&st).to_string()
    } else {
        format!("gantry {}: formed\n{}", st.index, status_text(&st))
    })
}

/// `mcctl gantry home`: home it and wait until the bridge is square.
pub fn home(card: &Card, index: usize, json: bool) -> Result<String> {
    let g = card.gantry_handle(index)?;
    let homing = g.home()?;
    let skew = super::wait_stepping(card, HOME_WAIT, |t| homing.wait(t))?;
    let st = g.status()?;
    Ok(if json {
        json!({ "gantry": index, "squared": st.squared, "skew": skew, "status": status_json(&st) })
            .to_string()
    } else {
        format!("gantry {index}: homed and squared, skew {skew}\n")
    })
}

/// `mcctl gantry status`: every formed gantry, or gantry `index` (refused if not formed).
pub fn status(card: &Card, index: Option<usize>, json: bool) -> Result<String> {
    let all = match index {
        Some(i) => vec![card.gantry_handle(i)?.status()?],
        None => card.gantries(),
    };
    Ok(if json {
        json!({ "gantries": all.iter().map(status_json).collect::<Vec<_>>() }).to_string()
    } else if all.is_empty() {
        "no gantry formed\n".to_string()
    } else {
        all.iter().map(status_text).collect()
    })
}

/// `mcctl gantry dissolve`.
pub fn dissolve(card: &Card, index: usize, json: bool) -> Result<String> {
    card.gantry_handle(index)?.dissolve()?;
    Ok(if json {
        json!({ "gantry": index, "dissolved": true }).to_string()
    } else {
        format!("gantry {index}: dissolved\n")
    })
}

fn phase_name(p: GantryPhase) -> &'static str {
    match p {
        GantryPhase::Coupled => "coupled",
        GantryPhase::Homing => "homing",
        GantryPhase::Squaring => "squaring",
    }
}

fn status_json(st: &GantryStatus) -> serde_json::Value {
    json!({
        "index": st.index,
        "phase": phase_name(st.phase),
        "master": st.master,
        "slaves": st.slaves.iter().map(|s| json!({
            "axis": s.axis,
            "offset": s.offset,
            "hold": s.hold,
            "skew": s.skew,
            "correction": s.correction,
            "max_skew": s.max_skew,
        })).collect::<Vec<_>>(),
        "kp": st.kp,
        "ki": st.ki,
        "skew_limit": st.skew_limit,
        "squared": st.squared,
    })
}

fn status_text(st: &GantryStatus) -> String {
    let mut out = format!(
        "gantry {}: {}, master axis {}, kp {} ki {}, skew limit {}, {}\n",
        st.index,
        phase_name(st.phase),
        st.master,
        st.kp,
        st.ki,
        st.skew_limit,
        if st.squared { "squared" } else { "not squared" }
    );
    for s in &st.slaves {
        out += &format!(
            "  slave axis {}: offset {} (in force {}), skew {}, largest {}\n",
            s.axis, s.offset, s.hold, s.skew, s.max_skew
        );
    }
    out
}
