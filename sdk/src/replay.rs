//! Replaying an API trace ([`crate::trace`]) on a stepped emulated card.

use crate::card::Card;
use crate::error::{Error, Result};
use crate::trace::MAGIC;
use firmware_proto::{layout, Command, Event, EventKind, Mem, Opcode, CMD_ARGS};
use std::path::Path;

/// One record of a trace, with its line number (from 1).
#[derive(Debug, Clone, PartialEq)]
enum Record {
    Command(usize, Command),
    Block(usize, usize, Vec<u64>),
    Event(usize, Event),
}

/// The fastest a card ticks, in ticks per second of the host's time: a card on the clock
/// ticks at most at `MC_SERVO_RATE_MAX_HZ` (20 kHz), and a stepped emulated card takes
/// microseconds a tick (stepped through the SDK, 3.5 µs with one axis and 4.6 µs with four on
/// the machine of BENCHMARKS.md, whose bare firmware tick of 8 axes is 1.1–1.6 µs); 10⁸ a
/// second, 10 ns a tick, is over 100 times faster than the bare tick.
pub const MAX_TICKS_PER_SECOND: u64 = 100_000_000;
/// Ticks a trace may advance beyond what its host time allows, for the time between a
/// card's tick and the host's record of it.
const TICK_SLACK: u64 = 1_000_000;

/// Checks the recorded events' ticks against the trace's own span, so that a replay never
/// steps further than the recorded card can have gone: they never go back (a card posts
/// events in order), and no event is more ticks after the first event than the host time
/// the trace had recorded by then allows ([`MAX_TICKS_PER_SECOND`]; the first event came
/// after the trace began). A tick of 10¹⁵ in a trace of seconds would take years to step.
fn check_ticks(records: &[(u64, Record)]) -> std::result::Result<(), String> {
    let mut first: Option<(usize, u64)> = None;
    let mut prev = 0u64;
    for (ns, r) in records {
        let Record::Event(n, e) = r else {
            continue;
        };
        let Some((n0, t0)) = first else {
            first = Some((*n, e.tick));
            prev = e.tick;
            continue;
        };
        if e.tick < prev {
            return Err(format!(
                "line {n}: tick {} is before the tick of the event before it ({prev}): a card \
                 posts its events in order",
                e.tick
            ));
        }
        prev = e.tick;
        let allowed =
            (*ns as u128 * MAX_TICKS_PER_SECOND as u128 / 1_000_000_000) as u64 + TICK_SLACK;
        if e.tick - t0 > allowed {
            return Err(format!(
                "line {n}: tick {} is {} ticks after the first event's (line {n0}, tick {t0}), \
                 but the trace had recorded {:.3} s by then: no card ticks more than {} times a \
                 second",
                e.tick,
                e.tick - t0,
                *ns as f64 * 1e-9,
                MAX_TICKS_PER_SECOND
            ));
        }
    }
    Ok(())
}

/// What a trace was recorded on.
#[derive(Debug, Clone, PartialEq)]
pub struct TraceHeader {
    /// Its DPRAM layout (major, minor).
    pub layout: (u16, u16),
    /// Its axes.
    pub axes: usize,
    /// Its servo rate.
    pub servo_rate_hz: u32,
    /// The URI it was opened with.
    pub uri: String,
}

