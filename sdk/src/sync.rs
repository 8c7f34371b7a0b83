//! Synchronised motion (layout 1.7): electronic gearing, PLCopen MC_GearIn, MC_GearInPos and
//! MC_GearOut, run by the card.
//!
//! A slave axis follows a [`Master`]: another axis's commanded or actual position, or one of
//! the card's auxiliary encoder inputs (a conveyor, a handwheel). The ratio is an integer
//! numerator over a positive integer denominator, in **encoder counts** of slave per count of
//! master (the card's integer arithmetic: no drift however long it runs), whatever scales the
//! axes have on this host. Engaging is the card's: the slave catches up within its own
//! [`SyncLimits`], then [`Motion::wait_in_sync`] returns; [`Axis::gear_out`] leaves it moving
//! at its velocity (velocity mode, [`Motion::wait_in_velocity`]); stop it with
//! [`Axis::halt`]. The full rules are in the register map's header (`MC_OP_GEAR_IN`) and in
//! `card_firmware::firmware::gear`.

use crate::card::{finite, lock, positive, Axis, Card, Motion, Outcome, Status};
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{self, GearIn, GearInPos, SyncCmd};
use firmware_proto::{
    layout, GearRatio, MasterSource, MotionFlags, NackCode, SyncEvent, AUX_ENCODERS,
};
use std::time::Duration;

/// What a slave follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Master {
    /// The commanded position of an axis, followed in the same servo tick: the slave's
    /// reference of a tick is the ratio applied to the master's reference of that tick (a
    /// master driven by homing or a PT/PVT stream: one tick late).
    Commanded(usize),
    /// The actual position (encoder) of an axis, latched at the tick's start: the slave's
    /// servo reaches it one tick later, so at a master velocity `v` the slave trails the
    /// ratio line by `ratio · v · Ts` (one tick of the master's travel) on top of its own
    /// following error. Follow `Commanded` where the master's command is the truth.
    Actual(usize),
    /// The actual position of an axis led by one servo period (its encoder plus its velocity
    /// estimate times the period): at a constant master velocity the slave meets the master's
    /// actual position of the same tick, without `Actual`'s tick of lag (the estimate's noise
    /// and a changing velocity are followed as they are).
    ActualLead(usize),
    /// An auxiliary encoder input, 0..[`AUX_ENCODERS`].
    Aux(usize),
}

impl Master {
    pub(crate) fn source(&self) -> (MasterSource, usize) {
        match *self {
            Master::Commanded(a) => (MasterSource::Commanded, a),
            Master::Actual(a) => (MasterSource::Actual, a),
            Master::ActualLead(a) => (MasterSource::ActualLead, a),
            Master::Aux(k) => (MasterSource::Aux, k),
        }
    }
}

/// The slave's own limits while it engages, in its user units (see [`Axis::set_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyncLimits {
    /// Velocity.
    pub velocity: f64,
    /// Acceleration (and deceleration).
    pub acceleration: f64,
    /// Jerk.
    pub jerk: f64,
}

impl SyncLimits {
    /// In counts, for an axis of `s` counts per user unit (|scale|).
    pub(crate) fn counts(&self, s: f64) -> cmd::SyncLimits {
        cmd::SyncLimits {
            vmax: self.velocity * s,
            amax: self.acceleration * s,
            jerk: self.jerk * s,
        }
    }

    /// Velocity, acceleration, jerk.
    pub fn new(velocity: f64, acceleration: f64, jerk: f64) -> Self {
        Self {
            velocity,
            acceleration,
            jerk,
        }
    }
}

/// A gear ratio's numerator and denominator, checked as the card checks them: `GearRatio`
/// unless both are integers, the numerator nonzero, the denominator positive, each of
/// magnitude at most 2³¹ − 1.
pub fn gear_ratio(numerator: i64, denominator: i64) -> Result<GearRatio> {
    GearRatio::from_args(numerator as f64, denominator as f64)
        .filter(|r| r.num == numerator && r.den == denominator)
        .ok_or(Error::Refused {
            command: "gear_in",
            target: Target::Card,
            code: NackCode::GearRatio,
            reason: crate::error::nack_reason(NackCode::GearRatio),
        })
}

