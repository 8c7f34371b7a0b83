//! The cards reachable from this process ([`crate::Card::list`]), and opening one by its name
//! or serial number (`name:NAME`, `serial:N`), resolved through the listing.
//!
//! Where the cards are found, and how each is read without disturbing a host that uses it:
//!
//! | backend | found in | read |
//! |---|---|---|
//! | `emu:NAME` | the listening abstract sockets `@motioncard/NAME` of `/proc/net/unix` | the server's info greeting ([`firmware_proto::emu_link::query`]): no lease taken, the same peer policy |
//! | `uio:/dev/uioN` | `/sys/class/uio/uio*`: `name` is [`UIO_NAME`], or a `uio_pci_generic` device with one of [`PCI_IDS`] | map 0 mapped read-only, no lock taken |
//! | `pci:DDDD:BB:DD.F` | `/sys/bus/pci/devices/*` with one of [`PCI_IDS`] (not bound to UIO: that one is listed as `uio:`) | `resource0` mapped read-only, no lock taken |
//!
//! A hardware card is read from its window without the device file's lock (which is its
//! host's): the identity block and `card_info` only, read until two reads agree, and nothing is
//! written. Whether a host holds it is read from `/proc/locks` (the flock of its device file),
//! not by trying the lock, which would make a host opening it at that instant fail. When the
//! window cannot be mapped (no permission to the device file), the listing gives the URI and
//! the error, with what sysfs says ([`CardListing::error`]).
//!
//! `sim` cards are not listed: each `sim` is a new card of the process that opens it.

use crate::error::{Error, ErrorKind, Result};
use firmware_proto::emu_link::{self, CardRecord, ConnectError};
use firmware_proto::raw;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// The name a UIO driver written for the card gives its devices (`/sys/class/uio/uioN/name`).
pub const UIO_NAME: &str = "motioncard";

/// The board's PCI (vendor, device) IDs: the FPGA vendor's ID with the board's device ID
/// 0x4D43 ("MC"), which the listing looks for in sysfs.
pub const PCI_IDS: &[(u16, u16)] = &[(0x1172, 0x4d43)];

/// A card's place on the sync bus ([`CardListing::sync_role`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SyncRole {
    /// On its own clock, no bus (`MC_BUS_ALONE`; also a card older than layout 1.12).
    Alone,
    /// Drives the bus's clock (`MC_BUS_MASTER`).
    Master,
    /// Runs on the bus's ticks (`MC_BUS_FOLLOWER`).
    Follower,
}

impl SyncRole {
    fn from_raw(v: u32) -> Self {
        match v {
            raw::MC_BUS_MASTER => SyncRole::Master,
            raw::MC_BUS_FOLLOWER => SyncRole::Follower,
            _ => SyncRole::Alone,
        }
    }

    /// `alone`, `master` or `follower`.
    pub fn as_str(self) -> &'static str {
        match self {
            SyncRole::Alone => "alone",
            SyncRole::Master => "master",
            SyncRole::Follower => "follower",
        }
    }
}

/// A card's sync state ([`CardListing::sync_state`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SyncState {
    /// Alone or master: its own clock (`MC_BUSST_FREE`).
    Free,
    /// A follower on the master's ticks (`MC_BUSST_LOCKED`).
    Locked,
    /// A follower that lost its master: its own clock, halted (`MC_BUSST_LOST`).
    Lost,
}

impl SyncState {
    fn from_raw(v: u32) -> Self {
        match v {
            raw::MC_BUSST_LOCKED => SyncState::Locked,
            raw::MC_BUSST_LOST => SyncState::Lost,
            _ => SyncState::Free,
        }
    }

    /// `free`, `locked` or `lost`.
    pub fn as_str(self) -> &'static str {
        match self {
            SyncState::Free => "free",
            SyncState::Locked => "locked",
            SyncState::Lost => "lost",
        }
    }
}

