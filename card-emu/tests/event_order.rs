//! The card publishes an axis's status before it posts the events about it: a host that has
//! taken an event (an ack, a state change, motion done) and then reads the status never sees
//! the state from before that event. A spy window records the published status at the instant
//! each event becomes visible to the host (the store of the event ring's head).

use card_emu::Firmware;
use firmware_proto::mem::HeapWindow;
use firmware_proto::ring::{CmdProducer, EvtConsumer, CMD_RING, EVT_RING};
use firmware_proto::{
    layout, seqlock, AxisState, Command, Event, EventKind, Mem, Opcode, MAX_AXES,
};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

/// What the host would read at the moment event ring head `head` was published.
#[derive(Debug, Clone, Copy)]
struct Seen {
    head: u32,
    state: u32,
    tick: u64,
}

#[derive(Clone)]
struct Spy {
    window: Arc<HeapWindow>,
    seen: Arc<Mutex<Vec<Seen>>>,
}

impl Mem for Spy {
    fn load32(&self, off: usize, order: Ordering) -> u32 {
        self.window.load32(off, order)
    }
    fn store32(&self, off: usize, val: u32, order: Ordering) {
        self.window.store32(off, val, order);
        // (Boot zeroes the head before it has published any status: nothing to record.)
        if off == layout::EVT_HEAD {
            if let Ok(s) = seqlock::read_axis_status(&*self.window, 0) {
                self.seen.lock().unwrap().push(Seen {
                    head: val,
                    state: s.state,
                    tick: s.tick,
                });
            }
        }
    }
    fn load64(&self, off: usize, order: Ordering) -> u64 {
        self.window.load64(off, order)
    }
    fn store64(&self, off: usize, val: u64, order: Ordering) {
        self.window.store64(off, val, order)
    }
}

#[test]
fn every_event_is_visible_only_after_the_status_it_describes() {
    let spy = Spy {
        window: Arc::new(HeapWindow::new()),
        seen: Arc::default(),
    };
    let mut fw = Firmware::boot(spy.clone(), 1, 10_000);
    let mut tx = CmdProducer::attach(spy.window.clone(), CMD_RING);
    let mut rx = EvtConsumer::attach(spy.window.clone(), EVT_RING);
    // A host in command: attached (the session gate refuses power and motion without one),
    // beating before each tick.
    let attach = {
        let mut c = Command::new(Opcode::HostAttach, 0);
        c.flags = 1;
        c.seq = tx.head().wrapping_add(1);
        tx.push(&c).unwrap();
        c.seq
    };
    let mut send = |op: Opcode, args: &[f64]| {
        let mut c = Command::new(op, 0).with_args(args);
        c.seq = tx.head().wrapping_add(1);
        tx.push(&c).unwrap();
        c.seq
    };
    let power_on = send(Opcode::PowerOn, &[]);
    let mv = send(
        Opcode::MoveRelative,
        &[1000.0, 1e5, 1e6, 1e6, 1e7, 1e7, 1e7, 1e7],
    );
    fw.serve_commands();

    // A perfect plant: the encoder follows the commanded position.
    let (mut enc, mut dac) = ([0i64; MAX_AXES], [0.0; MAX_AXES]);
    let mut events: Vec<Event> = Vec::new();
    while !events
        .iter()
        .any(|e| e.kind() == Some(EventKind::MotionDone))
    {
        assert!(fw.tick_count() < 100_000, "the move never finished");
        let hb = spy.window.read32(layout::HEARTBEAT);
        spy.window.write32(layout::HEARTBEAT, hb.wrapping_add(1));
        fw.tick(&enc, &mut dac);
        enc[0] = seqlock::read_axis_status(&*spy.window, 0)
            .unwrap()
            .cmd_pos
            .round() as i64;
        while let Some(e) = rx.pop::<Event>().unwrap() {
            events.push(e);
        }
    }

    let seen = spy.seen.lock().unwrap().clone();
    let standstill = AxisState::Standstill as u32;
    let moving = AxisState::DiscreteMotion as u32;
    for (k, e) in events.iter().enumerate() {
        // Event k became visible when the head went to k + 1.
        let at = seen
            .iter()
            .find(|s| s.head == k as u32 + 1)
            .unwrap_or_else(|| panic!("event {k} was never published"));
        assert!(
            at.tick >= e.tick,
            "event {k} {e:?} ahead of the status: {at:?}"
        );
        let expect = match (e.kind().unwrap(), e.seq) {
            (EventKind::Ack, s) if s == attach => AxisState::Disabled as u32,
            (EventKind::Ack, s) if s == power_on => standstill,
            (EventKind::Ack, s) if s == mv => moving,
            (EventKind::StateChanged, _) => e.code as u32,
            (EventKind::MotionDone, s) if s == mv => standstill,
            other => panic!("unexpected event {other:?}: {e:?}"),
        };
        assert_eq!(
            at.state, expect,
            "event {k} {e:?} visible with status {at:?}"
        );
    }
    let kinds: Vec<_> = events.iter().map(|e| e.kind().unwrap()).collect();
    assert!(kinds.contains(&EventKind::StateChanged), "{kinds:?}");
    assert_eq!(
        kinds.iter().filter(|k| **k == EventKind::Ack).count(),
        3,
        "{kinds:?}"
    );
}
