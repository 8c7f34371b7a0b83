//! Single-axis motion: MC_Power, MC_MoveAbsolute/Relative/Additive, MC_MoveVelocity and jog,
//! MC_SetOverride, MC_Halt, MC_Stop and its release, MC_Reset, MC_Home, MC_SetPosition.
//!
//! The card's order: the command's numbers finite, the axis one of the card's, the safety
//! layer's check (latches, causes, limits), not an axis of an enabled group (but power on and
//! reset), then the axis's own checks as it takes the command.

use super::super::axis::{Axis, MoveKind, Started};
use super::super::{homing, nack, Firmware};
use crate::motion::scurve::Limits;
use firmware_proto::cmd::{self, AxisCmd};
use firmware_proto::{layout, AxisState, Command, Mem, NackCode, Opcode};

/// The axis's move kind of a decoded position move's (the safety layer's check uses it too).
impl From<cmd::MoveKind> for MoveKind {
    fn from(k: cmd::MoveKind) -> Self {
        match k {
            cmd::MoveKind::Absolute => MoveKind::Absolute,
            cmd::MoveKind::Relative => MoveKind::Relative,
            cmd::MoveKind::Additive => MoveKind::Additive,
        }
    }
}

/// Are the numbers the command carries finite?
fn finite(c: &AxisCmd) -> bool {
    let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
    match c {
        AxisCmd::Move(_, m) => m.position.is_finite() && all(&m.limits.to_array()),
        AxisCmd::MoveVelocity(v) => all(&[v.velocity, v.amax, v.dmax, v.jerk]),
        AxisCmd::Halt(r) | AxisCmd::Stop(r) => all(&[r.dmax, r.jerk]),
        AxisCmd::Jog(j) => j.velocity.is_finite(),
        AxisCmd::SetOverride(o) => o.factor.is_finite(),
        AxisCmd::Home(h) => h.position.is_finite(),
        AxisCmd::SetPosition(p) => p.position.is_finite(),
        AxisCmd::CompTable(h) => all(&[h.bound, h.backlash, h.ramp_vel, h.ramp_acc]),
        AxisCmd::CompData(d) => d
            .points()
            .iter()
            .all(|p| all(&[p.position, p.forward, p.reverse])),
        AxisCmd::PowerOn
        | AxisCmd::PowerOff
        | AxisCmd::StopRelease
        | AxisCmd::Reset
        | AxisCmd::CompRead(_)
        | AxisCmd::Handwheel(_)
        | AxisCmd::HandwheelOff => true,
        AxisCmd::SetModulo(m) => m.modulo.is_finite(),
        // Layout 1.11: the filter's design checks its numbers itself (every one, NotFinite).
        AxisCmd::ServoFilterSet(_) | AxisCmd::ServoFilterClear(_) => true,
        // Layout 1.12: the sweep's check takes its numbers in its order (freq.rs).
        AxisCmd::FreqStart(_) | AxisCmd::FreqStop => true,
    }
}

