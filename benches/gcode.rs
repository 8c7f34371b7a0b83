//! The G-code front end's speed: the interpreter's throughput on a 100,000-block CAM program
//! (blocks a second, read from a file and from memory, best of 5), and the time from
//! `mcctl run` starting to the card's first motion on the same program (its whole text
//! checked first, the group set up, the first batch sent; the in-process stepped card).
//!
//! ```text
//! cargo bench --bench gcode
//! ```
//!
//! The program: a 3-axis surface finishing raster as CAM posts it (line numbers, 3 decimals,
//! modal G1 and F, a comment every pass, an arc to the next pass), in 100,000 blocks.

use motioncard_sdk::gcode::{Options, Program};
use std::time::Instant;

/// Blocks of the program.
const BLOCKS: usize = 100_000;
/// Chords a pass.
const PER_PASS: usize = 500;

fn cam_program() -> String {
    let mut s = String::from("%\n(raster, 100000 blocks)\nG21 G90 G17 G64 P0.01\nG0 Z5\n");
    s += "G0 X0 Y0\nG1 Z0 F1200\n";
    let mut n = 5;
    let mut pass = 0;
    while n < BLOCKS - 2 {
        let y = pass as f64 * 0.5;
        s += &format!("(pass {pass})\n");
        for i in 1..=PER_PASS {
            let t = i as f64 / PER_PASS as f64;
            let x = if pass % 2 == 0 { t } else { 1.0 - t } * 100.0;
            let z = 0.5 * (x * 0.1).sin() * (y * 0.2).cos();
            s += &format!("N{n} G1 X{x:.3} Y{y:.3} Z{z:.3} F3000\n");
            n += 1;
        }
        // a half circle of radius 0.25 to the next pass
        let (x, c) = if pass % 2 == 0 {
            (100.0, "G3")
        } else {
            (0.0, "G2")
        };
        s += &format!("N{n} {c} X{x:.3} Y{:.3} J0.25\n", y + 0.5);
        n += 1;
        pass += 1;
    }
    s + "G0 Z5\nM2\n%\n"
}

fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..n {
        let t0 = Instant::now();
        let r = f();
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("n > 0"))
}

fn count(
    p: impl Iterator<Item = Result<motioncard_sdk::gcode::Op, motioncard_sdk::gcode::GcodeError>>,
) -> usize {
    let mut n = 0;
    for op in p {
        op.expect("the benchmark program reads");
        n += 1;
    }
    n
}

fn main() {
    // `cargo bench` passes --bench; nothing else is taken.
    let text = cam_program();
    let blocks = text.lines().count();
    let dir = std::env::temp_dir().join(format!("gcode-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("raster.ngc");
    std::fs::write(&file, &text).expect("write the program");

    let opts = Options::default();
    let (t_file, ops) = best_of(5, || count(Program::open(&file, &opts).expect("open")));
    let (t_text, _) = best_of(5, || count(Program::from_text(text.clone(), &opts)));

    // mcctl run, as a process: the report's first_motion_ms.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mcctl"))
        .args(["run", file.to_str().expect("utf-8 path"), "--json"])
        .output()
        .expect("mcctl runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let first = j["first_motion_ms"].as_f64().expect("first_motion_ms");

    println!("| figure | value |");
    println!("|---|---|");
    println!(
        "| interpreter, {blocks} lines ({ops} operations) from a file | {:.0} blocks/s ({:.1} ms) |",
        blocks as f64 / t_file,
        t_file * 1e3
    );
    println!(
        "| the same from memory | {:.0} blocks/s ({:.1} ms) |",
        blocks as f64 / t_text,
        t_text * 1e3
    );
    println!(
        "| `mcctl run` to the first motion (the program checked whole first) | {first:.1} ms |"
    );
    println!(
        "| the run: path time {:.2} s, deviation {:.4} mm, peak v/a/j {:.3} {:.3} {:.3} | |",
        j["path_time"].as_f64().unwrap_or(f64::NAN),
        j["max_deviation"].as_f64().unwrap_or(f64::NAN),
        j["peak_vel_ratio"].as_f64().unwrap_or(f64::NAN),
        j["peak_accel_ratio"].as_f64().unwrap_or(f64::NAN),
        j["peak_jerk_ratio"].as_f64().unwrap_or(f64::NAN),
    );
    std::fs::remove_dir_all(&dir).ok();
}
