//! Status blocks whose content stands still: rewritten whole only when it changed.
//!
//! Every tick the card publishes each group's status, and most groups most of the time are
//! disabled or at rest: only the tick word moves. Writing such a block whole costs its 23
//! stores and its checksum; [`GroupBlock::publish`] compares the status with what it last wrote
//! and then rewrites only the tick word and the checksum (updated from the one before, a term
//! an xor away: [`firmware_proto::status_checksum_after`]), under the same seqlock.
//!
//! What that gives up: the card no longer restores, every tick, a block something else wrote
//! into. Nothing should: every status block has one writer, the card (the header's rules); the
//! SDK and the C ABI only read them. A stray write anyway (a host's bug, a bus error) fails the
//! block's checksum, since the checksum the card writes is its own and not recomputed from the
//! window, so the host reports the block corrupt rather than reading it; and every
//! [`REWRITE_TICKS`] ticks the card rewrites the block whole, which bounds how long such damage
//! lasts (6.4 ms at 10 kHz).

use firmware_proto::{layout, seqlock, status_checksum_after, GroupStatus, Mem, STATUS_WORDS};

/// Ticks between two whole rewrites of a block whose content stood still.
pub const REWRITE_TICKS: u64 = 64;

/// The payload word of the tick.
const TICK_WORD: usize = core::mem::offset_of!(GroupStatus, tick) / 8;
/// The first of the payload's reserved words, which [`GroupStatus`] leaves 0 (a field the
/// layout adds goes before them, and moves this along).
const RESERVED_WORD: usize = core::mem::offset_of!(GroupStatus, _reserved) / 8;
/// The payload word of the checksum.
const CHECKSUM_WORD: usize = STATUS_WORDS - 1;
const _: () = assert!(TICK_WORD < RESERVED_WORD && RESERVED_WORD < CHECKSUM_WORD);

/// One group's status block, as the card last wrote it.
#[derive(Debug, Clone, Copy, Default)]
pub struct GroupBlock {
    /// The payload written, its checksum included; `None` before the first write.
    written: Option<[u64; STATUS_WORDS]>,
}

impl GroupBlock {
    /// Publish group `g`'s status `s` of tick `tick`: whole when it changed since the last
    /// write (the tick aside) or on the group's turn to be rewritten, else its tick word and
    /// checksum. The groups take turns (`tick + g`), so no tick rewrites them all.
    #[inline]
    pub fn publish<M: Mem>(&mut self, mem: &M, g: usize, s: &GroupStatus, tick: u64) {
        let new = s.as_words();
        if let Some(old) = &mut self.written {
            let due = tick.wrapping_add(g as u64).is_multiple_of(REWRITE_TICKS);
            if !due && same_but_tick(new, old) {
                let checksum = status_checksum_after(
                    old[CHECKSUM_WORD],
                    TICK_WORD,
                    old[TICK_WORD],
                    new[TICK_WORD],
                );
                seqlock::write_status_word(
                    mem,
                    layout::group_status(g),
                    TICK_WORD,
                    new[TICK_WORD],
                    checksum,
                );
                old[TICK_WORD] = new[TICK_WORD];
                old[CHECKSUM_WORD] = checksum;
                return;
            }
        }
        let checksum = seqlock::write_group_status(mem, g, s);
        let mut written = *new;
        written[CHECKSUM_WORD] = checksum;
        self.written = Some(written);
    }
}

/// Do the payloads agree in every word before the reserved ones but the tick's?
#[inline]
fn same_but_tick(a: &[u64; STATUS_WORDS], b: &[u64; STATUS_WORDS]) -> bool {
    // The words' xors ored, no early exit: the words are few and mostly equal.
    let diff = |x: &[u64], y: &[u64]| x.iter().zip(y).fold(0, |d, (p, q)| d | (p ^ q));
    let before = diff(&a[..TICK_WORD], &b[..TICK_WORD]);
    let after = diff(
        &a[TICK_WORD + 1..RESERVED_WORD],
        &b[TICK_WORD + 1..RESERVED_WORD],
    );
    before | after == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::mem::HeapWindow;

    fn read(w: &HeapWindow, g: usize) -> Result<GroupStatus, seqlock::SnapshotError> {
        seqlock::read_group_status(w.dpram(), g)
    }

    /// A group at rest: the tick moves, the rest stays, and each read checks out; a change is
    /// written whole at once.
    #[test]
    fn a_group_at_rest_keeps_a_valid_block() {
        let w = HeapWindow::new();
        let mut b = GroupBlock::default();
        let mut s = GroupStatus {
            state: 1,
            feed_override: 1.0,
            rapid_override: 1.0,
            ..Default::default()
        };
        for tick in 1..200 {
            s.tick = tick;
            if tick == 150 {
                s.queued = 2;
                s.path_pos = 3.5;
            }
            b.publish(w.dpram(), 2, &s, tick);
            assert_eq!(
                read(&w, 2),
                Ok(GroupStatus { checksum: 0, ..s }),
                "tick {tick}"
            );
        }
    }

    /// A stray write into a block at rest fails its checksum until the group's turn to be
    /// rewritten whole, at most `REWRITE_TICKS` ticks later.
    #[test]
    fn a_stray_write_fails_the_checksum_until_the_rewrite() {
        let w = HeapWindow::new();
        let mut b = GroupBlock::default();
        let mut s = GroupStatus::default();
        let g = 1;
        let payload = layout::group_status(g) + layout::STATUS_PAYLOAD;
        let mut corrupt_ticks = 0;
        for tick in 1..=3 * REWRITE_TICKS {
            s.tick = tick;
            b.publish(w.dpram(), g, &s, tick);
            if tick == 10 {
                // path_len
                w.dpram().write64(payload + 40, 0x1234);
            }
            match read(&w, g) {
                Ok(r) => assert_eq!(r, s),
                Err(e) => {
                    assert_eq!(e, seqlock::SnapshotError::Corrupt);
                    corrupt_ticks += 1;
                }
            }
        }
        // Ticks 10 to 62 (the rewrite at tick + g = 64).
        assert_eq!(corrupt_ticks, REWRITE_TICKS - 1 - 10);
    }
}
