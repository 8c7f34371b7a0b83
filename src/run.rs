//! `mcctl run FILE.ngc`: a G-code program (the RS274/NGC subset of [`crate::gcode`]) turned
//! into path segments, streamed into the card's path buffer as it frees room, and measured
//! ([`crate::path_report`]): path time, peak axis velocity, acceleration and jerk against their
//! limits, the largest deviation from the programmed path, exact stops.
//!
//! The machine: group 0 over axes 0, 1, 2 (X, Y, Z) with `scale` counts per mm. On the
//! in-process card (`sim`) the card is stepped by this program and every servo tick's
//! commanded position is measured, so the report is exact. On another card the positions are
//! sampled from the status as fast as the host reads it; the report then takes the ticks it
//! saw as consecutive (and says how many it saw).
//!
//! Memory stays bounded whatever the program's length or duration: the file is read a line
//! at a time (twice: checked whole first, then streamed as the card frees room), at most the
//! card's path buffer of items is in hand, and the report is computed as the run goes
//! ([`Report`]: running peaks, stops and deviation, over a sliding window of the programmed
//! path).

use crate::gcode::{Block, Blocks, GcodeError, Program};
use crate::path_report::{AxisLimits, Report, ReportError};
use crate::proto::raw::MC_PATHST_RUNNING;

/// Program lines a stepped run reads ahead of the line the card runs (more than the SDK's
/// chord fitter holds before it sends a curve: a straight run of 16 chunks of 1024 points).
const AHEAD_LINES: usize = 32 * 1024;
/// Room in the card's path buffer (segments) a stepped run waits for before it sends more.
/// Each send is a stream of its own, and the chord fitter fits within a stream: sent as the
/// room came, a segment or two a tick, a program's chords after a stretch the fitter cannot
/// shorten went as they were, the buffer staying full of single lines. An eighth of the
/// buffer free leaves far more queued than the look-ahead needs.
const SEND_ROOM: usize = 512;
use crate::{
    ArcSpec, Card, Error, Group, GroupSettings, GroupState, PathItem, PathSettings, Result,
    Segment, Transition,
};
use std::fs::File;
use std::io::BufReader;
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
}

impl Default for RunOptions {
    /// 0.01 mm tolerance, 100 mm/s, 100 mm/s, 1000 mm/s², 1e5 mm/s³ per axis, 1 µm counts.
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
        }
    }
}

/// A block's path item: a segment per motion block and dwell (id = its source line), an
/// output action for an output (before the segment it belongs to).
pub fn item(b: &Block, opts: &RunOptions) -> PathItem {
    let tol = Transition::MaxDeviation(opts.tolerance);
    let feed = |f: f64| f.min(opts.feed_limit);
    match b {
        Block::Line {
            line, end, feed: f, ..
        } => Segment::line(*line as u32, end, feed(*f), 0.0)
            .transition(tol)
            .into(),
        Block::Arc {
            line,
            end,
            centre,
            plane,
            ccw,
            feed: f,
            ..
        } => {
            let (u, v, w) = plane.axes();
            let arc = ArcSpec::Centre {
                end: [end[u], end[v]],
                centre: [centre[u], centre[v]],
                ccw: *ccw,
            };
            Segment::arc(*line as u32, arc, (*plane).into(), &[end[w]], feed(*f), 0.0)
                .transition(tol)
                .into()
        }
        Block::Dwell { line, seconds } => Segment::dwell(*line as u32, *seconds).into(),
        Block::Output { bit, on, .. } => PathItem::Output {
            output: *bit,
            on: *on,
            at: crate::OutputAt::Start,
        },
    }
}

/// The program's items ([`item`] of each block), the last segment marked last.
pub fn items(p: &Program, opts: &RunOptions) -> Vec<PathItem> {
    let mut out: Vec<PathItem> = p.blocks.iter().map(|b| item(b, opts)).collect();
    if let Some(PathItem::Segment(s)) = out
        .iter_mut()
        .rev()
        .find(|i| matches!(i, PathItem::Segment(_)))
    {
        s.last = true;
    }
    out
}

