//! Listing the cards present (`Card::list`) and opening one by name or serial (issue 37,
//! part 4), with `card-emu` processes: each is read through its server's info greeting, which
//! takes no lease, so listing a card a host holds does not disturb that host.
//!
//! The cross-user part (a lister the card's policy refuses) is in `transport.rs`, with the
//! other tests that run a peer as another user.
mod common;

use common::{card_emu, open_when_ready, Proc};
use motioncard_sdk::{Card, CardListing, ErrorKind, MoveLimits, SyncRole, SyncState};
use std::time::{Duration, Instant};

/// A serial number of this test process's own (`k` tells its cards apart).
fn serial(k: u64) -> u64 {
    (u64::from(std::process::id()) << 16) | k
}

/// `card-emu --name NAME --serial S` with `extra`.
fn start(name: &str, serial: u64, extra: &[&str]) -> Proc {
    let s = serial.to_string();
    let mut args = vec!["--serial", s.as_str()];
    args.extend_from_slice(extra);
    card_emu(name, &args)
}

/// The listing of each of `names` (`emu:` cards), once every one of them is listed and read
/// (waiting up to 10 s for their processes to serve).
fn listed(names: &[&str]) -> Vec<CardListing> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let all = Card::list().expect("list");
        let got: Vec<CardListing> = names
            .iter()
            .filter_map(|n| {
                all.iter()
                    .find(|l| l.uri == format!("emu:{n}") && l.error.is_none())
                    .cloned()
            })
            .collect();
        if got.len() == names.len() {
            return got;
        }
        assert!(
            Instant::now() < deadline,
            "not all of {names:?} listed: {all:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn two_card_emu_processes_are_listed_with_their_names_serials_axes_and_rates() {
    let (a, b) = (
        format!("list-a-{}", std::process::id()),
        format!("list-b-{}", std::process::id()),
    );
    let _pa = start(&a, serial(1), &["--axes", "3", "--servo-rate", "5000"]);
    let _pb = start(&b, serial(2), &["--axes", "2"]);
    let got = listed(&[&a, &b]);
    let want = |name: &str, serial, axes, hz| CardListing {
        uri: format!("emu:{name}"),
        name: name.to_string(),
        serial,
        axes,
        servo_rate_hz: hz,
        layout: (firmware_proto::LAYOUT_MAJOR, firmware_proto::LAYOUT_MINOR),
        firmware_version: got[0].firmware_version,
        sync_role: SyncRole::Alone,
        sync_state: SyncState::Free,
        master: String::new(),
        available: true,
        open_here: false,
        error: None,
    };
    assert_eq!(got[0], want(&a, serial(1), 3, 5000));
    assert_eq!(got[1], want(&b, serial(2), 2, 10_000));
    assert_ne!(got[0].firmware_version, 0);
}

/// A host holds card a and moves an axis while the listing reads both cards, again and again:
/// a is listed busy (and open here), b available, and a's host carries on undisturbed: its
/// move ends at its target, it inherited no stop, and its session still answers.
#[test]
fn listing_a_card_a_host_holds_shows_it_busy_and_leaves_the_host_alone() {
    let (a, b) = (
        format!("held-a-{}", std::process::id()),
        format!("held-b-{}", std::process::id()),
    );
    let _pa = start(&a, serial(3), &["--axes", "2"]);
    let _pb = start(&b, serial(4), &["--axes", "2"]);
    let card = open_when_ready(&format!("emu:{a}"));
    let ax = card.axis(1).unwrap();
    ax.enable().unwrap();
    let target = 60_000.0;
    let m = ax
        .move_absolute(target, &MoveLimits::new(150_000.0, 2e6, 1e8))
        .unwrap();
    let tick = card.tick().unwrap();
    for _ in 0..50 {
        let got = listed(&[&a, &b]);
        assert!(!got[0].available && got[0].open_here, "{:?}", got[0]);
        assert!(got[1].available && !got[1].open_here, "{:?}", got[1]);
        assert_eq!(got[0].serial, serial(3));
    }
    let reached = m.wait(Duration::from_secs(10)).unwrap();
    assert!((reached - target).abs() <= 1.0, "reached {reached}");
    assert_eq!(card.inherited_stops(), 0);
    assert!(card.tick().unwrap() > tick);
    card.ping().unwrap();
    // Opening it again by its name is the same card, open here already.
    let e = Card::open(&format!("name:{a}"))
        .err()
        .expect("opened twice");
    assert_eq!(e.kind(), ErrorKind::Busy, "{e}");
    assert!(
        e.to_string().contains("already open in this process"),
        "{e}"
    );
    drop((m, ax, card));
    let got = listed(&[&a]);
    assert!(got[0].available && !got[0].open_here, "{:?}", got[0]);
}

