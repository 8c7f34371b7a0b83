//! The `emu:` transport's protections (issue 10, section 3; issue 31): who may connect to a
//! served card (the peer's credentials against card-emu's policy), a connection that says
//! nothing takes nothing, a window per lease (a past host cannot reach a later one's card), and
//! a DPRAM window whose size no host can change.
//!
//! The cross-user tests need root, to run a host as another user: this test binary runs again
//! with `MC_TRANSPORT_PEER` set, as uid 65534 (nobody), and its `peer_role` test opens the
//! card and prints what happened. It runs from a copy in a new directory under /tmp that every
//! user can reach ([`PeerExe`]): the checkout may be in a directory other users cannot enter.
//! Without root, or where no such copy can be run (a noexec /tmp), they say so and check what
//! they can in-process.
mod common;

use card_emu::emu::server::{self, LeaseFds, LeaseSource, ServeOptions, Server};
use card_emu::{EmuOptions, Emulator};
use common::{card_emu, open_when_ready, try_open, Proc};
use firmware_proto::emu_link::{self, ConnectError, STATUS_TIMEOUT};
use firmware_proto::window::MappedWindow;
use firmware_proto::{layout, Mem};
use motioncard_sdk::{AxisState, Card, ErrorKind, MoveLimits};
use nix::errno::Errno;
use nix::fcntl::{fcntl, FcntlArg, SealFlag};
use nix::unistd::{ftruncate, Gid, Uid};
use std::io::Read;
use std::os::fd::{AsFd, OwnedFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::fs::PermissionsExt;
use std::os::unix::net::{SocketAddr, UnixStream};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const ROLE: &str = "MC_TRANSPORT_PEER";
const NOBODY: u32 = 65534;

/// A `card-emu` of two axes, ready once this process (its own user, always admitted) has
/// connected. No SDK host: its heartbeat would arm the watchdog, which would trip when it
/// closes.
struct Emu(Proc);

impl Emu {
    fn start(name: &str, extra: &[&str]) -> Self {
        let mut args = vec!["--axes", "2"];
        args.extend_from_slice(extra);
        let emu = Emu(card_emu(name, &args));
        release(connect_when_ready(name));
        emu
    }

    /// Kill it and return what it wrote on stderr.
    fn stop(mut self) -> String {
        let p = &mut (self.0).0;
        let _ = p.kill();
        let _ = p.wait();
        let mut err = String::new();
        if let Some(mut e) = p.stderr.take() {
            let _ = e.read_to_string(&mut err);
        }
        err
    }
}

fn connect_when_ready(name: &str) -> emu_link::Connection {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match emu_link::connect(name) {
            Ok(c) => return c,
            Err(ConnectError::NotFound | ConnectError::Busy) if Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(e) => panic!("connecting to {name}: {e:?}"),
        }
    }
}

/// End a lease and wait until card-emu has let it go (it closes its end after that), so that
/// the card is free for whoever connects next.
fn release(conn: emu_link::Connection) {
    let mut lease = conn.lease;
    lease.shutdown(std::net::Shutdown::Write).unwrap();
    lease
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let mut b = [0u8; 16];
    assert_eq!(lease.read(&mut b).unwrap(), 0, "card-emu closed the lease");
}

fn len(fd: impl AsFd) -> u64 {
    let f = std::fs::File::from(fd.as_fd().try_clone_to_owned().unwrap());
    f.metadata().unwrap().len()
}

/// The host run as another user (only when started by the tests below): open the card,
/// drive it a little, and say how it went.
#[test]
fn peer_role() {
    let Ok(uri) = std::env::var(ROLE) else {
        return;
    };
    if let Some(name) = uri.strip_prefix("list:") {
        let all = Card::list().expect("list");
        let l = all
            .iter()
            .find(|l| l.uri == format!("emu:{name}"))
            .expect("listed");
        match &l.error {
            Some(e) => println!("\nPEER-LISTED {:?}: {}", e.kind, e.message),
            None => println!(
                "\nPEER-LISTED ok {} serial {} available {}",
                l.name, l.serial, l.available
            ),
        }
        return;
    }
    match try_open(&uri) {
        Ok(card) => {
            card.ping().unwrap();
            card.reset_faults().unwrap(); // the watchdog trip of an earlier peer
            let ax = card.axis(0).unwrap();
            ax.enable().unwrap();
            ax.disable().unwrap();
            println!("\nPEER-OPENED");
        }
        Err(e) => println!("\nPEER-ERROR {:?}: {e}", e.kind()),
    }
}

