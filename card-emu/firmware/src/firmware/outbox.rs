//! The firmware's fixed event queues: events raised while a command is served or a tick runs,
//! posted to the event ring afterwards (after the command's ack). A queue holds at most `N`
//! events; one that finds it full is counted ([`EventQueue::lost`]; the firmware publishes the
//! count in the window), never dropped silently, and never panics.

use firmware_proto::{Event, GROUP_QUEUE_LEN, MAX_AXES};

/// A fixed queue of at most `N` events that counts what it could not hold.
#[derive(Debug, Clone, Default)]
pub struct EventQueue<const N: usize> {
    events: heapless::Vec<Event, N>,
    lost: u32,
}

/// The command manager's and the groups' events: enough for a group aborting a full queue.
/// Its losses are published in `card.outbox_lost`.
pub type Outbox = EventQueue<{ 2 * GROUP_QUEUE_LEN + 8 }>;

/// The safety layer's events, sized for the worst tick: per axis an abort, a state change, a
/// stop and a rest event, plus card-wide events. Its losses are published in
/// `card.safety_events_lost`.
pub type SafetyEvents = EventQueue<{ 8 * MAX_AXES + 8 }>;

impl<const N: usize> EventQueue<N> {
    /// Events it holds.
    pub const CAP: usize = N;

    /// Empty.
    pub const fn new() -> Self {
        Self {
            events: heapless::Vec::new(),
            lost: 0,
        }
    }

    /// Queue an event; when full, count it as lost.
    pub fn push(&mut self, e: Event) {
        if self.events.push(e).is_err() {
            self.lost = self.lost.wrapping_add(1);
        }
    }

    /// Event `i`, in the order pushed.
    pub fn get(&self, i: usize) -> Option<Event> {
        self.events.get(i).copied()
    }

    /// The events, in the order pushed.
    pub fn iter(&self) -> impl Iterator<Item = &Event> {
        self.events.iter()
    }

    /// Events queued.
    pub fn len(&self) -> usize {
        self.events.len()
    }

    /// Nothing queued.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// Forget them (after posting).
    #[inline]
    pub fn clear(&mut self) {
        self.events.clear();
    }

    /// Events that found it full since boot (wrapping).
    pub fn lost(&self) -> u32 {
        self.lost
    }
}
