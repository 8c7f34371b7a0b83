//! Serving a card to another process (`emu:NAME`), the way vhost-user hands guest memory and
//! kick/call fds to a device process.
//!
//! The emulator listens on the abstract Unix socket `@motioncard/NAME` (no file to clean up; it
//! disappears with the process). A host connects and greets the server
//! ([`firmware_proto::emu_link::host_hello`]); the server answers with its greeting and, in the
//! same message with `SCM_RIGHTS`, the memfd holding the DPRAM window and the interrupt
//! eventfd; both sides map the same memory. The connection is the host's lease: while it is
//! open, other hosts are answered "busy"; when it closes (the host exited or was killed) the
//! card can be opened again. The card itself keeps running either way, like hardware.
//!
//! # The greeting and its deadline
//!
//! The host speaks first, and the card is leased only to a connection that has sent a whole
//! greeting of this version of the transport: a connection that says nothing never takes it.
//! One whose greeting has not arrived within [`HANDSHAKE_DEADLINE`] (2 s, or
//! [`ServeOptions::handshake_deadline`]) is answered "timeout" and closed, and its uid logged
//! once. Each admitted connection waits for its greeting on a thread of its own, so one that
//! says nothing holds up nobody; at most [`MAX_HANDSHAKES`] wait at once, and the next ones are
//! answered "busy".
//!
//! # Who the card is, without taking it
//!
//! A lister (`Card::list`, `mcctl list`) greets with
//! [`firmware_proto::emu_link::info_hello`] instead: once its peer is admitted (the same
//! policy, the same deadline), the server answers with the card's identity and `card_info`
//! read from its window and whether a host holds the lease
//! ([`firmware_proto::emu_link::CardRecord`]), and closes. It takes no lease, makes no window,
//! and the card's thread never waits for it: a host that holds the card sees nothing of it.
//!
//! # A window per lease
//!
//! Each lease gets a window and an interrupt line of its own ([`LeaseSource`]; the emulator's
//! is its `Lessor`): between two ticks the card copies its window into a new sealed memfd,
//! maps that over its own mapping in place, and raises its interrupt on a new eventfd from then
//! on; the server hands those two to the host and keeps no descriptor of them. A past host
//! that kept the memfd, its mapping or the eventfd after its lease ended holds memory the card
//! no longer reads and an eventfd it no longer raises: it cannot reach the card of a later
//! host.
//!
//! # Who may connect
//!
//! An abstract socket has no file, so no file permissions: any process in the network
//! namespace can connect. The server therefore checks each peer's credentials as the kernel
//! recorded them at `connect()` (`SO_PEERCRED`: effective uid and gid; `SO_PEERGROUPS`: the
//! supplementary groups) against a [`PeerPolicy`] before anything else: its own effective uid
//! and root are admitted, and the uids and groups the operator adds (`card-emu --allow-uid`,
//! `--allow-group`); a group admits a peer whose effective gid or any supplementary group is
//! that group. A refused peer gets the greeting status "denied" with its uid, no descriptors,
//! and the connection is closed; it never takes the lease, so it cannot keep other hosts out
//! either.
//!
//! # What the lease protects, and what it does not
//!
//! The lease keeps a second *SDK host* out: only the process holding the connection received
//! the window from the server, and the window of an earlier lease is no longer the card's. It
//! is not a wall around the current window. A process that may open `/proc/PID/fd/N` of the
//! card-emu process or of the current host (the kernel's ptrace read-access check: in practice
//! the same user, or root) can map the same memfd and write anything into it, and the card
//! cannot tell its writes from the host's. The card then does what it does with any host:
//! - every command is validated, and an invalid one is nacked without effect; a well-formed
//!   one is executed whoever wrote it, and a write to the heartbeat feeds the watchdog;
//! - configuration blocks are validated when a command applies them;
//! - a command ring whose head is more than the ring's length past the card's tail is not
//!   followed: the card drops its entries, stops every axis that is not disabled (category 1,
//!   or 0 where no ramp can be planned; each ends in ErrorStop), counts it in
//!   `protocol_errors`, and posts a protocol-error event and a safety-stop event
//!   (`Firmware::serve_commands` → `Safety::protocol_error`);
//! - inconsistent event-ring indices stop every axis the same way at the next tick
//!   (`StopReason::EvtRing`); the events it cannot post are counted in `events_lost`;
//! - card-written fields (status blocks, events) can be overwritten too: the SDK's checks
//!   (magic, checksums, indices, state values) catch garbage, not a writer that computes the
//!   checksums.
//!
//! Nobody can resize the window: its seals ([`firmware_proto::window::WINDOW_SEALS`]) make `ftruncate`
//! fail with `EPERM`, so no process can shrink it under the card's mapping.

