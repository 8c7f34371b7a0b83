//! Timed commands and the sync bus on one card (timed.rs): what runs on which tick, what is
//! refused with which code, and what a follower does when it loses its master.

use super::timed::Commit;
use super::*;
use firmware_proto::mem::HeapWindow;
use firmware_proto::ring::{CmdProducer, EvtConsumer};
use firmware_proto::Opcode;
use std::sync::Arc;

type Fw = Firmware<Arc<HeapWindow>>;

/// A card of the tests (layout 1.13's `tests_arc_pair.rs` too): the firmware over a window,
/// the host's rings, the events taken.
pub(super) struct Card {
    pub(super) w: Arc<HeapWindow>,
    pub(super) fw: Fw,
    tx: CmdProducer<Arc<HeapWindow>>,
    rx: EvtConsumer<Arc<HeapWindow>>,
    seq: u32,
    pub(super) events: Vec<Event>,
}

impl Card {
    fn new() -> Self {
        Self::with_axes(2)
    }

    /// A card of `n` axes with a host attached.
    pub(super) fn with_axes(n: usize) -> Self {
        let w = Arc::new(HeapWindow::new());
        let fw = Firmware::boot(w.clone(), n, 10_000);
        let tx = CmdProducer::attach(w.clone(), CMD_RING);
        let rx = EvtConsumer::attach(w.clone(), EVT_RING);
        let mut c = Self {
            w,
            fw,
            tx,
            rx,
            seq: 0,
            events: Vec::new(),
        };
        let s = c.entry(Opcode::HostAttach, 0, 7, &[]);
        c.send(&[s]);
        c
    }

    /// A card of `n` axes, all powered, with group 0 over them (exact interpolation,
    /// pre-interpolation acc/dec, tolerance 1 count) configured and enabled.
    pub(super) fn with_group(n: usize) -> Self {
        let mut c = Self::with_axes(n);
        for a in 0..n as u16 {
            let p = c.entry(Opcode::PowerOn, a, 0, &[]);
            c.send(&[p]);
            assert_eq!(c.answer(p.seq), Some(Ok(0)), "power {a}");
        }
        let mut block = firmware_proto::raw::mc_group_config {
            naxes: n as u32,
            accdec: firmware_proto::raw::MC_ACCDEC_PRE,
            interpolator: firmware_proto::raw::MC_INTERP_EXACT,
            tolerance: 1.0,
            ..Default::default()
        };
        for (k, a) in block.axes[..n].iter_mut().enumerate() {
            *a = k as u8;
        }
        layout::GROUP_CONFIG.at(0).write(&c.w, &block);
        let cfg = c.entry(Opcode::GroupConfigure, 0, 0, &[]);
        let en = c.entry(Opcode::GroupEnable, 0, 0, &[]);
        c.send(&[cfg, en]);
        assert_eq!(
            (c.answer(cfg.seq), c.answer(en.seq)),
            (Some(Ok(0)), Some(Ok(0)))
        );
        c
    }

    pub(super) fn entry(&mut self, op: Opcode, axis: u16, flags: u32, args: &[f64]) -> Command {
        self.seq += 1;
        let mut c = Command::new(op, axis).with_args(args);
        c.flags = flags;
        c.seq = self.seq;
        c
    }

    /// A timed command: the `MC_OP_AT_TICK` entry and `cmd`, seqs in order.
    pub(super) fn timed(&mut self, tick: u64, key: u32, op: Opcode, args: &[f64]) -> [Command; 2] {
        let at = self.entry(Opcode::AtTick, 0, 0, &[tick as f64, key as f64]);
        let c = self.entry(op, 0, 0, args);
        [at, c]
    }

    /// Publish `cmds` at once (one head update, as the SDK's push of a pair) and serve.
    pub(super) fn send(&mut self, cmds: &[Command]) {
        self.tx.push_all(cmds).unwrap();
        self.fw.serve_commands();
        self.drain();
    }

    pub(super) fn tick(&mut self) {
        self.fw.tick(&[0; MAX_AXES], &mut [0.0; MAX_AXES]);
        self.drain();
    }

    pub(super) fn drain(&mut self) {
        while let Ok(Some(e)) = self.rx.pop::<Event>() {
            self.events.push(e);
        }
    }

