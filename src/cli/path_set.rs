//! `mcctl path-set`: a path across the cards of one sync bus (layout 1.14, `CardSet::path`).
//! Each card's group 0 is configured over its first `--split` axes (disabled first when it is
//! enabled, and the axes enabled); the path's dimensions are
//! those axes, card after card (up to 16). The file gives the path: a line of N numbers (N the
//! dimensions) is a line to that point, `dwell SECONDS` an exact stop and a wait. It is read and
//! checked whole before any card is opened (exit status 2 naming the line), then pushed to
//! every card, released in batches (the first release starts it on one tick on every card) and
//! waited for; what every card's group did is printed.
//!
//! `--cards sim` (the default) runs it on stepped emulated cards of this process, one per
//! `--split` entry, on one bus; else `--cards` lists the bus's cards (the master first), as
//! `--card` names one.

use super::args::{non_negative, positive};
use super::{bad, interrupt, interrupted, progress, POLL, WAIT};
use crate::{
    Card, CardSet, Clock, EmuOptions, Error, GroupSettings, PathPart, PathSettings, Result,
    Segment, SetPath, SimOptions,
};
use clap::Args as ClapArgs;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Dimensions of a path across cards.
const MAX_DIMS: usize = 16;
/// Axes of each card of `--cards sim`.
const SIM_AXES: usize = 8;
/// Servo rate of `--cards sim`.
const SIM_RATE: u32 = 10_000;

/// `mcctl path-set`.
#[derive(ClapArgs)]
pub struct Args {
    /// The path: a line of N numbers (the point to go to, one per dimension, commas or blanks
    /// between) or `dwell SECONDS`; `#` starts a comment.
    pub file: std::path::PathBuf,
    /// The cards: `sim` (stepped emulated cards in this process, one per --split entry), or
    /// the card URIs of one sync bus, the master first, comma-separated.
    #[arg(long, default_value = "sim")]
    pub cards: String,
    /// Axes of each card's group 0 (its first axes), comma-separated, card by card: the
    /// path's dimensions in order (1 to 16 in all).
    #[arg(long, value_delimiter = ',', default_value = "6,6")]
    pub split: Vec<usize>,
    /// Path speed, first dimension's units per second.
    #[arg(long, default_value_t = 2e4, value_parser = positive("--feed"))]
    pub feed: f64,
    /// Corner blend: the largest deviation from each corner (0: an exact stop at each).
    #[arg(long, default_value_t = 0.0, value_parser = non_negative("--tolerance"))]
    pub tolerance: f64,
    /// Every dimension's velocity limit.
    #[arg(long, default_value_t = 5e4, value_parser = positive("--vmax"))]
    pub vmax: f64,
    /// Every dimension's acceleration limit.
    #[arg(long, default_value_t = 1e6, value_parser = positive("--amax"))]
    pub amax: f64,
    /// Every dimension's jerk limit.
    #[arg(long, default_value_t = 1e8, value_parser = positive("--jmax"))]
    pub jmax: f64,
    /// One JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// One item of the file.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A line to this point.
    Point(Vec<f64>),
    /// A dwell of this many seconds.
    Dwell(f64),
}

/// The items of a path file of `n`-dimension points. Err: the line (from 1) and what is wrong.
pub fn parse(text: &str, n: usize) -> std::result::Result<Vec<Item>, String> {
    let mut items = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        if words[0] == "dwell" {
            match words[1..] {
                [s] => match s.parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => items.push(Item::Dwell(v)),
                    _ => return Err(format!("line {}: a dwell of `{s}` seconds (> 0)", i + 1)),
                },
                _ => return Err(format!("line {}: expected `dwell SECONDS`", i + 1)),
            }
            continue;
        }
        let v: std::result::Result<Vec<f64>, _> = words.iter().map(|w| w.parse::<f64>()).collect();
        match v {
            Ok(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => items.push(Item::Point(v)),
            _ => {
                return Err(format!(
                    "line {}: expected {n} finite numbers (one per dimension) or `dwell SECONDS`, \
                     got `{line}`",
                    i + 1
                ))
            }
        }
    }
    if !items.iter().any(|i| matches!(i, Item::Point(_))) {
        return Err("no points".into());
    }
    Ok(items)
}