use firmware_proto::emu_link::{
    hello, socket_name, CardRecord, HOST_HELLO, INFO_HELLO, RECORD_LEN, STATUS_BUSY, STATUS_DENIED,
    STATUS_FAILED, STATUS_OK, STATUS_TIMEOUT, STATUS_VERSION, VERSION,
};
use nix::sys::socket::{getsockopt, sendmsg, sockopt, ControlMessage, MsgFlags};
use std::collections::BTreeSet;
use std::io::{IoSlice, Read};
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixListener, UnixStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// A connecting process's credentials, as the kernel recorded them when it called `connect()`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PeerCred {
    /// Effective user id.
    pub uid: u32,
    /// Effective group id.
    pub gid: u32,
    /// Process id (for the log only: it may be gone or reused by now).
    pub pid: i32,
    /// Supplementary groups.
    pub groups: Vec<u32>,
}

// SO_PEERGROUPS (Linux 4.13) is not in the libc crate for every target; its value is 59
// everywhere but SPARC.
#[cfg(any(target_arch = "sparc", target_arch = "sparc64"))]
const SO_PEERGROUPS: nix::libc::c_int = 0x3d;
#[cfg(not(any(target_arch = "sparc", target_arch = "sparc64")))]
const SO_PEERGROUPS: nix::libc::c_int = 59;

impl PeerCred {
    /// The credentials of the process at the other end of `stream`.
    pub fn of(stream: &UnixStream) -> std::io::Result<Self> {
        let c = getsockopt(stream, sockopt::PeerCredentials)?;
        Ok(Self {
            uid: c.uid(),
            gid: c.gid(),
            pid: c.pid(),
            groups: peer_groups(stream)?,
        })
    }
}

fn peer_groups(stream: &UnixStream) -> std::io::Result<Vec<u32>> {
    let mut groups: Vec<nix::libc::gid_t> = vec![0; 64];
    loop {
        let mut len = (groups.len() * size_of::<nix::libc::gid_t>()) as nix::libc::socklen_t;
        // SAFETY: the buffer is `len` bytes of writable, aligned gid_t storage; the kernel
        // writes at most `len` bytes and sets `len` to what it wrote (or needs, with ERANGE).
        let r = unsafe {
            nix::libc::getsockopt(
                stream.as_raw_fd(),
                nix::libc::SOL_SOCKET,
                SO_PEERGROUPS,
                groups.as_mut_ptr().cast(),
                &mut len,
            )
        };
        let n = len as usize / size_of::<nix::libc::gid_t>();
        if r == 0 {
            groups.truncate(n);
            return Ok(groups);
        }
        let e = std::io::Error::last_os_error();
        match e.raw_os_error() {
            Some(nix::libc::ERANGE) if n > groups.len() && n <= 1 << 16 => groups.resize(n, 0),
            _ => return Err(e),
        }
    }
}

/// Who may connect to a served card: the server's own user and root always, plus the uids
/// and groups the operator allows. Pure: [`PeerPolicy::admits`] only compares numbers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PeerPolicy {
    owner: u32,
    uids: BTreeSet<u32>,
    gids: BTreeSet<u32>,
}

impl PeerPolicy {
    /// Admit `owner` (the server's effective uid) and root only.
    pub fn new(owner: u32) -> Self {
        Self {
            owner,
            uids: BTreeSet::new(),
            gids: BTreeSet::new(),
        }
    }

    /// Admit the user of this process (its effective uid) and root only.
    pub fn this_user() -> Self {
        Self::new(nix::unistd::geteuid().as_raw())
    }

    /// Also admit user `uid`.
    pub fn allow_uid(mut self, uid: u32) -> Self {
        self.uids.insert(uid);
        self
    }