#[test]
fn a_card_opens_by_name_and_by_serial() {
    let (a, b) = (
        format!("byname-a-{}", std::process::id()),
        format!("byname-b-{}", std::process::id()),
    );
    let _pa = start(&a, serial(5), &["--axes", "3"]);
    let _pb = start(&b, serial(6), &["--axes", "5"]);
    listed(&[&a, &b]);
    let card = Card::open(&format!("name:{a}")).unwrap();
    assert_eq!(card.info().axes, 3);
    let by_serial = Card::open(&format!("serial:{}", serial(6))).unwrap();
    assert_eq!(by_serial.info().axes, 5);
    // Each is the card of its URI: its emu: URI is now open here.
    let e = Card::open(&format!("emu:{b}")).err().expect("opened twice");
    assert_eq!(e.kind(), ErrorKind::Busy, "{e}");
    card.close().unwrap();
    by_serial.close().unwrap();
}

#[test]
fn an_unknown_name_or_serial_is_not_found_and_a_shared_one_ambiguous() {
    let (a, b) = (
        format!("twin-a-{}", std::process::id()),
        format!("twin-b-{}", std::process::id()),
    );
    let twin = serial(7);
    let _pa = start(&a, twin, &["--axes", "1"]);
    let _pb = start(&b, twin, &["--axes", "1"]);
    listed(&[&a, &b]);
    let nobody = format!("nobody-{}", std::process::id());
    let e = Card::open(&format!("name:{nobody}")).err().expect("opened");
    assert_eq!(e.kind(), ErrorKind::NotFound, "{e}");
    let m = e.to_string();
    assert!(m.contains(&format!("no card named '{nobody}'")), "{m}");
    // The cards listed, a few of them: the message stays short whatever is present.
    assert!(m.contains(" serial "), "{m}");
    assert!(m.len() < 512, "{} bytes: {m}", m.len());
    let e = Card::open(&format!("serial:{}", serial(8)))
        .err()
        .expect("opened");
    assert_eq!(e.kind(), ErrorKind::NotFound, "{e}");
    assert!(
        e.to_string()
            .contains(&format!("no card with serial {}", serial(8))),
        "{e}"
    );
    let e = Card::open(&format!("serial:{twin}")).err().expect("opened");
    assert_eq!(e.kind(), ErrorKind::Ambiguous, "{e}");
    assert_eq!(e.kind().code(), -150);
    let m = e.to_string();
    assert!(
        m.contains(&format!("matches 2 cards: emu:{a}, emu:{b}")),
        "{m}"
    );
    for bad in ["serial:abc", "serial:0", "name:"] {
        assert_eq!(
            Card::open(bad).err().unwrap().kind(),
            ErrorKind::BadUri,
            "{bad}"
        );
    }
}

/// A card-emu that predates the info greeting closes the connection without a word: the
/// listing says so instead of waiting or taking the card. (Here a server that reads the
/// greeting and closes, as a version-2 server does with a greeting it does not know.)
#[test]
fn a_server_without_the_info_greeting_is_listed_with_a_protocol_error() {
    use std::io::Read;
    use std::os::linux::net::SocketAddrExt;
    use std::os::unix::net::{SocketAddr, UnixListener};
    let name = format!("old-{}", std::process::id());
    let addr =
        SocketAddr::from_abstract_name(firmware_proto::emu_link::socket_name(&name).as_bytes())
            .unwrap();
    let listener = UnixListener::bind_addr(&addr).unwrap();
    // Every lister (the other tests list too) gets the same: its greeting read, then the
    // connection closed. It serves until the test process ends.
    let (tx, greetings) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for mut s in listener.incoming().flatten() {
            let mut b = [0u8; 16];
            if s.read_exact(&mut b).is_ok() {
                let _ = tx.send(b);
            }
        }
    });
    let all = Card::list().unwrap();
    let l = all
        .iter()
        .find(|l| l.uri == format!("emu:{name}"))
        .expect("listed");
    let e = l.error.as_ref().expect("an error");
    assert_eq!(e.kind, ErrorKind::Protocol);
    assert!(e.message.contains("predates card listing"), "{}", e.message);
    assert!(!l.available);
    let g = greetings.recv_timeout(Duration::from_secs(10)).unwrap();
    assert_eq!(g[..8], *b"MCINFO\x02\0");
}

/// The name and serial are in `card_info` from the start, as a board's EEPROM's are: a lister
/// that comes before the card's first tick sees them (they were published with the first
/// tick, and such a lister saw no name and serial 0).
#[test]
fn a_card_shows_its_name_and_serial_before_its_first_tick() {
    use card_emu::{EmuOptions, Emulator};
    let opts = EmuOptions {
        serial: 77,
        ..EmuOptions::new(2, 10_000)
    };
    let emu = Emulator::create("early", &opts).unwrap();
    let r = emu.lessor().record(false);
    assert_eq!((r.name.as_str(), r.serial, r.axes), ("early", 77, 2));
}
