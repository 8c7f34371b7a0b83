//! The card's scope (layout 1.8): on-card data gathering, like a PMAC's gather.
//!
//! [`Card::scope`] gives the card's [`Scope`]. [`Scope::configure`] chooses up to 16 channels
//! ([`Source`]: a [`Signal`] of an axis, a group or the card), a divider (a sample every n-th
//! servo tick; 1: every tick, up to 20 kHz), a [`ScopeTrigger`] with pre-trigger samples, and
//! one-shot or continuous capture ([`ScopeMode`]). [`Scope::arm`] starts it; [`Scope::read`]
//! drains the card's ring of samples (each with its servo tick) without waiting, and
//! [`Scope::capture`] runs a one-shot capture to its end. The ring holds 4096 samples (204.8 ms
//! at 20 kHz): a reader that falls behind loses samples, which the card counts
//! ([`ScopeStatus::lost`], and an [`EventKind::Scope`](crate::EventKind::Scope) event of code
//! [`ScopeEvent::Lost`]). Values are the card's own, exactly those of its status blocks at the
//! sample's tick: counts, seconds and volts (not user units), words as their f64.
//!
//! One reader at a time: each [`Scope`] keeps its place in the ring, published in the window,
//! so a new handle continues where the last one left.

use crate::card::Card;
use crate::error::{nack_reason, Error, Result, Target};
use crate::lock::lock;
use firmware_proto::cmd::ScopeCmd;
use firmware_proto::{
    check_config, layout, raw, Edge, ScopeConfig, ScopeConsumer, ScopeMode, ScopeSample,
    ScopeState, Source, SCOPE_CHANNELS, SCOPE_RING,
};
use std::sync::Mutex;
use std::time::{Duration, Instant};

pub use firmware_proto::{
    ScopeEvent, Signal, SignalOwner, SCOPE_DIVIDER_MAX, SCOPE_PRETRIGGER_MAX, SCOPE_RING_LEN,
};

/// When a capture starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ScopeTrigger {
    /// At the first sample after the arm.
    Immediate,
    /// At the first sample after [`Scope::trigger`].
    Command,
    /// When channel `channel` crosses `level` (in the channel's unit) between two samples.
    Level {
        /// The channel (index into the settings' channels).
        channel: usize,
        /// The level.
        level: f64,
        /// Which way.
        edge: Edge,
    },
    /// At an edge of debounced digital input `input` between two samples.
    Input {
        /// The input, 0..[`crate::INPUTS`].
        input: usize,
        /// Rising: becomes active.
        edge: Edge,
    },
    /// When a safety fault of any axis appears.
    Fault,
}

/// What the scope samples and when.
#[derive(Debug, Clone, PartialEq)]
pub struct ScopeSettings {
    /// The channels, 1..=16.
    pub channels: Vec<Source>,
    /// A sample every `divider` servo ticks, 1..=65536.
    pub divider: u32,
    /// When the capture starts.
    pub trigger: ScopeTrigger,
    /// Samples kept from before the trigger, 0..=1024.
    pub pre_trigger: u32,
    /// One-shot or continuous.
    pub mode: ScopeMode,
    /// One-shot: samples from the trigger sample on (≥ 1).
    pub post_trigger: u32,
}

impl ScopeSettings {
    /// A one-shot capture of `channels`, every tick, `post_trigger` samples from an immediate
    /// trigger.
    pub fn new(channels: &[Source], post_trigger: u32) -> Self {
        Self {
            channels: channels.to_vec(),
            divider: 1,
            trigger: ScopeTrigger::Immediate,
            pre_trigger: 0,
            mode: ScopeMode::OneShot,
            post_trigger,
        }
    }

    /// The register map's block (`mc_scope_config`), unchecked.
    pub fn to_block(&self) -> ScopeConfig {
        let mut b = ScopeConfig {
            n_channels: self.channels.len().min(u32::MAX as usize) as u32,
            divider: self.divider,
            mode: self.mode as u32,
            pre_trigger: self.pre_trigger,
            post_trigger: self.post_trigger,
            ..Default::default()
        };
        for (w, s) in b.source.iter_mut().zip(&self.channels) {
            *w = s.to_raw();
        }
        let (trigger, edge) = match self.trigger {
            ScopeTrigger::Immediate => (raw::MC_SCOPE_TRIG_IMMEDIATE, Edge::Rising),
            ScopeTrigger::Command => (raw::MC_SCOPE_TRIG_COMMAND, Edge::Rising),
            ScopeTrigger::Fault => (raw::MC_SCOPE_TRIG_FAULT, Edge::Rising),
            ScopeTrigger::Level {
                channel,
                level,
                edge,
            } => {
                b.trigger_channel = channel.min(u32::MAX as usize) as u32;
                b.level = level;
                (raw::MC_SCOPE_TRIG_LEVEL, edge)
            }
            ScopeTrigger::Input { input, edge } => {
                b.trigger_input = input.min(u32::MAX as usize) as u32;
                (raw::MC_SCOPE_TRIG_INPUT, edge)
            }
        };
        b.trigger = trigger;
        b.edge = edge as u32;
        b
    }
}

