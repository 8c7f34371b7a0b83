//! PT/PVT streaming rate (layout 1.7): points accepted per second.
//!
//! - in-process: a stepped `sim` card, 4,096 points (the whole buffer) pushed four to a
//!   command, each command waited for; repeated, the median printed.
//! - across processes: a `card-emu` process at 10 kHz (real time) runs a 10 s PVT stream of a
//!   point per servo tick (100,000 points, a cosine of 2,000 counts), refilled from this
//!   process whenever 1,024 or more points are free; the rate at which the card accepted them
//!   and the starvation events; the card sleeping between ticks, then busy-polling its
//!   command ring (`--busy-poll`).
//!
//! `cargo bench -p card-emu --bench pvt_stream [-- local|remote]`
#[path = "common/procs.rs"]
mod procs;

use motioncard_sdk::{
    Card, EmuOptions, EventKind, PvtEvent, PvtLimits, PvtMode, PvtPoint, SimOptions, PVT_LEN,
};
use procs::{card_emu, open};
use std::f64::consts::PI;
use std::time::{Duration, Instant};

const RATE: f64 = 10_000.0;

/// Point k (1-based) of 2,000 (1 − cos πt) counts at one point per tick; the last at rest.
fn point(k: usize, n: usize) -> PvtPoint {
    let t = k as f64 / RATE;
    let v = if k == n {
        0.0
    } else {
        2_000.0 * PI * (PI * t).sin()
    };
    PvtPoint::new(t, 2_000.0 * (1.0 - (PI * t).cos()), v)
}

fn limits() -> PvtLimits {
    PvtLimits {
        velocity: 1e4,
        acceleration: 1e5,
    }
}

fn local() {
    let card = Card::open_sim(SimOptions {
        clock: motioncard_sdk::Clock::Stepped,
        emu: EmuOptions::new(1, RATE as u32),
    })
    .unwrap();
    let x = card.axis(0).unwrap();
    x.enable().unwrap();
    let pts: Vec<PvtPoint> = (1..=PVT_LEN).map(|k| point(k, usize::MAX)).collect();
    let mut rates: Vec<f64> = (0..20)
        .map(|_| {
            x.pvt_begin(PvtMode::Pvt, &limits(), 0).unwrap();
            let t = Instant::now();
            x.pvt_push(&pts, false).unwrap();
            PVT_LEN as f64 / t.elapsed().as_secs_f64()
        })
        .collect();
    rates.sort_by(f64::total_cmp);
    println!(
        "| points accepted in-process (stepped sim, 4 a command) | median {:.0} points/s (min {:.0}, max {:.0}) |",
        rates[10], rates[0], rates[19]
    );
}

fn remote(busy_poll: bool) {
    let name = format!("bench-pvt-{}-{busy_poll}", std::process::id());
    let mut args = vec!["--servo-rate", "10000"];
    if busy_poll {
        args.push("--busy-poll");
    }
    let _child = card_emu(&name, &args);
    let card = open(&format!("emu:{name}"));
    let x = card.axis(0).unwrap();
    x.enable().unwrap();
    let n = 100_000;
    let pts: Vec<PvtPoint> = (1..=n).map(|k| point(k, n)).collect();
    x.pvt_begin(PvtMode::Pvt, &limits(), 0).unwrap();
    let t0 = Instant::now();
    let mut sent = PVT_LEN;
    x.pvt_push(&pts[..sent], false).unwrap();
    let burst = sent as f64 / t0.elapsed().as_secs_f64();
    let m = x.pvt_start().unwrap();
    let (mut starved, mut busy) = (0, Duration::ZERO);
    while sent < n {
        let free = x.pvt_free();
        if free >= 1_024 {
            let take = free.min(n - sent);
            let t = Instant::now();
            x.pvt_push(&pts[sent..sent + take], sent + take == n)
                .unwrap();
            busy += t.elapsed();
            sent += take;
        } else {
            std::thread::sleep(Duration::from_millis(5));
        }
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            starved += (e.kind == EventKind::Pvt && e.code == PvtEvent::Starved as i32) as usize;
        }
    }
    let done = m.wait(Duration::from_secs(60));
    let total = t0.elapsed().as_secs_f64();
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        starved += (e.kind == EventKind::Pvt && e.code == PvtEvent::Starved as i32) as usize;
    }
    println!(
        "| across processes (card-emu at 10 kHz, real time{}): first {PVT_LEN} points | {burst:.0} points/s accepted |",
        if busy_poll { ", --busy-poll" } else { "" }
    );
    println!(
        "| the refills ({} points while the stream ran) | {:.0} points/s while pushing; the stream of {n} points (10 s) ended in {total:.2} s, {:?}; {starved} starvation events |",
        n - PVT_LEN,
        (n - PVT_LEN) as f64 / busy.as_secs_f64(),
        done.map(|_| "done")
    );
    drop(card);
}

fn main() {
    if !std::env::args().any(|a| a == "--bench") {
        println!("pvt_stream: skipped (run with `cargo bench`)");
        return;
    }
    let only = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    if only.as_deref().is_none_or(|o| o == "local") {
        local();
    }
    if only.as_deref().is_none_or(|o| o == "remote") {
        remote(false);
        remote(true);
    }
}