impl<M: Mem + Clone> Firmware<M> {
    /// A single-axis motion command (`op` of [`cmd::Family::Axis`]).
    pub(super) fn execute_axis(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        // Every argument is a plain number: decoding never refuses one.
        let cmd = AxisCmd::decode(op, c.flags, &c.args).map_err(|e| e.nack)?;
        if !finite(&cmd) {
            return Err(NackCode::NotFinite);
        }
        // Layout 1.12: a sweep stops whatever the axis field says.
        if let AxisCmd::FreqStop = cmd {
            return self.execute_freq_stop();
        }
        let ax = self.target_axis(c)?;
        // Layout 1.12: an axis being swept takes no motion of its own (freq.rs).
        self.sweep_gate(ax, &cmd)?;
        if let AxisCmd::FreqStart(s) = &cmd {
            self.safety.check_command(&cmd, &self.axes[ax])?;
            if self.grouped(ax) {
                return Err(NackCode::AxisGrouped);
            }
            self.gantry_gate(ax, &cmd)?;
            return self.execute_freq_start(c.seq, ax, s);
        }
        if let AxisCmd::CompTable(_) | AxisCmd::CompData(_) | AxisCmd::CompRead(_) = cmd {
            return self.execute_comp(ax, &cmd);
        }
        // Layout 1.11: the servo output's filters, in any state (a gantry's slave's included:
        // they shape its drive, not its motion).
        match cmd {
            AxisCmd::ServoFilterSet(f) => return self.execute_filter(ax, f.slot, Some(&f.spec)),
            AxisCmd::ServoFilterClear(f) => return self.execute_filter(ax, f.slot, None),
            _ => {}
        }
        // Layout 1.10: a gantry's slave is the gantry's; its master's frame is the gantry's.
        self.gantry_gate(ax, &cmd)?;
        if let AxisCmd::SetModulo(m) = cmd {
            return self.execute_modulo(ax, m.modulo);
        }
        // [safety] card-wide latches, causes still present, limits (safety.rs)
        self.safety.check_command(&cmd, &self.axes[ax])?;
        self.gantry_slaves_check(ax, &cmd)?;
        let pending = self.axes[ax].pending_motion();
        if !matches!(cmd, AxisCmd::PowerOn | AxisCmd::Reset) && self.grouped(ax) {
            return Err(NackCode::AxisGrouped);
        }
        if let AxisCmd::Handwheel(_) | AxisCmd::HandwheelOff = cmd {
            return self.execute_handwheel(c, op, ax, &cmd, pending);
        }
        let rate = self.servo_rate_hz;
        let max_stop_time = self.safety.config().max_stop_time();
        let axis = &mut self.axes[ax];
        // Does the command take over the axis (PLCopen Aborting): the motion in progress and
        // every buffered move are aborted.
        let mut aborting = matches!(
            cmd,
            AxisCmd::MoveVelocity(_)
                | AxisCmd::Jog(_)
                | AxisCmd::Halt(_)
                | AxisCmd::Stop(_)
                | AxisCmd::PowerOff
                | AxisCmd::Home(_)
        );
        let changed = match &cmd {
            // Served by `execute_comp`, `execute_handwheel` and `execute_modulo` above.
            AxisCmd::CompTable(_)
            | AxisCmd::CompData(_)
            | AxisCmd::CompRead(_)
            | AxisCmd::Handwheel(_)
            | AxisCmd::HandwheelOff
            | AxisCmd::SetModulo(_)
            | AxisCmd::ServoFilterSet(_)
            | AxisCmd::ServoFilterClear(_)
            | AxisCmd::FreqStart(_)
            | AxisCmd::FreqStop => return Err(NackCode::UnknownOpcode),
            AxisCmd::PowerOn => axis.power(true)?,
            AxisCmd::PowerOff => axis.power(false)?,
            AxisCmd::Move(kind, m) => {
                let l = &m.limits;
                let lim = Limits {
                    vmax: l.vmax,
                    amax: l.amax,
                    dmax: l.dmax,
                    j1: l.j1,
                    j3: l.j3,
                    j5: l.j5,
                    j7: l.j7,
                };
                lim.check_range(rate).map_err(nack::plan_nack)?;
                let kind = MoveKind::from(*kind);
                // The direction is an absolute move's (relative and additive ignore it).
                let dir = match kind {
                    MoveKind::Absolute => m.direction,
                    _ => cmd::MoveDirection::Shortest,
                };
                let (changed, started) =
                    axis.start_move_dir(c.seq, kind, m.position, &lim, m.buffered, rate, dir)?;
                aborting = started == Started::Now;
                changed
            }
            AxisCmd::MoveVelocity(v) => {
                let lim = Limits {
                    vmax: v.velocity.abs(),
                    amax: v.amax,
                    dmax: v.dmax,
                    ..Limits::symmetric(0.0, 0.0, v.jerk)
                };
                velocity_mode(axis, c.seq, v.velocity, &lim, rate)?
            }
            AxisCmd::Jog(j) => {
                let cfg = &axis.config;
                if j.velocity.abs() > cfg.jog_max_vel {
                    return Err(NackCode::OutOfRange);
                }
                let lim = Limits::symmetric(cfg.jog_max_vel, cfg.jog_accel, cfg.jog_jerk);
                velocity_mode(axis, c.seq, j.velocity, &lim, rate)?
            }
            AxisCmd::SetOverride(o) => {
                axis.set_override(o.factor, rate)?;
                None
            }
            AxisCmd::Halt(r) | AxisCmd::Stop(r) => {
                nack::check_ranges(rate, &[(2, r.dmax), (3, r.jerk)])?;
                let stop = matches!(cmd, AxisCmd::Stop(_));
                axis.start_stop(c.seq, stop, r.dmax, r.jerk, max_stop_time)?
            }
            AxisCmd::StopRelease => {
                axis.release_stop()?;
                None
            }
            AxisCmd::Reset => axis.reset()?,
            AxisCmd::Home(h) => self.homing[ax].start(axis, c.seq, h.position, rate)?,
            AxisCmd::SetPosition(p) => {
                homing::set_position(axis, p.position, p.relative)?;
                None
            }
        };
        self.finish_axis_command(c, op, ax, pending, aborting, changed);
        if let AxisCmd::PowerOn | AxisCmd::PowerOff | AxisCmd::Reset = cmd {
            // A gantry's master powers and resets its slaves.
            self.gantry_slaves_follow(ax, &cmd);
        }
        Ok(0.0)
    }
}

