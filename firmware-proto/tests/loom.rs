//! Loom models of the two shared-memory protocols: the SPSC rings and the status-block seqlock.
//!
//! Run with `RUSTFLAGS="--cfg loom" CARGO_TARGET_DIR=target/loom cargo test -p firmware-proto
//! --release --test loom` (`.ci/run` does; `-- --nocapture` prints how many executions each
//! model explored). Loom runs every interleaving of the threads (up to a preemption bound where
//! one is given) and, for every load, every store the C++ memory model lets it return, so a
//! missing Release or Acquire shows up as a stale word in some execution, not as a flaky test.
//!
//! The window is far too big for loom, so the models run the real `Producer`/`Consumer` and
//! `seqlock::write_words`/`read_words` over a [`LoomMem`]: a sparse map from byte offset to one
//! loom atomic, created inside the model closure, holding only the words of a tiny ring or of
//! one status block at small offsets. Any other offset, or a word accessed with the wrong
//! width, panics: the layout given to the code under test is wrong.
//!
//! Each `*_is_caught` test runs the same model with one ordering broken (in a copy of the code
//! in this file) and expects loom to find the failure.
#![cfg(loom)]

use std::collections::HashMap;
use std::sync::atomic::Ordering;
use std::sync::Arc;

use firmware_proto::layout::STATUS_PAYLOAD;
use firmware_proto::ring::{Consumer, Producer, RingLayout};
use firmware_proto::seqlock::{self, SnapshotError};
use firmware_proto::{Event, Mem, RingError, EVT_WORDS, STATUS_WORDS};
use loom::sync::atomic::{AtomicU32, AtomicU64};
use loom::thread;

/// One word of the model's window.
enum Word {
    U32(AtomicU32),
    U64(AtomicU64),
    /// A 64-bit word every access of which is made SeqCst, whatever the code under test asks
    /// for (see the seqlock model for why).
    U64SeqCst(AtomicU64),
}

/// Shared memory made of loom atomics at chosen offsets.
#[derive(Default)]
struct LoomMem {
    words: HashMap<usize, Word>,
}

impl LoomMem {
    fn with(mut self, off: usize, word: Word) -> Self {
        let old = self.words.insert(off, word);
        assert!(old.is_none(), "offset {off} created twice");
        self
    }

    fn u32_at(self, off: usize, init: u32) -> Self {
        assert!(off.is_multiple_of(4));
        self.with(off, Word::U32(AtomicU32::new(init)))
    }

    fn u64_at(self, off: usize, init: u64) -> Self {
        assert!(off.is_multiple_of(8));
        self.with(off, Word::U64(AtomicU64::new(init)))
    }

    fn u64_seq_cst_at(self, off: usize, init: u64) -> Self {
        assert!(off.is_multiple_of(8));
        let a = AtomicU64::new(init);
        // Loom's initial value counts as a Release store, which a SeqCst load may still return
        // after a later SeqCst store; a SeqCst store of the same value retires it.
        a.store(init, Ordering::SeqCst);
        self.with(off, Word::U64SeqCst(a))
    }

    fn word(&self, off: usize) -> &Word {
        match self.words.get(&off) {
            Some(w) => w,
            None => panic!("offset {off} is not in the model's window"),
        }
    }
}

// `Mem` takes `std::sync::atomic::Ordering`; loom re-exports that very type, so the orderings
// the code under test passes reach loom unchanged.
impl Mem for LoomMem {
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        match self.word(off) {
            Word::U32(a) => a.load(order),
            _ => panic!("offset {off} accessed as 32-bit, created as 64-bit"),
        }
    }
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        match self.word(off) {
            Word::U32(a) => a.store(val, order),
            _ => panic!("offset {off} accessed as 32-bit, created as 64-bit"),
        }
    }
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        match self.word(off) {
            Word::U64(a) => a.load(order),
            Word::U64SeqCst(a) => a.load(Ordering::SeqCst),
            Word::U32(_) => panic!("offset {off} accessed as 64-bit, created as 32-bit"),
        }
    }
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        match self.word(off) {
            Word::U64(a) => a.store(val, order),
            Word::U64SeqCst(a) => a.store(val, Ordering::SeqCst),
            Word::U32(_) => panic!("offset {off} accessed as 64-bit, created as 32-bit"),
        }
    }
}

