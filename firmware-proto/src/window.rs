//! DPRAM windows backed by a shared mapping: a memfd the emulator creates and hands to the host,
//! or any file (a UIO or sysfs resource) the host maps. Both sides map it with memmap2.
//!
//! The emulator's memfd is sealed at its size ([`WINDOW_SEALS`]: no shrinking, no growing, no
//! more seals) before it is mapped or handed out. A process that maps a file touches pages past
//! the file's end at its peril (SIGBUS), so a host that could shrink the memfd could kill the
//! card; with the seals its `ftruncate` fails with `EPERM` and nothing changes. A host maps a
//! received window only when it carries these seals ([`MappedWindow::from_fd`]), which also
//! protects the host from a server that would shrink it.
//!
//! The emulator moves its window onto a new memfd for each new host ([`MappedWindow::renew`]):
//! the kernel copies the contents file to file, and the new memfd is mapped over the old
//! mapping in place, so every [`Dpram`] over it keeps its addresses. A past host that kept the old memfd or its mapping
//! then holds memory the card no longer reads or writes.

use crate::{Dpram, Mem, DPRAM_SIZE};
use memmap2::{MmapOptions, MmapRaw};
use nix::fcntl::{fallocate, fcntl, FallocateFlags, FcntlArg, SealFlag};
use nix::sys::memfd::{memfd_create, MFdFlags};
use nix::sys::mman::{mmap, MapFlags, ProtFlags};
use std::fs::File;
use std::num::NonZeroUsize;
use std::os::fd::{AsFd, OwnedFd};
use std::sync::atomic::Ordering;
use std::sync::{Mutex, PoisonError};

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
    map: MmapRaw,
    /// What is mapped; [`MappedWindow::renew`] replaces it.
    backing: Mutex<Backing>,
}

/// The file mapped and the offset it is mapped from.
struct Backing {
    file: File,
    offset: u64,
}

impl MappedWindow {
    /// A new zeroed window in an anonymous memfd (the emulator's DPRAM), sealed at its size
    /// with [`WINDOW_SEALS`].
    pub fn create(name: &str) -> std::io::Result<Self> {
        Self::map(Self::memfd(name)?, 0, DPRAM_SIZE)
    }