/// Why a card found could not be read ([`CardListing::error`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ListingError {
    /// Its code: `PermissionDenied` (the card's server refused this user, or the device file
    /// is not readable), `Protocol` (a `card-emu` of another release), `Io`, ...
    pub kind: ErrorKind,
    /// What happened, and what to do about it.
    pub message: String,
}

/// One card found by [`crate::Card::list`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CardListing {
    /// The URI that opens it (`emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`).
    pub uri: String,
    /// Its name (`card_info.name`: `card-emu --name`, the board's EEPROM name); when it could
    /// not be read, the `emu:` socket's name or the UIO device's sysfs name.
    pub name: String,
    /// The board's serial number (0: none, or not read).
    pub serial: u64,
    /// Axes on the card (0: not read).
    pub axes: usize,
    /// Servo rate, Hz (0: not read).
    pub servo_rate_hz: u32,
    /// DPRAM layout (major, minor); (0, 0): not read.
    pub layout: (u16, u16),
    /// Firmware version, `major << 16 | minor << 8 | patch` (0: not read).
    pub firmware_version: u32,
    /// Its place on the sync bus.
    pub sync_role: SyncRole,
    /// Its sync state.
    pub sync_state: SyncState,
    /// A follower's master's name (empty otherwise).
    pub master: String,
    /// No host holds it: [`crate::Card::open`] would get it now (`false` also when it could not
    /// be read).
    pub available: bool,
    /// This process has it open.
    pub open_here: bool,
    /// Why it could not be read (`None`: every field above was read from the card).
    pub error: Option<ListingError>,
}

impl CardListing {
    fn found(uri: String, name: String) -> Self {
        Self {
            uri,
            name,
            serial: 0,
            axes: 0,
            servo_rate_hz: 0,
            layout: (0, 0),
            firmware_version: 0,
            sync_role: SyncRole::Alone,
            sync_state: SyncState::Free,
            master: String::new(),
            available: false,
            open_here: false,
            error: None,
        }
    }

    fn with_record(mut self, r: &CardRecord) -> Self {
        if r.magic != raw::MC_MAGIC {
            return self.failed(
                ErrorKind::Protocol,
                format!(
                    "its window has magic {:#010x}, not the card's {:#010x}: not booted, or not \
                     a motion card",
                    r.magic,
                    raw::MC_MAGIC
                ),
            );
        }
        if !r.name.is_empty() {
            self.name = r.name.clone();
        }
        self.serial = r.serial;
        self.axes = r.axes as usize;
        self.servo_rate_hz = r.servo_rate_hz;
        self.layout = r.layout;
        self.firmware_version = r.fw_version;
        self.sync_role = SyncRole::from_raw(r.sync_role);
        self.sync_state = SyncState::from_raw(r.sync_state);
        self.master = r.sync_master.clone();
        self.available = !r.leased;
        self
    }

    fn failed(mut self, kind: ErrorKind, message: String) -> Self {
        self.available = false;
        self.error = Some(ListingError { kind, message });
        self
    }
}

/// Every card reachable from this process, `emu:` first, then UIO, then PCI, each sorted by
/// URI. A card that could not be read is listed with its [`CardListing::error`]; an error here
/// is a listing that could not be made at all (`/proc` not readable).
pub fn list() -> Result<Vec<CardListing>> {
    let mut out = Vec::new();
    let unix = std::fs::read_to_string("/proc/net/unix")
        .map_err(|e| Error::io("reading /proc/net/unix (the emu: cards' sockets)", e))?;
    for name in emu_names(&unix) {
        out.push(emu_listing(&name));
    }
    let mut uio = Vec::new();
    let mut bound = Vec::new();
    if let Ok(dir) = std::fs::read_dir("/sys/class/uio") {
        for e in dir.flatten() {
            let dev = e.file_name().to_string_lossy().into_owned();
            if let Some(l) = uio_listing(&dev, &mut bound) {
                uio.push(l);
            }
        }
    }
    uio.sort_by(|a, b| a.uri.cmp(&b.uri));
    out.extend(uio);
    let mut pci = Vec::new();
    if let Ok(dir) = std::fs::read_dir("/sys/bus/pci/devices") {
        for e in dir.flatten() {
            let addr = e.file_name().to_string_lossy().into_owned();
            if !bound.contains(&addr) {
                if let Some(l) = pci_listing(&addr) {
                    pci.push(l);
                }
            }
        }
    }
    pci.sort_by(|a, b| a.uri.cmp(&b.uri));
    out.extend(pci);
    Ok(out)
}