    /// Also admit every peer whose effective gid or one of whose supplementary groups is
    /// `gid`.
    pub fn allow_gid(mut self, gid: u32) -> Self {
        self.gids.insert(gid);
        self
    }

    /// The server's own uid.
    pub fn owner(&self) -> u32 {
        self.owner
    }

    /// May `peer` connect?
    pub fn admits(&self, peer: &PeerCred) -> bool {
        peer.uid == self.owner
            || peer.uid == 0
            || self.uids.contains(&peer.uid)
            || self.gids.contains(&peer.gid)
            || peer.groups.iter().any(|g| self.gids.contains(g))
    }
}

impl std::fmt::Display for PeerPolicy {
    /// "uid 1000, root, uids 33 65534, groups 27".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "uid {}, root", self.owner)?;
        let list = |s: &BTreeSet<u32>| s.iter().map(u32::to_string).collect::<Vec<_>>().join(" ");
        if !self.uids.is_empty() {
            write!(f, ", uids {}", list(&self.uids))?;
        }
        if !self.gids.is_empty() {
            write!(f, ", groups {}", list(&self.gids))?;
        }
        Ok(())
    }
}

/// A group given by name or number (`card-emu --allow-group`) as its gid.
pub fn resolve_group(group: &str) -> Result<u32, String> {
    if let Ok(gid) = group.parse::<u32>() {
        return Ok(gid);
    }
    match nix::unistd::Group::from_name(group) {
        Ok(Some(g)) => Ok(g.gid.as_raw()),
        Ok(None) => Err(format!("no group named '{group}'")),
        Err(e) => Err(format!("looking up group '{group}': {e}")),
    }
}

/// How long a connecting host has to send its greeting before the server drops the connection
/// ([`ServeOptions::handshake_deadline`]).
pub const HANDSHAKE_DEADLINE: Duration = Duration::from_secs(2);

/// Connections awaiting their greeting at once; the server answers the next ones "busy".
pub const MAX_HANDSHAKES: usize = 32;

/// The window and the interrupt line handed to one host.
pub struct LeaseFds {
    /// The DPRAM window's memfd, sealed ([`firmware_proto::window::WINDOW_SEALS`]).
    pub window: OwnedFd,
    /// The interrupt eventfd.
    pub irq: OwnedFd,
}

/// Where each host's window and interrupt line come from.
pub trait LeaseSource: Send + Sync + 'static {
    /// The window and the interrupt line of the host that takes the card now. Called once per
    /// lease, after the host's greeting, never for two leases at a time.
    fn next_lease(&self) -> std::io::Result<LeaseFds>;

    /// Who the card is, read from its window without writing to it, for a lister; `leased`:
    /// a host holds the card now. Called from any server thread, while a host may hold the
    /// card. By default an empty record (magic 0: listed as "not booted"), for a source
    /// that has no card to read.
    fn record(&self, leased: bool) -> CardRecord {
        CardRecord {
            leased,
            ..CardRecord::default()
        }
    }
}

/// How a server admits hosts.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// Who may connect.
    pub policy: PeerPolicy,
    /// How long a connection may take to send its greeting before it is dropped
    /// ([`HANDSHAKE_DEADLINE`] by default).
    pub handshake_deadline: Duration,
}

impl ServeOptions {
    /// Admit the peers `policy` admits, with the default deadline.
    pub fn new(policy: PeerPolicy) -> Self {
        Self {
            policy,
            handshake_deadline: HANDSHAKE_DEADLINE,
        }
    }
}

impl Default for ServeOptions {
    /// This user and root ([`PeerPolicy::this_user`]), [`HANDSHAKE_DEADLINE`].
    fn default() -> Self {
        Self::new(PeerPolicy::this_user())
    }
}

/// The listening side. Its accept thread never waits on a client: each admitted connection
/// gets a thread of its own for its greeting and, if it takes the card, its lease.
pub struct Server {
    name: String,
}

impl Server {
    /// Listen for card `name`, handing each host the window and interrupt line `source` makes
    /// for it (an emulator's `Lessor`: a new window per host), to this user and root with the
    /// default deadline ([`ServeOptions::default`]). Fails with `AddrInUse` when a card of that
    /// name is already served.
    pub fn start(name: &str, source: impl LeaseSource) -> std::io::Result<Self> {
        Self::start_with(name, source, ServeOptions::default())
    }

