//! Word-addressed access to the shared window.
//!
//! Every access is an atomic load or store of an explicit width, so two processes (or the host
//! and the card's DSP) can touch the same words without a data race; plain `Relaxed` is used for
//! payload words and the ordering of a protocol is made with Acquire/Release on its index or
//! sequence words. No Rust reference to DPRAM memory outlives a single access.

use core::sync::atomic::Ordering;
#[cfg(target_has_atomic = "64")]
use core::{
    ptr::NonNull,
    sync::atomic::{AtomicU32, AtomicU64},
};

/// Shared memory addressed by byte offset. An offset that is out of range or misaligned is a
/// bug (the layout makes them impossible): debug builds panic on it at once; release builds
/// ignore it (loads return 0) instead of touching memory, so a bug cannot become undefined
/// behaviour, and count it ([`Mem::bad_accesses`]) so it cannot go unnoticed either.
pub trait Mem {
    /// Load a 32-bit word.
    fn load32(&self, off: usize, order: Ordering) -> u32;
    /// Store a 32-bit word.
    fn store32(&self, off: usize, val: u32, order: Ordering);
    /// Load a 64-bit word.
    fn load64(&self, off: usize, order: Ordering) -> u64;
    /// Store a 64-bit word.
    fn store64(&self, off: usize, val: u64, order: Ordering);

    /// Relaxed 32-bit load.
    fn read32(&self, off: usize) -> u32 {
        self.load32(off, Ordering::Relaxed)
    }
    /// Relaxed 32-bit store.
    fn write32(&self, off: usize, val: u32) {
        self.store32(off, val, Ordering::Relaxed)
    }
    /// Relaxed 64-bit load.
    fn read64(&self, off: usize) -> u64 {
        self.load64(off, Ordering::Relaxed)
    }
    /// Relaxed 64-bit store.
    fn write64(&self, off: usize, val: u64) {
        self.store64(off, val, Ordering::Relaxed)
    }
    /// Relaxed 64-bit stores of consecutive words, the first at `off`: the same as a
    /// [`Mem::write64`] of each word in order (what this default does). An implementation may
    /// check the whole run once instead of each word ([`Dpram`] does).
    fn write64s(&self, off: usize, words: &[u64]) {
        for (i, w) in words.iter().enumerate() {
            self.write64(off + 8 * i, *w);
        }
    }
    /// Relaxed load of an IEEE-754 double.
    fn read_f64(&self, off: usize) -> f64 {
        f64::from_bits(self.read64(off))
    }
    /// Relaxed store of an IEEE-754 double.
    fn write_f64(&self, off: usize, val: f64) {
        self.write64(off, val.to_bits())
    }

    /// Accesses refused (out of range or misaligned) through this handle since it was made,
    /// wrapping. Only release builds get here: debug builds panic on the access itself.
    /// Memory that cannot refuse an access (a test double) reports 0.
    fn bad_accesses(&self) -> u32 {
        0
    }
}

impl<T: Mem + ?Sized> Mem for &T {
    #[inline]
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        (**self).load32(off, order)
    }
    #[inline]
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        (**self).store32(off, val, order)
    }
    #[inline]
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        (**self).load64(off, order)
    }
    #[inline]
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        (**self).store64(off, val, order)
    }
    #[inline]
    fn write64s(&self, off: usize, words: &[u64]) {
        (**self).write64s(off, words)
    }
    #[inline]
    fn bad_accesses(&self) -> u32 {
        (**self).bad_accesses()
    }
}

#[cfg(feature = "std")]
impl<T: Mem + ?Sized> Mem for std::sync::Arc<T> {
    #[inline]
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        (**self).load32(off, order)
    }
    #[inline]
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        (**self).store32(off, val, order)
    }
    #[inline]
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        (**self).load64(off, order)
    }
    #[inline]
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        (**self).store64(off, val, order)
    }
    #[inline]
    fn write64s(&self, off: usize, words: &[u64]) {
        (**self).write64s(off, words)
    }
    #[inline]
    fn bad_accesses(&self) -> u32 {
        (**self).bad_accesses()
    }
}

/// A mapped DPRAM window: a base pointer and a length. It needs 64-bit atomics (a card whose
/// processor has none implements [`Mem`] over its bus itself). It does not own the mapping; whoever
/// creates it keeps the mapping alive for as long as the `Dpram` is used.
///
/// Everything that shares the handle (`&Dpram`, an `Arc` of a window holding it) shares its
/// count of refused accesses ([`Mem::bad_accesses`]).
#[cfg(target_has_atomic = "64")]
#[derive(Debug)]
pub struct Dpram {
    base: NonNull<u8>,
    len: usize,
    bad_accesses: AtomicU32,
}

// SAFETY: all access goes through atomic operations on the shared window, which is designed to
// be used by several threads and processes at once.
#[cfg(target_has_atomic = "64")]
unsafe impl Send for Dpram {}
// SAFETY: as above: `&Dpram` only ever performs atomic loads and stores.
#[cfg(target_has_atomic = "64")]
unsafe impl Sync for Dpram {}

