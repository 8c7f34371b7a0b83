//! CAM programs on the stepped emulated card, measured as `mcctl run` measures them (every
//! servo tick's commanded position: path time, each axis's peak velocity, acceleration and
//! jerk against its limit, the largest deviation from the program), at the settings of issue
//! 32: tolerance 0.01 mm, every axis 100 mm/s, 1000 mm/s², 10⁵ mm/s³, feed limit 100 mm/s.
//!
//! ```text
//! cargo bench --bench cam                      # the table
//! cargo bench --bench cam -- --corpus DIR      # and every .ngc under DIR (the programs the
//!                                              # reader refuses are counted, not run)
//! ```
//!
//! The rows: a circle of 1-inch radius as 10,000 chords (full precision, and rounded to 4
//! decimals in inches as CAM posts them) against the same circle as one G2; the G2 against its
//! time-optimal bound (below); one G1 of 25.4 mm against the axis's own S-curve
//! (`Profile::plan`, as `mcctl plan`); 1,000 collinear pieces of it against the G1, fitted
//! (the default) and sent one by one (`--no-chord-fit`); a 3-axis surface finishing raster
//! (mm rounded to 3 decimals, 0.2 mm chords, 20 passes) against the same passes sent as
//! curves of the surface itself.
//!
//! The bound of a circle: the time-optimal traversal with each axis's velocity and
//! acceleration limits (|a_t·T_k + v²·K_k| ≤ amax_k, signs kept, and the feed) along the
//! circle, from rest to rest, by the phase-plane method (the fastest speed at every point from
//! the forward pass at the most tangential acceleration and the backward pass at the most
//! deceleration, on 200,000 steps). It leaves the jerk limits out, so it is below any
//! jerk-limited motion's time: a lower bound.

use mcctl::run::{run, RunOptions};
use motioncard_sdk::plan::{Limits, Profile};
use motioncard_sdk::{
    Card, Clock, GroupSettings, GroupState, Nurbs, PathItem, PathSettings, Segment, SimOptions,
};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

const TOL: f64 = 0.01;
const V: f64 = 100.0;
const A: f64 = 1000.0;
const J: f64 = 100_000.0;
/// The card's servo period (its default rate, 10 kHz).
const TS: f64 = 1e-4;

fn stepped() -> Card {
    Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        ..Default::default()
    })
    .expect("a stepped sim card")
}

fn opts(chord_fit: bool) -> RunOptions {
    RunOptions {
        tolerance: TOL,
        feed_limit: V,
        vmax: [V; 3],
        amax: [A; 3],
        jmax: [J; 3],
        scale: 1000.0,
        progress: false,
        chord_fit,
        ..RunOptions::default()
    }
}

