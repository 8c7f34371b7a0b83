//! The scope (layout 1.8): on-card data gathering. What host and card share of it: the signal
//! ids, the configuration's check (the card refuses what the SDK would), the trigger's edge
//! rule, and the scope ring of samples.
//!
//! The rules (what a sample is, when the trigger fires, what is lost) are in the header's
//! comment before `MC_OP_SCOPE_CONFIGURE`. The scope ring is one of this map's rings
//! ([`crate::ring`]): the card produces, the host consumes, with free-running `u32` indices
//! on their own 64-byte lines; a sample that finds it full is counted, never waited for.

use crate::raw;
use crate::ring::{Consumer, Entry, Producer, RingLayout};
use crate::wire::NackCode;

// The scope's code enums, generated from the header's defines (`cargo xtask codegen`).
pub use crate::codes::{Edge, ScopeEvent, ScopeMode, ScopeState, Signal, Trigger};

/// Channels per sample.
pub const SCOPE_CHANNELS: usize = raw::MC_SCOPE_CHANNELS as usize;
/// Samples in the scope ring.
pub const SCOPE_RING_LEN: usize = raw::MC_SCOPE_RING_LEN as usize;
/// Samples the card keeps from before the trigger, at most.
pub const SCOPE_PRETRIGGER_MAX: usize = raw::MC_SCOPE_PRETRIGGER_MAX as usize;
/// The largest divider.
pub const SCOPE_DIVIDER_MAX: u32 = raw::MC_SCOPE_DIVIDER_MAX;
/// Words per scope ring entry: the tick and the channels.
pub const SCOPE_WORDS: usize = 1 + SCOPE_CHANNELS;

/// The scope's configuration block (`mc_scope_config`).
pub type ScopeConfig = raw::mc_scope_config;

/// The scope ring: card produces, host consumes.
pub const SCOPE_RING: RingLayout = RingLayout {
    head: crate::layout::SCOPE_HEAD,
    tail: crate::layout::SCOPE_TAIL,
    entries: crate::layout::SCOPE_RING,
    entry_bytes: crate::layout::SCOPE_SAMPLE_BYTES,
    len: raw::MC_SCOPE_RING_LEN,
};

/// Card side of the scope ring.
pub type ScopeProducer<M> = Producer<M, SCOPE_WORDS>;
/// Host side of the scope ring.
pub type ScopeConsumer<M> = Consumer<M, SCOPE_WORDS>;

/// One sample: the servo tick it was taken at and each channel's value (channels beyond the
/// configured count are 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScopeSample {
    /// The servo tick.
    pub tick: u64,
    /// Channel k's value.
    pub value: [f64; SCOPE_CHANNELS],
}

impl Default for ScopeSample {
    fn default() -> Self {
        Self {
            tick: 0,
            value: [0.0; SCOPE_CHANNELS],
        }
    }
}

impl Entry<SCOPE_WORDS> for ScopeSample {
    fn encode(&self) -> [u64; SCOPE_WORDS] {
        let mut w = [0u64; SCOPE_WORDS];
        w[0] = self.tick;
        for (o, v) in w[1..].iter_mut().zip(&self.value) {
            *o = v.to_bits();
        }
        w
    }
    fn decode(words: &[u64; SCOPE_WORDS]) -> Self {
        let mut s = ScopeSample {
            tick: words[0],
            ..Default::default()
        };
        for (v, w) in s.value.iter_mut().zip(&words[1..]) {
            *v = f64::from_bits(*w);
        }
        s
    }
}

/// What a signal's index names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SignalOwner {
    /// An axis.
    Axis,
    /// An axes group.
    Group,
    /// The card (index 0).
    Card,
}

impl Signal {
    /// Whose signal it is.
    pub fn owner(self) -> SignalOwner {
        match self as u32 {
            s if s < raw::MC_SIG_PATH_SPEED => SignalOwner::Axis,
            s if s < raw::MC_SIG_INPUTS => SignalOwner::Group,
            _ => SignalOwner::Card,
        }
    }
}

