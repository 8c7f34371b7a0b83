//! Single-producer single-consumer rings in the shared window.
//!
//! The rules (after io_uring's squeue/cqueue and nova-core's cmdq):
//! - indices are free-running `u32`s; entry `i` lives in slot `i & (LEN - 1)`;
//! - each side keeps its own index in a local and reloads the peer's with `Acquire`;
//! - the producer writes the entry words (`Relaxed`), then publishes `head` with `Release`;
//!   the consumer reads the entry after an `Acquire` load of `head`, then publishes `tail`
//!   with `Release`, which hands the slot back;
//! - a peer index is untrusted: `head - tail > LEN` means the peer is broken, and the ring
//!   reports [`RingError::Corrupt`] instead of reading garbage or overwriting unread entries.

use crate::layout;
use crate::mem::Mem;
use crate::raw;
use crate::sync::Ordering;
use crate::wire::{Command, Event, CMD_WORDS, EVT_WORDS};

/// Where a ring lives in the window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RingLayout {
    /// Offset of the producer's index.
    pub head: usize,
    /// Offset of the consumer's index.
    pub tail: usize,
    /// Offset of slot 0.
    pub entries: usize,
    /// Bytes per slot.
    pub entry_bytes: usize,
    /// Slots (a power of two).
    pub len: u32,
}

/// The command ring: host produces, card consumes.
pub const CMD_RING: RingLayout = RingLayout {
    head: layout::CMD_HEAD,
    tail: layout::CMD_TAIL,
    entries: layout::CMD_RING,
    entry_bytes: layout::CMD_BYTES,
    len: raw::MC_CMD_RING_LEN,
};

/// The event ring: card produces, host consumes.
pub const EVT_RING: RingLayout = RingLayout {
    head: layout::EVT_HEAD,
    tail: layout::EVT_TAIL,
    entries: layout::EVT_RING,
    entry_bytes: layout::EVT_BYTES,
    len: raw::MC_EVT_RING_LEN,
};

/// An entry moved as `N` 64-bit words.
pub trait Entry<const N: usize>: Sized {
    /// Encode.
    fn encode(&self) -> [u64; N];
    /// Decode (never fails; meaning is checked by the user).
    fn decode(words: &[u64; N]) -> Self;
}

impl Entry<CMD_WORDS> for Command {
    fn encode(&self) -> [u64; CMD_WORDS] {
        self.to_words()
    }
    fn decode(words: &[u64; CMD_WORDS]) -> Self {
        Command::from_words(words)
    }
}

impl Entry<EVT_WORDS> for Event {
    fn encode(&self) -> [u64; EVT_WORDS] {
        self.to_words()
    }
    fn decode(words: &[u64; EVT_WORDS]) -> Self {
        Event::from_words(words)
    }
}

/// A ring operation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RingError {
    /// No free slot (producer).
    Full,
    /// The indices in the window are inconsistent: `head - tail` exceeds the ring length.
    Corrupt {
        /// The head read.
        head: u32,
        /// The tail read.
        tail: u32,
    },
}

impl core::fmt::Display for RingError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RingError::Full => write!(f, "ring full"),
            RingError::Corrupt { head, tail } => {
                write!(f, "ring indices corrupt (head {head}, tail {tail})")
            }
        }
    }
}

impl core::error::Error for RingError {}

fn slot_offset(layout: &RingLayout, index: u32) -> usize {
    layout.entries + (index & (layout.len - 1)) as usize * layout.entry_bytes
}

/// The producing side of a ring.
#[derive(Debug)]
pub struct Producer<M: Mem, const N: usize> {
    mem: M,
    layout: RingLayout,
    head: u32,
    cached_tail: u32,
}

impl<M: Mem, const N: usize> Producer<M, N> {
    /// Attach to a ring, continuing from the head found in the window (our own index).
    pub fn attach(mem: M, layout: RingLayout) -> Self {
        let head = mem.load32(layout.head, Ordering::Relaxed);
        let cached_tail = mem.load32(layout.tail, Ordering::Acquire);
        Self {
            mem,
            layout,
            head,
            cached_tail,
        }
    }

    /// Free slots, reloading the consumer's index.
    pub fn free(&mut self) -> Result<u32, RingError> {
        self.cached_tail = self.mem.load32(self.layout.tail, Ordering::Acquire);
        let used = self.head.wrapping_sub(self.cached_tail);
        if used > self.layout.len {
            return Err(RingError::Corrupt {
                head: self.head,
                tail: self.cached_tail,
            });
        }
        Ok(self.layout.len - used)
    }

