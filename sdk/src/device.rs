//! The device layer: one mapped DPRAM window and one interrupt source per card, whatever the
//! backend. Everything above this module is the same for every backend.
//!
//! | URI | window | interrupt |
//! |---|---|---|
//! | `sim` | memfd, emulator thread in this process | eventfd |
//! | `emu:NAME` | memfd received from a `card-emu` process | eventfd received with it |
//! | `uio:/dev/uioN` | map 0 of the UIO device | the UIO fd (blocking read = count) |
//! | `pci:DDDD:BB:DD.F` | sysfs `resource0` | none: polling |
//! | `name:NAME` | the card listed ([`crate::Card::list`]) with that name, opened by its URI | its backend's |
//! | `serial:N` | the card listed with serial number N (decimal, 1 to 2^64-1), opened by its URI | its backend's |
//!
//! `name:` and `serial:` are resolved through the listing ([`crate::list`]): no card matches
//! is `NotFound` naming what was searched and what was listed; two or more is `Ambiguous`
//! naming them. The card opened is then the one its URI names, as if opened by that URI.

use crate::error::{Error, Result};
#[cfg(feature = "emulator")]
use card_emu::{Clock, EmuOptions, Emulator, Runner};
use firmware_proto::emu_link::{self, ConnectError};
use firmware_proto::window::MappedWindow;
use nix::fcntl::{Flock, FlockArg};
use std::fs::{File, OpenOptions};
use std::os::fd::{AsFd, BorrowedFd, OwnedFd};
use std::os::unix::net::UnixStream;
use std::sync::Arc;
#[cfg(feature = "emulator")]
use std::sync::Mutex;

/// The environment variable that sets up a real-time (or free-running) `sim` card for
/// debugging a host under gdb or valgrind: its value, in milliseconds (1 to 3,600,000), is the
/// card's watchdog timeout at boot and the least one a host can set on it
/// ([`crate::Card::set_watchdog_timeout`] asks for more or gets this). The watchdog stays
/// armed: a host that stops for longer still trips it. Unset (the default): 100 ms, and no
/// floor. A stepped card beats once per emulated tick and needs none of it.
pub const SIM_WATCHDOG_ENV: &str = "MOTIONCARD_SIM_WATCHDOG_MS";

/// The debugging watchdog timeout of [`SIM_WATCHDOG_ENV`], µs (`None`: unset). A value that is
/// not a whole number of milliseconds in 1..=3,600,000 is `BadConfig`.
pub fn sim_watchdog_from_env() -> Result<Option<u32>> {
    let Some(v) = std::env::var_os(SIM_WATCHDOG_ENV) else {
        return Ok(None);
    };
    let v = v.to_string_lossy();
    match v.trim().parse::<u32>() {
        Ok(ms @ 1..=3_600_000) => Ok(Some(ms * 1000)),
        _ => Err(Error::BadConfig(format!(
            "{SIM_WATCHDOG_ENV}={v}: the emulated card's debugging watchdog timeout is a whole \
             number of milliseconds, 1 to 3600000"
        ))),
    }
}

#[cfg(feature = "emulator")]
/// How an in-process emulated card (`sim`) is built and driven. [`crate::Card::open_sim`]
/// refuses axes outside 1..=8 and servo rates outside 1,000..=20,000 Hz
/// ([`crate::ErrorKind::BadConfig`]) rather than let the card clamp them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimOptions {
    /// Real-time (the default), free-running, or stepped (time advances only when the
    /// application calls [`crate::Sim::step`] or waits; deterministic).
    pub clock: Clock,
    /// Axes, servo rate and plant.
    pub emu: EmuOptions,
}

#[cfg(feature = "emulator")]
impl Default for SimOptions {
    fn default() -> Self {
        Self {
            clock: Clock::RealTime,
            emu: EmuOptions::default(),
        }
    }
}

/// The interrupt source.
pub(crate) enum Irq {
    /// An eventfd: read 8 bytes to clear.
    EventFd(OwnedFd),
    /// A UIO device: read 4 bytes (the interrupt count); write 1 to re-enable.
    Uio(File),
    /// No interrupt line: waits poll the window.
    None,
}

