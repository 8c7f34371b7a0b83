//! What the continuous-path engine (`motion::path`) costs the card per segment on the dense
//! micro-segment benchmark of issue 14 (`common/dense.rs`: 10,000 chords of ~0.083 mm along
//! a hypotrochoid, tolerance 1 µm, 10 kHz, the card's path buffer of `PATH_LEN` segments and
//! its default look-ahead of 256), run the way the card runs it: the buffer filled, then
//! refilled every 64 ticks as it frees room (what `path_run -- dense` does through the SDK),
//! the engine ticked until the path is at rest.
//!
//! `cargo bench -p card-emu --bench path [-- --runs N] [--plan-ticks M] [--baseline]`
//!
//! The engine plans every `M` servo ticks, by default as the card does (its default planner
//! period, 1 ms: 10 ticks at 10 kHz); `--plan-ticks 1` plans at every tick. It runs its
//! x86-64-v3 build where the CPU has it, as the card does, or with `--baseline` its baseline
//! x86-64 build (`motion/path/v3.rs`).
//!
//! Three parts, each summed over the run and divided by the 10,000 segments:
//! - push: `Path::push` (validation, the smoothing blend, the previous one rebuilt, caps,
//!   deviation): the blending;
//! - plan: `Path::tick_plan` (the look-ahead over the window, the speed planner, a blend cap
//!   left for the tick): the look-ahead;
//! - move: `Path::tick_move` (advance along the pieces, segment events, the position
//!   interpolated at the servo rate): a per-tick cost of any path, not look-ahead or blending.
//!
//! Each part is timed by reading the clock around every call, less the clock's own cost
//! (measured before each run); `N` runs (default 7), the median and the range printed. A
//! coarse run (one clock read per refill and per 64 ticks) checks the sum. `--once` runs the
//! engine once with no clock reads: for callgrind (`card-emu/benches/path_callgrind.sh`). It
//! prints an FNV-1a sum of every commanded position's bits (the same motion to the last bit
//! gives the same sum) and, with `PATH_DUMP=FILE`, writes the positions to FILE (f64, little
//! endian, x then y per tick), to measure how far two builds' motions are apart when the sum
//! differs.
#[path = "common/dense.rs"]
mod dense;

use card_emu::motion::path::{
    plan_ticks, BlendSpeed, Geom, Path, PathLimits, Segment, Transition, DEFAULT_LOOKAHEAD,
    MAX_AXES,
};
use dense::{CHORDS, TOL};
use firmware_proto::PATH_LEN;
use std::hint::black_box;
use std::time::Instant;

fn limits(plan_ticks: usize) -> PathLimits {
    PathLimits {
        naxes: 2,
        ts: dense::TS,
        vmax: [dense::V; MAX_AXES],
        amax: [dense::A; MAX_AXES],
        jmax: [dense::J; MAX_AXES],
        accel: 0.0,
        jerk: 0.0,
        plan_ticks,
    }
}

fn segments(pts: &[[f64; 2]]) -> Vec<Segment> {
    (1..pts.len())
        .map(|i| {
            let mut end = [0.0; MAX_AXES];
            end[..2].copy_from_slice(&pts[i]);
            Segment {
                id: i as u32,
                geom: Geom::Line { end },
                feed: dense::V,
                transition: Transition::MaxDeviation(TOL),
                blend: BlendSpeed::Low,
                last: i + 1 == pts.len(),
            }
        })
        .collect()
}

#[derive(Clone, Copy, PartialEq)]
enum Clock {
    /// Around every push batch and every half tick.
    Fine,
    /// Around every push batch and every 64 ticks.
    Coarse,
    /// Never (for callgrind).
    Off,
}

/// Totals of one run, ns.
#[derive(Debug, Clone, Copy, Default)]
struct Costs {
    ticks: usize,
    push: f64,
    plan: f64,
    mov: f64,
    /// Coarse runs: the ticks as a whole.
    tick: f64,
}

/// The clock's own cost per interval read (two `Instant::now` back to back), ns.
fn clock_cost() -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let n = 200_000;
        let t = Instant::now();
        let mut sum = 0u128;
        for _ in 0..n {
            let a = Instant::now();
            let b = Instant::now();
            sum += (b - a).as_nanos();
        }
        black_box(t);
        best = best.min(sum as f64 / n as f64);
    }
    best
}

fn run(
    p: &mut Path,
    plan_ticks: usize,
    start: [f64; 2],
    segs: &[Segment],
    clock: Clock,
    pos: &mut Vec<[f64; 2]>,
) -> Costs {
    let mut s0 = [0.0; MAX_AXES];
    s0[..2].copy_from_slice(&start);
    p.reset(s0, limits(plan_ticks), DEFAULT_LOOKAHEAD).unwrap();
    pos.clear();
    pos.push(start);
    let oh = if clock == Clock::Off {
        0.0
    } else {
        clock_cost()
    };
    let mut c = Costs::default();
    let mut next = 0;
    let refill = |p: &mut Path, c: &mut Costs, next: &mut usize| {
        let t = (clock != Clock::Off).then(Instant::now);
        while *next < segs.len() && p.free() > 0 {
            p.push(segs[*next]).unwrap();
            *next += 1;
        }
        if let Some(t) = t {
            c.push += t.elapsed().as_nanos() as f64 - oh;
        }
    };
    refill(p, &mut c, &mut next);
    let mut ev = |_| {};
    let mut block = Instant::now();
    loop {
        let q = match clock {
            Clock::Fine => {
                let t0 = Instant::now();
                let plan = p.tick_plan(1.0, &mut ev);
                let t1 = Instant::now();
                let q = p.tick_move(plan, &mut ev);
                let t2 = Instant::now();
                c.plan += (t1 - t0).as_nanos() as f64 - oh;
                c.mov += (t2 - t1).as_nanos() as f64 - oh;
                q
            }
            _ => p.tick(1.0, &mut ev),
        };
        c.ticks += 1;
        pos.push([q[0], q[1]]);
        if c.ticks.is_multiple_of(64) {
            if clock == Clock::Coarse {
                c.tick += block.elapsed().as_nanos() as f64 - oh;
            }
            refill(p, &mut c, &mut next);
            block = Instant::now();
        }
        if next == segs.len() && p.queued() == 0 && !p.is_moving() {
            break;
        }
        assert!(c.ticks < 10_000_000, "no end");
    }
    if clock == Clock::Coarse {
        c.tick += block.elapsed().as_nanos() as f64 - oh;
    }
    c
}