    /// [`Server::start`], admitting the peers `opts.policy` admits within its deadline.
    pub fn start_with(
        name: &str,
        source: impl LeaseSource,
        opts: ServeOptions,
    ) -> std::io::Result<Self> {
        let addr = SocketAddr::from_abstract_name(socket_name(name).as_bytes())?;
        let listener = UnixListener::bind_addr(&addr)?;
        let hosts = Arc::new(Hosts {
            source: Box::new(source),
            leased: AtomicBool::new(false),
            greeting: AtomicUsize::new(0),
            deadline: opts.handshake_deadline,
            late: Mutex::new(BTreeSet::new()),
        });
        let policy = opts.policy;
        let mut logged = BTreeSet::new();
        std::thread::Builder::new()
            .name("card-emu-accept".into())
            .spawn(move || {
                for stream in listener.incoming() {
                    let Ok(stream) = stream else { continue };
                    // Credentials first: a refused peer learns nothing, not even "busy", and
                    // is not waited for.
                    let Ok(peer) = PeerCred::of(&stream) else {
                        continue;
                    };
                    if !policy.admits(&peer) {
                        reply(&stream, STATUS_DENIED, peer.uid);
                        // Once per uid (and at most 64 uids), so a peer that keeps connecting
                        // cannot fill a log nobody reads and block this thread on it.
                        if logged.len() < 64 && logged.insert(peer.uid) {
                            eprintln!(
                                "card-emu: refused a host with uid {} gid {} (pid {}): this card \
                                 admits {policy}; allow it with --allow-uid {} or --allow-group",
                                peer.uid, peer.gid, peer.pid, peer.uid
                            );
                        }
                        continue;
                    }
                    if hosts.greeting.fetch_add(1, Ordering::AcqRel) >= MAX_HANDSHAKES {
                        hosts.greeting.fetch_sub(1, Ordering::AcqRel);
                        reply(&stream, STATUS_BUSY, 0);
                        continue;
                    }
                    let h = hosts.clone();
                    let spawned = std::thread::Builder::new()
                        .name("card-emu-host".into())
                        .spawn(move || h.serve(stream, peer));
                    if spawned.is_err() {
                        hosts.greeting.fetch_sub(1, Ordering::AcqRel);
                    }
                }
            })?;
        Ok(Self {
            name: name.to_string(),
        })
    }

    /// The card's name.
    pub fn name(&self) -> &str {
        &self.name
    }
}

/// What the threads of one server share.
struct Hosts {
    source: Box<dyn LeaseSource>,
    /// A host holds the card (from its greeting to the end of its connection).
    leased: AtomicBool,
    /// Connections awaiting their greeting.
    greeting: AtomicUsize,
    deadline: Duration,
    /// The uids already logged for a late greeting.
    late: Mutex<BTreeSet<u32>>,
}

/// What a connection sent before the deadline.
enum Greeting {
    /// A host of this version.
    Host,
    /// A lister of this version (it takes no lease).
    Info,
    /// A host of another version.
    Version,
    /// Nothing whole in time.
    Late,
    /// Not a host, or the connection closed.
    Gone,
}

