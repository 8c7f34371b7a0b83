//! The host's side of the `emu:NAME` transport, and the greetings both sides speak: connect
//! to the abstract Unix socket `@motioncard/NAME` of a `card-emu` process, greet it
//! ([`host_hello`]), and receive its greeting ([`hello`]) with, in the same message with
//! `SCM_RIGHTS`, the memfd holding the DPRAM window and the interrupt eventfd. The connection
//! is the host's lease. The serving side is `card_emu::emu::server`.
//!
//! The host speaks first, so that a connection that says nothing never takes the card: the
//! server gives a host a deadline for its greeting and drops a connection that has not sent it
//! by then ([`STATUS_TIMEOUT`]).
//!
//! A lister ([`query`]) greets with [`INFO_HELLO`] instead: the server answers with who the
//! card is ([`CardRecord`]: identity, name, serial, sync role, whether a host holds it) and
//! closes, without taking the lease, under the same peer policy (a refused peer gets
//! [`STATUS_DENIED`]). A server of this version that predates the info greeting closes such a
//! connection without a word ([`query`] says so).

use nix::sys::socket::{recvmsg, send, ControlMessageOwned, MsgFlags};
use std::io::IoSliceMut;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixStream};

/// The version of the transport: the sixth byte of both greetings. Version 1 had no host
/// greeting (the server spoke at once).
pub const VERSION: u8 = 2;
/// The server's greeting: magic and version (8 bytes), status (u32 LE), one status-specific
/// word (u32 LE: the refused uid for [`STATUS_DENIED`], the server's version for
/// [`STATUS_VERSION`], the deadline in ms for [`STATUS_TIMEOUT`], the errno for
/// [`STATUS_FAILED`], else 0).
pub const HELLO: [u8; 8] = *b"MCEMU\x02\0\0";
/// The host's greeting, which it sends first: magic and version (8 bytes), then 8 reserved
/// bytes, zero.
pub const HOST_HELLO: [u8; 8] = *b"MCHOST\x02\0";
/// A lister's greeting, in place of [`HOST_HELLO`]: magic and version (8 bytes), then 8
/// reserved bytes, zero. The server answers [`STATUS_OK`] with the length of the record in the
/// word, then the [`CardRecord`] (at least [`RECORD_LEN`] bytes: a later server may append
/// fields, which a reader of this version skips), and closes; it never takes the lease.
pub const INFO_HELLO: [u8; 8] = *b"MCINFO\x02\0";
/// The shortest [`CardRecord`] a server sends, bytes.
pub const RECORD_LEN: usize = 112;
/// The longest record a lister reads (a server's reply beyond it is a protocol violation).
pub const RECORD_MAX: usize = 4096;
/// The host has the card (the descriptors come with the greeting).
pub const STATUS_OK: u32 = 0;
/// Another host holds the card.
pub const STATUS_BUSY: u32 = 1;
/// The peer's credentials are not admitted by the server's `PeerPolicy`.
pub const STATUS_DENIED: u32 = 2;
/// The host's greeting came too late: the server closes the connection.
pub const STATUS_TIMEOUT: u32 = 3;
/// The host's greeting is of another version of the transport.
pub const STATUS_VERSION: u32 = 4;
/// The server could not make the host's window (an OS error, its errno in the word).
pub const STATUS_FAILED: u32 = 5;

/// The abstract socket name of card `name`.
pub fn socket_name(name: &str) -> String {
    format!("motioncard/{name}")
}

/// The greeting with `status` and its status-specific `word`.
pub fn hello(status: u32, word: u32) -> [u8; 16] {
    let mut m = [0u8; 16];
    m[..8].copy_from_slice(&HELLO);
    m[8..12].copy_from_slice(&status.to_le_bytes());
    m[12..16].copy_from_slice(&word.to_le_bytes());
    m
}

/// The host's greeting.
pub fn host_hello() -> [u8; 16] {
    let mut m = [0u8; 16];
    m[..8].copy_from_slice(&HOST_HELLO);
    m
}

/// A lister's greeting.
pub fn info_hello() -> [u8; 16] {
    let mut m = [0u8; 16];
    m[..8].copy_from_slice(&INFO_HELLO);
    m
}