impl Irq {
    pub(crate) fn fd(&self) -> Option<BorrowedFd<'_>> {
        match self {
            Irq::EventFd(fd) => Some(fd.as_fd()),
            Irq::Uio(f) => Some(f.as_fd()),
            Irq::None => None,
        }
    }

    /// Clear a pending interrupt (never blocks: called after poll said readable).
    pub(crate) fn acknowledge(&self) {
        match self {
            Irq::EventFd(fd) => {
                let mut b = [0u8; 8];
                let _ = nix::unistd::read(fd, &mut b);
            }
            Irq::Uio(f) => {
                let mut b = [0u8; 4];
                let _ = nix::unistd::read(f, &mut b);
                let _ = nix::unistd::write(f, &1u32.to_ne_bytes());
            }
            Irq::None => {}
        }
    }
}

/// What keeps a backend alive.
pub(crate) enum Backend {
    /// In-process emulator driven by a clock thread.
    #[cfg(feature = "emulator")]
    SimRunning { _runner: Runner },
    /// In-process emulator stepped by the application.
    #[cfg(feature = "emulator")]
    SimStepped { emu: Arc<Mutex<Emulator>> },
    /// A card-emu process; the stream is our lease.
    Emu { lease: UnixStream },
    /// A real card, locked with flock on this file.
    Hardware { _lock: Flock<File> },
}

/// An opened device: window + interrupt + backend.
pub(crate) struct Device {
    /// The least watchdog timeout a host may set, µs (0: none): a `sim` card set up for
    /// debugging ([`SIM_WATCHDOG_ENV`]).
    pub watchdog_floor_us: u32,
    pub window: Arc<MappedWindow>,
    pub irq: Irq,
    pub backend: Backend,
    /// Marks the URI open in this process while the device lives (see [`Held`]); last, so
    /// that it is let go after the backend.
    held: Option<Held>,
}

impl Backend {
    /// The emulator of a stepped `sim` card.
    #[cfg(feature = "emulator")]
    pub(crate) fn stepped(&self) -> Option<&Arc<Mutex<Emulator>>> {
        match self {
            Backend::SimStepped { emu } => Some(emu),
            _ => None,
        }
    }

    /// Is it a stepped `sim` card (its time advances only when the host steps it)?
    pub(crate) fn is_stepped(&self) -> bool {
        #[cfg(feature = "emulator")]
        return self.stepped().is_some();
        #[cfg(not(feature = "emulator"))]
        false
    }
}

impl Device {
    /// A duplicate of the `emu:` connection, for the heartbeat thread to watch: it hangs up
    /// when the card process goes away. `None` for other backends.
    pub(crate) fn lease_watch(&self) -> Option<OwnedFd> {
        match &self.backend {
            Backend::Emu { lease } => lease.as_fd().try_clone_to_owned().ok(),
            _ => None,
        }
    }

    /// End an `emu:` lease now, so that the next host can open the card at once: shut down
    /// this side and wait (up to 1 s) for the server's end to close, which it does after it
    /// has let the lease go. A host that dies ends its lease too, but the server notices that
    /// only a little later.
    pub(crate) fn release_lease(&self) {
        if let Backend::Emu { lease } = &self.backend {
            use std::io::Read;
            let _ = lease.shutdown(std::net::Shutdown::Write);
            let _ = lease.set_read_timeout(Some(std::time::Duration::from_secs(1)));
            let mut b = [0u8; 64];
            while matches!((&*lease).read(&mut b), Ok(n) if n > 0) {}
        }
    }
}

/// The URIs of the cards this process has open (`emu:`, `uio:`, `pci:`; every `sim` is a card
/// of its own): a second open of one of them is [`Error::Busy`] that says the card is open in
/// this process, not in another.
static OPEN_HERE: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

/// A URI in [`OPEN_HERE`] for as long as it lives.
struct Held(String);

impl Held {
    /// Mark `uri` open here; `None` when it already is.
    fn take(uri: &str) -> Option<Held> {
        let mut open = crate::lock::lock(&OPEN_HERE);
        if open.iter().any(|u| u == uri) {
            return None;
        }
        open.push(uri.to_string());
        Some(Held(uri.to_string()))
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        crate::lock::lock(&OPEN_HERE).retain(|u| *u != self.0);
    }
}

