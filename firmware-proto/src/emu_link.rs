//! The host's side of the `emu:NAME` transport, and the greetings both sides speak: connect
//! to the abstract Unix socket `@motioncard/NAME` of a `card-emu` process, greet it
//! ([`host_hello`]), and receive its greeting ([`hello`]) with, in the same message with
//! `SCM_RIGHTS`, the memfd holding the DPRAM window and the interrupt eventfd. The connection
//! is the host's lease. The serving side is `card_emu::emu::server`.
//!
//! The host speaks first, so that a connection that says nothing never takes the card: the
//! server gives a host a deadline for its greeting and drops a connection that has not sent it
//! by then ([`STATUS_TIMEOUT`]).

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

/// Connect to the emulator serving `name`.
pub fn connect(name: &str) -> Result<Connection, ConnectError> {
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
    match send(stream.as_raw_fd(), &host_hello(), MsgFlags::MSG_NOSIGNAL) {
        Ok(16) | Err(nix::errno::Errno::EPIPE | nix::errno::Errno::ECONNRESET) => {}
        Ok(n) => {
            return Err(ConnectError::Io(std::io::Error::new(
                std::io::ErrorKind::WriteZero,
                format!("greeting the card: {n} of 16 bytes sent"),
            )))
        }
        Err(e) => return Err(ConnectError::Io(e.into())),
    }
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
    let n = msg.bytes;
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
        STATUS_OK => {}
        STATUS_BUSY => return Err(ConnectError::Busy),
        STATUS_DENIED => return Err(ConnectError::Denied { uid: word }),
        STATUS_TIMEOUT => {
            return Err(ConnectError::Protocol(format!(
                "card-emu dropped the connection: this host's greeting did not arrive within \
                 its {word} ms"
            )))
        }
        STATUS_VERSION => {
            return Err(ConnectError::Protocol(format!(
                "card-emu speaks version {word} of the emu: transport, this host version \
                 {VERSION}: run a card-emu of the same release as the SDK"
            )))
        }
        STATUS_FAILED => {
            return Err(ConnectError::Io(std::io::Error::from_raw_os_error(
                word as i32,
            )))
        }
        s => return Err(ConnectError::Protocol(format!("unknown status {s}"))),
    }
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
