//! Listing the cards reachable from this process (`mc_list_cards`); opening one by name or
//! serial is `mc_open("name:NAME")` / `mc_open("serial:N")`.

use crate::ffi::ArrayBuf;
use crate::result::{guard, mc_result};
use motioncard_sdk::{Card, CardListing, SyncRole, SyncState};
use std::ffi::c_char;

/// One card found by `mc_list_cards`. Strings are NUL-terminated (cut to fit, at a character
/// boundary).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
#[allow(non_camel_case_types)]
pub struct mc_card_listing {
    /// The URI that opens it: `emu:NAME`, `uio:/dev/uioN` or `pci:DDDD:BB:DD.F`.
    pub uri: [c_char; 128],
    /// Its name (`card-emu --name`, the board's EEPROM name); when the card could not be read,
    /// the `emu:` socket's name or the UIO device's sysfs name.
    pub name: [c_char; 128],
    /// The board's serial number (0: none, or not read).
    pub serial: u64,
    /// Axes on the card (0: not read).
    pub axes: u32,
    /// Servo rate, Hz (0: not read).
    pub servo_rate_hz: u32,
    /// Firmware version, `major << 16 | minor << 8 | patch` (0: not read).
    pub firmware_version: u32,
    /// DPRAM layout major version (0: not read).
    pub layout_major: u16,
    /// DPRAM layout minor version.
    pub layout_minor: u16,
    /// `MC_BUS_ALONE`, `MC_BUS_MASTER` or `MC_BUS_FOLLOWER`.
    pub sync_role: u32,
    /// `MC_BUSST_FREE`, `MC_BUSST_LOCKED` or `MC_BUSST_LOST`.
    pub sync_state: u32,
    /// A follower's master's name (empty otherwise).
    pub master: [c_char; 32],
    /// 1: no host holds it, `mc_open` would get it now; 0: held (or not read).
    pub available: u32,
    /// 1: this process has it open.
    pub open_here: u32,
    /// `MC_OK`: every field was read from the card; else why it could not be read
    /// (`MC_ERR_PERMISSION_DENIED`: the card's server refused this user; `MC_ERR_PROTOCOL`: a
    /// card-emu of another release; ...), with `error_message`.
    pub error: mc_result,
    /// What `error` means here, and what to do about it (empty with `MC_OK`).
    pub error_message: [c_char; 256],
}

/// `s` into `out`, NUL-terminated, cut at a character boundary to fit.
fn put<const N: usize>(out: &mut [c_char; N], s: &str) {
    let mut n = s.len().min(N - 1);
    while !s.is_char_boundary(n) {
        n -= 1;
    }
    for (o, b) in out.iter_mut().zip(&s.as_bytes()[..n]) {
        *o = *b as c_char;
    }
    out[n..].fill(0);
}

impl From<&CardListing> for mc_card_listing {
    fn from(l: &CardListing) -> Self {
        let mut c = Self {
            uri: [0; 128],
            name: [0; 128],
            serial: l.serial,
            axes: l.axes as u32,
            servo_rate_hz: l.servo_rate_hz,
            firmware_version: l.firmware_version,
            layout_major: l.layout.0,
            layout_minor: l.layout.1,
            sync_role: match l.sync_role {
                SyncRole::Alone => firmware_proto::raw::MC_BUS_ALONE,
                SyncRole::Master => firmware_proto::raw::MC_BUS_MASTER,
                SyncRole::Follower => firmware_proto::raw::MC_BUS_FOLLOWER,
            },
            sync_state: match l.sync_state {
                SyncState::Free => firmware_proto::raw::MC_BUSST_FREE,
                SyncState::Locked => firmware_proto::raw::MC_BUSST_LOCKED,
                SyncState::Lost => firmware_proto::raw::MC_BUSST_LOST,
            },
            master: [0; 32],
            available: l.available.into(),
            open_here: l.open_here.into(),
            error: l.error.as_ref().map_or(0, |e| e.kind.code()),
            error_message: [0; 256],
        };
        put(&mut c.uri, &l.uri);
        put(&mut c.name, &l.name);
        put(&mut c.master, &l.master);
        if let Some(e) = &l.error {
            put(&mut c.error_message, &e.message);
        }
        c
    }
}

/// Every card reachable from this process: `card-emu` processes (`emu:`), UIO devices and PCI
/// functions with the card's IDs, in that order, each read without disturbing a host that
/// holds it (as the Rust SDK lists them). Writes the cards to `cards` and their count to
/// `*needed`; when `len` is too small, only `*needed` and `MC_ERR_BUFFER_TOO_SMALL` (`cards`
/// may be NULL when `len` is 0, to ask for the count; cards can come and go between two calls:
/// ask again on `MC_ERR_BUFFER_TOO_SMALL`). A card found but not read is listed with its
/// `error`. `MC_ERR_IO` when /proc cannot be read. Blocks while each `emu:` card answers (a
/// fraction of a millisecond each, at most 5 s for one that does not).
#[no_mangle]
pub unsafe extern "C" fn mc_list_cards(
    cards: *mut mc_card_listing,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let out = ArrayBuf::new(cards, len, needed)?;
        let all: Vec<mc_card_listing> = Card::list()?.iter().map(Into::into).collect();
        // SAFETY: the caller gives `len` writable listings at `cards` and a writable `*needed`.
        unsafe { out.fill(&all) }
    })
}