/// The URIs this process has open (`emu:`, `uio:`, `pci:`).
pub(crate) fn open_here() -> Vec<String> {
    crate::lock::lock(&OPEN_HERE).clone()
}

/// Parse and open a card URI.
pub(crate) fn open(uri: &str) -> Result<Device> {
    if uri == "sim" {
        return open_uri(uri);
    }
    let held = Held::take(uri).ok_or_else(|| Error::Busy {
        uri: uri.into(),
        in_this_process: true,
    })?;
    let mut dev = open_uri(uri)?;
    dev.held = Some(held);
    Ok(dev)
}

fn open_uri(uri: &str) -> Result<Device> {
    if uri == "sim" {
        #[cfg(feature = "emulator")]
        return open_sim(&SimOptions::default());
        #[cfg(not(feature = "emulator"))]
        return Err(Error::Unsupported(
            "sim: this library was built without the emulated card (feature `emulator`)".into(),
        ));
    }
    if let Some(name) = uri.strip_prefix("emu:") {
        if name.is_empty() || name.len() > 100 || name.contains('\0') {
            return Err(Error::BadUri(uri.into()));
        }
        return open_emu(uri, name);
    }
    if let Some(path) = uri.strip_prefix("uio:") {
        let n = path
            .strip_prefix("/dev/uio")
            .filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
        return match n {
            Some(n) => open_uio(uri, path, n),
            None => Err(Error::BadUri(uri.into())),
        };
    }
    if let Some(addr) = uri.strip_prefix("pci:") {
        if !is_pci_address(addr) {
            return Err(Error::BadUri(uri.into()));
        }
        return open_pci(uri, addr);
    }
    Err(Error::BadUri(uri.into()))
}

#[cfg(feature = "emulator")]
pub(crate) fn open_sim(opts: &SimOptions) -> Result<Device> {
    let (axes, hz) = (opts.emu.axes, opts.emu.servo_rate_hz);
    if !(1..=firmware_proto::MAX_AXES).contains(&axes) {
        return Err(Error::BadConfig(format!(
            "{axes} axes: an emulated card has 1 to {}",
            firmware_proto::MAX_AXES
        )));
    }
    let rates = firmware_proto::SERVO_RATE_MIN_HZ..=firmware_proto::SERVO_RATE_MAX_HZ;
    if !rates.contains(&hz) {
        return Err(Error::BadConfig(format!(
            "servo rate {hz} Hz: the card runs at {} to {} Hz",
            rates.start(),
            rates.end()
        )));
    }
    // [safety] debugging (SIM_WATCHDOG_ENV): a longer watchdog timeout, still armed; a
    // stepped card beats once per tick and keeps what it was given.
    let floor = match opts.clock {
        Clock::Stepped => None,
        _ => sim_watchdog_from_env()?,
    };
    let mut emu_opts = opts.emu;
    if let Some(us) = floor {
        emu_opts.watchdog_timeout_us = emu_opts.watchdog_timeout_us.max(us);
    }
    let emu = Emulator::create("sim", &emu_opts)
        .map_err(|e| Error::io("creating the emulated card", e))?;
    sim_device(emu, opts.clock, floor)
}

/// Layout 1.12: `n` in-process emulated cards on one sync bus, the first its master (named
/// `sim0`, `sim1`, …): stepped ones are stepped together by their hosts
/// ([`crate::CardSet::sim`]), running ones follow the master's thread.
#[cfg(feature = "emulator")]
pub(crate) fn open_sim_bus(opts: &SimOptions, n: usize) -> Result<Vec<Device>> {
    let one = open_sim(opts)?; // the checks of one card's options
    drop(one);
    let floor = match opts.clock {
        Clock::Stepped => None,
        _ => sim_watchdog_from_env()?,
    };
    let mut emu_opts = opts.emu;
    if let Some(us) = floor {
        emu_opts.watchdog_timeout_us = emu_opts.watchdog_timeout_us.max(us);
    }
    let io = |what: &'static str| move |e| Error::io(what, e);
    let mut emus = Vec::with_capacity(n);
    let mut master =
        Emulator::create("sim0", &emu_opts).map_err(io("creating the emulated card"))?;
    let bus = master.lead_bus().map_err(io("starting the sync bus"))?;
    emus.push(master);
    for k in 1..n {
        let mut e = Emulator::create(&format!("sim{k}"), &emu_opts)
            .map_err(io("creating the emulated card"))?;
        let (link, _id) = bus.join().map_err(io("joining the sync bus"))?;
        e.follow_bus(link).map_err(io("joining the sync bus"))?;
        emus.push(e);
    }
    drop(bus);
    emus.into_iter()
        .map(|e| sim_device(e, opts.clock, floor))
        .collect()
}

