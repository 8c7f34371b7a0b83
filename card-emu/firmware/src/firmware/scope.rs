//! The scope (layout 1.8): on-card data gathering, like a PMAC's gather buffer.
//!
//! Every `divider`-th tick after the arm, the firmware takes a sample of the configured channels
//! (the values it has just published in the status blocks of that tick) and hands it to
//! [`Scope::on_sample`]. Waiting for the trigger, samples go into a fixed pre-trigger history
//! (`SCOPE_PRETRIGGER_MAX` samples, made with the scope by the first `MC_OP_SCOPE_CONFIGURE`,
//! in the command manager); at the trigger the history goes to the scope ring oldest first,
//! then the trigger sample and those after it, until a one-shot capture has its
//! `post_trigger` samples or a continuous one is stopped. The ring never blocks the card: a
//! sample that does not fit is counted lost. The rules are the header's (`MC_OP_SCOPE_*`);
//! the configuration's check is `firmware_proto::check_config`, the SDK's too.
//!
//! Plain data: the window and the ring are the caller's (`push`), so the trigger, history and
//! loss rules are tested here with numbers.

use crate::ram::FixedVec;
use firmware_proto::{
    check_config, raw, Edge, NackCode, ScopeConfig, ScopeMode, ScopeSample, ScopeState, Source,
    Trigger, SCOPE_CHANNELS, SCOPE_PRETRIGGER_MAX,
};

/// What one sample did, for the events of the tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SampleReport {
    /// The trigger fired at this sample (its tick).
    pub triggered: Option<u64>,
    /// A sample found the ring full after one that went in: the lost count.
    pub lost: Option<u64>,
    /// A one-shot capture ended: its samples (in the ring or lost).
    pub done: Option<u64>,
}

/// The scope.
#[derive(Debug, Clone)]
pub struct Scope {
    config: ScopeConfig,
    sources: [Source; SCOPE_CHANNELS],
    configured: bool,
    state: ScopeState,
    arm_seq: u32,
    arm_tick: u64,
    /// A trigger command waits for the next sample.
    forced: bool,
    /// The pre-trigger history: a ring of `pre_trigger` slots, `hist_len` of them filled,
    /// the next one written at `hist_next`.
    history: FixedVec<ScopeSample, SCOPE_PRETRIGGER_MAX>,
    hist_next: usize,
    hist_len: usize,
    /// The previous sample's trigger inputs: the level channel's value, the inputs, the
    /// safety faults (none before the first sample of an arm).
    prev: Option<(f64, u32, u32)>,
    trigger_tick: u64,
    /// Samples since the arm that went into the ring, and that were lost.
    samples: u64,
    lost: u64,
    /// Samples from the trigger on.
    post: u64,
    /// The pre-trigger samples of the capture (the history at the trigger).
    pre_captured: u32,
    /// The last sample was lost (a run of losses posts one event).
    losing: bool,
}

impl Default for Scope {
    fn default() -> Self {
        Self::new()
    }
}

impl Scope {
    /// An idle, unconfigured scope with its history made.
    pub fn new() -> Self {
        Self {
            config: ScopeConfig::default(),
            sources: [Source::axis(firmware_proto::Signal::CmdPos, 0); SCOPE_CHANNELS],
            configured: false,
            state: ScopeState::Idle,
            arm_seq: 0,
            arm_tick: 0,
            forced: false,
            history: FixedVec::from_elem(ScopeSample::default(), SCOPE_PRETRIGGER_MAX),
            hist_next: 0,
            hist_len: 0,
            prev: None,
            trigger_tick: 0,
            samples: 0,
            lost: 0,
            post: 0,
            pre_captured: 0,
            losing: false,
        }
    }

    fn armed(&self) -> bool {
        matches!(self.state, ScopeState::Waiting | ScopeState::Capturing)
    }

    /// `MC_OP_SCOPE_CONFIGURE`: check the block and take it (nothing changes if refused).
    pub fn configure(&mut self, c: &ScopeConfig, num_axes: usize) -> Result<(), NackCode> {
        if self.armed() {
            return Err(NackCode::ScopeState);
        }
        check_config(c, num_axes)?;
        for (s, &w) in self
            .sources
            .iter_mut()
            .zip(&c.source[..c.n_channels as usize])
        {
            *s = Source::from_raw(w).ok_or(NackCode::ScopeSignal)?;
        }
        self.config = *c;
        self.configured = true;
        Ok(())
    }

