//! How late is the host's heartbeat on a loaded, non-real-time host? The figure the card's
//! default watchdog timeout is chosen from.
//!
//! Under CPU load (2 × the cores spinning, as `stress --cpu` does), for each scheduling policy
//! (SCHED_OTHER: what an unprivileged process gets; SCHED_FIFO 10: what the SDK asks for):
//! - the gaps of a loop that does what the heartbeat thread does (sleep half a period, beat),
//!   as a distribution (p50 … p99.99, max) of the gap beyond the nominal half period;
//! - what the card saw of the SDK's real heartbeat over the same run (a real-time `sim` card
//!   kept open): heartbeats later than the declared period, and the longest gap.
//!
//! `cargo bench -p motioncard-sdk --bench heartbeat` (MC_BENCH_SECS sets the seconds per run,
//! default 30).
use motioncard_sdk::{Card, HEARTBEAT_PERIOD_US};
use nix::libc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

fn set_policy(fifo: bool) -> bool {
    let param = libc::sched_param {
        sched_priority: if fifo { 10 } else { 0 },
    };
    let policy = if fifo {
        libc::SCHED_FIFO
    } else {
        libc::SCHED_OTHER
    };
    // SAFETY: pthread_self() is the calling thread; `param` is valid for the call.
    unsafe { libc::pthread_setschedparam(libc::pthread_self(), policy, &param) == 0 }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn main() {
    let secs: u64 = std::env::var("MC_BENCH_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(30);
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    println!(
        "heartbeat lateness under load: {} spinning threads on {cores} cores, {secs} s per run",
        2 * cores
    );
    println!(
        "{:<12} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9}   card: late beats, longest gap",
        "policy", "p50", "p99", "p99.9", "p99.99", "max", "samples"
    );
    for fifo in [false, true] {
        let stop = Arc::new(AtomicBool::new(false));
        let load: Vec<_> = (0..2 * cores)
            .map(|_| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let mut x = 0u64;
                    while !stop.load(Ordering::Relaxed) {
                        x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
                        std::hint::black_box(x);
                    }
                })
            })
            .collect();
        // The SDK's real heartbeat, seen by a card (its thread asks for SCHED_FIFO itself;
        // for the SCHED_OTHER run this process must not be allowed to: run as non-root, or
        // read the replica's figures).
        let card = Card::open("sim").expect("open sim");
        let half = Duration::from_micros(HEARTBEAT_PERIOD_US as u64 / 2);
        let replica = std::thread::spawn(move || {
            let got = set_policy(fifo);
            let mut gaps = Vec::with_capacity((secs * 2100) as usize);
            let end = Instant::now() + Duration::from_secs(secs);
            let mut last = Instant::now();
            while last < end {
                std::thread::sleep(half);
                let now = Instant::now();
                gaps.push((now - last).saturating_sub(half).as_secs_f64() * 1e6);
                last = now;
            }
            (got, gaps)
        });
        let (got, mut gaps) = replica.join().unwrap();
        let st = card.safety_status().expect("safety status");
        stop.store(true, Ordering::Relaxed);
        for t in load {
            t.join().unwrap();
        }
        gaps.sort_by(|a, b| a.total_cmp(b));
        let name = match (fifo, got) {
            (false, _) => "SCHED_OTHER",
            (true, true) => "SCHED_FIFO",
            (true, false) => "FIFO denied",
        };
        println!(
            "{name:<12} {:>7.0}us {:>7.0}us {:>7.0}us {:>7.0}us {:>8.0}us {:>9}   {}, {:?}",
            percentile(&gaps, 0.5),
            percentile(&gaps, 0.99),
            percentile(&gaps, 0.999),
            percentile(&gaps, 0.9999),
            gaps.last().copied().unwrap_or(0.0),
            gaps.len(),
            st.late_heartbeats,
            st.max_heartbeat_gap,
        );
    }
}
