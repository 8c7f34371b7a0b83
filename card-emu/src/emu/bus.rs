//! Layout 1.12: the sync bus between emulated cards, what a sync cable is between boards.
//!
//! The master card publishes, after each of its ticks, its tick count and the commits it took
//! (`MC_OP_SYNC_COMMIT`) in a page of shared memory (a memfd: a seqlock over a few words and
//! a ring of the last [`RING`] commits), then wakes each follower's eventfd. A follower steps
//! once for each master tick it has not run (never ahead of the master, never skipping one: a
//! follower the OS held back runs the missed ticks back to back), taking the commits the page
//! shows before each step. In one process the page and the eventfds are shared directly
//! ([`Bus::join`]); between processes a follower gets them from the master's `card-emu` over
//! the abstract socket `@motioncard-bus/NAME` ([`serve`], [`connect`]), under the same
//! credential policy as hosts, and keeps that connection: its hang-up is the master's death.
//!
//! Each follower acknowledges the ticks it has run in a slot of the page of its own, and the
//! master runs its next tick only once every follower has acknowledged its last
//! ([`Bus::await_followers`]): the cards tick in lock step, as one servo clock drives boards
//! wired to a sync line, so at any instant a follower's tick count is the master's or one
//! less. A follower the OS holds back longer than [`FOLLOWER_WAIT`] is not waited for again
//! until it has caught up (the master's clock does not stall behind a stopped process).
//!
//! A follower loses the master when the page says the master ended, the connection hangs up,
//! or no tick comes within [`loss_timeout`]; then the firmware halts everything
//! (`Firmware::lose_bus`) and the card goes on on its own clock.