/// Median and range.
fn stats(mut xs: Vec<f64>) -> (f64, f64, f64) {
    xs.sort_by(f64::total_cmp);
    (xs[xs.len() / 2], xs[0], xs[xs.len() - 1])
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let once = args.iter().any(|a| a == "--once");
    if !once && !args.iter().any(|a| a == "--bench") {
        println!("path: skipped (run with `cargo bench`)");
        return;
    }
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|x| x.parse::<usize>().ok())
    };
    let runs = arg("--runs").unwrap_or(7).max(1);
    // the card's planner period unless told (1: the planner at the servo rate)
    let m = arg("--plan-ticks").unwrap_or_else(|| plan_ticks(0.0, dense::TS));
    let (pts, _) = dense::dense_points(CHORDS);
    let segs = segments(&pts);
    let mut p = Path::with_capacity(PATH_LEN);
    // the baseline x86-64 build of the engine, not the x86-64-v3 one (see `path::v3`)
    p.set_v3(!args.iter().any(|a| a == "--baseline"));
    let build = if p.runs_v3() { "x86-64-v3" } else { "baseline" };
    let mut pos = Vec::with_capacity(200_000);
    if once {
        let c = run(&mut p, m, pts[0], &segs, Clock::Off, &mut pos);
        // FNV-1a of every position's bits: equal sums, the same motion to the last bit
        let sum = pos.iter().flatten().fold(0xcbf2_9ce4_8422_2325u64, |h, x| {
            (h ^ x.to_bits()).wrapping_mul(0x100_0000_01b3)
        });
        if let Ok(f) = std::env::var("PATH_DUMP") {
            let bytes: Vec<u8> = pos.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
            std::fs::write(f, bytes).unwrap();
        }
        println!(
            "path --once: {CHORDS} segments, {} ticks, planning every {m}, {build} build, positions {sum:016x}",
            c.ticks
        );
        return;
    }
    let lim = [[dense::V, dense::A, dense::J]; 2];
    let bound = dense::bound_time(dense::V);
    let mut fine = Vec::new();
    for _ in 0..runs {
        fine.push(run(&mut p, m, pts[0], &segs, Clock::Fine, &mut pos));
    }
    let q = dense::quality(&pos, &pts, lim);
    let mut coarse = Vec::new();
    for _ in 0..runs.min(3) {
        coarse.push(run(&mut p, m, pts[0], &segs, Clock::Coarse, &mut pos));
    }
    let ticks = fine[0].ticks;
    let n = CHORDS as f64;
    let row = |name: &str, f: &dyn Fn(&Costs) -> f64, cs: &[Costs]| {
        let (m, lo, hi) = stats(cs.iter().map(f).collect());
        println!("| {name:<58} | {m:>7.3} | {lo:>7.3} – {hi:<7.3} |");
    };
    println!(
        "\npath engine ({build} build), dense benchmark: {CHORDS} chords, {ticks} ticks ({:.2} per segment), planning every {m} ticks, {runs} runs",
        ticks as f64 / n
    );
    println!("| µs per segment (per tick where said)                       |  median | range             |");
    println!("|------------------------------------------------------------|---------|-------------------|");
    row("push: blending", &|c| c.push / n / 1e3, &fine);
    row(
        "plan: look-ahead and speed planner",
        &|c| c.plan / n / 1e3,
        &fine,
    );
    row(
        "look-ahead and blending (push + plan)",
        &|c| (c.push + c.plan) / n / 1e3,
        &fine,
    );
    row(
        "move: interpolation at the servo rate",
        &|c| c.mov / n / 1e3,
        &fine,
    );
    row(
        "total (push + plan + move)",
        &|c| (c.push + c.plan + c.mov) / n / 1e3,
        &fine,
    );
    row("plan, per tick", &|c| c.plan / c.ticks as f64 / 1e3, &fine);
    row("move, per tick", &|c| c.mov / c.ticks as f64 / 1e3, &fine);
    row("coarse clock: push", &|c| c.push / n / 1e3, &coarse);
    row(
        "coarse clock: ticks (plan + move)",
        &|c| c.tick / n / 1e3,
        &coarse,
    );
    row(
        "coarse clock: total",
        &|c| (c.push + c.tick) / n / 1e3,
        &coarse,
    );
    println!(
        "path time {:.4} s / offline bound {:.4} s = {:.4}; peak v, a, j over the limits {:.4}, {:.4}, {:.4}; worst distance from the chords {:.4} µm (tolerance {TOL} µm)",
        q.time, bound, q.time / bound, q.peaks[0], q.peaks[1], q.peaks[2], q.deviation
    );
}
