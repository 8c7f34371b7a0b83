//! Moves from any state (PLCopen Aborting and Buffered, MC_MoveAdditive), velocity mode and
//! jog, and the velocity override of one axis.

use crate::card::{finite, positive, Axis, Motion, MoveLimits, Outcome};
use crate::error::Result;
use firmware_proto::cmd::{AxisCmd, Jog, Override, VelocityMove};
use firmware_proto::layout;
use std::time::Duration;

/// PLCopen BufferMode of a single-axis move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BufferMode {
    /// Take over at once from the axis's current position, velocity and acceleration (in the
    /// tick the card serves the command); the motion in progress and every buffered move are
    /// aborted.
    #[default]
    Aborting,
    /// Wait in the axis's queue (16 moves) until the motion before it is done (in position,
    /// or velocity mode at its velocity). [`Motion::wait_active`] tells when it starts.
    Buffered,
}

/// Which of PLCopen's position moves: MC_MoveAbsolute (to a target position),
/// MC_MoveRelative (by a distance from the commanded position; buffered: from the target of
/// the move before it), MC_MoveAdditive (by a distance from the target of the last move). The
/// card's own command type.
pub use firmware_proto::cmd::MoveKind;

/// Limits of velocity mode, in user units (see [`Axis::set_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityLimits {
    /// Acceleration (speeding up).
    pub acceleration: f64,
    /// Deceleration (slowing down).
    pub deceleration: f64,
    /// Jerk.
    pub jerk: f64,
}

impl VelocityLimits {
    /// Deceleration = acceleration.
    pub fn new(acceleration: f64, jerk: f64) -> Self {
        Self {
            acceleration,
            deceleration: acceleration,
            jerk,
        }
    }
}

impl Motion {
    /// Wait until a buffered move starts (PLCopen Active) and return its target (velocity
    /// mode: its velocity); an error if it is aborted first or the timeout passes.
    pub fn wait_active(&self, timeout: Duration) -> Result<f64> {
        self.wait_outcome_of(timeout, |o| match o {
            Outcome::Active(v) => Some(v),
            _ => None,
        })
    }

    /// Wait until velocity mode reaches its velocity (PLCopen InVelocity) and return it; an
    /// error if it is aborted first or the timeout passes.
    pub fn wait_in_velocity(&self, timeout: Duration) -> Result<f64> {
        self.wait_outcome_of(timeout, |o| match o {
            Outcome::InVelocity(v) => Some(v),
            _ => None,
        })
    }
}

impl Axis {
    /// MC_MoveAbsolute, MC_MoveRelative or MC_MoveAdditive (`kind`) with a PLCopen buffer mode.
    /// From rest the move is the card's time-optimal S-curve with the four jerks of `limits`;
    /// from motion (Aborting while moving) it is time-optimal from the current state with one
    /// jerk, the smallest of the four. A full queue is `QueueFull`; nothing queued is lost.
    pub fn move_with(
        &self,
        kind: MoveKind,
        value: f64,
        limits: &MoveLimits,
        mode: BufferMode,
    ) -> Result<Motion> {
        let what = match kind {
            MoveKind::Absolute => "move_absolute",
            MoveKind::Relative => "move_relative",
            MoveKind::Additive => "move_additive",
        };
        let buffered = mode == BufferMode::Buffered;
        self.start_move(kind, value, limits, buffered, what)
    }

    /// [`Axis::move_with`] with an absolute move's direction on a modulo axis (layout 1.10; see
    /// [`Axis::move_absolute_dir`]). Relative and additive moves go their distance: they take
    /// `Direction::Shortest` only (else `ModuloMove`, nothing sent).
    pub fn move_with_dir(
        &self,
        kind: MoveKind,
        value: f64,
        limits: &MoveLimits,
        mode: BufferMode,
        direction: crate::MoveDirection,
    ) -> Result<Motion> {
        if kind != MoveKind::Absolute && direction != crate::MoveDirection::Shortest {
            return Err(crate::Error::Refused {
                command: "move_with_dir",
                target: crate::error::Target::Axis(self.index()),
                code: firmware_proto::NackCode::ModuloMove,
                reason: "a relative or additive move goes its distance: it takes no direction",
            });
        }
        let what = match kind {
            MoveKind::Absolute => "move_absolute",
            MoveKind::Relative => "move_relative",
            MoveKind::Additive => "move_additive",
        };
        let buffered = mode == BufferMode::Buffered;
        self.start_move_dir(kind, value, limits, buffered, direction, what)
    }

    /// MC_MoveAdditive (Aborting): by `distance` from the target of the last move.
    pub fn move_additive(&self, distance: f64, limits: &MoveLimits) -> Result<Motion> {
        self.move_with(MoveKind::Additive, distance, limits, BufferMode::Aborting)
    }

    /// MC_MoveVelocity: run at the signed `velocity` (user units/s), reached within `limits`
    /// from the current state; change it with another call, end it with [`Axis::halt`] or
    /// [`Axis::stop`]. State ContinuousMotion; [`Motion::wait_in_velocity`] waits for the
    /// velocity. The returned motion is never done, only aborted.
    pub fn move_velocity(&self, velocity: f64, limits: &VelocityLimits) -> Result<Motion> {
        finite("velocity", velocity)?;
        positive("acceleration", limits.acceleration)?;
        positive("deceleration", limits.deceleration)?;
        positive("jerk", limits.jerk)?;
        let s = self.scale();
        let m = VelocityMove {
            velocity: velocity * s,
            amax: limits.acceleration * s.abs(),
            dmax: limits.deceleration * s.abs(),
            jerk: limits.jerk * s.abs(),
        };
        let seq = self.run(self.cmd(AxisCmd::MoveVelocity(m)), "move_velocity")?;
        Ok(self.started(seq))
    }

    /// Jog: velocity mode at the signed `velocity` (user units/s) with the axis's jog limits
    /// (`AxisSettings::jog_max_vel`, `jog_accel`, `jog_jerk`); a velocity beyond
    /// `jog_max_vel` is `OutOfRange`. Release the button with [`Axis::jog_release`].
    pub fn jog(&self, velocity: f64) -> Result<Motion> {
        finite("jog velocity", velocity)?;
        let jog = Jog {
            velocity: velocity * self.scale(),
        };
        let seq = self.run(self.cmd(AxisCmd::Jog(jog)), "jog")?;
        Ok(self.started(seq))
    }

    /// Releasing the jog button: MC_Halt at the axis's jog deceleration and jerk.
    pub fn jog_release(&self) -> Result<Motion> {
        let cfg = layout::AXIS_CONFIG
            .at(self.index())
            .read(self.card().window());
        let s = self.scale().abs();
        self.halt(cfg.jog_accel / s, cfg.jog_jerk / s)
    }

    /// MC_SetOverride: scale the axis's velocity (its move's velocity limit, or velocity
    /// mode's velocity) by `factor`, 0.0 to 2.0 (0 % to 200 %, `OVERRIDE_MAX`), else `OverrideRange`. The
    /// change is planned from the current state within the acceleration and jerk limits (no
    /// step in acceleration); 0 holds the axis still in its motion state, and a factor above
    /// 0 resumes from there.
    pub fn set_override(&self, factor: f64) -> Result<()> {
        finite("override", factor)?;
        // The range is the card's to check (OVERRIDE_MAX): it never trusts the host.
        self.run(
            self.cmd(AxisCmd::SetOverride(Override { factor })),
            "set_override",
        )
        .map(|_| ())
    }
}