    /// A new zeroed memfd of [`DPRAM_SIZE`] bytes named `motioncard-NAME`, its memory
    /// allocated now (so that [`MappedWindow::renew`] does not allocate it while the card
    /// waits), sealed with [`WINDOW_SEALS`]: what [`MappedWindow::create`] maps, and what
    /// [`MappedWindow::renew`] takes.
    pub fn memfd(name: &str) -> std::io::Result<File> {
        let fd = memfd_create(
            format!("motioncard-{name}").as_str(),
            MFdFlags::MFD_CLOEXEC | MFdFlags::MFD_ALLOW_SEALING,
        )?;
        let file = File::from(fd);
        file.set_len(DPRAM_SIZE as u64)?;
        fallocate(&file, FallocateFlags::empty(), 0, DPRAM_SIZE as i64)?;
        fcntl(&file, FcntlArg::F_ADD_SEALS(WINDOW_SEALS))?;
        Ok(file)
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
            map,
            backing: Mutex::new(Backing { file, offset }),
        })
    }

    /// Map a window received from an emulator as a file descriptor. It must carry
    /// [`WINDOW_SEALS`] (so its size cannot change under the mapping) and hold at least
    /// [`DPRAM_SIZE`] bytes; else the error is `InvalidData` and nothing is mapped.
    pub fn from_fd(fd: OwnedFd) -> std::io::Result<Self> {
        let file = File::from(fd);
        check_sealed(&file, DPRAM_SIZE)?;
        Self::map(file, 0, DPRAM_SIZE)
    }

    /// Move this window onto `memfd` (from [`MappedWindow::memfd`]): copy the window's
    /// contents into it, map it over this window's mapping in place (`MAP_FIXED`: the same
    /// addresses, so every [`Dpram`] over the window, and every clone of the `Arc` it lives
    /// in, goes on working, now on the new memory), and return the file mapped before, for the
    /// caller to close when it suits it (freeing a window's memory takes a while). A process
    /// that still maps the old file keeps memory that nobody else reads or writes any more;
    /// so does this process through any other mapping of it.
    ///
    /// `memfd` must carry [`WINDOW_SEALS`] and hold the whole window, else the error is
    /// `InvalidData`; the file mapped now must be one the kernel copies from
    /// (`copy_file_range`: a memfd, a regular file), else its error. On an error nothing
    /// changed. The caller makes sure that nothing in this process writes the window meanwhile
    /// (the emulator: between two ticks); what another process writes into the old file
    /// during the copy may or may not be carried over.
    pub fn renew(&self, memfd: File) -> std::io::Result<File> {
        let (base, len) = (self.map.as_mut_ptr(), self.map.len());
        // SAFETY: sysconf has no preconditions.
        let page = unsafe { nix::libc::sysconf(nix::libc::_SC_PAGESIZE) }.max(1) as usize;
        if !(base as usize).is_multiple_of(page) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "a window mapped from an offset inside a page cannot be renewed",
            ));
        }
        check_sealed(&memfd, len)?;
        let mut old = self.backing.lock().unwrap_or_else(PoisonError::into_inner);
        // The kernel copies file to file: nothing is read through this process's mapping (no
        // page of it faulted in for the copy, no Rust access to shared memory).
        let mut from = old.offset as i64;
        let mut to = 0i64;
        while (to as usize) < len {
            let left = len - to as usize;
            let n = nix::fcntl::copy_file_range(
                &old.file,
                Some(&mut from),
                &memfd,
                Some(&mut to),
                left,
            );
            match n {
                Ok(0) => return Err(std::io::ErrorKind::UnexpectedEof.into()),
                Ok(_) | Err(nix::errno::Errno::EINTR) => {}
                Err(e) => return Err(e.into()),
            }
        }
        // SAFETY: the range is exactly this window's own mapping (page-aligned base, its
        // length), which `self.map` owns and unmaps on drop; replacing it in place with a
        // shared mapping of the same length and protection keeps every pointer into it valid.
        // Nothing in this process accesses the window meanwhile (the caller's rule above).
        if let Err(e) = unsafe { Self::map_over(base, len, &memfd, 0) } {
            // MAP_FIXED may have unmapped the range before failing: map the old file back,
            // or stop here rather than fault on the next access.
            // SAFETY: as above, with the file and offset that were mapped there.
            if unsafe { Self::map_over(base, len, &old.file, old.offset) }.is_err() {
                eprintln!("motioncard: the DPRAM window lost its mapping ({e}); aborting");
                std::process::abort();
            }
            return Err(e.into());
        }
        let new = Backing {
            file: memfd,
            offset: 0,
        };
        Ok(std::mem::replace(&mut *old, new).file)
    }

    /// Map `file` from `offset` over `len` bytes at `base`, read-write and shared.
    ///
    /// # Safety
    /// `base .. base + len` must be a mapping this window owns.
    unsafe fn map_over(base: *mut u8, len: usize, file: &File, offset: u64) -> nix::Result<()> {
        let addr = NonZeroUsize::new(base as usize).ok_or(nix::errno::Errno::EINVAL)?;
        let len = NonZeroUsize::new(len).ok_or(nix::errno::Errno::EINVAL)?;
        // SAFETY: by the caller's contract the range is ours to replace.
        let at = unsafe {
            mmap(
                Some(addr),
                len,
                ProtFlags::PROT_READ | ProtFlags::PROT_WRITE,
                MapFlags::MAP_SHARED | MapFlags::MAP_FIXED,
                file,
                offset as nix::libc::off_t,
            )?
        };
        debug_assert_eq!(at.as_ptr() as usize, base as usize);
        Ok(())
    }

    /// The window.
    pub fn dpram(&self) -> &Dpram {
        &self.dpram
    }

    /// A new descriptor of the file mapped now, to hand to another process (a duplicate:
    /// [`MappedWindow::renew`] may replace the file later, and this descriptor stays what it
    /// is).
    pub fn dup_fd(&self) -> std::io::Result<OwnedFd> {
        let backing = self.backing.lock().unwrap_or_else(PoisonError::into_inner);
        backing.file.as_fd().try_clone_to_owned()
    }
}

