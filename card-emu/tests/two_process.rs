//! The card served by a separate `card-emu` process, opened as `emu:NAME`: both processes map
//! the same DPRAM (memfd), interrupts arrive on the eventfd handed over with it.
mod common;

use common::{card_emu as start, open_when_ready};
use motioncard_sdk::{AxisState, Card, ErrorKind, MoveLimits};
use std::process::Command;
use std::time::Duration;

#[test]
fn an_axis_moves_through_a_card_emu_process() {
    let name = format!("twoproc-{}", std::process::id());
    let _emu = start(&name, &["--axes", "4", "--servo-rate", "5000"]);
    let card = open_when_ready(&format!("emu:{name}"));
    let info = card.info();
    assert_eq!((info.axes, info.servo_rate_hz), (4, 5000));
    assert_eq!(card.axis(4).err().unwrap().kind(), ErrorKind::BadAxis);
    let ax = card.axis(3).unwrap();
    ax.enable().unwrap();
    let target = -75_000.0;
    let m = ax
        .move_absolute(target, &MoveLimits::new(150_000.0, 2e6, 1e8))
        .unwrap();
    let reached = m.wait(Duration::from_secs(10)).unwrap();
    assert!((reached - target).abs() <= 1.0, "reached {reached}");
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::Standstill);
    assert!(s.raw.peak_vel <= 150_000.0 * (1.0 + 1e-9) && s.raw.peak_vel > 149_000.0);
    // A second host is refused while this one holds the card.
    assert_eq!(
        Card::open(&format!("emu:{name}")).err().unwrap().kind(),
        ErrorKind::Busy
    );
}

#[test]
fn a_second_server_of_the_same_name_is_refused() {
    let name = format!("dupname-{}", std::process::id());
    let _emu = start(&name, &[]);
    drop(open_when_ready(&format!("emu:{name}")));
    let out = Command::new(env!("CARGO_BIN_EXE_card-emu"))
        .args(["--name", &name])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("already being served"));
}
