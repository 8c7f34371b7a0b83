//! `card-emu` processes for the benchmarks that talk to a card across processes
//! (`roundtrip`, `pvt_stream`, `path_run`, `sync_bus`): started, opened once served, killed
//! when dropped (a panicking benchmark too).
use motioncard_sdk::{Card, ErrorKind};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A `card-emu` process, killed when dropped.
pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Start `card-emu --name NAME` with `extra` options, its stdout dropped.
pub fn card_emu(name: &str, extra: &[&str]) -> Proc {
    Proc(
        Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", name])
            .args(extra)
            .stdout(Stdio::null())
            .spawn()
            .expect("start card-emu"),
    )
}

/// Open `uri`, retrying for up to 10 s while it is not served yet.
pub fn open(uri: &str) -> Card {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match Card::open(uri) {
            Ok(c) => return c,
            Err(e) if e.kind() == ErrorKind::NotFound && Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(10))
            }
            Err(e) => panic!("{uri}: {e}"),
        }
    }
}