/// `file` carries [`WINDOW_SEALS`] (so its size cannot change under a mapping) and holds at
/// least `len` bytes; else `InvalidData`.
fn check_sealed(file: &File, len: usize) -> std::io::Result<()> {
    // The seals first: once the size is sealed, the size read next cannot change.
    let seals = match fcntl(file, FcntlArg::F_GET_SEALS) {
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
    let size = file.metadata()?.len();
    if size < len as u64 {
        return Err(invalid(format!(
            "shared window is {size} bytes, the layout needs {len}"
        )));
    }
    Ok(())
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
    fn write64s(&self, off: usize, words: &[u64]) {
        self.dpram.write64s(off, words)
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
        let fd = w.dup_fd().unwrap();
        let seals = SealFlag::from_bits_retain(fcntl(&fd, FcntlArg::F_GET_SEALS).unwrap());
        assert!(seals.contains(WINDOW_SEALS), "{seals:?}");
        assert_eq!(ftruncate(&fd, 0), Err(Errno::EPERM));
        assert_eq!(ftruncate(&fd, 2 * DPRAM_SIZE as i64), Err(Errno::EPERM));
        let more = FcntlArg::F_ADD_SEALS(SealFlag::F_SEAL_FUTURE_WRITE);
        assert_eq!(fcntl(&fd, more), Err(Errno::EPERM));
        assert_eq!(File::from(fd).metadata().unwrap().len(), DPRAM_SIZE as u64);
        // And a host maps it.
        let again = MappedWindow::from_fd(w.dup_fd().unwrap()).unwrap();
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

    /// A renewed window keeps its contents and its addresses, and a past host's mapping of
    /// the file before is cut off both ways: its writes do not reach the window, and the
    /// window's writes do not reach it.
    #[test]
    fn a_renewed_window_keeps_its_contents_and_leaves_the_old_file_behind() {
        let w = MappedWindow::create("renew-test").unwrap();
        for off in (0..DPRAM_SIZE).step_by(4096) {
            w.write64(off, off as u64 ^ 0x5A5A);
        }
        let past = MappedWindow::from_fd(w.dup_fd().unwrap()).unwrap();
        let old = w.dup_fd().unwrap();
        past.write32(8, 1);
        assert_eq!(w.read32(8), 1, "one memory before the renewal");

        let before = w.renew(MappedWindow::memfd("renew-test").unwrap()).unwrap();
        for off in (0..DPRAM_SIZE).step_by(4096) {
            assert_eq!(w.read64(off), off as u64 ^ 0x5A5A, "at {off}");
        }
        assert_eq!(w.read32(8), 1);
        // The past host writes everywhere; the window does not see it.
        for off in (0..DPRAM_SIZE).step_by(8) {
            past.write64(off, u64::MAX);
        }
        assert_eq!(w.read32(8), 1);
        assert_eq!(w.read64(4096), 4096 ^ 0x5A5A);
        // The window's writes miss the past host.
        w.write64(4096, 7);
        assert_eq!(w.read64(4096), 7);
        assert_eq!(past.read64(4096), u64::MAX);
        // The file handed out now is the new one, sealed; the old one is another file.
        let new = w.dup_fd().unwrap();
        let seals = SealFlag::from_bits_retain(fcntl(&new, FcntlArg::F_GET_SEALS).unwrap());
        assert!(seals.contains(WINDOW_SEALS), "{seals:?}");
        let ino = |fd: &OwnedFd| File::from(fd.try_clone().unwrap()).metadata().unwrap();
        use std::os::unix::fs::MetadataExt;
        assert_ne!(ino(&new).ino(), ino(&old).ino());
        assert_eq!(
            before.metadata().unwrap().ino(),
            ino(&old).ino(),
            "handed back"
        );
        let host = MappedWindow::from_fd(new).unwrap();
        assert_eq!(host.read64(4096), 7);
        host.write32(12, 3);
        assert_eq!(w.read32(12), 3);
    }

    #[test]
    fn a_window_is_renewed_only_onto_a_sealed_file_of_its_size() {
        let w = MappedWindow::create("renew-refuse").unwrap();
        w.write32(16, 9);
        let before = w.dup_fd().unwrap();
        let unsealed = memfd_create("unsealed", MFdFlags::MFD_CLOEXEC).unwrap();
        ftruncate(&unsealed, DPRAM_SIZE as i64).unwrap();
        let e = w.renew(File::from(unsealed)).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
        assert!(e.to_string().contains("not sealed"), "{e}");
        let short =
            memfd_create("short", MFdFlags::MFD_CLOEXEC | MFdFlags::MFD_ALLOW_SEALING).unwrap();
        ftruncate(&short, 4096).unwrap();
        fcntl(&short, FcntlArg::F_ADD_SEALS(WINDOW_SEALS)).unwrap();
        let e = w.renew(File::from(short)).unwrap_err();
        assert!(e.to_string().contains("4096 bytes"), "{e}");
        // Nothing changed: the same file, the same contents, still shared with it.
        let host = MappedWindow::from_fd(before).unwrap();
        assert_eq!(host.read32(16), 9);
        host.write32(16, 10);
        assert_eq!(w.read32(16), 10);
    }

    /// A window mapped from an offset into its file is copied from there.
    #[test]
    fn a_window_mapped_from_an_offset_is_renewed_with_its_contents() {
        use std::os::unix::fs::FileExt;
        let page = 4096u64;
        let file = File::from(memfd_create("offset", MFdFlags::MFD_CLOEXEC).unwrap());
        file.set_len(page + DPRAM_SIZE as u64).unwrap();
        file.write_at(&0xC0DEu32.to_ne_bytes(), page + 64).unwrap();
        file.write_at(&0xBADu32.to_ne_bytes(), 64).unwrap();
        let w = MappedWindow::map(file, page, DPRAM_SIZE).unwrap();
        assert_eq!(w.read32(64), 0xC0DE);
        w.renew(MappedWindow::memfd("offset").unwrap()).unwrap();
        assert_eq!(w.read32(64), 0xC0DE);
        let host = MappedWindow::from_fd(w.dup_fd().unwrap()).unwrap();
        assert_eq!(host.read32(64), 0xC0DE);
    }
}