    /// `MC_OP_SCOPE_ARM` at `tick` (the last tick run): sample from the next `divider`-th tick.
    pub fn arm(&mut self, seq: u32, tick: u64) -> Result<(), NackCode> {
        if self.armed() || !self.configured {
            return Err(NackCode::ScopeState);
        }
        self.state = ScopeState::Waiting;
        self.arm_seq = seq;
        self.arm_tick = tick;
        self.forced = false;
        self.hist_next = 0;
        self.hist_len = 0;
        self.prev = None;
        self.trigger_tick = 0;
        self.samples = 0;
        self.lost = 0;
        self.post = 0;
        self.pre_captured = 0;
        self.losing = false;
        Ok(())
    }

    /// `MC_OP_SCOPE_TRIGGER`: trigger at the next sample.
    pub fn force_trigger(&mut self) -> Result<(), NackCode> {
        if self.state != ScopeState::Waiting {
            return Err(NackCode::ScopeState);
        }
        self.forced = true;
        Ok(())
    }

    /// `MC_OP_SCOPE_STOP`.
    pub fn stop(&mut self) -> Result<(), NackCode> {
        if self.state == ScopeState::Idle {
            return Err(NackCode::ScopeState);
        }
        self.state = ScopeState::Idle;
        Ok(())
    }

    /// Does tick `tick` take a sample?
    pub fn samples_at(&self, tick: u64) -> bool {
        self.armed()
            && tick > self.arm_tick
            && (tick - self.arm_tick).is_multiple_of(self.config.divider as u64)
    }

    /// The channels' sources.
    pub fn sources(&self) -> &[Source] {
        &self.sources[..self.config.n_channels as usize]
    }

    /// Does the trigger need the safety faults (else the caller may pass 0)?
    pub fn wants_faults(&self) -> bool {
        self.state == ScopeState::Waiting && self.config.trigger == raw::MC_SCOPE_TRIG_FAULT
    }

    /// The status block.
    pub fn status(&self) -> raw::mc_scope_status {
        raw::mc_scope_status {
            state: self.state as u32,
            arm_seq: self.arm_seq,
            n_channels: self.config.n_channels,
            divider: self.config.divider,
            trigger_tick: self.trigger_tick,
            samples: self.samples,
            lost: self.lost,
            pre_captured: self.pre_captured,
            ..Default::default()
        }
    }

    /// The seq of the arm (the scope events carry it).
    pub fn arm_seq(&self) -> u32 {
        self.arm_seq
    }

    /// One sample (taken when [`Scope::samples_at`] said so). `inputs` is the debounced input
    /// word, `faults` the OR of the axes' safety fault bits; `push` puts a sample in the ring
    /// and says whether it fit.
    pub fn on_sample(
        &mut self,
        s: &ScopeSample,
        inputs: u32,
        faults: u32,
        push: &mut impl FnMut(&ScopeSample) -> bool,
    ) -> SampleReport {
        let mut report = SampleReport::default();
        match self.state {
            ScopeState::Waiting => {
                if !self.fires(s, inputs, faults) {
                    self.remember(s);
                    return report;
                }
                self.state = ScopeState::Capturing;
                self.trigger_tick = s.tick;
                report.triggered = Some(s.tick);
                let pre = self.config.pre_trigger as usize;
                self.pre_captured = self.hist_len as u32;
                for k in 0..self.hist_len {
                    let slot = (self.hist_next + pre - self.hist_len + k) % pre;
                    let h = self.history[slot];
                    self.emit(&h, push, &mut report);
                }
                self.hist_len = 0;
                self.emit(s, push, &mut report);
            }
            ScopeState::Capturing => self.emit(s, push, &mut report),
            ScopeState::Idle | ScopeState::Done => return report,
        }
        self.post += 1;
        if self.config.mode == ScopeMode::OneShot as u32
            && self.post >= self.config.post_trigger as u64
        {
            self.state = ScopeState::Done;
            report.done = Some(self.samples + self.lost);
        }
        report
    }

    /// Does the trigger fire at sample `s`? Updates the previous sample's inputs.
    fn fires(&mut self, s: &ScopeSample, inputs: u32, faults: u32) -> bool {
        let c = &self.config;
        let ch = (c.trigger_channel as usize).min(SCOPE_CHANNELS - 1);
        let now = (s.value[ch], inputs, faults);
        let edge = Edge::from_raw(c.edge).unwrap_or(Edge::Either);
        let fired = self.forced
            || match (Trigger::from_raw(c.trigger), self.prev) {
                (Some(Trigger::Immediate), _) => true,
                (Some(Trigger::Level), Some((v, _, _))) => edge.crossed(v, now.0, c.level),
                (Some(Trigger::Input), Some((_, was, _))) => {
                    let bit = 1u32 << (c.trigger_input % 32);
                    let (was, is) = ((was & bit != 0) as u8, (inputs & bit != 0) as u8);
                    edge.crossed(was as f64, is as f64, 0.5)
                }
                (Some(Trigger::Fault), Some((_, _, was))) => faults & !was != 0,
                _ => false,
            };
        self.prev = Some(now);
        self.forced = false;
        fired
    }

