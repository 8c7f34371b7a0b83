//! Group homing (layout 1.11, PLCopen Part 4 MC_GroupHome): a group homes its axes in stages.
//! The axes of a stage home together, each with its own homing (`homing.rs`, home position 0:
//! the home point reads the axis's home offset), and a member that is a gantry's master homes
//! its gantry (`gantry.rs`, squaring included). A stage starts once every axis of the stage
//! before it is homed and at rest. The group is in GroupHoming meanwhile; then GroupStandby
//! and `MC_EV_GROUP_HOMED`.
//!
//! **Failing as a whole.** A member whose homing fails (or that a halt, stop or safety stop
//! ended) ends it for the group: every other member still homing halts on its stop ramp (stop
//! reason `GroupHoming`), the later stages never start, and once every member is at rest the
//! group goes to GroupStandby and `MC_EV_GROUP_HOMING_FAILED` posts the member and its reason.
//! MC_GroupHalt and MC_GroupStop end it the same way (a stop holds the group in GroupStopping
//! until released), MC_GroupDisable at once; a member's safety stop stops the others as any
//! group motion's does (`Safety::trip_group`) and the group goes to GroupErrorStop.
//!
//! Stepped by `Firmware::tick` after the homing methods and the gantries (their reports of the
//! tick), only while a group homes. No allocation, no panic, no clock.
#![forbid(unsafe_code)]

use crate::firmware::gantry::HOMING_ABORTED;
use crate::firmware::group::{GroupHoming, HomeOrder};
use crate::firmware::homing::HomingReport;
use crate::firmware::Firmware;
use firmware_proto::cmd::GroupHome;
use firmware_proto::{
    AxisState, Event, EventKind, GroupState, Mem, NackCode, StopReason, MAX_AXES, MAX_GROUPS,
};

/// `MC_EV_GROUP_HOMING_FAILED`'s value when the group's own halt, stop or disable ended it.
const BY_GROUP: f64 = -1.0;

impl<M: Mem + Clone> Firmware<M> {
    /// `MC_OP_GROUP_HOME` (command `seq`) of group `g`: checks in the header's order, then the
    /// first stage starts.
    pub(super) fn group_home(&mut self, g: usize, seq: u32, h: &GroupHome) -> Result<(), NackCode> {
        let group = &self.groups[g];
        let cfg = group.config.ok_or(NackCode::GroupDisabled)?;
        match group.state {
            GroupState::Standby => {}
            GroupState::Disabled => return Err(NackCode::GroupDisabled),
            _ => return Err(NackCode::InvalidState),
        }
        let members = &cfg.axes[..cfg.naxes];
        if members.iter().any(|&a| {
            self.axes[a].state != AxisState::Standstill || self.axes[a].busy_with_motion()
        }) {
            return Err(NackCode::AxisBusy);
        }
        let mut order = HomeOrder::check(h.stages, &h.masks, cfg.naxes)?;
        if order.n == 0 {
            order = cfg.home;
        }
        if order.n == 0 {
            return Err(NackCode::HomeStage);
        }
        // Every axis's homing is checked before any starts (a gantry: each of its sides).
        let rate = self.servo_rate_hz;
        for &m in order.stages() {
            for (i, &a) in members.iter().enumerate() {
                if m >> i & 1 == 0 {
                    continue;
                }
                match self.gantry_of_master(a).and_then(|k| self.gantry(k)) {
                    Some(gantry) => {
                        if !self.gantry_ready(gantry) {
                            return Err(NackCode::GantryState);
                        }
                        for b in gantry.members() {
                            self.homing[b].check(&self.axes[b], 0.0, rate)?;
                        }
                    }
                    None => {
                        self.homing[a].check(&self.axes[a], 0.0, rate)?;
                    }
                }
            }
        }
        let (tick, out) = (self.tick, &mut self.outbox);
        self.groups[g].begin_homing(
            GroupHoming {
                seq,
                order,
                stage: 0,
                done: 0,
                failed: None,
                by_stop: None,
            },
            tick,
            out,
        );
        self.start_home_stage(g);
        Ok(())
    }