/// The device of an in-process emulated card, on `clock`.
#[cfg(feature = "emulator")]
fn sim_device(emu: Emulator, clock: Clock, floor: Option<u32>) -> Result<Device> {
    let window = emu.window().clone();
    let irq = emu
        .irq_fd()
        .map_err(|e| Error::io("duplicating the interrupt eventfd", e))?;
    let backend = match clock {
        Clock::Stepped => Backend::SimStepped {
            emu: Arc::new(Mutex::new(emu)),
        },
        clock => Backend::SimRunning {
            _runner: Runner::spawn(emu, clock, false)
                .map_err(|e| Error::io("starting the emulator thread", e))?,
        },
    };
    Ok(Device {
        watchdog_floor_us: floor.unwrap_or(0),
        window,
        irq: Irq::EventFd(irq),
        backend,
        held: None,
    })
}

fn open_emu(uri: &str, name: &str) -> Result<Device> {
    let conn = emu_link::connect(name).map_err(|e| match e {
        ConnectError::NotFound => Error::NotFound {
            uri: uri.into(),
            reason: format!(
                "no card-emu process is serving '{name}' (start one with `card-emu --name {name}`)"
            ),
        },
        ConnectError::Busy => Error::Busy {
            uri: uri.into(),
            in_this_process: false,
        },
        ConnectError::Denied { uid } => Error::PermissionDenied {
            uri: uri.into(),
            reason: format!(
                "card-emu refused uid {uid}; it admits its own user, root, and the users and \
                 groups its operator allows: restart it with `--allow-uid {uid}` (or \
                 `--allow-group GROUP` for a group of this user)"
            ),
        },
        ConnectError::Protocol(m) => Error::Protocol(format!("{uri}: {m}")),
        ConnectError::Io(e) => Error::io(format!("connecting to {uri}"), e),
    })?;
    // An unsealed or short window is the server breaking the protocol: its size could change
    // under our mapping (SIGBUS).
    let window = MappedWindow::from_fd(conn.window).map_err(|e| {
        if e.kind() == std::io::ErrorKind::InvalidData {
            Error::Protocol(format!("{uri}: {e}"))
        } else {
            Error::io(format!("mapping the DPRAM of {uri}"), e)
        }
    })?;
    Ok(Device {
        watchdog_floor_us: 0,
        window: Arc::new(window),
        irq: Irq::EventFd(conn.irq),
        backend: Backend::Emu { lease: conn.lease },
        held: None,
    })
}

/// Take the card for this process: a second opener gets [`Error::Busy`]. The lock is held
/// by a duplicate descriptor for as long as the device is open.
fn lock_exclusive(uri: &str, file: &File) -> Result<Flock<File>> {
    let dup = file
        .try_clone()
        .map_err(|e| Error::io(format!("locking {uri}"), e))?;
    Flock::lock(dup, FlockArg::LockExclusiveNonblock).map_err(|(_, e)| match e {
        nix::errno::Errno::EWOULDBLOCK => Error::Busy {
            uri: uri.into(),
            in_this_process: false,
        },
        e => Error::io(format!("locking {uri}"), e),
    })
}

fn not_found(uri: &str, path: &str, e: std::io::Error) -> Error {
    if e.kind() == std::io::ErrorKind::NotFound {
        Error::NotFound {
            uri: uri.into(),
            reason: format!("{path} does not exist"),
        }
    } else {
        Error::io(format!("opening {path}"), e)
    }
}

