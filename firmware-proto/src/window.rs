//! DPRAM windows backed by a shared mapping: a memfd the emulator creates and hands to the host,
//! or any file (a UIO or sysfs resource) the host maps. Both sides map it with memmap2.
//!
//! The emulator's memfd is sealed at its size ([`WINDOW_SEALS`]: no shrinking, no growing, no
//! more seals) before it is mapped or handed out. A process that maps a file touches pages past
//! the file's end at its peril (SIGBUS), so a host that could shrink the memfd could kill the
//! card; with the seals its `ftruncate` fails with `EPERM` and nothing changes. A host maps a
//! received window only when it carries these seals ([`MappedWindow::from_fd`]), which also
//! protects the host from a server that would shrink it.

use crate::{Dpram, Mem, DPRAM_SIZE};
use memmap2::{MmapOptions, MmapRaw};
use nix::fcntl::{fcntl, FcntlArg, SealFlag};
use nix::sys::memfd::{memfd_create, MFdFlags};
use std::fs::File;
use std::os::fd::{AsFd, BorrowedFd, OwnedFd};
use std::sync::atomic::Ordering;

/// The seals of an emulator's window: its size is fixed, and nobody can add a seal (such as
/// `F_SEAL_FUTURE_WRITE`, which would keep later hosts from mapping it writable).
pub const WINDOW_SEALS: SealFlag = SealFlag::F_SEAL_SHRINK
    .union(SealFlag::F_SEAL_GROW)
    .union(SealFlag::F_SEAL_SEAL);

fn invalid(msg: String) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, msg)
}

/// A mapped DPRAM window. Keeps the mapping (and the file) alive.
pub struct MappedWindow {
    dpram: Dpram,
    _map: MmapRaw,
    file: File,
}

impl MappedWindow {
    /// A new zeroed window in an anonymous memfd (the emulator's DPRAM), sealed at its size
    /// with [`WINDOW_SEALS`].
    pub fn create(name: &str) -> std::io::Result<Self> {
        let fd = memfd_create(
            format!("motioncard-{name}").as_str(),
            MFdFlags::MFD_CLOEXEC | MFdFlags::MFD_ALLOW_SEALING,
        )?;
        let file = File::from(fd);
        file.set_len(DPRAM_SIZE as u64)?;
        fcntl(&file, FcntlArg::F_ADD_SEALS(WINDOW_SEALS))?;
        Self::map(file, 0, DPRAM_SIZE)
    }

    /// Map `len` bytes of `file` from `offset` (a memfd received from the emulator, a UIO map,
    /// a PCI BAR resource file).
    pub fn map(file: File, offset: u64, len: usize) -> std::io::Result<Self> {
        let map = MmapOptions::new().offset(offset).len(len).map_raw(&file)?;
        // SAFETY: the mapping lives in `self._map` as long as `dpram` is used; all access to it
        // is atomic (see crate::mem).
        let dpram = unsafe { Dpram::from_raw(map.as_mut_ptr(), map.len()) }
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()))?;
        Ok(Self {
            dpram,
            _map: map,
            file,
        })
    }

    /// Map a window received from an emulator as a file descriptor. It must carry
    /// [`WINDOW_SEALS`] (so its size cannot change under the mapping) and hold at least
    /// [`DPRAM_SIZE`] bytes; else the error is `InvalidData` and nothing is mapped.
    pub fn from_fd(fd: OwnedFd) -> std::io::Result<Self> {
        let file = File::from(fd);
        // The seals first: once the size is sealed, the size read next cannot change.
        let seals = match fcntl(&file, FcntlArg::F_GET_SEALS) {
            Ok(bits) => SealFlag::from_bits_retain(bits),
            Err(nix::errno::Errno::EINVAL) => SealFlag::empty(), // not a sealable file
            Err(e) => return Err(e.into()),
        };
        if !seals.contains(WINDOW_SEALS) {
            return Err(invalid(format!(
                "shared window is not sealed against resizing (seals {:#x}, needs {:#x}): \
                 its size could change under the mapping",
                seals.bits(),
                WINDOW_SEALS.bits()
            )));
        }
        let len = file.metadata()?.len();
        if len < DPRAM_SIZE as u64 {
            return Err(invalid(format!(
                "shared window is {len} bytes, the layout needs {DPRAM_SIZE}"
            )));
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
    #[inline]
    fn bad_accesses(&self) -> u32 {
        self.dpram.bad_accesses()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nix::errno::Errno;
    use nix::unistd::ftruncate;

    #[test]
    fn the_emulator_window_is_sealed_at_its_size() {
        let w = MappedWindow::create("seal-test").unwrap();
        let seals = SealFlag::from_bits_retain(fcntl(w.fd(), FcntlArg::F_GET_SEALS).unwrap());
        assert!(seals.contains(WINDOW_SEALS), "{seals:?}");
        assert_eq!(ftruncate(w.fd(), 0), Err(Errno::EPERM));
        assert_eq!(ftruncate(w.fd(), 2 * DPRAM_SIZE as i64), Err(Errno::EPERM));
        let more = FcntlArg::F_ADD_SEALS(SealFlag::F_SEAL_FUTURE_WRITE);
        assert_eq!(fcntl(w.fd(), more), Err(Errno::EPERM));
        assert_eq!(w.file.metadata().unwrap().len(), DPRAM_SIZE as u64);
        // And a host maps it.
        let again = MappedWindow::from_fd(w.fd().try_clone_to_owned().unwrap()).unwrap();
        again.store32(64, 7, Ordering::Relaxed);
        assert_eq!(w.load32(64, Ordering::Relaxed), 7);
    }

    #[test]
    fn a_host_refuses_an_unsealed_or_short_window() {
        let unsealed = memfd_create("unsealed", MFdFlags::MFD_CLOEXEC).unwrap();
        ftruncate(&unsealed, DPRAM_SIZE as i64).unwrap();
        let e = MappedWindow::from_fd(unsealed).err().unwrap();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
        assert!(e.to_string().contains("not sealed"), "{e}");

        // Sealable but only partly sealed: still refused.
        let part =
            memfd_create("part", MFdFlags::MFD_CLOEXEC | MFdFlags::MFD_ALLOW_SEALING).unwrap();
        ftruncate(&part, DPRAM_SIZE as i64).unwrap();
        fcntl(&part, FcntlArg::F_ADD_SEALS(SealFlag::F_SEAL_GROW)).unwrap();
        let e = MappedWindow::from_fd(part).err().unwrap();
        assert!(e.to_string().contains("not sealed"), "{e}");

        // Sealed, but too small for the layout.
        let short =
            memfd_create("short", MFdFlags::MFD_CLOEXEC | MFdFlags::MFD_ALLOW_SEALING).unwrap();
        ftruncate(&short, 4096).unwrap();
        fcntl(&short, FcntlArg::F_ADD_SEALS(WINDOW_SEALS)).unwrap();
        let e = MappedWindow::from_fd(short).err().unwrap();
        assert!(e.to_string().contains("4096 bytes"), "{e}");

        // A file that cannot carry seals at all.
        let file = std::fs::File::open("/proc/self/status").unwrap();
        let e = MappedWindow::from_fd(file.into()).err().unwrap();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
    }
}