    /// The axes of the running stage of group `g` start homing (their checks passed).
    fn start_home_stage(&mut self, g: usize) {
        let (Some(cfg), Some(h)) = (self.groups[g].config, self.groups[g].homing().copied()) else {
            return;
        };
        let (rate, tick) = (self.servo_rate_hz, self.tick);
        let mask = h.order.masks[h.stage];
        for (i, &a) in cfg.axes[..cfg.naxes].iter().enumerate() {
            if mask >> i & 1 == 0 {
                continue;
            }
            if let Some(k) = self.gantry_of_master(a) {
                self.gantry_homed[k] = None;
                if let Err(e) = self.gantry_home_from(k, h.seq, true) {
                    self.fail_group_home(g, e as i32, a);
                }
                continue;
            }
            let axis = &mut self.axes[a];
            let old = axis.state;
            match self.homing[a].start(axis, h.seq, 0.0, rate) {
                Ok(_) if old != axis.state => self
                    .outbox
                    .push(super::state_event(a as u16, old, axis.state, tick)),
                Ok(_) => {}
                Err(e) => self.fail_group_home(g, e as i32, a),
            }
        }
    }

    /// Record group `g`'s failure (the first one counts) and halt every member still homing
    /// (stop reason `GroupHoming`).
    fn fail_group_home(&mut self, g: usize, code: i32, axis: usize) {
        let Some(cfg) = self.groups[g].config else {
            return;
        };
        let Some(mut h) = self.groups[g].homing().copied() else {
            return;
        };
        if h.failed.is_none() {
            h.failed = Some((code, axis as f64));
        }
        self.groups[g].home = Some(h);
        self.halt_group_members(&cfg.axes[..cfg.naxes], h.seq, None, StopReason::GroupHoming);
    }

    /// Halt each of `members` that homes (or squares its gantry) on `ramp` (None: its own stop
    /// ramp), with stop reason `reason`.
    fn halt_group_members(
        &mut self,
        members: &[usize],
        seq: u32,
        ramp: Option<(f64, f64)>,
        reason: StopReason,
    ) {
        let max_time = self.safety.config().max_stop_time();
        let tick = self.tick;
        for &a in members {
            let axis = &mut self.axes[a];
            if axis.state != AxisState::Homing {
                continue;
            }
            let c = axis.safety.config;
            let (d, j) = ramp.unwrap_or((c.stop_decel, c.stop_jerk));
            if let Ok(Some(old)) = axis.start_stop(seq, false, d, j, max_time) {
                self.outbox
                    .push(super::state_event(a as u16, old, axis.state, tick));
            }
            axis.safety.stop_reason = reason;
        }
    }

    /// MC_GroupHalt (`stop` false) or MC_GroupStop of group `g` while it homes: the members
    /// halt on `ramp` and it ends once they are at rest.
    pub(super) fn group_home_halt(&mut self, g: usize, seq: u32, stop: bool, ramp: (f64, f64)) {
        let Some(cfg) = self.groups[g].config else {
            return;
        };
        let Some(mut h) = self.groups[g].homing().copied() else {
            return;
        };
        h.failed.get_or_insert((HOMING_ABORTED, BY_GROUP));
        if stop || h.by_stop.is_none() {
            h.by_stop = Some(stop);
        }
        self.groups[g].home = Some(h);
        let reason = if stop {
            StopReason::Stop
        } else {
            StopReason::Halt
        };
        self.halt_group_members(&cfg.axes[..cfg.naxes], seq, Some(ramp), reason);
        if stop {
            let (tick, out) = (self.tick, &mut self.outbox);
            self.groups[g].homing_stopping(tick, out);
        }
    }

    /// MC_GroupDisable of group `g` while it homes: the members halt on their stop ramps and
    /// the failure posts now (the group is disabled at once).
    pub(super) fn group_home_disable(&mut self, g: usize) {
        let (Some(cfg), Some(h)) = (self.groups[g].config, self.groups[g].homing().copied()) else {
            return;
        };
        self.halt_group_members(&cfg.axes[..cfg.naxes], h.seq, None, StopReason::Halt);
        let (code, value) = h.failed.unwrap_or((HOMING_ABORTED, BY_GROUP));
        self.post_group_home_event(g, EventKind::GroupHomingFailed, h.seq, code, value);
    }

    /// The groups' homing step of a tick (after the homing methods and the gantries).
    pub(super) fn group_home_tick(&mut self, homed: &Option<[HomingReport; MAX_AXES]>) {
        for g in 0..MAX_GROUPS {
            if self.groups[g].homing().is_some() {
                self.group_home_step(g, homed);
            }
        }
    }

