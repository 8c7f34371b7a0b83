//! Four `card-emu` processes on one sync bus at 10 kHz: how far apart their tick counters are.
//!
//! Starts a master and three followers (`--sync-from`), opens each as `emu:NAME`, and samples
//! their tick counters every millisecond for `SECONDS` (default 10; the figure is 600):
//! each sample reads the master, a follower, and the master again; when the master did not
//! tick in between, the follower's lag at the instant it was read is the master's tick minus
//! its own (a follower is never ahead: it runs a tick only after the master's, until it has
//! lost the master and runs on its own clock; and the master runs a tick only once every
//! follower has run the one before, so the lag is 0 or 1 unless a follower fell
//! `FOLLOWER_WAIT` behind). It
//! prints the lag's distribution and the drift: the lag at the end minus the lag at the
//! start, with every card stopped being read at the same tick count when the master is
//! stopped (SIGSTOP) and the followers have caught up.
//!
//! `SECONDS=600 cargo bench -p card-emu --bench sync_bus`
#[path = "common/procs.rs"]
mod procs;

use motioncard_sdk::Card;
use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;
use procs::{card_emu, open};
use std::time::{Duration, Instant};

fn main() {
    let seconds: u64 = std::env::var("SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let master = format!("bench-bus-{}", std::process::id());
    let mut procs = vec![card_emu(&master, &["--axes", "8"])];
    let names: Vec<String> = (0..3).map(|k| format!("{master}-f{k}")).collect();
    for n in &names {
        procs.push(card_emu(n, &["--axes", "8", "--sync-from", &master]));
    }
    let m = open(&format!("emu:{master}"));
    let followers: Vec<Card> = names.iter().map(|n| open(&format!("emu:{n}"))).collect();
    let mut hist = [0u64; 6]; // lag 0, 1, 2, 3, 4..9, 10+
    let mut max = 0u64;
    let mut samples = 0u64;
    let t0 = Instant::now();
    let first = m.tick().unwrap();
    let mut stale = 0u64;
    let mut ahead = 0u64;
    let mut moved = 0u64;
    let mut moved_max = 0u64;
    while t0.elapsed() < Duration::from_secs(seconds) {
        for c in &followers {
            // The master read before and after the follower: when it did not tick in between,
            // the difference is the one at the instant the follower was read (else the lag
            // then lies between the two differences, and the sample is counted apart).
            // A card whose tick stood for the SDK's staleness limit (an OS stall of its process
            // on a loaded machine) is counted, not sampled.
            let (Ok(m1), Ok(t), Ok(m2)) = (m.tick(), c.tick(), m.tick()) else {
                stale += 1;
                continue;
            };
            if t > m2 {
                // Only after a loss: the follower runs on its own clock.
                ahead += 1;
                continue;
            }
            if m1 != m2 {
                moved += 1;
                moved_max = moved_max.max(m2 - t);
                continue;
            }
            let lag = m1 - t;
            max = max.max(lag);
            hist[match lag {
                0..=3 => lag as usize,
                4..=9 => 4,
                _ => 5,
            }] += 1;
            samples += 1;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let ticks = m.tick().unwrap() - first;
    // Drift: stop the master, let the followers catch up, read everyone.
    kill(Pid::from_raw(procs[0].0.id() as i32), Signal::SIGSTOP).unwrap();
    std::thread::sleep(Duration::from_millis(20));
    let end_m = m.tick().unwrap();
    let ends: Vec<u64> = followers.iter().map(|c| c.tick().unwrap()).collect();
    kill(Pid::from_raw(procs[0].0.id() as i32), Signal::SIGCONT).unwrap();
    println!("4 card-emu processes at 10 kHz on one sync bus, {seconds} s ({ticks} master ticks)");
    println!("| lag (ticks) | samples | share |");
    println!("|---|---|---|");
    for (label, n) in ["0", "1", "2", "3", "4-9", ">=10"].iter().zip(hist) {
        println!(
            "| {label} | {n} | {:.4} % |",
            100.0 * n as f64 / samples as f64
        );
    }
    println!(
        "largest lag: {max} ticks over {samples} samples ({stale} samples found a card stale, \
         {ahead} a follower ahead: after a loss)"
    );
    println!(
        "{moved} more samples saw the master tick while the follower was read (lag at most \
         {moved_max} there)"
    );
    let losses: Vec<u32> = followers
        .iter()
        .map(|c| c.bus_status().map_or(u32::MAX, |s| s.losses))
        .collect();
    println!("master losses per follower: {losses:?}");
    let drift: Vec<i64> = ends.iter().map(|&e| end_m as i64 - e as i64).collect();
    println!("drift (master stopped, followers caught up: master - follower): {drift:?}");
}