/// The card names of the listening `@motioncard/NAME` sockets in `/proc/net/unix` (its text),
/// sorted, once each.
pub(crate) fn emu_names(proc_net_unix: &str) -> Vec<String> {
    // "Num RefCount Protocol Flags Type St Inode Path": Flags has __SO_ACCEPTCON (0x10000) on
    // a listening socket; accepted connections show the listener's path too.
    let prefix = format!("@{}", emu_link::socket_name(""));
    let mut names: Vec<String> = proc_net_unix
        .lines()
        .skip(1)
        .filter_map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            let flags = u32::from_str_radix(f.get(3)?, 16).ok()?;
            let path = f.get(7..)?.join(" ");
            let name = path.strip_prefix(&prefix)?;
            (flags & 0x10000 != 0 && !name.is_empty()).then(|| name.to_string())
        })
        .collect();
    names.sort();
    names.dedup();
    names
}

fn emu_listing(name: &str) -> CardListing {
    let uri = format!("emu:{name}");
    let l = CardListing::found(uri.clone(), name.to_string());
    match emu_link::query(name) {
        Ok(r) => l.with_record(&r),
        Err(ConnectError::Denied { uid }) => l.failed(
            ErrorKind::PermissionDenied,
            format!(
                "card-emu refused uid {uid}; it admits its own user, root, and the users and \
                 groups its operator allows (`--allow-uid {uid}`, `--allow-group GROUP`)"
            ),
        ),
        Err(ConnectError::NotFound) => l.failed(
            ErrorKind::NotFound,
            "its card-emu process went away while listing".into(),
        ),
        Err(ConnectError::Busy) => l.failed(
            ErrorKind::Busy,
            "card-emu is answering too many connections at once; list again".into(),
        ),
        Err(ConnectError::Protocol(m)) => l.failed(ErrorKind::Protocol, m),
        Err(ConnectError::Io(e)) => l.failed(ErrorKind::Io, format!("asking {uri}: {e}")),
    }
}

fn read_hex(path: &str) -> Option<u16> {
    let s = std::fs::read_to_string(path).ok()?;
    u16::from_str_radix(s.trim().trim_start_matches("0x"), 16).ok()
}

/// Are the PCI function's IDs (its sysfs directory) one of [`PCI_IDS`]?
fn ours(sysfs_dev: &str) -> bool {
    match (
        read_hex(&format!("{sysfs_dev}/vendor")),
        read_hex(&format!("{sysfs_dev}/device")),
    ) {
        (Some(v), Some(d)) => PCI_IDS.contains(&(v, d)),
        _ => false,
    }
}

/// `uioN` when it is one of our cards; the PCI address of its function goes into `bound`.
fn uio_listing(dev: &str, bound: &mut Vec<String>) -> Option<CardListing> {
    let n = dev.strip_prefix("uio")?;
    if n.is_empty() || !n.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let sys = format!("/sys/class/uio/{dev}");
    let name = std::fs::read_to_string(format!("{sys}/name")).ok()?;
    let name = name.trim().to_string();
    let pci = format!("{sys}/device");
    let is_ours = name == UIO_NAME || (name == "uio_pci_generic" && ours(&pci));
    if !is_ours {
        return None;
    }
    if let Ok(target) = std::fs::read_link(&pci) {
        if let Some(addr) = target.file_name() {
            bound.push(addr.to_string_lossy().into_owned());
        }
    }
    let path = format!("/dev/{dev}");
    let l = CardListing::found(format!("uio:{path}"), name);
    Some(hardware(l, &path, 0))
}

