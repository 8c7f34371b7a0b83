//! `mcctl scope`: a one-shot capture of the card's scope, optionally of a move started while
//! it is armed, to CSV and to an SVG plot, with a summary per channel.

use super::args::{positive_duration, TravelArgs};
use super::machine::Travel;
use super::{enable_if_needed, on_card};
use crate::{Card, Result, SCOPE_DIVIDER_MAX, SCOPE_PRETRIGGER_MAX};
use crate::{Edge, ScopeMode, ScopeSettings, ScopeTrigger, Signal, SignalOwner, Source};
use clap::Args as ClapArgs;
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl scope`.
#[derive(ClapArgs)]
pub struct Args {
    /// A channel `SIGNAL[:INDEX]` (repeat for more, up to 16): cmd_pos, cmd_vel, cmd_acc,
    /// act_pos, act_vel, ferr, dac, u_request, encoder, servo_p, servo_i, servo_d, servo_ff,
    /// gantry_skew, comp_pos, filter_in, filter_out, servo_friction, freq_inject, freq_hz
    /// (of an axis), path_speed, path_acc, path_pos (of a group), inputs, outputs,
    /// inputs_raw. Default: cmd_pos, act_pos, ferr and dac of --axis.
    #[arg(long = "channel", value_parser = parse_source)]
    pub channels: Vec<Source>,
    /// Samples from the trigger on.
    #[arg(long, default_value_t = 2000, value_parser = clap::value_parser!(u32).range(1..))]
    pub samples: u32,
    /// Samples kept from before the trigger.
    #[arg(
        long,
        default_value_t = 0,
        value_parser = clap::value_parser!(u32).range(..=SCOPE_PRETRIGGER_MAX as i64)
    )]
    pub pre: u32,
    /// A sample every N servo ticks.
    #[arg(
        long,
        default_value_t = 1,
        value_parser = clap::value_parser!(u32).range(1..=SCOPE_DIVIDER_MAX as i64)
    )]
    pub divider: u32,
    /// immediate, command, fault, `level:CHANNEL:LEVEL[:rising|falling|either]` (CHANNEL:
    /// its place in the --channel list, from 0) or `input:N[:EDGE]`.
    #[arg(
        long,
        default_value = "immediate",
        allow_hyphen_values = true,
        value_parser = parse_trigger
    )]
    pub trigger: ScopeTrigger,
    /// The axis of the default channels and of --move.
    #[arg(long, default_value_t = 0)]
    pub axis: usize,
    /// Write the samples here (tick, seconds from the trigger, one column a channel).
    #[arg(long)]
    pub csv: Option<std::path::PathBuf>,
    /// Plot the channels against time here.
    #[arg(long)]
    pub svg: Option<std::path::PathBuf>,
    /// Seconds the whole capture may take.
    #[arg(
        long,
        default_value = "10",
        allow_negative_numbers = true,
        value_parser = positive_duration("--timeout")
    )]
    pub timeout: Duration,
    #[command(flatten)]
    pub travel: TravelArgs,
    #[arg(long)]
    pub json: bool,
}

/// Capture (the default channels of --axis without --channel) and report.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let mut channels = a.channels;
    if channels.is_empty() {
        channels = [Signal::CmdPos, Signal::ActPos, Signal::Ferr, Signal::Dac]
            .map(|s| Source::axis(s, a.axis))
            .to_vec();
    }
    let job = ScopeJob {
        channels,
        divider: a.divider,
        trigger: a.trigger,
        pre_trigger: a.pre,
        samples: a.samples,
        travel: a.travel.travel(a.axis),
        csv: a.csv,
        svg: a.svg,
        timeout: a.timeout,
    };
    let (axis, enable) = (a.axis, a.travel.enable);
    on_card(uri, |c| {
        if enable {
            enable_if_needed(c, axis)?;
        }
        scope(c, &job, a.json)
    })
}

/// A signal's name on the command line (the `MC_SIG_*` name in lower case).
fn signal_name(s: Signal) -> String {
    let mut out = String::new();
    for (i, c) in format!("{s:?}").chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

/// Every signal's name, for messages.
fn signal_names() -> String {
    Signal::ALL
        .iter()
        .map(|s| signal_name(*s))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A channel `SIGNAL[:INDEX]` (`cmd_pos:0`, `path_speed:1`, `inputs`).
pub fn parse_source(s: &str) -> std::result::Result<Source, String> {
    let (name, index) = s.split_once(':').unwrap_or((s, "0"));
    let signal = Signal::ALL
        .iter()
        .copied()
        .find(|sig| signal_name(*sig) == name)
        .ok_or_else(|| format!("`{name}` is not a signal: {}", signal_names()))?;
    let index = index
        .parse::<u16>()
        .map_err(|_| format!("`{s}`: the index after `:` is an axis or group number"))?;
    Ok(Source { signal, index })
}

fn parse_edge(s: Option<&str>) -> std::result::Result<Edge, String> {
    match s {
        None | Some("rising") => Ok(Edge::Rising),
        Some("falling") => Ok(Edge::Falling),
        Some("either") => Ok(Edge::Either),
        Some(e) => Err(format!("`{e}` is not an edge: rising, falling or either")),
    }
}

/// A trigger: `immediate`, `command`, `fault`, `level:CHANNEL:LEVEL[:EDGE]` (the channel's
/// number in --channel order) or `input:N[:EDGE]`.
pub fn parse_trigger(s: &str) -> std::result::Result<ScopeTrigger, String> {
    let f: Vec<&str> = s.split(':').collect();
    let num = |k: usize, what: &str| -> std::result::Result<usize, String> {
        f.get(k)
            .and_then(|x| x.parse().ok())
            .ok_or_else(|| format!("`{s}`: {what} is missing or not a whole number"))
    };
    match f[0] {
        "immediate" if f.len() == 1 => Ok(ScopeTrigger::Immediate),
        "command" if f.len() == 1 => Ok(ScopeTrigger::Command),
        "fault" if f.len() == 1 => Ok(ScopeTrigger::Fault),
        "level" if (3..=4).contains(&f.len()) => Ok(ScopeTrigger::Level {
            channel: num(1, "the channel")?,
            level: f[2]
                .parse()
                .map_err(|_| format!("`{s}`: the level is not a number"))?,
            edge: parse_edge(f.get(3).copied())?,
        }),
        "input" if (2..=3).contains(&f.len()) => Ok(ScopeTrigger::Input {
            input: num(1, "the input")?,
            edge: parse_edge(f.get(2).copied())?,
        }),
        _ => Err(format!(
            "`{s}` is not a trigger: immediate, command, fault, level:CHANNEL:LEVEL[:EDGE] or \
             input:N[:EDGE]"
        )),
    }
}

/// `mcctl scope`.
#[derive(Debug, Clone, PartialEq)]
pub struct ScopeJob {
    pub channels: Vec<Source>,
    pub divider: u32,
    pub trigger: ScopeTrigger,
    pub pre_trigger: u32,
    pub samples: u32,
    /// A move started while the scope is armed.
    pub travel: Option<Travel>,
    pub csv: Option<PathBuf>,
    pub svg: Option<PathBuf>,
    pub timeout: Duration,
}

fn label(s: &Source) -> String {
    match s.signal.owner() {
        SignalOwner::Card => signal_name(s.signal),
        _ => format!("{}:{}", signal_name(s.signal), s.index),
    }
}

/// Capture, write the files asked for, and summarise: samples, trigger, lost, and each
/// channel's first, last, least and greatest value.
pub fn scope(card: &Card, job: &ScopeJob, json: bool) -> Result<String> {
    let settings = ScopeSettings {
        channels: job.channels.clone(),
        divider: job.divider,
        trigger: job.trigger,
        pre_trigger: job.pre_trigger,
        mode: ScopeMode::OneShot,
        post_trigger: job.samples,
    };
    let travel = job.travel;
    let cap = card.scope().capture(&settings, job.timeout, |sc| {
        if let Some(t) = travel {
            card.axis(t.axis)?.move_absolute(t.target, &t.limits)?;
        }
        if job.trigger == ScopeTrigger::Command {
            sc.trigger()?;
        }
        Ok(())
    })?;
    let rate = card.info().servo_rate_hz as f64;
    let names: Vec<String> = job.channels.iter().map(label).collect();
    let t = |tick: u64| (tick as f64 - cap.trigger_tick as f64) / rate;
    let io = |e: std::io::Error, p: &PathBuf| crate::Error::Io {
        context: format!("mcctl scope: {}", p.display()),
        source: e,
    };
    if let Some(p) = &job.csv {
        let mut text = format!("tick,time_s,{}\n", names.join(","));
        for s in &cap.samples {
            let _ = write!(text, "{},{:?}", s.tick, t(s.tick));
            for v in &s.value[..cap.channels] {
                let _ = write!(text, ",{v:?}");
            }
            text.push('\n');
        }
        std::fs::write(p, text).map_err(|e| io(e, p))?;
    }
    if let Some(p) = &job.svg {
        let series: Vec<crate::plot::Series> = names
            .iter()
            .enumerate()
            .map(|(k, name)| crate::plot::Series {
                name,
                points: cap
                    .samples
                    .iter()
                    .map(|s| (t(s.tick), s.value[k]))
                    .collect(),
            })
            .collect();
        crate::plot::lines(
            p,
            "mcctl scope",
            "s from the trigger",
            "value",
            &series,
            false,
        )
        .map_err(|e| io(e, p))?;
    }
    let stats: Vec<(f64, f64, f64, f64)> = (0..cap.channels)
        .map(|k| {
            let v = cap.samples.iter().map(|s| s.value[k]);
            let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
            let first = cap.samples.first().map_or(f64::NAN, |s| s.value[k]);
            let last = cap.samples.last().map_or(f64::NAN, |s| s.value[k]);
            (first, last, lo, hi)
        })
        .collect();
    let pre = cap
        .samples
        .iter()
        .filter(|s| s.tick < cap.trigger_tick)
        .count();
    Ok(if json {
        let ch: Vec<_> = names
            .iter()
            .zip(&stats)
            .map(|(n, (first, last, lo, hi))| {
                json!({ "name": n, "first": first, "last": last, "min": lo, "max": hi })
            })
            .collect();
        json!({
            "samples": cap.samples.len(),
            "pre_trigger": pre,
            "trigger_tick": cap.trigger_tick,
            "first_tick": cap.samples.first().map(|s| s.tick),
            "last_tick": cap.samples.last().map(|s| s.tick),
            "lost": cap.lost,
            "channels": ch,
        })
        .to_string()
    } else {
        let mut out = format!(
            "captured {} samples x {} channels ({pre} before the trigger at tick {}), {} lost\n",
            cap.samples.len(),
            cap.channels,
            cap.trigger_tick,
            cap.lost
        );
        let _ = writeln!(
            out,
            "{:<16} {:>16} {:>16} {:>16} {:>16}",
            "channel", "first", "last", "min", "max"
        );
        for (n, (first, last, lo, hi)) in names.iter().zip(&stats) {
            let _ = writeln!(
                out,
                "{n:<16} {first:>16.6} {last:>16.6} {lo:>16.6} {hi:>16.6}"
            );
        }
        out
    })
}