/// Who a card is, as a lister sees it without taking the card: its identity block and its
/// `card_info` (layout 1.12; empty on an older card), and whether a host holds it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CardRecord {
    /// A host holds the card (an `emu:` lease; for hardware, its device file's lock).
    pub leased: bool,
    /// `identity.magic` (`MC_MAGIC` on a card that has booted).
    pub magic: u32,
    /// The DPRAM layout (major, minor).
    pub layout: (u16, u16),
    /// Firmware version, `major << 16 | minor << 8 | patch`.
    pub fw_version: u32,
    /// Axes on the card.
    pub axes: u32,
    /// Servo rate, Hz.
    pub servo_rate_hz: u32,
    /// `identity.card_state`.
    pub card_state: u32,
    /// The card's name (`card_info.name`).
    pub name: String,
    /// The board's serial number (0: none).
    pub serial: u64,
    /// `MC_BUS_ALONE`, `MC_BUS_MASTER` or `MC_BUS_FOLLOWER`.
    pub sync_role: u32,
    /// `MC_BUSST_FREE`, `MC_BUSST_LOCKED` or `MC_BUSST_LOST`.
    pub sync_state: u32,
    /// A follower's master's name (empty otherwise).
    pub sync_master: String,
    /// A master's followers on the bus now.
    pub sync_followers: u32,
}

/// A NUL-padded name as text (lossy: the card's bytes are not trusted to be UTF-8).
fn text(b: &[u8]) -> String {
    let n = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8_lossy(&b[..n]).into_owned()
}

fn padded(s: &str) -> [u8; 32] {
    let mut b = [0u8; 32];
    let n = s.len().min(31);
    b[..n].copy_from_slice(&s.as_bytes()[..n]);
    b
}

impl CardRecord {
    /// Read it from a card's window, without writing anything there. `card_info` changes
    /// while it is read (the card rewrites it whole when its sync state changes): it is read
    /// until two reads agree.
    pub fn read(mem: &impl crate::Mem, leased: bool) -> Self {
        use crate::layout;
        let lay = mem.read32(layout::LAYOUT);
        let layout = (lay as u16, (lay >> 16) as u16);
        let mut r = Self {
            leased,
            magic: mem.read32(layout::MAGIC),
            layout,
            fw_version: mem.read32(layout::FW_VERSION),
            axes: mem.read32(layout::NUM_AXES),
            servo_rate_hz: mem.read32(layout::SERVO_RATE_HZ),
            card_state: mem.read32(layout::CARD_STATE),
            ..Self::default()
        };
        if r.magic != crate::raw::MC_MAGIC || layout.0 != 1 || layout.1 < 12 {
            return r;
        }
        let mut info = layout::CARD_INFO.read(mem);
        for _ in 0..8 {
            let again = layout::CARD_INFO.read(mem);
            if crate::block::to_words::<_, 17>(&again) == crate::block::to_words::<_, 17>(&info) {
                break;
            }
            info = again;
        }
        let bytes = |c: &[core::ffi::c_char; 32]| c.map(|x| x as u8);
        r.name = text(&bytes(&info.name));
        r.serial = info.serial;
        r.sync_role = info.sync_role;
        r.sync_state = info.sync_state;
        r.sync_master = text(&bytes(&info.sync_master));
        r.sync_followers = info.sync_followers;
        r
    }

    /// The record as the server sends it ([`RECORD_LEN`] bytes, little-endian).
    pub fn encode(&self) -> [u8; RECORD_LEN] {
        let mut m = [0u8; RECORD_LEN];
        let mut put = |at: usize, b: &[u8]| m[at..at + b.len()].copy_from_slice(b);
        put(0, &u32::from(self.leased).to_le_bytes());
        put(4, &self.magic.to_le_bytes());
        put(8, &self.layout.0.to_le_bytes());
        put(10, &self.layout.1.to_le_bytes());
        put(12, &self.fw_version.to_le_bytes());
        put(16, &self.axes.to_le_bytes());
        put(20, &self.servo_rate_hz.to_le_bytes());
        put(24, &self.card_state.to_le_bytes());
        put(28, &self.sync_role.to_le_bytes());
        put(32, &self.serial.to_le_bytes());
        put(40, &self.sync_state.to_le_bytes());
        put(44, &self.sync_followers.to_le_bytes());
        put(48, &padded(&self.name));
        put(80, &padded(&self.sync_master));
        m
    }

