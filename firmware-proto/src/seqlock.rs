//! Seqlock-protected status blocks (after Amanieu/seqlock and Linux `perf_event_mmap_page`).
//!
//! Writer (the card, the only writer of a block): make `seq` odd, `Release` fence, write the
//! payload words, store `seq + 2` with `Release`. Reader: `Acquire` load of `seq` (retry while
//! odd), copy the payload as atomic words, `Acquire` fence, reload `seq`; equal means the copy is
//! consistent. Retries are bounded, so a stuck or dead writer cannot hang a reader.

use crate::layout;
use crate::mem::Mem;
use crate::sync::{fence, Ordering};
use crate::wire::{status_checksum, AxisStatus, GroupStatus, STATUS_WORDS};

/// A consistent copy could not be taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SnapshotError {
    /// The writer kept the block busy through every retry.
    Busy,
    /// A consistent copy failed its checksum: the block holds garbage.
    Corrupt,
}

impl core::fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SnapshotError::Busy => write!(f, "status block stayed busy through every retry"),
            SnapshotError::Corrupt => write!(f, "status block failed its checksum"),
        }
    }
}

impl core::error::Error for SnapshotError {}

/// Retries before [`SnapshotError::Busy`].
pub const MAX_RETRIES: u32 = 1000;

/// Write a payload under the seqlock at `seq_off` (payload at `seq_off + STATUS_PAYLOAD`).
#[inline(always)]
pub fn write_words<M: Mem>(mem: &M, seq_off: usize, words: &[u64; STATUS_WORDS]) {
    let seq = mem.load32(seq_off, Ordering::Relaxed);
    // An even sequence normally; if the window was scribbled, realign to even first.
    let seq = seq & !1;
    mem.store32(seq_off, seq.wrapping_add(1), Ordering::Relaxed);
    fence(Ordering::Release);
    mem.write64s(seq_off + layout::STATUS_PAYLOAD, words);
    mem.store32(seq_off, seq.wrapping_add(2), Ordering::Release);
}

/// Copy a consistent payload, with at most `retries` attempts.
pub fn read_words<M: Mem>(
    mem: &M,
    seq_off: usize,
    retries: u32,
) -> Result<[u64; STATUS_WORDS], SnapshotError> {
    let base = seq_off + layout::STATUS_PAYLOAD;
    for _ in 0..retries.max(1) {
        let s1 = mem.load32(seq_off, Ordering::Acquire);
        if s1 & 1 == 1 {
            core::hint::spin_loop();
            continue;
        }
        let mut words = [0u64; STATUS_WORDS];
        for (i, w) in words.iter_mut().enumerate() {
            *w = mem.load64(base + 8 * i, Ordering::Relaxed);
        }
        fence(Ordering::Acquire);
        let s2 = mem.load32(seq_off, Ordering::Relaxed);
        if s1 == s2 {
            return Ok(words);
        }
        core::hint::spin_loop();
    }
    Err(SnapshotError::Busy)
}

/// Write a status payload under the seqlock at `seq_off`, its checksum (the last word, which
/// `words` need not hold) computed after the other words are stored: the same words as
/// [`write_words`] of `to_words()`, but the payload is not held in registers across the
/// checksum (the card publishes 12 a tick, and computing the checksum first spilled them).
/// Returns the checksum written.
#[inline(always)]
pub fn write_status_words<M: Mem>(mem: &M, seq_off: usize, words: &[u64; STATUS_WORDS]) -> u64 {
    let seq = mem.load32(seq_off, Ordering::Relaxed) & !1;
    mem.store32(seq_off, seq.wrapping_add(1), Ordering::Relaxed);
    fence(Ordering::Release);
    let base = seq_off + layout::STATUS_PAYLOAD;
    mem.write64s(base, &words[..STATUS_WORDS - 1]);
    let checksum = status_checksum(words);
    mem.write64(base + 8 * (STATUS_WORDS - 1), checksum);
    mem.store32(seq_off, seq.wrapping_add(2), Ordering::Release);
    checksum
}