/// The scope's state as the card publishes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScopeStatus {
    /// Idle, waiting for the trigger, capturing, or done.
    pub state: ScopeState,
    /// The seq of the arm.
    pub arm_seq: u32,
    /// Channels per sample of the capture.
    pub channels: usize,
    /// Its divider.
    pub divider: u32,
    /// The trigger sample's tick (0: not triggered).
    pub trigger_tick: u64,
    /// Samples the card put in the ring since the arm.
    pub samples: u64,
    /// Samples lost since the arm (the ring was full).
    pub lost: u64,
    /// The pre-trigger samples the capture took (first in the ring): the configuration's
    /// `pre_trigger`, or fewer when the trigger came before that many samples were taken
    /// since the arm (0 until the trigger).
    pub pre_trigger: u32,
}

/// A finished one-shot capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Capture {
    /// The samples in order (pre-trigger samples first), `channels` values each.
    pub samples: Vec<ScopeSample>,
    /// The channels.
    pub channels: usize,
    /// The trigger sample's tick.
    pub trigger_tick: u64,
    /// Samples lost (the ring was full).
    pub lost: u64,
    /// The pre-trigger samples at the start of `samples` (fewer than asked when the trigger
    /// came early: see [`ScopeStatus::pre_trigger`]).
    pub pre_trigger: u32,
}

/// The card's scope ([`crate::Card::scope`]): channels, a trigger and pre-trigger samples,
/// captured on the card at the servo rate.
pub struct Scope {
    card: Card,
    ring: Mutex<ScopeConsumer<crate::card::Window>>,
}

impl Card {
    /// The card's scope.
    pub fn scope(&self) -> Scope {
        Scope {
            card: self.clone(),
            ring: Mutex::new(ScopeConsumer::attach(self.window().clone(), SCOPE_RING)),
        }
    }
}

impl Scope {
    /// Check `settings` (as the card will) and have the card take them. Refused while armed.
    pub fn configure(&self, settings: &ScopeSettings) -> Result<()> {
        if settings.channels.len() > SCOPE_CHANNELS {
            return Err(refused(firmware_proto::NackCode::ScopeChannels));
        }
        self.configure_block(&settings.to_block())
    }

    /// [`Scope::configure`] with the register map's block (the C ABI's `mc_scope_settings`).
    pub fn configure_block(&self, block: &ScopeConfig) -> Result<()> {
        let block = *block;
        check_config(&block, self.card.info().axes).map_err(refused)?;
        self.card.apply_block(
            layout::SCOPE_CONFIG,
            |b| *b = block,
            ScopeCmd::Configure.command(),
            "scope_configure",
            Target::Card,
        )
    }

    /// Start sampling and wait for the trigger. Samples left in the ring from before are
    /// dropped first. Returns the arm's seq (the scope events carry it).
    pub fn arm(&self) -> Result<u32> {
        self.card.inner().link.check()?;
        lock(&self.ring).resync();
        self.card
            .execute_seq(ScopeCmd::Arm.command(), "scope_arm", Target::Card)
    }

    /// Trigger the waiting scope at its next sample (any trigger kind).
    pub fn trigger(&self) -> Result<()> {
        self.card
            .execute(ScopeCmd::Trigger.command(), "scope_trigger", Target::Card)
    }

    /// Stop sampling (a continuous capture ends here). Samples in the ring stay to be read.
    pub fn stop(&self) -> Result<()> {
        self.card
            .execute(ScopeCmd::Stop.command(), "scope_stop", Target::Card)
    }

    /// The card's scope status.
    pub fn status(&self) -> Result<ScopeStatus> {
        self.card.inner().link.check()?;
        let b = layout::SCOPE_STATUS.read(self.card.window());
        Ok(ScopeStatus {
            state: ScopeState::from_raw(b.state)
                .ok_or_else(|| Error::Protocol(format!("scope state {}", b.state)))?,
            arm_seq: b.arm_seq,
            channels: (b.n_channels as usize).min(SCOPE_CHANNELS),
            divider: b.divider,
            trigger_tick: b.trigger_tick,
            samples: b.samples,
            lost: b.lost,
            pre_trigger: b.pre_captured,
        })
    }

