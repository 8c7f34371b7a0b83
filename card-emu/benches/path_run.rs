//! The continuous path end to end: the corner benchmark, the dense micro-segment benchmark and
//! streaming across processes. Prints tables (one count = 1 µm).
//!
//! - corners: a 50 mm square and a zig-zag (10 legs of 20 mm, ±5 mm) at 100 mm/s with corner
//!   tolerance 10 µm, 100 µm and 0 (exact stop): path time, and the worst deviation;
//! - dense: a free-form curve (a hypotrochoid, radius of curvature down to 1.25 mm) cut into
//!   10,000 chords of ~0.1 mm (chord error ≤ 1 µm), tolerance 1 µm, on the stepped card: path
//!   time against the offline bound (the time at the largest feed its curvature and the axis
//!   limits allow, accelerating within the axes' acceleration), peak axis velocity,
//!   acceleration and jerk over their limits (finite differences of the commanded positions per
//!   tick), the worst distance from the chords, and the card's time per segment: the card's
//!   steps less those of an idle card stepped beside it, and the calls that hand it the
//!   segments (see `benches/path.rs` for the engine's own parts, without the SDK);
//! - streaming: a `card-emu` process at 10 kHz (real time), 100,000 segments of 10 counts at
//!   150,000 counts/s along a circle streamed from this process (look-ahead 2048): segments
//!   per second and starvation events; once with chord fitting off (each chord a segment of the
//!   card's: the card's segment rate), once with it on (the SDK sends the circle as a curve).
//!
//! `cargo bench -p card-emu --bench path_run [-- corners|dense|streaming] [--runs N]` (`--runs`:
//! the dense part's runs, default 3; its cost figures are the median)
use motioncard_sdk::{
    Card, CardSet, EventKind, Group, GroupSettings, GroupState, PathPart, PathSettings, Segment,
    Sim, SimOptions,
};
#[path = "common/dense.rs"]
mod dense;
#[path = "common/procs.rs"]
mod procs;

use dense::{A, J, V};
use procs::{card_emu, open};
use std::time::{Duration, Instant};

/// The card's group 0 over axes 0 and 1 with `lim`. Chord fitting is the SDK's, and these
/// benchmarks measure what the card does with each segment: the callers turn it off except
/// where said.
fn group(card: &Card, lim: &PathSettings) -> Group {
    for a in 0..2 {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    g.enable().unwrap();
    g.configure_path(lim).unwrap();
    g
}

fn cmd(card: &Card) -> [f64; 2] {
    let p = |a| card.axis(a).unwrap().status().unwrap().raw.cmd_pos;
    [p(0), p(1)]
}

/// What a run on the stepped card measured.
#[derive(Clone, Copy)]
struct Measured {
    time: f64,
    peaks: [f64; 3],
    deviation: f64,
    /// Time in `sim.step` of the run's card, and of an idle card stepped beside it (the
    /// same steps, interleaved, when asked for), s.
    step_secs: f64,
    idle_secs: f64,
    /// Time in the calls that hand the segments to the card (the SDK's encoding and ring,
    /// the doorbell, the card's checks and `Path::push`), s.
    feed_secs: f64,
}

fn stepped_card(lim: &PathSettings) -> (Card, Group) {
    let card = Card::open_sim(SimOptions {
        clock: motioncard_sdk::Clock::Stepped,
        emu: Default::default(),
    })
    .unwrap();
    let g = group(&card, lim);
    (card, g)
}

/// Stream `pts` (from the first, where the group is) as blended lines at `feed` with `tol`,
/// feeding the card's buffer as it frees room, stepping and recording every tick. With
/// `paired`, a second card, idle with the same configuration, is stepped 64 times after every
/// 64 steps of the first and timed the same way (only `sim.step` under the clock), so that
/// the difference is what the path costs under the same load (blocks, not single steps, so
/// that the two cards do not evict each other's caches on every step).
fn run_polyline(
    pts: &[[f64; 2]],
    feed: f64,
    tol: f64,
    lim: &PathSettings,
    paired: bool,
) -> Measured {
    let (card, g) = stepped_card(lim);
    let idle = paired.then(|| stepped_card(lim));
    let idle_sim: Option<Sim> = idle.as_ref().map(|(c, _)| c.sim().unwrap());
    let sim: Sim = card.sim().unwrap();
    let segs: Vec<Segment> = (1..pts.len())
        .map(|i| {
            let s = Segment::line(i as u32, &pts[i], feed, tol);
            if i + 1 == pts.len() {
                s.last()
            } else {
                s
            }
        })
        .collect();
    let mut next = 0;
    let mut feed_secs = 0.0;
    let mut feed_card = |g: &Group, next: &mut usize| {
        let t = Instant::now();
        let room = g.path_free().unwrap();
        if room > 0 && *next < segs.len() {
            let end = (*next + room).min(segs.len());
            g.stream_path(segs[*next..end].iter().cloned(), |_| {})
                .unwrap();
            *next = end;
        }
        feed_secs += t.elapsed().as_secs_f64();
    };
    feed_card(&g, &mut next);
    let mut pos = vec![cmd(&card)];
    let (mut step_secs, mut idle_secs) = (0.0, 0.0);
    let mut starved = 0;
    loop {
        let t = Instant::now();
        sim.step(1);
        step_secs += t.elapsed().as_secs_f64();
        pos.push(cmd(&card));
        if pos.len().is_multiple_of(64) {
            if let Some(s) = &idle_sim {
                for _ in 0..64 {
                    let t = Instant::now();
                    s.step(1);
                    idle_secs += t.elapsed().as_secs_f64();
                }
            }
            feed_card(&g, &mut next);
        }
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            starved += (e.kind == EventKind::PathStarved) as usize;
        }
        if next == segs.len() && g.status().unwrap().0 == GroupState::Standby {
            break;
        }
        assert!(pos.len() < 20_000_000, "no end");
    }
    assert_eq!(starved, 0, "the stepped run starved");
    let l = |a: usize| [lim.vmax[a], lim.amax[a], lim.jmax[a]];
    let q = dense::quality(&pos, pts, [l(0), l(1)]);
    Measured {
        time: q.time,
        peaks: q.peaks,
        deviation: q.deviation,
        step_secs,
        idle_secs,
        feed_secs,
    }
}

