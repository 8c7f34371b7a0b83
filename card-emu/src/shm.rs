//! DPRAM windows backed by a shared mapping: a memfd the emulator creates and hands to the host,
//! or any file (a UIO or sysfs resource) the host maps. Both sides map it with memmap2.

use firmware_proto::{Dpram, Mem, DPRAM_SIZE};
use memmap2::{MmapOptions, MmapRaw};
use nix::sys::memfd::{memfd_create, MFdFlags};
use std::fs::File;
use std::os::fd::{AsFd, BorrowedFd, OwnedFd};
use std::sync::atomic::Ordering;

/// A mapped DPRAM window. Keeps the mapping (and the file) alive.
pub struct MappedWindow {
    dpram: Dpram,
    _map: MmapRaw,
    file: File,
}

impl MappedWindow {
    /// A new zeroed window in an anonymous memfd (the emulator's DPRAM).
    pub fn create(name: &str) -> std::io::Result<Self> {
        let fd = memfd_create(format!("motioncard-{name}").as_str(), MFdFlags::MFD_CLOEXEC)?;
        let file = File::from(fd);
        file.set_len(DPRAM_SIZE as u64)?;
        Self::map(file, 0, DPRAM_SIZE)
    }

    /// Map `len` bytes of `file` from `offset` (a memfd received from the emulator, a UIO map,
    /// a PCI BAR resource file).
    pub fn map(file: File, offset: u64, len: usize) -> std::io::Result<Self> {
        let map = MmapOptions::new().offset(offset).len(len).map_raw(&file)?;
        // SAFETY: the mapping lives in `self._map` as long as `dpram` is used; all access to it
        // is atomic (see firmware_proto::mem).
        let dpram = unsafe { Dpram::from_raw(map.as_mut_ptr(), map.len()) }
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()))?;
        Ok(Self {
            dpram,
            _map: map,
            file,
        })
    }

    /// Map a window received as a file descriptor.
    pub fn from_fd(fd: OwnedFd) -> std::io::Result<Self> {
        let file = File::from(fd);
        let len = file.metadata()?.len();
        if len < DPRAM_SIZE as u64 {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("shared window is {len} bytes, the layout needs {DPRAM_SIZE}"),
            ));
        }
        Self::map(file, 0, DPRAM_SIZE)
    }

    /// The window.
    pub fn dpram(&self) -> &Dpram {
        &self.dpram
    }

    /// The backing file, to hand to another process.
    pub fn fd(&self) -> BorrowedFd<'_> {
        self.file.as_fd()
    }
}

impl Mem for MappedWindow {
    #[inline]
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        self.dpram.load32(off, order)
    }
    #[inline]
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        self.dpram.store32(off, val, order)
    }
    #[inline]
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        self.dpram.load64(off, order)
    }
    #[inline]
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        self.dpram.store64(off, val, order)
    }
}