fn pci_listing(addr: &str) -> Option<CardListing> {
    let sys = format!("/sys/bus/pci/devices/{addr}");
    if !ours(&sys) {
        return None;
    }
    let l = CardListing::found(format!("pci:{addr}"), String::new());
    Some(hardware(l, &format!("{sys}/resource0"), 0))
}

/// A hardware card read from its window mapped read-only (no lock: see the module's notes).
fn hardware(l: CardListing, path: &str, offset: u64) -> CardListing {
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) => {
            let kind = if e.kind() == std::io::ErrorKind::PermissionDenied {
                ErrorKind::PermissionDenied
            } else {
                ErrorKind::Io
            };
            return l.failed(
                kind,
                format!("{path}: {e} (sysfs lists it with the card's IDs; it was not read)"),
            );
        }
    };
    let leased = flocked(&file);
    // SAFETY: a read-only shared mapping of the card's window: nothing in this process writes
    // it, and what the card writes is read only through atomic loads (`ReadOnly`).
    let map = unsafe {
        memmap2::MmapOptions::new()
            .offset(offset)
            .len(firmware_proto::DPRAM_SIZE)
            .map(&file)
    };
    match map {
        Ok(map) => l.with_record(&CardRecord::read(&ReadOnly(map), leased)),
        Err(e) => l.failed(ErrorKind::Io, format!("mapping {path} read-only: {e}")),
    }
}

/// Does some process hold a flock on this file (its device's host: see `device.rs`)? Read
/// from `/proc/locks` ("1: FLOCK ADVISORY WRITE PID MAJ:MIN:INODE 0 EOF"), never by locking.
fn flocked(file: &std::fs::File) -> bool {
    use std::os::unix::fs::MetadataExt;
    let Ok(m) = file.metadata() else {
        return false;
    };
    let (maj, min) = (
        nix::sys::stat::major(m.dev()),
        nix::sys::stat::minor(m.dev()),
    );
    let Ok(locks) = std::fs::read_to_string("/proc/locks") else {
        return false;
    };
    locks.lines().any(|line| {
        let f: Vec<&str> = line.split_whitespace().collect();
        let Some(at) = f.iter().position(|w| w.matches(':').count() == 2) else {
            return false;
        };
        let p: Vec<&str> = f[at].split(':').collect();
        f.get(1) == Some(&"FLOCK")
            && u64::from_str_radix(p[0], 16) == Ok(maj)
            && u64::from_str_radix(p[1], 16) == Ok(min)
            && p[2].parse::<u64>() == Ok(m.ino())
    })
}

/// A window mapped read-only: loads only (a store is a bug: the listing never writes).
struct ReadOnly(memmap2::Mmap);

impl ReadOnly {
    fn at<T>(&self, off: usize) -> Option<*const T> {
        let size = std::mem::size_of::<T>();
        (off.is_multiple_of(size) && off + size <= self.0.len())
            .then(|| self.0[off..].as_ptr().cast())
    }
}

impl firmware_proto::Mem for ReadOnly {
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        match self.at::<AtomicU32>(off) {
            // SAFETY: in bounds and aligned (`at`), mapped for as long as `self`; an atomic
            // load of memory the card writes.
            Some(p) => unsafe { (*p).load(order) },
            None => 0,
        }
    }
    fn store32(&self, _off: usize, _val: u32, _order: Ordering) {
        debug_assert!(false, "the listing's read-only window is never written");
    }
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        match self.at::<AtomicU64>(off) {
            // SAFETY: as in `load32`.
            Some(p) => unsafe { (*p).load(order) },
            None => 0,
        }
    }
    fn store64(&self, _off: usize, _val: u64, _order: Ordering) {
        debug_assert!(false, "the listing's read-only window is never written");
    }
}

