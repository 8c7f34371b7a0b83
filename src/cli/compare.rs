//! `mcctl compare`: position compare (EQU output), an output pulsed as the axis crosses
//! positions (on a rotary axis places on the turn, with `--each-turn` on every turn). Arms the
//! channel, runs --move (or watches --for seconds), reports the fires and
//! misses the card counted with the positions of its events (misses of one tick share one
//! event: the last position), and disarms.

use super::args::{finite, TravelArgs};
use super::machine::{halt_of, run_collecting, Powered, Travel};
use super::rows::{file_rows, NumberRows};
use super::{bad, on_card};
use crate::proto::raw;
use crate::{
    Card, CompareChannel, Direction, Error, EventKind, Result, COMPARE_FIRED, COMPARE_MISSED,
};
use clap::{Args as ClapArgs, ValueEnum};
use serde_json::json;
use std::process::ExitCode;
use std::time::Duration;

/// `mcctl compare`.
#[derive(ClapArgs)]
pub struct Args {
    pub axis: usize,
    /// The output pulsed (0..16).
    #[arg(long)]
    pub output: u32,
    /// The compare channel (0..4).
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
    /// Fire once, at this position.
    #[arg(
        long,
        allow_negative_numbers = true,
        value_name = "POSITION",
        value_parser = finite("--at")
    )]
    pub at: Option<f64>,
    /// Fire COUNT times from START, PITCH apart in the direction.
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        value_names = ["START,PITCH,COUNT"],
        value_parser = finite("--series")
    )]
    pub series: Option<Vec<f64>>,
    /// Fire at the positions of this file (one per line, strictly monotonic in the
    /// direction), streamed into the channel's table as it empties.
    #[arg(long, value_name = "FILE")]
    pub table: Option<std::path::PathBuf>,
    /// On a rotary axis: fire --at or --series on every turn, until the run ends (a series'
    /// COUNT 0: a whole turn of PITCH).
    #[arg(long)]
    pub each_turn: bool,
    /// The direction of crossing that fires.
    #[arg(long, value_enum, default_value = "positive")]
    pub direction: DirArg,
    /// Pulse width, µs.
    #[arg(
        long,
        default_value_t = 10,
        value_parser = clap::value_parser!(u32).range(1..=raw::MC_PULSE_MAX_US as i64)
    )]
    pub pulse_us: u32,
    #[command(flatten)]
    pub travel: TravelArgs,
    #[arg(long)]
    pub json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum DirArg {
    Positive,
    Negative,
    Either,
}

impl From<DirArg> for Direction {
    fn from(d: DirArg) -> Self {
        match d {
            DirArg::Positive => Direction::Positive,
            DirArg::Negative => Direction::Negative,
            DirArg::Either => Direction::Either,
        }
    }
}

/// Check where it fires (a table file whole, exit status 2 naming its line), then arm, run
/// and report.
pub fn run(uri: &str, a: Args) -> ExitCode {
    if a.each_turn && a.table.is_some() {
        return bad("--each-turn takes --at or --series, not --table".into());
    }
    let positions = match (a.at, a.series, a.table) {
        (Some(p), None, None) => ComparePositions::At(p),
        (None, Some(v), None) => match v[..] {
            [start, pitch, count]
                if count >= if a.each_turn { 0.0 } else { 1.0 }
                    && count.fract() == 0.0
                    && count <= u32::MAX as f64 =>
            {
                ComparePositions::Series {
                    start,
                    pitch,
                    count: count as u32,
                }
            }
            _ => {
                return bad(format!(
                    "--series takes START,PITCH,COUNT (COUNT a whole number >= 1, or 0 with \
                     --each-turn), got {v:?}"
                ))
            }
        },
        (None, None, Some(f)) => match table_positions(&f, a.direction.into()) {
            Ok(_) => ComparePositions::Table(f),
            Err(e) => return bad(format!("{}: {e}", f.display())),
        },
        _ => return bad("give exactly one of --at, --series and --table".into()),
    };

    let job = CompareJob {
        axis: a.axis,
        channel: a.channel,
        output: a.output,
        pulse_us: a.pulse_us,
        direction: a.direction.into(),
        each_turn: a.each_turn,
        positions,
        travel: a.travel.travel(a.axis),
        hold: a.travel.hold,
        enable: a.travel.enable,
    };
    on_card(uri, |c| compare(c, &job, a.json))
}

/// Where a compare channel fires.
#[derive(Debug, Clone, PartialEq)]
pub enum ComparePositions {
    /// Once, at this position.
    At(f64),
    /// `count` positions from `start`, `pitch` apart in the direction.
    Series { start: f64, pitch: f64, count: u32 },
    /// The positions of this file ([`table_positions`]) in order (strictly monotonic in the
    /// direction), read and streamed into the channel's table as it empties.
    Table(std::path::PathBuf),
}

/// Checks a compare table file a line at a time (one finite position a line, strictly
/// monotonic in `dir` when it is Positive or Negative) and counts its positions, so that a
/// bad file is refused before anything is armed or moved. Err: the line and what is wrong.
pub fn table_positions(path: &std::path::Path, dir: Direction) -> std::result::Result<u64, String> {
    let (mut n, mut last) = (0u64, None::<f64>);
    for row in file_rows(path, 1..=1, "position")? {
        let r = row?;
        let p = r.values[0];
        let onward = match (dir, last) {
            (Direction::Positive, Some(q)) => p > q,
            (Direction::Negative, Some(q)) => p < q,
            _ => true,
        };
        if !onward {
            return Err(format!(
                "line {}: position {p} does not come after {} in the {} direction",
                r.line,
                last.unwrap_or_default(),
                if dir == Direction::Positive {
                    "positive"
                } else {
                    "negative"
                }
            ));
        }
        last = Some(p);
        n += 1;
    }
    if n == 0 {
        return Err("no positions".into());
    }
    Ok(n)
}

