//! `mcctl run FILE.ngc`: a G-code program (the SDK's [`motioncard_sdk::gcode`]) turned into
//! path segments, streamed into the card's path buffer as it frees room, and measured by the
//! runner's report ([`motioncard_sdk::report`]): path time, peak axis velocity, acceleration
//! and jerk against their limits, the largest deviation of the commanded and of the actual
//! path from the programmed one, the largest following error, exact stops.
//!
//! The machine: group 0 over axes 0, 1, 2 (X, Y, Z) with `scale` counts per mm. On the
//! in-process card (`sim`) the card is stepped by this program and every servo tick's
//! commanded position is measured, so the report is exact. On another card the positions are
//! sampled from the status as fast as the host reads it; the report's peaks then come from the
//! consecutive ticks it saw, and it says how many it saw.
//!
//! Memory stays bounded whatever the program's length or duration: the file is read a line
//! at a time (twice: checked whole first, then streamed as the card frees room), at most the
//! card's path buffer of items is in hand, and the report is computed as the run goes
//! (the runner's report: running peaks, stops and deviation, over a sliding window of the
//! programmed path).

use motioncard_sdk::gcode::{
    run::{Hooks, RunSettings, RunState, Runner, SpindleSettings},
    Options, Program, ToolTable,
};
use motioncard_sdk::report::PathReport;
/// Room in the card's path buffer (segments) a stepped run waits for before it sends more.
/// Each send is a stream of its own, and the chord fitter fits within a stream: sent as the
/// room came, a segment or two a tick, a program's chords after a stretch the fitter cannot
/// shorten went as they were, the buffer staying full of single lines. An eighth of the
/// buffer free leaves far more queued than the look-ahead needs.
const SEND_ROOM: usize = 512;
use crate::{Card, Error, Group, GroupSettings, GroupState, PathSettings, Result};
use std::path::Path;
use std::time::Duration;

/// The machine and how to run the program.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Corner tolerance, mm (0: exact stop at every corner).
    pub tolerance: f64,
    /// The largest feed, mm/s (also the rapid feed).
    pub feed_limit: f64,
    /// Per axis (X, Y, Z): velocity, acceleration and jerk limits, mm/s, mm/s², mm/s³.
    pub vmax: [f64; 3],
    /// Acceleration limits.
    pub amax: [f64; 3],
    /// Jerk limits.
    pub jmax: [f64; 3],
    /// Counts per mm.
    pub scale: f64,
    /// Show a progress bar (on stderr).
    pub progress: bool,
    /// Runs of short lines that sample a smooth curve are sent as that curve
    /// ([`PathSettings::chord_fit`]).
    pub chord_fit: bool,
    /// The tool table (G43, G41/G42, M6).
    pub tools: ToolTable,
    /// Where `o<name> call` looks for `name.ngc` (then the program's directory).
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// The input of the touch probe (G38).
    pub probe_input: Option<u32>,
    /// The spindle on a card axis, and its encoder's counts per revolution (the axis's scale
    /// is set to it and the axis enabled).
    pub spindle: Option<(SpindleSettings, f64)>,
    /// The card output of mist coolant (M7).
    pub mist_output: Option<u32>,
    /// The card output of flood coolant (M8).
    pub flood_output: Option<u32>,
}

impl Default for RunOptions {
    /// 0.01 mm tolerance, 100 mm/s, 100 mm/s, 1000 mm/s², 1e5 mm/s³ per axis, 1 µm counts;
    /// no spindle or coolant on the card.
    fn default() -> Self {
        Self {
            tolerance: 0.01,
            feed_limit: 100.0,
            vmax: [100.0; 3],
            amax: [1_000.0; 3],
            jmax: [100_000.0; 3],
            scale: 1_000.0,
            progress: false,
            chord_fit: true,
            tools: ToolTable::default(),
            subroutine_path: Vec::new(),
            probe_input: None,
            spindle: None,
            mist_output: None,
            flood_output: None,
        }
    }
}