    /// The answer to `seq`: `Ok(tick)` for an ack, `Err(code)` for a nack, `None` yet.
    pub(super) fn answer(&self, seq: u32) -> Option<Result<u64, NackCode>> {
        self.events.iter().find_map(|e| {
            (e.seq == seq && (e.kind == EventKind::Ack as u16 || e.kind == EventKind::Nack as u16))
                .then(|| {
                    if e.kind == EventKind::Ack as u16 {
                        Ok(e.tick)
                    } else {
                        Err(NackCode::from_raw(e.code).unwrap())
                    }
                })
        })
    }

    pub(super) fn answers(&self, seq: u32) -> usize {
        self.events
            .iter()
            .filter(|e| {
                e.seq == seq
                    && (e.kind == EventKind::Ack as u16 || e.kind == EventKind::Nack as u16)
            })
            .count()
    }

    fn info(&self) -> firmware_proto::raw::mc_card_info {
        layout::CARD_INFO.read(&self.w)
    }
}

/// A timed MC_OP_SET_OUTPUTS (mask 1, value 1) runs on its tick exactly: the pair is held
/// when taken (the timing acked at once, the command not yet answered), the outputs change on
/// the tick and not one before, and the command's ack and `MC_EV_TIMED` carry that tick.
#[test]
fn a_timed_command_runs_on_its_tick_and_not_before() {
    let mut c = Card::new();
    for _ in 0..5 {
        c.tick();
    }
    let t = c.fw.tick_count() + 10;
    let pair = c.timed(t, 0, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&pair);
    assert_eq!(c.answer(pair[0].seq), Some(Ok(5)), "held at once");
    assert_eq!(
        c.answer(pair[1].seq),
        None,
        "the command waits for its tick"
    );
    assert_eq!(c.info().timed_held, 1);
    assert_eq!(c.info().timed_next, t);
    while c.fw.tick_count() < t - 1 {
        c.tick();
        assert_eq!(c.fw.outputs() & 1, 0, "tick {}", c.fw.tick_count());
    }
    c.tick();
    assert_eq!(c.fw.tick_count(), t);
    assert_eq!(c.fw.outputs() & 1, 1);
    assert_eq!(c.answer(pair[1].seq), Some(Ok(t)));
    let timed = c
        .events
        .iter()
        .find(|e| e.kind == EventKind::Timed as u16)
        .expect("MC_EV_TIMED");
    assert_eq!(
        (timed.seq, timed.code, timed.tick),
        (pair[1].seq, Opcode::SetOutputs as i32, t)
    );
    assert_eq!(c.info().timed_held, 0);
    assert_eq!(c.answers(pair[0].seq) + c.answers(pair[1].seq), 2);
}

/// Each refusal of a timing has its code, answers both entries once, and holds nothing.
#[test]
fn refused_timings_answer_both_entries_and_hold_nothing() {
    let mut c = Card::new();
    c.tick();
    let now = c.fw.tick_count();
    let far = now + firmware_proto::raw::MC_TIMED_MAX_AHEAD as u64 + 1;
    let cases: [(u64, f64, Opcode, NackCode, NackCode); 5] = [
        (
            now,
            0.0,
            Opcode::SetOutputs,
            NackCode::TickPassed,
            NackCode::TimedRefused,
        ),
        (
            far,
            0.0,
            Opcode::SetOutputs,
            NackCode::TickFar,
            NackCode::TimedRefused,
        ),
        (
            now + 5,
            0.5,
            Opcode::SetOutputs,
            NackCode::TickFar,
            NackCode::TimedRefused,
        ),
        (
            now + 5,
            0.0,
            Opcode::HostDetach,
            NackCode::TimedAlone,
            NackCode::TimedAlone,
        ),
        (
            now + 5,
            0.0,
            Opcode::AtTick,
            NackCode::TimedAlone,
            NackCode::TimedAlone,
        ),
    ];
    for (tick, key, op, at_code, cmd_code) in cases {
        let at = c.entry(Opcode::AtTick, 0, 0, &[tick as f64, key]);
        let cmd = c.entry(op, 0, 0, &[1.0, 1.0]);
        c.send(&[at, cmd]);
        assert_eq!(c.answer(at.seq), Some(Err(at_code)), "{op:?} at {tick}");
        assert_eq!(c.answer(cmd.seq), Some(Err(cmd_code)), "{op:?} at {tick}");
        assert_eq!((c.answers(at.seq), c.answers(cmd.seq)), (1, 1));
    }
    // A command that does not decode: its own code on both.
    let at = c.entry(Opcode::AtTick, 0, 0, &[(now + 5) as f64, 0.0]);
    let mut bad = c.entry(Opcode::SetOutputs, 0, 0, &[]);
    bad.opcode = 9999;
    c.send(&[at, bad]);
    assert_eq!(c.answer(at.seq), Some(Err(NackCode::UnknownOpcode)));
    assert_eq!(c.answer(bad.seq), Some(Err(NackCode::UnknownOpcode)));
    // A timing with nothing after it.
    let alone = c.entry(Opcode::AtTick, 0, 0, &[(now + 5) as f64, 0.0]);
    c.send(&[alone]);
    assert_eq!(c.answer(alone.seq), Some(Err(NackCode::TimedAlone)));
    assert_eq!(c.info().timed_held, 0);
    // The slots: 16 held, the 17th refused.
    for k in 0..TIMED_SLOTS as u64 {
        let p = c.timed(now + 100 + k, 0, Opcode::SetOutputs, &[1.0, 1.0]);
        c.send(&p);
        assert_eq!(c.answer(p[0].seq), Some(Ok(now)));
    }
    let p = c.timed(now + 200, 0, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&p);
    assert_eq!(c.answer(p[0].seq), Some(Err(NackCode::TimedFull)));
    assert_eq!(c.answer(p[1].seq), Some(Err(NackCode::TimedRefused)));
    assert_eq!(c.info().timed_held, TIMED_SLOTS as u32);
    // Without a session, a command that moves cannot be timed.
    let det = c.entry(Opcode::HostDetach, 0, 7, &[]);
    c.send(&[det]);
    let held: Vec<u32> = (0..TIMED_SLOTS as u32).collect();
    assert_eq!(c.info().timed_held, 0, "the detach dropped {held:?}");
    let p = c.timed(now + 5, 0, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&p);
    assert_eq!(c.answer(p[0].seq), Some(Err(NackCode::NoSession)));
    assert_eq!(c.answer(p[1].seq), Some(Err(NackCode::NoSession)));
}