fn is_root() -> bool {
    nix::unistd::geteuid().is_root()
}

/// A copy of an executable that every user can run: in a new directory under /tmp (or
/// /var/tmp), both mode 0755, removed when dropped. The checkout, and with it the test binary,
/// may sit in a directory other users cannot enter (a mode-0700 home, `mktemp -d`), where
/// uid 65534 cannot execute it in place (EACCES).
struct PeerExe {
    dir: PathBuf,
    exe: PathBuf,
}

impl PeerExe {
    /// Copy `exe` where every user can reach it, or say why it cannot be done.
    fn of(exe: &Path) -> Result<Self, String> {
        let mut why = Vec::new();
        for base in ["/tmp", "/var/tmp"] {
            let base = Path::new(base);
            if !reachable_by_all(base) {
                why.push(format!("{} is not open to every user", base.display()));
                continue;
            }
            let dir = base.join(format!(
                "motioncard-peer-{}-{}",
                std::process::id(),
                PEER_DIRS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
            ));
            let made = std::fs::create_dir(&dir)
                .and_then(|()| Self::fill(&dir, exe))
                .map(|exe| Self {
                    dir: dir.clone(),
                    exe,
                });
            match made {
                Ok(p) => return Ok(p),
                Err(e) => {
                    let _ = std::fs::remove_dir_all(&dir);
                    why.push(format!("{}: {e}", dir.display()));
                }
            }
        }
        Err(why.join("; "))
    }

    /// Make `dir` 0755 (whatever the umask) and copy `exe` into it, 0755.
    fn fill(dir: &Path, exe: &Path) -> std::io::Result<PathBuf> {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o755))?;
        let to = dir.join(exe.file_name().unwrap_or("peer".as_ref()));
        std::fs::copy(exe, &to)?;
        std::fs::set_permissions(&to, std::fs::Permissions::from_mode(0o755))?;
        Ok(to)
    }
}

impl Drop for PeerExe {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

static PEER_DIRS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Every directory from the root down to `path` lets other users through (o+x), and `path`
/// itself too (for a file: they may execute it).
fn reachable_by_all(path: &Path) -> bool {
    path.ancestors().all(|p| {
        p.as_os_str().is_empty()
            || std::fs::metadata(p).is_ok_and(|m| m.permissions().mode() & 0o001 != 0)
    })
}

/// This test binary as another user runs it: [`PeerExe`] of it.
struct Peer(PeerExe);

impl Peer {
    /// The peer, or `None` after saying why another user cannot run this binary here (no
    /// directory open to every user, or one mounted noexec).
    fn new(test: &str) -> Option<Self> {
        let exe = std::env::current_exe().expect("this test binary");
        let peer = match PeerExe::of(&exe) {
            Ok(p) => Peer(p),
            Err(why) => {
                eprintln!("{test}: skipped, uid {NOBODY} cannot run this test binary: {why}");
                return None;
            }
        };
        // Run it once with nothing to do (no role): only whether it starts at all.
        match peer.command(NOBODY, NOBODY, &[]).output() {
            Ok(out) if out.status.success() => Some(peer),
            Ok(out) => panic!(
                "the peer at {} did not run: {:?}\n{}",
                peer.0.exe.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr)
            ),
            Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
                eprintln!(
                    "{test}: skipped, uid {NOBODY} cannot execute {} ({e}: is {} mounted \
                     noexec?)",
                    peer.0.exe.display(),
                    peer.0.dir.display()
                );
                None
            }
            Err(e) => panic!("running the peer {}: {e}", peer.0.exe.display()),
        }
    }

    /// [`peer_command`] of this binary's copy.
    fn command(&self, uid: u32, gid: u32, groups: &[u32]) -> Command {
        peer_command(&self.0.exe, uid, gid, groups)
    }

    /// Run `peer_role` on `uri` as `uid` (see [`Peer::command`]); its verdict line.
    fn run(&self, uri: &str, uid: u32, gid: u32, groups: &[u32]) -> String {
        let out = self
            .command(uid, gid, groups)
            .env(ROLE, uri)
            .stderr(Stdio::inherit())
            .output()
            .expect("run the peer");
        let stdout = String::from_utf8_lossy(&out.stdout);
        stdout
            .lines()
            .find(|l| l.starts_with("PEER-"))
            .unwrap_or_else(|| panic!("the peer said nothing ({:?}): {stdout}", out.status))
            .to_string()
    }
}