    /// Wait until the one-shot capture armed last is done (or the scope was stopped), and
    /// return its status; `Timeout` (emulated time on a stepped card, which is stepped) when it
    /// is still waiting for its trigger or capturing, `ScopeState` when the scope is not armed
    /// (never was, or a continuous capture, which never ends: stop it). Reads nothing from
    /// the ring: a capture longer than the ring (`SCOPE_RING_LEN` samples) loses what does not
    /// fit unless another thread reads meanwhile ([`Scope::capture`] drains as it waits).
    pub fn wait_done(&self, timeout: Duration) -> Result<ScopeStatus> {
        let start = Instant::now();
        let rate = self.card.info().servo_rate_hz.max(1) as f64;
        let mut stepped_s = 0.0;
        let continuous =
            layout::SCOPE_CONFIG.read(self.card.window()).mode == ScopeMode::Continuous as u32;
        loop {
            let st = self.status()?;
            match st.state {
                ScopeState::Done => return Ok(st),
                ScopeState::Idle if st.arm_seq != 0 => return Ok(st),
                ScopeState::Idle => return Err(refused(firmware_proto::NackCode::ScopeState)),
                _ if continuous => return Err(refused(firmware_proto::NackCode::ScopeState)),
                _ => {}
            }
            let elapsed = if stepped_s > 0.0 {
                Duration::from_secs_f64(stepped_s)
            } else {
                start.elapsed()
            };
            if elapsed > timeout {
                return Err(Error::Timeout(timeout));
            }
            stepped_s += self.idle(rate);
        }
    }

    /// Samples waiting in the ring.
    pub fn pending(&self) -> Result<usize> {
        lock(&self.ring)
            .pending()
            .map(|n| n as usize)
            .map_err(|e| Error::Protocol(format!("scope ring: {e}")))
    }

    /// Append every sample waiting in the ring to `out`, without waiting; how many.
    pub fn read(&self, out: &mut Vec<ScopeSample>) -> Result<usize> {
        self.read_max(out, usize::MAX)
    }

    /// [`Scope::read`], at most `max` samples (the rest stay in the ring).
    pub fn read_max(&self, out: &mut Vec<ScopeSample>, max: usize) -> Result<usize> {
        self.card.inner().link.check()?;
        let mut ring = lock(&self.ring);
        let n = ring
            .pending()
            .map_err(|e| Error::Protocol(format!("scope ring: {e}")))?
            .min(max.min(u32::MAX as usize) as u32);
        out.reserve(n as usize);
        for _ in 0..n {
            match ring.pop::<ScopeSample>() {
                Ok(Some(s)) => out.push(s),
                Ok(None) => break,
                Err(e) => return Err(Error::Protocol(format!("scope ring: {e}"))),
            }
        }
        Ok(n as usize)
    }

    /// Configure, arm and run a one-shot capture to its end, draining the ring meanwhile;
    /// `timeout` bounds the whole capture (emulated time on a stepped card, which is stepped).
    /// While it waits for the trigger, `while_armed` runs once (to start the motion to be
    /// captured, or to call [`Scope::trigger`]).
    pub fn capture(
        &self,
        settings: &ScopeSettings,
        timeout: Duration,
        while_armed: impl FnOnce(&Scope) -> Result<()>,
    ) -> Result<Capture> {
        if settings.mode != ScopeMode::OneShot {
            return Err(refused(firmware_proto::NackCode::ScopeTrigger));
        }
        self.configure(settings)?;
        let seq = self.arm()?;
        while_armed(self)?;
        let mut samples = Vec::new();
        let start = Instant::now();
        let rate = self.card.info().servo_rate_hz.max(1) as f64;
        let mut stepped_s = 0.0;
        loop {
            self.read(&mut samples)?;
            let st = self.status()?;
            if st.arm_seq != seq {
                return Err(Error::Protocol("the scope was armed again".into()));
            }
            if st.state != ScopeState::Waiting && st.state != ScopeState::Capturing {
                // Done (or stopped): what is in the ring now is the rest.
                self.read(&mut samples)?;
                return Ok(Capture {
                    samples,
                    channels: settings.channels.len(),
                    trigger_tick: st.trigger_tick,
                    lost: st.lost,
                    pre_trigger: st.pre_trigger,
                });
            }
            let elapsed = if stepped_s > 0.0 {
                Duration::from_secs_f64(stepped_s)
            } else {
                start.elapsed()
            };
            if elapsed > timeout {
                return Err(Error::Timeout(timeout));
            }
            stepped_s += self.idle(rate);
        }
    }

    /// Let the card run a little: a stepped card is stepped (returns the emulated seconds),
    /// a real one is given a millisecond.
    fn idle(&self, rate: f64) -> f64 {
        #[cfg(feature = "emulator")]
        if let Some(sim) = self.card.sim() {
            const STEP: u64 = 256;
            sim.step(STEP);
            return STEP as f64 / rate;
        }
        let _ = rate;
        std::thread::sleep(Duration::from_millis(1));
        0.0
    }
}

fn refused(code: firmware_proto::NackCode) -> Error {
    Error::Refused {
        command: "scope_configure",
        target: Target::Card,
        code,
        reason: nack_reason(code),
    }
}
