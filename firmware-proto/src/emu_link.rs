//! The host's side of the `emu:NAME` transport, and the greeting both sides speak: connect
//! to the abstract Unix socket `@motioncard/NAME` of a `card-emu` process and receive, in one
//! message with `SCM_RIGHTS`, the memfd holding the DPRAM window and the interrupt eventfd.
//! The connection is the host's lease. The serving side is `card_emu::emu::server`.

use nix::sys::socket::{recvmsg, ControlMessageOwned, MsgFlags};
use std::io::IoSliceMut;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixStream};

/// The greeting: magic and version (8 bytes), status (u32 LE), one status-specific word
/// (u32 LE: the refused uid for [`STATUS_DENIED`], else 0).
pub const HELLO: [u8; 8] = *b"MCEMU\x01\0\0";
/// The host has the card (the descriptors come with the greeting).
pub const STATUS_OK: u32 = 0;
/// Another host holds the card.
pub const STATUS_BUSY: u32 = 1;
/// The peer's credentials are not admitted by the server's [`PeerPolicy`].
pub const STATUS_DENIED: u32 = 2;

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
    stream
        .set_read_timeout(Some(std::time::Duration::from_secs(5)))
        .map_err(ConnectError::Io)?;
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
    if n != 16 || buf[..8] != HELLO {
        return Err(ConnectError::Protocol(format!(
            "unexpected greeting ({n} bytes)"
        )));
    }
    match u32::from_le_bytes([buf[8], buf[9], buf[10], buf[11]]) {
        STATUS_OK => {}
        STATUS_BUSY => return Err(ConnectError::Busy),
        STATUS_DENIED => {
            let uid = u32::from_le_bytes([buf[12], buf[13], buf[14], buf[15]]);
            return Err(ConnectError::Denied { uid });
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
