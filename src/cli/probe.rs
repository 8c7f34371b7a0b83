//! `mcctl probe`: a touch probe (MC_TouchProbe) latching the axis's position at an input edge
//! or at the encoder's index pulse. Arms, runs --move (or watches --for seconds), reports every
//! capture, and aborts the probe (MC_AbortTrigger).

use super::args::{finite, TravelArgs};
use super::machine::{halt_of, run_collecting, Powered, Travel};
use super::on_card;
use crate::{Card, EventKind, ProbeTrigger, Result};
use clap::{Args as ClapArgs, ValueEnum};
use serde_json::json;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl probe`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// The probe channel (0..4).
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
    /// The input (0..16); without it, the encoder's index pulse.
    #[arg(long)]
    pub input: Option<u32>,
    /// The edge that captures.
    #[arg(long, value_enum, default_value = "rising")]
    pub edge: EdgeArg,
    /// Keep capturing (else the first edge only).
    #[arg(long)]
    pub continuous: bool,
    /// Only edges with the axis in LO..=HI count.
    #[arg(
        long,
        num_args = 2,
        allow_negative_numbers = true,
        value_names = ["LO", "HI"],
        value_parser = finite("--window")
    )]
    pub window: Option<Vec<f64>>,
    /// The capture halts the axis's motion (the card stops it in the tick it sees the edge).
    #[arg(long)]
    pub halt: bool,
    #[command(flatten)]
    pub travel: TravelArgs,
    #[arg(long)]
    pub json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum EdgeArg {
    Rising,
    Falling,
    Both,
}

/// Arm, run and report.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let job = ProbeJob {
        axis: a.axis,
        channel: a.channel,
        trigger: ProbeTrigger {
            input: a.input,
            rising: !matches!(a.edge, EdgeArg::Falling),
            falling: !matches!(a.edge, EdgeArg::Rising),
            continuous: a.continuous,
            window: a.window.map(|w| (w[0], w[1])),
            halt: a.halt,
        },
        travel: a.travel.travel(a.axis),
        hold: a.travel.hold,
        enable: a.travel.enable,
    };
    on_card(uri, |c| probe(c, &job, a.json))
}

/// `mcctl probe`.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeJob {
    pub axis: usize,
    pub channel: usize,
    pub trigger: ProbeTrigger,
    pub travel: Option<Travel>,
    pub hold: Duration,
    /// Power the axis for the move if it is disabled (`--enable`; off again at the end).
    pub enable: bool,
}

/// Arm a touch probe (MC_TouchProbe), run the move, and report every capture the card posted;
/// the probe is aborted at the end (MC_AbortTrigger). With `enable`, the axis is powered only
/// for a move, once the probe is armed, and powered off again however it ends.
pub fn probe(card: &Card, job: &ProbeJob, json: bool) -> Result<String> {
    let tp = card.axis(job.axis)?.touch_probe(job.channel);
    tp.arm(&job.trigger)?;
    let mut captures = Vec::new();
    let axis = [(job.axis, halt_of(job.travel.as_ref()))];
    let outcome = Powered::on(card, job.enable && job.travel.is_some(), &axis).and_then(|power| {
        let r = run_collecting(card, job.travel.as_ref(), job.hold, |e| {
            if let Some(e) =
                e.filter(|e| e.kind == EventKind::Probe && e.axis as usize == job.channel)
            {
                captures.push(e.value);
            }
            Ok(())
        });
        let released = power.release();
        let r = r?;
        released.map(|()| r)
    });
    let st = tp.status();
    let aborted = tp.abort();
    let at = outcome?;
    let st = st?;
    aborted?;
    Ok(if json {
        json!({
            "axis": job.axis,
            "channel": job.channel,
            "captures": st.captures,
            "outside_window": st.outside,
            "positions": captures,
            "position": at,
        })
        .to_string()
    } else {
        let mut s = format!(
            "probe {} on axis {}: {} captures, {} edges outside the window\n",
            job.channel, job.axis, st.captures, st.outside
        );
        for (k, p) in captures.iter().enumerate() {
            s += &format!("  {:>4} {p}\n", k + 1);
        }
        s
    })
}