fn open_uio(uri: &str, path: &str, n: &str) -> Result<Device> {
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map_err(|e| not_found(uri, path, e))?;
    let lock = lock_exclusive(uri, &file)?;
    let size_path = format!("/sys/class/uio/uio{n}/maps/map0/size");
    let size = std::fs::read_to_string(&size_path).map_err(|e| not_found(uri, &size_path, e))?;
    let size = usize::from_str_radix(size.trim().trim_start_matches("0x"), 16)
        .map_err(|_| Error::Protocol(format!("{size_path}: unreadable size '{}'", size.trim())))?;
    if size < firmware_proto::DPRAM_SIZE {
        return Err(Error::Protocol(format!(
            "{uri}: map0 is {size} bytes, the DPRAM layout needs {}",
            firmware_proto::DPRAM_SIZE
        )));
    }
    // UIO selects map N with offset N * page size; map 0 is the DPRAM BAR.
    let irq_file = file
        .try_clone()
        .map_err(|e| Error::io(format!("opening {path}"), e))?;
    let window = MappedWindow::map(file, 0, firmware_proto::DPRAM_SIZE)
        .map_err(|e| Error::io(format!("mapping {path}"), e))?;
    // Enable the interrupt (uio_pci_generic and most UIO drivers take a write of 1).
    let _ = nix::unistd::write(&irq_file, &1u32.to_ne_bytes());
    Ok(Device {
        watchdog_floor_us: 0,
        window: Arc::new(window),
        irq: Irq::Uio(irq_file),
        backend: Backend::Hardware { _lock: lock },
        held: None,
    })
}

fn open_pci(uri: &str, addr: &str) -> Result<Device> {
    let path = format!("/sys/bus/pci/devices/{addr}/resource0");
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .open(&path)
        .map_err(|e| not_found(uri, &path, e))?;
    let lock = lock_exclusive(uri, &file)?;
    let window = MappedWindow::map(file, 0, firmware_proto::DPRAM_SIZE)
        .map_err(|e| Error::io(format!("mapping {path}"), e))?;
    Ok(Device {
        watchdog_floor_us: 0,
        window: Arc::new(window),
        irq: Irq::None,
        backend: Backend::Hardware { _lock: lock },
        held: None,
    })
}

/// `DDDD:BB:DD.F`, hexadecimal, as sysfs names PCI functions.
fn is_pci_address(s: &str) -> bool {
    let b = s.as_bytes();
    let hex = |r: core::ops::Range<usize>| b[r].iter().all(u8::is_ascii_hexdigit);
    b.len() == 12
        && b[4] == b':'
        && b[7] == b':'
        && b[10] == b'.'
        && hex(0..4)
        && hex(5..7)
        && hex(8..10)
        && (b'0'..=b'7').contains(&b[11])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;

    fn kind(uri: &str) -> ErrorKind {
        match open(uri) {
            Ok(_) => panic!("{uri} opened"),
            Err(e) => e.kind(),
        }
    }

    #[test]
    fn uri_parsing() {
        assert!(is_pci_address("0000:03:00.0"));
        assert!(!is_pci_address("0000:03:00.8"));
        assert!(!is_pci_address("0000:3:00.0"));
        for bad in [
            "",
            "simulator",
            "emu:",
            "uio:/dev/uio",
            "uio:/dev/sda",
            "pci:00:03.0",
            "http://x",
        ] {
            assert_eq!(kind(bad), ErrorKind::BadUri, "{bad}");
        }
    }

    #[test]
    #[cfg(feature = "emulator")]
    fn out_of_range_sims_are_refused_not_clamped() {
        let sim = |axes, hz| {
            open_sim(&SimOptions {
                clock: Clock::Stepped,
                emu: EmuOptions::new(axes, hz),
            })
        };
        for (axes, hz) in [(0, 10_000), (9, 10_000), (2, 999), (2, 20_001), (2, 0)] {
            let e = sim(axes, hz).err().expect("opened");
            assert_eq!(e.kind(), ErrorKind::BadConfig, "{axes} axes, {hz} Hz");
        }
        for (axes, hz) in [(1, 1000), (8, 20_000)] {
            assert!(sim(axes, hz).is_ok(), "{axes} axes, {hz} Hz");
        }
    }

    #[test]
    fn absent_hardware_is_not_found() {
        assert_eq!(kind("uio:/dev/uio987"), ErrorKind::NotFound);
        assert_eq!(kind("pci:0000:fe:1f.7"), ErrorKind::NotFound);
        assert_eq!(kind("emu:nobody-serves-this-name"), ErrorKind::NotFound);
    }
}