fn group(card: &Card, opts: &RunOptions) -> Result<Group> {
    for a in 0..3 {
        let axis = card.axis(a)?;
        axis.set_scale(opts.scale)?;
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

/// The G-code error as mcctl reports it.
fn gcode_error(e: GcodeError) -> Error {
    Error::Unsupported(format!("G-code {e}"))
}

/// The program file's blocks, read a line at a time.
fn blocks(file: &Path, start: [f64; 3]) -> Result<Blocks<BufReader<File>>> {
    let f = File::open(file).map_err(|source| Error::Io {
        context: file.display().to_string(),
        source,
    })?;
    Ok(Blocks::new(BufReader::new(f), start))
}

/// What the first reading of the program found: its items, its segments (motion blocks and
/// dwells) and the moves dropped for their zero length.
#[derive(Debug, Clone, Copy, Default)]
struct Survey {
    items: u64,
    segments: u64,
    motions: u64,
    dropped_zero_length: usize,
}

fn survey(file: &Path, start: [f64; 3]) -> Result<Survey> {
    let mut s = Survey::default();
    let mut bs = blocks(file, start)?;
    for b in &mut bs {
        let b = b.map_err(gcode_error)?;
        s.items += 1;
        s.segments += u64::from(!matches!(b, Block::Output { .. }));
        s.motions += u64::from(b.is_motion());
    }
    s.dropped_zero_length = bs.parser().dropped_zero_length();
    Ok(s)
}

/// The second reading: each block with its item, the last segment marked last. A program
/// that differs from the survey (the file changed meanwhile) is an error.
struct Items {
    blocks: Blocks<BufReader<File>>,
    opts: RunOptions,
    segments_left: u64,
    file: String,
}

impl Iterator for Items {
    type Item = Result<(Block, PathItem)>;

    fn next(&mut self) -> Option<Self::Item> {
        let changed =
            || Error::Unsupported(format!("{}: the program changed while it ran", self.file));
        let b = match self.blocks.next() {
            None if self.segments_left > 0 => return Some(Err(changed())),
            None => return None,
            Some(Err(e)) => return Some(Err(gcode_error(e))),
            Some(Ok(b)) => b,
        };
        let mut item = item(&b, &self.opts);
        if let PathItem::Segment(s) = &mut item {
            if self.segments_left == 0 {
                return Some(Err(changed()));
            }
            self.segments_left -= 1;
            s.last = self.segments_left == 0;
        }
        Some(Ok((b, item)))
    }
}

/// Run the program in `file` on `card`: the report as text or one JSON object.
///
/// The file is read twice, a line at a time: once to check all of it (nothing moves when a
/// line is wrong) and count its items, then as the card's path buffer frees room. The
/// report is computed as the run goes ([`Report`]): memory does not grow with the program's
/// length or duration.
pub fn run(card: &Card, file: &Path, opts: &RunOptions, json: bool) -> Result<String> {
    let g = group(card, opts)?;
    let start = position(card)?;
    let survey = survey(file, start)?;
    if survey.motions == 0 {
        // Nothing to measure: refused before anything runs (a dwell would run in full).
        return Err(Error::Unsupported(format!(
            "G-code {}: no motion block (G0-G3) to run and measure",
            file.display()
        )));
    }
    let mut items = Items {
        blocks: blocks(file, start)?,
        opts: opts.clone(),
        segments_left: survey.segments,
        file: file.display().to_string(),
    };
    let bar = indicatif::ProgressBar::new(survey.items);
    if !opts.progress {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    let limits = [0, 1, 2].map(|a| AxisLimits {
        vmax: opts.vmax[a],
        amax: opts.amax[a],
        jmax: opts.jmax[a],
    });
    // Positions are f64 sums on the card: a tick slower than a thousandth of a count per tick
    // is at rest.
    let rest = 1e-3 / opts.scale / ts;
    let report_error = |e: ReportError| Error::Unsupported(format!("report: {e:?}"));
    let mut report = Report::new(ts, &limits, rest).map_err(report_error)?;
    let mut seen_ticks = 1u64;
    // (`Card::sim` is a stepped in-process card: mcctl opens `sim` stepped for a run.)
    if let Some(sim) = card.sim() {
        // Stepped: push what fits, step a tick, record, until the path is done.
        let mut next = items.next().transpose()?;
        let mut chunk = Vec::new();
        let mut sent = 0u64;
        let mut started = false;
        // the source line of the segment the card runs
        let mut running = 0usize;
        loop {
            let room = g.path_free()?;
            if room >= SEND_ROOM && next.is_some() {
                let mut segs = 0;
                while segs < room {
                    // (blocks reach the report at most AHEAD_LINES ahead of the card, so
                    // that the window it holds stays bounded when chords are fitted: a
                    // fitted curve of a thousand lines is one of the card's segments)
                    if next
                        .as_ref()
                        .is_some_and(|(b, _)| b.line() > running + AHEAD_LINES)
                    {
                        break;
                    }
                    let Some((b, item)) = next.take() else {
                        break;
                    };
                    segs += matches!(item, PathItem::Segment(_)) as usize;
                    report.add_block(&b);
                    chunk.push(item);
                    next = items.next().transpose()?;
                }
                sent += chunk.len() as u64;
                let before = card.tick()?;
                g.stream_path(chunk.drain(..), |_| {})
                    .map_err(|e| e.error)?;
                let stepped = card.tick()? - before;
                if stepped > 0 {
                    // (the stepped card runs a stream between two ticks; one that needed ticks
                    // would leave them out of the report)
                    return Err(Error::Unsupported(format!(
                        "the card ran {stepped} ticks while a batch was sent: the report \
                         would miss them"
                    )));
                }
                bar.set_position(sent);
            }
            if !started {
                // The start, measured against what was just queued.
                report.push(start).map_err(report_error)?;
                started = true;
            }
            sim.step(1);
            seen_ticks += 1;
            let (state, st) = g.status()?;
            if st.path_flags & MC_PATHST_RUNNING != 0 {
                running = st.path_id as usize;
                report.running(running);
            }
            report.push(position(card)?).map_err(report_error)?;
            if next.is_none() && state == GroupState::Standby {
                break;
            }
            if seen_ticks > 1_000_000_000 {
                return Err(Error::Unsupported("the program did not end".into()));
            }
        }
    } else {
        // The streamer's thread reads the program; each block reaches the report through
        // the channel before its item goes to the card.
        report.push(start).map_err(report_error)?;
        let (tx, rx) = std::sync::mpsc::channel::<Result<Block>>();
        let feed = items.map_while(move |r| match r {
            Ok((b, item)) => tx.send(Ok(b)).ok().map(|()| item),
            Err(e) => {
                let _ = tx.send(Err(e));
                None
            }
        });
        let streamer = g.spawn_path_stream(feed);
        let mut last_tick = card.tick()?;
        let outcome = (|| -> Result<()> {
            loop {
                let tick = card.tick()?;
                let at = (tick != last_tick).then(|| position(card)).transpose()?;
                while let Ok(b) = rx.try_recv() {
                    report.add_block(&b?);
                }
                if let Some(p) = at {
                    last_tick = tick;
                    seen_ticks += 1;
                    let (_, st) = g.status()?;
                    if st.path_flags & MC_PATHST_RUNNING != 0 {
                        report.running(st.path_id as usize);
                    }
                    report.push(p).map_err(report_error)?;
                }
                let progress = streamer.progress();
                bar.set_position(progress.accepted);
                // Done: every item accepted, none left on the card, the group at rest.
                if progress.accepted >= survey.items
                    && progress.queued == 0
                    && g.status()?.0 == GroupState::Standby
                {
                    return Ok(());
                }
                if streamer.is_finished() && streamer.progress().accepted < survey.items {
                    // Refused or failed: `join` has the error.
                    return Ok(());
                }
                // A signal to mcctl: the close that follows halts the path (cli::interrupt).
                crate::cli::interrupt::check()?;
                std::thread::sleep(Duration::from_micros(20));
            }
        })();
        if outcome.is_err() {
            streamer.cancel();
        }
        let joined = streamer.join().map_err(|e| e.error);
        outcome?;
        joined?;
    }
    bar.finish_and_clear();
    let r = report.finish().map_err(report_error)?;
    if json {
        let mut j = r.to_json();
        j["ticks_seen"] = seen_ticks.into();
        j["dropped_zero_length"] = survey.dropped_zero_length.into();
        return Ok(j.to_string());
    }
    Ok(format!(
        "path time {:.4} s, {} segments, peak velocity {:.4}, acceleration {:.4}, jerk {:.4} \
         of the limits, max deviation {:.6} mm, {} exact stops",
        r.path_time,
        r.segments,
        r.peak_vel_ratio,
        r.peak_accel_ratio,
        r.peak_jerk_ratio,
        r.max_deviation,
        r.exact_stops
    ))
}
