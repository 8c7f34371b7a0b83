//! An axis's own commands: its scale, MC_Power, MC_MoveAbsolute and MC_MoveRelative, MC_Halt,
//! MC_Stop and MC_Reset, its status and its servo configuration. The other motions of an axis
//! are in the modules of their kind (modes, homing, pvt, sync, cam, io, nurbs).

use crate::card::{
    finite, lock, positive, Axis, AxisSettings, Motion, MoveLimits, Status, SCALE_RANGE,
};
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{self, AxisCmd, CardCmd, Cmd, PositionMove, StopRamp};

/// Which way an absolute move on a modulo axis goes (PLCopen `MC_Direction`): the card's own
/// type ([`Axis::move_absolute_dir`], [`Axis::move_with_dir`]).
pub use firmware_proto::cmd::MoveDirection;
use firmware_proto::{layout, raw, Command};
use std::time::Duration;

impl Axis {
    /// Counts per user unit (default 1: positions in counts; negative: the user's axis runs
    /// against the encoder). |scale| must lie in [`SCALE_RANGE`]: zero, subnormal and absurd
    /// scales are refused (`BadConfig`). Layout 1.8: the card keeps it for hosts (it does not
    /// use it itself), so a host that opens the card later adopts it, and a configuration file
    /// saves it; a card of an older layout keeps none, and the scale is this host's only.
    pub fn set_scale(&self, counts_per_unit: f64) -> Result<()> {
        finite("scale", counts_per_unit)?;
        if !SCALE_RANGE.contains(&counts_per_unit.abs()) {
            return Err(Error::BadConfig(format!(
                "scale {counts_per_unit:e} counts per unit: |scale| must lie in {:e}..={:e}",
                SCALE_RANGE.start(),
                SCALE_RANGE.end()
            )));
        }
        if self.card().info().layout.1 >= 8 {
            let scale = cmd::SetScale {
                scale: counts_per_unit,
            };
            self.run(self.cmd(CardCmd::SetScale(scale)), "set_scale")?;
        }
        lock(&self.card().inner().scale)[self.index()] = counts_per_unit;
        Ok(())
    }

    /// The counts per user unit this host converts the axis's positions with.
    pub fn scale_factor(&self) -> f64 {
        self.scale()
    }

    /// Layout 1.8: the servo configuration the card holds (read back from the card, with its
    /// scale): FFPIV gains, DAC limit, in-position windows, jog limits, servo law.
    pub fn settings(&self) -> Result<AxisSettings> {
        Ok(self.card().read_axis_config(self.index())?.0)
    }

    pub(crate) fn scale(&self) -> f64 {
        self.card().scale(self.index())
    }

    pub(crate) fn run(&self, cmd: Command, what: &'static str) -> Result<u32> {
        self.card()
            .execute_seq(cmd, what, Target::Axis(self.index()))
    }

    /// The entry of a command to this axis.
    pub(crate) fn cmd(&self, c: impl Into<Cmd>) -> Command {
        c.into().command(self.index() as u16)
    }