fn parse(text: &str) -> std::result::Result<(TraceHeader, Vec<(u64, Record)>), String> {
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, l)) if l.trim_end() == MAGIC => {}
        _ => return Err(format!("line 1: not a motioncard trace (`{MAGIC}`)")),
    }
    let mut header = None;
    let mut records = Vec::new();
    for (i, line) in lines {
        let n = i + 1;
        let bad = |what: &str| format!("line {n}: {what}: `{line}`");
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |k: usize| -> std::result::Result<u64, String> {
            f.get(k)
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| bad("a field is missing or not a number"))
        };
        let float = |k: usize| -> std::result::Result<f64, String> {
            f.get(k)
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| bad("a field is missing or not a number"))
        };
        match f.first().copied() {
            None => {}
            Some(t) if t.starts_with('#') => {}
            Some("I") => {
                header = Some(TraceHeader {
                    layout: (num(1)? as u16, num(2)? as u16),
                    axes: num(3)? as usize,
                    servo_rate_hz: num(4)? as u32,
                    uri: f.get(5).unwrap_or(&"").to_string(),
                })
            }
            Some("C") => {
                let ns = num(1)?;
                if f.len() != 6 + CMD_ARGS {
                    return Err(bad("a command has 6 fields and its arguments"));
                }
                let mut c = Command {
                    seq: num(2)? as u32,
                    opcode: num(3)? as u16,
                    axis: num(4)? as u16,
                    flags: num(5)? as u32,
                    deadline_ms: 0,
                    args: [0.0; CMD_ARGS],
                };
                for k in 0..CMD_ARGS {
                    c.args[k] = float(6 + k)?;
                }
                records.push((ns, Record::Command(n, c)));
            }
            Some("W") => {
                let ns = num(1)?;
                let words = f[3.min(f.len())..]
                    .iter()
                    .map(|s| u64::from_str_radix(s, 16))
                    .collect::<std::result::Result<Vec<_>, _>>()
                    .map_err(|_| bad("a word is not hexadecimal"))?;
                records.push((ns, Record::Block(n, num(2)? as usize, words)));
            }
            Some("E") => {
                if f.len() != 8 {
                    return Err(bad("an event has 8 fields"));
                }
                records.push((
                    num(1)?,
                    Record::Event(
                        n,
                        Event {
                            kind: num(2)? as u16,
                            axis: num(3)? as u16,
                            seq: num(4)? as u32,
                            code: f[5].parse().map_err(|_| bad("the code is not a number"))?,
                            tick: num(6)?,
                            value: float(7)?,
                        },
                    ),
                ));
            }
            Some(_) => return Err(bad("unknown record")),
        }
    }
    let header = header.ok_or("no `I` record: the card the trace was taken on is unknown")?;
    check_ticks(&records)?;
    Ok((header, records))
}

/// What [`replay`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayReport {
    /// The card the trace was recorded on.
    pub header: TraceHeader,
    /// Commands sent again.
    pub commands: usize,
    /// Recorded events compared with the card's.
    pub events: usize,
    /// The first difference: the trace's line and what differs. `None`: the card answered as
    /// recorded.
    pub difference: Option<(usize, String)>,
}

/// A session command.
fn session_op(opcode: u16) -> bool {
    opcode == Opcode::HostAttach as u16 || opcode == Opcode::HostDetach as u16
}

/// The traced host's own attach, its open (the first command of a trace): not replayed, the
/// replaying host has its own session. Its seq and the traced session's id.
fn open_attach(records: &[Record]) -> Option<(u32, u32)> {
    records
        .iter()
        .find_map(|r| match r {
            Record::Command(_, c) => Some(c),
            _ => None,
        })
        .filter(|c| c.opcode == Opcode::HostAttach as u16)
        .map(|c| (c.seq, c.flags))
}

fn show(e: &Event) -> String {
    let kind = EventKind::from_raw(e.kind).map_or(format!("kind {}", e.kind), |k| format!("{k:?}"));
    format!(
        "{kind} axis {} seq {} code {} tick {} value {:?}",
        e.axis, e.seq, e.code, e.tick, e.value
    )
}

/// Replay the trace in `path` against a stepped emulated card with its axes and servo rate
/// (the plant the default: a trace of another plant differs where the plant shows). An error
/// for a file that cannot be read or parsed, or a layout other than this library's.
pub fn replay(path: &Path) -> Result<ReplayReport> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        context: format!("the trace {}", path.display()),
        source,
    })?;
    let (header, records) =
        parse(&text).map_err(|e| Error::BadConfig(format!("{}: {e}", path.display())))?;
    if header.layout != (firmware_proto::LAYOUT_MAJOR, firmware_proto::LAYOUT_MINOR) {
        return Err(Error::VersionMismatch {
            card_major: header.layout.0,
            card_minor: header.layout.1,
            lib_major: firmware_proto::LAYOUT_MAJOR,
            lib_minor: firmware_proto::LAYOUT_MINOR,
        });
    }
    // Not traced itself, whatever the environment says.
    let card = Card::attach(
        "sim",
        crate::device::open_sim(&crate::SimOptions {
            clock: card_emu::Clock::Stepped,
            emu: card_emu::EmuOptions::new(header.axes, header.servo_rate_hz),
        })?,
        None,
    )?;
    let records: Vec<Record> = records.into_iter().map(|(_, r)| r).collect();
    let r = run_replay(&card, &records);
    let closed = card.close();
    let (commands, events, difference) = r?;
    closed?;
    Ok(ReplayReport {
        header,
        commands,
        events,
        difference,
    })
}

type Replayed = (usize, usize, Option<(usize, String)>);

/// Ticks stepped at once towards a recorded event before the card's events are looked at.
const STEP_CHUNK: u64 = 1000;