use super::server::{PeerCred, PeerPolicy};
use crate::firmware::timed::Commit;
use firmware_proto::emu_link::{STATUS_DENIED, STATUS_FAILED, STATUS_OK};
use memmap2::{MmapOptions, MmapRaw};
use nix::sys::eventfd::{EfdFlags, EventFd};
use nix::sys::memfd::{memfd_create, MFdFlags};
use nix::sys::socket::{recvmsg, sendmsg, ControlMessage, ControlMessageOwned, MsgFlags};
use std::fs::File;
use std::io::{IoSlice, IoSliceMut, Read, Write};
use std::os::fd::{AsFd, AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::linux::net::SocketAddrExt;
use std::os::unix::net::{SocketAddr, UnixListener, UnixStream};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

/// Commits the page shows at once (far more than can be taken between two ticks).
pub const RING: usize = 32;
const SEQ: usize = 0;
const TICK: usize = 1;
const TOTAL: usize = 2;
const ALIVE: usize = 3;
const COMMITS: usize = 4;
/// The followers' acknowledgements: slot k holds the last tick follower k has run.
const ACKS: usize = 128;
/// An acknowledgement slot whose follower has run no tick yet.
const NOT_RUN: u64 = u64::MAX;
/// Followers one bus takes.
pub const MAX_FOLLOWERS: usize = 256;
const WORDS: usize = ACKS + MAX_FOLLOWERS;
const PAGE: usize = 4096;
const _: () = assert!(COMMITS + 2 * RING <= ACKS && WORDS * 8 <= PAGE);

/// The longest the master waits for a follower to run its last tick before it goes on
/// without it (and stops waiting for it until it has caught up): an OS's scheduling stall of
/// the follower, far longer than its tick takes.
pub const FOLLOWER_WAIT: Duration = Duration::from_millis(20);

/// The greeting of a follower (8 bytes), and the master's answer's first 6 of 16
/// (then the status and a word, little-endian u32s, and with `STATUS_OK` the page and the
/// eventfd as `SCM_RIGHTS`).
pub const BUS_HELLO: [u8; 8] = *b"MCBUS\x01\0\0";

/// The abstract socket a master `card-emu` serves its bus on.
pub fn socket_name(name: &str) -> String {
    format!("motioncard-bus/{name}")
}

/// How long a follower waits for the master's next tick before it calls the master lost:
/// `MC_BUS_LOSS_TICKS` periods, and at least 500 ms, an OS's scheduling stall of the master's
/// thread on a loaded machine (the master's own clock restarts its deadline grid after one,
/// see `Runner`; stalls of over 100 ms were seen with the machine's load at 13). Waiting costs
/// nothing: a follower runs no tick, so its emulated axes do not move, until the master ticks
/// or is called lost. A master that dies is seen at once (its connection hangs up, or its bus
/// ends).
pub fn loss_timeout(servo_rate_hz: u32) -> Duration {
    let ticks = firmware_proto::raw::MC_BUS_LOSS_TICKS as f64;
    Duration::from_secs_f64(ticks / servo_rate_hz.max(1) as f64).max(Duration::from_millis(500))
}

/// The shared page.
struct Page {
    map: MmapRaw,
    _file: File,
}

impl Page {
    fn create() -> std::io::Result<(Self, File)> {
        let fd = memfd_create("motioncard-bus", MFdFlags::MFD_CLOEXEC)?;
        let file = File::from(fd);
        file.set_len(PAGE as u64)?;
        let dup = file.try_clone()?;
        Ok((Self::map(file)?, dup))
    }

    fn map(file: File) -> std::io::Result<Self> {
        if file.metadata()?.len() < PAGE as u64 {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "the sync bus page is short",
            ));
        }
        let map = MmapOptions::new().len(PAGE).map_raw(&file)?;
        Ok(Self { map, _file: file })
    }

    fn word(&self, i: usize) -> &AtomicU64 {
        assert!(i < WORDS);
        // SAFETY: the mapping is PAGE bytes, page-aligned, alive as long as `self`; every
        // access to it, in every process, is through atomics.
        unsafe { &*(self.map.as_ptr() as *const AtomicU64).add(i) }
    }

    /// A consistent view (the seqlock retried while the master writes).
    fn read(&self) -> Snapshot {
        loop {
            let s0 = self.word(SEQ).load(Ordering::Acquire);
            if s0 & 1 == 1 {
                std::hint::spin_loop();
                continue;
            }
            let mut snap = Snapshot {
                tick: self.word(TICK).load(Ordering::Relaxed),
                total: self.word(TOTAL).load(Ordering::Relaxed),
                alive: self.word(ALIVE).load(Ordering::Relaxed) == 1,
                ring: [Commit::default(); RING],
            };
            for (k, c) in snap.ring.iter_mut().enumerate() {
                c.key = self.word(COMMITS + 2 * k).load(Ordering::Relaxed) as u32;
                c.tick = self.word(COMMITS + 2 * k + 1).load(Ordering::Relaxed);
            }
            std::sync::atomic::fence(Ordering::Acquire);
            if self.word(SEQ).load(Ordering::Relaxed) == s0 {
                return snap;
            }
        }
    }

    fn write(&self, tick: u64, commits: &[Commit], alive: bool) {
        let s = self.word(SEQ).load(Ordering::Relaxed);
        self.word(SEQ).store(s + 1, Ordering::Relaxed);
        std::sync::atomic::fence(Ordering::Release);
        let mut total = self.word(TOTAL).load(Ordering::Relaxed);
        for c in commits {
            let k = total as usize % RING;
            self.word(COMMITS + 2 * k)
                .store(c.key as u64, Ordering::Relaxed);
            self.word(COMMITS + 2 * k + 1)
                .store(c.tick, Ordering::Relaxed);
            total += 1;
        }
        self.word(TOTAL).store(total, Ordering::Relaxed);
        self.word(TICK).store(tick, Ordering::Relaxed);
        self.word(ALIVE).store(alive as u64, Ordering::Relaxed);
        self.word(SEQ).store(s + 2, Ordering::Release);
    }
}