/// Rewrite word `i` of the status payload under the seqlock at `seq_off` as `value`, and its
/// checksum as `checksum` (the caller's, e.g. [`crate::status_checksum_after`]), leaving the
/// other words as they are: for a writer that knows nothing else changed since it last wrote
/// the whole payload (the card's groups at rest: only their tick moves).
#[inline]
pub fn write_status_word<M: Mem>(mem: &M, seq_off: usize, i: usize, value: u64, checksum: u64) {
    debug_assert!(i < STATUS_WORDS - 1);
    let seq = mem.load32(seq_off, Ordering::Relaxed) & !1;
    mem.store32(seq_off, seq.wrapping_add(1), Ordering::Relaxed);
    fence(Ordering::Release);
    let base = seq_off + layout::STATUS_PAYLOAD;
    mem.write64(base + 8 * i, value);
    mem.write64(base + 8 * (STATUS_WORDS - 1), checksum);
    mem.store32(seq_off, seq.wrapping_add(2), Ordering::Release);
}

/// Publish an axis's status (card side).
#[inline]
pub fn write_axis_status<M: Mem>(mem: &M, axis: usize, status: &AxisStatus) {
    write_status_words(mem, layout::axis_status(axis), status.as_words());
}

/// Read an axis's status (host side): consistent and checksum-verified.
pub fn read_axis_status<M: Mem>(mem: &M, axis: usize) -> Result<AxisStatus, SnapshotError> {
    let words = read_words(mem, layout::axis_status(axis), MAX_RETRIES)?;
    AxisStatus::from_words(&words).ok_or(SnapshotError::Corrupt)
}

#[cfg(all(test, not(loom)))]
mod tests {
    use super::*;
    use crate::mem::HeapWindow;
    use std::sync::atomic::{AtomicBool, Ordering as O};
    use std::sync::Arc;

    #[test]
    fn round_trip() {
        let w = HeapWindow::new();
        let s = AxisStatus {
            cmd_pos: 12.5,
            state: 3,
            tick: 7,
            ..Default::default()
        };
        write_axis_status(w.dpram(), 2, &s);
        assert_eq!(read_axis_status(w.dpram(), 2), Ok(s));
        assert_eq!(w.dpram().read32(layout::axis_status(2)), 2);
    }

    #[test]
    fn writer_stuck_mid_write_gives_busy_not_a_torn_copy() {
        let w = HeapWindow::new();
        write_axis_status(w.dpram(), 0, &AxisStatus::default());
        // The writer made seq odd and died.
        w.dpram().write32(layout::axis_status(0), 3);
        assert_eq!(
            read_words(w.dpram(), layout::axis_status(0), 10),
            Err(SnapshotError::Busy)
        );
    }

    /// A window in which a writer slips in a whole new payload while the reader is copying the
    /// first one: the copy is torn, so the reader must retry and return the new payload.
    struct WriterInTheMiddle {
        w: HeapWindow,
        seq_loads: std::cell::Cell<u32>,
        interrupted: std::cell::Cell<bool>,
    }

    impl Mem for WriterInTheMiddle {
        fn load32(&self, off: usize, order: core::sync::atomic::Ordering) -> u32 {
            if off == layout::axis_status(0) {
                self.seq_loads.set(self.seq_loads.get() + 1);
            }
            self.w.dpram().load32(off, order)
        }
        fn store32(&self, off: usize, val: u32, order: core::sync::atomic::Ordering) {
            self.w.dpram().store32(off, val, order)
        }
        fn load64(&self, off: usize, order: core::sync::atomic::Ordering) -> u64 {
            let v = self.w.dpram().load64(off, order);
            // Halfway through the first copy, the card publishes tick 2.
            if off == layout::axis_status(0) + layout::STATUS_PAYLOAD + 8 * 12
                && !self.interrupted.replace(true)
            {
                let s = AxisStatus {
                    tick: 2,
                    cmd_pos: 2.0,
                    ..Default::default()
                };
                write_axis_status(self.w.dpram(), 0, &s);
            }
            v
        }
        fn store64(&self, off: usize, val: u64, order: core::sync::atomic::Ordering) {
            self.w.dpram().store64(off, val, order)
        }
    }

