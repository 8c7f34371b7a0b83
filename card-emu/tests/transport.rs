//! The `emu:` transport's protections (issue 10, section 3): a DPRAM window whose size no host
//! can change.
use card_emu::server::{self, ConnectError, Server};
use card_emu::shm::MappedWindow;
use motioncard_sdk::{AxisState, Card, ErrorKind, MoveLimits};
use nix::errno::Errno;
use nix::fcntl::{fcntl, FcntlArg, SealFlag};
use nix::unistd::ftruncate;
use std::os::fd::AsFd;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Emu(Child);

impl Emu {
    fn start(name: &str, extra: &[&str]) -> Self {
        let child = Command::new(env!("CARGO_BIN_EXE_card-emu"))
            .args(["--name", name, "--axes", "2"])
            .args(extra)
            .stdout(Stdio::null())
            .spawn()
            .expect("start card-emu");
        let emu = Emu(child);
        // Ready once this process has connected. No SDK host: its heartbeat would arm the
        // watchdog, which would trip when it closes.
        drop(connect_when_ready(name));
        emu
    }
}

impl Drop for Emu {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn connect_when_ready(name: &str) -> server::Connection {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match server::connect(name) {
            Ok(c) => return c,
            Err(ConnectError::NotFound | ConnectError::Busy) if Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(e) => panic!("connecting to {name}: {e:?}"),
        }
    }
}

fn len(fd: impl AsFd) -> u64 {
    let f = std::fs::File::from(fd.as_fd().try_clone_to_owned().unwrap());
    f.metadata().unwrap().len()
}

/// Open `uri`, waiting while it is not served yet or the previous host's lease is still
/// being released.
fn try_open(uri: &str) -> motioncard_sdk::Result<Card> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match Card::open(uri) {
            Err(e)
                if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::Busy)
                    && Instant::now() < deadline =>
            {
                std::thread::sleep(Duration::from_millis(5))
            }
            r => return r,
        }
    }
}

fn open_when_ready(uri: &str) -> Card {
    try_open(uri).unwrap_or_else(|e| panic!("opening {uri}: {e}"))
}

/// A connected host tries to resize the window it received: both fail with EPERM, and the
/// card keeps ticking and answering (before the seals, `ftruncate(fd, 0)` killed card-emu
/// with SIGBUS on its next tick).
#[test]
fn a_host_cannot_resize_the_window() {
    let name = format!("sealed-{}", std::process::id());
    let mut emu = Emu::start(&name, &[]);
    let conn = connect_when_ready(&name);
    let size = len(&conn.window);
    let shrink = ftruncate(&conn.window, 0);
    std::thread::sleep(Duration::from_millis(200));
    let died = emu.0.try_wait().unwrap();
    assert_eq!(died, None, "card-emu died after the host shrank its window");
    assert_eq!(shrink, Err(Errno::EPERM), "shrinking the window");
    assert_eq!(ftruncate(&conn.window, 2 * size as i64), Err(Errno::EPERM));
    let reseal = FcntlArg::F_ADD_SEALS(SealFlag::F_SEAL_FUTURE_WRITE);
    assert_eq!(
        fcntl(&conn.window, reseal),
        Err(Errno::EPERM),
        "adding a seal"
    );
    assert_eq!(len(&conn.window), size);
    MappedWindow::from_fd(conn.window).unwrap(); // still what a host maps
    drop(conn.lease);

    // Still ticking and answering.
    let card = open_when_ready(&format!("emu:{name}"));
    let t0 = card.tick();
    card.ping().unwrap();
    let ax = card.axis(1).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(5_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    let reached = m.wait(Duration::from_secs(10)).unwrap();
    assert!((reached - 5_000.0).abs() <= 1.0, "reached {reached}");
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    assert!(card.tick() > t0);
    assert_eq!(emu.0.try_wait().unwrap(), None);
}

/// A window that is not sealed at its size is a protocol violation for the SDK: it is not
/// mapped (the server could shrink it under the host).
#[test]
fn a_host_refuses_an_unsealed_window() {
    use nix::sys::memfd::{memfd_create, MFdFlags};
    let name = format!("unsealed-{}", std::process::id());
    let window = memfd_create("unsealed", MFdFlags::MFD_CLOEXEC).unwrap();
    ftruncate(&window, firmware_proto::DPRAM_SIZE as i64).unwrap();
    let irq = nix::sys::eventfd::EventFd::new().unwrap();
    let _server = Server::start(&name, window, irq.as_fd().try_clone_to_owned().unwrap()).unwrap();
    let e = Card::open(&format!("emu:{name}")).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::Protocol, "{e}");
    assert!(e.to_string().contains("not sealed"), "{e}");
}