impl Hosts {
    /// One admitted connection: its greeting within the deadline, then the lease.
    fn serve(&self, stream: UnixStream, peer: PeerCred) {
        let greeting = read_greeting(&stream, Instant::now() + self.deadline);
        self.greeting.fetch_sub(1, Ordering::AcqRel);
        match greeting {
            Greeting::Host => {}
            Greeting::Info => {
                let record = self.source.record(self.leased.load(Ordering::Acquire));
                let bytes = record.encode();
                // 128 bytes into an empty socket buffer: never blocks.
                let _ = sendmsg::<()>(
                    stream.as_raw_fd(),
                    &[
                        IoSlice::new(&hello(STATUS_OK, RECORD_LEN as u32)),
                        IoSlice::new(&bytes),
                    ],
                    &[],
                    MsgFlags::MSG_DONTWAIT | MsgFlags::MSG_NOSIGNAL,
                    None,
                );
                return;
            }
            Greeting::Version => return reply(&stream, STATUS_VERSION, VERSION.into()),
            Greeting::Gone => return,
            Greeting::Late => {
                let ms = self.deadline.as_millis().min(u32::MAX.into()) as u32;
                reply(&stream, STATUS_TIMEOUT, ms);
                let mut late = self.late.lock().unwrap_or_else(PoisonError::into_inner);
                if late.len() < 64 && late.insert(peer.uid) {
                    eprintln!(
                        "card-emu: dropped a connection of uid {} (pid {}) that sent no greeting \
                         within {ms} ms (an SDK older than this card-emu, or not a host)",
                        peer.uid, peer.pid
                    );
                }
                return;
            }
        }
        if self.leased.swap(true, Ordering::AcqRel) {
            return reply(&stream, STATUS_BUSY, 0);
        }
        // The lease ends when this function returns: the host closed its end (or died), or
        // it never got the card.
        struct Lease<'a>(&'a AtomicBool);
        impl Drop for Lease<'_> {
            fn drop(&mut self) {
                self.0.store(false, Ordering::Release);
            }
        }
        let lease = Lease(&self.leased);
        let fds = match self.source.next_lease() {
            Ok(fds) => fds,
            Err(e) => {
                eprintln!(
                    "card-emu: cannot make the window of a host with uid {} (pid {}): {e}",
                    peer.uid, peer.pid
                );
                let errno = e.raw_os_error().unwrap_or(nix::libc::EIO);
                return reply(&stream, STATUS_FAILED, errno as u32);
            }
        };
        let raw = [fds.window.as_raw_fd(), fds.irq.as_raw_fd()];
        let sent = sendmsg::<()>(
            stream.as_raw_fd(),
            &[IoSlice::new(&hello(STATUS_OK, 0))],
            &[ControlMessage::ScmRights(&raw)],
            MsgFlags::MSG_NOSIGNAL,
            None,
        );
        // The server keeps no descriptor of a host's window.
        drop(fds);
        if sent.is_err() || stream.set_read_timeout(None).is_err() {
            return;
        }
        let mut b = [0u8; 64];
        while matches!((&stream).read(&mut b), Ok(n) if n > 0) {}
        // Free the card, then close: a host that waits for the close (`Card::close`) can be
        // followed at once by the next.
        drop(lease);
        drop(stream);
    }
}

/// Read a host's greeting until `deadline`.
fn read_greeting(mut stream: &UnixStream, deadline: Instant) -> Greeting {
    let mut buf = [0u8; 16];
    let mut got = 0;
    while got < buf.len() {
        // The time left, not a fresh timeout per read: a peer sending a byte at a time gets no
        // longer than one that sends nothing.
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Greeting::Late;
        }
        if stream.set_read_timeout(Some(left)).is_err() {
            return Greeting::Gone;
        }
        match stream.read(&mut buf[got..]) {
            Ok(0) => return Greeting::Gone,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                return Greeting::Late
            }
            Err(_) => return Greeting::Gone,
        }
    }
    let info = buf[..6] == INFO_HELLO[..6];
    if buf[..6] != HOST_HELLO[..6] && !info {
        Greeting::Gone
    } else if buf[6] != VERSION {
        Greeting::Version
    } else if info {
        Greeting::Info
    } else {
        Greeting::Host
    }
}