impl Axis {
    fn gear_command(
        &self,
        master: Master,
        (numerator, denominator): (i64, i64),
        limits: &SyncLimits,
        sync_at: Option<(f64, f64)>,
        what: &'static str,
    ) -> Result<Motion> {
        let ratio = gear_ratio(numerator, denominator).map_err(|e| match e {
            Error::Refused { code, reason, .. } => Error::Refused {
                command: what,
                target: Target::Axis(self.index()),
                code,
                reason,
            },
            e => e,
        })?;
        positive("velocity", limits.velocity)?;
        positive("acceleration", limits.acceleration)?;
        positive("jerk", limits.jerk)?;
        let (source, index) = master.source();
        let count = match source {
            MasterSource::Aux => AUX_ENCODERS,
            _ => self.card().info().axes,
        };
        let self_master = source != MasterSource::Aux && index == self.index();
        if index >= count || self_master {
            return Err(Error::Refused {
                command: what,
                target: Target::Axis(self.index()),
                code: NackCode::SyncMaster,
                reason: crate::error::nack_reason(NackCode::SyncMaster),
            });
        }
        let s = self.scale().abs();
        let gear = GearIn {
            master: cmd::Master {
                source,
                index: index as u8, // below the card's axes or its aux encoders (checked above)
            },
            numerator: ratio.num as f64,
            denominator: ratio.den as f64,
            limits: limits.counts(s),
        };
        let c = match sync_at {
            None => SyncCmd::GearIn(gear),
            Some((m, x)) => {
                finite("master position", m)?;
                finite("slave position", x)?;
                let master_scale = match source {
                    MasterSource::Aux => 1.0,
                    _ => self.card().scale(index),
                };
                SyncCmd::GearInPos(GearInPos {
                    gear,
                    master_position: m * master_scale,
                    slave_position: x * self.scale(),
                })
            }
        };
        let (seq, offset) =
            self.card()
                .execute_value(self.cmd(c), what, Target::Axis(self.index()))?;
        lock(&self.card().inner().gear_offset)[self.index()] = Some(offset);
        Ok(self.started(seq))
    }

    /// MC_GearIn (Aborting): this axis follows `master` at `numerator / denominator` counts per
    /// master count, from Standstill or any motion of its own. It is in SynchronizedMotion at
    /// once and catches up within `limits` (time-optimal, jerk-limited, at a constant master
    /// velocity); [`Motion::wait_in_sync`] returns when it is in gear. Refused: `GearRatio`,
    /// `SyncMaster` (no such master, itself, a master axis disabled or in ErrorStop),
    /// `Infeasible` (the master runs faster than `limits` let the slave follow).
    pub fn gear_in(
        &self,
        master: Master,
        numerator: i64,
        denominator: i64,
        limits: &SyncLimits,
    ) -> Result<Motion> {
        self.gear_command(master, (numerator, denominator), limits, None, "gear_in")
    }

    /// MC_GearInPos (Aborting): as [`Axis::gear_in`], synchronised at a point: this axis is at
    /// `slave_position` (its user units) exactly when the master is at `master_position` (the
    /// master axis's user units; an auxiliary encoder's counts), velocity and acceleration
    /// continuous on the way. The card checks the catch-up against `limits` at the master's
    /// present velocity: `Infeasible` if it breaks them, or if the master is at rest or moving
    /// away from the point. [`Motion::wait_in_sync`] returns at the point.
    pub fn gear_in_pos(
        &self,
        master: Master,
        numerator: i64,
        denominator: i64,
        master_position: f64,
        slave_position: f64,
        limits: &SyncLimits,
    ) -> Result<Motion> {
        self.gear_command(
            master,
            (numerator, denominator),
            limits,
            Some((master_position, slave_position)),
            "gear_in_pos",
        )
    }