/// What the page showed.
#[derive(Debug, Clone, Copy)]
pub struct Snapshot {
    /// The master's last tick.
    pub tick: u64,
    /// Commits published since the bus began.
    pub total: u64,
    /// Does the master run? (`false`: it ended.)
    pub alive: bool,
    ring: [Commit; RING],
}

impl Snapshot {
    /// The commits after the first `seen` (at most the last [`RING`]).
    pub fn commits_after(&self, seen: u64) -> impl Iterator<Item = Commit> + '_ {
        let from = seen.max(self.total.saturating_sub(RING as u64));
        (from..self.total).map(|i| self.ring[i as usize % RING])
    }
}

/// A follower as the master sees it.
struct Follower {
    id: u64,
    /// Its acknowledgement slot in the page.
    slot: usize,
    wake: EventFd,
    /// It was not waited for (it fell [`FOLLOWER_WAIT`] behind) and has not caught up yet.
    late: bool,
}

/// The master's end of the bus: the page and the followers' wake-up lines.
pub struct Bus {
    page: Page,
    file: File,
    name: String,
    followers: Mutex<Vec<Follower>>,
    next: AtomicU64,
}

impl Bus {
    /// A bus driven by the card `name`.
    pub fn new(name: &str) -> std::io::Result<Self> {
        let (page, file) = Page::create()?;
        page.write(0, &[], true);
        Ok(Self {
            page,
            file,
            name: name.to_string(),
            followers: Mutex::new(Vec::new()),
            next: AtomicU64::new(1),
        })
    }

    /// The master's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// A new follower's link (its page and its wake-up line), and the id [`Bus::leave`] takes.
    pub fn join(&self) -> std::io::Result<(BusLink, u64)> {
        let (file, wake, slot, id) = self.join_remote()?;
        let page = Page::map(file)?;
        Ok((BusLink::new(page, wake, slot, None, &self.name), id))
    }

    /// A new follower's descriptors (the page, a new eventfd), its acknowledgement slot and
    /// its id.
    fn join_remote(&self) -> std::io::Result<(File, OwnedFd, usize, u64)> {
        let efd = EventFd::from_value_and_flags(0, EfdFlags::EFD_CLOEXEC | EfdFlags::EFD_NONBLOCK)?;
        let dup = efd.as_fd().try_clone_to_owned()?;
        let file = self.file.try_clone()?;
        let mut followers = self.lock();
        let slot = (0..MAX_FOLLOWERS)
            .find(|k| followers.iter().all(|f| f.slot != *k))
            .ok_or_else(|| {
                std::io::Error::other(format!(
                    "the sync bus of '{}' has {MAX_FOLLOWERS} followers",
                    self.name
                ))
            })?;
        // Not waited for until it has run a tick: joining does not hold the master up while
        // the follower's clock starts.
        self.page
            .word(ACKS + slot)
            .store(NOT_RUN, Ordering::Release);
        let id = self.next.fetch_add(1, Ordering::Relaxed);
        followers.push(Follower {
            id,
            slot,
            wake: efd,
            late: true,
        });
        Ok((file, dup, slot, id))
    }

    /// The follower `id` left.
    pub fn leave(&self, id: u64) {
        self.lock().retain(|f| f.id != id);
    }