    /// A record from a server's bytes: `None` when it is shorter than [`RECORD_LEN`]; bytes
    /// beyond it (a later server's fields) are skipped.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() < RECORD_LEN {
            return None;
        }
        let u32_at = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().expect("4 bytes"));
        let u16_at = |i: usize| u16::from_le_bytes(b[i..i + 2].try_into().expect("2 bytes"));
        Some(Self {
            leased: u32_at(0) != 0,
            magic: u32_at(4),
            layout: (u16_at(8), u16_at(10)),
            fw_version: u32_at(12),
            axes: u32_at(16),
            servo_rate_hz: u32_at(20),
            card_state: u32_at(24),
            sync_role: u32_at(28),
            serial: u64::from_le_bytes(b[32..40].try_into().expect("8 bytes")),
            sync_state: u32_at(40),
            sync_followers: u32_at(44),
            name: text(&b[48..80]),
            sync_master: text(&b[80..112]),
        })
    }
}

/// Why a connection to an emulator failed.
#[derive(Debug)]
pub enum ConnectError {
    /// Nothing serves that name.
    NotFound,
    /// Another host holds the card.
    Busy,
    /// The server's peer policy does not admit this process; `uid` is the effective uid
    /// the server saw.
    Denied {
        /// The refused uid.
        uid: u32,
    },
    /// The peer does not speak this protocol.
    Protocol(String),
    /// Any other I/O failure.
    Io(std::io::Error),
}

/// What a host gets from the emulator.
pub struct Connection {
    /// The DPRAM window's memfd.
    pub window: OwnedFd,
    /// The interrupt eventfd.
    pub irq: OwnedFd,
    /// The lease: keep it open while the card is in use.
    pub lease: UnixStream,
}

/// Connect to the abstract socket of `name` and send `greeting`.
fn dial(name: &str, greeting: &[u8; 16]) -> Result<UnixStream, ConnectError> {
    let addr =
        SocketAddr::from_abstract_name(socket_name(name).as_bytes()).map_err(ConnectError::Io)?;
    let stream = UnixStream::connect_addr(&addr).map_err(|e| match e.kind() {
        std::io::ErrorKind::ConnectionRefused | std::io::ErrorKind::NotFound => {
            ConnectError::NotFound
        }
        _ => ConnectError::Io(e),
    })?;
    let timeout = Some(std::time::Duration::from_secs(5));
    stream.set_read_timeout(timeout).map_err(ConnectError::Io)?;
    stream
        .set_write_timeout(timeout)
        .map_err(ConnectError::Io)?;
    // No SIGPIPE (a C host would die of it): a server that refused this peer at once has
    // closed its end, and its answer waits to be read below.
    match send(stream.as_raw_fd(), greeting, MsgFlags::MSG_NOSIGNAL) {
        Ok(16) | Err(nix::errno::Errno::EPIPE | nix::errno::Errno::ECONNRESET) => Ok(stream),
        Ok(n) => Err(ConnectError::Io(std::io::Error::new(
            std::io::ErrorKind::WriteZero,
            format!("greeting the card: {n} of 16 bytes sent"),
        ))),
        Err(e) => Err(ConnectError::Io(e.into())),
    }
}

