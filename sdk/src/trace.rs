//! API trace and replay: what a customer attaches to a bug report.
//!
//! With the environment variable [`TRACE_ENV`] set to a file name (any program, C programs
//! included), or opened with [`crate::Card::open_traced`], a card records to that file every command
//! the SDK sends, every configuration block it writes into the window, and every event the
//! card posts (acks and nacks included), each with the host time since the open. One record a
//! line, flushed as written, so the trace survives a crash of the program:
//!
//! ```text
//! # motioncard trace 1
//! I <layout major> <layout minor> <axes> <servo rate Hz> <uri>
//! C <ns> <seq> <opcode> <axis> <flags> <arg 0> … <arg 11>      a command sent
//! W <ns> <byte offset> <word hex> …                           host writes into a block
//! E <ns> <kind> <axis> <seq> <code> <tick> <value>            an event taken from the card
//! ```
//!
//! Numbers are exact: `f64`s in Rust's shortest round-trip form. `replay` (the `replay`
//! module, with the `emulator` feature) runs a trace
//! against a stepped emulated card with the trace's axes and servo rate: each block write
//! and command at the card tick the recorded card served it, and every recorded event compared
//! with the replayed one (kind, axis, command, code, tick, value). The first difference is
//! reported with its line. The session's own attach (the open) is not replayed: the
//! replaying host has its own session, and the later session commands (a raw detach or attach,
//! the close's detach) are replayed with the traced session's id replaced by its own. Before
//! anything is replayed, every recorded tick is checked against the trace's own span: events
//! never go back, and none is further after the first event than the host time recorded by
//! then allows a card to tick ([`MAX_TICKS_PER_SECOND`](crate::MAX_TICKS_PER_SECOND)), so a
//! tampered tick (10¹⁵) is refused, not stepped to for years; towards a recorded event the card
//! is stepped until its own next event.

use crate::error::{Error, Result};
use firmware_proto::{Command, Event, Mem};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

/// The environment variable that turns the trace on for every card a program opens: a file
/// name (a second card opened by the same program appends `.1`, `.2`, …).
pub const TRACE_ENV: &str = "MOTIONCARD_TRACE";

pub(crate) const MAGIC: &str = "# motioncard trace 1";

/// A trace being written.
pub(crate) struct Tracer {
    out: Mutex<std::io::BufWriter<std::fs::File>>,
    t0: Instant,
}

/// Cards opened with the environment's trace so far (for the file name of the next).
static OPENED: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);

impl Tracer {
    /// The trace [`TRACE_ENV`] asks for, if any.
    pub(crate) fn from_env() -> Result<Option<Tracer>> {
        let Some(path) = std::env::var_os(TRACE_ENV).filter(|p| !p.is_empty()) else {
            return Ok(None);
        };
        let n = OPENED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let mut path = std::path::PathBuf::from(path);
        if n > 0 {
            path.as_mut_os_string().push(format!(".{n}"));
        }
        Self::create(&path).map(Some)
    }

    pub(crate) fn create(path: &Path) -> Result<Tracer> {
        let file = std::fs::File::create(path).map_err(|source| Error::Io {
            context: format!("the API trace {}", path.display()),
            source,
        })?;
        Ok(Tracer {
            out: Mutex::new(std::io::BufWriter::new(file)),
            t0: Instant::now(),
        })
    }

    /// One record: the tag, the time, the rest. A trace that cannot be written any more (a
    /// full disk) is dropped silently: the program it watches goes on.
    fn line(&self, tag: char, rest: std::fmt::Arguments) {
        let ns = self.t0.elapsed().as_nanos();
        let mut out = crate::lock::lock(&self.out);
        let _ = writeln!(out, "{tag} {ns} {rest}");
        let _ = out.flush();
    }

    pub(crate) fn header(&self, uri: &str, layout: (u16, u16), axes: usize, rate: u32) {
        let mut out = crate::lock::lock(&self.out);
        let _ = writeln!(out, "{MAGIC}");
        let _ = writeln!(out, "I {} {} {axes} {rate} {uri}", layout.0, layout.1);
        let _ = out.flush();
    }

    pub(crate) fn command(&self, c: &Command) {
        let mut args = String::new();
        for a in c.args {
            let _ = write!(args, " {a:?}");
        }
        self.line(
            'C',
            format_args!("{} {} {} {}{args}", c.seq, c.opcode, c.axis, c.flags),
        );
    }

    /// The words of the window over `range` (byte offsets), as the host just wrote them.
    pub(crate) fn block(&self, w: &impl Mem, range: std::ops::Range<usize>) {
        let (start, end) = (range.start & !7, (range.end + 7) & !7);
        let mut words = String::new();
        for off in (start..end).step_by(8) {
            let _ = write!(words, " {:x}", w.read64(off));
        }
        self.line('W', format_args!("{start}{words}"));
    }

    pub(crate) fn event(&self, e: &Event) {
        self.line(
            'E',
            format_args!(
                "{} {} {} {} {} {:?}",
                e.kind, e.axis, e.seq, e.code, e.tick, e.value
            ),
        );
    }
}
