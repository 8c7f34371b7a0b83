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
//!   tick), the worst distance from the chords, and the card's time per segment;
//! - streaming: a `card-emu` process at 10 kHz (real time), 100,000 segments of 10 counts at
//!   150,000 counts/s along a circle streamed from this process (look-ahead 2048): segments
//!   per second and starvation events.
//!
//! `cargo bench -p card-emu --bench path_run [-- corners|dense|streaming]`
use motioncard_sdk::{
    Card, EventKind, Group, GroupSettings, GroupState, PathSettings, Segment, Sim, SimOptions,
};
use std::process::{Command as Process, Stdio};
use std::time::{Duration, Instant};

const TS: f64 = 1e-4;
const V: f64 = 1e5;
const A: f64 = 1e6;
const J: f64 = 1e8;

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

fn dist_seg(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// What a run on the stepped card measured.
#[derive(Clone, Copy)]
struct Measured {
    time: f64,
    peaks: [f64; 3],
    deviation: f64,
    step_secs: f64,
    ticks: usize,
}

/// Stream `pts` (from the first, where the group is) as blended lines at `feed` with `tol`,
/// feeding the card's buffer as it frees room, stepping and recording every tick.
fn run_polyline(pts: &[[f64; 2]], feed: f64, tol: f64, lim: &PathSettings) -> Measured {
    let card = Card::open_sim(SimOptions {
        clock: motioncard_sdk::Clock::Stepped,
        emu: Default::default(),
    })
    .unwrap();
    let g = group(&card, lim);
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
    let feed_card = |g: &Group, next: &mut usize| {
        let room = g.path_free().unwrap();
        if room > 0 && *next < segs.len() {
            let end = (*next + room).min(segs.len());
            g.stream_path(segs[*next..end].iter().cloned(), |_| {})
                .unwrap();
            *next = end;
        }
    };
    feed_card(&g, &mut next);
    let mut pos = vec![cmd(&card)];
    let mut step_secs = 0.0;
    let mut starved = 0;
    loop {
        let t = Instant::now();
        sim.step(1);
        step_secs += t.elapsed().as_secs_f64();
        pos.push(cmd(&card));
        if pos.len().is_multiple_of(64) {
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
    let first = pos.iter().position(|p| *p != pos[0]).unwrap_or(0);
    let last = pos
        .iter()
        .rposition(|p| *p != pos[pos.len() - 1])
        .unwrap_or(0);
    let mut peaks = [0.0f64; 3];
    for a in 0..2 {
        for w in pos.windows(4) {
            let v = (w[3][a] - w[2][a]) / TS;
            let acc = (w[3][a] - 2.0 * w[2][a] + w[1][a]) / (TS * TS);
            let j = (w[3][a] - 3.0 * w[2][a] + 3.0 * w[1][a] - w[0][a]) / (TS * TS * TS);
            peaks[0] = peaks[0].max(v.abs() / lim.vmax[a]);
            peaks[1] = peaks[1].max(acc.abs() / lim.amax[a]);
            peaks[2] = peaks[2].max(j.abs() / lim.jmax[a]);
        }
    }
    // Distance to the chords, walking a window forward with the motion.
    let mut k = 0usize;
    let mut deviation: f64 = 0.0;
    for p in &pos {
        let lo = k.saturating_sub(4);
        let hi = (k + 64).min(pts.len() - 1);
        let (mut best, mut bi) = (f64::INFINITY, k);
        for i in lo..hi {
            let d = dist_seg(*p, pts[i], pts[i + 1]);
            if d < best {
                best = d;
                bi = i;
            }
        }
        k = bi;
        deviation = deviation.max(best);
    }
    Measured {
        time: (last + 1 - first) as f64 * TS,
        peaks,
        deviation,
        step_secs,
        ticks: pos.len(),
    }
}

fn corners() {
    println!("\n| corner benchmark (100 mm/s)  | tolerance | path time s | vs exact stop | max deviation µm | peak a/amax | peak j/jmax |");
    println!("|------------------------------|-----------|-------------|---------------|------------------|-------------|-------------|");
    let lim = PathSettings::uniform(2, V, A, J);
    let s = 50_000.0;
    let square = vec![[0.0, 0.0], [s, 0.0], [s, s], [0.0, s], [0.0, 0.0]];
    let zigzag: Vec<[f64; 2]> = (0..=10)
        .map(|k| [k as f64 * 20_000.0, if k % 2 == 1 { 5_000.0 } else { 0.0 }])
        .collect();
    for (name, pts) in [("square 50 mm", square), ("zig-zag 10 × 20 mm", zigzag)] {
        let exact = run_polyline(&pts, V, 0.0, &lim);
        for tol in [0.0, 10.0, 100.0] {
            let m = if tol == 0.0 {
                exact
            } else {
                run_polyline(&pts, V, tol, &lim)
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

/// The hypotrochoid z(t) = a·e^{it} + b·e^{ikt} (counts), its minimum radius of curvature
/// (b·k − a)² / (b·k² − a) = 1250 counts = 1.25 mm.
const CA: f64 = 86_000.0;
const CK: f64 = 7.0;
const CB: f64 = 116_100.0 / 7.0;

fn curve(t: f64) -> [f64; 2] {
    [
        CA * t.cos() + CB * (CK * t).cos(),
        CA * t.sin() + CB * (CK * t).sin(),
    ]
}

/// 10,000 chords of equal parameter-arc length along one turn, starting at the origin (the
/// group's position: the curve is shifted).
fn dense_points(n: usize) -> (Vec<[f64; 2]>, f64) {
    // Arc length table on a fine parameter grid, then equal-length stations.
    let m = 2_000_000;
    let mut s = vec![0.0; m + 1];
    let dt = std::f64::consts::TAU / m as f64;
    let mut prev = curve(0.0);
    for i in 1..=m {
        let p = curve(i as f64 * dt);
        s[i] = s[i - 1] + (p[0] - prev[0]).hypot(p[1] - prev[1]);
        prev = p;
    }
    let total = s[m];
    let o = curve(0.0);
    let mut pts = Vec::with_capacity(n + 1);
    let mut j = 0;
    for k in 0..=n {
        let target = total * k as f64 / n as f64;
        while j < m && s[j + 1] < target {
            j += 1;
        }
        let f = if j < m {
            (target - s[j]) / (s[j + 1] - s[j])
        } else {
            0.0
        };
        let p = curve((j as f64 + f) * dt);
        pts.push([p[0] - o[0], p[1] - o[1]]);
    }
    // The largest chord error (sampled between the stations).
    let mut chord_err: f64 = 0.0;
    for k in 0..n {
        let t0 = total * k as f64 / n as f64;
        let mid = t0 + 0.5 * total / n as f64;
        let jm = s.partition_point(|x| *x < mid).min(m);
        let p = curve(jm as f64 * dt);
        chord_err = chord_err.max(dist_seg([p[0] - o[0], p[1] - o[1]], pts[k], pts[k + 1]));
    }
    (pts, chord_err)
}

/// The offline bound: the time along the exact curve at the largest speed its curvature and
/// each axis's velocity, acceleration and jerk allow (normal terms at constant speed), with a
/// tangential acceleration within the smallest axis acceleration (forward and backward
/// passes), from rest to rest. A lower bound on any jerk-limited run.
fn bound_time(feed: f64) -> f64 {
    let m = 400_000;
    let dt = std::f64::consts::TAU / m as f64;
    // unit tangent T, curvature vector κN = (z'' − (z''·T)T)/|z'|² and |z'| at parameter t
    let frame = |t: f64| {
        let d1 = [
            -CA * t.sin() - CB * CK * (CK * t).sin(),
            CA * t.cos() + CB * CK * (CK * t).cos(),
        ];
        let d2 = [
            -CA * t.cos() - CB * CK * CK * (CK * t).cos(),
            -CA * t.sin() - CB * CK * CK * (CK * t).sin(),
        ];
        let sp = d1[0].hypot(d1[1]);
        let tan = [d1[0] / sp, d1[1] / sp];
        let dt2 = d2[0] * tan[0] + d2[1] * tan[1];
        let kn = [
            (d2[0] - dt2 * tan[0]) / (sp * sp),
            (d2[1] - dt2 * tan[1]) / (sp * sp),
        ];
        (tan, kn, sp)
    };
    let mut ds = vec![0.0; m];
    let mut cap = vec![0.0; m + 1];
    for i in 0..=m {
        let t = i as f64 * dt;
        let (tan, kn, sp) = frame(t);
        let mut c = feed;
        for a in 0..2 {
            if tan[a].abs() > 0.0 {
                c = c.min(V / tan[a].abs());
            }
            if kn[a].abs() > 0.0 {
                c = c.min((A / kn[a].abs()).sqrt());
            }
        }
        if i < m {
            // jerk at constant speed: v³·|d(κN)/ds|, by differences of κN along s
            let (_, k1, _) = frame(t + dt);
            for a in 0..2 {
                let dk = ((k1[a] - kn[a]) / (sp * dt)).abs();
                if dk > 0.0 {
                    c = c.min((J / dk).cbrt());
                }
            }
            ds[i] = sp * dt;
        }
        cap[i] = c;
    }
    cap[0] = 0.0;
    cap[m] = 0.0;
    for i in 0..m {
        cap[i + 1] = cap[i + 1].min((cap[i] * cap[i] + 2.0 * A * ds[i]).sqrt());
    }
    for i in (0..m).rev() {
        cap[i] = cap[i].min((cap[i + 1] * cap[i + 1] + 2.0 * A * ds[i]).sqrt());
    }
    (0..m)
        .map(|i| 2.0 * ds[i] / (cap[i] + cap[i + 1]).max(1e-9))
        .sum()
}

fn dense() {
    let lim = PathSettings::uniform(2, V, A, J);
    let (pts, chord_err) = dense_points(10_000);
    let len: f64 = pts
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    let bound = bound_time(V);
    // Baseline: the same card stepping at rest.
    let idle = {
        let card = Card::open_sim(SimOptions {
            clock: motioncard_sdk::Clock::Stepped,
            emu: Default::default(),
        })
        .unwrap();
        let _g = group(&card, &lim);
        let sim = card.sim().unwrap();
        let t = Instant::now();
        for _ in 0..20_000 {
            sim.step(1);
            let _ = cmd(&card);
        }
        t.elapsed().as_secs_f64() / 20_000.0
    };
    let m = run_polyline(&pts, V, 1.0, &lim);
    let per_seg = (m.step_secs - idle * m.ticks as f64) / 10_000.0;
    println!("\n| dense curve: 10,000 chords      | value |");
    println!("|---------------------------------|-------|");
    println!(
        "| length, chord error             | {:.1} mm, {:.3} µm |",
        len / 1000.0,
        chord_err
    );
    println!(
        "| path time / offline bound       | {:.4} s / {:.4} s = {:.3} |",
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
    println!(
        "| card time per segment (in-process, stepped, minus idle ticks) | {:.2} µs |",
        per_seg * 1e6
    );
}

fn open(uri: &str) -> Card {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match Card::open(uri) {
            Ok(c) => return c,
            Err(e)
                if e.kind() == motioncard_sdk::ErrorKind::NotFound && Instant::now() < deadline =>
            {
                std::thread::sleep(Duration::from_millis(10))
            }
            Err(e) => panic!("{e}"),
        }
    }
}

fn streaming() {
    let name = format!("bench-path-{}", std::process::id());
    let mut child = Process::new(env!("CARGO_BIN_EXE_card-emu"))
        .args(["--name", &name, "--servo-rate", "10000"])
        .stdout(Stdio::null())
        .spawn()
        .expect("card-emu");
    let card = open(&format!("emu:{name}"));
    // the braking distance from 150,000 counts/s (≈ 12,000 counts) is 1,200 segments: the
    // look-ahead must see that far
    let mut lim = PathSettings::uniform(2, 2e5, 2e6, 2e8);
    lim.lookahead = 2048;
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
    println!("\n| streaming across processes (card-emu at 10 kHz) | value |");
    println!("|--------------------------------------------------|-------|");
    println!("| segments streamed                                | {n} |");
    println!(
        "| accepted, average rate                           | {:.0} segments/s over {:.2} s |",
        n as f64 / sent,
        sent
    );
    println!("| path consumption (the path's own rate)           | {:.0} segments/s ({:.2} s to the end) |", n as f64 / total, total);
    println!("| starvation events                                | {starved} |");
    drop(card);
    let _ = child.kill();
    let _ = child.wait();
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
        .filter(|a| !a.starts_with("--"))
        .collect();
    let part = |name: &str| only.is_empty() || only.iter().any(|a| a == name);
    if part("corners") {
        corners();
    }
    if part("dense") {
        dense();
    }
    if part("streaming") {
        streaming();
    }
}