    fn group_home_step(&mut self, g: usize, homed: &Option<[HomingReport; MAX_AXES]>) {
        let (Some(cfg), Some(mut h)) = (self.groups[g].config, self.groups[g].homing().copied())
        else {
            return;
        };
        let members = &cfg.axes[..cfg.naxes];
        let tick = self.tick;
        // A member's safety stop took the group to GroupErrorStop (its guard): it ends now.
        if self.groups[g].state == GroupState::ErrorStop {
            let first = members
                .iter()
                .copied()
                .filter(|&a| self.axes[a].state == AxisState::ErrorStop)
                .min_by_key(|&a| self.axes[a].safety.stop_reason == StopReason::Group);
            let (code, value) = h
                .failed
                .unwrap_or((HOMING_ABORTED, first.map_or(BY_GROUP, |a| a as f64)));
            self.groups[g].end_homing(&self.axes, false, tick, &mut self.outbox);
            self.post_group_home_event(g, EventKind::GroupHomingFailed, h.seq, code, value);
            return;
        }
        if h.failed.is_none() {
            // The running stage: each member's outcome this tick.
            let mask = h.order.masks[h.stage];
            let mut failed = None;
            for (i, &a) in members.iter().enumerate() {
                if mask >> i & 1 == 0 || h.done >> i & 1 == 1 {
                    continue;
                }
                if let Some(k) = self.gantry_of_master(a) {
                    match self.gantry_homed[k].take() {
                        Some((0, _)) => h.done |= 1 << i,
                        Some((code, v)) => {
                            failed.get_or_insert((code, v as usize));
                        }
                        None => {}
                    }
                    continue;
                }
                let report = homed.as_ref().map(|r| &r[a]);
                if let Some((_, why, _)) = report.and_then(|r| r.failed) {
                    failed.get_or_insert((why as i32, a));
                } else if report.is_some_and(|r| r.done.is_some()) {
                    h.done |= 1 << i;
                } else if self.axes[a].state != AxisState::Homing {
                    // A halt, stop, power off or safety stop ended it.
                    failed.get_or_insert((HOMING_ABORTED, a));
                }
            }
            self.groups[g].home = Some(h);
            if let Some((code, a)) = failed {
                self.fail_group_home(g, code, a);
                h = match self.groups[g].homing() {
                    Some(h) => *h,
                    None => return,
                };
            } else if h.done == mask {
                h.stage += 1;
                h.done = 0;
                self.groups[g].home = Some(h);
                if h.stage < h.order.n {
                    self.start_home_stage(g);
                    return;
                }
                self.groups[g].end_homing(&self.axes, false, tick, &mut self.outbox);
                let n = h.order.n as f64;
                self.post_group_home_event(g, EventKind::GroupHomed, h.seq, 0, n);
                return;
            } else {
                return;
            }
        }
        // Failed: it ends once every member is at rest (and its gantry coupled again).
        let at_rest = members.iter().all(|&a| {
            let axis = &self.axes[a];
            let gantry_busy = self
                .gantry_of_master(a)
                .and_then(|k| self.gantry(k))
                .is_some_and(|gy| gy.phase != crate::firmware::gantry::Phase::Coupled);
            !gantry_busy
                && match axis.state {
                    AxisState::Standstill | AxisState::Disabled => !axis.busy_with_motion(),
                    AxisState::ErrorStop => !axis.profile_running(),
                    AxisState::Stopping => !axis.profile_running(),
                    _ => false,
                }
        });
        if !at_rest {
            return;
        }
        let (code, value) = h.failed.unwrap_or((HOMING_ABORTED, BY_GROUP));
        let held = h.by_stop == Some(true);
        self.groups[g].end_homing(&self.axes, held, tick, &mut self.outbox);
        self.post_group_home_event(g, EventKind::GroupHomingFailed, h.seq, code, value);
    }

    fn post_group_home_event(
        &mut self,
        g: usize,
        kind: EventKind,
        seq: u32,
        code: i32,
        value: f64,
    ) {
        self.outbox.push(Event {
            seq,
            kind: kind as u16,
            axis: g as u16,
            code,
            tick: self.tick,
            value,
        });
    }
}
