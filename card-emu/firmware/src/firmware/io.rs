//! Digital I/O (layout 1.7): the card's inputs (polarity, debounce, edge events) and the unit
//! that runs the position-compare channels (`compare.rs`) and the touch probes (`probe.rs`)
//! beside them.
//!
//! The encoder interface samples the input pins once per tick and timestamps each pin's edge
//! within the tick ([`DigitalInputs`]). The card applies the polarity (`card.inputs_raw`) and
//! debounces each input: its debounced bit takes a new level once the input has held it for
//! `debounce[i]` ticks (a level seen on `d + 1` consecutive samples; 0: at once), so a pulse
//! of `d` samples or fewer never reaches `card.inputs`. An edge of the debounced word whose
//! bit is in `rise_events` / `fall_events` posts `MC_EV_INPUT`. The probes take the raw edges
//! (polarity applied, not debounced) with their instants.
//!
//! [`IoUnit::tick`] runs once per servo tick after the axes sensed their encoders: it needs
//! each axis's count at both ends of the tick. It allocates nothing; its events go to a queue
//! sized for the worst tick (every input, three compare codes per channel, a capture per
//! probe).

use super::axis::Axis;
use super::compare::{self, Compare, Fire};
use super::outbox::EventQueue;
use super::probe::{self, Probe, Trigger};
use super::quiet::REWRITE_TICKS;
use super::safety::IndexLatch;
use firmware_proto::cmd::IoCmd;
use firmware_proto::{
    layout, raw, Event, EventKind, Mem, NackCode, COMPARE_CHANNELS, INPUTS, MAX_AXES,
    PROBE_CHANNELS,
};

/// The input pins as the encoder interface samples them at a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DigitalInputs {
    /// The pins now, bit i = input i, before the polarity.
    pub levels: u32,
    /// For each input whose level changed since the last tick: the instant of its (last)
    /// change, a fraction of the tick just ended in `[0, 1]`.
    pub edge_at: [f64; INPUTS],
}

impl Default for DigitalInputs {
    fn default() -> Self {
        Self {
            levels: 0,
            edge_at: [1.0; INPUTS],
        }
    }
}

/// The lowest and highest count each axis's encoder reached over the tick just ended, as the
/// encoder interface tracks them between two servo samples (`None`: not tracked; the counts at
/// the tick's two ends stand for them). A compare position between an extreme and both ends
/// was crossed and crossed back within the tick.
pub type EncoderSpans = [Option<(i64, i64)>; MAX_AXES];

/// All the input bits.
const ALL: u32 = (1 << INPUTS) - 1;

/// The validated copy of `io_config`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IoConfig {
    /// Active-low inputs.
    pub polarity: u32,
    /// Inputs whose debounced rising edge posts `MC_EV_INPUT`.
    pub rise_events: u32,
    /// Inputs whose debounced falling edge posts `MC_EV_INPUT`.
    pub fall_events: u32,
    /// Debounce per input, ticks.
    pub debounce: [u16; INPUTS],
}

impl IoConfig {
    /// Validate the block (`MC_NACK_IO_CONFIG`: a mask bit beyond the inputs, a debounce
    /// beyond `MC_DEBOUNCE_MAX`).
    pub fn validate(b: &raw::mc_io_config) -> Result<Self, NackCode> {
        if (b.polarity | b.rise_events | b.fall_events) & !ALL != 0
            || b.debounce
                .iter()
                .any(|&d| u32::from(d) > raw::MC_DEBOUNCE_MAX)
        {
            return Err(NackCode::IoConfig);
        }
        Ok(Self {
            polarity: b.polarity,
            rise_events: b.rise_events,
            fall_events: b.fall_events,
            debounce: b.debounce,
        })
    }

    /// As the block.
    pub fn to_block(&self) -> raw::mc_io_config {
        raw::mc_io_config {
            polarity: self.polarity,
            rise_events: self.rise_events,
            fall_events: self.fall_events,
            debounce: self.debounce,
            ..Default::default()
        }
    }
}

/// The inputs' polarity and debounce.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Debounce {
    cfg: IoConfig,
    pins: u32,
    raw: u32,
    debounced: u32,
    held: [u16; INPUTS],
}

/// Edges of one tick, bit sets.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Edges {
    /// Became active.
    pub rising: u32,
    /// Became inactive.
    pub falling: u32,
}

impl Debounce {
    /// A new configuration; the debounced word starts again from the inputs as they are.
    pub fn apply(&mut self, cfg: IoConfig) {
        self.cfg = cfg;
        self.raw = (self.pins ^ cfg.polarity) & ALL;
        self.debounced = self.raw;
        self.held = [0; INPUTS];
    }