    /// Followers on the bus now.
    pub fn followers(&self) -> u32 {
        self.lock().len() as u32
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Follower>> {
        self.followers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }

    /// After the master's tick `tick`: publish it with `commits`, and wake every follower.
    pub fn publish(&self, tick: u64, commits: &[Commit]) {
        self.page.write(tick, commits, true);
        self.wake();
    }

    fn wake(&self) {
        for f in self.lock().iter() {
            let _ = f.wake.write(1);
        }
    }

    /// Before the master's tick after `tick`: wait until every follower has run `tick`, up to
    /// [`FOLLOWER_WAIT`] (or until `stop`). A follower that is not there by then is late: it is
    /// not waited for again until it has caught up to within a tick. Returns the followers
    /// that made the master go on without them (0 when the bus ticks in lock step).
    pub fn await_followers(&self, tick: u64, stop: &std::sync::atomic::AtomicBool) -> usize {
        let mut deadline = None;
        loop {
            let mut followers = self.lock();
            let mut waiting = false;
            for f in followers.iter_mut() {
                let ack = self.page.word(ACKS + f.slot).load(Ordering::Acquire);
                if f.late {
                    f.late = ack == NOT_RUN || ack + 1 < tick;
                }
                waiting |= !f.late && ack < tick;
            }
            if !waiting || stop.load(Ordering::Relaxed) {
                return 0;
            }
            let now = std::time::Instant::now();
            if now >= *deadline.get_or_insert(now + FOLLOWER_WAIT) {
                let mut left = 0;
                for f in followers.iter_mut() {
                    let ack = self.page.word(ACKS + f.slot).load(Ordering::Acquire);
                    if !f.late && ack < tick {
                        f.late = true;
                        left += 1;
                    }
                }
                return left;
            }
            drop(followers);
            // The followers need the CPU this thread would spin on.
            std::thread::yield_now();
        }
    }
}

impl Drop for Bus {
    /// The master ends: the followers see it at once.
    fn drop(&mut self) {
        let snap = self.page.read();
        self.page.write(snap.tick, &[], false);
        self.wake();
    }
}

/// What ended a follower's wait.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wake {
    /// The master woke it (one tick or several).
    Woken,
    /// The time passed.
    Quiet,
    /// The master's connection hung up: the master is gone.
    HungUp,
}

/// A follower's end of the bus.
pub struct BusLink {
    page: Page,
    wake: OwnedFd,
    /// Its acknowledgement slot in the page.
    slot: usize,
    /// The connection to a master in another process: its hang-up is the master's end.
    conn: Option<UnixStream>,
    master: String,
    /// Commits taken so far.
    seen: u64,
}

impl BusLink {
    fn new(page: Page, wake: OwnedFd, slot: usize, conn: Option<UnixStream>, master: &str) -> Self {
        let seen = page.read().total;
        Self {
            page,
            wake,
            slot,
            conn,
            master: master.to_string(),
            seen,
        }
    }

    /// The master's name.
    pub fn master(&self) -> &str {
        &self.master
    }

    /// The page now.
    pub fn read(&self) -> Snapshot {
        self.page.read()
    }

    /// This follower has run every tick up to `tick`: the master may run its next.
    pub fn ack(&self, tick: u64) {
        self.page
            .word(ACKS + self.slot)
            .store(tick, Ordering::Release);
    }

    /// The commits the page shows that this follower has not taken; marks them taken.
    pub fn take_commits(&mut self, snap: &Snapshot) -> Vec<Commit> {
        let v: Vec<Commit> = snap.commits_after(self.seen).collect();
        self.seen = snap.total;
        v
    }

    /// Wait up to `timeout` for the master's next tick.
    pub fn wait(&self, timeout: Duration) -> Wake {
        use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
        let ms = timeout.as_millis().min(i32::MAX as u128) as i32;
        let mut fds = vec![PollFd::new(self.wake.as_fd(), PollFlags::POLLIN)];
        if let Some(c) = &self.conn {
            fds.push(PollFd::new(c.as_fd(), PollFlags::POLLIN));
        }
        let n = poll(
            &mut fds,
            PollTimeout::try_from(ms).unwrap_or(PollTimeout::MAX),
        );
        let hung_up = fds.get(1).and_then(|f| f.revents()).is_some_and(|r| {
            r.intersects(PollFlags::POLLHUP | PollFlags::POLLERR | PollFlags::POLLIN)
        });
        if hung_up {
            // Only the end of the stream (or an error) comes on it: the master said nothing.
            return Wake::HungUp;
        }
        let mut b = [0u8; 8];
        let _ = nix::unistd::read(&self.wake, &mut b);
        if matches!(n, Ok(k) if k > 0) {
            Wake::Woken
        } else {
            Wake::Quiet
        }
    }
}