fn corners() {
    println!("\n| corner benchmark (100 mm/s)  | tolerance | path time s | vs exact stop | max deviation µm | peak a/amax | peak j/jmax |");
    println!("|------------------------------|-----------|-------------|---------------|------------------|-------------|-------------|");
    let lim = PathSettings {
        chord_fit: false,
        ..PathSettings::uniform(2, V, A, J)
    };
    let s = 50_000.0;
    let square = vec![[0.0, 0.0], [s, 0.0], [s, s], [0.0, s], [0.0, 0.0]];
    let zigzag: Vec<[f64; 2]> = (0..=10)
        .map(|k| [k as f64 * 20_000.0, if k % 2 == 1 { 5_000.0 } else { 0.0 }])
        .collect();
    for (name, pts) in [("square 50 mm", square), ("zig-zag 10 × 20 mm", zigzag)] {
        let exact = run_polyline(&pts, V, 0.0, &lim, false);
        for tol in [0.0, 10.0, 100.0] {
            let m = if tol == 0.0 {
                exact
            } else {
                run_polyline(&pts, V, tol, &lim, false)
            };
            println!(
                "| {:<28} | {:>6} µm | {:>11.4} | {:>12.1}% | {:>16.3} | {:>11.4} | {:>11.4} |",
                name,
                tol,
                m.time,
                100.0 * m.time / exact.time,
                m.deviation,
                m.peaks[1],
                m.peaks[2]
            );
        }
    }
}

/// Median and range.
fn stats(mut xs: Vec<f64>) -> (f64, f64, f64) {
    xs.sort_by(f64::total_cmp);
    (xs[xs.len() / 2], xs[0], xs[xs.len() - 1])
}