/// A channel's source: a signal of an axis, a group or the card.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Source {
    /// The signal.
    pub signal: Signal,
    /// The axis or group (0 for card signals).
    pub index: u16,
}

impl Source {
    /// An axis signal.
    pub fn axis(signal: Signal, axis: usize) -> Self {
        Self {
            signal,
            index: axis as u16,
        }
    }
    /// The word in `scope_config.source[]` (`MC_SCOPE_SOURCE`).
    pub fn to_raw(self) -> u32 {
        self.signal as u32 | (self.index as u32) << 16
    }
    /// Decode a `scope_config.source[]` word, or `None` for an unknown signal.
    pub fn from_raw(w: u32) -> Option<Self> {
        Some(Self {
            signal: Signal::from_raw(w & 0xFFFF)?,
            index: (w >> 16) as u16,
        })
    }
    /// Is it a signal this card has (`num_axes` axes)?
    pub fn exists(self, num_axes: usize) -> bool {
        let i = self.index as usize;
        match self.signal.owner() {
            SignalOwner::Axis => i < num_axes,
            SignalOwner::Group => i < crate::MAX_GROUPS,
            SignalOwner::Card => i == 0,
        }
    }
}

impl Edge {
    /// Did a value going from `prev` to `cur` cross `level` this way? Rising: `prev < level
    /// <= cur`; falling: `prev > level >= cur`. A NaN crosses nothing.
    pub fn crossed(self, prev: f64, cur: f64, level: f64) -> bool {
        let up = prev < level && cur >= level;
        let down = prev > level && cur <= level;
        match self {
            Edge::Rising => up,
            Edge::Falling => down,
            Edge::Either => up || down,
        }
    }
}

/// Check a scope configuration for a card of `num_axes` axes: what the card refuses, with the
/// nack it gives. The channel count first, then each source, the divider, the mode and
/// trigger, the pre-trigger count.
pub fn check_config(c: &ScopeConfig, num_axes: usize) -> Result<(), NackCode> {
    let n = c.n_channels as usize;
    if n == 0 || n > SCOPE_CHANNELS {
        return Err(NackCode::ScopeChannels);
    }
    for &w in &c.source[..n] {
        match Source::from_raw(w) {
            Some(s) if s.exists(num_axes) => {}
            _ => return Err(NackCode::ScopeSignal),
        }
    }
    if c.divider == 0 || c.divider > SCOPE_DIVIDER_MAX {
        return Err(NackCode::ScopeDivider);
    }
    let mode = ScopeMode::from_raw(c.mode).ok_or(NackCode::ScopeTrigger)?;
    let trigger = Trigger::from_raw(c.trigger).ok_or(NackCode::ScopeTrigger)?;
    let edge_ok = Edge::from_raw(c.edge).is_some();
    let trigger_ok = match trigger {
        Trigger::Immediate | Trigger::Command | Trigger::Fault => true,
        Trigger::Level => edge_ok && (c.trigger_channel as usize) < n && c.level.is_finite(),
        Trigger::Input => edge_ok && (c.trigger_input as usize) < crate::INPUTS,
    };
    if !trigger_ok || (mode == ScopeMode::OneShot && c.post_trigger == 0) {
        return Err(NackCode::ScopeTrigger);
    }
    if c.pre_trigger as usize > SCOPE_PRETRIGGER_MAX {
        return Err(NackCode::ScopePretrigger);
    }
    Ok(())
}

#[cfg(all(test, not(loom)))]
mod tests {
    use super::*;

    fn good() -> ScopeConfig {
        let mut c = ScopeConfig {
            n_channels: 2,
            divider: 1,
            post_trigger: 10,
            ..Default::default()
        };
        c.source[0] = Source::axis(Signal::CmdPos, 0).to_raw();
        c.source[1] = Source {
            signal: Signal::PathSpeed,
            index: 3,
        }
        .to_raw();
        c
    }