    /// MC_GearOut: the slave leaves the coupling and keeps moving at its velocity (velocity
    /// mode, ContinuousMotion; its acceleration ramps to 0 within the gear's limits): the
    /// returned motion's [`Motion::wait_in_velocity`] gives the velocity. The gear motion ends
    /// `Aborted` by `GearOut`. `InvalidState` unless the axis is geared.
    pub fn gear_out(&self) -> Result<Motion> {
        let seq = self.run(self.cmd(SyncCmd::GearOut), "gear_out")?;
        Ok(self.started(seq))
    }
}

impl Motion {
    /// Wait until the gear motion is in gear (MC_GearIn: caught up) or in sync (MC_GearInPos:
    /// at its point) and return the slave's commanded position then (user units); an error if
    /// it is aborted first (a halt, stop, gear-out, safety stop, or the master lost: `Aborted`
    /// by `Halt`) or the timeout passes.
    pub fn wait_in_sync(&self, timeout: Duration) -> Result<f64> {
        self.wait_outcome_of(timeout, |o| match o {
            Outcome::Sync(code, v)
                if matches!(
                    SyncEvent::from_raw(code),
                    Some(SyncEvent::InGear | SyncEvent::InSync)
                ) =>
            {
                Some(v)
            }
            _ => None,
        })
    }
}

impl Status {
    /// Does the axis follow its master (in gear, in sync: `MC_MOTION_IN_SYNC`)?
    pub fn in_sync(&self) -> bool {
        self.motion.contains(MotionFlags::IN_SYNC)
    }
}

impl Card {
    /// An auxiliary encoder's count, as the card published it last tick.
    pub fn aux_encoder(&self, k: usize) -> Result<i64> {
        let b = layout::SYNC_STATUS.read(self.window());
        b.aux_count.get(k).copied().ok_or(Error::Refused {
            command: "aux_encoder",
            target: Target::Card,
            code: NackCode::SyncMaster,
            reason: crate::error::nack_reason(NackCode::SyncMaster),
        })
    }
}

impl Axis {
    /// The ratio this axis follows its master at (slave counts per master count), or `None`
    /// when it is not geared.
    pub fn gear_ratio(&self) -> Option<f64> {
        let b = layout::SYNC_STATUS.read(self.card().window());
        b.gear_ratio
            .get(self.index())
            .copied()
            .filter(|r| *r != 0.0 && r.is_finite())
    }

    /// The coupling's engagement offset, in counts: in gear the slave's commanded position is
    /// `offset + ratio · master` (counts of both; a commanded master's position in counts,
    /// [`Axis::gear_ratio`] the ratio). The coupling is relative to where it was taken:
    /// MC_GearIn anchors the ratio line where the slave and the master were at the
    /// engagement, MC_GearInPos at the sync point; the offset is where that line puts the
    /// slave with the master at 0. The card computes it when it takes the command (its ack);
    /// `None` when the axis is not geared, or was not geared through this library.
    pub fn gear_offset(&self) -> Option<f64> {
        self.gear_ratio()?;
        lock(&self.card().inner().gear_offset)[self.index()]
    }
}

#[cfg(feature = "emulator")]
impl crate::card::Sim {
    /// Turn auxiliary encoder `k` of the emulated card at `velocity` counts/s (a conveyor, a
    /// handwheel); the fraction of a count is kept between periods. `BadConfig` for an encoder
    /// the card does not have or a velocity that is not finite.
    pub fn set_aux_velocity(&self, k: usize, velocity: f64) -> Result<()> {
        finite("aux velocity", velocity)?;
        self.with_emulator(|e| e.aux_mut(k).map(|a| a.velocity = velocity))
            .ok_or_else(|| Error::BadConfig(format!("no auxiliary encoder {k}")))
    }

    /// Jump auxiliary encoder `k` of the emulated card by `counts` at once.
    pub fn jump_aux(&self, k: usize, counts: i64) -> Result<()> {
        self.with_emulator(|e| e.aux_mut(k).map(|a| a.jump(counts)))
            .ok_or_else(|| Error::BadConfig(format!("no auxiliary encoder {k}")))
    }
}
