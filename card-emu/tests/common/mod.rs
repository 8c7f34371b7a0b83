//! What the tests that run a `card-emu` process share: starting it, killing it when the test
//! ends, and opening its card once it serves.
#![allow(dead_code)]

use motioncard_sdk::{Card, ErrorKind};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A child process, killed and reaped when dropped (a failing test leaves nothing behind).
pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Start `card-emu --name NAME` with `extra` options; its stderr is piped (some tests read
/// it), its stdout dropped.
pub fn card_emu(name: &str, extra: &[&str]) -> Proc {
    Proc(
        Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", name])
            .args(extra)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start card-emu"),
    )
}

/// Open `uri`, retrying while it is not served yet or the previous host's lease is still being
/// released (a fraction of a millisecond after that host dies), for up to 10 s.
pub fn try_open(uri: &str) -> motioncard_sdk::Result<Card> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match Card::open(uri) {
            Err(e)
                if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::Busy)
                    && Instant::now() < deadline =>
            {
                std::thread::sleep(Duration::from_micros(100))
            }
            r => return r,
        }
    }
}

/// [`try_open`], which must succeed.
pub fn open_when_ready(uri: &str) -> Card {
    try_open(uri).unwrap_or_else(|e| panic!("opening {uri}: {e}"))
}

/// Run this test binary again as a host: only the test `role` (which returns at once unless
/// one of `env` is set), with `env`; returns once it has printed `HOST-READY` ([`host_ready`]).
pub fn start_host_role(role: &str, env: &[(&str, String)], what: &str) -> Proc {
    let mut host = Proc(
        Command::new(std::env::current_exe().unwrap())
            .args(["--exact", role, "--nocapture", "--test-threads=1"])
            .envs(env.iter().map(|(k, v)| (*k, v.as_str())))
            .stdout(Stdio::piped())
            .spawn()
            .expect("start the host"),
    );
    let out = host.0.stdout.take().unwrap();
    let ready = BufReader::new(out)
        .lines()
        .map_while(Result::ok)
        .any(|l| l.contains("HOST-READY"));
    assert!(ready, "{what}: the host died before it was ready");
    host
}

/// A host role's end: it says it is ready and waits to be killed.
pub fn host_ready() -> ! {
    println!("\nHOST-READY");
    loop {
        std::thread::sleep(Duration::from_secs(1));
    }
}