    /// Write one entry and publish it.
    pub fn push<E: Entry<N>>(&mut self, entry: &E) -> Result<(), RingError> {
        self.push_all(core::slice::from_ref(entry))
    }

    /// Write `entries` and publish them together (one head update: the consumer sees all of
    /// them or none; a timed command and its timing, layout 1.12). All or nothing: `Full`
    /// when they do not all fit.
    pub fn push_all<E: Entry<N>>(&mut self, entries: &[E]) -> Result<(), RingError> {
        let n = entries.len() as u32;
        let used = self.head.wrapping_sub(self.cached_tail);
        if used + n > self.layout.len && self.free()? < n {
            return Err(RingError::Full);
        }
        for (k, entry) in entries.iter().enumerate() {
            let base = slot_offset(&self.layout, self.head.wrapping_add(k as u32));
            for (i, w) in entry.encode().iter().enumerate() {
                self.mem.store64(base + 8 * i, *w, Ordering::Relaxed);
            }
        }
        self.head = self.head.wrapping_add(n);
        self.mem
            .store32(self.layout.head, self.head, Ordering::Release);
        Ok(())
    }

    /// Our index (entries published so far).
    pub fn head(&self) -> u32 {
        self.head
    }

    /// The memory this ring lives in.
    pub fn mem(&self) -> &M {
        &self.mem
    }
}

/// The consuming side of a ring.
#[derive(Debug)]
pub struct Consumer<M: Mem, const N: usize> {
    mem: M,
    layout: RingLayout,
    tail: u32,
}

impl<M: Mem, const N: usize> Consumer<M, N> {
    /// Attach to a ring, continuing from the tail found in the window (our own index).
    pub fn attach(mem: M, layout: RingLayout) -> Self {
        let tail = mem.load32(layout.tail, Ordering::Relaxed);
        Self { mem, layout, tail }
    }

    /// Entries waiting, reloading the producer's index.
    pub fn pending(&self) -> Result<u32, RingError> {
        let head = self.mem.load32(self.layout.head, Ordering::Acquire);
        let avail = head.wrapping_sub(self.tail);
        if avail > self.layout.len {
            return Err(RingError::Corrupt {
                head,
                tail: self.tail,
            });
        }
        Ok(avail)
    }

    /// The next entry, if any, left in the ring (layout 1.13: the card looks whether the
    /// entry after a command is its second piece before taking it).
    pub fn peek<E: Entry<N>>(&self) -> Result<Option<E>, RingError> {
        if self.pending()? == 0 {
            return Ok(None);
        }
        let base = slot_offset(&self.layout, self.tail);
        let mut words = [0u64; N];
        for (i, w) in words.iter_mut().enumerate() {
            *w = self.mem.load64(base + 8 * i, Ordering::Relaxed);
        }
        Ok(Some(E::decode(&words)))
    }

    /// Take the next entry, if any, and hand its slot back.
    pub fn pop<E: Entry<N>>(&mut self) -> Result<Option<E>, RingError> {
        let e = self.peek()?;
        if e.is_some() {
            self.tail = self.tail.wrapping_add(1);
            self.mem
                .store32(self.layout.tail, self.tail, Ordering::Release);
        }
        Ok(e)
    }

    /// Skip everything pending (used after the consumer finds the ring corrupt and the producer
    /// has been reset).
    pub fn resync(&mut self) {
        self.tail = self.mem.load32(self.layout.head, Ordering::Acquire);
        self.mem
            .store32(self.layout.tail, self.tail, Ordering::Release);
    }

    /// The memory this ring lives in.
    pub fn mem(&self) -> &M {
        &self.mem
    }
}

/// Host side of the command ring.
pub type CmdProducer<M> = Producer<M, CMD_WORDS>;
/// Card side of the command ring.
pub type CmdConsumer<M> = Consumer<M, CMD_WORDS>;
/// Card side of the event ring.
pub type EvtProducer<M> = Producer<M, EVT_WORDS>;
/// Host side of the event ring.
pub type EvtConsumer<M> = Consumer<M, EVT_WORDS>;

#[cfg(all(test, not(loom)))]
mod tests {
    use super::*;
    use crate::mem::HeapWindow;
    use crate::wire::{EventKind, Opcode};

    fn ev(seq: u32) -> Event {
        Event {
            seq,
            kind: EventKind::Ack as u16,
            axis: 1,
            code: 0,
            tick: seq as u64 * 10,
            value: seq as f64,
        }
    }

    #[test]
    fn empty_ring_pops_nothing() {
        let w = HeapWindow::new();
        let mut c = EvtConsumer::attach(w.dpram(), EVT_RING);
        assert_eq!(c.pending(), Ok(0));
        assert_eq!(c.pop::<Event>(), Ok(None));
    }

