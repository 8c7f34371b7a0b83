//! `mcctl run FILE.ngc`: a G-code program (the RS274/NGC subset of [`crate::gcode`]) turned
//! into path segments, streamed into the card's path buffer as it frees room, and measured
//! ([`crate::path_report`]): path time, peak axis velocity, acceleration and jerk against their
//! limits, the largest deviation from the programmed path, exact stops.
//!
//! The machine: group 0 over axes 0, 1, 2 (X, Y, Z) with `scale` counts per mm. On the
//! in-process card (`sim`) the card is stepped by this program and every servo tick's
//! commanded position is recorded, so the report is exact. On another card the positions are
//! sampled from the status as fast as the host reads it; the report then measures only the
//! runs of consecutive ticks it saw (and says how many ticks it saw).

use crate::gcode::{Block, Program};
use crate::path_report::{analyse_with_rest_speed, AxisLimits};
use crate::{
    ArcSpec, Card, Error, Group, GroupSettings, GroupState, PathItem, PathSettings, Result,
    Segment, Transition,
};
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
        }
    }
}

/// The program's items: a segment per motion block (id = its source line), output actions
/// before the segment they belong to; the last segment marked last.
pub fn items(p: &Program, opts: &RunOptions) -> Vec<PathItem> {
    let tol = Transition::MaxDeviation(opts.tolerance);
    let mut out: Vec<PathItem> = Vec::with_capacity(p.blocks.len());
    for b in &p.blocks {
        let feed = |f: f64| f.min(opts.feed_limit);
        let seg = match b {
            Block::Line {
                line, end, feed: f, ..
            } => Segment::line(*line as u32, end, feed(*f), 0.0).transition(tol),
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
            }
            Block::Dwell { line, seconds } => Segment::dwell(*line as u32, *seconds),
            Block::Output { bit, on, .. } => {
                out.push(PathItem::Output {
                    output: *bit,
                    on: *on,
                    at: crate::OutputAt::Start,
                });
                continue;
            }
        };
        out.push(seg.into());
    }
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

/// Run `text` on `card`: the report as text or one JSON object.
pub fn run(card: &Card, text: &str, opts: &RunOptions, json: bool) -> Result<String> {
    let g = group(card, opts)?;
    let start = position(card)?;
    let program = crate::gcode::parse_from(text, start)
        .map_err(|e| Error::Unsupported(format!("G-code {e}")))?;
    let items = items(&program, opts);
    let bar = indicatif::ProgressBar::new(items.len() as u64);
    if !opts.progress {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    // (`Card::sim` is a stepped in-process card: mcctl opens `sim` stepped for a run.)
    let mut points = vec![start];
    let mut seen_ticks = 1u64;
    if let Some(sim) = card.sim() {
        // Stepped: push what fits, step a tick, record, until the path is done.
        let mut next = 0;
        loop {
            let room = g.path_free()?;
            if room > 0 && next < items.len() {
                let mut end = next;
                let mut segs = 0;
                while end < items.len() && segs < room {
                    segs += matches!(items[end], PathItem::Segment(_)) as usize;
                    end += 1;
                }
                g.stream_path(items[next..end].iter().cloned(), |_| {})
                    .map_err(|e| e.error)?;
                next = end;
                bar.set_position(next as u64);
            }
            sim.step(1);
            seen_ticks += 1;
            points.push(position(card)?);
            if next == items.len() && g.status()?.0 == GroupState::Standby {
                break;
            }
            if seen_ticks > 1_000_000_000 {
                return Err(Error::Unsupported("the program did not end".into()));
            }
        }
    } else {
        let streamer = g.spawn_path_stream(items.clone());
        let mut last_tick = card.tick()?;
        loop {
            let tick = card.tick()?;
            if tick != last_tick {
                last_tick = tick;
                seen_ticks += 1;
                points.push(position(card)?);
            }
            bar.set_position(streamer.progress().accepted);
            // A signal to mcctl: the close that follows halts the path (cli::interrupt).
            crate::cli::interrupt::check()?;
            if streamer.progress().sent as usize >= items.len()
                && g.status()?.0 == GroupState::Standby
            {
                break;
            }
            std::thread::sleep(Duration::from_micros(20));
        }
        streamer.join().map_err(|e| e.error)?;
    }
    bar.finish_and_clear();
    let limits = [0, 1, 2].map(|a| AxisLimits {
        vmax: opts.vmax[a],
        amax: opts.amax[a],
        jmax: opts.jmax[a],
    });
    // Positions are f64 sums on the card: a tick slower than a thousandth of a count per tick
    // is at rest.
    let rest = 1e-3 / opts.scale / ts;
    let r = analyse_with_rest_speed(&program.blocks, &points, ts, &limits, rest)
        .map_err(|e| Error::Unsupported(format!("report: {e:?}")))?;
    if json {
        let mut j = r.to_json();
        j["ticks_seen"] = seen_ticks.into();
        j["dropped_zero_length"] = program.dropped_zero_length.into();
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