/// The URI that `name:NAME` or `serial:N` (`uri`) names, through the listing: `NotFound`
/// naming what was searched, `Ambiguous` naming the matches, `BadUri` for a serial that is not
/// a decimal number 1 to 2^64-1 or an empty name.
pub(crate) fn resolve(uri: &str) -> Result<String> {
    type Matches = Box<dyn Fn(&CardListing) -> bool>;
    let (what, matches): (String, Matches) = if let Some(name) = uri.strip_prefix("name:") {
        if name.is_empty() {
            return Err(Error::BadUri(uri.into()));
        }
        let n = name.to_string();
        (format!("named '{name}'"), Box::new(move |l| l.name == n))
    } else if let Some(serial) = uri.strip_prefix("serial:") {
        let s = match serial.parse::<u64>() {
            Ok(s) if s > 0 && serial.bytes().all(|b| b.is_ascii_digit()) => s,
            _ => return Err(Error::BadUri(uri.into())),
        };
        (format!("with serial {s}"), Box::new(move |l| l.serial == s))
    } else {
        return Err(Error::BadUri(uri.into()));
    };
    let all = list()?;
    let found: Vec<&CardListing> = all
        .iter()
        .filter(|l| l.error.is_none() && matches(l))
        .collect();
    match found.as_slice() {
        [one] => Ok(one.uri.clone()),
        [] => {
            // At most a few of each, so that the message stays short whatever is present
            // (`mcctl list` shows them all).
            const SHOWN: usize = 4;
            let more = |n: usize| {
                if n > SHOWN {
                    format!(", and {} more", n - SHOWN)
                } else {
                    String::new()
                }
            };
            let read: Vec<String> = all
                .iter()
                .filter(|l| l.error.is_none())
                .map(|l| format!("{} ({}, serial {})", l.uri, l.name, l.serial))
                .collect();
            let mut reason = format!(
                "no card {what} among the emu: processes, UIO devices and PCI functions listed ({}{})",
                if read.is_empty() {
                    "none".to_string()
                } else {
                    read[..read.len().min(SHOWN)].join(", ")
                },
                more(read.len())
            );
            let unread: Vec<String> = all
                .iter()
                .filter_map(|l| {
                    l.error
                        .as_ref()
                        .map(|e| format!("{} ({})", l.uri, e.kind.description()))
                })
                .collect();
            if !unread.is_empty() {
                reason += &format!(
                    "; not read: {}{}",
                    unread[..unread.len().min(SHOWN)].join(", "),
                    more(unread.len())
                );
            }
            Err(Error::NotFound {
                uri: uri.into(),
                reason,
            })
        }
        many => Err(Error::Ambiguous {
            uri: uri.into(),
            matches: many.iter().map(|l| l.uri.clone()).collect(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listening_motioncard_sockets_are_the_emu_names() {
        let t = "Num       RefCount Protocol Flags    Type St Inode Path\n\
                 0000000000000000: 00000002 00000000 00010000 0001 01 4242 @motioncard/b\n\
                 0000000000000000: 00000002 00000000 00010000 0001 01 4243 @motioncard/a\n\
                 0000000000000000: 00000003 00000000 00000000 0001 03 4244 @motioncard/a\n\
                 0000000000000000: 00000002 00000000 00010000 0001 01 4245 @other/c\n\
                 0000000000000000: 00000002 00000000 00010000 0001 01 4246 /run/motioncard/d\n\
                 0000000000000000: 00000002 00000000 00000000 0001 01 4247\n\
                 0000000000000000: 00000002 00000000 00010000 0001 01 4248 @motioncard/with space\n";
        assert_eq!(emu_names(t), ["a", "b", "with space"]);
    }

    #[test]
    fn bad_name_and_serial_uris() {
        for bad in [
            "name:",
            "serial:",
            "serial:0",
            "serial:-1",
            "serial:+5",
            "serial:0x10",
        ] {
            assert_eq!(resolve(bad).unwrap_err().kind(), ErrorKind::BadUri, "{bad}");
        }
    }
}