fn run_replay(card: &Card, records: &[Record]) -> Result<Replayed> {
    let sim = card.sim().expect("a stepped emulated card");
    let w = card.window();
    let tick = || w.read64(layout::TICK);
    // Recorded seq → replayed seq, and the recorded commands not replayed: the open's attach.
    // Every later session command is replayed with the traced session's id replaced by this
    // host's: a trace that ended its session (a raw detach) refuses what it refused, and its
    // close's detach ends the replaying session as it ended the recorded one.
    let mut seqs = std::collections::HashMap::new();
    let mut skipped = std::collections::HashSet::new();
    let open = open_attach(records);
    let own = card.inner().link.session;
    // The tick each recorded command was answered at (its ack or nack).
    let answered: std::collections::HashMap<u32, u64> = records
        .iter()
        .filter_map(|r| match r {
            Record::Event(_, e)
                if matches!(
                    EventKind::from_raw(e.kind),
                    Some(EventKind::Ack | EventKind::Nack)
                ) =>
            {
                Some((e.seq, e.tick))
            }
            _ => None,
        })
        .collect();
    let mut got: std::collections::VecDeque<Event> = Default::default();
    let (mut commands, mut events) = (0, 0);
    // The recorded card's ticks on this card's clock: the first recorded tick is now.
    let first = records.iter().find_map(|r| match r {
        Record::Command(_, c) if open.is_none_or(|(seq, _)| seq != c.seq) => {
            answered.get(&c.seq).copied()
        }
        Record::Event(_, e)
            if !matches!(
                EventKind::from_raw(e.kind),
                Some(EventKind::Ack | EventKind::Nack)
            ) =>
        {
            Some(e.tick)
        }
        _ => None,
    });
    let shift = first.map_or(0, |t| t as i128 - tick() as i128);
    let here = |t: u64| (t as i128 - shift).max(0) as u64;
    let step_to = |t: u64| {
        let now = tick();
        if t > now {
            sim.step(t - now);
        }
    };
    // To a recorded event's tick, or to the card's next event if it comes first (a card that
    // went another way is found at its first event, not at the recorded one's tick).
    let step_to_event = |t: u64, got: &mut std::collections::VecDeque<Event>| -> Result<()> {
        loop {
            card.inner().take_raw_events(got)?;
            let now = tick();
            if !got.is_empty() || now >= t {
                return Ok(());
            }
            sim.step((t - now).min(STEP_CHUNK));
        }
    };
    for r in records {
        match r {
            Record::Block(_, off, words) => {
                for (k, v) in words.iter().enumerate() {
                    w.write64(off + 8 * k, *v);
                }
            }
            Record::Command(_, c) if open.is_some_and(|(seq, _)| seq == c.seq) => {
                skipped.insert(c.seq);
            }
            Record::Command(_, c) => {
                if let Some(&t) = answered.get(&c.seq) {
                    step_to(here(t));
                }
                let mut cmd = *c;
                cmd.deadline_ms = 0;
                if session_op(c.opcode) && open.is_some_and(|(_, traced)| traced == c.flags) {
                    cmd.flags = own;
                }
                seqs.insert(c.seq, card.inner().send_raw(cmd)?);
                commands += 1;
            }
            Record::Event(n, want) => {
                let kind = EventKind::from_raw(want.kind);
                let answer = matches!(kind, Some(EventKind::Ack | EventKind::Nack));
                if answer && skipped.contains(&want.seq) {
                    continue;
                }
                let mut want = *want;
                want.tick = here(want.tick);
                if want.seq != 0 {
                    if let Some(&s) = seqs.get(&want.seq) {
                        want.seq = s;
                    } else if answer {
                        return Ok((
                            commands,
                            events,
                            Some((
                                *n,
                                format!("an answer to command {} that was not sent", want.seq),
                            )),
                        ));
                    }
                }
                step_to_event(want.tick, &mut got)?;
                events += 1;
                match got.pop_front() {
                    Some(e) if e == want => {}
                    Some(e) => {
                        return Ok((
                            commands,
                            events,
                            Some((
                                *n,
                                format!("recorded {}, the card posted {}", show(&want), show(&e)),
                            )),
                        ))
                    }
                    None => {
                        return Ok((
                            commands,
                            events,
                            Some((
                                *n,
                                format!(
                                    "recorded {}, the card posted nothing by tick {}",
                                    show(&want),
                                    tick()
                                ),
                            )),
                        ))
                    }
                }
            }
        }
    }
    Ok((commands, events, None))
}