/// The `peer_role` test of the test binary `exe`, to run as `uid`, with effective gid `gid`
/// and supplementary `groups`, from `/` (the test's directory may be closed to it).
fn peer_command(exe: &Path, uid: u32, gid: u32, groups: &[u32]) -> Command {
    let groups: Vec<Gid> = groups.iter().map(|&g| Gid::from_raw(g)).collect();
    let mut cmd = Command::new(exe);
    cmd.args(["--exact", "peer_role", "--nocapture", "--test-threads=1"])
        .current_dir("/")
        .env_remove(ROLE)
        .stderr(Stdio::piped());
    // SAFETY: between fork and exec the closure only makes the three system calls (the group
    // list was built before the fork; nothing allocates). std's `uid()` would drop the
    // supplementary groups, and its `groups()` is unstable.
    unsafe {
        cmd.pre_exec(move || {
            nix::unistd::setgroups(&groups)?;
            nix::unistd::setgid(Gid::from_raw(gid))?;
            nix::unistd::setuid(Uid::from_raw(uid))?;
            Ok(())
        });
    }
    cmd
}

fn skip(what: &str) -> bool {
    if is_root() {
        return false;
    }
    println!("{what}: skipped, running as another user needs root (CI runs as root)");
    true
}

#[test]
fn a_host_of_another_user_is_refused_with_permission_denied() {
    let name = format!("acl-deny-{}", std::process::id());
    let uri = format!("emu:{name}");
    if !is_root() {
        skip("the cross-user part");
        // What a refused host sees, without a second user: a server whose policy belongs to
        // another uid, in this process.
        let me = nix::unistd::geteuid().as_raw();
        let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
        let opts = ServeOptions::new(server::PeerPolicy::new(me + 1));
        let _server = Server::start_with(&name, emu.lessor(), opts).unwrap();
        let e = Card::open(&uri).err().unwrap();
        assert_eq!(e.kind(), ErrorKind::PermissionDenied, "{e}");
        assert!(e.to_string().contains(&format!("--allow-uid {me}")), "{e}");
        return;
    }
    let Some(peer) = Peer::new("a_host_of_another_user_is_refused_with_permission_denied") else {
        return;
    };
    let emu = Emu::start(&name, &[]);
    let got = peer.run(&uri, NOBODY, NOBODY, &[]);
    assert!(got.starts_with("PEER-ERROR PermissionDenied"), "{got}");
    assert!(got.contains("refused uid 65534"), "{got}");
    assert!(got.contains("--allow-uid 65534"), "{got}");
    // This user still opens it.
    open_when_ready(&uri).ping().unwrap();
    // The operator sees who was refused, once.
    let _ = peer.run(&uri, NOBODY, NOBODY, &[]);
    let log = emu.stop();
    assert_eq!(
        log.matches("refused a host with uid 65534").count(),
        1,
        "{log}"
    );
    assert!(log.contains("--allow-uid 65534"), "{log}");
}