/// The window is too small or misaligned for the layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindowError {
    /// Bytes available.
    pub len: usize,
    /// Bytes the layout needs.
    pub needed: usize,
}

impl core::fmt::Display for WindowError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "DPRAM window of {} bytes is smaller than the {} bytes of the layout, or not 8-byte aligned", self.len, self.needed)
    }
}

impl core::error::Error for WindowError {}

#[cfg(target_has_atomic = "64")]
impl Dpram {
    /// Wrap a mapped window.
    ///
    /// # Safety
    /// `base` must point to `len` bytes that stay mapped, readable and writable for the whole
    /// life of the returned value, and that are only ever accessed atomically by others.
    pub unsafe fn from_raw(base: *mut u8, len: usize) -> Result<Self, WindowError> {
        let needed = core::mem::size_of::<crate::raw::mc_dpram>();
        let base = NonNull::new(base).ok_or(WindowError { len, needed })?;
        if len < needed || !(base.as_ptr() as usize).is_multiple_of(8) {
            return Err(WindowError { len, needed });
        }
        Ok(Self {
            base,
            len,
            bad_accesses: AtomicU32::new(0),
        })
    }

    /// Length of the window in bytes.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Never true: a window holds at least the layout.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The address of the `width`-byte word at `off`, or `None` (counted, and a panic in debug
    /// builds) when it is out of range or misaligned.
    #[inline]
    fn word_ptr(&self, off: usize, width: usize) -> Option<*mut u8> {
        let in_range = off.checked_add(width).is_some_and(|end| end <= self.len);
        if !in_range || !off.is_multiple_of(width) {
            self.refuse(off, width);
            return None;
        }
        // SAFETY: `off + width <= len`, so the result stays inside the mapping.
        Some(unsafe { self.base.as_ptr().add(off) })
    }

    /// A run of words not wholly in range or aligned: word by word, each bad one refused.
    #[cold]
    #[inline(never)]
    fn write64s_one_by_one(&self, off: usize, words: &[u64]) {
        for (i, w) in words.iter().enumerate() {
            self.store64(off + 8 * i, *w, Ordering::Relaxed);
        }
    }

    #[cold]
    #[inline(never)]
    fn refuse(&self, off: usize, width: usize) {
        debug_assert!(
            false,
            "DPRAM access out of range or misaligned: {width}-byte word at offset {off} of a \
             {}-byte window",
            self.len
        );
        self.bad_accesses.fetch_add(1, Ordering::Relaxed);
    }
}

#[cfg(target_has_atomic = "64")]
impl Mem for Dpram {
    #[inline]
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        match self.word_ptr(off, 4) {
            // SAFETY: in bounds and 4-aligned (checked); the memory is only accessed atomically.
            Some(p) => unsafe { AtomicU32::from_ptr(p.cast()) }.load(order),
            None => 0,
        }
    }
    #[inline]
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        if let Some(p) = self.word_ptr(off, 4) {
            // SAFETY: in bounds and 4-aligned (checked); the memory is only accessed atomically.
            unsafe { AtomicU32::from_ptr(p.cast()) }.store(val, order)
        }
    }
    #[inline]
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        match self.word_ptr(off, 8) {
            // SAFETY: in bounds and 8-aligned (checked); the memory is only accessed atomically.
            Some(p) => unsafe { AtomicU64::from_ptr(p.cast()) }.load(order),
            None => 0,
        }
    }
    #[inline]
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        if let Some(p) = self.word_ptr(off, 8) {
            // SAFETY: in bounds and 8-aligned (checked); the memory is only accessed atomically.
            unsafe { AtomicU64::from_ptr(p.cast()) }.store(val, order)
        }
    }
    /// One check for the whole run; a run that is not wholly in range and aligned is stored
    /// word by word, as the default does (the good words stored, each bad one refused).
    #[inline]
    fn write64s(&self, off: usize, words: &[u64]) {
        let in_range = words
            .len()
            .checked_mul(8)
            .and_then(|n| off.checked_add(n))
            .is_some_and(|end| end <= self.len);
        if !in_range || !off.is_multiple_of(8) {
            self.write64s_one_by_one(off, words);
            return;
        }
        // SAFETY: `off + 8 * words.len() <= len` (checked), so every word stays inside the
        // mapping.
        let p = unsafe { self.base.as_ptr().add(off) }.cast::<u64>();
        for (i, w) in words.iter().enumerate() {
            // SAFETY: in bounds (above) and 8-aligned (`off` is, and the mapping's base: see
            // `from_raw`); the memory is only accessed atomically.
            unsafe { AtomicU64::from_ptr(p.add(i)) }.store(*w, Ordering::Relaxed);
        }
    }
    #[inline]
    fn bad_accesses(&self) -> u32 {
        self.bad_accesses.load(Ordering::Relaxed)
    }
}