    /// One sample of the pins: the raw edges (polarity applied) and the debounced edges.
    pub fn tick(&mut self, pins: u32) -> (Edges, Edges) {
        self.pins = pins & ALL;
        let raw = (self.pins ^ self.cfg.polarity) & ALL;
        let raw_edges = Edges {
            rising: raw & !self.raw,
            falling: !raw & self.raw & ALL,
        };
        self.raw = raw;
        let before = self.debounced;
        if raw == self.debounced {
            // Every input as debounced: each count starts again (the loop below would clear
            // them one by one).
            self.held = [0; INPUTS];
            return (raw_edges, Edges::default());
        }
        for i in 0..INPUTS {
            let bit = 1 << i;
            if (raw ^ self.debounced) & bit == 0 {
                self.held[i] = 0;
                continue;
            }
            self.held[i] = self.held[i].saturating_add(1);
            if self.held[i] > self.cfg.debounce[i] {
                self.debounced ^= bit;
                self.held[i] = 0;
            }
        }
        let d = self.debounced;
        (
            raw_edges,
            Edges {
                rising: d & !before,
                falling: !d & before & ALL,
            },
        )
    }

    /// The debounced word.
    pub fn debounced(&self) -> u32 {
        self.debounced
    }

    /// The sampled word, polarity applied.
    pub fn raw(&self) -> u32 {
        self.raw
    }

    /// The configuration.
    pub fn config(&self) -> &IoConfig {
        &self.cfg
    }
}

/// Events one tick of the unit can raise at most.
pub const IO_EVENTS: usize = INPUTS + 3 * COMPARE_CHANNELS + PROBE_CHANNELS;

/// Fires the unit records per tick for the output recorder (beyond it they still count).
pub const FIRES_PER_TICK: usize = 512;

/// The digital inputs, the compare channels and the probes.
#[derive(Debug)]
pub struct IoUnit {
    inputs: DigitalInputs,
    spans: EncoderSpans,
    debounce: Debounce,
    compare: [Compare; COMPARE_CHANNELS],
    probes: [Probe; PROBE_CHANNELS],
    /// Each axis's count at the last tick (None before the first).
    last_count: [Option<i64>; MAX_AXES],
    last_index: [u32; MAX_AXES],
    fires: heapless::Vec<Fire, FIRES_PER_TICK>,
    events: EventQueue<IO_EVENTS>,
    /// The axes a halting probe captured on in the last tick, with the arm's seq (a bit an
    /// axis; the firmware halts their motion).
    halts: (u32, u32),
    /// The window's compare and probe status blocks hold the channels' statuses of now: no
    /// command and no armed tick since [`IoUnit::publish`] wrote them (only those change a
    /// channel's status; an unarmed tick counts down a pulse, which is not in it).
    statuses_written: bool,
}

impl Default for IoUnit {
    fn default() -> Self {
        Self::new()
    }
}

/// The axis a compare or probe arm names (`axis`), if it is one of the card's `num_axes`.
pub fn arm_axis(axis: u16, num_axes: usize) -> Result<usize, NackCode> {
    let a = axis as usize;
    if a < num_axes {
        Ok(a)
    } else {
        Err(NackCode::BadAxis)
    }
}

impl IoUnit {
    /// Boot state: every input active high, no debounce, nothing armed. The compare tables
    /// are allocated here.
    pub fn new() -> Self {
        Self {
            inputs: DigitalInputs::default(),
            spans: [None; MAX_AXES],
            debounce: Debounce::default(),
            compare: core::array::from_fn(|_| Compare::new()),
            probes: [Probe::default(); PROBE_CHANNELS],
            last_count: [None; MAX_AXES],
            last_index: [0; MAX_AXES],
            fires: heapless::Vec::new(),
            events: EventQueue::new(),
            halts: (0, 0),
            statuses_written: false,
        }
    }

    /// The pins for the next tick.
    pub fn set_inputs(&mut self, inputs: DigitalInputs) {
        self.inputs = inputs;
    }

    /// The encoders' extremes over the period the next tick ends.
    pub fn set_spans(&mut self, spans: EncoderSpans) {
        self.spans = spans;
    }