fn dense(runs: usize) {
    let lim = PathSettings {
        chord_fit: false,
        ..PathSettings::uniform(2, V, A, J)
    };
    let (pts, chord_err) = dense::dense_points(dense::CHORDS);
    let len: f64 = pts
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    let bound = dense::bound_time(V);
    let ms: Vec<Measured> = (0..runs)
        .map(|_| run_polyline(&pts, V, dense::TOL, &lim, true))
        .collect();
    let m = ms[0];
    let n = dense::CHORDS as f64;
    println!("\n| dense curve: 10,000 chords      | value |");
    println!("|---------------------------------|-------|");
    println!(
        "| length, chord error             | {:.1} mm, {:.3} µm |",
        len / 1000.0,
        chord_err
    );
    println!(
        "| path time / offline bound       | {:.4} s / {:.4} s = {:.4} |",
        m.time,
        bound,
        m.time / bound
    );
    println!(
        "| peak v, a, j over their limits  | {:.4}, {:.4}, {:.4} |",
        m.peaks[0], m.peaks[1], m.peaks[2]
    );
    println!(
        "| max deviation from the chords   | {:.4} µm (tolerance 1 µm) |",
        m.deviation
    );
    let row = |name: &str, f: &dyn Fn(&Measured) -> f64| {
        let (md, lo, hi) = stats(ms.iter().map(f).collect());
        println!("| {name} | {md:.2} µs ({lo:.2} – {hi:.2}) |");
    };
    println!("\nµs per segment, median (range) of {runs} runs of the in-process stepped card:");
    println!("| what | per segment |");
    println!("|------|-------------|");
    row("card steps, minus the same steps of an idle card stepped beside it (look-ahead, planner, interpolation, the group's path step)", &|m| {
        (m.step_secs - m.idle_secs) / n * 1e6
    });
    row("the calls that hand the segments over (SDK encoding and ring, doorbell, the card's checks, `Path::push`)", &|m| {
        m.feed_secs / n * 1e6
    });
    row("sum", &|m| {
        (m.step_secs - m.idle_secs + m.feed_secs) / n * 1e6
    });
    row("idle card's steps (not in the above)", &|m| {
        m.idle_secs / n * 1e6
    });
}

/// 100,000 chords from a separate process: with `fit` off each chord is a segment of the card's
/// (its segment rate), with it on the SDK sends the circle as the curve the chords sample.
fn streaming(fit: bool) {
    let name = format!("bench-path-{}", std::process::id());
    let _child = card_emu(&name, &["--servo-rate", "10000"]);
    let card = open(&format!("emu:{name}"));
    // the braking distance from 150,000 counts/s (≈ 12,000 counts) is 1,200 segments: the
    // look-ahead must see that far
    let mut lim = PathSettings::uniform(2, 2e5, 2e6, 2e8);
    lim.lookahead = 2048;
    lim.chord_fit = fit;
    let g = group(&card, &lim);
    let n = 100_000u32;
    // A circle of radius 50,000 counts in 10-count chords at 150,000 counts/s: 15,000
    // segments/s, a path whose curvature allows that speed (v²/R = 4.5e5 counts/s²).
    const R: f64 = 50_000.0;
    let segs = (1..=n).map(move |i| {
        let th = i as f64 * 10.0 / R;
        let s = Segment::line(i, &[R * th.sin(), R - R * th.cos()], 150_000.0, 1.0);
        if i == n {
            s.last()
        } else {
            s
        }
    });
    let mut starved = 0;
    let mut count = |card: &Card| {
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            starved += (e.kind == EventKind::PathStarved) as usize;
        }
    };
    let t = Instant::now();
    let mut k = 0u32;
    let last = g
        .stream_path(segs, |_| {
            k += 1;
            if k.is_multiple_of(256) {
                count(&card);
            }
        })
        .unwrap()
        .unwrap();
    let sent = t.elapsed().as_secs_f64();
    last.wait(Duration::from_secs(120)).unwrap();
    let total = t.elapsed().as_secs_f64();
    count(&card);
    let fitted = if fit { ", fitted" } else { "" };
    println!("\n| streaming across processes (card-emu at 10 kHz{fitted}) | value |");
    println!("|--------------------------------------------------|-------|");
    println!("| segments streamed                                | {n} |");
    println!(
        "| accepted, average rate                           | {:.0} segments/s over {:.2} s |",
        n as f64 / sent,
        sent
    );
    println!("| path consumption (the path's own rate)           | {:.0} segments/s ({:.2} s to the end) |", n as f64 / total, total);
    println!("| starvation events                                | {starved} |");
}

