//! Typed access to the blocks of the window: a block is one of the header's structs, read or
//! written whole, so its fields are listed once (in the header, and so in the bindings) and
//! nowhere else.
//!
//! [`BlockAt<B>`] is the place of one block; [`Blocks<B, N>`] an array of per-axis or per-group
//! blocks with [`Blocks::at`] (panics on a bad index, for indices the caller has checked) and
//! [`Blocks::try_at`]. A block moves as 64-bit words, each an atomic access of the window, so
//! no `f64` is ever torn; a block as a whole is consistent when its writer publishes it
//! before it is read (configuration blocks: written, then the apply command is published with
//! Release) — status blocks that change under the reader use [`crate::seqlock`] instead.
//!
//! ```
//! use firmware_proto::{layout, mem::HeapWindow};
//! let window = HeapWindow::new();
//! let mem = window.dpram();
//! let mut cfg = layout::AXIS_CONFIG.at(2).read(mem);
//! cfg.ffpiv.kp = 90.0;
//! layout::AXIS_CONFIG.at(2).write(mem, &cfg);
//! assert_eq!(layout::AXIS_CONFIG.at(2).read(mem).ffpiv.kp, 90.0);
//! ```

use crate::mem::Mem;
use crate::raw;
use core::marker::PhantomData;
use core::mem::{align_of, size_of, MaybeUninit};

/// A struct of the register map that moves as a whole.
///
/// # Safety
/// Implemented only (by `blocks!` below) for the bindgen structs of the header: plain data in
/// which every bit pattern is a valid value (integers, `f64`, arrays of them), with no
/// implicit padding (the header declares its gaps as `_reserved` fields, and the bindings are
/// generated with explicit padding) and a whole number of 64-bit words long (asserted at
/// compile time).
pub unsafe trait Block: Copy + 'static {
    /// Size in 64-bit words.
    const WORDS: usize = size_of::<Self>() / 8;
}

macro_rules! blocks {
    ($($t:ident),+ $(,)?) => {$(
        // SAFETY: a header struct of plain integers and doubles (see `Block`); the asserts
        // below check its alignment and size.
        unsafe impl Block for raw::$t {}
        const _: () = assert!(align_of::<raw::$t>() >= 4 && size_of::<raw::$t>().is_multiple_of(8));
    )+};
}

blocks!(
    mc_axis_status_payload,
    mc_group_status_payload,
    mc_card_config,
    mc_axis_config,
    mc_axis_filter,
    mc_group_config,
    mc_axis_pdplus,
    mc_safety_config,
    mc_axis_safety,
    mc_axis_homing,
    mc_group_path,
    mc_io_config,
    mc_compare_status,
    mc_probe_status,
    mc_sync_status,
    mc_scope_config,
    mc_scope_status,
    mc_comp_readback,
    mc_gantry_status,
    mc_axis_pidff,
    mc_servo_filters,
    mc_analog_status,
    mc_card_info,
    mc_freq_status,
    mc_group_dims,
    mc_freq_point,
);

/// A block as `N` words (`N` must be its size in words: checked at compile time).
#[inline]
pub(crate) fn to_words<B: Block, const N: usize>(b: &B) -> [u64; N] {
    const { assert!(size_of::<B>() == 8 * N) };
    // SAFETY: `b` is `N` words of plain data without padding (Block, and the assert above);
    // unaligned because some blocks are only 4-byte aligned.
    unsafe { (b as *const B).cast::<[u64; N]>().read_unaligned() }
}

/// A block seen as `N` words, in place (`N` must be its size in words, and the block 8-byte
/// aligned: both checked at compile time).
#[inline]
pub(crate) fn as_words<B: Block, const N: usize>(b: &B) -> &[u64; N] {
    const { assert!(size_of::<B>() == 8 * N && align_of::<B>() >= align_of::<u64>()) };
    // SAFETY: `b` is `N` words of plain data without padding (Block, and the assert above),
    // aligned for `u64` (the assert), and borrowed for as long as the result.
    unsafe { &*(b as *const B).cast::<[u64; N]>() }
}

/// A block from `N` words (`N` must be its size in words: checked at compile time).
#[inline]
pub(crate) fn from_words<B: Block, const N: usize>(w: &[u64; N]) -> B {
    const { assert!(size_of::<B>() == 8 * N) };
    // SAFETY: `w` is `size_of::<B>()` bytes (the assert above), and every bit pattern is a
    // valid `B` (Block).
    unsafe { (w as *const [u64; N]).cast::<B>().read_unaligned() }
}

/// The place of one block `B` in the window.
#[derive(Debug)]
pub struct BlockAt<B> {
    off: usize,
    _b: PhantomData<fn() -> B>,
}

impl<B> Clone for BlockAt<B> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<B> Copy for BlockAt<B> {}

impl<B: Block> BlockAt<B> {
    /// The block at byte offset `off` (a multiple of 8).
    pub const fn new(off: usize) -> Self {
        assert!(off.is_multiple_of(8));
        Self {
            off,
            _b: PhantomData,
        }
    }

    /// Its byte offset in the window.
    pub const fn offset(self) -> usize {
        self.off
    }

    /// The byte range it covers.
    pub const fn range(self) -> core::ops::Range<usize> {
        self.off..self.off + size_of::<B>()
    }

    /// The byte offset of a field at `field` bytes into the block (`offset_of!` on `B`).
    pub const fn field(self, field: usize) -> usize {
        assert!(field < size_of::<B>());
        self.off + field
    }