/// MC_MoveVelocity or jog (command `seq`): velocity mode at `vel` within `lim`'s acceleration,
/// deceleration and jerk, each in the card's range.
fn velocity_mode(
    axis: &mut Axis,
    seq: u32,
    vel: f64,
    lim: &Limits,
    rate: u32,
) -> Result<Option<AxisState>, NackCode> {
    if vel.abs() > *firmware_proto::limit_range(1, rate).end() {
        return Err(NackCode::OutOfRange);
    }
    nack::check_ranges(rate, &[(2, lim.amax), (2, lim.dmax), (3, lim.j1)])?;
    axis.start_velocity(seq, vel, lim, rate)
}

impl<M: Mem + Clone> Firmware<M> {
    /// Layout 1.10: `MC_OP_HANDWHEEL` and `MC_OP_HANDWHEEL_OFF` on axis `ax` (`handwheel.rs`).
    /// A selection that takes the axis over aborts its motion (PLCopen Aborting); an axis the
    /// input was handed over from reports its state change too.
    fn execute_handwheel(
        &mut self,
        c: &Command,
        op: Opcode,
        ax: usize,
        cmd: &AxisCmd,
        pending: Option<u32>,
    ) -> Result<f64, NackCode> {
        let (changed, aborting, value) = match cmd {
            AxisCmd::Handwheel(h) => {
                let s = self.start_handwheel(c.seq, ax, h)?;
                if let Some((b, Some(old))) = s.handed {
                    let e = super::super::state_event(b as u16, old, self.axes[b].state, self.tick);
                    self.outbox.push(e);
                }
                // The ack's value: the seq of the handwheel's motion.
                (s.changed, s.takes_over, f64::from(s.seq))
            }
            _ => (self.stop_handwheel(ax)?, false, 0.0),
        };
        self.finish_axis_command(c, op, ax, pending, aborting, changed);
        Ok(value)
    }