    #[test]
    fn every_refusal_has_its_nack() {
        assert_eq!(check_config(&good(), 1), Ok(()));
        type Change = fn(&mut ScopeConfig);
        let cases: [(Change, NackCode); 13] = [
            (|c| c.n_channels = 0, NackCode::ScopeChannels),
            (|c| c.n_channels = 17, NackCode::ScopeChannels),
            (|c| c.source[0] = 999, NackCode::ScopeSignal),
            (
                |c| c.source[0] = raw::MC_SIG_FERR | 1 << 16,
                NackCode::ScopeSignal,
            ),
            (
                |c| c.source[1] = raw::MC_SIG_PATH_SPEED | 4 << 16,
                NackCode::ScopeSignal,
            ),
            (
                |c| c.source[1] = raw::MC_SIG_INPUTS | 1 << 16,
                NackCode::ScopeSignal,
            ),
            (|c| c.divider = 0, NackCode::ScopeDivider),
            (
                |c| c.divider = SCOPE_DIVIDER_MAX + 1,
                NackCode::ScopeDivider,
            ),
            (|c| c.mode = 2, NackCode::ScopeTrigger),
            (|c| c.post_trigger = 0, NackCode::ScopeTrigger),
            (
                |c| {
                    c.trigger = raw::MC_SCOPE_TRIG_LEVEL;
                    c.level = f64::NAN;
                },
                NackCode::ScopeTrigger,
            ),
            (
                |c| {
                    c.trigger = raw::MC_SCOPE_TRIG_INPUT;
                    c.trigger_input = crate::INPUTS as u32;
                },
                NackCode::ScopeTrigger,
            ),
            (
                |c| c.pre_trigger = SCOPE_PRETRIGGER_MAX as u32 + 1,
                NackCode::ScopePretrigger,
            ),
        ];
        for (k, (change, nack)) in cases.iter().enumerate() {
            let mut c = good();
            change(&mut c);
            assert_eq!(check_config(&c, 1), Err(*nack), "case {k}");
        }
        // Continuous needs no post-trigger count; a level trigger on channel 1 of 2 is fine.
        let mut c = good();
        c.mode = raw::MC_SCOPE_CONTINUOUS;
        c.post_trigger = 0;
        c.trigger = raw::MC_SCOPE_TRIG_LEVEL;
        c.trigger_channel = 1;
        c.edge = raw::MC_SCOPE_EITHER;
        assert_eq!(check_config(&c, 1), Ok(()));
        c.trigger_channel = 2;
        assert_eq!(check_config(&c, 1), Err(NackCode::ScopeTrigger));
    }

    #[test]
    fn edges_cross_as_documented() {
        assert!(Edge::Rising.crossed(-1.0, 0.0, 0.0));
        assert!(!Edge::Rising.crossed(0.0, 1.0, 0.0)); // already at the level
        assert!(Edge::Falling.crossed(1.0, 0.0, 0.0));
        assert!(!Edge::Falling.crossed(-1.0, 0.0, 0.0));
        assert!(Edge::Either.crossed(1.0, -1.0, 0.0) && Edge::Either.crossed(-1.0, 1.0, 0.0));
        assert!(!Edge::Either.crossed(f64::NAN, 1.0, 0.0));
    }

    #[test]
    fn samples_round_trip_bit_for_bit() {
        let mut s = ScopeSample {
            tick: u64::MAX - 3,
            ..Default::default()
        };
        s.value[0] = -0.0;
        s.value[15] = f64::from_bits(0x7FF8_0000_0000_1234);
        let back = ScopeSample::decode(&s.encode());
        assert_eq!(back.tick, s.tick);
        for (a, b) in back.value.iter().zip(&s.value) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        for &sig in Signal::ALL {
            let src = Source {
                signal: sig,
                index: 7,
            };
            assert_eq!(Source::from_raw(src.to_raw()), Some(src));
        }
    }
}