/// Run the path file on the cards.
pub fn run(a: Args) -> ExitCode {
    let n: usize = a.split.iter().sum();
    if a.split.contains(&0) || a.split.iter().any(|&k| k > SIM_AXES) {
        return bad(format!(
            "--split: each card's group has 1 to {SIM_AXES} axes, got {:?}",
            a.split
        ));
    }
    if n > MAX_DIMS {
        return bad(format!(
            "--split: a path across cards has at most {MAX_DIMS} dimensions, got {n}"
        ));
    }
    let text = match std::fs::read_to_string(&a.file) {
        Ok(t) => t,
        Err(e) => return bad(format!("{}: {e}", a.file.display())),
    };
    let items = match parse(&text, n) {
        Ok(v) => v,
        Err(e) => return bad(format!("{}: {e}", a.file.display())),
    };
    let r = open(&a).and_then(|set| {
        let out = go(&set, &a, &items);
        let mut closed = Ok(());
        for c in set.cards() {
            let r = c.close();
            if closed.is_ok() {
                closed = r;
            }
        }
        out.and_then(|o| closed.map(|()| o))
    });
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
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

fn open(a: &Args) -> Result<CardSet> {
    if a.cards == "sim" {
        return CardSet::sim(
            a.split.len(),
            SimOptions {
                clock: Clock::Stepped,
                emu: EmuOptions::new(SIM_AXES, SIM_RATE),
            },
        );
    }
    let uris: Vec<&str> = a.cards.split(',').map(str::trim).collect();
    if uris.len() != a.split.len() {
        return Err(Error::BadConfig(format!(
            "{} cards in --cards, {} in --split",
            uris.len(),
            a.split.len()
        )));
    }
    let mut cards = Vec::with_capacity(uris.len());
    for u in uris {
        match Card::open(u) {
            Ok(c) => cards.push(c),
            Err(e) => {
                for c in &cards {
                    let _ = c.close();
                }
                return Err(e);
            }
        }
    }
    CardSet::new(cards)
}

/// Configure, push, release, wait; the report.
fn go(set: &CardSet, a: &Args, items: &[Item]) -> Result<String> {
    for (c, &k) in set.cards().iter().zip(&a.split) {
        let axes: Vec<usize> = (0..k).collect();
        for &x in &axes {
            let ax = c.axis(x)?;
            if ax.status()?.state == crate::AxisState::Disabled {
                ax.enable()?;
            }
        }
        let g = c.group(0)?;
        // (a card that ran a path before keeps its group enabled: configured anew, disabled
        // first)
        if g.status()?.0 != crate::GroupState::Disabled {
            g.disable()?;
        }
        g.configure(&GroupSettings::new(&axes))?;
        g.enable()?;
    }
    let n: usize = a.split.iter().sum();
    let parts: Vec<PathPart> = (0..a.split.len())
        .map(|card| PathPart { card, group: 0 })
        .collect();
    let mut path = set.path(&parts, &PathSettings::uniform(n, a.vmax, a.amax, a.jmax))?;
    let segs: Vec<Segment> = items
        .iter()
        .enumerate()
        .map(|(i, it)| match it {
            Item::Point(p) => Segment::line(i as u32 + 1, p, a.feed, a.tolerance),
            Item::Dwell(s) => Segment::dwell(i as u32 + 1, *s),
        })
        .collect();
    let start = path.run(&segs)?;
    let r = wait(set, &path, segs.len());
    if r.is_err() {
        let _ = path.halt(a.amax, a.jmax);
    }
    let ticks = r?.saturating_sub(start);
    report(set, a, &path, segs.len(), start, ticks)
}

/// Wait for the path with a bar of the segments done; the tick it came to rest on.
fn wait(set: &CardSet, path: &SetPath, total: usize) -> Result<u64> {
    let bar = progress(Some(total as u64), "path across cards");
    let begin = Instant::now();
    let r = loop {
        match path.wait(POLL.max(Duration::from_millis(10))) {
            Err(Error::Timeout(_)) if begin.elapsed() < WAIT => {}
            Err(Error::Timeout(_)) => break Err(Error::Timeout(WAIT)),
            r => break r,
        }
        if let Err(e) = interrupt::check() {
            break Err(e);
        }
        if let Ok(p) = path.progress() {
            bar.set_position(u64::from(p.done));
        }
    };
    bar.finish_and_clear();
    r?;
    set.tick()
}

fn report(
    set: &CardSet,
    a: &Args,
    path: &SetPath,
    total: usize,
    start: u64,
    ticks: u64,
) -> Result<String> {
    let rate = f64::from(set.cards()[0].info().servo_rate_hz);
    let done = path.progress()?.done;
    let mut cards = Vec::new();
    let mut text = format!(
        "path across {} cards: {} dimensions, {done} of {total} segments done, started on tick \
         {start}, at rest {:.4} s later (card time)\n",
        set.cards().len(),
        path.dims(),
        ticks as f64 / rate
    );
    let mut dim = 0;
    for (c, &k) in set.cards().iter().zip(&a.split) {
        let (state, _) = c.group(0)?.status()?;
        let mut at = Vec::with_capacity(k);
        for x in 0..k {
            at.push(c.axis(x)?.status()?.command_position);
        }
        let name = c.bus_status()?.name;
        text.push_str(&format!(
            "card {name}: group 0 {state:?}, dimensions {}..{}, axes at {}\n",
            dim,
            dim + k - 1,
            at.iter()
                .map(|x| format!("{x}"))
                .collect::<Vec<_>>()
                .join(" ")
        ));
        cards.push(serde_json::json!({
            "card": name,
            "state": format!("{state:?}"),
            "dimensions": [dim, dim + k - 1],
            "positions": at,
        }));
        dim += k;
    }
    if a.json {
        let j = serde_json::json!({
            "dimensions": path.dims(),
            "segments": total,
            "done": done,
            "start_tick": start,
            "seconds": ticks as f64 / rate,
            "cards": cards,
        });
        return Ok(format!("{j}\n"));
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_file_reads_points_and_dwells_and_names_a_bad_line() {
        let items = parse("# x y z\n1, 2 3\n\ndwell 0.5 # wait\n4 5 6\n", 3).unwrap();
        assert_eq!(
            items,
            vec![
                Item::Point(vec![1.0, 2.0, 3.0]),
                Item::Dwell(0.5),
                Item::Point(vec![4.0, 5.0, 6.0])
            ]
        );
        assert!(parse("1 2 3\n1 2\n", 3)
            .unwrap_err()
            .starts_with("line 2: expected 3"));
        assert!(parse("1 2 nan\n", 3).unwrap_err().starts_with("line 1:"));
        assert_eq!(
            parse("1 2 3\ndwell -1\n", 3).unwrap_err(),
            "line 2: a dwell of `-1` seconds (> 0)"
        );
        assert_eq!(parse("dwell 1\n", 3).unwrap_err(), "no points");
    }
}