/// Answer with a greeting without descriptors, never blocking and never raising SIGPIPE; the
/// connection closes when the caller drops it.
fn reply(stream: &UnixStream, status: u32, word: u32) {
    let _ = sendmsg::<()>(
        stream.as_raw_fd(),
        &[IoSlice::new(&hello(status, word))],
        &[],
        MsgFlags::MSG_DONTWAIT | MsgFlags::MSG_NOSIGNAL,
        None,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::emu_link::{connect, host_hello, ConnectError};
    use std::io::Write;

    fn peer(uid: u32, gid: u32, groups: &[u32]) -> PeerCred {
        PeerCred {
            uid,
            gid,
            pid: 1,
            groups: groups.to_vec(),
        }
    }

    #[test]
    fn the_owner_and_root_are_admitted_and_nobody_else_by_default() {
        let p = PeerPolicy::new(1000);
        assert!(p.admits(&peer(1000, 1000, &[])));
        assert!(p.admits(&peer(1000, 5, &[6, 7])));
        assert!(p.admits(&peer(0, 0, &[])));
        assert!(!p.admits(&peer(65534, 65534, &[])));
        assert!(
            !p.admits(&peer(1001, 1000, &[1000])),
            "the owner's gid is not a grant"
        );
        assert_eq!(p.to_string(), "uid 1000, root");
    }

    #[test]
    fn allowed_uids_are_admitted() {
        let p = PeerPolicy::new(0).allow_uid(65534).allow_uid(33);
        assert!(p.admits(&peer(65534, 65534, &[])));
        assert!(p.admits(&peer(33, 1, &[])));
        assert!(!p.admits(&peer(34, 1, &[])));
        assert!(!p.admits(&peer(1, 65534, &[65534])), "a uid is not a gid");
        assert_eq!(p.to_string(), "uid 0, root, uids 33 65534");
    }

    #[test]
    fn allowed_groups_admit_by_primary_or_supplementary_gid() {
        let p = PeerPolicy::new(0).allow_gid(27);
        assert!(p.admits(&peer(1000, 27, &[])));
        assert!(p.admits(&peer(1000, 1000, &[4, 27, 100])));
        assert!(!p.admits(&peer(1000, 1000, &[4, 100])));
        assert!(!p.admits(&peer(27, 1000, &[])), "a gid is not a uid");
        assert_eq!(p.to_string(), "uid 0, root, groups 27");
    }

    #[test]
    fn groups_resolve_by_number_or_name() {
        assert_eq!(resolve_group("4242"), Ok(4242));
        assert_eq!(resolve_group("root"), Ok(0));
        let e = resolve_group("no-such-group-motioncard").unwrap_err();
        assert!(e.contains("no group named"), "{e}");
    }

    #[test]
    fn peer_credentials_are_the_connecting_process() {
        let (a, b) = UnixStream::pair().unwrap();
        let c = PeerCred::of(&a).unwrap();
        assert_eq!(c.uid, nix::unistd::geteuid().as_raw());
        assert_eq!(c.gid, nix::unistd::getegid().as_raw());
        assert_eq!(c.pid, std::process::id() as i32);
        let mut mine: Vec<u32> = nix::unistd::getgroups()
            .unwrap()
            .iter()
            .map(|g| g.as_raw())
            .collect();
        let mut theirs = c.groups.clone();
        mine.sort_unstable();
        theirs.sort_unstable();
        assert_eq!(theirs, mine);
        drop(b);
    }

    /// A source that hands out one window (and counts the leases it made).
    struct Counted {
        window: firmware_proto::window::MappedWindow,
        leases: AtomicUsize,
    }

    impl Counted {
        fn new() -> Arc<Self> {
            Arc::new(Self {
                window: firmware_proto::window::MappedWindow::create("server-unit").unwrap(),
                leases: AtomicUsize::new(0),
            })
        }
    }

    impl LeaseSource for Arc<Counted> {
        fn next_lease(&self) -> std::io::Result<LeaseFds> {
            self.leases.fetch_add(1, Ordering::SeqCst);
            Ok(LeaseFds {
                window: self.window.dup_fd()?,
                irq: self.window.dup_fd()?,
            })
        }

        fn record(&self, leased: bool) -> CardRecord {
            CardRecord::read(&self.window, leased)
        }
    }

    fn raw(name: &str) -> UnixStream {
        let addr = SocketAddr::from_abstract_name(socket_name(name).as_bytes()).unwrap();
        let s = UnixStream::connect_addr(&addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        s
    }

    /// The server's greeting on `s` (status, word), then its end of the connection closed.
    fn answer_then_closed(mut s: &UnixStream) -> (u32, u32) {
        let mut m = [0u8; 16];
        s.read_exact(&mut m).unwrap();
        assert_eq!(m[..8], firmware_proto::emu_link::HELLO);
        let mut rest = [0u8; 1];
        assert_eq!(s.read(&mut rest).unwrap(), 0, "closed by the server");
        let word = |i: usize| u32::from_le_bytes(m[i..i + 4].try_into().unwrap());
        (word(8), word(12))
    }

    #[test]
    fn a_refused_peer_is_told_its_uid_and_gets_no_descriptors() {
        // A policy whose owner is not this process; as root (always admitted) only the
        // greeting is checked below.
        let me = nix::unistd::geteuid().as_raw();
        let name = format!("policy-unit-{}", std::process::id());
        let source = Counted::new();
        let opts = ServeOptions::new(PeerPolicy::new(me.wrapping_add(1)));
        let _s = Server::start_with(&name, source.clone(), opts).unwrap();
        match connect(&name) {
            Err(ConnectError::Denied { uid }) => {
                assert_ne!(me, 0);
                assert_eq!(uid, me);
                assert_eq!(source.leases.load(Ordering::SeqCst), 0);
            }
            Ok(_) => assert_eq!(me, 0, "only root passes a policy it does not own"),
            Err(e) => panic!("{e:?}"),
        }
    }

    /// A connection that says nothing does not take the card: a host that connects after it
    /// gets the card at once, and only that host's lease is made. At the deadline the silent
    /// one is answered "timeout" and closed. (Before the host greeted first, the server leased
    /// the card to whoever connected, and a silent client kept every host out.)
    #[test]
    fn a_silent_connection_takes_nothing_and_is_dropped_at_its_deadline() {
        let name = format!("squat-unit-{}", std::process::id());
        let source = Counted::new();
        let opts = ServeOptions {
            handshake_deadline: Duration::from_millis(300),
            ..ServeOptions::default()
        };
        let _s = Server::start_with(&name, source.clone(), opts).unwrap();
        let silent = raw(&name);
        let mut half = raw(&name);
        half.write_all(&host_hello()[..10]).unwrap(); // a greeting cut short
        let host = connect(&name).expect("a host while silent connections wait");
        assert_eq!(source.leases.load(Ordering::SeqCst), 1);
        assert_eq!(
            answer_then_closed(&silent),
            (STATUS_TIMEOUT, 300),
            "the silent one"
        );
        assert_eq!(
            answer_then_closed(&half),
            (STATUS_TIMEOUT, 300),
            "the slow one"
        );
        // The host still holds the card: the next one is busy.
        assert!(matches!(connect(&name), Err(ConnectError::Busy)));
        drop(host);
        assert_eq!(source.leases.load(Ordering::SeqCst), 1);
    }

    /// A greeting of another version is answered with the server's version; a connection
    /// that sends something else is closed without a word; neither takes the card.
    #[test]
    fn a_greeting_of_another_version_or_none_at_all_is_turned_away() {
        let name = format!("version-unit-{}", std::process::id());
        let source = Counted::new();
        let _s = Server::start(&name, source.clone()).unwrap();
        let mut other = raw(&name);
        let mut g = host_hello();
        g[6] = VERSION + 1;
        other.write_all(&g).unwrap();
        assert_eq!(answer_then_closed(&other), (STATUS_VERSION, VERSION.into()));
        let mut junk = raw(&name);
        junk.write_all(b"GET / HTTP/1.0\r\n").unwrap(); // 16 bytes, all read
        let mut b = [0u8; 16];
        assert_eq!(junk.read(&mut b).unwrap(), 0, "closed without a greeting");
        assert_eq!(source.leases.load(Ordering::SeqCst), 0);
        drop(connect(&name).unwrap());
        assert_eq!(source.leases.load(Ordering::SeqCst), 1);
    }

    /// Many silent connections: the ones past the limit are answered "busy" at once, and a
    /// host gets the card once the silent ones are gone.
    #[test]
    fn silent_connections_past_the_limit_are_answered_busy() {
        let name = format!("flood-unit-{}", std::process::id());
        let opts = ServeOptions {
            handshake_deadline: Duration::from_secs(60),
            ..ServeOptions::default()
        };
        let _s = Server::start_with(&name, Counted::new(), opts).unwrap();
        let silent: Vec<UnixStream> = (0..MAX_HANDSHAKES).map(|_| raw(&name)).collect();
        let past = raw(&name);
        assert_eq!(answer_then_closed(&past), (STATUS_BUSY, 0));
        drop(silent);
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            match connect(&name) {
                Ok(_) => break,
                Err(ConnectError::Busy) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                Err(e) => panic!("{e:?}"),
            }
        }
    }
}