    /// Execute an I/O command of this unit (all but `MC_OP_SET_OUTPUTS`, the firmware's) of
    /// command `seq` naming axis `axis`; `num_axes` bounds the axis of an arm; `modulo` gives
    /// an axis's period (counts, 0: linear; layout 1.13: a compare arm on a modulo axis is
    /// turn-aware).
    #[allow(clippy::too_many_arguments)]
    pub fn command<M: Mem>(
        &mut self,
        mem: &M,
        seq: u32,
        axis: u16,
        cmd: &IoCmd,
        num_axes: usize,
        rate_hz: u32,
        modulo: impl Fn(usize) -> f64,
    ) -> Result<f64, NackCode> {
        self.statuses_written = false;
        let axis = || arm_axis(axis, num_axes);
        match cmd {
            IoCmd::ApplyConfig => {
                let cfg = IoConfig::validate(&layout::IO_CONFIG.read(mem))?;
                self.debounce.apply(cfg);
                Ok(0.0)
            }
            IoCmd::CompareArm(a) => {
                let ch = a.channel as usize;
                let ax = axis()?;
                let arm = compare::validate_arm(ax, a, rate_hz, seq, modulo(ax))?;
                let others = self
                    .compare
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != ch)
                    .fold(0, |m, (_, k)| m | k.output_mask());
                if others & (1 << arm.output) != 0 {
                    return Err(NackCode::CompareBusy);
                }
                self.compare[ch].start(arm)?;
                Ok(0.0)
            }
            IoCmd::CompareTable(t) => {
                let room =
                    self.compare[t.channel as usize].queue(t.direction.sign(), &t.positions)?;
                Ok(f64::from(room))
            }
            IoCmd::CompareDisarm(d) => {
                self.compare[d.channel as usize].stop();
                Ok(0.0)
            }
            IoCmd::ProbeArm(p) => {
                let arm = probe::validate_arm(axis()?, p, seq)?;
                self.probes[p.channel as usize].start(arm);
                Ok(0.0)
            }
            IoCmd::ProbeAbort(p) => {
                self.probes[p.channel as usize].abort();
                Ok(0.0)
            }
            // The firmware's (`exec/io.rs`, `analog.rs`).
            IoCmd::SetOutputs(_)
            | IoCmd::AnalogInput(_)
            | IoCmd::AnalogOutput(_)
            | IoCmd::Pso(_)
            | IoCmd::PsoOff => Err(NackCode::UnknownOpcode),
        }
    }

    /// One tick (ending at `tick`): sample the inputs, run the compare channels and the
    /// probes on each axis's motion since the last tick (`counts`, the encoder counts now;
    /// `index`, the index latches). Events go to `IoUnit::events`
    /// (read with [`IoUnit::event`]).
    pub fn tick(
        &mut self,
        tick: u64,
        counts: &[i64; MAX_AXES],
        index: &[IndexLatch; MAX_AXES],
        axes: &[Axis],
    ) {
        self.events.clear();
        self.fires.clear();
        self.halts = (0, 0);
        let (raw_edges, edges) = self.debounce.tick(self.inputs.levels);
        let (rise_events, fall_events) = {
            let cfg = self.debounce.config();
            (cfg.rise_events, cfg.fall_events)
        };
        let word = self.debounce.debounced();
        let posted = (edges.rising & rise_events) | (edges.falling & fall_events);
        if posted != 0 {
            for i in 0..INPUTS as u16 {
                let bit = 1 << i;
                let rise = edges.rising & rise_events & bit != 0;
                let fall = edges.falling & fall_events & bit != 0;
                if rise || fall {
                    self.events.push(Event {
                        seq: 0,
                        kind: EventKind::Input as u16,
                        axis: i,
                        code: i32::from(rise),
                        tick,
                        value: f64::from(word),
                    });
                }
            }
        }
        // The compare channels and the probes watch the axes' motion; with none of them armed
        // the tick only keeps the counts and index latches it compares against next time (and
        // counts down the last pulses).
        let armed = self.compare.iter().any(|c| c.armed().is_some())
            || self.probes.iter().any(|p| p.armed().is_some());
        if !armed {
            for (a, last) in self.last_count.iter_mut().enumerate().take(axes.len()) {
                *last = Some(counts[a]);
            }
            for c in &mut self.compare {
                c.tick_unarmed();
            }
            for (a, last) in self.last_index.iter_mut().enumerate().take(axes.len()) {
                *last = index[a].latches;
            }
            return;
        }
        self.tick_armed(tick, counts, index, axes, raw_edges);
    }

    /// The rest of [`IoUnit::tick`] with a compare channel or a probe armed.
    #[inline(never)]
    fn tick_armed(
        &mut self,
        tick: u64,
        counts: &[i64; MAX_AXES],
        index: &[IndexLatch; MAX_AXES],
        axes: &[Axis],
        raw_edges: Edges,
    ) {
        self.statuses_written = false;
        // Each axis's motion over the tick, cell middles in its frame.
        let mut x = [(0.0, 0.0); MAX_AXES];
        let mut range = [(0.0, 0.0); MAX_AXES];
        for (a, axis) in axes.iter().enumerate().take(MAX_AXES) {
            let now = counts[a];
            let before = self.last_count[a].replace(now).unwrap_or(now);
            let at = |n: i64| axis.load_position_of_count(n) + 0.5;
            x[a] = (at(before), at(now));
            let (lo, hi) = self.spans[a].unwrap_or((before.min(now), before.max(now)));
            range[a] = (
                at(lo).min(x[a].0.min(x[a].1)),
                at(hi).max(x[a].0.max(x[a].1)),
            );
        }
        for (ch, c) in self.compare.iter_mut().enumerate() {
            let Some(arm) = c.armed().copied() else {
                c.tick(ch as u8, (0.0, 0.0), (0.0, 0.0), tick, &mut self.fires);
                continue;
            };
            if arm.axis >= axes.len() {
                continue;
            }
            let (motion, span) = (x[arm.axis], range[arm.axis]);
            let r = c.tick(ch as u8, motion, span, tick, &mut self.fires);
            let mut post = |code: i32, value: f64| {
                self.events.push(Event {
                    seq: arm.seq,
                    kind: EventKind::Compare as u16,
                    axis: ch as u16,
                    code,
                    tick,
                    value,
                })
            };
            if let Some(p) = r.fired {
                post(raw::MC_CMP_FIRED as i32, p);
            }
            if let Some(p) = r.missed {
                post(raw::MC_CMP_MISSED as i32, p);
            }
            if let Some(n) = r.low_water {
                post(raw::MC_CMP_LOW_WATER as i32, f64::from(n));
            }
        }
        let mut index_moved = [None; MAX_AXES];
        for (a, axis) in axes.iter().enumerate().take(MAX_AXES) {
            let l = index[a];
            if l.latches != self.last_index[a] {
                index_moved[a] = Some(axis.load_position_of_count(l.count) + 0.5);
            }
            self.last_index[a] = l.latches;
        }
        for (ch, p) in self.probes.iter_mut().enumerate() {
            let Some(arm) = p.armed().copied() else {
                continue;
            };
            if arm.axis >= axes.len() {
                continue;
            }
            let trigger = if arm.input == probe::INDEX {
                index_moved[arm.axis].map(|position| Trigger::Index { position })
            } else {
                let bit = 1 << arm.input;
                let rising = raw_edges.rising & bit != 0;
                (rising || raw_edges.falling & bit != 0).then(|| Trigger::Edge {
                    frac: self.inputs.edge_at[arm.input as usize].clamp(0.0, 1.0),
                    rising,
                })
            };
            let (x0, x1) = x[arm.axis];
            let ax = &axes[arm.axis];
            if let Some(c) = p.tick_wrapped(x0, x1, tick, trigger, |x| ax.wrap(x)) {
                if arm.halt {
                    self.halts = (self.halts.0 | 1 << arm.axis, arm.seq);
                }
                self.events.push(Event {
                    seq: c.seq,
                    kind: EventKind::Probe as u16,
                    axis: ch as u16,
                    code: c.number as i32,
                    tick,
                    value: c.position,
                });
            }
        }
    }

    /// Event `i` of the last tick.
    #[inline]
    pub fn event(&self, i: usize) -> Option<Event> {
        self.events.get(i)
    }

    /// Events of the last tick.
    #[inline]
    pub fn events_len(&self) -> usize {
        self.events.len()
    }

    /// Events that did not fit (never, by its size; counted with the outbox's).
    pub fn events_lost(&self) -> u32 {
        self.events.lost()
    }

    /// The axes (a bit each) whose motion a halting probe's capture stops, and the arm's
    /// seq, from the last tick.
    #[inline]
    pub fn halts(&self) -> (u32, u32) {
        self.halts
    }

    /// The fires of the last tick, with their instants (for the output recorder).
    pub fn fires(&self) -> &[Fire] {
        &self.fires
    }

    /// The debounced inputs and the inputs as sampled (polarity applied), as published.
    pub fn inputs(&self) -> (u32, u32) {
        (self.debounce.debounced(), self.debounce.raw())
    }

    /// The outputs the compare pulses hold on now.
    #[inline]
    pub fn pulse_outputs(&self) -> u32 {
        self.compare.iter().fold(0, |m, c| m | c.pulse_bits())
    }

    /// Publish the input words, and the compare and probe status blocks of tick `tick`.
    ///
    /// The blocks are written when a channel's status may have changed since the last write,
    /// and whole every [`REWRITE_TICKS`] ticks: the card is their only writer (the header's
    /// rules), so what it wrote stays, and the periodic rewrite bounds how long a stray write
    /// into them could (quiet.rs has the same reasoning for the group status blocks).
    pub fn publish<M: Mem>(&mut self, mem: &M, tick: u64) {
        mem.write32(layout::INPUTS, self.debounce.debounced());
        mem.write32(layout::INPUTS_RAW, self.debounce.raw());
        // The whole rewrite half a period from the groups' turns: no tick takes both.
        let due = tick
            .wrapping_add(REWRITE_TICKS / 2)
            .is_multiple_of(REWRITE_TICKS);
        if self.statuses_written && !due {
            return;
        }
        self.statuses_written = true;
        for (i, c) in self.compare.iter().enumerate() {
            layout::COMPARE_STATUS.at(i).write(mem, &c.status());
        }
        for (i, p) in self.probes.iter().enumerate() {
            layout::PROBE_STATUS.at(i).write(mem, &p.status());
        }
    }

    /// The configuration in force (what boot writes into `io_config`).
    pub fn config(&self) -> &IoConfig {
        self.debounce.config()
    }

    /// Layout 1.13: does an armed compare channel (not done) watch axis `axis`? Its period
    /// cannot change then (`MC_NACK_COMPARE_TURN`).
    pub fn compare_watches(&self, axis: usize) -> bool {
        self.compare.iter().any(|c| c.watching() == Some(axis))
    }

    /// A compare channel.
    pub fn compare(&self, ch: usize) -> Option<&Compare> {
        self.compare.get(ch)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Active low and debounced: a glitch of `d` samples never shows, a level held `d + 1`
    /// samples shows `d` ticks after it came, both ways.
    #[test]
    fn polarity_and_debounce_are_exact() {
        let mut d = Debounce::default();
        let mut cfg = IoConfig {
            polarity: 0b10,
            ..IoConfig::default()
        };
        cfg.debounce[0] = 3;
        d.apply(cfg);
        assert_eq!(
            d.debounced(),
            0b10,
            "input 1 is active low: idle pin reads active"
        );
        let pins = [1, 1, 1, 0, 1, 1, 1, 1, 1, 0, 0, 0, 0];
        let mut seen = Vec::new();
        for (k, &p) in pins.iter().enumerate() {
            let (_, e) = d.tick(p);
            if e.rising & 1 != 0 {
                seen.push((k, true));
            }
            if e.falling & 1 != 0 {
                seen.push((k, false));
            }
        }
        // The first three 1s are a glitch (3 samples); the run from sample 4 rises at 7; the
        // 0s from sample 9 fall at 12.
        assert_eq!(seen, [(7, true), (12, false)]);
        let (raw, e) = d.tick(0b10);
        assert_eq!(
            (raw.falling, e.falling),
            (0b10, 0b10),
            "no debounce on input 1"
        );
    }

    #[test]
    fn the_config_is_validated() {
        let mut b = raw::mc_io_config::default();
        assert!(IoConfig::validate(&b).is_ok());
        b.rise_events = 1 << 16;
        assert_eq!(IoConfig::validate(&b), Err(NackCode::IoConfig));
        b.rise_events = 0;
        b.debounce[15] = raw::MC_DEBOUNCE_MAX as u16 + 1;
        assert_eq!(IoConfig::validate(&b), Err(NackCode::IoConfig));
        b.debounce[15] = raw::MC_DEBOUNCE_MAX as u16;
        assert_eq!(IoConfig::validate(&b).unwrap().to_block(), b);
    }

    /// A channel number as the card decodes it (`firmware_proto::cmd`: a compare disarm's).
    fn channel(x: f64, n: usize) -> Result<usize, NackCode> {
        use firmware_proto::cmd::{Args, CompareDisarm};
        assert_eq!(n, COMPARE_CHANNELS);
        let mut a = [0.0; firmware_proto::CMD_ARGS];
        a[0] = x;
        CompareDisarm::decode(0, &a)
            .map(|d| d.channel as usize)
            .map_err(|e| e.nack)
    }

    #[test]
    fn channel_numbers_are_integers_in_range() {
        assert_eq!(channel(3.0, 4), Ok(3));
        assert_eq!(channel(4.0, 4), Err(NackCode::IoChannel));
        assert_eq!(channel(-0.5, 4), Err(NackCode::IoChannel));
        assert_eq!(channel(f64::NAN, 4), Err(NackCode::NotFinite));
    }
}