    /// Read the whole block (relaxed 64-bit loads).
    pub fn read(self, m: &impl Mem) -> B {
        let mut out = MaybeUninit::<B>::uninit();
        let p = out.as_mut_ptr().cast::<u64>();
        for i in 0..B::WORDS {
            // SAFETY: `out` is `B::WORDS` words long (Block) and `i` is in range; the write is
            // unaligned because some blocks are only 4-byte aligned.
            unsafe { p.add(i).write_unaligned(m.read64(self.off + 8 * i)) };
        }
        // SAFETY: every word was written above, and every bit pattern is a valid `B` (Block).
        unsafe { out.assume_init() }
    }

    /// Write the whole block (relaxed 64-bit stores, in order: [`Mem::write64s`]).
    pub fn write(self, m: &impl Mem, b: &B) {
        let p = (b as *const B).cast::<u64>();
        if align_of::<B>() >= align_of::<u64>() {
            // SAFETY: `b` is `B::WORDS` words of plain data with no padding that could be
            // uninitialised (Block), aligned for `u64` (the condition above), and borrowed for
            // the call.
            let words = unsafe { core::slice::from_raw_parts(p, B::WORDS) };
            m.write64s(self.off, words);
            return;
        }
        // A block only 4-byte aligned: through an aligned copy, a few words at a time.
        const CHUNK: usize = 16;
        let mut buf = [0u64; CHUNK];
        let mut i = 0;
        while i < B::WORDS {
            let n = (B::WORDS - i).min(CHUNK);
            for (k, w) in buf[..n].iter_mut().enumerate() {
                // SAFETY: `i + k < B::WORDS`, within `b` (plain data, see above); unaligned as
                // in `read`.
                *w = unsafe { p.add(i + k).read_unaligned() };
            }
            m.write64s(self.off + 8 * i, &buf[..n]);
            i += n;
        }
    }
}

/// An array of `N` blocks `B`: one per axis or per group.
#[derive(Debug)]
pub struct Blocks<B, const N: usize> {
    first: BlockAt<B>,
}

impl<B, const N: usize> Clone for Blocks<B, N> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<B, const N: usize> Copy for Blocks<B, N> {}

impl<B: Block, const N: usize> Blocks<B, N> {
    /// The array at byte offset `off`.
    pub const fn new(off: usize) -> Self {
        Self {
            first: BlockAt::new(off),
        }
    }

    /// Block `i`. Panics when `i >= N`: for indices already checked against the card.
    pub const fn at(self, i: usize) -> BlockAt<B> {
        assert!(i < N, "block index out of range");
        BlockAt::new(self.first.off + i * size_of::<B>())
    }

    /// Block `i`, or `None` when `i >= N`.
    pub const fn try_at(self, i: usize) -> Option<BlockAt<B>> {
        if i < N {
            Some(self.at(i))
        } else {
            None
        }
    }

    /// The byte range of the whole array.
    pub const fn range(self) -> core::ops::Range<usize> {
        self.first.off..self.first.off + N * size_of::<B>()
    }
}

#[cfg(test)]
mod tests {
    use crate::mem::HeapWindow;
    use crate::{layout, raw, Mem, MAX_AXES};

    #[test]
    fn a_block_round_trips_and_touches_nothing_else() {
        let w = HeapWindow::new();
        let m = w.dpram();
        let mut b = raw::mc_axis_safety {
            flags: 0xA5,
            limit_category: 2,
            soft_limit_neg: -1.5,
            soft_limit_pos: 2.5e9,
            stop_jerk: f64::MIN_POSITIVE,
            ..Default::default()
        };
        b._reserved[6] = -0.0;
        layout::AXIS_SAFETY.at(3).write(m, &b);
        let back = layout::AXIS_SAFETY.at(3).read(m);
        assert_eq!(back, b);
        assert_eq!(back.stop_jerk.to_bits(), f64::MIN_POSITIVE.to_bits());
        // The neighbours stay zero, and the fields sit where the header puts them.
        assert_eq!(layout::AXIS_SAFETY.at(2).read(m), Default::default());
        assert_eq!(layout::AXIS_SAFETY.at(4).read(m), Default::default());
        let at = layout::AXIS_SAFETY.at(3);
        assert_eq!(at.offset(), layout::AXIS_SAFETY.at(0).offset() + 3 * 128);
        assert_eq!(
            m.read_f64(at.field(core::mem::offset_of!(raw::mc_axis_safety, soft_limit_pos))),
            2.5e9
        );
        assert_eq!(m.read32(at.field(0)), 0xA5);
    }

    #[test]
    fn array_bounds() {
        assert!(layout::AXIS_CONFIG.try_at(MAX_AXES - 1).is_some());
        assert!(layout::AXIS_CONFIG.try_at(MAX_AXES).is_none());
        let r = layout::AXIS_CONFIG.range();
        assert_eq!(r.end - r.start, MAX_AXES * layout::AXIS_CONFIG_BYTES);
        assert!(std::panic::catch_unwind(|| layout::GROUP_CONFIG.at(crate::MAX_GROUPS)).is_err());
    }

    #[test]
    fn a_four_byte_aligned_block_moves_as_whole_words() {
        let w = HeapWindow::new();
        let m = w.dpram();
        let b = raw::mc_safety_config {
            watchdog_timeout_us: 7,
            estop_input_category: 2,
            max_stop_time_us: 123_456,
            ..Default::default()
        };
        layout::SAFETY_CONFIG.write(m, &b);
        assert_eq!(layout::SAFETY_CONFIG.read(m), b);
        assert_eq!(m.read32(layout::SAFETY_CONFIG.offset() + 8), 123_456);
    }
}