/// `mcctl compare`.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareJob {
    pub axis: usize,
    pub channel: usize,
    pub output: u32,
    pub pulse_us: u32,
    pub direction: Direction,
    /// On a rotary axis, --at or --series on every turn (layout 1.13).
    pub each_turn: bool,
    pub positions: ComparePositions,
    pub travel: Option<Travel>,
    /// Without a move: how long to watch.
    pub hold: Duration,
    /// Power the axis for the move if it is disabled (`--enable`; off again at the end).
    pub enable: bool,
}

/// Arm a compare channel, run the move, and report the channel's own counters with the
/// positions of the card's events (a fire each; the misses of one tick share one event, with
/// the last position); the channel is disarmed at the end. With `enable`, the axis is powered
/// only for a move, once the channel is armed, and powered off again however it ends.
pub fn compare(card: &Card, job: &CompareJob, json: bool) -> Result<String> {
    let ch = card.axis(job.axis)?.compare(job.channel);
    let (out, dir) = (job.output, job.direction);
    let mut table = None;
    match &job.positions {
        ComparePositions::At(p) if job.each_turn => {
            ch.arm_single_each_turn(out, job.pulse_us, *p, dir)?
        }
        ComparePositions::At(p) => ch.arm_single(out, job.pulse_us, *p, dir)?,
        ComparePositions::Series {
            start,
            pitch,
            count,
        } if job.each_turn => {
            ch.arm_series_each_turn(out, job.pulse_us, *start, *pitch, *count, dir)?
        }
        ComparePositions::Series {
            start,
            pitch,
            count,
        } => ch.arm_series(out, job.pulse_us, *start, *pitch, *count, dir)?,
        ComparePositions::Table(path) => {
            let rows = file_rows(path, 1..=1, "position").map_err(|e| table_error(path, e))?;
            ch.arm_table(out, job.pulse_us, 0, dir)?;
            table = Some((path.as_path(), rows));
        }
    }
    let axis = [(job.axis, halt_of(job.travel.as_ref()))];
    let outcome = Powered::on(card, job.enable && job.travel.is_some(), &axis).and_then(|power| {
        let r = watch_compare(card, &ch, job, table, json);
        let released = power.release();
        let r = r?;
        released.map(|()| r)
    });
    let disarmed = ch.disarm();
    let (fired, missed, at) = outcome?;
    disarmed?;
    let st = ch.status()?;
    Ok(if json {
        json!({
            "axis": job.axis,
            "channel": job.channel,
            "output": job.output,
            "fires": st.fires,
            "missed": st.missed,
            "fired_at": fired,
            "missed_at": missed,
            "position": at,
        })
        .to_string()
    } else {
        let span = |v: &[f64]| match (v.first(), v.last()) {
            (Some(a), Some(b)) => format!(" ({a} .. {b})"),
            _ => String::new(),
        };
        format!(
            "compare {} on axis {}: {} fired{}, {} missed{}, output {}\n",
            job.channel,
            job.axis,
            st.fires,
            span(&fired),
            st.missed,
            span(&missed),
            job.output
        )
    })
}

/// A table file that could not be read as it was checked (it changed meanwhile).
fn table_error(path: &std::path::Path, e: String) -> Error {
    Error::Io {
        context: path.display().to_string(),
        source: std::io::Error::other(e),
    }
}

/// The positions fired and missed (from the card's events; with `json` every one, else only
/// the first and the last) and where the move ended.
type Fires = (Vec<f64>, Vec<f64>, Option<f64>);

/// A position of an event: every one kept for the JSON, else the first and the last.
fn keep(v: &mut Vec<f64>, p: f64, all: bool) {
    if all || v.len() < 2 {
        v.push(p);
    } else {
        v[1] = p;
    }
}

fn watch_compare<R: std::io::BufRead>(
    card: &Card,
    ch: &CompareChannel,
    job: &CompareJob,
    mut table: Option<(&std::path::Path, NumberRows<R>)>,
    json: bool,
) -> Result<Fires> {
    let (mut fired, mut missed) = (Vec::new(), Vec::new());
    // At most a table's room of positions in hand.
    let mut batch = Vec::new();
    let at = run_collecting(card, job.travel.as_ref(), job.hold, |e| {
        match e {
            Some(e) if e.kind == EventKind::Compare && e.axis as usize == job.channel => {
                match e.code {
                    COMPARE_FIRED => keep(&mut fired, e.value, json),
                    COMPARE_MISSED => keep(&mut missed, e.value, json),
                    _ => {}
                }
            }
            Some(_) => {}
            None => {
                if let Some((path, rows)) = &mut table {
                    let room = ch.room()?;
                    batch.clear();
                    for row in rows.by_ref().take(room) {
                        batch.push(row.map_err(|e| table_error(path, e))?.values[0]);
                    }
                    if !batch.is_empty() {
                        ch.push(job.direction, &batch)?;
                    }
                    if batch.len() < room {
                        table = None;
                    }
                }
            }
        }
        Ok(())
    })?;
    Ok((fired, missed, at))
}