/// Serve the bus of `bus` to followers in other processes on `@motioncard-bus/NAME`, admitting
/// the peers `policy` admits. The accept thread runs as long as the process.
pub fn serve(bus: Arc<Bus>, policy: PeerPolicy) -> std::io::Result<()> {
    let addr = SocketAddr::from_abstract_name(socket_name(bus.name()).as_bytes())?;
    let listener = UnixListener::bind_addr(&addr)?;
    std::thread::Builder::new()
        .name("card-emu-bus".into())
        .spawn(move || {
            for stream in listener.incoming() {
                let Ok(stream) = stream else { continue };
                let Ok(peer) = PeerCred::of(&stream) else {
                    continue;
                };
                if !policy.admits(&peer) {
                    let _ = (&stream).write_all(&answer(STATUS_DENIED, peer.uid));
                    continue;
                }
                let bus = bus.clone();
                let _ = std::thread::Builder::new()
                    .name("card-emu-follower".into())
                    .spawn(move || follower(bus, stream));
            }
        })?;
    Ok(())
}

fn answer(status: u32, word: u32) -> [u8; 16] {
    let mut b = [0u8; 16];
    b[..8].copy_from_slice(&BUS_HELLO);
    b[8..12].copy_from_slice(&status.to_le_bytes());
    b[12..16].copy_from_slice(&word.to_le_bytes());
    b
}

/// One follower's connection: its greeting, its descriptors, then its lifetime.
fn follower(bus: Arc<Bus>, stream: UnixStream) {
    let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
    let mut hello = [0u8; 8];
    if (&stream).read_exact(&mut hello).is_err() || hello != BUS_HELLO {
        return;
    }
    let (file, efd, slot, id) = match bus.join_remote() {
        Ok(x) => x,
        Err(e) => {
            let errno = e.raw_os_error().unwrap_or(nix::libc::EIO);
            let _ = (&stream).write_all(&answer(STATUS_FAILED, errno as u32));
            return;
        }
    };
    let raw = [file.as_raw_fd(), efd.as_raw_fd()];
    let sent = sendmsg::<()>(
        stream.as_raw_fd(),
        &[IoSlice::new(&answer(STATUS_OK, slot as u32))],
        &[ControlMessage::ScmRights(&raw)],
        MsgFlags::MSG_NOSIGNAL,
        None,
    );
    drop((file, efd));
    if sent.is_ok() && stream.set_read_timeout(None).is_ok() {
        let mut b = [0u8; 64];
        while matches!((&stream).read(&mut b), Ok(n) if n > 0) {}
    }
    bus.leave(id);
}