fn group(card: &Card, opts: &RunOptions) -> Result<Group> {
    for a in 0..3 {
        let axis = card.axis(a)?;
        axis.set_scale(opts.scale)?;
        if axis.status()?.state == crate::AxisState::Disabled {
            axis.enable()?;
        }
    }
    if let Some((sp, scale)) = &opts.spindle {
        let axis = card.axis(sp.axis)?;
        axis.set_scale(*scale)?;
        if axis.status()?.state == crate::AxisState::Disabled {
            axis.enable()?;
        }
    }
    let g = card.group(0)?;
    if g.status()?.0 != GroupState::Disabled {
        g.disable()?;
    }
    g.configure(&GroupSettings {
        tolerance: 1e-3,
        ..GroupSettings::new(&[0, 1, 2])
    })?;
    g.enable()?;
    g.configure_path(&PathSettings {
        lookahead: 256,
        low_water: 0,
        accel: 0.0,
        jerk: 0.0,
        vmax: opts.vmax.to_vec(),
        amax: opts.amax.to_vec(),
        jmax: opts.jmax.to_vec(),
        plan_period: 0.0,
        chord_fit: opts.chord_fit,
    })?;
    Ok(g)
}

fn position(card: &Card) -> Result<[f64; 3]> {
    let s = card.statuses(&[0, 1, 2])?;
    Ok([
        s[0].command_position,
        s[1].command_position,
        s[2].command_position,
    ])
}

/// The program in `file`, starting at `start` (mm).
fn program(
    file: &Path,
    start: [f64; 3],
    opts: &RunOptions,
) -> Result<Program<motioncard_sdk::gcode::FileSource>> {
    let options = Options {
        start: [start[0], start[1], start[2], 0.0, 0.0, 0.0],
        tools: opts.tools.clone(),
        subroutine_path: opts.subroutine_path.clone(),
        ..Options::default()
    };
    Ok(Program::open(file, &options)?)
}

/// What the first reading of the program found: its operations and its motions.
#[derive(Debug, Clone, Copy, Default)]
struct Survey {
    ops: u64,
    motions: u64,
    dropped_zero_length: usize,
}

/// The program read once without a card: every line checked, operations counted (probes
/// taken as tripping at their programmed ends).
fn survey(file: &Path, start: [f64; 3], opts: &RunOptions) -> Result<Survey> {
    let mut s = Survey::default();
    for op in program(file, start, opts)? {
        let op = op?;
        s.ops += 1;
        if op.kind.is_null_motion() {
            s.dropped_zero_length += 1;
        } else if op.kind.ends().is_some() {
            s.motions += 1;
        }
    }
    Ok(s)
}

/// The run's hooks: unattended, a pause (M0, M1, M60) is passed.
struct Unattended;

impl Hooks for Unattended {
    fn pause(&mut self, _kind: motioncard_sdk::gcode::PauseKind) -> bool {
        false
    }
}

/// The report as one JSON object.
fn report_json(r: &PathReport) -> serde_json::Value {
    serde_json::json!({
        "path_time": r.path_time,
        "segments": r.segments,
        "peak_vel_ratio": r.peak_vel_ratio,
        "peak_accel_ratio": r.peak_accel_ratio,
        "peak_jerk_ratio": r.peak_jerk_ratio,
        "max_deviation": r.max_deviation,
        "max_contour_error": r.max_contour_error,
        "max_following_error": r.max_following_error,
        "exact_stops": r.exact_stops,
        "ticks": r.ticks,
        "ticks_seen": r.ticks_seen,
    })
}