    fn remember(&mut self, s: &ScopeSample) {
        let pre = self.config.pre_trigger as usize;
        if pre == 0 {
            return;
        }
        self.history[self.hist_next] = *s;
        self.hist_next = (self.hist_next + 1) % pre;
        self.hist_len = (self.hist_len + 1).min(pre);
    }

    fn emit(
        &mut self,
        s: &ScopeSample,
        push: &mut impl FnMut(&ScopeSample) -> bool,
        report: &mut SampleReport,
    ) {
        if push(s) {
            self.samples += 1;
            self.losing = false;
        } else {
            self.lost += 1;
            if !self.losing {
                report.lost = Some(self.lost);
            }
            self.losing = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::Signal;

    fn config(trigger: u32, mode: u32, pre: u32, post: u32) -> ScopeConfig {
        let mut c = ScopeConfig {
            n_channels: 2,
            divider: 1,
            mode,
            trigger,
            pre_trigger: pre,
            post_trigger: post,
            ..Default::default()
        };
        c.source[0] = Source::axis(Signal::CmdPos, 0).to_raw();
        c.source[1] = Source::axis(Signal::ActPos, 0).to_raw();
        c
    }

    fn sample(tick: u64, v: f64) -> ScopeSample {
        let mut s = ScopeSample {
            tick,
            ..Default::default()
        };
        s.value[0] = v;
        s.value[1] = -v;
        s
    }

    /// Run ticks 1..=n with channel 0 = `value(tick)`, into a ring of `room` samples.
    fn run(
        sc: &mut Scope,
        n: u64,
        room: usize,
        value: impl Fn(u64) -> f64,
        inputs: impl Fn(u64) -> u32,
    ) -> (Vec<ScopeSample>, Vec<SampleReport>) {
        let mut ring = Vec::new();
        let mut reports = Vec::new();
        for t in 1..=n {
            if sc.samples_at(t) {
                let mut push = |s: &ScopeSample| {
                    let fits = ring.len() < room;
                    if fits {
                        ring.push(*s);
                    }
                    fits
                };
                let r = sc.on_sample(&sample(t, value(t)), inputs(t), 0, &mut push);
                if r != SampleReport::default() {
                    reports.push(r);
                }
            }
        }
        (ring, reports)
    }

    #[test]
    fn level_trigger_keeps_its_pre_trigger_samples() {
        let mut sc = Scope::new();
        let mut c = config(raw::MC_SCOPE_TRIG_LEVEL, raw::MC_SCOPE_ONE_SHOT, 5, 4);
        c.level = 10.0;
        c.edge = raw::MC_SCOPE_RISING;
        sc.configure(&c, 1).unwrap();
        sc.arm(7, 0).unwrap();
        let (ring, reports) = run(&mut sc, 40, 100, |t| t as f64, |_| 0);
        let ticks: Vec<u64> = ring.iter().map(|s| s.tick).collect();
        assert_eq!(ticks, (5..=13).collect::<Vec<_>>()); // 5 before tick 10, 4 from it
        assert_eq!(reports[0].triggered, Some(10));
        assert_eq!(reports[0].done, None);
        assert_eq!(reports[1].done, Some(9));
        assert_eq!(sc.status().state, raw::MC_SCOPE_DONE);
        assert_eq!(sc.status().trigger_tick, 10);
        assert_eq!(ring[0].value[1], -5.0);
    }

    #[test]
    fn falling_level_and_either() {
        for (edge, want) in [
            (raw::MC_SCOPE_FALLING, 37),
            (raw::MC_SCOPE_EITHER, 4),
            (raw::MC_SCOPE_RISING, 4),
        ] {
            let mut sc = Scope::new();
            let mut c = config(raw::MC_SCOPE_TRIG_LEVEL, raw::MC_SCOPE_ONE_SHOT, 0, 1);
            c.level = 3.5;
            c.edge = edge;
            sc.configure(&c, 1).unwrap();
            sc.arm(1, 0).unwrap();
            // Up to 20 and down again.
            let (ring, _) = run(&mut sc, 40, 100, |t| 20.0 - (t as f64 - 20.0).abs(), |_| 0);
            assert_eq!(ring.len(), 1);
            assert_eq!(ring[0].tick, want, "edge {edge}");
        }
    }

    #[test]
    fn divider_and_fewer_pre_trigger_samples_than_asked() {
        let mut sc = Scope::new();
        let c = ScopeConfig {
            divider: 3,
            ..config(raw::MC_SCOPE_TRIG_INPUT, raw::MC_SCOPE_ONE_SHOT, 100, 3)
        };
        sc.configure(&c, 1).unwrap();
        sc.arm(1, 10).unwrap();
        // Input 0 rises at tick 20: seen at the sample of tick 22.
        let (ring, _) = run(&mut sc, 60, 100, |t| t as f64, |t| (t >= 20) as u32);
        let ticks: Vec<u64> = ring.iter().map(|s| s.tick).collect();
        assert_eq!(ticks, vec![13, 16, 19, 22, 25, 28]);
    }

    #[test]
    fn command_trigger_waits_for_the_command_and_continuous_runs_until_stopped() {
        let mut sc = Scope::new();
        sc.configure(
            &config(raw::MC_SCOPE_TRIG_COMMAND, raw::MC_SCOPE_CONTINUOUS, 2, 0),
            1,
        )
        .unwrap();
        assert_eq!(sc.force_trigger(), Err(NackCode::ScopeState));
        sc.arm(1, 0).unwrap();
        let (ring, _) = run(&mut sc, 10, 100, |t| t as f64, |_| 0);
        assert!(ring.is_empty());
        sc.force_trigger().unwrap();
        let mut ring = Vec::new();
        for t in 11..=1000 {
            if sc.samples_at(t) {
                sc.on_sample(&sample(t, 0.0), 0, 0, &mut |s| {
                    ring.push(s.tick);
                    true
                });
            }
        }
        assert_eq!(ring, (9..=1000).collect::<Vec<_>>());
        sc.stop().unwrap();
        assert!(!sc.samples_at(1001));
        assert_eq!(sc.stop(), Err(NackCode::ScopeState));
    }

    #[test]
    fn fault_trigger_fires_on_a_new_fault_only() {
        let mut sc = Scope::new();
        sc.configure(
            &config(raw::MC_SCOPE_TRIG_FAULT, raw::MC_SCOPE_ONE_SHOT, 0, 1),
            1,
        )
        .unwrap();
        sc.arm(1, 0).unwrap();
        let mut got = None;
        for t in 1..=20u64 {
            // A fault latched before the arm (bit 8), a new one (bit 14) at tick 12.
            let faults = 1 << 8 | if t >= 12 { 1 << 14 } else { 0 };
            let r = sc.on_sample(&sample(t, 0.0), 0, faults, &mut |_| true);
            got = got.or(r.triggered);
        }
        assert_eq!(got, Some(12));
    }

    #[test]
    fn a_full_ring_counts_every_lost_sample_and_reports_each_run_once() {
        let mut sc = Scope::new();
        sc.configure(
            &config(raw::MC_SCOPE_TRIG_IMMEDIATE, raw::MC_SCOPE_ONE_SHOT, 0, 100),
            1,
        )
        .unwrap();
        sc.arm(1, 0).unwrap();
        let (ring, reports) = run(&mut sc, 200, 30, |t| t as f64, |_| 0);
        assert_eq!(ring.len(), 30);
        let st = sc.status();
        assert_eq!((st.samples, st.lost), (30, 70));
        let lost: Vec<u64> = reports.iter().filter_map(|r| r.lost).collect();
        assert_eq!(lost, vec![1]);
        assert_eq!(reports.last().unwrap().done, Some(100));
    }

    #[test]
    fn refusals_change_nothing() {
        let mut sc = Scope::new();
        assert_eq!(sc.arm(1, 0), Err(NackCode::ScopeState)); // not configured
        let good = config(raw::MC_SCOPE_TRIG_COMMAND, raw::MC_SCOPE_ONE_SHOT, 0, 5);
        sc.configure(&good, 1).unwrap();
        let bad = ScopeConfig { divider: 0, ..good };
        assert_eq!(sc.configure(&bad, 1), Err(NackCode::ScopeDivider));
        assert_eq!(sc.config.divider, 1);
        sc.arm(1, 0).unwrap();
        assert_eq!(sc.configure(&good, 1), Err(NackCode::ScopeState));
        assert_eq!(sc.arm(2, 0), Err(NackCode::ScopeState));
        assert_eq!(sc.status().arm_seq, 1);
    }
}