    #[test]
    fn a_write_during_the_copy_makes_the_reader_retry() {
        let m = WriterInTheMiddle {
            w: HeapWindow::new(),
            seq_loads: Default::default(),
            interrupted: Default::default(),
        };
        let first = AxisStatus {
            tick: 1,
            cmd_pos: 1.0,
            ..Default::default()
        };
        write_axis_status(m.w.dpram(), 0, &first);
        m.seq_loads.set(0);
        let s = read_axis_status(&m, 0).unwrap();
        assert!(m.interrupted.get());
        assert_eq!((s.tick, s.cmd_pos), (2, 2.0), "a torn or stale copy: {s:?}");
        // Two loads of seq for the torn attempt, two for the good one.
        assert_eq!(m.seq_loads.get(), 4);
    }

    #[test]
    fn garbage_payload_fails_checksum() {
        let w = HeapWindow::new();
        write_axis_status(w.dpram(), 1, &AxisStatus::default());
        w.dpram()
            .write64(layout::axis_status(1) + layout::STATUS_PAYLOAD + 16, 0x1234);
        assert_eq!(read_axis_status(w.dpram(), 1), Err(SnapshotError::Corrupt));
    }

    /// Torn-write retries: a reader racing a writer never sees a mixed payload. Each payload has
    /// every value field equal to one counter, so a mixed copy is detectable even without the
    /// checksum; the checksum is checked too.
    #[test]
    fn concurrent_readers_never_see_a_torn_snapshot() {
        let w = Arc::new(HeapWindow::new());
        write_axis_status(&*w, 3, &AxisStatus::default());
        let stop = Arc::new(AtomicBool::new(false));
        let writer = {
            let (w, stop) = (w.clone(), stop.clone());
            std::thread::spawn(move || {
                let mut n = 0u64;
                while !stop.load(O::Relaxed) {
                    n += 1;
                    let x = n as f64;
                    let s = AxisStatus {
                        cmd_pos: x,
                        cmd_vel: x,
                        act_pos: x,
                        ferr: x,
                        tick: n,
                        encoder: n as i64,
                        ..Default::default()
                    };
                    write_axis_status(&*w, 3, &s);
                    // Gaps of varying length between writes, as the card's ticks leave: a
                    // writer that never pauses would let no read through on a loaded machine
                    // (each read would be retried until busy), which tests nothing.
                    for _ in 0..(n % 256) {
                        std::hint::spin_loop();
                    }
                    if n.is_multiple_of(64) {
                        std::thread::yield_now();
                    }
                }
                n
            })
        };
        let mut seen = 0u64;
        let mut busy = 0u64;
        for _ in 0..200_000 {
            match read_axis_status(&*w, 3) {
                Ok(s) => {
                    assert!(
                        s.cmd_pos == s.act_pos
                            && s.cmd_vel == s.ferr
                            && s.tick as f64 == s.cmd_pos
                            && s.encoder as u64 == s.tick,
                        "torn: {s:?}"
                    );
                    assert!(s.tick >= seen, "went backwards");
                    seen = s.tick;
                }
                Err(SnapshotError::Busy) => busy += 1,
                Err(SnapshotError::Corrupt) => panic!("checksum failed on a consistent copy"),
            }
        }
        stop.store(true, O::Relaxed);
        let written = writer.join().unwrap();
        assert!(written > 0);
        assert!(seen > 0 && busy < 200_000, "every read was busy");
    }
}

/// Publish a group's status (card side). Returns the checksum written.
#[inline]
pub fn write_group_status<M: Mem>(mem: &M, group: usize, status: &GroupStatus) -> u64 {
    write_status_words(mem, layout::group_status(group), status.as_words())
}

/// Read a group's status (host side): consistent and checksum-verified.
pub fn read_group_status<M: Mem>(mem: &M, group: usize) -> Result<GroupStatus, SnapshotError> {
    let words = read_words(mem, layout::group_status(group), MAX_RETRIES)?;
    GroupStatus::from_words(&words).ok_or(SnapshotError::Corrupt)
}