/// The server's greeting (`n` bytes of `buf`) checked: its status-specific word when the status
/// is [`STATUS_OK`], else the error the status stands for.
fn answer(buf: &[u8; 16], n: usize) -> Result<u32, ConnectError> {
    if n != 16 || buf[..5] != HELLO[..5] {
        return Err(ConnectError::Protocol(format!(
            "unexpected greeting ({n} bytes)"
        )));
    }
    if buf[5] != VERSION {
        return Err(ConnectError::Protocol(format!(
            "card-emu speaks version {} of the emu: transport, this host version {VERSION}: \
             run a card-emu of the same release as the SDK",
            buf[5]
        )));
    }
    let word = u32::from_le_bytes([buf[12], buf[13], buf[14], buf[15]]);
    match u32::from_le_bytes([buf[8], buf[9], buf[10], buf[11]]) {
        STATUS_OK => Ok(word),
        STATUS_BUSY => Err(ConnectError::Busy),
        STATUS_DENIED => Err(ConnectError::Denied { uid: word }),
        STATUS_TIMEOUT => Err(ConnectError::Protocol(format!(
            "card-emu dropped the connection: this host's greeting did not arrive within its \
             {word} ms"
        ))),
        STATUS_VERSION => Err(ConnectError::Protocol(format!(
            "card-emu speaks version {word} of the emu: transport, this host version \
             {VERSION}: run a card-emu of the same release as the SDK"
        ))),
        STATUS_FAILED => Err(ConnectError::Io(std::io::Error::from_raw_os_error(
            word as i32,
        ))),
        s => Err(ConnectError::Protocol(format!("unknown status {s}"))),
    }
}

/// Who the card served as `name` is, without taking it: the info greeting ([`INFO_HELLO`]).
/// A host that holds the card is not disturbed (the record says it is leased). Errors as
/// [`connect`]'s, but never `Busy` for a leased card (only when the server is flooded with
/// connections awaiting their greeting).
pub fn query(name: &str) -> Result<CardRecord, ConnectError> {
    use std::io::Read;
    let mut stream = dial(name, &info_hello())?;
    let mut buf = [0u8; 16];
    let mut n = 0;
    while n < 16 {
        match stream.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(ConnectError::Io(e)),
        }
    }
    if n == 0 {
        return Err(ConnectError::Protocol(
            "card-emu closed the connection without answering the info greeting: it predates \
             card listing (run a card-emu of the same release as the SDK)"
                .into(),
        ));
    }
    let len = answer(&buf, n)? as usize;
    if !(RECORD_LEN..=RECORD_MAX).contains(&len) {
        return Err(ConnectError::Protocol(format!(
            "a card record of {len} bytes (expected {RECORD_LEN} to {RECORD_MAX})"
        )));
    }
    let mut rec = vec![0u8; len];
    stream.read_exact(&mut rec).map_err(|e| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            ConnectError::Protocol(format!("a card record cut short (of {len} bytes)"))
        } else {
            ConnectError::Io(e)
        }
    })?;
    CardRecord::decode(&rec).ok_or_else(|| ConnectError::Protocol("a short card record".into()))
}

/// Connect to the emulator serving `name`.
pub fn connect(name: &str) -> Result<Connection, ConnectError> {
    let stream = dial(name, &host_hello())?;
    let mut buf = [0u8; 16];
    let mut cmsg = nix::cmsg_space!([RawFd; 2]);
    let mut iov = [IoSliceMut::new(&mut buf)];
    let msg = recvmsg::<()>(
        stream.as_raw_fd(),
        &mut iov,
        Some(&mut cmsg),
        MsgFlags::MSG_CMSG_CLOEXEC,
    )
    .map_err(|e| ConnectError::Io(e.into()))?;
    let n = msg.bytes;
    let mut fds: Vec<OwnedFd> = Vec::new();
    for c in msg.cmsgs().map_err(|e| ConnectError::Io(e.into()))? {
        if let ControlMessageOwned::ScmRights(raw) = c {
            // SAFETY: the kernel just installed these descriptors in our table for us; nobody
            // else owns them.
            fds.extend(
                raw.into_iter()
                    .map(|fd| unsafe { OwnedFd::from_raw_fd(fd) }),
            );
        }
    }
    answer(&buf, n)?;
    if fds.len() != 2 {
        return Err(ConnectError::Protocol(format!(
            "expected 2 descriptors, got {}",
            fds.len()
        )));
    }
    stream.set_read_timeout(None).map_err(ConnectError::Io)?;
    let irq = fds.pop().expect("two fds");
    let window = fds.pop().expect("two fds");
    Ok(Connection {
        window,
        irq,
        lease: stream,
    })
}