use super::timed::TIMED_SLOTS;

/// A keyed command runs only with its key's commit for its tick, seen before the tick; a
/// commit on or after the tick is refused and the command does not run; a cancel drops the
/// key's commands with their count.
#[test]
fn a_keyed_command_needs_its_commit_before_its_tick() {
    let mut c = Card::new();
    c.tick();
    let t = c.fw.tick_count() + 5;
    // No commit: refused on its tick, nothing done.
    let p = c.timed(t, 42, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&p);
    // A commit of another tick does not count.
    let other = c.entry(Opcode::SyncCommit, 0, 0, &[42.0, (t + 1) as f64]);
    c.send(&[other]);
    assert_eq!(c.answer(other.seq), Some(Ok(1)));
    while c.fw.tick_count() < t {
        c.tick();
    }
    assert_eq!(c.answer(p[1].seq), Some(Err(NackCode::NotCommitted)));
    assert_eq!(c.fw.outputs() & 1, 0);
    // Committed in time: runs.
    let t = c.fw.tick_count() + 5;
    let p = c.timed(t, 43, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&p);
    let commit = c.entry(Opcode::SyncCommit, 0, 0, &[43.0, t as f64]);
    c.send(&[commit]);
    assert_eq!(c.answer(commit.seq), Some(Ok(c.fw.tick_count())));
    while c.fw.tick_count() < t {
        c.tick();
    }
    assert_eq!(c.answer(p[1].seq), Some(Ok(t)));
    assert_eq!(c.fw.outputs() & 1, 1);
    // Too late: on the tick itself.
    let late = c.entry(Opcode::SyncCommit, 0, 0, &[44.0, c.fw.tick_count() as f64]);
    let zero = c.entry(Opcode::SyncCommit, 0, 0, &[0.0, (t + 9) as f64]);
    c.send(&[late, zero]);
    assert_eq!(c.answer(late.seq), Some(Err(NackCode::CommitLate)));
    assert_eq!(c.answer(zero.seq), Some(Err(NackCode::TickFar)));
    // A cancel: the key's two commands, not the other key's.
    let t = c.fw.tick_count() + 50;
    let a = c.timed(t, 7, Opcode::SetOutputs, &[1.0, 0.0]);
    let b = c.timed(t + 1, 7, Opcode::SetOutputs, &[1.0, 0.0]);
    let keep = c.timed(t + 2, 8, Opcode::SetOutputs, &[1.0, 0.0]);
    c.send(&a);
    c.send(&b);
    c.send(&keep);
    let cancel = c.entry(Opcode::TimedCancel, 0, 0, &[7.0]);
    c.send(&[cancel]);
    let value = c
        .events
        .iter()
        .find(|e| e.seq == cancel.seq)
        .map(|e| e.value);
    assert_eq!(value, Some(2.0));
    assert_eq!(c.answer(a[1].seq), Some(Err(NackCode::Cancelled)));
    assert_eq!(c.answer(b[1].seq), Some(Err(NackCode::Cancelled)));
    assert_eq!(c.answer(keep[1].seq), None);
    assert_eq!(c.info().timed_held, 1);
}