    /// MC_Power on.
    pub fn enable(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::PowerOn), "enable").map(|_| ())
    }

    /// MC_Power off (a moving axis loses power at once).
    pub fn disable(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::PowerOff), "disable").map(|_| ())
    }

    pub(crate) fn start_move(
        &self,
        kind: cmd::MoveKind,
        value: f64,
        lim: &MoveLimits,
        buffered: bool,
        what: &'static str,
    ) -> Result<Motion> {
        self.start_move_dir(kind, value, lim, buffered, MoveDirection::Shortest, what)
    }

    pub(crate) fn start_move_dir(
        &self,
        kind: cmd::MoveKind,
        value: f64,
        lim: &MoveLimits,
        buffered: bool,
        direction: MoveDirection,
        what: &'static str,
    ) -> Result<Motion> {
        finite(
            if kind == cmd::MoveKind::Absolute {
                "target position"
            } else {
                "distance"
            },
            value,
        )?;
        lim.check()?;
        let s = self.scale().abs();
        let m = PositionMove {
            position: value * self.scale(),
            limits: cmd::MoveLimits {
                vmax: lim.velocity * s,
                amax: lim.acceleration * s,
                dmax: lim.deceleration * s,
                j1: lim.jerk[0] * s,
                j3: lim.jerk[1] * s,
                j5: lim.jerk[2] * s,
                j7: lim.jerk[3] * s,
            },
            buffered,
            direction,
        };
        let seq = self.run(self.cmd(AxisCmd::Move(kind, m)), what)?;
        Ok(self.started(seq))
    }

    /// The motion of command `seq`, now the last one started on this axis.
    pub(crate) fn started(&self, seq: u32) -> Motion {
        lock(&self.card().inner().last_motion)[self.index()] = Some(seq);
        Motion::new(self.card().clone(), self.index(), seq)
    }

    /// MC_MoveAbsolute (Aborting): a time-optimal S-curve to `target` within `limits`, from
    /// whatever the axis is doing (see [`Axis::move_with`]).
    pub fn move_absolute(&self, target: f64, limits: &MoveLimits) -> Result<Motion> {
        self.start_move(
            cmd::MoveKind::Absolute,
            target,
            limits,
            false,
            "move_absolute",
        )
    }

    /// MC_MoveAbsolute (Aborting) on a modulo axis, the way `direction` names (PLCopen
    /// `MC_Direction`): `target` in [0, modulo) (else `ModuloMove`; the card does not
    /// normalise it: 370° on a 360° axis is a mistake more often than a wish), reached the
    /// shortest way (a tie of exactly half a turn: positive), positive, negative, or the way the
    /// axis moves now (at rest: the way it last moved). A target within the in-position window
    /// of where the axis is is no turn whichever way is named. On a linear axis only
    /// `Shortest` (else `ModuloMove`). [`Axis::move_absolute`] is this with `Shortest`.
    pub fn move_absolute_dir(
        &self,
        target: f64,
        direction: MoveDirection,
        limits: &MoveLimits,
    ) -> Result<Motion> {
        self.start_move_dir(
            cmd::MoveKind::Absolute,
            target,
            limits,
            false,
            direction,
            "move_absolute",
        )
    }

    /// Layout 1.10: make the axis a rotary (modulo) axis of `period` user units (for example
    /// 360.0 with a scale in counts per degree). At rest only (`ModuloBusy`); a period of zero
    /// is `ModuloZero` (use [`Axis::clear_modulo`]), a negative, non-finite or out-of-range one
    /// (the card takes 1 to 10¹¹ counts) `ModuloRange`; a refused call changes nothing. The
    /// axis needs a positive scale (`BadConfig`). The card holds the period to 1/65536 count
    /// ([`Axis::modulo`] reads back what it holds). From then on the status's positions, motion
    /// done's and probe captures are in [0, period), without drift however many turns it
    /// makes; soft limits do not apply (the card keeps them for when the axis is linear again).
    pub fn set_modulo(&self, period: f64) -> Result<()> {
        if period == 0.0 {
            return Err(Error::ModuloZero(self.index()));
        }
        if !period.is_finite() || period < 0.0 {
            return Err(Error::Refused {
                command: "set_modulo",
                target: Target::Axis(self.index()),
                code: firmware_proto::NackCode::ModuloRange,
                reason: "the period must be a positive, finite length",
            });
        }
        let s = self.scale();
        if s < 0.0 {
            return Err(Error::BadConfig(format!(
                "set_modulo on axis {}: a modulo axis needs a positive scale (it is {s})",
                self.index()
            )));
        }
        self.send_modulo(period * s)
    }

    /// Layout 1.10: make the axis linear again (its position stays where it is, in the turn it
    /// was in). At rest only (`ModuloBusy`).
    pub fn clear_modulo(&self) -> Result<()> {
        self.send_modulo(0.0)
    }

    fn send_modulo(&self, counts: f64) -> Result<()> {
        let m = cmd::SetModulo { modulo: counts };
        self.run(self.cmd(AxisCmd::SetModulo(m)), "set_modulo")
            .map(|_| ())
    }

    /// Layout 1.10: the modulo period the card holds, in user units (0: a linear axis).
    pub fn modulo(&self) -> Result<f64> {
        let counts = self.settings()?.modulo;
        Ok(crate::config::user_modulo(counts, self.scale()))
    }

    /// MC_MoveRelative (Aborting): a time-optimal S-curve by `distance` from the commanded
    /// position within `limits`.
    pub fn move_relative(&self, distance: f64, limits: &MoveLimits) -> Result<Motion> {
        self.start_move(
            cmd::MoveKind::Relative,
            distance,
            limits,
            false,
            "move_relative",
        )
    }

    fn stopping(
        &self,
        stop: bool,
        deceleration: f64,
        jerk: f64,
        what: &'static str,
    ) -> Result<Motion> {
        positive("deceleration", deceleration)?;
        positive("jerk", jerk)?;
        let s = self.scale().abs();
        let ramp = StopRamp {
            dmax: deceleration * s,
            jerk: jerk * s,
        };
        let c = if stop {
            AxisCmd::Stop(ramp)
        } else {
            AxisCmd::Halt(ramp)
        };
        let seq = self.run(self.cmd(c), what)?;
        Ok(self.started(seq))
    }

    /// MC_Halt: decelerate within the limits, then Standstill. The interrupted move is aborted.
    pub fn halt(&self, deceleration: f64, jerk: f64) -> Result<Motion> {
        self.stopping(false, deceleration, jerk, "halt")
    }

    /// MC_Stop: decelerate and stay in Stopping until [`Axis::release_stop`].
    pub fn stop(&self, deceleration: f64, jerk: f64) -> Result<Motion> {
        self.stopping(true, deceleration, jerk, "stop")
    }

    /// Leave Stopping (once at rest the axis goes to Standstill).
    pub fn release_stop(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::StopRelease), "release_stop")
            .map(|_| ())
    }

    /// MC_Reset: ErrorStop → Standstill.
    pub fn reset(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::Reset), "reset").map(|_| ())
    }

    /// Wait for the last motion started through this library on this axis. `NoMotion` when
    /// none was started since the card was opened (nothing to wait for).
    pub fn wait_done(&self, timeout: Duration) -> Result<f64> {
        let seq = lock(&self.card().inner().last_motion)[self.index()]
            .ok_or(Error::NoMotion(Target::Axis(self.index())))?;
        self.card()
            .wait_outcome(Target::Axis(self.index()), seq, timeout)
    }

    /// A consistent snapshot of the axis's status. Never stale: when the card's tick counter
    /// has stood still longer than [`crate::Card::stale_limit`] this is `NotResponding`, not the old
    /// snapshot.
    pub fn status(&self) -> Result<Status> {
        let raw = self.card().read_axis_status(self.index())?;
        self.card().link_alive(raw.tick)?;
        Status::from_raw(self.index(), raw, self.scale())
    }

    /// Write the servo and in-position configuration (FFPIV) and have the card check and apply
    /// it: a value that is not finite is `NotFinite`, one out of range `BadConfig`. The
    /// settings' `scale` is ignored (see [`Axis::set_scale`]); [`Axis::settings`] reads back
    /// what the card holds.
    pub fn configure(&self, cfg: &AxisSettings) -> Result<()> {
        let a = self.index();
        self.card().apply_block(
            layout::AXIS_CONFIG.at(a),
            |b| {
                *b = AxisSettings {
                    servo_law: raw::MC_SERVO_FFPIV,
                    ..*cfg
                }
            },
            self.cmd(CardCmd::ApplyAxisConfig),
            "configure",
            Target::Axis(a),
        )
    }
}