/// `mcctl run --json` of `text` on a fresh stepped card.
fn run_text(name: &str, text: &str, chord_fit: bool) -> Value {
    let path = std::env::temp_dir().join(format!("cam-bench-{}-{name}.ngc", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let r = run_file(&path, chord_fit);
    let _ = std::fs::remove_file(&path);
    r.unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run_file(path: &Path, chord_fit: bool) -> Result<Value, String> {
    let card = stepped();
    let out = run(&card, path, &opts(chord_fit), true).map_err(|e| e.to_string())?;
    serde_json::from_str(&out).map_err(|e| e.to_string())
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or(f64::NAN)
}

/// A circle of radius `r` mm about (r, 0) from the origin, counter-clockwise: `n` chords (G1)
/// with `decimals` in inches (None: full precision), or one G2.
fn circle(r_in: f64, n: usize, decimals: Option<usize>) -> String {
    let mut s = String::from("G20 G90 G17\nF236.2205\nG1 X0 Y0\n");
    if n == 0 {
        s += &format!("G3 X0 Y0 I{r_in:.6} J0\n");
    }
    for i in 1..=n {
        let t = std::f64::consts::TAU * i as f64 / n as f64;
        let (x, y) = (r_in - r_in * t.cos(), -r_in * t.sin());
        s += &match decimals {
            Some(d) => format!("G1 X{x:.d$} Y{y:.d$}\n"),
            None => format!("G1 X{x:.12} Y{y:.12}\n"),
        };
    }
    s + "M2\n"
}

/// The time-optimal bound of a circle of radius `r` (see the module doc).
fn circle_bound(r: f64) -> f64 {
    let n = 200_000usize;
    let len = std::f64::consts::TAU * r;
    let ds = len / n as f64;
    // at arc length s from the start, the point at angle π about the centre (r, 0):
    // the unit tangent and the curvature vector
    let frame = |s: f64| {
        let th = std::f64::consts::PI + s / r;
        ([-th.sin(), th.cos()], [-th.cos() / r, -th.sin() / r])
    };
    // the fastest speed with no tangential acceleration, and the tangential range at (s, v)
    let vcap = |s: f64| {
        let (t, k) = frame(s);
        let mut v = V;
        for a in 0..2 {
            if t[a].abs() > 0.0 {
                v = v.min(V / t[a].abs());
            }
            if k[a].abs() > 0.0 {
                v = v.min((A / k[a].abs()).sqrt());
            }
        }
        v
    };
    let range = |s: f64, v: f64| {
        let (t, k) = frame(s);
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for a in 0..2 {
            let c = v * v * k[a];
            if t[a].abs() < 1e-15 {
                continue;
            }
            let (b1, b2) = ((-A - c) / t[a], (A - c) / t[a]);
            lo = lo.max(b1.min(b2));
            hi = hi.min(b1.max(b2));
        }
        (lo, hi)
    };
    let mut fwd = vec![0.0f64; n + 1];
    for i in 0..n {
        let v = fwd[i];
        let (_, hi) = range(i as f64 * ds, v);
        let v2 = (v * v + 2.0 * hi.max(0.0) * ds).sqrt();
        fwd[i + 1] = v2.min(vcap((i + 1) as f64 * ds));
    }
    let mut bwd = vec![0.0f64; n + 1];
    for i in (0..n).rev() {
        let v = bwd[i + 1];
        let (lo, _) = range((i + 1) as f64 * ds, v);
        let v2 = (v * v + 2.0 * (-lo).max(0.0) * ds).sqrt();
        bwd[i] = v2.min(vcap(i as f64 * ds));
    }
    let v: Vec<f64> = fwd.iter().zip(&bwd).map(|(a, b)| a.min(*b)).collect();
    (0..n).map(|i| 2.0 * ds / (v[i] + v[i + 1])).sum()
}

/// The raster's surface, mm.
fn surface(x: f64, y: f64) -> f64 {
    3.0 * (x / 8.0).sin() * (y / 10.0).cos() + 0.5 * (x / 3.0).cos()
}
const RASTER_LEN: f64 = 60.0;
const RASTER_PASSES: usize = 20;
const RASTER_STEP: f64 = 1.0;

/// A zig-zag finishing raster of the surface: passes along X, 0.2 mm chords, mm rounded to 3
/// decimals, a stepover of 1 mm along Y between passes.
fn raster_gcode() -> String {
    let q = |x: f64| (x * 1e3).round() / 1e3;
    let mut s = String::from("G21 G90 G17\nF6000\n");
    s += &format!("G1 X0 Y0 Z{:.3}\n", q(surface(0.0, 0.0)));
    let n = (RASTER_LEN / 0.2).round() as usize;
    for p in 0..RASTER_PASSES {
        let y = p as f64 * RASTER_STEP;
        for i in 1..=n {
            let t = i as f64 / n as f64;
            let x = if p % 2 == 0 { t } else { 1.0 - t } * RASTER_LEN;
            s += &format!("G1 X{:.3} Y{:.3} Z{:.3}\n", q(x), q(y), q(surface(x, y)));
        }
        if p + 1 < RASTER_PASSES {
            let x = if p % 2 == 0 { RASTER_LEN } else { 0.0 };
            let y2 = y + RASTER_STEP;
            s += &format!("G1 X{:.3} Y{:.3} Z{:.3}\n", q(x), q(y2), q(surface(x, y2)));
        }
    }
    s + "M2\n"
}

/// The same raster with each pass a curve of the surface itself (a cubic B-spline through
/// it, a quasi-interpolant on 240 spans, within a micrometre of it) and the same stepovers:
/// its path time on a stepped card.
fn raster_exact_time() -> f64 {
    let card = stepped();
    for a in 0..3 {
        let x = card.axis(a).unwrap();
        x.set_scale(1000.0).unwrap();
        x.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        tolerance: 1e-3,
        ..GroupSettings::new(&[0, 1, 2])
    })
    .unwrap();
    g.enable().unwrap();
    g.configure_path(&PathSettings {
        chord_fit: false,
        ..PathSettings::uniform(3, V, A, J)
    })
    .unwrap();
    let mut items: Vec<PathItem> = vec![Segment::line(1, &[0.0, 0.0, surface(0.0, 0.0)], V, TOL)
        .buffer(motioncard_sdk::PathBuffer::Buffered)
        .into()];
    // uniform cubic B-spline quasi-interpolant: control points f − h²f''/6 at the knots
    let spans = 240usize;
    let h = RASTER_LEN / spans as f64;
    for p in 0..RASTER_PASSES {
        let y = p as f64 * RASTER_STEP;
        let mut ctrl = vec![];
        // clamped: the end control points are the ends, the next ones set the end tangents
        let n_ctrl = spans + 3;
        for c in 0..n_ctrl {
            // Greville abscissae of a clamped uniform cubic knot vector
            let g = match c {
                0 => 0.0,
                1 => h / 3.0,
                _ if c == n_ctrl - 2 => RASTER_LEN - h / 3.0,
                _ if c == n_ctrl - 1 => RASTER_LEN,
                _ => (c as f64 - 1.0) * h,
            };
            let x = if p % 2 == 0 { g } else { RASTER_LEN - g };
            let dd = {
                let e = 1e-3;
                (surface(x + e, y) - 2.0 * surface(x, y) + surface(x - e, y)) / (e * e)
            };
            let corr = if c == 0 || c == n_ctrl - 1 {
                0.0
            } else {
                h * h / 6.0
            };
            ctrl.extend([x, y, surface(x, y) - corr * dd]);
        }
        let knots = motioncard_sdk::clamped_uniform_knots(n_ctrl, 3).unwrap();
        let curve = Nurbs::new(3, 3, &ctrl, &vec![1.0; n_ctrl], &knots).unwrap();
        items.push(Segment::nurbs(2 + 2 * p as u32, curve, V, TOL, 1e-4).into());
        if p + 1 < RASTER_PASSES {
            let x = if p % 2 == 0 { RASTER_LEN } else { 0.0 };
            let y2 = y + RASTER_STEP;
            items.push(Segment::line(3 + 2 * p as u32, &[x, y2, surface(x, y2)], V, TOL).into());
        }
    }
    if let Some(PathItem::Segment(s)) = items.last_mut() {
        s.last = true;
    }
    let sim = card.sim().unwrap();
    // the first point at rest, then the raster, timed from its first moving tick
    let first = items.remove(0);
    g.path_push(&first)
        .unwrap()
        .wait(Duration::from_secs(60))
        .unwrap();
    g.stream_path(items, |_| {}).unwrap();
    let mut ticks = 0u64;
    let mut moving_from = None;
    let p0 = g.status().unwrap().1.path_done;
    loop {
        sim.step(1);
        ticks += 1;
        let st = g.status().unwrap();
        if moving_from.is_none() && (st.1.path_done != p0 || st.1.path_flags != 0) {
            moving_from = Some(ticks - 1);
        }
        if st.0 == GroupState::Standby && st.1.path_queued == 0 {
            break;
        }
    }
    (ticks - moving_from.unwrap_or(0)) as f64 / card.info().servo_rate_hz as f64
}

fn corpus(dir: &Path) {
    let mut files = vec![];
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("ngc")) {
                files.push(p);
            }
        }
    }
    // (a directory reached twice through a symbolic link is run once)
    files.sort_by_key(|p| std::fs::canonicalize(p).unwrap_or_else(|_| p.clone()));
    files.dedup_by_key(|p| std::fs::canonicalize(&*p).unwrap_or_else(|_| p.clone()));
    files.sort();
    let (mut refused, mut stripped, mut ran) = (0, 0, 0);
    let mut over: Vec<(PathBuf, String)> = vec![];
    let mut ratios = vec![];
    let tmp = std::env::temp_dir().join(format!("cam-bench-{}-corpus.ngc", std::process::id()));
    for p in &files {
        // The lines the reader refuses are left out (as many as it takes, up to a tenth of
        // the program): what is left is a program of the reader's G-code.
        let mut lines: Vec<String> = std::fs::read_to_string(p)
            .unwrap_or_default()
            .lines()
            .map(String::from)
            .collect();
        let most = lines.len() / 10 + 1;
        let mut cut = 0;
        let prog = loop {
            match motioncard_sdk::report::parse(&lines.join("\n")) {
                Ok(prog) => break Some(prog),
                Err(e) if cut < most && e.line >= 1 && e.line <= lines.len() => {
                    lines[e.line - 1] = String::new();
                    cut += 1;
                }
                Err(_) => break None,
            }
        };
        let Some(prog) = prog.filter(|p| p.motion_count() > 0) else {
            refused += 1;
            continue;
        };
        stripped += usize::from(cut > 0);
        std::fs::write(&tmp, lines.join("\n") + "\n").unwrap();
        let t = std::time::Instant::now();
        let r = run_file(&tmp, true);
        eprintln!("{}: {:.1} s", p.display(), t.elapsed().as_secs_f64());
        let r = match r {
            Ok(r) => r,
            Err(e) => {
                over.push((p.clone(), format!("failed: {e}")));
                continue;
            }
        };
        ran += 1;
        // The rounding floor of the jerk measured: a third difference of f64 positions
        // carries up to 8 units in the last place of the largest coordinate, over ts³ (at
        // 10 kHz and 200 mm, 2.3e-6 of 1e5 mm/s³); a profile at its jerk limit reads that much
        // over it.
        let far = prog
            .blocks
            .iter()
            .filter_map(|b| b.end())
            .flatten()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let jerk_floor = 8.0 * f64::EPSILON * far / (TS * TS * TS * J);
        for k in ["peak_vel_ratio", "peak_accel_ratio", "peak_jerk_ratio"] {
            let floor = if k == "peak_jerk_ratio" {
                jerk_floor
            } else {
                0.0
            };
            if f(&r, k) > 1.0 + 1e-6 + floor {
                over.push((p.clone(), format!("{k} 1 + {:.1e}", f(&r, k) - 1.0)));
            }
        }
        if f(&r, "max_deviation") > TOL * (1.0 + 1e-6) {
            over.push((
                p.clone(),
                format!("deviation {:.5} mm", f(&r, "max_deviation")),
            ));
        }
        // the feed-only bound: every block at its feed (the program's, within the limit)
        let bound: f64 = prog
            .blocks
            .iter()
            .filter_map(|b| Some(b.length() / b.feed()?.min(V)))
            .sum();
        if bound > 0.0 {
            ratios.push(f(&r, "path_time") / bound);
        }
    }
    let _ = std::fs::remove_file(&tmp);
    ratios.sort_by(f64::total_cmp);
    let q = |x: f64| {
        ratios
            .get(((ratios.len() as f64 - 1.0) * x).round() as usize)
            .copied()
    };
    println!(
        "\ncorpus {}: {} programs, {} left out (no motion the reader takes within a tenth of \
         their lines), {} ran ({} of them without the lines the reader refuses); path time \
         against the feed-only bound: median {:.2}, p90 {:.2}",
        dir.display(),
        files.len(),
        refused,
        ran,
        stripped,
        q(0.5).unwrap_or(f64::NAN),
        q(0.9).unwrap_or(f64::NAN)
    );
    for (p, why) in &over {
        println!("  over a limit or failed: {} ({why})", p.display());
    }
    if over.is_empty() {
        println!("  every limit and the tolerance held on every program that ran");
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let corpus_dir = args
        .iter()
        .position(|a| a == "--corpus")
        .and_then(|i| args.get(i + 1));
    // (cargo bench passes --bench)
    let row = |what: &str, figure: String| println!("| {what} | {figure} |");
    println!("| what | figure |\n|---|---|");
    let limits = |r: &Value| {
        format!(
            "peak v, a, j {:.4}, {:.4}, {:.4} of the limits, deviation {:.4} mm",
            f(r, "peak_vel_ratio"),
            f(r, "peak_accel_ratio"),
            f(r, "peak_jerk_ratio"),
            f(r, "max_deviation")
        )
    };
    let arc = run_text("arc", &circle(1.0, 0, None), true);
    let t_arc = f(&arc, "path_time");
    let bound = circle_bound(25.4);
    row(
        "G2 circle, 1-inch radius, at 100 mm/s",
        format!(
            "{t_arc:.4} s; time-optimal bound {bound:.4} s: **{:.3}×**; {}",
            t_arc / bound,
            limits(&arc)
        ),
    );
    for (what, dec) in [("full precision", None), ("4 decimals in inches", Some(4))] {
        let r = run_text("chords", &circle(1.0, 10_000, dec), true);
        let t = f(&r, "path_time");
        row(
            &format!("the circle as 10,000 chords, {what}"),
            format!("{t:.4} s: **{:.3}×** the G2; {}", t / t_arc, limits(&r)),
        );
    }
    let g1 = run_text("g1", "G21 G90\nF6000\nG1 X25.4\nM2\n", true);
    let t_g1 = f(&g1, "path_time");
    let lim = Limits {
        vmax: 100_000.0,
        amax: 1e6,
        dmax: 1e6,
        j1: 1e8,
        j3: 1e8,
        j5: 1e8,
        j7: 1e8,
    };
    let scurve = Profile::plan(0.0, 25_400.0, 0.0, 0.0, &lim)
        .unwrap()
        .duration();
    row(
        "one G1 of 25.4 mm",
        format!(
            "{t_g1:.4} s; the axis's S-curve {scurve:.4} s: **{:.3}×**; {}",
            t_g1 / scurve,
            limits(&g1)
        ),
    );
    let pieces: String = (1..=1000)
        .map(|i| format!("G1 X{:.6}\n", 25.4 * i as f64 / 1000.0))
        .collect();
    let text = format!("G21 G90\nF6000\n{pieces}M2\n");
    for (what, fit) in [("fitted (the default)", true), ("one by one", false)] {
        let r = run_text("pieces", &text, fit);
        let t = f(&r, "path_time");
        row(
            &format!("1,000 collinear pieces of it, {what}"),
            format!("{t:.4} s: **{:.3}×** the G1; {}", t / t_g1, limits(&r)),
        );
    }
    let raster = run_text("raster", &raster_gcode(), true);
    let t_raster = f(&raster, "path_time");
    let t_exact = raster_exact_time();
    row(
        "3-axis finishing raster, 20 passes of 60 mm, 0.2 mm chords, mm to 3 decimals",
        format!(
            "{t_raster:.4} s; the same passes as curves of the surface {t_exact:.4} s: \
             **{:.3}×**; {}",
            t_raster / t_exact,
            limits(&raster)
        ),
    );
    let raster_chords = run_text("raster-chords", &raster_gcode(), false);
    row(
        "... the raster sent one chord at a time (--no-chord-fit)",
        format!(
            "{:.4} s; {}",
            f(&raster_chords, "path_time"),
            limits(&raster_chords)
        ),
    );
    if let Some(d) = corpus_dir {
        corpus(Path::new(d));
    }
}