#[test]
fn an_allowed_uid_is_admitted() {
    if skip("an_allowed_uid_is_admitted") {
        return;
    }
    let Some(peer) = Peer::new("an_allowed_uid_is_admitted") else {
        return;
    };
    let name = format!("acl-uid-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = Emu::start(&name, &["--allow-uid", "65534", "--allow-uid", "4321"]);
    assert_eq!(peer.run(&uri, NOBODY, NOBODY, &[]), "PEER-OPENED");
    let got = peer.run(&uri, 4322, NOBODY, &[]);
    assert!(got.starts_with("PEER-ERROR PermissionDenied"), "{got}");
}

#[test]
fn an_allowed_group_admits_by_effective_or_supplementary_gid() {
    if skip("an_allowed_group_admits_by_effective_or_supplementary_gid") {
        return;
    }
    let Some(peer) = Peer::new("an_allowed_group_admits_by_effective_or_supplementary_gid") else {
        return;
    };
    // By name: whatever gid 65534 is called here (nogroup, nobody), else by number.
    let nogroup = nix::unistd::Group::from_gid(Gid::from_raw(NOBODY))
        .ok()
        .flatten()
        .map_or_else(|| NOBODY.to_string(), |g| g.name);
    let name = format!("acl-gid-{}", std::process::id());
    let uri = format!("emu:{name}");
    let emu = Emu::start(&name, &["--allow-group", &nogroup]);
    assert_eq!(peer.run(&uri, NOBODY, NOBODY, &[]), "PEER-OPENED");
    let got = peer.run(&uri, NOBODY, 4242, &[]);
    assert!(got.starts_with("PEER-ERROR PermissionDenied"), "{got}");
    drop(emu);

    let name = format!("acl-groups-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = Emu::start(&name, &["--allow-group", "4242"]);
    assert_eq!(peer.run(&uri, NOBODY, NOBODY, &[4242]), "PEER-OPENED");
    assert_eq!(peer.run(&uri, NOBODY, 4242, &[]), "PEER-OPENED");
    let got = peer.run(&uri, NOBODY, NOBODY, &[4241, 4243]);
    assert!(got.starts_with("PEER-ERROR PermissionDenied"), "{got}");
}

#[test]
fn an_unknown_group_is_refused_at_startup() {
    let out = Command::new(env!("CARGO_BIN_EXE_card-emu"))
        .args([
            "--name",
            "never-served",
            "--allow-group",
            "no-such-group-mc",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no group named 'no-such-group-mc'"), "{err}");
}

#[test]
fn the_help_states_the_access_rule() {
    let out = Command::new(env!("CARGO_BIN_EXE_card-emu"))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "--allow-uid <UID>",
        "--allow-group <GROUP>",
        "own user",
        "root",
    ] {
        assert!(help.contains(needle), "no '{needle}' in:\n{help}");
    }
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
    let died = emu.0 .0.try_wait().unwrap();
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
    let t0 = card.tick().unwrap();
    card.ping().unwrap();
    let ax = card.axis(1).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_relative(5_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    let reached = m.wait(Duration::from_secs(10)).unwrap();
    assert!((reached - 5_000.0).abs() <= 1.0, "reached {reached}");
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    assert!(card.tick().unwrap() > t0);
    assert_eq!(emu.0 .0.try_wait().unwrap(), None);
}

/// A window that is not sealed at its size is a protocol violation for the SDK: it is not
/// mapped (the server could shrink it under the host).
#[test]
fn a_host_refuses_an_unsealed_window() {
    use nix::sys::memfd::{memfd_create, MFdFlags};
    /// A server that breaks the protocol: an unsealed memfd.
    struct Unsealed(OwnedFd, nix::sys::eventfd::EventFd);
    impl LeaseSource for Unsealed {
        fn next_lease(&self) -> std::io::Result<LeaseFds> {
            Ok(LeaseFds {
                window: self.0.try_clone()?,
                irq: self.1.as_fd().try_clone_to_owned()?,
            })
        }
    }
    let name = format!("unsealed-{}", std::process::id());
    let window = memfd_create("unsealed", MFdFlags::MFD_CLOEXEC).unwrap();
    ftruncate(&window, firmware_proto::DPRAM_SIZE as i64).unwrap();
    let irq = nix::sys::eventfd::EventFd::new().unwrap();
    let _server = Server::start(&name, Unsealed(window, irq)).unwrap();
    let e = Card::open(&format!("emu:{name}")).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::Protocol, "{e}");
    assert!(e.to_string().contains("not sealed"), "{e}");
}

/// Issue 31: a client that connects and never says anything kept every host out ("busy") for
/// as long as it held the socket. Now the card is leased only after a host's greeting: a host
/// opens the card while the silent connection is still there, and card-emu closes the silent
/// one at its deadline (2 s), answering "timeout", and logs it once.
#[test]
fn a_silent_connection_locks_no_host_out() {
    let name = format!("squat-{}", std::process::id());
    let uri = format!("emu:{name}");
    let emu = Emu::start(&name, &[]); // and the card is free
    let addr = SocketAddr::from_abstract_name(emu_link::socket_name(&name).as_bytes()).unwrap();
    let mut silent = UnixStream::connect_addr(&addr).unwrap();
    silent
        .set_read_timeout(Some(Duration::from_secs(30)))
        .unwrap();
    let card = open_when_ready(&uri);
    card.ping().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    ax.disable().unwrap();
    drop(ax);
    drop(card);
    // Still silent; card-emu hangs up on it.
    let mut greeting = [0u8; 16];
    silent.read_exact(&mut greeting).unwrap();
    assert_eq!(greeting[..8], emu_link::HELLO);
    assert_eq!(greeting[8..12], STATUS_TIMEOUT.to_le_bytes());
    assert_eq!(greeting[12..16], 2000u32.to_le_bytes(), "the deadline, ms");
    assert_eq!(silent.read(&mut greeting).unwrap(), 0, "closed by card-emu");
    // And the next host opens the card.
    open_when_ready(&uri).ping().unwrap();
    let log = emu.stop();
    let me = nix::unistd::geteuid().as_raw();
    assert_eq!(
        log.matches(&format!("dropped a connection of uid {me}"))
            .count(),
        1,
        "{log}"
    );
}

/// Issue 31: a host that kept the window's memfd (and its mapping) after its lease wrote into
/// the window of the next host: that host's commands failed with a protocol violation and its
/// axis went to ErrorStop. Each lease now gets a window and an interrupt line of its own: the
/// past host scribbles over all of its old window and the card, and the host that has it now,
/// notice nothing.
#[test]
fn a_past_host_cannot_reach_a_later_hosts_window() {
    let name = format!("past-host-{}", std::process::id());
    let uri = format!("emu:{name}");
    let _emu = Emu::start(&name, &[]);
    let past = connect_when_ready(&name);
    let old = MappedWindow::from_fd(past.window).unwrap();
    let old_irq = past.irq;
    let t0 = old.read64(layout::TICK);
    while old.read64(layout::TICK) < t0 + 10 {
        std::thread::sleep(Duration::from_millis(1)); // the card ticks in it for now
    }
    drop(past.lease);

    let card = open_when_ready(&uri);
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let drain = |fd: &OwnedFd| nix::unistd::read(fd, &mut [0u8; 8]);
    let _ = drain(&old_irq);
    // The past host writes garbage over the whole window it kept, twice over a while.
    for round in 0..2u64 {
        for off in (0..firmware_proto::DPRAM_SIZE).step_by(8) {
            old.write64(off, 0xA5A5_5A5A_0000_0000 | off as u64 | round);
        }
        ax.jog(1_000.0).unwrap();
        std::thread::sleep(Duration::from_millis(20));
        ax.jog_release()
            .unwrap()
            .wait(Duration::from_secs(10))
            .unwrap();
    }
    let m = ax
        .move_relative(-5_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    m.wait(Duration::from_secs(10)).unwrap();
    let st = ax.status().unwrap();
    assert_eq!(st.state, AxisState::Standstill);
    let safety = card.safety_status().unwrap();
    assert_eq!(safety.protocol_errors, 0);
    assert!(!safety.watchdog_tripped);
    // The card no longer writes the old window: its tick counter stays the garbage written.
    let t = card.tick().unwrap();
    while card.tick().unwrap() < t + 100 {
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(
        old.read64(layout::TICK),
        0xA5A5_5A5A_0000_0000 | layout::TICK as u64 | 1
    );
    // Nor raises the old interrupt line.
    assert_eq!(drain(&old_irq), Err(Errno::EAGAIN));
}

/// Issue 31: the cross-user tests ran this test binary in place as uid 65534, which fails
/// with EACCES when the checkout is in a directory other users cannot enter (a mode-0700 home,
/// `mktemp -d`). Here the binary sits in such a directory: run in place as nobody it cannot
/// start, and from its [`PeerExe`] copy it runs and reaches the transport.
#[test]
fn the_peer_runs_from_a_checkout_other_users_cannot_enter() {
    if skip("the_peer_runs_from_a_checkout_other_users_cannot_enter") {
        return;
    }
    let private = std::env::temp_dir().join(format!("motioncard-private-{}", std::process::id()));
    std::fs::create_dir(&private).unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o700)).unwrap();
    struct Remove(PathBuf);
    impl Drop for Remove {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
    let _private = Remove(private.clone());
    let exe = private.join("transport-test");
    std::fs::copy(std::env::current_exe().unwrap(), &exe).unwrap();
    assert!(!reachable_by_all(&exe));

    // In place, as the tests ran it.
    let e = peer_command(&exe, NOBODY, NOBODY, &[])
        .output()
        .unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::PermissionDenied, "{e}");

    let copy = match PeerExe::of(&exe) {
        Ok(c) => c,
        Err(why) => {
            eprintln!("skipped: no directory open to every user: {why}");
            return;
        }
    };
    assert!(reachable_by_all(&copy.exe), "{}", copy.exe.display());
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!((mode(&copy.dir), mode(&copy.exe)), (0o755, 0o755));
    let dir = copy.dir.clone();
    let peer = Peer(copy);
    match peer.command(NOBODY, NOBODY, &[]).output() {
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied => {
            eprintln!("skipped: {} is mounted noexec ({e})", dir.display());
            return;
        }
        r => assert!(r.unwrap().status.success()),
    }
    let got = peer.run("emu:no-such-card-private", NOBODY, NOBODY, &[]);
    assert!(got.starts_with("PEER-ERROR NotFound"), "{got}");
    drop(peer);
    assert!(!dir.exists(), "the copy is removed");
}

/// A lister the card's policy refuses is listed with the card "denied" (and told how to be
/// admitted) and takes nothing; one it admits reads the card's name and serial.
#[test]
fn a_lister_of_another_user_is_told_denied() {
    let name = format!("acl-list-{}", std::process::id());
    if !is_root() {
        skip("the cross-user part");
        let me = nix::unistd::geteuid().as_raw();
        let emu = Emulator::create(&name, &EmuOptions::default()).unwrap();
        let opts = ServeOptions::new(server::PeerPolicy::new(me + 1));
        let _server = Server::start_with(&name, emu.lessor(), opts).unwrap();
        let all = Card::list().unwrap();
        let l = all.iter().find(|l| l.uri == format!("emu:{name}")).unwrap();
        let e = l.error.as_ref().expect("denied");
        assert_eq!(e.kind, ErrorKind::PermissionDenied, "{}", e.message);
        assert!(
            e.message.contains(&format!("--allow-uid {me}")),
            "{}",
            e.message
        );
        return;
    }
    let Some(peer) = Peer::new("a_lister_of_another_user_is_told_denied") else {
        return;
    };
    let emu = Emu::start(&name, &["--serial", "4711"]);
    let got = peer.run(&format!("list:{name}"), NOBODY, NOBODY, &[]);
    assert!(got.starts_with("PEER-LISTED PermissionDenied"), "{got}");
    assert!(got.contains("refused uid 65534"), "{got}");
    assert!(got.contains("--allow-uid 65534"), "{got}");
    // Nothing taken: this process opens the card at once.
    drop(open_when_ready(&format!("emu:{name}")));
    drop(emu);
    let admitted = format!("acl-list-ok-{}", std::process::id());
    let _emu = Emu::start(&admitted, &["--serial", "4712", "--allow-uid", "65534"]);
    let got = peer.run(&format!("list:{admitted}"), NOBODY, NOBODY, &[]);
    assert_eq!(
        got,
        format!("PEER-LISTED ok {admitted} serial 4712 available true")
    );
}