    /// A peek reads the next entry and leaves it (and the tail the producer sees) in place.
    #[test]
    fn peek_leaves_the_entry_for_the_pop() {
        let w = HeapWindow::new();
        let mut p = CmdProducer::attach(w.dpram(), CMD_RING);
        let mut c = CmdConsumer::attach(w.dpram(), CMD_RING);
        assert_eq!(c.peek::<Command>(), Ok(None));
        let mut cmds = [Command::new(Opcode::Nop, 0), Command::new(Opcode::Nop, 1)];
        cmds[1].seq = 7;
        p.push_all(&cmds).unwrap();
        let seen: Command = c.peek().unwrap().unwrap();
        assert_eq!((seen.axis, c.pending()), (0, Ok(2)));
        assert_eq!(p.free(), Ok(CMD_RING.len - 2));
        assert_eq!(c.pop::<Command>().unwrap().map(|c| c.axis), Some(0));
        let next: Command = c.peek().unwrap().unwrap();
        assert_eq!((next.axis, next.seq), (1, 7));
        assert_eq!(c.pop::<Command>().unwrap(), Some(next));
        assert_eq!(c.peek::<Command>(), Ok(None));
    }

    #[test]
    fn full_ring_refuses_then_accepts_after_pop() {
        let w = HeapWindow::new();
        let mut p = CmdProducer::attach(w.dpram(), CMD_RING);
        let mut c = CmdConsumer::attach(w.dpram(), CMD_RING);
        let mut cmd = Command::new(Opcode::Nop, 0);
        for i in 0..CMD_RING.len {
            cmd.seq = i;
            p.push(&cmd).unwrap();
        }
        assert_eq!(p.push(&cmd), Err(RingError::Full));
        assert_eq!(p.free(), Ok(0));
        let first: Command = c.pop().unwrap().unwrap();
        assert_eq!(first.seq, 0);
        cmd.seq = 999;
        p.push(&cmd).unwrap();
        let got: Vec<u32> = std::iter::from_fn(|| c.pop::<Command>().unwrap())
            .map(|c| c.seq)
            .collect();
        let mut want: Vec<u32> = (1..CMD_RING.len).collect();
        want.push(999);
        assert_eq!(got, want);
    }

    #[test]
    fn indices_wrap_around_u32() {
        let w = HeapWindow::new();
        let start = u32::MAX - 5;
        w.dpram().write32(EVT_RING.head, start);
        w.dpram().write32(EVT_RING.tail, start);
        let mut p = EvtProducer::attach(w.dpram(), EVT_RING);
        let mut c = EvtConsumer::attach(w.dpram(), EVT_RING);
        for round in 0..3u32 {
            for i in 0..EVT_RING.len {
                p.push(&ev(round * 1000 + i)).unwrap();
            }
            assert_eq!(p.push(&ev(0)), Err(RingError::Full));
            for i in 0..EVT_RING.len {
                assert_eq!(c.pop::<Event>().unwrap(), Some(ev(round * 1000 + i)));
            }
        }
        assert_eq!(p.head(), start.wrapping_add(3 * EVT_RING.len));
        assert_eq!(c.pop::<Event>(), Ok(None));
    }

    #[test]
    fn corrupt_peer_index_is_reported_not_followed() {
        let w = HeapWindow::new();
        let mut c = EvtConsumer::attach(w.dpram(), EVT_RING);
        w.dpram().write32(EVT_RING.head, EVT_RING.len + 1);
        assert_eq!(
            c.pop::<Event>(),
            Err(RingError::Corrupt {
                head: EVT_RING.len + 1,
                tail: 0
            })
        );
        let mut p = CmdProducer::attach(w.dpram(), CMD_RING);
        w.dpram().write32(CMD_RING.tail, 5); // tail ahead of head
        assert_eq!(p.free(), Err(RingError::Corrupt { head: 0, tail: 5 }));
        // Once the producer has seen the bad tail it refuses to write anything.
        assert!(matches!(
            p.push(&Command::new(Opcode::Nop, 0)),
            Err(RingError::Corrupt { .. })
        ));
    }

    #[test]
    fn entries_stay_in_their_slots() {
        // The last slot of the event ring must end before the next block.
        let end = slot_offset(&EVT_RING, EVT_RING.len - 1) + EVT_RING.entry_bytes;
        assert_eq!(end, crate::layout::CARD_CONFIG.offset());
        let end = slot_offset(&CMD_RING, CMD_RING.len - 1) + CMD_RING.entry_bytes;
        assert_eq!(end, crate::layout::EVT_RING);
    }
}