/// Check a model with loom's preemption bound set to `preemptions` (`None`: every
/// interleaving; `LOOM_MAX_PREEMPTIONS` overrides), and print how many executions it took.
fn check(name: &str, preemptions: Option<usize>, model: impl Fn() + Sync + Send + 'static) {
    let mut builder = loom::model::Builder::new();
    builder.preemption_bound = builder.preemption_bound.or(preemptions);
    let start = std::time::Instant::now();
    let runs = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let counter = runs.clone();
    builder.check(move || {
        counter.fetch_add(1, Ordering::Relaxed);
        model()
    });
    eprintln!(
        "{name}: {} executions, preemption bound {:?}, {:.1} s",
        runs.load(Ordering::Relaxed),
        builder.preemption_bound,
        start.elapsed().as_secs_f64()
    );
}

// ---------------------------------------------------------------------------------------------
// Rings
// ---------------------------------------------------------------------------------------------

/// A two-slot event ring: the indices on lines of their own, the slots after them.
const RING: RingLayout = RingLayout {
    head: 0,
    tail: 64,
    entries: 128,
    entry_bytes: EVT_WORDS * 8,
    len: 2,
};

/// Both indices start here, so they also wrap around `u32::MAX` during a model.
const START: u32 = u32::MAX - 1;

fn ring_mem() -> Arc<LoomMem> {
    let mut m = LoomMem::default()
        .u32_at(RING.head, START)
        .u32_at(RING.tail, START);
    for i in 0..RING.len as usize * EVT_WORDS {
        m = m.u64_at(RING.entries + 8 * i, 0);
    }
    Arc::new(m)
}

/// Entry `i`: every word differs from every other word of every entry, and from the zeroed
/// slots.
fn entry(i: u32) -> Event {
    Event {
        seq: 0x100 + i,
        kind: 0x200 + i as u16,
        axis: 0x300 + i as u16,
        code: 0x400 + i as i32,
        tick: 0x500 + i as u64,
        value: (0x600 + i) as f64,
    }
}

/// The real producer: push entries `0..n`, yielding and retrying while the ring is full.
fn produce(mem: Arc<LoomMem>, n: u32) {
    let mut p = Producer::<_, EVT_WORDS>::attach(mem, RING);
    for i in 0..n {
        loop {
            match p.push(&entry(i)) {
                Ok(()) => break,
                Err(RingError::Full) => thread::yield_now(),
                Err(e) => panic!("producer: {e}"),
            }
        }
    }
    assert_eq!(p.head(), START.wrapping_add(n));
}

/// The real consumer: pop until `n` entries arrived; each must be the next one, whole.
fn consume(mem: Arc<LoomMem>, n: u32) {
    let mut c = Consumer::<_, EVT_WORDS>::attach(mem, RING);
    let mut next = 0;
    while next < n {
        match c.pop::<Event>() {
            Ok(Some(e)) => {
                assert_eq!(e, entry(next), "entry {next} arrived wrong");
                next += 1;
            }
            Ok(None) => thread::yield_now(),
            Err(e) => panic!("consumer: {e}"),
        }
    }
    assert_eq!(c.pop::<Event>(), Ok(None), "more entries than were pushed");
}

/// Producer and consumer on two threads: every entry arrives exactly once, in order, with all
/// its words; the producer finds the ring full and retries; neither side sees `Corrupt`.
fn ring_model(n: u32, preemptions: Option<usize>) {
    check(&format!("ring, {n} entries"), preemptions, move || {
        let mem = ring_mem();
        let producer = {
            let mem = mem.clone();
            thread::spawn(move || produce(mem, n))
        };
        consume(mem.clone(), n);
        producer.join().unwrap();
        let end = START.wrapping_add(n);
        assert_eq!(mem.load32(RING.head, Ordering::Relaxed), end);
        assert_eq!(mem.load32(RING.tail, Ordering::Relaxed), end);
    });
}

