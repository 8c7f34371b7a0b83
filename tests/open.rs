//! Opening cards: URIs, exclusive open, layout version check, emu:NAME served in-process.
use card_emu::emu::server::Server;
use card_emu::{EmuOptions, Emulator, Runner};
use firmware_proto::{layout, Mem};
use motioncard_sdk::{Card, ErrorKind, MoveLimits};
use std::time::{Duration, Instant};

fn serve(name: &str, emu: Emulator) -> (Server, Runner) {
    let server = Server::start(name, emu.lessor()).unwrap();
    (
        server,
        Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap(),
    )
}

/// Serve a card whose firmware does not run (nothing rewrites its window): what a test writes
/// into the identity block stays there.
fn serve_frozen(name: &str, emu: &Emulator) -> Server {
    Server::start(name, emu.lessor()).unwrap()
}

fn unique(tag: &str) -> String {
    format!("test-{tag}-{}", std::process::id())
}

#[test]
fn bad_and_absent_uris_get_their_own_errors() {
    assert_eq!(
        Card::open("nonsense").err().unwrap().kind(),
        ErrorKind::BadUri
    );
    let e = Card::open("emu:no-such-card-anywhere").err().unwrap();
    assert_eq!(e.kind(), ErrorKind::NotFound);
    assert!(
        e.to_string()
            .contains("card-emu --name no-such-card-anywhere"),
        "{e}"
    );
    assert_eq!(
        Card::open("uio:/dev/uio4242").err().unwrap().kind(),
        ErrorKind::NotFound
    );
    assert_eq!(
        Card::open("pci:0000:ff:1f.7").err().unwrap().kind(),
        ErrorKind::NotFound
    );
}

#[test]
fn second_open_is_busy_until_the_first_closes() {
    let name = unique("busy");
    let (_server, _runner) = serve(
        &name,
        Emulator::create(&name, &EmuOptions::default()).unwrap(),
    );
    let uri = format!("emu:{name}");
    let first = Card::open(&uri).unwrap();
    let e = Card::open(&uri).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::Busy);
    assert!(e.to_string().contains(&uri));
    // Opened by this process: the message says so, not "another process" (issue 39).
    assert!(
        e.to_string().contains("already open in this process")
            && !e.to_string().contains("another process"),
        "{e}"
    );
    // The first host works while the second was refused.
    let ax = first.axis(0).unwrap();
    ax.enable().unwrap();
    ax.move_relative(5000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap()
        .wait(Duration::from_secs(5))
        .unwrap();
    drop(ax);
    drop(first);
    // The lease ends when the connection closes; the next open succeeds.
    let deadline = Instant::now() + Duration::from_secs(5);
    let again = loop {
        match Card::open(&uri) {
            Ok(c) => break c,
            Err(e) if e.kind() == ErrorKind::Busy && Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(e) => panic!("{e}"),
        }
    };
    // The card kept its state across hosts, like hardware.
    let s = again.axis(0).unwrap().status().unwrap();
    assert!(
        (s.actual_position - 5000.0).abs() <= 1.0,
        "{}",
        s.actual_position
    );
}

/// Layout 1.9 moved the status blocks' checksum: a 1.8 card's status cannot be read, so the
/// card is refused at the open, not with corrupt statuses later.
#[test]
fn a_card_of_layout_1_8_is_refused() {
    let name = unique("version18");
    let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
    emu.window().write32(layout::LAYOUT, 1 | 8 << 16);
    let _server = serve_frozen(&name, &emu);
    let e = Card::open(&format!("emu:{name}")).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::VersionMismatch);
    assert!(e.to_string().contains("1.8"), "{e}");
}

#[test]
fn a_card_with_another_layout_major_is_refused_naming_both_versions() {
    let name = unique("version");
    let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
    emu.window().write32(layout::LAYOUT, 7 | 3 << 16); // layout 7.3
    let _server = serve_frozen(&name, &emu);
    let e = Card::open(&format!("emu:{name}")).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::VersionMismatch);
    let msg = e.to_string();
    assert!(
        msg.contains("7.3")
            && msg.contains(&format!(
                "{}.{}",
                firmware_proto::LAYOUT_MAJOR,
                firmware_proto::LAYOUT_MINOR
            )),
        "{msg}"
    );
}

#[test]
fn a_window_without_the_signature_is_a_protocol_error() {
    let name = unique("magic");
    let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
    emu.window().write32(layout::MAGIC, 0xDEAD_BEEF);
    let _server = serve_frozen(&name, &emu);
    assert_eq!(
        Card::open(&format!("emu:{name}")).err().unwrap().kind(),
        ErrorKind::Protocol
    );
}

/// The card owns its identity block and republishes it every tick: one stray write into it (by
/// anything that maps the window) does not lock every later host out until a restart.
#[test]
fn a_stray_write_to_the_identity_block_is_repaired_by_the_card() {
    let name = unique("identity");
    let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
    let window = emu.window().clone();
    let (_server, _runner) = serve(&name, emu);
    let uri = format!("emu:{name}");
    drop(Card::open(&uri).unwrap());
    for (off, junk) in [
        (layout::MAGIC, 0xDEAD_BEEF),
        (layout::LAYOUT, 7 | 3 << 16),
        (layout::NUM_AXES, 0),
        (layout::CMD_RING_LEN, 3),
    ] {
        window.write32(off, junk);
        let t = window.read64(layout::TICK);
        while window.read64(layout::TICK) < t + 2 {
            std::thread::sleep(Duration::from_millis(1));
        }
        let card = Card::open(&uri).unwrap_or_else(|e| panic!("after junk at {off}: {e}"));
        assert_eq!(card.info().axes, firmware_proto::MAX_AXES);
    }
}

/// The real-time sim answers through the interrupt fd: a wait with a timeout returns by it.
#[test]
fn realtime_sim_waits_block_on_the_interrupt_fd() {
    let card = Card::open("sim").unwrap();
    assert!(card.irq_fd().is_some());
    let ax = card.axis(5).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(3e5, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    let t0 = Instant::now();
    assert_eq!(
        m.wait(Duration::from_millis(50)).unwrap_err().kind(),
        ErrorKind::Timeout
    );
    let waited = t0.elapsed();
    assert!(
        waited >= Duration::from_millis(50),
        "returned early after {waited:?}"
    );
    assert!((m.wait(Duration::from_secs(10)).unwrap() - 3e5).abs() <= 1.0);
}
