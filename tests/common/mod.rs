//! Helpers shared by the end-to-end tests.
#![allow(dead_code)]

use motioncard_sdk::plan::{Limits, Profile};
use motioncard_sdk::{
    Card, Clock, EmuOptions, Group, GroupSettings, PathLimits, PathSettings, SimOptions,
};

/// A stepped card with group 0 over X, Y, Z in mm (1000 counts a mm; 100 mm/s, 1000 mm/s²,
/// 10⁵ mm/s³), enabled, its path configured.
pub fn xyz_card() -> (Card, Group) {
    let card = stepped_card();
    for a in 0..3 {
        let axis = card.axis(a).unwrap();
        axis.set_scale(1000.0).unwrap();
        axis.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1, 2])).unwrap();
    g.enable().unwrap();
    g.configure_path(&PathSettings::uniform(3, 100.0, 1000.0, 1e5))
        .unwrap();
    (card, g)
}

/// A stepped emulated card: deterministic on any machine.
pub fn stepped_card() -> Card {
    stepped_card_with(EmuOptions::default())
}

/// A stepped emulated card with explicit options.
pub fn stepped_card_with(emu: EmuOptions) -> Card {
    Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })
    .expect("open stepped sim")
}

/// The seeded generator every test shares (card-emu's testkit): the same numbers on every
/// machine. (Like every helper here, not every test file uses it.)
#[allow(unused_imports)]
pub use card_emu::testkit::rng::Rng;

/// Duration of a rest-to-rest move of `distance` within `l` alone (the card's planner, one
/// jerk for every phase).
pub fn rest_to_rest_time(l: &PathLimits, distance: f64) -> f64 {
    let lim = Limits {
        vmax: l.velocity,
        amax: l.acceleration,
        dmax: l.deceleration,
        j1: l.jerk,
        j3: l.jerk,
        j5: l.jerk,
        j7: l.jerk,
    };
    Profile::plan(0.0, distance.abs(), 0.0, 0.0, &lim)
        .unwrap()
        .duration()
}

/// Runs mcctl with `args`: its exit code, stdout and stderr.
pub fn mcctl(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mcctl"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// Runs mcctl and reads its peak resident memory (`VmHWM`, kB) from /proc while it runs
/// (the last reading before it exits: the mark only rises).
pub fn mcctl_peak_rss(args: &[&str]) -> (i32, String, String, u64) {
    use std::io::Read;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_mcctl"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // (drained as it runs: a child writing more than a pipe holds would wait for us forever)
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            r.read_to_string(&mut s).unwrap();
            s
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let status = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    let code = loop {
        if let Ok(s) = std::fs::read_to_string(&status) {
            let hwm = s
                .lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok());
            peak = peak.max(hwm.unwrap_or(0));
        }
        if let Some(st) = child.try_wait().unwrap() {
            break st.code().unwrap_or(-1);
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    };
    (code, out.join().unwrap(), err.join().unwrap(), peak)
}