/// Three entries through two slots (the first slot is reused): every interleaving.
#[test]
fn ring_delivers_every_entry_once_in_order() {
    ring_model(3, None);
}

/// Four entries through two slots (both are reused): up to five preemptions (every
/// interleaving is 1.3 million executions, about a minute).
#[test]
fn ring_reuses_every_slot() {
    ring_model(4, Some(5));
}

/// Negative check: a producer that publishes `head` with Relaxed (otherwise the real one) lets
/// the consumer read a slot before the entry's words are visible.
#[test]
#[should_panic(expected = "arrived wrong")]
fn ring_with_relaxed_head_publish_is_caught() {
    check("ring, head published Relaxed", None, || {
        let mem = ring_mem();
        let producer = {
            let mem = mem.clone();
            thread::spawn(move || {
                let mut head = START;
                for i in 0..3 {
                    while head.wrapping_sub(mem.load32(RING.tail, Ordering::Acquire)) >= RING.len {
                        thread::yield_now();
                    }
                    let base = RING.entries + (head & (RING.len - 1)) as usize * RING.entry_bytes;
                    for (k, w) in entry(i).to_words().iter().enumerate() {
                        mem.store64(base + 8 * k, *w, Ordering::Relaxed);
                    }
                    head = head.wrapping_add(1);
                    mem.store32(RING.head, head, Ordering::Relaxed); // the bug
                }
            })
        };
        consume(mem, 3);
        producer.join().unwrap();
    });
}

// ---------------------------------------------------------------------------------------------
// Seqlock
// ---------------------------------------------------------------------------------------------
//
// A reader that took a stale `seq` may load each payload word from any of the writes it has
// not synchronised past, independently, so loom enumerates up to (writes + 1)^24 copies per
// interleaving: no preemption bound helps (it bounds interleavings, not values), and the
// all-Relaxed model of the real 24-word block was still running after 600,000 executions with a
// bound of one. So the model keeps the protocol's Relaxed payload accesses on the first two and the last
// two words, the ones written and read nearest to the `seq` accesses, and makes the 20 words
// between SeqCst. That only removes behaviours (whatever loom finds is a real execution) but can
// also add synchronisation, so a broken ordering is found only in executions where a Relaxed
// word tears; the negative checks below show it is found.
//
// `read_words` spins with `core::hint::spin_loop()`, which loom does not see (it is no yield);
// the model stays finite because its retries are bounded.

/// Where the block's `seq` lives in the model.
const SEQ: usize = 0;

/// Payload words the model accesses with the protocol's own (Relaxed) orderings.
const RELAXED_WORDS: [usize; 4] = [0, 1, STATUS_WORDS - 2, STATUS_WORDS - 1];

/// Payloads the writer publishes after the initial one; payload `n` has every word `n`.
const WRITES: u64 = 3;

/// Attempts the reader makes (`read_words`'s `retries`).
const RETRIES: u32 = 3;

/// Preemption bound of the seqlock models (3 took half a minute already with two writes).
const SEQLOCK_PREEMPTIONS: Option<usize> = Some(2);

fn payload(i: usize) -> usize {
    SEQ + STATUS_PAYLOAD + 8 * i
}

fn status_mem() -> Arc<LoomMem> {
    let mut m = LoomMem::default().u32_at(SEQ, 0);
    for i in 0..STATUS_WORDS {
        m = if RELAXED_WORDS.contains(&i) {
            m.u64_at(payload(i), 0)
        } else {
            m.u64_seq_cst_at(payload(i), 0)
        };
    }
    Arc::new(m)
}

