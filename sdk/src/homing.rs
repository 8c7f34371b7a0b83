//! Homing: PLCopen MC_Home with the homing methods of CiA 402, run by the card, and
//! MC_SetPosition.
//!
//! The card finds a home point (a switch edge, an index pulse, a hard stop, or the current
//! position) and sets the axis's position so that the home point reads the position given to
//! [`Axis::home`] plus the configured `home_offset`. The settings are the card's register block
//! (`mc_axis_homing`), in counts and seconds like [`crate::AxisSettings`]; the method numbers
//! and what each does are listed in the register map's header (`MC_OP_HOME`) and in
//! `card_firmware::firmware::homing`.

use crate::card::{finite, Axis, Motion, Status};
use crate::error::{Result, Target};
use firmware_proto::cmd::{AxisCmd, CardCmd, Home, SetPosition};
use firmware_proto::{layout, ConfigKind, MotionFlags};

/// An axis's homing configuration, in counts and seconds: the card's `mc_axis_homing` block
/// (its fields are listed in the register map's header). `Default` is what the card loads at
/// boot: method 37 (the current position), search at 20,000 counts/s, creep at 1,000 counts/s,
/// 2·10⁵ counts/s², 2·10⁷ counts/s³, a 60 s timeout, 10⁶ counts of search, the index within
/// 12,000 counts, an index channel, and the axis ending at the home point.
///
/// `method` is a CiA 402 number: 1–14 (a limit or home switch, then the index), 17–30 (the
/// same, the switch edge itself), 33, 34 (the next index pulse, negative or positive), 35, 37
/// (the current position), and -1, -2 (a hard stop, negative or positive, then the index),
/// -3, -4 (the hard stop itself). `flags` are [`HomingFlags`] bits.
pub use firmware_proto::AxisHoming as HomingSettings;
/// Why homing failed ([`crate::Error::HomingFailed`]).
pub use firmware_proto::HomingError;
/// [`HomingSettings::flags`]: the encoder has an index channel; the axis ends at the home
/// point.
pub use firmware_proto::HomingFlags;

impl Axis {
    /// Write the axis's homing configuration and have the card check and apply it: an unknown
    /// method, or an index method without [`HomingFlags::INDEX`], is `HomingMethod`; a value
    /// that is not finite `NotFinite`; one out of range `BadConfig` or `LimitRange`. A refused
    /// block is put back as it was.
    pub fn configure_homing(&self, settings: &HomingSettings) -> Result<()> {
        let a = self.index();
        self.card().apply_block(
            layout::AXIS_HOMING.at(a),
            |b| *b = *settings,
            self.cmd(CardCmd::ApplyAxisHoming),
            "configure_homing",
            Target::Axis(a),
        )
    }

    /// The homing configuration the card holds for this axis (layout 1.8: read back from the
    /// card).
    pub fn homing_settings(&self) -> Result<HomingSettings> {
        let a = self.index();
        self.card()
            .read_block(layout::AXIS_HOMING.at(a), ConfigKind::AxisHoming, a)
    }

    /// MC_Home from Standstill with the configured method: the home point will read
    /// `position` (user units) plus the configured home offset. The axis is in Homing until
    /// [`Motion::wait`] gives its actual position (homed and in position), or an error:
    /// [`crate::Error::HomingFailed`] (switch, hard stop or index not found, or the timeout:
    /// the axis is at rest, not homed), or `Aborted` (a halt, stop or safety stop). Moves and
    /// jogs meanwhile are `AxisHoming`.
    pub fn home(&self, position: f64) -> Result<Motion> {
        finite("home position", position)?;
        let home = Home {
            position: position * self.scale(),
        };
        let seq = self.run(self.cmd(AxisCmd::Home(home)), "home")?;
        Ok(self.started(seq))
    }

    /// MC_SetPosition: the actual and commanded positions become `position` (user units; with
    /// `relative`, they move by it) without moving the axis, and the axis counts as homed (soft
    /// limits take effect). At standstill or disabled; `AxisHoming` while it homes.
    pub fn set_position(&self, position: f64, relative: bool) -> Result<()> {
        finite("position", position)?;
        let set = SetPosition {
            position: position * self.scale(),
            relative,
        };
        self.run(self.cmd(AxisCmd::SetPosition(set)), "set_position")
            .map(|_| ())
    }
}

impl Status {
    /// Has the position been set by homing or [`Axis::set_position`] (`MC_MOTION_HOMED`)? Soft
    /// limits hold only then.
    pub fn homed(&self) -> bool {
        self.motion.contains(MotionFlags::HOMED)
    }
}
