//! Command round trip host → card → ack across two processes, and command throughput.
//!
//! Starts a `card-emu` process (real-time clock, busy-polling its command ring), opens it as
//! `emu:NAME` and prints a table:
//! - round trip of a no-op command: from queueing it to holding its ack (p50, p99, p99.9, max);
//! - commands per second, queued back to back and all acknowledged.
//!
//! `cargo bench -p card-emu --bench roundtrip`
use motioncard_sdk::proto::{Command, Opcode};
#[path = "common/procs.rs"]
mod procs;

use motioncard_sdk::ErrorKind;
use procs::{card_emu, open};
use std::time::{Duration, Instant};

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn run(busy_poll: bool) {
    let name = format!("bench-rt-{}-{busy_poll}", std::process::id());
    let _child = card_emu(&name, if busy_poll { &["--busy-poll"] } else { &[] });
    let card = open(&format!("emu:{name}"));
    for _ in 0..2000 {
        card.ping().unwrap();
    }
    let n = 20_000;
    let mut rt = Vec::with_capacity(n);
    for _ in 0..n {
        let t = Instant::now();
        card.ping().unwrap();
        rt.push(t.elapsed());
    }
    rt.sort();
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    println!(
        "| round trip, emulator {:<10} | {:>8} | {:>8.1} | {:>8.1} | {:>8.1} | {:>8.1} |",
        if busy_poll { "busy-poll" } else { "sleeping" },
        n,
        us(percentile(&rt, 0.5)),
        us(percentile(&rt, 0.99)),
        us(percentile(&rt, 0.999)),
        us(rt[n - 1])
    );

    // Throughput: queue no-ops back to back; when the ring is full, take the acks that have
    // arrived (as an application would) and go on. Ends when the last one is acknowledged.
    let total = 200_000u32;
    let t = Instant::now();
    let mut last = 0;
    let mut sent = 0;
    while sent < total {
        match card.send_raw(Command::new(Opcode::Nop, 0)) {
            Ok(seq) => {
                last = seq;
                sent += 1;
            }
            Err(e) if e.kind() == ErrorKind::RingFull => {
                card.poll_events().unwrap();
            }
            Err(e) => panic!("{e}"),
        }
        if sent % 128 == 0 {
            card.poll_events().unwrap();
        }
    }
    card.wait_ack(last).unwrap().unwrap();
    let secs = t.elapsed().as_secs_f64();
    println!(
        "| commands/s, emulator {:<10} | {:>8} | {:>8.0} commands/s, all acknowledged{:>17} |",
        if busy_poll { "busy-poll" } else { "sleeping" },
        total,
        total as f64 / secs,
        ""
    );
    drop(card);
}

fn main() {
    // `cargo test --benches` runs benches with --bench absent: keep that quick.
    if !std::env::args().any(|a| a == "--bench") {
        println!("roundtrip: skipped (run with `cargo bench`)");
        return;
    }
    println!(
        "| what                           |        n |  p50 µs  |  p99 µs  | p99.9 µs |  max µs  |"
    );
    println!(
        "|--------------------------------|----------|----------|----------|----------|----------|"
    );
    run(true);
    run(false);
}
