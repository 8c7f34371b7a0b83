//! The handwheel (layout 1.10, issue 35): one of the card's auxiliary encoder inputs (a manual
//! pulse generator) jogs an axis.
//!
//! Each detent of the wheel ([`Handwheel::detent`] auxiliary counts, 4 by default: a quadrature
//! wheel with one detent per cycle, 100 detents a turn) moves the axis by
//! [`Handwheel::ratio`] **encoder counts** (×1, ×10, ×100; with 1000 counts/mm, ×1 is 1 µm a
//! detent). The ratio turns with the axis's scale: on an axis whose scale is negative the card
//! gets the ratio negated, so a wheel turned forward moves the axis forward in user units.
//!
//! The card follows the wheel within the axis's jog limits (`AxisSettings::jog_max_vel`,
//! `jog_accel`, `jog_jerk`) along a jerk-limited trajectory, in SynchronizedMotion; the override
//! does not scale it. Turned faster than that, the excess is dropped: the axis never has more
//! to go than its stop distance from `jog_max_vel` plus one servo period at it, so it stops
//! within that once the wheel stops. Once homed with soft limits on, the wheel cannot take the
//! axis beyond a soft limit. An input drives one axis at a time: selecting it for another axis
//! hands it over, and [`Axis::handwheel_off`] lets go; either way the axis goes on to where the
//! wheel put it and its [`Motion`] is done there. A halt, stop, power off or safety stop ends it
//! as any motion (the motion aborted, with its stop reason). The full rules are in the register
//! map's header (`MC_OP_HANDWHEEL`) and in `card_firmware::firmware::handwheel`.

use crate::card::{Axis, Motion};
use crate::error::{nack_reason, Error, Result, Target};
use firmware_proto::cmd::{self, AxisCmd};
use firmware_proto::{raw, NackCode, AUX_ENCODERS};

/// The largest |ratio|, counts per detent.
pub const HANDWHEEL_RATIO_MAX: u32 = raw::MC_HANDWHEEL_RATIO_MAX;
/// The largest detent, auxiliary counts.
pub const HANDWHEEL_DETENT_MAX: u32 = raw::MC_HANDWHEEL_DETENT_MAX;

/// A handwheel selection: the input, the ratio, the detent. Built as
/// `Handwheel::new(input).ratio(10)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Handwheel {
    /// The auxiliary encoder input, 0..[`AUX_ENCODERS`].
    pub input: usize,
    /// Axis encoder counts per detent, 1 ≤ |ratio| ≤ [`HANDWHEEL_RATIO_MAX`] (negative: the
    /// wheel turns the axis the other way). 1 by default.
    pub ratio: i32,
    /// Auxiliary counts per detent, 1..=[`HANDWHEEL_DETENT_MAX`]. 4 by default.
    pub detent: u32,
}

impl Handwheel {
    /// The default detent: a quadrature wheel with one detent per cycle.
    pub const DEFAULT_DETENT: u32 = 4;

    /// Input `input`, ×1, the default detent.
    pub fn new(input: usize) -> Self {
        Self {
            input,
            ratio: 1,
            detent: Self::DEFAULT_DETENT,
        }
    }

    /// Counts per detent (×1, ×10, ×100).
    pub fn ratio(self, ratio: i32) -> Self {
        Self { ratio, ..self }
    }

    /// Auxiliary counts per detent.
    pub fn detent(self, detent: u32) -> Self {
        Self { detent, ..self }
    }

    /// The command, checked as the card checks it (`HandwheelInput`, `HandwheelRatio`), with the
    /// ratio turned by the sign of `scale`.
    fn command(&self, scale: f64, what: &'static str, target: Target) -> Result<cmd::Handwheel> {
        let refuse = |code| Error::Refused {
            command: what,
            target,
            code,
            reason: nack_reason(code),
        };
        if self.input >= AUX_ENCODERS {
            return Err(refuse(NackCode::HandwheelInput));
        }
        if self.ratio == 0
            || self.ratio.unsigned_abs() > HANDWHEEL_RATIO_MAX
            || !(1..=HANDWHEEL_DETENT_MAX).contains(&self.detent)
        {
            return Err(refuse(NackCode::HandwheelRatio));
        }
        Ok(cmd::Handwheel {
            input: self.input as u8, // below AUX_ENCODERS (checked above)
            ratio: if scale < 0.0 { -self.ratio } else { self.ratio },
            detent: self.detent as u16, // at most HANDWHEEL_DETENT_MAX (checked above)
        })
    }
}

impl Default for Handwheel {
    /// Input 0, ×1, the default detent.
    fn default() -> Self {
        Self::new(0)
    }
}

impl Axis {
    /// Select the handwheel `wheel` for this axis (MC_OP_HANDWHEEL): from rest, or taking over
    /// a move or velocity mode (Aborting: the wheel starts where the axis's jog ramp stops it),
    /// or on the axis's own handwheel (a new input, ratio or detent: the motion goes on, and
    /// the motion returned is the first selection's). An input selected for another axis is
    /// handed over: that axis goes on to where the wheel put it, motion done. The motion is
    /// done once the handwheel is let go ([`Axis::handwheel_off`], or the input handed over)
    /// and the axis is in position; a halt or stop aborts it. Refused: an input the card does
    /// not have (`HandwheelInput`), a ratio of 0 or beyond the maximum, a detent out of range
    /// (`HandwheelRatio`), an axis of an enabled group (`AxisGrouped`), an axis that is
    /// disabled, homing, stopping, geared or in ErrorStop.
    pub fn handwheel(&self, wheel: &Handwheel) -> Result<Motion> {
        let target = Target::Axis(self.index());
        let hw = wheel.command(self.scale(), "handwheel", target)?;
        // The ack's value: the seq of the handwheel's motion (a reselection's is the first's).
        let (seq, motion) =
            self.card()
                .execute_value(self.cmd(AxisCmd::Handwheel(hw)), "handwheel", target)?;
        let motion = if motion.is_finite() && motion > 0.0 && motion <= f64::from(u32::MAX) {
            motion as u32
        } else {
            seq
        };
        Ok(self.started(motion))
    }

    /// Let go of the axis's handwheel (MC_OP_HANDWHEEL_OFF): the axis goes on to where the
    /// wheel put it, and the handwheel's motion is done there. `InvalidState` when no handwheel
    /// drives the axis.
    pub fn handwheel_off(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::HandwheelOff), "handwheel_off")
            .map(|_| ())
    }
}