/// Join the bus of the `card-emu` serving `master`.
pub fn connect(master: &str) -> std::io::Result<BusLink> {
    let addr = SocketAddr::from_abstract_name(socket_name(master).as_bytes())?;
    let stream = UnixStream::connect_addr(&addr).map_err(|e| {
        std::io::Error::new(
            e.kind(),
            format!("no card-emu serves a sync bus named '{master}' ({e})"),
        )
    })?;
    stream.set_read_timeout(Some(Duration::from_secs(5)))?;
    (&stream).write_all(&BUS_HELLO)?;
    let mut buf = [0u8; 16];
    let mut cmsg = nix::cmsg_space!([RawFd; 2]);
    let mut iov = [IoSliceMut::new(&mut buf)];
    let msg = recvmsg::<()>(
        stream.as_raw_fd(),
        &mut iov,
        Some(&mut cmsg),
        MsgFlags::MSG_CMSG_CLOEXEC,
    )?;
    let mut fds: Vec<OwnedFd> = Vec::new();
    for c in msg.cmsgs()? {
        if let ControlMessageOwned::ScmRights(raw) = c {
            // SAFETY: the kernel just installed these descriptors for us; nobody else owns them.
            fds.extend(
                raw.into_iter()
                    .map(|fd| unsafe { OwnedFd::from_raw_fd(fd) }),
            );
        }
    }
    let bad = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidData, m);
    if msg.bytes != 16 || buf[..8] != BUS_HELLO {
        return Err(bad(format!("'{master}' answered no sync bus greeting")));
    }
    let status = u32::from_le_bytes([buf[8], buf[9], buf[10], buf[11]]);
    let word = u32::from_le_bytes([buf[12], buf[13], buf[14], buf[15]]);
    match status {
        STATUS_OK => {}
        STATUS_DENIED => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::PermissionDenied,
                format!("card-emu '{master}' refused uid {word}"),
            ))
        }
        _ => {
            return Err(bad(format!(
                "card-emu '{master}' failed: status {status}, {word}"
            )))
        }
    }
    let [page, wake]: [OwnedFd; 2] = fds
        .try_into()
        .map_err(|v: Vec<OwnedFd>| bad(format!("{} descriptors instead of 2", v.len())))?;
    stream.set_read_timeout(None)?;
    let slot = word as usize;
    if slot >= MAX_FOLLOWERS {
        return Err(bad(format!("'{master}' gave the follower slot {slot}")));
    }
    Ok(BusLink::new(
        Page::map(File::from(page))?,
        wake,
        slot,
        Some(stream),
        master,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicBool;

    /// The master waits for each follower to run its last tick: not for one that has, for one
    /// that does meanwhile, and up to `FOLLOWER_WAIT` for one that does not (then it goes on
    /// without it and does not wait for it again until it has caught up).
    #[test]
    fn the_master_runs_its_next_tick_once_every_follower_has_run_its_last() {
        let stop = AtomicBool::new(false);
        let bus = Bus::new("acks-unit").unwrap();
        let (a, _) = bus.join().unwrap();
        let (b, id_b) = bus.join().unwrap();
        assert_ne!(a.slot, b.slot);
        // Neither has run a tick yet: the master does not wait for them.
        assert_eq!(bus.await_followers(0, &stop), 0);
        // Once they have run the master's tick, it waits for them.
        a.ack(0);
        b.ack(0);
        bus.publish(1, &[]);
        a.ack(1);
        // b acks tick 1 from another thread while the master waits.
        let t = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(2));
            b.ack(1);
            b
        });
        assert_eq!(bus.await_followers(1, &stop), 0);
        let b = t.join().unwrap();
        // b stalls: the master goes on without it after FOLLOWER_WAIT, once.
        bus.publish(2, &[]);
        a.ack(2);
        let t0 = std::time::Instant::now();
        assert_eq!(bus.await_followers(2, &stop), 1);
        assert!(t0.elapsed() >= FOLLOWER_WAIT);
        bus.publish(3, &[]);
        a.ack(3);
        assert_eq!(
            bus.await_followers(3, &stop),
            0,
            "a late follower is not waited for"
        );
        // b catches up to within a tick: it is waited for again.
        b.ack(3);
        bus.publish(4, &[]);
        a.ack(4);
        assert_eq!(bus.await_followers(4, &stop), 1);
        // A follower that left is not waited for; its slot is taken by the next.
        bus.leave(id_b);
        assert_eq!(bus.await_followers(4, &stop), 0);
        let (c, _) = bus.join().unwrap();
        assert_eq!(c.slot, b.slot);
        bus.publish(5, &[]);
        a.ack(5);
        assert_eq!(bus.await_followers(5, &stop), 0, "c has run no tick yet");
        c.ack(5);
        bus.publish(6, &[]);
        a.ack(6);
        assert_eq!(bus.await_followers(6, &stop), 1, "c is waited for now");
    }
}
