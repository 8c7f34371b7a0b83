//! Configuration, sessions and safety: NOP, the applies of the card's and an axis's
//! configuration blocks, the configuration read-back and the scale (layout 1.8, `config.rs`),
//! the host's attach and detach, and the safety opcodes (`safety.rs`).

use super::super::axis::AxisConfig;
use super::super::homing::HomingConfig;
use super::super::{config, Firmware};
use super::hard_stop_ramp;
use crate::servo::biquad::ServoFilters;
use firmware_proto::cmd::{CardCmd, Session};
use firmware_proto::{
    layout, AxisState, Command, Event, EventKind, GroupState, Mem, NackCode, Opcode, StopReason,
    MAX_AXES,
};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Card`].
    pub(super) fn execute_card(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        // A malformed read-back or e-stop is the first thing the card refuses of either.
        let cmd = CardCmd::decode(op, c.flags, &c.args).map_err(|e| e.nack)?;
        let ok = |r: Result<(), NackCode>| r.map(|()| 0.0);
        match cmd {
            CardCmd::Nop => Ok(0.0),
            CardCmd::ApplyCardConfig => ok(self.apply_card_config()),
            // Layout 1.8: the configuration read back, the scale kept for hosts (config.rs).
            CardCmd::ReadConfig(r) => ok(self.read_config(&r)),
            CardCmd::SetScale(s) => ok(self.set_scale(c.axis, s.scale)),
            CardCmd::HostDetach(s) => ok(self.detach(c.seq, s)),
            // Layout 1.12 (timed.rs): MC_OP_AT_TICK is taken with its entry before execute;
            // met here it times nothing.
            CardCmd::AtTick(_) => Err(NackCode::TimedAlone),
            CardCmd::SyncCommit(sc) => self.sync_commit(sc),
            CardCmd::TimedCancel(tc) => Ok(self.timed_cancel(tc.key)),
            CardCmd::HostAttach(_)
            | CardCmd::ApplySafetyConfig
            | CardCmd::ApplyAxisSafety
            | CardCmd::EStop(_)
            | CardCmd::SafetyReset => {
                // [safety] opcodes 32..47 and the attach (safety.rs)
                let (mem, tick, rate) = (&self.mem, self.tick, self.servo_rate_hz);
                let axes = &mut self.axes[..self.num_axes];
                self.safety
                    .command(mem, &cmd, c.axis, tick, rate, axes)
                    .unwrap_or(Err(NackCode::UnknownOpcode))
            }
            CardCmd::ApplyAxisConfig | CardCmd::ApplyAxisFilter | CardCmd::ApplyAxisHoming => {
                self.apply_axis_block(c, op, &cmd)
            }
        }
    }

    /// `MC_OP_APPLY_AXIS_CONFIG`, `_FILTER`, `_HOMING`: validate the axis's block and take it.
    fn apply_axis_block(
        &mut self,
        c: &Command,
        op: Opcode,
        cmd: &CardCmd,
    ) -> Result<f64, NackCode> {
        let ax = self.target_axis(c)?;
        let rate = self.servo_rate_hz;
        match cmd {
            CardCmd::ApplyAxisConfig => {
                let block = layout::AXIS_CONFIG.at(ax).read(&self.mem);
                let pdplus = layout::AXIS_PDPLUS.at(ax).read(&self.mem);
                let pidff = layout::AXIS_PIDFF.at(ax).read(&self.mem);
                let cfg = config::validate_axis_config(&block, &pdplus, &pidff)?;
                let ts = self.ts();
                self.axes[ax].apply_config(cfg, ts);
            }
            CardCmd::ApplyAxisFilter => {
                let cfg = config::decode_axis_filter(&layout::AXIS_FILTER.at(ax).read(&self.mem))?;
                cfg.validate(self.ts())?;
                if !self.filters[ax].is_settled() {
                    return Err(NackCode::FilterBusy);
                }
                self.filters[ax].config = cfg;
                return Ok(0.0);
            }
            _ => {
                let block = layout::AXIS_HOMING.at(ax).read(&self.mem);
                self.homing[ax].apply(HomingConfig::validate(&block, rate)?);
            }
        }
        self.finish_axis_command(c, op, ax, None, false, None);
        Ok(0.0)
    }

    /// `MC_OP_APPLY_CARD_CONFIG`: the servo rate, while every axis is disabled. Every filter
    /// the card runs (the servo outputs', the analog inputs', the PSO's) is designed again
    /// for the same frequencies at the new rate, or the rate is refused with that filter's
    /// refusal.
    fn apply_card_config(&mut self) -> Result<(), NackCode> {
        let rate = layout::CARD_CONFIG.read(&self.mem).servo_rate_hz;
        if !(firmware_proto::SERVO_RATE_MIN_HZ..=firmware_proto::SERVO_RATE_MAX_HZ).contains(&rate)
        {
            return Err(NackCode::BadConfig);
        }
        if self.axes[..self.num_axes]
            .iter()
            .any(|a| a.state != AxisState::Disabled)
        {
            return Err(NackCode::AxesEnabled);
        }
        // Layout 1.11: every axis's filters designed at the new rate, or the rate refused.
        let mut filters = [ServoFilters::default(); MAX_AXES];
        for (f, axis) in filters.iter_mut().zip(&self.axes) {
            *f = axis.filters().redesigned(rate as f64)?;
        }
        // Layout 1.11: the analog inputs' and the PSO's filters too.
        self.analog.check_rate(rate)?;
        self.analog.set_rate(rate);
        self.servo_rate_hz = rate;
        let ts = self.ts();
        for (ax, (axis, f)) in self.axes.iter_mut().zip(filters).enumerate() {
            let cfg: AxisConfig = axis.config;
            axis.apply_config(cfg, ts);
            axis.with_filters(|ch, _| *ch = f);
            layout::SERVO_FILTERS.at(ax).write(&self.mem, &f.block());
        }
        self.mem.write32(layout::SERVO_RATE_HZ, rate);
        Ok(())
    }

    /// `MC_OP_HOST_DETACH` (command `seq`): the host closes the card cleanly. Every axis moving
    /// on its own (moves, velocity mode and jog, homing, a coupling or PT/PVT stream) and every
    /// moving group (its queue or path) halts along its stop ramp, each axis with reason
    /// `HostDetach`, then the session ends and the watchdog is disarmed: nothing is latched,
    /// and nothing moves on for a host that has gone.
    fn detach(&mut self, seq: u32, session: Session) -> Result<(), NackCode> {
        self.safety.detach(&self.mem, session.id)?;
        self.halt_motion(seq, u32::MAX, StopReason::HostDetach, Opcode::HostDetach);
        // Layout 1.12: nothing timed runs for a host that has gone.
        self.drop_held(0, NackCode::Cancelled);
        Ok(())
    }

    /// Halts the motion of the axes in `mask` (a bit an axis; all: `u32::MAX`), for command
    /// or arm `seq`: each moving group with such a member halts along its path on its members'
    /// stop ramps (as MC_GroupHalt), and each such axis moving on its own (a move, velocity
    /// mode or jog, homing, a coupling or PT/PVT stream) on its stop ramp, each axis with
    /// stop reason `reason`; the motion queued behind is aborted (`by` the events' code).
    pub(in crate::firmware) fn halt_motion(
        &mut self,
        seq: u32,
        mask: u32,
        reason: StopReason,
        by: Opcode,
    ) {
        let (tick, max_time) = (self.tick, self.safety.config().max_stop_time());
        for group in self.groups.iter_mut() {
            let Some(members) = group.moving_members() else {
                continue;
            };
            if group.state == GroupState::Stopping || !members.iter().any(|&a| mask >> a & 1 == 1) {
                continue;
            }
            let hard = hard_stop_ramp(&self.axes, members);
            let (mut list, n) = ([0usize; MAX_AXES], members.len().min(MAX_AXES));
            list[..n].copy_from_slice(&members[..n]);
            // Refused only by a group that cannot stop (none that moves).
            if group
                .start_stop(seq, false, hard, hard, max_time, tick, &mut self.outbox)
                .is_ok()
            {
                // The members' motion ends by the halt: the host reads why.
                for &a in &list[..n] {
                    self.axes[a].group_stopping(reason);
                }
            }
        }
        for (i, axis) in self.axes[..self.num_axes].iter_mut().enumerate() {
            if mask >> i & 1 == 0 {
                continue;
            }
            // Layout 1.7 (sync): a coupled slave or a PT/PVT stream halts too.
            let geared = axis.state == AxisState::SynchronizedMotion
                && (self.gears[i].engaged() || self.pvt[i].as_ref().is_some_and(|s| s.running()));
            if !geared
                && !matches!(
                    axis.state,
                    AxisState::DiscreteMotion | AxisState::ContinuousMotion | AxisState::Homing
                )
            {
                continue;
            }
            let pending = axis.pending_motion();
            let sc = axis.safety.config;
            if axis
                .start_stop(seq, false, sc.stop_decel, sc.stop_jerk, max_time)
                .is_ok()
            {
                axis.safety.stop_reason = reason;
                for old in pending.into_iter().chain(axis.drain_queue()) {
                    self.outbox.push(Event {
                        seq: old,
                        kind: EventKind::MotionAborted as u16,
                        axis: i as u16,
                        code: by as i32,
                        tick,
                        value: 0.0,
                    });
                }
            }
        }
    }
}