/// Commands timed to one tick run in the order they were taken, whatever slots they sit in.
#[test]
fn commands_of_one_tick_run_in_the_order_taken() {
    let mut c = Card::new();
    c.tick();
    let t = c.fw.tick_count() + 20;
    // Fill and free the first slots so that later commands take earlier slots.
    let early = c.timed(t - 10, 0, Opcode::SetOutputs, &[2.0, 2.0]);
    c.send(&early);
    let first = c.timed(t, 0, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&first);
    while c.fw.tick_count() < t - 10 {
        c.tick();
    }
    let second = c.timed(t, 0, Opcode::SetOutputs, &[1.0, 0.0]);
    c.send(&second); // takes the slot `early` left, before `first`'s
    while c.fw.tick_count() < t {
        c.tick();
    }
    assert_eq!(c.answer(first[1].seq), Some(Ok(t)));
    assert_eq!(c.answer(second[1].seq), Some(Ok(t)));
    assert_eq!(c.fw.outputs() & 1, 0, "set, then cleared: taken order");
    let pos = |s: u32| c.events.iter().position(|e| e.seq == s).unwrap();
    assert!(pos(first[1].seq) < pos(second[1].seq));
}

/// A follower takes the master's tick count on joining, runs a keyed command once the bus
/// brings the commit, refuses commits of its own; losing the master halts it (reason
/// `SyncLost`), refuses what it holds, and shows the loss in `card_info` and an event.
#[test]
fn a_follower_runs_the_masters_commits_and_stops_when_it_loses_the_master() {
    let mut c = Card::new();
    // Joining needs no host: a card a host commands does not jump its clock.
    assert!(!c.fw.join_bus("a", 1_000));
    let det = c.entry(Opcode::HostDetach, 0, 7, &[]);
    c.send(&[det]);
    assert!(c.fw.join_bus("a", 1_000));
    assert_eq!(c.fw.tick_count(), 1_000);
    assert_eq!(c.w.read64(layout::TICK), 1_000);
    let info = c.info();
    assert_eq!(
        (info.sync_role, info.sync_state),
        (
            firmware_proto::raw::MC_BUS_FOLLOWER,
            firmware_proto::raw::MC_BUSST_LOCKED
        )
    );
    assert_eq!(info.sync_master[0] as u8, b'a');
    let att = c.entry(Opcode::HostAttach, 0, 8, &[]);
    c.send(&[att]);
    let t = 1_010;
    let p = c.timed(t, 5, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&p);
    let own = c.entry(Opcode::SyncCommit, 0, 0, &[5.0, t as f64]);
    c.send(&[own]);
    assert_eq!(c.answer(own.seq), Some(Err(NackCode::NotMaster)));
    c.tick();
    c.fw.bus_commit(Commit { key: 5, tick: t });
    while c.fw.tick_count() < t {
        c.tick();
    }
    assert_eq!(c.answer(p[1].seq), Some(Ok(t)));
    // Loss: the held command is refused, the state shows it, once.
    let q = c.timed(t + 100, 0, Opcode::SetOutputs, &[1.0, 0.0]);
    c.send(&q);
    c.fw.lose_bus();
    c.fw.lose_bus();
    c.drain();
    assert_eq!(c.answer(q[1].seq), Some(Err(NackCode::SyncLost)));
    let lost: Vec<_> = c
        .events
        .iter()
        .filter(|e| e.kind == EventKind::SyncBus as u16)
        .map(|e| e.code as u32)
        .collect();
    assert_eq!(
        lost,
        [
            firmware_proto::raw::MC_BUSST_LOCKED,
            firmware_proto::raw::MC_BUSST_LOST
        ]
    );
    c.tick();
    let info = c.info();
    assert_eq!(info.sync_state, firmware_proto::raw::MC_BUSST_LOST);
    assert_eq!(info.sync_losses, 1);
    // Nothing more can be timed on a card that lost its clock.
    let r = c.timed(t + 200, 0, Opcode::SetOutputs, &[1.0, 1.0]);
    c.send(&r);
    assert_eq!(c.answer(r[0].seq), Some(Err(NackCode::SyncLost)));
}