/// A 12-axis path over two `card-emu` processes of six axes on one sync bus at 10 kHz,
/// streamed from this process with `SetPath::run` (releases timed `margin` ms ahead): 20,000
/// chords of 10 counts (a circle of radius 50,000 counts in axes 0 and 1, the other ten axes
/// a scaled copy of it) at 150,000 counts/s: segments per second pushed, the path's own
/// rate, starvation events on each card.
fn set_streaming(margin: u64) {
    let master = format!("bench-setpath-{}", std::process::id());
    let follower = format!("{master}-f");
    let args = ["--axes", "6", "--servo-rate", "10000"];
    let _m = card_emu(&master, &args);
    let cards = vec![open(&format!("emu:{master}"))];
    let _f = card_emu(&follower, &[&args[..], &["--sync-from", &master]].concat());
    let cards = [cards, vec![open(&format!("emu:{follower}"))]].concat();
    let axes: Vec<usize> = (0..6).collect();
    for c in &cards {
        for &a in &axes {
            c.axis(a).unwrap().enable().unwrap();
        }
        let g = c.group(0).unwrap();
        g.configure(&GroupSettings::new(&axes)).unwrap();
        g.enable().unwrap();
    }
    let mut set = CardSet::new(cards).unwrap();
    set.set_margin(Duration::from_millis(margin));
    let mut lim = PathSettings::uniform(12, 2e5, 2e6, 2e8);
    lim.lookahead = 2048;
    let parts = [
        PathPart { card: 0, group: 0 },
        PathPart { card: 1, group: 0 },
    ];
    let mut path = set.path(&parts, &lim).unwrap();
    const R: f64 = 50_000.0;
    let n = 20_000u32;
    let mut length = 0.0;
    let mut prev = vec![0.0; 12];
    let segs: Vec<Segment> = (1..=n)
        .map(|i| {
            let th = i as f64 * 10.0 / R;
            let (x, y) = (R * th.sin(), R - R * th.cos());
            let p: Vec<f64> = (0..12)
                .map(|d| match d {
                    0 => x,
                    1 => y,
                    _ => [x, y][d % 2] * (d as f64 / 24.0),
                })
                .collect();
            length += p
                .iter()
                .zip(&prev)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            prev.clone_from(&p);
            Segment::line(i, &p, 150_000.0, 1.0)
        })
        .collect();
    let t = Instant::now();
    path.run(&segs).unwrap();
    let sent = t.elapsed().as_secs_f64();
    path.wait(Duration::from_secs(120)).unwrap();
    let total = t.elapsed().as_secs_f64();
    let mut starved = [0usize; 2];
    for (k, c) in set.cards().iter().enumerate() {
        while let Some(e) = c.next_event(Duration::ZERO).unwrap() {
            starved[k] += (e.kind == EventKind::PathStarved) as usize;
        }
    }
    println!(
        "\n| a 12-axis path across two card-emu processes (10 kHz), margin {margin} ms | value |"
    );
    println!("|--------------------------------------------------|-------|");
    println!("| segments streamed                                | {n} |");
    println!(
        "| pushed and released, average rate                | {:.0} segments/s over {:.2} s |",
        n as f64 / sent,
        sent
    );
    println!(
        "| path consumption (the path's own rate)           | {:.0} segments/s ({:.2} s to the end; {:.2} s at the feed) |",
        n as f64 / total,
        total,
        length / 150_000.0
    );
    println!(
        "| starvation events (master, follower)             | {}, {} |",
        starved[0], starved[1]
    );
}

fn main() {
    if !std::env::args().any(|a| a == "--bench") {
        println!("path_run: skipped (run with `cargo bench`)");
        return;
    }
    // `cargo bench -p card-emu --bench path_run -- dense` runs one part (corners, dense,
    // streaming)
    let only: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--") && a.parse::<usize>().is_err())
        .collect();
    let part = |name: &str| only.is_empty() || only.iter().any(|a| a == name);
    if part("corners") {
        corners();
    }
    if part("dense") {
        let runs = std::env::args()
            .skip_while(|a| a != "--runs")
            .nth(1)
            .and_then(|x| x.parse().ok())
            .unwrap_or(3usize)
            .max(1);
        dense(runs);
    }
    if part("streaming") {
        streaming(false);
        streaming(true);
    }
    if part("set-streaming") {
        set_streaming(20);
        set_streaming(5);
    }
}