/// A DPRAM window in ordinary heap memory: the `sim` card and unit tests use it.
#[cfg(feature = "std")]
pub struct HeapWindow {
    // Atomic words: interior mutability, so the raw pointer in `dpram` stays valid while the
    // Box is moved or borrowed.
    words: Box<[std::sync::atomic::AtomicU64]>,
    dpram: Dpram,
}

#[cfg(feature = "std")]
impl HeapWindow {
    /// A zeroed window of [`crate::DPRAM_SIZE`] bytes.
    pub fn new() -> Self {
        let words: Box<[std::sync::atomic::AtomicU64]> = (0..crate::DPRAM_SIZE / 8)
            .map(|_| std::sync::atomic::AtomicU64::new(0))
            .collect();
        let base = words.as_ptr().cast_mut().cast::<u8>();
        // SAFETY: the boxed slice lives as long as `self` and is never accessed except through
        // `dpram` (atomically); moving the Box does not move its heap allocation.
        let dpram = unsafe { Dpram::from_raw(base, crate::DPRAM_SIZE) }
            .expect("heap window is large and aligned");
        Self { words, dpram }
    }

    /// The window.
    pub fn dpram(&self) -> &Dpram {
        let _ = &self.words;
        &self.dpram
    }
}

#[cfg(feature = "std")]
impl Default for HeapWindow {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(feature = "std")]
impl Mem for HeapWindow {
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

#[cfg(all(test, not(loom)))]
mod tests {
    use super::*;

    /// Release builds: a bad access touches nothing, loads 0, and is counted by every handle
    /// that shares the window.
    #[test]
    #[cfg(not(debug_assertions))]
    fn out_of_range_and_misaligned_access_is_ignored_and_counted() {
        let w = std::sync::Arc::new(HeapWindow::new());
        let d = w.dpram();
        assert_eq!(d.bad_accesses(), 0);
        d.write32(d.len(), 7); // out of range
        assert_eq!(d.read32(d.len()), 0);
        d.write32(usize::MAX - 1, 7); // out of range, offset + width overflows
        assert_eq!(d.bad_accesses(), 3);
        d.write64(4, 7); // misaligned for 64-bit
        assert_eq!(d.read64(0), 0, "the misaligned store touched nothing");
        assert_eq!(d.read32(2), 0); // misaligned for 32-bit
        assert_eq!(d.bad_accesses(), 5);
        d.write64(8, u64::MAX);
        assert_eq!(d.read64(8), u64::MAX);
        assert_eq!(d.read32(12), u32::MAX);
        assert_eq!(d.bad_accesses(), 5, "good accesses are not counted");
        // The window, a reference and a clone of the Arc all see the same count.
        let shared = w.clone();
        assert_eq!(shared.bad_accesses(), 5);
        let by_ref: &HeapWindow = &w;
        assert_eq!(by_ref.bad_accesses(), 5);
        shared.read64(d.len() - 4);
        assert_eq!(w.bad_accesses(), 6);
    }

    /// A run of words lands as the word-by-word stores would: in order at `off`; a run that
    /// ends past the window stores its words in range and refuses (counts) the rest.
    #[test]
    fn a_run_of_words_is_stored_as_its_words_would_be() {
        let w = HeapWindow::new();
        let d = w.dpram();
        d.write64s(64, &[1, 2, 3]);
        assert_eq!([d.read64(64), d.read64(72), d.read64(80)], [1, 2, 3]);
        assert_eq!(d.read64(88), 0);
        d.write64s(64, &[]);
        assert_eq!(d.read64(64), 1);
        #[cfg(not(debug_assertions))]
        {
            let end = d.len();
            d.write64s(end - 16, &[7, 8, 9, 10]);
            assert_eq!([d.read64(end - 16), d.read64(end - 8)], [7, 8]);
            assert_eq!(d.bad_accesses(), 2, "the two words past the end");
            d.write64s(4, &[5]);
            assert_eq!(d.read64(0), 0, "the misaligned run touched nothing");
            assert_eq!(d.bad_accesses(), 3);
        }
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "out of range or misaligned: 4-byte word at offset 1048576")]
    fn out_of_range_access_panics_in_debug_builds() {
        let w = HeapWindow::new();
        w.write32(w.dpram().len(), 7);
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "out of range or misaligned: 8-byte word at offset 4")]
    fn misaligned_access_panics_in_debug_builds() {
        let w = HeapWindow::new();
        w.read64(4);
    }

    #[test]
    fn small_window_refused() {
        let mut buf = vec![0u64; 16];
        // SAFETY: buf outlives the call; the result is dropped at once.
        let r = unsafe { Dpram::from_raw(buf.as_mut_ptr().cast(), 128) };
        assert_eq!(
            r.unwrap_err().needed,
            core::mem::size_of::<crate::raw::mc_dpram>()
        );
    }
}