    /// Layout 1.9: the compensation commands of axis `ax` (`firmware::comp`). A table changes
    /// only on an axis at rest (`MC_NACK_COMP_BUSY`); the read-back is taken in any state.
    fn execute_comp(&mut self, ax: usize, cmd: &AxisCmd) -> Result<f64, NackCode> {
        use firmware_proto::layout;
        let rate = self.servo_rate_hz;
        if let AxisCmd::CompRead(r) = cmd {
            let b = match self.comp.as_ref() {
                Some(store) => store.readback(ax, usize::from(r.first)),
                None => super::super::comp::readback(None, ax, usize::from(r.first)),
            };
            layout::COMP_READBACK.write(&self.mem, &b);
            return Ok(f64::from(b.points));
        }
        let axis = &self.axes[ax];
        let at_rest = matches!(
            axis.state,
            AxisState::Standstill | AxisState::Disabled | AxisState::ErrorStop
        ) && !axis.busy_with_motion()
            && !self.grouped_moving(ax);
        if !at_rest {
            if let Some(store) = self.comp.as_mut() {
                if store.open_for(ax) {
                    // A refusal closes the transfer: nothing half-loaded stays.
                    store.close();
                }
            }
            return Err(NackCode::CompBusy);
        }
        let store = self
            .comp
            .get_or_insert_with(super::super::comp::CompStore::new);
        let in_force = match cmd {
            AxisCmd::CompTable(h) => store.begin(ax, h, rate)?,
            AxisCmd::CompData(d) => store.data(ax, d)?,
            _ => None,
        };
        if let Some(params) = in_force {
            // The new table's correction ramps in from the one in force (its limits).
            self.axes[ax].compensation_changed(Some(params.ramp_limits()));
        }
        Ok(0.0)
    }

    /// Layout 1.10: `MC_OP_SET_MODULO` on axis `ax` (finite, checked by the caller): 0 makes
    /// it linear, else the period must be in `MODULO_RANGE` (`ModuloRange`); it changes only
    /// on an axis at rest (`ModuloBusy`), as compensation does, and nothing changes on a
    /// refusal.
    fn execute_modulo(&mut self, ax: usize, modulo: f64) -> Result<f64, NackCode> {
        if modulo != 0.0 && !firmware_proto::MODULO_RANGE.contains(&modulo) {
            return Err(NackCode::ModuloRange);
        }
        let axis = &self.axes[ax];
        let at_rest = matches!(
            axis.state,
            AxisState::Standstill | AxisState::Disabled | AxisState::ErrorStop
        ) && !axis.busy_with_motion()
            && !self.grouped_moving(ax);
        if !at_rest {
            return Err(NackCode::ModuloBusy);
        }
        // Layout 1.13: an armed compare channel's positions are in the period it was armed in.
        if self.io.compare_watches(ax) {
            return Err(NackCode::CompareTurn);
        }
        let q = firmware_proto::modulo_subcounts(modulo);
        self.axes[ax].set_modulo(q);
        Ok(self.axes[ax].modulo())
    }

    /// Layout 1.11: `MC_OP_SERVO_FILTER_SET` (`spec`) or `_CLEAR` (`None`) of slot `slot` of
    /// axis `ax`: checked and designed at the servo rate (refused: nothing changes), the
    /// read-back block written before the ack.
    fn execute_filter(
        &mut self,
        ax: usize,
        slot: u8,
        spec: Option<&cmd::BiquadSpec>,
    ) -> Result<f64, NackCode> {
        let rate = self.servo_rate_hz as f64;
        let k = slot as usize;
        self.axes[ax].with_filters(|ch, x| match spec {
            Some(spec) => ch.set(k, spec, rate, x),
            None => {
                ch.clear(k);
                Ok(())
            }
        })?;
        layout::SERVO_FILTERS
            .at(ax)
            .write(&self.mem, &self.axes[ax].filters().block());
        Ok(0.0)
    }

    /// Is axis `ax` driven by a group that moves?
    fn grouped_moving(&self, ax: usize) -> bool {
        self.axes[ax].state == AxisState::SynchronizedMotion && self.grouped(ax)
    }
}