/// A snapshot must be whole (every word equal) and one of the payloads written (or the
/// initial one).
fn check_snapshot(words: &[u64; STATUS_WORDS]) {
    assert!(
        words.iter().all(|w| *w == words[0]),
        "torn snapshot: {words:?}"
    );
    assert!(words[0] <= WRITES, "snapshot never written: {words:?}");
}

/// A writer thread publishing payloads `1..=WRITES`, and a reader on the model's thread.
fn seqlock_model(name: &str, writer: fn(&LoomMem, &[u64; STATUS_WORDS]), reader: fn(&LoomMem)) {
    check(name, SEQLOCK_PREEMPTIONS, move || {
        let mem = status_mem();
        let w = {
            let mem = mem.clone();
            thread::spawn(move || {
                for n in 1..=WRITES {
                    writer(&mem, &[n; STATUS_WORDS]);
                }
            })
        };
        reader(&mem);
        w.join().unwrap();
    });
}

fn real_writer(mem: &LoomMem, words: &[u64; STATUS_WORDS]) {
    seqlock::write_words(mem, SEQ, words);
}

fn real_reader(mem: &LoomMem) {
    match seqlock::read_words(mem, SEQ, RETRIES) {
        Ok(words) => check_snapshot(&words),
        Err(SnapshotError::Busy) => {}
        Err(e) => panic!("read_words: {e}"),
    }
}

/// The real writer and reader: every copy `read_words` returns is whole and was written.
#[test]
fn seqlock_snapshots_are_never_torn() {
    seqlock_model("seqlock", real_writer, real_reader);
}

/// Negative check: a reader that trusts its first even `seq` and does not re-check it after
/// copying.
#[test]
#[should_panic(expected = "torn snapshot")]
fn seqlock_reader_without_recheck_is_caught() {
    seqlock_model("seqlock, no re-check", real_writer, |mem| {
        for _ in 0..RETRIES {
            if mem.load32(SEQ, Ordering::Acquire) & 1 == 1 {
                thread::yield_now();
                continue;
            }
            let mut words = [0u64; STATUS_WORDS];
            for (i, w) in words.iter_mut().enumerate() {
                *w = mem.load64(payload(i), Ordering::Relaxed);
            }
            check_snapshot(&words); // the bug: no second load of `seq`
            return;
        }
    });
}

/// Negative check: a reader without the Acquire fence between its copy and the second load of
/// `seq`, which may then still see the old even value after copying new words.
#[test]
#[should_panic(expected = "torn snapshot")]
fn seqlock_reader_without_acquire_fence_is_caught() {
    seqlock_model("seqlock, no Acquire fence", real_writer, |mem| {
        for _ in 0..RETRIES {
            let s1 = mem.load32(SEQ, Ordering::Acquire);
            if s1 & 1 == 1 {
                thread::yield_now();
                continue;
            }
            let mut words = [0u64; STATUS_WORDS];
            for (i, w) in words.iter_mut().enumerate() {
                *w = mem.load64(payload(i), Ordering::Relaxed);
            }
            // the bug: no fence(Acquire) here
            if mem.load32(SEQ, Ordering::Relaxed) == s1 {
                check_snapshot(&words);
                return;
            }
            thread::yield_now();
        }
    });
}

/// Negative check: a writer without the Release fence after making `seq` odd, so its payload
/// stores may become visible to a reader whose second load still sees the old even `seq`.
#[test]
#[should_panic(expected = "torn snapshot")]
fn seqlock_writer_without_release_fence_is_caught() {
    seqlock_model(
        "seqlock, no Release fence",
        |mem, words| {
            let seq = mem.load32(SEQ, Ordering::Relaxed);
            mem.store32(SEQ, seq.wrapping_add(1), Ordering::Relaxed);
            // the bug: no fence(Release) here
            for (i, w) in words.iter().enumerate() {
                mem.store64(payload(i), *w, Ordering::Relaxed);
            }
            mem.store32(SEQ, seq.wrapping_add(2), Ordering::Release);
        },
        real_reader,
    );
}