/// Run the program in `file` on `card`: the report as text or one JSON object.
///
/// The file is read twice, a line at a time: once to check all of it (nothing moves when a
/// line is wrong), then by the SDK's runner as the card's path buffer frees room. The report
/// is computed as the run goes ([`Report`](motioncard_sdk::report::Report)): memory does not
/// grow with the program's length or duration.
pub fn run(card: &Card, file: &Path, opts: &RunOptions, json: bool) -> Result<String> {
    let t0 = std::time::Instant::now();
    // (wall-clock time from here to the first tick that moves: the program checked whole,
    // the group set up, the first batch sent)
    let mut first_motion: Option<Duration> = None;
    let g = group(card, opts)?;
    let start = position(card)?;
    let survey = survey(file, start, opts)?;
    if survey.motions == 0 {
        // Nothing to measure: refused before anything runs (a dwell would run in full).
        return Err(Error::Unsupported(format!(
            "G-code {}: no motion to run and measure",
            file.display()
        )));
    }
    let settings = RunSettings {
        rapid_feed: opts.feed_limit,
        max_feed: opts.feed_limit,
        tolerance: opts.tolerance,
        spline_tolerance: opts.tolerance.max(1e-3),
        batch: SEND_ROOM,
        probe_input: opts.probe_input,
        spindle: opts.spindle.as_ref().map(|s| s.0.clone()),
        mist_output: opts.mist_output,
        flood_output: opts.flood_output,
        ..RunSettings::default()
    };
    let mut runner = Runner::new(&g, program(file, start, opts)?, settings, Unattended)?;
    let bar = indicatif::ProgressBar::new(survey.ops);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} operations, {msg}")
    {
        bar.set_style(style);
    }
    if !opts.progress {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let sim = card.sim();
    let mut ticks = 0u64;
    loop {
        let before = card.tick()?;
        let state = runner.poll()?;
        if sim.is_some() && card.tick()? != before {
            // (the stepped card runs a batch between two ticks; one that needed ticks would
            // leave them out of the report)
            return Err(Error::Unsupported(format!(
                "the card ran {} ticks while a batch was sent: the report would miss them",
                card.tick()? - before
            )));
        }
        bar.set_position(runner.operations());
        bar.set_message(format!("line {}", runner.running_line()?));
        if state == RunState::Done {
            break;
        }
        match &sim {
            Some(sim) => sim.step(1),
            None => {
                // A signal to mcctl: the close that follows halts the path (cli::interrupt).
                crate::cli::interrupt::check()?;
                std::thread::sleep(Duration::from_micros(20));
            }
        }
        // (every tick of the stepped card; as many as the host reads of another)
        runner.sample()?;
        ticks += 1;
        if first_motion.is_none() && position(card)? != start {
            first_motion = Some(t0.elapsed());
        }
        if ticks > 1_000_000_000 {
            return Err(Error::Unsupported("the program did not end".into()));
        }
    }
    bar.finish_and_clear();
    let r = runner
        .report()
        .ok_or_else(|| Error::Unsupported("the run was not measured".into()))?
        .map_err(|e| Error::Unsupported(format!("report: {e}")))?;
    let end = position(card)?;
    if json {
        let mut j = report_json(&r);
        j["dropped_zero_length"] = survey.dropped_zero_length.into();
        j["operations"] = runner.operations().into();
        j["first_motion_ms"] = first_motion
            .map_or(f64::NAN, |d| d.as_secs_f64() * 1e3)
            .into();
        j["end"] = serde_json::json!({"x": end[0], "y": end[1], "z": end[2]});
        return Ok(j.to_string());
    }
    Ok(format!(
        "path time {:.4} s, {} segments, peak velocity {:.4}, acceleration {:.4}, jerk {:.4} \
         of the limits, max deviation {:.6} mm (actual path {:.6} mm, following error {:.6} \
         mm), {} exact stops, {} operations, end at ({:.4}, {:.4}, {:.4})",
        r.path_time,
        r.segments,
        r.peak_vel_ratio,
        r.peak_accel_ratio,
        r.peak_jerk_ratio,
        r.max_deviation,
        r.max_contour_error,
        r.max_following_error,
        r.exact_stops,
        runner.operations(),
        end[0],
        end[1],
        end[2]
    ))
}
