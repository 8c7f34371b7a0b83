//! Serving a card to another process (`emu:NAME`), the way vhost-user hands guest memory and
//! kick/call fds to a device process.
//!
//! The emulator listens on the abstract Unix socket `@motioncard/NAME` (no file to clean up; it
//! disappears with the process). A host connects and receives, in one message with
//! `SCM_RIGHTS`, the memfd holding the DPRAM window and the interrupt eventfd; both sides map
//! the same memory. The connection is the host's lease: while it is open, other hosts are
//! answered "busy"; when it closes (the host exited or was killed) the card can be opened
//! again. The card itself keeps running either way, like hardware.

use nix::sys::socket::{recvmsg, sendmsg, ControlMessage, ControlMessageOwned, MsgFlags};
use std::io::{IoSlice, IoSliceMut, Read};
use std::os::fd::{AsFd, AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixListener, UnixStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

const HELLO: [u8; 8] = *b"MCEMU\x01\0\0";
const STATUS_OK: u32 = 0;
const STATUS_BUSY: u32 = 1;

/// The abstract socket name of card `name`.
pub fn socket_name(name: &str) -> String {
    format!("motioncard/{name}")
}

fn hello(status: u32) -> [u8; 16] {
    let mut m = [0u8; 16];
    m[..8].copy_from_slice(&HELLO);
    m[8..12].copy_from_slice(&status.to_le_bytes());
    m
}

/// Why a connection to an emulator failed.
#[derive(Debug)]
pub enum ConnectError {
    /// Nothing serves that name.
    NotFound,
    /// Another host holds the card.
    Busy,
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

/// The listening side. Accepts hosts one at a time on a background thread.
pub struct Server {
    name: String,
}

impl Server {
    /// Listen for card `name`, handing out `window` and `irq`. Fails with `AddrInUse` when a
    /// card of that name is already served.
    pub fn start(name: &str, window: OwnedFd, irq: OwnedFd) -> std::io::Result<Self> {
        let addr = SocketAddr::from_abstract_name(socket_name(name).as_bytes())?;
        let listener = UnixListener::bind_addr(&addr)?;
        let leased = Arc::new(AtomicBool::new(false));
        std::thread::Builder::new()
            .name("card-emu-accept".into())
            .spawn(move || {
                for stream in listener.incoming() {
                    let Ok(stream) = stream else { continue };
                    if leased.swap(true, Ordering::AcqRel) {
                        let _ = sendmsg::<()>(
                            stream.as_raw_fd(),
                            &[IoSlice::new(&hello(STATUS_BUSY))],
                            &[],
                            MsgFlags::empty(),
                            None,
                        );
                        continue;
                    }
                    let fds = [window.as_fd().as_raw_fd(), irq.as_fd().as_raw_fd()];
                    let sent = sendmsg::<()>(
                        stream.as_raw_fd(),
                        &[IoSlice::new(&hello(STATUS_OK))],
                        &[ControlMessage::ScmRights(&fds)],
                        MsgFlags::empty(),
                        None,
                    );
                    if sent.is_err() {
                        leased.store(false, Ordering::Release);
                        continue;
                    }
                    let leased = leased.clone();
                    std::thread::spawn(move || {
                        // The lease ends when the host closes its end (or dies).
                        let mut stream = stream;
                        let mut b = [0u8; 64];
                        while matches!(stream.read(&mut b), Ok(n) if n > 0) {}
                        leased.store(false, Ordering::Release);
                    });
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
